//! The iterate (v^k, p^k) of a Uzawa run with its work vectors, the velocity solves
//! v = A⁻¹(f + Bp), and the residual of a row (module docs of [`super`], "Residual and rows").

use super::inner::Inner;
use super::pressure::project;
use super::UzawaError;
use crate::linalg::saddle_point::{dot, SaddlePoint};

/// The iterate of a run and the products computed from it.
pub(super) struct Iterate {
    /// p^k (within an SSOR update, the pressures being swept).
    pub(super) p: Vec<f64>,
    /// v^k (within an SSOR update, v^{k+½}).
    pub(super) v: Vec<f64>,
    /// f + B p, the right-hand side of the last velocity solve.
    pub(super) rhs_v: Vec<f64>,
    /// A v.
    av: Vec<f64>,
    /// Bᵀ v, for the pressure sweeps.
    pub(super) btv: Vec<f64>,
    /// C p.
    cp: Vec<f64>,
}

impl Iterate {
    /// v = 0 and p⁰ = `initial_pressure` (0 if `None`), max(p⁰, 0) in a projected run.
    pub(super) fn new(
        system: &SaddlePoint,
        initial_pressure: Option<&[f64]>,
        projected: bool,
    ) -> Iterate {
        let (n, m) = (system.n_velocity(), system.n_pressure());
        let mut p = initial_pressure.map_or_else(|| vec![0.0; m], <[f64]>::to_vec);
        project(&mut p, projected);
        Iterate {
            p,
            v: vec![0.0; n],
            rhs_v: vec![0.0; n],
            av: vec![0.0; n],
            btv: vec![0.0; m],
            cp: vec![0.0; m],
        }
    }

    /// `rhs_v` = f + B p.
    fn velocity_rhs(&mut self, system: &SaddlePoint) {
        system.b.multiply_into(&self.p, &mut self.rhs_v);
        for (r, f) in self.rhs_v.iter_mut().zip(&system.f) {
            *r += f;
        }
    }

    /// Row k: v^k = A⁻¹(f + B p^k) (warm from the last velocity) and the residual of
    /// (v^k, p^k), with s = g − Bᵀv^k − Cp^k = b_S − S p^k (up to the inner error). The solve
    /// starts at the tolerance τ(`last_residual`) and goes on (warm) until its residual also
    /// meets the tolerance of the outer residual it produces, not only that of the previous
    /// one. Returns (residual, s, inner iterations).
    pub(super) fn measure(
        &mut self,
        system: &SaddlePoint,
        inner: &Inner<'_>,
        projected: bool,
        last_residual: f64,
        iteration: usize,
    ) -> Result<(f64, Vec<f64>, usize), UzawaError> {
        let m = system.n_pressure();
        let mut inner_iterations = 0;
        self.velocity_rhs(system);
        system.c.multiply_into(&self.p, &mut self.cp);
        let mut tolerance_residual = last_residual;
        loop {
            inner_iterations += inner.solve(
                &self.rhs_v,
                &mut self.v,
                inner.tolerance(tolerance_residual),
                iteration,
            )?;
            system.a.multiply_into(&self.v, &mut self.av);
            let momentum: f64 = self
                .av
                .iter()
                .zip(&self.rhs_v)
                .map(|(a, r)| (a - r) * (a - r))
                .sum();
            system.bt().multiply_into(&self.v, &mut self.btv);
            let s: Vec<f64> = (0..m)
                .map(|j| system.g[j] - self.btv[j] - self.cp[j])
                .collect();
            let mass = if projected {
                // Natural residual of the complementarity: min(p_j, λ_j), λ = −s.
                s.iter()
                    .zip(&self.p)
                    .map(|(s, p)| p.min(-s).powi(2))
                    .sum::<f64>()
            } else {
                dot(&s, &s)
            };
            let residual = (momentum + mass).sqrt();
            let tight = inner.tolerance(residual);
            if !residual.is_finite()
                || inner.factor.is_some()
                || momentum.sqrt() <= tight
                || tight >= inner.tolerance(tolerance_residual)
            {
                return Ok((residual, s, inner_iterations));
            }
            tolerance_residual = residual;
        }
    }

    /// The middle of an SSOR update: v^{k+½} = A⁻¹(f + B p^{k+¼}) (warm, to τ(`last_residual`))
    /// and Bᵀv^{k+½} for the backward sweep. Returns the inner iterations.
    pub(super) fn half_step(
        &mut self,
        system: &SaddlePoint,
        inner: &Inner<'_>,
        last_residual: f64,
        iteration: usize,
    ) -> Result<usize, UzawaError> {
        self.velocity_rhs(system);
        let its = inner.solve(
            &self.rhs_v,
            &mut self.v,
            inner.tolerance(last_residual),
            iteration,
        )?;
        system.bt().multiply_into(&self.v, &mut self.btv);
        Ok(its)
    }
}
