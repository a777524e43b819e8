//! The identity of an experiment: table id, file name, section, title, notes and related ids.

use super::check::{Check, Checked};
use super::ids::{
    is_own_id, is_thesis_id, table_number, LAST_FIGURE, LAST_FIGURE_III, LAST_TABLE,
    MAX_OWN_ID_CHARS,
};
use super::position::{shorten, MAX_FIELD_CHARS};
use crate::experiment::spec::*;

/// Most notes of one table.
const MAX_NOTES: usize = 100;

/// Whether `c` shows nothing: white space, and the format characters and fillers that have no
/// glyph (zero-width space and joiners, word joiner, byte order mark, soft hyphen, variation
/// selectors, the Hangul fillers, the braille blank). A text made of them alone renders as
/// nothing on the page, and is no title.
pub(super) fn is_invisible(c: char) -> bool {
    c.is_whitespace()
        || matches!(
            c,
            '\u{00AD}'
                | '\u{034F}'
                | '\u{061C}'
                | '\u{115F}'
                | '\u{1160}'
                | '\u{17B4}'
                | '\u{17B5}'
                | '\u{180B}'..='\u{180F}'
                | '\u{200B}'..='\u{200F}'
                | '\u{202A}'..='\u{202E}'
                | '\u{2060}'..='\u{206F}'
                | '\u{2800}'
                | '\u{3164}'
                | '\u{FE00}'..='\u{FE0F}'
                | '\u{FEFF}'
                | '\u{FFA0}'
                | '\u{E0000}'..='\u{E007F}'
                | '\u{E0100}'..='\u{E01EF}'
        )
}

impl Check<'_> {
    /// A one-line text that is not made of invisible characters alone ([`is_invisible`]); an
    /// empty text is for the field's own check.
    pub(super) fn visible(&self, field: &str, text: &str) -> Checked {
        let invisible: Vec<String> = text
            .chars()
            .take(8)
            .map(|c| format!("U+{:04X}", c as u32))
            .collect();
        self.ensure(
            text.is_empty() || !text.chars().all(is_invisible),
            field,
            "a text with a visible character",
            format!(
                "only invisible characters ({}{})",
                invisible.join(" "),
                if text.chars().count() > 8 { " …" } else { "" }
            ),
        )
    }

    /// Table id, section and title (Chapter IV numbering).
    pub(super) fn identity(&self, spec: &ExperimentFile) -> Checked {
        let thesis_id = is_thesis_id(&spec.table);
        self.ensure(
            thesis_id || is_own_id(&spec.table),
            "table",
            &format!(
                "a Chapter IV table id `IV.<n>` with 1 ≤ n ≤ {LAST_TABLE}, a figure id \
                 `fig-IV.<n>` with 1 ≤ n ≤ {LAST_FIGURE} or `fig-III.<n>` with 1 ≤ n ≤ \
                 {LAST_FIGURE_III}, or an id of your own: ASCII letters, digits, `.`, `-` and \
                 `_`, starting with a letter or digit, at most {MAX_OWN_ID_CHARS} characters, \
                 not beginning with `IV.` or `fig-`"
            ),
            format!("`{}`", shorten(&spec.table, MAX_FIELD_CHARS)),
        )?;
        let stem = self
            .path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        self.ensure(
            spec.table == stem,
            "table",
            &format!("the file name's table id `{stem}`"),
            format!("`{}`", spec.table),
        )?;
        self.ensure(
            table_number(&spec.table).is_none() || spec.thesis.is_some(),
            "table",
            &format!(
                "an id of your own for a scene without a printed table: `{id}` is the \
                 thesis's Table {id}, whose experiment carries the printed table ([thesis] \
                 with columns and rows); pick another id (letters, digits, `.`, `-`, `_`, \
                 e.g. `my-{id}`) and name the file after it",
                id = spec.table,
            ),
            format!("`{}` without [thesis]", spec.table),
        )?;
        let (chapter, expected) = if !thesis_id {
            ("", "a non-empty section")
        } else if spec.table.starts_with("fig-III.") {
            (
                "III.",
                "a Chapter III section such as `III.2.3.4` (a `fig-III.<n>` experiment)",
            )
        } else {
            ("IV.", "a Chapter IV section such as `IV.1.1`")
        };
        self.ensure(
            spec.section.starts_with(chapter) && spec.section.len() > chapter.len(),
            "section",
            expected,
            format!("`{}`", spec.section),
        )?;
        self.ensure(
            !spec.title.trim().is_empty(),
            "title",
            "a non-empty title",
            "an empty string",
        )?;
        self.printable("section", &spec.section, false)?;
        self.printable("title", &spec.title, false)?;
        self.ensure(
            spec.notes.len() <= MAX_NOTES,
            "notes",
            &format!("at most {MAX_NOTES} notes"),
            format!("{} notes", spec.notes.len()),
        )?;
        for (i, note) in spec.notes.iter().enumerate() {
            self.printable(&format!("notes[{i}]"), note, true)?;
        }
        for (i, id) in spec.related.iter().enumerate() {
            self.ensure(
                (is_thesis_id(id) || is_own_id(id)) && *id != spec.table,
                &format!("related[{i}]"),
                "the id of another table or figure experiment, e.g. `IV.46`, or of a scene of your own",
                format!("`{id}`"),
            )?;
        }
        Ok(())
    }
}
