//! The families of tables: one module per kind of run, stating everything that kind needs —
//! the effects a scene names, the checks of their combination, the probe components, the
//! unknowns per vertex (for the memory budget), the warnings of the file and of the run, the
//! alternative readings the report runs beside it, the linear solver, the model the cycle loop
//! solves, the adaptation between cycles, and the box of the report that explains it.
//!
//! The loader ([`crate::experiment::load`]) picks a scene's family from [`FAMILIES`] by its
//! effects and its study kind and stores it in the [`Experiment`]; the study, the budget, the
//! warnings and the readings ask the experiment's family instead of matching on problems or
//! table ids. Adding a family is its module here, its entry in [`FAMILIES`], and its figures in
//! the report (plus, for new data, its section in the file format and its model).
//!
//! A family sits above the file format and the models: its checks use the loader's [`Check`],
//! its `build` the study's problems. The report does not use this module: it reads the run's
//! results, and a family's box on the page from `src/report/text/families.toml` under the id
//! [`Facts::report_family`] names (the test `report_boxes_name_the_families` ties the two).

mod contact;
mod elasticity;
mod model_contact;
mod model_fluid;
mod reynolds;
mod stokes_channel;
mod substokes;

use std::fmt;

use crate::experiment::{
    Check, Checked, Effect, Experiment, ExperimentFile, Problem, SceneFile, Scope, StudyKind,
    Warning,
};
use crate::linalg::SolverKind;
use crate::results::Row;
use crate::study::{self, Adaptation, AlternativeReading, StudyError};

/// What a family is, as plain data.
pub struct Facts {
    /// A short name, e.g. `reynolds`, unique in [`FAMILIES`].
    pub id: &'static str,
    /// The effects a scene of the family names (in any order).
    pub effects: &'static [Effect],
    /// The study kinds it runs. Where several families share the effects (contact and
    /// model-adaptive contact) the kind decides.
    pub kinds: &'static [StudyKind],
    /// The id of the family's box in the report (`src/report/text/families.toml`); `None`
    /// where the page has none.
    pub report_family: Option<&'static str>,
    /// The fields a probe can record: the components of the computed solution.
    pub components: &'static [&'static str],
    /// Solution components per vertex, for the memory budget of a cycle
    /// ([`crate::study::budget`]).
    pub unknowns_per_vertex: usize,
    /// Whether `[study] solver` chooses the linear solver of its systems (elsewhere the field
    /// is refused: it would be accepted and ignored).
    pub solver_choice: bool,
    /// The families whose tables the report can draw beside this one (`related` of the file);
    /// empty where it draws none.
    pub related: &'static [&'static str],
    /// The engineering quantities its rows carry ([`crate::study::quantities`]: the film's, the
    /// contact's, or none), which a sweep of its scenes can compare.
    pub quantities: &'static [&'static str],
}

/// One family of tables (module docs): its [`Facts`], and what it does at each stage. The
/// provided methods are what most families do.
pub trait Family: Sync {
    fn facts(&self) -> &'static Facts;

    /// Checks of the combination of sections the family needs, after each section's own
    /// checks and before the study's.
    fn check(&self, _check: &Check, _file: &ExperimentFile) -> Checked {
        Ok(())
    }

    /// The typed problem of a checked scene, or the name of a data section it lacks.
    fn problem(&self, scene: &SceneFile) -> Result<Problem, &'static str>;

    /// What is legal but suspicious in the family's data ([`Experiment::warnings`]).
    fn warnings(&self, _experiment: &Experiment, _scope: &Scope, _out: &mut Vec<Warning>) {}

    /// What only a finished run shows to be suspicious ([`crate::study::warnings`]).
    fn run_warnings(&self, _experiment: &Experiment, _rows: &[Row], _out: &mut Vec<Warning>) {}

    /// The alternative readings the report runs beside the experiment as written.
    fn readings(&self, _experiment: &Experiment) -> Vec<AlternativeReading> {
        Vec::new()
    }

    /// The linear solver of the SPD systems when neither the file nor `report --solver` names
    /// one: the one measured faster for the family.
    fn default_solver(&self) -> SolverKind {
        SolverKind::Direct
    }

    /// Why the scene has no solution in one of its first `rows` printed rows (the load steps of
    /// a load-step study), if it has none: checked before the first solve (the loader checks
    /// what the file alone says, this needs the models).
    fn infeasible(&self, _experiment: &Experiment, _rows: usize) -> Option<Infeasible> {
        None
    }

    /// Whether `other`, a table of a family in [`Facts::related`], solves the same scene and
    /// can be drawn beside `own`; else what the check of `related` expects.
    fn related_to(&self, _own: &Experiment, _other: &Experiment) -> Result<(), String> {
        Ok(())
    }

    /// Whether the report runs the cost-of-accuracy study ([`crate::study::cost`]) beside the
    /// experiment.
    fn cost_study(&self, _experiment: &Experiment) -> bool {
        false
    }

    /// The model the cycle loop solves.
    fn build(&self, experiment: &Experiment) -> Result<Box<dyn study::Problem>, StudyError>;

    /// What changes between the cycles: by default the strategy of the `[study] kind`.
    fn adaptation(&self, experiment: &Experiment) -> Box<dyn Adaptation> {
        study::build_adaptation(&experiment.study, &experiment.scene)
    }
}

/// Why a scene has no solution, and in which load step (`None` outside a load-step study).
#[derive(Clone, Debug, PartialEq)]
pub struct Infeasible {
    pub step: Option<usize>,
    pub message: String,
}

/// Every family, in the order of Chapter IV.
pub const FAMILIES: [&dyn Family; 7] = [
    &elasticity::Elasticity,
    &contact::Contact,
    &model_contact::ModelContact,
    &reynolds::Reynolds,
    &substokes::SubStokes,
    &model_fluid::ModelFluid,
    &stokes_channel::StokesChannel,
];

/// The family of a scene with `effects` and a study of `kind`: the one with these effects that
/// runs the kind, else the first with these effects (whose checks then say what is wrong with
/// the kind); `None` when no family has these effects.
pub fn of_scene(effects: &[Effect], kind: StudyKind) -> Option<FamilyRef> {
    let same = |f: &&&dyn Family| {
        let own = f.facts().effects;
        own.len() == effects.len() && own.iter().all(|e| effects.contains(e))
    };
    let mut candidates = FAMILIES.iter().filter(same).peekable();
    let first = **candidates.peek()?;
    let chosen = candidates
        .find(|f| f.facts().kinds.contains(&kind))
        .copied()
        .unwrap_or(first);
    Some(FamilyRef(chosen))
}

/// An experiment's family: a reference into [`FAMILIES`], compared and printed by its id.
#[derive(Clone, Copy)]
pub struct FamilyRef(pub &'static dyn Family);

impl std::ops::Deref for FamilyRef {
    type Target = dyn Family;
    fn deref(&self) -> &(dyn Family + 'static) {
        self.0
    }
}

impl PartialEq for FamilyRef {
    fn eq(&self, other: &FamilyRef) -> bool {
        self.0.facts().id == other.0.facts().id
    }
}

impl fmt::Debug for FamilyRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "FamilyRef({})", self.0.facts().id)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_and_effect_kind_pairs_are_unique() {
        let kinds = [
            StudyKind::GridAdaptive,
            StudyKind::ModelAdaptive,
            StudyKind::ModelAndGridAdaptive,
            StudyKind::LoadSteps,
            StudyKind::SolverIterations,
        ];
        for (i, a) in FAMILIES.iter().enumerate() {
            let a = a.facts();
            for b in &FAMILIES[i + 1..] {
                let b = b.facts();
                assert_ne!(a.id, b.id);
                let same_effects = a.effects.len() == b.effects.len()
                    && a.effects.iter().all(|e| b.effects.contains(e));
                for kind in kinds {
                    assert!(
                        !(same_effects && a.kinds.contains(&kind) && b.kinds.contains(&kind)),
                        "{} and {} both run {kind:?} on the same effects",
                        a.id,
                        b.id
                    );
                }
            }
        }
    }

    #[test]
    fn the_kind_decides_between_families_of_the_same_effects() {
        let contact = [Effect::Contact, Effect::Elasticity];
        let id = |kind| of_scene(&contact, kind).map(|f| f.facts().id);
        assert_eq!(id(StudyKind::GridAdaptive), Some("contact"));
        assert_eq!(id(StudyKind::ModelAdaptive), Some("model-contact"));
        assert_eq!(id(StudyKind::LoadSteps), Some("model-contact"));
        assert_eq!(
            of_scene(&[Effect::StokesChannel], StudyKind::GridAdaptive).map(|f| f.facts().id),
            Some("stokes-channel")
        );
        assert!(of_scene(&[Effect::Contact], StudyKind::GridAdaptive).is_none());
    }

    /// Every table of a report box belongs to a family whose `report_family` names that box,
    /// and every box a family names exists. Shipped scenes of tribo's own (the manufactured
    /// solutions) are in no box: the page shows them with the scenes of your own.
    #[test]
    fn report_boxes_name_the_families() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments");
        let experiments = crate::experiment::load_dir(&dir, None).unwrap();
        let boxes = crate::report::families::families();
        let thesis = experiments
            .iter()
            .filter(|e| e.comparison != crate::experiment::Comparison::OwnScene);
        for e in thesis {
            let listed = boxes.iter().find(|b| b.tables.contains(&e.table));
            assert_eq!(
                listed.map(|b| b.id.as_str()),
                e.family.facts().report_family,
                "{}: report box against family {}",
                e.table,
                e.family.facts().id
            );
        }
        for f in FAMILIES {
            if let Some(id) = f.facts().report_family {
                assert!(boxes.iter().any(|b| b.id == id), "{id}");
            }
        }
    }
}
