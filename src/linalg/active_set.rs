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

use std::borrow::Cow;

use super::{Csc, DirectSolver};

/// Whether a bound is an upper (x_d ≤ value) or a lower one (x_d ≥ value).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sense {
    Upper,
    Lower,
}

impl Sense {
    #[inline]
    fn sign(self) -> f64 {
        match self {
            Sense::Upper => 1.0,
            Sense::Lower => -1.0,
        }
    }
}

/// A bound on one dof (of the rotated system where a [`Rotation`] is given).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bound {
    pub dof: usize,
    pub value: f64,
    pub sense: Sense,
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
                let j = ri[q];
                let p0 = matrix.position(i0, j).expect("symmetric pattern");
                debug_assert_eq!(ri[p0 + 1], i0 + 1);
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

/// Writes the eliminated dofs (fixed and hanging) followed by an overlay into a vector
/// ([`crate::fe::Constraints::eliminated_with`]).
pub type Eliminated<'a> = &'a (dyn Fn(&[(usize, f64)], &mut Vec<(usize, f64)>) + Sync);

/// The problem: the matrix and load (Cartesian), the bounds, an optional rotation, and the
/// eliminated dofs with an overlay.
pub struct NodalBounds<'a> {
    pub matrix: Csc<'a>,
    pub rhs: &'a [f64],
    pub bounds: &'a [Bound],
    pub rotation: Option<&'a Rotation>,
    pub eliminated: Eliminated<'a>,
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
    solver: &mut DirectSolver,
    initial: Option<&[bool]>,
    options: &ActiveSetOptions,
) -> Result<ActiveSetSolution, String> {
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
    let diag = matrix.diagonal();
    let bounds = problem.bounds;
    let mut active: Vec<bool> = match initial {
        Some(a) if a.len() == bounds.len() => a.to_vec(),
        _ => vec![false; bounds.len()],
    };
    let mut eliminated = Vec::new();
    let mut overlay = Vec::new();
    let mut iterations = 0;
    loop {
        iterations += 1;
        overlay.clear();
        overlay.extend(
            bounds
                .iter()
                .zip(&active)
                .filter(|(_, &a)| a)
                .map(|(b, _)| (b.dof, b.value)),
        );
        (problem.eliminated)(&overlay, &mut eliminated);
        let x = solver
            .solve(matrix, &rhs, &eliminated)
            .map_err(|e| e.to_string())?;
        let kx = matrix.multiply(&x);
        let multipliers: Vec<f64> = bounds
            .iter()
            .map(|b| b.sense.sign() * (rhs[b.dof] - kx[b.dof]))
            .collect();
        let scale = match options.violation {
            ViolationTolerance::SolutionScale(_) => x.iter().fold(0.0f64, |m, v| m.max(v.abs())),
            ViolationTolerance::PerBound(_) => 0.0,
        };
        let next: Vec<bool> = bounds
            .iter()
            .zip(&active)
            .zip(&multipliers)
            .map(|((b, &is_active), &lambda)| {
                if is_active {
                    lambda > -options.multiplier_tolerance
                } else {
                    let tol = match options.violation {
                        ViolationTolerance::PerBound(f) => f * (1.0 + b.value.abs()),
                        ViolationTolerance::SolutionScale(f) => f * scale,
                    };
                    let d = diag[b.dof];
                    // σ(x − b) beyond rounding (scaled by the diagonal, as the iteration's
                    // c·(x − b) with c = K_dd)
                    d * (b.sense.sign() * (x[b.dof] - b.value)) > d * tol
                }
            })
            .collect();
        if next == active {
            let slack = bounds
                .iter()
                .map(|b| b.sense.sign() * (b.value - x[b.dof]))
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
            return Err(format!(
                "the primal–dual active-set method did not converge: the active set still changed \
                 after {iterations} iterations (the limit)"
            ));
        }
        active = next;
    }
}
