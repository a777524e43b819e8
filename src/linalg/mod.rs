//! Linear algebra on the assembled systems, apart from how they were assembled: a view of a
//! symmetric sparse matrix ([`Csc`]), the fill-reducing ordering ([`ordering`]), the direct
//! solvers — Cholesky for SPD systems, LDLᵀ for symmetric quasi-definite saddle points — with
//! symbolic reuse and reused work arrays ([`direct`]), the primal–dual active-set method for
//! nodal bounds ([`active_set`]), a preconditioned conjugate gradient method ([`krylov`]) and
//! the Uzawa variants (III.87)–(III.92) for stabilised saddle points ([`uzawa`]).

pub mod active_set;
pub mod csr;
pub mod direct;
pub mod krylov;
pub mod multigrid;
pub mod ordering;
pub mod saddle_point;
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

/// The concatenation of `parts`, copied in parallel.
pub(crate) fn joined<T: Copy + Default + Send + Sync>(parts: Vec<&[T]>) -> Vec<T> {
    let mut offsets = Vec::with_capacity(parts.len() + 1);
    offsets.push(0);
    for p in &parts {
        offsets.push(offsets[offsets.len() - 1] + p.len());
    }
    let mut all = vec![T::default(); offsets[parts.len()]];
    split_by_offsets(&mut all, &offsets)
        .into_par_iter()
        .zip(parts)
        .for_each(|(out, part)| out.copy_from_slice(part));
    all
}

/// The transpose of a sparse structure in compressed rows (`row_ptr`; entry p in column
/// `column(p)` of `n_cols`): for each column the rows with an entry there, in increasing order,
/// in compressed form (`col_ptr`, `rows`), and each entry's `value(p)` beside it.
///
/// In parallel over ranges of columns, one per thread: each task scans all rows for the
/// entries of its range (once to count, once to place them) and writes only its own part of
/// the output — the result is the same whatever the number of tasks, and no entry is written
/// by two. A serial counting sort had been a tenth of a multigrid setup.
pub(crate) fn transpose<T, C, F>(
    row_ptr: &[usize],
    column: C,
    n_cols: usize,
    value: F,
) -> (Vec<usize>, Vec<u32>, Vec<T>)
where
    T: Copy + Default + Send,
    C: Fn(usize) -> usize + Sync,
    F: Fn(usize) -> T + Sync,
{
    let n_rows = row_ptr.len() - 1;
    let entries = row_ptr[n_rows];
    let tasks = rayon::current_num_threads().clamp(1, n_cols.max(1));
    let bounds: Vec<usize> = (0..=tasks).map(|t| t * n_cols / tasks).collect();
    // Entries per column, each task counting its range.
    let mut count = vec![0usize; n_cols + 1];
    split_by_offsets(&mut count[1..], &bounds)
        .into_par_iter()
        .zip(bounds.par_windows(2))
        .for_each(|(count, range)| {
            for p in 0..entries {
                let j = column(p);
                if (range[0]..range[1]).contains(&j) {
                    count[j - range[0]] += 1;
                }
            }
        });
    for j in 0..n_cols {
        count[j + 1] += count[j];
    }
    let col_ptr = count;
    let nnz = col_ptr[n_cols];
    let starts: Vec<usize> = bounds.iter().map(|&b| col_ptr[b]).collect();
    let mut rows = vec![0u32; nnz];
    let mut values = vec![T::default(); nnz];
    split_by_offsets(&mut rows, &starts)
        .into_par_iter()
        .zip(split_by_offsets(&mut values, &starts))
        .zip(bounds.par_windows(2))
        .for_each(|((rows, values), range)| {
            let base = col_ptr[range[0]];
            let mut next: Vec<usize> = col_ptr[range[0]..range[1]]
                .iter()
                .map(|&p| p - base)
                .collect();
            for i in 0..n_rows {
                for p in row_ptr[i]..row_ptr[i + 1] {
                    let j = column(p);
                    if (range[0]..range[1]).contains(&j) {
                        let q = &mut next[j - range[0]];
                        rows[*q] = i as u32;
                        values[*q] = value(p);
                        *q += 1;
                    }
                }
            }
        });
    (col_ptr, rows, values)
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
        col.binary_search(&(i as u32))
            .ok()
            .map(|p| self.col_ptr[j] + p)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The parallel transpose gives the serial counting sort's result, with one task or several
    /// (and more tasks than some ranges have entries: empty columns, empty rows).
    #[test]
    fn transpose_is_the_counting_sort_whatever_the_tasks() {
        let (n_rows, n_cols) = (300, 157);
        let mut row_ptr = vec![0];
        let mut cols = Vec::new();
        for i in 0..n_rows {
            let mut row: Vec<u32> = (0..(i * 7) % 11)
                .map(|k| ((i * 31 + k * 17) % n_cols) as u32)
                .filter(|&j| j % 13 != 5)
                .collect();
            row.sort_unstable();
            row.dedup();
            cols.extend(row);
            row_ptr.push(cols.len());
        }
        let mut expected_ptr = vec![0usize; n_cols + 1];
        for &j in &cols {
            expected_ptr[j as usize + 1] += 1;
        }
        for j in 0..n_cols {
            expected_ptr[j + 1] += expected_ptr[j];
        }
        let (mut next, mut rows, mut from) = (
            expected_ptr.clone(),
            vec![0; cols.len()],
            vec![0; cols.len()],
        );
        for i in 0..n_rows {
            for p in row_ptr[i]..row_ptr[i + 1] {
                let q = &mut next[cols[p] as usize];
                (rows[*q], from[*q]) = (i as u32, p);
                *q += 1;
            }
        }
        for threads in [1, 2, 3, 8] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let got = pool.install(|| transpose(&row_ptr, |p| cols[p] as usize, n_cols, |p| p));
            assert_eq!(
                got,
                (expected_ptr.clone(), rows.clone(), from.clone()),
                "{threads} threads"
            );
        }
    }
}
