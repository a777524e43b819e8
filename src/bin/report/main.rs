//! `cargo run --release --bin report` — run every experiment file and render the report.
//!
//! Writes `report/index.html`, `report/figures/*.svg`, `report/data/<table>.csv` and
//! `report/data/<table>.probes.csv` (each also as `.parquet`), `<table>.joined.*` (the rows
//! beside the printed table) and `<table>.vtu` (the last mesh). Each table runs on its own: a file that does not load, a run
//! that fails and a run that panics each become a failed entry of the page (in the summary with
//! its status, and in a section with the table, the cycle and the message); the other tables are
//! still reported, and the exit status is 1. Usage errors, an experiment folder that cannot be
//! listed and an output folder that cannot be written end the program before anything is solved,
//! with exit status 2.
//!
//! Every run also writes `report/shard/<table>.json`, the record of each entry
//! ([`tribo::report::record`]). `report merge DIR… --out DIR` builds one page, its figures and
//! its data files from the records of several output folders, as a single run of all their
//! tables would (timings and the header aside): the tables can run as separate processes, on
//! one machine or a cluster, and be merged afterwards. Its exit status is 1 when a merged entry
//! failed, 2 when the shards cannot be merged (a folder without records, a table in two folders,
//! a record that cannot be read).

use std::io::IsTerminal;
use std::panic::{self, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicU64, Ordering as AtomicOrdering};
use std::sync::Mutex;
use std::time::Instant;

use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};

use tribo::experiment::{self, Experiment};
use tribo::report::record::{self, Record, RecordEntry};
use tribo::report::{self, data, Alternative, Entry, Failure, FailureKind, ReportMeta, Section};
use tribo::results::RunResult;
use tribo::study::{self, Tier};
use tribo::thesis::ThesisTable;

/// Regenerate the Chapter IV tables of Gimbel (2012) and render them beside the thesis tables.
#[derive(Parser, Debug)]
#[command(
    name = "report",
    version,
    about,
    args_conflicts_with_subcommands = true
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,

    /// Only these tables, comma-separated (e.g. `--only IV.1,IV.3`).
    #[arg(long, value_delimiter = ',', value_name = "TABLES")]
    only: Option<Vec<String>>,

    /// Run the quick (test) tier instead of the full thesis sizes.
    #[arg(long)]
    quick: bool,

    /// Directory of experiment files.
    #[arg(long, value_name = "DIR", default_value = "experiments")]
    experiments: PathBuf,

    /// Output directory.
    #[arg(long, value_name = "DIR", default_value = "report")]
    out: PathBuf,

    /// Do not show progress. By default a terminal shows a bar with the time left, and
    /// anything else (a log file, CI) gets one line per finished cycle.
    #[arg(long)]
    no_progress: bool,

    /// Do not run the alternative readings beside the experiments (the cavitation tables are
    /// otherwise run three times: printed, self-consistent and `reynolds` source R₃c).
    #[arg(long)]
    no_alternatives: bool,

    /// Also write the shard records (`<out>/shard/<table>.json`, everything the page needs,
    /// mesh pictures included) that `report merge` builds one page from. Off by default: the
    /// records of a full report take gigabytes.
    #[arg(long)]
    shard: bool,

    /// Tables run at once (default: one per core, fewer where the memory budget does not hold
    /// the largest predicted tables side by side). Whatever the number, a table starts only
    /// when its predicted memory fits beside the tables running. The results do not depend on
    /// it.
    #[arg(long, value_name = "N")]
    jobs: Option<usize>,

    /// Linear solver of the SPD problems of the Reynolds (with and without cavitation) and
    /// elasticity tables, overriding the experiments' `[study] solver`: `direct` (sparse
    /// Cholesky) or `multigrid` (CG with a geometric multigrid V-cycle); the contact tables
    /// always use the direct solver. The solver changes the run time, not the results.
    #[arg(long, value_enum, value_name = "SOLVER")]
    solver: Option<tribo::linalg::SolverKind>,

    /// Memory a table may use, e.g. `4G` or `1500M` (default: the machine's memory). A table
    /// predicted to need more is refused before its first solve, naming the cycle.
    #[arg(long, value_name = "SIZE", value_parser = study::Budget::parse)]
    memory_budget: Option<study::Budget>,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Build one page from the output folders of separate runs (shards): the page, figures and
    /// data of all their tables, as one run of them all would write them.
    Merge {
        /// Output folders of earlier runs, each with its records in `shard/`.
        #[arg(required = true, value_name = "SHARD")]
        shards: Vec<PathBuf>,

        /// Output directory of the merged page.
        #[arg(long, value_name = "DIR", default_value = "report")]
        out: PathBuf,
    },
}

/// Testing hook: when this environment variable holds a table id, the run of that table panics
/// just before it starts, so that the tests can check that a panic is isolated to its table.
/// Nothing else reads it.
const TEST_PANIC_VARIABLE: &str = "TRIBO_TEST_PANIC";

fn main() -> ExitCode {
    // Freed memory stays for the next cycle (tribo::heap): fewer page faults, same numbers.
    tribo::heap::keep_freed_memory();
    let cli = Cli::parse();
    install_panic_hook();
    let done = match &cli.command {
        Some(Command::Merge { shards, out }) => merge(shards, out),
        None => run(&cli),
    };
    match done {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::from(2)
        }
    }
}

/// How one table ended: its section's data, or why there is none. (The run is boxed: it is
/// large beside a failure.)
enum Outcome {
    Done {
        run: Box<RunResult>,
        thesis: ThesisTable,
        alternatives: Vec<Alternative>,
    },
    Failed(Failure),
}

/// Returns Ok(false) when some table failed (the others are still reported).
fn run(cli: &Cli) -> Result<bool, String> {
    let started = Instant::now();
    let provenance = report::provenance::Provenance::collect(
        std::env::args(),
        Path::new(env!("CARGO_MANIFEST_DIR")),
    );
    let only: Option<Vec<String>> = cli.only.as_ref().map(|v| {
        v.iter()
            .map(|s| s.trim().to_string())
            .filter(|s| !s.is_empty())
            .collect()
    });
    if matches!(&only, Some(v) if v.is_empty()) {
        return Err("--only needs at least one table id, e.g. --only IV.1,IV.3".into());
    }
    let loaded =
        experiment::load_each(&cli.experiments, only.as_deref()).map_err(|e| e.to_string())?;
    if loaded.is_empty() {
        return Err(format!(
            "no experiment files (*.toml) in {}",
            cli.experiments.display()
        ));
    }
    report::prepare_output(&cli.out)
        .and_then(|()| record::clear(&cli.out))
        .map_err(|e| format!("cannot write the report into {}: {e}", cli.out.display()))?;

    let tier = if cli.quick { Tier::Quick } else { Tier::Full };
    let budget = cli.memory_budget.unwrap_or_else(study::Budget::machine);
    let readings_of = |s: &Experiment| {
        if cli.no_alternatives {
            Vec::new()
        } else {
            study::alternative_readings(s)
        }
    };
    let cycles = |s: &Experiment| study::solves(s, tier) as u64;
    let total_cycles: u64 = loaded
        .iter()
        .filter_map(|(_, loaded)| loaded.as_ref().ok())
        .map(|s| cycles(s) * (1 + readings_of(s).len() as u64))
        .sum();
    // A bar in a terminal; elsewhere (a log file, CI) one line per finished cycle.
    let lines = !cli.no_progress && !std::io::stderr().is_terminal();
    let bar = if cli.no_progress || lines {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(total_cycles)
    };
    bar.set_style(
        ProgressStyle::with_template(
            "{elapsed_precise} [{bar:30}] {pos}/{len} cycles, about {eta} left  {msg}",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    let cycle_done = |table: &str, done: usize, total: usize| {
        if lines && done > 0 {
            eprintln!(
                "[{:>7.1} s] {table}: cycle {done} of {total} done",
                started.elapsed().as_secs_f64()
            );
        }
    };
    let report_failure = |f: &Failure| {
        bar.suspend(|| eprintln!("{}: {}", f.kind.name(), f.message));
    };

    // Tables run side by side (each one's solves stay as they are, so the results do not
    // depend on how many run at once); the outcomes keep the order of the files.
    let jobs = cli
        .jobs
        .unwrap_or_else(|| default_jobs(&loaded, tier, budget))
        .max(1);
    let ledger = study::Ledger::new(budget);
    let stems: Vec<String> = loaded.iter().map(|(stem, _)| stem.clone()).collect();
    let queue = Mutex::new(loaded.into_iter().enumerate());
    let finished: Mutex<Vec<(usize, Outcome, usize)>> = Mutex::new(Vec::new());
    // Progress counts the cycles each table has finished, whatever order they finish in.
    let advance = |counted: &AtomicU64, done: u64| {
        let before = counted.fetch_max(done, AtomicOrdering::Relaxed);
        if done > before {
            bar.inc(done - before);
        }
    };
    let run_one = |(stem, loaded): experiment::Loaded| -> (Outcome, usize) {
        let mut failed = 0;
        // Whatever happens below, nothing of an earlier run of this table may stay behind.
        let removed = report::remove_outputs(&cli.out, &stem).map_err(|e| {
            format!(
                "cannot remove the earlier output of {stem} from {}: {e}",
                cli.out.display()
            )
        });
        let ready = match (loaded, removed) {
            (Ok(mut spec), Ok(_)) => {
                if let Some(solver) = cli.solver {
                    spec.study.solver = Some(solver);
                }
                Ok(spec)
            }
            (Err(e), _) => Err((FailureKind::NotLoaded, e.to_string())),
            (Ok(_), Err(message)) => Err((FailureKind::Error, message)),
        };
        let spec = match ready {
            Ok(spec) => spec,
            Err((kind, message)) => {
                let failure = Failure {
                    table: stem,
                    title: None,
                    section: None,
                    kind,
                    cycle: None,
                    message,
                };
                report_failure(&failure);
                failed += 1;
                return (Outcome::Failed(failure), failed);
            }
        };
        // Wait until the table's predicted memory fits beside the tables running.
        let _memory = ledger.reserve(study::Budget::predicted_peak(
            &spec,
            study::Schedule::of(&spec, tier),
        ));
        bar.set_message(format!("{} {}", spec.table, spec.title));
        let readings = readings_of(&spec);
        let runs_of_spec = 1 + readings.len() as u64;
        let counted = AtomicU64::new(0);
        let progress = |_: &str, done: usize, total: usize| {
            advance(&counted, done as u64);
            cycle_done(&spec.table, done, total);
        };
        let outcome = match run_isolated(&spec, tier, budget, &progress)
            .map(|run| {
                if cli.no_alternatives {
                    run
                } else {
                    with_costs(&spec, run)
                }
            })
            .and_then(|run| write_data(&cli.out, &spec, run))
        {
            Ok(mut run) => {
                for w in &run.warnings {
                    bar.suspend(|| eprintln!("warning: table {}: {w}", spec.table));
                }
                let mut alternatives = Vec::new();
                for alt in readings {
                    if !alt.applies_to(&run) {
                        run.notes.push(format!(
                            "Alternative reading not run: {} — the cavitation model never \
                             switched on, so it would repeat the table.",
                            alt.label
                        ));
                        continue;
                    }
                    bar.set_message(format!("{} {} ({})", spec.table, spec.title, alt.suffix));
                    let label = format!("{} ({})", spec.table, alt.suffix);
                    let base = counted.load(AtomicOrdering::Relaxed);
                    let progress = |_: &str, done: usize, total: usize| {
                        advance(&counted, base + done as u64);
                        cycle_done(&label, done, total);
                    };
                    let outcome = run_isolated(&alt.experiment, tier, budget, &progress).and_then(
                        |mut run| {
                            run.table = format!("{}.{}", spec.table, alt.suffix);
                            write_data(&cli.out, &alt.experiment, run)
                        },
                    );
                    if let Err(f) = &outcome {
                        report_failure(f);
                        failed += 1;
                    }
                    alternatives.push(Alternative {
                        label: alt.label,
                        outcome,
                    });
                }
                Outcome::Done {
                    run: Box::new(run),
                    thesis: ThesisTable::of(&spec),
                    alternatives,
                }
            }
            Err(f) => {
                report_failure(&f);
                failed += 1;
                Outcome::Failed(f)
            }
        };
        advance(&counted, cycles(&spec) * runs_of_spec);
        (outcome, failed)
    };
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            scope.spawn(|| loop {
                let next = queue.lock().expect("queue").next();
                let Some((index, entry)) = next else {
                    break;
                };
                let (outcome, failed) = run_one(entry);
                finished
                    .lock()
                    .expect("outcomes")
                    .push((index, outcome, failed));
            });
        }
    });
    let mut finished = finished.into_inner().expect("outcomes");
    finished.sort_by_key(|f| f.0);
    let failed: usize = finished.iter().map(|f| f.2).sum();
    let outcomes: Vec<Outcome> = finished.into_iter().map(|f| f.1).collect();
    bar.finish_and_clear();

    let entries: Vec<Entry> = outcomes
        .iter()
        .map(|outcome| match outcome {
            Outcome::Done {
                run,
                thesis,
                alternatives,
            } => Entry::Done(Section {
                run,
                thesis,
                alternatives,
            }),
            Outcome::Failed(failure) => Entry::Failed(failure),
        })
        .collect();
    let meta = ReportMeta {
        tier: tier.name().into(),
        generated_by: format!("tribo {}", env!("CARGO_PKG_VERSION")),
        total_seconds: started.elapsed().as_secs_f64(),
        threads: rayon::current_num_threads(),
        provenance,
    };
    let written = report::write_report(&cli.out, &entries, &meta)
        .map_err(|e| format!("cannot write the report into {}: {e}", cli.out.display()))?;
    for message in &written.figure_failures {
        eprintln!("error (figures): {message}");
    }
    let record_failures = if cli.shard {
        write_records(&cli.out, &stems, &outcomes, &meta)
    } else {
        0
    };
    let failures = failed + written.figure_failures.len() + record_failures;
    let warned = outcomes
        .iter()
        .filter(|o| matches!(o, Outcome::Done { run, .. } if !run.warnings.is_empty()))
        .count();
    eprintln!(
        "wrote {} ({} tables, {} tier, {:.1} s){}{}",
        cli.out.join("index.html").display(),
        entries.len(),
        tier.name(),
        started.elapsed().as_secs_f64(),
        if failures == 0 {
            String::new()
        } else {
            format!("; {failures} failed")
        },
        if warned == 0 {
            String::new()
        } else {
            format!("; {warned} with warnings (see their sections)")
        }
    );
    Ok(failures == 0)
}

/// Run one experiment so that nothing in it can stop the other tables: an error of the study
/// becomes a failed entry with its cycle, and so does a panic (caught here, with the message and
/// the place the panic hook recorded).
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

fn run_isolated(
    spec: &Experiment,
    tier: Tier,
    budget: study::Budget,
    progress: study::Progress,
) -> Result<RunResult, Failure> {
    let failure = |kind, cycle, message| failure_of(spec, &spec.table, kind, cycle, message);
    if let Ok(mut place) = LAST_PANIC_PLACE.lock() {
        *place = None;
    }
    let caught = panic::catch_unwind(AssertUnwindSafe(|| {
        if std::env::var(TEST_PANIC_VARIABLE).is_ok_and(|t| t == spec.table) {
            panic!(
                "{TEST_PANIC_VARIABLE}={}: a panic on purpose (testing hook)",
                spec.table
            );
        }
        study::run_within(spec, tier, budget, progress)
    }));
    match caught {
        Ok(Ok(run)) => Ok(run),
        Ok(Err(e)) => Err(failure(FailureKind::Error, Some(e.cycle), e.to_string())),
        Err(payload) => {
            let message = report::panic_message(payload.as_ref());
            let place = LAST_PANIC_PLACE
                .lock()
                .ok()
                .and_then(|mut p| p.take())
                .map_or_else(String::new, |p| format!(" (at {p})"));
            Err(failure(
                FailureKind::Panic,
                None,
                format!("table {}: panicked{place}: {message}", spec.table),
            ))
        }
    }
}

/// Where the last panic happened (`file:line:column`), recorded by the panic hook so that a
/// caught panic's section can say where it came from; the payload alone has only the message.
static LAST_PANIC_PLACE: Mutex<Option<String>> = Mutex::new(None);

/// Record the place of every panic in [`LAST_PANIC_PLACE`], then do what the default hook does
/// (print the message to stderr).
fn install_panic_hook() {
    let default = panic::take_hook();
    panic::set_hook(Box::new(move |info| {
        if let (Some(location), Ok(mut place)) = (info.location(), LAST_PANIC_PLACE.lock()) {
            *place = Some(location.to_string());
        }
        default(info);
    }));
}

/// The run with the cost-of-accuracy study of its scene, where it applies
/// ([`study::cost::applies`]); a study that fails is a warning of the table, not a failure.
fn with_costs(spec: &Experiment, mut run: RunResult) -> RunResult {
    if study::cost::applies(spec) {
        match study::cost::accuracy_costs(spec) {
            Ok(costs) => run.costs = costs,
            Err(e) => run.warnings.push(format!("cost of accuracy: {e}")),
        }
    }
    run
}

/// Write the data files of a table into `out/data/` (CSV and Parquet, the join with the printed
/// table, the last mesh as `.vtu`: [`data::write_all`]); a table whose data cannot be written is
/// a failed entry like one whose run failed.
fn write_data(out: &Path, spec: &Experiment, mut run: RunResult) -> Result<RunResult, Failure> {
    let dir = out.join("data");
    let written = data::write_all(&dir, &run, &ThesisTable::of(spec));
    // The last mesh is written; the page does not need it, and it is as large as the mesh.
    run.last_mesh = None;
    match written {
        Ok(()) => Ok(run),
        Err(e) => Err(failure_of(
            spec,
            &run.table,
            FailureKind::Error,
            None,
            format!(
                "cannot write the data of {} into {}: {e}",
                run.table,
                dir.display()
            ),
        )),
    }
}

/// The failed entry of `table` (the experiment's own, or one of its alternative readings),
/// with the experiment's title and section.
fn failure_of(
    spec: &Experiment,
    table: &str,
    kind: FailureKind,
    cycle: Option<usize>,
    message: String,
) -> Failure {
    Failure {
        table: table.to_owned(),
        title: Some(spec.title.clone()),
        section: Some(spec.section.clone()),
        kind,
        cycle,
        message,
    }
}

/// Write the shard record of every outcome ([`record::write`]); return how many could not be
/// written (each named on stderr).
fn write_records(out: &Path, stems: &[String], outcomes: &[Outcome], meta: &ReportMeta) -> usize {
    let run_meta = record::RunMeta::of(meta);
    let mut failures = 0;
    for (stem, outcome) in stems.iter().zip(outcomes) {
        let entry = match outcome {
            Outcome::Done {
                run,
                thesis,
                alternatives,
            } => RecordEntry::Done {
                run: run.clone(),
                thesis: record::PrintedTable::of(thesis),
                alternatives: alternatives.clone(),
            },
            Outcome::Failed(failure) => RecordEntry::Failed(failure.clone()),
        };
        let record = Record {
            format: record::FORMAT,
            stem: stem.clone(),
            run: run_meta.clone(),
            entry,
        };
        if let Err(message) = record::write(out, &record) {
            eprintln!("error (records): {message}");
            failures += 1;
        }
    }
    failures
}

/// The last meshes (`data/*.vtu`) of the shards, copied into `out/data/`: the records do not
/// hold them (a mesh of 0.7 M cells), so merge takes the files the shard runs wrote.
fn copy_meshes(shards: &[PathBuf], out: &Path) -> std::io::Result<()> {
    let target = out.join("data");
    std::fs::create_dir_all(&target)?;
    for shard in shards {
        let Ok(files) = std::fs::read_dir(shard.join("data")) else {
            continue;
        };
        for file in files {
            let path = file?.path();
            if path.extension().is_some_and(|e| e == "vtu") {
                let to = target.join(path.file_name().expect("a file in a folder"));
                let same = matches!(
                    (path.canonicalize(), to.canonicalize()),
                    (Ok(a), Ok(b)) if a == b
                );
                if !same {
                    std::fs::copy(&path, &to)?;
                }
            }
        }
    }
    Ok(())
}

/// `report merge`: the page, figures, data files and records of the shards' entries in `out`.
/// Returns Ok(false) when a merged entry (or one of its alternative readings, or its figures)
/// failed; Err when the shards cannot be merged or `out` cannot be written.
fn merge(shards: &[PathBuf], out: &Path) -> Result<bool, String> {
    let started = Instant::now();
    let provenance = report::provenance::Provenance::collect(
        std::env::args(),
        Path::new(env!("CARGO_MANIFEST_DIR")),
    );
    let records = record::read_shards(shards)?;
    let cannot_write =
        |e: &dyn std::fmt::Display| format!("cannot write the report into {}: {e}", out.display());
    report::prepare_output(out).map_err(|e| cannot_write(&e))?;
    // Every record is in memory now, so `out` may be one of the shards.
    record::clear(out).map_err(|e| cannot_write(&e))?;
    let mut theses = Vec::with_capacity(records.len());
    let mut failed = 0;
    for r in &records {
        report::remove_outputs(out, &r.stem).map_err(|e| cannot_write(&e))?;
        record::write(out, r).map_err(|e| cannot_write(&e))?;
        match &r.entry {
            RecordEntry::Done {
                run,
                thesis,
                alternatives,
            } => {
                // Checked when the record was read.
                theses.push(Some(thesis.thesis()?));
                let printed = theses
                    .last()
                    .and_then(Option::as_ref)
                    .expect("pushed above");
                data::write_all(&out.join("data"), run, printed).map_err(|e| cannot_write(&e))?;
                for alt in alternatives {
                    match &alt.outcome {
                        Ok(run) => data::write_all(&out.join("data"), run, printed)
                            .map_err(|e| cannot_write(&e))?,
                        Err(_) => failed += 1,
                    }
                }
            }
            RecordEntry::Failed(_) => {
                theses.push(None);
                failed += 1;
            }
        }
    }
    copy_meshes(shards, out).map_err(|e| cannot_write(&e))?;
    let entries: Vec<Entry> = records
        .iter()
        .zip(&theses)
        .filter_map(|(r, thesis)| match &r.entry {
            RecordEntry::Done {
                run, alternatives, ..
            } => thesis.as_ref().map(|thesis| {
                Entry::Done(Section {
                    run,
                    thesis,
                    alternatives,
                })
            }),
            RecordEntry::Failed(failure) => Some(Entry::Failed(failure)),
        })
        .collect();
    let meta = record::merged_meta(
        &records,
        format!("tribo {}", env!("CARGO_PKG_VERSION")),
        provenance.command,
    );
    let written = report::write_report(out, &entries, &meta).map_err(|e| cannot_write(&e))?;
    for message in &written.figure_failures {
        eprintln!("error (figures): {message}");
    }
    let failures = failed + written.figure_failures.len();
    eprintln!(
        "wrote {} ({} tables from {} shards, {} tier, merged in {:.1} s){}",
        out.join("index.html").display(),
        entries.len(),
        shards.len(),
        meta.tier,
        started.elapsed().as_secs_f64(),
        if failures == 0 {
            String::new()
        } else {
            format!("; {failures} failed")
        },
    );
    Ok(failures == 0)
}
