//! Gauss–Legendre rules on the unit interval [0, 1] and their tensor products on cells.

/// Points and weights of the n-point Gauss rule on [0, 1] (n = 1…4).
pub fn gauss(n: usize) -> (&'static [f64], &'static [f64]) {
    const P1: [f64; 1] = [0.5];
    const W1: [f64; 1] = [1.0];
    const P2: [f64; 2] = [0.211_324_865_405_187_1, 0.788_675_134_594_812_9];
    const W2: [f64; 2] = [0.5, 0.5];
    const P3: [f64; 3] = [0.112_701_665_379_258_3, 0.5, 0.887_298_334_620_741_7];
    const W3: [f64; 3] = [5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0];
    const P4: [f64; 4] = [
        0.069_431_844_202_973_71,
        0.330_009_478_207_571_87,
        0.669_990_521_792_428_1,
        0.930_568_155_797_026_3,
    ];
    const W4: [f64; 4] = [
        0.173_927_422_568_726_93,
        0.326_072_577_431_273_07,
        0.326_072_577_431_273_07,
        0.173_927_422_568_726_93,
    ];
    match n {
        1 => (&P1, &W1),
        2 => (&P2, &W2),
        3 => (&P3, &W3),
        4 => (&P4, &W4),
        _ => panic!("Gauss rule with {n} points is not tabulated"),
    }
}

/// Tensor-product rule on the reference square \[0,1\]²: `(ξ, η, weight)`.
pub fn square(n: usize) -> Vec<(f64, f64, f64)> {
    let (p, w) = gauss(n);
    let mut q = Vec::with_capacity(n * n);
    for j in 0..n {
        for i in 0..n {
            q.push((p[i], p[j], w[i] * w[j]));
        }
    }
    q
}

/// The tensor-product Gauss rule with `N` = n² points on the reference square (n = 1…4) as an
/// array, for [`super::CellValues`]: `(ξ, η, weight)` in the order of [`square`].
pub fn square_rule<const N: usize>() -> [(f64, f64, f64); N] {
    let n = match N {
        1 => 1,
        4 => 2,
        9 => 3,
        16 => 4,
        _ => panic!("no tensor Gauss rule with {N} points"),
    };
    let q = square(n);
    std::array::from_fn(|i| q[i])
}
