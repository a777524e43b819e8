//! Experiment files: one TOML file per Chapter IV table (`experiments/IV.n.toml`), per figure
//! experiment (`fig-…`), or per scene of the user's own (a free id, no `[thesis]`;
//! `experiments/templates/`).
//!
//! [`spec`] holds the plain-data types of the format, [`load`] parses one file, checks it
//! against the thesis's setting (§IV.1–§IV.3) and returns a typed [`Experiment`] whose
//! [`Problem`] says which model to build; [`load_dir`] loads a whole directory in table order, [`load_each`] each file on its own.
//! Every problem with a file — unreadable, bad TOML, wrong type, unknown or missing field,
//! contradictory data — is an [`ExperimentError`] naming the file, the field and what was
//! expected.

pub mod parameters;
pub mod spec;
pub mod sweep;

mod error;
mod load;
mod printed;
mod warnings;

pub use error::ExperimentError;
pub use load::{load, load_dir, load_each, load_each_swept, table_order, Loaded, MAX_FILE_BYTES};
pub use load::{parse_set, SweepField, TableOrder};
pub use load::{Checked, FileCheck as Check, Found};
pub use printed::{fingerprints, PRINTED_LOCK};
pub use spec::*;
pub use warnings::Scope;
pub use warnings::Warning;

/// One experiment, loaded and checked: the scene's geometry, the typed problem, how to iterate,
/// probes, notes and the printed thesis rows.
#[derive(Clone, Debug, PartialEq)]
pub struct Experiment {
    /// Table id: `IV.1` … `IV.75`, a figure id (`fig-IV.54`), or the free id of a scene of
    /// the user's own (`my-reynolds-step`).
    pub table: String,
    /// Thesis section, e.g. `IV.1.1`.
    pub section: String,
    /// Human-readable title for the report.
    pub title: String,
    pub scene: Scene,
    /// The family of runs the scene's effects and study kind make ([`crate::family`]).
    pub family: crate::family::FamilyRef,
    pub problem: Problem,
    pub study: Study,
    pub probes: Probes,
    /// Readings of the thesis and known differences, shown in the report for this table.
    pub notes: Vec<String>,
    /// Tables of the same scene solved another way ([`ExperimentFile::related`]).
    pub related: Vec<String>,
    pub thesis: ThesisRows,
    /// The thesis figures that show the run ([`ThesisFigures`]).
    pub figures: ThesisFigures,
    /// The `[scene]` and `[study]` keys as the file writes them, for the report
    /// ([`parameters::of_file`]).
    pub parameters: Vec<crate::results::Parameter>,
    /// Whether the run is compared with the thesis: the file as shipped, an edited thesis
    /// experiment, or a scene of the user's own.
    pub comparison: Comparison,
    /// Where the run is one of a sweep's ([`sweep`]): the sweep, and which run it is.
    pub sweep: Option<sweep::SweepRun>,
}

/// What a run can be compared with, decided by the loader from the id and the file.
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Comparison {
    /// A thesis experiment as shipped: a table is compared with its printed rows; a figure
    /// experiment (`fig-…`) has none and is shown alone.
    #[default]
    Printed,
    /// A thesis experiment (`IV.<n>`, `fig-…`) whose scene, study or printed rows differ from
    /// the shipped file's: the dotted paths of the differing fields (empty when they cannot be
    /// named). It runs, but is not scored against the thesis.
    Edited(Vec<String>),
    /// A scene of the user's own: a free id and no `[thesis]`, so nothing to compare with.
    OwnScene,
}

impl Comparison {
    /// Whether the run is compared with (or, for a figure, belongs to) the thesis as printed.
    pub fn is_printed(&self) -> bool {
        matches!(self, Comparison::Printed)
    }
}

/// The domain and the initial mesh of a scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Descriptive scene name, e.g. `box-constant-load`.
    pub name: String,
    /// Rectangle `[x0, x1] × [y0, y1]`.
    pub domain: Rectangle,
    /// Number of coarse cells in x and y (the level-0 quadtree roots).
    pub coarse_cells: [usize; 2],
    /// Global refinements of the coarse grid before the first solve ([`SceneFile`]).
    pub global_refinements: usize,
    /// Refinements at `refined_sides` after the global ones ([`SceneFile::contact_refinements`]).
    pub side_refinements: usize,
    /// The contact sides (those with an obstacle) when `side_refinements` > 0.
    pub refined_sides: Vec<Side>,
    /// deal.II's mesh-smoothing flags applied at every grid refinement
    /// ([`SceneFile::mesh_smoothing`]); none by default.
    pub mesh_smoothing: crate::mesh::MeshSmoothing,
}

/// What a scene simulates — the effects it names, with their data. One variant per kind of data;
/// the scene's family ([`crate::family`]) builds it from the sections and its model from it.
#[derive(Clone, Debug, PartialEq)]
pub enum Problem {
    /// Linear elasticity (I.17), §IV.1.
    Elasticity(ElasticityData),
    /// An elastic body in contact with rigid obstacles, (I.20)/(I.21), §IV.2.
    Contact {
        elasticity: ElasticityData,
        contact: ContactData,
    },
    /// Reynolds thin-film flow (I.79), with or without cavitation (I.82), §IV.3.
    Reynolds(ReynoldsData),
    /// SubStokes thin-film flow (I.58), with or without cavitation (I.66), §IV.3.2, §IV.3.6.
    SubStokes(SubStokesData),
    /// The stabilised Stokes test problem (III.88) of the Uzawa comparison (Fig. III.6).
    StokesChannel(StokesChannelData),
    /// Reynolds and SubStokes on one film, the model chosen cell by cell (§IV.3.4, Fig.
    /// IV.116): a scene with both effects.
    FilmModels {
        reynolds: ReynoldsData,
        substokes: SubStokesData,
    },
}

impl Problem {
    /// The Reynolds data, if this is a Reynolds problem.
    pub fn reynolds(&self) -> Option<&ReynoldsData> {
        match self {
            Problem::Reynolds(r) => Some(r),
            _ => None,
        }
    }

    /// The Reynolds data for changing a reading, if this is a Reynolds problem.
    pub fn reynolds_mut(&mut self) -> Option<&mut ReynoldsData> {
        match self {
            Problem::Reynolds(r) => Some(r),
            _ => None,
        }
    }

    /// The SubStokes data, if this is a SubStokes problem.
    pub fn substokes(&self) -> Option<&SubStokesData> {
        match self {
            Problem::SubStokes(s) => Some(s),
            _ => None,
        }
    }

    /// The contact data, if this is a contact problem.
    pub fn contact(&self) -> Option<&ContactData> {
        match self {
            Problem::Contact { contact, .. } => Some(contact),
            _ => None,
        }
    }
}
