//! The defects of the printed thesis that tribo found while reproducing Chapter IV: duplicated
//! tables and columns, spikes and rounding noise, contradictions between the text and the tables,
//! garbled or missing formulas and parameters — each with its evidence and the reading tribo uses.
//!
//! The texts are data, `text/errata.toml` (compiled into the binary and read at first use; the
//! test `the_errata_file_parses` keeps it well-formed): [`errata`] is the list the report renders
//! as its errata section, linked from every table it affects ([`errata_for`]).
//! [`known_difference`] is the one-sentence reason, per table, why tribo's numbers differ from
//! the printed ones where the notes explain it; a table whose difference is not explained has no
//! entry.

use std::sync::OnceLock;

use serde::Deserialize;

/// What kind of defect an [`Erratum`] is (in the file: the variant's name in kebab case).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ErratumKind {
    /// A table (or a column) printed as a copy of another.
    Duplicate,
    /// A single printed value far off the trend of its neighbours.
    Spike,
    /// Rounding or solver noise in the printed numbers (ties, iterative solvers).
    Noise,
    /// The text says one thing, a table or another passage another.
    Contradiction,
    /// A formula or algorithm printed wrongly or unreadably.
    Garbled,
    /// A typo in an equation or a reference, with no other consequence.
    Typo,
    /// A parameter or condition the computation needs that the thesis never states.
    Missing,
}

impl ErratumKind {
    /// The kind as the errata section names it.
    pub fn name(self) -> &'static str {
        match self {
            ErratumKind::Duplicate => "duplicate",
            ErratumKind::Spike => "spike",
            ErratumKind::Noise => "rounding or solver noise",
            ErratumKind::Contradiction => "contradiction",
            ErratumKind::Garbled => "garbled formula",
            ErratumKind::Typo => "typo",
            ErratumKind::Missing => "missing data",
        }
    }
}

/// One defect of the printed thesis.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Erratum {
    /// The anchor of the erratum on the page (`erratum-IV.17-duplicate`).
    pub id: String,
    pub title: String,
    pub kind: ErratumKind,
    /// The tables (experiment ids) whose printed numbers or scene it affects.
    pub tables: Vec<String>,
    /// What the thesis prints, and where.
    pub evidence: String,
    /// The reading tribo uses.
    pub reading: String,
}

/// Why tribo's numbers differ from the printed ones, as the verdict column names it (in the
/// file: the variant's name in kebab case).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DifferenceKind {
    /// A defect of the printed table (see [`errata`]).
    Erratum,
    /// The printed table is a copy of another one.
    Duplicate,
    /// Rounding noise or the iterative solver of the thesis chose other cells among equal ones.
    SolverNoise,
    /// An estimator (or a term of one) whose constants or terms the printed numbers do not fix.
    UncalibratedEstimator,
    /// The thesis's code evidently used another reading of the model than the one printed.
    Reading,
}

impl DifferenceKind {
    pub fn name(self) -> &'static str {
        match self {
            DifferenceKind::Erratum => "thesis erratum",
            DifferenceKind::Duplicate => "duplicate in the thesis",
            DifferenceKind::SolverNoise => "thesis solver noise",
            DifferenceKind::UncalibratedEstimator => "uncalibrated estimator",
            DifferenceKind::Reading => "reading of the thesis's code",
        }
    }
}

/// The known reason a table differs from the printed one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct KnownDifference {
    pub kind: DifferenceKind,
    /// One sentence.
    pub reason: &'static str,
}

/// The known difference of some tables, as the file writes it.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Difference {
    tables: Vec<String>,
    kind: DifferenceKind,
    reason: String,
}

/// `text/errata.toml`: the errata in the order of the thesis and the known differences.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ErrataFile {
    erratum: Vec<Erratum>,
    difference: Vec<Difference>,
}

/// The errata file as shipped.
const ERRATA_TOML: &str = include_str!("text/errata.toml");

/// Parse an errata file and check what the types cannot: anchors unique and starting with
/// `erratum-`, every erratum and difference naming a table, no table with two differences.
pub fn parse(text: &str) -> Result<ErrataFile, String> {
    let file: ErrataFile = toml::from_str(text).map_err(|e| e.to_string())?;
    let mut anchors = std::collections::BTreeSet::new();
    for e in &file.erratum {
        if !e.id.starts_with("erratum-") || !anchors.insert(e.id.as_str()) {
            return Err(format!(
                "erratum {}: the id must be new and start with erratum-",
                e.id
            ));
        }
        if e.tables.is_empty() {
            return Err(format!("erratum {} affects no table", e.id));
        }
    }
    let mut explained = std::collections::BTreeSet::new();
    for d in &file.difference {
        if d.tables.is_empty() {
            return Err(format!("a difference without tables: {}", d.reason));
        }
        if let Some(t) = d.tables.iter().find(|t| !explained.insert(t.as_str())) {
            return Err(format!("{t} has two known differences"));
        }
    }
    Ok(file)
}

/// The shipped errata file, parsed at first use.
fn file() -> &'static ErrataFile {
    static FILE: OnceLock<ErrataFile> = OnceLock::new();
    FILE.get_or_init(|| {
        // Checked by the test `the_errata_file_parses`: a broken file fails the tests, it does
        // not reach a user.
        parse(ERRATA_TOML).unwrap_or_else(|e| panic!("src/report/text/errata.toml: {e}"))
    })
}

/// Every thesis defect tribo found, in the order of the thesis.
pub fn errata() -> &'static [Erratum] {
    &file().erratum
}

/// The errata that affect `table`, in the order of [`errata`].
pub fn errata_for(table: &str) -> Vec<&'static Erratum> {
    errata()
        .iter()
        .filter(|e| e.tables.iter().any(|t| t == table))
        .collect()
}

/// The erratum with anchor `id`.
pub fn erratum(id: &str) -> Option<&'static Erratum> {
    errata().iter().find(|e| e.id == id)
}

/// Why tribo's numbers for `table` differ from the printed ones, where the table's notes explain
/// it; `None` where they agree or the difference is not explained (the SubStokes tables whose
/// dofs and estimates differ without a found reason have no entry).
pub fn known_difference(table: &str) -> Option<KnownDifference> {
    file()
        .difference
        .iter()
        .find(|d| d.tables.iter().any(|t| t == table))
        .map(|d| KnownDifference {
            kind: d.kind,
            reason: &d.reason,
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_errata_file_parses() {
        let file = parse(ERRATA_TOML).unwrap();
        assert!(file.erratum.len() > 30 && file.difference.len() > 10);
        assert!(parse("erratum = []\ndifference = []\nnew = 1").is_err());
        let twice = "erratum = []\n[[difference]]\ntables = [\"IV.1\"]\nkind = \"reading\"\n\
                     reason = \"r\"\n[[difference]]\ntables = [\"IV.1\"]\nkind = \"reading\"\n\
                     reason = \"s\"";
        assert_eq!(parse(twice).unwrap_err(), "IV.1 has two known differences");
    }
}
