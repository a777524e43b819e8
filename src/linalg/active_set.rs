//! The primal–dual active-set method (semismooth Newton) for a quadratic problem with nodal
//! bounds: min ½xᵀKx − Fᵀx subject to x_d ≤ b (upper) or x_d ≥ b (lower) at the bounded dofs and
//! the eliminated dofs of the constraints (Dirichlet, hanging) at their values. One solver for
//! contact (n·s ≤ η at the contact vertices, §III.2.1.3, in the rotated normal/tangential frame)
//! and for cavitation (ψ ≥ 0 at the interior vertices, (III.61)).
//!
//! With the multiplier λ = σ(F − Kx)_d (σ = +1 for an upper bound, −1 for a lower one) and the
//! violation v = σ(x_d − b), the active set is updated to
//! A = {bounds with λ > −tol_λ (if active) or v > tol_v (if inactive)}; on A the dof is fixed at
//! its bound (an overlay on the eliminated dofs, so the sparsity pattern and the symbolic
//! factorisation are reused by every iteration), off A it is free. The iteration stops when A
//! repeats: the KKT conditions then hold up to the tolerances (Hintermüller, Ito, Kunisch,
//! SIAM J. Optim. 13 (2003), the primal–dual active set strategy as a semismooth Newton method).
//!
//! **Negated rows** ([`NodalBounds::negated_rows`]). In a symmetric quasi-definite saddle-point
//! system whose constraint equations are stored negated (the mass rows of SubStokes,
//! [`crate::models::substokes`]: row d reads −(Bᵀχ + Cψ)_d = −G_d), the bounded unknown is the
//! pressure and the complementarity condition is on the un-negated residual
//! (Bᵀχ + Cψ − G)_d = −(Kx − F)_d. With the row sign ρ = −1 the multiplier is
//! λ = ρσ(F − Kx)_d and the violation test is scaled by ρK_dd > 0 instead of K_dd < 0. For
//! ρ = +1 (every minimisation) both are the expressions above, bit for bit.
//!
//! **Inexact steps.** With an iterative solver ([`super::SolveConstrained::inexact_steps`]) each
//! iteration first solves only as accurately as deciding the next active set needs
//! ([`super::Accuracy::ActiveSetStep`]: multigrid stops at a relative residual of 1e-10 instead
//! of 1e-13); when the decided set is the set just solved for, it is confirmed on a
//! full-accuracy solve of the same set, which starts from the step's solution, and the iteration
//! stops only if that solution decides the same set again. The solution returned is therefore
//! always a full-accuracy solution whose active set repeats — the stopping rule above, exactly.
//! A step could only change the path, where a bound's decision sits within the step's error of
//! its threshold: then the iteration takes another route to the same solution (the problem's
//! solution is unique). On the six Reynolds cavitation tables at full size, in their three
//! readings of R₃c, every active set and iteration count stayed those of the full-accuracy
//! iteration even with steps stopped at 1e-8 (two orders looser than used); the steps save a
//! quarter of the CG iterations of these tables.

use std::borrow::Cow;

use super::solver::Accuracy;
use super::{Csc, SolveError};

/// Whether a bound is an upper (x_d ≤ value) or a lower one (x_d ≥ value).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sense {
    Upper,
    Lower,
}

impl Sense {
    #[inline]
    pub(crate) fn sign(self) -> f64 {
        match self {
            Sense::Upper => 1.0,
            Sense::Lower => -1.0,
        }
    }
}

/// A bound on one dof (of the rotated system where a [`Rotation`] is given). 16 bytes: a
/// cavitation problem has a bound at almost every dof.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bound {
    dof: u32,
    pub sense: Sense,
    pub value: f64,
}

impl Bound {
    pub fn new(dof: usize, sense: Sense, value: f64) -> Bound {
        Bound {
            dof: u32::try_from(dof).expect("fewer than 2³² dofs"),
            sense,
            value,
        }
    }

    /// The bounded dof.
    #[inline]
    pub fn dof(&self) -> usize {
        self.dof as usize
    }
}

/// The bounds of a problem: listed one by one (contact), or one value at every dof a mask selects
/// (cavitation: ψ ≥ 0 at every free vertex), which needs no list as long as the system.
#[derive(Clone, Copy, Debug)]
pub enum Bounds<'a> {
    Listed(&'a [Bound]),
    Uniform {
        at: &'a [bool],
        sense: Sense,
        value: f64,
    },
}

impl<'a> Bounds<'a> {
    /// The bounds in order (of the list, or of the dofs).
    pub fn iter(&self) -> BoundIter<'a> {
        match *self {
            Bounds::Listed(list) => BoundIter::Listed(list.iter()),
            Bounds::Uniform { at, sense, value } => BoundIter::Uniform {
                at: at.iter().enumerate(),
                sense,
                value,
            },
        }
    }

    /// Number of bounds.
    pub fn len(&self) -> usize {
        match self {
            Bounds::Listed(list) => list.len(),
            Bounds::Uniform { at, .. } => at.iter().filter(|&&m| m).count(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Iterator over [`Bounds`].
pub enum BoundIter<'a> {
    Listed(std::slice::Iter<'a, Bound>),
    Uniform {
        at: std::iter::Enumerate<std::slice::Iter<'a, bool>>,
        sense: Sense,
        value: f64,
    },
}

impl Iterator for BoundIter<'_> {
    type Item = Bound;

    #[inline]
    fn next(&mut self) -> Option<Bound> {
        match self {
            BoundIter::Listed(list) => list.next().copied(),
            BoundIter::Uniform { at, sense, value } => at
                .find(|(_, &m)| m)
                .map(|(dof, _)| Bound::new(dof, *sense, *value)),
        }
    }
}

/// A pre-transform of a two-component system into local frames: at each listed vertex the dofs
/// (2v, 2v + 1) become the components along n and along t = (−n₂, n₁) (values ← QᵀKQ, rhs ← QᵀF
/// with the 2×2 block R_v = [n | t]). A bound on dof 2v is then a bound on n·s.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Rotation {
    pub frames: Vec<(u32, [f64; 2])>,
}

impl Rotation {
    /// QᵀKQ and QᵀF. The pattern must be vertex-block complete (both dofs of a vertex have the
    /// same column pattern and are adjacent in every column), as every Q₁ vector pattern is.
    pub fn apply(&self, matrix: Csc<'_>, values: &mut [f64], rhs: &mut [f64]) {
        let (cp, ri) = (matrix.col_ptr, matrix.row_idx);
        for &(w, n) in &self.frames {
            let t = [-n[1], n[0]];
            let (j0, j1) = (2 * w as usize, 2 * w as usize + 1);
            let (a, b) = (cp[j0], cp[j1]);
            let len = cp[j0 + 1] - a;
            debug_assert_eq!(len, cp[j1 + 1] - b);
            for k in 0..len {
                debug_assert_eq!(ri[a + k], ri[b + k]);
                let (x0, x1) = (values[a + k], values[b + k]);
                values[a + k] = n[0] * x0 + n[1] * x1;
                values[b + k] = t[0] * x0 + t[1] * x1;
            }
            let (f0, f1) = (rhs[j0], rhs[j1]);
            rhs[j0] = n[0] * f0 + n[1] * f1;
            rhs[j1] = t[0] * f0 + t[1] * f1;
        }
        for &(v, n) in &self.frames {
            let t = [-n[1], n[0]];
            let i0 = 2 * v as usize;
            for q in cp[i0]..cp[i0 + 1] {
                let j = ri[q] as usize;
                let p0 = matrix.position(i0, j).expect("symmetric pattern");
                debug_assert_eq!(ri[p0 + 1] as usize, i0 + 1);
                let (y0, y1) = (values[p0], values[p0 + 1]);
                values[p0] = n[0] * y0 + n[1] * y1;
                values[p0 + 1] = t[0] * y0 + t[1] * y1;
            }
        }
    }

    /// Back from the local frames to Cartesian components: x ← Qx.
    pub fn to_cartesian(&self, x: &mut [f64]) {
        for &(v, n) in &self.frames {
            let (i0, i1) = (2 * v as usize, 2 * v as usize + 1);
            let (un, ut) = (x[i0], x[i1]);
            x[i0] = n[0] * un - n[1] * ut;
            x[i1] = n[1] * un + n[0] * ut;
        }
    }
}

/// Below which violation an inactive bound stays inactive (rounding of the solve).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ViolationTolerance {
    /// `factor · (1 + |b|)` for each bound (contact: bounds are distances of order one).
    PerBound(f64),
    /// `factor · max_d |x_d|` of the current iterate (cavitation: ψ is of the order of ψ₀).
    SolutionScale(f64),
}

/// Tolerances and the iteration limit.
#[derive(Clone, Debug, PartialEq)]
pub struct ActiveSetOptions {
    /// Most iterations (linear solves); an active set still changing after them is an error.
    pub max_iterations: usize,
    /// An active bound stays active while λ > −this (rounding-level negative multipliers).
    pub multiplier_tolerance: f64,
    pub violation: ViolationTolerance,
}

/// The problem: the matrix and load (Cartesian), the bounds, an optional rotation, and the dofs
/// the constraints eliminate ([`crate::fe::Constraints::eliminated`]), on top of which the active
/// set is laid in every iteration.
pub struct NodalBounds<'a> {
    pub matrix: Csc<'a>,
    pub rhs: &'a [f64],
    pub bounds: Bounds<'a>,
    pub rotation: Option<&'a Rotation>,
    pub eliminated: &'a [(usize, f64)],
    /// Whether the rows of the bounded dofs are the negated equations of the bounded unknowns
    /// (module docs, "Negated rows"). `false` for a minimisation (contact, Reynolds
    /// cavitation).
    pub negated_rows: bool,
}

impl NodalBounds<'_> {
    /// ρ = −1 for negated rows, +1 otherwise (module docs).
    #[inline]
    fn row_sign(&self) -> f64 {
        if self.negated_rows {
            -1.0
        } else {
            1.0
        }
    }
}

/// The converged iterate.
#[derive(Clone, Debug)]
pub struct ActiveSetSolution {
    /// The solution in Cartesian components; hanging dofs are 0 (distribute them).
    pub x: Vec<f64>,
    /// Whether each bound is active.
    pub active: Vec<bool>,
    /// λ per bound (≥ 0 up to the tolerance; 0 up to rounding on inactive bounds).
    pub multipliers: Vec<f64>,
    /// σ(b − x_d) per bound, in the solver's frame (≥ 0 up to the tolerance, 0 when active).
    pub slack: Vec<f64>,
    /// Linear solves done.
    pub iterations: usize,
}

/// The primal–dual active-set method (module docs), starting from `initial` (all inactive if
/// `None` or of the wrong length).
pub fn primal_dual_active_set(
    problem: &NodalBounds<'_>,
    solver: &mut dyn super::SolveConstrained,
    initial: Option<&[bool]>,
    options: &ActiveSetOptions,
) -> Result<ActiveSetSolution, SolveError> {
    let (values, rhs): (Cow<[f64]>, Cow<[f64]>) = match problem.rotation {
        Some(rotation) => {
            let mut k = problem.matrix.values.to_vec();
            let mut f = problem.rhs.to_vec();
            rotation.apply(problem.matrix, &mut k, &mut f);
            (Cow::Owned(k), Cow::Owned(f))
        }
        None => (
            Cow::Borrowed(problem.matrix.values),
            Cow::Borrowed(problem.rhs),
        ),
    };
    let matrix = problem.matrix.with_values(&values);
    solver.set_rotation(problem.rotation.map_or(&[], |r| &r.frames[..]));
    let diag = matrix.diagonal();
    let rho = problem.row_sign();
    let bounds = problem.bounds;
    let n_bounds = bounds.len();
    let mut active: Vec<bool> = match initial {
        Some(a) if a.len() == n_bounds => a.to_vec(),
        _ => vec![false; n_bounds],
    };
    // The constraints' eliminated dofs, then the active bounds at their values (the overlay).
    let mut eliminated = problem.eliminated.to_vec();
    let constrained = eliminated.len();
    // A step solve decides the next active set; when that is the same set, the set is confirmed
    // on the full-accuracy solution (module docs, "Inexact steps").
    let step = if solver.inexact_steps() {
        Accuracy::ActiveSetStep
    } else {
        Accuracy::Full
    };
    let mut iterations = 0;
    loop {
        iterations += 1;
        eliminated.truncate(constrained);
        eliminated.extend(
            bounds
                .iter()
                .zip(&active)
                .filter(|(_, &a)| a)
                .map(|(b, _)| (b.dof(), b.value)),
        );
        let solve = |solver: &mut dyn super::SolveConstrained, accuracy| {
            solver.solve_overlay(matrix, &rhs, &eliminated, constrained, accuracy)
        };
        let mut x = solve(solver, step)?;
        let mut kx = matrix.multiply(&x);
        let mut next = next_active(problem, &diag, &rhs, options, &active, &x, &kx);
        if next == active && step != Accuracy::Full {
            x = solve(solver, Accuracy::Full)?;
            kx = matrix.multiply(&x);
            next = next_active(problem, &diag, &rhs, options, &active, &x, &kx);
        }
        if next == active {
            let multipliers = bounds
                .iter()
                .map(|b| multiplier(rho, &rhs, &kx, &b))
                .collect();
            let slack = bounds
                .iter()
                .map(|b| b.sense.sign() * (b.value - x[b.dof()]))
                .collect();
            let mut x = x;
            if let Some(rotation) = problem.rotation {
                rotation.to_cartesian(&mut x);
            }
            return Ok(ActiveSetSolution {
                x,
                active,
                multipliers,
                slack,
                iterations,
            });
        }
        if iterations >= options.max_iterations {
            return Err(SolveError::ActiveSetNotConverged { iterations });
        }
        active = next;
    }
}

/// The active set after the iterate `x` (with `kx` = Kx) of the active set `active`: an active
/// bound stays active while its multiplier is positive (up to the multiplier tolerance), an
/// inactive one becomes active where x violates it beyond rounding.
fn next_active(
    problem: &NodalBounds<'_>,
    diag: &[f64],
    rhs: &[f64],
    options: &ActiveSetOptions,
    active: &[bool],
    x: &[f64],
    kx: &[f64],
) -> Vec<bool> {
    let rho = problem.row_sign();
    let scale = match options.violation {
        ViolationTolerance::SolutionScale(_) => x.iter().fold(0.0f64, |m, v| m.max(v.abs())),
        ViolationTolerance::PerBound(_) => 0.0,
    };
    problem
        .bounds
        .iter()
        .zip(active)
        .map(|(b, &is_active)| {
            if is_active {
                multiplier(rho, rhs, kx, &b) > -options.multiplier_tolerance
            } else {
                let tol = match options.violation {
                    ViolationTolerance::PerBound(f) => f * (1.0 + b.value.abs()),
                    ViolationTolerance::SolutionScale(f) => f * scale,
                };
                let d = rho * diag[b.dof()];
                // σ(x − b) beyond rounding (scaled by the diagonal, as the iteration's
                // c·(x − b) with c = ρK_dd > 0)
                d * (b.sense.sign() * (x[b.dof()] - b.value)) > d * tol
            }
        })
        .collect()
}

/// The multiplier λ = ρσ(F − Kx)_d of bound `b` (module docs), with `kx` = Kx.
#[inline]
fn multiplier(rho: f64, rhs: &[f64], kx: &[f64], b: &Bound) -> f64 {
    rho * b.sense.sign() * (rhs[b.dof()] - kx[b.dof()])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::DirectSolver;

    /// The 1D obstacle problem −u'' = f on (0, 1), u(0) = u(1) = 0, by finite differences on
    /// `n` intervals (the matrix of h⁻¹·tridiag(−1, 2, −1), load h·f), in full CSC storage.
    struct Laplacian1d {
        col_ptr: Vec<usize>,
        row_idx: Vec<u32>,
        diag: Vec<usize>,
        values: Vec<f64>,
        rhs: Vec<f64>,
    }

    impl Laplacian1d {
        fn new(n: usize, f: impl Fn(f64) -> f64) -> Laplacian1d {
            let h = 1.0 / n as f64;
            let (mut col_ptr, mut row_idx, mut diag, mut values) =
                (vec![0], vec![], vec![], vec![]);
            for j in 0..=n {
                for i in j.saturating_sub(1)..=(j + 1).min(n) {
                    if i == j {
                        diag.push(values.len());
                    }
                    row_idx.push(i as u32);
                    values.push(if i == j { 2.0 / h } else { -1.0 / h });
                }
                col_ptr.push(values.len());
            }
            let rhs = (0..=n).map(|i| h * f(i as f64 * h)).collect();
            Laplacian1d {
                col_ptr,
                row_idx,
                diag,
                values,
                rhs,
            }
        }

        fn matrix(&self) -> Csc<'_> {
            Csc {
                col_ptr: &self.col_ptr,
                row_idx: &self.row_idx,
                diag: &self.diag,
                values: &self.values,
            }
        }
    }

    /// Every KKT condition of the bounds at the converged iterate, to rounding.
    fn assert_kkt(matrix: Csc<'_>, rhs: &[f64], bounds: Bounds<'_>, s: &ActiveSetSolution) {
        let kx = matrix.multiply(&s.x);
        for (i, b) in bounds.iter().enumerate() {
            let sign = match b.sense {
                Sense::Upper => 1.0,
                Sense::Lower => -1.0,
            };
            let lambda = sign * (rhs[b.dof()] - kx[b.dof()]);
            let slack = sign * (b.value - s.x[b.dof()]);
            assert!((lambda - s.multipliers[i]).abs() < 1e-9, "bound {i}");
            assert!((slack - s.slack[i]).abs() < 1e-12, "bound {i}");
            assert!(slack >= -1e-12, "bound {i} violated by {slack}");
            if s.active[i] {
                assert!(lambda > 0.0 && slack.abs() < 1e-12, "bound {i}: λ {lambda}");
            } else {
                assert!(lambda.abs() < 1e-9, "bound {i}: free with λ {lambda}");
            }
        }
    }

    /// A solver whose step solves are off by a relative 1e-9 (as an iterative solver stopped
    /// early), exact otherwise; it records the accuracy of every solve.
    struct InexactSteps {
        exact: DirectSolver,
        asked: Vec<Accuracy>,
    }

    impl crate::linalg::SolveConstrained for InexactSteps {
        fn solve_overlay(
            &mut self,
            matrix: Csc<'_>,
            rhs: &[f64],
            eliminated: &[(usize, f64)],
            _always: usize,
            accuracy: Accuracy,
        ) -> Result<Vec<f64>, crate::linalg::SolveError> {
            self.asked.push(accuracy);
            let mut x = self.exact.solve(matrix, rhs, eliminated)?;
            if accuracy == Accuracy::ActiveSetStep {
                for (i, x) in x.iter_mut().enumerate() {
                    *x *= 1.0 + 1e-9 * if i % 2 == 0 { 1.0 } else { -1.0 };
                }
            }
            Ok(x)
        }

        fn inexact_steps(&self) -> bool {
            true
        }
    }

    /// With inexact steps the iteration takes the same active sets and returns the solution of
    /// an exact solve of the final set, confirmed by it (module docs, "Inexact steps").
    #[test]
    fn inexact_steps_end_on_a_confirmed_full_accuracy_solve() {
        let n = 64;
        let pull = Laplacian1d::new(n, |x| if x < 0.5 { -40.0 } else { 20.0 });
        let interior: Vec<bool> = (0..=n).map(|i| i > 0 && i < n).collect();
        let problem = NodalBounds {
            matrix: pull.matrix(),
            rhs: &pull.rhs,
            bounds: Bounds::Uniform {
                at: &interior,
                sense: Sense::Lower,
                value: 0.0,
            },
            rotation: None,
            eliminated: &[(0, 0.0), (n, 0.0)],
            negated_rows: false,
        };
        let options = ActiveSetOptions {
            max_iterations: 50,
            multiplier_tolerance: 0.0,
            violation: ViolationTolerance::PerBound(1e-13),
        };
        let exact = primal_dual_active_set(&problem, &mut DirectSolver::cholesky(), None, &options)
            .expect("converges");
        let mut inexact = InexactSteps {
            exact: DirectSolver::cholesky(),
            asked: Vec::new(),
        };
        let s = primal_dual_active_set(&problem, &mut inexact, None, &options).expect("converges");
        assert_eq!(s.iterations, exact.iterations);
        assert_eq!(s.active, exact.active);
        assert_eq!(
            s.x, exact.x,
            "the returned solution is the full-accuracy one"
        );
        let steps = inexact
            .asked
            .iter()
            .filter(|&&a| a == Accuracy::ActiveSetStep)
            .count();
        assert_eq!(steps, exact.iterations, "one step solve per iteration");
        assert_eq!(inexact.asked.last(), Some(&Accuracy::Full));
        assert_eq!(inexact.asked.len(), exact.iterations + 1);
    }

    #[test]
    fn obstacle_problem_from_above_and_below_satisfies_the_kkt_conditions() {
        let n = 64;
        let lap = Laplacian1d::new(n, |_| 20.0);
        let boundary = [(0, 0.0), (n, 0.0)];
        // u ≤ 1 − 2(x − ½)² (an upper obstacle the load pushes against in the middle), and
        // u ≥ 0 with a load pulling down on the left half (a lower bound like cavitation).
        let upper: Vec<Bound> = (1..n)
            .map(|i| {
                let x = i as f64 / n as f64;
                Bound::new(i, Sense::Upper, 1.0 - 2.0 * (x - 0.5).powi(2))
            })
            .collect();
        let pull = Laplacian1d::new(n, |x| if x < 0.5 { -40.0 } else { 20.0 });
        // ψ ≥ 0 at the interior nodes, as one uniform bound over a mask.
        let interior: Vec<bool> = (0..=n).map(|i| i > 0 && i < n).collect();
        let lower = Bounds::Uniform {
            at: &interior,
            sense: Sense::Lower,
            value: 0.0,
        };
        let options = ActiveSetOptions {
            max_iterations: 50,
            multiplier_tolerance: 0.0,
            violation: ViolationTolerance::PerBound(1e-13),
        };
        for (system, bounds) in [(&lap, Bounds::Listed(&upper)), (&pull, lower)] {
            let problem = NodalBounds {
                matrix: system.matrix(),
                rhs: &system.rhs,
                bounds,
                rotation: None,
                eliminated: &boundary,
                negated_rows: false,
            };
            let s = primal_dual_active_set(&problem, &mut DirectSolver::cholesky(), None, &options)
                .expect("converges");
            assert!(s.active.iter().any(|&a| a) && s.active.iter().any(|&a| !a));
            assert_kkt(system.matrix(), &system.rhs, bounds, &s);
            // A warm start at the solution's active set converges in one solve.
            let again = primal_dual_active_set(
                &problem,
                &mut DirectSolver::cholesky(),
                Some(&s.active),
                &options,
            )
            .unwrap();
            assert_eq!(again.iterations, 1);
            assert_eq!(again.x, s.x);
        }
    }

    /// The lower-bound obstacle problem with every row (matrix and load) negated, factored by
    /// LDLᵀ with all signs −1 and solved with `negated_rows`: the same iterates, the same active
    /// set, the same multipliers (to rounding) as the original problem. Without the flag the
    /// multipliers have the wrong sign and the iteration does not find that solution.
    #[test]
    fn negated_rows_give_the_multipliers_of_the_original_rows() {
        let n = 64;
        let pull = Laplacian1d::new(n, |x| if x < 0.5 { -40.0 } else { 20.0 });
        let mut negated = Laplacian1d::new(n, |x| if x < 0.5 { -40.0 } else { 20.0 });
        negated.values.iter_mut().for_each(|v| *v = -*v);
        negated.rhs.iter_mut().for_each(|v| *v = -*v);
        let interior: Vec<bool> = (0..=n).map(|i| i > 0 && i < n).collect();
        let lower = Bounds::Uniform {
            at: &interior,
            sense: Sense::Lower,
            value: 0.0,
        };
        let boundary = [(0, 0.0), (n, 0.0)];
        let options = ActiveSetOptions {
            max_iterations: 50,
            multiplier_tolerance: 0.0,
            violation: ViolationTolerance::PerBound(1e-13),
        };
        let original = NodalBounds {
            matrix: pull.matrix(),
            rhs: &pull.rhs,
            bounds: lower,
            rotation: None,
            eliminated: &boundary,
            negated_rows: false,
        };
        let reference =
            primal_dual_active_set(&original, &mut DirectSolver::cholesky(), None, &options)
                .unwrap();
        let flipped = NodalBounds {
            matrix: negated.matrix(),
            rhs: &negated.rhs,
            negated_rows: true,
            ..original
        };
        let ldlt = || DirectSolver::ldlt(vec![-1; n + 1]);
        let s = primal_dual_active_set(&flipped, &mut ldlt(), None, &options).unwrap();
        assert_eq!(s.active, reference.active);
        assert_eq!(s.iterations, reference.iterations);
        for (a, b) in s.multipliers.iter().zip(&reference.multipliers) {
            assert!((a - b).abs() < 1e-9, "λ {a} vs {b}");
        }
        for (a, b) in s.x.iter().zip(&reference.x) {
            assert!((a - b).abs() < 1e-12, "x {a} vs {b}");
        }
        assert_kkt(pull.matrix(), &pull.rhs, lower, &s);
        // The same negated system read as a minimisation: not the solution.
        let wrong = NodalBounds {
            negated_rows: false,
            ..flipped
        };
        match primal_dual_active_set(&wrong, &mut ldlt(), None, &options) {
            Ok(w) => {
                let off =
                    w.x.iter()
                        .zip(&reference.x)
                        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                assert!(off > 1e-3, "the wrong reading found the solution ({off:e})");
            }
            Err(e) => assert!(matches!(e, SolveError::ActiveSetNotConverged { .. }), "{e}"),
        }
    }

    #[test]
    fn too_few_iterations_is_an_error_that_says_so() {
        let n = 64;
        let lap = Laplacian1d::new(n, |_| 20.0);
        let bounds: Vec<Bound> = (1..n).map(|i| Bound::new(i, Sense::Upper, 0.01)).collect();
        let problem = NodalBounds {
            matrix: lap.matrix(),
            rhs: &lap.rhs,
            bounds: Bounds::Listed(&bounds),
            rotation: None,
            eliminated: &[(0, 0.0), (n, 0.0)],
            negated_rows: false,
        };
        let options = ActiveSetOptions {
            max_iterations: 1,
            multiplier_tolerance: 0.0,
            violation: ViolationTolerance::PerBound(1e-13),
        };
        let err = primal_dual_active_set(&problem, &mut DirectSolver::cholesky(), None, &options)
            .unwrap_err();
        assert!(
            matches!(err, SolveError::ActiveSetNotConverged { iterations: 1 }),
            "{err}"
        );
    }

    /// Two vertices, two components each, a spring between them and to the ground; a bound on
    /// n·s at vertex 1 in its rotated frame holds in Cartesian components after the solve.
    #[test]
    fn rotated_bound_constrains_the_normal_component() {
        // K = [[3, 0, −1, 0], [0, 3, 0, −1], [−1, 0, 2, 0], [0, −1, 0, 2]], F pulls vertex 1 along
        // (1, 1).
        let k = [
            [3.0, 0.0, -1.0, 0.0],
            [0.0, 3.0, 0.0, -1.0],
            [-1.0, 0.0, 2.0, 0.0],
            [0.0, -1.0, 0.0, 2.0],
        ];
        let (mut col_ptr, mut row_idx, mut diag, mut values) = (vec![0], vec![], vec![], vec![]);
        for j in 0..4 {
            // Vertex-block complete: the two vertices are coupled, so all 16 entries are stored.
            for (i, row) in k.iter().enumerate() {
                if i == j {
                    diag.push(values.len());
                }
                row_idx.push(i as u32);
                values.push(row[j]);
            }
            col_ptr.push(values.len());
        }
        let matrix = Csc {
            col_ptr: &col_ptr,
            row_idx: &row_idx,
            diag: &diag,
            values: &values,
        };
        let rhs = [0.0, 0.0, 1.0, 1.0];
        let n = [std::f64::consts::FRAC_1_SQRT_2; 2];
        let rotation = Rotation {
            frames: vec![(1, n)],
        };
        let bounds = [Bound::new(2, Sense::Upper, 0.1)];
        let problem = NodalBounds {
            matrix,
            rhs: &rhs,
            bounds: Bounds::Listed(&bounds),
            rotation: Some(&rotation),
            eliminated: &[],
            negated_rows: false,
        };
        let options = ActiveSetOptions {
            max_iterations: 10,
            multiplier_tolerance: 0.0,
            violation: ViolationTolerance::PerBound(1e-13),
        };
        let s = primal_dual_active_set(&problem, &mut DirectSolver::cholesky(), None, &options)
            .unwrap();
        assert_eq!(s.active, [true]);
        let normal = n[0] * s.x[2] + n[1] * s.x[3];
        assert!((normal - 0.1).abs() < 1e-14, "n·s = {normal}");
        // Tangentially free: the residual F − Ks is along n at vertex 1 and zero at vertex 0.
        let r: Vec<f64> = matrix
            .multiply(&s.x)
            .iter()
            .zip(&rhs)
            .map(|(kx, f)| f - kx)
            .collect();
        assert!(r[0].abs() < 1e-14 && r[1].abs() < 1e-14, "{r:?}");
        assert!((r[2] - r[3]).abs() < 1e-14 && r[2] > 0.0, "{r:?}");
        assert!((s.multipliers[0] - (n[0] * r[2] + n[1] * r[3])).abs() < 1e-14);
    }
}
