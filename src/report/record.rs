//! Shard records: everything the page needs of one entry, written as JSON beside the page, so
//! that the pages of separate runs (shards, one or a few tables each) can be merged into one.
//!
//! Every `report` run writes `<out>/shard/<table>.json` for each entry of its page: the run
//! (rows, probes, pictures, notes…), the printed thesis table, the alternative readings, or the
//! failure, together with facts of the run that wrote it ([`RunMeta`]). `report merge` reads the
//! records of several output folders ([`read_shards`]) and renders the page, the figures and the
//! data files from them exactly as a single run of all their tables would, also the figures that
//! set a table beside related tables of other shards. Numbers are written so that they read back
//! to the same `f64` (shortest round-trip form); the printed thesis values `inf` and `nan`,
//! which JSON has no numbers for, are written as the strings `"inf"`, `"-inf"` and `"nan"`.

use std::collections::HashMap;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::provenance::Provenance;
use super::{file_stem, Alternative, Failure, ReportMeta};
use crate::experiment::AdditivePart;
use crate::results::RunResult;
use crate::thesis::ThesisTable;

/// The version of the record layout; `report merge` reads only records of this version.
pub const FORMAT: u32 = 1;

/// The folder of the records inside an output folder.
pub const DIR: &str = "shard";

/// Largest record read, in bytes. The mesh pictures make the records of the full tier large
/// (IV.46: 91 MB, nearly all of it the cells of its two mesh pictures); a file beyond 1 GiB is
/// not a record.
pub const MAX_RECORD_BYTES: u64 = 1 << 30;

/// Facts of the run that wrote a record: the header of its page.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunMeta {
    /// `quick` or `full`.
    pub tier: String,
    /// Program and version, e.g. `tribo 0.1.0`.
    pub generated_by: String,
    /// Wall seconds of the whole run.
    pub total_seconds: f64,
    /// Worker threads of the run.
    pub threads: usize,
    pub provenance: Provenance,
}

impl RunMeta {
    /// The facts of a page's header.
    pub fn of(meta: &ReportMeta) -> RunMeta {
        RunMeta {
            tier: meta.tier.clone(),
            generated_by: meta.generated_by.clone(),
            total_seconds: meta.total_seconds,
            threads: meta.threads,
            provenance: meta.provenance.clone(),
        }
    }
}

/// One entry of a page, as `report merge` reads it back.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Record {
    /// [`FORMAT`].
    pub format: u32,
    /// The experiment file's stem (the table id): the entry's place in table order.
    pub stem: String,
    /// The run that wrote the record.
    pub run: RunMeta,
    pub entry: RecordEntry,
}

/// A table that ran, or one that did not (as [`super::Entry`]).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub enum RecordEntry {
    Done {
        run: Box<RunResult>,
        thesis: PrintedTable,
        alternatives: Vec<Alternative>,
    },
    Failed(Failure),
}

/// A printed thesis table ([`ThesisTable`]) whose values are JSON numbers where finite and
/// the words `inf`, `-inf`, `nan` where the thesis prints those.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PrintedTable {
    pub table: String,
    pub section: String,
    pub columns: Vec<String>,
    pub rows: Vec<Vec<Printed>>,
    pub duplicate_of: Option<String>,
    pub additive_part: Option<AdditivePart>,
    /// Whether the run is scored against these rows (an edited thesis experiment and a scene
    /// of one's own are not).
    #[serde(default)]
    pub comparison: crate::experiment::Comparison,
    /// The thesis figures that show the run (none in a record written before they were kept).
    #[serde(default)]
    pub figures: crate::experiment::ThesisFigures,
}

/// One printed value: a finite number, or a word for the others.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Printed {
    Number(f64),
    Word(String),
}

impl Printed {
    fn of(v: f64) -> Printed {
        if v.is_finite() {
            Printed::Number(v)
        } else if v.is_nan() {
            Printed::Word("nan".into())
        } else if v > 0.0 {
            Printed::Word("inf".into())
        } else {
            Printed::Word("-inf".into())
        }
    }

    fn value(&self) -> Result<f64, String> {
        match self {
            Printed::Number(v) => Ok(*v),
            Printed::Word(w) => match w.as_str() {
                "nan" => Ok(f64::NAN),
                "inf" => Ok(f64::INFINITY),
                "-inf" => Ok(f64::NEG_INFINITY),
                _ => Err(format!(
                    "a printed value is \"{w}\"; expected a number, \"inf\", \"-inf\" or \"nan\""
                )),
            },
        }
    }
}

impl PrintedTable {
    pub fn of(t: &ThesisTable) -> PrintedTable {
        PrintedTable {
            table: t.table.clone(),
            section: t.section.clone(),
            columns: t.columns.clone(),
            rows: t
                .rows
                .iter()
                .map(|r| r.iter().map(|&v| Printed::of(v)).collect())
                .collect(),
            duplicate_of: t.duplicate_of.clone(),
            additive_part: t.additive_part.clone(),
            comparison: t.comparison.clone(),
            figures: t.figures.clone(),
        }
    }

    /// The thesis table back; an error names a value that is neither a number nor one of the
    /// three words.
    pub fn thesis(&self) -> Result<ThesisTable, String> {
        Ok(ThesisTable {
            table: self.table.clone(),
            section: self.section.clone(),
            columns: self.columns.clone(),
            rows: self
                .rows
                .iter()
                .map(|r| r.iter().map(Printed::value).collect())
                .collect::<Result<_, _>>()?,
            duplicate_of: self.duplicate_of.clone(),
            additive_part: self.additive_part.clone(),
            comparison: self.comparison.clone(),
            figures: self.figures.clone(),
        })
    }
}

/// Remove the records of an earlier run from `<out>/shard/` (`*.json`): a run's records are
/// those of its page, never an earlier run's, so that merging the folder merges what its page
/// shows. With `keep` (`--shard`, a merge) the folder is made if missing and stays; otherwise a
/// folder left empty is removed, and none is made.
pub fn clear(out: &Path, keep: bool) -> io::Result<()> {
    let dir = out.join(DIR);
    if keep {
        fs::create_dir_all(&dir).map_err(|e| with_path(e, &dir))?;
    } else if !dir.is_dir() {
        return Ok(());
    }
    for entry in fs::read_dir(&dir).map_err(|e| with_path(e, &dir))? {
        let path = entry.map_err(|e| with_path(e, &dir))?.path();
        if path.extension().is_some_and(|e| e == "json") && path.is_file() {
            fs::remove_file(&path).map_err(|e| with_path(e, &path))?;
        }
    }
    if !keep
        && fs::read_dir(&dir)
            .map_err(|e| with_path(e, &dir))?
            .next()
            .is_none()
    {
        fs::remove_dir(&dir).map_err(|e| with_path(e, &dir))?;
    }
    Ok(())
}

fn with_path(e: io::Error, path: &Path) -> io::Error {
    io::Error::new(e.kind(), format!("{}: {e}", path.display()))
}

/// Write `record` to `<out>/shard/<stem>.json` and return the path.
///
/// The text is read back before it is written: a number JSON cannot hold (an infinite or NaN
/// value among the run's data) would not come back as written, and is an error naming the
/// table rather than a record that `report merge` later refuses or misreads.
pub fn write(out: &Path, record: &Record) -> Result<PathBuf, String> {
    let path = out
        .join(DIR)
        .join(format!("{}.json", file_stem(&record.stem)));
    let text = serde_json::to_string(record)
        .map_err(|e| format!("cannot encode the record of {}: {e}", record.stem))?;
    let same = serde_json::from_str::<Record>(&text)
        .ok()
        .and_then(|back| serde_json::to_string(&back).ok())
        .is_some_and(|again| again == text);
    if !same {
        return Err(format!(
            "the record of {} does not read back as written (a number that is infinite or \
             NaN?); {} not written",
            record.stem,
            path.display()
        ));
    }
    crate::fsio::write(&path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    Ok(path)
}

/// Read the records of every output folder in `dirs` (`<dir>/shard/*.json`), in table order.
///
/// Errors: a folder without records, a record that cannot be read or parsed (naming the file and
/// where in it), a record of another format, a table in two folders (naming both files), records
/// of different tiers.
pub fn read_shards(dirs: &[PathBuf]) -> Result<Vec<Record>, String> {
    let mut records: Vec<(PathBuf, Record)> = Vec::new();
    for dir in dirs {
        let shard = dir.join(DIR);
        let listing = fs::read_dir(&shard).map_err(|e| {
            format!(
                "{} has no shard records: cannot list {} ({e}); a `report --shard --out {}` run writes them",
                dir.display(),
                shard.display(),
                dir.display()
            )
        })?;
        let mut paths = Vec::new();
        for entry in listing {
            let path = entry
                .map_err(|e| format!("cannot list {}: {e}", shard.display()))?
                .path();
            if path.extension().is_some_and(|e| e == "json") {
                paths.push(path);
            }
        }
        if paths.is_empty() {
            return Err(format!(
                "{} has no shard records: {} holds no *.json file (run the report with --shard)",
                dir.display(),
                shard.display()
            ));
        }
        paths.sort();
        for path in paths {
            let record = read(&path)?;
            records.push((path, record));
        }
    }
    let mut seen: HashMap<&str, &Path> = HashMap::new();
    for (path, record) in &records {
        if let Some(first) = seen.insert(&record.stem, path) {
            return Err(format!(
                "table {} is in two shards: {} and {}",
                record.stem,
                first.display(),
                path.display()
            ));
        }
    }
    if let Some((first_path, first)) = records.first() {
        if let Some((path, other)) = records.iter().find(|(_, r)| r.run.tier != first.run.tier) {
            return Err(format!(
                "the shards mix tiers: {} is {}, {} is {}",
                first_path.display(),
                first.run.tier,
                path.display(),
                other.run.tier
            ));
        }
    }
    records.sort_by_key(|(_, r)| crate::experiment::table_order(&r.stem));
    Ok(records.into_iter().map(|(_, r)| r).collect())
}

/// One record file: a regular file of at most [`MAX_RECORD_BYTES`] holding a record of this
/// [`FORMAT`] whose printed values read back.
fn read(path: &Path) -> Result<Record, String> {
    let unreadable = |why: String| format!("cannot read the record {}: {why}", path.display());
    let metadata = fs::metadata(path).map_err(|e| unreadable(e.to_string()))?;
    if !metadata.is_file() {
        return Err(unreadable("not a regular file".into()));
    }
    if metadata.len() > MAX_RECORD_BYTES {
        return Err(unreadable(format!(
            "{} bytes, more than the {MAX_RECORD_BYTES} a record may have",
            metadata.len()
        )));
    }
    let text = fs::read_to_string(path).map_err(|e| unreadable(e.to_string()))?;
    // The format first, so that a record of another version is named as such rather than by
    // the first field it lacks.
    #[derive(Deserialize)]
    struct Format {
        format: Option<u32>,
    }
    match serde_json::from_str::<Format>(&text) {
        Ok(Format {
            format: Some(FORMAT),
        }) => {}
        Ok(Format { format: Some(n) }) => {
            return Err(unreadable(format!(
                "format {n}; this tribo reads format {FORMAT} (merge shards written by the same \
                 version)"
            )))
        }
        Ok(Format { format: None }) => {
            return Err(unreadable(format!(
                "no field `format`; expected a record of format {FORMAT}"
            )))
        }
        Err(e) => return Err(unreadable(e.to_string())),
    }
    let record: Record = serde_json::from_str(&text).map_err(|e| unreadable(e.to_string()))?;
    if let RecordEntry::Done { thesis, .. } = &record.entry {
        thesis.thesis().map_err(unreadable)?;
    }
    Ok(record)
}

/// The header of a merged page: the tier of the shards, `generated_by` of the merging program,
/// the wall seconds of the shard runs added up, the most threads any used, their commits and
/// machines (each once), the dates from the first to the last run, and the merge's command line.
pub fn merged_meta(records: &[Record], generated_by: String, command: String) -> ReportMeta {
    let mut runs: Vec<&RunMeta> = Vec::new();
    for r in records {
        if !runs.contains(&&r.run) {
            runs.push(&r.run);
        }
    }
    let mut dates = distinct(&runs, |r| r.provenance.date.as_str());
    dates.sort_unstable();
    let date = match (dates.first(), dates.last()) {
        (Some(a), Some(b)) if a != b => format!("{a} – {b}"),
        (Some(a), _) => a.to_string(),
        _ => "unknown".into(),
    };
    ReportMeta {
        tier: runs.first().map_or("unknown".into(), |r| r.tier.clone()),
        generated_by,
        total_seconds: runs.iter().map(|r| r.total_seconds).sum(),
        threads: runs.iter().map(|r| r.threads).max().unwrap_or(0),
        provenance: Provenance {
            commit: distinct(&runs, |r| r.provenance.commit.as_str()).join(", "),
            date,
            machine: distinct(&runs, |r| r.provenance.machine.as_str()).join("; "),
            command,
        },
        alongside: Default::default(),
    }
}

/// The values `f` gives for `runs`, each once, in the order of the runs.
fn distinct<'a>(runs: &[&'a RunMeta], f: fn(&'a RunMeta) -> &'a str) -> Vec<&'a str> {
    let mut v: Vec<&'a str> = Vec::new();
    for r in runs {
        if !v.contains(&f(r)) {
            v.push(f(r));
        }
    }
    v
}
