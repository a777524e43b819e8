//! The adaptation strategies: what changes between two cycles. Fixed-number grid marking, the
//! model strategies (Algorithms III.2, III.3: units — contact faces or cells — move between the
//! coarse and the accurate model) and model and grid together (Algorithm III.25); each changes
//! the [`Discretisation`] its way.

use std::collections::{BTreeSet, HashMap};

use super::error::StudyError;
use super::problem::{Discretisation, Estimate, Models};
use crate::adaptivity::model::{
    fixed_fraction, inherit_models, sorted_error, ModelIndicators, ModelUnit, Partition,
};
use crate::adaptivity::{mark_fixed_number, mark_fixed_number_split, rounded_measure, split_order};
use crate::estimators::FaceIndicators;
use crate::experiment::{self, ModelAlgorithm, Scene, Ties};
use crate::mesh::{BoundaryFace, Mesh, MeshSmoothing, Side};

/// One adaptation step between two solves.
pub trait Adaptation {
    /// Change the discretisation according to the estimate of the solve just done.
    fn adapt(&mut self, disc: &mut Discretisation, estimate: &Estimate) -> Result<(), StudyError>;
}

/// Fixed-number grid marking of every Chapter IV grid-adaptive run (refine the fraction
/// `refine` of the cells with the largest η_Q, coarsen the fraction `coarsen` with the smallest,
/// [`mark_fixed_number`], or [`mark_fixed_number_split`] with `ties = "split"`); indicators at
/// or below the estimate's noise floor count as zero.
pub struct FixedNumber {
    pub refine: f64,
    pub coarsen: f64,
    pub ties: Ties,
    /// deal.II's mesh-smoothing flags of the scene ([`Scene::mesh_smoothing`]), applied to the
    /// marking before the refinement; none by default.
    pub smoothing: MeshSmoothing,
}

impl FixedNumber {
    /// The fixed-number marking of a study's grid fractions θ_r, θ_c.
    pub fn of(grid: experiment::GridFractions, ties: Ties) -> FixedNumber {
        FixedNumber {
            refine: grid.refine,
            coarsen: grid.coarsen,
            ties,
            smoothing: MeshSmoothing::default(),
        }
    }

    /// The same marking with the scene's mesh-smoothing flags.
    pub fn smoothed(self, smoothing: MeshSmoothing) -> FixedNumber {
        FixedNumber { smoothing, ..self }
    }
}

impl Adaptation for FixedNumber {
    fn adapt(&mut self, disc: &mut Discretisation, estimate: &Estimate) -> Result<(), StudyError> {
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
    fn refine(&self, mesh: &mut Mesh, eta: &[f64]) -> Result<(), StudyError> {
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
        mesh.refine_and_coarsen_smoothed(&marking.refine, &marking.coarsen, self.smoothing)
            .map_err(|e| StudyError::from(e).context("cannot refine the mesh after this cycle"))?;
        Ok(())
    }
}

/// The partition of the contact faces `faces` (in their order) with the Signorini faces
/// `accurate`.
pub fn face_partition(faces: &FaceIndicators, accurate: &BTreeSet<BoundaryFace>) -> Partition {
    Partition::from_accurate(faces.iter().map(|(f, _)| accurate.contains(f)).collect())
}

/// The adaptation of a study on fixed models and a fixed mesh: nothing changes between the
/// cycles (the all-z and all-Signorini variants of the cost study).
pub struct KeepModels;

impl Adaptation for KeepModels {
    fn adapt(
        &mut self,
        _disc: &mut Discretisation,
        _estimate: &Estimate,
    ) -> Result<(), StudyError> {
        Ok(())
    }
}

/// Model marking of the model-adaptive tables (§IV.2.3, §IV.3.4): the units with their
/// indicators ε^m ([`Estimate::models`]: contact faces in the stable geometric order, or cells)
/// move between the coarse model 𝕋_c (z-faces, Reynolds cells) and the accurate one 𝕋_a
/// (Signorini faces, SubStokes cells; [`Discretisation::models`]) by Algorithm III.2
/// ([`fixed_fraction`]) or III.3 ([`sorted_error`]); the mesh stays.
pub struct ModelMarking {
    pub algorithm: ModelAlgorithm,
    /// p_r.
    pub refine: f64,
    /// p_c.
    pub coarsen: f64,
    /// ε₀.
    pub tolerance: f64,
}

impl From<experiment::ModelFractions> for ModelMarking {
    fn from(model: experiment::ModelFractions) -> ModelMarking {
        ModelMarking {
            algorithm: model.algorithm,
            refine: model.refine,
            coarsen: model.coarsen,
            tolerance: model.tolerance,
        }
    }
}

impl Adaptation for ModelMarking {
    fn adapt(&mut self, disc: &mut Discretisation, estimate: &Estimate) -> Result<(), StudyError> {
        disc.models = Models::of_units(self.mark(&estimate.models, &disc.models)?);
        Ok(())
    }
}

impl ModelMarking {
    /// The accurate units after marking `units` (with their indicators, in their order) whose
    /// models were `models`.
    fn mark(
        &self,
        units: &ModelIndicators,
        models: &Models,
    ) -> Result<BTreeSet<ModelUnit>, StudyError> {
        let eps: Vec<f64> = units.iter().map(|&(_, e)| e).collect();
        let mut partition =
            Partition::from_accurate(units.iter().map(|&(u, _)| models.is_accurate(u)).collect());
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
                .map_err(|e| StudyError::from(e).context("model marking"))?;
            }
        }
        Ok(units
            .iter()
            .zip(partition.accurate())
            .filter(|(_, &accurate)| accurate)
            .map(|((u, _), _)| *u)
            .collect())
    }
}

/// What the grid marking of [`Balanced`] ranks: η_Q (the contact tables) or η_Q² (the
/// model-adaptive fluid film, whose split marking reads its tie band on the squares).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GridIndicator {
    Eta,
    EtaSquared,
}

/// Algorithm III.25 (balance of model and grid refinement, §IV.2.4): the indicators of both
/// errors are balanced by (III.93) with α ∈ [0, 1),
///
/// ε̃_m = ε_m where ε_m ≥ α ε_d, else 0;   ε̃_d = ε_d where ε_d ≥ α ε_m, else 0;
///
/// then the model is marked with ε̃_m ([`ModelMarking`], Algorithm III.3 in the thesis) and the
/// grid with ε̃_d ([`FixedNumber`], 30 %/3 %), in this order (the algorithm's two `refine`
/// lines). α = 0 keeps every indicator: the model-adaptive fluid film marks both from the
/// same cycle's indicators without a balance. Model indicators live on units, grid indicators
/// on cells:
/// * a unit compares its ε^m with η of its cell (a contact face f: its cell K(f); a cell: itself);
/// * a cell K compares η_K with ε^m(K) = (Σ ε^m(u)²)^{1/2} over its **coarse** units (z-faces):
///   the thesis says the model error "of course only appears on the z-faces" (§IV.2.4), so a
///   cell whose contact face is already Signorini has no model error to balance (summing over
///   all its contact faces differs only on cells with an S-face).
///
/// After refinement a unit's children inherit its model; a unit made by coarsening is accurate
/// if any of the units it replaces was ([`inherit_models`]).
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
    /// What the grid marking ranks.
    pub grid_indicator: GridIndicator,
}

impl Adaptation for Balanced {
    fn adapt(&mut self, disc: &mut Discretisation, estimate: &Estimate) -> Result<(), StudyError> {
        let mesh = &disc.mesh;
        let eta: Vec<f64> = estimate.cells.iter().map(|e| e.sqrt()).collect();
        if eta.len() != mesh.n_active() {
            return Err(StudyError::Failed(format!(
                "the balance (III.93) needs one discretisation indicator per cell: {} for {} \
                 active cells",
                eta.len(),
                mesh.n_active()
            )));
        }
        let cell_of = unit_cells(mesh, &estimate.models)?;
        let mut model_of_cell = vec![0.0; eta.len()];
        for (&k, (u, e)) in cell_of.iter().zip(&estimate.models) {
            if !disc.models.is_accurate(*u) {
                model_of_cell[k] += e * e;
            }
        }
        let alpha = self.alpha;
        let model_tilde: ModelIndicators = estimate
            .models
            .iter()
            .zip(&cell_of)
            .map(|(&(u, e), &k)| (u, if e >= alpha * eta[k] { e } else { 0.0 }))
            .collect();
        let ranked = match self.grid_indicator {
            GridIndicator::Eta => &eta,
            GridIndicator::EtaSquared => &estimate.cells,
        };
        let grid_tilde: Vec<f64> = eta
            .iter()
            .zip(&model_of_cell)
            .zip(ranked)
            .map(|((&d, &m2), &r)| if d >= alpha * m2.sqrt() { r } else { 0.0 })
            .collect();
        let accurate = self.model.mark(&model_tilde, &disc.models)?;
        self.grid.refine(&mut disc.mesh, &grid_tilde)?;
        let units = units_of(&disc.mesh, &estimate.models);
        disc.models = Models::of_units(inherit_models(&accurate, &units));
        Ok(())
    }
}

/// The active cell (index into `mesh.active()`) of each unit of `units`, in their order: a
/// face's cell, a cell's own index; or the first unit that is not on the current mesh.
fn unit_cells(mesh: &Mesh, units: &ModelIndicators) -> Result<Vec<usize>, StudyError> {
    let cell_of_face: HashMap<BoundaryFace, usize> = mesh
        .active()
        .iter()
        .enumerate()
        .flat_map(|(k, &c)| mesh.boundary_faces_of(c).map(move |f| (f, k)))
        .collect();
    let cell_of_key: HashMap<_, usize> = if units.iter().any(|(u, _)| u.face().is_none()) {
        mesh.active()
            .iter()
            .enumerate()
            .map(|(k, &c)| (mesh.cell_key(c), k))
            .collect()
    } else {
        HashMap::new()
    };
    units
        .iter()
        .map(|(u, _)| match u {
            ModelUnit::Face(f) => cell_of_face.get(f).copied().ok_or_else(|| {
                StudyError::Failed(format!(
                    "the balance (III.93): the contact face {f:?} is not a boundary face of the \
                     current mesh"
                ))
            }),
            ModelUnit::Cell(c) => cell_of_key.get(c).copied().ok_or_else(|| {
                StudyError::Failed(format!(
                    "the balance (III.93): the cell {c:?} is not an active cell of the mesh"
                ))
            }),
        })
        .collect()
}

/// The units of `mesh` of the kinds `units` has: the boundary faces on the sides of its faces
/// (sorted), then, if it has cells, every active cell (in the order of `mesh.active()`).
fn units_of(mesh: &Mesh, units: &ModelIndicators) -> Vec<ModelUnit> {
    let sides: BTreeSet<Side> = units
        .iter()
        .filter_map(|(u, _)| u.face())
        .map(|f| f.side)
        .collect();
    let mut out: Vec<ModelUnit> = boundary_faces(mesh, &sides)
        .into_iter()
        .map(ModelUnit::Face)
        .collect();
    if units.iter().any(|(u, _)| u.face().is_none()) {
        out.extend(
            mesh.active()
                .iter()
                .map(|&c| ModelUnit::Cell(mesh.cell_key(c))),
        );
    }
    out
}

/// [`inherit_models`] of the contact faces: the Signorini faces among `faces` (a new mesh's
/// contact faces) when `accurate` were the Signorini faces of the old one.
pub fn inherit_face_models(
    accurate: &BTreeSet<BoundaryFace>,
    faces: &[BoundaryFace],
) -> BTreeSet<BoundaryFace> {
    let units: Vec<ModelUnit> = faces.iter().copied().map(ModelUnit::Face).collect();
    let accurate = accurate.iter().copied().map(ModelUnit::Face).collect();
    inherit_models(&accurate, &units)
        .iter()
        .filter_map(ModelUnit::face)
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
    fn adapt(&mut self, disc: &mut Discretisation, estimate: &Estimate) -> Result<(), StudyError> {
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
