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
fn check_scene(id: &str, window: [usize; 2], band: [f64; 2]) -> Vec<Row> {
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
    rows
}

/// The known active set (or cavitation zone) is found in the last quick cycle: the column
/// `mismatch` of its row (vertices away from the cells the free boundary crosses whose
/// computed state differs from the exact one) is 0.
fn check_free_boundary(id: &str, rows: &[Row], mismatch: &str) {
    let last = rows.last().expect("rows");
    let count = last.value(mismatch);
    assert_eq!(
        count,
        Some(0.0),
        "{id}, cycle {}: {mismatch} = {count:?}, expected 0",
        last.cycle
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
    let _ = check_scene("manufactured-elasticity", [4, 9], [8.0, 13.0]);
}

/// `manufactured-reynolds` (ψ = 200 + 1000·w on the linear gap of §IV.3.1, Theorem III.16): the
/// order over cycles 4–9 and an effectivity in [4.5, 8.5] in every cycle.
/// Measured at the quick tier: 5.3 to 7.1, 7.1 on the coarse grid that does not resolve the
/// front, then 5.3 and rising to 6.3 from cycle 5 on. The band has the same reasons and margins
/// as the elasticity one (c = 1 and h_Q the diagonal, as in the fluid tables).
#[test]
fn manufactured_reynolds_converges_at_order_one_half_with_a_steady_effectivity() {
    let _ = check_scene("manufactured-reynolds", [4, 9], [4.5, 8.5]);
}

/// `manufactured-z-contact` (the body on the flat obstacle, contact on x₁ ∈ [0.3, 0.7],
/// Theorem III.15 with the z-code's term set): the order over cycles 4–9, an effectivity in
/// [8.0, 11.4] in every cycle and the known contact set in the last quick cycle. Measured at
/// the quick tier: effectivity 9.43 to 9.91 (rising slowly from 9.4 at cycles 1–3 to 9.9 at
/// cycle 9), order −0.51; the band sits about 15 % outside the measured range, for the
/// reasons of the elasticity band (c = 1 calibrated, not derived).
#[test]
fn manufactured_z_contact_converges_at_order_one_half_and_finds_its_contact_set() {
    let id = "manufactured-z-contact";
    let rows = check_scene(id, [4, 9], [8.0, 11.4]);
    check_free_boundary(id, &rows, "contact_set_mismatch");
}

/// `manufactured-signorini` (the tilted obstacle, the Signorini condition linearised once per
/// cycle, Theorem III.15 with the Signorini code's term set): the order over cycles 4–9, an
/// effectivity in [7.2, 10.5] in every cycle and the known contact set in the last quick
/// cycle. Measured at the quick tier: effectivity 8.46 to 9.11, order −0.51.
#[test]
fn manufactured_signorini_converges_at_order_one_half_and_finds_its_contact_set() {
    let id = "manufactured-signorini";
    let rows = check_scene(id, [4, 9], [7.2, 10.5]);
    check_free_boundary(id, &rows, "contact_set_mismatch");
}

/// `manufactured-cavitation` (ψ = (F₊)² with a cavitation zone about the centre, Theorem
/// III.17): the order over cycles 4–9, an effectivity in [5.0, 7.4] in every cycle and the
/// known cavitation zone in the last quick cycle. Measured at the quick tier: effectivity 5.89
/// to 6.47, order −0.51; the zone differs from the known one at 8 vertices next to the cells the
/// free boundary crosses in cycles 4 and 6 (ψ ~ dist² is below the discretisation error there),
/// at none in the other cycles.
#[test]
fn manufactured_cavitation_converges_at_order_one_half_and_finds_its_zone() {
    let id = "manufactured-cavitation";
    let rows = check_scene(id, [4, 9], [5.0, 7.4]);
    check_free_boundary(id, &rows, "cavitation_zone_mismatch");
}

/// The error measured as on a scene without an exact solution (the energy identity with J(u)
/// extrapolated, `tribo::study::accuracy`, column `measured_error`) against the true error:
/// within 10 % from the third cycle (cycle 2) on, in every cycle of the quick tier. Measured:
/// within 0.5 % up to cycle 5 on both scenes, then growing with the weight of the extrapolated
/// J(u) in the last cycles, to −1.5 % (elasticity) and +6.7 % (Reynolds) in cycle 9; at the
/// full tier −4.0 % and +7.7 % in cycle 11. The cavitation scene, where the energy only bounds
/// the error, within 2.4 % at the quick tier and 8.2 % at the full tier. The check fails when
/// J(u_h) is integrated with the assembly's 2×2 points instead of 4×4 (Reynolds, cycle 2:
/// +11.4 %).
///
/// The cavitation scene's error in the Reynolds norm against a reference solve on the last mesh
/// refined once (`reference_error`), as the cavitation tables whose energy falls irregularly
/// (IV.64) are measured: within 10 % (measured: within 0.1 % at the quick tier, 0.5 % at the
/// full tier). Against its own last solve
/// (`last_solve_error`), as the uniform runs beside them are measured: within +2.0 % at the
/// quick tier (cycle 9), +5.1 % at the full tier (cycle 11).
fn check_measured_error(id: &str) {
    check_within_ten_percent(id, columns::MEASURED_ERROR);
}

/// The column `measured` of the scene `id` is within 10 % of the true `error` from cycle 2 on.
fn check_within_ten_percent(id: &str, measured: &str) {
    check_within(id, measured, 0.10);
}

/// The column `measured` of the scene `id` is within the fraction `tolerance` of the true
/// `error` from cycle 2 on.
fn check_within(id: &str, measured: &str, tolerance: f64) {
    for r in quick_rows(id).iter().filter(|r| r.cycle >= 2) {
        let (Some(truth), Some(value)) = (r.value(columns::ERROR), r.value(measured)) else {
            panic!("{id}, cycle {}: no error or no {measured}", r.cycle);
        };
        let off = value / truth - 1.0;
        assert!(
            off.abs() <= tolerance,
            "{id}, cycle {}: {measured} {value:.4e} is {:+.1} % off the true error {truth:.4e}",
            r.cycle,
            100.0 * off
        );
    }
}

#[test]
fn the_measured_error_matches_the_true_error_on_the_manufactured_scenes() {
    check_measured_error("manufactured-elasticity");
    check_measured_error("manufactured-reynolds");
    check_measured_error("manufactured-cavitation");
    check_within_ten_percent("manufactured-cavitation", columns::LAST_SOLVE_ERROR);
    check_within_ten_percent("manufactured-cavitation", columns::REFERENCE_ERROR);
}

/// The contact scenes have no energy (their surface load would have to enter J), so they are
/// measured as the contact tables whose energy bound fails and the model-and-grid tables:
/// against a reference solve on the last mesh refined once, its own error extrapolated
/// (`tribo::study::reference::against_refined_solve`, `measured_error` here): within 2 % from
/// cycle 2 on. Measured: within 0.5 % in every cycle on both scenes at the quick tier (+0.1 %
/// z-contact, +0.5 % Signorini in cycle 9), within 0.3 % at the full tier. The error against
/// the run's own last solve, the last solve's error carried from the estimator's effectivity
/// over the four cycles before, as the uniform runs beside those tables measure theirs
/// (`last_solve_error` here, `tribo::study::reference::against_last_solve`): within 10 %
/// (measured at the quick tier: +2.8 % and +4.4 % in cycle 9; at the full tier +3.3 % and
/// +6.2 % in cycle 11). A power law in the unknowns for the last solve's error instead fails
/// on the z-contact scene (−12 % in cycle 8, −21 % in cycle 9).
#[test]
fn reference_and_last_solve_errors_match_the_true_error_on_the_contact_scenes() {
    for id in ["manufactured-z-contact", "manufactured-signorini"] {
        check_within(id, columns::MEASURED_ERROR, 0.02);
        check_within_ten_percent(id, columns::LAST_SOLVE_ERROR);
    }
}

/// A scene with `exact` is refused, naming the field, where the exact field would not solve it:
/// another domain, a side that is not clamped, a load of its own; a Reynolds film with
/// cavitation or with the thesis-code estimator; a contact field with the wrong clamped sides,
/// a traction of its own, another obstacle, or (the tilted one) the z-model; the cavitating
/// pressure without cavitation.
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
    let cases = [
        (
            r#"dirichlet = ["left", "right", "top"]"#,
            r#"dirichlet = ["left", "right"]"#,
            "scene.elasticity.dirichlet",
            "touches the obstacle on the bottom side",
        ),
        (
            r#"dirichlet = ["left", "right", "top"]"#,
            "dirichlet = [\"left\", \"right\", \"top\"]\ntractions = [{ side = \"bottom\", \
             value = [0.0, 1.0] }]",
            "scene.elasticity.tractions",
            "derived from the field",
        ),
        (
            "level = -0.05",
            "level = -0.04",
            "scene.contact.obstacles",
            "the obstacle of the field",
        ),
    ];
    refuse_edits("manufactured-z-contact", &cases, &dir);
    let cases = [(
        r#"model = "signorini""#,
        r#"model = "z""#,
        "scene.contact.model",
        "meets the Signorini condition",
    )];
    refuse_edits("manufactured-signorini", &cases, &dir);
    let cases = [(
        r#"cavitation = "on""#,
        r#"cavitation = "off""#,
        "scene.reynolds.cavitation",
        "cavitates on a known zone",
    )];
    refuse_edits("manufactured-cavitation", &cases, &dir);
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
/// extrapolated e_ref). The error against the run's own last solve, as the uniform runs beside
/// the SubStokes tables measure theirs (`last_solve_error` here), is within 10 % too (measured:
/// within 6.6 %, in cycle 8; at the full tier +11.6 % in cycle 10, the one before the last).
#[test]
fn manufactured_substokes_converges_at_order_one_half_with_a_steady_effectivity() {
    let id = "manufactured-substokes";
    check_scene(id, [4, 9], [23.0, 52.0]);
    check_within_ten_percent(id, columns::MEASURED_ERROR);
    check_within_ten_percent(id, columns::LAST_SOLVE_ERROR);
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
