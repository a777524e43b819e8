//! Tables IV.1–IV.5: linear elasticity (I.17) with the estimator of Theorem III.12; scenes with
//! a manufactured solution add the true error and the effectivity to each row.

use super::clock::PhaseClock;
use super::error::StudyError;
use super::problem::{
    cg_column, setup_system, Discretisation, Estimate, Pictures, Problem, Solution,
};
use crate::estimators::{self, elasticity::BoundaryTerms};
use crate::experiment::{ElasticityData, Rectangle};
use crate::fe::{DofMap, System};
use crate::linalg::{LinearSolver, SolverKind};
use crate::mesh::Mesh;
use crate::models::elasticity::Elasticity;
use crate::models::manufactured::ExactDisplacement;
use crate::results::{columns, sig4, DeformedPicture};

/// The elasticity problem of one experiment.
pub struct ElasticityProblem {
    model: Elasticity,
    terms: BoundaryTerms,
    solver: LinearSolver,
    /// Height of the domain, the scale of the deformed-body picture.
    height: f64,
    /// The manufactured solution of the scene, if it has one: then each row gets the true
    /// error and the effectivity.
    exact: Option<ExactDisplacement>,
}

impl ElasticityProblem {
    /// The problem of `data` on `domain`, solved by `solver` ([`super::solver_of`]).
    pub fn new(data: &ElasticityData, domain: &Rectangle, solver: SolverKind) -> ElasticityProblem {
        ElasticityProblem {
            model: data.into(),
            terms: BoundaryTerms::default(),
            solver: LinearSolver::spd(solver),
            height: domain.y[1] - domain.y[0],
            exact: data.exact.map(ExactDisplacement::of),
        }
    }
}

/// The displacement components of a probe: `s1` and `s2`.
pub fn displacement_component(name: &str) -> Option<usize> {
    match name {
        "s1" => Some(0),
        "s2" => Some(1),
        _ => None,
    }
}

impl Problem for ElasticityProblem {
    fn setup(&mut self, disc: &Discretisation) -> System {
        setup_system(disc, 2, &mut self.solver, |s| self.model.constrain(s))
    }

    fn assemble(&mut self, disc: &Discretisation, system: &mut System) -> Result<(), StudyError> {
        self.model.assemble(&disc.mesh, system);
        Ok(())
    }

    fn solve(
        &mut self,
        _disc: &Discretisation,
        system: &mut System,
        _clock: &PhaseClock,
    ) -> Result<Solution, StudyError> {
        let u = system.solve(&mut self.solver);
        let cg = self.solver.take_iterations();
        self.solver.release_pattern();
        Ok(Solution {
            u: u?,
            counters: cg_column(cg).into_iter().collect(),
        })
    }

    fn estimate(
        &mut self,
        disc: &Discretisation,
        dofs: &DofMap,
        solution: &Solution,
    ) -> Result<Estimate, StudyError> {
        let estimate = Estimate::of_cells(estimators::elasticity::indicators(
            &disc.mesh,
            dofs,
            &solution.u,
            &self.model,
            &self.terms,
        ));
        let Some(exact) = &self.exact else {
            return Ok(estimate);
        };
        let error = estimators::true_error::elasticity_energy(
            &disc.mesh,
            dofs,
            &solution.u,
            &self.model,
            exact,
        );
        let effectivity = estimators::total(&estimate.cells) / error;
        Ok(estimate
            .with(columns::ERROR, error)
            .with(columns::EFFECTIVITY, effectivity))
    }

    fn pictures(
        &mut self,
        disc: &Discretisation,
        dofs: &DofMap,
        solution: &Solution,
        cycle: usize,
    ) -> Pictures {
        Pictures {
            deformed: vec![deformed_picture(
                &disc.mesh,
                dofs,
                &solution.u,
                cycle,
                Some(self.height),
            )],
            fields: Vec::new(),
            ..Pictures::default()
        }
    }

    fn component(&self, name: &str) -> Option<usize> {
        displacement_component(name)
    }

    fn elasticity(&self) -> Option<&Elasticity> {
        Some(&self.model)
    }

    fn energy(&self, disc: &Discretisation, dofs: &DofMap, solution: &Solution) -> Option<f64> {
        Some(self.model.energy(&disc.mesh, dofs, &solution.u))
    }
}

/// The deformed body x + scale·s(x). With `magnify_to = Some(height)` small displacements are
/// magnified so that the largest one is half of `height`; with `None` the picture is true scale
/// (contact pictures, whose obstacle curves are in true scale too).
pub fn deformed_picture(
    mesh: &Mesh,
    dofs: &DofMap,
    u: &[f64],
    cycle: usize,
    magnify_to: Option<f64>,
) -> DeformedPicture {
    let max = u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let scale = match magnify_to {
        Some(height) if max > 0.0 && max < 0.5 * height => (0.5 * height / max).round().max(1.0),
        _ => 1.0,
    };
    let quads = (0..mesh.n_active())
        .map(|k| {
            let cv = dofs.vertices.cell_vertices[k];
            // counter-clockwise from the lower-left corner
            [cv[0], cv[1], cv[3], cv[2]].map(|v| dofs.displaced(u, v, scale))
        })
        .collect();
    DeformedPicture {
        cycle,
        scale,
        quads,
        obstacles: Vec::new(),
        contact_points: Vec::new(),
        accurate_faces: Vec::new(),
        caption: format!("largest displacement component {}", sig4(max)),
    }
}
