//! What accuracy costs on the fixed mesh of a model-adaptive scene (§IV.2.2 closes with "this
//! advantage [of the Signorini solver] is balanced out against the higher speed of the z-solver
//! in section IV.2.3"): the scene solved with four choices of the contact model per face, each
//! through the cycles of its table,
//!
//! * `z` — every face z (the z-solve alone);
//! * `signorini` — every face Signorini, linearised once about the z-solution (the mixed solve
//!   of the model-adaptive tables with 𝕋_a = all faces);
//! * `III.2`, `III.3` — the partitions of Algorithms III.2 and III.3.
//!
//! Measured per cycle: the solve seconds (both solves of the cycle), the active-set iterations,
//! the true penetration of the deformed boundary into the obstacle, the energy distance
//! ‖s − s_S‖_a / ‖s_S‖_a to the all-Signorini solution s_S on the same mesh, and the model
//! error. The III.2 and III.3 variants also test the claim closing §IV.2.3: "after the same
//! number of refinement cycles the error estimate for the sorted error algorithm is lower than
//! that of the fixed-fraction algorithm and demands for the more expensive model on a lower
//! number of faces" ([`crate::results::claim_of_section_iv_2_3`]).

use std::collections::BTreeSet;
use std::fmt;

use super::adapt::{boundary_faces, Adaptation, KeepModels, ModelMarking};
use super::error::StudyError;
use super::model_contact::ModelAdaptiveContact;
use super::problem::{Discretisation, Estimate, Problem, Solution};
use super::{cycle_loop, CycleObserver, PhaseClock, RunError, Schedule, Solve};
use crate::experiment::{self, Experiment, ModelAlgorithm, ModelFractions, Plan};
use crate::fe::quadrature::square_rule;
use crate::fe::{CellValues, DofMap};
use crate::mesh::{BoundaryFace, Mesh};
use crate::models::elasticity::Elasticity;
use crate::results::{columns, CostRow, PhaseSeconds};

/// A choice of the contact model per face, run through the table's cycles. Its printed name
/// (`Display`) is the `variant` of the cost rows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CostVariant {
    /// Every face z (the z-solve alone): `z`.
    Z,
    /// Every face Signorini, linearised once about the z-solution: `signorini`.
    Signorini,
    /// The partitions of Algorithm III.2 (fixed fraction): `III.2`.
    FixedFraction,
    /// The partitions of Algorithm III.3 (sorted error): `III.3`.
    SortedError,
}

impl CostVariant {
    /// The variants in the order of the file and the page.
    pub const ALL: [CostVariant; 4] = [
        CostVariant::Z,
        CostVariant::Signorini,
        CostVariant::FixedFraction,
        CostVariant::SortedError,
    ];

    /// The first cycle's partition: every face Signorini for [`CostVariant::Signorini`], every
    /// face z otherwise.
    fn start(self, disc: &Discretisation, all_faces: &BTreeSet<BoundaryFace>) -> Discretisation {
        let mut disc = disc.clone();
        if self == CostVariant::Signorini {
            disc.models.set_accurate_faces(all_faces.iter().copied());
        }
        disc
    }

    /// What changes between the cycles: the partition by the variant's algorithm with the
    /// study's p_r, p_c and ε₀, or nothing (the fixed partitions).
    fn adaptation(self, fractions: ModelFractions) -> Box<dyn Adaptation> {
        let marking = |algorithm| ModelMarking {
            algorithm,
            ..ModelMarking::from(fractions)
        };
        match self {
            CostVariant::Z | CostVariant::Signorini => Box::new(KeepModels),
            CostVariant::FixedFraction => Box::new(marking(ModelAlgorithm::FixedFraction)),
            CostVariant::SortedError => Box::new(marking(ModelAlgorithm::SortedError)),
        }
    }
}

impl fmt::Display for CostVariant {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            CostVariant::Z => "z",
            CostVariant::Signorini => "signorini",
            CostVariant::FixedFraction => "III.2",
            CostVariant::SortedError => "III.3",
        })
    }
}

/// Whether the cost study applies to an experiment: its family says so
/// ([`crate::family::Family::cost_study`]: a model-adaptive contact table on a fixed mesh with
/// Algorithm III.3).
pub fn applies(experiment: &Experiment) -> bool {
    experiment.family.cost_study(experiment)
}

/// The four variants of [`applies`]'s scene through the table's printed cycles.
pub fn accuracy_costs(experiment: &Experiment) -> Result<Vec<CostRow>, RunError> {
    let experiment::Problem::Contact {
        elasticity,
        contact,
    } = &experiment.problem
    else {
        return Ok(Vec::new());
    };
    let Plan::ModelAdaptive { model: fractions } = experiment.study.plan else {
        return Ok(Vec::new());
    };
    let fail = |cycle: usize, cause: StudyError| {
        RunError::at_cycle(&experiment.table, cycle, cause.context("cost of accuracy"))
    };
    let disc = Discretisation::initial(&experiment.scene).map_err(|e| fail(0, e.into()))?;
    let model = Elasticity::from(elasticity);
    let new_problem = || ModelAdaptiveContact::new(elasticity, contact);
    let sides: BTreeSet<_> = contact.obstacles.iter().map(|o| o.side).collect();
    let all_faces: BTreeSet<_> = boundary_faces(&disc.mesh, &sides).into_iter().collect();

    // The reference s_S: every face Signorini.
    let mut reference_problem = new_problem();
    let all_signorini = CostVariant::Signorini.start(&disc, &all_faces);
    let (dofs, s_s) =
        solve_reference(&mut reference_problem, &all_signorini).map_err(|e| fail(0, e))?;
    let s_s_norm = energy_norm(&model, &disc.mesh, &dofs, &s_s, None);

    let mut rows = Vec::new();
    for variant in CostVariant::ALL {
        let mut problem = new_problem();
        let mut disc = variant.start(&disc, &all_faces);
        let mut adaptation = variant.adaptation(fractions);
        let cycles = Schedule {
            unprinted: 0,
            printed: experiment.study.rows,
            per_row: 1,
        };
        let mut variant_rows = VariantCycles {
            variant,
            model: &model,
            s_s: &s_s,
            s_s_norm,
            model_tolerance: fractions.tolerance,
            rows: &mut rows,
        };
        cycle_loop(
            &mut problem,
            &mut *adaptation,
            &mut disc,
            cycles.solves(),
            &mut variant_rows,
        )
        .map_err(|(solve, cause)| fail(solve.index, cause))?;
    }
    Ok(rows)
}

/// The rows of one variant: per cycle the energy distance to s_S, the active-set iterations of
/// both solves, the penetration, the model error and, once the cycle is over, its solve
/// seconds.
struct VariantCycles<'a> {
    variant: CostVariant,
    model: &'a Elasticity,
    s_s: &'a [f64],
    s_s_norm: f64,
    model_tolerance: f64,
    rows: &'a mut Vec<CostRow>,
}

impl CycleObserver for VariantCycles<'_> {
    fn solved(
        &mut self,
        solve: &Solve,
        disc: &Discretisation,
        dofs: &DofMap,
        solution: &Solution,
        estimate: &Estimate,
        _problem: &mut dyn Problem,
    ) {
        let distance =
            energy_norm(self.model, &disc.mesh, dofs, &solution.u, Some(self.s_s)) / self.s_s_norm;
        let column = |name: &str| estimate.value(name).unwrap_or(f64::NAN);
        self.rows.push(CostRow {
            variant: self.variant.to_string(),
            cycle: solve.index,
            seconds_solve: 0.0,
            iterations: active_set_iterations(solution),
            penetration: column(columns::PENETRATION),
            energy_distance: distance,
            accurate_faces: disc.models.n_accurate(),
            model_error: column(columns::MODEL_ERROR),
            model_tolerance: self.model_tolerance,
        });
    }

    fn finished(&mut self, _solve: &Solve, seconds: PhaseSeconds) {
        if let Some(row) = self.rows.last_mut() {
            row.seconds_solve = seconds.solve;
        }
    }
}

/// The active-set iterations of a cycle's solves (the counters named `…_iterations`).
fn active_set_iterations(solution: &Solution) -> i64 {
    solution
        .counters
        .iter()
        .filter(|(name, _)| name.ends_with("_iterations"))
        .map(|(_, n)| n)
        .sum()
}

/// The all-Signorini reference s_S on the first mesh: one solve through the study loop's phases
/// ([`super::solve_and_estimate`]), its numbering and displacement.
fn solve_reference(
    problem: &mut ModelAdaptiveContact,
    disc: &Discretisation,
) -> Result<(DofMap, Vec<f64>), StudyError> {
    let clock = PhaseClock::default();
    let (dofs, solution, _) = super::solve_and_estimate(problem, disc, &clock)?;
    Ok((dofs, solution.u))
}

/// ‖u − v‖_a = (∫_Ω σ(u − v) : ∇(u − v))^{1/2} (v = 0 when `minus` is None), with the 2×2
/// Gauss rule on each cell's map ([`CellValues`]; exact for Q₁ on rectangles).
pub(super) fn energy_norm(
    model: &Elasticity,
    mesh: &Mesh,
    dofs: &DofMap,
    u: &[f64],
    minus: Option<&[f64]>,
) -> f64 {
    let e: Vec<f64> = match minus {
        Some(v) => u.iter().zip(v).map(|(a, b)| a - b).collect(),
        None => u.to_vec(),
    };
    let rule = square_rule::<4>();
    let mut sum = 0.0;
    for (k, &c) in mesh.active().iter().enumerate() {
        let cv = CellValues::new(mesh.cell_shape(c), &rule);
        let corners = [dofs.corner_values(&e, k, 0), dofs.corner_values(&e, k, 1)];
        sum += cv.integrate(|q| {
            let phi = cv.gradients(q);
            let grad = corners.map(|ua| {
                (0..4).fold([0.0; 2], |g, a| {
                    [g[0] + ua[a] * phi[a][0], g[1] + ua[a] * phi[a][1]]
                })
            });
            let sigma = model.stress(grad);
            (0..2)
                .flat_map(|i| (0..2).map(move |j| (i, j)))
                .map(|(i, j)| sigma[i][j] * grad[i][j])
                .sum()
        });
    }
    sum.sqrt()
}
