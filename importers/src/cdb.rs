//! Reader for this format (to be written).

use std::path::Path;

use crate::error::ImportError;
use crate::mesh::Mesh;

/// Reads a file of this format.
pub fn read(path: &Path, _data: &[u8]) -> Result<Mesh, ImportError> {
    Err(ImportError::whole_file(
        path,
        "a supported format",
        "a reader not written yet",
    ))
}
