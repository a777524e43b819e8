//! The pressure updates of the Uzawa family (III.87)–(III.92): the approximate Schur diagonal
//! D, the Gauss–Seidel sweeps, the projection p ≥ 0, and one update p^k → p^{k+1} of each
//! variant ([`Update`]).

use super::cg_step::CgStep;
use super::inner::Inner;
use super::iterate::Iterate;
use super::{CgRule, DirectionProduct, UzawaError, UzawaOptions, Variant};
use crate::linalg::saddle_point::{dot, SaddlePoint};

/// D_jj = Σ_i B_ij² / A_ii + C_jj, the diagonal of Bᵀ diag(A)⁻¹ B + C.
pub fn approximate_schur_diagonal(system: &SaddlePoint) -> Vec<f64> {
    let a_diag = system.a.diagonal();
    let c_diag = system.c.diagonal();
    (0..system.n_pressure())
        .map(|j| {
            system
                .bt()
                .row(j)
                .map(|(i, b)| b * b / a_diag[i])
                .sum::<f64>()
                + c_diag[j]
        })
        .collect()
}

/// One Gauss–Seidel sweep (III.90)/(III.91) in place: for j in `order`,
/// p_j ← p_j + (g_j − (Bᵀv)_j − Σ_i C_ji p_i)/D_jj with the current p (updated entries
/// before j in the sweep, old ones after), projected if asked.
pub(super) fn sweep(
    system: &SaddlePoint,
    d: &[f64],
    btv: &[f64],
    p: &mut [f64],
    order: impl Iterator<Item = usize>,
    projected: bool,
) {
    for j in order {
        let cp: f64 = system.c.row(j).map(|(i, c)| c * p[i]).sum();
        let mut pj = p[j] + (system.g[j] - btv[j] - cp) / d[j];
        if projected {
            pj = pj.max(0.0);
        }
        p[j] = pj;
    }
}

/// p_j ← max(p_j, 0) for every pressure of a projected run (nothing otherwise).
pub(super) fn project(p: &mut [f64], projected: bool) {
    if projected {
        for x in p.iter_mut() {
            *x = x.max(0.0);
        }
    }
}

/// What the pressure update of outer iteration `iteration` works with: the system, the run's
/// options and inner solver, the diagonal D, the last outer residual r_k (which sets the
/// inner tolerance τ(r_k)) and ‖f + Bp^k‖ (which makes it relative for the S·w solves).
pub(super) struct Update<'a> {
    pub(super) system: &'a SaddlePoint,
    pub(super) options: &'a UzawaOptions,
    pub(super) inner: &'a Inner<'a>,
    pub(super) d: &'a [f64],
    pub(super) iteration: usize,
    pub(super) last_residual: f64,
    pub(super) velocity_rhs_norm: f64,
}

/// The CG-SSOR state carried from one outer iteration to the next.
#[derive(Default)]
pub(super) struct CgState {
    /// d = p^k − p^{k−1} and S d.
    direction: Option<(Vec<f64>, Vec<f64>)>,
    /// [`CgRule::Safeguarded`]: the face of the last step.
    face: Option<Vec<bool>>,
}

impl Update<'_> {
    /// p^k → p^{k+1} by the variant of the run, from the Schur residual
    /// `s` = g − Bᵀv^k − Cp^k = b_S − S p^k: Richardson (III.87), Jacobi (III.89), one
    /// Gauss–Seidel sweep (III.90), SSOR (III.91) or CG-SSOR (III.92) as printed or
    /// safeguarded. Returns the inner iterations spent.
    pub(super) fn apply(
        &self,
        x: &mut Iterate,
        s: &[f64],
        cg: &mut CgState,
    ) -> Result<usize, UzawaError> {
        let (system, options, d) = (self.system, self.options, self.d);
        let m = system.n_pressure();
        match options.variant {
            Variant::Identity => {
                for (p, s) in x.p.iter_mut().zip(s) {
                    *p += options.damping * s;
                }
                project(&mut x.p, options.projected);
                Ok(0)
            }
            Variant::Jacobi => {
                for ((p, s), d) in x.p.iter_mut().zip(s).zip(d) {
                    *p += s / d;
                }
                project(&mut x.p, options.projected);
                Ok(0)
            }
            Variant::GaussSeidel => {
                sweep(system, d, &x.btv, &mut x.p, 0..m, options.projected);
                Ok(0)
            }
            Variant::CgSsor if options.cg_rule == CgRule::Safeguarded => self.safeguarded(x, s, cg),
            Variant::Ssor | Variant::CgSsor => self.ssor(x, s, &mut cg.direction),
        }
    }

    /// SSOR (III.91), and for CG-SSOR as printed the two-term step of (III.92) after it.
    fn ssor(
        &self,
        x: &mut Iterate,
        s: &[f64],
        direction: &mut Option<(Vec<f64>, Vec<f64>)>,
    ) -> Result<usize, UzawaError> {
        let (system, options, d) = (self.system, self.options, self.d);
        let m = system.n_pressure();
        let old = x.p.clone();
        // Forward sweep from v^k, then v^{k+½} = A⁻¹(f + B p^{k+¼}), backward sweep.
        sweep(system, d, &x.btv, &mut x.p, 0..m, options.projected);
        let mut inner_iterations =
            x.half_step(system, self.inner, self.last_residual, self.iteration)?;
        sweep(system, d, &x.btv, &mut x.p, (0..m).rev(), options.projected);
        if options.variant == Variant::CgSsor {
            let step = self.cg_step(options.projected);
            inner_iterations += step.run(&old, &mut x.p, s, direction)?;
        }
        Ok(inner_iterations)
    }

    /// CG-SSOR with [`CgRule::Safeguarded`]: a proportioning step when the chopped residual
    /// outweighs the residual on the face, else SSOR over the face, the scaled residual D⁻¹s
    /// where the SSOR correction is no descent direction, and the face's CG step.
    fn safeguarded(
        &self,
        x: &mut Iterate,
        s: &[f64],
        cg: &mut CgState,
    ) -> Result<usize, UzawaError> {
        let (system, options, d) = (self.system, self.options, self.d);
        let m = system.n_pressure();
        let mut inner_iterations = 0;
        // The face {p_j > 0} (every unknown without projection); the chopped residual
        // c_j = max(s_j, 0) at p_j = 0 (the bound unknowns the descent direction
        // s = −∇J would raise).
        let bounded = options.projected;
        let free: Vec<bool> = x.p.iter().map(|&x| !bounded || x > 0.0).collect();
        let step = self.cg_step(bounded);
        if bounded {
            let chopped: Vec<f64> = (0..m)
                .map(|j| if free[j] { 0.0 } else { s[j].max(0.0) })
                .collect();
            let on_face: f64 = (0..m).filter(|&j| free[j]).map(|j| s[j] * s[j]).sum();
            if dot(&chopped, &chopped) > on_face {
                // Proportioning: release along c with the exact step ‖c‖²/cᵀSc.
                inner_iterations += step.release(&mut x.p, &chopped)?;
                cg.direction = None;
                cg.face = None;
                return Ok(inner_iterations);
            }
        }
        if cg.face.as_ref() != Some(&free) {
            cg.direction = None;
        }
        let old = x.p.clone();
        let forward = (0..m).filter(|&j| free[j]);
        sweep(system, d, &x.btv, &mut x.p, forward, false);
        inner_iterations += x.half_step(system, self.inner, self.last_residual, self.iteration)?;
        let backward = (0..m).rev().filter(|&j| free[j]);
        sweep(system, d, &x.btv, &mut x.p, backward, false);
        // The SSOR correction need not be a descent direction (the sweeps freeze
        // BᵀA⁻¹B); if it is not, the diagonally scaled residual on the face is.
        let p = &mut x.p;
        let q_s: f64 = (0..m).map(|j| (p[j] - old[j]) * s[j]).sum();
        if q_s.is_nan() || q_s <= 0.0 {
            for j in 0..m {
                p[j] = old[j] + if free[j] { s[j] / d[j] } else { 0.0 };
            }
            cg.direction = None;
        }
        inner_iterations += step.run_on_face(&old, p, s, &mut cg.direction)?;
        cg.face = Some(free);
        Ok(inner_iterations)
    }

    /// The CG step of this iteration; its S·w solves go to the relative accuracy of the v^k
    /// solve, τ(r_k) / ‖f + Bp^k‖.
    fn cg_step(&self, projected: bool) -> CgStep<'_> {
        let options = self.options;
        CgStep {
            system: self.system,
            inner: self.inner,
            relative: self.inner.tolerance(self.last_residual)
                / self.velocity_rhs_norm.max(f64::MIN_POSITIVE),
            projected,
            iteration: self.iteration,
            fresh: options.direction_product == DirectionProduct::Fresh,
        }
    }
}
