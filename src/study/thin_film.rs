//! Pieces every thin-film study composes (Reynolds now, SubStokes next): the off/on/auto
//! cavitation switch, the "estimate of the previous solve" column, the marking noise floor, and
//! the readings of the cavitation source R₃c that the report runs beside a table.

use super::transfer::evaluate;
use crate::experiment::{Cavitation, CavitationSource, Rectangle};
use crate::fe::DofMap;
use crate::mesh::Mesh;
use crate::results::{columns, Arrow, CellBox, FieldPicture, Value};

/// Resolution of the pressure map in the report (cells per side of the sampling grid).
const PICTURE_CELLS: usize = 128;

/// A film solution to draw: the field maps of the report sample it on a uniform grid of
/// `PICTURE_CELLS`² cells of the domain.
pub struct FieldSample<'a> {
    pub domain: Rectangle,
    pub mesh: &'a Mesh,
    pub dofs: &'a DofMap,
    pub u: &'a [f64],
}

impl FieldSample<'_> {
    /// The map of component `comp` named `name` at each sampling cell's centre; with
    /// `cavitation`, the sampling cells where the value is ≤ 0 are the cavitation zone.
    pub fn picture(&self, cycle: usize, name: &str, comp: usize, cavitation: bool) -> FieldPicture {
        let d = self.domain;
        let n = PICTURE_CELLS;
        let (wx, wy) = ((d.x[1] - d.x[0]) / n as f64, (d.y[1] - d.y[0]) / n as f64);
        let mut cells = Vec::with_capacity(n * n);
        let mut zone = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let b = CellBox {
                    x0: d.x[0] + i as f64 * wx,
                    y0: d.y[0] + j as f64 * wy,
                    x1: d.x[0] + (i + 1) as f64 * wx,
                    y1: d.y[0] + (j + 1) as f64 * wy,
                };
                let centre = [0.5 * (b.x0 + b.x1), 0.5 * (b.y0 + b.y1)];
                let v = self.value(comp, centre).unwrap_or(f64::NAN);
                if cavitation && v <= 0.0 {
                    zone.push(b);
                }
                cells.push((b, v));
            }
        }
        FieldPicture {
            cycle,
            name: name.into(),
            cells,
            zone,
            zone_label: if cavitation {
                "cavitation zone ψ = 0".into()
            } else {
                String::new()
            },
            arrows: Vec::new(),
        }
    }

    /// The vector field of components (`comps[0]`, `comps[1]`) at the centres of an `n × n`
    /// grid of the domain, as arrows.
    pub fn arrows(&self, comps: [usize; 2], n: usize) -> Vec<Arrow> {
        let d = self.domain;
        let (wx, wy) = ((d.x[1] - d.x[0]) / n as f64, (d.y[1] - d.y[0]) / n as f64);
        let mut arrows = Vec::with_capacity(n * n);
        for j in 0..n {
            for i in 0..n {
                let at = [
                    d.x[0] + (i as f64 + 0.5) * wx,
                    d.y[0] + (j as f64 + 0.5) * wy,
                ];
                if let (Some(a), Some(b)) = (self.value(comps[0], at), self.value(comps[1], at)) {
                    arrows.push(Arrow { at, v: [a, b] });
                }
            }
        }
        arrows
    }

    /// Component `comp` at a point of the domain.
    pub fn value(&self, comp: usize, p: [f64; 2]) -> Option<f64> {
        evaluate(self.mesh, self.dofs, self.u, comp, p)
    }
}

/// Whether the cavitation model runs. `auto` solves without cavitation and switches the
/// cavitation model on — for this and every later solve — as soon as the pressure drops below
/// zero at a vertex (docs/architecture.md, "Scenes"; the thesis does this by
/// hand in §IV.3.5).
#[derive(Clone, Debug)]
pub struct CavitationSwitch {
    pub mode: Cavitation,
    on: bool,
    /// Solve (0-based, unprinted ones included) in which `auto` switched cavitation on.
    pub switched_at: Option<usize>,
    /// Smallest vertex value of ψ_h in the last solve.
    pub min_psi: f64,
    /// Smallest vertex value of the solution without cavitation of the first solve.
    pub first_min_psi: Option<f64>,
    /// Solves so far.
    solves: usize,
}

impl CavitationSwitch {
    pub fn new(mode: Cavitation) -> CavitationSwitch {
        CavitationSwitch {
            mode,
            on: mode == Cavitation::On,
            switched_at: None,
            min_psi: f64::INFINITY,
            first_min_psi: None,
            solves: 0,
        }
    }

    /// Whether the cavitation model can run in this study (`on` or `auto`).
    pub fn may_run(&self) -> bool {
        self.mode != Cavitation::Off
    }

    /// Whether the cavitation model is in use.
    pub fn is_on(&self) -> bool {
        self.on
    }

    /// Start a solve; returns its number (0-based, unprinted solves included).
    pub fn begin_solve(&mut self) -> usize {
        self.solves += 1;
        self.solves - 1
    }

    /// Record the solution of solve `solve` without cavitation; returns whether the cavitation
    /// model takes over, in this solve already (`auto` and ψ < 0 at a vertex).
    pub fn after_free_solve(&mut self, solve: usize, psi: &[f64]) -> bool {
        self.min_psi = min_vertex_value(psi);
        self.first_min_psi.get_or_insert(self.min_psi);
        if self.mode == Cavitation::Auto && self.min_psi < 0.0 {
            self.on = true;
            self.switched_at = Some(solve);
        }
        self.on
    }

    /// Record the solution of a solve with cavitation.
    pub fn after_cavitation_solve(&mut self, psi: &[f64]) {
        self.min_psi = min_vertex_value(psi);
    }

    /// Whether a cycle keeps its solution for the next one: with cavitation it gives the next
    /// cavitation solve its initial active set ([`super::transfer::PreviousSolution::of`]).
    pub fn keeps_solution(&self) -> bool {
        self.on
    }

    /// What `auto` did, for the table's notes.
    pub fn note(&self) -> Option<String> {
        if self.mode != Cavitation::Auto {
            return None;
        }
        Some(match self.switched_at {
            Some(solve) => format!(
                "cavitation = auto: the pressure dropped below zero in solve {solve} (0 = the \
                 unprinted solve on the initial grid); the cavitation model ran from there on."
            ),
            None => format!(
                "cavitation = auto: the pressure stayed positive (smallest vertex value {:.4}), \
                 the cavitation model was not needed.",
                self.min_psi
            ),
        })
    }
}

fn min_vertex_value(u: &[f64]) -> f64 {
    u.iter().copied().fold(f64::INFINITY, f64::min)
}

/// The column with the estimate of the previous solve ([`columns::PREVIOUS_ESTIMATE`]): row k of
/// the thesis's fluid tables shows the mesh of solve k+1 and the estimate of solve k.
#[derive(Clone, Debug, Default)]
pub struct PreviousEstimate {
    last: Option<f64>,
}

impl PreviousEstimate {
    /// The column for a solve with estimate `total` (undefined in the first solve),
    /// remembering `total` for the next.
    pub fn column(&mut self, total: f64) -> (String, Value) {
        let previous = self.last.replace(total);
        (
            columns::PREVIOUS_ESTIMATE.to_string(),
            Value::real(previous),
        )
    }
}

/// Relative noise floor of the marking: η_Q ≤ NOISE·max|ψ_h| counts as zero.
///
/// When the exact solution is reproduced by the discretisation (ψ ≡ 200 in (IV.9) and (IV.14)),
/// every indicator is rounding noise. Rounding perturbs the nodal values by about u·κ·max|ψ_h|
/// and a perturbation δ of one nodal value gives an indicator η_Q ≈ |δ| independently of the cell
/// size (face jump δ/h on faces of length h, weight h). So an indicator with η_Q ≤
/// 1e-10·max|ψ_h| counts as zero when marking (it is kept in the printed estimate). Genuine
/// indicators of the tables are at least five orders of magnitude above that floor.
pub const NOISE: f64 = 1e-10;

/// The noise floor of η_Q² for a film pressure of largest magnitude `psi_scale`.
pub fn noise_floor(psi_scale: f64) -> f64 {
    let eta = NOISE * psi_scale;
    eta * eta
}

/// A reading of the cavitation source R₃c other than the experiment's own.
pub struct SourceReading {
    pub source: CavitationSource,
    /// What changes, for the report's heading.
    pub label: &'static str,
    /// Suffix of the data file (`report/data/<table>.<suffix>.csv`).
    pub suffix: &'static str,
}

/// The readings of R₃c that the report runs beside a thin-film table with cavitation and the
/// printed γ₃c of (I.61): the self-consistent 2γ₃ − γ₃c (docs/models.md §15 item 9), and R₃ of
/// (I.77), the source without cavitation, which the thesis's code evidently used
/// ([`CavitationSource::Reynolds`]). None for other tables.
pub fn source_readings(cavitation: Cavitation, source: CavitationSource) -> Vec<SourceReading> {
    if cavitation == Cavitation::Off || source != CavitationSource::Printed {
        return Vec::new();
    }
    vec![
        SourceReading {
            source: CavitationSource::SelfConsistent,
            label: "R₃c from 2γ₃ − γ₃c instead of the printed γ₃c of (I.61) \
                    (cavitation_source = \"self-consistent\")",
            suffix: "self-consistent",
        },
        SourceReading {
            source: CavitationSource::Reynolds,
            label: "R₃ of (I.77), the source without cavitation, in place of R₃c, as the thesis's \
                    code evidently had it (cavitation_source = \"reynolds\")",
            suffix: "reynolds",
        },
    ]
}
