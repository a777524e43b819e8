//! Sweeps of one's own scenes (`[sweep]` of a file, `report --set`): one run per value, each an
//! entry of its own, and one comparison section per sweep; every misuse refused with the file
//! and the field; and the thesis's alternative readings, which a scene of one's own runs only on
//! request.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Output;
use std::sync::OnceLock;

use tribo::experiment::{self, ExperimentError, SweepField};
use tribo::study::{Budget, TableOptions, Tier};

use crate::cli::{report, temp_dir};
use crate::common::{experiments_dir, without_seconds};

/// The shipped example: the step bearing at four sliding velocities.
const EXAMPLE: &str = "step-bearing-sweep";
const VELOCITIES: [f64; 4] = [-10.0, -20.0, -40.0, -80.0];

fn examples() -> PathBuf {
    experiments_dir().join("own")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// `report --quick --no-progress` over `dir` with `args`, into `out`.
fn quick_report(dir: &Path, out: &Path, args: &[&str]) -> Output {
    report()
        .args(["--quick", "--no-progress", "--experiments"])
        .arg(dir)
        .arg("--out")
        .arg(out)
        .args(args)
        .output()
        .unwrap()
}

/// The quick report of the shipped sweep with its shard records, made once per test process.
fn swept() -> &'static Path {
    static OUT: OnceLock<PathBuf> = OnceLock::new();
    OUT.get_or_init(|| {
        let out = temp_dir("sweep-example");
        let run = quick_report(&examples(), &out, &["--only", EXAMPLE, "--shard"]);
        assert!(run.status.success(), "{}", stderr(&run));
        out
    })
}

fn run_id(file: &str, v: f64) -> String {
    format!("{file}~{v}")
}

/// The value of `column` in the last row of `data/<table>.csv` of `out`.
fn last_value(out: &Path, table: &str, column: &str) -> f64 {
    let csv = fs::read_to_string(out.join("data").join(format!("{table}.csv"))).unwrap();
    let mut lines = csv.lines();
    let at = lines
        .next()
        .unwrap()
        .split(',')
        .position(|c| c == column)
        .unwrap_or_else(|| panic!("{table}: no column {column}"));
    lines
        .last()
        .unwrap()
        .split(',')
        .nth(at)
        .unwrap()
        .parse()
        .unwrap()
}

/// The section `id` of the page `html`, from its opening tag to its end.
fn section<'a>(html: &'a str, id: &str) -> &'a str {
    let start = html
        .find(&format!("<section id=\"{id}\""))
        .unwrap_or_else(|| panic!("no section {id}"));
    let end = start + html[start..].find("</section>").unwrap();
    &html[start..end]
}

/// The cells of each row of the first table of `html`, tags removed, with the header first.
fn table_rows(html: &str) -> Vec<Vec<String>> {
    let table = &html[html.find("<table>").unwrap()..html.find("</table>").unwrap()];
    let text = |cell: &str| {
        let mut out = String::new();
        let mut tag = false;
        for c in cell.chars() {
            match c {
                '<' => tag = true,
                '>' => tag = false,
                c if !tag => out.push(c),
                _ => {}
            }
        }
        out.trim().to_string()
    };
    table
        .split("<tr>")
        .skip(1)
        .map(|row| {
            row.split("</td>")
                .flat_map(|piece| piece.split("</th>"))
                .filter_map(|piece| {
                    let start = piece.rfind("<td").max(piece.rfind("<th"))?;
                    Some(text(&piece[start..]))
                })
                .collect()
        })
        .collect()
}

/// The shipped sweep of four velocities makes four runs — four data files, four sections, four
/// lines of `report --list` — and one comparison section whose table has each run's load
/// capacity. For a fixed gap the Reynolds load is linear in the sliding speed (ψ₀ = 0, no
/// cavitation: ψ is linear in δv, and the marking, which ranks the indicators, refines the same
/// cells at every speed), so the four loads are proportional to the velocity: measured, W/|v₁|
/// is 8.003646018840197 for all four at the quick tier (8.038224770301552 at the full tier, on
/// 92 516 dofs); asserted within 1 %.
#[test]
fn a_sweep_of_four_velocities_makes_four_runs_and_one_comparison() {
    let out = swept();
    let page = fs::read_to_string(out.join("scenes.html")).unwrap();
    for v in VELOCITIES {
        let id = run_id(EXAMPLE, v);
        assert!(out.join("data").join(format!("{id}.csv")).is_file(), "{id}");
        assert!(
            out.join("shard").join(format!("{id}.json")).is_file(),
            "{id}"
        );
        let own = section(&page, &format!("t-{id}"));
        assert!(own.contains("href=\"#sweep-step-bearing-sweep\""), "{id}");
        assert!(
            own.contains(&format!("upper_wall_velocity = [{v:?}, 0.0, 0.0]")),
            "{id}"
        );
    }
    assert_eq!(
        page.matches("<section id=\"t-step-bearing-sweep~").count(),
        4
    );
    assert_eq!(page.matches("<section id=\"sweep-").count(), 1);
    let comparison = section(&page, "sweep-step-bearing-sweep");
    assert!(
        comparison.contains("scene.reynolds.upper_wall_velocity over [-10.0, 0.0, 0.0], [-20.0, 0.0, 0.0], [-40.0, 0.0, 0.0], [-80.0, 0.0, 0.0]"),
        "the section says what was swept over which values"
    );
    assert!(
        !comparison.contains("thesis"),
        "no thesis figure in a comparison of own runs"
    );
    for kind in ["quantities", "cuts", "convergence"] {
        let file = format!("figures/step-bearing-sweep-sweep-{kind}.svg");
        assert!(comparison.contains(&file), "{file} on the page");
        assert!(out.join(&file).is_file(), "{file} written");
    }

    let rows = table_rows(comparison);
    let header = &rows[0];
    let load = header
        .iter()
        .position(|h| h.starts_with("load capacity"))
        .expect("a load capacity column");
    assert!(header.iter().any(|h| h.starts_with("largest pressure")));
    assert_eq!(rows.len(), 1 + VELOCITIES.len(), "{rows:?}");
    let mut per_speed = Vec::new();
    for v in VELOCITIES {
        let row = rows[1..]
            .iter()
            .find(|r| r[0] == format!("[{v:?}, 0.0, 0.0]"))
            .unwrap_or_else(|| panic!("no row for {v}: {rows:?}"));
        let shown: f64 = row[load].parse().unwrap();
        let computed = last_value(out, &run_id(EXAMPLE, v), "load_capacity");
        assert!(
            (shown / computed - 1.0).abs() < 1e-3,
            "{v}: the page shows {shown}, the data {computed}"
        );
        per_speed.push((v, computed / v.abs()));
    }
    let (lo, hi) = per_speed
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), (_, w)| {
            (lo.min(*w), hi.max(*w))
        });
    assert!(
        lo > 0.0 && hi / lo - 1.0 < 0.01,
        "load capacity per unit speed W/|v₁| differs by more than 1 %: {per_speed:?}"
    );

    let list = report()
        .args(["--quick", "--list", "--only", EXAMPLE, "--experiments"])
        .arg(examples())
        .output()
        .unwrap();
    let listing = String::from_utf8_lossy(&list.stdout);
    for v in VELOCITIES {
        assert!(listing.contains(&run_id(EXAMPLE, v)), "{listing}");
    }
}

/// `report --set` on the unswept step bearing gives the same runs as the sweep of the shipped
/// example: every value of every row (timings aside) of each velocity's data file is the same.
/// Integer values (`[-10,0,0]`) stand for the same numbers as `[-10.0, 0.0, 0.0]`.
#[test]
fn set_on_the_command_line_gives_the_runs_of_a_sweep_section() {
    let out = temp_dir("sweep-set");
    let run = quick_report(
        &examples(),
        &out,
        &[
            "--only",
            "step-bearing",
            "--set",
            "scene.reynolds.upper_wall_velocity=[-10,0,0],[-20,0,0],[-40,0,0],[-80,0,0]",
        ],
    );
    assert!(run.status.success(), "{}", stderr(&run));
    let data = |dir: &Path, table: &str| {
        without_seconds(&fs::read_to_string(dir.join("data").join(format!("{table}.csv"))).unwrap())
    };
    for v in VELOCITIES {
        let set = data(&out, &run_id("step-bearing", v));
        let section = data(swept(), &run_id(EXAMPLE, v));
        assert_eq!(set, section, "v₁ = {v}");
    }
    let page = fs::read_to_string(out.join("scenes.html")).unwrap();
    let comparison = section(&page, "sweep-step-bearing");
    assert!(
        comparison.contains("(report --set)"),
        "says where the sweep came from"
    );
    assert_eq!(table_rows(comparison).len(), 1 + VELOCITIES.len());
}

/// `report merge` of the sweep's shard records gives the comparison too.
#[test]
fn merged_shards_of_a_sweep_keep_its_comparison() {
    let merged = temp_dir("sweep-merged");
    let out = report()
        .arg("merge")
        .arg(swept())
        .arg("--out")
        .arg(&merged)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    let page = fs::read_to_string(merged.join("scenes.html")).unwrap();
    let comparison = section(&page, "sweep-step-bearing-sweep");
    assert_eq!(table_rows(comparison).len(), 1 + VELOCITIES.len());
    let single = fs::read_to_string(swept().join("scenes.html")).unwrap();
    let order = |html: &str| -> Vec<usize> {
        VELOCITIES
            .iter()
            .map(|v| {
                html.find(&format!("id=\"t-{}\"", run_id(EXAMPLE, *v)))
                    .unwrap()
            })
            .collect()
    };
    let rank = |positions: Vec<usize>| {
        let mut sorted = positions.clone();
        sorted.sort();
        positions
            .iter()
            .map(|p| sorted.iter().position(|s| s == p).unwrap())
            .collect::<Vec<_>>()
    };
    assert_eq!(
        rank(order(&page)),
        rank(order(&single)),
        "same order of the runs"
    );
}

/// A sweep whose value fails the checks of the file fails that run only: the others run, and the
/// comparison names the run without a result.
#[test]
fn a_run_that_fails_leaves_the_other_runs_of_its_sweep() {
    let dir = temp_dir("sweep-one-fails");
    let text = shipped().replace(
        "\"scene.reynolds.upper_wall_velocity\" = [[-10.0, 0.0, 0.0], [-20.0, 0.0, 0.0], [-40.0, 0.0, 0.0], [-80.0, 0.0, 0.0]]",
        "\"scene.reynolds.gap.g_out\" = [0.1, -0.05, 0.05]",
    );
    fs::write(dir.join(format!("{EXAMPLE}.toml")), text).unwrap();
    let out = dir.join("out");
    let run = quick_report(&dir, &out, &["--no-alternatives"]);
    assert_eq!(run.status.code(), Some(1), "{}", stderr(&run));
    assert!(
        stderr(&run).contains("sweep run step-bearing-sweep~-0.05 (scene.reynolds.gap.g_out = -0.05): field `scene.reynolds.gap.g_out`: expected a finite number > 0"),
        "{}",
        stderr(&run)
    );
    let page = fs::read_to_string(out.join("scenes.html")).unwrap();
    let comparison = section(&page, "sweep-step-bearing-sweep");
    assert_eq!(table_rows(comparison).len(), 3, "two runs with a result");
    assert!(comparison
        .contains("Without a result on this page: <a href=\"#t-step-bearing-sweep~-0.05\">"));
}

fn shipped() -> String {
    fs::read_to_string(examples().join(format!("{EXAMPLE}.toml"))).unwrap()
}

/// The runs of `text` written as `<file>.toml` in a fresh folder, with `set` swept.
fn runs_of(file: &str, text: &str, set: &[SweepField]) -> (PathBuf, Vec<experiment::Loaded>) {
    let dir = temp_dir(&format!("sweep-load-{file}"));
    let path = dir.join(format!("{file}.toml"));
    fs::write(&path, text).unwrap();
    (path, experiment::load_each_swept(&dir, None, set).unwrap())
}

/// The one error of the file: it names the file and `field`, and says `needle`.
fn refused(file: &str, text: &str, set: &[SweepField], field: &str, needle: &str) {
    let (path, loaded) = runs_of(file, text, set);
    let errors: Vec<&ExperimentError> = loaded
        .iter()
        .filter_map(|(_, l)| l.as_ref().err())
        .collect();
    assert!(!errors.is_empty(), "{file}: no error");
    for error in errors {
        let message = error.to_string();
        assert_eq!(error.path(), path, "{message}");
        assert_eq!(error.field(), Some(field), "{message}");
        assert!(
            message.starts_with(&path.display().to_string()),
            "{message}"
        );
        assert!(message.contains(&format!("`{field}`")), "{message}");
        assert!(
            message.contains(needle),
            "{file}: `{needle}` not in {message}"
        );
    }
}

/// The shipped sweep with its velocity line replaced by `line`.
fn sweeping(line: &str) -> String {
    let velocity = "\"scene.reynolds.upper_wall_velocity\" = [[-10.0, 0.0, 0.0], [-20.0, 0.0, 0.0], [-40.0, 0.0, 0.0], [-80.0, 0.0, 0.0]]";
    let text = shipped();
    assert!(text.contains(velocity), "test setup");
    text.replace(velocity, line)
}

/// Each misuse of a sweep fails with the file, the field and what was expected.
#[test]
fn bad_sweeps_are_refused_naming_file_and_field() {
    let v = "\"scene.reynolds.upper_wall_velocity\"";
    let field = "sweep.\"scene.reynolds.upper_wall_velocity\"";
    let cases: [(&str, String, &str, &str); 11] = [
        ("unknown", sweeping("\"scene.reynolds.velocity\" = [1.0, 2.0]"), "sweep.\"scene.reynolds.velocity\"", "a field that this file writes"),
        ("not-scene", sweeping("\"title\" = [\"a\", \"b\"]"), "sweep.\"title\"", "a field of [scene] or [study]"),
        ("table", sweeping("\"scene.reynolds\" = [1, 2]"), "sweep.\"scene.reynolds\"", "not a [table]"),
        ("empty", sweeping(&format!("{v} = []")), field, "an empty list runs nothing"),
        ("one", sweeping(&format!("{v} = [[-10.0, 0.0, 0.0]]")), field, "with one value, write it in the field itself"),
        ("twice", sweeping(&format!("{v} = [[-10.0, 0.0, 0.0], [-10, 0, 0]]")), field, "each value once"),
        ("single", sweeping(&format!("{v} = 3.0")), field, "a list of the values to run"),
        ("three", sweeping(&format!("{v} = [[-1.0, 0.0, 0.0], [-2.0, 0.0, 0.0]]\n\"scene.reynolds.gap.g_out\" = [0.1, 0.05]\n\"study.rows\" = [3, 4]")), "sweep", "at most 2 fields"),
        ("many", sweeping(&format!("{v} = [[-1.0, 0.0, 0.0], [-2.0, 0.0, 0.0], [-3.0, 0.0, 0.0]]\n\"scene.reynolds.gap.g_out\" = [0.1, 0.09, 0.08, 0.07, 0.06, 0.05]")), "sweep", "at most 16 runs"),
        ("type", sweeping(&format!("{v} = [\"fast\", \"slow\"]")), "scene.reynolds.upper_wall_velocity", "invalid type: string"),
        ("quantity", shipped().replace("quantities = [\"load_capacity\", \"max_pressure\"]", "quantities = [\"load_capacity\", \"contact_force\"]"), "sweep.quantities[1]", "a quantity of a reynolds scene"),
    ];
    for (name, text, field, needle) in &cases {
        refused(name, &text.replace(EXAMPLE, name), &[], field, needle);
    }
    // The type error is the run's own check, and names the run and its value.
    let (_, loaded) = runs_of("type-run", &cases[9].1.replace(EXAMPLE, "type-run"), &[]);
    let message = loaded[0].1.as_ref().unwrap_err().to_string();
    assert!(
        message.contains("sweep run type-run~fast (scene.reynolds.upper_wall_velocity = \"fast\")"),
        "{message}"
    );

    // A thesis file: copy it under an id of your own.
    let iv36 = fs::read_to_string(experiments_dir().join("IV.36.toml")).unwrap()
        + "\n[sweep]\n\"scene.reynolds.boundary_pressure\" = [100.0, 200.0]\n";
    refused(
        "IV.36",
        &iv36,
        &[],
        "sweep",
        "copy the file under an id of your own",
    );
    // `report --set` names its field so.
    let set = [experiment::parse_set("scene.reynolds.gap.g_out=0.1,0.1").unwrap()];
    refused(
        "set-twice",
        &shipped().replace(EXAMPLE, "set-twice"),
        &set,
        "--set scene.reynolds.gap.g_out",
        "each value once",
    );
    let dir = temp_dir("sweep-thesis-set");
    fs::copy(experiments_dir().join("IV.36.toml"), dir.join("IV.36.toml")).unwrap();
    let error = experiment::load_each_swept(&dir, None, &set).unwrap_err();
    assert!(
        error
            .to_string()
            .contains("--set sweeps scenes of your own"),
        "{error}"
    );
    // `load` of one file refuses a swept one: it makes several runs.
    let error = experiment::load(&examples().join(format!("{EXAMPLE}.toml"))).unwrap_err();
    assert_eq!(error.field(), Some("sweep"), "{error}");
}

/// `--set` is checked before anything runs: a value that is no TOML, or more than two fields,
/// ends the program with status 2 and says why.
#[test]
fn bad_set_flags_end_the_run_before_it_starts() {
    let out = temp_dir("sweep-bad-set");
    for (args, needle) in [
        (
            vec!["--set", "scene.reynolds.upper_wall_velocity=[-10,0,0"],
            "not a TOML value",
        ),
        (
            vec!["--set", "scene.reynolds.upper_wall_velocity"],
            "no `=`",
        ),
        (
            vec![
                "--set",
                "scene.a=1,2",
                "--set",
                "scene.b=1,2",
                "--set",
                "study.rows=3,4",
            ],
            "a sweep varies at most 2",
        ),
    ] {
        let run = quick_report(&examples(), &out, &args);
        assert_eq!(run.status.code(), Some(2), "{args:?}: {}", stderr(&run));
        assert!(stderr(&run).contains(needle), "{args:?}: {}", stderr(&run));
    }
}

/// `--only` takes a swept file's id (every run) or one run's id; a run the sweep does not make is
/// named with the runs it does.
#[test]
fn only_selects_a_sweep_or_one_of_its_runs() {
    let ids = |only: &[&str]| -> Vec<String> {
        let only: Vec<String> = only.iter().map(|s| s.to_string()).collect();
        experiment::load_each_swept(&examples(), Some(&only), &[])
            .unwrap()
            .into_iter()
            .map(|(id, loaded)| {
                assert!(loaded.is_ok(), "{id}");
                id
            })
            .collect()
    };
    assert_eq!(
        ids(&[EXAMPLE]),
        ["-80", "-40", "-20", "-10"].map(|v| format!("{EXAMPLE}~{v}")),
        "ordered by value"
    );
    assert_eq!(ids(&["step-bearing-sweep~-40"]), ["step-bearing-sweep~-40"]);
    let error = experiment::load_each_swept(
        &examples(),
        Some(&["step-bearing-sweep~-5".to_string()]),
        &[],
    )
    .unwrap_err();
    assert!(
        error.to_string().contains("step-bearing-sweep~-10"),
        "{error}"
    );
}

/// The thesis's alternative readings (here the two readings of the cavitation source R₃c) run
/// beside a thesis table and beside a scene of one's own only when its file asks; a file that
/// asks where the scene has none is refused.
#[test]
fn own_scenes_run_the_thesis_readings_only_on_request() {
    let options = TableOptions {
        tier: Tier::Quick,
        budget: Budget::machine(),
        alternatives: true,
        vtu: tribo::results::VtuOutput::None,
    };
    let template = |name: &str| {
        fs::read_to_string(
            experiments_dir()
                .join("templates")
                .join(format!("{name}.toml")),
        )
        .unwrap()
    };
    let load = |name: &str, text: &str| {
        let dir = temp_dir(&format!("readings-{name}"));
        let path = dir.join(format!("{name}.toml"));
        fs::write(&path, text).unwrap();
        experiment::load(&path)
    };
    let suffixes = |e: &experiment::Experiment| -> Vec<String> {
        options.readings(e).into_iter().map(|r| r.suffix).collect()
    };
    let reynolds = template("reynolds");
    assert!(
        reynolds.contains("cavitation = \"auto\""),
        "a template with cavitation"
    );
    let own = load("reynolds", &reynolds).unwrap();
    assert_eq!(suffixes(&own), Vec::<String>::new(), "not by default");
    let asked = reynolds.replace("# alternatives = true", "alternatives = true");
    assert_ne!(asked, reynolds, "the template documents the field");
    let own = load("reynolds", &asked).unwrap();
    assert_eq!(suffixes(&own), ["self-consistent", "reynolds"]);
    let thesis = crate::common::spec("IV.64");
    assert_eq!(suffixes(&thesis), ["self-consistent", "reynolds"]);
    let off = TableOptions {
        alternatives: false,
        ..options
    };
    assert!(off.readings(&thesis).is_empty(), "--no-alternatives");

    let elasticity = template("elasticity").replace("[study]\n", "[study]\nalternatives = true\n");
    let error = load("elasticity", &elasticity).unwrap_err();
    assert_eq!(error.field(), Some("study.alternatives"), "{error}");
}

/// The template `name` under the id `id`, with the film of the model-fluid template (its wave
/// gap, wall velocity and boundary pressure).
fn film_template(name: &str, id: &str) -> String {
    let text = fs::read_to_string(
        experiments_dir()
            .join("templates")
            .join(format!("{name}.toml")),
    )
    .unwrap();
    let mut out = String::new();
    for line in text.lines() {
        let line = if line.starts_with("table = ") {
            format!("table = \"{id}\"")
        } else if line.starts_with("gap = ") {
            "gap = { kind = \"wave-horizontal\", g0 = 0.1, amplitude = 0.05, frequency = 2.0 }"
                .into()
        } else if line.starts_with("upper_wall_velocity = ") {
            "upper_wall_velocity = [20.0, 0.0, 0.0]".into()
        } else if line.starts_with("boundary_pressure = ") {
            "boundary_pressure = 200.0".into()
        } else if line.starts_with("equation = ") {
            "equation = \"own\"".into()
        } else if line.starts_with("related = ") && name == "model-fluid" {
            "related = [\"my-reynolds\", \"my-substokes\"]".into()
        } else {
            line.to_string()
        };
        out.push_str(&line);
        out.push('\n');
    }
    out
}

/// A model-adaptive film of one's own with related pure Reynolds and SubStokes runs gets a
/// comparison of the three runs — a row each, ψ along the cut, the estimates against dofs — and
/// none of the thesis's Figs IV.117/IV.118 (no thesis number in a caption, no empty plot of
/// SubStokes cells).
#[test]
fn an_own_scene_is_compared_with_its_related_runs() {
    let dir = temp_dir("related-own");
    for (name, id) in [
        ("model-fluid", "my-film"),
        ("reynolds", "my-reynolds"),
        ("substokes", "my-substokes"),
    ] {
        fs::write(dir.join(format!("{id}.toml")), film_template(name, id)).unwrap();
    }
    let out = dir.join("out");
    let run = quick_report(&dir, &out, &[]);
    assert!(run.status.success(), "{}", stderr(&run));
    let page = fs::read_to_string(out.join("scenes.html")).unwrap();
    assert!(
        !page.contains("IV.117") && !page.contains("IV.118"),
        "no thesis figure"
    );
    assert!(!out.join("figures/my-film-substokes-cells.svg").exists());
    let comparison = section(&page, "runs-my-film");
    let rows = table_rows(comparison);
    assert_eq!(rows.len(), 4, "{rows:?}");
    for id in ["my-film", "my-reynolds", "my-substokes"] {
        assert!(
            rows.iter().any(|r| r.last() == Some(&id.to_string())),
            "{id}: {rows:?}"
        );
    }
    for kind in ["cuts", "convergence"] {
        let file = format!("figures/my-film-runs-{kind}.svg");
        assert!(
            comparison.contains(&file) && out.join(&file).is_file(),
            "{file}"
        );
    }
    assert!(section(&page, "t-my-film").contains("href=\"#runs-my-film\""));
}
