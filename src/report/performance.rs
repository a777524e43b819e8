//! The performance figure of the page: the cost of a solve per unknown over every table of the
//! page, by solver.

use std::io;
use std::path::Path;

use plotters::prelude::*;

use super::plots::*;
use crate::results::RunResult;

/// The cost of a solve per unknown on the page's tables: solve seconds per million unknowns
/// against the unknowns of every cycle (log–log, one dot per cycle), by solver — multigrid
/// (the rows with CG iterations) and the direct solver, the thin films apart from elasticity
/// and contact. Flat dots mean a cost proportional to the unknowns.
pub fn solve_cost(path: &Path, runs: &[&RunResult]) -> io::Result<()> {
    let groups: [(&str, RGBColor); 4] = [
        ("Reynolds, multigrid CG", RGBColor(31, 119, 180)),
        ("Reynolds, direct (Cholesky)", RGBColor(214, 39, 40)),
        ("elasticity, multigrid CG", RGBColor(44, 160, 44)),
        ("elasticity and contact, direct", RGBColor(120, 120, 120)),
    ];
    let mut points: [Vec<(f64, f64)>; 4] = Default::default();
    for run in runs {
        let family = super::families::family_of(&run.table).map(|f| f.id.as_str());
        for row in &run.rows {
            let Some(dofs) = row.dofs() else { continue };
            let multigrid = row
                .count_of(crate::results::columns::CG_ITERATIONS)
                .is_some();
            let group = match (family, multigrid) {
                (Some("family-reynolds"), true) => 0,
                (Some("family-reynolds"), false) => 1,
                (Some("family-elasticity"), true) => 2,
                (Some("family-elasticity" | "family-contact"), false) => 3,
                _ => continue,
            };
            let p = (dofs as f64, row.seconds.solve / (dofs as f64 / 1e6));
            if loggable(&p) && dofs >= 1000 {
                points[group].push(p);
            }
        }
    }
    let all: Vec<(f64, f64)> = points.iter().flatten().copied().collect();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (900, 560)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let (x_lo, x_hi) = log_range(all.iter().map(|p| p.0));
        let (y_lo, y_hi) = log_range(all.iter().map(|p| p.1));
        let mut chart = log_log_axes(
            &root,
            (
                "Solve seconds per million unknowns, every cycle of every table",
                22,
            ),
            48,
            ((x_lo, x_hi), (y_lo, y_hi)),
            ("unknowns (dofs)", "solve s per 10⁶ unknowns"),
        )?;
        for ((label, color), pts) in groups.iter().zip(&points) {
            if pts.is_empty() {
                continue;
            }
            let color = *color;
            chart
                .draw_series(pts.iter().map(|p| Circle::new(*p, 3, color.filled())))
                .map_err(plot_err)?
                .label(*label)
                .legend(move |(x, y)| Circle::new((x + 11, y), 4, color.filled()));
        }
        if all.is_empty() {
            empty_note(&root, "no cycle with unknowns on this page", (280, 250))?;
        } else {
            series_legend(&mut chart, SeriesLabelPosition::UpperLeft, 16)?;
        }
        root.present().map_err(plot_err)?;
    }
    crate::fsio::write(path, svg)
}
