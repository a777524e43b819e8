//! What a study iterates on, and the two places where table families differ: the *problem*
//! (what is assembled and solved, which columns it produces) and the *adaptation* (what changes
//! between cycles, [`super::adapt`]).

use std::collections::BTreeSet;

use super::reference::VertexField;
use crate::adaptivity::model::{ModelIndicators, ModelUnit};
use crate::experiment::Scene;
use crate::fe::hierarchy::CoarseLevels;
use crate::fe::{Constraints, DofMap, SparsityPattern, System};
use crate::linalg::multigrid::VertexHierarchy;
use crate::linalg::{DirectSolver, LinearSolver};
use crate::mesh::{BoundaryFace, Mesh, MeshError};
use crate::results::{
    columns, Cuts, DeformedPicture, ErrorMeasure, FieldPicture, MeshField, Value,
};

use super::clock::PhaseClock;
use super::error::StudyError;

/// Which model each unit of a model-adaptive study uses: the units on the accurate model, 𝕋_a
/// of Algorithms III.1–III.3 — the Signorini faces of the contact tables (the other contact
/// faces use the z-model) or the SubStokes cells of the fluid film (the other cells use
/// Reynolds). Every other unit is on the coarse model (𝕋_c); empty at the start. Through
/// refinement a unit's children inherit its model ([`crate::adaptivity::model::inherit_models`]).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Models {
    accurate: BTreeSet<ModelUnit>,
}

impl Models {
    /// The map with the accurate units `accurate`.
    pub fn of_units(accurate: impl IntoIterator<Item = ModelUnit>) -> Models {
        Models {
            accurate: accurate.into_iter().collect(),
        }
    }

    /// The map with the Signorini faces `faces`.
    pub fn of_faces(faces: impl IntoIterator<Item = BoundaryFace>) -> Models {
        Models::of_units(faces.into_iter().map(ModelUnit::Face))
    }

    /// Whether `unit` uses the accurate model.
    pub fn is_accurate(&self, unit: ModelUnit) -> bool {
        self.accurate.contains(&unit)
    }

    /// Whether the contact face `face` uses the Signorini model.
    pub fn is_accurate_face(&self, face: BoundaryFace) -> bool {
        self.is_accurate(ModelUnit::Face(face))
    }

    /// The accurate units, in their order.
    pub fn accurate(&self) -> &BTreeSet<ModelUnit> {
        &self.accurate
    }

    /// The Signorini faces, in their stable geometric order.
    pub fn accurate_faces(&self) -> impl Iterator<Item = BoundaryFace> + '_ {
        self.accurate.iter().filter_map(ModelUnit::face)
    }

    /// |𝕋_a|.
    pub fn n_accurate(&self) -> usize {
        self.accurate.len()
    }

    /// Put the faces `faces` on the Signorini model (in addition to the accurate units).
    pub fn set_accurate_faces(&mut self, faces: impl IntoIterator<Item = BoundaryFace>) {
        self.accurate.extend(faces.into_iter().map(ModelUnit::Face));
    }
}

/// What changes from cycle to cycle: the mesh, in the model-adaptive families the model of
/// each unit, and in a load-step study the step (the body and the tools).
#[derive(Clone, Debug)]
pub struct Discretisation {
    pub mesh: Mesh,
    /// The model of each contact face or cell ([`Models`]); every unit coarse at the start.
    pub models: Models,
    /// The load step j of a load-step study (0 in every other study): the body is the one
    /// moved by the steps before, the rising tools have risen j times.
    pub load_step: usize,
}

impl Discretisation {
    /// A mesh with every contact face on the z-model.
    pub fn of_mesh(mesh: Mesh) -> Discretisation {
        Discretisation {
            mesh,
            models: Models::default(),
            load_step: 0,
        }
    }

    /// The scene's coarse grid of its domain, refined globally `global_refinements` times and
    /// then `side_refinements` times at the contact sides, or the reason the mesh cannot be
    /// built (a grid too large to number, more refinements than [`crate::mesh::MAX_LEVEL`]).
    pub fn initial(scene: &Scene) -> Result<Discretisation, MeshError> {
        let d = &scene.domain;
        let mesh = Mesh::try_new(d.x, d.y, scene.coarse_cells[0], scene.coarse_cells[1])?;
        Discretisation::refined(scene, mesh)
    }

    /// The scene's refinements of a coarse grid, every face on the z-model.
    fn refined(scene: &Scene, mut mesh: Mesh) -> Result<Discretisation, MeshError> {
        for _ in 0..scene.global_refinements {
            mesh.refine_global()?;
        }
        mesh.refine_at_sides(&scene.refined_sides, scene.side_refinements)?;
        Ok(Discretisation::of_mesh(mesh))
    }

    /// The next load step (§IV.2.4.7): "we add to each vertex of the grid the local
    /// deformation and use this deformed grid for the next step". Every coarse vertex moves
    /// by `motion` (its displacement, [`Mesh::coarse_vertex_keys`] order); the moved,
    /// stress-free body restarts from its coarse cells with the scene's refinements, every
    /// face on the z-model. A coarse cell folded by the motion is an error naming it.
    pub fn next_load_step(
        &self,
        scene: &Scene,
        motion: &[[f64; 2]],
    ) -> Result<Discretisation, StudyError> {
        let keys = self.mesh.coarse_vertex_keys();
        if motion.len() != keys.len() {
            return Err(StudyError::Failed(format!(
                "the body's motion has {} vertices, the coarse grid {}",
                motion.len(),
                keys.len()
            )));
        }
        let moved = keys
            .iter()
            .zip(motion)
            .map(|(&k, d)| {
                let p = self.mesh.point(k);
                [p[0] + d[0], p[1] + d[1]]
            })
            .collect();
        let [nx, ny] = self.mesh.coarse_cells();
        let next = self.load_step + 1;
        let mesh = Mesh::with_coarse_vertices(nx, ny, moved).map_err(|e| {
            StudyError::Mesh(e).context(format!(
                "the body moved by the displacement of load step {} cannot start load step {next}",
                self.load_step
            ))
        })?;
        let mut disc = Discretisation::refined(scene, mesh)?;
        disc.load_step = next;
        Ok(disc)
    }
}

/// The setup of a Q₁ problem with `n_components` per vertex: the system on the current mesh,
/// the problem's constraints (`constrain`), and `solver` made ready for it. The multigrid level
/// hierarchy needs only the mesh and the numbering: its coarse levels are built alongside the
/// numbering of the dofs, its top prolongation alongside the hanging-node constraints and the
/// sparsity pattern (each of these has sequential stretches; on two cores they run side by
/// side).
pub fn setup_system(
    disc: &Discretisation,
    n_components: usize,
    solver: &mut dyn PrepareSolver,
    constrain: impl FnOnce(&mut System),
) -> System {
    let mesh = &disc.mesh;
    let needs_levels = solver.needs_levels();
    let (dofs, coarse_levels) = rayon::join(
        || DofMap::new(mesh, n_components),
        || needs_levels.then(|| CoarseLevels::of(mesh)),
    );
    let ((constraints, pattern), levels) = rayon::join(
        || {
            let constraints = Constraints::new(&dofs);
            let pattern = SparsityPattern::new(&dofs, &constraints);
            (constraints, pattern)
        },
        || coarse_levels.map(|levels| levels.with_finest(mesh, &dofs.vertices)),
    );
    let mut system = System::from_parts(dofs, constraints, pattern);
    constrain(&mut system);
    solver.prepare(&system, levels);
    system
}

/// One solve of `problem` on `disc` outside the cycle loop, as a cycle's (setup, assemble,
/// solve): its dofs and its field ([`Problem::reference_solve`]).
pub fn solve_once<P: Problem + ?Sized>(
    problem: &mut P,
    disc: &Discretisation,
) -> Result<(DofMap, Vec<f64>), StudyError> {
    let mut system = problem.setup(disc);
    problem.assemble(disc, &mut system)?;
    let solution = problem.solve(disc, &mut system, &PhaseClock::default())?;
    Ok((system.dofs, solution.u))
}

/// A solver made ready for the systems of a new mesh: the direct solver gets the fill-reducing
/// ordering of the pattern, multigrid the level hierarchy of the mesh.
pub trait PrepareSolver {
    /// Whether [`PrepareSolver::prepare`] wants the level hierarchy of the mesh.
    fn needs_levels(&self) -> bool {
        false
    }

    /// Get ready for `system`; `levels` is the mesh's hierarchy if the solver asked for it.
    fn prepare(&mut self, system: &System, levels: Option<VertexHierarchy>);
}

impl PrepareSolver for DirectSolver {
    fn prepare(&mut self, system: &System, _levels: Option<VertexHierarchy>) {
        self.reorder(system.ordering());
    }
}

impl PrepareSolver for LinearSolver {
    fn needs_levels(&self) -> bool {
        matches!(self, LinearSolver::Multigrid(_))
    }

    fn prepare(&mut self, system: &System, levels: Option<VertexHierarchy>) {
        match self {
            LinearSolver::Direct(d) => d.prepare(system, levels),
            LinearSolver::Multigrid(m) => m.set_hierarchy(
                levels.expect("the hierarchy multigrid asked for"),
                system.dofs.n_components,
            ),
        }
    }
}

/// The row's column `cg_iterations` (the most CG iterations of a cycle's solves) from the
/// counts of an iterative solver ([`LinearSolver::take_iterations`]; none for the direct one).
pub fn cg_column(iterations: Option<Vec<usize>>) -> Option<(String, i64)> {
    let most = iterations?.into_iter().max().unwrap_or(0);
    Some((columns::CG_ITERATIONS.into(), most as i64))
}

/// A solution of one cycle: the field (hanging dofs distributed) and solver counters.
pub struct Solution {
    pub u: Vec<f64>,
    /// Count columns for the row, e.g. `active_set_iterations`.
    pub counters: Vec<(String, i64)>,
}

impl Solution {
    /// The solution, or an error naming the first dof where it is not finite.
    pub fn finite(self) -> Result<Solution, StudyError> {
        match self.u.iter().position(|v| !v.is_finite()) {
            Some(i) => Err(StudyError::NonFinite(format!(
                "the solution is not finite at dof {i}"
            ))),
            None => Ok(self),
        }
    }
}

/// The a-posteriori estimate of one cycle.
pub struct Estimate {
    /// η_Q² per active cell (in the order of `mesh.active()`): the grid marking's indicators.
    pub cells: Vec<f64>,
    /// The model-error indicators ε^m per unit, where the study marks models: the contact
    /// faces in their stable order, or the cells in the order of `mesh.active()`.
    pub models: ModelIndicators,
    /// The row's columns from the estimate, in order.
    pub columns: Vec<(String, Value)>,
    /// Indicators η_Q² at or below this are rounding noise for the marking (kept in the
    /// printed estimate).
    pub noise_floor: Option<f64>,
    /// The displacement of the coarse vertices ([`Mesh::coarse_vertex_keys`] order), for the
    /// adaptation that moves the body at the end of a load step; `None` where the body stays.
    pub body_motion: Option<Vec<[f64; 2]>>,
}

impl Estimate {
    /// The estimate of the grid-adaptive tables: the indicators and the column `estimate`
    /// = √(Σ_Q η_Q²).
    pub fn of_cells(cells: Vec<f64>) -> Estimate {
        let total = crate::estimators::total(&cells);
        Estimate {
            cells,
            models: ModelIndicators::new(),
            columns: vec![(columns::ESTIMATE.to_string(), Value::real(Some(total)))],
            noise_floor: None,
            body_motion: None,
        }
    }

    /// Append a real column (empty where `value` is not finite).
    pub fn with(self, name: &str, value: f64) -> Estimate {
        self.with_optional(name, Some(value))
    }

    /// Append a real column that may be undefined (`None`, or not finite).
    pub fn with_optional(mut self, name: &str, value: Option<f64>) -> Estimate {
        self.columns.push((name.to_string(), Value::real(value)));
        self
    }

    /// The real value of the column `name`, if the estimate has it and it is defined.
    pub fn value(&self, name: &str) -> Option<f64> {
        self.columns
            .iter()
            .find(|(n, _)| n == name)
            .and_then(|(_, v)| v.as_f64())
    }

    /// √(Σ_Q η_Q²), or an error if it is not finite.
    pub fn finite_total(&self) -> Result<f64, StudyError> {
        let total = crate::estimators::total(&self.cells);
        if total.is_finite() {
            Ok(total)
        } else {
            Err(StudyError::NonFinite(
                "the error estimate is not finite: its residuals overflowed — the data (loads, \
                 tractions, wall velocities, boundary values) or the solution are too large for \
                 double precision"
                    .into(),
            ))
        }
    }
}

/// Figures of the last printed cycle.
#[derive(Default)]
pub struct Pictures {
    pub deformed: Vec<DeformedPicture>,
    pub fields: Vec<FieldPicture>,
    /// A thin-film comparison along a cut (SubStokes against Reynolds on the last mesh).
    pub cuts: Option<Cuts>,
}

/// One model inside the study loop ([`super::run_study`]): each method is one phase of a cycle.
pub trait Problem {
    /// Dofs, constraints and sparsity pattern on the current discretisation.
    fn setup(&mut self, disc: &Discretisation) -> System;

    /// Matrix, load and whatever else the solve needs (contact constraints transferred from the
    /// previous cycle, the cavitation load). An error message names what failed (the loop adds
    /// table and cycle).
    fn assemble(&mut self, disc: &Discretisation, system: &mut System) -> Result<(), StudyError>;

    /// Solve the assembled problem. Work of another phase inside the solve (a re-assembly) is
    /// timed on `clock`.
    fn solve(
        &mut self,
        disc: &Discretisation,
        system: &mut System,
        clock: &PhaseClock,
    ) -> Result<Solution, StudyError>;

    /// Indicators and the row's estimate columns (after the solve only the dofs of the system
    /// are kept). An error message names what could not be evaluated.
    fn estimate(
        &mut self,
        disc: &Discretisation,
        dofs: &DofMap,
        solution: &Solution,
    ) -> Result<Estimate, StudyError>;

    /// After the row is recorded and before the adaptation: keep what the next cycle transfers
    /// (the previous solution).
    fn finish_cycle(&mut self, _disc: &Discretisation, _dofs: DofMap, _solution: Solution) {}

    /// The figures of the last printed cycle.
    fn pictures(
        &mut self,
        _disc: &Discretisation,
        _dofs: &DofMap,
        _solution: &Solution,
        _cycle: usize,
    ) -> Pictures {
        Pictures::default()
    }

    /// The field component of a probe (`s1`, `s2`, `psi`).
    fn component(&self, name: &str) -> Option<usize>;

    /// The row's column `dofs`: the unknowns of the cycle's solves (those of `dofs`, the
    /// system the loop set up, in every problem of one system).
    fn n_dofs(&self, dofs: &DofMap) -> usize {
        dofs.n_dofs()
    }

    /// Whether each printed row is a load step of its own body (the forming of §IV.2.4.7):
    /// then every row gets its figures (the frames of the animation) and no ratio to the row
    /// before, whose body differs.
    fn rows_are_load_steps(&self) -> bool {
        false
    }

    /// Whether [`Solution::u`] is the problem's whole field at the vertices of the mesh: then
    /// the last printed one is probed and written as `data/<table>.vtu`.
    fn vertex_field(&self) -> bool {
        true
    }

    /// Sets of vertices of the last printed solve, as point fields of `data/<table>.vtu`
    /// (1 in the set, 0 elsewhere), e.g. the contact set of a contact problem. The solution
    /// components themselves are written by the recorder.
    fn point_sets(&self, _dofs: &DofMap) -> Vec<MeshField> {
        Vec::new()
    }

    /// The thin film of a fluid problem, whose gap g the VTU files show beside ψ with the mean
    /// pressure p = ψ/g (`None` for the solids).
    fn film(&self) -> Option<&crate::models::thin_film::ThinFilm> {
        None
    }

    /// The engineering quantities of a solve ([`super::quantities`]), appended to its row.
    fn quantities(
        &self,
        _disc: &Discretisation,
        _dofs: &DofMap,
        _solution: &Solution,
    ) -> Vec<(String, f64)> {
        Vec::new()
    }

    /// The elastic body of a solid problem, whose stresses σ(s_h) the VTU files show beside the
    /// displacement (`None` for the fluids).
    fn elasticity(&self) -> Option<&crate::models::elasticity::Elasticity> {
        None
    }

    /// Notes the run adds to its table (e.g. where `cavitation = "auto"` switched).
    fn notes(&self) -> Vec<String> {
        Vec::new()
    }

    /// A thin film: whether the cavitation model was in use at the end of the run (`None` for
    /// the problems without one).
    fn cavitation_ran(&self) -> Option<bool> {
        None
    }

    /// J(u_h) = ½a(u_h, u_h) − l(u_h), the energy of the cycle's solution, for the problems that
    /// minimise J (symmetric, coercive, convex constraints): the true error of each cycle then
    /// follows from the energy identity with J(u) extrapolated ([`super::accuracy`]). `None`
    /// for the problems that are no minimisation (the saddle points).
    fn energy(&self, _disc: &Discretisation, _dofs: &DofMap, _solution: &Solution) -> Option<f64> {
        None
    }

    /// Whether the solve of the run's last cycle was a variational inequality (contact,
    /// cavitation): the energy identity then only bounds the error from above
    /// ([`super::accuracy`]).
    fn constrained(&self) -> bool {
        false
    }

    /// Whether the study keeps every solve ([`KeptSolve`]) for [`Problem::reference_errors`]
    /// after the last cycle.
    fn keeps_solves(&self) -> bool {
        false
    }

    /// ‖a − b‖ of two solves in the norm of the problem's estimator, integrated on `on` (a mesh
    /// at least as fine as both), for the error against the last solve
    /// ([`super::reference::against_last_solve`]). `None` where the problem has no such norm
    /// or a cell of `on` lies in no cell of a field's mesh.
    fn solve_distance(&self, _on: &Mesh, _a: VertexField, _b: VertexField) -> Option<f64> {
        None
    }

    /// The problem solved once more after the run, on `disc` (the reference of
    /// [`super::reference::against_refined_solve`]), as a cycle is solved but without touching
    /// what the run reports (its notes, its comparisons): the field at the vertices with its
    /// dofs. `None`, the default, where the problem has no such reference.
    fn reference_solve(
        &mut self,
        _disc: &Discretisation,
    ) -> Result<Option<(DofMap, Vec<f64>)>, StudyError> {
        Ok(None)
    }

    /// The true error of each of `kept` (in its order, not empty: the problem keeps its solves,
    /// [`Problem::keeps_solves`]), in the norm of the problem's estimator
    /// ([`Problem::solve_distance`]), for the problems without an energy ([`Problem::energy`])
    /// or whose energy gives none: by default against a reference solve on the last mesh
    /// refined once ([`super::reference::against_refined_solve`]), and where the problem has no
    /// [`Problem::reference_solve`] against the run's own last solve
    /// ([`super::reference::against_last_solve`]). `Ok(Err(why))` where it cannot be measured,
    /// with the reason for the table's note.
    fn reference_errors(
        &mut self,
        kept: &[KeptSolve],
    ) -> Result<Result<ReferenceErrors, String>, StudyError> {
        match super::reference::against_refined_solve(self, kept)? {
            Ok(errors) => Ok(Ok(errors)),
            Err(_) => Ok(super::reference::against_last_solve(kept, |on, a, b| {
                self.solve_distance(on, a, b)
            })?),
        }
    }
}

/// The errors of kept solves against a reference solution ([`Problem::reference_errors`]).
pub struct ReferenceErrors {
    /// One per kept solve, in its order.
    pub errors: Vec<f64>,
    /// How they were measured (the page's sentence).
    pub measure: ErrorMeasure,
}

/// One solve kept for a reference error ([`Problem::reference_errors`]): its printed cycle, its
/// estimate, its discretisation, its dofs and its field.
pub struct KeptSolve {
    pub cycle: usize,
    pub estimate: Option<f64>,
    pub disc: Discretisation,
    pub dofs: DofMap,
    pub u: Vec<f64>,
}
