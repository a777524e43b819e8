//! The meshes of a run as VTK XML unstructured grids (`report/data/<table>.vtu`, with
//! `<table>.pvd` listing them for ParaView), readable by ParaView and VisIt: every active cell a
//! `VTK_QUAD` (type 9) of its four corners, counter-clockwise. A hanging vertex is a corner of
//! the finer cells beside it and not of the coarser one, so the coarse cell is still drawn as a
//! quadrilateral; the hanging vertex carries its constrained value (the mean of its edge's
//! ends), so a field is continuous across the edge.
//!
//! The file is written by hand in the XML "appended" format, each array zlib-compressed in
//! blocks of [`BLOCK`] bytes (`compressor="vtkZLibDataCompressor"`, UInt64 headers: the number
//! of blocks, the block size, the size of a partial last block, then each block's compressed
//! size). The fields of reals ([`FieldKind::Real`]: the solutions, p = ψ/g, g, the stresses)
//! are `Float32`, 7 significant digits, the indicators η² ([`FieldKind::Indicator`]) rounded to
//! 4 digits: doubles of the solutions compress to twice the
//! bytes (IV.36's ψ: 4.1 against 1.9 MB) and a default run's folder would pass 300 MB. The
//! points stay `Float64` (exact on the dyadic meshes, and they compress 10:1), flags and levels
//! ([`FieldKind::Small`]) are `UInt8`, the connectivity and offsets `Int32` where they fit. The
//! ASCII form of IV.36's mesh took 85 MB and seconds to write, the uncompressed binary 73 MB
//! (without p and g). Vectors in the plane (displacement, flow rate) are written with
//! a third component 0, which ParaView needs to draw or warp by them. [`read`] reads such a
//! file back, inflating the arrays (the tests use it, and so can a script without VTK).

use std::io::{self, BufWriter, Write};
use std::path::Path;

use rayon::prelude::*;

use crate::results::{FieldKind, LastMesh, MeshField, INDICATOR_BITS};

/// The VTK cell type of a four-node quadrilateral.
pub const VTK_QUAD: u8 = 9;

/// Uncompressed bytes per compressed block (VTK's own default).
pub const BLOCK: usize = 1 << 15;

/// zlib level of the blocks: the fastest. Levels 3 and 6 made the files of IV.1, IV.7 and IV.36
/// 5 % smaller (15.8 → 15.0 MB).
const LEVEL: u8 = 1;

/// Why a mesh cannot be written: a field whose length does not fit the mesh, a cell naming a
/// vertex the mesh does not have, a small field with a value that is no byte.
fn invalid(message: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidData, message)
}

/// Check that every cell names existing vertices, every field has `components` values per
/// point or per cell, and every small field holds whole numbers in 0..=255.
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
            let byte = |v: f64| (0.0..=255.0).contains(&v) && v.fract() == 0.0;
            if f.kind == FieldKind::Small {
                if let Some(v) = f.values.iter().find(|&&v| !byte(v)) {
                    return Err(invalid(format!(
                        "{kind} field `{}` is written as bytes, but holds the value {v}",
                        f.name
                    )));
                }
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

/// One data array: its XML attributes and its data, compressed with its header.
struct Array<'a> {
    kind: &'static str,
    name: &'a str,
    components: usize,
    encoded: Vec<u8>,
}

impl<'a> Array<'a> {
    fn new(kind: &'static str, name: &'a str, components: usize, raw: &[u8]) -> Array<'a> {
        Array {
            kind,
            name,
            components,
            encoded: compressed(raw),
        }
    }
}

/// `raw` as VTK's zlib compressor writes it (module docs): the UInt64 header, then the blocks.
fn compressed(raw: &[u8]) -> Vec<u8> {
    let blocks: Vec<Vec<u8>> = raw
        .par_chunks(BLOCK)
        .map(|b| miniz_oxide::deflate::compress_to_vec_zlib(b, LEVEL))
        .collect();
    let mut out =
        Vec::with_capacity(8 * (3 + blocks.len()) + blocks.iter().map(Vec::len).sum::<usize>());
    for n in [blocks.len(), BLOCK, raw.len() % BLOCK]
        .into_iter()
        .chain(blocks.iter().map(Vec::len))
    {
        out.extend_from_slice(&(n as u64).to_le_bytes());
    }
    for b in &blocks {
        out.extend_from_slice(b);
    }
    out
}

/// A field as an array: reals as `Float32` (a 2-vector with a third component 0), small whole
/// numbers as `UInt8`.
fn field_array(f: &MeshField) -> Array<'_> {
    match f.kind {
        FieldKind::Small => {
            let raw: Vec<u8> = f.values.iter().map(|&v| v as u8).collect();
            Array::new("UInt8", &f.name, f.components, &raw)
        }
        FieldKind::Indicator => {
            let raw: Vec<u8> = f
                .values
                .iter()
                .flat_map(|&v| rounded(v as f32, INDICATOR_BITS).to_le_bytes())
                .collect();
            Array::new("Float32", &f.name, f.components, &raw)
        }
        FieldKind::Real if f.components == 2 => {
            let raw: Vec<u8> = f
                .values
                .chunks_exact(2)
                .flat_map(|v| [v[0] as f32, v[1] as f32, 0.0])
                .flat_map(f32::to_le_bytes)
                .collect();
            Array::new("Float32", &f.name, 3, &raw)
        }
        FieldKind::Real => {
            let raw: Vec<u8> = f
                .values
                .iter()
                .flat_map(|&v| (v as f32).to_le_bytes())
                .collect();
            Array::new("Float32", &f.name, f.components, &raw)
        }
    }
}

/// `v` rounded to the nearest number with `bits` bits of mantissa (of single precision's 23), ties
/// away from zero: the dropped bits become zeros, which compress.
fn rounded(v: f32, bits: u32) -> f32 {
    let drop = 23 - bits;
    let half = 1u32 << (drop - 1);
    f32::from_bits((v.to_bits() + half) & !((1u32 << drop) - 1))
}

/// Integers as `Int32` where every one fits, else `Int64`.
fn integer_array(
    name: &str,
    values: impl Iterator<Item = usize> + Clone,
    largest: usize,
) -> Array<'_> {
    if i32::try_from(largest).is_ok() {
        let raw: Vec<u8> = values.flat_map(|v| (v as i32).to_le_bytes()).collect();
        Array::new("Int32", name, 1, &raw)
    } else {
        let raw: Vec<u8> = values.flat_map(|v| (v as i64).to_le_bytes()).collect();
        Array::new("Int64", name, 1, &raw)
    }
}

/// Write `mesh` as a VTK XML unstructured grid: the point fields as `PointData`, the cell fields
/// as `CellData`, the points (z = 0), the cells as quadrilaterals (`connectivity`, `offsets`,
/// `types`), every array appended compressed (module docs). A mesh whose fields do not fit it
/// is an error naming the field ([`check`]).
pub fn write(out: &mut impl Write, mesh: &LastMesh) -> io::Result<()> {
    check(mesh)?;
    let (n_points, n_cells) = (mesh.points.len(), mesh.cells.len());
    let point_arrays: Vec<Array> = mesh.point_fields.iter().map(field_array).collect();
    let cell_arrays: Vec<Array> = mesh.cell_fields.iter().map(field_array).collect();
    let coords: Vec<u8> = mesh
        .points
        .iter()
        .flat_map(|p| [p[0], p[1], 0.0])
        .flat_map(f64::to_le_bytes)
        .collect();
    let points = Array::new("Float64", "Points", 3, &coords);
    let corners = mesh.cells.iter().flatten().map(|&v| v as usize);
    let cells = [
        integer_array("connectivity", corners, n_points),
        integer_array("offsets", (1..=n_cells).map(|k| 4 * k), 4 * n_cells),
        Array::new("UInt8", "types", 1, &vec![VTK_QUAD; n_cells]),
    ];
    let mut offset = 0;
    let mut tag = |out: &mut dyn Write, a: &Array| -> io::Result<()> {
        writeln!(
            out,
            "<DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" \
             format=\"appended\" offset=\"{offset}\"/>",
            a.kind,
            xml_escape(a.name),
            a.components
        )?;
        offset += a.encoded.len();
        Ok(())
    };
    writeln!(out, "<?xml version=\"1.0\"?>")?;
    writeln!(
        out,
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" \
         header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\">"
    )?;
    writeln!(out, "<UnstructuredGrid>")?;
    writeln!(
        out,
        "<Piece NumberOfPoints=\"{n_points}\" NumberOfCells=\"{n_cells}\">"
    )?;
    writeln!(out, "<PointData>")?;
    for a in &point_arrays {
        tag(out, a)?;
    }
    writeln!(out, "</PointData>")?;
    writeln!(out, "<CellData>")?;
    for a in &cell_arrays {
        tag(out, a)?;
    }
    writeln!(out, "</CellData>")?;
    writeln!(out, "<Points>")?;
    tag(out, &points)?;
    writeln!(out, "</Points>")?;
    writeln!(out, "<Cells>")?;
    for a in &cells {
        tag(out, a)?;
    }
    writeln!(out, "</Cells>")?;
    writeln!(out, "</Piece>")?;
    writeln!(out, "</UnstructuredGrid>")?;
    write!(out, "<AppendedData encoding=\"raw\">\n_")?;
    for a in point_arrays
        .iter()
        .chain(&cell_arrays)
        .chain([&points])
        .chain(&cells)
    {
        out.write_all(&a.encoded)?;
    }
    writeln!(out, "\n</AppendedData>")?;
    writeln!(out, "</VTKFile>")
}

/// A ParaView collection (`.pvd`) of the VTU files `files` (file name relative to the `.pvd`,
/// and its time: the printed cycle, or the load step of the forming).
pub fn write_collection(path: &Path, files: &[(String, usize)]) -> io::Result<()> {
    crate::fsio::write_with(path, |file| {
        let mut out = BufWriter::new(file);
        writeln!(out, "<?xml version=\"1.0\"?>")?;
        writeln!(
            out,
            "<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">"
        )?;
        writeln!(out, "<Collection>")?;
        for (name, time) in files {
            writeln!(
                out,
                "<DataSet timestep=\"{time}\" part=\"0\" file=\"{}\"/>",
                xml_escape(name)
            )?;
        }
        writeln!(out, "</Collection>")?;
        writeln!(out, "</VTKFile>")?;
        out.flush()
    })
}

/// The files and times of a `.pvd` written by [`write_collection`].
pub fn read_collection(text: &str) -> io::Result<Vec<(String, usize)>> {
    text.split("<DataSet ")
        .skip(1)
        .map(|tag| {
            let tag = &tag[..tag.find('>').unwrap_or(tag.len())];
            let time = attribute(tag, "timestep")?
                .parse()
                .map_err(|e| invalid(format!("timestep: {e}")))?;
            Ok((xml_unescape(&attribute(tag, "file")?), time))
        })
        .collect()
}

/// The value of the attribute `name` in the text of a tag (a whole attribute name: `type` does
/// not match `header_type`).
fn attribute(tag: &str, name: &str) -> io::Result<String> {
    let padded = format!(" {tag}");
    let key = format!(" {name}=\"");
    let start = padded
        .find(&key)
        .ok_or_else(|| invalid(format!("no attribute {name} in {tag}")))?
        + key.len();
    let len = padded[start..]
        .find('"')
        .ok_or_else(|| invalid(format!("unterminated attribute {name}")))?;
    Ok(padded[start..start + len].to_string())
}

/// The number in the attribute `name` of a tag.
fn number(tag: &str, name: &str) -> io::Result<usize> {
    attribute(tag, name)?
        .parse()
        .map_err(|e| invalid(format!("{name}: {e}")))
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

/// Read a file written by `write` (appended zlib-compressed data, UInt64 headers,
/// little-endian); an error says what does not fit that form.
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
    let file = &xml[xml
        .find("<VTKFile ")
        .ok_or_else(|| invalid("no <VTKFile>".into()))?..];
    if attribute(file, "compressor")? != "vtkZLibDataCompressor" {
        return Err(invalid("not compressed with vtkZLibDataCompressor".into()));
    }
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
        let body = inflate(data, offset).map_err(|e| invalid(format!("array {name}: {e}")))?;
        let values: Vec<f64> = match kind.as_str() {
            "Float64" => body
                .chunks_exact(8)
                .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")))
                .collect(),
            "Float32" => body
                .chunks_exact(4)
                .map(|b| f64::from(f32::from_le_bytes(b.try_into().expect("4 bytes"))))
                .collect(),
            "Int64" => body
                .chunks_exact(8)
                .map(|b| i64::from_le_bytes(b.try_into().expect("8 bytes")) as f64)
                .collect(),
            "Int32" => body
                .chunks_exact(4)
                .map(|b| f64::from(i32::from_le_bytes(b.try_into().expect("4 bytes"))))
                .collect(),
            "UInt8" => body.iter().map(|&b| f64::from(b)).collect(),
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

/// The data of the compressed array at `offset` of the appended section (module docs).
fn inflate(data: &[u8], offset: usize) -> Result<Vec<u8>, String> {
    let past_end = || "runs past the end of the file".to_string();
    let word = |k: usize| -> Result<usize, String> {
        let at = k
            .checked_mul(8)
            .and_then(|b| offset.checked_add(b))
            .ok_or_else(past_end)?;
        let bytes: [u8; 8] = data
            .get(at..at.checked_add(8).ok_or_else(past_end)?)
            .and_then(|b| b.try_into().ok())
            .ok_or_else(past_end)?;
        usize::try_from(u64::from_le_bytes(bytes)).map_err(|_| past_end())
    };
    let (blocks, block, last) = (word(0)?, word(1)?, word(2)?);
    let mut at = blocks
        .checked_add(3)
        .and_then(|w| w.checked_mul(8))
        .and_then(|b| offset.checked_add(b))
        .ok_or_else(past_end)?;
    let mut out = Vec::new();
    for k in 0..blocks {
        let size = word(3 + k)?;
        let end = at.checked_add(size).ok_or_else(past_end)?;
        let block_data = data.get(at..end).ok_or_else(past_end)?;
        let inflated = miniz_oxide::inflate::decompress_to_vec_zlib(block_data)
            .map_err(|e| format!("block {k} does not inflate: {e:?}"))?;
        let expected = if k + 1 == blocks && last != 0 {
            last
        } else {
            block
        };
        if inflated.len() != expected {
            return Err(format!(
                "block {k} inflates to {} bytes, its header says {expected}",
                inflated.len()
            ));
        }
        out.extend_from_slice(&inflated);
        at = end;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> LastMesh {
        LastMesh {
            cycle: 0,
            points: vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]],
            cells: vec![[0, 1, 3, 2]],
            point_fields: vec![
                MeshField::real(
                    "displacement",
                    2,
                    vec![0.0, 0.0, 0.1, -0.2, 0.0, 0.0, 1e-300, 3.0],
                ),
                MeshField::flags("contact", [true, false, false, true]),
            ],
            cell_fields: vec![
                MeshField::indicator("eta_squared", vec![0.25]),
                MeshField::small("level", vec![7.0]),
            ],
        }
    }

    #[test]
    fn a_square_is_one_quad_with_padded_vectors_and_typed_arrays() {
        let mut out = Vec::new();
        write(&mut out, &square()).unwrap();
        let head = String::from_utf8_lossy(&out);
        assert!(head.contains("compressor=\"vtkZLibDataCompressor\""));
        assert!(head.contains("<Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">"));
        assert!(head.contains(
            "<DataArray type=\"Float32\" Name=\"displacement\" NumberOfComponents=\"3\" \
             format=\"appended\" offset=\"0\"/>"
        ));
        for (kind, name) in [
            ("Float32", "eta_squared"),
            ("UInt8", "contact"),
            ("UInt8", "level"),
            ("Int32", "connectivity"),
            ("Int32", "offsets"),
            ("UInt8", "types"),
        ] {
            assert!(
                head.contains(&format!("<DataArray type=\"{kind}\" Name=\"{name}\"")),
                "{name}"
            );
        }
        let file = read(&out).unwrap();
        assert_eq!((file.points, file.cells), (4, 1));
        assert_eq!(
            file.array("displacement").unwrap(),
            [0.0, 0.0, 0.0, 0.1, -0.2, 0.0, 0.0, 0.0, 0.0, 0.0, 3.0, 0.0].map(single)
        );
        assert_eq!(file.array("contact").unwrap(), [1.0, 0.0, 0.0, 1.0]);
        assert_eq!(file.array("eta_squared").unwrap(), [0.25]);
        assert_eq!(file.array("level").unwrap(), [7.0]);
        assert_eq!(file.array("connectivity").unwrap(), [0.0, 1.0, 3.0, 2.0]);
        assert_eq!(file.array("offsets").unwrap(), [4.0]);
        assert_eq!(file.array("types").unwrap(), [9.0]);
        assert_eq!(file.array("Points").unwrap().len(), 12);
    }

    /// `v` as written: rounded to single precision.
    fn single(v: f64) -> f64 {
        f64::from(v as f32)
    }

    /// An array longer than a block is split into blocks, the last one partial, and read back
    /// whole; a field of zeros compresses to almost nothing.
    #[test]
    fn long_arrays_span_blocks_and_compress() {
        let n = 3 * BLOCK / 8 + 5;
        let values: Vec<f64> = (0..n).map(|k| (k as f64).sqrt()).collect();
        let mut mesh = square();
        mesh.points = (0..n).map(|k| [k as f64, 0.0]).collect();
        mesh.point_fields = vec![
            MeshField::real("root", 1, values.clone()),
            MeshField::real("zero", 1, vec![0.0; n]),
        ];
        let mut out = Vec::new();
        write(&mut out, &mesh).unwrap();
        let file = read(&out).unwrap();
        let singles: Vec<f64> = values.iter().map(|&v| single(v)).collect();
        assert_eq!(file.array("root").unwrap(), &singles[..]);
        assert_eq!(file.array("zero").unwrap(), &vec![0.0; n][..]);
        assert!(compressed(&vec![0; 8 * n]).len() < 8 * n / 100);
        // four blocks: three whole, the last of 40 bytes
        let root = compressed(
            &values
                .iter()
                .flat_map(|v| v.to_le_bytes())
                .collect::<Vec<_>>(),
        );
        let word = |k: usize| u64::from_le_bytes(root[8 * k..8 * k + 8].try_into().unwrap());
        assert_eq!((word(0), word(1), word(2)), (4, BLOCK as u64, 40));
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
        let mut mesh = square();
        mesh.cell_fields[1].values[0] = 256.0;
        let e = write(&mut Vec::new(), &mesh).unwrap_err();
        assert!(e.to_string().contains("`level` is written as bytes"), "{e}");
    }

    #[test]
    fn indicators_keep_four_digits() {
        for v in [1.0_f32, 0.1, 1.0 / 3.0, 6.02e23, 1e-30, 0.99999] {
            let r = rounded(v, INDICATOR_BITS);
            assert!(((r - v) / v).abs() <= 2.0_f32.powi(-13), "{v} → {r}");
            assert_eq!(r.to_bits() & 0x7ff, 0, "{v}: the low bits are zeros");
        }
        assert_eq!(rounded(1.0, INDICATOR_BITS), 1.0);
        assert_eq!(rounded(0.0, INDICATOR_BITS), 0.0);
    }

    /// Fields come back rounded to single precision, the points exactly; a name is escaped.
    #[test]
    fn reals_read_back_in_single_precision_and_points_exactly() {
        let values = [0.1, -2.5e-17, 1.0 / 3.0, 6.02e23];
        let mut mesh = square();
        mesh.point_fields[0] = MeshField::real("a \"quoted\" <name>", 1, values.to_vec());
        mesh.points[3] = [1.0 / 3.0, f64::MIN_POSITIVE];
        let mut out = Vec::new();
        write(&mut out, &mesh).unwrap();
        let file = read(&out).unwrap();
        assert_eq!(
            file.array("a \"quoted\" <name>").unwrap(),
            values.map(single)
        );
        assert_ne!(single(1.0 / 3.0), 1.0 / 3.0);
        assert_eq!(
            file.array("Points").unwrap()[9..],
            [1.0 / 3.0, f64::MIN_POSITIVE, 0.0]
        );
    }

    #[test]
    fn a_truncated_or_corrupt_file_is_an_error() {
        let mut out = Vec::new();
        write(&mut out, &square()).unwrap();
        let e = read(&out[..out.len() - 60]).unwrap_err();
        assert!(e.to_string().contains("runs past the end"), "{e}");
        let data = out
            .windows(2)
            .position(|w| w == b"\n_")
            .expect("appended data")
            + 2;
        // A block count near 2⁶⁴ is an error, not an overflow.
        let mut huge = out.clone();
        huge[data..data + 8].copy_from_slice(&(u64::MAX - 3).to_le_bytes());
        assert!(read(&huge).is_err());
        // A block that does not inflate.
        let mut broken = out.clone();
        broken[data + 32] ^= 0xff;
        broken[data + 33] ^= 0xff;
        let e = read(&broken).unwrap_err();
        assert!(e.to_string().contains("displacement"), "{e}");
        assert!(read(b"<VTKFile>").is_err());
    }

    #[test]
    fn a_collection_lists_its_files_with_their_times() {
        let dir = std::env::temp_dir().join(format!("tribo-pvd-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("T.pvd");
        let files = vec![("T.cycle-0.vtu".to_string(), 0), ("T.vtu".to_string(), 3)];
        write_collection(&path, &files).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains("<VTKFile type=\"Collection\""));
        assert_eq!(read_collection(&text).unwrap(), files);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
