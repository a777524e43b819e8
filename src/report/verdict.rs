//! The verdict per table: reproduced, or what holds and what differs — decided on the columns
//! the table is about, its *primary* columns.
//!
//! Each family names its primary columns with a band per column (`text/families.toml`,
//! [`families::primary_columns`]): dofs and estimate for elasticity, z-contact and the fluids
//! (the fluids' estimate compared one solve late, `compared_value`), the contact and gap
//! estimates too for Signorini contact, the face split and the model error for the
//! model-adaptive tables on their fixed mesh, and further the three estimate parts with the
//! dofs for model and grid adaptivity. A table is *reproduced* only when every primary column
//! of every printed row that tribo computed lies within its band; otherwise the verdict names
//! the columns that hold and those that differ, with the reason where the report knows it.
//! Its severity is the worst primary deviation, in three bands: within the bands, up to
//! [`FAR`], beyond. A table the thesis prints as a copy of another is not scored (its printed
//! numbers belong to the other scene); a figure experiment and a scene without a printed table
//! have nothing to be scored against.

use super::families::{self, Primary};
use super::{compared_value, Section};
use crate::results::Row;
use crate::thesis::ThesisTable;

/// The primary columns of a table of no family (and of a family without verdict blocks): the
/// two every grid-adaptive table prints.
const DEFAULT_PRIMARY: [Band<'static>; 2] = [
    Band {
        column: "dofs",
        name: "dofs",
        band: 0.03,
        zero_below: 0.0,
    },
    Band {
        column: "estimate",
        name: "estimate",
        band: 0.05,
        zero_below: 0.0,
    },
];

/// A deviation beyond this is far (red); within the bands is reproduced (green), between the
/// two near (amber).
pub const FAR: f64 = 0.15;

/// A primary column with its band, borrowed from the families file or `DEFAULT_PRIMARY`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Band<'a> {
    pub column: &'a str,
    pub name: &'a str,
    pub band: f64,
    pub zero_below: f64,
}

impl<'a> From<&'a Primary> for Band<'a> {
    fn from(p: &'a Primary) -> Self {
        Band {
            column: &p.column,
            name: &p.name,
            band: p.band,
            zero_below: p.zero_below,
        }
    }
}

/// The primary columns of `table`.
pub fn primary_of(table: &str) -> Vec<Band<'static>> {
    match families::primary_columns(table) {
        Some(p) => p.iter().map(Band::from).collect(),
        None => DEFAULT_PRIMARY.to_vec(),
    }
}

/// tribo/thesis − 1 of one value, where values of magnitude at most `zero_below` are 0: 0 when
/// both are 0, ±∞ when only the printed one is; `None` when either is missing or not finite.
pub fn deviation(tribo: f64, printed: f64, zero_below: f64) -> Option<f64> {
    if !(tribo.is_finite() && printed.is_finite()) {
        return None;
    }
    let zero = |v: f64| v.abs() <= zero_below;
    match (zero(tribo), zero(printed)) {
        (true, true) => Some(0.0),
        (false, true) => Some(f64::INFINITY.copysign(tribo)),
        _ => Some(tribo / printed - 1.0),
    }
}

/// How one primary column compares over the printed rows tribo computed.
#[derive(Clone, Debug, PartialEq)]
pub struct ColumnScore {
    pub column: String,
    pub name: String,
    pub band: f64,
    /// Rows with both a printed and a computed value.
    pub rows: usize,
    /// Of those, the rows within the band.
    pub within: usize,
    /// The finite signed deviation of largest magnitude.
    pub worst: Option<f64>,
    /// Rows where the thesis prints 0 and tribo's value is not 0 (no finite deviation).
    pub against_zero: usize,
}

impl ColumnScore {
    /// Every compared row within the band (and at least one compared).
    pub fn holds(&self) -> bool {
        self.rows > 0 && self.within == self.rows
    }

    /// The worst deviation for ranking: ∞ when some row is not 0 where the thesis prints 0.
    pub fn severity(&self) -> f64 {
        if self.against_zero > 0 {
            f64::INFINITY
        } else {
            self.worst.map_or(0.0, f64::abs)
        }
    }

    /// The worst deviation in words: `+185.0 %`, and the rows that are not 0 where the thesis
    /// prints 0.
    pub fn describe(&self) -> String {
        let zeros = match self.against_zero {
            0 => None,
            1 => Some("not 0 in 1 row printed 0".to_string()),
            n => Some(format!("not 0 in {n} rows printed 0")),
        };
        match (self.worst.map(fmt_deviation), zeros) {
            (Some(d), None) => d,
            (Some(d), Some(z)) => format!("{d}; {z}"),
            (None, Some(z)) => z,
            (None, None) => "—".into(),
        }
    }
}

/// Rows within their bands: `within` of `scored` rows that have a primary column printed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RowsWithin {
    pub within: usize,
    pub scored: usize,
}

/// The comparison of a table's primary columns with the printed ones.
#[derive(Clone, Debug, PartialEq)]
pub struct Score {
    /// The primary columns the thesis prints, in the order of the families file.
    pub columns: Vec<ColumnScore>,
    pub rows: RowsWithin,
}

impl Score {
    /// Every primary column of every compared row within its band.
    pub fn reproduced(&self) -> bool {
        self.rows.scored > 0 && self.columns.iter().all(|c| c.rows == 0 || c.holds())
    }

    /// The column with the worst deviation ([`ColumnScore::severity`]); the first of equals.
    pub fn worst(&self) -> Option<&ColumnScore> {
        self.columns
            .iter()
            .rev()
            .max_by(|a, b| a.severity().total_cmp(&b.severity()))
    }

    /// The severity: the worst |Δ| of a primary column (0 with nothing compared, ∞ where a
    /// value is not 0 that the thesis prints as 0).
    pub fn severity(&self) -> f64 {
        self.worst().map_or(0.0, ColumnScore::severity)
    }

    /// The band of the severity: `ok` (reproduced), `near` (worst |Δ| ≤ [`FAR`]) or `off`.
    pub fn band(&self) -> &'static str {
        if self.reproduced() {
            "ok"
        } else if self.severity() <= FAR {
            "near"
        } else {
            "off"
        }
    }
}

/// Score the computed `rows` against the printed table on `primary`: a printed column that is
/// not primary, and a primary column the thesis does not print, are not scored.
pub fn score_rows(rows: &[Row], thesis: &ThesisTable, primary: &[Band]) -> Score {
    let printed: Vec<&Band> = primary
        .iter()
        .filter(|b| thesis.columns.iter().any(|c| c == b.column))
        .collect();
    let mut columns: Vec<ColumnScore> = printed
        .iter()
        .map(|b| ColumnScore {
            column: b.column.to_string(),
            name: b.name.to_string(),
            band: b.band,
            rows: 0,
            within: 0,
            worst: None,
            against_zero: 0,
        })
        .collect();
    let mut out = RowsWithin {
        within: 0,
        scored: 0,
    };
    for (i, row) in rows.iter().enumerate() {
        let mut compared = false;
        let mut all_within = true;
        for (b, score) in printed.iter().zip(columns.iter_mut()) {
            let d = compared_value(rows, i, b.column)
                .zip(thesis.value(row.cycle, b.column))
                .and_then(|(t, p)| deviation(t, p, b.zero_below));
            let Some(d) = d else { continue };
            compared = true;
            score.rows += 1;
            if d.abs() <= b.band {
                score.within += 1;
            } else {
                all_within = false;
            }
            if !d.is_finite() {
                score.against_zero += 1;
            } else if score.worst.is_none_or(|w| d.abs() > w.abs()) {
                score.worst = Some(d);
            }
        }
        if compared {
            out.scored += 1;
            out.within += usize::from(all_within);
        }
    }
    columns.retain(|c| c.rows > 0);
    Score { columns, rows: out }
}

/// [`score_rows`] of a section on its table's primary columns ([`primary_of`]).
pub fn score(section: &Section) -> Score {
    score_rows(
        &section.run.rows,
        section.thesis,
        &primary_of(&section.run.table),
    )
}

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
    /// Every primary column of every compared row within its band.
    Reproduced(Score),
    /// Some primary column outside its band, for the reason the report states (if it knows it).
    Differs {
        score: Score,
        known: Option<KnownReason>,
    },
    /// The printed table is a copy of another table (`of`): not scored.
    Duplicate { of: String },
    /// Nothing printed to score against (a figure experiment, a scene of the user's own).
    NotScored { why: String },
}

/// A deviation as the verdict names it: a signed percentage, with two decimals below 10 % so
/// that a value just outside its band does not read as on it (`+3.04 %`); from a hundredfold
/// on, the factor (`×2369`, `×6.81e7`).
pub fn fmt_deviation(d: f64) -> String {
    let p = d * 100.0;
    let factor = d + 1.0;
    if factor >= 100.0 {
        return if factor < 1e5 {
            format!("×{factor:.0}")
        } else {
            format!("×{factor:.2e}")
        };
    }
    if p == 0.0 {
        "0 %".into()
    } else if p.abs() >= 1000.0 {
        format!("{p:+.0} %")
    } else if p.abs() >= 10.0 {
        format!("{p:+.1} %")
    } else {
        format!("{p:+.2} %")
    }
    .replace('-', "−")
}

/// `a`, `a and b`, `a, b and c`.
fn listing(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [head @ .., last] => format!("{} and {last}", head.join(", ")),
    }
}

impl Verdict {
    /// The words of the verdict: what holds and what differs, with why where it is known.
    pub fn label(&self) -> String {
        match self {
            Verdict::Reproduced(_) => "reproduced".into(),
            Verdict::Differs { score, known } => {
                let held: Vec<String> = score
                    .columns
                    .iter()
                    .filter(|c| c.holds())
                    .map(|c| c.name.clone())
                    .collect();
                let off: Vec<String> = score
                    .columns
                    .iter()
                    .filter(|c| !c.holds())
                    .map(|c| format!("{} ({})", c.name, c.describe()))
                    .collect();
                let verb = if off.len() == 1 { "differs" } else { "differ" };
                let why = match known {
                    Some(r) => format!(": {}", r.kind),
                    None => ", unexplained".into(),
                };
                let held = if held.is_empty() {
                    String::new()
                } else {
                    format!("{} reproduced; ", listing(&held))
                };
                format!("{held}{} {verb}{why}", listing(&off))
            }
            Verdict::Duplicate { of } => format!("thesis duplicate of {of}: not scored"),
            Verdict::NotScored { why } => why.clone(),
        }
    }

    /// The verdict in a few words, for the front page's summary: `reproduced`, or how many
    /// primary columns differ and why (`3 of 7 columns differ: uncalibrated estimator`); the
    /// columns themselves are in [`Verdict::label`].
    pub fn short_label(&self) -> String {
        match self {
            Verdict::Differs { score, known } => {
                let off = score.columns.iter().filter(|c| !c.holds()).count();
                let why = match known {
                    Some(r) => format!(": {}", r.kind),
                    None => ", unexplained".into(),
                };
                let verb = if off == 1 { "differs" } else { "differ" };
                format!("{off} of {} columns {verb}{why}", score.columns.len())
            }
            Verdict::Duplicate { of } => format!("duplicate of {of}"),
            _ => self.label(),
        }
    }

    /// The score, for a table that was scored.
    pub fn score(&self) -> Option<&Score> {
        match self {
            Verdict::Reproduced(s) | Verdict::Differs { score: s, .. } => Some(s),
            _ => None,
        }
    }

    /// The word of a machine reading of the page (`data-verdict`): `reproduced`, `differs`,
    /// `duplicate` or `not-scored`.
    pub fn kind(&self) -> &'static str {
        match self {
            Verdict::Reproduced(_) => "reproduced",
            Verdict::Differs { .. } => "differs",
            Verdict::Duplicate { .. } => "duplicate",
            Verdict::NotScored { .. } => "not-scored",
        }
    }

    /// The CSS class of the verdict: by severity green (`ok`), amber (`near`) or red (`off`),
    /// neutral when not scored.
    pub fn class(&self) -> String {
        match self.score() {
            Some(s) => format!("verdict {}", s.band()),
            None => "verdict neutral".into(),
        }
    }
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
    let score = score(section);
    if score.rows.scored == 0 {
        return Verdict::NotScored {
            why: "no printed row computed".into(),
        };
    }
    if score.reproduced() {
        Verdict::Reproduced(score)
    } else {
        Verdict::Differs { score, known }
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

    /// A run of `table` with `columns` (after `cycle`; names ending in `faces` or `dofs` are
    /// counts) and one row per cycle.
    fn run(table: &str, columns: &[&str], rows: &[Vec<f64>]) -> RunResult {
        let mut r = RunResult::new(table, "IV", "t", "full", [0.0, 1.0, 0.0, 1.0]);
        r.rows = rows
            .iter()
            .enumerate()
            .map(|(cycle, values)| {
                columns
                    .iter()
                    .zip(values)
                    .fold(Row::new(cycle), |row, (c, v)| {
                        if c.ends_with("faces") || *c == "dofs" {
                            row.count(c, *v as usize)
                        } else {
                            row.real(c, Some(*v))
                        }
                    })
            })
            .collect();
        r
    }

    fn thesis(table: &str, columns: &[&str], rows: &[Vec<f64>]) -> ThesisTable {
        ThesisTable {
            table: table.into(),
            section: "IV".into(),
            columns: std::iter::once("cycle")
                .chain(columns.iter().copied())
                .map(String::from)
                .collect(),
            rows: rows
                .iter()
                .enumerate()
                .map(|(cycle, r)| std::iter::once(cycle as f64).chain(r.clone()).collect())
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

    const ELASTICITY: [&str; 2] = ["dofs", "estimate"];

    #[test]
    fn rows_are_within_their_bands_up_to_three_and_five_percent() {
        let printed = thesis(
            "IV.1",
            &ELASTICITY,
            &[vec![100.0, 1.0], vec![200.0, 0.7], vec![400.0, 0.5]],
        );
        let same = run(
            "IV.1",
            &ELASTICITY,
            &[vec![100.0, 1.0], vec![205.0, 0.72], vec![400.0, 0.5]],
        );
        let s = section(&same, &printed);
        let v = of(&s, None, None);
        assert_eq!(v.label(), "reproduced");
        assert_eq!(v.class(), "verdict ok");
        assert_eq!(
            v.score().unwrap().rows,
            RowsWithin {
                within: 3,
                scored: 3
            }
        );

        // dofs +5 % (beyond 3 %) in cycle 1, estimate +6 % (beyond 5 %) in cycle 2.
        let off = run(
            "IV.1",
            &ELASTICITY,
            &[vec![100.0, 1.0], vec![210.0, 0.7], vec![400.0, 0.53]],
        );
        let s = section(&off, &printed);
        let v = of(&s, None, None);
        assert_eq!(
            v.label(),
            "dofs (+5.00 %) and estimate (+6.00 %) differ, unexplained"
        );
        assert_eq!(v.class(), "verdict near");
        assert_eq!(
            v.score().unwrap().rows,
            RowsWithin {
                within: 1,
                scored: 3
            }
        );
        let known = KnownReason {
            kind: "solver noise".into(),
            reason: "ties".into(),
            anchor: None,
        };
        assert_eq!(
            of(&s, Some(known), None).label(),
            "dofs (+5.00 %) and estimate (+6.00 %) differ: solver noise"
        );
        assert_eq!(
            of(&s, None, Some("edited: not scored".into())).label(),
            "edited: not scored"
        );
    }

    /// A model-adaptive table on its fixed mesh: dofs and cells match by construction and do not
    /// make it reproduced; the verdict names the faces and the model error.
    #[test]
    fn a_fixed_mesh_table_is_judged_on_its_faces_and_model_error() {
        let columns = [
            "coarse_faces",
            "accurate_faces",
            "active_cells",
            "dofs",
            "model_error",
        ];
        let printed = thesis(
            "IV.21",
            &columns,
            &[
                vec![512.0, 0.0, 1472.0, 3980.0, 0.028],
                vec![500.0, 12.0, 1472.0, 3980.0, 0.0048],
                vec![492.0, 20.0, 1472.0, 3980.0, 1.029e-11],
            ],
        );
        let computed = run(
            "IV.21",
            &columns,
            &[
                vec![512.0, 0.0, 1472.0, 3980.0, 0.073],
                vec![500.0, 12.0, 1472.0, 3980.0, 0.044],
                vec![455.0, 57.0, 1472.0, 3980.0, 0.0],
            ],
        );
        let v = of(&section(&computed, &printed), None, None);
        let score = v.score().unwrap();
        let names: Vec<&str> = score.columns.iter().map(|c| c.column.as_str()).collect();
        assert_eq!(names, ["coarse_faces", "accurate_faces", "model_error"]);
        assert_eq!(
            v.label(),
            "z-faces (−7.52 %), Signorini faces (+185.0 %) and model error (+816.7 %) differ, \
             unexplained"
        );
        assert_eq!(v.class(), "verdict off");
        // The printed 1e-11 of cycle 2 is a vanished model error, as tribo's 0.
        let model = &score.columns[2];
        assert_eq!((model.rows, model.within), (3, 1));
        let worst = score.worst().unwrap();
        assert_eq!(worst.column, "model_error");
        assert!((worst.severity() - (0.044 / 0.0048 - 1.0)).abs() < 1e-12);
        // A model error where the thesis prints 0 is the worst there is, and said so.
        let mut zero = printed.clone();
        zero.rows[1][5] = 0.0;
        let v = of(&section(&computed, &zero), None, None);
        let model = &v.score().unwrap().columns[2];
        assert_eq!(model.against_zero, 1);
        assert_eq!(model.describe(), "+160.7 %; not 0 in 1 row printed 0");
        assert_eq!(v.score().unwrap().severity(), f64::INFINITY);

        // The same faces and model errors within 5 %: reproduced.
        let close = run(
            "IV.21",
            &columns,
            &[
                vec![512.0, 0.0, 1472.0, 3980.0, 0.0285],
                vec![500.0, 12.0, 1472.0, 3980.0, 0.0049],
                vec![492.0, 20.0, 1472.0, 3980.0, 0.0],
            ],
        );
        assert_eq!(
            of(&section(&close, &printed), None, None).label(),
            "reproduced"
        );
    }

    #[test]
    fn deviations_treat_zero_on_both_sides_as_equal() {
        assert_eq!(deviation(0.0, 0.0, 0.0), Some(0.0));
        assert_eq!(deviation(1e-12, 1.029e-11, 1e-9), Some(0.0));
        assert_eq!(deviation(5.0, 0.0, 0.0), Some(f64::INFINITY));
        assert_eq!(deviation(0.0, 2.0, 0.0), Some(-1.0));
        assert_eq!(deviation(f64::NAN, 2.0, 0.0), None);
        assert_eq!(fmt_deviation(-0.878), "−87.8 %");
        assert_eq!(fmt_deviation(0.0304), "+3.04 %");
        assert_eq!(fmt_deviation(2369.4), "×2370");
        assert_eq!(fmt_deviation(68_081_557.19), "×6.81e7");
        assert_eq!(fmt_deviation(30.3), "+3030 %");
    }

    /// The property the report's verdicts rest on, over many constructed tables of every shape
    /// the families file names: whenever the verdict is "reproduced", every primary column of
    /// every row is within its band; and whenever every such column is, the verdict is
    /// "reproduced".
    #[test]
    fn reproduced_means_every_primary_column_of_every_row_within_its_band() {
        let shapes: [(&str, &[&str]); 4] = [
            ("IV.1", &ELASTICITY),
            (
                "IV.12",
                &["dofs", "estimate", "contact_estimate", "gap_estimate"],
            ),
            (
                "IV.20",
                &["coarse_faces", "accurate_faces", "dofs", "model_error"],
            ),
            (
                "IV.31",
                &[
                    "z_faces",
                    "s_faces",
                    "dofs",
                    "model_error",
                    "est_z_boundary",
                    "est_s_boundary",
                    "est_interior",
                ],
            ),
        ];
        let factors = [1.0, 1.02, 0.975, 1.04, 1.06, 0.9, 2.0];
        let mut reproduced = 0;
        for (table, columns) in shapes {
            let bands = primary_of(table);
            let printed_rows: Vec<Vec<f64>> = (0..3)
                .map(|c| columns.iter().map(|_| 1200.0 / (c + 1) as f64).collect())
                .collect();
            let printed = thesis(table, columns, &printed_rows);
            for (k, f) in factors.iter().enumerate() {
                for col in 0..columns.len() {
                    let rows: Vec<Vec<f64>> = printed_rows
                        .iter()
                        .enumerate()
                        .map(|(i, r)| {
                            let mut r = r.clone();
                            if i == k % 3 {
                                r[col] = (r[col] * f).round();
                            }
                            r
                        })
                        .collect();
                    let computed = run(table, columns, &rows);
                    let v = of(&section(&computed, &printed), None, None);
                    let all_within = bands.iter().all(|b| {
                        let Some(c) = columns.iter().position(|c| *c == b.column) else {
                            return true;
                        };
                        rows.iter()
                            .zip(&printed_rows)
                            .all(|(t, p)| (t[c] / p[c] - 1.0).abs() <= b.band)
                    });
                    assert_eq!(
                        matches!(v, Verdict::Reproduced(_)),
                        all_within,
                        "{table}, column {}, factor {f}: {}",
                        columns[col],
                        v.label()
                    );
                    reproduced += usize::from(all_within);
                }
            }
        }
        // Both outcomes occur.
        assert!(reproduced > 10 && reproduced < 100, "{reproduced}");
    }

    #[test]
    fn severity_has_three_bands() {
        let printed = thesis("IV.57", &ELASTICITY, &[vec![100.0, 1.0]]);
        let class = |dofs: f64, estimate: f64| {
            let r = run("IV.57", &ELASTICITY, &[vec![dofs, estimate]]);
            of(&section(&r, &printed), None, None).class()
        };
        assert_eq!(class(102.0, 1.04), "verdict ok");
        assert_eq!(class(104.0, 1.0), "verdict near");
        assert_eq!(class(100.0, 0.122), "verdict off");
    }

    #[test]
    fn duplicates_and_figures_are_not_scored() {
        let mut printed = thesis("IV.17", &ELASTICITY, &[vec![100.0, 1.0]]);
        printed.duplicate_of = Some("IV.13".into());
        let r = run("IV.17", &ELASTICITY, &[vec![300.0, 9.0]]);
        let v = of(&section(&r, &printed), None, None);
        assert_eq!(v.label(), "thesis duplicate of IV.13: not scored");
        assert_eq!(v.class(), "verdict neutral");
        let mut figure = thesis("IV.17", &[], &[]);
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
