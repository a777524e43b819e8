//! Wall-clock seconds per phase of one cycle, kept apart from the algorithm: the loop wraps each
//! phase in [`PhaseClock::time`], and a problem that does work of another phase inside one (a
//! re-assembly inside the solve when `cavitation = "auto"` switches) wraps that part too — nested
//! time counts for the inner phase only.

use std::cell::Cell;
use std::time::Instant;

use crate::results::PhaseSeconds;

/// The phases of a cycle (docs/architecture.md, "Data flow").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    Setup,
    Assemble,
    Solve,
    Estimate,
    Refine,
}

/// Seconds per phase of one cycle (module docs).
#[derive(Default)]
pub struct PhaseClock {
    seconds: Cell<PhaseSeconds>,
    /// Seconds spent in nested phases of the innermost running phase.
    nested: Cell<f64>,
}

impl PhaseClock {
    /// Run `work` and count its wall time for `phase` (less any nested phase's time).
    pub fn time<T>(&self, phase: Phase, work: impl FnOnce() -> T) -> T {
        let outer_nested = self.nested.replace(0.0);
        let start = Instant::now();
        let out = work();
        let elapsed = start.elapsed().as_secs_f64();
        let inner = self.nested.replace(outer_nested + elapsed);
        let mut s = self.seconds.get();
        let slot = match phase {
            Phase::Setup => &mut s.setup,
            Phase::Assemble => &mut s.assemble,
            Phase::Solve => &mut s.solve,
            Phase::Estimate => &mut s.estimate,
            Phase::Refine => &mut s.refine,
        };
        *slot += elapsed - inner;
        self.seconds.set(s);
        out
    }

    /// The seconds counted so far.
    pub fn seconds(&self) -> PhaseSeconds {
        self.seconds.get()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn nested_time_counts_for_the_inner_phase_only() {
        let clock = PhaseClock::default();
        let start = Instant::now();
        clock.time(Phase::Solve, || {
            std::thread::sleep(Duration::from_millis(20));
            clock.time(Phase::Assemble, || {
                std::thread::sleep(Duration::from_millis(30))
            });
        });
        let wall = start.elapsed().as_secs_f64();
        let s = clock.seconds();
        // Sleeps last at least as long as asked; the two phases share the outer wall time.
        assert!(s.assemble >= 0.030, "{s:?}");
        assert!(s.solve >= 0.020, "{s:?}");
        assert!(s.solve + s.assemble <= wall, "{s:?} within {wall}");
        assert_eq!((s.setup, s.estimate, s.refine), (0.0, 0.0, 0.0));
    }
}
