//! Where a report comes from: the tribo version and commit, the date, the machine and the command
//! line, shown in the page header so that a page found later can be traced to its run.

use std::path::Path;
use std::process::Command;
use std::time::{SystemTime, UNIX_EPOCH};

/// The facts of one report run; every field is text ready for the page, `unknown` where the
/// fact could not be found.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Provenance {
    /// The git commit of the source tree (12 hex digits), with `+ local changes` when tracked
    /// files differ from it; `unknown` outside a git checkout.
    pub commit: String,
    /// The UTC date and time the run started, `YYYY-MM-DD HH:MM UTC`.
    pub date: String,
    /// Logical cores and memory of the machine, e.g. `2 cores, 23.4 GiB`.
    pub machine: String,
    /// The command line, arguments separated by spaces.
    pub command: String,
}

impl Provenance {
    /// Collect the facts now, for a run with these command-line arguments; `source` is the
    /// source tree whose commit is recorded (the crate's folder).
    pub fn collect(args: impl IntoIterator<Item = String>, source: &Path) -> Provenance {
        let seconds = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| d.as_secs());
        let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
        let memory = crate::machine::machine_memory().map_or("unknown memory".into(), |b| {
            format!("{:.1} GiB", b / (1024.0 * 1024.0 * 1024.0))
        });
        Provenance {
            commit: commit(source).unwrap_or_else(|| "unknown".into()),
            date: utc_date(seconds),
            machine: format!("{cores} cores, {memory}"),
            command: args.into_iter().collect::<Vec<_>>().join(" "),
        }
    }
}

/// `git rev-parse` of `source`'s HEAD, marked when tracked files have local changes.
fn commit(source: &Path) -> Option<String> {
    let git = |args: &[&str]| {
        let out = Command::new("git")
            .arg("-C")
            .arg(source)
            .args(args)
            .output()
            .ok()?;
        out.status
            .success()
            .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
    };
    let head = git(&["rev-parse", "--short=12", "HEAD"])?;
    let changed = git(&["status", "--porcelain", "--untracked-files=no"])?;
    Some(if changed.is_empty() {
        head
    } else {
        format!("{head} + local changes")
    })
}

/// `YYYY-MM-DD HH:MM UTC` of seconds since 1970-01-01 00:00 UTC (the proleptic Gregorian
/// calendar, days converted through 400-year eras of 146 097 days).
pub fn utc_date(seconds: u64) -> String {
    let days = (seconds / 86_400) as i64;
    let (hour, minute) = ((seconds % 86_400) / 3600, (seconds % 3600) / 60);
    // Shift the epoch to 0000-03-01 so that the leap day ends a year.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let day_of_era = z.rem_euclid(146_097);
    let year_of_era =
        (day_of_era - day_of_era / 1460 + day_of_era / 36_524 - day_of_era / 146_096) / 365;
    let day_of_year = day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
    let month_index = (5 * day_of_year + 2) / 153; // 0 = March
    let day = day_of_year - (153 * month_index + 2) / 5 + 1;
    let month = if month_index < 10 {
        month_index + 3
    } else {
        month_index - 9
    };
    let year = year_of_era + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02} {hour:02}:{minute:02} UTC")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Dates across leap days, century rules and the epoch.
    #[test]
    fn utc_dates() {
        assert_eq!(utc_date(0), "1970-01-01 00:00 UTC");
        assert_eq!(utc_date(951_782_400), "2000-02-29 00:00 UTC");
        assert_eq!(utc_date(951_868_800), "2000-03-01 00:00 UTC");
        assert_eq!(utc_date(4_107_542_400), "2100-03-01 00:00 UTC");
        // 2026-11-24 16:40 UTC.
        assert_eq!(utc_date(1_795_538_400 + 60), "2026-11-24 16:41 UTC");
    }

    /// The crate's own folder is a git checkout in development; elsewhere `unknown`.
    #[test]
    fn commit_of_a_folder_without_git_is_none() {
        assert_eq!(commit(Path::new("/")), None);
    }
}
