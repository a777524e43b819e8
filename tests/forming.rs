//! The U-O (J) forming of §IV.2.4.7 (Fig. IV.54, `experiments/fig-IV.54.toml`): load steps of
//! model and grid adaptivity on a moving body. The quick tier runs 3 steps; the full tier
//! (ignored, `full_tier`) all 25.

use crate::common::{quick, spec};
use tribo::experiment::{ContactData, ObstacleShape, Plan, Problem, Rise};
use tribo::mesh::MeshError;
use tribo::results::RunResult;
use tribo::study::{Discretisation, Schedule, Solve, StudyError};

pub const FORMING: &str = "fig-IV.54";

#[test]
fn golden_snapshot() {
    crate::common::assert_golden(&[FORMING]);
}

/// After every step the tip (the material point (16, 0), the lower right corner of the sheet)
/// rests on the die's plateau c_j = 10j/24: tip_y ∈ [c_j − 0.02, c_j + 0.3]; every step draws
/// its frame, and no constraint is violated beyond rounding at the vertices.
pub fn assert_forming_rules(r: &RunResult) {
    assert_eq!(r.deformed.len(), r.rows.len(), "one frame per step");
    for (j, row) in r.rows.iter().enumerate() {
        assert_eq!(row.cycle, j);
        let c = 10.0 * j as f64 / 24.0;
        let tip_y = row.value("tip_y").unwrap();
        assert!(
            (c - 0.02..=c + 0.3).contains(&tip_y),
            "step {j}: tip_y = {tip_y}, the die's plateau at {c}"
        );
        let tip_x = row.value("tip_x").unwrap();
        assert!(tip_x > 0.0 && tip_x < 16.01, "step {j}: tip_x = {tip_x}");
        assert_eq!(
            row.count_of("s_faces"),
            Some(r.deformed[j].accurate_faces.len() as i64),
            "step {j}: the frame draws the Signorini faces"
        );
        assert_eq!(r.deformed[j].cycle, j);
    }
}

#[test]
fn the_tip_rests_on_the_die() {
    let r = quick(FORMING);
    assert_eq!(r.rows.len(), 3, "quick tier = steps 0–2");
    assert!(r.is_load_steps());
    assert_forming_rules(&r);
    // Step 0: no load and the die just touching: the body stays, nothing refines.
    let first = &r.rows[0];
    assert_eq!(first.value("tip_y"), Some(0.0));
    assert_eq!(first.value("tip_x"), Some(16.0));
    assert_eq!(first.active_cells(), Some(128));
    assert_eq!(first.count_of("z_faces"), Some(128));
    // Step 1: the die has risen by 10/24 and lifted the sheet, whose free end tilts up to the
    // punch's plateau 0.2 above it (the sheet is 1 thick): the largest tip of the range.
    let tip = r.rows[1].value("tip_y").unwrap();
    assert!(
        (tip - (10.0 / 24.0 + 0.2)).abs() < 1e-3,
        "step 1: tip_y = {tip}"
    );
}

/// The rising tools of step j: the die (rises = "whole") with its circle and plateau raised by
/// j·lift, the punch (rises = "plateau") with its plateau only.
#[test]
fn tools_rise_by_the_lift() {
    let e = spec(FORMING);
    let Problem::Contact { contact, .. } = &e.problem else {
        panic!("the forming is a contact problem")
    };
    let Plan::LoadSteps {
        lift_per_step: lift,
        ..
    } = e.study.plan
    else {
        panic!("fig-IV.54 is a load-step study");
    };
    assert_eq!(lift, 10.0 / 24.0);
    let arc = |c: &ContactData, i: usize| match c.obstacles[i].shape {
        ObstacleShape::Arc {
            center, plateau, ..
        } => (center, plateau),
        ref other => panic!("obstacle {i} is {other:?}"),
    };
    let raised = contact.raised(24.0 * lift);
    assert_eq!(contact.obstacles[0].rises, Some(Rise::Plateau));
    assert_eq!(contact.obstacles[1].rises, Some(Rise::Whole));
    // Punch: circle fixed, plateau 0.2 + 10 above the top face (1.2 + 10 absolute).
    assert_eq!(arc(&raised, 0).0, arc(contact, 0).0);
    assert!((arc(&raised, 0).1 - 10.2).abs() < 1e-12);
    // Die: circle and plateau 10 higher.
    assert!((arc(&raised, 1).0[1] - 10.0).abs() < 1e-12);
    assert!((arc(&raised, 1).1 - 10.0).abs() < 1e-12);
    // At j = 24 the circles are concentric (the punch's circle is given relative to the top
    // face y = 1).
    assert!((arc(&raised, 0).0[1] + 1.0 - arc(&raised, 1).0[1]).abs() < 1e-12);
}

/// A load-step schedule: `per_row` solves per step, the row made by the step's last cycle,
/// errors named by step and cycle.
#[test]
fn a_load_step_schedule_names_step_and_cycle() {
    let schedule = Schedule {
        unprinted: 0,
        printed: 3,
        per_row: 4,
    };
    let solves: Vec<Solve> = schedule.solves().collect();
    assert_eq!(solves.len(), 12);
    let rows: Vec<(usize, usize)> = solves
        .iter()
        .filter_map(|s| s.row.map(|r| (s.index, r)))
        .collect();
    assert_eq!(rows, [(3, 0), (7, 1), (11, 2)]);
    assert_eq!(solves[6].step, Some((1, 2)));
    assert!(solves[11].last && !solves[10].last);
    let error = solves[6].error(FORMING, "the solve failed".into());
    assert_eq!(
        error.to_string(),
        "table fig-IV.54, load step 1, cycle 2: the solve failed"
    );
    // Any other study: one solve per row, named by its cycle.
    let plain = Schedule {
        unprinted: 0,
        printed: 2,
        per_row: 1,
    };
    let error = plain.solves().nth(1).unwrap().error("IV.30", "x".into());
    assert_eq!(error.to_string(), "table IV.30, cycle 1: x");
}

/// The next step's body is the coarse grid moved by the displacement; a motion that folds a
/// coarse cell is an error that names the step and the cell.
#[test]
fn a_folded_body_is_an_error_naming_step_and_cell() {
    let scene = spec(FORMING).scene;
    let disc = Discretisation::initial(&scene).unwrap();
    let n = disc.mesh.coarse_vertex_keys().len();
    assert_eq!(n, 65 * 3);
    // A rigid lift by 0.5: every vertex 0.5 higher, the body unfolded.
    let next = disc.next_load_step(&scene, &vec![[0.0, 0.5]; n]).unwrap();
    assert_eq!(next.load_step, 1);
    assert!(next.mesh.is_moved());
    assert_eq!(
        next.mesh.point(next.mesh.coarse_vertex_keys()[0]),
        [-16.0, 0.5]
    );
    // The top vertex of coarse column 10 pushed down through its cell's bottom.
    let mut motion = vec![[0.0, 0.0]; n];
    motion[2 * 65 + 10] = [0.0, -1.5];
    let error = next.next_load_step(&scene, &motion).unwrap_err();
    assert!(
        error.to_string().starts_with(
            "the body moved by the displacement of load step 1 cannot start load step 2: "
        ),
        "{error}"
    );
    assert!(
        matches!(error.kind(), StudyError::Mesh(MeshError::FoldedCell { .. })),
        "{error}"
    );
    // Wrong length.
    assert!(disc.next_load_step(&scene, &[[0.0, 0.0]]).is_err());
}
