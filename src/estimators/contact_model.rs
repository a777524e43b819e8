//! The contact model error: how far the z-contact model (I.20) is from the Signorini model (I.21)
//! on each contact face — the local projection difference ε_P of (III.9)–(III.16) and the face
//! indicator ε^m(f) = ‖ε_P(s_h)‖_{L2(f)} that Algorithms III.2/III.3 mark with
//! (docs/estimators.md §3.2–§3.4).
//!
//! **Reading (docs/estimators.md §3.4, \[R\]/\[A\]).** Both s_z and s_s of Theorem III.4 are replaced by the current
//! solution s_h (the thesis orders faces by "the monotony of the estimate with regard to
//! ε(s_h)"). At every contact vertex σ:
//! * n_z and η_z: the fixed direction ∓e₂ and the obstacle distance along it from the undeformed
//!   point (III.12);
//! * n_s: the outward unit normal of the deformed boundary polyline x + s_h at σ (mean of the two
//!   adjacent face normals, as in the Signorini solver), η_s: the distance along n_s from
//!   σ + s_h(σ) to the obstacle curve (III.13), by the same root finder;
//! * (Z) ⇔ η_z − s_h·n_z ≥ 0 and (S) ⇔ η_s ≥ 0, each up to 1e-12·(1 + |η|), so that a flat
//!   obstacle, where (S) ⇔ (Z), gives exactly 0;
//! * ε_P(σ) = 0 if (S) and (Z), else |η_s − η_z + s_h·n_z| (III.16).
//!
//! Between the vertices ε_P is linear, so ‖ε_P‖²_{L2(f)} = |f|/3·(a² + ab + b²) with the vertex
//! values a, b and the length |f| of the undeformed face.

use crate::models::obstacle::ContactSide;
use crate::models::ModelError;

/// Relative tolerance of the tests (S) and (Z).
pub const CONDITION_TOLERANCE: f64 = 1e-12;

/// ε_P(s_h) (III.16) at one vertex from η_z, η_s and s_h·n_z; η_s = +∞ when the normal line
/// meets no obstacle on the body's side (an obstacle out of reach: (S) holds).
pub fn projection_difference(eta_z: f64, eta_s: f64, s_dot_nz: f64) -> f64 {
    let z_gap = eta_z - s_dot_nz;
    let z_holds = z_gap >= -CONDITION_TOLERANCE * (1.0 + eta_z.abs());
    let s_holds = eta_s >= -CONDITION_TOLERANCE * (1.0 + eta_s.abs());
    if z_holds && s_holds {
        0.0
    } else {
        (eta_s - z_gap).abs()
    }
}

/// ε_P at the vertices of one contact side: `points` are the undeformed vertices in order of
/// increasing x₁ (hanging ones included), `displacement` the values of s_h there.
///
/// An obstacle out of reach of a vertex's normal line on the body's side gives η_s = +∞; if (Z)
/// fails there as well, the vertex has passed the z-obstacle but cannot see the Signorini one,
/// and that is an error naming the vertex, as is any other failure of the root finder.
pub fn vertex_differences(
    side: &ContactSide,
    points: &[[f64; 2]],
    displacement: &[[f64; 2]],
) -> Result<Vec<f64>, ModelError> {
    assert_eq!(
        points.len(),
        displacement.len(),
        "one displacement per vertex"
    );
    let deformed: Vec<[f64; 2]> = points
        .iter()
        .zip(displacement)
        .map(|(x, s)| [x[0] + s[0], x[1] + s[1]])
        .collect();
    let n_z = side.n_z();
    (0..points.len())
        .map(|i| {
            let here = deformed[i];
            let prev = deformed[i.saturating_sub(1)];
            let next = deformed[(i + 1).min(points.len() - 1)];
            let n_s = ContactSide::vertex_normal(prev, here, next, side.upper);
            let s = displacement[i];
            let s_dot_nz = s[0] * n_z[0] + s[1] * n_z[1];
            let eta_z = side.eta_z_at(points[i]);
            let eta_s = side
                .distance_within_reach(here, n_s)
                .map_err(|e| {
                    format!(
                        "model error at the contact vertex ({}, {}): {e}",
                        points[i][0], points[i][1]
                    )
                })?
                .unwrap_or(f64::INFINITY);
            let eps = projection_difference(eta_z, eta_s, s_dot_nz);
            if eps.is_finite() {
                Ok(eps)
            } else {
                Err(ModelError::Failed(format!(
                    "model error at the contact vertex ({}, {}): the z-constraint fails there \
                     (s₂ beyond the obstacle by {:e}) but the normal line of the deformed \
                     boundary meets no obstacle",
                    points[i][0],
                    points[i][1],
                    s_dot_nz - eta_z
                )))
            }
        })
        .collect()
}

/// The face indicators ε^m(f) = ‖ε_P‖_{L2(f)} of the faces between consecutive `points`, from
/// the vertex values `differences` of [`vertex_differences`]: |f|/3·(a² + ab + b²), square-rooted.
pub fn face_indicators(points: &[[f64; 2]], differences: &[f64]) -> Vec<f64> {
    assert_eq!(points.len(), differences.len(), "one value per vertex");
    points
        .windows(2)
        .zip(differences.windows(2))
        .map(|(p, e)| {
            let length = (p[1][0] - p[0][0]).hypot(p[1][1] - p[0][1]);
            let (a, b) = (e[0], e[1]);
            (length / 3.0 * (a * a + a * b + b * b)).sqrt()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::obstacle::Shape;

    fn lower_face(n: usize) -> Vec<[f64; 2]> {
        (0..=n)
            .map(|i| [-16.0 + 32.0 * i as f64 / n as f64, 0.0])
            .collect()
    }

    #[test]
    fn the_difference_is_zero_when_both_conditions_hold_and_else_the_gap_difference() {
        assert_eq!(projection_difference(0.5, 0.7, 0.1), 0.0);
        // (Z) fails: z-gap 0.5 − 0.6 = −0.1; |η_s − z-gap| = |0.2 + 0.1|.
        assert!((projection_difference(0.5, 0.2, 0.6) - 0.3).abs() < 1e-15);
        // (S) fails alone.
        assert!((projection_difference(0.5, -0.1, 0.1) - 0.5).abs() < 1e-15);
        // Within the tolerance both hold.
        assert_eq!(projection_difference(0.5, -1e-13, 0.5 + 1e-13), 0.0);
    }

    #[test]
    fn a_flat_obstacle_gives_exactly_zero_for_an_admissible_displacement() {
        let side = ContactSide::new(Shape::Constant { level: -0.25 }, false);
        let points = lower_face(64);
        // A wavy displacement above the obstacle, and one resting on it.
        for lift in [0.1, 0.0] {
            let s: Vec<[f64; 2]> = points
                .iter()
                .map(|p| {
                    [
                        0.01 * p[0].sin(),
                        -0.25 + lift + lift * (p[0] * 0.3).cos().abs(),
                    ]
                })
                .collect();
            let d = vertex_differences(&side, &points, &s).unwrap();
            assert!(d.iter().all(|&e| e == 0.0), "lift {lift}: {d:?}");
            assert!(face_indicators(&points, &d).iter().all(|&e| e == 0.0));
        }
    }

    #[test]
    fn a_sloped_obstacle_gives_the_normal_minus_the_vertical_gap() {
        // A smooth ramp b = θ₄(x₁) (slope ≤ 1/8). A body resting on it in the z-sense, s = (0, b):
        // the deformed boundary is the obstacle curve, (S) and (Z) hold, ε = 0. Shifted sideways
        // by 0.5, s = (0.5, b(x₁)): (Z) still holds (it looks at the undeformed x₁), but the
        // deformed point lies below the rising obstacle, so (S) fails.
        let side = ContactSide::new(
            Shape::Jump {
                base: 0.0,
                height: 1.0,
                at: 0.0,
                s: 4.0,
            },
            false,
        );
        let points = lower_face(64);
        let resting: Vec<[f64; 2]> = points.iter().map(|p| [0.0, side.z_bound(p[0])]).collect();
        let d = vertex_differences(&side, &points, &resting).unwrap();
        assert!(d.iter().all(|&e| e == 0.0), "{d:?}");
        let shifted: Vec<[f64; 2]> = points.iter().map(|p| [0.5, side.z_bound(p[0])]).collect();
        let d = vertex_differences(&side, &points, &shifted).unwrap();
        let mid = 32; // x₁ = 0, where the obstacle rises fastest
        assert!(d[mid] > 0.0, "{:?}", &d[28..36]);
        // At the vertex: the deformed point (0.5, b(0)) lies below b(0.5) by b(0.5) − b(0) along
        // a nearly vertical normal: ε ≈ |η_s − 0| ≈ b(0.5) − b(0).
        let rise = side.z_bound(0.5) - side.z_bound(0.0);
        assert!((d[mid] - rise).abs() < 0.02 * rise, "{} vs {rise}", d[mid]);
    }

    #[test]
    fn face_indicators_integrate_the_linear_interpolant() {
        let points = [[0.0, 0.0], [2.0, 0.0], [3.0, 0.0]];
        let f = face_indicators(&points, &[1.0, 2.0, 0.0]);
        // ∫₀² (1 + t/2)² dt = 2/3·(1 + 2 + 4) = 14/3; ∫₀¹ (2 − 2t)² dt = 4/3.
        assert!((f[0] * f[0] - 14.0 / 3.0).abs() < 1e-14);
        assert!((f[1] * f[1] - 4.0 / 3.0).abs() < 1e-14);
    }

    #[test]
    fn an_obstacle_out_of_reach_is_no_model_error() {
        let side = ContactSide::new(Shape::Constant { level: -1e6 }, false);
        let points = lower_face(8);
        let s = vec![[0.0, 0.0]; points.len()];
        let d = vertex_differences(&side, &points, &s).unwrap();
        assert!(d.iter().all(|&e| e == 0.0));
    }
}
