//! Layout of `index.html`: header, contents, summary, and one section per table.
//!
//! The page is built as a string with inline CSS and no scripts, so it renders identically from
//! disk, from a CI artefact or from an archive. Every piece of text that comes from data (titles,
//! notes, column names, captions, error messages) goes through [`escape`], which also makes
//! control characters visible. Every table has a summary row with its status and a section, also
//! a table that failed; its section holds the cycle and the message instead of data.

use std::collections::{BTreeSet, HashMap};
use std::fmt::Write as _;

use super::errata::{self, Erratum};
use super::families::{self, Family};
use super::verdict::{self, KnownReason, Verdict};
use super::{
    compared_value, compares_previous_estimate, estimate_ratio, rel_diff, thesis_figure, tolerance,
    Entry, Failure, FailureKind, Figure, ReportMeta, Section, Summary, MAX_SHOWN_THESIS_ROWS,
};
use crate::experiment::Comparison;
use crate::results::columns::{self, PREVIOUS_ESTIMATE, THEOREM_ESTIMATE};
use crate::results::{Cuts, Row, RunResult, Value};
use crate::thesis::ThesisTable;

/// The figures written for one section, in the order they appear, or why there are none.
#[derive(Default)]
pub(crate) struct SectionFigures {
    pub figures: Vec<Figure>,
    /// Set when drawing the section's figures failed (an I/O error or a panic).
    pub error: Option<String>,
}

/// Escape text for HTML and SVG (element content and quoted attribute values).
///
/// Control characters other than newline and tab (NUL, BEL, ESC, DEL, the C1 range) and the
/// bidirectional overrides, which would reorder the text around them, become visible escapes
/// such as `\u{7}`: raw, they are invalid in HTML and XML or invisible, and a file's title or
/// note must not hide what it contains.
pub(crate) fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            '\n' | '\t' => out.push(c),
            c if c.is_control() || is_bidi_control(c) => {
                let _ = write!(out, "\\u{{{:x}}}", c as u32);
            }
            _ => out.push(c),
        }
    }
    out
}

/// The bidirectional embedding, override and isolate characters (U+202A–U+202E, U+2066–U+2069).
fn is_bidi_control(c: char) -> bool {
    matches!(c, '\u{202A}'..='\u{202E}' | '\u{2066}'..='\u{2069}')
}

/// A number with 4 significant digits, the precision the thesis prints (`0.2860`, `1.234e-5`).
/// A value that is not finite (the thesis prints its first ratios as `inf`) is undefined and
/// shown as `—`, like tribo's own undefined values (report/README.md).
pub(crate) fn fmt_sig(v: f64) -> String {
    if !v.is_finite() {
        return "—".into();
    }
    if v == 0.0 {
        return "0".into();
    }
    let e = v.abs().log10().floor() as i32;
    if (-3..6).contains(&e) {
        format!("{:.*}", (3 - e).max(0) as usize, v)
    } else {
        format!("{v:.3e}")
    }
}

/// [`fmt_sig`] without trailing zeros, for labels rather than table columns (`× 40`, not
/// `× 40.00`).
pub(crate) fn fmt_short(v: f64) -> String {
    let s = fmt_sig(v);
    if s.contains('.') && !s.contains('e') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// A relative difference as a signed percentage.
fn fmt_pct(d: f64) -> String {
    let p = d * 100.0;
    if p == 0.0 {
        "0 %".into()
    } else if p.abs() < 0.1 {
        format!("{p:+.2} %")
    } else {
        format!("{p:+.1} %")
    }
}

/// Columns whose values are counts and are printed without decimals.
fn is_integer_column(column: &str) -> bool {
    matches!(column, "cycle" | "active_cells" | "dofs") || column.ends_with("_faces")
}

/// A table value: counts as integers, the rest with 4 significant digits.
fn fmt_value(column: &str, v: f64) -> String {
    if v.is_finite() && is_integer_column(column) && v.fract() == 0.0 {
        format!("{v:.0}")
    } else {
        fmt_sig(v)
    }
}

/// An order of convergence to two decimals, with a true minus sign.
fn fmt_order(order: f64) -> String {
    format!("{order:.2}").replace('-', "−")
}

fn fmt_seconds(s: f64) -> String {
    if !s.is_finite() {
        return fmt_sig(s);
    }
    if s >= 120.0 {
        let m = (s / 60.0).floor();
        format!("{s:.0} s ({m:.0} min {:.0} s)", s - 60.0 * m)
    } else if s >= 10.0 {
        format!("{s:.1} s")
    } else {
        format!("{s:.3} s")
    }
}

/// Anchor id of a table's section (`t-IV.1`).
fn anchor(table: &str) -> String {
    format!("t-{}", super::file_stem(table))
}

/// How the page names an entry: `Table IV.1`, or `Fig. IV.54` for a figure experiment
/// (`fig-IV.54`: the thesis shows that result as a figure only).
fn entry_name(table: &str) -> String {
    thesis_figure(table).unwrap_or_else(|| format!("Table {table}"))
}

const CSS: &str = r#"
:root { --ink: #1d2430; --muted: #6b7280; --rule: #d7dce3; --band: #f5f7fa; --off: #fde2dd; --offink: #a1271b; --ok: #1b7a3a; }
* { box-sizing: border-box; }
body { font: 15px/1.5 system-ui, -apple-system, "Segoe UI", Roboto, sans-serif; color: var(--ink); margin: 0; background: #fff; }
main { max-width: 1500px; margin: 0 auto; padding: 0 28px 60px; }
header { background: #15233a; color: #f1f4f8; padding: 26px 28px 20px; }
header .inner { max-width: 1500px; margin: 0 auto; }
header h1 { margin: 0 0 6px; font-size: 26px; }
header p { margin: 4px 0 12px; max-width: 980px; color: #c9d3e1; }
header dl { display: flex; flex-wrap: wrap; gap: 6px 28px; margin: 0; }
header dt { color: #9fb0c8; font-size: 12px; text-transform: uppercase; letter-spacing: .05em; }
header dd { margin: 0; font-weight: 600; }
h2 { font-size: 22px; margin: 38px 0 10px; padding-bottom: 4px; border-bottom: 2px solid var(--rule); }
h3 { font-size: 16px; margin: 22px 0 8px; }
nav ol { columns: 3 280px; padding-left: 22px; margin: 0; }
nav li { break-inside: avoid; }
a { color: #1f5fae; text-decoration: none; }
a:hover { text-decoration: underline; }
.scroll { overflow-x: auto; max-width: 100%; }
table { border-collapse: collapse; font-variant-numeric: tabular-nums; font-size: 13.5px; }
th, td { padding: 3px 8px; border-bottom: 1px solid var(--rule); text-align: right; white-space: nowrap; }
th { background: var(--band); font-weight: 600; }
thead th { position: sticky; top: 0; }
th.group { text-align: center; border-left: 2px solid #fff; }
td.text, th.text { text-align: left; white-space: normal; }
td.first { border-left: 2px solid var(--rule); }
td.thesis { color: #374151; background: #fafbfc; }
td.diff { color: var(--ok); }
td.off { background: var(--off); color: var(--offink); font-weight: 600; }
td.na { color: #b8bec8; }
tbody tr:hover td { background: #eef3fb; }
.legend { color: var(--muted); font-size: 13px; margin: 6px 0 10px; }
.legend .swatch { display: inline-block; width: 12px; height: 12px; background: var(--off); border: 1px solid var(--offink); vertical-align: -1px; }
.params { margin: 10px 0; }
.params summary { cursor: pointer; font-weight: 600; }
.params table { margin: 6px 0; }
.params td.group { font-weight: 600; background: var(--band); text-align: left; }
.params td.key { text-align: left; font-family: ui-monospace, monospace; white-space: nowrap; }
.params td.value { text-align: left; font-family: ui-monospace, monospace; white-space: normal; word-break: break-word; }
.verdict.ok { color: var(--ok); font-weight: 600; }
.verdict.known { color: #8a5a00; }
.verdict.off { color: var(--offink); background: var(--off); font-weight: 600; }
.verdict.neutral { color: var(--muted); }
tr.absent td { color: var(--muted); }
.warning { border: 1px solid #e0a800; border-left: 6px solid #e0a800; background: #fff8e1; padding: 8px 14px; margin: 10px 0; border-radius: 3px; }
.family { border: 1px solid var(--rule); border-left: 6px solid #5b7db1; background: #f5f8fc; padding: 4px 16px 10px; margin: 24px 0; border-radius: 3px; }
dl.model { display: grid; grid-template-columns: max-content 1fr; gap: 4px 14px; }
dl.model dt { font-weight: 600; }
dl.model dd { margin: 0; }
.erratum { border-top: 1px solid var(--rule); margin-top: 10px; }
.meta { color: var(--muted); margin: 0 0 8px; }
.failure { border: 1px solid var(--offink); border-left: 6px solid var(--offink); background: var(--off); padding: 8px 14px; margin: 10px 0; border-radius: 3px; }
.failure pre { white-space: pre-wrap; margin: 6px 0 0; font-size: 13px; }
td.status { text-align: left; }
td.status.ok { color: var(--ok); }
td.status.warned { background: #fff8e1; color: #7a5a00; }
td.status.failed { background: var(--off); color: var(--offink); font-weight: 600; }
ul.notes { margin: 4px 0; padding-left: 22px; }
ul.notes li { margin: 2px 0; }
.figures { display: flex; flex-wrap: wrap; gap: 18px; align-items: flex-start; }
figure { margin: 0; border: 1px solid var(--rule); border-radius: 4px; padding: 8px; background: #fff; max-width: 100%; }
figure.wide { flex-basis: 100%; }
figure.plot { flex: 1 1 520px; max-width: 780px; }
figure.plot img { width: 100%; }
figure img { display: block; max-width: 100%; height: auto; }
figcaption { color: var(--muted); font-size: 13px; margin-top: 4px; max-width: 760px; }
footer { color: var(--muted); font-size: 13px; margin-top: 40px; border-top: 1px solid var(--rule); padding-top: 10px; }
"#;

/// The whole page: one summary row and one section per entry, in the order given; `figures` has
/// one element per entry (empty for a failed one).
pub(crate) fn page(entries: &[Entry], figures: &[SectionFigures], meta: &ReportMeta) -> String {
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>tribo — Chapter IV report ({tier})</title>\n<style>{CSS}</style>\n</head>\n<body>\n",
        tier = escape(&meta.tier)
    );
    header(&mut h, entries, meta);
    h.push_str("<main>\n");
    contents(&mut h, entries);
    summary(&mut h, entries);
    substokes_row_zero(&mut h, entries);
    let mut boxes_shown = BTreeSet::new();
    for (entry, figs) in entries.iter().zip(figures) {
        let table = match entry {
            Entry::Done(s) => s.run.table.as_str(),
            Entry::Failed(f) => f.table.as_str(),
        };
        if let Some(family) = families::family_of(table) {
            if boxes_shown.insert(family.id.as_str()) {
                family_box(&mut h, family);
            }
        }
        match entry {
            Entry::Done(section) => table_section(&mut h, section, figs),
            Entry::Failed(failure) => failed_section(&mut h, failure),
        }
    }
    performance_section(&mut h, entries);
    errata_section(&mut h, entries);
    let _ = writeln!(
        h,
        "<footer>Written by {}. Thesis values are the printed tables of Chapter IV, shown for \
         comparison only; every tribo value above was computed in this run.</footer>",
        escape(&meta.generated_by)
    );
    h.push_str("</main>\n</body>\n</html>\n");
    h
}

fn header(h: &mut String, entries: &[Entry], meta: &ReportMeta) {
    let failed = entries
        .iter()
        .filter(|e| matches!(e, Entry::Failed(_)))
        .count();
    let tables = if failed == 0 {
        entries.len().to_string()
    } else {
        format!("{} ({failed} failed)", entries.len())
    };
    let _ = write!(
        h,
        "<header><div class=\"inner\">\n<h1>tribo — Chapter IV recomputed</h1>\n\
         <p>tribo re-runs the adaptive finite element computations of Chapter IV of F. Gimbel, \
         <i>Modelling and Numerical Simulation of Contact and Lubrication</i> (Siegen, 2012) — \
         linear elasticity, z- and Signorini contact, model-adaptive contact, and Reynolds / \
         SubStokes thin-film flow with and without cavitation — and shows each table beside the \
         printed one, with convergence, mesh and solution figures.</p>\n<dl>\
         <div><dt>tier</dt><dd>{}</dd></div>\
         <div><dt>tables</dt><dd>{}</dd></div>\
         <div><dt>total wall time</dt><dd>{}</dd></div>\
         <div><dt>threads</dt><dd>{}</dd></div>\
         <div><dt>generated by</dt><dd>{}</dd></div>\
         <div><dt>commit</dt><dd>{}</dd></div>\
         <div><dt>date</dt><dd>{}</dd></div>\
         <div><dt>machine</dt><dd>{}</dd></div>\
         <div><dt>command</dt><dd><code>{}</code></dd></div></dl>\n</div></header>\n",
        escape(&meta.tier),
        tables,
        fmt_seconds(meta.total_seconds),
        meta.threads,
        escape(&meta.generated_by),
        escape(&meta.provenance.commit),
        escape(&meta.provenance.date),
        escape(&meta.provenance.machine),
        escape(&meta.provenance.command),
    );
}

fn contents(h: &mut String, entries: &[Entry]) {
    h.push_str("<nav>\n<h2>Contents</h2>\n<ol>\n<li><a href=\"#summary\">Summary</a></li>\n");
    if entries.iter().any(
        |e| matches!(e, Entry::Done(s) if s.run.cuts.as_ref().is_some_and(Cuts::compares_models)),
    ) {
        h.push_str("<li><a href=\"#substokes-row-zero\">SubStokes: the estimate on the initial grid</a></li>\n");
    }
    for entry in entries {
        let _ = match entry {
            Entry::Done(s) => writeln!(
                h,
                "<li><a href=\"#{}\">{} ({})</a> — {}</li>",
                anchor(&s.run.table),
                escape(&entry_name(&s.run.table)),
                escape(&s.run.section),
                escape(&s.run.title)
            ),
            Entry::Failed(f) => writeln!(
                h,
                "<li><a href=\"#{}\">{}</a> — {} <b>({})</b></li>",
                anchor(&f.table),
                escape(&entry_name(&f.table)),
                escape(f.title.as_deref().unwrap_or("")),
                f.kind.name()
            ),
        };
    }
    h.push_str("<li><a href=\"#performance\">Performance</a></li>\n");
    h.push_str("<li><a href=\"#errata\">Thesis errata</a></li>\n</ol>\n</nav>\n");
}

/// A `<td>` holding a relative difference, highlighted beyond the column's tolerance.
fn diff_cell(column: &str, d: Option<f64>) -> String {
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
fn summary_diff_cell(column: &str, d: Option<f64>, scored: bool) -> String {
    match d {
        Some(d) if !scored => format!(
            "<td class=\"diff\" title=\"not scored\">{}</td>",
            fmt_pct(d)
        ),
        _ => diff_cell(column, d),
    }
}

fn opt_cell(v: Option<String>) -> String {
    match v {
        Some(s) => format!("<td>{s}</td>"),
        None => "<td class=\"na\">—</td>".into(),
    }
}

fn summary(h: &mut String, entries: &[Entry]) {
    h.push_str(
        "<section id=\"summary\">\n<h2>Summary</h2>\n\
         <p class=\"legend\">Status: ok, error (the run stopped with an error), panic (a bug in \
         tribo, caught) or not loaded (the experiment file was rejected); a failed table's \
         section has the message; figure: no printed table (the thesis shows the result as a \
         figure only, so tribo's rows are shown alone). Verdict: reproduced (every row within \
         tolerance), differs with the reason where it is known (the tooltip says it, the link \
         leads to the evidence), differs, unexplained; a table the thesis prints as a copy of \
         another, and a figure, are not scored. Rows within tolerance: the computed rows whose \
         dofs and estimate are both within 3 % and 5 % of the printed ones, of the rows the \
         thesis prints. Tables of Chapter IV not on this page are listed as such. Geometric mean of the estimate ratio over \
         the cycles that have one (the mean reduction per cycle). Order: the experimental order of \
         convergence, the least-squares slope of log estimate against log dofs over the rows \
         (−½ is optimal for Q₁ elements in two dimensions). Largest relative difference to the thesis over the \
         computed cycles; <span class=\"swatch\"></span> beyond 3 % (dofs) or 5 % (estimate).</p>\n\
         <div class=\"scroll\"><table>\n<thead><tr><th class=\"text\">table</th><th class=\"text\">section</th>\
         <th class=\"text\">title</th><th class=\"text\">status</th><th class=\"text\">verdict</th>\
         <th>rows within tolerance</th><th>rows (tribo / thesis)</th>\
         <th>last dofs</th><th>last estimate</th><th>geo-mean ratio</th>\
         <th>order (tribo / thesis)</th><th>max Δ dofs</th>\
         <th>max Δ estimate</th><th>seconds</th></tr></thead>\n<tbody>\n",
    );
    let mut next_thesis_table = 1;
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
        let sm = Summary::of(s);
        let not_scored = match &s.thesis.comparison {
            Comparison::OwnScene => Some("own scene: not compared".to_string()),
            Comparison::Edited(_) => Some("edited: not scored".to_string()),
            Comparison::Printed => None,
        };
        let verdict = verdict::of(s, known_reason(s), not_scored);
        let scored = !matches!(
            verdict,
            Verdict::Duplicate { .. } | Verdict::NotScored { .. }
        );
        let within = verdict::rows_within(s);
        let within = if within.scored == 0 || !scored {
            "—".to_string()
        } else {
            format!("{} / {}", within.within, within.scored)
        };
        let dup = if s.thesis.duplicate_of.is_some() {
            " <span title=\"the printed table is a copy of another table\">⚠</span>"
        } else {
            ""
        };
        let _ = writeln!(
            h,
            "<tr><td class=\"text\"><a href=\"#{}\">{}</a>{dup}</td><td class=\"text\">{}</td>\
             <td class=\"text\">{}</td>{}{}<td>{within}</td><td>{} / {}</td>{}{}{}<td>{} / {}</td>{}{}<td>{}</td></tr>",
            anchor(&s.run.table),
            escape(&s.run.table),
            escape(&s.run.section),
            escape(&s.run.title),
            status_cell(s),
            verdict_cell(&verdict),
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
    if next_thesis_table > 1 {
        absent_summary_rows(h, next_thesis_table..verdict::THESIS_TABLES + 1);
    }
    h.push_str("</tbody></table></div>\n</section>\n");
}

/// The verdict cell: the verdict's words, the reason as a tooltip and a link to its evidence.
fn verdict_cell(v: &Verdict) -> String {
    match v {
        Verdict::DiffersKnown(r) => {
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
fn absent_summary_rows(h: &mut String, numbers: std::ops::Range<usize>) {
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
         <td class=\"text na\" colspan=\"10\">{how}</td></tr>"
    );
}

/// Why the section's numbers differ from the printed ones, where the report knows it
/// ([`errata::known_difference`]), linked to the first thesis erratum affecting the table, or
/// else to the table's own section, whose readings give the evidence.
fn known_reason(section: &Section) -> Option<KnownReason> {
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
fn substokes_row_zero(h: &mut String, entries: &[Entry]) {
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
fn status_cell(s: &Section) -> String {
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
fn failed_summary_row(h: &mut String, f: &Failure) {
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
         <td class=\"text na\" colspan=\"10\">{}</td></tr>",
        anchor(&f.table),
        escape(&f.table),
        escape(f.section.as_deref().unwrap_or("—")),
        escape(f.title.as_deref().unwrap_or("—")),
        f.kind.name(),
        why
    );
}

/// The section of a table that failed: table, status, cycle (when known) and the message.
fn failed_section(h: &mut String, f: &Failure) {
    let title = f
        .title
        .as_deref()
        .map_or_else(String::new, |t| format!(" — {}", escape(t)));
    let _ = write!(
        h,
        "<section id=\"{}\" class=\"failed\">\n<h2>{}{title}</h2>\n<p class=\"meta\">",
        anchor(&f.table),
        escape(&entry_name(&f.table)),
    );
    if let Some(section) = &f.section {
        let _ = write!(h, "Section {} · ", escape(section));
    }
    let _ = writeln!(h, "status {}</p>", f.kind.name());
    failure_box(h, "", f);
    h.push_str(match f.kind {
        FailureKind::NotLoaded => {
            "<p>no data: the experiment file did not load; earlier output of this table was \
             removed.</p>\n"
        }
        _ => "<p>no data: the run failed; earlier output of this table was removed.</p>\n",
    });
    h.push_str("</section>\n");
}

/// A highlighted box saying what failed (`what` names an alternative reading, or is empty for
/// the table itself), where, and the message.
fn failure_box(h: &mut String, what: &str, f: &Failure) {
    let headline = match (f.kind, f.cycle) {
        (FailureKind::NotLoaded, _) => "The experiment file did not load.".to_string(),
        (FailureKind::Error, Some(c)) => format!("The run{what} failed in cycle {c}."),
        (FailureKind::Error, None) => format!("The run{what} failed."),
        (FailureKind::Panic, Some(c)) => {
            format!("The run{what} panicked in cycle {c} (a bug in tribo).")
        }
        (FailureKind::Panic, None) => format!("The run{what} panicked (a bug in tribo)."),
    };
    let _ = writeln!(
        h,
        "<div class=\"failure\"><b>{}</b> Table {}, status {}.<pre>{}</pre></div>",
        escape(&headline),
        escape(&f.table),
        f.kind.name(),
        escape(&f.message)
    );
}

/// A solver study (Fig. III.6): per Uzawa variant the iterations run, the first iteration with a
/// relative residual ≤ 1e-6, the relative residual at iteration 50 and at the last, the pressure
/// error against the direct solve, the inner CG iterations and the seconds.
fn uzawa_table(h: &mut String, rows: &[crate::linalg::uzawa::UzawaRow]) {
    h.push_str(
        "<p class=\"legend\">Relative residual r_k/r_0 with r_k = √(‖Av − Bp − f‖² + ‖Bᵀv + Cp − \
         g‖²); pressure error ‖p_k − p‖₂/‖p‖₂ against the direct LDLᵀ solve of the coupled \
         system; inner CG iterations and wall seconds summed over the run.</p>\n\
         <div class=\"scroll\"><table>\n<thead><tr><th class=\"text\">variant</th>\
         <th>iterations</th><th>first ≤ 1e-6</th><th>relative residual at 50</th>\
         <th>last relative residual</th><th>last pressure error</th><th>inner CG</th>\
         <th>seconds</th></tr></thead>\n<tbody>\n",
    );
    let mut variants: Vec<&str> = Vec::new();
    for r in rows {
        if !variants.contains(&r.variant.as_str()) {
            variants.push(&r.variant);
        }
    }
    for v in variants {
        let of: Vec<_> = rows.iter().filter(|r| r.variant == v).collect();
        let Some(last) = of.last() else { continue };
        let first = of.iter().find(|r| r.relative_residual <= 1e-6);
        let at50 = of.iter().find(|r| r.iteration == 50);
        let _ = writeln!(
            h,
            "<tr><td class=\"text\">{}</td><td>{}</td>{}{}<td>{}</td>{}<td>{}</td><td>{}</td></tr>",
            escape(v),
            last.iteration,
            opt_cell(first.map(|r| r.iteration.to_string())),
            opt_cell(at50.map(|r| fmt_sig(r.relative_residual))),
            fmt_sig(last.relative_residual),
            opt_cell(last.pressure_error.map(fmt_sig)),
            of.iter().map(|r| r.inner_iterations).sum::<usize>(),
            fmt_seconds(last.seconds),
        );
    }
    h.push_str("</tbody></table></div>\n");
}

/// Names of tribo's columns the thesis does not print, in first-appearance order.
fn tribo_only_columns(rows: &[Row], thesis_columns: &[String]) -> Vec<(String, bool)> {
    let mut out: Vec<(String, bool)> = Vec::new();
    let known = |n: &str| thesis_columns.iter().any(|c| c == n);
    for r in rows {
        for (name, value) in &r.columns {
            if !known(name) && !out.iter().any(|(n, _)| n == name) {
                out.push((name.to_string(), matches!(value, Value::Count(_))));
            }
        }
    }
    out
}

/// One table's section: comparison table, notes, figures, probes.
fn table_section(h: &mut String, s: &Section, figs: &SectionFigures) {
    let run = s.run;
    let thesis = s.thesis;
    let computed = if s.is_figure() {
        format!(
            "{} {} computed, {}",
            run.rows.len(),
            row_noun(run),
            if s.thesis.comparison.is_printed() {
                "no printed table"
            } else {
                "not compared"
            }
        )
    } else {
        format!(
            "{} cycles computed, {} printed",
            run.rows.len(),
            thesis.len()
        )
    };
    let _ = write!(
        h,
        "<section id=\"{}\">\n<h2>{} — {}</h2>\n<p class=\"meta\">Section {} · tier {} · \
         {computed}</p>\n",
        anchor(&run.table),
        escape(&entry_name(&run.table)),
        escape(&run.title),
        escape(&run.section),
        escape(&run.tier),
    );
    parameters(h, &run.parameters);
    if let Some(orig) = &thesis.duplicate_of {
        let _ = writeln!(
            h,
            "<div class=\"warning\"><b>Duplicate in the thesis.</b> The thesis prints this table \
             as a copy of {}; tribo computes the scene itself.</div>",
            escape(orig)
        );
    }
    if !run.warnings.is_empty() {
        h.push_str(
            "<div class=\"warning\"><b>Suspicious scene.</b> The table ran, but not as its \
             experiment file probably meant:\n<ul class=\"notes\">\n",
        );
        for w in &run.warnings {
            let _ = writeln!(h, "<li>{}</li>", escape(w));
        }
        h.push_str("</ul></div>\n");
    }
    if !run.uzawa.is_empty() {
        uzawa_table(h, &run.uzawa);
    } else if s.is_figure() {
        not_compared_notice(h, s);
        figure_rows(h, run, s.thesis.comparison.is_printed());
    } else {
        comparison_table(h, s);
    }
    for alt in s.alternatives {
        match &alt.outcome {
            Ok(alt_run) => alternative_table(h, run, thesis, &alt.label, alt_run),
            Err(failure) => {
                let _ = writeln!(h, "<h3>Alternative reading: {}</h3>", escape(&alt.label));
                failure_box(h, " of this reading", failure);
                h.push_str("<p>no data: the run failed.</p>\n");
            }
        }
    }

    if !run.costs.is_empty() {
        cost_table(h, &run.costs);
        claim_paragraph(h, &run.costs);
    }

    readings(h, &run.table, &run.notes);

    if let Some(error) = &figs.error {
        let _ = writeln!(
            h,
            "<h3>Figures</h3>\n<div class=\"failure\"><b>The figures could not be drawn.</b>\
             <pre>{}</pre></div>",
            escape(error)
        );
    }
    if !figs.figures.is_empty() {
        h.push_str("<h3>Figures</h3>\n<div class=\"figures\">\n");
        for f in &figs.figures {
            // Pictures of the whole domain get the full page width; plots keep their own size.
            let wide = ["-mesh", "-deformed", "-field", "-animation"]
                .iter()
                .any(|k| f.file.contains(k));
            let _ = write!(
                h,
                "<figure{}><img src=\"figures/{}\" alt=\"{}\" loading=\"lazy\"><figcaption>{}</figcaption>",
                if wide { " class=\"wide\"" } else { " class=\"plot\"" },
                escape(&f.file),
                escape(&f.caption),
                escape(&f.caption)
            );
            if !f.links.is_empty() {
                h.push_str("<p class=\"legend\">Files: ");
                for (i, (file, label)) in f.links.iter().enumerate() {
                    let _ = write!(
                        h,
                        "{}<a href=\"figures/{}\">{}</a>",
                        if i == 0 { "" } else { " · " },
                        escape(file),
                        escape(label)
                    );
                }
                h.push_str("</p>");
            }
            h.push_str("</figure>\n");
        }
        h.push_str("</div>\n");
    }

    if !run.probes.is_empty() {
        h.push_str(
            "<h3>Probes after the last cycle</h3>\n<table><thead><tr><th>x</th><th>y</th>\
             <th class=\"text\">component</th><th>value</th></tr></thead><tbody>\n",
        );
        for p in &run.probes {
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td>{}</td><td class=\"text\">{}</td><td>{}</td></tr>",
                fmt_short(p.x),
                fmt_short(p.y),
                escape(&p.component),
                fmt_sig(p.value)
            );
        }
        h.push_str("</tbody></table>\n");
    }
    h.push_str("</section>\n");
}

/// The problem solved, stated from the experiment file: its `[scene]` and `[study]` keys
/// (domain, mesh, gap or obstacles, velocities, boundary values, loads, material, marking
/// fractions, estimator reading), grouped by the file's tables. Open by default; nothing for a
/// run without parameters.
fn parameters(h: &mut String, parameters: &[crate::results::Parameter]) {
    if parameters.is_empty() {
        return;
    }
    h.push_str(
        "<details class=\"params\" open><summary>Problem solved: the scene and the study as the \
         experiment file states them</summary>\n<table><tbody>\n",
    );
    let mut group = "";
    for p in parameters {
        if p.group != group {
            group = &p.group;
            let _ = writeln!(
                h,
                "<tr><td class=\"group\" colspan=\"2\">[{}]</td></tr>",
                escape(group)
            );
        }
        let _ = writeln!(
            h,
            "<tr><td class=\"key\">{}</td><td class=\"value\">{}</td></tr>",
            escape(&p.key),
            escape(&p.value)
        );
    }
    h.push_str("</tbody></table></details>\n");
}

/// The "Readings and known differences" block of a table's section: the table's own notes first,
/// then the known difference, the family's shared notes that hold for it (shown once in the family
/// box, linked), and the thesis errata that affect the table (linked to the errata section).
fn readings(h: &mut String, table: &str, notes: &[String]) {
    let family = families::family_of(table);
    let shared = family
        .map(|f| families::notes_for(f, table).len())
        .unwrap_or(0);
    let found = errata::errata_for(table);
    let known = errata::known_difference(table);
    if notes.is_empty() && family.is_none() && found.is_empty() && known.is_none() {
        return;
    }
    h.push_str("<h3>Readings and known differences</h3>\n");
    if !notes.is_empty() {
        h.push_str("<ul class=\"notes\">\n");
        for n in notes {
            let _ = writeln!(h, "<li>{}</li>", escape(n));
        }
        h.push_str("</ul>\n");
    }
    if let Some(k) = known {
        let _ = writeln!(
            h,
            "<p class=\"known\"><b>Known difference ({}):</b> {}</p>",
            k.kind.name(),
            escape(k.reason)
        );
    }
    if let Some(f) = family {
        let what = match shared {
            0 => "The model and its conventions".to_string(),
            1 => "The model, its conventions and 1 shared note that holds for this table".into(),
            n => {
                format!("The model, its conventions and {n} shared notes that hold for this table")
            }
        };
        let _ = writeln!(
            h,
            "<p class=\"family-link\">{what}: <a href=\"#{}\">{}</a>.</p>",
            f.id,
            escape(&f.name)
        );
    }
    if !found.is_empty() {
        h.push_str("<p class=\"errata-link\">Thesis errata affecting this table: ");
        for (i, e) in found.iter().enumerate() {
            let _ = write!(
                h,
                "{}<a href=\"#{}\">{}</a>",
                if i == 0 { "" } else { " · " },
                escape(&e.id),
                escape(&e.title)
            );
        }
        h.push_str(".</p>\n");
    }
}

/// A family's "model and conventions" box with the notes its tables share; shown once, before
/// the first section of the family on the page.
fn family_box(h: &mut String, family: &Family) {
    let _ = write!(
        h,
        "<section id=\"{}\" class=\"family\">\n<h2>{} — model and conventions</h2>\n\
         <p class=\"meta\">{}</p>\n<dl class=\"model\">\n",
        family.id,
        escape(&family.name),
        escape(&family.sections)
    );
    for item in &family.model {
        let _ = writeln!(
            h,
            "<dt>{}</dt><dd>{}</dd>",
            escape(&item.heading),
            escape(&item.text)
        );
    }
    h.push_str("</dl>\n");
    if !family.notes.is_empty() {
        h.push_str("<h3>Notes shared by the family</h3>\n<ul class=\"notes\">\n");
        for n in &family.notes {
            let tables = if n.tables.is_empty() {
                "All tables".to_string()
            } else {
                n.tables
                    .iter()
                    .map(|t| entry_name(t))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            let _ = writeln!(h, "<li><b>{}:</b> {}</li>", escape(&tables), escape(&n.text));
        }
        h.push_str("</ul>\n");
    }
    h.push_str("</section>\n");
}

/// File name of the performance figure ([`super::plots::solve_cost`]).
pub(crate) const PERFORMANCE_FIGURE: &str = "performance-solve.svg";

/// The performance section: where each table's time goes (seconds per phase over all its
/// cycles), the solver and its CG iterations, the cost of a solve per unknown, and the measured
/// reference of a deal.II program.
fn performance_section(h: &mut String, entries: &[Entry]) {
    h.push_str(
        "<section id=\"performance\">\n<h2>Performance</h2>\n<p>Seconds per phase summed over \
         every cycle of a table (the unprinted ones included), from the table's own clock. Tables \
         run side by side (<code>--jobs</code>, one per core by default) share the cores, so \
         their phases take longer than alone; run with <code>--jobs 1</code> to time one table. \
         The Reynolds systems are solved by multigrid-preconditioned CG unless the run chose \
         <code>--solver direct</code>, the elasticity systems by the direct solver unless it \
         chose <code>--solver multigrid</code>, the contact systems always by the direct \
         solver; the CG iterations are the most of any solve of a cycle. CG stops at a relative \
         residual of 1e-13; in the cavitation tables a step of the active-set iteration, which \
         only decides the next active set, stops at 1e-10, and the final active set is \
         confirmed by a solve at 1e-13, whose solution the table reports. The V-cycle applies \
         its level matrices in single precision, its vectors and sums in double; CG's operator \
         is the matrix in double precision.</p>\n",
    );
    let _ = writeln!(
        h,
        "<figure><img src=\"figures/{PERFORMANCE_FIGURE}\" alt=\"solve seconds per million \
         unknowns against unknowns\" loading=\"lazy\"><figcaption>Solve seconds per million \
         unknowns against the unknowns, one dot per cycle: a cost proportional to the unknowns \
         is flat.</figcaption></figure>"
    );
    h.push_str(
        "<table class=\"performance\"><thead><tr><th>table</th><th>solver</th>\
         <th>largest dofs</th><th>most CG iterations</th><th>setup s</th><th>assemble s</th>\
         <th>solve s</th><th>estimate s</th><th>refine s</th><th>total s</th></tr></thead>\n<tbody>\n",
    );
    for entry in entries {
        let Entry::Done(s) = entry else { continue };
        let rows = &s.run.rows;
        if rows.is_empty() {
            continue;
        }
        let cg = rows
            .iter()
            .filter_map(|r| r.count_of(crate::results::columns::CG_ITERATIONS))
            .max();
        let solver = if cg.is_some() { "multigrid" } else { "direct" };
        let dofs = rows.iter().filter_map(|r| r.dofs()).max();
        let phases = rows
            .iter()
            .fold(crate::results::PhaseSeconds::default(), |sum, r| {
                sum.plus(&r.seconds)
            });
        let _ = write!(
            h,
            "<tr><td><a href=\"#{}\">{}</a></td><td>{solver}</td><td>{}</td><td>{}</td>",
            anchor(&s.run.table),
            escape(&s.run.table),
            dofs.map_or("–".into(), |d| d.to_string()),
            cg.map_or("–".into(), |k| k.to_string()),
        );
        let seconds = phases.named().map(|(_, v)| v);
        for (i, v) in seconds.iter().chain([&phases.total()]).enumerate() {
            let class = if i == 0 { " class=\"first\"" } else { "" };
            let _ = write!(h, "<td{class}>{v:.2}</td>");
        }
        h.push_str("</tr>\n");
    }
    h.push_str(
        "</tbody></table>\n<p><b>A measured reference.</b> A deal.II 9.4 program solving the \
         same squeeze problem (IV.7) on the same adaptive meshes, 9 cycles up to 706 893 \
         unknowns, took 20.2 s with UMFPACK and 59 s with CG and SSOR as measured for this \
         project; Table IV.36 is that run here (its total is above). It is a measurement of one \
         program, not a claim about deal.II in general.</p>\n\
         </section>\n",
    );
}

/// The errata section: every thesis defect tribo found, with its evidence and the reading used,
/// and links to the affected tables that are on the page.
fn errata_section(h: &mut String, entries: &[Entry]) {
    let on_page: BTreeSet<&str> = entries
        .iter()
        .map(|e| match e {
            Entry::Done(s) => s.run.table.as_str(),
            Entry::Failed(f) => f.table.as_str(),
        })
        .collect();
    h.push_str(
        "<section id=\"errata\">\n<h2>Thesis errata</h2>\n<p>Defects of the printed thesis \
         found while reproducing Chapter IV — duplicated tables, spikes and noise, contradictions \
         between text and tables, garbled or missing formulas — with the evidence and the reading \
         tribo uses.</p>\n",
    );
    for e in errata::errata() {
        erratum_entry(h, e, &on_page);
    }
    h.push_str("</section>\n");
}

fn erratum_entry(h: &mut String, e: &Erratum, on_page: &BTreeSet<&str>) {
    let tables = e
        .tables
        .iter()
        .map(|t| {
            if on_page.contains(t.as_str()) {
                format!("<a href=\"#{}\">{}</a>", anchor(t), escape(&entry_name(t)))
            } else {
                escape(&entry_name(t))
            }
        })
        .collect::<Vec<_>>()
        .join(", ");
    let _ = writeln!(
        h,
        "<div class=\"erratum\" id=\"{}\">\n<h3>{}</h3>\n<p class=\"meta\">{} · affects {}</p>\n\
         <p><b>Evidence.</b> {}</p>\n<p><b>Reading.</b> {}</p>\n</div>",
        escape(&e.id),
        escape(&e.title),
        e.kind.name(),
        tables,
        escape(&e.evidence),
        escape(&e.reading)
    );
}

/// Why a section has no thesis columns when its experiment is not the printed one: a scene of
/// the user's own, or a thesis experiment whose file was edited (the fields that differ).
fn not_compared_notice(h: &mut String, s: &Section) {
    let csv = escape(&super::data::csv_stem(&s.run.table));
    let _ = match &s.thesis.comparison {
        Comparison::Printed => Ok(()),
        Comparison::OwnScene => writeln!(
            h,
            "<div class=\"warning\"><b>Own scene: no thesis table, not compared.</b> This \
             experiment has an id of its own and no <code>[thesis]</code>; the rows below are \
             tribo's alone (every column is in <code>data/{csv}.csv</code>).</div>"
        ),
        Comparison::Edited(fields) => {
            let what = if thesis_figure(&s.run.table).is_some() {
                "the thesis's"
            } else {
                "the printed table's"
            };
            let fields = if fields.is_empty() {
                String::new()
            } else {
                let list: Vec<String> = fields
                    .iter()
                    .map(|f| format!("<code>{}</code>", escape(f)))
                    .collect();
                format!(" (fields {})", list.join(", "))
            };
            writeln!(
                h,
                "<div class=\"warning\"><b>Edited: not scored against the thesis.</b> The \
                 parameters differ from {what}{fields}, so the rows below are tribo's alone, \
                 with nothing compared (every column is in <code>data/{csv}.csv</code>).</div>"
            )
        }
    };
}

/// What one row of a run is: a load step of the forming (§IV.2.4.7), or a cycle.
fn row_noun(run: &RunResult) -> &'static str {
    if run.is_load_steps() {
        "load steps"
    } else {
        "cycles"
    }
}

/// The columns of a load-step run that its section shows, in this order and where the run has
/// them (`data/<table>.csv` has every column).
const LOAD_STEP_COLUMNS: [&str; 9] = [
    columns::Z_FACES,
    columns::S_FACES,
    columns::DOFS,
    columns::MODEL_ERROR,
    columns::PENETRATION,
    columns::TIP_X,
    columns::TIP_Y,
    "z_iterations",
    "mixed_iterations",
];

/// The rows of a figure experiment, which the thesis prints no table for (the forming of
/// §IV.2.4.7 shows only the pictures of Fig. IV.54): tribo's values alone, no thesis columns,
/// no ratio to the thesis and no convergence verdict. A load-step run shows one row per step
/// with [`LOAD_STEP_COLUMNS`], any other run every column; then the seconds of the row. Without
/// `figure` (a scene of the user's own, an edited thesis experiment) the rows come without the
/// sentence about the thesis's figure.
fn figure_rows(h: &mut String, run: &RunResult, figure: bool) {
    let name = thesis_figure(&run.table).unwrap_or_else(|| "a figure".into());
    if figure {
        let _ = writeln!(
            h,
            "<p>The thesis prints no table for this result, only the pictures of {}, so these rows \
             have nothing to compare with: they are tribo's alone. Every column is in \
             <code>data/{}.csv</code>.</p>",
            escape(&name),
            escape(&super::data::csv_stem(&run.table))
        );
    }
    let shown: Vec<String> = if run.is_load_steps() {
        LOAD_STEP_COLUMNS
            .iter()
            .filter(|c| run.rows.iter().any(|r| r.get(c).is_some()))
            .map(|c| c.to_string())
            .collect()
    } else {
        tribo_only_columns(&run.rows, &[])
            .into_iter()
            .map(|(n, _)| n)
            .collect()
    };
    let _ = write!(
        h,
        "<div class=\"scroll\"><table>\n<thead><tr><th>{}</th>",
        super::data::first_column(run)
    );
    for c in &shown {
        let _ = write!(h, "<th>{}</th>", escape(c));
    }
    h.push_str("<th>seconds</th></tr></thead>\n<tbody>\n");
    for r in &run.rows {
        let _ = write!(h, "<tr><td>{}</td>", r.cycle);
        for c in &shown {
            h.push_str(&opt_cell(match r.get(c) {
                Some(Value::Count(n)) => Some(n.to_string()),
                Some(Value::Real(Some(v))) if v.is_finite() => Some(fmt_sig(v)),
                _ => None,
            }));
        }
        let total = r.seconds.total();
        let _ = writeln!(
            h,
            "{}</tr>",
            opt_cell(total.is_finite().then(|| format!("{total:.3}")))
        );
    }
    h.push_str("</tbody></table></div>\n");
}

/// The cost-of-accuracy study of a model-adaptive scene: per variant the median solve seconds
/// over the cycles, the iterations, and the accuracy reached in the last cycle; then what it
/// says about §IV.2.2's "advantage [of the Signorini solver] balanced out against the higher
/// speed of the z-solver".
fn cost_table(h: &mut String, costs: &[crate::results::CostRow]) {
    struct Summary {
        median: f64,
        iterations: i64,
        penetration: f64,
        distance: f64,
        faces: usize,
    }
    let summary = |variant: &str| -> Option<Summary> {
        let rows: Vec<_> = costs.iter().filter(|c| c.variant == variant).collect();
        let last = rows.last()?;
        let mut seconds: Vec<f64> = rows.iter().map(|c| c.seconds_solve).collect();
        seconds.sort_by(f64::total_cmp);
        let n = seconds.len();
        let median = if n % 2 == 1 {
            seconds[n / 2]
        } else {
            (seconds[n / 2 - 1] + seconds[n / 2]) / 2.0
        };
        Some(Summary {
            median,
            iterations: rows.iter().map(|c| c.iterations).sum(),
            penetration: last.penetration,
            distance: last.energy_distance,
            faces: last.accurate_faces,
        })
    };
    h.push_str(
        "<h3>Cost of accuracy (this scene's fixed mesh)</h3>\n<p class=\"legend\">Each variant \
         runs the table's cycles: z on every face, Signorini on every face (linearised once about \
         the z-solution), and the partitions of Algorithms III.2 and III.3. Seconds: median over \
         the cycles of both solves of a cycle (the z-solve is warm-started from the previous \
         cycle). Accuracy in the last cycle: the true penetration of the deformed boundary into \
         the obstacle and ‖s − s_S‖_a/‖s_S‖_a, s_S the all-Signorini solution. Data: \
         <code>data/&lt;table&gt;.cost.csv</code>.</p>\n<div class=\"scroll\"><table><thead><tr>\
         <th class=\"text\">variant</th><th>median solve s</th><th>iterations</th>\
         <th>Signorini faces</th><th>penetration</th><th>energy distance</th></tr></thead><tbody>\n",
    );
    let variants = crate::study::cost::VARIANTS;
    for v in variants {
        if let Some(s) = summary(v) {
            let _ = writeln!(
                h,
                "<tr><td class=\"text\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>\
                 <td>{}</td></tr>",
                escape(v),
                fmt_sig(s.median),
                s.iterations,
                s.faces,
                fmt_sig(s.penetration),
                fmt_sig(s.distance)
            );
        }
    }
    h.push_str("</tbody></table></div>\n");
    if let (Some(z), Some(signorini), Some(iii3)) =
        (summary("z"), summary("signorini"), summary("III.3"))
    {
        let speed = signorini.median / z.median;
        let advantage = z.penetration > signorini.penetration + PENETRATION_NOISE;
        let _ = writeln!(
            h,
            "<p>The z-solver is ×{} faster per cycle than Signorini on every face, and its \
             penetration is {} against {} ({}); Algorithm III.3 costs ×{} the z-solver's time per \
             cycle for an energy distance of {} with {} Signorini faces. {}</p>",
            fmt_short(speed),
            fmt_sig(z.penetration),
            fmt_sig(signorini.penetration),
            if advantage {
                "the Signorini model's advantage"
            } else {
                "no advantage of the Signorini model here"
            },
            fmt_short(iii3.median / z.median),
            fmt_sig(iii3.distance),
            iii3.faces,
            if speed > 1.0 && advantage {
                "§IV.2.2's trade-off holds on this scene: accuracy against speed."
            } else {
                "§IV.2.2's trade-off does not show on this scene."
            }
        );
    }
}

/// Penetrations that differ by less are the same (rounding of the one-step linearisation).
const PENETRATION_NOISE: f64 = 1e-8;

/// The claim closing §IV.2.3 on the III.2 and III.3 runs of the cost study.
fn claim_paragraph(h: &mut String, costs: &[crate::results::CostRow]) {
    let (lower_error, fewer_faces, n) = crate::study::cost::claim_of_section_iv_2_3(costs);
    if n == 0 {
        return;
    }
    let _ = writeln!(
        h,
        "<p><b>III.2 vs III.3</b> (§IV.2.3: \"after the same number of refinement cycles the \
         error estimate for the sorted error algorithm is lower than that of the fixed-fraction \
         algorithm and demands for the more expensive model on a lower number of faces\"): on \
         this scene III.3's model error is at most III.2's (or both at most ε₀) in {lower_error} \
         of {n} cycles (cycles 1–{n}), and III.3 uses at most as many Signorini faces in {fewer_faces} of \
         {n}. The claim {}.</p>",
        match (lower_error == n, fewer_faces == n) {
            (true, true) => "holds in every cycle",
            (true, false) => "holds for the error, not for the number of faces",
            (false, true) => "holds for the number of faces, not for the error",
            (false, false) => "holds for neither the error nor the number of faces",
        }
    );
}

/// How much an alternative reading changes the table: dofs and estimate of both runs per cycle
/// and the relative change, plus the range of the change in the heading.
fn alternative_table(
    h: &mut String,
    run: &RunResult,
    thesis: &ThesisTable,
    label: &str,
    alt: &RunResult,
) {
    let pairs: Vec<(&Row, &Row)> = run
        .rows
        .iter()
        .filter_map(|r| Some((r, alt.rows.iter().find(|a| a.cycle == r.cycle)?)))
        .collect();
    let range = |f: &dyn Fn(&Row) -> f64| {
        pairs.iter().filter_map(|(r, a)| rel_diff(f(a), f(r))).fold(
            None,
            |acc: Option<(f64, f64)>, d| {
                Some(acc.map_or((d, d), |(lo, hi)| (lo.min(d), hi.max(d))))
            },
        )
    };
    let span = |r: Option<(f64, f64)>| match r {
        Some((lo, hi)) => format!("{} … {}", fmt_pct(lo), fmt_pct(hi)),
        None => "—".into(),
    };
    // The headline columns: dofs and estimate of the grid-adaptive tables, the face split and
    // the model error of the model-adaptive ones (whose mesh is fixed).
    let model_adaptive = run.is_model_adaptive();
    let (count, value) = if model_adaptive {
        (columns::COARSE_FACES, columns::MODEL_ERROR)
    } else {
        (columns::DOFS, columns::ESTIMATE)
    };
    let _ = write!(
        h,
        "<h3>Alternative reading: {}</h3>\n<p class=\"legend\">Computed in this run. Against the \
         table above: {value} {}, {count} {}.</p>\n<div class=\"scroll\"><table><thead><tr>\
         <th>cycle</th><th>{count}</th><th>{count} (alt.)</th><th>Δ</th><th>{value}</th>\
         <th>{value} (alt.)</th><th>Δ</th><th>tribo/thesis</th><th>alt./thesis</th>\
         </tr></thead><tbody>\n",
        escape(label),
        span(range(&|r| r.value(value).unwrap_or(f64::NAN))),
        span(range(&|r| r.value(count).unwrap_or(f64::NAN))),
    );
    // The ratio to the printed row, compared as in the table above.
    let to_thesis = |rows: &[Row], cycle: usize| {
        let i = rows.iter().position(|r| r.cycle == cycle)?;
        let printed = thesis.value(cycle, value);
        let ratio = if model_adaptive {
            Some(rows[i].value(value)? / printed?).filter(|q| q.is_finite())
        } else {
            estimate_ratio(rows, i, printed)
        };
        ratio.map(fmt_sig)
    };
    for (r, a) in &pairs {
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{}</td>{}<td>{}</td><td>{}</td>{}{}{}</tr>",
            r.cycle,
            opt_count(r.value(count).map(|v| v as usize)),
            opt_count(a.value(count).map(|v| v as usize)),
            diff_cell(
                count,
                rel_diff(nan_or(a.value(count)), nan_or(r.value(count)))
            ),
            fmt_sig(nan_or(r.value(value))),
            fmt_sig(nan_or(a.value(value))),
            diff_cell(
                value,
                rel_diff(nan_or(a.value(value)), nan_or(r.value(value)))
            ),
            opt_cell(to_thesis(&run.rows, r.cycle)),
            opt_cell(to_thesis(&alt.rows, r.cycle)),
        );
    }
    h.push_str("</tbody></table></div>\n");
}

/// A value that may be missing, as NaN (which every formatter shows as missing).
fn nan_or(v: Option<f64>) -> f64 {
    v.unwrap_or(f64::NAN)
}

/// A count that may be missing.
fn opt_count(v: Option<usize>) -> String {
    v.map_or_else(|| "—".into(), |n| n.to_string())
}

/// tribo beside the thesis: for each printed column tribo | thesis | Δ, then the estimate ratio,
/// tribo-only columns and seconds per phase. Rows are the union of computed and printed cycles,
/// so a quick tier that stops early still shows what the thesis printed further on; of the
/// printed rows, the first [`MAX_SHOWN_THESIS_ROWS`] are shown and the legend counts the rest.
///
/// The time is linear in the rows shown: each cycle's row of tribo is found through a map built
/// once, and each printed value directly by its cycle ([`ThesisTable::value`]).
fn comparison_table(h: &mut String, s: &Section) {
    let run = s.run;
    let thesis = s.thesis;
    let compared: Vec<&str> = thesis
        .columns
        .iter()
        .map(String::as_str)
        .filter(|c| *c != "cycle")
        .collect();
    let has_estimate = compared.contains(&"estimate");
    let shifted = compares_previous_estimate(run);
    let part = thesis.additive_part.as_ref().filter(|_| has_estimate);
    let extra = tribo_only_columns(&run.rows, &thesis.columns);
    // With the shifted comparison, tribo's estimate on the printed mesh is a tribo-only column.
    let extra_label = |n: &str| match n {
        PREVIOUS_ESTIMATE if shifted => "estimate on this mesh".to_string(),
        THEOREM_ESTIMATE => "estimate of the theorem as stated, this mesh".to_string(),
        _ => n.to_string(),
    };
    let phases = ["setup", "assemble", "solve", "estimate", "refine", "total"];

    let cycles: BTreeSet<usize> = run
        .rows
        .iter()
        .map(|r| r.cycle)
        .chain(
            thesis
                .rows
                .iter()
                .take(MAX_SHOWN_THESIS_ROWS)
                .filter_map(|r| r.first().copied())
                .filter(|c| c.is_finite() && *c >= 0.0)
                .map(|c| c as usize),
        )
        .collect();
    // The first row of each cycle, as a search from the front would find it.
    let mut row_of_cycle: HashMap<usize, usize> = HashMap::with_capacity(run.rows.len());
    for (i, r) in run.rows.iter().enumerate() {
        row_of_cycle.entry(r.cycle).or_insert(i);
    }

    h.push_str(
        "<p class=\"legend\">Each printed column as tribo | thesis | Δ = tribo/thesis − 1; \
         <span class=\"swatch\"></span> |Δ| beyond 3 % (cells, dofs) or 5 % (other columns). \
         — : not computed in this tier or not printed.</p>\n",
    );
    let order = super::Summary::of(s);
    if order.order.is_some() || order.thesis_order.is_some() {
        let _ = writeln!(
            h,
            "<p class=\"legend\">Experimental order of convergence, the least-squares slope of \
             log estimate against log dofs over the rows: tribo {}, thesis {} (−½ is optimal \
             for Q₁ elements in two dimensions).</p>",
            order.order.map_or("—".into(), fmt_order),
            order.thesis_order.map_or("—".into(), fmt_order),
        );
    }
    if thesis.len() > MAX_SHOWN_THESIS_ROWS {
        let _ = writeln!(
            h,
            "<p class=\"legend\">The thesis table has {} printed rows: the first {} are shown \
             here and in the figures, {} are left out.</p>",
            thesis.len(),
            MAX_SHOWN_THESIS_ROWS,
            thesis.len() - MAX_SHOWN_THESIS_ROWS
        );
    }
    if shifted {
        h.push_str(
            "<p class=\"legend\">The thesis prints each row's mesh after refinement next to the \
             estimate of the solve before it; its estimate and ratio are compared with tribo's \
             estimate of the previous solve (column estimate_previous_mesh).</p>\n",
        );
    }
    if extra.iter().any(|(n, _)| n == THEOREM_ESTIMATE) {
        h.push_str(
            "<p class=\"legend\">The estimate columns and the marking use the volume residual \
             that reproduces the thesis's printed estimates (estimator = \"thesis-code\", see \
             the notes); the column \"estimate of the theorem as stated\" is the estimator of \
             Theorem III.16/III.17 with every term, on the printed mesh.</p>\n",
        );
    }
    if let Some(p) = part {
        let _ = writeln!(
            h,
            "<p class=\"legend\">{t} prints a mesh-independent part of the thesis's estimate \
             alone; the column tribo/√(thesis² − {t}²) compares tribo with the printed estimate \
             without that part.</p>",
            t = escape(&p.table)
        );
    }
    h.push_str("<div class=\"scroll\"><table>\n<thead><tr><th rowspan=\"2\">cycle</th>");
    for c in &compared {
        let label = if shifted && matches!(*c, "estimate" | "ratio") {
            format!("{c} (of the solve before)")
        } else {
            c.to_string()
        };
        let _ = write!(
            h,
            "<th class=\"group\" colspan=\"3\">{}</th>",
            escape(&label)
        );
    }
    if has_estimate {
        h.push_str("<th class=\"group\" rowspan=\"2\">tribo/thesis<br>(estimate)</th>");
    }
    if let Some(p) = part {
        let _ = write!(
            h,
            "<th class=\"group\" rowspan=\"2\">tribo/√(thesis² − {}²)</th>",
            escape(&p.table)
        );
    }
    if !extra.is_empty() {
        let _ = write!(
            h,
            "<th class=\"group\" colspan=\"{}\">tribo only</th>",
            extra.len()
        );
    }
    h.push_str("<th class=\"group\" colspan=\"6\">seconds</th></tr>\n<tr>");
    for _ in &compared {
        h.push_str("<th>tribo</th><th>thesis</th><th>Δ</th>");
    }
    for (n, _) in &extra {
        let _ = write!(h, "<th>{}</th>", escape(&extra_label(n)));
    }
    for p in phases {
        let _ = write!(h, "<th>{p}</th>");
    }
    h.push_str("</tr></thead>\n<tbody>\n");

    let ratio_cell = |q: Option<f64>| match q {
        Some(q) if (q - 1.0).abs() > tolerance("estimate") => {
            format!("<td class=\"first off\">{}</td>", fmt_sig(q))
        }
        Some(q) => format!("<td class=\"first\">{}</td>", fmt_sig(q)),
        None => "<td class=\"first na\">—</td>".into(),
    };
    for cycle in cycles {
        let index = row_of_cycle.get(&cycle).copied();
        let row = index.map(|i| &run.rows[i]);
        let compared_at = |c: &str| index.and_then(|i| compared_value(&run.rows, i, c));
        let _ = write!(h, "<tr><td>{cycle}</td>");
        for c in &compared {
            let t = compared_at(c);
            let p = thesis.value(cycle, c);
            // The thesis prints `inf` for the first ratio; tribo has none there. Both mean "no
            // previous cycle", shown as an en dash rather than a number.
            let is_first_ratio = *c == "ratio" && row.is_some_and(|r| r.ratio().is_none());
            let tribo_cell = match t {
                Some(v) => format!("<td class=\"first\">{}</td>", fmt_value(c, v)),
                None if is_first_ratio => "<td class=\"first\">–</td>".into(),
                None => "<td class=\"first na\">—</td>".into(),
            };
            let thesis_cell = match p {
                Some(v) if *c == "ratio" && v.is_infinite() => "<td class=\"thesis\">–</td>".into(),
                Some(v) => format!("<td class=\"thesis\">{}</td>", fmt_value(c, v)),
                None => "<td class=\"thesis na\">—</td>".into(),
            };
            let _ = write!(
                h,
                "{tribo_cell}{thesis_cell}{}",
                diff_cell(c, t.zip(p).and_then(|(t, p)| rel_diff(t, p)))
            );
        }
        let ratio_to = |p: Option<f64>| index.and_then(|i| estimate_ratio(&run.rows, i, p));
        if has_estimate {
            h.push_str(&ratio_cell(ratio_to(thesis.value(cycle, "estimate"))));
        }
        if part.is_some() {
            h.push_str(&ratio_cell(ratio_to(thesis.estimate_without_part(cycle))));
        }
        for (i, (n, integer)) in extra.iter().enumerate() {
            let class = if i == 0 { "first" } else { "" };
            let v = row.and_then(|r| match n.as_str() {
                "ratio" => r.ratio(),
                PREVIOUS_ESTIMATE if shifted => r.estimate(),
                _ => r.value(n),
            });
            let _ = match v {
                Some(v) if *integer && v.fract() == 0.0 => {
                    write!(h, "<td class=\"{class}\">{v:.0}</td>")
                }
                Some(v) => write!(h, "<td class=\"{class}\">{}</td>", fmt_sig(v)),
                None if n == "ratio" && row.is_some() => write!(h, "<td class=\"{class}\">–</td>"),
                None => write!(h, "<td class=\"{class} na\">—</td>"),
            };
        }
        match row {
            Some(r) => {
                let s = r.seconds;
                for (i, v) in [
                    s.setup,
                    s.assemble,
                    s.solve,
                    s.estimate,
                    s.refine,
                    s.total(),
                ]
                .into_iter()
                .enumerate()
                {
                    let class = if i == 0 { " class=\"first\"" } else { "" };
                    let _ = write!(h, "<td{class}>{v:.3}</td>");
                }
            }
            None => {
                h.push_str("<td class=\"first na\">—</td>");
                h.push_str(&"<td class=\"na\">—</td>".repeat(5));
            }
        }
        h.push_str("</tr>\n");
    }
    h.push_str("</tbody></table></div>\n");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_have_four_significant_digits() {
        assert_eq!(fmt_sig(0.286), "0.2860");
        assert_eq!(fmt_sig(1000.0), "1000");
        assert_eq!(fmt_sig(1.5e-5), "1.500e-5");
        assert_eq!(fmt_sig(f64::INFINITY), "—");
        assert_eq!(fmt_sig(f64::NAN), "—");
    }

    #[test]
    fn escapes_markup() {
        assert_eq!(escape("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
    }

    #[test]
    fn control_characters_become_visible() {
        assert_eq!(escape("a\u{0}b\u{7}c"), "a\\u{0}b\\u{7}c");
        assert_eq!(
            escape("\u{1b}[31m\u{7f}\u{85}"),
            "\\u{1b}[31m\\u{7f}\\u{85}"
        );
        assert_eq!(escape("x\u{202e}y"), "x\\u{202e}y");
        // Newlines and tabs are text, and so is everything printable.
        assert_eq!(escape("a\nb\tc μ ≈ √"), "a\nb\tc μ ≈ √");
    }
}
