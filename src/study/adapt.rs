//! The adaptation strategies: what changes between two cycles. Fixed-number grid marking now;
//! the model strategies (Algorithms III.2, III.3: faces move between z and Signorini), model and
//! grid together (Algorithm III.25) and load steps are further implementations of
//! [`Adaptation`], each changing the [`Discretisation`] its way.

use std::collections::BTreeSet;

use super::problem::{Discretisation, Estimate};
use crate::adaptivity::model::{fixed_fraction, sorted_error, Partition};
use crate::adaptivity::{mark_fixed_number, rounded_measure};
use crate::estimators::FaceIndicators;
use crate::experiment::ModelAlgorithm;
use crate::mesh::BoundaryFace;

/// One adaptation step between two solves.
pub trait Adaptation {
    /// Change the discretisation according to the estimate of the solve just done.
    fn adapt(&mut self, disc: &mut Discretisation, estimate: &Estimate) -> Result<(), String>;
}

/// Fixed-number grid marking of every Chapter IV grid-adaptive run (refine the fraction
/// `refine` of the cells with the largest η_Q, coarsen the fraction `coarsen` with the smallest,
/// [`mark_fixed_number`]); indicators at or below the estimate's noise floor count as zero.
pub struct FixedNumber {
    pub refine: f64,
    pub coarsen: f64,
}

impl Adaptation for FixedNumber {
    fn adapt(&mut self, disc: &mut Discretisation, estimate: &Estimate) -> Result<(), String> {
        let floor = estimate.noise_floor.unwrap_or(f64::NEG_INFINITY);
        let eta: Vec<f64> = estimate
            .cells
            .iter()
            .map(|&e| if e < floor { 0.0 } else { e.sqrt() })
            .collect();
        let mesh = &disc.mesh;
        let marking = mark_fixed_number(
            &eta,
            |k| rounded_measure(mesh, mesh.active()[k]),
            self.refine,
            self.coarsen,
        );
        disc.mesh
            .refine_and_coarsen(&marking.refine, &marking.coarsen)
            .map_err(|e| format!("cannot refine the mesh after this cycle: {e}"))?;
        Ok(())
    }
}

/// The partition of the contact faces `faces` (in their order) with the Signorini faces
/// `accurate`.
pub fn face_partition(faces: &FaceIndicators, accurate: &BTreeSet<BoundaryFace>) -> Partition {
    Partition::from_accurate(faces.iter().map(|(f, _)| accurate.contains(f)).collect())
}

/// Model marking of the model-adaptive contact tables (§IV.2.3): the contact faces with their
/// indicators ε^m(f) ([`Estimate::faces`], in the stable geometric order) move between the
/// z-model (𝕋_c) and the Signorini model (𝕋_a, [`Discretisation::accurate_faces`]) by
/// Algorithm III.2 ([`fixed_fraction`]) or III.3 ([`sorted_error`]); the mesh stays.
pub struct ModelMarking {
    pub algorithm: ModelAlgorithm,
    /// p_r.
    pub refine: f64,
    /// p_c.
    pub coarsen: f64,
    /// ε₀.
    pub tolerance: f64,
}

impl Adaptation for ModelMarking {
    fn adapt(&mut self, disc: &mut Discretisation, estimate: &Estimate) -> Result<(), String> {
        let faces = &estimate.faces;
        let eps: Vec<f64> = faces.iter().map(|&(_, e)| e).collect();
        let mut partition = face_partition(faces, &disc.accurate_faces);
        match self.algorithm {
            ModelAlgorithm::FixedFraction => {
                fixed_fraction(&mut partition, &eps, self.refine, self.coarsen);
            }
            ModelAlgorithm::SortedError => {
                sorted_error(
                    &mut partition,
                    &eps,
                    self.refine,
                    self.coarsen,
                    self.tolerance,
                )
                .map_err(|e| format!("model marking: {e}"))?;
            }
        }
        disc.accurate_faces = faces
            .iter()
            .zip(partition.accurate())
            .filter(|(_, &accurate)| accurate)
            .map(|((f, _), _)| *f)
            .collect();
        Ok(())
    }
}
