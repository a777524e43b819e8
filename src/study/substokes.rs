//! Tables IV.50–IV.63 (SubStokes (I.58), estimator of Theorem III.23, §IV.3.2) and IV.70–IV.75
//! (SubStokes with cavitation (I.66)/(III.79), estimator of Theorem III.24, §IV.3.6).
//!
//! One [`SubStokesFilm`] per table: the stabilised Q₁/Q₁ system of
//! [`crate::models::substokes`] solved by the sparse LDLᵀ (with cavitation by the primal–dual
//! active set on the coupled system, warm-started from the previous cycle), the estimate of
//! Theorem III.23 or III.24 ([`crate::estimators::substokes`]) with its four parts as tribo-only
//! columns, and, as in the Reynolds tables, the estimate of the previous solve beside each row
//! ([`PreviousEstimate`]: row k of the thesis's fluid tables shows the mesh of solve k+1 and the
//! estimate of solve k). The marking splits tie groups (`ties = "split"` in the experiment
//! files, [`crate::adaptivity::mark_fixed_number_split`]).
//!
//! **Stabilisation term of the marked estimate** (experiment field `stabilisation_residual`):
//! `literal` is Theorem III.23's δ_Q²‖∇ψ_h − κ − γ‖² with δ_Q = h_Q (γ_c with cavitation),
//! `delta-eps` the thesis's own δ_ε h_Q²‖∇ψ_h‖², which Theorem III.24 prints. With cavitation
//! and `literal`, the estimate of Theorem III.24 as printed is recorded beside it
//! ([`columns::THEOREM_ESTIMATE`]).

use super::clock::{Phase, PhaseClock};
use super::error::StudyError;
use super::problem::{
    setup_system, Discretisation, Estimate, KeptSolve, Pictures, Problem, ReferenceErrors, Solution,
};
use super::quantities::{self, FilmSolution};
use super::reference;
use super::thin_film::{CavitationSwitch, FieldSample, PreviousEstimate};
use super::transfer::PreviousSolution;
use crate::estimators::substokes::{
    estimate_cavitation, estimate_with, lumped_multiplier, CavitationOptions, Options,
    Stabilisation, SubStokesEstimate, PART_NAMES,
};
use crate::estimators::true_error;
use crate::experiment::{
    FilmSolver, PointCondition, Rectangle, SubStokesData, SubStokesStabilisation,
};
use crate::fe::{DofMap, System};
use crate::linalg::uzawa::{InnerSolver, UzawaOptions};
use crate::linalg::DirectSolver;
use crate::models::film_comparison::Comparison;
use crate::models::manufactured_stokes::ExactFlow;
use crate::models::substokes::{solve_cavitation, solve_system, SubStokesProblem, PSI};
use crate::models::substokes_uzawa::{
    default_options, solve_cavitation_uzawa, solve_uzawa, CavitationUzawaOptions, UzawaStats,
};
use crate::models::thin_film::ThinFilm;
use crate::results::{columns, FieldPicture};

/// The Uzawa options of `solver = "uzawa"`: CG-SSOR (III.92) with the safeguarded step of
/// [`crate::models::substokes_uzawa`] to 1e-12 of ‖(f, g)‖, the inner A-solves by one sparse
/// Cholesky factor of A (the same iterates as the thesis's inner CG, 4–20× faster).
fn uzawa_options() -> UzawaOptions {
    UzawaOptions {
        inner: InnerSolver::Cholesky,
        ..default_options()
    }
}

/// ψ at every vertex of the SubStokes values `u` (χ₁, χ₂, ψ per vertex) on `dofs`.
fn psi_values(dofs: &DofMap, u: &[f64]) -> Vec<f64> {
    (0..dofs.vertices.len() as u32)
        .map(|v| u[dofs.dof(v, PSI)])
        .collect()
}

/// The counter columns of a Uzawa solve.
fn uzawa_counters(stats: &UzawaStats) -> Vec<(String, i64)> {
    vec![
        ("uzawa_iterations".into(), stats.outer_iterations as i64),
        ("uzawa_inner_solves".into(), stats.inner_iterations as i64),
    ]
}

/// Arrows per side of the flow-rate field drawn over the pressure map.
const ARROWS: usize = 16;

/// The probe components of a SubStokes solution, in dof order: χ₁, χ₂, ψ.
pub const COMPONENTS: [&str; 3] = ["chi1", "chi2", "psi"];

/// The SubStokes film of one experiment inside the study loop.
pub struct SubStokesFilm {
    pub problem: SubStokesProblem,
    /// The options of the Theorem III.23 estimate (experiment field `stabilisation_residual`).
    pub options: Options,
    /// Whether the cavitation model runs, and where `auto` switched it on.
    pub switch: CavitationSwitch,
    previous_estimate: PreviousEstimate,
    /// The multipliers λ_j of the last cavitation solve (per dof).
    lambda: Option<Vec<f64>>,
    /// The previous cycle's solution (warm start of the cavitation active set).
    previous: Option<PreviousSolution>,
    /// Why the Reynolds comparison of the last mesh failed, if it did (a note of the table).
    comparison_failure: Option<String>,
    /// The solver of the coupled system (experiment field `solver`).
    film_solver: FilmSolver,
    solver: DirectSolver,
    domain: Rectangle,
}

/// The SubStokes problem of an experiment's data on `domain` (the point of `point = "corner"` is
/// the domain's lower-left corner).
pub fn substokes_problem(d: &SubStokesData, domain: &Rectangle) -> SubStokesProblem {
    SubStokesProblem::new(
        ThinFilm::new((&d.gap).into(), d.upper_wall_velocity),
        d.boundary_pressure,
    )
    .with_delta_eps(d.delta_eps)
    .with_cavitation_source(d.cavitation_source.into())
    .with_point(match d.point {
        PointCondition::None => None,
        PointCondition::Corner => Some([domain.x[0], domain.y[0]]),
    })
    .with_exact(d.exact.map(|name| ExactFlow::of(name, d.boundary_pressure)))
}

impl SubStokesFilm {
    pub fn new(data: &SubStokesData, domain: &Rectangle) -> SubStokesFilm {
        let problem = substokes_problem(data, domain);
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
            switch: CavitationSwitch::new(data.cavitation),
            previous_estimate: PreviousEstimate::default(),
            lambda: None,
            previous: None,
            comparison_failure: None,
            film_solver: data.solver,
            solver: DirectSolver::ldlt(Vec::new()),
            domain: *domain,
        }
    }

    /// Assemble the form of the model in use: (I.58), or (III.79) with cavitation.
    fn assemble_form(&self, disc: &Discretisation, system: &mut System) {
        if self.switch.is_on() {
            self.problem.assemble_cavitation(&disc.mesh, system);
        } else {
            self.problem.assemble(&disc.mesh, system);
        }
    }

    /// Initial active set of the cavitation solve, per dof: with `psi` (the solution without
    /// cavitation on this mesh), the ψ dofs where it is negative; otherwise the ψ dofs where
    /// the previous cycle's solution, interpolated to the new vertices, is ≤ 0.
    fn initial_active(&self, dofs: &DofMap, psi: Option<&[f64]>) -> Vec<bool> {
        let mut active = vec![false; dofs.n_dofs()];
        for (v, &x) in dofs.vertices.coords.iter().enumerate() {
            let d = dofs.dof(v as u32, PSI);
            active[d] = match (psi, &self.previous) {
                (Some(u), _) => u[d] < 0.0,
                (None, Some(previous)) => previous.value(PSI, x).is_some_and(|p| p <= 0.0),
                (None, None) => false,
            };
        }
        active
    }

    /// The cavitation solve (III.79) on the assembled system.
    fn solve_with_cavitation(
        &mut self,
        system: &System,
        free_solution: Option<&[f64]>,
    ) -> Result<Solution, StudyError> {
        let (sol, counters) = match self.film_solver {
            FilmSolver::Uzawa => {
                let options = CavitationUzawaOptions {
                    uzawa: uzawa_options(),
                    ..CavitationUzawaOptions::default()
                };
                let (sol, stats) = solve_cavitation_uzawa(system, free_solution, &options)?;
                (sol, uzawa_counters(&stats))
            }
            FilmSolver::Ldlt => {
                let initial = self.initial_active(&system.dofs, free_solution);
                let sol = solve_cavitation(system, &mut self.solver, &initial)?;
                let iterations = sol.iterations as i64;
                (sol, vec![("active_set_iterations".into(), iterations)])
            }
        };
        self.switch
            .after_cavitation_solve(&psi_values(&system.dofs, &sol.solution.u));
        self.lambda = Some(sol.lambda);
        Ok(Solution {
            u: sol.solution.u,
            counters,
        })
    }

    /// The solve of the model in use; with `auto`, a negative pressure of the solve without
    /// cavitation switches the cavitation model on for this and every later solve.
    fn solve_on_mesh(
        &mut self,
        disc: &Discretisation,
        system: &mut System,
        clock: &PhaseClock,
    ) -> Result<Solution, StudyError> {
        let solve = self.switch.begin_solve();
        self.lambda = None;
        if self.switch.is_on() {
            return self.solve_with_cavitation(system, None);
        }
        let (u, counters) = match self.film_solver {
            FilmSolver::Ldlt => (solve_system(system, &mut self.solver)?.0, Vec::new()),
            FilmSolver::Uzawa => {
                let (u, stats) = solve_uzawa(system, &uzawa_options())?;
                (u, uzawa_counters(&stats))
            }
        };
        if !self
            .switch
            .after_free_solve(solve, &psi_values(&system.dofs, &u))
        {
            return Ok(Solution { u, counters });
        }
        clock.time(Phase::Assemble, || self.assemble_form(disc, system));
        self.solve_with_cavitation(system, Some(&u))
    }

    /// Theorem III.24 with the lumped λ_h of the last cavitation solve and the stabilisation
    /// term `stabilisation`.
    fn estimate_cavitation(
        &self,
        disc: &Discretisation,
        dofs: &DofMap,
        u: &[f64],
        lambda: &[f64],
        stabilisation: Stabilisation,
    ) -> Result<SubStokesEstimate, StudyError> {
        let options = CavitationOptions {
            stabilisation,
            ..CavitationOptions::new(&self.problem)
        };
        let lumped = lumped_multiplier(&disc.mesh, dofs, u, lambda);
        Ok(estimate_cavitation(
            &disc.mesh,
            dofs,
            u,
            &lumped,
            &self.problem,
            options,
        )?)
    }
}

/// The weights (value, gradient) of χ₁, χ₂ and ψ in the norm of the true error
/// ([`true_error::substokes_norm`], [`reference::distance`]).
const NORM_WEIGHTS: [(f64, f64); 3] = [(1.0, 1.0), (1.0, 1.0), (1.0, 0.0)];

impl Problem for SubStokesFilm {
    fn setup(&mut self, disc: &Discretisation) -> System {
        let system = setup_system(disc, 3, &mut self.solver, |s| self.problem.constrain(s));
        self.solver.set_signs(SubStokesProblem::signs(&system.dofs));
        system
    }

    fn assemble(&mut self, disc: &Discretisation, system: &mut System) -> Result<(), StudyError> {
        self.assemble_form(disc, system);
        Ok(())
    }

    fn solve(
        &mut self,
        disc: &Discretisation,
        system: &mut System,
        clock: &PhaseClock,
    ) -> Result<Solution, StudyError> {
        let solution = self.solve_on_mesh(disc, system, clock);
        self.solver.release_pattern();
        solution
    }

    fn estimate(
        &mut self,
        disc: &Discretisation,
        dofs: &DofMap,
        solution: &Solution,
    ) -> Result<Estimate, StudyError> {
        let u = &solution.u;
        let (eta, theorem) = match &self.lambda {
            None => {
                let eta = estimate_with(&disc.mesh, dofs, u, &self.problem, self.options);
                (eta, None)
            }
            Some(lambda) => {
                let marked = self.options.stabilisation;
                let eta = self.estimate_cavitation(disc, dofs, u, lambda, marked)?;
                let printed = Stabilisation::DeltaEps(self.problem.delta_eps);
                let theorem = (marked != printed)
                    .then(|| self.estimate_cavitation(disc, dofs, u, lambda, printed))
                    .transpose()?;
                (eta, theorem.map(|t| t.total()))
            }
        };
        let parts = eta.part_roots();
        let total = eta.total();
        let mut estimate = Estimate::of_cells(eta.indicators);
        estimate.columns.push(self.previous_estimate.column(total));
        if let Some(t) = theorem {
            estimate = estimate.with(columns::THEOREM_ESTIMATE, t);
        }
        for (name, part) in PART_NAMES.iter().zip(parts) {
            estimate = estimate.with(&format!("eta_{name}"), part);
        }
        if let Some(exact) = &self.problem.exact {
            let error = true_error::substokes_norm(&disc.mesh, dofs, u, exact);
            estimate = estimate
                .with(columns::ERROR, error)
                .with(columns::EFFECTIVITY, total / error);
        }
        Ok(estimate)
    }

    fn finish_cycle(&mut self, disc: &Discretisation, dofs: DofMap, solution: Solution) {
        self.previous = self
            .switch
            .keeps_solution()
            .then(|| PreviousSolution::of(disc, dofs, solution.u));
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
        let comparison = Comparison {
            film: self.problem.film.clone(),
            boundary_pressure: self.problem.boundary_pressure,
            cavitation: self
                .switch
                .is_on()
                .then_some(self.problem.cavitation_source),
        };
        let cuts = match comparison.cuts(&disc.mesh, dofs, &solution.u, self.domain.x) {
            Ok(cuts) => Some(cuts),
            Err(e) => {
                self.comparison_failure = Some(e.to_string());
                None
            }
        };
        Pictures {
            deformed: Vec::new(),
            fields: vec![FieldPicture {
                arrows: field.arrows([0, 1], ARROWS),
                ..field.picture(cycle, "psi", PSI, self.switch.is_on())
            }],
            cuts,
        }
    }

    fn film(&self) -> Option<&crate::models::thin_film::ThinFilm> {
        Some(&self.problem.film)
    }

    fn component(&self, name: &str) -> Option<usize> {
        COMPONENTS.iter().position(|&c| c == name)
    }

    fn keeps_solves(&self) -> bool {
        true
    }

    /// The norm of [`true_error::substokes_norm`], (‖χ‖²_{H¹} + ‖ψ‖²_{L²})^{1/2}.
    fn solve_distance(
        &self,
        on: &crate::mesh::Mesh,
        a: reference::VertexField,
        b: reference::VertexField,
    ) -> Option<f64> {
        reference::weighted_distance(on, a, b, &NORM_WEIGHTS)
    }

    /// The reference of [`super::reference`]: the overlay of the kept meshes refined once,
    /// solved afresh by the LDLᵀ with the model in use at the end of the run (with cavitation
    /// where it ran, the active set warm-started from the last kept solve), and the distance of each kept solve to it in the norm of
    /// [`true_error::substokes_norm`] — (‖χ‖²_{H¹} + ‖ψ‖²_{L²})^{1/2}, the Euclidean form of the
    /// left-hand side of Theorems III.23/III.24 — extrapolated by e_k = √(d_k² + e_ref²),
    /// e_ref = d_last/√3 ([`super::reference::extrapolated_errors`]; for this saddle point an
    /// approximation, not the Pythagoras of a symmetric Galerkin problem).
    fn reference_errors(
        &mut self,
        kept: &[KeptSolve],
    ) -> Result<Result<ReferenceErrors, String>, StudyError> {
        let meshes: Vec<&crate::mesh::Mesh> = kept.iter().map(|k| &k.disc.mesh).collect();
        let Some(mesh) = reference::reference_mesh(&meshes)? else {
            return Ok(Err("the run kept no mesh".into()));
        };
        let start = std::time::Instant::now();
        let (dofs, u) = if self.switch.is_on() {
            // Warm start: active where the last kept solve has ψ ≤ 0 (one or two factorisations
            // instead of the cold start's many on the largest mesh of the run).
            let mut system = self.problem.system(&mesh);
            self.problem.assemble_cavitation(&mesh, &mut system);
            let mut solver = DirectSolver::ldlt(SubStokesProblem::signs(&system.dofs));
            solver.reorder(system.ordering());
            let last = kept
                .last()
                .map(|k| PreviousSolution::of(&k.disc, k.dofs.clone(), k.u.clone()));
            let mut initial = vec![false; system.dofs.n_dofs()];
            for (v, &x) in system.dofs.vertices.coords.iter().enumerate() {
                let p = last.as_ref().and_then(|l| l.value(PSI, x));
                initial[system.dofs.dof(v as u32, PSI)] = p.is_some_and(|p| p <= 0.0);
            }
            let s = solve_cavitation(&system, &mut solver, &initial)?.solution;
            (s.dofs, s.u)
        } else {
            let s = self.problem.solve(&mesh)?;
            (s.dofs, s.u)
        };
        let seconds = start.elapsed().as_secs_f64();
        let reference = reference::VertexField {
            mesh: &mesh,
            dofs: &dofs,
            u: &u,
        };
        Ok(reference::reference_errors(
            kept,
            dofs.n_dofs(),
            seconds,
            |field| reference::distance(reference, field, &NORM_WEIGHTS),
        ))
    }

    fn cavitation_ran(&self) -> Option<bool> {
        Some(self.switch.is_on())
    }

    fn quantities(
        &self,
        disc: &Discretisation,
        dofs: &DofMap,
        solution: &Solution,
    ) -> Vec<(String, f64)> {
        let component = |name| COMPONENTS.iter().position(|&c| c == name).expect(name);
        let film = FilmSolution {
            film: &self.problem.film,
            boundary_pressure: self.problem.boundary_pressure,
            u: &solution.u,
            psi: component("psi"),
            chi: Some([component("chi1"), component("chi2")]),
            cavitation: self.switch.is_on(),
        };
        quantities::film(&disc.mesh, dofs, &film)
    }

    fn notes(&self) -> Vec<String> {
        let failure = self.comparison_failure.as_ref().map(|e| {
            format!("The Reynolds comparison on the last mesh could not be computed: {e}")
        });
        self.switch.note().into_iter().chain(failure).collect()
    }
}
