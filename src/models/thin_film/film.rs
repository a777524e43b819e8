//! [`FilmJets`]: the general Chapter I source terms and Reynolds loads from wall data given
//! as jets.

use super::Jet;

/// Which cavitation correction γ₃c to use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum CavitationSource {
    /// (I.61) as printed.
    #[default]
    Printed,
    /// The self-consistent reading of the derivation before (I.60): γ₃c → 2γ₃ − γ₃c.
    SelfConsistent,
    /// The source terms of the problems without cavitation: γ₃c → γ₃ and R₃c → R₃ of (I.77), so
    /// l_{R,c} = l_R. The thesis's code evidently solved and estimated its cavitation runs so:
    /// with it tribo's row-0 estimate of IV.66 (wave gap, upward velocity) is the printed 1170.7
    /// to 1e-5 and that of IV.68 (hill gap) 271.82 against 271.45, where the printed γ₃c gives
    /// 1203.5 and 287.35 (report notes of IV.66–IV.69).
    Reynolds,
}

impl From<crate::experiment::CavitationSource> for CavitationSource {
    fn from(s: crate::experiment::CavitationSource) -> CavitationSource {
        use crate::experiment::CavitationSource as File;
        match s {
            File::Printed => CavitationSource::Printed,
            File::SelfConsistent => CavitationSource::SelfConsistent,
            File::Reynolds => CavitationSource::Reynolds,
        }
    }
}

/// Wall data of a thin film at one point x ∈ Ω₂, as jets, and the derived quantities of
/// Section I.2.3 (list after (I.46)): g = z₁ − z₀, z̄ = ½(z₁ + z₀), v̄ = ½(v(z₁) + v(z₀)),
/// δv = v(z₁) − v(z₀).
///
/// Orders: with inputs known to third order, [`FilmJets::gamma3`], [`FilmJets::gamma3c`] and
/// [`FilmJets::gamma`] are known to first order, [`FilmJets::sigma3`] and [`FilmJets::r1`] to
/// second order, and [`FilmJets::r3`], [`FilmJets::r3c`] and the loads to order zero (value only).
///
/// The methods are always inlined, like the [`Jet`] operations, and so is
/// [`ThinFilm::film_jets`]: a load of [`ThinFilm`] is then one function from the gap's jet to the
/// value, in which the compiler computes only the entries the value uses (γ₃ is needed to first
/// order there, R₁ to order zero, most of every third-order product is never read) and knows the
/// wall data of the examples that are constant (z₀ = 0, v(z₀) = 0, κ = 0, the derivatives of
/// v(z₁)); each entry it computes has the same expression, so the same bits. The components are
/// computed in loops over μ rather than by `[0, 1].map(..)`, whose closure the compiler called
/// instead of inlining, with the wall data in memory (`cargo bench --bench load`: 380–530 ns per
/// point for both loads with the [`Jet`] operations alone inlined, 110–210 with this).
///
/// [`ThinFilm`]: super::ThinFilm
/// [`ThinFilm::film_jets`]: super::ThinFilm::film_jets
#[derive(Debug, Clone, Copy)]
pub struct FilmJets {
    /// Lower wall z₀.
    pub z0: Jet,
    /// Upper wall z₁.
    pub z1: Jet,
    /// Lower wall velocity v(z₀) (3 components).
    pub v0: [Jet; 3],
    /// Upper wall velocity v(z₁) (3 components).
    pub v1: [Jet; 3],
    /// Integrated in-plane body force κ_μ = ∫ f_μ dx₃ (I.40).
    pub kappa: [Jet; 2],
    /// Gap width g = z₁ − z₀.
    pub g: Jet,
    /// Gap centre z̄ = ½(z₁ + z₀).
    pub zbar: Jet,
    /// Average velocity v̄ = ½(v(z₁) + v(z₀)).
    pub vbar: [Jet; 3],
    /// Velocity difference δv = v(z₁) − v(z₀).
    pub dv: [Jet; 3],
}

impl FilmJets {
    /// Builds the derived quantities g, z̄, v̄, δv (list after (I.46)) from the wall data.
    #[inline(always)]
    pub fn from_walls(z0: Jet, z1: Jet, v0: [Jet; 3], v1: [Jet; 3], kappa: [Jet; 2]) -> FilmJets {
        let vbar = |i: usize| (v1[i] + v0[i]).scale(0.5);
        let dv = |i: usize| v1[i] - v0[i];
        FilmJets {
            z0,
            z1,
            v0,
            v1,
            kappa,
            g: z1 - z0,
            zbar: (z1 + z0).scale(0.5),
            vbar: [vbar(0), vbar(1), vbar(2)],
            dv: [dv(0), dv(1), dv(2)],
        }
    }

    /// (I.47): (γ₃)_μ = −2 ∂_ν v̄_μ ∂_ν g − 2 ∂_ν δv_μ ∂_ν z̄ − v̄_μ Δg − δv_μ Δz̄.
    #[inline(always)]
    pub fn gamma3(&self) -> [Jet; 2] {
        let (g, zb) = (self.g, self.zbar);
        let mut gamma3 = [Jet::ZERO; 2];
        for mu in 0..2 {
            let mut r = -(self.vbar[mu] * g.laplacian()) - self.dv[mu] * zb.laplacian();
            for nu in 0..2 {
                r += (self.vbar[mu].partial(nu) * g.partial(nu)).scale(-2.0);
                r += (self.dv[mu].partial(nu) * zb.partial(nu)).scale(-2.0);
            }
            gamma3[mu] = r;
        }
        gamma3
    }

    /// (I.52), (I.72): γ_μ = (γ₃)_μ + (12/g) v̄_μ (SubStokes momentum source).
    #[inline(always)]
    pub fn gamma(&self) -> [Jet; 2] {
        let mut r = self.gamma3();
        let ginv = self.g.recip();
        for mu in 0..2 {
            r[mu] += (self.vbar[mu] * ginv).scale(12.0);
        }
        r
    }

    /// (I.50), (I.73): σ₃ = −δv₃ + δv_μ ∂_μ z̄ + 2 v̄_μ ∂_μ g (SubStokes mass source).
    #[inline(always)]
    pub fn sigma3(&self) -> Jet {
        let mut r = -self.dv[2];
        for mu in 0..2 {
            r += self.dv[mu] * self.zbar.partial(mu);
            r += (self.vbar[mu] * self.g.partial(mu)).scale(2.0);
        }
        r
    }

    /// R₁ of (I.77): R₁ = g ∂_ν v̄_ν − δv_ν ∂_ν z̄.
    #[inline(always)]
    pub fn r1(&self) -> Jet {
        let mut r = Jet::ZERO;
        for nu in 0..2 {
            r += self.g * self.vbar[nu].partial(nu);
            r = r - self.dv[nu] * self.zbar.partial(nu);
        }
        r
    }

    /// R₃ of (I.77): R₃ = (g/12) ∂_ν( g ((γ₃)_ν + Δ(v̄_ν g)) ). Value only (order 0).
    #[inline(always)]
    pub fn r3(&self) -> Jet {
        let g3 = self.gamma3();
        let mut s = Jet::ZERO;
        for nu in 0..2 {
            s += (self.g * (g3[nu] + (self.vbar[nu] * self.g).laplacian())).partial(nu);
        }
        (self.g * s).scale(1.0 / 12.0)
    }

    /// (I.61): (γ₃c)_μ = (γ₃)_μ + ∂_μ∂_ν(v̄_ν g + δv_ν z̄) − (g ∂_μ∂_ν v̄_ν + z̄ ∂_μ∂_ν δv_ν)
    /// − g ∂_μ(δv₃/g) for [`CavitationSource::Printed`]; 2γ₃ − (that) for
    /// [`CavitationSource::SelfConsistent`]; γ₃ for
    /// [`CavitationSource::Reynolds`].
    #[inline(always)]
    pub fn gamma3c(&self, source: CavitationSource) -> [Jet; 2] {
        let g3 = self.gamma3();
        match source {
            CavitationSource::Printed => self.gamma3c_printed(g3),
            CavitationSource::SelfConsistent => {
                let p = self.gamma3c_printed(g3);
                let mut r = g3;
                for mu in 0..2 {
                    r[mu] = g3[mu].scale(2.0) - p[mu];
                }
                r
            }
            CavitationSource::Reynolds => g3,
        }
    }

    /// (γ₃c)_μ of (I.61) as printed, given `g3` = γ₃.
    #[inline(always)]
    fn gamma3c_printed(&self, g3: [Jet; 2]) -> [Jet; 2] {
        let (g, zb) = (self.g, self.zbar);
        // Scalars whose μ-derivative is needed: Σ_ν ∂_ν(v̄_ν g + δv_ν z̄), Σ_ν ∂_ν v̄_ν,
        // Σ_ν ∂_ν δv_ν.
        let mut div_flux = Jet::ZERO;
        let mut div_vbar = Jet::ZERO;
        let mut div_dv = Jet::ZERO;
        for nu in 0..2 {
            div_flux += (self.vbar[nu] * g + self.dv[nu] * zb).partial(nu);
            div_vbar += self.vbar[nu].partial(nu);
            div_dv += self.dv[nu].partial(nu);
        }
        let dv3_over_g = self.dv[2] / g;
        let mut r = g3;
        for mu in 0..2 {
            r[mu] = g3[mu] + div_flux.partial(mu)
                - (g * div_vbar.partial(mu) + zb * div_dv.partial(mu))
                - g * dv3_over_g.partial(mu);
        }
        r
    }

    /// (I.65): γ_c = γ₃c + (12/g) v̄ (SubStokes-with-cavitation momentum source).
    #[inline(always)]
    pub fn gamma_c(&self, source: CavitationSource) -> [Jet; 2] {
        let mut r = self.gamma3c(source);
        let ginv = self.g.recip();
        for mu in 0..2 {
            r[mu] += (self.vbar[mu] * ginv).scale(12.0);
        }
        r
    }

    /// R₃c of (I.81): R₃c = (g/12) ∂_μ[ g Δ(g v̄_μ) + g ∂_μ∂_ν(g v̄_ν) + g (γ₃c)_μ ]; R₃ of (I.77)
    /// for [`CavitationSource::Reynolds`]. Value only.
    #[inline(always)]
    pub fn r3c(&self, source: CavitationSource) -> Jet {
        if source == CavitationSource::Reynolds {
            return self.r3();
        }
        let g = self.g;
        let g3c = self.gamma3c(source);
        let mut div_gvbar = Jet::ZERO;
        for nu in 0..2 {
            div_gvbar += (g * self.vbar[nu]).partial(nu);
        }
        let mut s = Jet::ZERO;
        for mu in 0..2 {
            let inner = (g * self.vbar[mu]).laplacian() + div_gvbar.partial(mu) + g3c[mu];
            s += (g * inner).partial(mu);
        }
        (g * s).scale(1.0 / 12.0)
    }

    /// (g/12) ∂_ν(g κ_ν) (body-force term of (I.77)).
    #[inline(always)]
    fn kappa_term(&self) -> Jet {
        let mut s = Jet::ZERO;
        for nu in 0..2 {
            s += (self.g * self.kappa[nu]).partial(nu);
        }
        (self.g * s).scale(1.0 / 12.0)
    }

    /// Right-hand side of the Reynolds equation (I.77):
    /// (g/12) ∂_μ(g² ∂_μ(ψ/g)) = δv₃ + (g/12) ∂_ν(g κ_ν) + R₁ + R₃. Value only.
    #[inline(always)]
    pub fn reynolds_rhs(&self) -> Jet {
        self.dv[2] + self.kappa_term() + self.r1() + self.r3()
    }

    /// Right-hand side of the Reynolds inequality (I.81): δv₃ + (g/12) ∂_ν(g κ_ν) + R₁ + R₃c.
    /// Value only.
    #[inline(always)]
    pub fn cavitation_rhs(&self, source: CavitationSource) -> Jet {
        self.dv[2] + self.kappa_term() + self.r1() + self.r3c(source)
    }

    /// Reynolds load (II.37), from (I.79):
    /// l_R = −12 [ δv₃/g² + ∂_ν(g κ_ν)/(12 g) + (R₁ + R₃)/g² ]. Value only.
    #[inline(always)]
    pub fn reynolds_load(&self) -> Jet {
        self.load(self.r3())
    }

    /// Reynolds-with-cavitation load l_{R,c} (II.39), from (I.82): l_R with R₃c in place of R₃.
    /// Value only.
    #[inline(always)]
    pub fn cavitation_load(&self, source: CavitationSource) -> Jet {
        self.load(self.r3c(source))
    }

    /// −12 [ δv₃/g² + ∂_ν(g κ_ν)/(12 g) + (R₁ + r)/g² ].
    #[inline(always)]
    fn load(&self, r: Jet) -> Jet {
        let g = self.g;
        let ginv2 = (g * g).recip();
        let mut div_gk = Jet::ZERO;
        for nu in 0..2 {
            div_gk += (g * self.kappa[nu]).partial(nu);
        }
        let bracket = self.dv[2] * ginv2 + (div_gk / g).scale(1.0 / 12.0) + (self.r1() + r) * ginv2;
        bracket.scale(-12.0)
    }
}
