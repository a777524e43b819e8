//! The table the thesis printed (`[thesis]`): its columns and rows, and the tables it refers
//! to.

use std::collections::BTreeSet;

use super::check::{Check, Checked};
use super::ids::table_number;
use super::study::MAX_ROWS;
use crate::experiment::spec::*;

/// Most columns of a printed thesis table (Chapter IV prints at most 12).
const MAX_THESIS_COLUMNS: usize = 64;

impl Check<'_> {
    /// The printed table: `cycle` first, rectangular, cycles 0, 1, 2, … in order.
    pub(super) fn thesis(&self, thesis: &ThesisRows, table: &str) -> Checked {
        let columns = &thesis.columns;
        self.ensure(
            columns.first().is_some_and(|c| c == "cycle"),
            "thesis.columns[0]",
            "`cycle`",
            columns
                .first()
                .map_or("an empty list".to_owned(), |c| format!("`{c}`")),
        )?;
        self.ensure(
            columns.len() <= MAX_THESIS_COLUMNS,
            "thesis.columns",
            &format!("at most {MAX_THESIS_COLUMNS} columns"),
            format!("{} columns", columns.len()),
        )?;
        let mut seen = BTreeSet::new();
        for (i, column) in columns.iter().enumerate() {
            self.ensure(
                seen.insert(column.as_str()),
                &format!("thesis.columns[{i}]"),
                "each column named once",
                format!("`{column}` twice"),
            )?;
        }
        self.ensure(
            !thesis.rows.is_empty(),
            "thesis.rows",
            "at least one printed row",
            "an empty list",
        )?;
        self.ensure(
            thesis.rows.len() <= MAX_ROWS,
            "thesis.rows",
            &format!("at most {MAX_ROWS} printed rows (as study.rows)"),
            format!("{} rows", thesis.rows.len()),
        )?;
        for (i, column) in columns.iter().enumerate() {
            self.printable(&format!("thesis.columns[{i}]"), column, false)?;
        }
        for (i, row) in thesis.rows.iter().enumerate() {
            let field = format!("thesis.rows[{i}]");
            self.ensure(
                row.len() == columns.len(),
                &field,
                &format!("{} values, one per thesis.columns entry", columns.len()),
                format!("{} values", row.len()),
            )?;
            self.ensure(
                row[0] == i as f64,
                &format!("{field}[0]"),
                &format!("cycle {i} (cycles are 0, 1, 2, … in order)"),
                row[0],
            )?;
        }
        if let Some(original) = &thesis.duplicate_of {
            self.ensure(
                table_number(original).is_some() && original != table,
                "thesis.duplicate_of",
                "the id of another Chapter IV table, e.g. `IV.13`",
                format!("`{original}`"),
            )?;
        }
        if let Some(part) = &thesis.additive_part {
            self.ensure(
                table_number(&part.table).is_some() && part.table != table,
                "thesis.additive_part.table",
                "the id of another Chapter IV table, e.g. `IV.43`",
                format!("`{}`", part.table),
            )?;
            self.ensure(
                columns.iter().any(|c| c == "estimate"),
                "thesis.additive_part",
                "a table with an `estimate` column",
                "no `estimate` in thesis.columns",
            )?;
            self.ensure(
                part.estimate.len() == thesis.rows.len(),
                "thesis.additive_part.estimate",
                &format!("{} values, one per printed row", thesis.rows.len()),
                format!("{} values", part.estimate.len()),
            )?;
            for (i, v) in part.estimate.iter().enumerate() {
                self.ensure(
                    v.is_finite() && *v >= 0.0,
                    &format!("thesis.additive_part.estimate[{i}]"),
                    "a finite value ≥ 0",
                    *v,
                )?;
            }
        }
        Ok(())
    }
}
