//! VTK output for ParaView: `.vtu` unstructured grids (vtkio, XML, LZ4-compressed binary) and
//! `.pvd` collections for time series.
//!
//! LZ4 rather than zlib: vtkio feeds its zlib encoder one value at a time, and flate2 clears a
//! 32 KiB output buffer on every call, so zlib made writing a 73k-particle case take 0.7 s; LZ4
//! blocks are compressed whole (0.05 s, files about 25 % larger than zlib level 1). VTK reads
//! them with `vtkLZ4DataCompressor` (VTK 8.1 and later, ParaView 5.5 and later).
//!
//! Every file is written to a temporary name beside its target and renamed when complete, so
//! an interrupted run never leaves a truncated file under the real name.

use std::io::Write;
use std::path::{Path, PathBuf};

use nalgebra::Matrix3;
use rayon::prelude::*;
use vtkio::model::{Attribute, ByteOrder, CellType, DataArray, IOBuffer};
use vtkio::xml::{self, Compressor};

use crate::error::{Error, Result};
use crate::math::Vec3;

/// One named data array.
#[derive(Clone, Debug)]
pub enum Field {
    /// Real scalars.
    Scalar(String, Vec<f64>),
    /// Real 3-vectors.
    Vector(String, Vec<Vec3>),
    /// Real 3×3 tensors (ParaView reads the nine components row by row).
    Tensor(String, Vec<Matrix3<f64>>),
    /// Small integers (flags, body numbers).
    Int(String, Vec<i32>),
    /// Large integers (node ids).
    Id(String, Vec<i64>),
}

impl Field {
    /// A scalar field.
    pub fn scalar(name: &str, data: Vec<f64>) -> Field {
        Field::Scalar(name.to_string(), data)
    }
    /// A vector field.
    pub fn vector(name: &str, data: Vec<Vec3>) -> Field {
        Field::Vector(name.to_string(), data)
    }
    /// A tensor field.
    pub fn tensor(name: &str, data: Vec<Matrix3<f64>>) -> Field {
        Field::Tensor(name.to_string(), data)
    }
    /// A 0/1 flag field.
    pub fn flag(name: &str, data: &[bool]) -> Field {
        Field::Int(name.to_string(), data.iter().map(|&b| b as i32).collect())
    }
    /// An integer field.
    pub fn int(name: &str, data: Vec<i32>) -> Field {
        Field::Int(name.to_string(), data)
    }
    /// An id field.
    pub fn id(name: &str, data: Vec<i64>) -> Field {
        Field::Id(name.to_string(), data)
    }

    /// Name, VTK type and components of the array this field is written as.
    pub fn layout(&self) -> (String, &'static str, usize) {
        match self {
            Field::Scalar(n, _) => (n.clone(), "Float64", 1),
            Field::Vector(n, _) => (n.clone(), "Float64", 3),
            Field::Tensor(n, _) => (n.clone(), "Float64", 9),
            Field::Int(n, _) => (n.clone(), "Int32", 1),
            Field::Id(n, _) => (n.clone(), "Int64", 1),
        }
    }

    fn into_attribute(self) -> Attribute {
        match self {
            Field::Scalar(n, d) => Attribute::DataArray(DataArray::scalars(n, 1).with_data(d)),
            Field::Vector(n, d) => {
                let flat: Vec<f64> = d.iter().flat_map(|v| [v.x, v.y, v.z]).collect();
                Attribute::DataArray(DataArray::vectors(n).with_data(flat))
            }
            Field::Tensor(n, d) => {
                // Row by row: nalgebra stores columns, so the transpose's columns.
                let mut flat = Vec::with_capacity(9 * d.len());
                for t in &d {
                    flat.extend_from_slice(t.transpose().as_slice());
                }
                Attribute::DataArray(DataArray::tensors(n).with_data(flat))
            }
            Field::Int(n, d) => Attribute::DataArray(DataArray::scalars(n, 1).with_data(d)),
            Field::Id(n, d) => Attribute::DataArray(DataArray::scalars(n, 1).with_data(d)),
        }
    }
}

/// The cells of a grid.
#[derive(Clone, Debug)]
pub enum CellSpec {
    /// One vertex cell per point (a particle cloud).
    Vertices,
    /// Quads given as 4 point indices; `[a, b, c, c]` is written as a triangle.
    Quads(Vec<[u32; 4]>),
}

/// Writes an unstructured grid to `path` (atomically).
pub fn write_vtu(
    path: &Path,
    points: &[Vec3],
    cells: CellSpec,
    point_data: Vec<Field>,
    cell_data: Vec<Field>,
) -> Result<()> {
    write_vtu_with_field_data(path, points, cells, point_data, cell_data, &[])
}

/// Writes an unstructured grid to `path` (atomically), with one-value `Float64` arrays in the
/// grid's `<FieldData>` (values of the whole dataset: time, load factor, step).
///
/// The file is vtkio's, written one array at a time: each array is encoded by vtkio
/// (`DataArray::from_io_buffer`: LZ4 blocks, base64) and serialized by it, and the elements
/// around the arrays are written here as vtkio writes them (`tests`: the same bytes). Whole,
/// vtkio's serializer holds the text of every array several times over (each nested element
/// gathers its children's text before its own tag is closed): 800 bytes a particle, 800 MB
/// at the moment a run of a million particles writes its frame.
pub fn write_vtu_with_field_data(
    path: &Path,
    points: &[Vec3],
    cells: CellSpec,
    point_data: Vec<Field>,
    cell_data: Vec<Field>,
    field_data: &[(&str, f64)],
) -> Result<()> {
    write_atomically(path, |w| {
        stream_vtu(w, points, cells, point_data, cell_data, field_data)
            .map_err(|e| std::io::Error::other(e.to_string()))
    })
}

/// vtkio's encoding of the arrays: LZ4 (any level but 0, which vtkio takes to mean
/// "uncompressed"; LZ4 has no levels here), 64-bit headers, little-endian.
const ENCODING: xml::EncodingInfo = xml::EncodingInfo {
    byte_order: ByteOrder::LittleEndian,
    header_type: xml::ScalarType::UInt64,
    compressor: Compressor::LZ4,
    compression_level: 1,
};

/// [`write_vtu_with_field_data`]'s text, to `w`.
fn stream_vtu(
    w: &mut impl Write,
    points: &[Vec3],
    cells: CellSpec,
    point_data: Vec<Field>,
    cell_data: Vec<Field>,
    field_data: &[(&str, f64)],
) -> std::result::Result<(), Box<dyn std::error::Error>> {
    let (connectivity, offsets, types) = cell_arrays(points.len(), cells);
    w.write_all(b"<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\" compressor=\"vtkLZ4DataCompressor\"><UnstructuredGrid>")?;
    // vtkio writes no `<FieldData>`: it goes in front of the first `<Piece`, where VTK's XML
    // readers look for it (arrays are base64 text, so the file is text throughout).
    if !field_data.is_empty() {
        w.write_all(b"<FieldData>")?;
        for (name, value) in field_data {
            write!(
                w,
                "<DataArray type=\"Float64\" Name=\"{}\" NumberOfTuples=\"1\" format=\"ascii\">{value:.17e}</DataArray>",
                xml_escape(name)
            )?;
        }
        w.write_all(b"</FieldData>")?;
    }
    // vtkio leaves out a count of zero.
    w.write_all(b"<Piece")?;
    for (name, count) in [
        ("NumberOfPoints", points.len()),
        ("NumberOfCells", types.len()),
    ] {
        if count > 0 {
            write!(w, " {name}=\"{}\"", u32::try_from(count)?)?;
        }
    }
    w.write_all(b">")?;
    // The arrays compressed and encoded on the pool's threads, written in order: a frame's
    // arrays one after the other took 6-13 ms (15,625 particles).
    let coords: Vec<f64> = points.iter().flat_map(|p| [p.x, p.y, p.z]).collect();
    let cell_arrays = vec![
        ("connectivity", IOBuffer::U64(connectivity)),
        ("offsets", IOBuffer::U64(offsets)),
        (
            "types",
            IOBuffer::U8(types.into_iter().map(|t| t as u8).collect()),
        ),
    ];
    let ((point_text, cell_text), (points_text, cells_text)) = rayon::join(
        || {
            rayon::join(
                || attributes_text("PointData", point_data),
                || attributes_text("CellData", cell_data),
            )
        },
        || {
            rayon::join(
                || {
                    encoded(|t| {
                        let buffer = IOBuffer::F64(coords);
                        let array = xml::DataArray::from_io_buffer(buffer, ENCODING)?;
                        t.extend_from_slice(b"<Points>");
                        array_text(t, array.with_num_comp(3).with_name("Points"))?;
                        t.extend_from_slice(b"</Points>");
                        Ok(())
                    })
                },
                || {
                    cell_arrays
                        .into_par_iter()
                        .map(|(name, buffer)| {
                            encoded(|t| {
                                let array = xml::DataArray::from_io_buffer(buffer, ENCODING)?;
                                array_text(t, array.with_name(name))
                            })
                        })
                        .collect::<std::result::Result<Vec<_>, String>>()
                },
            )
        },
    );
    w.write_all(&point_text?)?;
    w.write_all(&cell_text?)?;
    w.write_all(&points_text?)?;
    w.write_all(b"<Cells>")?;
    for text in cells_text? {
        w.write_all(&text)?;
    }
    w.write_all(b"</Cells></Piece></UnstructuredGrid></VTKFile>")?;
    Ok(())
}

/// An encoded array's element as vtkio's serializer writes it, to `t`: vtkio serializes the
/// element around a stand-in, and the base64 text goes in its place as it is (the serializer
/// escapes text, and base64 holds nothing to escape; scanning it cost more than compressing
/// the array).
fn array_text(
    t: &mut Vec<u8>,
    mut array: xml::DataArray,
) -> std::result::Result<(), Box<dyn std::error::Error>> {
    const STAND_IN: &str = "STAND-IN";
    let text = match array.data.as_mut_slice() {
        [xml::Data::Data(text)] => std::mem::take(text),
        _ => return Err("an encoded array is one run of text".into()),
    };
    debug_assert!(!text.contains(['&', '<', '>', '"', '\'']));
    array.data = vec![xml::Data::Data(STAND_IN.into())];
    let mut shell = Vec::new();
    xml::se::to_writer(&mut shell, &array)?;
    let at = shell
        .windows(STAND_IN.len())
        .rposition(|w| w == STAND_IN.as_bytes())
        .ok_or("vtkio wrote no array text")?;
    t.extend_from_slice(&shell[..at]);
    t.extend_from_slice(text.as_bytes());
    t.extend_from_slice(&shell[at + STAND_IN.len()..]);
    Ok(())
}

/// The text that `write` puts out, or its error in words (to cross threads).
fn encoded(
    write: impl FnOnce(&mut Vec<u8>) -> std::result::Result<(), Box<dyn std::error::Error>>,
) -> std::result::Result<Vec<u8>, String> {
    let mut text = Vec::new();
    write(&mut text).map_err(|e| e.to_string())?;
    Ok(text)
}

/// A `<PointData>` or `<CellData>` element as vtkio writes it: the first array of each kind
/// named the active one, then the arrays, each compressed and encoded on its own thread.
fn attributes_text(tag: &str, fields: Vec<Field>) -> std::result::Result<Vec<u8>, String> {
    if fields.is_empty() {
        return Ok(Vec::new());
    }
    let mut w = format!("<{tag}");
    // vtkio's order of the attributes (Scalars, Vectors, Tensors), each its first such array.
    for (kind, is) in [
        (
            "Scalars",
            (|f: &Field| matches!(f, Field::Scalar(..) | Field::Int(..) | Field::Id(..)))
                as fn(&Field) -> bool,
        ),
        ("Vectors", |f: &Field| matches!(f, Field::Vector(..))),
        ("Tensors", |f: &Field| matches!(f, Field::Tensor(..))),
    ] {
        if let Some(f) = fields.iter().find(|f| is(f)) {
            w.push_str(&format!(" {kind}=\"{}\"", xml_escape(&f.layout().0)));
        }
    }
    w.push('>');
    let arrays = fields
        .into_par_iter()
        .map(|f| {
            encoded(|t| {
                if let Attribute::DataArray(data) = f.into_attribute() {
                    let array = xml::DataArray::from_model_data_array(data, ENCODING)?;
                    array_text(t, array)?;
                }
                Ok(())
            })
        })
        .collect::<std::result::Result<Vec<_>, String>>()?;
    let mut text = w.into_bytes();
    for a in arrays {
        text.extend(a);
    }
    text.extend(format!("</{tag}>").into_bytes());
    Ok(text)
}

/// The connectivity, offsets and cell types of `cells` over `n` points.
fn cell_arrays(n: usize, cells: CellSpec) -> (Vec<u64>, Vec<u64>, Vec<CellType>) {
    match cells {
        CellSpec::Vertices => (
            (0..n as u64).collect(),
            (1..=n as u64).collect(),
            vec![CellType::Vertex; n],
        ),
        CellSpec::Quads(quads) => {
            let mut conn = Vec::with_capacity(4 * quads.len());
            let mut offs = Vec::with_capacity(quads.len());
            let mut types = Vec::with_capacity(quads.len());
            for q in &quads {
                if q[2] == q[3] {
                    conn.extend(q[..3].iter().map(|&i| i as u64));
                    types.push(CellType::Triangle);
                } else {
                    conn.extend(q.iter().map(|&i| i as u64));
                    types.push(CellType::Quad);
                }
                offs.push(conn.len() as u64);
            }
            (conn, offs, types)
        }
    }
}

/// A node of a `.vtm` multiblock: a named block of nodes, or a named dataset file.
/// Writes a `.pvtu`: the unstructured grid made of the `.vtu` `pieces` (paths relative to
/// it), each written by [`write_vtu_with_field_data`] with point data of the `arrays`
/// ([`Field::layout`]: name, VTK type, components; the values are in the pieces). ParaView
/// and VTK's `vtkXMLPUnstructuredGridReader` read it as one dataset.
pub fn write_pvtu(path: &Path, pieces: &[String], arrays: &[(String, &str, usize)]) -> Result<()> {
    let mut s = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <PUnstructuredGrid GhostLevel=\"0\">\n    <PPointData>\n",
    );
    for (name, kind, components) in arrays {
        s.push_str(&format!(
            "      <PDataArray type=\"{kind}\" Name=\"{}\" NumberOfComponents=\"{components}\"/>\n",
            xml_escape(name)
        ));
    }
    s.push_str("    </PPointData>\n    <PPoints>\n      <PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>\n    </PPoints>\n");
    for p in pieces {
        s.push_str(&format!("    <Piece Source=\"{}\"/>\n", xml_escape(p)));
    }
    s.push_str("  </PUnstructuredGrid>\n</VTKFile>\n");
    write_atomically(path, |w| w.write_all(s.as_bytes()))
}

#[derive(Clone, Debug)]
pub enum BlockNode {
    /// A named block holding other nodes.
    Block(String, Vec<BlockNode>),
    /// A named dataset stored in `file` (relative to the `.vtm`).
    DataSet(String, String),
    /// A named dataset in pieces (files relative to the `.vtm`), one per rank of a decomposed
    /// run: VTK reads it as a `vtkMultiPieceDataSet`, ParaView shows it as one block.
    Pieces(String, Vec<String>),
}

/// Writes a `.vtm` multiblock file (atomically); ParaView shows the names in its Multiblock
/// Inspector and selects blocks by their paths (`/Root/ball/surface`).
pub fn write_vtm(path: &Path, nodes: &[BlockNode]) -> Result<()> {
    fn put(s: &mut String, nodes: &[BlockNode], depth: usize) {
        let pad = "  ".repeat(depth);
        for (k, n) in nodes.iter().enumerate() {
            match n {
                BlockNode::Block(name, children) => {
                    s.push_str(&format!(
                        "{pad}<Block index=\"{k}\" name=\"{}\">\n",
                        xml_escape(name)
                    ));
                    put(s, children, depth + 1);
                    s.push_str(&format!("{pad}</Block>\n"));
                }
                BlockNode::DataSet(name, file) => s.push_str(&format!(
                    "{pad}<DataSet index=\"{k}\" name=\"{}\" file=\"{}\"/>\n",
                    xml_escape(name),
                    xml_escape(file)
                )),
                BlockNode::Pieces(name, files) => {
                    s.push_str(&format!(
                        "{pad}<Piece index=\"{k}\" name=\"{}\">\n",
                        xml_escape(name)
                    ));
                    for (q, file) in files.iter().enumerate() {
                        s.push_str(&format!(
                            "{pad}  <DataSet index=\"{q}\" file=\"{}\"/>\n",
                            xml_escape(file)
                        ));
                    }
                    s.push_str(&format!("{pad}</Piece>\n"));
                }
            }
        }
    }
    let mut s = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"vtkMultiBlockDataSet\" version=\"1.0\" byte_order=\"LittleEndian\">\n  <vtkMultiBlockDataSet>\n",
    );
    put(&mut s, nodes, 2);
    s.push_str("  </vtkMultiBlockDataSet>\n</VTKFile>\n");
    write_atomically(path, |w| w.write_all(s.as_bytes()))
}

/// A `.pvd` collection: one entry per time step.
#[derive(Clone, Debug, Default)]
pub struct PvdCollection {
    entries: Vec<(f64, String)>,
}

impl PvdCollection {
    /// Adds a file (relative to the `.pvd`) at time `t`: one dataset per time step (a frame's
    /// bodies are the blocks of its `.vtm`).
    pub fn push(&mut self, t: f64, file: impl Into<String>) {
        self.entries.push((t, file.into()));
    }

    /// Number of entries.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// True when empty.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Writes the collection (atomically), so that ParaView opens it as a time series.
    pub fn write(&self, path: &Path) -> Result<()> {
        let mut s = String::from(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n",
        );
        for (t, f) in &self.entries {
            s.push_str(&format!(
                "    <DataSet timestep=\"{t:.9e}\" group=\"\" part=\"0\" file=\"{}\"/>\n",
                xml_escape(f)
            ));
        }
        s.push_str("  </Collection>\n</VTKFile>\n");
        write_atomically(path, |w| w.write_all(s.as_bytes()))
    }
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('"', "&quot;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Writes a file through `write` to a temporary name in the same folder, then renames it.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut std::io::BufWriter<std::fs::File>) -> std::io::Result<()>,
) -> Result<()> {
    let tmp = temporary_name(path);
    let result = (|| {
        let file = std::fs::File::create(&tmp)?;
        let mut w = std::io::BufWriter::new(file);
        write(&mut w)?;
        w.flush()?;
        drop(w);
        std::fs::rename(&tmp, path)
    })();
    result.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        Error::output(path, e)
    })
}

/// Writes `text` to `path` as [`write_atomically`] does; where `path` already holds something
/// else (a scene the user edited), that is first renamed to `NAME.edited` (or `NAME.edited.N`,
/// the first name free), never lost. Returns the name it was kept under.
pub fn write_keeping_edits(path: &Path, text: &str) -> Result<Option<PathBuf>> {
    let kept = match std::fs::read(path) {
        Ok(old) if old != text.as_bytes() => {
            let name = path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            let free = (0..)
                .map(|k| match k {
                    0 => path.with_file_name(format!("{name}.edited")),
                    k => path.with_file_name(format!("{name}.edited.{k}")),
                })
                .find(|p| !p.exists())
                .expect("some name is free");
            std::fs::rename(path, &free).map_err(|e| Error::output(&free, e))?;
            Some(free)
        }
        _ => None,
    };
    write_atomically(path, |w| w.write_all(text.as_bytes()))?;
    Ok(kept)
}

fn temporary_name(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.partial"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use vtkio::model::{DataSet, Vtk};

    /// What vtkio writes of the grid as one document (its model, converted and serialized
    /// whole), with the field data put in front of `<Piece`.
    fn vtkio_whole(
        points: &[Vec3],
        cells: CellSpec,
        point_data: Vec<Field>,
        cell_data: Vec<Field>,
        field_data: &[(&str, f64)],
    ) -> Vec<u8> {
        use vtkio::model::{Attributes, Cells, UnstructuredGridPiece, Version, VertexNumbers};
        let (connectivity, offsets, types) = cell_arrays(points.len(), cells);
        let piece = UnstructuredGridPiece {
            points: IOBuffer::F64(points.iter().flat_map(|p| [p.x, p.y, p.z]).collect()),
            cells: Cells {
                cell_verts: VertexNumbers::XML {
                    connectivity,
                    offsets,
                },
                types,
            },
            data: Attributes {
                point: point_data.into_iter().map(Field::into_attribute).collect(),
                cell: cell_data.into_iter().map(Field::into_attribute).collect(),
            },
        };
        let vtk = Vtk {
            version: Version::new_xml(1, 0),
            byte_order: ByteOrder::LittleEndian,
            title: String::new(),
            file_path: None,
            data: DataSet::inline(piece),
        };
        let mut text = Vec::new();
        vtk.try_into_xml_format(Compressor::LZ4, 1)
            .expect("vtkio model")
            .write(&mut text)
            .expect("vtkio text");
        let mut block = Vec::new();
        stream_vtu(
            &mut block,
            &[],
            CellSpec::Vertices,
            vec![],
            vec![],
            field_data,
        )
        .expect("field data");
        let block = String::from_utf8(block).expect("utf8");
        let to = block.find("<Piece").expect("piece");
        let from = block.find("<FieldData>").unwrap_or(to);
        let at = text.windows(6).position(|w| w == b"<Piece").expect("piece");
        let mut out = text[..at].to_vec();
        out.extend_from_slice(&block.as_bytes()[from..to]);
        out.extend_from_slice(&text[at..]);
        out
    }

    #[test]
    fn streams_the_bytes_vtkio_writes_whole() {
        let points: Vec<Vec3> = (0..300)
            .map(|i| Vec3::new(i as f64 * 0.1, (i % 7) as f64, -(i as f64).sqrt()))
            .collect();
        let fields = || {
            vec![
                Field::vector("displacement", points.iter().map(|p| p * 1e-3).collect()),
                Field::scalar("pressure <Pa>", points.iter().map(|p| p.x * 2.0).collect()),
                Field::tensor(
                    "stress",
                    points.iter().map(Matrix3::from_diagonal).collect(),
                ),
                Field::flag(
                    "surface",
                    &points.iter().map(|p| p.y > 3.0).collect::<Vec<_>>(),
                ),
                Field::Id("node".into(), (0..points.len() as i64).collect()),
                Field::vector("force", points.iter().map(|p| -p).collect()),
            ]
        };
        let quads: Vec<[u32; 4]> = (0..50)
            .map(|i| [i, i + 1, i + 2, i + 2 + (i % 2)])
            .collect();
        let cell = || vec![Field::scalar("area", (0..50).map(f64::from).collect())];
        let field_data = [("load_factor", 0.25), ("iteration", 17.0)];
        type Case<'a> = (
            &'a [Vec3],
            CellSpec,
            Vec<Field>,
            Vec<Field>,
            &'a [(&'a str, f64)],
        );
        let cases: Vec<Case> = vec![
            (&points, CellSpec::Vertices, fields(), vec![], &field_data),
            (&points, CellSpec::Vertices, fields(), vec![], &[]),
            (
                &points,
                CellSpec::Quads(quads.clone()),
                vec![],
                cell(),
                &field_data,
            ),
            (&points, CellSpec::Quads(quads), fields(), cell(), &[]),
            (&[], CellSpec::Vertices, vec![], vec![], &field_data),
        ];
        for (k, (p, c, pd, cd, fd)) in cases.into_iter().enumerate() {
            let mut streamed = Vec::new();
            stream_vtu(&mut streamed, p, c.clone(), pd.clone(), cd.clone(), fd).expect("stream");
            let whole = vtkio_whole(p, c, pd, cd, fd);
            assert!(
                streamed == whole,
                "case {k}:\n{}\n{}",
                String::from_utf8_lossy(&streamed[..streamed.len().min(600)]),
                String::from_utf8_lossy(&whole[..whole.len().min(600)])
            );
        }
    }

    #[test]
    fn writes_and_reads_back() {
        let dir = std::env::temp_dir().join(format!("pdcontact-vtk-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let path = dir.join("p.vtu");
        let pts = vec![
            Vec3::zeros(),
            Vec3::x(),
            Vec3::y(),
            Vec3::new(1.0, 1.0, 0.0),
        ];
        write_vtu(
            &path,
            &pts,
            CellSpec::Quads(vec![[0, 1, 3, 2], [0, 1, 2, 2]]),
            vec![Field::scalar("volume", vec![1.0, 2.0, 3.0, 4.0])],
            vec![Field::scalar("area", vec![1.0, 0.5])],
        )
        .expect("written");
        let back = Vtk::import(&path).expect("vtkio reads its own file");
        let DataSet::UnstructuredGrid { pieces, .. } = back.data else {
            panic!("not an unstructured grid");
        };
        assert_eq!(pieces.len(), 1);
        assert!(!dir.join(".p.vtu.partial").exists());
        std::fs::remove_dir_all(&dir).ok();
    }
}
