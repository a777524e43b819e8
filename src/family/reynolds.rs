//! Reynolds thin-film flow (I.79), with or without cavitation (I.82), §IV.3.1 and §IV.3.5,
//! Tables IV.36–IV.49 and IV.64–IV.69.

use super::{Facts, Family};
use crate::experiment::{
    Effect, Experiment, GapShape, Problem, ReynoldsData, SceneFile, Scope, StudyKind, Warning,
};
use crate::linalg::SolverKind;
use crate::study::thin_film::source_readings;
use crate::study::{self, reynolds::ReynoldsFilm, AlternativeReading, StudyError};

pub struct Reynolds;

impl Family for Reynolds {
    fn facts(&self) -> &'static Facts {
        &Facts {
            id: "reynolds",
            effects: &[Effect::Reynolds],
            kinds: &[StudyKind::GridAdaptive],
            report_family: Some("family-reynolds"),
            components: &["psi"],
            unknowns_per_vertex: 1,
            solver_choice: true,
            related: &[],
            quantities: crate::study::quantities::FILM,
        }
    }

    fn problem(&self, scene: &SceneFile) -> Result<Problem, &'static str> {
        Ok(Problem::Reynolds(scene.reynolds.clone().ok_or("reynolds")?))
    }

    /// Walls at rest over a gap with Δg = 0 (nothing drives the flow), a gap whose oscillation
    /// no mesh of the run resolves.
    fn warnings(&self, experiment: &Experiment, scope: &Scope, out: &mut Vec<Warning>) {
        if let Problem::Reynolds(r) = &experiment.problem {
            film_warnings(r, scope, out);
        }
    }

    /// With cavitation and the printed γ₃c of (I.61), two readings of the source term R₃c
    /// ([`source_readings`]).
    fn readings(&self, experiment: &Experiment) -> Vec<AlternativeReading> {
        let Problem::Reynolds(data) = &experiment.problem else {
            return Vec::new();
        };
        source_readings(data.cavitation, data.cavitation_source)
            .into_iter()
            .map(|reading| {
                let mut alt = experiment.clone();
                if let Some(r) = alt.problem.reynolds_mut() {
                    r.cavitation_source = reading.source;
                }
                AlternativeReading {
                    label: reading.label.into(),
                    suffix: reading.suffix.into(),
                    experiment: alt,
                    needs_cavitation: true,
                    asked: false,
                }
            })
            .collect()
    }

    /// Multigrid: measured faster than the direct solver on the Reynolds tables (the report's
    /// Performance section shows their solve seconds).
    fn default_solver(&self) -> SolverKind {
        SolverKind::Multigrid
    }

    fn build(&self, experiment: &Experiment) -> Result<Box<dyn study::Problem>, StudyError> {
        let Problem::Reynolds(data) = &experiment.problem else {
            return Err(StudyError::Failed(
                "a Reynolds run needs Reynolds data".into(),
            ));
        };
        Ok(Box::new(ReynoldsFilm::new(
            data,
            &experiment.scene.domain,
            study::solver_of(experiment),
        )))
    }
}

/// The warnings of a Reynolds film (alone or as the Reynolds model of the model-adaptive film):
/// both walls at rest over a gap with Δg = 0, where ψ ≡ ψ₀ is the exact solution (the form of
/// [`crate::models::reynolds`] reproduces constants exactly when Δg = 0, and the load vanishes
/// with the velocities; over a wave or hill gap the term ψΔg/g drives ψ away from ψ₀ even at
/// rest), and a gap whose oscillation no mesh of the run resolves.
pub(super) fn film_warnings(r: &ReynoldsData, scope: &Scope, out: &mut Vec<Warning>) {
    let flat = matches!(r.gap, GapShape::Plain { .. } | GapShape::Linear { .. });
    // A manufactured pressure brings its own load: the walls do not drive it.
    if r.upper_wall_velocity == [0.0; 3] && flat && r.exact.is_none() {
        out.push(Warning::new(
            "scene.reynolds.upper_wall_velocity",
            format!(
                "both walls at rest over a gap with Δg = 0: nothing drives the flow, ψ ≡ \
                 boundary_pressure = {} is the exact solution on every mesh, every estimate is \
                 0 up to rounding and the ratios mean nothing",
                r.boundary_pressure
            ),
        ));
    }
    scope.resolves("scene.reynolds.gap.frequency", half_period(&r.gap), out);
    step_inside("scene.reynolds", &r.gap, scope, out);
    // The form ∫∇ψ·∇φ + (Δg/g)ψφ of crate::models::reynolds is coercive for the exact
    // integral only: at a step much sharper than the cells, |Δg/g| ≈ |g_out − g_in|/(g s²) at a
    // quadrature point outweighs the stiffness and the system is indefinite (measured: s = 0.01
    // fails on cells of 1/32 and 1/16, s = 0.015 does not).
    if let GapShape::Step { s, .. } = r.gap {
        let first = scope.first_cell();
        if s < 0.5 * first {
            out.push(Warning::new(
                "scene.reynolds.gap.s",
                format!(
                    "a step smoothed over s = {s:?}, less than half the cells of the first mesh \
                     ({first:?} wide): the Reynolds operator ∫∇ψ·∇φ + (Δg/g)ψφ can be \
                     indefinite on the cells at the step, and the solve then fails; take \
                     s ≥ {:?} or refine the first mesh globally",
                    0.5 * first
                ),
            ));
        }
    }
}

/// A step gap whose step lies outside the domain: the gap is then (up to θ_s) constant.
pub(super) fn step_inside(section: &str, gap: &GapShape, scope: &Scope, out: &mut Vec<Warning>) {
    if let GapShape::Step { at, .. } = *gap {
        let field = format!("{section}.gap.at");
        let consequence = "the gap is (up to the smoothing θ_s) constant on the domain";
        scope.contains_jump(&field, at, consequence, out);
    }
}

/// Half the period of a gap's oscillation (infinite for the gaps that do not oscillate).
pub(super) fn half_period(gap: &GapShape) -> f64 {
    match *gap {
        GapShape::WaveHorizontal { frequency, .. } => 0.5 / frequency.abs(),
        // sin²(2π f x) has period 1/(2f).
        GapShape::Hill { frequency, .. } => 0.25 / frequency.abs(),
        GapShape::Plain { .. }
        | GapShape::Linear { .. }
        | GapShape::Step { .. }
        | GapShape::Parabolic { .. }
        | GapShape::Tabulated { .. } => f64::INFINITY,
    }
}
