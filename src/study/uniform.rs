//! Adaptive against uniform refinement (what adaptivity saves): a grid-adaptive table's scene
//! solved again on uniformly refined meshes — the scene's initial mesh, then each cell split
//! into four per cycle — up to the unknowns of the table's last cycle ([`DOFS_FACTOR`]) or the
//! first cycle that reaches its final error, each cycle's true
//! error measured as the table's ([`super::accuracy`]: with the J(u) extrapolated from the
//! adaptive run for the problems with an energy, against a reference of its own for the others).
//!
//! The comparison ([`saving`]) asks what a uniform mesh needs to reach the adaptive run's final
//! error: its unknowns, interpolated log–log between the two uniform cycles that bracket that
//! error, or extrapolated with the uniform run's own order over its last two cycles where no
//! uniform cycle reaches it (and said so); and its seconds — those of a single solve on that
//! uniform mesh (setup, assembly, solve, estimate), interpolated or extrapolated the same way
//! against the unknowns — against the adaptive run's seconds over all its cycles. A user who knew
//! the uniform mesh in advance would pay only that one solve, so the comparison is the one least
//! favourable to adaptivity.

use super::accuracy::energy_errors;
use super::clock::PhaseClock;
use super::error::StudyError;
use super::problem::{Discretisation, KeptSolve};
use super::reference::against_last_solve;
use super::{solve_and_estimate, Budget, RunError};
use crate::experiment::{Experiment, StudyKind};
use crate::results::{columns, ErrorMeasure, RunResult, UniformRow};

/// The uniform run stops before a cycle with more than this many times the adaptive run's final
/// unknowns ("about the same number"), and after the first cycle that reaches the adaptive
/// run's final error. A cycle has four times the unknowns of the one before, so a factor of 2
/// would add a cycle of up to eight times the cost of all before it — on the Reynolds tables
/// (700 000 unknowns) a cycle of a million, a third of the report's time for those tables —
/// where the factor 1 extrapolates over at most four times the unknowns with the uniform
/// run's own order instead.
pub const DOFS_FACTOR: f64 = 1.0;

/// Whether the table gets a uniform run: a grid-adaptive study with a measured error. The
/// uniform run's error is measured by the energy identity with the adaptive run's J(u) where
/// the table's is, else against the uniform run's own last solve
/// ([`super::reference::against_last_solve`]): a second reference solve for the uniform meshes
/// of a SubStokes table would cost about as much as the first (IV.57: 5.5 s against the
/// table's 1 s).
pub fn applies(experiment: &Experiment, run: &RunResult) -> bool {
    experiment.study.kind() == StudyKind::GridAdaptive && run.accuracy.is_some()
}

/// The uniform run of `experiment` beside its adaptive run `run` (rows with `error`), on a
/// thread of rayon's pool with `budget` as the solvers' limit (as [`super::run_within`]).
pub fn uniform_run(
    experiment: &Experiment,
    run: &RunResult,
    budget: Budget,
) -> Result<Vec<UniformRow>, RunError> {
    rayon::scope(|_| {
        let _limit = budget.limit_solvers();
        uniform_cycles(experiment, run, budget).map_err(Budget::refusal)
    })
}

/// The cycles of [`uniform_run`].
fn uniform_cycles(
    experiment: &Experiment,
    run: &RunResult,
    budget: Budget,
) -> Result<Vec<UniformRow>, RunError> {
    let fail = |cycle: usize, cause: StudyError| {
        RunError::at_cycle(
            &experiment.table,
            cycle,
            cause.context("uniform refinement"),
        )
    };
    let target = run.rows.last().and_then(|r| r.dofs()).unwrap_or(0) as f64 * DOFS_FACTOR;
    // The J(u) that measures a uniform cycle's error at once, and the adaptive final error.
    let goal = match (
        &run.accuracy,
        run.rows.last().and_then(|r| r.value(columns::ERROR)),
    ) {
        (Some(ErrorMeasure::Energy { limit, .. }), Some(error)) => Some((*limit, error)),
        _ => None,
    };
    let reached = |energy: Option<f64>| match (goal, energy) {
        (Some((limit, error)), Some(j)) => {
            energy_errors(limit, &[j])[0].is_some_and(|e| e <= error)
        }
        _ => false,
    };
    // A uniform cycle's error comes from its energy where the table's does, else from the kept
    // solves: each run computes only what its measure reads.
    let by_energy = matches!(run.accuracy, Some(ErrorMeasure::Energy { .. }));
    let mut problem = experiment
        .family
        .build(experiment)
        .map_err(|e| fail(0, e))?;
    let mut disc = Discretisation::initial(&experiment.scene).map_err(|e| fail(0, e.into()))?;
    let mut rows = Vec::new();
    let mut energies = Vec::new();
    let mut kept = Vec::new();
    for cycle in 0.. {
        budget
            .admit_cycle(experiment, disc.mesh.n_active())
            .map_err(|e| fail(cycle, e))?;
        let clock = PhaseClock::default();
        let (dofs, solution, estimate) =
            solve_and_estimate(&mut *problem, &disc, &clock).map_err(|e| fail(cycle, e))?;
        let n = problem.n_dofs(&dofs);
        let energy = if by_energy {
            problem.energy(&disc, &dofs, &solution)
        } else {
            None
        };
        energies.push(energy);
        rows.push(UniformRow {
            cycle,
            active_cells: disc.mesh.n_active(),
            dofs: n,
            estimate: crate::estimators::total(&estimate.cells),
            error: None,
            seconds: clock.seconds().total(),
        });
        if !by_energy && problem.keeps_solves() {
            kept.push(KeptSolve {
                cycle,
                estimate: rows.last().map(|r| r.estimate),
                disc: disc.clone(),
                dofs: dofs.clone(),
                u: solution.u.clone(),
            });
        }
        problem.finish_cycle(&disc, dofs, solution);
        // the next cycle has about four times the unknowns
        if 4.0 * n as f64 > target || reached(energy) {
            break;
        }
        disc.mesh.refine_global().map_err(|e| {
            fail(
                cycle,
                StudyError::from(e).context("cannot refine uniformly"),
            )
        })?;
    }
    let errors: Vec<Option<f64>> = match &run.accuracy {
        Some(ErrorMeasure::Energy { limit, .. }) => {
            let energies: Option<Vec<f64>> = energies.into_iter().collect();
            energies.map_or_else(|| vec![None; rows.len()], |j| energy_errors(*limit, &j))
        }
        // Against the uniform run's own last solve (a second reference solve for the uniform
        // meshes would cost as much as the table's own).
        _ => match against_last_solve(&kept, |on, a, b| problem.solve_distance(on, a, b))
            .map_err(|e| fail(rows.len(), e.into()))?
        {
            Ok(reference) => reference.errors.into_iter().map(Some).collect(),
            Err(_) => vec![None; rows.len()],
        },
    };
    for (row, error) in rows.iter_mut().zip(errors) {
        row.error = error.filter(|e| e.is_finite() && *e > 0.0);
    }
    Ok(rows)
}

/// What a uniform mesh needs to reach the adaptive run's final error ([`saving`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Saving {
    /// The adaptive run's final error, unknowns and seconds (all cycles).
    pub error: f64,
    pub adaptive_dofs: f64,
    pub adaptive_seconds: f64,
    /// The unknowns and the seconds of one solve of a uniform mesh with that error.
    pub uniform_dofs: f64,
    pub uniform_seconds: f64,
    /// Whether no uniform cycle reached the error, so that the uniform figures are extrapolated
    /// with the uniform run's own order.
    pub extrapolated: bool,
    /// The uniform run's order of the error against the unknowns over its last two cycles.
    pub uniform_order: f64,
}

/// The uniform unknowns and seconds at the adaptive run's final error (module docs); `None`
/// without errors in the adaptive run's last row or in two uniform cycles, or where the uniform
/// error does not decrease (no order to extrapolate with).
pub fn saving(run: &RunResult, uniform: &[UniformRow]) -> Option<Saving> {
    let last = run.rows.last()?;
    let error = last.value(columns::ERROR)?;
    let adaptive_dofs = last.dofs()? as f64;
    let adaptive_seconds: f64 = run.rows.iter().map(|r| r.seconds.total()).sum();
    let points: Vec<(f64, f64, f64)> = uniform
        .iter()
        .filter_map(|u| Some((u.dofs as f64, u.error?, u.seconds)))
        .collect();
    if points.len() < 2 {
        return None;
    }
    let log_interp = |a: f64, b: f64, t: f64| (a.ln() + t * (b.ln() - a.ln())).exp();
    let [(n1, e1, s1), (n2, e2, s2)] = [points[points.len() - 2], points[points.len() - 1]];
    let uniform_order = (e2 / e1).ln() / (n2 / n1).ln();
    let bracket = points
        .windows(2)
        .find(|w| w[0].1 > error && w[1].1 <= error);
    let (uniform_dofs, uniform_seconds, extrapolated) = match (points[0].1 <= error, bracket) {
        (true, _) => (points[0].0, points[0].2, false),
        (false, Some(w)) => {
            let t = (error / w[0].1).ln() / (w[1].1 / w[0].1).ln();
            (
                log_interp(w[0].0, w[1].0, t),
                log_interp(w[0].2, w[1].2, t),
                false,
            )
        }
        (false, None) => {
            if uniform_order.is_nan() || uniform_order >= 0.0 {
                return None;
            }
            // e = e2 (N/n2)^order, seconds = s2 (N/n2)^γ with γ from the last two cycles (≥ 1:
            // a solve costs at least linear time)
            let dofs = n2 * (error / e2).powf(1.0 / uniform_order);
            let gamma = ((s2 / s1).ln() / (n2 / n1).ln()).max(1.0);
            (dofs, s2 * (dofs / n2).powf(gamma), true)
        }
    };
    Some(Saving {
        error,
        adaptive_dofs,
        adaptive_seconds,
        uniform_dofs,
        uniform_seconds,
        extrapolated,
        uniform_order,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::results::{PhaseSeconds, Row};

    fn adaptive(error: f64, dofs: usize, seconds: f64) -> RunResult {
        let mut run = RunResult::new("T", "s", "t", "quick", [0.0, 1.0, 0.0, 1.0]);
        let mut row = Row::new(0)
            .count(columns::DOFS, dofs)
            .real(columns::ERROR, Some(error));
        row.seconds = PhaseSeconds {
            solve: seconds,
            ..PhaseSeconds::default()
        };
        run.rows.push(row);
        run
    }

    fn uniform(points: &[(usize, f64, f64)]) -> Vec<UniformRow> {
        points
            .iter()
            .enumerate()
            .map(|(cycle, &(dofs, error, seconds))| UniformRow {
                cycle,
                active_cells: dofs,
                dofs,
                estimate: error,
                error: Some(error),
                seconds,
            })
            .collect()
    }

    /// Between two uniform cycles the unknowns and seconds are interpolated log–log.
    #[test]
    fn a_bracketed_error_is_interpolated() {
        let run = adaptive(0.1, 500, 2.0);
        let u = uniform(&[(100, 0.4, 0.1), (400, 0.2, 0.4), (1600, 0.1 / 2.0, 1.6)]);
        let s = saving(&run, &u).unwrap();
        assert!(!s.extrapolated);
        // error 0.1 halfway (log) between 0.2 at 400 and 0.05 at 1600: 800 unknowns, 0.8 s
        assert!((s.uniform_dofs - 800.0).abs() < 1e-9, "{}", s.uniform_dofs);
        assert!((s.uniform_seconds - 0.8).abs() < 1e-9);
        assert_eq!(s.adaptive_seconds, 2.0);
    }

    /// Beyond the last uniform cycle the uniform run's own order extrapolates, and says so.
    #[test]
    fn an_unreached_error_is_extrapolated_with_the_uniform_order() {
        let run = adaptive(0.01, 500, 2.0);
        let u = uniform(&[(100, 0.4, 0.1), (400, 0.2, 0.4)]);
        let s = saving(&run, &u).unwrap();
        assert!(s.extrapolated);
        assert!((s.uniform_order + 0.5).abs() < 1e-12);
        // 0.2 → 0.01 at order −½: 400 · 20² unknowns
        assert!((s.uniform_dofs / 160_000.0 - 1.0).abs() < 1e-9);
        // a uniform error that grows has no order to extrapolate with
        let grows = uniform(&[(100, 0.2, 0.1), (400, 0.3, 0.4)]);
        assert_eq!(saving(&run, &grows), None);
    }
}
