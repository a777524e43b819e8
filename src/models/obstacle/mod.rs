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
//!   - IV.2.1.6 `Saw { s, reading }` (l. 5485; repeated verbatim at l. 5940, 6476, 6896);
//!   - scenes of the user's own: `Sine` (a periodic obstacle with its own period and phase) and
//!     `Tabulated` (piecewise linear through the rows of a CSV file).
//! * [`ContactSide`]: which face of Ω = [−16,16]×\[0,1\] touches the obstacle, with the z-contact
//!   bound, the signed distance along a normal (III.13) used by the Signorini linearisation and the
//!   model-error indicator (III.16), deformed-boundary vertex normals and a penetration measure.

//!
//! The obstacle functions are in `shape`, the contact face and its distance search in `side`.

mod shape;
mod side;
#[cfg(test)]
mod tests;

pub use shape::{theta, theta_derivatives, theta_prime, Polyline, SawReading, Shape};
pub use side::ContactSide;

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
