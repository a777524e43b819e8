//! The HTML report: every table tribo computed beside the printed thesis table, with figures.
//!
//! [`write_report`] writes `index.html` and one SVG per figure into `figures/`. The page is
//! self-contained (inline CSS, no scripts, no external resources) so it can be opened from disk
//! or archived with the golden snapshots. Every table has an [`Entry`] on the page, in table
//! order, also one that did not load or whose run failed ([`Failure`]); [`prepare_output`] and
//! [`remove_outputs`] keep the output folder honest: writable before anything is solved, and no
//! stale files of a table that failed today.
//!
//! The module is split by job: this file decides *what* is compared; `figures` decides which
//! figures a section gets, one kind per module (`convergence`, `meshes`, `deformed`, `field`,
//! `model_plots` for the model-adaptive tables, `forming` for a load-step run, Fig. IV.54, `film`
//! for the film comparisons and Fig. III.6, `performance` for the page's solve cost), drawn with
//! the shared helpers of `plots`; `html` lays out the page; `errata`, `families` and `keys` (what the
//! experiment file's keys mean) read their texts from `text/*.toml`.

mod compare;
mod convergence;
pub mod data;
mod deformed;
pub mod errata;
pub mod families;
mod field;
mod figures;
mod film;
mod forming;
mod html;
pub mod keys;
mod legend;
mod meshes;
mod model_plots;
mod overlap;
mod performance;
#[cfg(test)]
mod plot_tests;
mod plots;
pub mod provenance;
mod raster;
pub mod record;
pub mod verdict;
pub mod vtk;

use std::any::Any;
use std::fs;
use std::io;
use std::panic::{self, AssertUnwindSafe};
use std::path::{Path, PathBuf};

use crate::results::columns::PREVIOUS_ESTIMATE;
use crate::results::{Row, RunResult};
use crate::thesis::ThesisTable;

pub(crate) use figures::Figure;
pub use overlap::{Overlap, Running};

/// One table of the report, in table order: a table that ran, or one that did not.
pub enum Entry<'a> {
    /// The table ran: what it computed, beside the printed table.
    Done(Section<'a>),
    /// The file did not load, or the run failed or panicked: shown with its message, no data.
    Failed(&'a Failure),
}

impl Entry<'_> {
    /// The entry's table id (`IV.36`, `fig-IV.54`, an own scene's id, a sweep's run), whether
    /// it ran or not.
    pub fn table(&self) -> &str {
        match self {
            Entry::Done(s) => &s.run.table,
            Entry::Failed(f) => &f.table,
        }
    }

    /// What the entry computed, if it ran.
    pub fn run(&self) -> Option<&RunResult> {
        match self {
            Entry::Done(s) => Some(s.run),
            Entry::Failed(_) => None,
        }
    }
}

/// One table of the report: what tribo computed, and the printed thesis table beside it.
pub struct Section<'a> {
    pub run: &'a RunResult,
    /// The printed table; empty (no rows) for a figure experiment (`fig-IV.<n>`), whose result
    /// the thesis shows only as a figure.
    pub thesis: &'a ThesisTable,
    /// Runs of alternative readings of the same scene (computed by the caller),
    /// shown as differences against `run`.
    pub alternatives: &'a [Alternative],
}

impl Section<'_> {
    /// Whether the thesis prints no table for this result (a figure experiment such as
    /// `fig-IV.54`): the section has nothing to compare with, so it shows tribo's rows alone.
    pub fn is_figure(&self) -> bool {
        self.thesis.is_empty()
    }
}

/// A run of an alternative reading, with what it changes; or why it has no run.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Alternative {
    pub label: String,
    pub outcome: Result<RunResult, Failure>,
}

/// A table (or an alternative reading of one) that has no result, and why.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Failure {
    /// Table id; the file stem when the file did not load.
    pub table: String,
    /// The table's title, when its file loaded.
    pub title: Option<String>,
    /// The thesis section, when the file loaded.
    pub section: Option<String>,
    pub kind: FailureKind,
    /// The cycle the run stopped in, when known.
    pub cycle: Option<usize>,
    /// What went wrong: the loader's or the solver's message, or the panic's.
    pub message: String,
}

/// How a table failed, as the summary's status column shows it (a table that ran is `ok`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum FailureKind {
    /// The run returned an error (no convergence, a singular system, a non-finite value…).
    Error,
    /// The run panicked: a bug in tribo, caught so that the other tables are still reported.
    Panic,
    /// The experiment file did not load.
    NotLoaded,
}

impl FailureKind {
    /// The word shown in the summary's status column.
    pub fn name(self) -> &'static str {
        match self {
            FailureKind::Error => "error",
            FailureKind::Panic => "panic",
            FailureKind::NotLoaded => "not loaded",
        }
    }
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
    /// Commit, date, machine and command line of the run.
    pub provenance: provenance::Provenance,
    /// For each table, the most other tables that ran at the same time ([`Overlap`]); a table
    /// not in it has no record (a page merged from shards), and its seconds are shown unmarked
    /// but not taken as a one-table-at-a-time measurement.
    pub alongside: std::collections::BTreeMap<String, usize>,
}

/// Printed thesis rows beyond this many are left out of a section's table and figures (the page
/// says how many): the shipped tables have at most a few dozen rows, and a file with millions
/// would otherwise make a page no browser opens.
pub const MAX_SHOWN_THESIS_ROWS: usize = 1000;

/// What [`write_report`] wrote, and which sections' figures could not be drawn.
pub struct Written {
    /// Every file written: figures first, then the pages, `index.html` last.
    pub files: Vec<PathBuf>,
    /// One message per section whose figures failed (an I/O error or a panic while drawing);
    /// the page shows it in that section instead of the figures.
    pub figure_failures: Vec<String>,
}

/// Write the pages (`out_dir/index.html`, the front page, and one page per family of tables)
/// and `out_dir/figures/<table>-<kind>.svg`.
///
/// A section gets only the figures it has data for: no mesh picture, no mesh figure. Figures of
/// degenerate data (no rows, non-positive estimates on a log axis) are still written, showing
/// whatever points are valid, so a broken run is visible in the report instead of aborting it.
/// The figures of each section are drawn in isolation: an error or a panic while drawing one
/// section is reported in that section and in [`Written::figure_failures`], and the page is
/// still written. A failed entry gets a section with its status and message and no figures.
pub fn write_report(out_dir: &Path, entries: &[Entry], meta: &ReportMeta) -> io::Result<Written> {
    let fig_dir = out_dir.join("figures");
    fs::create_dir_all(&fig_dir)?;
    let mut files = Vec::new();
    let mut figure_failures = Vec::new();
    let mut rendered = Vec::with_capacity(entries.len());
    // Every run of the page, for the figures that set a run beside its related tables.
    let runs: Vec<&RunResult> = entries.iter().filter_map(Entry::run).collect();
    // The figures of one section, or of one comparison, drawn in isolation.
    let mut drawn = |name: &str, draw: &dyn Fn() -> io::Result<Vec<Figure>>| {
        let figures = match panic::catch_unwind(AssertUnwindSafe(draw)) {
            Ok(Ok(figures)) => html::SectionFigures {
                figures,
                error: None,
            },
            Ok(Err(e)) => html::SectionFigures {
                figures: Vec::new(),
                error: Some(format!(
                    "cannot write the figures into {}: {e}",
                    fig_dir.display()
                )),
            },
            Err(payload) => html::SectionFigures {
                figures: Vec::new(),
                error: Some(format!(
                    "drawing the figures panicked: {}",
                    panic_message(payload.as_ref())
                )),
            },
        };
        if let Some(error) = &figures.error {
            figure_failures.push(format!("{name}: {error}"));
        }
        for f in &figures.figures {
            files.push(fig_dir.join(&f.file));
            files.extend(f.links.iter().map(|(file, _)| fig_dir.join(file)));
        }
        figures
    };
    for entry in entries {
        rendered.push(match entry {
            Entry::Done(section) => drawn(&section.run.table, &|| {
                figures::write_figures(&fig_dir, section, &runs)
            }),
            Entry::Failed(_) => html::SectionFigures::default(),
        });
    }
    let compared: Vec<(compare::ComparedRuns, html::SectionFigures)> =
        compare::comparisons(entries)
            .into_iter()
            .map(|c| {
                let figures = drawn(&c.title, &|| compare::write_figures(&fig_dir, &c));
                (c, figures)
            })
            .collect();
    let performance = fig_dir.join(html::PERFORMANCE_FIGURE);
    performance::solve_cost(&performance, &runs)?;
    files.push(performance);
    let pages = html::pages(entries, &rendered, &compared, meta);
    // A page an earlier run wrote that this one does not (a family no longer in the run) goes:
    // the folder shows this run only.
    let written: Vec<&str> = pages.iter().map(|p| p.file.as_str()).collect();
    remove_pages_but(out_dir, &written)?;
    // The front page last: until it is written, the folder's `index.html` says the report is
    // incomplete.
    for page in pages.iter().rev() {
        let path = out_dir.join(&page.file);
        crate::fsio::write(&path, &page.html)?;
        files.push(path);
    }
    Ok(Written {
        files,
        figure_failures,
    })
}

/// Remove the pages of an earlier run other than the front page, which a new run replaces
/// with the page that says the report is incomplete: a family page left from the earlier run
/// would link figures and data the new run may remove or rewrite.
pub fn remove_pages(out_dir: &Path) -> io::Result<()> {
    remove_pages_but(out_dir, &[html::FRONT_PAGE])
}

/// Remove every page a report may write from `out_dir` but those named in `keep`.
fn remove_pages_but(out_dir: &Path, keep: &[&str]) -> io::Result<()> {
    for file in html::page_files() {
        let path = out_dir.join(&file);
        if !keep.contains(&file.as_str()) && path.is_file() {
            fs::remove_file(path)?;
        }
    }
    Ok(())
}

/// Every page of the report in `out_dir`, concatenated: the front page (`index.html`) first,
/// then the others a run writes (the family pages, the errata), those present. For reading a
/// report as one text (the tests, a search); a browser follows the links instead.
pub fn read_pages(out_dir: &Path) -> io::Result<String> {
    let mut text = fs::read_to_string(out_dir.join(html::FRONT_PAGE))?;
    for file in html::page_files() {
        let path = out_dir.join(&file);
        if file != html::FRONT_PAGE && path.is_file() {
            text.push_str(&fs::read_to_string(path)?);
        }
    }
    Ok(text)
}

/// The message of a caught panic: its `&str` or `String` payload, as `panic!` makes them.
pub fn panic_message(payload: &(dyn Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic without a message".into())
}

/// Create the output folder with its `data/` and `figures/` and check that files can be written
/// into each (a probe file is written and removed), so that a folder that cannot take the
/// report is found before any table is solved rather than after.
pub fn prepare_output(out_dir: &Path) -> io::Result<()> {
    for dir in [
        out_dir.to_path_buf(),
        out_dir.join("data"),
        out_dir.join("figures"),
    ] {
        if dir.exists() && !dir.is_dir() {
            return Err(io::Error::new(
                io::ErrorKind::AlreadyExists,
                format!("{} exists and is not a directory", dir.display()),
            ));
        }
        fs::create_dir_all(&dir).map_err(|e| with_path(e, &dir))?;
        let probe = dir.join(format!(".tribo-write-probe-{}", std::process::id()));
        fs::write(&probe, b"probe").map_err(|e| with_path(e, &dir))?;
        fs::remove_file(&probe).map_err(|e| with_path(e, &probe))?;
    }
    Ok(())
}

/// An I/O error with the path it is about in its message.
fn with_path(e: io::Error, path: &Path) -> io::Error {
    io::Error::new(e.kind(), format!("{}: {e}", path.display()))
}

/// Remove the output a table left in `out_dir` from an earlier run: `data/<table>.csv`,
/// `data/<table>.<word>….csv` (its probes and alternative readings), the same names ending in
/// `.parquet`, `.vtu` and `.pvd`, and
/// `figures/<table>-<word>….svg`; return the files removed.
///
/// Called before a table runs, so that a table that fails leaves no data or figures that look
/// like today's. The part after the table id must start with a letter: table ids end in a
/// number, so `IV.1` never matches the files of `IV.10` (`IV.10.csv`, `IV.10-mesh.svg`), and a
/// stray stem such as `IV` never matches `IV.1.csv`.
pub fn remove_outputs(out_dir: &Path, table: &str) -> io::Result<Vec<PathBuf>> {
    let mut removed = Vec::new();
    let data_stem = data::csv_stem(table);
    let figure_stem = file_stem(table);
    for (dir, stem, separator, extension) in [
        (out_dir.join("data"), data_stem.as_str(), '.', ".csv"),
        (out_dir.join("data"), data_stem.as_str(), '.', ".parquet"),
        (out_dir.join("data"), data_stem.as_str(), '.', ".vtu"),
        (out_dir.join("data"), data_stem.as_str(), '.', ".pvd"),
        (out_dir.join("figures"), figure_stem.as_str(), '-', ".svg"),
    ] {
        let entries = match fs::read_dir(&dir) {
            Ok(entries) => entries,
            Err(e) if e.kind() == io::ErrorKind::NotFound => continue,
            Err(e) => return Err(with_path(e, &dir)),
        };
        for entry in entries {
            let entry = entry.map_err(|e| with_path(e, &dir))?;
            let name = entry.file_name();
            let Some(name) = name.to_str() else { continue };
            if is_output_of(name, stem, separator, extension) {
                let path = entry.path();
                fs::remove_file(&path).map_err(|e| with_path(e, &path))?;
                removed.push(path);
            }
        }
    }
    Ok(removed)
}

/// Whether the file `name` is `<stem><extension>` or `<stem><separator><word>…<extension>` with
/// a word that starts with an ASCII letter (see [`remove_outputs`]).
fn is_output_of(name: &str, stem: &str, separator: char, extension: &str) -> bool {
    let Some(rest) = name
        .strip_prefix(stem)
        .and_then(|r| r.strip_suffix(extension))
    else {
        return false;
    };
    match rest.strip_prefix(separator) {
        Some(word) => word.starts_with(|c: char| c.is_ascii_alphabetic()),
        None => rest.is_empty() && separator == '.',
    }
}

/// The thesis figure a figure experiment's id names (`fig-IV.54` → `Fig. IV.54`).
pub(crate) fn thesis_figure(table: &str) -> Option<String> {
    table.strip_prefix("fig-").map(|f| format!("Fig. {f}"))
}

/// Which estimate a run's `estimate` column holds: the symbol with the norm it bounds, short
/// for an axis (`η, energy norm (Thm III.12)`) and long for a caption.
pub(crate) struct EstimateName {
    pub axis: String,
    pub caption: String,
}

/// The [`EstimateName`] of a run, by its thesis section (the run matrix of Chapter IV): Theorem
/// III.12 for elasticity and III.15 for contact, both bounding the error in the energy norm;
/// Theorem III.16 (Reynolds norm) for the Reynolds tables, III.17 with cavitation; Theorem
/// III.23 for SubStokes and III.24 with cavitation, bounding ‖χ − χ_h‖_H¹ + ‖ψ − ψ_h‖_L²; for
/// the model-adaptive film of Fig. IV.116 the root sum of squares of III.23 on the SubStokes
/// cells, III.16 on the Reynolds cells and the model error. A run of another section (a scene
/// of one's own) gets the generic name.
pub(crate) fn estimate_name(run: &RunResult) -> EstimateName {
    let s = run.section.as_str();
    let under = |prefix: &str| s == prefix || s.starts_with(&format!("{prefix}."));
    let (axis, caption) = if under("IV.1") {
        (
            "η, energy norm (Thm III.12)",
            "the estimate η of Theorem III.12 of the error in the energy norm ‖s − s_h‖_a",
        )
    } else if under("IV.2.1") || under("IV.2.2") || under("IV.2.3") {
        (
            "η, energy norm (Thm III.15)",
            "the estimate η of Theorem III.15 of the contact error in the energy norm",
        )
    } else if under("IV.2.4") {
        (
            "η, energy norm (Thm III.15)",
            "the estimate η of Theorem III.15 of the contact error in the energy norm, summed \
             over the z-, Signorini and interior cells, on the model chosen by (III.93)",
        )
    } else if under("IV.3.1") {
        (
            "η, Reynolds norm (Thm III.16)",
            "the estimate η of Theorem III.16 of the error ‖ψ − ψ_h‖_R in the Reynolds norm",
        )
    } else if under("IV.3.5") {
        (
            "η, Reynolds norm (Thm III.17)",
            "the estimate η of Theorem III.17 (cavitation) of the error in the Reynolds norm",
        )
    } else if under("IV.3.2") {
        (
            "η, H¹×L² (Thm III.23)",
            "the estimate η of Theorem III.23 of ‖χ − χ_h‖_H¹ + ‖ψ − ψ_h‖_L²",
        )
    } else if under("IV.3.6") {
        (
            "η, H¹×L² (Thm III.24)",
            "the estimate η of Theorem III.24 (cavitation) of ‖χ − χ_h‖_H¹ + ‖ψ − ψ_h‖_L²",
        )
    } else if under("IV.3.4") {
        (
            "η, III.23 + III.16 + model error",
            "the estimate η = (η_S² + η_R² + η_m²)^½ — Theorem III.23 on the SubStokes \
             cells, Theorem III.16 on the Reynolds cells and the model error of Theorem III.6",
        )
    } else {
        (
            "η (a-posteriori estimate)",
            "the a-posteriori error estimate η of the scene's solver",
        )
    };
    EstimateName {
        axis: axis.into(),
        caption: caption.into(),
    }
}

/// A file-name-safe form of a table id or field name (`IV.1` stays `IV.1`, the run of a sweep
/// `step-bearing~-10` stays so).
///
/// Table ids come from experiment files, so anything outside `[A-Za-z0-9._~-]` is replaced
/// rather than trusted inside a path.
pub(crate) fn file_stem(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '.' | '-' | '_' | '~') {
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
    /// Geometric mean of the per-cycle estimate ratios (the mean reduction per cycle); none for
    /// a load-step run, whose rows are load steps on a moving body, not refinements.
    pub geo_mean_ratio: Option<f64>,
    /// Largest |tribo/thesis − 1| over the cycles both have, with its signed value.
    pub max_dofs_diff: Option<f64>,
    pub max_estimate_diff: Option<f64>,
    pub total_seconds: f64,
    /// The experimental order of convergence of tribo's rows and of the printed ones
    /// ([`convergence_order`]).
    pub order: Option<f64>,
    pub thesis_order: Option<f64>,
    /// The smallest and the largest effectivity η/error over the rows that have one.
    pub effectivity: Option<(f64, f64)>,
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
        let geo_mean_ratio = (!ratios.is_empty() && !run.is_load_steps())
            .then(|| (ratios.iter().map(|r| r.ln()).sum::<f64>() / ratios.len() as f64).exp());
        Summary {
            rows: run.rows.len() + run.uzawa.len(),
            last_dofs: run.rows.last().and_then(|r| r.dofs()),
            last_estimate: run.rows.last().and_then(|r| r.estimate()),
            geo_mean_ratio,
            max_dofs_diff: max_abs_diff(section, "dofs"),
            max_estimate_diff: max_abs_diff(section, "estimate"),
            total_seconds: run_seconds(run),
            order: tribo_order(run),
            thesis_order: thesis_order(section),
            effectivity: effectivity_range(run),
        }
    }
}

/// The wall seconds of a run: every phase of every row, or a solver study's iterations.
pub(crate) fn run_seconds(run: &RunResult) -> f64 {
    // A fold from +0.0: an empty `sum()` of floats is −0.0, which would print as "-0.000 s".
    run.rows.iter().fold(0.0, |acc, r| acc + r.seconds.total()) + html::uzawa_seconds(&run.uzawa)
}

/// The smallest and the largest effectivity η/error of a run's rows (`None` without one).
pub fn effectivity_range(run: &RunResult) -> Option<(f64, f64)> {
    run.rows
        .iter()
        .filter_map(|r| r.value(crate::results::columns::EFFECTIVITY))
        .fold(None, |range, e| match range {
            None => Some((e, e)),
            Some((lo, hi)) => Some((f64::min(lo, e), f64::max(hi, e))),
        })
}

/// An effectivity range as the summary prints it: `9.3–11` (3 significant digits at most), `—`
/// without one.
pub fn fmt_effectivity(range: Option<(f64, f64)>) -> String {
    match range {
        None => "—".into(),
        Some((lo, hi)) => format!("{}–{}", fmt_sig3(lo), fmt_sig3(hi)),
    }
}

/// Three significant digits, no exponent for 0.01–9999.
fn fmt_sig3(v: f64) -> String {
    if !(0.01..10_000.0).contains(&v.abs()) {
        return format!("{v:.2e}");
    }
    let digits = (2 - v.abs().log10().floor() as i32).max(0) as usize;
    format!("{v:.digits$}")
}

/// The experimental order of convergence: the least-squares slope of log(estimate) against
/// log(dofs) over `points` (dofs, estimate). An adaptive method that is optimal for Q₁ elements
/// in two dimensions has η ∝ N^{-1/2}, order −½. `None` with fewer than three usable points or
/// without two different dofs.
pub fn convergence_order(points: &[(f64, f64)]) -> Option<f64> {
    let logs: Vec<(f64, f64)> = points
        .iter()
        .filter(|(n, e)| n.is_finite() && e.is_finite() && *n > 0.0 && *e > 0.0)
        .map(|(n, e)| (n.ln(), e.ln()))
        .collect();
    if logs.len() < 3 {
        return None;
    }
    let k = logs.len() as f64;
    let (mx, my) = logs
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / k, b + y / k));
    let sxx: f64 = logs.iter().map(|(x, _)| (x - mx).powi(2)).sum();
    let sxy: f64 = logs.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    (sxx > 1e-12).then(|| sxy / sxx)
}

/// The order of tribo's rows: each row's estimate on its own mesh against its dofs. None for a
/// load-step run (the rows are load steps) and a model-adaptive one (one fixed mesh).
fn tribo_order(run: &RunResult) -> Option<f64> {
    if run.is_load_steps() || run.is_model_adaptive() {
        return None;
    }
    let points: Vec<(f64, f64)> = run
        .rows
        .iter()
        .filter_map(|r| Some((r.dofs()? as f64, r.estimate()?)))
        .collect();
    convergence_order(&points)
}

/// The order of the printed rows. Where the thesis prints each row's mesh beside the estimate
/// of the solve before it (the fluid tables), the estimate of row k belongs to the mesh of row
/// k − 1, and the two are paired so.
fn thesis_order(section: &Section) -> Option<f64> {
    if section.run.is_load_steps() || section.run.is_model_adaptive() {
        return None;
    }
    let thesis = section.thesis;
    let column = |name: &str| -> Vec<f64> {
        let Some(c) = thesis.columns.iter().position(|n| n == name) else {
            return Vec::new();
        };
        thesis
            .rows
            .iter()
            .take(MAX_SHOWN_THESIS_ROWS)
            .map(|r| r.get(c).copied().unwrap_or(f64::NAN))
            .collect()
    };
    let (dofs, estimates) = (column("dofs"), column("estimate"));
    let shift = usize::from(compares_previous_estimate(section.run));
    let points: Vec<(f64, f64)> = dofs
        .iter()
        .zip(estimates.iter().skip(shift))
        .map(|(n, e)| (*n, *e))
        .collect();
    convergence_order(&points)
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
    fn outputs_of_a_table_match_exactly() {
        let data = |name| is_output_of(name, "IV.1", '.', ".csv");
        assert!(data("IV.1.csv"));
        assert!(data("IV.1.probes.csv"));
        assert!(data("IV.1.self-consistent.probes.csv"));
        assert!(!data("IV.10.csv"));
        assert!(!data("IV.10.probes.csv"));
        assert!(!data("IV.1.csv.bak"));
        assert!(!is_output_of("IV.1.csv", "IV", '.', ".csv"));
        let figure = |name| is_output_of(name, "IV.1", '-', ".svg");
        assert!(figure("IV.1-convergence.svg"));
        assert!(figure("IV.1-field-psi-0.svg"));
        assert!(!figure("IV.10-convergence.svg"));
        assert!(!figure("IV.1.svg"));
        assert!(!figure("IV.1-.svg"));
    }

    #[test]
    fn rel_diff_skips_undefined() {
        assert_eq!(rel_diff(1.0, 0.0), None);
        assert_eq!(rel_diff(1.0, f64::INFINITY), None);
        assert!((rel_diff(1.1, 1.0).unwrap() - 0.1).abs() < 1e-12);
    }

    /// The figure numbers come from the experiment files: a pair of grids and solution, a
    /// table the thesis draws only once or not at all, and a figure experiment that is its own
    /// figure in every part.
    #[test]
    fn figure_numbers_come_from_the_experiment_files() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments");
        let only: Vec<String> = ["IV.2", "IV.7", "IV.19", "IV.30", "fig-IV.54"]
            .map(String::from)
            .to_vec();
        let experiments = crate::experiment::load_dir(&dir, Some(&only)).unwrap();
        let figures = |id: &str| {
            let e = experiments.iter().find(|e| e.table == id).unwrap();
            let f = &e.figures;
            [&f.grids, &f.solution, &f.model].map(|f| f.as_ref().map(|_| figures::cf(f)))
        };
        let cited = |f: &str| Some(format!(" (cf. thesis Fig. {f})"));
        assert_eq!(figures("IV.7"), [cited("IV.12"), cited("IV.13"), None]);
        assert_eq!(figures("IV.2"), [None, cited("IV.3"), None]);
        assert_eq!(figures("IV.19"), [None, None, None]);
        assert_eq!(figures("IV.30"), [cited("IV.46"), None, cited("IV.46")]);
        assert_eq!(
            figures("fig-IV.54"),
            [cited("IV.54"), cited("IV.54"), cited("IV.54")]
        );
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

#[cfg(test)]
mod order_tests {
    use super::convergence_order;

    /// η = C N^p is recovered exactly; a wobble around it moves the slope a little; too few or
    /// degenerate points give none.
    #[test]
    fn the_order_is_the_log_log_slope() {
        let exact: Vec<(f64, f64)> = [100.0, 200.0, 400.0, 800.0]
            .iter()
            .map(|&n: &f64| (n, 3.0 * n.powf(-0.5)))
            .collect();
        assert!((convergence_order(&exact).unwrap() + 0.5).abs() < 1e-12);
        let wobble: Vec<(f64, f64)> = exact
            .iter()
            .enumerate()
            .map(|(i, &(n, e))| (n, e * if i % 2 == 0 { 1.05 } else { 0.95 }))
            .collect();
        let p = convergence_order(&wobble).unwrap();
        assert!((p + 0.5).abs() > 1e-3 && (p + 0.5).abs() < 0.1, "{p}");
        assert_eq!(convergence_order(&exact[..2]), None);
        assert_eq!(
            convergence_order(&[(10.0, 1.0), (10.0, 2.0), (10.0, 3.0)]),
            None
        );
        assert_eq!(
            convergence_order(&[(10.0, 1.0), (20.0, f64::NAN), (40.0, 0.5)]),
            None
        );
    }
}
