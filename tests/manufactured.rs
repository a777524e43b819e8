//! Manufactured solutions: the shipped scenes with a known exact field, run at the quick tier,
//! their true error against the dofs and the effectivity of their estimator per cycle.

use tribo::experiment;
use tribo::results::{columns, Row};
use tribo::study::{self, Tier};

use crate::common::experiments_dir;

/// The rows of the shipped experiment `id` at the quick tier.
fn quick_rows(id: &str) -> Vec<Row> {
    let path = experiments_dir().join(format!("{id}.toml"));
    let spec = experiment::load(&path).unwrap_or_else(|e| panic!("{id}: {e}"));
    study::run(&spec, Tier::Quick, &|_, _, _| {})
        .unwrap_or_else(|e| panic!("{id}: quick tier fails: {e}"))
        .rows
}

/// Least-squares slope of log y against log x.
fn log_log_slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (xs, ys): (Vec<f64>, Vec<f64>) = points.iter().map(|(x, y)| (x.ln(), y.ln())).unzip();
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let cov: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    cov / xs.iter().map(|x| (x - mx).powi(2)).sum::<f64>()
}

/// Checks one manufactured scene: in every cycle the error and effectivity are finite and
/// positive and the effectivity lies in `band`; over the cycles `window` (inclusive) the
/// least-squares slope of log error against log dofs lies in [−0.60, −0.40] (Q₁ in 2-D on
/// adaptive meshes: −½). Every failure names the scene and the cycle.
fn check_scene(id: &str, window: [usize; 2], band: [f64; 2]) {
    let rows = quick_rows(id);
    assert!(
        rows.len() > window[1],
        "{id}: {} quick rows, the window ends at cycle {}",
        rows.len(),
        window[1]
    );
    for r in &rows {
        let cycle = r.cycle;
        let error = r.value(columns::ERROR);
        let effectivity = r.value(columns::EFFECTIVITY);
        let (Some(error), Some(effectivity)) = (error, effectivity) else {
            panic!("{id}, cycle {cycle}: error {error:?}, effectivity {effectivity:?}");
        };
        assert!(
            error.is_finite() && error > 0.0,
            "{id}, cycle {cycle}: error {error}"
        );
        assert!(
            (band[0]..=band[1]).contains(&effectivity),
            "{id}, cycle {cycle}: effectivity {effectivity} outside {band:?}"
        );
    }
    let points: Vec<(f64, f64)> = rows[window[0]..=window[1]]
        .iter()
        .map(|r| {
            (
                r.value(columns::DOFS).unwrap(),
                r.value(columns::ERROR).unwrap(),
            )
        })
        .collect();
    let slope = log_log_slope(&points);
    assert!(
        (-0.60..=-0.40).contains(&slope),
        "{id}, cycles {}–{}: error order {slope:.3} against dofs outside [−0.60, −0.40]",
        window[0],
        window[1]
    );
}

/// `manufactured-elasticity` (s = (w, w) with an arctan cross, Theorem III.12): the order over
/// cycles 4–9 and an effectivity in [8, 13] in every cycle. Measured at the quick tier: 9.3 to
/// 11.0, rising slowly from cycle 1 on and settling at 10.9–11.0 once the front is resolved.
/// The estimator's constant c = 1 with h_Q the cell diagonal was calibrated on the thesis's
/// printed estimates, not derived, so only a band can be asked of it: the lower bound keeps
/// the estimate well above the error (reliability with the measured constant), the upper one
/// fails a residual that grows against the error; both sit about 15 % outside the measured
/// values.
#[test]
fn manufactured_elasticity_converges_at_order_one_half_with_a_steady_effectivity() {
    check_scene("manufactured-elasticity", [4, 9], [8.0, 13.0]);
}
