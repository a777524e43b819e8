//! The scene's parameters as the report shows them: the `[scene]` and `[study]` tables of the
//! experiment file, one line per key, in the file's own words and order.
//!
//! The page states the problem solved from the same text the solver read — domain, mesh, gap or
//! obstacles, velocities, boundary values, loads, material, marking fractions and the estimator
//! reading — so a reader needs neither the file nor the thesis to know what was computed.

use toml::de::{DeTable, DeValue};
use toml::Spanned;

use crate::results::Parameter;

/// A value longer than this many characters (a long list of points) is shortened on the page,
/// with its number of entries.
const MAX_VALUE_CHARS: usize = 160;

/// The parameters of an experiment file's text: every key of `[scene]` and `[study]` and of
/// their sub-tables (`[scene.substokes]` …), grouped by the table they are in, in the order of
/// the file. Numbers are shown as written (`1.0607e+02` stays so), inline tables and arrays on
/// one line. Text that is not TOML gives no parameters (the loader rejects such a file before
/// this is asked).
pub fn of_file(text: &str) -> Vec<Parameter> {
    let Ok(document) = DeTable::parse(text) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for group in ["scene", "study"] {
        let table = document
            .get_ref()
            .iter()
            .find(|(k, _)| k.get_ref() == group);
        if let Some((_, value)) = table {
            if let DeValue::Table(table) = value.get_ref() {
                flatten(text, group, table, &mut out);
            }
        }
    }
    out
}

/// The entries of `table` in file order.
fn in_file_order<'a, 'i>(
    table: &'a DeTable<'i>,
) -> Vec<(
    &'a Spanned<std::borrow::Cow<'i, str>>,
    &'a Spanned<DeValue<'i>>,
)> {
    let mut entries: Vec<_> = table.iter().collect();
    entries.sort_by_key(|(key, _)| key.span().start);
    entries
}

/// The keys of `table` under `group`: its values first, then each `[group.key]` sub-table as a
/// group of its own, as a reader meets them in the file.
fn flatten(text: &str, group: &str, table: &DeTable<'_>, out: &mut Vec<Parameter>) {
    let entries = in_file_order(table);
    let is_section = |value: &Spanned<DeValue<'_>>| {
        matches!(value.get_ref(), DeValue::Table(_))
            && !text[value.span()].trim_start().starts_with('{')
    };
    for (key, value) in &entries {
        if !is_section(value) {
            out.push(Parameter {
                group: group.to_string(),
                key: key.get_ref().to_string(),
                value: shorten(value, shown(text, value, true)),
            });
        }
    }
    for (key, value) in &entries {
        if let (true, DeValue::Table(sub)) = (is_section(value), value.get_ref()) {
            flatten(text, &format!("{group}.{}", key.get_ref()), sub, out);
        }
    }
}

/// The value on one line: a top-level string without quotes, nested strings quoted, numbers
/// and booleans as the file writes them.
fn shown(text: &str, value: &Spanned<DeValue<'_>>, top: bool) -> String {
    match value.get_ref() {
        DeValue::String(s) if top => s.to_string(),
        DeValue::String(s) => format!("\"{s}\""),
        DeValue::Array(items) => {
            let parts: Vec<String> = items.iter().map(|v| shown(text, v, false)).collect();
            format!("[{}]", parts.join(", "))
        }
        DeValue::Table(table) => {
            let parts: Vec<String> = in_file_order(table)
                .into_iter()
                .map(|(k, v)| format!("{} = {}", k.get_ref(), shown(text, v, false)))
                .collect();
            format!("{{ {} }}", parts.join(", "))
        }
        _ => text[value.span()].trim().to_string(),
    }
}

/// `shown` cut at [`MAX_VALUE_CHARS`], with the number of entries of a long list.
fn shorten(value: &Spanned<DeValue<'_>>, shown: String) -> String {
    if shown.chars().count() <= MAX_VALUE_CHARS {
        return shown;
    }
    let head: String = shown.chars().take(MAX_VALUE_CHARS).collect();
    match value.get_ref() {
        DeValue::Array(items) => format!("{head} … ({} entries)", items.len()),
        _ => format!("{head} …"),
    }
}

#[cfg(test)]
mod tests {
    use super::of_file;

    #[test]
    fn scene_and_study_keys_in_file_order_with_sub_tables_as_groups() {
        let text = r#"
table = "x"
notes = ["not a parameter"]
[scene]
name = "plain"
domain = { x = [0.0, 1.0], y = [0.0, 1.0] }
g0 = 1.0607e+02
effects = ["substokes"]
[scene.substokes]
gap = { kind = "plain", g0 = 0.1 }
boundary_pressure = 200.0
[study]
refine_fraction = 0.3
[thesis]
rows = [[0, 1]]
"#;
        let p = of_file(text);
        let lines: Vec<String> = p
            .iter()
            .map(|p| format!("{}|{}|{}", p.group, p.key, p.value))
            .collect();
        assert_eq!(
            lines,
            [
                "scene|name|plain",
                "scene|domain|{ x = [0.0, 1.0], y = [0.0, 1.0] }",
                "scene|g0|1.0607e+02",
                "scene|effects|[\"substokes\"]",
                "scene.substokes|gap|{ kind = \"plain\", g0 = 0.1 }",
                "scene.substokes|boundary_pressure|200.0",
                "study|refine_fraction|0.3",
            ]
        );
    }

    #[test]
    fn long_lists_are_shortened_with_their_length() {
        let points: Vec<String> = (0..500).map(|i| format!("[{i}.0, 0.5]")).collect();
        let text = format!("[scene]\npoints = [{}]\n", points.join(", "));
        let p = of_file(&text);
        assert!(p[0].value.ends_with("… (500 entries)"), "{}", p[0].value);
        assert!(p[0].value.chars().count() < 200);
        assert!(of_file("not = = toml").is_empty());
    }
}
