//! The summary's verdict per table: reproduced, differs for a known reason, or differs
//! unexplained — with how many rows lie within the page's tolerance.
//!
//! A row is within tolerance when each of its scored columns that both tribo and the thesis
//! have — `dofs` (3 %) and `estimate` (5 %), the columns of the summary's "max Δ" — differs by
//! no more than the tolerance (`super::tolerance`). A table whose every row is within
//! tolerance is *reproduced*. A table the thesis prints as a copy of another is not scored
//! (its printed numbers belong to the other scene); a figure experiment and a scene without a
//! printed table have nothing to be scored against.

use super::{compared_value, rel_diff, tolerance, Section};

/// The columns a row is scored on.
pub const SCORED: [&str; 2] = ["dofs", "estimate"];

/// Why tribo's numbers differ from the printed ones, where the report knows it.
#[derive(Clone, Debug, PartialEq)]
pub struct KnownReason {
    /// A short kind, e.g. `thesis erratum`, `solver noise`, `uncalibrated estimator`.
    pub kind: String,
    /// One sentence for the summary's tooltip.
    pub reason: String,
    /// An anchor on the page with the evidence (an erratum), if any.
    pub anchor: Option<String>,
}

/// The verdict on one table that ran.
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict {
    /// Every scored row within tolerance.
    Reproduced,
    /// Some row outside tolerance, for a reason the report states.
    DiffersKnown(KnownReason),
    /// Some row outside tolerance, reason unknown.
    DiffersUnexplained,
    /// The printed table is a copy of another table (`of`): not scored.
    Duplicate { of: String },
    /// Nothing printed to score against (a figure experiment, a scene of the user's own).
    NotScored { why: String },
}

impl Verdict {
    /// The words of the summary's verdict column.
    pub fn label(&self) -> String {
        match self {
            Verdict::Reproduced => "reproduced".into(),
            Verdict::DiffersKnown(r) => format!("differs: {}", r.kind),
            Verdict::DiffersUnexplained => "differs, unexplained".into(),
            Verdict::Duplicate { of } => format!("thesis duplicate of {of}: not scored"),
            Verdict::NotScored { why } => why.clone(),
        }
    }

    /// The CSS class of the verdict cell: green, amber, red or neutral.
    pub fn class(&self) -> &'static str {
        match self {
            Verdict::Reproduced => "verdict ok",
            Verdict::DiffersKnown(_) => "verdict known",
            Verdict::DiffersUnexplained => "verdict off",
            Verdict::Duplicate { .. } | Verdict::NotScored { .. } => "verdict neutral",
        }
    }
}

/// Rows within tolerance: `within` of `scored` rows that have a scored column printed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RowsWithin {
    pub within: usize,
    pub scored: usize,
}

/// How many of the section's computed rows are within tolerance on [`SCORED`].
pub fn rows_within(section: &Section) -> RowsWithin {
    let rows = &section.run.rows;
    let mut out = RowsWithin {
        within: 0,
        scored: 0,
    };
    for (i, row) in rows.iter().enumerate() {
        let diffs: Vec<f64> = SCORED
            .iter()
            .filter_map(|c| {
                let d = rel_diff(
                    compared_value(rows, i, c)?,
                    section.thesis.value(row.cycle, c)?,
                )?;
                Some(d.abs() / tolerance(c))
            })
            .collect();
        if diffs.is_empty() {
            continue;
        }
        out.scored += 1;
        if diffs.iter().all(|d| *d <= 1.0) {
            out.within += 1;
        }
    }
    out
}

/// The verdict on a section, given the reason the report knows for its differences (if any)
/// and why it is not scored against the thesis (if so: an edited or own scene).
pub fn of(section: &Section, known: Option<KnownReason>, not_scored: Option<String>) -> Verdict {
    if let Some(why) = not_scored {
        return Verdict::NotScored { why };
    }
    if section.is_figure() {
        return Verdict::NotScored {
            why: "figure: no printed table".into(),
        };
    }
    if let Some(of) = &section.thesis.duplicate_of {
        return Verdict::Duplicate { of: of.clone() };
    }
    let rows = rows_within(section);
    if rows.scored > 0 && rows.within == rows.scored {
        return Verdict::Reproduced;
    }
    if rows.scored == 0 {
        return Verdict::NotScored {
            why: "no printed row computed".into(),
        };
    }
    match known {
        Some(reason) => Verdict::DiffersKnown(reason),
        None => Verdict::DiffersUnexplained,
    }
}

/// The number n of a Chapter IV table id `IV.n` (1 ≤ n ≤ 75), `None` for any other id.
pub fn thesis_table_number(id: &str) -> Option<usize> {
    let n: usize = id.strip_prefix("IV.")?.parse().ok()?;
    (1..=THESIS_TABLES).contains(&n).then_some(n)
}

/// Chapter IV prints tables IV.1 … IV.75.
pub const THESIS_TABLES: usize = 75;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::results::{Row, RunResult};
    use crate::thesis::ThesisTable;

    fn run(rows: &[(usize, usize, f64)]) -> RunResult {
        let mut r = RunResult::new("IV.1", "IV.1.1", "t", "full", [0.0, 1.0, 0.0, 1.0]);
        r.rows = rows
            .iter()
            .map(|&(c, n, e)| Row::new(c).count("dofs", n).real("estimate", Some(e)))
            .collect();
        r
    }

    fn thesis(rows: &[(usize, usize, f64)]) -> ThesisTable {
        ThesisTable {
            table: "IV.1".into(),
            section: "IV.1.1".into(),
            columns: vec!["cycle".into(), "dofs".into(), "estimate".into()],
            rows: rows
                .iter()
                .map(|&(c, n, e)| vec![c as f64, n as f64, e])
                .collect(),
            duplicate_of: None,
            additive_part: None,
            comparison: Default::default(),
            figures: Default::default(),
        }
    }

    fn section<'a>(run: &'a RunResult, thesis: &'a ThesisTable) -> Section<'a> {
        Section {
            run,
            thesis,
            alternatives: &[],
        }
    }

    #[test]
    fn rows_are_within_tolerance_up_to_three_and_five_percent() {
        let printed = thesis(&[(0, 100, 1.0), (1, 200, 0.7), (2, 400, 0.5)]);
        let same = run(&[(0, 100, 1.0), (1, 205, 0.72), (2, 400, 0.5)]);
        let s = section(&same, &printed);
        assert_eq!(
            rows_within(&s),
            RowsWithin {
                within: 3,
                scored: 3
            }
        );
        assert_eq!(of(&s, None, None), Verdict::Reproduced);

        let off = run(&[(0, 100, 1.0), (1, 210, 0.7), (2, 400, 0.53)]);
        let s = section(&off, &printed);
        assert_eq!(
            rows_within(&s),
            RowsWithin {
                within: 1,
                scored: 3
            }
        );
        assert_eq!(of(&s, None, None), Verdict::DiffersUnexplained);
        let known = KnownReason {
            kind: "solver noise".into(),
            reason: "ties".into(),
            anchor: None,
        };
        assert_eq!(
            of(&s, Some(known.clone()), None),
            Verdict::DiffersKnown(known)
        );
        assert_eq!(
            of(&s, None, Some("edited: not scored".into())).label(),
            "edited: not scored"
        );
    }

    #[test]
    fn duplicates_and_figures_are_not_scored() {
        let mut printed = thesis(&[(0, 100, 1.0)]);
        printed.duplicate_of = Some("IV.13".into());
        let r = run(&[(0, 300, 9.0)]);
        let v = of(&section(&r, &printed), None, None);
        assert_eq!(v.label(), "thesis duplicate of IV.13: not scored");
        assert_eq!(v.class(), "verdict neutral");
        let mut figure = thesis(&[]);
        figure.columns.clear();
        assert_eq!(
            of(&section(&r, &figure), None, None).label(),
            "figure: no printed table"
        );
    }

    #[test]
    fn thesis_table_numbers() {
        assert_eq!(thesis_table_number("IV.1"), Some(1));
        assert_eq!(thesis_table_number("IV.75"), Some(75));
        assert_eq!(thesis_table_number("IV.76"), None);
        assert_eq!(thesis_table_number("fig-IV.54"), None);
        assert_eq!(thesis_table_number("my-scene"), None);
    }
}
