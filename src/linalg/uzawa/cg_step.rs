//! The CG step of CG-SSOR (III.92): the minimisation of ½pᵀSp − b_Sᵀp over the plane through
//! p^k spanned by the SSOR correction q and the previous direction d, as printed
//! ([`CgRule::AsPrinted`], [`CgStep::run`]) or safeguarded with the
//! face method of projected runs ([`CgRule::Safeguarded`],
//! [`CgStep::release`], [`CgStep::run_on_face`]; module docs of [`super`]).

use super::inner::{schur_product, Inner};
use super::pressure::project;
use super::UzawaError;
#[cfg(doc)]
use super::{CgRule, DirectionProduct};
use crate::linalg::saddle_point::{dot, SaddlePoint};

/// Trial points t = 1, ½, … of the projected path P(p + t w) in a blocked step of projected
/// [`CgRule::Safeguarded`].
const PROJECTED_SEARCH_STEPS: usize = 8;

/// The CG step of (III.92) in outer iteration `iteration`.
pub(super) struct CgStep<'a> {
    pub(super) system: &'a SaddlePoint,
    pub(super) inner: &'a Inner<'a>,
    /// Relative accuracy of the S·w solves: that of the v^k solve, tolerance / ‖f + Bp^k‖.
    pub(super) relative: f64,
    pub(super) projected: bool,
    pub(super) iteration: usize,
    /// [`DirectionProduct::Fresh`]: S d by a solve, not by the recurrence.
    pub(super) fresh: bool,
}

impl CgStep<'_> {
    /// Projected [`CgRule::Safeguarded`], proportioning: p ← p + t c with c ≥ 0 the chopped residual and
    /// t = cᵀr/cᵀSc = ‖c‖²/cᵀSc, the minimiser of J along c (feasible: c only raises
    /// pressures). Returns the inner iterations.
    pub(super) fn release(&self, p: &mut [f64], c: &[f64]) -> Result<usize, UzawaError> {
        let (sc, its) = schur_product(self.system, self.inner, c, self.relative, self.iteration)?;
        let csc = dot(c, &sc);
        if csc > 0.0 {
            let t = dot(c, c) / csc;
            for (p, c) in p.iter_mut().zip(c) {
                *p += t * c;
            }
        }
        Ok(its)
    }

    /// [`CgRule::Safeguarded`]: after the SSOR step on the face, `old` = p^k → `p` = p^{k+½}
    /// (q = p^{k+½} − p^k vanishes off the face), with the Schur residual `r` = b_S − S p^k:
    /// the two-term step w = αq + βd (α = qᵀr/qᵀSq along q alone after a restart,
    /// `direction` = None); taken whole if p^k + w ≥ 0, else the better of P(p^k + w) and
    /// p^k + t_max w (t_max the largest feasible step), and the direction is dropped
    /// (restart). Leaves p^{k+1} ≥ 0 in `p`; returns the inner iterations.
    pub(super) fn run_on_face(
        &self,
        old: &[f64],
        p: &mut [f64],
        r: &[f64],
        direction: &mut Option<(Vec<f64>, Vec<f64>)>,
    ) -> Result<usize, UzawaError> {
        let (system, inner) = (self.system, self.inner);
        let q: Vec<f64> = p.iter().zip(old).map(|(a, b)| a - b).collect();
        p.copy_from_slice(old);
        let (sq, mut its) = schur_product(system, inner, &q, self.relative, self.iteration)?;
        let (qsq, qr) = (dot(&q, &sq), dot(&q, r));
        if qsq.is_nan() || qsq <= 0.0 {
            // No SSOR correction on the face: nothing to step along.
            *direction = None;
            return Ok(its);
        }
        let (alpha, beta) = match direction.as_ref() {
            Some((d, sd)) => {
                let dsd = dot(d, sd);
                let qsd = dot(&q, sd);
                let dr = dot(d, r);
                let den = qsq * dsd - qsd * qsd;
                let beta = if dsd > 0.0 && den > 1e-14 * qsq * dsd {
                    (qsq * dr - qsd * qr) / den
                } else {
                    0.0
                };
                ((qr - beta * qsd) / qsq, beta)
            }
            None => (qr / qsq, 0.0),
        };
        let mut w = q.clone();
        let mut sw = sq.clone();
        for x in w.iter_mut().chain(sw.iter_mut()) {
            *x *= alpha;
        }
        if let Some((d, sd)) = direction.as_ref() {
            if beta != 0.0 {
                for j in 0..w.len() {
                    w[j] += beta * d[j];
                    sw[j] += beta * sd[j];
                }
            }
        }
        // Largest feasible step along w and the unknown that blocks it.
        let (t_max, blocking) = (0..w.len())
            .filter(|&j| self.projected && w[j] < 0.0)
            .map(|j| (old[j] / -w[j], j))
            .fold(
                (f64::INFINITY, usize::MAX),
                |a, b| if b.0 < a.0 { b } else { a },
            );
        if t_max >= 1.0 {
            for j in 0..p.len() {
                p[j] = old[j] + w[j];
            }
            project(p, self.projected);
            if self.fresh {
                let (fresh, more) =
                    schur_product(system, inner, &w, self.relative, self.iteration)?;
                its += more;
                sw = fresh;
            }
            *direction = Some((w, sw));
            return Ok(its);
        }
        // J(p^k + u) − J(p^k) = −uᵀr + ½uᵀSu. Along the segment p^k + t w, J decreases up to
        // t = 1 (w minimises J on a plane through p^k containing w), so its best feasible
        // point is the truncation at t_max. Along the projected path P(p^k + t w), t = 1, ½,
        // ¼, … while t > t_max, the first point below the truncation is taken.
        let truncated = -t_max * dot(&w, r) + 0.5 * t_max * t_max * dot(&w, &sw);
        let mut t = 1.0;
        let mut taken = false;
        for _ in 0..PROJECTED_SEARCH_STEPS {
            if t <= t_max {
                break;
            }
            let projected: Vec<f64> = (0..p.len()).map(|j| (old[j] + t * w[j]).max(0.0)).collect();
            let wp: Vec<f64> = projected.iter().zip(old).map(|(a, b)| a - b).collect();
            let (swp, more) = schur_product(system, inner, &wp, self.relative, self.iteration)?;
            its += more;
            if -dot(&wp, r) + 0.5 * dot(&wp, &swp) < truncated {
                p.copy_from_slice(&projected);
                taken = true;
                break;
            }
            t *= 0.5;
        }
        if !taken {
            for j in 0..p.len() {
                p[j] = (old[j] + t_max * w[j]).max(0.0);
            }
            p[blocking] = 0.0;
        }
        *direction = None;
        Ok(its)
    }

    /// After the SSOR step `old` = p^k → `p` = p^{k+½}, with the Schur residual `r` =
    /// b_S − S p^k: leave p^{k+1} in `p` and update (d, Sd). Returns the inner iterations.
    pub(super) fn run(
        &self,
        old: &[f64],
        p: &mut [f64],
        r: &[f64],
        direction: &mut Option<(Vec<f64>, Vec<f64>)>,
    ) -> Result<usize, UzawaError> {
        let (system, inner) = (self.system, self.inner);
        let q: Vec<f64> = p.iter().zip(old).map(|(a, b)| a - b).collect();
        let (sq, mut its) = schur_product(system, inner, &q, self.relative, self.iteration)?;
        let qsq = dot(&q, &sq);
        let mut coefficients = None;
        if let Some((d, sd)) = direction.as_ref() {
            if qsq > 0.0 {
                let dsd = dot(d, sd);
                let qsd = dot(&q, sd);
                let (dr, qr) = (dot(d, r), dot(&q, r));
                let den = qsq * dsd - qsd * qsd;
                // q ∥ d (or d = 0): the plane degenerates, minimise along q alone.
                let beta = if dsd > 0.0 && den > 1e-14 * qsq * dsd {
                    (qsq * dr - qsd * qr) / den
                } else {
                    0.0
                };
                let alpha = (qr - beta * qsd) / qsq;
                for j in 0..p.len() {
                    p[j] = old[j] + alpha * q[j] + beta * d[j];
                }
                coefficients = Some((alpha, beta));
            }
        }
        let mut clipped = false;
        if self.projected {
            for x in p.iter_mut() {
                if *x < 0.0 {
                    *x = 0.0;
                    clipped = true;
                }
            }
        }
        let d_new: Vec<f64> = p.iter().zip(old).map(|(a, b)| a - b).collect();
        let sd_new = match (coefficients, direction.as_ref()) {
            (Some((alpha, beta)), Some((_, sd))) if !clipped && !self.fresh => sq
                .iter()
                .zip(sd)
                .map(|(a, b)| alpha * a + beta * b)
                .collect(),
            // p = p^{k+½}: d_new = q exactly.
            (None, _) if !clipped => sq,
            _ => {
                let (sd, more) =
                    schur_product(system, inner, &d_new, self.relative, self.iteration)?;
                its += more;
                sd
            }
        };
        *direction = Some((d_new, sd_new));
        Ok(its)
    }
}
