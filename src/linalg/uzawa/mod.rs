//! The Uzawa family of §III.2.3.4 for the stabilised saddle point (III.86),
//!
//! ```text
//! A v − B p = f,
//! Bᵀv + C p = g,
//! ```
//!
//! with A ∈ ℝ^{n×n} SPD, B ∈ ℝ^{n×m}, C ∈ ℝ^{m×m} symmetric positive semidefinite and the Schur
//! complement S = BᵀA⁻¹B + C positive definite.
//! The variants differ in the preconditioner A_p of the pressure update (Fig. III.6):
//!
//! * [`Variant::Identity`]: Richardson (III.87) with A_p = I and step ω = [`UzawaOptions::damping`]
//!   (1 by default, no damping: on the test problem (III.88) λ_max(S) ≈ 0.124 < 2 by a power
//!   iteration, test `identity_needs_no_damping`; ω = 40 > 2/λ_max diverges, test
//!   `a_diverging_variant_is_an_error_naming_it`);
//! * [`Variant::Jacobi`]: (III.89) with A_p = D, where D ≈ diag(Bᵀ diag(A)⁻¹ B + C), the cheap
//!   diagonal the thesis allows instead of diag(BᵀA⁻¹B + C) (which would cost m A-solves);
//! * [`Variant::GaussSeidel`]: (III.90), one forward sweep over the pressures (the C part of the
//!   residual taken with the pressures already updated, the BᵀA⁻¹B part frozen at v^k), same D;
//! * [`Variant::Ssor`]: (III.91), forward sweep, v^{k+½} = A⁻¹(f + Bp^{k+½}), backward sweep;
//! * [`Variant::CgSsor`]: (III.92), the SSOR step q = p^{k+½} − p^k followed by the exact
//!   minimisation of ½pᵀSp − b_Sᵀp over p^k + span{q, d}, d = p^k − p^{k−1} (b_S = g − BᵀA⁻¹f):
//!   β = ((qᵀSq)(dᵀr) − (dᵀSq)(qᵀr)) / ((qᵀSq)(dᵀSd) − (qᵀSd)²), α = qᵀ(r − βSd)/(qᵀSq) with
//!   r = b_S − Sp^k, p^{k+1} = p^k + αq + βd (in the first step p^1 = p^{½}).
//!
//! **Cost per outer iteration** (every S·w product costs one inner A-solve): one A-solve for
//! identity, Jacobi and Gauss–Seidel; two for SSOR (v^k and v^{k+½}); three for CG-SSOR (v^k,
//! v^{k+½} and A⁻¹Bq for Sq), plus the few warm CG iterations of the tightening below. The
//! Schur residual r = b_S − Sp^k is g − Bᵀv^k − Cp^k, read off the v^k solve. S d comes from
//! [`UzawaOptions::direction_product`]: by default ([`DirectionProduct::Recurrence`]) the
//! recurrence S d_{k+1} = α Sq + β Sd_k (no solve), recomputed with one solve only when the
//! projection clipped a pressure (then d is not αq + βd); [`DirectionProduct::Fresh`] spends
//! that solve in every step. If the plane degenerates ((qᵀSq)(dᵀSd) − (qᵀSd)² ≤
//! 1e-14·(qᵀSq)(dᵀSd)) the step minimises along q alone (β = 0).
//!
//! **CG-SSOR step rules** ([`UzawaOptions::cg_rule`]). [`CgRule::AsPrinted`] is (III.92) as
//! above; Fig. III.6 uses it. On the SubStokes systems ([`crate::models::substokes_uzawa`],
//! δ_ε = 1.1e-3) it is slow: 1403 outer iterations to 1e-11 (relative to ‖(f, g)‖) for (IV.7)
//! on 32×32 with exact inner solves and a fresh S d, and with the recurrence the errors of S d
//! pile up until the run diverges ((IV.8), iteration 929). The cause is the SSOR correction q:
//! the sweeps freeze the BᵀA⁻¹B part, so q is no descent direction for ½pᵀSp − b_Sᵀp in every
//! other step there (qᵀr < 0), and the two-term minimiser then makes little progress.
//! [`CgRule::Safeguarded`] (a departure from the print, for those systems): when qᵀr ≤ 0, q is
//! replaced by the diagonally scaled residual D⁻¹r (always a descent direction) and d is dropped
//! (restart); after a restart the step is the exact minimiser along q alone, α = qᵀr/qᵀSq
//! (instead of the unit step p^{½} of the first iteration of (III.92)), otherwise the two-term
//! minimiser of (III.92). On (IV.7), 32×32: 69 outer iterations to 1e-11 instead of 1403.
//!
//! **Inner solves** ([`UzawaOptions::inner`]). [`InnerSolver::Cg`], the thesis's: A⁻¹ by plain
//! (unpreconditioned) CG ([`conjugate_gradient`]), warm-started from the last velocity (the S·w
//! solves from zero). The velocity solve of row k goes to the absolute residual
//! τ(r) = σ·min((r/σ)², 0.1·r/σ), floored at 1e-14·‖f‖ (1e-14·‖(f, g)‖ if f = 0), where r is
//! the current Uzawa residual and σ = 1 with [`ResidualScale::Initial`] (the absolute
//! min(r², 0.1·r) of Fig. III.6), σ = ‖(f, g)‖ with [`ResidualScale::RightHandSide`] (the
//! square of the *relative* residual: with σ = 1 the rule is not scale-invariant, and on the
//! SubStokes systems, r ≈ 1e-2·‖(f, g)‖ > 0.1, it left the inner residual at 10 % of r and the
//! iteration stalled at 3e-3): first the last residual measured (for row 0 the residual
//! of (0, p⁰)), then, if the residual r_k of the new iterate asks for a tighter τ(r_k), CG goes
//! on (warm) until the momentum residual is below τ(r_k) too — otherwise r_0 would be measured
//! with a velocity solved to only 0.1·‖f‖ and every relative residual would be off by the
//! factor 3 this costs on (III.88). This is "the residuals [of the inner solvers] should be less
//! than square of the gained Uzawa residual" of the thesis, capped at 0.1·r while r > 0.1. The
//! v^{k+½} solve of the SSOR variants uses τ(r_k). The S·w solves (A x = Bw) go to the same
//! *relative* accuracy as the v^k solve, residual ≤ τ(r_k)/‖f + Bp^k‖ · ‖Bw‖ (at least
//! 1e-14·‖Bw‖): the direction w = q is much smaller than the velocity data, and the absolute
//! τ(r_k) left Sq so inexact that CG-SSOR needed 53 iterations to 1e-6 instead of the 48 of
//! exact inner solves. With [`UzawaOptions::exact_inner`] every solve goes to the floor.
//! [`InnerSolver::Cholesky`] (not the thesis's): A is factored once per run by sparse Cholesky
//! ([`CholeskyFactor`], in [`SaddlePoint::velocity_ordering`]) and every A-solve is a pair of
//! triangular solves, exact to rounding; the tolerances are unused, and the rows count one
//! "inner iteration" per A-solve.
//!
//! **Residual and rows.** Row k of a run is the state (v^k, p^k) with v^k = A⁻¹(f + Bp^k) from
//! the inexact solve: residual r_k = √(‖Av^k − Bp^k − f‖² + ‖Bᵀv^k + Cp^k − g‖²) (the quantity
//! of Fig. III.6, computed from the matrices, not from the recurrences; for projected runs the
//! second term is ‖min(p^k, Bᵀv^k + Cp^k − g)‖², below), relative_residual r_k / r_0
//! ([`ResidualScale::Initial`], Fig. III.6, row 0 at p⁰) or r_k / ‖(f, g)‖
//! ([`ResidualScale::RightHandSide`]), pressure_error ‖p^k − p_direct‖₂ / ‖p_direct‖₂ (relative
//! Euclidean norm over the free pressures; p_direct from [`SaddlePoint::solve_direct`], the
//! sparse LDLᵀ of the coupled system), the inner CG iterations spent since the previous row, and
//! the cumulative wall seconds since the run started (the diagonal D included). A run starts
//! from p⁰ = 0 ([`uzawa`]) or from a given p⁰ ([`uzawa_from`], a warm start).
//!
//! **Divergence** is an error ([`UzawaError::Diverged`], naming the variant and the iteration):
//! a non-finite residual or pressure, or a residual above 1e6·r_0. No row ever holds NaN or inf.
//!
//! **Projection** ([`UzawaOptions::projected`], for cavitation): the bound p ≥ 0 on every
//! pressure of the block system (the free ones: Dirichlet values eliminated beforehand), i.e.
//! the complementarity problem p ≥ 0, λ = Sp − b_S ≥ 0, pᵀλ = 0 of min ½pᵀSp − b_Sᵀp over p ≥ 0.
//! Its residual replaces the mass residual by the natural one, min(p_j, λ_j) with
//! λ = Bᵀv + Cp − g (zero exactly at the solution; the plain residual keeps λ ≠ 0 on the active
//! set and never vanishes). The update: p_j ← max(p_j, 0) after each pressure update — per
//! unknown inside the Gauss–Seidel and SSOR sweeps, after the vector update for identity, Jacobi
//! and the CG step of [`CgRule::AsPrinted`] (the "projected cg-method" of the Outlook read
//! literally). That reading stalls for CG-SSOR on the SubStokes cavitation systems (at about
//! 3e-3 relative for (IV.8) on 32×32: the clipped two-term step is neither a minimiser nor a
//! descent step). [`CgRule::Safeguarded`] then solves the bound-constrained problem by a
//! face method in the manner of Dostál's MPRGP and Moré–Toraldo's GPCG, with the SSOR step as
//! the preconditioner on the face (a departure: the thesis gives no details):
//! * the face is {j : p_j > 0}; the chopped residual c_j = max(r_j, 0) at p_j = 0 (bound
//!   pressures the descent direction r = b_S − Sp would raise);
//! * if ‖c‖² > Σ_{p_j > 0} r_j² (the face problem is solved better than the bound is
//!   justified), a proportioning step p ← p + t c, t = ‖c‖²/cᵀSc (exact, feasible), restart;
//! * else the safeguarded CG-SSOR step with both sweeps over the face only (bound pressures stay
//!   0): d is dropped whenever the face changed; a step w with p + w ≥ 0 is taken whole, else
//!   the best feasible point is sought on the projected path P(p + t w), t = 1, ½, … (at most
//!   8 trials, each one S·w), against the truncation p + t_max w at the first bound (the best
//!   point of the segment), and d is dropped.
//!
//! On (IV.8) with cavitation on 32×32: 43 outer iterations to 1e-12 (the same 517 active
//! pressures as the primal–dual active-set method); as printed, clipping, no convergence.

mod cg_step;
mod inner;
mod iterate;
mod options;
mod pressure;
#[cfg(test)]
mod tests;

use std::time::Instant;

#[cfg(doc)]
use super::krylov::conjugate_gradient;
use super::krylov::CgError;
use super::saddle_point::{norm, SaddlePoint};
#[cfg(doc)]
use super::CholeskyFactor;
use super::SolveError;
use crate::results::UzawaRow;
use inner::Inner;
use iterate::Iterate;
use pressure::{CgState, Update};

pub use options::{CgRule, DirectionProduct, InnerSolver, ResidualScale, UzawaOptions, Variant};
pub use pressure::approximate_schur_diagonal;

/// A finished run: its rows and the last iterate.
#[derive(Clone, Debug)]
pub struct UzawaRun {
    pub rows: Vec<UzawaRow>,
    pub velocity: Vec<f64>,
    pub pressure: Vec<f64>,
    /// Whether the relative tolerance was reached.
    pub converged: bool,
}

/// Why a run failed.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum UzawaError {
    #[error(
        "Uzawa ({variant}) diverged in iteration {iteration}: residual {residual:e} \
         (initial {initial:e})"
    )]
    Diverged {
        variant: &'static str,
        iteration: usize,
        residual: f64,
        initial: f64,
    },
    #[error("Uzawa ({variant}), iteration {iteration}: inner CG failed: {source}")]
    Inner {
        variant: &'static str,
        iteration: usize,
        source: CgError,
    },
    #[error("Uzawa ({variant}): {message}")]
    Setup {
        variant: &'static str,
        message: String,
    },
    #[error("Uzawa ({variant}): Cholesky factor of A: {source}")]
    Factor {
        variant: &'static str,
        source: SolveError,
    },
}

/// A residual this many times the initial one counts as divergence.
pub const DIVERGENCE_FACTOR: f64 = 1e6;

/// Run one Uzawa variant from p⁰ = 0 (projected: max(0, 0) = 0) on `system`. With
/// `reference_pressure` (the direct solution) every row carries its pressure error.
pub fn uzawa(
    system: &SaddlePoint,
    options: &UzawaOptions,
    reference_pressure: Option<&[f64]>,
) -> Result<UzawaRun, UzawaError> {
    uzawa_from(system, options, reference_pressure, None)
}

/// [`uzawa`] from the pressure `initial_pressure` (p⁰ = 0 if `None`; projected runs start from
/// max(p⁰, 0)), e.g. the previous solution interpolated to this mesh (a warm start). The
/// velocity starts from 0 either way; v⁰ = A⁻¹(f + Bp⁰) is solved in row 0.
///
/// The outer iteration of (III.87)–(III.92): for k = 0, 1, …, solve v^k = A⁻¹(f + Bp^k) and
/// record row k; stop at the relative tolerance or after `max_iterations` updates; else
/// update the pressure by the variant.
pub fn uzawa_from(
    system: &SaddlePoint,
    options: &UzawaOptions,
    reference_pressure: Option<&[f64]>,
    initial_pressure: Option<&[f64]>,
) -> Result<UzawaRun, UzawaError> {
    let start = Instant::now();
    let variant = options.variant.name();
    let setup = |message: String| UzawaError::Setup { variant, message };
    check_pressures(system, reference_pressure, initial_pressure, variant)?;
    let reference_norm = reference_pressure.map(norm);
    let d = approximate_schur_diagonal(system);
    if let Some(j) = d.iter().position(|&x| !(x > 0.0 && x.is_finite())) {
        return Err(setup(format!(
            "the approximate Schur diagonal D is {} at pressure {j}",
            d[j]
        )));
    }
    let inner = Inner::new(system, options)?;

    let mut x = Iterate::new(system, initial_pressure, options.projected);
    let scale = match options.scale {
        ResidualScale::Initial => None,
        ResidualScale::RightHandSide => Some(system.rhs_norm()),
    };
    // "Current" outer residual before the first solve: that of (0, p⁰).
    let mut last_residual = system.residual(&x.v, &x.p);
    let mut rows: Vec<UzawaRow> = Vec::new();
    let mut inner_iterations = 0usize;
    let mut initial = 0.0;
    let mut cg = CgState::default();
    let mut converged = false;

    for k in 0..=options.max_iterations {
        if x.p.iter().any(|x| !x.is_finite()) {
            return Err(UzawaError::Diverged {
                variant,
                iteration: k,
                residual: f64::INFINITY,
                initial,
            });
        }
        let (residual, s, its) = x.measure(system, &inner, options.projected, last_residual, k)?;
        inner_iterations += its;
        let velocity_rhs_norm = norm(&x.rhs_v);
        if k == 0 {
            initial = residual;
        }
        if !residual.is_finite() || residual > DIVERGENCE_FACTOR * initial {
            return Err(UzawaError::Diverged {
                variant,
                iteration: k,
                residual,
                initial,
            });
        }
        let relative_residual = match scale {
            None if initial > 0.0 => residual / initial,
            Some(scale) if scale > 0.0 => residual / scale,
            _ => residual,
        };
        rows.push(UzawaRow {
            variant: variant.to_string(),
            iteration: k,
            residual,
            relative_residual,
            pressure_error: pressure_error(&x.p, reference_pressure, reference_norm),
            inner_iterations,
            seconds: start.elapsed().as_secs_f64(),
        });
        inner_iterations = 0;
        if relative_residual <= options.relative_tolerance {
            converged = true;
            break;
        }
        if k == options.max_iterations {
            break;
        }
        last_residual = residual;
        let update = Update {
            system,
            options,
            inner: &inner,
            d: &d,
            iteration: k,
            last_residual,
            velocity_rhs_norm,
        };
        inner_iterations += update.apply(&mut x, &s, &mut cg)?;
    }
    Ok(UzawaRun {
        rows,
        velocity: x.v,
        pressure: x.p,
        converged,
    })
}

/// The given pressures fit the system: `reference` and `initial` have one entry per pressure
/// unknown, and `initial` is finite. The error is the message of a setup error.
fn check_pressures(
    system: &SaddlePoint,
    reference: Option<&[f64]>,
    initial: Option<&[f64]>,
    variant: &'static str,
) -> Result<(), UzawaError> {
    let setup = |message: String| UzawaError::Setup { variant, message };
    let m = system.n_pressure();
    if let Some(reference) = reference {
        if reference.len() != m {
            return Err(setup(format!(
                "reference pressure has {} entries for {m} unknowns",
                reference.len()
            )));
        }
    }
    if let Some(initial) = initial {
        if initial.len() != m {
            return Err(setup(format!(
                "initial pressure has {} entries for {m} unknowns",
                initial.len()
            )));
        }
        if let Some(j) = initial.iter().position(|x| !x.is_finite()) {
            return Err(setup(format!(
                "initial pressure {} at unknown {j} is not finite",
                initial[j]
            )));
        }
    }
    Ok(())
}

/// ‖p − p_direct‖₂ / ‖p_direct‖₂ (the absolute error if ‖p_direct‖ = 0), when a reference
/// pressure was given.
fn pressure_error(
    p: &[f64],
    reference: Option<&[f64]>,
    reference_norm: Option<f64>,
) -> Option<f64> {
    reference.map(|reference| {
        let e: f64 = p
            .iter()
            .zip(reference)
            .map(|(a, b)| (a - b) * (a - b))
            .sum::<f64>()
            .sqrt();
        match reference_norm {
            Some(r) if r > 0.0 => e / r,
            _ => e,
        }
    })
}
