//! The faces of a cell, what lies across them (same level, coarser or finer cells, or the
//! boundary), and the cell containing a point, found by descending the trees.

use rayon::prelude::*;

use super::{CellId, Mesh, Side, MAX_LEVEL, NONE};

/// The four faces of a cell, in the order used everywhere: x⁻, x⁺, y⁻, y⁺.
pub const FACES: [Face; 4] = [Face::Left, Face::Right, Face::Bottom, Face::Top];

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Face {
    Left,
    Right,
    Bottom,
    Top,
}

impl Face {
    /// Outward unit normal.
    pub fn normal(self) -> [f64; 2] {
        match self {
            Face::Left => [-1.0, 0.0],
            Face::Right => [1.0, 0.0],
            Face::Bottom => [0.0, -1.0],
            Face::Top => [0.0, 1.0],
        }
    }

    /// Local vertex numbers (lexicographic: 0 = (x0,y0), 1 = (x1,y0), 2 = (x0,y1), 3 = (x1,y1))
    /// of the face's two end points, in increasing coordinate order.
    pub fn vertices(self) -> [usize; 2] {
        match self {
            Face::Left => [0, 2],
            Face::Right => [1, 3],
            Face::Bottom => [0, 1],
            Face::Top => [2, 3],
        }
    }

    /// The domain side this face lies on when it is a boundary face.
    pub fn side(self) -> Side {
        match self {
            Face::Left => Side::Left,
            Face::Right => Side::Right,
            Face::Bottom => Side::Bottom,
            Face::Top => Side::Top,
        }
    }

    pub(super) fn offset(self) -> (i64, i64) {
        match self {
            Face::Left => (-1, 0),
            Face::Right => (1, 0),
            Face::Bottom => (0, -1),
            Face::Top => (0, 1),
        }
    }

    pub(super) fn opposite(self) -> Face {
        match self {
            Face::Left => Face::Right,
            Face::Right => Face::Left,
            Face::Bottom => Face::Top,
            Face::Top => Face::Bottom,
        }
    }

    /// Child indices (0..4) touching this face.
    pub(super) fn children(self) -> [usize; 2] {
        self.vertices()
    }
}

/// What lies across a face of an active cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Neighbor {
    /// The face is on the domain boundary.
    Boundary(Side),
    /// An active cell of the same level.
    Same(CellId),
    /// An active cell one level coarser: this face is half of the neighbour's face.
    Coarser(CellId),
    /// Two active cells one level finer, in increasing coordinate order along the face.
    Finer([CellId; 2]),
}

/// The cell across each face of every cell of a mesh ([`Mesh::face_neighbors`]): the
/// same-level cell there or the coarser active one, none at the boundary.
#[derive(Clone, Debug)]
pub struct FaceNeighbors {
    pub(super) across: Vec<[CellId; 4]>,
}

impl Mesh {
    /// Deepest existing cell of level ≤ `max_level` containing the integer point `(x, y)`
    /// (points on a cell's lower/left edges belong to it).
    pub(super) fn descend(&self, x: u64, y: u64, max_level: u8) -> CellId {
        let size = Self::width(0);
        let (i, j) = ((x / size) as usize, (y / size) as usize);
        self.descend_from((j * self.nx + i) as u32, x, y, max_level)
    }

    /// [`Mesh::descend`] from the cell `c`, which contains `(x, y)`.
    pub(super) fn descend_from(&self, mut c: CellId, x: u64, y: u64, max_level: u8) -> CellId {
        loop {
            let cell = self.cells[c as usize];
            if cell.children == NONE || cell.level >= max_level {
                return c;
            }
            let half = Self::width(cell.level + 1);
            let ci = u32::from(x >= cell.x + half) + 2 * u32::from(y >= cell.y + half);
            c = cell.children + ci;
        }
    }

    /// Same-level cell across `face` (it may be active or refined), or the coarser active cell
    /// there, or `None` at the domain boundary.
    pub(super) fn across(&self, c: CellId, face: Face) -> Option<CellId> {
        let cell = self.cells[c as usize];
        let w = Self::width(cell.level) as i64;
        let (dx, dy) = face.offset();
        let nx = cell.x as i64 + dx * w;
        let ny = cell.y as i64 + dy * w;
        let (ex, ey) = self.extent();
        if nx < 0 || ny < 0 || nx >= ex as i64 || ny >= ey as i64 {
            return None;
        }
        let n = self.across_inside(c, face);
        debug_assert_eq!(n, self.descend(nx as u64, ny as u64, cell.level));
        Some(n)
    }

    /// [`Mesh::across`] for a face known to be inside the domain: through the parent (a sibling
    /// or a child of the parent's neighbour), O(1) on average instead of a descent from the
    /// coarse cell. Same result as `descend` to the neighbour's corner at `c`'s level.
    pub(super) fn across_inside(&self, c: CellId, face: Face) -> CellId {
        let cell = self.cells[c as usize];
        if cell.parent == NONE {
            let size = 1i64 << MAX_LEVEL;
            let (dx, dy) = face.offset();
            let i = cell.x as i64 / size + dx;
            let j = cell.y as i64 / size + dy;
            return (j * self.nx as i64 + i) as CellId;
        }
        self.across_child(c, face, |parent| Some(self.across_inside(parent, face)))
            .expect("inside the domain")
    }

    /// [`Mesh::across`] for the child `c` given what lies across the same face of its parent
    /// (`parent_across(parent)`, `None` at the boundary): a sibling, or the parent's neighbour
    /// where that is a leaf, or the child of it next to `c`.
    #[inline]
    pub(super) fn across_child(
        &self,
        c: CellId,
        face: Face,
        parent_across: impl FnOnce(CellId) -> Option<CellId>,
    ) -> Option<CellId> {
        let cell = self.cells[c as usize];
        let parent = self.cells[cell.parent as usize];
        let ci = c - parent.children;
        // Bit of the child index that moves along the face normal, and whether the face
        // points to the upper half.
        let (bit, up) = match face {
            Face::Left => (1, false),
            Face::Right => (1, true),
            Face::Bottom => (2, false),
            Face::Top => (2, true),
        };
        if (ci & bit == 0) == up {
            return Some(parent.children + (ci ^ bit));
        }
        let n = parent_across(cell.parent)?;
        let ncell = self.cells[n as usize];
        Some(if ncell.children == NONE {
            n
        } else {
            ncell.children + (ci ^ bit)
        })
    }

    /// What lies across `face` of the active cell `c`.
    pub fn neighbor(&self, c: CellId, face: Face) -> Neighbor {
        self.neighbor_across(c, face, self.across(c, face))
    }

    /// [`Mesh::neighbor`] read from the table of every cell's neighbours (built by
    /// [`Mesh::face_neighbors`] for this mesh): for the loops over all cells.
    #[inline]
    pub fn neighbor_in(&self, table: &FaceNeighbors, c: CellId, face: Face) -> Neighbor {
        let n = table.across[c as usize][face as usize];
        self.neighbor_across(c, face, (n != NONE).then_some(n))
    }

    /// [`Mesh::neighbor`] of `c` with `across` what [`Mesh::across`] gives.
    #[inline]
    pub(super) fn neighbor_across(
        &self,
        c: CellId,
        face: Face,
        across: Option<CellId>,
    ) -> Neighbor {
        let level = self.cells[c as usize].level;
        match across {
            None => Neighbor::Boundary(face.side()),
            Some(n) => {
                let ncell = self.cells[n as usize];
                if ncell.level < level {
                    Neighbor::Coarser(n)
                } else if ncell.children == NONE {
                    Neighbor::Same(n)
                } else {
                    let [a, b] = face.opposite().children();
                    Neighbor::Finer([ncell.children + a as u32, ncell.children + b as u32])
                }
            }
        }
    }

    /// `Mesh::across` of every cell and face at once, top-down: the cells are stored level
    /// after level (breadth-first, [`Mesh::truncated`] relies on it too), and a child's
    /// neighbour follows from its parent's (`Mesh::across_child`), so each level is one
    /// parallel pass and no query walks up the tree. The loops that visit every cell's four
    /// faces (the vertex numbering, the estimators) read it through [`Mesh::neighbor_in`].
    pub fn face_neighbors(&self) -> FaceNeighbors {
        let n = self.cells.len();
        let roots = self.nx * self.ny;
        let mut across = vec![[NONE; 4]; n];
        let entry = |a: Option<CellId>| a.unwrap_or(NONE);
        for (c, row) in across[..roots].iter_mut().enumerate() {
            *row = FACES.map(|face| entry(self.across(c as CellId, face)));
        }
        let mut start = roots;
        while start < n {
            let level = self.cells[start].level;
            let end = start + self.cells[start..].partition_point(|c| c.level == level);
            let (coarser, this) = across.split_at_mut(start);
            this[..end - start]
                .par_iter_mut()
                .enumerate()
                .for_each(|(i, row)| {
                    let c = (start + i) as CellId;
                    *row = FACES.map(|face| {
                        entry(self.across_child(c, face, |parent| {
                            let p = coarser[parent as usize][face as usize];
                            (p != NONE).then_some(p)
                        }))
                    });
                });
            start = end;
        }
        FaceNeighbors { across }
    }

    /// Active cell containing the physical point `p` (points on shared edges go to the cell
    /// above/right), or `None` outside the domain.
    pub fn locate(&self, p: [f64; 2]) -> Option<CellId> {
        if self.moved.is_some() {
            return self.locate_moved(p);
        }
        let (ex, ey) = self.extent();
        let fx = (p[0] - self.x0) / self.unit_x;
        let fy = (p[1] - self.y0) / self.unit_y;
        let tol = 1e-9 * ex as f64;
        if !(fx > -tol && fy > -tol && fx < ex as f64 + tol && fy < ey as f64 + tol) {
            return None;
        }
        let x = (fx.round().clamp(0.0, (ex - 1) as f64)) as u64;
        let y = (fy.round().clamp(0.0, (ey - 1) as f64)) as u64;
        let x = if (fx - fx.round()).abs() < 1e-6 {
            x
        } else {
            fx.floor().clamp(0.0, (ex - 1) as f64) as u64
        };
        let y = if (fy - fy.round()).abs() < 1e-6 {
            y
        } else {
            fy.floor().clamp(0.0, (ey - 1) as f64) as u64
        };
        Some(self.descend(x, y, MAX_LEVEL))
    }

    /// [`Mesh::locate`] on a moved grid: the coarse cell whose reference coordinates of `p` lie
    /// in \[0,1\]² (up to 1e-9), then down the tree by integer position.
    pub(super) fn locate_moved(&self, p: [f64; 2]) -> Option<CellId> {
        let size = Self::width(0);
        let tol = 1e-9;
        (0..(self.nx * self.ny) as CellId).find_map(|c| {
            let (xi, eta) = self.cell_shape(c).reference(p);
            let inside = |t: f64| t > -tol && t < 1.0 + tol;
            if !(inside(xi) && inside(eta)) {
                return None;
            }
            let cell = self.cells[c as usize];
            let offset = |t: f64| ((t.clamp(0.0, 1.0) * size as f64).round() as u64).min(size - 1);
            Some(self.descend(cell.x + offset(xi), cell.y + offset(eta), MAX_LEVEL))
        })
    }
}

/// A straight piece of a cell face with what lies on its other side.
#[derive(Clone, Copy, Debug)]
pub struct FaceSegment {
    pub a: [f64; 2],
    pub b: [f64; 2],
    /// Active index of the neighbouring cell, `None` on the boundary.
    pub neighbor: Option<usize>,
}

impl FaceSegment {
    pub fn length(&self) -> f64 {
        (self.b[0] - self.a[0]).hypot(self.b[1] - self.a[1])
    }

    /// Point at parameter t ∈ [0, 1].
    #[inline]
    pub fn at(&self, t: f64) -> [f64; 2] {
        [
            self.a[0] + t * (self.b[0] - self.a[0]),
            self.a[1] + t * (self.b[1] - self.a[1]),
        ]
    }
}

/// The pieces of face `face` of active cell `c`: one piece (boundary, same-level or coarser
/// neighbour) or two (two finer neighbours; hanging faces are integrated over the fine
/// sub-faces). Returns the boundary side if the face lies on one.
pub fn face_segments(mesh: &Mesh, c: CellId, face: Face) -> (Option<Side>, Vec<FaceSegment>) {
    let [pa, pb] = mesh.cell_shape(c).face_vertices(face);
    match mesh.neighbor(c, face) {
        Neighbor::Boundary(side) => (
            Some(side),
            vec![FaceSegment {
                a: pa,
                b: pb,
                neighbor: None,
            }],
        ),
        Neighbor::Same(n) | Neighbor::Coarser(n) => (
            None,
            vec![FaceSegment {
                a: pa,
                b: pb,
                neighbor: Some(mesh.active_index(n)),
            }],
        ),
        Neighbor::Finer([n0, n1]) => {
            let mid = [(pa[0] + pb[0]) / 2.0, (pa[1] + pb[1]) / 2.0];
            (
                None,
                vec![
                    FaceSegment {
                        a: pa,
                        b: mid,
                        neighbor: Some(mesh.active_index(n0)),
                    },
                    FaceSegment {
                        a: mid,
                        b: pb,
                        neighbor: Some(mesh.active_index(n1)),
                    },
                ],
            )
        }
    }
}

impl Mesh {
    /// Whether this mesh has the cell `key` (same coarse grid) and it is refined: the test of
    /// the overlay of meshes ([`crate::study::reference::overlay`]).
    pub fn refines(&self, key: super::CellKey) -> bool {
        let (ex, ey) = self.extent();
        if key.x >= ex || key.y >= ey {
            return false;
        }
        let c = self.descend(key.x, key.y, key.level);
        self.level(c) == key.level && !self.is_active(c)
    }

    /// The active cell of this mesh that contains the whole cell `key` of a mesh with the same
    /// coarse grid, or `None` where this mesh is finer there (or the cell lies outside):
    /// the point location of [`crate::study::reference`].
    pub fn active_cell_holding(&self, key: super::CellKey) -> Option<CellId> {
        let (ex, ey) = self.extent();
        if key.x >= ex || key.y >= ey {
            return None;
        }
        let c = self.descend(key.x, key.y, MAX_LEVEL);
        (self.level(c) <= key.level).then_some(c)
    }
}
