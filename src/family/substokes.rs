//! SubStokes thin-film flow (I.58), with or without cavitation (I.66), §IV.3.2 and §IV.3.6,
//! Tables IV.50–IV.63 and IV.70–IV.75.

use super::reynolds::{half_period, step_inside};
use super::{Facts, Family};
use crate::experiment::{
    Effect, Experiment, Problem, Rectangle, SceneFile, Scope, StudyKind, SubStokesData, Warning,
};
use crate::models::thin_film::Gap;
use crate::study::{self, substokes::SubStokesFilm, AlternativeReading, StudyError};

pub struct SubStokes;

impl Family for SubStokes {
    fn facts(&self) -> &'static Facts {
        &Facts {
            id: "substokes",
            effects: &[Effect::SubStokes],
            kinds: &[StudyKind::GridAdaptive],
            report_family: Some("family-substokes"),
            components: &["chi1", "chi2", "psi"],
            unknowns_per_vertex: 3,
            solver_choice: false,
            related: &[],
            quantities: crate::study::quantities::FILM,
        }
    }

    fn problem(&self, scene: &SceneFile) -> Result<Problem, &'static str> {
        Ok(Problem::SubStokes(
            scene.substokes.clone().ok_or("substokes")?,
        ))
    }

    fn warnings(&self, experiment: &Experiment, scope: &Scope, out: &mut Vec<Warning>) {
        if let Problem::SubStokes(s) = &experiment.problem {
            film_warnings(s, &experiment.scene.domain, scope, out);
        }
    }

    /// With `compare_with` another solver than `solver`: the same table solved by that one
    /// (the thesis's Uzawa family, (III.92), projected with cavitation).
    fn readings(&self, experiment: &Experiment) -> Vec<AlternativeReading> {
        let Problem::SubStokes(data) = &experiment.problem else {
            return Vec::new();
        };
        let Some(solver) = data.compare_with.filter(|s| *s != data.solver) else {
            return Vec::new();
        };
        let mut alt = experiment.clone();
        if let Problem::SubStokes(d) = &mut alt.problem {
            d.solver = solver;
            d.compare_with = None;
        }
        vec![AlternativeReading {
            label: format!(
                "the same table solved by solver = \"{}\" instead of \"{}\" (the thesis's \
                 Uzawa family, (III.92), projected with cavitation)",
                solver.name(),
                data.solver.name()
            ),
            suffix: solver.name().into(),
            experiment: alt,
            needs_cavitation: false,
            asked: true,
        }]
    }

    fn build(&self, experiment: &Experiment) -> Result<Box<dyn study::Problem>, StudyError> {
        let Problem::SubStokes(data) = &experiment.problem else {
            return Err(StudyError::Failed(
                "a SubStokes run needs SubStokes data".into(),
            ));
        };
        Ok(Box::new(SubStokesFilm::new(data, &experiment.scene.domain)))
    }
}

/// The warnings of a SubStokes film (alone or as the SubStokes model of the model-adaptive
/// film): a gap whose oscillation no mesh of the run resolves; a gap so thin that the film's
/// conductance g³/12 underflows (the pressure block is then zero in double precision and the
/// solve fails for a reason the file does not show); a pressure stabilisation δ_ε h² larger than
/// g³/12 even on the finest cell the run can reach, where the stabilisation, not the film, sets
/// the pressure (the Reynolds limit of the film is lost).
pub(super) fn film_warnings(
    s: &SubStokesData,
    domain: &Rectangle,
    scope: &Scope,
    out: &mut Vec<Warning>,
) {
    const F: &str = "scene.substokes";
    scope.resolves(&format!("{F}.gap.frequency"), half_period(&s.gap), out);
    step_inside(F, &s.gap, scope, out);
    let (g_min, _) =
        Gap::from(&s.gap).range_on_box([domain.x[0], domain.y[0], domain.x[1], domain.y[1]]);
    let conductance = g_min.powi(3) / 12.0;
    if conductance < f64::MIN_POSITIVE {
        out.push(Warning::new(
            format!("{F}.gap"),
            format!(
                "the thinnest gap g = {g_min:e} makes the film's conductance g³/12 = \
                 {conductance:e} underflow double precision: the pressure is not determined by \
                 the film, and the solve fails or returns the stabilisation's pressure"
            ),
        ));
        return;
    }
    let stabilisation = s.delta_eps * scope.finest * scope.finest;
    if stabilisation > conductance {
        out.push(Warning::new(
            format!("{F}.delta_eps"),
            format!(
                "the pressure stabilisation δ_ε h² = {stabilisation:.3e} exceeds the film's \
                 conductance g³/12 = {conductance:.3e} (thinnest gap {g_min:e}) even on the \
                 finest cell this run can reach ({:.3e} wide): the stabilisation, not the film, \
                 sets the pressure",
                scope.finest
            ),
        ));
    }
}
