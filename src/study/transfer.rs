//! The previous cycle's solution on the next mesh: the linearisation point s₀ and the warm start
//! of the contact active set, the initial active set of the cavitation solve. One transfer for
//! every problem: the Q₁ field of the old mesh evaluated at the points of the new one.

use super::error::StudyError;
use super::problem::Discretisation;
use rayon::prelude::*;

use crate::fe::cell_values::evaluate_at;
use crate::fe::DofMap;
use crate::mesh::{CellId, Mesh};
use crate::models::contact::ContactBoundary;

/// Value of component `comp` of the Q₁ field `u` at a physical point (None outside the domain).
pub fn evaluate(mesh: &Mesh, dofs: &DofMap, u: &[f64], comp: usize, p: [f64; 2]) -> Option<f64> {
    let c = mesh.locate(p)?;
    Some(evaluate_in(mesh, dofs, u, comp, c, p))
}

/// [`evaluate`] in the active cell `c`, which holds `p`.
fn evaluate_in(mesh: &Mesh, dofs: &DofMap, u: &[f64], comp: usize, c: CellId, p: [f64; 2]) -> f64 {
    let k = mesh.active_index(c);
    let shape = mesh.cell_shape(c);
    evaluate_at(&shape, dofs.corner_values(u, k, comp), p).0
}

/// Mesh, dofs and solution of the previous cycle.
#[derive(Clone, Debug)]
pub struct PreviousSolution {
    pub mesh: Mesh,
    pub dofs: DofMap,
    pub u: Vec<f64>,
}

impl PreviousSolution {
    /// The solution `u` on the mesh of `disc` numbered by `dofs`, kept for the next cycle.
    pub fn of(disc: &Discretisation, dofs: DofMap, u: Vec<f64>) -> PreviousSolution {
        PreviousSolution {
            mesh: disc.mesh.clone(),
            dofs,
            u,
        }
    }

    /// Component `comp` of the previous solution at a physical point of the new mesh (None
    /// outside the previous mesh).
    pub fn value(&self, comp: usize, p: [f64; 2]) -> Option<f64> {
        evaluate(&self.mesh, &self.dofs, &self.u, comp, p)
    }
}

impl PreviousSolution {
    /// The previous solution at every vertex of the new dofs `dofs` on `mesh` (the warm start
    /// of an iterative solve): a vertex of both meshes keeps its value, a new one gets the
    /// previous field's value at its position (0 outside the previous mesh). On an unmoved mesh
    /// rebuilt from the previous one, the previous cell that holds a new vertex is found from
    /// the vertex's cell ([`Mesh::cell_at_vertex_in`]): the cell [`Mesh::locate`] finds at its
    /// position, without a descent from the root.
    pub fn on_vertices(&self, mesh: &Mesh, dofs: &DofMap) -> Vec<f64> {
        let nc = dofs.n_components;
        let old = &self.dofs.vertices;
        let new = &dofs.vertices;
        let unmoved = !mesh.is_moved() && !self.mesh.is_moved();
        let mut values = vec![0.0; new.len() * nc];
        values.par_chunks_mut(nc).enumerate().for_each(|(v, out)| {
            let found = old.find(new.keys[v]);
            let (key, p) = (new.keys[v], new.coords[v]);
            let cell = match found {
                None if unmoved => mesh.cell_at_vertex_in(&self.mesh, new.owner[v], key),
                _ => None,
            };
            debug_assert!(cell.is_none() || cell == self.mesh.locate(p));
            for (c, out) in out.iter_mut().enumerate() {
                *out = match (found, cell) {
                    (Some(w), _) => self.u[self.dofs.dof(w, c)],
                    (None, Some(cell)) => self.value_in(cell, c, p),
                    (None, None) => self.value(c, p).unwrap_or(0.0),
                };
            }
        });
        values
    }

    /// Component `comp` of the previous solution at the point `p` of its cell `cell`.
    fn value_in(&self, cell: CellId, comp: usize, p: [f64; 2]) -> f64 {
        evaluate_in(&self.mesh, &self.dofs, &self.u, comp, cell, p)
    }

    /// The previous solution at the contact vertices of the new dofs `dofs` (zero elsewhere):
    /// the linearisation point s₀ of the Signorini constraints and the warm start of a contact
    /// active set, or the contact vertex that lies outside the previous mesh.
    pub fn at_contact_vertices(
        &self,
        boundaries: &[ContactBoundary],
        dofs: &DofMap,
    ) -> Result<Vec<f64>, StudyError> {
        let mut s0 = vec![0.0; dofs.n_dofs()];
        for cb in boundaries {
            for v in dofs.vertices.side_vertices(cb.side) {
                let p = dofs.vertices.coords[v as usize];
                for comp in 0..2 {
                    s0[dofs.dof(v, comp)] = self.value(comp, p).ok_or_else(|| {
                        format!(
                            "transfer of s₀: the vertex ({}, {}) lies outside the previous mesh",
                            p[0], p[1]
                        )
                    })?;
                }
            }
        }
        Ok(s0)
    }
}
