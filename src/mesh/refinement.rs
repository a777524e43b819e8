//! Refinement and coarsening with the 2:1 balance, the rebuild of the storage breadth-first
//! by level, its lineage (which cells a later mesh kept), and the level meshes.

use rayon::prelude::*;

use super::{
    Cell, CellId, Mesh, MeshError, Neighbor, Side, VertexKey, FACES, MAX_CELLS, MAX_LEVEL, NONE,
};

/// The identity of a mesh's storage: a stamp that no other storage in the process has (a clone
/// keeps it: same cells, same ids), and after a refinement ([`Mesh::refine_and_coarsen`]) the
/// stamp of the storage it was rebuilt from with the id each cell had there (`NONE` for a cell
/// the refinement created). It lets the next cycle find the cells it kept without searching
/// their positions ([`Mesh::kept_from`]).
#[derive(Clone, Debug)]
pub(super) struct Lineage {
    pub(super) stamp: u64,
    pub(super) before: Option<(u64, Vec<CellId>)>,
}

impl Lineage {
    /// The lineage of new storage, rebuilt from the storage stamped `before` (with the old id of
    /// each cell), or of none.
    pub(super) fn new(before: Option<(u64, Vec<CellId>)>) -> Lineage {
        static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
        Lineage {
            stamp: NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
            before,
        }
    }
}

/// What a later mesh needs of this one to find the cells it kept ([`Mesh::kept_from`]): the
/// stamp of its storage and the active index of each cell.
#[derive(Clone, Debug)]
pub struct ActiveCells {
    pub(super) stamp: u64,
    pub(super) active_index: Vec<u32>,
}
impl Mesh {
    /// Refine the active cells flagged in `refine` and coarsen complete sibling groups whose
    /// four children are all flagged in `coarsen` (flags indexed like [`Mesh::active`]).
    ///
    /// The 2:1 rule across faces is enforced as deal.II does it: refinement flags are added
    /// where a refinement would create a level difference of two, and coarsening flags are
    /// dropped where coarsening would. Level-0 cells are never coarsened. Returns the number of
    /// cells refined and the number of sibling groups coarsened.
    ///
    /// Fails, leaving the mesh unchanged, where a cell of level [`MAX_LEVEL`] would be refined
    /// ([`MeshError::PastDeepestLevel`]: its children would have no integer position) or the
    /// mesh would outgrow [`MAX_CELLS`]. The 2:1 closure only adds coarser cells, so the first
    /// error names a cell the caller flagged.
    pub fn refine_and_coarsen(
        &mut self,
        refine: &[bool],
        coarsen: &[bool],
    ) -> Result<(usize, usize), MeshError> {
        assert_eq!(refine.len(), self.active.len());
        assert_eq!(coarsen.len(), self.active.len());
        let n = self.cells.len();
        let mut ref_flag = vec![false; n];
        let mut coa_flag = vec![false; n];
        for (k, &c) in self.active.iter().enumerate() {
            ref_flag[c as usize] = refine[k];
            coa_flag[c as usize] = coarsen[k] && !refine[k];
        }
        self.close_under_face_rule(&mut ref_flag, &mut coa_flag);
        // Coarsening: complete groups only, not level 0, and no face neighbour of the parent may
        // be (or become) two levels finer than the parent.
        let mut coarsen_parent = vec![false; n];
        let mut n_coarsened = 0;
        for &c in &self.active {
            let cell = self.cells[c as usize];
            if cell.level == 0 || !coa_flag[c as usize] {
                continue;
            }
            let p = cell.parent;
            if coarsen_parent[p as usize] || self.cells[p as usize].children != c {
                continue; // decide each group once, at its first child
            }
            let kids = self.children(p).expect("parent has children");
            let all = kids.iter().all(|&k| {
                let kc = self.cells[k as usize];
                kc.children == NONE && coa_flag[k as usize] && !ref_flag[k as usize]
            });
            if !all || !self.parent_may_coarsen(p, &ref_flag) {
                continue;
            }
            coarsen_parent[p as usize] = true;
            n_coarsened += 1;
        }
        let refined = || self.active.iter().filter(|&&c| ref_flag[c as usize]);
        if let Some(&c) = refined().find(|&&c| self.cells[c as usize].level == MAX_LEVEL) {
            let centre = self.cell_shape(c).point(0.5, 0.5);
            return Err(MeshError::PastDeepestLevel { centre });
        }
        let n_refined = refined().count();
        // Each refinement adds four cells, each coarsening removes four.
        let cells = self.cells.len() as u64 + 4 * n_refined as u64 - 4 * n_coarsened as u64;
        if cells > MAX_CELLS {
            return Err(MeshError::TooManyCells { cells });
        }
        self.rebuild(&ref_flag, &coarsen_parent, cells as usize);
        Ok((n_refined, n_coarsened))
    }

    /// Whether removing the children of `p` keeps the 2:1 rule, given the refinement flags.
    pub(super) fn parent_may_coarsen(&self, p: CellId, ref_flag: &[bool]) -> bool {
        for face in FACES {
            let Some(nb) = self.across(p, face) else {
                continue;
            };
            let ncell = self.cells[nb as usize];
            if ncell.level < self.cells[p as usize].level {
                continue;
            }
            if ncell.children == NONE {
                continue; // same level as the parent: becomes at most one level finer if refined
            }
            let [a, b] = face.opposite().children();
            for k in [ncell.children + a as u32, ncell.children + b as u32] {
                let kc = self.cells[k as usize];
                if kc.children != NONE || ref_flag[k as usize] {
                    return false;
                }
            }
        }
        true
    }

    /// Rebuild the storage depth-first with the given refinements and coarsenings applied.
    /// `n_cells` is the number of cells afterwards: the new storage is allocated once, at its
    /// size (grown by doubling, it could hold up to twice as many cells as the mesh has, next to
    /// the old storage).
    pub(super) fn rebuild(&mut self, ref_flag: &[bool], coarsen_parent: &[bool], n_cells: usize) {
        let roots = self.nx * self.ny;
        let mut cells: Vec<Cell> = Vec::with_capacity(n_cells);
        cells.extend_from_slice(&self.cells[..roots]);
        for c in cells.iter_mut() {
            c.children = NONE;
        }
        // Breadth-first over levels so that children are consecutive; the active list is then
        // collected depth-first.
        let mut queue: Vec<(u32, u32)> = (0..roots as u32).map(|i| (i, i)).collect(); // (old, new)
        let mut old_id = vec![NONE; n_cells];
        let mut head = 0;
        while head < queue.len() {
            let (old, new) = queue[head];
            old_id[new as usize] = old;
            head += 1;
            let oc = self.cells[old as usize];
            let keep_children = oc.children != NONE && !coarsen_parent[old as usize];
            let make_children = oc.children == NONE && ref_flag[old as usize];
            if !(keep_children || make_children) {
                continue;
            }
            let first = cells.len() as u32;
            cells[new as usize].children = first;
            let half = Self::width(oc.level + 1);
            for ci in 0..4u32 {
                cells.push(Cell {
                    level: oc.level + 1,
                    x: oc.x + half * u64::from(ci & 1),
                    y: oc.y + half * u64::from(ci >> 1),
                    parent: new,
                    children: NONE,
                });
                if keep_children {
                    queue.push((oc.children + ci, first + ci));
                }
            }
        }
        assert_eq!(cells.len(), n_cells, "cells counted before the rebuild");
        self.cells = cells;
        self.lineage = Lineage::new(Some((self.lineage.stamp, old_id)));
        self.collect_active();
    }

    /// The stamp of this mesh's storage and the active index of each of its cells, for
    /// [`Mesh::kept_from`] on a later mesh.
    pub fn active_cells(&self) -> ActiveCells {
        ActiveCells {
            stamp: self.lineage.stamp,
            active_index: self.active_index.clone(),
        }
    }

    /// If this mesh is that of `before`, or was rebuilt from it by one refinement
    /// ([`Mesh::refine_and_coarsen`]): for each active cell (in [`Mesh::active`] order) its
    /// index among the active cells of that mesh, if it was active there — the same cell, at
    /// the same integer position and size. `None` for a mesh of another lineage.
    pub fn kept_from(&self, before: &ActiveCells) -> Option<Vec<Option<u32>>> {
        if before.stamp == self.lineage.stamp {
            return Some((0..self.active.len() as u32).map(Some).collect());
        }
        let (stamp, old_id) = self.lineage.before.as_ref()?;
        if *stamp != before.stamp {
            return None;
        }
        Some(
            self.active
                .par_iter()
                .map(|&c| {
                    let old = old_id[c as usize];
                    let k = if old == NONE {
                        NONE
                    } else {
                        before.active_index[old as usize]
                    };
                    (k != NONE).then_some(k)
                })
                .collect(),
        )
    }

    /// The active cells depth-first over the trees, and their indices.
    pub(super) fn collect_active(&mut self) {
        let roots = self.nx * self.ny;
        self.active.clear();
        let mut stack: Vec<u32> = (0..roots as u32).rev().collect();
        while let Some(c) = stack.pop() {
            let f = self.cells[c as usize].children;
            if f == NONE {
                self.active.push(c);
            } else {
                stack.extend([f + 3, f + 2, f + 1, f]);
            }
        }
        self.active_index = vec![NONE; self.cells.len()];
        for (k, &c) in self.active.iter().enumerate() {
            self.active_index[c as usize] = k as u32;
        }
    }

    /// Number of cells, active and refined.
    pub fn n_cells(&self) -> usize {
        self.cells.len()
    }

    /// Deepest level of an active cell.
    pub fn max_level(&self) -> u8 {
        self.cells.last().map_or(0, |c| c.level)
    }

    /// The mesh of the cells of level ≤ `level`: every cell of that level becomes active (the
    /// level meshes of global-coarsening multigrid, [`crate::fe::hierarchy`]). The storage is
    /// breadth-first by level (`Mesh::rebuild`), so the coarser mesh is a prefix of it with
    /// the same cell ids; a truncation of a 2:1-balanced mesh is 2:1 balanced (a leaf next to a
    /// cell of level `level` had a neighbour of level ≥ `level` before, so its level is at
    /// least `level − 1`).
    pub fn truncated(&self, level: u8) -> Mesh {
        let kept = self.cells.partition_point(|c| c.level <= level);
        let mut cells = self.cells[..kept].to_vec();
        for c in &mut cells {
            if c.level == level {
                c.children = NONE;
            }
        }
        let mut mesh = Mesh {
            cells,
            active: Vec::new(),
            active_index: Vec::new(),
            moved: self.moved.clone(),
            lineage: Lineage::new(None),
            ..*self
        };
        mesh.collect_active();
        mesh
    }

    /// The active cell that holds the vertex `key` in its closure (the cell to its upper right,
    /// or the one below or left of it on the right and top sides of the domain).
    pub fn cell_at_vertex(&self, key: VertexKey) -> CellId {
        let (ex, ey) = self.extent();
        self.descend(key.0.min(ex - 1), key.1.min(ey - 1), MAX_LEVEL)
    }

    /// [`Mesh::cell_at_vertex`] of `key` in `before`, the mesh this one was rebuilt from by one
    /// refinement ([`Mesh::kept_from`]), given the cell `c` of this mesh that holds the vertex
    /// so: from the nearest ancestor of `c` that `before` had, down `before`'s tree — a step or
    /// two where a descent from the root takes one per level. `None` for a mesh of another
    /// lineage.
    pub fn cell_at_vertex_in(&self, before: &Mesh, c: CellId, key: VertexKey) -> Option<CellId> {
        let start = if before.lineage.stamp == self.lineage.stamp {
            c
        } else {
            let (stamp, old_id) = self.lineage.before.as_ref()?;
            if *stamp != before.lineage.stamp {
                return None;
            }
            // The roots are always kept, so the walk ends.
            let mut a = c;
            while old_id[a as usize] == NONE {
                a = self.cells[a as usize].parent;
            }
            old_id[a as usize]
        };
        let (ex, ey) = before.extent();
        Some(before.descend_from(start, key.0.min(ex - 1), key.1.min(ey - 1), MAX_LEVEL))
    }

    /// Refine every active cell once (fails like [`Mesh::refine_and_coarsen`]).
    pub fn refine_global(&mut self) -> Result<(), MeshError> {
        let r = vec![true; self.active.len()];
        let c = vec![false; self.active.len()];
        self.refine_and_coarsen(&r, &c).map(|_| ())
    }

    /// Refine `times` times every active cell with a face on one of `sides` (with the 2:1
    /// closure of [`Mesh::refine_and_coarsen`]): the fixed meshes of the model-adaptive contact
    /// tables, §IV.2.3 — 64 × 2 cells refined 3× at the contact side give 1472 cells and 512
    /// contact faces (fails like [`Mesh::refine_and_coarsen`]).
    pub fn refine_at_sides(&mut self, sides: &[Side], times: usize) -> Result<(), MeshError> {
        for _ in 0..times {
            let refine: Vec<bool> = self
                .active
                .iter()
                .map(|&c| {
                    FACES
                        .iter()
                        .any(|&f| matches!(self.neighbor(c, f), Neighbor::Boundary(s) if sides.contains(&s)))
                })
                .collect();
            let coarsen = vec![false; refine.len()];
            self.refine_and_coarsen(&refine, &coarsen)?;
        }
        Ok(())
    }

    /// Check the 2:1 rule across every face of every active cell (for tests).
    pub fn is_balanced(&self) -> bool {
        self.active.iter().all(|&c| {
            FACES.iter().all(|&f| match self.neighbor(c, f) {
                Neighbor::Finer(k) => k.iter().all(|&x| self.is_active(x)),
                Neighbor::Coarser(n) => self.level(c) == self.level(n) + 1,
                _ => true,
            })
        })
    }
}

impl Mesh {
    /// Closure of refinement flags (by cell id) under the 2:1 rule: a flagged cell of level l
    /// needs every face neighbour to be of level ≥ l afterwards, so its coarser active face
    /// neighbours are flagged too (and not coarsened), recursively.
    pub(super) fn close_under_face_rule(&self, refine: &mut [bool], coarsen: &mut [bool]) {
        let mut stack: Vec<CellId> = self
            .active
            .iter()
            .copied()
            .filter(|&c| refine[c as usize])
            .collect();
        while let Some(c) = stack.pop() {
            let level = self.cells[c as usize].level;
            for face in FACES {
                if let Some(nb) = self.across(c, face) {
                    let ncell = self.cells[nb as usize];
                    if ncell.level < level && ncell.children == NONE && !refine[nb as usize] {
                        refine[nb as usize] = true;
                        coarsen[nb as usize] = false;
                        stack.push(nb);
                    }
                }
            }
        }
    }
}
