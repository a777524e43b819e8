//! The sparse matrices of the levels in compressed rows: built row by row in parallel, their
//! products (whole and masked, row-parallel in a fixed order), the single-precision copies the
//! cycle applies and the Galerkin products PᵀAP of the coarse operators.

use std::sync::Arc;

use rayon::prelude::*;

use super::{is_masked, Mask};
use crate::linalg::{split_by_offsets, transpose};

/// A sparse matrix in compressed rows with sorted columns (a level matrix in full symmetric
/// storage, or a prolongation), its values in double precision (the default: the block of the
/// assembled matrix, the prolongations and Galerkin products as built) or in single precision
/// (the copies a V-cycle applies, module docs, *Precision*).
///
/// The structure (`row_ptr`, `cols`) is shared: a copy in single precision of a matrix has the
/// structure of the original, not a copy of it.
#[derive(Clone, Debug, Default)]
pub(super) struct Sparse<T = f64> {
    pub(super) n_cols: usize,
    pub(super) row_ptr: Arc<Vec<usize>>,
    pub(super) cols: Arc<Vec<u32>>,
    pub(super) vals: Vec<T>,
}

/// The rows of one parallel task: where each row ends in the entries, and the entries.
pub(super) type RowBlock = (Vec<usize>, Vec<(u32, f64)>);

/// Rows per parallel task when building a [`Sparse`] row by row, and the fewest per task of a
/// product (a coarse level's product runs on the calling thread instead of waking another for
/// microseconds of work).
pub(super) const ROWS_PER_TASK: usize = 4096;

/// A [`Sparse`] matrix as its loops read it: slices of its row pointers, columns and values
/// (one look-up of the shared structure per loop, not per row).
#[derive(Clone, Copy)]
pub(super) struct Rows<'a, T> {
    pub(super) row_ptr: &'a [usize],
    pub(super) cols: &'a [u32],
    pub(super) vals: &'a [T],
}

impl<'a, T> Rows<'a, T> {
    #[inline]
    pub(super) fn row(&self, i: usize) -> (&'a [u32], &'a [T]) {
        let r = self.row_ptr[i]..self.row_ptr[i + 1];
        (&self.cols[r.clone()], &self.vals[r])
    }
}

impl<T: Copy + Into<f64> + Send + Sync> Sparse<T> {
    pub(super) fn n_rows(&self) -> usize {
        self.row_ptr.len() - 1
    }

    pub(super) fn rows(&self) -> Rows<'_, T> {
        Rows {
            row_ptr: &self.row_ptr,
            cols: &self.cols,
            vals: &self.vals,
        }
    }

    pub(super) fn row(&self, i: usize) -> (&[u32], &[T]) {
        self.rows().row(i)
    }

    /// Σ_j a_ij x_j over the entries of `cols`, `vals` (a row or part of one), in double
    /// precision whatever the values are stored in.
    #[inline]
    pub(super) fn dot(cols: &[u32], vals: &[T], x: &[f64]) -> f64 {
        let mut s = 0.0;
        for (&j, &a) in cols.iter().zip(vals) {
            s += a.into() * x[j as usize];
        }
        s
    }

    /// y = A x, rows in parallel, each summed in order.
    pub(super) fn multiply_into(&self, x: &[f64], y: &mut [f64]) {
        self.multiply_masked(x, y, None);
    }

    /// y = A x with the masked rows of y set to zero.
    pub(super) fn multiply_masked(&self, x: &[f64], y: &mut [f64], mask: Mask) {
        self.each_row(y, |i, y, (c, v)| {
            *y = if is_masked(mask, i) {
                0.0
            } else {
                Self::dot(c, v, x)
            };
        });
    }

    /// y += A x on the rows that are not masked.
    pub(super) fn add_product_masked(&self, x: &[f64], y: &mut [f64], mask: Mask) {
        self.each_row(y, |i, y, (c, v)| {
            if !is_masked(mask, i) {
                *y += Self::dot(c, v, x);
            }
        });
    }

    /// `update(i, y_i, row i)` for every row in parallel, at least [`ROWS_PER_TASK`] rows per
    /// task (the products of the coarse levels stay on the calling thread).
    pub(super) fn each_row(
        &self,
        y: &mut [f64],
        update: impl Fn(usize, &mut f64, (&[u32], &[T])) + Sync,
    ) {
        let a = self.rows();
        y.par_iter_mut()
            .with_min_len(ROWS_PER_TASK)
            .enumerate()
            .for_each(|(i, y)| update(i, y, a.row(i)));
    }

    /// Position of the diagonal entry of each row (every row has one).
    pub(super) fn diagonal_positions(&self) -> Vec<usize> {
        let a = self.rows();
        (0..self.n_rows())
            .into_par_iter()
            .map(|i| {
                let (c, _) = a.row(i);
                a.row_ptr[i] + c.partition_point(|&j| (j as usize) < i)
            })
            .collect()
    }
}

impl Sparse {
    pub(super) fn new(
        n_cols: usize,
        row_ptr: Vec<usize>,
        cols: Vec<u32>,
        vals: Vec<f64>,
    ) -> Sparse {
        Sparse {
            n_cols,
            row_ptr: Arc::new(row_ptr),
            cols: Arc::new(cols),
            vals,
        }
    }

    /// The matrix with `n_rows` rows whose row `i` is what `row(i, out)` appends to `out`
    /// (sorted by column), built in parallel over blocks of rows.
    pub(super) fn by_rows<F>(n_rows: usize, n_cols: usize, row: F) -> Sparse
    where
        F: Fn(usize, &mut Vec<(u32, f64)>) + Sync,
    {
        let (row_ptr, cols, vals) = Sparse::parts_by_rows(n_rows, row);
        Sparse::new(n_cols, row_ptr, cols, vals)
    }

    /// The row pointers, columns and values of [`Sparse::by_rows`].
    pub(super) fn parts_by_rows<F>(n_rows: usize, row: F) -> (Vec<usize>, Vec<u32>, Vec<f64>)
    where
        F: Fn(usize, &mut Vec<(u32, f64)>) + Sync,
    {
        let blocks: Vec<RowBlock> = (0..n_rows.div_ceil(ROWS_PER_TASK))
            .into_par_iter()
            .map(|b| {
                let rows = b * ROWS_PER_TASK..((b + 1) * ROWS_PER_TASK).min(n_rows);
                let mut ends = Vec::with_capacity(rows.len());
                let mut entries = Vec::with_capacity(rows.len() * 9);
                for i in rows {
                    row(i, &mut entries);
                    ends.push(entries.len());
                }
                (ends, entries)
            })
            .collect();
        // Stitched in parallel: each block's entries go to their place in the whole.
        let mut row_ptr = Vec::with_capacity(n_rows + 1);
        row_ptr.push(0);
        for (ends, entries) in &blocks {
            let base = *row_ptr.last().expect("starts with 0");
            row_ptr.extend(ends.iter().map(|e| base + e));
            debug_assert_eq!(ends.last().copied().unwrap_or(0), entries.len());
        }
        let nnz = *row_ptr.last().expect("starts with 0");
        let mut cols = vec![0u32; nnz];
        let mut vals = vec![0.0; nnz];
        Sparse::per_task(&row_ptr, &mut cols, &mut vals)
            .into_par_iter()
            .zip(&blocks)
            .for_each(|((c, v), (_, entries))| {
                for ((c, v), &(j, a)) in c.iter_mut().zip(v.iter_mut()).zip(entries.iter()) {
                    *c = j;
                    *v = a;
                }
            });
        (row_ptr, cols, vals)
    }

    /// The entries `cols`, `vals` of the rows `row_ptr` cut into the pieces of consecutive
    /// blocks of [`ROWS_PER_TASK`] rows, one per parallel task.
    pub(super) fn per_task<'a>(
        row_ptr: &[usize],
        cols: &'a mut [u32],
        vals: &'a mut [f64],
    ) -> Vec<(&'a mut [u32], &'a mut [f64])> {
        let n_rows = row_ptr.len() - 1;
        let starts: Vec<usize> = (0..n_rows.div_ceil(ROWS_PER_TASK) + 1)
            .map(|b| row_ptr[(b * ROWS_PER_TASK).min(n_rows)])
            .collect();
        split_by_offsets(cols, &starts)
            .into_iter()
            .zip(split_by_offsets(vals, &starts))
            .collect()
    }

    /// The matrix with `n_rows` rows of `len(i)` entries each, row `i` written by `fill(i,
    /// cols, vals)` into its place (sorted by column) — in parallel over blocks of rows, with no
    /// copy of the entries: for rows whose length is cheap to know beforehand.
    pub(super) fn by_counted_rows<L, F>(n_rows: usize, n_cols: usize, len: L, fill: F) -> Sparse
    where
        L: Fn(usize) -> usize + Sync,
        F: Fn(usize, &mut [u32], &mut [f64]) + Sync,
    {
        let lens: Vec<usize> = (0..n_rows).into_par_iter().map(&len).collect();
        let mut row_ptr = Vec::with_capacity(n_rows + 1);
        row_ptr.push(0);
        for l in lens {
            row_ptr.push(row_ptr[row_ptr.len() - 1] + l);
        }
        let nnz = row_ptr[n_rows];
        let mut cols = vec![0u32; nnz];
        let mut vals = vec![0.0; nnz];
        Sparse::per_task(&row_ptr, &mut cols, &mut vals)
            .into_par_iter()
            .enumerate()
            .for_each(|(b, (c, v))| {
                let rows = b * ROWS_PER_TASK..((b + 1) * ROWS_PER_TASK).min(n_rows);
                let base = row_ptr[rows.start];
                for i in rows {
                    let r = row_ptr[i] - base..row_ptr[i + 1] - base;
                    fill(i, &mut c[r.clone()], &mut v[r]);
                }
            });
        Sparse::new(n_cols, row_ptr, cols, vals)
    }

    /// The same matrix with its values rounded to single precision.
    pub(super) fn single(&self) -> Sparse<f32> {
        Sparse {
            n_cols: self.n_cols,
            row_ptr: Arc::clone(&self.row_ptr),
            cols: Arc::clone(&self.cols),
            vals: self.vals.par_iter().map(|&v| v as f32).collect(),
        }
    }

    pub(super) fn transpose(&self) -> Sparse {
        let (cols, vals) = (&self.cols, &self.vals);
        let (row_ptr, cols, vals) = transpose(
            &self.row_ptr,
            |p| cols[p] as usize,
            self.n_cols,
            |p| vals[p],
        );
        Sparse::new(self.n_rows(), row_ptr, cols, vals)
    }

    /// The Galerkin product PᵀAP with `pt` = Pᵀ, row by row in parallel (each row's sums in a
    /// fixed order).
    pub(super) fn galerkin(a: &Sparse, p: &Sparse, pt: &Sparse) -> Sparse {
        let nc = pt.n_rows();
        thread_local! {
            static ACCUMULATOR: std::cell::RefCell<(Vec<f64>, Vec<bool>, Vec<u32>)> =
                const { std::cell::RefCell::new((Vec::new(), Vec::new(), Vec::new())) };
        }
        Sparse::by_rows(nc, nc, |big_i, out| {
            ACCUMULATOR.with_borrow_mut(|(acc, seen, touched)| {
                if acc.len() < nc {
                    acc.resize(nc, 0.0);
                    seen.resize(nc, false);
                }
                let (pc, pv) = pt.row(big_i);
                for (&i, &p_ii) in pc.iter().zip(pv) {
                    let (ac, av) = a.row(i as usize);
                    for (&j, &a_ij) in ac.iter().zip(av) {
                        let w = p_ii * a_ij;
                        let (qc, qv) = p.row(j as usize);
                        for (&big_j, &p_jj) in qc.iter().zip(qv) {
                            let k = big_j as usize;
                            if !seen[k] {
                                seen[k] = true;
                                touched.push(big_j);
                            }
                            acc[k] += w * p_jj;
                        }
                    }
                }
                touched.sort_unstable();
                for &j in touched.iter() {
                    let k = j as usize;
                    out.push((j, acc[k]));
                    acc[k] = 0.0;
                    seen[k] = false;
                }
                touched.clear();
            })
        })
    }

    /// The matrix with the rows and columns of the indices not `kept` cut to their diagonal.
    pub(super) fn decoupled(&self, kept: &[bool]) -> Sparse {
        Sparse::by_rows(self.n_rows(), self.n_cols, |i, out| {
            let (c, v) = self.row(i);
            for (&j, &x) in c.iter().zip(v) {
                if j as usize == i || (kept[i] && kept[j as usize]) {
                    out.push((j, x));
                }
            }
        })
    }
}
