//! Tests of the Uzawa variants on (III.88) and on hand-sized systems.

use super::inner::{schur_product, Inner};
use super::*;
use crate::linalg::csr::CsrMatrix;
use crate::linalg::saddle_point::dot;
use crate::models::stokes_channel::{ChannelBlocks, StokesChannel};

/// (III.88) as the thesis states it, with its direct pressure.
fn channel() -> (ChannelBlocks, Vec<f64>) {
    let blocks = StokesChannel::thesis().blocks().unwrap();
    let direct = blocks.solve_direct().unwrap();
    (blocks, direct.pressure)
}

fn run(
    system: &SaddlePoint,
    reference: &[f64],
    variant: Variant,
    iterations: usize,
    tolerance: f64,
) -> UzawaRun {
    let options = UzawaOptions {
        max_iterations: iterations,
        relative_tolerance: tolerance,
        ..UzawaOptions::new(variant)
    };
    uzawa(system, &options, Some(reference)).unwrap()
}

/// A 2×1 system small enough to solve by hand: A = diag(2, 4), B = (1, 2)ᵀ, f = (2, 0),
/// C = (c), g = 1 + S with S = BᵀA⁻¹B + C = 3/2 + c, b_S = g − BᵀA⁻¹f = g − 1 = S, so
/// p = 1 and v = A⁻¹(f + Bp) = (3/2, 1/2).
fn hand_sized(c: f64) -> SaddlePoint {
    SaddlePoint::new(
        CsrMatrix::from_triplets(2, 2, vec![(0, 0, 2.0), (1, 1, 4.0)]),
        CsrMatrix::from_triplets(2, 1, vec![(0, 0, 1.0), (1, 0, 2.0)]),
        CsrMatrix::from_triplets(1, 1, vec![(0, 0, c)]),
        vec![2.0, 0.0],
        vec![2.5 + c],
    )
    .unwrap()
}

/// Every variant converges on the hand-sized system with S = 7/4 < 2; the direct solve
/// gives the exact solution; Richardson diverges once S = 5/2 > 2 (ω = 1).
#[test]
fn every_variant_solves_a_hand_sized_system() {
    let system = hand_sized(0.25);
    let direct = system.solve_direct(None).unwrap();
    assert!((direct.pressure[0] - 1.0).abs() < 1e-14);
    assert!((direct.velocity[0] - 1.5).abs() < 1e-14);
    assert!((direct.velocity[1] - 0.5).abs() < 1e-14);
    for variant in Variant::ALL {
        let out = run(&system, &direct.pressure, variant, 200, 1e-12);
        assert!(out.converged, "{variant}: {:?}", out.rows.last());
        assert!((out.pressure[0] - 1.0).abs() < 1e-10, "{variant}");
    }
    // One unknown: D = 1/2 + 1 + 1/4 = S, so Jacobi is exact in one step.
    let jacobi = run(&system, &direct.pressure, Variant::Jacobi, 10, 1e-12);
    assert_eq!(jacobi.rows.len(), 2);
    // S = 5/2: the unit Richardson step overshoots, |1 − S| = 3/2.
    let options = UzawaOptions::new(Variant::Identity);
    let err = uzawa(&hand_sized(1.0), &options, None).unwrap_err();
    assert!(
        matches!(
            err,
            UzawaError::Diverged {
                variant: "identity",
                ..
            }
        ),
        "{err}"
    );
    // Inconsistent blocks are refused.
    let bad = SaddlePoint::new(
        CsrMatrix::from_triplets(2, 2, vec![]),
        CsrMatrix::from_triplets(2, 2, vec![]),
        CsrMatrix::from_triplets(1, 1, vec![]),
        vec![0.0; 2],
        vec![0.0; 1],
    );
    assert!(bad.is_err());
}

/// CG-SSOR (III.92) on (III.88): relative residual 1e-6 within 100 iterations (48 measured;
/// a reference implementation with exact inner solves took 49), and on to the direct
/// pressure within 1e-8 (relative Euclidean norm).
#[test]
fn cg_ssor_reaches_the_direct_solution() {
    let (blocks, reference) = channel();
    let out = run(&blocks.system, &reference, Variant::CgSsor, 150, 1e-11);
    let first = out
        .rows
        .iter()
        .find(|r| r.relative_residual <= 1e-6)
        .map(|r| r.iteration);
    println!(
        "cg-ssor: 1e-6 after {first:?} iterations, {} rows, last {:?}",
        out.rows.len(),
        out.rows.last()
    );
    assert!(first.is_some_and(|k| k <= 100), "1e-6 reached at {first:?}");
    assert!(out.converged);
    let last = out.rows.last().unwrap();
    let error = last.pressure_error.unwrap();
    assert!(error <= 1e-8, "pressure error {error:e}");
    // The row's residual is the residual of the returned iterate.
    let recomputed = blocks.system.residual(&out.velocity, &out.pressure);
    assert!(
        (recomputed - last.residual).abs() <= 1e-12 * blocks.system.rhs_norm(),
        "{recomputed:e} vs {:e}",
        last.residual
    );
}

/// Fig. III.6's claim, "the supremacy of the cg-accelerated solver": after 50 iterations
/// every other variant's relative residual is at least 100 times CG-SSOR's.
#[test]
fn at_iteration_50_cg_ssor_is_100_times_ahead_of_the_others() {
    let (blocks, reference) = channel();
    let at_50: Vec<(Variant, f64)> = Variant::ALL
        .into_iter()
        .map(|variant| {
            let out = run(&blocks.system, &reference, variant, 50, 0.0);
            assert_eq!(out.rows.len(), 51, "{variant}");
            let last = out.rows.last().unwrap();
            println!(
                "{variant}: relative residual {:e} at 50",
                last.relative_residual
            );
            (variant, last.relative_residual)
        })
        .collect();
    let cg = at_50[4].1;
    assert_eq!(at_50[4].0, Variant::CgSsor);
    for &(variant, r) in &at_50[..4] {
        assert!(r >= 100.0 * cg, "{variant}: {r:e} vs cg-ssor {cg:e}");
    }
}

/// λ_max(S) of (III.88) by a power iteration (30 steps, exact inner solves: a lower bound,
/// 0.121; 200 steps give 0.124) is far below 2, so Richardson with ω = 1 needs no damping,
/// and its residual does decrease.
#[test]
fn identity_needs_no_damping() {
    let (blocks, reference) = channel();
    let s = &blocks.system;
    let inner = Inner {
        a: &s.a,
        factor: None,
        floor: 1e-14 * norm(&s.f),
        scale: 1.0,
        exact: true,
        variant: "power",
        max_iterations: 10_000,
    };
    let mut w = vec![1.0; s.n_pressure()];
    let mut lambda = 0.0;
    for k in 0..30 {
        let scale = norm(&w);
        w.iter_mut().for_each(|x| *x /= scale);
        let (sw, _) = schur_product(s, &inner, &w, 1e-12, k).unwrap();
        lambda = dot(&w, &sw);
        w = sw;
    }
    println!("λ_max(S) ≥ {lambda}");
    assert!(lambda > 0.05 && lambda < 1.0, "λ_max(S) ≈ {lambda}");
    let out = run(s, &reference, Variant::Identity, 60, 0.0);
    let r = |k: usize| out.rows[k].relative_residual;
    assert!(
        r(60) < r(30) && r(30) < r(10),
        "{} {} {}",
        r(10),
        r(30),
        r(60)
    );
}

/// Richardson with ω = 40 > 2/λ_max(S) diverges; the run stops with an error naming the
/// variant and the iteration, before any value overflows.
#[test]
fn a_diverging_variant_is_an_error_naming_it() {
    let (blocks, reference) = channel();
    let options = UzawaOptions {
        damping: 40.0,
        ..UzawaOptions::new(Variant::Identity)
    };
    let err = uzawa(&blocks.system, &options, Some(&reference)).unwrap_err();
    match &err {
        UzawaError::Diverged {
            variant,
            iteration,
            residual,
            initial,
        } => {
            assert_eq!(*variant, "identity");
            assert!(*iteration > 1 && *iteration < 50, "iteration {iteration}");
            assert!(residual.is_finite() && *residual > DIVERGENCE_FACTOR * initial);
        }
        other => panic!("not a divergence: {other}"),
    }
    let message = err.to_string();
    assert!(message.contains("identity") && message.contains("iteration"));
}

/// The projection: on (III.88) the direct pressure is positive (the bound is inactive at
/// the solution), and projected CG-SSOR still reaches it. With the data negated the direct
/// pressure is negative, so the projection acts: every variant keeps p ≥ 0 and finite.
#[test]
fn projected_runs_keep_the_pressure_nonnegative() {
    let (blocks, reference) = channel();
    assert!(reference.iter().all(|&p| p > 0.0));
    let options = UzawaOptions {
        max_iterations: 150,
        relative_tolerance: 1e-11,
        projected: true,
        ..UzawaOptions::new(Variant::CgSsor)
    };
    let out = uzawa(&blocks.system, &options, Some(&reference)).unwrap();
    let error = out.rows.last().unwrap().pressure_error.unwrap();
    assert!(out.converged && error < 1e-8, "{error:e}");

    let mut negated = blocks.system.clone();
    negated.f.iter_mut().for_each(|x| *x = -*x);
    negated.g.iter_mut().for_each(|x| *x = -*x);
    let negative: Vec<f64> = reference.iter().map(|p| -p).collect();
    for variant in Variant::ALL {
        let options = UzawaOptions {
            max_iterations: 30,
            projected: true,
            ..UzawaOptions::new(variant)
        };
        let out = uzawa(&negated, &options, Some(&negative)).unwrap();
        assert!(out.pressure.iter().all(|&p| p >= 0.0), "{variant}");
        assert!(out.rows.iter().all(|r| r.residual.is_finite()), "{variant}");
    }
}

/// The Cholesky inner solver gives the run of exact inner CG solves on (III.88): CG-SSOR
/// as printed reaches 1e-6 at the same iteration (48) and the direct pressure to 1e-9;
/// every row spends whole A-solves (one per product).
#[test]
fn cholesky_inner_solves_match_exact_cg() {
    let (blocks, reference) = channel();
    let first = |options: &UzawaOptions| {
        let out = uzawa(&blocks.system, options, Some(&reference)).unwrap();
        let k = out
            .rows
            .iter()
            .find(|r| r.relative_residual <= 1e-6)
            .map(|r| r.iteration);
        (k, out)
    };
    let exact = UzawaOptions {
        exact_inner: true,
        max_iterations: 150,
        relative_tolerance: 1e-11,
        ..UzawaOptions::new(Variant::CgSsor)
    };
    let cholesky = UzawaOptions {
        inner: InnerSolver::Cholesky,
        ..exact
    };
    let (k_exact, _) = first(&exact);
    let (k_cholesky, out) = first(&cholesky);
    println!("1e-6 at {k_exact:?} (exact CG), {k_cholesky:?} (Cholesky)");
    assert_eq!(k_exact, k_cholesky);
    assert!(out.converged);
    assert!(out.rows.last().unwrap().pressure_error.unwrap() <= 1e-9);
    assert!(out.rows[1..]
        .iter()
        .all(|r| (3..=4).contains(&r.inner_iterations)));
}

/// The safeguarded rule on (III.88) converges to the direct pressure too (in about as many
/// iterations as (III.92) as printed), the relative residual with
/// [`ResidualScale::RightHandSide`] is r_k/‖(f, g)‖, and a warm start from the direct
/// pressure stops in row 0 or 1; a warm start of the wrong length is an error.
#[test]
fn safeguarded_rule_scale_and_warm_start() {
    let (blocks, reference) = channel();
    let s = &blocks.system;
    let options = UzawaOptions {
        cg_rule: CgRule::Safeguarded,
        scale: ResidualScale::RightHandSide,
        relative_tolerance: 1e-12,
        ..UzawaOptions::new(Variant::CgSsor)
    };
    let out = uzawa(s, &options, Some(&reference)).unwrap();
    let last = out.rows.last().unwrap();
    println!("safeguarded: {} rows, {:?}", out.rows.len(), last);
    assert!(out.converged && last.iteration <= 150);
    assert!(last.pressure_error.unwrap() <= 1e-9);
    let row0 = &out.rows[0];
    assert!((row0.relative_residual - row0.residual / s.rhs_norm()).abs() <= 1e-15);
    let warm = uzawa_from(s, &options, Some(&reference), Some(&reference)).unwrap();
    assert!(
        warm.converged && warm.rows.len() <= 2,
        "{}",
        warm.rows.len()
    );
    let err = uzawa_from(s, &options, None, Some(&reference[1..])).unwrap_err();
    assert!(err.to_string().contains("initial pressure"), "{err}");
}

/// A two-pressure complementarity problem solved by hand: A = I₂, B = I₂, C = 0, so
/// S = I and the solution of min ½|p|² − b_Sᵀp over p ≥ 0 is p = max(b_S, 0) with
/// b_S = g − f. With b_S = (2, −3): p = (2, 0), λ = Sp − b_S = (0, 3). The projected
/// safeguarded run finds it with a zero natural residual; the unprojected run finds
/// p = b_S.
#[test]
fn projected_safeguarded_run_solves_a_hand_sized_complementarity_problem() {
    let identity = || CsrMatrix::from_triplets(2, 2, vec![(0, 0, 1.0), (1, 1, 1.0)]);
    let system = SaddlePoint::new(
        identity(),
        identity(),
        CsrMatrix::from_triplets(2, 2, vec![]),
        vec![1.0, 1.0],
        vec![3.0, -2.0],
    )
    .unwrap();
    for projected in [false, true] {
        let options = UzawaOptions {
            cg_rule: CgRule::Safeguarded,
            projected,
            max_iterations: 20,
            relative_tolerance: 1e-14,
            ..UzawaOptions::new(Variant::CgSsor)
        };
        let out = uzawa(&system, &options, None).unwrap();
        let expected = if projected { [2.0, 0.0] } else { [2.0, -3.0] };
        assert!(
            out.converged,
            "projected {projected}: {:?}",
            out.rows.last()
        );
        for (p, e) in out.pressure.iter().zip(expected) {
            assert!(
                (p - e).abs() <= 1e-12,
                "projected {projected}: {:?}",
                out.pressure
            );
        }
    }
}
