//! Data of the thin-film (Reynolds / SubStokes) examples (IV.7)–(IV.20) of Gimbel (2012), §IV.3.
//!
//! The module is self-contained (std only). It provides
//!
//! * [`Jet`]: a forward-mode 2-D Taylor jet up to third order (value, gradient, Hessian and third
//!   derivative tensor). Derivatives lower the order that is known; the unknown orders are marked
//!   with `NaN`, so any formula that needs more derivatives than its inputs carry yields `NaN`
//!   instead of a silently wrong number.
//! * [`Gap`]: the gap functions g(x₁, x₂) of the examples, with analytic derivatives up to third
//!   order.
//! * [`FilmJets`]: the general Chapter I source terms (I.47), (I.50), (I.52), (I.61), (I.65),
//!   (I.77), (I.81) evaluated from arbitrary wall data z₀, z₁, v(z₀), v(z₁), κ given as jets.
//! * [`ThinFilm`]: one example (gap, constant upper-wall velocity, lower wall z₀ = 0 at rest,
//!   κ = 0, η = ρ = 1), with per-point evaluation of those terms and of the Reynolds loads
//!   l_R (II.37) and l_{R,c} (II.39).
//! * [`example`]: the table of docs/models.md §14.
//!
//! Notation follows the thesis: `g` is the gap width, Greek indices μ, ν ∈ {1, 2} (0-based in the
//! code), Einstein summation, ∂ and Δ are 2-D tangential operators in (x₁, x₂) (docs/models.md §15 item 15).

// Index loops mirror the index notation of the thesis (sums over μ, ν); keep them.
#![allow(clippy::needless_range_loop)]

use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub};

// ---------------------------------------------------------------------------------------------
// Jet
// ---------------------------------------------------------------------------------------------

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

// ---------------------------------------------------------------------------------------------
// Gap functions
// ---------------------------------------------------------------------------------------------

/// Gap width g(x₁, x₂) = z₁ − z₀ of the fluid examples [Ch.IV §IV.3, (IV.7)–(IV.20)].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Gap {
    /// g = g0. (IV.7)–(IV.9): g0 = 0.1.
    Plain { g0: f64 },
    /// g = g0 + slope·x₁. (IV.10)–(IV.14): 0.1 + 0.05 x₁.
    Linear { g0: f64, slope: f64 },
    /// g = g0 + amplitude·sin(2π·frequency·x₁). (IV.15)–(IV.17): 0.1 + 0.07 sin(2π·2x₁).
    WaveHorizontal {
        g0: f64,
        amplitude: f64,
        frequency: f64,
    },
    /// g = g0 + amplitude·sin²(2π·frequency·x₁)·sin²(2π·frequency·x₂).
    /// (IV.18)–(IV.20): 0.1 + 0.07 sin²(2π·2x₁) sin²(2π·2x₂).
    Hill {
        g0: f64,
        amplitude: f64,
        frequency: f64,
    },
}

impl From<crate::experiment::GapShape> for Gap {
    fn from(g: crate::experiment::GapShape) -> Gap {
        use crate::experiment::GapShape as File;
        match g {
            File::Plain { g0 } => Gap::Plain { g0 },
            File::Linear { g0, slope } => Gap::Linear { g0, slope },
            File::WaveHorizontal {
                g0,
                amplitude,
                frequency,
            } => Gap::WaveHorizontal {
                g0,
                amplitude,
                frequency,
            },
            File::Hill {
                g0,
                amplitude,
                frequency,
            } => Gap::Hill {
                g0,
                amplitude,
                frequency,
            },
        }
    }
}

/// [s, s', s'', s'''] of s(t) = sin²(ω t) at t.
fn sin2_derivatives(omega: f64, t: f64) -> [f64; 4] {
    let s = (omega * t).sin();
    let (s2, c2) = (2.0 * omega * t).sin_cos();
    [
        s * s,
        omega * s2,
        2.0 * omega * omega * c2,
        -4.0 * omega * omega * omega * s2,
    ]
}

/// (min, max) of sin(t) over the closed interval [lo, hi] (exact).
fn sin_range(lo: f64, hi: f64) -> (f64, f64) {
    use std::f64::consts::{FRAC_PI_2, TAU};
    let (a, b) = (lo.min(hi), lo.max(hi));
    let (sa, sb) = (a.sin(), b.sin());
    // Does the interval contain a point t0 + 2πk?
    let hits = |t0: f64| ((a - t0) / TAU).ceil() <= ((b - t0) / TAU).floor();
    let min = if hits(-FRAC_PI_2) { -1.0 } else { sa.min(sb) };
    let max = if hits(FRAC_PI_2) { 1.0 } else { sa.max(sb) };
    (min, max)
}

impl Gap {
    /// g and its analytic derivatives up to third order at `x` (needed because R₃ (I.77) contains
    /// ∂(gΔg), docs/models.md §8.4). Inlined like the [`Jet`] operations: the loads then use the entries of
    /// the gap that are constant (zero for the plain, linear and wave gaps) as constants.
    #[inline(always)]
    pub fn jet(&self, x: [f64; 2]) -> Jet {
        use std::f64::consts::TAU;
        match *self {
            Gap::Plain { g0 } => Jet::constant(g0),
            Gap::Linear { g0, slope } => Jet::univariate(0, [g0 + slope * x[0], slope, 0.0, 0.0]),
            Gap::WaveHorizontal {
                g0,
                amplitude: a,
                frequency,
            } => {
                let w = TAU * frequency;
                let (s, c) = (w * x[0]).sin_cos();
                Jet::univariate(
                    0,
                    [g0 + a * s, a * w * c, -a * w * w * s, -a * w * w * w * c],
                )
            }
            Gap::Hill {
                g0,
                amplitude: a,
                frequency,
            } => {
                let w = TAU * frequency;
                let s1 = Jet::univariate(0, sin2_derivatives(w, x[0]));
                let s2 = Jet::univariate(1, sin2_derivatives(w, x[1]));
                Jet::constant(g0) + a * (s1 * s2)
            }
        }
    }

    /// Whether g depends on x₂. Only the hill gap does; the plain, linear and wave gaps are
    /// functions of x₁ alone, bitwise: [`Gap::jet`] reads `x[1]` for the hill only. The match is
    /// exhaustive on purpose: a new gap must say, because the Reynolds cell data evaluate the
    /// gaps that answer `false` once per distinct x₁ (`ReynoldsProblem::cell_data_reusing`).
    pub fn varies_in_x2(&self) -> bool {
        match self {
            Gap::Plain { .. } | Gap::Linear { .. } | Gap::WaveHorizontal { .. } => false,
            Gap::Hill { .. } => true,
        }
    }

    /// Whether g depends on x at all: the plain gap does not, bitwise ([`Gap::jet`] reads no
    /// coordinate), so the Reynolds cell data evaluate it once for every cell. Exhaustive on
    /// purpose, like [`Gap::varies_in_x2`].
    pub fn varies_in_x1(&self) -> bool {
        match self {
            Gap::Plain { .. } => false,
            Gap::Linear { .. } | Gap::WaveHorizontal { .. } | Gap::Hill { .. } => true,
        }
    }

    /// g(x) only.
    pub fn value(&self, x: [f64; 2]) -> f64 {
        self.jet(x).v
    }

    /// Exact minimum of g over the closed unit square [0, 1]² (Ω₂ of all fluid examples).
    pub fn min_on_unit_square(&self) -> f64 {
        self.range_on_unit_square().0
    }

    /// Exact maximum of g over the closed unit square [0, 1]².
    pub fn max_on_unit_square(&self) -> f64 {
        self.range_on_unit_square().1
    }

    /// Exact (min, max) of g over [0, 1]².
    fn range_on_unit_square(&self) -> (f64, f64) {
        self.range_on_box([0.0, 0.0, 1.0, 1.0])
    }

    /// Exact (min, max) of g over the closed box [x0, x1] × [y0, y1] given as `[x0, y0, x1, y1]`
    /// (a cell box, [`crate::mesh::Mesh::cell_box`]): for ‖g²‖_∞ on a cell in the model
    /// indicator of Theorem III.6 ([`crate::models::film_coupling`]).
    pub fn range_on_box(&self, b: [f64; 4]) -> (f64, f64) {
        use std::f64::consts::TAU;
        let [x0, y0, x1, y1] = b;
        // (min, max) of sin²(ω t) over [t0, t1]: 0 where sin changes sign or vanishes.
        let sin2_range = |omega: f64, t0: f64, t1: f64| {
            let (lo, hi) = sin_range(omega * t0, omega * t1);
            let max = (lo * lo).max(hi * hi);
            let min = if lo <= 0.0 && hi >= 0.0 {
                0.0
            } else {
                (lo * lo).min(hi * hi)
            };
            (min, max)
        };
        match *self {
            Gap::Plain { g0 } => (g0, g0),
            Gap::Linear { g0, slope } => {
                let (p, q) = (slope * x0, slope * x1);
                (g0 + p.min(q), g0 + p.max(q))
            }
            Gap::WaveHorizontal {
                g0,
                amplitude: a,
                frequency,
            } => {
                let w = TAU * frequency;
                let (lo, hi) = sin_range(w * x0, w * x1);
                let (p, q) = (a * lo, a * hi);
                (g0 + p.min(q), g0 + p.max(q))
            }
            Gap::Hill {
                g0,
                amplitude: a,
                frequency,
            } => {
                // Two independent factors in [m₁, M₁], [m₂, M₂] ⊂ [0, 1]: the product ranges
                // over [m₁m₂, M₁M₂].
                let w = TAU * frequency;
                let (m1, s1) = sin2_range(w, x0, x1);
                let (m2, s2) = sin2_range(w, y0, y1);
                let (p, q) = (a * m1 * m2, a * s1 * s2);
                (g0 + p.min(q), g0 + p.max(q))
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// General Chapter I formulas
// ---------------------------------------------------------------------------------------------

/// Which cavitation correction γ₃c to use (docs/models.md §7 and §15 item 9).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum CavitationSource {
    /// (I.61) as printed.
    #[default]
    Printed,
    /// The self-consistent reading of the derivation before (I.60): γ₃c → 2γ₃ − γ₃c.
    SelfConsistent,
    /// The source terms of the problems without cavitation: γ₃c → γ₃ and R₃c → R₃ of (I.77), so
    /// l_{R,c} = l_R. The thesis's code evidently solved and estimated its cavitation runs so:
    /// with it tribo's row-0 estimate of IV.66 (wave gap, upward velocity) is the printed 1170.7
    /// to 1e-5 and that of IV.68 (hill gap) 271.82 against 271.45, where the printed γ₃c gives
    /// 1203.5 and 287.35 (report notes of IV.66–IV.69).
    Reynolds,
}

impl From<crate::experiment::CavitationSource> for CavitationSource {
    fn from(s: crate::experiment::CavitationSource) -> CavitationSource {
        use crate::experiment::CavitationSource as File;
        match s {
            File::Printed => CavitationSource::Printed,
            File::SelfConsistent => CavitationSource::SelfConsistent,
            File::Reynolds => CavitationSource::Reynolds,
        }
    }
}

/// Wall data of a thin film at one point x ∈ Ω₂, as jets, and the derived quantities of
/// Section I.2.3 (list after (I.46)): g = z₁ − z₀, z̄ = ½(z₁ + z₀), v̄ = ½(v(z₁) + v(z₀)),
/// δv = v(z₁) − v(z₀).
///
/// Orders: with inputs known to third order, [`FilmJets::gamma3`], [`FilmJets::gamma3c`] and
/// [`FilmJets::gamma`] are known to first order, [`FilmJets::sigma3`] and [`FilmJets::r1`] to
/// second order, and [`FilmJets::r3`], [`FilmJets::r3c`] and the loads to order zero (value only).
///
/// The methods are always inlined, like the [`Jet`] operations, and so is
/// [`ThinFilm::film_jets`]: a load of [`ThinFilm`] is then one function from the gap's jet to the
/// value, in which the compiler computes only the entries the value uses (γ₃ is needed to first
/// order there, R₁ to order zero, most of every third-order product is never read) and knows the
/// wall data of the examples that are constant (z₀ = 0, v(z₀) = 0, κ = 0, the derivatives of
/// v(z₁)); each entry it computes has the same expression, so the same bits. The components are
/// computed in loops over μ rather than by `[0, 1].map(..)`, whose closure the compiler called
/// instead of inlining, with the wall data in memory (`cargo bench --bench load`: 380–530 ns per
/// point for both loads with the [`Jet`] operations alone inlined, 110–210 with this).
#[derive(Debug, Clone, Copy)]
pub struct FilmJets {
    /// Lower wall z₀.
    pub z0: Jet,
    /// Upper wall z₁.
    pub z1: Jet,
    /// Lower wall velocity v(z₀) (3 components).
    pub v0: [Jet; 3],
    /// Upper wall velocity v(z₁) (3 components).
    pub v1: [Jet; 3],
    /// Integrated in-plane body force κ_μ = ∫ f_μ dx₃ (I.40).
    pub kappa: [Jet; 2],
    /// Gap width g = z₁ − z₀.
    pub g: Jet,
    /// Gap centre z̄ = ½(z₁ + z₀).
    pub zbar: Jet,
    /// Average velocity v̄ = ½(v(z₁) + v(z₀)).
    pub vbar: [Jet; 3],
    /// Velocity difference δv = v(z₁) − v(z₀).
    pub dv: [Jet; 3],
}

impl FilmJets {
    /// Builds the derived quantities g, z̄, v̄, δv (list after (I.46)) from the wall data.
    #[inline(always)]
    pub fn from_walls(z0: Jet, z1: Jet, v0: [Jet; 3], v1: [Jet; 3], kappa: [Jet; 2]) -> FilmJets {
        let vbar = |i: usize| (v1[i] + v0[i]).scale(0.5);
        let dv = |i: usize| v1[i] - v0[i];
        FilmJets {
            z0,
            z1,
            v0,
            v1,
            kappa,
            g: z1 - z0,
            zbar: (z1 + z0).scale(0.5),
            vbar: [vbar(0), vbar(1), vbar(2)],
            dv: [dv(0), dv(1), dv(2)],
        }
    }

    /// (I.47): (γ₃)_μ = −2 ∂_ν v̄_μ ∂_ν g − 2 ∂_ν δv_μ ∂_ν z̄ − v̄_μ Δg − δv_μ Δz̄.
    #[inline(always)]
    pub fn gamma3(&self) -> [Jet; 2] {
        let (g, zb) = (self.g, self.zbar);
        let mut gamma3 = [Jet::ZERO; 2];
        for mu in 0..2 {
            let mut r = -(self.vbar[mu] * g.laplacian()) - self.dv[mu] * zb.laplacian();
            for nu in 0..2 {
                r += (self.vbar[mu].partial(nu) * g.partial(nu)).scale(-2.0);
                r += (self.dv[mu].partial(nu) * zb.partial(nu)).scale(-2.0);
            }
            gamma3[mu] = r;
        }
        gamma3
    }

    /// (I.52), (I.72): γ_μ = (γ₃)_μ + (12/g) v̄_μ (SubStokes momentum source).
    #[inline(always)]
    pub fn gamma(&self) -> [Jet; 2] {
        let mut r = self.gamma3();
        let ginv = self.g.recip();
        for mu in 0..2 {
            r[mu] += (self.vbar[mu] * ginv).scale(12.0);
        }
        r
    }

    /// (I.50), (I.73): σ₃ = −δv₃ + δv_μ ∂_μ z̄ + 2 v̄_μ ∂_μ g (SubStokes mass source).
    #[inline(always)]
    pub fn sigma3(&self) -> Jet {
        let mut r = -self.dv[2];
        for mu in 0..2 {
            r += self.dv[mu] * self.zbar.partial(mu);
            r += (self.vbar[mu] * self.g.partial(mu)).scale(2.0);
        }
        r
    }

    /// R₁ of (I.77): R₁ = g ∂_ν v̄_ν − δv_ν ∂_ν z̄.
    #[inline(always)]
    pub fn r1(&self) -> Jet {
        let mut r = Jet::ZERO;
        for nu in 0..2 {
            r += self.g * self.vbar[nu].partial(nu);
            r = r - self.dv[nu] * self.zbar.partial(nu);
        }
        r
    }

    /// R₃ of (I.77): R₃ = (g/12) ∂_ν( g ((γ₃)_ν + Δ(v̄_ν g)) ). Value only (order 0).
    #[inline(always)]
    pub fn r3(&self) -> Jet {
        let g3 = self.gamma3();
        let mut s = Jet::ZERO;
        for nu in 0..2 {
            s += (self.g * (g3[nu] + (self.vbar[nu] * self.g).laplacian())).partial(nu);
        }
        (self.g * s).scale(1.0 / 12.0)
    }

    /// (I.61): (γ₃c)_μ = (γ₃)_μ + ∂_μ∂_ν(v̄_ν g + δv_ν z̄) − (g ∂_μ∂_ν v̄_ν + z̄ ∂_μ∂_ν δv_ν)
    /// − g ∂_μ(δv₃/g) for [`CavitationSource::Printed`]; 2γ₃ − (that) for
    /// [`CavitationSource::SelfConsistent`] (docs/models.md §15 item 9); γ₃ for
    /// [`CavitationSource::Reynolds`].
    #[inline(always)]
    pub fn gamma3c(&self, source: CavitationSource) -> [Jet; 2] {
        let g3 = self.gamma3();
        match source {
            CavitationSource::Printed => self.gamma3c_printed(g3),
            CavitationSource::SelfConsistent => {
                let p = self.gamma3c_printed(g3);
                let mut r = g3;
                for mu in 0..2 {
                    r[mu] = g3[mu].scale(2.0) - p[mu];
                }
                r
            }
            CavitationSource::Reynolds => g3,
        }
    }

    /// (γ₃c)_μ of (I.61) as printed, given `g3` = γ₃.
    #[inline(always)]
    fn gamma3c_printed(&self, g3: [Jet; 2]) -> [Jet; 2] {
        let (g, zb) = (self.g, self.zbar);
        // Scalars whose μ-derivative is needed: Σ_ν ∂_ν(v̄_ν g + δv_ν z̄), Σ_ν ∂_ν v̄_ν,
        // Σ_ν ∂_ν δv_ν.
        let mut div_flux = Jet::ZERO;
        let mut div_vbar = Jet::ZERO;
        let mut div_dv = Jet::ZERO;
        for nu in 0..2 {
            div_flux += (self.vbar[nu] * g + self.dv[nu] * zb).partial(nu);
            div_vbar += self.vbar[nu].partial(nu);
            div_dv += self.dv[nu].partial(nu);
        }
        let dv3_over_g = self.dv[2] / g;
        let mut r = g3;
        for mu in 0..2 {
            r[mu] = g3[mu] + div_flux.partial(mu)
                - (g * div_vbar.partial(mu) + zb * div_dv.partial(mu))
                - g * dv3_over_g.partial(mu);
        }
        r
    }

    /// (I.65): γ_c = γ₃c + (12/g) v̄ (SubStokes-with-cavitation momentum source).
    #[inline(always)]
    pub fn gamma_c(&self, source: CavitationSource) -> [Jet; 2] {
        let mut r = self.gamma3c(source);
        let ginv = self.g.recip();
        for mu in 0..2 {
            r[mu] += (self.vbar[mu] * ginv).scale(12.0);
        }
        r
    }

    /// R₃c of (I.81): R₃c = (g/12) ∂_μ[ g Δ(g v̄_μ) + g ∂_μ∂_ν(g v̄_ν) + g (γ₃c)_μ ]; R₃ of (I.77)
    /// for [`CavitationSource::Reynolds`]. Value only.
    #[inline(always)]
    pub fn r3c(&self, source: CavitationSource) -> Jet {
        if source == CavitationSource::Reynolds {
            return self.r3();
        }
        let g = self.g;
        let g3c = self.gamma3c(source);
        let mut div_gvbar = Jet::ZERO;
        for nu in 0..2 {
            div_gvbar += (g * self.vbar[nu]).partial(nu);
        }
        let mut s = Jet::ZERO;
        for mu in 0..2 {
            let inner = (g * self.vbar[mu]).laplacian() + div_gvbar.partial(mu) + g3c[mu];
            s += (g * inner).partial(mu);
        }
        (g * s).scale(1.0 / 12.0)
    }

    /// (g/12) ∂_ν(g κ_ν) (body-force term of (I.77)).
    #[inline(always)]
    fn kappa_term(&self) -> Jet {
        let mut s = Jet::ZERO;
        for nu in 0..2 {
            s += (self.g * self.kappa[nu]).partial(nu);
        }
        (self.g * s).scale(1.0 / 12.0)
    }

    /// Right-hand side of the Reynolds equation (I.77):
    /// (g/12) ∂_μ(g² ∂_μ(ψ/g)) = δv₃ + (g/12) ∂_ν(g κ_ν) + R₁ + R₃. Value only.
    #[inline(always)]
    pub fn reynolds_rhs(&self) -> Jet {
        self.dv[2] + self.kappa_term() + self.r1() + self.r3()
    }

    /// Right-hand side of the Reynolds inequality (I.81): δv₃ + (g/12) ∂_ν(g κ_ν) + R₁ + R₃c.
    /// Value only.
    #[inline(always)]
    pub fn cavitation_rhs(&self, source: CavitationSource) -> Jet {
        self.dv[2] + self.kappa_term() + self.r1() + self.r3c(source)
    }

    /// Reynolds load (II.37), from (I.79):
    /// l_R = −12 [ δv₃/g² + ∂_ν(g κ_ν)/(12 g) + (R₁ + R₃)/g² ]. Value only.
    #[inline(always)]
    pub fn reynolds_load(&self) -> Jet {
        self.load(self.r3())
    }

    /// Reynolds-with-cavitation load l_{R,c} (II.39), from (I.82): l_R with R₃c in place of R₃.
    /// Value only.
    #[inline(always)]
    pub fn cavitation_load(&self, source: CavitationSource) -> Jet {
        self.load(self.r3c(source))
    }

    /// −12 [ δv₃/g² + ∂_ν(g κ_ν)/(12 g) + (R₁ + r)/g² ].
    #[inline(always)]
    fn load(&self, r: Jet) -> Jet {
        let g = self.g;
        let ginv2 = (g * g).recip();
        let mut div_gk = Jet::ZERO;
        for nu in 0..2 {
            div_gk += (g * self.kappa[nu]).partial(nu);
        }
        let bracket = self.dv[2] * ginv2 + (div_gk / g).scale(1.0 / 12.0) + (self.r1() + r) * ginv2;
        bracket.scale(-12.0)
    }
}

// ---------------------------------------------------------------------------------------------
// The examples
// ---------------------------------------------------------------------------------------------

/// One fluid example of §IV.3: Ω₂ = [0, 1]², lower wall z₀ = 0 at rest (v(z₀) = 0), upper wall
/// z₁ = g moving with the constant velocity `upper_wall_velocity` = δv = 2v̄, κ = 0, η = ρ = 1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThinFilm {
    /// Gap width g = z₁.
    pub gap: Gap,
    /// Upper-wall velocity v(z₁) (constant).
    pub upper_wall_velocity: [f64; 3],
}

impl ThinFilm {
    /// A film with the given gap and upper-wall velocity.
    pub const fn new(gap: Gap, upper_wall_velocity: [f64; 3]) -> ThinFilm {
        ThinFilm {
            gap,
            upper_wall_velocity,
        }
    }

    /// Wall data at `x` as jets (z₀ = 0, z₁ = g, v(z₀) = 0, v(z₁) constant, κ = 0). Inlined, so
    /// that the formulas of [`FilmJets`] see the constant data as constants.
    #[inline(always)]
    pub fn film_jets(&self, x: [f64; 2]) -> FilmJets {
        FilmJets::from_walls(
            Jet::ZERO,
            self.gap.jet(x),
            [Jet::ZERO; 3],
            self.upper_wall_velocity.map(Jet::constant),
            [Jet::ZERO; 2],
        )
    }

    /// (g, ∇g, Δg) at `x`, for the Reynolds product (II.9) (∇φ − φ∇g/g)·(∇ψ − ψ∇g/g) and the
    /// estimator of Thm III.16, ρ_Q = ‖l_R − ψ_h Δg/g‖_Q.
    pub fn gap(&self, x: [f64; 2]) -> (f64, [f64; 2], f64) {
        let j = self.gap.jet(x);
        (j.v, j.d, j.dd[0][0] + j.dd[1][1])
    }

    /// (I.47): (γ₃)_μ at `x`.
    pub fn gamma3(&self, x: [f64; 2]) -> [f64; 2] {
        self.film_jets(x).gamma3().map(|j| j.v)
    }

    /// (I.52): γ_μ = (γ₃)_μ + (12/g) v̄_μ at `x`.
    pub fn gamma(&self, x: [f64; 2]) -> [f64; 2] {
        self.film_jets(x).gamma().map(|j| j.v)
    }

    /// (I.50): σ₃ at `x`.
    pub fn sigma3(&self, x: [f64; 2]) -> f64 {
        self.film_jets(x).sigma3().v
    }

    /// R₁ of (I.77) at `x`.
    pub fn r1(&self, x: [f64; 2]) -> f64 {
        self.film_jets(x).r1().v
    }

    /// R₃ of (I.77) at `x`.
    pub fn r3(&self, x: [f64; 2]) -> f64 {
        self.film_jets(x).r3().v
    }

    /// (I.61): (γ₃c)_μ at `x` (in the reading `source`).
    pub fn gamma3c(&self, x: [f64; 2], source: CavitationSource) -> [f64; 2] {
        self.film_jets(x).gamma3c(source).map(|j| j.v)
    }

    /// (I.65): γ_c = γ₃c + (12/g) v̄ at `x`.
    pub fn gamma_c(&self, x: [f64; 2], source: CavitationSource) -> [f64; 2] {
        self.film_jets(x).gamma_c(source).map(|j| j.v)
    }

    /// R₃c of (I.81) at `x`.
    pub fn r3c(&self, x: [f64; 2], source: CavitationSource) -> f64 {
        self.film_jets(x).r3c(source).v
    }

    /// Couette flux g v̄_μ at `x` (the Dirichlet value χ(P) of (I.56) without the g³ρ term).
    pub fn couette_flux(&self, x: [f64; 2]) -> [f64; 2] {
        let g = self.gap.value(x);
        [
            0.5 * g * self.upper_wall_velocity[0],
            0.5 * g * self.upper_wall_velocity[1],
        ]
    }

    /// Reynolds load l_R (II.37) at `x` (right-hand side of ⟨ψ, φ⟩_R = ⟨l_R, φ⟩).
    pub fn reynolds_load(&self, x: [f64; 2]) -> f64 {
        self.film_jets(x).reynolds_load().v
    }

    /// Reynolds-with-cavitation load l_{R,c} (II.39) at `x`.
    pub fn cavitation_load(&self, x: [f64; 2], source: CavitationSource) -> f64 {
        self.film_jets(x).cavitation_load(source).v
    }

    /// The squeeze part −12 δv₃/g² of both loads at `x` (the δv₃ term of (I.77) and (I.81);
    /// δv₃ = v₃(z₁) because the lower wall is at rest).
    pub fn squeeze_load(&self, x: [f64; 2]) -> f64 {
        self.squeeze_load_at_gap(self.gap.value(x))
    }

    /// [`ThinFilm::squeeze_load`] where the gap g is already known.
    pub fn squeeze_load_at_gap(&self, g: f64) -> f64 {
        -12.0 * self.upper_wall_velocity[2] / (g * g)
    }
}

/// Equation labels of the fluid examples, in thesis order.
pub const EXAMPLES: [&str; 14] = [
    "IV.7", "IV.8", "IV.9", "IV.10", "IV.11", "IV.12", "IV.13", "IV.14", "IV.15", "IV.16", "IV.17",
    "IV.18", "IV.19", "IV.20",
];

/// The fluid example with thesis equation label `equation` ("IV.7" … "IV.20"; surrounding
/// parentheses are accepted), per docs/models.md §14 and thesis §IV.3.
pub fn example(equation: &str) -> Option<ThinFilm> {
    let label = equation
        .trim()
        .trim_start_matches('(')
        .trim_end_matches(')');
    let plain = Gap::Plain { g0: 0.1 };
    let linear = Gap::Linear {
        g0: 0.1,
        slope: 0.05,
    };
    let wave = Gap::WaveHorizontal {
        g0: 0.1,
        amplitude: 0.07,
        frequency: 2.0,
    };
    let hill = Gap::Hill {
        g0: 0.1,
        amplitude: 0.07,
        frequency: 2.0,
    };
    let (gap, v) = match label {
        "IV.7" => (plain, [0.0, 0.0, -10.0]),
        "IV.8" => (plain, [0.0, 0.0, 10.0]),
        "IV.9" => (plain, [10.0, 0.0, 0.0]),
        "IV.10" => (linear, [0.0, 0.0, -10.0]),
        "IV.11" => (linear, [0.0, 0.0, 10.0]),
        "IV.12" => (linear, [10.0, 0.0, 0.0]),
        "IV.13" => (linear, [-10.0, 0.0, 0.0]),
        "IV.14" => (linear, [0.0, 10.0, 0.0]),
        "IV.15" => (wave, [0.0, 0.0, -10.0]),
        "IV.16" => (wave, [0.0, 0.0, 10.0]),
        "IV.17" => (wave, [40.0, 0.0, 0.0]),
        "IV.18" => (hill, [0.0, 0.0, -10.0]),
        "IV.19" => (hill, [0.0, 0.0, 10.0]),
        "IV.20" => (hill, [1000.0, 0.0, 0.0]),
        _ => return None,
    };
    Some(ThinFilm::new(gap, v))
}

// ---------------------------------------------------------------------------------------------
// Tests
// ---------------------------------------------------------------------------------------------

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic sample points in [0, 1]² (a few fixed ones plus an LCG sequence).
    fn points(n: usize) -> Vec<[f64; 2]> {
        let mut pts = vec![
            [0.0, 0.0],
            [1.0, 1.0],
            [0.5, 0.5],
            [0.375, 0.375],
            [0.125, 0.8],
            [1.0, 0.3],
        ];
        let mut s: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut next = || {
            s = s
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        while pts.len() < n {
            pts.push([next(), next()]);
        }
        pts
    }

    fn all_gaps() -> Vec<Gap> {
        vec![
            Gap::Plain { g0: 0.1 },
            Gap::Linear {
                g0: 0.1,
                slope: 0.05,
            },
            Gap::WaveHorizontal {
                g0: 0.1,
                amplitude: 0.07,
                frequency: 2.0,
            },
            Gap::Hill {
                g0: 0.1,
                amplitude: 0.07,
                frequency: 2.0,
            },
            Gap::Hill {
                g0: 0.3,
                amplitude: -0.1,
                frequency: 0.7,
            },
        ]
    }

    /// Closed-form gap value, written independently of `Gap::jet`.
    fn gap_value(gap: &Gap, x: [f64; 2]) -> f64 {
        use std::f64::consts::PI;
        match *gap {
            Gap::Plain { g0 } => g0,
            Gap::Linear { g0, slope } => g0 + slope * x[0],
            Gap::WaveHorizontal {
                g0,
                amplitude,
                frequency,
            } => g0 + amplitude * (2.0 * PI * frequency * x[0]).sin(),
            Gap::Hill {
                g0,
                amplitude,
                frequency,
            } => {
                let a = (2.0 * PI * frequency * x[0]).sin();
                let b = (2.0 * PI * frequency * x[1]).sin();
                g0 + amplitude * a * a * b * b
            }
        }
    }

    fn shift(x: [f64; 2], h: [f64; 2]) -> [f64; 2] {
        [x[0] + h[0], x[1] + h[1]]
    }

    fn e(i: usize, h: f64) -> [f64; 2] {
        let mut r = [0.0; 2];
        r[i] = h;
        r
    }

    /// (a) Jet of every gap against finite differences, all orders up to three.
    #[test]
    fn gap_jets_match_finite_differences() {
        for gap in all_gaps() {
            for x in points(12) {
                let j = gap.jet(x);
                assert_eq!(j.valid_order(), Some(3));
                assert!((j.v - gap_value(&gap, x)).abs() < 1e-15);
                // Each order against central differences of the previous analytic order.
                let h = 1e-5;
                for i in 0..2 {
                    let p = gap.jet(shift(x, e(i, h)));
                    let m = gap.jet(shift(x, e(i, -h)));
                    let fd = (p.v - m.v) / (2.0 * h);
                    assert!((fd - j.d[i]).abs() < 1e-6, "{gap:?} d{i} at {x:?}");
                    for a in 0..2 {
                        let fd = (p.d[a] - m.d[a]) / (2.0 * h);
                        assert!((fd - j.dd[i][a]).abs() < 1e-5, "{gap:?} dd at {x:?}");
                        for b in 0..2 {
                            let fd = (p.dd[a][b] - m.dd[a][b]) / (2.0 * h);
                            assert!(
                                (fd - j.ddd[i][a][b]).abs() < 1e-3,
                                "{gap:?} ddd[{i}][{a}][{b}] at {x:?}: {fd} vs {}",
                                j.ddd[i][a][b]
                            );
                        }
                    }
                }
                // Third derivatives directly from values: δ_i δ_j δ_k with half-step h, Richardson-
                // extrapolated (h, h/2) to fourth order.
                for i in 0..2 {
                    for a in 0..2 {
                        for b in 0..2 {
                            let fd = |h: f64| {
                                let mut s = 0.0;
                                for si in [-1.0, 1.0] {
                                    for sa in [-1.0, 1.0] {
                                        for sb in [-1.0, 1.0] {
                                            let mut y = x;
                                            y[i] += si * h;
                                            y[a] += sa * h;
                                            y[b] += sb * h;
                                            s += si * sa * sb * gap_value(&gap, y);
                                        }
                                    }
                                }
                                s / (8.0 * h * h * h)
                            };
                            let rich = (4.0 * fd(1e-3) - fd(2e-3)) / 3.0;
                            let exact = j.ddd[i][a][b];
                            assert!(
                                (rich - exact).abs() < 1e-5 * (1.0 + exact.abs()),
                                "{gap:?} ddd[{i}][{a}][{b}] at {x:?}: {rich} vs {exact}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn jet_algebra_is_exact() {
        // f = x₁² x₂ + 3 x₂³, 1/f and f·(1/f) = 1, partial, laplacian, NaN bookkeeping.
        let x = [0.7, -1.3];
        let (x1, x2) = (Jet::variable(x, 0), Jet::variable(x, 1));
        let f = x1 * x1 * x2 + 3.0 * (x2 * x2 * x2);
        assert!((f.v - (0.49 * -1.3 + 3.0 * (-1.3f64).powi(3))).abs() < 1e-14);
        assert!((f.d[0] - 2.0 * 0.7 * -1.3).abs() < 1e-14);
        assert!((f.dd[1][1] - 18.0 * -1.3).abs() < 1e-14);
        assert!((f.ddd[0][0][1] - 2.0).abs() < 1e-14);
        assert!((f.ddd[1][0][0] - 2.0).abs() < 1e-14);
        assert!((f.ddd[1][1][1] - 18.0).abs() < 1e-14);
        let one = f * f.recip();
        assert!((one.v - 1.0).abs() < 1e-14);
        for i in 0..2 {
            assert!(one.d[i].abs() < 1e-12);
            for j in 0..2 {
                assert!(one.dd[i][j].abs() < 1e-12);
                for k in 0..2 {
                    assert!(one.ddd[i][j][k].abs() < 1e-11);
                }
            }
        }
        let q = (x1 * x2) / f;
        let q2 = (x1 * x2) * f.recip();
        assert!((q.ddd[0][1][1] - q2.ddd[0][1][1]).abs() < 1e-12);
        let lap = f.laplacian();
        assert!((lap.v - (2.0 * -1.3 + 18.0 * -1.3)).abs() < 1e-13);
        assert!((lap.d[0] - 0.0).abs() < 1e-13 && (lap.d[1] - 20.0).abs() < 1e-13);
        assert_eq!(lap.valid_order(), Some(1));
        assert_eq!(f.partial(0).valid_order(), Some(2));
        assert_eq!(f.partial(0).partial(1).partial(1).valid_order(), Some(0));
        assert_eq!((f * lap).valid_order(), Some(1));
        assert!((f.partial(0).partial(1).v - 2.0 * 0.7).abs() < 1e-14);
    }

    /// Non-constant wall data for the identity tests of the general formulas.
    fn general_film(x: [f64; 2]) -> FilmJets {
        let (x1, x2) = (Jet::variable(x, 0), Jet::variable(x, 1));
        let c = Jet::constant;
        let sin = |a: Jet| {
            let (s, co) = a.v.sin_cos();
            a.compose([s, co, -s, -co])
        };
        let exp = |a: Jet| {
            let e = a.v.exp();
            a.compose([e, e, e, e])
        };
        let z0 = c(0.05) * x1 * x2 - c(0.02) * sin(x1 + x2 * c(2.0));
        let z1 = c(0.3) + c(0.1) * sin(c(3.0) * x1) * exp(c(0.5) * x2) + c(0.04) * x2 * x2;
        let v0 = [
            c(1.0) + x1 * x2,
            sin(x2) - c(2.0) * x1 * x1,
            exp(c(0.3) * x1) * x2,
        ];
        let v1 = [
            c(3.0) * x2 * x2 * x1 - c(1.0),
            exp(c(-0.2) * x1 * x2),
            sin(c(2.0) * x1) + x2,
        ];
        let kappa = [x1 * x1 + c(0.5), sin(x2)];
        FilmJets::from_walls(z0, z1, v0, v1, kappa)
    }

    fn close(a: f64, b: f64, scale: f64) -> bool {
        (a - b).abs() <= 1e-10 * scale.max(a.abs()).max(b.abs())
    }

    /// Identities printed in Chapter I, checked with non-constant wall data.
    #[test]
    fn general_formulas_satisfy_printed_identities() {
        for x in points(20) {
            let f = general_film(x);
            let g3 = f.gamma3();
            for mu in 0..2 {
                // (I.47) first line: −∂_ν(v_μ(z₁)∂_ν z₁ − v_μ(z₀)∂_ν z₀) − ∂_ν v_μ(z₁)∂_ν z₁ + ∂_ν v_μ(z₀)∂_ν z₀.
                let mut first = Jet::ZERO;
                for nu in 0..2 {
                    first = first
                        - (f.v1[mu] * f.z1.partial(nu) - f.v0[mu] * f.z0.partial(nu)).partial(nu)
                        - f.v1[mu].partial(nu) * f.z1.partial(nu)
                        + f.v0[mu].partial(nu) * f.z0.partial(nu);
                }
                // (I.47) third line: −Δ(v̄_μ g + δv_μ z̄) + Δv̄_μ g + Δδv_μ z̄.
                let third = -(f.vbar[mu] * f.g + f.dv[mu] * f.zbar).laplacian()
                    + f.vbar[mu].laplacian() * f.g
                    + f.dv[mu].laplacian() * f.zbar;
                for (a, b) in [(first, g3[mu]), (third, g3[mu])] {
                    assert_eq!(b.valid_order(), Some(1));
                    assert!(close(a.v, b.v, 1.0));
                    assert!(close(a.d[0], b.d[0], 1.0) && close(a.d[1], b.d[1], 1.0));
                }
            }
            // (I.43): δv_μ ∂_μ z̄ + v̄_μ ∂_μ g = v_μ(z₁) ∂_μ z₁ − v_μ(z₀) ∂_μ z₀, hence (I.50).
            let mut lhs = 0.0;
            let mut rhs = 0.0;
            for mu in 0..2 {
                lhs += f.dv[mu].v * f.zbar.d[mu] + f.vbar[mu].v * f.g.d[mu];
                rhs += f.v1[mu].v * f.z1.d[mu] - f.v0[mu].v * f.z0.d[mu];
            }
            assert!(close(lhs, rhs, 1.0));
            let sigma_alt = -f.dv[2].v + rhs + (0..2).map(|m| f.vbar[m].v * f.g.d[m]).sum::<f64>();
            assert!(close(f.sigma3().v, sigma_alt, 1.0));
            // (I.77) second form: R₃ = (g/12) ∂_ν( g (Δv̄_ν g + Δδv_ν z̄ − Δ(δv_ν z̄)) ).
            let mut s = Jet::ZERO;
            for nu in 0..2 {
                let inner = f.vbar[nu].laplacian() * f.g + f.dv[nu].laplacian() * f.zbar
                    - (f.dv[nu] * f.zbar).laplacian();
                s += (f.g * inner).partial(nu);
            }
            let r3_alt = (f.g * s).scale(1.0 / 12.0);
            assert!(close(f.r3().v, r3_alt.v, 1.0));
            // (I.81) expanded form of R₃c (printed source):
            // R₃ + (g/12)∂_μ[ 2g∂_μ∂_ν(g v̄_ν) + g∂_μ∂_ν(δv_ν z̄) − g(g∂_μ∂_ν v̄_ν + z̄∂_μ∂_ν δv_ν) − g²∂_μ(δv₃/g) ].
            let (g, zb) = (f.g, f.zbar);
            let mut dgv = Jet::ZERO;
            let mut ddz = Jet::ZERO;
            let mut dvb = Jet::ZERO;
            let mut ddv = Jet::ZERO;
            for nu in 0..2 {
                dgv += (g * f.vbar[nu]).partial(nu);
                ddz += (f.dv[nu] * zb).partial(nu);
                dvb += f.vbar[nu].partial(nu);
                ddv += f.dv[nu].partial(nu);
            }
            let q = f.dv[2] / g;
            let mut s = Jet::ZERO;
            for mu in 0..2 {
                let inner = (g * dgv.partial(mu)).scale(2.0) + g * ddz.partial(mu)
                    - g * (g * dvb.partial(mu) + zb * ddv.partial(mu))
                    - g * g * q.partial(mu);
                s += inner.partial(mu);
            }
            let r3c_alt = f.r3().v + (g * s).v / 12.0;
            let r3c = f.r3c(CavitationSource::Printed).v;
            assert!(close(r3c, r3c_alt, 1.0), "{r3c} vs {r3c_alt}");
            // The loads are finite (no order was missing) and consistent with the rhs forms.
            let lr = f.reynolds_load().v;
            assert!(lr.is_finite());
            assert!(close(lr, -12.0 * f.reynolds_rhs().v / (g.v * g.v), 1.0));
            for src in [CavitationSource::Printed, CavitationSource::SelfConsistent] {
                let lc = f.cavitation_load(src).v;
                assert!(close(
                    lc,
                    -12.0 * f.cavitation_rhs(src).v / (g.v * g.v),
                    1.0
                ));
            }
        }
    }

    /// Names of the quantities compared in `general_formulas_match_simplified_forms`.
    const QUANTITIES: [&str; 16] = [
        "gamma3_1",
        "gamma3_2",
        "gamma_1",
        "gamma_2",
        "sigma3",
        "R1",
        "R3",
        "gamma3c_1 (printed)",
        "gamma3c_2 (printed)",
        "gamma3c_1 (self-consistent)",
        "gamma3c_2 (self-consistent)",
        "R3c (printed)",
        "R3c (self-consistent)",
        "l_R",
        "l_Rc (printed)",
        "l_Rc (self-consistent)",
    ];

    /// The quantities of `QUANTITIES` from the general formulas.
    fn general(film: &ThinFilm, x: [f64; 2]) -> [f64; 16] {
        use CavitationSource::{Printed as P, SelfConsistent as S};
        let (g3, ga) = (film.gamma3(x), film.gamma(x));
        let (cp, cs) = (film.gamma3c(x, P), film.gamma3c(x, S));
        [
            g3[0],
            g3[1],
            ga[0],
            ga[1],
            film.sigma3(x),
            film.r1(x),
            film.r3(x),
            cp[0],
            cp[1],
            cs[0],
            cs[1],
            film.r3c(x, P),
            film.r3c(x, S),
            film.reynolds_load(x),
            film.cavitation_load(x, P),
            film.cavitation_load(x, S),
        ]
    }

    /// The quantities of `QUANTITIES` from the simplified forms of docs/models.md §14 (constant
    /// δv, v(z₀) = 0, z₀ = 0, so z̄ = g/2, v̄ = δv/2), derived independently by hand.
    fn simplified(film: &ThinFilm, x: [f64; 2]) -> [f64; 16] {
        let j = film.gap.jet(x);
        let dv = film.upper_wall_velocity;
        let g = j.v;
        let lap = j.dd[0][0] + j.dd[1][1];
        let lap_d = [
            j.ddd[0][0][0] + j.ddd[1][1][0],
            j.ddd[0][0][1] + j.ddd[1][1][1],
        ];
        let dot_grad = dv[0] * j.d[0] + dv[1] * j.d[1];
        // ∂_ν(gΔg) = ∂_ν g Δg + g ∂_ν Δg.
        let d_glap = |nu: usize| j.d[nu] * lap + g * lap_d[nu];
        // γ₃ = −δv_μ Δg; γ = γ₃ + 6 δv_μ / g.
        let gamma3 = [-dv[0] * lap, -dv[1] * lap];
        let gamma = [gamma3[0] + 6.0 * dv[0] / g, gamma3[1] + 6.0 * dv[1] / g];
        // σ₃ = −δv₃ + (3/2) δv_μ ∂_μ g; R₁ = −½ δv_ν ∂_ν g; R₃ = −(g/24) δv_ν ∂_ν(gΔg).
        let sigma3 = -dv[2] + 1.5 * dot_grad;
        let r1 = -0.5 * dot_grad;
        let r3 = -(g / 24.0) * (dv[0] * d_glap(0) + dv[1] * d_glap(1));
        // γ₃c = −δv_μ Δg ± (δv_ν ∂_μ∂_ν g + δv₃ ∂_μ g / g).
        let mix = |mu: usize| dv[0] * j.dd[mu][0] + dv[1] * j.dd[mu][1];
        let c_p = [0, 1].map(|mu| -dv[mu] * lap + mix(mu) + dv[2] * j.d[mu] / g);
        let c_s = [0, 1].map(|mu| -dv[mu] * lap - mix(mu) - dv[2] * j.d[mu] / g);
        // t = δv_ν ∂_μ(g ∂_μ∂_ν g) = δv_ν (∂_μ g ∂_μ∂_ν g + g ∂_ν Δg).
        let mut t = 0.0;
        for nu in 0..2 {
            t += dv[nu] * (j.d[0] * j.dd[0][nu] + j.d[1] * j.dd[1][nu] + g * lap_d[nu]);
        }
        // R₃c = R₃ + (g/12)[(3/2) t + δv₃ Δg] (printed); the self-consistent source changes the
        // bracket to −(1/2) t − δv₃ Δg.
        let r3c_p = r3 + (g / 12.0) * (1.5 * t + dv[2] * lap);
        let r3c_s = r3 + (g / 12.0) * (-0.5 * t - dv[2] * lap);
        let load = |r: f64| -12.0 * (dv[2] + r1 + r) / (g * g);
        [
            gamma3[0],
            gamma3[1],
            gamma[0],
            gamma[1],
            sigma3,
            r1,
            r3,
            c_p[0],
            c_p[1],
            c_s[0],
            c_s[1],
            r3c_p,
            r3c_s,
            load(r3),
            load(r3c_p),
            load(r3c_s),
        ]
    }

    /// (b) General formulas against the simplified forms of docs/models.md §14, all 14 examples, 25 points
    /// each. The relative error is measured against the largest |simplified value| of that
    /// quantity over the sample points of that example (1 if the quantity vanishes identically).
    #[test]
    fn general_formulas_match_simplified_forms() {
        let pts = points(25);
        let mut overall: f64 = 0.0;
        for eq in EXAMPLES {
            let film = example(eq).unwrap();
            let gen: Vec<[f64; 16]> = pts.iter().map(|&x| general(&film, x)).collect();
            let simp: Vec<[f64; 16]> = pts.iter().map(|&x| simplified(&film, x)).collect();
            for (q, name) in QUANTITIES.iter().enumerate() {
                let m = simp.iter().map(|s| s[q].abs()).fold(0.0, f64::max);
                let scale = if m > 0.0 { m } else { 1.0 };
                for ((x, a), b) in pts.iter().zip(&gen).zip(&simp) {
                    let rel = (a[q] - b[q]).abs() / scale;
                    overall = overall.max(rel);
                    assert!(
                        rel <= 1e-10,
                        "{eq} {name} at {x:?}: general {} vs simplified {} (scale {scale})",
                        a[q],
                        b[q]
                    );
                }
            }
        }
        println!("largest relative deviation general vs simplified: {overall:e}");
    }

    /// (c) Plain squeeze: l_R = 12000 for (IV.7) and −12000 for (IV.8), everywhere.
    #[test]
    fn plain_gap_loads() {
        let (a, b) = (example("IV.7").unwrap(), example("(IV.8)").unwrap());
        for x in points(20) {
            assert!((a.reynolds_load(x) - 12000.0).abs() < 1e-9);
            assert!((b.reynolds_load(x) + 12000.0).abs() < 1e-9);
            for src in [CavitationSource::Printed, CavitationSource::SelfConsistent] {
                assert!((b.cavitation_load(x, src) + 12000.0).abs() < 1e-9);
            }
            assert_eq!(a.gap(x), (0.1, [0.0, 0.0], 0.0));
        }
        assert!(example("IV.21").is_none());
        assert!(example("IV.6").is_none());
    }

    /// (d) Pairs with Δg = 0 and reversed wall velocity have opposite loads.
    #[test]
    fn reversed_pairs_have_opposite_loads() {
        for (p, q) in [("IV.7", "IV.8"), ("IV.10", "IV.11"), ("IV.12", "IV.13")] {
            let (a, b) = (example(p).unwrap(), example(q).unwrap());
            for x in points(20) {
                assert_eq!(a.gap(x).2, 0.0);
                let (la, lb) = (a.reynolds_load(x), b.reynolds_load(x));
                assert!(
                    (la + lb).abs() <= 1e-12 * la.abs().max(1.0),
                    "{p}/{q} at {x:?}"
                );
                for src in [CavitationSource::Printed, CavitationSource::SelfConsistent] {
                    let (ca, cb) = (a.cavitation_load(x, src), b.cavitation_load(x, src));
                    assert!((ca + cb).abs() <= 1e-12 * ca.abs().max(1.0));
                }
            }
        }
    }

    /// The loads of the examples whose gap needs no libm call (plain and linear: the bits do not
    /// depend on the platform's `sin`) are pinned bitwise: a checksum over a 40 × 40 grid of l_R
    /// and of l_{R,c} in each reading, recorded before the jet operations were inlined ([`Jet`]
    /// type docs). A change to the jet arithmetic or to the formulas that is meant to keep every
    /// value must keep these.
    #[test]
    fn loads_are_bitwise_pinned() {
        use CavitationSource::{Printed, Reynolds, SelfConsistent};
        let pinned = [
            ("IV.7", 0xf26a_9000_0000_5d77),
            ("IV.8", 0x8d95_6fff_ffff_e098),
            ("IV.9", 0x7fff_ffff_ffff_bdef),
            ("IV.10", 0x2196_ebd5_835f_18d4),
            ("IV.11", 0x5e69_142a_7ca0_a53b),
            ("IV.12", 0x6f12_5c60_8e8e_1f9d),
            ("IV.13", 0x10ed_a39f_7171_a272),
            ("IV.14", 0x7fff_ffff_ffff_bdef),
        ];
        let n = 40;
        let mut failed = false;
        for (eq, expected) in pinned {
            let film = example(eq).unwrap();
            let mut bits = 0u64;
            for i in 0..=n {
                for k in 0..=n {
                    let x = [i as f64 / n as f64, k as f64 / n as f64];
                    let loads = [
                        film.reynolds_load(x),
                        film.cavitation_load(x, Printed),
                        film.cavitation_load(x, SelfConsistent),
                        film.cavitation_load(x, Reynolds),
                    ];
                    for l in loads {
                        bits = bits.rotate_left(5) ^ l.to_bits();
                    }
                }
            }
            println!("(\"{eq}\", 0x{bits:016x}),");
            failed |= bits != expected;
        }
        assert!(!failed, "checksums differ (printed above)");
    }

    /// The `reynolds` reading takes the source terms without cavitation: γ₃c = γ₃, R₃c = R₃,
    /// l_{R,c} = l_R (bitwise); on the wave gap with upward velocity it differs from the printed
    /// R₃c by (g/12)δv₃Δg.
    #[test]
    fn reynolds_reading_is_the_source_without_cavitation() {
        for eq in EXAMPLES {
            let film = example(eq).unwrap();
            for x in points(20) {
                let f = film.film_jets(x);
                let (c, r) = (f.gamma3c(CavitationSource::Reynolds), f.gamma3());
                assert_eq!([c[0].v, c[1].v], [r[0].v, r[1].v], "{eq}");
                assert_eq!(
                    film.cavitation_load(x, CavitationSource::Reynolds)
                        .to_bits(),
                    film.reynolds_load(x).to_bits(),
                    "{eq} at {x:?}"
                );
            }
        }
        let film = example("IV.16").unwrap();
        for x in points(20) {
            let (g, _, lap) = film.gap(x);
            let d =
                film.r3c(x, CavitationSource::Printed) - film.r3c(x, CavitationSource::Reynolds);
            assert!(
                (d - g / 12.0 * 10.0 * lap).abs() <= 1e-9 * (1.0 + lap.abs()),
                "{x:?}"
            );
        }
    }

    #[test]
    fn printed_and_self_consistent_coincide_without_curvature() {
        // Plain gaps: γ₃c identical. Linear gaps: γ₃c differ (±δv₃∂g/g) but R₃c does not.
        for eq in [
            "IV.7", "IV.8", "IV.9", "IV.10", "IV.11", "IV.12", "IV.13", "IV.14",
        ] {
            let film = example(eq).unwrap();
            for x in points(20) {
                let p = film.r3c(x, CavitationSource::Printed);
                let s = film.r3c(x, CavitationSource::SelfConsistent);
                assert!((p - s).abs() < 1e-12, "{eq}");
            }
        }
        let film = example("IV.11").unwrap();
        let x = [0.4, 0.6];
        let p = film.gamma3c(x, CavitationSource::Printed)[0];
        let s = film.gamma3c(x, CavitationSource::SelfConsistent)[0];
        let expected = 10.0 * 0.05 / (0.1 + 0.05 * 0.4);
        assert!((p - expected).abs() < 1e-12 && (s + expected).abs() < 1e-12);
    }

    #[test]
    fn gap_extrema_on_unit_square() {
        let ex = |eq: &str| example(eq).unwrap().gap;
        assert_eq!(ex("IV.7").min_on_unit_square(), 0.1);
        assert_eq!(ex("IV.10").min_on_unit_square(), 0.1);
        assert!((ex("IV.10").max_on_unit_square() - 0.15).abs() < 1e-15);
        assert!((ex("IV.15").min_on_unit_square() - 0.03).abs() < 1e-15);
        assert!((ex("IV.15").max_on_unit_square() - 0.17).abs() < 1e-15);
        assert_eq!(ex("IV.18").min_on_unit_square(), 0.1);
        assert!((ex("IV.18").max_on_unit_square() - 0.17).abs() < 1e-15);
        // Brute force on a fine grid never goes below the exact minimum, and gets close to it.
        for gap in all_gaps().into_iter().chain([
            Gap::Linear {
                g0: 0.2,
                slope: -0.1,
            },
            Gap::WaveHorizontal {
                g0: 0.2,
                amplitude: -0.05,
                frequency: 0.3,
            },
            Gap::WaveHorizontal {
                g0: 0.2,
                amplitude: 0.05,
                frequency: 0.3,
            },
        ]) {
            let (lo, hi) = (gap.min_on_unit_square(), gap.max_on_unit_square());
            let n = 400;
            let (mut bmin, mut bmax) = (f64::INFINITY, f64::NEG_INFINITY);
            for i in 0..=n {
                for k in 0..=n {
                    let v = gap.value([i as f64 / n as f64, k as f64 / n as f64]);
                    bmin = bmin.min(v);
                    bmax = bmax.max(v);
                }
            }
            assert!(bmin >= lo - 1e-15 && bmax <= hi + 1e-15, "{gap:?}");
            assert!(
                bmin - lo < 1e-4 && hi - bmax < 1e-4,
                "{gap:?}: {bmin} {lo} {bmax} {hi}"
            );
        }
    }

    /// The extrema on boxes agree with brute force on a fine grid of each box (never beyond
    /// the exact values, close to them), and on [0, 1]² with the unit-square extrema.
    #[test]
    fn gap_extrema_on_boxes() {
        let boxes = [
            [0.0, 0.0, 0.125, 0.125],
            [0.1, 0.2, 0.3, 0.45],
            [0.3, 0.0, 0.4, 1.0],
            [0.55, 0.6, 0.7, 0.65],
            [0.6, 0.3, 0.62, 0.31],
        ];
        let gaps = all_gaps().into_iter().chain([Gap::Linear {
            g0: 0.2,
            slope: -0.1,
        }]);
        for gap in gaps {
            let unit = gap.range_on_box([0.0, 0.0, 1.0, 1.0]);
            assert!((unit.0 - gap.min_on_unit_square()).abs() < 1e-15, "{gap:?}");
            assert!((unit.1 - gap.max_on_unit_square()).abs() < 1e-15, "{gap:?}");
            for b in boxes {
                let (lo, hi) = gap.range_on_box(b);
                let n = 200;
                let (mut bmin, mut bmax) = (f64::INFINITY, f64::NEG_INFINITY);
                for i in 0..=n {
                    for k in 0..=n {
                        let x = b[0] + (b[2] - b[0]) * i as f64 / n as f64;
                        let y = b[1] + (b[3] - b[1]) * k as f64 / n as f64;
                        let v = gap.value([x, y]);
                        bmin = bmin.min(v);
                        bmax = bmax.max(v);
                    }
                }
                assert!(
                    bmin >= lo - 1e-15 && bmax <= hi + 1e-15,
                    "{gap:?} {b:?}: [{lo}, {hi}] vs [{bmin}, {bmax}]"
                );
                assert!(
                    bmin - lo < 1e-5 && hi - bmax < 1e-5,
                    "{gap:?} {b:?}: [{lo}, {hi}] vs [{bmin}, {bmax}]"
                );
            }
        }
    }
}
