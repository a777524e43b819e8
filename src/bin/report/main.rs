//! `cargo run --release --bin report` — run every experiment file and render the report.
//!
//! Writes `report/index.html`, `report/figures/*.svg`, `report/data/<table>.csv` and
//! `report/data/<table>.probes.csv` (each also as `.parquet`), `<table>.joined.*` (the rows
//! beside the printed table), `<table>.vtu` (the last mesh, `--vtu`) and `<table>.pvd` (their
//! series). Each table runs on its own: a file that does not load, a run that fails and a run
//! that panics each become a failed entry of the page (in the summary with its status, and in a
//! section with the table, the cycle and the message); the other tables are
//! still reported, and the exit status is 1. Usage errors, an experiment folder that cannot be
//! listed and an output folder that cannot be written end the program before anything is solved,
//! with exit status 2. So does a folder that another run is writing ([`folder::FolderLock`]);
//! until the run has finished, `index.html` is a page that says the report is incomplete
//! ([`folder::PendingPage`]), and every file is written whole or not at all ([`tribo::fsio`]).
//!
//! Every run also writes `report/shard/<table>.json`, the record of each entry
//! ([`tribo::report::record`]). `report merge DIR… --out DIR` builds one page, its figures and
//! its data files from the records of several output folders, as a single run of all their
//! tables would (timings and the header aside): the tables can run as separate processes, on
//! one machine or a cluster, and be merged afterwards. Its exit status is 1 when a merged entry
//! failed, 2 when the shards cannot be merged (a folder without records, a table in two folders,
//! a record that cannot be read).

mod folder;
mod isolate;
mod list;
mod merge;
mod outputs;
mod progress;
mod schedule;

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use clap::{Parser, Subcommand};

use tribo::experiment;
use tribo::report::{self, record, Entry, ReportMeta};
use tribo::study::{self, TableOptions, Tier};

use merge::merge;
use outputs::Outcome;

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

    /// Only these tables, comma-separated (e.g. `--only IV.1,IV.3`); a swept file's id runs all
    /// its runs, a run's id (`step-bearing~-10`) that run alone.
    #[arg(long, value_delimiter = ',', value_name = "TABLES")]
    only: Option<Vec<String>>,

    /// Sweep a field of every selected experiment (scenes of your own): each value is a run of
    /// its own, and the page compares the runs. FIELD is a dotted path of the file
    /// (`scene.reynolds.upper_wall_velocity`, `scene.reynolds.gap.g_out`); the values are TOML —
    /// numbers, arrays, quoted strings or bare words — split at the commas outside brackets, so
    /// `--set scene.reynolds.upper_wall_velocity=[-10,0,0],[-20,0,0]` is two runs. Repeat it for
    /// a second field (at most two; every combination is a run, at most 16). It replaces the
    /// fields of a file's own `[sweep]`.
    #[arg(long = "set", value_name = "FIELD=V1,V2,…", value_parser = experiment::parse_set)]
    set: Vec<experiment::SweepField>,

    /// Run the quick (test) tier instead of the full thesis sizes.
    #[arg(long)]
    quick: bool,

    /// Directory of experiment files.
    #[arg(long, value_name = "DIR", default_value = "experiments")]
    experiments: PathBuf,

    /// Output directory. One run at a time writes into it; until the run has finished, its
    /// `index.html` says that the report is incomplete.
    #[arg(long, value_name = "DIR", default_value = "report")]
    out: PathBuf,

    /// Do not show progress. By default a terminal shows a bar with the time left, and
    /// anything else (a log file, CI) gets one line per finished cycle.
    #[arg(long)]
    no_progress: bool,

    /// Do not run the alternative readings beside the experiments (the cavitation tables are
    /// otherwise run three times: printed, self-consistent and `reynolds` source R₃c). A scene
    /// of your own runs them only when its file sets `[study] alternatives = true`.
    #[arg(long)]
    no_alternatives: bool,

    /// Also write the shard records (`<out>/shard/<table>.json`, everything the page needs,
    /// mesh pictures included) that `report merge` builds one page from. Off by default: the
    /// records of a full report take gigabytes.
    #[arg(long)]
    shard: bool,

    /// Tables run at once (default: one per core, fewer where the memory budget does not hold
    /// the largest predicted tables side by side; never more than the tables of the run).
    /// Whatever the number, a table starts only when its predicted memory fits beside the
    /// tables running. The results do not depend on it.
    #[arg(long, value_name = "N")]
    jobs: Option<usize>,

    /// Linear solver of the Reynolds (with and without cavitation), elasticity and z- and
    /// Signorini contact tables, overriding the experiments' `[study] solver`: `direct` (sparse
    /// Cholesky; for contact in the primal–dual active-set method) or `multigrid` (CG with a
    /// geometric multigrid V-cycle; for contact the truncated nonsmooth Newton multigrid
    /// method, checked against the direct solver on test problems but not yet on the thesis
    /// tables); the model-adaptive contact tables always use the direct solver. The solver
    /// changes the run time, not the results beyond rounding.
    #[arg(long, value_enum, value_name = "SOLVER")]
    solver: Option<tribo::linalg::SolverKind>,

    /// Which meshes go into `data/` as VTU files, with a `.pvd` series per table for
    /// ParaView: `none`; `last`, the last printed mesh of each table (not of its alternative
    /// readings); `all`, every printed cycle of each table and of its readings (several times
    /// the disk of `last`).
    #[arg(long, value_enum, value_name = "MESHES", default_value = "last")]
    vtu: tribo::results::VtuOutput,

    /// List the experiments of `--experiments DIR` (with `--only`, those) without running them:
    /// id, family, rows of the tier (`--quick`), the predicted cells of the last solve and
    /// peak memory, and the seconds of the last run into `--out` (else a rough guess); a file
    /// that does not load is listed with its error.
    #[arg(long)]
    list: bool,

    /// Memory a table may use, e.g. `4G`, `1500M` or `4e3M` (default: the machine's memory).
    /// A table predicted to need more is refused before its first solve, naming the cycle.
    #[arg(long, value_name = "SIZE", value_parser = parse_budget)]
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

fn main() -> ExitCode {
    // Freed memory stays for the next cycle (tribo::heap): fewer page faults, same numbers.
    tribo::heap::keep_freed_memory();
    let cli = Cli::parse();
    isolate::install_panic_hook();
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

/// `--memory-budget`: [`study::Budget::parse`], and a number in exponent notation before the
/// unit (`4e3M`, `1.5E3G`), which that parser takes for a part of the unit.
fn parse_budget(text: &str) -> Result<study::Budget, String> {
    study::Budget::parse(text).or_else(|error| {
        let t = text.trim();
        let (number, unit) =
            t.split_at(t.trim_end_matches(|c: char| c.is_ascii_alphabetic()).len());
        match number.trim().parse::<f64>() {
            // `Display` of an f64 never uses exponent notation.
            Ok(n) if n.is_finite() && n > 0.0 => study::Budget::parse(&format!("{n}{unit}")),
            Ok(_) => Err(format!(
                "`{text}` is not a memory size: expected a positive, finite number with an \
                 optional unit K, M, G or T, e.g. 4G or 4e3M"
            )),
            Err(_) => Err(error),
        }
    })
}

/// `--set`: at most two fields in all ([`experiment::sweep::MAX_SWEEP_FIELDS`]), each once.
fn swept_fields(set: &[experiment::SweepField]) -> Result<(), String> {
    let paths: Vec<&str> = set.iter().map(|f| f.path.as_str()).collect();
    if paths.len() > experiment::sweep::MAX_SWEEP_FIELDS {
        return Err(format!(
            "--set names {} fields ({}); a sweep varies at most {}, every combination of their \
             values being a run",
            paths.len(),
            paths.join(", "),
            experiment::sweep::MAX_SWEEP_FIELDS
        ));
    }
    if let [a, b] = paths[..] {
        if a == b {
            return Err(format!(
                "--set names {a} twice; give all its values in one --set, comma-separated"
            ));
        }
    }
    Ok(())
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
    swept_fields(&cli.set)?;
    let loaded = experiment::load_each_swept(&cli.experiments, only.as_deref(), &cli.set)
        .map_err(|e| e.to_string())?;
    if loaded.is_empty() {
        return Err(format!(
            "no experiment files (*.toml) in {}",
            cli.experiments.display()
        ));
    }
    let tier = if cli.quick { Tier::Quick } else { Tier::Full };
    if cli.list {
        let (text, all) = list::listing(&loaded, tier, &cli.out);
        print!("{text}");
        return Ok(all);
    }
    let _lock = folder::FolderLock::take(&cli.out)?;
    folder::check(&cli.out)?;
    let stems: Vec<String> = loaded.iter().map(|(stem, _)| stem.clone()).collect();
    let page = folder::PendingPage::new(
        &cli.out,
        &format!("{} tier, started {}", tier.name(), provenance.date),
        &stems,
    );
    report::prepare_output(&cli.out)
        .and_then(|()| page.write())
        .and_then(|()| record::clear(&cli.out, cli.shard))
        .map_err(|e| format!("cannot write the report into {}: {e}", cli.out.display()))?;

    let settings = schedule::Settings {
        out: &cli.out,
        options: TableOptions {
            tier,
            budget: cli.memory_budget.unwrap_or_else(study::Budget::machine),
            alternatives: !cli.no_alternatives,
            vtu: cli.vtu,
        },
        solver: cli.solver,
        jobs: cli.jobs,
        no_progress: cli.no_progress,
        started,
        page: &page,
        overlap: Default::default(),
    };
    let outcomes = schedule::run_tables(loaded, &settings);
    let failed: usize = outcomes.iter().map(Outcome::failures).sum();

    let entries: Vec<Entry> = outcomes.iter().map(Outcome::entry).collect();
    let meta = ReportMeta {
        tier: tier.name().into(),
        generated_by: format!("tribo {}", env!("CARGO_PKG_VERSION")),
        total_seconds: started.elapsed().as_secs_f64(),
        threads: rayon::current_num_threads(),
        provenance,
        alongside: settings.overlap.most_alongside(),
    };
    let written = report::write_report(&cli.out, &entries, &meta)
        .map_err(|e| format!("cannot write the report into {}: {e}", cli.out.display()))?;
    for message in &written.figure_failures {
        eprintln!("error (figures): {message}");
    }
    let record_failures = if cli.shard {
        outputs::write_records(&cli.out, &stems, &outcomes, &meta)
    } else {
        0
    };
    let failures = failed + written.figure_failures.len() + record_failures;
    let warned = outcomes.iter().filter(|o| o.warned()).count();
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
