//! The summary of the page: one row per table with its status, the largest differences from
//! the printed table, the verdict and its reason, and the first printed estimate of every
//! SubStokes table beside tribo's.

use super::*;

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

/// Columns of a summary row after the title (for the rows of absent and failed tables).
const SUMMARY_DATA_COLUMNS: usize = 11;

pub(super) fn summary(h: &mut String, entries: &[Entry]) {
    h.push_str(
        "<section id=\"summary\">\n<h2>Summary</h2>\n\
         <p class=\"legend\">Status: ok, error (the run stopped with an error), panic (a bug in \
         tribo, caught) or not loaded (the experiment file was rejected); a failed table's \
         section has the message; figure: no printed table (the thesis shows the result as a \
         figure only, so tribo's rows are shown alone). Verdict: decided on the table's \
         primary columns, the ones its family is about (dofs and estimate; the contact and gap \
         estimates of Signorini contact; the face split and model error of model adaptivity, \
         with the three estimate parts where the grid adapts too), each with its band (3 % for \
         dofs, 5 % for the others): reproduced when every primary column of every printed row \
         tribo computed is within its band; otherwise the columns that hold and those that \
         differ (worst Δ), with the reason where it is known (the tooltip says it, the link \
         leads to the evidence) or unexplained. A table the thesis prints as a copy of another, \
         and a figure, are not scored. Rows within bands: the computed rows whose primary \
         columns are all within their bands, of the printed rows compared. Worst primary Δ: the \
         severity, the largest relative difference of a primary column; \
         <span class=\"verdict ok\">within the bands</span>, \
         <span class=\"verdict near\">up to 15 %</span>, \
         <span class=\"verdict off\">beyond 15 %</span> (the table below the summary orders \
         each family by it). Tables of Chapter IV not on this page are listed as such. \
         Geometric mean of the estimate ratio over the cycles that have one (the mean reduction \
         per cycle). Order: the experimental order of convergence, the least-squares slope of \
         log estimate against log dofs over the rows (−½ is optimal for Q₁ elements in two \
         dimensions). Max Δ: largest relative difference to the thesis over the computed \
         cycles; <span class=\"swatch\"></span> beyond 3 % (dofs) or 5 % (estimate).</p>\n\
         <div class=\"scroll\"><table>\n<thead><tr><th class=\"text\">table</th><th class=\"text\">section</th>\
         <th class=\"text\">title</th><th class=\"text\">status</th><th class=\"text\">verdict</th>\
         <th>rows within bands</th><th>worst primary Δ</th><th>rows (tribo / thesis)</th>\
         <th>last dofs</th><th>last estimate</th><th>geo-mean ratio</th>\
         <th>order (tribo / thesis)</th><th>max Δ dofs</th>\
         <th>max Δ estimate</th><th>seconds</th></tr></thead>\n<tbody>\n",
    );
    let mut next_thesis_table = 1;
    let mut ranked: Vec<(&Section, Verdict)> = Vec::new();
    for entry in entries {
        let id = match entry {
            Entry::Done(s) => &s.run.table,
            Entry::Failed(f) => &f.table,
        };
        if let Some(n) = verdict::thesis_table_number(id) {
            absent_summary_rows(h, next_thesis_table..n);
            next_thesis_table = next_thesis_table.max(n + 1);
        }
        let s = match entry {
            Entry::Done(s) => s,
            Entry::Failed(f) => {
                failed_summary_row(h, f);
                continue;
            }
        };
        let verdict = section_verdict(s);
        summary_row(h, s, &verdict);
        if verdict.score().is_some() {
            ranked.push((s, verdict));
        }
    }
    if next_thesis_table > 1 {
        absent_summary_rows(h, next_thesis_table..verdict::THESIS_TABLES + 1);
    }
    h.push_str("</tbody></table></div>\n");
    by_severity(h, &ranked);
    h.push_str("</section>\n");
}

/// The summary row of a table that ran; `data-table`, `data-verdict` and `data-severity` let a
/// check read the verdicts off the page.
fn summary_row(h: &mut String, s: &Section, verdict: &Verdict) {
    let sm = Summary::of(s);
    let scored = verdict.score().is_some();
    let within = match verdict.score() {
        Some(score) if score.rows.scored > 0 => {
            format!("{} / {}", score.rows.within, score.rows.scored)
        }
        _ => "—".to_string(),
    };
    let dup = if s.thesis.duplicate_of.is_some() {
        " <span title=\"the printed table is a copy of another table\">⚠</span>"
    } else {
        ""
    };
    let _ = writeln!(
        h,
        "<tr data-table=\"{}\" data-verdict=\"{}\" data-severity=\"{}\"><td class=\"text\">\
         <a href=\"#{}\">{}</a>{dup}</td><td class=\"text\">{}</td>\
         <td class=\"text\">{}</td>{}{}<td>{within}</td>{}<td>{} / {}</td>{}{}{}<td>{} / {}</td>{}{}<td>{}</td></tr>",
        escape(&s.run.table),
        verdict.kind(),
        verdict.score().map_or(String::new(), |sc| format!("{:.6}", sc.severity())),
        anchor(&s.run.table),
        escape(&s.run.table),
        escape(&s.run.section),
        escape(&s.run.title),
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
        summary_diff_cell("dofs", sm.max_dofs_diff, scored),
        summary_diff_cell("estimate", sm.max_estimate_diff, scored),
        fmt_seconds(sm.total_seconds),
    );
}

/// The severity cell: the primary column with the worst deviation and that deviation, coloured
/// by its band; `—` for a table that is not scored.
pub(super) fn worst_cell(v: &Verdict) -> String {
    match v.score().and_then(Score::worst) {
        Some(column) => format!(
            "<td class=\"worst {}\" title=\"band {} %\">{} {}</td>",
            v.class(),
            fmt_short(column.band * 100.0),
            escape(&column.name),
            escape(&column.describe()),
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

/// One summary row for the Chapter IV tables `numbers` that are not on this page (left out
/// with `--only`, or without an experiment file), so that the summary of a report with any of
/// them accounts for all 75; a run of consecutive tables shares the row.
pub(super) fn absent_summary_rows(h: &mut String, numbers: std::ops::Range<usize>) {
    let (first, last) = match (numbers.clone().next(), numbers.clone().last()) {
        (Some(first), Some(last)) => (first, last),
        _ => return,
    };
    let (ids, how) = if first == last {
        (
            format!("IV.{first}"),
            format!("not run here: <code>report --only IV.{first}</code> runs it"),
        )
    } else {
        (
            format!("IV.{first} – IV.{last}"),
            "not run here (left out with <code>--only</code>)".to_string(),
        )
    };
    let _ = writeln!(
        h,
        "<tr class=\"absent\"><td class=\"text\">{ids}</td><td class=\"text na\">—</td>\
         <td class=\"text na\">—</td><td class=\"status na\">not on this page</td>\
         <td class=\"text na\" colspan=\"{SUMMARY_DATA_COLUMNS}\">{how}</td></tr>"
    );
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
pub(super) fn substokes_row_zero(h: &mut String, entries: &[Entry]) {
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
    let why = match f.kind {
        FailureKind::NotLoaded => "no data: the experiment file did not load".to_string(),
        _ => match f.cycle {
            Some(cycle) => format!("no data: the run failed in cycle {cycle}"),
            None => "no data: the run failed".to_string(),
        },
    };
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
