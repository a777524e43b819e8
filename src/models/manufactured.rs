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
//!
//! # The Reynolds solution with cavitation `cavitation-bubble`
//!
//! On the unit square, with B(x) = 16x₁(1 − x₁)x₂(1 − x₂) (B = 0 on ∂Ω, B = 1 at the centre),
//! β = [`ZONE_LEVEL`], K = √ψ₀/β and the level function F = √ψ₀ − K·B,
//!
//! ψ = (F₊)²,
//!
//! so ψ = ψ₀ on ∂Ω₂ exactly (B = 0 there; not taken exactly by Q₁ inside, but the Dirichlet
//! values are only the boundary vertices' ψ₀), ψ > 0 where B < β, and ψ = 0 on the known
//! cavitation zone Ω₀ = {B ≥ β}, a rounded square about the centre (for β = ¾ it reaches
//! x₁ ∈ [¼, ¾] on x₂ = ½). ψ is C¹ across the free boundary {B = β} (ψ ~ F² ~ dist² there,
//! ∇B ≠ 0 on it), its second derivatives jump there: the regularity of an obstacle problem's
//! solution. The cavitation model (I.82)/(III.61) is the LCP ψ ≥ 0, Aψ − l ≥ 0,
//! ψ·(Aψ − l) = 0 with Aψ = −Δψ + ψΔg/g in strong form; its data here are
//!
//! * where ψ > 0: l = −Δψ + ψΔg/g, Δψ = 2|∇F|² + 2FΔF (the equation holds);
//! * in Ω₀: ψ = 0, so Aψ − l = −l must be ≥ 0: l = −2|∇F|² + 2FΔF, which is < 0 strictly
//!   inside (F < 0, ΔF = −KΔB = 32K(x₁(1 − x₁) + x₂(1 − x₂)) > 0) and equals the outer load
//!   −2|∇F|² on the free boundary, so l is continuous and the multiplier Aψ − l = −l > 0
//!   vanishes only on the free boundary.
//!
//! As for `arctan-cross` l is evaluated at the points where the model evaluates its load, so the
//! assembly and the estimator of Theorem III.17 see the same l. ψ₀ (the scene's
//! `boundary_pressure`) must be positive.

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

/// w, its gradient and its Hessian at x (zero for the fields that are not built on w).
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
        _ => (0.0, [0.0; 2], [[0.0; 2]; 2]),
    }
}

/// β of `cavitation-bubble`: the cavitation zone is {B > β}, B = 16x₁(1 − x₁)x₂(1 − x₂).
pub const ZONE_LEVEL: f64 = 0.75;

/// The level function of `cavitation-bubble`, F = √ψ₀ − K·B with K = √ψ₀/β, its gradient and
/// its Hessian at x.
fn bubble(base: f64, x: [f64; 2]) -> (f64, [f64; 2], [[f64; 2]; 2]) {
    let root = base.max(0.0).sqrt();
    let k = root / ZONE_LEVEL;
    let (a, b) = (x[0] * (1.0 - x[0]), x[1] * (1.0 - x[1]));
    let (da, db) = (1.0 - 2.0 * x[0], 1.0 - 2.0 * x[1]);
    let big_b = 16.0 * a * b;
    let grad = [16.0 * da * b, 16.0 * a * db];
    let hess = [[-32.0 * b, 16.0 * da * db], [16.0 * da * db, -32.0 * a]];
    (
        root - k * big_b,
        grad.map(|g| -k * g),
        hess.map(|row| row.map(|h| -k * h)),
    )
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
        match self.name {
            ExactSolution::CavitationBubble => {
                let (f, _, _) = bubble(self.base, x);
                f.max(0.0).powi(2)
            }
            _ => self.base + PRESSURE_AMPLITUDE * scalar(self.name, x).0,
        }
    }

    /// ∇ψ(x).
    pub fn gradient(&self, x: [f64; 2]) -> [f64; 2] {
        match self.name {
            ExactSolution::CavitationBubble => {
                let (f, df, _) = bubble(self.base, x);
                df.map(|d| 2.0 * f.max(0.0) * d)
            }
            _ => scalar(self.name, x).1.map(|d| PRESSURE_AMPLITUDE * d),
        }
    }

    /// Whether x lies in the cavitation zone {ψ = 0} of the exact pressure (`cavitation-bubble`;
    /// the other fields have none).
    pub fn cavitated(&self, x: [f64; 2]) -> bool {
        match self.name {
            ExactSolution::CavitationBubble => bubble(self.base, x).0 <= 0.0,
            _ => false,
        }
    }

    /// The load l at x for the gap of `film`: l = −Δψ + ψΔg/g where ψ > 0; in the cavitation
    /// zone of `cavitation-bubble` the load −2|∇F|² + 2FΔF < 0 (module docs).
    pub fn load(&self, film: &ThinFilm, x: [f64; 2]) -> f64 {
        let (g, _, laplace_g) = film.gap(x);
        let minus_laplace = match self.name {
            ExactSolution::CavitationBubble => {
                let (f, df, h) = bubble(self.base, x);
                let (grad2, lap_f) = (df[0] * df[0] + df[1] * df[1], h[0][0] + h[1][1]);
                if f > 0.0 {
                    // Δψ = Δ(F²) = 2|∇F|² + 2FΔF
                    -2.0 * grad2 - 2.0 * f * lap_f
                } else {
                    -2.0 * grad2 + 2.0 * f * lap_f
                }
            }
            _ => {
                let (_, _, h) = scalar(self.name, x);
                -PRESSURE_AMPLITUDE * (h[0][0] + h[1][1])
            }
        };
        minus_laplace + self.value(x) * laplace_g / g
    }
}

/// A closed-form displacement field s of linear elasticity (I.17) on its domain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExactDisplacement {
    pub name: ExactSolution,
}

/// Value, gradient (rows = components) and Hessians (per component) of a displacement.
type Jet = ([f64; 2], [[f64; 2]; 2], [[[f64; 2]; 2]; 2]);

impl ExactDisplacement {
    /// The field named in an experiment file.
    pub fn of(name: ExactSolution) -> ExactDisplacement {
        ExactDisplacement { name }
    }

    /// s, ∇s and the Hessian of each component at x.
    fn jet(&self, x: [f64; 2]) -> Jet {
        match self.name {
            ExactSolution::ArctanCross => {
                let (w, g, h) = scalar(self.name, x);
                ([w, w], [g, g], [h, h])
            }
            ExactSolution::ContactStrip => ContactStrip::FLAT.jet(x),
            ExactSolution::ContactStripTilted => ContactStrip::TILTED.jet(x),
            // Not a displacement: the loader refuses it in an elasticity scene.
            ExactSolution::CavitationBubble => ([0.0; 2], [[0.0; 2]; 2], [[[0.0; 2]; 2]; 2]),
        }
    }

    /// The contact data of a `contact-strip` field, `None` for the other fields.
    pub fn strip(&self) -> Option<ContactStrip> {
        match self.name {
            ExactSolution::ContactStrip => Some(ContactStrip::FLAT),
            ExactSolution::ContactStripTilted => Some(ContactStrip::TILTED),
            _ => None,
        }
    }

    /// s(x).
    pub fn value(&self, x: [f64; 2]) -> [f64; 2] {
        self.jet(x).0
    }

    /// ∇s(x), rows = components (the layout of [`super::elasticity::Elasticity::stress`]).
    pub fn gradient(&self, x: [f64; 2]) -> [[f64; 2]; 2] {
        self.jet(x).1
    }

    /// ρf = −div σ(s) = −(μΔs + (μ + 2λ)∇ div s) at x.
    pub fn volume_load(&self, mu: f64, lambda: f64, x: [f64; 2]) -> [f64; 2] {
        let (_, _, h) = self.jet(x);
        // div s = ∂₁s₁ + ∂₂s₂, so ∂_i div s = ∂_i1 s₁ + ∂_i2 s₂
        let grad_div = [h[0][0][0] + h[1][0][1], h[0][1][0] + h[1][1][1]];
        [0, 1].map(|i| {
            let laplace = h[i][0][0] + h[i][1][1];
            -(mu * laplace + (mu + 2.0 * lambda) * grad_div[i])
        })
    }

    /// The volume load of this field for the Lamé constants μ, λ, as the model's load.
    pub fn load(self, mu: f64, lambda: f64) -> VolumeForce {
        VolumeForce::Field(Arc::new(move |x| self.volume_load(mu, lambda, x)))
    }

    /// The surface load t on the contact side x₂ = 0 of a `contact-strip` field at x = (x₁, 0),
    /// t = σ(s)n₀ + p ν ([`ContactStrip`]); zero for the other fields.
    pub fn contact_traction(&self, mu: f64, lambda: f64, x: [f64; 2]) -> [f64; 2] {
        let Some(strip) = self.strip() else {
            return [0.0; 2];
        };
        let g = self.gradient(x);
        let div = g[0][0] + g[1][1];
        let off = mu * (g[0][1] + g[1][0]);
        // σ(s)n₀ with n₀ = −e₂: −(σ₁₂, σ₂₂), σ = 2με + 2λ(div s)I as in (I.17)
        let sigma_n = [-off, -(2.0 * mu * g[1][1] + 2.0 * lambda * div)];
        let p = strip.pressure(x[0]);
        let nu = strip.contact_normal();
        [sigma_n[0] + p * nu[0], sigma_n[1] + p * nu[1]]
    }
}

/// The fields `contact-strip` and `contact-strip-tilted`: an elastic body on the unit square,
/// clamped on the left, right and top sides (Γ₀), pressed against a straight rigid obstacle
/// below its bottom side Γ_C = {x₂ = 0}, in contact on the known interval
/// I = [a_L, a_R] × {0} = [0.3, 0.7] × {0} and separated from the obstacle elsewhere.
///
/// # The field
///
/// With m(x₂) = (1 − x₂)²(1 + 2x₂) (m(0) = 1, m′(0) = 0, m(1) = m′(1) = 0),
///
/// s(x) = (u(x₁), v(x₁)) · m(x₂),   u(x₁) = 4U x₁(1 − x₁),
/// v(x₁) = b₀ + k (x₁ + u(x₁)) + q(x₁),
/// q(x₁) = c_L (a_L − x₁)₊³ + c_R (x₁ − a_R)₊³,
///
/// for the obstacle line b(ξ) = b₀ + kξ. c_L = −b₀/a_L³ and c_R = −(b₀ + k)/(1 − a_R)³ make
/// v(0) = v(1) = 0, so s = 0 on the three clamped sides exactly (u(0) = u(1) = 0, m(1) = 0);
/// the clamped corners need b₀ < 0 and b₀ + k < 0 (the obstacle below them). s is C² (q has
/// a jump of its third derivative at a_L and a_R), in H³ locally, enough for the optimal rate
/// of Q₁.
///
/// # The contact conditions
///
/// On Γ_C (m = 1) the deformed point is (x₁ + u, v); the signed gap to the obstacle, measured
/// vertically at the deformed abscissa, is v − b(x₁ + u) = q(x₁): zero on I, positive outside
/// (q > 0 off I). That is the **Signorini** condition (I.21) — the deformed boundary does not
/// enter the obstacle, and at a point in contact the boundary lies on the obstacle line, so its
/// normal is the obstacle's ν = (k, −1)/√(1 + k²) and (III.13)'s gap along it vanishes.
/// The **z-condition** (I.20) compares s₂ with the obstacle at the *undeformed* abscissa,
/// s₂ ≥ b(x₁): v − b(x₁) = k u + q. The two differ by k·u where the face slides (u ≠ 0);
/// with a flat obstacle (k = 0) they coincide exactly — for the nonlinear conditions and for
/// the discrete ones at the vertices (the converged Signorini constraint at a vertex asks
/// x₂ + s₂ ≥ b₀ there, the z-constraint the same) — so a flat obstacle cannot test the
/// Signorini model. Hence two fields:
///
/// * `contact-strip` ([`ContactStrip::FLAT`]): k = 0, b₀ = −0.05: the z-contact scene (and a
///   Signorini scene on it would solve the same problem);
/// * `contact-strip-tilted` ([`ContactStrip::TILTED`]): k = 0.05, b₀ = −0.1, U = 0.1: the
///   Signorini scene; on I its s₂ = b(x₁) + k u exceeds the obstacle at the undeformed abscissa
///   by k·u ≈ 5·10⁻³ at the centre, so the z-solution of the same data is a different field.
///
/// The contact pressure is p(x₁) = P ((x₁ − a_L)(a_R − x₁))₊², P = [`ContactStrip::PRESSURE`]:
/// p > 0 inside I, p = 0 outside, and p ~ dist² at the ends of I (C¹), so nothing singular
/// sits at the free boundary. Frictionless contact with a surface load t on Γ_C: stationarity of
/// J(s) − ∫_{Γ_C} t·s under the constraint gives σ(s)n₀ − t = −p ν on Γ_C (n₀ = −e₂ the outer
/// normal of the undeformed body; ν the direction of the constraint: n_z = −e₂ for z, the
/// obstacle normal for Signorini; the discrete multiplier λ_i = (F − Ku)·n_i ≥ 0 of
/// [`crate::models::contact::solve_contact`] is p's nodal value). So the data on Γ_C are
///
/// t = σ(s)n₀ + p ν,
///
/// evaluated at x₂ = 0 where ∂₂s = u, v times m′(0) = 0: σ(s)n₀ = −(μv′, 2λu′). Then the shear
/// of σ(s)n₀ − t along the obstacle is zero (frictionless), its normal part −p ≤ 0
/// (compressive) on I and 0 outside, and p·gap = 0: the complementarity conditions hold
/// exactly. The volume load is ρf = −div σ(s) as for `arctan-cross`.
///
/// Why m′(0) = 0: the contact estimator's η_{C,Q} = ‖∇(n·s_h)‖ on the contact faces
/// ([`crate::estimators::contact`]) then measures only discretisation error on I for the
/// flat field (∇(n·s) = −∇s₂ = 0 there); on the tilted one n·s = −(b₀ + kx₁)/√(1 + k²) on I,
/// whose tangential derivative −k/√(1 + k²) the term keeps (an O(h_Q) term of the estimate that
/// is not error, small for k = 0.05).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactStrip {
    /// b₀, the obstacle's height at x₁ = 0.
    pub offset: f64,
    /// k, the obstacle's slope.
    pub slope: f64,
    /// U, the amplitude of the tangential displacement u.
    pub slide: f64,
}

impl ContactStrip {
    /// The active interval [a_L, a_R] on the contact side.
    pub const ACTIVE: [f64; 2] = [0.3, 0.7];
    /// P of the contact pressure p = P((x₁ − a_L)(a_R − x₁))₊² (peak P·0.04² = 0.48).
    pub const PRESSURE: f64 = 300.0;
    /// The flat obstacle b = −0.05 of `contact-strip`.
    pub const FLAT: ContactStrip = ContactStrip {
        offset: -0.05,
        slope: 0.0,
        slide: 0.1,
    };
    /// The tilted obstacle b = −0.1 + 0.05 ξ of `contact-strip-tilted`.
    pub const TILTED: ContactStrip = ContactStrip {
        offset: -0.1,
        slope: 0.05,
        slide: 0.1,
    };

    /// The outer unit normal of the obstacle line (the body is above it), ν = (k, −1)/√(1 + k²).
    pub fn contact_normal(&self) -> [f64; 2] {
        let r = self.slope.hypot(1.0);
        [self.slope / r, -1.0 / r]
    }

    /// The contact pressure p(x₁) ≥ 0.
    pub fn pressure(&self, x1: f64) -> f64 {
        let [a, b] = Self::ACTIVE;
        let d = ((x1 - a) * (b - x1)).max(0.0);
        Self::PRESSURE * d * d
    }

    /// Whether x₁ lies in the active interval I.
    pub fn in_contact(&self, x1: f64) -> bool {
        (Self::ACTIVE[0]..=Self::ACTIVE[1]).contains(&x1)
    }

    /// The obstacle b(ξ) = b₀ + kξ.
    pub fn obstacle(&self, xi: f64) -> f64 {
        self.offset + self.slope * xi
    }

    /// u, v of the contact side and their first two derivatives.
    fn profiles(&self, t: f64) -> ([f64; 3], [f64; 3]) {
        let [a, b] = Self::ACTIVE;
        let u = [
            4.0 * self.slide * t * (1.0 - t),
            4.0 * self.slide * (1.0 - 2.0 * t),
            -8.0 * self.slide,
        ];
        let cl = -self.offset / a.powi(3);
        let cr = -(self.offset + self.slope) / (1.0 - b).powi(3);
        let (l, r) = ((a - t).max(0.0), (t - b).max(0.0));
        let q = [
            cl * l.powi(3) + cr * r.powi(3),
            -3.0 * cl * l * l + 3.0 * cr * r * r,
            6.0 * cl * l + 6.0 * cr * r,
        ];
        let k = self.slope;
        let v = [
            self.offset + k * (t + u[0]) + q[0],
            k * (1.0 + u[1]) + q[1],
            k * u[2] + q[2],
        ];
        (u, v)
    }

    /// s, ∇s and the Hessians of s at x.
    fn jet(&self, x: [f64; 2]) -> Jet {
        let (u, v) = self.profiles(x[0]);
        let y = x[1];
        let m = [
            (1.0 - y).powi(2) * (1.0 + 2.0 * y),
            -6.0 * y * (1.0 - y),
            -6.0 + 12.0 * y,
        ];
        let component = |a: [f64; 3]| {
            (
                a[0] * m[0],
                [a[1] * m[0], a[0] * m[1]],
                [[a[2] * m[0], a[1] * m[1]], [a[1] * m[1], a[0] * m[2]]],
            )
        };
        let (s1, g1, h1) = component(u);
        let (s2, g2, h2) = component(v);
        ([s1, s2], [g1, g2], [h1, h2])
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
            let (_, _, hess) = scalar(s.name, x);
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
                let (_, gp, _) = scalar(s.name, xp);
                let (_, gm, _) = scalar(s.name, xm);
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

    /// Central differences of a field's values and gradients against its gradient and
    /// Hessians, at points on both sides of the kinks of q (a_L, a_R) and of the free boundary.
    fn check_jet(jet: impl Fn([f64; 2]) -> Jet, points: &[[f64; 2]], what: &str) {
        let h = 1e-6;
        for &x in points {
            let (_, g, hess) = jet(x);
            for j in 0..2 {
                let (mut xp, mut xm) = (x, x);
                xp[j] += h;
                xm[j] -= h;
                let (vp, gp, _) = jet(xp);
                let (vm, gm, _) = jet(xm);
                for c in 0..2 {
                    let fd = (vp[c] - vm[c]) / (2.0 * h);
                    assert!(
                        (fd - g[c][j]).abs() < 1e-6 * (1.0 + fd.abs()),
                        "{what}: ∂{j}s{c} at {x:?}: {fd} vs {}",
                        g[c][j]
                    );
                    for i in 0..2 {
                        let fd2 = (gp[c][i] - gm[c][i]) / (2.0 * h);
                        assert!(
                            (fd2 - hess[c][i][j]).abs() < 1e-5 * (1.0 + fd2.abs()),
                            "{what}: ∂{i}{j}s{c} at {x:?}: {fd2} vs {}",
                            hess[c][i][j]
                        );
                    }
                }
            }
        }
    }

    /// The contact fields: derivatives against central differences; s = 0 on the clamped
    /// sides; on the contact side the Signorini gap s₂ − b(x₁ + s₁) is 0 on [a_L, a_R] and
    /// positive outside, the z-gap s₂ − b(x₁) equals it for the flat field and exceeds it by
    /// k·s₁ for the tilted one; the pressure is ≥ 0, positive exactly inside the interval.
    #[test]
    fn contact_strip_derivatives_and_complementarity() {
        let points = [
            [0.1, 0.2],
            [0.29, 0.0],
            [0.31, 0.5],
            [0.5, 0.05],
            [0.69, 0.9],
            [0.8, 0.3],
        ];
        for name in [
            ExactSolution::ContactStrip,
            ExactSolution::ContactStripTilted,
        ] {
            let s = ExactDisplacement::of(name);
            let strip = s.strip().expect("a contact field");
            check_jet(|x| s.jet(x), &points, name.name());
            for t in [0.0, 0.3, 0.77, 1.0] {
                for x in [[0.0, t], [1.0, t], [t, 1.0]] {
                    let v = s.value(x);
                    assert!(v[0].abs() < 1e-15 && v[1].abs() < 1e-15, "{x:?}: {v:?}");
                }
            }
            for i in 1..100 {
                let x1 = i as f64 / 100.0;
                let v = s.value([x1, 0.0]);
                let gap = v[1] - strip.obstacle(x1 + v[0]);
                let z_gap = v[1] - strip.obstacle(x1);
                assert!((z_gap - gap - strip.slope * v[0]).abs() < 1e-14);
                if strip.in_contact(x1) {
                    assert!(gap.abs() < 1e-15, "{x1}: gap {gap}");
                    assert!(strip.pressure(x1) > 0.0 || x1 == 0.3 || x1 == 0.7);
                } else {
                    assert!(gap > 0.0, "{x1}: gap {gap}");
                    assert_eq!(strip.pressure(x1), 0.0);
                }
            }
        }
    }

    /// `cavitation-bubble`: ∇ψ and Δψ (through the load on a gap with Δg = 0) against central
    /// differences off the free boundary; ψ = ψ₀ on ∂Ω; the load is negative in the zone and
    /// continuous across the free boundary.
    #[test]
    fn cavitation_bubble_derivatives_and_complementarity() {
        use crate::models::thin_film::{Gap, ThinFilm};
        let psi = ExactPressure {
            name: ExactSolution::CavitationBubble,
            base: 200.0,
        };
        let film = ThinFilm::new(
            Gap::Linear {
                g0: 0.1,
                slope: 0.05,
            },
            [0.0; 3],
        );
        let h = 1e-5;
        for x in [
            [0.1, 0.2],
            [0.2, 0.5],
            [0.5, 0.1],
            [0.85, 0.7],
            [0.5, 0.5],
            [0.4, 0.45],
        ] {
            let g = psi.gradient(x);
            let mut lap = 0.0;
            for j in 0..2 {
                let (mut xp, mut xm) = (x, x);
                xp[j] += h;
                xm[j] -= h;
                let fd = (psi.value(xp) - psi.value(xm)) / (2.0 * h);
                assert!(
                    (fd - g[j]).abs() < 1e-5 * (1.0 + fd.abs()),
                    "∂{j}ψ at {x:?}"
                );
                lap += (psi.gradient(xp)[j] - psi.gradient(xm)[j]) / (2.0 * h);
            }
            if psi.cavitated(x) {
                assert_eq!(psi.value(x), 0.0);
                assert!(psi.load(&film, x) < 0.0, "load at {x:?}");
            } else {
                let l = psi.load(&film, x);
                assert!(
                    (l + lap).abs() < 1e-4 * (1.0 + l.abs()),
                    "−Δψ at {x:?}: {l} vs {}",
                    -lap
                );
            }
        }
        for t in [0.0, 0.3, 1.0] {
            for x in [[t, 0.0], [t, 1.0], [0.0, t], [1.0, t]] {
                assert!((psi.value(x) - 200.0).abs() < 1e-12);
            }
        }
        // On x₂ = ½ the zone is x₁ ∈ [¼, ¾]: the load on both sides of x₁ = ¼ agrees.
        let (a, b) = (
            psi.load(&film, [0.25 - 1e-9, 0.5]),
            psi.load(&film, [0.25 + 1e-9, 0.5]),
        );
        assert!(psi.cavitated([0.25 + 1e-9, 0.5]) && !psi.cavitated([0.25 - 1e-9, 0.5]));
        assert!((a - b).abs() < 1e-5 * a.abs() && a < 0.0, "{a} vs {b}");
    }
}
