//! The constraints on the dofs of one mesh (deal.II `AffineConstraints`, Ferrite
//! `ConstraintHandler`): hanging nodes, fixed values — Dirichlet data per component and single
//! fixed dofs — and, during an active-set iteration, the active constraints as an overlay.
//!
//! Applied in one place and distributed in one place:
//! * **hanging nodes** (value = mean of the two ends of the coarse edge, §II.3) are condensed
//!   into their parents when cell matrices are scattered ([`super::SparsityPattern`] builds its
//!   scatter plan from [`Constraints::hanging_parents`]); their rows keep a diagonal entry and
//!   are eliminated with value 0 during the solve;
//! * **fixed dofs** are eliminated by the solver ([`Constraints::eliminated`] lists them: rows
//!   and columns removed, a diagonal entry kept, so the sparsity pattern and its symbolic
//!   factorisation survive a changing active set); the **active set** of a variational
//!   inequality is an overlay on that list ([`crate::linalg::active_set`] appends it in every
//!   iteration);
//! * [`Constraints::distribute`] sets every hanging dof from its parents after a solve.
//!
//! Hanging vertices are never fixed nor put in an active set: their values follow from their
//! parents (docs/architecture.md, "Determinism").

use super::dofs::{DofMap, Hanging};
use crate::mesh::Side;

/// What constrains one dof (one byte per dof; the values of fixed dofs are kept apart).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Line {
    Free,
    Hanging,
    Fixed,
}

/// Hanging-node and fixed-value constraints of the dofs of one mesh (module docs).
#[derive(Clone, Debug)]
pub struct Constraints {
    n_components: usize,
    lines: Vec<Line>,
    /// Values of the fixed dofs, sorted by dof.
    fixed: Vec<(usize, f64)>,
    /// Hanging vertices with their parents, sorted by vertex.
    hanging: Vec<Hanging>,
}

impl Constraints {
    /// The hanging-node constraints of `dofs` (every component of every hanging vertex); no dof
    /// fixed yet.
    pub fn new(dofs: &DofMap) -> Constraints {
        let nc = dofs.n_components;
        let mut lines = vec![Line::Free; dofs.n_dofs()];
        for h in &dofs.vertices.hanging {
            for c in 0..nc {
                lines[dofs.dof(h.vertex, c)] = Line::Hanging;
            }
        }
        Constraints {
            n_components: nc,
            lines,
            fixed: Vec::new(),
            hanging: dofs.vertices.hanging.clone(),
        }
    }

    pub fn n_dofs(&self) -> usize {
        self.lines.len()
    }

    /// Fix one dof at `value`. A hanging dof cannot be fixed (its value follows from its
    /// parents); fixing a dof twice keeps the last value.
    pub fn fix(&mut self, dof: usize, value: f64) {
        debug_assert!(
            self.lines[dof] != Line::Hanging,
            "dof {dof} is hanging and cannot be fixed"
        );
        self.lines[dof] = Line::Fixed;
        match self.fixed.binary_search_by_key(&dof, |f| f.0) {
            Ok(i) => self.fixed[i].1 = value,
            Err(i) => self.fixed.insert(i, (dof, value)),
        }
    }

    /// Dirichlet data `value` for one component at every vertex of a side.
    pub fn fix_side(&mut self, dofs: &DofMap, side: Side, component: usize, value: f64) {
        for v in 0..dofs.vertices.len() as u32 {
            if dofs.vertices.on_side(v, side) {
                self.fix(dofs.dof(v, component), value);
            }
        }
    }

    /// Whether a dof is fixed (Dirichlet or a single fixed dof).
    pub fn is_fixed(&self, dof: usize) -> bool {
        self.lines[dof] == Line::Fixed
    }

    /// Whether a dof belongs to a hanging vertex.
    pub fn is_hanging(&self, dof: usize) -> bool {
        self.lines[dof] == Line::Hanging
    }

    /// Whether a dof is free: neither hanging nor fixed (the dofs an active set may constrain).
    pub fn is_free(&self, dof: usize) -> bool {
        self.lines[dof] == Line::Free
    }

    /// The two parent vertices of a hanging vertex.
    pub fn hanging_parents(&self, vertex: u32) -> Option<[u32; 2]> {
        let i = self
            .hanging
            .binary_search_by_key(&vertex, |h| h.vertex)
            .ok()?;
        Some(self.hanging[i].parents)
    }

    /// The dofs the solver eliminates, with their values, in dof order: every fixed dof at its
    /// value and every hanging dof at 0 (its equation is condensed into its parents).
    pub fn eliminated(&self) -> Vec<(usize, f64)> {
        let mut out = Vec::with_capacity(self.fixed.len() + self.hanging.len() * self.n_components);
        let mut fixed = self.fixed.iter();
        for (dof, line) in self.lines.iter().enumerate() {
            match line {
                Line::Free => {}
                Line::Hanging => out.push((dof, 0.0)),
                Line::Fixed => out.push(*fixed.next().expect("a value per fixed dof")),
            }
        }
        out
    }

    /// Set every hanging dof to the mean of its two parents (distribute the hanging-node
    /// constraints after a solve).
    pub fn distribute(&self, u: &mut [f64]) {
        let nc = self.n_components;
        for h in &self.hanging {
            for c in 0..nc {
                let a = u[h.parents[0] as usize * nc + c];
                let b = u[h.parents[1] as usize * nc + c];
                u[h.vertex as usize * nc + c] = 0.5 * (a + b);
            }
        }
    }
}
