//! The linear solver of an SPD problem, chosen per experiment (`[study] solver`) or on the
//! command line (`report --solver`): the sparse Cholesky factorisation ([`DirectSolver`], the
//! reference) or multigrid-preconditioned CG ([`MultigridSolver`]). Both solve A x = b with
//! some dofs eliminated at given values ([`SolveConstrained`]), which is all the active-set
//! method and the models need.

use serde::{Deserialize, Serialize};

use super::multigrid::MultigridSolver;
use super::{Csc, DirectSolver, SolveError};

/// Which linear solver the SPD problems of a run use; without a choice, each family gets the
/// one measured faster for it ([`crate::study::solver_of`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum SolverKind {
    /// Sparse Cholesky (faer) with nested-dissection ordering: the default of the elasticity
    /// tables.
    Direct,
    /// Conjugate gradients preconditioned by a geometric multigrid V-cycle on the quadtree
    /// levels: the default of the Reynolds tables, where it is faster than the direct solver
    /// and keeps its meshes and active sets (a run's seconds per phase and solver: the report's
    /// Performance section).
    Multigrid,
}

impl SolverKind {
    pub fn name(self) -> &'static str {
        match self {
            SolverKind::Direct => "direct",
            SolverKind::Multigrid => "multigrid",
        }
    }
}

/// How accurately a solve must meet its equations. A direct solve is exact, whatever is asked;
/// an iterative one stops earlier for a step of an active-set iteration
/// ([`MultigridSolver::step_tolerance`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Accuracy {
    /// The solution the caller keeps.
    Full,
    /// A step of an active-set iteration: its solution only decides the next active set, and
    /// the final active set is confirmed by a [`Accuracy::Full`] solve
    /// ([`super::active_set::primal_dual_active_set`]).
    ActiveSetStep,
}

/// Solve A x = b where the dofs in `eliminated` take the given values.
pub trait SolveConstrained {
    /// The solve, where the first `always` entries of `eliminated` are eliminated in every solve
    /// of this matrix (the constraints) and the rest in this one only (the active bounds of an
    /// active-set iteration): a solver may keep what it prepared across such solves
    /// ([`MultigridSolver::solve_overlay`]).
    fn solve_overlay(
        &mut self,
        matrix: Csc<'_>,
        rhs: &[f64],
        eliminated: &[(usize, f64)],
        always: usize,
        accuracy: Accuracy,
    ) -> Result<Vec<f64>, SolveError>;

    /// Whether a solve at [`Accuracy::ActiveSetStep`] may be less accurate than at
    /// [`Accuracy::Full`] (an iterative solver).
    fn inexact_steps(&self) -> bool {
        false
    }

    /// The vertices whose two dofs the next solves take in their normal and tangential frame
    /// (the contact solves, [`super::active_set::Rotation`]); nothing to do for a solver that
    /// does not look at the mesh.
    fn set_rotation(&mut self, _rotated: &[(u32, [f64; 2])]) {}

    /// The solve with every entry of `eliminated` a constraint.
    fn solve(
        &mut self,
        matrix: Csc<'_>,
        rhs: &[f64],
        eliminated: &[(usize, f64)],
    ) -> Result<Vec<f64>, SolveError> {
        self.solve_overlay(matrix, rhs, eliminated, eliminated.len(), Accuracy::Full)
    }
}

impl SolveConstrained for DirectSolver {
    /// The factorisation is of the block of the free dofs of each solve: nothing to keep.
    fn solve_overlay(
        &mut self,
        matrix: Csc<'_>,
        rhs: &[f64],
        eliminated: &[(usize, f64)],
        _always: usize,
        _accuracy: Accuracy,
    ) -> Result<Vec<f64>, SolveError> {
        DirectSolver::solve(self, matrix, rhs, eliminated)
    }
}

impl SolveConstrained for MultigridSolver {
    fn solve_overlay(
        &mut self,
        matrix: Csc<'_>,
        rhs: &[f64],
        eliminated: &[(usize, f64)],
        always: usize,
        accuracy: Accuracy,
    ) -> Result<Vec<f64>, SolveError> {
        MultigridSolver::solve_overlay(self, matrix, rhs, eliminated, always, accuracy)
    }

    fn inexact_steps(&self) -> bool {
        true
    }

    fn set_rotation(&mut self, rotated: &[(u32, [f64; 2])]) {
        MultigridSolver::set_rotation(self, rotated);
    }
}

/// The solver of an SPD problem (module docs).
pub enum LinearSolver {
    Direct(Box<DirectSolver>),
    Multigrid(MultigridSolver),
}

impl LinearSolver {
    /// A solver of the given kind for SPD systems.
    pub fn spd(kind: SolverKind) -> LinearSolver {
        match kind {
            SolverKind::Direct => LinearSolver::Direct(Box::new(DirectSolver::cholesky())),
            SolverKind::Multigrid => LinearSolver::Multigrid(MultigridSolver::default()),
        }
    }

    /// Drop what belongs to the current mesh once its last solve is done.
    pub fn release_pattern(&mut self) {
        match self {
            LinearSolver::Direct(d) => d.release_pattern(),
            LinearSolver::Multigrid(m) => m.release_pattern(),
        }
    }

    /// CG iterations of the solves since the last call (`None` for the direct solver).
    pub fn take_iterations(&mut self) -> Option<Vec<usize>> {
        match self {
            LinearSolver::Direct(_) => None,
            LinearSolver::Multigrid(m) => Some(m.take_iterations()),
        }
    }
}

impl SolveConstrained for LinearSolver {
    fn solve_overlay(
        &mut self,
        matrix: Csc<'_>,
        rhs: &[f64],
        eliminated: &[(usize, f64)],
        always: usize,
        accuracy: Accuracy,
    ) -> Result<Vec<f64>, SolveError> {
        match self {
            LinearSolver::Direct(d) => d.solve(matrix, rhs, eliminated),
            LinearSolver::Multigrid(m) => {
                m.solve_overlay(matrix, rhs, eliminated, always, accuracy)
            }
        }
    }

    fn inexact_steps(&self) -> bool {
        matches!(self, LinearSolver::Multigrid(_))
    }

    fn set_rotation(&mut self, rotated: &[(u32, [f64; 2])]) {
        if let LinearSolver::Multigrid(m) = self {
            m.set_rotation(rotated);
        }
    }
}
