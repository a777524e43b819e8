//! The mesh at its limits, through the study: coarse grids of any shape (the integer positions of
//! a 300 × 2 strip pass 2³² units) and refinement down to the deepest level
//! ([`tribo::mesh::MAX_LEVEL`]), which ends a run with an error naming table and cycle — never a
//! panic and never a wrong mesh.

use std::fs;

use tribo::experiment::{self, Experiment, Plan, Problem, Rectangle};
use tribo::mesh::{MeshError, Side};
use tribo::results::RunResult;
use tribo::study::{self, StudyError, Tier};

use crate::cli::temp_dir;
use crate::common::spec;

/// Table IV.1 (μ = λ = 1, a constant volume load across the strip [−16, 16] × [0, 1], both ends
/// clamped) on a `coarse` grid refined `refinements` times, three cycles; `turned`: the same
/// problem on [0, 1] × [−16, 16], clamped at bottom and top, the load along x₁. Without
/// coarsening: level-0 cells are never coarsened, so a grid and its coarser half refined once
/// make different meshes as soon as a coarsening flag is honoured in one and not the other.
fn strip(coarse: [usize; 2], refinements: usize, turned: bool) -> Experiment {
    let mut e = spec("IV.1");
    let (long, short) = ([-16.0, 16.0], [0.0, 1.0]);
    let (along, across) = (vec![-13.13, -3.77, 0.02, 6.49, 15.91], vec![0.2, 0.65]);
    e.scene.coarse_cells = coarse;
    e.scene.global_refinements = refinements;
    e.study.quick_rows = 3;
    let Plan::GridAdaptive { grid, .. } = &mut e.study.plan else {
        panic!("IV.1 is grid-adaptive");
    };
    grid.coarsen = 0.0;
    let Problem::Elasticity(data) = &mut e.problem else {
        panic!("IV.1 is an elasticity table");
    };
    let load = data.volume_load.as_mut().expect("IV.1 has a volume load");
    assert_eq!(e.scene.domain, Rectangle { x: long, y: short });
    assert_eq!(data.dirichlet, [Side::Left, Side::Right]);
    assert_eq!(load.direction, [0.0, 1.0]);
    if turned {
        e.scene.domain = Rectangle { x: short, y: long };
        data.dirichlet = vec![Side::Bottom, Side::Top];
        load.direction = [1.0, 0.0];
        (e.probes.x, e.probes.y) = (across, along);
    } else {
        (e.probes.x, e.probes.y) = (along, across);
    }
    e
}

fn run(e: &Experiment) -> RunResult {
    study::run(e, Tier::Quick, &|_, _, _| {}).unwrap_or_else(|err| panic!("{err}"))
}

/// The same mesh sizes and dofs in every cycle, and estimates and probe values (s₁, s₂ at ten
/// points of the last cycle) equal up to `tolerance` relative to the largest value.
fn assert_same_run(a: &RunResult, b: &RunResult, tolerance: f64, what: &str) {
    assert_eq!(a.rows.len(), 3, "{what}");
    assert_eq!(a.rows.len(), b.rows.len(), "{what}");
    for (ra, rb) in a.rows.iter().zip(&b.rows) {
        let cycle = ra.cycle;
        let cells = ra.active_cells();
        assert_eq!(cells, rb.active_cells(), "{what}, cycle {cycle}");
        assert_eq!(ra.dofs(), rb.dofs(), "{what}, cycle {cycle}");
        let (ea, eb) = (ra.estimate().unwrap(), rb.estimate().unwrap());
        assert!(
            (ea - eb).abs() <= tolerance * ea.abs(),
            "{what}, cycle {cycle}: estimate {ea:e} against {eb:e}"
        );
    }
    assert_eq!(a.probes.len(), 20, "{what}");
    assert_eq!(a.probes.len(), b.probes.len(), "{what}");
    let scale = a.probes.iter().map(|p| p.value.abs()).fold(0.0, f64::max);
    assert!(scale > 0.0, "{what}: the strip does not move");
    for (pa, pb) in a.probes.iter().zip(&b.probes) {
        assert_eq!((pa.x, pa.y, &pa.component), (pb.x, pb.y, &pb.component));
        assert!(
            (pa.value - pb.value).abs() <= tolerance * scale,
            "{what}: {} at ({}, {}) is {:e} against {:e}",
            pa.component,
            pa.x,
            pa.y,
            pa.value,
            pb.value
        );
    }
}

/// A 300 × 2 coarse grid (integer positions up to 300 · 2²⁴ > 2³²: it panicked in
/// `Mesh::new`; 129–255 cells panicked in the dof numbering once a cell was refined) is the
/// 150 × 1 grid refined once, in every cycle of the adaptive loop, and so is the strip turned
/// on its side, 2 × 300 against 1 × 150.
///
/// 300 × 2 lists its cells row by row, 150 × 1 refined once four children per coarse cell: the
/// sums of the assembly run in another order, and the clamped 32 : 1 beam amplifies that
/// rounding to 2.4e-12 of the estimate (1.7e-12 of the largest displacement). Turned, both
/// grids list the cells in the same order (two per row), the integer positions differ by a factor
/// of two only and the physical positions are the same: every number is bitwise equal.
#[test]
fn strips_past_256_coarse_cells_equal_their_once_refined_halves() {
    let long = run(&strip([300, 2], 0, false));
    let half = run(&strip([150, 1], 1, false));
    assert_eq!(long.rows[0].dofs(), Some(2 * 301 * 3));
    assert!(long.rows[2].active_cells() > long.rows[1].active_cells());
    assert_same_run(&long, &half, 1e-11, "300 × 2 against 150 × 1 refined once");
    let turned = run(&strip([2, 300], 0, true));
    let turned_half = run(&strip([1, 150], 1, true));
    assert_same_run(
        &turned,
        &turned_half,
        0.0,
        "2 × 300 against 1 × 150 refined once",
    );
}

/// The coarse grids that panicked — 129 and 255 cells wide in the dof numbering once
/// refinement makes hanging vertices at the far end, 256 in `Mesh::new` — run.
#[test]
fn coarse_grids_past_128_cells_in_one_direction_run() {
    for (coarse, turned) in [
        ([129, 2], false),
        ([255, 2], false),
        ([256, 2], false),
        ([2, 256], true),
    ] {
        let r = run(&strip(coarse, 0, turned));
        let vertices = (coarse[0] + 1) * (coarse[1] + 1);
        assert_eq!(r.rows[0].dofs(), Some(2 * vertices), "{coarse:?}");
        assert!(
            r.rows[2].active_cells() > r.rows[1].active_cells(),
            "{coarse:?}"
        );
    }
}

/// A feature finer than the deepest level. The bottom obstacle lifts the body by
/// 0.01 everywhere but in the last 1e-9 before the clamped corner x₁ = 1, where it drops to 0 —
/// feasible (the obstacle is 0 where the clamp holds s = 0), but 1e-9 is below the 2⁻²⁶ ≈ 1.5e-8
/// of a level-24 cell of this 8 × 4 grid. On every mesh the corner vertex is held at 0 while the
/// next one is pushed to 0.01, a jump across one cell, so the indicator of the corner cell does not
/// decrease and every cycle refines it once more (four cells of 32 are marked, 4 %, so the run
/// stays small: ~200 cells at cycle 24). The adaptation after cycle 24 would refine a cell of level
/// 24; it must end the run with an error naming the table, the cycle and the mesh's 24 levels, not
/// go on with wrapped integer positions and fail later with "vertex … lies outside the previous
/// mesh". (The earlier form of this scene clamped both ends and raised the obstacle at the corner;
/// that contact problem has no solution and is now refused before the first solve.)
#[test]
fn refining_past_the_deepest_level_is_a_study_error_naming_table_and_cycle() {
    const SHARP_JUMP: &str = r#"table = "IV.9"
section = "IV.2.1.4"
title = "A body lifted by an obstacle that drops 1e-9 before the clamped corner"

[scene]
name = "jump-obstacle-pressed-into-clamped-box"
domain = { x = [-1.0, 1.0], y = [0.0, 1.0] }
coarse_cells = [8, 4]
effects = ["elasticity", "contact"]

[scene.elasticity]
mu = 1.0
lambda = 1.0
dirichlet = ["right"]
volume_load = { direction = [0.0, 1.0], profile = { kind = "constant", amplitude = -0.1 } }

[scene.contact]
model = "z"
estimator = "z-code"
obstacles = [
  { side = "bottom", shape = { kind = "jump", base = 0.01, height = -0.01, at = 0.999999999, s = 1e-12 } },
]

[study]
kind = "grid-adaptive"
rows = 30
quick_rows = 30
refine_fraction = 0.04
coarsen_fraction = 0.0
convergence_window = [1, 2]

[thesis]
columns = ["cycle", "dofs"]
rows = [[0, 90]]
"#;
    let dir = temp_dir("deepest-level");
    let path = dir.join("IV.9.toml");
    fs::write(&path, SHARP_JUMP).unwrap();
    let e = experiment::load(&path).unwrap_or_else(|err| panic!("{err}"));
    let err = match study::run(&e, Tier::Quick, &|_, _, _| {}) {
        Ok(r) => panic!("the run ended without an error: {:?}", r.rows.last()),
        Err(err) => err,
    };
    fs::remove_dir_all(&dir).ok();
    let message = err.to_string();
    assert_eq!((err.table.as_str(), err.cycle), ("IV.9", 24), "{message}");
    assert!(
        message.starts_with("table IV.9, cycle 24: cannot refine the mesh after this cycle: "),
        "{message}"
    );
    assert!(
        matches!(
            err.cause.kind(),
            StudyError::Mesh(MeshError::PastDeepestLevel { .. })
        ),
        "{message}"
    );
    assert!(!message.contains("outside the previous mesh"), "{message}");
}

/// Table IV.18's 64×2 strip with `refinements` at its contact side.
fn side_refined(refinements: usize) -> Experiment {
    let mut e = spec("IV.18");
    assert_eq!(e.scene.side_refinements, 3);
    e.scene.side_refinements = refinements;
    e
}

/// The memory budget's prediction for a strip refined at one side grows with its cells, as the
/// fill of its Cholesky factor does (26 nonzeros per unknown with 8 and with 12 refinements;
/// the ordering's test in `linalg::direct`): 1472 cells with 3 refinements need some MB, 12
/// refinements (786 368 cells) 10 to 25 times what 8 (49 088) need — not the 256 times of a
/// factor filling in as n². The largest is refused by a 4 GiB budget before its first solve,
/// naming table, cycle, the size and the field that makes it.
#[test]
fn strips_refined_at_one_side_are_predicted_with_their_cells() {
    const GIB: f64 = 1024.0 * 1024.0 * 1024.0;
    let peak =
        |e: &Experiment| study::Budget::predicted_peak(e, study::Schedule::of(e, Tier::Quick));
    let shipped = peak(&side_refined(3));
    assert!(shipped > 5e6 && shipped < 50e6, "{shipped:e}");
    let eight = peak(&side_refined(8));
    let largest = side_refined(12);
    let ratio = peak(&largest) / eight;
    assert!(ratio > 10.0 && ratio < 25.0, "{ratio}: {eight:e} with 8");
    assert!(peak(&largest) > 4.0 * GIB, "{:e}", peak(&largest));

    let budget = study::Budget { bytes: 4.0 * GIB };
    let error = match study::run_within(&largest, Tier::Quick, budget, &|_, _, _| {}) {
        Ok(_) => panic!("12 contact refinements fit 4 GiB"),
        Err(error) => error,
    };
    assert_eq!((error.table.as_str(), error.cycle), ("IV.18", 0), "{error}");
    assert!(
        matches!(error.cause.kind(), StudyError::OverBudget(_)),
        "{error}"
    );
    let message = error.to_string();
    for part in ["table IV.18, cycle 0", "GiB", "scene.contact_refinements"] {
        assert!(message.contains(part), "no `{part}` in: {message}");
    }
}
