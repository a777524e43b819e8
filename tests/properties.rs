//! Property test of the loader: mutations of the shipped experiment files — numbers scaled by
//! extreme factors or replaced by NaN and infinities, lists lengthened and shortened, keys
//! dropped, values of the wrong type — never panic, and each mutated file either loads or fails
//! with a message that names the file and a field.

use std::fs;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use proptest::prelude::*;
use toml::{Table, Value};

use tribo::experiment::load;

/// The shipped experiment files, parsed: (file name, document).
fn shipped() -> &'static [(String, Table)] {
    static FILES: OnceLock<Vec<(String, Table)>> = OnceLock::new();
    FILES.get_or_init(|| {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments");
        let mut files: Vec<(String, Table)> = fs::read_dir(&dir)
            .expect("experiments/")
            .map(|e| e.expect("entry").path())
            .filter(|p| p.extension().is_some_and(|e| e == "toml"))
            .map(|p| {
                let text = fs::read_to_string(&p).expect("readable");
                let name = p.file_name().expect("name").to_string_lossy().into_owned();
                (name, text.parse::<Table>().expect("shipped files parse"))
            })
            .collect();
        files.sort_by(|a, b| a.0.cmp(&b.0));
        files
    })
}

/// One change to a document.
#[derive(Clone, Debug)]
enum Mutation {
    /// Multiply a number (integers saturate) or replace it by a non-finite value.
    Scale(f64),
    /// Repeat the last element of a list.
    Lengthen,
    /// Drop the last element of a list.
    Shorten,
    /// Remove a key of a table.
    Drop,
    /// Replace a value by a string.
    Retype,
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let factors = prop_oneof![
        Just(0.0),
        Just(-1.0),
        Just(1e-300),
        Just(1e300),
        Just(1e9),
        Just(-1e9),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(f64::NAN),
        -4.0..4.0f64,
    ];
    prop_oneof![
        3 => factors.prop_map(Mutation::Scale),
        1 => Just(Mutation::Lengthen),
        1 => Just(Mutation::Shorten),
        1 => Just(Mutation::Drop),
        1 => Just(Mutation::Retype),
    ]
}

/// Apply `mutation` to the `target`-th value (modulo their number) of `doc` that it applies to.
/// Returns a description of the change, or `None` if no value of the document fits.
fn apply(doc: &mut Table, mutation: &Mutation, target: usize) -> Option<String> {
    let mut paths = Vec::new();
    collect(&Value::Table(doc.clone()), String::new(), &mut paths);
    let fits: Vec<&(String, Value)> = paths
        .iter()
        .filter(|(path, v)| match mutation {
            Mutation::Scale(_) => matches!(v, Value::Integer(_) | Value::Float(_)),
            Mutation::Lengthen | Mutation::Shorten => {
                matches!(v, Value::Array(a) if !a.is_empty())
            }
            Mutation::Drop => !path.ends_with(']') && !path.is_empty(),
            Mutation::Retype => !path.is_empty(),
        })
        .collect();
    if fits.is_empty() {
        return None;
    }
    let (path, _) = fits[target % fits.len()];
    let mut root = Value::Table(doc.clone());
    change(&mut root, &steps(path), mutation);
    if let Value::Table(t) = root {
        *doc = t;
    }
    Some(format!("{mutation:?} at `{path}`"))
}

/// Every (dotted path, value) of a document.
fn collect(value: &Value, path: String, out: &mut Vec<(String, Value)>) {
    out.push((path.clone(), value.clone()));
    match value {
        Value::Table(t) => {
            for (k, v) in t {
                let p = if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                };
                collect(v, p, out);
            }
        }
        Value::Array(a) => {
            for (i, v) in a.iter().enumerate() {
                collect(v, format!("{path}[{i}]"), out);
            }
        }
        _ => {}
    }
}

/// A path as steps: keys and list indices.
enum Step {
    Key(String),
    Index(usize),
}

fn steps(path: &str) -> Vec<Step> {
    let mut out = Vec::new();
    for part in path.split('.') {
        let (key, rest) = part.split_once('[').map_or((part, ""), |(k, r)| (k, r));
        out.push(Step::Key(key.to_owned()));
        for index in rest.split('[').filter(|s| !s.is_empty()) {
            out.push(Step::Index(
                index.trim_end_matches(']').parse().expect("index"),
            ));
        }
    }
    out
}

fn change(value: &mut Value, steps: &[Step], mutation: &Mutation) {
    if steps.len() == 1 {
        if let (Mutation::Drop, Value::Table(t), Step::Key(k)) = (mutation, &mut *value, &steps[0])
        {
            t.remove(k);
            return;
        }
    }
    match steps.split_first() {
        Some((Step::Key(k), rest)) => {
            if let Some(v) = value.as_table_mut().and_then(|t| t.get_mut(k)) {
                change(v, rest, mutation);
            }
        }
        Some((Step::Index(i), rest)) => {
            if let Some(v) = value.as_array_mut().and_then(|a| a.get_mut(*i)) {
                change(v, rest, mutation);
            }
        }
        None => mutate(value, mutation),
    }
}

fn mutate(value: &mut Value, mutation: &Mutation) {
    match (mutation, &mut *value) {
        (Mutation::Scale(f), Value::Integer(n)) if f.is_finite() => {
            *n = (*n as f64 * f).clamp(i64::MIN as f64, i64::MAX as f64) as i64;
        }
        (Mutation::Scale(f), Value::Integer(_)) => *value = Value::Float(*f),
        (Mutation::Scale(f), Value::Float(x)) => *x = if f.is_finite() { *x * f } else { *f },
        (Mutation::Lengthen, Value::Array(a)) => {
            let last = a.last().cloned();
            a.extend(last);
        }
        (Mutation::Shorten, Value::Array(a)) => {
            a.pop();
        }
        (Mutation::Retype, v) => *v = Value::String("mutated".into()),
        _ => {}
    }
}

/// The fixed-length lists of the format and their lengths.
const FIXED_LENGTH: [(&str, usize); 5] = [
    ("scene.coarse_cells", 2),
    ("scene.domain.x", 2),
    ("scene.domain.y", 2),
    ("scene.reynolds.upper_wall_velocity", 3),
    ("study.convergence_window", 2),
];

fn scratch(case: u64) -> PathBuf {
    crate::common::scratch(&format!("properties-{case}"))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1000, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn mutated_experiment_files_load_or_name_a_field(
        file in 0..64usize,
        mutations in proptest::collection::vec((mutation(), any::<usize>()), 1..4),
        case in any::<u64>(),
    ) {
        let files = shipped();
        let (name, original) = &files[file % files.len()];
        let mut doc = original.clone();
        let mut applied = Vec::new();
        for (m, target) in &mutations {
            if let Some(description) = apply(&mut doc, m, *target) {
                applied.push(description);
            }
        }
        let text = toml::to_string(&doc).expect("a table serialises");
        let dir = scratch(case);
        let path = dir.join(name);
        fs::write(&path, &text).expect("write");
        let outcome = std::panic::catch_unwind(|| load(&path));
        let _ = fs::remove_dir_all(&dir);
        let outcome = match outcome {
            Ok(outcome) => outcome,
            Err(_) => panic!("{name}: the loader panicked after {applied:?}"),
        };
        match outcome {
            Err(error) => {
                let message = error.to_string();
                prop_assert!(message.contains(&path.display().to_string()), "{name} {applied:?}: {message}");
                prop_assert!(error.field().is_some(), "{name} {applied:?}: no field in: {message}");
            }
            // A file that loads was read whole: no fixed-length list lost a value on the way.
            Ok(_) => {
                for (field, n) in FIXED_LENGTH {
                    let mut values = Vec::new();
                    collect(&Value::Table(doc.clone()), String::new(), &mut values);
                    if let Some((_, Value::Array(a))) = values.iter().find(|(p, _)| p == field) {
                        prop_assert_eq!(a.len(), n, "{} {:?}: `{}` loaded with {} values", name, applied, field, a.len());
                    }
                }
            }
        }
    }
}
