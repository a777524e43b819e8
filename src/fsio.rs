//! Files written so that no reader ever finds half of one: each file is written under a
//! temporary name in its own folder and renamed into place when it is complete.
//!
//! A run of `report` can end at any moment (Ctrl-C, `kill`, the machine's OOM killer). Written
//! in place, a file cut off there keeps its final name with a part of its content: a 0-byte
//! `.parquet`, a `.vtu` without its end, a page without its last sections, which look like
//! results. A rename within one folder replaces the old file in one step (POSIX `rename`), so
//! under the final name there is either the previous complete file or the new complete one.
//! What an interruption leaves is the temporary file, whose name ([`is_partial`]) says what it
//! is and which the next run removes ([`remove_partials`]).
//!
//! The data are not forced to the disk (`fsync`) before the rename: that protects against a
//! power cut, not against the end of a process, and it would cost seconds on the gigabytes of a
//! full report.

use std::fs::{self, File};
use std::io;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// What marks a temporary file in its name (after the final name it will get).
const PARTIAL_MARK: &str = ".tribo-partial-";

/// Temporary files made by this process so far, so that two threads writing the same final name
/// never share a temporary one.
static MADE: AtomicU64 = AtomicU64::new(0);

/// The temporary name of `path`: hidden, in the same folder, and ending in neither the final
/// name's extension nor any other, e.g. `data/.IV.1.csv.tribo-partial-4711-3`.
fn partial_path(path: &Path) -> io::Result<PathBuf> {
    let name = path.file_name().ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{} is not a file name", path.display()),
        )
    })?;
    let n = MADE.fetch_add(1, Ordering::Relaxed);
    let mut partial = std::ffi::OsString::from(".");
    partial.push(name);
    partial.push(format!("{PARTIAL_MARK}{}-{n}", std::process::id()));
    Ok(path.with_file_name(partial))
}

/// Whether the file name `name` is a temporary file of this module (one an interrupted run left).
pub fn is_partial(name: &str) -> bool {
    name.starts_with('.') && name.contains(PARTIAL_MARK)
}

/// Write `path` with `fill`, which gets the open temporary file and writes all of it; the file
/// takes its final name only when `fill` succeeded. On an error the temporary file is removed
/// and an earlier file under the final name stays as it was.
pub fn write_with<T, E: From<io::Error>>(
    path: &Path,
    fill: impl FnOnce(File) -> Result<T, E>,
) -> Result<T, E> {
    let partial = partial_path(path)?;
    let file = File::create(&partial)?;
    let done = fill(file).and_then(|value| {
        fs::rename(&partial, path)?;
        Ok(value)
    });
    if done.is_err() {
        // The temporary file is what is left of a failed write: nothing to keep.
        let _ = fs::remove_file(&partial);
    }
    done
}

/// Write `contents` to `path` (as [`std::fs::write`], but all or nothing).
pub fn write(path: &Path, contents: impl AsRef<[u8]>) -> io::Result<()> {
    write_with(path, |mut file| {
        io::Write::write_all(&mut file, contents.as_ref())
    })
}

/// Copy `from` to `to` (as [`std::fs::copy`], but all or nothing).
pub fn copy(from: &Path, to: &Path) -> io::Result<u64> {
    let mut source = File::open(from)?;
    write_with(to, |mut file| io::copy(&mut source, &mut file))
}

/// Remove the temporary files an interrupted run left in `dir` (not in its subfolders); return
/// how many. A folder that does not exist has none.
pub fn remove_partials(dir: &Path) -> io::Result<usize> {
    let entries = match fs::read_dir(dir) {
        Ok(entries) => entries,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(0),
        Err(e) => return Err(e),
    };
    let mut removed = 0;
    for entry in entries {
        let entry = entry?;
        let partial = entry.file_name().to_str().is_some_and(is_partial);
        if partial && entry.file_type()?.is_file() {
            fs::remove_file(entry.path())?;
            removed += 1;
        }
    }
    Ok(removed)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("tribo-fsio-{name}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn a_failed_write_keeps_the_old_file_and_leaves_no_partial() {
        let dir = folder("failed");
        let path = dir.join("a.csv");
        write(&path, "old").unwrap();
        let failed: io::Result<()> = write_with(&path, |mut f| {
            io::Write::write_all(&mut f, b"half")?;
            Err(io::Error::other("cut off"))
        });
        assert!(failed.is_err());
        assert_eq!(fs::read_to_string(&path).unwrap(), "old");
        let names: Vec<_> = fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("a.csv")]);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn partials_are_named_as_such_and_removed() {
        let dir = folder("partials");
        let partial = partial_path(&dir.join("IV.1.vtu")).unwrap();
        let name = partial.file_name().unwrap().to_str().unwrap().to_owned();
        assert!(is_partial(&name), "{name}");
        assert!(!name.ends_with(".vtu"), "{name}");
        fs::write(&partial, "half").unwrap();
        fs::write(dir.join("IV.1.csv"), "whole").unwrap();
        assert_eq!(remove_partials(&dir).unwrap(), 1);
        assert!(!partial.exists());
        assert!(dir.join("IV.1.csv").exists());
        assert!(!is_partial("IV.1.csv"));
        fs::remove_dir_all(&dir).unwrap();
    }
}
