//! Tables IV.1–IV.5 (linear elasticity, Theorem III.12) on the quick tier, and the element
//! checks: patch test, manufactured solution, determinism.

use std::f64::consts::PI;
use std::sync::Arc;

use crate::common::{quick, spec};
use tribo::adaptivity::{mark_fixed_number, rounded_measure};
use tribo::estimators::{self, elasticity::BoundaryTerms};
use tribo::fe::quadrature::square_rule;
use tribo::fe::{CellValues, DofMap, System};
use tribo::linalg::DirectSolver;
use tribo::mesh::{Mesh, Side};
use tribo::models::elasticity::{Elasticity, VolumeForce};
use tribo::results::RunResult;
use tribo::study::{self, Tier};

pub const TABLES: [&str; 5] = ["IV.1", "IV.2", "IV.3", "IV.4", "IV.5"];

/// The full-tier rules of a table (`tests/full_tier.rs`): every row within 3 % of the printed
/// dofs and 5 % of the printed estimate, and the convergence rule over the window.
pub fn full_tier_rules(t: &str, r: &RunResult) {
    crate::common::assert_thesis_rows(t, r, 0.03, Some(0.05));
    crate::common::assert_convergence(t, r);
}

#[test]
fn golden_snapshots() {
    crate::common::assert_golden(&TABLES);
}

#[test]
fn cycle_zero_estimates_equal_the_printed_values() {
    for (t, printed) in [
        ("IV.1", 0.6881),
        ("IV.2", 1.7202),
        ("IV.3", 0.1021),
        ("IV.4", 0.3676),
        ("IV.5", 2.0788),
    ] {
        crate::common::assert_printed_cycle_zero(t, printed);
        let r = quick(t);
        assert_eq!(
            (r.rows[0].active_cells(), r.rows[0].dofs()),
            (Some(128), Some(390)),
            "{t}"
        );
    }
}

#[test]
fn cycle_one_has_248_cells() {
    for t in TABLES {
        assert_eq!(
            quick(t).rows[1].active_cells(),
            Some(248),
            "{t}: 40 cells flagged in cycle 0"
        );
    }
}

#[test]
fn quick_tier_agrees_with_the_thesis() {
    for t in TABLES {
        let r = quick(t);
        crate::common::assert_thesis_rows(t, &r, 0.03, Some(0.05));
    }
}

/// The convergence rule on the quick tier's rows 1–3 (its window [2, 5] holds two rows, too
/// few for an order).
#[test]
fn convergence_rate_inside_the_window() {
    for t in TABLES {
        let order = crate::common::convergence_rule(&quick(t).rows, [1, 3]);
        assert!(order.is_ok(), "{t}: {order:?}");
    }
}

/// a(e, e) for e = u − u_h with the exact gradient `grad`.
fn energy_error(
    mesh: &Mesh,
    dofs: &DofMap,
    u: &[f64],
    p: &Elasticity,
    grad: &dyn Fn([f64; 2]) -> [[f64; 2]; 2],
) -> f64 {
    let rule = square_rule::<16>();
    let mut sum = 0.0;
    for (k, &c) in mesh.active().iter().enumerate() {
        let cv = CellValues::new(mesh.cell_shape(c), &rule);
        for q in 0..rule.len() {
            let x = cv.point(q);
            let gh = Elasticity::gradient_at(mesh, dofs, u, k, x);
            let g = grad(x);
            let e = [
                [g[0][0] - gh[0][0], g[0][1] - gh[0][1]],
                [g[1][0] - gh[1][0], g[1][1] - gh[1][1]],
            ];
            let s = p.stress(e);
            // σ(e):ε(e) = 2μ ε:ε + 2λ (div e)²
            let eps01 = 0.5 * (e[0][1] + e[1][0]);
            let val = s[0][0] * e[0][0] + s[1][1] * e[1][1] + 2.0 * s[0][1] * eps01;
            sum += val * cv.jxw(q);
        }
    }
    sum.sqrt()
}

/// Solve on `mesh` with the Dirichlet values `fixed_values` on the Dirichlet sides.
fn solve(
    mesh: &Mesh,
    p: &Elasticity,
    fixed_values: &dyn Fn([f64; 2]) -> [f64; 2],
) -> (DofMap, Vec<f64>) {
    let mut system = System::new(mesh, 2);
    p.constrain(&mut system);
    for (d, _) in system.constraints.eliminated() {
        let v = d / 2;
        if system.constraints.is_fixed(d) {
            let x = system.dofs.vertices.coords[v];
            system.constraints.fix(d, fixed_values(x)[d % 2]);
        }
    }
    p.assemble(mesh, &mut system);
    let mut solver = DirectSolver::cholesky();
    solver.reorder(system.ordering());
    let mut u = solver
        .solve(
            system.matrix(),
            &system.rhs,
            &system.constraints.eliminated(),
        )
        .expect("solve");
    system.constraints.distribute(&mut u);
    (system.dofs, u)
}

#[test]
fn patch_test_reproduces_linear_displacements_with_hanging_nodes() {
    let mut mesh = Mesh::new([0.0, 2.0], [0.0, 1.0], 4, 2);
    for target in [[0.6, 0.4], [0.62, 0.41], [0.63, 0.42]] {
        crate::common::refine_around(&mut mesh, target, 1);
    }
    let lin = |x: [f64; 2]| {
        [
            0.1 + 0.3 * x[0] - 0.2 * x[1],
            -0.05 + 0.15 * x[0] + 0.4 * x[1],
        ]
    };
    let p = Elasticity {
        mu: 1.0,
        lambda: 1.0,
        dirichlet: vec![Side::Left, Side::Right, Side::Bottom, Side::Top],
        load: None,
        tractions: vec![],
    };
    let (dofs, u) = solve(&mesh, &p, &lin);
    assert!(!dofs.vertices.hanging.is_empty());
    let scale = 1.0;
    for (v, x) in dofs.vertices.coords.iter().enumerate() {
        let e = lin(*x);
        for c in 0..2 {
            assert!(
                (u[2 * v + c] - e[c]).abs() <= 1e-12 * scale,
                "vertex {v} comp {c}: {} vs {}",
                u[2 * v + c],
                e[c]
            );
        }
    }
}

#[test]
fn reused_solver_work_arrays_give_the_fresh_solution_bitwise() {
    // The problems keep one direct solver from mesh to mesh, with its factor and scratch
    // arrays; a stale value must not leak into a solve, whether the next system is larger or
    // smaller.
    let p = Elasticity {
        mu: 1.0,
        lambda: 1.0,
        dirichlet: vec![Side::Left],
        load: Some(VolumeForce::Field(Arc::new(|x| [0.3, -1.0 - x[0]]))),
        tractions: vec![],
    };
    // A solver reordered for a new mesh keeps its work arrays (DirectSolver::reorder).
    let solve_on = |mesh: &Mesh, solver: &mut DirectSolver, reorder: bool| {
        let mut system = System::new(mesh, 2);
        p.constrain(&mut system);
        p.assemble(mesh, &mut system);
        if reorder {
            solver.reorder(system.ordering());
        }
        solver
            .solve(
                system.matrix(),
                &system.rhs,
                &system.constraints.eliminated(),
            )
            .expect("solve")
    };
    let small = Mesh::new([0.0, 2.0], [0.0, 1.0], 4, 2);
    let mut large = Mesh::new([0.0, 2.0], [0.0, 1.0], 16, 8);
    crate::common::refine_around(&mut large, [0.7, 0.3], 3);
    let fresh = |mesh: &Mesh| solve_on(mesh, &mut DirectSolver::cholesky(), true);
    let (fresh_small, fresh_large) = (fresh(&small), fresh(&large));
    assert!(fresh_large.iter().any(|&v| v != 0.0));

    let mut solver = DirectSolver::cholesky();
    solve_on(&large, &mut solver, true);
    assert_eq!(
        solve_on(&small, &mut solver, true),
        fresh_small,
        "large → small"
    );
    assert_eq!(
        solve_on(&small, &mut solver, false),
        fresh_small,
        "same system again"
    );
    assert_eq!(
        solve_on(&large, &mut solver, true),
        fresh_large,
        "small → large"
    );
}

/// The unit square as a coarse `n × n` grid whose interior vertices are moved by up to a fifth
/// of a cell in a fixed, irregular pattern: every coarse cell is a general quadrilateral, the
/// boundary stays the square's.
fn moved_unit_square(n: usize) -> Mesh {
    let h = 1.0 / n as f64;
    let mut vertices = Vec::with_capacity((n + 1) * (n + 1));
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f64 * h, j as f64 * h);
            let interior = i > 0 && i < n && j > 0 && j < n;
            let (dx, dy) = if interior {
                let t = (i * 7 + j * 13) as f64;
                (0.2 * h * t.sin(), 0.2 * h * (1.3 * t).cos())
            } else {
                (0.0, 0.0)
            };
            vertices.push([x + dx, y + dy]);
        }
    }
    Mesh::with_coarse_vertices(n, n, vertices).expect("no folded cell")
}

/// All four sides clamped, no load.
fn clamped(load: Option<VolumeForce>) -> Elasticity {
    Elasticity {
        mu: 1.0,
        lambda: 1.0,
        dirichlet: vec![Side::Left, Side::Right, Side::Bottom, Side::Top],
        load,
        tractions: vec![],
    }
}

#[test]
fn patch_test_holds_on_moved_cells_with_hanging_nodes() {
    let mut mesh = moved_unit_square(4);
    for target in [[0.4, 0.35], [0.41, 0.36], [0.7, 0.6]] {
        crate::common::refine_around(&mut mesh, target, 1);
    }
    assert!(mesh.is_moved());
    let lin = |x: [f64; 2]| {
        [
            0.1 + 0.3 * x[0] - 0.2 * x[1],
            -0.05 + 0.15 * x[0] + 0.4 * x[1],
        ]
    };
    let (dofs, u) = solve(&mesh, &clamped(None), &lin);
    assert!(!dofs.vertices.hanging.is_empty());
    for (v, x) in dofs.vertices.coords.iter().enumerate() {
        let e = lin(*x);
        for c in 0..2 {
            assert!(
                (u[2 * v + c] - e[c]).abs() <= 1e-12,
                "vertex {v} at {x:?}, component {c}: {} vs {}",
                u[2 * v + c],
                e[c]
            );
        }
    }
}

/// u = (sin πx sin πy, x(1−x)y(1−y)) on [0,1]², μ = λ = 1, a(s,r) = 2μ⟨ε,ε⟩ + 2λ⟨div,div⟩:
/// div σ = μΔu + (μ + 2λ)∇ div u, f = −div σ. Eleven cycles of fixed-number marking (30 %/3 %)
/// from `mesh`; returns the least-squares slope of log ‖u − u_h‖_a against log dofs over the last
/// five meshes, and the effectivities η/‖u − u_h‖_a of the last three.
fn manufactured_convergence(mut mesh: Mesh) -> (f64, Vec<f64>) {
    let (mu, lambda) = (1.0, 1.0);
    let f = move |x: [f64; 2]| {
        let (s, c) = ((PI * x[0]).sin(), (PI * x[0]).cos());
        let (sy, cy) = ((PI * x[1]).sin(), (PI * x[1]).cos());
        let (a, b) = (x[0] * (1.0 - x[0]), x[1] * (1.0 - x[1]));
        let lap = [-2.0 * PI * PI * s * sy, -2.0 * b - 2.0 * a];
        // div u = π cos πx sin πy + a (1 − 2y)
        let grad_div = [
            -PI * PI * s * sy + (1.0 - 2.0 * x[0]) * (1.0 - 2.0 * x[1]),
            PI * PI * c * cy - 2.0 * a,
        ];
        [
            -(mu * lap[0] + (mu + 2.0 * lambda) * grad_div[0]),
            -(mu * lap[1] + (mu + 2.0 * lambda) * grad_div[1]),
        ]
    };
    let grad = |x: [f64; 2]| {
        let (s, c) = ((PI * x[0]).sin(), (PI * x[0]).cos());
        let (sy, cy) = ((PI * x[1]).sin(), (PI * x[1]).cos());
        [
            [PI * c * sy, PI * s * cy],
            [
                (1.0 - 2.0 * x[0]) * x[1] * (1.0 - x[1]),
                x[0] * (1.0 - x[0]) * (1.0 - 2.0 * x[1]),
            ],
        ]
    };
    let p = clamped(Some(VolumeForce::Field(Arc::new(f))));
    let (mut n, mut err, mut eff) = (vec![], vec![], vec![]);
    for _ in 0..11 {
        let (dofs, u) = solve(&mesh, &p, &|_| [0.0, 0.0]);
        let eta2 =
            estimators::elasticity::indicators(&mesh, &dofs, &u, &p, &BoundaryTerms::default());
        let e = energy_error(&mesh, &dofs, &u, &p, &grad);
        n.push(dofs.n_dofs() as f64);
        err.push(e);
        eff.push(estimators::total(&eta2) / e);
        let eta: Vec<f64> = eta2.iter().map(|v| v.sqrt()).collect();
        let m = mark_fixed_number(
            &eta,
            |k| rounded_measure(&mesh, mesh.active()[k]),
            0.3,
            0.03,
        );
        mesh.refine_and_coarsen(&m.refine, &m.coarsen).unwrap();
    }
    let k = n.len() - 5;
    let (xs, ys): (Vec<f64>, Vec<f64>) = (
        n[k..].iter().map(|v| v.ln()).collect(),
        err[k..].iter().map(|v| v.ln()).collect(),
    );
    let (mx, my) = (xs.iter().sum::<f64>() / 5.0, ys.iter().sum::<f64>() / 5.0);
    let slope = xs
        .iter()
        .zip(&ys)
        .map(|(x, y)| (x - mx) * (y - my))
        .sum::<f64>()
        / xs.iter().map(|x| (x - mx).powi(2)).sum::<f64>();
    eprintln!("slope {slope}, errors {err:?}, dofs {n:?}, effectivities {eff:?}");
    (slope, eff[eff.len() - 3..].to_vec())
}

/// The rate −½ of the energy error against the dofs, and an effectivity of the estimator of
/// Theorem III.12 in [0.5, 20] that varies by at most 20 % over the last three meshes.
fn assert_rate_and_effectivity(slope: f64, effectivities: &[f64]) {
    assert!((-0.55..=-0.45).contains(&slope), "slope {slope}");
    for e in effectivities {
        assert!((0.5..=20.0).contains(e), "effectivity {e}");
    }
    let (lo, hi) = effectivities
        .iter()
        .fold((f64::MAX, 0.0f64), |(a, b), &e| (a.min(e), b.max(e)));
    assert!(
        hi / lo - 1.0 <= 0.2,
        "effectivity varies: {effectivities:?}"
    );
}

#[test]
fn manufactured_solution_converges_with_rate_one_half_and_stable_effectivity() {
    let (slope, eff) = manufactured_convergence(Mesh::new([0.0, 1.0], [0.0, 1.0], 4, 4));
    assert_rate_and_effectivity(slope, &eff);
}

/// The same on general quadrilaterals: Q₁ on the bilinear map of every cell, the estimator with
/// the Hessian of the mapped field and the normals of the moved faces.
#[test]
fn manufactured_solution_converges_on_moved_cells() {
    let (slope, eff) = manufactured_convergence(moved_unit_square(4));
    assert_rate_and_effectivity(slope, &eff);
}

#[test]
fn one_and_two_threads_give_bitwise_identical_tables() {
    // Elasticity IV.4, Reynolds IV.36 and Reynolds with cavitation IV.65 (quick tier).
    for t in ["IV.4", "IV.36", "IV.65"] {
        let s = spec(t);
        let run = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| study::run(&s, Tier::Quick, &|_, _, _| {}).unwrap())
        };
        let (a, b) = (run(1), run(2));
        assert_eq!(a.rows.len(), b.rows.len(), "{t}");
        for (x, y) in a.rows.iter().zip(&b.rows) {
            assert_eq!(x.columns.len(), y.columns.len(), "{t}");
            for ((name, a), (_, b)) in x.columns.iter().zip(&y.columns) {
                let bits = |v: &tribo::results::Value| v.as_f64().map(f64::to_bits);
                assert_eq!(bits(a), bits(b), "{t} cycle {} column {name}", x.cycle);
            }
        }
        assert_eq!(a.probes.len(), b.probes.len(), "{t}");
        for (x, y) in a.probes.iter().zip(&b.probes) {
            assert_eq!(x.value.to_bits(), y.value.to_bits(), "{t}");
        }
    }
}
