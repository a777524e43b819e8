//! The table families of Chapter IV and what a reader needs once per family: the model and its
//! conventions (unknowns, ψ and the pressure, signs, units, the estimator) and the notes that
//! hold for several tables of the family. The report shows each family's box once, before the
//! first section of that family on the page, and every section of the family links to it.
//!
//! The texts, and which tables belong to which family, are data: `text/families.toml`, compiled
//! into the binary and read at first use (the test `the_families_file_parses` keeps it
//! well-formed).

use std::sync::OnceLock;

use serde::Deserialize;

/// One "model and conventions" item of a family box: a short heading and its text.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelItem {
    pub heading: String,
    pub text: String,
}

/// A note shared by several tables of a family.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FamilyNote {
    /// The tables it holds for; empty (left out in the file) when it holds for every table of
    /// the family.
    #[serde(default)]
    pub tables: Vec<String>,
    pub text: String,
}

/// A column the verdict on a table is decided on, with its band: the table is *reproduced*
/// only when this column of every printed row lies within `band` of the printed value.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Primary {
    /// The printed column (`dofs`, `accurate_faces`, `est_z_boundary`, …).
    pub column: String,
    /// How the verdict names it (`Signorini faces`).
    pub name: String,
    /// The largest |tribo/thesis − 1| that counts as reproduced.
    pub band: f64,
    /// Values of at most this magnitude count as zero on both sides (a model error the thesis
    /// prints as 1e-11 next to tribo's 0): without it a printed 0 is matched by 0 only.
    #[serde(default)]
    pub zero_below: f64,
}

/// The primary columns of some tables of a family.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VerdictColumns {
    /// The tables they decide; empty (left out in the file) for every table of the family that
    /// no other block names.
    #[serde(default)]
    pub tables: Vec<String>,
    pub primary: Vec<Primary>,
}

/// A family of Chapter IV tables with its model box and shared notes.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Family {
    /// The anchor of the family's box on the page (`family-contact`).
    pub id: String,
    pub name: String,
    /// The thesis sections of the family.
    pub sections: String,
    /// The experiment ids of the family's tables and figures.
    pub tables: Vec<String>,
    pub model: Vec<ModelItem>,
    #[serde(default, rename = "note")]
    pub notes: Vec<FamilyNote>,
    /// What the verdict on each of its tables is decided on.
    #[serde(default, rename = "verdict")]
    pub verdicts: Vec<VerdictColumns>,
}

/// `text/families.toml`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FamiliesFile {
    family: Vec<Family>,
}

/// The families file as shipped.
const FAMILIES_TOML: &str = include_str!("text/families.toml");

/// Parse a families file and check what the types cannot: ids unique, no table in two
/// families, and a note's tables among its family's.
pub fn parse(text: &str) -> Result<Vec<Family>, String> {
    let file: FamiliesFile = toml::from_str(text).map_err(|e| e.to_string())?;
    let mut ids = std::collections::BTreeSet::new();
    let mut member = std::collections::BTreeSet::new();
    for f in &file.family {
        if !ids.insert(f.id.as_str()) {
            return Err(format!("family {} twice", f.id));
        }
        if let Some(t) = f.tables.iter().find(|t| !member.insert(t.as_str())) {
            return Err(format!("{t} is in two families"));
        }
        for n in &f.notes {
            if let Some(t) = n.tables.iter().find(|t| !f.tables.contains(t)) {
                return Err(format!("a note of {} names {t}, not of the family", f.id));
            }
        }
        check_verdicts(f)?;
    }
    Ok(file.family)
}

/// The verdict blocks of a family: their tables of the family, no table in two blocks, at most
/// one block for "the others", and every band a positive finite fraction.
fn check_verdicts(f: &Family) -> Result<(), String> {
    let mut named = std::collections::BTreeSet::new();
    let mut rest = 0;
    for v in &f.verdicts {
        if v.tables.is_empty() {
            rest += 1;
        }
        if let Some(t) = v.tables.iter().find(|t| !f.tables.contains(t)) {
            return Err(format!(
                "a verdict of {} names {t}, not of the family",
                f.id
            ));
        }
        if let Some(t) = v.tables.iter().find(|t| !named.insert(t.as_str())) {
            return Err(format!("{t} has two verdict blocks"));
        }
        if v.primary.is_empty() {
            return Err(format!("a verdict of {} has no primary column", f.id));
        }
        if let Some(p) = v
            .primary
            .iter()
            .find(|p| !(p.band.is_finite() && p.band > 0.0 && p.zero_below >= 0.0))
        {
            return Err(format!("{}: band of {} must be > 0", f.id, p.column));
        }
    }
    if rest > 1 {
        return Err(format!("{} has two verdict blocks without tables", f.id));
    }
    Ok(())
}

/// The seven families (six of Chapter IV, then the solver study of §III.2.3.4); parsed at first
/// use.
pub fn families() -> &'static [Family] {
    static FAMILIES: OnceLock<Vec<Family>> = OnceLock::new();
    FAMILIES.get_or_init(|| {
        // Checked by the test `the_families_file_parses`: a broken file fails the tests, it
        // does not reach a user.
        parse(FAMILIES_TOML).unwrap_or_else(|e| panic!("src/report/text/families.toml: {e}"))
    })
}

/// The family of a table id (`IV.36`, `fig-IV.54`, `fig-III.6`); `None` for a table of no family
/// (a scene of the user's own with another id).
pub fn family_of(table: &str) -> Option<&'static Family> {
    families()
        .iter()
        .find(|f| f.tables.iter().any(|t| t == table))
}

/// The primary columns of `table` ([`Primary`]): those of the block of its family that names
/// it, else of the family's block without tables; `None` for a table of no family or a family
/// without verdict blocks.
pub fn primary_columns(table: &str) -> Option<&'static [Primary]> {
    let family = family_of(table)?;
    let named = family
        .verdicts
        .iter()
        .find(|v| v.tables.iter().any(|t| t == table));
    named
        .or_else(|| family.verdicts.iter().find(|v| v.tables.is_empty()))
        .map(|v| v.primary.as_slice())
}

/// The notes of `family` that hold for `table`.
pub fn notes_for(family: &'static Family, table: &str) -> Vec<&'static FamilyNote> {
    family
        .notes
        .iter()
        .filter(|n| n.tables.is_empty() || n.tables.iter().any(|t| t == table))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_families_file_parses() {
        let families = parse(FAMILIES_TOML).unwrap();
        assert_eq!(families.len(), 7);
        let two = "[[family]]\nid = \"a\"\nname = \"A\"\nsections = \"\"\ntables = [\"IV.1\"]\n\
                   model = []\n[[family]]\nid = \"b\"\nname = \"B\"\nsections = \"\"\n\
                   tables = [\"IV.1\"]\nmodel = []";
        assert_eq!(parse(two).unwrap_err(), "IV.1 is in two families");
        assert!(parse("[[family]]\nid = \"a\"").is_err());
    }
}
