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
use super::legend::{self, Entry, Placed, Swatch};
use super::plots::*;
use super::MAX_SHOWN_THESIS_ROWS;
use super::{compared_value, compares_previous_estimate};
use crate::results::{columns, RunResult};
use crate::thesis::ThesisTable;

/// Log–log convergence plot: the estimate η against dofs for tribo (solid) and the thesis
/// (dashed), the axis naming η's theorem and norm ([`super::estimate_name`]),
/// with a slope −1/2 guide (the optimal rate of Q1 in 2-D, error ∝ N^(−1/2)).
pub fn convergence(path: &Path, run: &RunResult, thesis: &ThesisTable) -> io::Result<Placed> {
    let curves = convergence_curves(run, thesis);
    let guide_pts = slope_guide(&curves);
    write_log_log(
        path,
        &format!("{} — convergence", run.table),
        ("degrees of freedom", &super::estimate_name(run).axis),
        &curves,
        (&guide_pts, "slope −1/2"),
        "no positive estimates to plot",
    )
}

/// The curves of the convergence plot: tribo's estimate and the printed one, each against its
/// row's dofs; those without a drawable point left out.
///
/// tribo's curve holds the value the section's table compares with the printed estimate
/// ([`compared_value`]): in the fluid tables, whose printed rows set the mesh after refinement
/// beside the estimate of the solve before it, that is `estimate_previous_mesh`, drawn at the
/// dofs of the row the thesis prints it in — so the plot and the table show the same pairs.
///
/// Model-adaptive tables print `model_error` instead of `estimate`; when the thesis has that
/// column it is plotted too, against tribo's `model_error` quantity.
pub(super) fn convergence_curves(run: &RunResult, thesis: &ThesisTable) -> Vec<Curve> {
    let tribo_label = if pairs_previous_estimate(run, thesis) {
        "tribo η of the solve before (as printed)"
    } else {
        "tribo η"
    };
    let mut curves = vec![
        Curve {
            label: tribo_label.into(),
            color: TRIBO,
            dashed: false,
            points: run
                .rows
                .iter()
                .enumerate()
                .filter_map(|(i, r)| {
                    let estimate = if pairs_previous_estimate(run, thesis) {
                        compared_value(&run.rows, i, "estimate")?
                    } else {
                        r.estimate()?
                    };
                    Some((r.value("dofs")?, estimate))
                })
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
    curves
}

/// Whether the convergence plot draws tribo's `estimate_previous_mesh` (the fluid tables
/// compared with printed rows) instead of its estimate on each mesh (every other run, and a
/// fluid scene without printed rows, which is compared with nothing).
fn pairs_previous_estimate(run: &RunResult, thesis: &ThesisTable) -> bool {
    compares_previous_estimate(run) && !thesis.is_empty()
}

/// The slope −1/2 guide under every point of `curves`: c = min y·√x, drawn at 0.6·c/√x; none
/// for fewer than two points.
fn slope_guide(curves: &[Curve]) -> Vec<(f64, f64)> {
    let all: Vec<(f64, f64)> = curves
        .iter()
        .flat_map(|c| c.points.iter().copied())
        .collect();
    let guide = all
        .iter()
        .map(|(x, y)| y * x.sqrt())
        .fold(f64::INFINITY, f64::min);
    if guide.is_finite() && all.len() > 1 {
        let (a, b) = log_range(all.iter().map(|p| p.0));
        let (a, b) = (a * 1.1, b / 1.1);
        vec![(a, 0.6 * guide / a.sqrt()), (b, 0.6 * guide / b.sqrt())]
    } else {
        Vec::new()
    }
}

/// Cost of accuracy of a model-adaptive scene (`<table>.cost.csv`): per variant (z, Signorini on
/// every face, III.2, III.3) the energy distance to the all-Signorini solution and the true
/// penetration against the cumulative solve seconds over the cycles, log–log. The all-Signorini
/// variant is the reference (distance 0) and appears in the penetration panel only.
pub fn accuracy(path: &Path, run: &RunResult) -> io::Result<Placed> {
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
    // Two charts, one above the other: side by side they would be shrunk to half their size on
    // the page.
    let (distance, penetration) = (panel(|c| c.energy_distance), panel(|c| c.penetration));
    let none: (&[(f64, f64)], &str) = (&[], "");
    let upper = log_log_height(&distance, none);
    let mut svg = String::new();
    let mut placed = Placed::default();
    {
        let size = (760, upper + log_log_height(&penetration, none));
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        let (top, bottom) = root.split_vertically(upper);
        placed.extend(log_log_chart(
            &top,
            &format!("{} — accuracy: energy distance to all-Signorini", run.table),
            ("cumulative solve seconds", "‖s − s_S‖_a / ‖s_S‖_a"),
            &distance,
            none,
            "no positive distances",
        )?);
        placed.extend(log_log_chart(
            &bottom,
            &format!("{} — true penetration into the obstacle", run.table),
            ("cumulative solve seconds", "penetration"),
            &penetration,
            none,
            "no penetration",
        )?);
        root.present().map_err(plot_err)?;
    }
    crate::fsio::write(path, svg)?;
    Ok(placed)
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
pub fn cost(path: &Path, run: &RunResult) -> io::Result<Placed> {
    let cumulative = run.cumulative_seconds();
    let points: Vec<(f64, f64, usize)> = run
        .rows
        .iter()
        .zip(&cumulative)
        .filter_map(|(r, t)| Some((*t, r.estimate()?, r.dofs()?)))
        .filter(|(t, e, _)| loggable(&(*t, *e)))
        .collect();

    let phases: Vec<Entry> = PHASES
        .iter()
        .map(|(name, color)| Entry::new(*name, Swatch::Bar(*color)))
        .collect();
    let curves = true_error_curves(run);
    let none: (&[(f64, f64)], &str) = (&[], "");
    let upper = if curves.is_empty() {
        420
    } else {
        log_log_height(&curves, none)
    };
    let mut svg = String::new();
    let mut placed = Placed::default();
    {
        let size = (760, upper + 300 + legend::height(&phases, 760));
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let (top, bottom) = root.split_vertically(upper);
        if curves.is_empty() {
            placed.extend(cost_accuracy(
                &top,
                &run.table,
                &super::estimate_name(run).axis,
                &points,
            )?);
        } else {
            placed.extend(log_log_chart(
                &top,
                &format!("{} — cost of accuracy: true error", run.table),
                ("cumulative wall seconds", "error, estimate"),
                &curves,
                none,
                "no positive errors and timings",
            )?);
        }
        let (bars, strip) = legend::split(&bottom, &phases);
        placed.extend(phase_bars(&bars, run)?);
        placed.legends.extend(legend::draw(&strip, &phases)?);
        root.present().map_err(plot_err)?;
    }
    crate::fsio::write(path, svg)?;
    Ok(placed)
}

/// The upper panel of [`cost`] where the run has a true error (`crate::study::accuracy`): the
/// adaptive run's error and estimate against its cumulative wall seconds, and the uniform run's
/// error against its own cumulative seconds (`crate::study::uniform`). Empty without errors.
/// The thesis prints no timings, so its estimates have no place on this axis.
fn true_error_curves(run: &RunResult) -> Vec<Curve> {
    let cumulative = run.cumulative_seconds();
    let adaptive = |column: &str| -> Vec<(f64, f64)> {
        run.rows
            .iter()
            .zip(&cumulative)
            .filter_map(|(r, t)| Some((*t, r.value(column)?)))
            .filter(loggable)
            .collect()
    };
    let error = adaptive(crate::results::columns::ERROR);
    if error.is_empty() {
        return Vec::new();
    }
    let mut seconds = 0.0;
    let uniform: Vec<(f64, f64)> = run
        .uniform
        .iter()
        .filter_map(|u| {
            seconds += u.seconds;
            Some((seconds, u.error?))
        })
        .filter(loggable)
        .collect();
    let mut curves = vec![
        Curve {
            label: "adaptive: true error".into(),
            color: TRIBO,
            dashed: false,
            points: error,
        },
        Curve {
            label: "adaptive: estimate η".into(),
            color: TRIBO,
            dashed: true,
            points: adaptive(crate::results::columns::ESTIMATE),
        },
    ];
    if !uniform.is_empty() {
        curves.push(Curve {
            label: "uniform refinement: true error".into(),
            color: RGBColor(0, 0, 0),
            dashed: false,
            points: uniform,
        });
    }
    curves
}

/// Upper panel of [`cost`].
fn cost_accuracy(
    area: &DrawingArea<SVGBackend, Shift>,
    table: &str,
    estimate: &str,
    points: &[(f64, f64, usize)],
) -> io::Result<Placed> {
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
        return Ok(Placed::default());
    }
    chart
        .draw_series(LineSeries::new(
            points.iter().map(|p| (p.0, p.1)),
            TRIBO.stroke_width(2),
        ))
        .map_err(plot_err)?;
    chart
        .draw_series(
            points
                .iter()
                .map(|&(t, e, _)| Circle::new((t, e), 3, TRIBO.filled())),
        )
        .map_err(plot_err)?;
    let pixels = legend::pixels(&chart, points.iter().map(|p| (p.0, p.1)));
    let labels: Vec<String> = points.iter().map(|p| format!("{} dofs", p.2)).collect();
    let boxes = label_boxes(&pixels, &labels);
    let label_font = ("sans-serif", 14).into_font().color(&BLACK);
    let (x0, y0) = area.get_base_pixel();
    for (label, b) in labels.into_iter().zip(&boxes) {
        if let Some((left, top, ..)) = b {
            area.draw(&Text::new(label, (left - x0, top - y0), label_font.clone()))
                .map_err(plot_err)?;
        }
    }
    // The dofs labels are checked like legends: no point under them.
    Ok(Placed {
        points: pixels,
        legends: boxes.into_iter().flatten().collect(),
    })
}

/// Where the dofs labels of the cost plot go: above right of their points, each one only where
/// it covers no other point and no label already placed, from the last point back (so the
/// largest mesh is always named). Crowded points, as the last cycles of a stalling run, would
/// otherwise print their labels over each other. `None` for a label left out.
pub(super) fn label_boxes(
    pixels: &[(i32, i32)],
    labels: &[String],
) -> Vec<Option<legend::PixelBox>> {
    // 14 (plotters' size) is about 11.3 px; 0.6 em per character.
    let (height, per_char) = (12, 6.8);
    let mut boxes: Vec<Option<legend::PixelBox>> = vec![None; pixels.len()];
    for i in (0..pixels.len()).rev() {
        let (x, y) = pixels[i];
        let width = (labels[i].chars().count() as f64 * per_char).ceil() as i32;
        let b = (x + 6, y - 14, x + 6 + width, y - 14 + height);
        let hits = |&(l, t, r, bottom): &legend::PixelBox| {
            l <= b.2 + 2 && b.0 <= r + 2 && t <= b.3 + 2 && b.1 <= bottom + 2
        };
        let covers = pixels
            .iter()
            .any(|&(px, py)| px >= b.0 - 3 && px <= b.2 + 3 && py >= b.1 - 3 && py <= b.3 + 3);
        if !covers && !boxes.iter().flatten().any(hits) {
            boxes[i] = Some(b);
        }
    }
    boxes
}

/// Lower panel of [`cost`]: stacked bars of the phase seconds, one bar per printed cycle (the
/// legend of the phases is under it). The points placed are the bars' corners.
fn phase_bars(area: &DrawingArea<SVGBackend, Shift>, run: &RunResult) -> io::Result<Placed> {
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
        .margin_right(RIGHT_MARGIN)
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
    let mut corners = Vec::new();
    for (p, (_, color)) in PHASES.iter().enumerate() {
        let bars: Vec<Rectangle<(f64, f64)>> = run
            .rows
            .iter()
            .enumerate()
            .map(|(i, r)| {
                let s = r.seconds.named();
                let below: f64 = s[..p].iter().map(|(_, v)| finite(*v)).sum();
                let x = i as f64;
                let corner = [(x - 0.35, below), (x + 0.35, below + finite(s[p].1))];
                corners.extend(corner);
                Rectangle::new(corner, color.filled())
            })
            .collect();
        chart.draw_series(bars).map_err(plot_err)?;
    }
    Ok(Placed {
        points: legend::pixels(&chart, corners),
        ..Placed::default()
    })
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
            convergence_caption(run, at.thesis, &at.eta.caption),
        );
        convergence(&path, run, at.thesis)?;
        Ok(vec![figure])
    }
}

/// The caption of the convergence plot ([`convergence_curves`]): which estimate of tribo's it
/// draws, and the thesis only where a printed curve is drawn.
pub(super) fn convergence_caption(run: &RunResult, thesis: &ThesisTable, eta: &str) -> String {
    let curves = convergence_curves(run, thesis);
    let what = if !curves.iter().any(|c| c.dashed) {
        "tribo's, with a slope −1/2 guide".to_string()
    } else if pairs_previous_estimate(run, thesis) {
        "tribo's estimate of the solve before each printed mesh (estimate_previous_mesh) at that \
         mesh's degrees of freedom, the pairs the thesis prints and the table compares (solid), \
         and the thesis (dashed)"
            .to_string()
    } else {
        "tribo (solid) and the thesis (dashed)".to_string()
    };
    format!(
        "{}: {eta} against the degrees of freedom, log–log: {what}",
        run.table
    )
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
        let caption = if true_error_curves(run).is_empty() {
            format!(
                "{}: cost of accuracy — {} against the cumulative wall seconds, and the \
                 seconds per phase",
                run.table, at.eta.caption
            )
        } else {
            format!(
                "{}: cost of accuracy — the true error (and {}) against the cumulative wall \
                 seconds, of the adaptive run{}, and the seconds per phase",
                run.table,
                at.eta.caption,
                if run.uniform.is_empty() {
                    ""
                } else {
                    " and of uniform refinement"
                }
            )
        };
        let (figure, path) = at.figure("cost", caption);
        cost(&path, run)?;
        Ok(vec![figure])
    }
}
