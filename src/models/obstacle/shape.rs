//! The obstacle functions b(x₁) of §IV.2.1 and the θ_s of (IV.3) they are built from.

use std::sync::Arc;

use super::DEFAULT_SAW_S;

/// θ_s(x) = (x + √(s²+x²)) / (2√(s²+x²)) (IV.3), thesis l. 5326.
///
/// Smooth, monotone, θ_s(0) = ½, θ_s(x) + θ_s(−x) = 1, θ_s → 0 / 1 for x → ∓∞; the transition
/// width is O(s). Evaluated without cancellation: for x < 0 the numerator is rewritten as
/// x + r = s²/(r − x) with r = hypot(s, x). Finite (in [0, 1]) for every finite x and s > 0.
/// For s == 0 the sharp Heaviside step (with value ½ at 0) is returned.
pub fn theta(s: f64, x: f64) -> f64 {
    let s = s.abs();
    if s == 0.0 {
        return if x > 0.0 {
            1.0
        } else if x < 0.0 {
            0.0
        } else {
            0.5
        };
    }
    let r = s.hypot(x);
    if x >= 0.0 {
        0.5 + 0.5 * (x / r)
    } else {
        // (x + r)/(2r) = s² / (2 r (r − x)); r − x ≥ r > 0, no cancellation.
        0.5 * (s / r) * (s / (r - x))
    }
}

/// dθ_s/dx = s² / (2 (s²+x²)^{3/2}) (> 0, maximal 1/(2s) at x = 0). Written as ½(s/r)²/r so that
/// it neither overflows nor becomes NaN for large |x|. For s == 0 returns 0 (the Dirac part of
/// the sharp step is not representable).
pub fn theta_prime(s: f64, x: f64) -> f64 {
    let s = s.abs();
    if s == 0.0 {
        return 0.0;
    }
    let r = s.hypot(x);
    let q = s / r;
    0.5 * q * q / r
}

/// [θ_s, θ_s', θ_s'', θ_s'''] at x, for the step gap (`crate::models::thin_film::Gap::Step`),
/// whose Reynolds source needs three derivatives. With r = √(s² + x²):
///
///   θ_s'' = −(3/2) s² x / r⁵,   θ_s''' = (3/2) s² (4x² − s²) / r⁷,
///
/// evaluated as powers of s/r and x/r (no overflow for large |x|). For s == 0 the sharp step
/// with zero derivatives, as [`theta`] and [`theta_prime`].
pub fn theta_derivatives(s: f64, x: f64) -> [f64; 4] {
    let value = theta(s, x);
    let s = s.abs();
    if s == 0.0 {
        return [value, 0.0, 0.0, 0.0];
    }
    let r = s.hypot(x);
    let (q, u) = (s / r, x / r);
    let q2 = q * q;
    [
        value,
        0.5 * q2 / r,
        -1.5 * q2 * u / (r * r),
        1.5 * q2 * (4.0 * u * u - q2) / (r * r * r),
    ]
}

/// max of θ_s' over an interval [lo, hi] of arguments: θ_s' decreases in |x|.
fn theta_prime_max(s: f64, lo: f64, hi: f64) -> f64 {
    let d = if lo > 0.0 {
        lo
    } else if hi < 0.0 {
        -hi
    } else {
        0.0
    };
    theta_prime(s, d)
}

/// How the printed saw formula (l. 5485) is read. Both readings replace the printed x₂ by x₁
/// (the obstacle is a function on Γ_C = {x₂ = 0}, so x₂ ≡ 0 there would make it constant).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SawReading {
    /// The continuous saw through the nodes (−4,0), (−2,−1), (1,0), (5,2), (6,0), constant 0
    /// outside [−4,6]; every printed piece gets the value of its left node as offset.
    #[default]
    Continuous,
    /// The formula exactly as printed (offsets of the 2nd and 4th piece missing); it jumps by
    /// +1 at x₁ = −2, −1 at x₁ = 1, −2 at x₁ = 5 and +2 at x₁ = 6.
    Literal,
}

/// Nodes of the saw (x₁-coordinates and values) encoded by the printed slopes
/// (−1−0)/(−2−(−4)), (0−(−1))/(1−(−2)), (2−0)/(5−1), (0−2)/(6−5) of l. 5485.
pub(super) const SAW_X: [f64; 5] = [-4.0, -2.0, 1.0, 5.0, 6.0];
pub(super) const SAW_Y: [f64; 5] = [0.0, -1.0, 0.0, 2.0, 0.0];

/// A tabulated obstacle: the straight lines between the points (x_k, b_k), x_k strictly
/// increasing, held at the end values beyond the first and the last point.
#[derive(Debug, Clone, PartialEq)]
pub struct Polyline {
    points: Vec<[f64; 2]>,
}

impl Polyline {
    /// The polyline through `points` (x strictly increasing, at least two points: the loader
    /// checks both). No point gives NaN everywhere, one a constant: never a panic.
    pub fn new(points: &[[f64; 2]]) -> Polyline {
        Polyline {
            points: points.to_vec(),
        }
    }

    /// The segment k with x_k ≤ x < x_{k+1}; None beyond the ends (x < x_0 or x ≥ x_n).
    fn segment(&self, x: f64) -> Option<usize> {
        let after = self.points.partition_point(|p| p[0] <= x);
        (after >= 1 && after < self.points.len()).then(|| after - 1)
    }

    /// The slope (b_{k+1} − b_k)/(x_{k+1} − x_k) of segment k.
    fn slope_of(&self, k: usize) -> f64 {
        let ([x0, b0], [x1, b1]) = (self.points[k], self.points[k + 1]);
        (b1 - b0) / (x1 - x0)
    }

    /// b(x): b_k + (b_{k+1} − b_k)(x − x_k)/(x_{k+1} − x_k) on segment k, b_0 left of x_0, b_n
    /// from x_n on.
    pub fn value(&self, x: f64) -> f64 {
        let (Some(first), Some(last)) = (self.points.first(), self.points.last()) else {
            return f64::NAN;
        };
        match self.segment(x) {
            Some(k) => {
                let ([x0, b0], [x1, b1]) = (self.points[k], self.points[k + 1]);
                b0 + (b1 - b0) * ((x - x0) / (x1 - x0))
            }
            None if x < first[0] => first[1],
            None => last[1],
        }
    }

    /// b'(x) from the right: the slope of segment k on [x_k, x_{k+1}), 0 left of x_0 and from
    /// x_n on (b has kinks at the points; its left and right slopes differ there).
    pub fn slope(&self, x: f64) -> f64 {
        self.segment(x).map_or(0.0, |k| self.slope_of(k))
    }

    /// max |b'| on [lo, hi]: the largest |slope| of the segments that meet the interval (0 for
    /// the constant continuations) — a Lipschitz constant of b there.
    pub fn slope_bound(&self, lo: f64, hi: f64) -> f64 {
        let n = self.points.len();
        if n < 2 {
            return 0.0;
        }
        // Segments k with x_k ≤ hi and x_{k+1} ≥ lo.
        let first = self.points.partition_point(|p| p[0] < lo).saturating_sub(1);
        let end = self.points.partition_point(|p| p[0] <= hi).min(n - 1);
        (first..end)
            .map(|k| self.slope_of(k).abs())
            .fold(0.0, f64::max)
    }
}

/// Obstacle function b(x₁).
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// b = level.
    Constant { level: f64 },
    /// b = offset + slope·x₁ (the tilted straight obstacle of the manufactured Signorini scene,
    /// `crate::models::manufactured::ContactStrip`).
    Linear { offset: f64, slope: f64 },
    /// b = offset + amplitude·sin(periods·2π(x₁+16)/32) (l. 5216, 5279: periods = 2).
    Periodic {
        offset: f64,
        amplitude: f64,
        periods: f64,
    },
    /// b = offset + amplitude·sin(2π(x₁ − phase)/period): the periodic obstacle of a scene of
    /// the user's own, with its own period and phase (not tied to Ω = [−16, 16] × [0, 1]).
    Sine {
        offset: f64,
        amplitude: f64,
        period: f64,
        phase: f64,
    },
    /// A tabulated obstacle ([`Polyline`]): piecewise linear between the rows of a CSV file,
    /// constant beyond them.
    Tabulated(Arc<Polyline>),
    /// b = base + height·θ_s(x₁ − at) (l. 5351, 5415, 5423 with s = 0.01).
    Jump {
        base: f64,
        height: f64,
        at: f64,
        s: f64,
    },
    /// The saw obstacle of §IV.2.1.6 (l. 5485). With nodes X = (−4, −2, 1, 5, 6),
    /// Y = (0, −1, 0, 2, 0) and, for k = 0..3, a_k = X_k, e_k = X_{k+1},
    /// m_k = (Y_{k+1} − Y_k)/(e_k − a_k) (exactly the four printed slopes −1/2, 1/3, 1/2, −2):
    ///
    /// b(x₁) = Σ_k θ_s(x₁ − a_k) · θ_s(e_k − x₁) · (c_k + m_k (x₁ − a_k)),
    ///
    /// which is the printed formula with x₂ → x₁ and
    /// * `Continuous`: c_k = Y_k = (0, −1, 0, 2), i.e. each window θ_s(x₁−a_k)θ_s(e_k−x₁)
    ///   (≈ indicator of [a_k, e_k]) multiplies the linear interpolant of the piece. At an
    ///   interior node the two adjacent windows are ≈ θ_s(∓δ) and sum to 1 (θ_s(δ)+θ_s(−δ)=1),
    ///   so b passes through every node up to O(s²) (the far factors θ_s(e_k − a_k) ≈ 1 − O(s²))
    ///   and deviates from the piecewise-linear saw by O(s) only within O(s) of a kink; outside
    ///   [−4,6] b decays like O(s²/x²) to 0.
    /// * `Literal`: c_k = 0 for all k, the formula as printed (pieces 2 and 4 lack their offsets
    ///   −1 and +2), giving θ_s-smoothed jumps at x₁ = −2 (+1), 1 (−1), 5 (−2) and 6 (+2).
    Saw { s: f64, reading: SawReading },
    /// The tools of the U-O forming (§IV.2.4.7): the lower half of the circle of radius r about
    /// (c₁, c₂) up to its right end x_e = c₁ + r, where the tangent is vertical, blended by
    /// θ_s into the plateau h:
    ///
    /// b(x₁) = A(x₁) + θ_s(x₁ − x_e)·(h − A(x₁)),  A(x₁) = c₂ − √(max(0, r² − (x₁ − c₁)²)).
    ///
    /// The punch is c = (−16, 10), r = 8.8 (x_e = −7.2) with the plateau 1.2 + 10j/24, the die
    /// c = (−16, 10j/24), r = 10 (x_e = −6) with the plateau 10j/24 (absolute heights; the
    /// file gives them relative to the contact face like every b). |b'| is unbounded at x_e.
    Arc {
        center: [f64; 2],
        radius: f64,
        plateau: f64,
        s: f64,
    },
}

impl Shape {
    /// The circle part A(x₁) of [`Shape::Arc`] and its slope A'(x₁) (infinite at the ends).
    fn arc(center: [f64; 2], radius: f64, x1: f64) -> (f64, f64) {
        let dx = x1 - center[0];
        let root = (radius * radius - dx * dx).max(0.0).sqrt();
        let slope = if dx.abs() >= radius {
            if dx.abs() == radius {
                f64::INFINITY.copysign(dx)
            } else {
                0.0
            }
        } else {
            dx / root
        };
        (center[1] - root, slope)
    }

    /// The saw of §IV.2.1.6 with the default s = 0.01.
    pub fn saw(reading: SawReading) -> Shape {
        Shape::Saw {
            s: DEFAULT_SAW_S,
            reading,
        }
    }

    fn saw_piece(k: usize, reading: SawReading) -> (f64, f64, f64, f64) {
        let a = SAW_X[k];
        let e = SAW_X[k + 1];
        let m = (SAW_Y[k + 1] - SAW_Y[k]) / (e - a);
        let c = match reading {
            SawReading::Continuous => SAW_Y[k],
            SawReading::Literal => 0.0,
        };
        (a, e, m, c)
    }

    fn periodic_k(periods: f64) -> f64 {
        periods * 2.0 * std::f64::consts::PI / 32.0
    }

    /// The wavenumber 2π/period of [`Shape::Sine`].
    fn sine_k(period: f64) -> f64 {
        std::f64::consts::TAU / period
    }

    /// b(x₁).
    pub fn value(&self, x1: f64) -> f64 {
        match *self {
            Shape::Constant { level } => level,
            Shape::Linear { offset, slope } => offset + slope * x1,
            Shape::Periodic {
                offset,
                amplitude,
                periods,
            } => offset + amplitude * (Self::periodic_k(periods) * (x1 + 16.0)).sin(),
            Shape::Sine {
                offset,
                amplitude,
                period,
                phase,
            } => offset + amplitude * (Self::sine_k(period) * (x1 - phase)).sin(),
            Shape::Tabulated(ref table) => table.value(x1),
            Shape::Jump {
                base,
                height,
                at,
                s,
            } => base + height * theta(s, x1 - at),
            Shape::Arc {
                center,
                radius,
                plateau,
                s,
            } => {
                let (a, _) = Self::arc(center, radius, x1);
                a + theta(s, x1 - center[0] - radius) * (plateau - a)
            }
            Shape::Saw { s, reading } => (0..4)
                .map(|k| {
                    let (a, e, m, c) = Self::saw_piece(k, reading);
                    theta(s, x1 - a) * theta(s, e - x1) * (c + m * (x1 - a))
                })
                .sum(),
        }
    }

    /// b'(x₁), analytic.
    pub fn slope(&self, x1: f64) -> f64 {
        match *self {
            Shape::Linear { slope, .. } => slope,
            Shape::Constant { .. } => 0.0,
            Shape::Periodic {
                amplitude, periods, ..
            } => {
                let k = Self::periodic_k(periods);
                amplitude * k * (k * (x1 + 16.0)).cos()
            }
            Shape::Sine {
                amplitude,
                period,
                phase,
                ..
            } => {
                let k = Self::sine_k(period);
                amplitude * k * (k * (x1 - phase)).cos()
            }
            Shape::Tabulated(ref table) => table.slope(x1),
            Shape::Jump { height, at, s, .. } => height * theta_prime(s, x1 - at),
            Shape::Arc {
                center,
                radius,
                plateau,
                s,
            } => {
                let (a, da) = Self::arc(center, radius, x1);
                let x = x1 - center[0] - radius;
                da * (1.0 - theta(s, x)) + theta_prime(s, x) * (plateau - a)
            }
            Shape::Saw { s, reading } => (0..4)
                .map(|k| {
                    let (a, e, m, c) = Self::saw_piece(k, reading);
                    let (ta, te) = (theta(s, x1 - a), theta(s, e - x1));
                    let (da, de) = (theta_prime(s, x1 - a), theta_prime(s, e - x1));
                    let lin = c + m * (x1 - a);
                    (da * te - ta * de) * lin + ta * te * m
                })
                .sum(),
        }
    }

    /// An upper bound of |b'| on the interval between `x_lo` and `x_hi` (any order); used to
    /// certify root-free steps in the distance search.
    pub fn slope_bound(&self, x_lo: f64, x_hi: f64) -> f64 {
        let (lo, hi) = if x_lo <= x_hi {
            (x_lo, x_hi)
        } else {
            (x_hi, x_lo)
        };
        match *self {
            Shape::Linear { slope, .. } => slope.abs(),
            Shape::Constant { .. } => 0.0,
            Shape::Periodic {
                amplitude, periods, ..
            } => (amplitude * Self::periodic_k(periods)).abs(),
            Shape::Sine {
                amplitude, period, ..
            } => (amplitude * Self::sine_k(period)).abs(),
            Shape::Tabulated(ref table) => table.slope_bound(lo, hi),
            Shape::Jump { height, at, s, .. } => {
                height.abs() * theta_prime_max(s, lo - at, hi - at)
            }
            Shape::Arc {
                center,
                radius,
                plateau,
                s,
            } => {
                // |A'| grows with |x₁ − c₁| inside the circle: its largest value on the
                // interval is at the point farthest from c₁ within [c₁ − r, c₁ + r] (∞ where
                // the interval reaches an end); |h − A| ≤ |h − c₂| + r.
                let inside_lo = lo.max(center[0] - radius);
                let inside_hi = hi.min(center[0] + radius);
                let steepest = if inside_lo > inside_hi {
                    0.0
                } else {
                    let far = if (inside_hi - center[0]).abs() >= (inside_lo - center[0]).abs() {
                        inside_hi
                    } else {
                        inside_lo
                    };
                    Self::arc(center, radius, far).1.abs()
                };
                let x_e = center[0] + radius;
                steepest
                    + theta_prime_max(s, lo - x_e, hi - x_e)
                        * ((plateau - center[1]).abs() + radius)
            }
            Shape::Saw { s, reading } => (0..4)
                .map(|k| {
                    let (a, e, m, c) = Self::saw_piece(k, reading);
                    // |lin| is maximal at an end point of the interval (lin is affine).
                    let lin_max = (c + m * (lo - a)).abs().max((c + m * (hi - a)).abs());
                    // θ ≤ 1, θ'(x−a) over [lo−a, hi−a], θ'(e−x) over [e−hi, e−lo].
                    let da = theta_prime_max(s, lo - a, hi - a);
                    let de = theta_prime_max(s, e - hi, e - lo);
                    (da + de) * lin_max + m.abs()
                })
                .sum(),
        }
    }
}

impl From<crate::experiment::SawReading> for SawReading {
    fn from(r: crate::experiment::SawReading) -> SawReading {
        match r {
            crate::experiment::SawReading::Continuous => SawReading::Continuous,
            crate::experiment::SawReading::Literal => SawReading::Literal,
        }
    }
}

impl From<crate::experiment::ObstacleShape> for Shape {
    fn from(s: crate::experiment::ObstacleShape) -> Shape {
        Shape::from(&s)
    }
}

impl From<&crate::experiment::ObstacleShape> for Shape {
    /// The obstacle of a file's shape. A `periodic` shape with `periods` is the thesis's
    /// [`Shape::Periodic`] (its numbers unchanged), one with `period` (and `phase`, default 0)
    /// a [`Shape::Sine`]; the loader refuses both or neither (here `periods` wins, and neither
    /// gives NaN).
    fn from(s: &crate::experiment::ObstacleShape) -> Shape {
        use crate::experiment::ObstacleShape as File;
        match *s {
            File::Constant { level } => Shape::Constant { level },
            File::Linear { offset, slope } => Shape::Linear { offset, slope },
            File::Periodic {
                offset,
                amplitude,
                periods: Some(periods),
                ..
            } => Shape::Periodic {
                offset,
                amplitude,
                periods,
            },
            File::Periodic {
                offset,
                amplitude,
                periods: None,
                period,
                phase,
            } => Shape::Sine {
                offset,
                amplitude,
                period: period.unwrap_or(f64::NAN),
                phase: phase.unwrap_or(0.0),
            },
            File::Tabulated { ref rows, .. } => Shape::Tabulated(Arc::new(Polyline::new(rows))),
            File::Jump {
                base,
                height,
                at,
                s,
            } => Shape::Jump {
                base,
                height,
                at,
                s,
            },
            File::Saw { s, reading } => Shape::Saw {
                s,
                reading: reading.into(),
            },
            File::Arc {
                center,
                radius,
                plateau,
                s,
            } => Shape::Arc {
                center,
                radius,
                plateau,
                s,
            },
        }
    }
}
