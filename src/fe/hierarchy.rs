//! The level meshes of an adaptive quadtree mesh for geometric multigrid, and the prolongation
//! of Q₁ functions from each level to the next finer one.
//!
//! **Global coarsening.** Level `l` is the mesh of the cells of level ≤ `l`
//! ([`Mesh::truncated`]): each level mesh covers the whole domain, has its own hanging vertices,
//! and its Q₁ space (with the hanging-node constraints) is a subspace of the next finer one. The
//! alternative, local smoothing on the cells of one level with special treatment of the interface
//! to coarser cells (deal.II's `MGTransferPrebuilt`, Kanschat 2004), needs edge matrices and a
//! smoother that only sees part of the mesh; global coarsening needs neither, every level is an
//! ordinary conforming space, and the coarse operators can be the Galerkin products PᵀAP of the
//! assembled matrix, so the same code serves every SPD problem whatever it assembles. Munch,
//! Heister, Prieto Saavedra and Kronbichler (*Efficient distributed matrix-free multigrid methods
//! on locally refined meshes for FEM computations*, ACM TOPC 10, 2023) compare the two and find
//! global coarsening competitive or faster in iteration counts and time; its known cost is that
//! a level mesh is not much smaller than the next where only few cells are refined — levels whose
//! vertex count falls by less than [`MIN_COARSENING`] are therefore skipped (the prolongation
//! then spans two or more levels, still exact for nested spaces).
//!
//! **Prolongation.** A coarse Q₁ function evaluated at a fine vertex: locate the coarse cell
//! holding the vertex, take the bilinear weights of its four corners at the vertex's reference
//! position, and replace a hanging corner by the mean of its two parents. The bilinear map of a
//! cell is refined in reference coordinates, so the weights come from the integer positions and
//! hold on moved (quadrilateral) meshes too.

use rayon::prelude::*;

use super::dofs::Vertices;
use crate::linalg::multigrid::{Transfer, VertexHierarchy};
use crate::mesh::Mesh;

/// A level is kept when it has at most this fraction of the cells of the finer level kept
/// before it (the others are skipped: the next coarser one is prolongated directly). Cells, not
/// vertices: they are counted without numbering the level's vertices, and a quadrilateral mesh
/// has about as many vertices as cells.
pub const MIN_COARSENING: f64 = 0.4;

/// The level meshes of `mesh` from coarsest to finest and the prolongations between them;
/// `finest` are the vertices of `mesh` itself (the numbering of its dofs).
pub fn vertex_hierarchy(mesh: &Mesh, finest: &Vertices) -> VertexHierarchy {
    CoarseLevels::of(mesh).with_finest(mesh, finest)
}

/// The part of a mesh's hierarchy below the mesh itself: the kept levels, their numberings and
/// the prolongations between them, which need the mesh only, not the numbering of its dofs —
/// so a setup can build them while it numbers the dofs
/// ([`crate::study::problem::setup_system`]).
pub struct CoarseLevels {
    /// The finest kept level and its vertices (none on a mesh of one level).
    top: Option<(u8, Vertices)>,
    /// The prolongations between the kept levels, coarsest first, up to `top`.
    transfers: Vec<Transfer>,
}

impl CoarseLevels {
    /// The kept levels of `mesh` (those with at most [`MIN_COARSENING`] of the cells of the
    /// next finer kept one, and level 0), numbered; a level mesh is needed only for that.
    pub fn of(mesh: &Mesh) -> CoarseLevels {
        let cells = cells_per_truncation(mesh);
        let mut kept = Vec::new();
        let mut fine_cells = mesh.n_active();
        for level in (0..mesh.max_level()).rev() {
            let coarse_cells = cells[level as usize];
            if (coarse_cells as f64) > MIN_COARSENING * fine_cells as f64 && level > 0 {
                continue;
            }
            kept.push((level, Vertices::numbering_only(&mesh.truncated(level))));
            fine_cells = coarse_cells;
        }
        // Finest first: each level's prolongation goes to the one before it.
        let mut transfers: Vec<Transfer> = kept
            .windows(2)
            .map(|w| prolongation(mesh, w[1].0, &w[1].1, &w[0].1))
            .collect();
        transfers.reverse();
        CoarseLevels {
            top: kept.into_iter().next(),
            transfers,
        }
    }

    /// The hierarchy of `mesh` (whose levels these are) with `finest`, the vertices of `mesh`
    /// itself: the prolongation from the top kept level to them, after the others.
    pub fn with_finest(self, mesh: &Mesh, finest: &Vertices) -> VertexHierarchy {
        let mut transfers = self.transfers;
        if let Some((level, coarse)) = &self.top {
            transfers.push(prolongation(mesh, *level, coarse, finest));
        }
        VertexHierarchy { transfers }
    }
}

/// The number of cells of each truncation [`Mesh::truncated`] of `mesh`, by level: the active
/// cells of lower levels and all cells of the level itself.
fn cells_per_truncation(mesh: &Mesh) -> Vec<usize> {
    let levels = mesh.max_level() as usize + 1;
    let mut active = vec![0usize; levels];
    let mut all = vec![0usize; levels];
    for c in 0..mesh.n_cells() as u32 {
        let l = mesh.level(c) as usize;
        all[l] += 1;
        if mesh.is_active(c) {
            active[l] += 1;
        }
    }
    let mut below = 0;
    (0..levels)
        .map(|l| {
            let n = below + all[l];
            below += active[l];
            n
        })
        .collect()
}

/// The prolongation from the Q₁ space of the truncation of `mesh` at `level` (vertices
/// `coarse`) to the vertices `fine` of a finer truncation of `mesh` (or of `mesh`).
///
/// The coarse cell that holds a fine vertex is the ancestor at `level` of the fine cell that
/// holds it ([`Vertices::owner`]; the truncations share the cells of `mesh`, and with them
/// their corners): a step or two up the tree instead of a descent from the root per vertex.
fn prolongation(mesh: &Mesh, level: u8, coarse: &Vertices, fine: &Vertices) -> Transfer {
    let row = |v: usize, out: &mut Vec<(u32, f64)>| {
        if fine.is_hanging[v] {
            // Hanging dofs are eliminated at every level: no row.
            return;
        }
        let key = fine.keys[v];
        let corners = mesh.corner_keys(mesh.ancestor_at(fine.owner[v], level));
        let width = (corners[1].0 - corners[0].0) as f64;
        let s = (key.0 - corners[0].0) as f64 / width;
        let t = (key.1 - corners[0].1) as f64 / width;
        let weights = [(1.0 - s) * (1.0 - t), s * (1.0 - t), (1.0 - s) * t, s * t];
        // At most six coarse vertices per fine vertex: four corners, two of them hanging on
        // different edges, each replaced by its two parents (which are shared with the corners).
        let start = out.len();
        let mut add = |w: u32, weight: f64| match out[start..].iter_mut().find(|e| e.0 == w) {
            Some(e) => e.1 += weight,
            None => out.push((w, weight)),
        };
        for (&k, &weight) in corners.iter().zip(&weights) {
            if weight == 0.0 {
                continue;
            }
            let w = coarse.find(k).expect("corner is a vertex");
            if coarse.is_hanging[w as usize] {
                let i = coarse
                    .hanging
                    .binary_search_by_key(&w, |h| h.vertex)
                    .expect("hanging vertex listed");
                for p in coarse.hanging[i].parents {
                    add(p, 0.5 * weight);
                }
            } else {
                add(w, weight);
            }
        }
        out[start..].sort_unstable_by_key(|e| e.0);
    };
    let fine_of_coarse = coarse
        .keys
        .par_iter()
        .map(|&k| fine.find(k).expect("a coarse vertex is a fine vertex"))
        .collect();
    Transfer::by_rows(
        fine.len(),
        coarse.len(),
        row,
        fine_of_coarse,
        coarse.is_hanging.clone(),
    )
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::fe::cell_values::CellValues;
    use crate::fe::quadrature::square_rule;
    use crate::fe::{LocalDofs, System};
    use crate::linalg::multigrid::MultigridSolver;
    use crate::linalg::{Accuracy, DirectSolver, Rotation, SolveConstrained};

    /// max |a_i − b_i|, with b = 0 where it is shorter (max |a_i| for an empty b).
    fn max_difference(a: &[f64], b: &[f64]) -> f64 {
        a.iter().enumerate().fold(0.0f64, |m, (i, x)| {
            m.max((x - b.get(i).unwrap_or(&0.0)).abs())
        })
    }

    /// A mesh refined towards the corner (0, 0) and along x₂ = x₁ (hanging vertices on many
    /// levels), on a 2 × 1 coarse grid.
    pub(crate) fn graded_mesh(cycles: usize) -> Mesh {
        let mut mesh = Mesh::new([0.0, 2.0], [0.0, 1.0], 2, 1);
        mesh.refine_global().unwrap();
        for _ in 0..cycles {
            let refine: Vec<bool> = mesh
                .active()
                .iter()
                .map(|&c| {
                    let [x0, y0, x1, y1] = mesh.cell_box(c);
                    let corner = x0 == 0.0 && y0 == 0.0;
                    let diagonal = x0 <= y1 && y0 <= x1;
                    corner || (diagonal && mesh.level(c) < 6)
                })
                .collect();
            let none = vec![false; refine.len()];
            mesh.refine_and_coarsen(&refine, &none).unwrap();
        }
        mesh
    }

    /// −Δu + c u = 1 with u = 0 on the left and bottom sides and u = 1 on the right side,
    /// `components` copies of it per vertex.
    pub(crate) fn assembled(mesh: &Mesh, components: usize, c: f64) -> System {
        let mut system = System::new(mesh, components);
        for component in 0..components {
            system.constraints.fix_side(
                &system.dofs.clone(),
                crate::mesh::Side::Left,
                component,
                0.0,
            );
            system.constraints.fix_side(
                &system.dofs.clone(),
                crate::mesh::Side::Right,
                component,
                1.0,
            );
        }
        let rule = square_rule::<4>();
        let local = LocalDofs::new(components);
        let active = mesh.active().to_vec();
        system.assemble(active.len(), |k, ke, fe| {
            let cv = CellValues::new(mesh.cell_shape(active[k]), &rule);
            for q in 0..rule.len() {
                let (g, phi, jw) = (cv.gradients(q), cv.values(q), cv.jxw(q));
                for a in 0..4 {
                    for b in 0..4 {
                        let v = (g[a][0] * g[b][0] + g[a][1] * g[b][1] + c * phi[a] * phi[b]) * jw;
                        for comp in 0..components {
                            ke[local.entry(local.index(a, comp), local.index(b, comp))] += v;
                        }
                    }
                    for comp in 0..components {
                        fe[local.index(a, comp)] += phi[a] * jw;
                    }
                }
            }
        });
        system
    }

    #[test]
    fn prolongation_reproduces_bilinear_functions() {
        let mesh = graded_mesh(5);
        let fine = Vertices::new(&mesh);
        let h = vertex_hierarchy(&mesh, &fine);
        assert!(h.transfers.len() >= 3, "levels {:?}", h.level_sizes());
        let t = h.transfers.last().unwrap();
        let coarse_mesh_vertices = {
            // The coarse positions, found back through the fine vertices they sit on.
            let mut p = vec![[0.0; 2]; t.n_coarse];
            for (w, &v) in t.fine_of_coarse.iter().enumerate() {
                p[w] = fine.coords[v as usize];
            }
            p
        };
        let f = |x: [f64; 2]| 1.0 + 2.0 * x[0] - 3.0 * x[1] + 0.5 * x[0] * x[1];
        for v in 0..fine.len() {
            if fine.is_hanging[v] {
                continue;
            }
            let value: f64 = (t.row_ptr[v]..t.row_ptr[v + 1])
                .map(|k| t.weights[k] * f(coarse_mesh_vertices[t.cols[k] as usize]))
                .sum();
            let exact = f(fine.coords[v]);
            // A bilinear function of the whole domain is in every level's space only cell-wise;
            // x₁x₂ is bilinear on each cell, so the interpolation is exact.
            assert!(
                (value - exact).abs() < 1e-12,
                "vertex {v}: {value} vs {exact}"
            );
        }
    }

    #[test]
    fn multigrid_matches_the_direct_solver_with_hanging_vertices() {
        for components in [1, 2] {
            let mesh = graded_mesh(6);
            let system = assembled(&mesh, components, 0.5);
            let direct = system.solve(&mut DirectSolver::cholesky()).unwrap();
            let mut mg = MultigridSolver::default();
            mg.set_hierarchy(vertex_hierarchy(&mesh, &system.dofs.vertices), components);
            let mut u = mg
                .solve(
                    system.matrix(),
                    &system.rhs,
                    &system.constraints.eliminated(),
                )
                .unwrap();
            system.constraints.distribute(&mut u);
            let scale = max_difference(&direct, &[]);
            let diff = max_difference(&direct, &u);
            let iterations = mg.take_iterations();
            assert!(
                diff < 1e-9 * scale,
                "{components} components: max |Δu| = {diff:e}"
            );
            assert!(
                iterations[0] < 20,
                "{components} components: {iterations:?} CG iterations"
            );
            // A warm start from the solution takes no iteration at all.
            mg.solve(
                system.matrix(),
                &system.rhs,
                &system.constraints.eliminated(),
            )
            .unwrap();
            assert_eq!(mg.take_iterations(), vec![0]);
        }
    }

    /// Vertices whose two dofs are in a rotated normal/tangential frame, as in the contact
    /// solves: with the frames given (`set_rotation`) the prolongation rotates and multigrid
    /// converges as fast as on the Cartesian system; without them, component by component, it
    /// does not.
    #[test]
    fn multigrid_follows_rotated_frames() {
        let mesh = graded_mesh(6);
        let system = assembled(&mesh, 2, 0.5);
        let vertices = &system.dofs.vertices;
        // The upper half but the fixed sides, a normal turning across it (the contact solves
        // rotate a boundary only; more rotated vertices tell the frames apart more clearly).
        let frames: Vec<(u32, [f64; 2])> = (0..vertices.len())
            .filter(|&v| {
                let [x, y] = vertices.coords[v];
                y >= 0.5 && x > 0.0 && x < 2.0 && !vertices.is_hanging[v]
            })
            .map(|v| {
                let [x, y] = vertices.coords[v];
                let angle = 7.0 * x + 5.0 * y;
                (v as u32, [angle.sin(), angle.cos()])
            })
            .collect();
        assert!(frames.len() > 100, "{} rotated vertices", frames.len());
        let rotation = Rotation { frames };
        let mut values = system.matrix().values.to_vec();
        let mut rhs = system.rhs.clone();
        rotation.apply(system.matrix(), &mut values, &mut rhs);
        let rotated = system.matrix().with_values(&values);
        let eliminated = system.constraints.eliminated();
        let direct = system.solve(&mut DirectSolver::cholesky()).unwrap();
        let cartesian_iterations = {
            let mut mg = MultigridSolver::default();
            mg.set_hierarchy(vertex_hierarchy(&mesh, vertices), 2);
            mg.solve(system.matrix(), &system.rhs, &eliminated).unwrap();
            mg.take_iterations()[0]
        };
        let mut iterations = Vec::new();
        for with_frames in [true, false] {
            let mut mg = MultigridSolver::default();
            mg.set_hierarchy(vertex_hierarchy(&mesh, vertices), 2);
            if with_frames {
                mg.set_rotation(&rotation.frames);
            }
            let mut u = mg.solve(rotated, &rhs, &eliminated).unwrap();
            rotation.to_cartesian(&mut u);
            system.constraints.distribute(&mut u);
            let scale = max_difference(&direct, &[]);
            let diff = max_difference(&direct, &u);
            assert!(
                diff < 1e-9 * scale,
                "frames {with_frames}: max |Δu| = {diff:e}"
            );
            iterations.push(mg.take_iterations()[0]);
        }
        assert!(
            iterations[0] <= cartesian_iterations + 1,
            "{} CG iterations with the frames, {cartesian_iterations} on the Cartesian system",
            iterations[0]
        );
        assert!(
            iterations[1] > iterations[0] + 3,
            "without the frames {} CG iterations, with them {}",
            iterations[1],
            iterations[0]
        );
    }

    /// On a mesh of one level the cycle is a Cholesky solve: of each solve's own matrix, also
    /// when an active-set iteration eliminates other dofs than the first solve did — one CG
    /// iteration, where the factor of the first solve's matrix took 50–80 (Table IV.6, cycle 0).
    #[test]
    fn one_level_solves_are_exact_for_every_active_set() {
        let mesh = Mesh::new([0.0, 2.0], [0.0, 1.0], 16, 8);
        let system = assembled(&mesh, 1, 0.5);
        let constraints = system.constraints.eliminated();
        let mut mg = MultigridSolver::default();
        mg.set_hierarchy(vertex_hierarchy(&mesh, &system.dofs.vertices), 1);
        let free: Vec<usize> = (0..system.dofs.n_dofs())
            .filter(|d| constraints.iter().all(|&(c, _)| c != *d))
            .collect();
        for active in [&free[..0], &free[10..40], &free[25..60]] {
            let mut eliminated = constraints.clone();
            eliminated.extend(active.iter().map(|&d| (d, 0.1)));
            let u = mg
                .solve_overlay(
                    system.matrix(),
                    &system.rhs,
                    &eliminated,
                    constraints.len(),
                    Accuracy::Full,
                )
                .unwrap();
            let direct = DirectSolver::cholesky()
                .solve(system.matrix(), &system.rhs, &eliminated)
                .unwrap();
            let diff = max_difference(&direct, &u);
            assert!(diff < 1e-12, "{} active: max |Δu| = {diff:e}", active.len());
        }
        let iterations = mg.take_iterations();
        assert!(iterations.iter().all(|&k| k <= 1), "{iterations:?}");
    }

    /// The CG iterations do not grow with the mesh: graded meshes from about 2 000 to 130 000
    /// dofs, with hanging vertices on every level, take the same number within 2.
    #[test]
    fn iterations_are_bounded_independently_of_the_mesh_size() {
        let mut counts = Vec::new();
        for extra in [0, 2, 4] {
            let mut mesh = graded_mesh(4);
            for _ in 0..extra {
                mesh.refine_global().unwrap();
            }
            let system = assembled(&mesh, 1, 0.0);
            let mut mg = MultigridSolver::default();
            mg.set_hierarchy(vertex_hierarchy(&mesh, &system.dofs.vertices), 1);
            mg.solve(
                system.matrix(),
                &system.rhs,
                &system.constraints.eliminated(),
            )
            .unwrap();
            counts.push((system.dofs.n_dofs(), mg.take_iterations()[0]));
        }
        let (lo, hi) = counts
            .iter()
            .fold((usize::MAX, 0), |(lo, hi), &(_, k)| (lo.min(k), hi.max(k)));
        assert!(hi <= lo + 2 && hi <= 15, "(dofs, iterations): {counts:?}");
        assert!(
            counts[2].0 > 50 * counts[0].0 / 2,
            "(dofs, iterations): {counts:?}"
        );
    }
}
