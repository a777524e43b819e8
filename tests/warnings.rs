//! Legal but suspicious experiments: they run, and the report warns — in the
//! table's section, in the summary's status and on stderr. No shipped experiment warns.

use std::fs;
use std::path::{Path, PathBuf};

use tribo::experiment::{self, Experiment};
use tribo::results::Row;
use tribo::study::{self, Tier};

use crate::cli::{report, temp_dir};
use crate::common::{experiments_dir, quick};

/// A shipped experiment file with each `(from, to)` replaced once (each must be present).
pub fn edited(table: &str, edits: &[(&str, &str)]) -> String {
    let mut text = fs::read_to_string(experiments_dir().join(format!("{table}.toml"))).unwrap();
    for (from, to) in edits {
        assert!(text.contains(from), "{table}: `{from}` not in the file");
        text = text.replacen(from, to, 1);
    }
    text
}

/// Write `text` as `<table>.toml` into `dir`.
pub fn write(dir: &Path, table: &str, text: &str) -> PathBuf {
    let path = dir.join(format!("{table}.toml"));
    fs::write(&path, text).unwrap();
    path
}

/// Load an edited shipped file: it must load (a warning is not an error).
fn load_edited(case: &str, table: &str, edits: &[(&str, &str)]) -> Experiment {
    let dir = temp_dir(&format!("warn-{case}"));
    let path = write(&dir, table, &edited(table, edits));
    let e = experiment::load(&path).unwrap_or_else(|err| panic!("{case}: {err}"));
    let _ = fs::remove_dir_all(&dir);
    e
}

/// The warnings of `e` as `field: message` lines.
fn warning_lines(e: &Experiment) -> Vec<String> {
    e.warnings().iter().map(ToString::to_string).collect()
}

#[test]
fn no_shipped_experiment_warns() {
    for (stem, loaded) in experiment::load_each(&experiments_dir(), None).unwrap() {
        let e = loaded.unwrap_or_else(|err| panic!("{stem}: {err}"));
        assert_eq!(warning_lines(&e), Vec::<String>::new(), "{stem}");
    }
}

#[test]
fn no_shipped_quick_run_warns() {
    for table in ["IV.1", "IV.5", "IV.6", "IV.9", "IV.12", "IV.36", "IV.64"] {
        assert_eq!(quick(table).warnings, Vec::<String>::new(), "{table}");
    }
}

/// A warning case: its name, the shipped table it edits, the edits (from, to), the field warned
/// about, a word of the message.
type Case<'a> = (&'a str, &'a str, &'a [(&'a str, &'a str)], &'a str, &'a str);

/// Each suspicious field gives exactly one warning, naming the field.
#[test]
fn suspicious_fields_warn_naming_the_field() {
    let cases: [Case; 10] = [
        (
            "locking",
            "IV.1",
            &[("lambda = 1.0", "lambda = 1000.0")],
            "scene.elasticity.lambda",
            "locks the Q₁ elements",
        ),
        (
            "flat-cells",
            "IV.1",
            &[("coarse_cells = [64, 2]", "coarse_cells = [4, 2]")],
            "scene.coarse_cells",
            "sides in a ratio of 16.000",
        ),
        (
            "flat-cells-upright",
            "IV.1",
            &[("coarse_cells = [64, 2]", "coarse_cells = [64, 80]")],
            "scene.coarse_cells",
            "sides in a ratio of 40.000",
        ),
        (
            "step-outside",
            "IV.4",
            &[("at = 0.0", "at = 99.0")],
            "scene.elasticity.volume_load.profile.at",
            "the jump at x₁ = 99 lies outside the domain's x₁ ∈ (-16, 16)",
        ),
        (
            "jump-outside",
            "IV.9",
            &[("at = 0.0", "at = -16.0")],
            "scene.contact.obstacles[0].shape.at",
            "the jump at x₁ = -16 lies outside",
        ),
        (
            "estimator-of-the-other-model",
            "IV.12",
            &[("estimator = \"signorini-code\"", "estimator = \"z-code\"")],
            "scene.contact.estimator",
            "`z-code` with model `signorini`",
        ),
        (
            "walls-at-rest",
            "IV.36",
            &[(
                "upper_wall_velocity = [0.0, 0.0, -10.0]",
                "upper_wall_velocity = [0.0, 0.0, 0.0]",
            )],
            "scene.reynolds.upper_wall_velocity",
            "ψ ≡ boundary_pressure = 200",
        ),
        (
            // Cells of 0.5 refined at most 5 times: 0.015625.
            "sine-unresolved",
            "IV.5",
            &[("half_period = 16.0", "half_period = 1e-300")],
            "scene.elasticity.volume_load.profile.half_period",
            "half period 1e-300 is below the finest cell this run can reach (1.562e-2 wide",
        ),
        (
            "periodic-unresolved",
            "IV.7",
            &[("periods = 2.0", "periods = 1e6")],
            "scene.contact.obstacles[0].shape.periods",
            "half period 1.6e-5 is below the finest cell",
        ),
        (
            "gap-unresolved",
            "IV.44",
            &[("frequency = 2.0", "frequency = 1e9")],
            "scene.reynolds.gap.frequency",
            "half period 5e-10 is below the finest cell",
        ),
    ];
    for (case, table, edits, field, needle) in cases {
        let lines = warning_lines(&load_edited(case, table, edits));
        assert_eq!(lines.len(), 1, "{case}: {lines:?}");
        assert!(
            lines[0].starts_with(&format!("{field}: ")),
            "{case}: {lines:?}"
        );
        assert!(lines[0].contains(needle), "{case}: {lines:?}");
    }
}

/// At or below the thresholds: no warning (λ/μ = 100, cells of ratio 8, a jump just inside).
#[test]
fn ordinary_values_near_the_thresholds_do_not_warn() {
    for (case, table, edits) in [
        (
            "lambda-100",
            "IV.1",
            &[("lambda = 1.0", "lambda = 100.0")][..],
        ),
        (
            "ratio-8",
            "IV.1",
            &[("coarse_cells = [64, 2]", "coarse_cells = [64, 16]")][..],
        ),
        ("jump-inside", "IV.9", &[("at = 0.0", "at = 15.9")][..]),
    ] {
        assert_eq!(
            warning_lines(&load_edited(case, table, edits)),
            Vec::<String>::new(),
            "{case}"
        );
    }
}

fn run_warnings(case: &str, table: &str, edits: &[(&str, &str)]) -> Vec<String> {
    let e = load_edited(case, table, edits);
    study::run(&e, Tier::Quick, &|_, _, _| {})
        .unwrap_or_else(|err| panic!("{case}: {err}"))
        .warnings
}

/// What only the run shows: an unloaded body (every estimate exactly 0) and an obstacle that is
/// never touched.
#[test]
fn runs_warn_about_what_only_the_run_shows() {
    let w = run_warnings(
        "zero-load",
        "IV.1",
        &[("amplitude = 0.0004", "amplitude = 0.0")],
    );
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].starts_with("estimate: every printed estimate is 0"),
        "{w:?}"
    );

    let w = run_warnings("no-contact", "IV.12", &[("level = -2.0", "level = -100.0")]);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].starts_with("contact_vertices: no vertex touches an obstacle"),
        "{w:?}"
    );
}

/// An estimate that grows over the convergence window: the geometric mean of its ratios is
/// above 1 (rows made up; no shipped scene diverges).
#[test]
fn a_growing_estimate_warns_with_its_mean_growth() {
    let e = crate::common::spec("IV.1");
    let [first, last] = e.study.convergence_window().unwrap();
    let rows = |growth: f64| -> Vec<Row> {
        (0..=last)
            .map(|c| {
                Row::new(c)
                    .real("estimate", Some(growth.powi(c as i32)))
                    .real("ratio", (c > 0).then_some(growth))
            })
            .collect()
    };
    let w = study::warnings::of_run(&e, &rows(1.5));
    assert_eq!(w.len(), 1, "{w:?}");
    assert_eq!(w[0].field, "study.convergence_window");
    assert!(
        w[0].message.starts_with(&format!(
            "the estimate grows by ×1.5000 per cycle over printed cycles {first}–{last}"
        )),
        "{w:?}"
    );
    assert!(study::warnings::of_run(&e, &rows(0.7)).is_empty());
}

/// The report: the table is `ok` with its warning count in the summary, the section lists the
/// warnings, stderr names table and field, and the exit code is 0 (a warning is not a failure).
/// The step of IV.4's load moved past the domain leaves the body unloaded: one warning from the
/// file, one from the run.
#[test]
fn the_report_shows_warnings_in_summary_section_and_stderr() {
    let dir = temp_dir("warned-report");
    let exp = dir.join("experiments");
    fs::create_dir_all(&exp).unwrap();
    write(&exp, "IV.4", &edited("IV.4", &[("at = 0.0", "at = 99.0")]));
    write(&exp, "IV.2", &edited("IV.2", &[]));
    let out = report()
        .args(["--quick", "--no-progress", "--experiments"])
        .arg(&exp)
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    for line in [
        "warning: table IV.4: scene.elasticity.volume_load.profile.at: the jump at x₁ = 99",
        "warning: table IV.4: estimate: every printed estimate is 0",
        "; 1 with warnings",
    ] {
        assert!(stderr.contains(line), "`{line}` not in:\n{stderr}");
    }
    assert!(!stderr.contains("warning: table IV.2"), "{stderr}");
    let html = tribo::report::read_pages(&dir.join("out")).unwrap();
    let section = |table: &str| {
        let s = &html[html.find(&format!("<section id=\"t-{table}\"")).unwrap()..];
        s[..s.find("</section>").unwrap()].to_string()
    };
    let summary = &html[html.find("id=\"summary\"").unwrap()..];
    let summary = &summary[..summary.find("</table>").unwrap()];
    let row = |table: &str| {
        summary
            .split("<tr")
            .find(|r| r.contains(&format!("#t-{table}\"")))
            .unwrap()
            .to_string()
    };
    assert!(
        // IV.4 is edited (the jump moved): it runs, flagged, and is not scored.
        row("IV.4").contains(">edited: not scored, 2 warnings</td>"),
        "{}",
        row("IV.4")
    );
    assert!(
        row("IV.2").contains("<td class=\"status ok\">ok</td>"),
        "{}",
        row("IV.2")
    );
    let iv4 = section("IV.4");
    assert!(iv4.contains("Suspicious scene."), "{iv4}");
    assert!(
        iv4.contains("<li>scene.elasticity.volume_load.profile.at: the jump"),
        "{iv4}"
    );
    assert!(
        iv4.contains("<li>estimate: every printed estimate is 0"),
        "{iv4}"
    );
    assert!(!section("IV.2").contains("Suspicious scene."));
    let _ = fs::remove_dir_all(&dir);
}

/// The step gap warns where its step lies outside the domain, and where it is sharper than half
/// the cells of the first mesh (the Reynolds system is then indefinite, and the run fails — as
/// the warning says); the shipped example is clear of both.
#[test]
fn a_step_gap_warns_outside_the_domain_and_below_the_first_cells() {
    let shipped =
        fs::read_to_string(experiments_dir().join("own/step-bearing.toml")).expect("example");
    let gap = "gap = { kind = \"step\", g_in = 0.2, g_out = 0.1, at = 0.7, s = 0.02 }";
    assert!(shipped.contains(gap));
    let load = |case: &str, to: &str| {
        let dir = temp_dir(&format!("warn-{case}"));
        let path = write(&dir, "step-bearing", &shipped.replacen(gap, to, 1));
        let e = experiment::load(&path).unwrap_or_else(|err| panic!("{case}: {err}"));
        let _ = fs::remove_dir_all(&dir);
        e
    };
    let outside = load("step-outside", &gap.replace("at = 0.7", "at = 1.5"));
    assert_eq!(
        warning_lines(&outside),
        [
            "scene.reynolds.gap.at: the jump at x₁ = 1.5 lies outside the domain's x₁ ∈ (0, 1): \
          the gap is (up to the smoothing θ_s) constant on the domain"
        ]
    );
    let sharp = load("step-sharp", &gap.replace("s = 0.02", "s = 0.01"));
    let lines = warning_lines(&sharp);
    assert_eq!(lines.len(), 1, "{lines:?}");
    assert!(
        lines[0].starts_with("scene.reynolds.gap.s: a step smoothed over s = 0.01, less than half")
            && lines[0].contains("take s ≥ 0.015625"),
        "{lines:?}"
    );
    let failed = study::run(&sharp, Tier::Quick, &|_, _, _| {});
    assert!(
        failed.is_err(),
        "the sharp step is expected to fail, as warned"
    );
}
