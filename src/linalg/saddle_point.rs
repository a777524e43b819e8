//! The stabilised saddle point (III.86) of §III.2.3.4, A v − B p = f, Bᵀv + C p = g, as its
//! blocks, with its residual and its direct solution (the sparse LDLᵀ of the coupled system),
//! the reference the Uzawa iterations of [`super::uzawa`] are measured against.

use super::csr::CsrMatrix;
#[cfg(doc)]
use super::uzawa::InnerSolver;
use super::{Csc, DirectSolver, Ordering, SolveError};

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

/// Why a saddle point system could not be built or solved directly.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum SaddlePointError {
    /// Blocks, loads or an ordering of inconsistent sizes (the sizes in the message).
    #[error("saddle point: {0}")]
    Dimensions(String),
    /// The blocks of an assembled system cannot be split off ([`crate::fe::blocks`]).
    #[error("saddle blocks: {0}")]
    Blocks(String),
    /// The LDLᵀ factorisation or solve failed.
    #[error("saddle point, direct solve: {0}")]
    Direct(#[source] SolveError),
    /// The direct solution does not meet [`DIRECT_RELATIVE_RESIDUAL`].
    #[error(
        "saddle point, direct solve: relative residual {relative_residual:e} exceeds \
         {DIRECT_RELATIVE_RESIDUAL:e}"
    )]
    Residual { relative_residual: f64 },
}

/// Euclidean inner product.
pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Euclidean norm.
pub(super) fn norm(a: &[f64]) -> f64 {
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
    ) -> Result<SaddlePoint, SaddlePointError> {
        let (n, m) = (a.n_rows, c.n_rows);
        if a.n_cols != n || c.n_cols != m || b.n_rows != n || b.n_cols != m {
            return Err(SaddlePointError::Dimensions(format!(
                "A is {}×{}, B {}×{}, C {}×{}",
                a.n_rows, a.n_cols, b.n_rows, b.n_cols, c.n_rows, c.n_cols
            )));
        }
        if f.len() != n || g.len() != m {
            return Err(SaddlePointError::Dimensions(format!(
                "f has {} entries for n = {n}, g {} for m = {m}",
                f.len(),
                g.len()
            )));
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
    pub fn solve_direct(
        &self,
        ordering: Option<Ordering>,
    ) -> Result<DirectSolution, SaddlePointError> {
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
                return Err(SaddlePointError::Dimensions(format!(
                    "ordering of {} unknowns for {total}",
                    ordering.len()
                )));
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
            .map_err(SaddlePointError::Direct)?;
        let (velocity, pressure) = (x[..n].to_vec(), x[n..].to_vec());
        let scale = self.rhs_norm();
        let r = self.residual(&velocity, &pressure);
        let relative_residual = if scale > 0.0 { r / scale } else { r };
        if !relative_residual.is_finite() || relative_residual > DIRECT_RELATIVE_RESIDUAL {
            return Err(SaddlePointError::Residual { relative_residual });
        }
        Ok(DirectSolution {
            velocity,
            pressure,
            relative_residual,
        })
    }
}
