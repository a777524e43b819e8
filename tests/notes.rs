//! Notes a reader can follow: no references to files the reader does not have, to thesis text
//! lines or to an issue tracker outside the repository; every erratum names tables that exist
//! and is linked from them; each family's "model and conventions" box appears once on a page.

use std::collections::BTreeSet;
use std::fs;

use tribo::report::errata;
use tribo::report::families;

use crate::common::experiments_dir;

/// Every experiment id (file stem) of `experiments/`.
fn experiment_ids() -> BTreeSet<String> {
    fs::read_dir(experiments_dir())
        .expect("experiments/")
        .filter_map(|e| {
            let path = e.expect("entry").path();
            (path.extension()? == "toml").then(|| path.file_stem()?.to_str().map(String::from))?
        })
        .collect()
}

/// The reference a reader cannot follow in `text`, if any: a spec file, a Markdown file, an
/// issue, or a line number of the thesis text (`l. 4831`, `line 7085`, `lines 5966–5980`).
fn unfollowable(text: &str) -> Option<&'static str> {
    let lower = text.to_lowercase();
    if let Some(p) = ["spec/", "spec §", ".md", "issue"]
        .into_iter()
        .find(|p| lower.contains(p))
    {
        return Some(p);
    }
    ["l. ", "line ", "lines "].into_iter().find(|p| {
        lower.match_indices(p).any(|(i, _)| {
            let before = lower[..i].chars().next_back();
            let after = lower[i + p.len()..].chars().next();
            !before.is_some_and(char::is_alphanumeric) && after.is_some_and(|c| c.is_ascii_digit())
        })
    })
}

#[test]
fn no_note_cites_spec_files_thesis_lines_or_issues() {
    let mut found = Vec::new();
    for id in experiment_ids() {
        let spec = crate::common::spec(&id);
        for (i, note) in spec.notes.iter().enumerate() {
            if let Some(p) = unfollowable(note) {
                found.push(format!("{id} notes[{i}]: '{p}'"));
            }
        }
        if let Some(k) = errata::known_difference(&id) {
            if let Some(p) = unfollowable(k.reason) {
                found.push(format!("{id} known difference: '{p}'"));
            }
        }
    }
    for f in families::families() {
        let texts = f
            .model
            .iter()
            .map(|m| m.text.as_str())
            .chain(f.notes.iter().map(|n| n.text.as_str()));
        for t in texts {
            if let Some(p) = unfollowable(t) {
                found.push(format!("family {}: '{p}' in {t}", f.id));
            }
        }
    }
    for e in errata::errata() {
        for t in [&e.title, &e.evidence, &e.reading] {
            if let Some(p) = unfollowable(t) {
                found.push(format!("{}: '{p}'", e.id));
            }
        }
    }
    assert!(found.is_empty(), "{}", found.join("\n"));
}

#[test]
fn errata_name_existing_tables_and_have_unique_anchors() {
    let ids = experiment_ids();
    let mut anchors = BTreeSet::new();
    for e in errata::errata() {
        assert!(anchors.insert(e.id.as_str()), "{} twice", e.id);
        assert!(e.id.starts_with("erratum-"), "{}", e.id);
        assert!(!e.tables.is_empty(), "{} affects no table", e.id);
        for t in &e.tables {
            assert!(ids.contains(t), "{}: no experiment {t}", e.id);
            assert!(errata::errata_for(t).iter().any(|f| f.id == e.id), "{t}");
        }
    }
    // The duplicated thesis tables are errata, and a table without defect has none.
    for t in ["IV.17", "IV.47", "IV.48", "IV.49"] {
        assert!(
            errata::errata_for(t)
                .iter()
                .any(|e| e.kind == errata::ErratumKind::Duplicate),
            "{t}"
        );
    }
    assert!(errata::errata_for("no-such-table").is_empty());
    // Differences tribo cannot explain have no entry (the SubStokes dofs gaps); every entry
    // names an existing table.
    for t in [
        "IV.50", "IV.51", "IV.53", "IV.54", "IV.57", "IV.59", "IV.70", "IV.74",
    ] {
        assert_eq!(errata::known_difference(t), None, "{t}");
    }
    let explained: Vec<_> = ids
        .iter()
        .filter(|t| errata::known_difference(t).is_some())
        .collect();
    assert!(explained.len() >= 20, "{explained:?}");
    assert_eq!(
        errata::known_difference("IV.47").map(|k| k.kind),
        Some(errata::DifferenceKind::Duplicate)
    );
}

#[test]
fn every_chapter_table_has_a_family_and_family_notes_name_its_own_tables() {
    for n in 1..=75 {
        let t = format!("IV.{n}");
        let f = families::family_of(&t).unwrap_or_else(|| panic!("{t} has no family"));
        for note in &f.notes {
            for u in &note.tables {
                assert_eq!(
                    families::family_of(u).map(|g| &g.id),
                    Some(&f.id),
                    "{} lists {u}",
                    f.id
                );
            }
        }
    }
    assert_eq!(families::family_of("IV.36").unwrap().id, "family-reynolds");
    assert_eq!(families::family_of("IV.70").unwrap().id, "family-substokes");
    assert_eq!(
        families::family_of("fig-IV.54").unwrap().id,
        "family-model-contact"
    );
    assert_eq!(families::family_of("fig-III.6").unwrap().id, "family-uzawa");
    assert!(families::family_of("IV.76").is_none());
    assert!(families::family_of("my-scene").is_none());
    // A note shared by the whole family applies to each table; a listed one only to its tables.
    let reynolds = families::family_of("IV.38").unwrap();
    let n38 = families::notes_for(reynolds, "IV.38").len();
    let n64 = families::notes_for(reynolds, "IV.64").len();
    assert!(n64 > n38, "{n64} vs {n38}");
}

/// The `<section id="…">…</section>` of `id` on `page`.
fn section<'a>(page: &'a str, id: &str) -> &'a str {
    let start = page
        .find(&format!("<section id=\"{id}\""))
        .unwrap_or_else(|| panic!("no section {id}"));
    let end = page[start..].find("</section>").expect("section closes") + start;
    &page[start..end]
}

#[test]
fn a_page_shows_each_family_box_once_and_links_the_errata() {
    let tables = ["IV.1", "IV.2", "IV.47", "IV.48"];
    let out = crate::outputs::quick_report(
        &experiments_dir(),
        "notes-families",
        Some(&tables.join(",")),
    );
    let page = tribo::report::read_pages(&out).expect("index.html");
    for family in ["family-elasticity", "family-reynolds"] {
        assert_eq!(
            page.matches(&format!("<section id=\"{family}\"")).count(),
            1,
            "{family}"
        );
    }
    for family in ["family-contact", "family-substokes"] {
        assert!(!page.contains(&format!("id=\"{family}\"")), "{family}");
    }
    // The box comes before the first section of its family.
    assert!(page.find("id=\"family-reynolds\"").unwrap() < page.find("id=\"t-IV.47\"").unwrap());
    assert!(page.contains("<a href=\"errata.html\">"));
    let errata_part = section(&page, "errata");
    for t in tables {
        let s = section(&page, &format!("t-{t}"));
        let family = families::family_of(t).unwrap();
        assert!(s.contains(&format!("href=\"#{}\"", family.id)), "{t}");
        let found = errata::errata_for(t);
        assert!(!found.is_empty(), "{t}");
        for e in found {
            assert!(
                s.contains(&format!("href=\"errata.html#{}\"", e.id)),
                "{t}: {}",
                e.id
            );
            assert!(
                errata_part.contains(&format!("id=\"{}\"", e.id)),
                "{}",
                e.id
            );
        }
        assert!(errata_part.contains(&format!(".html#t-{t}\"")), "{t}");
        assert!(unfollowable("as printed (thesis l. 5925)").is_some());
        assert!(unfollowable("the normal line misses the obstacle").is_none());
        for item in s.split("<li>").skip(1) {
            let text = item.split("</li>").next().unwrap();
            assert!(unfollowable(text).is_none(), "{t}: {text}");
        }
    }
    // A table not on the page is named in the errata without a dangling link.
    assert!(!errata_part.contains("href=\"#t-IV.44\""));
}
