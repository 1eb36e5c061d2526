//! What the integration tests share.

use std::ffi::OsStr;
use std::path::Path;
use std::process::Command;

/// Runs tools/check_vtk.py with `args` (it reads the files with VTK's own readers) and returns
/// what it printed; `None` when Python's vtk is not installed (CI installs it). A failed check
/// fails the test with the script's output.
pub fn check_vtk<S: AsRef<OsStr>>(args: &[S]) -> Option<String> {
    let has_vtk = Command::new("python3")
        .args(["-c", "import vtk, numpy"])
        .status()
        .is_ok_and(|s| s.success());
    if !has_vtk {
        eprintln!("python3 with vtk not found: VTK reader check skipped (pip install vtk)");
        return None;
    }
    let check = Command::new("python3")
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("tools/check_vtk.py"))
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
