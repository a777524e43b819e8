//! The two linear solvers give the same tables: multigrid-preconditioned CG against the sparse
//! Cholesky reference (same meshes, active sets and iteration counts, estimates and probes
//! within 1e-8), CG iterations bounded, the solver chosen per file and on the command line, and
//! tables run side by side giving bitwise the same data as one at a time.

use std::path::Path;

use tribo::linalg::SolverKind;
use tribo::results::{columns, RunResult};
use tribo::study::{self, Tier};

use crate::cli::{report, temp_dir};
use crate::common::{experiments_dir, rel, spec, without_seconds};

fn run_with(table: &str, solver: SolverKind) -> RunResult {
    let mut s = spec(table);
    s.study.solver = Some(solver);
    study::run(&s, Tier::Quick, &|_, _, _| {}).unwrap_or_else(|e| panic!("{table}: {e}"))
}

/// Probes within 1e-8 of the largest probe value (a probe in the cavitation zone is 0).
/// IV.36 (Reynolds), IV.44 (a hill gap with vertical velocity), IV.65 (cavitation, an
/// active set per cycle) and IV.1 (elasticity, two components per vertex).
#[test]
fn multigrid_reproduces_the_direct_solver() {
    for (table, most_cg) in [("IV.36", 20), ("IV.44", 20), ("IV.65", 20), ("IV.1", 40)] {
        let direct = run_with(table, SolverKind::Direct);
        let multigrid = run_with(table, SolverKind::Multigrid);
        assert_eq!(direct.rows.len(), multigrid.rows.len(), "{table}");
        for (d, m) in direct.rows.iter().zip(&multigrid.rows) {
            for (name, value) in d.counts() {
                assert_eq!(
                    m.count_of(name),
                    Some(value),
                    "{table} cycle {}: {name}",
                    d.cycle
                );
            }
            for name in [
                columns::ESTIMATE,
                columns::THEOREM_ESTIMATE,
                columns::PREVIOUS_ESTIMATE,
            ] {
                if let (Some(a), Some(b)) = (d.value(name), m.value(name)) {
                    assert!(
                        rel(b, a).abs() < 1e-8,
                        "{table} cycle {}: {name} {a} (direct) vs {b} (multigrid)",
                        d.cycle
                    );
                }
            }
            assert_eq!(d.count_of(columns::CG_ITERATIONS), None, "{table}");
            let cg = m
                .count_of(columns::CG_ITERATIONS)
                .expect("cg_iterations column");
            assert!(
                (1..=most_cg).contains(&cg),
                "{table} cycle {}: {cg} CG iterations",
                d.cycle
            );
        }
        let scale = direct
            .probes
            .iter()
            .fold(0.0f64, |m, p| m.max(p.value.abs()));
        for (p, q) in direct.probes.iter().zip(&multigrid.probes) {
            assert!(
                (q.value - p.value).abs() <= 1e-8 * scale,
                "{table}: probe ({}, {}) {} vs {}",
                p.x,
                p.y,
                p.value,
                q.value
            );
        }
        // Both solvers share one snapshot.
        assert_eq!(direct.snapshot(), multigrid.snapshot(), "{table}");
    }
}

/// `[study] solver` must name a solver; the error names the file and the field.
/// Without `[study] solver`, the Reynolds tables use multigrid and the elasticity tables the
/// direct solver (faster at their size); contact tables with multigrid are solved by TNNMG,
/// which has no CG column.
#[test]
fn each_family_gets_its_faster_solver_by_default() {
    let cg_column = |table: &str, solver: Option<SolverKind>| {
        let mut s = spec(table);
        s.study.solver = solver;
        let run = study::run(&s, Tier::Quick, &|_, _, _| {}).unwrap();
        run.rows[0].count_of(columns::CG_ITERATIONS).is_some()
    };
    assert!(cg_column("IV.36", None));
    assert!(!cg_column("IV.1", None));
    assert!(cg_column("IV.1", Some(SolverKind::Multigrid)));
    assert!(!cg_column("IV.7", Some(SolverKind::Multigrid)));
}

#[test]
fn an_unknown_solver_is_refused_naming_the_field() {
    let dir = temp_dir("unknown-solver");
    let text = std::fs::read_to_string(experiments_dir().join("IV.36.toml")).unwrap();
    let edited = text.replace("[study]\n", "[study]\nsolver = \"gpu\"\n");
    std::fs::write(dir.join("IV.36.toml"), edited).unwrap();
    let out = report()
        .args(["--quick", "--no-progress", "--experiments"])
        .arg(&dir)
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("IV.36.toml") && stderr.contains("solver") && stderr.contains("gpu"),
        "{stderr}"
    );
}

/// The CSV files of a report folder without their timing columns.
fn data_without_seconds(out: &Path) -> Vec<(String, String)> {
    let mut files: Vec<_> = std::fs::read_dir(out.join("data"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "csv"))
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|p| {
            let text = std::fs::read_to_string(&p).unwrap();
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, without_seconds(&text))
        })
        .collect()
}

/// Three tables of different families, one at a time and two at once, with both solvers from
/// the command line: the data files are bitwise equal (timings aside), and `--solver` reaches
/// the run (the multigrid run has the CG column, the direct run has none, and the performance
/// section names the solver of each table).
#[test]
fn tables_side_by_side_and_the_solver_flag() {
    let dir = temp_dir("jobs");
    let run = |jobs: &str, solver: &str| {
        let out = dir.join(format!("{jobs}-{solver}"));
        let o = report()
            .args([
                "--quick",
                "--no-progress",
                "--no-alternatives",
                "--only",
                "IV.1,IV.36,IV.64",
            ])
            .args(["--jobs", jobs, "--solver", solver, "--experiments"])
            .arg(experiments_dir())
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        out
    };
    let one = data_without_seconds(&run("1", "multigrid"));
    let two_out = run("2", "multigrid");
    let two = data_without_seconds(&two_out);
    assert_eq!(one.len(), two.len());
    for ((name, a), (_, b)) in one.iter().zip(&two) {
        assert_eq!(a, b, "{name} differs between --jobs 1 and --jobs 2");
    }
    let direct_out = run("2", "direct");
    let direct = data_without_seconds(&direct_out);
    // The performance section names the solver of each table and draws its figure.
    let row = |out: &Path, table: &str| {
        let page = tribo::report::read_pages(out).unwrap();
        let start = page
            .find("<section id=\"performance\">")
            .expect("performance section");
        let anchor = format!(">{table}</a></td><td>");
        let i = page[start..].find(&anchor).expect("a row per table") + start + anchor.len();
        page[i..].split("</td>").next().unwrap().to_string()
    };
    assert_eq!(row(&two_out, "IV.36"), "multigrid");
    assert_eq!(row(&two_out, "IV.1"), "multigrid");
    assert_eq!(row(&direct_out, "IV.1"), "direct");
    assert_eq!(row(&direct_out, "IV.36"), "direct");
    assert!(two_out.join("figures/performance-solve.svg").exists());
    let header = |files: &[(String, String)]| {
        files
            .iter()
            .find(|(n, _)| n == "IV.36.csv")
            .map(|(_, t)| t.lines().next().unwrap().to_string())
            .unwrap()
    };
    assert!(header(&two).contains("cg_iterations"), "{}", header(&two));
    assert!(
        !header(&direct).contains("cg_iterations"),
        "{}",
        header(&direct)
    );
}
