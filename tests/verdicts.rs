//! The verdicts of a written report checked against its own data files: for every table the
//! summary calls reproduced (`data-verdict="reproduced"`), every primary column of its family
//! (`tribo::report::verdict::primary_of`) lies within its band in every row of
//! `data/<table>.joined.csv` that has a printed value. The check reads the page and the data,
//! not the verdict function, so a verdict that claims more than the numbers show fails it.
//!
//! The quick tier is checked with the other tests; the full tier, ignored by default, runs the
//! report at thesis sizes (about two minutes and 2.3 GB, removed afterwards) or reads the folder
//! `TRIBO_FULL_REPORT` names:
//!
//! ```sh
//! cargo test --release --test tribo -- --ignored full_tier_verdicts --nocapture
//! ```

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};

use crate::common::read_csv;
use std::process::Command;

use tribo::report::verdict::{deviation, primary_of};

/// Each summary row's table id, verdict and severity, in page order.
fn verdicts(page: &str) -> Vec<(String, String, String)> {
    let summary = page
        .split("<section id=\"summary\">")
        .nth(1)
        .and_then(|s| s.split("</section>").next())
        .expect("summary");
    let attribute = |tag: &str, name: &str| -> String {
        let key = format!("{name}=\"");
        tag.split(&key)
            .nth(1)
            .and_then(|s| s.split('"').next())
            .unwrap_or_default()
            .to_string()
    };
    summary
        .split("<tr data-table=")
        .skip(1)
        .map(|row| {
            let tag = format!("data-table={}", row.split('>').next().unwrap_or_default());
            (
                attribute(&tag, "data-table"),
                attribute(&tag, "data-verdict"),
                attribute(&tag, "data-severity"),
            )
        })
        .collect()
}

/// Check every reproduced table of the report in `out`; the failures, and the tables per
/// verdict.
fn check(out: &Path) -> (Vec<String>, BTreeMap<String, Vec<String>>) {
    let page = tribo::report::read_pages(out).expect("index.html");
    let mut failures = Vec::new();
    let mut by_verdict: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for (table, verdict, _) in verdicts(&page) {
        by_verdict
            .entry(verdict.clone())
            .or_default()
            .push(table.clone());
        if verdict != "reproduced" {
            continue;
        }
        let joined = read_csv(&out.join("data").join(format!("{table}.joined.csv")));
        let mut compared = 0;
        for band in primary_of(&table) {
            let Some(printed) = joined.get(&format!("thesis_{}", band.column)) else {
                continue;
            };
            // The fluid tables print the estimate of the solve before (report/README.md).
            let tribo_column = match joined.get("estimate_previous_mesh") {
                Some(previous) if band.column == "estimate" => previous,
                _ => &joined[band.column],
            };
            for (row, (t, p)) in tribo_column.iter().zip(printed).enumerate() {
                let (Some(t), Some(p)) = (t, p) else { continue };
                compared += 1;
                let d = deviation(*t, *p, band.zero_below).unwrap_or(f64::INFINITY);
                if d.abs() > band.band {
                    failures.push(format!(
                        "{table}: reproduced, but {} of row {row} is {t} against the printed \
                         {p} (Δ {:+.2} %, band {} %)",
                        band.column,
                        d * 100.0,
                        band.band * 100.0
                    ));
                }
            }
        }
        if compared == 0 {
            failures.push(format!(
                "{table}: reproduced with no primary value compared"
            ));
        }
    }
    (failures, by_verdict)
}

fn assert_verdicts_hold(out: &Path) -> BTreeMap<String, Vec<String>> {
    let (failures, by_verdict) = check(out);
    assert!(
        failures.is_empty(),
        "{} verdict(s) claim more than the data show:\n{}",
        failures.len(),
        failures.join("\n")
    );
    assert!(
        by_verdict.get("reproduced").is_some_and(|t| t.len() > 5),
        "{by_verdict:?}"
    );
    by_verdict
}

#[test]
fn reproduced_verdicts_of_the_quick_tier_hold_in_its_data() {
    let by_verdict = assert_verdicts_hold(crate::outputs::whole_quick_report());
    // The model-adaptive tables on their fixed mesh are not reproduced by their dofs alone.
    let differs = &by_verdict["differs"];
    for t in [
        "IV.21", "IV.23", "IV.25", "IV.27", "IV.29", "IV.31", "IV.33", "IV.35",
    ] {
        assert!(differs.iter().any(|d| d == t), "{t}: {by_verdict:?}");
    }
}

/// A report folder that does not claim what its data show fails the check.
#[test]
fn the_check_catches_a_verdict_its_data_do_not_show() {
    let out = crate::common::scratch("verdicts");
    fs::create_dir_all(out.join("data")).unwrap();
    fs::write(
        out.join("index.html"),
        "<section id=\"summary\"><table><tr data-table=\"IV.21\" data-verdict=\"reproduced\" \
         data-severity=\"0\"><td>IV.21</td></tr></table></section>",
    )
    .unwrap();
    fs::write(
        out.join("data/IV.21.joined.csv"),
        "cycle,coarse_faces,accurate_faces,dofs,model_error,thesis_coarse_faces,\
         thesis_accurate_faces,thesis_dofs,thesis_model_error\n\
         0,512,0,3980,0.07,512,0,3980,0.0283\n1,455,57,3980,0.0,492,20,3980,1e-11\n",
    )
    .unwrap();
    let (failures, _) = check(&out);
    assert_eq!(failures.len(), 3, "{failures:#?}");
    assert!(
        failures[0].contains("coarse_faces of row 1"),
        "{}",
        failures[0]
    );
    assert!(
        failures[2].contains("model_error of row 0"),
        "{}",
        failures[2]
    );
    let _ = fs::remove_dir_all(&out);
}

/// The full tier: every reproduced verdict holds in the data. Prints the tables per verdict.
#[test]
#[ignore]
fn full_tier_verdicts_hold_in_the_data() {
    let (out, made) = match std::env::var_os("TRIBO_FULL_REPORT") {
        Some(dir) => (PathBuf::from(dir), false),
        None => {
            let out = std::env::temp_dir().join(format!("tribo-full-{}", std::process::id()));
            let _ = fs::remove_dir_all(&out);
            let status = Command::new(env!("CARGO_BIN_EXE_report"))
                .args(["--no-progress", "--no-alternatives", "--out"])
                .arg(&out)
                .status()
                .expect("report runs");
            assert!(status.success(), "the full-tier report failed");
            (out, true)
        }
    };
    let by_verdict = check(&out);
    if made {
        let _ = fs::remove_dir_all(&out);
    }
    let (failures, by_verdict) = by_verdict;
    for (verdict, tables) in &by_verdict {
        println!("{verdict} ({}): {}", tables.len(), tables.join(", "));
    }
    assert!(
        failures.is_empty(),
        "{} verdict(s) claim more than the data show:\n{}",
        failures.len(),
        failures.join("\n")
    );
}
