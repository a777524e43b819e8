//! Fingerprints of the shipped thesis experiments: whether a loaded `IV.<n>` or `fig-…` file
//! still describes what the thesis printed.
//!
//! Every shipped thesis experiment (`experiments/IV.<n>.toml`, `experiments/fig-….toml`) has, in
//! `printed.lock` (compiled into the binary), one line per field of its `[scene]`, `[study]` and
//! `[thesis]`: the table id, the dotted field path and a 64-bit FNV-1a hash of the field's value
//! in canonical form. The canonical form is that of the parsed TOML value — a number is its
//! `f64` (so `1`, `1.0` and `1e0` are one value), a table is sorted by key — so whitespace,
//! comments, the order of keys, `notes`, `title`, `probes` and `related` do not count. A file
//! whose fields differ from its lines is *edited*: the report runs it but does not score it
//! against the thesis ([`super::Comparison::Edited`]).
//!
//! The lock is written by the test `shipped_experiments_match_their_fingerprints`
//! (`TRIBO_UPDATE_PRINTED=1 cargo test --release --test tribo shipped_experiments`), on purpose
//! only: a change to a shipped scene is a change to what tribo claims the thesis computed.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;
use std::sync::OnceLock;

use toml::{Table, Value};

use super::error::ExperimentError;
use super::load::{experiment_entries, is_thesis_id, read_experiment_file};

/// The fingerprints of the shipped thesis experiments, one `id field hash` line per field.
pub const PRINTED_LOCK: &str = include_str!("printed.lock");

/// The sections of an experiment file that make up what the thesis computed.
const FINGERPRINTED: [&str; 3] = ["scene", "study", "thesis"];

/// Fields that change how a table is computed, or what runs beside it, not what it computes:
/// setting them does not make a thesis experiment "edited".
const NOT_FINGERPRINTED: [&str; 2] = ["study.solver", "study.alternatives"];

/// Field path → hash of every fingerprinted field of one file.
type Fields = BTreeMap<String, String>;

/// The fingerprints of one parsed experiment file: its `[scene]`, `[study]` and `[thesis]`
/// flattened to dotted field paths (tables are entered, arrays of tables too, as `name[i]`;
/// any other value is one field), each with the hash of its canonical form.
fn fields(file: &Table) -> Fields {
    let mut out = Fields::new();
    for section in FINGERPRINTED {
        if let Some(value) = file.get(section) {
            flatten(section, value, &mut out);
        }
    }
    for field in NOT_FINGERPRINTED {
        out.remove(field);
    }
    out
}

fn flatten(path: &str, value: &Value, out: &mut Fields) {
    match value {
        Value::Table(table) => {
            for (key, value) in table {
                flatten(&format!("{path}.{key}"), value, out);
            }
        }
        Value::Array(items) if !items.is_empty() && items.iter().all(Value::is_table) => {
            for (i, item) in items.iter().enumerate() {
                flatten(&format!("{path}[{i}]"), item, out);
            }
        }
        leaf => {
            let mut text = String::new();
            canonical(leaf, &mut text);
            out.insert(path.to_owned(), format!("{:016x}", fnv1a(text.as_bytes())));
        }
    }
}

/// The canonical text of a TOML value: numbers as their `f64`, strings quoted, tables sorted
/// by key.
fn canonical(value: &Value, out: &mut String) {
    match value {
        Value::String(s) => {
            let _ = write!(out, "{s:?}");
        }
        Value::Integer(i) => {
            let _ = write!(out, "{:?}", *i as f64);
        }
        Value::Float(f) => {
            let _ = write!(out, "{:?}", if f.is_nan() { f64::NAN } else { *f });
        }
        Value::Boolean(b) => {
            let _ = write!(out, "{b}");
        }
        Value::Datetime(d) => {
            let _ = write!(out, "d{d}");
        }
        Value::Array(items) => {
            out.push('[');
            for item in items {
                canonical(item, out);
                out.push(',');
            }
            out.push(']');
        }
        Value::Table(table) => {
            let sorted: BTreeMap<&String, &Value> = table.iter().collect();
            out.push('{');
            for (key, value) in sorted {
                let _ = write!(out, "{key:?}=");
                canonical(value, out);
                out.push(',');
            }
            out.push('}');
        }
    }
}

/// 64-bit FNV-1a: a hash whose value is fixed by its definition (std's hasher may change
/// between Rust releases, and the lock must not).
fn fnv1a(bytes: &[u8]) -> u64 {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        hash ^= u64::from(b);
        hash = hash.wrapping_mul(0x0100_0000_01b3);
    }
    hash
}

/// The lock, parsed once: table id → its fields.
fn lock() -> &'static BTreeMap<String, Fields> {
    static LOCK: OnceLock<BTreeMap<String, Fields>> = OnceLock::new();
    LOCK.get_or_init(|| {
        let mut lock: BTreeMap<String, Fields> = BTreeMap::new();
        for line in PRINTED_LOCK.lines() {
            let mut parts = line.split_whitespace();
            if let (Some(id), Some(field), Some(hash)) = (parts.next(), parts.next(), parts.next())
            {
                if !id.starts_with('#') {
                    lock.entry(id.to_owned())
                        .or_default()
                        .insert(field.to_owned(), hash.to_owned());
                }
            }
        }
        lock
    })
}

/// Whether the text of the thesis experiment `id` still describes the printed table (or
/// figure): `None` if it does, else the dotted paths of the fields that differ from the shipped
/// file's (changed, added or left out), in order. An empty list means the differences cannot
/// be named: `id` has no fingerprint (tribo ships no experiment with that id) or the text is no
/// TOML table.
pub(crate) fn edited_fields(id: &str, text: &str) -> Option<Vec<String>> {
    let Some(printed) = lock().get(id) else {
        return Some(Vec::new());
    };
    let Ok(file) = toml::from_str::<Table>(text) else {
        return Some(Vec::new());
    };
    let here = fields(&file);
    let differing: Vec<String> = printed
        .keys()
        .chain(here.keys())
        .filter(|field| printed.get(*field) != here.get(*field))
        .cloned()
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .collect();
    (!differing.is_empty()).then_some(differing)
}

/// The text of `printed.lock` for the thesis experiments (`IV.<n>`, `fig-…`) in `dir`, in table
/// order: what [`PRINTED_LOCK`] must be when the shipped files are the printed ones. Files of
/// other ids are left out; a file that cannot be read or parsed is an error naming it.
pub fn fingerprints(dir: &Path) -> Result<String, ExperimentError> {
    let mut out = String::from(
        "# Fingerprints of the shipped thesis experiments: table id, field, FNV-1a hash of the\n\
         # field's canonical value. Written by the test shipped_experiments_match_their_fingerprints\n\
         # with TRIBO_UPDATE_PRINTED=1; do not edit by hand.\n",
    );
    for (stem, path) in experiment_entries(dir)? {
        if !is_thesis_id(&stem) {
            continue;
        }
        let text = read_experiment_file(&path)?;
        let file: Table = toml::from_str(&text).map_err(|e| ExperimentError::Toml {
            path: path.clone(),
            field: None,
            line: None,
            message: e.to_string(),
        })?;
        for (field, hash) in fields(&file) {
            let _ = writeln!(out, "{stem} {field} {hash}");
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn of(text: &str) -> Fields {
        fields(&toml::from_str::<Table>(text).unwrap())
    }

    #[test]
    fn numbers_key_order_and_comments_do_not_count() {
        let a = of("[scene]\nname = \"x\"\nmu = 1\n[study]\nrows = 3\n");
        let b = of("# c\n[study]\nrows = 3.0 # three\n[scene]\nmu = 1e0\nname = \"x\"\n");
        assert_eq!(a, b);
        assert_eq!(
            a.keys().collect::<Vec<_>>(),
            ["scene.mu", "scene.name", "study.rows"]
        );
    }

    #[test]
    fn notes_title_and_probes_are_not_fingerprinted() {
        let a = of("title = \"a\"\nnotes = [\"n\"]\n[probes]\nx = [1]\n[scene]\nmu = 1\n");
        assert_eq!(a.keys().collect::<Vec<_>>(), ["scene.mu"]);
    }

    #[test]
    fn arrays_of_tables_are_entered() {
        let a = of("[[scene.obstacles]]\nside = \"bottom\"\n[[scene.obstacles]]\nside = \"top\"\n");
        assert_eq!(
            a.keys().collect::<Vec<_>>(),
            ["scene.obstacles[0].side", "scene.obstacles[1].side"]
        );
    }

    #[test]
    fn fnv1a_is_the_published_function() {
        // Test vectors of the FNV reference: "" and "a".
        assert_eq!(fnv1a(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
    }
}
