//! The scene's parameters as the report shows them: the `[scene]` and `[study]` tables of the
//! experiment file, one line per key, in the file's own words and order, every entry of a list
//! shown.
//!
//! The page states the problem solved from the same text the solver read — domain, mesh, gap or
//! obstacles, velocities, boundary values, loads, material, marking fractions and the estimator
//! reading — so a reader needs neither the file nor the thesis to know what was computed.

use toml::de::{DeTable, DeValue};
use toml::Spanned;

use crate::results::Parameter;

/// A number written with more significant digits than this (`0.4166666666666667`, 10/24) is
/// shown rounded to [`SHOWN_DIGITS`], marked `≈`: the digits beyond are the binary rounding of a
/// fraction, not a choice of the file.
const MAX_WRITTEN_DIGITS: usize = 10;

/// The significant digits of a number rounded for the page.
const SHOWN_DIGITS: usize = 7;

/// The parameters of an experiment file's text: every key of `[scene]` and `[study]` and of
/// their sub-tables (`[scene.substokes]` …), grouped by the table they are in, in the order of
/// the file. Numbers are shown as written (`1.0607e+02` stays so) unless written with more
/// than `MAX_WRITTEN_DIGITS` significant digits, inline tables and arrays on one line, except
/// a list of tables (the obstacles), one entry per line. Text that is not TOML gives no
/// parameters (the loader rejects such a file before this is asked).
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
                value: shown(text, value, true),
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
            let of_tables = items.len() > 1
                && items
                    .iter()
                    .all(|v| matches!(v.get_ref(), DeValue::Table(_)));
            if top && of_tables {
                format!("[\n  {},\n]", parts.join(",\n  "))
            } else {
                format!("[{}]", parts.join(", "))
            }
        }
        DeValue::Float(_) | DeValue::Integer(_) => number(text[value.span()].trim()),
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

/// A number as the file writes it, or rounded to [`SHOWN_DIGITS`] significant digits and
/// marked `≈` when the file writes more than [`MAX_WRITTEN_DIGITS`].
fn number(written: &str) -> String {
    let mantissa = written
        .split(['e', 'E'])
        .next()
        .unwrap_or(written)
        .trim_start_matches(['+', '-']);
    let digits = mantissa
        .chars()
        .filter(char::is_ascii_digit)
        .skip_while(|c| *c == '0')
        .count();
    let value: Option<f64> = written.replace('_', "").parse().ok();
    match value {
        Some(v) if digits > MAX_WRITTEN_DIGITS && v.is_finite() && v != 0.0 => {
            let magnitude = v.abs().log10().floor() as i32;
            let decimals = (SHOWN_DIGITS as i32 - 1 - magnitude).max(0) as usize;
            let rounded = format!("{v:.decimals$}");
            let rounded = if rounded.contains('.') {
                rounded
                    .trim_end_matches('0')
                    .trim_end_matches('.')
                    .to_string()
            } else {
                rounded
            };
            format!("≈{rounded}")
        }
        _ => written.to_string(),
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
    fn every_entry_of_a_list_is_shown() {
        let points: Vec<String> = (0..500).map(|i| format!("[{i}.0, 0.5]")).collect();
        let text = format!("[scene]\npoints = [{}]\n", points.join(", "));
        let p = of_file(&text);
        assert!(p[0].value.ends_with("[499.0, 0.5]]"), "{}", p[0].value);
        assert!(!p[0].value.contains('…'));
        let two =
            "[scene]\nobstacles = [{ side = \"bottom\", b = 1.0 }, { side = \"top\", b = 2.0 }]";
        assert_eq!(
            of_file(two)[0].value,
            "[\n  { side = \"bottom\", b = 1.0 },\n  { side = \"top\", b = 2.0 },\n]"
        );
        assert!(of_file("not = = toml").is_empty());
    }

    #[test]
    fn numbers_with_binary_rounding_digits_are_rounded() {
        let text = "[study]\nlift = 0.4166666666666667\nsmall = 1.0607e+02\n\
                    tol = 1e-7\nn = 12\nthird = [0.3333333333333333, 0.5]\n\
                    big = 123456.78901234567";
        let values: Vec<String> = of_file(text).into_iter().map(|p| p.value).collect();
        assert_eq!(
            values,
            [
                "≈0.4166667",
                "1.0607e+02",
                "1e-7",
                "12",
                "[≈0.3333333, 0.5]",
                "≈123456.8"
            ]
        );
    }
}
