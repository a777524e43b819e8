//! The last mesh of a run as a VTK XML unstructured grid (`report/data/<table>.vtu`), readable by
//! ParaView and VisIt: every active cell a `VTK_QUAD` (type 9) of its four corners, counter-
//! clockwise. A hanging vertex is a corner of the finer cells beside it and not of the coarser
//! one, so the coarse cell is still drawn as a quadrilateral; the hanging vertex carries its
//! constrained value (the mean of its edge's ends), so a field is continuous across the edge.
//!
//! The file is written by hand in the XML "appended" format with raw little-endian binary data
//! (`<AppendedData encoding="raw">`, a UInt64 byte count before each array): the doubles are
//! those tribo computed, bit for bit, and writing them costs no decimal formatting — the ASCII
//! form of the same meshes took several seconds per fluid table (85 MB for IV.36) and was most of
//! the report's time outside the solvers. Vectors in the plane (displacement, flow rate) are
//! written with a third component 0, which ParaView needs to draw or warp by them. [`read`]
//! reads such a file back (the tests use it, and so can a script without VTK).

use std::io::{self, BufWriter, Write};
use std::path::Path;

use crate::results::{LastMesh, MeshField};

/// The VTK cell type of a four-node quadrilateral.
pub const VTK_QUAD: u8 = 9;

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

/// Write `mesh` to `path` as a `.vtu` file (`write`).
pub fn write_file(path: &Path, mesh: &LastMesh) -> io::Result<()> {
    crate::fsio::write_with(path, |file| {
        let mut out = BufWriter::with_capacity(1 << 20, file);
        write(&mut out, mesh)?;
        out.flush()
    })
}

/// One data array: its XML attributes and how many values of how many bytes it holds.
struct Head<'a> {
    kind: &'static str,
    name: &'a str,
    components: usize,
    values: usize,
    size: usize,
}

impl Head<'_> {
    /// Bytes of the array's data.
    fn data_bytes(&self) -> usize {
        self.values * self.size
    }

    /// Bytes in the appended section: the UInt64 count, then the data.
    fn bytes(&self) -> usize {
        8 + self.data_bytes()
    }
}

/// A field as a `Float64` array; a 2-vector gets a third component 0.
fn field_head(f: &MeshField) -> Head<'_> {
    let components = if f.components == 2 { 3 } else { f.components };
    Head {
        kind: "Float64",
        name: &f.name,
        components,
        values: f.values.len() / f.components * components,
        size: 8,
    }
}

/// Write `mesh` as a VTK XML unstructured grid: the point fields as `PointData`, the cell fields
/// as `CellData`, the points (z = 0), the cells as quadrilaterals (`connectivity`, `offsets`,
/// `types`), every array appended in raw binary (module docs). A mesh whose fields do not fit it
/// is an error naming the field ([`check`]).
pub fn write(out: &mut impl Write, mesh: &LastMesh) -> io::Result<()> {
    check(mesh)?;
    let (n_points, n_cells) = (mesh.points.len(), mesh.cells.len());
    let point_heads: Vec<Head> = mesh.point_fields.iter().map(field_head).collect();
    let cell_heads: Vec<Head> = mesh.cell_fields.iter().map(field_head).collect();
    let points = Head {
        kind: "Float64",
        name: "Points",
        components: 3,
        values: 3 * n_points,
        size: 8,
    };
    let cells = [
        Head {
            kind: "Int64",
            name: "connectivity",
            components: 1,
            values: 4 * n_cells,
            size: 8,
        },
        Head {
            kind: "Int64",
            name: "offsets",
            components: 1,
            values: n_cells,
            size: 8,
        },
        Head {
            kind: "UInt8",
            name: "types",
            components: 1,
            values: n_cells,
            size: 1,
        },
    ];
    let mut offset = 0;
    let mut tag = |out: &mut dyn Write, h: &Head| -> io::Result<()> {
        writeln!(
            out,
            "<DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" \
             format=\"appended\" offset=\"{offset}\"/>",
            h.kind,
            xml_escape(h.name),
            h.components
        )?;
        offset += h.bytes();
        Ok(())
    };
    writeln!(out, "<?xml version=\"1.0\"?>")?;
    writeln!(
        out,
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" \
         header_type=\"UInt64\">"
    )?;
    writeln!(out, "<UnstructuredGrid>")?;
    writeln!(
        out,
        "<Piece NumberOfPoints=\"{n_points}\" NumberOfCells=\"{n_cells}\">"
    )?;
    writeln!(out, "<PointData>")?;
    for h in &point_heads {
        tag(out, h)?;
    }
    writeln!(out, "</PointData>")?;
    writeln!(out, "<CellData>")?;
    for h in &cell_heads {
        tag(out, h)?;
    }
    writeln!(out, "</CellData>")?;
    writeln!(out, "<Points>")?;
    tag(out, &points)?;
    writeln!(out, "</Points>")?;
    writeln!(out, "<Cells>")?;
    for h in &cells {
        tag(out, h)?;
    }
    writeln!(out, "</Cells>")?;
    writeln!(out, "</Piece>")?;
    writeln!(out, "</UnstructuredGrid>")?;
    write!(out, "<AppendedData encoding=\"raw\">\n_")?;
    for (f, h) in mesh
        .point_fields
        .iter()
        .chain(&mesh.cell_fields)
        .zip(point_heads.iter().chain(&cell_heads))
    {
        count(out, h)?;
        if f.components == 2 {
            for v in f.values.chunks_exact(2) {
                reals(out, &[v[0], v[1], 0.0])?;
            }
        } else {
            reals(out, &f.values)?;
        }
    }
    count(out, &points)?;
    for p in &mesh.points {
        reals(out, &[p[0], p[1], 0.0])?;
    }
    count(out, &cells[0])?;
    for c in &mesh.cells {
        for &v in c {
            out.write_all(&(v as i64).to_le_bytes())?;
        }
    }
    count(out, &cells[1])?;
    for k in 1..=n_cells {
        out.write_all(&(4 * k as i64).to_le_bytes())?;
    }
    count(out, &cells[2])?;
    out.write_all(&vec![VTK_QUAD; n_cells])?;
    writeln!(out, "\n</AppendedData>")?;
    writeln!(out, "</VTKFile>")
}

/// The UInt64 byte count before an array's data.
fn count(out: &mut impl Write, h: &Head) -> io::Result<()> {
    out.write_all(&(h.data_bytes() as u64).to_le_bytes())
}

/// Doubles in little-endian order.
fn reals(out: &mut impl Write, values: &[f64]) -> io::Result<()> {
    for v in values {
        out.write_all(&v.to_le_bytes())?;
    }
    Ok(())
}

/// `name` with the characters XML reserves in an attribute replaced.
fn xml_escape(name: &str) -> String {
    name.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// `name` with the replacements of [`xml_escape`] undone.
fn xml_unescape(name: &str) -> String {
    name.replace("&quot;", "\"")
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&amp;", "&")
}

/// A `.vtu` file as `write` writes it, read back: the counts of its piece and every data array
/// as doubles (integers converted), by name.
#[derive(Debug)]
pub struct VtuFile {
    pub points: usize,
    pub cells: usize,
    pub arrays: Vec<(String, Vec<f64>)>,
}

impl VtuFile {
    /// The array `name`, if the file has one.
    pub fn array(&self, name: &str) -> Option<&[f64]> {
        self.arrays
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| &v[..])
    }
}

/// Read a file written by `write` (appended raw data, UInt64 headers, little-endian); an error
/// says what does not fit that form.
pub fn read(bytes: &[u8]) -> io::Result<VtuFile> {
    let marker = b"<AppendedData encoding=\"raw\">";
    let at = bytes
        .windows(marker.len())
        .position(|w| w == marker)
        .ok_or_else(|| invalid("no <AppendedData encoding=\"raw\"> section".into()))?;
    let xml = std::str::from_utf8(&bytes[..at]).map_err(|e| invalid(e.to_string()))?;
    let data_start = at
        + marker.len()
        + bytes[at + marker.len()..]
            .iter()
            .position(|&b| b == b'_')
            .ok_or_else(|| invalid("no `_` before the appended data".into()))?
        + 1;
    let data = &bytes[data_start..];
    let attribute = |tag: &str, name: &str| -> io::Result<String> {
        let key = format!("{name}=\"");
        let start = tag
            .find(&key)
            .ok_or_else(|| invalid(format!("no attribute {name} in {tag}")))?
            + key.len();
        let len = tag[start..]
            .find('"')
            .ok_or_else(|| invalid(format!("unterminated attribute {name}")))?;
        Ok(tag[start..start + len].to_string())
    };
    let number = |tag: &str, name: &str| -> io::Result<usize> {
        attribute(tag, name)?
            .parse()
            .map_err(|e| invalid(format!("{name}: {e}")))
    };
    let piece = &xml[xml
        .find("<Piece ")
        .ok_or_else(|| invalid("no <Piece>".into()))?..];
    let (points, cells) = (
        number(piece, "NumberOfPoints")?,
        number(piece, "NumberOfCells")?,
    );
    let mut arrays = Vec::new();
    for tag in xml.split("<DataArray ").skip(1) {
        let tag = &tag[..tag.find('>').unwrap_or(tag.len())];
        let (kind, name, offset) = (
            attribute(tag, "type")?,
            attribute(tag, "Name")?,
            number(tag, "offset")?,
        );
        let past_end = || invalid(format!("array {name} runs past the end of the file"));
        let start = offset.checked_add(8).ok_or_else(past_end)?;
        let count: [u8; 8] = data
            .get(offset..start)
            .and_then(|b| b.try_into().ok())
            .ok_or_else(past_end)?;
        let end = usize::try_from(u64::from_le_bytes(count))
            .ok()
            .and_then(|n| start.checked_add(n))
            .ok_or_else(past_end)?;
        let body = data.get(start..end).ok_or_else(past_end)?;
        let values: Vec<f64> = match kind.as_str() {
            "Float64" => body
                .chunks_exact(8)
                .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")))
                .collect(),
            "Int64" => body
                .chunks_exact(8)
                .map(|b| i64::from_le_bytes(b.try_into().expect("8 bytes")) as f64)
                .collect(),
            "UInt8" => body.iter().map(|&b| b as f64).collect(),
            other => return Err(invalid(format!("array {name}: type {other} not read"))),
        };
        arrays.push((xml_unescape(&name), values));
    }
    Ok(VtuFile {
        points,
        cells,
        arrays,
    })
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
        let head = String::from_utf8_lossy(&out);
        assert!(head.contains("<Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">"));
        assert!(head.contains(
            "Name=\"displacement\" NumberOfComponents=\"3\" format=\"appended\" offset=\"0\"/>"
        ));
        // 12 doubles of the displacement after its count: the next array starts at 8 + 96.
        assert!(head.contains(
            "Name=\"eta_squared\" NumberOfComponents=\"1\" format=\"appended\" offset=\"104\"/>"
        ));
        let file = read(&out).unwrap();
        assert_eq!((file.points, file.cells), (4, 1));
        assert_eq!(
            file.array("displacement").unwrap(),
            [0.0, 0.0, 0.0, 0.1, -0.2, 0.0, 0.0, 0.0, 0.0, 1e-300, 3.0, 0.0]
        );
        assert_eq!(file.array("eta_squared").unwrap(), [0.25]);
        assert_eq!(file.array("connectivity").unwrap(), [0.0, 1.0, 3.0, 2.0]);
        assert_eq!(file.array("offsets").unwrap(), [4.0]);
        assert_eq!(file.array("types").unwrap(), [9.0]);
        assert_eq!(file.array("Points").unwrap().len(), 12);
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
        let values = [0.1, -2.5e-17, 1.0 / 3.0, 6.02e23, 0.0, f64::MIN_POSITIVE];
        let mut mesh = square();
        mesh.point_fields[0] = MeshField {
            name: "a \"quoted\" <name>".into(),
            components: 1,
            values: values[..4].to_vec(),
        };
        let mut out = Vec::new();
        write(&mut out, &mesh).unwrap();
        let file = read(&out).unwrap();
        assert_eq!(file.array("a \"quoted\" <name>").unwrap(), &values[..4]);
    }

    #[test]
    fn a_truncated_file_is_an_error() {
        let mut out = Vec::new();
        write(&mut out, &square()).unwrap();
        let e = read(&out[..out.len() - 40]).unwrap_err();
        assert!(e.to_string().contains("runs past the end"), "{e}");
        // A byte count near 2⁶⁴ is an error, not an overflow.
        let data = out
            .windows(2)
            .position(|w| w == b"\n_")
            .expect("appended data")
            + 2;
        let mut huge = out.clone();
        huge[data..data + 8].copy_from_slice(&(u64::MAX - 3).to_le_bytes());
        let e = read(&huge).unwrap_err();
        assert!(e.to_string().contains("runs past the end"), "{e}");
        assert!(read(b"<VTKFile>").is_err());
    }
}
