//! Comparisons of runs of one scene, on the page of the scenes of one's own: the runs of a sweep
//! (`[sweep]` of a file, `report --set`; [`crate::experiment::sweep`]) and a scene of one's own
//! beside its related runs (`related` of the file).
//!
//! [`comparisons`] finds them among the page's entries; each gets a section of its own (laid out
//! by `html::compare`: what was compared, a table of every run's last printed cycle) with the
//! figures drawn here ([`write_figures`]): each compared quantity against the swept value (one
//! curve per value of a second swept field), ψ along the cut of every run in one plot, and every
//! run's estimate against its dofs. Every point is one run's own number; nothing is fitted.

use std::io;
use std::path::Path;

use plotters::prelude::*;

use super::figures::Figure;
use super::film::{self, CutRun};
use super::html::fmt_short;
use super::plots::{linear_chart, linear_legend_height, loggable, plot_err, write_log_log, Curve};
use super::{estimate_name, file_stem, Entry};
use crate::experiment::sweep::SweepRun;
use crate::experiment::Comparison;
use crate::results::RunResult;
use crate::study::quantities;

/// Runs of one scene compared in a section of their own.
pub(crate) struct ComparedRuns<'a> {
    /// The section's anchor: `sweep-<sweep id>`, or `runs-<table>` for a scene and its related
    /// runs.
    pub anchor: String,
    /// The start of the file names of its figures (`figures/<stem>-quantities.svg`, …).
    pub stem: String,
    /// The section's heading.
    pub title: String,
    /// What is compared, in a sentence (plain text).
    pub what: String,
    /// Headings of the table's columns that say which run a row is.
    pub columns: Vec<String>,
    /// The runs that have a result, in the order of the page.
    pub runs: Vec<ComparedRun<'a>>,
    /// The ids of runs without a result on this page (failed, or not run).
    pub missing: Vec<String>,
    /// The engineering quantities compared ([`crate::study::quantities`]).
    pub quantities: Vec<String>,
    /// The name of the swept value on the quantity plots' axis, where the values are numbers.
    pub axis: Option<String>,
    /// The labels of the curves of the quantity plots: the values of a second swept field, or
    /// one empty label.
    pub series: Vec<String>,
    /// Whether the runs solve different models, each estimate in its own norm.
    pub own_norms: bool,
    /// The index of the page's entry before which the section stands.
    pub first: usize,
}

/// One run of a comparison.
pub(crate) struct ComparedRun<'a> {
    pub run: &'a RunResult,
    /// The run's name in the legends, `upper_wall_velocity[0] = -10`.
    pub label: String,
    /// The cells of the table's columns that say which run it is.
    pub values: Vec<String>,
    /// Where the run stands on the quantity plots' axis.
    pub x: Option<f64>,
    /// Which curve of the quantity plots it is on ([`ComparedRuns::series`]).
    pub series: usize,
    pub color: RGBColor,
    pub dashed: bool,
}

/// The anchor of the comparison of the runs of sweep `sweep`.
pub(crate) fn sweep_anchor(sweep: &str) -> String {
    format!("sweep-{}", file_stem(sweep))
}

/// The anchor of the comparison of the scene `table` with its related runs.
pub(crate) fn runs_anchor(table: &str) -> String {
    format!("runs-{}", file_stem(table))
}

/// The comparisons of the page's entries, in the order of the entries they stand before.
pub(crate) fn comparisons<'a>(entries: &'a [Entry<'a>]) -> Vec<ComparedRuns<'a>> {
    let mut out = sweeps(entries);
    out.extend(related(entries));
    out.sort_by_key(|c| c.first);
    out
}

/// One comparison per sweep with a run that has a result.
fn sweeps<'a>(entries: &'a [Entry<'a>]) -> Vec<ComparedRuns<'a>> {
    let mut groups: Vec<(usize, &SweepRun, Vec<&RunResult>)> = Vec::new();
    for (i, entry) in entries.iter().enumerate() {
        let Some((run, sweep)) = entry.run().and_then(|r| Some((r, r.sweep.as_ref()?))) else {
            continue;
        };
        match groups.iter_mut().find(|g| g.1.sweep == sweep.sweep) {
            Some(group) => group.2.push(run),
            None => groups.push((i, sweep, vec![run])),
        }
    }
    groups
        .into_iter()
        .map(|(first, sweep, runs)| {
            // A failed run of the sweep before its first result moves the section up to it.
            let first = entries
                .iter()
                .position(|e| sweep.runs.iter().any(|id| id == e.table()))
                .unwrap_or(first)
                .min(first);
            of_sweep(first, sweep, &runs)
        })
        .collect()
}

/// The comparison of the runs `runs` of `sweep`.
fn of_sweep<'a>(first: usize, sweep: &SweepRun, runs: &[&'a RunResult]) -> ComparedRuns<'a> {
    let fields = &sweep.fields;
    // The axis: the first field whose values are numbers; the other field makes the curves.
    let axis = fields.iter().position(|f| f.numbers.is_some());
    let other = axis.and_then(|a| (0..fields.len()).find(|&k| k != a));
    let colors = ramp(runs.len());
    let compared: Vec<ComparedRun> = runs
        .iter()
        .zip(colors)
        .map(|(run, color)| {
            let at = sweep.values_of(run.sweep.as_ref().map_or(0, |s| s.index));
            let value_name = |k: usize| match &fields[k].numbers {
                Some(numbers) => format!("{} = {}", fields[k].axis(), fmt_short(numbers[at[k]])),
                None => format!("{} = {}", fields[k].name(), fields[k].values[at[k]]),
            };
            ComparedRun {
                run,
                label: (0..fields.len())
                    .map(value_name)
                    .collect::<Vec<_>>()
                    .join(", "),
                values: fields
                    .iter()
                    .zip(&at)
                    .map(|(f, &v)| f.values[v].clone())
                    .collect(),
                x: axis.and_then(|a| Some(fields[a].numbers.as_ref()?[at[a]])),
                series: other.map_or(0, |o| at[o]),
                color,
                dashed: false,
            }
        })
        .collect();
    let series = match other {
        Some(o) => (0..fields[o].values.len())
            .map(|v| match &fields[o].numbers {
                Some(numbers) => format!("{} = {}", fields[o].axis(), fmt_short(numbers[v])),
                None => format!("{} = {}", fields[o].name(), fields[o].values[v]),
            })
            .collect(),
        None => vec![String::new()],
    };
    let swept: Vec<String> = fields
        .iter()
        .map(|f| format!("{} over {}", f.path, f.values.join(", ")))
        .collect();
    ComparedRuns {
        anchor: sweep_anchor(&sweep.sweep),
        stem: format!("{}-sweep", file_stem(&sweep.sweep)),
        title: format!(
            "Sweep {}: {}",
            sweep.sweep,
            fields
                .iter()
                .map(|f| f.name())
                .collect::<Vec<_>>()
                .join(" × ")
        ),
        what: format!(
            "{} runs of {} ({}): {}{}. Each run is a table of its own on this page, with its \
             data files; every value below is that run's last printed cycle.",
            sweep.runs.len(),
            sweep.sweep,
            if sweep.from_command_line {
                "report --set"
            } else {
                "its [sweep]"
            },
            swept.join("; and "),
            if fields.len() > 1 {
                ", every combination a run"
            } else {
                ""
            },
        ),
        columns: fields.iter().map(|f| f.name().to_string()).collect(),
        missing: sweep
            .runs
            .iter()
            .filter(|id| !compared.iter().any(|r| &r.run.table == *id))
            .cloned()
            .collect(),
        runs: compared,
        quantities: sweep.quantities.clone(),
        axis: axis.map(|a| fields[a].axis()),
        series,
        own_norms: false,
        first,
    }
}

/// One comparison per scene of one's own with related runs: the scene and the related runs of
/// the page (the thesis's own scenes draw the figures of the thesis instead, `film::Related`).
fn related<'a>(entries: &'a [Entry<'a>]) -> Vec<ComparedRuns<'a>> {
    let runs: Vec<&RunResult> = entries.iter().filter_map(Entry::run).collect();
    entries
        .iter()
        .enumerate()
        .filter_map(|(first, entry)| {
            let Entry::Done(s) = entry else {
                return None;
            };
            if s.run.related.is_empty() || !matches!(s.thesis.comparison, Comparison::OwnScene) {
                return None;
            }
            let present: Vec<&RunResult> = s
                .run
                .related
                .iter()
                .filter_map(|id| runs.iter().find(|r| r.table == *id).copied())
                .collect();
            Some(of_related(first, s.run, &present))
        })
        .collect()
}

/// The comparison of the scene `run` with the related runs `related` of the page.
fn of_related<'a>(first: usize, run: &'a RunResult, related: &[&'a RunResult]) -> ComparedRuns<'a> {
    let own = ComparedRun {
        run,
        label: format!("model-adaptive ({})", run.table),
        values: vec!["model-adaptive".into()],
        x: None,
        series: 0,
        color: film::MODEL_ADAPTIVE,
        dashed: false,
    };
    let others = related.iter().map(|r| {
        let label = film::related_label(r);
        ComparedRun {
            run: r,
            values: vec![label.split(" (").next().unwrap_or_default().to_string()],
            label,
            x: None,
            series: 0,
            color: film::related_color(r),
            dashed: true,
        }
    });
    let runs: Vec<ComparedRun> = std::iter::once(own).chain(others).collect();
    let quantities = quantities::COMPARED
        .iter()
        .filter(|q| runs.iter().any(|r| last_value(r.run, q).is_some()))
        .map(|q| q.to_string())
        .collect();
    ComparedRuns {
        anchor: runs_anchor(&run.table),
        stem: format!("{}-runs", file_stem(&run.table)),
        title: format!("{} beside its related runs", run.table),
        what: format!(
            "The scene of {} solved by the model-adaptive film and by its related runs ({}), \
             each a table of its own; every value below is that run's last printed cycle.",
            run.table,
            run.related.join(", ")
        ),
        columns: vec!["model".into()],
        missing: run
            .related
            .iter()
            .filter(|id| !related.iter().any(|r| r.table == **id))
            .cloned()
            .collect(),
        runs,
        quantities,
        axis: None,
        series: vec![String::new()],
        own_norms: true,
        first,
    }
}

/// The value of `column` in the last printed row of `run`.
pub(crate) fn last_value(run: &RunResult, column: &str) -> Option<f64> {
    run.rows.last()?.value(column)
}

/// Colours of `n` runs in their order, along a ramp from indigo through blue, teal and green to
/// orange and red: neighbouring values get neighbouring colours, so the order of the runs reads
/// off the plot as off the legend.
fn ramp(n: usize) -> Vec<RGBColor> {
    const STOPS: [(f64, f64, f64); 6] = [
        (45.0, 40.0, 150.0),
        (30.0, 115.0, 195.0),
        (20.0, 160.0, 135.0),
        (105.0, 170.0, 40.0),
        (235.0, 140.0, 20.0),
        (200.0, 40.0, 40.0),
    ];
    (0..n)
        .map(|i| {
            let t = if n > 1 {
                i as f64 / (n - 1) as f64
            } else {
                0.0
            };
            let at = t * (STOPS.len() - 1) as f64;
            let k = (at.floor() as usize).min(STOPS.len() - 2);
            let f = at - k as f64;
            let (a, b) = (STOPS[k], STOPS[k + 1]);
            let mix = |x: f64, y: f64| (x + f * (y - x)).round() as u8;
            RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
        })
        .collect()
}

/// Draw the figures of comparison `c` into `fig_dir`: those it has data for.
pub(crate) fn write_figures(fig_dir: &Path, c: &ComparedRuns) -> io::Result<Vec<Figure>> {
    let figure = |kind: &str, caption: String| {
        let file = format!("{}-{kind}.svg", c.stem);
        let path = fig_dir.join(&file);
        (
            Figure {
                file,
                caption,
                links: Vec::new(),
            },
            path,
        )
    };
    let mut figures = Vec::new();
    if let Some(axis) = &c.axis {
        let panels = quantity_curves(c);
        if !panels.is_empty() {
            let names: Vec<String> = panels.iter().map(|(text, _, _)| text.clone()).collect();
            let (f, path) = figure(
                "quantities",
                format!(
                    "{}: {} of the last printed cycle of each run against {axis}{}; each point \
                     is one run",
                    c.title,
                    names.join(", "),
                    if c.series.len() > 1 {
                        ", one curve per value of the other swept field"
                    } else {
                        ""
                    }
                ),
            );
            quantity_plots(&path, axis, &panels)?;
            figures.push(f);
        }
    }
    let cut_runs: Vec<CutRun> = c
        .runs
        .iter()
        .map(|r| CutRun {
            run: r.run,
            label: r.label.clone(),
            color: r.color,
            dashed: r.dashed,
        })
        .collect();
    if let Some((y, curves)) = film::psi_cuts(&cut_runs).filter(|(_, c)| !c.is_empty()) {
        let (f, path) = figure(
            "cuts",
            format!(
                "{}: ψ along x₂ = {} on the last mesh of each run, one colour per run{}",
                c.title,
                fmt_short(y),
                if curves.len() < c.runs.len() {
                    " (a run cut at another height, or without a cut, is left out)"
                } else {
                    ""
                }
            ),
        );
        film::write_psi_cuts(&path, &c.title, y, &curves)?;
        figures.push(f);
    }
    let convergence: Vec<Curve> = c
        .runs
        .iter()
        .map(|r| Curve {
            label: r.label.clone(),
            color: r.color,
            dashed: r.dashed,
            points: r
                .run
                .rows
                .iter()
                .filter_map(|row| Some((row.dofs()? as f64, row.estimate()?)))
                .filter(loggable)
                .collect(),
        })
        .filter(|curve| !curve.points.is_empty())
        .collect();
    if !convergence.is_empty() {
        let (axis, norm) = if c.own_norms {
            (
                "η (each in its own norm)".to_string(),
                "; each estimate is in its own model's norm, so compare slopes, not levels",
            )
        } else {
            (estimate_name(c.runs[0].run).axis, "")
        };
        let (f, path) = figure(
            "convergence",
            format!(
                "{}: the a-posteriori estimate of every printed cycle of each run against its \
                 dofs, log–log{norm}",
                c.title
            ),
        );
        write_log_log(
            &path,
            &format!("{} — estimate vs dofs", c.title),
            ("dofs", &axis),
            &convergence,
            (&[], ""),
            "no rows with an estimate",
        )?;
        figures.push(f);
    }
    Ok(figures)
}

/// One panel per compared quantity that some run has: its label, its column with the unit, and
/// one curve per series of the quantity against the swept value.
fn quantity_curves(c: &ComparedRuns) -> Vec<(String, String, Vec<Curve>)> {
    c.quantities
        .iter()
        .filter_map(|q| {
            let (text, unit) = quantities::label(q)?;
            let colors = ramp(c.series.len());
            let mut curves: Vec<Curve> = c
                .series
                .iter()
                .zip(colors)
                .map(|(label, color)| Curve {
                    label: label.clone(),
                    color: if c.series.len() > 1 {
                        color
                    } else {
                        super::plots::TRIBO
                    },
                    dashed: false,
                    points: Vec::new(),
                })
                .collect();
            for r in &c.runs {
                if let (Some(x), Some(y)) = (r.x, last_value(r.run, q)) {
                    if y.is_finite() {
                        curves[r.series].points.push((x, y));
                    }
                }
            }
            for curve in &mut curves {
                curve.points.sort_by(|a, b| a.0.total_cmp(&b.0));
            }
            curves.retain(|curve| !curve.points.is_empty());
            (!curves.is_empty()).then(|| (text, format!("{q} [{unit}]"), curves))
        })
        .collect()
}

/// The quantity panels stacked in one figure, each titled with its quantity.
fn quantity_plots(
    path: &Path,
    axis: &str,
    panels: &[(String, String, Vec<Curve>)],
) -> io::Result<()> {
    const PANEL: u32 = 330;
    let heights: Vec<u32> = panels
        .iter()
        .map(|(_, _, curves)| PANEL + linear_legend_height(curves, true))
        .collect();
    let mut svg = String::new();
    {
        let root =
            SVGBackend::with_string(&mut svg, (760, heights.iter().sum())).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let mut rest = root;
        for ((text, column, curves), height) in panels.iter().zip(&heights) {
            let (panel, below) = rest.split_vertically(*height);
            linear_chart(&panel, text, (axis, column), curves, true)?;
            rest = below;
        }
        rest.present().map_err(plot_err)?;
    }
    crate::fsio::write(path, svg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ramp_runs_from_indigo_to_red_through_distinct_colours() {
        let colors = ramp(4);
        assert_eq!(colors[0], RGBColor(45, 40, 150));
        assert_eq!(colors[3], RGBColor(200, 40, 40));
        for pair in colors.windows(2) {
            assert_ne!(pair[0], pair[1]);
        }
        assert_eq!(ramp(1), [RGBColor(45, 40, 150)]);
    }
}
