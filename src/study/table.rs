//! One table of the report: the experiment as written, the cost of accuracy of its scene where
//! that study applies ([`super::cost`]), and its alternative readings ([`super::readings`]), in
//! this order. What becomes of each run — how it is guarded against panics, where its data go,
//! how its progress is shown — is the caller's, through a [`TableHost`]; the order of the runs,
//! which of them run and what the page is told about those that do not are decided here, once.

use super::{
    alternative_readings, cost, run_within, solves, uniform, AlternativeReading, Budget, Progress,
    RunError, Tier,
};
use crate::experiment::Experiment;
use crate::results::{RunResult, VtuOutput};

/// How the runs of every table are made.
#[derive(Clone, Copy, Debug)]
pub struct TableOptions {
    pub tier: Tier,
    /// The memory a run may use; a run predicted to need more is refused before its first solve.
    pub budget: Budget,
    /// Whether the alternative readings and the cost study run beside the table as written
    /// (`report --no-alternatives` runs neither: the table alone, once). The thesis's readings
    /// run only where the experiment wants them ([`crate::experiment::Study::readings`]: the
    /// thesis's experiments, and a scene of one's own with `[study] alternatives = true`).
    pub alternatives: bool,
    /// Which printed meshes go into the VTU files ([`crate::experiment::Study::vtu`]): the
    /// alternative readings keep theirs only for [`VtuOutput::All`].
    pub vtu: VtuOutput,
}

impl TableOptions {
    /// The alternative readings run beside `experiment`, those that may turn out not to apply
    /// included ([`AlternativeReading::applies_to`]): the runs its file asks for itself, and
    /// the thesis's readings where the experiment wants them
    /// ([`crate::experiment::Study::readings`]); none with `report --no-alternatives`.
    pub fn readings(&self, experiment: &Experiment) -> Vec<AlternativeReading> {
        if !self.alternatives {
            return Vec::new();
        }
        alternative_readings(experiment)
            .into_iter()
            .filter(|reading| reading.asked || experiment.study.readings)
            .collect()
    }

    /// The solves of a table, its readings' included, for progress bars: those of one run times
    /// the runs.
    pub fn solves(&self, experiment: &Experiment) -> u64 {
        solves(experiment, self.tier) as u64 * (1 + self.readings(experiment).len() as u64)
    }
}

/// One run of a table: the experiment as written, or one of its alternative readings.
#[derive(Clone, Copy, Debug)]
pub struct TableRun<'a> {
    /// The experiment this run solves (for a reading, the experiment with that reading).
    pub experiment: &'a Experiment,
    /// The reading's suffix (`reynolds`, `z-solution`…); `None` for the table as written.
    pub suffix: Option<&'a str>,
}

impl TableRun<'_> {
    /// The run's name in progress lines: `IV.8`, or `IV.8 (reynolds)` for a reading.
    pub fn label(&self) -> String {
        match self.suffix {
            None => self.experiment.table.clone(),
            Some(suffix) => format!("{} ({suffix})", self.experiment.table),
        }
    }

    /// The table id of the run's result and data files: `IV.8`, or `IV.8.reynolds` for a
    /// reading.
    pub fn table(&self) -> String {
        match self.suffix {
            None => self.experiment.table.clone(),
            Some(suffix) => format!("{}.{suffix}", self.experiment.table),
        }
    }
}

/// The solves of one run, as [`TableHost::isolate`] is handed them: called once with the
/// progress callback of the run.
pub type Solves<'a> = &'a dyn Fn(Progress) -> Result<RunResult, RunError>;

/// What the caller of [`run_table`] does around each run of a table.
pub trait TableHost {
    /// Why a run has no result, as the caller records it.
    type Failure;

    /// Run `solves`, the solves of `run`, which start now, so that nothing in them can stop
    /// the caller: an error of the study and a panic alike become a failure. The caller hands
    /// them the progress callback of the run.
    fn isolate(&self, run: TableRun, solves: Solves) -> Result<RunResult, Self::Failure>;

    /// Keep the finished result of `run` (its data files are written here, before the next
    /// run starts); a result that cannot be kept is a failure like a run that failed.
    fn keep(&self, run: TableRun, result: RunResult) -> Result<RunResult, Self::Failure>;
}

/// The run of an alternative reading that applied, or why it has no result.
pub struct ReadingOutcome<F> {
    /// What the reading changes, for the page's heading.
    pub label: String,
    pub outcome: Result<RunResult, F>,
}

/// The runs of a table whose run as written finished.
pub struct TableOutcome<F> {
    /// The table as written, with its cost study and the notes of the readings that were not
    /// run.
    pub run: RunResult,
    /// The readings that applied, in the order of [`alternative_readings`].
    pub alternatives: Vec<ReadingOutcome<F>>,
}

/// The runs of one table: the experiment as written, then (unless `options.alternatives` is
/// off) the cost of accuracy of its scene and each alternative reading that applies to the
/// result. A reading of the cavitation model that does not apply — the cavitation never
/// switched on — is not run (it would repeat the table); a note of the table says so. A reading
/// does not measure its true error ([`crate::experiment::Study::true_error`]). Each run
/// goes through `host` ([`TableHost::isolate`], then [`TableHost::keep`]); a table whose run as
/// written fails has no readings, and that failure is the result.
pub fn run_table<H: TableHost>(
    experiment: &Experiment,
    options: TableOptions,
    host: &H,
) -> Result<TableOutcome<H::Failure>, H::Failure> {
    let TableOptions { tier, budget, .. } = options;
    // The comparison of the linearised Signorini solutions with the converged ones is part of
    // what `--no-alternatives` leaves out, and no reading repeats it.
    let mut experiment = experiment.clone();
    experiment.study.signorini_comparison &= options.alternatives;
    experiment.study.vtu = options.vtu;
    let experiment = &experiment;
    let mut readings = options.readings(experiment);
    for reading in &mut readings {
        reading.experiment.study.signorini_comparison = false;
        reading.experiment.study.true_error = false;
        if options.vtu != VtuOutput::All {
            reading.experiment.study.vtu = VtuOutput::None;
        }
    }
    let written = TableRun {
        experiment,
        suffix: None,
    };
    let run = host.isolate(written, &|progress| {
        run_within(experiment, tier, budget, progress)
    })?;
    let run = if options.alternatives {
        with_uniform(experiment, budget, with_costs(experiment, run))
    } else {
        run
    };
    let mut run = host.keep(written, run)?;
    let mut alternatives = Vec::new();
    for alt in readings {
        if !alt.applies_to(&run) {
            run.notes.push(format!(
                "Alternative reading not run: {} — the cavitation model never switched on, so \
                 it would repeat the table.",
                alt.label
            ));
            continue;
        }
        let reading = TableRun {
            experiment: &alt.experiment,
            suffix: Some(&alt.suffix),
        };
        let outcome = host
            .isolate(reading, &|progress| {
                run_within(&alt.experiment, tier, budget, progress)
            })
            .and_then(|mut result| {
                result.table = reading.table();
                host.keep(reading, result)
            });
        alternatives.push(ReadingOutcome {
            label: alt.label,
            outcome,
        });
    }
    Ok(TableOutcome { run, alternatives })
}

/// The run with the cost-of-accuracy study of its scene, where it applies
/// ([`cost::applies`]); a study that fails is a warning of the table, not a failure.
fn with_costs(experiment: &Experiment, mut run: RunResult) -> RunResult {
    if cost::applies(experiment) {
        match cost::accuracy_costs(experiment) {
            Ok(costs) => run.costs = costs,
            Err(e) => run.warnings.push(format!("cost of accuracy: {e}")),
        }
    }
    run
}

/// The run with the uniform run of its scene, where it applies ([`uniform::applies`]); a
/// uniform run that fails is a warning of the table, not a failure.
fn with_uniform(experiment: &Experiment, budget: Budget, mut run: RunResult) -> RunResult {
    if uniform::applies(experiment, &run) {
        match uniform::uniform_run(experiment, &run, budget) {
            Ok(rows) => run.uniform = rows,
            Err(e) => run.warnings.push(format!("uniform refinement: {e}")),
        }
    }
    run
}
