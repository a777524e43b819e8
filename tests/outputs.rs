//! No NaN or infinity in any output (report/README.md, "Undefined values"): the CSV files and
//! the page of the whole quick tier and of hard cases, and the golden snapshots.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Tokens that spell a non-finite number in our outputs (Rust's and polars' spellings).
fn non_finite(token: &str) -> bool {
    let t = token
        .trim()
        .trim_start_matches(['+', '-'])
        .to_ascii_lowercase();
    t == "nan" || t == "inf" || t == "infinity" || t == "∞"
}

/// Every non-finite cell of the CSV files in `dir` and every non-finite number of its VTK
/// files, as `file:line:cell` (the Parquet files are binary; `open_data` reads them back).
fn scan_csv(dir: &Path) -> Vec<String> {
    let mut found = Vec::new();
    for entry in fs::read_dir(dir).expect("data/") {
        let path = entry.expect("entry").path();
        let separator: fn(char) -> bool = match path.extension().and_then(|e| e.to_str()) {
            Some("csv") => |c| c == ',',
            Some("vtu") => char::is_whitespace,
            _ => continue,
        };
        let text = fs::read_to_string(&path).expect("csv");
        for (n, line) in text.lines().enumerate() {
            for cell in line.split(separator) {
                if non_finite(cell) {
                    found.push(format!("{}:{}: {cell}", path.display(), n + 1));
                }
            }
        }
    }
    found
}

/// Every non-finite table cell (`<td>…</td>`) of a page.
fn scan_html(page: &Path) -> Vec<String> {
    let text = fs::read_to_string(page).expect("index.html");
    text.split("<td")
        .skip(1)
        .filter_map(|cell| {
            let content = cell.split_once('>')?.1.split("</td>").next()?;
            non_finite(content)
                .then(|| format!("{}: <td{}", page.display(), &cell[..cell.len().min(80)]))
        })
        .collect()
}

fn out_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tribo-outputs-{}-{name}", std::process::id()));
    let _ = fs::remove_dir_all(&d);
    d
}

/// Run the report on `experiments` at the quick tier into a fresh folder and return it;
/// `only` limits it to those tables.
pub fn quick_report(experiments: &Path, name: &str, only: Option<&str>) -> PathBuf {
    let out = out_dir(name);
    let output = Command::new(env!("CARGO_BIN_EXE_report"))
        .args(["--quick", "--no-progress", "--no-alternatives"])
        .args(only.map(|only| ["--only", only]).into_iter().flatten())
        .arg("--experiments")
        .arg(experiments)
        .arg("--out")
        .arg(&out)
        .output()
        .expect("report runs");
    assert!(
        output.status.success(),
        "report --quick on {} failed: {}",
        experiments.display(),
        String::from_utf8_lossy(&output.stderr)
    );
    out
}

fn assert_finite(out: &Path) {
    let mut found = scan_csv(&out.join("data"));
    found.extend(scan_html(&out.join("index.html")));
    assert!(found.is_empty(), "non-finite values:\n{}", found.join("\n"));
}

#[test]
fn the_quick_tier_writes_no_non_finite_value() {
    let experiments = Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments");
    let out = quick_report(&experiments, "quick", None);
    assert_finite(&out);
    let _ = fs::remove_dir_all(&out);
}

#[test]
fn golden_snapshots_hold_no_non_finite_value() {
    let golden = Path::new(env!("CARGO_MANIFEST_DIR")).join("golden");
    for entry in fs::read_dir(&golden).expect("golden/") {
        let path = entry.expect("entry").path();
        let text = fs::read_to_string(&path).expect("snapshot");
        for (n, line) in text.lines().enumerate() {
            let bad: Vec<&str> = line.split_whitespace().filter(|t| non_finite(t)).collect();
            assert!(bad.is_empty(), "{}:{}: {bad:?}", path.display(), n + 1);
        }
    }
}

/// Hard cases whose ratios are 0/0 or x/0: an elasticity scene without load (every estimate
/// 0), a Reynolds scene whose exact solution the elements reproduce (ψ ≡ 200, estimate 0 up to
/// rounding), and a Signorini scene whose obstacle is far below (no contact: the contact and
/// gap parts are 0).
#[test]
fn hard_cases_write_no_non_finite_value() {
    let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments");
    let dir = out_dir("hard-cases-in");
    fs::create_dir_all(&dir).expect("scratch");
    let copy = |table: &str, edits: &[(&str, &str)]| {
        let mut text = fs::read_to_string(shipped.join(format!("{table}.toml"))).expect("shipped");
        for (from, to) in edits {
            assert!(text.contains(from), "{table}: `{from}`");
            text = text.replacen(from, to, 1);
        }
        fs::write(dir.join(format!("{table}.toml")), text).expect("write");
    };
    copy("IV.1", &[("amplitude = 0.0004", "amplitude = 0.0")]);
    copy("IV.38", &[]);
    copy("IV.12", &[("level = -2.0", "level = -100.0")]);
    let out = quick_report(&dir, "hard-cases", None);
    assert_finite(&out);
    let _ = fs::remove_dir_all(&out);
    let _ = fs::remove_dir_all(&dir);
}
