//! Shared helpers: loading experiments, running the quick tier once per table, comparisons.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, OnceLock};

use tribo::experiment::{self, Experiment, Plan};
use tribo::mesh::Mesh;
use tribo::report::convergence_order;
use tribo::report::{self, Entry, ReportMeta, Section, Written};
use tribo::results::{Row, RunResult, Value};
use tribo::study::{self, Tier};
use tribo::thesis::ThesisTable;

/// A fresh, empty folder for a test's files: `<target>/tmp/tribo-tests/<process>/<name>`,
/// inside the target directory rather than the system's temporary folder. The first call of a
/// test run removes the folders of earlier runs whose process has ended (on Linux, where
/// `/proc` tells), so the suite leaves at most one run's files behind, where `cargo clean`
/// removes them.
pub fn scratch(name: &str) -> PathBuf {
    static ROOT: OnceLock<PathBuf> = OnceLock::new();
    let root = ROOT.get_or_init(|| {
        let base = Path::new(env!("CARGO_TARGET_TMPDIR")).join("tribo-tests");
        if Path::new("/proc/self").exists() {
            for entry in std::fs::read_dir(&base).into_iter().flatten().flatten() {
                let ended = entry
                    .file_name()
                    .to_str()
                    .and_then(|p| p.parse::<u32>().ok())
                    .is_some_and(|pid| !Path::new(&format!("/proc/{pid}")).exists());
                if ended {
                    let _ = std::fs::remove_dir_all(entry.path());
                }
            }
        }
        base.join(std::process::id().to_string())
    });
    let dir = root.join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a scratch folder for the test");
    dir
}

pub fn experiments_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("experiments")
}

pub fn spec(table: &str) -> Experiment {
    experiment::load(&experiments_dir().join(format!("{table}.toml"))).expect("experiment loads")
}

/// Quick-tier result of a table, computed once per test process (tests of the same table wait
/// for the first one).
pub fn quick(table: &str) -> Arc<RunResult> {
    type Slot = Arc<OnceLock<Arc<RunResult>>>;
    static CACHE: OnceLock<Mutex<BTreeMap<String, Slot>>> = OnceLock::new();
    let slot = {
        let mut cache = CACHE
            .get_or_init(|| Mutex::new(BTreeMap::new()))
            .lock()
            .unwrap();
        cache.entry(table.to_string()).or_default().clone()
    };
    slot.get_or_init(|| {
        Arc::new(
            study::run(&spec(table), Tier::Quick, &|_, _, _| {})
                .unwrap_or_else(|e| panic!("quick tier of {table} fails: {e}")),
        )
    })
    .clone()
}

/// Relative difference a/b − 1.
pub fn rel(a: f64, b: f64) -> f64 {
    a / b - 1.0
}

/// The ratios tribo/thesis of a table, one per row of `r`, vary by at most `limit`
/// (largest ÷ smallest − 1).
pub fn assert_ratio_spread(table: &str, r: &RunResult, ratios: &[f64], limit: f64) {
    let cycles: Vec<usize> = r.rows.iter().map(|row| row.cycle).collect();
    let (mut lo, mut hi) = (0, 0);
    for (i, q) in ratios.iter().enumerate() {
        if *q < ratios[lo] {
            lo = i;
        }
        if *q > ratios[hi] {
            hi = i;
        }
    }
    let spread = ratios[hi] / ratios[lo] - 1.0;
    assert!(
        spread <= limit,
        "{table}: ratio tribo/thesis varies by {:.1} % (limit {:.0} %), from {} in cycle {} to {} \
         in cycle {}: {ratios:?}",
        100.0 * spread,
        100.0 * limit,
        ratios[lo],
        cycles[lo],
        ratios[hi],
        cycles[hi]
    );
}

/// Run `check` on every table of `tables` at full tier and collect the failures (a failing table
/// never hides the others); panic at the end with every failure, each naming table, cycle and
/// number. Prints a line per table (run with `--nocapture` to see them).
///
/// With `TRIBO_FULL_REPORT` naming the folder of a full-tier report (as `.ci/run` sets it), the
/// rows are the ones that report wrote ([`report_rows`]): the checks read what the page shows
/// instead of solving every table a second time. Without it, every table runs here.
pub fn full_tier(tables: &[&str], check: fn(&str, &RunResult)) {
    match std::env::var_os("TRIBO_FULL_REPORT") {
        Some(out) => full_tier_of(tables, check, |t| report_rows(Path::new(&out), t)),
        None => full_tier_runs(tables, check),
    }
}

/// [`full_tier`] on fresh runs of the tables, whatever `TRIBO_FULL_REPORT` says: for checks that
/// need more of a run than its rows (the forming's deformed meshes).
pub fn full_tier_runs(tables: &[&str], check: fn(&str, &RunResult)) {
    full_tier_of(tables, check, |t| {
        // The checks read the printed rows, not the true error: the report's data carry that
        // (tests/true_error.rs), so these runs do not measure it again.
        let mut experiment = spec(t);
        experiment.study.true_error = false;
        study::run(&experiment, Tier::Full, &|_, _, _| {})
            .map_err(|e| format!("the run failed: {e}"))
    });
}

/// The rows of `table` as the report in `out` wrote them, read back from
/// `data/<table>.parquet` (the same bits as the run's rows: integer columns become counts,
/// float columns reals, a null a missing or undefined value; the `seconds_*` columns are left
/// out). Only the rows: the run's pictures and notes are not in that file.
pub fn report_rows(out: &Path, table: &str) -> Result<RunResult, String> {
    use polars::prelude::{DataType, ParquetReader, SerReader};
    let path = out
        .join("data")
        .join(format!("{}.parquet", report::data::csv_stem(table)));
    let file = std::fs::File::open(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let frame = ParquetReader::new(file)
        .finish()
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let failed = |e: polars::error::PolarsError| format!("{}: {e}", path.display());
    let cycles = frame
        .column("cycle")
        .map_err(failed)?
        .cast(&DataType::UInt64)
        .map_err(failed)?;
    let cycles = cycles.u64().map_err(failed)?;
    let mut rows: Vec<Row> = (0..cycles.len())
        .map(|i| Row::new(cycles.get(i).unwrap_or_default() as usize))
        .collect();
    let seconds = tribo::results::PhaseSeconds::default()
        .named()
        .map(|(name, _)| name);
    for column in frame.columns() {
        let name = column.name().as_str();
        if name == "cycle" || seconds.contains(&name) {
            continue;
        }
        if column.dtype().is_integer() {
            let values = column.cast(&DataType::Int64).map_err(failed)?;
            let values = values.i64().map_err(failed)?;
            for (i, row) in rows.iter_mut().enumerate() {
                if let Some(n) = values.get(i) {
                    row.set(name, Value::Count(n));
                }
            }
        } else {
            let values = column.cast(&DataType::Float64).map_err(failed)?;
            let values = values.f64().map_err(failed)?;
            for (i, row) in rows.iter_mut().enumerate() {
                row.set(name, Value::Real(values.get(i)));
            }
        }
    }
    let mut run = RunResult::new(table, "", "", "full", [0.0; 4]);
    run.rows = rows;
    Ok(run)
}

fn full_tier_of(
    tables: &[&str],
    check: fn(&str, &RunResult),
    rows_of: impl Fn(&str) -> Result<RunResult, String>,
) {
    let mut failures = Vec::new();
    for &t in tables {
        let start = std::time::Instant::now();
        let r = match rows_of(t) {
            Ok(r) => r,
            Err(e) => {
                failures.push(format!("{t}: {e}"));
                continue;
            }
        };
        let outcome = std::panic::catch_unwind(|| check(t, &r));
        let verdict = match outcome {
            Ok(()) => "holds".to_string(),
            Err(panic) => {
                let message = panic
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_else(|| "a check failed".into());
                failures.push(message.clone());
                format!("FAILS: {message}")
            }
        };
        let last = r.rows.last();
        println!(
            "{t}: {} rows, last dofs {:?}, last estimate {:?}, {:.1} s; agreement and convergence {verdict}",
            r.rows.len(),
            last.and_then(|row| row.dofs()),
            last.and_then(|row| row.estimate()),
            start.elapsed().as_secs_f64()
        );
    }
    assert!(
        failures.is_empty(),
        "{} full-tier check(s) failed:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// The convergence rule over the experiment's window (restricted to the rows computed): the
/// experimental order of convergence — the least-squares slope of log η against log dofs,
/// [`tribo::report::convergence_order`] — lies in [−0.60, −0.40] around the optimal −½ of Q₁
/// elements in two dimensions, and the estimate falls in every cycle of the window.
///
/// The order does not depend on how many cells a cycle marks, so the rule accepts any marking
/// fraction: 30 % gives ratios near 1/√2 per cycle, 10 % ratios near 0.9 at the same order. The
/// foundation's per-cycle band (every ratio in [0.60, 0.85], geometric mean in [0.66, 0.76])
/// held only for 30 %.
pub fn assert_convergence(table: &str, r: &RunResult) {
    let w = spec(table)
        .study
        .convergence_window()
        .unwrap_or_else(|| panic!("{table} has no convergence window"));
    if let Err(message) = convergence_rule(&r.rows, w) {
        panic!("{table}: {message}");
    }
}

/// [`assert_convergence`] on `rows` and window `[first, last]`: the order over the window, or
/// what breaks the rule (naming the cycle where one does).
pub fn convergence_rule(rows: &[Row], [first, last]: [usize; 2]) -> Result<f64, String> {
    let inside: Vec<&Row> = rows
        .iter()
        .filter(|row| first <= row.cycle && row.cycle <= last)
        .collect();
    let points: Vec<(f64, f64)> = inside
        .iter()
        .filter_map(|row| Some((row.dofs()? as f64, row.estimate()?)))
        .collect();
    let order = convergence_order(&points).ok_or_else(|| {
        format!(
            "fewer than three rows with dofs and a positive estimate in the window              [{first}, {last}]: {points:?}"
        )
    })?;
    if !(-0.60..=-0.40).contains(&order) {
        return Err(format!(
            "order of convergence {order:.3} over the window [{first}, {last}] outside              [−0.60, −0.40] (dofs, estimate: {points:?})"
        ));
    }
    for row in &inside {
        if let Some(q) = row.ratio().filter(|q| *q >= 1.0) {
            return Err(format!(
                "cycle {}: the estimate does not fall (ratio {q}) although the order over                  [{first}, {last}] is {order:.3}",
                row.cycle
            ));
        }
    }
    Ok(order)
}

/// Refine the cells touching point `p` `levels` times.
pub fn refine_around(mesh: &mut Mesh, p: [f64; 2], levels: usize) {
    for _ in 0..levels {
        let flags: Vec<bool> = mesh
            .active()
            .iter()
            .map(|&c| {
                let b = mesh.cell_box(c);
                p[0] >= b[0] && p[0] <= b[2] && p[1] >= b[1] && p[1] <= b[3]
            })
            .collect();
        let none = vec![false; flags.len()];
        mesh.refine_and_coarsen(&flags, &none).unwrap();
    }
}

/// Every table's quick tier against its golden snapshot `golden/<table>.snap`.
pub fn assert_golden(tables: &[&str]) {
    for &t in tables {
        let r = quick(t);
        insta::with_settings!({ snapshot_path => "../golden", prepend_module_to_snapshot => false }, {
            insta::assert_snapshot!(t, r.snapshot());
        });
    }
}

/// The cycle-0 estimate of a table rounds to the printed 4 decimals.
pub fn assert_printed_cycle_zero(table: &str, printed: f64) {
    let e = quick(table).rows[0].estimate().unwrap();
    assert!(
        ((e * 1e4).round() / 1e4 - printed).abs() < 1e-12,
        "{table}: cycle-0 estimate {e} is not {printed}"
    );
}

/// Every row within `dofs_tol` of the thesis dofs and, if given, `estimate_tol` of its estimate;
/// returns the ratios tribo/thesis of the estimate.
pub fn assert_thesis_rows(
    t: &str,
    r: &RunResult,
    dofs_tol: f64,
    estimate_tol: Option<f64>,
) -> Vec<f64> {
    let thesis = ThesisTable::of(&spec(t));
    let mut ratios = Vec::new();
    for row in &r.rows {
        let dofs = thesis.value(row.cycle, "dofs").unwrap();
        let est = thesis.value(row.cycle, "estimate").unwrap();
        let (tribo_dofs, estimate) = (row.value("dofs").unwrap(), row.estimate().unwrap());
        assert!(
            rel(tribo_dofs, dofs).abs() <= dofs_tol,
            "{t} cycle {}: dofs {tribo_dofs} vs thesis {dofs} (tolerance {dofs_tol})",
            row.cycle,
        );
        if let Some(tol) = estimate_tol {
            assert!(
                rel(estimate, est).abs() <= tol,
                "{t} cycle {}: estimate {estimate} vs thesis {est} (tolerance {tol})",
                row.cycle,
            );
        }
        ratios.push(estimate / est);
    }
    ratios
}

/// Rows with `dofs` and an estimate c·dofs^order, ratios filled in as the study does.
fn rows_of_order(dofs: &[usize], order: f64) -> Vec<Row> {
    let mut rows: Vec<Row> = Vec::new();
    for (cycle, &n) in dofs.iter().enumerate() {
        let estimate = 5.0 * (n as f64).powf(order);
        let ratio = rows
            .last()
            .and_then(|r: &Row| r.estimate())
            .map(|e| estimate / e);
        rows.push(
            Row::new(cycle)
                .count("dofs", n)
                .real("estimate", Some(estimate))
                .real("ratio", ratio),
        );
    }
    rows
}

/// Marking 10 % of the cells grows the dofs by about a fifth per cycle: the ratios are 0.91,
/// outside the old per-cycle band [0.60, 0.85], and the rule still accepts the order −½; an
/// order of −0.3 (a singularity the marking does not resolve) or a cycle whose estimate grows
/// is rejected with the number.
#[test]
fn the_convergence_rule_judges_the_order_not_the_marking_fraction() {
    let slow: Vec<usize> = (0..8).map(|k| (1000.0 * 1.2f64.powi(k)) as usize).collect();
    let rows = rows_of_order(&slow, -0.5);
    assert!(rows[3].ratio().unwrap() > 0.9);
    let order = convergence_rule(&rows, [2, 7]).unwrap();
    assert!((order + 0.5).abs() < 1e-3, "{order}");

    let fast: Vec<usize> = (0..8).map(|k| 100 * 2usize.pow(k)).collect();
    let poor = convergence_rule(&rows_of_order(&fast, -0.3), [2, 7]).unwrap_err();
    assert!(poor.contains("order of convergence -0.300"), "{poor}");

    let mut bump = rows_of_order(&fast, -0.5);
    let estimate = bump[4].estimate().unwrap() * 1.9;
    bump[4].set("estimate", Value::real(Some(estimate)));
    bump[4].set("ratio", Value::real(Some(1.9 / 2f64.sqrt())));
    let rule = convergence_rule(&bump, [2, 7]);
    assert!(
        rule.as_ref().is_err_and(|m| m.contains("cycle 4")),
        "{rule:?}"
    );
    assert!(
        convergence_rule(&rows, [6, 7]).is_err(),
        "two rows give no order"
    );
}

/// A real run with another marking fraction: IV.1 marking 10 % of the cells per cycle (nine rows)
/// converges at the optimal order although every ratio lies above the 30 % band.
#[test]
fn iv1_with_a_smaller_marking_fraction_passes_the_convergence_rule() {
    let mut e = spec("IV.1");
    let Plan::GridAdaptive { grid, .. } = &mut e.study.plan else {
        panic!("IV.1 is grid-adaptive");
    };
    grid.refine = 0.10;
    e.study.rows = 9;
    let r = study::run(&e, Tier::Full, &|_, _, _| {}).unwrap();
    let ratios: Vec<f64> = r
        .rows
        .iter()
        .skip(2)
        .filter_map(|row| row.ratio())
        .collect();
    assert!(
        ratios.iter().all(|q| *q > 0.85),
        "10 % marking should leave the 30 % band in every cycle: {ratios:?}"
    );
    let order = convergence_rule(&r.rows, [2, 8]).unwrap();
    assert!((-0.60..=-0.40).contains(&order), "{order}");
}

/// A table with nothing printed (a figure experiment), of thesis section `section`.
pub fn no_thesis(table: &str, section: &str) -> ThesisTable {
    ThesisTable {
        table: table.into(),
        section: section.into(),
        columns: vec![],
        rows: vec![],
        duplicate_of: None,
        additive_part: None,
        comparison: Default::default(),
        figures: Default::default(),
    }
}

/// The report of `sections` (each run with its printed table) in a fresh folder `name`; every
/// figure must be drawn.
pub fn report_of(name: &str, sections: &[(&RunResult, &ThesisTable)]) -> (PathBuf, Written) {
    let entries: Vec<Entry> = sections
        .iter()
        .map(|(run, thesis)| {
            Entry::Done(Section {
                run,
                thesis,
                alternatives: &[],
            })
        })
        .collect();
    let meta = ReportMeta {
        tier: "quick".into(),
        generated_by: "tribo test".into(),
        total_seconds: 0.1,
        threads: 1,
        provenance: Default::default(),
        alongside: Default::default(),
    };
    let dir = crate::cli::temp_dir(&format!("report-of-{name}"));
    let written = report::write_report(&dir, &entries, &meta).unwrap();
    assert!(
        written.figure_failures.is_empty(),
        "{:?}",
        written.figure_failures
    );
    (dir, written)
}

/// A CSV file without its columns of seconds (`seconds_*`, and `seconds` of the Uzawa rows).
pub fn without_seconds(csv: &str) -> String {
    let mut lines = csv.lines();
    let Some(header) = lines.next() else {
        return String::new();
    };
    let keep: Vec<bool> = header
        .split(',')
        .map(|c| !c.starts_with("seconds"))
        .collect();
    let pick = |line: &str| -> String {
        line.split(',')
            .zip(&keep)
            .filter(|(_, k)| **k)
            .map(|(c, _)| c)
            .collect::<Vec<_>>()
            .join(",")
    };
    let mut out = pick(header);
    for line in lines {
        out.push('\n');
        out += &pick(line);
    }
    out
}

/// The error of loading the experiment file at `path`: the file does not load, and the message
/// names the file and `field` and contains `needle`.
pub fn refused_at(path: &Path, field: &str, needle: &str) -> experiment::ExperimentError {
    let error = match experiment::load(path) {
        Ok(_) => panic!("{}: expected an error, the file loaded", path.display()),
        Err(error) => error,
    };
    let message = error.to_string();
    assert!(message.contains(&path.display().to_string()), "{message}");
    assert_eq!(error.field(), Some(field), "{message}");
    assert!(message.contains(needle), "no `{needle}` in: {message}");
    error
}

/// The columns of a CSV file by name (empty cells as `None`).
pub fn read_csv(path: &Path) -> BTreeMap<String, Vec<Option<f64>>> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let names: Vec<&str> = lines.next().expect("header").split(',').collect();
    let mut columns: BTreeMap<String, Vec<Option<f64>>> =
        names.iter().map(|n| (n.to_string(), Vec::new())).collect();
    for line in lines {
        for (name, cell) in names.iter().zip(line.split(',')) {
            columns
                .get_mut(*name)
                .unwrap()
                .push(cell.parse::<f64>().ok());
        }
    }
    columns
}
