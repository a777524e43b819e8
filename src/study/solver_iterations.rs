//! A solver study on one fixed problem: the Uzawa variants of Fig. III.6 (§III.2.3.4) on the
//! stabilised Stokes test problem (III.88) ([`crate::models::stokes_channel`],
//! [`crate::linalg::uzawa`]). No mesh adapts: each variant iterates from p⁰ = 0 for the tier's
//! number of iterations (`rows`, `quick_rows`) or until its relative residual reaches
//! [`crate::models::stokes_channel::FIG_III6_TOLERANCE`], and every iteration is recorded with
//! its error against the direct solve of the coupled system.

use super::{printed_rows, Progress, RunError, StudyError, Tier};
use crate::experiment::{Experiment, Problem};
use crate::linalg::uzawa::{uzawa, UzawaOptions, Variant};
use crate::models::stokes_channel::{StokesChannel, FIG_III6_TOLERANCE};
use crate::results::RunResult;

/// Run the variants of the experiment's `[scene.stokes_channel]`.
pub fn run(experiment: &Experiment, tier: Tier, progress: Progress) -> Result<RunResult, RunError> {
    let table = &experiment.table;
    let fail = |cause: StudyError| RunError::at_cycle(table, 0, cause);
    let Problem::StokesChannel(data) = &experiment.problem else {
        return Err(fail("a solver study needs the Uzawa test problem".into()));
    };
    let channel = StokesChannel {
        delta_eps: data.delta_eps,
        ..StokesChannel::thesis()
    };
    let blocks = channel.blocks().map_err(|e| fail(e.into()))?;
    let direct = blocks.solve_direct().map_err(|e| fail(e.into()))?;
    let iterations = printed_rows(experiment, tier);
    let d = &experiment.scene.domain;
    let mut result = RunResult::new(
        table,
        &experiment.section,
        &experiment.title,
        tier.name(),
        [d.x[0], d.x[1], d.y[0], d.y[1]],
    );
    result.notes = experiment.notes.clone();
    result.related = experiment.related.clone();
    for (k, name) in data.variants.iter().enumerate() {
        let variant = Variant::from_name(name)
            .ok_or_else(|| fail(format!("unknown Uzawa variant `{name}`").into()))?;
        let options = UzawaOptions {
            max_iterations: iterations,
            relative_tolerance: FIG_III6_TOLERANCE,
            ..UzawaOptions::new(variant)
        };
        let run =
            uzawa(&blocks.system, &options, Some(&direct.pressure)).map_err(|e| fail(e.into()))?;
        result.uzawa.extend(run.rows);
        progress(table, k + 1, data.variants.len());
    }
    Ok(result)
}
