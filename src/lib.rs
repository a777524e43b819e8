//! tribo — regenerates the results of Chapter IV of F. Gimbel, *Modelling and Numerical
//! Simulation of Contact and Lubrication* (Siegen, 2012).
//!
//! The pipeline of one experiment (docs/architecture.md, "Data flow"): [`experiment`] file → typed problem →
//! [`study`] loop over [`mesh::Mesh`] → [`fe::System`] (dofs, constraints, pattern) → assembly
//! ([`models`]) and solve ([`linalg`]) → estimate ([`estimators`]) → [`adaptivity`] →
//! [`results::RunResult`] → golden snapshot (tests) and [`report`].

pub mod adaptivity;
pub mod estimators;
pub mod experiment;
pub mod family;
pub mod fe;
pub mod fsio;
pub mod heap;
pub mod linalg;
pub mod machine;
pub mod mesh;
pub mod models;
pub mod report;
pub mod results;
pub mod study;
pub mod thesis;
