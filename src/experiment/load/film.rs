//! The thin films of §IV.3: the Reynolds and SubStokes sections, alone or as the two models of
//! one model-adaptive film (§IV.3.4).

use super::check::{Check, Checked};
use crate::experiment::spec::*;
use crate::models::thin_film::CubicSpline;

impl Check<'_> {
    /// The film data shared by the Reynolds and SubStokes sections `F` of §IV.3, (IV.7)–(IV.20):
    /// the gap must stay open (g > 0) on the domain.
    fn film(&self, section: &str, data: Film<'_>, domain: &Rectangle) -> Checked {
        self.ensure(
            !data.equation.trim().is_empty(),
            &format!("{section}.equation"),
            "the thesis equation of the example, e.g. `IV.7`",
            "an empty string",
        )?;
        self.printable(&format!("{section}.equation"), data.equation, false)?;
        let gap = format!("{section}.gap");
        let g = |name: &str| format!("{gap}.{name}");
        match *data.gap {
            GapShape::Plain { g0 } => self.positive(&g("g0"), g0)?,
            GapShape::Linear { g0, slope } => {
                self.finite(&g("g0"), g0)?;
                self.finite(&g("slope"), slope)?;
                for x in domain.x {
                    let width = g0 + slope * x;
                    self.ensure(
                        width > 0.0,
                        &gap,
                        "a positive gap g0 + slope·x₁ at both ends of scene.domain.x",
                        format!("g = {width:?} at x₁ = {x:?}"),
                    )?;
                }
            }
            GapShape::WaveHorizontal {
                g0,
                amplitude,
                frequency,
            }
            | GapShape::Hill {
                g0,
                amplitude,
                frequency,
            } => {
                self.finite(&g("g0"), g0)?;
                self.finite(&g("amplitude"), amplitude)?;
                self.finite(&g("frequency"), frequency)?;
                let min = g0 - amplitude.abs();
                self.ensure(
                    min > 0.0,
                    &gap,
                    "a positive gap everywhere, g0 − |amplitude| > 0",
                    format!("g0 − |amplitude| = {min:?}"),
                )?;
            }
            // g lies between g_in and g_out (θ_s ∈ [0, 1]).
            GapShape::Step { g_in, g_out, at, s } => {
                self.positive(&g("g_in"), g_in)?;
                self.positive(&g("g_out"), g_out)?;
                self.finite(&g("at"), at)?;
                self.positive(&g("s"), s)?;
            }
            // g ≥ g0 > 0.
            GapShape::Parabolic {
                g0,
                center,
                radius,
                center_x2,
                radius_x2,
            } => {
                self.positive(&g("g0"), g0)?;
                self.finite(&g("center"), center)?;
                self.positive(&g("radius"), radius)?;
                match (center_x2, radius_x2) {
                    (Some(c), Some(r)) => {
                        self.finite(&g("center_x2"), c)?;
                        self.positive(&g("radius_x2"), r)?;
                    }
                    (None, None) => {}
                    (Some(_), None) => self.ensure(
                        false,
                        &g("radius_x2"),
                        "radius_x2 with center_x2 (the gap curved across x₂ too), or neither",
                        "center_x2 alone",
                    )?,
                    (None, Some(_)) => self.ensure(
                        false,
                        &g("center_x2"),
                        "center_x2 with radius_x2 (the gap curved across x₂ too), or neither",
                        "radius_x2 alone",
                    )?,
                }
            }
            GapShape::Tabulated { ref file, ref rows } => {
                self.tabulated_gap(&g("file"), file, rows, domain)?;
            }
        }
        self.finite_all(
            &format!("{section}.upper_wall_velocity"),
            data.upper_wall_velocity,
        )?;
        self.finite(
            &format!("{section}.boundary_pressure"),
            data.boundary_pressure,
        )?;
        self.ensure(
            data.cavitation == Cavitation::Off || data.boundary_pressure >= 0.0,
            &format!("{section}.boundary_pressure"),
            "a pressure ≥ 0 when cavitation is `on` or `auto` (the cavitation problem asks \
             ψ ≥ 0, which a negative boundary value contradicts)",
            data.boundary_pressure,
        )?;
        self.ensure(
            data.cavitation != Cavitation::Off
                || data.cavitation_source == CavitationSource::default(),
            &format!("{section}.cavitation_source"),
            "no cavitation_source when cavitation = \"off\" (it chooses the source term of \
             the cavitation problem only)",
            format!("{:?} with cavitation = \"off\"", data.cavitation_source),
        )?;
        Ok(())
    }

    /// A tabulated gap (its rows read and checked by [`Check::read_profiles`]): the rows reach
    /// over the domain, and the natural cubic spline through them, which can overshoot between
    /// rows, stays positive on it.
    fn tabulated_gap(
        &self,
        field: &str,
        file: &str,
        rows: &[[f64; 2]],
        domain: &Rectangle,
    ) -> Checked {
        self.profile_covers(field, file, rows, domain.x)?;
        let spline = CubicSpline::natural(rows);
        let (min, at, _) = spline.range(domain.x[0], domain.x[1]);
        let k = spline.knot_before(at);
        let between = match (rows.get(k), rows.get(k + 1)) {
            (Some(a), Some(b)) => format!(" (between the rows x1 = {:?} and {:?})", a[0], b[0]),
            _ => String::new(),
        };
        self.ensure(
            min > 0.0,
            field,
            "a profile whose interpolant, the natural cubic spline through the rows, stays \
             positive on scene.domain.x (the spline overshoots between rows where the profile \
             turns sharply: add rows there)",
            format!(
                "{}: the spline reaches g = {min:?} at x₁ = {at:?}{between}",
                self.profile_path(file).display()
            ),
        )
    }

    /// Reynolds data of §IV.3, (IV.7)–(IV.20) ([`Check::film`]).
    pub(super) fn reynolds(&self, data: &ReynoldsData, domain: &Rectangle) -> Checked {
        const F: &str = "scene.reynolds";
        self.film(
            F,
            Film {
                equation: &data.equation,
                gap: &data.gap,
                upper_wall_velocity: &data.upper_wall_velocity,
                boundary_pressure: data.boundary_pressure,
                cavitation: data.cavitation,
                cavitation_source: data.cavitation_source,
            },
            domain,
        )?;
        self.ensure(
            data.zone_residual == ZoneResidual::Full || data.cavitation != Cavitation::Off,
            &format!("{F}.zone_residual"),
            "`full` (or left out) when cavitation = \"off\": there is no cavitation zone",
            format!("{} with cavitation = \"off\"", data.zone_residual.name()),
        )
    }

    /// SubStokes data of §IV.3.2 and §IV.3.6, (IV.7)–(IV.20) ([`Check::film`]), and the
    /// stabilisation constant δ_ε > 0.
    pub(super) fn substokes(&self, data: &SubStokesData, domain: &Rectangle) -> Checked {
        const F: &str = "scene.substokes";
        self.film(
            F,
            Film {
                equation: &data.equation,
                gap: &data.gap,
                upper_wall_velocity: &data.upper_wall_velocity,
                boundary_pressure: data.boundary_pressure,
                cavitation: data.cavitation,
                cavitation_source: data.cavitation_source,
            },
            domain,
        )?;
        self.positive(&format!("{F}.delta_eps"), data.delta_eps)
    }
}

/// Whether the scene is the model-adaptive film: `reynolds` and `substokes` together.
pub(super) fn is_film_models(scene: &SceneFile) -> bool {
    scene.effects.contains(&Effect::Reynolds) && scene.effects.contains(&Effect::SubStokes)
}

/// The film data of a thin-film section, the same for Reynolds and SubStokes.
struct Film<'a> {
    equation: &'a str,
    gap: &'a GapShape,
    upper_wall_velocity: &'a [f64; 3],
    boundary_pressure: f64,
    cavitation: Cavitation,
    cavitation_source: CavitationSource,
}
