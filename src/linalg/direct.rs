//! Sparse direct solvers (faer): Cholesky LLᵀ for the SPD systems of elasticity, contact and
//! Reynolds, and LDLᵀ for symmetric quasi-definite saddle points (the stabilised Q₁/Q₁ SubStokes
//! system with its mass rows negated, [A −B; −Bᵀ −C]).
//!
//! Eliminated dofs (Dirichlet data, hanging dofs, active constraints) are removed from the rows
//! and columns of a copy of the matrix, keeping a diagonal entry, so the sparsity pattern — and
//! with it the symbolic factorisation — stays the same while only the set of eliminated dofs
//! changes (as in deal.II): an active-set iteration costs one numeric factorisation. The symbolic
//! factorisation is computed at the first solve after [`DirectSolver::reorder`], and the large
//! work arrays survive from solve to solve and from mesh to mesh ([`DirectSolver::reorder`] keeps
//! them).
//!
//! **Memory.** The factor is by far the largest array of a solve, and its size is known from the
//! symbolic factorisation before anything of it is allocated: the nonzeros of L
//! ([`SymbolicCholesky::len_val`]). The fill depends on the mesh and the ordering, which the
//! prediction of a run from its cells cannot see (with an earlier ordering a 64×2 strip refined
//! 12 times at its contact side asked for 74 GB in one allocation). Each solve therefore
//! checks the factor, its work arrays and the copy of the matrix against the memory limit of the
//! running study ([`limit_memory`]) before allocating them, and refuses with
//! [`SolveError::OverBudget`]; the arrays are then reserved fallibly, so that a failed
//! allocation is [`SolveError::OutOfMemory`] for the cycle and not an abort of the process.

use std::cell::Cell;
use std::mem::MaybeUninit;

use faer::dyn_stack::{MemStack, StackReq};
use faer::linalg::cholesky::ldlt::factor::{LdltError, LdltRegularization};
use faer::linalg::cholesky::llt::factor::LltError;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Side};

use super::{Csc, Ordering};

/// faer's factorisation and triangular solves run sequentially. Its supernodal Cholesky visits
/// the supernodes one after another and parallelises only inside each dense block; on the 2D
/// meshes here almost all blocks are too small to pay for the synchronisation. Measured on the
/// 2-core machine over the twenty Reynolds tables at full size: 70 s of solve phases against
/// 110 s with `Par::rayon(2)` (same meshes, values equal to 2e-14). Assembly and estimation stay
/// parallel (rayon), and the factorisations do not depend on the size of the thread pool.
const FACTORISATION_PARALLELISM: faer::Par = faer::Par::Seq;

/// Which factorisation a [`DirectSolver`] computes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Factorisation {
    /// LLᵀ: symmetric positive definite systems.
    Cholesky,
    /// LDLᵀ without pivoting: symmetric quasi-definite systems, any symmetric ordering is stable
    /// in exact arithmetic. `signs[dof]` is +1 for the positive definite block (velocities) and
    /// −1 for the negative definite one (pressures); an eliminated dof keeps a diagonal entry of
    /// its sign.
    Ldlt { signs: Vec<i8> },
}

/// Why a linear solve failed.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum SolveError {
    #[error(
        "sparse Cholesky factorisation failed: the pivot of dof {dof} is not positive, the system \
         is not symmetric positive definite — {cause}"
    )]
    NotPositiveDefinite { dof: usize, cause: Cause },
    #[error(
        "sparse LDLᵀ factorisation failed: the matrix is singular, the pivot of dof {dof} vanishes \
         (its row is zero once the dofs before it are eliminated) — check the boundary conditions \
         and the pressure stabilisation"
    )]
    Singular { dof: usize },
    #[error("the symbolic factorisation failed: {0}")]
    Symbolic(String),
    #[error(
        "the solution contains a non-finite value at dof {0}: the solve overflowed — the data \
         (loads, tractions, wall velocities, boundary values) are too large for double precision"
    )]
    NonFinite(usize),
    #[error(
        "the right-hand side contains a non-finite value at dof {0}: assembling the data \
         overflowed — a load, traction, wall velocity or boundary value, or a profile's scale or \
         a gap, is too large or too small for double precision"
    )]
    NonFiniteData(usize),
    #[error("the multigrid-preconditioned CG solve failed: {0}")]
    Iterative(String),
    #[error(
        "the multigrid-preconditioned CG solve produced a non-finite value in iteration {0}: the \
         solve overflowed — the data (loads, tractions, wall velocities, boundary values) are too \
         large for double precision"
    )]
    IterativeNonFinite(usize),
    #[error("dof {0} has no diagonal sign for the LDLᵀ factorisation ({1} signs for {2} dofs)")]
    Signs(usize, usize, usize),
    #[error(
        "the primal–dual active-set method did not converge: the active set still changed after \
         {iterations} iterations (the limit)"
    )]
    ActiveSetNotConverged { iterations: usize },
    #[error(
        "the truncated nonsmooth Newton multigrid did not converge: the iterate still changed by \
         a relative {change:.3e} after {iterations} iterations (the limit)"
    )]
    ObstacleNotConverged { iterations: usize, change: f64 },
    /// A solver's arrays, predicted before they are allocated, exceed the memory limit
    /// ([`limit_memory`]); boxed, so that every error of a solve stays small.
    #[error("{0}")]
    OverBudget(Box<OverBudget>),
    /// The allocation of a solver's arrays failed: the machine does not have the memory.
    #[error(
        "the allocation of {} ({bytes} bytes) for {what} failed: the machine does not have that \
         much memory free (a smaller --memory-budget refuses such a cycle before it allocates)",
        human_bytes(*bytes as f64)
    )]
    OutOfMemory { what: &'static str, bytes: usize },
}

/// What a solver would allocate beyond the memory limit ([`SolveError::OverBudget`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "{what} is predicted to need {} ({bytes:.0} bytes), more than the memory budget of {} (set \
     it with --memory-budget)",
    human_bytes(*bytes),
    human_bytes(*budget)
)]
pub struct OverBudget {
    /// The arrays, with the sizes they follow from.
    pub what: String,
    /// Their predicted bytes.
    pub bytes: f64,
    /// The limit.
    pub budget: f64,
}

impl SolveError {
    /// [`SolveError::NonFiniteData`] at the first non-finite entry of a right-hand side.
    pub(crate) fn check_data(rhs: &[f64]) -> Result<(), SolveError> {
        match rhs.iter().position(|v| !v.is_finite()) {
            Some(i) => Err(SolveError::NonFiniteData(i)),
            None => Ok(()),
        }
    }
}

thread_local! {
    /// The memory limit of the study running on this thread ([`limit_memory`]).
    static MEMORY_LIMIT: Cell<Option<f64>> = const { Cell::new(None) };
}

/// The memory limit of the solves on this thread until the guard is dropped (then the limit
/// before it holds again). A study sets its budget here before its solves: the solvers are built
/// deep inside the problems, and a study's solves run on the thread of its cycle loop (the
/// factorisations are sequential, `FACTORISATION_PARALLELISM`).
pub fn limit_memory(bytes: f64) -> MemoryLimit {
    MemoryLimit {
        previous: MEMORY_LIMIT.with(|limit| limit.replace(Some(bytes))),
    }
}

/// The limit of [`limit_memory`], lifted when dropped.
pub struct MemoryLimit {
    previous: Option<f64>,
}

impl Drop for MemoryLimit {
    fn drop(&mut self) {
        MEMORY_LIMIT.with(|limit| limit.set(self.previous));
    }
}

/// [`SolveError::OverBudget`] if `bytes` for `what` exceed the memory limit of this thread.
pub(crate) fn check_memory(what: impl FnOnce() -> String, bytes: f64) -> Result<(), SolveError> {
    match MEMORY_LIMIT.with(Cell::get) {
        Some(budget) if bytes > budget => Err(SolveError::OverBudget(Box::new(OverBudget {
            what: what(),
            bytes,
            budget,
        }))),
        _ => Ok(()),
    }
}

/// `buffer` grown to `len` elements of `value`, reserved fallibly
/// ([`SolveError::OutOfMemory`] for `what`).
pub(crate) fn try_resize<T: Clone>(
    buffer: &mut Vec<T>,
    len: usize,
    value: T,
    what: &'static str,
) -> Result<(), SolveError> {
    if len > buffer.len() {
        buffer
            .try_reserve_exact(len - buffer.len())
            .map_err(|_| SolveError::OutOfMemory {
                what,
                bytes: len * std::mem::size_of::<T>(),
            })?;
    }
    buffer.resize(len, value);
    Ok(())
}

/// Bytes in GiB, MiB or KiB for a message.
pub(crate) fn human_bytes(bytes: f64) -> String {
    const KIB: f64 = 1024.0;
    const MIB: f64 = KIB * KIB;
    const GIB: f64 = MIB * KIB;
    if bytes >= GIB {
        format!("{:.1} GiB", bytes / GIB)
    } else if bytes >= MIB {
        format!("{:.0} MiB", bytes / MIB)
    } else if bytes >= KIB {
        format!("{:.0} KiB", bytes / KIB)
    } else {
        format!("{bytes:.0} bytes")
    }
}

/// The likely cause of a failed Cholesky factorisation, read off the matrix that was factored.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Cause {
    /// An entry is NaN or infinite: the data overflowed while assembling.
    NonFinite { dof: usize },
    /// The diagonal spans more than `ILL_CONDITIONED`: rounding swamps the small pivots.
    IllConditioned { spread: f64 },
    /// A well-scaled matrix that is singular or indefinite.
    Singular,
}

/// Ratio of the largest to the smallest diagonal entry beyond which a failed Cholesky
/// factorisation is put down to conditioning rather than to the boundary conditions.
const ILL_CONDITIONED: f64 = 1e12;

impl std::fmt::Display for Cause {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Cause::NonFinite { dof } => write!(
                f,
                "the matrix has a non-finite entry in the column of dof {dof}: the assembly \
                 overflowed (check the size of the material constants, loads and domain)"
            ),
            Cause::IllConditioned { spread } => write!(
                f,
                "its diagonal entries span a factor {spread:.1e}, so rounding swamps the small \
                 pivots (check for extreme material constants such as λ ≫ μ, or degenerate cells)"
            ),
            Cause::Singular => write!(
                f,
                "the matrix is well scaled but singular: check the boundary conditions (a body \
                 without a Dirichlet side can move rigidly)"
            ),
        }
    }
}

impl Cause {
    /// Diagnose the matrix `values` (with diagonal positions `diag`) that failed to factor.
    fn of(values: &[f64], col_ptr: &[usize], diag: &[usize]) -> Cause {
        if let Some(p) = values.iter().position(|v| !v.is_finite()) {
            let dof = col_ptr.partition_point(|&start| start <= p) - 1;
            return Cause::NonFinite { dof };
        }
        let (min, max) = diag.iter().fold((f64::INFINITY, 0.0_f64), |(lo, hi), &d| {
            let v = values[d].abs();
            (lo.min(v), hi.max(v))
        });
        let spread = max / min;
        if min > 0.0 && spread > ILL_CONDITIONED {
            Cause::IllConditioned { spread }
        } else {
            Cause::Singular
        }
    }
}

/// Work arrays of a solve: the eliminated matrix values, the values of the factor and faer's
/// scratch memory. They are large (the factor holds ~40 M values at 0.7 M dofs), and freshly
/// mapped memory costs a page fault per 4 KiB on first touch, so they are kept between the solves
/// of an active-set iteration and from one mesh to the next. Their contents never carry over:
/// every solve overwrites them.
#[derive(Default)]
struct Buffers {
    matrix: Vec<f64>,
    factor: Vec<f64>,
    scratch: Vec<MaybeUninit<u8>>,
}

/// faer's scratch memory for `req` in `buffer`, grown (fallibly) if needed.
fn scratch(buffer: &mut Vec<MaybeUninit<u8>>, req: StackReq) -> Result<&mut MemStack, SolveError> {
    let bytes = req.unaligned_bytes_required();
    if buffer.len() < bytes {
        try_resize(
            buffer,
            bytes,
            MaybeUninit::uninit(),
            "the work space of the sparse factorisation",
        )?;
    }
    Ok(MemStack::new(buffer))
}

/// The bytes a numeric factorisation with `symbolic` allocates for a matrix of `nnz` stored
/// values: the factor L, the eliminated copy of the matrix and faer's scratch memory.
fn factorisation_bytes(symbolic: &SymbolicCholesky<usize>, nnz: usize, ldlt: bool) -> f64 {
    let par = FACTORISATION_PARALLELISM;
    let scratch = if ldlt {
        symbolic.factorize_numeric_ldlt_scratch::<f64>(par, Default::default())
    } else {
        symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default())
    };
    let value = std::mem::size_of::<f64>() as f64;
    value * (symbolic.len_val() + nnz) as f64 + scratch.unaligned_bytes_required() as f64
}

/// [`SolveError::OverBudget`] if the factorisation of `symbolic` does not fit the memory limit
/// ([`factorisation_bytes`]), naming the size of the factor.
fn check_factorisation(
    symbolic: &SymbolicCholesky<usize>,
    nnz: usize,
    ldlt: bool,
) -> Result<(), SolveError> {
    let name = if ldlt { "LDLᵀ" } else { "Cholesky" };
    check_memory(
        || {
            format!(
                "the sparse {name} factorisation of {} unknowns (a factor of {} nonzeros from \
                 the symbolic factorisation)",
                symbolic.nrows(),
                symbolic.len_val()
            )
        },
        factorisation_bytes(symbolic, nnz, ldlt),
    )
}

/// A sparse direct solver for one sparsity pattern at a time (module docs).
pub struct DirectSolver {
    factorisation: Factorisation,
    ordering: Option<Ordering>,
    /// The symbolic factorisation of the current pattern and the pattern's row indices as faer
    /// reads them ([`Widened`]).
    symbolic: Option<(SymbolicCholesky<usize>, Widened)>,
    buffers: Buffers,
}

impl DirectSolver {
    pub fn new(factorisation: Factorisation) -> DirectSolver {
        DirectSolver {
            factorisation,
            ordering: None,
            symbolic: None,
            buffers: Buffers::default(),
        }
    }

    /// A Cholesky solver (SPD systems).
    pub fn cholesky() -> DirectSolver {
        DirectSolver::new(Factorisation::Cholesky)
    }

    /// An LDLᵀ solver with the given diagonal signs (symmetric quasi-definite systems).
    pub fn ldlt(signs: Vec<i8>) -> DirectSolver {
        DirectSolver::new(Factorisation::Ldlt { signs })
    }

    /// Start a new sparsity pattern (a new mesh) with its fill-reducing ordering: the symbolic
    /// factorisation is redone at the next solve, the work arrays are kept.
    pub fn reorder(&mut self, ordering: Ordering) {
        self.ordering = Some(ordering);
        self.symbolic = None;
    }

    /// Drop the ordering and the symbolic factorisation of the current pattern once its last
    /// solve is done (they are as large as the pattern), keeping the work arrays for the next
    /// one.
    pub fn release_pattern(&mut self) {
        self.ordering = None;
        self.symbolic = None;
    }

    /// New diagonal signs for LDLᵀ (with [`DirectSolver::reorder`], when the dofs change).
    pub fn set_signs(&mut self, signs: Vec<i8>) {
        if let Factorisation::Ldlt { signs: s } = &mut self.factorisation {
            *s = signs;
        }
    }

    /// Solve A x = b where the dofs in `eliminated` take the given values. Rows and columns of
    /// eliminated dofs are removed keeping a diagonal entry (the mean |diagonal| of the free rows,
    /// with the dof's sign for LDLᵀ), so the pattern and the symbolic factorisation are reused
    /// between calls. Without an ordering ([`DirectSolver::reorder`], none yet or released) the
    /// natural order is used.
    pub fn solve(
        &mut self,
        matrix: Csc<'_>,
        rhs: &[f64],
        eliminated: &[(usize, f64)],
    ) -> Result<Vec<f64>, SolveError> {
        let n = matrix.n();
        SolveError::check_data(rhs)?;
        if let Factorisation::Ldlt { signs } = &self.factorisation {
            if signs.len() != n {
                return Err(SolveError::Signs(signs.len().min(n), signs.len(), n));
            }
        }
        let ordering = self.ordering.get_or_insert_with(|| Ordering::identity(n));
        if self.symbolic.is_none() {
            self.symbolic = Some(symbolic_factorisation(&matrix, ordering)?);
        }
        let (symbolic, _) = self.symbolic.as_ref().expect("computed above");
        let ldlt = matches!(self.factorisation, Factorisation::Ldlt { .. });
        check_factorisation(symbolic, matrix.values.len(), ldlt)?;
        let mut buffers = std::mem::take(&mut self.buffers);
        let result = self.solve_in(&mut buffers, matrix, rhs, eliminated);
        self.buffers = buffers;
        result
    }

    /// [`DirectSolver::solve`] once the symbolic factorisation exists, in `buffers`.
    fn solve_in(
        &self,
        buffers: &mut Buffers,
        matrix: Csc<'_>,
        rhs: &[f64],
        eliminated: &[(usize, f64)],
    ) -> Result<Vec<f64>, SolveError> {
        let Buffers {
            matrix: a,
            factor,
            scratch: work,
        } = buffers;
        let n = matrix.n();
        let (col_ptr, row_idx, diag) = (matrix.col_ptr, matrix.row_idx, matrix.diag);
        a.clear();
        try_resize(
            a,
            matrix.values.len(),
            0.0,
            "the matrix of the sparse factorisation",
        )?;
        a.copy_from_slice(matrix.values);
        let mut b = rhs.to_vec();
        let mut is_eliminated = vec![false; n];
        for &(d, _) in eliminated {
            is_eliminated[d] = true;
        }
        // Diagonal scale of the free rows, for conditioning of the eliminated rows.
        let (sum, count) = (0..n)
            .filter(|&i| !is_eliminated[i])
            .fold((0.0, 0usize), |(s, c), i| {
                (s + matrix.values[diag[i]].abs(), c + 1)
            });
        let scale = if count > 0 && sum > 0.0 {
            sum / count as f64
        } else {
            1.0
        };
        for &(d, val) in eliminated {
            for p in col_ptr[d]..col_ptr[d + 1] {
                let i = row_idx[p] as usize;
                if !is_eliminated[i] {
                    b[i] -= a[p] * val;
                }
                a[p] = 0.0;
                // The mirrored entry (d, i) in column i.
                let col = &row_idx[col_ptr[i]..col_ptr[i + 1]];
                a[col_ptr[i] + col.binary_search(&(d as u32)).expect("symmetric pattern")] = 0.0;
            }
        }
        for &(d, val) in eliminated {
            let s = match &self.factorisation {
                Factorisation::Cholesky => scale,
                Factorisation::Ldlt { signs } => f64::from(signs[d]) * scale,
            };
            a[diag[d]] = s;
            b[d] = s * val;
        }
        let (symbolic, widened) = self.symbolic.as_ref().expect("symbolic factorisation");
        let mat = SparseColMatRef::new(widened.symbolic(&matrix), &a[..]);
        let par = FACTORISATION_PARALLELISM;
        let fwd = &self.ordering.as_ref().expect("ordering").fwd;
        // The dof of a failed pivot: faer numbers the pivot from 1 in its simplicial
        // factorisation and from 0 in its supernodal one (faer 0.24).
        let pivot_dof = |index: usize| match symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(_) => fwd[index - 1],
            SymbolicCholeskyRaw::Supernodal(_) => fwd[index],
        };
        // faer overwrites every value of the factor (it fills it with zeros first).
        try_resize(
            factor,
            symbolic.len_val(),
            0.0,
            "the factor of the sparse factorisation",
        )?;
        let mut x = b;
        let rhs_mat = MatMut::from_column_major_slice_mut(&mut x, n, 1);
        match &self.factorisation {
            Factorisation::Cholesky => {
                let llt = symbolic
                    .factorize_numeric_llt(
                        factor,
                        mat,
                        Side::Lower,
                        Default::default(),
                        par,
                        scratch(
                            work,
                            symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()),
                        )?,
                        Default::default(),
                    )
                    .map_err(|e| match e {
                        LltError::NonPositivePivot { index } => SolveError::NotPositiveDefinite {
                            dof: pivot_dof(index),
                            cause: Cause::of(a, col_ptr, diag),
                        },
                    })?;
                llt.solve_in_place_with_conj(
                    Conj::No,
                    rhs_mat,
                    par,
                    scratch(work, symbolic.solve_in_place_scratch::<f64>(1, par))?,
                );
            }
            Factorisation::Ldlt { .. } => {
                let ldlt = symbolic
                    .factorize_numeric_ldlt(
                        factor,
                        mat,
                        Side::Lower,
                        LdltRegularization::default(),
                        par,
                        scratch(
                            work,
                            symbolic.factorize_numeric_ldlt_scratch::<f64>(par, Default::default()),
                        )?,
                        Default::default(),
                    )
                    .map_err(|e| match e {
                        LdltError::ZeroPivot { index } => SolveError::Singular {
                            dof: pivot_dof(index),
                        },
                    })?;
                ldlt.solve_in_place_with_conj(
                    Conj::No,
                    rhs_mat,
                    par,
                    scratch(work, symbolic.solve_in_place_scratch::<f64>(1, par))?,
                );
            }
        }
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            return Err(SolveError::NonFinite(i));
        }
        for &(d, val) in eliminated {
            x[d] = val;
        }
        Ok(x)
    }
}

/// The Cholesky factor LLᵀ of one SPD matrix, kept for many solves with it (the inner A-solves
/// of the Uzawa methods, [`crate::linalg::uzawa::InnerSolver::Cholesky`]); no dof is
/// eliminated. Symbolic and numeric factorisation as [`DirectSolver`] does them (same faer
/// calls, sequential).
pub struct CholeskyFactor {
    symbolic: SymbolicCholesky<usize>,
    values: Vec<f64>,
    work: Vec<MaybeUninit<u8>>,
}

impl CholeskyFactor {
    /// Factor `matrix` in the fill-reducing `ordering` (natural order if `None`). A non-positive
    /// pivot is an error ([`SolveError::NotPositiveDefinite`]).
    pub fn new(matrix: Csc<'_>, ordering: Option<&Ordering>) -> Result<CholeskyFactor, SolveError> {
        let n = matrix.n();
        let identity;
        let ordering = match ordering {
            Some(o) => o,
            None => {
                identity = Ordering::identity(n);
                &identity
            }
        };
        if ordering.len() != n {
            return Err(SolveError::Symbolic(format!(
                "ordering of {} dofs for {n}",
                ordering.len()
            )));
        }
        if let Some(p) = matrix.values.iter().position(|v| !v.is_finite()) {
            let dof = matrix.col_ptr.partition_point(|&start| start <= p) - 1;
            return Err(SolveError::NonFiniteData(dof));
        }
        let (symbolic, widened) = symbolic_factorisation(&matrix, ordering)?;
        check_factorisation(&symbolic, 0, false)?;
        let par = FACTORISATION_PARALLELISM;
        let mut values = Vec::new();
        try_resize(
            &mut values,
            symbolic.len_val(),
            0.0,
            "the factor of the sparse factorisation",
        )?;
        let mut work = Vec::new();
        let fwd = &ordering.fwd;
        let pivot_dof = |index: usize| match symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(_) => fwd[index - 1],
            SymbolicCholeskyRaw::Supernodal(_) => fwd[index],
        };
        let mat = SparseColMatRef::new(widened.symbolic(&matrix), matrix.values);
        symbolic
            .factorize_numeric_llt(
                &mut values,
                mat,
                Side::Lower,
                Default::default(),
                par,
                scratch(
                    &mut work,
                    symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()),
                )?,
                Default::default(),
            )
            .map_err(|e| match e {
                LltError::NonPositivePivot { index } => SolveError::NotPositiveDefinite {
                    dof: pivot_dof(index),
                    cause: Cause::of(matrix.values, matrix.col_ptr, matrix.diag),
                },
            })?;
        // The solves' work space, reserved here so that a solve does not allocate.
        scratch(&mut work, symbolic.solve_in_place_scratch::<f64>(1, par))?;
        Ok(CholeskyFactor {
            symbolic,
            values,
            work,
        })
    }

    /// b ← A⁻¹b.
    pub fn solve_in_place(&mut self, b: &mut [f64]) {
        let par = FACTORISATION_PARALLELISM;
        let n = b.len();
        let llt = LltRef::new(&self.symbolic, &self.values);
        llt.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(b, n, 1),
            par,
            scratch(
                &mut self.work,
                self.symbolic.solve_in_place_scratch::<f64>(1, par),
            )
            .expect("the work space of the solves is reserved by CholeskyFactor::new"),
        );
    }

    /// Stored values of the factor L.
    pub fn len_val(&self) -> usize {
        self.values.len()
    }
}

/// faer's symbolic Cholesky factorisation of the pattern of `matrix` in `ordering`, with the
/// pattern's row indices as faer reads them.
///
/// faer picks its simplicial factorisation when the flops per nonzero of L stay below 40, its
/// supernodal one (dense blocks, BLAS-3 kernels) above. The 2-D meshes here sit near that line,
/// and supernodal was as fast or faster wherever both ran: Table IV.16 alone
/// (`--no-alternatives`), two interleaved pairs, 5.5 and 6.0 s of solve phases against 6.7 and
/// 6.2 s, IV.35 4.8 and 4.6 s against 5.4 and 5.2 s (with the ordering of an earlier version,
/// whose fill was larger, 5.4–5.7 s against 7.5–8.4 s on IV.16); the same meshes and active
/// sets, values within 1e-10 relative. Every factorisation is therefore supernodal.
fn symbolic_factorisation(
    matrix: &Csc<'_>,
    ordering: &Ordering,
) -> Result<(SymbolicCholesky<usize>, Widened), SolveError> {
    let perm = PermRef::new_checked(&ordering.fwd, &ordering.inv, matrix.n());
    let widened = Widened::of(matrix);
    let symbolic = factorize_symbolic_cholesky(
        widened.symbolic(matrix),
        Side::Lower,
        SymmetricOrdering::Custom(perm),
        CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        },
    )
    .map_err(|e| SolveError::Symbolic(format!("{e:?}")))?;
    Ok((symbolic, widened))
}

/// The row indices of a pattern as faer reads them: faer takes one index type for the column
/// pointers and the row indices, and [`Csc`] stores the row indices in 32 bits.
struct Widened {
    row_idx: Vec<usize>,
}

impl Widened {
    fn of(matrix: &Csc<'_>) -> Widened {
        Widened {
            row_idx: matrix.row_idx.iter().map(|&i| i as usize).collect(),
        }
    }

    /// faer's view of the pattern of `matrix` (the one this was made of).
    fn symbolic<'a>(&'a self, matrix: &Csc<'a>) -> SymbolicSparseColMatRef<'a, usize> {
        let n = matrix.n();
        SymbolicSparseColMatRef::new_checked(n, n, matrix.col_ptr, None, &self.row_idx)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Full-storage CSC of a dense symmetric matrix (zeros left out, diagonal always kept).
    struct Dense {
        col_ptr: Vec<usize>,
        row_idx: Vec<u32>,
        diag: Vec<usize>,
        values: Vec<f64>,
    }

    impl Dense {
        fn new(a: &[Vec<f64>]) -> Dense {
            let n = a.len();
            let (mut col_ptr, mut row_idx, mut diag, mut values) =
                (vec![0], vec![], vec![], vec![]);
            for j in 0..n {
                for (i, row) in a.iter().enumerate() {
                    assert_eq!(row[j], a[j][i], "symmetric");
                    if row[j] != 0.0 || i == j {
                        if i == j {
                            diag.push(values.len());
                        }
                        row_idx.push(i as u32);
                        values.push(row[j]);
                    }
                }
                col_ptr.push(values.len());
            }
            Dense {
                col_ptr,
                row_idx,
                diag,
                values,
            }
        }

        fn csc(&self) -> Csc<'_> {
            Csc {
                col_ptr: &self.col_ptr,
                row_idx: &self.row_idx,
                diag: &self.diag,
                values: &self.values,
            }
        }
    }

    /// [A Bᵀ; B −C] with A SPD (3 velocities), B 2×3, C SPD (2 pressures).
    fn saddle_point(c: f64) -> Vec<Vec<f64>> {
        let a = [[4.0, 1.0, 0.0], [1.0, 3.0, 0.5], [0.0, 0.5, 2.0]];
        let b = [[1.0, -1.0, 0.0], [0.0, 1.0, 2.0]];
        let mut m = vec![vec![0.0; 5]; 5];
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] = a[i][j];
            }
        }
        for (p, row) in b.iter().enumerate() {
            for (j, &v) in row.iter().enumerate() {
                m[3 + p][j] = v;
                m[j][3 + p] = v;
            }
        }
        m[3][3] = -c;
        m[4][4] = -2.0 * c;
        m[3][4] = -0.1 * c;
        m[4][3] = -0.1 * c;
        m
    }

    /// The fill of the nested-dissection ordering on a 64×2 strip refined 8 times at its
    /// bottom side, as the contact strips of the model-adaptive tables are (IV.18): the nonzeros
    /// of L stay within 6·n·log₂ n for the n unknowns (the two components of elasticity). Cut
    /// along the longer side of each subset alone, the cuts ran through the fine layer and L
    /// had 0.0026·n², some 20 times more at this size (module `ordering`).
    #[test]
    fn a_strip_refined_at_one_side_fills_in_like_a_quasi_uniform_mesh() {
        use crate::fe::System;
        use crate::mesh::Mesh;
        let mut mesh = Mesh::new([0.0, 64.0], [0.0, 2.0], 64, 2);
        for _ in 0..8 {
            let bottom: Vec<bool> = mesh
                .active()
                .iter()
                .map(|&c| mesh.cell_box(c)[1] == 0.0)
                .collect();
            let none = vec![false; bottom.len()];
            mesh.refine_and_coarsen(&bottom, &none).unwrap();
        }
        let mut system = System::new(&mesh, 2);
        system.assemble(mesh.n_active(), |_, ke, _| ke.fill(1.0));
        let matrix = system.matrix();
        let n = matrix.n() as f64;
        let (symbolic, _) = symbolic_factorisation(&matrix, &system.ordering()).unwrap();
        let bound = 6.0 * n * n.log2();
        assert!(n > 50_000.0, "{n} unknowns");
        assert!(
            (symbolic.len_val() as f64) < bound,
            "{} nonzeros in L for {n} unknowns, bound {bound:.3e}",
            symbolic.len_val()
        );
    }

    #[test]
    fn ldlt_solves_a_stabilised_saddle_point_system() {
        let m = saddle_point(0.3);
        let dense = Dense::new(&m);
        let x_exact = [1.0, -2.0, 0.5, 3.0, -1.5];
        let rhs: Vec<f64> = m
            .iter()
            .map(|row| row.iter().zip(&x_exact).map(|(a, x)| a * x).sum())
            .collect();
        let mut solver = DirectSolver::ldlt(vec![1, 1, 1, -1, -1]);
        let x = solver
            .solve(dense.csc(), &rhs, &[])
            .expect("quasi-definite");
        for (a, b) in x.iter().zip(&x_exact) {
            assert!((a - b).abs() <= 1e-12, "{x:?}");
        }
        // Cholesky must refuse it, naming a dof.
        let err = DirectSolver::cholesky()
            .solve(dense.csc(), &rhs, &[])
            .unwrap_err();
        assert!(
            matches!(err, SolveError::NotPositiveDefinite { .. }),
            "{err}"
        );
        // An eliminated pressure keeps a negative diagonal and takes its value.
        let x = solver
            .solve(dense.csc(), &rhs, &[(4, -1.5)])
            .expect("solves");
        for (a, b) in x.iter().zip(&x_exact) {
            assert!((a - b).abs() <= 1e-12, "{x:?}");
        }
    }

    #[test]
    fn singular_saddle_point_names_the_dof() {
        // No stabilisation and a pressure that no velocity couples to: its pivot is exactly 0.
        let mut m = saddle_point(0.0);
        for row in m.iter_mut() {
            row[4] = 0.0;
        }
        m[4] = vec![0.0; 5];
        let dense = Dense::new(&m);
        let err = DirectSolver::ldlt(vec![1, 1, 1, -1, -1])
            .solve(dense.csc(), &[1.0; 5], &[])
            .unwrap_err();
        assert_eq!(err, SolveError::Singular { dof: 4 });
        let message = err.to_string();
        assert!(
            message.contains("singular") && message.contains("dof 4"),
            "{message}"
        );
    }

    /// A factor larger than the memory limit of the thread is refused before it is allocated,
    /// naming its nonzeros and the bytes; once the limit is lifted the same solve runs.
    #[test]
    fn a_factor_beyond_the_memory_limit_is_refused_before_it_is_allocated() {
        let m = saddle_point(0.3);
        let dense = Dense::new(&m);
        let signs = vec![1, 1, 1, -1, -1];
        {
            let _limit = limit_memory(64.0);
            let err = DirectSolver::ldlt(signs.clone())
                .solve(dense.csc(), &[1.0; 5], &[])
                .unwrap_err();
            let SolveError::OverBudget(refused) = &err else {
                panic!("{err}");
            };
            assert!(refused.bytes > 64.0 && refused.budget == 64.0, "{err}");
            let message = err.to_string();
            assert!(
                message.contains("LDLᵀ factorisation of 5 unknowns")
                    && message.contains("nonzeros")
                    && message.contains("memory budget of 64 bytes"),
                "{message}"
            );
            let spd = Dense::new(&[vec![2.0, 1.0], vec![1.0, 2.0]]);
            assert!(matches!(
                CholeskyFactor::new(spd.csc(), None),
                Err(SolveError::OverBudget(_))
            ));
        }
        DirectSolver::ldlt(signs)
            .solve(dense.csc(), &[1.0; 5], &[])
            .expect("no limit once the guard is dropped");
    }

    #[test]
    fn the_cause_of_a_failed_factorisation_is_read_off_the_matrix() {
        // Diagonal 2×2 matrices: columns [0, 1), [1, 2), diagonal at 0 and 1.
        let (col_ptr, diag) = ([0, 1, 2], [0, 1]);
        assert_eq!(
            Cause::of(&[1.0, f64::NAN], &col_ptr, &diag),
            Cause::NonFinite { dof: 1 }
        );
        assert_eq!(
            Cause::of(&[1e20, 1.0], &col_ptr, &diag),
            Cause::IllConditioned { spread: 1e20 }
        );
        assert_eq!(Cause::of(&[1.0, -1.0], &col_ptr, &diag), Cause::Singular);
        assert_eq!(Cause::of(&[1.0, 0.0], &col_ptr, &diag), Cause::Singular);
        let message = SolveError::NotPositiveDefinite {
            dof: 1,
            cause: Cause::IllConditioned { spread: 1e20 },
        }
        .to_string();
        assert!(
            message.contains("span a factor 1.0e20") && message.contains("λ ≫ μ"),
            "{message}"
        );
    }
}
