//! Alternative readings of a scene that the report runs beside the experiment as written, to
//! show how much a choice of reading matters. One match arm per problem; the thin-film problems
//! share the readings of the cavitation source ([`super::thin_film::source_readings`]).

use super::thin_film::source_readings;
use crate::experiment::{ContactModel, Experiment, ModelErrorSolution, Problem, StudyKind};

/// An experiment with one reading changed.
pub struct AlternativeReading {
    /// What changes, for the report's heading.
    pub label: String,
    /// Suffix of the alternative's data file (`report/data/<table>.<suffix>.csv`).
    pub suffix: String,
    pub experiment: Experiment,
    /// Whether the reading changes only the cavitation model, so that it applies only to a run
    /// whose cavitation model was in use ([`AlternativeReading::applies_to`]).
    pub needs_cavitation: bool,
}

impl AlternativeReading {
    /// Whether the reading can differ from `run`, the run as written: a reading of the
    /// cavitation model does not apply to a run whose cavitation never switched on.
    pub fn applies_to(&self, run: &crate::results::RunResult) -> bool {
        !self.needs_cavitation || run.cavitation_ran != Some(false)
    }
}

/// The alternative readings the report compares an experiment with: for Reynolds with
/// cavitation and the printed γ₃c of (I.61), two readings of the source term R₃c
/// ([`source_readings`]); for model-adaptive contact the model error at the z-solution instead
/// of the mixed one ([`ModelErrorSolution`]), except in a load-step study (the thesis prints
/// no numbers for the forming, so there is no printed value a reading could be closer to);
/// none for the other problems.
pub fn alternative_readings(experiment: &Experiment) -> Vec<AlternativeReading> {
    match &experiment.problem {
        Problem::Reynolds(data) => source_readings(data.cavitation, data.cavitation_source)
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
                }
            })
            .collect(),
        Problem::SubStokes(data) => match data.compare_with {
            Some(solver) if solver != data.solver => {
                let mut alt = experiment.clone();
                if let Problem::SubStokes(d) = &mut alt.problem {
                    d.solver = solver;
                    d.compare_with = None;
                }
                vec![AlternativeReading {
                    label: format!(
                        "the same table solved by solver = \"{}\" instead of \"{}\" (the \
                         thesis's Uzawa family, (III.92), projected with cavitation)",
                        solver.name(),
                        data.solver.name()
                    ),
                    suffix: solver.name().into(),
                    experiment: alt,
                    needs_cavitation: false,
                }]
            }
            _ => Vec::new(),
        },
        Problem::Contact { contact, .. }
            if contact.model == ContactModel::ModelAdaptive
                && contact.model_error_solution == ModelErrorSolution::Mixed
                && experiment.study.kind != StudyKind::LoadSteps =>
        {
            let mut alt = experiment.clone();
            if let Problem::Contact { contact, .. } = &mut alt.problem {
                contact.model_error_solution = ModelErrorSolution::Z;
            }
            vec![AlternativeReading {
                label: "model error ε_P at the z-solution of each cycle (the coarse solution \
                        u_c), not at the mixed solution"
                    .into(),
                suffix: "z-solution".into(),
                experiment: alt,
                needs_cavitation: false,
            }]
        }
        Problem::Elasticity(_)
        | Problem::Contact { .. }
        | Problem::StokesChannel(_)
        | Problem::FilmModels { .. } => Vec::new(),
    }
}
