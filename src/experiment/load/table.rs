//! The CSV profiles of tabulated gaps and obstacles: read next to the experiment file, checked
//! row by row, and put into the parsed file before the other checks see it.
//!
//! A profile is a text file of two columns: a header line naming them (`x1,g` for a gap,
//! `x1,b` for an obstacle), then one row `x₁,value` per line, x₁ strictly increasing. Blank
//! lines and lines starting with `#` are skipped; a byte-order mark and Windows line ends, as
//! spreadsheets write them, are accepted. Every message names the experiment file, the
//! field (`scene.reynolds.gap.file`), the CSV file and the line.

use std::fs;
use std::io::Read;
use std::path::{Path, PathBuf};

use super::check::{Check, Checked};
use super::listing::file_kind;
use crate::experiment::spec::*;
use crate::experiment::ExperimentError;

/// Largest profile read, in bytes: a profile of a hundred thousand rows has about 4 MB.
const MAX_PROFILE_BYTES: u64 = 16 * 1024 * 1024;
/// Most rows of a profile.
const MAX_ROWS: usize = 100_000;

/// What a profile tabulates: its column, the least number of rows and whether its values must
/// be positive.
#[derive(Clone, Copy)]
pub(super) struct Column {
    /// The name of the second column in the header.
    name: &'static str,
    /// What the values are, for messages.
    meaning: &'static str,
    min_rows: usize,
    positive: bool,
}

/// A gap profile: `x1,g`, g > 0, at least 4 rows (the cubic spline through them).
pub(super) const GAP: Column = Column {
    name: "g",
    meaning: "the gap width",
    min_rows: 4,
    positive: true,
};

/// An obstacle profile: `x1,b`, at least 2 rows (the straight lines between them).
pub(super) const OBSTACLE: Column = Column {
    name: "b",
    meaning: "the obstacle height",
    min_rows: 2,
    positive: false,
};

impl Check<'_> {
    /// Reads the CSV profile of every tabulated gap and obstacle of `scene` into its `rows`.
    pub(super) fn read_profiles(&self, scene: &mut SceneFile) -> Checked {
        for (section, film) in [
            (
                "scene.reynolds",
                scene.reynolds.as_mut().map(|r| &mut r.gap),
            ),
            (
                "scene.substokes",
                scene.substokes.as_mut().map(|s| &mut s.gap),
            ),
        ] {
            if let Some(GapShape::Tabulated { file, rows }) = film {
                *rows = self
                    .profile_rows(&format!("{section}.gap.file"), file, GAP)?
                    .into();
            }
        }
        if let Some(contact) = &mut scene.contact {
            for (i, obstacle) in contact.obstacles.iter_mut().enumerate() {
                if let ObstacleShape::Tabulated { file, rows } = &mut obstacle.shape {
                    let field = format!("scene.contact.obstacles[{i}].shape.file");
                    *rows = self.profile_rows(&field, file, OBSTACLE)?.into();
                }
            }
        }
        Ok(())
    }

    /// The profile a file names in `field`, relative to the experiment file's folder.
    pub(super) fn profile_path(&self, file: &str) -> PathBuf {
        self.path.parent().unwrap_or(Path::new("")).join(file)
    }

    /// The rows of the profile `file` named in `field`, checked: the header, two finite numbers
    /// per row, x₁ strictly increasing, positive values where `column` asks for them, at least
    /// `column.min_rows` rows.
    fn profile_rows(
        &self,
        field: &str,
        file: &str,
        column: Column,
    ) -> Result<Vec<[f64; 2]>, ExperimentError> {
        let header = format!("x1,{}", column.name);
        let expected_file = format!(
            "a CSV file with the header `{header}` and one row `x₁,{}` per line, the path \
             relative to the experiment file's folder",
            column.name
        );
        self.ensure(
            !file.trim().is_empty(),
            field,
            &expected_file,
            "an empty file name",
        )?;
        let path = self.profile_path(file);
        let text = read_profile(&path).map_err(|why| self.fail(field, &expected_file, why))?;
        let shown = path.display();
        let mut lines = text
            .strip_prefix('\u{feff}')
            .unwrap_or(&text)
            .lines()
            .enumerate()
            .map(|(i, line)| (i + 1, line.trim()))
            .filter(|(_, line)| !line.is_empty() && !line.starts_with('#'));
        let Some((number, first)) = lines.next() else {
            return Err(self.fail(field, &expected_file, format!("{shown}: no lines")));
        };
        let names: Vec<&str> = first.split(',').map(str::trim).collect();
        self.ensure(
            names == ["x1", column.name],
            field,
            &format!("the header `{header}` on the first line of the CSV file"),
            format!("{shown}, line {number}: `{}`", clip(first)),
        )?;
        let mut rows: Vec<[f64; 2]> = Vec::new();
        let mut previous_line = number;
        for (number, line) in lines {
            let at = format!("{shown}, line {number}");
            self.ensure(
                rows.len() < MAX_ROWS,
                field,
                &format!("at most {MAX_ROWS} rows"),
                format!("{at}: more rows"),
            )?;
            let cells: Vec<&str> = line.split(',').map(str::trim).collect();
            let numbers: Option<Vec<f64>> = (cells.len() == 2)
                .then(|| cells.iter().map(|c| c.parse::<f64>().ok()).collect())
                .flatten();
            let Some([x, value]) = numbers.and_then(|n| <[f64; 2]>::try_from(n).ok()) else {
                return Err(self.fail(
                    field,
                    &format!("two numbers `x₁,{}` separated by a comma", column.name),
                    format!("{at}: `{}`", clip(line)),
                ));
            };
            self.ensure(
                x.is_finite() && value.is_finite(),
                field,
                "finite numbers",
                format!("{at}: x1 = {x:?}, {} = {value:?}", column.name),
            )?;
            if let Some(&[before, _]) = rows.last() {
                self.ensure(
                    x > before,
                    field,
                    "x₁ strictly increasing from row to row",
                    format!("{at}: x1 = {x:?} after x1 = {before:?} on line {previous_line}"),
                )?;
            }
            if column.positive {
                self.ensure(
                    value > 0.0,
                    field,
                    &format!("{} > 0 in every row", column.meaning),
                    format!("{at}: {} = {value:?}", column.name),
                )?;
            }
            rows.push([x, value]);
            previous_line = number;
        }
        self.ensure(
            rows.len() >= column.min_rows,
            field,
            &format!("at least {} rows after the header", column.min_rows),
            format!("{shown}: {} rows", rows.len()),
        )?;
        Ok(rows)
    }

    /// The rows of a profile must reach over the domain's x-range `[x0, x1]`: no extrapolation
    /// inside the domain.
    pub(super) fn profile_covers(
        &self,
        field: &str,
        file: &str,
        rows: &[[f64; 2]],
        domain_x: [f64; 2],
    ) -> Checked {
        let (first, last) = match (rows.first(), rows.last()) {
            (Some(first), Some(last)) => (first[0], last[0]),
            _ => (f64::NAN, f64::NAN),
        };
        self.ensure(
            first <= domain_x[0] && last >= domain_x[1],
            field,
            &format!(
                "rows whose x₁ reach over scene.domain.x = [{:?}, {:?}] (the first x₁ at most \
                 {:?}, the last at least {:?})",
                domain_x[0], domain_x[1], domain_x[0], domain_x[1]
            ),
            format!(
                "{}: x1 from {first:?} to {last:?}",
                self.profile_path(file).display()
            ),
        )
    }
}

/// The text of a profile: a regular file (not a FIFO or a device, which could block or never
/// end) of at most [`MAX_PROFILE_BYTES`], in UTF-8; the error says why not, naming the path.
fn read_profile(path: &Path) -> Result<String, String> {
    let shown = path.display();
    let metadata = fs::metadata(path).map_err(|e| format!("{shown}: cannot read it: {e}"))?;
    if !metadata.is_file() {
        return Err(format!(
            "{shown}: not a regular file ({})",
            file_kind(&metadata.file_type())
        ));
    }
    let too_large = |size: u64| {
        format!("{shown}: {size} bytes, more than the {MAX_PROFILE_BYTES} a profile may have")
    };
    if metadata.len() > MAX_PROFILE_BYTES {
        return Err(too_large(metadata.len()));
    }
    let mut bytes = Vec::new();
    fs::File::open(path)
        .and_then(|f| f.take(MAX_PROFILE_BYTES + 1).read_to_end(&mut bytes))
        .map_err(|e| format!("{shown}: cannot read it: {e}"))?;
    if bytes.len() as u64 > MAX_PROFILE_BYTES {
        return Err(too_large(bytes.len() as u64));
    }
    String::from_utf8(bytes).map_err(|e| {
        let line = 1 + e.as_bytes()[..e.utf8_error().valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        format!("{shown}: not UTF-8 (line {line})")
    })
}

/// A line as the message shows it: at most 80 characters.
fn clip(line: &str) -> String {
    if line.chars().count() <= 80 {
        line.to_owned()
    } else {
        format!("{}…", line.chars().take(80).collect::<String>())
    }
}
