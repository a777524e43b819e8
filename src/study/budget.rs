//! The size of a run: predicted before the first solve and checked before every one, so that a
//! study that would exhaust the machine's memory is refused with a message naming the table and
//! the cycle instead of taking the machine down (`global_refinements = 12` passed 8 GB in 44 s;
//! `refine_fraction = 1` quadruples the cells every cycle).
//!
//! **Model.** The memory of a cycle is dominated by the sparse factorisation and grows with the
//! number of active cells N and the number c of solution components per vertex (2 for
//! elasticity and contact, 1 for the thin films) as [`BYTES_PER_CELL`]·c²·N. The constant is
//! measured: peak RSS over the last active cells of the full tier, 288 MB / 42 566 cells for
//! IV.13 (c = 2, 6.8 kB per cell, the fixed part of the process included), rounded up; the
//! thin films need less since multigrid replaced the factorisation (Table IV.67, c = 1:
//! 1.13 GB / 672 064 cells with the direct solver, 0.75 GB with multigrid).
//!
//! **Prediction.** Global refinement multiplies the coarse cells by 4 per level; fixed-fraction
//! marking (§IV.1) refines the fraction θ_r of the cells into four and merges the fraction θ_c
//! in groups of four, so a cycle multiplies N by 1 + 3θ_r − ¾θ_c, and the 2:1 closure by
//! [`CLOSURE`] more. For the shipped tables the prediction is 0.99–1.13 times the cells reached
//! (full tier), except for the two tables whose exact solution stops the refinement (IV.38,
//! IV.43), where it is far above.

use super::{RunError, Schedule, Solve, StudyError};
use crate::experiment::Experiment;
use crate::linalg::direct::{limit_memory, MemoryLimit};
use crate::linalg::SolveError;

/// Bytes of memory per active cell and squared solution component, measured (module docs).
pub const BYTES_PER_CELL: f64 = 2000.0;

/// Growth of the cells per cycle by the 2:1 closure of the marking, measured: the shipped
/// tables reach 1.09–1.16 times 1 + 3θ_r − ¾θ_c to the power of their cycles (5 to 9).
pub const CLOSURE: f64 = 1.02;

pub use crate::machine::machine_memory;

/// The memory of the tables running at once, shared by the workers of a report: a table
/// starts when its predicted peak ([`Budget::predicted_peak`]) fits beside those of the tables
/// running, or when none runs (a table too large for the budget alone is refused by
/// [`Budget::admit_run`]). With `--jobs N` chosen by hand, tables wait for memory instead of
/// overcommitting it; the order in which they run does not change any result.
pub struct Ledger {
    budget: f64,
    reserved: std::sync::Mutex<f64>,
    freed: std::sync::Condvar,
}

/// Memory reserved in a [`Ledger`], given back when dropped.
pub struct Reservation<'a> {
    ledger: &'a Ledger,
    bytes: f64,
}

impl Ledger {
    pub fn new(budget: Budget) -> Ledger {
        Ledger {
            budget: budget.bytes,
            reserved: std::sync::Mutex::new(0.0),
            freed: std::sync::Condvar::new(),
        }
    }

    /// Reserve `bytes`, waiting until they fit beside the reservations held, or none is held.
    pub fn reserve(&self, bytes: f64) -> Reservation<'_> {
        let mut reserved = self.reserved.lock().unwrap_or_else(|e| e.into_inner());
        while *reserved > 0.0 && *reserved + bytes > self.budget {
            reserved = self.freed.wait(reserved).unwrap_or_else(|e| e.into_inner());
        }
        *reserved += bytes;
        Reservation {
            ledger: self,
            bytes,
        }
    }

    /// The bytes reserved now.
    pub fn reserved(&self) -> f64 {
        *self.reserved.lock().unwrap_or_else(|e| e.into_inner())
    }
}

impl Drop for Reservation<'_> {
    fn drop(&mut self) {
        let mut reserved = self
            .ledger
            .reserved
            .lock()
            .unwrap_or_else(|e| e.into_inner());
        *reserved = (*reserved - self.bytes).max(0.0);
        self.ledger.freed.notify_all();
    }
}

/// Memory a run may use.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Budget {
    pub bytes: f64,
}

impl Budget {
    /// The machine's memory ([`machine_memory`]), or 8 GiB where it cannot be read.
    pub fn machine() -> Budget {
        Budget {
            bytes: machine_memory().unwrap_or(8.0 * GIB),
        }
    }

    /// A size as written on the command line: a number with an optional unit `K`, `M`, `G`
    /// or `T` (powers of 1024; `KiB`, `MB`, … read the same), e.g. `4G` or `1500M`.
    pub fn parse(text: &str) -> Result<Budget, String> {
        let t = text.trim();
        let split = t.find(|c: char| c.is_ascii_alphabetic()).unwrap_or(t.len());
        let (number, unit) = t.split_at(split);
        let unit_bytes = match unit.to_ascii_uppercase().as_str() {
            "" | "B" => 1.0,
            "K" | "KB" | "KIB" => 1024.0,
            "M" | "MB" | "MIB" => 1024.0 * 1024.0,
            "G" | "GB" | "GIB" => GIB,
            "T" | "TB" | "TIB" => 1024.0 * GIB,
            _ => {
                return Err(format!(
                    "unknown unit `{unit}` in `{text}` (use K, M, G or T)"
                ))
            }
        };
        match number.trim().parse::<f64>() {
            Ok(n) if n.is_finite() && n > 0.0 => Ok(Budget {
                bytes: n * unit_bytes,
            }),
            _ => Err(format!(
                "`{text}` is not a memory size: expected a positive number with an optional \
                 unit K, M, G or T, e.g. 4G"
            )),
        }
    }

    /// The predicted memory of the largest cycle of a run (the model of the module docs).
    pub fn predicted_peak(experiment: &Experiment, schedule: Schedule) -> f64 {
        let c = components(experiment);
        predicted_cells(experiment, schedule)
            .fold(0.0f64, |peak, (_, cells)| peak.max(memory(cells, c)))
    }

    /// Check the predicted size of the whole run before its first solve.
    pub fn admit_run(&self, experiment: &Experiment, schedule: Schedule) -> Result<(), RunError> {
        let c = components(experiment);
        for (solve, cells) in predicted_cells(experiment, schedule) {
            if memory(cells, c) > self.bytes {
                return Err(solve.error(
                    &experiment.table,
                    StudyError::OverBudget(format!(
                        "the run is predicted to need {} for about {} active cells in \
                         this cycle, more than the memory budget of {} (from \
                         scene.coarse_cells, scene.global_refinements, study.refine_fraction \
                         and the number of cycles; set the budget with --memory-budget)",
                        human(memory(cells, c)),
                        count(cells),
                        human(self.bytes)
                    )),
                ));
            }
        }
        Ok(())
    }

    /// The budget as the limit of the solvers of the study on this thread, until the guard is
    /// dropped: the direct solver checks its factor (known from the symbolic factorisation)
    /// and multigrid its level hierarchy against it before allocating them
    /// ([`crate::linalg::direct::limit_memory`]).
    pub fn limit_solvers(&self) -> MemoryLimit {
        limit_memory(self.bytes)
    }

    /// A run's error with a solver's refusal ([`SolveError::OverBudget`], under whatever
    /// contexts) made the study's [`StudyError::OverBudget`], its message the whole text of the
    /// error: the budget refuses the cycle, whichever layer found it.
    pub fn refusal(mut error: RunError) -> RunError {
        if let Some(SolveError::OverBudget { .. }) = error.cause.solve_error() {
            error.cause = StudyError::OverBudget(error.cause.to_string());
        }
        error
    }

    /// Check the mesh of a cycle before it is solved.
    pub fn admit_cycle(
        &self,
        experiment: &Experiment,
        active_cells: usize,
    ) -> Result<(), StudyError> {
        let need = memory(active_cells as f64, components(experiment));
        if need > self.bytes {
            return Err(StudyError::OverBudget(format!(
                "the mesh has {active_cells} active cells, which needs about {}, more than the \
                 memory budget of {} (set it with --memory-budget)",
                human(need),
                human(self.bytes)
            )));
        }
        Ok(())
    }
}

const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

/// The predicted active cells of every solve of a run (module docs).
fn predicted_cells(
    experiment: &Experiment,
    schedule: Schedule,
) -> impl Iterator<Item = (Solve, f64)> {
    let initial = initial_cells(experiment);
    let growth = growth(experiment);
    let mut next = initial;
    schedule.solves().map(move |solve| {
        // A load step restarts from the coarse cells of the moved body.
        if let Some((_, 0)) = solve.step {
            next = initial;
        }
        let cells = next;
        next *= growth;
        (solve, cells)
    })
}

/// Growth of the active cells per cycle (module docs).
fn growth(experiment: &Experiment) -> f64 {
    match experiment.study.grid() {
        Some(grid) => CLOSURE * (1.0 + 3.0 * grid.refine - 0.75 * grid.coarsen),
        // The mesh is fixed; only the models of the contact faces change (or the solver
        // iterates on one mesh).
        None => 1.0,
    }
}

/// Solution components per vertex of the experiment's problem.
fn components(experiment: &Experiment) -> usize {
    experiment.family.facts().unknowns_per_vertex
}

/// Active cells of the first mesh: the coarse grid refined globally, then at the contact sides
/// (each refinement there splits the boundary row of 2^k·n cells into four; the 2:1 closure
/// behind them is bounded by [`CLOSURE`] per refinement).
fn initial_cells(experiment: &Experiment) -> f64 {
    let scene = &experiment.scene;
    let [nx, ny] = scene.coarse_cells;
    let levels = 2f64.powi(scene.global_refinements as i32);
    let mut cells = nx as f64 * ny as f64 * levels * levels;
    for k in 0..scene.side_refinements {
        let boundary_row: f64 = scene
            .refined_sides
            .iter()
            .map(|s| if s.is_horizontal() { nx } else { ny } as f64 * levels)
            .sum::<f64>()
            * 2f64.powi(k as i32);
        cells = (cells + 3.0 * boundary_row) * CLOSURE.powi(4);
    }
    cells
}

/// Predicted bytes of a cycle with `cells` active cells and `c` components.
fn memory(cells: f64, c: usize) -> f64 {
    BYTES_PER_CELL * (c * c) as f64 * cells
}

/// A predicted number of cells: an integer below ten million, with an exponent above.
fn count(cells: f64) -> String {
    if cells < 1e7 {
        format!("{cells:.0}")
    } else {
        format!("{cells:.3e}")
    }
}

/// Bytes in GiB, MiB, KiB or bytes for a message (a budget of 10K is "10 KiB", not "0 MiB").
fn human(bytes: f64) -> String {
    const MIB: f64 = 1024.0 * 1024.0;
    if bytes >= GIB {
        format!("{:.1} GiB", bytes / GIB)
    } else if bytes >= MIB {
        format!("{:.0} MiB", bytes / MIB)
    } else if bytes >= 1024.0 {
        format!("{:.0} KiB", bytes / 1024.0)
    } else {
        format!("{bytes:.0} bytes")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_with_binary_units() {
        assert_eq!(Budget::parse("4G").unwrap().bytes, 4.0 * GIB);
        assert_eq!(
            Budget::parse("1500M").unwrap().bytes,
            1500.0 * 1024.0 * 1024.0
        );
        assert_eq!(Budget::parse("2.5GiB").unwrap().bytes, 2.5 * GIB);
        assert_eq!(Budget::parse("1024").unwrap().bytes, 1024.0);
        for bad in ["", "G", "-1G", "4X", "nanG", "0", "inf"] {
            assert!(Budget::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn the_machine_has_some_memory() {
        assert!(Budget::machine().bytes >= 256.0 * 1024.0 * 1024.0);
    }

    #[test]
    fn the_ledger_holds_tables_back_until_their_memory_fits() {
        use std::sync::atomic::{AtomicBool, Ordering};
        let ledger = Ledger::new(Budget { bytes: 10.0 });
        let first = ledger.reserve(6.0);
        // Alone, a table larger than the budget still starts (admit_run refuses it).
        assert_eq!(ledger.reserved(), 6.0);
        let second_started = AtomicBool::new(false);
        std::thread::scope(|scope| {
            scope.spawn(|| {
                let _second = ledger.reserve(6.0);
                second_started.store(true, Ordering::SeqCst);
            });
            std::thread::sleep(std::time::Duration::from_millis(50));
            assert!(
                !second_started.load(Ordering::SeqCst),
                "6 + 6 bytes do not fit a budget of 10"
            );
            drop(first);
        });
        assert!(second_started.load(Ordering::SeqCst));
        assert_eq!(ledger.reserved(), 0.0);
        let small = [ledger.reserve(4.0), ledger.reserve(4.0)];
        assert_eq!(ledger.reserved(), 8.0, "two that fit run side by side");
        drop(small);
        let _alone = ledger.reserve(25.0);
        assert_eq!(ledger.reserved(), 25.0);
    }
}
