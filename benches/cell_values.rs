//! Cell-values benchmark (not a test): the physical gradients, det J and Hessian of Q₁ on
//! 100 000 random convex quadrilaterals at the 3×3 Gauss points, and the reference coordinates
//! of a point, computed by the library (on nalgebra's `Matrix2`) and by the closed formulas on
//! arrays it replaced, in alternating rounds on one thread. Prints nanoseconds per cell of each
//! and their ratio, and fails unless every result of the two is bitwise the same.
//!
//! `cargo bench --bench cell_values`

use std::hint::black_box;
use std::time::Instant;

use tribo::fe::cell_values::{gradients, hessian};
use tribo::fe::quadrature::square_rule;
use tribo::mesh::{bilinear_gradients, CellShape};

/// What one cell contributes: the gradients, det J and Hessian at each point, and the reference
/// coordinates of one point (as bits, so that −0 and +0 or two NaNs are told apart).
fn cell(shape: &CellShape, u: [f64; 4], p: [f64; 2], library: bool, out: &mut Vec<u64>) {
    for &(xi, eta, _) in &square_rule::<9>() {
        let (g, det, h) = if library {
            let det = shape.jacobian(xi, eta).determinant();
            (gradients(shape, xi, eta), det, hessian(shape, u, xi, eta))
        } else {
            let j = closed::jacobian(shape, xi, eta);
            let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
            (
                closed::gradients(shape, xi, eta),
                det,
                closed::hessian(shape, u, xi, eta),
            )
        };
        out.extend(g.iter().flatten().map(|v| v.to_bits()));
        out.push(det.to_bits());
        out.extend(h.iter().flatten().map(|v| v.to_bits()));
    }
    let (xi, eta) = if library {
        shape.reference(p)
    } else {
        closed::reference(shape, p)
    };
    out.extend([xi.to_bits(), eta.to_bits()]);
}

/// The closed formulas on arrays that `CellShape` and `cell_values` used before nalgebra.
mod closed {
    use super::*;
    use tribo::mesh::bilinear;

    fn evaluate(shape: &CellShape, u: [f64; 4], xi: f64, eta: f64) -> (f64, [f64; 2]) {
        let v = bilinear(xi, eta);
        let g = gradients(shape, xi, eta);
        let mut val = 0.0;
        let mut grad = [0.0; 2];
        for i in 0..4 {
            val += u[i] * v[i];
            grad[0] += u[i] * g[i][0];
            grad[1] += u[i] * g[i][1];
        }
        (val, grad)
    }

    pub fn jacobian(shape: &CellShape, xi: f64, eta: f64) -> [[f64; 2]; 2] {
        let g = bilinear_gradients(xi, eta);
        let mut j = [[0.0; 2]; 2];
        for (x, g) in shape.vertices().iter().zip(g) {
            for (row, &xi) in j.iter_mut().zip(x) {
                row[0] += xi * g[0];
                row[1] += xi * g[1];
            }
        }
        j
    }

    pub fn gradients(shape: &CellShape, xi: f64, eta: f64) -> [[f64; 2]; 4] {
        let j = jacobian(shape, xi, eta);
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        bilinear_gradients(xi, eta).map(|g| {
            [
                (j[1][1] * g[0] - j[1][0] * g[1]) / det,
                (-j[0][1] * g[0] + j[0][0] * g[1]) / det,
            ]
        })
    }

    pub fn hessian(shape: &CellShape, u: [f64; 4], xi: f64, eta: f64) -> [[f64; 2]; 2] {
        let x = shape.vertices();
        let mixed = |v: [f64; 4]| v[0] - v[1] - v[2] + v[3];
        let (_, g) = evaluate(shape, u, xi, eta);
        let m = mixed(u) - g[0] * mixed(x.map(|p| p[0])) - g[1] * mixed(x.map(|p| p[1]));
        let j = jacobian(shape, xi, eta);
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        let k = [
            [j[1][1] / det, -j[0][1] / det],
            [-j[1][0] / det, j[0][0] / det],
        ];
        let h = |i: usize, jj: usize| m * (k[0][i] * k[1][jj] + k[1][i] * k[0][jj]);
        [[h(0, 0), h(0, 1)], [h(1, 0), h(1, 1)]]
    }

    pub fn reference(shape: &CellShape, p: [f64; 2]) -> (f64, f64) {
        let (mut xi, mut eta) = (0.5, 0.5);
        for _ in 0..50 {
            let x = shape.point(xi, eta);
            let r = [x[0] - p[0], x[1] - p[1]];
            let j = jacobian(shape, xi, eta);
            let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
            let dxi = (j[1][1] * r[0] - j[0][1] * r[1]) / det;
            let deta = (j[0][0] * r[1] - j[1][0] * r[0]) / det;
            xi -= dxi;
            eta -= deta;
            if dxi.abs().max(deta.abs()) <= 1e-15 {
                break;
            }
        }
        (xi, eta)
    }
}

fn main() {
    let n = 100_000;
    // A linear congruential generator: the same cells in every run.
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let cells: Vec<(CellShape, [f64; 4], [f64; 2])> = (0..n)
        .map(|_| {
            let corners = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]];
            let v = corners.map(|c| [c[0] + 0.4 * next(), c[1] + 0.4 * next()]);
            let u = [next(), next(), next(), next()];
            (CellShape::Quadrilateral(v), u, [0.5 + next(), 0.5 + next()])
        })
        .collect();
    let run = |library: bool| {
        let mut out = Vec::with_capacity(n * 9 * 13 + 2 * n);
        let t = Instant::now();
        for (shape, u, p) in &cells {
            cell(black_box(shape), *u, *p, library, &mut out);
        }
        (t.elapsed().as_secs_f64(), out)
    };
    let (mut library, mut closed) = (Vec::new(), Vec::new());
    for round in 0..7 {
        let (tl, bits_l) = run(true);
        let (tc, bits_c) = run(false);
        let differ = bits_l.iter().zip(&bits_c).filter(|(a, b)| a != b).count();
        assert!(
            bits_l.len() == bits_c.len() && differ == 0,
            "{differ} of {} results differ",
            bits_l.len()
        );
        println!(
            "round {round}: nalgebra {:>7.1} ns per cell, closed formulas {:>7.1} ns per cell \
             ({} results bitwise the same)",
            1e9 * tl / n as f64,
            1e9 * tc / n as f64,
            bits_l.len()
        );
        library.push(tl);
        closed.push(tc);
    }
    library.sort_by(f64::total_cmp);
    closed.sort_by(f64::total_cmp);
    let (ml, mc) = (library[library.len() / 2], closed[closed.len() / 2]);
    println!(
        "medians: nalgebra {:.1} ns, closed formulas {:.1} ns per cell, ratio {:.3}",
        1e9 * ml / n as f64,
        1e9 * mc / n as f64,
        ml / mc
    );
}
