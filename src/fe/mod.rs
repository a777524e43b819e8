//! Q₁ finite elements on quadtree meshes: quadrature, shape functions, dofs with hanging-node
//! constraints, and sparse symmetric systems.

pub mod dofs;
pub mod q1;
pub mod quadrature;
pub mod system;

pub use dofs::{DofMap, Hanging, Vertices};
pub use q1::Rect;
pub use system::{SolveBuffers, SolveError, SparseSystem};
