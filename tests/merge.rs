//! `report merge`: tables run as separate processes (through GNU parallel, as the README shows)
//! and merged give the page of one run of them all, timings aside; shards that cannot be merged
//! are refused with exit status 2 and a message naming the folder or file.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::cli::{report, temp_dir};
use crate::common::{experiments_dir as experiments, without_seconds};

/// The flags of every shard run here: the quick tier, records for `merge`, no alternative
/// readings.
const SHARD_FLAGS: [&str; 4] = ["--quick", "--no-progress", "--shard", "--no-alternatives"];

/// A quick run of `tables` without alternative readings into `out`.
fn quick(tables: &str, out: &Path) -> Output {
    report()
        .args(SHARD_FLAGS)
        .args(["--only", tables])
        .arg("--experiments")
        .arg(experiments())
        .arg("--out")
        .arg(out)
        .output()
        .unwrap()
}

fn merge(shards: &[&Path], out: &Path) -> Output {
    report()
        .arg("merge")
        .args(shards)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap()
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// The page with what differs between runs of the same tables replaced by `#`: the header's
/// total wall time, date and command line, and every number of a seconds column (the
/// `seconds` cell of each summary row, the six seconds-per-phase cells of each row of a
/// table's section). Everything else — every computed and printed value, the notes, the
/// figure captions and links — must be equal.
fn masked(html: &str) -> String {
    let mut out = String::with_capacity(html.len());
    for line in html.lines() {
        let mut line = line.to_string();
        for dt in ["total wall time", "date", "command"] {
            line = mask_after(&line, &format!("<dt>{dt}</dt><dd>"), "</dd>");
        }
        // Whether IV.36 ran alone, which a page merged from shards does not record.
        line = mask_after(&line, "<p><b>A measured reference.</b>", "</p>");
        out += &mask_seconds_cells(&line);
        out.push('\n');
    }
    out
}

/// `line` with the text between `open` and the next `close` replaced by `#`.
fn mask_after(line: &str, open: &str, close: &str) -> String {
    match line.find(open) {
        Some(i) => {
            let start = i + open.len();
            let end = line[start..].find(close).map_or(line.len(), |j| start + j);
            format!("{}#{}", &line[..start], &line[end..])
        }
        None => line.to_string(),
    }
}

/// A summary row ends in its seconds cell (`<td>1.234 s</td></tr>`), a row of a section's table
/// in six seconds cells, the first `<td class="first">` (setup, assemble, solve, estimate,
/// refine, total): those cells become `<td>#</td>`.
fn mask_seconds_cells(line: &str) -> String {
    if !(line.starts_with("<tr") && line.ends_with("</td></tr>")) {
        return line.to_string();
    }
    // A row of the performance table ends in its six seconds cells (marked † where the table
    // ran beside others) and the number of tables that ran alongside: how the run was
    // scheduled, which a page merged from shards does not know. All seven are masked.
    if let Some(at) = line.find("<td class=\"alongside\">") {
        let head = &line[..at];
        let cells: Vec<usize> = head.match_indices("<td").map(|(i, _)| i).collect();
        if let Some(k) = cells.len().checked_sub(6).map(|k| cells[k]) {
            return format!("{}{}</tr>", &head[..k], "<td>#</td>".repeat(7));
        }
    }
    let cells: Vec<usize> = line.match_indices("<td").map(|(i, _)| i).collect();
    if line.ends_with(" s</td></tr>") {
        let last = cells[cells.len() - 1];
        return format!("{}<td>#</td></tr>", &line[..last]);
    }
    match cells.len().checked_sub(6).map(|k| cells[k]) {
        Some(i) if line[i..].starts_with("<td class=\"first\">") => {
            format!("{}{}</tr>", &line[..i], "<td>#</td>".repeat(6))
        }
        _ => line.to_string(),
    }
}

/// The files of a folder, sorted by name.
fn files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !n.starts_with('.'))
        .collect();
    names.sort();
    names
}

/// Two tables run as separate processes by GNU parallel — the README's command, with the
/// experiment files as input and `{/.}` (the file name without folder and extension) as the
/// table id and shard folder — and merged, give the page of one process running both: the same
/// page after masking timings ([`masked`]), the same figures (byte for byte, but for the cost
/// plots and the performance figure, which draw seconds), and the same data files but for their seconds columns.
///
/// Needs GNU `parallel` (a Debian package), which a bare machine with only the Rust toolchain
/// does not have: `cargo test --release` leaves it out (and says why); `.ci/run` installs the
/// package and runs it by name.
#[test]
#[ignore = "needs GNU parallel (Debian package `parallel`); .ci/run installs it and runs this test by name"]
fn parallel_shards_merge_into_the_single_run_page() {
    let dir = temp_dir("parallel");
    let single = dir.join("single");
    let run = quick("IV.1,IV.36", &single);
    assert!(run.status.success(), "{}", stderr(&run));

    let shards = dir.join("shards");
    let out = Command::new("parallel")
        .args(["--will-cite", "-j", "2"])
        .arg(env!("CARGO_BIN_EXE_report"))
        .args(SHARD_FLAGS)
        .args(["--only", "{/.}"])
        .arg("--experiments")
        .arg(experiments())
        .arg("--out")
        .arg(format!("{}/{{/.}}", shards.display()))
        .arg(":::")
        .arg(experiments().join("IV.1.toml"))
        .arg(experiments().join("IV.36.toml"))
        .output()
        .expect("GNU parallel (Debian package `parallel`) must be installed for this test");
    assert!(out.status.success(), "parallel: {}", stderr(&out));
    assert_eq!(files(&shards), ["IV.1", "IV.36"]);
    assert_eq!(files(&shards.join("IV.1/shard")), ["IV.1.json"]);

    // The shards in the opposite order: the page is in table order all the same.
    let merged = dir.join("merged");
    let out = merge(&[&shards.join("IV.36"), &shards.join("IV.1")], &merged);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("2 tables from 2 shards"),
        "{}",
        stderr(&out)
    );

    let page = |d: &Path| tribo::report::read_pages(d).unwrap();
    let (single_page, merged_page) = (page(&single), page(&merged));
    let at = |id: &str| merged_page.find(&format!("id=\"t-{id}\"")).unwrap();
    assert!(at("IV.1") < at("IV.36"));
    // The mask hides what it should and no more: some seconds were masked, and the two pages
    // differ before masking (their commands at least).
    assert_ne!(single_page, merged_page);
    // Each table has a seconds cell in the front page's summary and in its family page's; IV.1
    // has four rows and IV.36 three in the quick tier, six seconds cells each, and the
    // performance section one row of six and the count of tables alongside per table.
    assert_eq!(
        masked(&single_page).matches("<td>#</td>").count(),
        2 * 2 + 6 * (4 + 3) + 7 * 2,
        "the summary's, the sections' and the performance section's seconds cells"
    );
    assert!(masked(&single_page).contains("<dt>command</dt><dd>#</dd>"));
    let (a, b) = (masked(&single_page), masked(&merged_page));
    if a != b {
        let first = a
            .lines()
            .zip(b.lines())
            .find(|(x, y)| x != y)
            .map(|(x, y)| format!("single: {x}\nmerged: {y}"));
        panic!(
            "the merged page differs from the single run's: {}",
            first.unwrap_or_else(|| "in length".into())
        );
    }
    assert!(merged_page.contains(&format!("report merge {}", shards.join("IV.36").display())));

    let figures = files(&single.join("figures"));
    assert_eq!(figures, files(&merged.join("figures")));
    assert!(figures.len() >= 6, "{figures:?}");
    for f in &figures {
        if f.ends_with("-cost.svg") || f == "performance-solve.svg" {
            continue;
        }
        let read = |d: &Path| fs::read(d.join("figures").join(f)).unwrap();
        assert!(read(&single) == read(&merged), "figure {f} differs");
    }

    let data = files(&single.join("data"));
    assert_eq!(data, files(&merged.join("data")));
    // The Parquet files hold the same frames as the CSV files (tests/open_data.rs), seconds
    // included, so the text files are compared; the meshes (binary) byte for byte.
    for f in data.iter().filter(|f| f.ends_with(".vtu")) {
        let read = |d: &Path| fs::read(d.join("data").join(f)).unwrap();
        assert!(read(&single) == read(&merged), "mesh {f} differs");
    }
    for f in data
        .iter()
        .filter(|f| !f.ends_with(".parquet") && !f.ends_with(".vtu"))
    {
        let read = |d: &Path| fs::read_to_string(d.join("data").join(f)).unwrap();
        assert_eq!(
            without_seconds(&read(&single)),
            without_seconds(&read(&merged)),
            "data file {f}"
        );
    }
    // The merged folder has the records of both tables, so it can be merged again.
    assert_eq!(files(&merged.join("shard")), ["IV.1.json", "IV.36.json"]);
}

/// One quick shard of IV.1 in `dir/name`.
fn shard_of_iv1(dir: &Path, name: &str) -> PathBuf {
    let shard = dir.join(name);
    let out = quick("IV.1", &shard);
    assert!(out.status.success(), "{}", stderr(&out));
    shard
}

fn copy_dir(from: &Path, to: &Path) {
    fs::create_dir_all(to).unwrap();
    for e in fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        if e.file_type().unwrap().is_dir() {
            copy_dir(&e.path(), &to.join(e.file_name()));
        } else {
            fs::copy(e.path(), to.join(e.file_name())).unwrap();
        }
    }
}

/// Shards that cannot be merged: exit status 2, a message naming the folder or the file, and
/// no page written.
#[test]
fn unmergeable_shards_are_refused_with_their_names() {
    let dir = temp_dir("errors");
    let good = shard_of_iv1(&dir, "good");
    let refused = |shards: &[&Path], expected: &[&str]| {
        let out_dir = dir.join("out");
        let _ = fs::remove_dir_all(&out_dir);
        let out = merge(shards, &out_dir);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(!err.contains("panicked"), "{err}");
        for e in expected {
            assert!(err.contains(e), "expected {e:?} in: {err}");
        }
        assert!(!out_dir.join("index.html").exists());
    };

    // A folder without records (an empty one; one that does not exist).
    let empty = dir.join("empty");
    fs::create_dir_all(empty.join("shard")).unwrap();
    let empty_name = empty.display().to_string();
    refused(&[&good, &empty], &[&empty_name, "no shard records"]);
    let missing = dir.join("missing");
    let missing_name = missing.display().to_string();
    refused(&[&missing], &[&missing_name, "no shard records"]);

    // The same table in two shards: both files named.
    let twin = dir.join("twin");
    copy_dir(&good, &twin);
    let (a, b) = (
        good.join("shard/IV.1.json").display().to_string(),
        twin.join("shard/IV.1.json").display().to_string(),
    );
    refused(&[&good, &twin], &["table IV.1 is in two shards", &a, &b]);

    // A record that is not JSON, one cut short, one of another format.
    let broken = dir.join("broken");
    copy_dir(&good, &broken);
    let record = broken.join("shard/IV.1.json");
    let name = record.display().to_string();
    let text = fs::read_to_string(&record).unwrap();
    for bad in [
        "not a record".to_string(),
        text[..text.len() / 2].to_string(),
        text.replacen("\"format\":1", "\"format\":99", 1),
    ] {
        assert_ne!(bad, text);
        fs::write(&record, &bad).unwrap();
        refused(&[&broken], &["cannot read the record", &name]);
    }
    fs::write(&record, text.replacen("\"format\":1", "\"format\":99", 1)).unwrap();
    refused(&[&broken], &["format 99"]);

    // A printed value that is neither a number nor inf/nan.
    let printed = text.replacen("\"inf\"", "\"infinite\"", 1);
    assert_ne!(printed, text, "IV.1's printed first ratio is inf");
    fs::write(&record, printed).unwrap();
    refused(&[&broken], &[&name, "\"infinite\""]);

    // Merge needs at least one shard.
    let out = report().arg("merge").output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    // The run's flags and merge do not mix.
    let out = report()
        .args(["--quick", "merge"])
        .arg(&good)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
}

/// A shard whose table failed (here a panic through the testing hook) merges into a page with
/// that failure, and the merge exits with status 1 as the run did.
#[test]
fn a_failed_entry_merges_with_exit_status_1() {
    let dir = temp_dir("failed");
    let good = shard_of_iv1(&dir, "good");
    let failed = dir.join("failed");
    let out = report()
        .env("TRIBO_TEST_PANIC", "IV.3")
        .args([
            "--quick",
            "--no-progress",
            "--shard",
            "--no-alternatives",
            "--only",
            "IV.3",
        ])
        .arg("--experiments")
        .arg(experiments())
        .arg("--out")
        .arg(&failed)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert_eq!(files(&failed.join("shard")), ["IV.3.json"]);

    let merged = dir.join("merged");
    let out = merge(&[&failed, &good], &merged);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(stderr(&out).contains("1 failed"), "{}", stderr(&out));
    let html = tribo::report::read_pages(&merged).unwrap();
    assert!(html.contains("a panic on purpose (testing hook)"));
    assert!(
        html.contains("<dd>2 (1 failed)</dd>"),
        "header counts both tables"
    );
}

/// A later run into the same folder replaces the records: they are those of its page only.
#[test]
fn a_run_keeps_only_its_own_records() {
    let dir = temp_dir("rerun");
    let out_dir = dir.join("out");
    let out = quick("IV.1", &out_dir);
    assert!(out.status.success(), "{}", stderr(&out));
    let out = quick("IV.3", &out_dir);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(files(&out_dir.join("shard")), ["IV.3.json"]);
}

/// The figures that set fig-IV.116 beside IV.46 and IV.60 (its related tables) come out as in
/// one run when the three ran as separate processes: byte for byte, but for the plots of
/// seconds; a shard of fig-IV.116 alone names the related tables as missing, the merged page
/// does not.
#[test]
fn related_tables_of_other_shards_are_drawn_as_in_one_run() {
    let dir = temp_dir("related");
    let tables = ["IV.46", "IV.60", "fig-IV.116"];
    let single = dir.join("single");
    let run = quick(&tables.join(","), &single);
    assert!(run.status.success(), "{}", stderr(&run));
    let shards: Vec<PathBuf> = tables.iter().map(|t| dir.join(t)).collect();
    for (t, shard) in tables.iter().zip(&shards) {
        let run = quick(t, shard);
        assert!(run.status.success(), "{t}: {}", stderr(&run));
    }
    let alone = tribo::report::read_pages(&shards[2]).unwrap();
    assert!(alone.contains("not in this report"));

    let merged = dir.join("merged");
    let refs: Vec<&Path> = shards.iter().map(PathBuf::as_path).collect();
    let out = merge(&refs, &merged);
    assert!(out.status.success(), "{}", stderr(&out));
    let page = tribo::report::read_pages(&merged).unwrap();
    assert!(!page.contains("not in this report"));
    for kind in ["substokes-cells", "related-cuts", "mesh", "convergence"] {
        let f = format!("figures/fig-IV.116-{kind}.svg");
        let (a, b) = (fs::read(single.join(&f)), fs::read(merged.join(&f)));
        assert!(a.is_ok() && a.ok() == b.ok(), "{f} differs");
    }
    assert!(merged.join("figures/fig-IV.116-related-cost.svg").exists());
}

/// Records are written only with `--shard` (a full report's would take gigabytes); merging the
/// folder of a run without it is refused with the flag named.
#[test]
fn records_are_written_only_with_shard() {
    let dir = temp_dir("no-shard");
    let out = dir.join("plain");
    let run = report()
        .args([
            "--quick",
            "--no-progress",
            "--no-alternatives",
            "--only",
            "IV.1",
        ])
        .arg("--experiments")
        .arg(experiments())
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", stderr(&run));
    assert!(
        !out.join("shard").exists(),
        "no shard/ folder without --shard"
    );
    let merged = merge(&[&out], &dir.join("merged"));
    assert_eq!(merged.status.code(), Some(2));
    assert!(stderr(&merged).contains("--shard"), "{}", stderr(&merged));
    let _ = fs::remove_dir_all(&dir);
}
