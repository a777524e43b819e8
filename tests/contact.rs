//! Tables IV.6–IV.17: z-contact (§IV.2.1) and Signorini contact (§IV.2.2) with the estimator of
//! Theorem III.15 on the quick tier (cycles 0–3), the physics checks of the contact solver
//! (linearised constraint, complementarity, penetration) and the hard jump-obstacle cases.
//!
//! The convergence windows of all twelve tables (last four / last three cycles) lie wholly
//! beyond the quick rows, so the convergence rule is checked on the full tier only
//! (`full_tier::contact`, ignored by default; run with `-- --ignored full_tier`).

use crate::common::{quick, spec};
use tribo::experiment::{ContactEstimator, ObstacleShape, Problem as ProblemSpec};
use tribo::fe::{DofMap, System};
use tribo::mesh::Mesh;
use tribo::models::contact::ContactModel;
use tribo::results::RunResult;
use tribo::study::contact::{ContactProblem, CycleState};
use tribo::study::transfer::PreviousSolution;
use tribo::study::{self, Discretisation, PhaseClock, Problem, Tier};
use tribo::thesis::ThesisTable;

/// The contact problem of an experiment.
fn contact_problem(t: &str) -> ContactProblem {
    match &spec(t).problem {
        ProblemSpec::Contact {
            elasticity,
            contact,
        } => ContactProblem::new(elasticity, contact),
        other => panic!("{t} is not a contact table: {other:?}"),
    }
}

pub const TABLES: [&str; 12] = [
    "IV.6", "IV.7", "IV.8", "IV.9", "IV.10", "IV.11", "IV.12", "IV.13", "IV.14", "IV.15", "IV.16",
    "IV.17",
];
const SIGNORINI: [&str; 6] = ["IV.12", "IV.13", "IV.14", "IV.15", "IV.16", "IV.17"];

#[test]
fn golden_snapshots() {
    crate::common::assert_golden(&TABLES);
}

#[test]
fn cycle_zero_estimates_equal_the_printed_values() {
    for (t, printed) in [("IV.6", 1.2261), ("IV.12", 0.8374)] {
        crate::common::assert_printed_cycle_zero(t, printed);
        let r = quick(t);
        assert_eq!(
            (r.rows[0].active_cells(), r.rows[0].dofs()),
            (Some(128), Some(390)),
            "{t}"
        );
    }
}

/// Cycle 0 of a Signorini run linearises about s₀ = 0, so it equals the z-solution.
#[test]
fn signorini_cycle_zero_equals_the_z_solution() {
    for (z, s) in [
        ("IV.6", "IV.12"),
        ("IV.7", "IV.13"),
        ("IV.8", "IV.14"),
        ("IV.9", "IV.15"),
        ("IV.10", "IV.16"),
        ("IV.11", "IV.17"),
    ] {
        let (rz, rs) = (quick(z), quick(s));
        let (a, b) = (&rz.rows[0], &rs.rows[0]);
        // The Signorini table's comparison with the converged solution aside.
        let counts = |r: &tribo::results::Row| -> Vec<(String, i64)> {
            r.counts()
                .into_iter()
                .filter(|(n, _)| !tribo::study::signorini::columns::is_comparison(n))
                .map(|(n, c)| (n.to_string(), c))
                .collect()
        };
        assert_eq!(counts(a), counts(b), "{z} vs {s}: active sets of cycle 0");
        assert_eq!(
            a.value("penetration"),
            b.value("penetration"),
            "{z} vs {s}: cycle-0 solutions"
        );
    }
}

#[test]
fn constant_obstacle_agrees_with_the_thesis() {
    for t in ["IV.6", "IV.12"] {
        crate::common::assert_thesis_rows(t, &quick(t), 0.10, Some(0.15));
    }
}

/// Periodic obstacles: the obstacle terms of the thesis's codes are not calibrated, so only the
/// ratio tribo/thesis of the estimate has to be steady (≤ 15 % variation across the rows). The
/// z-tables with a smooth or kinked obstacle (IV.7, IV.8, IV.11) use the term set
/// `z-code-obstacle-slope`; with the plain z-code IV.8 fell from 0.53 to 0.39 over cycles 0–3.
#[test]
fn periodic_obstacles_agree_up_to_a_constant_factor() {
    for t in ["IV.7", "IV.8", "IV.11", "IV.13", "IV.14"] {
        let ratios = crate::common::assert_thesis_rows(t, &quick(t), 0.10, None);
        crate::common::assert_ratio_spread(t, &quick(t), &ratios, 0.15);
    }
}

/// The remaining offset of the z-tables with the obstacle-slope term is that term once more: at
/// cycle 0, on the thesis's own 64×2 mesh, thesis² − tribo² = α · obstacle_estimate² with α
/// within 10 % of 1 (IV.7 0.99, IV.8 0.93), i.e. the thesis's code carried the obstacle slope
/// about twice; the continuous saw of IV.11 needs α ≈ 3 (3.15). Later meshes differ, and α grows
/// along them (experiment notes).
#[test]
fn periodic_offset_is_explained_by_the_obstacle_term() {
    for (t, expected) in [("IV.7", 1.0), ("IV.8", 1.0), ("IV.11", 3.0)] {
        assert_eq!(
            spec(t).problem.contact().unwrap().estimator,
            Some(ContactEstimator::ZCodeObstacleSlope),
            "{t}"
        );
        let r = quick(t);
        let thesis = ThesisTable::of(&spec(t));
        for row in &r.rows[..1] {
            let e = thesis.value(row.cycle, "estimate").unwrap();
            let o = row.value("obstacle_estimate").unwrap();
            let tribo = row.estimate().unwrap();
            let alpha = (e * e - tribo * tribo) / (o * o);
            assert!(
                (alpha / expected - 1.0).abs() < 0.10,
                "{t} cycle {}: α = {alpha}",
                row.cycle
            );
        }
    }
}

#[test]
fn table_iv17_is_computed_from_the_saw_scene() {
    let s = spec("IV.17");
    assert_eq!(s.thesis.duplicate_of.as_deref(), Some("IV.13"));
    let obstacle = &s.problem.contact().unwrap().obstacles[0];
    assert!(matches!(obstacle.shape, ObstacleShape::Saw { .. }));
    let (a, b) = (quick("IV.17"), quick("IV.13"));
    assert!(
        (a.rows[0].estimate().unwrap() - b.rows[0].estimate().unwrap()).abs() > 0.1,
        "tribo's IV.17 must not copy IV.13"
    );
}

#[test]
fn active_set_iterations_are_recorded() {
    for t in TABLES {
        for row in &quick(t).rows {
            let it = row.value("active_set_iterations").expect("column");
            assert!((1.0..=50.0).contains(&it), "{t} cycle {}: {it}", row.cycle);
        }
    }
}

/// Run the quick tier with a problem we keep, so the final constraints can be inspected.
fn quick_with_state(t: &str) -> (ContactProblem, RunResult) {
    let s = spec(t);
    let mut model = contact_problem(t);
    let mut adaptation = study::build_adaptation(&s.study, &s.scene);
    let r = study::run_study(
        &s,
        Tier::Quick,
        study::Budget::machine(),
        &|_, _, _| {},
        &mut model,
        &mut *adaptation,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    (model, r)
}

pub fn check_state(t: &str, dofs: &DofMap, u: &[f64], state: &CycleState) {
    let sol = &state.solution;
    let max_lambda = sol.multipliers.iter().fold(0.0f64, |m, l| m.max(l.abs()));
    let max_gap = sol.gaps.iter().fold(0.0f64, |m, g| m.max(g.abs()));
    assert!(max_lambda > 0.0, "{t}: no contact force");
    for (i, c) in state.constraints.iter().enumerate() {
        assert!(
            !dofs.vertices.is_hanging[c.vertex as usize],
            "{t}: hanging vertex constrained"
        );
        let s = [u[dofs.dof(c.vertex, 0)], u[dofs.dof(c.vertex, 1)]];
        let ns = c.normal[0] * s[0] + c.normal[1] * s[1];
        // (s − s₀)·n ≤ g  ⇔  n·s ≤ bound
        assert!(
            ns <= c.bound + 1e-10,
            "{t}: constraint {i} violated by {}",
            ns - c.bound
        );
        let (l, g) = (sol.multipliers[i], sol.gaps[i]);
        assert!(l >= -1e-10 * max_lambda, "{t}: multiplier {l} < 0 at {i}");
        assert!(
            g >= -1e-10 * (1.0 + c.bound.abs()),
            "{t}: gap {g} < 0 at {i}"
        );
        assert!(
            (l * g).abs() <= 1e-10 * max_lambda * max_gap.max(1.0),
            "{t}: complementarity λ·gap = {} at {i}",
            l * g
        );
        if sol.active[i] {
            assert!(
                l > 0.0 && g == 0.0,
                "{t}: active constraint {i}: λ {l}, gap {g}"
            );
        }
    }
}

#[test]
fn constraints_and_complementarity_hold_at_the_solution() {
    for t in ["IV.6", "IV.9", "IV.11"].into_iter().chain(SIGNORINI) {
        let (model, _) = quick_with_state(t);
        let previous = model.previous().unwrap();
        check_state(
            t,
            &previous.dofs,
            &previous.u,
            model.state.as_ref().unwrap(),
        );
    }
}

/// The contact estimate's face indicators: one per face of Γ_C, keyed by stable ids in order along
/// the side, each the contact part of its cell's indicator, together the parts of the estimate;
/// the refined faces descend from the 64 faces of the coarse contact boundary.
#[test]
fn contact_faces_carry_indicators_under_stable_ids() {
    for t in ["IV.7", "IV.12"] {
        let (model, _) = quick_with_state(t);
        let previous = model.previous().unwrap();
        let e = model.contact_estimate(&previous.mesh, &previous.dofs, &previous.u);
        let faces: Vec<_> = e.faces.iter().map(|(f, _)| *f).collect();
        let mut sorted = faces.clone();
        sorted.sort();
        sorted.dedup();
        assert_eq!(faces, sorted, "{t}: face ids sorted and unique");
        let mesh = &previous.mesh;
        let gamma_c: usize = mesh
            .active()
            .iter()
            .filter(|&&c| mesh.boundary_face(c, tribo::mesh::Face::Bottom).is_some())
            .count();
        assert_eq!(faces.len(), gamma_c, "{t}: one indicator per contact face");
        for f in &faces {
            let mut root = *f;
            while let Some(p) = root.parent() {
                root = p;
            }
            assert_eq!((root.level, root.start % (1 << 24)), (0, 0), "{t}: {f:?}");
        }
        let total: f64 = e.faces.iter().map(|(_, v)| v).sum();
        let parts = e.contact + e.gap + if t == "IV.7" { e.obstacle } else { 0.0 };
        assert!(
            (total - parts).abs() <= 1e-12 * parts.max(1e-300),
            "{t}: faces {total} vs parts {parts}"
        );
        assert!(total > 0.0, "{t}: the contact faces carry an error");
    }
}

#[test]
fn signorini_penetrates_much_less_than_z_contact_for_two_obstacles() {
    let (z, s) = (quick("IV.10"), quick("IV.16"));
    let pz = z.rows.last().unwrap().value("penetration").unwrap();
    let ps = s.rows.last().unwrap().value("penetration").unwrap();
    assert!(pz > 0.1, "z-contact penetrates (thesis Fig. IV.20): {pz}");
    assert!(ps < 0.25 * pz, "Signorini {ps} vs z {pz}");
    // The Signorini table shows its own solution and the z-solution on the same mesh.
    assert_eq!(s.deformed.len(), 2);
    assert!(s.deformed.iter().all(|p| p.caption.contains("penetration")));
    assert!(!s.deformed[0].contact_points.is_empty());
    assert_eq!(s.deformed[0].obstacles.len(), 2);
}

/// Refine the cells touching each point `levels` times.
fn refine_at(mesh: &mut Mesh, points: &[[f64; 2]], levels: usize) {
    for _ in 0..levels {
        let mut flags = vec![false; mesh.n_active()];
        for p in points {
            for dx in [-1e-9, 1e-9] {
                let c = mesh.locate([p[0] + dx, p[1]]).expect("inside");
                flags[mesh.active_index(c)] = true;
            }
        }
        let none = vec![false; mesh.n_active()];
        mesh.refine_and_coarsen(&flags, &none).unwrap();
    }
}

fn solve_once(model: &mut ContactProblem, mesh: &Mesh) -> (DofMap, Vec<f64>) {
    let disc = Discretisation::of_mesh(mesh.clone());
    let mut system: System = model.setup(&disc);
    model
        .assemble(&disc, &mut system)
        .unwrap_or_else(|e| panic!("{e}"));
    let sol = model
        .solve(&disc, &mut system, &PhaseClock::default())
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(sol.u.iter().all(|v| v.is_finite()));
    (system.dofs, sol.u)
}

/// The θ₀.₀₁ jump obstacles on the coarsest mesh and after 12 levels of local refinement at the
/// jumps: finite solutions and a converged active set, for z-contact and for Signorini contact
/// linearised about the z-solution.
#[test]
fn jump_obstacles_stay_stable_under_local_refinement() {
    for (t, points) in [
        ("IV.9", vec![[0.0, 1.0]]),
        ("IV.10", vec![[-1.0, 0.0], [2.0, 1.0]]),
    ] {
        let s = spec(t);
        for levels in [0, 12] {
            let mut mesh = Mesh::new(
                s.scene.domain.x,
                s.scene.domain.y,
                s.scene.coarse_cells[0],
                s.scene.coarse_cells[1],
            );
            refine_at(&mut mesh, &points, levels);
            let mut z = contact_problem(t);
            let (dofs, u) = solve_once(&mut z, &mesh);
            check_state(t, &dofs, &u, z.state.as_ref().unwrap());
            let mut sig = z.with_model(ContactModel::Signorini);
            sig.set_linearisation(PreviousSolution {
                mesh: mesh.clone(),
                dofs,
                u,
            });
            let (dofs, u) = solve_once(&mut sig, &mesh);
            check_state(t, &dofs, &u, sig.state.as_ref().unwrap());
            let it = sig.state.as_ref().unwrap().solution.iterations;
            assert!(it <= 50, "{t}, {levels} levels: {it} iterations");
        }
    }
}

/// The full-tier rules of a table (`tests/full_tier.rs`): the convergence rule over its window,
/// and the agreement rules of the constant obstacles (dofs 10 %, estimate 15 %) and the periodic
/// ones (dofs 10 %, ratio spread 15 %) on every printed row.
pub fn full_tier_rules(t: &str, r: &RunResult) {
    crate::common::assert_convergence(t, r);
    match t {
        "IV.6" | "IV.12" => {
            crate::common::assert_thesis_rows(t, r, 0.10, Some(0.15));
        }
        "IV.7" | "IV.8" | "IV.13" | "IV.14" => {
            let q = crate::common::assert_thesis_rows(t, r, 0.10, None);
            crate::common::assert_ratio_spread(t, r, &q, 0.15);
        }
        _ => {}
    }
}
