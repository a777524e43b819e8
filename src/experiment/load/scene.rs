//! The scene: its domain and coarse grid, the effects and their data sections, the typed
//! [`Problem`] they make, and the elastic body with its loads and obstacles (§IV.2.1).

use std::collections::BTreeSet;

use super::check::{effect_name, names, side_name, Check, Checked};
use crate::experiment::spec::*;
use crate::experiment::{ExperimentError, Problem};
use crate::family::FamilyRef;
use crate::mesh::{MeshSmoothing, SmoothingName};

/// Most global refinements of the coarse grid (the size of the run is bounded by the memory
/// budget of the study as well).
const MAX_GLOBAL_REFINEMENTS: usize = 12;
/// Range of the length of a side of the domain.
const MIN_LENGTH: f64 = 1e-30;
const MAX_LENGTH: f64 = 1e30;
/// Largest ratio of the two sides of a coarse cell.
const MAX_ASPECT_RATIO: f64 = 1e4;
/// Range of the Lamé constants μ, λ (λ may also be 0).
const MIN_MATERIAL: f64 = 1e-30;
const MAX_MATERIAL: f64 = 1e30;
/// Largest λ/μ: beyond it (Poisson ratio within 5e-9 of ½) the Q₁ system is singular to
/// working precision.
const MAX_LAMBDA_OVER_MU: f64 = 1e8;

impl Check<'_> {
    /// One side of the domain, `[lo, hi]`: finite, ordered, and neither so small nor so large
    /// that the cell geometry (Jacobians of order (hi − lo)², distances relative to |lo|, |hi|)
    /// underflows, overflows or drowns in rounding.
    fn domain_extent(&self, field: &str, lo: f64, hi: f64) -> Checked {
        self.finite_all(field, &[lo, hi])?;
        self.ensure(
            lo < hi,
            field,
            "[lo, hi] with lo < hi",
            format!("[{lo:?}, {hi:?}]"),
        )?;
        let width = hi - lo;
        let scale = lo.abs().max(hi.abs());
        self.ensure(
            (MIN_LENGTH..=MAX_LENGTH).contains(&width) && width >= 1e-9 * scale,
            field,
            &format!(
                "an interval of length between {MIN_LENGTH:e} and {MAX_LENGTH:e}, \
                 and at least 1e-9 of its largest coordinate"
            ),
            format!("[{lo:?}, {hi:?}] of length {width:e}"),
        )
    }

    /// A material constant of (I.17): finite, in a range where the stiffness matrix and the
    /// squared energy norms of the estimators stay representable.
    fn material(&self, field: &str, value: f64, zero_allowed: bool) -> Checked {
        let ok = value.is_finite()
            && (value <= MAX_MATERIAL)
            && (value >= MIN_MATERIAL || (zero_allowed && value == 0.0));
        self.ensure(
            ok,
            field,
            &format!(
                "a finite value between {MIN_MATERIAL:e} and {MAX_MATERIAL:e}{} (outside, the \
                 stiffness matrix and the squared norms of the estimate overflow or underflow)",
                if zero_allowed { ", or 0" } else { "" }
            ),
            value,
        )
    }

    pub(super) fn scene(&self, scene: &SceneFile) -> Checked {
        self.ensure(
            !scene.name.trim().is_empty(),
            "scene.name",
            "a non-empty descriptive name",
            "an empty string",
        )?;
        self.printable("scene.name", &scene.name, false)?;
        for (name, [lo, hi]) in [("x", scene.domain.x), ("y", scene.domain.y)] {
            self.domain_extent(&format!("scene.domain.{name}"), lo, hi)?;
        }
        for (i, &n) in scene.coarse_cells.iter().enumerate() {
            self.ensure(
                n >= 1,
                &format!("scene.coarse_cells[{i}]"),
                "at least 1 cell",
                n,
            )?;
        }
        let [hx, hy] = scene.domain.cell_sides(scene.coarse_cells);
        let aspect = scene.domain.cell_aspect_ratio(scene.coarse_cells);
        self.ensure(
            aspect <= MAX_ASPECT_RATIO,
            "scene.coarse_cells",
            &format!(
                "coarse cells with sides in a ratio of at most {MAX_ASPECT_RATIO:e} \
                 (flatter cells make the stiffness matrix numerically singular)"
            ),
            format!("{hx:e} × {hy:e} cells, ratio {aspect:e}"),
        )?;
        self.ensure(
            scene.global_refinements <= MAX_GLOBAL_REFINEMENTS,
            "scene.global_refinements",
            &format!(
                "at most {MAX_GLOBAL_REFINEMENTS} global refinements (the mesh supports {} \
                 refinement levels; the size of a run is bounded separately)",
                crate::mesh::MAX_LEVEL
            ),
            scene.global_refinements,
        )?;
        self.ensure(
            scene.contact_refinements <= MAX_GLOBAL_REFINEMENTS,
            "scene.contact_refinements",
            &format!(
                "between 0 and {MAX_GLOBAL_REFINEMENTS} refinements at the contact sides (the \
                 thesis uses 3, §IV.2.3)"
            ),
            scene.contact_refinements,
        )?;
        self.ensure(
            scene.contact_refinements == 0 || scene.contact.is_some(),
            "scene.contact_refinements",
            "0 (or left out) in a scene without contact: the refinements are at the sides \
             with an obstacle",
            scene.contact_refinements,
        )?;
        self.mesh_smoothing(&scene.mesh_smoothing)?;
        self.effects(scene)?;
        if let Some(elasticity) = &scene.elasticity {
            self.elasticity(elasticity)?;
            match elasticity.exact {
                Some(ExactSolution::ArctanCross) => self.manufactured(scene, elasticity)?,
                Some(name) => self.manufactured_contact(scene, elasticity, name)?,
                None => {}
            }
        }
        if let Some(contact) = &scene.contact {
            self.contact(contact, scene)?;
        }
        if let Some(reynolds) = &scene.reynolds {
            self.reynolds(reynolds, &scene.domain)?;
            if let Some(name) = reynolds.exact {
                self.manufactured_film(scene, reynolds, name)?;
            }
        }
        if let Some(substokes) = &scene.substokes {
            self.substokes(substokes, &scene.domain)?;
            if substokes.exact.is_some() {
                self.manufactured_substokes(scene, substokes)?;
            }
        }

        Ok(())
    }

    /// `scene.mesh_smoothing`: names of deal.II's smoothing flags that tribo implements, each
    /// once.
    fn mesh_smoothing(&self, names: &[String]) -> Checked {
        let known: Vec<&str> = SmoothingName::ALL
            .into_iter()
            .filter(|n| n.flags().is_some())
            .map(SmoothingName::name)
            .collect();
        for (i, name) in names.iter().enumerate() {
            let field = format!("scene.mesh_smoothing[{i}]");
            let parsed = SmoothingName::from_name(name);
            self.ensure(
                parsed.is_some_and(|n| n.flags().is_some()),
                &field,
                &format!(
                    "one of deal.II's mesh-smoothing flags tribo implements: {}",
                    known.join(", ")
                ),
                format!("{name:?}"),
            )?;
            self.ensure(
                !names[..i].contains(name),
                &field,
                "each flag once",
                format!("{name:?} a second time"),
            )?;
        }
        Ok(())
    }

    /// `scene.mesh_smoothing` acts only where the fixed-number grid marking refines the mesh:
    /// a study that adapts the grid, and not the model-adaptive film (`reynolds` with
    /// `substokes`), whose grid marking is its own. Elsewhere it would be accepted and ignored.
    pub(super) fn smoothing_acts(&self, study: &StudyFile, scene: &SceneFile) -> Checked {
        if scene.mesh_smoothing.is_empty() {
            return Ok(());
        }
        let film = scene.reynolds.is_some() && scene.substokes.is_some();
        self.ensure(
            study.kind.adapts_grid() && !film,
            "scene.mesh_smoothing",
            "no smoothing flags (left out) in a study that does not refine the grid by the \
             fixed-number marking (model-adaptive and solver studies, the model-adaptive film)",
            format!("{} flags", scene.mesh_smoothing.len()),
        )
    }

    /// The effect list and the data sections must agree: every effect needs its section, every
    /// section its effect; contact is a boundary condition of elasticity (§IV.2), Reynolds flow
    /// is a separate problem on its own domain (§IV.3).
    fn effects(&self, scene: &SceneFile) -> Checked {
        self.ensure(
            !scene.effects.is_empty(),
            "scene.effects",
            "at least one of `elasticity`, `contact`, `reynolds`, `substokes`",
            "an empty list",
        )?;
        let mut seen = BTreeSet::new();
        for (i, effect) in scene.effects.iter().enumerate() {
            self.ensure(
                seen.insert(*effect),
                &format!("scene.effects[{i}]"),
                "each effect listed once",
                format!("`{}` twice", effect_name(*effect)),
            )?;
        }
        let has = |e| seen.contains(&e);
        self.ensure(
            !has(Effect::Contact) || has(Effect::Elasticity),
            "scene.effects",
            "`elasticity` alongside `contact` (contact constrains an elastic body)",
            "`contact` without `elasticity`",
        )?;
        // Reynolds and SubStokes together are the model-adaptive film (§IV.3.4).
        let film_models = seen.len() == 2 && has(Effect::Reynolds) && has(Effect::SubStokes);
        for fluid in [Effect::Reynolds, Effect::SubStokes, Effect::StokesChannel] {
            self.ensure(
                !has(fluid) || seen.len() == 1 || film_models,
                "scene.effects",
                &format!(
                    "`{}` alone (a thin-film model is a problem of its own; it cannot be \
                     combined with another effect), or `reynolds` with `substokes` (the \
                     model-adaptive film of §IV.3.4)",
                    effect_name(fluid)
                ),
                format!("{:?}", names(&scene.effects)),
            )?;
        }
        let sections = [
            (Effect::Elasticity, scene.elasticity.is_some(), "elasticity"),
            (Effect::Contact, scene.contact.is_some(), "contact"),
            (Effect::Reynolds, scene.reynolds.is_some(), "reynolds"),
            (Effect::SubStokes, scene.substokes.is_some(), "substokes"),
            (
                Effect::StokesChannel,
                scene.stokes_channel.is_some(),
                "stokes_channel",
            ),
        ];
        for (effect, present, name) in sections {
            if has(effect) {
                self.ensure(
                    present,
                    &format!("scene.{name}"),
                    &format!("a [scene.{name}] section because scene.effects lists `{name}`"),
                    "no such section",
                )?;
            } else {
                self.ensure(
                    !present,
                    &format!("scene.{name}"),
                    &format!("no [scene.{name}] section, or `{name}` in scene.effects"),
                    format!("a [scene.{name}] section for an effect that is not listed"),
                )?;
            }
        }
        Ok(())
    }

    /// The typed problem of a checked scene, as its family builds it from the sections (which
    /// [`Check::effects`] has matched to the effects).
    pub(super) fn problem(
        &self,
        scene: &SceneFile,
        family: FamilyRef,
    ) -> Result<Problem, ExperimentError> {
        family.problem(scene).map_err(|name| {
            self.fail(
                &format!("scene.{name}"),
                &format!("a [scene.{name}] section"),
                "none",
            )
        })
    }

    /// The material of (I.17): μ and λ of the form (II.13), or Young's modulus and Poisson's
    /// ratio ([`ElasticityData::lame`]), one pair complete and the other absent.
    fn material_constants(&self, data: &ElasticityData) -> Checked {
        const F: &str = "scene.elasticity";
        const PAIRS: &str = "`mu` and `lambda` (the constants of the thesis's form) or \
                             `young_modulus` and `poisson_ratio`";
        let lame = data.mu.is_some() || data.lambda.is_some();
        let engineering = data.young_modulus.is_some() || data.poisson_ratio.is_some();
        let given = [
            ("mu", data.mu),
            ("lambda", data.lambda),
            ("young_modulus", data.young_modulus),
            ("poisson_ratio", data.poisson_ratio),
        ]
        .iter()
        .filter(|(_, v)| v.is_some())
        .map(|(name, _)| *name)
        .collect::<Vec<_>>()
        .join(", ");
        self.ensure(
            lame || engineering,
            F,
            &format!("the material: {PAIRS}"),
            "none of them",
        )?;
        let second = if data.young_modulus.is_some() {
            "young_modulus"
        } else {
            "poisson_ratio"
        };
        self.ensure(
            !(lame && engineering),
            &format!("{F}.{second}"),
            &format!("either {PAIRS}, not both (the two pairs would contradict each other)"),
            given.as_str(),
        )?;
        if lame {
            let (Some(mu), Some(lambda)) = (data.mu, data.lambda) else {
                let missing = if data.mu.is_none() { "mu" } else { "lambda" };
                return Err(self.fail(
                    &format!("{F}.{missing}"),
                    &format!("`mu` and `lambda` together (or {PAIRS})"),
                    given.as_str(),
                ));
            };
            self.material(&format!("{F}.mu"), mu, false)?;
            self.material(&format!("{F}.lambda"), lambda, true)?;
            return self.ensure(
                lambda <= MAX_LAMBDA_OVER_MU * mu,
                &format!("{F}.lambda"),
                &format!(
                    "λ ≤ {MAX_LAMBDA_OVER_MU:e}·μ (a nearly incompressible material locks the Q₁ \
                     elements and makes the stiffness matrix numerically singular)"
                ),
                format!("λ/μ = {:e}", lambda / mu),
            );
        }
        let (Some(young), Some(nu)) = (data.young_modulus, data.poisson_ratio) else {
            let missing = if data.young_modulus.is_none() {
                "young_modulus"
            } else {
                "poisson_ratio"
            };
            return Err(self.fail(
                &format!("{F}.{missing}"),
                &format!("`young_modulus` and `poisson_ratio` together (or {PAIRS})"),
                given.as_str(),
            ));
        };
        self.material(&format!("{F}.young_modulus"), young, false)?;
        self.ensure(
            nu.is_finite() && nu > -1.0 && nu < 0.5,
            &format!("{F}.poisson_ratio"),
            "a Poisson's ratio ν with −1 < ν < ½ (at ½ the material is incompressible, which \
             displacement elements cannot represent; at −1 and beyond the energy is not \
             positive)",
            nu,
        )?;
        let Lame { mu, lambda } = data.lame();
        self.material(&format!("{F}.young_modulus"), mu, false)?;
        self.ensure(
            lambda <= MAX_LAMBDA_OVER_MU * mu,
            &format!("{F}.poisson_ratio"),
            &format!(
                "ν ≤ {:?} ≈ ½ − 2.5e-9, so that λ/μ = ν/(1 − 2ν) ≤ {MAX_LAMBDA_OVER_MU:e} (a \
                 nearly incompressible material locks the Q₁ elements and makes the stiffness \
                 matrix numerically singular)",
                MAX_LAMBDA_OVER_MU / (1.0 + 2.0 * MAX_LAMBDA_OVER_MU)
            ),
            format!("ν = {nu:?}, λ/μ = {:e}", lambda / mu),
        )
    }

    /// Material and loads of (I.17) / (IV.1).
    fn elasticity(&self, data: &ElasticityData) -> Checked {
        const F: &str = "scene.elasticity";
        self.material_constants(data)?;
        self.unique_sides(&format!("{F}.dirichlet"), data.dirichlet.iter().copied())?;
        if let Some(load) = &data.volume_load {
            self.finite_all(&format!("{F}.volume_load.direction"), &load.direction)?;
            self.profile(&format!("{F}.volume_load.profile"), &load.profile)?;
        }
        self.unique_sides(
            &format!("{F}.tractions"),
            data.tractions.iter().map(|t| t.side),
        )?;
        for (i, traction) in data.tractions.iter().enumerate() {
            let field = format!("{F}.tractions[{i}]");
            self.ensure(
                !data.dirichlet.contains(&traction.side),
                &format!("{field}.side"),
                "a side that is not in scene.elasticity.dirichlet (Γ_τ and Γ₀ are disjoint)",
                format!("`{}`", side_name(traction.side)),
            )?;
            self.finite_all(&format!("{field}.value"), &traction.value)?;
        }
        Ok(())
    }

    /// A scene with `exact`: the closed-form field lives on the unit square and vanishes on its
    /// boundary, so the scene clamps every side, has no load or traction of its own (the load is
    /// derived from the field) and no other effect.
    fn manufactured(&self, scene: &SceneFile, data: &ElasticityData) -> Checked {
        const F: &str = "scene.elasticity";
        self.ensure(
            scene.effects == [Effect::Elasticity],
            "scene.effects",
            "[\"elasticity\"] alone with scene.elasticity.exact",
            format!("{:?}", names(&scene.effects)),
        )?;
        self.unit_square(scene)?;
        let all = [Side::Left, Side::Right, Side::Bottom, Side::Top];
        self.ensure(
            all.iter().all(|s| data.dirichlet.contains(s)),
            &format!("{F}.dirichlet"),
            "all four sides with scene.elasticity.exact (the exact field is 0 on the boundary)",
            format!("{} sides", data.dirichlet.len()),
        )?;
        self.ensure(
            data.volume_load.is_none(),
            &format!("{F}.volume_load"),
            "no volume_load with scene.elasticity.exact (the load is derived from the field)",
            "a volume_load",
        )
    }

    /// A Reynolds scene with `exact`: the pressure lives on the unit square and equals ψ₀ on its
    /// boundary, so the scene is the Reynolds film alone, on the unit square, with the estimator
    /// of Theorems III.16/III.17 as stated (the thesis-code reading leaves out the squeeze part
    /// of l_R, which a manufactured load does not have). `arctan-cross` stays positive and needs
    /// `cavitation = "off"`; `cavitation-bubble` has a cavitation zone and needs
    /// `cavitation = "on"` (with `auto` the first solve would be the unconstrained one, whose
    /// load is not the field's) and ψ₀ > 0 (F = √ψ₀ − K·B); a displacement field is refused.
    fn manufactured_film(
        &self,
        scene: &SceneFile,
        data: &ReynoldsData,
        name: ExactSolution,
    ) -> Checked {
        const F: &str = "scene.reynolds";
        self.ensure(
            scene.effects == [Effect::Reynolds],
            "scene.effects",
            "[\"reynolds\"] alone with scene.reynolds.exact",
            format!("{:?}", names(&scene.effects)),
        )?;
        self.unit_square(scene)?;
        match name {
            ExactSolution::ArctanCross => self.ensure(
                data.cavitation == Cavitation::Off,
                &format!("{F}.cavitation"),
                "\"off\" with scene.reynolds.exact = \"arctan-cross\" (the exact pressure is \
                 positive)",
                format!("{:?}", data.cavitation),
            )?,
            ExactSolution::CavitationBubble => {
                self.ensure(
                    data.cavitation == Cavitation::On,
                    &format!("{F}.cavitation"),
                    "\"on\" with scene.reynolds.exact = \"cavitation-bubble\" (the exact \
                     pressure cavitates on a known zone, and its load is that of the LCP)",
                    format!("{:?}", data.cavitation),
                )?;
                self.ensure(
                    data.boundary_pressure > 0.0,
                    &format!("{F}.boundary_pressure"),
                    "a positive ψ₀ with scene.reynolds.exact = \"cavitation-bubble\" (the field \
                     is (√ψ₀ − K·B)₊²)",
                    data.boundary_pressure,
                )?;
            }
            other => self.ensure(
                false,
                &format!("{F}.exact"),
                "a pressure: \"arctan-cross\" or \"cavitation-bubble\"",
                format!("\"{}\", a displacement", other.name()),
            )?,
        }
        self.ensure(
            data.estimator == ReynoldsEstimator::Theorem,
            &format!("{F}.estimator"),
            "\"theorem\" with scene.reynolds.exact (the load is derived from the pressure)",
            format!("{:?}", data.estimator),
        )
    }

    /// A contact scene with `exact = "contact-strip"` or `"contact-strip-tilted"`
    /// ([`crate::models::manufactured::ContactStrip`]): the field lives on the unit square, is 0
    /// on the left, right and top sides and touches its obstacle below the bottom side. So the
    /// scene is elasticity and contact alone on the unit square, clamped on exactly those three
    /// sides, without a load or traction of its own (the volume load and the surface load on
    /// Γ_C are derived from the field), with the one obstacle of the field on the bottom side;
    /// the tilted field solves the Signorini condition and is refused with the z-model (whose
    /// solution differs by k·u), and neither is a model-adaptive scene.
    fn manufactured_contact(
        &self,
        scene: &SceneFile,
        data: &ElasticityData,
        name: ExactSolution,
    ) -> Checked {
        const F: &str = "scene.elasticity";
        let strip = match name {
            ExactSolution::ContactStrip => crate::models::manufactured::ContactStrip::FLAT,
            ExactSolution::ContactStripTilted => crate::models::manufactured::ContactStrip::TILTED,
            other => {
                return self.ensure(
                    false,
                    &format!("{F}.exact"),
                    "a displacement: \"arctan-cross\", \"contact-strip\" or \
                     \"contact-strip-tilted\"",
                    format!("\"{}\", a pressure", other.name()),
                )
            }
        };
        self.ensure(
            scene.effects.len() == 2
                && scene.effects.contains(&Effect::Elasticity)
                && scene.effects.contains(&Effect::Contact),
            "scene.effects",
            "[\"elasticity\", \"contact\"] with a contact field in scene.elasticity.exact",
            format!("{:?}", names(&scene.effects)),
        )?;
        self.unit_square(scene)?;
        let mut sides = data.dirichlet.clone();
        sides.sort_by_key(|s| side_name(*s));
        self.ensure(
            sides == [Side::Left, Side::Right, Side::Top],
            &format!("{F}.dirichlet"),
            "[\"left\", \"right\", \"top\"] with a contact field in scene.elasticity.exact (the \
             field is 0 there and touches the obstacle on the bottom side)",
            format!(
                "{:?}",
                data.dirichlet
                    .iter()
                    .map(|s| side_name(*s))
                    .collect::<Vec<_>>()
            ),
        )?;
        self.ensure(
            data.volume_load.is_none(),
            &format!("{F}.volume_load"),
            "no volume_load with scene.elasticity.exact (the load is derived from the field)",
            "a volume_load",
        )?;
        self.ensure(
            data.tractions.is_empty(),
            &format!("{F}.tractions"),
            "no tractions with a contact field in scene.elasticity.exact (the surface load on \
             the contact side is derived from the field)",
            format!("{} tractions", data.tractions.len()),
        )?;
        let Some(contact) = &scene.contact else {
            return Ok(());
        };
        self.ensure(
            matches!(contact.model, ContactModel::Z | ContactModel::Signorini),
            "scene.contact.model",
            "\"z\" or \"signorini\" with a contact field in scene.elasticity.exact",
            format!("\"{}\"", contact.model.name()),
        )?;
        if name == ExactSolution::ContactStripTilted {
            self.ensure(
                contact.model == ContactModel::Signorini,
                "scene.contact.model",
                "\"signorini\" with scene.elasticity.exact = \"contact-strip-tilted\" (the field \
                 meets the Signorini condition; the z-solution of its data differs by k·u)",
                format!("\"{}\"", contact.model.name()),
            )?;
        }
        let shape = if strip.slope == 0.0 {
            ObstacleShape::Constant {
                level: strip.offset,
            }
        } else {
            ObstacleShape::Linear {
                offset: strip.offset,
                slope: strip.slope,
            }
        };
        let expected = match shape {
            ObstacleShape::Linear { offset, slope } => format!(
                "one obstacle, side = \"bottom\", shape = {{ kind = \"linear\", offset = {offset:?}, \
                 slope = {slope:?} }}"
            ),
            _ => format!(
                "one obstacle, side = \"bottom\", shape = {{ kind = \"constant\", level = {:?} }}",
                strip.offset
            ),
        };
        let found = contact
            .obstacles
            .iter()
            .map(|o| format!("{} {:?}", side_name(o.side), o.shape))
            .collect::<Vec<_>>()
            .join(", ");
        self.ensure(
            contact.obstacles.len() == 1
                && contact.obstacles[0].side == Side::Bottom
                && contact.obstacles[0].shape == shape
                && contact.obstacles[0].rises.is_none(),
            "scene.contact.obstacles",
            &format!(
                "{expected} with scene.elasticity.exact = \"{}\" (the obstacle of the field)",
                name.name()
            ),
            format!("[{found}]"),
        )
    }

    /// A SubStokes scene with `exact`: the fields live on the unit square, ψ = ψ₀ on its boundary
    /// and ψ > 0, so the scene is the SubStokes film alone, on the unit square, without the point
    /// condition (I.56) (the exact χ is not g v̄ at a corner) and solved by the LDLᵀ. Cavitation
    /// `on` is allowed (the constraint ψ ≥ 0 stays inactive: the cavitation form's solve and
    /// estimator with the same data), `auto` is not (it would never switch).
    fn manufactured_substokes(&self, scene: &SceneFile, data: &SubStokesData) -> Checked {
        const F: &str = "scene.substokes";
        self.ensure(
            scene.effects == [Effect::SubStokes],
            "scene.effects",
            "[\"substokes\"] alone with scene.substokes.exact",
            format!("{:?}", names(&scene.effects)),
        )?;
        self.unit_square(scene)?;
        self.ensure(
            data.cavitation != Cavitation::Auto,
            &format!("{F}.cavitation"),
            "\"off\" or \"on\" with scene.substokes.exact (the exact pressure is positive)",
            format!("{:?}", data.cavitation),
        )?;
        self.ensure(
            data.point == PointCondition::None,
            &format!("{F}.point"),
            "\"none\" with scene.substokes.exact (the exact flow rate is not g v̄ at a corner)",
            format!("{:?}", data.point),
        )?;
        self.ensure(
            data.solver == FilmSolver::Ldlt && data.compare_with.is_none(),
            &format!("{F}.solver"),
            "\"ldlt\" and no compare_with with scene.substokes.exact",
            format!("{:?}", data.solver),
        )
    }

    /// The domain of the exact fields of [`crate::models::manufactured`].
    fn unit_square(&self, scene: &SceneFile) -> Checked {
        self.ensure(
            scene.domain.x == [0.0, 1.0] && scene.domain.y == [0.0, 1.0],
            "scene.domain",
            "the unit square { x = [0.0, 1.0], y = [0.0, 1.0] } (the domain of the exact field)",
            format!("x = {:?}, y = {:?}", scene.domain.x, scene.domain.y),
        )
    }

    fn profile(&self, field: &str, profile: &Profile) -> Checked {
        match *profile {
            Profile::Constant { amplitude } => {
                self.finite(&format!("{field}.amplitude"), amplitude)
            }
            Profile::Quadratic { amplitude, scale } => {
                self.finite(&format!("{field}.amplitude"), amplitude)?;
                self.positive(&format!("{field}.scale"), scale)
            }
            Profile::Step { amplitude, at } => {
                self.finite(&format!("{field}.amplitude"), amplitude)?;
                self.finite(&format!("{field}.at"), at)
            }
            Profile::Sine {
                amplitude,
                half_period,
            } => {
                self.finite(&format!("{field}.amplitude"), amplitude)?;
                self.positive(&format!("{field}.half_period"), half_period)
            }
        }
    }

    /// Obstacles of §IV.2.1: on the bottom or top face only, one per face, disjoint from Γ₀ and
    /// Γ_τ.
    fn contact(&self, data: &ContactData, scene: &SceneFile) -> Checked {
        const F: &str = "scene.contact.obstacles";
        self.ensure(
            !data.obstacles.is_empty(),
            F,
            "at least one obstacle",
            "an empty list",
        )?;
        self.unique_sides(F, data.obstacles.iter().map(|o| o.side))?;
        let (dirichlet, tractions) = match &scene.elasticity {
            Some(e) => (e.dirichlet.as_slice(), e.tractions.as_slice()),
            None => (&[][..], &[][..]),
        };
        for (i, obstacle) in data.obstacles.iter().enumerate() {
            let field = format!("{F}[{i}]");
            let side = obstacle.side;
            self.ensure(
                matches!(side, Side::Bottom | Side::Top),
                &format!("{field}.side"),
                "`bottom` or `top` (obstacles bound s₂ on a horizontal face)",
                format!("`{}`", side_name(side)),
            )?;
            self.ensure(
                !dirichlet.contains(&side),
                &format!("{field}.side"),
                "a side that is not in scene.elasticity.dirichlet (Γ_C and Γ₀ are disjoint)",
                format!("`{}`", side_name(side)),
            )?;
            self.ensure(
                !tractions.iter().any(|t| t.side == side),
                &format!("{field}.side"),
                "a side without a traction (Γ_τ = ∂Ω \\ (Γ₀ ∪ Γ_C))",
                format!("`{}` also in scene.elasticity.tractions", side_name(side)),
            )?;
            self.obstacle_shape(&format!("{field}.shape"), &obstacle.shape, scene)?;
        }
        if let Some(estimator) = data.estimator {
            self.ensure(
                data.model != ContactModel::ModelAdaptive,
                "scene.contact.estimator",
                "no estimator with model = \"model-adaptive\": the model-adaptive tables keep \
                 their mesh fixed and mark faces by the model error (III.16) alone, and the \
                 model-and-grid-adaptive ones use the term set of the thesis's MGA code",
                format!("{estimator:?}"),
            )?;
        }
        if let Some(reading) = data.signorini {
            self.ensure(
                data.model != ContactModel::Z,
                "scene.contact.signorini",
                "no `signorini` with model = \"z\": the option says how the Signorini \
                 constraints are solved (\"linearised\" or \"converged\"), and a z-contact \
                 scene has none",
                format!("\"{}\"", reading.name()),
            )?;
        }
        Ok(())
    }

    fn obstacle_shape(&self, field: &str, shape: &ObstacleShape, scene: &SceneFile) -> Checked {
        let f = |name: &str| format!("{field}.{name}");
        match *shape {
            ObstacleShape::Constant { level } => self.finite(&f("level"), level),
            ObstacleShape::Linear { offset, slope } => {
                self.finite(&f("offset"), offset)?;
                self.finite(&f("slope"), slope)
            }
            ObstacleShape::Periodic {
                offset,
                amplitude,
                periods,
                period,
                phase,
            } => {
                self.finite(&f("offset"), offset)?;
                self.finite(&f("amplitude"), amplitude)?;
                match (periods, period) {
                    (Some(periods), None) => {
                        self.finite(&f("periods"), periods)?;
                        self.ensure(
                            phase.is_none(),
                            &f("phase"),
                            "no phase with `periods` (its sine starts at the thesis's x₁ = −16), \
                             or `period` with `phase`",
                            "a phase with periods",
                        )
                    }
                    (None, Some(period)) => {
                        self.positive(&f("period"), period)?;
                        self.finite(&f("phase"), phase.unwrap_or(0.0))
                    }
                    (Some(_), Some(_)) => self.ensure(
                        false,
                        &f("period"),
                        "either `periods` (whole periods on the thesis's x₁ ∈ [−16, 16]) or \
                         `period` (a length, with an optional `phase`), not both",
                        "both periods and period",
                    ),
                    (None, None) => self.ensure(
                        false,
                        &f("period"),
                        "`period` (a length, with an optional `phase`) or `periods` (whole \
                         periods on the thesis's x₁ ∈ [−16, 16])",
                        "neither",
                    ),
                }
            }
            ObstacleShape::Tabulated { ref file, ref rows } => {
                self.profile_covers(&f("file"), file, rows, scene.domain.x)
            }
            ObstacleShape::Jump {
                base,
                height,
                at,
                s,
            } => {
                self.finite(&f("base"), base)?;
                self.finite(&f("height"), height)?;
                self.finite(&f("at"), at)?;
                self.positive(&f("s"), s)
            }
            ObstacleShape::Saw { s, .. } => self.positive(&f("s"), s),
            ObstacleShape::Arc {
                center,
                radius,
                plateau,
                s,
            } => {
                self.finite(&f("center[0]"), center[0])?;
                self.finite(&f("center[1]"), center[1])?;
                self.positive(&f("radius"), radius)?;
                self.finite(&f("plateau"), plateau)?;
                self.positive(&f("s"), s)
            }
        }
    }
}

/// The flags of a checked `scene.mesh_smoothing` list ([`Check::scene`] refused every name it
/// does not implement).
pub(super) fn mesh_smoothing(names: &[String]) -> MeshSmoothing {
    let names: Vec<SmoothingName> = names
        .iter()
        .map(|n| SmoothingName::from_name(n).expect("checked by the loader"))
        .collect();
    MeshSmoothing::of(&names).expect("checked by the loader")
}
