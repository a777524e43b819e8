//! [`Gap`]: the gap functions of the examples and of scenes of the user's own, as jets and with
//! their ranges on boxes.

use std::sync::Arc;

use super::spline::CubicSpline;
use super::Jet;
use crate::models::obstacle::{theta, theta_derivatives};

/// Gap width g(x₁, x₂) = z₁ − z₀ of the fluid examples [Ch.IV §IV.3, (IV.7)–(IV.20)], and the
/// step, parabolic and tabulated gaps of scenes of the user's own.
///
/// The Reynolds source R₃ (I.77) contains ∂(gΔg), so every gap has derivatives up to third
/// order ([`Gap::jet`]); the step is smoothed by θ_s for that reason, and the tabulated profile
/// is a C² spline.
#[derive(Debug, Clone, PartialEq)]
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
    /// The Rayleigh step smoothed by θ_s of (IV.3): g = g_in + (g_out − g_in)·θ_s(x₁ − at), so
    /// g ≈ g_in for x₁ < at and ≈ g_out beyond, with a transition of width O(s) (θ_s tends to
    /// its limits like s²/(4(x₁ − at)²)). Monotone in x₁.
    Step {
        g_in: f64,
        g_out: f64,
        at: f64,
        s: f64,
    },
    /// The parabolic approximation of a cylinder (a journal) of radius R₁ over a plane,
    /// g = g0 + (x₁ − c₁)²/(2R₁), and of a body with the second radius R₂ across it,
    /// + (x₂ − c₂)²/(2R₂) (`radius[1]` infinite: no x₂ term, g is a function of x₁ alone).
    Parabolic {
        g0: f64,
        center: [f64; 2],
        radius: [f64; 2],
    },
    /// A tabulated profile g(x₁): the natural cubic spline through the rows of a CSV file
    /// ([`CubicSpline`]), C², g''' piecewise constant (R₃ and the Reynolds load jump at the
    /// rows' x₁, bounded).
    Tabulated(Arc<CubicSpline>),
}

impl From<crate::experiment::GapShape> for Gap {
    fn from(g: crate::experiment::GapShape) -> Gap {
        Gap::from(&g)
    }
}

impl From<&crate::experiment::GapShape> for Gap {
    fn from(g: &crate::experiment::GapShape) -> Gap {
        use crate::experiment::GapShape as File;
        match *g {
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
            File::Step { g_in, g_out, at, s } => Gap::Step { g_in, g_out, at, s },
            File::Parabolic {
                g0,
                center,
                radius,
                center_x2,
                radius_x2,
            } => Gap::Parabolic {
                g0,
                center: [center, center_x2.unwrap_or(0.0)],
                radius: [radius, radius_x2.unwrap_or(f64::INFINITY)],
            },
            File::Tabulated { ref rows, .. } => {
                Gap::Tabulated(Arc::new(CubicSpline::natural(rows)))
            }
        }
    }
}

/// [p, p', p'', p'''] of the parabola p(t) = (t − c)²/(2R).
fn parabola_derivatives(center: f64, radius: f64, t: f64) -> [f64; 4] {
    let d = t - center;
    [0.5 * d * d / radius, d / radius, 1.0 / radius, 0.0]
}

/// (min, max) of (t − c)² over [lo, hi] (exact): 0 where the interval holds c.
fn square_range(center: f64, lo: f64, hi: f64) -> (f64, f64) {
    let (a, b) = ((lo - center).powi(2), (hi - center).powi(2));
    let min = if lo <= center && center <= hi {
        0.0
    } else {
        a.min(b)
    };
    (min, a.max(b))
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
    /// ∂(gΔg)). Inlined like the [`Jet`] operations: the loads then use the entries of
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
            Gap::Step { g_in, g_out, at, s } => {
                let h = g_out - g_in;
                let [t, t1, t2, t3] = theta_derivatives(s, x[0] - at);
                Jet::univariate(0, [g_in + h * t, h * t1, h * t2, h * t3])
            }
            Gap::Parabolic { g0, center, radius } => {
                let [p, p1, p2, p3] = parabola_derivatives(center[0], radius[0], x[0]);
                let along = Jet::univariate(0, [g0 + p, p1, p2, p3]);
                if radius[1].is_infinite() {
                    along
                } else {
                    along + Jet::univariate(1, parabola_derivatives(center[1], radius[1], x[1]))
                }
            }
            Gap::Tabulated(ref spline) => Jet::univariate(0, spline.derivatives(x[0])),
        }
    }

    /// Whether g depends on x₂. The hill gap does, and the parabolic gap with a second radius;
    /// the plain, linear, wave, step and tabulated gaps (and the parabolic one without a second
    /// radius) are functions of x₁ alone, bitwise: [`Gap::jet`] reads `x[1]` for those two only.
    /// The match is exhaustive on purpose: a new gap must say, because the Reynolds cell data
    /// evaluate the gaps that answer `false` once per distinct x₁
    /// (`ReynoldsProblem::cell_data_reusing`).
    pub fn varies_in_x2(&self) -> bool {
        match self {
            Gap::Plain { .. }
            | Gap::Linear { .. }
            | Gap::WaveHorizontal { .. }
            | Gap::Step { .. }
            | Gap::Tabulated(_) => false,
            Gap::Parabolic { radius, .. } => radius[1].is_finite(),
            Gap::Hill { .. } => true,
        }
    }

    /// Whether g depends on x at all: the plain gap does not, bitwise ([`Gap::jet`] reads no
    /// coordinate), so the Reynolds cell data evaluate it once for every cell. Exhaustive on
    /// purpose, like [`Gap::varies_in_x2`].
    pub fn varies_in_x1(&self) -> bool {
        match self {
            Gap::Plain { .. } => false,
            Gap::Linear { .. }
            | Gap::WaveHorizontal { .. }
            | Gap::Hill { .. }
            | Gap::Step { .. }
            | Gap::Parabolic { .. }
            | Gap::Tabulated(_) => true,
        }
    }

    /// g(x) only.
    pub fn value(&self, x: [f64; 2]) -> f64 {
        self.jet(x).v
    }

    /// Exact minimum of g over the closed unit square [0, 1]² (Ω₂ of all fluid examples; for the
    /// tabulated gap a lower bound within a few ulps, [`Gap::range_on_box`]).
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
    /// indicator of Theorem III.6 ([`crate::models::film_coupling`]). The step is monotone in x₁
    /// (its values at the box's ends); the parabola's two terms vary independently; the
    /// tabulated gap is enclosed piece by piece, each cubic's extremes widened by a bound of
    /// their rounding error ([`CubicSpline::range`]), so there the result is an enclosure that
    /// is exact up to a few ulps.
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
            Gap::Step { g_in, g_out, at, s } => {
                let h = g_out - g_in;
                let (p, q) = (g_in + h * theta(s, x0 - at), g_in + h * theta(s, x1 - at));
                (p.min(q), p.max(q))
            }
            Gap::Parabolic { g0, center, radius } => {
                let (m1, s1) = square_range(center[0], x0.min(x1), x0.max(x1));
                let (mut min, mut max) = (g0 + 0.5 * m1 / radius[0], g0 + 0.5 * s1 / radius[0]);
                if radius[1].is_finite() {
                    let (m2, s2) = square_range(center[1], y0.min(y1), y0.max(y1));
                    min += 0.5 * m2 / radius[1];
                    max += 0.5 * s2 / radius[1];
                }
                (min, max)
            }
            Gap::Tabulated(ref spline) => {
                let (min, _, max) = spline.range(x0, x1);
                (min, max)
            }
        }
    }
}
