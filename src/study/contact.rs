//! Placeholder: the contact tables are not implemented yet.

use super::{Progress, RunError, Tier};
use crate::experiment::ExperimentSpec;
use crate::results::RunResult;

pub fn run(spec: &ExperimentSpec, _tier: Tier, _progress: Progress) -> Result<RunResult, RunError> {
    Err(RunError {
        table: spec.table.clone(),
        cycle: 0,
        message: "the contact model is not implemented yet".into(),
    })
}
