//! What a study keeps of its cycles: one row per printed solve (named columns, the ratio beside
//! the estimate, seconds per phase), the meshes of the last printed cycles, and the probes and
//! figures of the last one.

use super::error::StudyError;
use super::problem::{Discretisation, Estimate, KeptSolve, Problem, Solution};
use super::transfer::evaluate;
use super::{Solve, Tier};
use crate::adaptivity::model::ModelUnit;
use crate::experiment::Experiment;
use crate::fe::DofMap;
use crate::mesh::{CellId, Mesh, Side};
use crate::models::elasticity::Elasticity;
use crate::results::{
    columns, CellBox, FaceModel, LastMesh, MeshField, MeshPicture, PartitionPicture, PhaseSeconds,
    Probe, Row, RunResult, Value, VtuOutput,
};

/// Builds the [`RunResult`] of one study.
pub struct Recorder<'a> {
    experiment: &'a Experiment,
    result: RunResult,
    /// Printed rows of the tier.
    printed: usize,
    /// The seconds of the cycles of the current load step before its printed one.
    step_seconds: PhaseSeconds,
    /// The printed solves, where the problem measures its error against a reference
    /// ([`Problem::keeps_solves`]).
    kept: Vec<KeptSolve>,
}

impl<'a> Recorder<'a> {
    pub fn new(experiment: &'a Experiment, tier: Tier, printed: usize) -> Recorder<'a> {
        let d = experiment.scene.domain;
        Recorder {
            experiment,
            result: RunResult {
                notes: experiment.notes.clone(),
                related: experiment.related.clone(),
                ..RunResult::new(
                    &experiment.table,
                    &experiment.section,
                    &experiment.title,
                    tier.name(),
                    [d.x[0], d.x[1], d.y[0], d.y[1]],
                )
            },
            printed,
            step_seconds: PhaseSeconds::default(),
            kept: Vec::new(),
        }
    }

    /// Record a solve: its row if it is printed (active cells, the problem's dofs, the
    /// estimate's columns with the ratio after `estimate`, the solver's counters), the mesh of
    /// the last four printed cycles (of every printed cycle, its accurate cells shaded, where
    /// the models of cells are marked), the partition of the contact faces where their models
    /// are marked, and probes and figures of the last one.
    pub fn cycle(
        &mut self,
        solve: &Solve,
        disc: &Discretisation,
        dofs: &DofMap,
        solution: &Solution,
        estimate: &Estimate,
        problem: &mut dyn Problem,
    ) {
        let Some(cycle) = solve.row else {
            return;
        };
        // A study that marks the models of cells draws its partition on the mesh of every
        // printed cycle (its accurate cells shaded); the others draw the last four meshes.
        let marks_cells = estimate.models.iter().any(|(u, _)| u.face().is_none());
        if marks_cells || cycle + 4 >= self.printed {
            let mut picture = mesh_picture(&disc.mesh, cycle);
            picture.shaded = shaded_cells(disc);
            self.result.meshes.push(picture);
        }
        let last = cycle + 1 == self.printed;
        if last && problem.vertex_field() {
            self.result.probes = self.probes(disc, dofs, solution, &*problem);
        }
        // The meshes of the VTU files: the last one, or every printed cycle's (`--vtu`).
        let vtu = match self.experiment.study.vtu {
            VtuOutput::None => false,
            VtuOutput::Last => last,
            VtuOutput::All => true,
        };
        if vtu && problem.vertex_field() {
            let mesh = last_mesh(disc, dofs, solution, estimate, &*problem, cycle);
            if last {
                self.result.last_mesh = Some(mesh);
            } else {
                self.result.cycle_meshes.push(mesh);
            }
        }
        // A load-step study draws the body after every step (the frames of its animation).
        let load_steps = problem.rows_are_load_steps();
        if last || load_steps {
            let pictures = problem.pictures(disc, dofs, solution, cycle);
            self.result.deformed.extend(pictures.deformed);
            self.result.fields.extend(pictures.fields);
            if pictures.cuts.is_some() {
                self.result.cuts = pictures.cuts;
            }
        }
        if self.experiment.study.kind().adapts_model() && !marks_cells {
            self.result
                .partitions
                .push(partition_picture(disc, estimate, cycle));
        }
        let mut row = Row::new(cycle)
            .count(columns::ACTIVE_CELLS, disc.mesh.n_active())
            .count(columns::DOFS, problem.n_dofs(dofs));
        for (name, value) in &estimate.columns {
            row.columns.push((name.clone(), value.defined()));
            // The ratio of successive estimates: not between load steps, whose bodies differ.
            if name == columns::ESTIMATE && !load_steps {
                let before = self.result.rows.last().and_then(|r| r.estimate());
                let ratio = match (value, before) {
                    (Value::Real(Some(now)), Some(before)) => Some(now / before),
                    _ => None,
                };
                row = row.real(columns::RATIO, ratio);
            }
        }
        for (name, n) in &solution.counters {
            row.columns.push((name.clone(), Value::Count(*n)));
        }
        for (name, value) in problem.quantities(disc, dofs, solution) {
            row = row.real(&name, Some(value));
        }
        // The energy and the kept solves serve the true error only: a run that does not measure
        // it (an alternative reading) computes neither.
        let measures = self.experiment.study.true_error;
        if measures {
            if let Some(energy) = problem.energy(disc, dofs, solution) {
                row = row.real(columns::ENERGY, Some(energy));
            }
        }
        if measures && problem.keeps_solves() {
            self.kept.push(KeptSolve {
                cycle,
                estimate: row.estimate(),
                disc: disc.clone(),
                dofs: dofs.clone(),
                u: solution.u.clone(),
            });
        }
        self.result.rows.push(row);
    }

    /// The seconds per phase of a printed solve; in a load-step study the sums over the cycles
    /// of the step.
    pub fn seconds(&mut self, solve: &Solve, seconds: PhaseSeconds) {
        let seconds = match solve.step {
            Some(_) => {
                self.step_seconds = self.step_seconds.plus(&seconds);
                if solve.row.is_none() {
                    return;
                }
                std::mem::take(&mut self.step_seconds)
            }
            None => seconds,
        };
        if let (Some(cycle), Some(row)) = (solve.row, self.result.rows.last_mut()) {
            if row.cycle == cycle {
                row.seconds = seconds;
            }
        }
    }

    /// The result, with the measured errors ([`super::accuracy::add_errors`]), the problem's
    /// notes and the warnings of the file and the run.
    pub fn finish(mut self, problem: &mut dyn Problem) -> Result<RunResult, StudyError> {
        if self.experiment.study.true_error {
            super::accuracy::add_errors(&mut self.result, problem, &self.kept)
                .map_err(|e| e.context("the true error against the reference"))?;
        }
        self.result.notes.extend(problem.notes());
        self.result.cavitation_ran = problem.cavitation_ran();
        self.result.warnings = super::warnings::of_run(self.experiment, &self.result.rows)
            .iter()
            .map(ToString::to_string)
            .collect();
        Ok(self.result)
    }

    /// Probe values at every (x, y) of the experiment's probe lists.
    fn probes(
        &self,
        disc: &Discretisation,
        dofs: &DofMap,
        solution: &Solution,
        problem: &dyn Problem,
    ) -> Vec<Probe> {
        let probes = &self.experiment.probes;
        let mut out = Vec::new();
        for &y in &probes.y {
            for &x in &probes.x {
                for name in &probes.components {
                    let Some(comp) = problem.component(name) else {
                        continue;
                    };
                    if let Some(value) = evaluate(&disc.mesh, dofs, &solution.u, comp, [x, y]) {
                        out.push(Probe {
                            x,
                            y,
                            component: name.clone(),
                            value,
                        });
                    }
                }
            }
        }
        out
    }
}

/// The active cells of a mesh after a cycle, for the report.
pub fn mesh_picture(mesh: &Mesh, cycle: usize) -> MeshPicture {
    MeshPicture {
        cycle,
        cells: mesh.active().iter().map(|&c| cell_box(mesh, c)).collect(),
        levels: mesh.active().iter().map(|&c| mesh.level(c)).collect(),
        shaded: Vec::new(),
    }
}

/// The active cells of `disc` on the accurate model (in the order of `mesh.active()`), as
/// boxes.
fn shaded_cells(disc: &Discretisation) -> Vec<CellBox> {
    let mesh = &disc.mesh;
    if !disc.models.accurate().iter().any(|u| u.face().is_none()) {
        return Vec::new();
    }
    mesh.active()
        .iter()
        .filter(|&&c| disc.models.is_accurate(ModelUnit::Cell(mesh.cell_key(c))))
        .map(|&c| cell_box(mesh, c))
        .collect()
}

/// The box of cell `c`.
fn cell_box(mesh: &Mesh, c: CellId) -> CellBox {
    let b = mesh.cell_box(c);
    CellBox {
        x0: b[0],
        y0: b[1],
        x1: b[2],
        y1: b[3],
    }
}

/// The solution components written as vectors in the plane: the displacement (s₁, s₂) of the
/// elasticity and contact problems and the flow rate (χ₁, χ₂) of the SubStokes model.
const VECTORS: [(&str, [&str; 2]); 2] = [("displacement", ["s1", "s2"]), ("chi", ["chi1", "chi2"])];

/// The last printed mesh and its fields (`data/<table>.vtu`): per vertex the solution
/// components ([`VECTORS`] and the film pressure `psi`), for a thin film `cavitation` (1 where
/// the cavitation model is on and ψ_h ≤ 0, the zone the pressure map outlines), `hanging` (1 at
/// hanging vertices, whose values follow from their edge's ends) and the problem's
/// [`Problem::point_sets`] (the contact set); per cell the indicators η_Q² of the grid marking
/// (`eta_squared`, where the estimate has them per cell) and the refinement `level`.
fn last_mesh(
    disc: &Discretisation,
    dofs: &DofMap,
    solution: &Solution,
    estimate: &Estimate,
    problem: &dyn Problem,
    cycle: usize,
) -> LastMesh {
    let vertices = &dofs.vertices;
    let nc = dofs.n_components;
    let u = &solution.u;
    let component = |c: usize| -> Vec<f64> { (0..vertices.len()).map(|v| u[v * nc + c]).collect() };
    let mut point_fields = Vec::new();
    for (name, [a, b]) in VECTORS {
        if let (Some(a), Some(b)) = (problem.component(a), problem.component(b)) {
            let values = (0..vertices.len())
                .flat_map(|v| [u[v * nc + a], u[v * nc + b]])
                .collect();
            point_fields.push(MeshField::real(name, 2, values));
        }
    }
    if let Some(psi) = problem.component("psi") {
        let psi = component(psi);
        // The cavitation zone only where the cavitation model ran.
        let zone = (problem.cavitation_ran() == Some(true))
            .then(|| MeshField::flags("cavitation", psi.iter().map(|&p| p <= 0.0)));
        // The film's gap g and the mean pressure p = ψ/g (ψ = ∫p dx₃ across the gap).
        let film = problem.film().map(|film| {
            let gap: Vec<f64> = vertices.coords.iter().map(|&x| film.gap(x).0).collect();
            let pressure = psi.iter().zip(&gap).map(|(p, g)| p / g).collect();
            [
                MeshField::real("p", 1, pressure),
                MeshField::real("g", 1, gap),
            ]
        });
        point_fields.push(MeshField::real("psi", 1, psi));
        point_fields.extend(zone);
        point_fields.extend(film.into_iter().flatten());
    }
    point_fields.extend(problem.point_sets(dofs));
    point_fields.push(MeshField::flags(
        "hanging",
        vertices.is_hanging.iter().copied(),
    ));
    let mesh = &disc.mesh;
    let mut cell_fields = Vec::new();
    if estimate.cells.len() == mesh.n_active() {
        cell_fields.push(MeshField::indicator("eta_squared", estimate.cells.clone()));
    }
    if let Some(body) = problem.elasticity() {
        cell_fields.extend(stresses(body, mesh, dofs, u));
    }
    let levels = mesh.active().iter().map(|&c| f64::from(mesh.level(c)));
    cell_fields.push(MeshField::small("level", levels.collect()));
    LastMesh {
        cycle,
        points: vertices.coords.clone(),
        // Lexicographic corners (ll, lr, ul, ur) to counter-clockwise (ll, lr, ur, ul).
        cells: vertices
            .cell_vertices
            .iter()
            .map(|&[ll, lr, ul, ur]| [ll, lr, ur, ul])
            .collect(),
        point_fields,
        cell_fields,
    }
}

/// The stresses of a solid at the cells' centres, as cell fields: `stress`, the tensor
/// σ(s_h) = 2μ ε(s_h) + 2λ (div s_h) I of the model (§1 of docs/models.md, the thesis's 2λ) in
/// ParaView's six-component symmetric order (xx, yy, zz, xy, yz, xz; the 2-D model has no zz,
/// yz, xz: written 0), and `von_mises`, √(σ₁₁² − σ₁₁σ₂₂ + σ₂₂² + 3σ₁₂²), the von Mises stress of
/// that in-plane tensor (σ₃₃ = 0: the thesis names neither plane strain nor plane stress). The
/// centre is where the gradient of a Q₁ displacement is most accurate.
fn stresses(body: &Elasticity, mesh: &Mesh, dofs: &DofMap, u: &[f64]) -> [MeshField; 2] {
    let (tensor, mises): (Vec<[f64; 6]>, Vec<f64>) = mesh
        .active()
        .iter()
        .enumerate()
        .map(|(k, &c)| {
            let corners = mesh.cell_shape(c).vertices();
            let centre = [0, 1].map(|i| corners.iter().map(|p| p[i]).sum::<f64>() / 4.0);
            let s = body.stress(Elasticity::gradient_at(mesh, dofs, u, k, centre));
            let (xx, yy, xy) = (s[0][0], s[1][1], s[0][1]);
            let mises = (xx * xx - xx * yy + yy * yy + 3.0 * xy * xy).sqrt();
            ([xx, yy, 0.0, xy, 0.0, 0.0], mises)
        })
        .unzip();
    [
        MeshField::real("stress", 6, tensor.into_iter().flatten().collect()),
        MeshField::real("von_mises", 1, mises),
    ]
}

/// The contact faces of a model-adaptive cycle with their models and indicators.
fn partition_picture(disc: &Discretisation, estimate: &Estimate, cycle: usize) -> PartitionPicture {
    let mesh = &disc.mesh;
    let (_, top) = mesh.extent();
    let faces = estimate
        .models
        .iter()
        .filter_map(|&(u, error)| Some((u.face()?, error)))
        .map(|(f, error)| {
            let y = if f.side == Side::Top { top } else { 0 };
            FaceModel {
                side: f.side.name().to_string(),
                x0: mesh.point((f.start, y))[0],
                x1: mesh.point((f.end(), y))[0],
                accurate: disc.models.is_accurate_face(f),
                error,
            }
        })
        .collect();
    PartitionPicture { cycle, faces }
}
