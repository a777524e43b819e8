//! Reynolds against SubStokes on one mesh (§IV.3.3, §IV.3.7; Figs IV.112–IV.115, IV.143): the
//! Reynolds problem (I.79), with cavitation (I.82) where the SubStokes run had it, solved on the
//! SubStokes run's last mesh, and both solutions sampled along a horizontal cut.
//!
//! **Velocities.** SubStokes computes χ; the Reynolds model only ψ^R, from which (I.86) rebuilds
//! the film-integrated velocity
//!
//! χ^R_μ = g v̄_μ + (g²/12) [Δ(g v̄_μ) − g ∂_μ(ψ^R/g) + κ_μ + (γ₃)_μ],
//!
//! with g ∂_μ(ψ/g) = ∂_μψ − ψ ∂_μg/g (docs/models.md §11). The pressure is p ≈ ψ/g (I.85).
//!
//! **Thin-film limits.** Eliminating χ from (I.58) gives ∇·(g⁴∇(ψ/g)) = 12gδv₃ for a vertical
//! squeeze, and g²·(I.77) is that minus 2g³∇g·∇(ψ/g): where ∇g ≠ 0 (wave, hill) the two models
//! have different thin-film limits, so their pressures differ by more than the film thickness
//! explains (the report says so beside the cuts).

use crate::fe::cell_values::evaluate_at;
use crate::fe::{DofMap, System};
use crate::linalg::DirectSolver;
use crate::mesh::Mesh;
use crate::models::reynolds::{solve_cavitation, Form, Load, ReynoldsProblem};
use crate::models::substokes::PSI;
use crate::models::thin_film::{CavitationSource, ThinFilm};
use crate::models::ModelError;
use crate::results::Cuts;

/// Points of a cut (x = x₀ + i (x₁ − x₀)/100, i = 0 … 100).
pub const CUT_POINTS: usize = 101;

/// The cut height of a film: x₂ = 0.375 over the hill (through a row of hill tops), ½ else.
pub fn cut_height(film: &ThinFilm) -> f64 {
    if film.gap.varies_in_x2() {
        0.375
    } else {
        0.5
    }
}

/// The abscissae of a cut over `x_range`: [`CUT_POINTS`] equidistant points, both ends included.
pub fn cut_abscissae(x_range: [f64; 2]) -> impl Iterator<Item = f64> {
    (0..CUT_POINTS)
        .map(move |i| x_range[0] + (x_range[1] - x_range[0]) * i as f64 / (CUT_POINTS - 1) as f64)
}

/// One film's pressure along the cut x₂ = `y`: columns `x` and `psi` from `pressure` (ψ at a
/// point, `None` outside the mesh), ψ₀ = `boundary_pressure`. The data of a single model's cut:
/// a Reynolds table's, or the model-adaptive film's (Fig. IV.118 sets them beside a SubStokes
/// table's [`Comparison::cuts`]).
pub fn pressure_cut(
    y: f64,
    x_range: [f64; 2],
    boundary_pressure: f64,
    pressure: impl Fn([f64; 2]) -> Option<f64>,
) -> Result<Cuts, ModelError> {
    let (mut xs, mut psi) = (
        Vec::with_capacity(CUT_POINTS),
        Vec::with_capacity(CUT_POINTS),
    );
    for x in cut_abscissae(x_range) {
        match pressure([x, y]) {
            Some(v) if v.is_finite() => {
                xs.push(x);
                psi.push(v);
            }
            Some(v) => {
                return Err(ModelError::NonFinite(format!(
                    "the cut: ψ = {v} at ({x}, {y}) is not finite"
                )))
            }
            None => {
                return Err(ModelError::Failed(format!(
                    "the cut point ({x}, {y}) lies outside the mesh"
                )))
            }
        }
    }
    Ok(Cuts {
        y,
        boundary_pressure,
        columns: vec![("x".into(), xs), ("psi".into(), psi)],
        cavitated_substokes: None,
        cavitated_reynolds: None,
    })
}

/// What to compare: the film, ψ₀, and whether (with which γ₃c) the runs have cavitation.
#[derive(Clone, Debug)]
pub struct Comparison {
    pub film: ThinFilm,
    pub boundary_pressure: f64,
    pub cavitation: Option<CavitationSource>,
}

/// A Reynolds solution on a mesh: its dofs and ψ^R.
pub struct ReynoldsOnMesh {
    pub dofs: DofMap,
    pub psi: Vec<f64>,
}

impl Comparison {
    /// The Reynolds problem of the same film.
    fn reynolds(&self) -> ReynoldsProblem {
        ReynoldsProblem {
            film: self.film.clone(),
            boundary_pressure: self.boundary_pressure,
            cavitation_source: self.cavitation.unwrap_or_default(),
            form: Form::default(),
            exact: None,
        }
    }

    /// ψ^R on `mesh`: (I.79), or (I.82) by the active set started from the vertices where
    /// `start` (the SubStokes pressure per vertex) is ≤ 0.
    pub fn solve_reynolds(&self, mesh: &Mesh, start: &[f64]) -> Result<ReynoldsOnMesh, ModelError> {
        let problem = self.reynolds();
        let mut system = System::new(mesh, 1);
        problem.constrain(&mut system);
        let load = match self.cavitation {
            Some(_) => Load::Cavitation,
            None => Load::Reynolds,
        };
        let data = problem.cell_data(mesh, load);
        problem.assemble(mesh, &mut system, &data);
        let mut solver = DirectSolver::cholesky();
        solver.reorder(system.ordering());
        let psi = match self.cavitation {
            None => system.solve(&mut solver)?,
            Some(_) => {
                let initial: Vec<bool> = start.iter().map(|&p| p <= 0.0).collect();
                solve_cavitation(&system, &mut solver, &initial)?.psi
            }
        };
        Ok(ReynoldsOnMesh {
            dofs: system.dofs,
            psi,
        })
    }

    /// Both solutions along the cut x₂ = [`cut_height`] over the domain's x-range: columns
    /// `x`, then `psi_`, `p_`, `chi1_`, `chi2_` with the suffixes `substokes` and `reynolds`,
    /// and the cavitated area fractions (cells whose four corner pressures are 0) of both.
    /// `u` is the SubStokes solution (χ₁, χ₂, ψ per vertex) on `dofs`.
    pub fn cuts(
        &self,
        mesh: &Mesh,
        dofs: &DofMap,
        u: &[f64],
        x_range: [f64; 2],
    ) -> Result<Cuts, ModelError> {
        let n_vertices = dofs.vertices.len() as u32;
        let psi_s: Vec<f64> = (0..n_vertices).map(|v| u[dofs.dof(v, PSI)]).collect();
        let reynolds = self.solve_reynolds(mesh, &psi_s)?;
        let y = cut_height(&self.film);
        let names = [
            "x",
            "psi_substokes",
            "psi_reynolds",
            "p_substokes",
            "p_reynolds",
            "chi1_substokes",
            "chi1_reynolds",
            "chi2_substokes",
            "chi2_reynolds",
        ];
        let mut columns: Vec<(String, Vec<f64>)> = names
            .iter()
            .map(|n| (n.to_string(), Vec::with_capacity(CUT_POINTS)))
            .collect();
        for x in cut_abscissae(x_range) {
            let values = self.at([x, y], mesh, dofs, u, &reynolds)?;
            for (column, v) in columns.iter_mut().zip(values) {
                column.1.push(v);
            }
        }
        Ok(Cuts {
            y,
            boundary_pressure: self.boundary_pressure,
            columns,
            cavitated_substokes: self.cavitation.map(|_| cavitated_area(mesh, dofs, u, PSI)),
            cavitated_reynolds: self
                .cavitation
                .map(|_| cavitated_area(mesh, &reynolds.dofs, &reynolds.psi, 0)),
        })
    }

    /// The columns of [`Comparison::cuts`] at one point.
    fn at(
        &self,
        p: [f64; 2],
        mesh: &Mesh,
        dofs: &DofMap,
        u: &[f64],
        reynolds: &ReynoldsOnMesh,
    ) -> Result<[f64; 9], String> {
        let c = mesh
            .locate(p)
            .ok_or_else(|| format!("the cut point ({}, {}) lies outside the mesh", p[0], p[1]))?;
        let k = mesh.active_index(c);
        let shape = mesh.cell_shape(c);
        let value =
            |d: &DofMap, w: &[f64], comp| evaluate_at(&shape, d.corner_values(w, k, comp), p);
        let (psi_s, _) = value(dofs, u, PSI);
        let (chi1_s, _) = value(dofs, u, 0);
        let (chi2_s, _) = value(dofs, u, 1);
        let (psi_r, grad_r) = value(&reynolds.dofs, &reynolds.psi, 0);
        let jets = self.film.film_jets(p);
        let g = jets.g.v;
        let gamma3 = jets.gamma3();
        let chi_r = [0, 1].map(|mu| {
            let g_vbar = jets.g * jets.vbar[mu];
            let g_grad_psi_over_g = grad_r[mu] - psi_r * jets.g.d[mu] / g;
            g_vbar.v
                + g * g / 12.0
                    * (g_vbar.laplacian().v - g_grad_psi_over_g + jets.kappa[mu].v + gamma3[mu].v)
        });
        let values = [
            p[0],
            psi_s,
            psi_r,
            psi_s / g,
            psi_r / g,
            chi1_s,
            chi_r[0],
            chi2_s,
            chi_r[1],
        ];
        match values.iter().position(|v| !v.is_finite()) {
            Some(i) => Err(format!(
                "the cuts: value {i} at ({}, {}) is not finite",
                p[0], p[1]
            )),
            None => Ok(values),
        }
    }
}

/// Fraction of the domain's area covered by cells whose four corner values of component `comp`
/// are 0 (the discrete cavitation zone, ψ_h ≡ 0 there).
pub fn cavitated_area(mesh: &Mesh, dofs: &DofMap, u: &[f64], comp: usize) -> f64 {
    let (mut zone, mut total) = (0.0, 0.0);
    for (k, &c) in mesh.active().iter().enumerate() {
        let area = mesh.cell_shape(c).area();
        total += area;
        if dofs.corner_values(u, k, comp).iter().all(|&v| v == 0.0) {
            zone += area;
        }
    }
    zone / total
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::substokes::fixtures::uniform;
    use crate::models::substokes::SubStokesProblem;
    use crate::models::thin_film::{example, Gap};

    /// max|ψ^S − ψ^R|/max|ψ^R − 200| along the cut of a uniform grid refined `times` times.
    fn difference(film: ThinFilm, times: usize) -> f64 {
        let mesh = uniform(times);
        let s = SubStokesProblem::new(film.clone(), 200.0)
            .solve(&mesh)
            .unwrap();
        let comparison = Comparison {
            film,
            boundary_pressure: 200.0,
            cavitation: None,
        };
        let cuts = comparison.cuts(&mesh, &s.dofs, &s.u, [0.0, 1.0]).unwrap();
        assert_eq!(cuts.column("x").unwrap().len(), CUT_POINTS);
        cuts.relative_pressure_difference().unwrap()
    }

    /// Plain gap, squeeze (IV.7): the models differ by a boundary effect of ∂_nχ = 0 (≤ 3 %),
    /// which shrinks with the film: g = 0.1 → 0.05 on 64×64 divides it by at least 2.5.
    #[test]
    fn plain_gap_pressures_agree_and_converge_with_the_film() {
        let thick = example("IV.7").unwrap();
        let thin = ThinFilm::new(Gap::Plain { g0: 0.05 }, [0.0, 0.0, -10.0]);
        let (d_thick, d_thin) = (difference(thick, 6), difference(thin, 6));
        eprintln!("plain squeeze on 64×64: g = 0.1 {d_thick:.4}, g = 0.05 {d_thin:.4}");
        assert!(d_thick <= 0.03, "g = 0.1: {d_thick}");
        assert!(
            d_thick >= 2.5 * d_thin,
            "g = 0.1: {d_thick}, g = 0.05: {d_thin}"
        );
    }

    /// Linear gap, vertical velocity (IV.10): within 8 %; the wave (IV.16) differs by far more
    /// (different thin-film limits where ∇g ≠ 0, module docs).
    #[test]
    fn linear_gap_agrees_and_the_wave_does_not() {
        let linear = difference(example("IV.10").unwrap(), 5);
        assert!(linear <= 0.08, "(IV.10): {linear}");
        let wave = difference(example("IV.15").unwrap(), 5);
        eprintln!("32×32: linear {linear:.4}, wave {wave:.4}");
        assert!(wave > 2.0 * linear, "(IV.15): {wave}, (IV.10): {linear}");
    }

    /// (I.86) reproduces a SubStokes flow where both models are exact: (IV.9), the plain gap
    /// sliding at 10, has χ ≡ (g v̄₁, 0) = (0.5, 0) and ψ ≡ 200 in both.
    #[test]
    fn velocity_reconstruction_of_plain_sliding() {
        let film = example("IV.9").unwrap();
        let mesh = uniform(3);
        let s = SubStokesProblem::new(film.clone(), 200.0)
            .solve(&mesh)
            .unwrap();
        let comparison = Comparison {
            film,
            boundary_pressure: 200.0,
            cavitation: None,
        };
        let cuts = comparison.cuts(&mesh, &s.dofs, &s.u, [0.0, 1.0]).unwrap();
        for name in ["chi1_substokes", "chi1_reynolds"] {
            for v in cuts.column(name).unwrap() {
                assert!((v - 0.5).abs() < 1e-9, "{name}: {v}");
            }
        }
        for v in cuts.column("psi_reynolds").unwrap() {
            assert!((v - 200.0).abs() < 1e-9, "ψ^R = {v}");
        }
    }
}
