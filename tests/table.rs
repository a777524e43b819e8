//! `study::run_table`: the runs of one table in their order — the table as written, then each
//! alternative reading — each isolated and kept through the caller's host as it finishes.

use std::sync::Mutex;

use tribo::results::{RunResult, VtuOutput};
use tribo::study::table::Solves;
use tribo::study::{self, TableHost, TableOptions, TableRun, Tier};

use crate::common::spec;

/// A host that records what it is asked to do, and fails to keep the runs named in `refuse`.
#[derive(Default)]
struct Recorder {
    calls: Mutex<Vec<String>>,
    refuse: Vec<String>,
}

impl TableHost for Recorder {
    type Failure = String;

    fn isolate(&self, run: TableRun, solves: Solves) -> Result<RunResult, String> {
        self.calls
            .lock()
            .unwrap()
            .push(format!("isolate {}", run.label()));
        solves(&|_, _, _| {}).map_err(|e| e.to_string())
    }

    fn keep(&self, run: TableRun, result: RunResult) -> Result<RunResult, String> {
        assert_eq!(result.table, run.table(), "a reading's result is renamed");
        self.calls
            .lock()
            .unwrap()
            .push(format!("keep {}", run.table()));
        if self.refuse.contains(&result.table) {
            return Err(format!("refused {}", result.table));
        }
        Ok(result)
    }
}

fn options(alternatives: bool) -> TableOptions {
    TableOptions {
        tier: Tier::Quick,
        budget: study::Budget::machine(),
        alternatives,
        vtu: VtuOutput::Last,
    }
}

/// IV.64 cavitates, so both readings of the cavitation source run, each kept before the next
/// starts; without alternatives the table runs once.
#[test]
fn readings_run_after_the_table_each_kept_before_the_next() {
    let experiment = spec("IV.64");
    let host = Recorder::default();
    let table = study::run_table(&experiment, options(true), &host).expect("IV.64 runs");
    let calls = host.calls.into_inner().unwrap();
    assert_eq!(
        calls,
        [
            "isolate IV.64",
            "keep IV.64",
            "isolate IV.64 (self-consistent)",
            "keep IV.64.self-consistent",
            "isolate IV.64 (reynolds)",
            "keep IV.64.reynolds",
        ]
    );
    assert_eq!(table.alternatives.len(), 2);
    assert!(table.alternatives.iter().all(|a| a.outcome.is_ok()));
    // `--vtu last`: the table keeps its last mesh, the readings none.
    assert!(table.run.last_mesh.is_some() && table.run.cycle_meshes.is_empty());
    for reading in &table.alternatives {
        assert!(reading.outcome.as_ref().unwrap().last_mesh.is_none());
    }

    let alone = Recorder::default();
    let table = study::run_table(&experiment, options(false), &alone).expect("IV.64 runs");
    assert_eq!(
        alone.calls.into_inner().unwrap(),
        ["isolate IV.64", "keep IV.64"]
    );
    assert!(table.alternatives.is_empty());
}

/// A table whose result cannot be kept is that failure, and no reading runs; a reading whose
/// result cannot be kept is a failed reading, and the next still runs.
/// `--vtu all` keeps the mesh of every printed cycle, of the table and of its readings, each
/// with its cycle; `--vtu none` keeps none.
#[test]
fn every_printed_mesh_is_kept_on_request_only() {
    let experiment = spec("IV.64");
    let all = TableOptions {
        vtu: VtuOutput::All,
        ..options(true)
    };
    let table = study::run_table(&experiment, all, &Recorder::default()).expect("IV.64 runs");
    let printed = table.run.rows.len();
    for run in std::iter::once(&table.run).chain(
        table
            .alternatives
            .iter()
            .map(|a| a.outcome.as_ref().unwrap()),
    ) {
        let cycles: Vec<usize> = run.cycle_meshes.iter().map(|m| m.cycle).collect();
        assert_eq!(
            cycles,
            (0..printed - 1).collect::<Vec<_>>(),
            "{}",
            run.table
        );
        assert_eq!(run.last_mesh.as_ref().map(|m| m.cycle), Some(printed - 1));
    }
    let none = TableOptions {
        vtu: VtuOutput::None,
        ..options(false)
    };
    let table = study::run_table(&experiment, none, &Recorder::default()).expect("IV.64 runs");
    assert!(table.run.last_mesh.is_none() && table.run.cycle_meshes.is_empty());
}

#[test]
fn a_failure_to_keep_stops_the_table_not_the_other_readings() {
    let experiment = spec("IV.64");
    let host = Recorder {
        refuse: vec!["IV.64".into()],
        ..Recorder::default()
    };
    let failed = study::run_table(&experiment, options(true), &host);
    assert_eq!(failed.err().as_deref(), Some("refused IV.64"));
    assert_eq!(
        host.calls.into_inner().unwrap(),
        ["isolate IV.64", "keep IV.64"]
    );

    let host = Recorder {
        refuse: vec!["IV.64.self-consistent".into()],
        ..Recorder::default()
    };
    let table = study::run_table(&experiment, options(true), &host).expect("IV.64 runs");
    let outcomes: Vec<_> = table
        .alternatives
        .iter()
        .map(|a| a.outcome.is_ok())
        .collect();
    assert_eq!(outcomes, [false, true]);
}
