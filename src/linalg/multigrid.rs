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
//! **Stopping.** Iterate until ‖b − Ax‖₂ ≤ `relative`·‖b‖₂ on the free dofs (default
//! [`RELATIVE_TOLERANCE`] = 1e-13). The algebraic error then lies many orders below the
//! discretisation error of every table, but that is not what sets the tolerance: the marking
//! treats indicators within a relative 1e-10 of the cut as tied, and an algebraic error shifts
//! the indicators of cells that are equal by symmetry apart. At 1e-12 the last marking of
//! Table IV.36 (cycle 6) refined 3 cells fewer than with the direct solver; at 1e-13 every
//! Reynolds table keeps the direct solver's meshes.
//! Every operation is sequential or row-parallel with a fixed order of summation, so the result
//! does not depend on the number of threads.

use std::cell::RefCell;

use rayon::prelude::*;

use super::krylov::{conjugate_gradient, CgError, Preconditioner, Stopping};
use super::{CholeskyFactor, Csc, SolveError};

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
/// storage, or a prolongation).
#[derive(Clone, Debug, Default)]
struct Sparse {
    n_cols: usize,
    row_ptr: Vec<usize>,
    cols: Vec<u32>,
    vals: Vec<f64>,
}

/// The rows of one parallel task: where each row ends in the entries, and the entries.
type RowBlock = (Vec<usize>, Vec<(u32, f64)>);

/// Rows per parallel task when building a [`Sparse`] row by row.
const ROWS_PER_TASK: usize = 4096;

impl Sparse {
    fn n_rows(&self) -> usize {
        self.row_ptr.len() - 1
    }

    fn row(&self, i: usize) -> (&[u32], &[f64]) {
        let r = self.row_ptr[i]..self.row_ptr[i + 1];
        (&self.cols[r.clone()], &self.vals[r])
    }

    /// Σ_j a_ij x_j over the entries of `cols`, `vals` (a row or part of one).
    #[inline]
    fn dot(cols: &[u32], vals: &[f64], x: &[f64]) -> f64 {
        let mut s = 0.0;
        for (&j, &a) in cols.iter().zip(vals) {
            s += a * x[j as usize];
        }
        s
    }

    /// The matrix with `n_rows` rows whose row `i` is what `row(i, out)` appends to `out`
    /// (sorted by column), built in parallel over blocks of rows.
    fn by_rows<F>(n_rows: usize, n_cols: usize, row: F) -> Sparse
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
        let nnz = blocks.iter().map(|b| b.1.len()).sum();
        let mut m = Sparse {
            n_cols,
            row_ptr: Vec::with_capacity(n_rows + 1),
            cols: Vec::with_capacity(nnz),
            vals: Vec::with_capacity(nnz),
        };
        m.row_ptr.push(0);
        for (ends, entries) in blocks {
            let base = m.cols.len();
            m.row_ptr.extend(ends.into_iter().map(|e| base + e));
            for (j, v) in entries {
                m.cols.push(j);
                m.vals.push(v);
            }
        }
        m
    }

    /// y = A x, rows in parallel, each summed in order.
    fn multiply_into(&self, x: &[f64], y: &mut [f64]) {
        y.par_iter_mut().enumerate().for_each(|(i, y)| {
            let (c, v) = self.row(i);
            *y = Sparse::dot(c, v, x);
        });
    }

    fn transpose(&self) -> Sparse {
        let mut count = vec![0usize; self.n_cols + 1];
        for &j in &self.cols {
            count[j as usize + 1] += 1;
        }
        for j in 0..self.n_cols {
            count[j + 1] += count[j];
        }
        let row_ptr = count.clone();
        let mut next = count;
        let mut cols = vec![0; self.cols.len()];
        let mut vals = vec![0.0; self.vals.len()];
        for i in 0..self.n_rows() {
            let (c, v) = self.row(i);
            for (&j, &a) in c.iter().zip(v) {
                let j = j as usize;
                cols[next[j]] = i as u32;
                vals[next[j]] = a;
                next[j] += 1;
            }
        }
        Sparse {
            n_cols: self.n_rows(),
            row_ptr,
            cols,
            vals,
        }
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

    /// Position of the diagonal entry of each row (every row has one).
    fn diagonal_positions(&self) -> Vec<usize> {
        (0..self.n_rows())
            .map(|i| {
                let (c, _) = self.row(i);
                self.row_ptr[i] + c.partition_point(|&j| (j as usize) < i)
            })
            .collect()
    }
}

/// One level of a V-cycle: its matrix, and the prolongation from the next coarser level.
struct Level {
    a: Sparse,
    /// Position of each row's diagonal entry: the entries before it are the strictly lower
    /// part of the row, those after it the strictly upper part.
    diag: Vec<usize>,
    inverse_diagonal: Vec<f64>,
    /// P and Pᵀ from the next coarser level (none on the coarsest).
    p: Option<(Sparse, Sparse)>,
}

impl Level {
    fn new(a: Sparse, p: Option<(Sparse, Sparse)>) -> Level {
        let diag = a.diagonal_positions();
        let inverse_diagonal = diag.iter().map(|&d| 1.0 / a.vals[d]).collect();
        Level {
            a,
            diag,
            inverse_diagonal,
            p,
        }
    }

    /// One forward Gauss–Seidel sweep for A z = r from z = 0 (only the lower part of each row
    /// meets a nonzero z), returning the residual r − A z, which is then minus the upper part
    /// of A times z.
    fn forward_sweep_from_zero(&self, r: &[f64], z: &mut [f64]) -> Vec<f64> {
        let a = &self.a;
        for i in 0..r.len() {
            let lower = a.row_ptr[i]..self.diag[i];
            let s = Sparse::dot(&a.cols[lower.clone()], &a.vals[lower], z);
            z[i] = (r[i] - s) * self.inverse_diagonal[i];
        }
        let mut residual = vec![0.0; r.len()];
        residual.par_iter_mut().enumerate().for_each(|(i, res)| {
            let upper = self.diag[i] + 1..a.row_ptr[i + 1];
            *res = -Sparse::dot(&a.cols[upper.clone()], &a.vals[upper], z);
        });
        residual
    }

    /// One backward Gauss–Seidel sweep for A z = r.
    fn backward_sweep(&self, r: &[f64], z: &mut [f64]) {
        for i in (0..r.len()).rev() {
            let (c, v) = self.a.row(i);
            let s = Sparse::dot(c, v, z);
            z[i] += (r[i] - s) * self.inverse_diagonal[i];
        }
    }
}

/// The V(1,1)-cycle of the module docs for the free dofs of one solve.
struct VCycle {
    /// Coarsest first.
    levels: Vec<Level>,
    coarse: RefCell<Option<CholeskyFactor>>,
}

impl VCycle {
    fn build(
        hierarchy: &VertexHierarchy,
        n_components: usize,
        fine: Sparse,
        fine_free: &[bool],
    ) -> Result<VCycle, SolveError> {
        let nc = n_components;
        let mut levels_fine_first = Vec::new();
        let mut a = fine;
        let mut free = fine_free.to_vec();
        for t in hierarchy.transfers.iter().rev() {
            let coarse_free: Vec<bool> = (0..t.n_coarse * nc)
                .map(|d| {
                    let (w, c) = (d / nc, d % nc);
                    !t.coarse_hanging[w] && free[t.fine_of_coarse[w] as usize * nc + c]
                })
                .collect();
            let coarse_index = numbering(&coarse_free);
            let n_coarse_free = coarse_free.iter().filter(|&&f| f).count();
            let fine_dofs: Vec<usize> = (0..free.len()).filter(|&d| free[d]).collect();
            let p = Sparse::by_rows(fine_dofs.len(), n_coarse_free, |i, out| {
                let (v, c) = (fine_dofs[i] / nc, fine_dofs[i] % nc);
                for k in t.row_ptr[v]..t.row_ptr[v + 1] {
                    let j = coarse_index[t.cols[k] as usize * nc + c];
                    if j != usize::MAX {
                        out.push((j as u32, t.weights[k]));
                    }
                }
            });
            let pt = p.transpose();
            let coarse_a = Sparse::galerkin(&a, &p, &pt);
            levels_fine_first.push(Level::new(a, Some((p, pt))));
            a = coarse_a;
            free = coarse_free;
        }
        let coarsest = Level::new(a, None);
        let coarse = factor(&coarsest)?;
        levels_fine_first.push(coarsest);
        levels_fine_first.reverse();
        Ok(VCycle {
            levels: levels_fine_first,
            coarse: RefCell::new(coarse),
        })
    }

    /// z = V(r) on level `k`.
    fn cycle(&self, k: usize, r: &[f64]) -> Vec<f64> {
        let level = &self.levels[k];
        let Some((p, pt)) = &level.p else {
            let mut z = r.to_vec();
            if let Some(f) = self.coarse.borrow_mut().as_mut() {
                f.solve_in_place(&mut z);
            }
            return z;
        };
        let mut z = vec![0.0; r.len()];
        let mut residual = level.forward_sweep_from_zero(r, &mut z);
        let mut coarse_r = vec![0.0; pt.n_rows()];
        pt.multiply_into(&residual, &mut coarse_r);
        let coarse_z = self.cycle(k - 1, &coarse_r);
        p.multiply_into(&coarse_z, &mut residual);
        for (z, c) in z.iter_mut().zip(&residual) {
            *z += c;
        }
        level.backward_sweep(r, &mut z);
        z
    }
}

impl Preconditioner for VCycle {
    fn apply(&self, r: &[f64], z: &mut [f64]) {
        let top = self.levels.len() - 1;
        z.copy_from_slice(&self.cycle(top, r));
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

/// The Cholesky factor of the coarsest matrix (none for an empty level).
fn factor(level: &Level) -> Result<Option<CholeskyFactor>, SolveError> {
    let a = &level.a;
    if a.n_rows() == 0 {
        return Ok(None);
    }
    let row_idx: Vec<usize> = a.cols.iter().map(|&j| j as usize).collect();
    let csc = Csc {
        col_ptr: &a.row_ptr,
        row_idx: &row_idx,
        diag: &level.diag,
        values: &a.vals,
    };
    CholeskyFactor::new(csc, None).map(Some)
}

/// Solves the systems of one mesh at a time by multigrid-preconditioned CG (module docs):
/// [`MultigridSolver::set_hierarchy`] per mesh, then any number of solves, each starting from the
/// guess set by [`MultigridSolver::set_guess`] or else from the previous solution of the same
/// mesh (the previous iterate of an active-set iteration).
pub struct MultigridSolver {
    hierarchy: Option<VertexHierarchy>,
    n_components: usize,
    guess: Option<Vec<f64>>,
    pub relative_tolerance: f64,
    pub max_iterations: usize,
    /// CG iterations of each solve since the last [`MultigridSolver::take_iterations`].
    iterations: Vec<usize>,
}

/// Default relative residual of the multigrid solves (module docs).
pub const RELATIVE_TOLERANCE: f64 = 1e-13;

impl Default for MultigridSolver {
    fn default() -> Self {
        MultigridSolver {
            hierarchy: None,
            n_components: 1,
            guess: None,
            relative_tolerance: RELATIVE_TOLERANCE,
            max_iterations: 500,
            iterations: Vec::new(),
        }
    }
}

impl MultigridSolver {
    /// The level hierarchy of a new mesh (its dofs have `n_components` per vertex); forgets
    /// the previous mesh's solution.
    pub fn set_hierarchy(&mut self, hierarchy: VertexHierarchy, n_components: usize) {
        self.hierarchy = Some(hierarchy);
        self.n_components = n_components;
        self.guess = None;
    }

    /// The initial guess of the next solve (e.g. the previous mesh's solution interpolated).
    pub fn set_guess(&mut self, guess: Vec<f64>) {
        self.guess = Some(guess);
    }

    /// Drop the hierarchy and the guess once the mesh's last solve is done.
    pub fn release_pattern(&mut self) {
        self.hierarchy = None;
        self.guess = None;
    }

    /// The CG iteration counts of the solves since the last call.
    pub fn take_iterations(&mut self) -> Vec<usize> {
        std::mem::take(&mut self.iterations)
    }

    /// Solve A x = b where the dofs in `eliminated` take the given values (as
    /// [`super::DirectSolver::solve`]).
    pub fn solve(
        &mut self,
        matrix: Csc<'_>,
        rhs: &[f64],
        eliminated: &[(usize, f64)],
    ) -> Result<Vec<f64>, SolveError> {
        let n = matrix.n();
        SolveError::check_data(rhs)?;
        let mut x = vec![0.0; n];
        let mut free = vec![true; n];
        for &(d, v) in eliminated {
            free[d] = false;
            x[d] = v;
        }
        let index = numbering(&free);
        let dofs: Vec<usize> = (0..n).filter(|&d| free[d]).collect();
        // The free block, and the load with the eliminated values moved to the right.
        let a = Sparse::by_rows(dofs.len(), dofs.len(), |i, out| {
            let d = dofs[i];
            for p in matrix.col_ptr[d]..matrix.col_ptr[d + 1] {
                let j = matrix.row_idx[p];
                if free[j] {
                    out.push((index[j] as u32, matrix.values[p]));
                }
            }
        });
        let b: Vec<f64> = dofs
            .par_iter()
            .map(|&d| {
                let eliminated_part: f64 = (matrix.col_ptr[d]..matrix.col_ptr[d + 1])
                    .filter(|&p| !free[matrix.row_idx[p]])
                    .map(|p| matrix.values[p] * x[matrix.row_idx[p]])
                    .sum();
                rhs[d] - eliminated_part
            })
            .collect();
        if let Some(i) = a.vals.iter().position(|v| !v.is_finite()) {
            let row = a.row_ptr.partition_point(|&s| s <= i) - 1;
            return Err(SolveError::NonFiniteData(dofs[row]));
        }
        let mut xf: Vec<f64> = match self.guess.as_ref().filter(|g| g.len() == n) {
            Some(g) => dofs.iter().map(|&d| g[d]).collect(),
            None => vec![0.0; dofs.len()],
        };
        // Without a hierarchy (a mesh of one level) the coarsest level is the mesh itself.
        let single_level = VertexHierarchy::default();
        let hierarchy = self.hierarchy.as_ref().unwrap_or(&single_level);
        let cycle = VCycle::build(hierarchy, self.n_components, a, &free)?;
        let fine = &cycle.levels[cycle.levels.len() - 1].a;
        let stopping = Stopping {
            relative: self.relative_tolerance,
            absolute: 0.0,
            max_iterations: self.max_iterations,
        };
        let report = conjugate_gradient(
            |v, out| fine.multiply_into(v, out),
            &b,
            &mut xf,
            &cycle,
            stopping,
        )
        .map_err(|e| match e {
            CgError::NonFinite(iteration) => SolveError::IterativeNonFinite(iteration),
            e => SolveError::Iterative(e.to_string()),
        })?;
        self.iterations.push(report.iterations);
        for (&d, &v) in dofs.iter().zip(&xf) {
            x[d] = v;
        }
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            return Err(SolveError::NonFinite(i));
        }
        self.guess = Some(x.clone());
        Ok(x)
    }
}
