//! The mesh pictures: the active cells after the drawn cycles, coloured by refinement level
//! (with a zoom onto the finest cells of a thin domain), or shaded by model, with the
//! Signorini faces. Written as SVG text directly: a picture holds up to hundreds of thousands
//! of cells, merged into a few `<path>`s with integer coordinates.

use std::collections::HashSet;
use std::fmt::Write as _;
use std::io;
use std::path::Path;

use super::figures::{cf, Drawing, Figure, Figures};
use super::html::fmt_short;
use super::plots::*;
use super::raster::{mix, rgb, Raster, RASTER_MIN_CELLS};
use crate::results::{CellBox, MeshPicture, PartitionPicture, RunResult};

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
    if cells.len() > RASTER_MIN_CELLS {
        let _ = writeln!(
            svg,
            "{}\n<rect x=\"{l:.1}\" y=\"{t:.1}\" width=\"{w:.1}\" height=\"{h:.1}\" fill=\"none\" stroke=\"black\" stroke-width=\"1\"/>",
            levels_raster(cells, levels, range, f)
        );
        return;
    }
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

/// [`draw_mesh_levels`] for a mesh of more than [`RASTER_MIN_CELLS`] cells: the cells painted
/// into a raster of the frame (coarse levels first, so that where sub-pixel cells share a pixel
/// the finest level colours it, as in the vector picture), the edges of the cells at least
/// [`EDGE_MIN_PX`] wide as one-pixel lines of [`MESH_LINE`] lightened to the weight of its
/// half-pixel stroke; an `<image>` in pixels.
fn levels_raster(cells: &[CellBox], levels: &[u8], range: (u8, u8), f: &Frame) -> String {
    let mut r = Raster::new(f.width(), f.height(), Some([255, 255, 255]));
    let mut order: Vec<usize> = (0..cells.len().min(levels.len()))
        .filter(|&i| finite_box(&cells[i]) && f.intersects(&cells[i]))
        .collect();
    order.sort_by_key(|&i| levels[i]);
    let corners = |c: &CellBox| {
        (
            f.px(c.x0) - f.left,
            f.px(c.x1) - f.left,
            f.py(c.y1) - f.top,
            f.py(c.y0) - f.top,
        )
    };
    for &i in &order {
        let (x0, x1, y0, y1) = corners(&cells[i]);
        r.fill_box(x0, x1, y0, y1, rgb(&level_color(levels[i], range)));
    }
    let edge = mix([255, 255, 255], rgb(MESH_LINE), 0.6);
    for &i in &order {
        let c = &cells[i];
        if (c.x1 - c.x0).min(c.y1 - c.y0) * f.scale < EDGE_MIN_PX {
            continue;
        }
        let (x0, x1, y0, y1) = corners(c);
        for (a, b) in [
            ((x0, y0), (x1, y0)),
            ((x1, y0), (x1, y1)),
            ((x1, y1), (x0, y1)),
            ((x0, y1), (x0, y0)),
        ] {
            r.line(a, b, edge);
        }
    }
    r.svg_image(f.left, f.top, 1.0)
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
            13.0,
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
///
/// A mesh the cycles do not change ([`fixed_mesh`]: the model-adaptive tables IV.18–IV.29
/// adapt the model only) is drawn once, labelled with every cycle drawn.
pub fn meshes(
    path: &Path,
    meshes: &[MeshPicture],
    domain: [f64; 4],
    partitions: &[PartitionPicture],
) -> io::Result<()> {
    let signorini = |body: &mut String, cycle: usize, frame: &Frame| {
        signorini_faces(body, partitions, domain, cycle, frame)
    };
    let fixed = fixed_mesh(meshes);
    let cycles_label = |m: &MeshPicture| {
        if fixed {
            let cycles: Vec<String> = meshes.iter().map(|m| m.cycle.to_string()).collect();
            format!(
                "cycles {}: the same mesh  ({} cells)",
                cycles.join(", "),
                m.cells.len()
            )
        } else {
            format!("cycle {}  ({} cells)", m.cycle, m.cells.len())
        }
    };
    let meshes = if fixed { &meshes[..1] } else { meshes };
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
            text(&mut body, left, y + 15.0, 15.0, "start", &cycles_label(m));
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
                detail_caption(&mut body, left + detail_w + 16.0, y, dwin, (level, finest));
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
            text(&mut body, left, top + 15.0, 15.0, "start", &cycles_label(m));
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
    crate::fsio::write(path, svg)
}

/// Whether the drawn meshes are one mesh: more than one cycle drawn, all with the same cells.
fn fixed_mesh(meshes: &[MeshPicture]) -> bool {
    meshes.len() > 1 && meshes.windows(2).all(|w| w[0].cells == w[1].cells)
}

/// The Signorini faces of `partitions` in cycle `cycle` as thick black lines on the side of the
/// domain they lie on, within `frame`.
fn signorini_faces(
    body: &mut String,
    partitions: &[PartitionPicture],
    domain: [f64; 4],
    cycle: usize,
    frame: &Frame,
) {
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
}

/// The two lines beside a detail of a strip, at `x` and from `y` down: its window, and the
/// level and width of the finest cells it is centred on.
fn detail_caption(body: &mut String, x: f64, y: f64, dwin: [f64; 4], (level, finest): (u8, f64)) {
    text(
        body,
        x,
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
        body,
        x,
        y + 38.0,
        14.0,
        "start",
        &format!(
            "around the finest cells (level {level}, width {})",
            fmt_short(finest)
        ),
    );
}

/// The active cells after the drawn cycles (not of a load-step run: its cells move).
pub(super) struct Meshes;

impl Figures for Meshes {
    fn applies(&self, run: &RunResult) -> bool {
        !run.meshes.is_empty() && !run.is_load_steps()
    }

    fn write(&self, at: &Drawing) -> io::Result<Vec<Figure>> {
        let run = at.run;
        let cycles: Vec<String> = run.meshes.iter().map(|m| m.cycle.to_string()).collect();
        // The Signorini faces on the adapted meshes of the model-and-grid tables.
        let partitions: &[_] = if run.is_model_adaptive() {
            &[]
        } else {
            &run.partitions
        };
        let (figure, path) = at.figure(
            "mesh",
            format!(
                "{}: {} {}{}{}",
                run.table,
                if fixed_mesh(&run.meshes) {
                    "the fixed mesh of cycles"
                } else {
                    "active cells after cycle"
                },
                cycles.join(", "),
                if !partitions.is_empty() {
                    "; Signorini faces thick black"
                } else if run.meshes.iter().any(|m| !m.shaded.is_empty()) {
                    "; SubStokes cells grey, Reynolds cells white"
                } else {
                    ", coloured by refinement level, with x₁/x₂ axes; a thin domain is followed \
                     by a zoom onto its finest cells"
                },
                cf(&at.cited().grids)
            ),
        );
        meshes(&path, &run.meshes, run.domain, partitions)?;
        Ok(vec![figure])
    }
}
