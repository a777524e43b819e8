//! The full-tier checks that CI runs after the snapshot regression (`.ci/run`): every table at
//! thesis size, its agreement with the printed rows and its convergence rate over the
//! experiment's window. Ignored by default. CI checks the rows of the full report it has just
//! written (`TRIBO_FULL_REPORT`, seconds); without that variable every table runs here (about
//! five minutes on two cores):
//!
//! ```sh
//! TRIBO_FULL_REPORT=report cargo test --release --test tribo -- --ignored full_tier --nocapture
//! cargo test --release --test tribo -- --ignored full_tier --nocapture
//! ```
//!
//! A failure names the table, the cycle and the number; every table of a family is checked even
//! when an earlier one fails. The forming always runs, since its check reads the deformed
//! meshes, which the report's data files do not hold.

use crate::common::{full_tier, full_tier_runs};

#[test]
#[ignore]
fn elasticity() {
    full_tier(
        &crate::elasticity::TABLES,
        crate::elasticity::full_tier_rules,
    );
}

#[test]
#[ignore]
fn contact() {
    full_tier(&crate::contact::TABLES, crate::contact::full_tier_rules);
}

#[test]
#[ignore]
fn model_grid() {
    full_tier(
        &crate::model_grid::TABLES,
        crate::model_grid::full_tier_rules,
    );
}

/// The U-O forming: all 25 load steps finish, Signorini faces appear, the tip rests on the
/// die's plateau after every step.
#[test]
#[ignore]
fn forming() {
    full_tier_runs(&[crate::forming::FORMING], |_, r| {
        assert_eq!(r.rows.len(), 25, "fig-IV.54: 25 load steps");
        crate::forming::assert_forming_rules(r);
        assert!(
            r.rows.iter().any(|row| row.count_of("s_faces") > Some(0)),
            "fig-IV.54: no Signorini face in any step"
        );
    });
}

#[test]
#[ignore]
fn reynolds() {
    full_tier(&crate::reynolds::TABLES, crate::reynolds::full_tier_rules);
}

#[test]
#[ignore]
fn substokes() {
    full_tier(&crate::substokes::TABLES, crate::substokes::full_tier_rules);
}

#[test]
#[ignore]
fn model_fluid() {
    full_tier(
        &[crate::model_fluid::FIGURE],
        crate::model_fluid::full_tier_rules,
    );
}
