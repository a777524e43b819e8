//! Tables IV.6–IV.17: z-contact (§IV.2.1) and Signorini contact (§IV.2.2) as variational
//! inequalities, grid-adaptive with the estimator of Theorem III.15.
//!
//! Per cycle: assemble the elasticity system, build the nodal constraints at the contact vertices
//! (z: fixed direction; Signorini: linearised about s₀ = the previous cycle's solution
//! transferred to the new mesh, s₀ = 0 in cycle 0, one linearised solve per cycle), solve by the
//! primal–dual active set method, estimate.

use std::time::Instant;

use super::{AdaptiveModel, Estimate, Progress, RunError, Solution, Tier};
use crate::estimators::contact::{self as contact_estimator, ContactEstimate};
use crate::experiment::{ContactEstimator, ContactModel, ExperimentSpec, Side};
use crate::fe::{DofMap, SparseSystem};
use crate::mesh::Mesh;
use crate::models::contact::{
    contact_boundaries, penetration, solve_pdas, Constraint, ConstraintBuilder, ContactBoundary,
    ContactSolution,
};
use crate::models::elasticity::Elasticity;
use crate::results::{DeformedPicture, PhaseSeconds, RunResult};

/// Boundary points per face at which the true penetration is sampled.
pub const PENETRATION_SAMPLES: usize = 8;

/// Contact model of a boundary face [x₀, x₁] of a side.
pub type FaceModels = Box<dyn Fn(Side, f64, f64) -> ContactModel + Send + Sync>;

/// Run a contact table.
pub fn run(spec: &ExperimentSpec, tier: Tier, progress: Progress) -> Result<RunResult, RunError> {
    super::run_grid_adaptive(spec, tier, progress, &mut ContactStudy::new(spec))
}

/// The constraints and the active-set solution of the current cycle.
#[derive(Clone, Debug)]
pub struct CycleState {
    pub constraints: Vec<Constraint>,
    pub solution: ContactSolution,
}

/// The contact model of one experiment inside the grid-adaptive loop.
pub struct ContactStudy {
    pub problem: Elasticity,
    pub boundaries: Vec<ContactBoundary>,
    /// Contact model per boundary face (uniform for the pure runs of §IV.2.1/§IV.2.2).
    pub face_models: FaceModels,
    /// Whether any face may use the Signorini model (then s₀ is kept between cycles).
    pub uses_signorini: bool,
    pub estimator: ContactEstimator,
    /// Mesh, dofs and solution of the previous cycle (the linearisation point s₀ of the
    /// Signorini constraints and the warm start of the active set).
    previous: Option<(Mesh, DofMap, Vec<f64>)>,
    /// State of the current cycle (after `solve`).
    pub state: Option<CycleState>,
    /// Contact parts of the previous cycle (Σ hη_C², Σ h⁻¹η_{−C}²), for the ratio columns.
    previous_parts: Option<(f64, f64)>,
}

impl ContactStudy {
    pub fn new(spec: &ExperimentSpec) -> ContactStudy {
        let elasticity = spec
            .scene
            .elasticity
            .as_ref()
            .expect("validated: elasticity data");
        let data = spec
            .scene
            .contact
            .as_ref()
            .expect("validated: contact data");
        let model = data.model;
        ContactStudy {
            problem: Elasticity::from_data(elasticity),
            boundaries: contact_boundaries(data),
            face_models: Box::new(move |_, _, _| model),
            uses_signorini: model == ContactModel::Signorini,
            estimator: data.estimator,
            previous: None,
            state: None,
            previous_parts: None,
        }
    }

    /// The same scene with another (uniform) contact model, e.g. the z-solution for comparison.
    pub fn with_model(&self, model: ContactModel) -> ContactStudy {
        ContactStudy {
            problem: self.problem.clone(),
            boundaries: self.boundaries.clone(),
            face_models: Box::new(move |_, _, _| model),
            uses_signorini: model == ContactModel::Signorini,
            estimator: self.estimator,
            previous: None,
            state: None,
            previous_parts: None,
        }
    }

    /// Set the linearisation point s₀ of the next Signorini solve explicitly.
    pub fn set_linearisation(&mut self, mesh: &Mesh, dofs: &DofMap, u: &[f64]) {
        self.previous = Some((mesh.clone(), dofs.clone(), u.to_vec()));
    }

    /// Mesh, dofs and solution of the last solved cycle (after `after_cycle`).
    pub fn last_solution(&self) -> Option<(&Mesh, &DofMap, &[f64])> {
        self.previous.as_ref().map(|(m, d, u)| (m, d, u.as_slice()))
    }

    /// s₀ at the contact vertices of the new mesh (zero elsewhere), from the previous cycle.
    fn transferred_s0(&self, dofs: &DofMap) -> Result<Option<Vec<f64>>, String> {
        let Some((old_mesh, old_dofs, old_u)) = &self.previous else {
            return Ok(None);
        };
        let mut s0 = vec![0.0; dofs.n_dofs()];
        for cb in &self.boundaries {
            for v in dofs.vertices.side_vertices(cb.side) {
                let p = dofs.vertices.coords[v as usize];
                for comp in 0..2 {
                    s0[dofs.dof(v, comp)] = super::evaluate(old_mesh, old_dofs, old_u, comp, p)
                        .ok_or_else(|| {
                            format!(
                                "transfer of s₀: the vertex ({}, {}) lies outside the previous mesh",
                                p[0], p[1]
                            )
                        })?;
                }
            }
        }
        Ok(Some(s0))
    }

    /// Assemble, build the constraints and solve the variational inequality on `dofs`.
    pub fn solve_contact(
        &mut self,
        mesh: &Mesh,
        dofs: &DofMap,
        system: &mut SparseSystem,
        seconds: &mut PhaseSeconds,
    ) -> Result<CycleState, String> {
        let t = Instant::now();
        let fixed = self.problem.fixed_dofs(dofs);
        let (values, rhs) = self.problem.assemble(mesh, system);
        let mut is_fixed = vec![false; dofs.n_dofs()];
        for &(d, _) in &fixed {
            is_fixed[d] = true;
        }
        // The previous cycle's solution at the contact vertices: the linearisation point s₀ of
        // the Signorini constraints, and the warm start of the active set for both models.
        let previous = self.transferred_s0(dofs)?;
        let s0 = if self.uses_signorini {
            previous.as_deref()
        } else {
            None
        };
        let builder = ConstraintBuilder {
            boundaries: &self.boundaries,
            face_model: &*self.face_models,
        };
        let constraints = builder.build(dofs, &is_fixed, s0)?;
        // Warm start: constraints that the previous solution touches or violates.
        let initial: Option<Vec<bool>> = previous.as_ref().map(|p| {
            constraints
                .iter()
                .map(|c| {
                    let s = [p[dofs.dof(c.vertex, 0)], p[dofs.dof(c.vertex, 1)]];
                    let gap = c.bound - (c.normal[0] * s[0] + c.normal[1] * s[1]);
                    gap <= 1e-9 * (1.0 + c.bound.abs())
                })
                .collect()
        });
        seconds.assemble += t.elapsed().as_secs_f64();
        let t = Instant::now();
        let solution = solve_pdas(
            system,
            dofs,
            &values,
            &rhs,
            &fixed,
            &constraints,
            initial.as_deref(),
        )?;
        seconds.solve += t.elapsed().as_secs_f64();
        Ok(CycleState {
            constraints,
            solution,
        })
    }

    /// Indicators of Theorem III.15 for the current state.
    pub fn contact_estimate(&self, mesh: &Mesh, dofs: &DofMap, u: &[f64]) -> ContactEstimate {
        let state = self.state.as_ref().expect("estimate after solve");
        contact_estimator::indicators(
            mesh,
            dofs,
            u,
            &self.problem,
            &self.boundaries,
            &state.constraints,
            &state.solution.active,
            self.estimator,
        )
    }

    /// The deformed body in true scale with the obstacle curves and the vertices in contact.
    pub fn picture(
        &self,
        mesh: &Mesh,
        dofs: &DofMap,
        state: &CycleState,
        cycle: usize,
        label: &str,
    ) -> DeformedPicture {
        let u = &state.solution.u;
        let mut pic = super::deformed_picture(mesh, dofs, u, cycle, None);
        let (x0, x1) = mesh
            .active()
            .iter()
            .map(|&c| mesh.cell_box(c))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), b| {
                (lo.min(b[0]), hi.max(b[2]))
            });
        let n = 3200;
        pic.obstacles = self
            .boundaries
            .iter()
            .map(|cb| {
                (0..=n)
                    .map(|i| {
                        cb.obstacle
                            .obstacle_point(x0 + (x1 - x0) * i as f64 / n as f64)
                    })
                    .collect()
            })
            .collect();
        pic.contact_points = state
            .constraints
            .iter()
            .zip(&state.solution.active)
            .filter(|(_, &a)| a)
            .map(|(c, _)| {
                let x = dofs.vertices.coords[c.vertex as usize];
                [
                    x[0] + u[dofs.dof(c.vertex, 0)],
                    x[1] + u[dofs.dof(c.vertex, 1)],
                ]
            })
            .collect();
        let depth = penetration(&self.boundaries, dofs, u, PENETRATION_SAMPLES);
        pic.caption = format!(
            "{label}: {} of {} contact vertices in contact (dots); true penetration of the \
             deformed boundary into the obstacle {:.3e} (largest vertical depth)",
            pic.contact_points.len(),
            state.constraints.len(),
            depth
        );
        pic
    }
}

fn model_label(model: ContactModel) -> &'static str {
    match model {
        ContactModel::Z => "z-contact",
        ContactModel::Signorini => "Signorini contact",
    }
}

impl AdaptiveModel for ContactStudy {
    fn n_components(&self) -> usize {
        2
    }

    fn solve(
        &mut self,
        mesh: &Mesh,
        dofs: &DofMap,
        system: &mut SparseSystem,
        seconds: &mut PhaseSeconds,
    ) -> Result<Solution, String> {
        let state = self.solve_contact(mesh, dofs, system, seconds)?;
        let counters = vec![
            (
                "active_set_iterations".to_string(),
                state.solution.iterations as i64,
            ),
            (
                "contact_vertices".to_string(),
                state.solution.active.iter().filter(|&&a| a).count() as i64,
            ),
        ];
        let u = state.solution.u.clone();
        self.state = Some(state);
        Ok(Solution { u, counters })
    }

    fn estimate(&mut self, mesh: &Mesh, dofs: &DofMap, u: &[f64]) -> Estimate {
        let e = self.contact_estimate(mesh, dofs, u);
        let mut quantities = Vec::new();
        if self.estimator == ContactEstimator::SignoriniCode {
            let ratio = |now: f64, before: Option<f64>| match before {
                None => f64::INFINITY,
                Some(b) => now.sqrt() / b.sqrt(),
            };
            quantities.push(("contact_estimate".to_string(), e.contact.sqrt()));
            quantities.push((
                "contact_ratio".to_string(),
                ratio(e.contact, self.previous_parts.map(|p| p.0)),
            ));
            quantities.push(("gap_estimate".to_string(), e.gap.sqrt()));
            quantities.push((
                "gap_ratio".to_string(),
                ratio(e.gap, self.previous_parts.map(|p| p.1)),
            ));
        }
        if matches!(
            self.estimator,
            ContactEstimator::ZCode | ContactEstimator::ZCodeObstacleSlope
        ) {
            quantities.push(("obstacle_estimate".to_string(), e.obstacle.sqrt()));
        }
        self.previous_parts = Some((e.contact, e.gap));
        quantities.push((
            "penetration".to_string(),
            penetration(&self.boundaries, dofs, u, PENETRATION_SAMPLES),
        ));
        Estimate {
            eta2: e.eta2,
            quantities,
        }
    }

    fn after_cycle(&mut self, mesh: &Mesh, dofs: &DofMap, u: &[f64]) {
        self.set_linearisation(mesh, dofs, u);
    }

    fn last_cycle(
        &mut self,
        _spec: &ExperimentSpec,
        mesh: &Mesh,
        dofs: &DofMap,
        _u: &[f64],
        cycle: usize,
        result: &mut RunResult,
    ) {
        let Some(state) = self.state.clone() else {
            return;
        };
        let label = if self.uses_signorini {
            model_label(ContactModel::Signorini)
        } else {
            model_label(ContactModel::Z)
        };
        result
            .deformed
            .push(self.picture(mesh, dofs, &state, cycle, label));
        if self.uses_signorini {
            // Side by side (thesis Figs. IV.20 and IV.32): the z-solution on the same mesh.
            let mut z = self.with_model(ContactModel::Z);
            let mut system = SparseSystem::new(dofs);
            let mut seconds = PhaseSeconds::default();
            if let Ok(zs) = z.solve_contact(mesh, dofs, &mut system, &mut seconds) {
                result.deformed.push(z.picture(
                    mesh,
                    dofs,
                    &zs,
                    cycle,
                    "for comparison, z-contact on the same mesh",
                ));
            }
        }
    }
}
