//! `[sweep]` and `report --set`: one experiment file expanded into one run per combination of
//! the values of one or two of its fields ([`crate::experiment::sweep`]).
//!
//! The expansion works on the file's text. Each run's text is the file with the swept values
//! written in place of the fields' own (located by toml's parse of the file, which keeps where
//! every value stands), so each run is then loaded and checked exactly as a file of its own: a
//! value of the wrong type or out of range is named with the file, the field and the line, and
//! the run's page states the problem solved with the swept value. Checked here, before any run
//! is made, is what only the sweep can get wrong — a thesis file, no field or more than
//! [`MAX_SWEEP_FIELDS`], a field the file does not write or that is not one value, fewer than
//! two values or one twice, more than [`MAX_SWEEP_RUNS`] runs, quantities the scene does not
//! compute — each an error of the file that names the sweep's field.
//!
//! The runs' ids are the file's id with each run's values (`step-bearing~-10`,
//! `step-bearing~0.05~-40`): `~` is in no id of a file, so a run's id can clash with no other
//! table's, and the report's outputs of a run never match another run's (`remove_outputs`).

use std::ops::Range;
use std::path::Path;

use toml::de::{DeTable, DeValue};
use toml::{Table, Value};

use super::check::Check;
use super::{load_text, Loaded};
use crate::experiment::sweep::{SweepRun, SweptField, MAX_SWEEP_FIELDS, MAX_SWEEP_RUNS};
use crate::experiment::{Comparison, Experiment, ExperimentError};
use crate::study::quantities;

/// One field to sweep with its values: a line of a file's `[sweep]`, or a `report --set`.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepField {
    /// The dotted path of the field, `scene.reynolds.upper_wall_velocity`.
    pub path: String,
    pub values: Vec<Value>,
}

/// Separates a sweep's id from the values of a run in the run's id.
pub const RUN_SEPARATOR: char = '~';

/// Most quantities one comparison shows (a panel each).
const MAX_QUANTITIES: usize = 6;

/// The longest number written into a run's id; a longer one (`0.000001234`) makes the runs of
/// its field numbered instead.
const MAX_TOKEN_CHARS: usize = 12;

/// `report --set FIELD=V1,V2,…`: the field and its values. The values are split at the commas
/// outside brackets, braces and quotes (`[-10,0,0],[-20,0,0]` is two values), each a TOML value;
/// a bare word (`on`) is taken for the string it spells, since a shell eats the quotes.
pub fn parse_set(arg: &str) -> Result<SweepField, String> {
    let usage = "FIELD=V1,V2,…, e.g. scene.reynolds.upper_wall_velocity=[-10,0,0],[-20,0,0]";
    let Some((path, values)) = arg.split_once('=') else {
        return Err(format!("`{arg}` has no `=`: expected {usage}"));
    };
    let path = path.trim();
    if path.is_empty() || path.chars().any(char::is_whitespace) {
        return Err(format!(
            "`{arg}`: expected a dotted field path before `=`, {usage}"
        ));
    }
    let values = split_top_level(values)
        .into_iter()
        .map(|piece| parse_value(piece.trim()))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| format!("--set {path}: {e}"))?;
    Ok(SweepField {
        path: path.to_string(),
        values,
    })
}

/// `text` split at the commas outside `[…]`, `{…}` and quotes.
fn split_top_level(text: &str) -> Vec<&str> {
    let (mut depth, mut quote, mut escaped) = (0i32, None::<char>, false);
    let (mut pieces, mut start) = (Vec::new(), 0);
    for (i, c) in text.char_indices() {
        match quote {
            Some(q) => {
                if escaped {
                    escaped = false;
                } else if c == '\\' && q == '"' {
                    escaped = true;
                } else if c == q {
                    quote = None;
                }
            }
            None => match c {
                '"' | '\'' => quote = Some(c),
                '[' | '{' => depth += 1,
                ']' | '}' => depth -= 1,
                ',' if depth == 0 => {
                    pieces.push(&text[start..i]);
                    start = i + 1;
                }
                _ => {}
            },
        }
    }
    pieces.push(&text[start..]);
    pieces
}

/// One value of `--set`: TOML, or a bare word for the string it spells.
fn parse_value(piece: &str) -> Result<Value, String> {
    if piece.is_empty() {
        return Err("an empty value (two commas in a row, or one at an end?)".into());
    }
    match format!("v = {piece}").parse::<Table>() {
        Ok(mut table) => Ok(table.remove("v").expect("the key just parsed")),
        Err(_) if is_bare_word(piece) => Ok(Value::String(piece.to_string())),
        Err(e) => Err(format!(
            "`{piece}` is not a TOML value (a number, a word or a quoted string, an array such \
             as [-10.0, 0.0, 0.0], an inline table): {}",
            e.message()
        )),
    }
}

fn is_bare_word(piece: &str) -> bool {
    piece
        .chars()
        .all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_'))
        && piece.starts_with(|c: char| c.is_ascii_alphabetic())
}

/// What a file is asked to sweep: its `[sweep]`, or the command line's fields (which replace
/// the file's; its `quantities` stay).
struct Request {
    fields: Vec<SweepField>,
    quantities: Option<Vec<String>>,
    from_command_line: bool,
}

/// The runs of the file at `path` (file stem `stem`, text `text`): `None` where it is not swept
/// (no `[sweep]`, no `--set`), else one entry per run, or one failed entry of the file when the
/// file or its sweep does not hold.
pub(super) fn runs(path: &Path, stem: &str, text: &str, set: &[SweepField]) -> Option<Vec<Loaded>> {
    let document: Option<Table> = text.parse().ok();
    let in_file = document.as_ref().and_then(|d| d.get("sweep")).cloned();
    if in_file.is_none() && set.is_empty() {
        return None;
    }
    let failed = |error| Some(vec![(stem.to_string(), Err(error))]);
    // The file as written: a sweep varies a scene that holds (and, loaded, is known to be a
    // table of its own).
    let base = match load_text(path, text) {
        Ok(base) => base,
        Err(error) => return failed(error),
    };
    let check = Check { path };
    let request = match request(&check, in_file, set).map(|r| in_file_order(r, text)) {
        Ok(request) => request,
        Err(error) => return failed(error),
    };
    let sweep = match Sweep::checked(&check, &base, text, request) {
        Ok(sweep) => sweep,
        Err(error) => return failed(error),
    };
    Some(sweep.runs(path, text, base))
}

/// Whether the text has a `[sweep]`: such a file makes several runs and is loaded by
/// [`super::load_each`], not [`super::load`].
pub(super) fn is_swept(text: &str) -> bool {
    text.parse::<Table>()
        .is_ok_and(|document| document.contains_key("sweep"))
}

/// The file's id of a run id (`step-bearing~-10` → `step-bearing`), if it is one.
pub(super) fn file_of_run(id: &str) -> Option<&str> {
    id.split_once(RUN_SEPARATOR).map(|(file, _)| file)
}

/// The request of the file's `[sweep]` (a table whose keys are dotted field paths — quoted,
/// or written as nested keys — each with a list of values, and an optional `quantities`) and
/// the command line's fields.
fn request(
    check: &Check,
    in_file: Option<Value>,
    set: &[SweepField],
) -> Result<Request, ExperimentError> {
    let mut fields = Vec::new();
    let mut quantities = None;
    if let Some(sweep) = in_file {
        let Value::Table(table) = sweep else {
            return Err(check.fail(
                "sweep",
                "a table [sweep] of fields, each with its values",
                format!("a {}", sweep.type_str()),
            ));
        };
        for (key, value) in table {
            if key == "quantities" {
                quantities = Some(quantity_names(check, value)?);
            } else {
                collect_fields(check, &key, value, &mut fields)?;
            }
        }
    }
    if !set.is_empty() {
        fields = set.to_vec();
    }
    Ok(Request {
        fields,
        quantities,
        from_command_line: !set.is_empty(),
    })
}

/// The request with its fields in the order the file writes them (toml's tables are sorted by
/// key): the first is the one whose values are outermost, and the plots' axis.
fn in_file_order(mut request: Request, text: &str) -> Request {
    let Ok(document) = DeTable::parse(text) else {
        return request;
    };
    if request.from_command_line {
        return request;
    }
    let mut starts: Vec<(String, usize)> = Vec::new();
    if let Some((_, sweep)) = document
        .get_ref()
        .iter()
        .find(|(k, _)| k.get_ref() == "sweep")
    {
        if let DeValue::Table(table) = sweep.get_ref() {
            key_starts(table, "", &mut starts);
        }
    }
    let start = |path: &str| {
        starts
            .iter()
            .find(|(p, _)| p == path)
            .map_or(usize::MAX, |(_, s)| *s)
    };
    request.fields.sort_by_key(|f| start(&f.path));
    request
}

/// Where each key path of `table` (below `prefix`) starts in the text.
fn key_starts(table: &DeTable, prefix: &str, out: &mut Vec<(String, usize)>) {
    for (key, value) in table.iter() {
        let path = if prefix.is_empty() {
            key.get_ref().to_string()
        } else {
            format!("{prefix}.{}", key.get_ref())
        };
        out.push((path.clone(), key.span().start));
        if let DeValue::Table(inner) = value.get_ref() {
            key_starts(inner, &path, out);
        }
    }
}

/// The fields under the `[sweep]` key `path`: a list of values is a field, a table holds more
/// (`scene.reynolds.x = […]` written without quotes is nested tables in TOML).
fn collect_fields(
    check: &Check,
    path: &str,
    value: Value,
    fields: &mut Vec<SweepField>,
) -> Result<(), ExperimentError> {
    match value {
        Value::Array(values) => {
            fields.push(SweepField {
                path: path.to_string(),
                values,
            });
            Ok(())
        }
        Value::Table(table) => {
            for (key, value) in table {
                collect_fields(check, &format!("{path}.{key}"), value, fields)?;
            }
            Ok(())
        }
        other => Err(check.fail(
            &format!("sweep.\"{path}\""),
            "a list of the values to run, e.g. [0.1, 0.2] or [[-10.0, 0.0, 0.0], [-20.0, 0.0, 0.0]]",
            format!("a single {} `{other}`", other.type_str()),
        )),
    }
}

/// `quantities` of `[sweep]`: a list of column names.
fn quantity_names(check: &Check, value: Value) -> Result<Vec<String>, ExperimentError> {
    let expected = "a list of quantity names, e.g. [\"load_capacity\", \"max_pressure\"]";
    let Value::Array(items) = value else {
        return Err(check.fail("sweep.quantities", expected, value.type_str()));
    };
    items
        .into_iter()
        .enumerate()
        .map(|(i, item)| match item {
            Value::String(name) => Ok(name),
            other => Err(check.fail(
                &format!("sweep.quantities[{i}]"),
                expected,
                format!("`{other}`"),
            )),
        })
        .collect()
}

/// A checked sweep of one file: its fields with where each stands in the text, and the
/// quantities compared.
struct Sweep {
    fields: Vec<Located>,
    quantities: Vec<String>,
    from_command_line: bool,
}

/// A swept field: its values and the bytes of the file's text that hold its own value.
struct Located {
    field: SweepField,
    span: Range<usize>,
    /// The values as inline TOML.
    texts: Vec<String>,
    /// Each value's part of a run's id.
    tokens: Vec<String>,
}

impl Sweep {
    /// Check `request` against the file (text `text`, loaded as written into `base`).
    fn checked(
        check: &Check,
        base: &Experiment,
        text: &str,
        request: Request,
    ) -> Result<Sweep, ExperimentError> {
        let source = |path: &str| {
            if request.from_command_line {
                format!("--set {path}")
            } else {
                format!("sweep.\"{path}\"")
            }
        };
        let whole = if request.from_command_line {
            "--set"
        } else {
            "sweep"
        };
        if !matches!(base.comparison, Comparison::OwnScene) {
            return Err(check.fail(
                whole,
                &format!(
                    "a scene of your own: `{id}` is the thesis's, whose runs are compared with \
                     the printed table; copy the file under an id of your own (e.g. \
                     `my-{id}.toml` with table = \"my-{id}\", without [thesis]) and sweep the \
                     copy",
                    id = base.table
                ),
                "a sweep of a thesis experiment",
            ));
        }
        let paths: Vec<&str> = request.fields.iter().map(|f| f.path.as_str()).collect();
        check.ensure(
            !paths.is_empty(),
            whole,
            "one or two fields, each with the values to run, e.g. \
             \"scene.reynolds.upper_wall_velocity\" = [[-10.0, 0.0, 0.0], [-20.0, 0.0, 0.0]]",
            "no field",
        )?;
        check.ensure(
            paths.len() <= MAX_SWEEP_FIELDS,
            whole,
            &format!(
                "at most {MAX_SWEEP_FIELDS} fields (every combination of their values is a run)"
            ),
            format!("{} fields: {}", paths.len(), paths.join(", ")),
        )?;
        if let [a, b] = paths[..] {
            let holds = |outer: &str, inner: &str| inner.starts_with(&format!("{outer}."));
            check.ensure(
                a != b && !holds(a, b) && !holds(b, a),
                &source(b),
                "two different fields, neither inside the other",
                format!("`{a}` and `{b}`"),
            )?;
        }
        let document = DeTable::parse(text)
            .map_err(|e| check.fail(whole, "a file that parses", e.message().to_string()))?;
        let mut fields = Vec::new();
        for field in request.fields {
            let name = source(&field.path);
            let span = value_span(check, &name, document.get_ref(), &field.path)?;
            fields.push(Located::checked(check, &name, text, field, span)?);
        }
        let runs: usize = fields.iter().map(|f| f.texts.len()).product();
        check.ensure(
            runs <= MAX_SWEEP_RUNS,
            whole,
            &format!(
                "at most {MAX_SWEEP_RUNS} runs (the product of the fields' numbers of values)"
            ),
            format!(
                "{} = {runs} runs",
                fields
                    .iter()
                    .map(|f| f.texts.len().to_string())
                    .collect::<Vec<_>>()
                    .join(" × ")
            ),
        )?;
        let quantities = compared_quantities(check, base, request.quantities)?;
        Ok(Sweep {
            fields,
            quantities,
            from_command_line: request.from_command_line,
        })
    }

    /// One entry per combination of values, the first field's outermost: the file's text with
    /// the combination in place, loaded and checked as a file, under the run's id.
    fn runs(self, path: &Path, text: &str, base: Experiment) -> Vec<Loaded> {
        let combinations = self.combinations();
        let ids: Vec<String> = combinations
            .iter()
            .map(|at| {
                let tokens: Vec<&str> = self
                    .fields
                    .iter()
                    .zip(at)
                    .map(|(f, &v)| f.tokens[v].as_str())
                    .collect();
                format!("{}{RUN_SEPARATOR}{}", base.table, tokens.join("~"))
            })
            .collect();
        let swept: Vec<SweptField> = self.fields.iter().map(Located::swept).collect();
        combinations
            .iter()
            .enumerate()
            .map(|(index, at)| {
                let sweep = SweepRun {
                    sweep: base.table.clone(),
                    fields: swept.clone(),
                    runs: ids.clone(),
                    index,
                    quantities: self.quantities.clone(),
                    from_command_line: self.from_command_line,
                };
                let outcome = load_text(path, &self.text_of(text, at))
                    .map(|mut run| {
                        run.table = ids[index].clone();
                        run.title = format!("{} — {}", base.title, sweep.label());
                        run.sweep = Some(sweep.clone());
                        run
                    })
                    .map_err(|source| ExperimentError::InSweepRun {
                        run: ids[index].clone(),
                        values: self.assignments(at),
                        source: Box::new(source),
                    });
                (ids[index].clone(), outcome)
            })
            .collect()
    }

    /// The value indices of every run, the first field's outermost.
    fn combinations(&self) -> Vec<Vec<usize>> {
        self.fields.iter().fold(vec![Vec::new()], |runs, field| {
            runs.into_iter()
                .flat_map(|run| {
                    (0..field.texts.len()).map(move |v| {
                        let mut run = run.clone();
                        run.push(v);
                        run
                    })
                })
                .collect()
        })
    }

    /// The file's text with the values `at` in place of the fields' own.
    fn text_of(&self, text: &str, at: &[usize]) -> String {
        let mut edits: Vec<(&Range<usize>, &str)> = self
            .fields
            .iter()
            .zip(at)
            .map(|(f, &v)| (&f.span, f.texts[v].as_str()))
            .collect();
        edits.sort_by_key(|(span, _)| std::cmp::Reverse(span.start));
        let mut out = text.to_string();
        for (span, value) in edits {
            out.replace_range(span.clone(), value);
        }
        out
    }

    /// `path = value` of each field of the run `at`, for messages.
    fn assignments(&self, at: &[usize]) -> String {
        self.fields
            .iter()
            .zip(at)
            .map(|(f, &v)| format!("{} = {}", f.field.path, f.texts[v]))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

impl Located {
    /// The field `field` (named `name` in messages), whose own value is `text[span]`: at least
    /// two values, each once, each one piece of TOML that can stand in the value's place.
    fn checked(
        check: &Check,
        name: &str,
        text: &str,
        field: SweepField,
        span: Range<usize>,
    ) -> Result<Located, ExperimentError> {
        let n = field.values.len();
        check.ensure(
            n >= 2,
            name,
            if n == 0 {
                "at least two values (an empty list runs nothing)"
            } else {
                "at least two values (with one value, write it in the field itself)"
            },
            format!("{n} value{}", if n == 1 { "" } else { "s" }),
        )?;
        for j in 1..n {
            if let Some(i) = (0..j).find(|&i| same(&field.values[i], &field.values[j])) {
                return Err(check.fail(
                    name,
                    "each value once",
                    format!("`{}` at [{i}] and [{j}]", field.values[j]),
                ));
            }
        }
        let texts: Vec<String> = field.values.iter().map(Value::to_string).collect();
        // The first value in place must read back as itself: the field's value is written in
        // one piece (not a [table] or a list of [[tables]], whose parts stand apart).
        let mut first = text.to_string();
        first.replace_range(span.clone(), &texts[0]);
        let read_back = first
            .parse::<Table>()
            .ok()
            .and_then(|document| value_at(&document, &field.path).map(Value::to_string));
        check.ensure(
            read_back.as_deref() == Some(texts[0].as_str()),
            name,
            "a field written as one value in the file (`key = value`, an array or an inline \
             table), not a [table] or a list of [[tables]]",
            format!("`{}` written in parts", field.path),
        )?;
        let (numbers, _) = numbers_of(&field.values);
        let tokens = tokens(&field.values, numbers.as_deref());
        Ok(Located {
            field,
            span,
            texts,
            tokens,
        })
    }

    /// What the runs carry of the field.
    fn swept(&self) -> SweptField {
        let (numbers, component) = numbers_of(&self.field.values);
        SweptField {
            path: self.field.path.clone(),
            values: self.texts.clone(),
            numbers,
            component,
        }
    }
}

/// Where the value of the dotted field `path` stands in the file (`name` in messages): a field
/// of `[scene]` or `[study]` that the file writes.
fn value_span(
    check: &Check,
    name: &str,
    document: &DeTable,
    path: &str,
) -> Result<Range<usize>, ExperimentError> {
    check.ensure(
        path.starts_with("scene.") || path.starts_with("study."),
        name,
        "a field of [scene] or [study], e.g. `scene.reynolds.upper_wall_velocity`",
        format!("`{path}`"),
    )?;
    let mut table = document;
    let mut segments = path.split('.').peekable();
    while let Some(segment) = segments.next() {
        let entry = table.iter().find(|(key, _)| key.get_ref() == segment);
        let Some((_, value)) = entry else {
            return Err(check.fail(
                name,
                "a field that this file writes (to sweep an optional field, write it with one \
                 value first)",
                format!("`{path}`, which is not in the file"),
            ));
        };
        if segments.peek().is_none() {
            return Ok(value.span());
        }
        match value.get_ref() {
            DeValue::Table(inner) => table = inner,
            _ => {
                return Err(check.fail(
                    name,
                    "a field of the file's tables",
                    format!("`{path}`, below the value `{segment}`"),
                ))
            }
        }
    }
    Err(check.fail(name, "a dotted field path", "an empty path"))
}

/// The value at the dotted `path` of a parsed document.
fn value_at<'a>(document: &'a Table, path: &str) -> Option<&'a Value> {
    let mut segments = path.split('.');
    let mut value = document.get(segments.next()?)?;
    for segment in segments {
        value = value.as_table()?.get(segment)?;
    }
    Some(value)
}

/// Whether two values are one: numbers by value (`1` and `1.0`), arrays item by item, the rest
/// as TOML writes them.
fn same(a: &Value, b: &Value) -> bool {
    match (number(a), number(b)) {
        (Some(x), Some(y)) => x == y,
        _ => match (a, b) {
            (Value::Array(a), Value::Array(b)) => {
                a.len() == b.len() && a.iter().zip(b).all(|(x, y)| same(x, y))
            }
            _ => a.to_string() == b.to_string(),
        },
    }
}

fn number(v: &Value) -> Option<f64> {
    match v {
        Value::Integer(n) => Some(*n as f64),
        Value::Float(x) => Some(*x),
        _ => None,
    }
}

/// The number each value stands for on a plot axis, and which component of array values that
/// is ([`SweptField::numbers`]).
fn numbers_of(values: &[Value]) -> (Option<Vec<f64>>, Option<usize>) {
    if let Some(numbers) = values.iter().map(number).collect::<Option<Vec<f64>>>() {
        return (Some(numbers), None);
    }
    let arrays: Option<Vec<Vec<f64>>> = values
        .iter()
        .map(|v| v.as_array()?.iter().map(number).collect())
        .collect();
    let Some(arrays) = arrays else {
        return (None, None);
    };
    let len = arrays[0].len();
    if arrays.iter().any(|a| a.len() != len) {
        return (None, None);
    }
    let varying: Vec<usize> = (0..len)
        .filter(|&k| arrays.iter().any(|a| a[k] != arrays[0][k]))
        .collect();
    match varying[..] {
        [k] => (Some(arrays.iter().map(|a| a[k]).collect()), Some(k)),
        _ => (None, None),
    }
}

/// Each value's part of a run id: the number it stands for (`-10`, `0.05`), a word as it is
/// (other characters as `_`), `true`/`false`; the value's place (1, 2, …) where one of them is
/// none of these, too long, or two parts would be the same.
fn tokens(values: &[Value], numbers: Option<&[f64]>) -> Vec<String> {
    let by_value: Option<Vec<String>> = values
        .iter()
        .enumerate()
        .map(|(i, v)| match (numbers, v) {
            (Some(numbers), _) => Some(format!("{}", numbers[i])),
            (None, Value::String(s)) => Some(
                s.chars()
                    .map(|c| {
                        if c.is_ascii_alphanumeric() || c == '-' {
                            c
                        } else {
                            '_'
                        }
                    })
                    .collect(),
            ),
            (None, Value::Boolean(b)) => Some(b.to_string()),
            _ => None,
        })
        .map(|t| t.filter(|t: &String| !t.is_empty() && t.len() <= MAX_TOKEN_CHARS))
        .collect();
    let distinct = |tokens: &Vec<String>| {
        let mut sorted = tokens.clone();
        sorted.sort();
        sorted.dedup();
        sorted.len() == tokens.len()
    };
    match by_value {
        Some(tokens) if distinct(&tokens) => tokens,
        _ => (1..=values.len()).map(|i| i.to_string()).collect(),
    }
}

/// The quantities the comparison shows: those `[sweep] quantities` names — each a quantity the
/// scene's family computes, each once, at most [`MAX_QUANTITIES`] — or else the family's among
/// [`quantities::COMPARED`].
fn compared_quantities(
    check: &Check,
    base: &Experiment,
    named: Option<Vec<String>>,
) -> Result<Vec<String>, ExperimentError> {
    let facts = base.family.facts();
    let computed = |q: &str| {
        facts.quantities.contains(&q)
            || (quantities::is_side_force(q) && facts.quantities.contains(&"contact_force"))
    };
    let Some(named) = named else {
        return Ok(quantities::COMPARED
            .iter()
            .filter(|q| computed(q))
            .map(|q| q.to_string())
            .collect());
    };
    check.ensure(
        named.len() <= MAX_QUANTITIES,
        "sweep.quantities",
        &format!("at most {MAX_QUANTITIES} quantities"),
        named.len(),
    )?;
    let known = if facts.quantities.is_empty() {
        format!(
            "none: a {} scene computes no engineering quantities",
            facts.id
        )
    } else {
        facts.quantities.join(", ")
    };
    for (i, q) in named.iter().enumerate() {
        check.ensure(
            computed(q),
            &format!("sweep.quantities[{i}]"),
            &format!("a quantity of a {} scene ({known})", facts.id),
            format!("`{q}`"),
        )?;
        check.ensure(
            !named[..i].contains(q),
            &format!("sweep.quantities[{i}]"),
            "each quantity once",
            format!("`{q}` twice"),
        )?;
    }
    Ok(named)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_splits_at_top_level_commas_only() {
        let f = parse_set("scene.reynolds.upper_wall_velocity=[-10,0,0],[-20, 0, 0]").unwrap();
        assert_eq!(f.path, "scene.reynolds.upper_wall_velocity");
        assert_eq!(f.values.len(), 2);
        assert_eq!(f.values[1].to_string(), "[-20, 0, 0]");
        let g =
            parse_set("scene.reynolds.gap={ kind = \"plain\", g0 = 0.1 },{kind=\"plain\",g0=0.2}")
                .unwrap();
        assert_eq!(g.values.len(), 2);
        let words = parse_set("scene.reynolds.cavitation=on,\"off\"").unwrap();
        assert_eq!(words.values, [Value::from("on"), Value::from("off")]);
        assert!(parse_set("scene.x").unwrap_err().contains("no `="));
        assert!(parse_set("scene.x=1,,2")
            .unwrap_err()
            .contains("empty value"));
        assert!(parse_set("scene.x=[1,2")
            .unwrap_err()
            .contains("not a TOML value"));
    }

    #[test]
    fn tokens_are_the_varying_numbers_or_the_places() {
        let values: Vec<Value> = ["[-10.0, 0.0, 0.0]", "[-20.5, 0.0, 0.0]"]
            .iter()
            .map(|v| parse_value(v).unwrap())
            .collect();
        let (numbers, component) = numbers_of(&values);
        assert_eq!(component, Some(0));
        assert_eq!(tokens(&values, numbers.as_deref()), ["-10", "-20.5"]);
        let both: Vec<Value> = ["[1.0, 2.0]", "[2.0, 1.0]"]
            .iter()
            .map(|v| parse_value(v).unwrap())
            .collect();
        assert_eq!(numbers_of(&both), (None, None));
        assert_eq!(tokens(&both, None), ["1", "2"]);
        let words = [Value::from("a.b"), Value::from("a_b")];
        assert_eq!(tokens(&words, None), ["1", "2"], "a_b twice: numbered");
        assert!(same(&Value::Integer(1), &Value::Float(1.0)));
    }
}
