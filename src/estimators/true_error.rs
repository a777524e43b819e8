//! The true error of a run with a manufactured solution ([`crate::models::manufactured`]), in
//! the norm of its estimator: what the estimate is judged against (the effectivity η/‖e‖). Not
//! an estimator itself — it needs the exact field.

use super::per_cell;
use crate::fe::cell_values::evaluate_at;
use crate::fe::quadrature::square_rule;
use crate::fe::DofMap;
use crate::mesh::Mesh;
use crate::models::elasticity::Elasticity;
use crate::models::manufactured::{ExactDisplacement, ExactPressure};
use crate::models::thin_film::ThinFilm;

/// ‖s − s_h‖_a = √a(e, e), e = s − s_h, the energy norm (III.35) of Theorem III.12 with the
/// thesis's a(e, e) = 2μ‖ε(e)‖² + 2λ‖div e‖² = ∫ σ(e) : ε(e).
///
/// Gauss quadrature with 4×4 points per cell: ∇s_h is affine in each coordinate on a
/// rectangle and ∇s smooth, so the rule that is exact for degree 7 per coordinate leaves a
/// quadrature error far below the discretisation error.
/// The cells are summed in the order of `mesh.active()`, so the value does not depend on the
/// thread count.
pub fn elasticity_energy(
    mesh: &Mesh,
    dofs: &DofMap,
    u: &[f64],
    model: &Elasticity,
    exact: &ExactDisplacement,
) -> f64 {
    let rule = square_rule::<16>();
    let cells = per_cell(mesh, &rule, |k, _, cv| {
        let mut sum = 0.0;
        for q in 0..rule.len() {
            let x = cv.point(q);
            let gh = Elasticity::gradient_at(mesh, dofs, u, k, x);
            let g = exact.gradient(x);
            let e = [
                [g[0][0] - gh[0][0], g[0][1] - gh[0][1]],
                [g[1][0] - gh[1][0], g[1][1] - gh[1][1]],
            ];
            sum += model.energy_density(e) * cv.jxw(q);
        }
        sum
    });
    cells.iter().sum::<f64>().sqrt()
}

/// ‖ψ − ψ_h‖_R, the Reynolds norm (II.9) of Theorem III.16:
/// ‖e‖_R² = ∫ |∇e − e∇g/g|² = ∫ g²|∇(e/g)|², with the gap g of `film`.
///
/// 4×4 Gauss points per cell, as [`elasticity_energy`]: e_h is bilinear, ψ and g smooth.
pub fn reynolds_norm(
    mesh: &Mesh,
    dofs: &DofMap,
    psi: &[f64],
    film: &ThinFilm,
    exact: &ExactPressure,
) -> f64 {
    let rule = square_rule::<16>();
    let cells = per_cell(mesh, &rule, |k, _, cv| {
        let values = dofs.corner_values(psi, k, 0);
        let mut sum = 0.0;
        for q in 0..rule.len() {
            let x = cv.point(q);
            let (v, grad) = evaluate_at(cv.shape(), values, x);
            let (g, dg, _) = film.gap(x);
            let e = exact.value(x) - v;
            let de = exact.gradient(x);
            let r = [0, 1].map(|i| de[i] - grad[i] - e * dg[i] / g);
            sum += (r[0] * r[0] + r[1] * r[1]) * cv.jxw(q);
        }
        sum
    });
    cells.iter().sum::<f64>().sqrt()
}

/// The SubStokes norm of Theorem III.23 (docs/estimators.md §5.6): the theorem bounds
/// ‖χ − χ_h‖_{H¹} + ‖ψ − ψ_h‖_{L²} by η; measured here is the Euclidean combination
///
/// ‖(e_χ, e_ψ)‖ = (‖e_χ‖²_{H¹} + ‖e_ψ‖²_{L²})^{1/2},  ‖e_χ‖²_{H¹} = Σ_μ ∫ (e_χμ² + |∇e_χμ|²),
///
/// which lies between 1/√2 times the theorem's sum and the sum itself (the squares add over
/// cells, which the reference error of [`crate::study::reference`] needs). The same norm serves
/// Theorem III.24 (cavitation), whose left-hand side has the same two terms.
///
/// 4×4 Gauss points per cell, as [`elasticity_energy`]: the discrete fields are bilinear, the
/// exact ones smooth. Cells are summed in the order of `mesh.active()`.
pub fn substokes_norm(
    mesh: &Mesh,
    dofs: &DofMap,
    u: &[f64],
    exact: &crate::models::manufactured_stokes::ExactFlow,
) -> f64 {
    let rule = square_rule::<16>();
    let cells = per_cell(mesh, &rule, |k, _, cv| {
        let values = [0, 1, 2].map(|c| dofs.corner_values(u, k, c));
        let mut sum = 0.0;
        for q in 0..rule.len() {
            let x = cv.point(q);
            let chi = exact.chi(x);
            let dchi = exact.chi_gradient(x);
            for mu in 0..2 {
                let (v, grad) = evaluate_at(cv.shape(), values[mu], x);
                let e = chi[mu] - v;
                let de = [dchi[mu][0] - grad[0], dchi[mu][1] - grad[1]];
                sum += (e * e + de[0] * de[0] + de[1] * de[1]) * cv.jxw(q);
            }
            let (p, _) = evaluate_at(cv.shape(), values[2], x);
            let e = exact.psi(x) - p;
            sum += e * e * cv.jxw(q);
        }
        sum
    });
    cells.iter().sum::<f64>().sqrt()
}
