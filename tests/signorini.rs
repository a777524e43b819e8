//! The Signorini condition to convergence (`tribo::study::signorini`): the scene option
//! `signorini = "linearised" | "converged"`, the fixed point of the §IV.2.2 linearisation, the
//! comparison columns of Tables IV.12–IV.17 and a scene whose fixed point cycles.

use std::fs;
use std::path::PathBuf;

use tribo::experiment::{self, Experiment, SignoriniReading};
use tribo::results::RunResult;
use tribo::study::signorini::columns;
use tribo::study::table::Solves;
use tribo::study::{self, TableHost, TableOptions, TableRun, Tier};
use tribo::thesis::ThesisTable;

use crate::common::{experiments_dir, quick, refused_at, report_of, spec};

const MODEL: &str = "model = \"signorini\"\n";

/// A scratch folder of this test process.
fn scratch(name: &str) -> PathBuf {
    crate::common::scratch(&format!("signorini-{name}"))
}

/// `IV.<n>.toml` with `from` replaced by `to` (once; `from` must occur), written to a scratch
/// folder under its own name.
fn edited_file(table: &str, from: &str, to: &str) -> PathBuf {
    let text = fs::read_to_string(experiments_dir().join(format!("{table}.toml"))).unwrap();
    assert!(text.contains(from), "test setup: `{from}` not in {table}");
    let dir = scratch(&format!("{table}-{}", to.len()));
    let path = dir.join(format!("{table}.toml"));
    fs::write(&path, text.replacen(from, to, 1)).unwrap();
    path
}

/// `IV.<n>` with `signorini = "converged"` in its contact section.
fn converged(table: &str) -> Experiment {
    let path = edited_file(table, MODEL, &format!("{MODEL}signorini = \"converged\"\n"));
    experiment::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn the_option_defaults_to_the_linearised_reading_and_reads_converged() {
    for t in ["IV.12", "IV.17", "IV.18"] {
        let contact = spec(t).problem.contact().cloned().unwrap();
        assert_eq!(contact.signorini, None, "{t}");
        assert_eq!(contact.signorini_reading(), SignoriniReading::Linearised);
    }
    let contact = converged("IV.12").problem.contact().cloned().unwrap();
    assert_eq!(contact.signorini_reading(), SignoriniReading::Converged);
}

#[test]
fn a_wrong_value_is_refused_naming_the_two_values() {
    let path = edited_file(
        "IV.12",
        MODEL,
        &format!("{MODEL}signorini = \"iterated\"\n"),
    );
    let error = refused_at(&path, "scene.contact.signorini", "linearised");
    let message = error.to_string();
    assert!(message.contains("converged"), "{message}");
    assert!(message.contains("iterated"), "{message}");
}

#[test]
fn the_option_on_a_z_contact_scene_is_refused() {
    let z = "model = \"z\"\n";
    let path = edited_file("IV.6", z, &format!("{z}signorini = \"converged\"\n"));
    refused_at(&path, "scene.contact.signorini", "z-contact scene has none");
}

/// On Table IV.12 (flat obstacle) the fixed point takes a few iterations in every quick cycle,
/// and the converged solution meets the exact condition at the contact vertices to rounding,
/// while the linearised one of cycle 1 (linearised about cycle 0's solution) does not.
#[test]
fn the_fixed_point_converges_in_few_iterations_and_meets_the_exact_condition() {
    let r = quick("IV.12");
    let iterations: Vec<i64> = r
        .rows
        .iter()
        .map(|row| {
            row.count_of(columns::ITERATIONS)
                .expect("a comparison per cycle")
        })
        .collect();
    assert_eq!(iterations, [4, 4, 4, 3]);
    let scale = 2.0; // the obstacle level: the size of the displacement
    for row in &r.rows {
        let converged = row.value(columns::PENETRATION_CONVERGED).unwrap();
        assert!(
            converged <= 1e-10 * scale,
            "cycle {}: {converged}",
            row.cycle
        );
        let relative = row.value(columns::RELATIVE_DISTANCE).unwrap();
        assert!(
            relative > 0.0 && relative < 1e-3,
            "cycle {}: {relative}",
            row.cycle
        );
        let absolute = row.value(columns::ENERGY_DISTANCE).unwrap();
        assert!(absolute > 0.0, "cycle {}", row.cycle);
    }
    let linearised = r.rows[1].value(columns::PENETRATION).unwrap();
    assert!(linearised > 1e-5, "{linearised}");
}

/// The default run is the linearised one: the rows of IV.12 with `signorini = "converged"`
/// differ from the linearised rows already in cycle 0 (s₀ = 0 there), on the same first mesh.
#[test]
fn the_converged_reading_is_the_solution_the_table_uses() {
    let linearised = quick("IV.12");
    let run = study::run(&converged("IV.12"), Tier::Quick, &|_, _, _| {}).unwrap();
    let (a, b) = (&linearised.rows[0], &run.rows[0]);
    assert_eq!(a.dofs(), b.dofs());
    let (ea, eb) = (a.estimate().unwrap(), b.estimate().unwrap());
    assert!((ea - eb).abs() > 1e-8 * ea, "{ea} {eb}");
    // Its table's own penetration column is the converged solution's (sampled on the faces:
    // between the vertices a flat obstacle is not entered either).
    for row in &run.rows {
        let p = row.value("penetration").unwrap();
        assert!(p <= 1e-10, "cycle {}: {p}", row.cycle);
    }
}

/// Table IV.16 (two steep jump obstacles) solved with `signorini = "converged"`: in cycle 1
/// the contact set of the fixed point alternates between 3 and 4 vertices without the change
/// shrinking, and the run ends with an error naming the table, the cycle and the iteration.
#[test]
fn a_cycling_fixed_point_ends_the_run_naming_table_cycle_and_iteration() {
    let error = study::run(&converged("IV.16"), Tier::Quick, &|_, _, _| {})
        .expect_err("the fixed point cycles");
    let message = error.to_string();
    assert_eq!(
        (error.table.as_str(), error.cycle),
        ("IV.16", 1),
        "{message}"
    );
    assert!(
        message.starts_with("table IV.16, cycle 1: Signorini fixed point, iteration 4:"),
        "{message}"
    );
    assert!(
        message.contains("cycles and does not converge"),
        "{message}"
    );
}

/// With the default reading the same cycling fixed point only loses the comparison of that
/// cycle: the table runs, the row's columns are empty, and a note names the cycle.
#[test]
fn with_the_linearised_reading_a_failed_fixed_point_is_a_note() {
    // Cycles 0–6 (the fixed point cycles in cycles 4–6 of the thesis's run).
    let path = edited_file("IV.16", "quick_rows = 4", "quick_rows = 7");
    let r = study::run(
        &experiment::load(&path).unwrap(),
        Tier::Quick,
        &|_, _, _| {},
    )
    .unwrap();
    let missing: Vec<usize> = r
        .rows
        .iter()
        .filter(|row| row.count_of(columns::ITERATIONS).is_none())
        .map(|row| row.cycle)
        .collect();
    assert!(!missing.is_empty());
    for cycle in &missing {
        let prefix = format!("cycle {cycle}: no converged Signorini solution");
        assert!(
            r.notes.iter().any(|n| n.starts_with(&prefix)),
            "{prefix}: {:?}",
            r.notes
        );
    }
}

/// The comparison is in `data/IV.12.csv` (the quick tier) and on the page, not in the
/// section's own table.
#[test]
fn the_comparison_columns_are_in_the_data_file_and_on_the_page() {
    let run: &RunResult = &quick("IV.12");
    let thesis = ThesisTable::of(&spec("IV.12"));
    let (dir, _) = report_of("signorini-columns", &[(run, &thesis)]);
    tribo::report::data::write_frames(&dir.join("data"), run).unwrap();
    let csv = fs::read_to_string(dir.join("data/IV.12.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    for c in columns::ALL {
        assert!(header.contains(&c), "{c} not in {header:?}");
    }
    let first = csv.lines().nth(1).unwrap().split(',').collect::<Vec<_>>();
    let at = |c: &str| first[header.iter().position(|h| *h == c).unwrap()];
    assert_eq!(at(columns::ITERATIONS), "4");
    let page = tribo::report::read_pages(&dir).unwrap();
    assert!(page.contains("Signorini: the linearised solution against the converged one"));
    assert!(!page.contains("<th>signorini_iterations</th>"));
}

/// A host that runs and keeps every run as it is.
struct Keep;

impl TableHost for Keep {
    type Failure = String;

    fn isolate(&self, _run: TableRun, solves: Solves) -> Result<RunResult, String> {
        solves(&|_, _, _| {}).map_err(|e| e.to_string())
    }

    fn keep(&self, _run: TableRun, result: RunResult) -> Result<RunResult, String> {
        Ok(result)
    }
}

/// Whether any row of `run` has the comparison.
fn compared(run: &RunResult) -> bool {
    run.rows
        .iter()
        .any(|r| r.count_of(columns::ITERATIONS).is_some())
}

/// The model-adaptive Table IV.18 compares its mixed solutions with the converged ones; its
/// alternative reading does not repeat the comparison, and `--no-alternatives` leaves it out.
#[test]
fn the_comparison_runs_with_the_alternatives_only() {
    let experiment = spec("IV.18");
    let options = |alternatives| TableOptions {
        tier: Tier::Quick,
        budget: study::Budget::machine(),
        alternatives,
        vtu: tribo::results::VtuOutput::Last,
    };
    let table = study::run_table(&experiment, options(true), &Keep).unwrap();
    assert!(compared(&table.run));
    assert!(!table.alternatives.is_empty());
    for reading in &table.alternatives {
        assert!(
            !compared(reading.outcome.as_ref().unwrap()),
            "{}",
            reading.label
        );
    }
    let alone = study::run_table(&experiment, options(false), &Keep).unwrap();
    assert!(!compared(&alone.run));
    let strip = |run: &RunResult| -> Vec<Vec<(String, tribo::results::Value)>> {
        run.rows
            .iter()
            .map(|r| {
                r.columns
                    .iter()
                    .filter(|(n, _)| !columns::is_comparison(n))
                    .cloned()
                    .collect()
            })
            .collect()
    };
    assert_eq!(
        strip(&table.run),
        strip(&alone.run),
        "the same table either way"
    );
}
