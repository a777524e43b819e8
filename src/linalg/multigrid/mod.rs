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
//! ([`crate::study::solver_of`]); their `multigrid` is the truncated nonsmooth Newton multigrid
//! method of [`obstacle`], which solves the contact problem itself on these levels.
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

mod cycle;
pub mod obstacle;
mod smoother;
mod sparse;

use rayon::prelude::*;

use super::krylov::{conjugate_gradient_with, CgError, Stopping, VectorOps};
use super::solver::Accuracy;
use super::{Csc, SolveError};
use cycle::{numbering, MaskedCycle, VCycle};
use sparse::Sparse;

pub use cycle::Frame;

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

/// The frame of each of `n_vertices` vertices ([`Frame`]) with the `rotated` ones in their
/// normal/tangential frame; empty (all Cartesian) when none is.
fn frames_by_vertex(rotated: &[(u32, [f64; 2])], n_vertices: usize) -> Vec<Frame> {
    let mut frames: Vec<Frame> = Vec::new();
    if !rotated.is_empty() {
        frames.resize(n_vertices, None);
        for &(v, normal) in rotated {
            frames[v as usize] = Some(normal);
        }
    }
    frames
}

/// A failed CG solve as the error of the solve: a non-finite value names its iteration.
impl From<CgError> for SolveError {
    fn from(e: CgError) -> SolveError {
        match e {
            CgError::NonFinite(iteration) => SolveError::IterativeNonFinite(iteration),
            e => SolveError::Iterative(e.to_string()),
        }
    }
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
        check_levels(hierarchy, n_components, &a)?;
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

/// [`SolveError::OverBudget`] if the levels of `hierarchy` below the block `fine` do not fit
/// the memory limit of the study ([`crate::linalg::direct::limit_memory`]), checked before the
/// Galerkin products are allocated. Each level's matrix is predicted with the entries per row
/// of the finest (the Galerkin products of Q₁ prolongations keep a nine-point stencil per
/// component) in double precision, its single-precision copy and 32-bit column indices, plus
/// its vectors (residual, correction, prolongated values).
fn check_levels(
    hierarchy: &VertexHierarchy,
    n_components: usize,
    fine: &Sparse,
) -> Result<(), SolveError> {
    let sizes = hierarchy.level_sizes();
    let coarse: usize = sizes.iter().rev().skip(1).map(|&v| v * n_components).sum();
    let rows = fine.n_rows().max(1) as f64;
    let per_row = fine.vals.len() as f64 / rows;
    let bytes = coarse as f64 * (per_row * (8.0 + 4.0 + 4.0) + 3.0 * 8.0);
    super::direct::check_memory(
        || {
            format!(
                "the multigrid hierarchy of {} levels ({coarse} unknowns below the finest)",
                sizes.len()
            )
        },
        bytes,
    )
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
            let frames = frames_by_vertex(&self.rotated, n / self.n_components);
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
        .map_err(SolveError::from)?;
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
