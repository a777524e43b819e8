//! How the report shows its progress on stderr: a bar with the time left in a terminal; one line
//! per finished cycle anywhere else (a log file, CI); nothing with `--no-progress`. Failures and
//! warnings are printed through it, so that they do not tear the bar.

use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};

use tribo::report::Failure;

pub struct ProgressDisplay {
    bar: ProgressBar,
    /// One line per finished cycle instead of the bar.
    lines: bool,
    /// When the report started (the lines' times count from it).
    started: Instant,
}

impl ProgressDisplay {
    /// The display of a report of `total` cycles.
    pub fn new(no_progress: bool, total: u64, started: Instant) -> ProgressDisplay {
        let lines = !no_progress && !std::io::stderr().is_terminal();
        let bar = if no_progress || lines {
            ProgressBar::hidden()
        } else {
            ProgressBar::new(total)
        };
        bar.set_style(
            ProgressStyle::with_template(
                "{elapsed_precise} [{bar:30}] {pos}/{len} cycles, about {eta} left  {msg}",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        ProgressDisplay {
            bar,
            lines,
            started,
        }
    }

    /// Cycle `done` of `total` of the run `label` (a table, or one of its readings) finished.
    pub fn cycle_done(&self, label: &str, done: usize, total: usize) {
        if self.lines && done > 0 {
            eprintln!(
                "[{:>7.1} s] {label}: cycle {done} of {total} done",
                self.started.elapsed().as_secs_f64()
            );
        }
    }

    /// A table has finished `done` cycles, all its runs together, as counted by `counted`:
    /// the bar moves by the cycles not counted yet, whatever order the tables finish in.
    pub fn advance(&self, counted: &AtomicU64, done: u64) {
        let before = counted.fetch_max(done, Ordering::Relaxed);
        if done > before {
            self.bar.inc(done - before);
        }
    }

    /// What runs now, beside the bar.
    pub fn running(&self, message: String) {
        self.bar.set_message(message);
    }

    /// A line of stderr, printed with the bar out of the way.
    pub fn print(&self, line: &str) {
        self.bar.suspend(|| eprintln!("{line}"));
    }

    /// A failed run, on stderr as it happens.
    pub fn failure(&self, f: &Failure) {
        self.print(&format!("{}: {}", f.kind.name(), f.message));
    }

    /// Every table has finished: the bar goes.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
