//! What the figures of the report share: the log–log charts, the log axis and the series
//! colours of the line plots, and the frame, axes and text of the pictures written as SVG text.
//!
//! Line and log plots (convergence, cost of accuracy) go through `plotters`' SVG backend. Mesh,
//! deformed-body and field pictures are written as SVG text directly: they hold up to hundreds of
//! thousands of cells, and one `<path>` per picture (or per colour) with integer coordinates is
//! orders of magnitude smaller and faster than one plotters element per cell. Each kind of
//! figure has its module (`convergence`, `meshes`, `deformed`, `field`, `performance`, …).
//!
//! Every function here and there tolerates degenerate data — no rows, a single row, zero, negative or NaN
//! values on a log axis — by skipping what cannot be drawn and saying so in the figure; it returns
//! an `io::Error` only when the file cannot be written.

use std::collections::HashSet;
use std::fmt::Write as _;
use std::io;
use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::html::{escape, fmt_short};
use super::legend::{self, Entry, Placed, Swatch};
use super::MAX_SHOWN_THESIS_ROWS;
use crate::results::CellBox;
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

/// Margin right of a chart's plotting area, pixels: room for half the last x tick label
/// ("300", "1e5"), which is centred on the right edge.
pub(super) const RIGHT_MARGIN: u32 = 30;

/// A log–log chart on `area`: the caption, the axes of the ranges `x` and `y` (margin 12,
/// [`RIGHT_MARGIN`] on the right, `x_label_area` pixels under the axis, 70 left of it) and the
/// grid ([`log_log_grid`]).
pub(super) fn log_log_axes<'a, DB: DrawingBackend + 'a>(
    area: &'a DrawingArea<DB, Shift>,
    (caption, caption_size): (&str, u32),
    x_label_area: u32,
    (x, y): ((f64, f64), (f64, f64)),
    (x_desc, y_desc): (&str, &str),
) -> io::Result<ChartContext<'a, DB, Cartesian2d<NiceLog, NiceLog>>> {
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", caption_size))
        .margin(12)
        .margin_right(RIGHT_MARGIN)
        .x_label_area_size(x_label_area)
        .y_label_area_size(70)
        .build_cartesian_2d(NiceLog::new(x), NiceLog::new(y))
        .map_err(plot_err)?;
    log_log_grid(&mut chart, x_desc, y_desc)?;
    Ok(chart)
}

/// The note in place of a chart with nothing to draw, at `at` (pixels) on `area`.
pub(super) fn empty_note<DB: DrawingBackend>(
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
            // Every mantissa last: a range inside one decade that holds at most one of 1, 2, 5
            // (a constant series, padded) still gets labels.
            plotters::coord::ranged1d::KeyPointWeight::Bold => [&[1.0, 2.0, 5.0], &[1.0], &all],
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

pub(super) const TRIBO: RGBColor = RGBColor(31, 119, 180);

pub(super) const THESIS: RGBColor = RGBColor(214, 39, 40);

pub(super) const TRIBO_ME: RGBColor = RGBColor(44, 160, 44);

pub(super) const THESIS_ME: RGBColor = RGBColor(148, 103, 189);

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
pub(super) fn thesis_pairs(thesis: &ThesisTable, x: &str, y: &str) -> Vec<(f64, f64)> {
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

/// The legend of a log–log chart: the guide (when it has one), then the curves.
fn log_log_entries(
    curves: &[Curve],
    (guide_pts, guide_label): (&[(f64, f64)], &str),
) -> Vec<Entry> {
    let guide = (!guide_pts.is_empty()).then(|| Entry::new(guide_label, Swatch::Guide));
    guide
        .into_iter()
        .chain(curves.iter().map(Entry::curve))
        .collect()
}

/// Height of a [`log_log_chart`] of `curves` and `guide`: 520 pixels and its legend strip.
pub(super) fn log_log_height(curves: &[Curve], guide: (&[(f64, f64)], &str)) -> u32 {
    520 + legend::height(&log_log_entries(curves, guide), 760)
}

/// Write one 760-pixel wide [`log_log_chart`] as an SVG file.
pub(super) fn write_log_log(
    path: &Path,
    title: &str,
    labels: (&str, &str),
    curves: &[Curve],
    guide: (&[(f64, f64)], &str),
    empty: &str,
) -> io::Result<Placed> {
    let mut svg = String::new();
    let placed;
    {
        let size = (760, log_log_height(curves, guide));
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        placed = log_log_chart(&root, title, labels, curves, guide, empty)?;
        root.present().map_err(plot_err)?;
    }
    crate::fsio::write(path, svg)?;
    Ok(placed)
}

/// A log–log chart of `curves` (solid with dots, or dashed with hollow triangles) on `root`
/// (760 pixels wide, [`log_log_height`] high) with an optional dashed grey guide line, its
/// legend under it ([`legend`]), and `empty` written where there is nothing to draw.
pub(super) fn log_log_chart(
    root: &DrawingArea<SVGBackend<'_>, Shift>,
    title: &str,
    (x_label, y_label): (&str, &str),
    curves: &[Curve],
    (guide_pts, guide_label): (&[(f64, f64)], &str),
    empty: &str,
) -> io::Result<Placed> {
    let all: Vec<(f64, f64)> = curves
        .iter()
        .flat_map(|c| c.points.iter().copied())
        .collect();
    let (x_lo, x_hi) = log_range(all.iter().map(|p| p.0));
    let (y_lo, y_hi) = log_range(all.iter().chain(guide_pts).map(|p| p.1));
    root.fill(&WHITE).map_err(plot_err)?;
    let entries = if curves.is_empty() {
        Vec::new()
    } else {
        log_log_entries(curves, (guide_pts, guide_label))
    };
    let (area, strip) = legend::split(root, &entries);
    let mut chart = log_log_axes(
        &area,
        (title, 24),
        48,
        ((x_lo, x_hi), (y_lo, y_hi)),
        (x_label, y_label),
    )?;

    if curves.is_empty() {
        empty_note(&area, empty, (280, 250))?;
    }
    if !guide_pts.is_empty() {
        let style = GUIDE.stroke_width(1);
        chart
            .draw_series(DashedLineSeries::new(guide_pts.to_vec(), 2, 4, style))
            .map_err(plot_err)?;
    }
    for c in curves {
        let style = c.color.stroke_width(2);
        let color = c.color;
        if c.dashed {
            chart
                .draw_series(DashedLineSeries::new(c.points.clone(), 7, 4, style))
                .map_err(plot_err)?;
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
    let mut placed = Placed {
        points: legend::pixels(&chart, all.iter().chain(guide_pts).copied()),
        ..Placed::default()
    };
    placed.legends.extend(legend::draw(&strip, &entries)?);
    Ok(placed)
}

/// The legend of a [`linear_chart`]: its curves that have a label (lines, or curves with their
/// dots where `dots`).
fn linear_entries(curves: &[Curve], dots: bool) -> Vec<Entry> {
    curves
        .iter()
        .filter(|c| !c.label.is_empty())
        .map(|c| {
            if dots {
                Entry::curve(c)
            } else {
                Entry::line(c)
            }
        })
        .collect()
}

/// Pixels the legend of a [`linear_chart`] of `curves`, 760 pixels wide, needs under it.
pub(super) fn linear_legend_height(curves: &[Curve], dots: bool) -> u32 {
    legend::height(&linear_entries(curves, dots), 760)
}

/// A chart of `curves` against x on linear axes on `area`, the legend of its labelled curves in
/// a strip under it ([`linear_legend_height`] pixels of `area`): lines, dashed where a curve is,
/// with a dot at every point where `dots` (a few values, such as a quantity against a swept
/// parameter). Nothing is drawn where the points span no range in x.
pub(super) fn linear_chart(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    title: &str,
    (x_desc, y_desc): (&str, &str),
    curves: &[Curve],
    dots: bool,
) -> io::Result<Placed> {
    let points = || curves.iter().flat_map(|c| c.points.iter());
    let (x0, x1) = points().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
        (a.min(p.0), b.max(p.0))
    });
    let (y0, y1) = points().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
        (a.min(p.1), b.max(p.1))
    });
    if !(x0.is_finite() && x1 > x0 && y0.is_finite() && y1.is_finite()) {
        return Ok(Placed::default());
    }
    let entries = linear_entries(curves, dots);
    let (area, strip) = legend::split(area, &entries);
    let pad = 0.05 * (y1 - y0).max(1e-9 * y1.abs().max(1.0));
    let mut chart = ChartBuilder::on(&area)
        .caption(title, ("sans-serif", 19))
        .margin(12)
        .margin_right(RIGHT_MARGIN)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(x0..x1, (y0 - pad)..(y1 + pad))
        .map_err(plot_err)?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_label_formatter(&|v| fmt_short(*v))
        .y_label_formatter(&|v| fmt_short(*v))
        .light_line_style(RGBColor(240, 240, 240))
        .bold_line_style(RGBColor(215, 215, 215))
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 15))
        .draw()
        .map_err(plot_err)?;
    for c in curves {
        let style = c.color.stroke_width(2);
        if c.dashed {
            chart
                .draw_series(DashedLineSeries::new(c.points.iter().copied(), 8, 5, style))
                .map_err(plot_err)?;
        } else if dots {
            solid_curve(&mut chart, c, &[&c.points])?;
        } else {
            chart
                .draw_series(LineSeries::new(c.points.iter().copied(), style))
                .map_err(plot_err)?;
        }
    }
    Ok(Placed {
        points: legend::pixels(&chart, points().copied()),
        legends: legend::draw(&strip, &entries)?.into_iter().collect(),
    })
}

/// A solid curve: a line through each of `runs` (pieces of the curve's points) and a dot at
/// every point of the curve.
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
    for run in runs {
        chart
            .draw_series(LineSeries::new(run.iter().copied(), style))
            .map_err(plot_err)?;
    }
    let color = c.color;
    chart
        .draw_series(c.points.iter().map(|p| Circle::new(*p, 3, color.filled())))
        .map_err(plot_err)?;
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Hand-written SVG pictures.
// ---------------------------------------------------------------------------------------------

/// Sub-pixel units per pixel for picture coordinates. Coordinates are written as integers in these
/// units inside a `scale(0.1)` group: one decimal of pixel precision without decimal points.
pub(super) const SUB: f64 = 10.0;

/// Maps a rectangle of the domain onto a pixel rectangle, y pointing up in the domain and down in
/// the SVG. Integer output is in [`SUB`] units.
#[derive(Clone, Copy)]
pub(super) struct Frame {
    /// Domain window `[x0, x1, y0, y1]`.
    pub(super) win: [f64; 4],
    /// Pixel origin (left, top) and pixels per domain unit.
    pub(super) left: f64,
    pub(super) top: f64,
    pub(super) scale: f64,
}

impl Frame {
    /// A frame showing `win` with `width` pixels, keeping the aspect ratio.
    pub(super) fn new(win: [f64; 4], left: f64, top: f64, width: f64) -> Frame {
        Frame {
            win,
            left,
            top,
            scale: width / (win[1] - win[0]),
        }
    }
    pub(super) fn width(&self) -> f64 {
        (self.win[1] - self.win[0]) * self.scale
    }
    pub(super) fn height(&self) -> f64 {
        (self.win[3] - self.win[2]) * self.scale
    }
    /// Pixel x of a domain x.
    pub(super) fn px(&self, x: f64) -> f64 {
        self.left + (x - self.win[0]) * self.scale
    }
    /// Pixel y of a domain y.
    pub(super) fn py(&self, y: f64) -> f64 {
        self.top + (self.win[3] - y) * self.scale
    }
    /// Integer sub-pixel coordinates of a domain point.
    pub(super) fn sub(&self, x: f64, y: f64) -> (i64, i64) {
        (
            (self.px(x) * SUB).round() as i64,
            (self.py(y) * SUB).round() as i64,
        )
    }
    pub(super) fn intersects(&self, c: &CellBox) -> bool {
        c.x1 >= self.win[0] && c.x0 <= self.win[1] && c.y1 >= self.win[2] && c.y0 <= self.win[3]
    }
}

pub(super) fn finite_box(c: &CellBox) -> bool {
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
pub(super) fn picture_window<'a>(
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
pub(super) type SubBox = (i64, i64, i64, i64);

/// A cell's box in sub-pixel units `(x0, top, x1, bottom)`.
///
/// Cells narrower or lower than a pixel are snapped to the pixel grid they fall in: at that size
/// they only darken (mesh) or colour (field) the pixel anyway, and snapped boxes repeat, so the
/// callers' de-duplication bounds the SVG by the picture's pixel count instead of the cell count.
pub(super) fn sub_box(c: &CellBox, f: &Frame) -> (i64, i64, i64, i64) {
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
pub(super) fn outline_path<'a>(cells: impl Iterator<Item = &'a CellBox>, f: &Frame) -> String {
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
pub(super) fn rects_path(mut boxes: Vec<(i64, i64, i64, i64)>) -> String {
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
pub(super) fn rect_path<'a>(cells: impl Iterator<Item = &'a CellBox>, f: &Frame) -> String {
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
    crate::fsio::write(path, svg)
}

/// Width of the wide pictures (strips, deformed body) in pixels.
pub(super) const WIDE: f64 = 1600.0;

/// Domains at least this many times wider than high are drawn as stacked strips.
pub(super) const STRIP_ASPECT: f64 = 3.0;

pub(super) const MESH_LINE: &str = "#1f3a5f";

/// Left margin in pixels of a picture with x₂ tick labels and the x₂ axis name.
pub(super) const AXIS_LEFT: f64 = 64.0;

/// Room in pixels under a picture for the x₁ tick labels and the x₁ axis name.
pub(super) const AXIS_BELOW: f64 = 37.0;

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
        text(svg, px, b + 16.0, 13.0, "middle", &fmt_short(x));
    }
    let ys = ticks(f.win[2], f.win[3], ((h / 28.0) as usize).clamp(2, 10));
    for y in ys {
        let py = f.py(y);
        let _ = write!(d, "M{l:.1} {py:.1}h-4");
        text(svg, l - 6.0, py + 4.5, 13.0, "end", &fmt_short(y));
    }
    let _ = writeln!(
        svg,
        "<path d=\"{d}\" stroke=\"#444\" stroke-width=\"1\" fill=\"none\"/>"
    );
    text(svg, l + 0.5 * w, b + 32.0, 14.0, "middle", "x₁");
    text(
        svg,
        l - AXIS_LEFT + 8.0,
        t + 0.5 * h + 4.0,
        14.0,
        "start",
        "x₂",
    );
    svg.push_str("</g>\n");
}

/// A run of table `T` with the given rows, deformed pictures and domain and nothing else, for the
/// tests of the figures.
#[cfg(test)]
pub(super) fn test_run(
    rows: Vec<crate::results::Row>,
    deformed: Vec<crate::results::DeformedPicture>,
    domain: [f64; 4],
) -> crate::results::RunResult {
    crate::results::RunResult {
        rows,
        deformed,
        ..crate::results::RunResult::new("T", "S", "t", "quick", domain)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::convergence::{convergence, cost};
    use crate::report::deformed::deformed;
    use crate::report::field::field;
    use crate::report::meshes::meshes;
    use crate::results::{DeformedPicture, FieldPicture, MeshPicture, Row};

    #[test]
    fn log_axis_labels_a_range_without_a_power_of_ten() {
        let axis = NiceLog::new((0.11, 0.8));
        let ticks = axis.key_points(plotters::coord::ranged1d::BoldPoints(12));
        // 0.2 and 0.5.
        assert_eq!(ticks.len(), 2, "{ticks:?}");
        // A constant 6.01e-10, padded by 1.25: labelled 5e-10, 6e-10, 7e-10.
        let narrow = NiceLog::new((6.01e-10 / 1.25, 6.01e-10 * 1.25))
            .key_points(plotters::coord::ranged1d::BoldPoints(12));
        assert_eq!(narrow.len(), 3, "{narrow:?}");
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
