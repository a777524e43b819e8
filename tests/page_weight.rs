//! The weight of the report page: what a reader's browser fetches when the page opens (the
//! page and the figures outside the folded table sections) and what all the figures of a run
//! take. The quick tier is checked in every `cargo test`; the full tier (ignored,
//! `full_tier`) over the folder in `TRIBO_FULL_REPORT`, or a full report made for the test.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::outputs::whole_quick_report;

/// The page with the figures it shows when it opens.
const FRONT_BUDGET: u64 = 3_000_000;
/// Every figure of a run.
const FIGURES_BUDGET: u64 = 25_000_000;

/// Bytes of a report folder: the page with the figures outside its folds, every figure, and the
/// largest figure with its name.
struct Weight {
    front: u64,
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

/// The page without the folded table sections (`<details class="entry">…</details>`, closed
/// when the page opens, their lazy figures not fetched).
fn outside_folds(html: &str) -> String {
    let mut out = String::new();
    let mut rest = html;
    while let Some(start) = rest.find("<details class=\"entry\">") {
        out.push_str(&rest[..start]);
        let after = &rest[start..];
        // A fold holds other (open) <details>; its own end is the first </details> at depth 0.
        let mut depth = 0usize;
        let mut at = 0;
        loop {
            let open = after[at..].find("<details").map(|i| at + i);
            let close = after[at..].find("</details>").map(|i| at + i);
            match (open, close) {
                (Some(o), Some(c)) if o < c => {
                    depth += 1;
                    at = o + 1;
                }
                (_, Some(c)) => {
                    depth -= 1;
                    at = c + "</details>".len();
                    if depth == 0 {
                        break;
                    }
                }
                _ => {
                    at = after.len();
                    break;
                }
            }
        }
        rest = &after[at..];
    }
    out.push_str(rest);
    out
}

fn weigh(dir: &Path) -> Weight {
    let html = fs::read_to_string(dir.join("index.html")).expect("index.html");
    let size = |p: &Path| fs::metadata(p).map_or(0, |m| m.len());
    let front = size(&dir.join("index.html"))
        + images(&outside_folds(&html))
            .iter()
            .map(|src| size(&dir.join(src)))
            .sum::<u64>();
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
fn folds_hide_their_figures_and_nested_details() {
    let html = "<img src=\"a.svg\"><details class=\"entry\"><summary>x</summary>\
                <details class=\"params\" open>p</details><img src=\"b.svg\"></details>\
                <img src=\"c.svg\">";
    assert_eq!(images(html), ["a.svg", "b.svg", "c.svg"]);
    assert_eq!(images(&outside_folds(html)), ["a.svg", "c.svg"]);
}

#[test]
fn the_quick_page_opens_light_and_its_figures_fit_the_budget() {
    let out = whole_quick_report();
    let html = fs::read_to_string(out.join("index.html")).unwrap();
    let folds = html.matches("<details class=\"entry\">").count();
    assert!(folds > 70, "only {folds} folded table sections");
    assert_within_budget(out);
}

/// The full tier: run `cargo test --release -- --ignored full_tier` (with `TRIBO_FULL_REPORT`
/// naming a full report's folder, or none to make one, about 2.3 GB, removed afterwards).
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
    let result = std::panic::catch_unwind(|| assert_within_budget(&out));
    if made {
        let _ = fs::remove_dir_all(&out);
    }
    if let Err(e) = result {
        std::panic::resume_unwind(e);
    }
}
