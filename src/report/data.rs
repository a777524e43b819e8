//! Per-table result data (`report/data/<table>.csv`, `<table>.probes.csv`, …), each file also
//! as Parquet (`<table>.parquet`, `<table>.probes.parquet`, …), built as polars data frames so
//! that the columns follow the `column` names of the printed tables; the rows beside the printed
//! columns (`<table>.joined.csv`/`.parquet`); and the last mesh with its fields
//! (`<table>.vtu`, [`super::vtk`]).
//!
//! An undefined value (the first `ratio`) is an empty cell in the CSV files and a null in the
//! Parquet files; no file holds NaN or an infinity.

use std::path::Path;

use polars::prelude::*;

use crate::results::UzawaRow;
use crate::results::{CostRow, PhaseSeconds, RunResult, UniformRow, Value};
use crate::thesis::ThesisTable;

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

/// The uniform run beside a grid-adaptive table: `cycle, active_cells, dofs, estimate, error,
/// seconds` (`error` empty where it could not be measured).
pub fn uniform_frame(rows: &[UniformRow]) -> PolarsResult<DataFrame> {
    let counts = |f: fn(&UniformRow) -> usize| rows.iter().map(|u| f(u) as u64).collect::<Vec<_>>();
    DataFrame::new(
        rows.len(),
        vec![
            Column::new("cycle".into(), counts(|u| u.cycle)),
            Column::new("active_cells".into(), counts(|u| u.active_cells)),
            Column::new("dofs".into(), counts(|u| u.dofs)),
            Column::new(
                "estimate".into(),
                rows.iter().map(|u| u.estimate).collect::<Vec<_>>(),
            ),
            Column::new(
                "error".into(),
                rows.iter().map(|u| u.error).collect::<Vec<_>>(),
            ),
            Column::new(
                "seconds".into(),
                rows.iter().map(|u| u.seconds).collect::<Vec<_>>(),
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

/// Write `frame` as `<dir>/<name>.csv` and `<dir>/<name>.parquet`.
fn write_frame(dir: &Path, name: &str, frame: &mut DataFrame) -> PolarsResult<()> {
    crate::fsio::write_with(&dir.join(format!("{name}.csv")), |f| {
        CsvWriter::new(f).finish(frame)
    })?;
    crate::fsio::write_with(&dir.join(format!("{name}.parquet")), |f| {
        ParquetWriter::new(f).finish(frame)
    })?;
    Ok(())
}

/// Write the data files of a run into `dir`, each as CSV and as Parquet: rows (a solver
/// study's iterations in their place), probes and, when the run has them, the cuts
/// (`<table>.cuts.*`), the costs (`<table>.cost.*`) and the uniform run (`<table>.uniform.*`).
pub fn write_frames(dir: &Path, run: &RunResult) -> PolarsResult<()> {
    std::fs::create_dir_all(dir)?;
    let safe = csv_stem(&run.table);
    let mut rows = if run.uzawa.is_empty() {
        rows_frame(run)?
    } else {
        uzawa_frame(&run.uzawa)?
    };
    write_frame(dir, &safe, &mut rows)?;
    let mut probes = probes_frame(run)?;
    write_frame(dir, &format!("{safe}.probes"), &mut probes)?;
    if let Some(cuts) = &run.cuts {
        let mut frame = DataFrame::new(
            cuts.columns.first().map_or(0, |c| c.1.len()),
            cuts.columns
                .iter()
                .map(|(name, values)| Column::new(name.as_str().into(), values.as_slice()))
                .collect(),
        )?;
        write_frame(dir, &format!("{safe}.cuts"), &mut frame)?;
    }
    if !run.costs.is_empty() {
        let mut costs = costs_frame(&run.costs)?;
        write_frame(dir, &format!("{safe}.cost"), &mut costs)?;
    }
    if !run.uniform.is_empty() {
        let mut uniform = uniform_frame(&run.uniform)?;
        write_frame(dir, &format!("{safe}.uniform"), &mut uniform)?;
    }
    Ok(())
}

/// Whether the printed `column` is compared with another tribo value than the column of the
/// same name: the `estimate` and `ratio` of the fluid tables, compared with
/// `estimate_previous_mesh` and its ratio ([`super::compared_value`]).
fn pairs_other_column(run: &RunResult, column: &str) -> bool {
    super::compares_previous_estimate(run) && matches!(column, "estimate" | "ratio")
}

/// tribo's rows beside the printed table: the columns of [`rows_frame`], then for each printed
/// column `c` (other than `cycle`) `thesis_c`, the printed value of the row's cycle (reference
/// data from the thesis, never computed), and `c_rel_diff`, tribo/thesis − 1 with the tribo
/// value the page compares it with. Where that value is not tribo's column `c` (in the fluid
/// tables the printed `estimate` and `ratio` are compared with `estimate_previous_mesh` and its
/// ratio), it is written as `c_compared` before `thesis_c`, so each pair sits side by side.
/// One row per cycle tribo computed; a value that is not printed, printed as `inf`, or a
/// difference to a printed 0 is empty. `None` for a run without printed rows (a figure
/// experiment, a solver study).
pub fn joined_frame(run: &RunResult, thesis: &ThesisTable) -> PolarsResult<Option<DataFrame>> {
    if thesis.is_empty() || run.rows.is_empty() || !run.uzawa.is_empty() {
        return Ok(None);
    }
    let mut frame = rows_frame(run)?;
    let rows = &run.rows;
    for column in thesis.columns.iter().filter(|c| *c != "cycle") {
        let printed: Vec<Option<f64>> = rows
            .iter()
            .map(|r| thesis.value(r.cycle, column).filter(|v| v.is_finite()))
            .collect();
        let integral = rows
            .iter()
            .any(|r| matches!(r.get(column), Some(Value::Count(_))))
            && printed.iter().flatten().all(|v| v.fract() == 0.0);
        if pairs_other_column(run, column) {
            let compared: Vec<Option<f64>> = (0..rows.len())
                .map(|i| super::compared_value(rows, i, column))
                .collect();
            frame.with_column(Column::new(format!("{column}_compared").into(), compared))?;
        }
        let name = format!("thesis_{column}");
        let printed_column = if integral {
            let v: Vec<Option<i64>> = printed.iter().map(|v| v.map(|v| v as i64)).collect();
            Column::new(name.into(), v)
        } else {
            Column::new(name.into(), printed.clone())
        };
        frame.with_column(printed_column)?;
        let diffs: Vec<Option<f64>> = printed
            .iter()
            .enumerate()
            .map(|(i, p)| super::rel_diff(super::compared_value(rows, i, column)?, (*p)?))
            .collect();
        frame.with_column(Column::new(format!("{column}_rel_diff").into(), diffs))?;
    }
    Ok(Some(frame))
}

/// Write `<table>.joined.csv` and `.parquet` ([`joined_frame`]) where the run has printed rows;
/// returns whether it wrote them.
pub fn write_joined(dir: &Path, run: &RunResult, thesis: &ThesisTable) -> PolarsResult<bool> {
    let Some(mut frame) = joined_frame(run, thesis)? else {
        return Ok(false);
    };
    std::fs::create_dir_all(dir)?;
    write_frame(dir, &format!("{}.joined", csv_stem(&run.table)), &mut frame)?;
    Ok(true)
}

/// Write the run's meshes as VTU files ([`super::vtk`]) where it kept any: the last printed
/// one as `<table>.vtu`, each earlier one (`report --vtu all`) as `<table>.cycle-<k>.vtu`, and
/// `<table>.pvd`, the series of them for ParaView (time = the printed cycle, or the load step
/// of the forming). Returns whether it wrote any.
pub fn write_vtu(dir: &Path, run: &RunResult) -> std::io::Result<bool> {
    let Some(last) = &run.last_mesh else {
        return Ok(false);
    };
    std::fs::create_dir_all(dir)?;
    let stem = csv_stem(&run.table);
    let mut series = Vec::new();
    for mesh in &run.cycle_meshes {
        let name = format!("{stem}.cycle-{}.vtu", mesh.cycle);
        super::vtk::write_file(&dir.join(&name), mesh)?;
        series.push((name, mesh.cycle));
    }
    let name = format!("{stem}.vtu");
    super::vtk::write_file(&dir.join(&name), last)?;
    series.push((name, last.cycle));
    super::vtk::write_collection(&dir.join(format!("{stem}.pvd")), &series)?;
    Ok(true)
}

/// Every data file of a run: [`write_frames`], [`write_joined`] and [`write_vtu`].
pub fn write_all(dir: &Path, run: &RunResult, thesis: &ThesisTable) -> PolarsResult<()> {
    write_frames(dir, run)?;
    write_joined(dir, run, thesis)?;
    write_vtu(dir, run)?;
    Ok(())
}
