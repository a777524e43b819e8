//! The deformed-body pictures: the cells moved by the displacement, the obstacles hatched on
//! their solid side, the Signorini faces and the vertices in contact. Written as SVG text
//! directly, and shared with the frames of a load-step run (`forming`).

use std::collections::HashSet;
use std::fmt::Write as _;
use std::io;
use std::path::Path;

use super::figures::{cf, indexed, Drawing, Figure, Figures};
use super::html::fmt_short;
use super::plots::*;
use super::raster::{mix, rgb, Raster, RASTER_MIN_CELLS};
use crate::results::{DeformedPicture, RunResult};

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
    let raster = (pic.quads.len() > RASTER_MIN_CELLS).then_some(1.0);
    deformed_drawing(&mut svg, title, pic, &canvas.frame, true, raster);
    axes(&mut svg, &canvas.frame);
    svg.push_str("</svg>\n");
    crate::fsio::write(path, svg)
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
            height: frame.top + frame.height() + AXIS_BELOW + 60.0 + CAPTION_LINE,
            frame,
        }
    }
}

/// Id of the clip path of a deformed-body picture's window.
pub(super) const DEFORMED_CLIP: &str = "c";

/// Id of the hatch pattern of the obstacles' solid side in a deformed-body picture.
pub(super) const OBSTACLE_HATCH: &str = "solid";

/// Fill of the body's cells.
const BODY_FILL: &str = "#d6e4f2";
/// Outline of the body's cells.
const BODY_LINE: &str = "#4a6a8a";

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

/// The points of a polyline (sub-pixel units) without those within a pixel of the point kept
/// before them, the last always kept: an obstacle sampled at thousands of points per curve
/// (the forming's die and punch) is drawn with one point per pixel of its length.
fn thin(pts: Vec<(i64, i64)>) -> Vec<(i64, i64)> {
    let px = SUB as i64;
    let n = pts.len();
    let mut kept: Vec<(i64, i64)> = Vec::with_capacity(n);
    for (i, p) in pts.into_iter().enumerate() {
        let near = kept
            .last()
            .is_some_and(|q| (p.0 - q.0).abs() < px && (p.1 - q.1).abs() < px);
        if !near || i + 1 == n {
            kept.push(p);
        }
    }
    kept
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
        let pts = thin(pts);
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
/// ([`deformed_clip`]) is written here; an animation of several pictures defines it once. With
/// `raster` (SVG pixels per raster pixel) the body's cells are a raster image ([`body_raster`];
/// for a picture, or all frames of an animation, of more than [`RASTER_MIN_CELLS`] cells), else
/// vector paths.
pub(super) fn deformed_drawing(
    svg: &mut String,
    title: &str,
    pic: &DeformedPicture,
    f: &Frame,
    define_clip: bool,
    raster: Option<f64>,
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
    if let Some(pixel) = raster {
        svg.push_str(&body_raster(pic, f, pixel));
        svg.push('\n');
    } else {
        svg.push_str(&body_path(pic, f));
    }
    let finite = |p: &&[f64; 2]| p[0].is_finite() && p[1].is_finite();
    let mut d = String::new();
    for line in &pic.obstacles {
        let pts = thin(
            line.iter()
                .filter(finite)
                .map(|p| f.sub(p[0], p[1]))
                .collect(),
        );
        for (i, (x, y)) in pts.into_iter().enumerate() {
            let _ = write!(d, "{}{x} {y}", if i == 0 { "M" } else { "L" });
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

    deformed_legend(svg, pic, f, margin);
}

/// The body's quadrilaterals as one vector path (in [`SUB`] units), filled light and outlined.
fn body_path(pic: &DeformedPicture, f: &Frame) -> String {
    let mut svg = String::new();
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
        &mut svg,
        "<path fill=\"{BODY_FILL}\" stroke=\"{BODY_LINE}\" stroke-width=\"{}\" stroke-linejoin=\"round\" d=\"{d}\"/>",
        0.5 * SUB
    );
    svg
}

/// The body's quadrilaterals painted into a raster of the frame `f` (`pixel` SVG pixels per
/// raster pixel),
/// as an `<image>` in [`SUB`] units: filled light with one-pixel edges of the colour four fifths of
/// the way to the outline of [`body_path`] (a half-pixel stroke as a whole pixel), so that a region of
/// sub-pixel cells turns as dark as in the vector picture.
fn body_raster(pic: &DeformedPicture, f: &Frame, pixel: f64) -> String {
    let fill = rgb(BODY_FILL);
    let edge = mix(fill, rgb(BODY_LINE), 0.8);
    let mut r = Raster::new(f.width() / pixel, f.height() / pixel, None);
    let at = |p: &[f64; 2]| ((f.px(p[0]) - f.left) / pixel, (f.py(p[1]) - f.top) / pixel);
    let quads: Vec<[(f64, f64); 4]> = pic
        .quads
        .iter()
        .filter(finite_quad)
        .map(|q| [at(&q[0]), at(&q[1]), at(&q[2]), at(&q[3])])
        .collect();
    for q in &quads {
        r.fill_quad(q, fill);
    }
    for q in &quads {
        for i in 0..4 {
            r.line(q[i], q[(i + 1) % 4], edge);
        }
    }
    r.svg_image(f.left * SUB, f.top * SUB, pixel * SUB)
}

/// The legend under a deformed-body picture (only for one with an obstacle or Signorini faces)
/// and its caption; `margin` is the picture's left margin.
fn deformed_legend(svg: &mut String, pic: &DeformedPicture, f: &Frame, margin: f64) {
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
    // A caption too long for the picture's width (a square domain is a narrow picture) goes on
    // two lines, split at its "; ".
    let width = f.left + f.width() + margin;
    let fits = pic.caption.chars().count() as f64 * 7.6 <= width - 2.0 * margin;
    match pic.caption.split_once("; ") {
        Some((first, second)) if !fits => {
            text(svg, margin, y + 28.0, 14.0, "start", &format!("{first};"));
            text(svg, margin, y + 28.0 + CAPTION_LINE, 14.0, "start", second);
        }
        _ => text(svg, margin, y + 28.0, 14.0, "start", &pic.caption),
    }
}

/// The height of the caption's second line, where it needs one.
const CAPTION_LINE: f64 = 18.0;

/// Class of the path of the Signorini faces in a deformed-body picture (what the tests look for).
pub(super) const SIGNORINI_CLASS: &str = "signorini-faces";

/// Width in pixels of the Signorini faces, as in the mesh figure of Tables IV.30–IV.35.
const SIGNORINI_WIDTH: f64 = 4.0;

/// The deformed body after each drawn cycle (a load-step run gets its animation instead).
pub(super) struct Deformed;

impl Figures for Deformed {
    fn applies(&self, run: &RunResult) -> bool {
        !run.is_load_steps() && !run.deformed.is_empty()
    }

    fn write(&self, at: &Drawing) -> io::Result<Vec<Figure>> {
        let run = at.run;
        let mut figures = Vec::new();
        for (i, pic) in run.deformed.iter().enumerate() {
            let kind = indexed("deformed", i, run.deformed.len());
            let (figure, path) = at.figure(
                &kind,
                format!(
                    "{}: deformed body after cycle {}, displacement × {}{}{}{}",
                    run.table,
                    pic.cycle,
                    fmt_short(pic.scale),
                    if pic.accurate_faces.is_empty() {
                        ""
                    } else {
                        "; Signorini faces thick black"
                    },
                    if pic.obstacles.is_empty() {
                        ""
                    } else {
                        "; obstacles brown, hatched on their solid side"
                    },
                    cf(&at.cited().solution)
                ),
            );
            figures.push(figure);
            deformed(&path, &run.table, pic)?;
        }
        Ok(figures)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thinning_keeps_one_point_per_pixel_and_the_ends() {
        let px = SUB as i64;
        // 100 points a tenth of a pixel apart: 10 pixels long.
        let pts: Vec<(i64, i64)> = (0..100).map(|i| (i, 0)).collect();
        let kept = thin(pts);
        assert_eq!(kept.first(), Some(&(0, 0)));
        assert_eq!(kept.last(), Some(&(99, 0)));
        assert!(kept.windows(2).rev().skip(1).all(|w| w[1].0 - w[0].0 >= px));
        assert_eq!(kept.len(), 11);
    }
}
