//! [`Gap`]: the gap functions of the examples, as jets and with their ranges on boxes.

use super::Jet;

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
