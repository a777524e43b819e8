//! Per-table result data as CSV (`report/data/<table>.csv`, `report/data/<table>.probes.csv`),
//! built as polars data frames so that the columns follow the `column` names of
//! `../shared/thesis/tables.csv` and can be joined against the thesis rows.

use std::fs::File;
use std::path::Path;

use polars::prelude::*;

use crate::results::{PhaseSeconds, RunResult};

/// One row per cycle: `cycle, active_cells, dofs, estimate, ratio`, the table family's further
/// columns, solver counters and `seconds_<phase>`. `ratio` is empty in the first row.
pub fn rows_frame(run: &RunResult) -> PolarsResult<DataFrame> {
    let rows = &run.rows;
    let mut columns = vec![
        Column::new(
            "cycle".into(),
            rows.iter().map(|r| r.cycle as u64).collect::<Vec<_>>(),
        ),
        Column::new(
            "active_cells".into(),
            rows.iter()
                .map(|r| r.active_cells as u64)
                .collect::<Vec<_>>(),
        ),
        Column::new(
            "dofs".into(),
            rows.iter().map(|r| r.dofs as u64).collect::<Vec<_>>(),
        ),
        Column::new(
            "estimate".into(),
            rows.iter().map(|r| r.estimate).collect::<Vec<_>>(),
        ),
        Column::new(
            "ratio".into(),
            rows.iter().map(|r| r.ratio).collect::<Vec<Option<f64>>>(),
        ),
    ];
    let mut quantity_names: Vec<&str> = Vec::new();
    let mut counter_names: Vec<&str> = Vec::new();
    for r in rows {
        for (n, _) in &r.quantities {
            if !quantity_names.contains(&n.as_str()) {
                quantity_names.push(n);
            }
        }
        for (n, _) in &r.counters {
            if !counter_names.contains(&n.as_str()) {
                counter_names.push(n);
            }
        }
    }
    for name in quantity_names {
        let v: Vec<Option<f64>> = rows
            .iter()
            .map(|r| {
                r.quantities
                    .iter()
                    .find(|(n, _)| n == name)
                    .map(|(_, v)| *v)
            })
            .collect();
        columns.push(Column::new(name.into(), v));
    }
    for name in counter_names {
        let v: Vec<Option<i64>> = rows
            .iter()
            .map(|r| r.counters.iter().find(|(n, _)| n == name).map(|(_, v)| *v))
            .collect();
        columns.push(Column::new(name.into(), v));
    }
    for (i, (name, _)) in PhaseSeconds::default().named().iter().enumerate() {
        let v: Vec<f64> = rows.iter().map(|r| r.seconds.named()[i].1).collect();
        columns.push(Column::new((*name).into(), v));
    }
    DataFrame::new(rows.len(), columns)
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

/// Write both CSV files of a run into `dir`.
pub fn write_csv(dir: &Path, run: &RunResult) -> PolarsResult<()> {
    std::fs::create_dir_all(dir)?;
    let safe = run.table.replace(['/', '\\'], "_");
    let mut rows = rows_frame(run)?;
    CsvWriter::new(File::create(dir.join(format!("{safe}.csv")))?).finish(&mut rows)?;
    let mut probes = probes_frame(run)?;
    CsvWriter::new(File::create(dir.join(format!("{safe}.probes.csv")))?).finish(&mut probes)?;
    Ok(())
}
