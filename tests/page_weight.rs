//! The weight of the report: what a reader's browser fetches when the front page opens (the
//! page and its figures), what each family's page fetches, and what all the figures of a run
//! take. The quick tier is checked in every `cargo test`; the full tier (ignored,
//! `full_tier`) over the folder in `TRIBO_FULL_REPORT`, or a full report made for the test.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::outputs::whole_quick_report;

/// The front page with its figures.
const FRONT_BUDGET: u64 = 3_000_000;
/// Every figure of a run.
const FIGURES_BUDGET: u64 = 25_000_000;

/// Bytes of a report folder: the front page with its figures, each other page with its
/// figures, every figure, and the largest figure with its name.
struct Weight {
    front: u64,
    pages: Vec<(String, u64)>,
    figures: u64,
    largest: (u64, String),
}

/// The `src` of every `<img>` of `html`.
fn images(html: &str) -> Vec<&str> {
    html.split("<img src=\"")
        .skip(1)
        .filter_map(|rest| rest.split('"').next())
        .collect()
}

fn weigh(dir: &Path) -> Weight {
    let size = |p: &Path| fs::metadata(p).map_or(0, |m| m.len());
    let with_figures = |page: &Path| {
        let html = fs::read_to_string(page).expect("a page");
        size(page)
            + images(&html)
                .iter()
                .map(|src| size(&dir.join(src)))
                .sum::<u64>()
    };
    let front = with_figures(&dir.join("index.html"));
    let mut pages = Vec::new();
    for entry in fs::read_dir(dir).expect("the report folder") {
        let path = entry.expect("entry").path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if name.ends_with(".html") && name != "index.html" {
            pages.push((name, with_figures(&path)));
        }
    }
    pages.sort();
    let mut figures = 0;
    let mut largest = (0, String::new());
    for entry in fs::read_dir(dir.join("figures")).expect("figures/") {
        let entry = entry.expect("entry");
        let n = size(&entry.path());
        figures += n;
        if n > largest.0 {
            largest = (n, entry.file_name().to_string_lossy().into_owned());
        }
    }
    Weight {
        front,
        pages,
        figures,
        largest,
    }
}

fn assert_within_budget(dir: &Path) {
    let w = weigh(dir);
    println!(
        "{}: front page with its figures {} B, all figures {} B, largest {} ({} B)",
        dir.display(),
        w.front,
        w.figures,
        w.largest.1,
        w.largest.0
    );
    for (page, bytes) in &w.pages {
        println!("  {page} with its figures: {bytes} B");
    }
    assert!(
        w.front <= FRONT_BUDGET,
        "the page opens with {} B (budget {FRONT_BUDGET} B)",
        w.front
    );
    assert!(
        w.figures <= FIGURES_BUDGET,
        "the figures take {} B (budget {FIGURES_BUDGET} B); the largest is {} ({} B)",
        w.figures,
        w.largest.1,
        w.largest.0
    );
}

#[test]
fn the_quick_page_opens_light_and_its_figures_fit_the_budget() {
    let out = whole_quick_report();
    // The front page shows one figure (performance); the table sections, folded, are on the
    // family pages.
    let front = fs::read_to_string(out.join("index.html")).unwrap();
    assert_eq!(images(&front), ["figures/performance-solve.svg"]);
    let pages = tribo::report::read_pages(out).unwrap();
    let folds = pages.matches("<details class=\"entry\">").count();
    assert!(folds > 70, "only {folds} folded table sections");
    assert_within_budget(out);
}

/// Bytes a default full run may write: the page, its figures and its data, the VTU meshes of
/// `--vtu last` included (2.4 GB before they were compressed and single precision).
const FULL_FOLDER_BUDGET: u64 = 300_000_000;

/// Every file under `dir` with its size, largest first.
fn files_by_size(dir: &Path) -> Vec<(u64, PathBuf)> {
    let mut out = Vec::new();
    for entry in fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
        let path = entry.unwrap().path();
        if path.is_dir() {
            out.extend(files_by_size(&path));
        } else {
            out.push((fs::metadata(&path).unwrap().len(), path));
        }
    }
    out.sort_by(|a, b| b.cmp(a));
    out
}

/// A default full run's folder is at most [`FULL_FOLDER_BUDGET`] bytes; a failure names the
/// largest files.
fn assert_folder_within_budget(out: &Path) {
    let files = files_by_size(out);
    let total: u64 = files.iter().map(|(n, _)| n).sum();
    let largest: Vec<String> = files
        .iter()
        .take(5)
        .map(|(n, p)| format!("{} ({:.1} MB)", p.display(), *n as f64 / 1e6))
        .collect();
    println!(
        "{}: {:.1} MB in {} files",
        out.display(),
        total as f64 / 1e6,
        files.len()
    );
    assert!(
        total <= FULL_FOLDER_BUDGET,
        "{} holds {:.1} MB, over the {} MB of a default full run; largest: {}",
        out.display(),
        total as f64 / 1e6,
        FULL_FOLDER_BUDGET / 1_000_000,
        largest.join(", ")
    );
}

/// The full tier: run `cargo test --release -- --ignored full_tier` (with `TRIBO_FULL_REPORT`
/// naming a full report's folder made with the default `--vtu`, or none to make one, removed
/// afterwards). Also checks the folder's size ([`FULL_FOLDER_BUDGET`]).
#[test]
#[ignore]
fn full_tier_page_opens_light_and_its_figures_fit_the_budget() {
    let (out, made) = match std::env::var_os("TRIBO_FULL_REPORT") {
        Some(dir) => (PathBuf::from(dir), false),
        None => {
            let out =
                std::env::temp_dir().join(format!("tribo-full-weight-{}", std::process::id()));
            let _ = fs::remove_dir_all(&out);
            let status = Command::new(env!("CARGO_BIN_EXE_report"))
                .args(["--no-progress", "--out"])
                .arg(&out)
                .status()
                .expect("report runs");
            assert!(status.success(), "the full-tier report failed");
            (out, true)
        }
    };
    let result = std::panic::catch_unwind(|| {
        assert_within_budget(&out);
        assert_folder_within_budget(&out);
    });
    if made {
        let _ = fs::remove_dir_all(&out);
    }
    if let Err(e) = result {
        std::panic::resume_unwind(e);
    }
}
