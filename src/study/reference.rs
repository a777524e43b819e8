//! A reference solution for the true error of runs without an exact solution and without an
//! energy identity (the saddle points: SubStokes, [`super::Problem::reference_errors`]), written
//! for any problem whose solution is a Q₁ field at the vertices of a quadtree mesh.
//!
//! **The reference mesh** ([`reference_mesh`]): the overlay of the kept meshes — every cell
//! refined as deep as any kept mesh has it (starting from the common coarse grid, a cell is
//! refined while some kept mesh has it refined, [`Mesh::refines`]; the 2:1 closure of the
//! refinement may add cells, never remove one) — refined once more uniformly. Every cell of it
//! then lies inside exactly one active cell of each kept mesh, on which the kept field is a
//! single bilinear polynomial; the adaptive loop's coarsening breaks the nesting of successive
//! meshes but not this.
//!
//! **The distance** ([`distance`]): ‖u_ref − u_k‖ integrated on the reference cells, at the
//! points of a 4×4 Gauss rule per reference cell: the kept field is evaluated at the same
//! physical points in the kept cell that holds the reference cell
//! ([`Mesh::active_cell_holding`]). Both fields are polynomial on each reference cell (Q₁ and
//! the restriction of a Q₁ on a larger rectangle), so the rule integrates the squared
//! difference exactly on rectangles. The norm is the weighted H¹-type norm
//! Σ_c ∫ (w₀(c) e_c² + w₁(c) |∇e_c|²) over the components c ([`ComponentWeights`]).
//!
//! **The extrapolation** ([`extrapolated_errors`]): the reference has an error of its own,
//! e_ref. With the reference the last kept mesh refined once (the adaptive meshes grow, so the
//! last one is the overlay up to the coarsened cells) and Q₁'s error halving under uniform
//! refinement in the norms that bound h (H¹, and the L² of the stabilised pressure at O(h)),
//! e_last ≈ 2 e_ref and d_last² ≈ e_last² − e_ref² = 3 e_ref², so e_ref ≈ d_last/√3 and
//!
//! e_k ≈ √(d_k² + e_ref²).
//!
//! The Pythagoras e_k² = d_k² + e_ref² is exact only for a symmetric Galerkin problem in its
//! energy norm on nested spaces (the reference's error is orthogonal to the difference of
//! the two discrete solutions); for the stabilised saddle point of SubStokes in the norm of its
//! estimator it is an approximation, whose quality is checked on the manufactured scene
//! (`tests/manufactured.rs`, the reference error against the exact one). For the early cycles
//! d_k ≫ e_ref and the extrapolation hardly matters; for the last one it sets the value.

use crate::estimators::per_cell;
use crate::fe::cell_values::evaluate_at;
use crate::fe::quadrature::square_rule;
use crate::fe::DofMap;
use crate::mesh::{Mesh, MeshError};

/// The overlay of `meshes` (same coarse grid, unmoved), refined once uniformly (module docs).
/// `None` without meshes.
pub fn reference_mesh(meshes: &[&Mesh]) -> Result<Option<Mesh>, MeshError> {
    let Some(first) = meshes.first() else {
        return Ok(None);
    };
    let mut mesh = first.truncated(0);
    loop {
        let refine: Vec<bool> = mesh
            .active()
            .iter()
            .map(|&c| {
                let key = mesh.cell_key(c);
                meshes.iter().any(|m| m.refines(key))
            })
            .collect();
        if !refine.contains(&true) {
            break;
        }
        let coarsen = vec![false; refine.len()];
        mesh.refine_and_coarsen(&refine, &coarsen)?;
    }
    mesh.refine_global()?;
    Ok(Some(mesh))
}

/// The weights (w₀, w₁) of the value and of the gradient of each component in the norm of
/// [`distance`]: (1, 1) is the H¹ norm of a component, (1, 0) its L² norm.
pub type ComponentWeights = [(f64, f64)];

/// A Q₁ field at the vertices of a mesh: values vertex-major, `n_components` per vertex, as
/// [`DofMap::corner_values`] reads them (hanging values distributed).
#[derive(Clone, Copy)]
pub struct VertexField<'a> {
    pub mesh: &'a Mesh,
    pub dofs: &'a DofMap,
    pub u: &'a [f64],
}

/// ‖reference − kept‖ in the norm of `weights` (one per component, module docs), integrated on
/// the cells of the reference mesh. `None` where a reference cell is not inside one cell of
/// the kept mesh (a kept mesh finer than the reference, or another coarse grid).
pub fn distance(
    reference: VertexField,
    kept: VertexField,
    weights: &ComponentWeights,
) -> Option<f64> {
    let rule = square_rule::<16>();
    let kept_active = kept.mesh.active();
    let cells = per_cell(reference.mesh, &rule, |k, c, cv| {
        let key = reference.mesh.cell_key(c);
        let holder = kept.mesh.active_cell_holding(key)?;
        let kk = kept.mesh.active_index(holder);
        debug_assert_eq!(kept_active[kk], holder);
        let kept_shape = kept.mesh.cell_shape(holder);
        let mut sum = 0.0;
        for (comp, &(w0, w1)) in weights.iter().enumerate() {
            let r = reference.dofs.corner_values(reference.u, k, comp);
            let h = kept.dofs.corner_values(kept.u, kk, comp);
            for q in 0..rule.len() {
                let x = cv.point(q);
                let (vr, gr) = evaluate_at(cv.shape(), r, x);
                let (vh, gh) = evaluate_at(&kept_shape, h, x);
                let (e, de) = (vr - vh, [gr[0] - gh[0], gr[1] - gh[1]]);
                sum += (w0 * e * e + w1 * (de[0] * de[0] + de[1] * de[1])) * cv.jxw(q);
            }
        }
        Some(sum)
    });
    let sum: Option<Vec<f64>> = cells.into_iter().collect();
    Some(sum?.iter().sum::<f64>().sqrt())
}

/// e_k = √(d_k² + e_ref²) with e_ref = d_last/√3, from the distances `d` of the kept solves to
/// the reference (module docs: the reference is the last mesh refined once).
pub fn extrapolated_errors(d: &[f64]) -> Vec<f64> {
    let e_ref = d.last().map_or(0.0, |last| last / 3f64.sqrt());
    d.iter()
        .map(|dk| (dk * dk + e_ref * e_ref).sqrt())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The overlay of two meshes refined in different corners holds both refinements, every
    /// cell of it (refined once more) lies in one active cell of each, and the distance of a
    /// field to itself on a coarser mesh is that of its interpolation (0 for a bilinear field).
    #[test]
    fn overlay_holds_every_kept_mesh_and_locates_its_cells() {
        let coarse = Mesh::new([0.0, 1.0], [0.0, 1.0], 2, 2);
        let mut a = coarse.clone();
        let mut flags = vec![false; a.n_active()];
        flags[0] = true;
        a.refine_and_coarsen(&flags, &vec![false; flags.len()])
            .unwrap();
        let mut b = coarse.clone();
        let mut flags = vec![false; b.n_active()];
        flags[3] = true;
        b.refine_and_coarsen(&flags, &vec![false; flags.len()])
            .unwrap();
        let r = reference_mesh(&[&a, &b]).unwrap().unwrap();
        // 4 coarse cells, two of them refined, all refined once more: 2·16 + 2·4 = 40.
        assert_eq!(r.n_active(), 40);
        for &c in r.active() {
            let key = r.cell_key(c);
            for m in [&a, &b] {
                let h = m.active_cell_holding(key).expect("inside a kept cell");
                assert!(m.level(h) < key.level);
            }
            assert!(!a.refines(key) && !b.refines(key));
        }
        // A bilinear field on each mesh: distance 0; a changed value: distance > 0.
        let field = |m: &Mesh, n: usize| {
            let dofs = DofMap::new(m, n);
            let u: Vec<f64> = dofs
                .vertices
                .coords
                .iter()
                .flat_map(|x| [1.0 + x[0] * x[1], 2.0 * x[0]].into_iter().take(n))
                .collect();
            (dofs, u)
        };
        let (dr, ur) = field(&r, 2);
        let (da, mut ua) = field(&a, 2);
        let reference = VertexField {
            mesh: &r,
            dofs: &dr,
            u: &ur,
        };
        let w = [(1.0, 1.0), (1.0, 0.0)];
        let d = distance(
            reference,
            VertexField {
                mesh: &a,
                dofs: &da,
                u: &ua,
            },
            &w,
        )
        .unwrap();
        assert!(d < 1e-12, "{d}");
        ua[0] += 1.0;
        let d = distance(
            reference,
            VertexField {
                mesh: &a,
                dofs: &da,
                u: &ua,
            },
            &w,
        )
        .unwrap();
        assert!(d > 0.1, "{d}");
        // A kept mesh finer than the reference is refused.
        let mut fine = r.clone();
        fine.refine_global().unwrap();
        let (df, uf) = field(&fine, 2);
        assert!(distance(
            reference,
            VertexField {
                mesh: &fine,
                dofs: &df,
                u: &uf
            },
            &w
        )
        .is_none());
    }

    #[test]
    fn extrapolation_adds_the_reference_error() {
        let e = extrapolated_errors(&[4.0, 3.0f64.sqrt()]);
        assert!((e[1] - 2.0).abs() < 1e-12);
        assert!((e[0] - 17f64.sqrt()).abs() < 1e-12);
    }
}
