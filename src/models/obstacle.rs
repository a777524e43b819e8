//! Obstacle geometry for the 2-D contact examples of Chapter IV (§IV.2.1–§IV.2.4).
//!
//! Self-contained (std only). Line numbers refer to
//! `/work/shared/thesis/gimbel-2012-contact-and-lubrication.md`.
//!
//! * [`theta`] / [`theta_prime`]: the Heaviside-like function θ_s of (IV.3) (l. 5326) and its
//!   derivative.
//! * [`Shape`]: the obstacle functions b(x₁) of the examples:
//!   - IV.2.1.1 `Constant { level: -2 }` (l. 5150);
//!   - IV.2.1.2 `Periodic { offset: -2, amplitude: 1.2, periods: 2 }` (l. 5216);
//!   - IV.2.1.3 `Periodic { offset: 0, amplitude: 1.2, periods: 2 }` (l. 5279);
//!   - IV.2.1.4 upper face, `Jump { base: 2, height: 8, at: 0, s: 0.01 }` (l. 5351, printed
//!     "2 + (10 − 2)·θ_{0.01}(x₁)");
//!   - IV.2.1.5 lower face `Jump { base: 0, height: -10, at: -1, s: 0.01 }` (l. 5415) and upper
//!     face `Jump { base: 2, height: -4, at: 2, s: 0.01 }` (l. 5423);
//!   - IV.2.1.6 `Saw { s, reading }` (l. 5485; repeated verbatim at l. 5940, 6476, 6896).
//! * [`ContactSide`]: which face of Ω = [−16,16]×\[0,1\] touches the obstacle, with the z-contact
//!   bound, the signed distance along a normal (III.13) used by the Signorini linearisation and the
//!   model-error indicator (III.16), deformed-boundary vertex normals and a penetration measure.

use std::fmt;

/// Default θ_s parameter of the saw obstacle. The thesis prints θ_s without a value (l. 5485);
/// 0.01 is the value used by all the other θ-obstacles (l. 5351, 5415, 5423).
pub const DEFAULT_SAW_S: f64 = 0.01;

/// x₂ of the lower face of Ω = [−16,16]×\[0,1\] (IV.1).
pub const LOWER_FACE_Y: f64 = 0.0;
/// x₂ of the upper face of Ω = [−16,16]×\[0,1\] (IV.1).
pub const UPPER_FACE_Y: f64 = 1.0;

/// Largest |t| searched by [`ContactSide::signed_distance_along`] (in units of |n|).
pub const SEARCH_RADIUS: f64 = 1.0e3;

/// Absolute tolerance on t of the root finder in [`ContactSide::signed_distance_along`].
pub const ROOT_TOL: f64 = 1.0e-13;

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
const SAW_X: [f64; 5] = [-4.0, -2.0, 1.0, 5.0, 6.0];
const SAW_Y: [f64; 5] = [0.0, -1.0, 0.0, 2.0, 0.0];

/// Obstacle function b(x₁).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    /// b = level.
    Constant { level: f64 },
    /// b = offset + amplitude·sin(periods·2π(x₁+16)/32) (l. 5216, 5279: periods = 2).
    Periodic {
        offset: f64,
        amplitude: f64,
        periods: f64,
    },
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

    /// b(x₁).
    pub fn value(&self, x1: f64) -> f64 {
        match *self {
            Shape::Constant { level } => level,
            Shape::Periodic {
                offset,
                amplitude,
                periods,
            } => offset + amplitude * (Self::periodic_k(periods) * (x1 + 16.0)).sin(),
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
            Shape::Constant { .. } => 0.0,
            Shape::Periodic {
                amplitude, periods, ..
            } => {
                let k = Self::periodic_k(periods);
                amplitude * k * (k * (x1 + 16.0)).cos()
            }
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
            Shape::Constant { .. } => 0.0,
            Shape::Periodic {
                amplitude, periods, ..
            } => (amplitude * Self::periodic_k(periods)).abs(),
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
        use crate::experiment::ObstacleShape as File;
        match s {
            File::Constant { level } => Shape::Constant { level },
            File::Periodic {
                offset,
                amplitude,
                periods,
            } => Shape::Periodic {
                offset,
                amplitude,
                periods,
            },
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

/// Errors of the obstacle geometry.
#[derive(Debug, Clone, PartialEq)]
pub enum GeometryError {
    /// The search direction is zero or not finite.
    DegenerateDirection { n: [f64; 2] },
    /// The start point is not finite.
    NonFiniteInput { q: [f64; 2] },
    /// The line q + t·n does not meet the obstacle curve for |t|·|n| ≤ `radius`.
    NoIntersection {
        q: [f64; 2],
        n: [f64; 2],
        radius: f64,
    },
}

impl fmt::Display for GeometryError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GeometryError::DegenerateDirection { n } => write!(
                f,
                "obstacle distance: direction n = ({}, {}) is zero or not finite",
                n[0], n[1]
            ),
            GeometryError::NonFiniteInput { q } => write!(
                f,
                "obstacle distance: start point q = ({}, {}) is not finite",
                q[0], q[1]
            ),
            GeometryError::NoIntersection { q, n, radius } => write!(
                f,
                "obstacle distance: the line ({}, {}) + t·({}, {}) does not meet the obstacle \
                 curve within distance {}",
                q[0], q[1], n[0], n[1], radius
            ),
        }
    }
}

impl std::error::Error for GeometryError {}

/// Which face of Ω = [−16,16]×\[0,1\] is the contact boundary and which obstacle it meets.
///
/// * `upper == false`: Γ_C = {x₂ = 0}, obstacle below the body, z-constraint s₂ ≥ b(x₁),
///   n_z = −e₂ (outward normal of the undeformed face).
/// * `upper == true`: Γ_C = {x₂ = 1}, obstacle above, s₂ ≤ b(x₁), n_z = +e₂.
///
/// In the deformed frame the obstacle is the curve {(t, y_face + b(t))}, y_face ∈ {0, 1} the
/// face's x₂ (the constraint s₂ ≥ b at x₂ = 0 reads x₂ + s₂ ≥ 0 + b).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactSide {
    pub shape: Shape,
    pub upper: bool,
}

impl ContactSide {
    pub fn new(shape: Shape, upper: bool) -> ContactSide {
        ContactSide { shape, upper }
    }

    /// x₂ of the undeformed contact face (0 or 1).
    pub fn y_face(&self) -> f64 {
        if self.upper {
            UPPER_FACE_Y
        } else {
            LOWER_FACE_Y
        }
    }

    /// Outward unit normal of the undeformed contact face, n_z = ∓e₂.
    pub fn n_z(&self) -> [f64; 2] {
        if self.upper {
            [0.0, 1.0]
        } else {
            [0.0, -1.0]
        }
    }

    /// b(x₁), the bound on s₂ of the z-contact model (I.20) at the **undeformed** x₁
    /// (docs/models.md §15 item 2): s₂ ≥ b (lower) or s₂ ≤ b (upper).
    pub fn z_bound(&self, x1: f64) -> f64 {
        self.shape.value(x1)
    }

    /// η_z (III.12): the distance along n_z from the undeformed face point (x₁, y_face) to the
    /// obstacle, so that the z-constraint reads r·n_z ≤ η_z (−b for lower, +b for upper).
    pub fn eta_z(&self, x1: f64) -> f64 {
        let b = self.z_bound(x1);
        if self.upper {
            b
        } else {
            -b
        }
    }

    /// η_z (III.12) at a boundary point p of the body: the distance along n_z from p to the
    /// obstacle y_face + b(p₁). On the undeformed face of the Chapter IV tables (p₂ = y_face)
    /// it is exactly [`ContactSide::eta_z`]`(p₁)`; on a moved body (the load steps of the U-O
    /// forming, §IV.2.4.7) the face point lies off y_face and the gap changes by the offset.
    pub fn eta_z_at(&self, p: [f64; 2]) -> f64 {
        let offset = p[1] - self.y_face();
        if offset == 0.0 {
            self.eta_z(p[0])
        } else if self.upper {
            self.z_bound(p[0]) - offset
        } else {
            offset - self.z_bound(p[0])
        }
    }

    /// Whether a displacement component s₂ at undeformed x₁ satisfies the z-constraint.
    pub fn z_admissible(&self, x1: f64, s2: f64, tol: f64) -> bool {
        let b = self.z_bound(x1);
        if self.upper {
            s2 <= b + tol
        } else {
            s2 >= b - tol
        }
    }

    /// The obstacle curve point (t, y_face + b(t)).
    pub fn obstacle_point(&self, t: f64) -> [f64; 2] {
        [t, self.y_face() + self.shape.value(t)]
    }

    /// Vertical signed clearance of a deformed point p from the obstacle: positive on the
    /// admissible side (body side), negative when p lies beyond the obstacle.
    pub fn vertical_clearance(&self, p: [f64; 2]) -> f64 {
        let c = self.y_face() + self.shape.value(p[0]);
        if self.upper {
            c - p[1]
        } else {
            p[1] - c
        }
    }

    /// Residual f(t) = (q + t n)₂ − y_face − b((q + t n)₁).
    fn residual(&self, q: [f64; 2], n: [f64; 2], t: f64) -> f64 {
        q[1] + t * n[1] - self.y_face() - self.shape.value(q[0] + t * n[0])
    }

    /// Bound on |f'| over t ∈ [t0, t1].
    fn residual_lipschitz(&self, q: [f64; 2], n: [f64; 2], t0: f64, t1: f64) -> f64 {
        let (x0, x1) = (q[0] + t0 * n[0], q[0] + t1 * n[0]);
        n[1].abs() + n[0].abs() * self.shape.slope_bound(x0, x1)
    }

    /// [`ContactSide::signed_distance_along`], or `None` when the obstacle is out of reach: the
    /// line meets no obstacle within [`SEARCH_RADIUS`] and q lies on the body's side of it, so no
    /// displacement below that radius (a thousand times the size of any Chapter IV body) reaches
    /// the obstacle — as for an obstacle at infinity. A line that meets nothing from beyond the
    /// obstacle is still an error.
    pub fn distance_within_reach(
        &self,
        q: [f64; 2],
        n: [f64; 2],
    ) -> Result<Option<f64>, GeometryError> {
        match self.signed_distance_along(q, n) {
            Ok(eta) => Ok(Some(eta)),
            Err(GeometryError::NoIntersection { .. }) if self.vertical_clearance(q) > 0.0 => {
                Ok(None)
            }
            Err(e) => Err(e),
        }
    }

    /// The signed distance η along n (III.13): the t with q + t·n on the obstacle curve, i.e.
    /// (q + t n)₂ = y_face + b((q + t n)₁). With n the outward normal of the body, t > 0 means
    /// a free gap ahead, t < 0 that q has penetrated. If n is a unit vector t is a distance.
    ///
    /// Algorithm: if n₁ == 0 the root is explicit. Otherwise march from t = 0 in the + and −
    /// directions with steps certified root-free by a Lipschitz bound of the residual
    /// (|f'| ≤ |n₂| + |n₁| max|b'| on the step, [`Shape::slope_bound`]); steps double while
    /// certified and shrink near a root down to 1e-7/|n|, where a sign change brackets it. The
    /// bracket is refined by Brent's method to |Δt| ≤ 1e-13. The − search is limited to the
    /// distance of the + root, so the root nearest to t = 0 is returned (two roots closer than
    /// 1e-7/|n| to each other, i.e. a near-tangency, may be stepped over). Error if no root lies
    /// within |t|·|n| ≤ [`SEARCH_RADIUS`], if the residual becomes non-finite, or (only for
    /// nearly grazing lines creeping along the obstacle) after 2·10⁶ march steps. Typical cost:
    /// a few dozen residual evaluations (≈ 1–15 µs).
    pub fn signed_distance_along(&self, q: [f64; 2], n: [f64; 2]) -> Result<f64, GeometryError> {
        if !(q[0].is_finite() && q[1].is_finite()) {
            return Err(GeometryError::NonFiniteInput { q });
        }
        let norm = n[0].hypot(n[1]);
        if !(norm.is_finite() && norm > 0.0) {
            return Err(GeometryError::DegenerateDirection { n });
        }
        let t_max = SEARCH_RADIUS / norm;
        let no_root = GeometryError::NoIntersection {
            q,
            n,
            radius: SEARCH_RADIUS,
        };
        if n[0] == 0.0 {
            // Vertical line: f(t) = q₂ + t n₂ − y_face − b(q₁) is affine.
            let t = (self.y_face() + self.shape.value(q[0]) - q[1]) / n[1];
            return if t.is_finite() && t.abs() <= t_max {
                Ok(t)
            } else {
                Err(no_root)
            };
        }
        let f0 = self.residual(q, n, 0.0);
        if !f0.is_finite() {
            return Err(GeometryError::NonFiniteInput { q });
        }
        if f0 == 0.0 {
            return Ok(0.0);
        }
        let h_min = 1.0e-7 / norm;
        let plus = self.march(q, n, f0, 1.0, t_max, h_min);
        let limit = plus.map_or(t_max, |t| t.abs());
        let minus = self.march(q, n, f0, -1.0, limit, h_min);
        let t = match (plus, minus) {
            (Some(p), Some(m)) => Some(if m.abs() < p.abs() { m } else { p }),
            (p, m) => p.or(m),
        };
        match t {
            Some(t) if t.is_finite() => Ok(t),
            _ => Err(no_root),
        }
    }

    /// Nearest root of the residual in direction `dir` (±1) with |t| ≤ `limit`.
    fn march(
        &self,
        q: [f64; 2],
        n: [f64; 2],
        f0: f64,
        dir: f64,
        limit: f64,
        h_min: f64,
    ) -> Option<f64> {
        let mut t = 0.0_f64; // |t|, position along dir
        let mut f = f0;
        let mut step = h_min;
        let mut iterations = 0usize;
        while t < limit {
            iterations += 1;
            if iterations > 2_000_000 || !f.is_finite() {
                return None;
            }
            let remaining = limit - t;
            let try_step = (2.0 * step).max(h_min).min(remaining);
            let lip = self.residual_lipschitz(q, n, dir * t, dir * (t + try_step));
            let certified = if lip > 0.0 {
                (0.99 * f.abs() / lip).min(try_step)
            } else {
                try_step
            };
            if certified >= h_min.min(remaining) {
                // No root in [t, t + certified]; advance.
                let t_next = t + certified;
                let f_next = self.residual(q, n, dir * t_next);
                if f_next == 0.0 {
                    return Some(dir * t_next);
                }
                if f_next.signum() != f.signum() {
                    // Only possible through rounding in the bound; treat as bracket.
                    return Some(self.brent(q, n, dir * t, dir * t_next, f, f_next));
                }
                t = t_next;
                f = f_next;
                step = certified;
            } else {
                let t_next = t + h_min.min(remaining);
                let f_next = self.residual(q, n, dir * t_next);
                if f_next == 0.0 {
                    return Some(dir * t_next);
                }
                if f_next.signum() != f.signum() {
                    return Some(self.brent(q, n, dir * t, dir * t_next, f, f_next));
                }
                t = t_next;
                f = f_next;
                step = h_min;
            }
        }
        None
    }

    /// Brent's method on a sign-changing bracket [a, b] of the residual.
    fn brent(&self, q: [f64; 2], n: [f64; 2], a: f64, b: f64, fa: f64, fb: f64) -> f64 {
        let (mut a, mut b, mut fa, mut fb) = (a, b, fa, fb);
        let mut c = a;
        let mut fc = fa;
        let mut d = b - a;
        let mut e = d;
        for _ in 0..200 {
            if fb.signum() == fc.signum() {
                c = a;
                fc = fa;
                d = b - a;
                e = d;
            }
            if fc.abs() < fb.abs() {
                a = b;
                b = c;
                c = a;
                fa = fb;
                fb = fc;
                fc = fa;
            }
            let tol = 2.0 * f64::EPSILON * b.abs() + 0.5 * ROOT_TOL;
            let m = 0.5 * (c - b);
            if m.abs() <= tol || fb == 0.0 {
                return b;
            }
            if e.abs() >= tol && fa.abs() > fb.abs() {
                let s = fb / fa;
                let (mut p, mut qq);
                if a == c {
                    p = 2.0 * m * s;
                    qq = 1.0 - s;
                } else {
                    let qa = fa / fc;
                    let r = fb / fc;
                    p = s * (2.0 * m * qa * (qa - r) - (b - a) * (r - 1.0));
                    qq = (qa - 1.0) * (r - 1.0) * (s - 1.0);
                }
                if p > 0.0 {
                    qq = -qq;
                } else {
                    p = -p;
                }
                if 2.0 * p < (3.0 * m * qq - (tol * qq).abs()).min((e * qq).abs()) {
                    e = d;
                    d = p / qq;
                } else {
                    d = m;
                    e = m;
                }
            } else {
                d = m;
                e = m;
            }
            a = b;
            fa = fb;
            b += if d.abs() > tol { d } else { tol.copysign(m) };
            fb = self.residual(q, n, b);
        }
        b
    }

    /// Outer unit normal of the deformed contact boundary polyline at the vertex `here`:
    /// the normalised mean of the outward unit normals of the faces prev→here and here→next.
    ///
    /// `prev`/`next` are the neighbouring contact-boundary vertices in order of increasing
    /// **reference** x₁; at an end of Γ_C pass `prev == here` or `next == here` (the degenerate
    /// face is ignored). The outward side follows from the orientation, not from the sign of n₂:
    /// for the lower face (body on the left of the +x₁ direction) the face normal of a tangent d
    /// is (d₂, −d₁)/|d|; for the upper face (body on the right) it is (−d₂, d₁)/|d|. If both faces
    /// are degenerate, or the two normals cancel (a cusp), n_z = ∓e₂ is returned.
    pub fn vertex_normal(prev: [f64; 2], here: [f64; 2], next: [f64; 2], upper: bool) -> [f64; 2] {
        let face_normal = |p: [f64; 2], r: [f64; 2]| -> Option<[f64; 2]> {
            let d = [r[0] - p[0], r[1] - p[1]];
            let len = d[0].hypot(d[1]);
            if !(len.is_finite() && len > 0.0) {
                return None;
            }
            Some(if upper {
                [-d[1] / len, d[0] / len]
            } else {
                [d[1] / len, -d[0] / len]
            })
        };
        let fallback = if upper { [0.0, 1.0] } else { [0.0, -1.0] };
        let mut sum = [0.0, 0.0];
        let mut count = 0;
        for nf in [face_normal(prev, here), face_normal(here, next)]
            .into_iter()
            .flatten()
        {
            sum[0] += nf[0];
            sum[1] += nf[1];
            count += 1;
        }
        if count == 0 {
            return fallback;
        }
        let len = sum[0].hypot(sum[1]);
        if len <= 1.0e-12 * f64::from(count) {
            return fallback;
        }
        [sum[0] / len, sum[1] / len]
    }

    /// Largest vertical depth by which the deformed boundary segment a→b lies beyond the
    /// obstacle, max over `samples.max(2)` equally spaced points (end points included) of
    /// (y_face + b(x₁) − y)⁺ on the lower side and (y − y_face − b(x₁))⁺ on the upper side;
    /// 0 if no sample penetrates. The vertical measure is the z-contact measure (constraint on
    /// s₂); for steep obstacle parts it overestimates the distance normal to the obstacle by at
    /// most a factor √(1 + b'²). Non-finite depths are ignored.
    pub fn penetration(&self, a: [f64; 2], b: [f64; 2], samples: usize) -> f64 {
        let m = samples.max(2);
        let mut depth = 0.0_f64;
        for i in 0..m {
            let lambda = i as f64 / (m - 1) as f64;
            let p = [a[0] + lambda * (b[0] - a[0]), a[1] + lambda * (b[1] - a[1])];
            let d = -self.vertical_clearance(p);
            if d.is_finite() && d > depth {
                depth = d;
            }
        }
        depth
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const S: f64 = 0.01;

    fn all_shapes() -> Vec<Shape> {
        vec![
            Shape::Constant { level: -2.0 },
            Shape::Periodic {
                offset: -2.0,
                amplitude: 1.2,
                periods: 2.0,
            },
            Shape::Jump {
                base: 2.0,
                height: 8.0,
                at: 0.0,
                s: S,
            },
            Shape::Jump {
                base: 0.0,
                height: -10.0,
                at: -1.0,
                s: S,
            },
            Shape::Jump {
                base: 2.0,
                height: -4.0,
                at: 2.0,
                s: S,
            },
            Shape::saw(SawReading::Continuous),
            Shape::saw(SawReading::Literal),
            Shape::Saw {
                s: 0.3,
                reading: SawReading::Continuous,
            },
        ]
    }

    #[test]
    fn theta_limits_symmetry_and_finiteness() {
        assert!((theta(S, 0.0) - 0.5).abs() < 1e-16);
        assert!(theta(S, 1e3) > 1.0 - 1e-10);
        assert!(theta(S, -1e3) < 1e-10);
        assert!(theta(S, -1e3) > 0.0);
        for &x in &[
            0.0,
            1e-5,
            0.003,
            0.01,
            0.2,
            1.0,
            7.5,
            1e4,
            1e10,
            1e200,
            1e300,
            f64::MAX,
        ] {
            for &s in &[1e-8, 0.01, 0.3, 2.0] {
                let (p, m) = (theta(s, x), theta(s, -x));
                assert!(p.is_finite() && m.is_finite(), "s={s} x={x}");
                assert!((0.0..=1.0).contains(&p) && (0.0..=1.0).contains(&m));
                assert!((p + m - 1.0).abs() < 4e-16, "s={s} x={x}: {p} + {m}");
                let d = theta_prime(s, x);
                assert!(d.is_finite() && d >= 0.0);
                assert!((d - theta_prime(s, -x)).abs() <= 1e-15 * d);
            }
        }
        // Far left the value is the small positive tail s²/(4x²), not a cancelled 0.
        let x = -1e6;
        let expect = S * S / (4.0 * x * x);
        assert!((theta(S, x) - expect).abs() < 1e-10 * expect);
        assert!((theta_prime(S, 0.0) - 0.5 / S).abs() < 1e-12);
    }

    #[test]
    fn theta_derivative_matches_fd() {
        for &s in &[0.01, 0.3] {
            for &x in &[-1.0, -0.02, -0.004, 0.0, 0.001, 0.015, 0.5, 3.0] {
                let h = 1e-6 * s;
                let fd = (theta(s, x + h) - theta(s, x - h)) / (2.0 * h);
                let d = theta_prime(s, x);
                assert!((fd - d).abs() <= 1e-6 * d + 1e-7, "s={s} x={x}");
            }
        }
    }

    #[test]
    fn shape_slopes_match_fd() {
        let xs = [
            -16.0, -10.0, -4.003, -4.0, -3.0, -2.004, -2.0, -1.0, -0.997, 0.0, 0.002, 1.0, 1.01,
            2.0, 2.005, 3.3, 5.0, 5.002, 6.0, 6.02, 12.0, 16.0,
        ];
        for shape in all_shapes() {
            for &x in &xs {
                let h = 1e-7;
                let fd = (shape.value(x + h) - shape.value(x - h)) / (2.0 * h);
                let d = shape.slope(x);
                let scale = d.abs().max(1.0);
                assert!(
                    (fd - d).abs() <= 2e-5 * scale,
                    "{shape:?} x={x}: fd {fd} analytic {d}"
                );
                // the bound really bounds the slope
                assert!(d.abs() <= shape.slope_bound(x - 1e-3, x + 1e-3) * (1.0 + 1e-12));
            }
        }
    }

    #[test]
    fn continuous_saw_through_nodes() {
        for &s in &[0.01, 0.001] {
            let saw = Shape::Saw {
                s,
                reading: SawReading::Continuous,
            };
            for (x, y) in SAW_X.iter().zip(SAW_Y.iter()) {
                let v = saw.value(*x);
                assert!((v - y).abs() <= s, "s={s} node ({x},{y}): {v}");
                // in fact only O(s²) at the nodes
                assert!((v - y).abs() <= 10.0 * s * s, "s={s} node ({x},{y}): {v}");
            }
            // piecewise linear away from the kinks, 0 outside [−4, 6]
            for &(x, y) in &[
                (-3.0, -0.5),
                (-0.5, -0.5),
                (3.0, 1.0),
                (5.5, 1.0),
                (-10.0, 0.0),
                (10.0, 0.0),
                (-16.0, 0.0),
                (16.0, 0.0),
            ] {
                assert!((saw.value(x) - y).abs() <= s, "s={s} x={x}");
            }
            // slopes of the pieces
            for &(x, m) in &[(-3.0, -0.5), (0.0, 1.0 / 3.0), (3.0, 0.5), (5.5, -2.0)] {
                assert!((saw.slope(x) - m).abs() <= 10.0 * s, "s={s} x={x}");
            }
            // continuity: no jumps at the nodes
            for x in SAW_X {
                let jump = (saw.value(x + 20.0 * s) - saw.value(x - 20.0 * s)).abs();
                assert!(jump <= 40.0 * s * 2.0 + 1e-12, "x={x}: {jump}");
            }
        }
    }

    #[test]
    fn literal_saw_jumps() {
        let saw = Shape::saw(SawReading::Literal);
        let d = 0.5;
        for &(x, j) in &[(-2.0, 1.0), (1.0, -1.0), (5.0, -2.0), (6.0, 2.0)] {
            // one-sided limits extrapolated from x ∓ d with the local slopes
            let left = saw.value(x - d) + saw.slope(x - d) * d;
            let right = saw.value(x + d) - saw.slope(x + d) * d;
            assert!((right - left - j).abs() < 5e-3, "x={x}: {left} → {right}");
        }
        assert!((saw.value(-3.0) + 0.5).abs() < 1e-3);
        assert!((saw.value(0.0) - 2.0 / 3.0).abs() < 1e-3);
        assert!((saw.value(3.0) - 1.0).abs() < 1e-3);
        assert!((saw.value(5.5) + 1.0).abs() < 1e-3);
    }

    #[test]
    fn periodic_and_jump_values() {
        let p = Shape::Periodic {
            offset: -2.0,
            amplitude: 1.2,
            periods: 2.0,
        };
        // x₁ = −12: 2·2π·4/32 = π/2
        assert!((p.value(-12.0) - (-0.8)).abs() < 1e-14);
        assert!((p.value(-16.0) + 2.0).abs() < 1e-14);
        let j = Shape::Jump {
            base: 2.0,
            height: 8.0,
            at: 0.0,
            s: S,
        };
        assert!((j.value(0.0) - 6.0).abs() < 1e-14);
        assert!((j.value(-5.0) - 2.0).abs() < 1e-5);
        assert!((j.value(5.0) - 10.0).abs() < 1e-5);
    }

    #[test]
    fn side_basics() {
        let low = ContactSide::new(Shape::Constant { level: -2.0 }, false);
        let up = ContactSide::new(Shape::Constant { level: 2.0 }, true);
        assert_eq!(low.y_face(), 0.0);
        assert_eq!(up.y_face(), 1.0);
        assert_eq!(low.n_z(), [0.0, -1.0]);
        assert_eq!(up.n_z(), [0.0, 1.0]);
        assert_eq!(low.z_bound(3.0), -2.0);
        assert_eq!(low.eta_z(3.0), 2.0);
        assert_eq!(up.eta_z(3.0), 2.0);
        assert_eq!(low.obstacle_point(1.5), [1.5, -2.0]);
        assert_eq!(up.obstacle_point(1.5), [1.5, 3.0]);
        assert!(low.z_admissible(0.0, -1.9, 0.0) && !low.z_admissible(0.0, -2.1, 0.0));
        assert!(up.z_admissible(0.0, 1.9, 0.0) && !up.z_admissible(0.0, 2.1, 0.0));
    }

    #[test]
    fn distance_flat_vertical_is_exact_gap() {
        let low = ContactSide::new(Shape::Constant { level: -2.0 }, false);
        assert_eq!(low.signed_distance_along([3.0, 0.5], [0.0, -1.0]), Ok(2.5));
        assert_eq!(
            low.signed_distance_along([3.0, -2.25], [0.0, -1.0]),
            Ok(-0.25)
        );
        let up = ContactSide::new(Shape::Constant { level: 2.0 }, true);
        let t = up.signed_distance_along([3.0, 1.25], [0.0, 1.0]).unwrap();
        assert_eq!(t, 1.75);
        // same with a tiny non-zero n₁ (goes through the march + Brent path)
        let t = low
            .signed_distance_along([3.0, 0.5], [1e-300, -1.0])
            .unwrap();
        assert!((t - 2.5).abs() < 1e-13);
    }

    #[test]
    fn distance_tilted_constant_analytic() {
        let low = ContactSide::new(Shape::Constant { level: -2.0 }, false);
        for &deg in &[-60.0_f64, -30.0, -5.0, 5.0, 30.0, 60.0] {
            let (sn, cs) = deg.to_radians().sin_cos();
            let n = [sn, -cs];
            for &(q2, expect) in &[(0.0, 2.0 / cs), (-2.5, -0.5 / cs), (0.7, 2.7 / cs)] {
                let t = low.signed_distance_along([1.0, q2], n).unwrap();
                assert!(
                    (t - expect).abs() < 1e-12,
                    "deg={deg} q2={q2}: {t} vs {expect}"
                );
            }
        }
        let up = ContactSide::new(Shape::Constant { level: 2.0 }, true);
        let (sn, cs) = 30f64.to_radians().sin_cos();
        let t = up.signed_distance_along([0.0, 1.0], [sn, cs]).unwrap();
        assert!((t - 2.0 / cs).abs() < 1e-12);
    }

    /// Brute-force nearest sign change of the residual on a grid of step 1e-4 within |t| ≤ range,
    /// for comparison.
    fn brute_nearest(side: &ContactSide, q: [f64; 2], n: [f64; 2], range: f64) -> Option<f64> {
        let h = 1e-4;
        let steps = (range / h) as i64;
        let mut best: Option<f64> = None;
        for dir in [1.0, -1.0] {
            let mut f_prev = side.residual(q, n, 0.0);
            for i in 1..=steps {
                let t = dir * i as f64 * h;
                let f = side.residual(q, n, t);
                if f == 0.0 || f.signum() != f_prev.signum() {
                    if best.is_none_or(|b| t.abs() < b.abs()) {
                        best = Some(t);
                    }
                    break;
                }
                f_prev = f;
            }
        }
        best
    }

    #[test]
    fn distance_at_theta_jumps() {
        // §IV.2.1.4 top: 2 + 8θ(x₁); §IV.2.1.5 bottom −10θ(x₁+1), top 2 − 4θ(x₁−2).
        let cases = [
            (
                ContactSide::new(
                    Shape::Jump {
                        base: 2.0,
                        height: 8.0,
                        at: 0.0,
                        s: S,
                    },
                    true,
                ),
                0.0,
            ),
            (
                ContactSide::new(
                    Shape::Jump {
                        base: 0.0,
                        height: -10.0,
                        at: -1.0,
                        s: S,
                    },
                    false,
                ),
                -1.0,
            ),
            (
                ContactSide::new(
                    Shape::Jump {
                        base: 2.0,
                        height: -4.0,
                        at: 2.0,
                        s: S,
                    },
                    true,
                ),
                2.0,
            ),
        ];
        let mut checked = 0;
        for (side, at) in cases.iter() {
            let outward = if side.upper { 1.0 } else { -1.0 };
            for &dx in &[-0.05, -0.01, -0.003, 0.0, 0.002, 0.01, 0.05] {
                let x1 = at + dx;
                let curve = side.obstacle_point(x1)[1];
                for &dy in &[-3.0, -0.5, -0.01, 0.0, 0.01, 0.5, 3.0] {
                    let q = [x1, curve + dy];
                    for &deg in &[-30.0_f64, 0.0, 30.0] {
                        let (sn, cs) = deg.to_radians().sin_cos();
                        let n = [sn, outward * cs];
                        let t = side
                            .signed_distance_along(q, n)
                            .unwrap_or_else(|e| panic!("{e}"));
                        assert!(t.is_finite());
                        let p = [q[0] + t * n[0], q[1] + t * n[1]];
                        let res = p[1] - side.obstacle_point(p[0])[1];
                        assert!(res.abs() < 1e-10, "q={q:?} n={n:?} t={t} res={res}");
                        if let Some(tb) = brute_nearest(side, q, n, t.abs() + 1e-3) {
                            assert!(
                                t.abs() <= tb.abs() + 1e-4,
                                "q={q:?} n={n:?}: got {t}, a root at {tb} is nearer"
                            );
                        }
                        checked += 1;
                    }
                }
            }
        }
        assert_eq!(checked, 3 * 7 * 7 * 3);
    }

    #[test]
    fn distance_picks_nearest_of_three_roots() {
        // Lower face, curve y = −10θ(x₁+1). The line from (−1.5, 0.5) along (sin30°, −cos30°)
        // meets the left plateau near x₁ ≈ −1.21 (t ≈ 0.58), crosses the smoothed wall again
        // near x₁ ≈ −1 and meets the lower plateau y = −10 at t ≈ 12: the first one is wanted.
        let side = ContactSide::new(
            Shape::Jump {
                base: 0.0,
                height: -10.0,
                at: -1.0,
                s: S,
            },
            false,
        );
        let (sn, cs) = 30f64.to_radians().sin_cos();
        let n = [sn, -cs];
        let q = [-1.5, 0.5];
        assert!(side.residual(q, n, 0.0) > 0.0);
        assert!(
            side.residual(q, n, 0.8) < 0.0,
            "below the curve after the first root"
        );
        assert!(
            side.residual(q, n, 2.0) > 0.0,
            "above the curve again behind the wall"
        );
        let t = side.signed_distance_along(q, n).unwrap();
        let p = [q[0] + t * n[0], q[1] + t * n[1]];
        assert!(t > 0.5 && t < 0.65, "{t}");
        assert!(p[0] < -1.15 && p[0] > -1.3, "{p:?}");
        assert!((p[1] - side.obstacle_point(p[0])[1]).abs() < 1e-10);
        // From a point beyond the wall the nearest crossing behind it is found (t < 0).
        let q = [-0.9, -0.5];
        let t = side.signed_distance_along(q, n).unwrap();
        assert!(t < 0.0 && t > -0.3, "{t}");
    }

    #[test]
    fn distance_saw_and_periodic() {
        for shape in [
            Shape::saw(SawReading::Continuous),
            Shape::saw(SawReading::Literal),
            Shape::Periodic {
                offset: -2.0,
                amplitude: 1.2,
                periods: 2.0,
            },
        ] {
            let side = ContactSide::new(shape, false);
            for &x1 in &[-4.0, -2.0, -1.0, 1.0, 5.0, 5.5, 6.0] {
                for &dy in &[-0.3, 0.0, 0.4] {
                    for &deg in &[-30.0_f64, 0.0, 30.0] {
                        let (sn, cs) = deg.to_radians().sin_cos();
                        let n = [sn, -cs];
                        let q = [x1, side.obstacle_point(x1)[1] + dy];
                        let t = side.signed_distance_along(q, n).unwrap();
                        let p = [q[0] + t * n[0], q[1] + t * n[1]];
                        assert!((p[1] - side.obstacle_point(p[0])[1]).abs() < 1e-10);
                        if let Some(tb) = brute_nearest(&side, q, n, t.abs() + 1e-3) {
                            assert!(t.abs() <= tb.abs() + 1e-4, "{shape:?} q={q:?} n={n:?}");
                        }
                    }
                }
            }
        }
    }

    /// The tools of the U-O forming at load steps j = 0, 12, 24, relative to their faces (the
    /// punch on the top face y = 1, the die on the bottom face y = 0).
    fn forming_tools(j: f64) -> [ContactSide; 2] {
        let lift = 10.0 * j / 24.0;
        [
            ContactSide::new(
                Shape::Arc {
                    center: [-16.0, 10.0 - 1.0],
                    radius: 8.8,
                    plateau: 1.2 + lift - 1.0,
                    s: 0.01,
                },
                true,
            ),
            ContactSide::new(
                Shape::Arc {
                    center: [-16.0, lift],
                    radius: 10.0,
                    plateau: lift,
                    s: 0.01,
                },
                false,
            ),
        ]
    }

    #[test]
    fn arc_values_and_slopes() {
        for j in [0.0, 12.0, 24.0] {
            let [punch, die] = forming_tools(j);
            let lift = 10.0 * j / 24.0;
            // Absolute heights: the punch starts 0.2 above the body, the die touches it at
            // the plateau; at j = 24 the circles are concentric, 1.2 apart. The algebraic
            // tails of θ_s (s²/4x²) move the heights at the clamp by less than 1e-5.
            assert!((punch.obstacle_point(-16.0)[1] - 1.2).abs() < 1e-5);
            assert!((die.obstacle_point(-16.0)[1] - (lift - 10.0)).abs() < 1e-5);
            assert!((die.obstacle_point(10.0)[1] - lift).abs() < 1e-12);
            assert!((punch.obstacle_point(10.0)[1] - (1.2 + lift)).abs() < 1e-5);
            for side in [punch, die] {
                for x in [-15.0, -12.0, -9.0, -7.5, 0.0, 8.0] {
                    let h = 1e-6;
                    let fd = (side.shape.value(x + h) - side.shape.value(x - h)) / (2.0 * h);
                    let exact = side.shape.slope(x);
                    assert!((fd - exact).abs() <= 1e-5 * (1.0 + exact.abs()), "x = {x}");
                    assert!(exact.abs() <= side.shape.slope_bound(x - 0.01, x + 0.01));
                }
                // Unbounded where an interval reaches the vertical end.
                let Shape::Arc { center, radius, .. } = side.shape else {
                    unreachable!()
                };
                let x_e = center[0] + radius;
                assert_eq!(side.shape.slope_bound(x_e - 0.1, x_e + 0.1), f64::INFINITY);
            }
        }
    }

    /// Distances along tilted lines that meet the tools near the vertical ends of their arcs:
    /// the root is correct to 1e-10 (a bisection of the residual to 1e-15 around it agrees) and
    /// is the nearest one.
    #[test]
    fn arc_distances_near_the_vertical_ends() {
        let mut checked = 0;
        for j in [0.0, 12.0, 24.0] {
            for side in forming_tools(j) {
                let Shape::Arc { center, radius, .. } = side.shape else {
                    unreachable!()
                };
                let x_e = center[0] + radius;
                let toward = if side.upper { 1.0 } else { -1.0 };
                for dx in [-0.5, -0.05, -1e-3, 0.0, 1e-3, 0.05] {
                    for dy in [0.05, 0.5] {
                        for deg in [-60.0_f64, -30.0, 0.0, 30.0, 60.0, 85.0] {
                            let (sn, cs) = deg.to_radians().sin_cos();
                            let n = [sn, toward * cs];
                            let x1 = x_e + dx;
                            let q = [x1, side.obstacle_point(x1)[1] - toward * dy];
                            let t = side
                                .signed_distance_along(q, n)
                                .unwrap_or_else(|e| panic!("q = {q:?}, n = {n:?}: {e}"));
                            let (mut a, mut b) = (t - 1e-9, t + 1e-9);
                            let (fa, fb) = (side.residual(q, n, a), side.residual(q, n, b));
                            assert!(
                                fa.signum() != fb.signum() || fa == 0.0 || fb == 0.0,
                                "j = {j}, q = {q:?}, n = {n:?}: no sign change around t = {t}"
                            );
                            for _ in 0..200 {
                                let m = 0.5 * (a + b);
                                if side.residual(q, n, m).signum() == fa.signum() {
                                    a = m;
                                } else {
                                    b = m;
                                }
                                if b - a < 1e-15 {
                                    break;
                                }
                            }
                            assert!((t - 0.5 * (a + b)).abs() <= 1e-10, "q = {q:?}, n = {n:?}");
                            if let Some(tb) = brute_nearest(&side, q, n, t.abs() + 1e-3) {
                                assert!(t.abs() <= tb.abs() + 1e-4, "q = {q:?} n = {n:?}");
                            }
                            checked += 1;
                        }
                    }
                }
            }
        }
        assert_eq!(checked, 432);
    }

    #[test]
    fn distance_errors() {
        let low = ContactSide::new(Shape::Constant { level: -2.0 }, false);
        let e = low
            .signed_distance_along([0.0, 0.0], [1.0, 0.0])
            .unwrap_err();
        assert!(matches!(e, GeometryError::NoIntersection { .. }));
        assert!(e.to_string().contains("does not meet"));
        let e = low
            .signed_distance_along([0.0, 0.0], [0.0, 0.0])
            .unwrap_err();
        assert!(matches!(e, GeometryError::DegenerateDirection { .. }));
        let e = low
            .signed_distance_along([0.0, 0.0], [f64::NAN, 1.0])
            .unwrap_err();
        assert!(matches!(e, GeometryError::DegenerateDirection { .. }));
        let e = low
            .signed_distance_along([f64::INFINITY, 0.0], [0.0, -1.0])
            .unwrap_err();
        assert!(matches!(e, GeometryError::NonFiniteInput { .. }));
        // Far beyond the search radius.
        let e = low
            .signed_distance_along([0.0, 5e3], [0.0, -1.0])
            .unwrap_err();
        assert!(matches!(e, GeometryError::NoIntersection { .. }));
        // Horizontal line that crosses the jump does have a root.
        let j = ContactSide::new(
            Shape::Jump {
                base: 2.0,
                height: 8.0,
                at: 0.0,
                s: S,
            },
            true,
        );
        let t = j.signed_distance_along([-3.0, 7.0], [1.0, 0.0]).unwrap();
        assert!((j.obstacle_point(-3.0 + t)[1] - 7.0).abs() < 1e-10);
        assert!((t - 3.0).abs() < 0.02);
    }

    #[test]
    fn vertex_normals() {
        let low = ContactSide::vertex_normal([-1.0, 0.0], [0.0, 0.0], [1.0, 0.0], false);
        assert!((low[0]).abs() < 1e-15 && (low[1] + 1.0).abs() < 1e-15);
        let up = ContactSide::vertex_normal([-1.0, 1.0], [0.0, 1.0], [1.0, 1.0], true);
        assert!((up[0]).abs() < 1e-15 && (up[1] - 1.0).abs() < 1e-15);
        // end vertices: a single face
        let e = ContactSide::vertex_normal([0.0, 0.0], [0.0, 0.0], [1.0, 1.0], false);
        let r = 0.5f64.sqrt();
        assert!((e[0] - r).abs() < 1e-15 && (e[1] + r).abs() < 1e-15);
        let e = ContactSide::vertex_normal([-1.0, 1.0], [0.0, 2.0], [0.0, 2.0], true);
        assert!((e[0] + r).abs() < 1e-15 && (e[1] - r).abs() < 1e-15);
        // symmetric V (lower face dented downward): mean normal is −e₂
        let v = ContactSide::vertex_normal([-1.0, 0.0], [0.0, -1.0], [1.0, 0.0], false);
        assert!(v[0].abs() < 1e-15 && (v[1] + 1.0).abs() < 1e-15);
        // asymmetric: unit length and between the two face normals
        let v = ContactSide::vertex_normal([-1.0, 0.0], [0.0, 0.0], [1.0, 1.0], false);
        assert!((v[0].hypot(v[1]) - 1.0).abs() < 1e-15);
        assert!(v[0] > 0.0 && v[1] < 0.0);
        // fully degenerate → n_z
        assert_eq!(
            ContactSide::vertex_normal([0.0, 0.0], [0.0, 0.0], [0.0, 0.0], true),
            [0.0, 1.0]
        );
    }

    #[test]
    fn penetration_detection() {
        let low = ContactSide::new(Shape::Constant { level: -2.0 }, false);
        assert_eq!(low.penetration([0.0, -1.0], [1.0, -1.5], 5), 0.0);
        assert_eq!(low.penetration([0.0, -2.0], [1.0, -2.0], 5), 0.0);
        let d = low.penetration([0.0, -2.5], [1.0, -1.5], 5);
        assert!((d - 0.5).abs() < 1e-15);
        // penetration only in the middle of the segment (upper jump obstacle)
        let up = ContactSide::new(
            Shape::Jump {
                base: 2.0,
                height: -4.0,
                at: 2.0,
                s: S,
            },
            true,
        );
        // the curve is y = 1 + b: 3 left of x₁ = 2, −1 right of it.
        assert_eq!(up.penetration([0.0, 2.5], [1.5, 2.5], 10), 0.0);
        let d = up.penetration([1.0, 0.0], [3.0, 0.0], 201);
        assert!((d - 1.0).abs() < 1e-3, "{d}");
        let lowj = ContactSide::new(
            Shape::Jump {
                base: 0.0,
                height: -10.0,
                at: -1.0,
                s: S,
            },
            false,
        );
        assert_eq!(lowj.penetration([-3.0, 0.0], [-1.1, 0.0], 20), 0.0);
        assert!((lowj.penetration([-0.5, -10.5], [0.5, -10.5], 3) - 0.5).abs() < 1e-2);
    }
}
