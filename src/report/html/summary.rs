//! The summary of the page: one row per table with its status, the largest differences from
//! the printed table, the verdict and its reason, and the first printed estimate of every
//! SubStokes table beside tribo's.

use super::*;
use crate::report::effectivity_range;

/// A `<td>` holding a relative difference, highlighted beyond the column's tolerance.
pub(super) fn diff_cell(column: &str, d: Option<f64>) -> String {
    match d {
        Some(d) if d.abs() > tolerance(column) => {
            format!("<td class=\"diff off\">{}</td>", fmt_pct(d))
        }
        Some(d) => format!("<td class=\"diff\">{}</td>", fmt_pct(d)),
        None => "<td class=\"na\">—</td>".into(),
    }
}

/// [`diff_cell`] in the summary: a table that is not scored (a thesis duplicate, a scene the
/// page does not compare) shows its difference without the highlight.
pub(super) fn summary_diff_cell(column: &str, d: Option<f64>, scored: bool) -> String {
    match d {
        Some(d) if !scored => format!(
            "<td class=\"diff\" title=\"not scored\">{}</td>",
            fmt_pct(d)
        ),
        _ => diff_cell(column, d),
    }
}

pub(super) fn opt_cell(v: Option<String>) -> String {
    match v {
        Some(s) => format!("<td>{s}</td>"),
        None => "<td class=\"na\">—</td>".into(),
    }
}

/// The verdict on a section that ran: not scored for an own or edited scene, else decided on
/// its primary columns ([`verdict::of`]) with the known reason of its differences.
pub(super) fn section_verdict(s: &Section) -> Verdict {
    let not_scored = match &s.thesis.comparison {
        Comparison::OwnScene => Some("own scene: not compared".to_string()),
        Comparison::Edited(_) => Some("edited: not scored".to_string()),
        Comparison::Printed => None,
    };
    verdict::of(s, known_reason(s), not_scored)
}

/// Columns of a detailed summary row after the title (for the rows of failed tables).
const SUMMARY_DATA_COLUMNS: usize = 11;

/// What the columns of the summaries mean, folded under the table.
const SUMMARY_LEGEND: &str = "<details class=\"legend\"><summary>How to read the summary\
     </summary><p>Status: ok, error (the run stopped with an error), panic (a bug in tribo, \
     caught) or not loaded (the experiment file was rejected); a failed table's section has the \
     message; figure: no printed table (the thesis shows the result as a figure only, so tribo's \
     rows are shown alone). Verdict: decided on the table's primary columns, the ones its family \
     is about (dofs and estimate; the contact and gap estimates of Signorini contact; the face \
     split and model error of model adaptivity, with the three estimate parts where the grid \
     adapts too), each with its band (3 % for dofs, 5 % for the others): reproduced when every \
     primary column of every printed row tribo computed is within its band; otherwise the \
     columns that differ, with the reason where it is known (the tooltip gives the whole \
     verdict and the reason, the link leads to the evidence) or unexplained. A table the thesis \
     prints as a copy of another, and a figure, are not scored. Rows within bands: the computed \
     rows whose primary columns are all within their bands, of the printed rows compared. Worst \
     primary Δ: the severity, the largest relative difference of a primary column; \
     <span class=\"verdict ok\">within the bands</span>, <span class=\"verdict near\">up to 15 \
     %</span>, <span class=\"verdict off\">beyond 15 %</span>. Order: the experimental order of \
     convergence, the least-squares slope of log estimate against log dofs over the rows (−½ is \
     optimal for Q₁ elements in two dimensions). On a family's page also: the geometric mean of \
     the estimate ratio over the cycles that have one (the mean reduction per cycle), and max Δ, \
     the largest relative difference to the thesis over the computed cycles; <span \
     class=\"swatch\"></span> beyond 3 % (dofs) or 5 % (estimate).</p></details>\n";

/// The summary of a family's page: every column for each of its tables.
pub(super) fn family_summary(h: &mut String, entries: &[&Entry]) {
    h.push_str(
        "<section id=\"family-summary\">\n<h2>The tables of this page</h2>\n\
         <div class=\"scroll\"><table class=\"family-table\">\n<thead><tr><th class=\"text\">table</th><th class=\"text\">section</th>\
         <th class=\"text\">title</th><th class=\"text\">status</th><th class=\"text\">verdict</th>\
         <th>rows within bands</th><th>worst primary Δ</th><th>rows (tribo / thesis)</th>\
         <th>last dofs</th><th>last estimate</th><th>geo-mean ratio</th>\
         <th>order (tribo / thesis)</th><th title=\"estimate / true error over the rows\">η / error</th><th>max Δ dofs</th>\
         <th>max Δ estimate</th><th>seconds</th></tr></thead>\n<tbody>\n",
    );
    for entry in entries {
        match entry {
            Entry::Done(s) => summary_row(h, s, &section_verdict(s)),
            Entry::Failed(f) => failed_summary_row(h, f),
        }
    }
    h.push_str("</tbody></table></div>\n");
    h.push_str(SUMMARY_LEGEND);
    h.push_str("</section>\n");
}

/// Columns of a compact summary row after the table id.
const COMPACT_DATA_COLUMNS: usize = 8;
/// … on a page without a thesis entry, whose rows have no verdict, bands or printed order.
const OWN_DATA_COLUMNS: usize = 5;

/// The front page's summary: one compact row per table (id, title, status, verdict, rows within
/// bands, worst primary Δ, order, seconds), grouped by family, each family headed by a link to
/// its page; where the run has a thesis table, every Chapter IV table not in the run has a row
/// saying so, under its family. `data-table`, `data-verdict` and `data-severity` let a check
/// read the verdicts off the page.
pub(super) fn front_summary(h: &mut String, entries: &[Entry], groups: &[pages::Group]) {
    let thesis_run = any_thesis_entry(entries);
    h.push_str(
        "<section id=\"summary\">\n<h2>Summary</h2>\n<div class=\"scroll\"><table class=\"compact\">\n\
         <thead><tr><th class=\"text\">table</th><th class=\"text\">title</th>\
         <th class=\"text\">status</th>",
    );
    h.push_str(if thesis_run {
        "<th class=\"text\">verdict</th><th>rows within bands</th>\
         <th class=\"text\">worst primary Δ</th><th>order (tribo / thesis)</th><th title=\"estimate / true error over the rows\">η / error</th><th>seconds</th>\
         </tr></thead>\n"
    } else {
        "<th>order</th><th title=\"estimate / true error over the rows\">η / error</th><th>seconds</th></tr></thead>\n"
    });
    let mut ranked: Vec<(&Section, Verdict)> = Vec::new();
    let families: Vec<&Family> = if thesis_run {
        families::families().iter().collect()
    } else {
        groups.iter().filter_map(|g| g.family).collect()
    };
    for family in families {
        let group = groups
            .iter()
            .find(|g| g.family.is_some_and(|f| f.id == family.id));
        family_rows(
            h,
            family.name.as_str(),
            group,
            &family.tables,
            thesis_run,
            &mut ranked,
        );
    }
    if let Some(own) = groups.iter().find(|g| g.family.is_none()) {
        family_rows(h, own.name(), Some(own), &[], thesis_run, &mut ranked);
    }
    h.push_str("</table></div>\n");
    if thesis_run {
        h.push_str(SUMMARY_LEGEND);
    }
    by_severity(h, &ranked);
    h.push_str("</section>\n");
}

/// One family's rows of the front summary: a heading row (a link to its page when it has one),
/// then its tables in the order of `tables` (the family's list; the run's order for a group
/// without one), a row for each run of tables not in the run.
fn family_rows<'a>(
    h: &mut String,
    name: &str,
    group: Option<&pages::Group<'a>>,
    tables: &[String],
    thesis_run: bool,
    ranked: &mut Vec<(&'a Section<'a>, Verdict)>,
) {
    let heading = match group {
        Some(g) => format!("<a href=\"{}\">{}</a>", escape(&g.file), escape(name)),
        None => format!(
            "{} <span class=\"meta\">(no table of it in this run)</span>",
            escape(name)
        ),
    };
    let _ = writeln!(
        h,
        "<tbody><tr class=\"family-head\"><th class=\"text\" colspan=\"{}\">{heading}</th></tr>",
        data_columns(thesis_run) + 1
    );
    let members: Vec<&'a Entry> = group.map_or_else(Vec::new, |g| g.entries.clone());
    let mut absent: Vec<&str> = Vec::new();
    for t in tables {
        match members.iter().find(|e| e.table() == t) {
            Some(e) => {
                absent_compact_row(h, &absent);
                absent.clear();
                compact_entry(h, e, thesis_run, ranked);
            }
            None => {
                // A run of absent tables is consecutive in Chapter IV's numbering.
                let follows = |a: &str, b: &str| match (
                    verdict::thesis_table_number(a),
                    verdict::thesis_table_number(b),
                ) {
                    (Some(a), Some(b)) => a + 1 == b,
                    _ => false,
                };
                if absent.last().is_some_and(|last| !follows(last, t)) {
                    absent_compact_row(h, &absent);
                    absent.clear();
                }
                absent.push(t);
            }
        }
    }
    absent_compact_row(h, &absent);
    // The entries its list does not name: all of a group without a list (the own scenes).
    for e in members
        .iter()
        .filter(|e| !tables.iter().any(|t| t == e.table()))
    {
        compact_entry(h, e, thesis_run, ranked);
    }
    h.push_str("</tbody>\n");
}

/// The data columns of a compact row: those of a page with a thesis entry, or of a page of
/// own scenes.
fn data_columns(thesis_run: bool) -> usize {
    if thesis_run {
        COMPACT_DATA_COLUMNS
    } else {
        OWN_DATA_COLUMNS
    }
}

/// The compact row of one entry; a scored section joins `ranked`.
fn compact_entry<'a>(
    h: &mut String,
    e: &'a Entry,
    thesis_run: bool,
    ranked: &mut Vec<(&'a Section<'a>, Verdict)>,
) {
    match e {
        Entry::Done(s) if !thesis_run => {
            let sm = Summary::of(s);
            let _ = writeln!(
                h,
                "<tr data-table=\"{}\" data-verdict=\"not-scored\" data-severity=\"\">\
                 <td class=\"text\"><a href=\"#{}\">{}</a></td>\
                 <td class=\"text title\" title=\"{t}\">{t}</td>{}<td>{}</td><td>{}</td><td>{}</td></tr>",
                escape(&s.run.table),
                anchor(&s.run.table),
                escape(&s.run.table),
                status_cell(s),
                sm.order.map_or("—".into(), fmt_order),
                fmt_effectivity(sm.effectivity),
                fmt_seconds(sm.total_seconds),
                t = escape(&s.run.title),
            );
        }
        Entry::Done(s) => {
            let verdict = section_verdict(s);
            compact_row(h, s, &verdict);
            if verdict.score().is_some() {
                ranked.push((s, verdict));
            }
        }
        Entry::Failed(f) => {
            let why = failure_words(f);
            let _ = writeln!(
                h,
                "<tr><td class=\"text\"><a href=\"#{}\">{}</a></td>\
                 <td class=\"text title\" title=\"{t}\">{t}</td><td class=\"status failed\">{}</td>\
                 <td class=\"text na\" colspan=\"{}\">{why}</td></tr>",
                anchor(&f.table),
                escape(&f.table),
                f.kind.name(),
                data_columns(thesis_run) - 2,
                t = escape(f.title.as_deref().unwrap_or("—")),
            );
        }
    }
}

/// The rows within bands of a scored table (`9 / 10`), `—` for one not scored.
fn rows_within(verdict: &Verdict) -> String {
    match verdict.score() {
        Some(score) if score.rows.scored > 0 => {
            format!("{} / {}", score.rows.within, score.rows.scored)
        }
        _ => "—".to_string(),
    }
}

/// The mark after the id of a table the thesis prints as a copy of another.
fn duplicate_mark(s: &Section) -> &'static str {
    if s.thesis.duplicate_of.is_some() {
        " <span title=\"the printed table is a copy of another table\">⚠</span>"
    } else {
        ""
    }
}

/// The compact summary row of a table that ran.
fn compact_row(h: &mut String, s: &Section, verdict: &Verdict) {
    let sm = Summary::of(s);
    let (within, dup) = (rows_within(verdict), duplicate_mark(s));
    let _ = writeln!(
        h,
        "<tr data-table=\"{}\" data-verdict=\"{}\" data-severity=\"{}\"><td class=\"text\">\
         <a href=\"#{}\">{}</a>{dup}</td><td class=\"text title\" title=\"{t}\">{t}</td>{}{}\
         <td>{within}</td>{}<td>{} / {}</td><td>{}</td><td>{}</td></tr>",
        escape(&s.run.table),
        verdict.kind(),
        verdict
            .score()
            .map_or(String::new(), |sc| format!("{:.6}", sc.severity())),
        anchor(&s.run.table),
        escape(&s.run.table),
        status_cell(s),
        compact_verdict_cell(verdict),
        worst_cell(verdict),
        sm.order.map_or("—".into(), fmt_order),
        sm.thesis_order.map_or("—".into(), fmt_order),
        fmt_effectivity(sm.effectivity),
        fmt_seconds(sm.total_seconds),
        t = escape(&s.run.title),
    );
}

/// The verdict in a few words ([`Verdict::short_label`]); the whole verdict and its reason as
/// the tooltip, and the link to the evidence.
fn compact_verdict_cell(v: &Verdict) -> String {
    let (tooltip, link) = match v {
        Verdict::Differs { known: Some(r), .. } => {
            (format!("{} — {}", v.label(), r.reason), r.anchor.as_deref())
        }
        _ => (v.label(), None),
    };
    let words = escape(&v.short_label());
    let words = match link {
        Some(a) => format!("<a href=\"#{}\">{words}</a>", escape(a)),
        None => words,
    };
    format!(
        "<td class=\"text {}\" title=\"{}\">{words}</td>",
        v.class(),
        escape(&tooltip)
    )
}

/// The compact row of tables of a family not in the run (nothing for none).
fn absent_compact_row(h: &mut String, tables: &[&str]) {
    let (Some(first), Some(last)) = (tables.first(), tables.last()) else {
        return;
    };
    let (ids, how) = if tables.len() == 1 {
        (
            escape(first),
            format!(
                "not run here: <code>report --only {}</code> runs it",
                escape(first)
            ),
        )
    } else {
        (
            format!("{} – {}", escape(first), escape(last)),
            "not run here (left out with <code>--only</code>)".to_string(),
        )
    };
    let _ = writeln!(
        h,
        "<tr class=\"absent\"><td class=\"text\">{ids}</td>\
         <td class=\"text na\" colspan=\"{COMPACT_DATA_COLUMNS}\">{how}</td></tr>"
    );
}

/// The detailed summary row of a table that ran (a family's page).
fn summary_row(h: &mut String, s: &Section, verdict: &Verdict) {
    let sm = Summary::of(s);
    let scored = verdict.score().is_some();
    let (within, dup) = (rows_within(verdict), duplicate_mark(s));
    let _ = writeln!(
        h,
        "<tr><td class=\"text\">\
         <a href=\"#{}\">{}</a>{dup}</td><td class=\"text\">{}</td>\
         <td class=\"text title\" title=\"{t}\">{t}</td>{}{}<td>{within}</td>{}<td>{} / {}</td>{}{}{}<td>{} / {}</td><td>{}</td>{}{}<td>{}</td></tr>",
        anchor(&s.run.table),
        escape(&s.run.table),
        escape(&s.run.section),
        status_cell(s),
        verdict_cell(verdict),
        worst_cell(verdict),
        sm.rows,
        if s.is_figure() {
            "—".to_string()
        } else {
            s.thesis.len().to_string()
        },
        opt_cell(sm.last_dofs.map(|d| d.to_string())),
        opt_cell(sm.last_estimate.map(fmt_sig)),
        opt_cell(sm.geo_mean_ratio.map(fmt_sig)),
        sm.order.map_or("—".into(), fmt_order),
        sm.thesis_order.map_or("—".into(), fmt_order),
        fmt_effectivity(sm.effectivity),
        summary_diff_cell("dofs", sm.max_dofs_diff, scored),
        summary_diff_cell("estimate", sm.max_estimate_diff, scored),
        fmt_seconds(sm.total_seconds),
        t = escape(&s.run.title),
    );
}

/// The severity cell: the primary column with the worst deviation and that deviation, coloured
/// by its band; `—` for a table that is not scored.
pub(super) fn worst_cell(v: &Verdict) -> String {
    match v.score().and_then(Score::worst) {
        Some(column) => format!(
            "<td class=\"worst {}\" title=\"{name} {describe} (band {} %)\">{name} {describe}</td>",
            v.class(),
            fmt_short(column.band * 100.0),
            name = escape(&column.name),
            describe = escape(&column.describe()),
        ),
        None => "<td class=\"na\">—</td>".into(),
    }
}

/// Each family's scored tables ordered by severity, worst first: where a family reproduces the
/// thesis and where it does not, at a glance.
fn by_severity(h: &mut String, ranked: &[(&Section, Verdict)]) {
    if ranked.is_empty() {
        return;
    }
    h.push_str(
        "<h3 id=\"by-severity\">Verdicts by family, worst primary difference first</h3>\n\
         <div class=\"scroll\"><table>\n<thead><tr><th class=\"text\">family</th>\
         <th class=\"text\">table</th><th>worst primary Δ</th><th class=\"text\">verdict</th>\
         </tr></thead>\n<tbody>\n",
    );
    let family_name = |t: &str| families::family_of(t).map_or("—", |f| f.name.as_str());
    let mut groups: Vec<&str> = Vec::new();
    for (s, _) in ranked {
        let name = family_name(&s.run.table);
        if !groups.contains(&name) {
            groups.push(name);
        }
    }
    for group in groups {
        let mut members: Vec<&(&Section, Verdict)> = ranked
            .iter()
            .filter(|(s, _)| family_name(&s.run.table) == group)
            .collect();
        members.sort_by(|a, b| {
            let sev = |v: &Verdict| v.score().map_or(0.0, |s| s.severity());
            sev(&b.1).total_cmp(&sev(&a.1))
        });
        for (i, (s, v)) in members.iter().enumerate() {
            let family = if i == 0 {
                format!(
                    "<td class=\"text\" rowspan=\"{}\">{}</td>",
                    members.len(),
                    escape(group)
                )
            } else {
                String::new()
            };
            let _ = writeln!(
                h,
                "<tr>{family}<td class=\"text\"><a href=\"#{}\">{}</a></td>{}{}</tr>",
                anchor(&s.run.table),
                escape(&s.run.table),
                worst_cell(v),
                verdict_cell(v),
            );
        }
    }
    h.push_str("</tbody></table></div>\n");
}

/// The verdict cell: the verdict's words, the reason as a tooltip and a link to its evidence.
pub(super) fn verdict_cell(v: &Verdict) -> String {
    match v {
        Verdict::Differs { known: Some(r), .. } => {
            let words = match &r.anchor {
                Some(a) => format!("<a href=\"#{}\">{}</a>", escape(a), escape(&v.label())),
                None => escape(&v.label()),
            };
            format!(
                "<td class=\"text {}\" title=\"{}\">{words}</td>",
                v.class(),
                escape(&r.reason)
            )
        }
        _ => format!(
            "<td class=\"text {}\">{}</td>",
            v.class(),
            escape(&v.label())
        ),
    }
}

/// Why the section's numbers differ from the printed ones, where the report knows it
/// ([`errata::known_difference`]), linked to the first thesis erratum affecting the table, or
/// else to the table's own section, whose readings give the evidence.
pub(super) fn known_reason(section: &Section) -> Option<KnownReason> {
    let table = &section.run.table;
    let known = errata::known_difference(table)?;
    let anchor = errata::errata_for(table)
        .first()
        .map(|e| e.id.to_string())
        .unwrap_or_else(|| anchor(table));
    Some(KnownReason {
        kind: known.kind.name().to_string(),
        reason: known.reason.to_string(),
        anchor: Some(anchor),
    })
}

/// The first printed estimate of every SubStokes table of the page (runs with a Reynolds
/// comparison on their last mesh) beside the thesis's: the uniform 8×8 grid's estimate, on which
/// δ_ε is calibrated (IV.50) and which holds out the others. Nothing without SubStokes tables.
pub(super) fn substokes_row_zero(h: &mut String, entries: &[&Entry]) {
    let sections: Vec<&Section> = entries
        .iter()
        .filter_map(|e| match e {
            Entry::Done(s) if s.run.cuts.as_ref().is_some_and(Cuts::compares_models) => Some(s),
            _ => None,
        })
        .collect();
    if sections.is_empty() {
        return;
    }
    h.push_str(
        "<section id=\"substokes-row-zero\">\n<h2>SubStokes: the estimate on the initial grid</h2>\n\
         <p class=\"legend\">The first printed estimate of each SubStokes table is the estimate \
         of the solve on the uniform 8×8 grid (row 0; IV.72, which prints that grid as row 0, \
         row 1). δ_ε = 1.10e-3 is calibrated on IV.50's value; the others are held out.</p>\n\
         <div class=\"scroll\"><table>\n<thead><tr><th class=\"text\">table</th>\
         <th class=\"text\">title</th><th>row</th><th>tribo</th><th>thesis</th>\
         <th>tribo / thesis</th></tr></thead>\n<tbody>\n",
    );
    for s in sections {
        let first = s
            .run
            .rows
            .iter()
            .find_map(|r| Some((r.cycle, r.value(PREVIOUS_ESTIMATE)?)));
        let Some((cycle, tribo)) = first else {
            continue;
        };
        let thesis = s.thesis.value(cycle, "estimate").filter(|v| v.is_finite());
        let _ = writeln!(
            h,
            "<tr><td class=\"text\"><a href=\"#{}\">{}</a></td><td class=\"text\">{}</td>\
             <td>{cycle}</td><td>{}</td>{}{}</tr>",
            anchor(&s.run.table),
            escape(&s.run.table),
            escape(&s.run.title),
            fmt_sig(tribo),
            opt_cell(thesis.map(fmt_sig)),
            opt_cell(thesis.map(|t| format!("{:.3}", tribo / t))),
        );
    }
    h.push_str("</tbody></table></div>\n</section>\n");
}

/// The status cell of a table that ran: `ok` (`figure: no printed table` for a figure
/// experiment), or how its first failed alternative reading failed.
pub(super) fn status_cell(s: &Section) -> String {
    let warnings = s.run.warnings.len();
    let ok = match &s.thesis.comparison {
        Comparison::OwnScene => "own scene: not compared",
        Comparison::Edited(_) => "edited: not scored",
        Comparison::Printed if s.is_figure() => "figure: no printed table",
        Comparison::Printed => "ok",
    };
    match s.alternatives.iter().find_map(|a| a.outcome.as_ref().err()) {
        None if warnings > 0 => format!(
            "<td class=\"status warned\" title=\"the table ran; its section says what is \
             suspicious\">{ok}, {warnings} warning{}</td>",
            if warnings == 1 { "" } else { "s" }
        ),
        None => format!("<td class=\"status ok\">{ok}</td>"),
        Some(f) => format!(
            "<td class=\"status failed\" title=\"the table ran; an alternative reading failed\">\
             {} (alternative reading)</td>",
            f.kind.name()
        ),
    }
}

/// The summary row of a table that failed: what is known of it, its status, and no numbers.
pub(super) fn failed_summary_row(h: &mut String, f: &Failure) {
    let why = failure_words(f);
    let _ = writeln!(
        h,
        "<tr><td class=\"text\"><a href=\"#{}\">{}</a></td><td class=\"text\">{}</td>\
         <td class=\"text\">{}</td><td class=\"status failed\">{}</td>\
         <td class=\"text na\" colspan=\"{SUMMARY_DATA_COLUMNS}\">{}</td></tr>",
        anchor(&f.table),
        escape(&f.table),
        escape(f.section.as_deref().unwrap_or("—")),
        escape(f.title.as_deref().unwrap_or("—")),
        f.kind.name(),
        why
    );
}

/// What a failed table has instead of numbers, in the summaries.
fn failure_words(f: &Failure) -> String {
    match f.kind {
        FailureKind::NotLoaded => "no data: the experiment file did not load".to_string(),
        _ => match f.cycle {
            Some(cycle) => format!("no data: the run failed in cycle {cycle}"),
            None => "no data: the run failed".to_string(),
        },
    }
}

/// The family's line on its page: by what factor its estimators over- or under-estimate the
/// true error, over the rows of its tables with a measured error (nothing without one).
pub(super) fn family_effectivity(h: &mut String, entries: &[&Entry]) {
    let ranges: Vec<(f64, f64)> = entries
        .iter()
        .filter_map(|e| match e {
            Entry::Done(s) => effectivity_range(s.run),
            Entry::Failed(_) => None,
        })
        .collect();
    let Some((lo, hi)) = ranges
        .iter()
        .copied()
        .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
    else {
        return;
    };
    let range = |a: f64, b: f64| fmt_effectivity(Some((a, b)));
    let claim = if lo >= 1.0 {
        format!(
            "overestimates the true error by a factor in {}",
            range(lo, hi)
        )
    } else if hi <= 1.0 {
        format!(
            "underestimates the true error by a factor in {}",
            range(1.0 / hi, 1.0 / lo)
        )
    } else {
        format!(
            "is within a factor in {} of the true error (η / error; it underestimates where \
             below 1)",
            range(lo, hi)
        )
    };
    let _ = writeln!(
        h,
        "<p class=\"effectivity\"><b>Estimate against true error:</b> over the rows of the \
         {} tables with a measured error, the estimator {claim}. Per table: the column \
         η / error above; how the error is measured: each section's “True error”.</p>",
        ranges.len()
    );
}
