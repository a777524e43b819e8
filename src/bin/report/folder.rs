//! The output folder of a run: one run at a time in it (a lock), the checks made before any
//! table is solved, and a page that says the report is incomplete until the run has finished.
//!
//! A run replaces the files of its tables as they finish and the page at the end. Interrupted
//! (Ctrl-C, `kill`, the OOM killer) or sharing the folder with a second run, it would leave
//! the previous page, with its old numbers and links to figures this run already removed, beside
//! new data. So the run first takes the folder's lock, then replaces the page by one that says
//! which tables are pending ([`PendingPage`]), updated as each table finishes; the full page
//! replaces it at the end. Every file is written under a temporary name and renamed into place
//! ([`tribo::fsio`]): an interrupted run leaves a page that says it is incomplete and complete
//! files, never a mix that looks finished.

use std::fs::{File, OpenOptions, TryLockError};
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use tribo::fsio;

/// The lock file in the output folder; it holds the process id of the run that has the lock.
pub const LOCK_FILE: &str = ".tribo-lock";

/// The lock of an output folder, held until it is dropped.
///
/// The lock is the operating system's lock on [`LOCK_FILE`] ([`File::try_lock`]): it ends with
/// the process however the process ends, so a killed run never blocks the folder. The file
/// holds the holder's process id, to name it to a second run; a process id left in a file
/// nobody locks is that of a run that was interrupted, and is taken over with a note. The file
/// is emptied, not removed, when the run ends: removing it would let a run that had opened it
/// just before lock a file no longer in the folder while a third run creates a new one.
pub struct FolderLock {
    file: File,
}

impl FolderLock {
    /// Take the lock of `out` (created if need be), or say which process holds it.
    pub fn take(out: &Path) -> Result<FolderLock, String> {
        let cannot = |e: &dyn std::fmt::Display| {
            format!("cannot write the report into {}: {e}", out.display())
        };
        if out.exists() && !out.is_dir() {
            return Err(cannot(&format!(
                "{} exists and is not a directory",
                out.display()
            )));
        }
        std::fs::create_dir_all(out).map_err(|e| cannot(&e))?;
        let path = out.join(LOCK_FILE);
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&path)
            .map_err(|e| cannot(&format!("{}: {e}", path.display())))?;
        let mut holder = String::new();
        let locked = file.try_lock();
        // What the file says; it may be empty (no run since) or unreadable (not ours).
        let _ = file.read_to_string(&mut holder);
        let holder = holder.trim().to_owned();
        match locked {
            Ok(()) => {}
            Err(TryLockError::WouldBlock) => {
                let who = if holder.is_empty() {
                    "another process".to_owned()
                } else {
                    format!("process {holder}")
                };
                return Err(format!(
                    "{} is in use by another report run ({who}, lock file {}); wait for it to \
                     finish or choose another --out",
                    out.display(),
                    path.display()
                ));
            }
            Err(TryLockError::Error(e)) => {
                return Err(cannot(&format!("cannot lock {}: {e}", path.display())))
            }
        }
        if !holder.is_empty() && holder != std::process::id().to_string() {
            eprintln!(
                "note: taking over the lock of {} from process {holder}, which is no longer \
                 running (an interrupted run)",
                out.display()
            );
        }
        let mut lock = FolderLock { file };
        lock.record(&std::process::id().to_string())
            .map_err(|e| cannot(&format!("{}: {e}", path.display())))?;
        Ok(lock)
    }

    /// Make the lock file hold `text` alone.
    fn record(&mut self, text: &str) -> std::io::Result<()> {
        self.file.set_len(0)?;
        self.file.rewind()?;
        self.file.write_all(text.as_bytes())
    }
}

impl Drop for FolderLock {
    fn drop(&mut self) {
        // An empty file: nobody holds the folder, and nobody was interrupted.
        let _ = self.record("");
    }
}

/// Check, before any table is solved, that the page can take its place: `out/index.html` must
/// be a file or absent (a folder there would be found only when the page is written, after
/// every table); then remove what interrupted runs left under temporary names, and the pages of
/// an earlier run other than `index.html`, which the page of the run in progress replaces.
pub fn check(out: &Path) -> Result<(), String> {
    let index = out.join("index.html");
    if index.exists() && !index.is_file() {
        return Err(format!(
            "cannot write the report into {}: {} exists and is not a file",
            out.display(),
            index.display()
        ));
    }
    for dir in [
        out.to_path_buf(),
        out.join("data"),
        out.join("figures"),
        out.join(tribo::report::record::DIR),
    ] {
        fsio::remove_partials(&dir).map_err(|e| {
            format!(
                "cannot write the report into {}: cannot clear {}: {e}",
                out.display(),
                dir.display()
            )
        })?;
    }
    tribo::report::remove_pages(out).map_err(|e| {
        format!(
            "cannot write the report into {}: cannot remove the pages of an earlier run: {e}",
            out.display()
        )
    })
}

/// The page of a run that has not finished: when and by which process it started, the tables
/// finished and those pending, written to `out/index.html` at the start and after each table.
pub struct PendingPage {
    index: PathBuf,
    /// Process, tier and start of the run, as the page states them.
    run: String,
    /// Each table of the run and whether it has finished, in the order of the page.
    tables: Mutex<Vec<(String, bool)>>,
}

impl PendingPage {
    /// The page of a run of `tables` into `out`; `what` says which run (tier, date).
    pub fn new(out: &Path, what: &str, tables: &[String]) -> PendingPage {
        PendingPage {
            index: out.join("index.html"),
            run: format!("process {}, {what}", std::process::id()),
            tables: Mutex::new(tables.iter().map(|t| (t.clone(), false)).collect()),
        }
    }

    /// Write the page with every table pending.
    pub fn write(&self) -> std::io::Result<()> {
        let tables = self.tables.lock().expect("pending tables");
        fsio::write(&self.index, self.html(&tables))
    }

    /// Table `index` has finished: the page says so. A page that cannot be written now is left
    /// as it was (it still says the report is incomplete); the full page comes at the end.
    pub fn finished(&self, index: usize) {
        let mut tables = self.tables.lock().expect("pending tables");
        if let Some(entry) = tables.get_mut(index) {
            entry.1 = true;
        }
        if let Err(e) = fsio::write(&self.index, self.html(&tables)) {
            eprintln!(
                "note: cannot update {} ({e}); it still says the report is incomplete",
                self.index.display()
            );
        }
    }

    fn html(&self, tables: &[(String, bool)]) -> String {
        let list = |done: bool| {
            let names: Vec<String> = tables
                .iter()
                .filter(|(_, d)| *d == done)
                .map(|(t, _)| format!("<code>{}</code>", escape(t)))
                .collect();
            if names.is_empty() {
                "none".to_owned()
            } else {
                names.join(", ")
            }
        };
        let finished = list(true);
        let pending = list(false);
        format!(
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
             <title>tribo report: incomplete</title>\n</head>\n<body>\n\
             <h1>This report is incomplete</h1>\n\
             <p>A <code>report</code> run ({run}) is writing this folder, or was interrupted \
             before it finished. Its page replaces this one when every table has run; until \
             then <code>data/</code> and <code>figures/</code> may hold files of an earlier \
             run beside those of this one. If no such process is running, run the report \
             again.</p>\n\
             <p id=\"pending\">Tables pending: {pending}</p>\n\
             <p id=\"finished\">Tables done (their data files are in <code>data/</code>, \
             unless the table failed): {finished}</p>\n\
             </body>\n</html>\n",
            run = escape(&self.run),
        )
    }
}

/// `text` with the characters HTML gives a meaning escaped.
fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c if c.is_control() => out.push_str(&format!("\\u{{{:x}}}", c as u32)),
            c => out.push(c),
        }
    }
    out
}
