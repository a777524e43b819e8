//! The Uzawa test problem (III.88) of §III.2.3.4, used only for Fig. III.6: stabilised Stokes
//! flow (η = 1, f = 0, g = 0) on Ω = [0, 4]² past an L-shaped obstacle, with equal-order
//! Q₁/Q₁ on a uniform 32×32 mesh (h = 1/8), written as the block system (III.86),
//!
//! ```text
//! A v − B p = f,    Bᵀv + C p = g,
//! ```
//!
//! for [`crate::linalg::uzawa`].
//!
//! **Weak form** (III.88), with the typos of the print corrected: for all w ∈ V_h,
//! ψ ∈ P_h vanishing at the Dirichlet vertices,
//! ⟨∂_i v_j, ∂_i w_j⟩ − ⟨∂_j w_j, p⟩ = 0 and ⟨∂_j v_j, ψ⟩ + Σ_Q δ_ε h_Q² ⟨∇p, ∇ψ⟩_Q = 0, so
//! A_{(a,μ),(b,μ)} = ∫ ∇φ_a·∇φ_b, B_{(a,μ),q} = ∫ ψ_q ∂_μ φ_a, C_{q,r} = Σ_Q δ_ε h_Q² ∫_Q ∇ψ_q·∇ψ_r
//! (2×2 Gauss points per cell, exact for these bilinear integrands on rectangles), δ_ε = 1.
//!
//! **h_Q** ([`CellSize`]): the thesis writes h_Q² without defining h_Q. The default is the
//! cell diameter (the diagonal, √2/8 here), the h_Q of the SubStokes model
//! ([`crate::models::substokes`]) and of every estimator in this crate, and what deal.II's
//! `cell->diameter()` — the library the thesis's code is built on — returns;
//! [`CellSize::Side`] (h_Q = 1/8, half the stabilisation) is kept as the alternative reading.
//! The convergence of Fig. III.6 depends on it. With exact inner solves the diameter gives
//! relative residuals 0.573 (identity), 0.261 (Jacobi), 0.140 (Gauss–Seidel), 0.040 (SSOR)
//! after 300 iterations and 1e-6 after 48 for CG-SSOR; the side gives 0.589, 0.163, 0.061,
//! 0.0082 and 40. An independent reference implementation (exact inner solves) reported 0.57,
//! 0.26, 0.15, 0.043 and 49, close to the diameter reading only — a second reason for it
//! (Fig. III.6 itself is a picture without numbers to compare).
//!
//! **Boundary conditions** (decimal commas of the print read as points), all nodal:
//! * v = (y(4 − y), 0) at the vertices with x = 0;
//! * v = 0 at the vertices with y = 4, with x = 4, and with y = 0, x > 1.5;
//! * v = 0 at the vertices of the closed blocks {1.5 ≤ x ≤ 2, y ≤ 1.5} ∪
//!   {2 ≤ x ≤ 3, 1 ≤ y ≤ 1.5} (the L-shaped obstacle standing on the bottom wall);
//! * p = 0 at the vertices with y = 0, 0 ≤ x ≤ 1.5 (the outflow; the velocity there is free,
//!   a do-nothing outlet, except at (1.5, 0), which belongs to the obstacle).
//!
//! **The obstacle's cells stay in the mesh.** The thesis counts dim V_h = 2178 = 2·33² and
//! dim P_h = 1089 = 33², i.e. every vertex of the full 32×32 grid, the obstacle's included: the
//! obstacle is imposed by nodal Dirichlet values on the velocity, not cut out of the mesh.
//! Here too: the velocity dofs at the vertices of the closed blocks are fixed to 0 and the
//! pressure dofs there stay unknowns; inside the obstacle the velocity vanishes, so those
//! pressures are fixed by the stabilisation alone (a discrete harmonic extension of the
//! pressure on the obstacle's boundary) and do not affect the flow outside.
//!
//! **Blocks.** The coupled system is assembled with three components per vertex (v₁, v₂, p;
//! [`System::new`]) as the symmetric quasi-definite [A −B; −Bᵀ −C], the Dirichlet values are
//! eliminated (f and g are minus the couplings to them: only the inflow values contribute, to
//! f and to g), and the free velocity rows and columns give A (n = 1744 free velocity dofs: 872
//! of the 1089 vertices are free), the free pressures give C (m = 1076: 13 outflow vertices are
//! fixed), and B couples them.

use crate::fe::blocks::SaddleBlocks;
use crate::fe::cell_values::CellValues;
use crate::fe::quadrature::square_rule;
use crate::fe::{LocalDofs, System};
use crate::linalg::saddle_point::{DirectSolution, SaddlePoint};
use crate::linalg::uzawa::{uzawa, UzawaOptions, Variant};
use crate::linalg::Ordering;
use crate::mesh::Mesh;
use crate::models::ModelError;
use crate::results::UzawaRow;

/// Components per vertex: v₁, v₂, p.
pub const N_COMPONENTS: usize = 3;

/// Component index of the pressure.
pub const PRESSURE: usize = 2;

/// Relative residual at which the runs of Fig. III.6 stop early.
pub const FIG_III6_TOLERANCE: f64 = 1e-10;

/// Which cell size h_Q enters the stabilisation Σ_Q δ_ε h_Q² ⟨∇p, ∇ψ⟩_Q (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CellSize {
    /// The cell diameter (diagonal of the square cell).
    Diameter,
    /// The side length of the square cell.
    Side,
}

/// The side of the square Ω = [0, 4]² of (III.88).
pub const SIDE: f64 = 4.0;

/// Cells per side of the thesis's mesh (h = 1/8).
pub const CELLS_PER_SIDE: usize = 32;

/// The test problem (III.88) on a uniform grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StokesChannel {
    /// Cells per side of Ω = [0, 4]² (32 in the thesis: h = 1/8).
    pub cells_per_side: usize,
    /// δ_ε (1 in (III.88)).
    pub delta_eps: f64,
    pub cell_size: CellSize,
}

/// The block system of a [`StokesChannel`] with the map back to the mesh.
#[derive(Clone, Debug)]
pub struct ChannelBlocks {
    pub system: SaddlePoint,
    /// dim V_h: two velocity components at every vertex, Dirichlet ones included.
    pub dim_velocity_space: usize,
    /// dim P_h: one pressure at every vertex, Dirichlet ones included.
    pub dim_pressure_space: usize,
    /// Dof of the 3-component system (vertex · 3 + component) of each velocity unknown.
    pub velocity_dofs: Vec<usize>,
    /// Dof of the 3-component system of each pressure unknown.
    pub pressure_dofs: Vec<usize>,
    /// The eliminated dofs of the 3-component system with their values.
    pub fixed: Vec<(usize, f64)>,
    /// Nested-dissection ordering of the n + m block unknowns (velocities first), from the
    /// mesh's vertex positions, for the direct solve.
    pub ordering: Ordering,
}

impl ChannelBlocks {
    /// The coupled system solved directly (LDLᵀ, [`SaddlePoint::solve_direct`]).
    pub fn solve_direct(&self) -> Result<DirectSolution, ModelError> {
        Ok(self.system.solve_direct(Some(self.ordering.clone()))?)
    }

    /// The vertex-major field (v₁, v₂, p) per vertex from block vectors, Dirichlet values
    /// filled in.
    pub fn field(&self, velocity: &[f64], pressure: &[f64]) -> Vec<f64> {
        let n = self.dim_pressure_space * N_COMPONENTS;
        let mut u = vec![0.0; n];
        for &(d, value) in &self.fixed {
            u[d] = value;
        }
        for (&d, &value) in self.velocity_dofs.iter().zip(velocity) {
            u[d] = value;
        }
        for (&d, &value) in self.pressure_dofs.iter().zip(pressure) {
            u[d] = value;
        }
        u
    }
}

const EPS: f64 = 1e-9;

/// Whether the velocity vanishes at (x, y) by the walls or the obstacle (not the inflow).
fn velocity_wall(x: f64, y: f64) -> bool {
    let walls = y >= 4.0 - EPS || x >= 4.0 - EPS || (y <= EPS && x > 1.5 + EPS);
    let block_a = (1.5 - EPS..=2.0 + EPS).contains(&x) && y <= 1.5 + EPS;
    let block_b = (2.0 - EPS..=3.0 + EPS).contains(&x) && (1.0 - EPS..=1.5 + EPS).contains(&y);
    walls || block_a || block_b
}

/// Whether the pressure is fixed to 0 at (x, y) (the outflow).
fn pressure_outflow(x: f64, y: f64) -> bool {
    y <= EPS && x <= 1.5 + EPS
}

impl StokesChannel {
    /// (III.88) as the thesis states it: 32×32 cells, δ_ε = 1, h_Q the cell diameter.
    pub fn thesis() -> StokesChannel {
        StokesChannel {
            cells_per_side: CELLS_PER_SIDE,
            delta_eps: 1.0,
            cell_size: CellSize::Diameter,
        }
    }

    /// The uniform grid of [0, 4]².
    pub fn mesh(&self) -> Mesh {
        Mesh::new(
            [0.0, SIDE],
            [0.0, SIDE],
            self.cells_per_side,
            self.cells_per_side,
        )
    }

    /// The 3-component system of `mesh` with the Dirichlet values of the module docs.
    pub fn system(&self, mesh: &Mesh) -> System {
        let mut system = System::new(mesh, N_COMPONENTS);
        for v in 0..system.dofs.vertices.len() as u32 {
            let [x, y] = system.dofs.vertices.coords[v as usize];
            if x <= EPS {
                system.constraints.fix(system.dofs.dof(v, 0), y * (4.0 - y));
                system.constraints.fix(system.dofs.dof(v, 1), 0.0);
            } else if velocity_wall(x, y) {
                system.constraints.fix(system.dofs.dof(v, 0), 0.0);
                system.constraints.fix(system.dofs.dof(v, 1), 0.0);
            }
            if pressure_outflow(x, y) {
                system.constraints.fix(system.dofs.dof(v, PRESSURE), 0.0);
            }
        }
        system
    }

    /// Assemble [A −B; −Bᵀ −C] (module docs) into `system`; the load is zero (f = g = 0).
    pub fn assemble(&self, mesh: &Mesh, system: &mut System) {
        let active = mesh.active();
        let rule = square_rule::<4>();
        let local = LocalDofs::new(N_COMPONENTS);
        let (delta, cell_size) = (self.delta_eps, self.cell_size);
        system.assemble(active.len(), |k, ke, _fe| {
            let shape = mesh.cell_shape(active[k]);
            let h_q = match cell_size {
                CellSize::Diameter => shape.diameter(),
                CellSize::Side => {
                    let [x0, y0, x1, y1] = mesh.cell_box(active[k]);
                    (x1 - x0).max(y1 - y0)
                }
            };
            let stab = delta * h_q * h_q;
            let cv = CellValues::new(shape, &rule);
            for q in 0..rule.len() {
                let grad = cv.gradients(q);
                let phi = cv.values(q);
                let jw = cv.jxw(q);
                for a in 0..4 {
                    for b in 0..4 {
                        let stiff = (grad[a][0] * grad[b][0] + grad[a][1] * grad[b][1]) * jw;
                        for mu in 0..2 {
                            ke[local.entry(local.index(a, mu), local.index(b, mu))] += stiff;
                            // −B and −Bᵀ: velocity component μ at a, pressure at b.
                            let bv = phi[b] * grad[a][mu] * jw;
                            ke[local.entry(local.index(a, mu), local.index(b, PRESSURE))] -= bv;
                            ke[local.entry(local.index(b, PRESSURE), local.index(a, mu))] -= bv;
                        }
                        ke[local.entry(local.index(a, PRESSURE), local.index(b, PRESSURE))] -=
                            stab * stiff;
                    }
                }
            }
        });
    }

    /// Assemble on [`StokesChannel::mesh`] and split into the blocks of (III.86) with the
    /// Dirichlet values eliminated ([`SaddleBlocks::new`], shared with the SubStokes Uzawa
    /// solver).
    pub fn blocks(&self) -> Result<ChannelBlocks, ModelError> {
        let mesh = self.mesh();
        let mut system = self.system(&mesh);
        self.assemble(&mesh, &mut system);
        let n_dofs = system.dofs.n_dofs();
        let n_vertices = system.dofs.vertices.len();
        if n_vertices * N_COMPONENTS != n_dofs || !system.dofs.vertices.hanging.is_empty() {
            return Err("stokes channel: the uniform grid has hanging vertices".into());
        }
        // The block unknowns ordered as the nested dissection orders their system dofs.
        let blocks = SaddleBlocks::new(&system, PRESSURE)?;
        Ok(ChannelBlocks {
            system: blocks.system,
            dim_velocity_space: 2 * n_vertices,
            dim_pressure_space: n_vertices,
            velocity_dofs: blocks.velocity_dofs,
            pressure_dofs: blocks.pressure_dofs,
            fixed: blocks.eliminated,
            ordering: blocks.ordering,
        })
    }
}

/// Fig. III.6: the five Uzawa variants ([`Variant::ALL`], in that order) on (III.88) as the
/// thesis states it ([`StokesChannel::thesis`]), each from p⁰ = 0 for at most `iterations`
/// outer iterations or until the relative residual is [`FIG_III6_TOLERANCE`], with the default
/// options otherwise ([`UzawaOptions::new`]: adaptive inner tolerance, ω = 1, no projection).
/// Rows 0..=k of each variant, one after the other; the pressure error is against the direct
/// LDLᵀ solution. A diverging variant or a failed inner solve is an error naming the variant
/// and the iteration.
pub fn run_fig_iii6(iterations: usize) -> Result<Vec<UzawaRow>, ModelError> {
    let blocks = StokesChannel::thesis().blocks()?;
    let direct = blocks.solve_direct()?;
    let mut rows = Vec::new();
    for variant in Variant::ALL {
        let options = UzawaOptions {
            max_iterations: iterations,
            relative_tolerance: FIG_III6_TOLERANCE,
            ..UzawaOptions::new(variant)
        };
        let run = uzawa(&blocks.system, &options, Some(&direct.pressure))?;
        rows.extend(run.rows);
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// dim V_h = 2178 and dim P_h = 1089 as the thesis counts them (every vertex of the 33×33
    /// grid, before the Dirichlet values are eliminated); after elimination n = 1744 velocity
    /// unknowns (217 of the 1089 vertices carry Dirichlet velocities: 97 on x = 0, x = 4,
    /// y = 4; 19 more on y = 0, x > 1.5; 61 more in the first block, 40 more in the second) and
    /// m = 1076 pressures (13 outflow vertices x = 0, 0.125, …, 1.5 on y = 0).
    #[test]
    fn dimensions_of_the_thesis_problem() {
        let blocks = StokesChannel::thesis().blocks().unwrap();
        assert_eq!(blocks.dim_velocity_space, 2178);
        assert_eq!(blocks.dim_pressure_space, 1089);
        assert_eq!(blocks.system.n_velocity(), 2 * (1089 - 217));
        assert_eq!(blocks.system.n_pressure(), 1089 - 13);
        assert_eq!(blocks.fixed.len(), 2 * 217 + 13);
        assert_eq!(blocks.ordering.len(), 1744 + 1076);
    }

    /// The blocks as (III.86) wants them: A and C symmetric with positive diagonals, Bᵀ the
    /// transpose of B, f and g nonzero only through the inflow.
    #[test]
    fn blocks_have_the_structure_of_iii86() {
        let blocks = StokesChannel::thesis().blocks().unwrap();
        let s = &blocks.system;
        for (name, m) in [("A", &s.a), ("C", &s.c)] {
            let t = m.transpose();
            assert_eq!(t.col_idx, m.col_idx, "{name}: pattern not symmetric");
            for (x, y) in t.values.iter().zip(&m.values) {
                assert!(
                    (x - y).abs() <= 1e-14 * x.abs().max(1.0),
                    "{name}: {x} vs {y}"
                );
            }
            assert!(m.diagonal().iter().all(|&d| d > 0.0), "{name}: diagonal");
        }
        assert_eq!(s.bt(), &s.b.transpose());
        assert!(s.f.iter().any(|&x| x != 0.0) && s.g.iter().any(|&x| x != 0.0));
        // Only unknowns next to x = 0 feel the inflow values.
        let mesh = StokesChannel::thesis().mesh();
        let coords = crate::fe::DofMap::new(&mesh, N_COMPONENTS).vertices.coords;
        let x_of = |dof: usize| coords[dof / N_COMPONENTS][0];
        for (k, &f) in s.f.iter().enumerate() {
            assert!(f == 0.0 || x_of(blocks.velocity_dofs[k]) <= 0.125 + EPS);
        }
        for (k, &g) in s.g.iter().enumerate() {
            assert!(g == 0.0 || x_of(blocks.pressure_dofs[k]) <= 0.125 + EPS);
        }
    }

    /// The direct LDLᵀ solve satisfies the block equations (III.86) to 1e-10 relative, and the
    /// field it gives satisfies the assembled 3-component system on its free rows (so the
    /// split into blocks lost nothing); the boundary values are in place.
    #[test]
    fn direct_solve_satisfies_the_coupled_equations() {
        let problem = StokesChannel::thesis();
        let blocks = problem.blocks().unwrap();
        let direct = blocks.solve_direct().unwrap();
        let s = &blocks.system;
        let relative = s.residual(&direct.velocity, &direct.pressure) / s.rhs_norm();
        println!("direct: relative residual {relative:e}");
        assert!(relative <= 1e-10, "{relative:e}");
        assert_eq!(relative, direct.relative_residual);
        // Against the assembled system [A −B; −Bᵀ −C] (rhs 0) on the free rows.
        let mesh = problem.mesh();
        let mut system = problem.system(&mesh);
        problem.assemble(&mesh, &mut system);
        let u = blocks.field(&direct.velocity, &direct.pressure);
        let ku = system.matrix().multiply(&u);
        let (mut r2, mut scale2) = (0.0, 0.0);
        for d in (0..u.len()).filter(|&d| system.constraints.is_free(d)) {
            r2 += ku[d] * ku[d];
            scale2 += 1.0;
        }
        let field_residual = (r2 / scale2).sqrt();
        assert!(field_residual <= 1e-12, "{field_residual:e}");
        // Boundary values: inflow, obstacle, outflow.
        let vertex = |x: f64, y: f64| {
            system
                .dofs
                .vertices
                .coords
                .iter()
                .position(|c| (c[0] - x).abs() < EPS && (c[1] - y).abs() < EPS)
                .unwrap() as u32
        };
        let at = |x, y, c| u[system.dofs.dof(vertex(x, y), c)];
        assert_eq!(at(0.0, 2.0, 0), 4.0);
        assert_eq!(at(0.0, 1.0, 0), 3.0);
        assert_eq!(at(1.75, 0.5, 0), 0.0);
        assert_eq!(at(2.5, 1.25, 1), 0.0);
        assert_eq!(at(1.0, 0.0, PRESSURE), 0.0);
        // The outflow velocity is free and leaves through y = 0 (v₂ < 0 there).
        assert!(at(0.75, 0.0, 1) < 0.0);
    }

    /// Fig. III.6 with 20 iterations: five variants in order, 21 rows each, finite values,
    /// relative residual 1 in row 0 and consistent with the residual, pressure errors given,
    /// wall time not decreasing.
    #[test]
    fn fig_iii6_rows() {
        let rows = run_fig_iii6(20).unwrap();
        assert_eq!(rows.len(), 5 * 21);
        for (i, variant) in Variant::ALL.into_iter().enumerate() {
            let block = &rows[21 * i..21 * (i + 1)];
            assert!(block.iter().all(|r| r.variant == variant.name()));
            assert!((block[0].relative_residual - 1.0).abs() < 1e-15);
            for (k, r) in block.iter().enumerate() {
                assert_eq!(r.iteration, k);
                assert!(r.residual.is_finite() && r.residual > 0.0);
                let rel = r.residual / block[0].residual;
                assert!((r.relative_residual - rel).abs() <= 1e-15 * rel.max(1.0));
                assert!(r.pressure_error.is_some_and(f64::is_finite));
                assert!(r.inner_iterations > 0 || k > 0);
                if k > 0 {
                    assert!(r.seconds >= block[k - 1].seconds);
                }
            }
        }
        // The same initial residual for every variant (p⁰ = 0).
        assert!(rows
            .iter()
            .step_by(21)
            .all(|r| r.residual == rows[0].residual));
    }

    /// The full Fig. III.6 run, 300 iterations (or relative residual 1e-10) per variant, with
    /// its wall time: `cargo test --release --lib fig_iii6_full -- --ignored --nocapture`.
    #[test]
    #[ignore = "prints the full Fig. III.6 run (about a second in release)"]
    fn fig_iii6_full_run() {
        let start = std::time::Instant::now();
        let rows = run_fig_iii6(300).unwrap();
        let seconds = start.elapsed().as_secs_f64();
        for variant in Variant::ALL {
            let rows: Vec<&UzawaRow> = rows
                .iter()
                .filter(|r| r.variant == variant.name())
                .collect();
            let at = |k: usize| rows.get(k).map(|r| r.relative_residual);
            let first = rows
                .iter()
                .find(|r| r.relative_residual <= 1e-6)
                .map(|r| r.iteration);
            let last = rows.last().unwrap();
            let inner: usize = rows.iter().map(|r| r.inner_iterations).sum();
            println!(
                "{variant}: 1e-6 at {first:?}, rel@50 {:?}, rel@300 {:?}, last row {} rel {:e} \
                 pressure error {:e}, {inner} CG iterations, {:.3} s",
                at(50),
                at(300),
                last.iteration,
                last.relative_residual,
                last.pressure_error.unwrap(),
                last.seconds
            );
        }
        println!("total {seconds:.3} s");
        assert!(seconds <= 10.0, "{seconds} s");
    }
}
