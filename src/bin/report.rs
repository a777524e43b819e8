//! `cargo run --release --bin report` — run every experiment file and render the report.
//!
//! Writes `report/index.html`, `report/figures/*.svg`, `report/data/<table>.csv` and
//! `report/data/<table>.probes.csv`. A failing experiment does not stop the others: its error is
//! printed, the remaining tables are rendered, and the exit status is non-zero.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::Parser;
use indicatif::{ProgressBar, ProgressStyle};

use tribo::experiment::{self, Experiment};
use tribo::report::{self, data, Alternative, ReportMeta, Section};
use tribo::study::{self, Tier};
use tribo::thesis::ThesisTable;

/// Regenerate the Chapter IV tables of Gimbel (2012) and render them beside the thesis tables.
#[derive(Parser, Debug)]
#[command(name = "report", version, about)]
struct Cli {
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

    /// Do not show the progress bar.
    #[arg(long)]
    no_progress: bool,

    /// Do not run the alternative readings beside the experiments (the cavitation tables are
    /// otherwise run three times: printed, self-consistent and `reynolds` source R₃c).
    #[arg(long)]
    no_alternatives: bool,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(&cli) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::from(2)
        }
    }
}

/// Returns Ok(false) when some experiment failed (the others are still reported).
fn run(cli: &Cli) -> Result<bool, String> {
    let started = Instant::now();
    let only: Option<Vec<String>> = cli.only.as_ref().map(|v| {
        v.iter()
            .map(|s| s.trim().to_string())
            .filter(|s| !s.is_empty())
            .collect()
    });
    if matches!(&only, Some(v) if v.is_empty()) {
        return Err("--only needs at least one table id, e.g. --only IV.1,IV.3".into());
    }
    let specs =
        experiment::load_dir(&cli.experiments, only.as_deref()).map_err(|e| e.to_string())?;
    if specs.is_empty() {
        return Err(format!(
            "no experiment files (*.toml) in {}",
            cli.experiments.display()
        ));
    }
    let tier = if cli.quick { Tier::Quick } else { Tier::Full };
    let readings_of = |s: &Experiment| {
        if cli.no_alternatives {
            Vec::new()
        } else {
            study::alternative_readings(s)
        }
    };
    let cycles = |s: &Experiment| study::solves(s, tier) as u64;
    let total_cycles: u64 = specs
        .iter()
        .map(|s| cycles(s) * (1 + readings_of(s).len() as u64))
        .sum();
    let bar = if cli.no_progress {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(total_cycles)
    };
    bar.set_style(
        ProgressStyle::with_template("{elapsed_precise} [{bar:30}] {pos}/{len} cycles  {msg}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    let mut runs = Vec::new();
    let mut failed = Vec::new();
    for spec in &specs {
        bar.set_message(format!("{} {}", spec.table, spec.title));
        let base = bar.position();
        let readings = readings_of(spec);
        let runs_of_spec = 1 + readings.len() as u64;
        let progress = |_: &str, done: usize, _: usize| bar.set_position(base + done as u64);
        match study::run(spec, tier, &progress) {
            Ok(r) => {
                let thesis = ThesisTable::of(spec);
                write_data(&cli.out, &r)?;
                let mut alternatives = Vec::new();
                for alt in readings {
                    bar.set_message(format!("{} {} ({})", spec.table, spec.title, alt.suffix));
                    let base = bar.position();
                    let progress =
                        |_: &str, done: usize, _: usize| bar.set_position(base + done as u64);
                    match study::run(&alt.experiment, tier, &progress) {
                        Ok(mut run) => {
                            run.table = format!("{}.{}", spec.table, alt.suffix);
                            write_data(&cli.out, &run)?;
                            alternatives.push(Alternative {
                                label: alt.label,
                                run,
                            });
                        }
                        Err(e) => {
                            bar.suspend(|| eprintln!("error ({}): {e}", alt.suffix));
                            failed.push(e.to_string());
                        }
                    }
                }
                runs.push((r, thesis, alternatives));
            }
            Err(e) => {
                bar.suspend(|| eprintln!("error: {e}"));
                failed.push(e.to_string());
            }
        }
        bar.set_position(base + cycles(spec) * runs_of_spec);
    }
    bar.finish_and_clear();
    let sections: Vec<Section> = runs
        .iter()
        .map(|(run, thesis, alternatives)| Section {
            run,
            thesis,
            alternatives,
        })
        .collect();
    let meta = ReportMeta {
        tier: tier.name().into(),
        generated_by: format!("tribo {}", env!("CARGO_PKG_VERSION")),
        total_seconds: started.elapsed().as_secs_f64(),
        threads: rayon::current_num_threads(),
    };
    report::write_report(&cli.out, &sections, &meta)
        .map_err(|e| format!("cannot write the report into {}: {e}", cli.out.display()))?;
    eprintln!(
        "wrote {} ({} tables, {} tier, {:.1} s){}",
        cli.out.join("index.html").display(),
        runs.len(),
        tier.name(),
        started.elapsed().as_secs_f64(),
        if failed.is_empty() {
            String::new()
        } else {
            format!("; {} failed", failed.len())
        }
    );
    Ok(failed.is_empty())
}

/// Write `out/data/<table>.csv` and its probes.
fn write_data(out: &std::path::Path, run: &tribo::results::RunResult) -> Result<(), String> {
    let dir = out.join("data");
    data::write_csv(&dir, run).map_err(|e| format!("cannot write {}: {e}", dir.display()))
}
