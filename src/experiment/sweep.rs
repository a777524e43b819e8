//! Sweeps: one experiment file run at several values of one or two of its fields, each
//! combination of values a run of its own (`[sweep]` in the file, or `report --set`), and the
//! runs compared side by side in the report.
//!
//! The types here are plain data: what a run of a sweep knows of the sweep, carried with its
//! result into the report and the shard records ([`crate::results::RunResult::sweep`]). The
//! expansion of a file into its runs, with every check, is the loader's (`load::sweep`).

use serde::{Deserialize, Serialize};

/// Most fields one sweep varies: one, or two for a grid of combinations.
pub const MAX_SWEEP_FIELDS: usize = 2;

/// Most runs of one sweep (the product of its fields' value counts): each run is a table of the
/// report with its data files and section, and a comparison of more curves than this is no
/// longer readable.
pub const MAX_SWEEP_RUNS: usize = 16;

/// One field a sweep varies, with every value it takes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweptField {
    /// The dotted path of the field in the experiment file, e.g.
    /// `scene.reynolds.upper_wall_velocity`.
    pub path: String,
    /// The values in the order given, each as inline TOML (`[-10.0, 0.0, 0.0]`, `0.1`, `"on"`).
    pub values: Vec<String>,
    /// The number each value stands for on a plot axis: the value itself, or for arrays of
    /// numbers the one component that varies across the values ([`SweptField::component`]);
    /// `None` where the values are not numbers (strings, tables) or more than one component
    /// varies.
    pub numbers: Option<Vec<f64>>,
    /// Which component of array values varies, where `numbers` is such a component.
    pub component: Option<usize>,
}

impl SweptField {
    /// The field's name without its table, `upper_wall_velocity`.
    pub fn name(&self) -> &str {
        self.path.rsplit('.').next().unwrap_or(&self.path)
    }

    /// What the plot axis of the field shows: its name, with the component that varies
    /// (`upper_wall_velocity[0]`).
    pub fn axis(&self) -> String {
        match self.component {
            Some(c) => format!("{}[{c}]", self.name()),
            None => self.name().to_string(),
        }
    }
}

/// What a run of a sweep knows of its sweep: the fields and their values, every run's id, which
/// of them it is, and the quantities the comparison shows.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepRun {
    /// The sweep's id: the id of the swept file (`step-bearing`).
    pub sweep: String,
    /// The fields varied, one or two ([`MAX_SWEEP_FIELDS`]).
    pub fields: Vec<SweptField>,
    /// The id of every run, one per combination of values: the first field's values outermost,
    /// so that run `i` takes value `i / n₂` of the first field and `i % n₂` of the second.
    pub runs: Vec<String>,
    /// This run's place in `runs`.
    pub index: usize,
    /// The engineering quantities the comparison shows (columns of
    /// [`crate::study::quantities`]).
    pub quantities: Vec<String>,
    /// Where the sweep was asked for: the file's `[sweep]`, or `report --set`.
    pub from_command_line: bool,
}

impl SweepRun {
    /// The value index of each field in run `index` (of [`SweepRun::runs`]).
    pub fn values_of(&self, index: usize) -> Vec<usize> {
        let mut rest = index;
        let mut at = vec![0; self.fields.len()];
        for (k, field) in self.fields.iter().enumerate().rev() {
            let n = field.values.len().max(1);
            at[k] = rest % n;
            rest /= n;
        }
        at
    }

    /// `name = value` of each field in run `index`, joined by `, `
    /// (`upper_wall_velocity = [-10.0, 0.0, 0.0]`).
    pub fn label_of(&self, index: usize) -> String {
        self.fields
            .iter()
            .zip(self.values_of(index))
            .map(|(field, v)| format!("{} = {}", field.name(), field.values[v]))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// [`SweepRun::label_of`] this run.
    pub fn label(&self) -> String {
        self.label_of(self.index)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn field(path: &str, values: &[&str]) -> SweptField {
        SweptField {
            path: path.into(),
            values: values.iter().map(|v| v.to_string()).collect(),
            numbers: None,
            component: None,
        }
    }

    #[test]
    fn runs_take_the_first_field_outermost() {
        let sweep = SweepRun {
            sweep: "s".into(),
            fields: vec![
                field("scene.reynolds.gap.g_out", &["0.1", "0.05"]),
                field("scene.reynolds.boundary_pressure", &["0.0", "1.0", "2.0"]),
            ],
            runs: (0..6).map(|i| format!("s~{i}")).collect(),
            index: 4,
            quantities: Vec::new(),
            from_command_line: false,
        };
        assert_eq!(sweep.values_of(0), [0, 0]);
        assert_eq!(sweep.values_of(2), [0, 2]);
        assert_eq!(sweep.values_of(4), [1, 1]);
        assert_eq!(sweep.label(), "g_out = 0.05, boundary_pressure = 1.0");
        assert_eq!(sweep.fields[0].axis(), "g_out");
    }
}
