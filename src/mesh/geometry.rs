//! The physical shape of a cell (the bilinear map of the reference square) and its 2×2
//! algebra: points, Jacobians, reference coordinates, areas, faces and normals.

use nalgebra::{Matrix2, RowVector2, Vector2};

use super::Face;

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
    pub(super) fn reference_by_newton(&self, p: [f64; 2]) -> (f64, f64) {
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
