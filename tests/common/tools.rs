//! The tools the integration tests check against (Python's vtk), shared with the
//! `pdcontact-mpi` package's tests.
// Each test file uses some of these.
#![allow(dead_code)]

use std::ffi::OsStr;
use std::io::Write;
use std::path::Path;
use std::process::{Command, Stdio};

/// The repository's root: the manifest's folder, or its parent for the `pdcontact-mpi`
/// package (`mpi/`).
fn root() -> &'static Path {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    if env!("CARGO_PKG_NAME") == "pdcontact-mpi" {
        manifest.parent().unwrap_or(manifest)
    } else {
        manifest
    }
}

/// Says that a check did not run, and why, where the reader of `cargo test` sees it: straight
/// to the process's stderr, past the harness's capture of a passing test's output. CI installs
/// every tool these checks need, so there none is skipped.
pub fn skipped(what: &str, why: &str) {
    let _ = writeln!(std::io::stderr(), "SKIPPED {what}: {why}");
}

/// Whether python3 imports `modules` (e.g. "vtk, numpy"), asked quietly: a missing module is a
/// skip to report, not a traceback in the test output.
pub fn python_has(modules: &str) -> bool {
    Command::new("python3")
        .args(["-c", &format!("import {modules}")])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// Runs tools/check_vtk.py with `args` (it reads the files with VTK's own readers) and returns
/// what it printed; `None` when Python's vtk is not installed (CI installs it). A failed check
/// fails the test with the script's output.
pub fn check_vtk<S: AsRef<OsStr>>(args: &[S]) -> Option<String> {
    if !python_has("vtk, numpy") {
        skipped(
            "VTK reader check",
            "python3 with vtk and numpy not found (pip install vtk numpy)",
        );
        return None;
    }
    let check = Command::new("python3")
        .arg(root().join("tools/check_vtk.py"))
        .args(args)
        .output()
        .expect("python3 runs");
    let stdout = String::from_utf8_lossy(&check.stdout).into_owned();
    assert!(
        check.status.success(),
        "VTK check failed: {stdout}{}",
        String::from_utf8_lossy(&check.stderr)
    );
    Some(stdout)
}
