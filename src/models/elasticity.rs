//! Linear elasticity (I.17) in the thesis form
//! a(s, r) = 2μ⟨ε(s), ε(r)⟩ + 2λ⟨div s, div r⟩,  b(r) = ⟨ρf, r⟩ + ⟨τn, r⟩_{Γ_τ}
//! (spec/models.md §1.2 and §15 item 1: the thesis uses 2λ throughout, so λ_std = 2λ),
//! discretised with vector Q₁ (II.47).

use crate::experiment::{ElasticityData, Profile, Side};
use crate::fe::{q1, quadrature, DofMap, Rect, SparseSystem};
use crate::mesh::{Mesh, Neighbor, FACES};

/// A volume load ρf.
#[derive(Clone)]
pub enum VolumeForce {
    /// direction · profile(x₁), the loads of §IV.1 and §IV.2.
    Profile([f64; 2], Profile),
    /// Any field (manufactured solutions in the tests).
    Field(std::sync::Arc<dyn Fn([f64; 2]) -> [f64; 2] + Send + Sync>),
}

impl std::fmt::Debug for VolumeForce {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            VolumeForce::Profile(d, p) => write!(f, "Profile({d:?}, {p:?})"),
            VolumeForce::Field(_) => write!(f, "Field(..)"),
        }
    }
}

/// Data of one elasticity problem.
#[derive(Clone, Debug)]
pub struct Elasticity {
    pub mu: f64,
    pub lambda: f64,
    pub dirichlet: Vec<Side>,
    pub load: Option<VolumeForce>,
    /// τn per side (Neumann data).
    pub tractions: Vec<(Side, [f64; 2])>,
}

impl Profile {
    /// Value of the profile at x₁.
    pub fn at(&self, x1: f64) -> f64 {
        match *self {
            Profile::Constant { amplitude } => amplitude,
            Profile::Quadratic { amplitude, scale } => amplitude * (x1 / scale).powi(2),
            Profile::Step { amplitude, at } => {
                if x1 > at {
                    amplitude
                } else {
                    0.0
                }
            }
            Profile::Sine {
                amplitude,
                half_period,
            } => amplitude * (std::f64::consts::PI * x1 / half_period).sin(),
        }
    }
}

impl Elasticity {
    pub fn from_data(d: &ElasticityData) -> Elasticity {
        Elasticity {
            mu: d.mu,
            lambda: d.lambda,
            dirichlet: d.dirichlet.clone(),
            load: d
                .volume_load
                .as_ref()
                .map(|l| VolumeForce::Profile(l.direction, l.profile)),
            tractions: d.tractions.iter().map(|t| (t.side, t.value)).collect(),
        }
    }

    /// Volume load ρf at a point.
    #[inline]
    pub fn volume_load(&self, p: [f64; 2]) -> [f64; 2] {
        match &self.load {
            None => [0.0; 2],
            Some(VolumeForce::Profile(dir, prof)) => {
                let a = prof.at(p[0]);
                [dir[0] * a, dir[1] * a]
            }
            Some(VolumeForce::Field(f)) => f(p),
        }
    }

    /// Surface stress τn prescribed on a side (zero where none is given).
    pub fn traction(&self, side: Side) -> [f64; 2] {
        self.tractions
            .iter()
            .find(|(s, _)| *s == side)
            .map(|(_, t)| *t)
            .unwrap_or([0.0; 2])
    }

    pub fn is_dirichlet(&self, side: Side) -> bool {
        self.dirichlet.contains(&side)
    }

    /// Stress σ(s) = 2μ ε(s) + 2λ (div s) I from the displacement gradient ∇s (rows = components).
    #[inline]
    pub fn stress(&self, grad: [[f64; 2]; 2]) -> [[f64; 2]; 2] {
        let div = grad[0][0] + grad[1][1];
        let off = self.mu * (grad[0][1] + grad[1][0]);
        [
            [2.0 * self.mu * grad[0][0] + 2.0 * self.lambda * div, off],
            [off, 2.0 * self.mu * grad[1][1] + 2.0 * self.lambda * div],
        ]
    }

    /// Dofs fixed by s = 0 on Γ₀, plus every hanging dof (value 0 during the solve, then
    /// distributed from its parents).
    pub fn fixed_dofs(&self, dofs: &DofMap) -> Vec<(usize, f64)> {
        let v = &dofs.vertices;
        let mut fixed: Vec<(usize, f64)> = Vec::new();
        for vert in 0..v.len() as u32 {
            let on_dirichlet = self.dirichlet.iter().any(|&s| v.on_side(vert, s));
            if on_dirichlet || v.is_hanging[vert as usize] {
                fixed.push((dofs.dof(vert, 0), 0.0));
                fixed.push((dofs.dof(vert, 1), 0.0));
            }
        }
        fixed
    }

    /// Assemble the stiffness matrix and load vector (volume load with 3×3 Gauss points,
    /// tractions with 3 points per Neumann face).
    pub fn assemble(&self, mesh: &Mesh, system: &SparseSystem) -> (Vec<f64>, Vec<f64>) {
        let active = mesh.active();
        let quad = quadrature::square(3);
        let (fp, fw) = quadrature::gauss(3);
        let (mu, lambda) = (self.mu, self.lambda);
        system.assemble(active.len(), |k, ke, fe| {
            let c = active[k];
            let r = Rect::from_box(mesh.cell_box(c));
            let area = r.area();
            for &(xi, eta, w) in &quad {
                let g = q1::gradients(xi, eta, r.hx, r.hy);
                let phi = q1::values(xi, eta);
                let jw = w * area;
                for a in 0..4 {
                    for b in 0..4 {
                        let dot = g[a][0] * g[b][0] + g[a][1] * g[b][1];
                        for ca in 0..2 {
                            for cb in 0..2 {
                                let mut val =
                                    mu * g[a][cb] * g[b][ca] + 2.0 * lambda * g[a][ca] * g[b][cb];
                                if ca == cb {
                                    val += mu * dot;
                                }
                                ke[(2 * a + ca) * 8 + 2 * b + cb] += val * jw;
                            }
                        }
                    }
                }
                let f = self.volume_load(r.point(xi, eta));
                for a in 0..4 {
                    fe[2 * a] += f[0] * phi[a] * jw;
                    fe[2 * a + 1] += f[1] * phi[a] * jw;
                }
            }
            for face in FACES {
                let Neighbor::Boundary(side) = mesh.neighbor(c, face) else {
                    continue;
                };
                if self.is_dirichlet(side) {
                    continue;
                }
                let t = self.traction(side);
                if t == [0.0; 2] {
                    continue;
                }
                let [va, vb] = face.vertices();
                let len = match face {
                    crate::mesh::Face::Left | crate::mesh::Face::Right => r.hy,
                    _ => r.hx,
                };
                for (s, w) in fp.iter().zip(fw) {
                    let (pa, pb) = (1.0 - s, *s);
                    for (lv, phi) in [(va, pa), (vb, pb)] {
                        fe[2 * lv] += t[0] * phi * w * len;
                        fe[2 * lv + 1] += t[1] * phi * w * len;
                    }
                }
            }
        })
    }

    /// Displacement gradient ∇s_h (rows = components) of the solution on active cell `k` at a
    /// physical point `p` of the cell.
    #[inline]
    pub fn gradient_at(
        mesh: &Mesh,
        dofs: &DofMap,
        u: &[f64],
        k: usize,
        p: [f64; 2],
    ) -> [[f64; 2]; 2] {
        let r = Rect::from_box(mesh.cell_box(mesh.active()[k]));
        let (xi, eta) = r.reference(p);
        let (_, g0) = r.eval(dofs.corner_values(u, k, 0), xi, eta);
        let (_, g1) = r.eval(dofs.corner_values(u, k, 1), xi, eta);
        [g0, g1]
    }
}
