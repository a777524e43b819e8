//! A manufactured solution of the SubStokes problem (I.58) = (II.32): a closed-form flow rate
//! χ and pressure ψ on the unit square, with the data of the model derived from them, so that
//! the true error of a SubStokes run can be measured against the estimate of Theorem III.23
//! ([`crate::estimators::true_error::substokes_norm`]).
//!
//! # The fields (`exact = "arctan-cross"` in a SubStokes scene)
//!
//! The flow rate is the curl of a stream function, so it is exactly divergence-free:
//!
//! φ = B q(x₁) q(x₂),  q(t) = t³(1 − t)³,  χ = (∂₂φ, −∂₁φ) = B (q(x₁)q′(x₂), −q′(x₁)q(x₂)),
//!
//! with B = [`FLOW_AMPLITUDE`]. The pressure is the Reynolds one of
//! [`crate::models::manufactured`]: ψ = ψ₀ + A·w, w = p(x₁)p(x₂), p(t) = t(1 − t)atan(25(t − ½)),
//! A = [`crate::models::manufactured::PRESSURE_AMPLITUDE`]: smooth, with the arctan front along
//! x₁ = ½ and x₂ = ½ that the adaptive marking has to find, ψ = ψ₀ on ∂Ω₂ exactly (the
//! Dirichlet data (I.55), taken exactly by Q₁) and ψ ≥ ψ₀ − 139 > 0 for ψ₀ = 200, so no
//! cavitation.
//!
//! **Boundary conditions.** The discrete problem (module docs of [`super::substokes`]) has no
//! Dirichlet condition on χ: the weak form (I.58) with X₀ = 0 imposes the natural condition
//! ψn − ∂_nχ = ψ₀n on ∂Ω₂ (integrate a₂ and b₂ by parts: ⟨∇χ, ∇ξ⟩ = −⟨Δχ, ξ⟩ + ⟨∂_nχ, ξ⟩_∂,
//! −b₂(ξ, ψ) = ⟨∇ψ − ψ∇g/g, ξ⟩ − ⟨ψ n, ξ⟩_∂). With ψ = ψ₀ there, the field must have ∂_nχ = 0 on
//! ∂Ω₂. q has q(0) = q′(0) = q″(0) = 0 (and the same at 1), so on x₁ ∈ {0, 1}
//! ∂₁χ = B(q′(x₁)q′(x₂), −q″(x₁)q(x₂)) = 0, and on x₂ ∈ {0, 1} ∂₂χ = B(q(x₁)q″(x₂), −q′(x₁)q′(x₂))
//! = 0: the boundary term of the load and the boundary jump of the estimator are those of the
//! thesis's examples (ψ₀n, X₀ = 0), unchanged.
//!
//! **Data.** The strong form of (I.58) is
//!
//! −Δχ + 12χ/g² + ∇ψ − ψ∇g/g = κ + γ,   (1/g)div(gχ) = div χ + χ·∇g/g = σ₃,
//!
//! so the momentum source (in place of κ + γ) and the mass source (in place of σ₃) are
//!
//! f = −Δχ + 12χ/g² + ∇ψ − ψ∇g/g,  s = χ·∇g/g  (div χ = 0),
//!
//! for the scene's gap g, evaluated wherever the model and the estimator evaluate κ + γ and σ₃
//! (the 2×2 Gauss points of the assembly, the 3×3 of the estimator's residuals), so both see
//! the same data and no data oscillation arises. Δχ needs third derivatives of φ:
//! Δχ₁ = B(q″(x₁)q′(x₂) + q(x₁)q‴(x₂)), Δχ₂ = −B(q‴(x₁)q(x₂) + q′(x₁)q″(x₂)).
//!
//! The cavitation form (I.66) adds −∇(div χ) to the momentum operator, 0 for this χ: the same
//! data serve it, and with ψ > 0 the constraint ψ ≥ 0 is inactive.

use crate::experiment::ExactSolution;
use crate::models::manufactured::ExactPressure;
use crate::models::thin_film::ThinFilm;

/// B of the stream function: max|χ| ≈ 7.6 (q(½)·max|q′| ≈ 1/64 · 0.049 · B). With B = 1000 the
/// L² error of the pressure (amplitude 139) dominated the norm and, super-convergent on the
/// coarse meshes, gave an order of −0.63 over cycles 4–9; with B = 10⁴ the H¹ error of χ
/// carries the norm and the order is −0.45 (measured, quick tier).
pub const FLOW_AMPLITUDE: f64 = 10000.0;

/// q(t) = t³(1 − t)³ and its first three derivatives.
fn bump(t: f64) -> [f64; 4] {
    let s = t * (1.0 - t); // s′ = 1 − 2t, s″ = −2
    let ds = 1.0 - 2.0 * t;
    // q = s³, q′ = 3s²s′, q″ = 6s s′² + 3s²s″, q‴ = 6s′³ + 18 s s′ s″ (s‴ = 0)
    [
        s * s * s,
        3.0 * s * s * ds,
        6.0 * s * ds * ds - 6.0 * s * s,
        6.0 * ds * ds * ds - 36.0 * s * ds,
    ]
}

/// The closed-form SubStokes solution (χ, ψ) on the unit square (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExactFlow {
    /// ψ = ψ₀ + A·w.
    pub pressure: ExactPressure,
}

impl ExactFlow {
    /// The field named in an experiment file, with the boundary pressure ψ₀.
    pub fn of(name: ExactSolution, boundary_pressure: f64) -> ExactFlow {
        ExactFlow {
            pressure: ExactPressure {
                name,
                base: boundary_pressure,
            },
        }
    }

    /// χ(x).
    pub fn chi(&self, x: [f64; 2]) -> [f64; 2] {
        let (a, b) = (bump(x[0]), bump(x[1]));
        [FLOW_AMPLITUDE * a[0] * b[1], -FLOW_AMPLITUDE * a[1] * b[0]]
    }

    /// ∇χ(x), rows = components: [∂₁χ_μ, ∂₂χ_μ] for μ = 1, 2.
    pub fn chi_gradient(&self, x: [f64; 2]) -> [[f64; 2]; 2] {
        let (a, b) = (bump(x[0]), bump(x[1]));
        let k = FLOW_AMPLITUDE;
        [
            [k * a[1] * b[1], k * a[0] * b[2]],
            [-k * a[2] * b[0], -k * a[1] * b[1]],
        ]
    }

    /// Δχ(x).
    pub fn chi_laplacian(&self, x: [f64; 2]) -> [f64; 2] {
        let (a, b) = (bump(x[0]), bump(x[1]));
        let k = FLOW_AMPLITUDE;
        [
            k * (a[2] * b[1] + a[0] * b[3]),
            -k * (a[3] * b[0] + a[1] * b[2]),
        ]
    }

    /// ψ(x).
    pub fn psi(&self, x: [f64; 2]) -> f64 {
        self.pressure.value(x)
    }

    /// ∇ψ(x).
    pub fn psi_gradient(&self, x: [f64; 2]) -> [f64; 2] {
        self.pressure.gradient(x)
    }

    /// The momentum source f = −Δχ + 12χ/g² + ∇ψ − ψ∇g/g and the mass source s = χ·∇g/g at x
    /// for the gap of `film` (module docs): what the model and the estimator use in place of
    /// κ + γ and σ₃.
    pub fn sources(&self, film: &ThinFilm, x: [f64; 2]) -> ([f64; 2], f64) {
        let (g, dg, _) = film.gap(x);
        let chi = self.chi(x);
        let lap = self.chi_laplacian(x);
        let psi = self.psi(x);
        let dpsi = self.psi_gradient(x);
        let f = [0, 1].map(|mu| -lap[mu] + 12.0 * chi[mu] / (g * g) + dpsi[mu] - psi * dg[mu] / g);
        let s = (chi[0] * dg[0] + chi[1] * dg[1]) / g;
        (f, s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::thin_film::Gap;

    fn flow() -> ExactFlow {
        ExactFlow::of(ExactSolution::ArctanCross, 200.0)
    }

    /// The derivatives agree with central differences of the values; χ is divergence-free,
    /// ∂_nχ = 0 and ψ = ψ₀ on the boundary.
    #[test]
    fn derivatives_match_differences() {
        let e = flow();
        let h = 1e-5;
        for x in [[0.3, 0.45], [0.52, 0.7], [0.1, 0.9], [0.8, 0.2]] {
            let g = e.chi_gradient(x);
            let lap = e.chi_laplacian(x);
            let mut fd_lap = [0.0; 2];
            for j in 0..2 {
                let (mut xp, mut xm) = (x, x);
                xp[j] += h;
                xm[j] -= h;
                let (cp, cm) = (e.chi(xp), e.chi(xm));
                let (gp, gm) = (e.chi_gradient(xp), e.chi_gradient(xm));
                for mu in 0..2 {
                    let fd = (cp[mu] - cm[mu]) / (2.0 * h);
                    assert!(
                        (fd - g[mu][j]).abs() < 1e-6 * (1.0 + fd.abs()),
                        "∂{j}χ{mu} at {x:?}: {fd} vs {}",
                        g[mu][j]
                    );
                    fd_lap[mu] += (gp[mu][j] - gm[mu][j]) / (2.0 * h);
                }
                let fd = (e.psi(xp) - e.psi(xm)) / (2.0 * h);
                let dpsi = e.psi_gradient(x)[j];
                assert!(
                    (fd - dpsi).abs() < 1e-5 * (1.0 + fd.abs()),
                    "∂{j}ψ at {x:?}"
                );
            }
            for mu in 0..2 {
                assert!(
                    (fd_lap[mu] - lap[mu]).abs() < 1e-5 * (1.0 + lap[mu].abs()),
                    "Δχ{mu} at {x:?}: {} vs {}",
                    fd_lap[mu],
                    lap[mu]
                );
            }
            assert!((g[0][0] + g[1][1]).abs() < 1e-12, "div χ at {x:?}");
        }
        for t in [0.0, 0.3, 0.77, 1.0] {
            for x in [[t, 0.0], [t, 1.0], [0.0, t], [1.0, t]] {
                let n = if x[0] == 0.0 || x[0] == 1.0 { 0 } else { 1 };
                let g = e.chi_gradient(x);
                assert_eq!([g[0][n], g[1][n]], [0.0, 0.0], "∂_nχ at {x:?}");
                assert_eq!(e.psi(x), 200.0);
            }
        }
        // The sources: the mass source is χ·∇g/g, zero on a plain gap.
        let plain = ThinFilm::new(Gap::Plain { g0: 0.1 }, [0.0; 3]);
        let (_, s) = e.sources(&plain, [0.3, 0.6]);
        assert_eq!(s, 0.0);
    }
}
