//! The adaptation strategies: what changes between two cycles. Fixed-number grid marking, the
//! model strategies (Algorithms III.2, III.3: faces move between z and Signorini) and model and
//! grid together (Algorithm III.25); each changes the [`Discretisation`] its way.

use std::collections::{BTreeSet, HashMap};

use super::problem::{Discretisation, Estimate};
use crate::adaptivity::model::{fixed_fraction, sorted_error, Partition};
use crate::adaptivity::{mark_fixed_number, mark_fixed_number_split, rounded_measure, split_order};
use crate::estimators::FaceIndicators;
use crate::experiment::{ModelAlgorithm, Scene, Ties};
use crate::mesh::{BoundaryFace, Mesh, Side};

/// One adaptation step between two solves.
pub trait Adaptation {
    /// Change the discretisation according to the estimate of the solve just done.
    fn adapt(&mut self, disc: &mut Discretisation, estimate: &Estimate) -> Result<(), String>;
}

/// Fixed-number grid marking of every Chapter IV grid-adaptive run (refine the fraction
/// `refine` of the cells with the largest η_Q, coarsen the fraction `coarsen` with the smallest,
/// [`mark_fixed_number`], or [`mark_fixed_number_split`] with `ties = "split"`); indicators at
/// or below the estimate's noise floor count as zero.
pub struct FixedNumber {
    pub refine: f64,
    pub coarsen: f64,
    pub ties: Ties,
}

impl Adaptation for FixedNumber {
    fn adapt(&mut self, disc: &mut Discretisation, estimate: &Estimate) -> Result<(), String> {
        let floor = estimate.noise_floor.unwrap_or(f64::NEG_INFINITY);
        let eta: Vec<f64> = estimate
            .cells
            .iter()
            .map(|&e| if e < floor { 0.0 } else { e.sqrt() })
            .collect();
        self.refine(&mut disc.mesh, &eta)
    }
}

impl FixedNumber {
    /// Mark by the indicators η_Q (one per active cell) and refine and coarsen `mesh`.
    fn refine(&self, mesh: &mut Mesh, eta: &[f64]) -> Result<(), String> {
        let marking = match self.ties {
            Ties::Band => mark_fixed_number(
                eta,
                |k| rounded_measure(mesh, mesh.active()[k]),
                self.refine,
                self.coarsen,
            ),
            Ties::Split => mark_fixed_number_split(
                eta,
                |k| split_order(mesh, mesh.active()[k]),
                self.refine,
                self.coarsen,
            ),
        };
        mesh.refine_and_coarsen(&marking.refine, &marking.coarsen)
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
        disc.accurate_faces = self.mark(&estimate.faces, &disc.accurate_faces)?;
        Ok(())
    }
}

impl ModelMarking {
    /// The Signorini faces after marking `faces` (with their indicators) whose Signorini faces
    /// were `accurate`.
    fn mark(
        &self,
        faces: &FaceIndicators,
        accurate: &BTreeSet<BoundaryFace>,
    ) -> Result<BTreeSet<BoundaryFace>, String> {
        let eps: Vec<f64> = faces.iter().map(|&(_, e)| e).collect();
        let mut partition = face_partition(faces, accurate);
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
        Ok(faces
            .iter()
            .zip(partition.accurate())
            .filter(|(_, &accurate)| accurate)
            .map(|((f, _), _)| *f)
            .collect())
    }
}

/// Algorithm III.25 (balance of model and grid refinement, §IV.2.4): the indicators of both
/// errors are balanced by (III.93) with α ∈ (0, 1),
///
/// ε̃_m = ε_m where ε_m ≥ α ε_d, else 0;   ε̃_d = ε_d where ε_d ≥ α ε_m, else 0;
///
/// then the model is marked with ε̃_m ([`ModelMarking`], Algorithm III.3 in the thesis) and the
/// grid with ε̃_d ([`FixedNumber`], 30 %/3 %), in this order (the algorithm's two `refine`
/// lines). Model indicators live on contact faces and grid indicators on cells:
/// * a face f compares ε^m(f) with η of its cell K(f);
/// * a cell K compares η_K with ε^m(K) = (Σ ε^m(f)²)^{1/2} over its **z-faces**: the thesis
///   says the model error "of course only appears on the z-faces" (§IV.2.4), so a cell whose
///   contact face is already Signorini has no model error to balance (docs/estimators.md §7
///   sums over all its contact faces; that reading differs only on cells with an S-face).
///
/// After refinement a face's children inherit its model; a face made by coarsening is
/// Signorini if any of the faces it replaces was ([`inherit_models`]).
///
/// Readings of the printed algorithm: α is not stated (default 0.5, `study.balance`);
/// "(ε^d)² ← (ε^d)² + ε^d(Q)" misses a square and is indented under "if Q ∈ 𝕋_c" (read: the
/// squares of all cells); the loop test compares the sum of squares with ε₀ unsquared (read:
/// ε₀²); "p_a" is III.3's p_r. The loop test never stops a Chapter IV run (every table prints
/// its ten cycles), so the study runs its printed cycles and ε₀ acts inside III.3 only.
pub struct Balanced {
    pub model: ModelMarking,
    pub grid: FixedNumber,
    /// α of (III.93).
    pub alpha: f64,
}

impl Adaptation for Balanced {
    fn adapt(&mut self, disc: &mut Discretisation, estimate: &Estimate) -> Result<(), String> {
        let mesh = &disc.mesh;
        let eta: Vec<f64> = estimate.cells.iter().map(|e| e.sqrt()).collect();
        if eta.len() != mesh.n_active() {
            return Err(format!(
                "the balance (III.93) needs one discretisation indicator per cell: {} for {} \
                 active cells",
                eta.len(),
                mesh.n_active()
            ));
        }
        let cell_of = contact_cells(mesh, &estimate.faces)?;
        let mut model_of_cell = vec![0.0; eta.len()];
        for (&k, (f, e)) in cell_of.iter().zip(&estimate.faces) {
            if !disc.accurate_faces.contains(f) {
                model_of_cell[k] += e * e;
            }
        }
        let alpha = self.alpha;
        let model_tilde: FaceIndicators = estimate
            .faces
            .iter()
            .zip(&cell_of)
            .map(|(&(f, e), &k)| (f, if e >= alpha * eta[k] { e } else { 0.0 }))
            .collect();
        let grid_tilde: Vec<f64> = eta
            .iter()
            .zip(&model_of_cell)
            .map(|(&d, &m2)| if d >= alpha * m2.sqrt() { d } else { 0.0 })
            .collect();
        let accurate = self.model.mark(&model_tilde, &disc.accurate_faces)?;
        self.grid.refine(&mut disc.mesh, &grid_tilde)?;
        let sides: BTreeSet<Side> = estimate.faces.iter().map(|(f, _)| f.side).collect();
        disc.accurate_faces = inherit_models(&accurate, &boundary_faces(&disc.mesh, &sides));
        Ok(())
    }
}

/// The active cell (index into `mesh.active()`) of each face of `faces`, in their order, or the
/// first face that is not a boundary face of the mesh.
fn contact_cells(mesh: &Mesh, faces: &FaceIndicators) -> Result<Vec<usize>, String> {
    let cell_of: HashMap<BoundaryFace, usize> = mesh
        .active()
        .iter()
        .enumerate()
        .flat_map(|(k, &c)| mesh.boundary_faces_of(c).map(move |f| (f, k)))
        .collect();
    faces
        .iter()
        .map(|(f, _)| {
            cell_of.get(f).copied().ok_or_else(|| {
                format!(
                    "the balance (III.93): the contact face {f:?} is not a boundary face of the \
                     current mesh"
                )
            })
        })
        .collect()
}

/// The boundary faces of `mesh` on `sides`.
pub fn boundary_faces(mesh: &Mesh, sides: &BTreeSet<Side>) -> Vec<BoundaryFace> {
    let mut faces: Vec<BoundaryFace> = mesh
        .active()
        .iter()
        .flat_map(|&c| mesh.boundary_faces_of(c))
        .filter(|f| sides.contains(&f.side))
        .collect();
    faces.sort();
    faces
}

/// The Signorini faces among `faces` (a new mesh's contact faces) when `accurate` were the
/// Signorini faces of the old one: a face that was there keeps its model, a refined face's
/// children inherit it, and a face made by coarsening is Signorini if any face it replaces was.
pub fn inherit_models(
    accurate: &BTreeSet<BoundaryFace>,
    faces: &[BoundaryFace],
) -> BTreeSet<BoundaryFace> {
    let ancestors_of_accurate: BTreeSet<BoundaryFace> = accurate
        .iter()
        .flat_map(|f| std::iter::successors(f.parent(), BoundaryFace::parent))
        .collect();
    faces
        .iter()
        .copied()
        .filter(|f| {
            accurate.contains(f)
                || ancestors_of_accurate.contains(f)
                || std::iter::successors(f.parent(), BoundaryFace::parent)
                    .any(|a| accurate.contains(&a))
        })
        .collect()
}

/// The load steps of the U-O forming (§IV.2.4.7): "for each step we perform 4 (model- and
/// grid-) refinement cycles. After this we add to each vertex of the grid the local deformation
/// and use this deformed grid for the next step". Between the cycles of a step the model and
/// the grid adapt by [`Balanced`]; after the step's last cycle the body moves by the
/// displacement of its coarse vertices ([`Estimate::body_motion`]) and the next step starts
/// from the moved coarse cells ([`Discretisation::next_load_step`]; kept meshes would grow
/// without bound).
pub struct LoadSteps {
    /// The cycles of one step.
    pub cycles: usize,
    pub model_and_grid: Balanced,
    /// The scene's refinements of the coarse cells, applied to every moved body.
    pub scene: Scene,
    /// Cycles done so far.
    done: usize,
}

impl LoadSteps {
    pub fn new(cycles: usize, model_and_grid: Balanced, scene: Scene) -> LoadSteps {
        LoadSteps {
            cycles,
            model_and_grid,
            scene,
            done: 0,
        }
    }
}

impl Adaptation for LoadSteps {
    fn adapt(&mut self, disc: &mut Discretisation, estimate: &Estimate) -> Result<(), String> {
        self.done += 1;
        if !self.done.is_multiple_of(self.cycles) {
            return self.model_and_grid.adapt(disc, estimate);
        }
        let motion = estimate
            .body_motion
            .as_deref()
            .ok_or("a load step needs the displacement of the body's coarse vertices")?;
        *disc = disc.next_load_step(&self.scene, motion)?;
        Ok(())
    }
}
