//! Readers for ANSYS CDB, Gmsh MSH and Abaqus INP meshes, producing one [`Mesh`] type.
//!
//! This crate knows nothing of peridynamics: it reads nodes, typed elements and named sets,
//! normalises node order to one convention (see [`mesh`]), and finds boundary faces
//! ([`faces`]). A file that cannot be read gives an [`ImportError`] naming the file, the line (or
//! byte offset in binary sections), what was expected and what was found.
//!
//! ```no_run
//! let mesh = pdcontact_importers::read_path(std::path::Path::new("part.msh"), None)?;
//! println!("{} nodes, {} solids", mesh.node_count(), mesh.solids().count());
//! # Ok::<(), pdcontact_importers::ImportError>(())
//! ```

pub mod cdb;
pub mod error;
pub mod faces;
pub mod inp;
pub mod mesh;
pub mod msh;
pub mod quality;
pub mod refine;
pub mod split;
pub mod summary;
mod text;

use std::path::Path;

pub use error::{describe_found, ImportError, Location};
pub use faces::{boundary_faces, face_corners, BoundaryFace, FaceSet};
pub use mesh::{ElementKind, ElementRef, Format, Mesh, NamedSet, NodeIndex, SetKind, MISSING_NODE};
pub use quality::{is_pieces_warning, quality_warnings, solid_pieces, NO_PIECE};
pub use refine::{refine_uniform, RefineRefusal};
pub use split::{has_splittable, split_second_order};
pub use summary::MeshSummary;

/// Reads a mesh file. The format is `format` if given, else guessed from the extension and the
/// first bytes of the file ([`detect_format`]).
pub fn read_path(path: &Path, format: Option<Format>) -> Result<Mesh, ImportError> {
    let data = std::fs::read(path)
        .map_err(|e| ImportError::whole_file(path, "a readable file", e.to_string()))?;
    read_bytes(path, &data, format)
}

/// Reads a mesh from bytes already in memory; `path` names the file in errors and anchors
/// relative `*INCLUDE` files of Abaqus decks.
pub fn read_bytes(path: &Path, data: &[u8], format: Option<Format>) -> Result<Mesh, ImportError> {
    let format = match format {
        Some(f) => f,
        None => detect_format(path, data)?,
    };
    read_format(path, data, format)
}

/// Reads bytes as the given format; the mesh's warnings end with those of the quality checks
/// ([`quality_warnings`]: unused nodes, duplicate nodes, disconnected pieces).
pub fn read_format(path: &Path, data: &[u8], format: Format) -> Result<Mesh, ImportError> {
    let mut mesh = match format {
        Format::Cdb => cdb::read(path, data),
        Format::Msh => msh::read(path, data),
        Format::Inp => inp::read(path, data),
    }?;
    let quality = quality_warnings(&mesh);
    mesh.warnings.extend(quality);
    mesh.shrink_to_fit();
    Ok(mesh)
}

/// Guesses the format: content first where it is unambiguous (`$MeshFormat` for Gmsh, `*NODE`
/// or `*HEADING` for Abaqus, `NBLOCK`/`/PREP7` for ANSYS), else the extension. Workbench writes
/// APDL solver input with `.inp` and `.dat` extensions, so content wins over the extension.
pub fn detect_format(path: &Path, data: &[u8]) -> Result<Format, ImportError> {
    if let Some(f) = sniff(data) {
        return Ok(f);
    }
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase());
    match ext.as_deref() {
        Some("msh") => Ok(Format::Msh),
        Some("cdb") | Some("dat") | Some("ans") => Ok(Format::Cdb),
        Some("inp") | Some("inc") => Ok(Format::Inp),
        _ => Err(ImportError::whole_file(
            path,
            "a Gmsh (.msh), ANSYS (.cdb, .dat) or Abaqus (.inp) mesh; use --format to say which",
            match ext {
                Some(e) => format!("extension '.{e}' and no recognisable content"),
                None => "no extension and no recognisable content".to_string(),
            },
        )),
    }
}

/// Looks at the first 64 KiB for a format's signature.
fn sniff(data: &[u8]) -> Option<Format> {
    let head = &data[..data.len().min(65536)];
    let mut abaqus = false;
    let mut ansys = false;
    for raw in head.split(|&b| b == b'\n') {
        let line = raw.trim_ascii_start();
        if line.starts_with(b"$MeshFormat") {
            return Some(Format::Msh);
        }
        let upper: Vec<u8> = line
            .iter()
            .take(12)
            .map(|b| b.to_ascii_uppercase())
            .collect();
        if upper.starts_with(b"*NODE")
            || upper.starts_with(b"*HEADING")
            || upper.starts_with(b"*ELEMENT")
            || upper.starts_with(b"*PART")
            || upper.starts_with(b"*INCLUDE")
        {
            abaqus = true;
        }
        if upper.starts_with(b"NBLOCK")
            || upper.starts_with(b"EBLOCK")
            || upper.starts_with(b"/PREP7")
            || upper.starts_with(b"/COM")
            || upper.starts_with(b"ET,")
            || upper.starts_with(b"ETBLOCK")
            || upper.starts_with(b"/BATCH")
        {
            ansys = true;
        }
    }
    match (abaqus, ansys) {
        (true, false) => Some(Format::Inp),
        (false, true) => Some(Format::Cdb),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sniffing() {
        let p = Path::new("x.inp");
        assert_eq!(
            detect_format(p, b"/batch\n/prep7\nnblock,3\n").ok(),
            Some(Format::Cdb)
        );
        assert_eq!(
            detect_format(Path::new("x.dat"), b"** c\n*Node\n1,0,0,0\n").ok(),
            Some(Format::Inp)
        );
        assert_eq!(
            detect_format(Path::new("x"), b"$MeshFormat\n4.1 0 8\n").ok(),
            Some(Format::Msh)
        );
        assert!(detect_format(Path::new("x.txt"), b"hello").is_err());
    }
}
