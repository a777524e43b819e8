//! Errors of the experiment loader: every message names the file, the field and what was
//! expected, so a user can fix the file without reading the source.

use std::io;
use std::path::{Path, PathBuf};

use thiserror::Error;

/// Why an experiment file (or directory of files) could not be used.
///
/// Every variant carries the file (or directory) path; the field-level variants also carry the
/// dotted field path (`study.rows`, `scene.elasticity.dirichlet[1]`) and what was expected.
#[derive(Debug, Error)]
pub enum ExperimentError {
    /// The file could not be read: missing, unreadable, or not UTF-8.
    #[error("{}: cannot read the experiment file: {source}", path.display())]
    Read {
        path: PathBuf,
        #[source]
        source: io::Error,
    },

    /// The path is not a regular file: a directory, a FIFO, a device, a socket, or a symbolic link
    /// to one of them. Such a path is never opened: opening a FIFO blocks until a writer comes,
    /// and a device such as `/dev/zero` never ends.
    #[error(
        "{}: not a regular file ({kind}); an experiment file must be a regular TOML file",
        path.display()
    )]
    NotRegularFile {
        path: PathBuf,
        /// What the path is instead, e.g. `a FIFO` or `a character device`.
        kind: &'static str,
    },

    /// The file is larger than any experiment file needs to be; it is not read into memory.
    #[error(
        "{}: the file has {size} bytes, more than the {limit} bytes an experiment file may have",
        path.display()
    )]
    TooLarge {
        path: PathBuf,
        /// Bytes found (at least `limit + 1` when the file grew while it was read).
        size: u64,
        limit: u64,
    },

    /// The experiment directory could not be listed.
    #[error(
        "{}: cannot list the experiment directory{}: {source} (choose it with --experiments DIR)",
        dir.display(),
        relative_to_cwd(dir)
    )]
    ReadDir {
        dir: PathBuf,
        #[source]
        source: io::Error,
    },

    /// The `toml` crate rejected the file: a syntax error, a value of the wrong type, a missing
    /// or an unknown field. `message` is toml's own report (it names the key and shows the line).
    #[error("{}: {}{message}", path.display(), field_prefix(field.as_deref()))]
    Toml {
        path: PathBuf,
        /// Dotted path of the offending field, when it could be located.
        field: Option<String>,
        /// 1-based line of the error, when toml reports a position.
        line: Option<usize>,
        message: String,
    },

    /// The file parsed, but a field is out of range or contradicts another field or the setting
    /// of the thesis (Chapter IV).
    #[error("{}: field `{field}`: expected {expected}, found {found}", path.display())]
    Invalid {
        path: PathBuf,
        field: String,
        expected: String,
        found: String,
    },

    /// A run of a sweep ([`crate::experiment::sweep`]) whose file, with the run's values in
    /// place, does not load: the error of that text, with the run and its values.
    #[error("{}", in_sweep_run(run, values, source))]
    InSweepRun {
        /// The run's id, `step-bearing~-10`.
        run: String,
        /// `path = value` of each swept field.
        values: String,
        #[source]
        source: Box<ExperimentError>,
    },

    /// `report --set` over experiments of the thesis, which are compared with printed tables and
    /// are not swept.
    #[error(
        "{}: --set sweeps scenes of your own, and the run selects thesis experiments ({}); choose \
         your own files with --only ID or --experiments DIR, or copy a thesis file under an id \
         of your own (table = \"my-IV.36\" in my-IV.36.toml, without [thesis]) and sweep the copy",
        dir.display(),
        shortened_list(tables)
    )]
    SweepOfThesis { dir: PathBuf, tables: Vec<String> },

    /// A table id asked for (e.g. on the command line) has no experiment file.
    #[error(
        "{}: no experiment file for table `{id}`; available tables: {}",
        dir.display(),
        available.join(", ")
    )]
    UnknownTable {
        dir: PathBuf,
        id: String,
        available: Vec<String>,
    },
}

/// The message of [`ExperimentError::InSweepRun`]: the file, the run and its values, then the
/// error of the run's text.
fn in_sweep_run(run: &str, values: &str, source: &ExperimentError) -> String {
    let path = source.path().display().to_string();
    let text = source.to_string();
    match text.strip_prefix(&format!("{path}: ")) {
        Some(rest) => format!("{path}: sweep run {run} ({values}): {rest}"),
        None => format!("sweep run {run} ({values}): {text}"),
    }
}

/// The first few of `items`, and how many more.
fn shortened_list(items: &[String]) -> String {
    const SHOWN: usize = 5;
    if items.len() <= SHOWN {
        items.join(", ")
    } else {
        format!("{}, … {} in all", items[..SHOWN].join(", "), items.len())
    }
}

fn field_prefix(field: Option<&str>) -> String {
    match field {
        Some(field) => format!("field `{field}`: "),
        None => String::new(),
    }
}

impl ExperimentError {
    /// A semantic error in `field` of the file at `path`.
    pub(crate) fn invalid(
        path: &Path,
        field: impl Into<String>,
        expected: impl Into<String>,
        found: impl Into<String>,
    ) -> Self {
        Self::Invalid {
            path: path.to_path_buf(),
            field: field.into(),
            expected: expected.into(),
            found: found.into(),
        }
    }

    /// The file or directory the error is about.
    pub fn path(&self) -> &Path {
        match self {
            Self::Read { path, .. }
            | Self::NotRegularFile { path, .. }
            | Self::TooLarge { path, .. }
            | Self::Toml { path, .. }
            | Self::Invalid { path, .. } => path,
            Self::InSweepRun { source, .. } => source.path(),
            Self::ReadDir { dir, .. }
            | Self::UnknownTable { dir, .. }
            | Self::SweepOfThesis { dir, .. } => dir,
        }
    }

    /// The dotted field path the error is about, when there is one.
    pub fn field(&self) -> Option<&str> {
        match self {
            Self::Toml { field, .. } => field.as_deref(),
            Self::Invalid { field, .. } => Some(field),
            Self::InSweepRun { source, .. } => source.field(),
            Self::SweepOfThesis { .. }
            | Self::Read { .. }
            | Self::NotRegularFile { .. }
            | Self::TooLarge { .. }
            | Self::ReadDir { .. }
            | Self::UnknownTable { .. } => None,
        }
    }
}

/// Where a relative path points: " (relative to <cwd>)", or nothing for an absolute path.
fn relative_to_cwd(path: &Path) -> String {
    match std::env::current_dir() {
        Ok(cwd) if path.is_relative() => format!(" (relative to {})", cwd.display()),
        _ => String::new(),
    }
}
