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
pub use ids::table_order;
pub use listing::MAX_FILE_BYTES;
pub(super) use listing::{experiment_entries, read_experiment_file};

/// Parse and validate one experiment file.
///
/// Errors name the file and the field: I/O errors, TOML syntax, type, missing- and
/// unknown-field errors (wrapped with toml's message, which shows the line), and every
/// semantic check of [`ExperimentFile`] (see the module documentation).
pub fn load(path: &Path) -> Result<Experiment, ExperimentError> {
    let text = read_experiment_file(path)?;
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
    let all = experiment_entries(dir)?;
    let mut files = all.clone();
    if let Some(only) = only {
        let mut wanted = BTreeSet::new();
        for id in only {
            if !files.iter().any(|(stem, _)| stem == id) {
                return Err(ExperimentError::UnknownTable {
                    dir: dir.to_path_buf(),
                    id: id.clone(),
                    available: all.iter().map(|(stem, _)| stem.clone()).collect(),
                });
            }
            wanted.insert(id.as_str());
        }
        files.retain(|(stem, _)| wanted.contains(stem.as_str()));
    }
    let loaded: Vec<Loaded> = files
        .iter()
        .map(|(stem, path)| (stem.clone(), load(path)))
        .collect();
    // The related ids need the other files: a table whose related ids do not hold is a failed
    // entry like a file that does not load.
    let related: Vec<Option<ExperimentError>> = files
        .iter()
        .zip(&loaded)
        .map(|((_, path), (_, outcome))| match outcome {
            Ok(experiment) => related_tables(path, experiment, &all, &loaded).err(),
            Err(_) => None,
        })
        .collect();
    Ok(loaded
        .into_iter()
        .zip(related)
        .map(|((stem, outcome), refused)| match refused {
            Some(error) => (stem, Err(error)),
            None => (stem, outcome),
        })
        .collect())
}
