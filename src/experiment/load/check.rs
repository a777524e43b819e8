//! The semantic checks of a parsed experiment file: what serde cannot check (ranges,
//! consistency between sections, the conventions of Chapter IV). [`Check`] holds the file's
//! path for the messages and the checks shared by every section; the sections' own checks are
//! in the sibling modules (identity, scene, film, study, probes, thesis), each an `impl` block
//! of [`Check`].

use std::collections::BTreeSet;
use std::path::Path;

use super::ids::{figure_number, is_thesis_id};
use crate::experiment::spec::*;
use crate::experiment::ExperimentError;
use crate::family::{self, FamilyRef};

/// Longest one-line text (title, section, names, column names), in characters.
const MAX_TEXT_CHARS: usize = 1_000;
/// Longest note, in characters (the longest shipped note has about 2 700).
const MAX_NOTE_CHARS: usize = 20_000;

pub type Checked = Result<(), ExperimentError>;

/// Semantic validation of one parsed file; `path` is only used in error messages.
pub struct Check<'p> {
    pub(super) path: &'p Path,
}

impl Check<'_> {
    pub fn fail(&self, field: &str, expected: &str, found: impl Found) -> ExperimentError {
        ExperimentError::invalid(self.path, field, expected, found.text())
    }

    pub fn ensure(&self, ok: bool, field: &str, expected: &str, found: impl Found) -> Checked {
        if ok {
            Ok(())
        } else {
            Err(self.fail(field, expected, found))
        }
    }

    pub fn finite(&self, field: &str, value: f64) -> Checked {
        self.ensure(value.is_finite(), field, "a finite number", value)
    }

    pub fn positive(&self, field: &str, value: f64) -> Checked {
        self.ensure(
            value.is_finite() && value > 0.0,
            field,
            "a finite number > 0",
            value,
        )
    }

    pub fn non_negative(&self, field: &str, value: f64) -> Checked {
        self.ensure(
            value.is_finite() && value >= 0.0,
            field,
            "a finite number ≥ 0",
            value,
        )
    }

    pub fn finite_all(&self, field: &str, values: &[f64]) -> Checked {
        for (i, &v) in values.iter().enumerate() {
            self.finite(&format!("{field}[{i}]"), v)?;
        }
        Ok(())
    }

    /// Every check of the file, in the order of its sections; the family of the scene
    /// ([`crate::family::of_scene`]) once its effects are known to combine.
    pub(super) fn experiment(&self, spec: &ExperimentFile) -> Result<FamilyRef, ExperimentError> {
        self.identity(spec)?;
        self.scene(&spec.scene)?;
        let family = family::of_scene(&spec.scene.effects, spec.study.kind).ok_or_else(|| {
            self.fail(
                "scene.effects",
                "the effects of one family of runs",
                format!("{:?}", names(&spec.scene.effects)),
            )
        })?;
        family.check(self, spec)?;
        self.study(&spec.study, &spec.scene)?;
        self.marks_cells(&spec.study, &spec.scene)?;
        self.smoothing_acts(&spec.study, &spec.scene)?;
        self.rising_tools(&spec.scene, &spec.study)?;
        self.probes(&spec.probes, &spec.scene, family.facts().components)?;
        self.family_fields(spec, family)?;
        let figure = figure_number(&spec.table).is_some();
        if !is_thesis_id(&spec.table) {
            self.ensure(
                spec.thesis.is_none(),
                "thesis",
                "no [thesis] in a scene of your own (an id that is not `IV.<n>` or `fig-…`): \
                 [thesis] holds a table the thesis printed; remove it, and the report shows \
                 tribo's rows alone",
                "a [thesis] table",
            )?;
            return Ok(family);
        }
        // A table id without printed rows is refused by `identity`.
        if let Some(thesis) = &spec.thesis {
            self.ensure(
                !figure,
                "thesis",
                "no printed table in a figure experiment (`fig-IV.<n>`: the thesis shows the \
                 result as a figure only)",
                "a [thesis] table",
            )?;
            self.thesis(thesis, &spec.table)?;
        }
        Ok(family)
    }

    /// The fields whose meaning depends on the family: `[study] solver` only where it chooses
    /// the linear solver, `related` only where the report draws related tables.
    fn family_fields(&self, spec: &ExperimentFile, family: FamilyRef) -> Checked {
        if let Some(solver) = spec.study.solver {
            let choosing: Vec<&str> = family::FAMILIES
                .iter()
                .filter(|f| f.facts().solver_choice)
                .map(|f| f.facts().id)
                .collect();
            self.ensure(
                family.facts().solver_choice,
                "study.solver",
                &format!(
                    "no such field in a {} scene: its systems are solved by the direct solver \
                     whatever the field says (only the families {} choose)",
                    family.facts().id,
                    choosing.join(", ")
                ),
                format!("`{}`", solver.name()),
            )?;
        }
        self.related(spec, family)
    }

    /// Text shown on the page and in file names: no control characters (a NUL or BEL would be
    /// copied into `index.html`), except line breaks and tabs where `multiline` (notes, the
    /// only text that can hold them); at most [`MAX_TEXT_CHARS`] characters on one line or
    /// [`MAX_NOTE_CHARS`] in a note.
    pub(super) fn printable(&self, field: &str, text: &str, multiline: bool) -> Checked {
        let max = if multiline {
            MAX_NOTE_CHARS
        } else {
            MAX_TEXT_CHARS
        };
        let chars = text.chars().count();
        if !multiline {
            self.visible(field, text)?;
        }
        self.ensure(
            chars <= max,
            field,
            &format!("at most {max} characters"),
            format!("{chars} characters"),
        )?;
        let bad = text
            .chars()
            .find(|&c| c.is_control() && !(multiline && (c == '\n' || c == '\t')));
        self.ensure(
            bad.is_none(),
            field,
            "text without control characters",
            format!("the control character {:?}", bad.unwrap_or(' ')),
        )
    }

    pub(super) fn unique_sides(&self, field: &str, sides: impl Iterator<Item = Side>) -> Checked {
        let mut seen = BTreeSet::new();
        for (i, side) in sides.enumerate() {
            self.ensure(
                seen.insert(side),
                &format!("{field}[{i}]"),
                "each side listed once",
                format!("`{}` twice", side_name(side)),
            )?;
        }
        Ok(())
    }
}

/// What a check found, as the error message shows it.
pub trait Found {
    fn text(self) -> String;
}

/// Numbers as Rust's `Debug` writes them: the shortest text that reads back to the same value,
/// with an exponent for very large or small magnitudes (`1e300`, not 301 digits).
impl Found for f64 {
    fn text(self) -> String {
        format!("{self:?}")
    }
}

impl Found for usize {
    fn text(self) -> String {
        self.to_string()
    }
}

impl Found for String {
    fn text(self) -> String {
        self
    }
}

impl Found for &str {
    fn text(self) -> String {
        self.to_owned()
    }
}

pub(super) fn side_name(side: Side) -> &'static str {
    side.name()
}

pub(super) fn effect_name(effect: Effect) -> &'static str {
    match effect {
        Effect::Elasticity => "elasticity",
        Effect::Contact => "contact",
        Effect::Reynolds => "reynolds",
        Effect::SubStokes => "substokes",
        Effect::StokesChannel => "stokes-channel",
    }
}

pub(super) fn names(effects: &[Effect]) -> Vec<&'static str> {
    effects.iter().map(|&e| effect_name(e)).collect()
}
