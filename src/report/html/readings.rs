//! The head of a table's section (its verdict, the known difference, the links to the family's
//! shared notes and the errata that affect it, its notes folded under them), the family boxes,
//! and the errata section of the page.

use super::*;

/// The head of a table's section: the one-line verdict (what holds and what differs, with the
/// known difference where there is one), how each primary column compares, the links to the
/// family box and the errata that affect the table, and the table's notes — the readings tried
/// — folded under it. An own or edited scene, which is not compared, gets its notes alone.
pub(super) fn verdict_and_readings(h: &mut String, s: &Section, verdict: &Verdict) {
    let table = &s.run.table;
    let notes = &s.run.notes;
    if !s.thesis.comparison.is_printed() {
        if !notes.is_empty() {
            h.push_str("<h3>Notes</h3>\n");
            note_list(h, notes);
        }
        return;
    }
    verdict_line(h, table, verdict);
    if let Some(score) = verdict.score() {
        primary_legend(h, score);
    }
    let family = families::family_of(table);
    let shared = family
        .map(|f| families::notes_for(f, table).len())
        .unwrap_or(0);
    if let Some(f) = family {
        let what = match shared {
            0 => "The model and its conventions".to_string(),
            1 => "The model, its conventions and 1 shared note that holds for this table".into(),
            n => {
                format!("The model, its conventions and {n} shared notes that hold for this table")
            }
        };
        let _ = writeln!(
            h,
            "<p class=\"family-link\">{what}: <a href=\"#{}\">{}</a>.</p>",
            f.id,
            escape(&f.name)
        );
    }
    let found = errata::errata_for(table);
    if !found.is_empty() {
        h.push_str("<p class=\"errata-link\">Thesis errata affecting this table: ");
        for (i, e) in found.iter().enumerate() {
            let _ = write!(
                h,
                "{}<a href=\"#{}\">{}</a>",
                if i == 0 { "" } else { " · " },
                escape(&e.id),
                escape(&e.title)
            );
        }
        h.push_str(".</p>\n");
    }
    if !notes.is_empty() {
        let _ = writeln!(
            h,
            "<details class=\"readings\"><summary>Readings tried and notes ({})</summary>",
            notes.len()
        );
        note_list(h, notes);
        h.push_str("</details>\n");
    }
}

fn note_list(h: &mut String, notes: &[String]) {
    h.push_str("<ul class=\"notes\">\n");
    for n in notes {
        let _ = writeln!(h, "<li>{}</li>", escape(n));
    }
    h.push_str("</ul>\n");
}

/// The verdict in one line, coloured by its severity, with the known difference's sentence.
fn verdict_line(h: &mut String, table: &str, verdict: &Verdict) {
    let known = match verdict {
        Verdict::Differs { .. } | Verdict::Duplicate { .. } => errata::known_difference(table),
        _ => None,
    };
    let because = known.map_or(String::new(), |k| {
        format!(
            " <span class=\"known\"><b>Known difference ({}):</b> {}</span>",
            k.kind.name(),
            escape(k.reason)
        )
    });
    let _ = writeln!(
        h,
        "<p class=\"verdict-line {}\"><b>Verdict:</b> {}.{because}</p>",
        verdict.class(),
        escape(&verdict.label())
    );
}

/// How each primary column compares: its band, the rows within it and the worst deviation.
fn primary_legend(h: &mut String, score: &Score) {
    let parts: Vec<String> = score
        .columns
        .iter()
        .map(|c| {
            format!(
                "{} (<code>{}</code>, band {} %): {} of {} rows within{}",
                escape(&c.name),
                escape(&c.column),
                fmt_short(c.band * 100.0),
                c.within,
                c.rows,
                if c.worst.is_some() || c.against_zero > 0 {
                    format!(", worst {}", c.describe())
                } else {
                    String::new()
                }
            )
        })
        .collect();
    if !parts.is_empty() {
        let _ = writeln!(
            h,
            "<p class=\"legend\">Primary columns: {}.</p>",
            parts.join("; ")
        );
    }
}

/// A family's "model and conventions" box with the notes its tables share; shown once, before
/// the first section of the family on the page.
pub(super) fn family_box(h: &mut String, family: &Family) {
    let _ = write!(
        h,
        "<section id=\"{}\" class=\"family\">\n<h2>{} — model and conventions</h2>\n\
         <p class=\"meta\">{}</p>\n<dl class=\"model\">\n",
        family.id,
        escape(&family.name),
        escape(&family.sections)
    );
    for item in &family.model {
        let _ = writeln!(
            h,
            "<dt>{}</dt><dd>{}</dd>",
            escape(&item.heading),
            escape(&item.text)
        );
    }
    h.push_str("</dl>\n");
    if !family.notes.is_empty() {
        let _ = writeln!(
            h,
            "<details class=\"shared\"><summary>Notes shared by the family ({})</summary>\n\
             <ul class=\"notes\">",
            family.notes.len()
        );
        for n in &family.notes {
            let tables = if n.tables.is_empty() {
                "All tables".to_string()
            } else {
                n.tables
                    .iter()
                    .map(|t| entry_name(t))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            let _ = writeln!(
                h,
                "<li><b>{}:</b> {}</li>",
                escape(&tables),
                escape(&n.text)
            );
        }
        h.push_str("</ul></details>\n");
    }
    h.push_str("</section>\n");
}

/// The tables and figures of the page, by id.
fn on_page<'a>(entries: &'a [Entry]) -> BTreeSet<&'a str> {
    entries
        .iter()
        .map(|e| match e {
            Entry::Done(s) => s.run.table.as_str(),
            Entry::Failed(f) => f.table.as_str(),
        })
        .collect()
}

/// The thesis errata that affect a table of the page run as printed (an own or edited scene
/// has none), in the order of the thesis.
pub(super) fn errata_on_page(entries: &[Entry]) -> Vec<&'static Erratum> {
    let printed: BTreeSet<&str> = entries
        .iter()
        .filter_map(|e| match e {
            Entry::Done(s) if s.thesis.comparison.is_printed() => Some(s.run.table.as_str()),
            Entry::Done(_) => None,
            Entry::Failed(f) => Some(f.table.as_str()),
        })
        .collect();
    errata::errata()
        .iter()
        .filter(|e| e.tables.iter().any(|t| printed.contains(t.as_str())))
        .collect()
}

/// The errata section: every thesis defect tribo found that affects a table of the page, with
/// its evidence and the reading used, and links to the affected tables that are on the page;
/// nothing on a page without such a table (a page of own scenes).
pub(super) fn errata_section(h: &mut String, entries: &[Entry]) {
    let shown = errata_on_page(entries);
    if shown.is_empty() {
        return;
    }
    let on_page = on_page(entries);
    let all = errata::errata().len();
    let how_many = if shown.len() == all {
        String::new()
    } else {
        format!(
            " This page shows the {} of {all} that affect its tables.",
            shown.len()
        )
    };
    let _ = writeln!(
        h,
        "<section id=\"errata\">\n<h2>Thesis errata</h2>\n<p>Defects of the printed thesis \
         found while reproducing Chapter IV — duplicated tables, spikes and noise, contradictions \
         between text and tables, garbled or missing formulas — with the evidence and the reading \
         tribo uses.{how_many}</p>"
    );
    for e in shown {
        erratum_entry(h, e, &on_page);
    }
    h.push_str("</section>\n");
}

pub(super) fn erratum_entry(h: &mut String, e: &Erratum, on_page: &BTreeSet<&str>) {
    let tables = e
        .tables
        .iter()
        .map(|t| {
            if on_page.contains(t.as_str()) {
                format!("<a href=\"#{}\">{}</a>", anchor(t), escape(&entry_name(t)))
            } else {
                escape(&entry_name(t))
            }
        })
        .collect::<Vec<_>>()
        .join(", ");
    let _ = writeln!(
        h,
        "<div class=\"erratum\" id=\"{}\">\n<h3>{}</h3>\n<p class=\"meta\">{} · affects {}</p>\n\
         <p><b>Evidence.</b> {}</p>\n<p><b>Reading.</b> {}</p>\n</div>",
        escape(&e.id),
        escape(&e.title),
        e.kind.name(),
        tables,
        escape(&e.evidence),
        escape(&e.reading)
    );
}
