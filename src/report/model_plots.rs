//! The figures of the model-adaptive tables (§IV.2.3), written as SVG text like the mesh
//! pictures: the face split and the model error per cycle beside the thesis, and the partition
//! of the contact faces per cycle, Signorini black and z light grey (thesis Figs IV.35–IV.45).

use std::fmt::Write as _;
use std::io;
use std::path::Path;

use super::figures::{cf, Drawing, Figure, Figures};
use super::html::fmt_short;
use super::plots::{svg_open, text};
use crate::results::{columns, PartitionPicture, RunResult};
use crate::thesis::ThesisTable;

const TRIBO: &str = "#1f77b4";
const THESIS: &str = "#d62728";
const AXIS: &str = "#555555";
const GRID: &str = "#e6e6e6";

/// A panel: its frame in pixels and the data ranges it maps.
struct Panel {
    left: f64,
    top: f64,
    width: f64,
    height: f64,
    cycles: f64,
    /// y range; on a log panel, of log₁₀ y.
    y: (f64, f64),
    log: bool,
}

impl Panel {
    fn x(&self, cycle: f64) -> f64 {
        self.left + self.width * (cycle + 0.5) / (self.cycles + 1.0)
    }

    /// The pixel row of a value, `None` where it cannot be drawn (≤ 0 on a log panel).
    fn y(&self, v: f64) -> Option<f64> {
        let t = if self.log {
            if v.is_nan() || v <= 0.0 {
                return None;
            }
            v.log10()
        } else {
            v
        };
        t.is_finite()
            .then(|| self.top + self.height * (1.0 - (t - self.y.0) / (self.y.1 - self.y.0)))
    }

    fn frame(&self, svg: &mut String, title: &str) {
        let (l, t, w, h) = (self.left, self.top, self.width, self.height);
        let cycles = self.cycles as usize;
        for c in 0..=cycles {
            let x = self.x(c as f64);
            let _ = writeln!(
                svg,
                "<line x1=\"{x:.1}\" y1=\"{t:.1}\" x2=\"{x:.1}\" y2=\"{:.1}\" stroke=\"{GRID}\"/>",
                t + h
            );
            text(svg, x, t + h + 16.0, 12.0, "middle", &c.to_string());
        }
        let ticks: Vec<(f64, String)> = if self.log {
            let (lo, hi) = (self.y.0.ceil() as i32, self.y.1.floor() as i32);
            (lo..=hi)
                .map(|e| (10f64.powi(e), format!("1e{e}")))
                .collect()
        } else {
            let step = nice_step(self.y.1 - self.y.0);
            let n = ((self.y.1 - self.y.0) / step).floor() as i32;
            (0..=n)
                .map(|k| {
                    let v = self.y.0 + k as f64 * step;
                    // Rounded: k·step carries floating noise (0.30000000000000004).
                    (v, fmt_short(v))
                })
                .collect()
        };
        for (v, label) in ticks {
            if let Some(y) = self.y(v) {
                let _ = writeln!(
                    svg,
                    "<line x1=\"{l:.1}\" y1=\"{y:.1}\" x2=\"{:.1}\" y2=\"{y:.1}\" stroke=\"{GRID}\"/>",
                    l + w
                );
                text(svg, l - 6.0, y + 4.0, 12.0, "end", &label);
            }
        }
        let _ = writeln!(
            svg,
            "<rect x=\"{l:.1}\" y=\"{t:.1}\" width=\"{w:.1}\" height=\"{h:.1}\" fill=\"none\" \
             stroke=\"{AXIS}\"/>"
        );
        text(svg, l + w / 2.0, t - 10.0, 15.0, "middle", title);
        text(svg, l + w / 2.0, t + h + 34.0, 13.0, "middle", "cycle");
    }

    /// One curve: a polyline through the drawable points with markers; the thesis dashed with
    /// hollow squares. Values that cannot be drawn (0 on a log axis) are marked on the bottom
    /// edge with a small open circle.
    fn curve(&self, svg: &mut String, points: &[(f64, f64)], color: &str, dashed: bool) {
        let mut path = String::new();
        for &(c, v) in points {
            match self.y(v) {
                Some(y) => {
                    let x = self.x(c);
                    let _ = write!(
                        path,
                        "{}{x:.1},{y:.1} ",
                        if path.is_empty() { "M" } else { "L" }
                    );
                    if dashed {
                        let _ = writeln!(
                            svg,
                            "<rect x=\"{:.1}\" y=\"{:.1}\" width=\"8\" height=\"8\" fill=\"none\" \
                             stroke=\"{color}\" stroke-width=\"1.5\"/>",
                            x - 4.0,
                            y - 4.0
                        );
                    } else {
                        let _ = writeln!(
                            svg,
                            "<circle cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"3.5\" fill=\"{color}\"/>"
                        );
                    }
                }
                None if self.log && v == 0.0 => {
                    let (x, y) = (self.x(c), self.top + self.height - 5.0);
                    let _ = writeln!(
                        svg,
                        "<circle cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"3.5\" fill=\"none\" \
                         stroke=\"{color}\"/>"
                    );
                }
                None => {}
            }
        }
        if !path.is_empty() {
            let dash = if dashed {
                " stroke-dasharray=\"7 4\""
            } else {
                ""
            };
            let _ = writeln!(
                svg,
                "<path d=\"{path}\" fill=\"none\" stroke=\"{color}\" stroke-width=\"2\"{dash}/>"
            );
        }
    }
}

/// A step of 1, 2 or 5 times a power of ten giving 4–10 ticks over `span`.
fn nice_step(span: f64) -> f64 {
    if span.is_nan() || span <= 0.0 {
        return 1.0;
    }
    let raw = span / 6.0;
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|s| span / s <= 10.0)
        .unwrap_or(10.0 * p)
}

/// (cycle, value) of a column, tribo's rows and the thesis's.
fn series(run: &RunResult, thesis: &ThesisTable, column: &str) -> [Vec<(f64, f64)>; 2] {
    let tribo = run
        .rows
        .iter()
        .filter_map(|r| Some((r.cycle as f64, r.value(column)?)))
        .collect();
    let printed = thesis
        .rows
        .iter()
        .filter_map(|r| Some((*r.first()?, thesis.value(*r.first()? as usize, column)?)))
        .collect();
    [tribo, printed]
}

/// The Signorini faces and the model error per cycle, tribo (solid) beside the thesis (dashed).
pub fn model_adaptivity(path: &Path, run: &RunResult, thesis: &ThesisTable) -> io::Result<()> {
    let faces = series(run, thesis, columns::ACCURATE_FACES);
    let errors = series(run, thesis, columns::MODEL_ERROR);
    let cycles = faces
        .iter()
        .chain(&errors)
        .flatten()
        .map(|p| p.0)
        .fold(0.0, f64::max);
    let max_faces = faces.iter().flatten().map(|p| p.1).fold(1.0, f64::max);
    let positive: Vec<f64> = errors
        .iter()
        .flatten()
        .map(|p| p.1)
        .filter(|v| *v > 0.0 && v.is_finite())
        .collect();
    let (lo, hi) = positive
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v.log10()), hi.max(v.log10()))
        });
    let (lo, hi) = if lo.is_finite() {
        (lo.floor() - 0.3, hi.ceil() + 0.1)
    } else {
        (-1.0, 1.0)
    };
    // One panel above the other, 760 pixels wide: the width the page shows a plot at, so the
    // text keeps its size.
    let (width, height) = (760.0, 660.0);
    let mut svg = svg_open(width, height);
    let panel = |top: f64, y: (f64, f64), log: bool| Panel {
        left: 80.0,
        top,
        width: 640.0,
        height: 220.0,
        cycles,
        y,
        log,
    };
    let upper = panel(
        70.0,
        (
            0.0,
            nice_step(max_faces) * (max_faces / nice_step(max_faces)).ceil(),
        ),
        false,
    );
    let lower = panel(380.0, (lo, hi), true);
    upper.frame(&mut svg, "Signorini faces |𝕋_a|");
    lower.frame(&mut svg, "model error (Σ over z-faces)^½ — open circles: 0");
    for (panel, [tribo, printed]) in [(&upper, &faces), (&lower, &errors)] {
        panel.curve(&mut svg, printed, THESIS, true);
        panel.curve(&mut svg, tribo, TRIBO, false);
    }
    let printed = faces[1].len() + errors[1].len() > 0;
    let what = if printed {
        "tribo (solid, dots), thesis (dashed, squares)"
    } else {
        "tribo"
    };
    text(
        &mut svg,
        width / 2.0,
        26.0,
        17.0,
        "middle",
        &format!("{} — model adaptivity: {what}", run.table),
    );
    svg.push_str("</svg>\n");
    crate::fsio::write(path, svg)
}

/// The models of the contact faces per printed cycle: one strip per cycle and contact side,
/// Signorini faces black, z-faces light grey (thesis Figs IV.35–IV.45).
pub fn partitions(path: &Path, run: &RunResult, domain: [f64; 4]) -> io::Result<()> {
    let [x0, x1, ..] = domain;
    let sides: Vec<String> = {
        let mut s: Vec<String> = run
            .partitions
            .iter()
            .flat_map(|p| p.faces.iter().map(|f| f.side.clone()))
            .collect();
        s.sort();
        s.dedup();
        // Top above bottom, as in the body.
        s.sort_by_key(|name| name != "top");
        s
    };
    let strip = 12.0;
    let gap = 10.0;
    let row = strip * sides.len() as f64 + gap;
    // 760 pixels wide, the width the page shows a plot at: wider, its text would shrink.
    let (left, right, width) = (120.0, 720.0, 760.0);
    let top = 70.0;
    let height = top + row * run.partitions.len() as f64 + 40.0;
    let mut svg = svg_open(width, height);
    text(
        &mut svg,
        width / 2.0,
        24.0,
        17.0,
        "middle",
        &format!("{} — contact faces per cycle", run.table),
    );
    text(
        &mut svg,
        width / 2.0,
        48.0,
        13.0,
        "middle",
        &format!("Signorini black, z light grey ({})", sides.join(" above ")),
    );
    let px = |x: f64| left + (right - left) * (x - x0) / (x1 - x0);
    for (k, picture) in run.partitions.iter().enumerate() {
        let y0 = top + row * k as f64;
        strip_row(&mut svg, picture, &sides, y0, strip, &px);
        let n = picture.faces.iter().filter(|f| f.accurate).count();
        text(
            &mut svg,
            left - 8.0,
            y0 + strip * sides.len() as f64 / 2.0 + 4.0,
            12.0,
            "end",
            &format!("cycle {}: {n} S", picture.cycle),
        );
    }
    let y = top + row * run.partitions.len() as f64 + 14.0;
    for x in [x0, (x0 + x1) / 2.0, x1] {
        text(&mut svg, px(x), y, 12.0, "middle", &format!("x₁ = {x}"));
    }
    svg.push_str("</svg>\n");
    crate::fsio::write(path, svg)
}

fn strip_row(
    svg: &mut String,
    picture: &PartitionPicture,
    sides: &[String],
    y0: f64,
    strip: f64,
    px: &dyn Fn(f64) -> f64,
) {
    for (i, side) in sides.iter().enumerate() {
        let y = y0 + strip * i as f64;
        for accurate in [false, true] {
            let mut path = String::new();
            for f in picture
                .faces
                .iter()
                .filter(|f| &f.side == side && f.accurate == accurate)
            {
                let (a, b) = (px(f.x0), px(f.x1));
                let _ = write!(path, "M{a:.2},{y:.1}H{b:.2}V{:.1}H{a:.2}Z", y + strip - 1.0);
            }
            if !path.is_empty() {
                let fill = if accurate { "#000000" } else { "#d0d0d0" };
                let _ = writeln!(svg, "<path d=\"{path}\" fill=\"{fill}\"/>");
            }
        }
    }
}

/// The face split and the model error per cycle of a model-adaptive run: a fixed mesh, so no
/// convergence in dofs.
pub(super) struct ModelAdaptivity;

impl Figures for ModelAdaptivity {
    fn applies(&self, run: &RunResult) -> bool {
        run.is_model_adaptive()
    }

    fn write(&self, at: &Drawing) -> io::Result<Vec<Figure>> {
        let run = at.run;
        let (figure, path) = at.figure(
            "model",
            format!(
                "{}: Signorini faces and model error per cycle, {}; the partitions are in the \
                 next figure{}",
                run.table,
                if at.thesis.is_empty() {
                    "tribo"
                } else {
                    "tribo (solid) and thesis (dashed)"
                },
                cf(&at.cited().model)
            ),
        );
        model_adaptivity(&path, run, at.thesis)?;
        Ok(vec![figure])
    }
}

/// The contact faces per cycle, on the undeformed strip (so not of a load-step run).
pub(super) struct Partition;

impl Figures for Partition {
    fn applies(&self, run: &RunResult) -> bool {
        run.has_partitions() && !run.is_load_steps()
    }

    fn write(&self, at: &Drawing) -> io::Result<Vec<Figure>> {
        let run = at.run;
        // Model and grid adaptivity: the faces change with the mesh.
        let mesh = if run.is_model_adaptive() {
            ""
        } else {
            " on the adapted mesh"
        };
        let (figure, path) = at.figure(
            "partition",
            format!(
                "{}: the contact faces per cycle{mesh}, Signorini black and z light grey{}",
                run.table,
                cf(&at.cited().model)
            ),
        );
        partitions(&path, run, run.domain)?;
        Ok(vec![figure])
    }
}
