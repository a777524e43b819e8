//! Linear algebra on the assembled systems, apart from how they were assembled: a view of a
//! symmetric sparse matrix ([`Csc`]), the fill-reducing ordering ([`ordering`]), the direct
//! solvers — Cholesky for SPD systems, LDLᵀ for symmetric quasi-definite saddle points — with
//! symbolic reuse and reused work arrays ([`direct`]), the primal–dual active-set method for
//! nodal bounds ([`active_set`]), a preconditioned conjugate gradient method ([`krylov`]) and
//! the Uzawa variants (III.87)–(III.92) for stabilised saddle points ([`uzawa`]).

pub mod active_set;
pub mod direct;
pub mod krylov;
pub mod multigrid;
pub mod ordering;
pub mod solver;
pub mod uzawa;

pub use active_set::{ActiveSetOptions, ActiveSetSolution, Bound, Rotation};
pub use direct::{CholeskyFactor, DirectSolver, Factorisation, SolveError};
pub use ordering::Ordering;
pub use solver::{Accuracy, LinearSolver, SolveConstrained, SolverKind};

use rayon::prelude::*;

/// Split `data` into the consecutive pieces `offsets[k]..offsets[k + 1]`.
pub(crate) fn split_by_offsets<'a, T>(
    mut data: &'a mut [T],
    offsets: &[usize],
) -> Vec<&'a mut [T]> {
    let mut out = Vec::with_capacity(offsets.len().saturating_sub(1));
    for w in offsets.windows(2) {
        let (head, tail) = data.split_at_mut(w[1] - w[0]);
        out.push(head);
        data = tail;
    }
    out
}

/// A symmetric sparse matrix in compressed columns with both triangles stored (full storage):
/// column `j` has the row indices `row_idx[col_ptr[j]..col_ptr[j + 1]]` (sorted) and the values at
/// the same positions; `diag[j]` is the position of entry (j, j), which every column has. Row
/// indices are 32-bit (the pattern has fewer than 2³² entries): half the memory of the largest
/// array of a system, read by the assembly and every solve.
#[derive(Clone, Copy, Debug)]
pub struct Csc<'a> {
    pub col_ptr: &'a [usize],
    pub row_idx: &'a [u32],
    pub diag: &'a [usize],
    pub values: &'a [f64],
}

impl<'a> Csc<'a> {
    /// Number of rows (= columns).
    pub fn n(&self) -> usize {
        self.col_ptr.len() - 1
    }

    /// The same pattern with other values.
    pub fn with_values<'b>(&self, values: &'b [f64]) -> Csc<'b>
    where
        'a: 'b,
    {
        Csc { values, ..*self }
    }

    /// Position of entry (i, j) in the value array, if it is in the pattern.
    pub fn position(&self, i: usize, j: usize) -> Option<usize> {
        let col = &self.row_idx[self.col_ptr[j]..self.col_ptr[j + 1]];
        col.binary_search(&(i as u32)).ok().map(|p| self.col_ptr[j] + p)
    }

    /// y = A x (row i of a symmetric matrix is column i; each row summed in order, in parallel
    /// over rows).
    pub fn multiply(&self, x: &[f64]) -> Vec<f64> {
        (0..self.n())
            .into_par_iter()
            .map(|i| {
                (self.col_ptr[i]..self.col_ptr[i + 1])
                    .map(|p| self.values[p] * x[self.row_idx[p] as usize])
                    .sum()
            })
            .collect()
    }

    /// The diagonal.
    pub fn diagonal(&self) -> Vec<f64> {
        self.diag.iter().map(|&p| self.values[p]).collect()
    }
}
