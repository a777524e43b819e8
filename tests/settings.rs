//! Nothing accepted and ignored, checks that hold in every load step, `related` validated, and
//! warnings for every family: each case an edit of a shipped experiment file that loaded (or
//! ran) silently before and is now refused, named or warned about.

use tribo::experiment::{load, load_each, Experiment, ExperimentError};
use tribo::study::{self, Tier};

use crate::cli::temp_dir;
use crate::warnings::{edited, write};

/// Load the edited file of `table` on its own.
fn load_edited(
    case: &str,
    table: &str,
    edits: &[(&str, &str)],
) -> Result<Experiment, ExperimentError> {
    let dir = temp_dir(&format!("settings-{case}"));
    load(&write(&dir, table, &edited(table, edits)))
}

/// The error of an edited file: it names `field` and contains `needle`.
fn refused(case: &str, table: &str, edits: &[(&str, &str)], field: &str, needle: &str) {
    let message = match load_edited(case, table, edits) {
        Ok(_) => panic!("{case}: loaded"),
        Err(e) => e.to_string(),
    };
    assert!(
        message.contains(&format!("field `{field}`")) || message.contains(field),
        "{case}: {message}"
    );
    assert!(message.contains(needle), "{case}: {message}");
}

#[test]
fn the_uzawa_study_refuses_another_geometry() {
    refused(
        "uzawa-domain",
        "fig-III.6",
        &[("x = [0.0, 4.0]", "x = [0.0, 8.0]")],
        "scene.domain",
        "the domain of the test problem (III.88)",
    );
    refused(
        "uzawa-mesh",
        "fig-III.6",
        &[("coarse_cells = [1, 1]", "coarse_cells = [2, 2]")],
        "scene.coarse_cells",
        "32×32 cells",
    );
    // The same 32×32 mesh written another way runs as before.
    load_edited(
        "uzawa-mesh-2x2",
        "fig-III.6",
        &[
            ("coarse_cells = [1, 1]", "coarse_cells = [2, 2]"),
            ("global_refinements = 5", "global_refinements = 4"),
        ],
    )
    .unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn the_film_refuses_solver_fields_it_never_runs() {
    refused(
        "film-solver",
        "fig-IV.116",
        &[(
            "[scene.substokes]\n",
            "[scene.substokes]\nsolver = \"uzawa\"\n",
        )],
        "scene.substokes.solver",
        "`uzawa`",
    );
    refused(
        "film-compare",
        "fig-IV.116",
        &[(
            "[scene.substokes]\n",
            "[scene.substokes]\ncompare_with = \"uzawa\"\n",
        )],
        "scene.substokes.compare_with",
        "no such field in a model-adaptive film",
    );
}

/// `[study] solver` acts in the elasticity, contact and Reynolds tables and is refused where
/// the systems are always solved by the direct solver.
#[test]
fn study_solver_is_refused_where_it_has_no_effect() {
    let add = ("[study]\n", "[study]\nsolver = \"multigrid\"\n");
    for table in ["IV.18", "IV.50", "fig-IV.54", "fig-III.6", "fig-IV.116"] {
        refused(
            &format!("solver-{table}"),
            table,
            &[add],
            "study.solver",
            "only the families elasticity, contact, reynolds choose",
        );
    }
    for table in ["IV.1", "IV.6", "IV.36"] {
        load_edited(&format!("solver-{table}"), table, &[add]).unwrap_or_else(|e| panic!("{e}"));
    }
}

/// A grid marking that refines no cell of the first mesh is refused: the "adaptive" study
/// would print the same mesh in every row.
#[test]
fn a_marking_of_zero_cells_is_refused() {
    refused(
        "zero-fraction",
        "IV.1",
        &[("refine_fraction = 0.3", "refine_fraction = 5e-324")],
        "study.refine_fraction",
        "refines at least one of the 128 cells",
    );
    refused(
        "one-cell",
        "IV.36",
        &[
            ("coarse_cells = [1, 1]", "coarse_cells = [1, 1]"),
            ("global_refinements = 6", "global_refinements = 0"),
        ],
        "study.refine_fraction",
        "refines at least one of the 1 cells",
    );
}

/// A tool that rises into the clamped end in a later load step: refused before the first solve,
/// naming the step (before, the run pressed the tool into the sheet by the lift and exited 0).
#[test]
fn a_tool_rising_into_the_clamped_end_is_refused_naming_the_step() {
    let e = load_edited(
        "rising-into-clamp",
        "fig-IV.54",
        &[(
            "center = [-16.0, 0.0], radius = 10.0",
            "center = [-16.0, 0.0], radius = 0.5",
        )],
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let err = study::run(&e, Tier::Quick, &|_, _, _| {}).expect_err("infeasible in step 2");
    assert_eq!(err.step, Some(2), "{err}");
    let message = err.to_string();
    assert!(message.contains("load step 2"), "{message}");
    assert!(
        message.contains("reaches into the body at the corner x₁ = -16"),
        "{message}"
    );
    // The shipped forming stays feasible in all its 25 steps.
    let shipped = crate::common::spec("fig-IV.54");
    assert!(shipped.family.infeasible(&shipped, 25).is_none());
}

/// `related` of a file: only where the report draws related tables, each id once.
#[test]
fn related_ids_are_checked_in_the_file() {
    refused(
        "related-in-reynolds",
        "IV.46",
        &[("[scene]", "related = [\"IV.60\"]\n\n[scene]")],
        "related",
        "no related tables in a reynolds scene",
    );
    refused(
        "related-twice",
        "fig-IV.116",
        &[(
            "related = [\"IV.46\", \"IV.60\"]",
            "related = [\"IV.46\", \"IV.46\"]",
        )],
        "related[1]",
        "`IV.46` twice",
    );
}

/// `related` against the folder: ids of tables of the folder, of a family drawn beside the
/// film, and of the same film; a failing check is the film's failed entry, the others load.
#[test]
fn related_ids_name_tables_of_the_same_film() {
    let case = |name: &str, related: &str, others: &[(&str, String)]| {
        let dir = temp_dir(&format!("settings-related-{name}"));
        write(
            &dir,
            "fig-IV.116",
            &edited(
                "fig-IV.116",
                &[("related = [\"IV.46\", \"IV.60\"]", related)],
            ),
        );
        for (table, text) in others {
            write(&dir, table, text);
        }
        let only = ["fig-IV.116".to_string()];
        let loaded = load_each(&dir, Some(&only)).unwrap();
        assert_eq!(loaded.len(), 1);
        loaded
            .into_iter()
            .next()
            .unwrap()
            .1
            .map(|_| ())
            .map_err(|e| e.to_string())
    };
    fn shipped(t: &'static str) -> (&'static str, String) {
        (t, edited(t, &[]))
    }
    let pair = [shipped("IV.46"), shipped("IV.60")];
    case("good", "related = [\"IV.46\", \"IV.60\"]", &pair).unwrap();
    let missing = case("missing", "related = [\"IV.46\", \"IV.47\"]", &pair).unwrap_err();
    assert!(
        missing.contains("related[1]") && missing.contains("no file here"),
        "{missing}"
    );
    let contact = case("contact", "related = [\"IV.6\"]", &[shipped("IV.6")]).unwrap_err();
    assert!(contact.contains("`IV.6`, a contact table"), "{contact}");
    let other_film = case("other-film", "related = [\"IV.50\"]", &[shipped("IV.50")]).unwrap_err();
    assert!(
        other_film.contains("a table of the same film"),
        "{other_film}"
    );
}

/// The warnings of each family, and the Reynolds warning that holds only where its data make
/// it true.
#[test]
fn every_fluid_family_warns_about_its_data() {
    let lines = |case: &str, table: &str, edits: &[(&str, &str)]| -> Vec<String> {
        load_edited(case, table, edits)
            .unwrap_or_else(|e| panic!("{case}: {e}"))
            .warnings()
            .iter()
            .map(|w| w.to_string())
            .collect()
    };
    // Walls at rest over the wave gap: ψ is driven by ψΔg/g, no "exact solution" warning.
    assert_eq!(
        lines(
            "rest-wave",
            "IV.46",
            &[(
                "upper_wall_velocity = [40.0, 0.0, 0.0]",
                "upper_wall_velocity = [0.0, 0.0, 0.0]"
            )]
        ),
        Vec::<String>::new()
    );
    let w = lines(
        "substokes-hill",
        "IV.61",
        &[("frequency = 2.0", "frequency = 1e6")],
    );
    assert!(
        w.len() == 1 && w[0].starts_with("scene.substokes.gap.frequency: "),
        "{w:?}"
    );
    let w = lines("substokes-thin", "IV.50", &[("g0 = 0.1", "g0 = 1e-12")]);
    assert!(
        w.len() == 1 && w[0].starts_with("scene.substokes.delta_eps: "),
        "{w:?}"
    );
    assert!(
        w[0].contains("the stabilisation, not the film, sets the pressure"),
        "{w:?}"
    );
    let w = lines(
        "substokes-underflow",
        "IV.50",
        &[("g0 = 0.1", "g0 = 1e-300")],
    );
    assert!(
        w.len() == 1 && w[0].starts_with("scene.substokes.gap: ") && w[0].contains("underflow"),
        "{w:?}"
    );
    let w = lines(
        "channel-delta",
        "fig-III.6",
        &[("delta_eps = 1.0", "delta_eps = 1e6")],
    );
    assert!(
        w.len() == 1 && w[0].starts_with("scene.stokes_channel.delta_eps: "),
        "{w:?}"
    );
    let film = edited("fig-IV.116", &[]).replace("frequency = 2.0", "frequency = 1e9");
    let dir = temp_dir("settings-film-frequency");
    let w: Vec<String> = load(&write(&dir, "fig-IV.116", &film))
        .unwrap_or_else(|e| panic!("{e}"))
        .warnings()
        .iter()
        .map(|w| w.to_string())
        .collect();
    assert_eq!(w.len(), 2, "{w:?}");
    assert!(
        w[0].starts_with("scene.reynolds.gap.frequency")
            && w[1].starts_with("scene.substokes.gap.frequency"),
        "{w:?}"
    );
    // A die narrower than any cell acts as its plateau.
    let w = lines(
        "thin-die",
        "fig-IV.54",
        &[("radius = 10.0", "radius = 1e-300")],
    );
    assert!(
        w.iter()
            .any(|l| l.starts_with("scene.contact.obstacles[1].shape.radius: ")),
        "{w:?}"
    );
}
