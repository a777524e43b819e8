//! The `report` binary when tables fail: every table is still on the page with its status, a
//! failed table leaves no stale output, odd experiment files (FIFOs, devices, huge files) are
//! named instead of blocking or filling memory, an unwritable `--out` stops before any solve,
//! data text reaches the page escaped, and a page of many printed rows renders in linear time.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use crate::cli::{report, temp_dir};
use crate::common::experiments_dir;

/// A shipped experiment file, as text.
fn shipped(table: &str) -> String {
    fs::read_to_string(experiments_dir().join(format!("{table}.toml"))).unwrap()
}

/// IV.1's scene renamed to `table` with no Dirichlet side: the loader accepts it, but the
/// elasticity system is singular (rigid motions), so the solver fails in cycle 0.
fn singular_elasticity(table: &str) -> String {
    let text = shipped("IV.1").replace("table = \"IV.1\"", &format!("table = \"{table}\""));
    let singular = text.replace("dirichlet = [\"left\", \"right\"]", "dirichlet = []");
    assert_ne!(
        text, singular,
        "the fixture must remove the Dirichlet sides"
    );
    singular
}

/// Run the report on `experiments` into `out` (quick tier, no progress bar), with extra
/// arguments and environment, and give up after a minute (a blocked read must fail the test,
/// not hang it).
fn run_report(experiments: &Path, out: &Path, args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut cmd = report();
    cmd.args(["--quick", "--no-progress", "--experiments"])
        .arg(experiments)
        .arg("--out")
        .arg(out)
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    for (k, v) in env {
        cmd.env(k, v);
    }
    let mut child = cmd.spawn().unwrap();
    let deadline = Instant::now() + Duration::from_secs(60);
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("the report did not finish within 60 s (blocked on an experiment file?)");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// The rows of the summary table of a page, one string per `<tr>`.
/// The summary rows of the tables on the page (not the rows that account for the Chapter IV
/// tables left out).
fn summary_rows(html: &str) -> Vec<&str> {
    let start = html.find("id=\"summary\"").expect("a summary section");
    let body = &html[start..];
    let end = body.find("</table>").expect("the summary table ends");
    body[..end]
        .split("<tr")
        .skip(2)
        .filter(|r| !r.starts_with(" class=\"absent\"") && !r.starts_with(" class=\"family-head\""))
        .collect()
}

/// The summary row of `table` (it links to the section `#t-<table>`).
fn summary_row<'a>(html: &'a str, table: &str) -> &'a str {
    let link = format!("#t-{table}\"");
    summary_rows(html)
        .into_iter()
        .find(|r| r.contains(&link))
        .unwrap_or_else(|| panic!("no summary row for {table} in:\n{html}"))
}

/// The status cell of a summary row.
fn status_of(row: &str) -> &str {
    let start = row.find("class=\"status").expect("a status cell");
    let rest = &row[start..];
    let text = &rest[rest.find('>').unwrap() + 1..];
    &text[..text.find('<').unwrap()]
}

/// The section of `table` on the page.
fn section_of<'a>(html: &'a str, table: &str) -> &'a str {
    let id = format!("<section id=\"t-{table}\"");
    let start = html
        .find(&id)
        .unwrap_or_else(|| panic!("no section for {table}"));
    let rest = &html[start..];
    &rest[..rest.find("</section>").unwrap()]
}

#[test]
fn mixed_folder_reports_every_table_with_its_status() {
    let dir = temp_dir("mixed");
    let exp = dir.join("experiments");
    fs::create_dir_all(&exp).unwrap();
    fs::write(exp.join("IV.1.toml"), shipped("IV.1")).unwrap();
    fs::write(exp.join("IV.2.toml"), singular_elasticity("IV.2")).unwrap();
    fs::write(exp.join("IV.3.toml"), shipped("IV.3")).unwrap();
    fs::write(exp.join("IV.4.toml"), shipped("IV.4")).unwrap();
    let out = dir.join("out");
    let result = run_report(&exp, &out, &[], &[("TRIBO_TEST_PANIC", "IV.3")]);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(1), "{stderr}");

    let html = tribo::report::read_pages(&out).expect("the page is written");
    let rows = summary_rows(&html);
    assert_eq!(rows.len(), 4, "one summary row per table:\n{rows:#?}");
    for (row, table) in rows.iter().zip(["IV.1", "IV.2", "IV.3", "IV.4"]) {
        assert!(row.contains(&format!("#t-{table}\"")), "table order");
    }
    assert_eq!(status_of(summary_row(&html, "IV.1")), "ok");
    assert_eq!(status_of(summary_row(&html, "IV.2")), "error");
    assert_eq!(status_of(summary_row(&html, "IV.3")), "panic");
    assert_eq!(status_of(summary_row(&html, "IV.4")), "ok");

    // The failed tables have their own sections with the cycle and the message.
    let solver = section_of(&html, "IV.2");
    assert!(solver.contains("cycle 0"), "{solver}");
    assert!(
        solver.contains("not symmetric positive definite"),
        "{solver}"
    );
    assert!(solver.contains("no data: the run failed"), "{solver}");
    let panic = section_of(&html, "IV.3");
    assert!(panic.contains("TRIBO_TEST_PANIC"), "{panic}");
    // The good tables are reported in full.
    for table in ["IV.1", "IV.4"] {
        assert!(out.join(format!("data/{table}.csv")).exists(), "{table}");
        assert!(section_of(&html, table).contains("figures/"), "{table}");
    }
    for table in ["IV.2", "IV.3"] {
        assert!(!out.join(format!("data/{table}.csv")).exists(), "{table}");
    }
    let _ = fs::remove_dir_all(&dir);
}

/// A broken file is a failed entry with the loader's message; the other tables still run.
#[test]
fn a_file_that_does_not_load_is_a_failed_entry() {
    let dir = temp_dir("not-loaded");
    let exp = dir.join("experiments");
    fs::create_dir_all(&exp).unwrap();
    fs::write(
        exp.join("IV.1.toml"),
        shipped("IV.1").replace("rows = 6", "rows = \"six\""),
    )
    .unwrap();
    fs::write(exp.join("IV.3.toml"), shipped("IV.3")).unwrap();
    let out = dir.join("out");
    let result = run_report(&exp, &out, &[], &[]);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("IV.1.toml") && stderr.contains("study.rows"),
        "{stderr}"
    );
    let html = tribo::report::read_pages(&out).unwrap();
    assert_eq!(status_of(summary_row(&html, "IV.1")), "not loaded");
    assert_eq!(status_of(summary_row(&html, "IV.3")), "ok");
    assert!(section_of(&html, "IV.1").contains("study.rows"));
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn a_failed_table_leaves_no_stale_output() {
    let dir = temp_dir("stale");
    let exp = dir.join("experiments");
    fs::create_dir_all(&exp).unwrap();
    let out = dir.join("out");
    fs::write(exp.join("IV.1.toml"), shipped("IV.1")).unwrap();
    let first = run_report(&exp, &out, &[], &[]);
    assert!(
        first.status.success(),
        "{}",
        String::from_utf8_lossy(&first.stderr)
    );
    let figure = out.join("figures/IV.1-convergence.svg");
    assert!(out.join("data/IV.1.csv").exists() && figure.exists());
    // Files of other tables whose names start alike must survive.
    let others = [
        out.join("data/IV.10.csv"),
        out.join("data/IV.10.probes.csv"),
        out.join("figures/IV.10-convergence.svg"),
    ];
    for f in &others {
        fs::write(f, "another table").unwrap();
    }
    // An alternative reading of an earlier run, too.
    fs::write(out.join("data/IV.1.reynolds.csv"), "old").unwrap();

    fs::write(exp.join("IV.1.toml"), singular_elasticity("IV.1")).unwrap();
    let second = run_report(&exp, &out, &[], &[]);
    assert_eq!(second.status.code(), Some(1));
    for stale in [
        "data/IV.1.csv",
        "data/IV.1.probes.csv",
        "data/IV.1.reynolds.csv",
        "figures/IV.1-convergence.svg",
        "figures/IV.1-cost.svg",
        "figures/IV.1-mesh.svg",
        "figures/IV.1-deformed.svg",
    ] {
        assert!(
            !out.join(stale).exists(),
            "{stale} is stale and must be removed"
        );
    }
    for f in &others {
        assert!(f.exists(), "{} belongs to another table", f.display());
    }
    let html = tribo::report::read_pages(&out).unwrap();
    let section = section_of(&html, "IV.1");
    assert!(section.contains("no data: the run failed"), "{section}");
    assert!(!section.contains("figures/"), "{section}");
    let _ = fs::remove_dir_all(&dir);
}

/// A path named `*.toml` that is not a regular file: reported as such, never opened.
fn assert_named_not_regular(dir: &Path, exp: &Path) {
    let out = dir.join("out");
    let only = run_report(exp, &out, &["--only", "IV.1"], &[]);
    let stderr = String::from_utf8_lossy(&only.stderr);
    assert_eq!(only.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("IV.1.toml") && stderr.contains("not a regular file"),
        "{stderr}"
    );
    assert!(!stderr.contains("available tables: \n"), "{stderr}");
    let html = tribo::report::read_pages(&out).unwrap();
    assert_eq!(status_of(summary_row(&html, "IV.1")), "not loaded");
    assert!(section_of(&html, "IV.1").contains("not a regular file"));

    // In a whole folder it is one failed entry among the others.
    let all = run_report(exp, &out, &[], &[]);
    assert_eq!(all.status.code(), Some(1));
    let html = tribo::report::read_pages(&out).unwrap();
    assert_eq!(status_of(summary_row(&html, "IV.1")), "not loaded");
    assert_eq!(status_of(summary_row(&html, "IV.3")), "ok");
}

#[test]
fn a_symlink_to_dev_zero_is_named_not_read() {
    let dir = temp_dir("dev-zero");
    let exp = dir.join("experiments");
    fs::create_dir_all(&exp).unwrap();
    fs::write(exp.join("IV.3.toml"), shipped("IV.3")).unwrap();
    std::os::unix::fs::symlink("/dev/zero", exp.join("IV.1.toml")).unwrap();
    assert_named_not_regular(&dir, &exp);
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn a_fifo_is_named_not_opened() {
    let dir = temp_dir("fifo");
    let exp = dir.join("experiments");
    fs::create_dir_all(&exp).unwrap();
    fs::write(exp.join("IV.3.toml"), shipped("IV.3")).unwrap();
    let fifo = exp.join("IV.1.toml");
    match Command::new("mkfifo").arg(&fifo).status() {
        Ok(s) if s.success() => {}
        other => {
            eprintln!("skipped: mkfifo is not available ({other:?})");
            return;
        }
    }
    assert_named_not_regular(&dir, &exp);
    let _ = fs::remove_dir_all(&dir);
}

/// A file beyond the size limit is not read (here a sparse file, so the test writes nothing),
/// and a directory named like an experiment file is not skipped: both are failed entries.
#[test]
fn a_huge_file_and_a_directory_are_failed_entries() {
    let dir = temp_dir("huge");
    let exp = dir.join("experiments");
    fs::create_dir_all(exp.join("IV.2.toml")).unwrap();
    fs::write(exp.join("IV.3.toml"), shipped("IV.3")).unwrap();
    let huge = fs::File::create(exp.join("IV.1.toml")).unwrap();
    huge.set_len(tribo::experiment::MAX_FILE_BYTES + 1).unwrap();
    let out = dir.join("out");
    let result = run_report(&exp, &out, &[], &[]);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(1), "{stderr}");
    let limit = tribo::experiment::MAX_FILE_BYTES.to_string();
    assert!(
        stderr.contains("IV.1.toml") && stderr.contains(&limit),
        "{stderr}"
    );
    assert!(
        stderr.contains("IV.2.toml") && stderr.contains("not a regular file (a directory)"),
        "{stderr}"
    );
    let html = tribo::report::read_pages(&out).unwrap();
    assert_eq!(status_of(summary_row(&html, "IV.1")), "not loaded");
    assert_eq!(status_of(summary_row(&html, "IV.2")), "not loaded");
    assert_eq!(status_of(summary_row(&html, "IV.3")), "ok");
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn an_unwritable_out_folder_stops_before_any_solve() {
    let dir = temp_dir("unwritable");
    let exp = dir.join("experiments");
    fs::create_dir_all(&exp).unwrap();
    // A failing solve would print its error: none may appear, since nothing is solved.
    fs::write(exp.join("IV.1.toml"), singular_elasticity("IV.1")).unwrap();
    let file = dir.join("a-file");
    fs::write(&file, "not a folder").unwrap();
    let out: PathBuf = file.join("sub");
    let result = run_report(&exp, &out, &[], &[]);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains(&out.display().to_string()), "{stderr}");
    assert!(
        !stderr.contains("cycle"),
        "a table was solved first: {stderr}"
    );
    let _ = fs::remove_dir_all(&dir);
}

/// User text that the loader lets through reaches the page escaped: here a file name with BEL
/// and ESC, shown as the id of a table that did not load.
#[test]
fn control_characters_in_a_file_name_are_escaped_on_the_page() {
    let dir = temp_dir("control");
    let exp = dir.join("experiments");
    fs::create_dir_all(&exp).unwrap();
    fs::write(exp.join("IV.3.toml"), shipped("IV.3")).unwrap();
    fs::write(exp.join("IV.9\u{7}\u{1b}.toml"), shipped("IV.3")).unwrap();
    let out = dir.join("out");
    let result = run_report(&exp, &out, &[], &[]);
    assert_eq!(result.status.code(), Some(1));
    let html = tribo::report::read_pages(&out).unwrap();
    assert!(
        !html.contains('\u{7}') && !html.contains('\u{1b}'),
        "raw control characters on the page"
    );
    assert!(html.contains("IV.9\\u{7}\\u{1b}"), "visible escapes");
    let _ = fs::remove_dir_all(&dir);
}

/// A run of `rows` cycles of tribo with the given title and notes.
fn run_result(title: &str, notes: &[&str], rows: usize) -> tribo::results::RunResult {
    use tribo::results::{Row, RunResult};
    let mut run = RunResult::new("IV.1", "IV.1.1", title, "quick", [0.0, 1.0, 0.0, 1.0]);
    run.rows = (0..rows)
        .map(|c| {
            Row::new(c)
                .count("active_cells", 10 * (c + 1))
                .count("dofs", 100 * (c + 1))
                .real("estimate", Some(1.0 / (c as f64 + 1.0)))
                .real("ratio", None)
        })
        .collect();
    run.notes = notes.iter().map(|n| n.to_string()).collect();
    run
}

fn meta() -> tribo::report::ReportMeta {
    tribo::report::ReportMeta {
        tier: "quick".into(),
        generated_by: "test".into(),
        total_seconds: 0.0,
        threads: 1,
        provenance: Default::default(),
        alongside: Default::default(),
    }
}

/// Titles, notes, column names and failure messages reach the page with control characters as
/// visible escapes, whatever the loader lets through.
#[test]
fn control_characters_in_titles_notes_columns_and_messages_are_escaped() {
    use tribo::report::{self, Entry, Failure, FailureKind, Section};
    use tribo::thesis::ThesisTable;

    let run = run_result("title\u{7}", &["note\u{0} with NUL"], 2);
    let thesis = ThesisTable {
        table: "IV.1".into(),
        section: "IV.1.1".into(),
        columns: ["cycle", "dofs", "col\u{1b}umn"].map(String::from).to_vec(),
        rows: vec![vec![0.0, 100.0, 1.0]],
        duplicate_of: None,
        additive_part: None,
        comparison: Default::default(),
        figures: Default::default(),
    };
    let failure = Failure {
        table: "IV.2".into(),
        title: Some("failed\u{8} title".into()),
        section: None,
        kind: FailureKind::Error,
        cycle: Some(3),
        message: "message\u{7f} end".into(),
    };
    let entries = [
        Entry::Done(Section {
            run: &run,
            thesis: &thesis,
            alternatives: &[],
        }),
        Entry::Failed(&failure),
    ];
    let dir = temp_dir("control-api");
    report::write_report(&dir, &entries, &meta()).unwrap();
    let html = tribo::report::read_pages(&dir).unwrap();
    let raw: Vec<char> = html
        .chars()
        .filter(|c| c.is_control() && !matches!(c, '\n' | '\t'))
        .collect();
    assert!(
        raw.is_empty(),
        "raw control characters on the page: {raw:?}"
    );
    for visible in [
        "title\\u{7}",
        "note\\u{0} with NUL",
        "col\\u{1b}umn",
        "failed\\u{8} title",
        "message\\u{7f} end",
    ] {
        assert!(html.contains(visible), "{visible} is not on the page");
    }
    let _ = fs::remove_dir_all(&dir);
}

/// Rendering is linear in the printed rows: a section with 200 000 thesis rows (a quadratic
/// lookup would take minutes) renders in seconds, and the page shows only the first rows.
#[test]
fn many_thesis_rows_render_in_linear_time_and_are_bounded() {
    use tribo::report::{self, Entry, Section};
    use tribo::thesis::ThesisTable;

    const PRINTED: usize = 200_000;
    let thesis = ThesisTable {
        table: "IV.1".into(),
        section: "IV.1.1".into(),
        columns: ["cycle", "active_cells", "dofs", "estimate", "ratio"]
            .map(String::from)
            .to_vec(),
        rows: (0..PRINTED)
            .map(|c| {
                let dofs = 100.0 * (c + 1) as f64;
                vec![c as f64, dofs / 3.0, dofs, 1.0 / dofs.sqrt(), 0.71]
            })
            .collect(),
        duplicate_of: None,
        additive_part: None,
        comparison: Default::default(),
        figures: Default::default(),
    };
    let run = run_result("many printed rows", &[], 4);
    let dir = temp_dir("many-rows");
    let meta = meta();
    let entries = [Entry::Done(Section {
        run: &run,
        thesis: &thesis,
        alternatives: &[],
    })];
    let started = Instant::now();
    let written = report::write_report(&dir, &entries, &meta).unwrap();
    let seconds = started.elapsed().as_secs_f64();
    assert!(seconds < 30.0, "rendering took {seconds:.1} s");
    assert!(
        written.figure_failures.is_empty(),
        "{:?}",
        written.figure_failures
    );

    let html = tribo::report::read_pages(&dir).unwrap();
    let section = section_of(&html, "IV.1");
    let rows = section.matches("<tr>").count();
    assert!(
        rows <= report::MAX_SHOWN_THESIS_ROWS + 10,
        "{rows} rows on the page"
    );
    assert!(
        section.contains(&format!(
            "{} are left out",
            PRINTED - report::MAX_SHOWN_THESIS_ROWS
        )),
        "the page says how many rows are left out"
    );
    let figure = fs::read_to_string(dir.join("figures/IV.1-convergence.svg")).unwrap();
    assert!(figure.len() < 2_000_000, "{} bytes of SVG", figure.len());
    let _ = fs::remove_dir_all(&dir);
}

/// A report run of `tables` (quick tier, one table at a time) into `out` whose run of `held`
/// waits at its start (the `TRIBO_TEST_HOLD` testing hook) until its stdin closes: the child,
/// once it has said on stderr that it holds, with the rest of its stderr.
fn held_run(
    out: &Path,
    tables: &str,
    held: &str,
) -> (
    std::process::Child,
    std::io::Lines<std::io::BufReader<std::process::ChildStderr>>,
) {
    use std::io::BufRead;
    let mut child = report()
        .args(["--quick", "--jobs", "1", "--only", tables, "--experiments"])
        .arg(experiments_dir())
        .arg("--out")
        .arg(out)
        .env("TRIBO_TEST_HOLD", held)
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut lines = std::io::BufReader::new(child.stderr.take().unwrap()).lines();
    let mut seen = String::new();
    loop {
        match lines.next() {
            Some(Ok(line)) if line.contains("TRIBO_TEST_HOLD=") => break,
            Some(Ok(line)) => seen.push_str(&line),
            _ => {
                let status = child.wait().unwrap();
                panic!("the run never held {held} ({status}): {seen}");
            }
        }
    }
    (child, lines)
}

/// What an interrupted run left in `out` must not look finished: the page says the report is
/// incomplete, with `pending` pending and `finished` finished, links no file that is not there,
/// and every data file is whole (no empty file, Parquet with both magic numbers, a `.vtu` with
/// its end); no file is left under a temporary name that looks like data.
fn assert_honest_folder(out: &Path, pending: &str, finished: &str) {
    let html = tribo::report::read_pages(out).unwrap();
    assert!(html.contains("This report is incomplete"), "{html}");
    let line = |id: &str| {
        html.lines()
            .find(|l| l.contains(&format!("id=\"{id}\"")))
            .unwrap_or_else(|| panic!("no {id} line: {html}"))
            .to_owned()
    };
    assert!(line("pending").contains(pending), "{html}");
    assert!(line("finished").contains(finished), "{html}");
    for link in html
        .split(['"', '\''])
        .filter(|s| s.starts_with("figures/") || s.starts_with("data/"))
    {
        assert!(
            out.join(link).is_file(),
            "the page links {link}, which is not there"
        );
    }
    for entry in fs::read_dir(out.join("data")).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let bytes = fs::read(&path).unwrap();
        assert!(!bytes.is_empty(), "{name} is empty");
        if name.ends_with(".parquet") {
            assert!(
                bytes.starts_with(b"PAR1") && bytes.ends_with(b"PAR1"),
                "{name}"
            );
        }
        if name.ends_with(".vtu") || name.ends_with(".pvd") {
            assert!(bytes.ends_with(b"</VTKFile>\n"), "{name} is cut off");
        }
        assert!(
            name.starts_with('.')
                || name.ends_with(".csv")
                || name.ends_with(".parquet")
                || name.ends_with(".vtu")
                || name.ends_with(".pvd"),
            "{name}"
        );
    }
}

/// SIGINT, SIGTERM and SIGKILL in the middle of a run (IV.1 finished, IV.2 held at its start)
/// leave a folder that says the report is incomplete, never the previous page linking figures
/// the run already removed; the next run takes the interrupted run's lock over with a note and
/// writes the full page.
#[test]
fn an_interrupted_run_leaves_a_page_that_says_it_is_incomplete() {
    let dir = temp_dir("interrupted");
    for signal in ["INT", "TERM", "KILL"] {
        let out = dir.join(signal);
        let whole = run_report(
            &experiments_dir(),
            &out,
            &["--only", "IV.1,IV.2", "--jobs", "1"],
            &[],
        );
        assert!(
            whole.status.success(),
            "{}",
            String::from_utf8_lossy(&whole.stderr)
        );
        let (mut child, _lines) = held_run(&out, "IV.1,IV.2", "IV.2");
        let pid = child.id();
        if signal == "KILL" {
            child.kill().unwrap();
        } else {
            let sent = Command::new("kill")
                .args(["-s", signal, &pid.to_string()])
                .status()
                .unwrap();
            assert!(sent.success());
        }
        let status = child.wait().unwrap();
        assert!(!status.success(), "{signal}: {status}");
        assert_honest_folder(&out, "IV.2", "IV.1");

        let again = run_report(&experiments_dir(), &out, &["--only", "IV.1,IV.2"], &[]);
        let stderr = String::from_utf8_lossy(&again.stderr);
        assert!(again.status.success(), "{signal}: {stderr}");
        assert!(
            stderr.contains(&format!(
                "taking over the lock of {} from process {pid}",
                out.display()
            )),
            "{signal}: {stderr}"
        );
        let html = tribo::report::read_pages(&out).unwrap();
        assert!(!html.contains("This report is incomplete"));
        assert_eq!(status_of(summary_row(&html, "IV.2")), "ok");
    }
    let _ = fs::remove_dir_all(&dir);
}

/// A second run into a folder that a run is writing is refused, naming the folder and the
/// other process, and touches nothing; the first run finishes as if alone.
#[test]
fn a_second_run_into_the_same_folder_is_refused() {
    let dir = temp_dir("two-runs");
    let out = dir.join("out");
    let (mut first, lines) = held_run(&out, "IV.1", "IV.1");
    let second = run_report(&experiments_dir(), &out, &["--only", "IV.2"], &[]);
    let stderr = String::from_utf8_lossy(&second.stderr);
    assert_eq!(second.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains(&out.display().to_string()), "{stderr}");
    assert!(
        stderr.contains(&format!("process {}", first.id())),
        "{stderr}"
    );
    assert!(!out.join("data/IV.2.csv").exists());
    // Closing its stdin lets the first run go on.
    drop(first.stdin.take());
    let rest: Vec<String> = lines.map_while(Result::ok).collect();
    assert!(first.wait().unwrap().success(), "{rest:?}");
    let html = tribo::report::read_pages(&out).unwrap();
    assert_eq!(status_of(summary_row(&html, "IV.1")), "ok");
    assert!(!html.contains("id=\"t-IV.2\""));
    let _ = fs::remove_dir_all(&dir);
}

/// An `index.html` that is a folder is refused before any table is solved (it was found only
/// when the page was written, after every table).
#[test]
fn an_index_html_folder_stops_before_any_solve() {
    let dir = temp_dir("index-folder");
    let out = dir.join("out");
    fs::create_dir_all(out.join("index.html")).unwrap();
    let result = run_report(&experiments_dir(), &out, &["--only", "IV.1"], &[]);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains(&out.join("index.html").display().to_string()),
        "{stderr}"
    );
    assert!(
        !out.join("data/IV.1.csv").exists(),
        "a table was solved first"
    );
    let _ = fs::remove_dir_all(&dir);
}

/// `--jobs` beyond the number of tables runs one worker per table (it started a thread per job,
/// and `--jobs 18446744073709551615` never ended).
#[test]
fn jobs_beyond_the_tables_start_one_worker_per_table() {
    let dir = temp_dir("many-jobs");
    let result = run_report(
        &experiments_dir(),
        &dir.join("out"),
        &["--only", "IV.1", "--jobs", "18446744073709551615"],
        &[],
    );
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    assert!(dir.join("out/data/IV.1.csv").is_file());
    let _ = fs::remove_dir_all(&dir);
}

/// The file's warnings are printed with a failed run too, before its error: a SubStokes film so
/// thin that g³/12 underflows fails in its solve, and the warning says why.
#[test]
fn warnings_come_before_the_error_of_a_failed_run() {
    let dir = temp_dir("warned-failure");
    let exp = dir.join("experiments");
    fs::create_dir_all(&exp).unwrap();
    let thin = shipped("IV.50").replace("g0 = 0.1", "g0 = 1e-300");
    assert_ne!(thin, shipped("IV.50"), "the fixture must thin the gap");
    fs::write(exp.join("IV.50.toml"), thin).unwrap();
    let out = dir.join("out");
    let result = run_report(&exp, &out, &[], &[]);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(1), "{stderr}");
    let warning = stderr
        .find("warning: table IV.50: scene.substokes.gap:")
        .unwrap_or_else(|| panic!("no warning: {stderr}"));
    let error = stderr
        .find("table IV.50, cycle")
        .unwrap_or_else(|| panic!("no error: {stderr}"));
    assert!(warning < error, "{stderr}");
    let _ = fs::remove_dir_all(&dir);
}

/// Table IV.18 with the most contact refinements a file may ask for (12): its fixed mesh is a
/// 64×2 strip graded to 2 M unknowns at the contact side. Once its Cholesky factor, ordered
/// badly, asked for 74 GB in one allocation and aborted the whole process (SIGABRT, no page,
/// every other table lost). The budget predicts the 5.9 GiB of its cells (the factor now has
/// 54.6 M nonzeros) and refuses it under a budget of 4 GiB before its first solve, naming
/// table, cycle and size, and IV.1 beside it is reported as usual.
#[test]
fn the_largest_contact_refinement_is_refused_and_the_other_tables_run() {
    let dir = temp_dir("contact-refinements-12");
    let exp = dir.join("experiments");
    fs::create_dir_all(&exp).unwrap();
    fs::write(exp.join("IV.1.toml"), shipped("IV.1")).unwrap();
    let text = shipped("IV.18");
    let refined = text.replace("contact_refinements = 3\n", "contact_refinements = 12\n");
    assert_ne!(text, refined, "the fixture must set 12 contact refinements");
    fs::write(exp.join("IV.18.toml"), refined).unwrap();
    let out = dir.join("out");
    let result = run_report(&exp, &out, &["--memory-budget", "4G"], &[]);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(1), "{stderr}");
    assert!(!stderr.contains("memory allocation"), "{stderr}");

    let html = tribo::report::read_pages(&out).expect("the page is written");
    assert_eq!(status_of(summary_row(&html, "IV.1")), "ok");
    assert_eq!(status_of(summary_row(&html, "IV.18")), "error");
    let refused = section_of(&html, "IV.18");
    for part in [
        "cycle 0",
        "predicted to need",
        "GiB",
        "memory budget of 4.0 GiB",
        "scene.contact_refinements",
    ] {
        assert!(refused.contains(part), "no `{part}` in:\n{refused}");
    }
    assert!(out.join("data/IV.1.csv").exists());
    assert!(!out.join("data/IV.18.csv").exists());
    let _ = fs::remove_dir_all(&dir);
}
