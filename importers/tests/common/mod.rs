//! Shared by the malformed-input tests: running one read with a time limit and a panic guard,
//! and checking that a failure is a clear, located error.

#![allow(dead_code)]

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use pdcontact_importers::{boundary_faces, Format, ImportError, Location, Mesh, MISSING_NODE};

/// Time one read may take.
pub const LIMIT: Duration = Duration::from_secs(5);

/// Longest message after the file name (and its colon), in characters.
pub const MAX_MESSAGE: usize = 280;

/// The only errors that may name no line or byte: files that hold nothing to read at all.
pub const WHOLE_FILE_OK: [&str; 2] = [
    "an ANSYS archive with nodes (an NBLOCK)",
    "an Abaqus deck with *NODE data",
];

/// What became of one read.
pub enum Outcome {
    Ok(Box<Mesh>),
    Err(ImportError),
    Panic(String),
    Hang,
}

/// Reads `data` as `format` in a thread, with a panic guard and the time limit [`LIMIT`].
/// Returns the outcome and the time taken.
pub fn read_guarded(path: &Path, data: Vec<u8>, format: Format) -> (Outcome, Duration) {
    let (tx, rx) = mpsc::channel();
    let path = path.to_path_buf();
    let start = Instant::now();
    std::thread::spawn(move || {
        let r = catch_unwind(AssertUnwindSafe(|| {
            pdcontact_importers::read_format(&path, &data, format)
        }));
        let _ = tx.send(r);
    });
    let outcome = match rx.recv_timeout(LIMIT) {
        Ok(Ok(Ok(mesh))) => Outcome::Ok(Box::new(mesh)),
        Ok(Ok(Err(e))) => Outcome::Err(e),
        Ok(Err(p)) => Outcome::Panic(
            p.downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "a panic".to_string()),
        ),
        Err(_) => Outcome::Hang,
    };
    (outcome, start.elapsed())
}

/// Why an error is not a clear one, or `None` when it is: "expected X, found Y", a line or
/// byte location inside the input (no location only for the [`WHOLE_FILE_OK`] errors), and at
/// most [`MAX_MESSAGE`] characters after the file name.
pub fn unclear(e: &ImportError, data: &[u8]) -> Option<String> {
    let s = e.to_string();
    if !s.contains("expected ") || !s.contains(", found ") {
        return Some(format!("no 'expected ..., found ...': {s}"));
    }
    if e.expected.trim().is_empty() || e.found.trim().is_empty() {
        return Some(format!("an empty half: {s}"));
    }
    let path_len = e.path.display().to_string().chars().count();
    let len = s.chars().count() - path_len;
    if len > MAX_MESSAGE {
        return Some(format!("{len} characters after the file name: {s}"));
    }
    match e.location {
        Location::Line(n) => {
            let lines = data.iter().filter(|&&b| b == b'\n').count() + 1;
            if n == 0 || n > lines + 1 {
                return Some(format!("line {n} outside the {lines} lines: {s}"));
            }
        }
        Location::Byte(o) => {
            if o > data.len() as u64 {
                return Some(format!("byte {o} past the {} bytes: {s}", data.len()));
            }
        }
        Location::File => {
            if !WHOLE_FILE_OK.contains(&e.expected.as_str()) {
                return Some(format!("no line or byte: {s}"));
            }
        }
    }
    None
}

/// Why a mesh that was read is inconsistent, or `None`; also runs the face finder on it.
pub fn inconsistent(mesh: &Mesh) -> Option<String> {
    let n = mesh.node_count();
    if mesh.node_ids.len() != n {
        return Some(format!("{} ids for {n} nodes", mesh.node_ids.len()));
    }
    if !mesh.coords.iter().flatten().all(|v| v.is_finite()) {
        return Some("a coordinate that is not finite".to_string());
    }
    for el in mesh.elements() {
        if let Some(&v) = el
            .nodes
            .iter()
            .find(|&&v| v != MISSING_NODE && v as usize >= n)
        {
            return Some(format!("element {} uses node index {v} of {n}", el.id));
        }
    }
    for set in &mesh.sets {
        if set.nodes.iter().flatten().any(|&v| v as usize >= n)
            || set
                .elements
                .iter()
                .flatten()
                .any(|&e| e as usize >= mesh.element_count())
        {
            return Some(format!(
                "set {} names a node or element out of range",
                set.name
            ));
        }
    }
    let _ = boundary_faces(mesh);
    None
}

/// The workspace root (this crate is `importers/` in it).
pub fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("the importers crate sits in the workspace")
        .to_path_buf()
}

/// The shared compatibility corpus beside the workspace, if present.
pub fn shared_corpus() -> Option<PathBuf> {
    let p = workspace().join("../shared/corpus");
    p.join("manifest.json").is_file().then_some(p)
}
