//! What every fuzz target checks: the reader returns (no panic, no hang, no huge allocation;
//! libFuzzer's -timeout and -malloc_limit_mb catch the last two), an error names a line or byte
//! and reads "expected X, found Y" in at most 280 characters after the file name, and a mesh
//! that is read is consistent (indices in range, finite coordinates) and goes through the face
//! finder.

use std::path::Path;

use pdcontact_importers::{boundary_faces, Format, Location, MeshSummary, MISSING_NODE};

/// Whole-file errors that make sense: nothing to read in the file at all.
const WHOLE_FILE_OK: [&str; 2] = [
    "an ANSYS archive with nodes (an NBLOCK)",
    "an Abaqus deck with *NODE data",
];

pub fn check(format: Format, data: &[u8]) {
    // A folder that does not exist: relative *INCLUDE targets of a fuzzed deck read nothing.
    let name = match format {
        Format::Cdb => "/nonexistent-fuzz/f.cdb",
        Format::Msh => "/nonexistent-fuzz/f.msh",
        Format::Inp => "/nonexistent-fuzz/f.inp",
    };
    match pdcontact_importers::read_format(Path::new(name), data, format) {
        Err(e) => {
            let s = e.to_string();
            assert!(s.contains("expected ") && s.contains(", found "), "{s}");
            let after_name = s.chars().count() - name.len();
            assert!(
                after_name <= 280,
                "{after_name} characters after the name: {s}"
            );
            if e.location == Location::File {
                assert!(
                    WHOLE_FILE_OK.contains(&e.expected.as_str()),
                    "no location: {s}"
                );
            }
        }
        Ok(mesh) => {
            let n = mesh.node_count();
            assert_eq!(mesh.node_ids.len(), n);
            assert!(mesh.coords.iter().flatten().all(|v| v.is_finite()));
            for el in mesh.elements() {
                for &v in el.nodes {
                    assert!(
                        v == MISSING_NODE || (v as usize) < n,
                        "node index {v} of {n}"
                    );
                }
            }
            for set in &mesh.sets {
                for &v in set.nodes.iter().flatten() {
                    assert!((v as usize) < n);
                }
                for &e in set.elements.iter().flatten() {
                    assert!((e as usize) < mesh.element_count());
                }
            }
            let _ = boundary_faces(&mesh);
            let _ = MeshSummary::of(&mesh, format);
        }
    }
}
