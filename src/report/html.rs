//! Layout of the report's pages: header, contents, summary, and one section per table.
//!
//! The pages are built as strings with inline CSS and no scripts, so they render identically
//! from disk, from a CI artefact or from an archive. Every piece of text that comes from data
//! (titles, notes, column names, captions, error messages) goes through [`escape`], which also
//! makes control characters visible. Every table has a summary row with its status and a
//! section, also a table that failed; its section holds the cycle and the message instead of
//! data.
//!
//! Which page shows what (`pages`), the summaries (`summary`), the readings, family boxes and
//! errata (`readings`) and the tables of a section (`tables`) have their own modules; this file
//! holds the sections and the formatting every part shares.

mod accuracy;
mod compare;
mod pages;
mod quantities;
mod readings;
mod signorini;
mod summary;
mod tables;

use std::collections::{BTreeSet, HashMap};
use std::fmt::Write as _;

use super::compare::ComparedRuns;
use super::errata::{self, Erratum};
use super::families::{self, Family};
use super::verdict::{self, KnownReason, Score, Verdict};
use super::{
    compared_value, compares_previous_estimate, estimate_ratio, fmt_effectivity, rel_diff,
    thesis_figure, tolerance, Entry, Failure, FailureKind, Figure, ReportMeta, Section, Summary,
    MAX_SHOWN_THESIS_ROWS,
};
use crate::experiment::Comparison;
use crate::results::columns::{self, PREVIOUS_ESTIMATE, THEOREM_ESTIMATE};
use crate::results::{Cuts, ErrorMeasure, Row, RunResult, Value};
use crate::thesis::ThesisTable;
use readings::*;
use summary::*;
use tables::*;

pub(crate) use pages::{page_files, pages, FRONT_PAGE};

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
details.entry { border-bottom: 1px solid var(--rule); }
details.entry > summary { cursor: pointer; font-size: 17px; font-weight: 600; padding: 6px 0; }
details.entry[open] > summary { color: var(--muted); font-size: 14px; }
.params { margin: 10px 0; }
.params summary { cursor: pointer; font-weight: 600; }
.params table { margin: 6px 0; }
.params td.group { font-weight: 600; background: var(--band); text-align: left; }
.params td.key { text-align: left; font-family: ui-monospace, monospace; white-space: nowrap; }
.params td.value { text-align: left; font-family: ui-monospace, monospace; white-space: pre-wrap; word-break: break-word; max-width: 760px; }
.params td.meaning { text-align: left; white-space: normal; color: var(--muted); max-width: 480px; }
.verdict.ok { color: var(--ok); font-weight: 600; }
.verdict.near { color: #7a5a00; background: #fff3cd; }
.verdict.off { color: var(--offink); background: var(--off); font-weight: 600; }
td.worst { text-align: left; }
.verdict.neutral { color: var(--muted); }
p.verdict-line { font-size: 16px; padding: 6px 12px; border-radius: 3px; margin: 8px 0 4px; }
p.verdict-line .known { font-weight: normal; color: var(--ink); }
details.readings { margin: 6px 0 10px; }
details.readings summary { cursor: pointer; color: var(--muted); }
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
header.slim { padding: 12px 28px 10px; }
header.slim h1 { font-size: 22px; margin: 4px 0; }
header.slim p { margin: 2px 0; }
header p.pages a { color: #cfe0ff; }
table.compact th { white-space: normal; vertical-align: bottom; }
table.compact td { white-space: nowrap; }
table.compact td.title { max-width: 280px; overflow: hidden; text-overflow: ellipsis; white-space: nowrap; }
table.compact td.verdict { white-space: nowrap; }
table.compact td.status { white-space: normal; max-width: 120px; }
table.compact td.worst { max-width: 250px; overflow: hidden; text-overflow: ellipsis; }
table.compact tr.family-head th { text-align: left; background: #e6edf7; font-size: 14.5px; padding-top: 8px; }
details.legend summary { cursor: pointer; }
table.family-table td.title { max-width: 280px; overflow: hidden; text-overflow: ellipsis; white-space: nowrap; }
table.family-table td.verdict { min-width: 280px; max-width: 440px; }
details.shared summary { cursor: pointer; font-weight: 600; margin: 12px 0 4px; }
footer { color: var(--muted); font-size: 13px; margin-top: 40px; border-top: 1px solid var(--rule); padding-top: 10px; }
"#;

/// The fold around an entry's section: a `<details>` closed by default, whose one-line
/// `<summary>` names the table, so that the page opens as a list of the tables (a full report
/// is otherwise hundreds of screens tall and its figures, though lazy, are laid out at once).
/// The section inside keeps its `id`: a link to it (the contents, the summary, the search of
/// the browser) opens the fold.
fn fold_open(h: &mut String, entry: &Entry) {
    let _ = match entry {
        Entry::Done(s) => writeln!(
            h,
            "<details class=\"entry\"><summary>{} ({}) — {}</summary>",
            escape(&entry_name(&s.run.table)),
            escape(&s.run.section),
            escape(&s.run.title)
        ),
        Entry::Failed(f) => writeln!(
            h,
            "<details class=\"entry\"><summary>{} — {} <b>({})</b></summary>",
            escape(&entry_name(&f.table)),
            escape(f.title.as_deref().unwrap_or("")),
            f.kind.name()
        ),
    };
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
        "<header><div class=\"inner\">\n<h1>{}</h1>\n<p>{}</p>\n<dl>\
         <div><dt>tier</dt><dd>{}</dd></div>\
         <div><dt>tables</dt><dd>{}</dd></div>\
         <div><dt>total wall time</dt><dd>{}</dd></div>\
         <div><dt>threads</dt><dd>{}</dd></div>\
         <div><dt>generated by</dt><dd>{}</dd></div>\
         <div><dt>commit</dt><dd>{}</dd></div>\
         <div><dt>date</dt><dd>{}</dd></div>\
         <div><dt>machine</dt><dd>{}</dd></div>\
         <div><dt>command</dt><dd><code>{}</code></dd></div></dl>\n</div></header>\n",
        if any_thesis_entry(entries) {
            "tribo — Chapter IV recomputed"
        } else {
            "tribo — scenes of your own"
        },
        intro(entries),
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

/// Whether some entry of the page is a thesis table or figure run as printed (not an own or
/// edited scene).
fn any_thesis_entry(entries: &[Entry]) -> bool {
    entries.iter().any(|e| match e {
        Entry::Done(s) => s.thesis.comparison.is_printed(),
        Entry::Failed(f) => verdict::thesis_table_number(&f.table).is_some(),
    })
}

/// The header's paragraph: what tribo does, and what this page compares — the printed tables
/// only where a thesis entry is on the page.
fn intro(entries: &[Entry]) -> &'static str {
    let compared = entries
        .iter()
        .any(|e| matches!(e, Entry::Done(s) if s.thesis.comparison.is_printed() && !s.is_figure()));
    if compared {
        "tribo re-runs the adaptive finite element computations of Chapter IV of F. Gimbel, \
         <i>Modelling and Numerical Simulation of Contact and Lubrication</i> (Siegen, 2012) — \
         linear elasticity, z- and Signorini contact, model-adaptive contact, and Reynolds / \
         SubStokes thin-film flow with and without cavitation — and shows each table beside the \
         printed one, with convergence, mesh and solution figures."
    } else {
        "tribo runs adaptive finite element computations after Chapter IV of F. Gimbel, \
         <i>Modelling and Numerical Simulation of Contact and Lubrication</i> (Siegen, 2012) — \
         linear elasticity, z- and Signorini contact, model-adaptive contact, and Reynolds / \
         SubStokes thin-film flow with and without cavitation. No entry of this page is compared \
         with a printed table: each shows tribo's rows with convergence, mesh and solution \
         figures."
    }
}

/// The front page's contents: the summary, each page of tables with its model box, the
/// performance section and the errata page.
fn contents(h: &mut String, entries: &[Entry], groups: &[pages::Group]) {
    h.push_str(
        "<nav>\n<h2>Contents</h2>\n<ol>\n<li><a href=\"#summary\">Summary</a>, by family</li>\n",
    );
    for g in groups {
        let n = g.members.len();
        let what = if n == 1 { "entry" } else { "entries" };
        let _ = match g.family {
            Some(f) => writeln!(
                h,
                "<li><a href=\"{}\">{}</a> — {n} {what} ({}); \
                 <a href=\"{}#{}\">model and conventions</a></li>",
                escape(&g.file),
                escape(&f.name),
                escape(&f.sections),
                escape(&g.file),
                escape(&f.id),
            ),
            None => writeln!(
                h,
                "<li><a href=\"{}\">{}</a> — {n} {what}</li>",
                escape(&g.file),
                escape(g.name()),
            ),
        };
    }
    h.push_str("<li><a href=\"#performance\">Performance</a></li>\n");
    let errata = errata_on_page(entries).len();
    if errata > 0 {
        let _ = writeln!(
            h,
            "<li><a href=\"errata.html\">Thesis errata</a> — {errata} affecting the tables of \
             this run</li>"
        );
    }
    h.push_str("</ol>\n</nav>\n");
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

/// What a solver study computed, for its section's header: variants, iterations and seconds
/// (its rows are iterations, not cycles).
fn uzawa_meta(rows: &[crate::results::UzawaRow]) -> String {
    // The last iteration of each variant (its rows start at iteration 0, the initial residual).
    let mut last: Vec<(&str, usize)> = Vec::new();
    for r in rows {
        match last.iter_mut().find(|(v, _)| *v == r.variant) {
            Some(entry) => entry.1 = entry.1.max(r.iteration),
            None => last.push((&r.variant, r.iteration)),
        }
    }
    format!(
        "{} variants, {} iterations computed in {}, no printed table",
        last.len(),
        last.iter().map(|(_, n)| n).sum::<usize>(),
        fmt_seconds(uzawa_seconds(rows))
    )
}

/// The seconds of a solver study: the sum over its variants of each one's last (cumulative)
/// seconds.
pub(crate) fn uzawa_seconds(rows: &[crate::results::UzawaRow]) -> f64 {
    let mut last: Vec<(&str, f64)> = Vec::new();
    for r in rows {
        match last.iter_mut().find(|(v, _)| *v == r.variant) {
            Some(entry) => entry.1 = r.seconds,
            None => last.push((&r.variant, r.seconds)),
        }
    }
    last.iter().fold(0.0, |sum, (_, s)| sum + s)
}

/// A solver study (Fig. III.6): per Uzawa variant the iterations run, the first iteration with a
/// relative residual ≤ 1e-6, the relative residual at iteration 50 and at the last, the pressure
/// error against the direct solve, the inner CG iterations and the seconds.
fn uzawa_table(h: &mut String, rows: &[crate::results::UzawaRow]) {
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

/// One table's section: comparison table, notes, figures, probes.
fn table_section(h: &mut String, s: &Section, figs: &SectionFigures) {
    let run = s.run;
    let thesis = s.thesis;
    let computed = if !run.uzawa.is_empty() {
        uzawa_meta(&run.uzawa)
    } else if s.is_figure() {
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
    comparison_link(h, s);
    verdict_and_readings(h, s, &section_verdict(s));
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
    quantities::engineering(h, run);
    signorini::signorini_comparison(h, run);
    accuracy::true_error(h, run);
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

    figures_block(h, figs);

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

/// Where the run is one of runs compared in a section of their own (a sweep's, or a scene of
/// one's own with its related runs): which run it is, and the link to the comparison.
fn comparison_link(h: &mut String, s: &Section) {
    let run = s.run;
    if let Some(sweep) = &run.sweep {
        let _ = writeln!(
            h,
            "<p class=\"meta\">Run {} of {} of the sweep {} ({}); the runs are compared in \
             <a href=\"#{}\">Sweep {}</a>.</p>",
            sweep.index + 1,
            sweep.runs.len(),
            escape(&sweep.sweep),
            escape(&sweep.label()),
            escape(&super::compare::sweep_anchor(&sweep.sweep)),
            escape(&sweep.sweep),
        );
    } else if !run.related.is_empty() && matches!(s.thesis.comparison, Comparison::OwnScene) {
        let _ = writeln!(
            h,
            "<p class=\"meta\">Compared with its related runs ({}) in <a href=\"#{}\">{} beside \
             its related runs</a>.</p>",
            escape(&run.related.join(", ")),
            escape(&super::compare::runs_anchor(&run.table)),
            escape(&run.table),
        );
    }
}

/// The figures of a section (or why they could not be drawn), under a heading "Figures".
fn figures_block(h: &mut String, figs: &SectionFigures) {
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
                let links = f.links.iter();
                link_list(
                    h,
                    links.map(|(file, label)| (format!("figures/{file}"), label)),
                    " · ",
                );
                h.push_str("</p>");
            }
            h.push_str("</figure>\n");
        }
        h.push_str("</div>\n");
    }
}

/// The links `(href, text)`, separated by `separator`.
fn link_list<'a>(
    h: &mut String,
    links: impl Iterator<Item = (String, &'a String)>,
    separator: &str,
) {
    for (i, (href, text)) in links.enumerate() {
        let _ = write!(
            h,
            "{}<a href=\"{}\">{}</a>",
            if i == 0 { "" } else { separator },
            escape(&href),
            escape(text)
        );
    }
}

/// The problem solved, stated from the experiment file: its `[scene]` and `[study]` keys
/// (domain, mesh, gap or obstacles, velocities, boundary values, loads, material, marking
/// fractions, estimator reading), grouped by the file's tables, each with what it means
/// ([`super::keys`]); every entry of a list, a list of tables one entry per line. Open by
/// default; nothing for a run without parameters.
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
                "<tr><td class=\"group\" colspan=\"3\">[{}]</td></tr>",
                escape(group)
            );
        }
        let _ = writeln!(
            h,
            "<tr><td class=\"key\">{}</td><td class=\"value\">{}</td><td class=\"meaning\">{}</td></tr>",
            escape(&p.key),
            escape(&p.value).replace('\n', "<br>"),
            super::keys::meaning(&p.group, &p.key).map_or(String::new(), escape)
        );
    }
    h.push_str("</tbody></table></details>\n");
}

/// File name of the performance figure ([`super::performance::solve_cost`]).
pub(crate) const PERFORMANCE_FIGURE: &str = "performance-solve.svg";

/// The performance section: where each table's time goes (seconds per phase over all its
/// cycles), the solver and its CG iterations, the cost of a solve per unknown, and the measured
/// reference of a deal.II program.
fn performance_section(
    h: &mut String,
    entries: &[Entry],
    alongside: &std::collections::BTreeMap<String, usize>,
) {
    h.push_str(
        "<section id=\"performance\">\n<h2>Performance</h2>\n<p>Seconds per phase summed over \
         every cycle of a table (the unprinted ones included), from the table's own clock. Tables \
         run side by side (<code>--jobs</code>, one per core by default) share the cores, so \
         their phases take longer than alone: the column <i>alongside</i> gives the most other \
         tables that ran at the same time as a table, and the seconds of a table that did not \
         run alone are marked †; run with <code>--jobs 1</code> to time one table at a time. \
         The Reynolds systems are solved by multigrid-preconditioned CG unless the run chose \
         <code>--solver direct</code>, the elasticity systems by the direct solver unless it \
         chose <code>--solver multigrid</code>, the contact systems by the primal–dual \
         active-set method with the direct solver unless it chose <code>--solver \
         multigrid</code> (truncated nonsmooth Newton multigrid; the model-adaptive contact \
         tables always direct); the CG iterations are the most of any solve of a cycle. CG stops at a relative \
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
         <th>solve s</th><th>estimate s</th><th>refine s</th><th>total s</th><th>alongside</th>\
         <th title=\"the uniform run beside a grid-adaptive table (its section's True error)\">\
         uniform s</th><th title=\"the reference solve of the table's true error (its \
         section's True error)\">reference s</th></tr></thead>\n<tbody>\n",
    );
    let (mut tables_total, mut uniform_total, mut reference_total) = (0.0, 0.0, 0.0);
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
        let others = alongside.get(&s.run.table).copied();
        let mark = if others.is_some_and(|n| n > 0) {
            "†"
        } else {
            ""
        };
        let seconds = phases.named().map(|(_, v)| v);
        for (i, v) in seconds.iter().chain([&phases.total()]).enumerate() {
            let class = if i == 0 { " class=\"first\"" } else { "" };
            let _ = write!(h, "<td{class}>{v:.2}{mark}</td>");
        }
        let uniform: f64 = s.run.uniform.iter().map(|u| u.seconds).sum();
        let reference = match s.run.accuracy {
            Some(ErrorMeasure::Reference { seconds, .. }) => Some(seconds),
            _ => None,
        };
        tables_total += phases.total();
        uniform_total += uniform;
        reference_total += reference.unwrap_or(0.0);
        let _ = writeln!(
            h,
            "<td class=\"alongside\">{}</td><td>{}</td><td>{}</td></tr>",
            others.map_or("not recorded".into(), |n| n.to_string()),
            if s.run.uniform.is_empty() {
                "–".to_string()
            } else {
                format!("{uniform:.2}")
            },
            reference.map_or("–".to_string(), |r| format!("{r:.2}"))
        );
    }
    h.push_str("</tbody></table>\n");
    if uniform_total + reference_total > 0.0 {
        let _ = writeln!(
            h,
            "<p>What the true errors cost (each table's “True error”): the uniform runs beside \
             the grid-adaptive tables (what adaptivity saves) took {uniform_total:.1} s of \
             phases in all and the reference solves {reference_total:.1} s, {:.0} % and {:.0} % \
             of the tables' own {tables_total:.1} s.</p>",
            100.0 * uniform_total / tables_total,
            100.0 * reference_total / tables_total
        );
    }
    deal_ii_reference(h, entries, alongside);
    h.push_str("</section>\n");
}

/// The measured deal.II reference beside Table IV.36, the same squeeze problem, when IV.36 is on
/// the page: its total compared with the reference only if IV.36 ran alone (its seconds are a
/// one-table-at-a-time measurement); otherwise the page says that no such measurement of tribo
/// is on it.
fn deal_ii_reference(
    h: &mut String,
    entries: &[Entry],
    alongside: &std::collections::BTreeMap<String, usize>,
) {
    const TABLE: &str = "IV.36";
    if !entries
        .iter()
        .any(|e| matches!(e, Entry::Done(s) if s.run.table == TABLE))
    {
        return;
    }
    let tribo = match alongside.get(TABLE).copied() {
        Some(0) => "Table IV.36 is that run here, and it ran alone, so its total above is a \
                    one-table-at-a-time measurement on this run's machine"
            .to_string(),
        Some(n) => format!(
            "Table IV.36 is that run here, but it ran beside {n} other table{} sharing the \
             cores, so its seconds above (marked †) are not a one-table-at-a-time measurement, \
             and no such measurement of tribo is on this page: <code>report --only IV.36 \
             --jobs 1</code> makes one",
            if n == 1 { "" } else { "s" }
        ),
        None => "Table IV.36 is that run here, but this page does not record whether it ran \
                 alone (a page merged from shards), so no one-table-at-a-time measurement of \
                 tribo is on it: <code>report --only IV.36 --jobs 1</code> makes one"
            .to_string(),
    };
    let _ = writeln!(
        h,
        "<p><b>A measured reference.</b> A deal.II 9.4 program solving the same squeeze problem \
         (IV.7) on the same adaptive meshes, 9 cycles up to 706 893 unknowns, with CG \
         preconditioned by Trilinos ML algebraic multigrid — the solver a deal.II user would \
         choose for this problem — took 11.4 s; with UMFPACK, 18.0 s. Measured for this project \
         on a quiet 2-core machine of the kind CI uses, in interleaved pairs beside tribo at \
         commit eea6b2e, whose phases took 2.6–3.4 s there (4.4× faster than deal.II with \
         algebraic multigrid, pairs 3.7–5.0×; 1.7–1.9 µs per unknown for all phases against \
         7.4–8.0). {tribo}. It is a measurement of one program on one machine, not a claim \
         about deal.II in general.</p>"
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
    let variants = crate::results::cost_variants(costs);
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
    let (lower_error, fewer_faces, n) = crate::results::claim_of_section_iv_2_3(costs);
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
