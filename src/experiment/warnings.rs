//! Legal but suspicious experiments: what loads and runs, but probably not as its author meant.
//!
//! The loader ([`super::load`]) rejects what is wrong or contradictory. What is merely unusual —
//! a material that locks the Q₁ elements, flat coarse cells, a jump outside the domain, an
//! estimator meant for the other contact model — runs, and the report shows a [`Warning`] in the
//! table's section and its count in the summary. No shipped experiment warns (tested).
//!
//! [`Experiment::warnings`] looks at the file only: the flat cells here, the data of each
//! family in its module ([`crate::family::Family::warnings`]); the study adds what only the run
//! shows (`crate::study::warnings`).

use std::fmt;

use super::Experiment;

/// Coarse-cell side ratio beyond which the warning about flat cells is given. Refinement keeps
/// the ratio, and the constants of the residual estimators grow with it (they assume
/// shape-regular cells), so estimates and marking lose their meaning.
const FLAT_CELLS: f64 = 10.0;

/// One warning: the field it concerns and what is suspicious about it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Warning {
    pub field: String,
    pub message: String,
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.field, self.message)
    }
}

impl Warning {
    pub fn new(field: impl Into<String>, message: impl Into<String>) -> Warning {
        Warning {
            field: field.into(),
            message: message.into(),
        }
    }
}

impl Experiment {
    /// What is legal but suspicious in this experiment file, in field order.
    pub fn warnings(&self) -> Vec<Warning> {
        let mut out = Vec::new();
        flat_cells(self, &mut out);
        self.family.warnings(self, &Scope::of(self), &mut out);
        out
    }
}

/// What the checks of the data need to know of the scene and the study: the domain's x-range
/// and the cells the run can resolve.
pub struct Scope {
    x: [f64; 2],
    /// Width of a cell of the first mesh (the coarse grid refined globally).
    first: f64,
    /// Adaptations before the last solve; each refines a cell at most once.
    adaptations: usize,
    /// Width of the finest cell the run can reach, `first / 2^adaptations`.
    pub finest: f64,
}

impl Scope {
    fn of(e: &Experiment) -> Scope {
        let [hx, _] = e.scene.domain.cell_sides(e.scene.coarse_cells);
        let first = hx / 2f64.powi(e.scene.global_refinements as i32);
        let adaptations = e.study.unprinted_cycles + e.study.rows - 1;
        Scope {
            x: e.scene.domain.x,
            first,
            adaptations,
            finest: first / 2f64.powi(adaptations.min(1000) as i32),
        }
    }

    /// Width of a cell of the first mesh (the coarse grid refined globally).
    pub fn first_cell(&self) -> f64 {
        self.first
    }

    /// Oscillating data whose half period lies below the finest cell the run can reach: no mesh
    /// of the run resolves it, and the quadrature samples it at arbitrary phases (aliasing) — a
    /// sine of half period 1e-300 is a pseudo-random load.
    pub fn resolves(&self, field: &str, half_period: f64, out: &mut Vec<Warning>) {
        if half_period < self.finest {
            out.push(Warning::new(
                field,
                format!(
                    "an oscillation of half period {half_period:?} is below the finest cell \
                     this run can reach ({:.3e} wide after {} refinements of {:?}): no mesh \
                     resolves it and the quadrature samples it at arbitrary phases",
                    self.finest, self.adaptations, self.first
                ),
            ));
        }
    }

    /// A jump at `at` that the domain's x-range does not contain.
    pub fn contains_jump(&self, field: &str, at: f64, consequence: &str, out: &mut Vec<Warning>) {
        let x = self.x;
        if at <= x[0] || at >= x[1] {
            out.push(Warning::new(
                field,
                format!(
                    "the jump at x₁ = {at} lies outside the domain's x₁ ∈ ({}, {}): \
                     {consequence}",
                    x[0], x[1]
                ),
            ));
        }
    }
}

fn flat_cells(e: &Experiment, out: &mut Vec<Warning>) {
    let [hx, hy] = e.scene.domain.cell_sides(e.scene.coarse_cells);
    let ratio = e.scene.domain.cell_aspect_ratio(e.scene.coarse_cells);
    if ratio > FLAT_CELLS {
        out.push(Warning::new(
            "scene.coarse_cells",
            format!(
                "coarse cells of {hx} × {hy}, sides in a ratio of {ratio:.3}: refinement keeps \
                 the ratio, and the residual estimators assume shape-regular cells (their \
                 constants grow with it), so estimates and marking are unreliable; cells of \
                 ratio ≤ {FLAT_CELLS} are safe"
            ),
        ));
    }
}
