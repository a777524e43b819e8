//! The SubStokes problem without cavitation (I.53), (I.57), weak form (I.58) = (II.32), and with
//! cavitation (I.65), weak form (I.66) = (II.36), discrete form (III.79), discretised with
//! equal-order Q₁/Q₁ and pressure stabilisation (§II.3.2.1, §III.2.3) on the quadtree mesh.
//!
//! **Unknowns.** Per vertex the film-integrated flow rate χ = (χ₁, χ₂) = ∫ v dx₃ (I.44) and the
//! film-integrated pressure ψ = ∫ p dx₃ (I.45), three Q₁ components in the order
//! χ₁, χ₂, ψ ([`System::new`] with 3 components; every vertex counts, hanging and boundary
//! ones included: 81 vertices, 243 dofs on the 8×8 grid).
//!
//! **Discrete problem** (docs/models.md §6.4): find χ_h ∈ (Q₁)², ψ_h ∈ Q₁ with ψ_h = ψ₀ at the
//! boundary vertices such that
//!
//! a₂(χ_h, ξ) − b₂(ξ, ψ_h) = ⟨κ + γ, ξ⟩ − ⟨ψ₀ n − X₀, ξ⟩_{∂Ω₂}   for all ξ ∈ (Q₁)²,
//! b₂(χ_h, φ) + Σ_Q δ_ε h_Q² ⟨∇ψ_h, ∇φ⟩_Q = ⟨σ₃, φ⟩            for all φ ∈ Q₁, φ|∂Ω₂ = 0,
//!
//! with a₂(χ, ξ) = ⟨∇χ, ∇ξ⟩ + 12⟨χ/g, ξ/g⟩ and b₂(ξ, φ) = ⟨φ/g, ∂_ν(g ξ_ν)⟩ = ∫ φ (div ξ + ξ·∇g/g)
//! (II.33), γ the momentum source (I.52) ([`FilmJets::gamma`]), σ₃ the mass source (I.50)
//! ([`FilmJets::sigma3`]), g the gap, h_Q the cell diameter (the diagonal of a rectangle) and δ_ε
//! the stabilisation constant ([`DEFAULT_DELTA_EPS`]). The examples of §IV.3 have κ = 0 and, by
//! the best reading of docs/models.md §15 item 8, X₀ = 0. The point condition (I.56) on χ is not imposed:
//! a₂ is coercive on all of H¹ (Thm II.40), so χ is determined without it.
//!
//! **Matrix.** The mass rows are negated so that the system is symmetric quasi-definite,
//!
//! ```text
//! [  A   −B ] [χ]   [  F ]
//! [ −Bᵀ  −C ] [ψ] = [ −G ]
//! ```
//!
//! A_{(i,μ),(j,ν)} = δ_μν ∫ (∇φ_j·∇φ_i + 12 φ_j φ_i / g²),
//! B_{(i,ν),q} = ∫ φ_q (∂_ν φ_i + φ_i ∂_ν g / g), C_{q,r} = Σ_Q δ_ε h_Q² ∫_Q ∇φ_r·∇φ_q,
//! F_{(i,μ)} = ∫ (κ_μ + γ_μ) φ_i − ∫_{∂Ω₂} (ψ₀ n_μ − X₀μ) φ_i ds, G_q = ∫ σ₃ φ_q,
//! and it is factored by the sparse LDLᵀ of [`DirectSolver::ldlt`] with the sign +1 on the
//! velocity dofs and −1 on the pressure dofs. Cell integrals use 2×2 Gauss points, the boundary
//! integral 2 Gauss points per boundary face. The boundary values ψ₀ are eliminated dofs, the
//! hanging-node constraints are condensed as in the other models ([`crate::fe::Constraints`]).
//!
//! **Cavitation** (§III.2.3.3, docs/models.md §7; [`Form::Cavitation`], [`solve_cavitation`]).
//! The velocity form is a₂c(χ, ξ) = ⟨∇χ, ∇ξ⟩ + 12⟨χ/g, ξ/g⟩ + ⟨div χ, div ξ⟩ with the plain 2-D
//! divergence (I.66); the boundary term −⟨div χ, n·ξ⟩_{∂Ω₂} of (I.66) is dropped, as (III.74),
//! (III.75) argue (div χ = 0 on ∂Ω₂ for ψ₀ > 0; docs/models.md §15 item 11), which keeps the matrix
//! symmetric. The momentum source is κ + γ_c with γ_c = γ₃c + 12 v̄/g (I.61), (I.65)
//! ([`FilmJets::gamma_c`], in the reading [`SubStokesProblem::cavitation_source`], default
//! (I.61) as printed). b₂c = b₂, the stabilisation C, the mass load G and the boundary term
//! −⟨ψ₀ n, ξ⟩_{∂Ω₂} are those of the plain form. The discrete problem (III.79) is solved in its
//! multiplier form: ψ_j ≥ 0 at the interior non-hanging vertices, λ_j = (Bᵀχ + Cψ − G)_j ≥ 0,
//! ψ_j λ_j = 0. Nodal ψ_h ≥ 0 gives ψ_h ≥ 0 everywhere for Q₁ (remark after (III.61)).
//!
//! [`FilmJets::gamma`]: crate::models::thin_film::FilmJets::gamma
//! [`FilmJets::sigma3`]: crate::models::thin_film::FilmJets::sigma3
//! [`FilmJets::gamma_c`]: crate::models::thin_film::FilmJets::gamma_c

use crate::fe::cell_values::CellValues;
use crate::fe::quadrature::{gauss, square_rule};
use crate::fe::{DofMap, LocalDofs, System};
use crate::linalg::active_set::{
    primal_dual_active_set, ActiveSetOptions, Bounds, NodalBounds, Sense, ViolationTolerance,
};
use crate::linalg::{Csc, DirectSolver};
use crate::mesh::{bilinear, CellId, Face, Mesh};
use crate::models::manufactured_stokes::ExactFlow;
use crate::models::thin_film::{CavitationSource, FilmJets, ThinFilm};
use crate::models::ModelError;

/// Default stabilisation constant δ_ε of the pressure stabilisation (the default of the
/// experiment files' `delta_eps`, defined there).
pub use crate::experiment::DEFAULT_DELTA_EPS;

/// Number of components per vertex: χ₁, χ₂, ψ.
pub const N_COMPONENTS: usize = 3;

/// Component index of the pressure ψ (χ_μ has component μ = 0, 1).
pub const PSI: usize = 2;

/// Largest relative residual ‖Kx − f‖/‖f‖ on the free dofs accepted after a solve.
pub const MAX_RELATIVE_RESIDUAL: f64 = 1e-10;

/// Largest number of primal–dual active-set iterations of [`solve_cavitation`].
pub const MAX_ACTIVE_SET_ITERATIONS: usize = 100;

/// Largest complementarity max_j |min(ψ_j, λ_j)| accepted after [`solve_cavitation`], relative
/// to max(1, ‖G‖∞) over the free ψ dofs.
pub const MAX_COMPLEMENTARITY: f64 = 1e-8;

/// One SubStokes example (§IV.3): film data, boundary pressure ψ₀ (I.55), δ_ε and the reading of
/// γ₃c (I.61) used by the cavitation form.
#[derive(Clone, Debug, PartialEq)]
pub struct SubStokesProblem {
    /// Gap g and wall velocities; γ (I.52) and σ₃ (I.50) are computed from them.
    pub film: ThinFilm,
    /// ψ₀ on ∂Ω₂ (200 in every example of §IV.3).
    pub boundary_pressure: f64,
    /// Stabilisation constant δ_ε.
    pub delta_eps: f64,
    /// The reading of γ₃c in the momentum source γ_c = γ₃c + 12 v̄/g (I.61), (I.65) of the
    /// cavitation form ([`Form::Cavitation`]); the plain form does not use it. Default: (I.61) as
    /// printed (docs/models.md §7).
    pub cavitation_source: CavitationSource,
    /// The point P of the point condition (I.56) χ(P) = (g v̄)(P) + g³ρ(P) (ρ = 0 in §IV.3), or
    /// none (the default: a₂ is coercive on all of H¹, Theorem II.40, so χ is determined without
    /// it, and a corner condition would break the symmetry of Figs IV.85, IV.101). P must be a
    /// vertex of every mesh (a corner of the domain).
    pub point: Option<[f64; 2]>,
    /// A manufactured solution ([`crate::models::manufactured_stokes`]): its momentum and mass
    /// sources replace κ + γ (κ + γ_c) and σ₃ in the assembly and in the estimators
    /// ([`SubStokesProblem::sources`]); `None` (the default) for the thesis's examples.
    pub exact: Option<ExactFlow>,
}

/// Which weak form [`SubStokesProblem::assemble_form`] assembles.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Form {
    /// (I.58) = (II.32): a₂ and the source κ + γ (module docs).
    #[default]
    Plain,
    /// The velocity equation of (I.66) = (II.36) in the discrete form (III.79) (module docs,
    /// "Cavitation"): a₂c = a₂ + ⟨div χ, div ξ⟩ and the source κ + γ_c.
    Cavitation,
}

/// A solved SubStokes system.
#[derive(Clone, Debug)]
pub struct SubStokesSolution {
    /// The dofs of the mesh it was solved on.
    pub dofs: DofMap,
    /// Vertex-major values (χ₁, χ₂, ψ) per vertex, hanging values distributed.
    pub u: Vec<f64>,
    /// Relative residual ‖Kx − f‖/‖f‖ of the solve on the free dofs, where f is the right-hand
    /// side of the reduced system (the load minus the couplings to the eliminated dofs).
    pub relative_residual: f64,
}

/// A solved SubStokes problem with cavitation ([`solve_cavitation`]).
#[derive(Clone, Debug)]
pub struct SubStokesCavitationSolution {
    /// Dofs, vertex-major (χ₁, χ₂, ψ) with hanging values distributed, and the relative residual
    /// of the last linear solve (on the free dofs off the active set).
    pub solution: SubStokesSolution,
    /// Per dof: the discrete multiplier λ_j = (Bᵀχ + Cψ − G)_j = b₂(χ_h, φ_j) +
    /// Σ_Q δ_ε h_Q²⟨∇ψ_h, ∇φ_j⟩_Q − ⟨σ₃, φ_j⟩ at the free ψ dofs (interior, not hanging) — the
    /// residual of the mass equation (III.79) tested with the hat function φ_j, ≥ 0 where ψ_j = 0
    /// and 0 up to rounding elsewhere (the rounding is kept, not zeroed) — and 0 at every other
    /// dof.
    pub lambda: Vec<f64>,
    /// Per dof: whether ψ_j = 0 is imposed (the final active set).
    pub active: Vec<bool>,
    /// Primal–dual active-set iterations (= numeric LDLᵀ factorisations).
    pub iterations: usize,
    /// max_j |min(ψ_j, λ_j)| over the free ψ dofs.
    pub complementarity: f64,
    /// ‖G‖∞ over the free ψ dofs (scale of the tolerances).
    pub load_scale: f64,
}

impl SubStokesCavitationSolution {
    /// The multiplier λ_j at vertex `v` (0 off the free ψ dofs).
    pub fn lambda_at(&self, v: u32) -> f64 {
        self.lambda[self.solution.dofs.dof(v, PSI)]
    }

    /// Fraction of the vertices with ψ = 0 (cavitated).
    pub fn cavitated_vertex_fraction(&self) -> f64 {
        let s = &self.solution;
        let n = s.dofs.vertices.len();
        let zero = (0..n as u32).filter(|&v| s.psi(v) == 0.0).count();
        zero as f64 / n as f64
    }

    /// Fraction of the area of Ω₂ covered by the cells whose four corners have ψ = 0 (ψ_h ≡ 0
    /// on them).
    pub fn cavitated_area_fraction(&self, mesh: &Mesh) -> f64 {
        let s = &self.solution;
        crate::models::film_comparison::cavitated_area(mesh, &s.dofs, &s.u, PSI)
    }
}

impl SubStokesSolution {
    /// χ_μ at vertex `v`.
    pub fn chi(&self, v: u32) -> [f64; 2] {
        [self.u[self.dofs.dof(v, 0)], self.u[self.dofs.dof(v, 1)]]
    }

    /// ψ at vertex `v`.
    pub fn psi(&self, v: u32) -> f64 {
        self.u[self.dofs.dof(v, PSI)]
    }

    /// The vertex at the point `x` (to 1e-12), if there is one.
    pub fn vertex_at(&self, x: [f64; 2]) -> Option<u32> {
        self.dofs
            .vertices
            .coords
            .iter()
            .position(|c| (c[0] - x[0]).abs() < 1e-12 && (c[1] - x[1]).abs() < 1e-12)
            .map(|v| v as u32)
    }
}

impl SubStokesProblem {
    /// The problem with the default δ_ε ([`DEFAULT_DELTA_EPS`]).
    pub fn new(film: ThinFilm, boundary_pressure: f64) -> SubStokesProblem {
        SubStokesProblem {
            film,
            boundary_pressure,
            delta_eps: DEFAULT_DELTA_EPS,
            cavitation_source: CavitationSource::default(),
            point: None,
            exact: None,
        }
    }

    /// The same problem with the manufactured solution `exact` (its data replace the film's
    /// sources).
    pub fn with_exact(self, exact: Option<ExactFlow>) -> SubStokesProblem {
        SubStokesProblem { exact, ..self }
    }

    /// The momentum source and the mass source at `x` of the film data `jets` = film_jets(x):
    /// κ + γ (κ + γ_c for `cavitation`, with [`SubStokesProblem::cavitation_source`]) and σ₃,
    /// or, with a manufactured solution, the sources derived from it
    /// ([`ExactFlow::sources`]; the same for both forms, its χ being divergence-free).
    #[inline]
    pub fn sources(
        &self,
        jets: &FilmJets,
        x: [f64; 2],
        source: Option<CavitationSource>,
    ) -> ([f64; 2], f64) {
        if let Some(exact) = &self.exact {
            return exact.sources(&self.film, x);
        }
        let gamma = match source {
            None => jets.gamma(),
            Some(s) => jets.gamma_c(s),
        };
        (
            [0, 1].map(|mu| jets.kappa[mu].v + gamma[mu].v),
            jets.sigma3().v,
        )
    }

    /// The same problem with the point condition (I.56) at `point`.
    pub fn with_point(self, point: Option<[f64; 2]>) -> SubStokesProblem {
        SubStokesProblem { point, ..self }
    }

    /// The same problem with another δ_ε.
    pub fn with_delta_eps(self, delta_eps: f64) -> SubStokesProblem {
        SubStokesProblem { delta_eps, ..self }
    }

    /// The same problem with another reading of γ₃c (cavitation form only).
    pub fn with_cavitation_source(self, cavitation_source: CavitationSource) -> SubStokesProblem {
        SubStokesProblem {
            cavitation_source,
            ..self
        }
    }

    /// The dofs (3 per vertex), hanging-node constraints and ψ = ψ₀ on ∂Ω₂ of `mesh`.
    pub fn system(&self, mesh: &Mesh) -> System {
        let mut system = System::new(mesh, N_COMPONENTS);
        self.constrain(&mut system);
        system
    }

    /// ψ = ψ₀ (I.55) at every boundary vertex; with a [`SubStokesProblem::point`], χ = g v̄ at
    /// its vertex (I.56).
    pub fn constrain(&self, system: &mut System) {
        let n_vertices = system.dofs.vertices.len() as u32;
        for v in 0..n_vertices {
            if system.dofs.vertices.on_boundary(v) {
                let dof = system.dofs.dof(v, PSI);
                system.constraints.fix(dof, self.boundary_pressure);
            }
        }
        if let Some(p) = self.point {
            let coords = &system.dofs.vertices.coords;
            if let Some(v) = coords.iter().position(|c| c[0] == p[0] && c[1] == p[1]) {
                let jets = self.film.film_jets(p);
                for mu in 0..2 {
                    let dof = system.dofs.dof(v as u32, mu);
                    system.constraints.fix(dof, jets.g.v * jets.vbar[mu].v);
                }
            }
        }
    }

    /// The LDLᵀ diagonal signs: +1 for χ dofs, −1 for ψ dofs.
    pub fn signs(dofs: &DofMap) -> Vec<i8> {
        (0..dofs.n_dofs())
            .map(|d| if d % N_COMPONENTS == PSI { -1 } else { 1 })
            .collect()
    }

    /// Assemble the symmetric quasi-definite matrix [A, −B; −Bᵀ, −C] and the load [F; −G]
    /// (module docs) into `system`: 2×2 Gauss points per cell, 2 Gauss points per boundary face.
    pub fn assemble(&self, mesh: &Mesh, system: &mut System) {
        self.assemble_form(mesh, system, Form::Plain)
    }

    /// Assemble the cavitation system (module docs, "Cavitation"): A with the grad-div term
    /// ⟨div χ, div ξ⟩ and F with κ + γ_c instead of κ + γ; B, C, G and the boundary term are
    /// those of [`Self::assemble`].
    pub fn assemble_cavitation(&self, mesh: &Mesh, system: &mut System) {
        self.assemble_form(mesh, system, Form::Cavitation)
    }

    /// Assemble `form` into `system` ([`Self::assemble`], [`Self::assemble_cavitation`]).
    pub fn assemble_form(&self, mesh: &Mesh, system: &mut System, form: Form) {
        let active = mesh.active();
        system.assemble(active.len(), |k, ke, fe| {
            self.cell_contributions(mesh, active[k], form, ke, fe)
        });
    }

    /// The local matrix and load of `form` on the active cell `c` (layout
    /// [`LocalDofs::new`]`(3)`, added into `ke` and `fe`): the cell integrals and, on the faces
    /// of `c` on ∂Ω₂, the boundary term −⟨ψ₀ n, ξ⟩ (module docs). [`Self::assemble_form`] calls
    /// it for every active cell; the model-adaptive coupling
    /// ([`crate::models::film_coupling`]) for the SubStokes cells only.
    pub fn cell_contributions(
        &self,
        mesh: &Mesh,
        c: CellId,
        form: Form,
        ke: &mut [f64],
        fe: &mut [f64],
    ) {
        let rule = square_rule::<4>();
        let local = LocalDofs::new(N_COMPONENTS);
        let (face_points, face_weights) = gauss(2);
        let psi0 = self.boundary_pressure;
        let delta = self.delta_eps;
        let shape = mesh.cell_shape(c);
        let h_q = shape.diameter();
        let stab = delta * h_q * h_q;
        let cv = CellValues::new(shape, &rule);
        for q in 0..rule.len() {
            let grad = cv.gradients(q);
            let phi = cv.values(q);
            let jw = cv.jxw(q);
            let jets = self.film.film_jets(cv.point(q));
            let g = jets.g.v;
            let dg_g = [jets.g.d[0] / g, jets.g.d[1] / g];
            // κ + γ, or κ + γ_c for cavitation (κ = 0 in the examples of §IV.3, kept for
            // the general form).
            let cavitation = match form {
                Form::Plain => None,
                Form::Cavitation => Some(self.cavitation_source),
            };
            let (source, sigma3) = self.sources(&jets, cv.point(q), cavitation);
            let mass = 12.0 / (g * g);
            for a in 0..4 {
                for b in 0..4 {
                    let stiff = grad[a][0] * grad[b][0] + grad[a][1] * grad[b][1];
                    // A: both velocity components.
                    let av = (stiff + mass * phi[a] * phi[b]) * jw;
                    for mu in 0..2 {
                        ke[local.entry(local.index(a, mu), local.index(b, mu))] += av;
                    }
                    // Grad-div: ⟨div χ, div ξ⟩ couples (a, μ) with (b, ν) by ∂_μφ_a ∂_νφ_b.
                    if form == Form::Cavitation {
                        for mu in 0..2 {
                            for nu in 0..2 {
                                ke[local.entry(local.index(a, mu), local.index(b, nu))] +=
                                    grad[a][mu] * grad[b][nu] * jw;
                            }
                        }
                    }
                    // −B (row χ of vertex a, column ψ of vertex b) and −Bᵀ.
                    for nu in 0..2 {
                        let bv = phi[b] * (grad[a][nu] + phi[a] * dg_g[nu]) * jw;
                        ke[local.entry(local.index(a, nu), local.index(b, PSI))] -= bv;
                        ke[local.entry(local.index(b, PSI), local.index(a, nu))] -= bv;
                    }
                    // −C.
                    ke[local.entry(local.index(a, PSI), local.index(b, PSI))] -= stab * stiff * jw;
                }
                for mu in 0..2 {
                    fe[local.index(a, mu)] += source[mu] * phi[a] * jw;
                }
                fe[local.index(a, PSI)] -= sigma3 * phi[a] * jw;
            }
        }
        // −∫_{∂Ω₂} ψ₀ n_μ φ_a ds (X₀ = 0).
        for bf in mesh.boundary_faces_of(c) {
            let face = match bf.side {
                crate::mesh::Side::Left => Face::Left,
                crate::mesh::Side::Right => Face::Right,
                crate::mesh::Side::Bottom => Face::Bottom,
                crate::mesh::Side::Top => Face::Top,
            };
            let n = shape.face_normal(face);
            let len = shape.face_length(face);
            for (&t, &w) in face_points.iter().zip(face_weights) {
                let (xi, eta) = match face {
                    Face::Left => (0.0, t),
                    Face::Right => (1.0, t),
                    Face::Bottom => (t, 0.0),
                    Face::Top => (t, 1.0),
                };
                let phi = bilinear(xi, eta);
                for a in 0..4 {
                    for mu in 0..2 {
                        fe[local.index(a, mu)] -= psi0 * n[mu] * phi[a] * w * len;
                    }
                }
            }
        }
    }

    /// Set up, assemble and solve on `mesh` with a fresh LDLᵀ solver.
    pub fn solve(&self, mesh: &Mesh) -> Result<SubStokesSolution, ModelError> {
        let mut system = self.system(mesh);
        self.assemble(mesh, &mut system);
        let mut solver = DirectSolver::ldlt(Self::signs(&system.dofs));
        solver.reorder(system.ordering());
        let (u, relative_residual) = solve_system(&system, &mut solver)?;
        Ok(SubStokesSolution {
            dofs: system.dofs,
            u,
            relative_residual,
        })
    }

    /// Set up, assemble the cavitation form and solve the complementarity problem on `mesh`
    /// ([`solve_cavitation`]) with a fresh LDLᵀ solver, from the empty active set (so the first
    /// iteration is the unconstrained solve of the cavitation form).
    pub fn solve_with_cavitation(
        &self,
        mesh: &Mesh,
    ) -> Result<SubStokesCavitationSolution, ModelError> {
        let mut system = self.system(mesh);
        self.assemble_cavitation(mesh, &mut system);
        let mut solver = DirectSolver::ldlt(Self::signs(&system.dofs));
        solver.reorder(system.ordering());
        let initial = vec![false; system.dofs.n_dofs()];
        solve_cavitation(&system, &mut solver, &initial)
    }
}

/// ‖Kx − f‖/‖f̃‖ over the dofs `rows`, where x holds the eliminated values (hanging dofs at 0)
/// as the solver returns it and f̃ = f − K x_eliminated is the right-hand side of the reduced
/// system (f itself on the rows when it vanishes).
pub(crate) fn relative_residual(
    matrix: Csc<'_>,
    rhs: &[f64],
    x: &[f64],
    eliminated: &[(usize, f64)],
    rows: impl Fn(usize) -> bool,
) -> f64 {
    let n = x.len();
    let mut lift = vec![0.0; n];
    for &(d, v) in eliminated {
        lift[d] = v;
    }
    let k_lift = matrix.multiply(&lift);
    let ku = matrix.multiply(x);
    let (mut r2, mut f2) = (0.0f64, 0.0f64);
    for i in (0..n).filter(|&i| rows(i)) {
        r2 += (ku[i] - rhs[i]).powi(2);
        f2 += (rhs[i] - k_lift[i]).powi(2);
    }
    if f2 > 0.0 {
        (r2 / f2).sqrt()
    } else {
        r2.sqrt()
    }
}

/// The free ψ dofs of a cavitation system (interior, non-hanging vertices), where ψ ≥ 0 is
/// imposed, and ‖G‖∞ over them (the scale of the tolerances): what the LDLᵀ active set
/// ([`solve_cavitation`]) and the projected Uzawa
/// ([`crate::models::substokes_uzawa::solve_cavitation_uzawa`]) check their solutions against.
pub(crate) struct PsiBounds {
    pub bounded: Vec<bool>,
    pub load_scale: f64,
}

impl PsiBounds {
    pub(crate) fn of(system: &System) -> PsiBounds {
        let n = system.dofs.n_dofs();
        let bounded: Vec<bool> = (0..n)
            .map(|d| d % N_COMPONENTS == PSI && system.constraints.is_free(d))
            .collect();
        let load_scale = (0..n)
            .filter(|&d| bounded[d])
            .fold(0.0f64, |m, d| m.max(system.rhs[d].abs()));
        PsiBounds {
            bounded,
            load_scale,
        }
    }

    /// λ_j = (F − Kx)_j on the negated mass rows = (Bᵀχ + Cψ − G)_j at the bounded dofs, 0
    /// elsewhere, from `u` with the hanging dofs at 0 (their columns hold only the diagonal).
    pub(crate) fn multipliers(&self, system: &System, u: &[f64]) -> Vec<f64> {
        let ku = system.matrix().multiply(u);
        (0..u.len())
            .map(|d| {
                if self.bounded[d] {
                    system.rhs[d] - ku[d]
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// The checks of a cavitation solution `u` (hanging values distributed) with multipliers
    /// `lambda`: ψ ≥ 0 at every vertex, and max_j |min(ψ_j, λ_j)| ≤
    /// `max_complementarity`·max(1, ‖G‖∞), which it returns. Messages start with `what`; `after`
    /// ends the complementarity message (how the solver got there).
    pub(crate) fn check(
        &self,
        u: &[f64],
        lambda: &[f64],
        max_complementarity: f64,
        what: &str,
        after: &str,
    ) -> Result<f64, ModelError> {
        let n = u.len();
        if let Some(d) = (0..n).find(|&d| d % N_COMPONENTS == PSI && u[d] < 0.0) {
            return Err(ModelError::Failed(format!(
                "{what}: ψ = {} < 0 at vertex {}",
                u[d],
                d / N_COMPONENTS
            )));
        }
        let complementarity = (0..n)
            .filter(|&d| self.bounded[d])
            .map(|d| u[d].min(lambda[d]).abs())
            .fold(0.0f64, f64::max);
        let tolerance = max_complementarity * self.load_scale.max(1.0);
        if !complementarity.is_finite() || complementarity > tolerance {
            return Err(ModelError::Failed(format!(
                "{what}: complementarity max|min(ψ, λ)| = {complementarity:e} exceeds \
                 {tolerance:e}{after}"
            )));
        }
        Ok(complementarity)
    }
}

/// Solve the assembled cavitation `system` ([`SubStokesProblem::assemble_cavitation`]) under
/// ψ_j ≥ 0 at the free ψ dofs (interior, non-hanging vertices; hanging values are means of their
/// parents, boundary values ψ₀), i.e. the discrete problem (III.79) in its multiplier form:
///
/// A χ − B ψ = F,  Bᵀχ + Cψ − G = λ,  ψ ≥ 0,  λ ≥ 0,  λ_j ψ_j = 0,
///
/// (λ_j = ⟨λ_h, φ_j⟩, the hat-function residual of the mass equation), by the primal–dual
/// active-set method ([`primal_dual_active_set`]) on the coupled symmetric quasi-definite
/// system. The mass rows are stored negated (module docs), so row j reads −(Bᵀχ + Cψ)_j = −G_j
/// and λ_j = (F − Kx)_j: the solver runs with [`NodalBounds::negated_rows`]. Active ψ dofs are an
/// overlay on the eliminated dofs, so every iteration is one numeric LDLᵀ factorisation with
/// the ordering and symbolic factorisation of `solver` reused (signs +1 on χ, −1 on ψ; an active
/// ψ dof keeps a −1 diagonal entry).
///
/// Tolerances as the Reynolds cavitation ([`crate::models::reynolds::solve_cavitation`]): an
/// active dof stays active while λ_j > −1e-12·max(1, ‖G‖∞), an inactive one becomes active when
/// ψ_j < −1e-13·max|x|. `initial_active` flags the first active set per dof (only its entries at
/// free ψ dofs are read; its length must be the number of dofs).
///
/// Checks (each failure is an `Err`): the factorisations (a zero pivot is an error, no pivot is
/// regularised), at most [`MAX_ACTIVE_SET_ITERATIONS`] iterations, the relative residual of the
/// last solve on the free dofs off the active set ≤ [`MAX_RELATIVE_RESIDUAL`], finite values,
/// ψ ≥ 0 at every vertex (negative values of rounding size, |ψ_j| ≤ 1e-12·max|ψ|, at inactive
/// dofs are set to 0 first), and max_j |min(ψ_j, λ_j)| ≤ [`MAX_COMPLEMENTARITY`]·max(1, ‖G‖∞).
pub fn solve_cavitation(
    system: &System,
    solver: &mut DirectSolver,
    initial_active: &[bool],
) -> Result<SubStokesCavitationSolution, ModelError> {
    let n = system.dofs.n_dofs();
    if initial_active.len() != n {
        return Err(ModelError::Failed(format!(
            "SubStokes cavitation: the initial active set has {} entries for {n} dofs",
            initial_active.len()
        )));
    }
    let rhs = &system.rhs;
    let psi_bounds = PsiBounds::of(system);
    let (bounded, load_scale) = (&psi_bounds.bounded, psi_bounds.load_scale);
    let bounds = Bounds::Uniform {
        at: bounded,
        sense: Sense::Lower,
        value: 0.0,
    };
    let initial: Vec<bool> = bounds.iter().map(|b| initial_active[b.dof()]).collect();
    let eliminated = system.constraints.eliminated();
    let matrix = system.matrix();
    let problem = NodalBounds {
        matrix,
        rhs,
        bounds,
        rotation: None,
        eliminated: &eliminated,
        negated_rows: true,
    };
    let options = ActiveSetOptions {
        max_iterations: MAX_ACTIVE_SET_ITERATIONS,
        multiplier_tolerance: 1e-12 * load_scale.max(1.0),
        violation: ViolationTolerance::SolutionScale(1e-13),
    };
    let result = primal_dual_active_set(&problem, solver, Some(&initial), &options)
        .map_err(|e| ModelError::from(e).context("SubStokes cavitation"))?;
    let mut active = vec![false; n];
    for (b, &a) in bounds.iter().zip(&result.active) {
        active[b.dof()] = a;
    }
    let mut u = result.x;
    if let Some(d) = u.iter().position(|v| !v.is_finite()) {
        return Err(ModelError::Failed(format!(
            "SubStokes cavitation: non-finite value {} at dof {d}",
            u[d]
        )));
    }
    // Residual of the last linear system (active ψ dofs eliminated at 0) and the multipliers,
    // from x as the solver returns it (hanging dofs at 0).
    let relative = relative_residual(matrix, rhs, &u, &eliminated, |i| {
        system.constraints.is_free(i) && !active[i]
    });
    if !relative.is_finite() || relative > MAX_RELATIVE_RESIDUAL {
        return Err(ModelError::Failed(format!(
            "SubStokes cavitation: relative residual {relative:e} of the last LDLᵀ solve \
             exceeds {MAX_RELATIVE_RESIDUAL:e}"
        )));
    }
    let lambda = psi_bounds.multipliers(system, &u);
    let psi_scale = (0..n)
        .filter(|&d| d % N_COMPONENTS == PSI)
        .fold(0.0f64, |m, d| m.max(u[d].abs()));
    for d in 0..n {
        if !bounded[d] || u[d] >= 0.0 {
            continue;
        }
        if u[d] < -1e-12 * psi_scale {
            return Err(ModelError::Failed(format!(
                "SubStokes cavitation: ψ = {} < 0 at an inactive dof {d} after convergence",
                u[d]
            )));
        }
        u[d] = 0.0;
    }
    system.constraints.distribute(&mut u);
    let complementarity =
        psi_bounds.check(&u, &lambda, MAX_COMPLEMENTARITY, "SubStokes cavitation", "")?;
    Ok(SubStokesCavitationSolution {
        solution: SubStokesSolution {
            dofs: system.dofs.clone(),
            u,
            relative_residual: relative,
        },
        lambda,
        active,
        iterations: result.iterations,
        complementarity,
        load_scale,
    })
}

/// Solve the assembled SubStokes `system` with `solver` (an LDLᵀ solver with the signs of
/// [`SubStokesProblem::signs`]), check the relative residual ‖Kx − f‖/‖f‖ on the free dofs
/// (neither fixed nor hanging; f = load minus the couplings to the eliminated values), and
/// distribute the hanging values. Returns the solution and that residual.
///
/// Errors: a failed factorisation (a zero pivot; [`DirectSolver`] factors without dynamic
/// regularisation, so no pivot is ever silently regularised) or a relative residual above
/// [`MAX_RELATIVE_RESIDUAL`].
pub fn solve_system(
    system: &System,
    solver: &mut DirectSolver,
) -> Result<(Vec<f64>, f64), ModelError> {
    let eliminated = system.constraints.eliminated();
    let matrix = system.matrix();
    let mut u = solver
        .solve(matrix, &system.rhs, &eliminated)
        .map_err(|e| ModelError::from(e).context("SubStokes"))?;
    // Residual of the reduced system: x holds the eliminated values (hanging dofs at 0), so
    // (Kx − f)_free is the residual of the free equations, and the reduced right-hand side is
    // f_free − (K x_eliminated)_free.
    let relative = relative_residual(matrix, &system.rhs, &u, &eliminated, |i| {
        system.constraints.is_free(i)
    });
    if !relative.is_finite() || relative > MAX_RELATIVE_RESIDUAL {
        return Err(ModelError::Failed(format!(
            "SubStokes: relative residual {relative:e} of the LDLᵀ solve exceeds \
             {MAX_RELATIVE_RESIDUAL:e}"
        )));
    }
    system.constraints.distribute(&mut u);
    Ok((u, relative))
}

/// Meshes and problems shared by the SubStokes tests of the model and of its estimator.
#[cfg(test)]
pub(crate) mod fixtures {
    use super::SubStokesProblem;
    use crate::mesh::Mesh;
    use crate::models::thin_film::example;

    /// [0, 1]² as one cell refined globally `times` times (8×8 for 3, 32×32 for 5).
    pub(crate) fn uniform(times: usize) -> Mesh {
        let mut mesh = Mesh::new([0.0, 1.0], [0.0, 1.0], 1, 1);
        for _ in 0..times {
            mesh.refine_global().unwrap();
        }
        mesh
    }

    /// The 8×8 grid with the cells whose centre lies in [0.25, 0.5]² ∪ the corner cell at the
    /// origin refined once more: hanging nodes inside and next to the boundary.
    pub(crate) fn with_hanging() -> Mesh {
        let mut mesh = uniform(3);
        let refine: Vec<bool> = mesh
            .active()
            .iter()
            .map(|&c| {
                let [x0, y0, x1, y1] = mesh.cell_box(c);
                let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
                ((0.25..0.5).contains(&cx) && (0.25..0.5).contains(&cy))
                    || (cx < 0.125 && cy < 0.125)
            })
            .collect();
        let coarsen = vec![false; refine.len()];
        mesh.refine_and_coarsen(&refine, &coarsen).unwrap();
        mesh
    }

    pub(crate) fn problem(eq: &str) -> SubStokesProblem {
        SubStokesProblem::new(example(eq).unwrap(), 200.0)
    }

    /// The examples that Chapter IV solves with cavitation (§IV.3.6): those with negative
    /// pressure without it.
    pub(crate) const CAVITATING: [&str; 6] = ["IV.8", "IV.11", "IV.16", "IV.17", "IV.19", "IV.20"];
}

#[cfg(test)]
mod tests {
    use super::fixtures::{problem, uniform, with_hanging, CAVITATING};
    use super::*;

    /// The point condition (I.56) at the corner: χ(0, 0) = g v̄ exactly; for the sliding plain
    /// gap (IV.9) that is the exact solution's value (0.5, 0), so nothing else changes; for the
    /// squeeze (IV.7) χ(0,0) = 0 is imposed and the solution changes (it did not vanish there).
    #[test]
    fn corner_point_condition() {
        let mesh = uniform(3);
        for (eq, changes) in [("IV.9", false), ("IV.7", true)] {
            let free = problem(eq).solve(&mesh).unwrap();
            let fixed = problem(eq)
                .with_point(Some([0.0, 0.0]))
                .solve(&mesh)
                .unwrap();
            let v = fixed.vertex_at([0.0, 0.0]).unwrap();
            let film = problem(eq).film.film_jets([0.0, 0.0]);
            let expected = [0, 1].map(|mu| film.g.v * film.vbar[mu].v);
            assert_eq!(fixed.chi(v), expected, "{eq}");
            let diff = free
                .u
                .iter()
                .zip(&fixed.u)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert_eq!(diff > 1e-9, changes, "{eq}: largest change {diff}");
        }
    }
    use crate::models::thin_film::EXAMPLES;

    fn centre_psi(p: &SubStokesProblem, mesh: &Mesh) -> f64 {
        let s = p.solve(mesh).unwrap();
        s.psi(s.vertex_at([0.5, 0.5]).unwrap())
    }

    #[test]
    fn dof_count_on_8x8_grid() {
        let mesh = uniform(3);
        let system = problem("IV.7").system(&mesh);
        assert_eq!(mesh.n_active(), 64);
        assert_eq!(system.dofs.vertices.len(), 81);
        assert_eq!(system.dofs.n_dofs(), 243);
        // ψ fixed at the 32 boundary vertices.
        let fixed = (0..243).filter(|&d| system.constraints.is_fixed(d)).count();
        assert_eq!(fixed, 32);
    }

    /// (IV.9): plain gap g = 0.1, upper wall velocity (10, 0, 0): γ = (600, 0), σ₃ = 0, and
    /// χ ≡ g v̄ = (0.5, 0), ψ ≡ 200 solve the discrete problem exactly for every δ_ε.
    #[test]
    fn couette_example_iv9_is_exact() {
        for (name, mesh) in [("8x8", uniform(3)), ("hanging", with_hanging())] {
            let hanging = !mesh_hanging_free(&mesh);
            assert_eq!(hanging, name == "hanging");
            for delta in [DEFAULT_DELTA_EPS, 1.0] {
                let s = problem("IV.9").with_delta_eps(delta).solve(&mesh).unwrap();
                for v in 0..s.dofs.vertices.len() as u32 {
                    let [c1, c2] = s.chi(v);
                    assert!(
                        (c1 - 0.5).abs() < 1e-9
                            && c2.abs() < 1e-9
                            && (s.psi(v) - 200.0).abs() < 1e-9,
                        "{name}, δ_ε = {delta}: vertex {v} at {:?}: χ = ({c1}, {c2}), ψ = {}",
                        s.dofs.vertices.coords[v as usize],
                        s.psi(v)
                    );
                }
            }
        }
    }

    fn mesh_hanging_free(mesh: &Mesh) -> bool {
        DofMap::new(mesh, 1).vertices.hanging.is_empty()
    }

    #[test]
    fn assembled_matrix_is_symmetric() {
        for eq in ["IV.12", "IV.20"] {
            for mesh in [uniform(3), with_hanging()] {
                let p = problem(eq);
                let mut system = p.system(&mesh);
                p.assemble(&mesh, &mut system);
                let m = system.matrix();
                let scale = m.values.iter().fold(0.0f64, |s, v| s.max(v.abs()));
                let mut off_diagonal_blocks = 0;
                for j in 0..m.n() {
                    for p in m.col_ptr[j]..m.col_ptr[j + 1] {
                        let i = m.row_idx[p] as usize;
                        let t = m.position(j, i).expect("symmetric pattern");
                        assert!(
                            (m.values[p] - m.values[t]).abs() <= 1e-12 * scale,
                            "{eq}: K[{i}][{j}] = {} vs K[{j}][{i}] = {}",
                            m.values[p],
                            m.values[t]
                        );
                        if (i % 3 == PSI) != (j % 3 == PSI) && m.values[p] != 0.0 {
                            off_diagonal_blocks += 1;
                        }
                    }
                }
                // The coupling blocks −B, −Bᵀ are present.
                assert!(off_diagonal_blocks > 0);
                // Signs of the diagonal: A > 0 on χ, −C < 0 on interior ψ.
                let d = m.diagonal();
                for (k, &v) in d.iter().enumerate() {
                    if !system.constraints.is_free(k) {
                        continue;
                    }
                    if k % 3 == PSI {
                        assert!(v < 0.0, "{eq}: ψ diagonal {v} at dof {k}");
                    } else {
                        assert!(v > 0.0, "{eq}: χ diagonal {v} at dof {k}");
                    }
                }
            }
        }
    }

    /// (IV.7)/(IV.8): same plain gap, upper wall velocity (0, 0, ∓10): σ₃ = ±10, γ = 0, so
    /// (χ, ψ − 200) changes sign.
    #[test]
    fn squeeze_pair_iv7_iv8_is_antisymmetric() {
        let mesh = uniform(3);
        let a = problem("IV.7").solve(&mesh).unwrap();
        let b = problem("IV.8").solve(&mesh).unwrap();
        let mut largest = 0.0f64;
        for v in 0..a.dofs.vertices.len() as u32 {
            let (ca, cb) = (a.chi(v), b.chi(v));
            for mu in 0..2 {
                assert!(
                    (ca[mu] + cb[mu]).abs() < 1e-9,
                    "χ_{mu} at {v}: {} vs {}",
                    ca[mu],
                    cb[mu]
                );
            }
            let (pa, pb) = (a.psi(v) - 200.0, b.psi(v) - 200.0);
            assert!((pa + pb).abs() < 1e-9, "ψ − 200 at {v}: {pa} vs {pb}");
            largest = largest.max(pa.abs());
        }
        // Not trivially zero: the squeeze raises the pressure in the interior.
        assert!(largest > 1.0, "ψ − 200 is {largest} at most");
        let centre = a.vertex_at([0.5, 0.5]).unwrap();
        assert!(a.psi(centre) > 200.0 && b.psi(centre) < 200.0);
    }

    /// Every example (IV.7)–(IV.20) solves with relative residual below 1e-10 and finite values.
    #[test]
    fn all_examples_solve_with_small_residual() {
        let mesh = uniform(3);
        for eq in EXAMPLES {
            let s = problem(eq).solve(&mesh).unwrap();
            assert!(
                s.relative_residual < MAX_RELATIVE_RESIDUAL,
                "{eq}: residual {:e}",
                s.relative_residual
            );
            assert!(s.u.iter().all(|v| v.is_finite()), "{eq}: non-finite value");
            println!("{eq}: relative residual {:e}", s.relative_residual);
        }
    }

    /// The residual measure of [`solve_system`] is near rounding for the solve (natural
    /// ordering here) and large for a perturbed solution, so the 1e-10 check can fail.
    #[test]
    fn residual_measure_detects_a_wrong_solution() {
        let mesh = uniform(3);
        let p = problem("IV.9");
        let mut system = p.system(&mesh);
        p.assemble(&mesh, &mut system);
        let mut solver = DirectSolver::ldlt(SubStokesProblem::signs(&system.dofs));
        let (u, r) = solve_system(&system, &mut solver).unwrap();
        assert!(r < 1e-12, "residual {r:e}");
        // A perturbed solution has a large residual by the same measure.
        let eliminated = system.constraints.eliminated();
        let mut w = u.clone();
        w[system.dofs.dof(40, 0)] += 1e-3;
        let m = system.matrix();
        let kw = m.multiply(&w);
        let mut lift = vec![0.0; w.len()];
        for &(d, v) in &eliminated {
            lift[d] = v;
        }
        let kl = m.multiply(&lift);
        let (mut r2, mut f2) = (0.0, 0.0);
        for i in (0..w.len()).filter(|&i| system.constraints.is_free(i)) {
            r2 += (kw[i] - system.rhs[i]).powi(2);
            f2 += (system.rhs[i] - kl[i]).powi(2);
        }
        assert!((r2 / f2).sqrt() > 1e-8);
    }

    fn min_psi(s: &SubStokesSolution) -> f64 {
        (0..s.dofs.vertices.len() as u32)
            .map(|v| s.psi(v))
            .fold(f64::INFINITY, f64::min)
    }

    /// On 32×32 with δ_ε = 1.10e-3 the solution without cavitation has a negative vertex value
    /// of ψ exactly for the six examples Chapter IV solves with cavitation (minima printed; an
    /// independent check found −690, −388, −900, −28, −649, −191 for them and ≥ 163 for the
    /// others).
    #[test]
    fn negative_pressure_exactly_for_the_cavitation_examples() {
        let mesh = uniform(5);
        for eq in EXAMPLES {
            let m = min_psi(&problem(eq).solve(&mesh).unwrap());
            println!("{eq}: min ψ = {m:.3} (32x32, no cavitation)");
            assert_eq!(m < 0.0, CAVITATING.contains(&eq), "{eq}: min ψ = {m}");
        }
    }

    /// The cavitation form differs from the plain one by the grad-div block in A and by
    /// γ_c − γ in F only; B, C and G are the same, and the matrix is symmetric.
    #[test]
    fn cavitation_form_adds_grad_div_and_gamma_c() {
        let mesh = with_hanging();
        for eq in ["IV.11", "IV.20"] {
            let p = problem(eq);
            let mut plain = p.system(&mesh);
            p.assemble(&mesh, &mut plain);
            let mut cav = p.system(&mesh);
            p.assemble_cavitation(&mesh, &mut cav);
            let (mp, mc) = (plain.matrix(), cav.matrix());
            let scale = mc.values.iter().fold(0.0f64, |s, v| s.max(v.abs()));
            let mut changed = 0;
            for j in 0..mc.n() {
                for q in mc.col_ptr[j]..mc.col_ptr[j + 1] {
                    let i = mc.row_idx[q] as usize;
                    let t = mc.position(j, i).unwrap();
                    assert!((mc.values[q] - mc.values[t]).abs() <= 1e-12 * scale);
                    let diff = mc.values[q] - mp.values[q];
                    if i % 3 == PSI || j % 3 == PSI {
                        assert_eq!(diff, 0.0, "{eq}: B or C changed at ({i}, {j})");
                    } else if diff != 0.0 {
                        changed += 1;
                    }
                }
            }
            assert!(changed > 0, "{eq}: no grad-div entries");
            let mut load_changed = false;
            for d in 0..plain.rhs.len() {
                if d % 3 == PSI {
                    assert_eq!(plain.rhs[d], cav.rhs[d], "{eq}: G changed at {d}");
                } else {
                    load_changed |= plain.rhs[d] != cav.rhs[d];
                }
            }
            // γ_c ≠ γ for the linear and hill gaps (the ∂_μ∂_ν g and δv₃ ∂g/g terms).
            assert!(load_changed, "{eq}: γ_c = γ");
        }
    }

    /// An example without negative pressure ((IV.7), squeeze upward pressure) solved with
    /// cavitation: the active set stays empty and the solution is that of the unconstrained
    /// cavitation system (the LDLᵀ solve of the same assembly), with multipliers of rounding
    /// size.
    #[test]
    fn empty_active_set_solves_the_unconstrained_cavitation_system() {
        for mesh in [uniform(3), with_hanging()] {
            let p = problem("IV.7");
            let cav = p.solve_with_cavitation(&mesh).unwrap();
            assert!(cav.active.iter().all(|&a| !a));
            assert_eq!(cav.iterations, 1);
            let mut system = p.system(&mesh);
            p.assemble_cavitation(&mesh, &mut system);
            let mut solver = DirectSolver::ldlt(SubStokesProblem::signs(&system.dofs));
            let (u, r) = solve_system(&system, &mut solver).unwrap();
            assert!(r < MAX_RELATIVE_RESIDUAL);
            let scale = u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for (a, b) in cav.solution.u.iter().zip(&u) {
                assert!((a - b).abs() <= 1e-10 * scale, "{a} vs {b}");
            }
            let lambda = cav.lambda.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            assert!(lambda <= 1e-10 * cav.load_scale.max(1.0), "λ = {lambda:e}");
            // And it is not the plain solution (the grad-div term acts).
            let plain = p.solve(&mesh).unwrap();
            let diff = plain
                .u
                .iter()
                .zip(&u)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(diff > 1e-6, "plain and cavitation forms agree to {diff:e}");
        }
    }

    /// The six cavitation examples on 8×8 and 32×32 (including the hard case (IV.20)) and on the
    /// mesh with hanging nodes: converged, finite, ψ ≥ 0 at every vertex, λ ≥ 0 at the active
    /// dofs, λ of rounding size off them, complementarity within tolerance, a non-empty active
    /// set, and the unconstrained residual of the active rows is the multiplier.
    #[test]
    fn cavitation_examples_satisfy_the_complementarity_conditions() {
        for (name, mesh) in [
            ("8x8", uniform(3)),
            ("32x32", uniform(5)),
            ("hanging", with_hanging()),
        ] {
            for eq in CAVITATING {
                let p = problem(eq);
                let c = p
                    .solve_with_cavitation(&mesh)
                    .unwrap_or_else(|e| panic!("{eq} {name}: {e}"));
                let s = &c.solution;
                assert!(s.u.iter().all(|v| v.is_finite()), "{eq} {name}");
                assert!(c.lambda.iter().all(|v| v.is_finite()), "{eq} {name}");
                assert!(s.relative_residual <= MAX_RELATIVE_RESIDUAL);
                let tol = MAX_COMPLEMENTARITY * c.load_scale.max(1.0);
                assert!(
                    c.complementarity <= tol,
                    "{eq} {name}: {}",
                    c.complementarity
                );
                // The LCP has a non-empty active set exactly when the unconstrained solution of
                // the cavitation form has a negative ψ (S = BᵀA⁻¹B + C is positive definite, so
                // a non-negative unconstrained solution is the solution). Not so for (IV.20) on
                // 8×8 only.
                let n_active = c.active.iter().filter(|&&a| a).count();
                let mut system = p.system(&mesh);
                p.assemble_cavitation(&mesh, &mut system);
                let mut solver = DirectSolver::ldlt(SubStokesProblem::signs(&system.dofs));
                let (free, _) = solve_system(&system, &mut solver).unwrap();
                let negative = (0..free.len()).any(|d| d % 3 == PSI && free[d] < 0.0);
                assert_eq!(n_active > 0, negative, "{eq} {name}: {n_active} active");
                assert_eq!(negative, (eq, name) != ("IV.20", "8x8"), "{eq} {name}");
                for v in 0..s.dofs.vertices.len() as u32 {
                    let d = s.dofs.dof(v, PSI);
                    assert!(s.psi(v) >= 0.0, "{eq} {name}: ψ = {} at {v}", s.psi(v));
                    if c.active[d] {
                        assert_eq!(s.psi(v), 0.0);
                        assert!(c.lambda[d] >= -1e-12 * c.load_scale.max(1.0));
                    } else {
                        assert!(c.lambda[d].abs() <= 1e-10 * c.load_scale.max(1.0));
                    }
                }
                let largest = c.lambda.iter().fold(0.0f64, |m, v| m.max(*v));
                println!(
                    "{eq} {name}: {} iterations, {n_active} active, complementarity {:e}, \
                     residual {:e}, max λ {largest:.4e}, ‖G‖∞ {:.4e}, cavitated: {:.1} % of \
                     the vertices, {:.1} % of the area",
                    c.iterations,
                    c.complementarity,
                    s.relative_residual,
                    c.load_scale,
                    100.0 * c.cavitated_vertex_fraction(),
                    100.0 * c.cavitated_area_fraction(&mesh),
                );
            }
        }
    }

    /// (IV.8) on 8×8: the unconstrained solve has negative ψ, the solution with cavitation has
    /// positive multipliers, and starting from every free ψ dof active converges to the same
    /// active set and solution as the cold start. An initial set of the wrong length is an error.
    #[test]
    fn warm_start_from_all_active_converges_to_the_same_solution() {
        let mesh = uniform(3);
        let p = problem("IV.8");
        let cold = p.solve_with_cavitation(&mesh).unwrap();
        let mut system = p.system(&mesh);
        p.assemble_cavitation(&mesh, &mut system);
        let mut solver = DirectSolver::ldlt(SubStokesProblem::signs(&system.dofs));
        let all = vec![true; system.dofs.n_dofs()];
        let warm = solve_cavitation(&system, &mut solver, &all).unwrap();
        assert_eq!(warm.active, cold.active);
        for (a, b) in warm.solution.u.iter().zip(&cold.solution.u) {
            assert!((a - b).abs() <= 1e-9 * (1.0 + b.abs()), "{a} vs {b}");
        }
        let (mut unconstrained, _) = solve_system(&system, &mut solver).unwrap();
        system.constraints.distribute(&mut unconstrained);
        let negative = (0..system.dofs.n_dofs())
            .filter(|&d| d % 3 == PSI && unconstrained[d] < 0.0)
            .count();
        assert!(negative > 0);
        assert!(cold.lambda.iter().any(|&l| l > 1e-6));
        // The wrong length is an error.
        let err = solve_cavitation(&system, &mut solver, &all[1..]).unwrap_err();
        assert!(err.to_string().contains("initial active set"), "{err}");
    }

    /// ψ(½, ½) of (IV.7) on 8×8 and 32×32 with δ_ε = 1.10e-3 and δ_ε = 1 (printed; run with
    /// `--nocapture`). Asserted: the squeeze raises the centre pressure above ψ₀, and with
    /// δ_ε = 1 the values agree with an independent reference computation (223 on 8×8,
    /// 466 on 32×32) to the digits quoted (±1).
    #[test]
    fn centre_pressure_of_iv7() {
        for delta in [DEFAULT_DELTA_EPS, 1.0] {
            for (times, quoted) in [(3, 223.0), (5, 466.0)] {
                let psi = centre_psi(&problem("IV.7").with_delta_eps(delta), &uniform(times));
                let n = 1 << times;
                println!("IV.7, δ_ε = {delta}, {n}x{n}: ψ(½,½) = {psi}");
                assert!(psi > 200.0 && psi.is_finite());
                if delta == 1.0 {
                    assert!(
                        (psi - quoted).abs() < 1.0,
                        "{n}x{n}: ψ(½,½) = {psi}, quoted {quoted}"
                    );
                }
            }
        }
    }
}
