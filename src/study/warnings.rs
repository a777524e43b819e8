//! What only a run shows to be suspicious: every estimate 0, an obstacle that is
//! never touched, an estimate that grows where the study expects convergence. Joined to the
//! file's own warnings ([`Experiment::warnings`]) in the run's result.

use crate::experiment::{Experiment, Warning};
use crate::results::{columns, Row};

/// The warnings of a finished run with printed `rows`: the experiment file's, then the run's.
pub fn of_run(experiment: &Experiment, rows: &[Row]) -> Vec<Warning> {
    let mut out = experiment.warnings();
    if rows.is_empty() {
        return out;
    }
    if rows.iter().all(|r| r.estimate() == Some(0.0)) {
        out.push(Warning::new(
            columns::ESTIMATE,
            "every printed estimate is 0: the discrete solution is exact on every mesh, so \
             nothing loads the body or drives the flow (a zero load, zero wall velocities), and \
             every ratio is undefined",
        ));
    }
    experiment.family.run_warnings(experiment, rows, &mut out);
    if let Some((first, last, growth)) = growth_over_window(experiment, rows) {
        out.push(Warning::new(
            "study.convergence_window",
            format!(
                "the estimate grows by ×{growth:.4} per cycle over printed cycles {first}–{last} \
                 (geometric mean of the ratios): the adaptive loop does not converge there"
            ),
        ));
    }
    out
}

/// The printed cycles of the convergence window the run reached and the geometric mean of the
/// estimate ratios over them, when it is above 1.
fn growth_over_window(experiment: &Experiment, rows: &[Row]) -> Option<(usize, usize, f64)> {
    let [first, last] = experiment.study.convergence_window()?;
    let ratios: Vec<(usize, f64)> = rows
        .iter()
        .filter(|r| first < r.cycle && r.cycle <= last)
        .filter_map(|r| Some((r.cycle, r.ratio().filter(|q| *q > 0.0)?)))
        .collect();
    let (reached, _) = *ratios.last()?;
    let mean = (ratios.iter().map(|(_, q)| q.ln()).sum::<f64>() / ratios.len() as f64).exp();
    (mean > 1.0).then_some((first, reached, mean))
}
