//! The figures of the fluid solvers and models: a SubStokes table's comparison with Reynolds on
//! its last mesh (thesis §IV.3.3, §IV.3.7, Figs IV.112–IV.115 and IV.143) — the pressure
//! p ≈ ψ/g and the flow rate χ₁ along the cut, SubStokes solid and Reynolds dashed — and the
//! convergence of Uzawa's algorithm with each preconditioner (Fig. III.6).

use std::io;
use std::path::Path;

use plotters::prelude::*;

use super::figures::{Drawing, Figure, Figures};
use super::html::fmt_short;
use super::legend::{self, Entry, Placed};
use super::plots::{
    linear_chart, linear_legend_height, log_range, log_tick, loggable, plot_err, write_log_log,
    Curve, NiceLog, RIGHT_MARGIN,
};
use crate::experiment::Comparison;
use crate::results::{Cuts, RunResult};

const SUBSTOKES: RGBColor = RGBColor(31, 90, 180);
const REYNOLDS: RGBColor = RGBColor(200, 60, 40);

/// Column `column` of `cuts` against x₁ as a curve (non-finite values left out).
fn cut_curve(cuts: &Cuts, column: &str, label: String, color: RGBColor, dashed: bool) -> Curve {
    Curve {
        label,
        color,
        dashed,
        points: cuts
            .column("x")
            .unwrap_or_default()
            .iter()
            .copied()
            .zip(cuts.column(column).unwrap_or_default().iter().copied())
            .filter(|(_, v)| v.is_finite())
            .collect(),
    }
}

/// Write the comparison figure of `run`'s cuts to `path`.
pub(super) fn cuts(path: &Path, run: &RunResult, cuts: &Cuts) -> io::Result<Placed> {
    let curve = |column: &str, label: &str, color: RGBColor, dashed: bool| {
        cut_curve(cuts, column, label.to_string(), color, dashed)
    };
    let pressure = [
        curve("p_substokes", "SubStokes ψ/g", SUBSTOKES, false),
        curve("p_reynolds", "Reynolds ψ/g", REYNOLDS, true),
    ];
    let flow = [
        curve("chi1_substokes", "SubStokes χ₁", SUBSTOKES, false),
        curve("chi1_reynolds", "Reynolds χ₁ from (I.86)", REYNOLDS, true),
    ];
    let y = fmt_short(cuts.y);
    let mut svg = String::new();
    let mut placed = Placed::default();
    {
        let lower = 350 + linear_legend_height(&flow, false);
        let size = (760, 350 + linear_legend_height(&pressure, false) + lower);
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let (top, bottom) = root.split_vertically(size.1 - lower);
        placed.extend(linear_chart(
            &top,
            &format!("{} — pressure p ≈ ψ/g along x₂ = {y}", run.table),
            ("x₁", "p"),
            &pressure,
            false,
        )?);
        placed.extend(linear_chart(
            &bottom,
            &format!("flow rate χ₁ along x₂ = {y}"),
            ("x₁", "χ₁"),
            &flow,
            false,
        )?);
        root.present().map_err(plot_err)?;
    }
    crate::fsio::write(path, svg)?;
    Ok(placed)
}

/// Colours of the Uzawa variants, in the order of Fig. III.6.
const VARIANTS: [RGBColor; 5] = [
    RGBColor(120, 120, 120),
    RGBColor(200, 60, 40),
    RGBColor(230, 150, 20),
    RGBColor(40, 150, 70),
    RGBColor(31, 90, 180),
];

/// The relative residual of every Uzawa variant against the iteration, log scale (Fig. III.6).
pub(super) fn uzawa(path: &Path, run: &RunResult) -> io::Result<Placed> {
    let mut curves: Vec<Curve> = Vec::new();
    for r in &run.uzawa {
        if curves.last().is_none_or(|c| c.label != r.variant) {
            curves.push(Curve {
                label: r.variant.clone(),
                color: VARIANTS[curves.len() % VARIANTS.len()],
                dashed: false,
                points: Vec::new(),
            });
        }
        if let Some(c) = curves.last_mut() {
            if r.relative_residual > 0.0 && r.relative_residual.is_finite() {
                c.points.push((r.iteration as f64, r.relative_residual));
            }
        }
    }
    let last = run
        .uzawa
        .iter()
        .map(|r| r.iteration)
        .max()
        .unwrap_or(1)
        .max(1) as f64;
    let y = NiceLog::new(log_range(
        curves.iter().flat_map(|c| c.points.iter().map(|p| p.1)),
    ));
    let entries: Vec<Entry> = curves.iter().map(Entry::line).collect();
    let mut svg = String::new();
    let placed;
    {
        let size = (760, 480 + legend::height(&entries, 760));
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let (area, strip) = legend::split(&root, &entries);
        let mut chart = ChartBuilder::on(&area)
            .caption(
                format!("{} — Uzawa's algorithm, relative residual", run.table),
                ("sans-serif", 19),
            )
            .margin(12)
            .margin_right(RIGHT_MARGIN)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(0.0..last, y)
            .map_err(plot_err)?;
        chart
            .configure_mesh()
            .x_desc("Uzawa iteration k")
            .y_desc("r_k / r_0")
            .x_label_formatter(&|v| fmt_short(*v))
            .y_label_formatter(&log_tick)
            .light_line_style(RGBColor(240, 240, 240))
            .bold_line_style(RGBColor(215, 215, 215))
            .label_style(("sans-serif", 15))
            .axis_desc_style(("sans-serif", 15))
            .draw()
            .map_err(plot_err)?;
        for c in &curves {
            chart
                .draw_series(LineSeries::new(
                    c.points.iter().copied(),
                    c.color.stroke_width(2),
                ))
                .map_err(plot_err)?;
        }
        placed = Placed {
            points: legend::pixels(&chart, curves.iter().flat_map(|c| c.points.clone())),
            legends: legend::draw(&strip, &entries)?.into_iter().collect(),
        };
        root.present().map_err(plot_err)?;
    }
    crate::fsio::write(path, svg)?;
    Ok(placed)
}

/// The model of a run the model-adaptive film is compared with: a SubStokes table (its cuts
/// compare SubStokes with Reynolds), else a Reynolds table.
fn is_substokes(run: &RunResult) -> bool {
    run.cuts.as_ref().is_some_and(Cuts::compares_models)
}

/// The legend name of a related run: its table and model.
pub(super) fn related_label(run: &RunResult) -> String {
    let model = if is_substokes(run) {
        "pure SubStokes"
    } else {
        "pure Reynolds"
    };
    format!("{model} ({})", run.table)
}

/// The colour of a related run: its model's.
pub(super) fn related_color(run: &RunResult) -> RGBColor {
    if is_substokes(run) {
        SUBSTOKES
    } else {
        REYNOLDS
    }
}

/// Colour of the model-adaptive run in the cross-run figures.
pub(super) const MODEL_ADAPTIVE: RGBColor = RGBColor(0, 0, 0);

/// Fig. IV.117: the a-posteriori estimate against the number of SubStokes cells — the
/// model-adaptive run's Theorem III.23 estimate with the model error, √(η_S² + η_m²) (the
/// thesis's "total error"), and with the Reynolds part as well (tribo's `estimate`, dashed),
/// beside each related SubStokes table's estimate against its cells (all of them SubStokes).
/// Cycles without SubStokes cells have no point on the log axis.
pub(super) fn estimate_vs_substokes_cells(
    path: &Path,
    run: &RunResult,
    related: &[&RunResult],
) -> io::Result<Placed> {
    let points = |f: &dyn Fn(&crate::results::Row) -> Option<(f64, f64)>, r: &RunResult| {
        r.rows
            .iter()
            .filter_map(f)
            .filter(loggable)
            .collect::<Vec<_>>()
    };
    let cells = |r: &crate::results::Row| r.count_of("substokes_cells").map(|n| n as f64);
    let mut curves = vec![
        Curve {
            label: format!("{}: III.23 + model error", run.table),
            color: MODEL_ADAPTIVE,
            dashed: false,
            points: points(
                &|r| {
                    let s = r.value("estimate_substokes")?;
                    let m = r.value("model_error")?;
                    Some((cells(r)?, s.hypot(m)))
                },
                run,
            ),
        },
        Curve {
            label: format!("{}: with the Reynolds part", run.table),
            color: MODEL_ADAPTIVE,
            dashed: true,
            points: points(&|r| Some((cells(r)?, r.estimate()?)), run),
        },
    ];
    for r in related.iter().filter(|r| is_substokes(r)) {
        curves.push(Curve {
            label: related_label(r),
            color: related_color(r),
            dashed: false,
            points: points(
                &|row| Some((row.active_cells()? as f64, row.estimate()?)),
                r,
            ),
        });
    }
    write_log_log(
        path,
        &format!("{} — estimate vs SubStokes cells", run.table),
        ("SubStokes cells", "η (Thm III.23 + model error III.6)"),
        &curves,
        (&[], ""),
        "no SubStokes cells",
    )
}

/// One run of a figure of ψ along a cut ([`psi_cuts`]): its legend label, colour and dash.
pub(super) struct CutRun<'a> {
    pub run: &'a RunResult,
    pub label: String,
    pub color: RGBColor,
    pub dashed: bool,
}

/// The pressure ψ along the cut of each of `runs` (ψ^S of a SubStokes table, whose cuts hold both
/// models; ψ of a Reynolds table and of the model-adaptive film), one curve each, at the height
/// of the first run's cut: a run without a cut, or cut at another height, is left out. `None`
/// where the first run has no cut.
pub(super) fn psi_cuts(runs: &[CutRun]) -> Option<(f64, Vec<Curve>)> {
    let y = runs.first()?.run.cuts.as_ref()?.y;
    let curves = runs
        .iter()
        .filter_map(|r| {
            let cuts = r.run.cuts.as_ref().filter(|c| c.y == y)?;
            let column = if is_substokes(r.run) {
                "psi_substokes"
            } else {
                "psi"
            };
            Some(cut_curve(cuts, column, r.label.clone(), r.color, r.dashed))
        })
        .collect();
    Some((y, curves))
}

/// Write the figure of `curves` of ψ along x₂ = `y` ([`psi_cuts`]) with the title `name — ψ
/// along x₂ = y`.
pub(super) fn write_psi_cuts(
    path: &Path,
    name: &str,
    y: f64,
    curves: &[Curve],
) -> io::Result<Placed> {
    let mut svg = String::new();
    let placed;
    {
        let size = (760, 420 + linear_legend_height(curves, false));
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        placed = linear_chart(
            &root,
            &format!("{name} — ψ along x₂ = {}", fmt_short(y)),
            ("x₁", "ψ"),
            curves,
            false,
        )?;
        root.present().map_err(plot_err)?;
    }
    crate::fsio::write(path, svg)?;
    Ok(placed)
}

/// Fig. IV.118: the pressure ψ along the cut of the model-adaptive run beside the last solutions
/// of the related runs (ψ^S of a SubStokes table, ψ of a Reynolds table) along the same cut;
/// a related run cut at another height is left out.
pub(super) fn related_cuts(
    path: &Path,
    run: &RunResult,
    related: &[&RunResult],
) -> io::Result<Placed> {
    let own = CutRun {
        run,
        label: format!("model-adaptive ({})", run.table),
        color: MODEL_ADAPTIVE,
        dashed: false,
    };
    let runs: Vec<CutRun> = std::iter::once(own)
        .chain(related.iter().map(|r| CutRun {
            run: r,
            label: related_label(r),
            color: related_color(r),
            dashed: true,
        }))
        .collect();
    match psi_cuts(&runs) {
        Some((y, curves)) => write_psi_cuts(path, &run.table, y, &curves),
        None => Ok(Placed::default()),
    }
}

/// The cost of accuracy of one scene solved three ways: each run's estimate against its
/// cumulative wall seconds, log–log. Each estimate is in its own norm (Theorem III.16's for
/// Reynolds, III.23's for SubStokes, their combination with the model error for the
/// model-adaptive film), so the curves compare slopes and seconds, not levels.
pub(super) fn related_cost(
    path: &Path,
    run: &RunResult,
    related: &[&RunResult],
) -> io::Result<Placed> {
    let curve = |r: &RunResult, label: String, color: RGBColor| Curve {
        label,
        color,
        dashed: false,
        points: r
            .rows
            .iter()
            .zip(r.cumulative_seconds())
            .filter_map(|(row, t)| Some((t, row.estimate()?)))
            .filter(loggable)
            .collect(),
    };
    let mut curves = vec![curve(
        run,
        format!("model-adaptive ({})", run.table),
        MODEL_ADAPTIVE,
    )];
    for r in related {
        curves.push(curve(r, related_label(r), related_color(r)));
    }
    write_log_log(
        path,
        &format!("{} — cost of accuracy, one scene three ways", run.table),
        ("cumulative wall seconds", "η (each in its own norm)"),
        &curves,
        (&[], ""),
        "no timed rows",
    )
}

/// The residuals of Uzawa's algorithm with each preconditioner (Fig. III.6).
pub(super) struct Uzawa;

impl Figures for Uzawa {
    fn applies(&self, run: &RunResult) -> bool {
        !run.is_model_adaptive() && !run.is_load_steps() && !run.uzawa.is_empty()
    }

    fn write(&self, at: &Drawing) -> io::Result<Vec<Figure>> {
        let run = at.run;
        let (figure, path) = at.figure(
            "uzawa",
            format!(
                "{}: relative residual √(‖Av − Bp − f‖² + ‖Bᵀv + Cp − g‖²)/r₀ of Uzawa's algorithm \
                 with each preconditioner on the test problem (III.88), log scale (thesis Fig. \
                 III.6)",
                run.table
            ),
        );
        uzawa(&path, run)?;
        Ok(vec![figure])
    }
}

/// SubStokes and Reynolds along a cut of the last mesh, in a SubStokes table.
pub(super) struct ModelCuts;

impl Figures for ModelCuts {
    fn applies(&self, run: &RunResult) -> bool {
        run.cuts.as_ref().is_some_and(|c| c.compares_models())
    }

    fn write(&self, at: &Drawing) -> io::Result<Vec<Figure>> {
        let run = at.run;
        let Some(c) = run.cuts.as_ref() else {
            return Ok(Vec::new());
        };
        // The thesis figures show its own scenes, not a scene of the user's.
        let cited = if matches!(at.thesis.comparison, Comparison::OwnScene) {
            ""
        } else {
            " (thesis Figs IV.112–IV.115, IV.143)"
        };
        let mut caption = format!(
            "{}: SubStokes (solid) and Reynolds (dashed) on the last mesh along x₂ = {} — \
             pressure ψ/g and flow rate χ₁, the latter rebuilt by (I.86) for Reynolds{cited}; \
             max|ψ^S − ψ^R| is {} of max|ψ^R − ψ₀|",
            run.table,
            fmt_short(c.y),
            c.relative_pressure_difference()
                .map_or("undefined".into(), |d| format!("{:.1} %", 100.0 * d)),
        );
        if let (Some(s), Some(r)) = (c.cavitated_substokes, c.cavitated_reynolds) {
            caption.push_str(&format!(
                "; cavitated area SubStokes {:.0} %, Reynolds {:.0} %",
                100.0 * s,
                100.0 * r
            ));
        }
        let (figure, path) = at.figure("cuts", caption);
        cuts(&path, run, c)?;
        Ok(vec![figure])
    }
}

/// The figures that set a run beside its related tables (`related` of the experiment: the
/// model-adaptive film of Fig. IV.116 with the pure Reynolds and pure SubStokes runs of its
/// scene): Fig. IV.117 (estimate vs SubStokes cells), Fig. IV.118 (ψ along the cut) and the cost
/// of accuracy of the three. A related table that is not on this page is named in the captions.
pub(super) struct Related;

impl Figures for Related {
    fn applies(&self, run: &RunResult) -> bool {
        !run.related.is_empty()
    }

    fn write(&self, at: &Drawing) -> io::Result<Vec<Figure>> {
        // A scene of one's own is compared with its related runs in a section of its own
        // (`compare`), without the thesis's figures.
        if matches!(at.thesis.comparison, Comparison::OwnScene) {
            return Ok(Vec::new());
        }
        let run = at.run;
        let related: Vec<&RunResult> = run
            .related
            .iter()
            .filter_map(|id| at.runs.iter().find(|r| r.table == *id).copied())
            .collect();
        let missing: Vec<&str> = run
            .related
            .iter()
            .filter(|id| !related.iter().any(|r| r.table == **id))
            .map(String::as_str)
            .collect();
        let absent = if missing.is_empty() {
            String::new()
        } else {
            format!(
                " ({} not in this report: run the report with them, e.g. --only {},{})",
                missing.join(", "),
                run.table,
                run.related.join(",")
            )
        };
        let mut figures = Vec::new();
        let (figure, path) = at.figure(
            "substokes-cells",
            format!(
                "{}: the a-posteriori estimate against the number of SubStokes cells (thesis Fig. \
                 IV.117) — Theorem III.23 on the SubStokes cells with the model error (the \
                 thesis's total error, solid black), the same with the Reynolds estimate of the \
                 Reynolds cells (dashed), and the pure SubStokes run, all of whose cells are \
                 SubStokes; log–log, cycles without SubStokes cells left out{absent}",
                run.table
            ),
        );
        figures.push(figure);
        estimate_vs_substokes_cells(&path, run, &related)?;
        if let Some(cuts) = &run.cuts {
            let (figure, path) = at.figure(
                "related-cuts",
                format!(
                    "{}: ψ along x₂ = {} of the last model-adaptive solution (solid) and of the \
                     last solutions of the pure runs (dashed; thesis Fig. IV.118){absent}",
                    run.table,
                    fmt_short(cuts.y)
                ),
            );
            figures.push(figure);
            related_cuts(&path, run, &related)?;
        }
        let (figure, path) = at.figure(
            "related-cost",
            format!(
                "{}: cost of accuracy of one scene solved three ways — each run's estimate against \
                 its cumulative wall seconds, log–log; each estimate is in its own norm (Theorem \
                 III.16 for Reynolds, III.23 for SubStokes, the total of Fig. IV.117 for the \
                 model-adaptive film), so compare slopes and seconds, not levels{absent}",
                run.table
            ),
        );
        figures.push(figure);
        related_cost(&path, run, &related)?;
        Ok(figures)
    }
}
