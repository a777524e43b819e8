//! Fig. IV.116 (the model-adaptive fluid simulation of §IV.3.4) as the experiment `fig-IV.116`:
//! golden snapshot of the quick tier (3 cycles), SubStokes cells growing from the wide gap,
//! the rows' columns, and the full-tier rule.

use crate::common::quick;
use tribo::results::RunResult;

pub const FIGURE: &str = "fig-IV.116";

#[test]
fn golden_snapshot() {
    crate::common::assert_golden(&[FIGURE]);
}

/// Row 0 is the pure Reynolds solve on the 8×8 grid; the SubStokes cells then rise strictly;
/// the total is the root of the sum of the squares of its parts; every SubStokes cell of the
/// first model step lies where the gap is wide (the grey cells of the mesh picture).
#[test]
fn substokes_cells_grow_from_the_wide_gap() {
    let r = quick(FIGURE);
    assert_eq!(r.rows.len(), 3);
    assert_eq!(r.rows[0].count_of("substokes_cells"), Some(0));
    assert_eq!(r.rows[0].count_of("active_cells"), Some(64));
    assert_substokes_rise(&r, 2);
    for row in &r.rows {
        let parts = ["estimate_substokes", "estimate_reynolds", "model_error"]
            .map(|c| row.value(c).unwrap());
        let total = parts.iter().map(|p| p * p).sum::<f64>().sqrt();
        let e = row.estimate().unwrap();
        assert!(
            (e - total).abs() <= 1e-12 * e,
            "row {}: {e} vs {total}",
            row.cycle
        );
    }
    let gap = |x: f64| 0.1 + 0.07 * (std::f64::consts::TAU * 2.0 * x).sin();
    let first = &r.meshes[1];
    assert!(!first.shaded.is_empty());
    for c in &first.shaded {
        // The mean of the gap over the cell (it depends on x₁ only), by the midpoint rule.
        let mean = (0..16)
            .map(|i| gap(c.x0 + (i as f64 + 0.5) / 16.0 * (c.x1 - c.x0)))
            .sum::<f64>()
            / 16.0;
        assert!(
            mean > 0.1,
            "SubStokes cell [{}, {}] has mean gap {mean}",
            c.x0,
            c.x1
        );
    }
    let cuts = r.cuts.as_ref().expect("the coupled ψ along x₂ = ½");
    assert_eq!(cuts.column("psi").unwrap().len(), 101);
}

/// The SubStokes cells rise strictly over cycles 1 … `last`.
pub fn assert_substokes_rise(r: &RunResult, last: usize) {
    let cells: Vec<i64> = r
        .rows
        .iter()
        .map(|row| row.count_of("substokes_cells").unwrap())
        .collect();
    for k in 1..last {
        assert!(cells[k + 1] > cells[k], "SubStokes cells {cells:?}");
    }
}

/// Full tier (`full_tier::model_fluid`): 8 cycles, the SubStokes cells rise strictly over
/// cycles 1–4, the total estimate decreases in every cycle.
pub fn full_tier_rules(table: &str, r: &RunResult) {
    assert_eq!(r.rows.len(), 8, "{table}");
    assert_substokes_rise(r, 4);
    for row in r.rows.iter().skip(1) {
        let q = row.ratio().unwrap();
        assert!(q < 1.0, "{table} cycle {}: ratio {q}", row.cycle);
    }
}

/// With its related tables on the page, the model-adaptive film gets Figs IV.117 and IV.118 and
/// the cost of accuracy of (IV.17) solved three ways, each with a curve of every related run;
/// alone, the captions name the tables that are missing and how to add them.
#[test]
fn related_figures_set_the_pure_runs_beside_it() {
    let experiments = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments");
    let out = crate::outputs::quick_report(
        &experiments,
        "related",
        Some(&format!("IV.46,IV.60,{FIGURE}")),
    );
    let figure = |kind: &str| {
        std::fs::read_to_string(out.join("figures").join(format!("{FIGURE}-{kind}.svg")))
            .unwrap_or_else(|e| panic!("{FIGURE}-{kind}.svg: {e}"))
    };
    for (kind, labels) in [
        ("substokes-cells", &["pure SubStokes (IV.60)"][..]),
        (
            "related-cuts",
            &["pure Reynolds (IV.46)", "pure SubStokes (IV.60)"][..],
        ),
        (
            "related-cost",
            &["pure Reynolds (IV.46)", "pure SubStokes (IV.60)"][..],
        ),
    ] {
        let svg = figure(kind);
        assert!(svg.contains(&format!("model-adaptive ({FIGURE})")) || kind == "substokes-cells");
        for label in labels {
            assert!(svg.contains(label), "{kind} lacks the curve {label}");
        }
    }
    // The Reynolds table's cut: ψ on ∂Ω₂ at both ends, 101 points.
    let cut = std::fs::read_to_string(out.join("data").join("IV.46.cuts.csv")).unwrap();
    let lines: Vec<&str> = cut.lines().collect();
    assert_eq!(lines[0], "x,psi");
    assert_eq!(lines.len(), 102);
    for line in [lines[1], lines[101]] {
        let psi: f64 = line.split(',').nth(1).unwrap().parse().unwrap();
        assert!((psi - 200.0).abs() < 1e-9, "{line}");
    }
    let page = tribo::report::read_pages(&out).unwrap();
    assert!(!page.contains("not in this report"));

    let alone = crate::outputs::quick_report(&experiments, "related-alone", Some(FIGURE));
    let page = tribo::report::read_pages(&alone).unwrap();
    assert!(
        page.contains("IV.46, IV.60 not in this report: run the report with them, e.g. --only fig-IV.116,IV.46,IV.60"),
        "the captions name the missing related tables"
    );
}
