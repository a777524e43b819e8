//! Manufactured solutions: closed-form fields whose data are derived from them, so that the
//! true error of a run can be measured against the estimate. This module holds the exact
//! fields, their derivatives and the data that follow from them; the error itself is measured
//! in [`crate::estimators::true_error`].
//!
//! # The elasticity solution `arctan-cross`
//!
//! On the unit square [0, 1]², with p(t) = t(1 − t) · atan(α(t − ½)) and α = [`STEEPNESS`],
//!
//! w(x) = p(x₁) p(x₂),   s(x) = (w(x), w(x)).
//!
//! Why this field: it is smooth (C^∞), so Q₁ elements on well adapted meshes reach the optimal
//! rate dofs^{−½} in the energy norm; the arctan makes a front of width ~1/α along x₁ = ½ and
//! along x₂ = ½ where the gradients are about α/4 times larger than elsewhere, so a uniform
//! mesh wastes most of its cells and the adaptive marking has something to find. The factor
//! t(1 − t) makes s vanish on the whole boundary: with Γ₀ = ∂Ω the Dirichlet data s = 0 are
//! taken exactly by the Q₁ space (no interpolation of boundary data, hence no boundary data
//! oscillation), and no traction data are needed.
//!
//! The volume load is ρf = −div σ(s) with σ(s) = 2μ ε(s) + 2λ (div s) I (the thesis's 2λ,
//! (I.17)): div σ(s) = μΔs + (μ + 2λ)∇(div s), from the first and second derivatives of w,
//!
//! ∂₁w = p′(x₁)p(x₂), ∂₂w = p(x₁)p′(x₂), ∂₁₁w = p″(x₁)p(x₂), ∂₂₂w = p(x₁)p″(x₂),
//! ∂₁₂w = p′(x₁)p′(x₂),
//!
//! so that, with both components equal to w, Δs_i = ∂₁₁w + ∂₂₂w and
//! ∂_i(div s) = ∂_i1 w + ∂_i2 w. The load is evaluated at the quadrature points of the
//! assembly and of the estimator's cell residual, so both see the same f; the data
//! oscillation h_Q‖f − f_h‖ that a projected load would add does not arise.
//!
//! # The Reynolds solution `arctan-cross`
//!
//! The same w on the unit square as a pressure: ψ = ψ₀ + A·w with ψ₀ the scene's
//! `boundary_pressure` and A = [`PRESSURE_AMPLITUDE`], so ψ = ψ₀ on ∂Ω₂ exactly (the Dirichlet
//! data of the Reynolds problem, taken exactly by Q₁). The load replaces l_R (II.37): from the
//! strong form −(1/g)∂_μ(g²∂_μ(ψ/g)) = −Δψ + ψΔg/g of (I.77),
//!
//! l = −A(∂₁₁w + ∂₂₂w) + ψ Δg/g,
//!
//! for the scene's gap g, evaluated where the model evaluates l_R (the 2×2 Gauss points shared by
//! the assembly and the cell residual of Theorem III.16), so the estimator sees the same load.

use std::sync::Arc;

use crate::experiment::ExactSolution;
use crate::models::elasticity::VolumeForce;
use crate::models::thin_film::ThinFilm;

/// α of `arctan-cross`: the front is ~1/α = 0.04 wide, a few cells of a coarse 8×8 grid
/// refined three to four times.
pub const STEEPNESS: f64 = 25.0;

/// p(t) = t(1 − t) atan(α(t − ½)) and its first two derivatives.
fn profile(t: f64) -> [f64; 3] {
    let (b, db, ddb) = (t * (1.0 - t), 1.0 - 2.0 * t, -2.0);
    let z = STEEPNESS * (t - 0.5);
    let den = 1.0 + z * z;
    let (a, da, dda) = (
        z.atan(),
        STEEPNESS / den,
        -2.0 * STEEPNESS * STEEPNESS * z / (den * den),
    );
    [b * a, db * a + b * da, ddb * a + 2.0 * db * da + b * dda]
}

/// A of the Reynolds solution: the pressure rises by up to A·max w ≈ 139 above ψ₀ (ψ₀ = 200 in
/// the thesis's examples), so ψ > 0 everywhere and the film needs no cavitation.
pub const PRESSURE_AMPLITUDE: f64 = 1000.0;

/// w, its gradient and its Hessian at x.
fn scalar(name: ExactSolution, x: [f64; 2]) -> (f64, [f64; 2], [[f64; 2]; 2]) {
    match name {
        ExactSolution::ArctanCross => {
            let [p1, d1, dd1] = profile(x[0]);
            let [p2, d2, dd2] = profile(x[1]);
            (
                p1 * p2,
                [d1 * p2, p1 * d2],
                [[dd1 * p2, d1 * d2], [d1 * d2, p1 * dd2]],
            )
        }
    }
}

/// A closed-form pressure ψ = ψ₀ + A·w of the Reynolds problem (I.79) on its domain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExactPressure {
    pub name: ExactSolution,
    /// ψ₀, the boundary value.
    pub base: f64,
}

impl ExactPressure {
    /// ψ(x).
    pub fn value(&self, x: [f64; 2]) -> f64 {
        self.base + PRESSURE_AMPLITUDE * scalar(self.name, x).0
    }

    /// ∇ψ(x).
    pub fn gradient(&self, x: [f64; 2]) -> [f64; 2] {
        scalar(self.name, x).1.map(|d| PRESSURE_AMPLITUDE * d)
    }

    /// The load l = −Δψ + ψΔg/g at x for the gap of `film`.
    pub fn load(&self, film: &ThinFilm, x: [f64; 2]) -> f64 {
        let (_, _, h) = scalar(self.name, x);
        let (g, _, laplace_g) = film.gap(x);
        -PRESSURE_AMPLITUDE * (h[0][0] + h[1][1]) + self.value(x) * laplace_g / g
    }
}

/// A closed-form displacement field s of linear elasticity (I.17) on its domain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExactDisplacement {
    pub name: ExactSolution,
}

impl ExactDisplacement {
    /// The field named in an experiment file.
    pub fn of(name: ExactSolution) -> ExactDisplacement {
        ExactDisplacement { name }
    }

    /// w, its gradient and its Hessian at x.
    fn scalar(&self, x: [f64; 2]) -> (f64, [f64; 2], [[f64; 2]; 2]) {
        scalar(self.name, x)
    }

    /// s(x).
    pub fn value(&self, x: [f64; 2]) -> [f64; 2] {
        let (w, _, _) = self.scalar(x);
        [w, w]
    }

    /// ∇s(x), rows = components (the layout of [`super::elasticity::Elasticity::stress`]).
    pub fn gradient(&self, x: [f64; 2]) -> [[f64; 2]; 2] {
        let (_, g, _) = self.scalar(x);
        [g, g]
    }

    /// ρf = −div σ(s) = −(μΔs + (μ + 2λ)∇ div s) at x.
    pub fn volume_load(&self, mu: f64, lambda: f64, x: [f64; 2]) -> [f64; 2] {
        let (_, _, h) = self.scalar(x);
        let laplace = h[0][0] + h[1][1];
        // div s = ∂₁w + ∂₂w, so ∂_i div s = ∂_i1 w + ∂_i2 w
        let grad_div = [h[0][0] + h[0][1], h[1][0] + h[1][1]];
        [0, 1].map(|i| -(mu * laplace + (mu + 2.0 * lambda) * grad_div[i]))
    }

    /// The volume load of this field for the Lamé constants μ, λ, as the model's load.
    pub fn load(self, mu: f64, lambda: f64) -> VolumeForce {
        VolumeForce::Field(Arc::new(move |x| self.volume_load(mu, lambda, x)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The derivatives agree with central differences of the values (a wrong sign or factor in
    /// p′ or p″ would change the load and with it every error).
    #[test]
    fn derivatives_match_differences() {
        let s = ExactDisplacement::of(ExactSolution::ArctanCross);
        let h = 1e-5;
        for x in [[0.3, 0.45], [0.52, 0.7], [0.1, 0.9]] {
            let g = s.gradient(x);
            let (_, _, hess) = s.scalar(x);
            for j in 0..2 {
                let mut xp = x;
                let mut xm = x;
                xp[j] += h;
                xm[j] -= h;
                let fd = (s.value(xp)[0] - s.value(xm)[0]) / (2.0 * h);
                assert!(
                    (fd - g[0][j]).abs() < 1e-6 * (1.0 + fd.abs()),
                    "∂{j}w at {x:?}"
                );
                let (_, gp, _) = s.scalar(xp);
                let (_, gm, _) = s.scalar(xm);
                for i in 0..2 {
                    let fd2 = (gp[i] - gm[i]) / (2.0 * h);
                    assert!(
                        (fd2 - hess[i][j]).abs() < 1e-5 * (1.0 + fd2.abs()),
                        "∂{i}{j}w at {x:?}: {fd2} vs {}",
                        hess[i][j]
                    );
                }
            }
        }
        // zero on the boundary
        for t in [0.0, 0.3, 1.0] {
            for x in [[t, 0.0], [t, 1.0], [0.0, t], [1.0, t]] {
                assert_eq!(s.value(x), [0.0, 0.0]);
            }
        }
    }
}
