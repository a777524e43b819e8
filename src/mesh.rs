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

use nalgebra::{Matrix2, RowVector2, Vector2};
use rayon::prelude::*;
use serde::Deserialize;

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

/// The physical shape of a cell: the image of the reference square \[0,1\]² under the bilinear
/// map of its four vertices (lexicographic: 0 = (ξ, η) = (0, 0), 1 = (1, 0), 2 = (0, 1),
/// 3 = (1, 1)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CellShape {
    /// An axis-parallel rectangle `[x0, x1] × [y0, y1]` (every cell of a mesh whose vertices are
    /// not moved): the map is affine and diagonal, and everything is computed with the
    /// rectangle's own formulas.
    Rectangle { x0: f64, y0: f64, x1: f64, y1: f64 },
    /// A general quadrilateral given by its four vertices.
    Quadrilateral([[f64; 2]; 4]),
}

impl CellShape {
    /// The four vertices (lexicographic order).
    #[inline]
    pub fn vertices(&self) -> [[f64; 2]; 4] {
        match *self {
            CellShape::Rectangle { x0, y0, x1, y1 } => [[x0, y0], [x1, y0], [x0, y1], [x1, y1]],
            CellShape::Quadrilateral(v) => v,
        }
    }

    /// Physical point of the reference point (ξ, η).
    #[inline]
    pub fn point(&self, xi: f64, eta: f64) -> [f64; 2] {
        match *self {
            CellShape::Rectangle { x0, y0, x1, y1 } => [x0 + xi * (x1 - x0), y0 + eta * (y1 - y0)],
            CellShape::Quadrilateral(v) => {
                let phi = bilinear(xi, eta);
                let mut p = [0.0; 2];
                for (x, w) in v.iter().zip(phi) {
                    p[0] += x[0] * w;
                    p[1] += x[1] * w;
                }
                p
            }
        }
    }

    /// Jacobian J = ∂x/∂(ξ, η) at (ξ, η): `j[(i, a)] = ∂xᵢ/∂ξ_a`. On a quadrilateral
    /// J = Σ_a x_a (∇̂φ̂_a)ᵀ, the outer products added vertex by vertex (each entry is the sum
    /// of its four products in vertex order).
    #[inline]
    pub fn jacobian(&self, xi: f64, eta: f64) -> Matrix2<f64> {
        match *self {
            CellShape::Rectangle { x0, y0, x1, y1 } => Matrix2::new(x1 - x0, 0.0, 0.0, y1 - y0),
            CellShape::Quadrilateral(v) => {
                let mut j = Matrix2::zeros();
                for (x, g) in v.iter().zip(bilinear_gradients(xi, eta)) {
                    j += Vector2::from(*x) * RowVector2::from(g);
                }
                j
            }
        }
    }

    /// Reference coordinates (ξ, η) of a physical point (Newton's method on a quadrilateral; the
    /// point need not lie inside the cell).
    #[inline]
    pub fn reference(&self, p: [f64; 2]) -> (f64, f64) {
        match *self {
            CellShape::Rectangle { x0, y0, x1, y1 } => {
                ((p[0] - x0) / (x1 - x0), (p[1] - y0) / (y1 - y0))
            }
            CellShape::Quadrilateral(_) => self.reference_by_newton(p),
        }
    }

    /// [`CellShape::reference`] on a quadrilateral: Newton's method for x(ξ, η) = p from the
    /// cell's centre.
    fn reference_by_newton(&self, p: [f64; 2]) -> (f64, f64) {
        let (mut xi, mut eta) = (0.5, 0.5);
        for _ in 0..50 {
            let x = self.point(xi, eta);
            let r = [x[0] - p[0], x[1] - p[1]];
            let j = self.jacobian(xi, eta);
            // J⁻¹ r = cof(J)ᵀ r / det J.
            let d = cofactor(&j).transpose() * Vector2::from(r) / j.determinant();
            let (dxi, deta) = (d.x, d.y);
            xi -= dxi;
            eta -= deta;
            if dxi.abs().max(deta.abs()) <= 1e-15 {
                break;
            }
        }
        (xi, eta)
    }

    /// Area of the cell.
    pub fn area(&self) -> f64 {
        match *self {
            CellShape::Rectangle { x0, y0, x1, y1 } => (x1 - x0) * (y1 - y0),
            CellShape::Quadrilateral(v) => {
                // Shoelace formula over the counter-clockwise boundary 0, 1, 3, 2.
                let ring = [v[0], v[1], v[3], v[2]];
                (0..4)
                    .map(|i| {
                        let (a, b) = (ring[i], ring[(i + 1) % 4]);
                        a[0] * b[1] - b[0] * a[1]
                    })
                    .sum::<f64>()
                    * 0.5
            }
        }
    }

    /// Diameter h_Q: the largest distance between two vertices (the diagonal of a rectangle),
    /// the cell size of every estimator.
    #[inline]
    pub fn diameter(&self) -> f64 {
        match *self {
            CellShape::Rectangle { x0, y0, x1, y1 } => (x1 - x0).hypot(y1 - y0),
            CellShape::Quadrilateral(v) => {
                let mut d = 0.0f64;
                for a in 0..4 {
                    for b in a + 1..4 {
                        d = d.max((v[b][0] - v[a][0]).hypot(v[b][1] - v[a][1]));
                    }
                }
                d
            }
        }
    }

    /// The end points of a face, in increasing reference coordinate.
    #[inline]
    pub fn face_vertices(&self, face: Face) -> [[f64; 2]; 2] {
        let v = self.vertices();
        let [a, b] = face.vertices();
        [v[a], v[b]]
    }

    /// Length of a face.
    pub fn face_length(&self, face: Face) -> f64 {
        match *self {
            CellShape::Rectangle { x0, y0, x1, y1 } => match face {
                Face::Left | Face::Right => y1 - y0,
                Face::Bottom | Face::Top => x1 - x0,
            },
            CellShape::Quadrilateral(_) => {
                let [a, b] = self.face_vertices(face);
                (b[0] - a[0]).hypot(b[1] - a[1])
            }
        }
    }

    /// Outward unit normal of a (straight) face.
    #[inline]
    pub fn face_normal(&self, face: Face) -> [f64; 2] {
        match self {
            CellShape::Rectangle { .. } => face.normal(),
            CellShape::Quadrilateral(_) => {
                let [a, b] = self.face_vertices(face);
                let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
                let len = dx.hypot(dy);
                // The face runs in increasing reference coordinate: for x⁻ and y⁺ the outward
                // normal is the tangent turned counter-clockwise, for x⁺ and y⁻ clockwise.
                match face {
                    Face::Left | Face::Top => [-dy / len, dx / len],
                    Face::Right | Face::Bottom => [dy / len, -dx / len],
                }
            }
        }
    }
}

/// The bilinear shape functions of the reference square at (ξ, η), lexicographic vertex order.
#[inline]
pub fn bilinear(xi: f64, eta: f64) -> [f64; 4] {
    [
        (1.0 - xi) * (1.0 - eta),
        xi * (1.0 - eta),
        (1.0 - xi) * eta,
        xi * eta,
    ]
}

/// Reference gradients ∂/∂(ξ, η) of [`bilinear`].
#[inline]
pub fn bilinear_gradients(xi: f64, eta: f64) -> [[f64; 2]; 4] {
    [
        [-(1.0 - eta), -(1.0 - xi)],
        [1.0 - eta, -xi],
        [-eta, 1.0 - xi],
        [eta, xi],
    ]
}

/// The cofactor matrix cof(J) = det J · J⁻ᵀ of a 2×2 matrix: J⁻ᵀ without the division, which
/// the callers apply last, to the product (J⁻ᵀ∇̂φ̂ = cof(J) ∇̂φ̂ / det J; J⁻¹ = cof(J)ᵀ / det J).
#[inline]
pub fn cofactor(j: &Matrix2<f64>) -> Matrix2<f64> {
    Matrix2::new(j.m22, -j.m21, -j.m12, j.m11)
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

/// The cell across each face of every cell of a mesh ([`Mesh::face_neighbors`]): the
/// same-level cell there or the coarser active one, none at the boundary.
#[derive(Clone, Debug)]
pub struct FaceNeighbors {
    across: Vec<[CellId; 4]>,
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

/// The identity of a mesh's storage: a stamp that no other storage in the process has (a clone
/// keeps it: same cells, same ids), and after a refinement ([`Mesh::refine_and_coarsen`]) the
/// stamp of the storage it was rebuilt from with the id each cell had there (`NONE` for a cell
/// the refinement created). It lets the next cycle find the cells it kept without searching
/// their positions ([`Mesh::kept_from`]).
#[derive(Clone, Debug)]
struct Lineage {
    stamp: u64,
    before: Option<(u64, Vec<CellId>)>,
}

impl Lineage {
    /// The lineage of new storage, rebuilt from the storage stamped `before` (with the old id of
    /// each cell), or of none.
    fn new(before: Option<(u64, Vec<CellId>)>) -> Lineage {
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
    stamp: u64,
    active_index: Vec<u32>,
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
    ) -> Result<Mesh, String> {
        if vertices.len() != (nx + 1) * (ny + 1) {
            return Err(format!(
                "a {nx} × {ny} coarse grid has {} vertices, not {}",
                (nx + 1) * (ny + 1),
                vertices.len()
            ));
        }
        if let Some(i) = vertices
            .iter()
            .position(|p| !(p[0].is_finite() && p[1].is_finite()))
        {
            return Err(format!(
                "coarse vertex {i} is not finite: {:?}",
                vertices[i]
            ));
        }
        let mut mesh =
            Mesh::try_new([0.0, nx as f64], [0.0, ny as f64], nx, ny).map_err(|e| e.to_string())?;
        mesh.moved = Some(vertices);
        for c in 0..(nx * ny) as CellId {
            let shape = mesh.cell_shape(c);
            for (xi, eta) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
                let det = shape.jacobian(xi, eta).determinant();
                if det.is_nan() || det <= 0.0 {
                    let (i, jj) = (c as usize % nx, c as usize / nx);
                    return Err(format!(
                        "coarse cell ({i}, {jj}) is folded or degenerate: det J = {det:.3e} at \
                         its corner (ξ, η) = ({xi}, {eta})"
                    ));
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

    /// Deepest existing cell of level ≤ `max_level` containing the integer point `(x, y)`
    /// (points on a cell's lower/left edges belong to it).
    fn descend(&self, x: u64, y: u64, max_level: u8) -> CellId {
        let size = Self::width(0);
        let (i, j) = ((x / size) as usize, (y / size) as usize);
        self.descend_from((j * self.nx + i) as u32, x, y, max_level)
    }

    /// [`Mesh::descend`] from the cell `c`, which contains `(x, y)`.
    fn descend_from(&self, mut c: CellId, x: u64, y: u64, max_level: u8) -> CellId {
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
        debug_assert_eq!(n, self.descend(nx as u64, ny as u64, cell.level));
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
        self.across_child(c, face, |parent| Some(self.across_inside(parent, face)))
            .expect("inside the domain")
    }

    /// [`Mesh::across`] for the child `c` given what lies across the same face of its parent
    /// (`parent_across(parent)`, `None` at the boundary): a sibling, or the parent's neighbour
    /// where that is a leaf, or the child of it next to `c`.
    #[inline]
    fn across_child(
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
    fn neighbor_across(&self, c: CellId, face: Face, across: Option<CellId>) -> Neighbor {
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

    /// [`Mesh::across`] of every cell and face at once, top-down: the cells are stored level
    /// after level (breadth-first, [`Mesh::truncated`] relies on it too), and a child's
    /// neighbour follows from its parent's ([`Mesh::across_child`]), so each level is one
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
    fn locate_moved(&self, p: [f64; 2]) -> Option<CellId> {
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
    /// `n_cells` is the number of cells afterwards: the new storage is allocated once, at its
    /// size (grown by doubling, it could hold up to twice as many cells as the mesh has, next to
    /// the old storage).
    fn rebuild(&mut self, ref_flag: &[bool], coarsen_parent: &[bool], n_cells: usize) {
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
    fn collect_active(&mut self) {
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
    /// breadth-first by level ([`Mesh::rebuild`]), so the coarser mesh is a prefix of it with
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
