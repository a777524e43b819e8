//! Linear elasticity (I.17), §IV.1, Tables IV.1–IV.5: grid-adaptive cycles on a loaded box.

use super::{Facts, Family};
use crate::experiment::Effect;
use crate::experiment::{
    ElasticityData, Experiment, Lame, Problem, Profile, SceneFile, Scope, StudyKind, Warning,
};
use crate::study::{self, elasticity::ElasticityProblem, StudyError};

/// λ/μ beyond which the warning about locking is given: Poisson's ratio ν = λ/(2λ + μ) above
/// 0.4975 (the form's 2λ is the standard Lamé constant, `ElasticityData::lame`).
/// Pure-displacement Q₁ elements lock as ν → ½ (the discrete displacement is too small by a
/// factor that grows with λ/μ), and the residual estimator does not see it.
const LOCKING_LAMBDA_OVER_MU: f64 = 100.0;

pub struct Elasticity;

impl Family for Elasticity {
    fn facts(&self) -> &'static Facts {
        &Facts {
            id: "elasticity",
            effects: &[Effect::Elasticity],
            kinds: &[StudyKind::GridAdaptive],
            report_family: Some("family-elasticity"),
            components: &["s1", "s2"],
            unknowns_per_vertex: 2,
            solver_choice: true,
            related: &[],
            quantities: &[],
        }
    }

    fn problem(&self, scene: &SceneFile) -> Result<Problem, &'static str> {
        let data = scene.elasticity.clone().ok_or("elasticity")?;
        Ok(Problem::Elasticity(data))
    }

    fn warnings(&self, experiment: &Experiment, scope: &Scope, out: &mut Vec<Warning>) {
        if let Problem::Elasticity(data) = &experiment.problem {
            warnings(data, scope, out);
        }
    }

    /// The direct solver: the elasticity tables stay below 55 000 unknowns, where `cargo bench
    /// --bench solve` measured it and the multigrid solver equally fast (0.085 s at 54 904
    /// unknowns); the reference solver wins the tie.
    fn default_solver(&self) -> crate::linalg::SolverKind {
        crate::linalg::SolverKind::Direct
    }

    fn build(&self, experiment: &Experiment) -> Result<Box<dyn study::Problem>, StudyError> {
        let Problem::Elasticity(data) = &experiment.problem else {
            return Err(StudyError::Failed(
                "an elasticity run needs elasticity data".into(),
            ));
        };
        Ok(Box::new(ElasticityProblem::new(
            data,
            &experiment.scene.domain,
            study::solver_of(experiment),
        )))
    }
}

/// The warnings of the elasticity data (I.17): a locking material, a load whose jump or
/// oscillation no mesh of the run resolves.
pub(super) fn warnings(e: &ElasticityData, scope: &Scope, out: &mut Vec<Warning>) {
    const F: &str = "scene.elasticity";
    let Lame { mu, lambda } = e.lame();
    if lambda > LOCKING_LAMBDA_OVER_MU * mu {
        // The form's 2λ is the standard Lamé constant (ElasticityData::lame).
        let nu = lambda / (2.0 * lambda + mu);
        let field = if e.poisson_ratio.is_some() {
            "poisson_ratio"
        } else {
            "lambda"
        };
        out.push(Warning::new(
            format!("{F}.{field}"),
            format!(
                "λ/μ = {:.4e} (Poisson's ratio {nu:.6}): a nearly incompressible material locks \
                 the Q₁ elements — the displacement comes out too small and the residual \
                 estimator does not show it",
                lambda / mu
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
