//! The model-adaptive film, §IV.3.4, Figs. IV.116–IV.118: Reynolds and SubStokes on one film,
//! the model chosen cell by cell (Algorithm III.3 over the cells), with grid adaptivity.

use super::{Facts, Family};
use crate::experiment::{
    Cavitation, Check, Checked, Effect, Experiment, ExperimentFile, FilmSolver, GapShape, Plan,
    Problem, ReynoldsData, SceneFile, Scope, StudyKind, SubStokesData, Warning,
};
use crate::study::{self, model_fluid, Adaptation, StudyError};

pub struct ModelFluid;

impl Family for ModelFluid {
    fn facts(&self) -> &'static Facts {
        &Facts {
            id: "model-fluid",
            effects: &[Effect::Reynolds, Effect::SubStokes],
            kinds: &[StudyKind::ModelAndGridAdaptive],
            report_family: Some("family-model-fluid"),
            components: &["psi"],
            unknowns_per_vertex: 3,
            solver_choice: false,
            related: &["reynolds", "substokes"],
            quantities: &[],
        }
    }

    /// One film in both sections, and none of the SubStokes solver fields: the coupled solve
    /// of the film always factors the SubStokes system with the LDLᵀ (they would be printed and
    /// never run).
    fn check(&self, check: &Check, file: &ExperimentFile) -> Checked {
        let (Some(r), Some(s)) = (&file.scene.reynolds, &file.scene.substokes) else {
            return Ok(());
        };
        same_film(check, r, s)?;
        check.ensure(
            s.solver == FilmSolver::Ldlt,
            "scene.substokes.solver",
            "`ldlt` (or left out) in a model-adaptive film: its coupled solve factors the \
             SubStokes system with the LDLᵀ",
            format!("`{}`", s.solver.name()),
        )?;
        check.ensure(
            s.compare_with.is_none(),
            "scene.substokes.compare_with",
            "no such field in a model-adaptive film (the report runs no second solver beside \
             it)",
            format!("{:?}", s.compare_with.map(FilmSolver::name)),
        )
    }

    /// A pure Reynolds or pure SubStokes table of the same film on the same domain: the runs
    /// the film's figures set beside it (Figs. IV.117, IV.118).
    fn related_to(&self, own: &Experiment, other: &Experiment) -> Result<(), String> {
        let Problem::FilmModels { reynolds: film, .. } = &own.problem else {
            return Ok(());
        };
        let same = |equation: &str, gap: &GapShape, velocity: &[f64; 3], pressure| {
            equation == film.equation
                && *gap == film.gap
                && *velocity == film.upper_wall_velocity
                && pressure == film.boundary_pressure
        };
        let same_film = match &other.problem {
            Problem::Reynolds(r) => same(
                &r.equation,
                &r.gap,
                &r.upper_wall_velocity,
                r.boundary_pressure,
            ),
            Problem::SubStokes(s) => same(
                &s.equation,
                &s.gap,
                &s.upper_wall_velocity,
                s.boundary_pressure,
            ),
            _ => false,
        };
        if same_film && other.scene.domain == own.scene.domain {
            Ok(())
        } else {
            Err(format!(
                "a table of the same film (equation `{}`, the same gap, wall velocity and \
                 boundary pressure) on the same domain",
                film.equation
            ))
        }
    }

    /// The warnings of both models' data on the one film.
    fn warnings(&self, experiment: &Experiment, scope: &Scope, out: &mut Vec<Warning>) {
        if let Problem::FilmModels {
            reynolds,
            substokes,
        } = &experiment.problem
        {
            super::reynolds::film_warnings(reynolds, scope, out);
            super::substokes::film_warnings(substokes, &experiment.scene.domain, scope, out);
        }
    }

    fn problem(&self, scene: &SceneFile) -> Result<Problem, &'static str> {
        let reynolds = scene.reynolds.clone().ok_or("reynolds")?;
        let substokes = scene.substokes.clone().ok_or("substokes")?;
        Ok(Problem::FilmModels {
            reynolds,
            substokes,
        })
    }

    fn build(&self, experiment: &Experiment) -> Result<Box<dyn study::Problem>, StudyError> {
        let Problem::FilmModels { substokes, .. } = &experiment.problem else {
            return Err(StudyError::Failed(
                "a model-adaptive film needs Reynolds and SubStokes data".into(),
            ));
        };
        Ok(Box::new(model_fluid::ModelAdaptiveFilm::new(
            substokes,
            &experiment.scene.domain,
        )))
    }

    /// The film's own marking ([`model_fluid::marking`]): model and grid marking from the same
    /// indicators, without the balance (III.93).
    fn adaptation(&self, experiment: &Experiment) -> Box<dyn Adaptation> {
        match experiment.study.plan {
            Plan::ModelAndGridAdaptive { grid, model, .. } => {
                Box::new(model_fluid::marking(grid, model, experiment.study.ties))
            }
            _ => study::build_adaptation(&experiment.study, &experiment.scene),
        }
    }
}

/// The two sections of a model-adaptive film describe one film, without cavitation (the
/// coupling of §IV.3.4 has none).
fn same_film(check: &Check, r: &ReynoldsData, s: &SubStokesData) -> Checked {
    let pairs = [
        (
            "equation",
            r.equation == s.equation,
            format!("`{}` and `{}`", r.equation, s.equation),
        ),
        (
            "gap",
            r.gap == s.gap,
            format!("{:?} and {:?}", r.gap, s.gap),
        ),
        (
            "upper_wall_velocity",
            r.upper_wall_velocity == s.upper_wall_velocity,
            format!(
                "{:?} and {:?}",
                r.upper_wall_velocity, s.upper_wall_velocity
            ),
        ),
        (
            "boundary_pressure",
            r.boundary_pressure == s.boundary_pressure,
            format!("{:?} and {:?}", r.boundary_pressure, s.boundary_pressure),
        ),
    ];
    for (field, same, found) in pairs {
        check.ensure(
            same,
            &format!("scene.substokes.{field}"),
            &format!("the same {field} as scene.reynolds (both models solve one film)"),
            found,
        )?;
    }
    for (section, cavitation) in [("reynolds", r.cavitation), ("substokes", s.cavitation)] {
        check.ensure(
            cavitation == Cavitation::Off,
            &format!("scene.{section}.cavitation"),
            "\"off\" in a model-adaptive film (the coupling of §IV.3.4 has no cavitation)",
            format!("{cavitation:?}"),
        )?;
    }
    Ok(())
}
