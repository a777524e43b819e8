//! Data of the thin-film (Reynolds / SubStokes) examples (IV.7)–(IV.20) of Gimbel (2012), §IV.3.
//!
//! The module is self-contained (std only, and θ_s of [`crate::models::obstacle`] for the step
//! gap). It provides
//!
//! * [`Jet`]: a forward-mode 2-D Taylor jet up to third order (value, gradient, Hessian and third
//!   derivative tensor). Derivatives lower the order that is known; the unknown orders are marked
//!   with `NaN`, so any formula that needs more derivatives than its inputs carry yields `NaN`
//!   instead of a silently wrong number.
//! * [`Gap`]: the gap functions g(x₁, x₂) of the examples and of scenes of the user's own, with
//!   analytic derivatives up to third order; [`CubicSpline`] the natural spline of a tabulated
//!   gap.
//! * [`FilmJets`]: the general Chapter I source terms (I.47), (I.50), (I.52), (I.61), (I.65),
//!   (I.77), (I.81) evaluated from arbitrary wall data z₀, z₁, v(z₀), v(z₁), κ given as jets.
//! * [`ThinFilm`]: one example (gap, constant upper-wall velocity, lower wall z₀ = 0 at rest,
//!   κ = 0, η = ρ = 1), with per-point evaluation of those terms and of the Reynolds loads
//!   l_R (II.37) and l_{R,c} (II.39).
//! * [`example`]: the table of the fourteen examples of §IV.3.
//!
//! [`Jet`], [`Gap`] and [`FilmJets`] have a module each (`jet`, `gap`, `film`); the examples are
//! here.
//!
//! Notation follows the thesis: `g` is the gap width, Greek indices μ, ν ∈ {1, 2} (0-based in the
//! code), Einstein summation, ∂ and Δ are 2-D tangential operators in (x₁, x₂).

// Index loops mirror the index notation of the thesis (sums over μ, ν); keep them.
#![allow(clippy::needless_range_loop)]

mod film;
mod gap;
mod jet;
mod spline;
#[cfg(test)]
mod tests;

pub use film::{CavitationSource, FilmJets};
pub use gap::Gap;
pub use jet::Jet;
pub use spline::CubicSpline;

/// One fluid example of §IV.3: Ω₂ = [0, 1]², lower wall z₀ = 0 at rest (v(z₀) = 0), upper wall
/// z₁ = g moving with the constant velocity `upper_wall_velocity` = δv = 2v̄, κ = 0, η = ρ = 1.
#[derive(Debug, Clone, PartialEq)]
pub struct ThinFilm {
    /// Gap width g = z₁.
    pub gap: Gap,
    /// Upper-wall velocity v(z₁) (constant).
    pub upper_wall_velocity: [f64; 3],
}

impl ThinFilm {
    /// A film with the given gap and upper-wall velocity.
    pub const fn new(gap: Gap, upper_wall_velocity: [f64; 3]) -> ThinFilm {
        ThinFilm {
            gap,
            upper_wall_velocity,
        }
    }

    /// Wall data at `x` as jets (z₀ = 0, z₁ = g, v(z₀) = 0, v(z₁) constant, κ = 0). Inlined, so
    /// that the formulas of [`FilmJets`] see the constant data as constants.
    #[inline(always)]
    pub fn film_jets(&self, x: [f64; 2]) -> FilmJets {
        FilmJets::from_walls(
            Jet::ZERO,
            self.gap.jet(x),
            [Jet::ZERO; 3],
            self.upper_wall_velocity.map(Jet::constant),
            [Jet::ZERO; 2],
        )
    }

    /// (g, ∇g, Δg) at `x`, for the Reynolds product (II.9) (∇φ − φ∇g/g)·(∇ψ − ψ∇g/g) and the
    /// estimator of Thm III.16, ρ_Q = ‖l_R − ψ_h Δg/g‖_Q.
    pub fn gap(&self, x: [f64; 2]) -> (f64, [f64; 2], f64) {
        let j = self.gap.jet(x);
        (j.v, j.d, j.dd[0][0] + j.dd[1][1])
    }

    /// (I.47): (γ₃)_μ at `x`.
    pub fn gamma3(&self, x: [f64; 2]) -> [f64; 2] {
        self.film_jets(x).gamma3().map(|j| j.v)
    }

    /// (I.52): γ_μ = (γ₃)_μ + (12/g) v̄_μ at `x`.
    pub fn gamma(&self, x: [f64; 2]) -> [f64; 2] {
        self.film_jets(x).gamma().map(|j| j.v)
    }

    /// (I.50): σ₃ at `x`.
    pub fn sigma3(&self, x: [f64; 2]) -> f64 {
        self.film_jets(x).sigma3().v
    }

    /// R₁ of (I.77) at `x`.
    pub fn r1(&self, x: [f64; 2]) -> f64 {
        self.film_jets(x).r1().v
    }

    /// R₃ of (I.77) at `x`.
    pub fn r3(&self, x: [f64; 2]) -> f64 {
        self.film_jets(x).r3().v
    }

    /// (I.61): (γ₃c)_μ at `x` (in the reading `source`).
    pub fn gamma3c(&self, x: [f64; 2], source: CavitationSource) -> [f64; 2] {
        self.film_jets(x).gamma3c(source).map(|j| j.v)
    }

    /// (I.65): γ_c = γ₃c + (12/g) v̄ at `x`.
    pub fn gamma_c(&self, x: [f64; 2], source: CavitationSource) -> [f64; 2] {
        self.film_jets(x).gamma_c(source).map(|j| j.v)
    }

    /// R₃c of (I.81) at `x`.
    pub fn r3c(&self, x: [f64; 2], source: CavitationSource) -> f64 {
        self.film_jets(x).r3c(source).v
    }

    /// Couette flux g v̄_μ at `x` (the Dirichlet value χ(P) of (I.56) without the g³ρ term).
    pub fn couette_flux(&self, x: [f64; 2]) -> [f64; 2] {
        let g = self.gap.value(x);
        [
            0.5 * g * self.upper_wall_velocity[0],
            0.5 * g * self.upper_wall_velocity[1],
        ]
    }

    /// Reynolds load l_R (II.37) at `x` (right-hand side of ⟨ψ, φ⟩_R = ⟨l_R, φ⟩).
    pub fn reynolds_load(&self, x: [f64; 2]) -> f64 {
        self.film_jets(x).reynolds_load().v
    }

    /// Reynolds-with-cavitation load l_{R,c} (II.39) at `x`.
    pub fn cavitation_load(&self, x: [f64; 2], source: CavitationSource) -> f64 {
        self.film_jets(x).cavitation_load(source).v
    }

    /// The squeeze part −12 δv₃/g² of both loads at `x` (the δv₃ term of (I.77) and (I.81);
    /// δv₃ = v₃(z₁) because the lower wall is at rest).
    pub fn squeeze_load(&self, x: [f64; 2]) -> f64 {
        self.squeeze_load_at_gap(self.gap.value(x))
    }

    /// [`ThinFilm::squeeze_load`] where the gap g is already known.
    pub fn squeeze_load_at_gap(&self, g: f64) -> f64 {
        -12.0 * self.upper_wall_velocity[2] / (g * g)
    }
}

/// Equation labels of the fluid examples, in thesis order.
pub const EXAMPLES: [&str; 14] = [
    "IV.7", "IV.8", "IV.9", "IV.10", "IV.11", "IV.12", "IV.13", "IV.14", "IV.15", "IV.16", "IV.17",
    "IV.18", "IV.19", "IV.20",
];

/// The fluid example with thesis equation label `equation` ("IV.7" … "IV.20"; surrounding
/// parentheses are accepted), per thesis §IV.3.
pub fn example(equation: &str) -> Option<ThinFilm> {
    let label = equation
        .trim()
        .trim_start_matches('(')
        .trim_end_matches(')');
    let plain = Gap::Plain { g0: 0.1 };
    let linear = Gap::Linear {
        g0: 0.1,
        slope: 0.05,
    };
    let wave = Gap::WaveHorizontal {
        g0: 0.1,
        amplitude: 0.07,
        frequency: 2.0,
    };
    let hill = Gap::Hill {
        g0: 0.1,
        amplitude: 0.07,
        frequency: 2.0,
    };
    let (gap, v) = match label {
        "IV.7" => (plain, [0.0, 0.0, -10.0]),
        "IV.8" => (plain, [0.0, 0.0, 10.0]),
        "IV.9" => (plain, [10.0, 0.0, 0.0]),
        "IV.10" => (linear, [0.0, 0.0, -10.0]),
        "IV.11" => (linear, [0.0, 0.0, 10.0]),
        "IV.12" => (linear, [10.0, 0.0, 0.0]),
        "IV.13" => (linear, [-10.0, 0.0, 0.0]),
        "IV.14" => (linear, [0.0, 10.0, 0.0]),
        "IV.15" => (wave, [0.0, 0.0, -10.0]),
        "IV.16" => (wave, [0.0, 0.0, 10.0]),
        "IV.17" => (wave, [40.0, 0.0, 0.0]),
        "IV.18" => (hill, [0.0, 0.0, -10.0]),
        "IV.19" => (hill, [0.0, 0.0, 10.0]),
        "IV.20" => (hill, [1000.0, 0.0, 0.0]),
        _ => return None,
    };
    Some(ThinFilm::new(gap, v))
}
