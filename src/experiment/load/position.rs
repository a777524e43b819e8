//! Where in the file an error of the `toml` crate is: the dotted path of the field and the
//! line, found in toml's recovering parse of the text, so that every syntax, type, missing-
//! and unknown-field error names the field it is about.

use std::path::Path;

use toml::de::{DeTable, DeValue};
use toml::Spanned;

use crate::experiment::ExperimentError;

/// Wrap an error of the `toml` crate with the file name and, where it can be located, the
/// dotted path of the field it is about.
pub(super) fn toml_error(path: &Path, text: &str, error: &toml::de::Error) -> ExperimentError {
    let position = error.span().map(|span| span.start);
    let missing = quoted_after(error.message(), "missing field `");
    let mut field = position.and_then(|pos| field_at(text, pos, missing.is_some()));
    if let Some(missing) = missing {
        field = Some(match field {
            Some(parent) if !parent.is_empty() => format!("{parent}.{missing}"),
            _ => missing.to_owned(),
        });
    }
    ExperimentError::Toml {
        path: path.to_path_buf(),
        field: field
            .filter(|f| !f.is_empty())
            .map(|f| shorten(&f, MAX_FIELD_CHARS)),
        line: position.map(|pos| line_of(text, pos)),
        message: error
            .to_string()
            .trim_end()
            .lines()
            .map(|line| shorten(line, MAX_LINE_CHARS))
            .collect::<Vec<_>>()
            .join("\n"),
    }
}

/// Longest field path and longest line of toml's message quoted in an error: a 100 000-deep
/// nested array made a 200 KB message, its path and the quoted source line.
pub(super) const MAX_FIELD_CHARS: usize = 120;
const MAX_LINE_CHARS: usize = 240;

/// `text` cut to about `max` characters, keeping its beginning and end around an ellipsis.
pub(super) fn shorten(text: &str, max: usize) -> String {
    let n = text.chars().count();
    if n <= max {
        return text.to_owned();
    }
    let head: String = text.chars().take(max / 2).collect();
    let tail: String = text.chars().skip(n - max / 2).collect();
    format!("{head}…{tail}")
}

/// The text between `prefix` and the next backtick in `message`.
fn quoted_after<'m>(message: &'m str, prefix: &str) -> Option<&'m str> {
    let rest = &message[message.find(prefix)? + prefix.len()..];
    Some(&rest[..rest.find('`')?])
}

/// 1-based line number of byte offset `pos`.
fn line_of(text: &str, pos: usize) -> usize {
    1 + text
        .bytes()
        .take(pos.min(text.len()))
        .filter(|&b| b == b'\n')
        .count()
}

/// The dotted path (`study.rows`, `scene.elasticity.dirichlet[1]`) of the innermost key or value
/// whose source span contains byte offset `pos`, found with toml's recovering parser so that
/// syntax errors inside a value are located too. With `tables_only` (for "missing field"
/// errors, whose span is the table that lacks the field) only table values count, and the top
/// level is `Some("")`. Falls back to the key written on the error's line.
fn field_at(text: &str, pos: usize, tables_only: bool) -> Option<String> {
    let (document, _) = DeTable::parse_recoverable(text);
    let mut best: Option<(usize, String)> = None;
    search_table(document.get_ref(), "", pos, tables_only, &mut best);
    match best {
        Some((_, path)) => Some(path),
        None if tables_only => Some(String::new()),
        None => key_on_line(text, pos),
    }
}

/// Depth-first search of `table` for the smallest span containing `pos`; on equal spans the
/// deeper entry wins.
fn search_table(
    table: &DeTable<'_>,
    prefix: &str,
    pos: usize,
    tables_only: bool,
    best: &mut Option<(usize, String)>,
) {
    for (key, value) in table.iter() {
        let path = if prefix.is_empty() {
            key.get_ref().to_string()
        } else {
            format!("{prefix}.{}", key.get_ref())
        };
        let is_table = matches!(value.get_ref(), DeValue::Table(_));
        if !tables_only || is_table {
            for span in [key.span(), value.span()] {
                consider(&span, &path, pos, best);
            }
        }
        search_value(value, &path, pos, tables_only, best);
    }
}

fn search_value(
    value: &Spanned<DeValue<'_>>,
    path: &str,
    pos: usize,
    tables_only: bool,
    best: &mut Option<(usize, String)>,
) {
    match value.get_ref() {
        DeValue::Table(table) => search_table(table, path, pos, tables_only, best),
        DeValue::Array(items) => {
            for (index, item) in items.iter().enumerate() {
                let item_path = format!("{path}[{index}]");
                if !tables_only || matches!(item.get_ref(), DeValue::Table(_)) {
                    consider(&item.span(), &item_path, pos, best);
                }
                search_value(item, &item_path, pos, tables_only, best);
            }
        }
        _ => {}
    }
}

fn consider(
    span: &std::ops::Range<usize>,
    path: &str,
    pos: usize,
    best: &mut Option<(usize, String)>,
) {
    // An empty span (e.g. at the end of the input) contains its start.
    let contains = span.contains(&pos) || (span.is_empty() && span.start == pos);
    let len = span.end - span.start;
    if contains && best.as_ref().is_none_or(|(best_len, _)| len <= *best_len) {
        *best = Some((len, path.to_owned()));
    }
}

/// Textual fallback: `header.key` for an error on a line `key = …` below a `[header]`.
fn key_on_line(text: &str, pos: usize) -> Option<String> {
    let pos = pos.min(text.len());
    if !text.is_char_boundary(pos) {
        return None;
    }
    let line_start = text[..pos].rfind('\n').map_or(0, |i| i + 1);
    let line_end = text[pos..].find('\n').map_or(text.len(), |i| pos + i);
    let line = &text[line_start..line_end];
    let key = line.split_once('=')?.0.trim();
    let is_key = |k: &str| {
        !k.is_empty()
            && k.chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'))
    };
    if !is_key(key) {
        return None;
    }
    let header = text[..line_start]
        .lines()
        .rev()
        .find_map(|l| {
            let inner = l.trim().strip_prefix('[')?.strip_suffix(']')?;
            let inner = inner.trim_start_matches('[').trim_end_matches(']').trim();
            is_key(inner).then_some(inner)
        })
        .unwrap_or("");
    Some(if header.is_empty() {
        key.to_owned()
    } else {
        format!("{header}.{key}")
    })
}
