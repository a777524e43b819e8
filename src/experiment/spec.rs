//! The experiment file format: one TOML file per Chapter IV table in `experiments/`.
//!
//! An experiment is a *scene* (domain, coarse mesh, data, and the effects to simulate), a *study*
//! (how to iterate: grid-adaptive cycles, marking fractions, quick tier, convergence window) and
//! the thesis rows for comparison (reference data only — never copied into an output).
//!
//! The types here are plain data: they describe the file and nothing else. [`super::load`] parses
//! and validates a file and turns it into a typed [`super::Experiment`]; the models convert from
//! these types (the study does it when it builds a model), so imports run one way: the models
//! know nothing of the file format.

use std::sync::Arc;

use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serialize};

/// Sides of the domain are the mesh's own geometric type.
pub use crate::mesh::Side;

/// One experiment file (`experiments/IV.n.toml`), as written.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ExperimentFile {
    /// Table id, `IV.1` … `IV.75`, the id of a figure experiment, `fig-IV.<n>` (a result the
    /// thesis shows as a figure only, e.g. the U-O forming of Fig. IV.54), or the free id of a
    /// scene of the user's own (letters, digits, `.`, `-`, `_`; not `IV.…` or `fig-…`).
    pub table: String,
    /// Thesis section, e.g. `IV.1.1`.
    pub section: String,
    /// Human-readable title for the report.
    pub title: String,
    pub scene: SceneFile,
    pub study: StudyFile,
    #[serde(default)]
    pub probes: Probes,
    /// Readings of the thesis and known differences, shown in the report for this table.
    #[serde(default)]
    pub notes: Vec<String>,
    /// Tables of the same scene solved another way, drawn beside this one where the report has
    /// them (the model-adaptive film of Fig. IV.116 with the pure Reynolds and pure SubStokes
    /// runs of (IV.17), IV.46 and IV.60: Figs IV.117, IV.118 and the cost of accuracy).
    #[serde(default)]
    pub related: Vec<String>,
    /// The printed table; a figure experiment and a scene of the user's own have none.
    #[serde(default)]
    pub thesis: Option<ThesisRows>,
    /// The thesis figures that show this run ([`ThesisFigures`]); none where the thesis draws
    /// none. Not part of what the thesis computed, so not fingerprinted.
    #[serde(default)]
    pub figures: ThesisFigures,
    /// `[sweep]`: fields of `[scene]` or `[study]` to run at several values, each combination a
    /// run of its own ([`super::sweep`]). The loader reads it from the text and expands the file
    /// into its runs; the checks of one run leave it alone.
    #[serde(default)]
    pub sweep: Option<toml::Table>,
}

/// An effect a scene asks the pipeline to simulate. Only the named effects are built.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq, PartialOrd, Ord)]
#[serde(rename_all = "kebab-case")]
pub enum Effect {
    /// Linear elasticity (I.17).
    Elasticity,
    /// Contact with a rigid obstacle (z-contact (I.20) or Signorini (I.21)); needs `elasticity`.
    Contact,
    /// Reynolds thin-film flow (I.77)/(I.79).
    Reynolds,
    /// SubStokes thin-film flow (I.58), with cavitation (I.66).
    #[serde(rename = "substokes")]
    SubStokes,
    /// The stabilised Stokes test problem (III.88) of the Uzawa comparison, Fig. III.6.
    StokesChannel,
}

/// Domain, coarse mesh, data and effects, as written.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Descriptive scene name, e.g. `box-constant-load`, `wave-horizontal-squeeze`.
    pub name: String,
    /// Rectangle `[x0, x1] × [y0, y1]`.
    pub domain: Rectangle,
    /// Number of coarse cells in x and y (the level-0 quadtree roots).
    #[serde(deserialize_with = "exactly")]
    pub coarse_cells: [usize; 2],
    /// Global refinements of the coarse grid before the first solve. The cells they create can
    /// be coarsened again (level-0 cells cannot): the fluid tables' row-0 cell counts (7777,
    /// 7747, 7699, … < 7783 = 4096 + 3·1229) show that the thesis's 64×64 grid was a once-coarser
    /// grid refined globally, deal.II style (`refine_global`).
    #[serde(default)]
    pub global_refinements: usize,
    /// Refinements of the cells at the contact sides (the sides with an obstacle) after the
    /// global ones: the fixed meshes of the model-adaptive tables, §IV.2.3 — 64×2 cells refined
    /// 3× at one contact side give 1472 cells, 3980 dofs and 512 contact faces.
    #[serde(default)]
    pub contact_refinements: usize,
    /// deal.II's mesh-smoothing flags of the triangulation (`Triangulation::MeshSmoothing`),
    /// kebab-case: `limit-level-difference-at-vertices`, `eliminate-unrefined-islands`,
    /// `patch-level-1`, `coarsest-level-1`, `smoothing-on-refinement`, `maximum-smoothing`
    /// ([`crate::mesh::SmoothingName`]). They add refinement flags (and remove coarsening
    /// flags) beyond the marked cells at every grid refinement. Empty (the default): tribo's
    /// 2:1 rule across faces alone, deal.II's `none`.
    #[serde(default)]
    pub mesh_smoothing: Vec<String>,
    pub effects: Vec<Effect>,
    pub elasticity: Option<ElasticityData>,
    pub contact: Option<ContactData>,
    pub reynolds: Option<ReynoldsData>,
    pub substokes: Option<SubStokesData>,
    pub stokes_channel: Option<StokesChannelData>,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Rectangle {
    #[serde(deserialize_with = "exactly")]
    pub x: [f64; 2],
    #[serde(deserialize_with = "exactly")]
    pub y: [f64; 2],
}

impl Rectangle {
    /// Width and height `[h_x, h_y]` of the cells of an `nx × ny` grid of the rectangle.
    pub fn cell_sides(&self, [nx, ny]: [usize; 2]) -> [f64; 2] {
        [
            (self.x[1] - self.x[0]) / nx as f64,
            (self.y[1] - self.y[0]) / ny as f64,
        ]
    }

    /// Ratio of the longer to the shorter side of those cells.
    pub fn cell_aspect_ratio(&self, cells: [usize; 2]) -> f64 {
        let [hx, hy] = self.cell_sides(cells);
        (hx / hy).max(hy / hx)
    }
}

/// Material and loads of the elasticity problem (I.17) with a(s,r) = 2μ⟨ε,ε⟩ + 2λ⟨div,div⟩.
///
/// The material is given either by the thesis's constants `mu` and `lambda` of that form, or by
/// Young's modulus E and Poisson's ratio ν (`young_modulus`, `poisson_ratio`), never both: see
/// [`ElasticityData::lame`] for the conversion.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ElasticityData {
    /// μ of a(s, r), the shear modulus (with `lambda`).
    #[serde(default)]
    pub mu: Option<f64>,
    /// λ of a(s, r) (with `mu`). The thesis's form has 2λ where Hooke's law has λ, so this λ is
    /// half the standard Lamé constant (docs/models.md §1.2).
    #[serde(default)]
    pub lambda: Option<f64>,
    /// Young's modulus E > 0 (with `poisson_ratio`, instead of `mu` and `lambda`).
    #[serde(default)]
    pub young_modulus: Option<f64>,
    /// Poisson's ratio ν ∈ (−1, ½) (with `young_modulus`).
    #[serde(default)]
    pub poisson_ratio: Option<f64>,
    /// Sides in Γ₀ (s = 0).
    pub dirichlet: Vec<Side>,
    /// Volume load ρf = direction · profile(x₁).
    pub volume_load: Option<VolumeLoad>,
    /// Surface stress τn on whole sides (Neumann data); sides not listed and not Dirichlet are
    /// traction-free.
    #[serde(default)]
    pub tractions: Vec<Traction>,
    /// A manufactured solution: the displacement is known in closed form, the volume load is
    /// derived from it ([`crate::models::manufactured`]) and the rows get the true error and
    /// the effectivity of the estimate.
    #[serde(default)]
    pub exact: Option<ExactSolution>,
}

/// The constants μ, λ of the form a(s, r) = 2μ⟨ε,ε⟩ + 2λ⟨div,div⟩ of (II.13).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lame {
    pub mu: f64,
    pub lambda: f64,
}

impl ElasticityData {
    /// μ and λ of the form (II.13): as written, or from E and ν.
    ///
    /// The 2-D model with the 3-D constants is the plane-strain model (the thesis names neither
    /// plane strain nor plane stress; docs/models.md §1.2 derives E = 8/3, ν = 1/3 for its
    /// μ = λ = 1 the same way), so E and ν give the standard Lamé constants
    ///
    ///   μ = E / (2(1 + ν)),   λ_std = E ν / ((1 + ν)(1 − 2ν)),
    ///
    /// and, since the form has 2λ where Hooke's law has λ_std, λ = λ_std / 2
    /// = E ν / (2(1 + ν)(1 − 2ν)). E = 8/3, ν = 1/3 is the thesis's μ = λ = 1. NaN where the
    /// file gives neither pair (the loader refuses such a file).
    pub fn lame(&self) -> Lame {
        match (self.mu, self.lambda, self.young_modulus, self.poisson_ratio) {
            (Some(mu), Some(lambda), _, _) => Lame { mu, lambda },
            (_, _, Some(e), Some(nu)) => Lame {
                mu: e / (2.0 * (1.0 + nu)),
                lambda: e * nu / (2.0 * (1.0 + nu) * (1.0 - 2.0 * nu)),
            },
            _ => Lame {
                mu: f64::NAN,
                lambda: f64::NAN,
            },
        }
    }
}

/// The closed-form fields a scene can name as `exact` ([`crate::models::manufactured`]).
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum ExactSolution {
    /// w = p(x₁)p(x₂), p(t) = t(1 − t) atan(25(t − ½)) on the unit square: the displacement
    /// s = (w, w), or the pressure ψ = ψ₀ + 1000·w (Reynolds; SubStokes with the flow rate of
    /// [`crate::models::manufactured_stokes`]).
    ArctanCross,
    /// A displacement in contact with the flat obstacle b = −0.05 below the bottom side on
    /// x₁ ∈ [0.3, 0.7] and separated elsewhere (`models::manufactured::ContactStrip::FLAT`).
    ContactStrip,
    /// The same with the tilted obstacle b = −0.1 + 0.05 x₁ and the Signorini condition
    /// (`models::manufactured::ContactStrip::TILTED`).
    ContactStripTilted,
    /// A pressure (F₊)², F = √ψ₀ − K·16x₁(1 − x₁)x₂(1 − x₂), with a cavitation zone about the
    /// centre (`models::manufactured`, `cavitation-bubble`).
    CavitationBubble,
}

impl ExactSolution {
    /// The experiment-file spelling.
    pub fn name(self) -> &'static str {
        match self {
            ExactSolution::ArctanCross => "arctan-cross",
            ExactSolution::ContactStrip => "contact-strip",
            ExactSolution::ContactStripTilted => "contact-strip-tilted",
            ExactSolution::CavitationBubble => "cavitation-bubble",
        }
    }
}

#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct VolumeLoad {
    #[serde(deserialize_with = "exactly")]
    pub direction: [f64; 2],
    pub profile: Profile,
}

/// A scalar profile of x₁ (the loads of §IV.1.1–IV.1.5 and §IV.2.1).
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Profile {
    /// a
    Constant { amplitude: f64 },
    /// a · (x₁ / scale)²
    Quadratic { amplitude: f64, scale: f64 },
    /// a for x₁ > at, 0 otherwise
    Step { amplitude: f64, at: f64 },
    /// a · sin(π x₁ / half_period)
    Sine { amplitude: f64, half_period: f64 },
}

#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Traction {
    pub side: Side,
    #[serde(deserialize_with = "exactly")]
    pub value: [f64; 2],
}

/// Which contact projection a face uses.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum ContactModel {
    /// Fixed-direction projection (I.20).
    Z,
    /// Signorini projection (I.21), linearised per cycle about the previous solution (§IV.2.2).
    Signorini,
    /// Chosen face by face by the model marking of a `model-adaptive` study (§IV.2.3): every
    /// face starts with the z-model.
    ModelAdaptive,
}

impl ContactModel {
    /// The experiment-file spelling.
    pub fn name(self) -> &'static str {
        match self {
            ContactModel::Z => "z",
            ContactModel::Signorini => "signorini",
            ContactModel::ModelAdaptive => "model-adaptive",
        }
    }
}

/// The term set of the contact estimator (Theorem III.15) that the thesis's codes evidently used
/// (docs/estimators.md §5.2; `crate::estimators::contact::ContactEstimator`).
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum ContactEstimator {
    /// Cell residual, ½ interior jumps, full Neumann residual, ‖∇(n·s_h)‖² on all Γ_C faces.
    ZCode,
    /// The z-code plus the obstacle part of η_{C,Q}, h_Q‖∂₁I_h b‖² on all Γ_C faces: the
    /// reading for the smooth and kinked obstacles of Tables IV.7, IV.8 and IV.11, whose printed
    /// rows carry an obstacle term; the jump obstacles of IV.9 and IV.10 cannot have had it.
    ZCodeObstacleSlope,
    /// Cell residual and ½ interior jumps only, η_C on contact cells (Σ_p1).
    SignoriniCode,
}

#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ContactData {
    pub model: ContactModel,
    /// Term set of the grid estimator; left out, the thesis's pairing with `model` (`z-code`
    /// for z, `signorini-code` for Signorini). A model-adaptive study on a fixed mesh has no
    /// grid estimator.
    #[serde(default)]
    pub estimator: Option<ContactEstimator>,
    /// Model-adaptive: the displacement s_h at which the model error ε_P(s_h) of (III.16) is
    /// evaluated ([`ModelErrorSolution`]).
    #[serde(default)]
    pub model_error_solution: ModelErrorSolution,
    /// How the Signorini constraints of a cycle are solved ([`SignoriniReading`]); left out,
    /// the thesis's single linearisation. Only for scenes with Signorini faces (`signorini`,
    /// `model-adaptive`): the loader refuses it with `model = "z"`.
    #[serde(default)]
    pub signorini: Option<SignoriniReading>,
    /// One obstacle per contact side: `bottom` means s₂ ≥ b(x₁) on x₂ = y0 (n = −e₂),
    /// `top` means s₂ ≤ b(x₁) on x₂ = y1 (n = +e₂).
    pub obstacles: Vec<Obstacle>,
}

/// Which solution of a model-adaptive cycle the model error ε^m(f) = ‖ε_P(s_h)‖_{L2(f)} is
/// evaluated at (§III.1.1 replaces s_z and s_s of Theorem III.4 by "s_h"; the thesis does not
/// say which of the cycle's two solves).
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum ModelErrorSolution {
    /// The mixed solution, the solution of the cycle (docs/estimators.md §3.4).
    #[default]
    Mixed,
    /// The z-solution on all faces, computed first in every cycle (the coarse solution u_c of
    /// Algorithms III.2/III.3); on the fixed mesh it is the same in every cycle.
    Z,
}

/// How the Signorini constraints of a cycle are solved. §IV.2.2 linearises the Signorini
/// condition about an initial guess s₀ (the previous cycle's solution, or the z-solution of
/// the cycle in the model-adaptive tables) and solves once; whether the thesis iterated the
/// linearisation to a fixed point it does not say.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum SignoriniReading {
    /// One linearised solve per cycle (the thesis's reading, the default).
    #[default]
    Linearised,
    /// The linearisation point iterated to a fixed point in every cycle
    /// (`crate::study::signorini`): the table uses the converged solution.
    Converged,
}

impl SignoriniReading {
    /// The experiment-file spelling.
    pub fn name(self) -> &'static str {
        match self {
            SignoriniReading::Linearised => "linearised",
            SignoriniReading::Converged => "converged",
        }
    }
}

impl ContactData {
    /// The Signorini reading of the scene: as written, else the thesis's linearised one.
    pub fn signorini_reading(&self) -> SignoriniReading {
        self.signorini.unwrap_or_default()
    }

    /// The term set of the grid estimator of a grid-adaptive study: as written, or the thesis's
    /// pairing with the model (z-code for z, Signorini-code for Signorini). The model-adaptive
    /// studies refuse an estimator: on a fixed mesh there is none, and the model-and-grid
    /// study uses the MGA code's term set (`crate::estimators::contact::ContactEstimator::MgaCode`);
    /// `model-adaptive` maps to the z-code only so that the pairing check has an answer.
    pub fn grid_estimator(&self) -> ContactEstimator {
        self.estimator.unwrap_or(match self.model {
            ContactModel::Z | ContactModel::ModelAdaptive => ContactEstimator::ZCode,
            ContactModel::Signorini => ContactEstimator::SignoriniCode,
        })
    }
}

impl ContactData {
    /// The tools of load step j: every obstacle that rises ([`Obstacle::rises`]) raised by
    /// `by` = j · `study.lift_per_step`.
    pub fn raised(&self, by: f64) -> ContactData {
        let mut raised = self.clone();
        for o in &mut raised.obstacles {
            if let Some(rise) = o.rises {
                o.shape = o.shape.clone().raised(rise, by);
            }
        }
        raised
    }
}

#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Obstacle {
    pub side: Side,
    pub shape: ObstacleShape,
    /// Load steps (§IV.2.4.7): which part of the tool rises by `study.lift_per_step` in every
    /// step; left out, the tool stays where it is.
    #[serde(default)]
    pub rises: Option<Rise>,
}

/// What of an `arc` tool rises in every load step of the U-O forming (§IV.2.4.7): "the
/// complete lower obstacle and the plain part of the higher obstacle rises in each step by
/// 10/24" (`c^L_j = (−16, j·10/24)`, `H^U_j = 1.2 + j·10/24`, `H^L_j = j·10/24`).
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum Rise {
    /// The whole tool: its circle's center and its plateau (the die).
    Whole,
    /// Only the plateau; the circle stays (the punch).
    Plateau,
}

/// The rows (x₁, value) of a CSV profile, read by the loader ([`GapShape::Tabulated`],
/// [`ObstacleShape::Tabulated`]); empty as deserialized.
pub type ProfileRows = Arc<[[f64; 2]]>;

/// Obstacle function b(x₁) (`models::obstacle::Shape`, thesis §IV.2.1).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum ObstacleShape {
    /// b = level.
    Constant { level: f64 },
    /// b = offset + slope·x₁, a straight tilted obstacle (the manufactured Signorini scene).
    Linear { offset: f64, slope: f64 },
    /// With `periods` (the thesis's tables): b = offset + amplitude·sin(periods·2π(x₁+16)/32),
    /// `periods` whole periods on the thesis's x₁ ∈ [−16, 16]. With `period` instead:
    /// b = offset + amplitude·sin(2π(x₁ − phase)/period), `phase` (default 0) where the sine
    /// rises through `offset`. One of `periods` and `period`, never both; `phase` only with
    /// `period`.
    Periodic {
        offset: f64,
        amplitude: f64,
        #[serde(default)]
        periods: Option<f64>,
        #[serde(default)]
        period: Option<f64>,
        #[serde(default)]
        phase: Option<f64>,
    },
    /// Piecewise linear through the rows (x₁, b) of the CSV file `file` (a header line `x1,b`,
    /// then one row per line; the path relative to the experiment file's folder), held at the
    /// end values beyond the first and last row.
    Tabulated {
        file: String,
        /// The rows of `file`, read by the loader.
        #[serde(skip)]
        rows: ProfileRows,
    },
    /// b = base + height·θ_s(x₁ − at).
    Jump {
        base: f64,
        height: f64,
        at: f64,
        s: f64,
    },
    /// The saw obstacle of §IV.2.1.6 in one of two readings of the printed formula.
    Saw { s: f64, reading: SawReading },
    /// The tools of the U-O forming (§IV.2.4.7): b = A + θ_s(x₁ − c₁ − r)·(plateau − A) with
    /// A = c₂ − √(r² − (x₁ − c₁)²), the lower half circle about `center` up to its vertical
    /// end x₁ = c₁ + r, blended into the `plateau` (heights relative to the contact face).
    Arc {
        center: [f64; 2],
        radius: f64,
        plateau: f64,
        s: f64,
    },
}

impl ObstacleShape {
    /// The tool raised by `by`: an `arc` with its plateau, and with [`Rise::Whole`] its
    /// circle's center too. Other shapes do not rise (the loader allows `rises` on arcs only).
    pub fn raised(self, rise: Rise, by: f64) -> ObstacleShape {
        match self {
            ObstacleShape::Arc {
                center,
                radius,
                plateau,
                s,
            } => ObstacleShape::Arc {
                center: match rise {
                    Rise::Whole => [center[0], center[1] + by],
                    Rise::Plateau => center,
                },
                radius,
                plateau: plateau + by,
                s,
            },
            other => other,
        }
    }
}

/// How the printed saw formula of §IV.2.1.6 is read (`models::obstacle::SawReading`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SawReading {
    /// The continuous saw through its nodes.
    #[default]
    Continuous,
    /// The formula exactly as printed (with its jumps).
    Literal,
}

/// Gap width g(x₁, x₂) of a fluid example, (IV.7)–(IV.20), or of a scene of the user's own
/// (`models::thin_film::Gap`).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum GapShape {
    /// g = g0.
    Plain { g0: f64 },
    /// g = g0 + slope·x₁.
    Linear { g0: f64, slope: f64 },
    /// g = g0 + amplitude·sin(2π·frequency·x₁).
    WaveHorizontal {
        g0: f64,
        amplitude: f64,
        frequency: f64,
    },
    /// g = g0 + amplitude·sin²(2π·frequency·x₁)·sin²(2π·frequency·x₂).
    Hill {
        g0: f64,
        amplitude: f64,
        frequency: f64,
    },
    /// The Rayleigh step: g = g_in + (g_out − g_in)·θ_s(x₁ − at), θ_s of (IV.3) — g_in before
    /// the step (x₁ < at), g_out after it, blended over a width of order s > 0 (the Reynolds
    /// source needs g three times differentiable).
    Step {
        g_in: f64,
        g_out: f64,
        at: f64,
        s: f64,
    },
    /// A cylinder (a journal) of radius R = `radius` over a plane, in the parabolic
    /// approximation: g = g0 + (x₁ − center)²/(2R), least gap g0 at x₁ = center. With
    /// `radius_x2` and `center_x2` also curved across: + (x₂ − center_x2)²/(2·radius_x2).
    Parabolic {
        g0: f64,
        center: f64,
        radius: f64,
        #[serde(default)]
        center_x2: Option<f64>,
        #[serde(default)]
        radius_x2: Option<f64>,
    },
    /// The natural cubic spline through the rows (x₁, g) of the CSV file `file` (a header line
    /// `x1,g`, then one row per line; the path relative to the experiment file's folder).
    Tabulated {
        file: String,
        /// The rows of `file`, read by the loader.
        #[serde(skip)]
        rows: ProfileRows,
    },
}

/// Reading of the source term R₃c of (I.81) (`models::thin_film::CavitationSource`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CavitationSource {
    /// γ₃c of (I.61) as printed.
    #[default]
    Printed,
    /// 2γ₃ − γ₃c.
    SelfConsistent,
    /// R₃ of (I.77), the source without cavitation.
    Reynolds,
}

/// The volume residual of Theorem III.17 in the cavitation zone
/// (`crate::estimators::reynolds::ZoneResidual`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ZoneResidual {
    /// The full residual everywhere, as the theorem states it.
    #[default]
    Full,
    /// Dropped on cells whose four corner values are 0.
    OffZone,
    /// Dropped on cells with a corner value 0.
    OffTouching,
}

impl ZoneResidual {
    /// The experiment-file spelling.
    pub fn name(self) -> &'static str {
        match self {
            ZoneResidual::Full => "full",
            ZoneResidual::OffZone => "off-zone",
            ZoneResidual::OffTouching => "off-touching",
        }
    }
}

/// Whether the Reynolds cavitation model (I.82) is used.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum Cavitation {
    Off,
    On,
    /// Solve without cavitation first; switch it on only when ψ drops below zero.
    Auto,
}

/// The terms of the Reynolds volume residual (Theorems III.16, III.17) the study marks with
/// (`crate::estimators::reynolds::VolumeResidual`).
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum ReynoldsEstimator {
    /// ρ_Q = ‖l − ψ_hΔg/g‖_Q as the theorems state it.
    Theorem,
    /// The reading that reproduces the printed row-0 estimates: no −ψ_hΔg/g, and no squeeze
    /// part −12δv₃/g² of the load without cavitation; the theorem's estimate is reported beside
    /// it (`estimate_theorem`).
    ThesisCode,
}

#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ReynoldsData {
    /// Thesis equation of the example, e.g. `IV.7` (for the report only).
    pub equation: String,
    pub gap: GapShape,
    /// Constant upper-wall velocity δv = v(z₁) (lower wall at rest).
    #[serde(deserialize_with = "exactly")]
    pub upper_wall_velocity: [f64; 3],
    /// ψ₀ on ∂Ω₂.
    pub boundary_pressure: f64,
    pub cavitation: Cavitation,
    /// Reading of the source term R₃c of (I.81): `printed` (default, γ₃c of (I.61) as printed),
    /// `self-consistent` (2γ₃ − γ₃c) or `reynolds` (R₃ of (I.77), the source without cavitation).
    #[serde(default)]
    pub cavitation_source: CavitationSource,
    /// Terms of the volume residual the study marks with.
    pub estimator: ReynoldsEstimator,
    /// The volume residual in the cavitation zone (Theorem III.17): `full` as the theorem states
    /// it, or the alternative readings `off-zone` / `off-touching` whose measured effect the
    /// notes of IV.64 quote. Only meaningful with cavitation `on` or `auto`.
    #[serde(default)]
    pub zone_residual: ZoneResidual,
    /// A manufactured solution: the pressure is ψ₀ + A·w in closed form, the load is derived
    /// from it ([`crate::models::manufactured`]) and the rows get the true error and the
    /// effectivity.
    #[serde(default)]
    pub exact: Option<ExactSolution>,
}

/// The stabilisation term of the Theorem III.23 estimate
/// (`crate::estimators::substokes::Stabilisation`).
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum SubStokesStabilisation {
    /// δ_Q²‖∇ψ_h − κ − γ‖² with δ_Q = h_Q, as Theorem III.23 prints it.
    #[default]
    Literal,
    /// δ_ε h_Q²‖∇ψ_h‖², the thesis's own stabilisation (docs/estimators.md §5.6).
    DeltaEps,
}

impl SubStokesStabilisation {
    /// The experiment-file spelling.
    pub fn name(self) -> &'static str {
        match self {
            SubStokesStabilisation::Literal => "literal",
            SubStokesStabilisation::DeltaEps => "delta-eps",
        }
    }
}

/// The point condition (I.56) on χ.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum PointCondition {
    /// None: a₂ is coercive on all of H¹ (Theorem II.40), χ is determined without it.
    #[default]
    None,
    /// χ(P) = (g v̄)(P) at the corner P = (x₀, y₀) of the domain.
    Corner,
}

/// Default stabilisation constant δ_ε of the pressure stabilisation Σ_Q δ_ε h_Q² ⟨∇ψ, ∇φ⟩_Q
/// (§III.2.3), when a file gives none. The thesis only states the form ε = δ_ε h²
/// (docs/models.md §15 item 13), not the value: 1.10e-3 is the value calibrated on row 0 of
/// table IV.50, not a thesis number.
pub const DEFAULT_DELTA_EPS: f64 = 1.10e-3;

fn default_delta_eps() -> f64 {
    DEFAULT_DELTA_EPS
}

/// A SubStokes example of §IV.3.2 / §IV.3.6: the film of (IV.7)–(IV.20) as for Reynolds, the
/// stabilisation constant and the readings of the estimator.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SubStokesData {
    /// Thesis equation of the example, e.g. `IV.7` (for the report only).
    pub equation: String,
    pub gap: GapShape,
    /// Constant upper-wall velocity δv = v(z₁) (lower wall at rest).
    #[serde(deserialize_with = "exactly")]
    pub upper_wall_velocity: [f64; 3],
    /// ψ₀ on ∂Ω₂.
    pub boundary_pressure: f64,
    pub cavitation: Cavitation,
    /// Reading of γ₃c in the cavitation source γ_c (I.61), (I.65).
    #[serde(default)]
    pub cavitation_source: CavitationSource,
    /// δ_ε of the pressure stabilisation Σ_Q δ_ε h_Q²⟨∇ψ, ∇φ⟩_Q (default
    /// [`DEFAULT_DELTA_EPS`]).
    #[serde(default = "default_delta_eps")]
    pub delta_eps: f64,
    /// The point condition (I.56) (default none).
    #[serde(default)]
    pub point: PointCondition,
    /// The stabilisation term of the Theorem III.23 estimate (default `literal`).
    #[serde(default)]
    pub stabilisation_residual: SubStokesStabilisation,
    /// The solver of the coupled system (default `ldlt`).
    #[serde(default)]
    pub solver: FilmSolver,
    /// A solver the report runs the table with again, to compare (IV.50, IV.70: `uzawa`).
    #[serde(default)]
    pub compare_with: Option<FilmSolver>,
    /// A manufactured solution: the flow rate χ = curl(B t³(1 − t)³ ⊗ t³(1 − t)³) and the
    /// pressure ψ₀ + A·w in closed form, the sources derived from them
    /// ([`crate::models::manufactured_stokes`]); the rows get the true error and the
    /// effectivity.
    #[serde(default)]
    pub exact: Option<ExactSolution>,
}

/// The solver of a SubStokes system (`models::substokes`,
/// `models::substokes_uzawa`).
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum FilmSolver {
    /// The sparse LDLᵀ of the quasi-definite system (with cavitation: the primal–dual active
    /// set on it).
    #[default]
    Ldlt,
    /// CG-accelerated SSOR Uzawa (III.92), projected with cavitation.
    Uzawa,
}

impl FilmSolver {
    /// The experiment-file spelling.
    pub fn name(self) -> &'static str {
        match self {
            FilmSolver::Ldlt => "ldlt",
            FilmSolver::Uzawa => "uzawa",
        }
    }
}

/// The Uzawa comparison of Fig. III.6 on the test problem (III.88): [0, 4]², 32×32 cells
/// (`models::stokes_channel`).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct StokesChannelData {
    /// δ_ε of the stabilisation Σ_Q δ_ε h_Q²⟨∇p, ∇q⟩_Q (1 in (III.88)).
    pub delta_eps: f64,
    /// The variants of Uzawa's algorithm to run, in order: `identity`, `jacobi`,
    /// `gauss-seidel`, `ssor`, `cg-ssor` ((III.87)–(III.92)).
    pub variants: Vec<String>,
}

/// How to iterate.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum StudyKind {
    /// solve → estimate → mark (fixed number) → refine, one printed row per cycle.
    GridAdaptive,
    /// Model adaptivity on a fixed mesh (§IV.2.3): solve → model error (III.16) per contact
    /// face → move faces between the z- and the Signorini model (Algorithm III.2 or III.3).
    ModelAdaptive,
    /// Model and grid adaptivity balanced (Algorithm III.25, §IV.2.4): per cycle the model
    /// marking on the balanced model indicators ε̃_m and the fixed-number grid marking on the
    /// balanced discretisation indicators ε̃_d of (III.93).
    ModelAndGridAdaptive,
    /// Load steps of the U-O forming (§IV.2.4.7): per step `cycles_per_step` cycles of model and
    /// grid adaptivity (Algorithm III.25) on the body of the step, then every vertex moves by
    /// its displacement, the tools rise and the moved, stress-free body is the next step's
    /// domain, restarted from its coarse cells. One printed row per step (`rows` steps).
    LoadSteps,
    /// Iterations of a solver on one fixed problem (the Uzawa variants of Fig. III.6): `rows`
    /// iterations (`quick_rows` in the quick tier), no adaptivity.
    SolverIterations,
}

impl StudyKind {
    /// The experiment-file spelling.
    pub fn name(self) -> &'static str {
        match self {
            StudyKind::GridAdaptive => "grid-adaptive",
            StudyKind::ModelAdaptive => "model-adaptive",
            StudyKind::ModelAndGridAdaptive => "model-and-grid-adaptive",
            StudyKind::LoadSteps => "load-steps",
            StudyKind::SolverIterations => "solver-iterations",
        }
    }

    /// Whether the study moves contact faces between the z- and the Signorini model.
    pub fn adapts_model(self) -> bool {
        matches!(
            self,
            StudyKind::ModelAdaptive | StudyKind::ModelAndGridAdaptive | StudyKind::LoadSteps
        )
    }

    /// Whether the study refines and coarsens the mesh.
    pub fn adapts_grid(self) -> bool {
        matches!(
            self,
            StudyKind::GridAdaptive | StudyKind::ModelAndGridAdaptive | StudyKind::LoadSteps
        )
    }
}

/// The model-marking algorithm of a model-adaptive study (§III.1).
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
pub enum ModelAlgorithm {
    /// Algorithm III.2, fixed fraction strategy.
    #[serde(rename = "III.2")]
    FixedFraction,
    /// Algorithm III.3, sorted error strategy.
    #[serde(rename = "III.3")]
    SortedError,
}

/// ε₀ of Algorithms III.2/III.3 when a file does not set it: unstated in the thesis; IV.27
/// row 1 (2.9744e-08, no refinement after it) and IV.29 row 8 (7.6012e-07, refinement
/// continues) bound it to [2.97e-8, 7.6e-7) (docs/estimators.md §2.3).
pub const DEFAULT_MODEL_TOLERANCE: f64 = 1e-7;

/// α of the balance (III.93) when a file does not set it: unstated in the thesis; 0.5, the
/// middle of (0, 1) (docs/estimators.md §7).
pub const DEFAULT_BALANCE: f64 = 0.5;

/// `[study]` as written: every field of every kind, each optional where a kind may leave it
/// out. The loader checks it field by field (its messages name the dotted field) and turns it
/// into the typed [`Study`], whose [`Plan`] holds exactly the fields of its kind.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct StudyFile {
    pub kind: StudyKind,
    /// Number of printed rows (cycles 0 … rows−1).
    pub rows: usize,
    /// Number of printed rows in the quick (test) tier.
    pub quick_rows: usize,
    /// Solves on coarser meshes that the thesis did not print (1 for the fluid tables, whose
    /// row 0 is already the once-refined mesh).
    #[serde(default)]
    pub unprinted_cycles: usize,
    /// Grid-adaptive and model-and-grid-adaptive: the fraction of cells refined (θ_r).
    /// Model-adaptive: p_r, the fraction of the coarse (z) faces moved to the accurate
    /// (Signorini) model. Required by every kind but `solver-iterations` (the loader checks it;
    /// typed in [`Study::grid`] or [`Study::model`]).
    #[serde(default)]
    pub refine_fraction: Option<f64>,
    /// Grid-adaptive and model-and-grid-adaptive: the fraction of cells coarsened (θ_c).
    /// Model-adaptive: p_c, the fraction of the accurate faces moved back. Required as
    /// `refine_fraction`.
    #[serde(default)]
    pub coarsen_fraction: Option<f64>,
    /// Model-and-grid-adaptive: p_r of the model marking (the grid's θ_r is
    /// `refine_fraction`).
    #[serde(default)]
    pub model_refine_fraction: Option<f64>,
    /// Model-and-grid-adaptive: p_c of the model marking.
    #[serde(default)]
    pub model_coarsen_fraction: Option<f64>,
    /// Model-and-grid-adaptive: α ∈ (0, 1) of the balance (III.93) (default
    /// [`DEFAULT_BALANCE`]).
    #[serde(default)]
    pub balance: Option<f64>,
    /// Printed cycles `[first, last]` (inclusive) where the convergence rule applies (required
    /// for grid-adaptive studies; a model-adaptive study on a fixed mesh has none).
    #[serde(default, deserialize_with = "exactly_some")]
    pub convergence_window: Option<[usize; 2]>,
    /// Model-adaptive: the marking algorithm, `III.2` or `III.3`.
    #[serde(default)]
    pub algorithm: Option<ModelAlgorithm>,
    /// Model-adaptive: ε₀ of Algorithms III.2/III.3 (default [`DEFAULT_MODEL_TOLERANCE`]).
    #[serde(default)]
    pub model_tolerance: Option<f64>,
    /// Load steps: the cycles of model and grid adaptivity in every step (4 in §IV.2.4.7).
    #[serde(default)]
    pub cycles_per_step: Option<usize>,
    /// Load steps: how far the rising tools ([`Obstacle::rises`]) rise per step (10/24).
    #[serde(default)]
    pub lift_per_step: Option<f64>,
    /// How the fixed-number marking treats tied indicators at a cut (default `band`).
    #[serde(default)]
    pub ties: Ties,
    /// The linear solver of the SPD problems of the Reynolds and elasticity tables (`direct` or
    /// `multigrid`; default the faster for the family, [`crate::study::solver_of`]); `report
    /// --solver` overrides it. It changes how the systems are solved, not what is computed.
    #[serde(default)]
    pub solver: Option<crate::linalg::SolverKind>,
    /// Whether the report runs the thesis's alternative readings beside the experiment
    /// ([`crate::family::Family::readings`]: two readings of the cavitation source R₃c, the
    /// model error at the z-solution). Default: yes for the thesis's experiments, no for a
    /// scene of the user's own, whose numbers no printed table explains (typed as
    /// [`Study::readings`]). Like `solver`, it changes what runs beside the table, not what the
    /// table computes.
    #[serde(default)]
    pub alternatives: Option<bool>,
}

/// Tied indicators at a cut of the fixed-number marking (`crate::adaptivity::grid`).
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum Ties {
    /// Flag every cell within the tie band of a threshold (symmetric groups together), thin
    /// plateaus ([`crate::adaptivity::mark_fixed_number`]).
    #[default]
    Band,
    /// Flag exactly the requested counts, splitting tie groups in a fixed order
    /// ([`crate::adaptivity::mark_fixed_number_split`]): the SubStokes tables.
    Split,
}

/// How to iterate, checked and typed: what every kind has, and the [`Plan`] of its kind.
#[derive(Clone, Debug, PartialEq)]
pub struct Study {
    /// Number of printed rows (cycles 0 … rows−1; iterations of a solver study).
    pub rows: usize,
    /// Number of printed rows in the quick (test) tier.
    pub quick_rows: usize,
    /// Solves on coarser meshes that the thesis did not print ([`StudyFile::unprinted_cycles`]).
    pub unprinted_cycles: usize,
    /// How the fixed-number marking treats tied indicators at a cut.
    pub ties: Ties,
    /// The linear solver of the SPD systems, if the file names one ([`StudyFile::solver`]).
    pub solver: Option<crate::linalg::SolverKind>,
    /// Whether a scene with Signorini faces also computes, per cycle, the converged solution
    /// beside the linearised one for its `signorini_*` columns (`crate::study::signorini`): on
    /// as loaded, off for `report --no-alternatives` and the alternative readings (it costs
    /// about as much as the contact tables themselves). The converged reading computes it
    /// anyway.
    pub signorini_comparison: bool,
    /// Whether the run measures its true error (`crate::study::accuracy`: the energy of every
    /// printed cycle, or the solves kept for a reference): on as loaded, off for the alternative
    /// readings, which the page compares by their estimates (the error is the table's as
    /// written; measuring it again for each reading would double the cavitation tables' cost).
    pub true_error: bool,
    /// Which printed meshes the run keeps for the VTU files (`report --vtu`): the last one as
    /// loaded; none for the alternative readings unless every one is asked for.
    pub vtu: crate::results::VtuOutput,
    /// Whether the thesis's alternative readings run beside the table
    /// ([`StudyFile::alternatives`], resolved by the loader: by default for the thesis's
    /// experiments only). A run the file asks for itself (SubStokes `compare_with`) runs
    /// whatever this says; `report --no-alternatives` runs none.
    pub readings: bool,
    /// What the kind iterates, with its fields.
    pub plan: Plan,
}

/// The fixed-number grid marking of §IV.1: the fractions θ_r of cells refined and θ_c coarsened.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridFractions {
    pub refine: f64,
    pub coarsen: f64,
}

/// The model marking of §IV.2.3 (Algorithm III.2 or III.3): p_r of the coarse units moved to the
/// accurate model, p_c of the accurate ones moved back, and ε₀.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModelFractions {
    pub algorithm: ModelAlgorithm,
    pub refine: f64,
    pub coarsen: f64,
    /// ε₀ (default [`DEFAULT_MODEL_TOLERANCE`]).
    pub tolerance: f64,
}

/// What a study kind iterates, with the fields of that kind only (`[study] kind`).
#[derive(Clone, Debug, PartialEq)]
pub enum Plan {
    /// solve → estimate → mark (fixed number) → refine; the convergence rule applies over the
    /// printed cycles `window` (inclusive).
    GridAdaptive {
        grid: GridFractions,
        window: [usize; 2],
    },
    /// Model adaptivity on a fixed mesh (§IV.2.3).
    ModelAdaptive { model: ModelFractions },
    /// Model and grid adaptivity (Algorithm III.25, §IV.2.4; the model-adaptive film of
    /// §IV.3.4), balanced by α of (III.93) (default [`DEFAULT_BALANCE`]).
    ModelAndGridAdaptive {
        grid: GridFractions,
        model: ModelFractions,
        balance: f64,
        window: [usize; 2],
    },
    /// The load steps of the U-O forming (§IV.2.4.7): `cycles_per_step` cycles of model and
    /// grid adaptivity per step, the rising tools lifted by `lift_per_step` between steps.
    LoadSteps {
        grid: GridFractions,
        model: ModelFractions,
        balance: f64,
        cycles_per_step: usize,
        lift_per_step: f64,
    },
    /// Iterations of a solver on one fixed problem (Fig. III.6).
    SolverIterations,
}

impl Study {
    /// The kind, as `[study] kind` names it.
    pub fn kind(&self) -> StudyKind {
        match self.plan {
            Plan::GridAdaptive { .. } => StudyKind::GridAdaptive,
            Plan::ModelAdaptive { .. } => StudyKind::ModelAdaptive,
            Plan::ModelAndGridAdaptive { .. } => StudyKind::ModelAndGridAdaptive,
            Plan::LoadSteps { .. } => StudyKind::LoadSteps,
            Plan::SolverIterations => StudyKind::SolverIterations,
        }
    }

    /// The grid marking, where the kind refines the mesh.
    pub fn grid(&self) -> Option<GridFractions> {
        match self.plan {
            Plan::GridAdaptive { grid, .. }
            | Plan::ModelAndGridAdaptive { grid, .. }
            | Plan::LoadSteps { grid, .. } => Some(grid),
            Plan::ModelAdaptive { .. } | Plan::SolverIterations => None,
        }
    }

    /// The model marking, where the kind moves units between models.
    pub fn model(&self) -> Option<ModelFractions> {
        match self.plan {
            Plan::ModelAdaptive { model }
            | Plan::ModelAndGridAdaptive { model, .. }
            | Plan::LoadSteps { model, .. } => Some(model),
            Plan::GridAdaptive { .. } | Plan::SolverIterations => None,
        }
    }

    /// α of the balance (III.93), where the kind balances the two markings.
    pub fn balance(&self) -> Option<f64> {
        match self.plan {
            Plan::ModelAndGridAdaptive { balance, .. } | Plan::LoadSteps { balance, .. } => {
                Some(balance)
            }
            _ => None,
        }
    }

    /// The printed cycles `[first, last]` where the convergence rule applies; none on a fixed
    /// mesh, in the load steps (each restarts) and in a solver study.
    pub fn convergence_window(&self) -> Option<[usize; 2]> {
        match self.plan {
            Plan::GridAdaptive { window, .. } | Plan::ModelAndGridAdaptive { window, .. } => {
                Some(window)
            }
            _ => None,
        }
    }

    /// The solves of one printed row: `cycles_per_step` in a load-step study, 1 otherwise.
    pub fn cycles_per_row(&self) -> usize {
        match self.plan {
            Plan::LoadSteps {
                cycles_per_step, ..
            } => cycles_per_step,
            _ => 1,
        }
    }
}

/// Where to record solution values after the last cycle.
#[derive(Clone, Debug, Deserialize, PartialEq, Default)]
#[serde(deny_unknown_fields)]
pub struct Probes {
    #[serde(default)]
    pub x: Vec<f64>,
    #[serde(default)]
    pub y: Vec<f64>,
    /// `s1`, `s2` or `psi`.
    #[serde(default)]
    pub components: Vec<String>,
}

/// The printed thesis table (reference data only); empty (no columns, no rows) for a figure
/// experiment.
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ThesisRows {
    /// Column names as in `tables.csv`, the first is always `cycle`.
    pub columns: Vec<String>,
    /// One row per printed cycle; `inf` where the thesis prints inf, `nan` where it prints nan.
    pub rows: Vec<Vec<f64>>,
    /// Set when the printed table is known to be a copy of another (e.g. IV.17 = IV.13).
    #[serde(default)]
    pub duplicate_of: Option<String>,
    /// A part of the printed estimate that the thesis prints alone in another table (IV.41 and
    /// IV.42 carry IV.43's mesh-independent 0.34). The report then also compares tribo with
    /// √(thesis² − part²).
    #[serde(default)]
    pub additive_part: Option<AdditivePart>,
}

/// The thesis figures that show a table's run (`[figures]` of the file), as the text of Chapter
/// IV assigns them: the adaptively refined grids, the solution on the last grid, and for the
/// model-adaptive tables the refined model (the contact faces; with grid adaptivity, the grids
/// with those faces). A part the thesis does not draw is left out; a figure experiment
/// (`fig-IV.54`) is its own figure in every part. Each is a figure number such as `IV.12`,
/// which the report cites as "Fig. IV.12".
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ThesisFigures {
    #[serde(default, deserialize_with = "figure_number")]
    pub grids: Option<String>,
    #[serde(default, deserialize_with = "figure_number")]
    pub solution: Option<String>,
    #[serde(default, deserialize_with = "figure_number")]
    pub model: Option<String>,
}

/// A thesis figure number: a chapter in Roman numerals, a dot and a number (`IV.12`, `III.6`).
fn figure_number<'de, D>(deserializer: D) -> Result<Option<String>, D::Error>
where
    D: Deserializer<'de>,
{
    let Some(number) = Option::<String>::deserialize(deserializer)? else {
        return Ok(None);
    };
    let valid = number.split_once('.').is_some_and(|(chapter, n)| {
        !chapter.is_empty()
            && chapter.chars().all(|c| matches!(c, 'I' | 'V' | 'X'))
            && !n.is_empty()
            && n.len() <= 4
            && n.chars().all(|c| c.is_ascii_digit())
    });
    if valid {
        Ok(Some(number))
    } else {
        Err(D::Error::invalid_value(
            serde::de::Unexpected::Str(&number),
            &"a thesis figure number such as \"IV.12\"",
        ))
    }
}

/// Reference data for [`ThesisRows::additive_part`]: the printed estimates of the other table,
/// one per printed row.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct AdditivePart {
    /// The table that prints the part alone, e.g. `IV.43`.
    pub table: String,
    /// Its printed `estimate` column, row by row.
    pub estimate: Vec<f64>,
}

/// [`exactly`] for an optional field.
fn exactly_some<'de, D, T, const N: usize>(deserializer: D) -> Result<Option<[T; N]>, D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de>,
{
    exactly(deserializer).map(Some)
}

/// A list of exactly `N` values. serde's own `[T; N]` reads the first `N` values of a longer list
/// and drops the rest without a word (`upper_wall_velocity = [0, 0, 0, -10]` ran as `[0, 0, 0]`:
/// the squeeze was lost), so every fixed-length field of the format is read through this.
fn exactly<'de, D, T, const N: usize>(deserializer: D) -> Result<[T; N], D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de>,
{
    let values = Vec::<T>::deserialize(deserializer)?;
    let found = values.len();
    values.try_into().map_err(|_| {
        D::Error::invalid_length(found, &format!("a list of exactly {N} values").as_str())
    })
}
