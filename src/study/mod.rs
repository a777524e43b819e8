//! The study: one loop for every table (docs/architecture.md, "Data flow"), deal.II step-6 style —
//! setup → assemble → solve → estimate → record → adapt. What differs between table families
//! lives in two places: the [`Problem`] (what is assembled and solved, which columns it produces)
//! and the [`Adaptation`] (what changes between cycles), both made by the experiment's family
//! ([`crate::family`]). A new family is a new problem or a new strategy, never a new branch
//! inside the loop.
//!
//! Only the effects a scene names are built: an elasticity scene never touches contact or
//! thin-film code.

pub mod accuracy;
pub mod adapt;
pub mod budget;
pub mod clock;
pub mod contact;
pub mod cost;
pub mod elasticity;
pub mod error;
pub mod model_contact;
pub mod model_fluid;
pub mod problem;
pub mod quantities;
pub mod readings;
pub mod record;
pub mod reference;
pub mod reynolds;
pub mod signorini;
pub mod solver_iterations;
pub mod substokes;
pub mod table;
pub mod thin_film;
pub mod transfer;
pub mod uniform;
pub mod warnings;

pub use adapt::{Adaptation, Balanced, FixedNumber, GridIndicator, LoadSteps, ModelMarking};
pub use budget::{Budget, Ledger};
pub use clock::{Phase, PhaseClock};
pub use error::StudyError;
pub use problem::{
    Discretisation, Estimate, KeptSolve, Models, Pictures, Problem, ReferenceErrors, Solution,
};
pub use readings::{alternative_readings, AlternativeReading};
pub use table::{run_table, TableHost, TableOptions, TableOutcome, TableRun};

use crate::experiment::{self, Experiment, Plan, StudyKind};
use crate::fe;
use crate::linalg::SolverKind;
use crate::results::{PhaseSeconds, RunResult};
use record::Recorder;

/// Which rows to compute: the quick tier of the tests or the full thesis sizes of the report.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tier {
    Quick,
    Full,
}

impl Tier {
    pub fn name(self) -> &'static str {
        match self {
            Tier::Quick => "quick",
            Tier::Full => "full",
        }
    }
}

/// A run that could not finish: names the table, the cycle (and the load step) and the reason.
#[derive(Debug, thiserror::Error)]
#[error(
    "table {table}, {}cycle {cycle}: {cause}",
    step.map_or(String::new(), |j| format!("load step {j}, "))
)]
pub struct RunError {
    pub table: String,
    /// The printed cycle; in a load-step study the cycle within the step.
    pub cycle: usize,
    /// The load step of a load-step study.
    pub step: Option<usize>,
    /// Why: the kind of failure, its text the end of the message.
    pub cause: StudyError,
}

impl RunError {
    /// An error of `table` in printed cycle `cycle` (no load steps).
    pub fn at_cycle(table: &str, cycle: usize, cause: impl Into<StudyError>) -> RunError {
        RunError {
            table: table.to_string(),
            cycle,
            step: None,
            cause: cause.into(),
        }
    }
}

/// Progress callback: (table, solves done, solves in total).
pub type Progress<'a> = &'a (dyn Fn(&str, usize, usize) + Sync);

/// Number of printed rows of a tier.
pub fn printed_rows(experiment: &Experiment, tier: Tier) -> usize {
    match tier {
        Tier::Quick => experiment.study.quick_rows,
        Tier::Full => experiment.study.rows,
    }
}

/// Number of solves of a run (the unprinted ones included), for progress bars.
pub fn solves(experiment: &Experiment, tier: Tier) -> usize {
    Schedule::of(experiment, tier).len()
}

/// One solve of a study: its number and the printed row it makes, if any.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Solve {
    pub index: usize,
    /// Printed cycle (row) of this solve; `None` for the unprinted solves before row 0 and, in
    /// a load-step study, for every cycle of a step but its last.
    pub row: Option<usize>,
    /// Whether it is the last solve (no adaptation after it).
    pub last: bool,
    /// In a load-step study: the step and the cycle within it.
    pub step: Option<(usize, usize)>,
}

impl Solve {
    /// The error of this solve in `table`, named by its cycle (0 for the unprinted solves) and
    /// its load step.
    pub fn error(&self, table: &str, cause: StudyError) -> RunError {
        if let Some((step, cycle)) = self.step {
            return RunError {
                step: Some(step),
                ..RunError::at_cycle(table, cycle, cause)
            };
        }
        match self.row {
            Some(cycle) => RunError::at_cycle(table, cycle, cause),
            None => RunError::at_cycle(
                table,
                0,
                cause.context(format!("unprinted solve {} before row 0", self.index + 1)),
            ),
        }
    }
}

/// The solves of a study: `unprinted` silent ones, then `per_row` solves for each printed row
/// of the tier (the cycles of a load step; 1 in every other study), the row made by the last.
#[derive(Clone, Copy, Debug)]
pub struct Schedule {
    pub unprinted: usize,
    pub printed: usize,
    pub per_row: usize,
}

impl Schedule {
    pub fn of(experiment: &Experiment, tier: Tier) -> Schedule {
        Schedule {
            unprinted: experiment.study.unprinted_cycles,
            printed: printed_rows(experiment, tier),
            per_row: experiment.study.cycles_per_row(),
        }
    }

    /// Number of solves.
    pub fn len(&self) -> usize {
        self.unprinted + self.printed * self.per_row
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn solves(self) -> impl Iterator<Item = Solve> {
        (0..self.len()).map(move |index| {
            let printed = index.checked_sub(self.unprinted);
            let (row, step) = match printed {
                None => (None, None),
                Some(k) if self.per_row == 1 => (Some(k), None),
                Some(k) => {
                    let (step, cycle) = (k / self.per_row, k % self.per_row);
                    let row = (cycle + 1 == self.per_row).then_some(step);
                    (row, Some((step, cycle)))
                }
            };
            Solve {
                index,
                row,
                last: index + 1 == self.len(),
                step,
            }
        })
    }
}

/// Run one experiment: build its problem and its adaptation, then the study loop.
pub fn run(experiment: &Experiment, tier: Tier, progress: Progress) -> Result<RunResult, RunError> {
    run_within(experiment, tier, Budget::machine(), progress)
}

/// [`run`] with a memory budget other than the machine's memory.
///
/// The study runs on a thread of rayon's pool (`rayon::scope`): the parallel loops of its
/// solvers then split their work from inside the pool, a push on the thread's own queue, instead
/// of handing each loop to the pool from outside and sleeping until it is done — tens of
/// microseconds per loop, and a multigrid cycle runs several loops per level. The results are
/// the same: every loop has a fixed order of summation whatever thread runs which part.
pub fn run_within(
    experiment: &Experiment,
    tier: Tier,
    budget: Budget,
    progress: Progress,
) -> Result<RunResult, RunError> {
    rayon::scope(|_| {
        let _limit = budget.limit_solvers();
        let mut result =
            run_study_of_kind(experiment, tier, budget, progress).map_err(Budget::refusal)?;
        result.parameters = experiment.parameters.clone();
        result.sweep = experiment.sweep.clone();
        Ok(result)
    })
}

/// [`run_within`] by the study's kind: a solver study, or the adaptive loop of a problem.
fn run_study_of_kind(
    experiment: &Experiment,
    tier: Tier,
    budget: Budget,
    progress: Progress,
) -> Result<RunResult, RunError> {
    if experiment.study.kind() == StudyKind::SolverIterations {
        return solver_iterations::run(experiment, tier, progress);
    }
    feasible(experiment, tier)?;
    budget.admit_run(experiment, Schedule::of(experiment, tier))?;
    let family = experiment.family;
    let mut problem = family
        .build(experiment)
        .map_err(|e| RunError::at_cycle(&experiment.table, 0, e))?;
    let mut adaptation = family.adaptation(experiment);
    run_study(
        experiment,
        tier,
        budget,
        progress,
        &mut *problem,
        &mut *adaptation,
    )
}

/// Reject, before the first solve, a scene whose problem has no solution (contact: an obstacle
/// reaching into the body where it is clamped; [`crate::family::Family::infeasible`]).
fn feasible(experiment: &Experiment, tier: Tier) -> Result<(), RunError> {
    let rows = printed_rows(experiment, tier);
    match experiment.family.infeasible(experiment, rows) {
        Some(infeasible) => Err(RunError {
            step: infeasible.step,
            ..RunError::at_cycle(
                &experiment.table,
                0,
                StudyError::InfeasibleObstacle(infeasible.message)
                    .context("before the first solve"),
            )
        }),
        None => Ok(()),
    }
}

/// The linear solver of an experiment's SPD systems: `[study] solver` (or `report --solver`),
/// else the one measured faster for its family ([`crate::family::Family::default_solver`]).
pub fn solver_of(experiment: &Experiment) -> SolverKind {
    experiment
        .study
        .solver
        .unwrap_or(experiment.family.default_solver())
}

/// The adaptation strategy of a study: one match arm per `[study] kind`.
pub fn build_adaptation(
    study: &experiment::Study,
    scene: &experiment::Scene,
) -> Box<dyn Adaptation> {
    let grid = |grid| FixedNumber::of(grid, study.ties).smoothed(scene.mesh_smoothing);
    let balanced = |g, model: experiment::ModelFractions, alpha| Balanced {
        model: model.into(),
        grid: grid(g),
        alpha,
        grid_indicator: GridIndicator::Eta,
    };
    match study.plan {
        Plan::GridAdaptive { grid: g, .. } => Box::new(grid(g)),
        // A solver study has no adaptive loop ([`solver_iterations`]); nothing is marked.
        Plan::SolverIterations => Box::new(grid(experiment::GridFractions {
            refine: 0.0,
            coarsen: 0.0,
        })),
        Plan::ModelAdaptive { model } => Box::new(ModelMarking::from(model)),
        Plan::ModelAndGridAdaptive {
            grid: g,
            model,
            balance,
            ..
        } => Box::new(balanced(g, model, balance)),
        Plan::LoadSteps {
            grid: g,
            model,
            balance,
            cycles_per_step,
            ..
        } => Box::new(LoadSteps::new(
            cycles_per_step,
            balanced(g, model, balance),
            scene.clone(),
        )),
    }
}

/// One solve of the study loop on `disc`: setup → assemble → solve → estimate, each phase timed
/// on `clock`; the solution and the estimate are finite or an error.
pub fn solve_and_estimate(
    problem: &mut dyn Problem,
    disc: &Discretisation,
    clock: &PhaseClock,
) -> Result<(fe::DofMap, Solution, Estimate), StudyError> {
    let mut system = clock.time(Phase::Setup, || problem.setup(disc));
    clock.time(Phase::Assemble, || problem.assemble(disc, &mut system))?;
    let solution = clock
        .time(Phase::Solve, || problem.solve(disc, &mut system, clock))
        .and_then(Solution::finite)?;
    let dofs = system.into_dofs();
    let estimate = clock.time(Phase::Estimate, || problem.estimate(disc, &dofs, &solution))?;
    estimate.finite_total()?;
    Ok((dofs, solution, estimate))
}

/// The study loop: one row per printed solve.
pub fn run_study(
    experiment: &Experiment,
    tier: Tier,
    budget: Budget,
    progress: Progress,
    problem: &mut dyn Problem,
    adaptation: &mut dyn Adaptation,
) -> Result<RunResult, RunError> {
    let schedule = Schedule::of(experiment, tier);
    let mut disc = Discretisation::initial(&experiment.scene).map_err(|e| {
        RunError::at_cycle(
            &experiment.table,
            0,
            StudyError::from(e).context("the initial mesh cannot be built"),
        )
    })?;
    let mut table = TableCycles {
        experiment,
        budget,
        progress,
        solves: schedule.len(),
        record: Recorder::new(experiment, tier, schedule.printed),
    };
    cycle_loop(
        problem,
        adaptation,
        &mut disc,
        schedule.solves(),
        &mut table,
    )
    .map_err(|(solve, cause)| solve.error(&experiment.table, cause))?;
    let last = schedule.printed.saturating_sub(1);
    table
        .record
        .finish(problem)
        .map_err(|cause| RunError::at_cycle(&experiment.table, last, cause))
}

/// What a loop over cycles does around each solve; the loop itself ([`cycle_loop`]) is the same
/// for every run: a table's ([`run_study`]: memory budget, rows, progress) and the variants of
/// the cost-of-accuracy study ([`cost`]).
pub trait CycleObserver {
    /// Before the solve on `disc`; an error stops the loop at this solve.
    fn before(&mut self, _solve: &Solve, _disc: &Discretisation) -> Result<(), StudyError> {
        Ok(())
    }

    /// The solve's result, before the problem keeps its solution.
    fn solved(
        &mut self,
        solve: &Solve,
        disc: &Discretisation,
        dofs: &fe::DofMap,
        solution: &Solution,
        estimate: &Estimate,
        problem: &mut dyn Problem,
    );

    /// The seconds of the solve's phases, after the adaptation that follows it.
    fn finished(&mut self, _solve: &Solve, _seconds: PhaseSeconds) {}
}

/// The cycle loop, deal.II step-6 style: for each of `solves`, setup → assemble → solve →
/// estimate on `disc` ([`solve_and_estimate`]), hand the result to `observer`, let the problem
/// keep its solution (the next cycle's start), and adapt `disc` unless it is the last solve. An
/// error names the solve it stopped at.
pub fn cycle_loop(
    problem: &mut dyn Problem,
    adaptation: &mut dyn Adaptation,
    disc: &mut Discretisation,
    solves: impl Iterator<Item = Solve>,
    observer: &mut dyn CycleObserver,
) -> Result<(), (Solve, StudyError)> {
    for solve in solves {
        let fail = |cause: StudyError| (solve, cause);
        observer.before(&solve, disc).map_err(fail)?;
        let clock = PhaseClock::default();
        let (dofs, solution, estimate) = solve_and_estimate(problem, disc, &clock).map_err(fail)?;
        observer.solved(&solve, disc, &dofs, &solution, &estimate, problem);
        problem.finish_cycle(disc, dofs, solution);
        if !solve.last {
            clock
                .time(Phase::Refine, || adaptation.adapt(disc, &estimate))
                .map_err(fail)?;
        }
        observer.finished(&solve, clock.seconds());
    }
    Ok(())
}

/// The cycles of a table: each admitted by the memory budget, recorded as a row, counted for
/// the progress bar.
struct TableCycles<'a> {
    experiment: &'a Experiment,
    budget: Budget,
    progress: Progress<'a>,
    solves: usize,
    record: Recorder<'a>,
}

impl CycleObserver for TableCycles<'_> {
    fn before(&mut self, _solve: &Solve, disc: &Discretisation) -> Result<(), StudyError> {
        self.budget
            .admit_cycle(self.experiment, disc.mesh.n_active())
    }

    fn solved(
        &mut self,
        solve: &Solve,
        disc: &Discretisation,
        dofs: &fe::DofMap,
        solution: &Solution,
        estimate: &Estimate,
        problem: &mut dyn Problem,
    ) {
        self.record
            .cycle(solve, disc, dofs, solution, estimate, problem);
    }

    fn finished(&mut self, solve: &Solve, seconds: PhaseSeconds) {
        self.record.seconds(solve, seconds);
        (self.progress)(&self.experiment.table, solve.index + 1, self.solves);
    }
}
