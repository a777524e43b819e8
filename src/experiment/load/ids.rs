//! The ids of experiments: the thesis's tables `IV.<n>` and figures `fig-IV.<n>`,
//! `fig-III.<n>`, the free ids of scenes of the user's own, and their order in the report.

/// Highest table number of Chapter IV (Table IV.75).
pub(super) const LAST_TABLE: u32 = 75;
/// The last figure of Chapter IV (Fig. IV.143).
pub(super) const LAST_FIGURE: u32 = 143;
/// Figures of Chapter III (the Uzawa comparison is Fig. III.6).
pub(super) const LAST_FIGURE_III: u32 = 6;

/// Sort key of a file stem or the id of a run of a sweep ([`table_order`]).
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct TableOrder {
    number: u32,
    file: String,
    run: Vec<RunValue>,
}

/// A value in a run's id, `-10` of `step-bearing~-10`: numbers sort by value, before words.
#[derive(Clone, Debug)]
enum RunValue {
    Number(f64),
    Word(String),
}

impl Ord for RunValue {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        use RunValue::*;
        match (self, other) {
            (Number(a), Number(b)) => a.total_cmp(b),
            (Number(_), Word(_)) => std::cmp::Ordering::Less,
            (Word(_), Number(_)) => std::cmp::Ordering::Greater,
            (Word(a), Word(b)) => a.cmp(b),
        }
    }
}

impl PartialOrd for RunValue {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl PartialEq for RunValue {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == std::cmp::Ordering::Equal
    }
}

impl Eq for RunValue {}

/// Sort key of a file stem: tables in numeric order, then figures in numeric order, anything
/// else after them by name; the runs of a sweep (`step-bearing~-10`) after their file's name,
/// by their values (−80 before −10, 0.05 before 0.1).
pub fn table_order(stem: &str) -> TableOrder {
    let (file, values) = match stem.split_once('~') {
        Some((file, values)) => (file, Some(values)),
        None => (stem, None),
    };
    let figure = figure_number(file).map(|n| LAST_TABLE + n);
    TableOrder {
        number: table_number(file).or(figure).unwrap_or(u32::MAX),
        file: file.to_owned(),
        run: values
            .into_iter()
            .flat_map(|v| v.split('~'))
            .map(|v| {
                v.parse()
                    .map_or_else(|_| RunValue::Word(v.to_owned()), RunValue::Number)
            })
            .collect(),
    }
}

/// `fig-III.<n>` with 1 ≤ n ≤ 6 (the figures of Chapter III) → n, or `fig-IV.<n>` with 1 ≤ n ≤
/// 143 (Chapter IV) → 6 + n, written without leading zeros.
pub(super) fn figure_number(id: &str) -> Option<u32> {
    let number = |chapter: &str, last: u32| -> Option<u32> {
        let n: u32 = id.strip_prefix(&format!("fig-{chapter}."))?.parse().ok()?;
        (format!("fig-{chapter}.{n}") == id && (1..=last).contains(&n)).then_some(n)
    };
    number("III", LAST_FIGURE_III)
        .or_else(|| number("IV", LAST_FIGURE).map(|n| LAST_FIGURE_III + n))
}

/// Whether `id` names a result of the thesis: a table `IV.<n>` or a figure `fig-IV.<n>`,
/// `fig-III.<n>` ([`table_number`], [`figure_number`]).
pub(in crate::experiment) fn is_thesis_id(id: &str) -> bool {
    table_number(id).is_some() || figure_number(id).is_some()
}

/// Whether `id` is in the thesis's name space (`IV.…`, `fig-…`), where only the thesis's own
/// tables and figures may be named ([`is_thesis_id`]).
fn is_reserved_id(id: &str) -> bool {
    id.starts_with("IV.") || id.starts_with("fig-")
}

/// Longest free id of a scene of the user's own, in characters.
pub(super) const MAX_OWN_ID_CHARS: usize = 64;

/// Whether `id` can be the free id of a scene of the user's own: ASCII letters, digits, `.`,
/// `-` and `_`, starting with a letter or a digit, at most [`MAX_OWN_ID_CHARS`] long — it
/// names the file and the report's outputs (`data/<id>.csv`, `figures/<id>-….svg`).
pub(super) fn is_own_id(id: &str) -> bool {
    id.len() <= MAX_OWN_ID_CHARS
        && id.chars().next().is_some_and(|c| c.is_ascii_alphanumeric())
        && id
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '.' | '-' | '_'))
        && !is_reserved_id(id)
}

/// `IV.<n>` with 1 ≤ n ≤ 75, written without leading zeros → n.
pub(super) fn table_number(id: &str) -> Option<u32> {
    let n: u32 = id.strip_prefix("IV.")?.parse().ok()?;
    (format!("IV.{n}") == id && (1..=LAST_TABLE).contains(&n)).then_some(n)
}
