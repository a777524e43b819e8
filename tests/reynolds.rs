//! Tables IV.36–IV.49 (Reynolds, Theorem III.16) and IV.64–IV.69 (Reynolds with cavitation,
//! Theorem III.17) on the quick tier, plus further checks: analytic value of (IV.7),
//! constant solutions, sign-symmetric pairs, thesis agreement, `auto` cavitation, hard case.

use std::f64::consts::PI;

use crate::common::{assert_convergence, quick, rel, spec};
use tribo::experiment::{Cavitation, ReynoldsEstimator, ZoneResidual};
use tribo::fe::System;
use tribo::linalg::DirectSolver;
use tribo::mesh::Mesh;
use tribo::models::reynolds::{Form, Load, ReynoldsProblem};
use tribo::models::thin_film::EXAMPLES;
use tribo::results::columns::PREVIOUS_ESTIMATE;
use tribo::results::RunResult;
use tribo::study::reynolds::ReynoldsFilm;
use tribo::study::{self, run_study, Tier};
use tribo::thesis::ThesisTable;

/// The Reynolds data of an experiment, for changing a reading.
fn reynolds_mut(s: &mut tribo::experiment::Experiment) -> &mut tribo::experiment::ReynoldsData {
    s.problem.reynolds_mut().expect("a Reynolds table")
}

pub const TABLES: [&str; 20] = [
    "IV.36", "IV.37", "IV.38", "IV.39", "IV.40", "IV.41", "IV.42", "IV.43", "IV.44", "IV.45",
    "IV.46", "IV.47", "IV.48", "IV.49", "IV.64", "IV.65", "IV.66", "IV.67", "IV.68", "IV.69",
];
const CAVITATION: [&str; 6] = ["IV.64", "IV.65", "IV.66", "IV.67", "IV.68", "IV.69"];
/// Exact solution constant: the thesis refined on noise (IV.38) or printed 0.34 (IV.43).
const CONSTANT: [&str; 2] = ["IV.38", "IV.43"];
/// Copies of IV.44–IV.46 in the thesis (thesis.duplicate_of).
const DUPLICATES: [&str; 3] = ["IV.47", "IV.48", "IV.49"];
/// IV.64 (plain gap with cavitation): the cavitation zone is a plateau of equal indicators, and
/// tribo's stand-in for the thesis's rounding noise there (src/adaptivity.rs) is not correlated
/// between siblings as the thesis's was: row 1 of the full tier has 3.04 % more dofs (the thesis
/// coarsened 42 sibling groups of the zone in its first step, tribo none; experiment notes).
/// Checked against 4 % instead of 3 %.
const CAVITATION_MESH_DIFFERS: [&str; 1] = ["IV.64"];

#[test]
fn golden_snapshots() {
    crate::common::assert_golden(&TABLES);
}

/// u(½, ½) of −Δu = 1 on the unit square, u = 0 on the boundary (double sine series).
fn poisson_centre() -> f64 {
    let mut s = 0.0;
    for m in (1..400).step_by(2) {
        for n in (1..400).step_by(2) {
            let (mf, nf) = (m as f64, n as f64);
            let sign = if ((m + n) / 2 - 1) % 2 == 0 {
                1.0
            } else {
                -1.0
            };
            s += sign * 16.0 / (PI.powi(4) * mf * nf * (mf * mf + nf * nf));
        }
    }
    s
}

#[test]
fn plain_squeeze_matches_the_series_solution() {
    let u = poisson_centre();
    assert!((u - 0.0736713).abs() < 1e-6, "series: {u}");
    let exact = 200.0 + 12000.0 * u;
    let r = quick("IV.36");
    let p = r
        .probes
        .iter()
        .find(|p| p.x == 0.5 && p.y == 0.5)
        .expect("probe at the centre");
    assert!(
        rel(p.value, exact).abs() <= 5e-4,
        "ψ(½,½) = {} vs {exact}",
        p.value
    );
}

#[test]
fn constant_exact_solutions_are_reproduced_and_the_mesh_stays() {
    for t in CONSTANT {
        let r = quick(t);
        for p in &r.probes {
            assert!(rel(p.value, 200.0).abs() <= 1e-9, "{t}: ψ = {}", p.value);
        }
        for row in &r.rows {
            let estimate = row.estimate().unwrap();
            assert!(estimate < 1e-6, "{t}: estimate {estimate}");
            assert_eq!(row.active_cells(), Some(4096), "{t}: refined on noise");
        }
    }
}

#[test]
fn pairs_without_curvature_are_sign_symmetric() {
    for (a, b) in [("IV.36", "IV.37"), ("IV.39", "IV.40"), ("IV.41", "IV.42")] {
        let (ra, rb) = (quick(a), quick(b));
        assert_eq!(ra.rows.len(), rb.rows.len());
        for (x, y) in ra.rows.iter().zip(&rb.rows) {
            assert_eq!(
                (x.active_cells(), x.dofs()),
                (y.active_cells(), y.dofs()),
                "{a}/{b}"
            );
            assert!(
                rel(x.estimate().unwrap(), y.estimate().unwrap()).abs() <= 1e-9,
                "{a}/{b} cycle {}: {} vs {}",
                x.cycle,
                x.estimate().unwrap(),
                y.estimate().unwrap()
            );
        }
        let mut sign_change = false;
        for (p, q) in ra.probes.iter().zip(&rb.probes) {
            let (da, db) = (p.value - 200.0, q.value - 200.0);
            assert!(
                (da + db).abs() <= 1e-7 * da.abs().max(1.0),
                "{a}/{b}: {da} vs {db}"
            );
            sign_change |= da * db < 0.0;
        }
        assert!(sign_change, "{a}/{b}: ψ − 200 does not change sign");
    }
}

/// Tables compared row by row with the thesis (not the constant solutions, not the copies).
fn compared_tables() -> impl Iterator<Item = &'static str> {
    TABLES
        .into_iter()
        .filter(|t| !CONSTANT.contains(t) && !DUPLICATES.contains(t))
}

/// dofs within 3 % of the thesis in every row (4 % for [`CAVITATION_MESH_DIFFERS`]).
fn assert_dofs_follow_the_thesis(t: &str, r: &RunResult) {
    let bound = if CAVITATION_MESH_DIFFERS.contains(&t) {
        0.04
    } else {
        0.03
    };
    crate::common::assert_thesis_rows(t, r, bound, None);
}

/// The thesis prints the estimate of the previous mesh (column `estimate_previous_mesh`): the
/// ratio tribo/thesis of that column varies by at most 10 % along a table. For IV.41 and IV.42
/// the printed estimate is taken without the part IV.43 prints alone
/// ([`assert_additive_part_explains_the_drift`]; raw, the full tier drifts by 15 %).
fn assert_estimate_ratio_spread(t: &str, r: &RunResult) {
    let thesis = ThesisTable::of(&spec(t));
    let ratios: Vec<f64> = r
        .rows
        .iter()
        .map(|row| row.value(PREVIOUS_ESTIMATE).unwrap() / printed_estimate(&thesis, row.cycle))
        .collect();
    crate::common::assert_ratio_spread(t, r, &ratios, 0.10);
}

/// The printed estimate of row `cycle`, without the additive part where the table has one.
fn printed_estimate(thesis: &ThesisTable, cycle: usize) -> f64 {
    thesis
        .estimate_without_part(cycle)
        .unwrap_or_else(|| thesis.value(cycle, "estimate").unwrap())
}

#[test]
fn dofs_follow_the_thesis() {
    for t in compared_tables() {
        assert_dofs_follow_the_thesis(t, &quick(t));
    }
}

#[test]
fn estimate_ratio_to_the_thesis_is_constant_along_a_table() {
    for t in compared_tables() {
        assert_estimate_ratio_spread(t, &quick(t));
    }
}

/// The printed row 0 carries the estimate of the uniform 64×64 grid, which calibrates the
/// Reynolds estimator (src/estimators/reynolds.rs, thesis-code reading): tribo reproduces it to
/// 1e-4 without cavitation (the printed values have five digits) and to 5e-4 with it, IV.41 and
/// IV.42 once IV.43's constant is taken out. Theorem III.16 as stated gives more than twice the
/// printed value on the squeeze and wave gaps.
#[test]
fn row_zero_reproduces_the_printed_estimate() {
    let calibrated = [
        ("IV.36", 1e-4),
        ("IV.37", 1e-4),
        ("IV.39", 1e-4),
        ("IV.40", 1e-4),
        ("IV.41", 1e-4),
        ("IV.42", 1e-4),
        ("IV.44", 1e-4),
        ("IV.45", 1e-4),
        ("IV.64", 5e-4),
        ("IV.65", 5e-4),
    ];
    for (t, tol) in calibrated {
        let thesis = ThesisTable::of(&spec(t));
        let printed = printed_estimate(&thesis, 0);
        let row0 = quick(t).rows[0].value(PREVIOUS_ESTIMATE).unwrap();
        assert!(
            rel(row0, printed).abs() <= tol,
            "{t}: row-0 estimate {row0} against printed {printed}"
        );
    }
    for t in ["IV.36", "IV.39", "IV.44"] {
        let mut theorem = spec(t);
        reynolds_mut(&mut theorem).estimator = ReynoldsEstimator::Theorem;
        theorem.study.quick_rows = 1;
        let r = study::run(&theorem, Tier::Quick, &|_, _, _| {}).expect("runs");
        let row0 = r.rows[0].value(PREVIOUS_ESTIMATE).unwrap();
        let printed = ThesisTable::of(&theorem).value(0, "estimate").unwrap();
        assert!(
            row0 / printed > 2.0,
            "{t}: theorem as stated {row0} vs {printed}"
        );
    }
}

/// With R₃ in place of R₃c (`cavitation_source = "reynolds"`) the row-0 estimate of the wave gap
/// with upward velocity (IV.66) is the printed one to 1e-4 and that of the hill gap (IV.68) to
/// 2e-3; the printed γ₃c misses them by 2.8 % and 5.9 %. Evidence that the thesis's code solved
/// and estimated its cavitation runs with the source without cavitation (notes of IV.66).
#[test]
fn source_without_cavitation_reproduces_row_zero_of_the_curved_gaps() {
    for (t, tol) in [("IV.66", 1e-4), ("IV.68", 2e-3)] {
        let printed = ThesisTable::of(&spec(t)).value(0, "estimate").unwrap();
        let readings = study::alternative_readings(&spec(t));
        let mut alt = readings
            .into_iter()
            .find(|a| a.suffix == "reynolds")
            .expect("reading offered")
            .experiment;
        alt.study.quick_rows = 1;
        let r = study::run(&alt, Tier::Quick, &|_, _, _| {}).expect("runs");
        let row0 = r.rows[0].value(PREVIOUS_ESTIMATE).unwrap();
        assert!(
            rel(row0, printed).abs() <= tol,
            "{t}: row 0 {row0} against printed {printed}"
        );
        let as_printed = quick(t).rows[0].value(PREVIOUS_ESTIMATE).unwrap();
        assert!(
            rel(as_printed, printed) >= 0.02,
            "{t}: printed γ₃c gives {as_printed} against {printed}"
        );
    }
}

/// The alternative readings of the residual in the cavitation zone (`zone_residual`, notes of
/// IV.64) drop volume terms, so on the same 64×64 solve they give a smaller estimate: dropping
/// it on cells touching the zone drops more than on cells inside it.
#[test]
fn zone_residual_readings_drop_the_zone_volume_terms() {
    let row0 = |zone: ZoneResidual| {
        let mut s = spec("IV.64");
        reynolds_mut(&mut s).zone_residual = zone;
        s.study.quick_rows = 1;
        let r = study::run(&s, Tier::Quick, &|_, _, _| {}).expect("runs");
        r.rows[0].value(PREVIOUS_ESTIMATE).unwrap()
    };
    let (full, off_zone, off_touching) = (
        row0(ZoneResidual::Full),
        row0(ZoneResidual::OffZone),
        row0(ZoneResidual::OffTouching),
    );
    assert!(
        off_touching < off_zone && off_zone < 0.99 * full,
        "full {full}, off-zone {off_zone}, off-touching {off_touching}"
    );
}

/// IV.41 and IV.42 (linear gap, sliding) drift against the thesis because its estimate carries
/// the mesh-independent part that IV.43 prints alone: tribo/√(thesis² − IV.43²) stays within
/// 1 % of 1 (the full tier: 1.000–1.008), while tribo/thesis falls from 0.998 to 0.865. The
/// part in the experiment files is IV.43's printed estimate column.
fn assert_additive_part_explains_the_drift(t: &str, r: &RunResult) {
    let thesis = ThesisTable::of(&spec(t));
    let part = thesis.additive_part.as_ref().expect("additive_part");
    let printed_alone = spec(&part.table).thesis;
    let column = printed_alone.columns.iter().position(|c| c == "estimate");
    let alone: Vec<f64> = printed_alone
        .rows
        .iter()
        .map(|row| row[column.unwrap()])
        .collect();
    assert_eq!(
        part.estimate, alone,
        "{t}: additive_part = {}'s estimates",
        part.table
    );
    for row in &r.rows {
        let corrected = thesis.estimate_without_part(row.cycle).expect("printed");
        let q = row.value(PREVIOUS_ESTIMATE).unwrap() / corrected;
        assert!((q - 1.0).abs() <= 0.01, "{t} row {}: {q}", row.cycle);
    }
}

#[test]
fn linear_gap_sliding_estimates_are_the_thesis_without_its_constant_part() {
    for t in ["IV.41", "IV.42"] {
        assert_additive_part_explains_the_drift(t, &quick(t));
    }
}

/// The per-cycle band of the 30 % marking (every ratio in [0.60, 0.85], geometric mean in
/// [0.66, 0.76]): the quick tier holds too few rows for the order of the full-tier rule
/// (`common::assert_convergence`). It holds a single ratio inside the window [2, 7], and fixed-number marking of
/// 30 % makes the ratio alternate with period two (the thesis too: 0.827, 0.659, 0.807, 0.712 in
/// IV.36), so the quick tier applies the rule to one full period, printed rows 1–2; the full
/// tier applies `assert_convergence` on [2, 7] (`full_tier::reynolds`, ignored by default).
#[test]
fn convergence_rate_inside_the_window() {
    for t in TABLES {
        if CONSTANT.contains(&t) {
            continue;
        }
        let ratios: Vec<f64> = quick(t).rows.iter().filter_map(|r| r.ratio()).collect();
        assert_eq!(ratios.len(), 2, "{t}");
        for q in &ratios {
            assert!((0.60..=0.85).contains(q), "{t}: ratios {ratios:?}");
        }
        let gm = (ratios[0] * ratios[1]).sqrt();
        assert!(
            (0.66..=0.76).contains(&gm),
            "{t}: geometric mean {gm}: {ratios:?}"
        );
    }
}

/// The full-tier rules of a table (`tests/full_tier.rs`): the convergence rule on printed rows
/// 2–7 (not for the constant solutions) and the agreement rules — dofs, ratio spread, IV.43's
/// part — on all eight rows (not for the copies).
pub fn full_tier_rules(t: &str, r: &RunResult) {
    if CONSTANT.contains(&t) {
        return;
    }
    assert_convergence(t, r);
    if DUPLICATES.contains(&t) {
        return;
    }
    assert_dofs_follow_the_thesis(t, r);
    assert_estimate_ratio_spread(t, r);
    if spec(t).thesis.additive_part.is_some() {
        assert_additive_part_explains_the_drift(t, r);
    }
}

#[test]
fn cavitation_solutions_are_admissible() {
    for t in CAVITATION {
        let r = quick(t);
        for row in &r.rows {
            let it = row.value("active_set_iterations").expect("counter");
            assert!((1.0..100.0).contains(&it), "{t}: {it} iterations");
        }
        for p in &r.probes {
            assert!(p.value >= 0.0, "{t}: ψ = {} < 0", p.value);
        }
        let f = &r.fields[0];
        assert!(!f.zone.is_empty(), "{t}: no cavitation zone");
    }
}

#[test]
fn hard_case_hill_gap_with_velocity_1000() {
    for t in ["IV.49", "IV.69"] {
        let r = quick(t);
        assert_eq!(r.rows.len(), 3);
        assert!(r.rows.iter().all(|row| row.estimate().unwrap().is_finite()));
        assert!(r.probes.iter().all(|p| p.value.is_finite()));
    }
}

/// Which of the fourteen examples switch the cavitation model on under `auto` (first solve on
/// the 64×64 grid). The thesis treats six with cavitation; with the Chapter I source terms the
/// hill gap with horizontal velocity (IV.20) stays positive.
#[test]
fn auto_cavitation_switches_where_the_pressure_gets_negative() {
    let mut switched = Vec::new();
    let mut minima = Vec::new();
    for (k, eq) in EXAMPLES.iter().enumerate() {
        let table = format!("IV.{}", 36 + k);
        let mut s = spec(&table);
        reynolds_mut(&mut s).cavitation = Cavitation::Auto;
        s.study.quick_rows = 0;
        let mut model = ReynoldsFilm::new(
            s.problem.reynolds().unwrap(),
            &s.scene.domain,
            study::solver_of(&s),
        );
        let mut adaptation = study::build_adaptation(&s.study, &s.scene);
        run_study(
            &s,
            Tier::Quick,
            tribo::study::Budget::machine(),
            &|_, _, _| {},
            &mut model,
            &mut *adaptation,
        )
        .expect("runs");
        minima.push((*eq, model.switch.first_min_psi.unwrap()));
        if model.switch.switched_at.is_some() {
            switched.push(*eq);
        }
    }
    eprintln!("smallest ψ of the Reynolds solution per example: {minima:?}");
    assert_eq!(
        switched,
        ["IV.8", "IV.11", "IV.16", "IV.17", "IV.19"],
        "minima {minima:?}"
    );
}

/// The cell data (load, Δg/g, squeeze part at the quadrature points) are bitwise those of a
/// direct evaluation at each point: for the gaps that depend on x₁ alone they come from one
/// evaluation per distinct x₁ (plain, linear, wave; with and without cavitation load), for the
/// hill point by point, and after a refinement partly from the previous mesh's cache.
#[test]
fn cell_data_are_bitwise_the_pointwise_evaluation() {
    use tribo::models::reynolds::quadrature_points;
    for (t, load) in [
        ("IV.36", Load::Reynolds),
        ("IV.41", Load::Reynolds),
        ("IV.46", Load::Reynolds),
        ("IV.66", Load::Cavitation),
        ("IV.48", Load::Reynolds),
    ] {
        let s = spec(t);
        let p = ReynoldsProblem::from(s.problem.reynolds().unwrap());
        let mut mesh = Mesh::new([0.0, 1.0], [0.0, 1.0], 16, 16);
        let first = p.cell_data_reusing(&mesh, load, None);
        // Refine a corner block, so the second mesh mixes cached and fresh cells of two sizes.
        let flags: Vec<bool> = mesh
            .active()
            .iter()
            .map(|&c| mesh.cell_box(c)[2] <= 0.375 && mesh.cell_box(c)[3] <= 0.5)
            .collect();
        let none = vec![false; flags.len()];
        mesh.refine_and_coarsen(&flags, &none).unwrap();
        let cache = p.cell_data_reusing(&mesh, load, Some(&first));
        // The cells outside the corner block are those of the first mesh.
        let outside = mesh
            .active()
            .iter()
            .filter(|&&c| mesh.cell_box(c)[2] > 0.375 || mesh.cell_box(c)[3] > 0.5)
            .count();
        assert_eq!(
            cache.reused, outside,
            "{t}: cells taken from the first mesh"
        );
        let data = cache.data;
        for (k, &c) in mesh.active().iter().enumerate() {
            let shape = mesh.cell_shape(c);
            for (q, &(xi, eta, _)) in quadrature_points().iter().enumerate() {
                let x = shape.point(xi, eta);
                let (g, _, lap) = p.film.gap(x);
                let direct = [p.load(x, load), lap / g, p.film.squeeze_load(x)];
                let stored = [data.load[k][q], data.dg_over_g[k][q], data.squeeze[k][q]];
                assert_eq!(
                    direct.map(f64::to_bits),
                    stored.map(f64::to_bits),
                    "{t}: cell {k} point {q} at {x:?}"
                );
            }
        }
    }
}

/// The potential form ∫∇ψ·∇φ + (Δg/g)ψφ and the printed product form (II.9) give the same
/// solution up to quadrature error (wave and hill gaps, 32×32 grid).
#[test]
fn potential_and_product_forms_agree() {
    for t in ["IV.44", "IV.48"] {
        let s = spec(t);
        let mut p = ReynoldsProblem::from(s.problem.reynolds().unwrap());
        let mesh = Mesh::new([0.0, 1.0], [0.0, 1.0], 32, 32);
        let data = p.cell_data(&mesh, Load::Reynolds);
        let mut sol = Vec::new();
        for form in [Form::Potential, Form::Product] {
            p.form = form;
            let mut system = System::new(&mesh, 1);
            p.constrain(&mut system);
            p.assemble(&mesh, &mut system, &data);
            let mut solver = DirectSolver::cholesky();
            sol.push(
                solver
                    .solve(
                        system.matrix(),
                        &system.rhs,
                        &system.constraints.eliminated(),
                    )
                    .unwrap(),
            );
        }
        let scale = sol[0].iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let diff = sol[0]
            .iter()
            .zip(&sol[1])
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(
            diff <= 2e-2 * scale,
            "{t}: max difference {diff} of {scale}"
        );
    }
}

/// The report runs two readings of R₃c beside every cavitation table: the self-consistent γ₃c
/// (2γ₃ − γ₃c) and R₃ (`reynolds`). For the plain gap (IV.8, table IV.64) the self-consistent
/// reading coincides with the printed one; on the wave gap of IV.66 it lowers the estimate by a
/// few per cent (full tier: about 5 %).
#[test]
fn alternative_gamma3c_readings_are_offered_for_cavitation_tables() {
    for t in TABLES {
        let s = spec(t);
        let cavitation = s.problem.reynolds().unwrap().cavitation != Cavitation::Off;
        let suffixes: Vec<String> = study::alternative_readings(&s)
            .into_iter()
            .map(|a| a.suffix)
            .collect();
        let expected: &[&str] = if cavitation {
            &["self-consistent", "reynolds"]
        } else {
            &[]
        };
        assert_eq!(suffixes, expected, "{t}");
    }
    let mut plain = study::alternative_readings(&spec("IV.64"))
        .remove(0)
        .experiment;
    plain.study.quick_rows = 1;
    let r = study::run(&plain, Tier::Quick, &|_, _, _| {}).expect("runs");
    assert_eq!(r.rows[0].estimate(), quick("IV.64").rows[0].estimate());
    let alt = study::alternative_readings(&spec("IV.66")).remove(0);
    let r = study::run(&alt.experiment, Tier::Quick, &|_, _, _| {}).expect("runs");
    let base = quick("IV.66");
    for (a, b) in r.rows.iter().zip(&base.rows) {
        let d = a.estimate().unwrap() / b.estimate().unwrap() - 1.0;
        assert!((-0.10..=-0.02).contains(&d), "cycle {}: {d}", a.cycle);
    }
}
