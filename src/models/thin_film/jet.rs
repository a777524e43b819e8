//! [`Jet`]: forward-mode 2-D Taylor jets up to third order, with the arithmetic of the source
//! terms and loads.

use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub};

/// Second-order tensor with every entry `NaN` ("unknown").
const NAN2: [[f64; 2]; 2] = [[f64::NAN; 2]; 2];
/// Third-order tensor with every entry `NaN` ("unknown").
const NAN3: [[[f64; 2]; 2]; 2] = [[[f64::NAN; 2]; 2]; 2];

/// Truncated 2-D Taylor jet of a function f(x₁, x₂) at one point:
/// `v` = f, `d[i]` = ∂ᵢf, `dd[i][j]` = ∂ᵢ∂ⱼf, `ddd[i][j][k]` = ∂ᵢ∂ⱼ∂ₖf (symmetric tensors, stored in
/// full).
///
/// Arithmetic (`+`, `-`, `*`, `/`, [`Jet::recip`], [`Jet::compose`]) is exact up to third order
/// (Leibniz rule / Faà di Bruno). Differentiation ([`Jet::partial`], [`Jet::laplacian`]) loses
/// orders: the orders that cannot be known are set to `NaN`, and `NaN` only ever propagates into
/// orders that are themselves unknown, because the order-k entry of a sum, product or composition
/// only depends on orders ≤ k of its operands. [`Jet::valid_order`] reports how many orders are
/// known.
///
/// The operations are always inlined, so that a formula built from them (the source terms and
/// loads of [`FilmJets`]) is one function in which the compiler sees every entry. It then
/// computes only what the result uses: entries that are never read are dropped, and a product or
/// sum with a `NaN` entry of an unknown order folds to `NaN` whatever the other operand, so the
/// unknown orders cost nothing either. Every entry that is computed is computed by the same
/// expression, to the same bits (Rust neither reorders nor contracts floating-point operations).
/// Called one by one instead, each operation computes all 15 entries and passes its 120-byte
/// operands through memory (`cargo bench --bench load`: 850–1000 ns per point for both loads of
/// an example, 380–530 with the operations inlined, 110–210 with the formulas of [`FilmJets`]
/// inlined as well).
///
/// [`FilmJets`]: super::FilmJets
#[derive(Debug, Clone, Copy)]
pub struct Jet {
    /// Value f.
    pub v: f64,
    /// Gradient ∂ᵢf.
    pub d: [f64; 2],
    /// Hessian ∂ᵢ∂ⱼf.
    pub dd: [[f64; 2]; 2],
    /// Third derivatives ∂ᵢ∂ⱼ∂ₖf.
    pub ddd: [[[f64; 2]; 2]; 2],
}

impl Jet {
    /// The zero function (all derivatives exactly zero).
    pub const ZERO: Jet = Jet::constant(0.0);

    /// A constant function: value `c`, all derivatives exactly zero.
    #[inline(always)]
    pub const fn constant(c: f64) -> Jet {
        Jet {
            v: c,
            d: [0.0; 2],
            dd: [[0.0; 2]; 2],
            ddd: [[[0.0; 2]; 2]; 2],
        }
    }

    /// The coordinate function x ↦ x_axis evaluated at `x` (`axis` ∈ {0, 1}).
    #[inline(always)]
    pub fn variable(x: [f64; 2], axis: usize) -> Jet {
        let mut r = Jet::constant(x[axis]);
        r.d[axis] = 1.0;
        r
    }

    /// A function of one coordinate only, x ↦ f(x_axis), from its derivatives
    /// `f = [f, f', f'', f''']` at the point.
    #[inline(always)]
    pub fn univariate(axis: usize, f: [f64; 4]) -> Jet {
        let mut r = Jet::constant(f[0]);
        r.d[axis] = f[1];
        r.dd[axis][axis] = f[2];
        r.ddd[axis][axis][axis] = f[3];
        r
    }

    /// Composition φ ∘ self for a scalar function φ, given `phi = [φ, φ', φ'', φ''']` evaluated at
    /// `self.v` (Faà di Bruno up to third order; exact).
    #[inline(always)]
    pub fn compose(&self, phi: [f64; 4]) -> Jet {
        let (g, gd, gdd) = (self.d, self.dd, self.ddd);
        let mut r = Jet::constant(phi[0]);
        for i in 0..2 {
            r.d[i] = phi[1] * g[i];
            for j in 0..2 {
                r.dd[i][j] = phi[2] * g[i] * g[j] + phi[1] * gd[i][j];
                for k in 0..2 {
                    r.ddd[i][j][k] = phi[3] * g[i] * g[j] * g[k]
                        + phi[2] * (gd[i][j] * g[k] + gd[i][k] * g[j] + gd[j][k] * g[i])
                        + phi[1] * gdd[i][j][k];
                }
            }
        }
        r
    }

    /// Reciprocal 1/f (exact up to third order; `NaN`/`inf` if f = 0).
    #[inline(always)]
    pub fn recip(&self) -> Jet {
        let t = 1.0 / self.v;
        let t2 = t * t;
        self.compose([t, -t2, 2.0 * t2 * t, -6.0 * t2 * t2])
    }

    /// Multiplication by a scalar.
    #[inline(always)]
    pub fn scale(&self, s: f64) -> Jet {
        let mut r = *self;
        r.v *= s;
        for i in 0..2 {
            r.d[i] *= s;
            for j in 0..2 {
                r.dd[i][j] *= s;
                for k in 0..2 {
                    r.ddd[i][j][k] *= s;
                }
            }
        }
        r
    }

    /// Partial derivative ∂_mu f (`mu` ∈ {0, 1}). The result knows one order less than `self`:
    /// its third-order entries are set to `NaN` (unknown).
    #[inline(always)]
    pub fn partial(&self, mu: usize) -> Jet {
        Jet {
            v: self.d[mu],
            d: self.dd[mu],
            dd: self.ddd[mu],
            ddd: NAN3,
        }
    }

    /// 2-D Laplacian Δf = ∂₁∂₁f + ∂₂∂₂f. The result knows two orders less than `self`: its second-
    /// and third-order entries are set to `NaN` (unknown).
    #[inline(always)]
    pub fn laplacian(&self) -> Jet {
        Jet {
            v: self.dd[0][0] + self.dd[1][1],
            d: [
                self.ddd[0][0][0] + self.ddd[1][1][0],
                self.ddd[0][0][1] + self.ddd[1][1][1],
            ],
            dd: NAN2,
            ddd: NAN3,
        }
    }

    /// Highest order k ≤ 3 such that all entries of order ≤ k are finite; `None` if the value
    /// itself is not finite.
    pub fn valid_order(&self) -> Option<usize> {
        if !self.v.is_finite() {
            return None;
        }
        if !self.d.iter().all(|x| x.is_finite()) {
            return Some(0);
        }
        if !self.dd.iter().flatten().all(|x| x.is_finite()) {
            return Some(1);
        }
        if !self.ddd.iter().flatten().flatten().all(|x| x.is_finite()) {
            return Some(2);
        }
        Some(3)
    }
}

impl Add for Jet {
    type Output = Jet;
    #[inline(always)]
    fn add(self, b: Jet) -> Jet {
        let mut r = self;
        r += b;
        r
    }
}

impl AddAssign for Jet {
    #[inline(always)]
    fn add_assign(&mut self, b: Jet) {
        self.v += b.v;
        for i in 0..2 {
            self.d[i] += b.d[i];
            for j in 0..2 {
                self.dd[i][j] += b.dd[i][j];
                for k in 0..2 {
                    self.ddd[i][j][k] += b.ddd[i][j][k];
                }
            }
        }
    }
}

impl Neg for Jet {
    type Output = Jet;
    #[inline(always)]
    fn neg(self) -> Jet {
        self.scale(-1.0)
    }
}

impl Sub for Jet {
    type Output = Jet;
    #[inline(always)]
    fn sub(self, b: Jet) -> Jet {
        self + (-b)
    }
}

impl Mul for Jet {
    type Output = Jet;
    /// Product by the Leibniz rule up to third order.
    #[inline(always)]
    fn mul(self, b: Jet) -> Jet {
        let a = self;
        let mut r = Jet::constant(a.v * b.v);
        for i in 0..2 {
            r.d[i] = a.d[i] * b.v + a.v * b.d[i];
            for j in 0..2 {
                r.dd[i][j] =
                    a.dd[i][j] * b.v + a.d[i] * b.d[j] + a.d[j] * b.d[i] + a.v * b.dd[i][j];
                for k in 0..2 {
                    r.ddd[i][j][k] = a.ddd[i][j][k] * b.v
                        + a.dd[i][j] * b.d[k]
                        + a.dd[i][k] * b.d[j]
                        + a.dd[j][k] * b.d[i]
                        + a.d[i] * b.dd[j][k]
                        + a.d[j] * b.dd[i][k]
                        + a.d[k] * b.dd[i][j]
                        + a.v * b.ddd[i][j][k];
                }
            }
        }
        r
    }
}

impl Mul<f64> for Jet {
    type Output = Jet;
    #[inline(always)]
    fn mul(self, s: f64) -> Jet {
        self.scale(s)
    }
}

impl Mul<Jet> for f64 {
    type Output = Jet;
    #[inline(always)]
    fn mul(self, a: Jet) -> Jet {
        a.scale(self)
    }
}

impl Div for Jet {
    type Output = Jet;
    /// Quotient a / b = a · (1/b).
    #[allow(clippy::suspicious_arithmetic_impl)]
    #[inline(always)]
    fn div(self, b: Jet) -> Jet {
        self * b.recip()
    }
}
