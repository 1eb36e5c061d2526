//! The command line as a user drives it: exit codes, JSON, error lines.

use std::path::{Path, PathBuf};
use std::process::Command;

fn exe() -> Command {
    Command::new(env!("CARGO_BIN_EXE_pdcontact"))
}

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pdcontact-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

fn json_of(out: &std::process::Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("stdout is JSON")
}

/// The stored meshes, checked against counts that follow from their construction:
/// the box is 10 x 10 x 5 cells; the spheres' counts are gmsh's (meshes/README.md).
#[test]
fn inspect_stored_meshes() {
    let cases = [
        ("meshes/block_hex.msh", 726, 500, 400),
        ("meshes/sphere_r1_d012.msh", 3137, 2800, 600),
        ("meshes/sphere_r1_d008.msh", 8087, 7448, 1176),
    ];
    for (file, nodes, hexes, quads) in cases {
        let v = json_of(
            &exe()
                .args(["inspect", "--json"])
                .arg(repo(file))
                .output()
                .expect("runs"),
        );
        assert_eq!(v["format"], "msh", "{file}");
        assert_eq!(v["nodes_total"], nodes, "{file}");
        assert_eq!(v["corner_nodes_in_3d_elements"], nodes, "{file}");
        assert_eq!(v["elements_3d"]["hex8"], hexes, "{file}");
        assert_eq!(v["elements_3d"]["total"], hexes, "{file}");
        assert_eq!(v["boundary_faces"]["quad"], quads, "{file}");
        assert_eq!(v["boundary_faces"]["tri"], 0, "{file}");
    }
    let tet = json_of(
        &exe()
            .args(["inspect", "--json"])
            .arg(repo("meshes/sphere_tet4.msh"))
            .output()
            .expect("runs"),
    );
    assert_eq!(tet["elements_3d"]["tet4"], 5571);
    // A closed triangulated surface of V vertices has 2V − 4 triangles.
    let surface_nodes = tet["sets"]
        .as_array()
        .expect("sets")
        .iter()
        .find(|s| s["name"] == "surface")
        .expect("surface group")["nodes"]
        .as_u64()
        .expect("count");
    assert_eq!(
        tet["boundary_faces"]["tri"].as_u64(),
        Some(2 * surface_nodes - 4)
    );
}

#[test]
fn inspect_text_and_forced_format() {
    let out = exe()
        .args(["inspect", "--format", "msh"])
        .arg(repo("meshes/block_hex.msh"))
        .output()
        .expect("runs");
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("500 hex8") && text.contains("top"), "{text}");
}

#[test]
fn bad_mesh_exits_2_with_a_located_error() {
    let dir = temp_dir("bad");
    let file = dir.join("broken.msh");
    std::fs::write(
        &file,
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2 1 2\n3 1 0 two\n",
    )
    .expect("write");
    let out = exe().args(["inspect"]).arg(&file).output().expect("runs");
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    let first = err.lines().next().unwrap_or("");
    assert!(
        first.contains("broken.msh:") && first.contains("expected") && first.contains("found"),
        "{err}"
    );
    // Not a mesh at all.
    let junk = dir.join("junk.xyz");
    std::fs::write(&junk, [0u8, 159, 146, 150]).expect("write");
    let out = exe().args(["inspect"]).arg(&junk).output().expect("runs");
    assert_eq!(out.status.code(), Some(2));
    let missing = exe()
        .args(["inspect", "no/such/file.msh"])
        .output()
        .expect("runs");
    assert_eq!(missing.status.code(), Some(2));
}

#[test]
fn convert_writes_a_case_folder() {
    let dir = temp_dir("convert");
    let out = exe()
        .args(["convert", "--json", "-o"])
        .arg(&dir)
        .arg(repo("meshes/sphere_r1_d012.msh"))
        .output()
        .expect("runs");
    let v = json_of(&out);
    for key in [
        "particles",
        "bonds",
        "spacing",
        "horizon",
        "total_volume",
        "mesh_volume",
        "surface_particles",
        "boundary_nodes",
        "surface_missed",
        "surface_extra",
        "master_segments",
        "dropped_faces",
        "seconds",
    ] {
        assert!(!v[key].is_null(), "missing {key} in {v}");
    }
    assert_eq!(v["particles"], 3137);
    let h = v["horizon"].as_f64().expect("h") / v["spacing"].as_f64().expect("d");
    assert!((h - 3.0).abs() < 1e-12);
    for f in ["case.toml", "particles.vtu", "segments.vtu"] {
        assert!(dir.join(f).exists(), "{f}");
    }
    // The scene skeleton runs as it is: one solid, by the static solver
    // (docs/PERFORMANCE.md, "The cases `convert` writes").
    let run = exe()
        .args(["run", "--quiet", "--json"])
        .arg(dir.join("case.toml"))
        .output()
        .expect("runs");
    let s = json_of(&run);
    assert_eq!(s["converged"], true, "{s}");
    assert_eq!(s["solver"]["solver"], "static", "{s}");
    assert!(
        s["force_balance_error"].as_f64().expect("balance") < 1e-3,
        "{s}"
    );
    // Run from its own folder with the frames beside the scene (`folder = "."`), as the
    // demo writes its scene: the output folder is "." and not an empty path.
    let case = std::fs::read_to_string(dir.join("case.toml")).expect("case.toml");
    let here = case.replacen("folder = \"out\"", "folder = \".\"", 1);
    assert_ne!(here, case, "case.toml names its output folder \"out\"");
    std::fs::write(dir.join("here.toml"), here).expect("writes");
    let run = exe()
        .current_dir(&dir)
        .args(["run", "--quiet", "--json", "here.toml"])
        .output()
        .expect("runs");
    assert_eq!(json_of(&run)["converged"], true);
    assert!(dir.join("summary.json").exists() && dir.join("run.pvd").exists());
    // Converting again over a case.toml the user edited keeps the edit under another name.
    std::fs::write(
        dir.join("case.toml"),
        case.replace("youngs_modulus = 1e9", "youngs_modulus = 3e9"),
    )
    .expect("writes");
    let again = exe()
        .args(["convert", "-o"])
        .arg(&dir)
        .arg(repo("meshes/sphere_r1_d012.msh"))
        .output()
        .expect("runs");
    assert!(again.status.success());
    let edited = std::fs::read_to_string(dir.join("case.toml.edited")).expect("the edit is kept");
    assert!(edited.contains("youngs_modulus = 3e9"));
    assert_eq!(
        std::fs::read_to_string(dir.join("case.toml")).expect("case.toml"),
        case
    );
    assert!(
        String::from_utf8_lossy(&again.stderr).contains("kept as"),
        "{}",
        String::from_utf8_lossy(&again.stderr)
    );
    // And --horizon-factor changes the horizon.
    let v = json_of(
        &exe()
            .args(["convert", "--json", "--horizon-factor", "2.5", "-o"])
            .arg(dir.join("m25"))
            .arg(repo("meshes/block_hex.msh"))
            .output()
            .expect("runs"),
    );
    assert!(
        (v["horizon"].as_f64().expect("h") - 0.25).abs() < 1e-9,
        "{v}"
    );
}

#[test]
fn scene_errors_exit_2_with_line_and_column() {
    let dir = temp_dir("scene");
    let scene = dir.join("s.toml");
    std::fs::write(&scene, "[solver]\nkind = \"adr\"\nspeed = 3\n").expect("write");
    let out = exe().args(["run"]).arg(&scene).output().expect("runs");
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("s.toml:3:1:") && err.contains("speed"),
        "{err}"
    );
}

#[test]
fn bench_lattice_sphere_json() {
    let out = exe()
        .args([
            "bench",
            "--lattice-sphere",
            "0.2",
            "--steps",
            "5",
            "--threads",
            "1",
            "--json",
        ])
        .output()
        .expect("runs");
    let v = json_of(&out);
    // The 515 lattice points of spacing 0.2 with norm ≤ 1.
    assert_eq!(v["particles"], 515);
    assert_eq!(v["steps"], 5);
    assert_eq!(v["threads"], 1);
    for key in [
        "bonds_per_particle",
        "loop_seconds",
        "setup_seconds",
        "bond_updates_per_second",
        "energy_drift",
    ] {
        assert!(v[key].as_f64().is_some(), "{key} in {v}");
    }
    let bad = exe()
        .args(["bench", "--lattice-sphere", "0"])
        .output()
        .expect("runs");
    assert_eq!(bad.status.code(), Some(2));
}

#[test]
fn bench_adr_times_iterations_against_bond_passes() {
    let dir = temp_dir("bench-adr");
    std::fs::create_dir_all(&dir).expect("temp dir");
    let scene = dir.join("block.toml");
    std::fs::write(
        &scene,
        r#"[solver]
kind = "adr"

[[body]]
name = "block"
generator = { shape = "box", min = [0.0, 0.0, 0.0], max = [0.4, 0.4, 0.4], spacing = 0.05 }
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0

[[load]]
body = "block"
set = "top"
force = [0.0, 0.0, -1e5]

[[constraint]]
body = "block"
set = "bottom"
fix = ["x", "y", "z"]
"#,
    )
    .expect("scene written");
    let out = exe()
        .args(["bench", "--adr"])
        .arg(&scene)
        .args(["--steps", "7", "--json"])
        .output()
        .expect("runs");
    let v = json_of(&out);
    assert_eq!(v["iterations"], 7, "{v}");
    assert!(v["particles"].as_u64().unwrap_or(0) > 500, "{v}");
    // Times are measured, not asserted (tests are not benchmarks): only their consistency.
    let ratio = v["ratio"].as_f64().expect("ratio");
    let adr = v["adr_iteration_seconds"].as_f64().expect("adr seconds");
    let bare = v["bond_pass_seconds"].as_f64().expect("bare seconds");
    assert!(adr > 0.0 && bare > 0.0, "{v}");
    assert!((ratio - adr / bare).abs() <= 1e-9 * ratio.abs(), "{v}");
    let neither = exe().args(["bench"]).output().expect("runs");
    assert_eq!(neither.status.code(), Some(2));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bench_pipeline_times_every_stage() {
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/block_hex.msh");
    let out = exe()
        .args(["bench", "--pipeline"])
        .arg(&mesh)
        .arg("--json")
        .output()
        .expect("runs");
    let v = json_of(&out);
    let stages = v["stages"].as_array().expect("stages");
    let names: Vec<&str> = stages.iter().filter_map(|s| s["stage"].as_str()).collect();
    for want in [
        "import",
        "neighbours",
        "surface",
        "correction",
        "neighbours alone",
        "surface alone",
        "write case folder",
    ] {
        assert!(names.contains(&want), "{want} missing from {names:?}");
    }
    // The same mesh through `convert`: the same particles and bonds.
    let dir = temp_dir("bench-pipeline");
    let conv = exe()
        .arg("convert")
        .arg(&mesh)
        .arg("-o")
        .arg(&dir)
        .arg("--json")
        .output()
        .expect("runs");
    let c = json_of(&conv);
    assert_eq!(v["particles"], c["particles"], "{v}\n{c}");
    assert_eq!(v["bonds"], c["bonds"], "{v}\n{c}");
    // The standalone neighbour build finds exactly the case's bonds (throughput × seconds).
    let alone = stages
        .iter()
        .find(|s| s["stage"] == "neighbours alone")
        .expect("neighbours alone");
    let found =
        alone["throughput"].as_f64().unwrap_or(0.0) * alone["seconds"].as_f64().unwrap_or(0.0);
    let bonds = c["bonds"].as_f64().expect("bonds");
    assert!((found - bonds).abs() <= 1e-6 * bonds, "{found} vs {bonds}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Started by an MPI launcher as several processes, `pdcontact` (built without MPI) refuses (exit 2)
/// instead of running the job once per rank into the same folder; the first rank says why,
/// the others stop quietly. One process under a launcher (`mpirun -n 1`) runs as usual.
#[test]
fn several_mpi_copies_are_refused() {
    let dir = temp_dir("mpi");
    for (size_var, rank_var) in [
        ("OMPI_COMM_WORLD_SIZE", "OMPI_COMM_WORLD_RANK"),
        ("PMI_SIZE", "PMI_RANK"),
        ("MV2_COMM_WORLD_SIZE", "MV2_COMM_WORLD_RANK"),
    ] {
        for rank in ["0", "1"] {
            let out = exe()
                .args(["demo", "--quiet", "-o"])
                .arg(dir.join("demo"))
                .env(size_var, "2")
                .env(rank_var, rank)
                .output()
                .expect("runs");
            assert_eq!(out.status.code(), Some(2), "{size_var} rank {rank}");
            let err = String::from_utf8_lossy(&out.stderr);
            if rank == "0" {
                assert!(
                    err.contains("as 2 processes") && err.contains(size_var),
                    "{err}"
                );
            } else {
                assert!(err.is_empty(), "{err}");
            }
            assert!(!dir.join("demo").exists(), "nothing written");
        }
    }
    let out = exe()
        .args(["inspect", "--json"])
        .arg(repo("meshes/block_hex.msh"))
        .env("OMPI_COMM_WORLD_SIZE", "1")
        .env("OMPI_COMM_WORLD_RANK", "0")
        .output()
        .expect("runs");
    assert_eq!(json_of(&out)["nodes_total"], 726);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn convert_refuses_a_horizon_factor_under_one() {
    let dir = temp_dir("horizon-factor");
    let out = exe()
        .args(["convert", "--horizon-factor", "0.5", "-o"])
        .arg(dir.join("case"))
        .arg(repo("meshes/two_boxes_gap.msh"))
        .output()
        .expect("runs");
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("'0.5'") && err.contains("at least 1"), "{err}");
}
