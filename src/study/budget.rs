//! The size of a run: predicted before the first solve and checked before every one, so that a
//! study that would exhaust the machine's memory is refused with a message naming the table and
//! the cycle instead of taking the machine down (`global_refinements = 12` passed 8 GB in 44 s;
//! `refine_fraction = 1` quadruples the cells every cycle).
//!
//! **Model.** The memory of a cycle grows with the number of active cells N and the number c of
//! solution components per vertex (2 for elasticity and contact, 1 for the thin films, 3 for
//! SubStokes) as [`BYTES_PER_CELL`]·c·min(c, 2)·N with the direct solver and
//! [`BYTES_PER_CELL_MULTIGRID`]·c²·N with multigrid. The constants are measured: peak RSS over
//! the last active cells of the full tier, 288 MB / 42 566 cells for IV.13 (c = 2, 6.8 kB per
//! cell, the fixed part of the process included), rounded up; Table IV.67 (c = 1) took
//! 1.13 GB / 672 064 cells with the direct solver. A strip refined at one side
//! (`scene.contact_refinements`) fills its Cholesky factor in like any mesh of its cells: some 26
//! nonzeros per unknown, 54.6 M for the 786 368 cells of IV.18's 64×2 strip refined 12 times
//! (an earlier ordering cut the graded layers along the strip, 9.2 G nonzeros there, and the
//! model had a term for it, [`crate::linalg::ordering`]). The direct solver still checks the
//! factor itself, known from the symbolic factorisation, before allocating it
//! ([`crate::linalg::direct::limit_memory`]), as multigrid checks its levels: what the model
//! misses is still refused, naming the cycle.
//!
//! Predicted (the table's model plus 30 MB of the process: code, threads, loaded files — the
//! RSS of the smallest runs) against the peak RSS measured by `/usr/bin/time -v` on single
//! full-tier runs (`--no-alternatives`), in MB:
//!
//! | scene | last cells | predicted | measured | ratio |
//! |---|---:|---:|---:|---:|
//! | IV.1 elasticity | 3 308 | 56 | 38 | 1.48 |
//! | IV.13 contact | 42 566 | 385 | 295 | 1.30 |
//! | IV.30 model and grid | 42 950 | 385 | 249 | 1.54 |
//! | fig-IV.54 load steps | — | 37 | 40 | 0.93 |
//! | IV.18 model-adaptive contact, 3 contact refinements | 1 472 | 42 | 34 | 1.25 |
//! | IV.18 with 8 | 49 088 | 423 | 218 | 1.94 |
//! | IV.18 with 9 | 98 240 | 816 | 391 | 2.09 |
//! | IV.36 Reynolds (multigrid) | 687 664 | 771 | 679 | 1.14 |
//! | IV.50 SubStokes | 11 227 | 169 | 128 | 1.32 |
//! | fig-IV.116 model-adaptive film | 7 252 | 103 | 58 | 1.77 |
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

/// Bytes of memory per active cell and squared solution component with the direct solver,
/// measured (module docs).
pub const BYTES_PER_CELL: f64 = 2000.0;

/// Bytes per active cell and squared component with the multigrid solver, measured: 663 MB peak
/// for the 687 664 cells of Table IV.36 (c = 1), rounded up.
pub const BYTES_PER_CELL_MULTIGRID: f64 = 1000.0;

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
        predicted_cells(experiment, schedule).fold(0.0f64, |peak, (_, cells)| {
            peak.max(memory(experiment, cells))
        })
    }

    /// The predicted active cells of the last solve of a run, and their sum over its solves
    /// (the model of the module docs), for `report --list`.
    pub fn predicted_size(experiment: &Experiment, schedule: Schedule) -> (f64, f64) {
        predicted_cells(experiment, schedule)
            .fold((0.0, 0.0), |(_, sum), (_, cells)| (cells, sum + cells))
    }

    /// Check the predicted size of the whole run before its first solve.
    pub fn admit_run(&self, experiment: &Experiment, schedule: Schedule) -> Result<(), RunError> {
        for (solve, cells) in predicted_cells(experiment, schedule) {
            let need = memory(experiment, cells);
            if need > self.bytes {
                return Err(solve.error(
                    &experiment.table,
                    StudyError::OverBudget(format!(
                        "the run is predicted to need {} for about {} active cells in \
                         this cycle, more than the memory budget of {} (from \
                         scene.coarse_cells, scene.global_refinements, \
                         scene.contact_refinements, study.refine_fraction and the number of \
                         cycles; set the budget with --memory-budget)",
                        human(need),
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
        if let Some(SolveError::OverBudget(_)) = error.cause.solve_error() {
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
        let need = memory(experiment, active_cells as f64);
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

/// Active cells of the first mesh: the coarse grid refined globally, then at the contact sides.
/// Each refinement there splits the boundary row of 2^k·n cells into four; the refined layers
/// nest along a straight side, so the 2:1 rule adds nothing (the 64×2 strip of Table IV.18 has
/// 128 + 3·64·(2³ − 1) = 1472 cells with 3 refinements, as counted). Where two refined sides
/// meet, their corner cells are counted twice: a bound from above.
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
        cells += 3.0 * boundary_row;
    }
    cells
}

/// Predicted bytes of a cycle of `experiment` with `cells` active cells (module docs): the
/// cells' share, growing as c² up to the two components of elasticity and linearly beyond
/// (the SubStokes tables, c = 3, measured 8.4 kB per cell, not 9/4 of elasticity's 6.1 kB).
fn memory(experiment: &Experiment, cells: f64) -> f64 {
    let c = components(experiment) as f64;
    let per_cell = match super::solver_of(experiment) {
        crate::linalg::SolverKind::Direct => BYTES_PER_CELL,
        crate::linalg::SolverKind::Multigrid => BYTES_PER_CELL_MULTIGRID,
    };
    per_cell * c * c.min(2.0) * cells
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
pub fn human(bytes: f64) -> String {
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
    use crate::linalg::direct::OverBudget;

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

    /// A solver's refusal under the contexts of the model and the study becomes the study's
    /// [`StudyError::OverBudget`], its text kept whole; any other failure stays as it was.
    #[test]
    fn a_solvers_refusal_is_the_budgets() {
        let refused = SolveError::OverBudget(Box::new(OverBudget {
            what: "the factor".into(),
            bytes: 3.0 * GIB,
            budget: GIB,
        }));
        let cause = StudyError::Solve(refused).context("contact");
        let text = cause.to_string();
        let error = Budget::refusal(RunError::at_cycle("IV.18", 2, cause));
        assert!(matches!(error.cause, StudyError::OverBudget(_)), "{error}");
        assert_eq!(error.cause.to_string(), text);
        assert!(
            text.contains("3.0 GiB") && text.contains("1.0 GiB"),
            "{text}"
        );
        let other = Budget::refusal(RunError::at_cycle(
            "IV.1",
            0,
            StudyError::Failed("x".into()),
        ));
        assert!(matches!(other.cause, StudyError::Failed(_)));
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
