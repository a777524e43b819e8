//! Bad-input tests of the experiment loader: every shipped experiment file loads, and every kind
//! of broken file (missing, unreadable, bad TOML, wrong type, unknown or missing field,
//! contradictory data) gives an error that names the file and the field — never a panic.

use std::fs;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use tribo::experiment::{load, load_dir, ExperimentError};
use tribo::linalg::direct::Cause;
use tribo::linalg::SolveError;
use tribo::models::ModelError;
use tribo::study::StudyError;

/// A valid experiment (the setting of §IV.1.1, Table IV.1) that the cases below break.
const VALID: &str = r#"table = "IV.1"
section = "IV.1.1"
title = "Box under a constant volume load"

[scene]
name = "box-constant-load"
domain = { x = [-16.0, 16.0], y = [0.0, 1.0] }
coarse_cells = [64, 2]
effects = ["elasticity"]

[scene.elasticity]
mu = 1.0
lambda = 1.0
dirichlet = ["left", "right"]
volume_load = { direction = [0.0, 1.0], profile = { kind = "constant", amplitude = 0.0004 } }

[study]
kind = "grid-adaptive"
rows = 6
quick_rows = 4
refine_fraction = 0.3
coarsen_fraction = 0.03
convergence_window = [2, 5]

[probes]
x = [-12.0, 0.0, 12.0]
y = [0.5]
components = ["s1", "s2"]

[thesis]
columns = ["cycle", "active_cells", "dofs", "estimate", "ratio"]
rows = [
  [0, 128, 390, 0.6881, inf],
  [1, 245, 676, 0.5118, 0.7439],
  [2, 464, 1200, 0.3743, 0.7312],
  [3, 884, 2138, 0.2860, 0.7642],
  [4, 1682, 3906, 0.2025, 0.7081],
  [5, 3197, 7152, 0.1536, 0.7583],
]
"#;

/// The Reynolds section of (IV.7), §IV.3.1.1.
const REYNOLDS: &str = r#"
[scene.reynolds]
equation = "IV.7"
gap = { kind = "plain", g0 = 0.1 }
upper_wall_velocity = [0.0, 0.0, -10.0]
boundary_pressure = 200.0
cavitation = "off"
estimator = "thesis-code"
"#;

/// The contact section of §IV.2.1.1.
const CONTACT: &str = r#"
[scene.contact]
model = "z"
estimator = "z-code"
obstacles = [{ side = "bottom", shape = { kind = "constant", level = -2.0 } }]
"#;

/// A fresh, empty directory, unique per call.
fn scratch_dir(name: &str) -> PathBuf {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    crate::common::scratch(&format!("bad-input-{n}-{name}"))
}

/// Write `text` as `dir/file_name` and return its path.
fn write(dir: &Path, file_name: &str, text: &str) -> PathBuf {
    let path = dir.join(file_name);
    fs::write(&path, text).expect("write a scratch experiment file");
    path
}

/// `VALID` with `from` replaced by `to` (which must occur).
fn edit(from: &str, to: &str) -> String {
    assert!(VALID.contains(from), "test setup: `{from}` not in VALID");
    VALID.replacen(from, to, 1)
}

/// Load `text` as `IV.1.toml` and return the error, checking that its message names the file
/// and `field` and contains `needle`.
fn expect_error(case: &str, text: &str, field: &str, needle: &str) -> ExperimentError {
    expect_error_in("IV.1.toml", case, text, field, needle)
}

/// [`expect_error`] with the file named `file_name`.
fn expect_error_in(
    file_name: &str,
    case: &str,
    text: &str,
    field: &str,
    needle: &str,
) -> ExperimentError {
    let dir = scratch_dir(case);
    let path = write(&dir, file_name, text);
    let error = match load(&path) {
        Ok(_) => panic!("{case}: expected an error, the file loaded"),
        Err(error) => error,
    };
    let message = error.to_string();
    assert!(
        message.contains(&path.display().to_string()),
        "{case}: message does not name the file:\n{message}"
    );
    assert!(
        message.contains(&format!("`{field}`")),
        "{case}: message does not name field `{field}`:\n{message}"
    );
    assert!(
        message.contains(needle),
        "{case}: message does not contain `{needle}`:\n{message}"
    );
    assert_eq!(error.field(), Some(field), "{case}: field()");
    assert_eq!(error.path(), path.as_path(), "{case}: path()");
    let _ = fs::remove_dir_all(&dir);
    error
}

/// The shipped scenes that are not the thesis's: the manufactured solutions.
const OWN_SCENES: [&str; 6] = [
    "manufactured-cavitation",
    "manufactured-elasticity",
    "manufactured-reynolds",
    "manufactured-signorini",
    "manufactured-substokes",
    "manufactured-z-contact",
];

#[test]
fn every_shipped_experiment_loads() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments");
    let specs = match load_dir(&dir, None) {
        Ok(specs) => specs,
        Err(error) => panic!("{error}"),
    };
    assert!(
        !specs.is_empty(),
        "no experiment files in {}",
        dir.display()
    );
    // Tables in numeric order, then the figure experiments (`fig-IV.<n>`), in numeric order,
    // then the scenes of tribo's own (the manufactured solutions).
    let (tables, rest): (Vec<_>, Vec<_>) = specs.iter().partition(|s| s.table.starts_with("IV."));
    let (figures, own): (Vec<_>, Vec<_>) =
        rest.into_iter().partition(|s| s.table.starts_with("fig-"));
    assert_eq!(
        own.iter().map(|s| s.table.as_str()).collect::<Vec<_>>(),
        OWN_SCENES
    );
    assert_eq!(
        specs.iter().map(|s| &s.table).collect::<Vec<_>>(),
        tables
            .iter()
            .chain(&figures)
            .chain(&own)
            .map(|s| &s.table)
            .collect::<Vec<_>>(),
        "tables before figures"
    );
    let numbers: Vec<u32> = tables
        .iter()
        .map(|s| s.table["IV.".len()..].parse().expect("validated id"))
        .collect();
    assert!(
        numbers.windows(2).all(|w| w[0] < w[1]),
        "not in numeric order: {numbers:?}"
    );
    // Figures: Chapter III before Chapter IV, each in numeric order.
    assert_eq!(
        figures.iter().map(|s| s.table.as_str()).collect::<Vec<_>>(),
        ["fig-III.6", "fig-IV.54", "fig-IV.116"]
    );
    for spec in figures {
        assert!(spec.thesis.rows.is_empty() && spec.thesis.columns.is_empty());
    }
    for spec in tables {
        assert_eq!(
            spec.thesis.rows.len(),
            spec.study.rows,
            "{}: study.rows differs from the number of printed thesis rows",
            spec.table
        );
        // A table marked as a copy must really repeat the rows of its original.
        if let Some(original) = &spec.thesis.duplicate_of {
            let Some(original) = specs.iter().find(|s| &s.table == original) else {
                panic!("{}: duplicate_of names a table without a file", spec.table);
            };
            let same = |a: &[Vec<f64>], b: &[Vec<f64>]| {
                a.len() == b.len()
                    && a.iter().zip(b).all(|(x, y)| {
                        x.len() == y.len()
                            && x.iter()
                                .zip(y)
                                .all(|(p, q)| p == q || (p.is_nan() && q.is_nan()))
                    })
            };
            assert!(
                same(&spec.thesis.rows, &original.thesis.rows),
                "{}: rows differ from {}",
                spec.table,
                original.table
            );
        }
    }
}

#[test]
fn valid_base_file_loads() {
    let dir = scratch_dir("valid");
    let path = write(&dir, "IV.1.toml", VALID);
    let spec = match load(&path) {
        Ok(spec) => spec,
        Err(error) => panic!("{error}"),
    };
    assert_eq!(spec.table, "IV.1");
    assert_eq!(spec.thesis.rows.len(), 6);
    assert!(spec.thesis.rows[0][4].is_infinite());
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn quick_rows_past_rows_has_the_documented_message() {
    let dir = scratch_dir("quick-rows");
    let path = write(&dir, "IV.1.toml", &edit("quick_rows = 4", "quick_rows = 7"));
    let error = load(&path).expect_err("quick_rows > rows");
    assert_eq!(
        error.to_string(),
        format!(
            "{}: field `study.quick_rows`: expected at most study.rows (6), found 7",
            path.display()
        )
    );
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn toml_level_errors_name_file_and_field() {
    expect_error(
        "missing-field",
        &edit("rows = 6\n", ""),
        "study.rows",
        "missing field `rows`",
    );
    expect_error(
        "missing-top-level-field",
        &edit("title = \"Box under a constant volume load\"\n", ""),
        "title",
        "missing field `title`",
    );
    expect_error(
        "missing-inline-field",
        &edit(", y = [0.0, 1.0] }", " }"),
        "scene.domain.y",
        "missing field `y`",
    );
    expect_error(
        "wrong-type",
        &edit("rows = 6", "rows = \"six\""),
        "study.rows",
        "invalid type",
    );
    expect_error(
        "negative-count",
        &edit("coarse_cells = [64, 2]", "coarse_cells = [64, -2]"),
        "scene.coarse_cells[1]",
        "line 8",
    );
    expect_error(
        "unknown-field",
        &edit(
            "kind = \"grid-adaptive\"",
            "kind = \"grid-adaptive\"\ncolour = \"red\"",
        ),
        "study.colour",
        "unknown field `colour`",
    );
    expect_error(
        "unknown-side",
        &edit("[\"left\", \"right\"]", "[\"left\", \"sideways\"]"),
        "scene.elasticity.dirichlet[1]",
        "unknown variant `sideways`",
    );
    expect_error(
        "unknown-profile-kind",
        &edit("kind = \"constant\"", "kind = \"cubic\""),
        "scene.elasticity.volume_load.profile.kind",
        "unknown variant `cubic`",
    );
    expect_error(
        "syntax-error",
        &edit("mu = 1.0", "mu = 1.0.0"),
        "scene.elasticity.mu",
        "TOML parse error",
    );
    expect_error(
        "unterminated-array",
        &edit("y = [0.5]", "y = [0.5"),
        "probes.y[1]",
        "missing comma between array elements",
    );
}

#[test]
fn contradictory_fields_name_file_and_field() {
    let cases: Vec<(&str, String, &str, &str)> = vec![
        (
            "reynolds-section-without-effect",
            edit("\n[study]", &format!("{REYNOLDS}\n[study]")),
            "scene.reynolds",
            "no [scene.reynolds] section, or `reynolds` in scene.effects",
        ),
        (
            "contact-without-elasticity",
            edit("effects = [\"elasticity\"]", "effects = [\"contact\"]")
                .replacen("\n[study]", &format!("{CONTACT}\n[study]"), 1),
            "scene.effects",
            "`elasticity` alongside `contact`",
        ),
        (
            "contact-effect-without-section",
            edit("effects = [\"elasticity\"]", "effects = [\"elasticity\", \"contact\"]"),
            "scene.contact",
            "a [scene.contact] section",
        ),
        (
            "reynolds-with-elasticity",
            edit("effects = [\"elasticity\"]", "effects = [\"elasticity\", \"reynolds\"]"),
            "scene.effects",
            "`reynolds` alone",
        ),
        (
            "duplicate-effect",
            edit("effects = [\"elasticity\"]", "effects = [\"elasticity\", \"elasticity\"]"),
            "scene.effects[1]",
            "each effect listed once",
        ),
        (
            "no-effects",
            edit("effects = [\"elasticity\"]", "effects = []"),
            "scene.effects",
            "at least one",
        ),
        (
            "convergence-window-past-last-row",
            edit("convergence_window = [2, 5]", "convergence_window = [2, 6]"),
            "study.convergence_window[1]",
            "at most study.rows − 1 (5), found 6",
        ),
        (
            "convergence-window-reversed",
            edit("convergence_window = [2, 5]", "convergence_window = [4, 3]"),
            "study.convergence_window",
            "first ≤ last",
        ),
        (
            "zero-rows",
            edit("rows = 6", "rows = 0"),
            "study.rows",
            "at least 1",
        ),
        (
            "fractions-above-one",
            edit("refine_fraction = 0.3", "refine_fraction = 0.99"),
            "study.refine_fraction",
            "≤ 1",
        ),
        (
            "thesis-row-too-short",
            edit("[2, 464, 1200, 0.3743, 0.7312]", "[2, 464, 1200, 0.3743]"),
            "thesis.rows[2]",
            "5 values, one per thesis.columns entry, found 4 values",
        ),
        (
            "thesis-cycles-out-of-order",
            edit("[3, 884,", "[4, 884,"),
            "thesis.rows[3][0]",
            "cycle 3",
        ),
        (
            "additive-part-too-short",
            format!("{VALID}additive_part = {{ table = \"IV.43\", estimate = [0.34, 0.34] }}\n"),
            "thesis.additive_part.estimate",
            "6 values, one per printed row, found 2 values",
        ),
        (
            "additive-part-of-itself",
            format!(
                "{VALID}additive_part = {{ table = \"IV.1\", estimate = [0, 0, 0, 0, 0, 0] }}\n"
            ),
            "thesis.additive_part.table",
            "another Chapter IV table",
        ),
        (
            "thesis-columns-without-cycle",
            edit("columns = [\"cycle\", ", "columns = ["),
            "thesis.columns[0]",
            "`cycle`",
        ),
        (
            "table-id-out-of-range",
            edit("table = \"IV.1\"", "table = \"IV.76\""),
            "table",
            "1 ≤ n ≤ 75",
        ),
        (
            "table-id-not-file-name",
            edit("table = \"IV.1\"", "table = \"IV.2\""),
            "table",
            "`IV.1`",
        ),
        (
            "section-outside-chapter-iv",
            edit("section = \"IV.1.1\"", "section = \"III.1\""),
            "section",
            "Chapter IV section",
        ),
        (
            "empty-domain",
            edit("x = [-16.0, 16.0]", "x = [16.0, -16.0]"),
            "scene.domain.x",
            "lo < hi",
        ),
        (
            "no-coarse-cells",
            edit("coarse_cells = [64, 2]", "coarse_cells = [0, 2]"),
            "scene.coarse_cells[0]",
            "at least 1 cell",
        ),
        (
            "negative-shear-modulus",
            edit("mu = 1.0", "mu = -1.0"),
            "scene.elasticity.mu",
            "between 1e-30 and 1e30",
        ),
        (
            "nan-lambda",
            edit("lambda = 1.0", "lambda = nan"),
            "scene.elasticity.lambda",
            "finite",
        ),
        (
            "duplicate-dirichlet-side",
            edit("[\"left\", \"right\"]", "[\"left\", \"left\"]"),
            "scene.elasticity.dirichlet[1]",
            "each side listed once",
        ),
        (
            "traction-on-dirichlet-side",
            edit(
                "dirichlet = [\"left\", \"right\"]",
                "dirichlet = [\"left\", \"right\"]\ntractions = [{ side = \"left\", value = [0.0, 1.0] }]",
            ),
            "scene.elasticity.tractions[0].side",
            "not in scene.elasticity.dirichlet",
        ),
        (
            "probe-component-of-another-model",
            edit("components = [\"s1\", \"s2\"]", "components = [\"s1\", \"psi\"]"),
            "probes.components[1]",
            "one of `s1`, `s2`",
        ),
        (
            "probe-outside-domain",
            edit("y = [0.5]", "y = [1.5]"),
            "probes.y[0]",
            "a point of scene.domain.y",
        ),
    ];
    for (case, text, field, needle) in &cases {
        expect_error(case, text, field, needle);
    }
}

/// A contact scene (§IV.2.1) and a Reynolds scene (§IV.3) built from `VALID`.
fn contact_scene(obstacles: &str, dirichlet: &str) -> String {
    edit("effects = [\"elasticity\"]", "effects = [\"elasticity\", \"contact\"]")
        .replacen(
            "dirichlet = [\"left\", \"right\"]",
            &format!("dirichlet = {dirichlet}"),
            1,
        )
        .replacen(
            "\n[study]",
            &format!(
                "\n[scene.contact]\nmodel = \"z\"\nestimator = \"z-code\"\nobstacles = {obstacles}\n\n[study]"
            ),
            1,
        )
}

fn reynolds_scene(gap: &str, components: &str) -> String {
    let text = edit("effects = [\"elasticity\"]", "effects = [\"reynolds\"]");
    let start = text.find("[scene.elasticity]").expect("elasticity section");
    let end = text.find("[study]").expect("study section");
    let reynolds = REYNOLDS.replace("{ kind = \"plain\", g0 = 0.1 }", gap);
    format!(
        "{}{}\n{}",
        &text[..start],
        reynolds.trim_start(),
        &text[end..]
    )
    .replace(
        "x = [-16.0, 16.0], y = [0.0, 1.0]",
        "x = [0.0, 1.0], y = [0.0, 1.0]",
    )
    .replace("x = [-12.0, 0.0, 12.0]", "x = [0.25, 0.75]")
    .replace("components = [\"s1\", \"s2\"]", components)
}

#[test]
fn contact_and_reynolds_checks_name_file_and_field() {
    let plain_reynolds =
        || reynolds_scene(r#"{ kind = "plain", g0 = 0.1 }"#, r#"components = ["psi"]"#);
    let bottom = r#"[{ side = "bottom", shape = { kind = "constant", level = -2.0 } }]"#;
    let jump = r#"[{ side = "top", shape = { kind = "jump", base = 2.0, height = 8.0, at = 0.0, s = 0.01 } }]"#;
    let dir = scratch_dir("contact-ok");
    for (obstacles, dirichlet) in [(bottom, r#"["left", "right"]"#), (jump, r#"["left"]"#)] {
        let path = write(&dir, "IV.1.toml", &contact_scene(obstacles, dirichlet));
        if let Err(error) = load(&path) {
            panic!("valid contact scene rejected: {error}");
        }
    }
    let path = write(&dir, "IV.1.toml", &plain_reynolds());
    if let Err(error) = load(&path) {
        panic!("valid Reynolds scene rejected: {error}");
    }
    let _ = fs::remove_dir_all(&dir);

    let cases: Vec<(&str, String, &str, &str)> = vec![
        (
            "obstacle-on-left-side",
            contact_scene(
                r#"[{ side = "left", shape = { kind = "constant", level = -2.0 } }]"#,
                r#"["right"]"#,
            ),
            "scene.contact.obstacles[0].side",
            "`bottom` or `top`",
        ),
        (
            "obstacle-on-dirichlet-side",
            contact_scene(bottom, r#"["left", "bottom"]"#),
            "scene.contact.obstacles[0].side",
            "not in scene.elasticity.dirichlet",
        ),
        (
            "two-obstacles-on-one-side",
            contact_scene(
                r#"[{ side = "bottom", shape = { kind = "constant", level = -2.0 } }, { side = "bottom", shape = { kind = "constant", level = -1.0 } }]"#,
                r#"["left", "right"]"#,
            ),
            "scene.contact.obstacles[1]",
            "each side listed once",
        ),
        (
            "jump-without-width",
            contact_scene(&jump.replace("s = 0.01", "s = 0.0"), r#"["left"]"#),
            "scene.contact.obstacles[0].shape.s",
            "> 0",
        ),
        (
            "no-obstacles",
            contact_scene("[]", r#"["left", "right"]"#),
            "scene.contact.obstacles",
            "at least one obstacle",
        ),
        (
            "closed-wave-gap",
            reynolds_scene(
                r#"{ kind = "wave-horizontal", g0 = 0.1, amplitude = 0.1, frequency = 2.0 }"#,
                r#"components = ["psi"]"#,
            ),
            "scene.reynolds.gap",
            "g0 − |amplitude| > 0",
        ),
        (
            "closed-linear-gap",
            reynolds_scene(
                r#"{ kind = "linear", g0 = 0.1, slope = -0.2 }"#,
                r#"components = ["psi"]"#,
            ),
            "scene.reynolds.gap",
            "at x₁ = 1",
        ),
        (
            "infinite-boundary-pressure",
            plain_reynolds().replace("boundary_pressure = 200.0", "boundary_pressure = inf"),
            "scene.reynolds.boundary_pressure",
            "finite",
        ),
        (
            "unknown-reynolds-estimator",
            plain_reynolds().replace("estimator = \"thesis-code\"", "estimator = \"z-code\""),
            "scene.reynolds.estimator",
            "unknown variant `z-code`, expected `theorem` or `thesis-code`",
        ),
        (
            "missing-reynolds-estimator",
            plain_reynolds().replace("estimator = \"thesis-code\"\n", ""),
            "scene.reynolds.estimator",
            "missing field `estimator`",
        ),
        (
            "zone-residual-without-cavitation",
            plain_reynolds().replace(
                "estimator = \"thesis-code\"\n",
                "estimator = \"thesis-code\"\nzone_residual = \"off-zone\"\n",
            ),
            "scene.reynolds.zone_residual",
            "`full` (or left out) when cavitation = \"off\"",
        ),
        (
            "unknown-zone-residual",
            plain_reynolds().replace(
                "cavitation = \"off\"\nestimator = \"thesis-code\"\n",
                "cavitation = \"on\"\nestimator = \"thesis-code\"\nzone_residual = \"zero\"\n",
            ),
            "scene.reynolds.zone_residual",
            "unknown variant `zero`, expected one of `full`, `off-zone`, `off-touching`",
        ),
        (
            "unknown-cavitation-source",
            plain_reynolds().replace(
                "cavitation = \"off\"\nestimator = \"thesis-code\"\n",
                "cavitation = \"on\"\nestimator = \"thesis-code\"\ncavitation_source = \"mirror\"\n",
            ),
            "scene.reynolds.cavitation_source",
            "unknown variant `mirror`, expected one of `printed`, `self-consistent`, `reynolds`",
        ),
        (
            "displacement-probe-on-fluid",
            reynolds_scene(r#"{ kind = "plain", g0 = 0.1 }"#, r#"components = ["s2"]"#),
            "probes.components[0]",
            "one of `psi`",
        ),
    ];
    for (case, text, field, needle) in &cases {
        expect_error(case, text, field, needle);
    }
}

/// The fields of the manufactured contact and cavitation scenes outside their shipped files:
/// the `linear` obstacle shape (finite offset and slope), a pressure field named as a
/// displacement and a displacement field named as a pressure.
#[test]
fn manufactured_contact_and_cavitation_fields_name_file_and_field() {
    let dir = scratch_dir("linear-ok");
    let linear =
        r#"[{ side = "bottom", shape = { kind = "linear", offset = -2.0, slope = 0.01 } }]"#;
    let path = write(
        &dir,
        "IV.1.toml",
        &contact_scene(linear, r#"["left", "right"]"#),
    );
    if let Err(error) = load(&path) {
        panic!("valid linear obstacle rejected: {error}");
    }
    let nan_slope =
        r#"[{ side = "bottom", shape = { kind = "linear", offset = -2.0, slope = nan } }]"#;
    expect_error(
        "linear-slope-nan",
        &contact_scene(nan_slope, r#"["left", "right"]"#),
        "scene.contact.obstacles[0].shape.slope",
        "a finite number",
    );
    let inf_offset =
        r#"[{ side = "bottom", shape = { kind = "linear", offset = inf, slope = 0.0 } }]"#;
    expect_error(
        "linear-offset-inf",
        &contact_scene(inf_offset, r#"["left", "right"]"#),
        "scene.contact.obstacles[0].shape.offset",
        "a finite number",
    );
    let pressure_as_displacement = edit(
        r#"volume_load = { direction = [0.0, 1.0], profile = { kind = "constant", amplitude = 0.0004 } }"#,
        r#"exact = "cavitation-bubble""#,
    );
    expect_error(
        "exact-pressure-in-elasticity",
        &pressure_as_displacement,
        "scene.elasticity.exact",
        "a displacement",
    );
    let displacement_as_pressure =
        reynolds_scene(r#"{ kind = "plain", g0 = 0.1 }"#, r#"components = ["psi"]"#).replacen(
            "estimator = \"thesis-code\"",
            "estimator = \"thesis-code\"\nexact = \"contact-strip\"",
            1,
        );
    expect_error(
        "exact-displacement-in-reynolds",
        &displacement_as_pressure,
        "scene.reynolds.exact",
        "a pressure",
    );
}

#[test]
fn missing_and_unreadable_files_name_the_file() {
    let dir = scratch_dir("missing");
    let path = dir.join("IV.1.toml");
    let error = load(&path).expect_err("missing file");
    assert!(matches!(error, ExperimentError::Read { .. }));
    assert!(error.to_string().contains(&path.display().to_string()));

    // A directory where a file is expected, and a file that is not UTF-8.
    fs::create_dir_all(dir.join("IV.2.toml")).expect("create a directory");
    let error = load(&dir.join("IV.2.toml")).expect_err("directory instead of file");
    assert!(error.to_string().contains("IV.2.toml"), "{error}");
    let binary = dir.join("IV.3.toml");
    fs::write(&binary, [0xff, 0xfe, 0x00, 0x80]).expect("write binary");
    let error = load(&binary).expect_err("binary file");
    assert!(error.to_string().contains("IV.3.toml"), "{error}");

    let error = load_dir(&dir.join("no-such-dir"), None).expect_err("missing directory");
    assert!(error.to_string().contains("no-such-dir"), "{error}");
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn garbage_never_panics() {
    let dir = scratch_dir("garbage");
    let inputs = [
        "",
        "=",
        "[[[",
        "table = ",
        "\u{0}\u{1}\u{2}",
        "table = \"IV.1\"\n[scene\n",
        "[thesis]\nrows = [[0, 1], [1]]",
        &VALID.replace("inf", "infinity"),
        &VALID[..VALID.len() / 2],
    ];
    for (i, text) in inputs.iter().enumerate() {
        let path = write(&dir, "IV.1.toml", text);
        let error = load(&path).expect_err("garbage must not load");
        assert!(
            error.to_string().contains("IV.1.toml"),
            "input {i}: message does not name the file: {error}"
        );
    }
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn load_dir_sorts_numerically_and_filters() {
    let dir = scratch_dir("sorted");
    for n in [10, 2, 1] {
        let text = edit("table = \"IV.1\"", &format!("table = \"IV.{n}\""));
        write(&dir, &format!("IV.{n}.toml"), &text);
    }
    write(&dir, "README.md", "not an experiment");
    let specs = load_dir(&dir, None).unwrap_or_else(|e| panic!("{e}"));
    let tables: Vec<&str> = specs.iter().map(|s| s.table.as_str()).collect();
    assert_eq!(tables, ["IV.1", "IV.2", "IV.10"]);

    let only = ["IV.10".to_owned(), "IV.2".to_owned()];
    let specs = load_dir(&dir, Some(&only)).unwrap_or_else(|e| panic!("{e}"));
    let tables: Vec<&str> = specs.iter().map(|s| s.table.as_str()).collect();
    assert_eq!(tables, ["IV.2", "IV.10"]);

    let only = ["IV.7".to_owned()];
    let error = load_dir(&dir, Some(&only)).expect_err("unknown table");
    let message = error.to_string();
    assert!(message.contains("`IV.7`"), "{message}");
    assert!(message.contains("IV.1, IV.2, IV.10"), "{message}");

    // One broken file fails the whole directory, naming that file.
    write(&dir, "IV.2.toml", &edit("rows = 6", "rows = \"six\""));
    let error = load_dir(&dir, None).expect_err("broken file");
    assert!(error.to_string().contains("IV.2.toml"), "{error}");
    assert_eq!(error.field(), Some("study.rows"));
    let _ = fs::remove_dir_all(&dir);
}

/// Hostile inputs that the loader must refuse, each naming file and field:
/// fixed-length lists of another length (serde's arrays dropped extra values and ran a changed
/// problem), control characters in text that reaches the page, degenerate domains and extreme
/// material constants (they reached the solver as "not positive definite"), contradictory
/// physics, unbounded studies, and refinement beyond what the mesh supports.
#[test]
fn hostile_inputs_name_file_and_field() {
    let reynolds = || reynolds_scene("{ kind = \"plain\", g0 = 0.1 }", "components = [\"psi\"]");
    let cavitation = |pressure: &str, mode: &str| {
        reynolds()
            .replace(
                "boundary_pressure = 200.0",
                &format!("boundary_pressure = {pressure}"),
            )
            .replace("cavitation = \"off\"", &format!("cavitation = \"{mode}\""))
    };
    let thesis_rows = |n: usize| {
        let rows: Vec<String> = (0..n)
            .map(|i| format!("  [{i}, 128, 390, 0.5, 0.7],"))
            .collect();
        let start = VALID.find("rows = [\n").expect("thesis rows");
        format!("{}rows = [\n{}\n]\n", &VALID[..start], rows.join("\n"))
    };
    let cases: Vec<(&str, String, &str, &str)> = vec![
        // fixed-length lists
        ("coarse-cells-three", edit("coarse_cells = [64, 2]", "coarse_cells = [64, 2, 3]"), "scene.coarse_cells", "exactly 2 values"),
        ("coarse-cells-one", edit("coarse_cells = [64, 2]", "coarse_cells = [64]"), "scene.coarse_cells", "2"),
        ("coarse-cells-empty", edit("coarse_cells = [64, 2]", "coarse_cells = []"), "scene.coarse_cells", "2"),
        ("domain-x-three", edit("x = [-16.0, 16.0]", "x = [-16.0, 16.0, 99.0]"), "scene.domain.x", "exactly 2 values"),
        ("domain-y-one", edit("y = [0.0, 1.0]", "y = [1.0]"), "scene.domain.y", "2"),
        ("direction-three", edit("direction = [0.0, 1.0]", "direction = [0.0, 1.0, 0.0]"), "scene.elasticity.volume_load.direction", "exactly 2 values"),
        ("window-three", edit("convergence_window = [2, 5]", "convergence_window = [2, 5, 9]"), "study.convergence_window", "exactly 2 values"),
        ("window-one", edit("convergence_window = [2, 5]", "convergence_window = [2]"), "study.convergence_window", "2"),
        ("velocity-four", reynolds().replace("upper_wall_velocity = [0.0, 0.0, -10.0]", "upper_wall_velocity = [0.0, 0.0, 0.0, -10.0]"), "scene.reynolds.upper_wall_velocity", "exactly 3 values"),
        ("velocity-two", reynolds().replace("upper_wall_velocity = [0.0, 0.0, -10.0]", "upper_wall_velocity = [0.0, -10.0]"), "scene.reynolds.upper_wall_velocity", "3"),
        ("traction-three", edit("dirichlet = [\"left\", \"right\"]", "dirichlet = [\"left\", \"right\"]\ntractions = [{ side = \"top\", value = [0.0, 1.0, 2.0] }]"), "scene.elasticity.tractions[0].value", "exactly 2 values"),
        // control characters
        ("title-nul", edit("title = \"Box under", "title = \"Box\\u0000 under"), "title", "control character"),
        ("title-bel", edit("title = \"Box under", "title = \"Box\\u0007 under"), "title", "control character"),
        ("title-escape", edit("title = \"Box under", "title = \"\\u001b[31mBox under"), "title", "control character"),
        ("section-newline", edit("section = \"IV.1.1\"", "section = \"IV.1.1\\n\""), "section", "control character"),
        ("scene-name-tab", edit("name = \"box-constant-load\"", "name = \"box\\tload\""), "scene.name", "control character"),
        ("note-bel", edit("\n[scene]\n", "notes = [\"ok\", \"ring\\u0007\"]\n\n[scene]\n"), "notes[1]", "control character"),
        ("thesis-column-nul", edit("\"active_cells\", \"dofs\"", "\"active\\u0000cells\", \"dofs\""), "thesis.columns[1]", "control character"),
        // domain and mesh
        ("domain-width-1e-300", edit("x = [-16.0, 16.0]", "x = [0.0, 1e-300]"), "scene.domain.x", "length between"),
        ("domain-height-tiny", edit("y = [0.0, 1.0]", "y = [0.0, 1e-40]"), "scene.domain.y", "length between"),
        ("domain-width-huge", edit("x = [-16.0, 16.0]", "x = [-1e300, 1e300]"), "scene.domain.x", "length between"),
        ("domain-lost-in-rounding", edit("x = [-16.0, 16.0]", "x = [1e20, 1.0000000000001e20]"), "scene.domain.x", "1e-9 of its largest coordinate"),
        ("domain-reversed-y", edit("y = [0.0, 1.0]", "y = [1.0, 0.0]"), "scene.domain.y", "lo < hi"),
        ("domain-empty-y", edit("y = [0.0, 1.0]", "y = [0.5, 0.5]"), "scene.domain.y", "lo < hi"),
        ("domain-infinite", edit("x = [-16.0, 16.0]", "x = [-inf, 16.0]"), "scene.domain.x[0]", "finite"),
        ("coarse-cells-flat", edit("coarse_cells = [64, 2]", "coarse_cells = [1, 100000]"), "scene.coarse_cells", "ratio of at most"),
        ("coarse-cells-zero-y", edit("coarse_cells = [64, 2]", "coarse_cells = [64, 0]"), "scene.coarse_cells[1]", "at least 1"),
        ("coarse-cells-negative", edit("coarse_cells = [64, 2]", "coarse_cells = [-64, 2]"), "scene.coarse_cells[0]", "usize"),
        ("global-refinements-13", edit("coarse_cells = [64, 2]", "coarse_cells = [64, 2]\nglobal_refinements = 13"), "scene.global_refinements", "at most 12"),
        ("global-refinements-huge", edit("coarse_cells = [64, 2]", "coarse_cells = [64, 2]\nglobal_refinements = 1000000"), "scene.global_refinements", "refinement levels"),
        // material constants
        ("mu-overflows", edit("mu = 1.0", "mu = 1e308"), "scene.elasticity.mu", "between 1e-30 and 1e30"),
        ("lambda-overflows", edit("mu = 1.0\nlambda = 1.0", "mu = 1e308\nlambda = 1e308"), "scene.elasticity.mu", "between 1e-30 and 1e30"),
        ("lambda-locks", edit("lambda = 1.0", "lambda = 1e15"), "scene.elasticity.lambda", "λ/μ"),
        ("lambda-just-past-ratio", edit("lambda = 1.0", "lambda = 1.0000001e8"), "scene.elasticity.lambda", "λ ≤ 1e8·μ"),
        ("mu-underflows", edit("mu = 1.0", "mu = 1e-40"), "scene.elasticity.mu", "between 1e-30 and 1e30"),
        ("mu-zero", edit("mu = 1.0", "mu = 0.0"), "scene.elasticity.mu", "between 1e-30 and 1e30"),
        ("lambda-negative", edit("lambda = 1.0", "lambda = -0.5"), "scene.elasticity.lambda", "or 0"),
        ("lambda-infinite", edit("lambda = 1.0", "lambda = inf"), "scene.elasticity.lambda", "finite"),
        // contradictory physics
        ("cavitation-negative-pressure", cavitation("-200.0", "on"), "scene.reynolds.boundary_pressure", "ψ ≥ 0"),
        ("auto-cavitation-negative-pressure", cavitation("-1e-9", "auto"), "scene.reynolds.boundary_pressure", "ψ ≥ 0"),
        ("source-without-cavitation", reynolds().replace("cavitation = \"off\"", "cavitation = \"off\"\ncavitation_source = \"reynolds\""), "scene.reynolds.cavitation_source", "cavitation = \"off\""),
        ("self-consistent-without-cavitation", reynolds().replace("cavitation = \"off\"", "cavitation = \"off\"\ncavitation_source = \"self-consistent\""), "scene.reynolds.cavitation_source", "only"),
        // the size of a study
        ("rows-billion", edit("rows = 6", "rows = 1000000000"), "study.rows", "at most 200"),
        ("unprinted-billion", edit("rows = 6", "rows = 6\nunprinted_cycles = 1000000000"), "study.unprinted_cycles", "at most 200"),
        ("rows-overflow-usize", edit("rows = 6", "rows = 99999999999999999999999"), "study.rows", ""),
        ("thesis-rows-201", thesis_rows(201), "thesis.rows", "at most 200"),
        ("refine-fraction-huge", edit("refine_fraction = 0.3", "refine_fraction = 1e308"), "study.refine_fraction", "≤ 1"),
        ("coarsen-fraction-nan", edit("coarsen_fraction = 0.03", "coarsen_fraction = nan"), "study.coarsen_fraction", "finite"),
        // sizes of what the page and the probe file hold
        ("probes-grid-huge", edit("x = [-12.0, 0.0, 12.0]\ny = [0.5]", &format!("x = [{}]\ny = [{}]", vec!["0.0"; 200].join(", "), vec!["0.5"; 51].join(", "))), "probes", "at most 10000 probe points"),
        ("thesis-columns-65", edit("columns = [\"cycle\", \"active_cells\", \"dofs\", \"estimate\", \"ratio\"]", &format!("columns = [\"cycle\", {}]", (1..65).map(|i| format!("\"c{i}\"")).collect::<Vec<_>>().join(", "))), "thesis.columns", "at most 64 columns"),
        ("title-long", edit("title = \"Box under a constant volume load\"", &format!("title = \"{}\"", "x".repeat(1001))), "title", "at most 1000 characters"),
        ("note-long", edit("table = \"IV.1\"", &format!("table = \"IV.1\"\nnotes = [\"{}\"]", "y".repeat(20_001))), "notes[0]", "at most 20000 characters"),
        ("notes-many", edit("table = \"IV.1\"", &format!("table = \"IV.1\"\nnotes = [{}]", vec!["\"n\""; 101].join(", "))), "notes", "at most 100 notes"),
        ("equation-control", reynolds().replace("equation = \"IV.7\"", "equation = \"IV.7\\u0007\""), "scene.reynolds.equation", "control character"),
    ];
    for (case, text, field, needle) in &cases {
        expect_error(case, text, field, needle);
    }
    assert!(cases.len() >= 54, "{} cases", cases.len());
}

/// A 100 000-deep nested array made a 200 KB message; the message stays short and still names
/// the file.
#[test]
fn deeply_nested_values_give_a_short_message() {
    let depth = 100_000;
    let nested = format!("{}1{}", "[".repeat(depth), "]".repeat(depth));
    let dir = scratch_dir("deep");
    let path = write(
        &dir,
        "IV.1.toml",
        &edit("rows = 6", &format!("rows = {nested}")),
    );
    let error = load(&path).expect_err("a nested array is no row count");
    let message = error.to_string();
    assert!(message.contains(&path.display().to_string()), "{message}");
    assert!(
        message.len() < 2_000,
        "{} bytes: {}",
        message.len(),
        &message[..200]
    );
    let _ = fs::remove_dir_all(&dir);
}

/// Load `text` as `IV.1.toml` and run it at the quick tier within `budget`: the study's error.
fn run_error(case: &str, text: &str, budget: &str) -> tribo::study::RunError {
    let dir = scratch_dir(case);
    let path = write(&dir, "IV.1.toml", text);
    let experiment = load(&path).unwrap_or_else(|e| panic!("{case}: {e}"));
    let budget = tribo::study::Budget::parse(budget).expect("a budget");
    let _ = fs::remove_dir_all(&dir);
    match tribo::study::run_within(
        &experiment,
        tribo::study::Tier::Quick,
        budget,
        &|_, _, _| {},
    ) {
        Ok(_) => panic!("{case}: the run was expected to fail"),
        Err(error) => error,
    }
}

/// A study that would outgrow the memory is refused before its first solve, naming the table,
/// the cycle the prediction passes the budget in, and the flag that sets the budget
/// (`global_refinements = 12` passed 8 GB in 44 s; `refine_fraction = 1` quadruples the cells
/// of every cycle).
#[test]
fn runs_beyond_the_memory_budget_are_refused_naming_table_and_cycle() {
    let huge = edit(
        "coarse_cells = [64, 2]",
        "coarse_cells = [64, 2]\nglobal_refinements = 12",
    );
    let error = run_error("global-12", &huge, "64G");
    assert_eq!((error.table.as_str(), error.cycle), ("IV.1", 0), "{error}");
    assert!(
        matches!(error.cause.kind(), StudyError::OverBudget(_)),
        "{error}"
    );
    assert!(
        error.cause.to_string().contains("--memory-budget"),
        "{error}"
    );

    // 128 cells need about 1 MB; quadrupling every cycle passes 10 MB in cycle 2.
    let greedy = edit(
        "refine_fraction = 0.3\ncoarsen_fraction = 0.03",
        "refine_fraction = 1.0\ncoarsen_fraction = 0.0",
    );
    let error = run_error("refine-all", &greedy, "10M");
    assert_eq!(error.cycle, 2, "{error}");
    assert!(
        matches!(error.cause.kind(), StudyError::OverBudget(_)),
        "{error}"
    );
    assert!(
        error.to_string().starts_with("table IV.1, cycle 2: "),
        "{error}"
    );
}

/// An obstacle reaching into the body where the Dirichlet sides clamp it leaves the contact
/// problem without a solution: refused before the first solve (it ran and showed a penetration
/// of 2.0 in a column).
#[test]
fn an_obstacle_above_the_clamped_corners_is_refused() {
    let scene = contact_scene(
        "[{ side = \"bottom\", shape = { kind = \"constant\", level = 2.0 } }]",
        "[\"left\", \"right\"]",
    );
    let error = run_error("obstacle-above", &scene, "64G");
    assert_eq!((error.table.as_str(), error.cycle), ("IV.1", 0), "{error}");
    assert!(
        matches!(error.cause.kind(), StudyError::InfeasibleObstacle(_)),
        "{error}"
    );
    assert!(
        error.to_string().contains("scene.contact.obstacles[0]"),
        "{error}"
    );
    // The same obstacle below the body is an ordinary contact problem.
    let below = contact_scene(
        "[{ side = \"bottom\", shape = { kind = \"constant\", level = -2.0 } }]",
        "[\"left\", \"right\"]",
    );
    let dir = scratch_dir("obstacle-below");
    let experiment = load(&write(&dir, "IV.1.toml", &below)).expect("loads");
    tribo::study::run(&experiment, tribo::study::Tier::Quick, &|_, _, _| {}).expect("solves");
    let _ = fs::remove_dir_all(&dir);
}

/// A body without a Dirichlet side can move rigidly: the solver's message says so, rather than
/// blaming the boundary conditions for an overflow or the reverse.
#[test]
fn a_singular_system_names_the_boundary_conditions() {
    let free = edit("dirichlet = [\"left\", \"right\"]", "dirichlet = []");
    let error = run_error("no-dirichlet", &free, "64G");
    assert_eq!(error.cycle, 0, "{error}");
    assert!(
        matches!(
            error.cause.solve_error(),
            Some(SolveError::NotPositiveDefinite {
                cause: Cause::Singular,
                ..
            })
        ),
        "{error}"
    );
    assert!(
        error
            .to_string()
            .contains("singular: check the boundary conditions"),
        "{error}"
    );
}

/// Data too large (or too small) for double precision loads — each number is finite — but
/// overflows in the run: the error names the table and cycle 0 and says that the data are too
/// large, instead of blaming the boundary conditions.
#[test]
fn overflowing_data_is_an_error_naming_the_cause() {
    let plain_reynolds = |from: &str, to: &str| {
        let text = reynolds_scene("{ kind = \"plain\", g0 = 0.1 }", "components = [\"psi\"]");
        assert!(text.contains(from), "test setup: `{from}`");
        text.replacen(from, to, 1)
    };
    let load = "profile = { kind = \"constant\", amplitude = 0.0004 }";
    let cases: Vec<(&str, String)> = vec![
        ("amplitude-1e300", edit("amplitude = 0.0004", "amplitude = 1e300")),
        (
            "quadratic-scale-1e-300",
            edit(load, "profile = { kind = \"quadratic\", amplitude = 0.0004, scale = 1e-300 }"),
        ),
        ("direction-1e300", edit("direction = [0.0, 1.0]", "direction = [1e300, 1e300]")),
        (
            "traction-1e308",
            edit(
                "dirichlet = [\"left\", \"right\"]",
                "dirichlet = [\"left\", \"right\"]\ntractions = [{ side = \"top\", value = [0.0, 1e308] }]",
            ),
        ),
        ("gap-1e-300", plain_reynolds("g0 = 0.1", "g0 = 1e-300")),
        (
            "squeeze-1e308",
            plain_reynolds("[0.0, 0.0, -10.0]", "[0.0, 0.0, -1e308]"),
        ),
        (
            "boundary-pressure-1e308",
            plain_reynolds("boundary_pressure = 200.0", "boundary_pressure = 1e308"),
        ),
    ];
    for (case, text) in &cases {
        let error = run_error(case, text, "64G");
        assert_eq!(
            (error.table.as_str(), error.cycle),
            ("IV.1", 0),
            "{case}: {error}"
        );
        assert!(
            overflowed(&error.cause),
            "{case}: the error is an overflow: {error} ({:?})",
            error.cause.kind()
        );
        assert!(
            error.cause.to_string().contains("too large"),
            "{case}: the message names the cause: {error}"
        );
        assert!(
            !error.cause.to_string().contains("boundary conditions"),
            "{case}: {error}"
        );
    }
}

/// Whether `error` is an overflow of the data: a non-finite right-hand side, solution or
/// estimate, or a factorisation that met a non-finite entry.
fn overflowed(error: &StudyError) -> bool {
    let solve = matches!(
        error.solve_error(),
        Some(
            SolveError::NonFinite(_)
                | SolveError::NonFiniteData(_)
                | SolveError::IterativeNonFinite(_)
                | SolveError::NotPositiveDefinite {
                    cause: Cause::NonFinite { .. },
                    ..
                }
        )
    );
    let field = match error.kind() {
        StudyError::NonFinite(_) => true,
        StudyError::Model(m) => matches!(m.kind(), ModelError::NonFinite(_)),
        _ => false,
    };
    solve || field
}

/// An obstacle far away (beyond the Signorini search radius of 1000, up to −1e308) is never
/// touched: the run succeeds and warns, for both contact models (the Signorini linearisation
/// stopped with "does not meet the obstacle curve within distance 1000").
#[test]
fn a_far_obstacle_is_never_touched() {
    for model in ["z", "signorini"] {
        for level in ["-1e4", "-1e308"] {
            let scene = contact_scene(
                &format!(
                    "[{{ side = \"bottom\", shape = {{ kind = \"constant\", level = {level} }} }}]"
                ),
                "[\"left\", \"right\"]",
            )
            .replace(
                "model = \"z\"\nestimator = \"z-code\"",
                &format!(
                    "model = \"{model}\"\nestimator = \"{}\"",
                    if model == "z" {
                        "z-code"
                    } else {
                        "signorini-code"
                    }
                ),
            );
            let dir = scratch_dir(&format!("far-{model}{level}"));
            let experiment = load(&write(&dir, "IV.1.toml", &scene)).expect("loads");
            let _ = fs::remove_dir_all(&dir);
            let run = tribo::study::run(&experiment, tribo::study::Tier::Quick, &|_, _, _| {})
                .unwrap_or_else(|e| panic!("{model} {level}: {e}"));
            assert!(
                run.rows
                    .iter()
                    .all(|r| r.count_of("contact_vertices") == Some(0)),
                "{model} {level}"
            );
            assert_eq!(run.warnings.len(), 1, "{model} {level}: {:?}", run.warnings);
        }
    }
}

/// Huge numbers in messages are written with an exponent, not as hundreds of digits.
#[test]
fn huge_numbers_in_messages_are_short() {
    let error = expect_error(
        "domain-1e300",
        &edit("x = [-16.0, 16.0]", "x = [-1e300, 1e300]"),
        "scene.domain.x",
        "[-1e300, 1e300]",
    );
    assert!(error.to_string().len() < 400, "{error}");
    let scene = contact_scene(
        "[{ side = \"bottom\", shape = { kind = \"constant\", level = 1e300 } }]",
        "[\"left\", \"right\"]",
    );
    let error = run_error("obstacle-1e300", &scene, "64G");
    assert!(error.cause.to_string().contains("b = 1e300 > 0"), "{error}");
    assert!(error.cause.to_string().len() < 400, "{error}");
}

/// `VALID` with contact on the bottom face against a flat obstacle, the model chosen per face
/// (`model = "model-adaptive"`); the study is still the grid study of `VALID`.
fn model_adaptive_contact() -> String {
    contact_scene(
        "[{ side = \"bottom\", shape = { kind = \"constant\", level = -2.0 } }]",
        "[\"left\", \"right\"]",
    )
    .replacen(
        "model = \"z\"\nestimator = \"z-code\"\n",
        "model = \"model-adaptive\"\n",
        1,
    )
}

/// A model-adaptive contact file (§IV.2.3) built from `VALID`: Algorithm III.3, p_r = 2 %,
/// p_c = 1 %, the mesh refined 3× at the contact side.
fn model_adaptive() -> String {
    model_adaptive_contact()
        .replacen(
            "coarse_cells = [64, 2]\n",
            "coarse_cells = [64, 2]\ncontact_refinements = 3\n",
            1,
        )
        .replacen(
            "kind = \"grid-adaptive\"",
            "kind = \"model-adaptive\"\nalgorithm = \"III.3\"",
            1,
        )
        .replacen("refine_fraction = 0.3", "refine_fraction = 0.02", 1)
        .replacen("coarsen_fraction = 0.03", "coarsen_fraction = 0.01", 1)
        .replacen("convergence_window = [2, 5]\n", "", 1)
}

#[test]
fn model_adaptive_checks_name_file_and_field() {
    let base = model_adaptive();
    let dir = scratch_dir("ma-valid");
    let e = load(&write(&dir, "IV.1.toml", &base)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(e.scene.side_refinements, 3);
    assert_eq!(e.study.model().map(|m| m.tolerance), Some(1e-7));
    let with = |from: &str, to: &str| {
        assert!(base.contains(from), "test setup: `{from}`");
        base.replacen(from, to, 1)
    };
    let iii2 = |from: &str, to: &str| {
        with("algorithm = \"III.3\"", "algorithm = \"III.2\"").replacen(from, to, 1)
    };
    let cases = [
        (
            "unknown algorithm",
            with("\"III.3\"", "\"III.4\""),
            "study.algorithm",
            "III.4",
        ),
        (
            "no algorithm",
            with("algorithm = \"III.3\"\n", ""),
            "study.algorithm",
            "III.2",
        ),
        (
            "p_r = 0 for III.3",
            with("refine_fraction = 0.02", "refine_fraction = 0.0"),
            "study.refine_fraction",
            "(0, 1)",
        ),
        (
            "p_c = 1 for III.3",
            with("coarsen_fraction = 0.01", "coarsen_fraction = 1.0"),
            "study.coarsen_fraction",
            "(0, 1)",
        ),
        (
            "p_r > 1 for III.2",
            iii2("refine_fraction = 0.02", "refine_fraction = 1.5"),
            "study.refine_fraction",
            "[0, 1]",
        ),
        (
            "p_c < 0 for III.2",
            iii2("coarsen_fraction = 0.01", "coarsen_fraction = -0.1"),
            "study.coarsen_fraction",
            "[0, 1]",
        ),
        (
            "eps0 = 0",
            with(
                "algorithm = \"III.3\"",
                "algorithm = \"III.3\"\nmodel_tolerance = 0.0",
            ),
            "study.model_tolerance",
            "> 0",
        ),
        (
            "eps0 < 0",
            with(
                "algorithm = \"III.3\"",
                "algorithm = \"III.3\"\nmodel_tolerance = -1e-7",
            ),
            "study.model_tolerance",
            "> 0",
        ),
        (
            "fixed z model",
            with("model = \"model-adaptive\"", "model = \"z\""),
            "scene.contact.model",
            "`z`",
        ),
        (
            "fixed Signorini model",
            with("model = \"model-adaptive\"", "model = \"signorini\""),
            "scene.contact.model",
            "`signorini`",
        ),
        (
            "model-adaptive in a grid study",
            with(
                "kind = \"model-adaptive\"\nalgorithm = \"III.3\"",
                "kind = \"grid-adaptive\"\nconvergence_window = [2, 5]",
            ),
            "scene.contact.model",
            "study.kind",
        ),
        (
            "levels > 12",
            with("contact_refinements = 3", "contact_refinements = 13"),
            "scene.contact_refinements",
            "12",
        ),
        (
            "a convergence window",
            with(
                "algorithm = \"III.3\"",
                "algorithm = \"III.3\"\nconvergence_window = [2, 5]",
            ),
            "study.convergence_window",
            "fixed",
        ),
        (
            "an estimator",
            with(
                "model = \"model-adaptive\"",
                "model = \"model-adaptive\"\nestimator = \"z-code\"",
            ),
            "scene.contact.estimator",
            "model error",
        ),
        (
            "an algorithm in a grid study",
            edit(
                "kind = \"grid-adaptive\"",
                "kind = \"grid-adaptive\"\nalgorithm = \"III.2\"",
            ),
            "study.algorithm",
            "model-adaptive",
        ),
    ];
    for (case, text, field, needle) in cases {
        expect_error(case, &text, field, needle);
    }
    // Model-and-grid fields in a model-adaptive study on a fixed mesh.
    for field in ["model_refine_fraction", "model_coarsen_fraction", "balance"] {
        expect_error(
            field,
            &with(
                "algorithm = \"III.3\"",
                &format!("algorithm = \"III.3\"\n{field} = 0.5"),
            ),
            &format!("study.{field}"),
            "model-and-grid-adaptive",
        );
    }
    // Without contact: a model-adaptive study of pure elasticity, and refinements at no side.
    let no_contact = edit(
        "kind = \"grid-adaptive\"",
        "kind = \"model-adaptive\"\nalgorithm = \"III.3\"",
    )
    .replacen("convergence_window = [2, 5]\n", "", 1);
    expect_error(
        "no contact",
        &no_contact,
        "study.kind",
        "scene with contact",
    );
    let levels = edit(
        "coarse_cells = [64, 2]\n",
        "coarse_cells = [64, 2]\ncontact_refinements = 2\n",
    );
    expect_error(
        "levels without contact",
        &levels,
        "scene.contact_refinements",
        "without contact",
    );
}

/// A model-and-grid-adaptive contact file (§IV.2.4, Algorithm III.25) built from `VALID`: grid
/// marking 30 %/3 %, Algorithm III.3 with p_r = 2 %, p_c = 1 %, α = 0.5.
fn model_and_grid() -> String {
    model_adaptive_contact().replacen(
        "kind = \"grid-adaptive\"",
        "kind = \"model-and-grid-adaptive\"\nalgorithm = \"III.3\"\nmodel_refine_fraction = 0.02\n\
         model_coarsen_fraction = 0.01\nbalance = 0.5",
        1,
    )
}

#[test]
fn model_and_grid_checks_name_file_and_field() {
    let base = model_and_grid();
    let dir = scratch_dir("mga-valid");
    let e = load(&write(&dir, "IV.1.toml", &base)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(e.study.balance(), Some(0.5));
    assert_eq!(
        e.study.model().map(|m| (m.refine, m.coarsen)),
        Some((0.02, 0.01))
    );
    let with = |from: &str, to: &str| {
        assert!(base.contains(from), "test setup: `{from}`");
        base.replacen(from, to, 1)
    };
    let cases = [
        (
            "alpha = 0",
            with("balance = 0.5", "balance = 0.0"),
            "study.balance",
            "(0, 1)",
        ),
        (
            "alpha = 1",
            with("balance = 0.5", "balance = 1.0"),
            "study.balance",
            "(0, 1)",
        ),
        (
            "alpha < 0",
            with("balance = 0.5", "balance = -0.5"),
            "study.balance",
            "(0, 1)",
        ),
        (
            "alpha > 1",
            with("balance = 0.5", "balance = 2.0"),
            "study.balance",
            "(0, 1)",
        ),
        (
            "alpha nan",
            with("balance = 0.5", "balance = nan"),
            "study.balance",
            "(0, 1)",
        ),
        (
            "no model p_r",
            with("model_refine_fraction = 0.02\n", ""),
            "study.model_refine_fraction",
            "model marking",
        ),
        (
            "no model p_c",
            with("model_coarsen_fraction = 0.01\n", ""),
            "study.model_coarsen_fraction",
            "model marking",
        ),
        (
            "model p_r = 1 for III.3",
            with(
                "model_refine_fraction = 0.02",
                "model_refine_fraction = 1.0",
            ),
            "study.model_refine_fraction",
            "(0, 1)",
        ),
        (
            "model p_c > 1 for III.2",
            with("\"III.3\"", "\"III.2\"").replacen(
                "model_coarsen_fraction = 0.01",
                "model_coarsen_fraction = 1.5",
                1,
            ),
            "study.model_coarsen_fraction",
            "[0, 1]",
        ),
        (
            "no algorithm",
            with("algorithm = \"III.3\"\n", ""),
            "study.algorithm",
            "III.3",
        ),
        (
            "no convergence window",
            with("convergence_window = [2, 5]\n", ""),
            "study.convergence_window",
            "[first, last]",
        ),
        (
            "grid fractions over 1",
            with("refine_fraction = 0.3", "refine_fraction = 0.99"),
            "study.refine_fraction",
            "≤ 1",
        ),
        (
            "fixed z model",
            with("model = \"model-adaptive\"", "model = \"z\""),
            "scene.contact.model",
            "`z`",
        ),
        (
            "an estimator",
            with(
                "model = \"model-adaptive\"",
                "model = \"model-adaptive\"\nestimator = \"signorini-code\"",
            ),
            "scene.contact.estimator",
            "MGA",
        ),
        (
            "eps0 < 0",
            with("balance = 0.5", "balance = 0.5\nmodel_tolerance = -1.0"),
            "study.model_tolerance",
            "> 0",
        ),
    ];
    for (case, text, field, needle) in cases {
        expect_error(case, &text, field, needle);
    }
    // The arc tools of the U-O forming.
    let arc = |radius: &str| {
        with(
            "shape = { kind = \"constant\", level = -2.0 }",
            &format!(
                "shape = {{ kind = \"arc\", center = [-16.0, 10.0], radius = {radius}, \
                 plateau = 0.0, s = 0.01 }}"
            ),
        )
    };
    let dir = scratch_dir("arc-valid");
    load(&write(&dir, "IV.1.toml", &arc("10.0"))).unwrap_or_else(|e| panic!("{e}"));
    for radius in ["0.0", "-1.0", "nan", "inf"] {
        expect_error(
            &format!("arc radius {radius}"),
            &arc(radius),
            "scene.contact.obstacles[0].shape.radius",
            "> 0",
        );
    }
    // A balance in a grid-adaptive study.
    expect_error(
        "balance in a grid study",
        &edit(
            "kind = \"grid-adaptive\"",
            "kind = \"grid-adaptive\"\nbalance = 0.5",
        ),
        "study.balance",
        "model-and-grid-adaptive",
    );
}

/// The load steps of the U-O forming (§IV.2.4.7, `experiments/fig-IV.54.toml`): steps, cycles,
/// lift, the rising tools, and the figure id without thesis rows.
#[test]
fn forming_checks_name_file_and_field() {
    let base = fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments/fig-IV.54.toml"),
    )
    .expect("the shipped forming experiment");
    let dir = scratch_dir("forming-valid");
    let e = load(&write(&dir, "fig-IV.54.toml", &base)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(e.study.cycles_per_row(), 4);
    assert!(e.thesis.rows.is_empty());
    let with = |from: &str, to: &str| {
        assert!(base.contains(from), "test setup: `{from}`");
        base.replacen(from, to, 1)
    };
    let cases = [
        (
            "no steps",
            with("rows = 25", "rows = 0"),
            "study.rows",
            "at least 1",
        ),
        (
            "no cycles",
            with("cycles_per_step = 4", "cycles_per_step = 0"),
            "study.cycles_per_step",
            "between 1 and",
        ),
        (
            "cycles missing",
            with("cycles_per_step = 4\n", ""),
            "study.cycles_per_step",
            "cycles of model and grid adaptivity",
        ),
        (
            "lift missing",
            with("lift_per_step = 0.4166666666666667\n", ""),
            "study.lift_per_step",
            "rise",
        ),
        (
            "lift nan",
            with("lift_per_step = 0.4166666666666667", "lift_per_step = nan"),
            "study.lift_per_step",
            "finite",
        ),
        (
            "a convergence window",
            with(
                "balance = 0.5",
                "balance = 0.5\nconvergence_window = [1, 2]",
            ),
            "study.convergence_window",
            "restarts",
        ),
        (
            "radius 0",
            with("radius = 8.8", "radius = 0.0"),
            "scene.contact.obstacles[0].shape.radius",
            "> 0",
        ),
        (
            "a rising constant",
            with(
                "shape = { kind = \"arc\", center = [-16.0, 9.0], radius = 8.8, plateau = 0.2, \
                 s = 0.01 }",
                "shape = { kind = \"constant\", level = 0.2 }",
            ),
            "scene.contact.obstacles[0].rises",
            "arc",
        ),
        (
            "no model fractions",
            with("model_refine_fraction = 0.02\n", ""),
            "study.model_refine_fraction",
            "model marking",
        ),
        (
            "a fixed contact model",
            with("model = \"model-adaptive\"", "model = \"signorini\""),
            "scene.contact.model",
            "model-adaptive",
        ),
        (
            "thesis rows for a figure",
            format!("{base}\n[thesis]\ncolumns = [\"cycle\"]\nrows = [[0]]\n"),
            "thesis",
            "figure experiment",
        ),
    ];
    for (case, text, field, needle) in cases {
        expect_error_in("fig-IV.54.toml", case, &text, field, needle);
    }
    // A figure id needs a figure number of Chapter IV; a table id needs its printed rows.
    let renamed = with("table = \"fig-IV.54\"", "table = \"fig-IV.999\"");
    expect_error_in(
        "fig-IV.999.toml",
        "figure 999",
        &renamed,
        "table",
        "fig-IV.<n>",
    );
    let as_table = with("table = \"fig-IV.54\"", "table = \"IV.1\"");
    expect_error(
        "a table without rows",
        &as_table,
        "table",
        "pick another id",
    );
    // Load-step fields and rising tools belong to load-step studies.
    expect_error(
        "cycles in a grid study",
        &edit(
            "kind = \"grid-adaptive\"",
            "kind = \"grid-adaptive\"\ncycles_per_step = 4",
        ),
        "study.cycles_per_step",
        "load-steps",
    );
    let mga = with(
        "kind = \"load-steps\"",
        "kind = \"model-and-grid-adaptive\"",
    )
    .replacen("cycles_per_step = 4\n", "", 1)
    .replacen("lift_per_step = 0.4166666666666667\n", "", 1)
    .replacen(
        "balance = 0.5",
        "balance = 0.5\nconvergence_window = [1, 2]",
        1,
    );
    expect_error_in(
        "fig-IV.54.toml",
        "rises outside load steps",
        &mga,
        "scene.contact.obstacles[0].rises",
        "load-steps",
    );
}

/// The SubStokes fields: every bad value names file, field and expectation.
#[test]
fn substokes_checks_name_file_and_field() {
    let base =
        fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments/IV.70.toml"))
            .expect("the shipped SubStokes experiment");
    let dir = scratch_dir("substokes-valid");
    load(&write(&dir, "IV.70.toml", &base)).unwrap_or_else(|e| panic!("{e}"));
    let with = |from: &str, to: &str| {
        assert!(base.contains(from), "test setup: `{from}`");
        base.replacen(from, to, 1)
    };
    let cases: Vec<(&str, String, &str, &str)> = vec![
        (
            "delta-zero",
            with(
                "cavitation = \"on\"",
                "cavitation = \"on\"\ndelta_eps = 0.0",
            ),
            "scene.substokes.delta_eps",
            "> 0",
        ),
        (
            "delta-negative",
            with(
                "cavitation = \"on\"",
                "cavitation = \"on\"\ndelta_eps = -1e-3",
            ),
            "scene.substokes.delta_eps",
            "> 0",
        ),
        (
            "delta-nan",
            with(
                "cavitation = \"on\"",
                "cavitation = \"on\"\ndelta_eps = nan",
            ),
            "scene.substokes.delta_eps",
            "finite",
        ),
        (
            "delta-inf",
            with(
                "cavitation = \"on\"",
                "cavitation = \"on\"\ndelta_eps = inf",
            ),
            "scene.substokes.delta_eps",
            "finite",
        ),
        (
            "gap-zero",
            with("g0 = 0.1", "g0 = 0.0"),
            "scene.substokes.gap.g0",
            "> 0",
        ),
        (
            "gap-negative",
            with("g0 = 0.1", "g0 = -0.1"),
            "scene.substokes.gap.g0",
            "> 0",
        ),
        (
            "point-unknown",
            with(
                "cavitation = \"on\"",
                "cavitation = \"on\"\npoint = \"centre\"",
            ),
            "scene.substokes.point",
            "none",
        ),
        (
            "stabilisation-unknown",
            with(
                "cavitation = \"on\"",
                "cavitation = \"on\"\nstabilisation_residual = \"becker\"",
            ),
            "scene.substokes.stabilisation_residual",
            "literal",
        ),
        (
            "ties-unknown",
            with("ties = \"split\"", "ties = \"random\""),
            "study.ties",
            "split",
        ),
        (
            "velocity-two",
            with(
                "upper_wall_velocity = [0.0, 0.0, 10.0]",
                "upper_wall_velocity = [0.0, 10.0]",
            ),
            "scene.substokes.upper_wall_velocity",
            "3",
        ),
        (
            "negative-pressure-cavitation",
            with("boundary_pressure = 200.0", "boundary_pressure = -1.0"),
            "scene.substokes.boundary_pressure",
            "≥ 0",
        ),
        (
            "with-elasticity",
            with(
                "effects = [\"substokes\"]",
                "effects = [\"substokes\", \"elasticity\"]",
            ),
            "scene.effects",
            "alone",
        ),
        (
            "unknown-section",
            with("[scene.substokes]", "[scene.reynolds_typo]"),
            "scene.reynolds_typo",
            "substokes",
        ),
        (
            "probe-s1",
            with(
                "components = [\"psi\", \"chi1\", \"chi2\"]",
                "components = [\"s1\"]",
            ),
            "probes.components[0]",
            "chi1",
        ),
        (
            "unknown-solver",
            with(
                "cavitation = \"on\"",
                "cavitation = \"on\"\nsolver = \"umfpack\"",
            ),
            "scene.substokes.solver",
            "ldlt",
        ),
    ];
    for (case, text, field, needle) in &cases {
        expect_error_in("IV.70.toml", case, text, field, needle);
    }
}

/// The solver study of Fig. III.6: bad values name file, field and expectation.
#[test]
fn uzawa_checks_name_file_and_field() {
    let base = fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments/fig-III.6.toml"),
    )
    .expect("the shipped Uzawa experiment");
    let dir = scratch_dir("uzawa-valid");
    load(&write(&dir, "fig-III.6.toml", &base)).unwrap_or_else(|e| panic!("{e}"));
    let with = |from: &str, to: &str| {
        assert!(base.contains(from), "test setup: `{from}`");
        base.replacen(from, to, 1)
    };
    let cases: Vec<(&str, String, &str, &str)> = vec![
        (
            "zero-iterations",
            with("rows = 300", "rows = 0"),
            "study.rows",
            "at least 1",
        ),
        (
            "too-many-iterations",
            with("rows = 300", "rows = 100000"),
            "study.rows",
            "at most 10000",
        ),
        (
            "unknown-variant",
            with("\"ssor\", \"cg-ssor\"", "\"ssor\", \"multigrid\""),
            "scene.stokes_channel.variants[4]",
            "cg-ssor",
        ),
        (
            "twice",
            with("\"ssor\", \"cg-ssor\"", "\"ssor\", \"ssor\""),
            "scene.stokes_channel.variants[4]",
            "once",
        ),
        (
            "no-variant",
            with(
                "variants = [\"identity\", \"jacobi\", \"gauss-seidel\", \"ssor\", \"cg-ssor\"]",
                "variants = []",
            ),
            "scene.stokes_channel.variants",
            "at least one",
        ),
        (
            "delta-zero",
            with("delta_eps = 1.0", "delta_eps = 0.0"),
            "scene.stokes_channel.delta_eps",
            "> 0",
        ),
        (
            "delta-nan",
            with("delta_eps = 1.0", "delta_eps = nan"),
            "scene.stokes_channel.delta_eps",
            "finite",
        ),
        (
            "grid-kind",
            with("kind = \"solver-iterations\"", "kind = \"grid-adaptive\""),
            "study.kind",
            "solver-iterations",
        ),
        (
            "marking-field",
            with("quick_rows = 60", "quick_rows = 60\nrefine_fraction = 0.3"),
            "study.refine_fraction",
            "no such field",
        ),
        (
            "window",
            with(
                "quick_rows = 60",
                "quick_rows = 60\nconvergence_window = [1, 2]",
            ),
            "study.convergence_window",
            "no such field",
        ),
        (
            "figure-id",
            with("table = \"fig-III.6\"", "table = \"fig-III.7\""),
            "table",
            "fig-III.<n>",
        ),
        (
            "section-chapter",
            with("section = \"III.2.3.4\"", "section = \"IV.2.3.4\""),
            "section",
            "III",
        ),
        (
            "with-substokes",
            with(
                "effects = [\"stokes-channel\"]",
                "effects = [\"stokes-channel\", \"substokes\"]",
            ),
            "scene.effects",
            "alone",
        ),
    ];
    for (case, text, field, needle) in &cases {
        expect_error_in("fig-III.6.toml", case, text, field, needle);
    }
}

/// The model-adaptive film of Fig. IV.116: the two sections must describe one film without
/// cavitation, the study must mark models by Algorithm III.3.
#[test]
fn model_fluid_checks_name_file_and_field() {
    let base = fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments/fig-IV.116.toml"),
    )
    .expect("the shipped model-adaptive fluid experiment");
    let dir = scratch_dir("model-fluid-valid");
    load(&write(&dir, "fig-IV.116.toml", &base)).unwrap_or_else(|e| panic!("{e}"));
    let in_substokes = |from: &str, to: &str| {
        let at = base.find("[scene.substokes]").expect("test setup");
        let (head, tail) = base.split_at(at);
        assert!(tail.contains(from), "test setup: `{from}`");
        format!("{head}{}", tail.replacen(from, to, 1))
    };
    let with = |from: &str, to: &str| {
        assert!(base.contains(from), "test setup: `{from}`");
        base.replacen(from, to, 1)
    };
    let cases: Vec<(&str, String, &str, &str)> = vec![
        (
            "other-gap",
            in_substokes("g0 = 0.1", "g0 = 0.2"),
            "scene.substokes.gap",
            "same gap",
        ),
        (
            "other-velocity",
            in_substokes("[40.0, 0.0, 0.0]", "[10.0, 0.0, 0.0]"),
            "scene.substokes.upper_wall_velocity",
            "same",
        ),
        (
            "other-pressure",
            in_substokes("boundary_pressure = 200.0", "boundary_pressure = 100.0"),
            "scene.substokes.boundary_pressure",
            "same",
        ),
        (
            "cavitation",
            in_substokes("cavitation = \"off\"", "cavitation = \"on\""),
            "scene.substokes.cavitation",
            "off",
        ),
        (
            "grid-kind",
            with(
                "kind = \"model-and-grid-adaptive\"",
                "kind = \"grid-adaptive\"",
            ),
            "study.kind",
            "model-and-grid-adaptive",
        ),
        (
            "algorithm-iii2",
            with("algorithm = \"III.3\"", "algorithm = \"III.2\""),
            "study.algorithm",
            "III.3",
        ),
        (
            "balance",
            with(
                "algorithm = \"III.3\"",
                "algorithm = \"III.3\"\nbalance = 0.5",
            ),
            "study.balance",
            "no balance",
        ),
        (
            "no-model-fraction",
            with("model_refine_fraction = 0.05\n", ""),
            "study.model_refine_fraction",
            "no such field",
        ),
        (
            "three-effects",
            with(
                "effects = [\"reynolds\", \"substokes\"]",
                "effects = [\"reynolds\", \"substokes\", \"elasticity\"]",
            ),
            "scene.effects",
            "alone",
        ),
        (
            "related-not-an-id",
            with(
                "related = [\"IV.46\", \"IV.60\"]",
                "related = [\"IV.46\", \"Table 60\"]",
            ),
            "related[1]",
            "another table or figure experiment",
        ),
        (
            "related-itself",
            with(
                "related = [\"IV.46\", \"IV.60\"]",
                "related = [\"fig-IV.116\"]",
            ),
            "related[0]",
            "another table",
        ),
        (
            "related-past-the-tables",
            with("related = [\"IV.46\", \"IV.60\"]", "related = [\"IV.76\"]"),
            "related[0]",
            "`IV.76`",
        ),
    ];
    for (case, text, field, needle) in &cases {
        expect_error_in("fig-IV.116.toml", case, text, field, needle);
    }
}

/// A file with a byte that is not UTF-8 (here a Latin-1 `é` in the title) is named with the line
/// and column of the byte, not only "stream did not contain valid UTF-8".
#[test]
fn invalid_utf8_is_named_with_line_and_column() {
    let dir = scratch_dir("latin1");
    let mut bytes = Vec::new();
    for line in VALID.lines() {
        if line.starts_with("title = ") {
            bytes.extend_from_slice("title = \"Box ü caf".as_bytes());
            bytes.push(0xE9);
            bytes.extend_from_slice(b"\"");
        } else {
            bytes.extend_from_slice(line.as_bytes());
        }
        bytes.push(b'\n');
    }
    let path = dir.join("IV.1.toml");
    fs::write(&path, bytes).unwrap();
    let error = load(&path).expect_err("Latin-1 file");
    let message = error.to_string();
    assert!(message.contains(&path.display().to_string()), "{message}");
    // Line 3; `title = "Box ü caf` has 18 characters, so the byte is character 19.
    assert!(message.contains("line 3, column 19"), "{message}");
    assert!(message.contains("0xE9"), "{message}");
    let _ = fs::remove_dir_all(&dir);
}

/// A file named with another case of `.toml` is not skipped in silence (which made `--only IV.1`
/// say "available tables: " with nothing after it): it is an entry whose error names the file;
/// beside a `.toml` file of the same table it is left out.
#[test]
fn an_upper_case_toml_extension_is_named() {
    let dir = scratch_dir("upper-case");
    let upper = write(&dir, "IV.1.TOML", VALID);
    let only = ["IV.1".to_owned()];
    let loaded = tribo::experiment::load_each(&dir, Some(&only)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(loaded.len(), 1);
    let message = loaded[0].1.as_ref().expect_err("IV.1.TOML").to_string();
    assert!(message.contains(&upper.display().to_string()), "{message}");
    assert!(message.contains("`.toml`"), "{message}");
    write(&dir, "IV.1.toml", VALID);
    let specs = load_dir(&dir, None).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(specs.len(), 1);
    let _ = fs::remove_dir_all(&dir);
}

/// One-line texts made of invisible characters alone (zero-width space, word joiner, byte
/// order mark, Hangul filler, braille blank) render as nothing and are refused with file and
/// field; an invisible character inside visible text stays allowed.
#[test]
fn invisible_one_line_texts_are_refused() {
    let title = "title = \"Box under a constant volume load\"";
    for (case, text, field) in [
        (
            "zero-width title",
            edit(title, "title = \"\u{200B}\""),
            "title",
        ),
        (
            "joiners title",
            edit(title, "title = \"\u{2060}\u{FEFF}\u{200D}\""),
            "title",
        ),
        (
            "filler title",
            edit(title, "title = \"\u{3164} \u{2800}\""),
            "title",
        ),
        (
            "zero-width scene name",
            edit(
                "name = \"box-constant-load\"",
                "name = \"\u{200B}\u{200C}\"",
            ),
            "scene.name",
        ),
    ] {
        expect_error(case, &text, field, "only invisible characters");
    }
    let dir = scratch_dir("visible");
    let path = write(
        &dir,
        "IV.1.toml",
        &edit(title, "title = \"Box\u{200B}under a load\""),
    );
    load(&path).unwrap_or_else(|e| panic!("{e}"));
    let _ = fs::remove_dir_all(&dir);
}

/// An unknown manufactured field of a SubStokes scene is refused naming `scene.substokes.exact`
/// and the one known field; `exact` on a SubStokes scene with the Uzawa comparison is refused
/// naming the solver.
#[test]
fn unknown_substokes_exact_field_is_refused() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments/manufactured-substokes.toml");
    let text = fs::read_to_string(path).expect("shipped");
    expect_error_in(
        "manufactured-substokes.toml",
        "substokes-exact-unknown",
        &text.replace("exact = \"arctan-cross\"", "exact = \"stream-bump\""),
        "scene.substokes.exact",
        "unknown variant `stream-bump`, expected one of `arctan-cross`",
    );
    expect_error_in(
        "manufactured-substokes.toml",
        "substokes-exact-compare",
        &text.replace(
            "exact = \"arctan-cross\"",
            "exact = \"arctan-cross\"\ncompare_with = \"uzawa\"",
        ),
        "scene.substokes.solver",
        "no compare_with",
    );
}

// The wider vocabulary of own scenes: step, parabolic and tabulated gaps, periodic obstacles
// with a period and a phase, tabulated obstacles, and the material by E and ν.

/// A gap profile over the unit square's x₁ ∈ [0, 1]: a converging pad.
const GAP_CSV: &str = "x1,g\n0.0,0.2\n0.25,0.15\n0.5,0.12\n0.75,0.11\n1.0,0.1\n";

/// An obstacle profile over the thesis's x₁ ∈ [−16, 16].
const OBSTACLE_CSV: &str = "x1,b\n-16,-2\n-4,-2\n0,-1.2\n4,-2\n16,-2\n";

/// Loads `text` as `IV.1.toml` with `files` (name, text) beside it and returns the error,
/// checking as [`expect_error`] that it names the file and `field` and contains `needle`; a
/// message about a profile (`…file`) must also name the CSV file's path.
fn expect_error_beside(
    case: &str,
    text: &str,
    files: &[(&str, &str)],
    field: &str,
    needle: &str,
) -> ExperimentError {
    let dir = scratch_dir(case);
    for (name, content) in files {
        if let Some(folder) = dir.join(name).parent() {
            fs::create_dir_all(folder).expect("a profile folder");
        }
        write(&dir, name, content);
    }
    let path = write(&dir, "IV.1.toml", text);
    let error = match load(&path) {
        Ok(_) => panic!("{case}: expected an error, the file loaded"),
        Err(error) => error,
    };
    let message = error.to_string();
    assert!(
        message.contains(&path.display().to_string()),
        "{case}: message does not name the file:\n{message}"
    );
    assert!(
        message.contains(&format!("`{field}`")),
        "{case}: message does not name field `{field}`:\n{message}"
    );
    assert!(
        message.contains(needle),
        "{case}: message does not contain `{needle}`:\n{message}"
    );
    if let (true, Some((csv, _))) = (field.ends_with(".file"), files.first()) {
        let shown = dir.join(csv).display().to_string();
        assert!(
            message.contains(&shown),
            "{case}: message does not name the CSV file {shown}:\n{message}"
        );
    }
    assert_eq!(error.field(), Some(field), "{case}: field()");
    let _ = fs::remove_dir_all(&dir);
    error
}

/// Loads `text` as `IV.1.toml` with `files` beside it; it must load.
fn loads_beside(case: &str, text: &str, files: &[(&str, &str)]) -> tribo::experiment::Experiment {
    let dir = scratch_dir(case);
    for (name, content) in files {
        if let Some(folder) = dir.join(name).parent() {
            fs::create_dir_all(folder).expect("a profile folder");
        }
        write(&dir, name, content);
    }
    let path = write(&dir, "IV.1.toml", text);
    let spec = load(&path).unwrap_or_else(|e| panic!("{case}: {e}"));
    let _ = fs::remove_dir_all(&dir);
    spec
}

fn gap_scene(gap: &str) -> String {
    reynolds_scene(gap, r#"components = ["psi"]"#)
}

#[test]
fn own_gap_shapes_load() {
    use tribo::experiment::{GapShape, Problem};
    loads_beside(
        "step-ok",
        &gap_scene(r#"{ kind = "step", g_in = 0.2, g_out = 0.1, at = 0.7, s = 0.01 }"#),
        &[],
    );
    loads_beside(
        "journal-ok",
        &gap_scene(r#"{ kind = "parabolic", g0 = 0.05, center = 0.5, radius = 4.0 }"#),
        &[],
    );
    loads_beside(
        "ball-ok",
        &gap_scene(
            r#"{ kind = "parabolic", g0 = 0.05, center = 0.5, radius = 4.0, center_x2 = 0.5, radius_x2 = 2.0 }"#,
        ),
        &[],
    );
    // Comments and blank lines in the profile are skipped; the rows reach the loaded scene.
    let csv = format!("# measured\n{GAP_CSV}\n\n# end\n");
    let spec = loads_beside(
        "tabulated-ok",
        &gap_scene(r#"{ kind = "tabulated", file = "pad.csv" }"#),
        &[("pad.csv", &csv)],
    );
    let Problem::Reynolds(r) = &spec.problem else {
        panic!("a Reynolds scene")
    };
    let GapShape::Tabulated { file, rows } = &r.gap else {
        panic!("a tabulated gap")
    };
    assert_eq!(file, "pad.csv");
    assert_eq!(rows.len(), 5);
    assert_eq!(rows[1], [0.25, 0.15]);
    // As a spreadsheet saves it: a byte-order mark and Windows line ends.
    let saved = format!("\u{feff}{}", GAP_CSV.replace('\n', "\r\n"));
    loads_beside(
        "tabulated-spreadsheet-ok",
        &gap_scene(r#"{ kind = "tabulated", file = "pad.csv" }"#),
        &[("pad.csv", &saved)],
    );
    // A path into a subfolder, relative to the experiment file.
    loads_beside(
        "tabulated-subfolder-ok",
        &gap_scene(r#"{ kind = "tabulated", file = "profiles/pad.csv" }"#),
        &[("profiles/pad.csv", GAP_CSV)],
    );
}

#[test]
fn own_gap_shapes_name_file_and_field() {
    let step = r#"{ kind = "step", g_in = 0.2, g_out = 0.1, at = 0.7, s = 0.01 }"#;
    let journal = r#"{ kind = "parabolic", g0 = 0.05, center = 0.5, radius = 4.0 }"#;
    let tabulated = gap_scene(r#"{ kind = "tabulated", file = "pad.csv" }"#);
    let cases: Vec<(&str, String, &str, &str)> = vec![
        (
            "step-closed",
            gap_scene(&step.replace("g_out = 0.1", "g_out = 0.0")),
            "scene.reynolds.gap.g_out",
            "a finite number > 0",
        ),
        (
            "step-negative-inlet",
            gap_scene(&step.replace("g_in = 0.2", "g_in = -0.2")),
            "scene.reynolds.gap.g_in",
            "a finite number > 0",
        ),
        (
            "step-sharp",
            gap_scene(&step.replace("s = 0.01", "s = 0.0")),
            "scene.reynolds.gap.s",
            "a finite number > 0",
        ),
        (
            "step-at-nan",
            gap_scene(&step.replace("at = 0.7", "at = nan")),
            "scene.reynolds.gap.at",
            "a finite number",
        ),
        (
            "step-unknown-field",
            gap_scene(&step.replace("s = 0.01", "s = 0.01, g0 = 0.1")),
            "scene.reynolds.gap",
            "unknown field `g0`",
        ),
        (
            "journal-flat",
            gap_scene(&journal.replace("radius = 4.0", "radius = 0.0")),
            "scene.reynolds.gap.radius",
            "a finite number > 0",
        ),
        (
            "journal-closed",
            gap_scene(&journal.replace("g0 = 0.05", "g0 = 0.0")),
            "scene.reynolds.gap.g0",
            "a finite number > 0",
        ),
        (
            "journal-center-inf",
            gap_scene(&journal.replace("center = 0.5", "center = inf")),
            "scene.reynolds.gap.center",
            "a finite number",
        ),
        (
            "ball-without-radius",
            gap_scene(&journal.replace("radius = 4.0", "radius = 4.0, center_x2 = 0.5")),
            "scene.reynolds.gap.radius_x2",
            "radius_x2 with center_x2",
        ),
        (
            "ball-without-center",
            gap_scene(&journal.replace("radius = 4.0", "radius = 4.0, radius_x2 = 2.0")),
            "scene.reynolds.gap.center_x2",
            "center_x2 with radius_x2",
        ),
        (
            "ball-flat",
            gap_scene(&journal.replace(
                "radius = 4.0",
                "radius = 4.0, center_x2 = 0.5, radius_x2 = -1.0",
            )),
            "scene.reynolds.gap.radius_x2",
            "a finite number > 0",
        ),
        (
            "tabulated-rows-in-toml",
            gap_scene(r#"{ kind = "tabulated", file = "pad.csv", rows = [[0.0, 0.1]] }"#),
            "scene.reynolds.gap",
            "unknown field `rows`",
        ),
    ];
    for (case, text, field, needle) in &cases {
        expect_error_beside(case, text, &[("pad.csv", GAP_CSV)], field, needle);
    }
    // The profile itself: each bad file names the experiment file, the field, the CSV file,
    // the line and what was expected.
    let f = "scene.reynolds.gap.file";
    let csv_cases: [(&str, String, &str); 10] = [
        (
            "header",
            GAP_CSV.replace("x1,g", "x,g"),
            "the header `x1,g`",
        ),
        (
            "three-rows",
            "x1,g\n0,0.2\n0.5,0.1\n1,0.1\n".into(),
            "at least 4 rows",
        ),
        (
            "decreasing",
            GAP_CSV.replace("0.5,0.12", "0.2,0.12"),
            "strictly increasing from row to row, found",
        ),
        (
            "closed",
            GAP_CSV.replace("0.5,0.12", "0.5,0.0"),
            "the gap width > 0",
        ),
        (
            "semicolon",
            GAP_CSV.replace("0.5,0.12", "0.5;0.12"),
            "two numbers",
        ),
        (
            "three-columns",
            GAP_CSV.replace("0.5,0.12", "0.5,0.12,1"),
            "two numbers",
        ),
        (
            "nan",
            GAP_CSV.replace("0.5,0.12", "0.5,nan"),
            "finite numbers",
        ),
        (
            "short",
            GAP_CSV.replace("0.0,0.2", "0.1,0.2"),
            "reach over scene.domain.x",
        ),
        (
            "overshoot",
            // A drop from 0.3 to 0.01 that the spline undershoots to −0.0204 at x₁ ≈ 0.54.
            "x1,g\n0,0.3\n0.2,0.3\n0.4,0.3\n0.5,0.01\n0.6,0.01\n0.8,0.01\n1,0.01\n".into(),
            "stays positive on scene.domain.x",
        ),
        ("empty", String::new(), "no lines"),
    ];
    for (case, csv, needle) in &csv_cases {
        let error = expect_error_beside(
            &format!("csv-{case}"),
            &tabulated,
            &[("pad.csv", csv)],
            f,
            needle,
        );
        // Every row message points at a line of the file.
        if !["three-rows", "short", "overshoot", "empty"].contains(case) {
            assert!(error.to_string().contains(", line "), "{case}: {error}");
        }
    }
    let error = expect_error_beside("csv-missing", &tabulated, &[], f, "cannot read it");
    assert!(error.to_string().contains("pad.csv"), "{error}");
    expect_error_beside(
        "csv-empty-name",
        &tabulated.replace("pad.csv", ""),
        &[],
        f,
        "an empty file name",
    );
    // A directory where the profile should be.
    let dir = scratch_dir("csv-directory");
    fs::create_dir_all(dir.join("pad.csv")).expect("a directory");
    let path = write(&dir, "IV.1.toml", &tabulated);
    let error = load(&path).expect_err("a directory is no profile");
    assert!(error.to_string().contains("not a regular file"), "{error}");
    assert_eq!(error.field(), Some(f));
    let _ = fs::remove_dir_all(&dir);
    // The same checks in a SubStokes section name that section.
    let substokes = fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments/templates/substokes.toml"),
    )
    .expect("template");
    let gap_line = substokes
        .lines()
        .find(|l| l.starts_with("gap = "))
        .expect("a gap line");
    expect_error_in(
        "substokes.toml",
        "substokes-step-sharp",
        &substokes.replace(
            gap_line,
            r#"gap = { kind = "step", g_in = 0.2, g_out = 0.1, at = 0.7, s = -1.0 }"#,
        ),
        "scene.substokes.gap.s",
        "a finite number > 0",
    );
}

#[test]
fn own_obstacles_name_file_and_field() {
    let obstacle = |shape: &str| format!(r#"[{{ side = "bottom", shape = {shape} }}]"#);
    let scene = |shape: &str| contact_scene(&obstacle(shape), r#"["left", "right"]"#);
    let wave =
        r#"{ kind = "periodic", offset = -2.0, amplitude = 0.5, period = 8.0, phase = 1.0 }"#;
    let tabulated = r#"{ kind = "tabulated", file = "die.csv" }"#;
    let files = [("die.csv", OBSTACLE_CSV)];
    loads_beside("wave-ok", &scene(wave), &[]);
    loads_beside(
        "wave-without-phase-ok",
        &scene(&wave.replace(", phase = 1.0", "")),
        &[],
    );
    let spec = loads_beside("die-ok", &scene(tabulated), &files);
    let tribo::experiment::Problem::Contact { contact, .. } = &spec.problem else {
        panic!("a contact scene")
    };
    assert!(matches!(
        &contact.obstacles[0].shape,
        tribo::experiment::ObstacleShape::Tabulated { rows, .. } if rows.len() == 5
    ));
    let f = "scene.contact.obstacles[0].shape";
    let cases: Vec<(&str, String, &str, &str)> = vec![
        (
            "periods-and-period",
            scene(&wave.replace("phase = 1.0", "periods = 2.0")),
            "scene.contact.obstacles[0].shape.period",
            "not both",
        ),
        (
            "neither-periods-nor-period",
            scene(&wave.replace("period = 8.0, phase = 1.0", "phase = 1.0")),
            "scene.contact.obstacles[0].shape.period",
            "`period` (a length",
        ),
        (
            "phase-with-periods",
            scene(&wave.replace("period = 8.0", "periods = 2.0")),
            "scene.contact.obstacles[0].shape.phase",
            "no phase with `periods`",
        ),
        (
            "period-zero",
            scene(&wave.replace("period = 8.0", "period = 0.0")),
            "scene.contact.obstacles[0].shape.period",
            "a finite number > 0",
        ),
        (
            "period-negative",
            scene(&wave.replace("period = 8.0", "period = -8.0")),
            "scene.contact.obstacles[0].shape.period",
            "a finite number > 0",
        ),
        (
            "phase-infinite",
            scene(&wave.replace("phase = 1.0", "phase = inf")),
            "scene.contact.obstacles[0].shape.phase",
            "a finite number",
        ),
    ];
    for (case, text, field, needle) in &cases {
        expect_error_beside(case, text, &[], field, needle);
    }
    let file = format!("{f}.file");
    let csv_cases: [(&str, String, &str); 5] = [
        ("one-row", "x1,b\n-16,-2\n".into(), "at least 2 rows"),
        (
            "gap-header",
            OBSTACLE_CSV.replace("x1,b", "x1,g"),
            "the header `x1,b`",
        ),
        (
            "short",
            OBSTACLE_CSV.replace("16,-2\n", "15,-2\n"),
            "reach over scene.domain.x",
        ),
        (
            "repeated-x",
            OBSTACLE_CSV.replace("0,-1.2", "-4,-1.2"),
            "strictly increasing",
        ),
        (
            "inf",
            OBSTACLE_CSV.replace("0,-1.2", "0,-inf"),
            "finite numbers",
        ),
    ];
    for (case, csv, needle) in &csv_cases {
        expect_error_beside(
            &format!("die-{case}"),
            &scene(tabulated),
            &[("die.csv", csv)],
            &file,
            needle,
        );
    }
    expect_error_beside("die-missing", &scene(tabulated), &[], &file, "die.csv");
}

#[test]
fn material_by_young_and_poisson_names_file_and_field() {
    use tribo::experiment::Problem;
    let lame = "mu = 1.0\nlambda = 1.0";
    let by = |e: &str, nu: &str| edit(lame, &format!("young_modulus = {e}\npoisson_ratio = {nu}"));
    // E = 8/3, ν = 1/3 is the thesis's μ = λ = 1 (with its 2λ, λ_std = 2).
    let spec = loads_beside(
        "young-ok",
        &by("2.6666666666666665", "0.3333333333333333"),
        &[],
    );
    let Problem::Elasticity(data) = &spec.problem else {
        panic!("an elasticity scene")
    };
    let tribo::experiment::Lame { mu, lambda } = data.lame();
    assert!(
        (mu - 1.0).abs() < 1e-15 && (lambda - 1.0).abs() < 1e-15,
        "{mu} {lambda}"
    );
    loads_beside("auxetic-ok", &by("1.0", "-0.5"), &[]);
    let cases: Vec<(&str, String, &str, &str)> = vec![
        (
            "both-pairs",
            edit(
                lame,
                &format!("{lame}\nyoung_modulus = 1.0\npoisson_ratio = 0.3"),
            ),
            "scene.elasticity.young_modulus",
            "not both",
        ),
        (
            "lame-and-poisson",
            edit(lame, &format!("{lame}\npoisson_ratio = 0.3")),
            "scene.elasticity.poisson_ratio",
            "not both",
        ),
        (
            "neither",
            edit(lame, ""),
            "scene.elasticity",
            "the material: `mu` and `lambda`",
        ),
        (
            "mu-alone",
            edit(lame, "mu = 1.0"),
            "scene.elasticity.lambda",
            "together",
        ),
        (
            "lambda-alone",
            edit(lame, "lambda = 1.0"),
            "scene.elasticity.mu",
            "together",
        ),
        (
            "young-alone",
            edit(lame, "young_modulus = 1.0"),
            "scene.elasticity.poisson_ratio",
            "together",
        ),
        (
            "poisson-alone",
            edit(lame, "poisson_ratio = 0.3"),
            "scene.elasticity.young_modulus",
            "together",
        ),
        (
            "nu-half",
            by("1.0", "0.5"),
            "scene.elasticity.poisson_ratio",
            "−1 < ν < ½",
        ),
        (
            "nu-minus-one",
            by("1.0", "-1.0"),
            "scene.elasticity.poisson_ratio",
            "−1 < ν < ½",
        ),
        (
            "nu-nan",
            by("1.0", "nan"),
            "scene.elasticity.poisson_ratio",
            "−1 < ν < ½",
        ),
        (
            "nu-large",
            by("1.0", "2.0"),
            "scene.elasticity.poisson_ratio",
            "−1 < ν < ½",
        ),
        (
            "nu-locks",
            by("1.0", "0.49999999999"),
            "scene.elasticity.poisson_ratio",
            "λ/μ = ν/(1 − 2ν) ≤ 1e8",
        ),
        (
            "young-zero",
            by("0.0", "0.3"),
            "scene.elasticity.young_modulus",
            "a finite value",
        ),
        (
            "young-negative",
            by("-3.0", "0.3"),
            "scene.elasticity.young_modulus",
            "a finite value",
        ),
        (
            "young-infinite",
            by("inf", "0.3"),
            "scene.elasticity.young_modulus",
            "a finite value",
        ),
        (
            "young-as-text",
            by("\"stiff\"", "0.3"),
            "scene.elasticity.young_modulus",
            "invalid type",
        ),
    ];
    for (case, text, field, needle) in &cases {
        expect_error(case, text, field, needle);
    }
}
