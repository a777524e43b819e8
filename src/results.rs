//! What one experiment run produces: one [`CycleRow`] per adaptive cycle, solution probes and
//! pictures for the report. Everything here comes from running the solvers; the thesis rows live
//! in [`crate::thesis`] and are only ever shown beside these numbers.

use serde::Serialize;

/// Wall-clock seconds spent in each phase of one cycle (DESIGN.md data flow).
#[derive(Clone, Copy, Debug, Default, Serialize, PartialEq)]
pub struct PhaseSeconds {
    /// Dof numbering, constraints and sparsity pattern.
    pub setup: f64,
    /// Matrix and right-hand side assembly.
    pub assemble: f64,
    /// Linear solve or variational-inequality solve (all active-set iterations).
    pub solve: f64,
    /// A-posteriori error estimate.
    pub estimate: f64,
    /// Marking, refinement, coarsening and solution transfer.
    pub refine: f64,
}

impl PhaseSeconds {
    pub fn total(&self) -> f64 {
        self.setup + self.assemble + self.solve + self.estimate + self.refine
    }

    /// The phases with the column names used in the CSV output (`seconds_<phase>`).
    pub fn named(&self) -> [(&'static str, f64); 5] {
        [
            ("seconds_setup", self.setup),
            ("seconds_assemble", self.assemble),
            ("seconds_solve", self.solve),
            ("seconds_estimate", self.estimate),
            ("seconds_refine", self.refine),
        ]
    }
}

/// One row of a Chapter IV table as computed by tribo.
///
/// Column names follow the `column` values of `../shared/thesis/tables.csv`.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct CycleRow {
    /// Printed cycle number (row index of the thesis table).
    pub cycle: usize,
    pub active_cells: usize,
    /// Degrees of freedom, hanging and Dirichlet dofs included (deal.II `n_dofs()`).
    pub dofs: usize,
    /// A-posteriori estimate √(Σ_Q η_Q²).
    pub estimate: f64,
    /// estimate_k / estimate_{k−1}; `None` on the first printed row (the thesis prints `inf`).
    pub ratio: Option<f64>,
    /// Further real-valued columns of the table family (`contact_estimate`, `gap_ratio`, …),
    /// in a fixed order.
    pub quantities: Vec<(String, f64)>,
    /// Integer solver counters (`active_set_iterations`, …), in a fixed order.
    pub counters: Vec<(String, i64)>,
    pub seconds: PhaseSeconds,
}

impl CycleRow {
    /// Value of a real-valued column by name (`estimate`, `ratio` or one of `quantities`).
    pub fn value(&self, column: &str) -> Option<f64> {
        match column {
            "active_cells" => Some(self.active_cells as f64),
            "dofs" => Some(self.dofs as f64),
            "estimate" => Some(self.estimate),
            "ratio" => self.ratio,
            _ => self
                .quantities
                .iter()
                .find(|(n, _)| n == column)
                .map(|(_, v)| *v)
                .or_else(|| {
                    self.counters
                        .iter()
                        .find(|(n, _)| n == column)
                        .map(|(_, v)| *v as f64)
                }),
        }
    }
}

/// A solution value at a point after the last cycle (`report/data/<table>.probes.csv`).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Probe {
    pub x: f64,
    pub y: f64,
    /// `s1`, `s2` (displacement components) or `psi` (film pressure).
    pub component: String,
    pub value: f64,
}

/// An axis-parallel cell `[x0, x1] × [y0, y1]` with an optional value to colour it by.
#[derive(Clone, Copy, Debug, Serialize, PartialEq)]
pub struct CellBox {
    pub x0: f64,
    pub y0: f64,
    pub x1: f64,
    pub y1: f64,
}

/// The active cells of the mesh after a given cycle (thesis Fig. IV.1).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct MeshPicture {
    pub cycle: usize,
    pub cells: Vec<CellBox>,
}

/// The deformed body: every active cell as a quadrilateral of displaced corners
/// `x + scale · s(x)` (counter-clockwise from the lower-left corner), thesis Fig. IV.2.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct DeformedPicture {
    pub cycle: usize,
    /// Magnification of the displacement in the picture (1 = true scale).
    pub scale: f64,
    pub quads: Vec<[[f64; 2]; 4]>,
    /// Obstacle curves as polylines, in the same (magnified) frame.
    pub obstacles: Vec<Vec<[f64; 2]>>,
    /// Deformed positions of contact vertices that are in contact (active constraints).
    pub contact_points: Vec<[f64; 2]>,
    /// Short caption (e.g. penetration depth).
    pub caption: String,
}

/// A scalar field on the active cells (one value per cell, e.g. the mean film pressure ψ).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct FieldPicture {
    pub cycle: usize,
    /// Name of the field, e.g. `psi`.
    pub name: String,
    pub cells: Vec<(CellBox, f64)>,
    /// Cells to outline as a marked zone (e.g. cavitation ψ = 0), may be empty.
    pub zone: Vec<CellBox>,
    pub zone_label: String,
}

/// Everything one experiment run produced.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct RunResult {
    /// Table id, e.g. `IV.1`.
    pub table: String,
    /// Thesis section, e.g. `IV.1.1`.
    pub section: String,
    pub title: String,
    /// `quick` or `full`.
    pub tier: String,
    pub rows: Vec<CycleRow>,
    pub probes: Vec<Probe>,
    pub meshes: Vec<MeshPicture>,
    pub deformed: Vec<DeformedPicture>,
    pub fields: Vec<FieldPicture>,
    /// Bounding box of the domain `[x0, x1, y0, y1]`.
    pub domain: [f64; 4],
    /// Readings of the thesis and known differences that apply to this table (shown in the report).
    pub notes: Vec<String>,
}

impl RunResult {
    /// Cumulative wall seconds after each cycle (for the cost-of-accuracy plot).
    pub fn cumulative_seconds(&self) -> Vec<f64> {
        let mut acc = 0.0;
        self.rows
            .iter()
            .map(|r| {
                acc += r.seconds.total();
                acc
            })
            .collect()
    }
}

/// `v` to 4 significant digits (the precision of the printed thesis tables).
pub fn sig4(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let e = v.abs().log10().floor() as i32;
    if (-3..5).contains(&e) {
        let decimals = (3 - e).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.3e}")
    }
}

/// A float for a snapshot: 4 significant digits, and values below 1e-9 in magnitude (the
/// estimates of problems whose exact solution the discretisation reproduces, IV.38 and IV.43)
/// as `<1e-9`, because their digits are rounding noise that any change of summation order moves.
fn snap(v: f64) -> String {
    if v != 0.0 && v.abs() < 1e-9 {
        "<1e-9".into()
    } else {
        sig4(v)
    }
}

impl RunResult {
    /// The golden snapshot of a run: integers exactly, floats to 4 significant digits, never
    /// timings. Probe values below 1e-9 of the largest probe value are rounding noise (e.g. s₁
    /// on the neutral axis) and are written as 0.
    pub fn snapshot(&self) -> String {
        let mut s = format!(
            "table {} ({}), tier {}\n",
            self.table, self.section, self.tier
        );
        for r in &self.rows {
            s += &format!(
                "cycle {:>2}  cells {:>7}  dofs {:>8}  estimate {:>10}  ratio {:>7}",
                r.cycle,
                r.active_cells,
                r.dofs,
                snap(r.estimate),
                r.ratio.map(sig4).unwrap_or_else(|| "-".into())
            );
            for (name, v) in &r.quantities {
                s += &format!("  {name} {}", snap(*v));
            }
            for (name, v) in &r.counters {
                s += &format!("  {name} {v}");
            }
            s += "\n";
        }
        let scale = self.probes.iter().fold(0.0f64, |m, q| m.max(q.value.abs()));
        for p in &self.probes {
            let v = if p.value.abs() <= 1e-9 * scale {
                0.0
            } else {
                p.value
            };
            s += &format!("probe {} ({}, {}) = {}\n", p.component, p.x, p.y, sig4(v));
        }
        s
    }
}
