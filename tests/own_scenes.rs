//! Scenes of the user's own: the templates of `experiments/templates/`, free ids, the optional
//! `[thesis]`, and edited thesis experiments, which run but are not scored against the thesis.

use std::fs;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use tribo::experiment::{self, Comparison, Experiment, ExperimentError};
use tribo::study::{self, Tier};
use tribo::thesis::ThesisTable;

use crate::cli::report;
use crate::common::{experiments_dir, refused_at};

/// The templates, one per family; each one's id is its file name.
const TEMPLATES: [&str; 6] = [
    "elasticity",
    "contact",
    "model-contact",
    "reynolds",
    "substokes",
    "model-fluid",
];

/// The shipped examples of `experiments/own/`, one per part of the wider vocabulary: the step
/// gap, the tabulated gap, and the tabulated and periodic obstacles with the material by E and ν.
/// (The sweep of the step bearing, `step-bearing-sweep`, is checked in tests/sweep.rs.)
const EXAMPLES: [&str; 3] = ["die-and-wave", "step-bearing", "worn-pad"];

fn templates_dir() -> PathBuf {
    experiments_dir().join("templates")
}

fn examples_dir() -> PathBuf {
    experiments_dir().join("own")
}

fn template(name: &str) -> String {
    fs::read_to_string(templates_dir().join(format!("{name}.toml"))).expect("template exists")
}

fn scratch(name: &str) -> PathBuf {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    crate::common::scratch(&format!("own-{n}-{name}"))
}

fn write(dir: &Path, file: &str, text: &str) -> PathBuf {
    let path = dir.join(file);
    fs::write(&path, text).unwrap();
    path
}

/// `text` with `from` replaced by `to` once (`from` must occur).
fn with(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "test setup: `{from}` not found");
    text.replacen(from, to, 1)
}

/// The error of loading `text` as `dir/file`; its message names the file, the field and
/// contains `needle`.
fn refused(file: &str, text: &str, field: &str, needle: &str) -> ExperimentError {
    let dir = scratch("refused");
    refused_at(&write(&dir, file, text), field, needle)
}

#[test]
fn every_template_loads_and_runs_at_quick_tier() {
    for name in TEMPLATES {
        let id = name;
        let path = templates_dir().join(format!("{name}.toml"));
        let spec = experiment::load(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(spec.comparison, Comparison::OwnScene, "{name}");
        assert_eq!(spec.table, id, "{name}");
        assert!(
            spec.thesis.rows.is_empty(),
            "{name}: a template has no [thesis]"
        );
        let thesis = ThesisTable::of(&spec);
        assert!(thesis.is_empty() && thesis.comparison == Comparison::OwnScene);
        let run = study::run(&spec, Tier::Quick, &|_, _, _| {})
            .unwrap_or_else(|e| panic!("{name}: quick tier fails: {e}"));
        assert_eq!(run.table, id);
        assert_eq!(
            run.rows.len(),
            spec.study.quick_rows,
            "{name}: one row per cycle"
        );
        assert!(
            run.rows.iter().all(|r| r
                .value("estimate")
                .or_else(|| r.value("model_error"))
                .is_some_and(f64::is_finite)),
            "{name}: every row has a finite estimate or model error"
        );
    }
}

/// In every block of lines (between blank lines) of `text` that sets a field, a comment comes
/// before the first field.
fn assert_commented(name: &str, text: &str) {
    for block in text.split("\n\n") {
        let lines: Vec<&str> = block.lines().map(str::trim_start).collect();
        let Some(first) = lines
            .iter()
            .position(|l| l.contains(" = ") && !l.starts_with('#'))
        else {
            continue;
        };
        assert!(
            lines[..first].iter().any(|l| l.starts_with('#')),
            "{name}: no comment before `{}`",
            lines[first]
        );
    }
}

/// Every template explains its fields ([`assert_commented`]) and says how to run it.
#[test]
fn templates_are_commented() {
    for name in TEMPLATES {
        let text = template(name);
        assert!(text.contains("--experiments my-dir"), "{name}: how to run");
        assert_commented(name, &text);
    }
}

/// The examples of `experiments/own/` are commented like the templates, say how to run them,
/// load as scenes of the user's own, do not warn, and run at the quick tier with results that
/// show what each is about: the step bearing's pressure peaks at the step, the worn pad's at the
/// end of its taper, and the strip rests on the die's insert.
#[test]
fn the_own_examples_run_and_show_their_point() {
    let loaded: Vec<_> = experiment::load_dir(&examples_dir(), None)
        .unwrap()
        .into_iter()
        .filter(|e| e.sweep.is_none())
        .collect();
    let ids: Vec<&str> = loaded.iter().map(|e| e.table.as_str()).collect();
    assert_eq!(ids, EXAMPLES);
    for spec in &loaded {
        let id = spec.table.as_str();
        let text = fs::read_to_string(examples_dir().join(format!("{id}.toml"))).unwrap();
        assert!(
            text.contains("--experiments experiments/own"),
            "{id}: how to run"
        );
        assert_commented(id, &text);
        assert_eq!(spec.comparison, Comparison::OwnScene, "{id}");
        assert_eq!(spec.warnings(), Vec::new(), "{id}");
        let run = study::run(spec, Tier::Quick, &|_, _, _| {})
            .unwrap_or_else(|e| panic!("{id}: quick tier fails: {e}"));
        assert_eq!(run.rows.len(), spec.study.quick_rows, "{id}");
        assert!(
            run.rows
                .iter()
                .all(|r| r.value("estimate").is_some_and(f64::is_finite)),
            "{id}: every row has a finite estimate"
        );
        assert_eq!(run.warnings, Vec::<String>::new(), "{id}");
        let probe = |x: f64, y: f64| {
            run.probes
                .iter()
                .find(|p| p.x == x && p.y == y)
                .unwrap_or_else(|| panic!("{id}: no probe at ({x}, {y})"))
                .value
        };
        match id {
            "step-bearing" => {
                let psi: Vec<f64> = [0.2, 0.5, 0.65, 0.7, 0.75, 0.85, 0.95]
                    .iter()
                    .map(|&x| probe(x, 0.5))
                    .collect();
                assert!(psi.iter().all(|&p| p > 0.0), "{psi:?}");
                // ψ ≈ g·p rises to the step, and p ≈ ψ/g falls after it.
                assert!(psi[0] < psi[1] && psi[1] < psi[2], "{psi:?}");
                assert!(psi[4] / 0.1 > psi[1] / 0.2 && psi[4] > psi[5] && psi[5] > psi[6]);
            }
            "worn-pad" => {
                let psi: Vec<f64> = [0.1, 0.3, 0.5, 0.9]
                    .iter()
                    .map(|&x| probe(x, 0.5))
                    .collect();
                assert!(
                    psi[1] > psi[0] && psi[1] > psi[2] && psi[2] > psi[3],
                    "{psi:?}"
                );
            }
            "die-and-wave" => {
                // Resting on the insert b = −0.6, pushed against the wave's trough
                // b = 0.8 − 0.3 at x₁ = 6.5 (the probes lie beside it, below the wave).
                assert!(
                    (probe(-7.0, 0.0) + 0.6).abs() < 1e-9,
                    "{}",
                    probe(-7.0, 0.0)
                );
                for x in [5.0, 8.0] {
                    let top = 0.8 + 0.3 * (std::f64::consts::TAU * (x - 2.0) / 6.0).sin();
                    assert!(probe(x, 1.0) <= top + 1e-9, "x = {x}");
                }
                assert!(run.rows[0].count_of("contact_vertices") > Some(0));
            }
            other => panic!("{other}: an example without a check"),
        }
    }
}

#[test]
fn the_default_experiment_folder_does_not_pick_up_the_templates() {
    let loaded = experiment::load_each(&experiments_dir(), None).unwrap();
    let stems: Vec<&str> = loaded.iter().map(|(stem, _)| stem.as_str()).collect();
    assert_eq!(
        stems.len(),
        84,
        "75 tables, 3 figures and the 6 manufactured scenes: {stems:?}"
    );
    for id in TEMPLATES.iter().chain(&EXAMPLES) {
        assert!(!stems.contains(id), "{id} picked up");
    }
}

#[test]
fn a_template_copied_under_a_thesis_id_is_refused() {
    let text = with(
        &template("reynolds"),
        "table = \"reynolds\"",
        "table = \"IV.40\"",
    );
    let error = refused("IV.40.toml", &text, "table", "pick another id");
    assert!(
        error.to_string().contains("the thesis's Table IV.40"),
        "{error}"
    );
}

#[test]
fn free_ids_follow_the_file_name_pattern() {
    let base = template("elasticity");
    let as_id = |id: &str| {
        with(
            &base,
            "table = \"elasticity\"",
            &format!("table = \"{id}\""),
        )
    };
    // Letters, digits, `.`, `-`, `_`: loads, under its own file name.
    let dir = scratch("free-id");
    let path = write(&dir, "Strip_2.b-c.toml", &as_id("Strip_2.b-c"));
    let spec = experiment::load(&path).unwrap();
    assert_eq!(spec.comparison, Comparison::OwnScene);
    // A space, a leading dot, a reserved prefix and a number out of the thesis's range.
    refused(
        "my strip.toml",
        &as_id("my strip"),
        "table",
        "letters, digits",
    );
    refused(
        ".strip.toml",
        &as_id(".strip"),
        "table",
        "starting with a letter or digit",
    );
    refused(
        "fig-mine.toml",
        &as_id("fig-mine"),
        "table",
        "not beginning with `IV.` or `fig-`",
    );
    refused("IV.76.toml", &as_id("IV.76"), "table", "1 ≤ n ≤ 75");
    // The id must be the file name.
    refused("other.toml", &as_id("my-strip"), "table", "`other`");
}

#[test]
fn an_own_scene_with_a_thesis_table_is_refused() {
    let text = format!(
        "{}\n[thesis]\ncolumns = [\"cycle\", \"dofs\"]\nrows = [[0, 1]]\n",
        template("elasticity")
    );
    refused("elasticity.toml", &text, "thesis", "scene of your own");
}

/// Copies `IV.<n>.toml` with `edits` applied into a scratch folder and loads it.
fn edited(table: &str, edits: &[(&str, &str)]) -> Experiment {
    let mut text = fs::read_to_string(experiments_dir().join(format!("{table}.toml"))).unwrap();
    for (from, to) in edits {
        text = with(&text, from, to);
    }
    let dir = scratch("edited");
    experiment::load(&write(&dir, &format!("{table}.toml"), &text)).unwrap()
}

#[test]
fn an_edited_thesis_experiment_names_the_fields_that_differ() {
    let e = edited(
        "IV.36",
        &[
            ("g0 = 0.1", "g0 = 0.12"),
            ("quick_rows = 3", "quick_rows = 2"),
        ],
    );
    assert_eq!(
        e.comparison,
        Comparison::Edited(vec![
            "scene.reynolds.gap.g0".into(),
            "study.quick_rows".into()
        ])
    );
    let thesis = ThesisTable::of(&e);
    assert!(thesis.is_empty(), "an edited table is not scored");
    assert_eq!(thesis.comparison, e.comparison);
    // A field added (even with its default value) or left out counts as a difference.
    let e = edited(
        "IV.1",
        &[("quick_rows = 4", "quick_rows = 4\nties = \"band\"")],
    );
    assert_eq!(e.comparison, Comparison::Edited(vec!["study.ties".into()]));
    // Printed rows count too.
    let shipped = experiment::load(&experiments_dir().join("IV.1.toml")).unwrap();
    let first = format!("[0, {}", shipped.thesis.rows[0][1]);
    let e = edited("IV.1", &[(&first, "[0, 1")]);
    assert_eq!(e.comparison, Comparison::Edited(vec!["thesis.rows".into()]));
}

#[test]
fn comments_layout_numbers_and_notes_do_not_make_an_edit() {
    let e = edited(
        "IV.36",
        &[
            ("g0 = 0.1", "g0 = 1e-1"),
            ("[study]", "[study] # how to iterate"),
            ("rows = 8\n", "rows   =   8\n"),
            ("[0.0, 0.0, -10.0]", "[0, 0, -10]"),
            ("notes = [", "notes = [\n  \"a note of my own\","),
        ],
    );
    assert_eq!(e.comparison, Comparison::Printed);
    assert_eq!(
        ThesisTable::of(&e).len(),
        8,
        "compared with the printed rows"
    );
}

#[test]
fn shipped_experiments_match_their_fingerprints() {
    let current = experiment::fingerprints(&experiments_dir()).unwrap();
    if current == experiment::PRINTED_LOCK {
        return;
    }
    let lock = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src/experiment/printed.lock");
    if std::env::var_os("TRIBO_UPDATE_PRINTED").is_some() {
        fs::write(&lock, &current).unwrap();
        panic!(
            "wrote new fingerprints to {}; rebuild and run the tests again",
            lock.display()
        );
    }
    let old: std::collections::BTreeSet<&str> = experiment::PRINTED_LOCK.lines().collect();
    let new: std::collections::BTreeSet<&str> = current.lines().collect();
    let changed: std::collections::BTreeSet<&str> = old
        .symmetric_difference(&new)
        .filter_map(|l| l.split_whitespace().next())
        .filter(|id| !id.starts_with('#'))
        .collect();
    panic!(
        "the scene, study or printed rows of shipped thesis experiments differ from their \
         fingerprints ({}): such a file is reported as edited and not scored against the \
         thesis. If the change is deliberate (a corrected reading, a fixed printed value), \
         update the fingerprints with\n  TRIBO_UPDATE_PRINTED=1 cargo test --release --test \
         tribo shipped_experiments_match_their_fingerprints\nand commit {}.",
        changed.into_iter().collect::<Vec<_>>().join(", "),
        lock.display()
    );
}

/// The page of an own scene and of an edited thesis table: status, notice, no Δ coloured, and
/// neither the thesis errata nor captions or header that speak of a printed table.
#[test]
fn the_report_says_what_is_not_compared() {
    let dir = scratch("report");
    let experiments = dir.join("experiments");
    fs::create_dir_all(&experiments).unwrap();
    let own = with(&template("elasticity"), "quick_rows = 3", "quick_rows = 2");
    let own = with(
        &own,
        "table = \"elasticity\"",
        "table = \"my-elastic-strip\"",
    );
    write(&experiments, "my-elastic-strip.toml", &own);
    let shipped = fs::read_to_string(experiments_dir().join("IV.1.toml")).unwrap();
    write(
        &experiments,
        "IV.1.toml",
        &with(&shipped, "mu = 1.0", "mu = 2.0"),
    );
    let out = dir.join("out");
    let output = report()
        .args([
            "--quick",
            "--no-progress",
            "--no-alternatives",
            "--experiments",
        ])
        .arg(&experiments)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let html = tribo::report::read_pages(&out).unwrap();
    assert!(html.contains("<td class=\"status ok\">own scene: not compared</td>"));
    assert!(html.contains("<td class=\"status ok\">edited: not scored</td>"));
    assert!(html.contains("Own scene: no thesis table, not compared."));
    assert!(html.contains(
        "The parameters differ from the printed table's (fields <code>scene.elasticity.mu</code>)"
    ));
    assert!(!html.contains("class=\"diff off\""), "no Δ coloured");
    assert!(!html.contains("The thesis prints no table for this result"));
    // Nothing of the thesis's framing where nothing is compared with it.
    assert!(!html.contains("<section id=\"errata\">"), "no errata");
    assert!(!html.contains("beside the printed one"));
    assert!(!html.contains("thesis (dashed)"));
    assert!(html.contains("<h1>tribo — scenes of your own</h1>"));
    // The front page's summary has no verdict, bands or printed order to show.
    let front = fs::read_to_string(out.join("index.html")).unwrap();
    assert!(front.contains(
        "<th class=\"text\">status</th><th>order</th><th title=\"estimate / true error over \
         the rows\">η / error</th><th>seconds</th>"
    ));
    assert!(!front.contains("rows within bands") && !front.contains("tribo / thesis"));
    assert!(out.join("data/my-elastic-strip.csv").exists());
    let _ = fs::remove_dir_all(&dir);
}
