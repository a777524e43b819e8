//! A-posteriori error estimators of Chapter III with the conventions that reproduce the printed
//! thesis numbers (docs/estimators.md §1.3): h_Q = cell diameter, ½ inside the norm on interior
//! faces, the full residual on Neumann faces, constant c = 1. Every estimator returns the squared
//! indicator η_Q² per active cell; the printed estimate is √(Σ_Q η_Q²).

pub mod contact;
pub mod contact_model;
pub mod elasticity;
pub mod reynolds;
pub mod substokes;

use rayon::prelude::*;

use crate::fe::cell_values::CellValues;
use crate::mesh::{BoundaryFace, CellId, Face, Mesh, Neighbor, Side};

/// The loop of every residual estimator: `cell(k, c, values)` for each active cell (k its index
/// in `mesh.active()`, c its id), Q₁ on the cell at the points of `rule`, in parallel; the
/// results in the order of the active cells.
pub fn per_cell<T: Send, const N: usize>(
    mesh: &Mesh,
    rule: &[(f64, f64, f64); N],
    cell: impl Fn(usize, CellId, &CellValues<N>) -> T + Sync + Send,
) -> Vec<T> {
    mesh.active()
        .par_iter()
        .enumerate()
        .map(|(k, &c)| cell(k, c, &CellValues::new(mesh.cell_shape(c), rule)))
        .collect()
}

/// A straight piece of a cell face with what lies on its other side.
#[derive(Clone, Copy, Debug)]
pub struct FaceSegment {
    pub a: [f64; 2],
    pub b: [f64; 2],
    /// Active index of the neighbouring cell, `None` on the boundary.
    pub neighbor: Option<usize>,
}

impl FaceSegment {
    pub fn length(&self) -> f64 {
        (self.b[0] - self.a[0]).hypot(self.b[1] - self.a[1])
    }

    /// Point at parameter t ∈ [0, 1].
    #[inline]
    pub fn at(&self, t: f64) -> [f64; 2] {
        [
            self.a[0] + t * (self.b[0] - self.a[0]),
            self.a[1] + t * (self.b[1] - self.a[1]),
        ]
    }
}

/// The pieces of face `face` of active cell `c`: one piece (boundary, same-level or coarser
/// neighbour) or two (two finer neighbours; hanging faces are integrated over the fine
/// sub-faces). Returns the boundary side if the face lies on one.
pub fn face_segments(mesh: &Mesh, c: CellId, face: Face) -> (Option<Side>, Vec<FaceSegment>) {
    let [pa, pb] = mesh.cell_shape(c).face_vertices(face);
    match mesh.neighbor(c, face) {
        Neighbor::Boundary(side) => (
            Some(side),
            vec![FaceSegment {
                a: pa,
                b: pb,
                neighbor: None,
            }],
        ),
        Neighbor::Same(n) | Neighbor::Coarser(n) => (
            None,
            vec![FaceSegment {
                a: pa,
                b: pb,
                neighbor: Some(mesh.active_index(n)),
            }],
        ),
        Neighbor::Finer([n0, n1]) => {
            let mid = [(pa[0] + pb[0]) / 2.0, (pa[1] + pb[1]) / 2.0];
            (
                None,
                vec![
                    FaceSegment {
                        a: pa,
                        b: mid,
                        neighbor: Some(mesh.active_index(n0)),
                    },
                    FaceSegment {
                        a: mid,
                        b: pb,
                        neighbor: Some(mesh.active_index(n1)),
                    },
                ],
            )
        }
    }
}

/// √(Σ η_Q²).
pub fn total(indicators_squared: &[f64]) -> f64 {
    indicators_squared.iter().sum::<f64>().sqrt()
}

/// Indicators on boundary faces, keyed by their stable ids ([`BoundaryFace`]) and sorted by them:
/// the units of model adaptivity (the contact faces f ⊂ Γ_C of §III.1.1).
pub type FaceIndicators = Vec<(BoundaryFace, f64)>;
