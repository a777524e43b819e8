//! The printed thesis tables, as reference data to compare against (never copied into an output).

use serde::Serialize;

use crate::experiment::{AdditivePart, Comparison, Experiment, ThesisFigures};

/// One printed Chapter IV table.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ThesisTable {
    /// Table id, e.g. `IV.1`.
    pub table: String,
    /// Thesis section, e.g. `IV.1.1`.
    pub section: String,
    /// Column names as in `tables.csv`; the first is `cycle`.
    pub columns: Vec<String>,
    /// One row per printed cycle (`inf`/`nan` where the thesis prints them).
    pub rows: Vec<Vec<f64>>,
    /// Set when the printed table is a known copy of another table.
    pub duplicate_of: Option<String>,
    /// A part of the printed estimate that another table prints alone (IV.43 for IV.41/IV.42).
    pub additive_part: Option<AdditivePart>,
    /// Whether the run is compared with the thesis at all: an edited thesis experiment or a
    /// scene of the user's own has no printed rows here (nothing is scored), and the report
    /// says why.
    pub comparison: Comparison,
    /// The thesis figures that show the run, from the experiment file (also for an edited
    /// experiment: its figures are still the thesis's nearest pictures).
    pub figures: ThesisFigures,
}

impl ThesisTable {
    /// The printed table of an experiment (reference data, never an output).
    ///
    /// Only an experiment that describes the printed table ([`Comparison::Printed`]) gets its
    /// rows: one whose file was edited (its scene, study or printed rows differ from the
    /// shipped file's) or a scene of the user's own gets an empty table, so no row of it is
    /// scored against the thesis, and [`ThesisTable::comparison`] says which.
    pub fn of(experiment: &Experiment) -> ThesisTable {
        if !experiment.comparison.is_printed() {
            return ThesisTable {
                table: experiment.table.clone(),
                section: experiment.section.clone(),
                columns: Vec::new(),
                rows: Vec::new(),
                duplicate_of: None,
                additive_part: None,
                comparison: experiment.comparison.clone(),
                figures: experiment.figures.clone(),
            };
        }
        ThesisTable {
            table: experiment.table.clone(),
            section: experiment.section.clone(),
            columns: experiment.thesis.columns.clone(),
            rows: experiment.thesis.rows.clone(),
            duplicate_of: experiment.thesis.duplicate_of.clone(),
            additive_part: experiment.thesis.additive_part.clone(),
            comparison: Comparison::Printed,
            figures: experiment.figures.clone(),
        }
    }

    /// Printed value of `column` in printed cycle `cycle`, if the thesis has it.
    ///
    /// The loader checks that the printed rows are cycles 0, 1, 2, … in order, so row `cycle` is
    /// looked at first: a lookup takes constant time, and a report of many rows stays linear. A
    /// table built otherwise is searched from the front.
    pub fn value(&self, cycle: usize, column: &str) -> Option<f64> {
        let c = self.columns.iter().position(|n| n == column)?;
        let is_cycle = |r: &&Vec<f64>| r.first().map(|v| *v as usize) == Some(cycle);
        self.rows
            .get(cycle)
            .filter(is_cycle)
            .or_else(|| self.rows.iter().find(is_cycle))
            .and_then(|r| r.get(c).copied())
    }

    /// The printed estimate of row `cycle` with the additive part removed in quadrature,
    /// √(estimate² − part²), if the table has one (`None` where the part is not smaller).
    pub fn estimate_without_part(&self, cycle: usize) -> Option<f64> {
        let part = self.additive_part.as_ref()?.estimate.get(cycle).copied()?;
        let e = self.value(cycle, "estimate")?;
        (e.is_finite() && part.is_finite() && e.abs() > part.abs())
            .then(|| (e * e - part * part).sqrt())
    }

    /// Number of printed rows.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }
}
