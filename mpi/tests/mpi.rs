//! A run decomposed over MPI ranks gives the one-process run's figures bit for bit
//! (`pdcontact-mpi`; needs `mpirun`, which `.ci/run` installs): the bond forces, ADR's
//! sums and the contact forces are added in the same order on any number of threads and ranks.
//! Its frames (one piece of particles per rank) hold every particle once, with the values of
//! the one-process frames, read by VTK's own readers when Python's vtk is present.

use std::path::{Path, PathBuf};
use std::process::Command;

#[path = "../../tests/common/tools.rs"]
mod common;

fn exe() -> &'static str {
    env!("CARGO_BIN_EXE_pdcontact-mpi")
}

/// A path in the repository (this package is its folder `mpi/`).
fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(p)
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pdcontact-mpi-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

fn summary(out: &std::process::Output, dir: &Path) -> serde_json::Value {
    assert!(
        out.status.success(),
        "failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(dir.join("summary.json")).expect("summary.json");
    serde_json::from_str(&text).expect("summary is JSON")
}

/// The demo's scene and mesh written into `dir`, with the solver it takes under `mpirun`
/// (ADR: the static solver runs in one process), as `pdcontact demo` writes them.
fn write_demo(dir: &Path) {
    use pdcontact::studies::demo::{scene_text, DemoSolver, DEMO_MESH, DEMO_MESH_NAME};
    std::fs::write(dir.join(DEMO_MESH_NAME), DEMO_MESH).expect("mesh written");
    std::fs::write(dir.join("scene.toml"), scene_text(DemoSolver::Adr)).expect("scene written");
}

/// `mpirun -n ranks pdcontact`, allowed to run as root (CI's containers), the program's
/// arguments to follow.
fn mpirun(ranks: usize) -> Command {
    let mut c = Command::new("mpirun");
    c.args(["--oversubscribe", "-n", &ranks.to_string(), exe()])
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1");
    c
}

/// `pdcontact run` of `scene` into `out` by `mpirun -n ranks`, on 1 thread each (not quiet:
/// its last line is checked).
fn on_ranks(ranks: usize, out: &Path, scene: &Path) -> std::process::Output {
    mpirun(ranks)
        .args(["run", "-o"])
        .arg(out)
        .arg(scene)
        .env("RAYON_NUM_THREADS", "1")
        .output()
        .expect("mpirun runs (install Open MPI: apt install openmpi-bin)")
}

/// `pdcontact bench --lattice-sphere SPACING --steps STEPS --threads 1 --json`, in one process
/// (`ranks` 1) or by `mpirun -n ranks`: the first rank's JSON report.
fn bench(spacing: &str, steps: &str, ranks: usize) -> serde_json::Value {
    let args = [
        "bench",
        "--lattice-sphere",
        spacing,
        "--steps",
        steps,
        "--threads",
        "1",
        "--json",
    ];
    let out = if ranks == 1 {
        Command::new(exe()).args(args).output()
    } else {
        mpirun(ranks).args(args).output()
    }
    .expect("runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON report, from the first rank")
}

/// `scene` run in one process on 2 threads, and by `mpirun -n ranks` on 1 thread each.
fn both(scene: &Path, ranks: usize) -> (serde_json::Value, serde_json::Value) {
    let dir = scene.parent().expect("folder");
    let one = dir.join("one");
    let out = Command::new(exe())
        .args(["run", "--quiet", "-o"])
        .arg(&one)
        .arg(scene)
        .env("RAYON_NUM_THREADS", "2")
        .output()
        .expect("runs");
    let a = summary(&out, &one);
    let many = dir.join("many");
    let out = on_ranks(ranks, &many, scene);
    let b = summary(&out, &many);
    // `run`'s last line says how the ranks shared the run.
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(
        said.contains(&format!("; {ranks} ranks: peak memory "))
            && said.contains(" MB a rank, ghosts ")
            && said.contains(" % of a rank's particles"),
        "{said}"
    );
    (a, b)
}

fn num(v: &serde_json::Value, key: &str) -> f64 {
    v[key].as_f64().unwrap_or_else(|| panic!("{key} in {v}"))
}

/// The same converged state: iterations, contact radius, peak pressure and contact force
/// with the same bits, and the Verlet lists rebuilt at the same evaluations (the ranks
/// decide a rebuild together, each particle's move counted once).
fn assert_identical(a: &serde_json::Value, b: &serde_json::Value) {
    assert_eq!(a["converged"], true, "{a}");
    assert_eq!(b["converged"], true, "{b}");
    for key in [
        "particles",
        "bonds",
        "contact_radius",
        "peak_pressure",
        "total_contact_force",
        "verlet_rebuilds",
    ] {
        assert_eq!(a[key], b[key], "{key}: one process {a}, ranks {b}");
    }
    assert_eq!(a["solver"]["iterations"], b["solver"]["iterations"]);
}

/// Each rank of `b` built its part of the model: it holds at most `share` of the model's
/// bonds (its own particles' and its halo's), and the shares cover the model.
fn assert_built_in_parts(b: &serde_json::Value, share: f64) {
    let d = &b["decomposition"];
    let model = num(d, "model_bonds");
    assert_eq!(model, num(b, "bonds"), "{d}");
    let held: Vec<f64> = d["bonds"]
        .as_array()
        .expect("per rank")
        .iter()
        .map(|x| x.as_f64().expect("a count"))
        .collect();
    assert!(
        held.iter().all(|&h| h <= share * model),
        "{held:?} of {model}"
    );
    assert!(held.iter().sum::<f64>() >= model, "{held:?} of {model}");
}

/// The demo (a sphere on a rigid plane, quarter model with symmetry planes): the ranks hold
/// ghosts across the cut and mirror images of their own particles.
#[test]
fn demo_on_two_ranks() {
    let dir = temp_dir("demo");
    write_demo(&dir);
    let (a, b) = both(&dir.join("scene.toml"), 2);
    assert_identical(&a, &b);
    assert_built_in_parts(&b, 0.65);
    // Each rank's peak memory, as the kernel counts it, beside what it owned.
    let peaks = b["decomposition"]["peak_memory_mb"]
        .as_array()
        .expect("per rank");
    assert_eq!(peaks.len(), 2);
    for (one, p) in [&a["peak_memory_mb"]].into_iter().cycle().zip(peaks) {
        if let (Some(one), Some(p)) = (one.as_f64(), p.as_f64()) {
            assert!(p > 1.0 && one > 1.0, "{one} and {p} MB");
        }
    }
    // Each rank wrote its particles' piece of every frame: put together in rank order they
    // are the one-process frames, bit for bit, and the `.pvtu` beside them loads as one grid.
    let vtm = b["outputs"]["last_frame"].as_str().expect("last frame");
    let pieces = std::fs::read_to_string(vtm).expect("frame");
    assert!(pieces.contains("ball_particles_1.vtu"), "{pieces}");
    let (one, many) = (dir.join("one"), dir.join("many"));
    common::check_vtk(&["same".as_ref(), one.as_os_str(), many.as_os_str()]);
    common::check_vtk(&[
        "run".as_ref(),
        many.as_os_str(),
        "--plane-normal".as_ref(),
        "0,0,1".as_ref(),
        "--plane-point".as_ref(),
        "0,0,-1".as_ref(),
    ]);
    // The run's `view.py` reads the pieces as the one-process frame: the same aim and the
    // same largest pressure (`--focus`: Python's vtk, no ParaView).
    if !common::python_has("vtk") {
        common::skipped(
            "view.py --focus",
            "python3 with vtk not found (pip install vtk)",
        );
        return;
    }
    let focus = |run: &Path| -> serde_json::Value {
        let out = Command::new("python3")
            .arg(run.join("view.py"))
            .arg("--focus")
            .output()
            .expect("python3 runs");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_slice(&out.stdout).expect("JSON")
    };
    let (f1, f2) = (focus(&one), focus(&many));
    assert!(f1["loaded"].as_u64().expect("loaded") > 0, "{f1}");
    for key in [
        "centre",
        "normal",
        "radius",
        "loaded",
        "pressure_max",
        "caption",
    ] {
        assert_eq!(f1[key], f2[key], "{key}: {f1} against {f2}");
    }
}

/// A scene file: a sphere (spacing 0.05 m) held on its axis, pressed by 1e5 N into a
/// deformable block fixed at its bottom, the pair's `[[contact]]` ending with `contact`.
fn ball_on_block(name: &str, contact: &str) -> PathBuf {
    let dir = temp_dir(name);
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        format!(
            r#"
[solver]
kind = "adr"
max_iterations = 20000
[output]
every = 100000
[[body]]
name = "ball"
generator = {{ shape = "sphere", radius = 0.3, spacing = 0.05, center = [0.0, 0.0, 0.3] }}
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[body]]
name = "block"
generator = {{ shape = "box", min = [-0.5, -0.5, -0.3], max = [0.5, 0.5, 0.0], spacing = 0.0625 }}
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[constraint]]
body = "block"
set = "bottom"
fix = ["x", "y", "z"]
[[constraint]]
body = "ball"
set = "ball"
fix = ["x", "y"]
[[load]]
body = "ball"
set = "top"
force = [0.0, 0.0, -1e5]
[[contact]]
slave = "ball"
master = "block"
{contact}
"#
        ),
    )
    .expect("scene");
    scene
}

/// A sphere pressed into a deformable block, both bodies slave and master (two passes): the
/// reactions on master nodes go to their owners, who add them in one process's order.
#[test]
fn two_deformable_bodies_on_three_ranks() {
    let scene = ball_on_block("dent", "two_pass = true");
    let (a, b) = both(&scene, 3);
    assert_identical(&a, &b);
    assert_built_in_parts(&b, 0.5);
    assert!((num(&b, "force_balance_error")) < 2e-3, "{b}");
}

/// The same with one pass: the block's nodes, nobody's slaves, keep a fading share of their
/// contact stiffness in ADR's density (`OPENED_CONTACT_MEMORY`), each rank for the particles
/// it owns, and the ranks agree to the bit.
#[test]
fn one_pass_between_deformable_bodies_on_three_ranks() {
    let scene = ball_on_block("dent-one-pass", "two_pass = false");
    let (a, b) = both(&scene, 3);
    assert_identical(&a, &b);
    assert!((num(&b, "force_balance_error")) < 2e-3, "{b}");
}

/// Explicit dynamics: a sphere dropped on a plane bounces off; the ranks agree on the step at
/// which it leaves the plane and on the energy balance.
#[test]
fn explicit_drop_on_two_ranks() {
    let dir = temp_dir("drop");
    let scene = dir.join("scene.toml");
    let mesh = repo("meshes/sphere_r1_d012.msh");
    std::fs::write(
        &scene,
        format!(
            r#"
[solver]
kind = "explicit"
end_time = 0.1
stop_after_rebound = true
[output]
every = 100000
[[body]]
name = "ball"
mesh = "{}"
velocity = [0.0, 0.0, -1.0]
translate = [0.0, 0.0, 0.002]
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[body]]
name = "plane"
kind = "rigid"
generator = {{ shape = "plane", point = [0.0, 0.0, -1.0], normal = [0.0, 0.0, 1.0], size = 3.0 }}
[[contact]]
slave = "ball"
master = "plane"
"#,
            mesh.display()
        ),
    )
    .expect("scene");
    let (a, b) = both(&scene, 2);
    let (sa, sb) = (&a["solver"], &b["solver"]);
    assert_eq!(sa["rebounded"], true, "{a}");
    assert_eq!(sa["iterations"], sb["iterations"], "steps to the rebound");
    assert_eq!(sa["dt"], sb["dt"]);
    // The energies are summed block by block of particles: the same bits on any rank count.
    assert!(num(sa, "energy_drift") < 1e-3, "{a}");
    assert_eq!(sa["energy_drift"], sb["energy_drift"]);
}

/// The bond-force benchmark decomposed over 2 ranks: the energies of the one-process run, bit
/// for bit, every particle owned once, and each rank's memory reported.
#[test]
fn bench_on_two_ranks() {
    let (one, two) = (bench("0.1", "20", 1), bench("0.1", "20", 2));
    assert_eq!(one["ranks"], 1);
    assert_eq!(two["ranks"], 2);
    for key in ["particles", "initial_energy", "final_energy"] {
        assert_eq!(one[key], two[key], "{key}");
    }
    let ranks = two["per_rank"].as_array().expect("per rank");
    let owned: u64 = ranks
        .iter()
        .map(|r| r["particles"].as_u64().expect("count"))
        .sum();
    assert_eq!(owned, one["particles"].as_u64().expect("count"));
    for r in ranks {
        assert!(r["ghosts"].as_u64().expect("ghosts") > 0, "{r}");
        if let Some(mb) = r["resident_mb"].as_f64() {
            assert!(mb > 0.0, "{r}");
        }
    }
}

/// Each rank builds only its part of the benchmark's bonds, so its peak memory falls with the
/// rank count: on 155,331 particles 2 ranks measured 0.61-0.68 of one process's peak (134 MB)
/// and 4 ranks 0.42-0.48, each process's fixed cost (the program and MPI's library, about
/// 25 MB) weighing at this size; when each rank built the whole list first, 2 ranks peaked
/// above one process. Same energies, bit for bit, on any count.
#[test]
fn each_ranks_peak_memory_falls_with_the_rank_count() {
    let peaks = |ranks: usize| -> (Vec<f64>, serde_json::Value) {
        let report = bench("0.03", "2", ranks);
        let peaks = report["per_rank"]
            .as_array()
            .expect("per rank")
            .iter()
            .filter_map(|r| r["peak_rss_mb"].as_f64())
            .collect();
        (peaks, report["final_energy"].clone())
    };
    let (one, energy) = peaks(1);
    if one.is_empty() {
        eprintln!("no /proc/self/status here: peak memory not measured");
        return;
    }
    let worst = |p: &[f64]| p.iter().copied().fold(0.0, f64::max);
    for (ranks, bound) in [(2, 0.8), (4, 0.6)] {
        let (p, e) = peaks(ranks);
        assert_eq!(e, energy, "{ranks} ranks");
        assert_eq!(p.len(), ranks);
        assert!(
            worst(&p) <= bound * one[0],
            "{ranks} ranks: peaks {p:?} MB against {} MB for one process",
            one[0]
        );
    }
}

/// The short-range method between two deformable bodies on 2 ranks: each rank evaluates the
/// repulsion on its own surface particles from the other body's whole surface (its ghosts),
/// and the counts, forces and energies are summed as one process sums them.
#[test]
fn short_range_on_two_ranks() {
    let scene = ball_on_block("short-range", "method = \"short-range\"");
    let (a, b) = both(&scene, 2);
    assert_identical(&a, &b);
    assert!(num(&a, "contact_pairs") > 0.0, "{a}");
}

/// The static solver is not decomposed over ranks yet: under `mpirun` it refuses before it
/// solves (exit 2), naming the reason and ADR, instead of solving each rank's part alone.
#[test]
fn static_solver_refuses_to_run_on_ranks() {
    let dir = temp_dir("static");
    write_demo(&dir);
    let scene = std::fs::read_to_string(dir.join("scene.toml")).expect("scene");
    let scene = scene.replacen("kind = \"adr\"", "kind = \"static\"", 1);
    let path = dir.join("static.toml");
    std::fs::write(&path, scene).expect("written");
    let out = on_ranks(2, &dir.join("many"), &path);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{stderr}");
    assert!(
        stderr.contains("static solver runs in one process") && stderr.contains("adr"),
        "{stderr}"
    );
}

/// An LPS body (the demo at ν = 0.3, on the gmsh tet4 mesh of its quarter cap: 2,744
/// particles where the demo's hexes are 15,625) on 3 ranks, with either influence function:
/// between its two sweeps each rank sends its particles' force states to the ranks that hold
/// them as ghosts, so every particle's dilatation and force is one process's sum: the
/// converged state and the frames (the recovered `stress` among them) have the same bits.
#[test]
fn lps_on_three_ranks() {
    let tet4 = repo("meshes/sphere_cap_quarter_tet4.msh");
    let demo_mesh = format!("mesh = \"{}\"", pdcontact::studies::demo::DEMO_MESH_NAME);
    for influence in ["constant", "position-aware"] {
        let dir = temp_dir(&format!("lps-{influence}"));
        write_demo(&dir);
        let scene = std::fs::read_to_string(dir.join("scene.toml")).expect("scene");
        assert!(
            scene.contains("poisson_ratio = 0.25") && scene.contains(&demo_mesh),
            "{scene}"
        );
        let scene = scene
            .replacen(
                "poisson_ratio = 0.25",
                &format!(
                    "poisson_ratio = 0.3\nmodel = \"lps\"\ninfluence_function = \"{influence}\""
                ),
                1,
            )
            .replacen(&demo_mesh, &format!("mesh = {tet4:?}"), 1);
        let path = dir.join("lps.toml");
        std::fs::write(&path, scene).expect("written");
        let (a, b) = both(&path, 3);
        assert_identical(&a, &b);
        let (one, many) = (dir.join("one"), dir.join("many"));
        common::check_vtk(&["same".as_ref(), one.as_os_str(), many.as_os_str()]);
    }
}

/// Bonds that fail (a notched beam broken by a roller driven through the contact; Δ = 2.5 mm,
/// 3 increments): on three ranks the same bonds fail in the same increments, with the
/// one-process reactions bit for bit; each rank tests its own pairs and the ranks share what
/// failed.
#[test]
fn fracture_on_three_ranks() {
    beam_on_three_ranks("fracture", None);
}

/// The same as a linear peridynamic solid (ν = 0.3): the broken bonds leave the dilatations
/// and force states alike on every rank.
#[test]
fn lps_fracture_on_three_ranks() {
    beam_on_three_ranks("lps-fracture", Some(0.3));
}

fn beam_on_three_ranks(name: &str, lps_poisson: Option<f64>) {
    let dir = temp_dir(name);
    let beam = pdcontact::studies::fracture::NotchedBeam {
        spacing: 0.0025,
        thickness: 0.01,
        displacement: 0.0005,
        steps: 3,
        mesh: None,
        static_solver: false,
        lps_poisson,
        failure: Default::default(),
    };
    let path = dir.join("beam.toml");
    std::fs::write(&path, beam.scene(".")).expect("written");
    let (a, b) = both(&path, 3);
    assert_identical(&a, &b);
    assert_eq!(a["solver"]["increments"], b["solver"]["increments"]);
    // Everything but the time the new surface took to find.
    let timeless = |v: &serde_json::Value| {
        let mut v = v["fracture"].clone();
        for body in v.as_array_mut().expect("a list") {
            body.as_object_mut()
                .expect("an object")
                .remove("new_surface_seconds");
        }
        v
    };
    assert_eq!(timeless(&a), timeless(&b));
    assert!(
        a["fracture"][0]["new_surface_particles"].as_u64() > Some(0),
        "{a}"
    );
    let last = &a["solver"]["increments"][2];
    let first = &a["solver"]["increments"][0];
    assert!(
        last["broken_bonds"].as_u64() > first["broken_bonds"].as_u64(),
        "no bond failed: {a}"
    );
    let (one, many) = (dir.join("one"), dir.join("many"));
    common::check_vtk(&["same".as_ref(), one.as_os_str(), many.as_os_str()]);
}

/// Friction (a sphere pressed into a block and pushed sideways, two passes): on three ranks
/// the stick points, the tangential forces and the stick states come out as in one process,
/// bit for bit, frames included; each slave's stick point is its owner's.
#[test]
fn friction_on_three_ranks() {
    let dir = temp_dir("friction");
    let mut scene = pdcontact::studies::friction::MindlinScene {
        contact_radius: 0.15,
        spacing: 0.05,
        friction: 0.3,
        push: 0.0,
        steps: 2,
        rigid_flat: false,
        static_solver: false,
        meshes: None,
    };
    scene.push = 1.5 * scene.full_slip_travel();
    let path = dir.join("mindlin.toml");
    std::fs::write(&path, scene.scene()).expect("written");
    let (a, b) = both(&path, 3);
    assert_identical(&a, &b);
    assert_eq!(a["friction"], b["friction"]);
    assert_eq!(a["friction_pairs"], b["friction_pairs"]);
    assert!(a["friction"][0]["slipping"].as_u64() > Some(0), "{a}");
    let (one, many) = (dir.join("one"), dir.join("many"));
    common::check_vtk(&["same".as_ref(), one.as_os_str(), many.as_os_str()]);
}
