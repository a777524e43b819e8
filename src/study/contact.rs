//! Tables IV.6–IV.17: z-contact (§IV.2.1) and Signorini contact (§IV.2.2) as variational
//! inequalities, grid-adaptive with the estimator of Theorem III.15.
//!
//! Per cycle: assemble the elasticity system, build the nodal constraints at the contact vertices
//! (z: fixed direction; Signorini: linearised about s₀ = the previous cycle's solution
//! transferred to the new mesh, s₀ = 0 in cycle 0, one linearised solve per cycle), solve by the
//! primal–dual active set method warm-started from the previous cycle's contact set, estimate.
//!
//! With Signorini faces every cycle also iterates the linearisation to a fixed point on the same
//! mesh ([`super::signorini`]): with `signorini = "linearised"` (the default) only to record how
//! far the linearised solution is from the converged one (the `signorini_*` columns), the
//! table and its mesh adaptation continuing from the linearised solution; with
//! `signorini = "converged"` the converged solution is the cycle's solution.

use super::clock::PhaseClock;
use super::elasticity::{deformed_picture, displacement_component};
use super::error::StudyError;
use super::problem::{
    setup_system, solve_once, Discretisation, Estimate, Pictures, Problem, Solution,
};
use super::quantities;
use super::reference::{self, VertexField};
use super::signorini::{converge, Comparison, ComparisonFailures, Converged, FixedPoint};
use super::transfer::PreviousSolution;
use crate::estimators;
use crate::estimators::contact::{self as contact_estimator, ContactEstimate, ContactEstimator};
use crate::experiment::{ContactData, ElasticityData, Rectangle, SignoriniReading};
use crate::fe::hierarchy::vertex_hierarchy;
use crate::fe::quadrature;
use crate::fe::{DofMap, System};
use crate::linalg::multigrid::obstacle::TnnmgOptions;
use crate::linalg::DirectSolver;
use crate::mesh::{BoundaryFace, Mesh, Side};
use crate::models::contact::{
    contact_boundaries, contact_set, penetration, solve_contact, solve_contact_tnnmg,
    ConstraintBuilder, ContactBoundary, ContactConstraint, ContactModel, ContactSolution,
};
use crate::models::elasticity::Elasticity;
use crate::models::manufactured::{ContactStrip, ExactDisplacement};
use crate::results::{columns, DeformedPicture, MeshField};

/// Boundary points per face at which the true penetration is sampled.
pub const PENETRATION_SAMPLES: usize = 8;

/// Contact model of each boundary face of Γ_C.
pub type FaceModels = Box<dyn Fn(BoundaryFace) -> ContactModel + Send + Sync>;

/// The constraints and the active-set solution of the current cycle.
#[derive(Clone, Debug)]
pub struct CycleState {
    pub constraints: Vec<ContactConstraint>,
    pub solution: ContactSolution,
}

impl CycleState {
    /// Keep the constraints and the active-set solution of a cycle in `state` (the estimate and
    /// the pictures use them) and return the loop's [`Solution`]: the displacement, `counters`
    /// and the count of vertices in contact.
    pub fn keep(
        state: &mut Option<CycleState>,
        constraints: Vec<ContactConstraint>,
        solution: ContactSolution,
        mut counters: Vec<(String, i64)>,
    ) -> Solution {
        counters.push((
            columns::CONTACT_VERTICES.to_string(),
            solution.active.iter().filter(|&&a| a).count() as i64,
        ));
        let u = solution.u.clone();
        *state = Some(CycleState {
            constraints,
            solution,
        });
        Solution { u, counters }
    }
}

/// The contact problem of one experiment.
pub struct ContactProblem {
    pub model: Elasticity,
    pub boundaries: Vec<ContactBoundary>,
    /// Contact model per boundary face (uniform for the pure runs of §IV.2.1/§IV.2.2).
    pub face_models: FaceModels,
    /// Whether any face may use the Signorini model (then s₀ is kept between cycles).
    pub uses_signorini: bool,
    pub estimator: ContactEstimator,
    solver: DirectSolver,
    /// Whether the cycle's (linearised) solve is the truncated nonsmooth Newton multigrid
    /// method on the mesh's level hierarchy ([`solve_contact_tnnmg`], `[study] solver =
    /// "multigrid"`) instead of the primal–dual active-set method with the direct solver; the
    /// fixed point of the Signorini comparison keeps the direct solver. Its
    /// `active_set_iterations` are then the TNNMG iterations.
    pub multigrid: bool,
    /// The previous cycle's solution: the linearisation point s₀ of the Signorini constraints
    /// and the warm start of the active set.
    previous: Option<PreviousSolution>,
    /// Constraints of the current cycle (after `assemble`) and the warm start of its active set.
    constraints: Vec<ContactConstraint>,
    initial: Option<Vec<bool>>,
    /// State of the current cycle (after `solve`).
    pub state: Option<CycleState>,
    /// Contact parts of the previous cycle (Σ hη_C², Σ h⁻¹η_{−C}²), for the ratio columns.
    previous_parts: Option<(f64, f64)>,
    /// Which Signorini solution the table uses (with Signorini faces).
    pub reading: SignoriniReading,
    /// The stopping rule of the fixed point.
    pub fixed_point: FixedPoint,
    /// Whether the linearised reading computes the converged solution for the comparison.
    pub compares: bool,
    /// The current cycle's linearised solution against the converged one (after `solve`).
    comparison: Option<Comparison>,
    /// Where the fixed point of the comparison failed with `signorini = "linearised"` (the
    /// table goes on; the notes of its section say it).
    pub failures: ComparisonFailures,
    /// The manufactured solution of the scene (`contact-strip`, `contact-strip-tilted`), if it
    /// has one: its surface load is added on Γ_C, and each row gets the true error, the
    /// effectivity and the vertices whose contact state differs from the known one.
    pub exact: Option<ExactDisplacement>,
}

impl ContactProblem {
    pub fn new(elasticity: &ElasticityData, contact: &ContactData) -> ContactProblem {
        ContactProblem {
            reading: contact.signorini_reading(),
            exact: elasticity
                .exact
                .map(ExactDisplacement::of)
                .filter(|e| e.strip().is_some()),
            ..ContactProblem::uniform(
                elasticity.into(),
                contact_boundaries(contact),
                contact.model.into(),
                contact.grid_estimator().into(),
            )
        }
    }

    /// One contact model on every face.
    fn uniform(
        model: Elasticity,
        boundaries: Vec<ContactBoundary>,
        contact_model: ContactModel,
        estimator: ContactEstimator,
    ) -> ContactProblem {
        ContactProblem {
            model,
            boundaries,
            face_models: Box::new(move |_| contact_model),
            uses_signorini: contact_model == ContactModel::Signorini,
            estimator,
            solver: DirectSolver::cholesky(),
            multigrid: false,
            previous: None,
            constraints: Vec::new(),
            initial: None,
            state: None,
            previous_parts: None,
            reading: SignoriniReading::Linearised,
            fixed_point: FixedPoint::default(),
            compares: true,
            comparison: None,
            failures: ComparisonFailures::default(),
            exact: None,
        }
    }

    /// The same scene with another (uniform) contact model, e.g. the z-solution for comparison.
    pub fn with_model(&self, model: ContactModel) -> ContactProblem {
        ContactProblem {
            exact: self.exact,
            ..ContactProblem::uniform(
                self.model.clone(),
                self.boundaries.clone(),
                model,
                self.estimator,
            )
        }
    }

    /// Set the linearisation point s₀ of the next Signorini solve explicitly.
    pub fn set_linearisation(&mut self, previous: PreviousSolution) {
        self.previous = Some(previous);
    }

    /// Mesh, dofs and solution of the last solved cycle (after `finish_cycle`).
    pub fn previous(&self) -> Option<&PreviousSolution> {
        self.previous.as_ref()
    }

    /// s₀ at the contact vertices of the new mesh (zero elsewhere), from the previous cycle.
    fn transferred_s0(&self, system: &System) -> Result<Option<Vec<f64>>, StudyError> {
        self.previous
            .as_ref()
            .map(|p| p.at_contact_vertices(&self.boundaries, &system.dofs))
            .transpose()
    }

    /// With Signorini faces: the fixed point of the linearisation from the cycle's linearised
    /// solve `linearised` (with the constraints of `assemble`), its constraints, solution and
    /// active-set iterations over all its solves; the comparison of the two is kept for the
    /// row. `None` without Signorini faces.
    fn converged(
        &mut self,
        disc: &Discretisation,
        system: &System,
        linearised: &ContactSolution,
    ) -> Result<Option<Converged>, StudyError> {
        self.comparison = None;
        let compared = self.compares || self.reading == SignoriniReading::Converged;
        if !self.uses_signorini || !compared {
            return Ok(None);
        }
        let builder = ConstraintBuilder {
            boundaries: &self.boundaries,
            face_model: &*self.face_models,
        };
        self.failures.start_solve();
        let fixed_point = converge(
            system,
            &mut self.solver,
            &builder,
            &self.constraints,
            linearised,
            &self.fixed_point,
        );
        let Some(converged) = self.failures.settle(self.reading, fixed_point)? else {
            return Ok(None);
        };
        self.comparison = Some(Comparison::of(
            &self.model,
            &disc.mesh,
            &system.dofs,
            &self.boundaries,
            (&self.constraints, &linearised.u),
            &converged,
        ));
        Ok(Some(converged))
    }

    /// The indicators of Theorem III.15 for the current state.
    pub fn contact_estimate(&self, mesh: &Mesh, dofs: &DofMap, u: &[f64]) -> ContactEstimate {
        let state = self.state.as_ref().expect("estimate after solve");
        contact_estimator::indicators(
            mesh,
            dofs,
            u,
            &self.model,
            &self.boundaries,
            &state.constraints,
            &state.solution.active,
            self.estimator,
        )
    }
}

/// The deformed body of a contact solution in true scale with the obstacle curves of
/// `boundaries` and the vertices in contact, captioned with `label`.
pub fn contact_picture(
    boundaries: &[ContactBoundary],
    mesh: &Mesh,
    dofs: &DofMap,
    state: &CycleState,
    cycle: usize,
    label: &str,
) -> DeformedPicture {
    let u = &state.solution.u;
    let mut pic = deformed_picture(mesh, dofs, u, cycle, None);
    let (x0, x1) = mesh
        .active()
        .iter()
        .map(|&c| mesh.cell_box(c))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), b| {
            (lo.min(b[0]), hi.max(b[2]))
        });
    let n = 3200;
    pic.obstacles = boundaries
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
        .map(|(c, _)| dofs.displaced(u, c.vertex, 1.0))
        .collect();
    let depth = penetration(boundaries, dofs, u, PENETRATION_SAMPLES);
    pic.caption = format!(
        "{label}: {} of {} contact vertices in contact (dots); true penetration of the \
         deformed boundary into the obstacle {:.3e} (largest vertical depth)",
        pic.contact_points.len(),
        state.constraints.len(),
        depth
    );
    pic
}

/// The contact set of a cycle as point fields of the last mesh: `contact`, 1 at the contact
/// vertices whose constraint is active (in contact with the obstacle), 0 at every other vertex,
/// and `contact_pressure`, the nodal contact force λ_i of the active-set solve (the residual
/// (F − Ku)·n) over the length ℓ_i of boundary the vertex stands for ([`tributary_lengths`]):
/// the lumped reading of a traction, exact for a uniform pressure; 0 off the contact set.
pub fn contact_set_fields(
    state: &Option<CycleState>,
    boundaries: &[ContactBoundary],
    dofs: &DofMap,
) -> Vec<MeshField> {
    let Some(state) = state else {
        return Vec::new();
    };
    let mut member = vec![false; dofs.vertices.len()];
    let mut pressure = vec![0.0; dofs.vertices.len()];
    for load in active_loads(state, boundaries, dofs) {
        let v = load.vertex as usize;
        member[v] = true;
        pressure[v] += load.force / load.length;
    }
    vec![
        MeshField::flags("contact", member),
        MeshField::real("contact_pressure", 1, pressure),
    ]
}

/// The nodal contact force of an active constraint and the boundary length it stands for.
pub struct NodalLoad {
    pub vertex: u32,
    /// Index into the contact boundaries.
    pub boundary: usize,
    /// λᵢ, the multiplier of the active-set solve.
    pub force: f64,
    /// ℓᵢ ([`tributary_lengths`]).
    pub length: f64,
}

/// The active constraints of a cycle with their nodal forces and lengths. An inactive
/// constraint's multiplier is 0 up to the solve's rounding (1e-12 in IV.7), so it has none.
pub fn active_loads<'a>(
    state: &'a CycleState,
    boundaries: &[ContactBoundary],
    dofs: &DofMap,
) -> impl Iterator<Item = NodalLoad> + 'a {
    let lengths: Vec<Vec<f64>> = boundaries
        .iter()
        .map(|b| tributary_lengths(dofs, b.side))
        .collect();
    state
        .constraints
        .iter()
        .zip(&state.solution.active)
        .zip(&state.solution.multipliers)
        .filter(|((_, &active), _)| active)
        .map(move |((c, _), &force)| NodalLoad {
            vertex: c.vertex,
            boundary: c.boundary,
            force,
            length: lengths[c.boundary][c.vertex as usize],
        })
}

/// Per vertex the length of the side `side` it stands for: half of each boundary face it ends
/// (0 off the side). A nodal force λ_i over ℓ_i is the mean traction there.
pub fn tributary_lengths(dofs: &DofMap, side: Side) -> Vec<f64> {
    let coords = &dofs.vertices.coords;
    let mut lengths = vec![0.0; coords.len()];
    for face in dofs.vertices.side_vertices(side).windows(2) {
        let [a, b] = [face[0] as usize, face[1] as usize];
        let half = 0.5 * (coords[b][0] - coords[a][0]).hypot(coords[b][1] - coords[a][1]);
        lengths[a] += half;
        lengths[b] += half;
    }
    lengths
}

fn model_label(model: ContactModel) -> &'static str {
    match model {
        ContactModel::Z => "z-contact",
        ContactModel::Signorini => "Signorini contact",
    }
}

impl Problem for ContactProblem {
    fn setup(&mut self, disc: &Discretisation) -> System {
        setup_system(disc, 2, &mut self.solver, |s| self.model.constrain(s))
    }

    /// The elasticity system and the contact constraints: the previous cycle's solution at the
    /// contact vertices is the linearisation point s₀ of the Signorini constraints, and its
    /// contact set (the constraints it touches or violates) the warm start of the active set for
    /// both models.
    fn assemble(&mut self, disc: &Discretisation, system: &mut System) -> Result<(), StudyError> {
        self.model.assemble(&disc.mesh, system);
        if let Some(exact) = &self.exact {
            add_surface_load(&self.model, exact, system);
        }
        let previous = self.transferred_s0(system)?;
        let s0 = if self.uses_signorini {
            previous.as_deref()
        } else {
            None
        };
        let builder = ConstraintBuilder {
            boundaries: &self.boundaries,
            face_model: &*self.face_models,
        };
        let dofs = &system.dofs;
        self.constraints = builder.build(dofs, &system.constraints, s0)?;
        self.initial = previous
            .as_ref()
            .map(|p| contact_set(&self.constraints, dofs, p));
        Ok(())
    }

    /// The linearised solve; with Signorini faces also the fixed point from it, which is the
    /// cycle's solution with `signorini = "converged"` (its active-set iterations are then
    /// those of every solve of the cycle).
    fn solve(
        &mut self,
        disc: &Discretisation,
        system: &mut System,
        _clock: &PhaseClock,
    ) -> Result<Solution, StudyError> {
        let solved = if self.multigrid {
            let levels = vertex_hierarchy(&disc.mesh, &system.dofs.vertices);
            solve_contact_tnnmg(system, &levels, &self.constraints, &TnnmgOptions::default())
                .map(|(solution, _)| solution)
        } else {
            solve_contact(
                system,
                &mut self.solver,
                &self.constraints,
                self.initial.as_deref(),
            )
        };
        let solved = solved.map_err(StudyError::from).and_then(|linearised| {
            let converged = self.converged(disc, system, &linearised)?;
            Ok((linearised, converged))
        });
        self.solver.release_pattern();
        let (linearised, converged) = solved?;
        let (constraints, solution) = match (self.reading, converged) {
            (SignoriniReading::Converged, Some(converged)) => {
                converged.as_cycle_solve(linearised.iterations)
            }
            _ => (std::mem::take(&mut self.constraints), linearised),
        };
        let iterations = solution.iterations as i64;
        Ok(CycleState::keep(
            &mut self.state,
            constraints,
            solution,
            vec![("active_set_iterations".to_string(), iterations)],
        ))
    }

    fn estimate(
        &mut self,
        disc: &Discretisation,
        dofs: &DofMap,
        solution: &Solution,
    ) -> Result<Estimate, StudyError> {
        let u = &solution.u;
        let e = self.contact_estimate(&disc.mesh, dofs, u);
        let mut estimate = Estimate::of_cells(e.eta2);
        if self.estimator == ContactEstimator::SignoriniCode {
            // Undefined in the first row and after a part that was 0 (no contact yet).
            let ratio = |now: f64, before: Option<f64>| {
                before.filter(|&b| b > 0.0).map(|b| now.sqrt() / b.sqrt())
            };
            estimate = estimate
                .with("contact_estimate", e.contact.sqrt())
                .with_optional(
                    "contact_ratio",
                    ratio(e.contact, self.previous_parts.map(|p| p.0)),
                )
                .with("gap_estimate", e.gap.sqrt())
                .with_optional("gap_ratio", ratio(e.gap, self.previous_parts.map(|p| p.1)));
        }
        if matches!(
            self.estimator,
            ContactEstimator::ZCode | ContactEstimator::ZCodeObstacleSlope
        ) {
            estimate = estimate.with("obstacle_estimate", e.obstacle.sqrt());
        }
        self.previous_parts = Some((e.contact, e.gap));
        estimate = estimate.with(
            "penetration",
            penetration(&self.boundaries, dofs, u, PENETRATION_SAMPLES),
        );
        if let Some(comparison) = self.comparison.take() {
            estimate.columns.extend(comparison.columns());
        }
        if let Some(exact) = &self.exact {
            let error =
                estimators::true_error::elasticity_energy(&disc.mesh, dofs, u, &self.model, exact);
            let total = estimators::total(&estimate.cells);
            let state = self.state.as_ref().expect("estimate after solve");
            estimate = estimate
                .with(columns::ERROR, error)
                .with(columns::EFFECTIVITY, total / error)
                .with(
                    CONTACT_SET_MISMATCH,
                    contact_set_mismatch(exact, dofs, state) as f64,
                );
        }
        Ok(estimate)
    }

    /// J(s_h) of the elastic body: the contact constraints restrict where it is minimised, not
    /// the functional (frictionless contact). Not for a manufactured field, whose surface load
    /// on the contact side ([`add_surface_load`]) J would have to include: those scenes have
    /// their true error.
    fn energy(&self, disc: &Discretisation, dofs: &DofMap, solution: &Solution) -> Option<f64> {
        if self.exact.is_some() {
            return None;
        }
        Some(self.model.energy(&disc.mesh, dofs, &solution.u))
    }

    fn constrained(&self) -> bool {
        true
    }

    fn finish_cycle(&mut self, disc: &Discretisation, dofs: DofMap, solution: Solution) {
        self.previous = Some(PreviousSolution::of(disc, dofs, solution.u));
    }

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
        let mesh = &disc.mesh;
        let label = if self.uses_signorini {
            model_label(ContactModel::Signorini)
        } else {
            model_label(ContactModel::Z)
        };
        let mut deformed = vec![contact_picture(
            &self.boundaries,
            mesh,
            dofs,
            state,
            cycle,
            label,
        )];
        if self.uses_signorini {
            // Side by side (thesis Figs. IV.20 and IV.32): the z-solution on the same mesh.
            let mut z = self.with_model(ContactModel::Z);
            let mut z_system = z.setup(disc);
            let solved = z
                .assemble(disc, &mut z_system)
                .and_then(|()| z.solve(disc, &mut z_system, &PhaseClock::default()));
            if let (Ok(_), Some(z_state)) = (solved, &z.state) {
                deformed.push(contact_picture(
                    &z.boundaries,
                    mesh,
                    &z_system.dofs,
                    z_state,
                    cycle,
                    "for comparison, z-contact on the same mesh",
                ));
            }
        }
        Pictures {
            deformed,
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

    fn point_sets(&self, dofs: &DofMap) -> Vec<MeshField> {
        contact_set_fields(&self.state, &self.boundaries, dofs)
    }

    fn notes(&self) -> Vec<String> {
        self.failures.notes()
    }

    /// Where the energy bound fails (or a manufactured scene has no energy), the error is
    /// measured against a reference solve on the last mesh refined once, the distances to the
    /// kept solves (the default [`Problem::reference_errors`]).
    fn keeps_solves(&self) -> bool {
        true
    }

    /// The energy norm of elasticity (III.35), the norm of Theorems III.12 and III.15.
    fn solve_distance(&self, on: &Mesh, a: VertexField, b: VertexField) -> Option<f64> {
        reference::energy_distance(on, a, b, &self.model)
    }

    /// The solve of a cycle on `disc`, warm-started from the last solution, without the
    /// comparison columns; the problem's state stays that of the run's last cycle.
    fn reference_solve(
        &mut self,
        disc: &Discretisation,
    ) -> Result<Option<(DofMap, Vec<f64>)>, StudyError> {
        let kept = (
            self.state.take(),
            self.failures.clone(),
            std::mem::replace(&mut self.compares, false),
        );
        let solved = solve_once(self, disc);
        (self.state, self.failures, self.compares) = kept;
        solved.map(Some)
    }
}

/// Column of the manufactured contact scenes: the contact vertices, away from the ends of the
/// known active interval, whose computed state (in contact or not) differs from the exact one.
pub const CONTACT_SET_MISMATCH: &str = "contact_set_mismatch";

/// ∫_{Γ_C} t·φ added to the load vector for the surface load t of a manufactured contact field
/// on the bottom side ([`ExactDisplacement::contact_traction`]): t = σ(s)n₀ + pν is not
/// polynomial, so 4 Gauss points per face. The vertices of a boundary side are never hanging
/// (a hanging vertex is the midpoint of an interior face), so the face integrals go straight to
/// the dofs of their end points; the clamped corners' dofs are fixed and skipped.
fn add_surface_load(model: &Elasticity, exact: &ExactDisplacement, system: &mut System) {
    let (gp, gw) = quadrature::gauss(4);
    let dofs = &system.dofs;
    let verts = dofs.vertices.side_vertices(Side::Bottom);
    for w in verts.windows(2) {
        let (xa, xb) = (
            dofs.vertices.coords[w[0] as usize],
            dofs.vertices.coords[w[1] as usize],
        );
        let len = xb[0] - xa[0];
        for (t, weight) in gp.iter().zip(gw) {
            let x = [xa[0] + t * len, xa[1]];
            let load = exact.contact_traction(model.mu, model.lambda, x);
            for (vert, phi) in [(w[0], 1.0 - t), (w[1], *t)] {
                for (i, li) in load.iter().enumerate() {
                    let d = dofs.dof(vert, i);
                    if system.constraints.is_free(d) {
                        system.rhs[d] += li * phi * weight * len;
                    }
                }
            }
        }
    }
}

/// The contact vertices whose computed state (active constraint or not) differs from the
/// exact one (x₁ in the active interval of the field), leaving out the end points of the
/// bottom faces that contain an end of the interval (the cells touching the free boundary).
pub fn contact_set_mismatch(exact: &ExactDisplacement, dofs: &DofMap, state: &CycleState) -> usize {
    let Some(strip) = exact.strip() else {
        return 0;
    };
    let coords = &dofs.vertices.coords;
    let verts = dofs.vertices.side_vertices(Side::Bottom);
    let mut touching = std::collections::HashSet::<u32>::new();
    for w in verts.windows(2) {
        let (a, b) = (coords[w[0] as usize][0], coords[w[1] as usize][0]);
        if ContactStrip::ACTIVE.iter().any(|&e| a <= e && e <= b) {
            touching.extend(w.iter().copied());
        }
    }
    state
        .constraints
        .iter()
        .zip(&state.solution.active)
        .filter(|(c, _)| !touching.contains(&c.vertex))
        .filter(|(c, &active)| strip.in_contact(coords[c.vertex as usize][0]) != active)
        .count()
}

/// Relative reach of an obstacle into the body at a clamped corner that is still accepted.
pub const CORNER_TOLERANCE: f64 = 1e-3;

/// Why a contact scene has no solution, if it has none that can be seen from its data: an
/// obstacle that reaches into the body at a point the Dirichlet condition clamps. There s = 0,
/// but the constraint asks s₂ ≥ b > 0 on a lower contact face and s₂ ≤ b < 0 on an upper one
/// (§IV.2.1), so the convex set of admissible displacements is empty. The points checked are
/// the ends of a contact face on a Dirichlet side (the corners the clamped sides share with it).
///
/// A reach below [`CORNER_TOLERANCE`] times the height of the body is let through: the smooth
/// obstacles of the thesis do not vanish exactly at the corners (the saw of Table IV.17 has
/// b(−16) = 2·10⁻⁶ from the tails of θ_s), and the discrete problem, which constrains only the
/// contact vertices off the clamped sides, is solvable anyway.
pub fn infeasible_obstacle(
    elasticity: &ElasticityData,
    contact: &ContactData,
    domain: &Rectangle,
) -> Option<String> {
    let x = domain.x;
    let tolerance = CORNER_TOLERANCE * (domain.y[1] - domain.y[0]);
    for (i, boundary) in contact_boundaries(contact).iter().enumerate() {
        for (side, corner) in [(Side::Left, x[0]), (Side::Right, x[1])] {
            if !elasticity.dirichlet.contains(&side) {
                continue;
            }
            let b = boundary.obstacle.shape.value(corner);
            let upper = boundary.obstacle.upper;
            if (!upper && b > tolerance) || (upper && b < -tolerance) {
                return Some(format!(
                    "scene.contact.obstacles[{i}]: the obstacle on the {} face reaches into the \
                     body at the corner x₁ = {corner:?}, which the Dirichlet side `{}` clamps \
                     (b = {b:?} {} 0 asks s₂ {} b there, but s = 0): the contact problem has no \
                     solution",
                    boundary.side.name(),
                    side.name(),
                    if upper { "<" } else { ">" },
                    if upper { "≤" } else { "≥" },
                ));
            }
        }
    }
    None
}
