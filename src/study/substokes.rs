//! Tables IV.50–IV.63 (SubStokes (I.58), estimator of Theorem III.23, §IV.3.2).
//!
//! One [`SubStokesFilm`] per table: the stabilised Q₁/Q₁ system of
//! [`crate::models::substokes`] solved by the sparse LDLᵀ, the estimate of Theorem III.23
//! ([`crate::estimators::substokes`]) with its four parts as tribo-only columns, and, as in the
//! Reynolds tables, the estimate of the previous solve beside each row ([`PreviousEstimate`]:
//! row k of the thesis's fluid tables shows the mesh of solve k+1 and the estimate of solve k).
//! The marking splits tie groups (`ties = "split"` in the experiment files,
//! [`crate::adaptivity::mark_fixed_number_split`]).

use super::clock::PhaseClock;
use super::problem::{setup_system, Discretisation, Estimate, Pictures, Problem, Solution};
use super::thin_film::{FieldSample, PreviousEstimate};
use crate::estimators::substokes::{estimate_with, Options, Stabilisation, PART_NAMES};
use crate::experiment::{Rectangle, SubStokesData, SubStokesStabilisation};
use crate::fe::{DofMap, System};
use crate::linalg::DirectSolver;
use crate::models::substokes::{solve_system, SubStokesProblem, PSI};
use crate::models::thin_film::ThinFilm;

/// The probe components of a SubStokes solution, in dof order: χ₁, χ₂, ψ.
pub const COMPONENTS: [&str; 3] = ["chi1", "chi2", "psi"];

/// The SubStokes film of one experiment inside the study loop.
pub struct SubStokesFilm {
    pub problem: SubStokesProblem,
    /// The options of the Theorem III.23 estimate (experiment field `stabilisation_residual`).
    pub options: Options,
    previous_estimate: PreviousEstimate,
    solver: DirectSolver,
    domain: Rectangle,
}

impl From<&SubStokesData> for SubStokesProblem {
    fn from(d: &SubStokesData) -> SubStokesProblem {
        SubStokesProblem::new(
            ThinFilm::new(d.gap.into(), d.upper_wall_velocity),
            d.boundary_pressure,
        )
        .with_delta_eps(d.delta_eps)
    }
}

impl SubStokesFilm {
    pub fn new(data: &SubStokesData, domain: &Rectangle) -> SubStokesFilm {
        let problem = SubStokesProblem::from(data);
        let stabilisation = match data.stabilisation_residual {
            SubStokesStabilisation::Literal => Stabilisation::Literal,
            SubStokesStabilisation::DeltaEps => Stabilisation::DeltaEps(problem.delta_eps),
        };
        SubStokesFilm {
            problem,
            options: Options {
                stabilisation,
                ..Options::default()
            },
            previous_estimate: PreviousEstimate::default(),
            solver: DirectSolver::ldlt(Vec::new()),
            domain: *domain,
        }
    }
}

impl Problem for SubStokesFilm {
    fn setup(&mut self, disc: &Discretisation) -> System {
        let system = setup_system(disc, 3, &mut self.solver, |s| self.problem.constrain(s));
        self.solver.set_signs(SubStokesProblem::signs(&system.dofs));
        system
    }

    fn assemble(&mut self, disc: &Discretisation, system: &mut System) -> Result<(), String> {
        self.problem.assemble(&disc.mesh, system);
        Ok(())
    }

    fn solve(
        &mut self,
        _disc: &Discretisation,
        system: &mut System,
        _clock: &PhaseClock,
    ) -> Result<Solution, String> {
        let solved = solve_system(system, &mut self.solver);
        self.solver.release_pattern();
        let (u, _relative_residual) = solved?;
        Ok(Solution {
            u,
            counters: Vec::new(),
        })
    }

    fn estimate(
        &mut self,
        disc: &Discretisation,
        dofs: &DofMap,
        solution: &Solution,
    ) -> Result<Estimate, String> {
        let eta = estimate_with(&disc.mesh, dofs, &solution.u, &self.problem, self.options);
        let parts = eta.part_roots();
        let total = eta.total();
        let mut estimate = Estimate::of_cells(eta.indicators);
        estimate.columns.push(self.previous_estimate.column(total));
        for (name, part) in PART_NAMES.iter().zip(parts) {
            estimate = estimate.with(&format!("eta_{name}"), part);
        }
        Ok(estimate)
    }

    fn pictures(
        &mut self,
        disc: &Discretisation,
        dofs: &DofMap,
        solution: &Solution,
        cycle: usize,
    ) -> Pictures {
        let field = FieldSample {
            domain: self.domain,
            mesh: &disc.mesh,
            dofs,
            u: &solution.u,
        };
        Pictures {
            deformed: Vec::new(),
            fields: vec![field.picture(cycle, "psi", PSI, false)],
        }
    }

    fn component(&self, name: &str) -> Option<usize> {
        COMPONENTS.iter().position(|&c| c == name)
    }
}
