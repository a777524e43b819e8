//! Linear elasticity (I.17) in the thesis form
//! a(s, r) = 2μ⟨ε(s), ε(r)⟩ + 2λ⟨div s, div r⟩,  b(r) = ⟨ρf, r⟩ + ⟨τn, r⟩_{Γ_τ}
//! (the thesis uses 2λ throughout, so λ_std = 2λ), discretised with vector Q₁ (II.47).

use crate::fe::cell_values::{evaluate_at, CellValues};
use crate::fe::quadrature::{self, square_rule};
use crate::fe::{DofMap, LocalDofs, System};
use crate::mesh::{Mesh, Neighbor, Side, FACES};
use crate::models::manufactured::ExactDisplacement;

/// A scalar profile of x₁: the loads of §IV.1.1–IV.1.5 and §IV.2.1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Profile {
    /// a
    Constant { amplitude: f64 },
    /// a · (x₁ / scale)²
    Quadratic { amplitude: f64, scale: f64 },
    /// a for x₁ > at, 0 otherwise
    Step { amplitude: f64, at: f64 },
    /// a · sin(π x₁ / half_period)
    Sine { amplitude: f64, half_period: f64 },
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

/// A volume load ρf.
#[derive(Clone)]
pub enum VolumeForce {
    /// direction · profile(x₁), the loads of §IV.1 and §IV.2.
    Profile([f64; 2], Profile),
    /// Any field (the loads of manufactured solutions, [`crate::models::manufactured`]).
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
    /// Sides in Γ₀ (s = 0).
    pub dirichlet: Vec<Side>,
    pub load: Option<VolumeForce>,
    /// τn per side (Neumann data).
    pub tractions: Vec<(Side, [f64; 2])>,
}

/// Local layout of the two displacement components.
const LOCAL: LocalDofs = LocalDofs { n_components: 2 };

impl Elasticity {
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

    /// σ(e) : ε(e), the integrand of the energy norm a(e, e) (III.35), from the gradient ∇e
    /// (rows = components); σ is symmetric, so σ : ε = σ₁₁e₁₁ + σ₂₂e₂₂ + σ₁₂(e₁₂ + e₂₁).
    #[inline]
    pub fn energy_density(&self, grad: [[f64; 2]; 2]) -> f64 {
        let s = self.stress(grad);
        s[0][0] * grad[0][0] + s[1][1] * grad[1][1] + s[0][1] * (grad[0][1] + grad[1][0])
    }

    /// s = 0 on Γ₀: both components fixed at every vertex of the Dirichlet sides.
    pub fn constrain(&self, system: &mut System) {
        for &side in &self.dirichlet {
            for component in 0..2 {
                system
                    .constraints
                    .fix_side(&system.dofs, side, component, 0.0);
            }
        }
    }

    /// Assemble the stiffness matrix and load vector into `system` (volume terms with 3×3 Gauss
    /// points, tractions with 3 points per Neumann face).
    pub fn assemble(&self, mesh: &Mesh, system: &mut System) {
        let active = mesh.active();
        let rule = square_rule::<9>();
        let (fp, fw) = quadrature::gauss(3);
        let (mu, lambda) = (self.mu, self.lambda);
        system.assemble(active.len(), |k, ke, fe| {
            let c = active[k];
            let cv = CellValues::new(mesh.cell_shape(c), &rule);
            for q in 0..rule.len() {
                let g = cv.gradients(q);
                let phi = cv.values(q);
                let jw = cv.jxw(q);
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
                                ke[LOCAL.entry(LOCAL.index(a, ca), LOCAL.index(b, cb))] += val * jw;
                            }
                        }
                    }
                }
                let f = self.volume_load(cv.point(q));
                for a in 0..4 {
                    fe[LOCAL.index(a, 0)] += f[0] * phi[a] * jw;
                    fe[LOCAL.index(a, 1)] += f[1] * phi[a] * jw;
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
                let len = cv.shape().face_length(face);
                for (s, w) in fp.iter().zip(fw) {
                    let (pa, pb) = (1.0 - s, *s);
                    for (lv, phi) in [(va, pa), (vb, pb)] {
                        fe[LOCAL.index(lv, 0)] += t[0] * phi * w * len;
                        fe[LOCAL.index(lv, 1)] += t[1] * phi * w * len;
                    }
                }
            }
        })
    }

    /// J(s_h) = ½a(s_h, s_h) − b(s_h), the energy of a displacement, the functional whose
    /// minimiser over V_h (or the contact set) the solve finds: the energy identity of
    /// [`crate::study::accuracy`] measures the error with it. The identity needs the exact J,
    /// so the volume terms are integrated with 4×4 Gauss points, beyond the assembly's 3×3 (a
    /// smooth load's quadrature error would otherwise add to J(s_h) − J(s) on coarse meshes);
    /// the tractions are constant per side, integrated exactly by the 3-point rule. The cells
    /// are summed in the order of `mesh.active()`, so the value does not depend on the thread
    /// count.
    pub fn energy(&self, mesh: &Mesh, dofs: &DofMap, u: &[f64]) -> f64 {
        use rayon::prelude::*;
        let active = mesh.active();
        let rule = square_rule::<16>();
        let (fp, fw) = quadrature::gauss(3);
        let cells: Vec<f64> = (0..active.len())
            .into_par_iter()
            .map(|k| {
                let c = active[k];
                let cv = CellValues::new(mesh.cell_shape(c), &rule);
                let corner = [dofs.corner_values(u, k, 0), dofs.corner_values(u, k, 1)];
                let mut sum = 0.0;
                for q in 0..rule.len() {
                    let g = cv.gradients(q);
                    let phi = cv.values(q);
                    let grad: [[f64; 2]; 2] = std::array::from_fn(|i| {
                        std::array::from_fn(|j| (0..4).map(|a| corner[i][a] * g[a][j]).sum())
                    });
                    let s: [f64; 2] =
                        std::array::from_fn(|i| (0..4).map(|a| corner[i][a] * phi[a]).sum());
                    let t = self.stress(grad);
                    let work = t[0][0] * grad[0][0]
                        + t[1][1] * grad[1][1]
                        + t[0][1] * (grad[0][1] + grad[1][0]);
                    let f = self.volume_load(cv.point(q));
                    sum += (0.5 * work - f[0] * s[0] - f[1] * s[1]) * cv.jxw(q);
                }
                for face in FACES {
                    let Neighbor::Boundary(side) = mesh.neighbor(c, face) else {
                        continue;
                    };
                    if self.is_dirichlet(side) {
                        continue;
                    }
                    let t = self.traction(side);
                    let [va, vb] = face.vertices();
                    let len = cv.shape().face_length(face);
                    for (x, w) in fp.iter().zip(fw) {
                        let (pa, pb) = (1.0 - x, *x);
                        for i in 0..2 {
                            let si = pa * corner[i][va] + pb * corner[i][vb];
                            sum -= t[i] * si * w * len;
                        }
                    }
                }
                sum
            })
            .collect();
        cells.iter().sum()
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
        let shape = mesh.cell_shape(mesh.active()[k]);
        let (_, g0) = evaluate_at(&shape, dofs.corner_values(u, k, 0), p);
        let (_, g1) = evaluate_at(&shape, dofs.corner_values(u, k, 1), p);
        [g0, g1]
    }
}

impl From<crate::experiment::Profile> for Profile {
    fn from(p: crate::experiment::Profile) -> Profile {
        use crate::experiment::Profile as File;
        match p {
            File::Constant { amplitude } => Profile::Constant { amplitude },
            File::Quadratic { amplitude, scale } => Profile::Quadratic { amplitude, scale },
            File::Step { amplitude, at } => Profile::Step { amplitude, at },
            File::Sine {
                amplitude,
                half_period,
            } => Profile::Sine {
                amplitude,
                half_period,
            },
        }
    }
}

impl From<&crate::experiment::ElasticityData> for Elasticity {
    fn from(d: &crate::experiment::ElasticityData) -> Elasticity {
        let crate::experiment::Lame { mu, lambda } = d.lame();
        Elasticity {
            mu,
            lambda,
            dirichlet: d.dirichlet.clone(),
            // A manufactured solution brings its load; the loader forbids both together.
            load: match d.exact {
                Some(name) => Some(ExactDisplacement::of(name).load(mu, lambda)),
                None => d
                    .volume_load
                    .as_ref()
                    .map(|l| VolumeForce::Profile(l.direction, l.profile.into())),
            },
            tractions: d.tractions.iter().map(|t| (t.side, t.value)).collect(),
        }
    }
}
