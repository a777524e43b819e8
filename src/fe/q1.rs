//! The bilinear element Q₁ (II.45) on an axis-parallel rectangle.
//!
//! Local vertices are numbered lexicographically: 0 = (x₀,y₀), 1 = (x₁,y₀), 2 = (x₀,y₁),
//! 3 = (x₁,y₁). Reference coordinates (ξ, η) ∈ \[0,1\]².

/// Values of the four shape functions at (ξ, η).
#[inline]
pub fn values(xi: f64, eta: f64) -> [f64; 4] {
    [
        (1.0 - xi) * (1.0 - eta),
        xi * (1.0 - eta),
        (1.0 - xi) * eta,
        xi * eta,
    ]
}

/// Physical gradients of the four shape functions at (ξ, η) on a cell of size hx × hy.
#[inline]
pub fn gradients(xi: f64, eta: f64, hx: f64, hy: f64) -> [[f64; 2]; 4] {
    [
        [-(1.0 - eta) / hx, -(1.0 - xi) / hy],
        [(1.0 - eta) / hx, -xi / hy],
        [-eta / hx, (1.0 - xi) / hy],
        [eta / hx, xi / hy],
    ]
}

/// The constant mixed derivative ∂₁∂₂ of each shape function (the only second derivative of a
/// bilinear function that is not zero).
#[inline]
pub fn mixed_derivatives(hx: f64, hy: f64) -> [f64; 4] {
    let d = 1.0 / (hx * hy);
    [d, -d, -d, d]
}

/// A cell as seen by the element: lower-left corner and size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    pub x0: f64,
    pub y0: f64,
    pub hx: f64,
    pub hy: f64,
}

impl Rect {
    /// From a box `[x0, y0, x1, y1]`.
    pub fn from_box(b: [f64; 4]) -> Rect {
        Rect {
            x0: b[0],
            y0: b[1],
            hx: b[2] - b[0],
            hy: b[3] - b[1],
        }
    }

    /// Physical point of reference coordinates (ξ, η).
    #[inline]
    pub fn point(&self, xi: f64, eta: f64) -> [f64; 2] {
        [self.x0 + xi * self.hx, self.y0 + eta * self.hy]
    }

    /// Reference coordinates of a physical point.
    #[inline]
    pub fn reference(&self, p: [f64; 2]) -> (f64, f64) {
        ((p[0] - self.x0) / self.hx, (p[1] - self.y0) / self.hy)
    }

    pub fn area(&self) -> f64 {
        self.hx * self.hy
    }

    /// Diameter h_Q (diagonal length).
    pub fn diameter(&self) -> f64 {
        self.hx.hypot(self.hy)
    }

    /// Value and gradient of the Q₁ function with corner values `u` at (ξ, η).
    #[inline]
    pub fn eval(&self, u: [f64; 4], xi: f64, eta: f64) -> (f64, [f64; 2]) {
        let v = values(xi, eta);
        let g = gradients(xi, eta, self.hx, self.hy);
        let mut val = 0.0;
        let mut grad = [0.0; 2];
        for i in 0..4 {
            val += u[i] * v[i];
            grad[0] += u[i] * g[i][0];
            grad[1] += u[i] * g[i][1];
        }
        (val, grad)
    }
}
