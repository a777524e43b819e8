//! Forest of quadtrees over a coarse `nx × ny` grid: isotropic refinement and coarsening, 2:1
//! balance across faces, hanging vertices, stable cell and boundary-face ids, and the geometry of
//! the cells.
//!
//! Positions are integers: a coarse cell is `2^MAX_LEVEL` units wide, a cell of level `l` is
//! `2^(MAX_LEVEL − l)` units wide. They are `u64`: a coarse grid has at most [`MAX_CELLS`] < 2³²
//! cells (the most a [`CellId`] can number), so it spans less than 2³² · 2²⁴ = 2⁵⁶ units in
//! either direction, and positions, their sums and midpoints never overflow, whatever the shape
//! of the grid (a 300 × 2 strip as well as a square). Positions below 2⁵³ (grids of fewer than
//! 2²⁹ cells in a row) are exact in `f64` too. Neighbour and vertex lookup is therefore exact,
//! and every numbering is derived from the (deterministic) depth-first order of the trees —
//! never from the iteration order of a hash map. The integer position of a cell ([`CellKey`])
//! and of a boundary face ([`BoundaryFace`]) never changes under refinement of other cells, so
//! they identify cells and faces from cycle to cycle.
//!
//! **Geometry.** The coarse grid covers a rectangle ([`Mesh::new`]), or its vertices are moved
//! ([`Mesh::with_coarse_vertices`], the moved body of a forming step): every coarse cell is then
//! the image of the reference square under the bilinear map of its four vertices, and a finer cell
//! is the image of its part of the square, again a bilinear quadrilateral ([`CellShape`]). A
//! refined mesh therefore describes the same body as its coarse grid, and the Q₁ spaces of the
//! refinements are nested (the hanging-node constraint "mean of the two ends" stays exact).

//!
//! The cell shapes are in `geometry`, faces, neighbours and point location in `neighbors`,
//! refinement, coarsening and the lineage of a mesh's storage in `refinement`, deal.II's
//! mesh-smoothing flags in `smoothing`.

mod geometry;
mod neighbors;
mod refinement;
mod smoothing;

use serde::Deserialize;

pub use geometry::{bilinear, bilinear_gradients, cofactor, CellShape};
pub use neighbors::{face_segments, Face, FaceNeighbors, FaceSegment, Neighbor, FACES};
pub use refinement::ActiveCells;
use refinement::Lineage;
pub use smoothing::{MeshSmoothing, SmoothingName};

/// Deepest refinement level a cell can reach: the mesh supports `MAX_LEVEL` refinement levels
/// below its coarse grid. Refining a cell of this level is an error
/// ([`MeshError::PastDeepestLevel`]).
pub const MAX_LEVEL: u8 = 24;

/// Index of a cell in [`Mesh`] storage (active or not).
pub type CellId = u32;
const NONE: u32 = u32::MAX;

/// Most cells a mesh can hold, active and refined together: every [`CellId`] but the one that
/// marks "none". Also the largest coarse grid (`nx · ny`), far more than fits in memory with the
/// dofs and matrices of a solve.
pub const MAX_CELLS: u64 = NONE as u64;

/// Integer position `(x, y)` of a vertex (a cell corner), in the units of the module docs.
pub type VertexKey = (u64, u64);

/// What the mesh cannot do: a coarse grid it cannot number, a refinement past its deepest level
/// or beyond [`MAX_CELLS`]. The mesh is left unchanged.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MeshError {
    #[error(
        "a coarse grid of {nx} × {ny} cells is not supported: it needs at least one cell in each \
         direction and at most {MAX_CELLS} cells in all"
    )]
    CoarseGrid { nx: usize, ny: usize },
    #[error(
        "the cell centred at ({}, {}) is marked for refinement but already has the deepest \
         level: the mesh supports {MAX_LEVEL} refinement levels",
        centre[0],
        centre[1]
    )]
    PastDeepestLevel { centre: [f64; 2] },
    #[error("refinement would make {cells} cells, more than the mesh can number ({MAX_CELLS})")]
    TooManyCells { cells: u64 },
    #[error("a {nx} × {ny} coarse grid has {expected} vertices, not {got}")]
    CoarseVertexCount {
        nx: usize,
        ny: usize,
        expected: usize,
        got: usize,
    },
    #[error("coarse vertex {index} is not finite: {vertex:?}")]
    NonFiniteVertex { index: usize, vertex: [f64; 2] },
    #[error(
        "coarse cell ({i}, {j}) is folded or degenerate: det J = {det:.3e} at its corner (ξ, η) \
         = ({xi}, {eta})"
    )]
    FoldedCell {
        i: usize,
        j: usize,
        det: f64,
        xi: f64,
        eta: f64,
    },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Cell {
    level: u8,
    /// Lower-left corner in integer units.
    x: u64,
    y: u64,
    parent: u32,
    /// First of four consecutive children (order: lower-left, lower-right, upper-left,
    /// upper-right), or `NONE` for an active cell.
    children: u32,
}

/// A side of the domain: the faces x₁ = x₀ (`Left`), x₁ = x₁ (`Right`), x₂ = y₀ (`Bottom`) and
/// x₂ = y₁ (`Top`) of the coarse grid (in integer positions, so also of a moved body).
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[serde(rename_all = "kebab-case")]
pub enum Side {
    Left,
    Right,
    Bottom,
    Top,
}

impl Side {
    /// The name used in experiment files.
    pub fn name(self) -> &'static str {
        match self {
            Side::Left => "left",
            Side::Right => "right",
            Side::Bottom => "bottom",
            Side::Top => "top",
        }
    }

    /// Whether the side runs along x₁ (bottom, top) rather than along x₂.
    pub fn is_horizontal(self) -> bool {
        matches!(self, Side::Bottom | Side::Top)
    }
}

/// A face on the domain boundary, identified by its integer position: the side, the refinement
/// level of the cells it belongs to and its first integer coordinate along the side. The id
/// stays the same from cycle to cycle while the face exists; the two faces that refinement makes
/// of it name it as their [`BoundaryFace::parent`]. Ordered along each side (a parent before its
/// first child), which is the stable geometric order of model marking (Algorithms III.2, III.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct BoundaryFace {
    pub side: Side,
    /// First integer coordinate along the side (x for bottom and top, y for left and right).
    pub start: u64,
    pub level: u8,
}

impl BoundaryFace {
    /// The boundary face of a side spanning the integer coordinates `[start, end]` along it.
    /// `end − start` must be the width of a cell of some level (a power of two, at most the
    /// coarse width) and `start` a multiple of it.
    pub fn spanning(side: Side, start: u64, end: u64) -> BoundaryFace {
        let width = end - start;
        debug_assert!(width.is_power_of_two() && width <= 1 << MAX_LEVEL);
        debug_assert_eq!(start % width, 0);
        BoundaryFace {
            side,
            start,
            level: MAX_LEVEL - width.trailing_zeros() as u8,
        }
    }

    /// Width in integer units.
    pub fn width(&self) -> u64 {
        1u64 << (MAX_LEVEL - self.level)
    }

    /// Last integer coordinate along the side.
    pub fn end(&self) -> u64 {
        self.start + self.width()
    }

    /// The face this one was made from by refinement (`None` for a face of the coarse grid).
    pub fn parent(&self) -> Option<BoundaryFace> {
        let level = self.level.checked_sub(1)?;
        let width = 2 * self.width();
        Some(BoundaryFace {
            side: self.side,
            start: self.start - self.start % width,
            level,
        })
    }

    /// The two faces refinement makes of this one, in order along the side.
    pub fn children(&self) -> [BoundaryFace; 2] {
        let half = self.width() / 2;
        [self.start, self.start + half].map(|start| BoundaryFace {
            side: self.side,
            start,
            level: self.level + 1,
        })
    }
}

/// Stable id of a cell: its level and the integer position of its lower-left corner. Unlike
/// [`CellId`] (a storage index, renumbered by every refinement) it identifies the same cell in
/// every mesh that has it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct CellKey {
    pub level: u8,
    pub x: u64,
    pub y: u64,
}

/// Forest of quadtrees (see module docs).
#[derive(Clone, Debug)]
pub struct Mesh {
    /// Physical domain `[x0, x1] × [y0, y1]` of an unmoved grid.
    x0: f64,
    y0: f64,
    /// Physical size of one integer unit of an unmoved grid.
    unit_x: f64,
    unit_y: f64,
    /// Positions of the `(nx + 1) × (ny + 1)` coarse vertices (row by row) when they are moved.
    moved: Option<Vec<[f64; 2]>>,
    nx: usize,
    ny: usize,
    cells: Vec<Cell>,
    /// Active cells in depth-first order (coarse cells row by row, children lexicographic).
    active: Vec<CellId>,
    /// Position of each cell in `active` (`NONE` for refined cells).
    active_index: Vec<u32>,
    /// Which storage this is, and which one it was rebuilt from ([`Lineage`]).
    lineage: Lineage,
}

impl Mesh {
    /// Coarse `nx × ny` grid of the rectangle `[x0, x1] × [y0, y1]`.
    ///
    /// # Panics
    ///
    /// If [`Mesh::try_new`] fails (an empty grid or more than [`MAX_CELLS`] cells): for grids
    /// known to be valid, as in tests. A grid from user input goes through `try_new`.
    pub fn new(x: [f64; 2], y: [f64; 2], nx: usize, ny: usize) -> Mesh {
        Mesh::try_new(x, y, nx, ny).unwrap_or_else(|e| panic!("{e}"))
    }

    /// Coarse `nx × ny` grid of the rectangle `[x0, x1] × [y0, y1]`, or
    /// [`MeshError::CoarseGrid`] when it is empty or has more than [`MAX_CELLS`] cells (its
    /// cells could not all be numbered by a [`CellId`]). Any grid that fits in memory is
    /// supported, however long and thin.
    pub fn try_new(x: [f64; 2], y: [f64; 2], nx: usize, ny: usize) -> Result<Mesh, MeshError> {
        let n_coarse = (nx as u64).checked_mul(ny as u64);
        if nx == 0 || ny == 0 || n_coarse.is_none_or(|n| n > MAX_CELLS) {
            return Err(MeshError::CoarseGrid { nx, ny });
        }
        let size = Self::width(0);
        let mut cells = Vec::with_capacity(nx * ny);
        for j in 0..ny {
            for i in 0..nx {
                cells.push(Cell {
                    level: 0,
                    x: i as u64 * size,
                    y: j as u64 * size,
                    parent: NONE,
                    children: NONE,
                });
            }
        }
        let active: Vec<CellId> = (0..cells.len() as u32).collect();
        let active_index = active.clone();
        Ok(Mesh {
            x0: x[0],
            y0: y[0],
            unit_x: (x[1] - x[0]) / (nx as f64 * size as f64),
            unit_y: (y[1] - y[0]) / (ny as f64 * size as f64),
            moved: None,
            nx,
            ny,
            cells,
            active,
            active_index,
            lineage: Lineage::new(None),
        })
    }

    /// A coarse `nx × ny` grid whose `(nx + 1) × (ny + 1)` vertices (row by row, x fastest) lie
    /// at the given positions: every coarse cell is the bilinear quadrilateral of its four
    /// vertices (the moved body of a load step). Fails, naming the cell, where a coarse cell is
    /// folded or degenerate (det J ≤ 0 at a corner; det J of a bilinear map is affine in each
    /// reference coordinate, so the corners decide).
    pub fn with_coarse_vertices(
        nx: usize,
        ny: usize,
        vertices: Vec<[f64; 2]>,
    ) -> Result<Mesh, MeshError> {
        if vertices.len() != (nx + 1) * (ny + 1) {
            return Err(MeshError::CoarseVertexCount {
                nx,
                ny,
                expected: (nx + 1) * (ny + 1),
                got: vertices.len(),
            });
        }
        if let Some(i) = vertices
            .iter()
            .position(|p| !(p[0].is_finite() && p[1].is_finite()))
        {
            return Err(MeshError::NonFiniteVertex {
                index: i,
                vertex: vertices[i],
            });
        }
        let mut mesh = Mesh::try_new([0.0, nx as f64], [0.0, ny as f64], nx, ny)?;
        mesh.moved = Some(vertices);
        for c in 0..(nx * ny) as CellId {
            let shape = mesh.cell_shape(c);
            for (xi, eta) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
                let det = shape.jacobian(xi, eta).determinant();
                if det.is_nan() || det <= 0.0 {
                    let (i, jj) = (c as usize % nx, c as usize / nx);
                    return Err(MeshError::FoldedCell {
                        i,
                        j: jj,
                        det,
                        xi,
                        eta,
                    });
                }
            }
        }
        Ok(mesh)
    }

    /// The integer positions of the `(nx + 1) × (ny + 1)` coarse vertices, row by row, x fastest
    /// (the order of [`Mesh::with_coarse_vertices`]).
    pub fn coarse_vertex_keys(&self) -> Vec<VertexKey> {
        let size = Self::width(0);
        (0..=self.ny as u64)
            .flat_map(|j| (0..=self.nx as u64).map(move |i| (i * size, j * size)))
            .collect()
    }

    /// The integer positions of the two ends of a boundary face.
    pub fn face_vertex_keys(&self, f: BoundaryFace) -> [VertexKey; 2] {
        let (ex, ey) = self.extent();
        let (a, b) = (f.start, f.end());
        match f.side {
            Side::Bottom => [(a, 0), (b, 0)],
            Side::Top => [(a, ey), (b, ey)],
            Side::Left => [(0, a), (0, b)],
            Side::Right => [(ex, a), (ex, b)],
        }
    }

    /// Whether the coarse vertices are moved (cells are general quadrilaterals).
    pub fn is_moved(&self) -> bool {
        self.moved.is_some()
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

    /// The ancestor of cell `c` of level `level`, or `c` itself if it is not finer.
    pub fn ancestor_at(&self, mut c: CellId, level: u8) -> CellId {
        while self.cells[c as usize].level > level {
            c = self.cells[c as usize].parent;
        }
        c
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

    /// Width of a cell of `level` in integer units.
    fn width(level: u8) -> u64 {
        1u64 << (MAX_LEVEL - level)
    }

    /// Integer corner positions `(x, y)` of a cell, lexicographic order.
    pub fn corner_keys(&self, c: CellId) -> [VertexKey; 4] {
        let cell = self.cells[c as usize];
        let w = Self::width(cell.level);
        [
            (cell.x, cell.y),
            (cell.x + w, cell.y),
            (cell.x, cell.y + w),
            (cell.x + w, cell.y + w),
        ]
    }

    /// Physical position of an integer point. On a moved grid: the bilinear map of the coarse
    /// cell that holds it (always the same one for a given point: the lowest-numbered one, so
    /// that every cell sharing a vertex sees the same bits).
    pub fn point(&self, key: VertexKey) -> [f64; 2] {
        match &self.moved {
            None => [
                self.x0 + key.0 as f64 * self.unit_x,
                self.y0 + key.1 as f64 * self.unit_y,
            ],
            Some(v) => {
                let size = Self::width(0);
                let i = ((key.0 / size) as usize).min(self.nx - 1);
                let j = ((key.1 / size) as usize).min(self.ny - 1);
                // Offsets within the coarse cell are at most 2^MAX_LEVEL: exact in f64.
                let xi = (key.0 - i as u64 * size) as f64 / size as f64;
                let eta = (key.1 - j as u64 * size) as f64 / size as f64;
                let row = self.nx + 1;
                let corners = [
                    v[j * row + i],
                    v[j * row + i + 1],
                    v[(j + 1) * row + i],
                    v[(j + 1) * row + i + 1],
                ];
                CellShape::Quadrilateral(corners).point(xi, eta)
            }
        }
    }

    /// Physical bounding box `[x0, y0, x1, y1]` of a cell (the cell itself on an unmoved grid).
    pub fn cell_box(&self, c: CellId) -> [f64; 4] {
        if self.moved.is_some() {
            let v = self.cell_shape(c).vertices();
            let lo = |k: usize| v.iter().map(|p| p[k]).fold(f64::INFINITY, f64::min);
            let hi = |k: usize| v.iter().map(|p| p[k]).fold(f64::NEG_INFINITY, f64::max);
            return [lo(0), lo(1), hi(0), hi(1)];
        }
        let cell = self.cells[c as usize];
        let w = Self::width(cell.level) as f64;
        let x0 = self.x0 + cell.x as f64 * self.unit_x;
        let y0 = self.y0 + cell.y as f64 * self.unit_y;
        [x0, y0, x0 + w * self.unit_x, y0 + w * self.unit_y]
    }

    /// The physical shape of a cell: an axis-parallel rectangle on an unmoved grid, the bilinear
    /// quadrilateral of its vertices on a moved one.
    #[inline]
    pub fn cell_shape(&self, c: CellId) -> CellShape {
        if self.moved.is_some() {
            CellShape::Quadrilateral(self.corner_keys(c).map(|k| self.point(k)))
        } else {
            let [x0, y0, x1, y1] = self.cell_box(c);
            CellShape::Rectangle { x0, y0, x1, y1 }
        }
    }

    /// Diameter h_Q of a cell ([`CellShape::diameter`]), the cell size of every estimator.
    pub fn diameter(&self, c: CellId) -> f64 {
        self.cell_shape(c).diameter()
    }

    /// Stable id of a cell ([`CellKey`]).
    pub fn cell_key(&self, c: CellId) -> CellKey {
        let cell = self.cells[c as usize];
        CellKey {
            level: cell.level,
            x: cell.x,
            y: cell.y,
        }
    }

    /// The faces of active cell `c` that lie on the domain boundary.
    pub fn boundary_faces_of(&self, c: CellId) -> impl Iterator<Item = BoundaryFace> + '_ {
        FACES
            .into_iter()
            .filter_map(move |face| self.boundary_face(c, face))
    }

    /// The boundary face of active cell `c` at `face`, if that face lies on the domain boundary.
    pub fn boundary_face(&self, c: CellId, face: Face) -> Option<BoundaryFace> {
        let Neighbor::Boundary(side) = self.neighbor(c, face) else {
            return None;
        };
        let [a, b] = face.vertices().map(|i| self.corner_keys(c)[i]);
        let (start, end) = if side.is_horizontal() {
            (a.0, b.0)
        } else {
            (a.1, b.1)
        };
        Some(BoundaryFace::spanning(side, start, end))
    }

    /// Extent of the domain in integer units.
    pub fn extent(&self) -> (u64, u64) {
        let size = Self::width(0);
        (self.nx as u64 * size, self.ny as u64 * size)
    }
}
