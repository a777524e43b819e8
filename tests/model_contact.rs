//! Tables IV.18–IV.29: model-adaptive contact on a fixed mesh (§IV.2.3), run in full (ten
//! cycles of about 0.05 s each): the printed meshes and face counts, the flat obstacle's exact
//! zero, the marking of Algorithms III.2/III.3 on the real indicators, the mixed solve's
//! constraints, and what the §3.4 reading of the indicator does and does not reproduce.

use std::collections::BTreeSet;

use crate::common::{quick, spec};
use tribo::adaptivity::model::{sorted_error, Partition};
use tribo::experiment::Problem as ProblemSpec;
use tribo::models::contact::ContactModel;
use tribo::results::RunResult;
use tribo::study::model_contact::ModelAdaptiveContact;
use tribo::study::{Discretisation, Models, PhaseClock, Problem};
use tribo::thesis::ThesisTable;

/// The six scenes, each as (III.2 table, III.3 table).
const PAIRS: [(&str, &str); 6] = [
    ("IV.18", "IV.19"),
    ("IV.20", "IV.21"),
    ("IV.22", "IV.23"),
    ("IV.24", "IV.25"),
    ("IV.26", "IV.27"),
    ("IV.28", "IV.29"),
];

pub const TABLES: [&str; 12] = [
    "IV.18", "IV.19", "IV.20", "IV.21", "IV.22", "IV.23", "IV.24", "IV.25", "IV.26", "IV.27",
    "IV.28", "IV.29",
];

fn count(r: &RunResult, cycle: usize, column: &str) -> i64 {
    r.rows[cycle]
        .count_of(column)
        .unwrap_or_else(|| panic!("{}: no count {column} in cycle {cycle}", r.table))
}

fn model_errors(r: &RunResult) -> Vec<f64> {
    r.rows
        .iter()
        .map(|row| row.value("model_error").expect("model_error"))
        .collect()
}

fn problem(t: &str) -> ModelAdaptiveContact {
    match &spec(t).problem {
        ProblemSpec::Contact {
            elasticity,
            contact,
        } => ModelAdaptiveContact::new(elasticity, contact),
        other => panic!("{t} is not a contact table: {other:?}"),
    }
}

#[test]
fn golden_snapshots() {
    crate::common::assert_golden(&TABLES);
}

/// Every row has the printed cells and dofs (the fixed meshes of §IV.2.3), all ten rows run,
/// and coarse + accurate faces = 512.
#[test]
fn printed_meshes_and_all_faces() {
    for t in TABLES {
        let r = quick(t);
        let thesis = ThesisTable::of(&spec(t));
        assert_eq!(r.rows.len(), 10, "{t}");
        for row in &r.rows {
            for column in ["active_cells", "dofs"] {
                assert_eq!(
                    row.value(column),
                    thesis.value(row.cycle, column),
                    "{t} cycle {}: {column}",
                    row.cycle
                );
            }
            let faces =
                count(&r, row.cycle, "coarse_faces") + count(&r, row.cycle, "accurate_faces");
            assert_eq!(faces, 512, "{t} cycle {}", row.cycle);
        }
    }
}

/// Algorithm III.2 moves ⌊p_r|𝕋_c|⌋ faces per cycle, also when ε^m = 0: exactly the printed
/// sequence in all six tables.
#[test]
fn fixed_fraction_face_counts_are_the_printed_ones() {
    let printed = [512, 502, 492, 483, 474, 465, 456, 447, 439, 431];
    for (t, _) in PAIRS {
        let r = quick(t);
        let coarse: Vec<i64> = (0..10).map(|c| count(&r, c, "coarse_faces")).collect();
        assert_eq!(coarse, printed, "{t}");
    }
}

/// A flat obstacle: (S) ⇔ (Z), so the model error is exactly 0 in every row, and III.3 never
/// moves a face (Tables IV.18, IV.19).
#[test]
fn flat_obstacle_has_no_model_error() {
    for t in ["IV.18", "IV.19"] {
        let r = quick(t);
        assert!(model_errors(&r).iter().all(|&e| e == 0.0), "{t}");
    }
    let r = quick("IV.19");
    for c in 0..10 {
        assert_eq!(count(&r, c, "coarse_faces"), 512);
        assert_eq!(count(&r, c, "partition_repeat"), i64::from(c > 0));
    }
}

/// The flat obstacle gives ε_P = 0 for any partition: exactly on every face between z-vertices,
/// and on the faces with a Signorini vertex up to the one-step linearisation — a Signorini vertex that slides along the
/// tilted half-plane n·(s − s₀) ≤ g sinks below the line by a depth d, where (S) and (Z) both
/// fail and ε_P = |d|·(1/cos θ − 1), θ the tilt of n_s (measured: 2.5e-16 at most, on 4 of the 512 faces with every third one Signorini).
#[test]
fn flat_obstacle_gives_zero_for_any_partition() {
    let e = spec("IV.18");
    let mut model = problem("IV.18");
    let mut disc = Discretisation::initial(&e.scene).unwrap();
    let (dofs, u) = solve(&mut model, &disc);
    let faces = model.face_errors(&dofs, &u).unwrap();
    assert!(faces.iter().all(|&(_, e)| e == 0.0), "all-z partition");
    // Every third face Signorini.
    disc.models = Models::of_faces(faces.iter().step_by(3).map(|(f, _)| *f));
    let (dofs, u) = solve(&mut model, &disc);
    let errors = model.face_errors(&dofs, &u).unwrap();
    assert_eq!(errors.len(), 512);
    let signorini_vertices: BTreeSet<u64> = disc
        .models
        .accurate_faces()
        .flat_map(|f| [f.start, f.end()])
        .collect();
    for (f, e) in errors {
        if signorini_vertices.contains(&f.start) || signorini_vertices.contains(&f.end()) {
            assert!(e <= 1e-14, "face {f:?} with a Signorini vertex: {e:e}");
        } else {
            assert_eq!(e, 0.0, "z-face {f:?} between z-vertices");
        }
    }
}

fn solve(model: &mut ModelAdaptiveContact, disc: &Discretisation) -> (tribo::fe::DofMap, Vec<f64>) {
    let mut system = model.setup(disc);
    model
        .assemble(disc, &mut system)
        .unwrap_or_else(|e| panic!("{e}"));
    let sol = model
        .solve(disc, &mut system, &PhaseClock::default())
        .unwrap_or_else(|e| panic!("{e}"));
    (system.dofs, sol.u)
}

/// The mixed solve holds each model's constraint to 1e-10 with complementarity, and a vertex
/// between a z-face and a Signorini face carries the Signorini constraint. Partitions: the
/// faces with x₁ ∈ [−8, 8] Signorini, on the periodic, jump and saw scenes.
#[test]
fn mixed_solves_hold_both_constraints() {
    for t in ["IV.20", "IV.24", "IV.26", "IV.28"] {
        let e = spec(t);
        let mut model = problem(t);
        let mut disc = Discretisation::initial(&e.scene).unwrap();
        let (dofs, u) = solve(&mut model, &disc);
        let faces = model.face_errors(&dofs, &u).unwrap();
        let units = 1u64 << tribo::mesh::MAX_LEVEL;
        let (lo, hi) = (16 * units, 48 * units);
        disc.models = Models::of_faces(
            faces
                .iter()
                .map(|(f, _)| *f)
                .filter(|f| lo <= f.start && f.end() <= hi),
        );
        let (dofs, u) = solve(&mut model, &disc);
        let state = model.state.as_ref().unwrap();
        crate::contact::check_state(t, &dofs, &u, state);
        let x_of = |c: &tribo::models::contact::ContactConstraint| {
            dofs.vertices.coords[c.vertex as usize][0]
        };
        let signorini: Vec<f64> = state
            .constraints
            .iter()
            .filter(|c| c.model == ContactModel::Signorini)
            .map(x_of)
            .collect();
        assert!(
            signorini.contains(&-8.0) && signorini.contains(&8.0),
            "{t}: the vertices at x₁ = ±8 between z- and Signorini faces are Signorini"
        );
        assert!(
            signorini.iter().all(|&x| (-8.0..=8.0).contains(&x)),
            "{t}: Signorini constraints only on the Signorini faces"
        );
    }
}

/// A scene's two tables share cycle 0 (the all-z solve), and every non-flat scene has a model
/// error there.
#[test]
fn a_scenes_tables_share_cycle_zero() {
    for (a, b) in PAIRS {
        let (ra, rb) = (quick(a), quick(b));
        assert_eq!(ra.rows[0].columns, rb.rows[0].columns, "{a} and {b}");
        if a != "IV.18" {
            assert!(model_errors(&ra)[0] > 0.0, "{a}");
        }
    }
}

/// Marking on the real indicators: III.3's cycle 1 keeps 500–511 coarse faces, III.2 ends at
/// ≤ 10⁻² of its cycle-0 model error, III.3 reaches ≤ 5·10⁻² of it.
#[test]
fn model_marking_on_the_real_indicators() {
    for (fixed, sorted) in PAIRS.into_iter().skip(1) {
        let r = quick(sorted);
        let c1 = count(&r, 1, "coarse_faces");
        assert!(
            (500..=511).contains(&c1),
            "{sorted}: cycle 1 has {c1} coarse faces"
        );
        let e = model_errors(&quick(fixed));
        assert!(e[9] <= 1e-2 * e[0], "{fixed}: {} vs cycle 0 {}", e[9], e[0]);
        let e = model_errors(&r);
        let best = e.iter().copied().fold(f64::INFINITY, f64::min);
        assert!(
            best <= 5e-2 * e[0],
            "{sorted}: best {best} vs cycle 0 {}",
            e[0]
        );
    }
}

/// III.3 with the §3.4 indicator flips between two partitions on the saw: 454/58 ↔ 464/48,
/// as an independent computation found; the column `partition_repeat` records the period 2.
#[test]
fn sorted_error_flips_on_the_saw() {
    let r = quick("IV.29");
    let split: Vec<(i64, i64)> = (6..10)
        .map(|c| (count(&r, c, "coarse_faces"), count(&r, c, "accurate_faces")))
        .collect();
    assert_eq!(split, [(464, 48), (454, 58), (464, 48), (454, 58)]);
    for c in 6..10 {
        assert_eq!(count(&r, c, "partition_repeat"), 2, "cycle {c}");
    }
}

/// After a III.3 step on real indicators (the saw's cycle 0 and the periodic scene's), every
/// coarse face has an indicator at most every accurate face's.
#[test]
fn sorted_error_leaves_coarse_below_accurate() {
    for t in ["IV.21", "IV.29"] {
        let e = spec(t);
        let mut model = problem(t);
        let disc = Discretisation::initial(&e.scene).unwrap();
        let (dofs, u) = solve(&mut model, &disc);
        let eps: Vec<f64> = model
            .face_errors(&dofs, &u)
            .unwrap()
            .iter()
            .map(|&(_, e)| e)
            .collect();
        let mut p = Partition::coarse(eps.len());
        for _ in 0..3 {
            sorted_error(&mut p, &eps, 0.02, 0.01, 1e-7).unwrap();
            let max_c = (0..eps.len())
                .filter(|&i| !p.is_accurate(i))
                .map(|i| eps[i])
                .fold(0.0, f64::max);
            let min_a = (0..eps.len())
                .filter(|&i| p.is_accurate(i))
                .map(|i| eps[i])
                .fold(f64::INFINITY, f64::min);
            assert!(max_c <= min_a, "{t}: {max_c} > {min_a}");
        }
    }
}

/// The hard cases: the jump scenes with Signorini faces on the jumps, and the saw, finish every
/// cycle with finite values within the active-set limit; warm-started z-solves need one
/// iteration after cycle 0 (the cold one of IV.24 needs 44).
#[test]
fn jump_scenes_stay_finite_and_converge() {
    for t in ["IV.24", "IV.25", "IV.26", "IV.27", "IV.28", "IV.29"] {
        let r = quick(t);
        for row in &r.rows {
            for column in ["z_iterations", "mixed_iterations"] {
                let n = row.count_of(column).unwrap();
                assert!(n <= 50, "{t} cycle {}: {column} {n}", row.cycle);
            }
            if row.cycle > 0 {
                assert_eq!(
                    row.count_of("z_iterations"),
                    Some(1),
                    "{t} cycle {}",
                    row.cycle
                );
            }
        }
    }
    assert_eq!(quick("IV.24").rows[0].count_of("z_iterations"), Some(44));
    let s = quick("IV.25");
    let accurate: BTreeSet<i64> = (1..10).map(|c| count(&s, c, "accurate_faces")).collect();
    assert!(
        accurate.iter().all(|&n| n > 0),
        "IV.25 keeps Signorini faces on the jump"
    );
}

/// The cost-of-accuracy study of the saw (IV.29's scene): the all-Signorini variant is its own
/// reference (distance exactly 0), the z-variant penetrates deeper and is farther from it, and
/// the III.2/III.3 variants run the partitions of Tables IV.28 and IV.29.
#[test]
fn cost_of_accuracy_on_the_saw() {
    use tribo::results::claim_of_section_iv_2_3;
    use tribo::study::cost::{accuracy_costs, applies};
    assert!(applies(&spec("IV.29")));
    assert!(
        !applies(&spec("IV.28")),
        "one study per scene, on its III.3 table"
    );
    let costs = accuracy_costs(&spec("IV.29")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(costs.len(), 40);
    let last = |variant: &str| {
        costs
            .iter()
            .rfind(|c| c.variant == variant)
            .unwrap()
            .clone()
    };
    let (z, signorini) = (last("z"), last("signorini"));
    assert_eq!(signorini.energy_distance, 0.0);
    assert_eq!(signorini.accurate_faces, 512);
    assert!(
        z.penetration > 2.0 * signorini.penetration,
        "{z:?} {signorini:?}"
    );
    assert!(z.energy_distance > 0.1, "{z:?}");
    for (variant, table) in [("III.2", "IV.28"), ("III.3", "IV.29")] {
        let run = quick(table);
        let faces: Vec<usize> = costs
            .iter()
            .filter(|c| c.variant == variant)
            .map(|c| c.accurate_faces)
            .collect();
        let printed: Vec<usize> = (0..10)
            .map(|c| count(&run, c, "accurate_faces") as usize)
            .collect();
        assert_eq!(faces, printed, "{variant} as in {table}");
    }
    // The claim closing §IV.2.3 fails on the saw: III.3 flips between two partitions (454/58 ↔
    // 464/48) and is below III.2's error and faces in 4 of the 9 cycles each (measured); the
    // thesis's own rows fail its face part here too (89 against 81 Signorini faces).
    assert_eq!(claim_of_section_iv_2_3(&costs), (4, 4, 9));
}
