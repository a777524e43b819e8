//! The model-adaptive fluid of §IV.3.4: the Reynolds model (I.77) on all of Ω₂ and the
//! SubStokes model (I.58) on the cells flagged SubStokes, coupled one way (docs/models.md §11),
//! and the per-cell model indicator of Theorem III.6 that decides which cells are flagged.
//!
//! **The coupled solve** ([`Coupling::solve`]; the two `calculate` lines of Algorithms
//! III.1–III.3, "u ← u_c on 𝕋; u ← u_a on 𝕋_a"):
//! 1. the Reynolds problem (I.79) on the whole mesh, ψ = ψ₀ on ∂Ω₂ ([`ReynoldsProblem`],
//!    Q₁, Cholesky): ψ^R;
//! 2. the SubStokes problem (I.58) on Ω^S, the union of the SubStokes cells, discretised as in
//!    [`crate::models::substokes`] (Q₁/Q₁, stabilisation δ_ε h_Q², LDLᵀ), with
//!    * ψ = ψ₀ at the vertices on ∂Ω₂ and ψ = ψ^R at the vertices on the interface
//!      Γ_I = ∂Ω^S ∩ Ω₂ (Dirichlet data for ψ, the only coupling: one way, the Reynolds solution
//!      does not see the SubStokes one);
//!    * the natural condition ∂_nχ = X₀ = 0 on all of ∂Ω^S. Since (I.58) integrates the pressure
//!      term by parts, the momentum load carries −⟨ψ₀ n, ξ⟩ on ∂Ω₂ (as in the plain SubStokes
//!      solve) and −⟨ψ^R n, ξ⟩ on Γ_I ([`Coupling::assemble_substokes`]); without the second
//!      term the natural condition would be ∂_nχ = ψ^R n instead.
//!
//!    No Neumann data for χ from (I.86) is imposed (optional in docs/models.md §11), and no
//!    point condition (I.56) (as in the plain SubStokes solve: a₂ is coercive).
//!
//! The coupled pressure is ψ_h on the SubStokes cells and ψ^R on the Reynolds cells
//! ([`CoupledSolution::pressure_at`]). It is continuous: along every interface face ψ_h and ψ^R
//! are linear between the same end values (see the hanging cases below).
//!
//! **Dofs of the SubStokes region** ([`Region`]): (χ₁, χ₂, ψ) at the vertices of the SubStokes
//! cells only, hanging and Dirichlet vertices included (the deal.II count, as in the plain
//! SubStokes tables). Which vertices hang is decided inside the region, i.e. by the SubStokes
//! cells alone. For a vertex M in the middle of the face between a coarse cell Q and its two
//! finer neighbours Q₁, Q₂ (M hangs in the Reynolds mesh in every case):
//! * Q, Q₁, Q₂ all SubStokes: M hangs (all three components), as in the plain solve;
//! * Q Reynolds, Q₁ or Q₂ SubStokes: M is not hanging in the region — no SubStokes cell has it
//!   inside an edge, it is a regular vertex on Γ_I: χ free, ψ = ψ^R(M), which is the mean of
//!   ψ^R at the ends of the coarse edge (M hangs in the Reynolds solution);
//! * Q SubStokes, Q₁ and Q₂ Reynolds: M is not a SubStokes vertex at all; ψ^R is linear along
//!   Q's edge (M hangs in the Reynolds solution), so the Dirichlet data at the two ends of the
//!   edge reproduce ψ^R on the whole edge;
//! * Q SubStokes, one of Q₁, Q₂ SubStokes and the other Reynolds: M must hang (conformity
//!   between Q and the SubStokes fine cell) and lies on Γ_I (a corner of the Reynolds fine
//!   cell). A hanging value cannot be fixed, so ψ_h(M) = ψ^R(M) is imposed by fixing ψ at both
//!   ends of the coarse edge (recursively, where an end hangs itself) at ψ^R: then ψ_h = ψ^R on
//!   the whole edge, as on every other interface face. One end is a corner of the Reynolds
//!   cell anyway; the other may be a vertex with SubStokes cells only around it, where ψ = ψ^R
//!   is then an extra condition of this reading ([`Region::extra_fixed`] counts them).
//!
//! **Model indicator** ([`model_indicator`]), the velocity bound of Theorem III.6 on one cell
//! Q (docs/estimators.md §4.2, the reading chosen there):
//! ε^m(Q) = V(Q) = (‖g²‖_{∞,Q}/12)·P(Q) + ‖g²Δ(g³)‖_Q + ‖g⁵‖_Q + 6‖g⁴∇g‖_Q, with the pressure
//! bound restricted to Q
//! P(Q) = (1/g_min)(‖∂_μ(gΔ(g³)) + 24g∂_μg‖_Q + ‖gΔ(g³)‖_Q + 2‖∂_μ(g∂_ν(g³))‖_Q
//!        + 2‖g∂_ν(g³)‖_Q + ‖∂_μ(g⁴)‖_Q + ‖g⁴‖_Q),
//! C = C_vR = 1, g_min = inf_{Ω₂} g (global, [`crate::models::thin_film::Gap::min_on_unit_square`]:
//! Ω₂ = [0, 1]² in §IV.3), ‖g²‖_{∞,Q} exact ([`crate::models::thin_film::Gap::range_on_box`]),
//! vector and tensor fields in the Euclidean/Frobenius norm pointwise, L²(Q) norms by 4×4 Gauss
//! points on sub-cells of side ≤ 1/32 ([`model_indicator`]), the derivatives of g analytic (the
//! third-order [`Jet`] of the gap). P(Q) alone (the other reading of docs/estimators.md §4.2)
//! does not single out the wide gap, as §IV.3.4 says the refinement does: on 8×8 it is 6.610 in the cells next to the
//! widest gap (x₁ = 1/8, 5/8) and 6.692 next to the narrowest (3/8, 7/8); the velocity bound is
//! 0.01789 and 0.00582 there (test `theorem_iii6_bounds_on_8x8`).

use crate::models::ModelError;
use rayon::prelude::*;

use crate::fe::cell_values::evaluate_at;
use crate::fe::{DofMap, Hanging, LocalDofs, System, Vertices};
use crate::linalg::DirectSolver;
use crate::mesh::{bilinear, face_segments, CellId, Mesh, Neighbor, VertexKey, FACES};
use crate::models::reynolds::{CellData, Load, ReynoldsProblem};
use crate::models::substokes::{
    self, solve_system, SubStokesProblem, SubStokesSolution, N_COMPONENTS, PSI,
};
use crate::models::thin_film::{Jet, ThinFilm};

/// The two bounds of Theorem III.6 on one cell (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModelIndicator {
    /// P(Q): the bound of ‖ψ − ψ^R‖_R restricted to Q.
    pub pressure: f64,
    /// V(Q): the bound of ‖χ − χ^R‖_{L²(Q)}, the model indicator ε^m(Q) of §IV.3.4.
    pub velocity: f64,
}

/// Largest side of the sub-cells on which [`model_indicator`] applies the 4×4 Gauss rule.
pub const INDICATOR_SUBCELL: f64 = 1.0 / 32.0;

/// The bounds of Theorem III.6 on the active cell `c` for the gap of `film` (module docs),
/// with the global minimum `g_min` of the gap. The L² norms are integrated by 4×4 Gauss points
/// on m × m sub-cells of side ≤ [`INDICATOR_SUBCELL`] (m = 4 on the 8×8 grid, 1 from 32×32 on):
/// the terms contain products of up to five factors sin/cos(4πx₁) for the wave gap, and the
/// plain 4×4 rule on an 8×8 cell is 0.27 % off (P = 6.628 instead of 6.610); with the
/// sub-cells the error is below 1e-6 (test against 8×8 sub-cells).
pub fn model_indicator(film: &ThinFilm, g_min: f64, mesh: &Mesh, c: CellId) -> ModelIndicator {
    let b = mesh.cell_box(c);
    let [x0, y0, x1, y1] = b;
    let m = ((x1 - x0).max(y1 - y0) / INDICATOR_SUBCELL).ceil().max(1.0) as usize;
    let (hx, hy) = ((x1 - x0) / m as f64, (y1 - y0) / m as f64);
    let rule = crate::fe::quadrature::square(4);
    let points = (0..m * m).flat_map(|s| {
        let (i, j) = ((s % m) as f64, (s / m) as f64);
        rule.iter()
            .map(move |&(xi, eta, w)| ([x0 + (i + xi) * hx, y0 + (j + eta) * hy], w * hx * hy))
    });
    let g_max = film.gap.range_on_box(b).1;
    bounds(film, g_min, g_max * g_max, points)
}

/// P and V of Theorem III.6 with the L² norms integrated over the quadrature `points`
/// (position, weight), ‖g²‖_∞ = `g2_max`.
fn bounds(
    film: &ThinFilm,
    g_min: f64,
    g2_max: f64,
    points: impl IntoIterator<Item = ([f64; 2], f64)>,
) -> ModelIndicator {
    // Squared L² norms of the terms, in the order of the theorem.
    let mut p2 = [0.0f64; 6];
    let mut v2 = [0.0f64; 3];
    for (x, jw) in points {
        let g = film.gap.jet(x);
        let g3 = g * g * g;
        let g4 = g3 * g;
        let lap_g3 = g3.laplacian();
        // gΔ(g³): value and gradient known.
        let g_lap_g3 = g * lap_g3;
        let grad_g = g.d;
        let t1 = [0, 1].map(|mu| g_lap_g3.d[mu] + 24.0 * g.v * grad_g[mu]);
        // g∂_ν(g³) as jets (value and gradient known); its gradient is ∂_μ(g∂_ν(g³)).
        let g_d_g3: [Jet; 2] = [0, 1].map(|nu| g * g3.partial(nu));
        let t3: f64 = g_d_g3
            .iter()
            .map(|t| t.d[0] * t.d[0] + t.d[1] * t.d[1])
            .sum();
        let terms = [
            t1[0] * t1[0] + t1[1] * t1[1],
            g_lap_g3.v * g_lap_g3.v,
            t3,
            g_d_g3[0].v.powi(2) + g_d_g3[1].v.powi(2),
            g4.d[0].powi(2) + g4.d[1].powi(2),
            g4.v * g4.v,
        ];
        for (s, t) in p2.iter_mut().zip(terms) {
            *s += t * jw;
        }
        let g2 = g.v * g.v;
        let velocity = [
            (g2 * lap_g3.v).powi(2),
            (g4.v * g.v).powi(2),
            g4.v * g4.v * (grad_g[0] * grad_g[0] + grad_g[1] * grad_g[1]),
        ];
        for (s, t) in v2.iter_mut().zip(velocity) {
            *s += t * jw;
        }
    }
    let [a, b, c, d, e, f] = p2.map(f64::sqrt);
    let pressure = (a + b + 2.0 * c + 2.0 * d + e + f) / g_min;
    let [v1, v2, v3] = v2.map(f64::sqrt);
    let velocity = g2_max / 12.0 * pressure + v1 + v2 + 6.0 * v3;
    ModelIndicator { pressure, velocity }
}

/// [`model_indicator`] on every active cell (in parallel), g_min the minimum of the gap over
/// [0, 1]² (Ω₂ of §IV.3).
pub fn model_indicators(film: &ThinFilm, mesh: &Mesh) -> Vec<ModelIndicator> {
    let g_min = film.gap.min_on_unit_square();
    mesh.active()
        .par_iter()
        .map(|&c| model_indicator(film, g_min, mesh, c))
        .collect()
}

/// The SubStokes region Ω^S of a mesh: its cells, its vertices (numbered among themselves, in
/// the order of the mesh's vertices), its hanging vertices and its interface (module docs).
#[derive(Clone, Debug)]
pub struct Region {
    /// Per active cell: SubStokes.
    pub flags: Vec<bool>,
    /// Active indices of the SubStokes cells, in active order (the cell order of [`Self::dofs`]).
    pub cells: Vec<usize>,
    /// Per active cell: its index in [`Self::cells`].
    pub cell_index: Vec<Option<u32>>,
    /// Vertices, cells and hanging vertices of the region, 3 components per vertex.
    pub dofs: DofMap,
    /// Per region vertex: the vertex of the whole mesh (the Reynolds numbering).
    pub mesh_vertex: Vec<u32>,
    /// Region vertices on the interface Γ_I = ∂Ω^S ∩ Ω₂ (corners of a Reynolds cell or inside
    /// one of its edges), sorted.
    pub interface: Vec<u32>,
    /// Region vertices whose ψ is fixed at ψ^R although they are not on Γ_I: the ends of a
    /// coarse SubStokes edge whose hanging midpoint lies on Γ_I (module docs), sorted.
    pub extra_fixed: Vec<u32>,
    /// Region vertices whose ψ is fixed at ψ^R: the interface and the extra ones, without
    /// hanging vertices (their ψ follows from these), sorted.
    pub psi_fixed: Vec<u32>,
}

/// The vertex in the middle of face `f`'s two corners `a`, `b` of a cell.
fn midpoint(corners: &[VertexKey; 4], a: usize, b: usize) -> VertexKey {
    (
        (corners[a].0 + corners[b].0) / 2,
        (corners[a].1 + corners[b].1) / 2,
    )
}

impl Region {
    /// The region of the cells flagged in `flags` (indexed like `mesh.active()`) on `mesh`,
    /// whose vertices are `vertices` (those of the Reynolds dofs).
    pub fn new(mesh: &Mesh, vertices: &Vertices, flags: &[bool]) -> Region {
        assert_eq!(
            flags.len(),
            mesh.n_active(),
            "one model flag per active cell"
        );
        let active = mesh.active();
        let cells: Vec<usize> = (0..flags.len()).filter(|&k| flags[k]).collect();
        let mut cell_index = vec![None; flags.len()];
        for (j, &k) in cells.iter().enumerate() {
            cell_index[k] = Some(j as u32);
        }
        // Region vertices: corners of SubStokes cells, in mesh-vertex order.
        let n_mesh = vertices.len();
        let mut in_region = vec![false; n_mesh];
        for &k in &cells {
            for v in vertices.cell_vertices[k] {
                in_region[v as usize] = true;
            }
        }
        let mesh_vertex: Vec<u32> = (0..n_mesh as u32)
            .filter(|&v| in_region[v as usize])
            .collect();
        let mut local = vec![u32::MAX; n_mesh];
        for (i, &v) in mesh_vertex.iter().enumerate() {
            local[v as usize] = i as u32;
        }
        let find = |key: VertexKey| vertices.find(key).expect("a face midpoint is a vertex");
        // Hanging inside the region: the midpoint of a SubStokes cell's face towards two finer
        // cells, one of them SubStokes.
        let mut hanging = Vec::new();
        // Interface: corners of Reynolds cells, and midpoints of their faces towards finer
        // cells, that are region vertices.
        let mut on_interface = vec![false; mesh_vertex.len()];
        for (k, &c) in active.iter().enumerate() {
            let corners = mesh.corner_keys(c);
            if !flags[k] {
                for v in vertices.cell_vertices[k] {
                    if in_region[v as usize] {
                        on_interface[local[v as usize] as usize] = true;
                    }
                }
            }
            for f in FACES {
                let Neighbor::Finer([n0, n1]) = mesh.neighbor(c, f) else {
                    continue;
                };
                let fine = [n0, n1].map(|n| flags[mesh.active_index(n)]);
                if !(fine[0] || fine[1]) {
                    continue;
                }
                let [a, b] = f.vertices();
                let m = local[find(midpoint(&corners, a, b)) as usize];
                if flags[k] {
                    let ends = [a, b].map(|i| local[vertices.cell_vertices[k][i] as usize]);
                    hanging.push(Hanging {
                        vertex: m,
                        parents: ends,
                    });
                } else {
                    on_interface[m as usize] = true;
                }
            }
        }
        hanging.sort_by_key(|h| h.vertex);
        let mut is_hanging = vec![false; mesh_vertex.len()];
        for h in &hanging {
            is_hanging[h.vertex as usize] = true;
        }
        let mut region_vertices = vertices.clone();
        region_vertices.keys = mesh_vertex
            .iter()
            .map(|&v| vertices.keys[v as usize])
            .collect();
        region_vertices.coords = mesh_vertex
            .iter()
            .map(|&v| vertices.coords[v as usize])
            .collect();
        region_vertices.owner = mesh_vertex
            .iter()
            .map(|&v| vertices.owner[v as usize])
            .collect();
        region_vertices.cell_vertices = cells
            .iter()
            .map(|&k| vertices.cell_vertices[k].map(|v| local[v as usize]))
            .collect();
        region_vertices.hanging = hanging;
        region_vertices.is_hanging = is_hanging;
        let interface: Vec<u32> = (0..mesh_vertex.len() as u32)
            .filter(|&v| on_interface[v as usize])
            .collect();
        // ψ fixed at ψ^R: every interface vertex, a hanging one through its parents.
        let mut fixed = vec![false; mesh_vertex.len()];
        let parents_of = |v: u32| {
            let h = &region_vertices.hanging;
            h.binary_search_by_key(&v, |h| h.vertex)
                .ok()
                .map(|i| h[i].parents)
        };
        let mut stack = interface.clone();
        while let Some(v) = stack.pop() {
            match parents_of(v) {
                Some(p) => stack.extend(p),
                None => fixed[v as usize] = true,
            }
        }
        let psi_fixed: Vec<u32> = (0..mesh_vertex.len() as u32)
            .filter(|&v| fixed[v as usize])
            .collect();
        let extra_fixed = psi_fixed
            .iter()
            .copied()
            .filter(|&v| !on_interface[v as usize])
            .collect();
        Region {
            flags: flags.to_vec(),
            cells,
            cell_index,
            dofs: DofMap {
                vertices: region_vertices,
                n_components: N_COMPONENTS,
            },
            mesh_vertex,
            interface,
            extra_fixed,
            psi_fixed,
        }
    }

    /// Number of SubStokes cells.
    pub fn n_cells(&self) -> usize {
        self.cells.len()
    }

    /// Whether the region has no cell.
    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }

    /// The SubStokes dofs (3 per region vertex, hanging and Dirichlet ones included).
    pub fn n_dofs(&self) -> usize {
        self.dofs.n_dofs()
    }

    /// The discrete system of the region: its dofs, the hanging-node constraints inside it and
    /// the sparsity pattern (no value fixed yet).
    pub fn system(&self) -> System {
        System::of_dofs(self.dofs.clone())
    }

    /// Values (χ₁, χ₂, ψ) per region vertex, placed at the vertices of the whole mesh
    /// (`n_mesh_vertices` of them; 0 off the region): the layout the estimator of Theorem III.23
    /// reads with the mesh's own cell numbering (`estimators::substokes::cell_parts_in_region`).
    pub fn on_mesh_vertices(&self, u: &[f64], n_mesh_vertices: usize) -> Vec<f64> {
        let mut out = vec![0.0; n_mesh_vertices * N_COMPONENTS];
        for (i, &v) in self.mesh_vertex.iter().enumerate() {
            for comp in 0..N_COMPONENTS {
                out[v as usize * N_COMPONENTS + comp] = u[i * N_COMPONENTS + comp];
            }
        }
        out
    }
}

/// The two models of one film (§IV.3.4): the Reynolds problem and the SubStokes problem with
/// the same film data and boundary pressure ψ₀.
#[derive(Clone, Debug, PartialEq)]
pub struct Coupling {
    pub reynolds: ReynoldsProblem,
    pub substokes: SubStokesProblem,
}

/// The Reynolds solve of one mesh: dofs, ψ^R and the cell data the estimator reuses.
pub struct ReynoldsSolution {
    pub dofs: DofMap,
    pub psi: Vec<f64>,
    pub data: CellData,
}

/// The SubStokes part of a coupled solve: (χ₁, χ₂, ψ) per vertex of the region.
pub struct RegionSolution {
    pub u: Vec<f64>,
    /// Relative residual of the LDLᵀ solve ([`solve_system`]).
    pub relative_residual: f64,
}

/// A coupled solve on one mesh ([`Coupling::solve`]).
pub struct CoupledSolution {
    pub reynolds: ReynoldsSolution,
    pub region: Region,
    /// None when the region is empty.
    pub substokes: Option<RegionSolution>,
}

impl Coupling {
    /// Reynolds (I.79) and SubStokes (I.58) for `film` with ψ = `boundary_pressure` on ∂Ω₂:
    /// the Reynolds problem in its default form, the SubStokes problem with the default δ_ε
    /// ([`substokes::DEFAULT_DELTA_EPS`]).
    pub fn new(film: ThinFilm, boundary_pressure: f64) -> Coupling {
        Coupling {
            reynolds: ReynoldsProblem {
                film: film.clone(),
                boundary_pressure,
                cavitation_source: Default::default(),
                form: Default::default(),
                exact: None,
            },
            substokes: SubStokesProblem::new(film, boundary_pressure),
        }
    }

    /// The Reynolds system of `mesh` with ψ = ψ₀ on ∂Ω₂.
    pub fn reynolds_system(&self, mesh: &Mesh) -> System {
        let mut system = System::new(mesh, 1);
        self.reynolds.constrain(&mut system);
        system
    }

    /// Assemble the Reynolds system (load l_R); returns the cell data.
    pub fn assemble_reynolds(&self, mesh: &Mesh, system: &mut System) -> CellData {
        let data = self.reynolds.cell_data(mesh, Load::Reynolds);
        self.reynolds.assemble(mesh, system, &data);
        data
    }

    /// Solve the assembled Reynolds system (Cholesky in the nested-dissection order).
    pub fn solve_reynolds(system: &System) -> Result<Vec<f64>, ModelError> {
        let mut solver = DirectSolver::cholesky();
        solver.reorder(system.ordering());
        let psi = system
            .solve(&mut solver)
            .map_err(|e| ModelError::from(e).context("Reynolds"))?;
        finite("Reynolds ψ", &psi)?;
        Ok(psi)
    }

    /// Fix ψ in the region's `system`: ψ₀ on ∂Ω₂, ψ^R (`psi_r` on the mesh vertices) at
    /// [`Region::psi_fixed`].
    pub fn constrain_substokes(&self, region: &Region, system: &mut System, psi_r: &[f64]) {
        for &v in &region.psi_fixed {
            let value = psi_r[region.mesh_vertex[v as usize] as usize];
            system.constraints.fix(system.dofs.dof(v, PSI), value);
        }
        self.substokes.constrain(system);
    }

    /// Assemble (I.58) on the SubStokes cells into the region's `system`: the cell integrals
    /// and the ∂Ω₂ term of [`SubStokesProblem::cell_contributions`], and on every face piece
    /// towards a Reynolds cell the interface term −⟨ψ^R n, ξ⟩ (module docs), ψ^R the bilinear
    /// interpolant of the cell's corner values of `psi_r` (= ψ^R on the face), 2 Gauss points
    /// per piece (exact).
    pub fn assemble_substokes(
        &self,
        mesh: &Mesh,
        region: &Region,
        reynolds_dofs: &DofMap,
        psi_r: &[f64],
        system: &mut System,
    ) {
        let active = mesh.active();
        let local = LocalDofs::new(N_COMPONENTS);
        let (points, weights) = crate::fe::quadrature::gauss(2);
        system.assemble(region.cells.len(), |j, ke, fe| {
            let k = region.cells[j];
            let c = active[k];
            self.substokes
                .cell_contributions(mesh, c, substokes::Form::Plain, ke, fe);
            let shape = mesh.cell_shape(c);
            let corner_psi = reynolds_dofs.corner_values(psi_r, k, 0);
            for face in FACES {
                let n = shape.face_normal(face);
                let (_, segments) = face_segments(mesh, c, face);
                for seg in segments {
                    let Some(nb) = seg.neighbor else { continue };
                    if region.flags[nb] {
                        continue;
                    }
                    let len = seg.length();
                    for (&t, &w) in points.iter().zip(weights) {
                        let p = seg.at(t);
                        let (psi, _) = evaluate_at(&shape, corner_psi, p);
                        let (xi, eta) = shape.reference(p);
                        let phi = bilinear(xi, eta);
                        for a in 0..4 {
                            for mu in 0..2 {
                                fe[local.index(a, mu)] -= psi * n[mu] * phi[a] * w * len;
                            }
                        }
                    }
                }
            }
        });
    }

    /// Solve the assembled and constrained SubStokes system of a region (LDLᵀ with the signs
    /// +1 on χ, −1 on ψ, nested-dissection order; [`solve_system`] checks the residual).
    pub fn solve_substokes(system: &System) -> Result<RegionSolution, ModelError> {
        let mut solver = DirectSolver::ldlt(SubStokesProblem::signs(&system.dofs));
        solver.reorder(system.ordering());
        let (u, relative_residual) = solve_system(system, &mut solver)?;
        finite("SubStokes (χ, ψ)", &u)?;
        Ok(RegionSolution {
            u,
            relative_residual,
        })
    }

    /// The coupled solve on `mesh` with the cells flagged in `substokes` (module docs): Reynolds
    /// everywhere, then SubStokes on the region with ψ^R as Dirichlet data on the interface.
    pub fn solve(&self, mesh: &Mesh, substokes: &[bool]) -> Result<CoupledSolution, ModelError> {
        let mut system = self.reynolds_system(mesh);
        let data = self.assemble_reynolds(mesh, &mut system);
        let psi = Self::solve_reynolds(&system)?;
        let dofs = system.into_dofs();
        let region = Region::new(mesh, &dofs.vertices, substokes);
        let substokes = if region.is_empty() {
            None
        } else {
            let mut sub = region.system();
            self.constrain_substokes(&region, &mut sub, &psi);
            self.assemble_substokes(mesh, &region, &dofs, &psi, &mut sub);
            Some(Self::solve_substokes(&sub)?)
        };
        Ok(CoupledSolution {
            reynolds: ReynoldsSolution { dofs, psi, data },
            region,
            substokes,
        })
    }
}

/// An error naming the first non-finite entry of `u`.
fn finite(what: &str, u: &[f64]) -> Result<(), ModelError> {
    match u.iter().position(|v| !v.is_finite()) {
        Some(i) => Err(ModelError::NonFinite(format!(
            "{what} is not finite at dof {i}: {}",
            u[i]
        ))),
        None => Ok(()),
    }
}

impl CoupledSolution {
    /// The SubStokes values as a [`SubStokesSolution`] on the region's dofs (None without
    /// SubStokes cells).
    pub fn substokes_solution(&self) -> Option<SubStokesSolution> {
        self.substokes.as_ref().map(|s| SubStokesSolution {
            dofs: self.region.dofs.clone(),
            u: s.u.clone(),
            relative_residual: s.relative_residual,
        })
    }

    /// The coupled pressure at the point `p` of Ω₂: ψ_h of the SubStokes solve on a SubStokes
    /// cell, ψ^R on a Reynolds cell (the cell that [`Mesh::locate`] finds; the field is
    /// continuous, module docs). None outside the mesh.
    pub fn pressure_at(&self, mesh: &Mesh, p: [f64; 2]) -> Option<f64> {
        let c = mesh.locate(p)?;
        Some(self.pressure_on(mesh, mesh.active_index(c), p))
    }

    /// The pressure of active cell `k`'s model (ψ_h on a SubStokes cell, ψ^R on a Reynolds
    /// cell) at the point `p`, extended bilinearly if `p` is outside the cell.
    pub fn pressure_on(&self, mesh: &Mesh, k: usize, p: [f64; 2]) -> f64 {
        let shape = mesh.cell_shape(mesh.active()[k]);
        let corners = match (self.region.cell_index[k], &self.substokes) {
            (Some(j), Some(s)) => self.region.dofs.corner_values(&s.u, j as usize, PSI),
            _ => self.reynolds.dofs.corner_values(&self.reynolds.psi, k, 0),
        };
        evaluate_at(&shape, corners, p).0
    }

    /// Total dofs: the Reynolds dofs (one per mesh vertex) and the SubStokes dofs (three per
    /// region vertex), hanging and Dirichlet dofs included.
    pub fn n_dofs(&self) -> usize {
        self.reynolds.dofs.n_dofs() + self.region.n_dofs()
    }
}

/// The coupling, meshes and SubStokes regions shared by the tests of the coupling and of the
/// estimator on a region (`estimators::substokes`).
#[cfg(test)]
pub(crate) mod fixtures {
    use super::*;
    use crate::models::substokes::fixtures::with_hanging;
    use crate::models::thin_film::example;

    pub fn coupling() -> Coupling {
        Coupling::new(example("IV.17").unwrap(), 200.0)
    }

    /// A deterministic scatter of SubStokes flags: about `percent` % of the cells, chosen by a
    /// hash of the cell's position and `seed`.
    pub fn scattered(mesh: &Mesh, seed: u64, percent: u64) -> Vec<bool> {
        mesh.active()
            .iter()
            .map(|&c| {
                let key = mesh.cell_key(c);
                let h = (key.x >> 16)
                    .wrapping_mul(0x9E37_79B9_7F4A_7C15)
                    .wrapping_add((key.y >> 16).wrapping_mul(0xC2B2_AE3D_27D4_EB4F))
                    .wrapping_add(u64::from(key.level).wrapping_mul(0x1656_67B1_9E37_79F9))
                    .wrapping_add(seed.wrapping_mul(0x27D4_EB2F_1656_67C5));
                (h >> 33) % 100 < percent
            })
            .collect()
    }

    /// The meshes of the interface tests: the mesh with hanging nodes, refined once more where
    /// the cell centre lies in [0.3, 0.7] × [0.2, 0.5] (three levels side by side).
    pub fn interface_meshes() -> Vec<Mesh> {
        let mut deeper = with_hanging();
        let refine: Vec<bool> = deeper
            .active()
            .iter()
            .map(|&c| {
                let [x0, y0, x1, y1] = deeper.cell_box(c);
                let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
                (0.3..0.7).contains(&cx) && (0.2..0.5).contains(&cy)
            })
            .collect();
        let coarsen = vec![false; refine.len()];
        deeper.refine_and_coarsen(&refine, &coarsen).unwrap();
        vec![with_hanging(), deeper]
    }
}

#[cfg(test)]
mod tests {
    use super::fixtures::{coupling, interface_meshes, scattered};
    use super::*;
    use crate::models::substokes::fixtures::{uniform, with_hanging};
    use crate::models::thin_film::{example, Gap};

    /// The model indicator on the 8×8 grid for (IV.17): per column of cells (it depends on x₁
    /// alone), P(Q) and V(Q). A reference computation gives P = 6.61 next to the widest gap (x₁ = 1/8, 5/8)
    /// and 6.69 next to the narrowest (3/8, 7/8), V = 0.0179 and 0.0058.
    #[test]
    fn theorem_iii6_bounds_on_8x8() {
        let film = example("IV.17").unwrap();
        let mesh = uniform(3);
        let eps = model_indicators(&film, &mesh);
        let mut columns = vec![None; 8];
        for (k, &c) in mesh.active().iter().enumerate() {
            let [x0, ..] = mesh.cell_box(c);
            let i = (x0 * 8.0).round() as usize;
            match columns[i] {
                None => columns[i] = Some(eps[k]),
                // Every cell of a column has the same bits.
                Some(e) => assert_eq!(e, eps[k], "column {i}"),
            }
        }
        let columns: Vec<ModelIndicator> = columns.into_iter().map(Option::unwrap).collect();
        for (i, e) in columns.iter().enumerate() {
            println!(
                "x1 in [{}, {}]: P = {:.4}, V = {:.5}",
                i as f64 / 8.0,
                (i + 1) as f64 / 8.0,
                e.pressure,
                e.velocity
            );
        }
        // Wide: the columns next to x₁ = 1/8 and 5/8; narrow: next to 3/8 and 7/8.
        for i in [0, 1, 4, 5] {
            let e = columns[i];
            assert!(
                (e.pressure - 6.61).abs() < 0.005,
                "column {i}: P = {}",
                e.pressure
            );
            assert!(
                (e.velocity - 0.0179).abs() < 0.00005,
                "column {i}: V = {}",
                e.velocity
            );
        }
        for i in [2, 3, 6, 7] {
            let e = columns[i];
            assert!(
                (e.pressure - 6.69).abs() < 0.005,
                "column {i}: P = {}",
                e.pressure
            );
            assert!(
                (e.velocity - 0.0058).abs() < 0.00005,
                "column {i}: V = {}",
                e.velocity
            );
        }
    }

    /// Plain gap g = 0.1: every derivative vanishes, P(Q) = ‖g⁴‖_Q/g_min = g³|Q|^½ and
    /// V(Q) = (g²/12)P(Q) + g⁵|Q|^½.
    #[test]
    fn plain_gap_has_closed_form_bounds() {
        let film = ThinFilm::new(Gap::Plain { g0: 0.1 }, [40.0, 0.0, 0.0]);
        let mesh = with_hanging();
        for (e, &c) in model_indicators(&film, &mesh).iter().zip(mesh.active()) {
            let root = mesh.cell_shape(c).area().sqrt();
            let p = 1e-3 * root;
            let v = 0.01 / 12.0 * p + 1e-5 * root;
            assert!((e.pressure - p).abs() <= 1e-12 * p, "{} vs {p}", e.pressure);
            assert!((e.velocity - v).abs() <= 1e-12 * v, "{} vs {v}", e.velocity);
        }
    }

    /// The rule of the indicator against a composite reference (4×4 Gauss points on 8×8
    /// sub-cells) on 8×8, 16×16 and 32×32 cells of (IV.17): relative difference below 1e-6.
    #[test]
    fn quadrature_of_the_bounds_is_converged() {
        let film = example("IV.17").unwrap();
        let g_min = film.gap.min_on_unit_square();
        let (gp, gw) = crate::fe::quadrature::gauss(4);
        let mut largest = 0.0f64;
        let meshes = [uniform(3), uniform(4), uniform(5)];
        let cells = meshes
            .iter()
            .flat_map(|mesh| mesh.active().iter().step_by(3).map(move |&c| (mesh, c)));
        for (mesh, c) in cells {
            let [x0, y0, x1, y1] = mesh.cell_box(c);
            let n = 8;
            let (hx, hy) = ((x1 - x0) / n as f64, (y1 - y0) / n as f64);
            let mut points = Vec::new();
            for i in 0..n {
                for j in 0..n {
                    for (a, wa) in gp.iter().zip(gw) {
                        for (b, wb) in gp.iter().zip(gw) {
                            let x = [x0 + (i as f64 + a) * hx, y0 + (j as f64 + b) * hy];
                            points.push((x, wa * wb * hx * hy));
                        }
                    }
                }
            }
            let g_max = film.gap.range_on_box([x0, y0, x1, y1]).1;
            let reference = bounds(&film, g_min, g_max * g_max, points);
            let e = model_indicator(&film, g_min, mesh, c);
            for (a, b) in [
                (e.pressure, reference.pressure),
                (e.velocity, reference.velocity),
            ] {
                largest = largest.max((a - b).abs() / b);
            }
        }
        println!("largest relative quadrature error: {largest:e}");
        assert!(largest < 1e-6, "{largest:e}");
    }

    fn max_abs(u: &[f64]) -> f64 {
        u.iter().fold(0.0f64, |m, v| m.max(v.abs()))
    }

    /// With every cell SubStokes the coupled solve is the plain SubStokes solve on the same
    /// mesh (same system: same vertices, hanging vertices, Dirichlet data).
    #[test]
    fn every_cell_substokes_is_the_plain_substokes_solve() {
        let p = coupling();
        for mesh in [uniform(3), with_hanging()] {
            let all = vec![true; mesh.n_active()];
            let coupled = p.solve(&mesh, &all).unwrap();
            let plain = p.substokes.solve(&mesh).unwrap();
            let u = &coupled.substokes.as_ref().unwrap().u;
            assert_eq!(u.len(), plain.u.len());
            assert_eq!(coupled.region.dofs.vertices.keys, plain.dofs.vertices.keys);
            assert_eq!(
                coupled.region.dofs.vertices.hanging,
                plain.dofs.vertices.hanging
            );
            assert!(coupled.region.interface.is_empty());
            let scale = max_abs(&plain.u);
            let diff = u
                .iter()
                .zip(&plain.u)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(diff <= 1e-12 * scale, "difference {diff:e} (scale {scale})");
        }
    }

    /// Without SubStokes cells the coupled pressure is the Reynolds solution (an independent
    /// assembly and solve of (I.79)), and there are no SubStokes dofs.
    #[test]
    fn no_substokes_cell_is_the_reynolds_solve() {
        let p = coupling();
        for mesh in [uniform(3), with_hanging()] {
            let none = vec![false; mesh.n_active()];
            let coupled = p.solve(&mesh, &none).unwrap();
            assert!(coupled.substokes.is_none());
            assert_eq!(coupled.region.n_dofs(), 0);
            let mut system = System::new(&mesh, 1);
            p.reynolds.constrain(&mut system);
            let data = p.reynolds.cell_data(&mesh, Load::Reynolds);
            p.reynolds.assemble(&mesh, &mut system, &data);
            let psi = system.solve(&mut DirectSolver::cholesky()).unwrap();
            assert_eq!(coupled.n_dofs(), psi.len());
            for (v, x) in system.dofs.vertices.coords.iter().enumerate() {
                let value = coupled.pressure_at(&mesh, *x).unwrap();
                assert!(
                    (value - psi[v]).abs() <= 1e-9 * max_abs(&psi),
                    "at {x:?}: {value} vs {}",
                    psi[v]
                );
            }
        }
    }

    /// Scattered SubStokes regions on meshes with hanging nodes: ψ_h = ψ^R at every interface
    /// vertex (hanging ones included), the coupled pressure is continuous across every face
    /// (between two models as well), and the four hanging configurations of the module docs all
    /// occur.
    #[test]
    fn interface_carries_the_reynolds_pressure() {
        let p = coupling();
        // Coarse cell's model, then the two fine cells' models: SSS, RS·, SRR, S(S,R).
        let mut cases = [0usize; 4];
        for mesh in interface_meshes() {
            for seed in 0..6 {
                let flags = scattered(&mesh, seed, 50);
                let coupled = p.solve(&mesh, &flags).unwrap();
                let region = &coupled.region;
                let u = &coupled.substokes.as_ref().unwrap().u;
                let psi_r = &coupled.reynolds.psi;
                let scale = max_abs(psi_r);
                assert!(!region.interface.is_empty());
                for &v in &region.interface {
                    let a = u[region.dofs.dof(v, PSI)];
                    let b = psi_r[region.mesh_vertex[v as usize] as usize];
                    assert!((a - b).abs() <= 1e-12 * scale, "vertex {v}: {a} vs {b}");
                }
                // Continuity across every face piece, at its ends and middle.
                for (k, &c) in mesh.active().iter().enumerate() {
                    for face in FACES {
                        let (_, segments) = face_segments(&mesh, c, face);
                        for seg in segments {
                            let Some(nb) = seg.neighbor else { continue };
                            for t in [0.0, 0.5, 1.0] {
                                let x = seg.at(t);
                                let (a, b) = (
                                    coupled.pressure_on(&mesh, k, x),
                                    coupled.pressure_on(&mesh, nb, x),
                                );
                                assert!(
                                    (a - b).abs() <= 1e-10 * scale,
                                    "seed {seed}, cell {k} / {nb} at {x:?}: {a} vs {b}"
                                );
                            }
                        }
                        if let Neighbor::Finer([n0, n1]) = mesh.neighbor(c, face) {
                            let fine = [n0, n1].map(|n| flags[mesh.active_index(n)]);
                            let case = match (flags[k], fine) {
                                (true, [true, true]) => 0,
                                (false, [a, b]) if a || b => 1,
                                (true, [false, false]) => 2,
                                (true, _) => 3,
                                _ => continue,
                            };
                            cases[case] += 1;
                        }
                    }
                }
            }
        }
        println!("hanging configurations SSS, R(S), SRR, S(SR): {cases:?}");
        assert!(cases.iter().all(|&n| n > 0), "{cases:?}");
    }

    /// (IV.9) (g = 0.1, upper wall (10, 0, 0)): the exact solutions are ψ ≡ 200 for both models
    /// and χ ≡ (g v̄₁, 0) = (0.5, 0) for SubStokes (γ = (600, 0), σ₃ = 0), which Q₁ reproduces.
    /// The coupled solve on a scattered region reproduces them only with the interface term
    /// −⟨ψ^R n, ξ⟩ in the momentum load (natural condition ∂_nχ = 0): without it the natural
    /// condition would be ∂_nχ = 200 n on the interface.
    #[test]
    fn interface_term_keeps_the_exact_couette_flow() {
        let p = Coupling::new(example("IV.9").unwrap(), 200.0);
        for mesh in interface_meshes() {
            let flags = scattered(&mesh, 3, 40);
            let coupled = p.solve(&mesh, &flags).unwrap();
            let u = &coupled.substokes.as_ref().unwrap().u;
            for v in 0..coupled.region.dofs.vertices.len() as u32 {
                let d = |comp| u[coupled.region.dofs.dof(v, comp)];
                assert!((d(0) - 0.5).abs() < 1e-9, "χ₁ = {} at {v}", d(0));
                assert!(d(1).abs() < 1e-9, "χ₂ = {} at {v}", d(1));
                assert!((d(PSI) - 200.0).abs() < 1e-9, "ψ = {} at {v}", d(PSI));
            }
            // Without the interface term the flow is far from it.
            let mut sub = coupled.region.system();
            p.constrain_substokes(&coupled.region, &mut sub, &coupled.reynolds.psi);
            let active = mesh.active();
            sub.assemble(coupled.region.cells.len(), |j, ke, fe| {
                let c = active[coupled.region.cells[j]];
                p.substokes
                    .cell_contributions(&mesh, c, substokes::Form::Plain, ke, fe)
            });
            let without = Coupling::solve_substokes(&sub).unwrap();
            let off = (0..coupled.region.dofs.vertices.len() as u32)
                .map(|v| (without.u[coupled.region.dofs.dof(v, 0)] - 0.5).abs())
                .fold(0.0f64, f64::max);
            assert!(off > 1.0, "χ₁ is off by {off} only");
        }
    }
}
