//! Tables IV.18–IV.29: model-adaptive contact on a fixed mesh (§IV.2.3). Every contact face
//! f ⊂ Γ_C uses the z-model (I.20) or the Signorini model (I.21); the partition
//! ([`Discretisation::models`]) is what the model marking
//! ([`super::adapt::ModelMarking`], Algorithms III.2/III.3) changes between cycles.
//!
//! **Per cycle** — the two `calculate` lines of Algorithms III.2/III.3:
//! 1. the z-solve on all faces (u ← u_c on Ω), its active set warm-started from the contact
//!    set of the last z-solution (on the fixed mesh the z-problem is the same every cycle;
//!    cold, Table IV.24's scene needs 44 of the 50 iterations allowed);
//! 2. the mixed solve (u ← u_a on 𝕋_a): the Signorini faces linearised once about this
//!    z-solution (the "coarse solution as initial guess" of §III.1), the active set started
//!    from the z-solution's contact set. A vertex between a z-face and a Signorini face takes
//!    the Signorini constraint. Without Signorini faces the z-solution is the solution.
//!
//! With `signorini = "converged"` the mixed solve is iterated to the fixed point of its
//! linearisation ([`super::signorini`]) and that is the cycle's mixed solution; with the default
//! the fixed point is computed beside it for the `signorini_*` columns of the table (not in the
//! cost study nor the load steps).
//!
//! **Indicator.** ε^m(f) = ‖ε_P(s_h)‖_{L2(f)} of (III.16) for the mixed solution s_h on every
//! face ([`crate::estimators::contact_model`], docs/estimators.md §3.4), the printed
//! `model_error` = (Σ_{f∈𝕋_c} ε^m(f)²)^{1/2} over the z-faces.
//!
//! **Model and grid (Tables IV.30–IV.35, Algorithm III.25).** The same two solves per cycle on
//! a mesh that adapts too ([`super::adapt::Balanced`]): the last z-solution is transferred to
//! the new mesh for the warm start, and the estimate adds
//! the discretisation indicators η_Q² of Theorem III.15 with the term set of the thesis's MGA
//! code ([`ContactEstimator::MgaCode`]) for the mixed solution, printed as √Σ over three cell
//! groups: cells with a z-face, cells with a Signorini face, cells without a contact face.
//!
//! **Load steps (the U-O forming of §IV.2.4.7, Fig. IV.54).** The same cycles on the body of
//! each step ([`super::adapt::LoadSteps`] moves it between the steps), the tools of step j
//! raised by j times the lift ([`ContactData::raised`]). Each step starts with every face z and
//! keeps nothing of the previous body's solution but which material points were in contact
//! (the warm start of its first z-solve; integer vertex positions name the same material
//! points in every step). The estimate adds the displacement of the coarse vertices (the
//! motion of the body) and the tip (the material point at the lower right corner of the
//! undeformed strip, (16, 0)) after the step's motion.

use std::collections::BTreeSet;

use super::adapt::{boundary_faces, face_partition};
use super::clock::PhaseClock;
use super::elasticity::displacement_component;
use super::error::StudyError;
use super::problem::{
    setup_system, solve_once, Discretisation, Estimate, Pictures, Problem, Solution,
};
use super::quantities;
use super::reference::{self, VertexField};
use super::signorini::{converge, Comparison, ComparisonFailures, FixedPoint};
use super::transfer::PreviousSolution;
use crate::adaptivity::model::{model_error, ModelUnit};
use crate::estimators::contact::{self as contact_estimator, ContactEstimator};
use crate::estimators::contact_model::{face_indicators, vertex_differences};
use crate::estimators::FaceIndicators;
use crate::experiment::{ContactData, ElasticityData, ModelErrorSolution, SignoriniReading};
use crate::fe::{DofMap, System};
use crate::linalg::DirectSolver;
use crate::mesh::{BoundaryFace, Mesh, VertexKey};
use crate::models::contact::{
    contact_boundaries, contact_set, penetration, side_faces, solve_contact, ConstraintBuilder,
    ContactBoundary, ContactConstraint, ContactModel, ContactSolution,
};
use crate::models::elasticity::Elasticity;
use crate::results::{columns, MeshField, Value};

use super::contact::{contact_picture, contact_set_fields, CycleState, PENETRATION_SAMPLES};

/// η_Q² per cell and the estimate's columns of a model-and-grid cycle.
type GridEstimate = (Vec<f64>, Vec<(String, Value)>);

/// The constraints and solution of a cycle's mixed solve (none without Signorini faces).
type MixedSolve = Option<(Vec<ContactConstraint>, ContactSolution)>;

/// The model-adaptive contact problem of one experiment.
pub struct ModelAdaptiveContact {
    model: Elasticity,
    boundaries: Vec<ContactBoundary>,
    solver: DirectSolver,
    /// Constraints of the z-solve of the current cycle (all faces z).
    z_constraints: Vec<ContactConstraint>,
    /// The warm start of the current cycle's z-solve (after `assemble`).
    z_active: Option<Vec<bool>>,
    /// The Signorini faces of the current cycle.
    accurate: BTreeSet<BoundaryFace>,
    /// The partitions of the earlier cycles, for the column `partition_repeat`.
    history: Vec<BTreeSet<BoundaryFace>>,
    /// Which solution the model error is evaluated at.
    error_solution: ModelErrorSolution,
    /// The z-solution of the current cycle (after `solve`).
    z_solution: Option<Vec<f64>>,
    /// Constraints and active-set solution of the current cycle's mixed solve (after `solve`).
    pub state: Option<CycleState>,
    /// Whether the mesh adapts too (Algorithm III.25).
    adapts_grid: bool,
    /// The last z-solution on its mesh: the warm start of the next z-solve.
    previous_z: Option<PreviousSolution>,
    /// The load steps of a forming study.
    forming: Option<Forming>,
    /// Which mixed solution the table uses, and whether the fixed point is computed beside
    /// the linearised one for the comparison (the tables, not the cost study).
    reading: SignoriniReading,
    pub compares: bool,
    /// The current cycle's linearised mixed solution against the converged one.
    comparison: Option<Comparison>,
    /// Where the fixed point of the comparison failed with the linearised reading.
    pub failures: ComparisonFailures,
}

/// The tools of a forming study and the step the problem is at.
struct Forming {
    /// The tools of step 0, as the file gives them.
    tools: ContactData,
    /// How far the rising tools rise per step.
    lift: f64,
    step: usize,
    /// The vertices (integer positions: the same material points in every step's body) in
    /// contact in the last z-solve: the warm start of the next step's first z-solve.
    z_contact: BTreeSet<VertexKey>,
}

impl ModelAdaptiveContact {
    pub fn new(elasticity: &ElasticityData, contact: &ContactData) -> ModelAdaptiveContact {
        ModelAdaptiveContact {
            model: elasticity.into(),
            boundaries: contact_boundaries(contact),
            solver: DirectSolver::cholesky(),
            z_constraints: Vec::new(),
            z_active: None,
            accurate: BTreeSet::new(),
            history: Vec::new(),
            error_solution: contact.model_error_solution,
            z_solution: None,
            state: None,
            adapts_grid: false,
            previous_z: None,
            forming: None,
            reading: contact.signorini_reading(),
            compares: false,
            comparison: None,
            failures: ComparisonFailures::default(),
        }
    }

    /// The problem of a load-step study (the U-O forming, §IV.2.4.7): model and grid
    /// adaptivity on each step's body, the rising tools raised by `lift` per step.
    pub fn forming(
        elasticity: &ElasticityData,
        contact: &ContactData,
        lift: f64,
    ) -> ModelAdaptiveContact {
        ModelAdaptiveContact {
            forming: Some(Forming {
                tools: contact.clone(),
                lift,
                step: 0,
                z_contact: BTreeSet::new(),
            }),
            ..ModelAdaptiveContact::with_grid(elasticity, contact)
        }
    }

    /// Start load step `step` if the problem is not at it: the tools of the step, and nothing
    /// kept from the previous body but which material points were in contact (no transfer of
    /// the displacement, no partition history).
    fn start_load_step(&mut self, step: usize) {
        let Some(forming) = &mut self.forming else {
            return;
        };
        if forming.step == step {
            return;
        }
        forming.step = step;
        self.boundaries = contact_boundaries(&forming.tools.raised(step as f64 * forming.lift));
        self.previous_z = None;
        self.history.clear();
    }

    /// The displacement of the body's coarse vertices and the columns `tip_x`, `tip_y`: the
    /// position of the material point at the lower right corner of the undeformed body (the
    /// coarse vertex (n_x, 0)) moved by its displacement.
    fn body_motion(mesh: &Mesh, dofs: &DofMap, u: &[f64]) -> (Vec<[f64; 2]>, [f64; 2]) {
        let keys = mesh.coarse_vertex_keys();
        let motion: Vec<[f64; 2]> = keys
            .iter()
            .map(|&k| {
                let v = dofs
                    .vertices
                    .find(k)
                    .expect("a coarse vertex is a vertex of every refinement");
                dofs.vector(u, v)
            })
            .collect();
        let corner = mesh.coarse_cells()[0];
        let p = mesh.point(keys[corner]);
        let d = motion[corner];
        (motion, [p[0] + d[0], p[1] + d[1]])
    }

    /// The problem of a model-and-grid-adaptive study (Algorithm III.25).
    pub fn with_grid(elasticity: &ElasticityData, contact: &ContactData) -> ModelAdaptiveContact {
        ModelAdaptiveContact {
            adapts_grid: true,
            ..ModelAdaptiveContact::new(elasticity, contact)
        }
    }

    /// The columns of the discretisation estimate (model-and-grid-adaptive): η_Q² of the
    /// MGA-code term set per cell and √Σ over the cells with a z-face, with a Signorini face,
    /// without a contact face, and over all cells (`estimate`).
    fn grid_estimate(
        &self,
        mesh: &Mesh,
        dofs: &DofMap,
        u: &[f64],
    ) -> Result<GridEstimate, StudyError> {
        let state = self
            .state
            .as_ref()
            .ok_or("the discretisation estimate needs the cycle's mixed solve")?;
        let eta2 = contact_estimator::indicators(
            mesh,
            dofs,
            u,
            &self.model,
            &self.boundaries,
            &state.constraints,
            &state.solution.active,
            ContactEstimator::MgaCode,
        )
        .eta2;
        // [z-face cells, Signorini-face cells, interior cells]; a cell with faces of both
        // models (a one-cell-thick body) counts as Signorini.
        let mut groups = [0.0; 3];
        for (&c, &e) in mesh.active().iter().zip(&eta2) {
            let contact_faces = mesh
                .boundary_faces_of(c)
                .filter(|f| self.boundaries.iter().any(|b| b.side == f.side));
            let mut group = 2;
            for f in contact_faces {
                if self.accurate.contains(&f) {
                    group = 1;
                } else if group == 2 {
                    group = 0;
                }
            }
            groups[group] += e;
        }
        let real = |name: &str, v: f64| (name.to_string(), Value::real(Some(v.sqrt())));
        let columns = vec![
            real(columns::EST_Z_BOUNDARY, groups[0]),
            real(columns::EST_S_BOUNDARY, groups[1]),
            real(columns::EST_INTERIOR, groups[2]),
            real(columns::ESTIMATE, groups.iter().sum()),
        ];
        Ok((eta2, columns))
    }

    /// The model-error indicators ε^m(f) of every contact face for the displacement `u`, in
    /// the stable geometric order of the faces.
    pub fn face_errors(&self, dofs: &DofMap, u: &[f64]) -> Result<FaceIndicators, StudyError> {
        let v = &dofs.vertices;
        let mut faces = FaceIndicators::new();
        for cb in &self.boundaries {
            let verts = v.side_vertices(cb.side);
            let points: Vec<[f64; 2]> = verts.iter().map(|&i| v.coords[i as usize]).collect();
            let displacement: Vec<[f64; 2]> = verts.iter().map(|&i| dofs.vector(u, i)).collect();
            let differences = vertex_differences(&cb.obstacle, &points, &displacement)?;
            let eps = face_indicators(&points, &differences);
            faces.extend(side_faces(dofs, cb.side, &verts).into_iter().zip(eps));
        }
        faces.sort_by_key(|(f, _)| *f);
        Ok(faces)
    }

    /// The cycle's two solves: the z-solve on all faces, warm-started from the last one, and,
    /// when there are Signorini faces, the mixed solve linearised about the z-solution with its
    /// constraints.
    fn solve_models(
        &mut self,
        mesh: &Mesh,
        system: &System,
    ) -> Result<(ContactSolution, MixedSolve), StudyError> {
        let z = solve_contact(
            system,
            &mut self.solver,
            &self.z_constraints,
            self.z_active.as_deref(),
        )
        .map_err(|e| StudyError::from(e).context("z-solve on all faces"))?;
        if self.accurate.is_empty() {
            return Ok((z, None));
        }
        let accurate = &self.accurate;
        let face_model = |f: BoundaryFace| {
            if accurate.contains(&f) {
                ContactModel::Signorini
            } else {
                ContactModel::Z
            }
        };
        let builder = ConstraintBuilder {
            boundaries: &self.boundaries,
            face_model: &face_model,
        };
        let mixed = builder
            .build(&system.dofs, &system.constraints, Some(&z.u))
            .and_then(|constraints| {
                let initial = contact_set(&constraints, &system.dofs, &z.u);
                let solution =
                    solve_contact(system, &mut self.solver, &constraints, Some(&initial))?;
                Ok((constraints, solution))
            })
            .map_err(|e| {
                format!(
                    "mixed solve ({} Signorini faces linearised about the z-solution): {e}",
                    accurate.len()
                )
            })?;
        self.comparison = None;
        let converged = self.reading == SignoriniReading::Converged;
        if !converged && (!self.compares || self.forming.is_some()) {
            return Ok((z, Some(mixed)));
        }
        let fixed_point = converge(
            system,
            &mut self.solver,
            &builder,
            &mixed.0,
            &mixed.1,
            &FixedPoint::default(),
        )
        .map_err(|e| e.context(format!("mixed solve ({} Signorini faces)", accurate.len())));
        let Some(fixed) = self.failures.settle(self.reading, fixed_point)? else {
            return Ok((z, Some(mixed)));
        };
        self.comparison = Some(Comparison::of(
            &self.model,
            mesh,
            &system.dofs,
            &self.boundaries,
            (&mixed.0, &mixed.1.u),
            &fixed,
        ));
        if converged {
            return Ok((z, Some(fixed.as_cycle_solve(mixed.1.iterations))));
        }
        Ok((z, Some(mixed)))
    }

    /// How many cycles back the current partition was used before (the smallest such
    /// number), 0 if it is new: 1 for a partition that stays, 2 for Algorithm III.3 flipping
    /// between two partitions.
    fn partition_repeat(&self) -> usize {
        self.history
            .iter()
            .rev()
            .position(|p| *p == self.accurate)
            .map_or(0, |k| k + 1)
    }
}

impl Problem for ModelAdaptiveContact {
    fn setup(&mut self, disc: &Discretisation) -> System {
        setup_system(disc, 2, &mut self.solver, |s| self.model.constrain(s))
    }

    fn assemble(&mut self, disc: &Discretisation, system: &mut System) -> Result<(), StudyError> {
        self.start_load_step(disc.load_step);
        self.model.assemble(&disc.mesh, system);
        let all_z = ConstraintBuilder {
            boundaries: &self.boundaries,
            face_model: &|_| ContactModel::Z,
        };
        self.z_constraints = all_z.build(&system.dofs, &system.constraints, None)?;
        // The warm start: the contact set of the last z-solution on this mesh (the same mesh
        // on a fixed grid, the transferred solution when the grid adapts). The first z-solve
        // of a load step starts from the material points in contact at the end of the step
        // before (cold, the 64×2 body of the forming needs 40–64 iterations in every step).
        self.z_active = match (&self.previous_z, &self.forming) {
            (Some(previous), _) => {
                let z = previous.at_contact_vertices(&self.boundaries, &system.dofs)?;
                Some(contact_set(&self.z_constraints, &system.dofs, &z))
            }
            (None, Some(forming)) if !forming.z_contact.is_empty() => {
                let keys = &system.dofs.vertices.keys;
                Some(
                    self.z_constraints
                        .iter()
                        .map(|c| forming.z_contact.contains(&keys[c.vertex as usize]))
                        .collect(),
                )
            }
            _ => None,
        };
        self.accurate = disc.models.accurate_faces().collect();
        Ok(())
    }

    fn solve(
        &mut self,
        disc: &Discretisation,
        system: &mut System,
        _clock: &PhaseClock,
    ) -> Result<Solution, StudyError> {
        self.failures.start_solve();
        let solved = self.solve_models(&disc.mesh, system);
        self.solver.release_pattern();
        let (z, mixed) = solved?;
        if let Some(forming) = &mut self.forming {
            let keys = &system.dofs.vertices.keys;
            forming.z_contact = self
                .z_constraints
                .iter()
                .zip(&z.active)
                .filter(|(_, &active)| active)
                .map(|(c, _)| keys[c.vertex as usize])
                .collect();
        }
        let z_iterations = z.iterations;
        let mixed_iterations = mixed.as_ref().map_or(0, |(_, m)| m.iterations);
        self.z_solution = Some(z.u.clone());
        let (constraints, solution) =
            mixed.unwrap_or_else(|| (std::mem::take(&mut self.z_constraints), z));
        Ok(CycleState::keep(
            &mut self.state,
            constraints,
            solution,
            vec![
                ("z_iterations".to_string(), z_iterations as i64),
                ("mixed_iterations".to_string(), mixed_iterations as i64),
            ],
        ))
    }

    fn estimate(
        &mut self,
        disc: &Discretisation,
        dofs: &DofMap,
        solution: &Solution,
    ) -> Result<Estimate, StudyError> {
        let u = &solution.u;
        let at = match (self.error_solution, &self.z_solution) {
            (ModelErrorSolution::Z, Some(z)) => z,
            _ => u,
        };
        let faces = self.face_errors(dofs, at)?;
        let partition = face_partition(&faces, &self.accurate);
        let eps: Vec<f64> = faces.iter().map(|&(_, e)| e).collect();
        let count = |name: &str, n: usize| (name.to_string(), Value::Count(n as i64));
        let (coarse, accurate) = if self.adapts_grid {
            (columns::Z_FACES, columns::S_FACES)
        } else {
            (columns::COARSE_FACES, columns::ACCURATE_FACES)
        };
        let mut columns = vec![
            count(coarse, partition.n_coarse()),
            count(accurate, partition.n_accurate()),
            (
                columns::MODEL_ERROR.to_string(),
                Value::real(Some(model_error(&partition, &eps))),
            ),
            (
                columns::PENETRATION.to_string(),
                Value::real(Some(penetration(
                    &self.boundaries,
                    dofs,
                    u,
                    PENETRATION_SAMPLES,
                ))),
            ),
            count(columns::PARTITION_REPEAT, self.partition_repeat()),
        ];
        let mut cells = Vec::new();
        if self.adapts_grid {
            let (eta2, grid) = self.grid_estimate(&disc.mesh, dofs, u)?;
            cells = eta2;
            // After model_error, before penetration: the order of Tables IV.30–IV.35.
            let tail = columns.split_off(3);
            columns.extend(grid);
            columns.extend(tail);
        }
        let mut body_motion = None;
        if self.forming.is_some() {
            let (motion, tip) = Self::body_motion(&disc.mesh, dofs, u);
            body_motion = Some(motion);
            columns.push((columns::TIP_X.to_string(), Value::real(Some(tip[0]))));
            columns.push((columns::TIP_Y.to_string(), Value::real(Some(tip[1]))));
        }
        if let Some(comparison) = self.comparison.take() {
            columns.extend(comparison.columns());
        }
        Ok(Estimate {
            cells,
            models: faces
                .iter()
                .map(|&(f, e)| (ModelUnit::Face(f), e))
                .collect(),
            columns,
            noise_floor: None,
            body_motion,
        })
    }

    fn finish_cycle(&mut self, disc: &Discretisation, dofs: DofMap, _solution: Solution) {
        self.history.push(std::mem::take(&mut self.accurate));
        if let Some(u) = self.z_solution.take() {
            self.previous_z = Some(PreviousSolution::of(disc, dofs, u));
        }
    }

    /// The deformed body of the last printed cycle with the mixed solution and its Signorini
    /// faces (thesis Figs IV.35–IV.51 show the partitions; the deformed body is tribo's
    /// addition); in a load-step study the body after every step (the frames of Fig. IV.54).
    fn pictures(
        &mut self,
        disc: &Discretisation,
        dofs: &DofMap,
        _solution: &Solution,
        cycle: usize,
    ) -> Pictures {
        let Some(state) = &self.state else {
            return Pictures::default();
        };
        let faces = boundary_faces(
            &disc.mesh,
            &self.boundaries.iter().map(|b| b.side).collect(),
        );
        let mut label = format!(
            "mixed contact, {} of {} faces Signorini (thick)",
            disc.models.accurate_faces().count(),
            faces.len()
        );
        if self.forming.is_some() {
            label = format!("load step {}, {label}", disc.load_step);
        }
        let mut picture = contact_picture(&self.boundaries, &disc.mesh, dofs, state, cycle, &label);
        let u = &state.solution.u;
        picture.accurate_faces = disc
            .models
            .accurate_faces()
            .map(|f| {
                disc.mesh.face_vertex_keys(f).map(|k| {
                    let v = dofs
                        .vertices
                        .find(k)
                        .expect("the ends of a face are vertices");
                    dofs.displaced(u, v, 1.0)
                })
            })
            .collect();
        Pictures {
            deformed: vec![picture],
            fields: Vec::new(),
            ..Pictures::default()
        }
    }

    fn component(&self, name: &str) -> Option<usize> {
        displacement_component(name)
    }

    fn elasticity(&self) -> Option<&Elasticity> {
        Some(&self.model)
    }

    fn quantities(
        &self,
        _disc: &Discretisation,
        dofs: &DofMap,
        _solution: &Solution,
    ) -> Vec<(String, f64)> {
        quantities::contact(self.state.as_ref(), &self.boundaries, dofs)
    }

    fn notes(&self) -> Vec<String> {
        self.failures.notes()
    }

    /// The model-and-grid-adaptive tables (IV.30–IV.35) keep their solves for the true error
    /// against a reference solve on the last mesh refined once with the mixed model of the
    /// last cycle (the default [`Problem::reference_errors`]); the fixed-mesh model-adaptive
    /// tables and the load steps measure none.
    fn keeps_solves(&self) -> bool {
        self.adapts_grid && self.forming.is_none()
    }

    /// The energy norm of elasticity (III.35), the norm of Theorems III.12 and III.15.
    fn solve_distance(&self, on: &Mesh, a: VertexField, b: VertexField) -> Option<f64> {
        reference::energy_distance(on, a, b, &self.model)
    }

    /// The mixed solve of a cycle on `disc`: the z-solve warm-started from the last
    /// z-solution, then the mixed solve linearised about the new z-solution (or its fixed
    /// point with `signorini = "converged"`), without the comparison columns; the problem's
    /// state stays that of the run's last cycle.
    fn reference_solve(
        &mut self,
        disc: &Discretisation,
    ) -> Result<Option<(DofMap, Vec<f64>)>, StudyError> {
        let kept = (
            self.state.take(),
            self.z_solution.take(),
            self.failures.clone(),
            std::mem::replace(&mut self.compares, false),
        );
        let solved = solve_once(self, disc);
        (self.state, self.z_solution, self.failures, self.compares) = kept;
        solved.map(Some)
    }

    fn rows_are_load_steps(&self) -> bool {
        self.forming.is_some()
    }

    fn point_sets(&self, dofs: &DofMap) -> Vec<MeshField> {
        contact_set_fields(&self.state, &self.boundaries, dofs)
    }
}
