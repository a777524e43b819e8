//! The legends of the line charts, drawn in a strip of their own under the chart instead of a
//! box over the plotting area.
//!
//! A legend inside the plotting area hides whatever data fall under it, and no corner is free
//! for every run (IV.32's box covered the last five estimates, the stall its notes discuss). A
//! strip under the axis name cannot cover a data point, at the price of a taller figure: the
//! chart reserves [`height`] pixels at its bottom ([`split`]) and [`draw`] fills them, in as
//! many columns as the labels allow.
//!
//! [`Placed`] records, in the SVG's own pixels, every legend box and every plotted point of a
//! figure, so the tests can check that no point lies inside a legend.

use std::io;

use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

use super::plots::{plot_err, Curve, GUIDE};

/// Font size of the legend labels (plotters' size; about 12 px in the SVG).
pub(super) const FONT: u32 = 15;
/// Height of one row of entries, pixels.
const ROW: u32 = 22;
/// Padding inside the legend frame, pixels.
const PAD: u32 = 6;
/// Width of an entry's sample and the gap before its label, pixels.
const SAMPLE: u32 = 34;
/// Left edge of the legend in its strip: under the plotting area of a chart with a 70-pixel
/// y-label area and a 12-pixel margin.
pub(super) const INSET: i32 = 82;
/// Colour of the legend frame (the check of a report folder finds legends by it).
pub(super) const FRAME: RGBColor = RGBColor(160, 160, 160);

/// What an entry's sample shows.
#[derive(Clone, Copy)]
pub(super) enum Swatch {
    /// A curve: solid with dots, or dashed with hollow triangles.
    Curve { color: RGBColor, dashed: bool },
    /// A plain line without markers (cuts, residuals).
    Line { color: RGBColor, dashed: bool },
    /// The grey dotted slope guide.
    Guide,
    /// A dot (a scatter of points).
    Dot(RGBColor),
    /// A filled bar (stacked bars).
    Bar(RGBColor),
}

/// One entry of a legend.
pub(super) struct Entry {
    pub label: String,
    pub swatch: Swatch,
}

impl Entry {
    pub(super) fn new(label: impl Into<String>, swatch: Swatch) -> Entry {
        Entry {
            label: label.into(),
            swatch,
        }
    }

    /// The entry of a curve drawn with its markers ([`super::plots::log_log_chart`]).
    pub(super) fn curve(c: &Curve) -> Entry {
        Entry::new(
            c.label.clone(),
            Swatch::Curve {
                color: c.color,
                dashed: c.dashed,
            },
        )
    }

    /// The entry of a curve drawn as a plain line.
    pub(super) fn line(c: &Curve) -> Entry {
        Entry::new(
            c.label.clone(),
            Swatch::Line {
                color: c.color,
                dashed: c.dashed,
            },
        )
    }
}

/// A pixel rectangle of the SVG, `(left, top, right, bottom)`.
pub(super) type PixelBox = (i32, i32, i32, i32);

/// Where a figure put its legends and its data points, in the SVG's pixels.
#[derive(Default, Debug)]
pub(super) struct Placed {
    pub legends: Vec<PixelBox>,
    pub points: Vec<(i32, i32)>,
}

impl Placed {
    pub(super) fn extend(&mut self, other: Placed) {
        self.legends.extend(other.legends);
        self.points.extend(other.points);
    }

    /// The points that lie inside a legend box (none in a figure drawn by this module).
    #[cfg(test)]
    pub(super) fn covered(&self) -> Vec<(i32, i32)> {
        self.points
            .iter()
            .copied()
            .filter(|&(x, y)| {
                self.legends
                    .iter()
                    .any(|&(l, t, r, b)| x >= l && x <= r && y >= t && y <= b)
            })
            .collect()
    }
}

/// The pixel positions of `points` on `chart` (where they were drawn).
pub(super) fn pixels<DB: DrawingBackend, X: Ranged, Y: Ranged>(
    chart: &ChartContext<'_, DB, Cartesian2d<X, Y>>,
    points: impl IntoIterator<Item = (X::ValueType, Y::ValueType)>,
) -> Vec<(i32, i32)> {
    points
        .into_iter()
        .map(|p| chart.backend_coord(&p))
        .collect()
}

/// Estimated width of a label in pixels: sans-serif averages about 0.6 em, and plotters writes
/// its size `FONT` as `FONT / 1.24` pixels. Generous, so that columns never overlap.
fn label_width(label: &str) -> u32 {
    (label.chars().count() as f64 * 0.6 * f64::from(FONT) / 1.24).ceil() as u32
}

/// Columns and rows of a legend of `entries` in a strip `width` pixels wide.
fn grid(entries: &[Entry], width: u32) -> (u32, u32, u32) {
    let column = entries
        .iter()
        .map(|e| SAMPLE + label_width(&e.label) + 18)
        .max()
        .unwrap_or(0);
    let room = width.saturating_sub(INSET as u32 + 2 * PAD + 12);
    let n = entries.len() as u32;
    let columns = (room / column.max(1)).clamp(1, n.max(1));
    (columns, n.div_ceil(columns), column)
}

/// Pixels a legend of `entries` needs under a chart `width` pixels wide (0 without entries).
pub(super) fn height(entries: &[Entry], width: u32) -> u32 {
    if entries.is_empty() {
        return 0;
    }
    let (_, rows, _) = grid(entries, width);
    rows * ROW + 2 * PAD + 10
}

/// `area` split into the chart (top) and the strip its legend of `entries` needs (bottom).
pub(super) fn split<'a>(
    area: &DrawingArea<SVGBackend<'a>, Shift>,
    entries: &[Entry],
) -> (
    DrawingArea<SVGBackend<'a>, Shift>,
    DrawingArea<SVGBackend<'a>, Shift>,
) {
    let (w, h) = area.dim_in_pixel();
    let legend = height(entries, w).min(h / 2);
    area.split_vertically(h - legend)
}

/// Draw the legend of `entries` in its strip `area` ([`split`]): a framed grid of samples and
/// labels from the left edge of the plotting area. Returns the frame, in the SVG's pixels.
pub(super) fn draw(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    entries: &[Entry],
) -> io::Result<Option<PixelBox>> {
    if entries.is_empty() {
        return Ok(None);
    }
    let (w, _) = area.dim_in_pixel();
    let (columns, rows, column) = grid(entries, w);
    let (x0, y0) = (INSET, 2);
    let frame_w = (columns * column + 2 * PAD) as i32;
    let frame_h = (rows * ROW + 2 * PAD) as i32;
    let right = (x0 + frame_w).min(w as i32 - 2);
    area.draw(&Rectangle::new(
        [(x0, y0), (right, y0 + frame_h)],
        FRAME.stroke_width(1),
    ))
    .map_err(plot_err)?;
    let font = ("sans-serif", FONT).into_font().color(&BLACK);
    for (k, e) in entries.iter().enumerate() {
        let (c, r) = (k as u32 % columns, k as u32 / columns);
        let x = x0 + (PAD + c * column) as i32;
        let y = y0 + (PAD + r * ROW + ROW / 2) as i32;
        sample(area, e.swatch, (x, y))?;
        area.draw(&Text::new(
            e.label.clone(),
            (x + SAMPLE as i32, y - 7),
            font.clone(),
        ))
        .map_err(plot_err)?;
    }
    let (bx, by) = area.get_base_pixel();
    Ok(Some((bx + x0, by + y0, bx + right, by + y0 + frame_h)))
}

/// The sample of an entry, 24 pixels wide, centred on row `y` from `x`.
fn sample(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    swatch: Swatch,
    (x, y): (i32, i32),
) -> io::Result<()> {
    let line = vec![(x, y), (x + 24, y)];
    match swatch {
        Swatch::Curve { color, dashed } | Swatch::Line { color, dashed } => {
            let style = color.stroke_width(2);
            if dashed {
                area.draw(&DashedPathElement::new(line, 7, 4, style))
            } else {
                area.draw(&PathElement::new(line, style))
            }
            .map_err(plot_err)?;
            match swatch {
                Swatch::Curve { dashed: true, .. } => {
                    area.draw(&TriangleMarker::new((x + 12, y), 6, color.stroke_width(2)))
                }
                Swatch::Curve { .. } => area.draw(&Circle::new((x + 12, y), 3, color.filled())),
                _ => Ok(()),
            }
            .map_err(plot_err)
        }
        Swatch::Guide => area
            .draw(&DashedPathElement::new(line, 2, 4, GUIDE.stroke_width(1)))
            .map_err(plot_err),
        Swatch::Dot(color) => area
            .draw(&Circle::new((x + 12, y), 4, color.filled()))
            .map_err(plot_err),
        Swatch::Bar(color) => area
            .draw(&Rectangle::new(
                [(x + 6, y - 6), (x + 18, y + 6)],
                color.filled(),
            ))
            .map_err(plot_err),
    }
}
