//! Tests of the obstacle geometry.

use super::shape::{SAW_X, SAW_Y};
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
        -16.0, -10.0, -4.003, -4.0, -3.0, -2.004, -2.0, -1.0, -0.997, 0.0, 0.002, 1.0, 1.01, 2.0,
        2.005, 3.3, 5.0, 5.002, 6.0, 6.02, 12.0, 16.0,
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
        let side = ContactSide::new(shape.clone(), false);
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

/// A tabulated obstacle over x₁ ∈ [−16, 16]: a bump with a flat top and a dip.
fn polyline() -> Shape {
    Shape::Tabulated(std::sync::Arc::new(Polyline::new(&[
        [-16.0, -2.0],
        [-5.0, -2.0],
        [-3.0, -0.5],
        [0.0, -0.5],
        [2.5, -3.0],
        [16.0, -2.0],
    ])))
}

fn sine() -> Shape {
    Shape::Sine {
        offset: -1.0,
        amplitude: 0.4,
        period: 5.0,
        phase: 1.5,
    }
}

/// The periodic obstacle with its own period and phase, and the periodic obstacle of the
/// thesis as the special case period = 32/periods, phase = −16.
#[test]
fn sine_values_and_slopes() {
    let s = sine();
    assert_eq!(s.value(1.5), -1.0);
    assert!((s.value(1.5 + 1.25) - (-0.6)).abs() < 1e-15);
    assert!((s.value(1.5 - 1.25) - (-1.4)).abs() < 1e-15);
    let k = std::f64::consts::TAU / 5.0;
    assert!((s.slope(1.5) - 0.4 * k).abs() < 1e-15);
    assert_eq!(s.slope_bound(-100.0, 100.0), 0.4 * k);
    let thesis = Shape::Periodic {
        offset: -2.0,
        amplitude: 1.2,
        periods: 2.0,
    };
    let same = Shape::Sine {
        offset: -2.0,
        amplitude: 1.2,
        period: 16.0,
        phase: -16.0,
    };
    for i in 0..=64 {
        let x = -16.0 + 0.5 * i as f64;
        assert!((thesis.value(x) - same.value(x)).abs() < 1e-14, "x = {x}");
        assert!((thesis.slope(x) - same.slope(x)).abs() < 1e-14, "x = {x}");
    }
}

/// The tabulated obstacle: through its rows, straight between them, constant beyond them; the
/// slope is the segment's (from the right at a row), and the bound is a Lipschitz constant of b
/// on the interval, attained by a segment that meets it.
#[test]
fn tabulated_values_slopes_and_bounds() {
    let p = polyline();
    for (x, b) in [
        (-16.0, -2.0),
        (-5.0, -2.0),
        (-3.0, -0.5),
        (2.5, -3.0),
        (16.0, -2.0),
    ] {
        assert_eq!(p.value(x), b, "x = {x}");
    }
    assert_eq!(p.value(-4.0), -1.25);
    assert_eq!(p.value(-40.0), -2.0);
    assert_eq!(p.value(1e6), -2.0);
    assert_eq!(p.slope(-4.0), 0.75);
    assert_eq!(p.slope(-3.0), 0.0, "from the right");
    assert_eq!(p.slope(1.0), -1.0);
    assert_eq!(p.slope(-20.0), 0.0);
    assert_eq!(p.slope(16.0), 0.0);
    assert_eq!(p.slope_bound(-16.0, 16.0), 1.0);
    assert_eq!(p.slope_bound(-4.0, -3.5), 0.75);
    assert_eq!(p.slope_bound(-3.0, -3.0), 0.75, "both segments at a row");
    assert_eq!(p.slope_bound(-2.0, -1.0), 0.0);
    assert_eq!(p.slope_bound(20.0, 30.0), 0.0);
    assert_eq!(p.slope_bound(-30.0, -20.0), 0.0);
    assert_eq!(p.slope_bound(3.0, -4.0), 1.0, "any order");
    // Slopes against differences away from the rows; the bound against every pair of samples
    // of random intervals.
    let mut seed: u64 = 7;
    let mut next = || {
        seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    for shape in [p, sine()] {
        for _ in 0..200 {
            let x = -20.0 + 40.0 * next();
            let h = 1e-7;
            if [-16.0, -5.0, -3.0, 0.0, 2.5, 16.0]
                .iter()
                .all(|r: &f64| (r - x).abs() > 2.0 * h)
            {
                let fd = (shape.value(x + h) - shape.value(x - h)) / (2.0 * h);
                assert!((fd - shape.slope(x)).abs() < 1e-6, "{shape:?} x = {x}");
            }
            let (a, b) = (-20.0 + 40.0 * next(), -20.0 + 40.0 * next());
            let bound = shape.slope_bound(a, b);
            let samples: Vec<f64> = (0..=50).map(|i| a + (b - a) * i as f64 / 50.0).collect();
            for &u in &samples {
                for &v in &samples {
                    let rise = (shape.value(u) - shape.value(v)).abs();
                    assert!(rise <= bound * (u - v).abs() * (1.0 + 1e-12) + 1e-15);
                }
            }
        }
    }
    // Fewer than two rows: no panic.
    let empty = Shape::Tabulated(std::sync::Arc::new(Polyline::new(&[])));
    assert!(empty.value(0.0).is_nan());
    assert_eq!(empty.slope_bound(-1.0, 1.0), 0.0);
}

/// The distance search over the kinks of a tabulated obstacle finds the nearest crossing.
#[test]
fn distance_tabulated() {
    let side = ContactSide::new(polyline(), false);
    for &x1 in &[-6.0, -5.0, -3.0, -1.0, 0.0, 2.5, 10.0] {
        for &dy in &[-0.3, 0.0, 0.4] {
            for &deg in &[-30.0_f64, 0.0, 30.0] {
                let (sn, cs) = deg.to_radians().sin_cos();
                let n = [sn, -cs];
                let q = [x1, side.obstacle_point(x1)[1] + dy];
                let t = side.signed_distance_along(q, n).unwrap();
                let p = [q[0] + t * n[0], q[1] + t * n[1]];
                assert!((p[1] - side.obstacle_point(p[0])[1]).abs() < 1e-10);
                if let Some(tb) = brute_nearest(&side, q, n, t.abs() + 1e-3) {
                    assert!(t.abs() <= tb.abs() + 1e-4, "q={q:?} n={n:?}");
                }
            }
        }
    }
}

/// θ_s and its derivatives up to third order against differences of the order below.
#[test]
fn theta_derivatives_match_fd() {
    for &s in &[0.01, 0.3] {
        for &x in &[-1.0, -0.02, -0.004, 0.0, 0.001, 0.015, 0.5, 3.0] {
            let j = theta_derivatives(s, x);
            assert_eq!(j[0], theta(s, x));
            assert_eq!(j[1], theta_prime(s, x));
            let h = 1e-6 * s;
            let (p, m) = (theta_derivatives(s, x + h), theta_derivatives(s, x - h));
            for o in 1..4 {
                let fd = (p[o - 1] - m[o - 1]) / (2.0 * h);
                let scale = j[o].abs().max(1.0 / s.powi(o as i32) * 1e-3);
                assert!(
                    (fd - j[o]).abs() <= 1e-5 * scale,
                    "s={s} x={x} order {o}: {fd} vs {}",
                    j[o]
                );
            }
        }
    }
    // Finite far out and for s = 0.
    for x in [1e200, -1e300, f64::MAX] {
        assert!(theta_derivatives(0.01, x).iter().all(|v| v.is_finite()));
    }
    assert_eq!(theta_derivatives(0.0, 1.0), [1.0, 0.0, 0.0, 0.0]);
}
