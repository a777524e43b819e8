//! The V(1,1)-cycle over the levels (module docs of [`super`], *Cycle*), the prolongations of
//! the dofs that build its coarse levels, through the frames of rotated vertices (*Rotated
//! frames*), and the Cholesky factor of its coarsest level.

use std::cell::RefCell;

use super::smoother::Level;
use super::sparse::Sparse;
use super::{is_masked, Mask, Transfer, VertexHierarchy};
use crate::linalg::krylov::Preconditioner;
use crate::linalg::{CholeskyFactor, Csc, SolveError};

/// The V(1,1)-cycle of the module docs for the free dofs of one solve.
pub(super) struct VCycle {
    /// Coarsest first.
    pub(super) levels: Vec<Level>,
    pub(super) coarse: RefCell<Option<CholeskyFactor>>,
    /// The vectors of one application, kept across the iterations of a solve.
    pub(super) work: RefCell<Vec<Work>>,
}

/// The vectors of a V-cycle on one level: its right-hand side and correction, the residual after
/// the forward sweep, the correction before the backward sweep (all of the level's size).
pub(super) struct Work {
    pub(super) r: Vec<f64>,
    pub(super) z: Vec<f64>,
    pub(super) residual: Vec<f64>,
    pub(super) before: Vec<f64>,
}

impl Work {
    /// The vectors of a level of `n` rows; on the finest level (`top`) r and z are those of the
    /// application ([`VCycle::cycle`]).
    pub(super) fn new(n: usize, top: bool) -> Work {
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
    pub(super) fn build(
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
            let coarse_free = coarse_free_of(t, nc, &free);
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
    pub(super) fn cycle(
        &self,
        k: usize,
        work: &mut [Work],
        top: Option<(&[f64], &mut [f64])>,
        mask: Mask,
    ) {
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

/// The free dofs of the coarse level of `t` (by dof, `nc` per vertex) given those of its fine
/// level (module docs of [`super`], *Levels*): not hanging on the coarse level, and free at the
/// fine vertex at the same position.
pub(super) fn coarse_free_of(t: &Transfer, nc: usize, free: &[bool]) -> Vec<bool> {
    (0..t.n_coarse * nc)
        .map(|d| {
            let (w, c) = (d / nc, d % nc);
            !t.coarse_hanging[w] && free[t.fine_of_coarse[w] as usize * nc + c]
        })
        .collect()
}

/// The V-cycle of a block with some of its rows masked ([`Mask`]).
pub(super) struct MaskedCycle<'a> {
    pub(super) cycle: &'a VCycle,
    pub(super) mask: Mask<'a>,
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
/// ([`crate::linalg::active_set::Rotation`]); `None` for Cartesian components.
pub type Frame = Option<[f64; 2]>;

/// Entry (c, c′) of R_v R_wᵀ, which takes the components of a vector in the frame of a coarse
/// vertex w (c′) to those in the frame of a fine vertex v (c); R is the rotation (n; t) of a
/// rotated vertex and the identity of a Cartesian one. With it the prolongation interpolates the
/// Cartesian vector, whatever the frames, so that the coarse spaces are those of the unrotated
/// problem (the Galerkin product of the rotated matrix Rᵀ… is that of the Cartesian one in the
/// rotated frames).
pub(super) fn frame_change(fine: Frame, coarse: Frame, c: usize, c2: usize) -> f64 {
    let rotation = |f: Frame| match f {
        Some(n) => [[n[0], n[1]], [-n[1], n[0]]],
        None => [[1.0, 0.0], [0.0, 1.0]],
    };
    let (rv, rw) = (rotation(fine), rotation(coarse));
    rv[c][0] * rw[c2][0] + rv[c][1] * rw[c2][1]
}

/// The prolongation of the dofs of one level mesh from those of the next coarser kept one
/// ([`Transfer`] for each component, through the frames of rotated vertices).
pub(super) struct Prolongation<'a> {
    pub(super) transfer: &'a Transfer,
    pub(super) n_components: usize,
    /// The frame of each fine and of each coarse vertex (empty: all Cartesian).
    pub(super) fine_frames: &'a [Frame],
    pub(super) coarse_frames: &'a [Frame],
    /// The number of each coarse dof among the coarse level's free dofs (`usize::MAX`: none).
    pub(super) coarse_index: &'a [usize],
}

impl Prolongation<'_> {
    /// The entries (coarse free dof, weight) of fine dof `d`'s row, in order.
    pub(super) fn row(&self, d: usize, emit: &mut dyn FnMut(u32, f64)) {
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
pub(super) fn numbering(free: &[bool]) -> Vec<usize> {
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
pub(super) fn factor(a: &Sparse, diag: &[usize]) -> Result<Option<CholeskyFactor>, SolveError> {
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
