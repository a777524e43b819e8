//! The study: one loop for every table (docs/architecture.md, "Data flow"), deal.II step-6 style —
//! setup → assemble → solve → estimate → record → adapt. What differs between table families
//! lives in two places: the [`Problem`] (what is assembled and solved, which columns it produces)
//! and the [`Adaptation`] (what changes between cycles). A new family is a new problem or a new
//! strategy, never a new branch inside the loop.
//!
//! Only the effects a scene names are built: an elasticity scene never touches contact or
//! thin-film code.

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
pub mod readings;
pub mod record;
pub mod reynolds;
pub mod solver_iterations;
pub mod substokes;
pub mod table;
pub mod thin_film;
pub mod transfer;
pub mod warnings;

pub use adapt::{Adaptation, Balanced, FixedNumber, GridIndicator, LoadSteps, ModelMarking};
pub use budget::{Budget, Ledger};
pub use clock::{Phase, PhaseClock};
pub use error::StudyError;
pub use problem::{Discretisation, Estimate, Models, Pictures, Problem, Solution};
pub use readings::{alternative_readings, AlternativeReading};
pub use table::{run_table, TableHost, TableOptions, TableOutcome, TableRun};

use crate::experiment::{self, Experiment, StudyKind};
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
        let mut result = run_study_of_kind(experiment, tier, budget, progress)?;
        result.parameters = experiment.parameters.clone();
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
    if experiment.study.kind == StudyKind::SolverIterations {
        return solver_iterations::run(experiment, tier, progress);
    }
    feasible(experiment)?;
    budget.admit_run(experiment, Schedule::of(experiment, tier))?;
    let mut problem =
        build_problem(experiment).map_err(|e| RunError::at_cycle(&experiment.table, 0, e))?;
    let mut adaptation = adaptation_of(experiment);
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
/// reaching into the body where it is clamped). The loader checks what the file alone says;
/// this needs the models.
fn feasible(experiment: &Experiment) -> Result<(), RunError> {
    let problem = match &experiment.problem {
        experiment::Problem::Contact {
            elasticity,
            contact,
        } => contact::infeasible_obstacle(elasticity, contact, &experiment.scene.domain),
        experiment::Problem::Elasticity(_)
        | experiment::Problem::Reynolds(_)
        | experiment::Problem::SubStokes(_)
        | experiment::Problem::StokesChannel(_)
        | experiment::Problem::FilmModels { .. } => None,
    };
    match problem {
        Some(message) => Err(RunError::at_cycle(
            &experiment.table,
            0,
            StudyError::InfeasibleObstacle(message).context("before the first solve"),
        )),
        None => Ok(()),
    }
}

/// The linear solver of an experiment's SPD systems: `[study] solver` (or `report --solver`),
/// else the one measured faster for its family — multigrid for the Reynolds films, the direct
/// solver for elasticity (its tables stay below 55 000 unknowns, where `cargo bench --bench
/// solve` measured the two equally fast, 0.085 s at 54 904 unknowns: the reference solver
/// wins the tie). The contact families always use
/// the direct solver: with the dofs of the contact vertices rotated into normal and tangential
/// components, the component-wise prolongation no longer fits and CG took 100–500 iterations,
/// growing with the mesh (IV.6–IV.17, tried). With a prolongation that rotates too
/// ([`crate::linalg::multigrid`], *Rotated frames*) it took 16–102 iterations on IV.14, still
/// growing with the mesh, the solve phases of IV.6, IV.10 and IV.14 were 1.7–4 times the direct
/// solver's, and IV.10 refined to 2 dofs more in cycle 1 (a marking tie decided otherwise; the
/// cycle-0 estimates of the two solvers are 6.5e-12 apart).
pub fn solver_of(experiment: &Experiment) -> SolverKind {
    experiment.study.solver.unwrap_or(match experiment.problem {
        experiment::Problem::Reynolds(_) => SolverKind::Multigrid,
        _ => SolverKind::Direct,
    })
}

/// The model of an experiment's problem: one match arm per model. A solver study
/// ([`StudyKind::SolverIterations`]) has no model of the study loop ([`solver_iterations`]).
pub fn build_problem(experiment: &Experiment) -> Result<Box<dyn Problem>, StudyError> {
    let domain = &experiment.scene.domain;
    Ok(match &experiment.problem {
        experiment::Problem::Elasticity(data) => Box::new(elasticity::ElasticityProblem::new(
            data,
            domain,
            solver_of(experiment),
        )),
        experiment::Problem::Contact {
            elasticity,
            contact,
        } => match experiment.study.kind {
            StudyKind::GridAdaptive => Box::new(contact::ContactProblem::new(elasticity, contact)),
            StudyKind::ModelAdaptive => Box::new(model_contact::ModelAdaptiveContact::new(
                elasticity, contact,
            )),
            StudyKind::ModelAndGridAdaptive => Box::new(
                model_contact::ModelAdaptiveContact::with_grid(elasticity, contact),
            ),
            StudyKind::LoadSteps => Box::new(model_contact::ModelAdaptiveContact::forming(
                elasticity,
                contact,
                experiment.study.lift_per_step.unwrap_or(0.0),
            )),
            StudyKind::SolverIterations => {
                return Err("contact has no solver-iterations study".into())
            }
        },
        experiment::Problem::Reynolds(data) => Box::new(reynolds::ReynoldsFilm::new(
            data,
            domain,
            solver_of(experiment),
        )),
        experiment::Problem::SubStokes(data) => {
            Box::new(substokes::SubStokesFilm::new(data, domain))
        }
        experiment::Problem::StokesChannel(_) => {
            return Err("the Uzawa test problem runs as a solver-iterations study only".into())
        }
        experiment::Problem::FilmModels { substokes, .. } => {
            Box::new(model_fluid::ModelAdaptiveFilm::new(substokes, domain))
        }
    })
}

/// The adaptation of an experiment: the model-adaptive film's marking ([`model_fluid::marking`]),
/// else the strategy of its `[study] kind` ([`build_adaptation`]).
pub fn adaptation_of(experiment: &Experiment) -> Box<dyn Adaptation> {
    match experiment.problem {
        experiment::Problem::FilmModels { .. } => Box::new(model_fluid::marking(&experiment.study)),
        _ => build_adaptation(&experiment.study, &experiment.scene),
    }
}

/// The adaptation strategy of a study: one match arm per `[study] kind`.
pub fn build_adaptation(
    study: &experiment::Study,
    scene: &experiment::Scene,
) -> Box<dyn Adaptation> {
    let grid = FixedNumber {
        refine: study.refine(),
        coarsen: study.coarsen(),
        ties: study.ties,
    };
    // The loader requires `algorithm` in the studies that mark models; III.3 is the one the
    // model-and-grid tables use.
    let (refine, coarsen) = study.model_fractions();
    let model = ModelMarking {
        algorithm: study
            .algorithm
            .unwrap_or(experiment::ModelAlgorithm::SortedError),
        refine,
        coarsen,
        tolerance: study.model_tolerance(),
    };
    let balanced = Balanced {
        model,
        grid,
        alpha: study.balance(),
        grid_indicator: GridIndicator::Eta,
    };
    match study.kind {
        StudyKind::GridAdaptive | StudyKind::SolverIterations => Box::new(balanced.grid),
        StudyKind::ModelAdaptive => Box::new(balanced.model),
        StudyKind::ModelAndGridAdaptive => Box::new(balanced),
        StudyKind::LoadSteps => Box::new(LoadSteps::new(
            study.cycles_per_row(),
            balanced,
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
    Ok(table.record.finish(problem))
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
