//! Parsing and validation of experiment files.
//!
//! [`load`] reads one file with the `toml` crate into [`ExperimentFile`], checks what serde
//! cannot — ranges, consistency between sections, and the conventions of Chapter IV (table ids
//! `IV.1`…`IV.75` with their printed rows, figure ids `fig-…`, free ids for scenes of the user's
//! own without `[thesis]`, the fixed-fraction marking of §IV.1, printed rows numbered from cycle
//! 0) — and returns the typed [`Experiment`]: the effects and their data sections become one
//! [`Problem`](super::Problem), and the fingerprints of the shipped files say whether a thesis
//! experiment was edited ([`Comparison`]).
//! Nothing here panics on user input; every failure is an [`ExperimentError`].
//!
//! The work is split by job: [`listing`] finds and reads the files of a folder, [`ids`] knows
//! the table and figure ids, [`position`] locates toml's errors in the text, [`table`] reads the
//! CSV profiles of tabulated gaps and obstacles, and [`check`] with one module per part of the
//! file (identity, scene, film, study, probes, thesis) does the semantic checks.

mod check;
mod film;
mod identity;
mod ids;
mod listing;
mod position;
mod probes;
mod related;
mod scene;
mod study;
mod sweep;
mod table;
mod thesis;

use std::collections::BTreeSet;
use std::path::Path;

use super::error::ExperimentError;
use super::printed::edited_fields;
use super::spec::*;
use super::{Comparison, Experiment, Scene};
use check::Check;
pub use check::{Check as FileCheck, Checked, Found};
use position::toml_error;
use related::related_tables;

pub(super) use ids::is_thesis_id;
pub use ids::{table_order, TableOrder};
pub use listing::MAX_FILE_BYTES;
pub(super) use listing::{experiment_entries, read_experiment_file};
pub use sweep::{parse_set, SweepField};

/// Parse and validate one experiment file.
///
/// Errors name the file and the field: I/O errors, TOML syntax, type, missing- and
/// unknown-field errors (wrapped with toml's message, which shows the line), and every
/// semantic check of [`ExperimentFile`] (see the module documentation).
///
/// A file with `[sweep]` makes one run per combination of values and is refused here (naming
/// the field): [`load_each`] loads its runs.
pub fn load(path: &Path) -> Result<Experiment, ExperimentError> {
    let text = read_experiment_file(path)?;
    let experiment = load_text(path, &text)?;
    if sweep::is_swept(&text) {
        return Err(Check { path }.fail(
            "sweep",
            "a file of one run: a file with [sweep] makes a run per combination of its values \
             (run it with `report`, or load its folder with `load_each`)",
            "a [sweep] table",
        ));
    }
    Ok(experiment)
}

/// [`load`] of the file at `path` whose text is `text`; a `[sweep]` in it is left alone.
fn load_text(path: &Path, text: &str) -> Result<Experiment, ExperimentError> {
    let text = text.to_string();
    let mut file: ExperimentFile =
        toml::from_str(&text).map_err(|error| toml_error(path, &text, &error))?;
    let check = Check { path };
    check.read_profiles(&mut file.scene)?;
    let family = check.experiment(&file)?;
    let problem = check.problem(&file.scene, family)?;
    let mut typed_study = check.typed_study(&file.study)?;
    let comparison = if is_thesis_id(&file.table) {
        edited_fields(&file.table, &text).map_or(Comparison::Printed, Comparison::Edited)
    } else {
        Comparison::OwnScene
    };
    // The thesis's readings explain printed numbers: a scene of one's own runs them on request.
    let asked_for_readings = file.study.alternatives;
    typed_study.readings =
        asked_for_readings.unwrap_or(!matches!(comparison, Comparison::OwnScene));
    let ExperimentFile {
        table,
        section,
        title,
        scene,
        study: _,
        probes,
        notes,
        related,
        thesis,
        figures,
        sweep: _,
    } = file;
    let experiment = Experiment {
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
            mesh_smoothing: self::scene::mesh_smoothing(&scene.mesh_smoothing),
        },
        family,
        problem,
        study: typed_study,
        probes,
        notes,
        related,
        thesis: thesis.unwrap_or_default(),
        figures,
        parameters: super::parameters::of_file(&text),
        comparison,
        sweep: None,
    };
    if asked_for_readings == Some(true) {
        check.has_readings(&experiment)?;
    }
    Ok(experiment)
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

/// One entry of [`load_each`]: the file stem (the table id of a good file; a run's id for the
/// runs of a sweep) and what loading it gave.
pub type Loaded = (String, Result<Experiment, ExperimentError>);

/// Load every `*.toml` in `dir` (or just the tables of `only`) in table order, each file on its
/// own: one `(stem, outcome)` per file, so that a broken file becomes one failed entry of the
/// report while the other tables still run. A file with `[sweep]` gives one entry per run,
/// under the run's id ([`crate::experiment::sweep`]).
///
/// Every entry named `*.toml` counts, whatever it is: a directory, a FIFO, a device or a
/// symbolic link to one is a failed entry ([`ExperimentError::NotRegularFile`]) and is never
/// opened, so `--only IV.1` names `IV.1.toml` even when it is not a file. Only problems with
/// the directory itself are errors of the whole call: it cannot be listed, or `only` names a
/// table without an entry.
pub fn load_each(dir: &Path, only: Option<&[String]>) -> Result<Vec<Loaded>, ExperimentError> {
    load_each_swept(dir, only, &[])
}

/// [`load_each`] with the fields of `report --set` swept in every file (in place of a file's
/// own `[sweep]` fields). `only` may name a whole file (all its runs) or one run of a sweep
/// (`step-bearing~-10`). A `set` over thesis experiments is an error of the whole call.
pub fn load_each_swept(
    dir: &Path,
    only: Option<&[String]>,
    set: &[SweepField],
) -> Result<Vec<Loaded>, ExperimentError> {
    let all = experiment_entries(dir)?;
    let unknown = |id: &str, available: Vec<String>| ExperimentError::UnknownTable {
        dir: dir.to_path_buf(),
        id: id.to_string(),
        available,
    };
    let stems = || all.iter().map(|(stem, _)| stem.clone()).collect::<Vec<_>>();
    // Files asked for whole, and single runs asked for by their id.
    let mut whole: BTreeSet<&str> = BTreeSet::new();
    let mut runs: BTreeSet<&str> = BTreeSet::new();
    if let Some(only) = only {
        for id in only {
            if all.iter().any(|(stem, _)| stem == id) {
                whole.insert(id);
            } else if sweep::file_of_run(id).is_some_and(|f| all.iter().any(|(s, _)| s == f)) {
                runs.insert(id);
            } else {
                return Err(unknown(id, stems()));
            }
        }
    }
    let wanted = |stem: &str| {
        only.is_none()
            || whole.contains(stem)
            || runs.iter().any(|run| sweep::file_of_run(run) == Some(stem))
    };
    let files: Vec<&(String, std::path::PathBuf)> =
        all.iter().filter(|(stem, _)| wanted(stem)).collect();
    if !set.is_empty() {
        let thesis: Vec<String> = files
            .iter()
            .filter(|(stem, _)| is_thesis_id(stem))
            .map(|(stem, _)| stem.clone())
            .collect();
        if !thesis.is_empty() {
            return Err(ExperimentError::SweepOfThesis {
                dir: dir.to_path_buf(),
                tables: thesis,
            });
        }
    }
    let mut entries: Vec<(&Path, Loaded)> = Vec::new();
    for (stem, path) in files {
        let mut loaded = load_runs(path, stem, set);
        if !whole.contains(stem.as_str()) && only.is_some() {
            // Only the runs asked for; a file that failed as a whole stays, with its error.
            let asked: Vec<&str> = runs
                .iter()
                .copied()
                .filter(|run| sweep::file_of_run(run) == Some(stem))
                .collect();
            let failed_whole = matches!(&loaded[..], [(s, Err(_))] if s == stem);
            if !failed_whole {
                if let Some(missing) = asked
                    .iter()
                    .find(|run| !loaded.iter().any(|(s, _)| s == *run))
                {
                    return Err(unknown(
                        missing,
                        loaded.iter().map(|(s, _)| s.clone()).collect(),
                    ));
                }
                loaded.retain(|(s, _)| asked.contains(&s.as_str()));
            }
        }
        entries.extend(loaded.into_iter().map(|entry| (path.as_path(), entry)));
    }
    let (paths, loaded): (Vec<&Path>, Vec<Loaded>) = entries.into_iter().unzip();
    // The related ids need the other files: a table whose related ids do not hold is a failed
    // entry like a file that does not load.
    let refused: Vec<Option<ExperimentError>> = paths
        .iter()
        .zip(&loaded)
        .map(|(path, (_, outcome))| match outcome {
            Ok(experiment) => related_tables(path, experiment, &all, &loaded).err(),
            Err(_) => None,
        })
        .collect();
    Ok(loaded
        .into_iter()
        .zip(refused)
        .map(|((stem, outcome), refused)| match refused {
            Some(error) => (stem, Err(error)),
            None => (stem, outcome),
        })
        .collect())
}

/// The entries of one file: its runs where it is swept, in table order (by their values, as
/// `report merge` orders their records), else the file itself.
fn load_runs(path: &Path, stem: &str, set: &[SweepField]) -> Vec<Loaded> {
    let text = match read_experiment_file(path) {
        Ok(text) => text,
        Err(error) => return vec![(stem.to_string(), Err(error))],
    };
    match sweep::runs(path, stem, &text, set) {
        Some(mut runs) => {
            runs.sort_by_key(|(id, _)| table_order(id));
            runs
        }
        None => vec![(stem.to_string(), load_text(path, &text))],
    }
}
