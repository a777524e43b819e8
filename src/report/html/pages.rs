//! The report as a set of pages: a front page (`index.html`: the run, the families, the compact
//! summary grouped by family, performance), one page per family of tables (`contact.html`,
//! `reynolds.html`, …: the family's model and conventions, its tables in detail and their
//! sections), a page of the scenes that belong to no family (`scenes.html`) and the thesis
//! errata (`errata.html`).
//!
//! One page of 78 tables and 370 figures took seconds to open: a browser lays out every section
//! and fetches every figure of the page, however it is folded. Split this way the front page
//! holds one figure and opens at once, and each family page holds only its own tables.
//!
//! The parts of a page link to each other by anchors (`#t-IV.36`, `#erratum-…`,
//! `#family-contact`); each part writes its links as if everything were on one page, and
//! [`link_pages`] then points every link whose anchor is on another page at that page
//! (`reynolds.html#t-IV.36`), so no part needs to know where the others are.

use super::*;

/// One written page: its file name in the output folder and its HTML.
pub(crate) struct Page {
    pub file: String,
    pub html: String,
}

/// The page of the entries that belong to no family: scenes without a thesis table (the user's
/// own, and the shipped scenes with a known solution).
const SCENES_PAGE: &str = "scenes.html";
/// The page of the thesis errata.
const ERRATA_PAGE: &str = "errata.html";
/// The front page.
pub(crate) const FRONT_PAGE: &str = "index.html";

/// The page file of a family: its box id without the `family-` prefix (`family-contact` →
/// `contact.html`).
fn family_file(family: &Family) -> String {
    format!(
        "{}.html",
        family.id.strip_prefix("family-").unwrap_or(&family.id)
    )
}

/// Every page file a report may write, for removing those an earlier run left that this run
/// does not write (a page of a family no longer in the run would otherwise still be there).
pub(crate) fn page_files() -> Vec<String> {
    let mut files = vec![
        FRONT_PAGE.to_string(),
        SCENES_PAGE.to_string(),
        ERRATA_PAGE.to_string(),
    ];
    files.extend(families::families().iter().map(family_file));
    files
}

/// The entries of one page: a family's (in the order of the run), or those of no family.
pub(super) struct Group<'a> {
    pub family: Option<&'static Family>,
    pub file: String,
    /// The indices of its entries in the run's list.
    pub members: Vec<usize>,
    pub entries: Vec<&'a Entry<'a>>,
}

impl Group<'_> {
    /// How the page is named in the contents and in its header.
    pub fn name(&self) -> &str {
        match self.family {
            Some(f) => &f.name,
            None => "Scenes without a thesis table",
        }
    }
}

/// The entries grouped by page: the families in the order of Chapter IV (`families.toml`),
/// then the entries of no family; a group only where the run has an entry.
pub(super) fn groups<'a>(entries: &'a [Entry<'a>]) -> Vec<Group<'a>> {
    let mut groups: Vec<Group> = families::families()
        .iter()
        .map(|f| Group {
            family: Some(f),
            file: family_file(f),
            members: Vec::new(),
            entries: Vec::new(),
        })
        .collect();
    groups.push(Group {
        family: None,
        file: SCENES_PAGE.to_string(),
        members: Vec::new(),
        entries: Vec::new(),
    });
    for (i, entry) in entries.iter().enumerate() {
        let at = families::family_of(entry.table())
            .and_then(|f| {
                groups
                    .iter()
                    .position(|g| g.family.is_some_and(|g| g.id == f.id))
            })
            .unwrap_or(groups.len() - 1);
        groups[at].members.push(i);
        groups[at].entries.push(entry);
    }
    groups.retain(|g| !g.members.is_empty());
    groups
}

/// Every page of the report: the front page first, then one per group, then the errata (when
/// a table of the run has one); `figures` has one element per entry.
pub(crate) fn pages(
    entries: &[Entry],
    figures: &[SectionFigures],
    compared: &[(ComparedRuns, SectionFigures)],
    meta: &ReportMeta,
) -> Vec<Page> {
    let groups = groups(entries);
    let mut pages = vec![Page {
        file: FRONT_PAGE.to_string(),
        html: front_page(entries, &groups, meta),
    }];
    for group in &groups {
        pages.push(Page {
            file: group.file.clone(),
            html: group_page(entries, &groups, group, figures, compared, meta),
        });
    }
    if !errata_on_page(entries).is_empty() {
        let mut h = head(&format!("Thesis errata ({})", meta.tier));
        slim_header(&mut h, "Thesis errata", "", &groups, meta);
        h.push_str("<main>\n");
        errata_section(&mut h, entries);
        footer(&mut h, entries, meta);
        pages.push(Page {
            file: ERRATA_PAGE.to_string(),
            html: h,
        });
    }
    link_pages(&mut pages);
    pages
}

/// The start of a page up to `<body>`: title and the shared style.
fn head(title: &str) -> String {
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>tribo — {}</title>\n<style>{CSS}</style>\n</head>\n<body>\n",
        escape(title)
    )
}

/// The end of every page: who wrote it and what its numbers are.
fn footer(h: &mut String, entries: &[Entry], meta: &ReportMeta) {
    let _ = writeln!(
        h,
        "<footer>Written by {}. {}</footer>",
        escape(&meta.generated_by),
        if any_thesis_entry(entries) {
            "Thesis values are the printed tables of Chapter IV, shown for comparison only; \
             every tribo value on these pages was computed in this run."
        } else {
            "Every value on these pages was computed in this run."
        }
    );
    h.push_str("</main>\n</body>\n</html>\n");
}

/// The front page: the run, the pages, the summary grouped by family, and performance.
fn front_page(entries: &[Entry], groups: &[Group], meta: &ReportMeta) -> String {
    let mut h = head(&format!("Chapter IV report ({})", meta.tier));
    header(&mut h, entries, meta);
    h.push_str("<main>\n");
    contents(&mut h, entries, groups);
    front_summary(&mut h, entries, groups);
    performance_section(&mut h, entries, &meta.alongside);
    footer(&mut h, entries, meta);
    h
}

/// The page of one group of `groups`: its model box, its tables in detail, and a folded section
/// per table, each comparison of runs before the first entry it compares.
fn group_page(
    entries: &[Entry],
    groups: &[Group],
    group: &Group,
    figures: &[SectionFigures],
    compared: &[(ComparedRuns, SectionFigures)],
    meta: &ReportMeta,
) -> String {
    let mut h = head(&format!("{} ({})", group.name(), meta.tier));
    let sections = group.family.map_or("", |f| f.sections.as_str());
    slim_header(&mut h, group.name(), sections, groups, meta);
    h.push_str("<main>\n");
    if let Some(family) = group.family {
        family_box(&mut h, family);
    }
    family_summary(&mut h, &group.entries);
    family_effectivity(&mut h, &group.entries);
    substokes_row_zero(&mut h, &group.entries);
    for &i in &group.members {
        for (c, figs) in compared.iter().filter(|(c, _)| c.first == i) {
            compare::comparison_section(&mut h, c, figs);
        }
        let entry = &entries[i];
        fold_open(&mut h, entry);
        match entry {
            Entry::Done(section) => table_section(&mut h, section, &figures[i]),
            Entry::Failed(failure) => failed_section(&mut h, failure),
        }
        h.push_str("</details>\n");
    }
    footer(&mut h, entries, meta);
    h
}

/// The header of a page other than the front page: the way back, the other pages, and what
/// run it belongs to.
fn slim_header(h: &mut String, name: &str, sections: &str, groups: &[Group], meta: &ReportMeta) {
    let _ = write!(
        h,
        "<header class=\"slim\"><div class=\"inner\">\n<p class=\"pages\"><a href=\"{FRONT_PAGE}\">\
         ← summary</a>"
    );
    for g in groups {
        let _ = write!(
            h,
            " · <a href=\"{}\">{}</a>",
            escape(&g.file),
            escape(g.name())
        );
    }
    let _ = writeln!(
        h,
        "</p>\n<h1>{}</h1>\n<p>{}{}tier {} · commit {} · {}</p>\n</div></header>",
        escape(name),
        escape(sections),
        if sections.is_empty() { "" } else { " · " },
        escape(&meta.tier),
        escape(&meta.provenance.commit),
        escape(&meta.provenance.date),
    );
}

/// Point every link `href="#x"` whose anchor `x` is not on its own page at the page that has
/// it (`reynolds.html#x`); a link whose anchor is on no page is left as it is (the tests find
/// it).
fn link_pages(pages: &mut [Page]) {
    let ids: Vec<BTreeSet<String>> = pages.iter().map(|p| ids_of(&p.html)).collect();
    let mut home: HashMap<&str, &str> = HashMap::new();
    for (page, ids) in pages.iter().zip(&ids) {
        for id in ids {
            home.entry(id.as_str()).or_insert(page.file.as_str());
        }
    }
    let relinked: Vec<String> = pages
        .iter()
        .zip(&ids)
        .map(|(page, own)| {
            let mut out = String::with_capacity(page.html.len());
            let mut rest = page.html.as_str();
            const LINK: &str = "href=\"#";
            while let Some(at) = rest.find(LINK) {
                let (before, after) = rest.split_at(at + LINK.len());
                let id = &after[..after.find('"').unwrap_or(after.len())];
                match home.get(id) {
                    Some(file) if !own.contains(id) => {
                        out.push_str(&before[..before.len() - 1]);
                        out.push_str(&escape(file));
                        out.push('#');
                    }
                    _ => out.push_str(before),
                }
                rest = after;
            }
            out.push_str(rest);
            out
        })
        .collect();
    for (page, html) in pages.iter_mut().zip(relinked) {
        page.html = html;
    }
}

/// The element ids of a page (`id="…"` attributes).
fn ids_of(html: &str) -> BTreeSet<String> {
    html.split(" id=\"")
        .skip(1)
        .filter_map(|rest| rest.split('"').next())
        .map(str::to_string)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn links_point_at_the_page_that_has_their_anchor() {
        let mut pages = vec![
            Page {
                file: "index.html".into(),
                html: "<p id=\"summary\"><a href=\"#t-IV.36\">IV.36</a> \
                       <a href=\"#summary\">up</a> <a href=\"#nowhere\">x</a></p>"
                    .into(),
            },
            Page {
                file: "reynolds.html".into(),
                html: "<section id=\"t-IV.36\"><a href=\"#erratum-a\">e</a>\
                       <a href=\"#t-IV.36\">self</a></section>"
                    .into(),
            },
            Page {
                file: "errata.html".into(),
                html: "<div class=\"erratum\" id=\"erratum-a\"></div>".into(),
            },
        ];
        link_pages(&mut pages);
        assert_eq!(
            pages[0].html,
            "<p id=\"summary\"><a href=\"reynolds.html#t-IV.36\">IV.36</a> \
             <a href=\"#summary\">up</a> <a href=\"#nowhere\">x</a></p>"
        );
        assert_eq!(
            pages[1].html,
            "<section id=\"t-IV.36\"><a href=\"errata.html#erratum-a\">e</a>\
             <a href=\"#t-IV.36\">self</a></section>"
        );
    }

    #[test]
    fn every_family_has_its_own_page_file() {
        let files = page_files();
        let unique: BTreeSet<&String> = files.iter().collect();
        assert_eq!(
            unique.len(),
            files.len(),
            "two pages share a file: {files:?}"
        );
        assert!(files.contains(&"contact.html".to_string()));
        assert!(files.contains(&"model-contact.html".to_string()));
    }
}
