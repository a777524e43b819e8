//! The pictures of the report: meshes coloured by refinement level with a legend, the zoom of a
//! strip onto its finest cells, x₁/x₂ axes on the mesh, field and deformed-body pictures,
//! obstacles hatched on their solid side, and captions that name η's theorem and the thesis
//! figure a picture corresponds to.

use std::fs;
use std::path::PathBuf;

use crate::common::no_thesis;
use tribo::results::{CellBox, DeformedPicture, FieldPicture, MeshPicture, Row, RunResult};

/// The report of one run in a fresh folder `name`; every figure must be drawn.
fn report_of(name: &str, run: &RunResult) -> PathBuf {
    let mut thesis = no_thesis(&run.table, "");
    // The thesis figures a caption cites come from the experiment file, as in a real run.
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("experiments")
        .join(format!("{}.toml", run.table));
    if file.exists() {
        thesis.figures = crate::common::spec(&run.table).figures;
    }
    crate::common::report_of(&format!("figures-{name}"), &[(run, &thesis)]).0
}

fn read(dir: &std::path::Path, file: &str) -> String {
    fs::read_to_string(dir.join(file)).unwrap_or_else(|e| panic!("{file}: {e}"))
}

/// The cells of a quadtree refined towards the point `p`: the coarse cells of width `h` over
/// `[x0, x1] × [y0, y1]`, each cell containing `p` split again, down to level `depth`; with
/// their levels.
fn refined_towards(
    [x0, x1, y0, y1]: [f64; 4],
    h: f64,
    p: [f64; 2],
    depth: u8,
) -> (Vec<CellBox>, Vec<u8>) {
    fn split(c: CellBox, level: u8, p: [f64; 2], depth: u8, out: &mut (Vec<CellBox>, Vec<u8>)) {
        let inside = (c.x0..=c.x1).contains(&p[0]) && (c.y0..=c.y1).contains(&p[1]);
        if level == depth || !inside {
            out.0.push(c);
            out.1.push(level);
            return;
        }
        let (xm, ym) = (0.5 * (c.x0 + c.x1), 0.5 * (c.y0 + c.y1));
        for (a, b, c_, d) in [
            (c.x0, xm, c.y0, ym),
            (xm, c.x1, c.y0, ym),
            (c.x0, xm, ym, c.y1),
            (xm, c.x1, ym, c.y1),
        ] {
            let child = CellBox {
                x0: a,
                x1: b,
                y0: c_,
                y1: d,
            };
            split(child, level + 1, p, depth, out);
        }
    }
    let mut out = (Vec::new(), Vec::new());
    let (nx, ny) = (
        ((x1 - x0) / h).round() as usize,
        ((y1 - y0) / h).round() as usize,
    );
    for j in 0..ny {
        for i in 0..nx {
            let c = CellBox {
                x0: x0 + i as f64 * h,
                x1: x0 + (i + 1) as f64 * h,
                y0: y0 + j as f64 * h,
                y1: y0 + (j + 1) as f64 * h,
            };
            split(c, 0, p, depth, &mut out);
        }
    }
    out
}

fn mesh_run(table: &str, section: &str, domain: [f64; 4], h: f64, p: [f64; 2]) -> RunResult {
    let (cells, levels) = refined_towards(domain, h, p, 3);
    RunResult {
        rows: vec![Row::new(0)
            .count("active_cells", cells.len())
            .count("dofs", 2 * cells.len())
            .real("estimate", Some(0.5))],
        meshes: vec![MeshPicture {
            cycle: 0,
            cells,
            levels,
            shaded: vec![],
        }],
        ..RunResult::new(table, section, "synthetic", "quick", domain)
    }
}

/// A locally refined mesh on a square: one `<path class="level-k">` per level present (0–3),
/// a legend entry "level k" for each, and x₁/x₂ tick labels.
#[test]
fn a_locally_refined_mesh_is_coloured_by_level_with_a_legend_and_axes() {
    let run = mesh_run("S", "own", [0.0, 1.0, 0.0, 1.0], 0.25, [0.3, 0.6]);
    let dir = report_of("levels", &run);
    let svg = read(&dir, "figures/S-mesh.svg");
    for k in 0..=3 {
        assert_eq!(
            svg.matches(&format!("<path class=\"level-{k}\"")).count(),
            1,
            "level {k}"
        );
        assert!(
            svg.contains(&format!(">level {k}</text>")),
            "legend of level {k}"
        );
    }
    assert!(!svg.contains("class=\"level-4\""));
    assert_eq!(svg.matches("class=\"legend-level\"").count(), 4);
    assert!(svg.contains("<g class=\"axes\">"));
    for tick in [
        ">0</text>",
        ">0.4</text>",
        ">1</text>",
        ">x₁</text>",
        ">x₂</text>",
    ] {
        assert!(svg.contains(tick), "{tick}");
    }
}

/// The detail of a strip zooms onto its finest cells: refined towards x₁ = 5 (level 3, width
/// 1/16), the window holds x₁ = 5 and is far narrower than the 4 domain heights a fixed window
/// had; the caption of the mesh names the thesis figure of the grids of Table IV.7.
#[test]
fn the_detail_of_a_strip_zooms_onto_its_finest_cells() {
    let run = mesh_run("IV.7", "IV.2.1.2", [-16.0, 16.0, 0.0, 1.0], 0.5, [5.0, 0.1]);
    let dir = report_of("detail", &run);
    let svg = read(&dir, "figures/IV.7-mesh.svg");
    let line = svg
        .lines()
        .find(|l| l.contains("detail: x₁ ∈ ["))
        .expect("the detail's label");
    let numbers: Vec<f64> = line
        .split_once("detail:")
        .expect("the label")
        .1
        .split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'))
        .filter_map(|s| s.parse().ok())
        .collect();
    let [a, b, c, d] = numbers[..] else {
        panic!("{line}");
    };
    assert!(a < 5.0 && 5.0 < b && b - a < 2.0, "{line}");
    assert!(c <= 0.1 && 0.1 <= d, "{line}");
    assert!(svg.contains("(level 3, width 0.0625)"), "{svg}");
    let page = tribo::report::read_pages(&dir).unwrap();
    assert!(
        page.contains("(cf. thesis Fig. IV.12)"),
        "grids of Table IV.7"
    );
    // The convergence and cost captions say which estimate: Theorem III.15, energy norm.
    assert!(
        page.contains("the estimate η of Theorem III.15 of the contact error in the energy norm")
    );
    let convergence = read(&dir, "figures/IV.7-convergence.svg");
    assert!(convergence.contains("η, energy norm (Thm III.15)"));
}

/// A field map carries x₁/x₂ ticks in domain coordinates, and its caption names the thesis
/// figure of the solution (Table IV.36: Fig. IV.57).
#[test]
fn a_field_map_has_axes_and_names_its_thesis_figure() {
    let (cells, _) = refined_towards([0.0, 2.0, 0.0, 1.0], 0.25, [0.5, 0.5], 1);
    let run = RunResult {
        fields: vec![FieldPicture {
            cycle: 2,
            name: "psi".into(),
            cells: cells.iter().map(|c| (*c, c.x0 + c.y0)).collect(),
            zone: vec![],
            zone_label: String::new(),
            arrows: vec![],
        }],
        ..RunResult::new(
            "IV.36",
            "IV.3.1.1",
            "synthetic",
            "quick",
            [0.0, 2.0, 0.0, 1.0],
        )
    };
    let dir = report_of("field", &run);
    let svg = read(&dir, "figures/IV.36-field-psi.svg");
    assert!(svg.contains("<g class=\"axes\">"));
    for tick in [
        ">0</text>",
        ">1</text>",
        ">2</text>",
        ">0.4</text>",
        ">x₁</text>",
        ">x₂</text>",
    ] {
        assert!(svg.contains(tick), "{tick}");
    }
    let page = tribo::report::read_pages(&dir).unwrap();
    assert!(page.contains("after cycle 2, x₁/x₂ axes (cf. thesis Fig. IV.57)"));
}

/// An obstacle under the body is hatched below its curve: the solid-side path closes under the
/// window, i.e. its two closing points lie below every point of the curve on screen.
#[test]
fn an_obstacle_is_hatched_on_its_solid_side() {
    let quad = |x: f64| [[x, 0.0], [x + 1.0, 0.0], [x + 1.0, 1.0], [x, 1.0]];
    let pic = |obstacle_y: f64| DeformedPicture {
        cycle: 0,
        scale: 1.0,
        quads: vec![quad(0.0), quad(1.0), quad(2.0), quad(3.0)],
        obstacles: vec![vec![[-1.0, obstacle_y], [5.0, obstacle_y]]],
        contact_points: vec![],
        accurate_faces: vec![],
        caption: String::new(),
    };
    let run = RunResult {
        deformed: vec![pic(-0.05), pic(1.05)],
        ..RunResult::new(
            "IV.9",
            "IV.2.1.4",
            "synthetic",
            "quick",
            [0.0, 4.0, 0.0, 1.0],
        )
    };
    let dir = report_of("hatch", &run);
    for (file, below) in [
        ("IV.9-deformed-0.svg", true),
        ("IV.9-deformed-1.svg", false),
    ] {
        let svg = read(&dir, &format!("figures/{file}"));
        let path = svg
            .lines()
            .find(|l| l.contains("class=\"obstacle-solid\""))
            .unwrap_or_else(|| panic!("{file}: no hatched solid side"));
        assert!(path.contains("fill=\"url(#solid)\""), "{path}");
        let d = path.split("d=\"").nth(1).unwrap().trim_end_matches("\"/>");
        // M x edge L x y L x y L x edge z
        let ys: Vec<i64> = d
            .trim_end_matches('z')
            .split(['M', 'L'])
            .filter(|s| !s.is_empty())
            .map(|p| p.split(' ').nth(1).unwrap().parse().unwrap())
            .collect();
        let (edge, curve) = (ys[0], ys[1]);
        assert_eq!(ys[0], *ys.last().unwrap());
        assert_eq!(edge > curve, below, "{file}: {d}");
        assert!(svg.contains("<g class=\"axes\">"), "{file}");
    }
    let page = tribo::report::read_pages(&dir).unwrap();
    assert!(page.contains("hatched on their solid side (cf. thesis Fig. IV.18)"));
}
