//! The preconditioned conjugate gradient method (Hestenes–Stiefel) for symmetric positive
//! definite operators, with a pluggable preconditioner: the inner solver of the Uzawa variants
//! of §III.2.3.4 (III.88)–(III.92), and the iterative alternative to the direct solvers.

use rayon::prelude::*;

use super::Csc;

/// A symmetric positive definite approximation M ≈ A, applied as z = M⁻¹r.
pub trait Preconditioner {
    fn apply(&self, r: &[f64], z: &mut [f64]);
}

/// No preconditioning: z = r.
pub struct Identity;

impl Preconditioner for Identity {
    fn apply(&self, r: &[f64], z: &mut [f64]) {
        z.copy_from_slice(r);
    }
}

/// Diagonal (Jacobi) preconditioning: z = D⁻¹r.
pub struct Jacobi {
    inverse_diagonal: Vec<f64>,
}

impl Jacobi {
    /// From the diagonal of A (every entry must be positive).
    pub fn new(diagonal: &[f64]) -> Jacobi {
        Jacobi {
            inverse_diagonal: diagonal.iter().map(|d| 1.0 / d).collect(),
        }
    }
}

impl Preconditioner for Jacobi {
    fn apply(&self, r: &[f64], z: &mut [f64]) {
        for ((z, r), d) in z.iter_mut().zip(r).zip(&self.inverse_diagonal) {
            *z = r * d;
        }
    }
}

/// When to stop: the residual ‖b − Ax‖₂ at most `absolute` or at most `relative`·‖b‖₂, after at
/// most `max_iterations` iterations.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stopping {
    pub relative: f64,
    pub absolute: f64,
    pub max_iterations: usize,
}

/// What a CG run did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CgReport {
    pub iterations: usize,
    /// Final residual ‖b − Ax‖₂ (the recurrence's).
    pub residual: f64,
}

/// Why CG stopped without meeting its tolerance.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum CgError {
    #[error("CG did not converge: residual {residual:.3e} above {target:.3e} after {iterations} iterations")]
    NotConverged {
        iterations: usize,
        residual: f64,
        target: f64,
    },
    #[error("CG broke down in iteration {0}: pᵀAp ≤ 0 (the operator or the preconditioner is not positive definite)")]
    Breakdown(usize),
    #[error("CG produced a non-finite value in iteration {0}")]
    NonFinite(usize),
}

/// How CG runs its vector operations (dot products and updates).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VectorOps {
    /// One thread; every dot product summed from the first entry to the last.
    Sequential,
    /// In parallel over fixed chunks of [`CHUNK`] entries: each chunk's part of a dot product
    /// summed in order, the parts summed in chunk order — the same bits whatever the number of
    /// threads, and those of [`VectorOps::Sequential`] for vectors of at most one chunk.
    Chunked,
}

/// Entries per chunk of [`VectorOps::Chunked`].
pub const CHUNK: usize = 16384;

impl VectorOps {
    fn dot(self, a: &[f64], b: &[f64]) -> f64 {
        let sum = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        match self {
            VectorOps::Sequential => sum(a, b),
            VectorOps::Chunked => a
                .par_chunks(CHUNK)
                .zip(b.par_chunks(CHUNK))
                .map(|(a, b)| sum(a, b))
                .collect::<Vec<f64>>()
                .into_iter()
                .sum(),
        }
    }

    /// x += α p and r −= α q; returns ‖r‖₂² of the updated r.
    fn step(self, alpha: f64, p: &[f64], q: &[f64], x: &mut [f64], r: &mut [f64]) -> f64 {
        let step = |p: &[f64], q: &[f64], x: &mut [f64], r: &mut [f64]| {
            for i in 0..x.len() {
                x[i] += alpha * p[i];
                r[i] -= alpha * q[i];
            }
            r.iter().map(|r| r * r).sum::<f64>()
        };
        match self {
            VectorOps::Sequential => step(p, q, x, r),
            VectorOps::Chunked => x
                .par_chunks_mut(CHUNK)
                .zip(r.par_chunks_mut(CHUNK))
                .zip(p.par_chunks(CHUNK).zip(q.par_chunks(CHUNK)))
                .map(|((x, r), (p, q))| step(p, q, x, r))
                .collect::<Vec<f64>>()
                .into_iter()
                .sum(),
        }
    }

    /// p = z + β p.
    fn direction(self, beta: f64, z: &[f64], p: &mut [f64]) {
        let update = |z: &[f64], p: &mut [f64]| {
            for (p, z) in p.iter_mut().zip(z) {
                *p = z + beta * *p;
            }
        };
        match self {
            VectorOps::Sequential => update(z, p),
            VectorOps::Chunked => p
                .par_chunks_mut(CHUNK)
                .zip(z.par_chunks(CHUNK))
                .for_each(|(p, z)| update(z, p)),
        }
    }
}

/// Solve A x = b by preconditioned CG from the initial guess in `x`; `apply(v, out)` computes
/// out = A v. The vector operations run on one thread ([`conjugate_gradient_with`]).
pub fn conjugate_gradient(
    apply: impl Fn(&[f64], &mut [f64]),
    b: &[f64],
    x: &mut [f64],
    preconditioner: &dyn Preconditioner,
    stopping: Stopping,
) -> Result<CgReport, CgError> {
    conjugate_gradient_with(VectorOps::Sequential, apply, b, x, preconditioner, stopping)
}

/// [`conjugate_gradient`] with the vector operations run by `ops`.
pub fn conjugate_gradient_with(
    ops: VectorOps,
    apply: impl Fn(&[f64], &mut [f64]),
    b: &[f64],
    x: &mut [f64],
    preconditioner: &dyn Preconditioner,
    stopping: Stopping,
) -> Result<CgReport, CgError> {
    let n = b.len();
    let mut r = vec![0.0; n];
    apply(x, &mut r);
    for (r, b) in r.iter_mut().zip(b) {
        *r = b - *r;
    }
    let target = stopping
        .absolute
        .max(stopping.relative * ops.dot(b, b).sqrt());
    let mut z = vec![0.0; n];
    preconditioner.apply(&r, &mut z);
    let mut p = z.clone();
    let mut ap = vec![0.0; n];
    let mut rz = ops.dot(&r, &z);
    let mut residual = ops.dot(&r, &r).sqrt();
    for iteration in 0..stopping.max_iterations {
        if residual <= target {
            return Ok(CgReport {
                iterations: iteration,
                residual,
            });
        }
        apply(&p, &mut ap);
        let pap = ops.dot(&p, &ap);
        if !pap.is_finite() {
            return Err(CgError::NonFinite(iteration + 1));
        }
        if pap <= 0.0 {
            return Err(CgError::Breakdown(iteration + 1));
        }
        let alpha = rz / pap;
        residual = ops.step(alpha, &p, &ap, x, &mut r).sqrt();
        preconditioner.apply(&r, &mut z);
        let rz_next = ops.dot(&r, &z);
        let beta = rz_next / rz;
        rz = rz_next;
        ops.direction(beta, &z, &mut p);
        if !residual.is_finite() {
            return Err(CgError::NonFinite(iteration + 1));
        }
    }
    if residual <= target {
        return Ok(CgReport {
            iterations: stopping.max_iterations,
            residual,
        });
    }
    Err(CgError::NotConverged {
        iterations: stopping.max_iterations,
        residual,
        target,
    })
}

/// [`conjugate_gradient`] for an assembled symmetric matrix.
pub fn solve_csc(
    matrix: Csc<'_>,
    b: &[f64],
    x: &mut [f64],
    preconditioner: &dyn Preconditioner,
    stopping: Stopping,
) -> Result<CgReport, CgError> {
    conjugate_gradient(
        |v, out| out.copy_from_slice(&matrix.multiply(v)),
        b,
        x,
        preconditioner,
        stopping,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tridiagonal 1D Laplacian L = tridiag(−1, 2, −1), badly scaled: D L D with
    /// D = diag(1, 101, 201, 1, 101, …).
    fn operator(n: usize) -> impl Fn(&[f64], &mut [f64]) {
        move |v: &[f64], out: &mut [f64]| {
            let s = |i: usize| 1.0 + 100.0 * (i % 3) as f64;
            for i in 0..n {
                let mut y = 2.0 * s(i) * v[i];
                if i > 0 {
                    y -= s(i - 1) * v[i - 1];
                }
                if i + 1 < n {
                    y -= s(i + 1) * v[i + 1];
                }
                out[i] = s(i) * y;
            }
        }
    }

    #[test]
    fn cg_solves_spd_systems_and_jacobi_helps_a_badly_scaled_one() {
        let n = 200;
        let a = operator(n);
        let x_exact: Vec<f64> = (0..n).map(|i| (i as f64 * 0.1).sin()).collect();
        let mut b = vec![0.0; n];
        a(&x_exact, &mut b);
        let stopping = Stopping {
            relative: 1e-12,
            absolute: 0.0,
            max_iterations: 10 * n,
        };
        let mut diag = vec![0.0; n];
        for (i, d) in diag.iter_mut().enumerate() {
            let mut e = vec![0.0; n];
            let mut ae = vec![0.0; n];
            e[i] = 1.0;
            a(&e, &mut ae);
            *d = ae[i];
        }
        let mut x = vec![0.0; n];
        let plain = conjugate_gradient(&a, &b, &mut x, &Identity, stopping).expect("converges");
        let err = x
            .iter()
            .zip(&x_exact)
            .fold(0.0f64, |m, (u, v)| m.max((u - v).abs()));
        assert!(err < 1e-8, "identity: error {err}");
        let mut x = vec![0.0; n];
        let jacobi =
            conjugate_gradient(&a, &b, &mut x, &Jacobi::new(&diag), stopping).expect("converges");
        let err = x
            .iter()
            .zip(&x_exact)
            .fold(0.0f64, |m, (u, v)| m.max((u - v).abs()));
        assert!(err < 1e-8, "jacobi: error {err}");
        assert!(
            jacobi.iterations < plain.iterations,
            "jacobi {} vs identity {}",
            jacobi.iterations,
            plain.iterations
        );
        // A warm start at the solution stops at once.
        let report = conjugate_gradient(&a, &b, &mut x, &Identity, stopping).unwrap();
        assert_eq!(report.iterations, 0);
    }

    #[test]
    fn cg_reports_failure() {
        let n = 50;
        let a = operator(n);
        let b = vec![1.0; n];
        let mut x = vec![0.0; n];
        let few = Stopping {
            relative: 1e-14,
            absolute: 0.0,
            max_iterations: 3,
        };
        let err = conjugate_gradient(&a, &b, &mut x, &Identity, few).unwrap_err();
        assert!(
            matches!(err, CgError::NotConverged { iterations: 3, .. }),
            "{err}"
        );
        let negative = |v: &[f64], out: &mut [f64]| {
            for (o, v) in out.iter_mut().zip(v) {
                *o = -v;
            }
        };
        let err = conjugate_gradient(negative, &b, &mut vec![0.0; n], &Identity, few).unwrap_err();
        assert_eq!(err, CgError::Breakdown(1));
    }
}
