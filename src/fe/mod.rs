//! Q₁ finite elements on quadtree meshes: quadrature, cell values on the bilinear map of a cell,
//! dofs and the local-dof layout, constraints (hanging nodes, Dirichlet data, active sets), the
//! sparsity pattern with its scatter plan, the discrete system of one mesh, and its split into
//! the saddle-point blocks of (III.86) for the Uzawa solvers.

pub mod blocks;
pub mod cell_values;
pub mod constraints;
pub mod dofs;
pub mod hierarchy;
pub mod pattern;
pub mod quadrature;
pub mod system;

pub use blocks::SaddleBlocks;
pub use cell_values::CellValues;
pub use constraints::Constraints;
pub use dofs::{DofMap, Hanging, LocalDofs, Vertices};
pub use pattern::SparsityPattern;
pub use system::System;
