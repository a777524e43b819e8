//! The Uzawa family of §III.2.3.4 for the stabilised saddle point (III.86),
//!
//! ```text
//! A v − B p = f,
//! Bᵀv + C p = g,
//! ```
//!
//! with A ∈ ℝ^{n×n} SPD, B ∈ ℝ^{n×m}, C ∈ ℝ^{m×m} symmetric positive semidefinite and the Schur
//! complement S = BᵀA⁻¹B + C positive definite (docs/estimators.md §6, docs/models.md §13.2).
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
//! and the CG step of [`CgRule::AsPrinted`] (the "projected cg-method" of the Outlook read as
//! docs/estimators.md §6 does). That reading stalls for CG-SSOR on the SubStokes cavitation systems (at about
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
use std::cell::RefCell;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::krylov::{conjugate_gradient, CgError, Identity, Stopping};
use super::{CholeskyFactor, Csc, DirectSolver, Ordering};

/// A sparse matrix in compressed rows (any shape): row `i` has the column indices
/// `col_idx[row_ptr[i]..row_ptr[i + 1]]` (sorted, no duplicates) and the values at the same
/// positions.
#[derive(Clone, Debug, PartialEq)]
pub struct CsrMatrix {
    pub n_rows: usize,
    pub n_cols: usize,
    pub row_ptr: Vec<usize>,
    pub col_idx: Vec<usize>,
    pub values: Vec<f64>,
}

impl CsrMatrix {
    /// From (row, column, value) triplets; duplicates are summed. Panics on an index out of
    /// range.
    pub fn from_triplets(
        n_rows: usize,
        n_cols: usize,
        mut triplets: Vec<(usize, usize, f64)>,
    ) -> CsrMatrix {
        for &(i, j, _) in &triplets {
            assert!(
                i < n_rows && j < n_cols,
                "entry ({i}, {j}) outside {n_rows}×{n_cols}"
            );
        }
        triplets.sort_unstable_by_key(|&(i, j, _)| (i, j));
        let mut row_ptr = vec![0usize; n_rows + 1];
        let mut col_idx = Vec::with_capacity(triplets.len());
        let mut values: Vec<f64> = Vec::with_capacity(triplets.len());
        let mut last = None;
        for (i, j, v) in triplets {
            if last == Some((i, j)) {
                *values.last_mut().expect("a previous entry") += v;
            } else {
                col_idx.push(j);
                values.push(v);
                row_ptr[i + 1] += 1;
                last = Some((i, j));
            }
        }
        for i in 0..n_rows {
            row_ptr[i + 1] += row_ptr[i];
        }
        CsrMatrix {
            n_rows,
            n_cols,
            row_ptr,
            col_idx,
            values,
        }
    }

    /// Stored entries.
    pub fn nnz(&self) -> usize {
        self.values.len()
    }

    /// Row `i` as (column, value) pairs.
    pub fn row(&self, i: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let range = self.row_ptr[i]..self.row_ptr[i + 1];
        self.col_idx[range.clone()]
            .iter()
            .copied()
            .zip(self.values[range].iter().copied())
    }

    /// y = M x (sequential: the blocks of the test problem are small).
    pub fn multiply_into(&self, x: &[f64], y: &mut [f64]) {
        debug_assert_eq!(x.len(), self.n_cols);
        debug_assert_eq!(y.len(), self.n_rows);
        for (i, y) in y.iter_mut().enumerate() {
            let mut s = 0.0;
            for p in self.row_ptr[i]..self.row_ptr[i + 1] {
                s += self.values[p] * x[self.col_idx[p]];
            }
            *y = s;
        }
    }

    /// M x.
    pub fn multiply(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.n_rows];
        self.multiply_into(x, &mut y);
        y
    }

    /// Mᵀ as its own compressed rows.
    pub fn transpose(&self) -> CsrMatrix {
        let mut triplets = Vec::with_capacity(self.nnz());
        for i in 0..self.n_rows {
            triplets.extend(self.row(i).map(|(j, v)| (j, i, v)));
        }
        CsrMatrix::from_triplets(self.n_cols, self.n_rows, triplets)
    }

    /// The diagonal entries M_ii, i < min(rows, columns) (0 where not stored).
    pub fn diagonal(&self) -> Vec<f64> {
        (0..self.n_rows.min(self.n_cols))
            .map(|i| self.row(i).find(|&(j, _)| j == i).map_or(0.0, |(_, v)| v))
            .collect()
    }
}

/// The block system (III.86), A v − B p = f, Bᵀv + C p = g, with Bᵀ kept as its own compressed
/// rows for the pressure updates.
#[derive(Clone, Debug)]
pub struct SaddlePoint {
    pub a: CsrMatrix,
    pub b: CsrMatrix,
    pub c: CsrMatrix,
    pub f: Vec<f64>,
    pub g: Vec<f64>,
    /// Fill-reducing ordering of the n velocity unknowns for [`InnerSolver::Cholesky`]
    /// (natural order if `None`).
    pub velocity_ordering: Option<Ordering>,
    bt: CsrMatrix,
}

/// The direct solution of a [`SaddlePoint`].
#[derive(Clone, Debug, PartialEq)]
pub struct DirectSolution {
    pub velocity: Vec<f64>,
    pub pressure: Vec<f64>,
    /// r(v, p) / ‖(f, g)‖ with r the residual of [`SaddlePoint::residual`].
    pub relative_residual: f64,
}

/// Largest relative residual accepted from [`SaddlePoint::solve_direct`].
pub const DIRECT_RELATIVE_RESIDUAL: f64 = 1e-10;

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

impl SaddlePoint {
    /// The system from its blocks; fails on inconsistent dimensions.
    pub fn new(
        a: CsrMatrix,
        b: CsrMatrix,
        c: CsrMatrix,
        f: Vec<f64>,
        g: Vec<f64>,
    ) -> Result<SaddlePoint, String> {
        let (n, m) = (a.n_rows, c.n_rows);
        if a.n_cols != n || c.n_cols != m || b.n_rows != n || b.n_cols != m {
            return Err(format!(
                "saddle point: A is {}×{}, B {}×{}, C {}×{}",
                a.n_rows, a.n_cols, b.n_rows, b.n_cols, c.n_rows, c.n_cols
            ));
        }
        if f.len() != n || g.len() != m {
            return Err(format!(
                "saddle point: f has {} entries for n = {n}, g {} for m = {m}",
                f.len(),
                g.len()
            ));
        }
        let bt = b.transpose();
        Ok(SaddlePoint {
            a,
            b,
            c,
            f,
            g,
            velocity_ordering: None,
            bt,
        })
    }

    /// n: velocity unknowns.
    pub fn n_velocity(&self) -> usize {
        self.a.n_rows
    }

    /// m: pressure unknowns.
    pub fn n_pressure(&self) -> usize {
        self.c.n_rows
    }

    /// Bᵀ.
    pub fn bt(&self) -> &CsrMatrix {
        &self.bt
    }

    /// (‖Av − Bp − f‖₂, ‖Bᵀv + Cp − g‖₂).
    pub fn residuals(&self, v: &[f64], p: &[f64]) -> (f64, f64) {
        let mut av = self.a.multiply(v);
        let bp = self.b.multiply(p);
        for ((x, b), f) in av.iter_mut().zip(&bp).zip(&self.f) {
            *x -= b + f;
        }
        let mut btv = self.bt.multiply(v);
        let cp = self.c.multiply(p);
        for ((x, c), g) in btv.iter_mut().zip(&cp).zip(&self.g) {
            *x += c - g;
        }
        (norm(&av), norm(&btv))
    }

    /// The residual of Fig. III.6, √(‖Av − Bp − f‖² + ‖Bᵀv + Cp − g‖²).
    pub fn residual(&self, v: &[f64], p: &[f64]) -> f64 {
        let (a, b) = self.residuals(v, p);
        a.hypot(b)
    }

    /// ‖(f, g)‖₂.
    pub fn rhs_norm(&self) -> f64 {
        norm(&self.f).hypot(norm(&self.g))
    }

    /// Solve the coupled system directly: the symmetric quasi-definite matrix
    /// [A −B; −Bᵀ −C] (velocities first) with right-hand side [f; −g] by the sparse LDLᵀ of
    /// [`DirectSolver::ldlt`] (signs +1, −1), in the given fill-reducing `ordering` of the
    /// n + m unknowns (natural order if `None`). Fails if the factorisation fails or the
    /// relative residual exceeds [`DIRECT_RELATIVE_RESIDUAL`].
    pub fn solve_direct(&self, ordering: Option<Ordering>) -> Result<DirectSolution, String> {
        let (n, m) = (self.n_velocity(), self.n_pressure());
        let total = n + m;
        // Full symmetric storage: column j = row j of the symmetric matrix.
        let mut col_ptr = Vec::with_capacity(total + 1);
        let mut row_idx = Vec::new();
        let mut values = Vec::new();
        let mut diag = Vec::with_capacity(total);
        col_ptr.push(0);
        let mut push_row = |entries: &mut Vec<(usize, f64)>, j: usize| {
            if !entries.iter().any(|&(i, _)| i == j) {
                entries.push((j, 0.0));
            }
            entries.sort_unstable_by_key(|&(i, _)| i);
            for &(i, v) in entries.iter() {
                if i == j {
                    diag.push(row_idx.len());
                }
                row_idx.push(i as u32);
                values.push(v);
            }
            col_ptr.push(row_idx.len());
        };
        let mut entries = Vec::new();
        for i in 0..n {
            entries.clear();
            entries.extend(self.a.row(i));
            entries.extend(self.b.row(i).map(|(j, v)| (n + j, -v)));
            push_row(&mut entries, i);
        }
        for j in 0..m {
            entries.clear();
            entries.extend(self.bt.row(j).map(|(i, v)| (i, -v)));
            entries.extend(self.c.row(j).map(|(k, v)| (n + k, -v)));
            push_row(&mut entries, n + j);
        }
        let matrix = Csc {
            col_ptr: &col_ptr,
            row_idx: &row_idx,
            diag: &diag,
            values: &values,
        };
        let signs: Vec<i8> = (0..total).map(|k| if k < n { 1 } else { -1 }).collect();
        let mut solver = DirectSolver::ldlt(signs);
        if let Some(ordering) = ordering {
            if ordering.len() != total {
                return Err(format!(
                    "saddle point: ordering of {} unknowns for {total}",
                    ordering.len()
                ));
            }
            solver.reorder(ordering);
        }
        let rhs: Vec<f64> = self
            .f
            .iter()
            .copied()
            .chain(self.g.iter().map(|g| -g))
            .collect();
        let x = solver
            .solve(matrix, &rhs, &[])
            .map_err(|e| format!("saddle point, direct solve: {e}"))?;
        let (velocity, pressure) = (x[..n].to_vec(), x[n..].to_vec());
        let scale = self.rhs_norm();
        let r = self.residual(&velocity, &pressure);
        let relative_residual = if scale > 0.0 { r / scale } else { r };
        if !relative_residual.is_finite() || relative_residual > DIRECT_RELATIVE_RESIDUAL {
            return Err(format!(
                "saddle point, direct solve: relative residual {relative_residual:e} exceeds \
                 {DIRECT_RELATIVE_RESIDUAL:e}"
            ));
        }
        Ok(DirectSolution {
            velocity,
            pressure,
            relative_residual,
        })
    }
}

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
    /// projected runs clip, p_j ← max(p_j, 0), after every update (the reading of docs/estimators.md §6).
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

/// One outer iteration of a run (module docs, "Residual and rows").
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct UzawaRow {
    /// [`Variant::name`].
    pub variant: String,
    pub iteration: usize,
    /// √(‖Av − Bp − f‖² + ‖Bᵀv + Cp − g‖²).
    pub residual: f64,
    /// residual / residual of row 0.
    pub relative_residual: f64,
    /// ‖p − p_direct‖₂ / ‖p_direct‖₂, when a reference pressure was given.
    pub pressure_error: Option<f64>,
    /// Inner CG iterations since the previous row.
    pub inner_iterations: usize,
    /// Wall seconds since the run started.
    pub seconds: f64,
}

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
}

/// Trial points t = 1, ½, … of the projected path P(p + t w) in a blocked step of projected
/// [`CgRule::Safeguarded`].
const PROJECTED_SEARCH_STEPS: usize = 8;

/// A residual this many times the initial one counts as divergence.
pub const DIVERGENCE_FACTOR: f64 = 1e6;

/// The inner A-solves of one run: tolerance policy and iteration count.
struct Inner<'a> {
    a: &'a CsrMatrix,
    /// [`InnerSolver::Cholesky`]: the factor of A.
    factor: Option<RefCell<CholeskyFactor>>,
    floor: f64,
    /// σ of the tolerance σ·min((r/σ)², 0.1·r/σ): 1 for [`ResidualScale::Initial`] (the
    /// absolute rule of Fig. III.6), ‖(f, g)‖ for [`ResidualScale::RightHandSide`].
    scale: f64,
    exact: bool,
    variant: &'static str,
    max_iterations: usize,
}

impl Inner<'_> {
    /// The absolute tolerance when the last outer residual is `r`.
    fn tolerance(&self, r: f64) -> f64 {
        if self.exact {
            self.floor
        } else {
            (r * r / self.scale).min(0.1 * r).max(self.floor)
        }
    }

    /// x ← A⁻¹b from the guess in x to the absolute residual `tolerance`; returns the CG
    /// iterations.
    fn solve(
        &self,
        b: &[f64],
        x: &mut [f64],
        tolerance: f64,
        iteration: usize,
    ) -> Result<usize, UzawaError> {
        if let Some(factor) = &self.factor {
            x.copy_from_slice(b);
            factor.borrow_mut().solve_in_place(x);
            if let Some(i) = x.iter().position(|v| !v.is_finite()) {
                return Err(UzawaError::Diverged {
                    variant: self.variant,
                    iteration,
                    residual: x[i],
                    initial: f64::NAN,
                });
            }
            return Ok(1);
        }
        let stopping = Stopping {
            relative: 0.0,
            absolute: tolerance,
            max_iterations: self.max_iterations,
        };
        conjugate_gradient(
            |v, out| self.a.multiply_into(v, out),
            b,
            x,
            &Identity,
            stopping,
        )
        .map(|report| report.iterations)
        .map_err(|source| UzawaError::Inner {
            variant: self.variant,
            iteration,
            source,
        })
    }
}

/// The Cholesky factor of the symmetric `a` (full storage: its compressed rows are its
/// compressed columns) in `ordering`.
fn cholesky_of(a: &CsrMatrix, ordering: Option<&Ordering>) -> Result<CholeskyFactor, String> {
    let diag = (0..a.n_rows)
        .map(|i| {
            (a.row_ptr[i]..a.row_ptr[i + 1])
                .find(|&p| a.col_idx[p] == i)
                .ok_or_else(|| format!("A has no diagonal entry in row {i}"))
        })
        .collect::<Result<Vec<usize>, String>>()?;
    let col_idx: Vec<u32> = a.col_idx.iter().map(|&j| j as u32).collect();
    let matrix = Csc {
        col_ptr: &a.row_ptr,
        row_idx: &col_idx,
        diag: &diag,
        values: &a.values,
    };
    CholeskyFactor::new(matrix, ordering).map_err(|e| format!("Cholesky factor of A: {e}"))
}

/// D_jj = Σ_i B_ij² / A_ii + C_jj, the diagonal of Bᵀ diag(A)⁻¹ B + C.
pub fn approximate_schur_diagonal(system: &SaddlePoint) -> Vec<f64> {
    let a_diag = system.a.diagonal();
    let c_diag = system.c.diagonal();
    (0..system.n_pressure())
        .map(|j| {
            system
                .bt
                .row(j)
                .map(|(i, b)| b * b / a_diag[i])
                .sum::<f64>()
                + c_diag[j]
        })
        .collect()
}

/// One Gauss–Seidel sweep (III.90)/(III.91) in place: for j in `order`,
/// p_j ← p_j + (g_j − (Bᵀv)_j − Σ_i C_ji p_i)/D_jj with the current p (updated entries
/// before j in the sweep, old ones after), projected if asked.
fn sweep(
    system: &SaddlePoint,
    d: &[f64],
    btv: &[f64],
    p: &mut [f64],
    order: impl Iterator<Item = usize>,
    projected: bool,
) {
    for j in order {
        let cp: f64 = system.c.row(j).map(|(i, c)| c * p[i]).sum();
        let mut pj = p[j] + (system.g[j] - btv[j] - cp) / d[j];
        if projected {
            pj = pj.max(0.0);
        }
        p[j] = pj;
    }
}

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
pub fn uzawa_from(
    system: &SaddlePoint,
    options: &UzawaOptions,
    reference_pressure: Option<&[f64]>,
    initial_pressure: Option<&[f64]>,
) -> Result<UzawaRun, UzawaError> {
    let start = Instant::now();
    let variant = options.variant.name();
    let (n, m) = (system.n_velocity(), system.n_pressure());
    let setup = |message: String| UzawaError::Setup { variant, message };
    if let Some(reference) = reference_pressure {
        if reference.len() != m {
            return Err(setup(format!(
                "reference pressure has {} entries for {m} unknowns",
                reference.len()
            )));
        }
    }
    if let Some(initial) = initial_pressure {
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
    let reference_norm = reference_pressure.map(norm);
    let d = approximate_schur_diagonal(system);
    if let Some(j) = d.iter().position(|&x| !(x > 0.0 && x.is_finite())) {
        return Err(setup(format!(
            "the approximate Schur diagonal D is {} at pressure {j}",
            d[j]
        )));
    }
    let f_norm = norm(&system.f);
    let floor = 1e-14
        * if f_norm > 0.0 {
            f_norm
        } else {
            system.rhs_norm()
        };
    let factor = match options.inner {
        InnerSolver::Cg => None,
        InnerSolver::Cholesky => Some(RefCell::new(
            cholesky_of(&system.a, system.velocity_ordering.as_ref()).map_err(setup)?,
        )),
    };
    let inner = Inner {
        a: &system.a,
        factor,
        floor,
        scale: match options.scale {
            ResidualScale::Initial => 1.0,
            ResidualScale::RightHandSide if system.rhs_norm() > 0.0 => system.rhs_norm(),
            ResidualScale::RightHandSide => 1.0,
        },
        exact: options.exact_inner,
        variant,
        max_iterations: 20 * n.max(10),
    };

    let mut p = initial_pressure.map_or_else(|| vec![0.0; m], <[f64]>::to_vec);
    project(&mut p, options.projected);
    let mut v = vec![0.0; n];
    let scale = match options.scale {
        ResidualScale::Initial => None,
        ResidualScale::RightHandSide => Some(system.rhs_norm()),
    };
    // "Current" outer residual before the first solve: that of (0, p⁰).
    let mut last_residual = system.residual(&v, &p);
    let mut rows: Vec<UzawaRow> = Vec::new();
    let mut inner_iterations = 0usize;
    let mut initial = 0.0;
    // CG-SSOR state: d = p^k − p^{k−1} and S d.
    let mut direction: Option<(Vec<f64>, Vec<f64>)> = None;
    // CgRule::Safeguarded: the face of the last step.
    let mut face: Option<Vec<bool>> = None;
    let mut rhs_v = vec![0.0; n];
    let mut av = vec![0.0; n];
    let mut btv = vec![0.0; m];
    let mut cp = vec![0.0; m];
    let mut converged = false;

    for k in 0..=options.max_iterations {
        if p.iter().any(|x| !x.is_finite()) {
            return Err(UzawaError::Diverged {
                variant,
                iteration: k,
                residual: f64::INFINITY,
                initial,
            });
        }
        // v^k = A⁻¹(f + B p^k).
        system.b.multiply_into(&p, &mut rhs_v);
        for (r, f) in rhs_v.iter_mut().zip(&system.f) {
            *r += f;
        }
        // Residual of (v^k, p^k); s = g − Bᵀv^k − Cp^k = b_S − S p^k (up to the inner error).
        // The solve goes on (warm) until its residual also meets the tolerance of the outer
        // residual it produces, not only that of the previous one.
        system.c.multiply_into(&p, &mut cp);
        let mut tolerance_residual = last_residual;
        let (residual, s) = loop {
            inner_iterations +=
                inner.solve(&rhs_v, &mut v, inner.tolerance(tolerance_residual), k)?;
            system.a.multiply_into(&v, &mut av);
            let momentum: f64 = av.iter().zip(&rhs_v).map(|(a, r)| (a - r) * (a - r)).sum();
            system.bt.multiply_into(&v, &mut btv);
            let s: Vec<f64> = (0..m).map(|j| system.g[j] - btv[j] - cp[j]).collect();
            let mass = if options.projected {
                // Natural residual of the complementarity: min(p_j, λ_j), λ = −s.
                s.iter()
                    .zip(&p)
                    .map(|(s, p)| p.min(-s).powi(2))
                    .sum::<f64>()
            } else {
                dot(&s, &s)
            };
            let residual = (momentum + mass).sqrt();
            let tight = inner.tolerance(residual);
            if !residual.is_finite()
                || inner.factor.is_some()
                || momentum.sqrt() <= tight
                || tight >= inner.tolerance(tolerance_residual)
            {
                break (residual, s);
            }
            tolerance_residual = residual;
        };
        let velocity_rhs_norm = norm(&rhs_v);
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
        let pressure_error = reference_pressure.map(|reference| {
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
        });
        rows.push(UzawaRow {
            variant: variant.to_string(),
            iteration: k,
            residual,
            relative_residual,
            pressure_error,
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

        match options.variant {
            Variant::Identity => {
                for (p, s) in p.iter_mut().zip(&s) {
                    *p += options.damping * s;
                }
                project(&mut p, options.projected);
            }
            Variant::Jacobi => {
                for ((p, s), d) in p.iter_mut().zip(&s).zip(&d) {
                    *p += s / d;
                }
                project(&mut p, options.projected);
            }
            Variant::GaussSeidel => {
                sweep(system, &d, &btv, &mut p, 0..m, options.projected);
            }
            Variant::CgSsor if options.cg_rule == CgRule::Safeguarded => {
                // The face {p_j > 0} (every unknown without projection); the chopped residual
                // c_j = max(s_j, 0) at p_j = 0 (the bound unknowns the descent direction
                // s = −∇J would raise).
                let bounded = options.projected;
                let free: Vec<bool> = p.iter().map(|&x| !bounded || x > 0.0).collect();
                let step = CgStep {
                    system,
                    inner: &inner,
                    relative: inner.tolerance(last_residual)
                        / velocity_rhs_norm.max(f64::MIN_POSITIVE),
                    projected: bounded,
                    iteration: k,
                    fresh: options.direction_product == DirectionProduct::Fresh,
                };
                if bounded {
                    let chopped: Vec<f64> = (0..m)
                        .map(|j| if free[j] { 0.0 } else { s[j].max(0.0) })
                        .collect();
                    let on_face: f64 = (0..m).filter(|&j| free[j]).map(|j| s[j] * s[j]).sum();
                    if dot(&chopped, &chopped) > on_face {
                        // Proportioning: release along c with the exact step ‖c‖²/cᵀSc.
                        inner_iterations += step.release(&mut p, &chopped)?;
                        direction = None;
                        face = None;
                        continue;
                    }
                }
                if face.as_ref() != Some(&free) {
                    direction = None;
                }
                let old = p.clone();
                sweep(system, &d, &btv, &mut p, (0..m).filter(|&j| free[j]), false);
                system.b.multiply_into(&p, &mut rhs_v);
                for (r, f) in rhs_v.iter_mut().zip(&system.f) {
                    *r += f;
                }
                inner_iterations +=
                    inner.solve(&rhs_v, &mut v, inner.tolerance(last_residual), k)?;
                system.bt.multiply_into(&v, &mut btv);
                let backward = (0..m).rev().filter(|&j| free[j]);
                sweep(system, &d, &btv, &mut p, backward, false);
                // The SSOR correction need not be a descent direction (the sweeps freeze
                // BᵀA⁻¹B); if it is not, the diagonally scaled residual on the face is.
                let q_s: f64 = (0..m).map(|j| (p[j] - old[j]) * s[j]).sum();
                if q_s.is_nan() || q_s <= 0.0 {
                    for j in 0..m {
                        p[j] = old[j] + if free[j] { s[j] / d[j] } else { 0.0 };
                    }
                    direction = None;
                }
                inner_iterations += step.run_on_face(&old, &mut p, &s, &mut direction)?;
                face = Some(free);
            }
            Variant::Ssor | Variant::CgSsor => {
                let old = p.clone();
                // Forward sweep from v^k, then v^{k+½} = A⁻¹(f + B p^{k+¼}), backward sweep.
                sweep(system, &d, &btv, &mut p, 0..m, options.projected);
                system.b.multiply_into(&p, &mut rhs_v);
                for (r, f) in rhs_v.iter_mut().zip(&system.f) {
                    *r += f;
                }
                inner_iterations +=
                    inner.solve(&rhs_v, &mut v, inner.tolerance(last_residual), k)?;
                system.bt.multiply_into(&v, &mut btv);
                sweep(system, &d, &btv, &mut p, (0..m).rev(), options.projected);
                if options.variant == Variant::CgSsor {
                    let step = CgStep {
                        system,
                        inner: &inner,
                        relative: inner.tolerance(last_residual)
                            / velocity_rhs_norm.max(f64::MIN_POSITIVE),
                        projected: options.projected,
                        iteration: k,
                        fresh: options.direction_product == DirectionProduct::Fresh,
                    };
                    inner_iterations += step.run(&old, &mut p, &s, &mut direction)?;
                }
            }
        }
    }
    Ok(UzawaRun {
        rows,
        velocity: v,
        pressure: p,
        converged,
    })
}

fn project(p: &mut [f64], projected: bool) {
    if projected {
        for x in p.iter_mut() {
            *x = x.max(0.0);
        }
    }
}

/// S w = Bᵀ A⁻¹ (B w) + C w with one inner solve (from zero) to the residual
/// `relative`·‖Bw‖ (at least 1e-14·‖Bw‖); returns (S w, CG iterations).
fn schur_product(
    system: &SaddlePoint,
    inner: &Inner<'_>,
    w: &[f64],
    relative: f64,
    iteration: usize,
) -> Result<(Vec<f64>, usize), UzawaError> {
    let bw = system.b.multiply(w);
    let mut x = vec![0.0; system.n_velocity()];
    let tolerance = relative.max(1e-14) * norm(&bw);
    let its = inner.solve(&bw, &mut x, tolerance, iteration)?;
    let mut sw = system.bt.multiply(&x);
    for (s, c) in sw.iter_mut().zip(system.c.multiply(w)) {
        *s += c;
    }
    Ok((sw, its))
}

/// The CG step of (III.92) in outer iteration `iteration`.
struct CgStep<'a> {
    system: &'a SaddlePoint,
    inner: &'a Inner<'a>,
    /// Relative accuracy of the S·w solves: that of the v^k solve, tolerance / ‖f + Bp^k‖.
    relative: f64,
    projected: bool,
    iteration: usize,
    /// [`DirectionProduct::Fresh`]: S d by a solve, not by the recurrence.
    fresh: bool,
}

impl CgStep<'_> {
    /// Projected [`CgRule::Safeguarded`], proportioning: p ← p + t c with c ≥ 0 the chopped residual and
    /// t = cᵀr/cᵀSc = ‖c‖²/cᵀSc, the minimiser of J along c (feasible: c only raises
    /// pressures). Returns the inner iterations.
    fn release(&self, p: &mut [f64], c: &[f64]) -> Result<usize, UzawaError> {
        let (sc, its) = schur_product(self.system, self.inner, c, self.relative, self.iteration)?;
        let csc = dot(c, &sc);
        if csc > 0.0 {
            let t = dot(c, c) / csc;
            for (p, c) in p.iter_mut().zip(c) {
                *p += t * c;
            }
        }
        Ok(its)
    }

    /// [`CgRule::Safeguarded`]: after the SSOR step on the face, `old` = p^k → `p` = p^{k+½}
    /// (q = p^{k+½} − p^k vanishes off the face), with the Schur residual `r` = b_S − S p^k:
    /// the two-term step w = αq + βd (α = qᵀr/qᵀSq along q alone after a restart,
    /// `direction` = None); taken whole if p^k + w ≥ 0, else the better of P(p^k + w) and
    /// p^k + t_max w (t_max the largest feasible step), and the direction is dropped
    /// (restart). Leaves p^{k+1} ≥ 0 in `p`; returns the inner iterations.
    fn run_on_face(
        &self,
        old: &[f64],
        p: &mut [f64],
        r: &[f64],
        direction: &mut Option<(Vec<f64>, Vec<f64>)>,
    ) -> Result<usize, UzawaError> {
        let (system, inner) = (self.system, self.inner);
        let q: Vec<f64> = p.iter().zip(old).map(|(a, b)| a - b).collect();
        p.copy_from_slice(old);
        let (sq, mut its) = schur_product(system, inner, &q, self.relative, self.iteration)?;
        let (qsq, qr) = (dot(&q, &sq), dot(&q, r));
        if qsq.is_nan() || qsq <= 0.0 {
            // No SSOR correction on the face: nothing to step along.
            *direction = None;
            return Ok(its);
        }
        let (alpha, beta) = match direction.as_ref() {
            Some((d, sd)) => {
                let dsd = dot(d, sd);
                let qsd = dot(&q, sd);
                let dr = dot(d, r);
                let den = qsq * dsd - qsd * qsd;
                let beta = if dsd > 0.0 && den > 1e-14 * qsq * dsd {
                    (qsq * dr - qsd * qr) / den
                } else {
                    0.0
                };
                ((qr - beta * qsd) / qsq, beta)
            }
            None => (qr / qsq, 0.0),
        };
        let mut w = q.clone();
        let mut sw = sq.clone();
        for x in w.iter_mut().chain(sw.iter_mut()) {
            *x *= alpha;
        }
        if let Some((d, sd)) = direction.as_ref() {
            if beta != 0.0 {
                for j in 0..w.len() {
                    w[j] += beta * d[j];
                    sw[j] += beta * sd[j];
                }
            }
        }
        // Largest feasible step along w and the unknown that blocks it.
        let (t_max, blocking) = (0..w.len())
            .filter(|&j| self.projected && w[j] < 0.0)
            .map(|j| (old[j] / -w[j], j))
            .fold(
                (f64::INFINITY, usize::MAX),
                |a, b| if b.0 < a.0 { b } else { a },
            );
        if t_max >= 1.0 {
            for j in 0..p.len() {
                p[j] = old[j] + w[j];
            }
            project(p, self.projected);
            if self.fresh {
                let (fresh, more) =
                    schur_product(system, inner, &w, self.relative, self.iteration)?;
                its += more;
                sw = fresh;
            }
            *direction = Some((w, sw));
            return Ok(its);
        }
        // J(p^k + u) − J(p^k) = −uᵀr + ½uᵀSu. Along the segment p^k + t w, J decreases up to
        // t = 1 (w minimises J on a plane through p^k containing w), so its best feasible
        // point is the truncation at t_max. Along the projected path P(p^k + t w), t = 1, ½,
        // ¼, … while t > t_max, the first point below the truncation is taken.
        let truncated = -t_max * dot(&w, r) + 0.5 * t_max * t_max * dot(&w, &sw);
        let mut t = 1.0;
        let mut taken = false;
        for _ in 0..PROJECTED_SEARCH_STEPS {
            if t <= t_max {
                break;
            }
            let projected: Vec<f64> = (0..p.len()).map(|j| (old[j] + t * w[j]).max(0.0)).collect();
            let wp: Vec<f64> = projected.iter().zip(old).map(|(a, b)| a - b).collect();
            let (swp, more) = schur_product(system, inner, &wp, self.relative, self.iteration)?;
            its += more;
            if -dot(&wp, r) + 0.5 * dot(&wp, &swp) < truncated {
                p.copy_from_slice(&projected);
                taken = true;
                break;
            }
            t *= 0.5;
        }
        if !taken {
            for j in 0..p.len() {
                p[j] = (old[j] + t_max * w[j]).max(0.0);
            }
            p[blocking] = 0.0;
        }
        *direction = None;
        Ok(its)
    }

    /// After the SSOR step `old` = p^k → `p` = p^{k+½}, with the Schur residual `r` =
    /// b_S − S p^k: leave p^{k+1} in `p` and update (d, Sd). Returns the inner iterations.
    fn run(
        &self,
        old: &[f64],
        p: &mut [f64],
        r: &[f64],
        direction: &mut Option<(Vec<f64>, Vec<f64>)>,
    ) -> Result<usize, UzawaError> {
        let (system, inner) = (self.system, self.inner);
        let q: Vec<f64> = p.iter().zip(old).map(|(a, b)| a - b).collect();
        let (sq, mut its) = schur_product(system, inner, &q, self.relative, self.iteration)?;
        let qsq = dot(&q, &sq);
        let mut coefficients = None;
        if let Some((d, sd)) = direction.as_ref() {
            if qsq > 0.0 {
                let dsd = dot(d, sd);
                let qsd = dot(&q, sd);
                let (dr, qr) = (dot(d, r), dot(&q, r));
                let den = qsq * dsd - qsd * qsd;
                // q ∥ d (or d = 0): the plane degenerates, minimise along q alone.
                let beta = if dsd > 0.0 && den > 1e-14 * qsq * dsd {
                    (qsq * dr - qsd * qr) / den
                } else {
                    0.0
                };
                let alpha = (qr - beta * qsd) / qsq;
                for j in 0..p.len() {
                    p[j] = old[j] + alpha * q[j] + beta * d[j];
                }
                coefficients = Some((alpha, beta));
            }
        }
        let mut clipped = false;
        if self.projected {
            for x in p.iter_mut() {
                if *x < 0.0 {
                    *x = 0.0;
                    clipped = true;
                }
            }
        }
        let d_new: Vec<f64> = p.iter().zip(old).map(|(a, b)| a - b).collect();
        let sd_new = match (coefficients, direction.as_ref()) {
            (Some((alpha, beta)), Some((_, sd))) if !clipped && !self.fresh => sq
                .iter()
                .zip(sd)
                .map(|(a, b)| alpha * a + beta * b)
                .collect(),
            // p = p^{k+½}: d_new = q exactly.
            (None, _) if !clipped => sq,
            _ => {
                let (sd, more) =
                    schur_product(system, inner, &d_new, self.relative, self.iteration)?;
                its += more;
                sd
            }
        };
        *direction = Some((d_new, sd_new));
        Ok(its)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::stokes_channel::{ChannelBlocks, StokesChannel};

    /// (III.88) as the thesis states it, with its direct pressure.
    fn channel() -> (ChannelBlocks, Vec<f64>) {
        let blocks = StokesChannel::thesis().blocks().unwrap();
        let direct = blocks.solve_direct().unwrap();
        (blocks, direct.pressure)
    }

    fn run(
        system: &SaddlePoint,
        reference: &[f64],
        variant: Variant,
        iterations: usize,
        tolerance: f64,
    ) -> UzawaRun {
        let options = UzawaOptions {
            max_iterations: iterations,
            relative_tolerance: tolerance,
            ..UzawaOptions::new(variant)
        };
        uzawa(system, &options, Some(reference)).unwrap()
    }

    #[test]
    fn csr_sums_duplicates_multiplies_and_transposes() {
        let m = CsrMatrix::from_triplets(
            2,
            3,
            vec![
                (1, 2, 4.0),
                (0, 0, 1.0),
                (0, 2, 2.0),
                (1, 2, -1.0),
                (0, 0, 0.5),
            ],
        );
        assert_eq!(m.row_ptr, vec![0, 2, 3]);
        assert_eq!(m.col_idx, vec![0, 2, 2]);
        assert_eq!(m.values, vec![1.5, 2.0, 3.0]);
        assert_eq!(m.multiply(&[1.0, 10.0, 100.0]), vec![201.5, 300.0]);
        let t = m.transpose();
        assert_eq!((t.n_rows, t.n_cols), (3, 2));
        assert_eq!(t.multiply(&[1.0, 10.0]), vec![1.5, 0.0, 32.0]);
        assert_eq!(m.diagonal(), vec![1.5, 0.0]);
    }

    /// A 2×1 system small enough to solve by hand: A = diag(2, 4), B = (1, 2)ᵀ, f = (2, 0),
    /// C = (c), g = 1 + S with S = BᵀA⁻¹B + C = 3/2 + c, b_S = g − BᵀA⁻¹f = g − 1 = S, so
    /// p = 1 and v = A⁻¹(f + Bp) = (3/2, 1/2).
    fn hand_sized(c: f64) -> SaddlePoint {
        SaddlePoint::new(
            CsrMatrix::from_triplets(2, 2, vec![(0, 0, 2.0), (1, 1, 4.0)]),
            CsrMatrix::from_triplets(2, 1, vec![(0, 0, 1.0), (1, 0, 2.0)]),
            CsrMatrix::from_triplets(1, 1, vec![(0, 0, c)]),
            vec![2.0, 0.0],
            vec![2.5 + c],
        )
        .unwrap()
    }

    /// Every variant converges on the hand-sized system with S = 7/4 < 2; the direct solve
    /// gives the exact solution; Richardson diverges once S = 5/2 > 2 (ω = 1).
    #[test]
    fn every_variant_solves_a_hand_sized_system() {
        let system = hand_sized(0.25);
        let direct = system.solve_direct(None).unwrap();
        assert!((direct.pressure[0] - 1.0).abs() < 1e-14);
        assert!((direct.velocity[0] - 1.5).abs() < 1e-14);
        assert!((direct.velocity[1] - 0.5).abs() < 1e-14);
        for variant in Variant::ALL {
            let out = run(&system, &direct.pressure, variant, 200, 1e-12);
            assert!(out.converged, "{variant}: {:?}", out.rows.last());
            assert!((out.pressure[0] - 1.0).abs() < 1e-10, "{variant}");
        }
        // One unknown: D = 1/2 + 1 + 1/4 = S, so Jacobi is exact in one step.
        let jacobi = run(&system, &direct.pressure, Variant::Jacobi, 10, 1e-12);
        assert_eq!(jacobi.rows.len(), 2);
        // S = 5/2: the unit Richardson step overshoots, |1 − S| = 3/2.
        let options = UzawaOptions::new(Variant::Identity);
        let err = uzawa(&hand_sized(1.0), &options, None).unwrap_err();
        assert!(
            matches!(
                err,
                UzawaError::Diverged {
                    variant: "identity",
                    ..
                }
            ),
            "{err}"
        );
        // Inconsistent blocks are refused.
        let bad = SaddlePoint::new(
            CsrMatrix::from_triplets(2, 2, vec![]),
            CsrMatrix::from_triplets(2, 2, vec![]),
            CsrMatrix::from_triplets(1, 1, vec![]),
            vec![0.0; 2],
            vec![0.0; 1],
        );
        assert!(bad.is_err());
    }

    /// CG-SSOR (III.92) on (III.88): relative residual 1e-6 within 100 iterations (48 measured;
    /// a reference implementation with exact inner solves took 49), and on to the direct
    /// pressure within 1e-8 (relative Euclidean norm).
    #[test]
    fn cg_ssor_reaches_the_direct_solution() {
        let (blocks, reference) = channel();
        let out = run(&blocks.system, &reference, Variant::CgSsor, 150, 1e-11);
        let first = out
            .rows
            .iter()
            .find(|r| r.relative_residual <= 1e-6)
            .map(|r| r.iteration);
        println!(
            "cg-ssor: 1e-6 after {first:?} iterations, {} rows, last {:?}",
            out.rows.len(),
            out.rows.last()
        );
        assert!(first.is_some_and(|k| k <= 100), "1e-6 reached at {first:?}");
        assert!(out.converged);
        let last = out.rows.last().unwrap();
        let error = last.pressure_error.unwrap();
        assert!(error <= 1e-8, "pressure error {error:e}");
        // The row's residual is the residual of the returned iterate.
        let recomputed = blocks.system.residual(&out.velocity, &out.pressure);
        assert!(
            (recomputed - last.residual).abs() <= 1e-12 * blocks.system.rhs_norm(),
            "{recomputed:e} vs {:e}",
            last.residual
        );
    }

    /// Fig. III.6's claim, "the supremacy of the cg-accelerated solver": after 50 iterations
    /// every other variant's relative residual is at least 100 times CG-SSOR's.
    #[test]
    fn at_iteration_50_cg_ssor_is_100_times_ahead_of_the_others() {
        let (blocks, reference) = channel();
        let at_50: Vec<(Variant, f64)> = Variant::ALL
            .into_iter()
            .map(|variant| {
                let out = run(&blocks.system, &reference, variant, 50, 0.0);
                assert_eq!(out.rows.len(), 51, "{variant}");
                let last = out.rows.last().unwrap();
                println!(
                    "{variant}: relative residual {:e} at 50",
                    last.relative_residual
                );
                (variant, last.relative_residual)
            })
            .collect();
        let cg = at_50[4].1;
        assert_eq!(at_50[4].0, Variant::CgSsor);
        for &(variant, r) in &at_50[..4] {
            assert!(r >= 100.0 * cg, "{variant}: {r:e} vs cg-ssor {cg:e}");
        }
    }

    /// λ_max(S) of (III.88) by a power iteration (30 steps, exact inner solves: a lower bound,
    /// 0.121; 200 steps give 0.124) is far below 2, so Richardson with ω = 1 needs no damping,
    /// and its residual does decrease.
    #[test]
    fn identity_needs_no_damping() {
        let (blocks, reference) = channel();
        let s = &blocks.system;
        let inner = Inner {
            a: &s.a,
            factor: None,
            floor: 1e-14 * norm(&s.f),
            scale: 1.0,
            exact: true,
            variant: "power",
            max_iterations: 10_000,
        };
        let mut w = vec![1.0; s.n_pressure()];
        let mut lambda = 0.0;
        for k in 0..30 {
            let scale = norm(&w);
            w.iter_mut().for_each(|x| *x /= scale);
            let (sw, _) = schur_product(s, &inner, &w, 1e-12, k).unwrap();
            lambda = dot(&w, &sw);
            w = sw;
        }
        println!("λ_max(S) ≥ {lambda}");
        assert!(lambda > 0.05 && lambda < 1.0, "λ_max(S) ≈ {lambda}");
        let out = run(s, &reference, Variant::Identity, 60, 0.0);
        let r = |k: usize| out.rows[k].relative_residual;
        assert!(
            r(60) < r(30) && r(30) < r(10),
            "{} {} {}",
            r(10),
            r(30),
            r(60)
        );
    }

    /// Richardson with ω = 40 > 2/λ_max(S) diverges; the run stops with an error naming the
    /// variant and the iteration, before any value overflows.
    #[test]
    fn a_diverging_variant_is_an_error_naming_it() {
        let (blocks, reference) = channel();
        let options = UzawaOptions {
            damping: 40.0,
            ..UzawaOptions::new(Variant::Identity)
        };
        let err = uzawa(&blocks.system, &options, Some(&reference)).unwrap_err();
        match &err {
            UzawaError::Diverged {
                variant,
                iteration,
                residual,
                initial,
            } => {
                assert_eq!(*variant, "identity");
                assert!(*iteration > 1 && *iteration < 50, "iteration {iteration}");
                assert!(residual.is_finite() && *residual > DIVERGENCE_FACTOR * initial);
            }
            other => panic!("not a divergence: {other}"),
        }
        let message = err.to_string();
        assert!(message.contains("identity") && message.contains("iteration"));
    }

    /// The projection: on (III.88) the direct pressure is positive (the bound is inactive at
    /// the solution), and projected CG-SSOR still reaches it. With the data negated the direct
    /// pressure is negative, so the projection acts: every variant keeps p ≥ 0 and finite.
    #[test]
    fn projected_runs_keep_the_pressure_nonnegative() {
        let (blocks, reference) = channel();
        assert!(reference.iter().all(|&p| p > 0.0));
        let options = UzawaOptions {
            max_iterations: 150,
            relative_tolerance: 1e-11,
            projected: true,
            ..UzawaOptions::new(Variant::CgSsor)
        };
        let out = uzawa(&blocks.system, &options, Some(&reference)).unwrap();
        let error = out.rows.last().unwrap().pressure_error.unwrap();
        assert!(out.converged && error < 1e-8, "{error:e}");

        let mut negated = blocks.system.clone();
        negated.f.iter_mut().for_each(|x| *x = -*x);
        negated.g.iter_mut().for_each(|x| *x = -*x);
        let negative: Vec<f64> = reference.iter().map(|p| -p).collect();
        for variant in Variant::ALL {
            let options = UzawaOptions {
                max_iterations: 30,
                projected: true,
                ..UzawaOptions::new(variant)
            };
            let out = uzawa(&negated, &options, Some(&negative)).unwrap();
            assert!(out.pressure.iter().all(|&p| p >= 0.0), "{variant}");
            assert!(out.rows.iter().all(|r| r.residual.is_finite()), "{variant}");
        }
    }

    /// The Cholesky inner solver gives the run of exact inner CG solves on (III.88): CG-SSOR
    /// as printed reaches 1e-6 at the same iteration (48) and the direct pressure to 1e-9;
    /// every row spends whole A-solves (one per product).
    #[test]
    fn cholesky_inner_solves_match_exact_cg() {
        let (blocks, reference) = channel();
        let first = |options: &UzawaOptions| {
            let out = uzawa(&blocks.system, options, Some(&reference)).unwrap();
            let k = out
                .rows
                .iter()
                .find(|r| r.relative_residual <= 1e-6)
                .map(|r| r.iteration);
            (k, out)
        };
        let exact = UzawaOptions {
            exact_inner: true,
            max_iterations: 150,
            relative_tolerance: 1e-11,
            ..UzawaOptions::new(Variant::CgSsor)
        };
        let cholesky = UzawaOptions {
            inner: InnerSolver::Cholesky,
            ..exact
        };
        let (k_exact, _) = first(&exact);
        let (k_cholesky, out) = first(&cholesky);
        println!("1e-6 at {k_exact:?} (exact CG), {k_cholesky:?} (Cholesky)");
        assert_eq!(k_exact, k_cholesky);
        assert!(out.converged);
        assert!(out.rows.last().unwrap().pressure_error.unwrap() <= 1e-9);
        assert!(out.rows[1..]
            .iter()
            .all(|r| (3..=4).contains(&r.inner_iterations)));
    }

    /// The safeguarded rule on (III.88) converges to the direct pressure too (in about as many
    /// iterations as (III.92) as printed), the relative residual with
    /// [`ResidualScale::RightHandSide`] is r_k/‖(f, g)‖, and a warm start from the direct
    /// pressure stops in row 0 or 1; a warm start of the wrong length is an error.
    #[test]
    fn safeguarded_rule_scale_and_warm_start() {
        let (blocks, reference) = channel();
        let s = &blocks.system;
        let options = UzawaOptions {
            cg_rule: CgRule::Safeguarded,
            scale: ResidualScale::RightHandSide,
            relative_tolerance: 1e-12,
            ..UzawaOptions::new(Variant::CgSsor)
        };
        let out = uzawa(s, &options, Some(&reference)).unwrap();
        let last = out.rows.last().unwrap();
        println!("safeguarded: {} rows, {:?}", out.rows.len(), last);
        assert!(out.converged && last.iteration <= 150);
        assert!(last.pressure_error.unwrap() <= 1e-9);
        let row0 = &out.rows[0];
        assert!((row0.relative_residual - row0.residual / s.rhs_norm()).abs() <= 1e-15);
        let warm = uzawa_from(s, &options, Some(&reference), Some(&reference)).unwrap();
        assert!(
            warm.converged && warm.rows.len() <= 2,
            "{}",
            warm.rows.len()
        );
        let err = uzawa_from(s, &options, None, Some(&reference[1..])).unwrap_err();
        assert!(err.to_string().contains("initial pressure"), "{err}");
    }

    /// A two-pressure complementarity problem solved by hand: A = I₂, B = I₂, C = 0, so
    /// S = I and the solution of min ½|p|² − b_Sᵀp over p ≥ 0 is p = max(b_S, 0) with
    /// b_S = g − f. With b_S = (2, −3): p = (2, 0), λ = Sp − b_S = (0, 3). The projected
    /// safeguarded run finds it with a zero natural residual; the unprojected run finds
    /// p = b_S.
    #[test]
    fn projected_safeguarded_run_solves_a_hand_sized_complementarity_problem() {
        let identity = || CsrMatrix::from_triplets(2, 2, vec![(0, 0, 1.0), (1, 1, 1.0)]);
        let system = SaddlePoint::new(
            identity(),
            identity(),
            CsrMatrix::from_triplets(2, 2, vec![]),
            vec![1.0, 1.0],
            vec![3.0, -2.0],
        )
        .unwrap();
        for projected in [false, true] {
            let options = UzawaOptions {
                cg_rule: CgRule::Safeguarded,
                projected,
                max_iterations: 20,
                relative_tolerance: 1e-14,
                ..UzawaOptions::new(Variant::CgSsor)
            };
            let out = uzawa(&system, &options, None).unwrap();
            let expected = if projected { [2.0, 0.0] } else { [2.0, -3.0] };
            assert!(
                out.converged,
                "projected {projected}: {:?}",
                out.rows.last()
            );
            for (p, e) in out.pressure.iter().zip(expected) {
                assert!(
                    (p - e).abs() <= 1e-12,
                    "projected {projected}: {:?}",
                    out.pressure
                );
            }
        }
    }
}
