//! No NaN or infinity in any output (report/README.md, "Undefined values"): the CSV files and
//! the page of the whole quick tier and of hard cases, and the golden snapshots.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

/// Tokens that spell a non-finite number in our outputs (Rust's and polars' spellings).
fn non_finite(token: &str) -> bool {
    let t = token
        .trim()
        .trim_start_matches(['+', '-'])
        .to_ascii_lowercase();
    t == "nan" || t == "inf" || t == "infinity" || t == "∞"
}

/// Every non-finite cell of the CSV files in `dir` and every non-finite number of its VTK
/// files, as `file:line:cell` or `file:array[index]` (the Parquet files are binary; `open_data`
/// reads them back).
fn scan_csv(dir: &Path) -> Vec<String> {
    let mut found = Vec::new();
    for entry in fs::read_dir(dir).expect("data/") {
        let path = entry.expect("entry").path();
        match path.extension().and_then(|e| e.to_str()) {
            Some("csv") => {
                let text = fs::read_to_string(&path).expect("csv");
                for (n, line) in text.lines().enumerate() {
                    for cell in line.split(',') {
                        if non_finite(cell) {
                            found.push(format!("{}:{}: {cell}", path.display(), n + 1));
                        }
                    }
                }
            }
            Some("vtu") => {
                let file = tribo::report::vtk::read(&fs::read(&path).expect("vtu"))
                    .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
                for (name, values) in &file.arrays {
                    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
                        found.push(format!("{}:{name}[{i}]: {}", path.display(), values[i]));
                    }
                }
            }
            _ => continue,
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
    crate::common::scratch(&format!("outputs-{name}"))
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
    for page in fs::read_dir(out).unwrap().flatten().map(|e| e.path()) {
        if page.extension().is_some_and(|e| e == "html") {
            found.extend(scan_html(&page));
        }
    }
    assert!(found.is_empty(), "non-finite values:\n{}", found.join("\n"));
}

/// The quick report of every shipped experiment (without alternative readings), made once per
/// test run and shared by the tests that read a whole page; left in the temporary folder.
pub fn whole_quick_report() -> &'static Path {
    static WHOLE: OnceLock<PathBuf> = OnceLock::new();
    WHOLE.get_or_init(|| {
        let experiments = Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments");
        quick_report(&experiments, "quick", None)
    })
}

#[test]
fn the_quick_tier_writes_no_non_finite_value() {
    assert_finite(whole_quick_report());
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

/// Every section states the problem it solved from its experiment file: IV.52's section shows
/// its gap, wall velocity, boundary value and marking fraction as the file writes them, each key
/// with its meaning; no list is cut short.
#[test]
fn each_section_states_the_scene_and_the_study() {
    let page = tribo::report::read_pages(whole_quick_report()).unwrap();
    let section = page
        .split("<section id=\"t-IV.52\">")
        .nth(1)
        .and_then(|s| s.split("</section>").next())
        .expect("IV.52 section");
    for line in [
        "<td class=\"group\" colspan=\"3\">[scene.substokes]</td>",
        "<td class=\"key\">gap</td><td class=\"value\">{ kind = &quot;plain&quot;, g0 = 0.1 }</td>",
        "<td class=\"key\">upper_wall_velocity</td><td class=\"value\">[10.0, 0.0, 0.0]</td>",
        "<td class=\"key\">boundary_pressure</td><td class=\"value\">200.0</td>",
        "<td class=\"key\">refine_fraction</td><td class=\"value\">0.3</td>",
        "<td class=\"key\">ties</td><td class=\"value\">split</td><td class=\"meaning\">tied \
         indicators at a cut",
    ] {
        assert!(section.contains(line), "IV.52 lacks {line}");
    }
    assert!(!page.contains(" entries)"), "a list cut short");
    // A solver study counts its iterations and seconds, not cycles.
    let uzawa = page
        .split("<section id=\"t-fig-III.6\">")
        .nth(1)
        .expect("fig-III.6 section");
    assert!(
        uzawa.contains("5 variants, 300 iterations computed in "),
        "{}",
        &uzawa[..400]
    );
    let boxes = page.matches("<details class=\"params\" open>").count();
    assert_eq!(
        boxes,
        page.matches("<section id=\"t-").count(),
        "one box per section"
    );
}

/// The summary row of `table` on `page` (from its `<tr>` to its `</tr>`).
fn summary_row<'a>(page: &'a str, table: &str) -> &'a str {
    let summary = page
        .split("<section id=\"summary\">")
        .nth(1)
        .and_then(|s| s.split("</section>").next())
        .expect("summary");
    let link = format!("#t-{table}\">{table}</a>");
    let at = summary
        .find(&link)
        .unwrap_or_else(|| panic!("{table} not in the summary"));
    let start = summary[..at].rfind("<tr").unwrap();
    let end = at + summary[at..].find("</tr>").unwrap();
    &summary[start..end]
}

/// The summary gives every table a verdict: all 75 tables of Chapter IV are in a whole
/// report's summary, a duplicated table is shown as such and not highlighted, a reproduced
/// table says so with its rows within tolerance; a report of a few tables still accounts for
/// the others.
#[test]
fn the_summary_has_a_verdict_for_every_table() {
    let page = tribo::report::read_pages(whole_quick_report()).unwrap();
    for n in 1..=75 {
        summary_row(&page, &format!("IV.{n}"));
    }
    let duplicate = summary_row(&page, "IV.17");
    assert!(
        duplicate.contains("thesis duplicate of IV.13: not scored"),
        "{duplicate}"
    );
    assert!(!duplicate.contains("diff off"), "{duplicate}");
    assert!(!duplicate.contains("verdict off"), "{duplicate}");
    let reproduced = summary_row(&page, "IV.1");
    assert!(
        reproduced.contains(
            "<td class=\"text verdict ok\" title=\"reproduced\">reproduced</td><td>4 / 4</td>"
        ),
        "{reproduced}"
    );
    assert!(summary_row(&page, "fig-IV.54").contains("figure: no printed table"));

    let experiments = Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments");
    let out = quick_report(&experiments, "verdict-only", Some("IV.1,IV.7"));
    // The tables left out are listed under their families, in runs.
    let front = fs::read_to_string(out.join("index.html")).unwrap();
    assert!(front.contains("<td class=\"text\">IV.2 – IV.5</td>"));
    assert!(front.contains("<td class=\"text\">IV.6</td>"));
    assert!(front.contains("<code>report --only IV.6</code> runs it"));
    assert!(front.contains("<td class=\"text\">IV.8 – IV.17</td>"));
    assert!(front.contains("<td class=\"text\">IV.36 – IV.49</td>"));
    assert!(front.contains("<td class=\"text\">IV.64 – IV.69</td>"));
    assert!(
        front.contains("Reynolds, with and without cavitation <span class=\"meta\">(no table of it in this run)</span>")
    );
    let _ = fs::remove_dir_all(&out);
}

/// The ids (`id="…"`) of a page.
fn ids_of(html: &str) -> std::collections::BTreeSet<&str> {
    html.split(" id=\"")
        .skip(1)
        .filter_map(|rest| rest.split('"').next())
        .collect()
}

/// Every link of every page of the whole quick report reaches what it names: a link within
/// the page an element of it, a link to another page (`reynolds.html#t-IV.36`) that page and an
/// element of it, a link to a file (`figures/…`, `data/…`) a file of the folder.
#[test]
fn every_link_of_every_page_reaches_its_target() {
    let out = whole_quick_report();
    let mut pages = std::collections::BTreeMap::new();
    for entry in fs::read_dir(out).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if name.ends_with(".html") && !name.contains("check") && !name.contains("measure") {
            pages.insert(name, fs::read_to_string(&path).unwrap());
        }
    }
    assert!(pages.len() >= 8, "pages: {:?}", pages.keys());
    let mut links = 0;
    let mut dangling = Vec::new();
    for (name, html) in &pages {
        for href in html.split("href=\"").skip(1) {
            let href = href.split('"').next().unwrap();
            if href.starts_with("http") {
                continue;
            }
            links += 1;
            let (file, id) = href.split_once('#').unwrap_or((href, ""));
            let target = if file.is_empty() { name.as_str() } else { file };
            let reached = match pages.get(target) {
                Some(page) => id.is_empty() || ids_of(page).contains(id),
                None => id.is_empty() && out.join(target).is_file(),
            };
            if !reached {
                dangling.push(format!("{name}: {href}"));
            }
        }
    }
    assert!(links > 500, "only {links} links");
    assert!(
        dangling.is_empty(),
        "links that reach nothing:\n{}",
        dangling.join("\n")
    );
}
