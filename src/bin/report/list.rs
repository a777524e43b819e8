//! `report --list`: the experiments of a folder without running them — id, family, rows of the
//! tier, and the predictions the scheduler works with (cells of the last solve, peak memory),
//! with the seconds of the last run into `--out` or a rough guess; a file that does not load is
//! listed with its error.

use std::fmt::Write as _;
use std::fs;
use std::path::Path;

use tribo::experiment::{Experiment, Loaded};
use tribo::study::{self, budget, Schedule, Tier};

/// Seconds per predicted active cell, summed over a run's solves, per family: the medians over
/// each family's tables of a full report of 1305b16 on a 2-core machine (seconds of all phases /
/// Σ predicted cells). Within a family the tables spread by up to 50× (the Signorini
/// iterations, the active sets), so the guess is an order of magnitude, marked `~`.
fn seconds_per_cell(family: &str) -> f64 {
    match family {
        "elasticity" => 1.4e-5,
        "contact" => 6e-5,
        "model-contact" => 2e-4,
        "reynolds" => 1.3e-5,
        "substokes" | "model-fluid" => 5e-5,
        _ => 1e-5,
    }
}

/// A guess of the seconds of a table's own run (no readings, no uniform run).
fn guessed_seconds(experiment: &Experiment, tier: Tier) -> f64 {
    let (_, sum) = study::Budget::predicted_size(experiment, Schedule::of(experiment, tier));
    sum * seconds_per_cell(experiment.family.facts().id)
}

/// The seconds of all phases of `<folder>/data/<stem>.csv`, the table's last run into
/// `folder`, if it has `rows` rows (the tier's: a run of the other tier has other rows, where
/// the tiers differ).
fn measured_seconds(folder: &Path, stem: &str, rows: usize) -> Option<f64> {
    let text = fs::read_to_string(folder.join("data").join(format!("{stem}.csv"))).ok()?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next()?.split(',').collect();
    let timed: Vec<usize> = (0..header.len())
        .filter(|&i| header[i].starts_with("seconds_"))
        .collect();
    let rows_of_file: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    if timed.is_empty() || rows_of_file.len() != rows {
        return None;
    }
    let cell = |row: &Vec<&str>, i: usize| row.get(i).and_then(|v| v.parse::<f64>().ok());
    Some(
        rows_of_file
            .iter()
            .flat_map(|row| timed.iter().map(move |&i| cell(row, i).unwrap_or(0.0)))
            .sum(),
    )
}

/// The listing of `loaded` at `tier`, one line per file, with the seconds measured in the
/// output folder `folder`, and whether every file loaded.
pub fn listing(loaded: &[Loaded], tier: Tier, folder: &Path) -> (String, bool) {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:<28} {:<14} {:>5} {:>12} {:>10} {:>9}",
        "id", "family", "rows", "last cells", "memory", "seconds"
    );
    let mut all = true;
    for (stem, outcome) in loaded {
        match outcome {
            Ok(e) => {
                let schedule = Schedule::of(e, tier);
                let (last, _) = study::Budget::predicted_size(e, schedule);
                let memory = study::Budget::predicted_peak(e, schedule);
                let _ = writeln!(
                    out,
                    "{:<28} {:<14} {:>5} {:>12.0} {:>10} {:>9}",
                    stem,
                    e.family.facts().id,
                    schedule.printed,
                    last,
                    budget::human(memory),
                    measured_seconds(folder, stem, schedule.printed)
                        .map_or_else(|| rough(guessed_seconds(e, tier)), |s| format!("{s:.1}"))
                );
            }
            Err(error) => {
                all = false;
                let first = error.to_string();
                let first = first.lines().next().unwrap_or_default();
                let _ = writeln!(out, "{stem:<28} does not load: {first}");
            }
        }
    }
    let _ = writeln!(
        out,
        "({} tier; cells and memory as the scheduler predicts them; seconds of all phases of \
         the table's own run: measured by the last run into {} where it has the table, else \
         `~` an order-of-magnitude guess; its alternative readings and uniform run not counted)",
        tier.name(),
        folder.display()
    );
    (out, all)
}

/// Seconds to one or two significant digits, marked as a guess.
fn rough(seconds: f64) -> String {
    if seconds < 1.0 {
        "<1".into()
    } else if seconds < 10.0 {
        format!("~{seconds:.0}")
    } else {
        let scale = 10f64.powi(seconds.log10().floor() as i32 - 1);
        format!("~{:.0}", (seconds / scale).round() * scale)
    }
}
