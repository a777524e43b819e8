//! Per-table result data as CSV (`report/data/<table>.csv`, `report/data/<table>.probes.csv`),
//! built as polars data frames so that the columns follow the `column` names of
//! `../shared/thesis/tables.csv` and can be joined against the thesis rows.

use std::fs::File;
use std::path::Path;

use polars::prelude::*;

use crate::linalg::uzawa::UzawaRow;
use crate::results::{CostRow, PhaseSeconds, RunResult, Value};

/// One row per cycle: `cycle`, then the rows' named columns in order of first appearance
/// (`active_cells, dofs, estimate, ratio` and the family's further columns for the
/// grid-adaptive tables), then `seconds_<phase>`. Count columns are integers, real columns
/// floats; a value a row does not have, or that is undefined (the first `ratio`), is empty.
///
/// A load-step run (the forming of §IV.2.4.7, Fig. IV.54) has one row per load step, so its
/// first column is `step` ([`first_column`]).
pub fn rows_frame(run: &RunResult) -> PolarsResult<DataFrame> {
    let rows = &run.rows;
    let mut names: Vec<(&str, bool)> = Vec::new();
    for r in rows {
        for (name, value) in &r.columns {
            if !names.iter().any(|(n, _)| n == name) {
                names.push((name, matches!(value, Value::Count(_))));
            }
        }
    }
    let mut columns = vec![Column::new(
        first_column(run).into(),
        rows.iter().map(|r| r.cycle as u64).collect::<Vec<_>>(),
    )];
    for (name, count) in names {
        let column = if count {
            let v: Vec<Option<i64>> = rows.iter().map(|r| r.count_of(name)).collect();
            Column::new(name.into(), v)
        } else {
            let v: Vec<Option<f64>> = rows.iter().map(|r| r.value(name)).collect();
            Column::new(name.into(), v)
        };
        columns.push(column);
    }
    for (i, (name, _)) in PhaseSeconds::default().named().iter().enumerate() {
        let v: Vec<f64> = rows.iter().map(|r| r.seconds.named()[i].1).collect();
        columns.push(Column::new((*name).into(), v));
    }
    DataFrame::new(rows.len(), columns)
}

/// The name of a run's row index: `step` for a load-step run (its rows are load steps j, each
/// of several cycles), `cycle` for every other run.
pub fn first_column(run: &RunResult) -> &'static str {
    if run.is_load_steps() {
        "step"
    } else {
        "cycle"
    }
}

/// Solution probes: `x, y, component, value`.
pub fn probes_frame(run: &RunResult) -> PolarsResult<DataFrame> {
    let p = &run.probes;
    DataFrame::new(
        p.len(),
        vec![
            Column::new("x".into(), p.iter().map(|q| q.x).collect::<Vec<_>>()),
            Column::new("y".into(), p.iter().map(|q| q.y).collect::<Vec<_>>()),
            Column::new(
                "component".into(),
                p.iter().map(|q| q.component.as_str()).collect::<Vec<_>>(),
            ),
            Column::new(
                "value".into(),
                p.iter().map(|q| q.value).collect::<Vec<_>>(),
            ),
        ],
    )
}

/// The file-name stem of a table's CSV files: `<stem>.csv`, `<stem>.probes.csv`. Table ids are
/// checked by the loader; a separator is still never let into a path.
pub fn csv_stem(table: &str) -> String {
    table.replace(['/', '\\'], "_")
}

/// The cost-of-accuracy study: `variant, cycle, seconds_solve, iterations, penetration,
/// energy_distance, accurate_faces, model_error, model_tolerance`.
pub fn costs_frame(costs: &[CostRow]) -> PolarsResult<DataFrame> {
    DataFrame::new(
        costs.len(),
        vec![
            Column::new(
                "variant".into(),
                costs.iter().map(|c| c.variant.as_str()).collect::<Vec<_>>(),
            ),
            Column::new(
                "cycle".into(),
                costs.iter().map(|c| c.cycle as u64).collect::<Vec<_>>(),
            ),
            Column::new(
                "seconds_solve".into(),
                costs.iter().map(|c| c.seconds_solve).collect::<Vec<_>>(),
            ),
            Column::new(
                "iterations".into(),
                costs.iter().map(|c| c.iterations).collect::<Vec<_>>(),
            ),
            Column::new(
                "penetration".into(),
                costs.iter().map(|c| c.penetration).collect::<Vec<_>>(),
            ),
            Column::new(
                "energy_distance".into(),
                costs.iter().map(|c| c.energy_distance).collect::<Vec<_>>(),
            ),
            Column::new(
                "accurate_faces".into(),
                costs
                    .iter()
                    .map(|c| c.accurate_faces as u64)
                    .collect::<Vec<_>>(),
            ),
            Column::new(
                "model_error".into(),
                costs.iter().map(|c| c.model_error).collect::<Vec<_>>(),
            ),
            Column::new(
                "model_tolerance".into(),
                costs.iter().map(|c| c.model_tolerance).collect::<Vec<_>>(),
            ),
        ],
    )
}

/// The iterations of a solver study (Fig. III.6): `variant, iteration, residual,
/// relative_residual, pressure_error, inner_iterations, seconds` (cumulative per variant).
pub fn uzawa_frame(rows: &[UzawaRow]) -> PolarsResult<DataFrame> {
    DataFrame::new(
        rows.len(),
        vec![
            Column::new(
                "variant".into(),
                rows.iter().map(|r| r.variant.as_str()).collect::<Vec<_>>(),
            ),
            Column::new(
                "iteration".into(),
                rows.iter().map(|r| r.iteration as u64).collect::<Vec<_>>(),
            ),
            Column::new(
                "residual".into(),
                rows.iter().map(|r| r.residual).collect::<Vec<_>>(),
            ),
            Column::new(
                "relative_residual".into(),
                rows.iter().map(|r| r.relative_residual).collect::<Vec<_>>(),
            ),
            Column::new(
                "pressure_error".into(),
                rows.iter().map(|r| r.pressure_error).collect::<Vec<_>>(),
            ),
            Column::new(
                "inner_iterations".into(),
                rows.iter()
                    .map(|r| r.inner_iterations as u64)
                    .collect::<Vec<_>>(),
            ),
            Column::new(
                "seconds".into(),
                rows.iter().map(|r| r.seconds).collect::<Vec<_>>(),
            ),
        ],
    )
}

/// Write the CSV files of a run into `dir`: rows (a solver study's iterations in their place),
/// probes and, when the run has them, the cuts
/// (`<table>.cuts.csv`) and the costs (`<table>.cost.csv`).
pub fn write_csv(dir: &Path, run: &RunResult) -> PolarsResult<()> {
    std::fs::create_dir_all(dir)?;
    let safe = csv_stem(&run.table);
    let mut rows = if run.uzawa.is_empty() {
        rows_frame(run)?
    } else {
        uzawa_frame(&run.uzawa)?
    };
    CsvWriter::new(File::create(dir.join(format!("{safe}.csv")))?).finish(&mut rows)?;
    let mut probes = probes_frame(run)?;
    CsvWriter::new(File::create(dir.join(format!("{safe}.probes.csv")))?).finish(&mut probes)?;
    if let Some(cuts) = &run.cuts {
        let mut frame = DataFrame::new(
            cuts.columns.first().map_or(0, |c| c.1.len()),
            cuts.columns
                .iter()
                .map(|(name, values)| Column::new(name.as_str().into(), values.as_slice()))
                .collect(),
        )?;
        CsvWriter::new(File::create(dir.join(format!("{safe}.cuts.csv")))?).finish(&mut frame)?;
    }
    if !run.costs.is_empty() {
        let mut costs = costs_frame(&run.costs)?;
        CsvWriter::new(File::create(dir.join(format!("{safe}.cost.csv")))?).finish(&mut costs)?;
    }
    Ok(())
}
