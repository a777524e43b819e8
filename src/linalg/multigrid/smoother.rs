//! One level of the V-cycle and its hybrid Gauss–Seidel sweeps (module docs of
//! [`super`], *Hybrid Gauss–Seidel* and *Precision*).

use std::ops::Range;

use rayon::prelude::*;

use super::sparse::{Rows, Sparse};
use super::{is_masked, Mask};

/// Rows per block of the hybrid Gauss–Seidel smoother (module docs): a fixed size, so that the
/// smoother, and every result, is the same whatever the number of threads; levels of fewer rows
/// are smoothed by plain Gauss–Seidel.
pub(super) const SMOOTHING_BLOCK: usize = 32768;

/// One level of a V-cycle: its matrix, and the prolongation from the next coarser level, in
/// single precision (module docs, *Precision*).
pub(super) struct Level {
    pub(super) a: Sparse<f32>,
    /// Position of each row's diagonal entry: the entries before it are the strictly lower
    /// part of the row, those after it the strictly upper part.
    pub(super) diag: Vec<usize>,
    /// 1/a_ii of the matrix in double precision.
    pub(super) inverse_diagonal: Vec<f64>,
    /// P and Pᵀ from the next coarser level (none on the coarsest).
    pub(super) p: Option<(Sparse<f32>, Sparse<f32>)>,
}

impl Level {
    /// The level of the matrix `a` with the prolongation and restriction `p` (as built, in
    /// double precision).
    pub(super) fn new(a: &Sparse, p: Option<(&Sparse, &Sparse)>) -> Level {
        let diag = a.diagonal_positions();
        let inverse_diagonal = diag.par_iter().map(|&d| 1.0 / a.vals[d]).collect();
        Level {
            a: a.single(),
            diag,
            inverse_diagonal,
            p: p.map(|(p, pt)| (p.single(), pt.single())),
        }
    }

    /// Position of the first entry of row `i` in the smoothing block that starts at row `start`:
    /// the entries before it are the row's coupling to earlier blocks (none in most rows).
    #[inline]
    pub(super) fn first_in_block(&self, a: Rows<'_, f32>, i: usize, start: usize) -> usize {
        let first = a.row_ptr[i];
        if a.cols[first] as usize >= start {
            return first;
        }
        let lower = first..self.diag[i];
        lower.start + a.cols[lower].partition_point(|&j| (j as usize) < start)
    }

    /// One forward sweep for A z = r from z = 0 (module docs, *hybrid Gauss–Seidel*): in each
    /// block the lower part of a row inside the block meets the new z, the part in earlier blocks
    /// the initial zero. Writes the residual r − A z to `residual`: minus the rest of A times z,
    /// the coupling to earlier blocks and the upper part.
    ///
    /// The residual of a row needs z up to the row's last column, some rows further on: each
    /// block computes it as soon as the sweep has got there, while the row is still in cache,
    /// and leaves only the rows that reach into other blocks for after the sweep.
    pub(super) fn forward_sweep_from_zero(
        &self,
        r: &[f64],
        z: &mut [f64],
        residual: &mut [f64],
        mask: Mask,
    ) {
        let a = self.a.rows();
        if mask.is_some() {
            residual.fill(0.0);
        }
        // −(the coupling to earlier blocks + the upper part) of row i times z, with `z` the
        // values of the rows `from` on.
        let residual_of = |i: usize, before: Range<usize>, z: &[f64], from: usize| {
            let upper = self.diag[i] + 1..a.row_ptr[i + 1];
            let dot = |range: Range<usize>| {
                let mut s = 0.0;
                for (&j, &v) in a.cols[range.clone()].iter().zip(&a.vals[range]) {
                    s += f64::from(v) * z[j as usize - from];
                }
                s
            };
            -(dot(before) + dot(upper))
        };
        let deferred: Vec<Vec<usize>> = z
            .par_chunks_mut(SMOOTHING_BLOCK)
            .zip(residual.par_chunks_mut(SMOOTHING_BLOCK))
            .enumerate()
            .map(|(b, (zb, rb))| {
                let start = b * SMOOTHING_BLOCK;
                let end = start + zb.len();
                let mut deferred = Vec::new();
                // The next row whose residual is due.
                let mut k = start;
                for i in start..end {
                    if !is_masked(mask, i) {
                        let lower = self.first_in_block(a, i, start)..self.diag[i];
                        let mut s = 0.0;
                        for (&j, &v) in a.cols[lower.clone()].iter().zip(&a.vals[lower]) {
                            s += f64::from(v) * zb[j as usize - start];
                        }
                        zb[i - start] = (r[i] - s) * self.inverse_diagonal[i];
                    }
                    while k <= i {
                        let (first, last) = (a.row_ptr[k], a.row_ptr[k + 1] - 1);
                        let last_column = a.cols[last] as usize;
                        if last_column > i && last_column < end {
                            break;
                        }
                        if !is_masked(mask, k) {
                            if last_column >= end || (a.cols[first] as usize) < start {
                                deferred.push(k);
                            } else {
                                rb[k - start] = residual_of(k, first..first, zb, start);
                            }
                        }
                        k += 1;
                    }
                }
                // The rows left reach past the block.
                deferred.extend((k..end).filter(|&k| !is_masked(mask, k)));
                deferred
            })
            .collect();
        let z = &*z;
        let late: Vec<(usize, f64)> = deferred
            .par_iter()
            .enumerate()
            .flat_map_iter(|(b, rows)| {
                let start = b * SMOOTHING_BLOCK;
                rows.iter().map(move |&i| {
                    let before = a.row_ptr[i]..self.first_in_block(a, i, start);
                    (i, residual_of(i, before, z, 0))
                })
            })
            .collect();
        for (i, value) in late {
            residual[i] = value;
        }
    }

    /// One backward sweep for A z = r, the adjoint of the forward one: in each block, rows in
    /// reverse order, the part of a row in other blocks meeting z as it was before the sweep
    /// (`before`, a copy of z).
    pub(super) fn backward_sweep(&self, r: &[f64], z: &mut [f64], before: &mut [f64], mask: Mask) {
        let a = self.a.rows();
        before
            .par_chunks_mut(SMOOTHING_BLOCK)
            .zip(z.par_chunks(SMOOTHING_BLOCK))
            .for_each(|(b, z)| b.copy_from_slice(z));
        let before = &*before;
        by_blocks(z, mask, true, |start, i, zb| {
            let end = start + zb.len();
            let (c, v) = a.row(i);
            let inside = c[0] as usize >= start && (c[c.len() - 1] as usize) < end;
            let mut s = 0.0;
            if inside {
                for (&j, &v) in c.iter().zip(v) {
                    s += f64::from(v) * zb[j as usize - start];
                }
            } else {
                for (&j, &v) in c.iter().zip(v) {
                    let j = j as usize;
                    let zj = if (start..end).contains(&j) {
                        zb[j - start]
                    } else {
                        before[j]
                    };
                    s += f64::from(v) * zj;
                }
            }
            zb[i - start] += (r[i] - s) * self.inverse_diagonal[i];
        });
    }
}

/// The smoothing blocks of `out` in parallel ([`SMOOTHING_BLOCK`] rows each): `row(start, i,
/// block)` for every unmasked row `i` of the block that starts at row `start`, in order or in
/// `reverse` order, with the block's part of `out` (row `i` at `i − start`).
pub(super) fn by_blocks(
    out: &mut [f64],
    mask: Mask,
    reverse: bool,
    row: impl Fn(usize, usize, &mut [f64]) + Sync,
) {
    out.par_chunks_mut(SMOOTHING_BLOCK)
        .enumerate()
        .for_each(|(b, block)| {
            let start = b * SMOOTHING_BLOCK;
            let rows = start..start + block.len();
            let mut visit = |i: usize| {
                if !is_masked(mask, i) {
                    row(start, i, block);
                }
            };
            if reverse {
                rows.rev().for_each(&mut visit);
            } else {
                rows.for_each(&mut visit);
            }
        });
}
