//! The repository stands alone: no file points at notes that are not in it (the project's
//! former design and specification notes, or numbered tickets of a tracker), and every
//! `docs/…` file a source comment names exists, with the section it cites.

use std::fs;
use std::path::{Path, PathBuf};

/// The folders and files whose text a reader of the repository follows.
const SEARCHED: [&str; 9] = [
    "src",
    "tests",
    "benches",
    "examples",
    "scripts",
    "experiments",
    "docs",
    "README.md",
    "report/README.md",
];

/// The folders whose files are source code (their `docs/…` references are checked).
const SOURCE: [&str; 5] = ["src", "tests", "benches", "examples", "scripts"];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every text file under `entry` (a folder, walked recursively, or a single file).
fn text_files(entry: &Path, out: &mut Vec<(PathBuf, String)>) {
    if entry.is_dir() {
        let mut children: Vec<PathBuf> = fs::read_dir(entry)
            .unwrap_or_else(|e| panic!("{}: {e}", entry.display()))
            .map(|e| e.expect("folder entry").path())
            .collect();
        children.sort();
        for child in children {
            text_files(&child, out);
        }
    } else if let Ok(text) = fs::read_to_string(entry) {
        out.push((entry.to_path_buf(), text));
    }
}

fn files_of(entries: &[&str]) -> Vec<(PathBuf, String)> {
    let mut out = Vec::new();
    for entry in entries {
        text_files(&root().join(entry), &mut out);
    }
    assert!(!out.is_empty(), "no files found under {entries:?}");
    out
}

/// The names of the notes that are not in the repository, put together here so that this file
/// does not name them itself.
fn missing_notes() -> [String; 3] {
    [
        ["DESIGN", ".md"].concat(),
        ["spec/", "models.md"].concat(),
        ["spec/", "estimators.md"].concat(),
    ]
}

/// Whether `line` cites a numbered ticket: the word `issue` followed by a space and a digit.
fn cites_a_ticket(line: &str) -> bool {
    let lower = line.to_lowercase();
    lower.match_indices("issue ").any(|(i, word)| {
        let before = lower[..i].chars().next_back();
        let after = lower[i + word.len()..].chars().next();
        !before.is_some_and(|c| c.is_alphanumeric() || c == '_')
            && after.is_some_and(|c| c.is_ascii_digit())
    })
}

#[test]
fn no_reference_to_notes_outside_the_repository() {
    let notes = missing_notes();
    let mut found = Vec::new();
    for (path, text) in files_of(&SEARCHED) {
        for (n, line) in text.lines().enumerate() {
            let named = notes.iter().find(|note| line.contains(note.as_str()));
            if named.is_some() || cites_a_ticket(line) {
                found.push(format!("{}:{}: {}", path.display(), n + 1, line.trim()));
            }
        }
    }
    assert!(
        found.is_empty(),
        "references to notes or tickets that are not in the repository:\n{}",
        found.join("\n")
    );
}

/// The `docs/…` paths of `line`, each with the section number it cites after ` §`, if any.
fn docs_references(line: &str) -> Vec<(String, Option<String>)> {
    let path_char = |c: char| c.is_ascii_alphanumeric() || "_-./".contains(c);
    let mut refs = Vec::new();
    for (i, _) in line.match_indices("docs/") {
        if line[..i].chars().next_back().is_some_and(path_char) {
            continue; // part of a longer path or address
        }
        let rest = &line[i..];
        let end = rest.find(|c: char| !path_char(c)).unwrap_or(rest.len());
        let path = rest[..end].trim_end_matches('.').to_string();
        let section = rest[end..].strip_prefix(" §").map(|s| {
            let number: String = s
                .chars()
                .take_while(|c| c.is_ascii_digit() || *c == '.')
                .collect();
            number.trim_end_matches('.').to_string()
        });
        refs.push((path, section.filter(|s| !s.is_empty())));
    }
    refs
}

/// Whether the Markdown `text` has a heading numbered `section` (`## 5. …`, `### 5.6 …`).
fn has_section(text: &str, section: &str) -> bool {
    text.lines().any(|line| {
        let heading = line.trim_start_matches('#');
        heading.len() < line.len()
            && heading
                .split_whitespace()
                .next()
                .map(|n| n.trim_end_matches('.'))
                == Some(section)
    })
}

#[test]
fn docs_cited_in_source_comments_exist() {
    let mut missing = Vec::new();
    let mut cited = 0;
    for (path, text) in files_of(&SOURCE) {
        for (n, line) in text.lines().enumerate() {
            for (doc, section) in docs_references(line) {
                cited += 1;
                let at = format!("{}:{}", path.display(), n + 1);
                let file = root().join(&doc);
                if !file.exists() {
                    missing.push(format!("{at}: {doc} does not exist"));
                } else if let Some(s) = section {
                    let body = fs::read_to_string(&file).unwrap_or_default();
                    if !has_section(&body, &s) {
                        missing.push(format!("{at}: {doc} has no section {s}"));
                    }
                }
            }
        }
    }
    assert!(
        cited > 0,
        "no source comment cites docs/: the check would be empty"
    );
    assert!(
        missing.is_empty(),
        "docs cited in source comments that do not exist:\n{}",
        missing.join("\n")
    );
}

#[test]
fn the_ticket_check_reads_words() {
    assert!(cites_a_ticket(&["see ", "issue", " 17"].concat()));
    assert!(cites_a_ticket(&["(", "Issue", " 4)"].concat()));
    assert!(!cites_a_ticket("the reading issued 3 times"));
    assert!(!cites_a_ticket("an issue tracker"));
    assert_eq!(
        docs_references("(docs/estimators.md §5.6; see docs/models.md.)"),
        vec![
            ("docs/estimators.md".to_string(), Some("5.6".to_string())),
            ("docs/models.md".to_string(), None),
        ]
    );
    assert!(docs_references("https://example.org/docs/x").is_empty());
    assert!(has_section(
        "## 5. Estimators\n### 5.6 Theorem III.23\n",
        "5.6"
    ));
    assert!(has_section("## 15. Garbled\n", "15"));
    assert!(!has_section("5.6 in text\n", "5.6"));
}

/// The files a reader of the documentation is sent to.
const DOCUMENTATION: [&str; 3] = ["docs", "README.md", "report/README.md"];

/// The `src/…` paths of `line` (a file `src/x.rs` or a folder `src/x/`).
fn source_paths(line: &str) -> Vec<String> {
    let path_char = |c: char| c.is_ascii_alphanumeric() || "_-./".contains(c);
    line.match_indices("src/")
        .filter(|(i, _)| !line[..*i].chars().next_back().is_some_and(path_char))
        .map(|(i, _)| {
            let rest = &line[i..];
            let end = rest.find(|c: char| !path_char(c)).unwrap_or(rest.len());
            rest[..end].trim_end_matches('.').to_string()
        })
        .collect()
}

/// Code moves between files; the documentation must follow it. Every `src/…` file or folder
/// that the README, report/README.md or docs/ name exists.
#[test]
fn source_paths_named_in_the_documentation_exist() {
    let mut missing = Vec::new();
    let mut named = 0;
    for (path, text) in files_of(&DOCUMENTATION) {
        for (n, line) in text.lines().enumerate() {
            for source in source_paths(line) {
                named += 1;
                if !root().join(&source).exists() {
                    missing.push(format!("{}:{}: {source}", path.display(), n + 1));
                }
            }
        }
    }
    assert!(
        named > 0,
        "the documentation names no source path: the check would be empty"
    );
    assert!(
        missing.is_empty(),
        "source paths named in the documentation that do not exist:\n{}",
        missing.join("\n")
    );
    assert_eq!(
        source_paths("(`src/mesh/`, src/fe/constraints.rs.) and a/src/x"),
        vec!["src/mesh/".to_string(), "src/fe/constraints.rs".to_string()]
    );
}
