//! The sparsity pattern of a Q₁ problem and the plan that scatters cell matrices into it, with
//! the hanging-node constraints condensed (a hanging dof's row and column are distributed to its
//! two parents with weight ½, [`super::Constraints::hanging_parents`]); deterministic parallel
//! assembly.
//!
//! The pattern is symmetric, stored in full (both triangles) in compressed columns, and has every
//! diagonal entry — also those of hanging and fixed dofs, whose rows the solver eliminates while
//! keeping the diagonal, so the pattern does not depend on which dofs are fixed.

use std::ops::Range;

use rayon::prelude::*;

use super::constraints::Constraints;
use super::dofs::DofMap;
use crate::linalg::{joined, split_by_offsets, transpose, Csc};

/// One local dof of a cell expanded to a global dof with weight 2^(−wexp)
/// (hanging dofs expand to their two parents with weight ½).
#[derive(Clone, Copy, Debug)]
struct Expanded {
    global: u32,
    local: u8,
    wexp: u8,
}

/// Symmetric sparsity pattern over all dofs (full storage, compressed columns) and the plan to
/// scatter cell matrices into it: the expanded local dofs of every cell (the positions of their
/// pairs in the matrix are found when assembling, [`SparsityPattern::assemble`]).
pub struct SparsityPattern {
    n: usize,
    n_local: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<u32>,
    diag: Vec<usize>,
    rhs_start: Vec<usize>,
    rhs_entries: Vec<Expanded>,
}

/// The most expanded dofs of a cell: two parents for each hanging one.
const MAX_EXPANDED: usize = 64;

impl SparsityPattern {
    /// Pattern of a Q₁ problem on `dofs`: every pair of dofs that share a cell (after
    /// expanding hanging dofs into their parents) plus every diagonal entry.
    pub fn new(dofs: &DofMap, constraints: &Constraints) -> SparsityPattern {
        let n = dofs.n_dofs();
        assert!(
            n < u32::MAX as usize,
            "too many dofs for 32-bit row indices"
        );
        let nc = dofs.n_components;
        let n_local = 4 * nc;
        // A cell's dofs after expanding the hanging ones ([`SparsityPattern::cell_positions`]).
        assert!(2 * n_local <= MAX_EXPANDED, "too many components");
        let v = &dofs.vertices;
        let hang = |vert: u32| -> Option<[u32; 2]> {
            if v.is_hanging[vert as usize] {
                Some(constraints.hanging_parents(vert).expect("hanging vertex"))
            } else {
                None
            }
        };
        // Expanded local dofs of every cell, flat: cell k owns rhs_entries[rhs_start[k]..rhs_start[k + 1]].
        let n_cells = v.cell_vertices.len();
        let expand = |k: usize, push: &mut dyn FnMut(Expanded)| {
            for (lv, &vert) in v.cell_vertices[k].iter().enumerate() {
                for c in 0..nc {
                    let local = (lv * nc + c) as u8;
                    match hang(vert) {
                        None => push(Expanded {
                            global: (vert as usize * nc + c) as u32,
                            local,
                            wexp: 0,
                        }),
                        Some(p) => {
                            for q in p {
                                push(Expanded {
                                    global: (q as usize * nc + c) as u32,
                                    local,
                                    wexp: 1,
                                });
                            }
                        }
                    }
                }
            }
        };
        let counts: Vec<usize> = (0..n_cells)
            .into_par_iter()
            .map(|k| {
                let mut m = 0;
                expand(k, &mut |_| m += 1);
                m
            })
            .collect();
        let mut rhs_start = Vec::with_capacity(n_cells + 1);
        rhs_start.push(0);
        for &m in &counts {
            rhs_start.push(rhs_start.last().unwrap() + m);
        }
        drop(counts);
        let mut rhs_entries = vec![
            Expanded {
                global: 0,
                local: 0,
                wexp: 0
            };
            rhs_start[n_cells]
        ];
        split_by_offsets(&mut rhs_entries, &rhs_start)
            .into_par_iter()
            .enumerate()
            .for_each(|(k, out)| {
                let mut i = 0;
                expand(k, &mut |e| {
                    out[i] = e;
                    i += 1;
                });
            });
        // Cells touching each global dof (after expansion), in cell order.
        let (touch_start, touch, _) =
            transpose(&rhs_start, |p| rhs_entries[p].global as usize, n, |_| ());
        // Column j: every dof sharing a cell with j, plus j itself; built in parallel blocks of
        // columns and stitched in column order.
        const BLOCK: usize = 4096;
        let blocks: Vec<(Vec<usize>, Vec<u32>)> = (0..n.div_ceil(BLOCK))
            .into_par_iter()
            .map(|b| {
                let cols = b * BLOCK..((b + 1) * BLOCK).min(n);
                let mut lens = Vec::with_capacity(cols.len());
                let mut rows = Vec::with_capacity(cols.len() * 10 * nc);
                let mut buf: Vec<u32> = Vec::new();
                for j in cols {
                    buf.clear();
                    buf.push(j as u32);
                    for &k in &touch[touch_start[j]..touch_start[j + 1]] {
                        let k = k as usize;
                        buf.extend(
                            rhs_entries[rhs_start[k]..rhs_start[k + 1]]
                                .iter()
                                .map(|e| e.global),
                        );
                    }
                    buf.sort_unstable();
                    buf.dedup();
                    lens.push(buf.len());
                    rows.extend_from_slice(&buf);
                }
                (lens, rows)
            })
            .collect();
        drop(touch);
        drop(touch_start);
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0usize);
        for (lens, _) in &blocks {
            for &l in lens {
                col_ptr.push(col_ptr.last().unwrap() + l);
            }
        }
        let nnz = col_ptr[n];
        // Stitched in parallel: each block's rows go to their place in the whole.
        let row_idx = joined(blocks.iter().map(|(_, rows)| &rows[..]).collect());
        assert!(
            nnz < u32::MAX as usize,
            "matrix too large for 32-bit positions"
        );
        let mut pattern = SparsityPattern {
            n,
            n_local,
            col_ptr,
            row_idx,
            diag: Vec::new(),
            rhs_start,
            rhs_entries,
        };
        pattern.diag = (0..n).into_par_iter().map(|i| pattern.find(i, i)).collect();
        pattern
    }

    /// Position of entry (i, j), which is in the pattern.
    #[inline]
    fn find(&self, i: usize, j: usize) -> usize {
        let col = &self.row_idx[self.col_ptr[j]..self.col_ptr[j + 1]];
        self.col_ptr[j] + col.binary_search(&(i as u32)).expect("entry in pattern")
    }

    pub fn n(&self) -> usize {
        self.n
    }

    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Column pointers of the (full, symmetric) compressed-column pattern.
    pub fn col_ptr(&self) -> &[usize] {
        &self.col_ptr
    }

    /// Row indices of the pattern, sorted within each column.
    pub fn row_idx(&self) -> &[u32] {
        &self.row_idx
    }

    /// Position of entry (i, j) in the value array, if it is in the pattern.
    pub fn position(&self, i: usize, j: usize) -> Option<usize> {
        let col = &self.row_idx[self.col_ptr[j]..self.col_ptr[j + 1]];
        col.binary_search(&(i as u32))
            .ok()
            .map(|p| self.col_ptr[j] + p)
    }

    /// Assemble cell matrices and vectors. `cell(k, ke, fe)` fills the `n_local × n_local`
    /// matrix (row-major) and the `n_local` vector of active cell `k`; it runs in parallel,
    /// the summation into the global system runs in cell order (bitwise deterministic).
    pub fn assemble<F>(&self, n_cells: usize, cell: F) -> (Vec<f64>, Vec<f64>)
    where
        F: Fn(usize, &mut [f64], &mut [f64]) + Sync,
    {
        let nl = self.n_local;
        // Cells are computed in parallel blocks, with the matrix positions of their expanded
        // dof pairs, into reused buffers and summed block by block in cell order: no array of
        // the whole mesh.
        const BLOCK: usize = 8192;
        let mut ke = vec![0.0; BLOCK.min(n_cells) * nl * nl];
        let mut fe = vec![0.0; BLOCK.min(n_cells) * nl];
        let mut positions: Vec<u32> = Vec::new();
        // Written, not calloc'ed: a fresh zero page that is read before it is written costs a
        // copy-on-write fault with a TLB shootdown on every page.
        let mut values = zeros(self.nnz());
        let mut rhs = zeros(self.n);
        for first in (0..n_cells).step_by(BLOCK) {
            let len = BLOCK.min(n_cells - first);
            let cells = first..first + len;
            // Where each cell's positions start: it has m² for m expanded dofs.
            let mut starts = Vec::with_capacity(len + 1);
            starts.push(0);
            for k in cells.clone() {
                let m = self.rhs_start[k + 1] - self.rhs_start[k];
                starts.push(starts[starts.len() - 1] + m * m);
            }
            positions.resize(starts[len], 0);
            ke[..len * nl * nl].fill(0.0);
            fe[..len * nl].fill(0.0);
            ke[..len * nl * nl]
                .par_chunks_mut(nl * nl)
                .zip(fe[..len * nl].par_chunks_mut(nl))
                .zip(split_by_offsets(&mut positions, &starts))
                .enumerate()
                .for_each(|(i, ((m, f), pos))| {
                    cell(first + i, m, f);
                    self.cell_positions(self.expanded(first + i), pos);
                });
            // Summed on both cores, each owning the columns on one side of the middle dof of
            // the block: each still adds in cell order, so the sums are those of one pass.
            let (lo, hi) = cells.clone().fold((usize::MAX, 0), |(lo, hi), k| {
                self.expanded(k).iter().fold((lo, hi), |(lo, hi), e| {
                    (lo.min(e.global as usize), hi.max(e.global as usize))
                })
            });
            let middle = lo + (hi - lo) / 2;
            let (values_lo, values_hi) = values.split_at_mut(self.col_ptr[middle]);
            let (rhs_lo, rhs_hi) = rhs.split_at_mut(middle);
            let block = Block {
                pattern: self,
                first,
                ke: &ke,
                fe: &fe,
                positions: &positions,
                starts: &starts,
            };
            rayon::join(
                || block.sum(values_lo, rhs_lo, 0, 0..middle),
                || block.sum(values_hi, rhs_hi, self.col_ptr[middle], middle..self.n),
            );
        }
        (values, rhs)
    }

    /// The positions of the entries (a, b) of the expanded dofs `e` of a cell, row-major by a,
    /// into `out` (e.len()² of them). Column b holds every a of the cell: one walk down the
    /// column per b with the dofs in increasing order finds them all, where a binary search
    /// per entry branched unpredictably.
    fn cell_positions(&self, e: &[Expanded], out: &mut [u32]) {
        let m = e.len();
        // The cell's dofs in increasing order.
        let mut order = [0u8; MAX_EXPANDED];
        let order = &mut order[..m];
        for (i, o) in order.iter_mut().enumerate() {
            *o = i as u8;
        }
        order.sort_unstable_by_key(|&i| e[i as usize].global);
        for (bi, b) in e.iter().enumerate() {
            let start = self.col_ptr[b.global as usize];
            let column = &self.row_idx[start..self.col_ptr[b.global as usize + 1]];
            let mut p = 0;
            for &ai in order.iter() {
                let row = e[ai as usize].global;
                while column[p] < row {
                    p += 1;
                }
                debug_assert_eq!(column[p], row, "entry in pattern");
                out[ai as usize * m + bi] = (start + p) as u32;
            }
        }
    }

    /// The expanded local dofs of active cell `k`.
    #[inline]
    fn expanded(&self, k: usize) -> &[Expanded] {
        &self.rhs_entries[self.rhs_start[k]..self.rhs_start[k + 1]]
    }

    /// The matrix with this pattern and the given values (e.g. assembled by
    /// [`SparsityPattern::assemble`]).
    pub fn matrix<'a>(&'a self, values: &'a [f64]) -> Csc<'a> {
        debug_assert_eq!(values.len(), self.nnz());
        Csc {
            col_ptr: &self.col_ptr,
            row_idx: &self.row_idx,
            diag: &self.diag,
            values,
        }
    }
}

/// One block of computed cells of [`SparsityPattern::assemble`]: cell matrices and vectors
/// and the matrix positions of their expanded dof pairs.
struct Block<'a> {
    pattern: &'a SparsityPattern,
    /// The first cell of the block.
    first: usize,
    ke: &'a [f64],
    fe: &'a [f64],
    positions: &'a [u32],
    starts: &'a [usize],
}

impl Block<'_> {
    /// Add the block's cells, in cell order, to the part of the matrix values that starts at
    /// position `offset` (the columns `dofs`) and the part `rhs` of the load (the same dofs).
    fn sum(&self, values: &mut [f64], rhs: &mut [f64], offset: usize, dofs: Range<usize>) {
        let nl = self.pattern.n_local;
        let n_cells = self.starts.len() - 1;
        for i in 0..n_cells {
            let m = &self.ke[i * nl * nl..(i + 1) * nl * nl];
            let e = self.pattern.expanded(self.first + i);
            let mut pos = self.positions[self.starts[i]..self.starts[i + 1]].iter();
            for a in e {
                for b in e {
                    let p = *pos.next().expect("a position per pair") as usize;
                    if dofs.contains(&(b.global as usize)) {
                        let lij = a.local as usize * nl + b.local as usize;
                        values[p - offset] += m[lij] * weight(a.wexp + b.wexp);
                    }
                }
            }
            let f = &self.fe[i * nl..(i + 1) * nl];
            for e in e {
                let g = e.global as usize;
                if dofs.contains(&g) {
                    rhs[g - dofs.start] += f[e.local as usize] * weight(e.wexp);
                }
            }
        }
    }
}

#[inline]
fn weight(wexp: u8) -> f64 {
    match wexp {
        0 => 1.0,
        1 => 0.5,
        2 => 0.25,
        w => 0.5f64.powi(w as i32),
    }
}

/// A vector of `len` zeros, written (in parallel) rather than allocated zeroed.
fn zeros(len: usize) -> Vec<f64> {
    (0..len).into_par_iter().map(|_| 0.0).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::DofMap;
    use crate::mesh::Mesh;

    /// The walk of [`SparsityPattern::cell_positions`] finds, for every cell of a graded mesh
    /// (hanging vertices expanded into their parents, some of them shared within a cell), the
    /// position a binary search finds, for one and for three components.
    #[test]
    fn cell_positions_are_those_of_a_search() {
        let mut mesh = Mesh::new([0.0, 1.0], [0.0, 1.0], 2, 2);
        for _ in 0..4 {
            let refine: Vec<bool> = mesh
                .active()
                .iter()
                .map(|&c| {
                    let [x0, y0, ..] = mesh.cell_box(c);
                    x0 + y0 < 0.5
                })
                .collect();
            let none = vec![false; refine.len()];
            mesh.refine_and_coarsen(&refine, &none).unwrap();
        }
        for components in [1, 3] {
            let dofs = DofMap::new(&mesh, components);
            let constraints = Constraints::new(&dofs);
            assert!(
                !dofs.vertices.hanging.is_empty(),
                "the mesh has hanging vertices"
            );
            let pattern = SparsityPattern::new(&dofs, &constraints);
            let mut expanded_cells = 0;
            for k in 0..mesh.n_active() {
                let e = pattern.expanded(k);
                expanded_cells += usize::from(e.len() > pattern.n_local);
                let mut walked = vec![0; e.len() * e.len()];
                pattern.cell_positions(e, &mut walked);
                for (ai, a) in e.iter().enumerate() {
                    for (bi, b) in e.iter().enumerate() {
                        let searched = pattern.find(a.global as usize, b.global as usize);
                        assert_eq!(walked[ai * e.len() + bi] as usize, searched, "cell {k}");
                    }
                }
            }
            assert!(expanded_cells > 0, "some cells have hanging dofs");
        }
    }
}
