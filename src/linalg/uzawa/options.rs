//! What one Uzawa run does: the variant (the pressure preconditioner of Fig. III.6) and how it
//! iterates (module docs of [`super`]).

use serde::Serialize;

#[cfg(doc)]
use crate::linalg::{saddle_point::SaddlePoint, CholeskyFactor};

/// The pressure preconditioners of Fig. III.6.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
pub enum Variant {
    /// (III.87) with A_p = I (Richardson).
    Identity,
    /// (III.89), A_p = D ≈ diag(Bᵀ diag(A)⁻¹ B + C).
    Jacobi,
    /// (III.90), one forward sweep.
    GaussSeidel,
    /// (III.91), forward and backward sweep.
    Ssor,
    /// (III.92), SSOR with the two-term minimisation over span{q, d}.
    CgSsor,
}

impl Variant {
    /// The five variants in the order of Fig. III.6's legend reading (simplest first).
    pub const ALL: [Variant; 5] = [
        Variant::Identity,
        Variant::Jacobi,
        Variant::GaussSeidel,
        Variant::Ssor,
        Variant::CgSsor,
    ];

    /// `identity`, `jacobi`, `gauss-seidel`, `ssor`, `cg-ssor`.
    pub fn name(self) -> &'static str {
        match self {
            Variant::Identity => "identity",
            Variant::Jacobi => "jacobi",
            Variant::GaussSeidel => "gauss-seidel",
            Variant::Ssor => "ssor",
            Variant::CgSsor => "cg-ssor",
        }
    }

    /// The variant of a [`Variant::name`].
    pub fn from_name(name: &str) -> Option<Variant> {
        Variant::ALL.into_iter().find(|v| v.name() == name)
    }
}

impl std::fmt::Display for Variant {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// How one Uzawa run is done (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UzawaOptions {
    pub variant: Variant,
    /// Outer iterations at most (rows 0..=max_iterations).
    pub max_iterations: usize,
    /// Stop once r_k / r_0 ≤ this.
    pub relative_tolerance: f64,
    /// p_j ← max(p_j, 0) after each pressure update.
    pub projected: bool,
    /// Step ω of [`Variant::Identity`] (p ← p + ω(g − Bᵀv − Cp)); ignored by the others.
    pub damping: f64,
    /// Every inner solve to the floor 1e-14·‖f‖ instead of min(r², 0.1·r).
    pub exact_inner: bool,
    /// What the relative residual of a row (and [`UzawaOptions::relative_tolerance`]) is
    /// relative to.
    pub scale: ResidualScale,
    /// How CG-SSOR gets S·d for its previous direction d (module docs).
    pub direction_product: DirectionProduct,
    /// How the inner A-solves are done (module docs, "Inner solves").
    pub inner: InnerSolver,
    /// How CG-SSOR steps (module docs, "CG-SSOR step rules").
    pub cg_rule: CgRule,
}

/// How [`Variant::CgSsor`] steps (module docs, "CG-SSOR step rules").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum CgRule {
    /// (III.92) as printed: p¹ = p^{½}, then always the two-term minimiser over span{q, d};
    /// projected runs clip, p_j ← max(p_j, 0), after every update (the Outlook's "projected
    /// cg-method" read literally).
    #[default]
    AsPrinted,
    /// Safeguarded: the SSOR correction q is replaced by D⁻¹s when it is no descent direction
    /// (qᵀs ≤ 0), the direction d is dropped then (restart) and the step after a restart is
    /// the exact minimiser along q alone; projected runs work on the face {p_j > 0} with
    /// proportioning steps and feasible steps (module docs).
    Safeguarded,
}

/// The inner solver of A x = b (module docs, "Inner solves").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum InnerSolver {
    /// Plain (unpreconditioned) CG, warm-started, to the adaptive tolerance (the thesis's).
    #[default]
    Cg,
    /// A sparse Cholesky factor of A computed once per run ([`CholeskyFactor`], in
    /// [`SaddlePoint::velocity_ordering`]), every solve exact to rounding; the tolerances are
    /// not used and an "inner iteration" counts one pair of triangular solves.
    Cholesky,
}

/// How [`Variant::CgSsor`] obtains S·d_k for the previous direction d_k = p^k − p^{k−1}
/// (module docs, "Cost per outer iteration").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum DirectionProduct {
    /// The recurrence S d_{k+1} = α Sq + β Sd_k (one extra solve when the projection clipped).
    /// Exact in exact arithmetic, but an inexact S·q enters every later Sd: with the loose
    /// inner tolerances of the first iterations the error stays and the iteration stalls once
    /// the residual is below it (on SubStokes at 2e-7 relative to ‖(f, g)‖). Fig. III.6 uses it.
    #[default]
    Recurrence,
    /// S d_{k+1} by one more inner solve (from zero, to the accuracy of the S·q solve) in every
    /// step: four A-solves per iteration instead of three, but S d carries only the current
    /// inner error.
    Fresh,
}

/// The denominator of the relative residual (module docs, "Residual and rows").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ResidualScale {
    /// r_k / r_0, the residual of row 0 (Fig. III.6: p⁰ = 0, so r_0 is the residual of
    /// (A⁻¹f, 0)).
    #[default]
    Initial,
    /// r_k / ‖(f, g)‖₂, the measure of the direct solvers (‖Kx − f̃‖/‖f̃‖ on the free dofs,
    /// f̃ the reduced right-hand side); independent of p⁰, so a warm start does not tighten
    /// the stopping test.
    RightHandSide,
}

impl UzawaOptions {
    /// 300 iterations at most, stop at relative residual 1e-10 (relative to row 0), no
    /// projection, ω = 1, adaptive inner tolerance.
    pub fn new(variant: Variant) -> UzawaOptions {
        UzawaOptions {
            variant,
            max_iterations: 300,
            relative_tolerance: 1e-10,
            projected: false,
            damping: 1.0,
            exact_inner: false,
            scale: ResidualScale::Initial,
            direction_product: DirectionProduct::Recurrence,
            inner: InnerSolver::Cg,
            cg_rule: CgRule::AsPrinted,
        }
    }
}
