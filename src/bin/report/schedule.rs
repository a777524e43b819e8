//! The tables run side by side: a queue of tables taken by `--jobs` workers, each table started
//! only when its predicted memory fits beside the tables running ([`study::Ledger`]), its runs
//! ([`study::run_table`]) isolated from panics and shown on the progress display. Each table's
//! solves stay as they are, so the results do not depend on how many run at once; the outcomes
//! keep the order of the files.

use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use tribo::experiment::{self, Experiment};
use tribo::linalg::SolverKind;
use tribo::report::{self, Alternative, Failure, FailureKind};
use tribo::results::RunResult;
use tribo::study::{self, table::Solves, TableHost, TableOptions, TableRun, Tier};
use tribo::thesis::ThesisTable;

use crate::folder::PendingPage;
use crate::isolate::run_isolated;
use crate::outputs::{write_data, Outcome};
use crate::progress::ProgressDisplay;

/// How the tables of a report run.
pub struct Settings<'a> {
    /// The output folder: each table's data files are written as its runs finish.
    pub out: &'a Path,
    pub options: TableOptions,
    /// `--solver`: the linear solver of every table, overriding the experiments'.
    pub solver: Option<SolverKind>,
    /// `--jobs`: tables at once (by default [`default_jobs`]).
    pub jobs: Option<usize>,
    pub no_progress: bool,
    /// When the report started.
    pub started: Instant,
    /// The page that says which tables are pending until the report is written.
    pub page: &'a PendingPage,
    /// Which tables ran at the same time (the page marks their seconds).
    pub overlap: report::Overlap,
}

/// Run every loaded table (and record each file that did not load as a failure); the outcomes
/// in the order of `loaded`.
pub fn run_tables(loaded: Vec<experiment::Loaded>, settings: &Settings) -> Vec<Outcome> {
    let options = settings.options;
    let total_cycles: u64 = loaded
        .iter()
        .filter_map(|(_, loaded)| loaded.as_ref().ok())
        .map(|s| options.solves(s))
        .sum();
    let display = ProgressDisplay::new(settings.no_progress, total_cycles, settings.started);
    // Never more workers than tables: each is a thread, and `--jobs` may be any number.
    let jobs = settings
        .jobs
        .unwrap_or_else(|| default_jobs(&loaded, options.tier, options.budget))
        .min(loaded.len())
        .max(1);
    let ledger = study::Ledger::new(options.budget);
    let queue = Mutex::new(loaded.into_iter().enumerate());
    let finished: Mutex<Vec<(usize, Outcome)>> = Mutex::new(Vec::new());
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            scope.spawn(|| loop {
                let next = queue.lock().expect("queue").next();
                let Some((index, entry)) = next else {
                    break;
                };
                let outcome = run_one(entry, settings, &ledger, &display);
                finished.lock().expect("outcomes").push((index, outcome));
                settings.page.finished(index);
            });
        }
    });
    let mut finished = finished.into_inner().expect("outcomes");
    finished.sort_by_key(|f| f.0);
    display.finish();
    finished.into_iter().map(|f| f.1).collect()
}

/// Tables at once by default: one per core, as many as the memory budget holds of the largest
/// predicted table ([`study::Budget::predicted_peak`]).
fn default_jobs(loaded: &[experiment::Loaded], tier: Tier, budget: study::Budget) -> usize {
    let largest = loaded
        .iter()
        .filter_map(|(_, l)| l.as_ref().ok())
        .map(|e| study::Budget::predicted_peak(e, study::Schedule::of(e, tier)))
        .fold(0.0f64, f64::max);
    let by_memory = if largest > 0.0 {
        (budget.bytes / largest).floor() as usize
    } else {
        usize::MAX
    };
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    cores.min(by_memory).max(1)
}

/// One table of the queue: the earlier output of its stem removed, then (when its file loaded)
/// its runs, once its predicted memory fits beside the tables running.
fn run_one(
    entry: experiment::Loaded,
    settings: &Settings,
    ledger: &study::Ledger,
    display: &ProgressDisplay,
) -> Outcome {
    let spec = match ready(entry, settings) {
        Ok(spec) => spec,
        Err(failure) => {
            display.failure(&failure);
            return Outcome::Failed(failure);
        }
    };
    let options = settings.options;
    // Wait until the table's predicted memory fits beside the tables running.
    let _memory = ledger.reserve(study::Budget::predicted_peak(
        &spec,
        study::Schedule::of(&spec, options.tier),
    ));
    let host = Host {
        out: settings.out,
        display,
        counted: AtomicU64::new(0),
    };
    let _running = settings.overlap.enter(&spec.table);
    let outcome = match study::run_table(&spec, options, &host) {
        Ok(table) => Outcome::Done {
            run: Box::new(table.run),
            thesis: ThesisTable::of(&spec),
            alternatives: table
                .alternatives
                .into_iter()
                .map(|a| Alternative {
                    label: a.label,
                    outcome: a.outcome,
                })
                .collect(),
        },
        Err(failure) => Outcome::Failed(failure),
    };
    // The readings that did not run, and the cycles a failed run did not reach, count as done.
    display.advance(&host.counted, options.solves(&spec));
    outcome
}

/// The experiment of a table, with `--solver` applied, once nothing of an earlier run of its
/// stem stays behind (whatever happens next); or why the table cannot run.
fn ready((stem, loaded): experiment::Loaded, settings: &Settings) -> Result<Experiment, Failure> {
    let out = settings.out;
    let removed = report::remove_outputs(out, &stem).map_err(|e| {
        format!(
            "cannot remove the earlier output of {stem} from {}: {e}",
            out.display()
        )
    });
    let failure = |kind, message| Failure {
        table: stem.clone(),
        title: None,
        section: None,
        kind,
        cycle: None,
        message,
    };
    match (loaded, removed) {
        (Ok(mut spec), Ok(_)) => {
            if let Some(solver) = settings.solver {
                spec.study.solver = Some(solver);
            }
            Ok(spec)
        }
        (Err(e), _) => Err(failure(FailureKind::NotLoaded, e.to_string())),
        (Ok(_), Err(message)) => Err(failure(FailureKind::Error, message)),
    }
}

/// The report's side of a table's runs: each run isolated from panics with its progress shown,
/// each result's data written as it finishes, failures and the table's warnings on stderr as
/// they happen.
struct Host<'a> {
    out: &'a Path,
    display: &'a ProgressDisplay,
    /// The table's cycles shown as done, all its runs together.
    counted: AtomicU64,
}

impl TableHost for Host<'_> {
    type Failure = Failure;

    fn isolate(&self, run: TableRun, solves: Solves) -> Result<RunResult, Failure> {
        let spec = run.experiment;
        self.display.running(match run.suffix {
            None => format!("{} {}", spec.table, spec.title),
            Some(suffix) => format!("{} {} ({suffix})", spec.table, spec.title),
        });
        let label = run.label();
        // A reading's cycles count on from those of the runs before it.
        let base = self.counted.load(Ordering::Relaxed);
        let progress = |_: &str, done: usize, total: usize| {
            self.display.advance(&self.counted, base + done as u64);
            self.display.cycle_done(&label, done, total);
        };
        let result = run_isolated(spec, || solves(&progress));
        if let Err(failure) = &result {
            // What the file's data make suspicious often explains the failure (an unresolved
            // gap, a film too thin for double precision): printed before it.
            if run.suffix.is_none() {
                for w in spec.warnings() {
                    self.display
                        .print(&format!("warning: table {}: {w}", spec.table));
                }
            }
            self.display.failure(failure);
        }
        result
    }

    fn keep(&self, run: TableRun, result: RunResult) -> Result<RunResult, Failure> {
        let kept = write_data(self.out, run.experiment, result);
        match &kept {
            Ok(result) if run.suffix.is_none() => {
                for w in &result.warnings {
                    let table = &run.experiment.table;
                    self.display.print(&format!("warning: table {table}: {w}"));
                }
            }
            Ok(_) => {}
            Err(failure) => self.display.failure(failure),
        }
        kept
    }
}
