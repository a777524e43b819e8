//! `[scene] mesh_smoothing`: deal.II's mesh-smoothing flags as a scene option. The loader
//! types the names, refuses unknown ones and those of studies that never
//! refine the grid, and a thesis file that sets it counts as edited.

use std::fs;
use std::path::PathBuf;

use tribo::experiment;
use tribo::mesh::{MeshSmoothing, SmoothingName};

use crate::common::{experiments_dir, refused_at as refused};

/// The shipped file `IV.<n>.toml` with `line` added after the scene's `effects`, written to a
/// scratch folder under its own name.
fn with_smoothing(table: &str, line: &str) -> PathBuf {
    let text = fs::read_to_string(experiments_dir().join(format!("{table}.toml"))).unwrap();
    let effects = text
        .lines()
        .find(|l| l.starts_with("effects = "))
        .expect("a scene with effects");
    let text = text.replacen(effects, &format!("{effects}\n{line}"), 1);
    let dir = crate::common::scratch(&format!("smoothing-{}", line.len() + table.len() * 1000));
    let path = dir.join(format!("{table}.toml"));
    fs::write(&path, text).unwrap();
    path
}

#[test]
fn shipped_files_set_no_smoothing() {
    let spec = experiment::load(&experiments_dir().join("IV.50.toml")).unwrap();
    assert!(spec.scene.mesh_smoothing.is_empty());
}

#[test]
fn names_are_typed_and_the_file_counts_as_edited() {
    let path = with_smoothing(
        "IV.50",
        "mesh_smoothing = [\"limit-level-difference-at-vertices\", \"patch-level-1\"]",
    );
    let spec = experiment::load(&path).unwrap();
    let expected = MeshSmoothing::of(&[
        SmoothingName::LimitLevelDifferenceAtVertices,
        SmoothingName::PatchLevel1,
    ])
    .unwrap();
    assert_eq!(spec.scene.mesh_smoothing, expected);
    assert!(!spec.comparison.is_printed(), "{:?}", spec.comparison);
}

/// The coarsening smoothers are accepted, alone and as deal.II's combination.
#[test]
fn coarsening_smoothers_are_accepted() {
    let path = with_smoothing(
        "IV.50",
        "mesh_smoothing = [\"patch-level-1\", \"smoothing-on-coarsening\"]",
    );
    let spec = experiment::load(&path).unwrap();
    let expected = MeshSmoothing::of(&[
        SmoothingName::PatchLevel1,
        SmoothingName::EliminateRefinedInnerIslands,
        SmoothingName::EliminateRefinedBoundaryIslands,
        SmoothingName::DoNotProduceUnrefinedIslands,
    ])
    .unwrap();
    assert_eq!(spec.scene.mesh_smoothing, expected);
}

#[test]
fn unknown_and_repeated_names_are_refused() {
    let path = with_smoothing("IV.50", "mesh_smoothing = [\"patch-level-2\"]");
    refused(
        &path,
        "scene.mesh_smoothing[0]",
        "limit-level-difference-at-vertices",
    );
    let path = with_smoothing(
        "IV.50",
        "mesh_smoothing = [\"patch-level-1\", \"patch-level-1\"]",
    );
    refused(&path, "scene.mesh_smoothing[1]", "each flag once");
}

#[test]
fn a_study_that_does_not_refine_the_grid_refuses_it() {
    let path = with_smoothing("IV.18", "mesh_smoothing = [\"maximum-smoothing\"]");
    refused(&path, "scene.mesh_smoothing", "does not refine the grid");
}
