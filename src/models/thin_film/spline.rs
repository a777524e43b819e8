//! [`CubicSpline`]: the natural cubic spline through a tabulated gap profile (x₁, g), with its
//! derivatives up to third order and enclosures of its range.

/// The natural cubic spline through the points (x_k, y_k), k = 0 … n, x_k strictly increasing.
///
/// On [x_k, x_{k+1}] it is the cubic y_k + b_k t + c_k t² + d_k t³, t = x − x_k, with the second
/// derivatives M_k = 2c_k solving the tridiagonal system
///
///   h_{k−1} M_{k−1} + 2(h_{k−1} + h_k) M_k + h_k M_{k+1} = 6 (δ_k − δ_{k−1}),  k = 1 … n−1,
///
/// h_k = x_{k+1} − x_k, δ_k = (y_{k+1} − y_k)/h_k, and the natural end conditions M_0 = M_n = 0;
/// then b_k = δ_k − h_k (2M_k + M_{k+1})/6 and d_k = (M_{k+1} − M_k)/(6h_k).
///
/// The spline is C² (value, slope and curvature continuous at every knot); its third
/// derivative d_k·6 is constant on each piece and jumps at the knots. Beyond the end points it
/// continues as the straight line of its end slope, which keeps it C² there too (M = 0 at the
/// ends). "Natural" because no end slopes need to be known: a tabulated profile carries none.
#[derive(Debug, Clone, PartialEq)]
pub struct CubicSpline {
    /// The knots x_0 < … < x_n.
    knots: Vec<f64>,
    /// [y_k, b_k, c_k, d_k] of the piece on [x_k, x_{k+1}], k = 0 … n−1.
    pieces: Vec<[f64; 4]>,
    /// The slope at x_n (that of the straight continuation to the right).
    end_slope: f64,
}

impl CubicSpline {
    /// The natural cubic spline through `points` (x strictly increasing, at least two points;
    /// the loader checks both). Fewer than two points give a spline that is NaN everywhere, a
    /// point out of order one with NaN or infinite pieces: never a panic.
    pub fn natural(points: &[[f64; 2]]) -> CubicSpline {
        let n = points.len().saturating_sub(1);
        if n == 0 {
            return CubicSpline {
                knots: vec![f64::NAN, f64::NAN],
                pieces: vec![[f64::NAN; 4]],
                end_slope: f64::NAN,
            };
        }
        let x: Vec<f64> = points.iter().map(|p| p[0]).collect();
        let y: Vec<f64> = points.iter().map(|p| p[1]).collect();
        let h: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
        let delta: Vec<f64> = (0..n).map(|k| (y[k + 1] - y[k]) / h[k]).collect();
        // The second derivatives M_1 … M_{n−1} by the Thomas algorithm (the system is strictly
        // diagonally dominant); M_0 = M_n = 0.
        let mut m = vec![0.0; n + 1];
        if n >= 2 {
            let inner = n - 1;
            let mut diag = vec![0.0; inner];
            let mut rhs = vec![0.0; inner];
            for i in 0..inner {
                let k = i + 1;
                diag[i] = 2.0 * (h[k - 1] + h[k]);
                rhs[i] = 6.0 * (delta[k] - delta[k - 1]);
            }
            // Forward elimination: row i has h_{i} below-left, h_{i+1} above-right (k = i + 1).
            for i in 1..inner {
                let factor = h[i] / diag[i - 1];
                diag[i] -= factor * h[i];
                rhs[i] -= factor * rhs[i - 1];
            }
            m[inner] = rhs[inner - 1] / diag[inner - 1];
            for i in (0..inner - 1).rev() {
                m[i + 1] = (rhs[i] - h[i + 1] * m[i + 2]) / diag[i];
            }
        }
        let pieces: Vec<[f64; 4]> = (0..n)
            .map(|k| {
                let b = delta[k] - h[k] * (2.0 * m[k] + m[k + 1]) / 6.0;
                [y[k], b, 0.5 * m[k], (m[k + 1] - m[k]) / (6.0 * h[k])]
            })
            .collect();
        let [_, b, c, d] = pieces[n - 1];
        let t = h[n - 1];
        CubicSpline {
            knots: x,
            pieces,
            end_slope: b + t * (2.0 * c + 3.0 * d * t),
        }
    }

    /// [s, s', s'', s'''] at `x`: on [x_0, x_n] of the piece that holds x (the piece to the
    /// right at an interior knot; s''' jumps there, s, s', s'' do not), beyond the ends of the
    /// straight continuation.
    #[inline]
    pub fn derivatives(&self, x: f64) -> [f64; 4] {
        let (first, last) = (self.knots[0], self.knots[self.knots.len() - 1]);
        if x < first {
            let [y, b, _, _] = self.pieces[0];
            return [y + b * (x - first), b, 0.0, 0.0];
        }
        if x > last {
            let y = self.value_in(self.pieces.len() - 1, last);
            return [y + self.end_slope * (x - last), self.end_slope, 0.0, 0.0];
        }
        let k = self.piece_of(x);
        let [y, b, c, d] = self.pieces[k];
        let t = x - self.knots[k];
        [
            y + t * (b + t * (c + t * d)),
            b + t * (2.0 * c + 3.0 * d * t),
            2.0 * c + 6.0 * d * t,
            6.0 * d,
        ]
    }

    /// The spline's value at `x`.
    pub fn value(&self, x: f64) -> f64 {
        self.derivatives(x)[0]
    }

    /// The piece k with x_k ≤ x < x_{k+1}, the last piece for x = x_n (x within [x_0, x_n]).
    fn piece_of(&self, x: f64) -> usize {
        let after = self.knots.partition_point(|&k| k <= x);
        after.clamp(1, self.pieces.len()) - 1
    }

    /// Piece k's cubic at `x` (also outside its interval).
    fn value_in(&self, k: usize, x: f64) -> f64 {
        let [y, b, c, d] = self.pieces[k];
        let t = x - self.knots[k];
        y + t * (b + t * (c + t * d))
    }

    /// An enclosure of the spline's values on [lo, hi] (any order), with the point of the
    /// minimum: `(min, argmin, max)`. On each piece the cubic's extremes lie at the ends of the
    /// part of the piece within [lo, hi] or at a root of its derivative b + 2ct + 3dt² there; the
    /// straight continuations beyond the ends have theirs at the ends. Every candidate value is
    /// widened by a bound of its rounding error, 4ε·(|y| + |bt| + |ct²| + |dt³|), so the result
    /// encloses the exact spline's range, not only the computed one.
    pub fn range(&self, lo: f64, hi: f64) -> (f64, f64, f64) {
        let (lo, hi) = if lo <= hi { (lo, hi) } else { (hi, lo) };
        let mut min = (f64::INFINITY, lo);
        let mut max = f64::NEG_INFINITY;
        let mut visit = |value: f64, error: f64, at: f64| {
            if value - error < min.0 {
                min = (value - error, at);
            }
            max = max.max(value + error);
        };
        let (first, last) = (self.knots[0], self.knots[self.knots.len() - 1]);
        // The straight continuations: value and error at an end of [lo, hi] beyond the knots.
        for x in [lo, hi] {
            if x < first || x > last {
                let v = self.derivatives(x)[0];
                visit(v, 4.0 * f64::EPSILON * v.abs(), x);
            }
        }
        let from = lo.max(first);
        let to = hi.min(last);
        if from <= to {
            for k in self.piece_of(from)..=self.piece_of(to) {
                let [y, b, c, d] = self.pieces[k];
                let x0 = self.knots[k];
                let t0 = from.max(x0) - x0;
                let t1 = to.min(self.knots[k + 1]) - x0;
                if t0 > t1 {
                    continue;
                }
                let mut candidates = vec![t0, t1];
                // Roots of 3d t² + 2c t + b in [t0, t1].
                let (qa, qb, qc) = (3.0 * d, 2.0 * c, b);
                if qa == 0.0 {
                    if qb != 0.0 {
                        candidates.push(-qc / qb);
                    }
                } else {
                    let disc = qb * qb - 4.0 * qa * qc;
                    if disc >= 0.0 {
                        // Without cancellation: q = −(qb + sign(qb)√disc)/2, roots q/qa, qc/q.
                        let q = -0.5 * (qb + disc.sqrt().copysign(qb));
                        candidates.push(q / qa);
                        if q != 0.0 {
                            candidates.push(qc / q);
                        }
                    }
                }
                for t in candidates {
                    if !(t >= t0 && t <= t1) {
                        continue;
                    }
                    let value = y + t * (b + t * (c + t * d));
                    let size = y.abs() + (b * t).abs() + (c * t * t).abs() + (d * t * t * t).abs();
                    visit(value, 4.0 * f64::EPSILON * size, x0 + t);
                }
            }
        }
        (min.0, min.1, max)
    }

    /// The index k of the knot at or left of `x` within [x_0, x_n] (for messages that name the
    /// rows around a point).
    pub fn knot_before(&self, x: f64) -> usize {
        self.piece_of(x.clamp(self.knots[0], self.knots[self.knots.len() - 1]))
    }
}
