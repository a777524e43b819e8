//! The engineering quantities (report/README.md, "Engineering quantities") against hand
//! calculations on scenes where they are known: the squeeze film of (IV.7) against the Fourier
//! series of its pressure, and a flat punch pressed into an elastic layer.

use std::f64::consts::PI;
use std::fs;

use tribo::experiment;
use tribo::results::{LastMesh, RunResult};
use tribo::study::{self, Tier};

use crate::common::{quick, rel, scratch};

/// ∫∫ w and w(½, ½) of −Δw = 1 on the unit square, w = 0 on its boundary, from the series
/// w = Σ_{m,n odd} 16 sin(mπx) sin(nπy) / (π⁴ m n (m² + n²)), summed until the terms are below
/// 1e-16.
fn unit_square_torsion() -> (f64, f64) {
    let (mut integral, mut centre) = (0.0, 0.0);
    for m in (1..4000).step_by(2) {
        for n in (1..4000).step_by(2) {
            let (m, n) = (m as f64, n as f64);
            let d = m * n * (m * m + n * n);
            integral += 64.0 / (PI.powi(6) * m * n * d);
            // sin(mπ/2) sin(nπ/2) = (−1)^((m+n)/2 − 1) for odd m, n
            let sign = if ((m + n) as i64 / 2) % 2 == 1 {
                1.0
            } else {
                -1.0
            };
            centre += sign * 16.0 / (PI.powi(4) * d);
        }
    }
    (integral, centre)
}

/// The last row's value of a column.
fn last(run: &RunResult, column: &str) -> f64 {
    run.rows
        .last()
        .and_then(|r| r.value(column))
        .unwrap_or_else(|| panic!("{}: no {column} in the last row", run.table))
}

/// IV.36 is the squeeze film (IV.7): g = 0.1, δv₃ = −10, ψ₀ = 200 on the unit square, so
/// Δψ = 12δv₃/g² = −12000 and ψ = 200 + 12000·w. The load capacity is
/// W = ∫(ψ − ψ₀)/g = 12000·∫w/g, the largest pressure p = (200 + 12000·w(½, ½))/g at the centre,
/// and the fluid the wall squeezes out, −δv₃·|Ω| = 10, leaves through the four sides.
#[test]
fn the_squeeze_films_load_capacity_is_its_series_solution() {
    let run = quick("IV.36");
    let (integral, centre) = unit_square_torsion();
    assert!(
        (integral - 0.035_144).abs() < 1e-6,
        "series ∫w = {integral}"
    );
    let (g, psi0) = (0.1, 200.0);
    let load = 12000.0 * integral / g;
    let measured = last(&run, "load_capacity");
    assert!(
        rel(measured, load).abs() < 0.01,
        "W = {measured}, series {load}"
    );
    let top = (psi0 + 12000.0 * centre) / g;
    let measured = last(&run, "max_pressure");
    assert!(
        rel(measured, top).abs() < 0.01,
        "max p = {measured}, series {top}"
    );
    assert_eq!(
        (last(&run, "max_pressure_x1"), last(&run, "max_pressure_x2")),
        (0.5, 0.5)
    );
    let sides = ["flow_left", "flow_right", "flow_bottom", "flow_top"];
    let out: f64 = sides.iter().map(|s| last(&run, s)).sum();
    // The flows come from the gradient of ψ_h on the boundary faces, first order in h.
    assert!(rel(out, 10.0).abs() < 0.02, "outflow {out}, squeezed 10");
    for s in sides {
        assert!(
            rel(last(&run, s), out / 4.0).abs() < 1e-9,
            "{s}: the four sides alike"
        );
    }
    // A squeeze without sliding: no shear force on either wall.
    for wall in ["lower", "upper"] {
        for c in ["x1", "x2"] {
            let f = last(&run, &format!("friction_{wall}_{c}"));
            assert!(f.abs() < 1e-9, "friction on the {wall} wall, {c}: {f}");
        }
    }
}

/// A flat rigid punch pressed d = 0.01 into the top of a layer of width 4 and height 1, clamped
/// at the bottom, free at the sides, with μ = 1 and λ = 0 (no Poisson effect): s = (0, −d x₂),
/// σ₂₂ = −2μd = −0.02 everywhere, so the punch carries 2μd·4 = 0.08 over its whole width, at a
/// uniform contact pressure of 0.02 (von Mises stress 0.02).
const FLAT_PUNCH: &str = r#"
table = "flat-punch"
section = "a hand calculation"
title = "flat punch on an elastic layer"

[scene]
name = "flat-punch"
domain = { x = [0.0, 4.0], y = [0.0, 1.0] }
coarse_cells = [8, 2]
effects = ["elasticity", "contact"]

[scene.elasticity]
mu = 1.0
lambda = 0.0
dirichlet = ["bottom"]

[scene.contact]
model = "z"
obstacles = [{ side = "top", shape = { kind = "constant", level = -0.01 } }]

[study]
kind = "grid-adaptive"
rows = 3
quick_rows = 3
refine_fraction = 0.3
coarsen_fraction = 0.03
convergence_window = [0, 2]
"#;

fn cell_field<'a>(mesh: &'a LastMesh, name: &str) -> &'a [f64] {
    &mesh
        .cell_fields
        .iter()
        .find(|f| f.name == name)
        .unwrap_or_else(|| panic!("no cell field {name}"))
        .values
}

#[test]
fn a_flat_punch_carries_its_hand_force() {
    let dir = scratch("flat-punch");
    let path = dir.join("flat-punch.toml");
    fs::write(&path, FLAT_PUNCH).unwrap();
    let spec = experiment::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let run = study::run(&spec, Tier::Quick, &|_, _, _| {}).unwrap_or_else(|e| panic!("{e}"));
    let (force, pressure) = (0.08, 0.02);
    for row in &run.rows {
        let f = row.value("contact_force").expect("contact_force");
        assert!(rel(f, force).abs() < 0.01, "cycle {}: F = {f}", row.cycle);
    }
    let p = last(&run, "max_contact_pressure");
    assert!(rel(p, pressure).abs() < 0.01, "max pressure {p}");
    assert!((last(&run, "contact_length") - 4.0).abs() < 1e-9);
    let mesh = run.last_mesh.as_ref().expect("the last mesh");
    let stress = cell_field(mesh, "stress");
    let mises = cell_field(mesh, "von_mises");
    assert_eq!(stress.len(), 6 * mises.len());
    for (s, m) in stress.chunks_exact(6).zip(mises) {
        assert!(rel(-s[1], pressure).abs() < 1e-6, "σ₂₂ = {}", s[1]);
        assert!(s[0].abs() < 1e-9 && s[3].abs() < 1e-9, "σ₁₁, σ₁₂: {s:?}");
        assert_eq!((s[2], s[4], s[5]), (0.0, 0.0, 0.0));
        assert!(rel(*m, pressure).abs() < 1e-6, "von Mises {m}");
    }
    let contact = &mesh
        .point_fields
        .iter()
        .find(|f| f.name == "contact_pressure")
        .expect("contact_pressure")
        .values;
    let top: Vec<f64> = contact.iter().copied().filter(|&p| p != 0.0).collect();
    assert!(!top.is_empty());
    assert!(
        top.iter().all(|&p| rel(p, pressure).abs() < 1e-6),
        "{top:?}"
    );
}
