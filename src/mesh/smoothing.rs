//! Mesh smoothing: deal.II's `Triangulation::MeshSmoothing` flags, which its
//! `prepare_coarsening_and_refinement` applies to the marked cells before every refinement.
//!
//! The thesis's runs were made with deal.II, whose triangulation takes these flags at
//! construction; they add refinement flags beyond the marked cells and remove coarsening flags.
//! tribo's own rule, the 2:1 balance across faces ([`Mesh::refine_and_coarsen`]), is deal.II's
//! basic rule and is applied in any case; the flags here go beyond it:
//!
//! - `limit_level_difference_at_vertices`: no two active cells that share a *vertex* (not only
//!   a face) differ by more than one level;
//! - `eliminate_unrefined_islands`: an unrefined cell with more refined (or flagged) face
//!   neighbours than unrefined ones is refined too;
//! - `patch_level_1`: the mesh consists of patches, cells refined once: if one child of a cell
//!   is flagged for refinement all four are, and a group of grandchildren is coarsened only
//!   whole;
//! - `coarsest_level_1`: no cell of level 1 is coarsened (no level-0 cell is created).
//!
//! The combinations: `smoothing_on_refinement` = the first two; `maximum_smoothing` = all flags,
//! where `patch_level_1` makes deal.II skip its coarsening flags (`eliminate_refined_*_islands`,
//! `do_not_produce_unrefined_islands`), so it is the four flags above. Those coarsening flags
//! (and `smoothing_on_coarsening`) are not implemented.
//!
//! deal.II's loop, reproduced in [`Mesh::smooth_flags`]: before it, `coarsest_level_1` and
//! `patch_level_1` clear the coarsening flags of level-1 cells; then, until no flag changes,
//! (3) the vertex limit, (4) the unrefined islands, (5) patch level 1, (6) the 2:1 rule across
//! faces, (8) coarsening of complete sibling groups only. Every step only adds refinement flags
//! or removes coarsening flags, so the loop ends.

use std::collections::HashMap;

use serde::Deserialize;

use super::{CellId, Mesh, MeshError, VertexKey, FACES, NONE};

/// One name of the `[scene] mesh_smoothing` list: a deal.II flag or combination, kebab-case.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[serde(rename_all = "kebab-case")]
pub enum SmoothingName {
    LimitLevelDifferenceAtVertices,
    EliminateUnrefinedIslands,
    PatchLevel1,
    CoarsestLevel1,
    EliminateRefinedInnerIslands,
    EliminateRefinedBoundaryIslands,
    DoNotProduceUnrefinedIslands,
    SmoothingOnRefinement,
    SmoothingOnCoarsening,
    MaximumSmoothing,
}

impl SmoothingName {
    /// Every name, in deal.II's order.
    pub const ALL: [SmoothingName; 10] = [
        SmoothingName::LimitLevelDifferenceAtVertices,
        SmoothingName::EliminateUnrefinedIslands,
        SmoothingName::PatchLevel1,
        SmoothingName::CoarsestLevel1,
        SmoothingName::EliminateRefinedInnerIslands,
        SmoothingName::EliminateRefinedBoundaryIslands,
        SmoothingName::DoNotProduceUnrefinedIslands,
        SmoothingName::SmoothingOnRefinement,
        SmoothingName::SmoothingOnCoarsening,
        SmoothingName::MaximumSmoothing,
    ];

    /// The name used in experiment files.
    pub fn name(self) -> &'static str {
        match self {
            SmoothingName::LimitLevelDifferenceAtVertices => "limit-level-difference-at-vertices",
            SmoothingName::EliminateUnrefinedIslands => "eliminate-unrefined-islands",
            SmoothingName::PatchLevel1 => "patch-level-1",
            SmoothingName::CoarsestLevel1 => "coarsest-level-1",
            SmoothingName::EliminateRefinedInnerIslands => "eliminate-refined-inner-islands",
            SmoothingName::EliminateRefinedBoundaryIslands => "eliminate-refined-boundary-islands",
            SmoothingName::DoNotProduceUnrefinedIslands => "do-not-produce-unrefined-islands",
            SmoothingName::SmoothingOnRefinement => "smoothing-on-refinement",
            SmoothingName::SmoothingOnCoarsening => "smoothing-on-coarsening",
            SmoothingName::MaximumSmoothing => "maximum-smoothing",
        }
    }

    /// The name of an experiment file's `mesh_smoothing` list, if it is one.
    pub fn from_name(name: &str) -> Option<SmoothingName> {
        SmoothingName::ALL.into_iter().find(|n| n.name() == name)
    }

    /// The flags the name sets, or `None` for a deal.II flag tribo does not implement (the
    /// coarsening smoothers, which `maximum_smoothing` switches off through `patch_level_1`).
    pub fn flags(self) -> Option<MeshSmoothing> {
        let m = |bits| Some(MeshSmoothing { bits });
        match self {
            SmoothingName::LimitLevelDifferenceAtVertices => m(MeshSmoothing::VERTICES),
            SmoothingName::EliminateUnrefinedIslands => m(MeshSmoothing::ISLANDS),
            SmoothingName::PatchLevel1 => m(MeshSmoothing::PATCH),
            SmoothingName::CoarsestLevel1 => m(MeshSmoothing::COARSEST),
            SmoothingName::SmoothingOnRefinement => {
                m(MeshSmoothing::VERTICES | MeshSmoothing::ISLANDS)
            }
            SmoothingName::MaximumSmoothing => m(MeshSmoothing::VERTICES
                | MeshSmoothing::ISLANDS
                | MeshSmoothing::PATCH
                | MeshSmoothing::COARSEST),
            SmoothingName::EliminateRefinedInnerIslands
            | SmoothingName::EliminateRefinedBoundaryIslands
            | SmoothingName::DoNotProduceUnrefinedIslands
            | SmoothingName::SmoothingOnCoarsening => None,
        }
    }
}

/// A set of deal.II mesh-smoothing flags ([`SmoothingName`]); the default, none, is tribo's
/// plain 2:1 rule.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MeshSmoothing {
    bits: u8,
}

impl MeshSmoothing {
    const VERTICES: u8 = 1;
    const ISLANDS: u8 = 2;
    const PATCH: u8 = 4;
    const COARSEST: u8 = 8;

    /// The union of the flags of `names`, or the first name tribo does not implement.
    pub fn of(names: &[SmoothingName]) -> Result<MeshSmoothing, SmoothingName> {
        let mut bits = 0;
        for &name in names {
            bits |= name.flags().ok_or(name)?.bits;
        }
        Ok(MeshSmoothing { bits })
    }

    /// No flag set: [`Mesh::refine_and_coarsen_smoothed`] is [`Mesh::refine_and_coarsen`].
    pub fn is_empty(self) -> bool {
        self.bits == 0
    }

    fn has(self, bit: u8) -> bool {
        self.bits & bit != 0
    }
}

/// Refinement and coarsening flags indexed by cell id (only active cells carry them).
struct Flags {
    refine: Vec<bool>,
    coarsen: Vec<bool>,
}

impl Mesh {
    /// [`Mesh::refine_and_coarsen`] after the smoothing flags have added refinement flags and
    /// removed coarsening flags ([`Mesh::smooth_flags`]). With no flag it is
    /// `refine_and_coarsen` itself, bit for bit.
    pub fn refine_and_coarsen_smoothed(
        &mut self,
        refine: &[bool],
        coarsen: &[bool],
        smoothing: MeshSmoothing,
    ) -> Result<(usize, usize), MeshError> {
        if smoothing.is_empty() {
            return self.refine_and_coarsen(refine, coarsen);
        }
        let (refine, coarsen) = self.smooth_flags(refine, coarsen, smoothing);
        self.refine_and_coarsen(&refine, &coarsen)
    }

    /// The flags (indexed like [`Mesh::active`]) after deal.II's smoothing loop
    /// (module docs): refinement flags only added, coarsening flags only removed.
    pub fn smooth_flags(
        &self,
        refine: &[bool],
        coarsen: &[bool],
        smoothing: MeshSmoothing,
    ) -> (Vec<bool>, Vec<bool>) {
        assert_eq!(refine.len(), self.active.len());
        assert_eq!(coarsen.len(), self.active.len());
        let n = self.cells.len();
        let mut f = Flags {
            refine: vec![false; n],
            coarsen: vec![false; n],
        };
        for (k, &c) in self.active.iter().enumerate() {
            f.refine[c as usize] = refine[k];
            f.coarsen[c as usize] = coarsen[k] && !refine[k];
        }
        // Step 0: no level-0 cell is made by coarsening.
        if smoothing.has(MeshSmoothing::COARSEST) || smoothing.has(MeshSmoothing::PATCH) {
            for &c in &self.active {
                if self.cells[c as usize].level == 1 {
                    f.coarsen[c as usize] = false;
                }
            }
        }
        loop {
            let before = (f.refine.clone(), f.coarsen.clone());
            if smoothing.has(MeshSmoothing::VERTICES) {
                self.limit_level_difference_at_vertices(&mut f);
            }
            if smoothing.has(MeshSmoothing::ISLANDS) {
                for &c in self.active.iter().rev() {
                    if !f.refine[c as usize] {
                        self.refine_unrefined_island(c, &mut f);
                    }
                }
            }
            if smoothing.has(MeshSmoothing::PATCH) {
                self.ensure_patch_level_1(&mut f);
            }
            self.face_rule(&mut f);
            self.complete_sibling_groups(&mut f);
            if (&f.refine, &f.coarsen) == (&before.0, &before.1) {
                break;
            }
        }
        let refine = self.active.iter().map(|&c| f.refine[c as usize]).collect();
        let coarsen = self.active.iter().map(|&c| f.coarsen[c as usize]).collect();
        (refine, coarsen)
    }

    /// deal.II's step 3: the highest level each vertex will touch (a coarsening-flagged cell
    /// counted one level coarser), then, from the last active cell back, a cell that touches a
    /// vertex of a level above its own loses its coarsening flag, and one that touches a vertex
    /// two levels above its own is flagged for refinement.
    fn limit_level_difference_at_vertices(&self, f: &mut Flags) {
        let mut vertex_level: HashMap<VertexKey, i32> = HashMap::new();
        let raise = |vl: &mut HashMap<VertexKey, i32>, c: CellId, level: i32| {
            for key in self.corner_keys(c) {
                let v = vl.entry(key).or_insert(0);
                *v = (*v).max(level);
            }
        };
        for &c in &self.active {
            let level = i32::from(self.cells[c as usize].level);
            let after = if f.refine[c as usize] {
                level + 1
            } else if f.coarsen[c as usize] {
                level - 1
            } else {
                level
            };
            raise(&mut vertex_level, c, after);
        }
        for &c in self.active.iter().rev() {
            if f.refine[c as usize] {
                continue;
            }
            let level = i32::from(self.cells[c as usize].level);
            for key in self.corner_keys(c) {
                let v = vertex_level[&key];
                if v > level {
                    f.coarsen[c as usize] = false;
                    if v > level + 1 && !f.refine[c as usize] {
                        f.refine[c as usize] = true;
                        raise(&mut vertex_level, c, level + 1);
                    }
                }
            }
        }
    }

    /// Whether the face `face` of active cell `c` will be refined from the other side (deal.II's
    /// `face_will_be_refined_by_neighbor`): the neighbour of the same level is refined and not
    /// coarsened, or is flagged for refinement. A coarser neighbour does not refine the face.
    fn face_refined_by_neighbor(&self, c: CellId, face: super::Face, f: &Flags) -> Option<bool> {
        let nb = self.across(c, face)?;
        let ncell = self.cells[nb as usize];
        if ncell.level < self.cells[c as usize].level {
            return Some(false);
        }
        if ncell.children == NONE {
            return Some(f.refine[nb as usize]);
        }
        let kids = ncell.children..ncell.children + 4;
        let coarsened = kids
            .clone()
            .all(|k| self.cells[k as usize].children == NONE && f.coarsen[k as usize]);
        Some(!coarsened)
    }

    /// deal.II's step 4 for one active unflagged cell: if more of its interior faces will be
    /// refined from the other side than not, flag it, and look again at its unrefined
    /// unflagged neighbours (a cascade).
    fn refine_unrefined_island(&self, c: CellId, f: &mut Flags) {
        let (mut refined, mut unrefined) = (0, 0);
        for face in FACES {
            match self.face_refined_by_neighbor(c, face, f) {
                Some(true) => refined += 1,
                Some(false) => unrefined += 1,
                None => {}
            }
        }
        if unrefined >= refined {
            return;
        }
        f.coarsen[c as usize] = false;
        f.refine[c as usize] = true;
        if unrefined == 0 {
            return;
        }
        for face in FACES {
            if self.face_refined_by_neighbor(c, face, f) != Some(false) {
                continue;
            }
            let nb = self.across(c, face).expect("an interior face");
            let ncell = self.cells[nb as usize];
            if ncell.children == NONE && !f.refine[nb as usize] {
                self.refine_unrefined_island(nb, f);
            }
        }
    }

    /// deal.II's step 5. A cell whose four children are active: if one child is flagged for
    /// refinement, all four are (and none is coarsened). A cell whose children are all refined
    /// and that has active grandchildren: unless every grandchild is flagged for coarsening,
    /// none of those in patches is. (deal.II assumes the mesh is of patch level 1 already, e.g.
    /// refined globally once; a parent with active and refined children is left alone here.)
    fn ensure_patch_level_1(&self, f: &mut Flags) {
        let children = |p: usize| {
            let first = self.cells[p].children;
            (first..first + 4).map(|k| k as usize)
        };
        let active = |k: usize| self.cells[k].children == NONE;
        for p in 0..self.cells.len() {
            if active(p) || !children(p).all(active) {
                continue;
            }
            if children(p).any(|k| f.refine[k]) {
                for k in children(p) {
                    f.refine[k] = true;
                    f.coarsen[k] = false;
                }
            }
        }
        for p in 0..self.cells.len() {
            if active(p) || children(p).any(active) {
                continue;
            }
            let patches: Vec<usize> = children(p).filter(|&k| children(k).all(active)).collect();
            if patches.is_empty() {
                continue;
            }
            let flagged = patches
                .iter()
                .flat_map(|&k| children(k))
                .filter(|&g| f.coarsen[g])
                .count();
            if flagged > 0 && flagged != 16 {
                for g in patches.iter().flat_map(|&k| children(k)) {
                    f.coarsen[g] = false;
                }
            }
        }
    }

    /// deal.II's step 6, tribo's 2:1 rule: a flagged cell's coarser face neighbours are
    /// flagged too (and not coarsened).
    fn face_rule(&self, f: &mut Flags) {
        self.close_under_face_rule(&mut f.refine, &mut f.coarsen);
    }

    /// deal.II's step 8: a sibling group is coarsened whole or not at all, so the coarsening
    /// flags of incomplete groups go (the vertex limit must not count them as coarsened).
    fn complete_sibling_groups(&self, f: &mut Flags) {
        for &c in &self.active {
            let cell = self.cells[c as usize];
            if cell.level == 0 {
                f.coarsen[c as usize] = false;
                continue;
            }
            let first = self.cells[cell.parent as usize].children;
            let whole = (first..first + 4)
                .all(|k| self.cells[k as usize].children == NONE && f.coarsen[k as usize]);
            if !whole {
                f.coarsen[c as usize] = false;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The flags of `names` (all implemented).
    fn smoothing(names: &[SmoothingName]) -> MeshSmoothing {
        MeshSmoothing::of(names).unwrap()
    }

    /// The active cell whose lower-left corner is at (x, y) in units of the coarse cell width
    /// divided by 2^level, of that level.
    fn cell_at(mesh: &Mesh, level: u8, x: u64, y: u64) -> CellId {
        let w = Mesh::width(level);
        let c = mesh.descend(x * w, y * w, level);
        assert_eq!(mesh.level(c), level);
        c
    }

    /// Refine the active cells at `at` ([`cell_at`]; with the given smoothing).
    fn refine(mesh: &mut Mesh, at: &[(u8, u64, u64)], s: MeshSmoothing) {
        let cells: Vec<CellId> = at.iter().map(|&(l, x, y)| cell_at(mesh, l, x, y)).collect();
        let refine: Vec<bool> = mesh.active().iter().map(|c| cells.contains(c)).collect();
        let coarsen = vec![false; refine.len()];
        mesh.refine_and_coarsen_smoothed(&refine, &coarsen, s)
            .unwrap();
    }

    /// A 2 × 2 grid whose lower-left cell is refined, then its upper-right child (at the centre
    /// vertex): the 2:1 rule refines the right and top coarse cells (they share a face with a
    /// level-2 cell); only the vertex limit also refines the diagonal one, which touches the
    /// level-2 cell at the centre only.
    #[test]
    fn vertex_limit_refines_the_diagonal_cell() {
        for (names, diagonal_refined, n_active) in [
            (vec![], false, 4 + 3 + 3 + 6),
            (
                vec![SmoothingName::LimitLevelDifferenceAtVertices],
                true,
                4 + 3 + 3 + 9,
            ),
        ] {
            let s = smoothing(&names);
            let mut mesh = Mesh::new([0.0, 2.0], [0.0, 2.0], 2, 2);
            refine(&mut mesh, &[(0, 0, 0)], s);
            refine(&mut mesh, &[(1, 1, 1)], s);
            assert!(mesh.is_balanced());
            let diagonal = mesh.descend(3 * Mesh::width(1), 3 * Mesh::width(1), 1);
            assert_eq!(mesh.level(diagonal) == 1, diagonal_refined, "{names:?}");
            assert_eq!(mesh.n_active(), n_active, "{names:?}");
        }
    }

    /// A 3 × 1 strip with its left and right cells flagged: the middle cell has two refined
    /// face neighbours and no unrefined one (its other faces are on the boundary), so with
    /// `eliminate_unrefined_islands` it is refined too.
    #[test]
    fn unrefined_island_is_refined() {
        for (names, middle_refined) in [
            (vec![], false),
            (vec![SmoothingName::EliminateUnrefinedIslands], true),
        ] {
            let s = smoothing(&names);
            let mut mesh = Mesh::new([0.0, 3.0], [0.0, 1.0], 3, 1);
            refine(&mut mesh, &[(0, 0, 0), (0, 2, 0)], s);
            let middle = mesh.descend(Mesh::width(0), 0, 0);
            assert_eq!(mesh.is_active(middle), !middle_refined, "{names:?}");
            assert_eq!(mesh.n_active(), if middle_refined { 12 } else { 9 });
        }
    }

    /// deal.II's strict majority. A 3 × 3 grid with the centre's left and right neighbours
    /// flagged: the centre has two refined and two unrefined face neighbours and stays (and so
    /// does every other cell: a corner cell has one of each). With the bottom one flagged as
    /// well, the centre has three of four and is refined, and so are the two bottom corner
    /// cells (both of their interior faces refined): six coarse cells refined.
    #[test]
    fn unrefined_island_needs_a_strict_majority() {
        let s = smoothing(&[SmoothingName::EliminateUnrefinedIslands]);
        let mut mesh = Mesh::new([0.0, 3.0], [0.0, 3.0], 3, 3);
        refine(&mut mesh, &[(0, 0, 1), (0, 2, 1)], s);
        let centre = mesh.descend(Mesh::width(0), Mesh::width(0), 0);
        assert!(mesh.is_active(centre));
        assert_eq!(mesh.n_active(), 9 + 6);
        let mut mesh = Mesh::new([0.0, 3.0], [0.0, 3.0], 3, 3);
        refine(&mut mesh, &[(0, 0, 1), (0, 2, 1), (0, 1, 0)], s);
        assert!(!mesh.is_active(centre));
        assert_eq!(mesh.n_active(), 9 + 6 * 3);
    }

    /// `patch_level_1`: on a 1 × 1 grid refined once, flagging one child refines all four; and
    /// coarsening three of the sixteen grandchildren is refused while all sixteen coarsen.
    #[test]
    fn patch_level_1_refines_and_coarsens_whole_patches() {
        let s = smoothing(&[SmoothingName::PatchLevel1]);
        let mut mesh = Mesh::new([0.0, 1.0], [0.0, 1.0], 1, 1);
        mesh.refine_global().unwrap();
        let plain = {
            let mut m = mesh.clone();
            refine(&mut m, &[(1, 0, 0)], MeshSmoothing::default());
            m.n_active()
        };
        assert_eq!(plain, 7);
        refine(&mut mesh, &[(1, 0, 0)], s);
        assert_eq!(mesh.n_active(), 16);
        // Sixteen level-2 cells: coarsening one sibling group (four) is not a whole level-2
        // patch of the root, so it is refused; all sixteen coarsen to the four level-1 cells.
        let group: Vec<bool> = (0..16).map(|k| k < 4).collect();
        let none = vec![false; 16];
        let (_, c) = mesh.smooth_flags(&none, &group, s);
        assert!(c.iter().all(|&x| !x));
        let all = vec![true; 16];
        let (_, c) = mesh.smooth_flags(&none, &all, s);
        assert!(c.iter().all(|&x| x));
        let (_, coarsened) = mesh.refine_and_coarsen_smoothed(&none, &all, s).unwrap();
        assert_eq!((coarsened, mesh.n_active()), (4, 4));
    }

    /// `coarsest_level_1`: the four children of a refined 1 × 1 grid keep their coarsening
    /// flags without it and lose them with it.
    #[test]
    fn coarsest_level_1_keeps_level_1() {
        for (names, n_active) in [(vec![], 1), (vec![SmoothingName::CoarsestLevel1], 4)] {
            let mut mesh = Mesh::new([0.0, 1.0], [0.0, 1.0], 1, 1);
            mesh.refine_global().unwrap();
            let none = vec![false; 4];
            let all = vec![true; 4];
            mesh.refine_and_coarsen_smoothed(&none, &all, smoothing(&names))
                .unwrap();
            assert_eq!(mesh.n_active(), n_active, "{names:?}");
        }
    }

    /// The vertex limit also removes coarsening flags: a 2 × 2 grid refined once, then at the
    /// level-1 cell at the centre vertex in the lower-left coarse cell. The children of the
    /// diagonal (upper-right) coarse cell are flagged for coarsening: the 2:1 rule across
    /// faces allows it, but the coarsened cell would touch a level-2 cell at the centre
    /// vertex, so with the vertex limit the group is kept.
    #[test]
    fn vertex_limit_keeps_coarsening_flags_off() {
        for (names, n_coarsened) in [
            (vec![], 1),
            (vec![SmoothingName::LimitLevelDifferenceAtVertices], 0),
        ] {
            let mut mesh = Mesh::new([0.0, 2.0], [0.0, 2.0], 2, 2);
            mesh.refine_global().unwrap();
            refine(&mut mesh, &[(1, 1, 1)], MeshSmoothing::default());
            let diagonal = mesh.descend(Mesh::width(0), Mesh::width(0), 0);
            let kids = mesh.children(diagonal).unwrap();
            let none = vec![false; mesh.n_active()];
            let coarsen: Vec<bool> = mesh.active().iter().map(|c| kids.contains(c)).collect();
            let (_, coarsened) = mesh
                .refine_and_coarsen_smoothed(&none, &coarsen, smoothing(&names))
                .unwrap();
            assert_eq!(coarsened, n_coarsened, "{names:?}");
        }
    }

    /// Names: the combinations expand, the unimplemented coarsening smoothers are refused.
    #[test]
    fn names_expand_and_refuse() {
        let max = smoothing(&[SmoothingName::MaximumSmoothing]);
        let four = smoothing(&[
            SmoothingName::LimitLevelDifferenceAtVertices,
            SmoothingName::EliminateUnrefinedIslands,
            SmoothingName::PatchLevel1,
            SmoothingName::CoarsestLevel1,
        ]);
        assert_eq!(max, four);
        assert_eq!(
            MeshSmoothing::of(&[SmoothingName::SmoothingOnCoarsening]),
            Err(SmoothingName::SmoothingOnCoarsening)
        );
        assert!(MeshSmoothing::default().is_empty());
    }
}
