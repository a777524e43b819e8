//! Fig. III.6 (Uzawa's algorithm with five preconditioners on the test problem (III.88)) as the
//! experiment `fig-III.6`: golden snapshot of the quick tier (60 iterations), the thesis's
//! claim that the cg-accelerated variant is far ahead, and the data file's columns.

use crate::common::quick;

pub const FIGURE: &str = "fig-III.6";

#[test]
fn golden_snapshot() {
    crate::common::assert_golden(&[FIGURE]);
}

/// cg-ssor reaches a relative residual of 1e-6 within the 60 quick iterations; at iteration 50
/// every other variant is at least 100 times above it; every variant's pressure error shrinks.
#[test]
fn the_cg_accelerated_variant_is_far_ahead() {
    let r = quick(FIGURE);
    let at = |variant: &str, k: usize| {
        r.uzawa
            .iter()
            .find(|row| row.variant == variant && row.iteration == k)
            .unwrap_or_else(|| panic!("{variant}: no iteration {k}"))
    };
    let cg = at("cg-ssor", 50).relative_residual;
    assert!(cg <= 1e-6, "cg-ssor at 50: {cg}");
    for variant in ["identity", "jacobi", "gauss-seidel", "ssor"] {
        let other = at(variant, 50).relative_residual;
        assert!(
            other >= 100.0 * cg,
            "{variant} at 50: {other} vs cg-ssor {cg}"
        );
        let (first, last) = (
            at(variant, 0).pressure_error.unwrap(),
            at(variant, 60).pressure_error.unwrap(),
        );
        assert!(last < first, "{variant}: pressure error {first} → {last}");
    }
    assert!(r.rows.is_empty(), "a solver study has no adaptive cycles");
}

/// The data file: one row per variant and iteration, the columns of report/README.md.
#[test]
fn data_file_has_one_row_per_iteration() {
    let r = quick(FIGURE);
    let dir = crate::common::scratch("uzawa");
    tribo::report::data::write_frames(&dir, &r).unwrap();
    let text = std::fs::read_to_string(dir.join("fig-III.6.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some(
            "variant,iteration,residual,relative_residual,pressure_error,inner_iterations,seconds"
        )
    );
    assert_eq!(lines.count(), r.uzawa.len());
    let _ = std::fs::remove_dir_all(&dir);
}
