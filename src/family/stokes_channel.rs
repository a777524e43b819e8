//! The Uzawa comparison of Fig. III.6 on the stabilised Stokes test problem (III.88): a solver
//! study, every variant of Uzawa's algorithm iterated on one mesh.

use std::collections::BTreeSet;

use super::{Facts, Family};
use crate::experiment::{
    Check, Checked, Effect, Experiment, ExperimentFile, Problem, SceneFile, StudyKind,
};
use crate::linalg::uzawa::Variant;
use crate::study::{self, StudyError};

pub struct StokesChannel;

impl Family for StokesChannel {
    fn facts(&self) -> &'static Facts {
        &Facts {
            id: "stokes-channel",
            effects: &[Effect::StokesChannel],
            kinds: &[StudyKind::SolverIterations],
            report_family: None,
            components: &[],
            unknowns_per_vertex: 3,
        }
    }

    /// δ_ε > 0, a list of known, distinct variants, and a solver study.
    fn check(&self, check: &Check, file: &ExperimentFile) -> Checked {
        let Some(data) = &file.scene.stokes_channel else {
            return Ok(());
        };
        const F: &str = "scene.stokes_channel";
        check.positive(&format!("{F}.delta_eps"), data.delta_eps)?;
        check.ensure(
            !data.variants.is_empty(),
            &format!("{F}.variants"),
            "at least one Uzawa variant",
            "an empty list",
        )?;
        let mut seen = BTreeSet::new();
        for (i, v) in data.variants.iter().enumerate() {
            let field = format!("{F}.variants[{i}]");
            check.ensure(
                Variant::from_name(v).is_some(),
                &field,
                "one of `identity`, `jacobi`, `gauss-seidel`, `ssor`, `cg-ssor`",
                format!("`{}`", v.escape_debug()),
            )?;
            check.ensure(
                seen.insert(v.as_str()),
                &field,
                "each variant once",
                format!("`{v}` twice"),
            )?;
        }
        let kind = file.study.kind;
        check.ensure(
            kind == StudyKind::SolverIterations,
            "study.kind",
            "\"solver-iterations\" for the Uzawa test problem (it iterates a solver on one mesh)",
            format!("`{}`", kind.name()),
        )
    }

    fn problem(&self, scene: &SceneFile) -> Result<Problem, &'static str> {
        Ok(Problem::StokesChannel(
            scene.stokes_channel.clone().ok_or("stokes_channel")?,
        ))
    }

    /// None: the solver study runs its variants itself ([`study::solver_iterations`]).
    fn build(&self, _experiment: &Experiment) -> Result<Box<dyn study::Problem>, StudyError> {
        Err(StudyError::Failed(
            "the Uzawa test problem runs as a solver-iterations study only".into(),
        ))
    }
}
