//! What the report keeps of each table: its data files as soon as a run finishes, its entry of
//! the page, and its shard record.

use std::path::Path;

use tribo::experiment::Experiment;
use tribo::report::record::{self, Record, RecordEntry};
use tribo::report::{data, Alternative, Entry, Failure, FailureKind, ReportMeta, Section};
use tribo::results::RunResult;
use tribo::thesis::ThesisTable;

/// How one table ended: its section's data, or why there is none. (The run is boxed: it is
/// large beside a failure.)
pub enum Outcome {
    Done {
        run: Box<RunResult>,
        thesis: ThesisTable,
        alternatives: Vec<Alternative>,
    },
    Failed(Failure),
}

impl Outcome {
    /// The failed runs of the table: the table itself, or those of its alternative readings.
    pub fn failures(&self) -> usize {
        match self {
            Outcome::Done { alternatives, .. } => {
                alternatives.iter().filter(|a| a.outcome.is_err()).count()
            }
            Outcome::Failed(_) => 1,
        }
    }

    /// Whether the table ran with warnings.
    pub fn warned(&self) -> bool {
        matches!(self, Outcome::Done { run, .. } if !run.warnings.is_empty())
    }

    /// The table's entry of the page.
    pub fn entry(&self) -> Entry<'_> {
        match self {
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
        }
    }
}

/// Write the data files of a table into `out/data/` (CSV and Parquet, the join with the printed
/// table, the last mesh as `.vtu`: [`data::write_all`]); a table whose data cannot be written is
/// a failed entry like one whose run failed.
pub fn write_data(out: &Path, spec: &Experiment, mut run: RunResult) -> Result<RunResult, Failure> {
    let dir = out.join("data");
    let written = data::write_all(&dir, &run, &ThesisTable::of(spec));
    // The meshes are written; the page does not need them, and they are as large as the mesh.
    run.last_mesh = None;
    run.cycle_meshes = Vec::new();
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
pub fn failure_of(
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
pub fn write_records(
    out: &Path,
    stems: &[String],
    outcomes: &[Outcome],
    meta: &ReportMeta,
) -> usize {
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
