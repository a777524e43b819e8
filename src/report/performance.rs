//! The performance figure of the page: the cost of a solve per unknown over every table of the
//! page, by solver.

use std::io;
use std::path::Path;

use plotters::prelude::*;

use super::legend::{self, Entry, Placed, Swatch};
use super::plots::*;
use crate::results::RunResult;

/// The model a run's solves belong to in [`solve_cost`]: its family for a thesis table, its
/// scene's effects for a scene of one's own (which has an id of its own and so no family).
/// `None` for the runs the figure leaves out (SubStokes, the model-adaptive runs).
fn solved_model(run: &RunResult) -> Option<&'static str> {
    if let Some(family) = super::families::family_of(&run.table) {
        return match family.id.as_str() {
            "family-reynolds" => Some("reynolds"),
            "family-elasticity" => Some("elasticity"),
            "family-contact" => Some("contact"),
            _ => None,
        };
    }
    if run.is_model_adaptive() {
        return None;
    }
    let effects = run
        .parameters
        .iter()
        .find(|p| p.group == "scene" && p.key == "effects")?
        .value
        .as_str();
    let has = |effect: &str| effects.contains(&format!("\"{effect}\""));
    if has("substokes") {
        None
    } else if has("reynolds") {
        Some("reynolds")
    } else if has("contact") {
        Some("contact")
    } else if has("elasticity") {
        Some("elasticity")
    } else {
        None
    }
}

/// The cost of a solve per unknown on the page's tables: solve seconds per million unknowns
/// against the unknowns of every cycle (log–log, one dot per cycle), by solver — multigrid
/// (the rows with CG iterations) and the direct solver, the thin films apart from elasticity
/// and contact. Flat dots mean a cost proportional to the unknowns. A scene of one's own counts
/// with the model its scene names ([`solved_model`]).
pub fn solve_cost(path: &Path, runs: &[&RunResult]) -> io::Result<Placed> {
    let groups: [(&str, RGBColor); 4] = [
        ("Reynolds, multigrid CG", RGBColor(31, 119, 180)),
        ("Reynolds, direct (Cholesky)", RGBColor(214, 39, 40)),
        ("elasticity, multigrid CG", RGBColor(44, 160, 44)),
        ("elasticity and contact, direct", RGBColor(120, 120, 120)),
    ];
    let mut points: [Vec<(f64, f64)>; 4] = Default::default();
    for run in runs {
        let Some(model) = solved_model(run) else {
            continue;
        };
        for row in &run.rows {
            let Some(dofs) = row.dofs() else { continue };
            let multigrid = row
                .count_of(crate::results::columns::CG_ITERATIONS)
                .is_some();
            let group = match (model, multigrid) {
                ("reynolds", true) => 0,
                ("reynolds", false) => 1,
                ("elasticity", true) => 2,
                ("elasticity" | "contact", false) => 3,
                _ => continue,
            };
            let p = (dofs as f64, row.seconds.solve / (dofs as f64 / 1e6));
            if loggable(&p) && dofs >= 1000 {
                points[group].push(p);
            }
        }
    }
    let all: Vec<(f64, f64)> = points.iter().flatten().copied().collect();
    let entries: Vec<Entry> = groups
        .iter()
        .zip(&points)
        .filter(|(_, pts)| !pts.is_empty())
        .map(|((label, color), _)| Entry::new(*label, Swatch::Dot(*color)))
        .collect();
    let mut svg = String::new();
    let mut placed = Placed::default();
    {
        let size = (900, 560 + legend::height(&entries, 900));
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let (area, strip) = legend::split(&root, &entries);
        let (x_lo, x_hi) = log_range(all.iter().map(|p| p.0));
        let (y_lo, y_hi) = log_range(all.iter().map(|p| p.1));
        let mut chart = log_log_axes(
            &area,
            (
                "Solve seconds per million unknowns, every cycle of every table",
                22,
            ),
            48,
            ((x_lo, x_hi), (y_lo, y_hi)),
            ("unknowns (dofs)", "solve s per 10⁶ unknowns"),
        )?;
        for ((_, color), pts) in groups.iter().zip(&points) {
            let color = *color;
            chart
                .draw_series(pts.iter().map(|p| Circle::new(*p, 3, color.filled())))
                .map_err(plot_err)?;
        }
        if all.is_empty() {
            empty_note(&area, "no cycle with unknowns on this page", (280, 250))?;
        }
        placed.points = legend::pixels(&chart, all.iter().copied());
        placed.legends.extend(legend::draw(&strip, &entries)?);
        root.present().map_err(plot_err)?;
    }
    crate::fsio::write(path, svg)?;
    Ok(placed)
}
