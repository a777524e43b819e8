//! The true error of a section (`crate::study::accuracy`): how it was measured, the
//! effectivity range, and the uniform run beside a grid-adaptive table with what adaptivity
//! saves (`crate::study::uniform`). The per-row `error` and `effectivity` are columns of the
//! section's own table and of `data/<table>.csv`; the uniform run is `data/<table>.uniform.csv`.

use std::fmt::Write as _;

use super::{fmt_seconds, fmt_sig};
use crate::report::{effectivity_range, fmt_effectivity};
use crate::results::{ErrorMeasure, RunResult};
use crate::study::uniform::saving;

/// How the error of a run was measured, in one sentence.
fn measure_sentence(measure: &ErrorMeasure) -> String {
    match measure {
        ErrorMeasure::Energy {
            limit,
            beta,
            cycles,
            bound,
        } => {
            let (first, last) = (cycles.first().unwrap_or(&0), cycles.last().unwrap_or(&0));
            let how = if *bound {
                "the energy bound ‖u − u_h‖ ≤ √(2(J(u_h) − J(u))) (a variational inequality: \
                 an upper bound of the error, so the effectivity is a lower bound)"
            } else {
                "the energy identity ‖u − u_h‖ = √(2(J(u_h) − J(u)))"
            };
            format!(
                "error is measured by {how}, with J(u) = {} extrapolated from cycles \
                 {first}–{last} by J(u_h) = J(u) + C·dofs<sup>−{}</sup>",
                fmt_sig(*limit),
                format_args!("{beta:.2}")
            )
        }
        ErrorMeasure::LastSolve {
            effectivity,
            cycles,
        } => {
            let (first, last) = (cycles.first().unwrap_or(&0), cycles.last().unwrap_or(&0));
            format!(
                "error is measured against the run's own last solve, in the estimator's norm: \
                 the distance of each cycle's solution to it, plus the last solve's own \
                 error, extrapolated as its estimate divided by {}, the effectivity fitted to \
                 the distances of cycles {first}–{last}. The last row's effectivity is that \
                 extrapolation, not a measurement",
                fmt_sig(*effectivity)
            )
        }
        ErrorMeasure::Reference { dofs, seconds } => format!(
            "error is measured against a reference solution on the overlay of the run's meshes \
             refined once ({dofs} unknowns, solved in {} after the run), with the reference's \
             own error extrapolated",
            fmt_seconds(*seconds)
        ),
    }
}

/// The true-error paragraph and the uniform run of a section; nothing for a run without a
/// measured error.
pub(super) fn true_error(h: &mut String, run: &RunResult) {
    let Some(measure) = &run.accuracy else {
        return;
    };
    let _ = writeln!(
        h,
        "<h3>True error</h3>\n<p>The {}; effectivity η / error {} over the rows (columns \
         <code>error</code>, <code>effectivity</code>).</p>",
        measure_sentence(measure),
        fmt_effectivity(effectivity_range(run))
    );
    if run.uniform.is_empty() {
        return;
    }
    let uniform_measure = match measure {
        ErrorMeasure::Energy { .. } => "by the energy with the adaptive run's J(u)",
        ErrorMeasure::LastSolve { .. } | ErrorMeasure::Reference { .. } => {
            "against the uniform run's own last solve, its error carried from the estimator's \
             effectivity over the cycles before"
        }
    };
    let _ = writeln!(
        h,
        "<details><summary>Adaptive against uniform refinement (each uniform cycle's error \
         measured {uniform_measure})</summary>"
    );
    h.push_str(
        "\
         <div class=\"scroll\"><table>\n<thead><tr><th>uniform cycle</th><th>cells</th>\
         <th>dofs</th><th>error</th><th>estimate</th><th>seconds</th></tr></thead>\n<tbody>\n",
    );
    for u in &run.uniform {
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            u.cycle,
            u.active_cells,
            u.dofs,
            u.error.map_or("—".into(), fmt_sig),
            fmt_sig(u.estimate),
            fmt_seconds(u.seconds),
        );
    }
    h.push_str("</tbody></table></div></details>\n");
    let Some(s) = saving(run, &run.uniform) else {
        h.push_str(
            "<p>Adaptive against uniform: no saving could be measured (fewer than two uniform \
             cycles with an error, or a uniform error that does not decrease).</p>\n",
        );
        return;
    };
    let how = if s.extrapolated {
        format!(
            "extrapolated with the uniform run's own order {:.2} (no uniform cycle reached it; \
             the last has {} dofs)",
            s.uniform_order,
            run.uniform.last().map_or(0, |u| u.dofs)
        )
    } else {
        "interpolated between the uniform cycles that bracket it".to_string()
    };
    let _ = writeln!(
        h,
        "<p class=\"saving\"><b>What adaptivity saves:</b> the adaptive run reaches error {} with \
         {} dofs in {} over all its cycles; a uniform mesh needs about {} dofs ({}× as many) and \
         {} for a single solve ({}× the adaptive run) — {how}.</p>",
        fmt_sig(s.error),
        s.adaptive_dofs as u64,
        fmt_seconds(s.adaptive_seconds),
        fmt_sig(s.uniform_dofs.round()),
        ratio(s.uniform_dofs / s.adaptive_dofs),
        fmt_seconds(s.uniform_seconds),
        ratio(s.uniform_seconds / s.adaptive_seconds),
    );
}

/// A ratio with two significant digits (`0.13`, `1.2`, `35`).
fn ratio(r: f64) -> String {
    if r >= 10.0 {
        format!("{r:.0}")
    } else {
        let digits = (1 - r.log10().floor() as i32).max(0) as usize;
        format!("{r:.digits$}")
    }
}
