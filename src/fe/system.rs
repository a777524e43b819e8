//! The discrete system of one mesh: dofs, constraints, sparsity pattern, and the assembled
//! matrix and load — what every problem sets up, assembles and hands to a solver.

use super::constraints::Constraints;
use super::dofs::DofMap;
use super::pattern::SparsityPattern;
use crate::linalg::{Csc, Ordering, SolveConstrained, SolveError};
use crate::mesh::Mesh;

/// Dofs, constraints, pattern and assembled values of one mesh.
pub struct System {
    pub dofs: DofMap,
    pub constraints: Constraints,
    pub pattern: SparsityPattern,
    /// Assembled matrix values (pattern order), empty before assembly.
    pub matrix: Vec<f64>,
    /// Assembled load vector, empty before assembly.
    pub rhs: Vec<f64>,
}

impl System {
    /// Q₁ dofs with `n_components` per vertex on `mesh`, the hanging-node constraints, and the
    /// pattern with them condensed. Dirichlet data are added by the problem
    /// ([`Constraints::fix`], [`Constraints::fix_side`]).
    pub fn new(mesh: &Mesh, n_components: usize) -> System {
        System::of_dofs(DofMap::new(mesh, n_components))
    }

    /// The system of a numbering `dofs`: its hanging-node constraints and the pattern with them
    /// condensed (a subset of the mesh's vertices, e.g. the SubStokes region of a model-adaptive
    /// film).
    pub fn of_dofs(dofs: DofMap) -> System {
        let constraints = Constraints::new(&dofs);
        let pattern = SparsityPattern::new(&dofs, &constraints);
        System::from_parts(dofs, constraints, pattern)
    }

    /// The system of a numbering, its hanging-node constraints and their pattern
    /// ([`System::of_dofs`] built in parts), not yet assembled.
    pub fn from_parts(dofs: DofMap, constraints: Constraints, pattern: SparsityPattern) -> System {
        System {
            dofs,
            constraints,
            pattern,
            matrix: Vec::new(),
            rhs: Vec::new(),
        }
    }

    /// Assemble cell matrices and vectors into `matrix` and `rhs`
    /// ([`SparsityPattern::assemble`]): `cell(k, ke, fe)` fills the row-major local matrix and
    /// vector of active cell `k` (layout [`super::LocalDofs`]).
    pub fn assemble<F>(&mut self, n_cells: usize, cell: F)
    where
        F: Fn(usize, &mut [f64], &mut [f64]) + Sync,
    {
        (self.matrix, self.rhs) = self.pattern.assemble(n_cells, cell);
    }

    /// Solve the assembled linear system with the constraints eliminated, and distribute the
    /// hanging dofs.
    pub fn solve(&self, solver: &mut dyn SolveConstrained) -> Result<Vec<f64>, SolveError> {
        let mut u = solver.solve(self.matrix(), &self.rhs, &self.constraints.eliminated())?;
        self.constraints.distribute(&mut u);
        Ok(u)
    }

    /// The dofs, dropping the rest once the solve is done: the estimate and the transfer to
    /// the next mesh need the numbering, not the assembled system, whose pattern and matrix
    /// are the largest arrays alive at that point.
    pub fn into_dofs(self) -> DofMap {
        self.dofs
    }

    /// The assembled matrix.
    pub fn matrix(&self) -> Csc<'_> {
        self.pattern.matrix(&self.matrix)
    }

    /// The fill-reducing ordering of this system's dofs for a direct solver (geometric nested
    /// dissection on the vertex positions).
    pub fn ordering(&self) -> Ordering {
        Ordering::nested_dissection(
            &self.dofs.vertices.keys,
            self.pattern.col_ptr(),
            self.pattern.row_idx(),
            self.dofs.n_components,
        )
    }
}
