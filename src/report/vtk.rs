//! The last mesh of a run as a VTK XML unstructured grid (`report/data/<table>.vtu`), readable by
//! ParaView and VisIt: every active cell a `VTK_QUAD` (type 9) of its four corners, counter-
//! clockwise. A hanging vertex is a corner of the finer cells beside it and not of the coarser
//! one, so the coarse cell is still drawn as a quadrilateral; the hanging vertex carries its
//! constrained value (the mean of its edge's ends), so a field is continuous across the edge.
//!
//! The file is written by hand in the XML "ascii" format (no base64, no compression): every
//! number is in the shortest decimal form that reads back to the same `f64`, so a reader gets the
//! values tribo computed bit for bit. Vectors in the plane (displacement, flow rate) are written
//! with a third component 0, which ParaView needs to draw or warp by them.

use std::fmt::Write as _;
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

use crate::results::{LastMesh, MeshField};

/// The VTK cell type of a four-node quadrilateral.
pub const VTK_QUAD: u8 = 9;

/// Numbers per line in the data arrays (only to keep lines readable).
const PER_LINE: usize = 12;

/// Why a mesh cannot be written: a field whose length does not fit the mesh, a cell naming a
/// vertex the mesh does not have.
fn invalid(message: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidData, message)
}

/// Check that every cell names existing vertices and every field has `components` values per
/// point or per cell.
pub fn check(mesh: &LastMesh) -> io::Result<()> {
    let n = mesh.points.len();
    if let Some((k, c)) = mesh
        .cells
        .iter()
        .enumerate()
        .find(|(_, c)| c.iter().any(|&v| v as usize >= n))
    {
        return Err(invalid(format!(
            "cell {k} has the corners {c:?}, but the mesh has {n} vertices"
        )));
    }
    for (fields, per, kind) in [
        (&mesh.point_fields, n, "point"),
        (&mesh.cell_fields, mesh.cells.len(), "cell"),
    ] {
        for f in fields {
            if f.components == 0 || f.values.len() != f.components * per {
                return Err(invalid(format!(
                    "{kind} field `{}` has {} values, expected {} component(s) for each of {per} {kind}s",
                    f.name,
                    f.values.len(),
                    f.components
                )));
            }
        }
    }
    Ok(())
}

/// Write `mesh` to `path` as a `.vtu` file ([`write`]).
pub fn write_file(path: &Path, mesh: &LastMesh) -> io::Result<()> {
    let mut out = BufWriter::new(File::create(path)?);
    write(&mut out, mesh)?;
    out.flush()
}

/// Write `mesh` as a VTK XML unstructured grid: the points (z = 0), the cells as quadrilaterals
/// (`connectivity`, `offsets`, `types`), the point fields as `PointData` and the cell fields as
/// `CellData`. A mesh whose fields do not fit it is an error naming the field ([`check`]).
pub fn write(out: &mut impl Write, mesh: &LastMesh) -> io::Result<()> {
    check(mesh)?;
    writeln!(out, "<?xml version=\"1.0\"?>")?;
    writeln!(
        out,
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" \
         header_type=\"UInt64\">"
    )?;
    writeln!(out, "<UnstructuredGrid>")?;
    writeln!(
        out,
        "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
        mesh.points.len(),
        mesh.cells.len()
    )?;
    writeln!(out, "<PointData>")?;
    for f in &mesh.point_fields {
        field(out, f)?;
    }
    writeln!(out, "</PointData>")?;
    writeln!(out, "<CellData>")?;
    for f in &mesh.cell_fields {
        field(out, f)?;
    }
    writeln!(out, "</CellData>")?;
    writeln!(out, "<Points>")?;
    array(
        out,
        "Float64",
        "Points",
        3,
        mesh.points.iter().flat_map(|p| [p[0], p[1], 0.0]).map(real),
    )?;
    writeln!(out, "</Points>")?;
    writeln!(out, "<Cells>")?;
    array(
        out,
        "Int64",
        "connectivity",
        1,
        mesh.cells.iter().flatten().map(|v| v.to_string()),
    )?;
    array(
        out,
        "Int64",
        "offsets",
        1,
        (1..=mesh.cells.len()).map(|k| (4 * k).to_string()),
    )?;
    array(
        out,
        "UInt8",
        "types",
        1,
        mesh.cells.iter().map(|_| VTK_QUAD.to_string()),
    )?;
    writeln!(out, "</Cells>")?;
    writeln!(out, "</Piece>")?;
    writeln!(out, "</UnstructuredGrid>")?;
    writeln!(out, "</VTKFile>")
}

/// One field as a `Float64` data array; a 2-vector gets a third component 0.
fn field(out: &mut impl Write, f: &MeshField) -> io::Result<()> {
    if f.components == 2 {
        let values = f
            .values
            .chunks_exact(2)
            .flat_map(|v| [v[0], v[1], 0.0])
            .map(real);
        array(out, "Float64", &f.name, 3, values)
    } else {
        array(
            out,
            "Float64",
            &f.name,
            f.components,
            f.values.iter().copied().map(real),
        )
    }
}

/// A data array of the "ascii" format, `PER_LINE` values a line.
fn array(
    out: &mut impl Write,
    kind: &str,
    name: &str,
    components: usize,
    values: impl Iterator<Item = String>,
) -> io::Result<()> {
    writeln!(
        out,
        "<DataArray type=\"{kind}\" Name=\"{}\" NumberOfComponents=\"{components}\" \
         format=\"ascii\">",
        xml_escape(name)
    )?;
    let mut line = String::new();
    for (i, v) in values.enumerate() {
        if i % PER_LINE != 0 {
            line.push(' ');
        }
        line.push_str(&v);
        if i % PER_LINE == PER_LINE - 1 {
            writeln!(out, "{line}")?;
            line.clear();
        }
    }
    if !line.is_empty() {
        writeln!(out, "{line}")?;
    }
    writeln!(out, "</DataArray>")
}

/// A real number in the shortest form that reads back to the same `f64` (`1.5e-3`, `0e0`); a
/// non-finite value (never produced: solutions and estimates are checked) as `nan`.
fn real(v: f64) -> String {
    let mut s = String::new();
    if v.is_finite() {
        let _ = write!(s, "{v:e}");
    } else {
        s.push_str("nan");
    }
    s
}

/// `name` with the characters XML reserves in an attribute replaced.
fn xml_escape(name: &str) -> String {
    name.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> LastMesh {
        LastMesh {
            cycle: 0,
            points: vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]],
            cells: vec![[0, 1, 3, 2]],
            point_fields: vec![MeshField {
                name: "displacement".into(),
                components: 2,
                values: vec![0.0, 0.0, 0.1, -0.2, 0.0, 0.0, 1e-300, 3.0],
            }],
            cell_fields: vec![MeshField {
                name: "eta_squared".into(),
                components: 1,
                values: vec![0.25],
            }],
        }
    }

    #[test]
    fn a_square_is_one_quad_with_padded_vectors() {
        let mut out = Vec::new();
        write(&mut out, &square()).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(text.contains("<Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">"));
        assert!(text.contains("Name=\"displacement\" NumberOfComponents=\"3\""));
        assert!(text.contains("0e0 0e0 0e0 1e-1 -2e-1 0e0 0e0 0e0 0e0 1e-300 3e0 0e0"));
        assert!(text.contains("\n0 1 3 2\n"));
        assert!(text.contains("Name=\"offsets\" NumberOfComponents=\"1\" format=\"ascii\">\n4\n"));
        assert!(text.contains("Name=\"types\" NumberOfComponents=\"1\" format=\"ascii\">\n9\n"));
    }

    #[test]
    fn a_field_of_the_wrong_length_is_an_error_naming_it() {
        let mut mesh = square();
        mesh.cell_fields[0].values.push(1.0);
        let e = write(&mut Vec::new(), &mesh).unwrap_err();
        assert!(
            e.to_string()
                .contains("cell field `eta_squared` has 2 values"),
            "{e}"
        );
        let mut mesh = square();
        mesh.cells[0][2] = 4;
        let e = write(&mut Vec::new(), &mesh).unwrap_err();
        assert!(e.to_string().contains("cell 0"), "{e}");
    }

    #[test]
    fn reals_read_back_exactly() {
        for v in [0.1, -2.5e-17, 1.0 / 3.0, 6.02e23, 0.0] {
            assert_eq!(real(v).parse::<f64>().unwrap(), v);
        }
    }
}
