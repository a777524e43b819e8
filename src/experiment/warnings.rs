//! Legal but suspicious experiments: what loads and runs, but probably not as its author meant.
//!
//! The loader ([`super::load`]) rejects what is wrong or contradictory. What is merely unusual —
//! a material that locks the Q₁ elements, flat coarse cells, a jump outside the domain, an
//! estimator meant for the other contact model — runs, and the report shows a [`Warning`] in the
//! table's section and its count in the summary. No shipped experiment warns (tested).
//!
//! [`Experiment::warnings`] looks at the file only; the study adds what only the run shows
//! (`crate::study::warnings`).

use std::fmt;

use super::spec::*;
use super::{Experiment, Problem};

/// λ/μ beyond which the warning about locking is given: Poisson's ratio ν = λ/(2(λ+μ)) above
/// 0.495. Pure-displacement Q₁ elements lock as ν → ½ (the discrete displacement is too small
/// by a factor that grows with λ/μ), and the residual estimator does not see it.
const LOCKING_LAMBDA_OVER_MU: f64 = 100.0;

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
        let scope = Scope::of(self);
        match &self.problem {
            Problem::Elasticity(e) => elasticity(e, &scope, &mut out),
            Problem::Contact {
                elasticity: e,
                contact,
            } => {
                elasticity(e, &scope, &mut out);
                contact_data(contact, &scope, &mut out);
            }
            Problem::Reynolds(r) => reynolds(r, &scope, &mut out),
            Problem::SubStokes(_) | Problem::StokesChannel(_) | Problem::FilmModels { .. } => {}
        }
        out
    }
}

/// What the checks of the data need to know of the scene and the study: the domain's x-range
/// and the cells the run can resolve.
struct Scope {
    x: [f64; 2],
    /// Width of a cell of the first mesh (the coarse grid refined globally).
    first: f64,
    /// Adaptations before the last solve; each refines a cell at most once.
    adaptations: usize,
    /// Width of the finest cell the run can reach, `first / 2^adaptations`.
    finest: f64,
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

    /// Oscillating data whose half period lies below the finest cell the run can reach: no mesh
    /// of the run resolves it, and the quadrature samples it at arbitrary phases (aliasing) — a
    /// sine of half period 1e-300 is a pseudo-random load.
    fn resolves(&self, field: &str, half_period: f64, out: &mut Vec<Warning>) {
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
    fn contains_jump(&self, field: &str, at: f64, consequence: &str, out: &mut Vec<Warning>) {
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

fn elasticity(e: &ElasticityData, scope: &Scope, out: &mut Vec<Warning>) {
    const F: &str = "scene.elasticity";
    if e.lambda > LOCKING_LAMBDA_OVER_MU * e.mu {
        let nu = e.lambda / (2.0 * (e.lambda + e.mu));
        out.push(Warning::new(
            format!("{F}.lambda"),
            format!(
                "λ/μ = {:.4e} (Poisson's ratio {nu:.6}): a nearly incompressible material locks \
                 the Q₁ elements — the displacement comes out too small and the residual \
                 estimator does not show it",
                e.lambda / e.mu
            ),
        ));
    }
    match e.volume_load.as_ref().map(|load| load.profile) {
        Some(Profile::Step { at, .. }) => scope.contains_jump(
            &format!("{F}.volume_load.profile.at"),
            at,
            "the load is constant on the whole domain",
            out,
        ),
        Some(Profile::Sine { half_period, .. }) => scope.resolves(
            &format!("{F}.volume_load.profile.half_period"),
            half_period,
            out,
        ),
        Some(Profile::Constant { .. } | Profile::Quadratic { .. }) | None => {}
    }
}

fn contact_data(c: &ContactData, scope: &Scope, out: &mut Vec<Warning>) {
    const F: &str = "scene.contact";
    let estimator = c.grid_estimator();
    let expected = match c.model {
        ContactModel::Z | ContactModel::ModelAdaptive => [
            ContactEstimator::ZCode,
            ContactEstimator::ZCodeObstacleSlope,
        ]
        .contains(&estimator),
        ContactModel::Signorini => estimator == ContactEstimator::SignoriniCode,
    };
    if !expected {
        out.push(Warning::new(
            format!("{F}.estimator"),
            format!(
                "`{}` with model `{}`: the thesis pairs the z-code terms with the z-model \
                 (Tables IV.6–IV.11) and the Signorini-code terms with the Signorini model \
                 (IV.12–IV.17); this pairing estimates the error of a different problem",
                estimator_name(estimator),
                c.model.name()
            ),
        ));
    }
    for (i, obstacle) in c.obstacles.iter().enumerate() {
        match obstacle.shape {
            ObstacleShape::Jump { at, .. } => scope.contains_jump(
                &format!("{F}.obstacles[{i}].shape.at"),
                at,
                "the obstacle is (up to the smoothing θ_s) constant on the contact face",
                out,
            ),
            // sin(periods·2π(x₁+16)/32): half period 16/|periods|.
            ObstacleShape::Periodic { periods, .. } if periods != 0.0 => scope.resolves(
                &format!("{F}.obstacles[{i}].shape.periods"),
                16.0 / periods.abs(),
                out,
            ),
            _ => {}
        }
    }
}

fn reynolds(r: &ReynoldsData, scope: &Scope, out: &mut Vec<Warning>) {
    if r.upper_wall_velocity == [0.0; 3] {
        out.push(Warning::new(
            "scene.reynolds.upper_wall_velocity",
            format!(
                "both walls at rest: nothing drives the flow, ψ ≡ boundary_pressure = {} is \
                 the exact solution on every mesh, every estimate is 0 up to rounding and the \
                 ratios mean nothing",
                r.boundary_pressure
            ),
        ));
    }
    let half_period = match r.gap {
        GapShape::WaveHorizontal { frequency, .. } => 0.5 / frequency.abs(),
        // sin²(2π f x) has period 1/(2f).
        GapShape::Hill { frequency, .. } => 0.25 / frequency.abs(),
        GapShape::Plain { .. } | GapShape::Linear { .. } => f64::INFINITY,
    };
    scope.resolves("scene.reynolds.gap.frequency", half_period, out);
}

fn estimator_name(estimator: ContactEstimator) -> &'static str {
    match estimator {
        ContactEstimator::ZCode => "z-code",
        ContactEstimator::ZCodeObstacleSlope => "z-code-obstacle-slope",
        ContactEstimator::SignoriniCode => "signorini-code",
    }
}
