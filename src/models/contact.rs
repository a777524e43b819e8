//! Contact of an elastic body with a rigid obstacle as a variational inequality (I.23)/(II.15),
//! discretised as in §III.2.1.3: the constraint n·s ≤ b is imposed only at the contact vertices
//! Σ_C = Σ_h ∩ Γ_C (III.42)/(III.43). Hanging vertices are never constrained (their values follow
//! from their parents), nor are Dirichlet vertices.
//!
//! * z-contact (I.20), §IV.2.1: fixed direction n = n_z = ∓e₂ and the bound η_z(x₁) on the
//!   **undeformed** face (spec/models.md §2.4, §15 item 2).
//! * Signorini contact (I.21), linearised per cycle as in §IV.2.2 (thesis l. 5556–5568): with a
//!   displacement s₀ (the previous cycle's solution), at every contact vertex n is the outer unit
//!   normal of the deformed boundary polyline x + s₀ (mean of the two adjacent face normals,
//!   [`ContactSide::vertex_normal`]) and g the signed distance from x + s₀ to the obstacle along
//!   that same n (III.13), [`ContactSide::signed_distance_along`]; the constraint is
//!   (s − s₀)·n ≤ g ⇔ n·s ≤ g + n·s₀ (with b := g + n·(x + s₀) in the notation of Thm III.15).
//!   With s₀ = 0 on a flat face this is exactly the z-constraint.
//!
//! The contact boundary is split face by face into z-faces and Signorini-faces
//! ([`ConstraintBuilder::face_model`]), so one solve can mix both models (§IV.2.3); a vertex
//! between a z-face and a Signorini-face takes the Signorini constraint \[A\].
//!
//! Solver: primal–dual active set (semismooth Newton, [`solve_pdas`]) on top of the faer
//! Cholesky of [`SparseSystem::solve_fixed`]. Every constrained vertex is rotated into its
//! normal/tangential frame (Q^T K Q with 2×2 blocks, which keeps the vertex-block complete
//! pattern, so the symbolic factorisation is reused by every active-set iteration); an active
//! constraint fixes the normal component at its bound.

use crate::experiment::{self, ContactModel, Side};
use crate::fe::{DofMap, SparseSystem};
use crate::models::obstacle::ContactSide;

/// One side of the domain in Γ_C with its obstacle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactBoundary {
    pub side: Side,
    pub obstacle: ContactSide,
}

/// The contact boundaries of an experiment (the loader has checked that every obstacle is on the
/// bottom or the top side, at most one per side).
pub fn contact_boundaries(data: &experiment::ContactData) -> Vec<ContactBoundary> {
    data.obstacles
        .iter()
        .map(|o| ContactBoundary {
            side: o.side,
            obstacle: ContactSide::new(o.shape, o.side == Side::Top),
        })
        .collect()
}

/// The nodal constraint n·s(σ) ≤ bound at one contact vertex σ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Constraint {
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

impl Constraint {
    /// The obstacle value b of Theorem III.15 for the constraint n·(x + s) ≤ b:
    /// b = bound + n·x.
    pub fn b(&self, x: [f64; 2]) -> f64 {
        self.bound + self.normal[0] * x[0] + self.normal[1] * x[1]
    }
}

/// Builds the constraints of one mesh.
pub struct ConstraintBuilder<'a> {
    pub boundaries: &'a [ContactBoundary],
    /// Contact model of the boundary face [x₀, x₁] on a side.
    pub face_model: &'a (dyn Fn(Side, f64, f64) -> ContactModel + Sync),
}

impl ConstraintBuilder<'_> {
    /// Constraints at every non-hanging contact vertex whose dofs are not fixed (Dirichlet).
    /// `fixed[d]` flags fixed dofs; `s0` is the linearisation point of the Signorini constraints
    /// as a field on `dofs` (only its values at contact vertices are read; `None` means s₀ = 0).
    pub fn build(
        &self,
        dofs: &DofMap,
        fixed: &[bool],
        s0: Option<&[f64]>,
    ) -> Result<Vec<Constraint>, String> {
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
            // Consecutive vertices of a side are the end points of its boundary faces (a
            // boundary face has no finer neighbour across it, so no vertex lies inside it).
            let face_models: Vec<ContactModel> = (0..verts.len().saturating_sub(1))
                .map(|i| (self.face_model)(cb.side, x(i)[0], x(i + 1)[0]))
                .collect();
            for (i, &vert) in verts.iter().enumerate() {
                if v.is_hanging[vert as usize]
                    || fixed[dofs.dof(vert, 0)]
                    || fixed[dofs.dof(vert, 1)]
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
                    let eta = cb.obstacle.eta_z(xv[0]);
                    out.push(Constraint {
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
                let g = cb.obstacle.signed_distance_along(here, n).map_err(|e| {
                    format!(
                        "Signorini linearisation at the contact vertex ({}, {}) deformed to \
                         ({:.6}, {:.6}) with normal ({:.4}, {:.4}): {e}; the deformation s₀ is too \
                         large for the normal line to meet the obstacle",
                        xv[0], xv[1], here[0], here[1], n[0], n[1]
                    )
                })?;
                let s0n = n[0] * (here[0] - xv[0]) + n[1] * (here[1] - xv[1]);
                out.push(Constraint {
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

/// Result of the primal–dual active set method.
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

/// Most active-set iterations allowed before the solve counts as failed.
pub const MAX_ACTIVE_SET_ITERATIONS: usize = 50;

/// Rotate the nodal dofs of the vertices in `frames` into (normal, tangential) coordinates:
/// values ← Qᵀ K Q, rhs ← Qᵀ F with the 2×2 block R_v = [n | t], t = (−n₂, n₁), at each listed
/// vertex. The pattern is vertex-block complete, so both dofs of a vertex have the same column
/// pattern and are adjacent in every column.
fn rotate(system: &SparseSystem, values: &mut [f64], rhs: &mut [f64], frames: &[(u32, [f64; 2])]) {
    let cp = system.col_ptr();
    let ri = system.row_idx();
    for &(w, n) in frames {
        let t = [-n[1], n[0]];
        let (j0, j1) = (2 * w as usize, 2 * w as usize + 1);
        let (a, b) = (cp[j0], cp[j1]);
        let len = cp[j0 + 1] - a;
        debug_assert_eq!(len, cp[j1 + 1] - b);
        for k in 0..len {
            debug_assert_eq!(ri[a + k], ri[b + k]);
            let (x0, x1) = (values[a + k], values[b + k]);
            values[a + k] = n[0] * x0 + n[1] * x1;
            values[b + k] = t[0] * x0 + t[1] * x1;
        }
        let (f0, f1) = (rhs[j0], rhs[j1]);
        rhs[j0] = n[0] * f0 + n[1] * f1;
        rhs[j1] = t[0] * f0 + t[1] * f1;
    }
    for &(v, n) in frames {
        let t = [-n[1], n[0]];
        let i0 = 2 * v as usize;
        for q in cp[i0]..cp[i0 + 1] {
            let j = ri[q];
            let p0 = system.position(i0, j).expect("symmetric pattern");
            debug_assert_eq!(ri[p0 + 1], i0 + 1);
            let (y0, y1) = (values[p0], values[p0 + 1]);
            values[p0] = n[0] * y0 + n[1] * y1;
            values[p0 + 1] = t[0] * y0 + t[1] * y1;
        }
    }
}

/// Primal–dual active set method (semismooth Newton) for
/// min ½uᵀKu − Fᵀu subject to n_i·u(σ_i) ≤ bound_i at every constraint and u_d = value at the
/// `fixed` dofs (Dirichlet and hanging dofs, fixed at 0 and distributed afterwards).
///
/// With the multiplier λ_i = (F − K u)·n_i and c > 0 the active set is updated to
/// A = {i : λ_i + c (n_i·u − bound_i) > 0}; on A the normal component is fixed at its bound, off
/// A it is free (λ_i = 0). The iteration stops when A repeats (the KKT conditions then hold
/// exactly); more than [`MAX_ACTIVE_SET_ITERATIONS`] solves is an error that states the count.
pub fn solve_pdas(
    system: &mut SparseSystem,
    dofs: &DofMap,
    values: &[f64],
    rhs: &[f64],
    fixed: &[(usize, f64)],
    constraints: &[Constraint],
    initial_active: Option<&[bool]>,
) -> Result<ContactSolution, String> {
    let frames: Vec<(u32, [f64; 2])> = constraints.iter().map(|c| (c.vertex, c.normal)).collect();
    let mut kr = values.to_vec();
    let mut fr = rhs.to_vec();
    rotate(system, &mut kr, &mut fr, &frames);
    let diag = system.diagonal(&kr);
    let normal_dof = |c: &Constraint| 2 * c.vertex as usize;
    let mut active: Vec<bool> = match initial_active {
        Some(a) if a.len() == constraints.len() => a.to_vec(),
        _ => vec![false; constraints.len()],
    };
    let mut iterations = 0;
    loop {
        iterations += 1;
        if iterations > MAX_ACTIVE_SET_ITERATIONS {
            return Err(format!(
                "the contact active set did not converge: {} active-set iterations exceed the \
                 limit of {MAX_ACTIVE_SET_ITERATIONS}",
                iterations - 1
            ));
        }
        let mut all_fixed = fixed.to_vec();
        all_fixed.extend(
            constraints
                .iter()
                .zip(&active)
                .filter(|(_, &a)| a)
                .map(|(c, _)| (normal_dof(c), c.bound)),
        );
        let x = system
            .solve_fixed(&kr, &fr, &all_fixed)
            .map_err(|e| e.to_string())?;
        let kx = system.multiply(&kr, &x);
        let lambda: Vec<f64> = constraints
            .iter()
            .map(|c| fr[normal_dof(c)] - kx[normal_dof(c)])
            .collect();
        let next: Vec<bool> = constraints
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let d = normal_dof(c);
                if active[i] {
                    lambda[i] > 0.0
                } else {
                    // λ = 0 off the active set; a violation beyond rounding activates.
                    let tol = 1e-13 * (1.0 + c.bound.abs());
                    diag[d] * (x[d] - c.bound) > diag[d] * tol
                }
            })
            .collect();
        if next == active {
            let gaps: Vec<f64> = constraints
                .iter()
                .map(|c| c.bound - x[normal_dof(c)])
                .collect();
            let mut u = x;
            for &(v, n) in &frames {
                let (i0, i1) = (2 * v as usize, 2 * v as usize + 1);
                let (un, ut) = (u[i0], u[i1]);
                u[i0] = n[0] * un - n[1] * ut;
                u[i1] = n[1] * un + n[0] * ut;
            }
            dofs.distribute_hanging(&mut u);
            return Ok(ContactSolution {
                u,
                multipliers: lambda,
                active,
                gaps,
                iterations,
            });
        }
        active = next;
    }
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
        let p = |vert: u32| {
            let x = v.coords[vert as usize];
            [x[0] + u[dofs.dof(vert, 0)], x[1] + u[dofs.dof(vert, 1)]]
        };
        for w in verts.windows(2) {
            depth = depth.max(cb.obstacle.penetration(p(w[0]), p(w[1]), samples));
        }
    }
    depth
}
