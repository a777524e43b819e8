//! The `report` binary: flags, bad flags, malformed experiment files, and the files it writes.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn report() -> Command {
    Command::new(env!("CARGO_BIN_EXE_report"))
}

pub fn temp_dir(name: &str) -> PathBuf {
    crate::common::scratch(&format!("cli-{name}"))
}

fn experiments() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("experiments")
}

/// `report --quick --no-progress --only <table>` on the shipped experiments into `out`, with
/// `extra` flags.
fn quick_table(table: &str, out: &Path, extra: &[&str]) -> Output {
    report()
        .args(["--quick", "--no-progress", "--only", table, "--experiments"])
        .arg(experiments())
        .arg("--out")
        .arg(out)
        .args(extra)
        .output()
        .unwrap()
}

#[test]
fn unknown_flag_is_rejected_with_a_message() {
    let out = report().arg("--bogus").output().unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--bogus"), "{err}");
}

#[test]
fn unknown_table_is_named() {
    let out = report()
        .args(["--only", "IV.1,IV.999", "--experiments"])
        .arg(experiments())
        .arg("--out")
        .arg(temp_dir("unknown"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("IV.999"), "{err}");
}

#[test]
fn malformed_experiment_file_names_file_and_field() {
    let dir = temp_dir("malformed");
    let good = std::fs::read_to_string(experiments().join("IV.1.toml")).unwrap();
    let bad = good.replace("rows = 6", "rows = \"six\"");
    assert_ne!(good, bad, "the fixture must change the file");
    std::fs::write(dir.join("IV.1.toml"), bad).unwrap();
    let out = report()
        .arg("--experiments")
        .arg(&dir)
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .unwrap();
    // The file is a failed entry of the page (exit status 1), not an error of the whole run.
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("IV.1.toml") && err.contains("study.rows"),
        "{err}"
    );
    let html = tribo::report::read_pages(&dir.join("out")).unwrap();
    assert!(html.contains("not loaded") && html.contains("study.rows"));
}

#[test]
fn quick_run_of_one_table_writes_report_and_data() {
    let dir = temp_dir("quick");
    let out = quick_table("IV.3", &dir, &[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = std::fs::read_to_string(dir.join("data/IV.3.csv")).unwrap();
    let mut lines = csv.lines();
    assert!(lines
        .next()
        .unwrap()
        .starts_with("cycle,active_cells,dofs,estimate,ratio"));
    assert_eq!(lines.count(), 4, "quick tier has four rows");
    let probes = std::fs::read_to_string(dir.join("data/IV.3.probes.csv")).unwrap();
    assert!(probes.starts_with("x,y,component,value"));
    assert_eq!(probes.lines().count(), 1 + 14);
    let html = tribo::report::read_pages(&dir).unwrap();
    assert!(html.contains("IV.3") && html.contains("figures/"));
}

/// A cavitation table writes one data file per alternative reading of R₃c, and
/// `--no-alternatives` runs the experiment as written only.
#[test]
fn alternative_readings_run_unless_switched_off() {
    for (flag, expected) in [(None, true), (Some("--no-alternatives"), false)] {
        let dir = temp_dir(&format!("alternatives-{expected}"));
        let out = quick_table("IV.66", &dir, flag.as_slice());
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(dir.join("data/IV.66.csv").exists());
        for suffix in ["self-consistent", "reynolds"] {
            assert_eq!(
                dir.join(format!("data/IV.66.{suffix}.csv")).exists(),
                expected,
                "{flag:?}: {suffix}"
            );
        }
    }
}

/// `--out` naming a file: refused before any solve, saying what is wrong with it.
#[test]
fn out_that_is_a_file_is_named() {
    let dir = temp_dir("out-is-file");
    let file = dir.join("report.txt");
    std::fs::write(&file, "not a folder").unwrap();
    let out = quick_table("IV.1", &file, &[]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("exists and is not a directory"), "{err}");
    assert!(!err.contains("table IV.1"), "no table ran: {err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A small budget is written in its own unit (it said "0 MiB" for 10K) and the predicted
/// cells as an integer.
#[test]
fn a_small_memory_budget_is_written_in_its_unit() {
    let dir = temp_dir("small-budget");
    let out = quick_table("IV.1", &dir, &["--memory-budget", "10K"]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(
            "for about 128 active cells in this cycle, more than the memory budget of 10 KiB"
        ),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A model-adaptive table's page: the face split and model error per cycle and the partition
/// strips instead of the convergence and cost plots (its mesh is fixed), the z-solution reading
/// beside it, and the partition of every printed cycle.
#[test]
fn model_adaptive_tables_draw_their_partitions() {
    let out = temp_dir("model-adaptive");
    let run = quick_table("IV.29", &out, &[]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let figures = out.join("figures");
    assert!(figures.join("IV.29-model.svg").is_file());
    assert!(!figures.join("IV.29-convergence.svg").exists());
    assert!(!figures.join("IV.29-cost.svg").exists());
    let strips = std::fs::read_to_string(figures.join("IV.29-partition.svg")).unwrap();
    for (cycle, signorini) in [(0, 0), (1, 12), (8, 48), (9, 58)] {
        assert!(
            strips.contains(&format!("cycle {cycle}: {signorini} S")),
            "cycle {cycle}"
        );
    }
    assert!(out.join("data/IV.29.z-solution.csv").is_file());
    let page = tribo::report::read_pages(&out).unwrap();
    assert!(page.contains("Alternative reading: model error ε_P at the z-solution"));
    assert!(page.contains("<th>coarse_faces (alt.)</th>"));
    // The cost of accuracy of the scene: four variants over the ten cycles, the plot, the
    // verdicts on §IV.2.2 and §IV.2.3.
    let costs = std::fs::read_to_string(out.join("data/IV.29.cost.csv")).unwrap();
    let mut lines = costs.lines();
    assert_eq!(
        lines.next(),
        Some(
            "variant,cycle,seconds_solve,iterations,penetration,energy_distance,accurate_faces,\
             model_error,model_tolerance"
        )
    );
    assert_eq!(lines.count(), 40);
    assert!(figures.join("IV.29-accuracy.svg").is_file());
    assert!(page.contains("Cost of accuracy (this scene's fixed mesh)"));
    assert!(page.contains("§IV.2.2's trade-off holds on this scene"));
    assert!(page.contains("<b>III.2 vs III.3</b>"));
}

/// A model-and-grid-adaptive table: the convergence plot (with the thesis's three printed
/// estimate groups combined) and the partition on the adapted mesh.
#[test]
fn model_and_grid_tables_draw_convergence_and_partitions() {
    let out = temp_dir("model-and-grid");
    let run = quick_table("IV.31", &out, &["--no-alternatives"]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let figures = out.join("figures");
    let convergence = std::fs::read_to_string(figures.join("IV.31-convergence.svg")).unwrap();
    assert!(convergence.contains("thesis √(z² + S² + interior²)"));
    assert!(figures.join("IV.31-partition.svg").is_file());
    assert!(!figures.join("IV.31-model.svg").exists());
    // The Signorini faces (1, 3, 9 in cycles 1–3) drawn on the meshes.
    let meshes = std::fs::read_to_string(figures.join("IV.31-mesh.svg")).unwrap();
    assert!(meshes.contains("stroke-width=\"4\""));
    let data = std::fs::read_to_string(out.join("data/IV.31.csv")).unwrap();
    assert!(data.starts_with(
        "cycle,active_cells,dofs,z_faces,s_faces,model_error,est_z_boundary,est_s_boundary,\
         est_interior,estimate,ratio,"
    ));
}

/// Without a terminal on stderr (CI, a log file) the report prints one line per finished cycle
/// instead of a bar; `--no-progress` prints none.
#[test]
fn progress_without_a_terminal_is_one_line_per_cycle() {
    let run = |extra: &[&str], name: &str| {
        let out = report()
            .args([
                "--quick",
                "--no-alternatives",
                "--only",
                "IV.52",
                "--experiments",
            ])
            .arg(experiments())
            .arg("--out")
            .arg(temp_dir(name))
            .args(extra)
            .output()
            .unwrap();
        assert!(out.status.success());
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    let err = run(&[], "progress-lines");
    let lines: Vec<&str> = err.lines().filter(|l| l.contains("IV.52: cycle")).collect();
    // The quick tier of IV.52: one unprinted solve and five printed rows.
    assert_eq!(lines.len(), 6, "{err}");
    assert!(lines[5].ends_with("IV.52: cycle 6 of 6 done"), "{err}");
    let quiet = run(&["--no-progress"], "progress-none");
    assert!(!quiet.contains("cycle"), "{quiet}");
}

/// The page header records where the report came from: the commit of the checkout, the UTC
/// date, the machine and the command line.
#[test]
fn the_header_records_commit_date_machine_and_command() {
    let out = temp_dir("provenance");
    assert!(quick_table("IV.52", &out, &[]).status.success());
    let page = tribo::report::read_pages(&out).unwrap();
    let field = |name: &str| -> String {
        let start = format!("<dt>{name}</dt><dd>");
        let at = page
            .find(&start)
            .unwrap_or_else(|| panic!("no {name} in the header"))
            + start.len();
        page[at..].split("</dd>").next().unwrap().to_string()
    };
    let commit = field("commit");
    let hex = commit.split(' ').next().unwrap();
    if Path::new(env!("CARGO_MANIFEST_DIR")).join(".git").exists() {
        assert!(
            hex.len() == 12 && hex.chars().all(|c| c.is_ascii_hexdigit()),
            "{commit}"
        );
    } else {
        assert_eq!(commit, "unknown");
    }
    let date = field("date");
    assert!(
        date.len() == 20 && date.starts_with("20") && date.ends_with(" UTC"),
        "{date}"
    );
    assert!(field("machine").contains(" cores, "));
    assert!(field("command").contains("--only IV.52"));
}

/// The readings of the cavitation source apply only where the cavitation model runs: with
/// `cavitation = "auto"` on (IV.7), whose pressure never drops below zero, they are not run and
/// the page says why; on (IV.8), which cavitates, both run.
#[test]
fn cavitation_readings_run_only_where_cavitation_switches_on() {
    let dir = temp_dir("auto-readings");
    for (table, auto) in [("IV.36", "never"), ("IV.64", "switches")] {
        let text = std::fs::read_to_string(experiments().join(format!("{table}.toml"))).unwrap();
        let edited = text
            .replacen("cavitation = \"off\"", "cavitation = \"auto\"", 1)
            .replacen("cavitation = \"on\"", "cavitation = \"auto\"", 1);
        assert_ne!(text, edited, "{auto}: test setup");
        std::fs::write(dir.join(format!("{table}.toml")), edited).unwrap();
    }
    let out = dir.join("out");
    let run = report()
        .args(["--quick", "--no-progress", "--experiments"])
        .arg(&dir)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let data = |name: &str| out.join("data").join(name).exists();
    assert!(!data("IV.36.self-consistent.csv") && !data("IV.36.reynolds.csv"));
    assert!(data("IV.64.self-consistent.csv") && data("IV.64.reynolds.csv"));
    let page = tribo::report::read_pages(&out).unwrap();
    assert_eq!(
        page.matches("the cavitation model never switched on, so it would repeat the table")
            .count(),
        2,
        "one note per reading of IV.36"
    );
}

#[test]
fn a_memory_budget_in_exponent_notation_is_read() {
    let dir = temp_dir("budget-exponent");
    let out = quick_table("IV.1", &dir, &["--memory-budget", "4e3M"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // Far too small: the table is refused, which shows that the number was read as 4 KiB.
    let out = quick_table("IV.1", &dir, &["--memory-budget", "4e0K"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    // A number beyond f64 is refused, not read as infinity, and a negative one as such.
    for size in ["1e400M", "-4e3M"] {
        let out = quick_table("IV.1", &dir, &[&format!("--memory-budget={size}")]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(
            err.contains(&format!("`{size}` is not a memory size")),
            "{err}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A record edited to another stem holds the same table as the record of that table: merge
/// refuses it, naming the table and both records, instead of writing the table's data twice.
#[test]
fn merge_refuses_two_records_of_one_table_under_other_stems() {
    let dir = temp_dir("merge-stem");
    let (a, b) = (dir.join("a"), dir.join("b"));
    let out = quick_table("IV.1", &a, &["--shard"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let record = std::fs::read_to_string(a.join("shard/IV.1.json")).unwrap();
    let edited = record.replacen("\"stem\":\"IV.1\"", "\"stem\":\"IV.2\"", 1);
    assert_ne!(record, edited, "the fixture must change the stem");
    std::fs::create_dir_all(b.join("shard")).unwrap();
    std::fs::write(b.join("shard/IV.2.json"), edited).unwrap();
    let out = report()
        .arg("merge")
        .args([&a, &b])
        .arg("--out")
        .arg(dir.join("merged"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("table IV.1 is in two shard records")
            && err.contains("IV.1.json")
            && err.contains("IV.2.json"),
        "{err}"
    );
    assert!(!dir.join("merged/data/IV.1.csv").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--list` shows each experiment with its family, rows and predictions, runs nothing and
/// writes no folder; a file that does not load is listed with its error, and the exit code
/// says so.
#[test]
fn list_shows_the_experiments_without_running_them() {
    let dir = temp_dir("list");
    let out = dir.join("never-written");
    let listed = report()
        .args(["--list", "--quick", "--only", "IV.1,IV.36", "--experiments"])
        .arg(experiments())
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(listed.status.success(), "{listed:?}");
    let text = String::from_utf8_lossy(&listed.stdout);
    let line = |id: &str| {
        text.lines()
            .find(|l| l.split_whitespace().next() == Some(id))
            .unwrap_or_else(|| panic!("no line for {id}:\n{text}"))
            .to_string()
    };
    let iv1 = line("IV.1");
    let fields: Vec<&str> = iv1.split_whitespace().collect();
    assert_eq!((fields[1], fields[2]), ("elasticity", "4"), "{text}");
    assert!(line("IV.36").contains("reynolds"), "{text}");
    assert!(text.contains("quick tier"), "{text}");
    assert!(!out.exists(), "--list writes nothing");

    let broken = dir.join("broken");
    std::fs::create_dir_all(&broken).unwrap();
    std::fs::write(broken.join("bad.toml"), "table = \"bad\"\n[scene\n").unwrap();
    let listed = report()
        .args(["--list", "--experiments"])
        .arg(&broken)
        .output()
        .unwrap();
    assert_eq!(listed.status.code(), Some(1));
    let text = String::from_utf8_lossy(&listed.stdout);
    assert!(
        text.contains("bad") && text.contains("does not load"),
        "{text}"
    );
}

/// A relative experiment folder that does not exist is named with the folder it is relative
/// to, and the flag that chooses it.
#[test]
fn a_missing_experiment_folder_is_named() {
    let dir = temp_dir("no-experiments");
    let run = report().arg("--list").current_dir(&dir).output().unwrap();
    assert_eq!(run.status.code(), Some(2));
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(
        err.contains("experiments: cannot list the experiment directory")
            && err.contains(&format!("relative to {}", dir.display()))
            && err.contains("--experiments DIR"),
        "{err}"
    );
}
