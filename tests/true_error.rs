//! The true error of every grid-adaptive thesis table (`tribo::study::accuracy`): finite,
//! positive `error` and `effectivity` in every row, except the tables listed below with the
//! reason — and a listed table must indeed have none, so the list cannot go stale. The quick
//! tier runs with the other tests; the full tier reads the data of the report in
//! `TRIBO_FULL_REPORT` (`.ci/run` makes it):
//!
//! ```sh
//! TRIBO_FULL_REPORT=report cargo test --release --test tribo -- --ignored full_tier_true_error
//! ```

use std::path::PathBuf;

use tribo::experiment::StudyKind;
use tribo::results::columns;

use crate::common::{experiments_dir, quick, read_csv, spec};

/// Grid-adaptive tables without a true error, at either tier, and why.
const WITHOUT: [(&str, &str); 3] = [
    (
        "IV.38",
        "the exact solution is constant: the discrete solution is exact",
    ),
    (
        "IV.43",
        "the exact solution is constant: the discrete solution is exact",
    ),
    (
        "IV.52",
        "the discrete SubStokes solution is exact up to rounding",
    ),
];

/// The grid-adaptive thesis tables (the model-and-grid-adaptive ones too), in file order.
fn grid_adaptive_tables() -> Vec<String> {
    let mut tables: Vec<String> = std::fs::read_dir(experiments_dir())
        .expect("experiments/")
        .filter_map(|e| {
            let name = e.ok()?.file_name().into_string().ok()?;
            let table = name.strip_suffix(".toml")?.to_string();
            table.starts_with("IV.").then_some(table)
        })
        .filter(|t| {
            matches!(
                spec(t).study.kind(),
                StudyKind::GridAdaptive | StudyKind::ModelAndGridAdaptive
            )
        })
        .collect();
    tables.sort();
    tables
}

/// Check one table's `error` and `effectivity` columns (one value per row, `None` where a cell
/// is empty or the column missing) against the lists; a failure message or nothing.
fn check(
    table: &str,
    error: &[Option<f64>],
    effectivity: &[Option<f64>],
    without: &[(&str, &str)],
) -> Option<String> {
    let listed = without.iter().find(|(t, _)| *t == table);
    let good = |v: &Option<f64>| v.is_some_and(|x| x.is_finite() && x > 0.0);
    let complete = !error.is_empty()
        && error.len() == effectivity.len()
        && error.iter().all(good)
        && effectivity.iter().all(good);
    match (listed, complete) {
        (None, false) => {
            let row = error
                .iter()
                .zip(effectivity)
                .position(|(e, f)| !good(e) || !good(f))
                .unwrap_or(0);
            Some(format!(
                "{table}: no finite positive error and effectivity in row {row} \
                 (error {:?}, effectivity {:?})",
                error.get(row),
                effectivity.get(row)
            ))
        }
        (Some((_, why)), true) => Some(format!(
            "{table} is listed without a true error ({why}) but has one in every row: take it \
             off the list"
        )),
        _ => None,
    }
}

/// [`check`] every grid-adaptive table, its columns from `columns_of(table)` (a column by name);
/// panics with every failure.
fn check_every_table<C: Fn(&str) -> Vec<Option<f64>>>(
    without: &[(&str, &str)],
    columns_of: impl Fn(&str) -> C,
) {
    let failures: Vec<String> = grid_adaptive_tables()
        .iter()
        .filter_map(|t| {
            let column = columns_of(t);
            check(
                t,
                &column(columns::ERROR),
                &column(columns::EFFECTIVITY),
                without,
            )
        })
        .collect();
    assert!(
        failures.is_empty(),
        "{} table(s):\n{}",
        failures.len(),
        failures.join("\n")
    );
}

#[test]
fn quick_tier_grid_adaptive_tables_have_a_true_error() {
    let tables = grid_adaptive_tables();
    assert!(tables.len() >= 50, "{} grid-adaptive tables", tables.len());
    check_every_table(&WITHOUT, |t| {
        let r = quick(t);
        move |name: &str| -> Vec<Option<f64>> { r.rows.iter().map(|row| row.value(name)).collect() }
    });
}

#[test]
#[ignore]
fn full_tier_true_error_in_the_report_data() {
    let out = PathBuf::from(std::env::var_os("TRIBO_FULL_REPORT").expect(
        "TRIBO_FULL_REPORT names the folder of a full-tier report (cargo run --release --bin \
         report -- --out DIR)",
    ));
    check_every_table(&WITHOUT, |t| {
        let data = read_csv(&out.join("data").join(format!("{t}.csv")));
        let rows = data.get(columns::DOFS).map_or(0, Vec::len);
        move |name: &str| data.get(name).cloned().unwrap_or(vec![None; rows])
    });
}

/// The check fails a table that lacks the error in one row, and a listed table that has it.
#[test]
fn the_check_can_fail() {
    let full = [Some(1.0), Some(2.0)];
    assert_eq!(check("T", &full, &full, &[]), None);
    let message = check("T", &[Some(1.0), None], &full, &[]).expect("fails");
    assert!(message.contains("row 1"), "{message}");
    let message = check("T", &full, &full, &[("T", "why")]).expect("fails");
    assert!(message.contains("take it off the list"), "{message}");
    assert_eq!(check("T", &[None, None], &full, &[("T", "why")]), None);
}
