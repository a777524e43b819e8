//! The field pictures: a scalar on the active cells in the viridis colour map, with its zone
//! (the cavitated cells) and the flow arrows. Written as SVG text directly.

use std::collections::HashSet;
use std::fmt::Write as _;
use std::io;
use std::path::Path;

use super::figures::{cf, indexed, Drawing, Figure, Figures};
use super::file_stem;
use super::html::fmt_short;
use super::plots::*;
use super::raster::{Raster, RASTER_MIN_BYTES, RASTER_MIN_CELLS};
use crate::results::{Arrow, FieldPicture, RunResult};

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
    let undefined = pic.cells.iter().filter(|(_, v)| !v.is_finite()).count();
    let mut fills = String::new();
    cells_path(&mut fills, pic, &f, &bin);
    if pic.cells.len() > RASTER_MIN_CELLS || fills.len() > RASTER_MIN_BYTES {
        svg.push_str(&cells_raster(pic, &f, &bin));
        svg.push('\n');
    } else {
        svg.push_str(&fills);
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

    colour_bar(&mut svg, margin, bar_top, bar_w, (lo, hi), pic, undefined);
    svg.push_str("</svg>\n");
    crate::fsio::write(path, svg)
}

/// The cells as vector paths (in [`SUB`] units): one path per colour bin.
fn cells_path(svg: &mut String, pic: &FieldPicture, f: &Frame, bin: &dyn Fn(f64) -> usize) {
    let mut by_bin = vec![Vec::new(); BINS + 1];
    let mut seen = HashSet::new();
    for (c, v) in &pic.cells {
        let k = if v.is_finite() { bin(*v) } else { BINS };
        if finite_box(c) && f.intersects(c) {
            let b = sub_box(c, f);
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
            *svg,
            "<path fill=\"{fill}\" shape-rendering=\"crispEdges\" d=\"{d}\"/>"
        );
    }
}

/// The colour of a value in the bins `bin`: its bin's viridis colour, grey without a finite value.
fn bin_colour(v: f64, bin: &dyn Fn(f64) -> usize) -> [u8; 3] {
    if !v.is_finite() {
        return [0xbb; 3];
    }
    let (r, g, b) = viridis((bin(v) as f64 + 0.5) / BINS as f64);
    [r, g, b]
}

/// The cells of a field of more than [`RASTER_MIN_CELLS`] cells as a raster of the frame (one
/// pixel per SVG pixel) in [`SUB`] units, coloured as [`cells_path`] colours them (the first
/// cell on a pixel colours it).
fn cells_raster(pic: &FieldPicture, f: &Frame, bin: &dyn Fn(f64) -> usize) -> String {
    let mut r = Raster::new(f.width(), f.height(), None);
    for (c, v) in pic.cells.iter().rev() {
        if finite_box(c) && f.intersects(c) {
            r.fill_box(
                f.px(c.x0) - f.left,
                f.px(c.x1) - f.left,
                f.py(c.y1) - f.top,
                f.py(c.y0) - f.top,
                bin_colour(*v, bin),
            );
        }
    }
    r.svg_image(f.left * SUB, f.top * SUB, SUB)
}

/// The colour bar of a field picture from `lo` to `hi` (five ticks, the field's name), and below
/// it the legend of the zone and of the `undefined` cells without a finite value.
fn colour_bar(
    svg: &mut String,
    margin: f64,
    bar_top: f64,
    bar_w: f64,
    (lo, hi): (f64, f64),
    pic: &FieldPicture,
    undefined: usize,
) {
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
            svg,
            x,
            bar_top + 35.0,
            13.0,
            anchor,
            &fmt_short(lo + t * (hi - lo)),
        );
    }
    text(
        svg,
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
            svg,
            margin + 30.0,
            legend_y,
            13.0,
            "start",
            &format!("{} ({} cells)", pic.zone_label, pic.zone.len()),
        );
    }
    if undefined > 0 {
        text(
            svg,
            margin + 320.0,
            legend_y,
            13.0,
            "start",
            &format!("grey: {undefined} cells without a finite value"),
        );
    }
}

/// A field (ψ, the cavitation zone, …) on the active cells after its cycle, one per field.
pub(super) struct Fields;

impl Figures for Fields {
    fn applies(&self, run: &RunResult) -> bool {
        !run.fields.is_empty()
    }

    fn write(&self, at: &Drawing) -> io::Result<Vec<Figure>> {
        let run = at.run;
        let mut figures = Vec::new();
        for (i, pic) in run.fields.iter().enumerate() {
            let kind = indexed(
                &format!("field-{}", file_stem(&pic.name)),
                i,
                run.fields.len(),
            );
            let (figure, path) = at.figure(
                &kind,
                format!(
                    "{}: {} on the active cells after cycle {}, x₁/x₂ axes{}",
                    run.table,
                    pic.name,
                    pic.cycle,
                    cf(&at.cited().solution)
                ),
            );
            figures.push(figure);
            field(&path, &run.table, pic, run.domain)?;
        }
        Ok(figures)
    }
}
