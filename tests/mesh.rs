//! The quadtree mesh, hanging-node constraints and the marking rule.

use crate::common::refine_around;
use tribo::adaptivity::{apply_noise_floor, mark_fixed_number, rounded_measure, PLATEAU_CELLS};
use tribo::fe::{Constraints, DofMap};
use tribo::mesh::{BoundaryFace, Mesh, MeshError, Neighbor, Side, FACES, MAX_LEVEL};

#[test]
fn twelve_levels_of_local_refinement_keep_two_to_one_and_valid_constraints() {
    let mut mesh = Mesh::new([-16.0, 16.0], [0.0, 1.0], 64, 2);
    refine_around(&mut mesh, [0.3, 0.7], 12);
    assert!(mesh.is_balanced(), "2:1 rule violated");
    let max_level = mesh.active().iter().map(|&c| mesh.level(c)).max().unwrap();
    assert_eq!(max_level, 12);
    let dofs = DofMap::new(&mesh, 1);
    let v = &dofs.vertices;
    assert_hanging_vertices_are_midpoints(&dofs, 1e-12);
    // Every hanging vertex lies on a face between a coarse and two fine cells, and every such
    // face has exactly one hanging vertex.
    let mut faces_with_finer = 0;
    for &c in mesh.active() {
        for f in FACES {
            if let Neighbor::Finer(k) = mesh.neighbor(c, f) {
                faces_with_finer += 1;
                assert!(k.iter().all(|&x| mesh.is_active(x)));
            }
        }
    }
    assert_eq!(faces_with_finer, v.hanging.len());
    // A linear function interpolated at the parents reproduces itself at hanging vertices.
    let lin = |p: [f64; 2]| 3.0 * p[0] - 2.0 * p[1] + 0.5;
    let mut u: Vec<f64> = v.coords.iter().map(|&p| lin(p)).collect();
    for h in &v.hanging {
        u[h.vertex as usize] = f64::NAN;
    }
    Constraints::new(&dofs).distribute(&mut u);
    for (i, p) in v.coords.iter().enumerate() {
        assert!((u[i] - lin(*p)).abs() < 1e-12);
    }
}

/// The table of every cell's neighbours (built top-down, level by level) gives what the
/// neighbour query gives, on an adapted mesh with refinement and coarsening, on its level
/// meshes, and on a grid of several coarse cells.
#[test]
fn the_face_neighbour_table_agrees_with_the_neighbour_query() {
    let mut mesh = Mesh::new([-2.0, 2.0], [0.0, 1.0], 4, 2);
    refine_around(&mut mesh, [0.3, 0.7], 7);
    refine_around(&mut mesh, [-1.0, 0.0], 5);
    // Coarsen what the first refinement made near its point, refine a band elsewhere.
    let refine: Vec<bool> = mesh
        .active()
        .iter()
        .map(|&c| mesh.cell_box(c)[0] > 1.5)
        .collect();
    let coarsen: Vec<bool> = mesh.active().iter().map(|&c| mesh.level(c) >= 6).collect();
    mesh.refine_and_coarsen(&refine, &coarsen).unwrap();
    let max_level = mesh.active().iter().map(|&c| mesh.level(c)).max().unwrap();
    let mut checked = [0usize; 4];
    for m in (0..=max_level)
        .map(|l| mesh.truncated(l))
        .chain([mesh.clone()])
    {
        let table = m.face_neighbors();
        for &c in m.active() {
            for f in FACES {
                let (expected, got) = (m.neighbor(c, f), m.neighbor_in(&table, c, f));
                assert_eq!(got, expected, "cell {c} face {f:?}");
                checked[match expected {
                    Neighbor::Boundary(_) => 0,
                    Neighbor::Same(_) => 1,
                    Neighbor::Coarser(_) => 2,
                    Neighbor::Finer(_) => 3,
                }] += 1;
            }
        }
    }
    assert!(
        checked.iter().all(|&n| n > 100),
        "every kind of neighbour seen: {checked:?}"
    );
}

/// The cell listed as each vertex's owner is the one `cell_at_vertex` finds (the multigrid
/// prolongation starts from it), and its ancestor at a coarser level is the cell of the level
/// mesh that holds the vertex — on an adapted mesh and on each of its level meshes.
#[test]
fn the_owner_of_a_vertex_is_the_cell_that_holds_it() {
    let mut mesh = Mesh::new([0.0, 3.0], [0.0, 1.0], 3, 1);
    refine_around(&mut mesh, [2.9, 0.95], 6);
    refine_around(&mut mesh, [0.2, 0.3], 4);
    let max_level = mesh.active().iter().map(|&c| mesh.level(c)).max().unwrap();
    for m in (0..=max_level)
        .map(|l| mesh.truncated(l))
        .chain([mesh.clone()])
    {
        let v = DofMap::new(&m, 1).vertices;
        assert_eq!(v.owner.len(), v.len());
        let finest = m.active().iter().map(|&c| m.level(c)).max().unwrap();
        let coarser: Vec<Mesh> = (0..finest).map(|l| mesh.truncated(l)).collect();
        for (k, &owner) in v.keys.iter().zip(&v.owner) {
            assert_eq!(owner, m.cell_at_vertex(*k), "vertex {k:?}");
            for (level, coarse) in coarser.iter().enumerate() {
                let cell = mesh.ancestor_at(owner, level as u8);
                assert_eq!(
                    cell,
                    coarse.cell_at_vertex(*k),
                    "vertex {k:?} on level {level}"
                );
            }
        }
    }
}

/// The previous mesh's cell that holds a vertex of the next mesh, found from the vertex's
/// cell through the refinement's lineage, is the one a search of the previous mesh finds —
/// after refinement and coarsening; a mesh of another lineage gets none.
#[test]
fn the_previous_cell_of_a_vertex_is_found_through_the_lineage() {
    let mut before = Mesh::new([0.0, 2.0], [0.0, 1.0], 2, 1);
    refine_around(&mut before, [0.6, 0.4], 5);
    let mut after = before.clone();
    let refine: Vec<bool> = after
        .active()
        .iter()
        .map(|&c| after.cell_box(c)[0] > 1.2)
        .collect();
    let coarsen: Vec<bool> = after
        .active()
        .iter()
        .map(|&c| after.level(c) >= 4)
        .collect();
    after.refine_and_coarsen(&refine, &coarsen).unwrap();
    let v = DofMap::new(&after, 1).vertices;
    for (k, &owner) in v.keys.iter().zip(&v.owner) {
        let expected = before.cell_at_vertex(*k);
        assert_eq!(
            after.cell_at_vertex_in(&before, owner, *k),
            Some(expected),
            "{k:?}"
        );
    }
    // The same storage: the cell itself is a start.
    let c = after.active()[7];
    let key = after.corner_keys(c)[0];
    assert_eq!(after.cell_at_vertex_in(&after, c, key), Some(c));
    let other = Mesh::new([0.0, 2.0], [0.0, 1.0], 2, 1);
    assert_eq!(after.cell_at_vertex_in(&other, c, key), None);
}

/// Coarse grids more than 128 cells wide (integer positions past 2³¹, whose vertex
/// midpoints overflowed 32 bits: "hanging vertex exists") or 256 wide (past 2³²: an assert in
/// `Mesh::new`). Hanging vertices at the far end of the strip, in x₁ and turned in x₂, are the
/// midpoints of their parents.
#[test]
fn grids_wider_than_128_coarse_cells_number_their_hanging_vertices() {
    for n in [129, 255, 256, 300] {
        let far = n as f64 - 0.3;
        for (nx, ny, p) in [(n, 2, [far, 0.7]), (2, n, [0.7, far])] {
            let mut mesh = Mesh::new([0.0, nx as f64], [0.0, ny as f64], nx, ny);
            refine_around(&mut mesh, p, 3);
            assert!(mesh.is_balanced());
            let dofs = DofMap::new(&mesh, 1);
            assert_hanging_vertices_are_midpoints(&dofs, 1e-12);
            let v = &dofs.vertices;
            let far_hanging = v
                .hanging
                .iter()
                .filter(|h| v.coords[h.vertex as usize][if nx > ny { 0 } else { 1 }] > 128.0)
                .count();
            assert!(far_hanging > 0, "{nx} × {ny}: no hanging vertex past 128");
            // The right and top sides are found at the grid's extent.
            let right = v.side_vertices(Side::Right);
            let top = v.side_vertices(Side::Top);
            assert!(right.len() > ny && top.len() > nx);
            assert!(right.iter().all(|&r| v.coords[r as usize][0] == nx as f64));
            assert!(top.iter().all(|&t| v.coords[t as usize][1] == ny as f64));
        }
    }
}

/// The vertex list (built from one entry per vertex: lower-left corners, hanging midpoints of
/// left and bottom faces, corners on the right and top sides) is exactly the set of corners of
/// the active cells, sorted by integer position.
#[test]
fn vertices_are_the_corners_of_the_active_cells_each_once() {
    let mut meshes = Vec::new();
    let mut mesh = Mesh::new([-16.0, 16.0], [0.0, 1.0], 64, 2);
    refine_around(&mut mesh, [0.3, 0.7], 8);
    refine_around(&mut mesh, [16.0, 1.0], 5);
    refine_around(&mut mesh, [-16.0, 0.25], 4);
    meshes.push(mesh);
    let mut mesh = Mesh::new([0.0, 1.0], [0.0, 3.0], 1, 3);
    refine_around(&mut mesh, [0.5, 1.5], 6);
    meshes.push(mesh);
    let mut mesh = Mesh::new([0.0, 2.0], [0.0, 300.0], 2, 300);
    refine_around(&mut mesh, [2.0, 300.0], 3);
    refine_around(&mut mesh, [0.0, 150.0], 3);
    meshes.push(mesh);
    meshes.push(Mesh::new([0.0, 1.0], [0.0, 1.0], 1, 1));
    for mesh in &meshes {
        let mut corners: Vec<_> = mesh
            .active()
            .iter()
            .flat_map(|&c| mesh.corner_keys(c))
            .collect();
        corners.sort_unstable();
        corners.dedup();
        let dofs = DofMap::new(mesh, 1);
        assert_eq!(dofs.vertices.keys, corners, "{:?}", mesh.coarse_cells());
    }
}

/// A cell of the deepest level cannot be refined (its children would have no integer
/// position); the refinement fails, names the cell and the mesh's levels, and leaves the mesh as
/// it was.
#[test]
fn refining_a_cell_of_the_deepest_level_fails_and_keeps_the_mesh() {
    let mut mesh = Mesh::new([-16.0, 16.0], [0.0, 1.0], 64, 2);
    let p = [0.3, 0.7];
    refine_around(&mut mesh, p, MAX_LEVEL as usize);
    assert!(mesh.is_balanced());
    let deepest = mesh.locate(p).unwrap();
    assert_eq!(mesh.level(deepest), MAX_LEVEL);
    let before = mesh.active().to_vec();
    let flags: Vec<bool> = before.iter().map(|&c| c == deepest).collect();
    let none = vec![false; flags.len()];
    let err = mesh.refine_and_coarsen(&flags, &none).unwrap_err();
    let MeshError::PastDeepestLevel { centre } = err else {
        panic!("{err}");
    };
    let b = mesh.cell_box(deepest);
    assert!(
        (centre[0] - (b[0] + b[2]) / 2.0).abs() < 1e-12,
        "{centre:?} not in {b:?}"
    );
    assert!(
        (centre[1] - (b[1] + b[3]) / 2.0).abs() < 1e-12,
        "{centre:?} not in {b:?}"
    );
    assert!(
        err.to_string()
            .contains("the mesh supports 24 refinement levels"),
        "{err}"
    );
    assert_eq!(mesh.active(), &before[..], "the mesh changed");
    // A cell one level coarser still refines.
    let coarser: Vec<bool> = before
        .iter()
        .map(|&c| mesh.level(c) == MAX_LEVEL - 1)
        .collect();
    assert!(coarser.iter().any(|&f| f));
    assert!(mesh.refine_and_coarsen(&coarser, &none).is_ok());
}

/// A coarse grid the mesh cannot number is an error, not a panic or an allocation failure.
#[test]
fn coarse_grids_without_cells_or_beyond_the_cell_ids_are_errors() {
    let grid = |nx, ny| Mesh::try_new([0.0, 1.0], [0.0, 1.0], nx, ny).map(|m| m.n_active());
    assert_eq!(grid(3, 2), Ok(6));
    for (nx, ny) in [(0, 2), (2, 0), (1 << 20, 1 << 12), (usize::MAX, 2)] {
        assert_eq!(grid(nx, ny), Err(MeshError::CoarseGrid { nx, ny }));
    }
    assert!(grid(1 << 20, 1 << 12)
        .unwrap_err()
        .to_string()
        .contains("at most 4294967295 cells"));
}

#[test]
fn refinement_and_coarsening_round_trip() {
    let mut mesh = Mesh::new([0.0, 1.0], [0.0, 1.0], 4, 4);
    refine_around(&mut mesh, [0.5, 0.5], 3);
    let n = mesh.n_active();
    // Coarsen everything: only complete groups of the finest level, never level 0.
    let all = vec![true; n];
    let none = vec![false; n];
    mesh.refine_and_coarsen(&none, &all).unwrap();
    assert!(mesh.is_balanced());
    assert!(mesh.n_active() < n);
    for _ in 0..5 {
        let all = vec![true; mesh.n_active()];
        let none = vec![false; mesh.n_active()];
        mesh.refine_and_coarsen(&none, &all).unwrap();
    }
    assert_eq!(mesh.n_active(), 16, "level-0 cells are never coarsened");
}

#[test]
fn two_to_one_rule_adds_refinement_flags() {
    let mut mesh = Mesh::new([0.0, 1.0], [0.0, 1.0], 2, 1);
    // Refine the left cell twice at its right edge: the right cell must follow once.
    refine_around(&mut mesh, [0.49, 0.5], 2);
    assert!(mesh.is_balanced());
    let right = mesh.locate([0.9, 0.9]).unwrap();
    assert_eq!(mesh.level(right), 1, "neighbour refined by the 2:1 closure");
}

#[test]
fn coarsening_is_refused_where_it_would_break_two_to_one() {
    let mut mesh = Mesh::new([0.0, 1.0], [0.0, 1.0], 2, 1);
    refine_around(&mut mesh, [0.49, 0.5], 2);
    // Try to coarsen the right cell's children while the left side is two levels deep.
    let flags: Vec<bool> = mesh
        .active()
        .iter()
        .map(|&c| mesh.cell_box(c)[0] >= 0.5)
        .collect();
    let none = vec![false; flags.len()];
    mesh.refine_and_coarsen(&none, &flags).unwrap();
    assert!(mesh.is_balanced());
    let right = mesh.locate([0.9, 0.9]).unwrap();
    assert_eq!(mesh.level(right), 1);
}

#[test]
fn marking_flags_whole_tie_groups() {
    // 10 cells, 30 % = 3 to refine: the threshold is the 4th largest (5.0) and all four equal
    // values within the tie band are flagged together.
    let eta = [
        9.0,
        5.0,
        5.0 * (1.0 + 1e-12),
        5.0,
        5.0 * (1.0 - 1e-12),
        1.0,
        1.0,
        0.5,
        0.2,
        0.1,
    ];
    let m = mark_fixed_number(&eta, exact, 0.3, 0.1);
    assert_eq!(
        m.refine,
        vec![true, true, true, true, true, false, false, false, false, false]
    );
    // 10 % = 1 to coarsen: the smallest.
    assert_eq!(m.n_coarsen(), 1);
    assert!(m.coarsen[9]);
}

#[test]
fn marking_outside_the_tie_band_separates() {
    // 20 % of 10 = 2: the threshold is the 3rd largest (4.0); 4·(1 − 1e-8) is outside the band.
    let eta = [
        9.0,
        5.0,
        4.0,
        4.0 * (1.0 - 1e-8),
        3.0,
        1.0,
        1.0,
        0.5,
        0.2,
        0.1,
    ];
    let m = mark_fixed_number(&eta, exact, 0.2, 0.0);
    assert_eq!(
        m.refine,
        vec![true, true, true, false, false, false, false, false, false, false]
    );
}

#[test]
fn marking_all_zero_flags_nothing() {
    let eta = vec![0.0; 100];
    let m = mark_fixed_number(&eta, exact, 0.3, 0.03);
    assert_eq!(m.n_refine(), 0);
    assert_eq!(m.n_coarsen(), 0);
    let mut noisy = vec![1e-14; 100];
    noisy[3] = 2e-13;
    apply_noise_floor(&mut noisy, 1e-12);
    assert_eq!(mark_fixed_number(&noisy, exact, 0.3, 0.03).n_refine(), 0);
}

#[test]
fn marking_with_zero_threshold_uses_smallest_positive() {
    let mut eta = vec![0.0; 10];
    eta[0] = 2.0;
    eta[1] = 1.0;
    let m = mark_fixed_number(&eta, exact, 0.3, 0.0);
    assert_eq!(m.n_refine(), 2);
}

/// Cell measures without rounding: every cell of a plateau ties with every other.
fn exact(_: usize) -> f64 {
    1.0
}

/// Cell measures that round into classes, 1 + k ulp for `class(i)` = k.
fn rounded(class: impl Fn(usize) -> usize) -> impl Fn(usize) -> f64 {
    move |i| 1.0 + class(i) as f64 * f64::EPSILON
}

#[test]
fn a_plateau_at_the_coarsening_threshold_is_cut_where_the_rounding_ties() {
    // 1000 cells: 900 distinct large values and a plateau of 100 equal small ones (as in a
    // cavitated zone). 3 % = 30 to coarsen.
    let mut eta: Vec<f64> = (0..1000).map(|i| 10.0 + i as f64).collect();
    for e in eta.iter_mut().step_by(10) {
        *e = 1.0;
    }
    // Exact arithmetic: deal.II's <= flags the whole plateau.
    let m = mark_fixed_number(&eta, exact, 0.3, 0.03);
    assert_eq!(m.n_coarsen(), 100);
    // The plateau's measures round into five classes of 20 cells: the 30th smallest lies in
    // class 1, so classes 0 and 1 are flagged whole (40 cells), nothing else.
    let class = |i: usize| (i / 10) % 5;
    let m = mark_fixed_number(&eta, rounded(class), 0.3, 0.03);
    assert_eq!(m.n_coarsen(), 40);
    assert!((0..1000).all(|i| m.coarsen[i] == (eta[i] == 1.0 && class(i) <= 1)));
    // Refinement is untouched: the 301 largest (threshold = 301st largest, no ties).
    assert_eq!(m.n_refine(), 301);
}

#[test]
fn a_plateau_at_the_refinement_threshold_is_cut_but_symmetry_groups_are_not() {
    // 100 large distinct values, then a plateau of 400 equal values: 30 % of 500 = 150, so the
    // threshold (151st largest) lies in the plateau and 51 of its cells are asked for.
    let mut eta: Vec<f64> = (0..100).map(|i| 1000.0 + i as f64).collect();
    eta.extend(std::iter::repeat_n(5.0, 400));
    assert_eq!(mark_fixed_number(&eta, exact, 0.3, 0.0).n_refine(), 500);
    // Five rounding classes of 80 plateau cells; the largest class holds the 51st: 100 + 80.
    let class = |i: usize| i % 5;
    let m = mark_fixed_number(&eta, rounded(class), 0.3, 0.0);
    assert_eq!(m.n_refine(), 180);
    assert!((100..500).all(|i| m.refine[i] == (class(i) == 4)));
    // A class per cell: exactly the 51 largest measures.
    let distinct = |i: usize| 1.0 + (i % 400) as f64 * 1e-15;
    assert_eq!(mark_fixed_number(&eta, distinct, 0.3, 0.0).n_refine(), 151);
    // A tie group of PLATEAU_CELLS cells at the threshold is a symmetry group: all flagged.
    // 200 cells: 50 large, the group, 134 small; the 61st largest lies in the group.
    let mut eta: Vec<f64> = (0..50).map(|i| 1000.0 + i as f64).collect();
    eta.extend(std::iter::repeat_n(5.0, PLATEAU_CELLS));
    eta.extend((0..200 - 50 - PLATEAU_CELLS).map(|i| 1.0 + i as f64 * 1e-3));
    let m = mark_fixed_number(&eta, rounded(|i| i % 7), 0.3, 0.0);
    assert_eq!(m.n_refine(), 50 + PLATEAU_CELLS);
}

#[test]
fn rounded_measures_differ_by_position_only_in_the_last_bits() {
    // 64×64 cells of the unit square: each measures exactly h² = 2⁻¹², but MappingQ1's sum
    // rounds differently by position, which is what splits a plateau (IV.64).
    let mut mesh = Mesh::new([0.0, 1.0], [0.0, 1.0], 1, 1);
    for _ in 0..6 {
        mesh.refine_global().unwrap();
    }
    let m: Vec<f64> = mesh
        .active()
        .iter()
        .map(|&c| rounded_measure(&mesh, c))
        .collect();
    assert!(m.iter().all(|&v| (v - 1.0).abs() < 1e-14), "not h²");
    let mut distinct = m.clone();
    distinct.sort_by(f64::total_cmp);
    distinct.dedup();
    assert!(distinct.len() > 10, "{} distinct values", distinct.len());
}

/// The boundary faces of a side, with the cells they belong to, in order along the side.
fn boundary_faces(mesh: &Mesh, side: Side) -> Vec<BoundaryFace> {
    let mut faces: Vec<BoundaryFace> = mesh
        .active()
        .iter()
        .flat_map(|&c| {
            FACES
                .into_iter()
                .filter_map(move |f| mesh.boundary_face(c, f))
        })
        .filter(|f| f.side == side)
        .collect();
    faces.sort();
    faces
}

/// A face of the coarse contact boundary keeps its id while it exists; refinement replaces it by
/// two faces that name it as their parent; the faces of a side tile it without gaps.
#[test]
fn boundary_face_ids_are_stable_and_children_name_their_parent() {
    let mut mesh = Mesh::new([-16.0, 16.0], [0.0, 1.0], 64, 2);
    let before = boundary_faces(&mesh, Side::Bottom);
    assert_eq!(before.len(), 64);
    assert!(before.iter().all(|f| f.level == 0 && f.parent().is_none()));
    refine_around(&mut mesh, [0.3, 0.0], 3);
    let after = boundary_faces(&mesh, Side::Bottom);
    assert!(after.len() > before.len());
    let mut end = 0;
    for f in &after {
        assert_eq!(f.start, end, "faces tile the side: {f:?}");
        end = f.end();
        if f.level == 0 {
            assert!(before.contains(f), "an unrefined coarse face keeps its id");
        } else {
            let parent = f.parent().unwrap();
            assert!(parent.children().contains(f));
            let mut root = *f;
            while let Some(p) = root.parent() {
                root = p;
            }
            assert!(before.contains(&root), "{f:?} descends from a coarse face");
            assert!(!before.contains(f));
        }
    }
    assert_eq!(end, mesh.extent().0, "the faces cover the whole side");
    // Cell keys survive refinement elsewhere.
    let keys: Vec<_> = mesh.active().iter().map(|&c| mesh.cell_key(c)).collect();
    let far = mesh.locate([15.9, 0.9]).unwrap();
    let far_key = mesh.cell_key(far);
    refine_around(&mut mesh, [-10.0, 0.5], 1);
    let still = mesh.locate([15.9, 0.9]).unwrap();
    assert_eq!(mesh.cell_key(still), far_key);
    assert!(keys.contains(&far_key));
}

/// A grid with moved coarse vertices: vertices shared by cells have the same position in each,
/// the cells tile the body, points are located, and a folded coarse cell is refused.
#[test]
fn moved_coarse_vertices_describe_one_body_and_folded_cells_are_refused() {
    let vertices = vec![
        [0.0, 0.0],
        [1.1, 0.1],
        [2.0, 0.0],
        [0.1, 1.0],
        [0.9, 1.2],
        [2.1, 0.9],
    ];
    let mut mesh = Mesh::with_coarse_vertices(2, 1, vertices.clone()).unwrap();
    let area: f64 = mesh
        .active()
        .iter()
        .map(|&c| mesh.cell_shape(c).area())
        .sum();
    refine_around(&mut mesh, [1.0, 0.6], 2);
    assert!(mesh.is_balanced());
    let refined_area: f64 = mesh
        .active()
        .iter()
        .map(|&c| mesh.cell_shape(c).area())
        .sum();
    assert!(
        (area - refined_area).abs() < 1e-12,
        "{area} vs {refined_area}"
    );
    for &c in mesh.active() {
        let shape = mesh.cell_shape(c);
        let centre = shape.point(0.5, 0.5);
        assert_eq!(mesh.locate(centre), Some(c));
    }
    // The edges of moved cells stay straight.
    assert_hanging_vertices_are_midpoints(&DofMap::new(&mesh, 1), 1e-14);
    let mut folded = vertices;
    folded.swap(0, 1);
    let err = Mesh::with_coarse_vertices(2, 1, folded).unwrap_err();
    assert!(
        matches!(err, MeshError::FoldedCell { i: 0, j: 0, .. }),
        "{err}"
    );
}

/// Every hanging vertex is the midpoint of its two parents (to `tol`), which are not hanging
/// themselves, and there is at least one.
fn assert_hanging_vertices_are_midpoints(dofs: &DofMap, tol: f64) {
    let v = &dofs.vertices;
    assert!(!v.hanging.is_empty());
    for h in &v.hanging {
        let (m, a, b) = (
            v.coords[h.vertex as usize],
            v.coords[h.parents[0] as usize],
            v.coords[h.parents[1] as usize],
        );
        assert!(
            (m[0] - 0.5 * (a[0] + b[0])).abs() < tol && (m[1] - 0.5 * (a[1] + b[1])).abs() < tol,
            "hanging vertex {} at {m:?}, parents at {a:?} and {b:?}",
            h.vertex
        );
        assert!(!v.is_hanging[h.parents[0] as usize] && !v.is_hanging[h.parents[1] as usize]);
    }
}

/// The fixed meshes of the model-adaptive contact tables (§IV.2.3): 64 × 2 cells on
/// [−16, 16] × [0, 1] refined 3× at the contact side — the printed 1472 cells, 3980 dofs and
/// 512 faces of IV.18–IV.25 and IV.28–IV.29; 2× at both sides — the 1280 cells, 3342 dofs and
/// 256 + 256 faces that IV.26/IV.27 print; 3× at both sides — the 7442 dofs of the text.
#[test]
fn meshes_refined_at_the_contact_sides_have_the_printed_sizes() {
    use tribo::mesh::Face;
    let faces_on = |mesh: &Mesh, side: Side| {
        mesh.active()
            .iter()
            .filter(|&&c| {
                [Face::Bottom, Face::Top]
                    .iter()
                    .any(|&f| mesh.neighbor(c, f) == Neighbor::Boundary(side))
            })
            .count()
    };
    for (sides, times, cells, dofs, bottom, top) in [
        (&[Side::Bottom][..], 3, 1472, 3980, 512, 64),
        (&[Side::Bottom, Side::Top][..], 2, 1280, 3342, 256, 256),
        (&[Side::Bottom, Side::Top][..], 3, 2816, 7442, 512, 512),
    ] {
        let mut mesh = Mesh::new([-16.0, 16.0], [0.0, 1.0], 64, 2);
        mesh.refine_at_sides(sides, times).unwrap();
        assert!(mesh.is_balanced());
        assert_eq!(
            (mesh.n_active(), DofMap::new(&mesh, 2).n_dofs()),
            (cells, dofs),
            "{sides:?} ×{times}"
        );
        assert_eq!(
            (faces_on(&mesh, Side::Bottom), faces_on(&mesh, Side::Top)),
            (bottom, top),
            "{sides:?} ×{times}"
        );
    }
}
