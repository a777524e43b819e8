//! Model-adaptive contact, §IV.2.3–§IV.2.4, Tables IV.18–IV.35 and the U-O forming of Fig.
//! IV.54: the z- or the Signorini model chosen face by face (Algorithms III.2 and III.3), on a
//! fixed mesh, balanced with grid adaptivity (Algorithm III.25), or over the load steps of the
//! forming.

use super::contact::{contact_data, data_warnings, elastic_body_with_contact, untouched_obstacles};
use super::{Facts, Family, Infeasible};
use crate::experiment::{
    ContactModel, Effect, Experiment, ModelAlgorithm, ModelErrorSolution, Plan, Problem, SceneFile,
    Scope, StudyKind, Warning,
};
use crate::results::Row;
use crate::study::{self, model_contact::ModelAdaptiveContact, AlternativeReading, StudyError};

pub struct ModelContact;

impl Family for ModelContact {
    fn facts(&self) -> &'static Facts {
        &Facts {
            id: "model-contact",
            effects: &[Effect::Elasticity, Effect::Contact],
            kinds: &[
                StudyKind::ModelAdaptive,
                StudyKind::ModelAndGridAdaptive,
                StudyKind::LoadSteps,
            ],
            report_family: Some("family-model-contact"),
            components: &["s1", "s2"],
            unknowns_per_vertex: 2,
            solver_choice: false,
            related: &[],
            quantities: crate::study::quantities::CONTACT,
        }
    }

    fn problem(&self, scene: &SceneFile) -> Result<Problem, &'static str> {
        elastic_body_with_contact(scene)
    }

    fn warnings(&self, experiment: &Experiment, scope: &Scope, out: &mut Vec<Warning>) {
        data_warnings(experiment, scope, out);
    }

    fn run_warnings(&self, _experiment: &Experiment, rows: &[Row], out: &mut Vec<Warning>) {
        untouched_obstacles(rows, out);
    }

    /// The model error ε_P at the z-solution of each cycle instead of the mixed one
    /// ([`ModelErrorSolution`]); not in a load-step study (the thesis prints no numbers for the
    /// forming, so there is no printed value a reading could be closer to).
    fn readings(&self, experiment: &Experiment) -> Vec<AlternativeReading> {
        let Ok((_, contact)) = contact_data(experiment) else {
            return Vec::new();
        };
        if contact.model != ContactModel::ModelAdaptive
            || contact.model_error_solution != ModelErrorSolution::Mixed
            || experiment.study.kind() == StudyKind::LoadSteps
        {
            return Vec::new();
        }
        let mut alt = experiment.clone();
        if let Problem::Contact { contact, .. } = &mut alt.problem {
            contact.model_error_solution = ModelErrorSolution::Z;
        }
        vec![AlternativeReading {
            label: "model error ε_P at the z-solution of each cycle (the coarse solution u_c), \
                    not at the mixed solution"
                .into(),
            suffix: "z-solution".into(),
            experiment: alt,
            needs_cavitation: false,
            asked: false,
        }]
    }

    /// On a fixed mesh with Algorithm III.3: one study per scene (its III.2 twin shares the
    /// mesh).
    fn cost_study(&self, experiment: &Experiment) -> bool {
        matches!(
            experiment.study.plan,
            Plan::ModelAdaptive { model } if model.algorithm == ModelAlgorithm::SortedError
        )
    }

    /// An obstacle reaching into the body where it is clamped, at the start or, in a load-step
    /// study, in any of the first `rows` steps: the rising tools of step j are raised by
    /// j · lift_per_step, and the clamped ends do not move.
    fn infeasible(&self, experiment: &Experiment, rows: usize) -> Option<Infeasible> {
        let (elasticity, contact) = contact_data(experiment).ok()?;
        let domain = &experiment.scene.domain;
        let Plan::LoadSteps { lift_per_step, .. } = experiment.study.plan else {
            let message = study::contact::infeasible_obstacle(elasticity, contact, domain)?;
            return Some(Infeasible {
                step: None,
                message,
            });
        };
        (0..rows.max(1)).find_map(|step| {
            let tools = contact.raised(step as f64 * lift_per_step);
            let message = study::contact::infeasible_obstacle(elasticity, &tools, domain)?;
            Some(Infeasible {
                step: Some(step),
                message,
            })
        })
    }

    fn build(&self, experiment: &Experiment) -> Result<Box<dyn study::Problem>, StudyError> {
        let (elasticity, contact) = contact_data(experiment)?;
        let mut problem = match experiment.study.plan {
            Plan::ModelAndGridAdaptive { .. } => {
                ModelAdaptiveContact::with_grid(elasticity, contact)
            }
            Plan::LoadSteps { lift_per_step, .. } => {
                ModelAdaptiveContact::forming(elasticity, contact, lift_per_step)
            }
            _ => ModelAdaptiveContact::new(elasticity, contact),
        };
        // The table records its linearised mixed solutions against the converged ones.
        problem.compares = experiment.study.signorini_comparison;
        problem.failures.unprinted = experiment.study.unprinted_cycles;
        Ok(Box::new(problem))
    }
}
