//! Q₁ on the bilinear map of one cell (deal.II `FEValues`, Ferrite `CellValues`): shape values,
//! physical gradients, weights, Jacobian determinants and points at the quadrature points of a
//! cell, evaluation of a Q₁ field at any reference point, and its Hessian.
//!
//! The element is isoparametric: on the cell `x(ξ, η) = Σ_a x_a φ̂_a(ξ, η)` with the bilinear
//! shape functions φ̂_a of the reference square (II.45), and φ_a = φ̂_a ∘ x⁻¹. On a rectangle
//! ([`CellShape::Rectangle`], every cell of an unmoved mesh) the map is affine and diagonal and
//! everything is computed with the rectangle's own closed formulas — the same arithmetic as the
//! assemblers and estimators have always used there, so results on rectangles do not depend on
//! which branch a quadrilateral needs. On a general quadrilateral gradients are J⁻ᵀ∇̂φ̂ and
//! J×W = w·det J. The 2×2 algebra of the map (J, det J, its cofactor matrix) is on nalgebra's
//! fixed-size types, every entry computed by the same expression as the closed formulas.

use nalgebra::Vector2;

use crate::mesh::{bilinear, bilinear_gradients, cofactor, CellShape};

/// Q₁ on one cell at the `N` points of a quadrature rule. Each quantity is computed when asked
/// for, so a caller pays only for what it uses (an estimator that needs values and weights does
/// not compute gradients).
#[derive(Clone, Copy, Debug)]
pub struct CellValues<'a, const N: usize> {
    shape: CellShape,
    rule: &'a [(f64, f64, f64); N],
}

impl<'a, const N: usize> CellValues<'a, N> {
    /// The cell `shape` at the points of `rule` (`(ξ, η, weight)`, e.g.
    /// [`super::quadrature::square_rule`]).
    pub fn new(shape: CellShape, rule: &'a [(f64, f64, f64); N]) -> CellValues<'a, N> {
        CellValues { shape, rule }
    }

    pub fn shape(&self) -> &CellShape {
        &self.shape
    }

    /// Reference coordinates (ξ, η) of point q.
    #[inline]
    pub fn reference(&self, q: usize) -> (f64, f64) {
        (self.rule[q].0, self.rule[q].1)
    }

    /// φ_a at point q (a = 0…3, lexicographic vertices).
    #[inline]
    pub fn values(&self, q: usize) -> [f64; 4] {
        let (xi, eta) = self.reference(q);
        bilinear(xi, eta)
    }

    /// ∇φ_a at point q.
    #[inline]
    pub fn gradients(&self, q: usize) -> [[f64; 2]; 4] {
        let (xi, eta) = self.reference(q);
        gradients(&self.shape, xi, eta)
    }

    /// Quadrature weight of point q on the reference square.
    #[inline]
    pub fn weight(&self, q: usize) -> f64 {
        self.rule[q].2
    }

    /// det J at point q (the area of a rectangle).
    #[inline]
    pub fn det(&self, q: usize) -> f64 {
        let (xi, eta) = self.reference(q);
        det_j(&self.shape, xi, eta)
    }

    /// w_q · det J(x_q), the physical weight of point q.
    #[inline]
    pub fn jxw(&self, q: usize) -> f64 {
        self.weight(q) * self.det(q)
    }

    /// Physical position of point q.
    #[inline]
    pub fn point(&self, q: usize) -> [f64; 2] {
        let (xi, eta) = self.reference(q);
        self.shape.point(xi, eta)
    }

    /// ∫_Q f ≈ Σ_q f(q)·w_q·det J(x_q). On a rectangle det J is the same at every point and is
    /// factored out of the sum: (Σ_q f(q)·w_q)·|Q|.
    pub fn integrate(&self, f: impl Fn(usize) -> f64) -> f64 {
        match self.shape {
            CellShape::Rectangle { .. } => {
                let mut sum = 0.0;
                for q in 0..N {
                    sum += f(q) * self.weight(q);
                }
                sum * self.det(0)
            }
            CellShape::Quadrilateral(_) => {
                let mut sum = 0.0;
                for q in 0..N {
                    sum += f(q) * self.weight(q) * self.det(q);
                }
                sum
            }
        }
    }

    /// Value of the Q₁ field with vertex values `u` at point q.
    #[inline]
    pub fn value(&self, u: [f64; 4], q: usize) -> f64 {
        let phi = self.values(q);
        u[0] * phi[0] + u[1] * phi[1] + u[2] * phi[2] + u[3] * phi[3]
    }
}

/// Determinant of the Jacobian at (ξ, η) (the area on a rectangle).
#[inline]
fn det_j(shape: &CellShape, xi: f64, eta: f64) -> f64 {
    match *shape {
        CellShape::Rectangle { x0, y0, x1, y1 } => (x1 - x0) * (y1 - y0),
        CellShape::Quadrilateral(_) => shape.jacobian(xi, eta).determinant(),
    }
}

/// Physical gradients of the four shape functions at the reference point (ξ, η).
#[inline(always)]
pub fn gradients(shape: &CellShape, xi: f64, eta: f64) -> [[f64; 2]; 4] {
    match *shape {
        CellShape::Rectangle { x0, y0, x1, y1 } => {
            let (hx, hy) = (x1 - x0, y1 - y0);
            [
                [-(1.0 - eta) / hx, -(1.0 - xi) / hy],
                [(1.0 - eta) / hx, -xi / hy],
                [-eta / hx, (1.0 - xi) / hy],
                [eta / hx, xi / hy],
            ]
        }
        CellShape::Quadrilateral(_) => {
            let j = shape.jacobian(xi, eta);
            let (cof, det) = (cofactor(&j), j.determinant());
            bilinear_gradients(xi, eta).map(|g| (cof * Vector2::from(g) / det).into())
        }
    }
}

/// Value and gradient of the Q₁ field with vertex values `u` at the reference point (ξ, η).
#[inline(always)]
pub fn evaluate(shape: &CellShape, u: [f64; 4], xi: f64, eta: f64) -> (f64, [f64; 2]) {
    let v = bilinear(xi, eta);
    let g = gradients(shape, xi, eta);
    let mut val = 0.0;
    let mut grad = [0.0; 2];
    for i in 0..4 {
        val += u[i] * v[i];
        grad[0] += u[i] * g[i][0];
        grad[1] += u[i] * g[i][1];
    }
    (val, grad)
}

/// Value and gradient of the Q₁ field with vertex values `u` at the physical point `p` of the
/// cell.
#[inline(always)]
pub fn evaluate_at(shape: &CellShape, u: [f64; 4], p: [f64; 2]) -> (f64, [f64; 2]) {
    let (xi, eta) = shape.reference(p);
    evaluate(shape, u, xi, eta)
}

/// Hessian ∇²u_h of the Q₁ field with vertex values `u` at the reference point (ξ, η).
///
/// On a rectangle only the mixed derivative ∂₁∂₂u_h = Σ_a u_a ∂₁∂₂φ_a is non-zero, constant
/// (±1/(h_x h_y)). On a quadrilateral, differentiating ∂φ/∂ξ_a = Σ_k J_ka ∂φ/∂x_k once more gives
/// ∇̂²u = Jᵀ(∇²u)J + Σ_k ∂_k u ∇̂²x_k, where the only reference second derivatives of a bilinear
/// function are the mixed ones: ∇²u = J⁻ᵀ(∇̂²u − Σ_k ∂_k u ∇̂²x_k)J⁻¹.
pub fn hessian(shape: &CellShape, u: [f64; 4], xi: f64, eta: f64) -> [[f64; 2]; 2] {
    match *shape {
        CellShape::Rectangle { x0, y0, x1, y1 } => {
            let d = 1.0 / ((x1 - x0) * (y1 - y0));
            let m = [d, -d, -d, d];
            let d12 = (0..4).map(|i| u[i] * m[i]).sum::<f64>();
            [[0.0, d12], [d12, 0.0]]
        }
        CellShape::Quadrilateral(x) => {
            let mixed = |v: [f64; 4]| v[0] - v[1] - v[2] + v[3];
            let (_, g) = evaluate(shape, u, xi, eta);
            let m = mixed(u) - g[0] * mixed(x.map(|p| p[0])) - g[1] * mixed(x.map(|p| p[1]));
            let j = shape.jacobian(xi, eta);
            // K = J⁻¹; H_ij = Σ_ab K_ai M_ab K_bj with M = [[0, m], [m, 0]].
            let k = cofactor(&j).transpose() / j.determinant();
            let h = |i: usize, jj: usize| m * (k[(0, i)] * k[(1, jj)] + k[(1, i)] * k[(0, jj)]);
            [[h(0, 0), h(0, 1)], [h(1, 0), h(1, 1)]]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::quadrature::square_rule;

    fn quad() -> CellShape {
        CellShape::Quadrilateral([[0.1, -0.2], [1.3, 0.1], [-0.1, 0.9], [1.1, 1.4]])
    }

    #[test]
    fn quadrilateral_reproduces_linear_fields_and_its_area() {
        let shape = quad();
        let lin = |p: [f64; 2]| 0.3 - 1.7 * p[0] + 2.5 * p[1];
        let u = shape.vertices().map(lin);
        let rule = square_rule::<9>();
        let cv = CellValues::new(shape, &rule);
        let mut area = 0.0;
        for q in 0..9 {
            let g: [f64; 2] = (0..4).fold([0.0, 0.0], |a, i| {
                [
                    a[0] + u[i] * cv.gradients(q)[i][0],
                    a[1] + u[i] * cv.gradients(q)[i][1],
                ]
            });
            assert!(
                (g[0] + 1.7).abs() < 1e-13 && (g[1] - 2.5).abs() < 1e-13,
                "{g:?}"
            );
            assert!((cv.value(u, q) - lin(cv.point(q))).abs() < 1e-13);
            area += cv.jxw(q);
        }
        assert!((area - shape.area()).abs() < 1e-13);
        let p = [0.55, 0.45];
        let (xi, eta) = shape.reference(p);
        let back = shape.point(xi, eta);
        assert!((back[0] - p[0]).abs() < 1e-14 && (back[1] - p[1]).abs() < 1e-14);
        let h = hessian(&shape, u, xi, eta);
        assert!(h.iter().flatten().all(|v| v.abs() < 1e-12), "{h:?}");
    }

    #[test]
    fn quadrilateral_hessian_matches_finite_differences() {
        let shape = quad();
        let u = [0.3, -1.1, 0.7, 2.0];
        let (xi, eta) = (0.35, 0.6);
        let p = shape.point(xi, eta);
        let grad_at = |q: [f64; 2]| evaluate_at(&shape, u, q).1;
        let h = hessian(&shape, u, xi, eta);
        let e = 1e-6;
        for k in 0..2 {
            let mut a = p;
            let mut b = p;
            a[k] -= e;
            b[k] += e;
            let (ga, gb) = (grad_at(a), grad_at(b));
            for i in 0..2 {
                let fd = (gb[i] - ga[i]) / (2.0 * e);
                assert!(
                    (fd - h[i][k]).abs() < 1e-6,
                    "H[{i}][{k}] = {} vs {fd}",
                    h[i][k]
                );
            }
        }
    }
}
