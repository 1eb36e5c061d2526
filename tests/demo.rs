//! The README's first command, and its files read back by VTK's own readers.

use std::path::{Path, PathBuf};
use std::process::Command;

mod common;

use pdcontact::run::RunOptions;
use pdcontact::studies::demo::run_demo;

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pdcontact-demo-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// tools/check_vtk.py's JSON report; `None` when Python's vtk is not installed.
fn vtk_report(args: &[&str]) -> Option<serde_json::Value> {
    common::check_vtk(args).map(|s| serde_json::from_str(&s).expect("JSON report"))
}

#[test]
fn demo_converges_balances_and_loads_in_vtk() {
    let dir = temp_dir("run");
    let report = run_demo(
        &dir,
        &RunOptions {
            output: None,
            quiet: true,
            stop: None,
            comm: None,
            study: false,
        },
    )
    .expect("demo runs");
    let s = &report.summary;
    assert!(s.converged);
    assert!(s.force_balance_error < 1e-3, "{}", s.force_balance_error);
    assert_eq!(s.missed_contacts, 0);
    // The printed table compares with Hertz: a = (3PR/4E*)^{1/3} = 0.15 m. Measured (the
    // static solver, 21 Newton iterations): MRE 0.15 %, fitted radius −0.61 %, peak −0.06 %
    // (METHOD.md §7).
    assert_eq!(s.solver.solver, "static");
    assert!((report.theory_radius - 0.15).abs() < 1e-4);
    assert!(report.accuracy.mre < 0.02, "{}", report.to_text());
    assert!(
        (report.contact_radius / report.theory_radius - 1.0).abs() < 0.02,
        "{}",
        report.to_text()
    );
    assert!(
        (report.peak_pressure / report.theory_peak_pressure - 1.0).abs() < 0.03,
        "{}",
        report.to_text()
    );
    assert!(dir.join("scene.toml").exists() && dir.join("summary.json").exists());
    if let Some(r) = vtk_report(&[
        "run",
        dir.to_str().expect("utf-8"),
        "--plane-normal",
        "0,0,1",
        "--plane-point",
        "0,0,-1",
    ]) {
        assert_eq!(r["loaded_not_facing"], 0);
        assert!(r["loaded"].as_u64().expect("count") > 10);
        // Loaded particles, at their points + displacement, sit on the plane (within the
        // penetration; their reference positions are up to 1 cm above it).
        assert!(r["max_height_of_loaded"].as_f64().expect("height").abs() < 0.01);
        // Named blocks; the surface carries the pressure on its own nodes.
        assert_eq!(
            r["blocks"],
            serde_json::json!(["ball/particles", "ball/surface", "plane"])
        );
        assert_eq!(r["surface_loaded"], r["loaded"]);
        assert_eq!(r["plane_offset"], 0.0);
        // The full load at once: timesteps are the Newton iterations' progress, ending at 1.
        assert_eq!(r["load_factor"], 1.0);
        assert_eq!(r["last_timestep"], 1.0);
    }
}

#[test]
fn convert_output_loads_in_vtk() {
    let dir = temp_dir("case");
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/sphere_tet4.msh");
    let status = Command::new(env!("CARGO_BIN_EXE_pdcontact"))
        .args(["convert", "-o"])
        .arg(&dir)
        .arg(&mesh)
        .output()
        .expect("runs");
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    if let Some(r) = vtk_report(&["case", dir.to_str().expect("utf-8")]) {
        assert_eq!(r["particles"], r["vertex_cells"]);
        assert!(r["segments"].as_u64().expect("count") > 100);
    }
}
