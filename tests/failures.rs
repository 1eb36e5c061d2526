//! Runs that fail numerically, and a run stopped by SIGTERM, through the command line: exit
//! codes, the one-line message, `summary.json`, and the frames left on disk.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pdcontact-fail-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// A 1 × 1 × 0.5 m block (spacing 0.25) over a rigid plane 1 cm below it; `solver` is the
/// `[solver]` table's body, `extra` is appended.
fn scene(solver: &str, every: usize, velocity: f64, extra: &str) -> String {
    format!(
        r#"[solver]
{solver}
[output]
every = {every}
folder = "out"
[[body]]
name = "block"
generator = {{ shape = "box", min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 0.5], spacing = 0.25 }}
velocity = [0.0, 0.0, {velocity:?}]
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[body]]
name = "floor"
kind = "rigid"
generator = {{ shape = "plane", point = [0.0, 0.0, -0.01], normal = [0.0, 0.0, 1.0], size = 3.0 }}
{extra}
"#
    )
}

const CONTACT: &str = "[[contact]]\nslave = \"block\"\nmaster = \"floor\"\n";

/// Files listed by a `.pvd` or a `.vtm` (it must be complete XML).
fn listed_files(file: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(file).unwrap_or_else(|e| panic!("{file:?}: {e}"));
    assert!(text.starts_with("<?xml"), "{text}");
    assert!(
        text.trim_end().ends_with("</VTKFile>"),
        "incomplete: {text}"
    );
    text.lines()
        .filter_map(|l| l.split_once("file=\"").map(|(_, r)| r))
        .map(|r| r.split('"').next().expect("quoted").to_string())
        .collect()
}

/// Every listed frame (`frame_NNNNNN.vtm`) and every dataset it lists exists and is a
/// complete VTK XML file; nothing else is left (no temporary file, no unlisted frame).
fn check_frames(dir: &Path) -> Vec<String> {
    let files = if dir.join("run.pvd").exists() {
        listed_files(&dir.join("run.pvd"))
    } else {
        Vec::new()
    };
    let mut datasets = Vec::new();
    for f in &files {
        assert!(f.starts_with("frame_") && f.ends_with(".vtm"), "{f}");
        datasets.extend(listed_files(&dir.join(f)));
    }
    for f in &datasets {
        let text = std::fs::read(dir.join(f)).unwrap_or_else(|e| panic!("{f}: {e}"));
        let text = String::from_utf8_lossy(&text);
        assert!(
            text.starts_with("<?xml") || text.starts_with("<VTKFile"),
            "{f}"
        );
        assert!(text.trim_end().ends_with("</VTKFile>"), "{f} is incomplete");
    }
    for entry in std::fs::read_dir(dir).expect("folder").flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        assert!(!name.ends_with(".partial"), "temporary file left: {name}");
        assert!(!name.ends_with(".vtu"), "flat frame file: {name}");
        if name.ends_with(".vtm") {
            assert!(files.contains(&name), "{name} is not listed in run.pvd");
        }
        if entry.path().is_dir() {
            assert!(
                files.contains(&format!("{name}.vtm")),
                "{name}/ is not a listed frame"
            );
            for inner in std::fs::read_dir(entry.path())
                .expect("frame folder")
                .flatten()
            {
                let inner = format!("{name}/{}", inner.file_name().to_string_lossy());
                assert!(
                    datasets.contains(&inner),
                    "{inner} is not listed in a frame"
                );
            }
        }
    }
    files
}

struct Failure {
    message: String,
    summary: serde_json::Value,
    frames: Vec<String>,
}

/// Runs a scene that must fail: exit code 1, one line on stderr, summary.json with the error.
fn failing_run(case: &str, text: &str) -> Failure {
    let dir = temp_dir(case);
    std::fs::write(dir.join("scene.toml"), text).expect("scene");
    let out = Command::new(env!("CARGO_BIN_EXE_pdcontact"))
        .args(["run", "--quiet"])
        .arg(dir.join("scene.toml"))
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(1), "{case}: {err}");
    assert_eq!(err.lines().count(), 1, "{case}: {err}");
    let message = err
        .trim_end()
        .strip_prefix("error: run failed: ")
        .unwrap_or_else(|| panic!("{case}: {err}"))
        .to_string();
    let out = dir.join("out");
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out.join("summary.json")).expect("summary.json"),
    )
    .expect("json");
    assert_eq!(summary["converged"], false, "{case}");
    assert_eq!(summary["interrupted"], false, "{case}");
    let recorded = summary["error"].as_str().expect("error in summary.json");
    assert!(
        recorded.contains(&message),
        "{case}: {recorded} vs {message}"
    );
    let frames = check_frames(&out);
    let _ = std::fs::remove_dir_all(&dir);
    Failure {
        message,
        summary,
        frames,
    }
}

/// The step number a message names after `word` (e.g. "step 70").
fn step_in(message: &str, word: &str) -> usize {
    let rest = message
        .split_once(&format!("{word} "))
        .unwrap_or_else(|| panic!("no {word} in {message}"))
        .1;
    rest.split(|c: char| !c.is_ascii_digit())
        .next()
        .and_then(|d| d.parse().ok())
        .unwrap_or_else(|| panic!("no number after {word} in {message}"))
}

/// Frames `frame_NNNNNN.vtm` listed, as step numbers.
fn particle_steps(frames: &[String]) -> Vec<usize> {
    frames
        .iter()
        .filter_map(|f| f.strip_prefix("frame_")?.strip_suffix(".vtm")?.parse().ok())
        .collect()
}

/// A time step so large that the first step overflows: non-finite values.
#[test]
fn nan_from_a_huge_time_step() {
    let extra = "[[load]]\nbody = \"block\"\nset = \"top\"\nforce = [0.0, 0.0, -1e5]\n[[constraint]]\nbody = \"block\"\nset = \"bottom\"\nfix = [\"x\", \"y\", \"z\"]\n";
    let f = failing_run(
        "nan",
        &scene(
            "kind = \"explicit\"\nend_time = 1e300\ndt = 1e96",
            1,
            0.0,
            extra,
        ),
    );
    assert!(f.message.contains("non-finite"), "{}", f.message);
    assert_eq!(step_in(&f.message, "step"), 1);
    assert!(
        f.message.contains("likely cause: the time step"),
        "{}",
        f.message
    );
    // Nothing was good: no frame is listed.
    assert!(f.frames.is_empty(), "{:?}", f.frames);
}

/// 1.5 × the stable step (1.62 before the skin correction stiffened the block's surface
/// row): slow growth, caught by the energy balance; the frames before the
/// failure stay on disk.
#[test]
fn energy_growth_keeps_the_last_good_frame() {
    let f = failing_run(
        "energy",
        &scene(
            "kind = \"explicit\"\nend_time = 0.2\nsafety = 1.5",
            5,
            -1.0,
            CONTACT,
        ),
    );
    assert!(
        f.message.contains("energy grew") && f.message.contains("likely cause: the time step"),
        "{}",
        f.message
    );
    let step = step_in(&f.message, "step");
    let steps = particle_steps(&f.frames);
    let last = *steps.last().expect("frames before the failure");
    assert!(
        last < step && step - last <= 5,
        "last frame {last}, failed at {step}"
    );
    assert!(f.summary["outputs"]["last_frame"]
        .as_str()
        .expect("last_frame")
        .ends_with(&format!("frame_{last:06}.vtm")));
}

/// Twice the stable step: fast growth, caught the step it explodes.
#[test]
fn kinetic_energy_blow_up() {
    let f = failing_run(
        "kinetic",
        &scene(
            "kind = \"explicit\"\nend_time = 0.05\nsafety = 2.0",
            5,
            -1.0,
            CONTACT,
        ),
    );
    assert!(
        f.message.contains("kinetic energy exploded")
            && f.message.contains("above the stable step"),
        "{}",
        f.message
    );
    let step = step_in(&f.message, "step");
    assert!(particle_steps(&f.frames).iter().all(|&s| s < step));
    assert!(!f.frames.is_empty());
}

/// A block at 3 km/s crosses the contact window (half a spacing) in one step.
#[test]
fn missed_contact_of_a_fast_body() {
    let f = failing_run(
        "fast",
        &scene(
            "kind = \"explicit\"\nend_time = 0.001\ndt = 2e-5",
            1,
            -3000.0,
            CONTACT,
        ),
    );
    assert!(
        f.message.contains("missed contact at step")
            && f.message.contains("impact speed is too high"),
        "{}",
        f.message
    );
    let step = step_in(&f.message, "step");
    assert_eq!(particle_steps(&f.frames), (1..step).collect::<Vec<_>>());
}

/// A penalty with R = 1 nm is far too soft for 100 MN: the load pushes the block through.
#[test]
fn missed_contact_of_a_soft_penalty() {
    let extra =
        format!("{CONTACT}radius = 1e-9\n[[load]]\nbody = \"block\"\nforce = [0.0, 0.0, -1e8]\n");
    let f = failing_run("soft", &scene("kind = \"adr\"", 2, 0.0, &extra));
    assert!(
        f.message.contains("missed contact at iteration")
            && f.message.contains("penalty is too soft")
            && f.message.contains("the deepest: node")
            && f.message.contains("cut this load increment back 4 times"),
        "{}",
        f.message
    );
    assert!(f.summary["missed_contacts"].as_u64().expect("count") > 0);
}

/// A load of 1e12 N on a 1 GPa block: the out-of-balance force runs away.
#[test]
fn adr_divergence() {
    let extra = format!("{CONTACT}[[load]]\nbody = \"block\"\nforce = [0.0, 0.0, -1e12]\n");
    let f = failing_run("diverge", &scene("kind = \"adr\"", 50, 0.0, &extra));
    assert!(
        f.message.contains("ADR diverged at iteration") && f.message.contains("likely cause"),
        "{}",
        f.message
    );
    let step = step_in(&f.message, "iteration");
    let steps = particle_steps(&f.frames);
    assert!(
        !steps.is_empty() && steps.iter().all(|&s| s < step),
        "{steps:?}"
    );
}

/// ADR stopped by max_iterations before the tolerance: a failed run (exit 1), with its last
/// state written as the last frame, and the particle that carries the most of the force left.
#[test]
fn adr_without_convergence() {
    let extra = format!("{CONTACT}[[load]]\nbody = \"block\"\nforce = [0.0, 0.0, -1e5]\n");
    let f = failing_run(
        "noconv",
        &scene("kind = \"adr\"\nmax_iterations = 30", 10, 0.0, &extra),
    );
    assert!(
        f.message.contains("did not converge in 30 iterations")
            && f.message.contains("max_iterations"),
        "{}",
        f.message
    );
    // Where the force is left: the particle that carries the most of it.
    assert!(
        f.message.contains("the largest out-of-balance force")
            && f.message.contains("of \"block\" at ["),
        "{}",
        f.message
    );
    // After 30 iterations the block, 1 cm above the plane, has not reached it: the message
    // says the body touches nothing and is still moving, not only "too few iterations".
    assert!(
        f.message
            .contains("(75 particles about [0.5, 0.5, 0.25], the whole body) touches nothing")
            && f.message
                .contains("% of its load, 1.000e5 N, is out of balance")
            && f.message.contains("along [0.00, 0.00, -1.00]"),
        "{}",
        f.message
    );
    assert_eq!(f.summary["iterations"], 30);
    assert_eq!(particle_steps(&f.frames), vec![10, 20, 30]);
}

/// SIGTERM during a long explicit run: the process ends with 130, the collection lists only
/// complete frames, summary.json says interrupted, and VTK reads every frame.
#[test]
fn sigterm_ends_a_run_cleanly() {
    let dir = temp_dir("sigterm");
    // About 10^5 steps of 726 particles: far longer than the test waits.
    let text = r#"[solver]
kind = "explicit"
end_time = 10.0
[output]
every = 20
folder = "out"
[[body]]
name = "block"
generator = { shape = "box", min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 0.5], spacing = 0.1 }
velocity = [0.0, 0.0, -0.5]
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[body]]
name = "floor"
kind = "rigid"
generator = { shape = "plane", point = [0.0, 0.0, -0.001], normal = [0.0, 0.0, 1.0], size = 3.0 }
[[contact]]
slave = "block"
master = "floor"
"#;
    std::fs::write(dir.join("scene.toml"), text).expect("scene");
    let mut child = Command::new(env!("CARGO_BIN_EXE_pdcontact"))
        .args(["run", "--quiet"])
        .arg(dir.join("scene.toml"))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("starts");
    let out = dir.join("out");
    // Wait for a few frames, then stop it.
    let start = Instant::now();
    while !out.join("run.pvd").exists() && start.elapsed() < Duration::from_secs(20) {
        std::thread::sleep(Duration::from_millis(50));
    }
    std::thread::sleep(Duration::from_millis(1500));
    assert!(child.try_wait().expect("status").is_none(), "ended early");
    let sent = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(sent.success());
    let t0 = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().expect("status") {
            break s;
        }
        if t0.elapsed() > Duration::from_secs(20) {
            let _ = child.kill();
            panic!("the run did not stop within 20 s of SIGTERM");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let stderr = {
        use std::io::Read;
        let mut s = String::new();
        child
            .stderr
            .take()
            .expect("stderr")
            .read_to_string(&mut s)
            .expect("read");
        s
    };
    assert_eq!(status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("interrupted at step"), "{stderr}");

    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out.join("summary.json")).expect("summary.json"),
    )
    .expect("json");
    assert_eq!(summary["interrupted"], true);
    assert_eq!(summary["solver"]["interrupted"], true);
    assert_eq!(summary["converged"], false);
    assert!(summary["error"].is_null());
    let iterations = summary["iterations"].as_u64().expect("iterations") as usize;
    let frames = check_frames(&out);
    let steps = particle_steps(&frames);
    assert!(steps.len() >= 2, "{steps:?}");
    // The last frame is the state the run stopped in.
    assert_eq!(steps.last().copied(), Some(iterations));
    assert!(
        iterations < 100_000,
        "the run was not stopped early: {iterations}"
    );

    // VTK's own reader loads every listed frame, when Python's vtk is there.
    if common::python_has("vtk") {
        let check = Command::new("python3")
            .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("tools/check_vtk.py"))
            .arg("run")
            .arg(&out)
            .output()
            .expect("python3 runs");
        assert!(
            check.status.success(),
            "{}{}",
            String::from_utf8_lossy(&check.stdout),
            String::from_utf8_lossy(&check.stderr)
        );
    } else {
        common::skipped(
            "VTK reader check",
            "python3 with vtk not found (pip install vtk)",
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Short-range contact: a block thrown so fast at a deformable floor that its bottom particles
/// go from above the repulsion zone to below the floor's surface in one step.
#[test]
fn short_range_missed_contact_of_a_fast_body() {
    let text = r#"[solver]
kind = "explicit"
end_time = 0.001
dt = 2e-5
[output]
every = 1
folder = "out"
[[body]]
name = "block"
generator = { shape = "box", min = [0.0, 0.0, 0.35], max = [1.0, 1.0, 0.85], spacing = 0.25 }
velocity = [0.0, 0.0, -25000.0]
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[body]]
name = "floor"
generator = { shape = "box", min = [-0.25, -0.25, -0.5], max = [1.25, 1.25, 0.0], spacing = 0.25 }
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[constraint]]
body = "floor"
set = "bottom"
fix = ["x", "y", "z"]
[[contact]]
slave = "block"
master = "floor"
method = "short-range"
"#;
    let f = failing_run("short-range-fast", text);
    assert!(
        f.message.contains("missed contact at step")
            && f.message.contains("went through the master's surface")
            && f.message.contains("d = 3.375e-1 m")
            && f.message.contains("crossed the repulsion zone in one step"),
        "{}",
        f.message
    );
}

/// A model larger than the memory the process may use (here `ulimit -v`; a cgroup's limit
/// alike) is refused before its bonds are made, with what it would need and what to do,
/// instead of being killed part way: exit code 2, nothing written.
#[test]
fn a_model_past_the_memory_limit_is_refused_before_its_bonds() {
    let dir = temp_dir("memory");
    // 51 × 51 × 26 particles: about 0.4 GB with their bonds, against a 256 MB address space.
    let text =
        scene("kind = \"adr\"", 10, 0.0, CONTACT).replace("spacing = 0.25", "spacing = 0.02");
    std::fs::write(dir.join("scene.toml"), text).expect("scene");
    let out = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -v 250000 && exec '{}' run --quiet scene.toml",
            env!("CARGO_BIN_EXE_pdcontact")
        ))
        .current_dir(&dir)
        .env("RAYON_NUM_THREADS", "1")
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    for said in [
        "body \"block\"",
        "67626 particles",
        "past the 256 MB it may use (its address-space limit (ulimit -v))",
        "mpirun -n",
    ] {
        assert!(err.contains(said), "{said:?} in {err}");
    }
    assert!(!dir.join("out").join("summary.json").exists());
}
