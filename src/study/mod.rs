//! The cycle loop of a grid-adaptive study (DESIGN.md data flow), deal.II step-6 style:
//! setup → assemble → solve → estimate → record row → mark → refine.
//!
//! Only the effects a scene names are built: an elasticity scene never touches contact or
//! thin-film code.

use std::time::Instant;

pub mod contact;
pub mod elasticity;
pub mod reynolds;

use crate::adaptivity::{apply_noise_floor, mark_fixed_number, rounded_measure};
use crate::estimators;
use crate::experiment::{Cavitation, CavitationSource, Effect, ExperimentSpec};
use crate::fe::{DofMap, Rect, SolveBuffers, SparseSystem};
use crate::mesh::Mesh;
use crate::results::{
    CellBox, CycleRow, DeformedPicture, MeshPicture, PhaseSeconds, Probe, RunResult,
};
use crate::thesis::ThesisTable;

/// Which rows to compute: the quick tier of the tests or the full thesis sizes of the report.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tier {
    Quick,
    Full,
}

impl Tier {
    pub fn name(self) -> &'static str {
        match self {
            Tier::Quick => "quick",
            Tier::Full => "full",
        }
    }
}

/// A run that could not finish: names the table, the cycle and the reason.
#[derive(Debug, thiserror::Error)]
#[error("table {table}, cycle {cycle}: {message}")]
pub struct RunError {
    pub table: String,
    pub cycle: usize,
    pub message: String,
}

/// Progress callback: (table, cycles done, cycles in total).
pub type Progress<'a> = &'a (dyn Fn(&str, usize, usize) + Sync);

/// The printed thesis table of an experiment.
pub fn thesis_table(spec: &ExperimentSpec) -> ThesisTable {
    ThesisTable {
        table: spec.table.clone(),
        section: spec.section.clone(),
        columns: spec.thesis.columns.clone(),
        rows: spec.thesis.rows.clone(),
        duplicate_of: spec.thesis.duplicate_of.clone(),
        additive_part: spec.thesis.additive_part.clone(),
    }
}

/// An alternative reading of a scene that the report runs beside the experiment as written, to
/// show how much the choice matters.
pub struct AlternativeReading {
    /// What changes, for the report's heading.
    pub label: String,
    /// Suffix of the alternative's data file (`report/data/<table>.<suffix>.csv`).
    pub suffix: String,
    pub spec: ExperimentSpec,
}

/// The alternative readings the report compares an experiment with. For Reynolds with
/// cavitation and the printed γ₃c of (I.61), two readings of the source term R₃c:
/// the self-consistent 2γ₃ − γ₃c (spec/models.md §15 item 9; issue: "the report shows how much
/// it changes IV.65–IV.69"), and R₃ of (I.77), the source without cavitation, which the thesis's
/// code evidently used ([`CavitationSource::Reynolds`]).
pub fn alternative_readings(spec: &ExperimentSpec) -> Vec<AlternativeReading> {
    let Some(r) = &spec.scene.reynolds else {
        return Vec::new();
    };
    if r.cavitation == Cavitation::Off || r.cavitation_source != CavitationSource::Printed {
        return Vec::new();
    }
    let reading = |source: CavitationSource, label: &str, suffix: &str| {
        let mut alt = spec.clone();
        if let Some(ra) = alt.scene.reynolds.as_mut() {
            ra.cavitation_source = source;
        }
        AlternativeReading {
            label: label.into(),
            suffix: suffix.into(),
            spec: alt,
        }
    };
    vec![
        reading(
            CavitationSource::SelfConsistent,
            "R₃c from 2γ₃ − γ₃c instead of the printed γ₃c of (I.61) \
             (cavitation_source = \"self-consistent\")",
            "self-consistent",
        ),
        reading(
            CavitationSource::Reynolds,
            "R₃ of (I.77), the source without cavitation, in place of R₃c, as the thesis's code \
             evidently had it (cavitation_source = \"reynolds\")",
            "reynolds",
        ),
    ]
}

/// Number of printed rows of a tier.
pub fn printed_rows(spec: &ExperimentSpec, tier: Tier) -> usize {
    match tier {
        Tier::Quick => spec.study.quick_rows,
        Tier::Full => spec.study.rows,
    }
}

/// Run one experiment.
pub fn run(spec: &ExperimentSpec, tier: Tier, progress: Progress) -> Result<RunResult, RunError> {
    let effects = &spec.scene.effects;
    if effects.contains(&Effect::Contact) {
        contact::run(spec, tier, progress)
    } else if effects.contains(&Effect::Reynolds) {
        reynolds::run(spec, tier, progress)
    } else {
        run_grid_adaptive(
            spec,
            tier,
            progress,
            &mut elasticity::ElasticityStudy::new(spec),
        )
    }
}

fn new_mesh(spec: &ExperimentSpec) -> Mesh {
    let s = &spec.scene;
    let mut mesh = Mesh::new(s.domain.x, s.domain.y, s.coarse_cells[0], s.coarse_cells[1]);
    for _ in 0..s.global_refinements {
        mesh.refine_global();
    }
    mesh
}

fn empty_result(spec: &ExperimentSpec, tier: Tier) -> RunResult {
    let d = spec.scene.domain;
    RunResult {
        table: spec.table.clone(),
        section: spec.section.clone(),
        title: spec.title.clone(),
        tier: tier.name().to_string(),
        rows: Vec::new(),
        probes: Vec::new(),
        meshes: Vec::new(),
        deformed: Vec::new(),
        fields: Vec::new(),
        domain: [d.x[0], d.x[1], d.y[0], d.y[1]],
        notes: spec.notes.clone(),
    }
}

/// Cycles whose meshes go into the report: the last four printed ones.
fn picture_cycles(printed: usize) -> std::ops::Range<usize> {
    printed.saturating_sub(4)..printed
}

pub fn mesh_picture(mesh: &Mesh, cycle: usize) -> MeshPicture {
    MeshPicture {
        cycle,
        cells: mesh
            .active()
            .iter()
            .map(|&c| {
                let b = mesh.cell_box(c);
                CellBox {
                    x0: b[0],
                    y0: b[1],
                    x1: b[2],
                    y1: b[3],
                }
            })
            .collect(),
    }
}

/// Value of component `comp` of the Q₁ field `u` at a point (None outside the domain).
pub fn evaluate(mesh: &Mesh, dofs: &DofMap, u: &[f64], comp: usize, p: [f64; 2]) -> Option<f64> {
    let c = mesh.locate(p)?;
    let k = mesh.active_index(c);
    let r = Rect::from_box(mesh.cell_box(c));
    let (xi, eta) = r.reference(p);
    Some(r.eval(dofs.corner_values(u, k, comp), xi, eta).0)
}

/// Probe values after the last cycle at every (x, y) of the experiment's probe lists.
fn probes(
    spec: &ExperimentSpec,
    mesh: &Mesh,
    dofs: &DofMap,
    u: &[f64],
    model: &dyn AdaptiveModel,
) -> Vec<Probe> {
    let mut out = Vec::new();
    for &y in &spec.probes.y {
        for &x in &spec.probes.x {
            for name in &spec.probes.components {
                let comp = model.component(name);
                if let Some(value) = evaluate(mesh, dofs, u, comp, [x, y]) {
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

/// The deformed body x + scale·s(x). With `magnify_to = Some(height)` small displacements are
/// magnified so that the largest one is half of `height`; with `None` the picture is true scale
/// (contact pictures, whose obstacle curves are in true scale too).
pub fn deformed_picture(
    mesh: &Mesh,
    dofs: &DofMap,
    u: &[f64],
    cycle: usize,
    magnify_to: Option<f64>,
) -> DeformedPicture {
    let max = u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let scale = match magnify_to {
        Some(height) if max > 0.0 && max < 0.5 * height => (0.5 * height / max).round().max(1.0),
        _ => 1.0,
    };
    let quads = mesh
        .active()
        .iter()
        .enumerate()
        .map(|(k, _)| {
            let cv = dofs.vertices.cell_vertices[k];
            // counter-clockwise from the lower-left corner
            [cv[0], cv[1], cv[3], cv[2]].map(|v| {
                let x = dofs.vertices.coords[v as usize];
                [
                    x[0] + scale * u[dofs.dof(v, 0)],
                    x[1] + scale * u[dofs.dof(v, 1)],
                ]
            })
        })
        .collect();
    DeformedPicture {
        cycle,
        scale,
        quads,
        obstacles: Vec::new(),
        contact_points: Vec::new(),
        caption: format!(
            "largest displacement component {}",
            crate::results::sig4(max)
        ),
    }
}

/// A solution of one cycle: the field (hanging dofs distributed) and solver counters.
pub struct Solution {
    pub u: Vec<f64>,
    /// Integer counters for the row, e.g. `active_set_iterations`.
    pub counters: Vec<(String, i64)>,
}

/// The squared indicators η_Q² of one cycle and further columns of the table family.
pub struct Estimate {
    pub eta2: Vec<f64>,
    pub quantities: Vec<(String, f64)>,
}

/// One model inside the grid-adaptive cycle loop of [`run_grid_adaptive`].
pub trait AdaptiveModel {
    /// Dofs per vertex.
    fn n_components(&self) -> usize;

    /// Assemble and solve on the current mesh; add the time spent to `seconds.assemble` and
    /// `seconds.solve`. An error message names what failed (the loop adds table and cycle).
    fn solve(
        &mut self,
        mesh: &Mesh,
        dofs: &DofMap,
        system: &mut SparseSystem,
        seconds: &mut PhaseSeconds,
    ) -> Result<Solution, String>;

    /// Error indicators of the solution.
    fn estimate(&mut self, mesh: &Mesh, dofs: &DofMap, u: &[f64]) -> Estimate;

    /// Indicators below this value count as zero when marking (rounding noise), if any.
    fn noise_floor(&self, _estimate: &Estimate) -> Option<f64> {
        None
    }

    /// Called after the solve of every cycle before refinement (e.g. to keep s₀ for the next
    /// Signorini linearisation).
    fn after_cycle(&mut self, _mesh: &Mesh, _dofs: &DofMap, _u: &[f64]) {}

    /// Pictures and other output of the last printed cycle.
    fn last_cycle(
        &mut self,
        _spec: &ExperimentSpec,
        _mesh: &Mesh,
        _dofs: &DofMap,
        _u: &[f64],
        _cycle: usize,
        _result: &mut RunResult,
    ) {
    }

    /// Probe component name → field component.
    fn component(&self, name: &str) -> usize {
        usize::from(name == "s2")
    }
}

/// The grid-adaptive study: one printed row per cycle after `unprinted_cycles` silent ones.
pub fn run_grid_adaptive(
    spec: &ExperimentSpec,
    tier: Tier,
    progress: Progress,
    model: &mut dyn AdaptiveModel,
) -> Result<RunResult, RunError> {
    let printed = printed_rows(spec, tier);
    let total = spec.study.unprinted_cycles + printed;
    let mut mesh = new_mesh(spec);
    let mut result = empty_result(spec, tier);
    let fail = |cycle: usize, message: String| RunError {
        table: spec.table.clone(),
        cycle,
        message,
    };
    // The solver's work arrays move from mesh to mesh (see `SolveBuffers`).
    let mut buffers = SolveBuffers::default();
    for step in 0..total {
        let printed_cycle = step.checked_sub(spec.study.unprinted_cycles);
        let row_cycle = printed_cycle.unwrap_or(0);
        let mut seconds = PhaseSeconds::default();
        let active_cells = mesh.n_active();

        let t = Instant::now();
        let dofs = DofMap::new(&mesh, model.n_components());
        let mut system = SparseSystem::with_buffers(&dofs, std::mem::take(&mut buffers));
        seconds.setup = t.elapsed().as_secs_f64();

        let solution = model
            .solve(&mesh, &dofs, &mut system, &mut seconds)
            .map_err(|m| fail(row_cycle, m))?;
        buffers = system.into_buffers();
        let u = solution.u;
        if let Some(i) = u.iter().position(|v| !v.is_finite()) {
            return Err(fail(
                row_cycle,
                format!("the solution is not finite at dof {i}"),
            ));
        }

        let t = Instant::now();
        let mut estimate = model.estimate(&mesh, &dofs, &u);
        let total_estimate = estimators::total(&estimate.eta2);
        seconds.estimate = t.elapsed().as_secs_f64();
        if !total_estimate.is_finite() {
            return Err(fail(row_cycle, "the error estimate is not finite".into()));
        }

        if let Some(cycle) = printed_cycle {
            if picture_cycles(printed).contains(&cycle) {
                result.meshes.push(mesh_picture(&mesh, cycle));
            }
            if cycle + 1 == printed {
                result.probes = probes(spec, &mesh, &dofs, &u, &*model);
                model.last_cycle(spec, &mesh, &dofs, &u, cycle, &mut result);
            }
        }
        model.after_cycle(&mesh, &dofs, &u);

        let t = Instant::now();
        if step + 1 < total {
            let floor = model.noise_floor(&estimate);
            if let Some(floor) = floor {
                apply_noise_floor(&mut estimate.eta2, floor);
            }
            let eta: Vec<f64> = estimate.eta2.iter().map(|e| e.sqrt()).collect();
            let marking = mark_fixed_number(
                &eta,
                |k| rounded_measure(&mesh, mesh.active()[k]),
                spec.study.refine_fraction,
                spec.study.coarsen_fraction,
            );
            mesh.refine_and_coarsen(&marking.refine, &marking.coarsen);
        }
        seconds.refine = t.elapsed().as_secs_f64();

        if let Some(cycle) = printed_cycle {
            let ratio = result.rows.last().map(|r| total_estimate / r.estimate);
            result.rows.push(CycleRow {
                cycle,
                active_cells,
                dofs: dofs.n_dofs(),
                estimate: total_estimate,
                ratio,
                quantities: estimate.quantities,
                counters: solution.counters,
                seconds,
            });
        }
        progress(&spec.table, step + 1, total);
    }
    Ok(result)
}
