//! A-posteriori error estimators of Chapter III with the conventions that reproduce the printed
//! thesis numbers (docs/estimators.md §1.3): h_Q = cell diameter, ½ inside the norm on interior
//! faces, the full residual on Neumann faces, constant c = 1. Every estimator returns the squared
//! indicator η_Q² per active cell; the printed estimate is √(Σ_Q η_Q²).

pub mod contact;
pub mod contact_model;
pub mod elasticity;
pub mod reynolds;
pub mod substokes;
pub mod true_error;

use rayon::prelude::*;

use crate::fe::cell_values::CellValues;
use crate::mesh::{BoundaryFace, CellId, Mesh};

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

pub use crate::mesh::{face_segments, FaceSegment};

/// √(Σ η_Q²).
pub fn total(indicators_squared: &[f64]) -> f64 {
    indicators_squared.iter().sum::<f64>().sqrt()
}

/// Indicators on boundary faces, keyed by their stable ids ([`BoundaryFace`]) and sorted by them:
/// the units of model adaptivity (the contact faces f ⊂ Γ_C of §III.1.1).
pub type FaceIndicators = Vec<(BoundaryFace, f64)>;
