//! Solver benchmark (not a test): the Reynolds system of Table IV.36 and the elasticity system of
//! Table IV.1 on adaptively refined meshes of about 50 k, 200 k, 700 k and 1.5 M unknowns, solved
//! by the sparse Cholesky factorisation and by multigrid-preconditioned CG; and the contact
//! problems of Table IV.6 (z-contact, `contact-z`) and IV.12 (Signorini, linearised about the
//! z-solution, `contact-signorini`) on the strip of those scenes refined towards its contact face,
//! solved by the primal–dual active-set method with the direct solver (`direct`, from an empty
//! active set) and by the truncated nonsmooth Newton multigrid method (`tnnmg`,
//! [`tribo::linalg::multigrid::obstacle`]). For each: seconds (the direct solver's ordering and
//! the multigrid hierarchy included, as in a study's cycle), seconds per million unknowns,
//! iterations (CG iterations of multigrid; for contact the active-set iterations of `direct`, and
//! the TNNMG iterations + the CG iterations of its final solve of `tnnmg`, with the iteration
//! after which its active set no longer changed), the peak memory of
//! the solve above what the assembled system holds (each measurement runs in its own process),
//! and for contact the number of active constraints. Writes `target/bench/solve.csv`.
//!
//! `cargo bench --bench solve [-- <filter>…]`: only the problems whose name contains a filter
//! (`reynolds`, `elasticity`, `contact`, `contact-z`, …).

use std::time::Instant;

use tribo::experiment;
use tribo::fe::hierarchy::vertex_hierarchy;
use tribo::fe::System;
use tribo::linalg::multigrid::obstacle::TnnmgOptions;
use tribo::linalg::DirectSolver;
use tribo::linalg::{LinearSolver, SolverKind};
use tribo::mesh::Mesh;
use tribo::models::contact::{
    contact_boundaries, solve_contact, solve_contact_tnnmg, ConstraintBuilder, ContactModel,
};
use tribo::models::elasticity::Elasticity;
use tribo::models::reynolds::{Load, ReynoldsProblem};
use tribo::study::problem::PrepareSolver;

const TARGETS: [usize; 4] = [50_000, 200_000, 700_000, 1_500_000];

/// A mesh of the unit square refined towards a circle (hanging vertices on many levels, as in
/// an adaptive run) until it has at least `unknowns` dofs with `components` per vertex.
fn mesh_with(unknowns: usize, components: usize) -> Mesh {
    let mut mesh = Mesh::new([0.0, 1.0], [0.0, 1.0], 1, 1);
    for _ in 0..5 {
        mesh.refine_global().expect("refines");
    }
    let cells = unknowns.div_ceil(components);
    while mesh.n_active() < cells {
        // Refine the cells nearest to the circle r = 0.3, as many as bring the mesh to its
        // size (each refinement adds three cells), at most a third of them per step.
        let distance = |b: [f64; 4]| {
            let (x, y) = (0.5 * (b[0] + b[2]) - 0.5, 0.5 * (b[1] + b[3]) - 0.5);
            ((x * x + y * y).sqrt() - 0.3).abs()
        };
        let wanted = ((cells - mesh.n_active()) / 3 + 1).min(mesh.n_active() / 3 + 1);
        refine_first(&mut mesh, wanted, distance);
    }
    mesh
}

/// The strip of Tables IV.6 and IV.12 (32 × 1, 64 × 2 coarse cells) refined globally, then
/// towards its contact face (the bottom, cells nearest to it first), until it has at least
/// `unknowns` dofs (two per vertex).
fn contact_mesh(scene: &experiment::Scene, unknowns: usize) -> Mesh {
    let [cx, cy] = scene.coarse_cells;
    let mut mesh = Mesh::new(scene.domain.x, scene.domain.y, cx, cy);
    let dofs = |m: &Mesh| 2 * m.n_active();
    while 4 * dofs(&mesh) <= unknowns {
        mesh.refine_global().expect("refines");
    }
    while dofs(&mesh) < unknowns {
        let wanted = ((unknowns - dofs(&mesh)) / 6 + 1).min(mesh.n_active() / 3 + 1);
        refine_first(&mut mesh, wanted, |b| b[1]);
    }
    mesh
}

/// Refine the `wanted` active cells of `mesh` whose boxes have the smallest `key`.
fn refine_first(mesh: &mut Mesh, wanted: usize, key: impl Fn([f64; 4]) -> f64) {
    let keys: Vec<f64> = mesh
        .active()
        .iter()
        .map(|&c| key(mesh.cell_box(c)))
        .collect();
    let mut order: Vec<usize> = (0..mesh.n_active()).collect();
    order.sort_by(|&a, &b| keys[a].total_cmp(&keys[b]));
    let mut flags = vec![false; mesh.n_active()];
    for &k in order.iter().take(wanted) {
        flags[k] = true;
    }
    let none = vec![false; flags.len()];
    mesh.refine_and_coarsen(&flags, &none).expect("refines");
}

/// One contact measurement (`problem` `contact-z` or `contact-signorini`): the iterations and the
/// number of active constraints beside the CSV line's other fields.
fn one_contact(problem: &str, target: usize, solver: &str) -> (Measured, usize, String, usize) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let path = dir.join("experiments").join("IV.6.toml");
    let iv6 = experiment::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let experiment::Problem::Contact {
        elasticity,
        contact,
    } = &iv6.problem
    else {
        panic!("IV.6 is contact")
    };
    let mesh = contact_mesh(&iv6.scene, target);
    let mut system = System::new(&mesh, 2);
    let model = Elasticity::from(elasticity);
    model.constrain(&mut system);
    model.assemble(&mesh, &mut system);
    let n = system.dofs.n_dofs();
    let boundaries = contact_boundaries(contact);
    let build = |model: ContactModel, s0: Option<&[f64]>| {
        let faces = move |_| model;
        ConstraintBuilder {
            boundaries: &boundaries,
            face_model: &faces,
        }
        .build(&system.dofs, &system.constraints, s0)
        .expect("constraints")
    };
    let options = TnnmgOptions::default();
    let tnnmg = |constraints: &[tribo::models::contact::ContactConstraint]| {
        let levels = vertex_hierarchy(&mesh, &system.dofs.vertices);
        solve_contact_tnnmg(&system, &levels, constraints, &options).expect("TNNMG")
    };
    // The Signorini constraints are linearised about the z-solution (by TNNMG, untimed, the
    // same for both solvers).
    let constraints = if problem == "contact-signorini" {
        let z = tnnmg(&build(ContactModel::Z, None)).0;
        build(ContactModel::Signorini, Some(&z.u))
    } else {
        build(ContactModel::Z, None)
    };
    let mut iterations = String::new();
    let mut active = 0;
    let m = measure(|| {
        let solution = if solver == "direct" {
            let s = solve_contact(&system, &mut DirectSolver::cholesky(), &constraints, None)
                .expect("active set");
            iterations = s.iterations.to_string();
            s
        } else {
            let (s, work) = tnnmg(&constraints);
            iterations = format!(
                "{}+{} (settled {})",
                s.iterations, work.cg_iterations, work.settled_after
            );
            s
        };
        active = solution.active.iter().filter(|&&a| a).count();
        (solution.u, None)
    });
    (m, n, iterations, active)
}

/// Resident memory now and the peak since the last reset, in bytes (`/proc/self/status`).
fn memory() -> (f64, f64) {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let field = |name: &str| {
        status
            .lines()
            .find(|l| l.starts_with(name))
            .and_then(|l| l.split_whitespace().nth(1))
            .and_then(|v| v.parse::<f64>().ok())
            .map_or(f64::NAN, |kib| kib * 1024.0)
    };
    (field("VmRSS:"), field("VmHWM:"))
}

struct Measured {
    seconds: f64,
    iterations: Option<usize>,
    extra_bytes: f64,
    solution: Vec<f64>,
}

fn measure(f: impl FnOnce() -> (Vec<f64>, Option<usize>)) -> Measured {
    let (before, _) = memory();
    let t = Instant::now();
    let (solution, iterations) = f();
    let seconds = t.elapsed().as_secs_f64();
    let (_, peak) = memory();
    Measured {
        seconds,
        iterations,
        extra_bytes: peak - before,
        solution,
    }
}

/// One measurement in this process: `solve <problem> <unknowns> <solver>` prints one CSV line.
fn one(problem: &str, target: usize, solver: &str) {
    if problem.starts_with("contact") {
        let (m, n, iterations, active) = one_contact(problem, target, solver);
        assert!(
            m.solution.iter().all(|v| v.is_finite()),
            "{problem} {n} {solver}: a non-finite solution"
        );
        println!(
            "{problem},{n},{solver},{},{},{iterations},{},{active}",
            m.seconds,
            m.seconds / (n as f64 / 1e6),
            m.extra_bytes / 1e6
        );
        return;
    }
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let load = |t: &str| {
        experiment::load(&dir.join("experiments").join(format!("{t}.toml")))
            .unwrap_or_else(|e| panic!("{e}"))
    };
    let components = if problem == "reynolds" { 1 } else { 2 };
    let mesh = mesh_with(target, components);
    let mut system = System::new(&mesh, components);
    if components == 1 {
        let iv36 = load("IV.36");
        let reynolds = ReynoldsProblem::from(iv36.problem.reynolds().expect("IV.36 is Reynolds"));
        reynolds.constrain(&mut system);
        let data = reynolds.cell_data(&mesh, Load::Reynolds);
        reynolds.assemble(&mesh, &mut system, &data);
    } else {
        let iv1 = load("IV.1");
        let experiment::Problem::Elasticity(elastic) = &iv1.problem else {
            panic!("IV.1 is elasticity")
        };
        let elasticity = Elasticity::from(elastic);
        elasticity.constrain(&mut system);
        elasticity.assemble(&mesh, &mut system);
    }
    let n = system.dofs.n_dofs();
    let kind = match solver {
        "direct" => SolverKind::Direct,
        _ => SolverKind::Multigrid,
    };
    // Prepared and solved as a study's cycle does (study::problem::setup_system).
    let m = measure(|| {
        let mut s = LinearSolver::spd(kind);
        let levels = s
            .needs_levels()
            .then(|| vertex_hierarchy(&mesh, &system.dofs.vertices));
        s.prepare(&system, levels);
        let u = system.solve(&mut s).expect("solve");
        (u, s.take_iterations().and_then(|k| k.first().copied()))
    });
    let finite = m.solution.iter().all(|v| v.is_finite());
    assert!(finite, "{problem} {n} {solver}: a non-finite solution");
    let cg = m.iterations.map_or(String::new(), |k| k.to_string());
    println!(
        "{problem},{n},{solver},{},{},{cg},{},",
        m.seconds,
        m.seconds / (n as f64 / 1e6),
        m.extra_bytes / 1e6
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if let Some(i) = args.iter().position(|a| a == "solve") {
        let target = args[i + 2].parse().expect("unknowns");
        one(&args[i + 1], target, &args[i + 3]);
        return;
    }
    // `cargo bench` passes `--bench`; any other argument is a filter on the problem names.
    let filters: Vec<&String> = args[1..].iter().filter(|a| !a.starts_with('-')).collect();
    // Each measurement in its own process, so that its peak memory is its own.
    let mut csv = String::from(
        "problem,unknowns,solver,seconds,seconds_per_million_unknowns,iterations,solve_peak_mb,\
         active\n",
    );
    println!(
        "{:<17} {:>9}  {:>9} {:>8} {:>8} {:>20} {:>9} {:>6}",
        "problem", "unknowns", "solver", "s", "s/M", "iter", "peak MB", "active"
    );
    let problems = [
        ("reynolds", ["direct", "multigrid"]),
        ("elasticity", ["direct", "multigrid"]),
        ("contact-z", ["direct", "tnnmg"]),
        ("contact-signorini", ["direct", "tnnmg"]),
    ];
    for (problem, solvers) in problems {
        if !filters.is_empty() && !filters.iter().any(|f| problem.contains(f.as_str())) {
            continue;
        }
        for target in TARGETS {
            for solver in solvers {
                let out = std::process::Command::new(&args[0])
                    .args(["solve", problem, &target.to_string(), solver])
                    .output()
                    .expect("runs itself");
                assert!(
                    out.status.success(),
                    "{problem} {target} {solver}: {}",
                    String::from_utf8_lossy(&out.stderr)
                );
                let line = String::from_utf8_lossy(&out.stdout).trim().to_string();
                let f: Vec<&str> = line.split(',').collect();
                let num = |i: usize| f[i].parse::<f64>().unwrap_or(f64::NAN);
                println!(
                    "{:<17} {:>9}  {:>9} {:>8.3} {:>8.3} {:>20} {:>9.0} {:>6}",
                    f[0],
                    f[1],
                    f[2],
                    num(3),
                    num(4),
                    f[5],
                    num(6),
                    f.get(7).copied().unwrap_or("")
                );
                csv += &line;
                csv += "\n";
            }
        }
    }
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = dir.join("target").join("bench");
    std::fs::create_dir_all(&out).expect("target/bench");
    std::fs::write(out.join("solve.csv"), csv).expect("write solve.csv");
    println!("wrote {}", out.join("solve.csv").display());
}
