//! Forest of quadtrees over a coarse `nx × ny` grid of a rectangle: isotropic refinement and
//! coarsening, 2:1 balance across faces, hanging vertices.
//!
//! Positions are integers: a coarse cell is `2^MAX_LEVEL` units wide, a cell of level `l` is
//! `2^(MAX_LEVEL − l)` units wide. Neighbour and vertex lookup is therefore exact, and every
//! numbering is derived from the (deterministic) depth-first order of the trees — never from the
//! iteration order of a hash map.

use crate::experiment::Side;

/// Deepest refinement level a cell can reach.
pub const MAX_LEVEL: u8 = 24;

/// Index of a cell in [`Mesh`] storage (active or not).
pub type CellId = u32;
const NONE: u32 = u32::MAX;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Cell {
    level: u8,
    /// Lower-left corner in integer units.
    x: u32,
    y: u32,
    parent: u32,
    /// First of four consecutive children (order: lower-left, lower-right, upper-left,
    /// upper-right), or `NONE` for an active cell.
    children: u32,
}

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

    fn offset(self) -> (i64, i64) {
        match self {
            Face::Left => (-1, 0),
            Face::Right => (1, 0),
            Face::Bottom => (0, -1),
            Face::Top => (0, 1),
        }
    }

    fn opposite(self) -> Face {
        match self {
            Face::Left => Face::Right,
            Face::Right => Face::Left,
            Face::Bottom => Face::Top,
            Face::Top => Face::Bottom,
        }
    }

    /// Child indices (0..4) touching this face.
    fn children(self) -> [usize; 2] {
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

/// Forest of quadtrees (see module docs).
#[derive(Clone, Debug)]
pub struct Mesh {
    /// Physical domain `[x0, x1] × [y0, y1]`.
    x0: f64,
    y0: f64,
    /// Physical size of one integer unit.
    unit_x: f64,
    unit_y: f64,
    nx: usize,
    ny: usize,
    cells: Vec<Cell>,
    /// Active cells in depth-first order (coarse cells row by row, children lexicographic).
    active: Vec<CellId>,
    /// Position of each cell in `active` (`NONE` for refined cells).
    active_index: Vec<u32>,
}

impl Mesh {
    /// Coarse `nx × ny` grid of the rectangle `[x0, x1] × [y0, y1]`.
    pub fn new(x: [f64; 2], y: [f64; 2], nx: usize, ny: usize) -> Mesh {
        assert!(nx >= 1 && ny >= 1, "coarse grid needs at least one cell");
        let size = 1u64 << MAX_LEVEL;
        assert!(
            (nx as u64) * size < u32::MAX as u64 && (ny as u64) * size < u32::MAX as u64,
            "coarse grid too large for integer coordinates"
        );
        let mut cells = Vec::with_capacity(nx * ny);
        for j in 0..ny {
            for i in 0..nx {
                cells.push(Cell {
                    level: 0,
                    x: (i as u64 * size) as u32,
                    y: (j as u64 * size) as u32,
                    parent: NONE,
                    children: NONE,
                });
            }
        }
        let active: Vec<CellId> = (0..cells.len() as u32).collect();
        let active_index = active.clone();
        Mesh {
            x0: x[0],
            y0: y[0],
            unit_x: (x[1] - x[0]) / (nx as f64 * size as f64),
            unit_y: (y[1] - y[0]) / (ny as f64 * size as f64),
            nx,
            ny,
            cells,
            active,
            active_index,
        }
    }

    /// Active cells in depth-first order.
    pub fn active(&self) -> &[CellId] {
        &self.active
    }

    /// Position of an active cell in [`Mesh::active`].
    #[inline]
    pub fn active_index(&self, c: CellId) -> usize {
        let k = self.active_index[c as usize];
        debug_assert!(k != NONE, "cell {c} is not active");
        k as usize
    }

    pub fn n_active(&self) -> usize {
        self.active.len()
    }

    pub fn coarse_cells(&self) -> [usize; 2] {
        [self.nx, self.ny]
    }

    pub fn level(&self, c: CellId) -> u8 {
        self.cells[c as usize].level
    }

    pub fn is_active(&self, c: CellId) -> bool {
        self.cells[c as usize].children == NONE
    }

    pub fn parent(&self, c: CellId) -> Option<CellId> {
        let p = self.cells[c as usize].parent;
        (p != NONE).then_some(p)
    }

    /// The four children of a refined cell.
    pub fn children(&self, c: CellId) -> Option<[CellId; 4]> {
        let f = self.cells[c as usize].children;
        (f != NONE).then_some([f, f + 1, f + 2, f + 3])
    }

    fn width(level: u8) -> u32 {
        1u32 << (MAX_LEVEL - level)
    }

    /// Integer corner positions `(x, y)` of a cell, lexicographic order.
    pub fn corner_keys(&self, c: CellId) -> [(u32, u32); 4] {
        let cell = self.cells[c as usize];
        let w = Self::width(cell.level);
        [
            (cell.x, cell.y),
            (cell.x + w, cell.y),
            (cell.x, cell.y + w),
            (cell.x + w, cell.y + w),
        ]
    }

    /// Physical position of an integer point.
    pub fn point(&self, key: (u32, u32)) -> [f64; 2] {
        [
            self.x0 + key.0 as f64 * self.unit_x,
            self.y0 + key.1 as f64 * self.unit_y,
        ]
    }

    /// Physical bounding box `[x0, y0, x1, y1]` of a cell.
    pub fn cell_box(&self, c: CellId) -> [f64; 4] {
        let cell = self.cells[c as usize];
        let w = Self::width(cell.level) as f64;
        let x0 = self.x0 + cell.x as f64 * self.unit_x;
        let y0 = self.y0 + cell.y as f64 * self.unit_y;
        [x0, y0, x0 + w * self.unit_x, y0 + w * self.unit_y]
    }

    /// Diameter h_Q (length of the diagonal), the cell size of every estimator.
    pub fn diameter(&self, c: CellId) -> f64 {
        let b = self.cell_box(c);
        (b[2] - b[0]).hypot(b[3] - b[1])
    }

    /// Extent of the domain in integer units.
    pub fn extent(&self) -> (u64, u64) {
        let size = 1u64 << MAX_LEVEL;
        (self.nx as u64 * size, self.ny as u64 * size)
    }

    /// Deepest existing cell of level ≤ `max_level` containing the integer point `(x, y)`
    /// (points on a cell's lower/left edges belong to it).
    fn descend(&self, x: u32, y: u32, max_level: u8) -> CellId {
        let size = 1u32 << MAX_LEVEL;
        let (i, j) = ((x / size) as usize, (y / size) as usize);
        let mut c = (j * self.nx + i) as u32;
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
    fn across(&self, c: CellId, face: Face) -> Option<CellId> {
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
        debug_assert_eq!(n, self.descend(nx as u32, ny as u32, cell.level));
        Some(n)
    }

    /// [`Mesh::across`] for a face known to be inside the domain: through the parent (a sibling
    /// or a child of the parent's neighbour), O(1) on average instead of a descent from the
    /// coarse cell. Same result as `descend` to the neighbour's corner at `c`'s level.
    fn across_inside(&self, c: CellId, face: Face) -> CellId {
        let cell = self.cells[c as usize];
        if cell.parent == NONE {
            let size = 1i64 << MAX_LEVEL;
            let (dx, dy) = face.offset();
            let i = cell.x as i64 / size + dx;
            let j = cell.y as i64 / size + dy;
            return (j * self.nx as i64 + i) as CellId;
        }
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
            return parent.children + (ci ^ bit);
        }
        let n = self.across_inside(cell.parent, face);
        let ncell = self.cells[n as usize];
        if ncell.children == NONE {
            n
        } else {
            ncell.children + (ci ^ bit)
        }
    }

    /// What lies across `face` of the active cell `c`.
    pub fn neighbor(&self, c: CellId, face: Face) -> Neighbor {
        let level = self.cells[c as usize].level;
        match self.across(c, face) {
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

    /// Active cell containing the physical point `p` (points on shared edges go to the cell
    /// above/right), or `None` outside the domain.
    pub fn locate(&self, p: [f64; 2]) -> Option<CellId> {
        let (ex, ey) = self.extent();
        let fx = (p[0] - self.x0) / self.unit_x;
        let fy = (p[1] - self.y0) / self.unit_y;
        let tol = 1e-9 * ex as f64;
        if !(fx > -tol && fy > -tol && fx < ex as f64 + tol && fy < ey as f64 + tol) {
            return None;
        }
        let x = (fx.round().clamp(0.0, (ex - 1) as f64)) as u32;
        let y = (fy.round().clamp(0.0, (ey - 1) as f64)) as u32;
        let x = if (fx - fx.round()).abs() < 1e-6 {
            x
        } else {
            fx.floor().clamp(0.0, (ex - 1) as f64) as u32
        };
        let y = if (fy - fy.round()).abs() < 1e-6 {
            y
        } else {
            fy.floor().clamp(0.0, (ey - 1) as f64) as u32
        };
        Some(self.descend(x, y, MAX_LEVEL))
    }

    /// Refine the active cells flagged in `refine` and coarsen complete sibling groups whose
    /// four children are all flagged in `coarsen` (flags indexed like [`Mesh::active`]).
    ///
    /// The 2:1 rule across faces is enforced as deal.II does it: refinement flags are added
    /// where a refinement would create a level difference of two, and coarsening flags are
    /// dropped where coarsening would. Level-0 cells are never coarsened. Returns the number of
    /// cells refined and the number of sibling groups coarsened.
    pub fn refine_and_coarsen(&mut self, refine: &[bool], coarsen: &[bool]) -> (usize, usize) {
        assert_eq!(refine.len(), self.active.len());
        assert_eq!(coarsen.len(), self.active.len());
        let n = self.cells.len();
        let mut ref_flag = vec![false; n];
        let mut coa_flag = vec![false; n];
        for (k, &c) in self.active.iter().enumerate() {
            ref_flag[c as usize] = refine[k];
            coa_flag[c as usize] = coarsen[k] && !refine[k];
        }
        // Closure of refinement flags under the 2:1 rule: a flagged cell of level l needs every
        // face neighbour to be of level ≥ l afterwards.
        let mut stack: Vec<CellId> = self
            .active
            .iter()
            .copied()
            .filter(|&c| ref_flag[c as usize])
            .collect();
        while let Some(c) = stack.pop() {
            let level = self.cells[c as usize].level;
            for face in FACES {
                if let Some(nb) = self.across(c, face) {
                    let ncell = self.cells[nb as usize];
                    if ncell.level < level && ncell.children == NONE && !ref_flag[nb as usize] {
                        ref_flag[nb as usize] = true;
                        coa_flag[nb as usize] = false;
                        stack.push(nb);
                    }
                }
            }
        }
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
        let n_refined = self
            .active
            .iter()
            .filter(|&&c| ref_flag[c as usize])
            .count();
        self.rebuild(&ref_flag, &coarsen_parent);
        (n_refined, n_coarsened)
    }

    /// Whether removing the children of `p` keeps the 2:1 rule, given the refinement flags.
    fn parent_may_coarsen(&self, p: CellId, ref_flag: &[bool]) -> bool {
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
    fn rebuild(&mut self, ref_flag: &[bool], coarsen_parent: &[bool]) {
        let roots = self.nx * self.ny;
        let mut cells: Vec<Cell> = self.cells[..roots].to_vec();
        for c in cells.iter_mut() {
            c.children = NONE;
        }
        // Breadth-first over levels so that children are consecutive; the active list is then
        // collected depth-first.
        let mut queue: Vec<(u32, u32)> = (0..roots as u32).map(|i| (i, i)).collect(); // (old, new)
        let mut head = 0;
        while head < queue.len() {
            let (old, new) = queue[head];
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
                    x: oc.x + half * (ci & 1),
                    y: oc.y + half * (ci >> 1),
                    parent: new,
                    children: NONE,
                });
                if keep_children {
                    queue.push((oc.children + ci, first + ci));
                }
            }
        }
        self.cells = cells;
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

    /// Refine every active cell once.
    pub fn refine_global(&mut self) {
        let r = vec![true; self.active.len()];
        let c = vec![false; self.active.len()];
        self.refine_and_coarsen(&r, &c);
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
