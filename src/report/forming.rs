//! The figures of a load-step run: the U-O (J) forming of thesis §IV.2.4.7, whose result the
//! thesis shows only as the pictures of Fig. IV.54.
//!
//! - frames `<stem>-step-NN.svg`: the body after each load step, all in one fixed view, so that
//!   stepping through them shows the motion between the punch and the die;
//! - `<stem>-animation.svg`: the same frames in one self-contained SVG, cycled by SMIL (it runs
//!   inside an `<img>`, with no script and no reference to another file);
//! - `<stem>-steps.svg`: what changes from step to step — the tip's position, the split of the
//!   contact faces into z and Signorini, the penetration and the model error, and the punch and
//!   die forces against the stroke.
//!
//! The frames and the animation draw each body with [`deformed::deformed_drawing`], the code of
//! every other deformed-body picture.

use std::collections::HashSet;
use std::fmt::Write as _;
use std::io;
use std::path::Path;

use plotters::coord::ranged1d::ValueFormatter;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::deformed::{self, deformed_clip, deformed_drawing, deformed_window, DeformedCanvas};
use super::figures::{cf, Drawing, Figure, Figures};
use super::html::fmt_short;
use super::legend::{self, Entry, Placed};
use super::plots::{
    self, bbox, log_range, log_tick, plot_err, solid_curve, svg_open, text, Curve, NiceLog,
    RIGHT_MARGIN,
};
use crate::experiment::ThesisFigures;
use crate::results::{columns, DeformedPicture, RunResult};

/// Seconds each frame of the animation is shown.
pub(super) const FRAME_SECONDS: f64 = 0.4;
/// Extra seconds the last frame stays before the animation starts again.
pub(super) const FINAL_PAUSE_SECONDS: f64 = 1.6;

/// A frame written for a load-step run: its file inside `figures/` and its load step.
pub(super) struct FrameFile {
    pub file: String,
    pub step: usize,
}

/// The pictures of a run, one per load step, in step order; of two pictures of the same step the
/// first (a run records one per step, so this only guards the file names).
fn pictures_by_step(run: &RunResult) -> Vec<&DeformedPicture> {
    let mut seen = HashSet::new();
    let mut pics: Vec<&DeformedPicture> = run
        .deformed
        .iter()
        .filter(|p| seen.insert(p.cycle))
        .collect();
    pics.sort_by_key(|p| p.cycle);
    pics
}

/// The one view all frames share: the union of the frames' own views (each body with the
/// obstacle parts near it, [`deformed_window`]); `None` when no frame has a finite body.
fn shared_window(pics: &[&DeformedPicture]) -> Option<[f64; 4]> {
    bbox(
        pics.iter()
            .filter_map(|p| deformed_window(p))
            .flat_map(|w| [(w[0], w[2]), (w[1], w[3])]),
    )
}

/// The title of the frame of one load step.
fn frame_title(table: &str, pic: &DeformedPicture) -> String {
    let scale = if pic.scale == 1.0 {
        "true scale".to_string()
    } else {
        format!("displacement × {}", fmt_short(pic.scale))
    };
    format!(
        "{table} — load step {}: the body after the step's motion, {scale}",
        pic.cycle
    )
}

/// Draw the frames `<stem>-step-NN.svg` (NN the load step, two digits) of a load-step run into
/// `fig_dir` and their animation into `animation`; return the frames in step order.
///
/// Every frame shows the same window ([`shared_window`]), obstacles clipped to it. A run without
/// a finite body gets placeholder frames and a placeholder animation.
pub(super) fn frames(
    fig_dir: &Path,
    stem: &str,
    run: &RunResult,
    animation: &Path,
) -> io::Result<Vec<FrameFile>> {
    let pics = pictures_by_step(run);
    let win = shared_window(&pics);
    let mut files = Vec::with_capacity(pics.len());
    for pic in &pics {
        let file = format!("{stem}-step-{:02}.svg", pic.cycle);
        let path = fig_dir.join(&file);
        let title = frame_title(&run.table, pic);
        match win {
            Some(win) => deformed::deformed_in(&path, &title, pic, win)?,
            None => plots::placeholder(&path, &title, "no finite cells to draw")?,
        }
        files.push(FrameFile {
            file,
            step: pic.cycle,
        });
    }
    match win {
        Some(win) => write_animation(animation, &run.table, &pics, win)?,
        None => plots::placeholder(
            animation,
            &format!("{} — load steps", run.table),
            "no finite cells to draw",
        )?,
    }
    Ok(files)
}

/// The animation: every frame's drawing as a `<g class="frame">` in one SVG, shown in turn for
/// [`FRAME_SECONDS`] each, the last one [`FINAL_PAUSE_SECONDS`] longer, looping for ever. Without
/// SMIL (a static renderer) the last frame shows.
fn write_animation(
    path: &Path,
    table: &str,
    pics: &[&DeformedPicture],
    win: [f64; 4],
) -> io::Result<()> {
    let canvas = DeformedCanvas::new(win);
    let f = &canvas.frame;
    let mut svg = svg_open(canvas.width, canvas.height);
    let _ = writeln!(svg, "<defs>{}</defs>", deformed_clip(f));
    let last_step = pics.last().map_or(0, |p| p.cycle);
    // The frames together are many cells: a raster each, at half the resolution of a picture
    // (the animation shows the motion, the step frames the cells).
    let raster = (pics.iter().map(|p| p.quads.len()).sum::<usize>()
        > super::raster::RASTER_MIN_CELLS)
        .then_some(2.0);
    for (i, pic) in pics.iter().enumerate() {
        let shown = if i + 1 == pics.len() {
            "visible"
        } else {
            "hidden"
        };
        let _ = writeln!(
            svg,
            "<g class=\"frame\" id=\"step-{:02}\" visibility=\"{shown}\">",
            pic.cycle
        );
        deformed_drawing(&mut svg, &frame_title(table, pic), pic, f, false, raster);
        text(
            &mut svg,
            canvas.width - DeformedCanvas::MARGIN,
            26.0,
            17.0,
            "end",
            &format!("step {} / {last_step}", pic.cycle),
        );
        svg.push_str(&visibility_animation(i, pics.len()));
        svg.push_str("</g>\n");
    }
    // One window for every frame: its axes are drawn once.
    plots::axes(&mut svg, f);
    svg.push_str("</svg>\n");
    crate::fsio::write(path, svg)
}

/// The SMIL element that shows frame `i` of `n` in its time slot of the loop: one `<animate>` of
/// `visibility` per frame, discrete, all with the same period and `repeatCount="indefinite"`, so
/// they stay in step. A single frame needs none.
fn visibility_animation(i: usize, n: usize) -> String {
    if n < 2 {
        return String::new();
    }
    let period = n as f64 * FRAME_SECONDS + FINAL_PAUSE_SECONDS;
    let at = |k: usize| k as f64 * FRAME_SECONDS / period;
    let (values, key_times) = if i == 0 {
        ("visible;hidden", format!("0;{:.6}", at(1)))
    } else if i + 1 == n {
        ("hidden;visible", format!("0;{:.6}", at(i)))
    } else {
        (
            "hidden;visible;hidden",
            format!("0;{:.6};{:.6}", at(i), at(i + 1)),
        )
    };
    format!(
        "<animate attributeName=\"visibility\" values=\"{values}\" keyTimes=\"{key_times}\" \
         calcMode=\"discrete\" dur=\"{period:.2}s\" repeatCount=\"indefinite\"/>\n"
    )
}

const TIP_X: RGBColor = RGBColor(31, 119, 180);
const TIP_Y: RGBColor = RGBColor(214, 39, 40);
const Z_FACES: RGBColor = RGBColor(150, 150, 150);
const S_FACES: RGBColor = RGBColor(0, 0, 0);
const PENETRATION: RGBColor = RGBColor(255, 127, 14);
const MODEL_ERROR: RGBColor = plots::TRIBO_ME;
const PUNCH: RGBColor = RGBColor(140, 86, 75);
const DIE: RGBColor = RGBColor(148, 103, 189);

/// The per-step chart of a load-step run (thesis §IV.2.4.7, Fig. IV.54 shows only the bodies):
/// against the load step, the tip's position (`tip_x`, `tip_y`), the contact faces on the z- and
/// the Signorini model (`z_faces`, `s_faces`), on a log axis the penetration and the model
/// error (values ≤ 0 or undefined are not drawn, so a step without penetration leaves a gap),
/// and the force–stroke curve: the contact force on the punch (the top side) and on the die
/// (the bottom side), Σλᵢ of each side's active constraints
/// ([`crate::study::quantities::contact`]), against the step — the stroke, since the rising
/// tools rise by the same lift in every step.
pub(super) fn steps(path: &Path, run: &RunResult) -> io::Result<Placed> {
    let curve = |column: &str, color: RGBColor| Curve {
        label: column.to_string(),
        color,
        dashed: false,
        points: run
            .rows
            .iter()
            .filter_map(|r| Some((r.cycle as f64, r.value(column)?)))
            .filter(|(_, v)| v.is_finite())
            .collect(),
    };
    let tip = [curve(columns::TIP_X, TIP_X), curve(columns::TIP_Y, TIP_Y)];
    let faces = [
        curve(columns::Z_FACES, Z_FACES),
        curve(columns::S_FACES, S_FACES),
    ];
    let mut errors = [
        curve(columns::PENETRATION, PENETRATION),
        curve(columns::MODEL_ERROR, MODEL_ERROR),
    ];
    for c in &mut errors {
        c.points.retain(|(_, v)| *v > 0.0);
    }
    let forces = [
        Curve {
            label: "punch (top)".to_string(),
            ..curve("contact_force_top", PUNCH)
        },
        Curve {
            label: "die (bottom)".to_string(),
            ..curve("contact_force_bottom", DIE)
        },
    ];
    // The steps of a run are 0, 1, …, its last.
    let last = run.rows.iter().map(|r| r.cycle).max().unwrap_or(1) as f64;
    let x = -0.5..(last + 0.5);

    let mut svg = String::new();
    let mut placed = Placed::default();
    {
        // Each panel 320 pixels and its legend of two entries.
        let strip = legend::height(&tip.iter().map(Entry::curve).collect::<Vec<_>>(), 760);
        let root = SVGBackend::with_string(&mut svg, (760, 4 * (320 + strip))).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let panels = root.split_evenly((4, 1));
        let linear = |curves: &[Curve]| -> RangedCoordf64 {
            linear_range(curves.iter().flat_map(|c| &c.points)).into()
        };
        placed.extend(step_panel(
            &panels[0],
            &format!(
                "{} — the tip (the lower right corner of the undeformed body)",
                run.table
            ),
            "position",
            (x.clone(), linear(&tip)),
            &tip,
            &|v| fmt_short(*v),
        )?);
        placed.extend(step_panel(
            &panels[1],
            "contact faces: z-model and Signorini",
            "faces",
            (x.clone(), linear(&faces)),
            &faces,
            &|v| fmt_short(*v),
        )?);
        let log = NiceLog::new(log_range(
            errors.iter().flat_map(|c| c.points.iter().map(|p| p.1)),
        ));
        placed.extend(step_panel(
            &panels[2],
            "penetration and model error (log; zeros not drawn)",
            "value",
            (x.clone(), log),
            &errors,
            &log_tick,
        )?);
        placed.extend(step_panel(
            &panels[3],
            "force against the stroke: contact force Σλᵢ on punch and die",
            "force [F/L]",
            (x, linear(&forces)),
            &forces,
            &|v| fmt_short(*v),
        )?);
        root.present().map_err(plot_err)?;
    }
    crate::fsio::write(path, svg)?;
    Ok(placed)
}

/// A linear axis range around the finite values, padded; a single value or none still gives a
/// non-empty range.
fn linear_range<'a>(points: impl Iterator<Item = &'a (f64, f64)>) -> std::ops::Range<f64> {
    let (lo, hi) = points
        .map(|p| p.1)
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return 0.0..1.0;
    }
    let pad = if hi > lo {
        0.08 * (hi - lo)
    } else {
        0.5_f64.max(0.1 * hi.abs())
    };
    (lo - pad)..(hi + pad)
}

/// The points split into runs of consecutive steps (x one apart).
fn consecutive_runs(points: &[(f64, f64)]) -> Vec<&[(f64, f64)]> {
    let mut runs = Vec::new();
    let mut start = 0;
    for i in 1..=points.len() {
        if i == points.len() || points[i].0 - points[i - 1].0 > 1.5 {
            runs.push(&points[start..i]);
            start = i;
        }
    }
    runs.retain(|r| !r.is_empty());
    runs
}

/// One panel of [`steps`]: `curves` as lines with dots against the load step, x ticks at whole
/// steps, the legend under it, and a note where there is nothing to draw.
fn step_panel<Y>(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    title: &str,
    y_desc: &str,
    (x, y): (std::ops::Range<f64>, Y),
    curves: &[Curve],
    y_format: &dyn Fn(&f64) -> String,
) -> io::Result<Placed>
where
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let steps = (x.end - x.start).round().max(1.0) as usize;
    let drawn: Vec<&Curve> = curves.iter().filter(|c| !c.points.is_empty()).collect();
    let entries: Vec<Entry> = drawn.iter().map(|c| Entry::curve(c)).collect();
    // The strip is kept when there is nothing to draw, so the panels stay aligned.
    let all: Vec<Entry> = curves.iter().map(Entry::curve).collect();
    let (area, strip) = legend::split(area, &all);
    let mut chart = ChartBuilder::on(&area)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .margin_right(RIGHT_MARGIN)
        .x_label_area_size(44)
        .y_label_area_size(70)
        .build_cartesian_2d(x, y)
        .map_err(plot_err)?;
    let step_label = |v: &f64| {
        let j = v.round();
        if (v - j).abs() < 1e-6 && j >= 0.0 {
            format!("{j:.0}")
        } else {
            String::new()
        }
    };
    chart
        .configure_mesh()
        .x_labels(steps.min(13) + 1)
        .y_labels(8)
        .x_label_formatter(&step_label)
        .y_label_formatter(y_format)
        .x_desc("load step j")
        .y_desc(y_desc)
        .light_line_style(RGBColor(240, 240, 240))
        .bold_line_style(RGBColor(215, 215, 215))
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 15))
        .draw()
        .map_err(plot_err)?;
    if drawn.is_empty() {
        area.draw(&Text::new(
            "nothing to plot",
            (300, 140),
            ("sans-serif", 18).into_font().color(&plots::GUIDE),
        ))
        .map_err(plot_err)?;
        return Ok(Placed::default());
    }
    for c in &drawn {
        // A step without a value (0 on the log axis) breaks the line instead of being bridged.
        solid_curve(&mut chart, c, &consecutive_runs(&c.points))?;
    }
    Ok(Placed {
        points: legend::pixels(&chart, drawn.iter().flat_map(|c| c.points.clone())),
        legends: legend::draw(&strip, &entries)?.into_iter().collect(),
    })
}

/// The per-step chart of a load-step run: tip, contact faces, penetration and model error.
pub(super) struct Steps;

impl Figures for Steps {
    fn applies(&self, run: &RunResult) -> bool {
        !run.is_model_adaptive() && run.is_load_steps()
    }

    fn write(&self, at: &Drawing) -> io::Result<Vec<Figure>> {
        let run = at.run;
        let (figure, path) = at.figure(
            "steps",
            format!(
                "{}: per load step, the position of the tip (the lower right corner of the \
                 undeformed body), the contact faces on the z-model and on the Signorini \
                 model, the penetration and model error (log axis; steps where they are 0 are \
                 not drawn), and the force–stroke curve: the contact force on the punch and on \
                 the die against the step (the tools rise by the same lift in every step); the \
                 thesis draws only the bodies{}",
                run.table,
                cf(&at.cited().solution)
            ),
        );
        steps(&path, run)?;
        Ok(vec![figure])
    }
}

/// The animation of a load-step run, with its frames listed under it.
pub(super) struct Animation;

impl Figures for Animation {
    fn applies(&self, run: &RunResult) -> bool {
        run.is_load_steps() && !run.deformed.is_empty()
    }

    fn write(&self, at: &Drawing) -> io::Result<Vec<Figure>> {
        let run = at.run;
        let (mut figure, path) = at.figure("animation", animation_caption(run, at.cited()));
        figure.links = frames(at.fig_dir, &at.stem, run, &path)?
            .into_iter()
            .map(|f| (f.file, format!("step {:02}", f.step)))
            .collect();
        Ok(vec![figure])
    }
}

/// The caption of a load-step run's animation.
fn animation_caption(run: &RunResult, thesis: &ThesisFigures) -> String {
    let steps = run.deformed.len();
    let signorini = if run.deformed.iter().any(|p| !p.accurate_faces.is_empty()) {
        ", Signorini faces thick black"
    } else {
        ""
    };
    format!(
        "{}: the body after each of the {steps} load step{} in one fixed view, {} s per step \
         and a pause on the last (an SVG animation); obstacles brown, hatched on their solid \
         side{signorini}, vertices in contact red{}",
        run.table,
        if steps == 1 { "" } else { "s" },
        fmt_short(FRAME_SECONDS),
        cf(&thesis.solution)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_take_turns_in_one_loop() {
        let n = 3;
        let all: Vec<String> = (0..n).map(|i| visibility_animation(i, n)).collect();
        // 3 × 0.4 s + 1.6 s.
        assert!(all.iter().all(|a| a.contains("dur=\"2.80s\"")), "{all:?}");
        assert!(all[0].contains("values=\"visible;hidden\" keyTimes=\"0;0.142857\""));
        assert!(all[1].contains("keyTimes=\"0;0.142857;0.285714\""));
        assert!(all[2].contains("values=\"hidden;visible\" keyTimes=\"0;0.285714\""));
        assert_eq!(visibility_animation(0, 1), "");
    }

    #[test]
    fn lines_break_where_a_step_has_no_value() {
        let points = [(0.0, 1.0), (1.0, 2.0), (3.0, 1.0), (4.0, 1.0), (6.0, 1.0)];
        let runs = consecutive_runs(&points);
        assert_eq!(runs, vec![&points[0..2], &points[2..4], &points[4..5]]);
        assert!(consecutive_runs(&[]).is_empty());
    }

    /// No finite body, no values, a single step: placeholders and empty panels, never a panic.
    #[test]
    fn degenerate_load_steps_still_write_figures() {
        use crate::results::Row;
        let dir = std::env::temp_dir().join(format!("tribo-forming-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let pic = DeformedPicture {
            cycle: 0,
            scale: 1.0,
            quads: vec![[[f64::NAN; 2]; 4]],
            obstacles: vec![vec![[f64::NAN, 0.0]]],
            contact_points: vec![],
            accurate_faces: vec![[[f64::NAN; 2]; 2]],
            caption: String::new(),
        };
        let row = Row::new(0)
            .real(columns::TIP_Y, None)
            .real(columns::PENETRATION, Some(0.0));
        for rows in [vec![], vec![row]] {
            let run = plots::test_run(rows, vec![pic.clone(), pic.clone()], [f64::NAN; 4]);
            steps(&dir.join("s.svg"), &run).unwrap();
            let files = frames(&dir, "T", &run, &dir.join("a.svg")).unwrap();
            // Two pictures of step 0: one frame.
            assert_eq!(files.len(), 1);
            assert!(std::fs::read_to_string(dir.join("T-step-00.svg"))
                .unwrap()
                .contains("no finite cells"));
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn linear_ranges_are_never_empty() {
        assert_eq!(linear_range([].iter()), 0.0..1.0);
        let one = linear_range([(0.0, 2.0)].iter());
        assert!(one.start < 2.0 && one.end > 2.0);
        let nan = linear_range([(0.0, f64::NAN), (1.0, 3.0)].iter());
        assert!(nan.start < 3.0 && nan.end > 3.0);
    }
}
