//! Contact of an elastic body with rigid obstacles, z-contact (I.20) or Signorini (I.21),
//! §IV.2.1–§IV.2.2, Tables IV.6–IV.17: grid-adaptive cycles, one contact model on every face.

use super::{elasticity, Facts, Family, Infeasible};
use crate::experiment::{
    ContactData, ContactEstimator, ContactModel, Effect, Experiment, ObstacleShape, Problem,
    SceneFile, Scope, StudyKind, Warning,
};
use crate::results::{columns, Row};
use crate::study::{self, contact::ContactProblem, StudyError};

pub struct Contact;

impl Family for Contact {
    fn facts(&self) -> &'static Facts {
        &Facts {
            id: "contact",
            effects: &[Effect::Elasticity, Effect::Contact],
            kinds: &[StudyKind::GridAdaptive],
            report_family: Some("family-contact"),
            components: &["s1", "s2"],
            unknowns_per_vertex: 2,
            solver_choice: true,
            related: &[],
            quantities: crate::study::quantities::CONTACT,
        }
    }

    fn problem(&self, scene: &SceneFile) -> Result<Problem, &'static str> {
        elastic_body_with_contact(scene)
    }

    fn warnings(&self, experiment: &Experiment, scope: &Scope, out: &mut Vec<Warning>) {
        data_warnings(experiment, scope, out);
    }

    fn run_warnings(&self, _experiment: &Experiment, rows: &[Row], out: &mut Vec<Warning>) {
        untouched_obstacles(rows, out);
    }

    fn infeasible(&self, experiment: &Experiment, _rows: usize) -> Option<Infeasible> {
        let (elasticity, contact) = contact_data(experiment).ok()?;
        let message =
            study::contact::infeasible_obstacle(elasticity, contact, &experiment.scene.domain)?;
        Some(Infeasible {
            step: None,
            message,
        })
    }

    /// The contact tables use the direct solver unless `[study] solver = "multigrid"` (or
    /// `report --solver multigrid`) asks for the truncated nonsmooth Newton multigrid method
    /// ([`crate::linalg::multigrid::obstacle`]) for the cycle's solve. Multigrid-preconditioned
    /// CG inside the primal–dual active-set iteration had not paid: with the dofs of the contact
    /// vertices rotated into normal and tangential components, the component-wise
    /// prolongation no longer fits and CG took 100–500 iterations, growing with the mesh
    /// (IV.6–IV.17, tried). With a prolongation that rotates too ([`crate::linalg::multigrid`],
    /// *Rotated frames*) it took 16–102 iterations on IV.14, still growing with the mesh, the
    /// solve phases of IV.6, IV.10 and IV.14 were 1.7–4 times the direct solver's, and IV.10
    /// refined to 2 dofs more in cycle 1 (a marking tie decided otherwise; the cycle-0
    /// estimates of the two solvers are 6.5e-12 apart). TNNMG solves the contact problem
    /// itself by multigrid, in a number of iterations that stays bounded (`benches/solve.rs`);
    /// it is not the default until the tables have been run with it.
    fn default_solver(&self) -> crate::linalg::SolverKind {
        crate::linalg::SolverKind::Direct
    }

    fn build(&self, experiment: &Experiment) -> Result<Box<dyn study::Problem>, StudyError> {
        let (elasticity, contact) = contact_data(experiment)?;
        let mut problem = ContactProblem::new(elasticity, contact);
        problem.multigrid = study::solver_of(experiment) == crate::linalg::SolverKind::Multigrid;
        problem.failures.unprinted = experiment.study.unprinted_cycles;
        problem.compares = experiment.study.signorini_comparison;
        Ok(Box::new(problem))
    }
}

/// The elasticity and contact sections of a contact scene as one problem.
pub(super) fn elastic_body_with_contact(scene: &SceneFile) -> Result<Problem, &'static str> {
    let elasticity = scene.elasticity.clone().ok_or("elasticity")?;
    let contact = scene.contact.clone().ok_or("contact")?;
    Ok(Problem::Contact {
        elasticity,
        contact,
    })
}

/// The data of a contact experiment.
pub(super) fn contact_data(
    experiment: &Experiment,
) -> Result<(&crate::experiment::ElasticityData, &ContactData), StudyError> {
    match &experiment.problem {
        Problem::Contact {
            elasticity,
            contact,
        } => Ok((elasticity, contact)),
        _ => Err(StudyError::Failed(
            "a contact run needs elasticity and contact data".into(),
        )),
    }
}

/// The warnings of the elasticity data and of the obstacles: an estimator meant for the other
/// contact model, a jump or an oscillation no mesh of the run resolves.
pub(super) fn data_warnings(experiment: &Experiment, scope: &Scope, out: &mut Vec<Warning>) {
    let Problem::Contact {
        elasticity: e,
        contact: c,
    } = &experiment.problem
    else {
        return;
    };
    elasticity::warnings(e, scope, out);
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
            // A circle narrower than any cell: the tool acts as its plateau.
            ObstacleShape::Arc { radius, .. } if radius < scope.finest => out.push(Warning::new(
                format!("{F}.obstacles[{i}].shape.radius"),
                format!(
                    "an arc of radius {radius:e} is narrower than the finest cell this run \
                         can reach ({:.3e} wide): no mesh resolves the circle, and the tool acts \
                         as its plateau",
                    scope.finest
                ),
            )),
            // sin(periods·2π(x₁+16)/32): half period 16/|periods|.
            ObstacleShape::Periodic {
                periods: Some(periods),
                ..
            } if periods != 0.0 => scope.resolves(
                &format!("{F}.obstacles[{i}].shape.periods"),
                16.0 / periods.abs(),
                out,
            ),
            // sin(2π(x₁ − phase)/period): half period period/2.
            ObstacleShape::Periodic {
                period: Some(period),
                ..
            } => scope.resolves(
                &format!("{F}.obstacles[{i}].shape.period"),
                0.5 * period.abs(),
                out,
            ),
            _ => {}
        }
    }
}

/// No vertex touched an obstacle in any printed cycle.
pub(super) fn untouched_obstacles(rows: &[Row], out: &mut Vec<Warning>) {
    if rows
        .iter()
        .all(|r| r.count_of(columns::CONTACT_VERTICES) == Some(0))
    {
        out.push(Warning::new(
            columns::CONTACT_VERTICES,
            "no vertex touches an obstacle in any printed cycle: the table solves elasticity \
             without contact",
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
