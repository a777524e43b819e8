//! Alternative readings of a scene that the report runs beside the experiment as written, to
//! show how much a choice of reading matters. Each family names its own
//! ([`crate::family::Family::readings`]).

use crate::experiment::Experiment;

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
    /// Whether the experiment file asks for this run itself (SubStokes `compare_with`), so that
    /// it runs whatever `[study] alternatives` says; the thesis's readings run only where that
    /// is on ([`crate::experiment::Study::readings`]).
    pub asked: bool,
}

impl AlternativeReading {
    /// Whether the reading can differ from `run`, the run as written: a reading of the
    /// cavitation model does not apply to a run whose cavitation never switched on.
    pub fn applies_to(&self, run: &crate::results::RunResult) -> bool {
        !self.needs_cavitation || run.cavitation_ran != Some(false)
    }
}

/// The alternative readings the report compares an experiment with: those its family names
/// ([`crate::family::Family::readings`]: two readings of the cavitation source R₃c for
/// Reynolds, another solver for SubStokes, the model error at the z-solution for model-adaptive
/// contact); none for the other families.
pub fn alternative_readings(experiment: &Experiment) -> Vec<AlternativeReading> {
    experiment.family.readings(experiment)
}
