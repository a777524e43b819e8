//! Contact of an elastic body with a rigid obstacle as a variational inequality (I.23)/(II.15),
//! discretised as in §III.2.1.3: the constraint n·s ≤ b is imposed only at the contact vertices
//! Σ_C = Σ_h ∩ Γ_C (III.42)/(III.43). Hanging vertices are never constrained (their values follow
//! from their parents), nor are Dirichlet vertices.
//!
//! * z-contact (I.20), §IV.2.1: fixed direction n = n_z = ∓e₂ and the bound η_z(x₁) on the
//!   **undeformed** face (docs/models.md §2.4, §15 item 2).
//! * Signorini contact (I.21), linearised per cycle as in §IV.2.2 (thesis l. 5556–5568): with a
//!   displacement s₀ (the previous cycle's solution), at every contact vertex n is the outer unit
//!   normal of the deformed boundary polyline x + s₀ (mean of the two adjacent face normals,
//!   [`ContactSide::vertex_normal`]) and g the signed distance from x + s₀ to the obstacle along
//!   that same n (III.13), [`ContactSide::signed_distance_along`]; the constraint is
//!   (s − s₀)·n ≤ g ⇔ n·s ≤ g + n·s₀ (with b := g + n·(x + s₀) in the notation of Thm III.15).
//!   With s₀ = 0 on a flat face this is exactly the z-constraint. A vertex whose normal line
//!   meets no obstacle within [`crate::models::obstacle::SEARCH_RADIUS`] on the body's side (an
//!   obstacle far away) is left unconstrained.
//!
//! The contact boundary is split face by face into z-faces and Signorini-faces
//! ([`ConstraintBuilder::face_model`]), so one solve can mix both models (§IV.2.3); a vertex
//! between a z-face and a Signorini-face takes the Signorini constraint \[A\].
//!
//! Solver ([`solve_contact`]): the primal–dual active-set method of
//! [`crate::linalg::active_set`] on top of the faer Cholesky. Every constrained vertex is rotated
//! into its normal/tangential frame (QᵀKQ with 2×2 blocks, which keeps the vertex-block complete
//! pattern, so the symbolic factorisation is reused by every active-set iteration); an active
//! constraint fixes the normal component at its bound.

use crate::fe::{Constraints, DofMap, System};
use crate::linalg::active_set::{
    primal_dual_active_set, ActiveSetOptions, ActiveSetSolution, Bound, Bounds, NodalBounds,
    Rotation, Sense, ViolationTolerance,
};
use crate::linalg::multigrid::obstacle::{
    truncated_nonsmooth_newton_multigrid, TnnmgOptions, TnnmgWork,
};
use crate::linalg::multigrid::VertexHierarchy;
use crate::mesh::{BoundaryFace, Side};
use crate::models::obstacle::{ContactSide, Shape};
use crate::models::ModelError;

/// Which contact projection a face uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContactModel {
    /// Fixed-direction projection (I.20).
    Z,
    /// Signorini projection (I.21), linearised per cycle about the previous solution (§IV.2.2).
    Signorini,
}

/// One side of the domain in Γ_C with its obstacle.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactBoundary {
    pub side: Side,
    pub obstacle: ContactSide,
}

impl From<crate::experiment::ContactModel> for ContactModel {
    /// The model of every face at the start: a model-adaptive run starts with z everywhere
    /// (𝕋_c = 𝕋, Algorithms III.1–III.3).
    fn from(m: crate::experiment::ContactModel) -> ContactModel {
        match m {
            crate::experiment::ContactModel::Z | crate::experiment::ContactModel::ModelAdaptive => {
                ContactModel::Z
            }
            crate::experiment::ContactModel::Signorini => ContactModel::Signorini,
        }
    }
}

/// The contact boundaries of an experiment (the loader has checked that every obstacle is on the
/// bottom or the top side, at most one per side).
pub fn contact_boundaries(data: &crate::experiment::ContactData) -> Vec<ContactBoundary> {
    data.obstacles
        .iter()
        .map(|o| ContactBoundary {
            side: o.side,
            obstacle: ContactSide::new(Shape::from(&o.shape), o.side == Side::Top),
        })
        .collect()
}

/// The nodal constraint n·s(σ) ≤ bound at one contact vertex σ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactConstraint {
    pub vertex: u32,
    /// Index into the contact boundaries.
    pub boundary: usize,
    pub model: ContactModel,
    /// Outer unit normal n (n_z for z-contact).
    pub normal: [f64; 2],
    /// The gap g along n: η_z for z-contact, the signed distance from σ + s₀(σ) for Signorini.
    pub gap: f64,
    /// Right-hand side of n·s ≤ bound: η_z for z-contact, g + n·s₀ for Signorini.
    pub bound: f64,
}

impl ContactConstraint {
    /// The obstacle value b of Theorem III.15 for the constraint n·(x + s) ≤ b:
    /// b = bound + n·x.
    pub fn b(&self, x: [f64; 2]) -> f64 {
        self.bound + self.normal[0] * x[0] + self.normal[1] * x[1]
    }
}

/// The boundary faces between consecutive vertices `verts` of a side (as
/// [`crate::fe::dofs::Vertices::side_vertices`] lists them): a boundary face has no finer neighbour
/// across it, so no vertex lies inside it, and consecutive vertices are the end points of one.
pub fn side_faces(dofs: &DofMap, side: Side, verts: &[u32]) -> Vec<BoundaryFace> {
    let along = |vert: u32| {
        let key = dofs.vertices.keys[vert as usize];
        if side.is_horizontal() {
            key.0
        } else {
            key.1
        }
    };
    verts
        .windows(2)
        .map(|w| BoundaryFace::spanning(side, along(w[0]), along(w[1])))
        .collect()
}

/// Builds the contact constraints of one mesh.
pub struct ConstraintBuilder<'a> {
    pub boundaries: &'a [ContactBoundary],
    /// Contact model of a boundary face of Γ_C.
    pub face_model: &'a (dyn Fn(BoundaryFace) -> ContactModel + Sync),
}

impl ConstraintBuilder<'_> {
    /// Constraints at every contact vertex whose dofs are free (not hanging, not Dirichlet).
    /// `s0` is the linearisation point of the Signorini constraints as a field on `dofs` (only
    /// its values at contact vertices are read; `None` means s₀ = 0).
    pub fn build(
        &self,
        dofs: &DofMap,
        constraints: &Constraints,
        s0: Option<&[f64]>,
    ) -> Result<Vec<ContactConstraint>, ModelError> {
        assert_eq!(dofs.n_components, 2, "contact needs a vector field");
        let v = &dofs.vertices;
        let mut out = Vec::new();
        for (bi, cb) in self.boundaries.iter().enumerate() {
            let verts = v.side_vertices(cb.side);
            let x = |i: usize| v.coords[verts[i] as usize];
            let shifted = |i: usize| {
                let p = x(i);
                match s0 {
                    Some(s) => [
                        p[0] + s[dofs.dof(verts[i], 0)],
                        p[1] + s[dofs.dof(verts[i], 1)],
                    ],
                    None => p,
                }
            };
            let face_models: Vec<ContactModel> = side_faces(dofs, cb.side, &verts)
                .into_iter()
                .map(|f| (self.face_model)(f))
                .collect();
            for (i, &vert) in verts.iter().enumerate() {
                if !constraints.is_free(dofs.dof(vert, 0))
                    || !constraints.is_free(dofs.dof(vert, 1))
                {
                    continue;
                }
                let left = i.checked_sub(1).map(|f| face_models[f]);
                let right = face_models.get(i).copied();
                let signorini = [left, right]
                    .into_iter()
                    .flatten()
                    .any(|m| m == ContactModel::Signorini);
                let xv = x(i);
                if !signorini {
                    let eta = cb.obstacle.eta_z_at(xv);
                    out.push(ContactConstraint {
                        vertex: vert,
                        boundary: bi,
                        model: ContactModel::Z,
                        normal: cb.obstacle.n_z(),
                        gap: eta,
                        bound: eta,
                    });
                    continue;
                }
                let here = shifted(i);
                let prev = if i > 0 { shifted(i - 1) } else { here };
                let next = if i + 1 < verts.len() {
                    shifted(i + 1)
                } else {
                    here
                };
                let n = ContactSide::vertex_normal(prev, here, next, cb.obstacle.upper);
                // An obstacle out of reach leaves the vertex unconstrained.
                let g = match cb.obstacle.distance_within_reach(here, n) {
                    Ok(Some(g)) => g,
                    Ok(None) => continue,
                    Err(e) => {
                        return Err(ModelError::Failed(format!(
                            "Signorini linearisation at the contact vertex ({}, {}) deformed to \
                             ({:.6}, {:.6}) with normal ({:.4}, {:.4}): {e}, and the vertex lies \
                             beyond the obstacle: the displacement s₀ of the previous cycle (or \
                             the obstacle itself, in cycle 0) puts it deeper inside the obstacle \
                             than the normal line can be followed",
                            xv[0], xv[1], here[0], here[1], n[0], n[1]
                        )))
                    }
                };
                let s0n = n[0] * (here[0] - xv[0]) + n[1] * (here[1] - xv[1]);
                out.push(ContactConstraint {
                    vertex: vert,
                    boundary: bi,
                    model: ContactModel::Signorini,
                    normal: n,
                    gap: g,
                    bound: g + s0n,
                });
            }
        }
        Ok(out)
    }
}

/// The contact set of a displacement `u` for `constraints`: the constraints it touches or
/// violates (bound − n·u ≤ 1e-9·(1 + |bound|)) — the warm start of an active-set solve from
/// another solution (the previous cycle's, or the z-solution for the mixed solve of §IV.2.3).
pub fn contact_set(constraints: &[ContactConstraint], dofs: &DofMap, u: &[f64]) -> Vec<bool> {
    constraints
        .iter()
        .map(|c| {
            let s = [u[dofs.dof(c.vertex, 0)], u[dofs.dof(c.vertex, 1)]];
            let gap = c.bound - (c.normal[0] * s[0] + c.normal[1] * s[1]);
            gap <= 1e-9 * (1.0 + c.bound.abs())
        })
        .collect()
}

/// Result of the contact solve.
#[derive(Clone, Debug)]
pub struct ContactSolution {
    /// Displacement in Cartesian components, hanging dofs distributed.
    pub u: Vec<f64>,
    /// Contact force λ ≥ 0 per constraint (nodal multiplier, the residual (F − K u)·n).
    pub multipliers: Vec<f64>,
    /// Whether the constraint is active (in contact).
    pub active: Vec<bool>,
    /// bound − n·u per constraint (≥ 0; exactly 0 for active constraints).
    pub gaps: Vec<f64>,
    /// Number of linear solves of the active-set iteration.
    pub iterations: usize,
}

/// Most active-set iterations allowed before the solve counts as failed, or one per contact
/// constraint where there are more: the contact zone of a thin body can move by one vertex per
/// iteration (in the first load step of the U-O forming the die lifts a clamped strip, and the
/// zone walks from the free end back to the die's edge one vertex at a time, 64 iterations for
/// 128 constraints from a cold start).
pub const MAX_ACTIVE_SET_ITERATIONS: usize = 50;

/// Solve min ½uᵀKu − Fᵀu subject to n_i·u(σ_i) ≤ bound_i at every contact constraint and the
/// constraints of `system` (Dirichlet dofs, hanging dofs), by the primal–dual active-set method
/// ([`primal_dual_active_set`]) in the rotated frame of the constrained vertices: with
/// λ_i = (F − K u)·n_i, an active constraint stays active while λ_i > 0, an inactive one becomes
/// active when n_i·u − bound_i exceeds 1e-13·(1 + |bound_i|). `initial` is the first active set
/// (the warm start from the previous cycle). More than [`MAX_ACTIVE_SET_ITERATIONS`] solves (or
/// one per constraint, where there are more) is an error that states the count.
pub fn solve_contact(
    system: &System,
    solver: &mut dyn crate::linalg::SolveConstrained,
    constraints: &[ContactConstraint],
    initial: Option<&[bool]>,
) -> Result<ContactSolution, ModelError> {
    let (rotation, bounds) = contact_bounds(system, constraints);
    let eliminated = system.constraints.eliminated();
    let problem = contact_problem(system, &rotation, &bounds, &eliminated);
    let options = ActiveSetOptions {
        max_iterations: MAX_ACTIVE_SET_ITERATIONS.max(constraints.len()),
        multiplier_tolerance: 0.0,
        violation: ViolationTolerance::PerBound(1e-13),
    };
    let solution = primal_dual_active_set(&problem, solver, initial, &options)
        .map_err(|e| ModelError::from(e).context("contact"))?;
    Ok(contact_solution(system, solution))
}

/// The minimisation of [`solve_contact`] as nodal bounds: the matrix and load of `system` with
/// its eliminated dofs, the contact bounds in their rotated frames ([`contact_bounds`]).
pub fn contact_problem<'a>(
    system: &'a System,
    rotation: &'a Rotation,
    bounds: &'a [Bound],
    eliminated: &'a [(usize, f64)],
) -> NodalBounds<'a> {
    NodalBounds {
        matrix: system.matrix(),
        rhs: &system.rhs,
        bounds: Bounds::Listed(bounds),
        rotation: Some(rotation),
        eliminated,
        negated_rows: false,
    }
}

/// The displacement (with the hanging and Dirichlet dofs distributed), multipliers, active set,
/// gaps and iterations of a solved contact problem.
fn contact_solution(system: &System, solution: ActiveSetSolution) -> ContactSolution {
    let mut u = solution.x;
    system.constraints.distribute(&mut u);
    ContactSolution {
        u,
        multipliers: solution.multipliers,
        active: solution.active,
        gaps: solution.slack,
        iterations: solution.iterations,
    }
}

/// The contact constraints as nodal bounds: the rotation of every constrained vertex into its
/// normal/tangential frame and the upper bound on its normal component (dof 2v of the rotated
/// system).
pub fn contact_bounds(
    system: &System,
    constraints: &[ContactConstraint],
) -> (Rotation, Vec<Bound>) {
    let rotation = Rotation {
        frames: constraints.iter().map(|c| (c.vertex, c.normal)).collect(),
    };
    let bounds: Vec<Bound> = constraints
        .iter()
        .map(|c| Bound::new(system.dofs.dof(c.vertex, 0), Sense::Upper, c.bound))
        .collect();
    (rotation, bounds)
}

/// The problem of [`solve_contact`] solved by the truncated nonsmooth Newton multigrid method
/// ([`truncated_nonsmooth_newton_multigrid`]) on the level hierarchy of the mesh instead of the
/// primal–dual active-set method; `iterations` of the solution counts TNNMG iterations, and the
/// rest of its work is returned beside it.
pub fn solve_contact_tnnmg(
    system: &System,
    hierarchy: &VertexHierarchy,
    constraints: &[ContactConstraint],
    options: &TnnmgOptions,
) -> Result<(ContactSolution, TnnmgWork), ModelError> {
    let (rotation, bounds) = contact_bounds(system, constraints);
    let eliminated = system.constraints.eliminated();
    let problem = contact_problem(system, &rotation, &bounds, &eliminated);
    let solved = truncated_nonsmooth_newton_multigrid(&problem, hierarchy, 2, options)
        .map_err(|e| ModelError::from(e).context("contact"))?;
    Ok((contact_solution(system, solved.solution), solved.work))
}

/// Largest vertical depth by which the deformed contact boundary x + s (sides' polylines,
/// `samples` points per boundary face) lies beyond its obstacle curve ([`ContactSide::penetration`]).
pub fn penetration(
    boundaries: &[ContactBoundary],
    dofs: &DofMap,
    u: &[f64],
    samples: usize,
) -> f64 {
    let v = &dofs.vertices;
    let mut depth = 0.0f64;
    for cb in boundaries {
        let verts = v.side_vertices(cb.side);
        let p = |vert: u32| dofs.displaced(u, vert, 1.0);
        for w in verts.windows(2) {
            depth = depth.max(cb.obstacle.penetration(p(w[0]), p(w[1]), samples));
        }
    }
    depth
}
