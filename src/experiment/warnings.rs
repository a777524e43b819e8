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
        let x = self.scene.domain.x;
        match &self.problem {
            Problem::Elasticity(e) => elasticity(e, x, &mut out),
            Problem::Contact {
                elasticity: e,
                contact,
            } => {
                elasticity(e, x, &mut out);
                contact_data(contact, x, &mut out);
            }
            Problem::Reynolds(r) => reynolds(r, &mut out),
        }
        unresolved_oscillations(self, &mut out);
        out
    }
}

fn flat_cells(e: &Experiment, out: &mut Vec<Warning>) {
    let d = e.scene.domain;
    let [nx, ny] = e.scene.coarse_cells;
    let hx = (d.x[1] - d.x[0]) / nx as f64;
    let hy = (d.y[1] - d.y[0]) / ny as f64;
    let ratio = (hx / hy).max(hy / hx);
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

fn elasticity(e: &ElasticityData, x: [f64; 2], out: &mut Vec<Warning>) {
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
    if let Some(load) = &e.volume_load {
        if let Profile::Step { at, .. } = load.profile {
            outside(
                &format!("{F}.volume_load.profile.at"),
                at,
                x,
                "the load is constant on the whole domain",
                out,
            );
        }
    }
}

fn contact_data(c: &ContactData, x: [f64; 2], out: &mut Vec<Warning>) {
    const F: &str = "scene.contact";
    let expected = match c.model {
        ContactModel::Z => [
            ContactEstimator::ZCode,
            ContactEstimator::ZCodeObstacleSlope,
        ]
        .contains(&c.estimator),
        ContactModel::Signorini => c.estimator == ContactEstimator::SignoriniCode,
    };
    if !expected {
        out.push(Warning::new(
            format!("{F}.estimator"),
            format!(
                "`{}` with model `{}`: the thesis pairs the z-code terms with the z-model \
                 (Tables IV.6–IV.11) and the Signorini-code terms with the Signorini model \
                 (IV.12–IV.17); this pairing estimates the error of a different problem",
                estimator_name(c.estimator),
                model_name(c.model)
            ),
        ));
    }
    for (i, obstacle) in c.obstacles.iter().enumerate() {
        if let ObstacleShape::Jump { at, .. } = obstacle.shape {
            outside(
                &format!("{F}.obstacles[{i}].shape.at"),
                at,
                x,
                "the obstacle is (up to the smoothing θ_s) constant on the contact face",
                out,
            );
        }
    }
}

fn reynolds(r: &ReynoldsData, out: &mut Vec<Warning>) {
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
}

/// Oscillating data whose half period lies below the finest cell the run can reach (each cycle
/// refines a cell at most once): no mesh of the run resolves it, and the quadrature samples it
/// at arbitrary phases (aliasing) — a sine of half period 1e-300 is a pseudo-random load.
fn unresolved_oscillations(e: &Experiment, out: &mut Vec<Warning>) {
    let [nx, _] = e.scene.coarse_cells;
    let first = (e.scene.domain.x[1] - e.scene.domain.x[0])
        / nx as f64
        / 2f64.powi(e.scene.global_refinements as i32);
    let adaptations = e.study.unprinted_cycles + e.study.rows - 1;
    let finest = first / 2f64.powi(adaptations.min(1000) as i32);
    let mut check = |field: &str, half_period: f64| {
        if half_period < finest {
            out.push(Warning::new(
                field,
                format!(
                    "an oscillation of half period {half_period:?} is below the finest cell \
                     this run can reach ({finest:.3e} wide after {adaptations} refinements of \
                     {first:?}): no mesh resolves it and the quadrature samples it at arbitrary \
                     phases"
                ),
            ));
        }
    };
    let load = match &e.problem {
        Problem::Elasticity(el) | Problem::Contact { elasticity: el, .. } => {
            el.volume_load.as_ref().map(|l| l.profile)
        }
        Problem::Reynolds(_) => None,
    };
    if let Some(Profile::Sine { half_period, .. }) = load {
        check(
            "scene.elasticity.volume_load.profile.half_period",
            half_period,
        );
    }
    if let Problem::Contact { contact, .. } = &e.problem {
        for (i, o) in contact.obstacles.iter().enumerate() {
            if let ObstacleShape::Periodic { periods, .. } = o.shape {
                if periods != 0.0 {
                    // sin(periods·2π(x₁+16)/32): half period 16/|periods|.
                    check(
                        &format!("scene.contact.obstacles[{i}].shape.periods"),
                        16.0 / periods.abs(),
                    );
                }
            }
        }
    }
    if let Problem::Reynolds(r) = &e.problem {
        let half_period = match r.gap {
            GapShape::WaveHorizontal { frequency, .. } => 0.5 / frequency.abs(),
            // sin²(2π f x) has period 1/(2f).
            GapShape::Hill { frequency, .. } => 0.25 / frequency.abs(),
            GapShape::Plain { .. } | GapShape::Linear { .. } => f64::INFINITY,
        };
        check("scene.reynolds.gap.frequency", half_period);
    }
}

/// A jump at `at` that the domain's x-range `x` does not contain.
fn outside(field: &str, at: f64, x: [f64; 2], consequence: &str, out: &mut Vec<Warning>) {
    if at <= x[0] || at >= x[1] {
        out.push(Warning::new(
            field,
            format!(
                "the jump at x₁ = {at} lies outside the domain's x₁ ∈ ({}, {}): {consequence}",
                x[0], x[1]
            ),
        ));
    }
}

fn estimator_name(estimator: ContactEstimator) -> &'static str {
    match estimator {
        ContactEstimator::ZCode => "z-code",
        ContactEstimator::ZCodeObstacleSlope => "z-code-obstacle-slope",
        ContactEstimator::SignoriniCode => "signorini-code",
    }
}

fn model_name(model: ContactModel) -> &'static str {
    match model {
        ContactModel::Z => "z",
        ContactModel::Signorini => "signorini",
    }
}
