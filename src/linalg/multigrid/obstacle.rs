//! Truncated nonsmooth Newton multigrid (TNNMG) for the quadratic problem with nodal bounds of
//! [`crate::linalg::active_set`]: min J(x) = ½xᵀKx − Fᵀx subject to x_d ≤ b or x_d ≥ b at the
//! bounded dofs (in the rotated frame of a [`crate::linalg::Rotation`]) and the eliminated dofs
//! (Dirichlet, hanging) at their values — the problem [`super::super::active_set::primal_dual_active_set`]
//! solves with a linear solve per active set, here by a multigrid iteration whose number of
//! iterations does not grow with the mesh.
//!
//! **Algorithm** (Gräser and Kornhuber, *Multigrid methods for obstacle problems*, J. Comput.
//! Math. 27, 2009, §4; Gräser, Sack and Sander, *Truncated nonsmooth Newton multigrid methods
//! for convex minimization problems*, DD18, 2009, Algorithm 1). One iteration from a feasible x:
//!
//! 1. *Nonlinear smoothing* ([`projected_gauss_seidel`]): on the finest level only, projected
//!    Gauss–Seidel — each dof in turn minimises J exactly along its own direction and is
//!    projected onto its bound, a forward and a backward sweep ([`TnnmgOptions::presmoothing`]
//!    pairs). Each step lowers J, so the iteration is monotone whatever the coarse correction.
//! 2. *Truncation*: the bounded dofs the smoothed iterate x̃ holds at their bound are the
//!    active set 𝒜(x̃); their rows and columns of the fine operator are cut off (the
//!    [`super::Mask`] of the linear multigrid) and so are their rows of the prolongation: the
//!    coarse levels are rebuilt ([`VCycle::build`] for the dofs outside 𝒜(x̃), the Galerkin
//!    products of the truncated prolongation) whenever 𝒜(x̃) differs from the set they were
//!    built for in more than [`TnnmgOptions::rebuild`] of the bounds (default: at any change;
//!    the active set settles after a few iterations, and then the levels are kept). With the
//!    mask alone and coarse levels of the untruncated operator the iteration converged too, but
//!    the coarse corrections of a contact zone spanning the whole face were poor.
//! 3. *Linear correction*: one V(1,1)-cycle of [`super`] (rotated frames, hybrid Gauss–Seidel,
//!    single-precision levels) for the truncated defect problem A_𝒜 v = r_𝒜 with
//!    r = F − Kx̃, or [`TnnmgOptions::correction_steps`] steps of CG preconditioned by it.
//! 4. *Projection and line search*: the correction is projected, v̄ = P(x̃ + v) − x̃ with P the
//!    projection onto the bounds, and the step along v̄ is the exact minimiser of the quadratic
//!    J(x̃ + αv̄), α* = rᵀv̄ / v̄ᵀKv̄, clipped to [0, α_max] with α_max ≥ 1 the longest feasible
//!    step (Gräser–Sack–Sander: the projected Newton direction with a line search; the energy
//!    is quadratic, so the search is explicit).
//!
//! **Start.** The iteration starts from a nested iteration on the levels (Gräser–Kornhuber,
//! §5, and Kornhuber, *Monotone multigrid methods for elliptic variational inequalities I*,
//! Numer. Math. 69, 1994, who start each level from the prolongated solution of the one below):
//! the obstacle problem of the coarsest level (its Galerkin operator, the restricted load, and
//! at each coarse dof the bound of the fine dof at the same vertex, in the same frame) is solved
//! by the primal–dual active-set method with the direct solver, and its solution prolongated and
//! projected level by level, with iterations of steps 1–4 on each level in between (the level's
//! own Galerkin operator, truncated on that level only) until the level's active set repeats
//! and its iterate moves by less than 1e-3, at most 8. Without it the iteration
//! starts from the projection of zero, and the active set has to move across the contact zone
//! one layer of vertices per iteration: on the scalar test problems 7, 10 and 15 iterations on
//! meshes of 340, 1 200 and 4 500 dofs, with it 4 on each; the contact problem of Table IV.6
//! (a strip whose free sag is 25 times the gap) did not converge in 100 iterations from zero,
//! the first projected corrections tearing the clamped contact layer from the body (α ≈ 2e-6).
//!
//! **Finish.** Once the active set after step 1 is the same in two consecutive iterations and
//! the iterate moved by less than [`TnnmgOptions::hand_over`] (relative, max norm), the active
//! set is taken as identified (Gräser–Kornhuber, Theorem 4.1: the truncated iteration turns into
//! linear multigrid on the identified set) and the linear problem on it is solved by CG
//! preconditioned by the same truncated cycle to [`TnnmgOptions::relative_tolerance`] (1e-13,
//! the linear multigrid's [`super::RELATIVE_TOLERANCE`]). Its solution is accepted if it satisfies
//! the KKT conditions — multipliers λ = σ(F − Kx)_d ≥ −[`TnnmgOptions::multiplier_tolerance`]·‖F‖∞
//! on the active bounds, violations σ(x_d − b) ≤ [`TnnmgOptions::violation_tolerance`]·(1 + |b|)
//! on the others — and otherwise projected and iterated on. This is what brings the solution to
//! the 1e-8 agreement with the primal–dual active-set method and the direct solver; the
//! iteration itself contracts the error by about an order of magnitude per step (the tests and
//! `benches/solve.rs`).
//!
//! Only minimisations: rows negated as in SubStokes ([`NodalBounds::negated_rows`]) are refused.

use rayon::prelude::*;

use super::cycle::{coarse_free_of, numbering, MaskedCycle, VCycle};
use super::sparse::Sparse;
use super::{frames_by_vertex, is_masked, Mask, Prepared, VertexHierarchy};
use crate::linalg::active_set::{
    primal_dual_active_set, ActiveSetOptions, ActiveSetSolution, Bound, Bounds, NodalBounds, Sense,
    ViolationTolerance,
};
use crate::linalg::krylov::{
    conjugate_gradient_with, CgError, Preconditioner, Stopping, VectorOps,
};
use crate::linalg::{Csc, DirectSolver, SolveError};

/// The iteration's parameters (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct TnnmgOptions {
    /// Most TNNMG iterations; an iterate still moving after them is
    /// [`SolveError::ObstacleNotConverged`].
    pub max_iterations: usize,
    /// Pairs of projected Gauss–Seidel sweeps (forward, backward) of step 1.
    pub presmoothing: usize,
    /// Step 3: 1 for one V-cycle, k > 1 for k steps of CG preconditioned by it.
    pub correction_steps: usize,
    /// The relative change (max norm) of an iteration below which, with the same active set as
    /// in the iteration before, the final linear solve is tried.
    pub hand_over: f64,
    /// Relative residual of the final linear solve on the identified active set.
    pub relative_tolerance: f64,
    /// Most CG iterations of one final linear solve.
    pub max_cg_iterations: usize,
    /// An active bound's multiplier may be this far below zero (times ‖F‖∞ of the free dofs).
    pub multiplier_tolerance: f64,
    /// An inactive bound may be violated by this much (times 1 + |b|).
    pub violation_tolerance: f64,
    /// The coarse levels are truncated anew when the active set after step 1 differs from the
    /// one they were truncated for in more than this fraction of the bounded dofs (0: at every
    /// change); in between, the finest level's mask alone truncates.
    pub rebuild: f64,
}

impl Default for TnnmgOptions {
    fn default() -> Self {
        TnnmgOptions {
            max_iterations: 100,
            presmoothing: 1,
            correction_steps: 1,
            hand_over: 1e-5,
            relative_tolerance: super::RELATIVE_TOLERANCE,
            max_cg_iterations: 500,
            multiplier_tolerance: 1e-10,
            violation_tolerance: 1e-10,
            rebuild: 0.0,
        }
    }
}

/// The solution with the work it took.
#[derive(Clone, Debug)]
pub struct ObstacleSolution {
    /// As the primal–dual active-set method returns it (x in Cartesian components, hanging dofs
    /// 0); `iterations` counts TNNMG iterations.
    pub solution: ActiveSetSolution,
    pub work: TnnmgWork,
}

/// What a TNNMG solve did beside its iterations.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TnnmgWork {
    /// CG iterations of the final linear solves (module docs, *Finish*).
    pub cg_iterations: usize,
    /// Final linear solves tried (1 unless the KKT check sent the iteration on).
    pub final_solves: usize,
    /// Times the coarse levels were rebuilt for a new active set (step 2).
    pub coarse_rebuilds: usize,
    /// The last iteration whose active set (after step 1) differed from the one before: the
    /// iterations it took to identify the active set.
    pub settled_after: usize,
}

/// The problem on the dofs of one level: on the finest, the block of the dofs that are not
/// eliminated (its matrix in double precision); on a coarser one (the nested start), the level's
/// Galerkin operator as the cycle applies it (single precision).
struct Block<'a, T = f64> {
    a: &'a Sparse<T>,
    inverse_diagonal: Vec<f64>,
    /// The load (on the finest level with the eliminated values moved to the right).
    b: Vec<f64>,
    /// Bounds per dof (±∞ where there is none).
    lower: Vec<f64>,
    upper: Vec<f64>,
}

impl<T: Copy + Into<f64> + Send + Sync> Block<'_, T> {
    /// P(y): the projection onto the bounds of dof `i` (no panic on NaN, unlike `clamp`).
    #[inline]
    fn project(&self, i: usize, y: f64) -> f64 {
        y.max(self.lower[i]).min(self.upper[i])
    }

    /// r = b − A x.
    fn residual(&self, x: &[f64], r: &mut [f64]) {
        self.a.multiply_into(x, r);
        r.par_iter_mut().zip(&self.b).for_each(|(r, b)| *r = b - *r);
    }

    /// Whether dof `i` of the iterate `x` sits on one of its bounds.
    #[inline]
    fn at_bound(&self, i: usize, x: &[f64]) -> bool {
        x[i] == self.lower[i] || x[i] == self.upper[i]
    }
}

/// Step 1 of the module docs: one projected Gauss–Seidel sweep, forward or `backward` — dof i
/// moves to the minimiser of J along e_i, x_i + (b − Ax)_i / a_ii, projected onto its bounds.
fn projected_gauss_seidel<T: Copy + Into<f64> + Send + Sync>(
    block: &Block<'_, T>,
    x: &mut [f64],
    backward: bool,
) {
    let a = block.a.rows();
    let mut visit = |i: usize| {
        let (c, v) = a.row(i);
        let s = Sparse::<T>::dot(c, v, x);
        let y = x[i] + (block.b[i] - s) * block.inverse_diagonal[i];
        x[i] = block.project(i, y);
    };
    let n = block.b.len();
    if backward {
        (0..n).rev().for_each(&mut visit);
    } else {
        (0..n).for_each(&mut visit);
    }
}

/// The vectors of the iterations on one level.
struct Vectors {
    r: Vec<f64>,
    v: Vec<f64>,
    av: Vec<f64>,
    start: Vec<f64>,
}

impl Vectors {
    fn new(n: usize) -> Vectors {
        Vectors {
            r: vec![0.0; n],
            v: vec![0.0; n],
            av: vec![0.0; n],
            start: vec![0.0; n],
        }
    }
}

/// Step 3 for the truncation `active` (true: masked): the correction v of the defect r (zero
/// on the active dofs).
type Correction<'c> = dyn FnMut(&[bool], &[f64], &mut [f64]) -> Result<(), SolveError> + 'c;

/// Steps 1–4 of the module docs on `block` from x; `active` receives the truncation. Returns
/// the relative change of x (max norm) and the step length α.
fn iterate<T: Copy + Into<f64> + Send + Sync>(
    block: &Block<'_, T>,
    x: &mut [f64],
    active: &mut [bool],
    w: &mut Vectors,
    presmoothing: usize,
    correct: &mut Correction<'_>,
) -> Result<(f64, f64), SolveError> {
    let n = x.len();
    w.start.copy_from_slice(x);
    // (1) nonlinear smoothing
    for _ in 0..presmoothing {
        projected_gauss_seidel(block, x, false);
        projected_gauss_seidel(block, x, true);
    }
    // (2) truncation
    active
        .par_iter_mut()
        .enumerate()
        .for_each(|(i, a)| *a = block.at_bound(i, x));
    block.residual(x, &mut w.r);
    for (r, &a) in w.r.iter_mut().zip(active.iter()) {
        if a {
            *r = 0.0;
        }
    }
    // (3) linear correction on the truncated problem
    correct(active, &w.r, &mut w.v)?;
    // (4) projection and line search
    let v = &mut w.v;
    let mut longest = f64::INFINITY;
    for i in 0..n {
        v[i] = block.project(i, x[i] + v[i]) - x[i];
        if v[i] > 0.0 && block.upper[i].is_finite() {
            longest = longest.min((block.upper[i] - x[i]) / v[i]);
        } else if v[i] < 0.0 && block.lower[i].is_finite() {
            longest = longest.min((block.lower[i] - x[i]) / v[i]);
        }
    }
    block.a.multiply_into(v, &mut w.av);
    let (slope, curvature) = (dot(&w.r, v), dot(v, &w.av));
    let alpha = if curvature > 0.0 {
        (slope / curvature).min(longest).max(0.0)
    } else {
        0.0
    };
    for i in 0..n {
        x[i] = block.project(i, x[i] + alpha * v[i]);
    }
    let scale = max_abs(x);
    let moved = x
        .iter()
        .zip(&w.start)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    let change = if scale > 0.0 { moved / scale } else { moved };
    Ok((change, alpha))
}

/// Step 3: the correction v of the truncated defect problem A_𝒜 v = r (r zero on the masked
/// rows), one cycle or `steps` CG steps preconditioned by it.
fn linear_correction(
    block: &Block<'_>,
    cycle: &MaskedCycle<'_>,
    r: &[f64],
    v: &mut [f64],
    steps: usize,
) -> Result<(), SolveError> {
    if steps <= 1 {
        cycle.apply(r, v);
        return Ok(());
    }
    v.fill(0.0);
    let stopping = Stopping {
        relative: 0.0,
        absolute: 0.0,
        max_iterations: steps,
    };
    let mask = cycle.mask;
    match conjugate_gradient_with(
        VectorOps::Chunked,
        |u, out| block.a.multiply_masked(u, out, mask),
        r,
        v,
        cycle,
        stopping,
    ) {
        Ok(_) | Err(CgError::NotConverged { .. }) => Ok(()),
        Err(e) => Err(SolveError::from(e)),
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn max_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

/// The truncated nonsmooth Newton multigrid method (module docs) on the level hierarchy of the
/// mesh (`n_components` dofs per vertex), from the projection of zero.
pub fn truncated_nonsmooth_newton_multigrid(
    problem: &NodalBounds<'_>,
    hierarchy: &VertexHierarchy,
    n_components: usize,
    options: &TnnmgOptions,
) -> Result<ObstacleSolution, SolveError> {
    if problem.negated_rows {
        return Err(SolveError::Iterative(
            "the truncated nonsmooth Newton multigrid minimises: negated rows are not supported"
                .into(),
        ));
    }
    SolveError::check_data(problem.rhs)?;
    let (values, rhs) = {
        let mut k = problem.matrix.values.to_vec();
        let mut f = problem.rhs.to_vec();
        if let Some(rotation) = problem.rotation {
            rotation.apply(problem.matrix, &mut k, &mut f);
        }
        (k, f)
    };
    let matrix = problem.matrix.with_values(&values);
    let n = matrix.n();
    let mut full = vec![0.0; n];
    let mut rows = vec![true; n];
    for &(d, v) in problem.eliminated {
        rows[d] = false;
        full[d] = v;
    }
    let rotated = problem.rotation.map_or(&[][..], |r| &r.frames[..]);
    let frames = frames_by_vertex(rotated, n / n_components);
    let Prepared {
        rows,
        dofs,
        block: a,
        mut cycle,
        ..
    } = Prepared::build(matrix, rows.clone(), rows, hierarchy, n_components, &frames)?;
    let index = numbering(&rows);
    let dofs = &dofs;
    let nb = dofs.len();
    let a = &a;
    let (rows, full_ref) = (&rows, &full);
    let b: Vec<f64> = dofs
        .par_iter()
        .map(|&d| {
            let eliminated_part: f64 = (matrix.col_ptr[d]..matrix.col_ptr[d + 1])
                .filter(|&p| !rows[matrix.row_idx[p] as usize])
                .map(|p| matrix.values[p] * full_ref[matrix.row_idx[p] as usize])
                .sum();
            rhs[d] - eliminated_part
        })
        .collect();
    let (mut lower, mut upper) = (vec![f64::NEG_INFINITY; nb], vec![f64::INFINITY; nb]);
    for bound in problem.bounds.iter() {
        let i = index[bound.dof()];
        if i == usize::MAX {
            continue;
        }
        match bound.sense {
            Sense::Upper => upper[i] = upper[i].min(bound.value),
            Sense::Lower => lower[i] = lower[i].max(bound.value),
        }
    }
    if let Some(i) =
        (0..nb).find(|&i| lower[i] > upper[i] || lower[i].is_nan() || upper[i].is_nan())
    {
        return Err(SolveError::Iterative(format!(
            "the bounds of dof {} leave no feasible value ({} ≤ x ≤ {})",
            dofs[i], lower[i], upper[i]
        )));
    }
    let inverse_diagonal = a
        .diagonal_positions()
        .iter()
        .map(|&p| 1.0 / a.vals[p])
        .collect();
    let block = Block {
        a,
        inverse_diagonal,
        b,
        lower,
        upper,
    };
    let load_scale = max_abs(&block.b);
    let mut x = nested_start(
        &block,
        &cycle,
        hierarchy,
        n_components,
        rows,
        &index,
        options.presmoothing,
    );
    let mut w = Vectors::new(nb);
    let mut active = vec![false; nb];
    let mut previous: Option<Vec<bool>> = None;
    // The active set the coarse levels are truncated for (none at first).
    let mut truncated_for = vec![false; nb];
    let n_bounded = (0..nb)
        .filter(|&i| block.lower[i].is_finite() || block.upper[i].is_finite())
        .count();
    let (mut cg_iterations, mut final_solves, mut coarse_rebuilds) = (0, 0, 0);
    let mut settled_after = 0;
    for iteration in 1..=options.max_iterations {
        let mut correct = |active: &[bool], r: &[f64], v: &mut [f64]| {
            let changed = active
                .par_iter()
                .zip(&truncated_for)
                .filter(|(a, b)| a != b)
                .count();
            if changed > 0 && changed as f64 > options.rebuild * n_bounded as f64 {
                // The truncated prolongation: no coarse correction at the active dofs, and the
                // coarse operators its Galerkin products.
                let mut coarse_free = rows.clone();
                for (&d, &a) in dofs.iter().zip(active) {
                    coarse_free[d] = !a;
                }
                cycle = VCycle::build(hierarchy, n_components, &frames, a, rows, &coarse_free)?;
                truncated_for.copy_from_slice(active);
                coarse_rebuilds += 1;
            }
            let truncated = MaskedCycle {
                cycle: &cycle,
                mask: active.contains(&true).then_some(active),
            };
            linear_correction(&block, &truncated, r, v, options.correction_steps)
        };
        let (change, alpha) = iterate(
            &block,
            &mut x,
            &mut active,
            &mut w,
            options.presmoothing,
            &mut correct,
        )?;
        if !change.is_finite() || !alpha.is_finite() {
            return Err(SolveError::IterativeNonFinite(iteration));
        }
        let settled = previous.as_ref() == Some(&active);
        if !settled {
            settled_after = iteration;
        }
        previous = Some(active.clone());
        if settled && change <= options.hand_over {
            final_solves += 1;
            let mask: Mask = active.contains(&true).then_some(&active[..]);
            cg_iterations += solve_on_active_set(&block, &cycle, mask, &mut x, options)?;
            block.residual(&x, &mut w.r);
            if satisfies_kkt(&block, &active, &x, &w.r, load_scale, options) {
                let solution = finish(problem, matrix, &rhs, dofs, full, &x, iteration);
                return Ok(ObstacleSolution {
                    solution,
                    work: TnnmgWork {
                        cg_iterations,
                        final_solves,
                        coarse_rebuilds,
                        settled_after,
                    },
                });
            }
            for (i, x) in x.iter_mut().enumerate() {
                *x = block.project(i, *x);
            }
            previous = None;
        }
        if iteration == options.max_iterations {
            return Err(SolveError::ObstacleNotConverged {
                iterations: iteration,
                change,
            });
        }
    }
    Err(SolveError::ObstacleNotConverged {
        iterations: 0,
        change: f64::INFINITY,
    })
}

/// The initial iterate by nested iteration (module docs, *Start*). The levels of `cycle` (built
/// for the whole block) carry the obstacle problems: their Galerkin operators, the load
/// restricted to them, and at each coarse dof the bounds of the finest dof at the same vertex
/// (in the same frame). The coarsest is solved by the primal–dual active-set method with the
/// direct solver; its solution is prolongated and projected level by level, each level iterated
/// on by at most [`NESTED_ITERATIONS`] iterations of steps 1–4 with the cycle below it (truncated on the
/// level only), to the finest level. The projection of zero where the coarse problem fails (it
/// is only a start).
fn nested_start(
    block: &Block<'_>,
    cycle: &VCycle,
    hierarchy: &VertexHierarchy,
    nc: usize,
    rows: &[bool],
    index: &[usize],
    presmoothing: usize,
) -> Vec<f64> {
    let nb = block.b.len();
    let zero = || (0..nb).map(|i| block.project(i, 0.0)).collect();
    let top = cycle.levels.len() - 1;
    if top == 0 {
        // A mesh of one level: the coarsest problem is the finest, in double precision.
        let a = block.a;
        return coarsest_solution(a.rows(), a.vals.clone(), block)
            .map_or_else(zero, |x| (0..nb).map(|i| block.project(i, x[i])).collect());
    }
    if hierarchy.transfers.len() != top {
        return zero();
    }
    // For each level, coarsest first, the finest block dof at the position of each of its
    // free dofs.
    let mut block_of: Vec<Vec<usize>> = Vec::with_capacity(top);
    let mut finest: Vec<usize> = (0..rows.len()).collect();
    let mut free = rows.to_vec();
    for t in hierarchy.transfers.iter().rev() {
        let coarse_free = coarse_free_of(t, nc, &free);
        finest = (0..t.n_coarse * nc)
            .map(|d| finest[t.fine_of_coarse[d / nc] as usize * nc + d % nc])
            .collect();
        block_of.push(
            (0..coarse_free.len())
                .filter(|&d| coarse_free[d])
                .map(|d| index[finest[d]])
                .collect(),
        );
        free = coarse_free;
    }
    block_of.reverse();
    // The load restricted level by level, coarsest first.
    let mut loads = vec![block.b.clone()];
    for k in (1..=top).rev() {
        let Some((_, pt)) = &cycle.levels[k].p else {
            return zero();
        };
        let mut coarse = vec![0.0; pt.n_rows()];
        pt.multiply_into(&loads[loads.len() - 1], &mut coarse);
        loads.push(coarse);
    }
    loads.reverse();
    for (level, at) in cycle.levels.iter().zip(&block_of) {
        if level.a.n_rows() != at.len() || at.contains(&usize::MAX) {
            return zero();
        }
    }
    let level_block = |k: usize| {
        let level = &cycle.levels[k];
        Block {
            a: &level.a,
            inverse_diagonal: level.inverse_diagonal.clone(),
            b: loads[k].clone(),
            lower: block_of[k].iter().map(|&i| block.lower[i]).collect(),
            upper: block_of[k].iter().map(|&i| block.upper[i]).collect(),
        }
    };
    // The coarsest level: the primal–dual active-set method.
    let coarsest = level_block(0);
    let a = coarsest.a;
    let values: Vec<f64> = a.vals.iter().map(|&v| f64::from(v)).collect();
    let Some(coarse) = coarsest_solution(a.rows(), values, &coarsest) else {
        return zero();
    };
    let mut z = coarse;
    for k in 1..=top {
        let Some((p, _)) = &cycle.levels[k].p else {
            return zero();
        };
        let mut fine = vec![0.0; p.n_rows()];
        p.multiply_into(&z, &mut fine);
        z = fine;
        if k == top {
            break;
        }
        let level = level_block(k);
        for (i, z) in z.iter_mut().enumerate() {
            *z = level.project(i, *z);
        }
        let n = z.len();
        let (mut active, mut w) = (vec![false; n], Vectors::new(n));
        let mut previous = vec![false; n];
        for _ in 0..NESTED_ITERATIONS {
            let mut correct = |active: &[bool], r: &[f64], v: &mut [f64]| {
                let mut work = cycle.work.borrow_mut();
                let mask: Mask = active.contains(&true).then_some(active);
                cycle.cycle(k, &mut work, Some((r, v)), mask);
                Ok(())
            };
            match iterate(
                &level,
                &mut z,
                &mut active,
                &mut w,
                presmoothing,
                &mut correct,
            ) {
                Ok((change, _)) if change.is_finite() => {
                    if active == previous && change <= NESTED_TOLERANCE {
                        break;
                    }
                }
                _ => return zero(),
            }
            previous.clone_from(&active);
        }
    }
    if z.len() != nb || z.iter().any(|v| !v.is_finite()) {
        return zero();
    }
    z.iter()
        .enumerate()
        .map(|(i, &v)| block.project(i, v))
        .collect()
}

/// The obstacle problem of `level` (its matrix the `rows` with the `values` in double
/// precision) solved by the primal–dual active-set method with the direct solver (`None` if
/// that fails).
fn coarsest_solution<T: Copy + Into<f64> + Send + Sync>(
    rows: super::sparse::Rows<'_, T>,
    values: Vec<f64>,
    level: &Block<'_, T>,
) -> Option<Vec<f64>> {
    let n = level.b.len();
    let diag: Vec<usize> = (0..n)
        .map(|i| {
            let (c, _) = rows.row(i);
            rows.row_ptr[i] + c.partition_point(|&j| (j as usize) < i)
        })
        .collect();
    let matrix = Csc {
        col_ptr: rows.row_ptr,
        row_idx: rows.cols,
        diag: &diag,
        values: &values,
    };
    let mut bounds = Vec::new();
    for j in 0..n {
        if level.upper[j].is_finite() {
            bounds.push(Bound::new(j, Sense::Upper, level.upper[j]));
        }
        if level.lower[j].is_finite() {
            bounds.push(Bound::new(j, Sense::Lower, level.lower[j]));
        }
    }
    let problem = NodalBounds {
        matrix,
        rhs: &level.b,
        bounds: Bounds::Listed(&bounds),
        rotation: None,
        eliminated: &[],
        negated_rows: false,
    };
    let options = ActiveSetOptions {
        max_iterations: 100,
        multiplier_tolerance: 0.0,
        violation: ViolationTolerance::PerBound(1e-13),
    };
    primal_dual_active_set(&problem, &mut DirectSolver::cholesky(), None, &options)
        .ok()
        .map(|s| s.x)
}

/// Most iterations of steps 1–4 on each level between the coarsest and the finest in the
/// nested start ([`nested_start`]); fewer once the level's active set repeats and its iterate
/// moves by less than [`NESTED_TOLERANCE`] (relative, max norm).
const NESTED_ITERATIONS: usize = 8;

/// See [`NESTED_ITERATIONS`].
const NESTED_TOLERANCE: f64 = 1e-3;

/// The linear problem of the active set `mask` (its dofs fixed where x holds them) solved by CG
/// preconditioned by the truncated cycle, from x (module docs, *Finish*); returns the CG
/// iterations.
fn solve_on_active_set(
    block: &Block<'_>,
    cycle: &VCycle,
    mask: Mask,
    x: &mut [f64],
    options: &TnnmgOptions,
) -> Result<usize, SolveError> {
    let nb = x.len();
    // The load of the truncated problem, b − A(x on the active dofs), on the free rows: its norm
    // sets the tolerance as in a linear solve of that set.
    let fixed: Vec<f64> = (0..nb)
        .map(|i| if is_masked(mask, i) { x[i] } else { 0.0 })
        .collect();
    let mut load = vec![0.0; nb];
    block.residual(&fixed, &mut load);
    let mut r = vec![0.0; nb];
    block.residual(x, &mut r);
    for i in 0..nb {
        if is_masked(mask, i) {
            load[i] = 0.0;
            r[i] = 0.0;
        }
    }
    let stopping = Stopping {
        relative: 0.0,
        absolute: options.relative_tolerance * dot(&load, &load).sqrt(),
        max_iterations: options.max_cg_iterations,
    };
    let cycle = MaskedCycle { cycle, mask };
    let mut delta = vec![0.0; nb];
    let report = conjugate_gradient_with(
        VectorOps::Chunked,
        |u, out| block.a.multiply_masked(u, out, mask),
        &r,
        &mut delta,
        &cycle,
        stopping,
    )
    .map_err(SolveError::from)?;
    for (x, d) in x.iter_mut().zip(&delta) {
        *x += d;
    }
    if x.iter().any(|v| !v.is_finite()) {
        return Err(SolveError::IterativeNonFinite(report.iterations));
    }
    Ok(report.iterations)
}

/// The KKT conditions of the bounds at x with r = b − Ax (module docs, *Finish*).
fn satisfies_kkt(
    block: &Block<'_>,
    active: &[bool],
    x: &[f64],
    r: &[f64],
    load_scale: f64,
    options: &TnnmgOptions,
) -> bool {
    let multiplier_floor = -options.multiplier_tolerance * load_scale;
    (0..x.len()).into_par_iter().all(|i| {
        let (lo, up) = (block.lower[i], block.upper[i]);
        if active[i] {
            // λ = σr_i: σ = +1 at an upper bound, −1 at a lower one.
            let lambda = if x[i] == up { r[i] } else { -r[i] };
            lambda >= multiplier_floor
        } else {
            let tol = |b: f64| options.violation_tolerance * (1.0 + b.abs());
            (!up.is_finite() || x[i] - up <= tol(up)) && (!lo.is_finite() || lo - x[i] <= tol(lo))
        }
    })
}

/// The solution of the primal–dual active-set method's form from the block iterate x.
fn finish(
    problem: &NodalBounds<'_>,
    matrix: crate::linalg::Csc<'_>,
    rhs: &[f64],
    dofs: &[usize],
    mut full: Vec<f64>,
    x: &[f64],
    iterations: usize,
) -> ActiveSetSolution {
    for (&d, &v) in dofs.iter().zip(x) {
        full[d] = v;
    }
    let kx = matrix.multiply(&full);
    let in_block: Vec<bool> = {
        let mut b = vec![false; full.len()];
        for &d in dofs {
            b[d] = true;
        }
        b
    };
    let bounds = problem.bounds;
    let active = bounds
        .iter()
        .map(|b| in_block[b.dof()] && full[b.dof()] == b.value)
        .collect();
    let multipliers = bounds
        .iter()
        .map(|b| b.sense.sign() * (rhs[b.dof()] - kx[b.dof()]))
        .collect();
    let slack = bounds
        .iter()
        .map(|b| b.sense.sign() * (b.value - full[b.dof()]))
        .collect();
    if let Some(rotation) = problem.rotation {
        rotation.to_cartesian(&mut full);
    }
    ActiveSetSolution {
        x: full,
        active,
        multipliers,
        slack,
        iterations,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::hierarchy::tests::{assembled, graded_mesh};
    use crate::fe::hierarchy::vertex_hierarchy;
    use crate::fe::System;
    use crate::linalg::active_set::{
        primal_dual_active_set, ActiveSetOptions, Bound, Bounds, ViolationTolerance,
    };
    use crate::linalg::{DirectSolver, Rotation};
    use crate::mesh::Mesh;

    /// The reference: the primal–dual active-set method with the direct solver, at the
    /// tolerances of the contact solves.
    fn reference(problem: &NodalBounds<'_>) -> ActiveSetSolution {
        let options = ActiveSetOptions {
            max_iterations: 200,
            multiplier_tolerance: 0.0,
            violation: ViolationTolerance::PerBound(1e-13),
        };
        primal_dual_active_set(problem, &mut DirectSolver::cholesky(), None, &options)
            .expect("the active-set method converges")
    }

    /// The same active set (some bounds active, some not) and the solution within 1e-8
    /// relative (max norm); returns the TNNMG iterations.
    fn assert_agrees(problem: &NodalBounds<'_>, system: &System, mesh: &Mesh) -> usize {
        let direct = reference(problem);
        let hierarchy = vertex_hierarchy(mesh, &system.dofs.vertices);
        let n_components = system.dofs.n_components;
        let t = truncated_nonsmooth_newton_multigrid(
            problem,
            &hierarchy,
            n_components,
            &TnnmgOptions::default(),
        )
        .expect("TNNMG converges");
        let active = direct.active.iter().filter(|&&a| a).count();
        eprintln!(
            "{} dofs, {active} of {} bounds active: TNNMG {} iterations (active set settled \
             after {}, {} coarse rebuilds, {} final CG iterations), active set {} iterations",
            system.dofs.n_dofs(),
            direct.active.len(),
            t.solution.iterations,
            t.work.settled_after,
            t.work.coarse_rebuilds,
            t.work.cg_iterations,
            direct.iterations
        );
        assert!(
            active > 0 && active < direct.active.len(),
            "{active} of {} bounds active",
            direct.active.len()
        );
        assert_eq!(t.solution.active, direct.active, "active sets differ");
        let scale = max_abs(&direct.x);
        let diff = direct
            .x
            .iter()
            .zip(&t.solution.x)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(
            diff <= 1e-8 * scale,
            "max |Δx| = {diff:e} of {scale:e} ({} iterations)",
            t.solution.iterations
        );
        for (a, b) in t.solution.multipliers.iter().zip(&direct.multipliers) {
            assert!((a - b).abs() <= 1e-7 * (1.0 + b.abs()), "λ {a} vs {b}");
        }
        assert_eq!(t.work.final_solves, 1, "the first final solve is accepted");
        t.solution.iterations
    }

    /// The free (not eliminated) dofs of a system.
    fn free_dofs(system: &System) -> Vec<usize> {
        let mut free = vec![true; system.dofs.n_dofs()];
        for (d, _) in system.constraints.eliminated() {
            free[d] = false;
        }
        (0..free.len()).filter(|&d| free[d]).collect()
    }

    /// −Δu + ½u = 1 (u = 0 on the left, 1 on the right) under an obstacle from above and one
    /// from below, on graded meshes of about 2 000 to 30 000 dofs with hanging vertices on every
    /// level: the active sets and solutions of the primal–dual active-set method, in a number of
    /// TNNMG iterations that does not grow with the mesh.
    #[test]
    fn scalar_obstacles_agree_with_the_active_set_method_in_bounded_iterations() {
        let mut counts = Vec::new();
        for extra in [0, 1, 2] {
            let mut mesh = graded_mesh(4);
            for _ in 0..extra {
                mesh.refine_global().unwrap();
            }
            let system = assembled(&mesh, 1, 0.5);
            let coords = &system.dofs.vertices.coords;
            let free = free_dofs(&system);
            let upper: Vec<Bound> = free
                .iter()
                .map(|&d| {
                    let [x, y] = coords[d];
                    Bound::new(d, Sense::Upper, 0.3 + 0.2 * x * (1.0 - y))
                })
                .collect();
            let lower: Vec<Bound> = free
                .iter()
                .map(|&d| {
                    let [x, y] = coords[d];
                    let bump = 0.8 - 3.0 * (x - 0.6).powi(2) - 3.0 * (y - 0.5).powi(2);
                    Bound::new(d, Sense::Lower, bump)
                })
                .collect();
            let eliminated = system.constraints.eliminated();
            for bounds in [&upper, &lower] {
                let problem = NodalBounds {
                    matrix: system.matrix(),
                    rhs: &system.rhs,
                    bounds: Bounds::Listed(bounds),
                    rotation: None,
                    eliminated: &eliminated,
                    negated_rows: false,
                };
                let k = assert_agrees(&problem, &system, &mesh);
                counts.push((system.dofs.n_dofs(), k));
            }
        }
        let (lo, hi) = counts
            .iter()
            .fold((usize::MAX, 0), |(lo, hi), &(_, k)| (lo.min(k), hi.max(k)));
        assert!(hi <= lo + lo / 2 + 2, "(dofs, iterations): {counts:?}");
        assert!(
            counts[4].0 > 10 * counts[0].0,
            "(dofs, iterations): {counts:?}"
        );
    }

    /// Two components per vertex, the upper half rotated into turning frames (as the contact
    /// solves rotate their vertices) and a bound on each rotated vertex's normal component.
    #[test]
    fn rotated_bounds_agree_with_the_active_set_method() {
        let mesh = graded_mesh(5);
        let system = assembled(&mesh, 2, 0.5);
        let vertices = &system.dofs.vertices;
        let eliminated = system.constraints.eliminated();
        let mut fixed = vec![false; system.dofs.n_dofs()];
        for &(d, _) in &eliminated {
            fixed[d] = true;
        }
        let frames: Vec<(u32, [f64; 2])> = (0..vertices.len())
            .filter(|&v| {
                let y = vertices.coords[v][1];
                y >= 0.5 && !fixed[2 * v] && !fixed[2 * v + 1]
            })
            .map(|v| {
                let [x, y] = vertices.coords[v];
                let angle = 0.3 + 0.5 * x + 0.5 * y;
                (v as u32, [angle.cos(), angle.sin()])
            })
            .collect();
        let bounds: Vec<Bound> = frames
            .iter()
            .map(|&(v, _)| {
                let x = vertices.coords[v as usize][0];
                Bound::new(2 * v as usize, Sense::Upper, 0.25 + 0.1 * x)
            })
            .collect();
        let rotation = Rotation { frames };
        let problem = NodalBounds {
            matrix: system.matrix(),
            rhs: &system.rhs,
            bounds: Bounds::Listed(&bounds),
            rotation: Some(&rotation),
            eliminated: &eliminated,
            negated_rows: false,
        };
        assert_agrees(&problem, &system, &mesh);
    }

    /// The contact problem of Table IV.6 (z-contact) and of IV.12 (Signorini, linearised about
    /// the z-solution, so that the frames turn with the deformed face) on a mesh refined
    /// globally twice and towards the contact face.
    #[test]
    fn contact_agrees_with_the_active_set_method() {
        use crate::models::contact::{
            contact_boundaries, contact_bounds, contact_problem, solve_contact, ConstraintBuilder,
            ContactModel,
        };
        use crate::models::elasticity::Elasticity;
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let iv6 = crate::experiment::load(&dir.join("experiments").join("IV.6.toml")).unwrap();
        let crate::experiment::Problem::Contact {
            elasticity,
            contact,
        } = &iv6.problem
        else {
            panic!("IV.6 is contact")
        };
        let domain = &iv6.scene.domain;
        let [cx, cy] = iv6.scene.coarse_cells;
        let mut mesh = Mesh::new(domain.x, domain.y, cx, cy);
        mesh.refine_global().unwrap();
        mesh.refine_global().unwrap();
        let near: Vec<bool> = mesh
            .active()
            .iter()
            .map(|&c| mesh.cell_box(c)[1] < 0.2)
            .collect();
        let none = vec![false; near.len()];
        mesh.refine_and_coarsen(&near, &none).unwrap();
        let model = Elasticity::from(elasticity);
        let mut system = System::new(&mesh, 2);
        model.constrain(&mut system);
        model.assemble(&mesh, &mut system);
        let boundaries = contact_boundaries(contact);
        let z_faces = |_| ContactModel::Z;
        let z = ConstraintBuilder {
            boundaries: &boundaries,
            face_model: &z_faces,
        }
        .build(&system.dofs, &system.constraints, None)
        .unwrap();
        let z_solution = solve_contact(&system, &mut DirectSolver::cholesky(), &z, None).unwrap();
        let signorini_faces = |_| ContactModel::Signorini;
        let signorini = ConstraintBuilder {
            boundaries: &boundaries,
            face_model: &signorini_faces,
        }
        .build(&system.dofs, &system.constraints, Some(&z_solution.u))
        .unwrap();
        let eliminated = system.constraints.eliminated();
        for constraints in [&z, &signorini] {
            let (rotation, bounds) = contact_bounds(&system, constraints);
            let problem = contact_problem(&system, &rotation, &bounds, &eliminated);
            assert_agrees(&problem, &system, &mesh);
        }
    }

    /// Too few iterations, or negated rows, are errors that say so; no NaN leaves the solver.
    #[test]
    fn failures_are_errors() {
        let mesh = graded_mesh(4);
        let system = assembled(&mesh, 1, 0.5);
        let free = free_dofs(&system);
        let bounds: Vec<Bound> = free
            .iter()
            .map(|&d| Bound::new(d, Sense::Upper, 0.2))
            .collect();
        let eliminated = system.constraints.eliminated();
        let problem = NodalBounds {
            matrix: system.matrix(),
            rhs: &system.rhs,
            bounds: Bounds::Listed(&bounds),
            rotation: None,
            eliminated: &eliminated,
            negated_rows: false,
        };
        let hierarchy = vertex_hierarchy(&mesh, &system.dofs.vertices);
        let options = TnnmgOptions {
            max_iterations: 2,
            ..TnnmgOptions::default()
        };
        let err =
            truncated_nonsmooth_newton_multigrid(&problem, &hierarchy, 1, &options).unwrap_err();
        assert!(
            matches!(err, SolveError::ObstacleNotConverged { iterations: 2, .. }),
            "{err}"
        );
        let negated = NodalBounds {
            negated_rows: true,
            ..problem
        };
        let err =
            truncated_nonsmooth_newton_multigrid(&negated, &hierarchy, 1, &TnnmgOptions::default())
                .unwrap_err();
        assert!(matches!(err, SolveError::Iterative(_)), "{err}");
        let mut rhs = system.rhs.clone();
        rhs[free[0]] = f64::NAN;
        let poisoned = NodalBounds {
            rhs: &rhs,
            ..problem
        };
        let err = truncated_nonsmooth_newton_multigrid(
            &poisoned,
            &hierarchy,
            1,
            &TnnmgOptions::default(),
        )
        .unwrap_err();
        assert!(matches!(err, SolveError::NonFiniteData(_)), "{err}");
    }
}
