//! The inner solves A x = b of a Uzawa run (module docs of [`super`], "Inner solves"): plain CG
//! to the adaptive tolerance, or the triangular solves of a Cholesky factor of A, and the Schur
//! complement product S w = BᵀA⁻¹Bw + Cw built on them.

use std::cell::RefCell;

use super::{InnerSolver, ResidualScale, UzawaError, UzawaOptions};
use crate::linalg::csr::CsrMatrix;
use crate::linalg::krylov::{conjugate_gradient, Identity, Stopping};
use crate::linalg::saddle_point::{norm, SaddlePoint};
use crate::linalg::{CholeskyFactor, Csc, Ordering};

/// The inner A-solves of one run: tolerance policy and iteration count.
pub(super) struct Inner<'a> {
    pub(super) a: &'a CsrMatrix,
    /// [`InnerSolver::Cholesky`]: the factor of A.
    pub(super) factor: Option<RefCell<CholeskyFactor>>,
    pub(super) floor: f64,
    /// σ of the tolerance σ·min((r/σ)², 0.1·r/σ): 1 for [`ResidualScale::Initial`] (the
    /// absolute rule of Fig. III.6), ‖(f, g)‖ for [`ResidualScale::RightHandSide`].
    pub(super) scale: f64,
    pub(super) exact: bool,
    pub(super) variant: &'static str,
    pub(super) max_iterations: usize,
}

impl<'a> Inner<'a> {
    /// The inner solver of a run of `options` on `system`: the floor 1e-14·‖f‖ (1e-14·‖(f, g)‖
    /// if f = 0), the Cholesky factor of A for [`InnerSolver::Cholesky`] and the scale σ of
    /// the tolerance rule. Fails (the message of a setup error) if A cannot be factored.
    pub(super) fn new(
        system: &'a SaddlePoint,
        options: &UzawaOptions,
    ) -> Result<Inner<'a>, UzawaError> {
        let f_norm = norm(&system.f);
        let floor = 1e-14
            * if f_norm > 0.0 {
                f_norm
            } else {
                system.rhs_norm()
            };
        let factor = match options.inner {
            InnerSolver::Cg => None,
            InnerSolver::Cholesky => Some(RefCell::new(cholesky_of(
                &system.a,
                system.velocity_ordering.as_ref(),
                options.variant.name(),
            )?)),
        };
        Ok(Inner {
            a: &system.a,
            factor,
            floor,
            scale: match options.scale {
                ResidualScale::Initial => 1.0,
                ResidualScale::RightHandSide if system.rhs_norm() > 0.0 => system.rhs_norm(),
                ResidualScale::RightHandSide => 1.0,
            },
            exact: options.exact_inner,
            variant: options.variant.name(),
            max_iterations: 20 * system.n_velocity().max(10),
        })
    }
}

impl Inner<'_> {
    /// The absolute tolerance when the last outer residual is `r`.
    pub(super) fn tolerance(&self, r: f64) -> f64 {
        if self.exact {
            self.floor
        } else {
            (r * r / self.scale).min(0.1 * r).max(self.floor)
        }
    }

    /// x ← A⁻¹b from the guess in x to the absolute residual `tolerance`; returns the CG
    /// iterations.
    pub(super) fn solve(
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
fn cholesky_of(
    a: &CsrMatrix,
    ordering: Option<&Ordering>,
    variant: &'static str,
) -> Result<CholeskyFactor, UzawaError> {
    let diag = (0..a.n_rows)
        .map(|i| {
            (a.row_ptr[i]..a.row_ptr[i + 1])
                .find(|&p| a.col_idx[p] == i)
                .ok_or_else(|| UzawaError::Setup {
                    variant,
                    message: format!("A has no diagonal entry in row {i}"),
                })
        })
        .collect::<Result<Vec<usize>, UzawaError>>()?;
    let col_idx: Vec<u32> = a.col_idx.iter().map(|&j| j as u32).collect();
    let matrix = Csc {
        col_ptr: &a.row_ptr,
        row_idx: &col_idx,
        diag: &diag,
        values: &a.values,
    };
    CholeskyFactor::new(matrix, ordering).map_err(|source| UzawaError::Factor { variant, source })
}

/// S w = Bᵀ A⁻¹ (B w) + C w with one inner solve (from zero) to the residual
/// `relative`·‖Bw‖ (at least 1e-14·‖Bw‖); returns (S w, CG iterations).
pub(super) fn schur_product(
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
    let mut sw = system.bt().multiply(&x);
    for (s, c) in sw.iter_mut().zip(system.c.multiply(w)) {
        *s += c;
    }
    Ok((sw, its))
}
