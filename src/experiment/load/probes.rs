//! The probe points, located in the last mesh and written to `data/<table>.probes.csv`.

use std::collections::BTreeSet;

use super::check::{names, Check, Checked};
use crate::experiment::spec::*;

/// Most probe points (the grid `probes.x` × `probes.y`); Chapter IV probes at most 21. Each is
/// located in the last mesh and written to `data/<table>.probes.csv`.
const MAX_PROBE_POINTS: usize = 10_000;

impl Check<'_> {
    /// Probe points inside the domain; components among the `allowed` ones that the scene's
    /// family computes.
    pub(super) fn probes(&self, probes: &Probes, scene: &SceneFile, allowed: &[&str]) -> Checked {
        let Rectangle { x, y } = scene.domain;
        let points = probes.x.len().saturating_mul(probes.y.len());
        self.ensure(
            points <= MAX_PROBE_POINTS,
            "probes",
            &format!("at most {MAX_PROBE_POINTS} probe points (probes.x × probes.y)"),
            format!("{} × {} = {points} points", probes.x.len(), probes.y.len()),
        )?;
        for (name, values, [lo, hi]) in [("x", &probes.x, x), ("y", &probes.y, y)] {
            for (i, &v) in values.iter().enumerate() {
                self.ensure(
                    v.is_finite() && lo <= v && v <= hi,
                    &format!("probes.{name}[{i}]"),
                    &format!("a point of scene.domain.{name} = [{lo}, {hi}]"),
                    v,
                )?;
            }
        }
        let expected = if allowed.is_empty() {
            "no components (the scene computes no field)".to_owned()
        } else {
            format!(
                "one of {} (the fields of scene.effects {:?})",
                allowed
                    .iter()
                    .map(|c| format!("`{c}`"))
                    .collect::<Vec<_>>()
                    .join(", "),
                names(&scene.effects)
            )
        };
        let mut seen = BTreeSet::new();
        for (i, component) in probes.components.iter().enumerate() {
            let field = format!("probes.components[{i}]");
            self.ensure(
                allowed.contains(&component.as_str()),
                &field,
                &expected,
                format!("`{component}`"),
            )?;
            self.ensure(
                seen.insert(component.as_str()),
                &field,
                "each component listed once",
                format!("`{component}` twice"),
            )?;
        }
        Ok(())
    }
}
