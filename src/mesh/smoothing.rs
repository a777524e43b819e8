//! Mesh smoothing: deal.II's `Triangulation::MeshSmoothing` flags, which its
//! `prepare_coarsening_and_refinement` applies to the marked cells before every refinement.
//!
//! The thesis's runs were made with deal.II, whose triangulation takes these flags at
//! construction; they add and remove refinement and coarsening flags beyond the marked cells.
//! tribo's own rule, the 2:1 balance across faces ([`Mesh::refine_and_coarsen`]), is deal.II's
//! basic rule and is applied in any case; the flags here go beyond it. On refinement:
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
//! On coarsening (deal.II's definitions, which differ from the unrefined islands on purpose: a
//! majority rule would eat a chain of refined cells from its ends):
//!
//! - `do_not_produce_unrefined_islands`: a cell whose children are to be coarsened keeps them
//!   if every face neighbour will be refined at the common face, or all but one and the cell
//!   has four neighbours (is inside the domain);
//! - `eliminate_refined_inner_islands` / `eliminate_refined_boundary_islands`: a cell refined
//!   into four active children, or flagged for refinement, none of whose face neighbours will
//!   be refined at the common face, is an island: its children are flagged for coarsening, or
//!   its refinement flag is removed. The inner flag acts on cells away from the boundary, the
//!   boundary flag on cells with a face on it.
//!
//! The combinations: `smoothing_on_refinement` = the first two; `smoothing_on_coarsening` =
//! the three coarsening flags; `maximum_smoothing` = all seven, where `patch_level_1` makes
//! deal.II skip the three coarsening flags (a mesh of patches has no islands of either kind),
//! so it acts as the four refinement flags.
//!
//! deal.II's loop, reproduced in [`Mesh::smooth_flags`]: before it, `coarsest_level_1` and
//! `patch_level_1` clear the coarsening flags of level-1 cells; then, until no flag changes,
//! (1) no unrefined islands made by coarsening, (2) the refined islands, (3) the vertex limit,
//! (4) the unrefined islands, (5) patch level 1, (6) the 2:1 rule across faces, (8) coarsening
//! of complete sibling groups only. Steps 1 and 2 run only without `patch_level_1`, and walk
//! the cells level by level as deal.II does. Steps 3–8 only add refinement flags or remove
//! coarsening flags; step 2 is the one that removes refinement flags and adds coarsening
//! flags, at the lowest priority: what a later step needs, it flags again.

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

    /// The flags the name sets (deal.II's values of the combinations). `Option` so that a
    /// flag tribo does not implement can be refused by the loader; today every name has flags.
    pub fn flags(self) -> Option<MeshSmoothing> {
        let m = |bits| Some(MeshSmoothing { bits });
        let coarsening = MeshSmoothing::INNER_ISLANDS
            | MeshSmoothing::BOUNDARY_ISLANDS
            | MeshSmoothing::NO_UNREFINED_ISLANDS;
        match self {
            SmoothingName::LimitLevelDifferenceAtVertices => m(MeshSmoothing::VERTICES),
            SmoothingName::EliminateUnrefinedIslands => m(MeshSmoothing::ISLANDS),
            SmoothingName::PatchLevel1 => m(MeshSmoothing::PATCH),
            SmoothingName::CoarsestLevel1 => m(MeshSmoothing::COARSEST),
            SmoothingName::SmoothingOnRefinement => {
                m(MeshSmoothing::VERTICES | MeshSmoothing::ISLANDS)
            }
            SmoothingName::EliminateRefinedInnerIslands => m(MeshSmoothing::INNER_ISLANDS),
            SmoothingName::EliminateRefinedBoundaryIslands => m(MeshSmoothing::BOUNDARY_ISLANDS),
            SmoothingName::DoNotProduceUnrefinedIslands => m(MeshSmoothing::NO_UNREFINED_ISLANDS),
            SmoothingName::SmoothingOnCoarsening => m(coarsening),
            SmoothingName::MaximumSmoothing => m(MeshSmoothing::VERTICES
                | MeshSmoothing::ISLANDS
                | MeshSmoothing::PATCH
                | MeshSmoothing::COARSEST
                | coarsening),
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
    const INNER_ISLANDS: u8 = 16;
    const BOUNDARY_ISLANDS: u8 = 32;
    const NO_UNREFINED_ISLANDS: u8 = 64;

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
    /// [`Mesh::refine_and_coarsen`] after the smoothing flags have changed the refinement and
    /// coarsening flags ([`Mesh::smooth_flags`]). With no flag it is
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
    /// (module docs): refinement flags added and coarsening flags removed, and with the
    /// refined-island flags the reverse for the islands.
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
        // Steps 1 and 2 walk all cells level by level (deal.II's cell order); without
        // `patch_level_1` only, which fulfils them.
        let coarsening = !smoothing.has(MeshSmoothing::PATCH);
        let mut by_level: Vec<CellId> = Vec::new();
        if coarsening {
            by_level = (0..n as CellId).collect();
            by_level.sort_by_key(|&c| self.cells[c as usize].level);
        }
        loop {
            let before = (f.refine.clone(), f.coarsen.clone());
            if coarsening && smoothing.has(MeshSmoothing::NO_UNREFINED_ISLANDS) {
                for &p in &by_level {
                    if self.cells[p as usize].children != NONE && self.will_be_coarsened(p, &mut f)
                    {
                        self.keep_unrefined_island_out(p, &mut f);
                    }
                }
            }
            if coarsening {
                let inner = smoothing.has(MeshSmoothing::INNER_ISLANDS);
                let boundary = smoothing.has(MeshSmoothing::BOUNDARY_ISLANDS);
                if inner || boundary {
                    for &c in &by_level {
                        self.eliminate_refined_island(c, inner, boundary, &mut f);
                    }
                }
            }
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

    /// deal.II's `cell_will_be_coarsened` for a refined cell `p`: its four children are active
    /// and flagged for coarsening. An incomplete group loses its coarsening flags on the way,
    /// as in deal.II (step 8 would remove them at the end of the round anyway; removed here,
    /// the vertex limit of the same round no longer counts them).
    fn will_be_coarsened(&self, p: CellId, f: &mut Flags) -> bool {
        let first = self.cells[p as usize].children;
        let kids = first..first + 4;
        let active = |k: CellId| self.cells[k as usize].children == NONE;
        if kids.clone().all(|k| active(k) && f.coarsen[k as usize]) {
            return true;
        }
        for k in kids.filter(|&k| active(k)) {
            f.coarsen[k as usize] = false;
        }
        false
    }

    /// [`Mesh::face_refined_by_neighbor`] as steps 1 and 2 ask it: a refined neighbour is
    /// first asked [`Mesh::will_be_coarsened`], with its side effect.
    fn face_refined_by_neighbor_mut(
        &self,
        c: CellId,
        face: super::Face,
        f: &mut Flags,
    ) -> Option<bool> {
        let nb = self.across(c, face)?;
        let ncell = self.cells[nb as usize];
        if ncell.children != NONE && ncell.level == self.cells[c as usize].level {
            self.will_be_coarsened(nb, f);
        }
        self.face_refined_by_neighbor(c, face, f)
    }

    /// deal.II's step 1 for a cell `p` whose children are to be coarsened: if every face
    /// neighbour will be refined at the common face, or all but one and `p` lies inside the
    /// domain (four neighbours), coarsening would leave an unrefined island, so the children
    /// keep their cells; then the neighbours about to be coarsened are looked at again (a
    /// cascade).
    fn keep_unrefined_island_out(&self, p: CellId, f: &mut Flags) {
        let (mut neighbours, mut refined) = (0, 0);
        for face in FACES {
            if let Some(r) = self.face_refined_by_neighbor_mut(p, face, f) {
                neighbours += 1;
                refined += usize::from(r);
            }
        }
        if !(refined == neighbours || (refined + 1 >= neighbours && neighbours == FACES.len())) {
            return;
        }
        let first = self.cells[p as usize].children;
        for k in first..first + 4 {
            f.coarsen[k as usize] = false;
        }
        for face in FACES {
            let Some(nb) = self.across(p, face) else {
                continue;
            };
            if self.cells[nb as usize].children != NONE && self.will_be_coarsened(nb, f) {
                self.keep_unrefined_island_out(nb, f);
            }
        }
    }

    /// deal.II's step 2 for one cell `c`, refined into four active children or active and
    /// flagged for refinement: if none of its face neighbours will be refined at the common
    /// face (a coarser neighbour counts as unrefined) and it has at least one, it is a refined
    /// island: inside the domain under `inner`, at the boundary under `boundary`. Its children
    /// are then flagged for coarsening (and not refinement), or its refinement flag goes.
    fn eliminate_refined_island(&self, c: CellId, inner: bool, boundary: bool, f: &mut Flags) {
        let cell = self.cells[c as usize];
        let kids = cell.children..cell.children + 4;
        if cell.children == NONE {
            if !f.refine[c as usize] {
                return;
            }
        } else if kids
            .clone()
            .any(|k| self.cells[k as usize].children != NONE)
        {
            return;
        }
        let (mut neighbours, mut unrefined, mut at_boundary) = (0, 0, false);
        for face in FACES {
            match self.face_refined_by_neighbor_mut(c, face, f) {
                Some(r) => {
                    neighbours += 1;
                    unrefined += usize::from(!r);
                }
                None => at_boundary = true,
            }
        }
        let island = if at_boundary { boundary } else { inner };
        if !island || unrefined != neighbours || neighbours == 0 {
            return;
        }
        if cell.children == NONE {
            f.refine[c as usize] = false;
        } else {
            for k in kids {
                f.refine[k as usize] = false;
                f.coarsen[k as usize] = true;
            }
        }
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

    /// Refine the coarse cells `refine` and coarsen the children of the coarse cells
    /// `coarsen` (all at (x, y) of level 0) with the given smoothing; the active cells after.
    fn refine_and_coarsen_at(
        mesh: &mut Mesh,
        refine: &[(u64, u64)],
        coarsen: &[(u64, u64)],
        s: MeshSmoothing,
    ) -> usize {
        let w = Mesh::width(0);
        let at = |&(x, y): &(u64, u64)| mesh.descend(x * w, y * w, 0);
        let refined: Vec<CellId> = refine.iter().map(at).collect();
        let coarsened: Vec<CellId> = coarsen.iter().map(at).collect();
        let parent_in =
            |c: &CellId, set: &[CellId]| mesh.parent(*c).is_some_and(|p| set.contains(&p));
        let r: Vec<bool> = mesh.active().iter().map(|c| refined.contains(c)).collect();
        let k: Vec<bool> = mesh
            .active()
            .iter()
            .map(|c| parent_in(c, &coarsened))
            .collect();
        mesh.refine_and_coarsen_smoothed(&r, &k, s).unwrap();
        mesh.n_active()
    }

    /// `eliminate_refined_*_islands` on flagged cells: on a 3 × 3 grid, the centre flagged
    /// alone has four unrefined neighbours and is an inner island (its flag goes: 9 cells, not
    /// 12); a corner cell flagged alone is a boundary island. Each flag acts on its kind only,
    /// and two flagged neighbours are not islands (9 + 2·3 cells).
    #[test]
    fn refined_islands_lose_their_refinement_flags() {
        let inner = smoothing(&[SmoothingName::EliminateRefinedInnerIslands]);
        let boundary = smoothing(&[SmoothingName::EliminateRefinedBoundaryIslands]);
        let both = smoothing(&[SmoothingName::SmoothingOnCoarsening]);
        let grid = || Mesh::new([0.0, 3.0], [0.0, 3.0], 3, 3);
        for (flagged, s, n_active) in [
            (vec![(1, 1)], MeshSmoothing::default(), 12),
            (vec![(1, 1)], inner, 9),
            (vec![(1, 1)], boundary, 12),
            (vec![(0, 0)], inner, 12),
            (vec![(0, 0)], boundary, 9),
            (vec![(0, 1), (1, 1)], both, 15),
        ] {
            let n = refine_and_coarsen_at(&mut grid(), &flagged, &[], s);
            assert_eq!(n, n_active, "{flagged:?} {s:?}");
        }
    }

    /// `eliminate_refined_inner_islands` on a refined cell: a 3 × 3 grid whose centre is
    /// refined, with no flag at all, has its centre coarsened back (12 → 9 cells); the same
    /// centre with its right neighbour refined too is no island (stays at 15).
    #[test]
    fn a_refined_island_is_coarsened() {
        let inner = smoothing(&[SmoothingName::EliminateRefinedInnerIslands]);
        for (refined, n_before, n_after) in [(vec![(1, 1)], 12, 9), (vec![(1, 1), (2, 1)], 15, 15)]
        {
            let mut mesh = Mesh::new([0.0, 3.0], [0.0, 3.0], 3, 3);
            refine_and_coarsen_at(&mut mesh, &refined, &[], MeshSmoothing::default());
            assert_eq!(mesh.n_active(), n_before);
            assert_eq!(refine_and_coarsen_at(&mut mesh, &[], &[], inner), n_after);
        }
    }

    /// `do_not_produce_unrefined_islands` on a 3 × 1 strip refined once (12 cells): coarsening
    /// the middle cell, both of whose neighbours stay refined, is refused (without the flag:
    /// 9 cells); a boundary cell needs every neighbour refined, so the left and middle cells
    /// coarsen together (6 cells).
    #[test]
    fn coarsening_into_an_unrefined_island_is_refused() {
        let s = smoothing(&[SmoothingName::DoNotProduceUnrefinedIslands]);
        for (coarsened, s, n_active) in [
            (vec![(1, 0)], MeshSmoothing::default(), 9),
            (vec![(1, 0)], s, 12),
            (vec![(0, 0), (1, 0)], s, 6),
        ] {
            let mut mesh = Mesh::new([0.0, 3.0], [0.0, 1.0], 3, 1);
            mesh.refine_global().unwrap();
            let n = refine_and_coarsen_at(&mut mesh, &[], &coarsened, s);
            assert_eq!(n, n_active, "{coarsened:?} {s:?}");
        }
    }

    /// `do_not_produce_unrefined_islands` inside the domain and its cascade: a 3 × 3 grid
    /// refined once (36 cells), the centre and its left neighbour flagged for coarsening. The
    /// centre would have three of four neighbours refined (all but one: refused); then the
    /// left cell has all three neighbours refined (refused too). Without the flag: 30 cells.
    #[test]
    fn unrefined_islands_cascade() {
        let s = smoothing(&[SmoothingName::DoNotProduceUnrefinedIslands]);
        for (s, n_active) in [(MeshSmoothing::default(), 30), (s, 36)] {
            let mut mesh = Mesh::new([0.0, 3.0], [0.0, 3.0], 3, 3);
            mesh.refine_global().unwrap();
            let n = refine_and_coarsen_at(&mut mesh, &[], &[(0, 1), (1, 1)], s);
            assert_eq!(n, n_active, "{s:?}");
        }
    }

    /// `maximum_smoothing` sets the coarsening flags too, but `patch_level_1` switches them
    /// off: on a 3 × 3 grid refined twice, with one cell flagged for refinement and the
    /// sixteen grandchildren of the centre and of a corner cell for coarsening, it flags
    /// exactly as the four refinement flags do.
    #[test]
    fn maximum_smoothing_acts_as_the_refinement_flags() {
        let max = smoothing(&[SmoothingName::MaximumSmoothing]);
        let four = smoothing(&[
            SmoothingName::LimitLevelDifferenceAtVertices,
            SmoothingName::EliminateUnrefinedIslands,
            SmoothingName::PatchLevel1,
            SmoothingName::CoarsestLevel1,
        ]);
        assert_ne!(max, four);
        let mut mesh = Mesh::new([0.0, 3.0], [0.0, 3.0], 3, 3);
        mesh.refine_global().unwrap();
        mesh.refine_global().unwrap();
        let w = Mesh::width(0);
        let grand = [mesh.descend(w, w, 0), mesh.descend(0, 0, 0)];
        let refine: Vec<bool> = (0..mesh.n_active()).map(|k| k == 70).collect();
        let coarsen: Vec<bool> = mesh
            .active()
            .iter()
            .map(|&c| grand.contains(&mesh.ancestor_at(c, 0)))
            .collect();
        let (r_max, c_max) = mesh.smooth_flags(&refine, &coarsen, max);
        assert_eq!((r_max, c_max), mesh.smooth_flags(&refine, &coarsen, four));
    }

    /// Names: the combinations expand to deal.II's values.
    #[test]
    fn names_expand() {
        let all: Vec<SmoothingName> = SmoothingName::ALL[..7].to_vec();
        assert_eq!(
            smoothing(&[SmoothingName::MaximumSmoothing]),
            smoothing(&all)
        );
        assert_eq!(
            smoothing(&[SmoothingName::SmoothingOnCoarsening]),
            smoothing(&SmoothingName::ALL[4..7])
        );
        assert_eq!(
            smoothing(&[SmoothingName::SmoothingOnRefinement]),
            smoothing(&SmoothingName::ALL[..2])
        );
        assert!(MeshSmoothing::default().is_empty());
    }
}
