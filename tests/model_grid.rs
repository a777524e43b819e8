//! Tables IV.30–IV.35: model and grid adaptivity balanced by Algorithm III.25 (§IV.2.4). The
//! quick tier runs cycles 0–3; the full tier (ignored, `full_tier`) all ten rows.

use std::collections::BTreeSet;

use crate::common::{quick, rel, spec};
use tribo::adaptivity::model::ModelUnit;
use tribo::estimators::FaceIndicators;
use tribo::mesh::{BoundaryFace, Face, Mesh, Side, MAX_LEVEL};
use tribo::results::RunResult;
use tribo::study::adapt::{boundary_faces, inherit_face_models as inherit_models};
use tribo::study::{
    Adaptation, Balanced, Discretisation, Estimate, FixedNumber, GridIndicator, ModelMarking,
    Models,
};
use tribo::thesis::ThesisTable;

pub const TABLES: [&str; 6] = ["IV.30", "IV.31", "IV.32", "IV.33", "IV.34", "IV.35"];

fn value(r: &RunResult, cycle: usize, column: &str) -> f64 {
    r.rows[cycle]
        .value(column)
        .unwrap_or_else(|| panic!("{}: no {column} in cycle {cycle}", r.table))
}

/// Every row's dofs within 10 % of the printed row.
fn assert_dofs_within_10_percent(t: &str, rows: &[tribo::results::Row], thesis: &ThesisTable) {
    for row in rows {
        let printed = thesis.value(row.cycle, "dofs").unwrap();
        let dofs = row.value("dofs").unwrap();
        assert!(
            rel(dofs, printed).abs() <= 0.10,
            "{t} cycle {}: {dofs} dofs, printed {printed}",
            row.cycle
        );
    }
}

#[test]
fn golden_snapshots() {
    crate::common::assert_golden(&TABLES);
}

/// Cycle 0 is the 64×2 grid with every contact face on the z-model (128 faces on the two
/// contact sides of IV.34); the dofs of every computed row are within 10 % of the printed ones.
#[test]
fn start_on_z_faces_and_printed_dofs() {
    for t in TABLES {
        let r = quick(t);
        let thesis = ThesisTable::of(&spec(t));
        let faces = if t == "IV.34" { 128.0 } else { 64.0 };
        assert_eq!(value(&r, 0, "z_faces"), faces, "{t}");
        assert_eq!(value(&r, 0, "s_faces"), 0.0, "{t}");
        assert_eq!(r.rows.len(), 4, "{t}: quick tier = cycles 0–3");
        assert_dofs_within_10_percent(t, &r.rows, &thesis);
    }
}

/// Table IV.30 (flat obstacle): the MGA term set reproduces the cycle-0 "interior" estimate to
/// 4 digits and the z-boundary estimate to 0.5 %; there is never a model error nor an S-face,
/// and both estimates stay within 15 % of the printed rows.
#[test]
fn flat_obstacle_estimates() {
    let r = quick("IV.30");
    let thesis = ThesisTable::of(&spec("IV.30"));
    assert_eq!(format!("{:.4}", value(&r, 0, "est_interior")), "0.6213");
    let z = value(&r, 0, "est_z_boundary");
    assert!(rel(z, 0.5941).abs() <= 0.005, "est_z_boundary {z}");
    for row in &r.rows {
        let c = row.cycle;
        assert_eq!(value(&r, c, "model_error"), 0.0, "cycle {c}");
        assert_eq!(value(&r, c, "s_faces"), 0.0, "cycle {c}");
        for column in ["est_z_boundary", "est_interior"] {
            let (ours, printed) = (value(&r, c, column), thesis.value(c, column).unwrap());
            assert!(
                rel(ours, printed).abs() <= 0.15,
                "cycle {c}: {column} {ours} vs printed {printed}"
            );
        }
    }
}

/// The three groups are the whole estimate: estimate² = z² + S² + interior².
#[test]
fn estimate_groups_add_up() {
    for t in TABLES {
        let r = quick(t);
        for row in &r.rows {
            let c = row.cycle;
            let groups: f64 = ["est_z_boundary", "est_s_boundary", "est_interior"]
                .iter()
                .map(|g| value(&r, c, g).powi(2))
                .sum();
            let total = value(&r, c, "estimate");
            assert!(
                (groups.sqrt() - total).abs() <= 1e-12 * total,
                "{t} cycle {c}: √Σ groups {} vs estimate {total}",
                groups.sqrt()
            );
        }
    }
}

/// Hard cases: the jump scenes, where Signorini faces sit on the jumps (IV.33 one jump, IV.34 two
/// obstacles on two sides), stay finite and every active-set solve converges in ≤ 50 iterations.
#[test]
fn jump_scenes_stay_finite() {
    for t in ["IV.33", "IV.34"] {
        let r = quick(t);
        assert!(
            r.rows.iter().any(|row| row.value("s_faces").unwrap() > 0.0),
            "{t}: some Signorini face in cycles 1–3"
        );
        for row in &r.rows {
            for (name, v) in &row.columns {
                if let Some(x) = v.as_f64() {
                    assert!(x.is_finite(), "{t} cycle {}: {name} = {x}", row.cycle);
                }
            }
            for it in ["z_iterations", "mixed_iterations"] {
                let n = row.count_of(it).unwrap();
                assert!(n <= 50, "{t} cycle {}: {it} = {n}", row.cycle);
            }
        }
    }
}

fn face(start: u64, level: u8) -> BoundaryFace {
    let width = 1u64 << (MAX_LEVEL - level);
    BoundaryFace::spanning(Side::Bottom, start * width, (start + 1) * width)
}

/// Refined faces pass their model to both children; a face made by coarsening is Signorini if
/// any face it replaces was; other faces stay z.
#[test]
fn faces_inherit_their_model() {
    let accurate: BTreeSet<BoundaryFace> = [face(0, 1), face(5, 2)].into();
    // After: face(0,1) refined into face(0,2), face(1,2); face(5,2) and face(4,2) coarsened
    // into face(2,1); face(3,1) untouched.
    let new = [face(0, 2), face(1, 2), face(1, 1), face(2, 1), face(3, 1)];
    let got = inherit_models(&accurate, &new);
    let expected: BTreeSet<BoundaryFace> = [face(0, 2), face(1, 2), face(2, 1)].into();
    assert_eq!(got, expected);
    // Nothing Signorini, nothing inherited.
    assert!(inherit_models(&BTreeSet::new(), &new).is_empty());
}

/// (III.93) on a synthetic estimate, 8×1 cells over [0, 8]: the left cells have the larger
/// discretisation indicators (η ≈ 2, right ≈ 1), but the model error of their bottom faces
/// (10–13) dominates them; on the right half it is 0. With α = 0.5 the left cells are not
/// refined (ε̃_d = 0), the right ones are, and the model marking moves left faces; with
/// α = 0.01 the balance no longer blocks the left cells, which the grid marking refines.
#[test]
fn balance_separates_model_and_grid_refinement() {
    let run = |alpha: f64| {
        let mesh = Mesh::new([0.0, 8.0], [0.0, 1.0], 8, 1);
        let mut disc = Discretisation::of_mesh(mesh);
        let cells: Vec<f64> = (0..8)
            .map(|k| if k < 4 { 2.0 } else { 1.0 } + 0.01 * k as f64)
            .collect();
        let faces: FaceIndicators = disc
            .mesh
            .active()
            .iter()
            .enumerate()
            .map(|(k, &c)| {
                let f = disc.mesh.boundary_face(c, Face::Bottom).unwrap();
                (f, if k < 4 { 10.0 + k as f64 } else { 0.0 })
            })
            .collect();
        let estimate = Estimate {
            cells: cells.iter().map(|e| e * e).collect(),
            models: faces
                .iter()
                .map(|&(f, e)| (ModelUnit::Face(f), e))
                .collect(),
            columns: Vec::new(),
            noise_floor: None,
            body_motion: None,
        };
        let mut balanced = Balanced {
            model: ModelMarking {
                algorithm: tribo::experiment::ModelAlgorithm::SortedError,
                refine: 0.02,
                coarsen: 0.01,
                tolerance: 1e-7,
            },
            grid: FixedNumber {
                refine: 0.3,
                coarsen: 0.0,
                ties: tribo::experiment::Ties::Band,
                smoothing: Default::default(),
            },
            alpha,
            grid_indicator: GridIndicator::Eta,
        };
        balanced.adapt(&mut disc, &estimate).unwrap();
        let bottom = boundary_faces(&disc.mesh, &[Side::Bottom].into());
        let refined: Vec<bool> = faces.iter().map(|(f, _)| !bottom.contains(f)).collect();
        (refined, disc)
    };
    let (refined, disc) = run(0.5);
    // Fixed number: the ⌊0.3·8⌋ + 1 = 3 largest non-zero ε̃_d, all on the right.
    assert_eq!(
        refined,
        [false, false, false, false, false, true, true, true],
        "α = 0.5: only right-half cells are refined"
    );
    // III.3 swaps the largest ε̃_m (the left faces: 13 first) to Signorini; the refined right
    // faces are z and their children stay z.
    assert!(disc.models.accurate_faces().next().is_some());
    let bottom = boundary_faces(&disc.mesh, &[Side::Bottom].into());
    for f in disc.models.accurate_faces() {
        assert!(bottom.contains(&f));
        assert!(
            f.start < 4 << MAX_LEVEL,
            "Signorini face {f:?} on the left half"
        );
    }
    let (refined, disc) = run(0.01);
    assert_eq!(
        refined,
        [false, true, true, true, false, false, false, false],
        "α = 0.01: the three largest η, on the left, are refined"
    );
    // The Signorini faces were refined: their children inherited the model.
    assert!(disc.models.accurate_faces().any(|f| f.level == 1));
}

/// Full-tier rules (ignored by default, run by `full_tier`): every row's dofs within 10 % of
/// the printed (IV.34: rows 0–6; its printed rows 7–9 grow by ×2.1 and ×2.8 per cycle), the
/// balance claim (last row: model error ≤ the total estimate), IV.30's estimates within 15 %
/// in every row. The convergence rule and the spread of the interior estimate are reported in
/// docs/results.md and the notes, not asserted: they hold for IV.30 and IV.31 only (module docs of
/// `study::model_contact`).
pub fn full_tier_rules(t: &str, r: &RunResult) {
    let thesis = ThesisTable::of(&spec(t));
    assert_eq!(r.rows.len(), 10, "{t}");
    let rows = if t == "IV.34" { 7 } else { 10 };
    assert_dofs_within_10_percent(t, &r.rows[..rows], &thesis);
    let last = r.rows.len() - 1;
    assert!(
        value(r, last, "model_error") <= value(r, last, "estimate"),
        "{t}: last model error {} above the estimate {}",
        value(r, last, "model_error"),
        value(r, last, "estimate")
    );
    if t == "IV.30" {
        for row in &r.rows {
            let c = row.cycle;
            for column in ["est_z_boundary", "est_interior"] {
                let (ours, printed) = (value(r, c, column), thesis.value(c, column).unwrap());
                assert!(
                    rel(ours, printed).abs() <= 0.15,
                    "IV.30 cycle {c}: {column} {ours} vs printed {printed}"
                );
            }
        }
        crate::common::assert_convergence(t, r);
    }
}

/// A body moved rigidly by d = 0.37 upwards with its obstacles (the shapes raised by d) is the
/// same contact problem: the coarse grid of the moved body (`Mesh::with_coarse_vertices`, the
/// domain of a load step of §IV.2.4.7) gives the same displacement, the same active sets and
/// the same estimates and model errors as the Chapter IV grid, for z- and Signorini faces
/// (every third face Signorini) on the periodic (IV.31) and the jump (IV.33) scenes. This checks
/// that the z-gap, the estimator's face geometry and the model error use the actual face
/// positions. One term is not invariant, by its reading (`estimators::contact` docs): the gap
/// term on z-faces next to a Signorini vertex.
#[test]
fn a_raised_body_with_raised_obstacles_is_the_same_problem() {
    use tribo::experiment::{ObstacleShape, Problem as ProblemSpec};
    use tribo::study::model_contact::ModelAdaptiveContact;
    use tribo::study::{PhaseClock, Problem};
    let d = 0.37;
    for t in ["IV.31", "IV.33"] {
        let e = spec(t);
        let ProblemSpec::Contact {
            elasticity,
            contact,
        } = &e.problem
        else {
            panic!("{t} is a contact table")
        };
        let mut raised = contact.clone();
        for o in &mut raised.obstacles {
            o.shape = match o.shape {
                ObstacleShape::Periodic {
                    offset,
                    amplitude,
                    periods,
                    period,
                    phase,
                } => ObstacleShape::Periodic {
                    offset: offset + d,
                    amplitude,
                    periods,
                    period,
                    phase,
                },
                ObstacleShape::Jump {
                    base,
                    height,
                    at,
                    s,
                } => ObstacleShape::Jump {
                    base: base + d,
                    height,
                    at,
                    s,
                },
                ref other => panic!("{t}: no raised version of {other:?}"),
            };
        }
        let flat = Discretisation::initial(&e.scene).unwrap();
        let vertices: Vec<[f64; 2]> = (0..=2)
            .flat_map(|j| (0..=64).map(move |i| [-16.0 + 0.5 * i as f64, 0.5 * j as f64 + d]))
            .collect();
        let moved = Discretisation::of_mesh(Mesh::with_coarse_vertices(64, 2, vertices).unwrap());
        let run = |data: &tribo::experiment::ContactData, disc: &mut Discretisation| {
            let mut problem = ModelAdaptiveContact::with_grid(elasticity, data);
            // Every third contact face Signorini.
            let sides: BTreeSet<Side> = data.obstacles.iter().map(|o| o.side).collect();
            disc.models =
                Models::of_faces(boundary_faces(&disc.mesh, &sides).into_iter().step_by(3));
            let mut system = problem.setup(disc);
            problem.assemble(disc, &mut system).unwrap();
            let solution = problem
                .solve(disc, &mut system, &PhaseClock::default())
                .unwrap();
            let dofs = system.into_dofs();
            let estimate = problem.estimate(disc, &dofs, &solution).unwrap();
            let active = problem.state.as_ref().unwrap().solution.active.clone();
            (solution.u, active, estimate)
        };
        let (mut flat, mut moved) = (flat, moved);
        let (u0, active0, est0) = run(contact, &mut flat);
        let (u1, active1, est1) = run(&raised, &mut moved);
        assert_eq!(active0, active1, "{t}: active sets");
        let scale = u0.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let diff = u0
            .iter()
            .zip(&u1)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(
            diff <= 1e-9 * scale,
            "{t}: displacements differ by {diff:e}"
        );
        for ((name, a), (_, b)) in est0.columns.iter().zip(&est1.columns) {
            if let (Some(a), Some(b)) = (a.as_f64(), b.as_f64()) {
                // The gap term η_{−C} of the calibrated Signorini-code reading interpolates
                // b = g + n·x linearly, which depends on the origin where the nodal normals
                // jump (z-faces next to a Signorini vertex): measured 2e-6 (IV.31) and 1e-5
                // (IV.33) relative in est_z_boundary; every other column agrees to 1e-11.
                let tolerance = match name.as_str() {
                    "est_z_boundary" | "estimate" => 1e-4,
                    _ => 1e-9,
                };
                assert!(
                    (a - b).abs() <= tolerance * a.abs().max(1e-12),
                    "{t}: {name} {a} vs {b}"
                );
            }
        }
        for ((f, a), (g, b)) in est0.models.iter().zip(&est1.models) {
            assert_eq!(f, g);
            assert!(
                (a - b).abs() <= 1e-8 * a.abs().max(1e-10),
                "{t}: ε^m of {f:?}: {a} vs {b}"
            );
        }
    }
}
