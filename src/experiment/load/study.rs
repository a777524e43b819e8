//! The study: how many rows, and how the cycles iterate — grid adaptivity (§IV.1), model
//! adaptivity (§IV.2.3, §IV.2.4), load steps (§IV.2.4.7) or solver iterations (Fig. III.6).

use super::check::{names, Check, Checked};
use super::film::is_film_models;
use crate::experiment::spec::*;
use crate::experiment::ExperimentError;

/// Most cycles of one load step (§IV.2.4.7 runs 4).
const MAX_CYCLES_PER_STEP: usize = 12;
/// Most printed rows of a study (and of a thesis table); Chapter IV prints at most 26.
pub const MAX_ROWS: usize = 200;
/// Most iterations of a solver study (`solver-iterations`, Fig. III.6 runs 300).
const MAX_ITERATIONS: usize = 10_000;
/// Most unprinted cycles before row 0 (Chapter IV uses at most a few).
pub const MAX_UNPRINTED_CYCLES: usize = 200;

impl Check<'_> {
    /// The printed cycles and how to iterate: fixed-fraction grid adaptivity (§IV.1: refine
    /// 30 %, coarsen 3 %) or model adaptivity (§IV.2.3: Algorithm III.2 or III.3).
    pub(super) fn study(&self, study: &StudyFile, scene: &SceneFile) -> Checked {
        self.ensure(study.rows >= 1, "study.rows", "at least 1", study.rows)?;
        self.ensure(
            !is_film_models(scene) || study.kind == StudyKind::ModelAndGridAdaptive,
            "study.kind",
            "\"model-and-grid-adaptive\" for a scene with `reynolds` and `substokes` (the \
             model-adaptive film of §IV.3.4)",
            format!("`{}`", study.kind.name()),
        )?;
        if study.kind == StudyKind::SolverIterations {
            self.ensure(
                study.rows <= MAX_ITERATIONS,
                "study.rows",
                &format!("at most {MAX_ITERATIONS} solver iterations"),
                study.rows,
            )?;
        } else {
            self.ensure(
                study.rows <= MAX_ROWS,
                "study.rows",
                &format!("at most {MAX_ROWS} printed rows"),
                study.rows,
            )?;
        }
        self.ensure(
            study.unprinted_cycles <= MAX_UNPRINTED_CYCLES,
            "study.unprinted_cycles",
            &format!("at most {MAX_UNPRINTED_CYCLES} cycles before the printed rows"),
            study.unprinted_cycles,
        )?;
        self.ensure(
            study.quick_rows >= 1,
            "study.quick_rows",
            "at least 1",
            study.quick_rows,
        )?;
        self.ensure(
            study.quick_rows <= study.rows,
            "study.quick_rows",
            &format!("at most study.rows ({})", study.rows),
            study.quick_rows,
        )?;
        match study.kind {
            StudyKind::GridAdaptive => {
                self.refused(
                    study,
                    "\"model-adaptive\", \"model-and-grid-adaptive\" or \"load-steps\"",
                    &[
                        ("study.algorithm", study.algorithm.is_some()),
                        ("study.model_tolerance", study.model_tolerance.is_some()),
                    ],
                )?;
                self.refused_model_and_grid_fields(study)?;
                let model = scene.contact.as_ref().map(|c| c.model);
                self.ensure(
                    model != Some(ContactModel::ModelAdaptive),
                    "scene.contact.model",
                    "`z` or `signorini` in a grid-adaptive study (model = \"model-adaptive\" \
                     needs study.kind = \"model-adaptive\" or \"model-and-grid-adaptive\")",
                    "`model-adaptive`",
                )?;
                self.grid_marking(study)
            }
            StudyKind::ModelAdaptive => {
                self.refused_model_and_grid_fields(study)?;
                self.fractions(study)?;
                self.model_marking(
                    study,
                    scene,
                    ["study.refine_fraction", "study.coarsen_fraction"],
                )?;
                if let Some([first, last]) = study.convergence_window {
                    return Err(self.fail(
                        "study.convergence_window",
                        "no convergence window in a model-adaptive study (the mesh is fixed: \
                         there is no discretisation error that converges)",
                        format!("[{first}, {last}]"),
                    ));
                }
                Ok(())
            }
            StudyKind::ModelAndGridAdaptive | StudyKind::LoadSteps => {
                for (field, given) in [
                    ("study.model_refine_fraction", study.model_refine_fraction),
                    ("study.model_coarsen_fraction", study.model_coarsen_fraction),
                ] {
                    if given.is_none() {
                        return Err(self.fail(
                            field,
                            "the fraction of the model marking (p_r, p_c of Algorithm III.3; \
                             refine_fraction and coarsen_fraction are the grid's)",
                            "no such field",
                        ));
                    }
                }
                self.model_marking(
                    study,
                    scene,
                    [
                        "study.model_refine_fraction",
                        "study.model_coarsen_fraction",
                    ],
                )?;
                if let Some(alpha) = study.balance {
                    self.ensure(
                        alpha > 0.0 && alpha < 1.0,
                        "study.balance",
                        "α of the balance (III.93) in (0, 1)",
                        alpha,
                    )?;
                }
                if study.kind == StudyKind::LoadSteps {
                    self.grid_fractions(study)?;
                    self.load_steps(study)
                } else {
                    self.refused(study, "\"load-steps\"", &load_step_fields(study))?;
                    self.grid_marking(study)
                }
            }
            StudyKind::SolverIterations => self.solver_iterations(study, scene),
        }
    }

    /// A grid marking that refines at least one cell of the first mesh: the fixed-number
    /// marking refines ⌊θ_r · N⌋ of N cells, and with none refined the mesh never changes — an
    /// "adaptive" study whose ratios are all 1. Checked where the first mesh is the coarse
    /// grid refined globally (N = n_x n_y 4^global_refinements); refinements at the contact
    /// sides only add cells.
    pub(super) fn marks_cells(&self, study: &StudyFile, scene: &SceneFile) -> Checked {
        let (Some(refine), true) = (study.refine_fraction, study.kind.adapts_grid()) else {
            return Ok(());
        };
        if scene.contact_refinements > 0 {
            return Ok(());
        }
        let [nx, ny] = scene.coarse_cells;
        let cells = nx as f64 * ny as f64 * 4f64.powi(scene.global_refinements as i32);
        let marked = (refine * cells).floor();
        self.ensure(
            marked >= 1.0,
            "study.refine_fraction",
            &format!(
                "a fraction that refines at least one of the {cells} cells of the first mesh \
                 (the marking refines ⌊refine_fraction · N⌋ cells; with none the mesh never \
                 changes)"
            ),
            format!("{refine:e}, which refines ⌊{:e}⌋ = 0", refine * cells),
        )
    }

    /// The typed study of a checked `[study]`: the fields of its kind, with the defaults of
    /// ε₀ and α. [`Check::study`] has checked every field read here; one that is missing all
    /// the same is an error, never a default.
    pub(super) fn typed_study(&self, study: &StudyFile) -> Result<Study, ExperimentError> {
        let given = |field: &str, value: Option<f64>| {
            value.ok_or_else(|| self.fail(field, "a fraction", "no such field"))
        };
        let grid = || -> Result<GridFractions, ExperimentError> {
            let (refine, coarsen) = self.fractions(study)?;
            Ok(GridFractions { refine, coarsen })
        };
        let model = |on_fixed_mesh: bool| -> Result<ModelFractions, ExperimentError> {
            let algorithm = study.algorithm.ok_or_else(|| {
                self.fail(
                    "study.algorithm",
                    "`III.2` (fixed fraction) or `III.3` (sorted error)",
                    "no such field",
                )
            })?;
            let (refine, coarsen) = if on_fixed_mesh {
                self.fractions(study)?
            } else {
                (
                    given("study.model_refine_fraction", study.model_refine_fraction)?,
                    given("study.model_coarsen_fraction", study.model_coarsen_fraction)?,
                )
            };
            Ok(ModelFractions {
                algorithm,
                refine,
                coarsen,
                tolerance: study.model_tolerance.unwrap_or(DEFAULT_MODEL_TOLERANCE),
            })
        };
        let window = || {
            study.convergence_window.ok_or_else(|| {
                self.fail(
                    "study.convergence_window",
                    "[first, last]: the printed cycles where the convergence rule applies",
                    "no such field",
                )
            })
        };
        let balance = study.balance.unwrap_or(DEFAULT_BALANCE);
        let plan = match study.kind {
            StudyKind::GridAdaptive => Plan::GridAdaptive {
                grid: grid()?,
                window: window()?,
            },
            StudyKind::ModelAdaptive => Plan::ModelAdaptive {
                model: model(true)?,
            },
            StudyKind::ModelAndGridAdaptive => Plan::ModelAndGridAdaptive {
                grid: grid()?,
                model: model(false)?,
                balance,
                window: window()?,
            },
            StudyKind::LoadSteps => Plan::LoadSteps {
                grid: grid()?,
                model: model(false)?,
                balance,
                cycles_per_step: study.cycles_per_step.ok_or_else(|| {
                    self.fail(
                        "study.cycles_per_step",
                        "a number of cycles",
                        "no such field",
                    )
                })?,
                lift_per_step: study
                    .lift_per_step
                    .ok_or_else(|| self.fail("study.lift_per_step", "a lift", "no such field"))?,
            },
            StudyKind::SolverIterations => Plan::SolverIterations,
        };
        Ok(Study {
            rows: study.rows,
            quick_rows: study.quick_rows,
            unprinted_cycles: study.unprinted_cycles,
            ties: study.ties,
            solver: study.solver,
            signorini_comparison: true,
            true_error: true,
            vtu: crate::results::VtuOutput::Last,
            // The loader decides, once it knows whether the file is the thesis's.
            readings: false,
            plan,
        })
    }

    /// `[study] alternatives = true` where the family has a reading of the thesis to run
    /// beside the scene (else the field would be accepted and do nothing).
    pub(super) fn has_readings(&self, experiment: &crate::experiment::Experiment) -> Checked {
        let thesis_readings = crate::study::alternative_readings(experiment)
            .iter()
            .filter(|reading| !reading.asked)
            .count();
        self.ensure(
            thesis_readings > 0,
            "study.alternatives",
            "a scene with an alternative reading of the thesis (a Reynolds film with cavitation \
             and the printed source R₃c: two readings of R₃c; model-adaptive contact: the model \
             error at the z-solution); remove the field",
            format!(
                "`true` in a {} scene without one",
                experiment.family.facts().id
            ),
        )
    }

    /// A solver study (Fig. III.6): the Uzawa test problem and none of the adaptive fields.
    fn solver_iterations(&self, study: &StudyFile, scene: &SceneFile) -> Checked {
        self.ensure(
            scene.effects == [Effect::StokesChannel],
            "scene.effects",
            "[\"stokes-channel\"] in a solver-iterations study (the Uzawa test problem (III.88))",
            format!("{:?}", names(&scene.effects)),
        )?;
        self.refused_model_and_grid_fields(study)?;
        let marking = [
            ("study.refine_fraction", study.refine_fraction.is_some()),
            ("study.coarsen_fraction", study.coarsen_fraction.is_some()),
            (
                "study.convergence_window",
                study.convergence_window.is_some(),
            ),
            ("study.algorithm", study.algorithm.is_some()),
            ("study.model_tolerance", study.model_tolerance.is_some()),
            ("study.unprinted_cycles", study.unprinted_cycles > 0),
            ("study.ties", study.ties != Ties::default()),
        ];
        self.refused(study, "the adaptive kinds", &marking)
    }

    /// `rises` of an obstacle: only the `arc` tools of a load-step study rise (§IV.2.4.7).
    pub(super) fn rising_tools(&self, scene: &SceneFile, study: &StudyFile) -> Checked {
        let Some(contact) = &scene.contact else {
            return Ok(());
        };
        for (i, obstacle) in contact.obstacles.iter().enumerate() {
            if obstacle.rises.is_none() {
                continue;
            }
            let field = format!("scene.contact.obstacles[{i}].rises");
            self.ensure(
                study.kind == StudyKind::LoadSteps,
                &field,
                "no such field outside a study.kind = \"load-steps\" (tools rise between load \
                 steps)",
                format!("a value in a {} study", study.kind.name()),
            )?;
            self.ensure(
                matches!(obstacle.shape, ObstacleShape::Arc { .. }),
                &field,
                "a tool of kind = \"arc\" (the U-O forming's punch and die; other shapes do \
                 not rise)",
                "another shape",
            )?;
        }
        Ok(())
    }

    /// The load steps of a forming study (§IV.2.4.7): at least one cycle per step, a finite
    /// lift, and no convergence window (every step restarts from the coarse cells).
    fn load_steps(&self, study: &StudyFile) -> Checked {
        let Some(cycles) = study.cycles_per_step else {
            return Err(self.fail(
                "study.cycles_per_step",
                "the cycles of model and grid adaptivity in every load step (4 in §IV.2.4.7)",
                "no such field",
            ));
        };
        self.ensure(
            (1..=MAX_CYCLES_PER_STEP).contains(&cycles),
            "study.cycles_per_step",
            &format!("between 1 and {MAX_CYCLES_PER_STEP} cycles per load step"),
            cycles,
        )?;
        let Some(lift) = study.lift_per_step else {
            return Err(self.fail(
                "study.lift_per_step",
                "how far the rising tools rise in every load step (10/24 in §IV.2.4.7)",
                "no such field",
            ));
        };
        self.finite("study.lift_per_step", lift)?;
        if let Some([first, last]) = study.convergence_window {
            return Err(self.fail(
                "study.convergence_window",
                "no convergence window in a load-step study (every step restarts from the \
                 coarse cells of its body: there is no sequence of meshes that converges)",
                format!("[{first}, {last}]"),
            ));
        }
        Ok(())
    }

    /// The fields of the model-and-grid and the load-step studies, in a study of another kind.
    fn refused_model_and_grid_fields(&self, study: &StudyFile) -> Checked {
        self.refused(
            study,
            "\"model-and-grid-adaptive\" or \"load-steps\"",
            &balance_fields(study),
        )?;
        self.refused(study, "\"load-steps\"", &load_step_fields(study))
    }

    /// Fields a study kind does not have, each given or not; they belong to the kinds `owners`.
    fn refused(&self, study: &StudyFile, owners: &str, fields: &[(&str, bool)]) -> Checked {
        for &(field, given) in fields {
            self.ensure(
                !given,
                field,
                &format!(
                    "no such field in a {} study (it belongs to study.kind = {owners})",
                    study.kind.name()
                ),
                "a value",
            )?;
        }
        Ok(())
    }

    /// Fixed-number grid marking: the fractions and the convergence window.
    fn grid_marking(&self, study: &StudyFile) -> Checked {
        self.grid_fractions(study)?;
        let Some([first, last]) = study.convergence_window else {
            return Err(self.fail(
                "study.convergence_window",
                "[first, last]: the printed cycles where the convergence rule applies",
                "no such field",
            ));
        };
        self.ensure(
            first <= last,
            "study.convergence_window",
            "[first, last] with first ≤ last",
            format!("[{first}, {last}]"),
        )?;
        self.ensure(
            last < study.rows,
            "study.convergence_window[1]",
            &format!(
                "a printed cycle, at most study.rows − 1 ({})",
                study.rows - 1
            ),
            last,
        )
    }

    /// The fractions θ_r, θ_c of fixed-number grid marking.
    fn grid_fractions(&self, study: &StudyFile) -> Checked {
        let (refine, coarsen) = self.fractions(study)?;
        self.non_negative("study.coarsen_fraction", coarsen)?;
        self.positive("study.refine_fraction", refine)?;
        let total = refine + coarsen;
        self.ensure(
            total <= 1.0,
            "study.refine_fraction",
            "refine_fraction + coarsen_fraction ≤ 1",
            format!("{refine:?} + {coarsen:?} = {total:?}"),
        )
    }

    /// `refine_fraction` and `coarsen_fraction`, which every kind but `solver-iterations` needs.
    fn fractions(&self, study: &StudyFile) -> Result<(f64, f64), ExperimentError> {
        let given = |field: &str, v: Option<f64>| {
            v.ok_or_else(|| {
                self.fail(
                    field,
                    &format!("a fraction: a {} study marks with it", study.kind.name()),
                    "no such field",
                )
            })
        };
        Ok((
            given("study.refine_fraction", study.refine_fraction)?,
            given("study.coarsen_fraction", study.coarsen_fraction)?,
        ))
    }

    /// The model marking of a model-adaptive or model-and-grid-adaptive study (§IV.2.3,
    /// §IV.2.4): a contact scene whose faces the marking assigns (`model = "model-adaptive"`),
    /// Algorithm III.2 with p_r, p_c ∈ [0, 1] or III.3 with p_r, p_c ∈ (0, 1) (read from the
    /// two `fraction_fields`), and ε₀ > 0.
    fn model_marking(
        &self,
        study: &StudyFile,
        scene: &SceneFile,
        fraction_fields: [&str; 2],
    ) -> Checked {
        if is_film_models(scene) {
            // The model-adaptive film (§IV.3.4): Algorithm III.3 over the cells.
            self.ensure(
                study.algorithm == Some(ModelAlgorithm::SortedError),
                "study.algorithm",
                "`III.3` (sorted error) for the model-adaptive film (§IV.3.4)",
                format!("{:?}", study.algorithm),
            )?;
            self.ensure(
                study.balance.is_none(),
                "study.balance",
                "no balance in the model-adaptive film (its model and grid markings use their \
                 own indicators, §IV.3.4)",
                "a value",
            )?;
        } else if let Some(contact) = &scene.contact {
            self.ensure(
                contact.model == ContactModel::ModelAdaptive,
                "scene.contact.model",
                "`model-adaptive` in a model-adaptive study (the marking chooses z or Signorini \
                 per face; a fixed model leaves nothing to choose)",
                format!("`{}`", contact.model.name()),
            )?;
        } else {
            return Err(self.fail(
                "study.kind",
                "a scene with contact for a model-adaptive study (it chooses the contact model \
                 face by face, §IV.2.3)",
                format!(
                    "`{}` with scene.effects {:?}",
                    study.kind.name(),
                    names(&scene.effects)
                ),
            ));
        }
        let Some(algorithm) = study.algorithm else {
            return Err(self.fail(
                "study.algorithm",
                "`III.2` (fixed fraction) or `III.3` (sorted error)",
                "no such field",
            ));
        };
        let (p_r, p_c) = file_model_fractions(study);
        for (field, p) in fraction_fields.into_iter().zip([p_r, p_c]) {
            match algorithm {
                ModelAlgorithm::FixedFraction => self.ensure(
                    (0.0..=1.0).contains(&p),
                    field,
                    "a fraction in [0, 1] for Algorithm III.2",
                    p,
                )?,
                ModelAlgorithm::SortedError => self.ensure(
                    p > 0.0 && p < 1.0,
                    field,
                    "a fraction in (0, 1) for Algorithm III.3",
                    p,
                )?,
            }
        }
        if let Some(eps0) = study.model_tolerance {
            self.positive("study.model_tolerance", eps0)?;
        }
        Ok(())
    }
}

/// p_r and p_c of the model marking as written: `refine_fraction` and `coarsen_fraction` on a
/// fixed mesh, the `model_*` fractions when the grid adapts too (NaN where missing, which the
/// checks of the fraction refuse).
fn file_model_fractions(study: &StudyFile) -> (f64, f64) {
    match study.kind {
        StudyKind::ModelAndGridAdaptive | StudyKind::LoadSteps => (
            study.model_refine_fraction.unwrap_or(f64::NAN),
            study.model_coarsen_fraction.unwrap_or(f64::NAN),
        ),
        _ => (
            study.refine_fraction.unwrap_or(f64::NAN),
            study.coarsen_fraction.unwrap_or(f64::NAN),
        ),
    }
}

/// The fields of a load-step study, each given or not.
fn load_step_fields(study: &StudyFile) -> [(&'static str, bool); 2] {
    [
        ("study.cycles_per_step", study.cycles_per_step.is_some()),
        ("study.lift_per_step", study.lift_per_step.is_some()),
    ]
}

/// The fields only a model-and-grid-adaptive study has, each given or not.
fn balance_fields(study: &StudyFile) -> [(&'static str, bool); 3] {
    [
        (
            "study.model_refine_fraction",
            study.model_refine_fraction.is_some(),
        ),
        (
            "study.model_coarsen_fraction",
            study.model_coarsen_fraction.is_some(),
        ),
        ("study.balance", study.balance.is_some()),
    ]
}
