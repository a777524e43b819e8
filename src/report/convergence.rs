//! The line charts of a grid-adaptive run: its estimate against the degrees of freedom beside
//! the printed one (convergence), the cost of accuracy against the wall seconds with the seconds
//! per phase (cost), and the accuracy of the model-adaptive variants against their solve seconds
//! (accuracy). Drawn with `plotters`' SVG backend; degenerate data (no rows, values a log axis
//! cannot show) is skipped and said so in the figure.

use std::io;
use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::figures::{Drawing, Figure, Figures};
use super::html::fmt_short;
use super::plots::*;
use super::MAX_SHOWN_THESIS_ROWS;
use crate::results::{columns, RunResult};
use crate::thesis::ThesisTable;

/// Log–log convergence plot: the estimate η against dofs for tribo (solid) and the thesis
/// (dashed), the axis naming η's theorem and norm ([`super::estimate_name`]),
/// with a slope −1/2 guide (the optimal rate of Q1 in 2-D, error ∝ N^(−1/2)).
///
/// Model-adaptive tables print `model_error` instead of `estimate`; when the thesis has that
/// column it is plotted too, against tribo's `model_error` quantity.
pub fn convergence(path: &Path, run: &RunResult, thesis: &ThesisTable) -> io::Result<()> {
    let mut curves = vec![
        Curve {
            label: "tribo η".into(),
            color: TRIBO,
            dashed: false,
            points: run
                .rows
                .iter()
                .filter_map(|r| Some((r.value("dofs")?, r.estimate()?)))
                .filter(loggable)
                .collect(),
        },
        Curve {
            label: "thesis η".into(),
            color: THESIS,
            dashed: true,
            points: thesis_pairs(thesis, "dofs", "estimate"),
        },
    ];
    if curves[1].points.is_empty() {
        // Tables IV.30–IV.35 print the estimate in three cell groups: their root sum of squares
        // is the estimate tribo's column holds.
        let groups = [
            columns::EST_Z_BOUNDARY,
            columns::EST_S_BOUNDARY,
            columns::EST_INTERIOR,
        ];
        curves[1].label = "thesis √(z² + S² + interior²)".into();
        curves[1].points = thesis
            .rows
            .iter()
            .take(MAX_SHOWN_THESIS_ROWS)
            .filter_map(|row| {
                let cycle = *row.first()? as usize;
                let total = groups
                    .iter()
                    .map(|g| thesis.value(cycle, g).map(|v| v * v))
                    .sum::<Option<f64>>()?
                    .sqrt();
                Some((thesis.value(cycle, columns::DOFS)?, total))
            })
            .filter(loggable)
            .collect();
    }
    if thesis.columns.iter().any(|c| c == "model_error") {
        curves.push(Curve {
            label: "tribo model error".into(),
            color: TRIBO_ME,
            dashed: false,
            points: run
                .rows
                .iter()
                .filter_map(|r| Some((r.value("dofs")?, r.value("model_error")?)))
                .filter(loggable)
                .collect(),
        });
        curves.push(Curve {
            label: "thesis model error".into(),
            color: THESIS_ME,
            dashed: true,
            points: thesis_pairs(thesis, "dofs", "model_error"),
        });
    }
    curves.retain(|c| !c.points.is_empty());

    // The guide passes below every point: c = min y·√x, drawn at 0.6·c/√x.
    let all: Vec<(f64, f64)> = curves
        .iter()
        .flat_map(|c| c.points.iter().copied())
        .collect();
    let guide = all
        .iter()
        .map(|(x, y)| y * x.sqrt())
        .fold(f64::INFINITY, f64::min);
    let guide_pts: Vec<(f64, f64)> = if guide.is_finite() && all.len() > 1 {
        let (a, b) = log_range(all.iter().map(|p| p.0));
        let (a, b) = (a * 1.1, b / 1.1);
        vec![(a, 0.6 * guide / a.sqrt()), (b, 0.6 * guide / b.sqrt())]
    } else {
        Vec::new()
    };
    write_log_log(
        path,
        &format!("{} — convergence", run.table),
        ("degrees of freedom", &super::estimate_name(run).axis),
        &curves,
        (&guide_pts, "slope −1/2"),
        "no positive estimates to plot",
    )
}

/// Cost of accuracy of a model-adaptive scene (`<table>.cost.csv`): per variant (z, Signorini on
/// every face, III.2, III.3) the energy distance to the all-Signorini solution and the true
/// penetration against the cumulative solve seconds over the cycles, log–log. The all-Signorini
/// variant is the reference (distance 0) and appears in the penetration panel only.
pub fn accuracy(path: &Path, run: &RunResult) -> io::Result<()> {
    const COLORS: [RGBColor; 4] = [
        RGBColor(31, 119, 180),
        RGBColor(0, 0, 0),
        RGBColor(44, 160, 44),
        RGBColor(214, 39, 40),
    ];
    let panel = |measure: fn(&crate::results::CostRow) -> f64| -> Vec<Curve> {
        crate::results::cost_variants(&run.costs)
            .into_iter()
            .zip(COLORS)
            .map(|(variant, color)| {
                let mut seconds = 0.0;
                let points = run
                    .costs
                    .iter()
                    .filter(|c| c.variant == variant)
                    .map(|c| {
                        seconds += c.seconds_solve;
                        (seconds, measure(c))
                    })
                    .filter(loggable)
                    .collect();
                Curve {
                    label: variant.to_string(),
                    color,
                    dashed: false,
                    points,
                }
            })
            .filter(|c| !c.points.is_empty())
            .collect()
    };
    // Two 760×520 charts side by side.
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (1520, 520)).into_drawing_area();
        let (left, right) = root.split_horizontally(760);
        log_log_chart(
            &left,
            &format!("{} — accuracy: energy distance to all-Signorini", run.table),
            ("cumulative solve seconds", "‖s − s_S‖_a / ‖s_S‖_a"),
            &panel(|c| c.energy_distance),
            (&[], ""),
            "no positive distances",
        )?;
        log_log_chart(
            &right,
            &format!("{} — true penetration into the obstacle", run.table),
            ("cumulative solve seconds", "penetration"),
            &panel(|c| c.penetration),
            (&[], ""),
            "no penetration",
        )?;
        root.present().map_err(plot_err)?;
    }
    crate::fsio::write(path, svg)
}

/// The five phases in drawing order, with their colours.
const PHASES: [(&str, RGBColor); 5] = [
    ("setup", RGBColor(141, 160, 203)),
    ("assemble", RGBColor(102, 194, 165)),
    ("solve", RGBColor(252, 141, 98)),
    ("estimate", RGBColor(231, 138, 195)),
    ("refine", RGBColor(166, 216, 84)),
];

/// Cost of accuracy: the estimate against cumulative wall seconds (log–log, each point labelled
/// with its dofs), and below it the seconds of each cycle stacked by phase — where the time goes.
pub fn cost(path: &Path, run: &RunResult) -> io::Result<()> {
    let cumulative = run.cumulative_seconds();
    let points: Vec<(f64, f64, usize)> = run
        .rows
        .iter()
        .zip(&cumulative)
        .filter_map(|(r, t)| Some((*t, r.estimate()?, r.dofs()?)))
        .filter(|(t, e, _)| loggable(&(*t, *e)))
        .collect();

    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (760, 720)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let (top, bottom) = root.split_vertically(420);
        cost_accuracy(&top, &run.table, &super::estimate_name(run).axis, &points)?;
        phase_bars(&bottom, run)?;
        root.present().map_err(plot_err)?;
    }
    crate::fsio::write(path, svg)
}

/// Upper panel of [`cost`].
fn cost_accuracy(
    area: &DrawingArea<SVGBackend, Shift>,
    table: &str,
    estimate: &str,
    points: &[(f64, f64, usize)],
) -> io::Result<()> {
    let (x_lo, x_hi) = log_range(points.iter().map(|p| p.0));
    let (y_lo, y_hi) = log_range(points.iter().map(|p| p.1));
    // Extra room on the right for the dofs labels of the last point.
    let x_hi = x_hi * (x_hi / x_lo).powf(0.12);
    let mut chart = log_log_axes(
        area,
        (&format!("{table} — cost of accuracy"), 24),
        44,
        ((x_lo, x_hi), (y_lo, y_hi)),
        ("cumulative wall seconds", estimate),
    )?;
    if points.is_empty() {
        empty_note(
            area,
            "no positive timings and estimates to plot",
            (200, 200),
        )?;
        return Ok(());
    }
    chart
        .draw_series(LineSeries::new(
            points.iter().map(|p| (p.0, p.1)),
            TRIBO.stroke_width(2),
        ))
        .map_err(plot_err)?;
    let label_font = ("sans-serif", 14).into_font().color(&BLACK);
    chart
        .draw_series(points.iter().map(|&(t, e, dofs)| {
            EmptyElement::at((t, e))
                + Circle::new((0, 0), 3, TRIBO.filled())
                + Text::new(format!("{dofs} dofs"), (6, -14), label_font.clone())
        }))
        .map_err(plot_err)?;
    Ok(())
}

/// Lower panel of [`cost`]: stacked bars of the phase seconds, one bar per printed cycle.
fn phase_bars(area: &DrawingArea<SVGBackend, Shift>, run: &RunResult) -> io::Result<()> {
    let n = run.rows.len().max(1);
    let finite = |v: f64| if v.is_finite() && v > 0.0 { v } else { 0.0 };
    let max_total = run
        .rows
        .iter()
        .map(|r| {
            r.seconds
                .named()
                .iter()
                .map(|(_, s)| finite(*s))
                .sum::<f64>()
        })
        .fold(0.0, f64::max);
    let y_hi = if max_total > 0.0 {
        max_total * 1.08
    } else {
        1.0
    };
    let mut chart = ChartBuilder::on(area)
        .caption("seconds per phase and cycle", ("sans-serif", 16))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(-0.5..(n as f64 - 0.5), 0.0..y_hi)
        .map_err(plot_err)?;
    let cycles: Vec<usize> = run.rows.iter().map(|r| r.cycle).collect();
    let x_label = move |v: &f64| {
        let i = v.round();
        if (v - i).abs() < 1e-6 && i >= 0.0 {
            cycles
                .get(i as usize)
                .map(|c| c.to_string())
                .unwrap_or_default()
        } else {
            String::new()
        }
    };
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_labels(n + 1)
        .x_label_formatter(&x_label)
        .y_label_formatter(&|v| fmt_short(*v))
        .x_desc("cycle")
        .y_desc("seconds")
        .y_max_light_lines(1)
        .light_line_style(RGBColor(240, 240, 240))
        .bold_line_style(RGBColor(215, 215, 215))
        .label_style(("sans-serif", 17))
        .axis_desc_style(("sans-serif", 17))
        .draw()
        .map_err(plot_err)?;
    for (p, (name, color)) in PHASES.iter().enumerate() {
        let bars: Vec<Rectangle<(f64, f64)>> = run
            .rows
            .iter()
            .enumerate()
            .map(|(i, r)| {
                let s = r.seconds.named();
                let below: f64 = s[..p].iter().map(|(_, v)| finite(*v)).sum();
                let x = i as f64;
                Rectangle::new(
                    [(x - 0.35, below), (x + 0.35, below + finite(s[p].1))],
                    color.filled(),
                )
            })
            .collect();
        let color = *color;
        chart
            .draw_series(bars)
            .map_err(plot_err)?
            .label(*name)
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 12, y + 5)], color.filled()));
    }
    series_legend(&mut chart, SeriesLabelPosition::UpperLeft, 17)
}

/// The estimate against the degrees of freedom beside the printed one: the headline of a
/// grid-adaptive run.
pub(super) struct Convergence;

impl Figures for Convergence {
    fn applies(&self, run: &RunResult) -> bool {
        !run.is_model_adaptive() && !run.is_load_steps() && run.uzawa.is_empty()
    }

    fn write(&self, at: &Drawing) -> io::Result<Vec<Figure>> {
        let run = at.run;
        let (figure, path) = at.figure(
            "convergence",
            format!(
                "{}: {} against the degrees of freedom, tribo (solid) and thesis (dashed), \
                 log–log",
                run.table, at.eta.caption
            ),
        );
        convergence(&path, run, at.thesis)?;
        Ok(vec![figure])
    }
}

/// The cost of accuracy of the model-adaptive variants on a scene's fixed mesh.
pub(super) struct Accuracy;

impl Figures for Accuracy {
    fn applies(&self, run: &RunResult) -> bool {
        !run.costs.is_empty()
    }

    fn write(&self, at: &Drawing) -> io::Result<Vec<Figure>> {
        let run = at.run;
        let (figure, path) = at.figure(
            "accuracy",
            format!(
                "{}: cost of accuracy on this scene's fixed mesh — energy distance to the \
                 all-Signorini solution and true penetration against cumulative solve seconds, \
                 for z on every face, Signorini on every face, Algorithms III.2 and III.3",
                run.table
            ),
        );
        accuracy(&path, run)?;
        Ok(vec![figure])
    }
}

/// The estimate against the cumulative wall seconds, and the seconds per phase, of a run that
/// refines one mesh hierarchy.
pub(super) struct Cost;

impl Figures for Cost {
    fn applies(&self, run: &RunResult) -> bool {
        !run.rows.is_empty() && !run.is_model_adaptive() && !run.is_load_steps()
    }

    fn write(&self, at: &Drawing) -> io::Result<Vec<Figure>> {
        let run = at.run;
        let (figure, path) = at.figure(
            "cost",
            format!(
                "{}: cost of accuracy — {} against the cumulative wall seconds, and the \
                 seconds per phase",
                run.table, at.eta.caption
            ),
        );
        cost(&path, run)?;
        Ok(vec![figure])
    }
}
