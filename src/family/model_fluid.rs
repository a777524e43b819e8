//! The model-adaptive film, §IV.3.4, Figs. IV.116–IV.118: Reynolds and SubStokes on one film,
//! the model chosen cell by cell (Algorithm III.3 over the cells), with grid adaptivity.

use super::{Facts, Family};
use crate::experiment::{
    Cavitation, Check, Checked, Effect, Experiment, ExperimentFile, Plan, Problem, ReynoldsData,
    SceneFile, StudyKind, SubStokesData,
};
use crate::study::{self, model_fluid, Adaptation, StudyError};

pub struct ModelFluid;

impl Family for ModelFluid {
    fn facts(&self) -> &'static Facts {
        &Facts {
            id: "model-fluid",
            effects: &[Effect::Reynolds, Effect::SubStokes],
            kinds: &[StudyKind::ModelAndGridAdaptive],
            report_family: Some("family-model-fluid"),
            components: &["psi"],
            unknowns_per_vertex: 3,
        }
    }

    fn check(&self, check: &Check, file: &ExperimentFile) -> Checked {
        match (&file.scene.reynolds, &file.scene.substokes) {
            (Some(r), Some(s)) => same_film(check, r, s),
            _ => Ok(()),
        }
    }

    fn problem(&self, scene: &SceneFile) -> Result<Problem, &'static str> {
        let reynolds = scene.reynolds.clone().ok_or("reynolds")?;
        let substokes = scene.substokes.clone().ok_or("substokes")?;
        Ok(Problem::FilmModels {
            reynolds,
            substokes,
        })
    }

    fn build(&self, experiment: &Experiment) -> Result<Box<dyn study::Problem>, StudyError> {
        let Problem::FilmModels { substokes, .. } = &experiment.problem else {
            return Err(StudyError::Failed(
                "a model-adaptive film needs Reynolds and SubStokes data".into(),
            ));
        };
        Ok(Box::new(model_fluid::ModelAdaptiveFilm::new(
            substokes,
            &experiment.scene.domain,
        )))
    }

    /// The film's own marking ([`model_fluid::marking`]): model and grid marking from the same
    /// indicators, without the balance (III.93).
    fn adaptation(&self, experiment: &Experiment) -> Box<dyn Adaptation> {
        match experiment.study.plan {
            Plan::ModelAndGridAdaptive { grid, model, .. } => {
                Box::new(model_fluid::marking(grid, model, experiment.study.ties))
            }
            _ => study::build_adaptation(&experiment.study, &experiment.scene),
        }
    }
}

/// The two sections of a model-adaptive film describe one film, without cavitation (the
/// coupling of §IV.3.4 has none).
fn same_film(check: &Check, r: &ReynoldsData, s: &SubStokesData) -> Checked {
    let pairs = [
        (
            "equation",
            r.equation == s.equation,
            format!("`{}` and `{}`", r.equation, s.equation),
        ),
        (
            "gap",
            r.gap == s.gap,
            format!("{:?} and {:?}", r.gap, s.gap),
        ),
        (
            "upper_wall_velocity",
            r.upper_wall_velocity == s.upper_wall_velocity,
            format!(
                "{:?} and {:?}",
                r.upper_wall_velocity, s.upper_wall_velocity
            ),
        ),
        (
            "boundary_pressure",
            r.boundary_pressure == s.boundary_pressure,
            format!("{:?} and {:?}", r.boundary_pressure, s.boundary_pressure),
        ),
    ];
    for (field, same, found) in pairs {
        check.ensure(
            same,
            &format!("scene.substokes.{field}"),
            &format!("the same {field} as scene.reynolds (both models solve one film)"),
            found,
        )?;
    }
    for (section, cavitation) in [("reynolds", r.cavitation), ("substokes", s.cavitation)] {
        check.ensure(
            cavitation == Cavitation::Off,
            &format!("scene.{section}.cavitation"),
            "\"off\" in a model-adaptive film (the coupling of §IV.3.4 has no cavitation)",
            format!("{cavitation:?}"),
        )?;
    }
    Ok(())
}
