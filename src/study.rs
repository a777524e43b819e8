//! The cycle loop of a grid-adaptive study (DESIGN.md data flow), deal.II step-6 style:
//! setup → assemble → solve → estimate → record row → mark → refine.
//!
//! Only the effects a scene names are built: an elasticity scene never touches contact or
//! thin-film code.

use std::time::Instant;

use crate::adaptivity::mark_fixed_number;
use crate::estimators::{self, elasticity::BoundaryTerms};
use crate::experiment::{Effect, ExperimentSpec};
use crate::fe::{DofMap, Rect, SolveError, SparseSystem};
use crate::mesh::Mesh;
use crate::models::elasticity::Elasticity;
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
    }
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
    if spec.scene.effects.contains(&Effect::Elasticity)
        && !spec.scene.effects.contains(&Effect::Contact)
    {
        return run_elasticity(spec, tier, progress);
    }
    Err(RunError {
        table: spec.table.clone(),
        cycle: 0,
        message: format!(
            "the effects {:?} are not implemented yet",
            spec.scene.effects
        ),
    })
}

fn new_mesh(spec: &ExperimentSpec) -> Mesh {
    let s = &spec.scene;
    Mesh::new(s.domain.x, s.domain.y, s.coarse_cells[0], s.coarse_cells[1])
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
fn probes(spec: &ExperimentSpec, mesh: &Mesh, dofs: &DofMap, u: &[f64]) -> Vec<Probe> {
    let mut out = Vec::new();
    for &y in &spec.probes.y {
        for &x in &spec.probes.x {
            for name in &spec.probes.components {
                let comp = match name.as_str() {
                    "s2" => 1,
                    _ => 0,
                };
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

/// The deformed body x + scale·s(x), with the displacement magnified so that the largest one
/// is a visible fraction of the domain height.
pub fn deformed_picture(
    mesh: &Mesh,
    dofs: &DofMap,
    u: &[f64],
    cycle: usize,
    height: f64,
) -> DeformedPicture {
    let max = u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let scale = if max > 0.0 && max < 0.5 * height {
        (0.5 * height / max).round().max(1.0)
    } else {
        1.0
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
        caption: format!("largest displacement component {max:.3e}"),
    }
}

fn solve_error(spec: &ExperimentSpec, cycle: usize, e: SolveError) -> RunError {
    RunError {
        table: spec.table.clone(),
        cycle,
        message: e.to_string(),
    }
}

fn ratio(rows: &[CycleRow], estimate: f64) -> Option<f64> {
    rows.last().map(|r| estimate / r.estimate)
}

/// Elasticity (I.17) with the estimator of Theorem III.12 (Tables IV.1–IV.5).
fn run_elasticity(
    spec: &ExperimentSpec,
    tier: Tier,
    progress: Progress,
) -> Result<RunResult, RunError> {
    let data = spec
        .scene
        .elasticity
        .as_ref()
        .expect("validated: elasticity data");
    let problem = Elasticity::from_data(data);
    let terms = BoundaryTerms::default();
    let printed = printed_rows(spec, tier);
    let total = spec.study.unprinted_cycles + printed;
    let mut mesh = new_mesh(spec);
    let mut result = empty_result(spec, tier);
    for step in 0..total {
        let mut seconds = PhaseSeconds::default();
        let active_cells = mesh.n_active();
        let t = Instant::now();
        let dofs = DofMap::new(&mesh, 2);
        let mut system = SparseSystem::new(&dofs);
        let fixed = problem.fixed_dofs(&dofs);
        seconds.setup = t.elapsed().as_secs_f64();

        let t = Instant::now();
        let (matrix, rhs) = problem.assemble(&mesh, &system);
        seconds.assemble = t.elapsed().as_secs_f64();

        let t = Instant::now();
        let mut u = system
            .solve_fixed(&matrix, &rhs, &fixed)
            .map_err(|e| solve_error(spec, step, e))?;
        dofs.distribute_hanging(&mut u);
        seconds.solve = t.elapsed().as_secs_f64();

        let t = Instant::now();
        let eta2 = estimators::elasticity::indicators(&mesh, &dofs, &u, &problem, &terms);
        let estimate = estimators::total(&eta2);
        seconds.estimate = t.elapsed().as_secs_f64();
        if !estimate.is_finite() {
            return Err(RunError {
                table: spec.table.clone(),
                cycle: step,
                message: "the estimate is not finite".into(),
            });
        }

        let printed_cycle = step.checked_sub(spec.study.unprinted_cycles);
        if let Some(cycle) = printed_cycle {
            if picture_cycles(printed).contains(&cycle) {
                result.meshes.push(mesh_picture(&mesh, cycle));
            }
            if cycle + 1 == printed {
                let d = spec.scene.domain;
                result
                    .deformed
                    .push(deformed_picture(&mesh, &dofs, &u, cycle, d.y[1] - d.y[0]));
                result.probes = probes(spec, &mesh, &dofs, &u);
            }
        }

        let t = Instant::now();
        if step + 1 < total {
            let eta: Vec<f64> = eta2.iter().map(|e| e.sqrt()).collect();
            let marking = mark_fixed_number(
                &eta,
                spec.study.refine_fraction,
                spec.study.coarsen_fraction,
            );
            mesh.refine_and_coarsen(&marking.refine, &marking.coarsen);
        }
        seconds.refine = t.elapsed().as_secs_f64();

        if let Some(cycle) = printed_cycle {
            let row = CycleRow {
                cycle,
                active_cells,
                dofs: dofs.n_dofs(),
                estimate,
                ratio: ratio(&result.rows, estimate),
                quantities: Vec::new(),
                counters: Vec::new(),
                seconds,
            };
            result.rows.push(row);
        }
        progress(&spec.table, step + 1, total);
    }
    Ok(result)
}
