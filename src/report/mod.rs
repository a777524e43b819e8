//! The HTML report: every table tribo computed beside the printed thesis table, with figures.
//!
//! [`write_report`] writes `index.html` and one SVG per figure into `figures/`. The page is
//! self-contained (inline CSS, no scripts, no external resources) so it can be opened from disk
//! or archived with the golden snapshots.
//!
//! The module is split by job: this file decides *what* is compared and which figures a section
//! gets, `plots` draws the figures, `html` lays out the page.

pub mod data;
mod html;
mod plots;

use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use crate::results::columns::PREVIOUS_ESTIMATE;
use crate::results::{Row, RunResult};
use crate::thesis::ThesisTable;

/// One table of the report: what tribo computed, and the printed thesis table beside it.
pub struct Section<'a> {
    pub run: &'a RunResult,
    pub thesis: &'a ThesisTable,
    /// Runs of alternative readings of the same scene (computed by the caller),
    /// shown as differences against `run`.
    pub alternatives: &'a [Alternative],
}

/// A run of an alternative reading, with what it changes.
pub struct Alternative {
    pub label: String,
    pub run: RunResult,
}

/// Facts about the whole report run, shown in the page header.
pub struct ReportMeta {
    /// `quick` or `full`.
    pub tier: String,
    /// Program and version that wrote the report (e.g. `tribo 0.1.0`).
    pub generated_by: String,
    /// Wall seconds of the whole run, all experiments.
    pub total_seconds: f64,
    /// Worker threads used (rayon pool size).
    pub threads: usize,
}

/// Printed thesis rows beyond this many are left out of a section's table and figures (the page
/// says how many): the shipped tables have at most a few dozen rows, and a file with millions
/// would otherwise make a page no browser opens.
pub const MAX_SHOWN_THESIS_ROWS: usize = 1000;

/// Write `out_dir/index.html` and `out_dir/figures/<table>-<kind>.svg`; return the list of files
/// written (figures first, `index.html` last).
///
/// A section gets only the figures it has data for: no mesh picture, no mesh figure. Figures of
/// degenerate data (no rows, non-positive estimates on a log axis) are still written, showing
/// whatever points are valid, so a broken run is visible in the report instead of aborting it.
pub fn write_report(
    out_dir: &Path,
    sections: &[Section],
    meta: &ReportMeta,
) -> io::Result<Vec<PathBuf>> {
    let fig_dir = out_dir.join("figures");
    fs::create_dir_all(&fig_dir)?;
    let mut written = Vec::new();
    let mut rendered = Vec::with_capacity(sections.len());
    for section in sections {
        let figures = write_figures(&fig_dir, section)?;
        written.extend(figures.iter().map(|f| fig_dir.join(&f.file)));
        rendered.push(html::SectionFigures { figures });
    }
    let index = out_dir.join("index.html");
    fs::write(&index, html::page(sections, &rendered, meta))?;
    written.push(index);
    Ok(written)
}

/// A figure written for a section, as the page refers to it.
pub(crate) struct Figure {
    /// File name inside `figures/`.
    pub file: String,
    /// Alternative text and caption.
    pub caption: String,
}

/// Draw every figure one section has data for.
fn write_figures(fig_dir: &Path, section: &Section) -> io::Result<Vec<Figure>> {
    let run = section.run;
    let stem = file_stem(&run.table);
    let mut figures = Vec::new();
    let mut push = |kind: &str, caption: String| -> PathBuf {
        let file = format!("{stem}-{kind}.svg");
        let path = fig_dir.join(&file);
        figures.push(Figure { file, caption });
        path
    };

    let path = push(
        "convergence",
        format!(
            "{}: estimate vs degrees of freedom, tribo (solid) and thesis (dashed), log–log",
            run.table
        ),
    );
    plots::convergence(&path, run, section.thesis)?;

    if !run.rows.is_empty() {
        let path = push(
            "cost",
            format!(
                "{}: cost of accuracy — estimate vs cumulative wall seconds, and seconds per phase",
                run.table
            ),
        );
        plots::cost(&path, run)?;
    }
    if !run.meshes.is_empty() {
        let cycles: Vec<String> = run.meshes.iter().map(|m| m.cycle.to_string()).collect();
        let path = push(
            "mesh",
            format!(
                "{}: active cells after cycle {}",
                run.table,
                cycles.join(", ")
            ),
        );
        plots::meshes(&path, &run.meshes, run.domain)?;
    }

    for (i, pic) in run.deformed.iter().enumerate() {
        let kind = indexed("deformed", i, run.deformed.len());
        let path = push(
            &kind,
            format!(
                "{}: deformed body after cycle {}, displacement × {}",
                run.table,
                pic.cycle,
                html::fmt_short(pic.scale)
            ),
        );
        plots::deformed(&path, &run.table, pic)?;
    }

    for (i, pic) in run.fields.iter().enumerate() {
        let kind = indexed(
            &format!("field-{}", file_stem(&pic.name)),
            i,
            run.fields.len(),
        );
        let path = push(
            &kind,
            format!(
                "{}: {} on the active cells after cycle {}",
                run.table, pic.name, pic.cycle
            ),
        );
        plots::field(&path, &run.table, pic, run.domain)?;
    }

    Ok(figures)
}

/// `kind` when a run has one picture of that kind, `kind-i` when it has several.
fn indexed(kind: &str, i: usize, n: usize) -> String {
    if n > 1 {
        format!("{kind}-{i}")
    } else {
        kind.to_string()
    }
}

/// A file-name-safe form of a table id or field name (`IV.1` stays `IV.1`).
///
/// Table ids come from experiment files, so anything outside `[A-Za-z0-9._-]` is replaced rather
/// than trusted inside a path.
pub(crate) fn file_stem(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '.' | '-' | '_') {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() || s.starts_with('.') {
        format!("_{s}")
    } else {
        s
    }
}

/// Relative difference tribo/thesis − 1, when both are finite and the thesis value is non-zero.
pub(crate) fn rel_diff(tribo: f64, thesis: f64) -> Option<f64> {
    (tribo.is_finite() && thesis.is_finite() && thesis != 0.0).then(|| tribo / thesis - 1.0)
}

/// Relative difference beyond which a cell is highlighted.
///
/// Mesh sizes are deterministic given the marking rule, so 3 % already means a different
/// refinement history; estimates and derived columns carry discretisation and calibration
/// differences, hence the wider 5 %.
pub(crate) fn tolerance(column: &str) -> f64 {
    match column {
        "dofs" | "active_cells" => 0.03,
        _ => 0.05,
    }
}

/// Per-table numbers of the summary table.
pub(crate) struct Summary {
    pub rows: usize,
    pub last_dofs: Option<usize>,
    pub last_estimate: Option<f64>,
    /// Geometric mean of the per-cycle estimate ratios (the mean reduction per cycle).
    pub geo_mean_ratio: Option<f64>,
    /// Largest |tribo/thesis − 1| over the cycles both have, with its signed value.
    pub max_dofs_diff: Option<f64>,
    pub max_estimate_diff: Option<f64>,
    pub total_seconds: f64,
}

impl Summary {
    pub fn of(section: &Section) -> Summary {
        let run = section.run;
        let ratios: Vec<f64> = run
            .rows
            .iter()
            .filter_map(|r| r.ratio())
            .filter(|r| r.is_finite() && *r > 0.0)
            .collect();
        let geo_mean_ratio = (!ratios.is_empty())
            .then(|| (ratios.iter().map(|r| r.ln()).sum::<f64>() / ratios.len() as f64).exp());
        Summary {
            rows: run.rows.len(),
            last_dofs: run.rows.last().and_then(|r| r.dofs()),
            last_estimate: run.rows.last().and_then(|r| r.estimate()),
            geo_mean_ratio,
            max_dofs_diff: max_abs_diff(section, "dofs"),
            max_estimate_diff: max_abs_diff(section, "estimate"),
            // A fold from +0.0: an empty `sum()` of floats is −0.0, which would print as "-0.000 s".
            total_seconds: run.rows.iter().fold(0.0, |acc, r| acc + r.seconds.total()),
        }
    }
}

/// Whether the run's estimates are compared with the thesis one solve late: the fluid tables
/// print the estimate of the previous solve next to the refined mesh (column
/// [`PREVIOUS_ESTIMATE`]).
pub(crate) fn compares_previous_estimate(run: &RunResult) -> bool {
    run.rows
        .iter()
        .any(|r| r.value(PREVIOUS_ESTIMATE).is_some())
}

/// The tribo value that the thesis's printed `column` of row `i` is compared with.
///
/// Where the run has [`PREVIOUS_ESTIMATE`], the printed `estimate` is compared with that column
/// and the printed `ratio` with the ratio of two consecutive values of it; every other column,
/// and every column of the other tables, with the value of the same name.
pub(crate) fn compared_value(rows: &[Row], i: usize, column: &str) -> Option<f64> {
    let row = rows.get(i)?;
    let previous = |r: &Row| r.value(PREVIOUS_ESTIMATE).filter(|v| v.is_finite());
    match (column, row.value(PREVIOUS_ESTIMATE).is_some()) {
        ("estimate", true) => previous(row),
        ("ratio", true) => {
            let before = previous(rows.get(i.checked_sub(1)?)?)?;
            let now = previous(row)?;
            (before != 0.0).then(|| now / before)
        }
        _ => row.value(column),
    }
}

/// tribo's compared estimate of row `i` ([`compared_value`]) divided by a printed value; `None`
/// where either is missing or the printed value is 0 or not finite.
pub(crate) fn estimate_ratio(rows: &[Row], i: usize, printed: Option<f64>) -> Option<f64> {
    let p = printed.filter(|p| p.is_finite() && *p != 0.0)?;
    Some(compared_value(rows, i, "estimate")? / p)
}

/// The signed relative difference of largest magnitude in `column` over the computed cycles.
fn max_abs_diff(section: &Section, column: &str) -> Option<f64> {
    let rows = &section.run.rows;
    rows.iter()
        .enumerate()
        .filter_map(|(i, r)| {
            rel_diff(
                compared_value(rows, i, column)?,
                section.thesis.value(r.cycle, column)?,
            )
        })
        .fold(None, |best: Option<f64>, d| match best {
            Some(b) if b.abs() >= d.abs() => Some(b),
            _ => Some(d),
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_stems_are_safe() {
        assert_eq!(file_stem("IV.1"), "IV.1");
        assert_eq!(file_stem("../x y"), "_.._x_y");
        assert_eq!(file_stem(""), "_");
    }

    #[test]
    fn rel_diff_skips_undefined() {
        assert_eq!(rel_diff(1.0, 0.0), None);
        assert_eq!(rel_diff(1.0, f64::INFINITY), None);
        assert!((rel_diff(1.1, 1.0).unwrap() - 0.1).abs() < 1e-12);
    }

    fn row(cycle: usize, estimate: f64, previous: Option<f64>) -> Row {
        let row = Row::new(cycle)
            .count("active_cells", 1)
            .count("dofs", 4)
            .real("estimate", Some(estimate))
            .real("ratio", None);
        match previous {
            Some(p) => row.real(PREVIOUS_ESTIMATE, Some(p)),
            None => row,
        }
    }

    #[test]
    fn fluid_estimates_are_compared_one_solve_late() {
        // Solves give 8, 4, 2; the printed rows start after the first solve.
        let rows = [row(0, 4.0, Some(8.0)), row(1, 2.0, Some(4.0))];
        assert_eq!(compared_value(&rows, 0, "estimate"), Some(8.0));
        assert_eq!(compared_value(&rows, 1, "estimate"), Some(4.0));
        assert_eq!(compared_value(&rows, 0, "ratio"), None);
        assert_eq!(compared_value(&rows, 1, "ratio"), Some(0.5));
        assert_eq!(compared_value(&rows, 1, "dofs"), Some(4.0));
        // Other tables compare the values of the same name.
        let mut plain = [row(0, 4.0, None), row(1, 2.0, None)];
        plain[1].set("ratio", crate::results::Value::Real(Some(0.5)));
        assert_eq!(compared_value(&plain, 0, "estimate"), Some(4.0));
        assert_eq!(compared_value(&plain, 1, "ratio"), Some(0.5));
        assert_eq!(compared_value(&plain, 2, "estimate"), None);
    }
}
