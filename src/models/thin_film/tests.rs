//! Tests of the thin-film data: jets against finite differences, the general formulas against
//! printed identities and simplified forms, loads pinned bitwise, gap ranges.

use super::*;

/// Deterministic sample points in [0, 1]² (a few fixed ones plus an LCG sequence).
fn points(n: usize) -> Vec<[f64; 2]> {
    let mut pts = vec![
        [0.0, 0.0],
        [1.0, 1.0],
        [0.5, 0.5],
        [0.375, 0.375],
        [0.125, 0.8],
        [1.0, 0.3],
    ];
    let mut s: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = || {
        s = s
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    while pts.len() < n {
        pts.push([next(), next()]);
    }
    pts
}

fn all_gaps() -> Vec<Gap> {
    vec![
        Gap::Plain { g0: 0.1 },
        Gap::Linear {
            g0: 0.1,
            slope: 0.05,
        },
        Gap::WaveHorizontal {
            g0: 0.1,
            amplitude: 0.07,
            frequency: 2.0,
        },
        Gap::Hill {
            g0: 0.1,
            amplitude: 0.07,
            frequency: 2.0,
        },
        Gap::Hill {
            g0: 0.3,
            amplitude: -0.1,
            frequency: 0.7,
        },
    ]
}

/// Closed-form gap value, written independently of `Gap::jet`.
fn gap_value(gap: &Gap, x: [f64; 2]) -> f64 {
    use std::f64::consts::PI;
    match *gap {
        Gap::Plain { g0 } => g0,
        Gap::Linear { g0, slope } => g0 + slope * x[0],
        Gap::WaveHorizontal {
            g0,
            amplitude,
            frequency,
        } => g0 + amplitude * (2.0 * PI * frequency * x[0]).sin(),
        Gap::Hill {
            g0,
            amplitude,
            frequency,
        } => {
            let a = (2.0 * PI * frequency * x[0]).sin();
            let b = (2.0 * PI * frequency * x[1]).sin();
            g0 + amplitude * a * a * b * b
        }
        ref other => unreachable!("{other:?}: not one of the thesis's gaps"),
    }
}

fn shift(x: [f64; 2], h: [f64; 2]) -> [f64; 2] {
    [x[0] + h[0], x[1] + h[1]]
}

fn e(i: usize, h: f64) -> [f64; 2] {
    let mut r = [0.0; 2];
    r[i] = h;
    r
}

/// (a) Jet of every gap against finite differences, all orders up to three.
#[test]
fn gap_jets_match_finite_differences() {
    for gap in all_gaps() {
        for x in points(12) {
            let j = gap.jet(x);
            assert_eq!(j.valid_order(), Some(3));
            assert!((j.v - gap_value(&gap, x)).abs() < 1e-15);
            // Each order against central differences of the previous analytic order.
            let h = 1e-5;
            for i in 0..2 {
                let p = gap.jet(shift(x, e(i, h)));
                let m = gap.jet(shift(x, e(i, -h)));
                let fd = (p.v - m.v) / (2.0 * h);
                assert!((fd - j.d[i]).abs() < 1e-6, "{gap:?} d{i} at {x:?}");
                for a in 0..2 {
                    let fd = (p.d[a] - m.d[a]) / (2.0 * h);
                    assert!((fd - j.dd[i][a]).abs() < 1e-5, "{gap:?} dd at {x:?}");
                    for b in 0..2 {
                        let fd = (p.dd[a][b] - m.dd[a][b]) / (2.0 * h);
                        assert!(
                            (fd - j.ddd[i][a][b]).abs() < 1e-3,
                            "{gap:?} ddd[{i}][{a}][{b}] at {x:?}: {fd} vs {}",
                            j.ddd[i][a][b]
                        );
                    }
                }
            }
            // Third derivatives directly from values: δ_i δ_j δ_k with half-step h, Richardson-
            // extrapolated (h, h/2) to fourth order.
            for i in 0..2 {
                for a in 0..2 {
                    for b in 0..2 {
                        let fd = |h: f64| {
                            let mut s = 0.0;
                            for si in [-1.0, 1.0] {
                                for sa in [-1.0, 1.0] {
                                    for sb in [-1.0, 1.0] {
                                        let mut y = x;
                                        y[i] += si * h;
                                        y[a] += sa * h;
                                        y[b] += sb * h;
                                        s += si * sa * sb * gap_value(&gap, y);
                                    }
                                }
                            }
                            s / (8.0 * h * h * h)
                        };
                        let rich = (4.0 * fd(1e-3) - fd(2e-3)) / 3.0;
                        let exact = j.ddd[i][a][b];
                        assert!(
                            (rich - exact).abs() < 1e-5 * (1.0 + exact.abs()),
                            "{gap:?} ddd[{i}][{a}][{b}] at {x:?}: {rich} vs {exact}"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn jet_algebra_is_exact() {
    // f = x₁² x₂ + 3 x₂³, 1/f and f·(1/f) = 1, partial, laplacian, NaN bookkeeping.
    let x = [0.7, -1.3];
    let (x1, x2) = (Jet::variable(x, 0), Jet::variable(x, 1));
    let f = x1 * x1 * x2 + 3.0 * (x2 * x2 * x2);
    assert!((f.v - (0.49 * -1.3 + 3.0 * (-1.3f64).powi(3))).abs() < 1e-14);
    assert!((f.d[0] - 2.0 * 0.7 * -1.3).abs() < 1e-14);
    assert!((f.dd[1][1] - 18.0 * -1.3).abs() < 1e-14);
    assert!((f.ddd[0][0][1] - 2.0).abs() < 1e-14);
    assert!((f.ddd[1][0][0] - 2.0).abs() < 1e-14);
    assert!((f.ddd[1][1][1] - 18.0).abs() < 1e-14);
    let one = f * f.recip();
    assert!((one.v - 1.0).abs() < 1e-14);
    for i in 0..2 {
        assert!(one.d[i].abs() < 1e-12);
        for j in 0..2 {
            assert!(one.dd[i][j].abs() < 1e-12);
            for k in 0..2 {
                assert!(one.ddd[i][j][k].abs() < 1e-11);
            }
        }
    }
    let q = (x1 * x2) / f;
    let q2 = (x1 * x2) * f.recip();
    assert!((q.ddd[0][1][1] - q2.ddd[0][1][1]).abs() < 1e-12);
    let lap = f.laplacian();
    assert!((lap.v - (2.0 * -1.3 + 18.0 * -1.3)).abs() < 1e-13);
    assert!((lap.d[0] - 0.0).abs() < 1e-13 && (lap.d[1] - 20.0).abs() < 1e-13);
    assert_eq!(lap.valid_order(), Some(1));
    assert_eq!(f.partial(0).valid_order(), Some(2));
    assert_eq!(f.partial(0).partial(1).partial(1).valid_order(), Some(0));
    assert_eq!((f * lap).valid_order(), Some(1));
    assert!((f.partial(0).partial(1).v - 2.0 * 0.7).abs() < 1e-14);
}

/// Non-constant wall data for the identity tests of the general formulas.
fn general_film(x: [f64; 2]) -> FilmJets {
    let (x1, x2) = (Jet::variable(x, 0), Jet::variable(x, 1));
    let c = Jet::constant;
    let sin = |a: Jet| {
        let (s, co) = a.v.sin_cos();
        a.compose([s, co, -s, -co])
    };
    let exp = |a: Jet| {
        let e = a.v.exp();
        a.compose([e, e, e, e])
    };
    let z0 = c(0.05) * x1 * x2 - c(0.02) * sin(x1 + x2 * c(2.0));
    let z1 = c(0.3) + c(0.1) * sin(c(3.0) * x1) * exp(c(0.5) * x2) + c(0.04) * x2 * x2;
    let v0 = [
        c(1.0) + x1 * x2,
        sin(x2) - c(2.0) * x1 * x1,
        exp(c(0.3) * x1) * x2,
    ];
    let v1 = [
        c(3.0) * x2 * x2 * x1 - c(1.0),
        exp(c(-0.2) * x1 * x2),
        sin(c(2.0) * x1) + x2,
    ];
    let kappa = [x1 * x1 + c(0.5), sin(x2)];
    FilmJets::from_walls(z0, z1, v0, v1, kappa)
}

fn close(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= 1e-10 * scale.max(a.abs()).max(b.abs())
}

/// Identities printed in Chapter I, checked with non-constant wall data.
#[test]
fn general_formulas_satisfy_printed_identities() {
    for x in points(20) {
        let f = general_film(x);
        let g3 = f.gamma3();
        for mu in 0..2 {
            // (I.47) first line: −∂_ν(v_μ(z₁)∂_ν z₁ − v_μ(z₀)∂_ν z₀) − ∂_ν v_μ(z₁)∂_ν z₁ + ∂_ν v_μ(z₀)∂_ν z₀.
            let mut first = Jet::ZERO;
            for nu in 0..2 {
                first = first
                    - (f.v1[mu] * f.z1.partial(nu) - f.v0[mu] * f.z0.partial(nu)).partial(nu)
                    - f.v1[mu].partial(nu) * f.z1.partial(nu)
                    + f.v0[mu].partial(nu) * f.z0.partial(nu);
            }
            // (I.47) third line: −Δ(v̄_μ g + δv_μ z̄) + Δv̄_μ g + Δδv_μ z̄.
            let third = -(f.vbar[mu] * f.g + f.dv[mu] * f.zbar).laplacian()
                + f.vbar[mu].laplacian() * f.g
                + f.dv[mu].laplacian() * f.zbar;
            for (a, b) in [(first, g3[mu]), (third, g3[mu])] {
                assert_eq!(b.valid_order(), Some(1));
                assert!(close(a.v, b.v, 1.0));
                assert!(close(a.d[0], b.d[0], 1.0) && close(a.d[1], b.d[1], 1.0));
            }
        }
        // (I.43): δv_μ ∂_μ z̄ + v̄_μ ∂_μ g = v_μ(z₁) ∂_μ z₁ − v_μ(z₀) ∂_μ z₀, hence (I.50).
        let mut lhs = 0.0;
        let mut rhs = 0.0;
        for mu in 0..2 {
            lhs += f.dv[mu].v * f.zbar.d[mu] + f.vbar[mu].v * f.g.d[mu];
            rhs += f.v1[mu].v * f.z1.d[mu] - f.v0[mu].v * f.z0.d[mu];
        }
        assert!(close(lhs, rhs, 1.0));
        let sigma_alt = -f.dv[2].v + rhs + (0..2).map(|m| f.vbar[m].v * f.g.d[m]).sum::<f64>();
        assert!(close(f.sigma3().v, sigma_alt, 1.0));
        // (I.77) second form: R₃ = (g/12) ∂_ν( g (Δv̄_ν g + Δδv_ν z̄ − Δ(δv_ν z̄)) ).
        let mut s = Jet::ZERO;
        for nu in 0..2 {
            let inner = f.vbar[nu].laplacian() * f.g + f.dv[nu].laplacian() * f.zbar
                - (f.dv[nu] * f.zbar).laplacian();
            s += (f.g * inner).partial(nu);
        }
        let r3_alt = (f.g * s).scale(1.0 / 12.0);
        assert!(close(f.r3().v, r3_alt.v, 1.0));
        // (I.81) expanded form of R₃c (printed source):
        // R₃ + (g/12)∂_μ[ 2g∂_μ∂_ν(g v̄_ν) + g∂_μ∂_ν(δv_ν z̄) − g(g∂_μ∂_ν v̄_ν + z̄∂_μ∂_ν δv_ν) − g²∂_μ(δv₃/g) ].
        let (g, zb) = (f.g, f.zbar);
        let mut dgv = Jet::ZERO;
        let mut ddz = Jet::ZERO;
        let mut dvb = Jet::ZERO;
        let mut ddv = Jet::ZERO;
        for nu in 0..2 {
            dgv += (g * f.vbar[nu]).partial(nu);
            ddz += (f.dv[nu] * zb).partial(nu);
            dvb += f.vbar[nu].partial(nu);
            ddv += f.dv[nu].partial(nu);
        }
        let q = f.dv[2] / g;
        let mut s = Jet::ZERO;
        for mu in 0..2 {
            let inner = (g * dgv.partial(mu)).scale(2.0) + g * ddz.partial(mu)
                - g * (g * dvb.partial(mu) + zb * ddv.partial(mu))
                - g * g * q.partial(mu);
            s += inner.partial(mu);
        }
        let r3c_alt = f.r3().v + (g * s).v / 12.0;
        let r3c = f.r3c(CavitationSource::Printed).v;
        assert!(close(r3c, r3c_alt, 1.0), "{r3c} vs {r3c_alt}");
        // The loads are finite (no order was missing) and consistent with the rhs forms.
        let lr = f.reynolds_load().v;
        assert!(lr.is_finite());
        assert!(close(lr, -12.0 * f.reynolds_rhs().v / (g.v * g.v), 1.0));
        for src in [CavitationSource::Printed, CavitationSource::SelfConsistent] {
            let lc = f.cavitation_load(src).v;
            assert!(close(
                lc,
                -12.0 * f.cavitation_rhs(src).v / (g.v * g.v),
                1.0
            ));
        }
    }
}

/// Names of the quantities compared in `general_formulas_match_simplified_forms`.
const QUANTITIES: [&str; 16] = [
    "gamma3_1",
    "gamma3_2",
    "gamma_1",
    "gamma_2",
    "sigma3",
    "R1",
    "R3",
    "gamma3c_1 (printed)",
    "gamma3c_2 (printed)",
    "gamma3c_1 (self-consistent)",
    "gamma3c_2 (self-consistent)",
    "R3c (printed)",
    "R3c (self-consistent)",
    "l_R",
    "l_Rc (printed)",
    "l_Rc (self-consistent)",
];

/// The quantities of `QUANTITIES` from the general formulas.
fn general(film: &ThinFilm, x: [f64; 2]) -> [f64; 16] {
    use CavitationSource::{Printed as P, SelfConsistent as S};
    let (g3, ga) = (film.gamma3(x), film.gamma(x));
    let (cp, cs) = (film.gamma3c(x, P), film.gamma3c(x, S));
    [
        g3[0],
        g3[1],
        ga[0],
        ga[1],
        film.sigma3(x),
        film.r1(x),
        film.r3(x),
        cp[0],
        cp[1],
        cs[0],
        cs[1],
        film.r3c(x, P),
        film.r3c(x, S),
        film.reynolds_load(x),
        film.cavitation_load(x, P),
        film.cavitation_load(x, S),
    ]
}

/// The quantities of `QUANTITIES` from the simplified forms of the examples (constant
/// δv, v(z₀) = 0, z₀ = 0, so z̄ = g/2, v̄ = δv/2), derived independently by hand.
fn simplified(film: &ThinFilm, x: [f64; 2]) -> [f64; 16] {
    let j = film.gap.jet(x);
    let dv = film.upper_wall_velocity;
    let g = j.v;
    let lap = j.dd[0][0] + j.dd[1][1];
    let lap_d = [
        j.ddd[0][0][0] + j.ddd[1][1][0],
        j.ddd[0][0][1] + j.ddd[1][1][1],
    ];
    let dot_grad = dv[0] * j.d[0] + dv[1] * j.d[1];
    // ∂_ν(gΔg) = ∂_ν g Δg + g ∂_ν Δg.
    let d_glap = |nu: usize| j.d[nu] * lap + g * lap_d[nu];
    // γ₃ = −δv_μ Δg; γ = γ₃ + 6 δv_μ / g.
    let gamma3 = [-dv[0] * lap, -dv[1] * lap];
    let gamma = [gamma3[0] + 6.0 * dv[0] / g, gamma3[1] + 6.0 * dv[1] / g];
    // σ₃ = −δv₃ + (3/2) δv_μ ∂_μ g; R₁ = −½ δv_ν ∂_ν g; R₃ = −(g/24) δv_ν ∂_ν(gΔg).
    let sigma3 = -dv[2] + 1.5 * dot_grad;
    let r1 = -0.5 * dot_grad;
    let r3 = -(g / 24.0) * (dv[0] * d_glap(0) + dv[1] * d_glap(1));
    // γ₃c = −δv_μ Δg ± (δv_ν ∂_μ∂_ν g + δv₃ ∂_μ g / g).
    let mix = |mu: usize| dv[0] * j.dd[mu][0] + dv[1] * j.dd[mu][1];
    let c_p = [0, 1].map(|mu| -dv[mu] * lap + mix(mu) + dv[2] * j.d[mu] / g);
    let c_s = [0, 1].map(|mu| -dv[mu] * lap - mix(mu) - dv[2] * j.d[mu] / g);
    // t = δv_ν ∂_μ(g ∂_μ∂_ν g) = δv_ν (∂_μ g ∂_μ∂_ν g + g ∂_ν Δg).
    let mut t = 0.0;
    for nu in 0..2 {
        t += dv[nu] * (j.d[0] * j.dd[0][nu] + j.d[1] * j.dd[1][nu] + g * lap_d[nu]);
    }
    // R₃c = R₃ + (g/12)[(3/2) t + δv₃ Δg] (printed); the self-consistent source changes the
    // bracket to −(1/2) t − δv₃ Δg.
    let r3c_p = r3 + (g / 12.0) * (1.5 * t + dv[2] * lap);
    let r3c_s = r3 + (g / 12.0) * (-0.5 * t - dv[2] * lap);
    let load = |r: f64| -12.0 * (dv[2] + r1 + r) / (g * g);
    [
        gamma3[0],
        gamma3[1],
        gamma[0],
        gamma[1],
        sigma3,
        r1,
        r3,
        c_p[0],
        c_p[1],
        c_s[0],
        c_s[1],
        r3c_p,
        r3c_s,
        load(r3),
        load(r3c_p),
        load(r3c_s),
    ]
}

/// (b) General formulas against the simplified forms of the examples, all 14 examples, 25 points
/// each. The relative error is measured against the largest |simplified value| of that
/// quantity over the sample points of that example (1 if the quantity vanishes identically).
#[test]
fn general_formulas_match_simplified_forms() {
    let pts = points(25);
    let mut overall: f64 = 0.0;
    for eq in EXAMPLES {
        let film = example(eq).unwrap();
        let gen: Vec<[f64; 16]> = pts.iter().map(|&x| general(&film, x)).collect();
        let simp: Vec<[f64; 16]> = pts.iter().map(|&x| simplified(&film, x)).collect();
        for (q, name) in QUANTITIES.iter().enumerate() {
            let m = simp.iter().map(|s| s[q].abs()).fold(0.0, f64::max);
            let scale = if m > 0.0 { m } else { 1.0 };
            for ((x, a), b) in pts.iter().zip(&gen).zip(&simp) {
                let rel = (a[q] - b[q]).abs() / scale;
                overall = overall.max(rel);
                assert!(
                    rel <= 1e-10,
                    "{eq} {name} at {x:?}: general {} vs simplified {} (scale {scale})",
                    a[q],
                    b[q]
                );
            }
        }
    }
    println!("largest relative deviation general vs simplified: {overall:e}");
}

/// (c) Plain squeeze: l_R = 12000 for (IV.7) and −12000 for (IV.8), everywhere.
#[test]
fn plain_gap_loads() {
    let (a, b) = (example("IV.7").unwrap(), example("(IV.8)").unwrap());
    for x in points(20) {
        assert!((a.reynolds_load(x) - 12000.0).abs() < 1e-9);
        assert!((b.reynolds_load(x) + 12000.0).abs() < 1e-9);
        for src in [CavitationSource::Printed, CavitationSource::SelfConsistent] {
            assert!((b.cavitation_load(x, src) + 12000.0).abs() < 1e-9);
        }
        assert_eq!(a.gap(x), (0.1, [0.0, 0.0], 0.0));
    }
    assert!(example("IV.21").is_none());
    assert!(example("IV.6").is_none());
}

/// (d) Pairs with Δg = 0 and reversed wall velocity have opposite loads.
#[test]
fn reversed_pairs_have_opposite_loads() {
    for (p, q) in [("IV.7", "IV.8"), ("IV.10", "IV.11"), ("IV.12", "IV.13")] {
        let (a, b) = (example(p).unwrap(), example(q).unwrap());
        for x in points(20) {
            assert_eq!(a.gap(x).2, 0.0);
            let (la, lb) = (a.reynolds_load(x), b.reynolds_load(x));
            assert!(
                (la + lb).abs() <= 1e-12 * la.abs().max(1.0),
                "{p}/{q} at {x:?}"
            );
            for src in [CavitationSource::Printed, CavitationSource::SelfConsistent] {
                let (ca, cb) = (a.cavitation_load(x, src), b.cavitation_load(x, src));
                assert!((ca + cb).abs() <= 1e-12 * ca.abs().max(1.0));
            }
        }
    }
}

/// The loads of the examples whose gap needs no libm call (plain and linear: the bits do not
/// depend on the platform's `sin`) are pinned bitwise: a checksum over a 40 × 40 grid of l_R
/// and of l_{R,c} in each reading, recorded before the jet operations were inlined ([`Jet`]
/// type docs). A change to the jet arithmetic or to the formulas that is meant to keep every
/// value must keep these.
#[test]
fn loads_are_bitwise_pinned() {
    use CavitationSource::{Printed, Reynolds, SelfConsistent};
    let pinned = [
        ("IV.7", 0xf26a_9000_0000_5d77),
        ("IV.8", 0x8d95_6fff_ffff_e098),
        ("IV.9", 0x7fff_ffff_ffff_bdef),
        ("IV.10", 0x2196_ebd5_835f_18d4),
        ("IV.11", 0x5e69_142a_7ca0_a53b),
        ("IV.12", 0x6f12_5c60_8e8e_1f9d),
        ("IV.13", 0x10ed_a39f_7171_a272),
        ("IV.14", 0x7fff_ffff_ffff_bdef),
    ];
    let n = 40;
    let mut failed = false;
    for (eq, expected) in pinned {
        let film = example(eq).unwrap();
        let mut bits = 0u64;
        for i in 0..=n {
            for k in 0..=n {
                let x = [i as f64 / n as f64, k as f64 / n as f64];
                let loads = [
                    film.reynolds_load(x),
                    film.cavitation_load(x, Printed),
                    film.cavitation_load(x, SelfConsistent),
                    film.cavitation_load(x, Reynolds),
                ];
                for l in loads {
                    bits = bits.rotate_left(5) ^ l.to_bits();
                }
            }
        }
        println!("(\"{eq}\", 0x{bits:016x}),");
        failed |= bits != expected;
    }
    assert!(!failed, "checksums differ (printed above)");
}

/// The `reynolds` reading takes the source terms without cavitation: γ₃c = γ₃, R₃c = R₃,
/// l_{R,c} = l_R (bitwise); on the wave gap with upward velocity it differs from the printed
/// R₃c by (g/12)δv₃Δg.
#[test]
fn reynolds_reading_is_the_source_without_cavitation() {
    for eq in EXAMPLES {
        let film = example(eq).unwrap();
        for x in points(20) {
            let f = film.film_jets(x);
            let (c, r) = (f.gamma3c(CavitationSource::Reynolds), f.gamma3());
            assert_eq!([c[0].v, c[1].v], [r[0].v, r[1].v], "{eq}");
            assert_eq!(
                film.cavitation_load(x, CavitationSource::Reynolds)
                    .to_bits(),
                film.reynolds_load(x).to_bits(),
                "{eq} at {x:?}"
            );
        }
    }
    let film = example("IV.16").unwrap();
    for x in points(20) {
        let (g, _, lap) = film.gap(x);
        let d = film.r3c(x, CavitationSource::Printed) - film.r3c(x, CavitationSource::Reynolds);
        assert!(
            (d - g / 12.0 * 10.0 * lap).abs() <= 1e-9 * (1.0 + lap.abs()),
            "{x:?}"
        );
    }
}

#[test]
fn printed_and_self_consistent_coincide_without_curvature() {
    // Plain gaps: γ₃c identical. Linear gaps: γ₃c differ (±δv₃∂g/g) but R₃c does not.
    for eq in [
        "IV.7", "IV.8", "IV.9", "IV.10", "IV.11", "IV.12", "IV.13", "IV.14",
    ] {
        let film = example(eq).unwrap();
        for x in points(20) {
            let p = film.r3c(x, CavitationSource::Printed);
            let s = film.r3c(x, CavitationSource::SelfConsistent);
            assert!((p - s).abs() < 1e-12, "{eq}");
        }
    }
    let film = example("IV.11").unwrap();
    let x = [0.4, 0.6];
    let p = film.gamma3c(x, CavitationSource::Printed)[0];
    let s = film.gamma3c(x, CavitationSource::SelfConsistent)[0];
    let expected = 10.0 * 0.05 / (0.1 + 0.05 * 0.4);
    assert!((p - expected).abs() < 1e-12 && (s + expected).abs() < 1e-12);
}

#[test]
fn gap_extrema_on_unit_square() {
    let ex = |eq: &str| example(eq).unwrap().gap;
    assert_eq!(ex("IV.7").min_on_unit_square(), 0.1);
    assert_eq!(ex("IV.10").min_on_unit_square(), 0.1);
    assert!((ex("IV.10").max_on_unit_square() - 0.15).abs() < 1e-15);
    assert!((ex("IV.15").min_on_unit_square() - 0.03).abs() < 1e-15);
    assert!((ex("IV.15").max_on_unit_square() - 0.17).abs() < 1e-15);
    assert_eq!(ex("IV.18").min_on_unit_square(), 0.1);
    assert!((ex("IV.18").max_on_unit_square() - 0.17).abs() < 1e-15);
    // Brute force on a fine grid never goes below the exact minimum, and gets close to it.
    for gap in all_gaps().into_iter().chain([
        Gap::Linear {
            g0: 0.2,
            slope: -0.1,
        },
        Gap::WaveHorizontal {
            g0: 0.2,
            amplitude: -0.05,
            frequency: 0.3,
        },
        Gap::WaveHorizontal {
            g0: 0.2,
            amplitude: 0.05,
            frequency: 0.3,
        },
    ]) {
        let (lo, hi) = (gap.min_on_unit_square(), gap.max_on_unit_square());
        let n = 400;
        let (mut bmin, mut bmax) = (f64::INFINITY, f64::NEG_INFINITY);
        for i in 0..=n {
            for k in 0..=n {
                let v = gap.value([i as f64 / n as f64, k as f64 / n as f64]);
                bmin = bmin.min(v);
                bmax = bmax.max(v);
            }
        }
        assert!(bmin >= lo - 1e-15 && bmax <= hi + 1e-15, "{gap:?}");
        assert!(
            bmin - lo < 1e-4 && hi - bmax < 1e-4,
            "{gap:?}: {bmin} {lo} {bmax} {hi}"
        );
    }
}

/// The extrema on boxes agree with brute force on a fine grid of each box (never beyond
/// the exact values, close to them), and on [0, 1]² with the unit-square extrema.
#[test]
fn gap_extrema_on_boxes() {
    let boxes = [
        [0.0, 0.0, 0.125, 0.125],
        [0.1, 0.2, 0.3, 0.45],
        [0.3, 0.0, 0.4, 1.0],
        [0.55, 0.6, 0.7, 0.65],
        [0.6, 0.3, 0.62, 0.31],
    ];
    let gaps = all_gaps().into_iter().chain([Gap::Linear {
        g0: 0.2,
        slope: -0.1,
    }]);
    for gap in gaps {
        let unit = gap.range_on_box([0.0, 0.0, 1.0, 1.0]);
        assert!((unit.0 - gap.min_on_unit_square()).abs() < 1e-15, "{gap:?}");
        assert!((unit.1 - gap.max_on_unit_square()).abs() < 1e-15, "{gap:?}");
        for b in boxes {
            let (lo, hi) = gap.range_on_box(b);
            let n = 200;
            let (mut bmin, mut bmax) = (f64::INFINITY, f64::NEG_INFINITY);
            for i in 0..=n {
                for k in 0..=n {
                    let x = b[0] + (b[2] - b[0]) * i as f64 / n as f64;
                    let y = b[1] + (b[3] - b[1]) * k as f64 / n as f64;
                    let v = gap.value([x, y]);
                    bmin = bmin.min(v);
                    bmax = bmax.max(v);
                }
            }
            assert!(
                bmin >= lo - 1e-15 && bmax <= hi + 1e-15,
                "{gap:?} {b:?}: [{lo}, {hi}] vs [{bmin}, {bmax}]"
            );
            assert!(
                bmin - lo < 1e-5 && hi - bmax < 1e-5,
                "{gap:?} {b:?}: [{lo}, {hi}] vs [{bmin}, {bmax}]"
            );
        }
    }
}

// The gaps of scenes of the user's own: step, parabolic and tabulated.

/// Rows of a tabulated gap over [−0.05, 1.05], unevenly spaced: a bump over a slope.
fn profile_rows() -> Vec<[f64; 2]> {
    let xs: [f64; 10] = [-0.05, 0.1, 0.18, 0.3, 0.45, 0.5, 0.62, 0.8, 0.9, 1.05];
    xs.iter()
        .map(|&x| {
            [
                x,
                0.1 + 0.05 * x + 0.04 * (-((x - 0.5) / 0.15).powi(2)).exp(),
            ]
        })
        .collect()
}

fn own_gaps() -> Vec<Gap> {
    vec![
        Gap::Step {
            g_in: 0.2,
            g_out: 0.1,
            at: 0.6,
            s: 0.02,
        },
        Gap::Step {
            g_in: 0.05,
            g_out: 0.15,
            at: 0.3,
            s: 0.2,
        },
        Gap::Parabolic {
            g0: 0.05,
            center: [0.4, 0.0],
            radius: [2.0, f64::INFINITY],
        },
        Gap::Parabolic {
            g0: 0.05,
            center: [0.4, 0.7],
            radius: [2.0, 0.5],
        },
        Gap::Tabulated(std::sync::Arc::new(CubicSpline::natural(&profile_rows()))),
    ]
}

/// Whether `x` lies within `d` of a row of the tabulated gap (its third derivative jumps there).
fn near_a_row(x: f64, d: f64) -> bool {
    profile_rows().iter().any(|r| (r[0] - x).abs() < d)
}

/// The jet of every new gap against central differences of the jet one order lower, at points
/// whose stencil does not cross a row of the spline (where g''' jumps).
#[test]
fn own_gap_jets_match_finite_differences() {
    let h = 1e-5;
    for gap in own_gaps() {
        for x in points(40) {
            if near_a_row(x[0], 2.0 * h) {
                continue;
            }
            let j = gap.jet(x);
            assert_eq!(j.valid_order(), Some(3), "{gap:?}");
            for i in 0..2 {
                let p = gap.jet(shift(x, e(i, h)));
                let m = gap.jet(shift(x, e(i, -h)));
                let fd = (p.v - m.v) / (2.0 * h);
                assert!((fd - j.d[i]).abs() < 1e-7, "{gap:?} d{i} at {x:?}");
                for a in 0..2 {
                    let fd = (p.d[a] - m.d[a]) / (2.0 * h);
                    assert!(
                        (fd - j.dd[i][a]).abs() < 1e-5 * (1.0 + j.dd[i][a].abs()),
                        "{gap:?} dd[{i}][{a}] at {x:?}: {fd} vs {}",
                        j.dd[i][a]
                    );
                    for b in 0..2 {
                        let fd = (p.dd[a][b] - m.dd[a][b]) / (2.0 * h);
                        let exact = j.ddd[i][a][b];
                        assert!(
                            (fd - exact).abs() < 1e-4 * (1.0 + exact.abs()),
                            "{gap:?} ddd[{i}][{a}][{b}] at {x:?}: {fd} vs {exact}"
                        );
                    }
                }
            }
        }
    }
}

/// The step, the parabola and the spline in closed form, and x₂ read only where the gap says so.
#[test]
fn own_gap_values() {
    let step = Gap::Step {
        g_in: 0.2,
        g_out: 0.1,
        at: 0.6,
        s: 0.02,
    };
    assert!((step.value([0.6, 0.3]) - 0.15).abs() < 1e-16);
    assert!((step.value([0.0, 0.0]) - 0.2).abs() < 0.1 * 0.02 * 0.02 / (4.0 * 0.36) + 1e-15);
    assert!((step.value([1.0, 0.0]) - 0.1).abs() < 0.1 * 0.02 * 0.02 / (4.0 * 0.16) + 1e-15);
    // θ_s'' is odd and vanishes at the step; θ_s''' there is −(3/2)/s³.
    let at = step.jet([0.6, 0.0]);
    assert_eq!(at.dd[0][0], 0.0);
    let expected = (-0.1) * (-1.5 / (0.02 * 0.02 * 0.02));
    assert!((at.ddd[0][0][0] - expected).abs() < 1e-12 * expected);
    let journal = Gap::Parabolic {
        g0: 0.05,
        center: [0.4, 0.7],
        radius: [2.0, f64::INFINITY],
    };
    assert_eq!(journal.value([0.4, 0.9]), 0.05);
    assert!((journal.value([0.9, 0.1]) - (0.05 + 0.25 / 4.0)).abs() < 1e-16);
    assert!(!journal.varies_in_x2() && journal.varies_in_x1());
    let ball = Gap::Parabolic {
        g0: 0.05,
        center: [0.4, 0.7],
        radius: [2.0, 0.5],
    };
    assert!((ball.value([0.9, 0.2]) - (0.05 + 0.25 / 4.0 + 0.25)).abs() < 1e-15);
    assert!(ball.varies_in_x2());
    // Functions of x₁ alone give the same bits whatever x₂.
    for gap in own_gaps().into_iter().filter(|g| !g.varies_in_x2()) {
        for x in points(20) {
            let (a, b) = (gap.jet(x), gap.jet([x[0], 0.123]));
            assert!(
                a.v == b.v && a.d == b.d && a.dd == b.dd && a.ddd == b.ddd,
                "{gap:?}"
            );
        }
    }
}

/// The natural spline through (0, 0), (1, 1), (2, 0): M₁ = −3, so on [0, 1]
/// s = 1.5 t − 0.5 t³ (by hand from the tridiagonal system).
#[test]
fn spline_of_three_points_by_hand() {
    let s = CubicSpline::natural(&[[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]]);
    let [v, d, dd, ddd] = s.derivatives(0.5);
    assert!((v - 0.6875).abs() < 1e-15 && (d - 1.125).abs() < 1e-15);
    assert!((dd + 1.5).abs() < 1e-15 && (ddd + 3.0).abs() < 1e-15);
    // Symmetric about x = 1.
    assert!((s.value(1.5) - 0.6875).abs() < 1e-15);
    // Beyond the ends: the straight line of the end slope, ±1.5.
    assert_eq!(s.derivatives(-1.0), [-1.5, 1.5, 0.0, 0.0]);
    assert!((s.value(3.0) + 1.5).abs() < 1e-15);
}

/// The spline meets the conditions that define the natural cubic spline: it passes through
/// every row, is a cubic on each piece (g''' constant there), value, slope and curvature are
/// continuous at the rows, and the curvature is 0 at both ends. It reproduces a straight line.
#[test]
fn spline_is_the_natural_cubic_spline() {
    let rows = profile_rows();
    let s = CubicSpline::natural(&rows);
    for (k, &[x, y]) in rows.iter().enumerate() {
        assert!((s.value(x) - y).abs() < 1e-15, "row {k}");
        if k > 0 && k + 1 < rows.len() {
            // Left limits by Taylor from just before the knot.
            let eps = 1e-7;
            let [v, d, dd, ddd] = s.derivatives(x - eps);
            let left = [
                v + eps * d + 0.5 * eps * eps * dd + eps.powi(3) / 6.0 * ddd,
                d + eps * dd + 0.5 * eps * eps * ddd,
                dd + eps * ddd,
            ];
            let right = s.derivatives(x);
            for (o, (l, r)) in left.iter().zip(right).enumerate() {
                assert!((l - r).abs() < 1e-9 * (1.0 + r.abs()), "row {k} order {o}");
            }
        }
    }
    for w in rows.windows(2) {
        let (a, b) = (w[0][0], w[1][0]);
        let third = s.derivatives(a + 0.25 * (b - a))[3];
        assert_eq!(third, s.derivatives(a + 0.75 * (b - a))[3]);
    }
    let (first, last) = (rows[0][0], rows[rows.len() - 1][0]);
    assert!(s.derivatives(first)[2].abs() < 1e-12);
    assert!(s.derivatives(last)[2].abs() < 1e-12);
    let line: Vec<[f64; 2]> = rows.iter().map(|r| [r[0], 2.0 - 3.0 * r[0]]).collect();
    let straight = CubicSpline::natural(&line);
    for x in points(30) {
        let [v, d, dd, ddd] = straight.derivatives(x[0]);
        assert!((v - (2.0 - 3.0 * x[0])).abs() < 1e-14 && (d + 3.0).abs() < 1e-13);
        assert!(dd.abs() < 1e-12 && ddd.abs() < 1e-10);
    }
    // Fewer than two rows: NaN, not a panic.
    assert!(CubicSpline::natural(&[]).value(0.5).is_nan());
    assert!(CubicSpline::natural(&[[0.0, 1.0]]).value(0.5).is_nan());
}

/// The ranges of the new gaps on boxes (also boxes reaching beyond the rows of the spline)
/// enclose every sampled value and are close to the sampled extremes.
#[test]
fn own_gap_ranges_enclose_sampled_values() {
    let boxes = [
        [0.0, 0.0, 1.0, 1.0],
        [0.0, 0.0, 0.125, 0.125],
        [0.1, 0.2, 0.3, 0.45],
        [0.35, 0.0, 0.65, 1.0],
        [0.55, 0.6, 0.7, 0.65],
        [0.59, 0.3, 0.61, 0.31],
        [-0.3, 0.0, 0.05, 0.1],
        [0.9, 0.5, 1.4, 0.9],
    ];
    for gap in own_gaps() {
        for b in boxes {
            let (lo, hi) = gap.range_on_box(b);
            let n = 200;
            let (mut bmin, mut bmax) = (f64::INFINITY, f64::NEG_INFINITY);
            for i in 0..=n {
                for k in 0..=n {
                    let x = b[0] + (b[2] - b[0]) * i as f64 / n as f64;
                    let y = b[1] + (b[3] - b[1]) * k as f64 / n as f64;
                    let v = gap.value([x, y]);
                    bmin = bmin.min(v);
                    bmax = bmax.max(v);
                }
            }
            assert!(
                bmin >= lo && bmax <= hi,
                "{gap:?} {b:?}: [{lo}, {hi}] vs [{bmin}, {bmax}]"
            );
            assert!(
                bmin - lo < 1e-5 && hi - bmax < 1e-5,
                "{gap:?} {b:?}: [{lo}, {hi}] vs [{bmin}, {bmax}]"
            );
        }
    }
    // A spline that overshoots below zero between positive rows: the range sees the dip.
    // (−0.1193 at x₁ ≈ 0.058, by an independent evaluation.)
    let rows = [[0.0, 0.01], [0.1, 0.01], [0.2, 1.0], [0.3, 1.0], [0.4, 1.0]];
    let sharp = CubicSpline::natural(&rows);
    let (min, at, _) = sharp.range(0.0, 0.4);
    assert!(
        (min + 0.119285).abs() < 1e-5 && (at - 0.0577).abs() < 1e-3,
        "{min} at {at}"
    );
    assert!(min <= sharp.value(at));
}
