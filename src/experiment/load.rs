//! Parsing and validation of experiment files.
//!
//! [`load`] reads one file with the `toml` crate into [`ExperimentFile`], checks what serde
//! cannot — ranges, consistency between sections, and the conventions of Chapter IV (table ids
//! `IV.1`…`IV.75` with their printed rows, figure ids `fig-…`, free ids for scenes of the user's
//! own without `[thesis]`, the fixed-fraction marking of §IV.1, printed rows numbered from cycle
//! 0) — and returns the typed [`Experiment`]: the effects and their data sections become one
//! [`Problem`], and the fingerprints of the shipped files say whether a thesis experiment was
//! edited ([`Comparison`]).
//! Nothing here panics on user input; every failure is an [`ExperimentError`].

use std::collections::BTreeSet;
use std::fs;
use std::io::Read;
use std::path::{Path, PathBuf};

use toml::de::{DeTable, DeValue};
use toml::Spanned;

use super::error::ExperimentError;
use super::printed::edited_fields;
use super::spec::*;
use super::{Comparison, Experiment, Problem, Scene};
use crate::linalg::uzawa::Variant;

/// Highest table number of Chapter IV (Table IV.75).
const LAST_TABLE: u32 = 75;
/// Most cycles of one load step (§IV.2.4.7 runs 4).
const MAX_CYCLES_PER_STEP: usize = 12;
/// The last figure of Chapter IV (Fig. IV.143).
const LAST_FIGURE: u32 = 143;
/// Figures of Chapter III (the Uzawa comparison is Fig. III.6).
const LAST_FIGURE_III: u32 = 6;

/// Most printed rows of a study (and of a thesis table); Chapter IV prints at most 26.
pub const MAX_ROWS: usize = 200;
/// Most iterations of a solver study (`solver-iterations`, Fig. III.6 runs 300).
const MAX_ITERATIONS: usize = 10_000;
/// Most unprinted cycles before row 0 (Chapter IV uses at most a few).
pub const MAX_UNPRINTED_CYCLES: usize = 200;
/// Most global refinements of the coarse grid (the size of the run is bounded by the memory
/// budget of the study as well).
const MAX_GLOBAL_REFINEMENTS: usize = 12;
/// Range of the length of a side of the domain.
const MIN_LENGTH: f64 = 1e-30;
const MAX_LENGTH: f64 = 1e30;
/// Largest ratio of the two sides of a coarse cell.
const MAX_ASPECT_RATIO: f64 = 1e4;
/// Range of the Lamé constants μ, λ (λ may also be 0).
const MIN_MATERIAL: f64 = 1e-30;
const MAX_MATERIAL: f64 = 1e30;
/// Largest λ/μ: beyond it (Poisson ratio within 5e-9 of ½) the Q₁ system is singular to
/// working precision.
const MAX_LAMBDA_OVER_MU: f64 = 1e8;
/// Most columns of a printed thesis table (Chapter IV prints at most 12).
const MAX_THESIS_COLUMNS: usize = 64;
/// Longest one-line text (title, section, names, column names), in characters.
const MAX_TEXT_CHARS: usize = 1_000;
/// Longest note, in characters (the longest shipped note has about 2 700).
const MAX_NOTE_CHARS: usize = 20_000;
/// Most notes of one table.
const MAX_NOTES: usize = 100;
/// Most probe points (the grid `probes.x` × `probes.y`); Chapter IV probes at most 21. Each is
/// located in the last mesh and written to `data/<table>.probes.csv`.
const MAX_PROBE_POINTS: usize = 10_000;

/// Parse and validate one experiment file.
///
/// Errors name the file and the field: I/O errors, TOML syntax, type, missing- and
/// unknown-field errors (wrapped with toml's message, which shows the line), and every
/// semantic check of [`ExperimentFile`] (see the module documentation).
pub fn load(path: &Path) -> Result<Experiment, ExperimentError> {
    let text = read_experiment_file(path)?;
    let file: ExperimentFile =
        toml::from_str(&text).map_err(|error| toml_error(path, &text, &error))?;
    let check = Check { path };
    check.experiment(&file)?;
    let problem = check.problem(&file.scene)?;
    let comparison = if is_thesis_id(&file.table) {
        edited_fields(&file.table, &text).map_or(Comparison::Printed, Comparison::Edited)
    } else {
        Comparison::OwnScene
    };
    let ExperimentFile {
        table,
        section,
        title,
        scene,
        study,
        probes,
        notes,
        related,
        thesis,
        figures,
    } = file;
    Ok(Experiment {
        table,
        section,
        title,
        scene: Scene {
            name: scene.name,
            domain: scene.domain,
            coarse_cells: scene.coarse_cells,
            global_refinements: scene.global_refinements,
            side_refinements: scene.contact_refinements,
            refined_sides: match &scene.contact {
                Some(contact) if scene.contact_refinements > 0 => {
                    contact.obstacles.iter().map(|o| o.side).collect()
                }
                _ => Vec::new(),
            },
        },
        problem,
        study,
        probes,
        notes,
        related,
        thesis: thesis.unwrap_or_default(),
        figures,
        parameters: super::parameters::of_file(&text),
        comparison,
    })
}

/// Load every `*.toml` in `dir`, sorted by table number (IV.2 before IV.10).
///
/// With `only`, load just those tables; an id without a file is an error that names it and
/// lists the available tables. Files not asked for are not read. The first file that does not
/// load fails the whole directory; [`load_each`] keeps going instead.
pub fn load_dir(dir: &Path, only: Option<&[String]>) -> Result<Vec<Experiment>, ExperimentError> {
    load_each(dir, only)?
        .into_iter()
        .map(|(_, experiment)| experiment)
        .collect()
}

/// One entry of [`load_each`]: the file stem (the table id of a good file) and what loading the
/// file gave.
pub type Loaded = (String, Result<Experiment, ExperimentError>);

/// Load every `*.toml` in `dir` (or just the tables of `only`) in table order, each file on its
/// own: one `(stem, outcome)` per file, so that a broken file becomes one failed entry of the
/// report while the other tables still run.
///
/// Every entry named `*.toml` counts, whatever it is: a directory, a FIFO, a device or a
/// symbolic link to one is a failed entry ([`ExperimentError::NotRegularFile`]) and is never
/// opened, so `--only IV.1` names `IV.1.toml` even when it is not a file. Only problems with
/// the directory itself are errors of the whole call: it cannot be listed, or `only` names a
/// table without an entry.
pub fn load_each(dir: &Path, only: Option<&[String]>) -> Result<Vec<Loaded>, ExperimentError> {
    let mut files = experiment_entries(dir)?;
    if let Some(only) = only {
        let mut wanted = BTreeSet::new();
        for id in only {
            if !files.iter().any(|(stem, _)| stem == id) {
                return Err(ExperimentError::UnknownTable {
                    dir: dir.to_path_buf(),
                    id: id.clone(),
                    available: files.iter().map(|(stem, _)| stem.clone()).collect(),
                });
            }
            wanted.insert(id.as_str());
        }
        files.retain(|(stem, _)| wanted.contains(stem.as_str()));
    }
    Ok(files
        .into_iter()
        .map(|(stem, path)| (stem, load(&path)))
        .collect())
}

/// The `(stem, path)` of every directory entry whose name ends in `.toml`, in table order.
///
/// Entries are not opened or followed here: what they are is for [`read_experiment_file`] to
/// find out, so that an odd entry is named rather than skipped.
pub(super) fn experiment_entries(dir: &Path) -> Result<Vec<(String, PathBuf)>, ExperimentError> {
    let read_dir_error = |source| ExperimentError::ReadDir {
        dir: dir.to_path_buf(),
        source,
    };
    let mut files: Vec<(String, PathBuf)> = Vec::new();
    for entry in fs::read_dir(dir).map_err(read_dir_error)? {
        let path = entry.map_err(read_dir_error)?.path();
        if path.extension().and_then(|e| e.to_str()) != Some("toml") {
            continue;
        }
        let stem = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        files.push((stem, path));
    }
    files.sort_by_key(|(stem, _)| table_order(stem));
    Ok(files)
}

/// Largest experiment file read, in bytes. The largest shipped file has a few kilobytes; the
/// cap keeps a mistaken path (a log, a disk image) from being read into memory.
pub const MAX_FILE_BYTES: u64 = 16 * 1024 * 1024;

/// The text of an experiment file: a regular file (a symbolic link to one is fine) of at most
/// [`MAX_FILE_BYTES`], in UTF-8.
///
/// What the path is gets checked before it is opened, since opening a FIFO blocks until a writer
/// comes and a device like `/dev/zero` has no end. The size is checked from the metadata and
/// again while reading (through `take`), in case the file grows in between.
pub(super) fn read_experiment_file(path: &Path) -> Result<String, ExperimentError> {
    let read_error = |source| ExperimentError::Read {
        path: path.to_path_buf(),
        source,
    };
    let metadata = fs::metadata(path).map_err(read_error)?;
    if !metadata.is_file() {
        return Err(ExperimentError::NotRegularFile {
            path: path.to_path_buf(),
            kind: file_kind(&metadata.file_type()),
        });
    }
    let too_large = |size| ExperimentError::TooLarge {
        path: path.to_path_buf(),
        size,
        limit: MAX_FILE_BYTES,
    };
    if metadata.len() > MAX_FILE_BYTES {
        return Err(too_large(metadata.len()));
    }
    let file = fs::File::open(path).map_err(read_error)?;
    let mut text = String::new();
    file.take(MAX_FILE_BYTES + 1)
        .read_to_string(&mut text)
        .map_err(read_error)?;
    if text.len() as u64 > MAX_FILE_BYTES {
        return Err(too_large(text.len() as u64));
    }
    Ok(text)
}

/// What a path that is not a regular file is, for the error message.
fn file_kind(file_type: &fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if file_type.is_fifo() {
            return "a FIFO";
        }
        if file_type.is_char_device() {
            return "a character device";
        }
        if file_type.is_block_device() {
            return "a block device";
        }
        if file_type.is_socket() {
            return "a socket";
        }
    }
    if file_type.is_dir() {
        "a directory"
    } else {
        "neither a file nor a directory"
    }
}

/// Sort key of a file stem: tables in numeric order, then figures in numeric order, anything
/// else after them by name.
pub fn table_order(stem: &str) -> (u32, String) {
    let figure = figure_number(stem).map(|n| LAST_TABLE + n);
    (
        table_number(stem).or(figure).unwrap_or(u32::MAX),
        stem.to_owned(),
    )
}

/// `fig-III.<n>` with 1 ≤ n ≤ 6 (the figures of Chapter III) → n, or `fig-IV.<n>` with 1 ≤ n ≤
/// 143 (Chapter IV) → 6 + n, written without leading zeros.
fn figure_number(id: &str) -> Option<u32> {
    let number = |chapter: &str, last: u32| -> Option<u32> {
        let n: u32 = id.strip_prefix(&format!("fig-{chapter}."))?.parse().ok()?;
        (format!("fig-{chapter}.{n}") == id && (1..=last).contains(&n)).then_some(n)
    };
    number("III", LAST_FIGURE_III)
        .or_else(|| number("IV", LAST_FIGURE).map(|n| LAST_FIGURE_III + n))
}

/// Whether `id` names a result of the thesis: a table `IV.<n>` or a figure `fig-IV.<n>`,
/// `fig-III.<n>` ([`table_number`], [`figure_number`]).
pub(super) fn is_thesis_id(id: &str) -> bool {
    table_number(id).is_some() || figure_number(id).is_some()
}

/// Whether `id` is in the thesis's name space (`IV.…`, `fig-…`), where only the thesis's own
/// tables and figures may be named ([`is_thesis_id`]).
fn is_reserved_id(id: &str) -> bool {
    id.starts_with("IV.") || id.starts_with("fig-")
}

/// Longest free id of a scene of the user's own, in characters.
const MAX_OWN_ID_CHARS: usize = 64;

/// Whether `id` can be the free id of a scene of the user's own: ASCII letters, digits, `.`,
/// `-` and `_`, starting with a letter or a digit, at most [`MAX_OWN_ID_CHARS`] long — it
/// names the file and the report's outputs (`data/<id>.csv`, `figures/<id>-….svg`).
fn is_own_id(id: &str) -> bool {
    id.len() <= MAX_OWN_ID_CHARS
        && id.chars().next().is_some_and(|c| c.is_ascii_alphanumeric())
        && id
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '.' | '-' | '_'))
        && !is_reserved_id(id)
}

/// `IV.<n>` with 1 ≤ n ≤ 75, written without leading zeros → n.
fn table_number(id: &str) -> Option<u32> {
    let n: u32 = id.strip_prefix("IV.")?.parse().ok()?;
    (format!("IV.{n}") == id && (1..=LAST_TABLE).contains(&n)).then_some(n)
}

// ---------------------------------------------------------------------------------------------
// toml errors

/// Wrap an error of the `toml` crate with the file name and, where it can be located, the
/// dotted path of the field it is about.
fn toml_error(path: &Path, text: &str, error: &toml::de::Error) -> ExperimentError {
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
const MAX_FIELD_CHARS: usize = 120;
const MAX_LINE_CHARS: usize = 240;

/// `text` cut to about `max` characters, keeping its beginning and end around an ellipsis.
fn shorten(text: &str, max: usize) -> String {
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

// ---------------------------------------------------------------------------------------------
// semantic checks

type Checked = Result<(), ExperimentError>;

/// Semantic validation of one parsed file; `path` is only used in error messages.
struct Check<'p> {
    path: &'p Path,
}

impl Check<'_> {
    fn fail(&self, field: &str, expected: &str, found: impl Found) -> ExperimentError {
        ExperimentError::invalid(self.path, field, expected, found.text())
    }

    fn ensure(&self, ok: bool, field: &str, expected: &str, found: impl Found) -> Checked {
        if ok {
            Ok(())
        } else {
            Err(self.fail(field, expected, found))
        }
    }

    fn finite(&self, field: &str, value: f64) -> Checked {
        self.ensure(value.is_finite(), field, "a finite number", value)
    }

    fn positive(&self, field: &str, value: f64) -> Checked {
        self.ensure(
            value.is_finite() && value > 0.0,
            field,
            "a finite number > 0",
            value,
        )
    }

    fn non_negative(&self, field: &str, value: f64) -> Checked {
        self.ensure(
            value.is_finite() && value >= 0.0,
            field,
            "a finite number ≥ 0",
            value,
        )
    }

    fn finite_all(&self, field: &str, values: &[f64]) -> Checked {
        for (i, &v) in values.iter().enumerate() {
            self.finite(&format!("{field}[{i}]"), v)?;
        }
        Ok(())
    }

    /// One side of the domain, `[lo, hi]`: finite, ordered, and neither so small nor so large
    /// that the cell geometry (Jacobians of order (hi − lo)², distances relative to |lo|, |hi|)
    /// underflows, overflows or drowns in rounding.
    fn domain_extent(&self, field: &str, lo: f64, hi: f64) -> Checked {
        self.finite_all(field, &[lo, hi])?;
        self.ensure(
            lo < hi,
            field,
            "[lo, hi] with lo < hi",
            format!("[{lo:?}, {hi:?}]"),
        )?;
        let width = hi - lo;
        let scale = lo.abs().max(hi.abs());
        self.ensure(
            (MIN_LENGTH..=MAX_LENGTH).contains(&width) && width >= 1e-9 * scale,
            field,
            &format!(
                "an interval of length between {MIN_LENGTH:e} and {MAX_LENGTH:e}, \
                 and at least 1e-9 of its largest coordinate"
            ),
            format!("[{lo:?}, {hi:?}] of length {width:e}"),
        )
    }

    /// A material constant of (I.17): finite, in a range where the stiffness matrix and the
    /// squared energy norms of the estimators stay representable.
    fn material(&self, field: &str, value: f64, zero_allowed: bool) -> Checked {
        let ok = value.is_finite()
            && (value <= MAX_MATERIAL)
            && (value >= MIN_MATERIAL || (zero_allowed && value == 0.0));
        self.ensure(
            ok,
            field,
            &format!(
                "a finite value between {MIN_MATERIAL:e} and {MAX_MATERIAL:e}{} (outside, the \
                 stiffness matrix and the squared norms of the estimate overflow or underflow)",
                if zero_allowed { ", or 0" } else { "" }
            ),
            value,
        )
    }

    fn experiment(&self, spec: &ExperimentFile) -> Checked {
        self.identity(spec)?;
        self.scene(&spec.scene)?;
        if let Some(channel) = &spec.scene.stokes_channel {
            self.stokes_channel(channel, &spec.study)?;
        }
        self.study(&spec.study, &spec.scene)?;
        self.rising_tools(&spec.scene, &spec.study)?;
        self.probes(&spec.probes, &spec.scene)?;
        let figure = figure_number(&spec.table).is_some();
        if !is_thesis_id(&spec.table) {
            return self.ensure(
                spec.thesis.is_none(),
                "thesis",
                "no [thesis] in a scene of your own (an id that is not `IV.<n>` or `fig-…`): \
                 [thesis] holds a table the thesis printed; remove it, and the report shows \
                 tribo's rows alone",
                "a [thesis] table",
            );
        }
        match &spec.thesis {
            Some(thesis) => {
                self.ensure(
                    !figure,
                    "thesis",
                    "no printed table in a figure experiment (`fig-IV.<n>`: the thesis shows \
                     the result as a figure only)",
                    "a [thesis] table",
                )?;
                self.thesis(thesis, &spec.table)
            }
            // A table id without printed rows is refused by `identity`.
            None => Ok(()),
        }
    }

    /// Table id, section and title (Chapter IV numbering).
    fn identity(&self, spec: &ExperimentFile) -> Checked {
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

    /// Text shown on the page and in file names: no control characters (a NUL or BEL would be
    /// copied into `index.html`), except line breaks and tabs where `multiline` (notes, the
    /// only text that can hold them); at most [`MAX_TEXT_CHARS`] characters on one line or
    /// [`MAX_NOTE_CHARS`] in a note.
    fn printable(&self, field: &str, text: &str, multiline: bool) -> Checked {
        let max = if multiline {
            MAX_NOTE_CHARS
        } else {
            MAX_TEXT_CHARS
        };
        let chars = text.chars().count();
        self.ensure(
            chars <= max,
            field,
            &format!("at most {max} characters"),
            format!("{chars} characters"),
        )?;
        let bad = text
            .chars()
            .find(|&c| c.is_control() && !(multiline && (c == '\n' || c == '\t')));
        self.ensure(
            bad.is_none(),
            field,
            "text without control characters",
            format!("the control character {:?}", bad.unwrap_or(' ')),
        )
    }

    fn scene(&self, scene: &SceneFile) -> Checked {
        self.ensure(
            !scene.name.trim().is_empty(),
            "scene.name",
            "a non-empty descriptive name",
            "an empty string",
        )?;
        self.printable("scene.name", &scene.name, false)?;
        for (name, [lo, hi]) in [("x", scene.domain.x), ("y", scene.domain.y)] {
            self.domain_extent(&format!("scene.domain.{name}"), lo, hi)?;
        }
        for (i, &n) in scene.coarse_cells.iter().enumerate() {
            self.ensure(
                n >= 1,
                &format!("scene.coarse_cells[{i}]"),
                "at least 1 cell",
                n,
            )?;
        }
        let [hx, hy] = scene.domain.cell_sides(scene.coarse_cells);
        let aspect = scene.domain.cell_aspect_ratio(scene.coarse_cells);
        self.ensure(
            aspect <= MAX_ASPECT_RATIO,
            "scene.coarse_cells",
            &format!(
                "coarse cells with sides in a ratio of at most {MAX_ASPECT_RATIO:e} \
                 (flatter cells make the stiffness matrix numerically singular)"
            ),
            format!("{hx:e} × {hy:e} cells, ratio {aspect:e}"),
        )?;
        self.ensure(
            scene.global_refinements <= MAX_GLOBAL_REFINEMENTS,
            "scene.global_refinements",
            &format!(
                "at most {MAX_GLOBAL_REFINEMENTS} global refinements (the mesh supports {} \
                 refinement levels; the size of a run is bounded separately)",
                crate::mesh::MAX_LEVEL
            ),
            scene.global_refinements,
        )?;
        self.ensure(
            scene.contact_refinements <= MAX_GLOBAL_REFINEMENTS,
            "scene.contact_refinements",
            &format!(
                "between 0 and {MAX_GLOBAL_REFINEMENTS} refinements at the contact sides (the \
                 thesis uses 3, §IV.2.3)"
            ),
            scene.contact_refinements,
        )?;
        self.ensure(
            scene.contact_refinements == 0 || scene.contact.is_some(),
            "scene.contact_refinements",
            "0 (or left out) in a scene without contact: the refinements are at the sides \
             with an obstacle",
            scene.contact_refinements,
        )?;
        self.effects(scene)?;
        if let Some(elasticity) = &scene.elasticity {
            self.elasticity(elasticity)?;
        }
        if let Some(contact) = &scene.contact {
            self.contact(contact, scene)?;
        }
        if let Some(reynolds) = &scene.reynolds {
            self.reynolds(reynolds, &scene.domain)?;
        }
        if let Some(substokes) = &scene.substokes {
            self.substokes(substokes, &scene.domain)?;
        }
        if let (Some(r), Some(s)) = (&scene.reynolds, &scene.substokes) {
            self.same_film(r, s)?;
        }

        Ok(())
    }

    /// The effect list and the data sections must agree: every effect needs its section, every
    /// section its effect; contact is a boundary condition of elasticity (§IV.2), Reynolds flow
    /// is a separate problem on its own domain (§IV.3).
    fn effects(&self, scene: &SceneFile) -> Checked {
        self.ensure(
            !scene.effects.is_empty(),
            "scene.effects",
            "at least one of `elasticity`, `contact`, `reynolds`, `substokes`",
            "an empty list",
        )?;
        let mut seen = BTreeSet::new();
        for (i, effect) in scene.effects.iter().enumerate() {
            self.ensure(
                seen.insert(*effect),
                &format!("scene.effects[{i}]"),
                "each effect listed once",
                format!("`{}` twice", effect_name(*effect)),
            )?;
        }
        let has = |e| seen.contains(&e);
        self.ensure(
            !has(Effect::Contact) || has(Effect::Elasticity),
            "scene.effects",
            "`elasticity` alongside `contact` (contact constrains an elastic body)",
            "`contact` without `elasticity`",
        )?;
        // Reynolds and SubStokes together are the model-adaptive film (§IV.3.4).
        let film_models = seen.len() == 2 && has(Effect::Reynolds) && has(Effect::SubStokes);
        for fluid in [Effect::Reynolds, Effect::SubStokes, Effect::StokesChannel] {
            self.ensure(
                !has(fluid) || seen.len() == 1 || film_models,
                "scene.effects",
                &format!(
                    "`{}` alone (a thin-film model is a problem of its own; it cannot be \
                     combined with another effect), or `reynolds` with `substokes` (the \
                     model-adaptive film of §IV.3.4)",
                    effect_name(fluid)
                ),
                format!("{:?}", names(&scene.effects)),
            )?;
        }
        let sections = [
            (Effect::Elasticity, scene.elasticity.is_some(), "elasticity"),
            (Effect::Contact, scene.contact.is_some(), "contact"),
            (Effect::Reynolds, scene.reynolds.is_some(), "reynolds"),
            (Effect::SubStokes, scene.substokes.is_some(), "substokes"),
            (
                Effect::StokesChannel,
                scene.stokes_channel.is_some(),
                "stokes_channel",
            ),
        ];
        for (effect, present, name) in sections {
            if has(effect) {
                self.ensure(
                    present,
                    &format!("scene.{name}"),
                    &format!("a [scene.{name}] section because scene.effects lists `{name}`"),
                    "no such section",
                )?;
            } else {
                self.ensure(
                    !present,
                    &format!("scene.{name}"),
                    &format!("no [scene.{name}] section, or `{name}` in scene.effects"),
                    format!("a [scene.{name}] section for an effect that is not listed"),
                )?;
            }
        }
        Ok(())
    }

    /// The typed problem of a checked scene: the effects and their sections (which
    /// [`Check::effects`] has matched) as one variant.
    fn problem(&self, scene: &SceneFile) -> Result<Problem, ExperimentError> {
        let has = |e: Effect| scene.effects.contains(&e);
        let section = |name: &str| {
            self.fail(
                &format!("scene.{name}"),
                &format!("a [scene.{name}] section"),
                "none",
            )
        };
        if has(Effect::Reynolds) && has(Effect::SubStokes) {
            let reynolds = scene.reynolds.clone().ok_or_else(|| section("reynolds"))?;
            let substokes = scene
                .substokes
                .clone()
                .ok_or_else(|| section("substokes"))?;
            return Ok(Problem::FilmModels {
                reynolds,
                substokes,
            });
        }
        if has(Effect::Reynolds) {
            let reynolds = scene.reynolds.clone().ok_or_else(|| section("reynolds"))?;
            return Ok(Problem::Reynolds(reynolds));
        }
        if has(Effect::StokesChannel) {
            let channel = scene
                .stokes_channel
                .clone()
                .ok_or_else(|| section("stokes_channel"))?;
            return Ok(Problem::StokesChannel(channel));
        }
        if has(Effect::SubStokes) {
            let substokes = scene
                .substokes
                .clone()
                .ok_or_else(|| section("substokes"))?;
            return Ok(Problem::SubStokes(substokes));
        }
        let elasticity = scene
            .elasticity
            .clone()
            .ok_or_else(|| section("elasticity"))?;
        if has(Effect::Contact) {
            let contact = scene.contact.clone().ok_or_else(|| section("contact"))?;
            return Ok(Problem::Contact {
                elasticity,
                contact,
            });
        }
        Ok(Problem::Elasticity(elasticity))
    }

    /// Material and loads of (I.17) / (IV.1).
    fn elasticity(&self, data: &ElasticityData) -> Checked {
        const F: &str = "scene.elasticity";
        self.material(&format!("{F}.mu"), data.mu, false)?;
        self.material(&format!("{F}.lambda"), data.lambda, true)?;
        self.ensure(
            data.lambda <= MAX_LAMBDA_OVER_MU * data.mu,
            &format!("{F}.lambda"),
            &format!(
                "λ ≤ {MAX_LAMBDA_OVER_MU:e}·μ (a nearly incompressible material locks the Q₁ \
                 elements and makes the stiffness matrix numerically singular)"
            ),
            format!("λ/μ = {:e}", data.lambda / data.mu),
        )?;
        self.unique_sides(&format!("{F}.dirichlet"), data.dirichlet.iter().copied())?;
        if let Some(load) = &data.volume_load {
            self.finite_all(&format!("{F}.volume_load.direction"), &load.direction)?;
            self.profile(&format!("{F}.volume_load.profile"), &load.profile)?;
        }
        self.unique_sides(
            &format!("{F}.tractions"),
            data.tractions.iter().map(|t| t.side),
        )?;
        for (i, traction) in data.tractions.iter().enumerate() {
            let field = format!("{F}.tractions[{i}]");
            self.ensure(
                !data.dirichlet.contains(&traction.side),
                &format!("{field}.side"),
                "a side that is not in scene.elasticity.dirichlet (Γ_τ and Γ₀ are disjoint)",
                format!("`{}`", side_name(traction.side)),
            )?;
            self.finite_all(&format!("{field}.value"), &traction.value)?;
        }
        Ok(())
    }

    fn profile(&self, field: &str, profile: &Profile) -> Checked {
        match *profile {
            Profile::Constant { amplitude } => {
                self.finite(&format!("{field}.amplitude"), amplitude)
            }
            Profile::Quadratic { amplitude, scale } => {
                self.finite(&format!("{field}.amplitude"), amplitude)?;
                self.positive(&format!("{field}.scale"), scale)
            }
            Profile::Step { amplitude, at } => {
                self.finite(&format!("{field}.amplitude"), amplitude)?;
                self.finite(&format!("{field}.at"), at)
            }
            Profile::Sine {
                amplitude,
                half_period,
            } => {
                self.finite(&format!("{field}.amplitude"), amplitude)?;
                self.positive(&format!("{field}.half_period"), half_period)
            }
        }
    }

    /// Obstacles of §IV.2.1: on the bottom or top face only, one per face, disjoint from Γ₀ and
    /// Γ_τ.
    fn contact(&self, data: &ContactData, scene: &SceneFile) -> Checked {
        const F: &str = "scene.contact.obstacles";
        self.ensure(
            !data.obstacles.is_empty(),
            F,
            "at least one obstacle",
            "an empty list",
        )?;
        self.unique_sides(F, data.obstacles.iter().map(|o| o.side))?;
        let (dirichlet, tractions) = match &scene.elasticity {
            Some(e) => (e.dirichlet.as_slice(), e.tractions.as_slice()),
            None => (&[][..], &[][..]),
        };
        for (i, obstacle) in data.obstacles.iter().enumerate() {
            let field = format!("{F}[{i}]");
            let side = obstacle.side;
            self.ensure(
                matches!(side, Side::Bottom | Side::Top),
                &format!("{field}.side"),
                "`bottom` or `top` (obstacles bound s₂ on a horizontal face)",
                format!("`{}`", side_name(side)),
            )?;
            self.ensure(
                !dirichlet.contains(&side),
                &format!("{field}.side"),
                "a side that is not in scene.elasticity.dirichlet (Γ_C and Γ₀ are disjoint)",
                format!("`{}`", side_name(side)),
            )?;
            self.ensure(
                !tractions.iter().any(|t| t.side == side),
                &format!("{field}.side"),
                "a side without a traction (Γ_τ = ∂Ω \\ (Γ₀ ∪ Γ_C))",
                format!("`{}` also in scene.elasticity.tractions", side_name(side)),
            )?;
            self.obstacle_shape(&format!("{field}.shape"), &obstacle.shape)?;
        }
        if let Some(estimator) = data.estimator {
            self.ensure(
                data.model != ContactModel::ModelAdaptive,
                "scene.contact.estimator",
                "no estimator with model = \"model-adaptive\": the model-adaptive tables keep \
                 their mesh fixed and mark faces by the model error (III.16) alone, and the \
                 model-and-grid-adaptive ones use the term set of the thesis's MGA code",
                format!("{estimator:?}"),
            )?;
        }
        Ok(())
    }

    fn obstacle_shape(&self, field: &str, shape: &ObstacleShape) -> Checked {
        let f = |name: &str| format!("{field}.{name}");
        match *shape {
            ObstacleShape::Constant { level } => self.finite(&f("level"), level),
            ObstacleShape::Periodic {
                offset,
                amplitude,
                periods,
            } => {
                self.finite(&f("offset"), offset)?;
                self.finite(&f("amplitude"), amplitude)?;
                self.finite(&f("periods"), periods)
            }
            ObstacleShape::Jump {
                base,
                height,
                at,
                s,
            } => {
                self.finite(&f("base"), base)?;
                self.finite(&f("height"), height)?;
                self.finite(&f("at"), at)?;
                self.positive(&f("s"), s)
            }
            ObstacleShape::Saw { s, .. } => self.positive(&f("s"), s),
            ObstacleShape::Arc {
                center,
                radius,
                plateau,
                s,
            } => {
                self.finite(&f("center[0]"), center[0])?;
                self.finite(&f("center[1]"), center[1])?;
                self.positive(&f("radius"), radius)?;
                self.finite(&f("plateau"), plateau)?;
                self.positive(&f("s"), s)
            }
        }
    }

    /// The film data shared by the Reynolds and SubStokes sections `F` of §IV.3, (IV.7)–(IV.20):
    /// the gap must stay open (g > 0) on the domain.
    fn film(&self, section: &str, data: Film<'_>, domain: &Rectangle) -> Checked {
        self.ensure(
            !data.equation.trim().is_empty(),
            &format!("{section}.equation"),
            "the thesis equation of the example, e.g. `IV.7`",
            "an empty string",
        )?;
        self.printable(&format!("{section}.equation"), data.equation, false)?;
        let gap = format!("{section}.gap");
        let g = |name: &str| format!("{gap}.{name}");
        match data.gap {
            GapShape::Plain { g0 } => self.positive(&g("g0"), g0)?,
            GapShape::Linear { g0, slope } => {
                self.finite(&g("g0"), g0)?;
                self.finite(&g("slope"), slope)?;
                for x in domain.x {
                    let width = g0 + slope * x;
                    self.ensure(
                        width > 0.0,
                        &gap,
                        "a positive gap g0 + slope·x₁ at both ends of scene.domain.x",
                        format!("g = {width:?} at x₁ = {x:?}"),
                    )?;
                }
            }
            GapShape::WaveHorizontal {
                g0,
                amplitude,
                frequency,
            }
            | GapShape::Hill {
                g0,
                amplitude,
                frequency,
            } => {
                self.finite(&g("g0"), g0)?;
                self.finite(&g("amplitude"), amplitude)?;
                self.finite(&g("frequency"), frequency)?;
                let min = g0 - amplitude.abs();
                self.ensure(
                    min > 0.0,
                    &gap,
                    "a positive gap everywhere, g0 − |amplitude| > 0",
                    format!("g0 − |amplitude| = {min:?}"),
                )?;
            }
        }
        self.finite_all(
            &format!("{section}.upper_wall_velocity"),
            data.upper_wall_velocity,
        )?;
        self.finite(
            &format!("{section}.boundary_pressure"),
            data.boundary_pressure,
        )?;
        self.ensure(
            data.cavitation == Cavitation::Off || data.boundary_pressure >= 0.0,
            &format!("{section}.boundary_pressure"),
            "a pressure ≥ 0 when cavitation is `on` or `auto` (the cavitation problem asks \
             ψ ≥ 0, which a negative boundary value contradicts)",
            data.boundary_pressure,
        )?;
        self.ensure(
            data.cavitation != Cavitation::Off
                || data.cavitation_source == CavitationSource::default(),
            &format!("{section}.cavitation_source"),
            "no cavitation_source when cavitation = \"off\" (it chooses the source term of \
             the cavitation problem only)",
            format!("{:?} with cavitation = \"off\"", data.cavitation_source),
        )?;
        Ok(())
    }

    /// Reynolds data of §IV.3, (IV.7)–(IV.20) ([`Check::film`]).
    fn reynolds(&self, data: &ReynoldsData, domain: &Rectangle) -> Checked {
        const F: &str = "scene.reynolds";
        self.film(
            F,
            Film {
                equation: &data.equation,
                gap: data.gap,
                upper_wall_velocity: &data.upper_wall_velocity,
                boundary_pressure: data.boundary_pressure,
                cavitation: data.cavitation,
                cavitation_source: data.cavitation_source,
            },
            domain,
        )?;
        self.ensure(
            data.zone_residual == ZoneResidual::Full || data.cavitation != Cavitation::Off,
            &format!("{F}.zone_residual"),
            "`full` (or left out) when cavitation = \"off\": there is no cavitation zone",
            format!("{} with cavitation = \"off\"", data.zone_residual.name()),
        )
    }

    /// SubStokes data of §IV.3.2 and §IV.3.6, (IV.7)–(IV.20) ([`Check::film`]), and the
    /// stabilisation constant δ_ε > 0.
    fn substokes(&self, data: &SubStokesData, domain: &Rectangle) -> Checked {
        const F: &str = "scene.substokes";
        self.film(
            F,
            Film {
                equation: &data.equation,
                gap: data.gap,
                upper_wall_velocity: &data.upper_wall_velocity,
                boundary_pressure: data.boundary_pressure,
                cavitation: data.cavitation,
                cavitation_source: data.cavitation_source,
            },
            domain,
        )?;
        self.positive(&format!("{F}.delta_eps"), data.delta_eps)
    }

    /// The two sections of a model-adaptive film describe one film, without cavitation (the
    /// coupling of §IV.3.4 has none).
    fn same_film(&self, r: &ReynoldsData, s: &SubStokesData) -> Checked {
        let pairs = [
            (
                "equation",
                r.equation == s.equation,
                format!("`{}` and `{}`", r.equation, s.equation),
            ),
            (
                "gap",
                r.gap == s.gap,
                format!("{:?} and {:?}", r.gap, s.gap),
            ),
            (
                "upper_wall_velocity",
                r.upper_wall_velocity == s.upper_wall_velocity,
                format!(
                    "{:?} and {:?}",
                    r.upper_wall_velocity, s.upper_wall_velocity
                ),
            ),
            (
                "boundary_pressure",
                r.boundary_pressure == s.boundary_pressure,
                format!("{:?} and {:?}", r.boundary_pressure, s.boundary_pressure),
            ),
        ];
        for (field, same, found) in pairs {
            self.ensure(
                same,
                &format!("scene.substokes.{field}"),
                &format!("the same {field} as scene.reynolds (both models solve one film)"),
                found,
            )?;
        }
        for (section, cavitation) in [("reynolds", r.cavitation), ("substokes", s.cavitation)] {
            self.ensure(
                cavitation == Cavitation::Off,
                &format!("scene.{section}.cavitation"),
                "\"off\" in a model-adaptive film (the coupling of §IV.3.4 has no cavitation)",
                format!("{cavitation:?}"),
            )?;
        }
        Ok(())
    }

    /// The printed cycles and how to iterate: fixed-fraction grid adaptivity (§IV.1: refine
    /// 30 %, coarsen 3 %) or model adaptivity (§IV.2.3: Algorithm III.2 or III.3).
    fn study(&self, study: &Study, scene: &SceneFile) -> Checked {
        self.ensure(study.rows >= 1, "study.rows", "at least 1", study.rows)?;
        self.ensure(
            !is_film_models(scene) || study.kind == StudyKind::ModelAndGridAdaptive,
            "study.kind",
            "\"model-and-grid-adaptive\" for a scene with `reynolds` and `substokes` (the \
             model-adaptive film of §IV.3.4)",
            format!("`{}`", study.kind.name()),
        )?;
        if study.kind == StudyKind::SolverIterations {
            self.ensure(
                study.rows <= MAX_ITERATIONS,
                "study.rows",
                &format!("at most {MAX_ITERATIONS} solver iterations"),
                study.rows,
            )?;
        } else {
            self.ensure(
                study.rows <= MAX_ROWS,
                "study.rows",
                &format!("at most {MAX_ROWS} printed rows"),
                study.rows,
            )?;
        }
        self.ensure(
            study.unprinted_cycles <= MAX_UNPRINTED_CYCLES,
            "study.unprinted_cycles",
            &format!("at most {MAX_UNPRINTED_CYCLES} cycles before the printed rows"),
            study.unprinted_cycles,
        )?;
        self.ensure(
            study.quick_rows >= 1,
            "study.quick_rows",
            "at least 1",
            study.quick_rows,
        )?;
        self.ensure(
            study.quick_rows <= study.rows,
            "study.quick_rows",
            &format!("at most study.rows ({})", study.rows),
            study.quick_rows,
        )?;
        match study.kind {
            StudyKind::GridAdaptive => {
                self.refused(
                    study,
                    "\"model-adaptive\", \"model-and-grid-adaptive\" or \"load-steps\"",
                    &[
                        ("study.algorithm", study.algorithm.is_some()),
                        ("study.model_tolerance", study.model_tolerance.is_some()),
                    ],
                )?;
                self.refused_model_and_grid_fields(study)?;
                let model = scene.contact.as_ref().map(|c| c.model);
                self.ensure(
                    model != Some(ContactModel::ModelAdaptive),
                    "scene.contact.model",
                    "`z` or `signorini` in a grid-adaptive study (model = \"model-adaptive\" \
                     needs study.kind = \"model-adaptive\" or \"model-and-grid-adaptive\")",
                    "`model-adaptive`",
                )?;
                self.grid_marking(study)
            }
            StudyKind::ModelAdaptive => {
                self.refused_model_and_grid_fields(study)?;
                self.fractions(study)?;
                self.model_marking(
                    study,
                    scene,
                    ["study.refine_fraction", "study.coarsen_fraction"],
                )?;
                if let Some([first, last]) = study.convergence_window {
                    return Err(self.fail(
                        "study.convergence_window",
                        "no convergence window in a model-adaptive study (the mesh is fixed: \
                         there is no discretisation error that converges)",
                        format!("[{first}, {last}]"),
                    ));
                }
                Ok(())
            }
            StudyKind::ModelAndGridAdaptive | StudyKind::LoadSteps => {
                for (field, given) in [
                    ("study.model_refine_fraction", study.model_refine_fraction),
                    ("study.model_coarsen_fraction", study.model_coarsen_fraction),
                ] {
                    if given.is_none() {
                        return Err(self.fail(
                            field,
                            "the fraction of the model marking (p_r, p_c of Algorithm III.3; \
                             refine_fraction and coarsen_fraction are the grid's)",
                            "no such field",
                        ));
                    }
                }
                self.model_marking(
                    study,
                    scene,
                    [
                        "study.model_refine_fraction",
                        "study.model_coarsen_fraction",
                    ],
                )?;
                if let Some(alpha) = study.balance {
                    self.ensure(
                        alpha > 0.0 && alpha < 1.0,
                        "study.balance",
                        "α of the balance (III.93) in (0, 1)",
                        alpha,
                    )?;
                }
                if study.kind == StudyKind::LoadSteps {
                    self.grid_fractions(study)?;
                    self.load_steps(study)
                } else {
                    self.refused(study, "\"load-steps\"", &load_step_fields(study))?;
                    self.grid_marking(study)
                }
            }
            StudyKind::SolverIterations => self.solver_iterations(study, scene),
        }
    }

    /// A solver study (Fig. III.6): the Uzawa test problem and none of the adaptive fields.
    fn solver_iterations(&self, study: &Study, scene: &SceneFile) -> Checked {
        self.ensure(
            scene.effects == [Effect::StokesChannel],
            "scene.effects",
            "[\"stokes-channel\"] in a solver-iterations study (the Uzawa test problem (III.88))",
            format!("{:?}", names(&scene.effects)),
        )?;
        self.refused_model_and_grid_fields(study)?;
        let marking = [
            ("study.refine_fraction", study.refine_fraction.is_some()),
            ("study.coarsen_fraction", study.coarsen_fraction.is_some()),
            (
                "study.convergence_window",
                study.convergence_window.is_some(),
            ),
            ("study.algorithm", study.algorithm.is_some()),
            ("study.model_tolerance", study.model_tolerance.is_some()),
            ("study.unprinted_cycles", study.unprinted_cycles > 0),
            ("study.ties", study.ties != Ties::default()),
        ];
        self.refused(study, "the adaptive kinds", &marking)
    }

    /// The Uzawa test problem (III.88): δ_ε > 0 and a list of known, distinct variants.
    fn stokes_channel(&self, data: &StokesChannelData, study: &Study) -> Checked {
        const F: &str = "scene.stokes_channel";
        self.positive(&format!("{F}.delta_eps"), data.delta_eps)?;
        self.ensure(
            !data.variants.is_empty(),
            &format!("{F}.variants"),
            "at least one Uzawa variant",
            "an empty list",
        )?;
        let mut seen = BTreeSet::new();
        for (i, v) in data.variants.iter().enumerate() {
            let field = format!("{F}.variants[{i}]");
            self.ensure(
                Variant::from_name(v).is_some(),
                &field,
                "one of `identity`, `jacobi`, `gauss-seidel`, `ssor`, `cg-ssor`",
                format!("`{}`", v.escape_debug()),
            )?;
            self.ensure(
                seen.insert(v.as_str()),
                &field,
                "each variant once",
                format!("`{v}` twice"),
            )?;
        }
        self.ensure(
            study.kind == StudyKind::SolverIterations,
            "study.kind",
            "\"solver-iterations\" for the Uzawa test problem (it iterates a solver on one mesh)",
            format!("`{}`", study.kind.name()),
        )
    }

    /// `rises` of an obstacle: only the `arc` tools of a load-step study rise (§IV.2.4.7).
    fn rising_tools(&self, scene: &SceneFile, study: &Study) -> Checked {
        let Some(contact) = &scene.contact else {
            return Ok(());
        };
        for (i, obstacle) in contact.obstacles.iter().enumerate() {
            if obstacle.rises.is_none() {
                continue;
            }
            let field = format!("scene.contact.obstacles[{i}].rises");
            self.ensure(
                study.kind == StudyKind::LoadSteps,
                &field,
                "no such field outside a study.kind = \"load-steps\" (tools rise between load \
                 steps)",
                format!("a value in a {} study", study.kind.name()),
            )?;
            self.ensure(
                matches!(obstacle.shape, ObstacleShape::Arc { .. }),
                &field,
                "a tool of kind = \"arc\" (the U-O forming's punch and die; other shapes do \
                 not rise)",
                "another shape",
            )?;
        }
        Ok(())
    }

    /// The load steps of a forming study (§IV.2.4.7): at least one cycle per step, a finite
    /// lift, and no convergence window (every step restarts from the coarse cells).
    fn load_steps(&self, study: &Study) -> Checked {
        let Some(cycles) = study.cycles_per_step else {
            return Err(self.fail(
                "study.cycles_per_step",
                "the cycles of model and grid adaptivity in every load step (4 in §IV.2.4.7)",
                "no such field",
            ));
        };
        self.ensure(
            (1..=MAX_CYCLES_PER_STEP).contains(&cycles),
            "study.cycles_per_step",
            &format!("between 1 and {MAX_CYCLES_PER_STEP} cycles per load step"),
            cycles,
        )?;
        let Some(lift) = study.lift_per_step else {
            return Err(self.fail(
                "study.lift_per_step",
                "how far the rising tools rise in every load step (10/24 in §IV.2.4.7)",
                "no such field",
            ));
        };
        self.finite("study.lift_per_step", lift)?;
        if let Some([first, last]) = study.convergence_window {
            return Err(self.fail(
                "study.convergence_window",
                "no convergence window in a load-step study (every step restarts from the \
                 coarse cells of its body: there is no sequence of meshes that converges)",
                format!("[{first}, {last}]"),
            ));
        }
        Ok(())
    }

    /// The fields of the model-and-grid and the load-step studies, in a study of another kind.
    fn refused_model_and_grid_fields(&self, study: &Study) -> Checked {
        self.refused(
            study,
            "\"model-and-grid-adaptive\" or \"load-steps\"",
            &balance_fields(study),
        )?;
        self.refused(study, "\"load-steps\"", &load_step_fields(study))
    }

    /// Fields a study kind does not have, each given or not; they belong to the kinds `owners`.
    fn refused(&self, study: &Study, owners: &str, fields: &[(&str, bool)]) -> Checked {
        for &(field, given) in fields {
            self.ensure(
                !given,
                field,
                &format!(
                    "no such field in a {} study (it belongs to study.kind = {owners})",
                    study.kind.name()
                ),
                "a value",
            )?;
        }
        Ok(())
    }

    /// Fixed-number grid marking: the fractions and the convergence window.
    fn grid_marking(&self, study: &Study) -> Checked {
        self.grid_fractions(study)?;
        let Some([first, last]) = study.convergence_window else {
            return Err(self.fail(
                "study.convergence_window",
                "[first, last]: the printed cycles where the convergence rule applies",
                "no such field",
            ));
        };
        self.ensure(
            first <= last,
            "study.convergence_window",
            "[first, last] with first ≤ last",
            format!("[{first}, {last}]"),
        )?;
        self.ensure(
            last < study.rows,
            "study.convergence_window[1]",
            &format!(
                "a printed cycle, at most study.rows − 1 ({})",
                study.rows - 1
            ),
            last,
        )
    }

    /// The fractions θ_r, θ_c of fixed-number grid marking.
    fn grid_fractions(&self, study: &Study) -> Checked {
        let (refine, coarsen) = self.fractions(study)?;
        self.non_negative("study.coarsen_fraction", coarsen)?;
        self.positive("study.refine_fraction", refine)?;
        let total = refine + coarsen;
        self.ensure(
            total <= 1.0,
            "study.refine_fraction",
            "refine_fraction + coarsen_fraction ≤ 1",
            format!("{refine:?} + {coarsen:?} = {total:?}"),
        )
    }

    /// `refine_fraction` and `coarsen_fraction`, which every kind but `solver-iterations` needs.
    fn fractions(&self, study: &Study) -> Result<(f64, f64), ExperimentError> {
        let given = |field: &str, v: Option<f64>| {
            v.ok_or_else(|| {
                self.fail(
                    field,
                    &format!("a fraction: a {} study marks with it", study.kind.name()),
                    "no such field",
                )
            })
        };
        Ok((
            given("study.refine_fraction", study.refine_fraction)?,
            given("study.coarsen_fraction", study.coarsen_fraction)?,
        ))
    }

    /// The model marking of a model-adaptive or model-and-grid-adaptive study (§IV.2.3,
    /// §IV.2.4): a contact scene whose faces the marking assigns (`model = "model-adaptive"`),
    /// Algorithm III.2 with p_r, p_c ∈ [0, 1] or III.3 with p_r, p_c ∈ (0, 1) (read from the
    /// two `fraction_fields`), and ε₀ > 0.
    fn model_marking(
        &self,
        study: &Study,
        scene: &SceneFile,
        fraction_fields: [&str; 2],
    ) -> Checked {
        if is_film_models(scene) {
            // The model-adaptive film (§IV.3.4): Algorithm III.3 over the cells.
            self.ensure(
                study.algorithm == Some(ModelAlgorithm::SortedError),
                "study.algorithm",
                "`III.3` (sorted error) for the model-adaptive film (§IV.3.4)",
                format!("{:?}", study.algorithm),
            )?;
            self.ensure(
                study.balance.is_none(),
                "study.balance",
                "no balance in the model-adaptive film (its model and grid markings use their \
                 own indicators, §IV.3.4)",
                "a value",
            )?;
        } else if let Some(contact) = &scene.contact {
            self.ensure(
                contact.model == ContactModel::ModelAdaptive,
                "scene.contact.model",
                "`model-adaptive` in a model-adaptive study (the marking chooses z or Signorini \
                 per face; a fixed model leaves nothing to choose)",
                format!("`{}`", contact.model.name()),
            )?;
        } else {
            return Err(self.fail(
                "study.kind",
                "a scene with contact for a model-adaptive study (it chooses the contact model \
                 face by face, §IV.2.3)",
                format!(
                    "`{}` with scene.effects {:?}",
                    study.kind.name(),
                    names(&scene.effects)
                ),
            ));
        }
        let Some(algorithm) = study.algorithm else {
            return Err(self.fail(
                "study.algorithm",
                "`III.2` (fixed fraction) or `III.3` (sorted error)",
                "no such field",
            ));
        };
        let (p_r, p_c) = study.model_fractions();
        for (field, p) in fraction_fields.into_iter().zip([p_r, p_c]) {
            match algorithm {
                ModelAlgorithm::FixedFraction => self.ensure(
                    (0.0..=1.0).contains(&p),
                    field,
                    "a fraction in [0, 1] for Algorithm III.2",
                    p,
                )?,
                ModelAlgorithm::SortedError => self.ensure(
                    p > 0.0 && p < 1.0,
                    field,
                    "a fraction in (0, 1) for Algorithm III.3",
                    p,
                )?,
            }
        }
        if let Some(eps0) = study.model_tolerance {
            self.positive("study.model_tolerance", eps0)?;
        }
        Ok(())
    }

    /// Probe points inside the domain; components that the scene's effects compute.
    fn probes(&self, probes: &Probes, scene: &SceneFile) -> Checked {
        let Rectangle { x, y } = scene.domain;
        let points = probes.x.len().saturating_mul(probes.y.len());
        self.ensure(
            points <= MAX_PROBE_POINTS,
            "probes",
            &format!("at most {MAX_PROBE_POINTS} probe points (probes.x × probes.y)"),
            format!("{} × {} = {points} points", probes.x.len(), probes.y.len()),
        )?;
        for (name, values, [lo, hi]) in [("x", &probes.x, x), ("y", &probes.y, y)] {
            for (i, &v) in values.iter().enumerate() {
                self.ensure(
                    v.is_finite() && lo <= v && v <= hi,
                    &format!("probes.{name}[{i}]"),
                    &format!("a point of scene.domain.{name} = [{lo}, {hi}]"),
                    v,
                )?;
            }
        }
        let has = |e| scene.effects.contains(&e);
        let allowed: &[&str] = if has(Effect::Elasticity) {
            &["s1", "s2"]
        } else if has(Effect::Reynolds) {
            &["psi"]
        } else if has(Effect::SubStokes) {
            &["chi1", "chi2", "psi"]
        } else {
            &[]
        };
        let expected = if allowed.is_empty() {
            "no components (the scene computes no field)".to_owned()
        } else {
            format!(
                "one of {} (the fields of scene.effects {:?})",
                allowed
                    .iter()
                    .map(|c| format!("`{c}`"))
                    .collect::<Vec<_>>()
                    .join(", "),
                names(&scene.effects)
            )
        };
        let mut seen = BTreeSet::new();
        for (i, component) in probes.components.iter().enumerate() {
            let field = format!("probes.components[{i}]");
            self.ensure(
                allowed.contains(&component.as_str()),
                &field,
                &expected,
                format!("`{component}`"),
            )?;
            self.ensure(
                seen.insert(component.as_str()),
                &field,
                "each component listed once",
                format!("`{component}` twice"),
            )?;
        }
        Ok(())
    }

    /// The printed table: `cycle` first, rectangular, cycles 0, 1, 2, … in order.
    fn thesis(&self, thesis: &ThesisRows, table: &str) -> Checked {
        let columns = &thesis.columns;
        self.ensure(
            columns.first().is_some_and(|c| c == "cycle"),
            "thesis.columns[0]",
            "`cycle`",
            columns
                .first()
                .map_or("an empty list".to_owned(), |c| format!("`{c}`")),
        )?;
        self.ensure(
            columns.len() <= MAX_THESIS_COLUMNS,
            "thesis.columns",
            &format!("at most {MAX_THESIS_COLUMNS} columns"),
            format!("{} columns", columns.len()),
        )?;
        let mut seen = BTreeSet::new();
        for (i, column) in columns.iter().enumerate() {
            self.ensure(
                seen.insert(column.as_str()),
                &format!("thesis.columns[{i}]"),
                "each column named once",
                format!("`{column}` twice"),
            )?;
        }
        self.ensure(
            !thesis.rows.is_empty(),
            "thesis.rows",
            "at least one printed row",
            "an empty list",
        )?;
        self.ensure(
            thesis.rows.len() <= MAX_ROWS,
            "thesis.rows",
            &format!("at most {MAX_ROWS} printed rows (as study.rows)"),
            format!("{} rows", thesis.rows.len()),
        )?;
        for (i, column) in columns.iter().enumerate() {
            self.printable(&format!("thesis.columns[{i}]"), column, false)?;
        }
        for (i, row) in thesis.rows.iter().enumerate() {
            let field = format!("thesis.rows[{i}]");
            self.ensure(
                row.len() == columns.len(),
                &field,
                &format!("{} values, one per thesis.columns entry", columns.len()),
                format!("{} values", row.len()),
            )?;
            self.ensure(
                row[0] == i as f64,
                &format!("{field}[0]"),
                &format!("cycle {i} (cycles are 0, 1, 2, … in order)"),
                row[0],
            )?;
        }
        if let Some(original) = &thesis.duplicate_of {
            self.ensure(
                table_number(original).is_some() && original != table,
                "thesis.duplicate_of",
                "the id of another Chapter IV table, e.g. `IV.13`",
                format!("`{original}`"),
            )?;
        }
        if let Some(part) = &thesis.additive_part {
            self.ensure(
                table_number(&part.table).is_some() && part.table != table,
                "thesis.additive_part.table",
                "the id of another Chapter IV table, e.g. `IV.43`",
                format!("`{}`", part.table),
            )?;
            self.ensure(
                columns.iter().any(|c| c == "estimate"),
                "thesis.additive_part",
                "a table with an `estimate` column",
                "no `estimate` in thesis.columns",
            )?;
            self.ensure(
                part.estimate.len() == thesis.rows.len(),
                "thesis.additive_part.estimate",
                &format!("{} values, one per printed row", thesis.rows.len()),
                format!("{} values", part.estimate.len()),
            )?;
            for (i, v) in part.estimate.iter().enumerate() {
                self.ensure(
                    v.is_finite() && *v >= 0.0,
                    &format!("thesis.additive_part.estimate[{i}]"),
                    "a finite value ≥ 0",
                    *v,
                )?;
            }
        }
        Ok(())
    }

    fn unique_sides(&self, field: &str, sides: impl Iterator<Item = Side>) -> Checked {
        let mut seen = BTreeSet::new();
        for (i, side) in sides.enumerate() {
            self.ensure(
                seen.insert(side),
                &format!("{field}[{i}]"),
                "each side listed once",
                format!("`{}` twice", side_name(side)),
            )?;
        }
        Ok(())
    }
}

/// What a check found, as the error message shows it.
trait Found {
    fn text(self) -> String;
}

/// Numbers as Rust's `Debug` writes them: the shortest text that reads back to the same value,
/// with an exponent for very large or small magnitudes (`1e300`, not 301 digits).
impl Found for f64 {
    fn text(self) -> String {
        format!("{self:?}")
    }
}

impl Found for usize {
    fn text(self) -> String {
        self.to_string()
    }
}

impl Found for String {
    fn text(self) -> String {
        self
    }
}

impl Found for &str {
    fn text(self) -> String {
        self.to_owned()
    }
}

/// Whether the scene is the model-adaptive film: `reynolds` and `substokes` together.
fn is_film_models(scene: &SceneFile) -> bool {
    scene.effects.contains(&Effect::Reynolds) && scene.effects.contains(&Effect::SubStokes)
}

/// The film data of a thin-film section, the same for Reynolds and SubStokes.
struct Film<'a> {
    equation: &'a str,
    gap: GapShape,
    upper_wall_velocity: &'a [f64; 3],
    boundary_pressure: f64,
    cavitation: Cavitation,
    cavitation_source: CavitationSource,
}

fn side_name(side: Side) -> &'static str {
    side.name()
}

fn effect_name(effect: Effect) -> &'static str {
    match effect {
        Effect::Elasticity => "elasticity",
        Effect::Contact => "contact",
        Effect::Reynolds => "reynolds",
        Effect::SubStokes => "substokes",
        Effect::StokesChannel => "stokes-channel",
    }
}

fn names(effects: &[Effect]) -> Vec<&'static str> {
    effects.iter().map(|&e| effect_name(e)).collect()
}

/// The fields only a model-and-grid-adaptive study has, each given or not.
/// The fields of a load-step study, each given or not.
fn load_step_fields(study: &Study) -> [(&'static str, bool); 2] {
    [
        ("study.cycles_per_step", study.cycles_per_step.is_some()),
        ("study.lift_per_step", study.lift_per_step.is_some()),
    ]
}

fn balance_fields(study: &Study) -> [(&'static str, bool); 3] {
    [
        (
            "study.model_refine_fraction",
            study.model_refine_fraction.is_some(),
        ),
        (
            "study.model_coarsen_fraction",
            study.model_coarsen_fraction.is_some(),
        ),
        ("study.balance", study.balance.is_some()),
    ]
}
