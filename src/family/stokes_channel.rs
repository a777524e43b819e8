//! The Uzawa comparison of Fig. III.6 on the stabilised Stokes test problem (III.88): a solver
//! study, every variant of Uzawa's algorithm iterated on one mesh.

use std::collections::BTreeSet;

use super::{Facts, Family};
use crate::experiment::{
    Check, Checked, Effect, Experiment, ExperimentFile, Problem, SceneFile, Scope, StudyKind,
    Warning,
};
use crate::linalg::uzawa::Variant;
use crate::models::stokes_channel::{CELLS_PER_SIDE, SIDE};
use crate::study::{self, StudyError};

pub struct StokesChannel;

impl Family for StokesChannel {
    fn facts(&self) -> &'static Facts {
        &Facts {
            id: "stokes-channel",
            effects: &[Effect::StokesChannel],
            kinds: &[StudyKind::SolverIterations],
            report_family: Some("family-uzawa"),
            components: &[],
            unknowns_per_vertex: 3,
            solver_choice: false,
            related: &[],
            quantities: &[],
        }
    }

    /// δ_ε > 0, a list of known, distinct variants, and a solver study.
    fn check(&self, check: &Check, file: &ExperimentFile) -> Checked {
        let Some(data) = &file.scene.stokes_channel else {
            return Ok(());
        };
        geometry(check, &file.scene)?;
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

    /// A stabilisation far from the (III.88)'s δ_ε = 1.
    fn warnings(&self, experiment: &Experiment, _scope: &Scope, out: &mut Vec<Warning>) {
        let Problem::StokesChannel(data) = &experiment.problem else {
            return;
        };
        if !(1e-3..=1e3).contains(&data.delta_eps) {
            out.push(Warning::new(
                "scene.stokes_channel.delta_eps",
                format!(
                    "δ_ε = {:e}, three orders of magnitude or more from the 1 of (III.88): the \
                     stabilisation Σ δ_ε h_Q²⟨∇p, ∇q⟩ {} the pressure, and the iteration counts \
                     are not comparable with Fig. III.6",
                    data.delta_eps,
                    if data.delta_eps > 1.0 {
                        "dominates"
                    } else {
                        "hardly stabilises"
                    }
                ),
            ));
        }
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

/// The test problem (III.88) is one mesh: Ω = [0, 4]² in 32×32 cells ([`crate::models::stokes_channel::StokesChannel`]
/// fixes both). A scene that writes another domain or mesh would print it on the page
/// beside the numbers of this one.
fn geometry(check: &Check, scene: &SceneFile) -> Checked {
    let square = [0.0, SIDE];
    check.ensure(
        scene.domain.x == square && scene.domain.y == square,
        "scene.domain",
        "x = [0, 4], y = [0, 4]: the domain of the test problem (III.88)",
        format!("x = {:?}, y = {:?}", scene.domain.x, scene.domain.y),
    )?;
    let [nx, ny] = scene.coarse_cells;
    let cells = nx.checked_shl(scene.global_refinements as u32);
    check.ensure(
        nx == ny && cells == Some(CELLS_PER_SIDE),
        "scene.coarse_cells",
        &format!(
            "a square coarse grid that global_refinements refine to {0}×{0} cells, e.g. [1, 1] \
             with global_refinements = 5: the mesh of the test problem (III.88)",
            CELLS_PER_SIDE
        ),
        format!(
            "[{nx}, {ny}] with global_refinements = {}",
            scene.global_refinements
        ),
    )
}
