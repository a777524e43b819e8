//! The open data files of the report (report/README.md, "Data files"): every CSV file also as
//! Parquet with the same frame, the join of tribo's rows with the printed table, and the last
//! mesh of a table as a VTK unstructured grid that ParaView reads.

use std::fs::{self, File};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use polars::prelude::*;

use crate::common::spec;
use crate::outputs::quick_report;
use tribo::report::vtk::{self, VtuFile};
use tribo::thesis::ThesisTable;

/// One quick report of a linear elasticity, a contact and a Reynolds table, shared by the tests.
fn report() -> &'static PathBuf {
    static OUT: OnceLock<PathBuf> = OnceLock::new();
    OUT.get_or_init(|| {
        let experiments = Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments");
        quick_report(&experiments, "open-data", Some("IV.1,IV.7,IV.36"))
    })
}

fn data(file: &str) -> PathBuf {
    report().join("data").join(file)
}

fn read_csv(path: &Path) -> DataFrame {
    CsvReadOptions::default()
        .with_has_header(true)
        .try_into_reader_with_file_path(Some(path.to_path_buf()))
        .and_then(|r| r.finish())
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn read_parquet(path: &Path) -> DataFrame {
    let file = File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    ParquetReader::new(file)
        .finish()
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The values of a column as reals (integers converted), `None` where it is null.
fn reals(frame: &DataFrame, name: &str) -> Vec<Option<f64>> {
    let column = frame
        .column(name)
        .unwrap_or_else(|e| panic!("column {name}: {e}"));
    let cast = column.cast(&DataType::Float64).expect("numeric column");
    let values = cast.f64().expect("f64");
    (0..values.len()).map(|i| values.get(i)).collect()
}

/// The last row's value of a column.
fn last(frame: &DataFrame, name: &str) -> f64 {
    reals(frame, name)
        .last()
        .copied()
        .flatten()
        .expect("a value")
}

/// A `.vtu` file of the quick report, read back.
fn vtu(file: &str) -> VtuFile {
    vtk::read(&fs::read(data(file)).expect(file)).unwrap_or_else(|e| panic!("{file}: {e}"))
}

/// The array `name` of a `.vtu` file.
fn vtu_array(file: &VtuFile, name: &str) -> Vec<f64> {
    file.array(name)
        .unwrap_or_else(|| panic!("no array {name}"))
        .to_vec()
}

#[test]
fn every_csv_file_has_a_parquet_twin_with_the_same_frame() {
    let dir = report().join("data");
    let mut compared = 0;
    for entry in fs::read_dir(&dir).expect("data/") {
        let path = entry.expect("entry").path();
        if path.extension().and_then(|e| e.to_str()) != Some("csv") {
            continue;
        }
        let csv = read_csv(&path);
        let parquet = read_parquet(&path.with_extension("parquet"));
        assert_eq!(
            csv.get_column_names(),
            parquet.get_column_names(),
            "{}",
            path.display()
        );
        assert_eq!(csv.height(), parquet.height(), "{}", path.display());
        for name in csv.get_column_names() {
            let name = name.as_str();
            let (a, b) = (csv.column(name).unwrap(), parquet.column(name).unwrap());
            if b.dtype() == &DataType::String {
                assert!(
                    a.as_materialized_series()
                        .equals_missing(b.as_materialized_series()),
                    "{}: {name}",
                    path.display()
                );
            } else {
                // Undefined values are empty in the CSV file and null in the Parquet file, and
                // the CSV text reads back to the same doubles.
                assert_eq!(
                    reals(&csv, name),
                    reals(&parquet, name),
                    "{}: {name}",
                    path.display()
                );
            }
        }
        compared += 1;
    }
    // IV.1, IV.7, IV.36: rows, probes and joined; IV.36 also its cuts.
    assert_eq!(compared, 10, "CSV files in {}", dir.display());
    let rows = read_parquet(&data("IV.1.parquet"));
    assert_eq!(reals(&rows, "ratio")[0], None, "the first ratio is null");
}

#[test]
fn the_joined_file_holds_the_printed_columns_beside_tribos() {
    let thesis = ThesisTable::of(&spec("IV.1"));
    for file in ["IV.1.joined.csv", "IV.1.joined.parquet"] {
        let frame = if file.ends_with("csv") {
            read_csv(&data(file))
        } else {
            read_parquet(&data(file))
        };
        let cycles = reals(&frame, "cycle");
        let rows = read_csv(&data("IV.1.csv"));
        assert_eq!(
            cycles,
            reals(&rows, "cycle"),
            "{file}: one row per cycle of IV.1.csv"
        );
        assert!(cycles.len() >= 3, "{file}");
        for column in ["active_cells", "dofs", "estimate"] {
            let printed = reals(&frame, &format!("thesis_{column}"));
            let tribo = reals(&frame, column);
            let diffs = reals(&frame, &format!("{column}_rel_diff"));
            for (i, cycle) in cycles.iter().enumerate() {
                let cycle = cycle.expect("a cycle") as usize;
                assert_eq!(
                    printed[i],
                    thesis.value(cycle, column),
                    "{file}: {column} row {i}"
                );
                let diff = tribo[i].unwrap() / printed[i].unwrap() - 1.0;
                assert!(
                    (diffs[i].unwrap() - diff).abs() <= 1e-12,
                    "{file}: {column} row {i}"
                );
            }
        }
        // Row 0: 128 cells and 390 dofs printed; the printed ratio `inf` is undefined (empty).
        assert_eq!(reals(&frame, "thesis_active_cells")[0], Some(128.0));
        assert_eq!(reals(&frame, "thesis_dofs")[0], Some(390.0));
        assert_eq!(reals(&frame, "thesis_ratio")[0], None, "{file}");
        assert_eq!(reals(&frame, "ratio_rel_diff")[0], None, "{file}");
    }
    let header = fs::read_to_string(data("IV.1.joined.csv")).unwrap();
    assert!(
        header.starts_with("cycle,active_cells,dofs,estimate,ratio,"),
        "{header}"
    );
    assert!(
        header.lines().nth(1).unwrap().starts_with("0,128,390,"),
        "integer columns stay integers: {header}"
    );
}

#[test]
fn the_elasticity_mesh_reads_back_with_its_cells_and_fields() {
    let text = vtu("IV.1.vtu");
    let rows = read_csv(&data("IV.1.csv"));
    let cells = text.cells;
    assert_eq!(cells as f64, last(&rows, "active_cells"));
    let points = text.points;
    // Q₁ with two components: dofs = 2 × vertices (hanging vertices included).
    assert_eq!(2 * points, last(&rows, "dofs") as usize);
    let xyz = vtu_array(&text, "Points");
    let s = vtu_array(&text, "displacement");
    assert_eq!((xyz.len(), s.len()), (3 * points, 3 * points));
    // Clamped on the left side x₁ = −16 (and the right): s = 0 there, exactly.
    let left: Vec<usize> = (0..points).filter(|&v| xyz[3 * v] == -16.0).collect();
    assert!(left.len() >= 3);
    for v in &left {
        assert_eq!((s[3 * v], s[3 * v + 1]), (0.0, 0.0), "vertex {v}");
    }
    assert!(s.iter().any(|&u| u != 0.0), "the body moves");
    // The indicators: √Σ η_Q² is the last row's estimate.
    // (η² is rounded to 4 significant digits: 1.2e-4 relative per cell at most.)
    let eta2 = vtu_array(&text, "eta_squared");
    assert_eq!(eta2.len(), cells);
    let total = eta2.iter().sum::<f64>().sqrt();
    assert!((total / last(&rows, "estimate") - 1.0).abs() < 1e-4);
    let connectivity = vtu_array(&text, "connectivity");
    assert_eq!(connectivity.len(), 4 * cells);
    assert!(vtu_array(&text, "types").iter().all(|&t| t == 9.0));
    assert!(connectivity.iter().all(|&v| (v as usize) < points));
}

#[test]
fn the_contact_mesh_marks_the_vertices_in_contact() {
    let text = vtu("IV.7.vtu");
    let rows = read_csv(&data("IV.7.csv"));
    let contact = vtu_array(&text, "contact");
    let in_contact = contact.iter().filter(|&&c| c == 1.0).count();
    assert_eq!(in_contact as f64, last(&rows, "contact_vertices"));
    assert!(contact.iter().all(|&c| c == 0.0 || c == 1.0));
    // The contact pressure λᵢ/ℓᵢ: on the contact set only, never negative, and its nodal
    // forces λᵢ sum to the row's contact force.
    let pressure = vtu_array(&text, "contact_pressure");
    for (v, (&c, &p)) in contact.iter().zip(&pressure).enumerate() {
        assert!(
            p >= 0.0 && (c == 1.0 || p == 0.0),
            "vertex {v}: contact {c}, pressure {p}"
        );
    }
    let top = pressure.iter().fold(0.0_f64, |a, &b| a.max(b));
    let expected = last(&rows, "max_contact_pressure");
    assert!(
        (top / expected - 1.0).abs() < 1e-6,
        "{top} against {expected}"
    );
    assert_eq!(text.cells as f64, last(&rows, "active_cells"));
}

#[test]
fn the_film_mesh_holds_the_boundary_pressure_on_the_boundary() {
    let text = vtu("IV.36.vtu");
    let rows = read_csv(&data("IV.36.csv"));
    let cells = text.cells;
    assert_eq!(cells as f64, last(&rows, "active_cells"));
    let points = text.points;
    assert_eq!(points as f64, last(&rows, "dofs"));
    let xyz = vtu_array(&text, "Points");
    let psi = vtu_array(&text, "psi");
    // ψ = ψ₀ = 200 on ∂Ω (the unit square).
    let on_boundary = |v: usize| {
        let (x, y) = (xyz[3 * v], xyz[3 * v + 1]);
        x == 0.0 || x == 1.0 || y == 0.0 || y == 1.0
    };
    let boundary: Vec<usize> = (0..points).filter(|&v| on_boundary(v)).collect();
    assert!(boundary.len() >= 4 * 64);
    for v in boundary {
        assert_eq!(psi[v], 200.0, "ψ at vertex {v}");
    }
    assert!(
        psi.iter().any(|&p| p > 200.0),
        "the squeeze raises ψ inside"
    );
    // No cavitation model in this scene: no cavitation set.
    assert!(text.array("cavitation").is_none());
    // The gap and the mean pressure p = ψ/g (single precision).
    let (g, p) = (vtu_array(&text, "g"), vtu_array(&text, "p"));
    assert_eq!((g.len(), p.len()), (points, points));
    for v in 0..points {
        assert!(g[v] > 0.0, "g at vertex {v}");
        assert!(
            (p[v] * g[v] / psi[v] - 1.0).abs() < 1e-6,
            "p·g = ψ at vertex {v}"
        );
    }
    // The refinement level of every cell, as bytes; the adaptive mesh has several.
    let level = vtu_array(&text, "level");
    assert_eq!(level.len(), cells);
    assert!(level
        .iter()
        .all(|&l| l.fract() == 0.0 && (1.0..=30.0).contains(&l)));
    assert!(level.iter().any(|&l| l != level[0]), "one level only");
}

/// The `.pvd` series of a table lists its VTU file with the printed cycle as its time; by
/// default (`--vtu last`) that is the last mesh alone.
#[test]
fn the_film_series_opens_in_paraview_order() {
    let text = fs::read_to_string(data("IV.36.pvd")).expect("IV.36.pvd");
    let series = vtk::read_collection(&text).expect("a collection");
    let rows = read_csv(&data("IV.36.csv"));
    let cycle = last(&rows, "cycle") as usize;
    assert_eq!(series, vec![("IV.36.vtu".to_string(), cycle)]);
    let file = vtu(&series[0].0);
    for name in ["psi", "p", "g", "level"] {
        assert!(file.array(name).is_some(), "no {name} in IV.36.vtu");
    }
}
