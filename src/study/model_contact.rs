//! Tables IV.18–IV.29: model-adaptive contact on a fixed mesh (§IV.2.3). Every contact face
//! f ⊂ Γ_C uses the z-model (I.20) or the Signorini model (I.21); the partition
//! ([`Discretisation::accurate_faces`]) is what the model marking
//! ([`super::adapt::ModelMarking`], Algorithms III.2/III.3) changes between cycles.
//!
//! **Per cycle** — the two `calculate` lines of Algorithms III.2/III.3:
//! 1. the z-solve on all faces (u ← u_c on Ω), its active set warm-started from the last
//!    z-solve (on the fixed mesh the z-problem is the same every cycle; cold, Table IV.24's
//!    scene needs 44 of the 50 iterations allowed);
//! 2. the mixed solve (u ← u_a on 𝕋_a): the Signorini faces linearised once about this
//!    z-solution (the "coarse solution as initial guess" of §III.1), the active set started
//!    from the z-solution's contact set. A vertex between a z-face and a Signorini face takes
//!    the Signorini constraint. Without Signorini faces the z-solution is the solution.
//!
//! **Indicator.** ε^m(f) = ‖ε_P(s_h)‖_{L2(f)} of (III.16) for the mixed solution s_h on every
//! face ([`crate::estimators::contact_model`], spec/estimators.md §3.4), the printed
//! `model_error` = (Σ_{f∈𝕋_c} ε^m(f)²)^{1/2} over the z-faces.

use std::collections::BTreeSet;

use super::adapt::face_partition;
use super::clock::PhaseClock;
use super::elasticity::displacement_component;
use super::problem::{setup_system, Discretisation, Estimate, Problem, Solution};
use crate::adaptivity::model::model_error;
use crate::estimators::contact_model::{face_indicators, vertex_differences};
use crate::estimators::FaceIndicators;
use crate::experiment::{ContactData, ElasticityData, ModelErrorSolution};
use crate::fe::{DofMap, System};
use crate::linalg::DirectSolver;
use crate::mesh::BoundaryFace;
use crate::models::contact::{
    contact_boundaries, contact_set, penetration, side_faces, solve_contact, ConstraintBuilder,
    ContactBoundary, ContactConstraint, ContactModel, ContactSolution,
};
use crate::models::elasticity::Elasticity;
use crate::results::{columns, Value};

use super::contact::{CycleState, PENETRATION_SAMPLES};

/// The constraints and solution of a cycle's mixed solve (none without Signorini faces).
type MixedSolve = Option<(Vec<ContactConstraint>, ContactSolution)>;

/// The model-adaptive contact problem of one experiment.
pub struct ModelAdaptiveContact {
    model: Elasticity,
    boundaries: Vec<ContactBoundary>,
    solver: DirectSolver,
    /// Constraints of the z-solve of the current cycle (all faces z).
    z_constraints: Vec<ContactConstraint>,
    /// Active set of the last z-solve: the warm start of the next one.
    z_active: Option<Vec<bool>>,
    /// The Signorini faces of the current cycle.
    accurate: BTreeSet<BoundaryFace>,
    /// The partitions of the earlier cycles, for the column `partition_repeat`.
    history: Vec<BTreeSet<BoundaryFace>>,
    /// Which solution the model error is evaluated at.
    error_solution: ModelErrorSolution,
    /// The z-solution of the current cycle (kept when the model error is evaluated at it).
    z_solution: Option<Vec<f64>>,
    /// Constraints and active-set solution of the current cycle's mixed solve (after `solve`).
    pub state: Option<CycleState>,
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
        }
    }

    /// The model-error indicators ε^m(f) of every contact face for the displacement `u`, in
    /// the stable geometric order of the faces.
    pub fn face_errors(&self, dofs: &DofMap, u: &[f64]) -> Result<FaceIndicators, String> {
        let v = &dofs.vertices;
        let mut faces = FaceIndicators::new();
        for cb in &self.boundaries {
            let verts = v.side_vertices(cb.side);
            let points: Vec<[f64; 2]> = verts.iter().map(|&i| v.coords[i as usize]).collect();
            let displacement: Vec<[f64; 2]> = verts
                .iter()
                .map(|&i| [u[dofs.dof(i, 0)], u[dofs.dof(i, 1)]])
                .collect();
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
    fn solve_models(&mut self, system: &System) -> Result<(ContactSolution, MixedSolve), String> {
        let z = solve_contact(
            system,
            &mut self.solver,
            &self.z_constraints,
            self.z_active.as_deref(),
        )
        .map_err(|e| format!("z-solve on all faces: {e}"))?;
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

    fn assemble(&mut self, disc: &Discretisation, system: &mut System) -> Result<(), String> {
        self.model.assemble(&disc.mesh, system);
        let all_z = ConstraintBuilder {
            boundaries: &self.boundaries,
            face_model: &|_| ContactModel::Z,
        };
        self.z_constraints = all_z.build(&system.dofs, &system.constraints, None)?;
        if self
            .z_active
            .as_ref()
            .is_some_and(|a| a.len() != self.z_constraints.len())
        {
            self.z_active = None;
        }
        self.accurate = disc.accurate_faces.clone();
        Ok(())
    }

    fn solve(
        &mut self,
        _disc: &Discretisation,
        system: &mut System,
        _clock: &PhaseClock,
    ) -> Result<Solution, String> {
        let solved = self.solve_models(system);
        self.solver.release_pattern();
        let (z, mixed) = solved?;
        let z_iterations = z.iterations;
        let mixed_iterations = mixed.as_ref().map_or(0, |(_, m)| m.iterations);
        self.z_active = Some(z.active.clone());
        self.z_solution = (self.error_solution == ModelErrorSolution::Z).then(|| z.u.clone());
        let (constraints, solution) =
            mixed.unwrap_or_else(|| (std::mem::take(&mut self.z_constraints), z));
        let counters = vec![
            ("z_iterations".to_string(), z_iterations as i64),
            ("mixed_iterations".to_string(), mixed_iterations as i64),
            (
                columns::CONTACT_VERTICES.to_string(),
                solution.active.iter().filter(|&&a| a).count() as i64,
            ),
        ];
        let u = solution.u.clone();
        self.state = Some(CycleState {
            constraints,
            solution,
        });
        Ok(Solution { u, counters })
    }

    fn estimate(
        &mut self,
        _disc: &Discretisation,
        dofs: &DofMap,
        solution: &Solution,
    ) -> Result<Estimate, String> {
        let u = &solution.u;
        // The z-solution is kept only when the model error is evaluated at it.
        let faces = self.face_errors(dofs, self.z_solution.as_deref().unwrap_or(u))?;
        let partition = face_partition(&faces, &self.accurate);
        let eps: Vec<f64> = faces.iter().map(|&(_, e)| e).collect();
        let count = |name: &str, n: usize| (name.to_string(), Value::Count(n as i64));
        let columns = vec![
            count(columns::COARSE_FACES, partition.n_coarse()),
            count(columns::ACCURATE_FACES, partition.n_accurate()),
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
        Ok(Estimate {
            cells: Vec::new(),
            faces,
            columns,
            noise_floor: None,
        })
    }

    fn finish_cycle(&mut self, _disc: &Discretisation, _dofs: DofMap, _solution: Solution) {
        self.history.push(std::mem::take(&mut self.accurate));
    }

    fn component(&self, name: &str) -> Option<usize> {
        displacement_component(name)
    }
}
