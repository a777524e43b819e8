//! Tables IV.1–IV.5: linear elasticity (I.17) with the estimator of Theorem III.12.

use std::time::Instant;

use super::{AdaptiveModel, Estimate, Solution};
use crate::estimators::{self, elasticity::BoundaryTerms};
use crate::experiment::ExperimentSpec;
use crate::fe::{DofMap, SparseSystem};
use crate::mesh::Mesh;
use crate::models::elasticity::Elasticity;
use crate::results::{PhaseSeconds, RunResult};

/// The elasticity model of one experiment.
pub struct ElasticityStudy {
    problem: Elasticity,
    terms: BoundaryTerms,
}

impl ElasticityStudy {
    pub fn new(spec: &ExperimentSpec) -> ElasticityStudy {
        let data = spec
            .scene
            .elasticity
            .as_ref()
            .expect("validated: elasticity data");
        ElasticityStudy {
            problem: Elasticity::from_data(data),
            terms: BoundaryTerms::default(),
        }
    }
}

impl AdaptiveModel for ElasticityStudy {
    fn n_components(&self) -> usize {
        2
    }

    fn solve(
        &mut self,
        mesh: &Mesh,
        dofs: &DofMap,
        system: &mut SparseSystem,
        seconds: &mut PhaseSeconds,
    ) -> Result<Solution, String> {
        let t = Instant::now();
        let fixed = self.problem.fixed_dofs(dofs);
        let (matrix, rhs) = self.problem.assemble(mesh, system);
        seconds.assemble += t.elapsed().as_secs_f64();
        let t = Instant::now();
        let mut u = system
            .solve_fixed(&matrix, &rhs, &fixed)
            .map_err(|e| e.to_string())?;
        dofs.distribute_hanging(&mut u);
        seconds.solve += t.elapsed().as_secs_f64();
        Ok(Solution {
            u,
            counters: Vec::new(),
        })
    }

    fn estimate(&mut self, mesh: &Mesh, dofs: &DofMap, u: &[f64]) -> Estimate {
        Estimate {
            eta2: estimators::elasticity::indicators(mesh, dofs, u, &self.problem, &self.terms),
            quantities: Vec::new(),
        }
    }

    fn last_cycle(
        &mut self,
        spec: &ExperimentSpec,
        mesh: &Mesh,
        dofs: &DofMap,
        u: &[f64],
        cycle: usize,
        result: &mut RunResult,
    ) {
        let d = spec.scene.domain;
        result.deformed.push(super::deformed_picture(
            mesh,
            dofs,
            u,
            cycle,
            Some(d.y[1] - d.y[0]),
        ));
    }
}
