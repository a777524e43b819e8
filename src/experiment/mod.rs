//! Experiment files: one TOML file per Chapter IV table (`experiments/IV.n.toml`).
//!
//! [`spec`] holds the serde types of the format, [`load`] parses one file and checks it against
//! the thesis's setting (§IV.1–§IV.3), [`load_dir`] loads a whole directory in table order. Every
//! problem with a file — unreadable, bad TOML, wrong type, unknown or missing field, contradictory
//! data — is an [`ExperimentError`] naming the file, the field and what was expected.

pub mod spec;

mod error;
mod load;

pub use error::ExperimentError;
pub use load::{load, load_dir};
pub use spec::*;
