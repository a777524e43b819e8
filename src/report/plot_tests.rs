//! Tests of what the figures show: the convergence plot pairs the values its table compares,
//! no legend covers a plotted point, and the text of every figure is readable and inside it.
//!
//! [`check_svg_text`] is also what the ignored test `report_folder_figures_are_readable` runs
//! over the figures of a report folder (`TRIBO_REPORT=<folder>`), with
//! [`check_svg_legends`] for the points of the written files.

use std::path::{Path, PathBuf};

use super::convergence::{
    accuracy, convergence, convergence_caption, convergence_curves, cost, label_boxes,
};
use super::film::{cuts, uzawa};
use super::forming::steps;
use super::legend::Placed;
use super::model_plots::{model_adaptivity, partitions};
use super::performance::solve_cost;
use super::plots::test_run;
use super::{compared_value, rel_diff};
use crate::results::{
    columns, CostRow, Cuts, FaceModel, PartitionPicture, PhaseSeconds, Row, RunResult, UzawaRow,
};
use crate::thesis::ThesisTable;

/// Width in pixels at which the page shows a plot (`figure.plot`: 780 pixels less padding);
/// wider plot SVGs are scaled down to it.
const PLOT_WIDTH: f64 = 762.0;

/// Width in pixels at which a page in a 1 400 px window shows a picture of the whole domain
/// (`figure.wide`: the 1 329 px of the page's content less the figure's padding and border);
/// wider pictures (1 600 px) are scaled down to it.
const WIDE_WIDTH: f64 = 1311.0;

/// Smallest readable text, pixels as shown.
const MIN_TEXT_PX: f64 = 10.0;

fn manifest(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tribo-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The printed table of a shipped experiment.
fn printed(table: &str) -> ThesisTable {
    let spec = crate::experiment::load(&manifest(&format!("experiments/{table}.toml"))).unwrap();
    ThesisTable::of(&spec)
}

/// The rows of a golden snapshot (`cycle N  cells N  dofs N  estimate X …`), as a run's rows.
fn golden_rows(table: &str) -> Vec<Row> {
    let text = std::fs::read_to_string(manifest(&format!("golden/{table}.snap"))).unwrap();
    text.lines()
        .filter(|l| l.starts_with("cycle "))
        .map(|line| {
            let words: Vec<&str> = line.split_whitespace().collect();
            let mut row = Row::new(words[1].parse().unwrap());
            for pair in words[2..].chunks(2) {
                let value = pair[1].parse::<f64>().ok();
                row = match pair[0] {
                    "cells" => row.count("active_cells", value.unwrap() as usize),
                    "dofs" => row.count("dofs", value.unwrap() as usize),
                    name => row.real(name, value),
                };
            }
            row
        })
        .collect()
}

/// IV.36's table compares the printed estimate with `estimate_previous_mesh` (within 1.8 % in
/// every quick row); its plot must draw the same pairs: each tribo point lies on the printed
/// point of its row, within the table's relative differences of dofs and estimate.
#[test]
fn iv36_convergence_plot_draws_the_pairs_its_table_compares() {
    let thesis = printed("IV.36");
    let mut run = test_run(golden_rows("IV.36"), vec![], [0.0, 1.0, 0.0, 1.0]);
    run.table = "IV.36".into();
    assert_eq!(run.rows.len(), 3);
    let curves = convergence_curves(&run, &thesis);
    let tribo = &curves[0];
    let printed = curves.iter().find(|c| c.label == "thesis η").unwrap();
    assert_eq!(tribo.points.len(), run.rows.len());
    for (i, (row, &(x, y))) in run.rows.iter().zip(&tribo.points).enumerate() {
        let (px, py) = printed.points[i];
        let dofs_diff = rel_diff(row.value("dofs").unwrap(), px).unwrap();
        let estimate_diff = rel_diff(compared_value(&run.rows, i, "estimate").unwrap(), py);
        assert!((x / px - 1.0 - dofs_diff).abs() < 1e-12 && dofs_diff.abs() < 0.005);
        let plotted = y / py - 1.0;
        assert!(
            (plotted - estimate_diff.unwrap()).abs() < 1e-12 && plotted.abs() < 0.02,
            "row {i}: plotted {plotted}, table {estimate_diff:?}"
        );
        // The estimate on the printed mesh is 17–22 % below the printed value after row 0:
        // drawing it, as the plot did, puts the curves apart.
        let own = rel_diff(row.value("estimate").unwrap(), py).unwrap();
        assert!(i == 0 || own < -0.15, "row {i}: {own}");
    }
}

/// IV.36's joined data set each printed value beside the tribo value its difference compares:
/// `estimate_compared` (= `estimate_previous_mesh`) beside `thesis_estimate`, `ratio_compared`
/// beside `thesis_ratio`.
#[test]
fn iv36_joined_data_name_the_compared_values() {
    let thesis = printed("IV.36");
    let run = test_run(golden_rows("IV.36"), vec![], [0.0, 1.0, 0.0, 1.0]);
    let frame = super::data::joined_frame(&run, &thesis).unwrap().unwrap();
    let names: Vec<String> = frame
        .get_column_names()
        .iter()
        .map(|c| c.to_string())
        .collect();
    let at = |n: &str| names.iter().position(|c| c == n).unwrap();
    assert_eq!(at("estimate_compared") + 1, at("thesis_estimate"));
    assert_eq!(at("ratio_compared") + 1, at("thesis_ratio"));
    let column = |n: &str| -> Vec<Option<f64>> {
        let values = frame.column(n).unwrap().f64().unwrap().clone();
        (0..values.len()).map(|i| values.get(i)).collect()
    };
    let (compared, previous) = (
        column("estimate_compared"),
        column("estimate_previous_mesh"),
    );
    assert_eq!(compared, previous);
    for (i, (c, (p, d))) in compared
        .iter()
        .zip(
            column("thesis_estimate")
                .iter()
                .zip(column("estimate_rel_diff")),
        )
        .enumerate()
    {
        assert_eq!(d, rel_diff(c.unwrap(), p.unwrap()), "row {i}");
    }
    let ratios = column("ratio_compared");
    assert_eq!(ratios[0], None, "no solve before the first one's");
    assert_eq!(ratios[1], Some(previous[1].unwrap() / previous[0].unwrap()));
    // A table compared column by column gets no `_compared` column.
    let rows = vec![Row::new(0).count("dofs", 100).real("estimate", Some(1.0))];
    let plain = test_run(rows, vec![], [0.0, 1.0, 0.0, 1.0]);
    let frame = super::data::joined_frame(&plain, &ThesisTable::of_rows(&[[0.0, 90.0, 1.1, 0.1]]))
        .unwrap()
        .unwrap();
    assert!(!frame
        .get_column_names()
        .iter()
        .any(|c| c.ends_with("_compared")));
}

/// A table without `estimate_previous_mesh` draws its estimate, unchanged; so does a fluid
/// scene without printed rows (nothing is compared, so the estimate on each mesh is drawn).
#[test]
fn convergence_plot_of_other_tables_draws_the_estimate() {
    let rows = vec![
        Row::new(0).count("dofs", 100).real("estimate", Some(1.0)),
        Row::new(1).count("dofs", 400).real("estimate", Some(0.5)),
    ];
    let run = test_run(rows, vec![], [0.0, 1.0, 0.0, 1.0]);
    let curves = convergence_curves(&run, &ThesisTable::of_rows(&[]));
    assert_eq!(curves.len(), 1, "no thesis curve without printed rows");
    assert_eq!(curves[0].points, vec![(100.0, 1.0), (400.0, 0.5)]);
    assert_eq!(curves[0].label, "tribo η");
    let fluid = test_run(golden_rows("IV.36"), vec![], [0.0, 1.0, 0.0, 1.0]);
    let curves = convergence_curves(&fluid, &ThesisTable::of_rows(&[]));
    let estimates: Vec<f64> = fluid.rows.iter().map(|r| r.estimate().unwrap()).collect();
    let plotted: Vec<f64> = curves[0].points.iter().map(|p| p.1).collect();
    assert_eq!(plotted, estimates);
    let caption = convergence_caption(&fluid, &ThesisTable::of_rows(&[]), "η");
    assert!(!caption.contains("thesis"), "{caption}");
    let caption = convergence_caption(&fluid, &printed("IV.36"), "η");
    assert!(caption.contains("estimate_previous_mesh") && caption.contains("thesis (dashed)"));
}

impl ThesisTable {
    /// A printed table of `cycle, dofs, estimate, model_error` rows, for the tests.
    fn of_rows(rows: &[[f64; 4]]) -> ThesisTable {
        ThesisTable {
            table: "T".into(),
            section: "S".into(),
            columns: ["cycle", "dofs", "estimate", "model_error"]
                .map(String::from)
                .to_vec(),
            rows: rows.iter().map(|r| r.to_vec()).collect(),
            duplicate_of: None,
            additive_part: None,
            comparison: Default::default(),
            figures: Default::default(),
        }
    }
}

fn seconds(k: usize) -> PhaseSeconds {
    let s = 0.01 * (k + 1) as f64;
    PhaseSeconds {
        setup: s,
        assemble: 2.0 * s,
        solve: 5.0 * s * s,
        estimate: s,
        refine: 0.5 * s,
    }
}

/// Ten cycles whose estimate stalls at the end (as in IV.32) and whose model error fills the
/// lower part of the chart: points near every corner of the plotting area.
fn crowded_run() -> (RunResult, ThesisTable) {
    let rows: Vec<Row> = (0..10)
        .map(|k| {
            let dofs = 400.0 * 1.8f64.powi(k as i32);
            let stall = if k < 5 { 0.7f64.powi(k as i32) } else { 0.17 };
            let mut row = Row::new(k)
                .count("dofs", dofs as usize)
                .real("estimate", Some(stall))
                .real("model_error", Some(0.1 * 0.5f64.powi(k as i32)))
                .count(columns::CG_ITERATIONS, 10);
            row.seconds = seconds(k);
            row
        })
        .collect();
    let printed: Vec<[f64; 4]> = (0..10)
        .map(|k| {
            let dofs = 400.0 * 1.8f64.powi(k);
            [
                k as f64,
                dofs,
                1.1 * 0.7f64.powi(k),
                1e-4 * 3f64.powi(k % 4),
            ]
        })
        .collect();
    let run = test_run(rows, vec![], [-16.0, 16.0, 0.0, 4.0]);
    (run, ThesisTable::of_rows(&printed))
}

/// Every legend of `placed` is drawn, and covers none of its points.
fn assert_clear(kind: &str, placed: &Placed) {
    assert!(!placed.legends.is_empty(), "{kind}: no legend");
    assert!(!placed.points.is_empty(), "{kind}: no points");
    assert!(
        placed.covered().is_empty(),
        "{kind}: points {:?} under the legends {:?}",
        placed.covered(),
        placed.legends
    );
}

/// One representative run of each kind of line chart: no plotted point lies inside a legend,
/// and the written SVG's text is readable and inside the picture.
#[test]
fn legends_cover_no_plotted_point() {
    let dir = temp_dir("legends");
    let (mut run, thesis) = crowded_run();
    let file = |name: &str| dir.join(name);

    assert_clear(
        "convergence",
        &convergence(&file("convergence.svg"), &run, &thesis).unwrap(),
    );
    assert_clear("cost", &cost(&file("cost.svg"), &run).unwrap());

    run.costs = ["z", "signorini", "III.2", "III.3"]
        .iter()
        .enumerate()
        .flat_map(|(v, variant)| {
            (0..6).map(move |cycle| CostRow {
                variant: variant.to_string(),
                cycle,
                seconds_solve: 0.1 * (cycle + v + 1) as f64,
                iterations: 3,
                penetration: 10f64.powi(-(cycle as i32) - v as i32),
                energy_distance: 0.5f64.powi(cycle as i32 + v as i32),
                accurate_faces: cycle,
                model_error: 0.1,
                model_tolerance: 0.01,
            })
        })
        .collect();
    assert_clear("accuracy", &accuracy(&file("accuracy.svg"), &run).unwrap());

    let x: Vec<f64> = (0..=100).map(|i| f64::from(i) / 100.0).collect();
    let wave = |a: f64| x.iter().map(|x| a * (6.0 * x).sin()).collect::<Vec<f64>>();
    let c = Cuts {
        y: 0.5,
        boundary_pressure: 0.0,
        columns: vec![
            ("x".into(), x.clone()),
            ("p_substokes".into(), wave(3000.0)),
            ("p_reynolds".into(), wave(4000.0)),
            ("chi1_substokes".into(), wave(5.0)),
            ("chi1_reynolds".into(), wave(8.0)),
        ],
        cavitated_substokes: None,
        cavitated_reynolds: None,
    };
    assert_clear("cuts", &cuts(&file("cuts.svg"), &run, &c).unwrap());

    run.uzawa = ["identity", "jacobi", "gauss-seidel", "ssor", "cg-ssor"]
        .iter()
        .enumerate()
        .flat_map(|(v, variant)| {
            (0..=300).map(move |k| UzawaRow {
                variant: variant.to_string(),
                iteration: k,
                residual: 1.0,
                relative_residual: (1.0 - 0.002 * (v + 1) as f64).powi(k as i32),
                pressure_error: None,
                inner_iterations: 1,
                seconds: 0.0,
            })
        })
        .collect();
    assert_clear("uzawa", &uzawa(&file("uzawa.svg"), &run).unwrap());

    let forming: Vec<Row> = (0..25)
        .map(|j| {
            let j64 = f64::from(j);
            Row::new(j as usize)
                .real(columns::TIP_X, Some(16.0 - 0.14 * j64))
                .real(columns::TIP_Y, Some(0.42 * j64))
                .count(columns::Z_FACES, 300 - j as usize)
                .count(columns::S_FACES, j as usize)
                .real(columns::PENETRATION, Some(1e-4 * (1.0 + j64)))
                .real(columns::MODEL_ERROR, Some(1e-3 * (1.0 + j64)))
                .real("contact_force_top", Some(0.01 * j64 * j64))
                .real("contact_force_bottom", Some(0.012 * j64 * j64))
        })
        .collect();
    let moved = test_run(forming, vec![], [0.0, 16.0, 0.0, 2.0]);
    assert_clear("steps", &steps(&file("steps.svg"), &moved).unwrap());

    let mut reynolds = test_run(run.rows.clone(), vec![], [0.0, 1.0, 0.0, 1.0]);
    reynolds.table = "IV.36".into();
    assert_clear(
        "performance",
        &solve_cost(&file("performance.svg"), &[&reynolds]).unwrap(),
    );

    for name in [
        "convergence",
        "cost",
        "accuracy",
        "cuts",
        "uzawa",
        "steps",
        "performance",
    ] {
        let svg = std::fs::read_to_string(file(&format!("{name}.svg"))).unwrap();
        let problems = check_svg_text(&svg, PLOT_WIDTH);
        assert!(problems.is_empty(), "{name}: {problems:?}");
        let problems = check_svg_legends(&svg);
        assert!(problems.is_empty(), "{name}: {problems:?}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The dofs labels of the cost plot: crowded points (a stall) keep the last label and drop
/// those that would cover it or a point; points far apart keep every label.
#[test]
fn cost_labels_do_not_cover_each_other() {
    let labels: Vec<String> = ["24992 dofs", "40256 dofs", "88550 dofs"]
        .map(String::from)
        .to_vec();
    let crowded = label_boxes(&[(470, 750), (490, 746), (520, 743)], &labels);
    assert!(crowded[2].is_some() && crowded[1].is_none() && crowded[0].is_none());
    let apart = label_boxes(&[(100, 100), (300, 200), (500, 300)], &labels);
    assert!(apart.iter().all(Option::is_some), "{apart:?}");
}

/// The uzawa chart labels its iterations as whole numbers, the last one inside the picture
/// (it printed "300.(" before).
#[test]
fn uzawa_iterations_are_whole_numbers() {
    let dir = temp_dir("uzawa");
    let mut run = test_run(vec![], vec![], [0.0, 1.0, 0.0, 1.0]);
    run.uzawa = (0..=300)
        .map(|k| UzawaRow {
            variant: "ssor".into(),
            iteration: k,
            residual: 1.0,
            relative_residual: 0.99f64.powi(k as i32),
            pressure_error: None,
            inner_iterations: 1,
            seconds: 0.0,
        })
        .collect();
    uzawa(&dir.join("u.svg"), &run).unwrap();
    let svg = std::fs::read_to_string(dir.join("u.svg")).unwrap();
    let labels: Vec<String> = texts(&svg).into_iter().map(|t| t.content).collect();
    assert!(labels.iter().any(|l| l == "300"), "{labels:?}");
    assert!(!labels.iter().any(|l| l.ends_with(".0")), "{labels:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The model-adaptive figures: readable at the width the page shows them, and a scene without
/// printed rows names no thesis curve.
#[test]
fn model_figures_are_readable_and_name_only_what_they_draw() {
    let dir = temp_dir("model-figures");
    let (mut run, thesis) = crowded_run();
    run.rows = run
        .rows
        .into_iter()
        .map(|r| r.count(columns::ACCURATE_FACES, 3))
        .collect();
    run.partitions = (0..10)
        .map(|cycle| PartitionPicture {
            cycle,
            faces: (0..1385)
                .map(|k| FaceModel {
                    side: "bottom".into(),
                    x0: -16.0 + 32.0 * f64::from(k) / 1385.0,
                    x1: -16.0 + 32.0 * f64::from(k + 1) / 1385.0,
                    accurate: k % 7 == 0,
                    error: 0.0,
                })
                .collect(),
        })
        .collect();
    partitions(&dir.join("p.svg"), &run, run.domain).unwrap();
    model_adaptivity(&dir.join("m.svg"), &run, &thesis).unwrap();
    model_adaptivity(&dir.join("own.svg"), &run, &ThesisTable::of_rows(&[])).unwrap();
    for name in ["p.svg", "m.svg", "own.svg"] {
        let svg = std::fs::read_to_string(dir.join(name)).unwrap();
        let problems = check_svg_text(&svg, PLOT_WIDTH);
        assert!(problems.is_empty(), "{name}: {problems:?}");
    }
    let own = std::fs::read_to_string(dir.join("own.svg")).unwrap();
    assert!(!own.contains("thesis"), "{own}");
    assert!(std::fs::read_to_string(dir.join("m.svg"))
        .unwrap()
        .contains("thesis (dashed"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A scene of one's own (an id without a family) shows its cycles in the performance figure,
/// by the model its scene names.
#[test]
fn performance_figure_shows_own_scenes() {
    let dir = temp_dir("performance");
    let (run, _) = crowded_run();
    let mut own = test_run(run.rows.clone(), vec![], [0.0, 1.0, 0.0, 1.0]);
    own.table = "my-slider".into();
    own.parameters = vec![crate::results::Parameter {
        group: "scene".into(),
        key: "effects".into(),
        value: "[\"reynolds\"]".into(),
    }];
    let placed = solve_cost(&dir.join("p.svg"), &[&own]).unwrap();
    // Cycles of at least 1000 dofs: 400·1.8^k for k ≥ 2.
    assert_eq!(placed.points.len(), 8);
    own.parameters[0].value = "[\"substokes\"]".into();
    let placed = solve_cost(&dir.join("p.svg"), &[&own]).unwrap();
    assert!(placed.points.is_empty());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A mesh the cycles do not change (a model-adaptive table) is drawn once, labelled with every
/// cycle; meshes that differ get a panel each. The axis labels of a 1 600 px picture stay
/// readable at the width the page shows it.
#[test]
fn a_fixed_mesh_is_drawn_once() {
    use crate::results::{CellBox, MeshPicture};
    let dir = temp_dir("fixed-mesh");
    let cells = |n: usize| -> Vec<CellBox> {
        (0..n)
            .map(|i| {
                let x0 = i as f64 / n as f64;
                CellBox {
                    x0,
                    y0: 0.0,
                    x1: x0 + 1.0 / n as f64,
                    y1: 1.0,
                }
            })
            .collect()
    };
    let picture = |cycle: usize, n: usize| MeshPicture {
        cycle,
        cells: cells(n),
        levels: Vec::new(),
        shaded: Vec::new(),
    };
    let domain = [0.0, 1.0, 0.0, 1.0];
    let path = dir.join("fixed.svg");
    let fixed = [picture(3, 4), picture(6, 4), picture(9, 4)];
    super::meshes::meshes(&path, &fixed, domain, &[]).unwrap();
    let svg = std::fs::read_to_string(&path).unwrap();
    assert!(
        svg.contains("cycles 3, 6, 9: the same mesh  (4 cells)"),
        "{svg}"
    );
    assert!(!svg.contains(">cycle "), "one panel only");
    let changing = [picture(3, 4), picture(6, 8)];
    super::meshes::meshes(&path, &changing, domain, &[]).unwrap();
    let svg = std::fs::read_to_string(&path).unwrap();
    assert!(svg.contains("cycle 3  (4 cells)") && svg.contains("cycle 6  (8 cells)"));
    assert_eq!(check_svg_text(&svg, WIDE_WIDTH), Vec::<String>::new());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A `<text>` element of an SVG: position, size, anchor and content.
struct SvgText {
    x: f64,
    size: f64,
    anchor: String,
    rotated: bool,
    content: String,
}

/// The value of attribute `name` in the attributes `attrs` of one element.
fn attr<'a>(attrs: &'a str, name: &str) -> Option<&'a str> {
    let key = format!("{name}=\"");
    // The attribute at the start of `attrs` or after a space (so `x` is not found in `cx`).
    let start = attrs
        .match_indices(&key)
        .map(|(at, _)| at)
        .find(|&at| at == 0 || attrs.as_bytes()[at - 1] == b' ')?
        + key.len();
    let len = attrs[start..].find('"')?;
    Some(&attrs[start..start + len])
}

fn texts(svg: &str) -> Vec<SvgText> {
    svg.split("<text")
        .skip(1)
        .filter_map(|part| {
            let close = part.find('>')?;
            let attrs = &part[..close];
            let end = part.find("</text>")?;
            Some(SvgText {
                x: attr(attrs, "x")?.parse().ok()?,
                size: attr(attrs, "font-size")?.parse().ok()?,
                anchor: attr(attrs, "text-anchor").unwrap_or("start").to_string(),
                rotated: attrs.contains("transform"),
                content: part[close + 1..end].trim().to_string(),
            })
        })
        .collect()
}

/// The width of an SVG's canvas in pixels.
fn svg_width(svg: &str) -> Option<f64> {
    let open = &svg[svg.find("<svg")?..];
    attr(&open[..open.find('>')?], "width")?.parse().ok()
}

/// Text that is too small where the page shows the SVG at most `shown` pixels wide (or at its
/// own width, if that is smaller), or that runs off the left or right edge: sans-serif text is
/// taken to be 0.55 em per character wide, so a problem reported is a real one and some clipped
/// text may pass.
pub(super) fn check_svg_text(svg: &str, shown: f64) -> Vec<String> {
    let Some(width) = svg_width(svg) else {
        return vec!["no width".into()];
    };
    let scale = (shown / width).min(1.0);
    let mut problems = Vec::new();
    for t in texts(svg).iter().filter(|t| !t.content.is_empty()) {
        if t.size * scale < MIN_TEXT_PX - 1e-9 {
            problems.push(format!(
                "'{}' at {:.1} px as shown ({} px in a {width} px picture)",
                t.content,
                t.size * scale,
                t.size
            ));
        }
        if t.rotated {
            continue;
        }
        let w = 0.55 * t.size * t.content.chars().count() as f64;
        let (left, right) = match t.anchor.as_str() {
            "middle" => (t.x - w / 2.0, t.x + w / 2.0),
            "end" => (t.x - w, t.x),
            _ => (t.x, t.x + w),
        };
        if left < -0.5 || right > width + 0.5 {
            problems.push(format!(
                "'{}' spans x {left:.0}–{right:.0} of {width}",
                t.content
            ));
        }
    }
    problems
}

/// The data points of a written chart (circles and polyline vertices) that lie inside a legend
/// frame (a rectangle stroked in the legend's colour) and were drawn before it: a legend's own
/// samples come after its frame, the data of its chart before.
pub(super) fn check_svg_legends(svg: &str) -> Vec<String> {
    let frame = format!(
        "stroke=\"#{:02X}{:02X}{:02X}\"",
        super::legend::FRAME.0,
        super::legend::FRAME.1,
        super::legend::FRAME.2
    );
    let number = |attrs: &str, name: &str| attr(attrs, name).and_then(|v| v.parse::<f64>().ok());
    // (offset in the file, attributes) of every element `tag`.
    let elements = |tag: &str| -> Vec<(usize, &str)> {
        let key = format!("<{tag} ");
        svg.match_indices(&key)
            .filter_map(|(at, _)| {
                let rest = &svg[at + key.len()..];
                rest.find('>').map(|e| (at, &rest[..e]))
            })
            .collect()
    };
    let boxes: Vec<(usize, [f64; 4])> = elements("rect")
        .into_iter()
        .filter(|(_, a)| a.contains(&frame))
        .filter_map(|(at, a)| {
            let (x, y) = (number(a, "x")?, number(a, "y")?);
            Some((
                at,
                [x, y, x + number(a, "width")?, y + number(a, "height")?],
            ))
        })
        .collect();
    let mut points: Vec<(usize, (f64, f64))> = elements("circle")
        .into_iter()
        .filter_map(|(at, a)| Some((at, (number(a, "cx")?, number(a, "cy")?))))
        .collect();
    for (at, a) in elements("polyline") {
        if let Some(list) = attr(a, "points") {
            points.extend(list.split_whitespace().filter_map(|p| {
                let (x, y) = p.split_once(',')?;
                Some((at, (x.parse().ok()?, y.parse().ok()?)))
            }));
        }
    }
    let inside =
        |(x, y): (f64, f64), b: &[f64; 4]| x >= b[0] && x <= b[2] && y >= b[1] && y <= b[3];
    points
        .iter()
        .filter(|(at, p)| {
            boxes
                .iter()
                .any(|(frame_at, b)| at < frame_at && inside(*p, b))
        })
        .map(|(_, (x, y))| format!("point ({x}, {y}) under a legend"))
        .collect()
}

/// The figures of a report folder (`TRIBO_REPORT=<folder>`, e.g. a full-tier report): the
/// text of every SVG readable at the width the page shows it and inside the picture, and no
/// plotted point under a legend. Run by the full tier:
/// `TRIBO_REPORT=/tmp/r cargo test --release --lib -- --ignored report_folder_figures`.
#[test]
#[ignore = "needs a generated report folder in TRIBO_REPORT"]
fn report_folder_figures_are_readable() {
    let folder = std::env::var("TRIBO_REPORT").expect("TRIBO_REPORT=<report folder>");
    let mut problems = Vec::new();
    let mut checked = 0;
    for entry in std::fs::read_dir(Path::new(&folder).join("figures")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "svg") {
            continue;
        }
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let svg = std::fs::read_to_string(&path).unwrap();
        // The page shows pictures of the domain across its width (WIDE_WIDTH in a 1 400 px
        // window), plots at most PLOT_WIDTH.
        let wide = [
            "-mesh",
            "-deformed",
            "-field",
            "-animation",
            "-step-",
            "performance-",
        ]
        .iter()
        .any(|k| name.contains(k));
        let shown = if wide { WIDE_WIDTH } else { PLOT_WIDTH };
        for p in check_svg_text(&svg, shown)
            .into_iter()
            .chain(check_svg_legends(&svg))
        {
            problems.push(format!("{name}: {p}"));
        }
        checked += 1;
    }
    assert!(checked > 0, "no SVG in {folder}/figures");
    assert!(
        problems.is_empty(),
        "{} problems in {checked} figures:\n{}",
        problems.len(),
        problems.join("\n")
    );
}
