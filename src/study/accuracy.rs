//! The true error of a run without an exact solution — what accuracy costs, measured — in the
//! norm of the run's estimator, so that the effectivity η/‖e‖ can be given for every table.
//!
//! # The energy identity (elasticity, contact, Reynolds)
//!
//! Where the problem minimises J(v) = ½a(v, v) − l(v) over a closed convex set K of an affine
//! space V_D (the Dirichlet data fixed), with a symmetric coercive a, the exact solution u
//! satisfies a(u, v − u) ≥ l(v − u) for v ∈ K, hence for every v ∈ K
//!
//! J(v) − J(u) = ½‖v − u‖²_a + [a(u, v − u) − l(v − u)] ≥ ½‖v − u‖²_a,
//!
//! with equality when K = V_D (no constraints): the linear problems (elasticity, Reynolds
//! without cavitation). The discrete solution u_h is such a v whenever the discrete space is
//! conforming and takes the boundary data exactly — Q₁ on the quadtree mesh with hanging nodes
//! constrained is a subspace of H¹, the Dirichlet data of the thesis's scenes are 0 or the
//! constant ψ₀, both in Q₁ — on any mesh, nested or not (the coarsened cells of the adaptive
//! loop break the nesting but not the identity). So
//!
//! ‖u − u_h‖_a = √(2(J(u_h) − J(u)))  (linear),  ‖u − u_h‖_a ≤ √(2(J(u_h) − J(u)))  (constraints),
//!
//! the latter an upper bound whose slack [a(u, u_h − u) − l(u_h − u)] = ⟨σ_n(u), gap⟩-type
//! complementarity term is of the order of the error squared as well; it holds when
//! u_h ∈ K, exactly for the cavitation constraint ψ_h ≥ 0 (nodal values ≥ 0 give a
//! nonnegative bilinear) and for straight obstacles, up to the interpolation of a curved
//! obstacle between the vertices otherwise. The effectivity η/‖e‖ computed with the bound is
//! then a lower bound of the true effectivity.
//!
//! J(u) is not known. It is extrapolated from the run's own cycles: asymptotically
//! J(u_h) − J(u) = ½‖e‖² ≈ C·N^{−β} in the unknowns N (β = 1 for the optimal rate N^{−½} of Q₁
//! in 2-D), and the three parameters J(u), C, β are fitted by least squares to the last
//! [`FIT_CYCLES`] printed cycles ([`extrapolate`]). The earlier cycles' errors hardly depend on
//! the extrapolation (J(u_h) − J(u) is large there); the last ones do, which is why the
//! method is checked on the scenes with a manufactured solution, where the true error is known
//! (`measured_error` against `error`, `tests/manufactured.rs`).
//!
//! The identity holds for every v ∈ V_D, so also for the discrete solution of a problem whose
//! load was integrated inexactly — but only for the exact J. J(u_h) is therefore evaluated
//! with more quadrature points than the assembly uses, the data evaluated afresh at them
//! ([`crate::models::elasticity::Elasticity::energy`],
//! [`crate::models::reynolds::ReynoldsProblem::energy`]).
//!
//! # Against a reference solution (saddle points)
//!
//! A problem that minimises no energy (the SubStokes saddle point) keeps its solves and measures
//! their distance to a reference solution on a finer mesh itself
//! ([`super::Problem::reference_errors`]).

use super::error::StudyError;
use super::problem::{KeptSolve, Problem};
use crate::results::{columns, ErrorMeasure, RunResult, Value};

/// Cycles of the fit of J(u): the last four printed cycles (three where a run has only three).
pub const FIT_CYCLES: usize = 4;

/// J(u) extrapolated from (N_k, J(u_h,k)).
#[derive(Clone, Debug, PartialEq)]
pub struct EnergyLimit {
    /// J(u).
    pub limit: f64,
    /// C of J(u_h) − J(u) ≈ C·N^{−β}.
    pub factor: f64,
    /// β.
    pub beta: f64,
}

/// The least-squares fit of J_k = J + C·N_k^{−β} to `points` (N_k, J_k): for each β the fit is
/// linear in (J, C); β is searched on [0.05, 4] (a grid of step 0.01, then golden sections
/// around the best) and only fits with C > 0 (the energy decreasing towards its limit) count.
/// `None` with fewer than three points or no fit with C > 0.
pub fn extrapolate(points: &[(f64, f64)]) -> Option<EnergyLimit> {
    if points.len() < 3 {
        return None;
    }
    // J scaled to O(1) around the last value, so that the sums do not cancel
    let (_, last) = points[points.len() - 1];
    let scale = points
        .iter()
        .map(|(_, j)| (j - last).abs())
        .fold(0.0f64, f64::max)
        .max(f64::MIN_POSITIVE);
    let fit = |beta: f64| -> Option<(f64, f64, f64)> {
        let xs: Vec<f64> = points.iter().map(|(n, _)| n.powf(-beta)).collect();
        let ys: Vec<f64> = points.iter().map(|(_, j)| (j - last) / scale).collect();
        let m = xs.len() as f64;
        let (sx, sy) = (xs.iter().sum::<f64>(), ys.iter().sum::<f64>());
        let sxx: f64 = xs.iter().map(|x| x * x).sum();
        let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| x * y).sum();
        let det = m * sxx - sx * sx;
        if det.abs() <= f64::EPSILON * m * sxx {
            return None;
        }
        let c = (m * sxy - sx * sy) / det;
        let j = (sy - c * sx) / m;
        let residual: f64 = xs
            .iter()
            .zip(&ys)
            .map(|(x, y)| (y - j - c * x).powi(2))
            .sum();
        (c > 0.0).then_some((residual, j, c))
    };
    let mut best: Option<(f64, f64)> = None;
    for i in 5..=400 {
        let beta = i as f64 * 0.01;
        if let Some((r, _, _)) = fit(beta) {
            if best.is_none_or(|(rb, _)| r < rb) {
                best = Some((r, beta));
            }
        }
    }
    let (_, mut beta) = best?;
    let (mut lo, mut hi) = (beta - 0.01, beta + 0.01);
    let golden = 0.5 * (5f64.sqrt() - 1.0);
    let residual = |b: f64| fit(b).map_or(f64::INFINITY, |(r, _, _)| r);
    for _ in 0..40 {
        let (a, b) = (hi - golden * (hi - lo), lo + golden * (hi - lo));
        if residual(a) < residual(b) {
            hi = b;
        } else {
            lo = a;
        }
        beta = 0.5 * (lo + hi);
    }
    let (_, j, c) = fit(beta)?;
    Some(EnergyLimit {
        limit: last + j * scale,
        factor: c * scale,
        beta,
    })
}

/// √(2(J_k − J(u))) for each energy, `None` where J_k ≤ J(u) (the fit above a cycle's energy).
pub fn energy_errors(limit: f64, energies: &[f64]) -> Vec<Option<f64>> {
    energies
        .iter()
        .map(|&j| (j > limit).then(|| (2.0 * (j - limit)).sqrt()))
        .collect()
}

/// The error of each row and how it was measured.
type Measured = (Vec<Option<f64>>, ErrorMeasure);

/// The errors of the rows of `result` by the energy identity, where it measures one in every
/// row: every row has an energy, the fit of J(u) has C > 0, and every energy lies above it.
/// Otherwise why not — an energy that does not fall under refinement (the discrete solution
/// exact), or one that falls irregularly (a discrete contact set or cavitation zone that changes
/// between cycles: no fit with C > 0, or a cycle below the fitted limit) — and the run is
/// measured against a reference instead, where the problem has one. `Ok(None)` for a run
/// without energies.
fn energy_measure(result: &RunResult, bound: bool) -> Result<Option<Measured>, &'static str> {
    let rows = &result.rows;
    let Some(points) = rows
        .iter()
        .map(|r| Some((r.dofs()? as f64, r.value(columns::ENERGY)?)))
        .collect::<Option<Vec<(f64, f64)>>>()
        .filter(|p| !p.is_empty())
    else {
        return Ok(None);
    };
    let (first, last) = (points[0].1, points[points.len() - 1].1);
    if (first - last).abs() <= 1e-12 * first.abs().max(last.abs()) {
        return Err(
            "J(u_h) does not change under refinement: the discrete solution is exact up to \
             rounding, so there is no error to measure",
        );
    }
    let from = points.len().saturating_sub(FIT_CYCLES);
    let fit = extrapolate(&points[from..]).ok_or(
        "the energies J(u_h) of the last cycles do not fall like J(u) + C·dofs^−β with C > 0, \
         so J(u) cannot be extrapolated",
    )?;
    let energies: Vec<f64> = points.iter().map(|p| p.1).collect();
    let errors = energy_errors(fit.limit, &energies);
    if errors.iter().any(Option::is_none) {
        return Err(
            "a cycle's energy J(u_h) lies below the J(u) extrapolated from the last cycles \
             (the energies fall irregularly), so the energy gives no error there",
        );
    }
    let measure = ErrorMeasure::Energy {
        limit: fit.limit,
        beta: fit.beta,
        cycles: rows[from..].iter().map(|r| r.cycle).collect(),
        bound,
    };
    Ok(Some((errors, measure)))
}

/// Add the measured error to the rows of `result`: by the energy identity where every row has
/// an energy, else against the problem's reference ([`Problem::reference_errors`] on `kept`).
/// Rows that already have the true `error` (a manufactured solution) get the measurement as
/// `measured_error`; the other rows get it as `error` with the `effectivity` η/error.
pub fn add_errors(
    result: &mut RunResult,
    problem: &mut dyn Problem,
    kept: &[KeptSolve],
) -> Result<(), StudyError> {
    let by_energy = energy_measure(result, problem.constrained());
    let (errors, measure) = match by_energy {
        Ok(Some(measured)) => measured,
        Ok(None) | Err(_) => {
            let reference = if kept.is_empty() {
                Err(None)
            } else {
                problem.reference_errors(kept)?.map_err(Some)
            };
            let notes = &mut result.notes;
            match (reference, by_energy) {
                (Ok(errors), by_energy) => {
                    if let Err(why) = by_energy {
                        let against = match errors.measure {
                            ErrorMeasure::Reference { .. } => "a reference solve",
                            _ => "the run's own last solve",
                        };
                        notes.push(format!(
                            "True error: the energy gives none here — {why}; it is measured \
                             against {against} instead."
                        ));
                    }
                    let measure = errors.measure;
                    (errors.errors.into_iter().map(Some).collect(), measure)
                }
                (Err(why_not), by_energy) => {
                    if let Err(why) = by_energy {
                        notes.push(format!("True error: not measured — {why}."));
                    }
                    if let Some(why) = why_not {
                        notes.push(format!(
                            "True error: not measured against a reference — {why}."
                        ));
                    }
                    return Ok(());
                }
            }
        }
    };
    let rows = &result.rows;
    let exact = rows.iter().any(|r| r.value(columns::ERROR).is_some());
    // A run whose discrete solution is exact up to rounding (the SubStokes film of IV.52) has
    // errors of 1e-13 against estimates of order 1: no effectivity can be read off them.
    let rounding = rows
        .iter()
        .zip(&errors)
        .all(|(r, e)| matches!((r.estimate(), e), (Some(eta), Some(e)) if *e <= 1e-9 * eta));
    if rounding && !exact {
        result.notes.push(
            "True error: none shown — the discrete solution is exact up to rounding (measured \
             errors below 1e-9 of the estimate)."
                .into(),
        );
        return Ok(());
    }
    // On a manufactured scene whose table-like measure is not already the last solve's (a
    // reference solve, the cavitation energy), the error against the last solve as well: it
    // validates the measure of the uniform runs.
    if exact && !kept.is_empty() && !matches!(measure, ErrorMeasure::LastSolve { .. }) {
        let last_solve = super::reference::against_last_solve(kept, |on, a, b| {
            problem.solve_distance(on, a, b)
        })?;
        if let Ok(last_solve) = last_solve {
            for (row, error) in result.rows.iter_mut().zip(last_solve.errors) {
                row.set(columns::LAST_SOLVE_ERROR, Value::real(Some(error)));
            }
        }
    }
    // And, where that measure is not a reference solve either, the error against one: it
    // validates the measure of the tables whose energy gives none (IV.64).
    if exact && !kept.is_empty() && !matches!(measure, ErrorMeasure::Reference { .. }) {
        if let Ok(reference) = super::reference::against_refined_solve(problem, kept)? {
            for (row, error) in result.rows.iter_mut().zip(reference.errors) {
                row.set(columns::REFERENCE_ERROR, Value::real(Some(error)));
            }
        }
    }
    for (row, error) in result.rows.iter_mut().zip(errors) {
        if exact {
            row.set(columns::MEASURED_ERROR, Value::real(error));
        } else {
            let effectivity = row.estimate().zip(error).map(|(eta, e)| eta / e);
            row.set(columns::ERROR, Value::real(error));
            row.set(columns::EFFECTIVITY, Value::real(effectivity));
        }
    }
    if !exact {
        result.accuracy = Some(measure);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sequence that follows the model exactly gives back its J(u) and β.
    #[test]
    fn the_fit_recovers_a_power_law() {
        let (limit, c, beta) = (-3.25, 40.0, 1.1);
        let points: Vec<(f64, f64)> = (0..4)
            .map(|k| {
                let n = 1000.0 * 1.9f64.powi(k);
                (n, limit + c * n.powf(-beta))
            })
            .collect();
        let fit = extrapolate(&points).expect("a fit");
        let last = points[3].1 - limit;
        assert!(
            (fit.limit - limit).abs() < 1e-4 * last,
            "J(u) {} instead of {limit}",
            fit.limit
        );
        assert!((fit.beta - beta).abs() < 1e-3, "β {}", fit.beta);
        let errors = energy_errors(fit.limit, &[points[3].1]);
        let truth = (2.0 * last).sqrt();
        assert!((errors[0].unwrap() / truth - 1.0).abs() < 1e-4);
    }

    /// An energy that grows under refinement (a discrete contact set larger than the exact one)
    /// has no fit with C > 0; two points are too few.
    #[test]
    fn no_fit_for_a_growing_energy_or_two_points() {
        let growing = [(100.0, 1.0), (200.0, 1.5), (400.0, 1.7), (800.0, 1.8)];
        assert_eq!(extrapolate(&growing), None);
        assert_eq!(extrapolate(&[(100.0, 2.0), (200.0, 1.0)]), None);
    }

    /// A cycle whose energy lies below the fitted J(u) has no error.
    #[test]
    fn an_energy_below_the_limit_has_no_error() {
        assert_eq!(energy_errors(1.0, &[3.0, 0.5]), vec![Some(2.0), None]);
    }
}
