//! Mesh benchmark (not a test): grow a forest to ~1.5 million active cells by adaptive-style
//! refinement and time refinement, vertex numbering with hanging nodes, and the sparsity pattern.
//!
//! `cargo bench --bench mesh`

use std::time::Instant;

use tribo::fe::{Constraints, DofMap, SparsityPattern};
use tribo::mesh::Mesh;

fn main() {
    let mut mesh = Mesh::new([0.0, 1.0], [0.0, 1.0], 64, 64);
    let target = 1_500_000;
    let mut step = 0;
    while mesh.n_active() < target {
        // Refine the cells nearer to a circle than a shrinking band: local, hanging-node rich.
        let band = 0.5f64.powi(step / 2 + 1);
        let flags: Vec<bool> = mesh
            .active()
            .iter()
            .map(|&c| {
                let b = mesh.cell_box(c);
                let (x, y) = (0.5 * (b[0] + b[2]) - 0.5, 0.5 * (b[1] + b[3]) - 0.5);
                ((x * x + y * y).sqrt() - 0.3).abs() < band.max(0.02) || step < 2
            })
            .collect();
        let none = vec![false; flags.len()];
        let t = Instant::now();
        mesh.refine_and_coarsen(&flags, &none)
            .expect("above the deepest level");
        println!(
            "refine step {step:>2}: {:>9} active cells  {:>7.3} s",
            mesh.n_active(),
            t.elapsed().as_secs_f64()
        );
        step += 1;
    }
    assert!(mesh.is_balanced());
    let t = Instant::now();
    let dofs = DofMap::new(&mesh, 1);
    println!(
        "vertices: {} ({} hanging)  {:.3} s",
        dofs.vertices.len(),
        dofs.vertices.hanging.len(),
        t.elapsed().as_secs_f64()
    );
    let t = Instant::now();
    let pattern = SparsityPattern::new(&dofs, &Constraints::new(&dofs));
    println!(
        "sparsity pattern: {} nonzeros  {:.3} s",
        pattern.nnz(),
        t.elapsed().as_secs_f64()
    );
    let t = Instant::now();
    let all = vec![true; mesh.n_active()];
    let none = vec![false; mesh.n_active()];
    mesh.refine_and_coarsen(&none, &all).expect("coarsening");
    println!(
        "coarsen everything once: {} active cells  {:.3} s",
        mesh.n_active(),
        t.elapsed().as_secs_f64()
    );
}
