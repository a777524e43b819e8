//! The contact face of Ω and the obstacle it meets: the z-contact bound, the signed distance
//! along a normal (III.13) by a bracketing march and Brent's method, deformed-boundary vertex
//! normals and a penetration measure.

use super::{GeometryError, Shape, LOWER_FACE_Y, ROOT_TOL, SEARCH_RADIUS, UPPER_FACE_Y};

/// Which face of Ω = [−16,16]×\[0,1\] is the contact boundary and which obstacle it meets.
///
/// * `upper == false`: Γ_C = {x₂ = 0}, obstacle below the body, z-constraint s₂ ≥ b(x₁),
///   n_z = −e₂ (outward normal of the undeformed face).
/// * `upper == true`: Γ_C = {x₂ = 1}, obstacle above, s₂ ≤ b(x₁), n_z = +e₂.
///
/// In the deformed frame the obstacle is the curve {(t, y_face + b(t))}, y_face ∈ {0, 1} the
/// face's x₂ (the constraint s₂ ≥ b at x₂ = 0 reads x₂ + s₂ ≥ 0 + b).
#[derive(Debug, Clone, PartialEq)]
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
    pub(super) fn residual(&self, q: [f64; 2], n: [f64; 2], t: f64) -> f64 {
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
