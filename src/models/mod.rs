//! The models of Chapters I–II: elasticity, contact obstacles, thin-film data.

pub mod contact;
pub mod elasticity;
pub mod error;
pub mod film_comparison;
pub mod film_coupling;
pub mod manufactured;
pub mod manufactured_stokes;
pub mod obstacle;
pub mod reynolds;
pub mod stokes_channel;
pub mod substokes;
pub mod substokes_uzawa;
pub mod thin_film;

pub use error::ModelError;
