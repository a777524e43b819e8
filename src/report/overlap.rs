//! Which tables ran at the same time: the report runs tables side by side (`--jobs`), and a
//! table's phase seconds, measured by its own clock, are longer when others share the cores.
//! The page marks such seconds ([`Overlap::most_alongside`]) and uses only a table that ran
//! alone as a one-table-at-a-time measurement.

use std::collections::BTreeMap;
use std::sync::Mutex;

/// The tables running now and, for every table that ran, the most other tables that ran while
/// it did.
#[derive(Default)]
pub struct Overlap {
    state: Mutex<State>,
}

#[derive(Default)]
struct State {
    running: Vec<String>,
    most: BTreeMap<String, usize>,
}

/// A table's stay in the running set: it leaves when this is dropped.
pub struct Running<'a> {
    overlap: &'a Overlap,
    table: String,
}

impl Overlap {
    /// `table` starts: every running table (`table` included) has at least the others now
    /// running beside it.
    pub fn enter(&self, table: &str) -> Running<'_> {
        let mut state = self.state.lock().unwrap_or_else(|e| e.into_inner());
        state.running.push(table.to_string());
        let others = state.running.len() - 1;
        let running = state.running.clone();
        for t in running {
            let most = state.most.entry(t).or_insert(0);
            *most = (*most).max(others);
        }
        Running {
            overlap: self,
            table: table.to_string(),
        }
    }

    /// For every table that ran, the most other tables that ran at the same time.
    pub fn most_alongside(&self) -> BTreeMap<String, usize> {
        self.state
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .most
            .clone()
    }
}

impl Drop for Running<'_> {
    fn drop(&mut self) {
        let mut state = self.overlap.state.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(i) = state.running.iter().position(|t| *t == self.table) {
            state.running.remove(i);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_the_tables_that_overlapped_each_one() {
        let o = Overlap::default();
        let a = o.enter("IV.1");
        let b = o.enter("IV.2");
        drop(a);
        let c = o.enter("IV.3");
        drop(b);
        drop(c);
        let d = o.enter("IV.36");
        drop(d);
        let most = o.most_alongside();
        assert_eq!(most["IV.1"], 1);
        assert_eq!(most["IV.2"], 1);
        assert_eq!(most["IV.3"], 1);
        assert_eq!(most["IV.36"], 0);
    }
}
