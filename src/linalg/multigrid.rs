//! Geometric multigrid on the quadtree hierarchy as a preconditioner for the conjugate gradient
//! method: the iterative alternative to [`super::DirectSolver`] for the SPD systems (Reynolds with
//! and without cavitation, elasticity and contact with their active constraints eliminated).
//!
//! **Levels.** The level meshes and the prolongations between their vertices come from the mesh
//! ([`crate::fe::hierarchy`], global coarsening). For one solve the free dofs of the finest level
//! are those not eliminated (Dirichlet data, hanging dofs, the active set of a variational
//! inequality); a coarse dof is free when it is not hanging on its level and the fine dof at the
//! same vertex is free, so that every coarse correction vanishes on the eliminated dofs. The
//! prolongation P restricted to the free dofs of two levels has full column rank (a free coarse
//! dof is one at its own fine vertex), and the coarse operators are the Galerkin products
//! A_c = PᵀAP of the assembled matrix — the same for every problem, whatever it assembles, and
//! no coarse-level assembly.
//!
//! **Cycle.** A V(1,1)-cycle with one forward Gauss–Seidel sweep before and one backward sweep
//! after the coarse correction: the cycle is a symmetric positive definite operator (the backward
//! sweep is the adjoint of the forward one), so it preconditions CG (Hackbusch, *Multi-Grid
//! Methods and Applications*, 1985, §10.7; Trottenberg, Oosterlee, Schüller, *Multigrid*, 2001,
//! §2.5 and §7.8). The coarsest level is solved by a sparse Cholesky factorisation.
//!
//! **Hybrid Gauss–Seidel.** To smooth on both cores, the rows of a level are cut into blocks of
//! `SMOOTHING_BLOCK` (32 768) consecutive rows, smoothed in parallel: Gauss–Seidel inside a block,
//! Jacobi between blocks (a row's coupling to other blocks meets the values from before the
//! sweep) — the "hybrid Gauss–Seidel" of Baker, Falgout, Kolev and Yang (*Multigrid smoothers
//! for ultraparallel computing*, SIAM J. Sci. Comput. 33, 2011), which keeps the smoothing
//! property when blocks are large. Forward, from zero, the sweep is (D + L_B)⁻¹ with L_B the
//! lower part inside the blocks; backward it is (D + U_B)⁻¹ = (D + L_B)⁻ᵀ on the residual, the
//! adjoint, so the cycle stays symmetric. Vertices are numbered column by column, so a block is
//! a strip of the domain some 40 vertex columns wide at 700 000 dofs: the CG iterations of the
//! Reynolds tables did not change by more than one.
//!
//! **Precision.** The cycle applies its level matrices and prolongations in single precision,
//! the vectors and every sum in double: the smoother of each level is that of the level matrix
//! rounded to `f32`, and Pᵀ is the transpose of the rounded P, so the cycle is still a fixed
//! symmetric positive definite operator, and CG, whose operator stays the block in double
//! precision, converges to the same tolerance (mixed-precision multigrid as in deal.II's
//! matrix-free solvers: Kronbichler and Ljungkvist, *Multigrid for matrix-free high-order finite
//! element computations on graphics processors*, ACM TOPC 6, 2019). The Galerkin products and
//! the coarsest factor are computed in double precision. The sweeps read a third less memory;
//! Table IV.36's CG took 0.47 s of phases instead of 0.52 s, with the same iteration counts. The
//! solutions moved below the 1e-8 of the direct-solver agreement on every table, and the meshes
//! and iteration counts stayed the same; only the estimates of IV.38 and IV.43, whose exact
//! solution is constant and whose estimate is rounding noise (1.5e-10 at ψ = 200), moved in
//! their fourth digit.
//!
//! **Active sets.** The solves of a primal–dual active-set iteration share one matrix and differ
//! in the active bounds they eliminate. The first solve builds the block of the dofs that every
//! solve leaves free (all but the constraints) and coarse levels for the dofs free in that solve
//! (its active set eliminated, as above); later solves keep both and *mask* their own active set
//! on the finest level (`Mask`). Their coarse space is then the first solve's, cut off at the
//! masked rows: still a symmetric positive definite cycle, and as good as a rebuilt one while the
//! active set moves by a thin layer of vertices — when more than `MAX_MASK_CHANGE` (2 %) of the block
//! changes, the coarse levels are rebuilt. The first solve of the cavitation tables starts from
//! the previous mesh's zone, so the later ones move it by a layer or two: they took the same
//! number of CG iterations within a few, and no block extraction or Galerkin product.
//!
//! On a mesh of one level the cycle is the Cholesky factor of the block alone, so it is an exact
//! solve only of the matrix it was built for: there every other active set rebuilds it, with the
//! eliminated dofs decoupled (`Level::decoupled`).
//!
//! **Rotated frames.** The contact solves take the two dofs of a contact vertex as its normal and
//! tangential components ([`super::active_set::Rotation`]). Given those frames
//! ([`MultigridSolver::set_rotation`]), a coarse vertex takes the frame of the fine vertex at its
//! position and the prolongation maps coarse to fine components through R_v R_wᵀ
//! (`frame_change`): it interpolates the Cartesian vector, and the Galerkin coarse operators are
//! those of the unrotated problem. Without it the component-wise prolongation mixes normal and
//! tangential components; the contact tables took 100–500 CG iterations, with it 16–102 (IV.14,
//! growing with the mesh), so the contact tables keep the direct solver
//! ([`crate::study::solver_of`]).
//!
//! **Stopping.** Iterate until ‖b − Ax‖₂ ≤ `relative`·‖b‖₂ on the free dofs (default
//! [`RELATIVE_TOLERANCE`] = 1e-13). The algebraic error then lies many orders below the
//! discretisation error of every table, but that is not what sets the tolerance: the marking
//! treats indicators within a relative 1e-10 of the cut as tied, and an algebraic error shifts
//! the indicators of cells that are equal by symmetry apart. At 1e-12 the last marking of
//! Table IV.36 (cycle 6) refined 3 cells fewer than with the direct solver; at 1e-13 every
//! Reynolds table keeps the direct solver's meshes. A step of an active-set iteration, whose
//! solution only decides the next active set ([`Accuracy::ActiveSetStep`]), stops at
//! [`STEP_TOLERANCE`] = 1e-10; the final active set is confirmed by a solve at the full
//! tolerance ([`super::active_set`], *Inexact steps*).
//! Every operation is sequential or row-parallel with a fixed order of summation, so the result
//! does not depend on the number of threads.

use std::cell::RefCell;
use std::ops::Range;
use std::sync::Arc;

use rayon::prelude::*;

use super::krylov::{conjugate_gradient_with, CgError, Preconditioner, Stopping, VectorOps};
use super::solver::Accuracy;
use super::{split_by_offsets, transpose, CholeskyFactor, Csc, SolveError};

/// The prolongation from the vertices of one level mesh to those of the next finer kept one
/// ([`crate::fe::hierarchy`]): row `v` (a fine vertex) lists coarse vertices and weights; hanging
/// fine vertices have empty rows.
#[derive(Clone, Debug)]
pub struct Transfer {
    pub n_coarse: usize,
    pub row_ptr: Vec<usize>,
    pub cols: Vec<u32>,
    pub weights: Vec<f64>,
    /// The fine vertex at the position of each coarse vertex.
    pub fine_of_coarse: Vec<u32>,
    /// Whether each coarse vertex is hanging on its level.
    pub coarse_hanging: Vec<bool>,
}

impl Transfer {
    /// The transfer to `n_fine` fine vertices from `n_coarse` coarse ones whose row `v` is what
    /// `row(v, out)` appends to `out` (sorted by coarse vertex), built in parallel over blocks
    /// of rows into place: no array of fixed-size rows per fine vertex, which at six entries
    /// per row had cost 104 B per vertex of short-lived memory.
    pub fn by_rows<F>(
        n_fine: usize,
        n_coarse: usize,
        row: F,
        fine_of_coarse: Vec<u32>,
        coarse_hanging: Vec<bool>,
    ) -> Transfer
    where
        F: Fn(usize, &mut Vec<(u32, f64)>) + Sync,
    {
        let (row_ptr, cols, weights) = Sparse::parts_by_rows(n_fine, row);
        Transfer {
            n_coarse,
            row_ptr,
            cols,
            weights,
            fine_of_coarse,
            coarse_hanging,
        }
    }
}

/// The prolongations of a mesh's level hierarchy, coarsest first; the last one ends at the
/// vertices of the mesh itself.
#[derive(Clone, Debug, Default)]
pub struct VertexHierarchy {
    pub transfers: Vec<Transfer>,
}

impl VertexHierarchy {
    /// Number of vertices of each level, coarsest first (the finest last).
    pub fn level_sizes(&self) -> Vec<usize> {
        let mut sizes: Vec<usize> = self.transfers.iter().map(|t| t.n_coarse).collect();
        if let Some(t) = self.transfers.last() {
            sizes.push(t.row_ptr.len() - 1);
        }
        sizes
    }
}

/// A sparse matrix in compressed rows with sorted columns (a level matrix in full symmetric
/// storage, or a prolongation), its values in double precision (the default: the block of the
/// assembled matrix, the prolongations and Galerkin products as built) or in single precision
/// (the copies a V-cycle applies, module docs, *Precision*).
///
/// The structure (`row_ptr`, `cols`) is shared: a copy in single precision of a matrix has the
/// structure of the original, not a copy of it.
#[derive(Clone, Debug, Default)]
struct Sparse<T = f64> {
    n_cols: usize,
    row_ptr: Arc<Vec<usize>>,
    cols: Arc<Vec<u32>>,
    vals: Vec<T>,
}

/// The rows of one parallel task: where each row ends in the entries, and the entries.
type RowBlock = (Vec<usize>, Vec<(u32, f64)>);

/// Rows per parallel task when building a [`Sparse`] row by row, and the fewest per task of a
/// product (a coarse level's product runs on the calling thread instead of waking another for
/// microseconds of work).
const ROWS_PER_TASK: usize = 4096;

/// Rows per block of the hybrid Gauss–Seidel smoother (module docs): a fixed size, so that the
/// smoother, and every result, is the same whatever the number of threads; levels of fewer rows
/// are smoothed by plain Gauss–Seidel.
const SMOOTHING_BLOCK: usize = 32768;

/// A [`Sparse`] matrix as its loops read it: slices of its row pointers, columns and values
/// (one look-up of the shared structure per loop, not per row).
#[derive(Clone, Copy)]
struct Rows<'a, T> {
    row_ptr: &'a [usize],
    cols: &'a [u32],
    vals: &'a [T],
}

impl<'a, T> Rows<'a, T> {
    #[inline]
    fn row(&self, i: usize) -> (&'a [u32], &'a [T]) {
        let r = self.row_ptr[i]..self.row_ptr[i + 1];
        (&self.cols[r.clone()], &self.vals[r])
    }
}

impl<T: Copy + Into<f64> + Send + Sync> Sparse<T> {
    fn n_rows(&self) -> usize {
        self.row_ptr.len() - 1
    }

    fn rows(&self) -> Rows<'_, T> {
        Rows {
            row_ptr: &self.row_ptr,
            cols: &self.cols,
            vals: &self.vals,
        }
    }

    fn row(&self, i: usize) -> (&[u32], &[T]) {
        self.rows().row(i)
    }

    /// Σ_j a_ij x_j over the entries of `cols`, `vals` (a row or part of one), in double
    /// precision whatever the values are stored in.
    #[inline]
    fn dot(cols: &[u32], vals: &[T], x: &[f64]) -> f64 {
        let mut s = 0.0;
        for (&j, &a) in cols.iter().zip(vals) {
            s += a.into() * x[j as usize];
        }
        s
    }

    /// y = A x, rows in parallel, each summed in order.
    fn multiply_into(&self, x: &[f64], y: &mut [f64]) {
        self.multiply_masked(x, y, None);
    }

    /// y = A x with the masked rows of y set to zero.
    fn multiply_masked(&self, x: &[f64], y: &mut [f64], mask: Mask) {
        self.each_row(y, |i, y, (c, v)| {
            *y = if is_masked(mask, i) {
                0.0
            } else {
                Self::dot(c, v, x)
            };
        });
    }

    /// y += A x on the rows that are not masked.
    fn add_product_masked(&self, x: &[f64], y: &mut [f64], mask: Mask) {
        self.each_row(y, |i, y, (c, v)| {
            if !is_masked(mask, i) {
                *y += Self::dot(c, v, x);
            }
        });
    }

    /// `update(i, y_i, row i)` for every row in parallel, at least [`ROWS_PER_TASK`] rows per
    /// task (the products of the coarse levels stay on the calling thread).
    fn each_row(&self, y: &mut [f64], update: impl Fn(usize, &mut f64, (&[u32], &[T])) + Sync) {
        let a = self.rows();
        y.par_iter_mut()
            .with_min_len(ROWS_PER_TASK)
            .enumerate()
            .for_each(|(i, y)| update(i, y, a.row(i)));
    }

    /// Position of the diagonal entry of each row (every row has one).
    fn diagonal_positions(&self) -> Vec<usize> {
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
    fn new(n_cols: usize, row_ptr: Vec<usize>, cols: Vec<u32>, vals: Vec<f64>) -> Sparse {
        Sparse {
            n_cols,
            row_ptr: Arc::new(row_ptr),
            cols: Arc::new(cols),
            vals,
        }
    }

    /// The matrix with `n_rows` rows whose row `i` is what `row(i, out)` appends to `out`
    /// (sorted by column), built in parallel over blocks of rows.
    fn by_rows<F>(n_rows: usize, n_cols: usize, row: F) -> Sparse
    where
        F: Fn(usize, &mut Vec<(u32, f64)>) + Sync,
    {
        let (row_ptr, cols, vals) = Sparse::parts_by_rows(n_rows, row);
        Sparse::new(n_cols, row_ptr, cols, vals)
    }

    /// The row pointers, columns and values of [`Sparse::by_rows`].
    fn parts_by_rows<F>(n_rows: usize, row: F) -> (Vec<usize>, Vec<u32>, Vec<f64>)
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
    fn per_task<'a>(
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
    fn by_counted_rows<L, F>(n_rows: usize, n_cols: usize, len: L, fill: F) -> Sparse
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
    fn single(&self) -> Sparse<f32> {
        Sparse {
            n_cols: self.n_cols,
            row_ptr: Arc::clone(&self.row_ptr),
            cols: Arc::clone(&self.cols),
            vals: self.vals.par_iter().map(|&v| v as f32).collect(),
        }
    }

    fn transpose(&self) -> Sparse {
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
    fn galerkin(a: &Sparse, p: &Sparse, pt: &Sparse) -> Sparse {
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
    fn decoupled(&self, kept: &[bool]) -> Sparse {
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

/// One level of a V-cycle: its matrix, and the prolongation from the next coarser level, in
/// single precision (module docs, *Precision*).
struct Level {
    a: Sparse<f32>,
    /// Position of each row's diagonal entry: the entries before it are the strictly lower
    /// part of the row, those after it the strictly upper part.
    diag: Vec<usize>,
    /// 1/a_ii of the matrix in double precision.
    inverse_diagonal: Vec<f64>,
    /// P and Pᵀ from the next coarser level (none on the coarsest).
    p: Option<(Sparse<f32>, Sparse<f32>)>,
}

impl Level {
    /// The level of the matrix `a` with the prolongation and restriction `p` (as built, in
    /// double precision).
    fn new(a: &Sparse, p: Option<(&Sparse, &Sparse)>) -> Level {
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
    fn first_in_block(&self, a: Rows<'_, f32>, i: usize, start: usize) -> usize {
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
    fn forward_sweep_from_zero(&self, r: &[f64], z: &mut [f64], residual: &mut [f64], mask: Mask) {
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
    fn backward_sweep(&self, r: &[f64], z: &mut [f64], before: &mut [f64], mask: Mask) {
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
fn by_blocks(
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

/// Whether row `i` is masked.
#[inline]
fn is_masked(mask: Mask, i: usize) -> bool {
    mask.is_some_and(|m| m[i])
}

/// The rows of the finest level that one solve eliminates on top of those it was built for
/// (`true`), or `None` when there are none ([`Prepared`]). Masked rows and columns drop out of
/// the CG operator and of the finest level of the V-cycle: the smoother leaves them at zero,
/// their residual is not restricted and the prolongated correction is cut off there. The cycle is
/// then S̄ + (I − SᵀA) Π C Π (I − A S) with S̄ the symmetrised smoother of the masked block and C
/// the coarse correction — symmetric and positive definite, a valid CG preconditioner whatever
/// the mask; it is a good one while the masked rows are a thin layer (module docs).
type Mask<'a> = Option<&'a [bool]>;

/// The V(1,1)-cycle of the module docs for the free dofs of one solve.
struct VCycle {
    /// Coarsest first.
    levels: Vec<Level>,
    coarse: RefCell<Option<CholeskyFactor>>,
    /// The vectors of one application, kept across the iterations of a solve.
    work: RefCell<Vec<Work>>,
}

/// The vectors of a V-cycle on one level: its right-hand side and correction, the residual after
/// the forward sweep, the correction before the backward sweep (all of the level's size).
struct Work {
    r: Vec<f64>,
    z: Vec<f64>,
    residual: Vec<f64>,
    before: Vec<f64>,
}

impl Work {
    /// The vectors of a level of `n` rows; on the finest level (`top`) r and z are those of the
    /// application ([`VCycle::cycle`]).
    fn new(n: usize, top: bool) -> Work {
        let own = if top { 0 } else { n };
        Work {
            r: vec![0.0; own],
            z: vec![0.0; own],
            residual: vec![0.0; n],
            before: vec![0.0; n],
        }
    }
}

impl VCycle {
    /// The cycle of the block `fine` of the dofs `rows` (by dof, `true` in the block); the
    /// coarse levels are those of the dofs `coarse_free` (a subset of `rows`): the prolongation
    /// has empty rows at the other dofs of the block.
    fn build(
        hierarchy: &VertexHierarchy,
        n_components: usize,
        frames: &[Frame],
        fine: &Sparse,
        rows: &[bool],
        coarse_free: &[bool],
    ) -> Result<VCycle, SolveError> {
        let nc = n_components;
        let mut levels_fine_first = Vec::new();
        // The Galerkin product of the level above (none yet: the block itself).
        let mut coarse_a: Option<Sparse> = None;
        let mut free = coarse_free.to_vec();
        let mut rows = rows.to_vec();
        let mut frames = frames.to_vec();
        for t in hierarchy.transfers.iter().rev() {
            let a = coarse_a.as_ref().unwrap_or(fine);
            // A coarse vertex has the frame of the fine vertex at its position.
            let coarse_frames: Vec<Frame> = if frames.is_empty() {
                Vec::new()
            } else {
                t.fine_of_coarse
                    .iter()
                    .map(|&v| frames[v as usize])
                    .collect()
            };
            let coarse_free: Vec<bool> = (0..t.n_coarse * nc)
                .map(|d| {
                    let (w, c) = (d / nc, d % nc);
                    !t.coarse_hanging[w] && free[t.fine_of_coarse[w] as usize * nc + c]
                })
                .collect();
            let coarse_index = numbering(&coarse_free);
            let n_coarse_free = coarse_free.iter().filter(|&&f| f).count();
            let fine_dofs: Vec<usize> = (0..rows.len()).filter(|&d| rows[d]).collect();
            let prolongation = Prolongation {
                transfer: t,
                n_components: nc,
                fine_frames: &frames,
                coarse_frames: &coarse_frames,
                coarse_index: &coarse_index,
            };
            // Row i: the free fine dof fine_dofs[i] from the coarse dofs; empty where the dof
            // is not free in the solve the levels are built for.
            let row = |i: usize, emit: &mut dyn FnMut(u32, f64)| {
                let d = fine_dofs[i];
                if free[d] {
                    prolongation.row(d, emit);
                }
            };
            let p = Sparse::by_counted_rows(
                fine_dofs.len(),
                n_coarse_free,
                |i| {
                    let mut len = 0;
                    row(i, &mut |_, _| len += 1);
                    len
                },
                |i, cols, vals| {
                    let mut k = 0;
                    row(i, &mut |j, w| {
                        (cols[k], vals[k]) = (j, w);
                        k += 1;
                    });
                },
            );
            let pt = p.transpose();
            let next = Sparse::galerkin(a, &p, &pt);
            levels_fine_first.push(Level::new(a, Some((&p, &pt))));
            coarse_a = Some(next);
            rows.clone_from(&coarse_free);
            free = coarse_free;
            frames = coarse_frames;
        }
        let a = coarse_a.as_ref().unwrap_or(fine);
        let coarsest = Level::new(a, None);
        // On a mesh of one level the coarsest level is the block itself, which keeps the dofs
        // the solve eliminates on top of the constraints: the factor is of the solve's own
        // matrix, those dofs decoupled (their rows and columns cut to the diagonal).
        let coarse = if rows.iter().zip(&free).any(|(&r, &f)| r && !f) {
            let kept: Vec<bool> = rows
                .iter()
                .zip(&free)
                .filter(|(&r, _)| r)
                .map(|(_, &f)| f)
                .collect();
            let decoupled = a.decoupled(&kept);
            factor(&decoupled, &decoupled.diagonal_positions())?
        } else {
            factor(a, &coarsest.diag)?
        };
        levels_fine_first.push(coarsest);
        levels_fine_first.reverse();
        let top = levels_fine_first.len() - 1;
        let work = levels_fine_first
            .iter()
            .enumerate()
            .map(|(k, l)| Work::new(l.a.n_rows(), k == top))
            .collect();
        Ok(VCycle {
            levels: levels_fine_first,
            coarse: RefCell::new(coarse),
            work: RefCell::new(work),
        })
    }

    /// z = V(r) on level `k` with `work` the vectors of levels 0..=k: r in `work[k].r` and z into
    /// `work[k].z`, or on the finest level the given `top` (r, z); `mask` applies to the rows of
    /// that level (the finest).
    fn cycle(&self, k: usize, work: &mut [Work], top: Option<(&[f64], &mut [f64])>, mask: Mask) {
        let level = &self.levels[k];
        let (coarser, this) = work.split_at_mut(k);
        let Work {
            r: own_r,
            z: own_z,
            residual,
            before,
        } = &mut this[0];
        let (r, z): (&[f64], &mut [f64]) = match top {
            Some((r, z)) => (r, z),
            None => (own_r, own_z),
        };
        let Some((p, pt)) = &level.p else {
            z.copy_from_slice(r);
            if let Some(f) = self.coarse.borrow_mut().as_mut() {
                f.solve_in_place(z);
            }
            for (i, z) in z.iter_mut().enumerate() {
                if is_masked(mask, i) {
                    *z = 0.0;
                }
            }
            return;
        };
        if mask.is_some() {
            // The sweep reads only entries it wrote before, but for masked rows.
            z.fill(0.0);
        }
        level.forward_sweep_from_zero(r, z, residual, mask);
        pt.multiply_into(residual, &mut coarser[k - 1].r);
        self.cycle(k - 1, coarser, None, None);
        p.add_product_masked(&coarser[k - 1].z, z, mask);
        level.backward_sweep(r, z, before, mask);
    }
}

/// The V-cycle of a block with some of its rows masked ([`Mask`]).
struct MaskedCycle<'a> {
    cycle: &'a VCycle,
    mask: Mask<'a>,
}

impl Preconditioner for MaskedCycle<'_> {
    fn apply(&self, r: &[f64], z: &mut [f64]) {
        let top = self.cycle.levels.len() - 1;
        let mut work = self.cycle.work.borrow_mut();
        self.cycle.cycle(top, &mut work, Some((r, z)), self.mask);
    }
}

/// The frame of a vertex's two dofs: `Some(n)` where they are its normal and tangential
/// components (n·u, t·u with t = (−n₂, n₁)), as the contact solves rotate them
/// ([`super::active_set::Rotation`]); `None` for Cartesian components.
pub type Frame = Option<[f64; 2]>;

/// Entry (c, c′) of R_v R_wᵀ, which takes the components of a vector in the frame of a coarse
/// vertex w (c′) to those in the frame of a fine vertex v (c); R is the rotation (n; t) of a
/// rotated vertex and the identity of a Cartesian one. With it the prolongation interpolates the
/// Cartesian vector, whatever the frames, so that the coarse spaces are those of the unrotated
/// problem (the Galerkin product of the rotated matrix Rᵀ… is that of the Cartesian one in the
/// rotated frames).
fn frame_change(fine: Frame, coarse: Frame, c: usize, c2: usize) -> f64 {
    let rotation = |f: Frame| match f {
        Some(n) => [[n[0], n[1]], [-n[1], n[0]]],
        None => [[1.0, 0.0], [0.0, 1.0]],
    };
    let (rv, rw) = (rotation(fine), rotation(coarse));
    rv[c][0] * rw[c2][0] + rv[c][1] * rw[c2][1]
}

/// The prolongation of the dofs of one level mesh from those of the next coarser kept one
/// ([`Transfer`] for each component, through the frames of rotated vertices).
struct Prolongation<'a> {
    transfer: &'a Transfer,
    n_components: usize,
    /// The frame of each fine and of each coarse vertex (empty: all Cartesian).
    fine_frames: &'a [Frame],
    coarse_frames: &'a [Frame],
    /// The number of each coarse dof among the coarse level's free dofs (`usize::MAX`: none).
    coarse_index: &'a [usize],
}

impl Prolongation<'_> {
    /// The entries (coarse free dof, weight) of fine dof `d`'s row, in order.
    fn row(&self, d: usize, emit: &mut dyn FnMut(u32, f64)) {
        let (nc, t) = (self.n_components, self.transfer);
        let (v, c) = (d / nc, d % nc);
        let fine_frame = self.fine_frames.get(v).copied().flatten();
        for k in t.row_ptr[v]..t.row_ptr[v + 1] {
            let w = t.cols[k] as usize;
            let coarse_frame = self.coarse_frames.get(w).copied().flatten();
            if fine_frame.is_none() && coarse_frame.is_none() {
                let j = self.coarse_index[w * nc + c];
                if j != usize::MAX {
                    emit(j as u32, t.weights[k]);
                }
                continue;
            }
            for c2 in 0..nc {
                let weight = t.weights[k] * frame_change(fine_frame, coarse_frame, c, c2);
                let j = self.coarse_index[w * nc + c2];
                if weight != 0.0 && j != usize::MAX {
                    emit(j as u32, weight);
                }
            }
        }
    }
}

/// Consecutive numbers for the `true` entries, `usize::MAX` elsewhere.
fn numbering(free: &[bool]) -> Vec<usize> {
    let mut next = 0;
    free.iter()
        .map(|&f| {
            if f {
                next += 1;
                next - 1
            } else {
                usize::MAX
            }
        })
        .collect()
}

/// The Cholesky factor of the coarsest matrix `a` with the diagonal positions `diag` (none for
/// an empty level), in double precision.
fn factor(a: &Sparse, diag: &[usize]) -> Result<Option<CholeskyFactor>, SolveError> {
    if a.n_rows() == 0 {
        return Ok(None);
    }
    let csc = Csc {
        col_ptr: &a.row_ptr,
        row_idx: &a.cols,
        diag,
        values: &a.vals,
    };
    CholeskyFactor::new(csc, None).map(Some)
}

/// The block of a symmetric matrix on the dofs `rows` (`true` in the block).
#[derive(Clone, Copy)]
struct BlockOf<'a> {
    matrix: Csc<'a>,
    rows: &'a [bool],
}

impl BlockOf<'_> {
    /// The positions of the entries of dof `d`'s row (= column) inside the block, in order.
    fn entries(&self, d: usize) -> impl Iterator<Item = usize> + '_ {
        let (matrix, rows) = (self.matrix, self.rows);
        (matrix.col_ptr[d]..matrix.col_ptr[d + 1])
            .filter(move |&p| rows[matrix.row_idx[p] as usize])
    }
}

/// The operator of one matrix made ready for its solves (module docs, *Active sets*): the block
/// of the dofs that every solve leaves free and its V-cycle, whose coarse levels are those of the
/// dofs free in the first solve.
struct Prepared {
    /// The address and length of the pattern of the matrix it was built from (its values are
    /// those of the block, compared bitwise before reuse).
    pattern: (usize, usize),
    /// By dof: `true` in the block (not eliminated by the constraints).
    rows: Vec<bool>,
    /// Block index → dof.
    dofs: Vec<usize>,
    /// By dof: free in the solve the coarse levels were built for.
    coarse_free: Vec<bool>,
    /// The block of the matrix: the operator of CG.
    block: Sparse,
    cycle: VCycle,
}

/// The coarse levels are rebuilt when a solve masks more than this fraction of the block
/// differently from the solve they were built for (module docs, *Active sets*).
const MAX_MASK_CHANGE: f64 = 0.02;

impl Prepared {
    /// The block of `rows` of `matrix` with coarse levels for the dofs `free` (⊆ `rows`).
    fn build(
        matrix: Csc<'_>,
        rows: Vec<bool>,
        free: Vec<bool>,
        hierarchy: &VertexHierarchy,
        n_components: usize,
        frames: &[Frame],
    ) -> Result<Prepared, SolveError> {
        let index = numbering(&rows);
        let dofs: Vec<usize> = (0..rows.len()).filter(|&d| rows[d]).collect();
        let block = BlockOf {
            matrix,
            rows: &rows,
        };
        let a = Sparse::by_counted_rows(
            dofs.len(),
            dofs.len(),
            |i| block.entries(dofs[i]).count(),
            |i, cols, vals| {
                for ((c, v), p) in cols.iter_mut().zip(vals).zip(block.entries(dofs[i])) {
                    *c = index[matrix.row_idx[p] as usize] as u32;
                    *v = matrix.values[p];
                }
            },
        );
        if let Some(i) = a.vals.iter().position(|v| !v.is_finite()) {
            let row = a.row_ptr.partition_point(|&s| s <= i) - 1;
            return Err(SolveError::NonFiniteData(dofs[row]));
        }
        let cycle = VCycle::build(hierarchy, n_components, frames, &a, &rows, &free)?;
        Ok(Prepared {
            pattern: Prepared::pattern_of(matrix),
            coarse_free: free,
            rows,
            dofs,
            block: a,
            cycle,
        })
    }

    fn pattern_of(matrix: Csc<'_>) -> (usize, usize) {
        (matrix.row_idx.as_ptr() as usize, matrix.row_idx.len())
    }

    /// Whether this was built for `matrix` with the block `rows`, and a solve that leaves the
    /// dofs `solved` free is close enough to the one its coarse levels were built for.
    fn fits(&self, matrix: Csc<'_>, rows: &[bool], solved: &[bool]) -> bool {
        let same_matrix = self.pattern == Prepared::pattern_of(matrix) && self.rows == rows && {
            // The solves read the block from here and the rest of the matrix afresh.
            let (block, kept) = (&self.block, BlockOf { matrix, rows });
            self.dofs.par_iter().enumerate().all(|(i, &d)| {
                let (_, vals) = block.row(i);
                let mut entries = kept.entries(d);
                vals.iter().all(|v| {
                    entries
                        .next()
                        .is_some_and(|p| matrix.values[p].to_bits() == v.to_bits())
                }) && entries.next().is_none()
            })
        };
        if !same_matrix {
            return false;
        }
        let changed = self
            .dofs
            .iter()
            .filter(|&&d| solved[d] != self.coarse_free[d])
            .count();
        // A cycle of one level is an exact solve of the matrix it was built for: any other
        // mask needs its own.
        let single_level = self.cycle.levels.len() == 1;
        changed == 0
            || (!single_level && changed as f64 <= MAX_MASK_CHANGE * self.dofs.len() as f64)
    }
}

/// Solves the systems of one mesh at a time by multigrid-preconditioned CG (module docs):
/// [`MultigridSolver::set_hierarchy`] per mesh, then any number of solves, each starting from the
/// guess set by [`MultigridSolver::set_guess`] or else from the previous solution of the same
/// mesh (the previous iterate of an active-set iteration).
pub struct MultigridSolver {
    hierarchy: Option<VertexHierarchy>,
    n_components: usize,
    guess: Option<Vec<f64>>,
    /// The vertices whose dofs are in a rotated frame, with their normals
    /// ([`MultigridSolver::set_rotation`]).
    rotated: Vec<(u32, [f64; 2])>,
    prepared: Option<Box<Prepared>>,
    pub relative_tolerance: f64,
    /// The relative residual of a step of an active-set iteration ([`Accuracy::ActiveSetStep`],
    /// module docs, *Stopping*).
    pub step_tolerance: f64,
    pub max_iterations: usize,
    /// CG iterations of each solve since the last [`MultigridSolver::take_iterations`].
    iterations: Vec<usize>,
}

/// Default relative residual of the multigrid solves (module docs).
pub const RELATIVE_TOLERANCE: f64 = 1e-13;

/// Default relative residual of a step of an active-set iteration (module docs, *Stopping*).
pub const STEP_TOLERANCE: f64 = 1e-10;

impl Default for MultigridSolver {
    fn default() -> Self {
        MultigridSolver {
            hierarchy: None,
            n_components: 1,
            guess: None,
            rotated: Vec::new(),
            prepared: None,
            relative_tolerance: RELATIVE_TOLERANCE,
            step_tolerance: STEP_TOLERANCE,
            max_iterations: 500,
            iterations: Vec::new(),
        }
    }
}

impl MultigridSolver {
    /// The level hierarchy of a new mesh (its dofs have `n_components` per vertex); forgets
    /// the previous mesh's solution and operator.
    pub fn set_hierarchy(&mut self, hierarchy: VertexHierarchy, n_components: usize) {
        self.hierarchy = Some(hierarchy);
        self.n_components = n_components;
        self.guess = None;
        self.rotated.clear();
        self.prepared = None;
    }

    /// The vertices whose two dofs the next solves take in their normal and tangential frame
    /// ([`Frame`]; the contact solves, [`super::active_set::Rotation`]), the others Cartesian.
    /// The prolongation then rotates (`frame_change`); a new rotation rebuilds the levels.
    pub fn set_rotation(&mut self, rotated: &[(u32, [f64; 2])]) {
        let same = self.rotated.len() == rotated.len()
            && self.rotated.iter().zip(rotated).all(|(a, b)| {
                a.0 == b.0
                    && a.1[0].to_bits() == b.1[0].to_bits()
                    && a.1[1].to_bits() == b.1[1].to_bits()
            });
        if !same {
            self.rotated = rotated.to_vec();
            self.prepared = None;
        }
    }

    /// The initial guess of the next solve (e.g. the previous mesh's solution interpolated).
    pub fn set_guess(&mut self, guess: Vec<f64>) {
        self.guess = Some(guess);
    }

    /// Drop the hierarchy, the operator and the guess once the mesh's last solve is done.
    pub fn release_pattern(&mut self) {
        self.hierarchy = None;
        self.guess = None;
        self.rotated.clear();
        self.prepared = None;
    }

    /// The CG iteration counts of the solves since the last call.
    pub fn take_iterations(&mut self) -> Vec<usize> {
        std::mem::take(&mut self.iterations)
    }

    /// Solve A x = b where the dofs in `eliminated` take the given values (as
    /// [`super::DirectSolver::solve`]); the first `always` entries of `eliminated` are
    /// eliminated in every solve of this matrix (the constraints), the rest in this one only
    /// (the active bounds of an active-set iteration): the block and the V-cycle are kept across
    /// such solves, the rest masked (module docs, *Active sets*). [`super::SolveConstrained`]
    /// gives the plain `solve`.
    pub fn solve_overlay(
        &mut self,
        matrix: Csc<'_>,
        rhs: &[f64],
        eliminated: &[(usize, f64)],
        always: usize,
        accuracy: Accuracy,
    ) -> Result<Vec<f64>, SolveError> {
        let n = matrix.n();
        SolveError::check_data(rhs)?;
        let mut rows = vec![true; n];
        for &(d, _) in &eliminated[..always] {
            rows[d] = false;
        }
        let mut x = vec![0.0; n];
        let mut solved = rows.clone();
        for &(d, v) in eliminated {
            x[d] = v;
            solved[d] = false;
        }
        let reuse = self
            .prepared
            .as_ref()
            .is_some_and(|p| p.fits(matrix, &rows, &solved));
        if !reuse {
            self.prepared = None;
            // Without a hierarchy (a mesh of one level) the coarsest level is the mesh itself.
            let single_level = VertexHierarchy::default();
            let hierarchy = self.hierarchy.as_ref().unwrap_or(&single_level);
            let mut frames: Vec<Frame> = Vec::new();
            if !self.rotated.is_empty() {
                frames.resize(n / self.n_components, None);
                for &(v, normal) in &self.rotated {
                    frames[v as usize] = Some(normal);
                }
            }
            self.prepared = Some(Box::new(Prepared::build(
                matrix,
                rows,
                solved.clone(),
                hierarchy,
                self.n_components,
                &frames,
            )?));
        }
        let prepared = self.prepared.as_ref().expect("prepared above");
        let dofs = &prepared.dofs;
        let masked: Vec<bool> = dofs.iter().map(|&d| !solved[d]).collect();
        let mask: Mask = masked.contains(&true).then_some(&masked[..]);
        // The load with the eliminated values moved to the right (zero on masked dofs).
        let b: Vec<f64> = dofs
            .par_iter()
            .map(|&d| {
                if !solved[d] {
                    return 0.0;
                }
                let eliminated_part: f64 = (matrix.col_ptr[d]..matrix.col_ptr[d + 1])
                    .filter(|&p| !solved[matrix.row_idx[p] as usize])
                    .map(|p| matrix.values[p] * x[matrix.row_idx[p] as usize])
                    .sum();
                rhs[d] - eliminated_part
            })
            .collect();
        let mut xf: Vec<f64> = match self.guess.as_ref().filter(|g| g.len() == n) {
            Some(g) => dofs
                .iter()
                .map(|&d| if solved[d] { g[d] } else { 0.0 })
                .collect(),
            None => vec![0.0; dofs.len()],
        };
        let block = &prepared.block;
        let stopping = Stopping {
            relative: match accuracy {
                Accuracy::Full => self.relative_tolerance,
                Accuracy::ActiveSetStep => self.step_tolerance,
            },
            absolute: 0.0,
            max_iterations: self.max_iterations,
        };
        let preconditioner = MaskedCycle {
            cycle: &prepared.cycle,
            mask,
        };
        let report = conjugate_gradient_with(
            VectorOps::Chunked,
            |v, out| block.multiply_masked(v, out, mask),
            &b,
            &mut xf,
            &preconditioner,
            stopping,
        )
        .map_err(|e| match e {
            CgError::NonFinite(iteration) => SolveError::IterativeNonFinite(iteration),
            e => SolveError::Iterative(e.to_string()),
        })?;
        self.iterations.push(report.iterations);
        for (&d, &v) in dofs.iter().zip(&xf) {
            if solved[d] {
                x[d] = v;
            }
        }
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            return Err(SolveError::NonFinite(i));
        }
        self.guess = Some(x.clone());
        Ok(x)
    }
}
