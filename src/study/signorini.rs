//! The Signorini condition solved to convergence, and what the thesis's single linearisation
//! costs in accuracy.
//!
//! §IV.2.2 (thesis l. 5556–5568) linearises the Signorini condition (I.21) about an initial
//! guess s₀: at every contact vertex the normal n of the deformed boundary x + s₀ and the gap g
//! along it give the linear constraint (s − s₀)·n ≤ g ([`crate::models::contact`]). The thesis
//! takes s₀ from "a prior run", one solve per cycle (the previous cycle's solution in Tables
//! IV.12–IV.17, the cycle's z-solution in the model-adaptive Tables IV.18–IV.35), and does not
//! say whether it iterated. That single solve is the default reading
//! ([`crate::experiment::SignoriniReading::Linearised`]); a solution of it satisfies the
//! linearised constraint, not necessarily the exact one: a vertex can end up beyond the
//! obstacle where the obstacle or the deformed boundary is curved.
//!
//! **Fixed point** ([`converge`]): on the same mesh, take the last solution as the new
//! linearisation point s₀, rebuild n and g, solve again (the active set warm-started from the
//! last one, vertex by vertex), until
//! * the contact set (the vertices whose constraint is active) is the one of the iteration
//!   before, **and**
//! * the relative change of the displacement in the max-norm, ‖s_k − s₀‖_∞ over the dofs of
//!   the contact-side vertices divided by ‖s_k‖_∞, is at most [`FixedPoint::tolerance`]
//!   (1e-10).
//!
//! Those dofs are the only values of s₀ the constraints read, so the change is the fixed-point
//! residual: how far the solution is from the point it was linearised about. The next point is
//! the Anderson mixing of the last solutions (`Anderson`), restarted whenever the contact set
//! changes; without the mixing it would be the plain substitution s₀ ← s_k, which converges
//! only linearly (factors 0.7–0.9 per solve on the obstacles of Tables IV.16 and IV.17).
//!
//! At the fixed point s₀ = s, so every constrained vertex has g ≥ 0: the exact Signorini
//! condition holds at the contact vertices. The iteration fails, naming the iteration, when
//! the contact sets repeat with a period p ≥ 2 for two periods while the change shrinks by
//! less than 20 % over a period (a cycle, `cycle_period`), when the change exceeds the whole
//! displacement or grows to 1000 × the smallest change before (divergence), or after
//! [`FixedPoint::max_iterations`] (50) iterations; the study adds the table and the cycle in
//! front of the message.
//!
//! **Comparison** ([`Comparison`]): per cycle, the linearised solution s_lin against the
//! converged one s_conv on the same mesh: the iterations, the energy distance ‖s_lin − s_conv‖_a
//! (absolute and relative to ‖s_conv‖_a) and the largest violation of the exact Signorini
//! condition at the Signorini contact vertices by each ([`nodal_penetration`]). The tables
//! compute it only with the alternatives on (`report --no-alternatives` leaves it out,
//! [`crate::experiment::Study::signorini_comparison`]): it costs about as much again as the
//! contact tables themselves. A fixed point that fails there only empties the cycle's columns
//! and adds a note ([`ComparisonFailures`]).

use std::collections::{BTreeSet, VecDeque};

use super::cost::energy_norm;
use super::error::StudyError;
use crate::experiment::SignoriniReading;
use crate::fe::{DofMap, System};
use crate::linalg::SolveConstrained;
use crate::mesh::Mesh;
use crate::models::contact::{
    solve_contact, ConstraintBuilder, ContactBoundary, ContactConstraint, ContactModel,
    ContactSolution,
};
use crate::models::elasticity::Elasticity;
use crate::results::Value;

/// The stopping rule of the fixed-point iteration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FixedPoint {
    /// Largest relative change ‖s_k − s₀‖_∞ (contact-side dofs) / ‖s_k‖_∞ of a converged
    /// iteration.
    pub tolerance: f64,
    /// Most re-linearised solves before the iteration counts as failed.
    pub max_iterations: usize,
}

impl Default for FixedPoint {
    fn default() -> FixedPoint {
        FixedPoint {
            tolerance: 1e-10,
            max_iterations: 50,
        }
    }
}

/// The factor by which the residual must shrink over a period of repeating contact sets for
/// the repetition to count as a transient rather than a cycle.
const CYCLE_SHRINK: f64 = 0.8;

/// Growth of the relative change over the smallest one before that counts as divergence.
const DIVERGENCE_GROWTH: f64 = 1e3;

/// The converged solution of a cycle: its constraints (linearised about itself), the
/// active-set solution and the number of re-linearised solves it took.
#[derive(Clone, Debug)]
pub struct Converged {
    pub constraints: Vec<ContactConstraint>,
    pub solution: ContactSolution,
    /// Re-linearised solves (the fixed-point iterations).
    pub iterations: usize,
    /// Active-set iterations (linear solves) of all of them.
    pub active_set_iterations: usize,
}

impl Converged {
    /// The converged solution as the cycle's solve (`signorini = "converged"`): its constraints
    /// and solution, whose active-set iterations count every solve of the cycle, the linearised
    /// one's (`linearised_iterations`) and the fixed point's.
    pub fn as_cycle_solve(
        self,
        linearised_iterations: usize,
    ) -> (Vec<ContactConstraint>, ContactSolution) {
        let mut solution = self.solution;
        solution.iterations = linearised_iterations + self.active_set_iterations;
        (self.constraints, solution)
    }
}

/// The vertices whose constraint is active, in order.
fn contact_vertices(constraints: &[ContactConstraint], active: &[bool]) -> BTreeSet<u32> {
    constraints
        .iter()
        .zip(active)
        .filter(|(_, &a)| a)
        .map(|(c, _)| c.vertex)
        .collect()
}

/// Anderson mixing (depth [`ANDERSON_DEPTH`]) of the linearisation points: the next point is
/// the combination of the last solutions whose fixed-point residuals (solution − point) combine
/// to the least residual, instead of the last solution alone. Plain substitution converges
/// linearly, with factors of 0.7–0.9 per iteration on the steep obstacles of Tables IV.16 and
/// IV.17 (62 and 53 solves to 1e-10 in cycles 0 and 1 of IV.16, more than 100 in cycle 3 of
/// IV.17; with the mixing 10–31 in every cycle of the two that converges). The mixing is
/// restarted whenever the contact set changes, where the map is not smooth.
struct Anderson {
    /// (point, solution) at the contact-side dofs, oldest first.
    history: VecDeque<(Vec<f64>, Vec<f64>)>,
}

/// Earlier iterations the mixing combines.
const ANDERSON_DEPTH: usize = 5;

impl Anderson {
    fn new() -> Anderson {
        Anderson {
            history: VecDeque::new(),
        }
    }

    fn restart(&mut self) {
        self.history.clear();
    }

    /// The next point after the point `x` gave the solution `g` (both at the contact-side
    /// dofs): min_γ ‖f − ΔF γ‖₂ over the differences of the residuals f = g − x of the kept
    /// iterations (normal equations, Tikhonov-regularised by 1e-12 of their trace), then
    /// g − ΔG γ. With one iteration kept, `g` itself (plain substitution).
    fn next(&mut self, x: Vec<f64>, g: Vec<f64>) -> Vec<f64> {
        self.history.push_back((x, g));
        if self.history.len() > ANDERSON_DEPTH + 1 {
            self.history.pop_front();
        }
        let h = &self.history;
        let (last_x, last_g) = h.back().expect("just pushed");
        let residual = |(x, g): &(Vec<f64>, Vec<f64>)| -> Vec<f64> {
            g.iter().zip(x).map(|(a, b)| a - b).collect()
        };
        let f_last: Vec<f64> = last_g.iter().zip(last_x).map(|(a, b)| a - b).collect();
        let m = h.len() - 1;
        if m == 0 {
            return last_g.clone();
        }
        let fs: Vec<Vec<f64>> = h.iter().map(residual).collect();
        let delta = |v: &[Vec<f64>], i: usize| -> Vec<f64> {
            v[i + 1].iter().zip(&v[i]).map(|(a, b)| a - b).collect()
        };
        let gs: Vec<Vec<f64>> = h.iter().map(|(_, g)| g.clone()).collect();
        let df: Vec<Vec<f64>> = (0..m).map(|i| delta(&fs, i)).collect();
        let dg: Vec<Vec<f64>> = (0..m).map(|i| delta(&gs, i)).collect();
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let mut a = vec![vec![0.0; m + 1]; m];
        for i in 0..m {
            for j in 0..m {
                a[i][j] = dot(&df[i], &df[j]);
            }
            a[i][m] = dot(&df[i], &f_last);
        }
        let trace: f64 = (0..m).map(|i| a[i][i]).sum();
        for (i, row) in a.iter_mut().enumerate() {
            row[i] += 1e-12 * trace;
        }
        let Some(gamma) = solve_small(a) else {
            return last_g.clone();
        };
        let mut next = last_g.clone();
        for (dgi, gi) in dg.iter().zip(&gamma) {
            for (n, d) in next.iter_mut().zip(dgi) {
                *n -= gi * d;
            }
        }
        next
    }
}

/// The solution of the m×m system with the augmented rows `a` (right-hand side last), by
/// Gaussian elimination with partial pivoting; `None` if it is singular.
fn solve_small(mut a: Vec<Vec<f64>>) -> Option<Vec<f64>> {
    let m = a.len();
    for c in 0..m {
        let p = (c..m).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if a[p][c].abs() == 0.0 || !a[p][c].is_finite() {
            return None;
        }
        a.swap(c, p);
        let (upper, lower) = a.split_at_mut(c + 1);
        let pivot = &upper[c];
        for row in lower.iter_mut() {
            let factor = row[c] / pivot[c];
            for (x, q) in row[c..].iter_mut().zip(&pivot[c..]) {
                *x -= factor * q;
            }
        }
    }
    let mut x = vec![0.0; m];
    for r in (0..m).rev() {
        let sum: f64 = (r + 1..m).map(|k| a[r][k] * x[k]).sum();
        x[r] = (a[r][m] - sum) / a[r][r];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// The dofs of the vertices on the contact sides of `boundaries`: the values of a
/// linearisation point that the constraints read.
fn contact_side_dofs(boundaries: &[ContactBoundary], dofs: &DofMap) -> Vec<usize> {
    let mut out: Vec<usize> = boundaries
        .iter()
        .flat_map(|cb| dofs.vertices.side_vertices(cb.side))
        .flat_map(|v| [dofs.dof(v, 0), dofs.dof(v, 1)])
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

/// The period p ≥ 2 of a cycle: the last 2p contact sets are one period of p sets repeated
/// (not all the same), and over the last period the residual shrank by less than
/// [`CYCLE_SHRINK`] (`residuals[k]` is the residual of the solve that gave `sets[k]`). A set
/// that flips while the residual keeps shrinking is a transient (Table IV.16, cycle 1: 3, 3, 4,
/// 3, 4, 3 vertices in contact with the residual × 0.55–0.6 per two iterations, then it
/// settles), not a cycle; the cycles of its cycles 4–6 keep the residual at × 0.83–1.0 per
/// period.
fn cycle_period(sets: &[BTreeSet<u32>], residuals: &[f64]) -> Option<usize> {
    let n = sets.len();
    (2..=n / 2).find(|&p| {
        let tail = &sets[n - 2 * p..];
        tail[..p] == tail[p..]
            && tail[..p].iter().any(|s| *s != tail[0])
            && residuals[n - 1] > CYCLE_SHRINK * residuals[n - 1 - p]
    })
}

/// Iterate the linearisation point of the Signorini constraints of `builder` to a fixed point on
/// the mesh of `system`, starting from the solution `start` with its constraints
/// `start_constraints` (the linearised solve of the cycle). See the module documentation for
/// the stopping rule and the failures; an error names the iteration.
pub fn converge(
    system: &System,
    solver: &mut dyn SolveConstrained,
    builder: &ConstraintBuilder,
    start_constraints: &[ContactConstraint],
    start: &ContactSolution,
    options: &FixedPoint,
) -> Result<Converged, StudyError> {
    let dofs = &system.dofs;
    let side = contact_side_dofs(builder.boundaries, dofs);
    let at_side = |u: &[f64]| -> Vec<f64> { side.iter().map(|&i| u[i]).collect() };
    let mut sets = vec![contact_vertices(start_constraints, &start.active)];
    let mut residuals = vec![f64::INFINITY];
    let mut mixing = Anderson::new();
    // The first point: the linearised solution itself (the thesis's next s₀).
    let mut point = start.u.clone();
    let mut smallest = f64::INFINITY;
    let mut residual = f64::NAN;
    let mut active_set_iterations = 0;
    for k in 1..=options.max_iterations {
        let at = |what: String| format!("Signorini fixed point, iteration {k}: {what}");
        let constraints = builder
            .build(dofs, &system.constraints, Some(&point))
            .map_err(|e| StudyError::from(e).context(at("re-linearisation".into())))?;
        let last = sets.last().expect("the start's set");
        let initial: Vec<bool> = constraints
            .iter()
            .map(|c| last.contains(&c.vertex))
            .collect();
        let solution = solve_contact(system, solver, &constraints, Some(&initial))
            .map_err(|e| StudyError::from(e).context(at("linearised solve".into())))?;
        active_set_iterations += solution.iterations;
        let set = contact_vertices(&constraints, &solution.active);
        // The fixed-point residual: how far the solution is from the point it is linearised
        // about, at the dofs the constraints read, relative to the whole displacement.
        let scale = solution.u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let change = side
            .iter()
            .fold(0.0f64, |m, &i| m.max((solution.u[i] - point[i]).abs()));
        residual = if change == 0.0 { 0.0 } else { change / scale };
        let same_set = set == *last;
        if same_set && residual <= options.tolerance {
            return Ok(Converged {
                constraints,
                solution,
                iterations: k,
                active_set_iterations,
            });
        }
        sets.push(set);
        residuals.push(residual);
        if let Some(p) = cycle_period(&sets, &residuals) {
            return Err(StudyError::Failed(at(format!(
                "the contact sets of the last {} iterations repeat with period {p} (sizes {}) \
                 and the relative change of the displacement stays at {residual:.3e}: the \
                 linearisation cycles and does not converge",
                2 * p,
                sets[sets.len() - p..]
                    .iter()
                    .map(|s| s.len().to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            ))));
        }
        if residual > 1.0 || residual > DIVERGENCE_GROWTH * smallest {
            return Err(StudyError::Failed(at(format!(
                "the relative change of the displacement grew to {residual:.3e}, {:.0}× the \
                 smallest before ({smallest:.3e}): the linearisation diverges",
                residual / smallest
            ))));
        }
        smallest = smallest.min(residual);
        if !same_set {
            mixing.restart();
        }
        let next = mixing.next(at_side(&point), at_side(&solution.u));
        point = solution.u;
        for (&i, v) in side.iter().zip(next) {
            point[i] = v;
        }
    }
    Err(StudyError::Failed(format!(
        "Signorini fixed point, iteration {}: not converged within {} iterations (relative \
         change of the displacement {residual:.3e}, tolerance {:.0e})",
        options.max_iterations, options.max_iterations, options.tolerance,
    )))
}

/// The largest violation of the exact Signorini condition at the Signorini contact vertices by
/// the displacement `u`: the vertical depth of σ + u(σ) beyond the obstacle, max over the
/// vertices whose constraint is a Signorini one (0 if none is beyond). The same vertical
/// measure as the `penetration` column, but at the vertices only, where the discrete problem
/// (III.43) imposes the condition.
pub fn nodal_penetration(
    boundaries: &[ContactBoundary],
    constraints: &[ContactConstraint],
    dofs: &DofMap,
    u: &[f64],
) -> f64 {
    constraints
        .iter()
        .filter(|c| c.model == ContactModel::Signorini)
        .map(|c| {
            let p = dofs.displaced(u, c.vertex, 1.0);
            boundaries[c.boundary].obstacle.penetration(p, p, 2)
        })
        .fold(0.0, f64::max)
}

/// The linearised solution of a cycle against the converged one on the same mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Comparison {
    /// Re-linearised solves to the fixed point.
    pub iterations: usize,
    /// ‖s_lin − s_conv‖_a.
    pub energy_distance: f64,
    /// ‖s_conv‖_a.
    pub energy_norm: f64,
    /// Largest violation of the exact condition at the Signorini vertices by s_lin.
    pub penetration: f64,
    /// The same for s_conv (≈ 0).
    pub penetration_converged: f64,
}

/// Column names of the comparison in `data/<table>.csv`.
pub mod columns {
    pub const ITERATIONS: &str = "signorini_iterations";
    pub const ENERGY_DISTANCE: &str = "signorini_energy_distance";
    pub const RELATIVE_DISTANCE: &str = "signorini_relative_distance";
    pub const PENETRATION: &str = "signorini_penetration";
    pub const PENETRATION_CONVERGED: &str = "signorini_penetration_converged";
    /// Every column of the comparison, in the order of the file.
    pub const ALL: [&str; 5] = [
        ITERATIONS,
        ENERGY_DISTANCE,
        RELATIVE_DISTANCE,
        PENETRATION,
        PENETRATION_CONVERGED,
    ];

    /// Whether `name` is a column of the comparison (kept out of the golden snapshots and of
    /// the table's own columns on the page, which shows them apart).
    pub fn is_comparison(name: &str) -> bool {
        ALL.contains(&name)
    }
}

impl Comparison {
    /// The comparison of the linearised solution `linearised` (with its constraints) with the
    /// converged one on the mesh `mesh`.
    pub fn of(
        model: &Elasticity,
        mesh: &Mesh,
        dofs: &DofMap,
        boundaries: &[ContactBoundary],
        linearised: (&[ContactConstraint], &[f64]),
        converged: &Converged,
    ) -> Comparison {
        let u = &converged.solution.u;
        Comparison {
            iterations: converged.iterations,
            energy_distance: energy_norm(model, mesh, dofs, linearised.1, Some(u)),
            energy_norm: energy_norm(model, mesh, dofs, u, None),
            penetration: nodal_penetration(boundaries, linearised.0, dofs, linearised.1),
            penetration_converged: nodal_penetration(boundaries, &converged.constraints, dofs, u),
        }
    }

    /// The row's columns ([`columns`]).
    pub fn columns(&self) -> Vec<(String, Value)> {
        let real = |name: &str, v: f64| (name.to_string(), Value::real(Some(v)));
        let relative = (self.energy_norm > 0.0).then(|| self.energy_distance / self.energy_norm);
        vec![
            (
                columns::ITERATIONS.to_string(),
                Value::Count(self.iterations as i64),
            ),
            real(columns::ENERGY_DISTANCE, self.energy_distance),
            (
                columns::RELATIVE_DISTANCE.to_string(),
                Value::real(relative),
            ),
            real(columns::PENETRATION, self.penetration),
            real(columns::PENETRATION_CONVERGED, self.penetration_converged),
        ]
    }
}

/// The fixed points of a run's comparisons that failed with the linearised reading: the table
/// goes on with its linearised solutions, the cycle's comparison is empty, and a note of the
/// section names the cycle and says why.
#[derive(Clone, Debug, Default)]
pub struct ComparisonFailures {
    /// Solves before the first printed cycle (`study.unprinted_cycles`).
    pub unprinted: usize,
    /// Solves started so far.
    solves: usize,
    notes: Vec<String>,
}

impl ComparisonFailures {
    /// Count a solve of the run (every solve, with or without Signorini faces).
    pub fn start_solve(&mut self) {
        self.solves += 1;
    }

    /// The fixed point of the current solve: with `signorini = "converged"` a failure stays
    /// the error it is (the table fails); with the linearised reading it becomes a note and
    /// `None`.
    pub fn settle(
        &mut self,
        reading: SignoriniReading,
        fixed_point: Result<Converged, StudyError>,
    ) -> Result<Option<Converged>, StudyError> {
        match fixed_point {
            Ok(converged) => Ok(Some(converged)),
            Err(e) if reading == SignoriniReading::Linearised => {
                let solve = self.solves.saturating_sub(1);
                let cycle = solve
                    .checked_sub(self.unprinted)
                    .map_or(format!("unprinted solve {solve}"), |c| format!("cycle {c}"));
                self.notes.push(format!(
                    "{cycle}: no converged Signorini solution to compare the linearised one \
                     with (its signorini_* columns are empty): {e}"
                ));
                Ok(None)
            }
            Err(e) => Err(e),
        }
    }

    /// The notes of the failures, in the order of the cycles.
    pub fn notes(&self) -> Vec<String> {
        self.notes.clone()
    }
}
