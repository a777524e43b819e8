//! The Reynolds problem (I.79) = (II.37) and the Reynolds problem with cavitation
//! (I.82) = (II.39), discretised with Q₁ (II.48), (II.50), (III.61) on the quadtree mesh.
//!
//! **Bilinear form.** The Reynolds scalar product (II.9) is
//! ⟨ψ, φ⟩_R = ∫ (∇φ − φ∇g/g)·(∇ψ − ψ∇g/g) dx. Expanding and integrating the cross term by parts,
//! −∫ ∇(ψφ)·∇g/g = ∫ ψφ (Δg/g − |∇g|²/g²) − ∫_{∂Ω₂} ψφ ∂_n g/g, gives for every test function
//! φ ∈ H¹₀(Ω₂) (the boundary term vanishes with φ)
//!
//! ⟨ψ, φ⟩_R = ∫ ∇ψ·∇φ dx + ∫ (Δg/g) ψ φ dx,
//!
//! i.e. the operator −(1/g)∂_μ(g²∂_μ(ψ/g)) = −Δψ + ψΔg/g of the strong form (I.77) that the
//! estimator of Theorem III.16 also uses. Only rows of test functions in H¹₀ are solved for (the
//! Dirichlet rows are eliminated), so both expressions define the same discrete problem up to
//! quadrature. tribo assembles the second form ([`Form::Potential`], the default): it is
//! symmetric, needs only g and Δg, and it reproduces constants exactly when Δg = 0 — the exact
//! solutions ψ ≡ 200 of (IV.9) and (IV.14) and the sign symmetry of the pairs (IV.7)/(IV.8),
//! (IV.10)/(IV.11), (IV.12)/(IV.13) then hold to rounding, which the product form with inexact
//! quadrature of ∇g/g only gives to O(h⁴). The product form (II.9) itself is available as
//! [`Form::Product`]; a test checks that both give the same solution up to quadrature error.
//!
//! **Load.** l_R (II.37) and l_{R,c} (II.39) from the general Chapter I formulas
//! ([`ThinFilm::reynolds_load`], [`ThinFilm::cavitation_load`]), 2×2 Gauss points per cell
//! (docs/estimators.md §1.2). The load, Δg/g and the squeeze part of the load at the quadrature
//! points are computed once per mesh ([`CellData`]) and shared by assembly and estimator; cells
//! unchanged since the previous mesh keep theirs, and for gaps that depend on x₁ alone the
//! formulas are evaluated once per distinct x₁ ([`ReynoldsProblem::cell_data_reusing`]).
//!
//! **Cavitation** (I.82): ψ ≥ 0 at every interior non-hanging vertex (hanging values are means
//! of their parents, boundary values are ψ₀ = 200), solved as the LCP Kψ − F ≥ 0, ψ ≥ 0,
//! ψ·(Kψ − F) = 0 by the primal–dual active-set method of [`crate::linalg::active_set`]
//! ([`solve_cavitation`]); the pattern of K never changes, so every iteration costs one numeric
//! Cholesky factorisation with the symbolic factorisation reused.

use crate::models::ModelError;
use rayon::prelude::*;

use crate::fe::cell_values::CellValues;
use crate::fe::quadrature::{self, square_rule};
use crate::fe::{DofMap, LocalDofs, System};
use crate::linalg::active_set::{
    primal_dual_active_set, ActiveSetOptions, ActiveSetSolution, Bounds, NodalBounds, Sense,
    ViolationTolerance,
};
use crate::mesh::{ActiveCells, CellId, Mesh};
use crate::models::manufactured::ExactPressure;
use crate::models::thin_film::{CavitationSource, ThinFilm};

/// Which expression of the Reynolds product (II.9) to assemble (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Form {
    /// ∫ ∇ψ·∇φ + (Δg/g) ψ φ — equal to (II.9) for φ ∈ H¹₀.
    #[default]
    Potential,
    /// ∫ (∇φ − φ∇g/g)·(∇ψ − ψ∇g/g), (II.9) as printed.
    Product,
}

/// Which load: l_R of (II.37) or l_{R,c} of (II.39).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Load {
    Reynolds,
    Cavitation,
}

/// The 2×2 Gauss points of the reference square, in the order of [`CellData`].
pub fn quadrature_points() -> [(f64, f64, f64); 4] {
    quadrature::square_rule::<4>()
}

/// Per-cell data at the 2×2 Gauss points (order of [`quadrature_points`]): the load l, Δg/g
/// and the squeeze part −12δv₃/g² of l (which the estimator's thesis-code reading leaves out,
/// `estimators::reynolds::VolumeResidual`).
pub struct CellData {
    pub load: Vec<[f64; 4]>,
    pub dg_over_g: Vec<[f64; 4]>,
    pub squeeze: Vec<[f64; 4]>,
}

/// The values of one cell in [`CellData`]: load, Δg/g, squeeze part.
type PointData = ([f64; 4], [f64; 4], [f64; 4]);

/// Values at the quadrature points of cells — the [`PointData`] of the cells a mesh did not keep
/// ([`ReynoldsProblem::fresh_point_data`]), or the film data of the energy's points
/// ([`ReynoldsProblem::energy`]) — as evaluated: per cell, once for every cell, or per column of
/// cells, read where they go, without a per-cell copy of the shared values.
enum FreshData<P> {
    /// The values of the `j`-th fresh cell.
    PerCell(Vec<P>),
    /// The same values for every cell.
    Everywhere(P),
    /// The values of each column (sorted), [`FreshData::column`].
    PerColumn {
        columns: Vec<(u8, u64)>,
        values: Vec<P>,
    },
}

impl<P: Copy> FreshData<P> {
    /// The column of cell `c`: its level and the integer position of its left side, which fix
    /// the x₁ of its quadrature points on a mesh of rectangles.
    fn column(mesh: &Mesh, c: CellId) -> (u8, u64) {
        let key = mesh.cell_key(c);
        (key.level, key.x)
    }

    /// The values of the `j`-th fresh cell, `c`.
    fn get(&self, mesh: &Mesh, j: usize, c: CellId) -> P {
        match self {
            FreshData::PerCell(values) => values[j],
            FreshData::Everywhere(values) => *values,
            FreshData::PerColumn { columns, values } => {
                let i = columns
                    .binary_search(&Self::column(mesh, c))
                    .expect("every column has a first cell");
                values[i]
            }
        }
    }
}

/// The film data at one point of the energy's quadrature: the gap g, ∇g, Δg and the load.
type EnergyPoint = (f64, [f64; 2], f64, f64);

/// [`CellData`] of one mesh with what the next mesh needs to find the cells it kept
/// ([`ReynoldsProblem::cell_data_reusing`]).
pub struct CellDataCache {
    pub load: Load,
    /// The mesh's cells ([`Mesh::kept_from`]).
    cells: ActiveCells,
    pub data: CellData,
    /// How many cells took their values from the previous mesh's cache.
    pub reused: usize,
}

/// One Reynolds example (§IV.3): film data, boundary pressure ψ₀, reading of γ₃c.
#[derive(Clone, Debug, PartialEq)]
pub struct ReynoldsProblem {
    pub film: ThinFilm,
    pub boundary_pressure: f64,
    pub cavitation_source: CavitationSource,
    pub form: Form,
    /// A manufactured pressure: its load −Δψ + ψΔg/g replaces l_R ([`ExactPressure::load`]).
    pub exact: Option<ExactPressure>,
}

/// Result of the cavitation solve.
#[derive(Clone, Debug)]
pub struct CavitationSolution {
    /// ψ_h, hanging values distributed.
    pub psi: Vec<f64>,
    /// Primal–dual active-set iterations (= numeric factorisations).
    pub iterations: usize,
    /// Vertices in the final active set (ψ = 0 imposed).
    pub active: Vec<bool>,
    /// max |min(ψᵢ, (Kψ − F)ᵢ)| over interior non-hanging vertices.
    pub complementarity: f64,
    /// ‖F‖∞ (scale of the complementarity tolerance).
    pub load_scale: f64,
}

/// Maximal number of primal–dual active-set iterations.
pub const MAX_ACTIVE_SET_ITERATIONS: usize = 100;

impl From<&crate::experiment::ReynoldsData> for ReynoldsProblem {
    fn from(d: &crate::experiment::ReynoldsData) -> ReynoldsProblem {
        ReynoldsProblem {
            film: ThinFilm::new((&d.gap).into(), d.upper_wall_velocity),
            boundary_pressure: d.boundary_pressure,
            cavitation_source: d.cavitation_source.into(),
            form: Form::default(),
            exact: d.exact.map(|name| ExactPressure {
                name,
                base: d.boundary_pressure,
            }),
        }
    }
}

impl ReynoldsProblem {
    /// l_R (II.37) or l_{R,c} (II.39) at `x`.
    #[inline]
    pub fn load(&self, x: [f64; 2], load: Load) -> f64 {
        if let Some(exact) = &self.exact {
            return exact.load(&self.film, x);
        }
        match load {
            Load::Reynolds => self.film.reynolds_load(x),
            Load::Cavitation => self.film.cavitation_load(x, self.cavitation_source),
        }
    }

    /// Load and Δg/g at the quadrature points of every active cell (in parallel).
    pub fn cell_data(&self, mesh: &Mesh, load: Load) -> CellData {
        self.cell_data_reusing(mesh, load, None).data
    }

    /// Load, Δg/g and squeeze part at the point `x`.
    fn point_values(&self, x: [f64; 2], load: Load) -> (f64, f64, f64) {
        let (g, _, lap) = self.film.gap(x);
        (
            self.load(x, load),
            lap / g,
            self.film.squeeze_load_at_gap(g),
        )
    }

    /// Load, Δg/g and squeeze part at the four quadrature points of active cell `c`, each
    /// point's values from `at`.
    fn point_data(mesh: &Mesh, c: CellId, at: impl Fn([f64; 2]) -> (f64, f64, f64)) -> PointData {
        let shape = mesh.cell_shape(c);
        let mut values = ([0.0; 4], [0.0; 4], [0.0; 4]);
        for (q, &(xi, eta, _)) in quadrature_points().iter().enumerate() {
            (values.0[q], values.1[q], values.2[q]) = at(shape.point(xi, eta));
        }
        values
    }

    /// [`PointData`] of the active cells `cells`, evaluated afresh.
    ///
    /// The film data of a scene are functions of the gap's jet and of constants
    /// ([`ThinFilm::film_jets`]), so where the gap does not vary in x₂ ([`Gap::varies_in_x2`]:
    /// plain, linear and wave gaps) every value depends on the x₁ coordinate of the point alone,
    /// bitwise. On a mesh of rectangles the x₁ of a quadrature point depends only on the
    /// cell's column — its level and the integer position of its left side
    /// ([`CellShape::point`]) — so the Chapter I formulas are evaluated once per column of
    /// cells (a few thousand per mesh instead of four points per cell) and looked up; the
    /// values are the same bits as a direct evaluation. Where the gap does not vary at all
    /// ([`Gap::varies_in_x1`]) one evaluation serves every cell. The hill gap, and any gap on a
    /// moved mesh, is evaluated point by point.
    ///
    /// [`Gap::varies_in_x2`]: crate::models::thin_film::Gap::varies_in_x2
    /// [`Gap::varies_in_x1`]: crate::models::thin_film::Gap::varies_in_x1
    /// [`CellShape::point`]: crate::mesh::CellShape::point
    fn fresh_point_data(&self, mesh: &Mesh, cells: &[CellId], load: Load) -> FreshData<PointData> {
        let evaluate = |c: CellId| Self::point_data(mesh, c, |x| self.point_values(x, load));
        self.shared_data(mesh, cells, &evaluate)
            .unwrap_or_else(|| FreshData::PerCell(cells.par_iter().map(|&c| evaluate(c)).collect()))
    }

    /// The values `evaluate` gives each of `cells`, evaluated once for every cell or once per
    /// column of cells where the film data allow it ([`Self::fresh_point_data`]); `None` where
    /// they must be evaluated cell by cell (a gap that varies in x₂, a moved mesh, a
    /// manufactured load).
    fn shared_data<P: Copy + Send + Sync>(
        &self,
        mesh: &Mesh,
        cells: &[CellId],
        evaluate: &(impl Fn(CellId) -> P + Sync),
    ) -> Option<FreshData<P>> {
        let gap = &self.film.gap;
        // A manufactured load varies in x₂ whatever the gap.
        if gap.varies_in_x2() || mesh.is_moved() || self.exact.is_some() {
            return None;
        }
        if !gap.varies_in_x1() {
            return Some(match cells.first() {
                Some(&c) => FreshData::Everywhere(evaluate(c)),
                None => FreshData::PerCell(Vec::new()),
            });
        }
        // One cell of each column, the first in `cells`.
        let mut firsts: Vec<((u8, u64), CellId)> = cells
            .par_iter()
            .map(|&c| (FreshData::<P>::column(mesh, c), c))
            .collect();
        firsts.par_sort_by_key(|e| e.0);
        firsts.dedup_by_key(|e| e.0);
        let values = firsts.par_iter().map(|&(_, c)| evaluate(c)).collect();
        Some(FreshData::PerColumn {
            columns: firsts.into_iter().map(|e| e.0).collect(),
            values,
        })
    }

    /// [`Self::cell_data`] reusing the values of cells that are unchanged since `previous`
    /// (same load, and a cell the refinement from the previous mesh kept, [`Mesh::kept_from`]:
    /// the same integer corners, so the quadrature points are the same and the values are
    /// bitwise those of a fresh evaluation). Returns the data of `mesh` and the cache for the
    /// next mesh. About 40 % of the cells survive a cycle of 30 % refinement; the others are
    /// evaluated afresh, once per distinct x₁ where the gap does not vary in x₂.
    pub fn cell_data_reusing(
        &self,
        mesh: &Mesh,
        load: Load,
        previous: Option<&CellDataCache>,
    ) -> CellDataCache {
        let active = mesh.active();
        // For each active cell: its index in `previous`, if it has one.
        let previous = previous.filter(|p| p.load == load);
        let kept = previous
            .and_then(|p| mesh.kept_from(&p.cells))
            .unwrap_or_else(|| vec![None; active.len()]);
        let fresh_cells: Vec<CellId> = active
            .iter()
            .zip(&kept)
            .filter(|(_, s)| s.is_none())
            .map(|(&c, _)| c)
            .collect();
        let reused = active.len() - fresh_cells.len();
        let fresh = self.fresh_point_data(mesh, &fresh_cells, load);
        let none = CellData {
            load: Vec::new(),
            dg_over_g: Vec::new(),
            squeeze: Vec::new(),
        };
        let old = previous.map_or(&none, |p| &p.data);
        // Cell k's values: from the previous mesh, or the next fresh ones in cell order; by
        // blocks of cells in parallel, each block starting after the fresh cells before it.
        const CELLS_PER_TASK: usize = 4096;
        let mut fresh_before: Vec<usize> = kept
            .par_chunks(CELLS_PER_TASK)
            .map(|block| block.iter().filter(|s| s.is_none()).count())
            .collect();
        let mut sum = 0;
        for n in &mut fresh_before {
            (*n, sum) = (sum, sum + *n);
        }
        let n = active.len();
        let mut data = CellData {
            load: vec![[0.0; 4]; n],
            dg_over_g: vec![[0.0; 4]; n],
            squeeze: vec![[0.0; 4]; n],
        };
        data.load
            .par_chunks_mut(CELLS_PER_TASK)
            .zip(data.dg_over_g.par_chunks_mut(CELLS_PER_TASK))
            .zip(data.squeeze.par_chunks_mut(CELLS_PER_TASK))
            .zip(kept.par_chunks(CELLS_PER_TASK))
            .zip(fresh_before)
            .for_each(|((((load, dg_over_g), squeeze), kept), mut j)| {
                for (i, s) in kept.iter().enumerate() {
                    (load[i], dg_over_g[i], squeeze[i]) = match *s {
                        Some(k) => {
                            let k = k as usize;
                            (old.load[k], old.dg_over_g[k], old.squeeze[k])
                        }
                        None => {
                            j += 1;
                            fresh.get(mesh, j - 1, fresh_cells[j - 1])
                        }
                    };
                }
            });
        CellDataCache {
            load,
            cells: mesh.active_cells(),
            data,
            reused,
        }
    }

    /// ψ = ψ₀ on ∂Ω₂: every boundary vertex fixed at the boundary pressure.
    pub fn constrain(&self, system: &mut System) {
        let v = &system.dofs.vertices;
        for vertex in 0..v.len() as u32 {
            if v.on_boundary(vertex) {
                system
                    .constraints
                    .fix(vertex as usize, self.boundary_pressure);
            }
        }
    }

    /// Stiffness matrix and load vector (2×2 Gauss) into `system`, with the cell data of
    /// [`Self::cell_data`].
    pub fn assemble(&self, mesh: &Mesh, system: &mut System, data: &CellData) {
        let active = mesh.active();
        let rule = square_rule::<4>();
        let form = self.form;
        let local = LocalDofs::new(1);
        system.assemble(active.len(), |k, ke, fe| {
            let cv = CellValues::new(mesh.cell_shape(active[k]), &rule);
            for q in 0..rule.len() {
                let g = cv.gradients(q);
                let phi = cv.values(q);
                let jw = cv.jxw(q);
                match form {
                    Form::Potential => {
                        let m = data.dg_over_g[k][q];
                        for a in 0..4 {
                            for b in 0..4 {
                                ke[local.entry(a, b)] +=
                                    (g[a][0] * g[b][0] + g[a][1] * g[b][1] + m * phi[a] * phi[b])
                                        * jw;
                            }
                        }
                    }
                    Form::Product => {
                        let (gv, dg, _) = self.film.gap(cv.point(q));
                        let t = [dg[0] / gv, dg[1] / gv];
                        let v: [[f64; 2]; 4] = std::array::from_fn(|a| {
                            [g[a][0] - phi[a] * t[0], g[a][1] - phi[a] * t[1]]
                        });
                        for a in 0..4 {
                            for b in 0..4 {
                                ke[local.entry(a, b)] +=
                                    (v[a][0] * v[b][0] + v[a][1] * v[b][1]) * jw;
                            }
                        }
                    }
                }
                let l = data.load[k][q];
                for a in 0..4 {
                    fe[a] += l * phi[a] * jw;
                }
            }
        })
    }
}

impl ReynoldsProblem {
    /// J(ψ_h) = ½a(ψ_h, ψ_h) − l(ψ_h), the functional the Reynolds solve minimises over V_h
    /// (the cavitation solve over ψ_h ≥ 0), for the load `load`: the energy identity of
    /// [`crate::study::accuracy`] measures the error with it. With the potential form a(ψ, ψ)
    /// differs from ‖ψ‖²_R by a boundary term that is the same for every ψ with ψ = ψ₀ on ∂Ω₂,
    /// so J differences are those of the Reynolds norm.
    ///
    /// The identity J(v) − J(u) = ½‖v − u‖² holds for every v, the discrete solution of the
    /// assembled problem (whose load is integrated with 2×2 Gauss points) included, but only for
    /// the exact J: so J is integrated here with 4×4 Gauss points, and the load and the gap are
    /// evaluated afresh at them. With the assembly's 2×2 points the quadrature error of ∫ l ψ_h
    /// (O(h⁴) per unit area, but with the fourth derivatives of l) would add to J(ψ_h) − J(ψ)
    /// on coarse meshes: on the manufactured Reynolds scene it moved the measured error of
    /// cycles 1 and 2 by 15 % and 11 %. The cells are summed in the order of `mesh.active()`.
    pub fn energy(&self, mesh: &Mesh, dofs: &DofMap, psi: &[f64], load: Load) -> f64 {
        let active = mesh.active();
        let rule = square_rule::<16>();
        // The film data at the 16 points of a cell; per column of cells where they depend on
        // x₁ alone, the same bits as cell by cell ([`Self::fresh_point_data`]).
        let evaluate = |c: CellId| -> [EnergyPoint; 16] {
            let shape = mesh.cell_shape(c);
            std::array::from_fn(|q| {
                let (xi, eta, _) = rule[q];
                let x = shape.point(xi, eta);
                let (gap, dg, laplace_g) = self.film.gap(x);
                (gap, dg, laplace_g, self.load(x, load))
            })
        };
        let shared = self.shared_data(mesh, active, &evaluate);
        let cells: Vec<f64> = (0..active.len())
            .into_par_iter()
            .map(|k| {
                let cv = CellValues::new(mesh.cell_shape(active[k]), &rule);
                let film = match &shared {
                    Some(shared) => shared.get(mesh, k, active[k]),
                    None => evaluate(active[k]),
                };
                let corner = dofs.corner_values(psi, k, 0);
                let mut sum = 0.0;
                for (q, &(gap, dg, laplace_g, l)) in film.iter().enumerate() {
                    let g = cv.gradients(q);
                    let phi = cv.values(q);
                    let v: f64 = (0..4).map(|a| corner[a] * phi[a]).sum();
                    let grad: [f64; 2] =
                        std::array::from_fn(|j| (0..4).map(|a| corner[a] * g[a][j]).sum());
                    let quadratic = match self.form {
                        Form::Potential => {
                            grad[0] * grad[0] + grad[1] * grad[1] + laplace_g / gap * v * v
                        }
                        Form::Product => {
                            let r = [grad[0] - v * dg[0] / gap, grad[1] - v * dg[1] / gap];
                            r[0] * r[0] + r[1] * r[1]
                        }
                    };
                    sum += (0.5 * quadratic - l * v) * cv.jxw(q);
                }
                sum
            })
            .collect();
        cells.iter().sum()
    }
}

/// The LCP of (III.61) by the primal–dual active-set method ([`primal_dual_active_set`]):
/// find ψ with ψᵢ ≥ 0, λᵢ = (Kψ − F)ᵢ ≥ 0, ψᵢλᵢ = 0 at the free vertices (not on ∂Ω₂, not
/// hanging), the constraints of `system` prescribed.
///
/// Iteration: A = {i : λᵢ − cᵢψᵢ > 0} with cᵢ = Kᵢᵢ > 0 (λ = 0 off A, ψ = 0 on A), up to
/// rounding bands of 1e-12·max(1, ‖F‖∞) for λ and 1e-13·max|ψ| for ψ; solve with ψ = 0 on A; stop
/// when A does not change. `initial` flags the first active set per dof (e.g. the vertices where
/// the unconstrained solution or the previous cycle's solution is ≤ 0). Tiny negative values
/// (rounding, |ψᵢ| below 1e-12·max|ψ|) left on inactive vertices are set to 0, so ψ ≥ 0 holds at
/// every vertex.
pub fn solve_cavitation(
    system: &System,
    solver: &mut dyn crate::linalg::SolveConstrained,
    initial: &[bool],
) -> Result<CavitationSolution, ModelError> {
    let n = system.dofs.n_dofs();
    let rhs = &system.rhs;
    let constrained: Vec<bool> = (0..n).map(|d| system.constraints.is_free(d)).collect();
    let bounds = Bounds::Uniform {
        at: &constrained,
        sense: Sense::Lower,
        value: 0.0,
    };
    let initial: Vec<bool> = bounds.iter().map(|b| initial[b.dof()]).collect();
    let load_scale = rhs
        .iter()
        .zip(&constrained)
        .filter(|(_, &c)| c)
        .fold(0.0f64, |m, (f, _)| m.max(f.abs()));
    let eliminated = system.constraints.eliminated();
    let problem = NodalBounds {
        matrix: system.matrix(),
        rhs,
        bounds,
        rotation: None,
        eliminated: &eliminated,
        negated_rows: false,
    };
    let options = ActiveSetOptions {
        max_iterations: MAX_ACTIVE_SET_ITERATIONS,
        multiplier_tolerance: 1e-12 * load_scale.max(1.0),
        violation: ViolationTolerance::SolutionScale(1e-13),
    };
    // Multipliers and slacks are not needed here: dropped at once.
    let ActiveSetSolution {
        x: mut psi,
        active: bound_active,
        iterations,
        ..
    } = primal_dual_active_set(&problem, solver, Some(&initial), &options)
        .map_err(|e| ModelError::from(e).context("cavitation"))?;
    drop(initial);
    let scale = psi.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for i in 0..n {
        if constrained[i] && psi[i] < 0.0 {
            if psi[i] < -1e-12 * scale {
                return Err(ModelError::Failed(format!(
                    "cavitation: ψ = {} < 0 at an inactive vertex after convergence",
                    psi[i]
                )));
            }
            psi[i] = 0.0;
        }
    }
    system.constraints.distribute(&mut psi);
    let kpsi = system.matrix().multiply(&psi);
    let complementarity = (0..n)
        .filter(|&i| constrained[i])
        .map(|i| psi[i].min(kpsi[i] - rhs[i]).abs())
        .fold(0.0f64, f64::max);
    let mut active = vec![false; n];
    for (b, &a) in bounds.iter().zip(&bound_active) {
        active[b.dof()] = a;
    }
    Ok(CavitationSolution {
        psi,
        iterations,
        active,
        complementarity,
        load_scale,
    })
}
