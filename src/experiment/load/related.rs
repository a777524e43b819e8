//! `related`: the tables of the same scene solved another way, which the report draws beside
//! an experiment (the model-adaptive film of Fig. IV.116 beside the pure Reynolds and pure
//! SubStokes runs of (IV.17)). The file alone says whether its family draws any, and whether
//! the list is short and without repeats ([`Check::related`]); whether each id names a table of
//! the folder, of a family that can be drawn beside it and of the same scene needs the other
//! files ([`related_tables`]).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use super::check::{Check, Checked};
use super::load;
use crate::experiment::spec::*;
use crate::experiment::{Experiment, ExperimentError};
use crate::family::{FamilyRef, FAMILIES};

/// Most related tables of one experiment (the report draws one curve per table).
pub const MAX_RELATED: usize = 8;

impl Check<'_> {
    /// The related ids of the file: none where the family draws no related tables, at most
    /// [`MAX_RELATED`], each once.
    pub(super) fn related(&self, spec: &ExperimentFile, family: FamilyRef) -> Checked {
        let facts = family.facts();
        if let Some(first) = spec.related.first() {
            let drawing: Vec<&str> = FAMILIES
                .iter()
                .filter(|f| !f.facts().related.is_empty())
                .map(|f| f.facts().id)
                .collect();
            self.ensure(
                !facts.related.is_empty(),
                "related",
                &format!(
                    "no related tables in a {} scene (the report draws related tables beside a \
                     scene of the families {} only)",
                    facts.id,
                    drawing.join(", ")
                ),
                format!("`{first}`"),
            )?;
        }
        self.ensure(
            spec.related.len() <= MAX_RELATED,
            "related",
            &format!("at most {MAX_RELATED} related tables"),
            format!("{} ids", spec.related.len()),
        )?;
        let mut seen = BTreeSet::new();
        for (i, id) in spec.related.iter().enumerate() {
            self.ensure(
                seen.insert(id.as_str()),
                &format!("related[{i}]"),
                "each related table once",
                format!("`{id}` twice"),
            )?;
        }
        Ok(())
    }
}

/// Check the related ids of `experiment` (loaded from `path`) against the other tables of its
/// folder: each names a file of `files` (the folder's `(stem, path)` entries), that file loads
/// (taken from `loaded` where it was loaded already), its family is one the experiment's family
/// draws beside it, and it solves the same scene ([`crate::family::Family::related_to`]).
pub(super) fn related_tables(
    path: &Path,
    experiment: &Experiment,
    files: &[(String, PathBuf)],
    loaded: &[(String, Result<Experiment, ExperimentError>)],
) -> Result<(), ExperimentError> {
    let check = Check { path };
    let facts = experiment.family.facts();
    for (i, id) in experiment.related.iter().enumerate() {
        let field = format!("related[{i}]");
        let Some((_, other_path)) = files.iter().find(|(stem, _)| stem == id) else {
            return Err(check.fail(
                &field,
                "the id of a table of this folder",
                format!("`{id}`, which has no file here"),
            ));
        };
        let other = match loaded.iter().find(|(stem, _)| stem == id) {
            Some((_, Ok(other))) => other.clone(),
            Some((_, Err(_))) | None => load(other_path).map_err(|_| {
                check.fail(
                    &field,
                    "a table whose file loads",
                    format!("`{id}`, whose file does not load (run it alone to see why)"),
                )
            })?,
        };
        let kind = other.family.facts().id;
        check.ensure(
            facts.related.contains(&kind),
            &field,
            &format!(
                "a table of the families {} (drawn beside a {} scene)",
                facts.related.join(", "),
                facts.id
            ),
            format!("`{id}`, a {kind} table"),
        )?;
        if let Err(expected) = experiment.family.related_to(experiment, &other) {
            return Err(check.fail(&field, &expected, format!("`{id}`")));
        }
    }
    Ok(())
}
