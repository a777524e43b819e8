//! What one experiment run produces: one [`Row`] of named columns per printed cycle, solution probes and
//! pictures for the report. Everything here comes from running the solvers; the thesis rows live
//! in [`crate::thesis`] and are only ever shown beside these numbers.

use serde::{Deserialize, Serialize};

/// Wall-clock seconds spent in each phase of one cycle (docs/architecture.md, "Data flow").
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq)]
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

    /// The phase-wise sum of two cycles' seconds.
    pub fn plus(&self, other: &PhaseSeconds) -> PhaseSeconds {
        PhaseSeconds {
            setup: self.setup + other.setup,
            assemble: self.assemble + other.assemble,
            solve: self.solve + other.solve,
            estimate: self.estimate + other.estimate,
            refine: self.refine + other.refine,
        }
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

/// Names of the columns that the loop and the report know by name. Every other column is the
/// problem's own (`contact_estimate`, `coarse_faces`, …); the report shows it without a special
/// case.
pub mod columns {
    /// Active cells of the mesh of the row (a count).
    pub const ACTIVE_CELLS: &str = "active_cells";
    /// Degrees of freedom, hanging and Dirichlet dofs included (deal.II `n_dofs()`; a count).
    pub const DOFS: &str = "dofs";
    /// A-posteriori estimate √(Σ_Q η_Q²) of the grid-adaptive tables.
    pub const ESTIMATE: &str = "estimate";
    /// estimate_k / estimate_{k−1} between printed rows, empty in the first (the thesis prints
    /// `inf`); added by the study beside every `estimate` column.
    pub const RATIO: &str = "ratio";
    /// The estimate of the previous solve: the thesis's fluid tables print the cells and dofs of
    /// the mesh *after* refinement next to the estimate computed *before* it (row k: mesh of
    /// solve k+1, estimate of solve k). The report compares the printed estimate with it.
    pub const PREVIOUS_ESTIMATE: &str = "estimate_previous_mesh";
    /// The estimate of Theorem III.16 / III.17 as stated, recorded when the marking uses another
    /// term set (`estimator = "thesis-code"`).
    pub const THEOREM_ESTIMATE: &str = "estimate_theorem";
    /// Vertices of the contact boundary where the obstacle constraint is active (a count).
    pub const CONTACT_VERTICES: &str = "contact_vertices";
    /// Contact faces with the z-model, |𝕋_c| of the model-adaptive tables (a count).
    pub const COARSE_FACES: &str = "coarse_faces";
    /// Contact faces with the Signorini model, |𝕋_a| (a count).
    pub const ACCURATE_FACES: &str = "accurate_faces";
    /// The model-error estimate (Σ_{f∈𝕋_c} ε^m(f)²)^{1/2} of (III.16) over the z-faces.
    pub const MODEL_ERROR: &str = "model_error";
    /// Largest vertical depth of the deformed contact boundary beyond its obstacle.
    pub const PENETRATION: &str = "penetration";
    /// How many cycles back the same face partition was used (0: new; 1: unchanged; 2: a flip
    /// between two partitions).
    pub const PARTITION_REPEAT: &str = "partition_repeat";
    /// Load steps (the U-O forming, §IV.2.4.7): the position of the material point at the
    /// lower right corner of the undeformed strip after the step's motion.
    pub const TIP_X: &str = "tip_x";
    pub const TIP_Y: &str = "tip_y";
    /// Model-and-grid-adaptive contact (Tables IV.30–IV.35): contact faces on the z-model.
    pub const Z_FACES: &str = "z_faces";
    /// Contact faces on the Signorini model.
    pub const S_FACES: &str = "s_faces";
    /// √Σ η_Q² over the cells with a z-face.
    pub const EST_Z_BOUNDARY: &str = "est_z_boundary";
    /// √Σ η_Q² over the cells with a Signorini face.
    pub const EST_S_BOUNDARY: &str = "est_s_boundary";
    /// √Σ η_Q² over the cells without a contact face.
    pub const EST_INTERIOR: &str = "est_interior";
    /// CG iterations of the multigrid-preconditioned solve (the most over the solves of the
    /// cycle, e.g. of an active-set iteration); absent with the direct solver.
    pub const CG_ITERATIONS: &str = "cg_iterations";
    /// The true error in the estimator's norm (‖s − s_h‖_a for elasticity and contact,
    /// ‖ψ − ψ_h‖_R for Reynolds): against the exact field on the scenes with a manufactured
    /// solution ([`crate::estimators::true_error`]), else measured without one
    /// ([`crate::study::accuracy`]).
    pub const ERROR: &str = "error";
    /// estimate / error, the effectivity index.
    pub const EFFECTIVITY: &str = "effectivity";
    /// J(u_h) = ½a(u_h, u_h) − l(u_h), the energy of the cycle's solution, where the problem
    /// minimises one ([`crate::study::Problem::energy`]).
    pub const ENERGY: &str = "energy";
    /// Scenes with a manufactured solution only: the error measured as on a scene without one
    /// ([`crate::study::accuracy`]), to check that measurement against the true `error`.
    pub const MEASURED_ERROR: &str = "measured_error";
    /// Scenes with a manufactured solution measured against a reference solve (SubStokes)
    /// only: the error measured against the run's own last solve, as the uniform runs beside
    /// those tables are ([`crate::study::reference::against_last_solve`]), to check it.
    pub const LAST_SOLVE_ERROR: &str = "last_solve_error";
    /// Scenes with a manufactured solution whose measure is not a reference solve (the
    /// cavitation scene, measured by its energy) only: the error against a reference solve on
    /// the last mesh refined once, as the tables whose energy gives none are measured (IV.64,
    /// [`crate::study::reference::against_refined_solve`]), to check it.
    pub const REFERENCE_ERROR: &str = "reference_error";
}

/// One cycle of the uniform run beside a grid-adaptive table ([`crate::study::uniform`]).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct UniformRow {
    /// Uniform refinements of the scene's initial mesh.
    pub cycle: usize,
    pub active_cells: usize,
    pub dofs: usize,
    /// √(Σ η_Q²) of the table's estimator.
    pub estimate: f64,
    /// The true error, measured as the table's (`None` where it could not be).
    pub error: Option<f64>,
    /// Seconds of the cycle's solve: setup, assembly, solve and estimate.
    pub seconds: f64,
}

/// How the true error of a run without an exact solution was measured ([`crate::study::accuracy`]).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub enum ErrorMeasure {
    /// The energy identity J(u_h) − J(u) = ½‖u − u_h‖²_a with J(u) extrapolated from the
    /// cycles `cycles` by J(u_h) = J(u) + C·dofs^(−beta); `bound` where the problem is a
    /// variational inequality and the identity only bounds the error from above.
    Energy {
        limit: f64,
        beta: f64,
        cycles: Vec<usize>,
        bound: bool,
    },
    /// Against a reference solution on a finer mesh of `dofs` unknowns, solved in `seconds`
    /// (setup, assembly and solve, wall time) after the run.
    Reference {
        dofs: usize,
        #[serde(default)]
        seconds: f64,
    },
    /// Against the run's own last solve, whose error is extrapolated as the estimate divided
    /// by `effectivity`, fitted to the distances of the cycles `cycles`
    /// ([`crate::study::reference::against_last_solve`]).
    LastSolve {
        effectivity: f64,
        cycles: Vec<usize>,
    },
}

/// The value of one column in one row.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub enum Value {
    /// An integer: cells, dofs, faces, iterations.
    Count(i64),
    /// A real number; `None` where it is undefined (the first ratio, a ratio to 0). Never NaN
    /// or infinite when made with [`Value::real`], which every producer uses: an undefined value
    /// is an empty cell in the CSV files and the snapshots (report/README.md).
    Real(Option<f64>),
}

impl Value {
    /// A real value, `None` (undefined) unless it is finite: 0/0 and x/0 are undefined, not NaN
    /// or infinite, in every output.
    pub fn real(v: Option<f64>) -> Value {
        Value::Real(v.filter(|x| x.is_finite()))
    }

    /// The value with a non-finite real made undefined (counts unchanged): what a row stores,
    /// whoever made the value.
    pub fn defined(self) -> Value {
        match self {
            Value::Real(v) => Value::real(v),
            count => count,
        }
    }

    /// The value as a real number (counts converted).
    pub fn as_f64(&self) -> Option<f64> {
        match *self {
            Value::Count(n) => Some(n as f64),
            Value::Real(v) => v,
        }
    }
}

/// One row of a Chapter IV table as computed by tribo: the printed cycle, named columns in a
/// fixed order, and the seconds per phase. Column names follow the `column` values of
/// `../shared/thesis/tables.csv` where the thesis prints them.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Row {
    /// Printed cycle number (row index of the thesis table).
    pub cycle: usize,
    pub columns: Vec<(String, Value)>,
    pub seconds: PhaseSeconds,
}

impl Row {
    /// A row of cycle `cycle` without columns.
    pub fn new(cycle: usize) -> Row {
        Row {
            cycle,
            columns: Vec::new(),
            seconds: PhaseSeconds::default(),
        }
    }

    /// Append a count column.
    pub fn count(mut self, name: &str, n: usize) -> Row {
        self.columns
            .push((name.to_string(), Value::Count(n as i64)));
        self
    }

    /// Append a real column.
    pub fn real(mut self, name: &str, v: Option<f64>) -> Row {
        self.columns.push((name.to_string(), Value::real(v)));
        self
    }

    /// Set a column's value (appended if the row does not have it yet).
    pub fn set(&mut self, name: &str, value: Value) {
        let value = value.defined();
        match self.columns.iter_mut().find(|(n, _)| n == name) {
            Some((_, v)) => *v = value,
            None => self.columns.push((name.to_string(), value)),
        }
    }

    /// The column of that name.
    pub fn get(&self, column: &str) -> Option<Value> {
        self.columns
            .iter()
            .find(|(n, _)| n == column)
            .map(|(_, v)| *v)
    }

    /// Value of a column by name as a real number (counts converted), if the row has it and it
    /// is defined.
    pub fn value(&self, column: &str) -> Option<f64> {
        self.get(column)?.as_f64()
    }

    /// Value of a count column by name.
    pub fn count_of(&self, column: &str) -> Option<i64> {
        match self.get(column)? {
            Value::Count(n) => Some(n),
            Value::Real(_) => None,
        }
    }

    /// Active cells of the row's mesh.
    pub fn active_cells(&self) -> Option<usize> {
        self.count_of(columns::ACTIVE_CELLS).map(|n| n as usize)
    }

    /// Dofs of the row's mesh.
    pub fn dofs(&self) -> Option<usize> {
        self.count_of(columns::DOFS).map(|n| n as usize)
    }

    /// The `estimate` column.
    pub fn estimate(&self) -> Option<f64> {
        self.value(columns::ESTIMATE)
    }

    /// The `ratio` column.
    pub fn ratio(&self) -> Option<f64> {
        self.value(columns::RATIO)
    }

    /// The count columns (solver counters and face counts), in order.
    pub fn counts(&self) -> Vec<(&str, i64)> {
        self.columns
            .iter()
            .filter_map(|(n, v)| match v {
                Value::Count(c) => Some((n.as_str(), *c)),
                Value::Real(_) => None,
            })
            .collect()
    }
}

/// A solution value at a point after the last cycle (`report/data/<table>.probes.csv`).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Probe {
    pub x: f64,
    pub y: f64,
    /// `s1`, `s2` (displacement components) or `psi` (film pressure).
    pub component: String,
    pub value: f64,
}

/// An axis-parallel cell `[x0, x1] × [y0, y1]` with an optional value to colour it by.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct CellBox {
    pub x0: f64,
    pub y0: f64,
    pub x1: f64,
    pub y1: f64,
}

/// The active cells of the mesh after a given cycle (thesis Fig. IV.1).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct MeshPicture {
    pub cycle: usize,
    pub cells: Vec<CellBox>,
    /// Refinement level of each cell of `cells` (0 = a cell of the coarse grid), in the same
    /// order; empty when the producer does not know them (the picture then counts levels by
    /// halvings of the largest cell drawn).
    pub levels: Vec<u8>,
    /// Cells drawn grey (the SubStokes cells of a model-adaptive fluid run); usually empty.
    pub shaded: Vec<CellBox>,
}

/// The deformed body: every active cell as a quadrilateral of displaced corners
/// `x + scale · s(x)` (counter-clockwise from the lower-left corner), thesis Fig. IV.2.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct DeformedPicture {
    pub cycle: usize,
    /// Magnification of the displacement in the picture (1 = true scale).
    pub scale: f64,
    pub quads: Vec<[[f64; 2]; 4]>,
    /// Obstacle curves as polylines, in the same (magnified) frame.
    pub obstacles: Vec<Vec<[f64; 2]>>,
    /// Deformed positions of contact vertices that are in contact (active constraints).
    pub contact_points: Vec<[f64; 2]>,
    /// The contact faces on the Signorini model (model-adaptive contact), deformed ends.
    pub accurate_faces: Vec<[[f64; 2]; 2]>,
    /// Short caption (e.g. penetration depth).
    pub caption: String,
}

/// A scalar field on the active cells (one value per cell, e.g. the mean film pressure ψ).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct FieldPicture {
    pub cycle: usize,
    /// Name of the field, e.g. `psi`.
    pub name: String,
    pub cells: Vec<(CellBox, f64)>,
    /// Cells to outline as a marked zone (e.g. cavitation ψ = 0), may be empty.
    pub zone: Vec<CellBox>,
    pub zone_label: String,
    /// A vector field drawn as arrows over the map (the SubStokes flow rate χ), may be empty.
    pub arrows: Vec<Arrow>,
}

/// One arrow of a vector field: its foot and the vector there.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct Arrow {
    pub at: [f64; 2],
    pub v: [f64; 2],
}

/// One contact face of a model-adaptive cycle: where it lies, its model and its indicator.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct FaceModel {
    /// `bottom` or `top`.
    pub side: String,
    /// The face's extent along x₁ (undeformed).
    pub x0: f64,
    pub x1: f64,
    /// Signorini (𝕋_a) rather than z (𝕋_c).
    pub accurate: bool,
    /// ε^m(f) of this cycle.
    pub error: f64,
}

/// The partition of the contact faces into z and Signorini in one cycle (thesis Figs IV.35–IV.45).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct PartitionPicture {
    pub cycle: usize,
    pub faces: Vec<FaceModel>,
}

/// One cycle of one variant of the cost-of-accuracy study of a model-adaptive scene
/// (`crate::study::cost`).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct CostRow {
    /// `z`, `signorini`, `III.2` or `III.3`.
    pub variant: String,
    pub cycle: usize,
    /// Wall seconds of the cycle's solves.
    pub seconds_solve: f64,
    /// Active-set iterations of the cycle's solves.
    pub iterations: i64,
    /// Largest vertical depth of the deformed contact boundary beyond its obstacle.
    pub penetration: f64,
    /// ‖s − s_S‖_a / ‖s_S‖_a, s_S the all-Signorini solution on the same mesh.
    pub energy_distance: f64,
    /// Contact faces on the Signorini model.
    pub accurate_faces: usize,
    /// The model-error estimate (Σ_{f∈𝕋_c} ε^m(f)²)^{1/2} over the z-faces.
    pub model_error: f64,
    /// ε₀ of the marking: Algorithm III.3 stops moving faces once the model error is below it,
    /// so errors below ε₀ count as equal when the variants are compared.
    pub model_tolerance: f64,
}

/// The variants of cost rows in the order they first appear (the order of the study, hence of
/// the file and the page).
pub fn cost_variants(costs: &[CostRow]) -> Vec<&str> {
    let mut variants: Vec<&str> = Vec::new();
    for c in costs {
        if !variants.contains(&c.variant.as_str()) {
            variants.push(&c.variant);
        }
    }
    variants
}

/// The claim closing §IV.2.3 on the cost rows of one scene: over the cycles after the first,
/// (cycles where III.3's model error ≤ III.2's — or both are at most ε₀, where III.3 stops by
/// design —, cycles where III.3 has no more Signorini faces than III.2, cycles compared).
pub fn claim_of_section_iv_2_3(costs: &[CostRow]) -> (usize, usize, usize) {
    let of = |variant: &str| -> Vec<&CostRow> {
        costs
            .iter()
            .filter(|c| c.variant == variant && c.cycle > 0)
            .collect()
    };
    let pairs: Vec<_> = of("III.2").into_iter().zip(of("III.3")).collect();
    let lower_error = pairs
        .iter()
        .filter(|(f, s)| s.model_error <= f.model_error.max(s.model_tolerance))
        .count();
    let fewer_faces = pairs
        .iter()
        .filter(|(f, s)| s.accurate_faces <= f.accurate_faces)
        .count();
    (lower_error, fewer_faces, pairs.len())
}

/// Two thin-film models along a horizontal cut (§IV.3.3, §IV.3.7): the columns of
/// `report/data/<table>.cuts.csv` (`crate::models::film_comparison`).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Cuts {
    /// The height x₂ of the cut.
    pub y: f64,
    /// ψ₀ on ∂Ω₂, the reference of the relative difference.
    pub boundary_pressure: f64,
    /// Named columns of equal length, `x` first.
    pub columns: Vec<(String, Vec<f64>)>,
    /// With cavitation: the cavitated area fraction of the SubStokes solution.
    pub cavitated_substokes: Option<f64>,
    /// With cavitation: the cavitated area fraction of the Reynolds solution on the same mesh.
    pub cavitated_reynolds: Option<f64>,
}

impl Cuts {
    /// Whether these are a SubStokes table's cuts, with the Reynolds model beside it (else one
    /// model's pressure: a Reynolds table's, or the model-adaptive film's).
    pub fn compares_models(&self) -> bool {
        self.column("psi_substokes").is_some()
    }

    /// The column `name`, if there is one.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.columns
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_slice())
    }

    /// max|ψ^S − ψ^R| over the cut relative to max|ψ^R − ψ₀|, the measure of §IV.3.3's
    /// comparison; `None` without both models' pressure or where ψ^R is ψ₀ along the whole cut.
    pub fn relative_pressure_difference(&self) -> Option<f64> {
        let boundary_pressure = self.boundary_pressure;
        let s = self.column("psi_substokes")?;
        let r = self.column("psi_reynolds")?;
        let diff = s
            .iter()
            .zip(r)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        let scale = r
            .iter()
            .fold(0.0f64, |m, b| m.max((b - boundary_pressure).abs()));
        (scale > 0.0).then(|| diff / scale)
    }
}

/// One outer iteration of a Uzawa run of a solver study (Fig. III.6; the module docs of
/// [`crate::linalg::uzawa`], "Residual and rows").
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct UzawaRow {
    /// [`Variant::name`](crate::linalg::uzawa::Variant::name).
    pub variant: String,
    pub iteration: usize,
    /// √(‖Av − Bp − f‖² + ‖Bᵀv + Cp − g‖²).
    pub residual: f64,
    /// residual / residual of row 0.
    pub relative_residual: f64,
    /// ‖p − p_direct‖₂ / ‖p_direct‖₂, when a reference pressure was given.
    pub pressure_error: Option<f64>,
    /// Inner CG iterations since the previous row.
    pub inner_iterations: usize,
    /// Wall seconds since the run started.
    pub seconds: f64,
}

/// One parameter of the scene or the study, as the experiment file writes it
/// ([`crate::experiment::parameters`]): `group` is the file's table (`scene`,
/// `scene.substokes`, `study`).
#[derive(Clone, Debug, Serialize, serde::Deserialize, PartialEq)]
pub struct Parameter {
    pub group: String,
    pub key: String,
    pub value: String,
}

/// A field on the last mesh: `components` values per point or per cell, interleaved
/// (`values.len()` = `components` × points or cells).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct MeshField {
    /// `displacement`, `psi`, `cavitation`, `contact`, `eta_squared`, …
    pub name: String,
    /// 1 for a scalar, 2 for a vector in the plane (s₁, s₂ or χ₁, χ₂).
    pub components: usize,
    pub values: Vec<f64>,
    /// What the values are: reals, or small whole numbers (flags, levels) that a file may
    /// store in one byte each.
    pub kind: FieldKind,
}

/// Mantissa bits an [`FieldKind::Indicator`] keeps (relative rounding 2⁻¹³ ≈ 1.2e-4).
pub const INDICATOR_BITS: u32 = 12;

/// The kind of a [`MeshField`]'s values, which sets how a file stores them.
#[derive(Clone, Copy, Debug, Serialize, PartialEq, Eq)]
pub enum FieldKind {
    /// Reals: the solutions (ψ, χ, the displacement) and the fields derived from them (the mean
    /// pressure ψ/g, the gap, the stresses, the indicators η²), stored in single precision,
    /// 7 significant digits: enough to look at, half the bytes of doubles.
    Real,
    /// The indicators η_Q² of a marking: single precision rounded to
    /// [`INDICATOR_BITS`] bits of mantissa (4 significant digits, the page's), which halves
    /// their compressed size; an indicator ranks cells, its fifth digit says nothing.
    Indicator,
    /// Whole numbers in 0..=255: a 0/1 flag of a vertex set, a refinement level.
    Small,
}

impl MeshField {
    /// A field of reals, `components` per point or cell.
    pub fn real(name: &str, components: usize, values: Vec<f64>) -> MeshField {
        MeshField {
            name: name.into(),
            components,
            values,
            kind: FieldKind::Real,
        }
    }

    /// A scalar field of marking indicators ([`FieldKind::Indicator`]).
    pub fn indicator(name: &str, values: Vec<f64>) -> MeshField {
        MeshField {
            name: name.into(),
            components: 1,
            values,
            kind: FieldKind::Indicator,
        }
    }

    /// A scalar field of small whole numbers ([`FieldKind::Small`]).
    pub fn small(name: &str, values: Vec<f64>) -> MeshField {
        MeshField {
            name: name.into(),
            components: 1,
            values,
            kind: FieldKind::Small,
        }
    }

    /// A 0/1 field: 1 where `member` holds.
    pub fn flags(name: &str, member: impl IntoIterator<Item = bool>) -> MeshField {
        let values = member.into_iter().map(|m| f64::from(u8::from(m))).collect();
        MeshField::small(name, values)
    }
}

/// Which meshes of a run go into `data/` as VTU files (`report --vtu`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum VtuOutput {
    /// No VTU file.
    None,
    /// The last printed mesh of each table as written (not of its alternative readings).
    #[default]
    Last,
    /// Every printed cycle of each table and of its alternative readings.
    All,
}

/// The mesh of the last printed cycle with the solution on it, for `data/<table>.vtu`: every
/// vertex of the active cells (hanging vertices included, with their constrained values) and
/// every active cell by its four corners.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct LastMesh {
    /// The printed cycle (the load step of a load-step run).
    pub cycle: usize,
    /// Vertex positions; on a moved grid (the forming) the moved positions.
    pub points: Vec<[f64; 2]>,
    /// Four vertex numbers per active cell, counter-clockwise from the lower-left corner.
    pub cells: Vec<[u32; 4]>,
    /// Fields with one value (or vector) per point.
    pub point_fields: Vec<MeshField>,
    /// Fields with one value per cell.
    pub cell_fields: Vec<MeshField>,
}

/// Everything one experiment run produced.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct RunResult {
    /// Table id, e.g. `IV.1`.
    pub table: String,
    /// Thesis section, e.g. `IV.1.1`.
    pub section: String,
    pub title: String,
    /// `quick` or `full`.
    pub tier: String,
    pub rows: Vec<Row>,
    pub probes: Vec<Probe>,
    pub meshes: Vec<MeshPicture>,
    pub deformed: Vec<DeformedPicture>,
    pub fields: Vec<FieldPicture>,
    /// The contact-face models of every printed cycle of a model-adaptive run (empty otherwise).
    pub partitions: Vec<PartitionPicture>,
    /// The cost-of-accuracy study of a model-adaptive scene (empty unless the report ran it).
    pub costs: Vec<CostRow>,
    /// A SubStokes run: the Reynolds model on its last mesh and both along a cut.
    pub cuts: Option<Cuts>,
    /// A solver study (Fig. III.6): every iteration of every Uzawa variant (empty otherwise).
    pub uzawa: Vec<UzawaRow>,
    /// Bounding box of the domain `[x0, x1, y0, y1]`.
    pub domain: [f64; 4],
    /// Readings of the thesis and known differences that apply to this table (shown in the report).
    pub notes: Vec<String>,
    /// Tables of the same scene solved another way, drawn beside this one where the report has
    /// them (`related` of the experiment file).
    pub related: Vec<String>,
    /// A thin film: whether the cavitation model was in use at the end of the run (with
    /// `cavitation = "auto"`, whether it switched on); `None` for the other problems.
    pub cavitation_ran: Option<bool>,
    /// What is legal but suspicious in the experiment or the run (`field: message`, shown in
    /// the report and on stderr).
    pub warnings: Vec<String>,
    /// The `[scene]` and `[study]` keys of the experiment file, shown above the section's table.
    pub parameters: Vec<Parameter>,
    /// How the column `error` was measured on a scene without an exact solution (`None` where
    /// it was not: no energy and no reference, or an exact solution).
    #[serde(default)]
    pub accuracy: Option<ErrorMeasure>,
    /// The uniform run beside a grid-adaptive table (empty unless the report ran it).
    #[serde(default)]
    pub uniform: Vec<UniformRow>,
    /// The run's place in a sweep, where it is one of a sweep's runs (the report compares them).
    #[serde(default)]
    pub sweep: Option<crate::experiment::sweep::SweepRun>,
    /// The last printed mesh with its solution fields; the report writes it as
    /// `data/<table>.vtu` and then drops it (it is as large as the mesh).
    #[serde(skip)]
    pub last_mesh: Option<LastMesh>,
    /// The meshes of the printed cycles before the last, with their fields, where the run
    /// keeps them (`report --vtu all`); written and dropped like `last_mesh`.
    #[serde(skip)]
    pub cycle_meshes: Vec<LastMesh>,
}

impl RunResult {
    /// The result of a run before its first row: nothing computed, no notes.
    pub fn new(table: &str, section: &str, title: &str, tier: &str, domain: [f64; 4]) -> RunResult {
        RunResult {
            table: table.into(),
            section: section.into(),
            title: title.into(),
            tier: tier.into(),
            rows: Vec::new(),
            probes: Vec::new(),
            meshes: Vec::new(),
            deformed: Vec::new(),
            fields: Vec::new(),
            partitions: Vec::new(),
            costs: Vec::new(),
            cuts: None,
            uzawa: Vec::new(),
            domain,
            notes: Vec::new(),
            related: Vec::new(),
            cavitation_ran: None,
            warnings: Vec::new(),
            accuracy: None,
            uniform: Vec::new(),
            sweep: None,
            parameters: Vec::new(),
            last_mesh: None,
            cycle_meshes: Vec::new(),
        }
    }

    /// Whether the run chose a contact model per face on a fixed mesh (the model-adaptive
    /// tables IV.18–IV.29): it has a partition per printed cycle and the columns
    /// `coarse_faces`/`accurate_faces` of a fixed mesh (the model-and-grid-adaptive tables
    /// print `z_faces`/`s_faces` and an estimate that converges in dofs).
    pub fn is_model_adaptive(&self) -> bool {
        !self.partitions.is_empty()
            && self
                .rows
                .first()
                .is_some_and(|r| r.count_of(columns::COARSE_FACES).is_some())
    }

    /// Whether the run is a load-step study (the U-O forming, Fig. IV.54): one row per step with
    /// the tip's position, and the body after every step among the deformed pictures.
    pub fn is_load_steps(&self) -> bool {
        self.rows
            .first()
            .is_some_and(|r| r.get(columns::TIP_Y).is_some())
    }

    /// Whether the run chose a contact model per face (model-adaptive, with or without grid
    /// adaptivity): it has a partition per printed cycle.
    pub fn has_partitions(&self) -> bool {
        !self.partitions.is_empty()
    }
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
    /// on the neutral axis) and are written as 0. The layout of a row is `cycle`, then every
    /// column as `name value` (the four columns of every grid-adaptive table aligned).
    pub fn snapshot(&self) -> String {
        let mut s = format!(
            "table {} ({}), tier {}\n",
            self.table, self.section, self.tier
        );
        for r in &self.rows {
            s += &format!("cycle {:>2}", r.cycle);
            // The CG iterations depend on the solver chosen, not on what is computed: both
            // solvers share one snapshot (the iterations are in the CSV files). The comparison
            // of the linearised Signorini solution with the converged one is a reading beside
            // the table, checked by its own tests (it is in the CSV files too). The energy is
            // the measurement behind `error`, which is in the snapshot.
            for (name, v) in r.columns.iter().filter(|(n, _)| {
                n != columns::CG_ITERATIONS
                    && n != columns::ENERGY
                    && n != columns::MEASURED_ERROR
                    && n != columns::LAST_SOLVE_ERROR
                    && n != columns::REFERENCE_ERROR
                    && !crate::study::signorini::columns::is_comparison(n)
            }) {
                s += &snapshot_column(name, v);
            }
            s += "\n";
        }
        // A solver study: every tenth iteration of each variant and its last.
        for (i, r) in self.uzawa.iter().enumerate() {
            let last = self.uzawa.get(i + 1).is_none_or(|n| n.variant != r.variant);
            if r.iteration % 10 == 0 || last {
                s += &format!(
                    "{:<12} k {:>3}  relative residual {}  pressure error {}  inner {}\n",
                    r.variant,
                    r.iteration,
                    sig4(r.relative_residual),
                    r.pressure_error.map_or("-".into(), sig4),
                    r.inner_iterations
                );
            }
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

/// One column of a snapshot row: `  name value`. The four columns every grid-adaptive table has
/// are aligned (`cells`, `dofs`, `estimate`, `ratio`), and the ratio, a number near 1 by
/// construction, is never written as a noise floor.
fn snapshot_column(name: &str, value: &Value) -> String {
    let real = |v: &Option<f64>, f: fn(f64) -> String| v.map(f).unwrap_or_else(|| "-".into());
    match (name, value) {
        (columns::ACTIVE_CELLS, Value::Count(n)) => format!("  cells {n:>7}"),
        (columns::DOFS, Value::Count(n)) => format!("  dofs {n:>8}"),
        (columns::ESTIMATE, Value::Real(v)) => format!("  estimate {:>10}", real(v, snap)),
        (columns::RATIO, Value::Real(v)) => format!("  ratio {:>7}", real(v, sig4)),
        (_, Value::Count(n)) => format!("  {name} {n}"),
        (_, Value::Real(v)) => format!("  {name} {}", real(v, snap)),
    }
}
