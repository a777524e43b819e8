//! Shared helpers: loading experiments, running the quick tier once per table, comparisons.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::{Arc, Mutex, OnceLock};

use tribo::experiment::{self, Experiment};
use tribo::mesh::Mesh;
use tribo::results::RunResult;
use tribo::study::{self, Tier};
use tribo::thesis::ThesisTable;

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
pub fn full_tier(tables: &[&str], check: fn(&str, &RunResult)) {
    let mut failures = Vec::new();
    for &t in tables {
        let start = std::time::Instant::now();
        let r = match study::run(&spec(t), Tier::Full, &|_, _, _| {}) {
            Ok(r) => r,
            Err(e) => {
                failures.push(format!("{t}: the run failed: {e}"));
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

/// The convergence rule of the foundation issue over the experiment's window (restricted to the
/// rows computed): every ratio within [0.60, 0.85], geometric mean within [0.66, 0.76].
pub fn assert_convergence(table: &str, r: &RunResult) {
    let w = spec(table)
        .study
        .convergence_window
        .unwrap_or_else(|| panic!("{table} has no convergence window"));
    let cycles_and_ratios: Vec<(usize, f64)> = r
        .rows
        .iter()
        .filter(|row| row.cycle >= w[0] && row.cycle <= w[1])
        .filter_map(|row| Some((row.cycle, row.ratio()?)))
        .collect();
    let ratios: Vec<f64> = cycles_and_ratios.iter().map(|(_, q)| *q).collect();
    assert!(
        !ratios.is_empty(),
        "{table}: no ratio inside the window {w:?}"
    );
    for (cycle, q) in &cycles_and_ratios {
        assert!(
            (0.60..=0.85).contains(q),
            "{table} cycle {cycle}: ratio {q} outside [0.60, 0.85] (window {w:?}: {ratios:?})"
        );
    }
    let gm = (ratios.iter().map(|q| q.ln()).sum::<f64>() / ratios.len() as f64).exp();
    assert!(
        (0.66..=0.76).contains(&gm),
        "{table}: geometric mean ratio {gm} outside [0.66, 0.76]: {ratios:?}"
    );
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
