//! The figures of the report, one SVG file each.
//!
//! Line and log plots (convergence, cost of accuracy) go through `plotters`' SVG backend. Mesh,
//! deformed-body and field pictures are written as SVG text directly: they hold up to hundreds of
//! thousands of cells, and one `<path>` per picture (or per colour) with integer coordinates is
//! orders of magnitude smaller and faster than one plotters element per cell.
//!
//! Every function here tolerates degenerate data — no rows, a single row, zero, negative or NaN
//! values on a log axis — by skipping what cannot be drawn and saying so in the figure; it returns
//! an `io::Error` only when the file cannot be written.

use std::collections::HashSet;
use std::fmt::Write as _;
use std::fs;
use std::io;
use std::path::Path;

use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

use super::html::{escape, fmt_short};
use super::MAX_SHOWN_THESIS_ROWS;
use crate::results::{
    columns, Arrow, CellBox, DeformedPicture, FieldPicture, MeshPicture, PartitionPicture,
    RunResult,
};
use crate::thesis::ThesisTable;

/// Turn a plotters error into an `io::Error` (plotters' SVG backend draws into a `String`, so
/// these are layout errors, not file errors).
pub(super) fn plot_err<E: std::fmt::Debug>(e: E) -> io::Error {
    io::Error::other(format!("plotting failed: {e:?}"))
}

/// Grid, tick labels (1, 2, 5 × 10^k) and axis descriptions of a log–log chart.
fn log_log_grid<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<NiceLog, NiceLog>>,
    x_desc: &str,
    y_desc: &str,
) -> io::Result<()> {
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_labels(12)
        .y_labels(12)
        .x_label_formatter(&log_tick)
        .y_label_formatter(&log_tick)
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(205, 205, 205))
        .label_style(("sans-serif", 17))
        .axis_desc_style(("sans-serif", 17))
        .draw()
        .map_err(plot_err)?;
    Ok(())
}

/// A log–log chart on `area`: the caption, the axes of the ranges `x` and `y` (margin 12,
/// `x_label_area` pixels under the axis, 70 left of it) and the grid ([`log_log_grid`]).
fn log_log_axes<'a, DB: DrawingBackend + 'a>(
    area: &'a DrawingArea<DB, Shift>,
    (caption, caption_size): (&str, u32),
    x_label_area: u32,
    (x, y): ((f64, f64), (f64, f64)),
    (x_desc, y_desc): (&str, &str),
) -> io::Result<ChartContext<'a, DB, Cartesian2d<NiceLog, NiceLog>>> {
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", caption_size))
        .margin(12)
        .x_label_area_size(x_label_area)
        .y_label_area_size(70)
        .build_cartesian_2d(NiceLog::new(x), NiceLog::new(y))
        .map_err(plot_err)?;
    log_log_grid(&mut chart, x_desc, y_desc)?;
    Ok(chart)
}

/// The note in place of a chart with nothing to draw, at `at` (pixels) on `area`.
fn empty_note<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
    at: (i32, i32),
) -> io::Result<()> {
    area.draw(&Text::new(
        text,
        at,
        ("sans-serif", 18).into_font().color(&GUIDE),
    ))
    .map_err(plot_err)
}

/// A point that can sit on a log–log axis.
pub(super) fn loggable(p: &(f64, f64)) -> bool {
    p.0.is_finite() && p.1.is_finite() && p.0 > 0.0 && p.1 > 0.0
}

/// A log-axis range around the given positive values, padded so markers do not sit on the frame;
/// a single value (or none) still gives a non-empty range.
pub(super) fn log_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, 0.0_f64), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if hi <= 0.0 {
        return (1.0, 10.0);
    }
    let pad = ((hi / lo).powf(0.06)).max(1.25);
    (lo / pad, hi * pad)
}

/// A logarithmic axis with ticks at 1, 2, 5 × 10^k.
///
/// plotters' own log axis starts its ticks at the first power of ten inside the range (computed
/// through a rounding-prone `ln`), so a range like 0.11–0.8 gets no labels at all, and its
/// minor ticks repeat each power of ten, printing those labels twice. This axis enumerates the
/// decades itself: labelled ticks at mantissas 1, 2, 5 (or 1 only, or every few decades, as space
/// allows), grid lines at every integer mantissa.
#[derive(Clone)]
pub(super) struct NiceLog {
    lo: f64,
    hi: f64,
}

impl NiceLog {
    pub(super) fn new((lo, hi): (f64, f64)) -> NiceLog {
        NiceLog { lo, hi }
    }

    /// All values m·10^k in the range, m from `mantissas`, every `step`-th decade.
    fn ticks(&self, mantissas: &[f64], step: i32) -> Vec<f64> {
        let (k0, k1) = (
            self.lo.log10().floor() as i32 - 1,
            self.hi.log10().ceil() as i32 + 1,
        );
        let mut out = Vec::new();
        for k in (k0..=k1).filter(|k| k.rem_euclid(step) == 0) {
            for m in mantissas {
                let v = m * 10f64.powi(k);
                if v >= self.lo * (1.0 - 1e-9) && v <= self.hi * (1.0 + 1e-9) {
                    out.push(v);
                }
            }
        }
        out
    }
}

impl Ranged for NiceLog {
    type FormatOption = plotters::coord::ranged1d::DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        let t = (value.ln() - self.lo.ln()) / (self.hi.ln() - self.lo.ln());
        // Clamped, so a stray non-positive value maps off-canvas instead of overflowing.
        let t = if t.is_nan() {
            -10.0
        } else {
            t.clamp(-10.0, 10.0)
        };
        limit.0 + (f64::from(limit.1 - limit.0) * t).round() as i32
    }

    fn key_points<H: plotters::coord::ranged1d::KeyPointHint>(&self, hint: H) -> Vec<f64> {
        let max = hint.max_num_points().max(2);
        let all: Vec<f64> = (1..=9).map(f64::from).collect();
        let candidates: [&[f64]; 3] = match hint.weight() {
            plotters::coord::ranged1d::KeyPointWeight::Bold => [&[1.0, 2.0, 5.0], &[1.0], &[1.0]],
            plotters::coord::ranged1d::KeyPointWeight::Any => [&all, &[1.0, 2.0, 5.0], &[1.0]],
        };
        let decades = (self.hi / self.lo).log10().ceil().max(1.0) as usize;
        for m in candidates {
            let t = self.ticks(m, 1);
            // Grid lines at every mantissa only while a decade is wide enough to show them.
            let too_dense = m.len() == 9 && decades > 3;
            if t.len() <= max && !too_dense && (t.len() >= 2 || m.len() == 9) {
                return t;
            }
        }
        // Many decades: every `step`-th power of ten.
        // Both ends may carry a tick, hence `max − 1` intervals.
        let step = decades.div_ceil(max.saturating_sub(1).max(1)).max(1) as i32;
        self.ticks(&[1.0], step)
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.lo..self.hi
    }
}

/// Tick label for a log axis: plain numbers in the human range, `1e5` style beyond it.
pub(super) fn log_tick(v: &f64) -> String {
    let a = v.abs();
    if a == 0.0 || !a.is_finite() {
        return String::new();
    }
    if (1e-2..1e4).contains(&a) {
        let s = format!("{v:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        let s = format!("{v:.0e}");
        s.replace(".0e", "e")
    }
}

const TRIBO: RGBColor = RGBColor(31, 119, 180);
const THESIS: RGBColor = RGBColor(214, 39, 40);
pub(super) const TRIBO_ME: RGBColor = RGBColor(44, 160, 44);
const THESIS_ME: RGBColor = RGBColor(148, 103, 189);
pub(super) const GUIDE: RGBColor = RGBColor(120, 120, 120);

/// One curve of a chart (the convergence plot, the per-step chart of a load-step run).
pub(super) struct Curve {
    pub label: String,
    pub color: RGBColor,
    pub dashed: bool,
    pub points: Vec<(f64, f64)>,
}

/// (x, y) pairs of two thesis columns, in printed order, skipping rows without both; only the
/// first [`MAX_SHOWN_THESIS_ROWS`] rows, as in the section's table.
fn thesis_pairs(thesis: &ThesisTable, x: &str, y: &str) -> Vec<(f64, f64)> {
    let (Some(cx), Some(cy)) = (
        thesis.columns.iter().position(|c| c == x),
        thesis.columns.iter().position(|c| c == y),
    ) else {
        return Vec::new();
    };
    thesis
        .rows
        .iter()
        .take(MAX_SHOWN_THESIS_ROWS)
        .filter_map(|r| Some((*r.get(cx)?, *r.get(cy)?)))
        .filter(loggable)
        .collect()
}

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

/// Write one 760×520 [`log_log_chart`] as an SVG file.
pub(super) fn write_log_log(
    path: &Path,
    title: &str,
    labels: (&str, &str),
    curves: &[Curve],
    guide: (&[(f64, f64)], &str),
    empty: &str,
) -> io::Result<()> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (760, 520)).into_drawing_area();
        log_log_chart(&root, title, labels, curves, guide, empty)?;
        root.present().map_err(plot_err)?;
    }
    fs::write(path, svg)
}

/// A log–log chart of `curves` (solid with dots, or dashed with hollow triangles) on `root`
/// (760×520 pixels) with an optional dashed grey guide line, a legend, and `empty` written where
/// there is nothing to draw.
fn log_log_chart(
    root: &DrawingArea<SVGBackend<'_>, Shift>,
    title: &str,
    (x_label, y_label): (&str, &str),
    curves: &[Curve],
    (guide_pts, guide_label): (&[(f64, f64)], &str),
    empty: &str,
) -> io::Result<()> {
    let all: Vec<(f64, f64)> = curves
        .iter()
        .flat_map(|c| c.points.iter().copied())
        .collect();
    let (x_lo, x_hi) = log_range(all.iter().map(|p| p.0));
    let (y_lo, y_hi) = log_range(all.iter().chain(guide_pts).map(|p| p.1));
    root.fill(&WHITE).map_err(plot_err)?;
    let mut chart = log_log_axes(
        root,
        (title, 24),
        48,
        ((x_lo, x_hi), (y_lo, y_hi)),
        (x_label, y_label),
    )?;

    if curves.is_empty() {
        empty_note(root, empty, (280, 250))?;
    }
    if !guide_pts.is_empty() {
        let style = GUIDE.stroke_width(1);
        chart
            .draw_series(DashedLineSeries::new(guide_pts.to_vec(), 2, 4, style))
            .map_err(plot_err)?
            .label(guide_label)
            .legend(move |(x, y)| DashedPathElement::new(vec![(x, y), (x + 22, y)], 2, 4, style));
    }
    for c in curves {
        let style = c.color.stroke_width(2);
        let color = c.color;
        if c.dashed {
            chart
                .draw_series(DashedLineSeries::new(c.points.clone(), 7, 4, style))
                .map_err(plot_err)?
                .label(c.label.as_str())
                .legend(move |(x, y)| {
                    DashedPathElement::new(vec![(x, y), (x + 22, y)], 7, 4, style)
                });
            // Hollow triangles, so thesis markers stay visible under coinciding tribo ones.
            chart
                .draw_series(
                    c.points
                        .iter()
                        .map(|p| TriangleMarker::new(*p, 6, color.stroke_width(2))),
                )
                .map_err(plot_err)?;
        } else {
            solid_curve(&mut chart, c, &[&c.points])?;
        }
    }
    if !curves.is_empty() {
        series_legend(&mut chart, SeriesLabelPosition::UpperRight, 16)?;
    }
    Ok(())
}

/// A solid curve: a line through each of `runs` (pieces of the curve's points; the legend
/// entry is the first piece's) and a dot at every point of the curve.
pub(super) fn solid_curve<X, Y>(
    chart: &mut ChartContext<'_, SVGBackend<'_>, Cartesian2d<X, Y>>,
    c: &Curve,
    runs: &[&[(f64, f64)]],
) -> io::Result<()>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let style = c.color.stroke_width(2);
    for (k, run) in runs.iter().enumerate() {
        let series = chart
            .draw_series(LineSeries::new(run.iter().copied(), style))
            .map_err(plot_err)?;
        if k == 0 {
            series
                .label(c.label.as_str())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 22, y)], style));
        }
    }
    let color = c.color;
    chart
        .draw_series(c.points.iter().map(|p| Circle::new(*p, 3, color.filled())))
        .map_err(plot_err)?;
    Ok(())
}

/// The legend of a chart's labelled series: a framed, nearly opaque box at `position`.
pub(super) fn series_legend<'a, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
    font_size: u32,
) -> io::Result<()> {
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.9))
        .border_style(RGBColor(160, 160, 160))
        .label_font(("sans-serif", font_size))
        .draw()
        .map_err(plot_err)?;
    Ok(())
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
        crate::study::cost::VARIANTS
            .iter()
            .zip(COLORS)
            .map(|(variant, color)| {
                let mut seconds = 0.0;
                let points = run
                    .costs
                    .iter()
                    .filter(|c| c.variant == *variant)
                    .map(|c| {
                        seconds += c.seconds_solve;
                        (seconds, measure(c))
                    })
                    .filter(loggable)
                    .collect();
                Curve {
                    label: (*variant).to_string(),
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
    fs::write(path, svg)
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
    fs::write(path, svg)
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

// ---------------------------------------------------------------------------------------------
// Hand-written SVG pictures.
// ---------------------------------------------------------------------------------------------

/// Sub-pixel units per pixel for picture coordinates. Coordinates are written as integers in these
/// units inside a `scale(0.1)` group: one decimal of pixel precision without decimal points.
const SUB: f64 = 10.0;

/// Maps a rectangle of the domain onto a pixel rectangle, y pointing up in the domain and down in
/// the SVG. Integer output is in [`SUB`] units.
#[derive(Clone, Copy)]
pub(super) struct Frame {
    /// Domain window `[x0, x1, y0, y1]`.
    win: [f64; 4],
    /// Pixel origin (left, top) and pixels per domain unit.
    left: f64,
    top: f64,
    scale: f64,
}

impl Frame {
    /// A frame showing `win` with `width` pixels, keeping the aspect ratio.
    fn new(win: [f64; 4], left: f64, top: f64, width: f64) -> Frame {
        Frame {
            win,
            left,
            top,
            scale: width / (win[1] - win[0]),
        }
    }
    fn width(&self) -> f64 {
        (self.win[1] - self.win[0]) * self.scale
    }
    fn height(&self) -> f64 {
        (self.win[3] - self.win[2]) * self.scale
    }
    /// Pixel x of a domain x.
    fn px(&self, x: f64) -> f64 {
        self.left + (x - self.win[0]) * self.scale
    }
    /// Pixel y of a domain y.
    fn py(&self, y: f64) -> f64 {
        self.top + (self.win[3] - y) * self.scale
    }
    /// Integer sub-pixel coordinates of a domain point.
    fn sub(&self, x: f64, y: f64) -> (i64, i64) {
        (
            (self.px(x) * SUB).round() as i64,
            (self.py(y) * SUB).round() as i64,
        )
    }
    fn intersects(&self, c: &CellBox) -> bool {
        c.x1 >= self.win[0] && c.x0 <= self.win[1] && c.y1 >= self.win[2] && c.y0 <= self.win[3]
    }
}

fn finite_box(c: &CellBox) -> bool {
    c.x0.is_finite() && c.x1.is_finite() && c.y0.is_finite() && c.y1.is_finite()
}

/// Bounding box `[x0, x1, y0, y1]` of finite points, `None` if there are none or it has no area.
pub(super) fn bbox(points: impl Iterator<Item = (f64, f64)>) -> Option<[f64; 4]> {
    let mut b = [
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ];
    for (x, y) in points.filter(|(x, y)| x.is_finite() && y.is_finite()) {
        b = [b[0].min(x), b[1].max(x), b[2].min(y), b[3].max(y)];
    }
    (b[1] > b[0] && b[3] > b[2]).then_some(b)
}

/// The domain box to draw: the run's domain when it is a proper box, otherwise the cells' extent.
fn picture_window<'a>(
    domain: [f64; 4],
    cells: impl Iterator<Item = &'a CellBox>,
) -> Option<[f64; 4]> {
    let d = domain;
    if d.iter().all(|v| v.is_finite()) && d[1] > d[0] && d[3] > d[2] {
        return Some(d);
    }
    bbox(
        cells
            .filter(|c| finite_box(c))
            .flat_map(|c| [(c.x0, c.y0), (c.x1, c.y1)]),
    )
}

/// A box in sub-pixel units `(x0, top, x1, bottom)`.
type SubBox = (i64, i64, i64, i64);

/// A cell's box in sub-pixel units `(x0, top, x1, bottom)`.
///
/// Cells narrower or lower than a pixel are snapped to the pixel grid they fall in: at that size
/// they only darken (mesh) or colour (field) the pixel anyway, and snapped boxes repeat, so the
/// callers' de-duplication bounds the SVG by the picture's pixel count instead of the cell count.
fn sub_box(c: &CellBox, f: &Frame) -> (i64, i64, i64, i64) {
    let (mut x0, mut top) = f.sub(c.x0, c.y1);
    let (mut x1, mut bottom) = f.sub(c.x1, c.y0);
    let px = SUB as i64;
    if x1 - x0 < px {
        x0 = x0.div_euclid(px) * px;
        x1 = x0 + px;
    }
    if bottom - top < px {
        top = top.div_euclid(px) * px;
        bottom = top + px;
    }
    (x0, top, x1, bottom)
}

/// Merge collinear segments `(line, from, to)` that overlap or touch, in place.
fn merge_segments(segs: &mut Vec<(i64, i64, i64)>) {
    segs.sort_unstable();
    let mut out: Vec<(i64, i64, i64)> = Vec::with_capacity(segs.len() / 4 + 1);
    for &(line, a, b) in segs.iter() {
        match out.last_mut() {
            Some(last) if last.0 == line && a <= last.2 => last.2 = last.2.max(b),
            _ => out.push((line, a, b)),
        }
    }
    *segs = out;
}

/// Outline path of the cells, in sub-pixel units.
///
/// Each cell contributes only its top and right edge: every interior edge of a quadtree mesh (with
/// hanging nodes too) is part of the top or right edge of the cell below or left of it; the caller
/// draws the window frame for the remaining left and bottom boundary. The edges are then merged
/// into maximal horizontal and vertical lines, so a uniform n × n patch costs 2n segments rather
/// than n² — the SVG grows with the picture's resolution, not with the mesh.
fn outline_path<'a>(cells: impl Iterator<Item = &'a CellBox>, f: &Frame) -> String {
    let mut horizontal = Vec::new();
    let mut vertical = Vec::new();
    for c in cells.filter(|c| finite_box(c) && f.intersects(c)) {
        let (x0, top, x1, bottom) = sub_box(c, f);
        horizontal.push((top, x0, x1));
        vertical.push((x1, top, bottom));
    }
    merge_segments(&mut horizontal);
    merge_segments(&mut vertical);
    let mut d = String::new();
    for (y, a, b) in horizontal {
        let _ = write!(d, "M{a} {y}h{}", b - a);
    }
    for (x, a, b) in vertical {
        let _ = write!(d, "M{x} {a}v{}", b - a);
    }
    d
}

/// Filled rectangles `(x0, top, x1, bottom)` in sub-pixel units, de-duplicated against `seen` by
/// the caller and merged here into horizontal runs: neighbouring cells of one colour in a row
/// become one rectangle.
fn rects_path(mut boxes: Vec<(i64, i64, i64, i64)>) -> String {
    boxes.sort_unstable_by_key(|&(x0, top, _, bottom)| (top, bottom, x0));
    let mut d = String::new();
    let mut run: Option<(i64, i64, i64, i64)> = None;
    let mut emit = |r: (i64, i64, i64, i64)| {
        let (x0, top, x1, bottom) = r;
        let _ = write!(d, "M{x0} {top}h{}v{}h{}z", x1 - x0, bottom - top, x0 - x1);
    };
    for b in boxes {
        run = match run {
            Some(r) if r.1 == b.1 && r.3 == b.3 && b.0 <= r.2 => {
                Some((r.0, r.1, r.2.max(b.2), r.3))
            }
            Some(r) => {
                emit(r);
                Some(b)
            }
            None => Some(b),
        };
    }
    if let Some(r) = run {
        emit(r);
    }
    d
}

/// Closed rectangles of the cells (for fills), in sub-pixel units.
fn rect_path<'a>(cells: impl Iterator<Item = &'a CellBox>, f: &Frame) -> String {
    let mut seen = HashSet::new();
    rects_path(
        cells
            .filter(|c| finite_box(c) && f.intersects(c))
            .map(|c| sub_box(c, f))
            .filter(|b| seen.insert(*b))
            .collect(),
    )
}

pub(super) fn svg_open(width: f64, height: f64) -> String {
    let (w, h) = (width.ceil(), height.ceil());
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" \
         viewBox=\"0 0 {w} {h}\" font-family=\"sans-serif\">\n\
         <rect width=\"{w}\" height=\"{h}\" fill=\"white\"/>\n"
    )
}

pub(super) fn text(svg: &mut String, x: f64, y: f64, size: f64, anchor: &str, s: &str) {
    let _ = writeln!(
        svg,
        "<text x=\"{x:.1}\" y=\"{y:.1}\" font-size=\"{size}\" text-anchor=\"{anchor}\">{}</text>",
        escape(s)
    );
}

pub(super) fn placeholder(path: &Path, title: &str, why: &str) -> io::Result<()> {
    let mut svg = svg_open(600.0, 80.0);
    text(&mut svg, 10.0, 28.0, 16.0, "start", title);
    text(&mut svg, 10.0, 58.0, 14.0, "start", why);
    svg.push_str("</svg>\n");
    fs::write(path, svg)
}

/// Width of the wide pictures (strips, deformed body) in pixels.
const WIDE: f64 = 1600.0;
/// Domains at least this many times wider than high are drawn as stacked strips.
const STRIP_ASPECT: f64 = 3.0;
const MESH_LINE: &str = "#1f3a5f";

/// Left margin in pixels of a picture with x₂ tick labels and the x₂ axis name.
pub(super) const AXIS_LEFT: f64 = 56.0;
/// Room in pixels under a picture for the x₁ tick labels and the x₁ axis name.
pub(super) const AXIS_BELOW: f64 = 34.0;

/// Round tick values inside `[lo, hi]`: the multiples of one step 1, 2 or 5 × 10^k, at most
/// `max` of them; none for an empty or non-finite range.
fn ticks(lo: f64, hi: f64, max: usize) -> Vec<f64> {
    if !(lo.is_finite() && hi.is_finite() && hi > lo) || max == 0 {
        return Vec::new();
    }
    let span = hi - lo;
    let p = 10f64.powf((span / max as f64).log10().floor());
    for m in [1.0, 2.0, 5.0, 10.0, 20.0, 50.0] {
        let step = m * p;
        let (first, last) = ((lo / step - 1e-9).ceil(), (hi / step + 1e-9).floor());
        if last - first + 1.0 <= max as f64 {
            return (first as i64..=last as i64)
                .map(|k| k as f64 * step)
                // −0 and rounding noise around 0 print as 0.
                .map(|v| if v.abs() < 1e-9 * span { 0.0 } else { v })
                .collect();
        }
    }
    Vec::new()
}

/// The x₁ and x₂ axes of the picture frame `f`, in domain coordinates: round ticks with labels
/// under the bottom edge and left of the left edge, and the axis names x₁ (under the ticks) and
/// x₂ (left of them). Needs [`AXIS_BELOW`] pixels under the frame and [`AXIS_LEFT`] left of it.
pub(super) fn axes(svg: &mut String, f: &Frame) {
    let (l, t, w, h) = (f.left, f.top, f.width(), f.height());
    let b = t + h;
    let mut d = String::new();
    let _ = writeln!(svg, "<g class=\"axes\">");
    let xs = ticks(f.win[0], f.win[1], ((w / 70.0) as usize).clamp(2, 16));
    for x in xs {
        let px = f.px(x);
        let _ = write!(d, "M{px:.1} {b:.1}v4");
        text(svg, px, b + 15.0, 11.0, "middle", &fmt_short(x));
    }
    let ys = ticks(f.win[2], f.win[3], ((h / 24.0) as usize).clamp(2, 10));
    for y in ys {
        let py = f.py(y);
        let _ = write!(d, "M{l:.1} {py:.1}h-4");
        text(svg, l - 6.0, py + 4.0, 11.0, "end", &fmt_short(y));
    }
    let _ = writeln!(
        svg,
        "<path d=\"{d}\" stroke=\"#444\" stroke-width=\"1\" fill=\"none\"/>"
    );
    text(svg, l + 0.5 * w, b + 29.0, 12.0, "middle", "x₁");
    text(
        svg,
        l - AXIS_LEFT + 8.0,
        t + 0.5 * h + 4.0,
        12.0,
        "start",
        "x₂",
    );
    svg.push_str("</g>\n");
}

/// Width in pixels below which a mesh picture leaves out a cell's edges: its colour shows its
/// level, and edges that close would only turn the region into a dark block.
const EDGE_MIN_PX: f64 = 2.0;

/// Sequential palette of the refinement levels, light (coarse) to blue (fine); dark enough for
/// contrast at the fine end, light enough for the cell edges to stay visible.
const LEVEL_STOPS: [(f64, f64, f64); 7] = [
    (255.0, 255.0, 217.0),
    (237.0, 248.0, 177.0),
    (199.0, 233.0, 180.0),
    (127.0, 205.0, 187.0),
    (65.0, 182.0, 196.0),
    (29.0, 145.0, 192.0),
    (34.0, 94.0, 168.0),
];

/// The fill of refinement level `level` when the picture shows the levels `range` (inclusive):
/// the coarsest is the lightest colour of [`LEVEL_STOPS`], the finest the darkest.
fn level_color(level: u8, range: (u8, u8)) -> String {
    let t = if range.1 > range.0 {
        f64::from(level.saturating_sub(range.0)) / f64::from(range.1 - range.0)
    } else {
        0.4
    };
    let s = t.clamp(0.0, 1.0) * (LEVEL_STOPS.len() - 1) as f64;
    let i = (s.floor() as usize).min(LEVEL_STOPS.len() - 2);
    let u = s - i as f64;
    let (a, b) = (LEVEL_STOPS[i], LEVEL_STOPS[i + 1]);
    let mix = |p: f64, q: f64| (p + u * (q - p)).round() as u8;
    format!(
        "#{:02x}{:02x}{:02x}",
        mix(a.0, b.0),
        mix(a.1, b.1),
        mix(a.2, b.2)
    )
}

/// The refinement level of every cell of `m`: the recorded [`MeshPicture::levels`], or, when
/// they are missing or do not match the cells, the number of halvings from `coarsest` (the
/// width of the largest cell of the figure) to the cell's width.
fn cell_levels(m: &MeshPicture, coarsest: f64) -> Vec<u8> {
    if m.levels.len() == m.cells.len() {
        return m.levels.clone();
    }
    m.cells
        .iter()
        .map(|c| {
            let l = (coarsest / (c.x1 - c.x0)).log2().round();
            if l.is_finite() {
                l.clamp(0.0, 255.0) as u8
            } else {
                0
            }
        })
        .collect()
}

/// One mesh inside frame `f`, framed by the window boundary: every cell filled with the colour
/// of its refinement level ([`level_color`] over `range`), one `<path class="level-k">` per
/// level, and the cell edges of the cells at least [`EDGE_MIN_PX`] wide on top. Where snapped
/// sub-pixel cells share a pixel, the finest level colours it.
fn draw_mesh_levels(
    svg: &mut String,
    cells: &[CellBox],
    levels: &[u8],
    range: (u8, u8),
    f: &Frame,
    clip_id: &str,
) {
    let (l, t, w, h) = (f.left, f.top, f.width(), f.height());
    let mut order: Vec<usize> = (0..cells.len().min(levels.len()))
        .filter(|&i| finite_box(&cells[i]) && f.intersects(&cells[i]))
        .collect();
    order.sort_by_key(|&i| std::cmp::Reverse(levels[i]));
    let mut by_level: Vec<(u8, Vec<SubBox>)> = Vec::new();
    let mut seen = HashSet::new();
    for i in order {
        let b = sub_box(&cells[i], f);
        if !seen.insert(b) {
            continue;
        }
        match by_level.last_mut() {
            Some((k, boxes)) if *k == levels[i] => boxes.push(b),
            _ => by_level.push((levels[i], vec![b])),
        }
    }
    let _ = writeln!(
        svg,
        "<clipPath id=\"{clip_id}\"><rect x=\"{l:.1}\" y=\"{t:.1}\" width=\"{w:.1}\" height=\"{h:.1}\"/></clipPath>\n\
         <g clip-path=\"url(#{clip_id})\"><g transform=\"scale({})\">",
        1.0 / SUB
    );
    for (k, boxes) in by_level.into_iter().rev() {
        let _ = writeln!(
            svg,
            "<path class=\"level-{k}\" fill=\"{}\" shape-rendering=\"crispEdges\" d=\"{}\"/>",
            level_color(k, range),
            rects_path(boxes)
        );
    }
    let visible = cells
        .iter()
        .filter(|c| (c.x1 - c.x0).min(c.y1 - c.y0) * f.scale >= EDGE_MIN_PX);
    let _ = writeln!(
        svg,
        "<path fill=\"none\" stroke=\"{MESH_LINE}\" stroke-width=\"{}\" d=\"{}\"/></g></g>\n\
         <rect x=\"{l:.1}\" y=\"{t:.1}\" width=\"{w:.1}\" height=\"{h:.1}\" fill=\"none\" stroke=\"black\" stroke-width=\"1\"/>",
        0.5 * SUB,
        outline_path(visible, f),
    );
}

/// The legend of the refinement levels `range` at `(x, y)` (the swatches' top left corner), as
/// wide as it needs; returns its width in pixels.
fn level_legend(svg: &mut String, x: f64, y: f64, range: (u8, u8)) -> f64 {
    text(svg, x, y + 11.0, 13.0, "start", "refinement level:");
    let mut at = x + 118.0;
    for k in range.0..=range.1 {
        let _ = writeln!(
            svg,
            "<rect class=\"legend-level\" x=\"{at:.1}\" y=\"{y:.1}\" width=\"14\" height=\"14\" fill=\"{}\" stroke=\"#444\" stroke-width=\"0.5\"/>",
            level_color(k, range)
        );
        text(
            svg,
            at + 18.0,
            y + 11.0,
            12.0,
            "start",
            &format!("level {k}"),
        );
        at += 18.0 + 7.5 * format!("level {k}").len() as f64 + 10.0;
    }
    at - x
}

/// Aspect ratio (width : height) of the detail window of a strip.
const DETAIL_ASPECT: f64 = 4.0;
/// The detail window is at most this many finest-cell widths wide, so that in the detail panel
/// (about 770 pixels) the finest cells are some 8 pixels wide or more.
const DETAIL_CELLS: f64 = 96.0;

/// The zoom onto the finest cells of a mesh: the bounding box of the cells of the deepest
/// level, padded by two of their widths, widened to [`DETAIL_ASPECT`], no wider than
/// [`DETAIL_CELLS`] finest cells and inside `win`. When the deepest cells spread wider than
/// that, the window starts at the leftmost of them (at the height of the lowest there).
/// Returns the window `[x0, x1, y0, y1]`, the deepest level and the finest cells' width; `None`
/// without finite cells.
fn detail_window(cells: &[CellBox], levels: &[u8], win: [f64; 4]) -> Option<([f64; 4], u8, f64)> {
    let finite: Vec<(usize, &CellBox)> = cells
        .iter()
        .enumerate()
        .filter(|(i, c)| finite_box(c) && *i < levels.len() && c.x1 > c.x0 && c.y1 > c.y0)
        .collect();
    let deepest = finite.iter().map(|(i, _)| levels[*i]).max()?;
    let finest: Vec<&CellBox> = finite
        .iter()
        .filter(|(i, _)| levels[*i] == deepest)
        .map(|(_, c)| *c)
        .collect();
    let h = finest
        .iter()
        .map(|c| (c.x1 - c.x0).min(c.y1 - c.y0))
        .fold(f64::INFINITY, f64::min);
    let b = bbox(finest.iter().flat_map(|c| [(c.x0, c.y0), (c.x1, c.y1)]))?;
    let pad = 2.0 * h;
    let b = [b[0] - pad, b[1] + pad, b[2] - pad, b[3] + pad];
    let (bw, bh) = (b[1] - b[0], b[3] - b[2]);
    let (ww, wh) = (win[1] - win[0], win[3] - win[2]);
    let wide = bw.max(DETAIL_ASPECT * bh).min(DETAIL_CELLS * h);
    let height = (wide / DETAIL_ASPECT).min(wh);
    let width = (height * DETAIL_ASPECT).min(ww);
    let first = finest
        .iter()
        .min_by(|p, q| p.x0.total_cmp(&q.x0).then(p.y0.total_cmp(&q.y0)))?;
    let cx = if bw <= width {
        0.5 * (b[0] + b[1])
    } else {
        b[0] + 0.5 * width
    };
    let cy = if bh <= height {
        0.5 * (b[2] + b[3])
    } else {
        first.y0 - pad + 0.5 * height
    };
    let clamp = |c: f64, lo: f64, hi: f64, half: f64| {
        if hi - lo <= 2.0 * half {
            0.5 * (lo + hi)
        } else {
            c.clamp(lo + half, hi - half)
        }
    };
    let cx = clamp(cx, win[0], win[1], 0.5 * width);
    let cy = clamp(cy, win[2], win[3], 0.5 * height);
    Some((
        [
            cx - 0.5 * width,
            cx + 0.5 * width,
            cy - 0.5 * height,
            cy + 0.5 * height,
        ],
        deepest,
        h,
    ))
}

/// One mesh inside frame `f` as cell outlines, the cells `shaded` filled grey under them (the
/// SubStokes cells of a model-adaptive fluid run, thesis Fig. IV.116).
fn draw_mesh_shaded(
    svg: &mut String,
    cells: &[CellBox],
    shaded: &[CellBox],
    f: &Frame,
    clip_id: &str,
) {
    let (l, t, w, h) = (f.left, f.top, f.width(), f.height());
    let fill = if shaded.is_empty() {
        String::new()
    } else {
        format!(
            "<path transform=\"scale({})\" fill=\"#c8c8c8\" shape-rendering=\"crispEdges\" d=\"{}\"/>",
            1.0 / SUB,
            rect_path(shaded.iter(), f)
        )
    };
    let _ = writeln!(
        svg,
        "<clipPath id=\"{clip_id}\"><rect x=\"{l:.1}\" y=\"{t:.1}\" width=\"{w:.1}\" height=\"{h:.1}\"/></clipPath>\n\
         <g clip-path=\"url(#{clip_id})\">{fill}<path transform=\"scale({s})\" fill=\"none\" stroke=\"{MESH_LINE}\" \
         stroke-width=\"{sw}\" d=\"{d}\"/></g>\n\
         <rect x=\"{l:.1}\" y=\"{t:.1}\" width=\"{w:.1}\" height=\"{h:.1}\" fill=\"none\" stroke=\"black\" stroke-width=\"1\"/>",
        s = 1.0 / SUB,
        sw = 0.6 * SUB,
        d = outline_path(cells.iter(), f),
    );
}

/// Mesh pictures (thesis Fig. IV.1): every cell filled with the colour of its refinement level
/// (legend on top) under the edges of the cells wide enough to show them, x₁/x₂ axes, aspect
/// ratio kept. A mesh of hundreds of thousands of cells thus shows where it is refined instead
/// of a solid block of edges.
///
/// Thin domains (like the strip [−16,16]×[0,1]) are stacked vertically, each strip followed by a
/// detail zoomed onto its finest cells ([`detail_window`]) — at true aspect ratio the refined
/// ends of a 32:1 strip are a few pixels wide, and the detail is where the refinement pattern
/// can actually be compared with the thesis figure. Squarish domains are drawn side by side.
/// A picture with shaded cells (the SubStokes cells of Fig. IV.116) keeps white and grey cells
/// under outlines instead of the level colours.
///
/// With `partitions` (model-and-grid adaptivity), the Signorini faces of each drawn cycle are
/// thick black lines on the boundary (thesis Figs IV.46–IV.51).
pub fn meshes(
    path: &Path,
    meshes: &[MeshPicture],
    domain: [f64; 4],
    partitions: &[PartitionPicture],
) -> io::Result<()> {
    let signorini = |body: &mut String, cycle: usize, frame: &Frame| {
        let Some(p) = partitions.iter().find(|p| p.cycle == cycle) else {
            return;
        };
        for f in p.faces.iter().filter(|f| f.accurate) {
            let y = if f.side == "top" {
                domain[3]
            } else {
                domain[2]
            };
            let (a, b) = (f.x0.max(frame.win[0]), f.x1.min(frame.win[1]));
            if a < b && (frame.win[2]..=frame.win[3]).contains(&y) {
                let _ = writeln!(
                    body,
                    "<line x1=\"{:.2}\" y1=\"{:.2}\" x2=\"{:.2}\" y2=\"{:.2}\" stroke=\"#000\" \
                     stroke-width=\"4\"/>",
                    frame.px(a),
                    frame.py(y),
                    frame.px(b),
                    frame.py(y)
                );
            }
        }
    };
    let Some(win) = picture_window(domain, meshes.iter().flat_map(|m| &m.cells)) else {
        return placeholder(path, "mesh", "no cells with a finite extent to draw");
    };
    let shaded = meshes.iter().any(|m| !m.shaded.is_empty());
    let coarsest = meshes
        .iter()
        .flat_map(|m| &m.cells)
        .filter(|c| finite_box(c))
        .map(|c| c.x1 - c.x0)
        .fold(0.0f64, f64::max);
    let levels: Vec<Vec<u8>> = meshes.iter().map(|m| cell_levels(m, coarsest)).collect();
    let range = levels
        .iter()
        .flatten()
        .fold(None, |r: Option<(u8, u8)>, &k| {
            Some(r.map_or((k, k), |(a, b)| (a.min(k), b.max(k))))
        })
        .unwrap_or((0, 0));
    let draw = |body: &mut String, i: usize, f: &Frame, clip: &str| {
        let m = &meshes[i];
        if shaded {
            draw_mesh_shaded(body, &m.cells, &m.shaded, f, clip);
        } else {
            draw_mesh_levels(body, &m.cells, &levels[i], range, f, clip);
        }
        axes(body, f);
    };
    let (w, h) = (win[1] - win[0], win[3] - win[2]);
    let aspect = w / h;
    let margin = 12.0;
    let label_h = 22.0;
    let legend_h = if shaded { 0.0 } else { 26.0 };
    let mut body = String::new();
    if !shaded {
        level_legend(&mut body, margin, margin, range);
    }
    let left = margin + AXIS_LEFT;

    let (width, height) = if aspect >= STRIP_ASPECT {
        let strip_w = WIDE - left - margin;
        let detail_w = strip_w * 0.5;
        let mut y = margin + legend_h;
        for (i, m) in meshes.iter().enumerate() {
            text(
                &mut body,
                left,
                y + 15.0,
                15.0,
                "start",
                &format!("cycle {}  ({} cells)", m.cycle, m.cells.len()),
            );
            y += label_h;
            let strip = Frame::new(win, left, y, strip_w);
            draw(&mut body, i, &strip, &format!("m{i}"));
            signorini(&mut body, m.cycle, &strip);
            y += strip.height() + AXIS_BELOW + 4.0;

            if let Some((dwin, level, finest)) = detail_window(&m.cells, &levels[i], win) {
                // Mark the detail window on the strip (at least 3 pixels, so it stays visible).
                let (x0, x1) = (strip.px(dwin[0]), strip.px(dwin[1]));
                let (y0, y1) = (strip.py(dwin[3]), strip.py(dwin[2]));
                let _ = writeln!(
                    body,
                    "<rect class=\"detail-mark\" x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\" fill=\"none\" stroke=\"#d62728\" stroke-width=\"1.5\"/>",
                    x0.min(x1 - 3.0),
                    y0.min(y1 - 3.0),
                    (x1 - x0).max(3.0),
                    (y1 - y0).max(3.0)
                );
                let detail = Frame::new(dwin, left, y, detail_w);
                draw(&mut body, i, &detail, &format!("d{i}"));
                signorini(&mut body, m.cycle, &detail);
                let _ = writeln!(
                    body,
                    "<rect x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\" fill=\"none\" stroke=\"#d62728\" stroke-width=\"1.5\"/>",
                    detail.left, detail.top, detail.width(), detail.height()
                );
                text(
                    &mut body,
                    left + detail_w + 16.0,
                    y + 18.0,
                    14.0,
                    "start",
                    &format!(
                        "detail: x₁ ∈ [{}, {}], x₂ ∈ [{}, {}]",
                        fmt_short(dwin[0]),
                        fmt_short(dwin[1]),
                        fmt_short(dwin[2]),
                        fmt_short(dwin[3])
                    ),
                );
                text(
                    &mut body,
                    left + detail_w + 16.0,
                    y + 38.0,
                    14.0,
                    "start",
                    &format!(
                        "around the finest cells (level {level}, width {})",
                        fmt_short(finest)
                    ),
                );
                y += detail.height() + AXIS_BELOW;
            }
            y += 14.0;
        }
        (WIDE, y)
    } else {
        // Side by side, wrapping rows at the page width.
        let panel_h = if aspect > 1.0 { 440.0 / aspect } else { 440.0 };
        let panel_w = panel_h * aspect;
        let step_x = AXIS_LEFT + panel_w + margin;
        let step_y = label_h + panel_h + AXIS_BELOW + margin;
        let per_row = ((WIDE - margin) / step_x).floor().max(1.0) as usize;
        let cols = meshes.len().clamp(1, per_row);
        let rows = meshes.len().div_ceil(per_row).max(1);
        let top0 = margin + legend_h;
        for (i, m) in meshes.iter().enumerate() {
            let left = left + (i % per_row) as f64 * step_x;
            let top = top0 + (i / per_row) as f64 * step_y;
            text(
                &mut body,
                left,
                top + 15.0,
                15.0,
                "start",
                &format!("cycle {}  ({} cells)", m.cycle, m.cells.len()),
            );
            let f = Frame::new(win, left, top + label_h, panel_w);
            draw(&mut body, i, &f, &format!("m{i}"));
        }
        (
            (margin + cols as f64 * step_x).max(640.0),
            top0 + rows as f64 * step_y,
        )
    };
    let mut svg = svg_open(width, height);
    svg.push_str(&body);
    svg.push_str("</svg>\n");
    fs::write(path, svg)
}

/// The deformed body (thesis Fig. IV.2): displaced quadrilaterals filled light and outlined,
/// obstacles as thick polylines, the Signorini faces of a model-adaptive run as thick black
/// segments (thesis Figs IV.35–IV.51 mark them so), active contact vertices as dots.
///
/// The view is the body's extent plus a margin ([`deformed_window`]), so an obstacle curve that
/// runs far from the body is clipped instead of shrinking the body to a sliver.
pub fn deformed(path: &Path, table: &str, pic: &DeformedPicture) -> io::Result<()> {
    let title = format!(
        "{table} — deformed body after cycle {}, displacement × {}",
        pic.cycle,
        fmt_short(pic.scale)
    );
    match deformed_window(pic) {
        Some(win) => deformed_in(path, &title, pic, win),
        None => placeholder(path, &title, "no finite cells to draw"),
    }
}

/// A deformed-body picture of `pic` showing the domain window `win` (the load-step frames of
/// Fig. IV.54 share one window, so that stepping through them shows the motion).
pub(super) fn deformed_in(
    path: &Path,
    title: &str,
    pic: &DeformedPicture,
    win: [f64; 4],
) -> io::Result<()> {
    let canvas = DeformedCanvas::new(win);
    let mut svg = svg_open(canvas.width, canvas.height);
    deformed_drawing(&mut svg, title, pic, &canvas.frame, true);
    axes(&mut svg, &canvas.frame);
    svg.push_str("</svg>\n");
    fs::write(path, svg)
}

/// Whether every corner of a quadrilateral is finite (the others are not drawn).
fn finite_quad(q: &&[[f64; 2]; 4]) -> bool {
    q.iter().flatten().all(|v| v.is_finite())
}

/// The view of one deformed body: the extent of its finite quadrilaterals plus a margin,
/// extended to the obstacles and contact points within that margin, with a little air; `None`
/// when no quadrilateral is finite.
pub(super) fn deformed_window(pic: &DeformedPicture) -> Option<[f64; 4]> {
    let body = bbox(
        pic.quads
            .iter()
            .filter(finite_quad)
            .flatten()
            .map(|p| (p[0], p[1])),
    )?;
    let (bw, bh) = (body[1] - body[0], body[3] - body[2]);
    let (mx, my) = (0.03 * bw, 0.35 * bh.max(bw / 40.0));
    let reach = [body[0] - mx, body[1] + mx, body[2] - my, body[3] + my];
    // Extend to obstacles and contact points, but never beyond `reach`.
    let extra = pic
        .obstacles
        .iter()
        .flatten()
        .chain(&pic.contact_points)
        .map(|p| (p[0], p[1]));
    let all = bbox(extra.chain([(body[0], body[2]), (body[1], body[3])])).unwrap_or(body);
    let win = [
        all[0].max(reach[0]),
        all[1].min(reach[1]),
        all[2].max(reach[2]),
        all[3].min(reach[3]),
    ];
    // A little air around the drawing.
    let pad = 0.02 * (win[3] - win[2]).max((win[1] - win[0]) / 60.0);
    Some([win[0] - pad, win[1] + pad, win[2] - pad, win[3] + pad])
}

/// The canvas of a deformed-body picture: where the window is drawn, and the picture's size in
/// pixels (room for the title above and the legend and caption below).
pub(super) struct DeformedCanvas {
    pub frame: Frame,
    pub width: f64,
    pub height: f64,
}

impl DeformedCanvas {
    /// Left and right margin in pixels.
    pub const MARGIN: f64 = 12.0;

    pub fn new(win: [f64; 4]) -> DeformedCanvas {
        let margin = Self::MARGIN;
        let aspect = (win[1] - win[0]) / (win[3] - win[2]);
        // Keep tall pictures at a readable height.
        let plot_w = (WIDE - 2.0 * margin - AXIS_LEFT).min(820.0 * aspect);
        let frame = Frame::new(win, margin + AXIS_LEFT, 40.0, plot_w);
        DeformedCanvas {
            width: (plot_w + AXIS_LEFT + 2.0 * margin).max(640.0),
            height: frame.top + frame.height() + AXIS_BELOW + 60.0,
            frame,
        }
    }
}

/// Id of the clip path of a deformed-body picture's window.
pub(super) const DEFORMED_CLIP: &str = "c";

/// Id of the hatch pattern of the obstacles' solid side in a deformed-body picture.
pub(super) const OBSTACLE_HATCH: &str = "solid";
/// Colour of the obstacles.
const OBSTACLE: &str = "#5b3a1a";

/// The clip path [`DEFORMED_CLIP`] of the window `f` and the hatch patterns of the obstacles:
/// [`OBSTACLE_HATCH`] in the sub-pixel units of the drawing, `…-px` in pixels for the legend.
pub(super) fn deformed_clip(f: &Frame) -> String {
    format!(
        "<clipPath id=\"{DEFORMED_CLIP}\"><rect x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\"/></clipPath>\
         <pattern id=\"{OBSTACLE_HATCH}\" patternUnits=\"userSpaceOnUse\" width=\"{p}\" height=\"{p}\" \
         patternTransform=\"rotate(45)\"><rect width=\"{w}\" height=\"{p}\" fill=\"{OBSTACLE}\" fill-opacity=\"0.55\"/></pattern>\
         <pattern id=\"{OBSTACLE_HATCH}-px\" patternUnits=\"userSpaceOnUse\" width=\"8\" height=\"8\" \
         patternTransform=\"rotate(45)\"><rect width=\"1.5\" height=\"8\" fill=\"{OBSTACLE}\" fill-opacity=\"0.55\"/></pattern>",
        f.left,
        f.top,
        f.width(),
        f.height(),
        p = 8.0 * SUB,
        w = 1.5 * SUB,
    )
}

/// The solid side of each obstacle curve as closed paths (sub-pixel units of `f`): the curve,
/// closed past the window's edge on the side away from the body. An obstacle whose mean height
/// lies below the body's mean height is solid below its curve (the obstacles under the strip),
/// one above it solid above (the upper die of the forming).
fn obstacle_solid_sides(pic: &DeformedPicture, f: &Frame) -> String {
    let mean_y = |pts: &mut dyn Iterator<Item = f64>| {
        let (sum, n) = pts
            .filter(|y| y.is_finite())
            .fold((0.0, 0usize), |(s, n), y| (s + y, n + 1));
        (n > 0).then(|| sum / n as f64)
    };
    let Some(body) = mean_y(&mut pic.quads.iter().filter(finite_quad).flatten().map(|p| p[1]))
    else {
        return String::new();
    };
    let mut d = String::new();
    for line in &pic.obstacles {
        let pts: Vec<(i64, i64)> = line
            .iter()
            .filter(|p| p[0].is_finite() && p[1].is_finite())
            .map(|p| f.sub(p[0], p[1]))
            .collect();
        let (Some(first), Some(last)) = (pts.first(), pts.last()) else {
            continue;
        };
        let Some(mean) = mean_y(&mut line.iter().map(|p| p[1])) else {
            continue;
        };
        // Past the window's bottom or top edge, so the clip path cuts the fill at the frame.
        let edge = if mean < body {
            ((f.top + f.height() + 20.0) * SUB) as i64
        } else {
            ((f.top - 20.0) * SUB) as i64
        };
        let _ = write!(d, "M{} {edge}", first.0);
        for (x, y) in &pts {
            let _ = write!(d, "L{x} {y}");
        }
        let _ = write!(d, "L{} {edge}z", last.0);
    }
    d
}

/// Everything of one deformed-body picture inside an open `<svg>`: the title, the body, the
/// obstacles, the Signorini faces and the contact points clipped to the window `f`, the window's
/// frame, the legend and the picture's caption. With `define_clip` the clip path
/// ([`deformed_clip`]) is written here; an animation of several pictures defines it once.
pub(super) fn deformed_drawing(
    svg: &mut String,
    title: &str,
    pic: &DeformedPicture,
    f: &Frame,
    define_clip: bool,
) {
    let margin = f.left - AXIS_LEFT;
    text(svg, margin, 26.0, 17.0, "start", title);
    if define_clip {
        svg.push_str(&deformed_clip(f));
        svg.push('\n');
    }
    let _ = writeln!(
        svg,
        "<g clip-path=\"url(#{DEFORMED_CLIP})\"><g transform=\"scale({})\">",
        1.0 / SUB
    );
    // The obstacles' solid side under everything else.
    let solid = obstacle_solid_sides(pic, f);
    if !solid.is_empty() {
        let _ = writeln!(
            svg,
            "<path class=\"obstacle-solid\" fill=\"url(#{OBSTACLE_HATCH})\" stroke=\"none\" d=\"{solid}\"/>"
        );
    }
    let mut d = String::new();
    // Quads smaller than a pixel become that pixel, written once (as in `sub_box`).
    let mut tiny = HashSet::new();
    let px = SUB as i64;
    for q in pic.quads.iter().filter(finite_quad) {
        let p: Vec<(i64, i64)> = q.iter().map(|p| f.sub(p[0], p[1])).collect();
        let (xs, ys) = (p.iter().map(|p| p.0), p.iter().map(|p| p.1));
        let w = xs.clone().max().unwrap_or(0) - xs.min().unwrap_or(0);
        let h = ys.clone().max().unwrap_or(0) - ys.min().unwrap_or(0);
        if w < px && h < px {
            let (x, y) = (p[0].0.div_euclid(px) * px, p[0].1.div_euclid(px) * px);
            if tiny.insert((x, y)) {
                let _ = write!(d, "M{x} {y}h{px}v{px}h-{px}z");
            }
            continue;
        }
        let _ = write!(
            d,
            "M{} {}L{} {} {} {} {} {}z",
            p[0].0, p[0].1, p[1].0, p[1].1, p[2].0, p[2].1, p[3].0, p[3].1
        );
    }
    let _ = writeln!(
        svg,
        "<path fill=\"#d6e4f2\" stroke=\"#4a6a8a\" stroke-width=\"{}\" stroke-linejoin=\"round\" d=\"{d}\"/>",
        0.5 * SUB
    );
    let finite = |p: &&[f64; 2]| p[0].is_finite() && p[1].is_finite();
    let mut d = String::new();
    for line in &pic.obstacles {
        let mut first = true;
        for p in line.iter().filter(finite) {
            let (x, y) = f.sub(p[0], p[1]);
            let _ = write!(d, "{}{x} {y}", if first { "M" } else { "L" });
            first = false;
        }
    }
    let _ = writeln!(
        svg,
        "<path fill=\"none\" stroke=\"{OBSTACLE}\" stroke-width=\"{}\" stroke-linejoin=\"round\" d=\"{d}\"/>",
        3.0 * SUB
    );
    // The Signorini faces on top of the body and the obstacles, under the contact points.
    if !pic.accurate_faces.is_empty() {
        // A face that starts where the previous one ended continues its line.
        let mut d = String::new();
        let mut end = None;
        for [a, b] in pic
            .accurate_faces
            .iter()
            .filter(|[a, b]| finite(&a) && finite(&b))
        {
            let (start, to) = (f.sub(a[0], a[1]), f.sub(b[0], b[1]));
            if end != Some(start) {
                let _ = write!(d, "M{} {}", start.0, start.1);
            }
            let _ = write!(d, "L{} {}", to.0, to.1);
            end = Some(to);
        }
        let _ = writeln!(
            svg,
            "<path class=\"{SIGNORINI_CLASS}\" fill=\"none\" stroke=\"#000\" stroke-width=\"{}\" stroke-linejoin=\"round\" d=\"{d}\"/>",
            SIGNORINI_WIDTH * SUB
        );
    }
    // Dots as zero-length segments with round caps: one path for any number of points.
    let mut d = String::new();
    for p in pic.contact_points.iter().filter(finite) {
        let (x, y) = f.sub(p[0], p[1]);
        let _ = write!(d, "M{x} {y}h0");
    }
    let _ = writeln!(
        svg,
        "<path stroke=\"#e31a1c\" stroke-width=\"{}\" stroke-linecap=\"round\" d=\"{d}\"/>\n</g></g>",
        5.0 * SUB
    );
    let _ = writeln!(
        svg,
        "<rect x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\" fill=\"none\" stroke=\"#999\" stroke-width=\"0.5\"/>",
        f.left,
        f.top,
        f.width(),
        f.height()
    );

    // Legend (only for pictures with an obstacle or Signorini faces) and caption under the
    // picture.
    let y = f.top + f.height() + AXIS_BELOW + 22.0;
    if !pic.obstacles.is_empty() {
        let _ = writeln!(
            svg,
            "<rect x=\"{margin}\" y=\"{y}\" width=\"28\" height=\"9\" fill=\"url(#{OBSTACLE_HATCH}-px)\"/>\
             <path d=\"M{margin} {y}h28\" stroke=\"{OBSTACLE}\" stroke-width=\"3\"/>\
             <path d=\"M{:.1} {y}h0\" stroke=\"#e31a1c\" stroke-width=\"5\" stroke-linecap=\"round\"/>",
            margin + 270.0
        );
        text(
            svg,
            margin + 34.0,
            y + 5.0,
            13.0,
            "start",
            "obstacle (hatched: its solid side)",
        );
        text(
            svg,
            margin + 278.0,
            y + 5.0,
            13.0,
            "start",
            &format!("contact points ({})", pic.contact_points.len()),
        );
    }
    if !pic.accurate_faces.is_empty() {
        let _ = writeln!(
            svg,
            "<path d=\"M{:.1} {y:.1}h28\" stroke=\"#000\" stroke-width=\"{SIGNORINI_WIDTH}\"/>",
            margin + 430.0
        );
        text(
            svg,
            margin + 464.0,
            y + 5.0,
            13.0,
            "start",
            &format!("Signorini faces ({})", pic.accurate_faces.len()),
        );
    }
    text(svg, margin, y + 28.0, 14.0, "start", &pic.caption);
}

/// Class of the path of the Signorini faces in a deformed-body picture (what the tests look for).
pub(super) const SIGNORINI_CLASS: &str = "signorini-faces";
/// Width in pixels of the Signorini faces, as in the mesh figure of Tables IV.30–IV.35.
const SIGNORINI_WIDTH: f64 = 4.0;

/// Viridis colormap (matplotlib's perceptually uniform map), sampled at nine points and
/// interpolated linearly: close enough for a report and free of dependencies.
pub(crate) fn viridis(t: f64) -> (u8, u8, u8) {
    const STOPS: [(f64, f64, f64); 9] = [
        (68.0, 1.0, 84.0),
        (71.0, 44.0, 122.0),
        (59.0, 82.0, 139.0),
        (44.0, 114.0, 142.0),
        (33.0, 145.0, 140.0),
        (40.0, 174.0, 128.0),
        (94.0, 201.0, 98.0),
        (173.0, 220.0, 48.0),
        (253.0, 231.0, 37.0),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let s = t * (STOPS.len() - 1) as f64;
    let i = (s.floor() as usize).min(STOPS.len() - 2);
    let u = s - i as f64;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    let mix = |p: f64, q: f64| (p + u * (q - p)).round() as u8;
    (mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// Colour bins of a field picture: cells are grouped by bin so each colour is one `<path>`.
const BINS: usize = 64;
const ZONE: &str = "#ff1f5b";

/// Draw a vector field as arrows in pixel space: lengths proportional to |v|, the longest as long
/// as 90 % of the spacing of the arrows' feet, white over a dark edge so they read on every
/// colour of the map; arrows shorter than 5 % of the longest are left out.
fn arrows(svg: &mut String, arrows: &[Arrow], f: &Frame) {
    let longest = arrows
        .iter()
        .map(|a| a.v[0].hypot(a.v[1]))
        .filter(|l| l.is_finite())
        .fold(0.0f64, f64::max);
    if arrows.is_empty() || longest <= 0.0 {
        return;
    }
    let side = (arrows.len() as f64).sqrt().max(1.0);
    let spacing = f.width().min(f.height()) / side;
    let scale = 0.9 * spacing / longest;
    let mut d = String::new();
    for a in arrows {
        let len = a.v[0].hypot(a.v[1]);
        if !len.is_finite() || len < 0.05 * longest {
            continue;
        }
        let (x0, y0) = (f.px(a.at[0]), f.py(a.at[1]));
        // Screen y grows downwards.
        let (dx, dy) = (a.v[0] * scale, -a.v[1] * scale);
        let (x1, y1) = (x0 + dx, y0 + dy);
        let head = (0.3 * len * scale).min(6.0);
        let (ux, uy) = (dx / (len * scale), dy / (len * scale));
        let (lx, ly) = (x1 - head * (ux + 0.5 * uy), y1 - head * (uy - 0.5 * ux));
        let (rx, ry) = (x1 - head * (ux - 0.5 * uy), y1 - head * (uy + 0.5 * ux));
        let _ = write!(
            d,
            "M{x0:.1} {y0:.1}L{x1:.1} {y1:.1}M{lx:.1} {ly:.1}L{x1:.1} {y1:.1}L{rx:.1} {ry:.1}"
        );
    }
    let _ = writeln!(
        svg,
        "<path fill=\"none\" stroke=\"#222\" stroke-width=\"2.6\" stroke-linecap=\"round\" d=\"{d}\"/>\n\
         <path fill=\"none\" stroke=\"white\" stroke-width=\"1.2\" stroke-linecap=\"round\" d=\"{d}\"/>"
    );
}

/// A scalar field on the active cells, coloured with [`viridis`], with x₁/x₂ axes, a colour bar
/// and the zone (e.g. the cavitated region ψ = 0) hatched and outlined in a contrasting colour.
pub fn field(path: &Path, table: &str, pic: &FieldPicture, domain: [f64; 4]) -> io::Result<()> {
    let title = format!("{table} — {} after cycle {}", pic.name, pic.cycle);
    let Some(win) = picture_window(domain, pic.cells.iter().map(|(c, _)| c)) else {
        return placeholder(path, &title, "no cells with a finite extent to draw");
    };
    let (lo, hi) = pic
        .cells
        .iter()
        .map(|(_, v)| *v)
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    let (lo, hi) = if lo > hi {
        (0.0, 1.0)
    } else if lo == hi {
        (lo - 0.5, hi + 0.5)
    } else {
        (lo, hi)
    };
    let bin = |v: f64| {
        ((v - lo) / (hi - lo) * BINS as f64)
            .floor()
            .clamp(0.0, BINS as f64 - 1.0) as usize
    };

    let aspect = (win[1] - win[0]) / (win[3] - win[2]);
    let margin = 14.0;
    let plot_w = (WIDE - 2.0 * margin - AXIS_LEFT).min(620.0 * aspect);
    let f = Frame::new(win, margin + AXIS_LEFT, 40.0, plot_w);
    let bar_w = plot_w.clamp(240.0, 480.0);
    let width = (plot_w + AXIS_LEFT + 2.0 * margin).max(bar_w + 2.0 * margin + 260.0);
    let bar_top = f.top + f.height() + AXIS_BELOW + 16.0;
    let height = bar_top + 80.0;

    let mut svg = svg_open(width, height);
    text(&mut svg, margin, 26.0, 17.0, "start", &title);
    // Hatch for the zone: diagonal lines in user space, so adjacent zone cells join seamlessly.
    let _ = writeln!(
        svg,
        "<defs><pattern id=\"hatch\" patternUnits=\"userSpaceOnUse\" width=\"{p}\" height=\"{p}\" \
         patternTransform=\"rotate(45)\"><rect width=\"{h}\" height=\"{p}\" fill=\"{ZONE}\" fill-opacity=\"0.75\"/></pattern>\n\
         <path id=\"zone\" d=\"{z}\"/>\n\
         <mask id=\"outside\" maskUnits=\"userSpaceOnUse\" x=\"-1e6\" y=\"-1e6\" width=\"2e6\" height=\"2e6\">\
         <rect x=\"-1e6\" y=\"-1e6\" width=\"2e6\" height=\"2e6\" fill=\"white\"/><use href=\"#zone\" fill=\"black\"/></mask>\n\
         <clipPath id=\"c\"><rect x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\"/></clipPath>\n\
         <pattern id=\"hatch-px\" patternUnits=\"userSpaceOnUse\" width=\"7\" height=\"7\" \
         patternTransform=\"rotate(45)\"><rect width=\"1.6\" height=\"7\" fill=\"{ZONE}\"/></pattern>\n\
         <linearGradient id=\"bar\">{stops}</linearGradient></defs>",
        f.left * SUB,
        f.top * SUB,
        f.width() * SUB,
        f.height() * SUB,
        p = 7.0 * SUB,
        h = 1.6 * SUB,
        z = rect_path(pic.zone.iter(), &f),
        stops = (0..=8)
            .map(|k| {
                let (r, g, b) = viridis(k as f64 / 8.0);
                format!("<stop offset=\"{}\" stop-color=\"rgb({r},{g},{b})\"/>", k as f64 / 8.0)
            })
            .collect::<String>(),
    );
    let _ = writeln!(
        svg,
        "<g transform=\"scale({})\" clip-path=\"url(#c)\">",
        1.0 / SUB
    );
    // One path per colour bin; `BINS` is the bin of cells without a finite value (grey). The
    // first cell to claim a snapped pixel colours it.
    let mut by_bin = vec![Vec::new(); BINS + 1];
    let mut seen = HashSet::new();
    let mut undefined = 0;
    for (c, v) in &pic.cells {
        let k = if v.is_finite() {
            bin(*v)
        } else {
            undefined += 1;
            BINS
        };
        if finite_box(c) && f.intersects(c) {
            let b = sub_box(c, &f);
            if seen.insert(b) {
                by_bin[k].push(b);
            }
        }
    }
    let by_bin: Vec<String> = by_bin.into_iter().map(rects_path).collect();
    for (k, d) in by_bin.iter().enumerate().filter(|(_, d)| !d.is_empty()) {
        let fill = if k == BINS {
            "#bbbbbb".to_string()
        } else {
            let (r, g, b) = viridis((k as f64 + 0.5) / BINS as f64);
            format!("rgb({r},{g},{b})")
        };
        let _ = writeln!(
            svg,
            "<path fill=\"{fill}\" shape-rendering=\"crispEdges\" d=\"{d}\"/>"
        );
    }
    // Cell outlines only while they do not drown the colours (roughly ≥ 6 pixels per cell).
    let px_per_cell = f.width() * f.height() / pic.cells.len().max(1) as f64;
    if px_per_cell >= 36.0 {
        let _ = writeln!(
            svg,
            "<path fill=\"none\" stroke=\"white\" stroke-opacity=\"0.45\" stroke-width=\"{}\" d=\"{}\"/>",
            0.5 * SUB,
            outline_path(pic.cells.iter().map(|(c, _)| c), &f)
        );
    }
    if !pic.zone.is_empty() {
        // The outline is the zone cells' stroke masked to the outside of the zone: what remains
        // is the outer half of the stroke along the union's boundary, with no interior edges.
        let _ = writeln!(
            svg,
            "<use href=\"#zone\" fill=\"url(#hatch)\"/>\n\
             <use href=\"#zone\" fill=\"none\" stroke=\"{ZONE}\" stroke-width=\"{}\" mask=\"url(#outside)\"/>",
            5.0 * SUB
        );
    }
    svg.push_str("</g>\n");
    arrows(&mut svg, &pic.arrows, &f);
    let _ = writeln!(
        svg,
        "<rect x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\" fill=\"none\" stroke=\"black\" stroke-width=\"1\"/>",
        f.left,
        f.top,
        f.width(),
        f.height()
    );
    axes(&mut svg, &f);

    // Colour bar with five ticks.
    let _ = writeln!(
        svg,
        "<rect x=\"{margin}\" y=\"{bar_top:.1}\" width=\"{bar_w:.1}\" height=\"16\" fill=\"url(#bar)\" stroke=\"#444\" stroke-width=\"0.5\"/>"
    );
    for k in 0..=4 {
        let t = k as f64 / 4.0;
        let x = margin + t * bar_w;
        let _ = writeln!(
            svg,
            "<path d=\"M{x:.1} {:.1}v5\" stroke=\"#444\"/>",
            bar_top + 16.0
        );
        let anchor = match k {
            0 => "start",
            4 => "end",
            _ => "middle",
        };
        text(
            &mut svg,
            x,
            bar_top + 35.0,
            12.0,
            anchor,
            &fmt_short(lo + t * (hi - lo)),
        );
    }
    text(
        &mut svg,
        margin + bar_w + 14.0,
        bar_top + 13.0,
        14.0,
        "start",
        &pic.name,
    );
    let legend_y = bar_top + 60.0;
    if !pic.zone.is_empty() {
        let _ = writeln!(
            svg,
            "<rect x=\"{margin}\" y=\"{:.1}\" width=\"22\" height=\"14\" fill=\"url(#hatch-px)\" stroke=\"{ZONE}\" stroke-width=\"2\"/>",
            legend_y - 11.0
        );
        text(
            &mut svg,
            margin + 30.0,
            legend_y,
            13.0,
            "start",
            &format!("{} ({} cells)", pic.zone_label, pic.zone.len()),
        );
    }
    if undefined > 0 {
        text(
            &mut svg,
            margin + 320.0,
            legend_y,
            13.0,
            "start",
            &format!("grey: {undefined} cells without a finite value"),
        );
    }
    svg.push_str("</svg>\n");
    fs::write(path, svg)
}

/// A run of table `T` with the given rows, deformed pictures and domain and nothing else, for the
/// tests of the figures.
#[cfg(test)]
pub(super) fn test_run(
    rows: Vec<crate::results::Row>,
    deformed: Vec<DeformedPicture>,
    domain: [f64; 4],
) -> RunResult {
    RunResult {
        rows,
        deformed,
        ..RunResult::new("T", "S", "t", "quick", domain)
    }
}

/// The cost of a solve per unknown on the page's tables: solve seconds per million unknowns
/// against the unknowns of every cycle (log–log, one dot per cycle), by solver — multigrid
/// (the rows with CG iterations) and the direct solver, the thin films apart from elasticity
/// and contact. Flat dots mean a cost proportional to the unknowns.
pub fn solve_cost(path: &Path, runs: &[&RunResult]) -> io::Result<()> {
    let groups: [(&str, RGBColor); 4] = [
        ("Reynolds, multigrid CG", RGBColor(31, 119, 180)),
        ("Reynolds, direct (Cholesky)", RGBColor(214, 39, 40)),
        ("elasticity, multigrid CG", RGBColor(44, 160, 44)),
        ("elasticity and contact, direct", RGBColor(120, 120, 120)),
    ];
    let mut points: [Vec<(f64, f64)>; 4] = Default::default();
    for run in runs {
        let family = super::families::family_of(&run.table).map(|f| f.id.as_str());
        for row in &run.rows {
            let Some(dofs) = row.dofs() else { continue };
            let multigrid = row
                .count_of(crate::results::columns::CG_ITERATIONS)
                .is_some();
            let group = match (family, multigrid) {
                (Some("family-reynolds"), true) => 0,
                (Some("family-reynolds"), false) => 1,
                (Some("family-elasticity"), true) => 2,
                (Some("family-elasticity" | "family-contact"), false) => 3,
                _ => continue,
            };
            let p = (dofs as f64, row.seconds.solve / (dofs as f64 / 1e6));
            if loggable(&p) && dofs >= 1000 {
                points[group].push(p);
            }
        }
    }
    let all: Vec<(f64, f64)> = points.iter().flatten().copied().collect();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (900, 560)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let (x_lo, x_hi) = log_range(all.iter().map(|p| p.0));
        let (y_lo, y_hi) = log_range(all.iter().map(|p| p.1));
        let mut chart = log_log_axes(
            &root,
            (
                "Solve seconds per million unknowns, every cycle of every table",
                22,
            ),
            48,
            ((x_lo, x_hi), (y_lo, y_hi)),
            ("unknowns (dofs)", "solve s per 10⁶ unknowns"),
        )?;
        for ((label, color), pts) in groups.iter().zip(&points) {
            if pts.is_empty() {
                continue;
            }
            let color = *color;
            chart
                .draw_series(pts.iter().map(|p| Circle::new(*p, 3, color.filled())))
                .map_err(plot_err)?
                .label(*label)
                .legend(move |(x, y)| Circle::new((x + 11, y), 4, color.filled()));
        }
        if all.is_empty() {
            empty_note(&root, "no cycle with unknowns on this page", (280, 250))?;
        } else {
            series_legend(&mut chart, SeriesLabelPosition::UpperLeft, 16)?;
        }
        root.present().map_err(plot_err)?;
    }
    fs::write(path, svg)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::results::Row;

    #[test]
    fn log_axis_labels_a_range_without_a_power_of_ten() {
        let axis = NiceLog::new((0.11, 0.8));
        let ticks = axis.key_points(plotters::coord::ranged1d::BoldPoints(12));
        assert_eq!(ticks.len(), 2, "{ticks:?}"); // 0.2 and 0.5
        let wide = NiceLog::new((1e-9, 1e9)).key_points(plotters::coord::ranged1d::BoldPoints(6));
        assert!(!wide.is_empty() && wide.len() <= 6, "{wide:?}");
    }

    #[test]
    fn merged_outline_of_a_uniform_grid_is_one_line_per_grid_line() {
        let n = 40;
        let cells: Vec<CellBox> = (0..n * n)
            .map(|k| {
                let (i, j) = ((k % n) as f64, (k / n) as f64);
                let h = 1.0 / n as f64;
                CellBox {
                    x0: i * h,
                    x1: (i + 1.0) * h,
                    y0: j * h,
                    y1: (j + 1.0) * h,
                }
            })
            .collect();
        let f = Frame::new([0.0, 1.0, 0.0, 1.0], 0.0, 0.0, 400.0);
        assert_eq!(outline_path(cells.iter(), &f).matches('M').count(), 2 * n);
    }

    /// Degenerate data must give a figure, not a panic or an error.
    #[test]
    fn degenerate_data_still_writes_figures() {
        let dir = std::env::temp_dir().join(format!("tribo-plots-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let row = |estimate: f64| {
            Row::new(0)
                .count("active_cells", 1)
                .count("dofs", 4)
                .real("estimate", Some(estimate))
                .real("ratio", None)
        };
        let thesis = ThesisTable {
            table: "T".into(),
            section: "S".into(),
            columns: vec!["cycle".into(), "dofs".into(), "estimate".into()],
            rows: vec![vec![0.0, f64::NAN, -1.0]],
            duplicate_of: None,
            additive_part: None,
            comparison: Default::default(),
            figures: Default::default(),
        };
        for rows in [
            vec![],
            vec![row(0.0)],
            vec![row(f64::NAN), row(-1.0)],
            vec![row(0.5)],
        ] {
            let run = test_run(rows, vec![], [0.0, 1.0, 0.0, 1.0]);
            convergence(&dir.join("c.svg"), &run, &thesis).unwrap();
            cost(&dir.join("k.svg"), &run).unwrap();
        }
        let empty = MeshPicture {
            cycle: 0,
            cells: vec![],
            levels: vec![],
            shaded: vec![],
        };
        meshes(&dir.join("m.svg"), &[empty], [f64::NAN; 4], &[]).unwrap();
        let pic = DeformedPicture {
            cycle: 0,
            scale: 1.0,
            quads: vec![[[f64::NAN; 2]; 4]],
            obstacles: vec![vec![]],
            contact_points: vec![],
            accurate_faces: vec![],
            caption: String::new(),
        };
        deformed(&dir.join("d.svg"), "T", &pic).unwrap();
        let field_pic = FieldPicture {
            cycle: 0,
            name: "psi".into(),
            cells: vec![],
            zone: vec![],
            zone_label: String::new(),
            arrows: vec![],
        };
        field(&dir.join("f.svg"), "T", &field_pic, [0.0, 1.0, 0.0, 1.0]).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
