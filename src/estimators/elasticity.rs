//! Residual estimator of Theorem III.12 (linear elasticity, energy norm), with the calibrated
//! conventions of docs/estimators.md §5.1:
//!
//! η_Q² = h_Q² ‖ρf + div σ(s_h)‖²_Q + h_Q Σ_{E⊂∂Q} ‖J_E‖²_E,
//!
//! J_E = ½(σ(s_h)|_Q − σ(s_h)|_{Q′}) n_Q on interior faces, σ(s_h)n − τn on Neumann faces
//! (full, no ½) and 0 on Dirichlet faces; h_Q is the cell diagonal, c = 1. This reproduces the
//! five printed cycle-0 estimates of Tables IV.1–IV.5 to all four digits.
//!
//! The cell residual ρf + div σ(s_h) = ρf + μΔs_h + (μ + 2λ)∇div s_h uses the Hessian of the
//! bilinear field ([`crate::fe::cell_values::hessian`]): on a rectangle only ∂₁∂₂s_h is non-zero,
//! so div σ(s_h) = (μ + 2λ)(∂₁₂s₂, ∂₁₂s₁) there.

use super::{face_segments, per_cell};
use crate::fe::cell_values::hessian;
use crate::fe::quadrature::{self, square_rule};
use crate::fe::DofMap;
use crate::mesh::{Mesh, Side, FACES};
use crate::models::elasticity::Elasticity;

/// Which boundary residuals the estimator includes (the three thesis codes differ here,
/// docs/estimators.md §5.2).
#[derive(Clone, Debug, PartialEq)]
pub struct BoundaryTerms {
    /// Include the full residual σn − τn on Neumann faces.
    pub neumann: bool,
    /// Sides that are contact boundaries Γ_C: no σn residual there.
    pub contact_sides: Vec<Side>,
}

impl Default for BoundaryTerms {
    fn default() -> Self {
        BoundaryTerms {
            neumann: true,
            contact_sides: Vec::new(),
        }
    }
}

/// Squared indicators η_Q² of Theorem III.12 for every active cell.
pub fn indicators(
    mesh: &Mesh,
    dofs: &DofMap,
    u: &[f64],
    problem: &Elasticity,
    terms: &BoundaryTerms,
) -> Vec<f64> {
    let rule = square_rule::<9>();
    let (fp, fw) = quadrature::gauss(2);
    let (mu, lambda) = (problem.mu, problem.lambda);
    per_cell(mesh, &rule, |k, c, cv| {
        let shape = cv.shape();
        let h = shape.diameter();
        let u0 = dofs.corner_values(u, k, 0);
        let u1 = dofs.corner_values(u, k, 1);
        let mut cell = 0.0;
        for (q, &(xi, eta, _)) in rule.iter().enumerate() {
            // div σ(s_h) = μΔs_h + (μ + 2λ)∇div s_h
            let (h0, h1) = (hessian(shape, u0, xi, eta), hessian(shape, u1, xi, eta));
            let div_sigma = [
                mu * (h0[0][0] + h0[1][1]) + (mu + 2.0 * lambda) * (h0[0][0] + h1[0][1]),
                mu * (h1[0][0] + h1[1][1]) + (mu + 2.0 * lambda) * (h0[0][1] + h1[1][1]),
            ];
            let f = problem.volume_load(cv.point(q));
            let res = [f[0] + div_sigma[0], f[1] + div_sigma[1]];
            cell += (res[0] * res[0] + res[1] * res[1]) * cv.weight(q) * cv.det(q);
        }
        let mut faces = 0.0;
        for face in FACES {
            let n = shape.face_normal(face);
            let (side, segments) = face_segments(mesh, c, face);
            if let Some(side) = side {
                if problem.is_dirichlet(side)
                    || terms.contact_sides.contains(&side)
                    || !terms.neumann
                {
                    continue;
                }
            }
            for seg in &segments {
                let len = seg.length();
                for (t, w) in fp.iter().zip(fw) {
                    let p = seg.at(*t);
                    let s = problem.stress(Elasticity::gradient_at(mesh, dofs, u, k, p));
                    let sn = [
                        s[0][0] * n[0] + s[0][1] * n[1],
                        s[1][0] * n[0] + s[1][1] * n[1],
                    ];
                    let j = match (side, seg.neighbor) {
                        (Some(side), _) => {
                            let t = problem.traction(side);
                            [sn[0] - t[0], sn[1] - t[1]]
                        }
                        (None, Some(nb)) => {
                            let so = problem.stress(Elasticity::gradient_at(mesh, dofs, u, nb, p));
                            let son = [
                                so[0][0] * n[0] + so[0][1] * n[1],
                                so[1][0] * n[0] + so[1][1] * n[1],
                            ];
                            [0.5 * (sn[0] - son[0]), 0.5 * (sn[1] - son[1])]
                        }
                        (None, None) => unreachable!("interior face without neighbour"),
                    };
                    faces += (j[0] * j[0] + j[1] * j[1]) * w * len;
                }
            }
        }
        h * h * cell + h * faces
    })
}
