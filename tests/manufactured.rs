//! Manufactured solutions: the shipped scenes with a known exact field, run at the quick tier,
//! their true error against the dofs and the effectivity of their estimator per cycle.

use tribo::experiment;
use tribo::results::{columns, Row};
use tribo::study::{self, Tier};

use crate::common::{experiments_dir, refused_at, scratch};

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

/// `manufactured-reynolds` (ψ = 200 + 1000·w on the linear gap of §IV.3.1, Theorem III.16): the
/// order over cycles 4–9 and an effectivity in [4.5, 8.5] in every cycle.
/// Measured at the quick tier: 5.3 to 7.1, 7.1 on the coarse grid that does not resolve the
/// front, then 5.3 and rising to 6.3 from cycle 5 on. The band has the same reasons and margins
/// as the elasticity one (c = 1 and h_Q the diagonal, as in the fluid tables).
#[test]
fn manufactured_reynolds_converges_at_order_one_half_with_a_steady_effectivity() {
    check_scene("manufactured-reynolds", [4, 9], [4.5, 8.5]);
}

/// A scene with `exact` is refused, naming the field, where the exact field would not solve it:
/// another domain, a side that is not clamped, a load of its own; a Reynolds film with
/// cavitation or with the thesis-code estimator.
#[test]
fn manufactured_scene_refuses_data_the_exact_field_does_not_meet() {
    let dir = scratch("manufactured-refused");
    let cases = [
        (
            "x = [0.0, 1.0], y = [0.0, 1.0]",
            "x = [0.0, 2.0], y = [0.0, 1.0]",
            "scene.domain",
            "unit square",
        ),
        (
            r#"dirichlet = ["left", "right", "bottom", "top"]"#,
            r#"dirichlet = ["left", "right"]"#,
            "scene.elasticity.dirichlet",
            "all four sides",
        ),
        (
            r#"exact = "arctan-cross""#,
            "exact = \"arctan-cross\"\nvolume_load = { direction = [0.0, 1.0], profile = \
             { kind = \"constant\", amplitude = 1.0 } }",
            "scene.elasticity.volume_load",
            "derived from the field",
        ),
    ];
    refuse_edits("manufactured-elasticity", &cases, &dir);
    let cases = [
        (
            r#"cavitation = "off""#,
            r#"cavitation = "auto""#,
            "scene.reynolds.cavitation",
            "the exact pressure is positive",
        ),
        (
            r#"estimator = "theorem""#,
            r#"estimator = "thesis-code""#,
            "scene.reynolds.estimator",
            "derived from the pressure",
        ),
    ];
    refuse_edits("manufactured-reynolds", &cases, &dir);
}

/// Each of `cases` (text replaced, its replacement, the field and a phrase of the message)
/// applied to the shipped file `id` alone is refused naming the field.
fn refuse_edits(id: &str, cases: &[(&str, &str, &str, &str)], dir: &std::path::Path) {
    let text =
        std::fs::read_to_string(experiments_dir().join(format!("{id}.toml"))).expect("shipped");
    for (i, (from, to, field, needle)) in cases.iter().enumerate() {
        assert!(text.contains(from), "test setup: `{from}` not found");
        let path = dir.join(format!("{id}-case{i}/{id}.toml"));
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
        refused_at(&path, field, needle);
    }
}

/// `manufactured-substokes` (χ = curl(10⁴ q(x₁)q(x₂)), q(t) = t³(1 − t)³, ψ = 200 + 1000·w on
/// the linear gap of §IV.3.1, Theorem III.23 with the tables' literal stabilisation term): the
/// order over cycles 4–9 and an effectivity in [23, 52] in every cycle. Measured at the quick
/// tier: order −0.45, effectivity 27.0 to 45.3 — 45.3 on the coarse grid, 34–38 in cycles 1–4,
/// 27–31 from cycle 5 on. The effectivity is high because the literal stabilisation term
/// δ_Q²‖∇ψ_h − κ − γ‖² with δ_Q = h_Q carries the whole source (here 12χ/g² and ψ∇g/g of
/// order 10⁴) and dominates η; the band sits about 15 % outside the measured values.
///
/// The reference error of the SubStokes tables ([`tribo::study::reference`], `measured_error`
/// here, where the exact `error` is known) is within 10 % of the true error from cycle 2 on
/// (measured: within 6.2 %, the largest deviation in the last cycle, whose value rests on the
/// extrapolated e_ref).
#[test]
fn manufactured_substokes_converges_at_order_one_half_with_a_steady_effectivity() {
    let id = "manufactured-substokes";
    check_scene(id, [4, 9], [23.0, 52.0]);
    for r in quick_rows(id).iter().filter(|r| r.cycle >= 2) {
        let (Some(error), Some(measured)) = (
            r.value(columns::ERROR),
            r.value(columns::MEASURED_ERROR),
        ) else {
            panic!("{id}, cycle {}: no error or measured_error", r.cycle);
        };
        let deviation = measured / error - 1.0;
        assert!(
            deviation.abs() <= 0.10,
            "{id}, cycle {}: reference error {measured:.4e} against the true error {error:.4e} \
             ({:+.1} %), outside ±10 %",
            r.cycle,
            100.0 * deviation
        );
    }
}

/// A SubStokes scene with `exact` is refused, naming the field, where the exact field would not
/// solve it: another domain, `cavitation = "auto"`, the point condition, the Uzawa solver.
#[test]
fn manufactured_substokes_refuses_data_the_exact_field_does_not_meet() {
    let dir = scratch("manufactured-substokes-refused");
    let cases = [
        (
            "x = [0.0, 1.0], y = [0.0, 1.0]",
            "x = [0.0, 2.0], y = [0.0, 1.0]",
            "scene.domain",
            "unit square",
        ),
        (
            r#"cavitation = "off""#,
            r#"cavitation = "auto""#,
            "scene.substokes.cavitation",
            "the exact pressure is positive",
        ),
        (
            r#"exact = "arctan-cross""#,
            "exact = \"arctan-cross\"\npoint = \"corner\"",
            "scene.substokes.point",
            "not g v̄ at a corner",
        ),
        (
            r#"exact = "arctan-cross""#,
            "exact = \"arctan-cross\"\nsolver = \"uzawa\"",
            "scene.substokes.solver",
            "\"ldlt\"",
        ),
    ];
    refuse_edits("manufactured-substokes", &cases, &dir);
}
