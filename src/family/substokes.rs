//! SubStokes thin-film flow (I.58), with or without cavitation (I.66), §IV.3.2 and §IV.3.6,
//! Tables IV.50–IV.63 and IV.70–IV.75.

use super::{Facts, Family};
use crate::experiment::{Effect, Experiment, Problem, SceneFile, StudyKind};
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
        }
    }

    fn problem(&self, scene: &SceneFile) -> Result<Problem, &'static str> {
        Ok(Problem::SubStokes(
            scene.substokes.clone().ok_or("substokes")?,
        ))
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
