//! The report of a load-step run, the U-O (J) forming of thesis §IV.2.4.7 (`fig-IV.54`, a figure
//! experiment: the thesis prints no table, only the pictures of Fig. IV.54): one frame per load
//! step in a fixed view, their SMIL animation on the page, the per-step chart and table, and
//! `data/fig-IV.54.csv` indexed by `step`. The Signorini faces are drawn thick black in every
//! deformed-body picture that has them.

use std::fs;
use std::path::{Path, PathBuf};

use crate::common::{no_thesis, report_of};
use tribo::results::{columns, DeformedPicture, PhaseSeconds, Row, RunResult, Value};

/// The element of a deformed-body picture that draws the Signorini faces.
const SIGNORINI_PATH: &str = "<path class=\"signorini-faces\"";

/// `report --quick --only fig-IV.54` on the shipped experiments into a fresh folder.
fn quick_forming_report(name: &str) -> PathBuf {
    let experiments = Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments");
    crate::outputs::quick_report(&experiments, &format!("forming-{name}"), Some("fig-IV.54"))
}

fn read(path: &Path) -> String {
    fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The text of the section of `id` on the page.
fn section<'a>(html: &'a str, id: &str) -> &'a str {
    let start = html
        .find(&format!("<section id=\"t-{id}\">"))
        .unwrap_or_else(|| panic!("no section of {id}"));
    let end = html[start..]
        .find("</section>")
        .map_or(html.len(), |e| start + e);
    &html[start..end]
}

/// Words that spell a non-finite number, as whole words.
fn non_finite_words(text: &str) -> Vec<&str> {
    text.split(|c: char| !(c.is_alphanumeric() || c == '-' || c == '+'))
        .filter(|w| {
            let w = w.trim_start_matches(['+', '-']).to_ascii_lowercase();
            w == "nan" || w == "inf" || w == "infinity"
        })
        .collect()
}

#[test]
fn quick_forming_report_writes_frames_animation_chart_and_step_table() {
    let out = quick_forming_report("quick");
    let figures = out.join("figures");

    // One frame per load step of the quick tier (3 steps), numbered from the picture's step.
    for step in 0..3 {
        let frame = figures.join(format!("fig-IV.54-step-{step:02}.svg"));
        assert!(frame.is_file(), "{} is missing", frame.display());
        let svg = read(&frame);
        assert!(
            svg.contains(&format!("fig-IV.54 — load step {step}:")),
            "frame {step} has no step title"
        );
    }
    assert!(!figures.join("fig-IV.54-step-03.svg").exists());
    // Figures of refinement studies on a fixed body are not drawn for a moving body.
    for kind in [
        "convergence",
        "cost",
        "mesh",
        "partition",
        "deformed-0",
        "deformed",
    ] {
        let f = figures.join(format!("fig-IV.54-{kind}.svg"));
        assert!(!f.exists(), "{} should not be drawn", f.display());
    }
    assert!(figures.join("fig-IV.54-steps.svg").is_file());

    // The frames share one view: the same window (clip rectangle) in every frame.
    let clip = |svg: &str| {
        let start = svg.find("<clipPath").expect("a clip path");
        svg[start..start + svg[start..].find("</clipPath>").unwrap()].to_string()
    };
    let first = clip(&read(&figures.join("fig-IV.54-step-00.svg")));
    for step in ["01", "02"] {
        let other = clip(&read(&figures.join(format!("fig-IV.54-step-{step}.svg"))));
        assert_eq!(first, other, "frame {step} has another view");
    }

    // The animation: the three frames inline, SMIL, nothing from another file.
    let animation = read(&figures.join("fig-IV.54-animation.svg"));
    assert_eq!(animation.matches("<g class=\"frame\"").count(), 3);
    for step in ["00", "01", "02"] {
        assert!(animation.contains(&format!("id=\"step-{step}\"")), "{step}");
    }
    assert_eq!(
        animation
            .matches("<animate attributeName=\"visibility\"")
            .count(),
        3
    );
    assert!(animation.contains("repeatCount=\"indefinite\""));
    assert!(
        !animation.contains("href"),
        "the animation refers to a file"
    );
    assert!(!animation.contains("<image"));

    // The Signorini faces: drawn in exactly the frames whose step has any (the quick tier's
    // first steps may have none; `frames_draw_the_signorini_faces…` covers the drawing).
    let csv = read(&out.join("data/fig-IV.54.csv"));
    assert!(csv.starts_with("step,"), "{}", &csv[..csv.len().min(80)]);
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let s_faces = header
        .iter()
        .position(|c| *c == "s_faces")
        .expect("an s_faces column");
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), 3, "one row per load step");
    for (step, row) in rows.iter().enumerate() {
        assert_eq!(row[0], step.to_string());
        let faces: usize = row[s_faces].parse().expect("a count");
        let frame = read(&figures.join(format!("fig-IV.54-step-{step:02}.svg")));
        assert_eq!(
            frame.contains(SIGNORINI_PATH),
            faces > 0,
            "step {step}: {faces} Signorini faces"
        );
    }

    // The page: the animation as an image with its frames as links, the per-step table, no
    // comparison with a thesis table that does not exist.
    let html = tribo::report::read_pages(&out).unwrap();
    assert!(html.contains("<img src=\"figures/fig-IV.54-animation.svg\""));
    for step in ["00", "01", "02"] {
        assert!(html.contains(&format!("<a href=\"figures/fig-IV.54-step-{step}.svg\">")));
    }
    assert!(html.contains("<td class=\"status ok\">figure: no printed table</td>"));
    let s = section(&html, "fig-IV.54");
    assert!(
        s.contains("The thesis prints no table for this result, only the pictures of Fig. IV.54")
    );
    assert!(s.contains(
        "<th>step</th><th>z_faces</th><th>s_faces</th><th>dofs</th><th>model_error</th>\
         <th>penetration</th><th>contact_force_top</th><th>contact_force_bottom</th>\
         <th>tip_x</th><th>tip_y</th><th>z_iterations</th>\
         <th>mixed_iterations</th><th>seconds</th>"
    ));
    for absent in [
        "<th>thesis</th>",
        "tribo/thesis",
        "0 printed",
        "<th>cycle</th>",
    ] {
        assert!(!s.contains(absent), "the section shows {absent}");
    }
    let bad = non_finite_words(&html);
    assert!(bad.is_empty(), "non-finite values on the page: {bad:?}");
    let _ = fs::remove_dir_all(&out);
}

/// A load-step row of a synthetic run.
fn step_row(step: usize, s_faces: usize) -> Row {
    let mut row = Row::new(step)
        .count(columns::ACTIVE_CELLS, 2)
        .count(columns::DOFS, 12)
        .count(columns::Z_FACES, 2 - s_faces)
        .count(columns::S_FACES, s_faces)
        .real(columns::MODEL_ERROR, Some(0.0))
        .real(columns::PENETRATION, Some(1e-3 * step as f64))
        .real(columns::TIP_X, Some(2.0))
        .real(columns::TIP_Y, Some(0.5 * step as f64));
    // An undefined value, as a producer might hand it over.
    row.set("z_iterations", Value::Real(Some(f64::NAN)));
    row.seconds = PhaseSeconds {
        solve: 0.01,
        ..PhaseSeconds::default()
    };
    row
}

/// Two unit squares side by side, lifted by `lift`, with a Signorini face on the bottom of the
/// right one (and one with a NaN end, which is skipped).
fn picture(step: usize, lift: f64) -> DeformedPicture {
    let quad = |x: f64| {
        [
            [x, lift],
            [x + 1.0, lift],
            [x + 1.0, lift + 1.0],
            [x, lift + 1.0],
        ]
    };
    DeformedPicture {
        cycle: step,
        scale: 1.0,
        quads: vec![quad(0.0), quad(1.0)],
        obstacles: vec![vec![[-1.0, lift - 0.1], [3.0, lift - 0.1]]],
        contact_points: vec![[1.5, lift]],
        accurate_faces: vec![[[1.0, lift], [2.0, lift]], [[f64::NAN, 0.0], [1.0, 0.0]]],
        caption: format!("load step {step}"),
    }
}

fn synthetic_run(table: &str, rows: Vec<Row>, deformed: Vec<DeformedPicture>) -> RunResult {
    RunResult {
        rows,
        deformed,
        ..RunResult::new(
            table,
            "IV.2.4.7",
            "synthetic forming",
            "quick",
            [0.0, 2.0, 0.0, 1.0],
        )
    }
}

/// The frames of a load-step run and the deformed picture of any other run both draw the
/// Signorini faces (the quick forming run has none in its first steps, so this is the check of
/// the drawing itself).
#[test]
fn frames_and_deformed_pictures_draw_the_signorini_faces() {
    let forming = synthetic_run(
        "fig-IV.99",
        vec![step_row(0, 1), step_row(1, 1)],
        vec![picture(0, 0.0), picture(1, 0.5)],
    );
    // The same picture in a run that is not a load-step study (no tip columns).
    let table = synthetic_run(
        "IV.99",
        vec![Row::new(0).count(columns::DOFS, 12)],
        vec![picture(0, 0.0)],
    );
    let (figure_thesis, table_thesis) = (
        no_thesis("fig-IV.99", "IV.2.4.7"),
        no_thesis("IV.99", "IV.2.4.7"),
    );
    let (dir, written) = report_of(
        "synthetic",
        &[(&forming, &figure_thesis), (&table, &table_thesis)],
    );
    let figures = dir.join("figures");
    for frame in ["fig-IV.99-step-00.svg", "fig-IV.99-step-01.svg"] {
        assert!(
            written.files.contains(&figures.join(frame)),
            "{frame} not listed"
        );
        let svg = read(&figures.join(frame));
        assert_eq!(svg.matches(SIGNORINI_PATH).count(), 1, "{frame}");
        // One segment: the face with a NaN end is left out.
        let d = svg
            .split(SIGNORINI_PATH)
            .nth(1)
            .and_then(|rest| rest.split(" d=\"").nth(1))
            .and_then(|rest| rest.split('"').next())
            .expect("a path with d");
        assert_eq!(d.matches('M').count(), 1, "{d}");
        assert_eq!(d.matches('L').count(), 1, "{d}");
        assert!(svg.contains("Signorini faces (2)"), "{frame}: legend");
        assert!(!svg.contains("NaN"));
    }
    let animation = read(&figures.join("fig-IV.99-animation.svg"));
    assert_eq!(animation.matches(SIGNORINI_PATH).count(), 2);
    assert_eq!(animation.matches("<g class=\"frame\"").count(), 2);
    assert!(!animation.contains("href"));

    let deformed = read(&figures.join("IV.99-deformed.svg"));
    assert_eq!(deformed.matches(SIGNORINI_PATH).count(), 1);
    assert!(!figures.join("IV.99-step-00.svg").exists());

    let html = tribo::report::read_pages(&dir).unwrap();
    assert!(html.contains(
        "IV.99: deformed body after cycle 0, displacement × 1; Signorini faces thick black"
    ));
    assert!(html.contains("Signorini faces thick black, vertices in contact red"));
    // The undefined iteration count is a dash, not NaN.
    let s = section(&html, "fig-IV.99");
    assert!(s.contains("<td class=\"na\">—</td>"));
    let bad = non_finite_words(&html);
    assert!(bad.is_empty(), "non-finite values on the page: {bad:?}");
    let _ = fs::remove_dir_all(&dir);
}

/// A figure experiment whose run has no rows and no pictures still gets a section that says the
/// thesis prints no table, and no frames.
#[test]
fn an_empty_figure_run_is_reported_without_frames() {
    let run = synthetic_run("fig-IV.98", vec![], vec![]);
    let (dir, _) = report_of("empty", &[(&run, &no_thesis("fig-IV.98", "IV.2.4.7"))]);
    assert!(!dir.join("figures/fig-IV.98-animation.svg").exists());
    let html = tribo::report::read_pages(&dir).unwrap();
    assert!(html.contains("figure: no printed table"));
    assert!(html.contains("0 cycles computed, no printed table"));
    let _ = fs::remove_dir_all(&dir);
}
