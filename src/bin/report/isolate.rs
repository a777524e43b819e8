//! Panic isolation: a run that panics becomes a failed entry of its table (with the message and
//! the place of the panic) instead of ending the other tables' runs.

use std::panic::{self, AssertUnwindSafe};
use std::sync::Mutex;

use tribo::experiment::Experiment;
use tribo::report::{self, Failure, FailureKind};
use tribo::results::RunResult;
use tribo::study::RunError;

use crate::outputs::failure_of;

/// Testing hook: when this environment variable holds a table id, the run of that table panics
/// just before it starts, so that the tests can check that a panic is isolated to its table.
/// Nothing else reads it.
const TEST_PANIC_VARIABLE: &str = "TRIBO_TEST_PANIC";

/// Testing hook: when this environment variable holds a table id, the run of that table waits
/// just before it starts until standard input ends (after a line on stderr that says so), so
/// that the tests can interrupt or lock a run at a known point. Nothing else reads it.
const TEST_HOLD_VARIABLE: &str = "TRIBO_TEST_HOLD";

/// Where the last panic happened (`file:line:column`), recorded by the panic hook so that a
/// caught panic's section can say where it came from; the payload alone has only the message.
static LAST_PANIC_PLACE: Mutex<Option<String>> = Mutex::new(None);

/// Record the place of every panic in [`LAST_PANIC_PLACE`], then do what the default hook does
/// (print the message to stderr).
pub fn install_panic_hook() {
    let default = panic::take_hook();
    panic::set_hook(Box::new(move |info| {
        if let (Some(location), Ok(mut place)) = (info.location(), LAST_PANIC_PLACE.lock()) {
            *place = Some(location.to_string());
        }
        default(info);
    }));
}

/// Run `solves`, the study of `spec`, so that nothing in it can stop the other tables: an
/// error of the study becomes a failed entry with its cycle, and so does a panic (caught here,
/// with the message and the place the panic hook recorded).
pub fn run_isolated(
    spec: &Experiment,
    solves: impl FnOnce() -> Result<RunResult, RunError>,
) -> Result<RunResult, Failure> {
    let failure = |kind, cycle, message| failure_of(spec, &spec.table, kind, cycle, message);
    if let Ok(mut place) = LAST_PANIC_PLACE.lock() {
        *place = None;
    }
    let caught = panic::catch_unwind(AssertUnwindSafe(|| {
        if std::env::var(TEST_HOLD_VARIABLE).is_ok_and(|t| t == spec.table) {
            eprintln!(
                "{TEST_HOLD_VARIABLE}={}: holding the run until stdin ends (testing hook)",
                spec.table
            );
            let _ = std::io::copy(&mut std::io::stdin(), &mut std::io::sink());
        }
        if std::env::var(TEST_PANIC_VARIABLE).is_ok_and(|t| t == spec.table) {
            panic!(
                "{TEST_PANIC_VARIABLE}={}: a panic on purpose (testing hook)",
                spec.table
            );
        }
        solves()
    }));
    match caught {
        Ok(Ok(run)) => Ok(run),
        Ok(Err(e)) => Err(failure(FailureKind::Error, Some(e.cycle), e.to_string())),
        Err(payload) => {
            let message = report::panic_message(payload.as_ref());
            let place = LAST_PANIC_PLACE
                .lock()
                .ok()
                .and_then(|mut p| p.take())
                .map_or_else(String::new, |p| format!(" (at {p})"));
            Err(failure(
                FailureKind::Panic,
                None,
                format!("table {}: panicked{place}: {message}", spec.table),
            ))
        }
    }
}
