//! The split of an assembled saddle-point [`System`] into the blocks of (III.86),
//!
//! ```text
//! A v − B p = f,    Bᵀv + C p = g,
//! ```
//!
//! for the Uzawa solvers of [`crate::linalg::uzawa`].
//!
//! **What is split.** A system with several components per vertex, one of which is the pressure
//! (the others the velocity), assembled as the symmetric quasi-definite matrix
//! [A −B; −Bᵀ −C] with the mass rows negated and the load [f; −g] (the Stokes test problem
//! (III.88) of [`crate::models::stokes_channel`], the SubStokes systems of
//! [`crate::models::substokes`]). The blocks live on the **free** dofs only
//! ([`crate::fe::Constraints::is_free`]): every eliminated dof
//! ([`crate::fe::Constraints::eliminated`]) is left out —
//! * a fixed (Dirichlet) dof at its value: its couplings move to the right-hand side,
//!   f = load − (K·lift) on the velocity rows and g = −(load − K·lift) on the pressure rows
//!   (negated back), lift = the fixed values;
//! * a hanging dof at 0: the hanging-node constraints are already condensed into the parents
//!   when the cell matrices are scattered ([`crate::fe::SparsityPattern`]), so a hanging dof's
//!   row and column hold only their diagonal and the free rows never see it; its value is set
//!   from its parents afterwards ([`crate::fe::Constraints::distribute`]).
//!
//! So the blocks are exactly the reduced system the direct solver factors
//! ([`crate::fe::System::solve`], `substokes::solve_system`): a block solution scattered back
//! ([`SaddleBlocks::field`], eliminated values in place, hanging dofs at 0) and distributed
//! solves the same equations (test `blocks_of_a_mesh_with_hanging_nodes_solve_like_the_system`
//! in `models::substokes_uzawa`: 1.3e-15 relative against `solve_system`). Zero entries of the
//! assembled pattern are not stored in the blocks. The block unknowns also get the
//! nested-dissection order of their dofs ([`SaddleBlocks::ordering`] for the direct solve of
//! the blocks, its velocities alone as [`SaddlePoint::velocity_ordering`] for a Cholesky factor
//! of A).

use super::System;
use crate::linalg::csr::CsrMatrix;
use crate::linalg::saddle_point::{SaddlePoint, SaddlePointError};
use crate::linalg::Ordering;

/// The blocks of (III.86) of an assembled [`System`] with the maps back to its dofs.
#[derive(Clone, Debug)]
pub struct SaddleBlocks {
    /// A, B, C, f, g on the free dofs.
    pub system: SaddlePoint,
    /// Dof of the system of each velocity unknown (increasing).
    pub velocity_dofs: Vec<usize>,
    /// Dof of the system of each pressure unknown (increasing).
    pub pressure_dofs: Vec<usize>,
    /// The eliminated dofs of the system with their values (fixed dofs at their value, hanging
    /// dofs at 0), in dof order.
    pub eliminated: Vec<(usize, f64)>,
    /// Dofs of the system.
    pub n_dofs: usize,
    /// The n + m block unknowns (velocities first) in the nested-dissection order of their
    /// dofs ([`System::ordering`]), for [`SaddlePoint::solve_direct`]; its velocities alone
    /// are `system.velocity_ordering` (for a Cholesky factor of A).
    pub ordering: Ordering,
}

impl SaddleBlocks {
    /// Split the assembled `system` (matrix [A −B; −Bᵀ −C], load [f; −g], module docs) whose
    /// component `pressure_component` is the pressure and whose other components are the
    /// velocity. Fails if the system is not assembled or the blocks are inconsistent.
    pub fn new(
        system: &System,
        pressure_component: usize,
    ) -> Result<SaddleBlocks, SaddlePointError> {
        let n_dofs = system.dofs.n_dofs();
        let nc = system.dofs.n_components;
        if pressure_component >= nc {
            return Err(SaddlePointError::Blocks(format!(
                "pressure component {pressure_component} of {nc}"
            )));
        }
        if system.matrix.is_empty() || system.rhs.len() != n_dofs {
            return Err(SaddlePointError::Blocks(
                "the system is not assembled".into(),
            ));
        }
        let is_pressure = |d: usize| d % nc == pressure_component;
        // Block index of each free dof (velocity or pressure numbering).
        const NONE: usize = usize::MAX;
        let mut index = vec![NONE; n_dofs];
        let (mut velocity_dofs, mut pressure_dofs) = (Vec::new(), Vec::new());
        for (d, slot) in index.iter_mut().enumerate() {
            if !system.constraints.is_free(d) {
                continue;
            }
            if is_pressure(d) {
                *slot = pressure_dofs.len();
                pressure_dofs.push(d);
            } else {
                *slot = velocity_dofs.len();
                velocity_dofs.push(d);
            }
        }
        let (n, m) = (velocity_dofs.len(), pressure_dofs.len());
        let eliminated = system.constraints.eliminated();
        let mut lift = vec![0.0; n_dofs];
        for &(d, value) in &eliminated {
            lift[d] = value;
        }
        let matrix = system.matrix();
        let k_lift = matrix.multiply(&lift);
        let (mut a, mut b, mut c) = (Vec::new(), Vec::new(), Vec::new());
        // Full symmetric storage: column j holds the entries (i, j); take each block from the
        // rows of its first block row.
        for j in 0..n_dofs {
            if index[j] == NONE {
                continue;
            }
            for p in matrix.col_ptr[j]..matrix.col_ptr[j + 1] {
                let (i, value) = (matrix.row_idx[p] as usize, matrix.values[p]);
                if index[i] == NONE || value == 0.0 {
                    continue;
                }
                match (is_pressure(i), is_pressure(j)) {
                    (false, false) => a.push((index[i], index[j], value)),
                    (false, true) => b.push((index[i], index[j], -value)),
                    (true, true) => c.push((index[i], index[j], -value)),
                    (true, false) => {}
                }
            }
        }
        // Reduced right-hand side: load minus the couplings to the eliminated values; the
        // pressure rows are negated back (−Bᵀv − Cp = −g).
        let f: Vec<f64> = velocity_dofs
            .iter()
            .map(|&d| system.rhs[d] - k_lift[d])
            .collect();
        let g: Vec<f64> = pressure_dofs
            .iter()
            .map(|&d| -(system.rhs[d] - k_lift[d]))
            .collect();
        let mut saddle = SaddlePoint::new(
            CsrMatrix::from_triplets(n, n, a),
            CsrMatrix::from_triplets(n, m, b),
            CsrMatrix::from_triplets(m, m, c),
            f,
            g,
        )?;
        let mut blocks = SaddleBlocks {
            system: saddle.clone(),
            velocity_dofs,
            pressure_dofs,
            eliminated,
            n_dofs,
            ordering: Ordering::identity(0),
        };
        blocks.ordering = blocks.block_ordering(&system.ordering());
        let fwd: Vec<usize> = blocks
            .ordering
            .fwd
            .iter()
            .copied()
            .filter(|&k| k < n)
            .collect();
        let mut inv = vec![0usize; n];
        for (new, &old) in fwd.iter().enumerate() {
            inv[old] = new;
        }
        saddle.velocity_ordering = Some(Ordering { fwd, inv });
        blocks.system = saddle;
        Ok(blocks)
    }

    /// System dof of block unknown `k` (velocities first, then pressures).
    fn system_dof(&self, k: usize) -> usize {
        let n = self.velocity_dofs.len();
        if k < n {
            self.velocity_dofs[k]
        } else {
            self.pressure_dofs[k - n]
        }
    }

    /// The n + m block unknowns (velocities first) in the order a fill-reducing ordering of
    /// the system's dofs gives their dofs.
    fn block_ordering(&self, of_system: &Ordering) -> Ordering {
        let total = self.velocity_dofs.len() + self.pressure_dofs.len();
        let mut order: Vec<usize> = (0..total).collect();
        order.sort_by_key(|&k| of_system.inv[self.system_dof(k)]);
        let mut inv = vec![0usize; total];
        for (new, &old) in order.iter().enumerate() {
            inv[old] = new;
        }
        Ordering { fwd: order, inv }
    }

    /// The dof vector of the system from block vectors: eliminated values in place (hanging
    /// dofs at 0, to be set by [`crate::fe::Constraints::distribute`]).
    pub fn field(&self, velocity: &[f64], pressure: &[f64]) -> Vec<f64> {
        let mut u = vec![0.0; self.n_dofs];
        for &(d, value) in &self.eliminated {
            u[d] = value;
        }
        for (&d, &value) in self.velocity_dofs.iter().zip(velocity) {
            u[d] = value;
        }
        for (&d, &value) in self.pressure_dofs.iter().zip(pressure) {
            u[d] = value;
        }
        u
    }

    /// The pressure unknowns of a dof vector of the system.
    pub fn pressure_of(&self, u: &[f64]) -> Vec<f64> {
        self.pressure_dofs.iter().map(|&d| u[d]).collect()
    }

    /// The velocity unknowns of a dof vector of the system.
    pub fn velocity_of(&self, u: &[f64]) -> Vec<f64> {
        self.velocity_dofs.iter().map(|&d| u[d]).collect()
    }
}
