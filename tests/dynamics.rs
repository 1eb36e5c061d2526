//! Whole runs through the library: explicit impact, stable step, several bodies.

use std::path::{Path, PathBuf};

use pdcontact::run::{run_scene, RunOptions};
use pdcontact::scene::Scene;
use pdcontact::Error;

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pdcontact-dyn-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

fn mesh(p: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(p)
        .display()
        .to_string()
}

fn quiet(dir: &Path) -> RunOptions {
    RunOptions {
        output: Some(dir.to_path_buf()),
        quiet: true,
        stop: None,
        comm: None,
        study: false,
    }
}

/// The sphere dropped onto the rigid plane at 1 m/s (explicit): it bounces off elastically,
/// no contact is missed, and the total energy (kinetic + strain + contact) is conserved.
fn drop_scene(safety: f64) -> String {
    format!(
        r#"
[solver]
kind = "explicit"
end_time = 0.1
safety = {safety}
stop_after_rebound = true
[output]
every = 100000
[[body]]
name = "ball"
mesh = "{mesh}"
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
        mesh = mesh("meshes/sphere_r1_d012.msh")
    )
}

#[test]
fn explicit_drop_conserves_energy() {
    let dir = temp_dir("drop");
    let scene = Scene::parse(&drop_scene(0.8), "drop.toml", &dir).expect("scene");
    let (model, summary) = run_scene(&scene, &quiet(&dir)).expect("runs");
    assert!(summary.solver.rebounded, "{summary:?}");
    assert_eq!(summary.missed_contacts, 0);
    assert!(
        summary.solver.energy_drift < 0.01,
        "energy drift {}",
        summary.solver.energy_drift
    );
    // The energy's terms at the start and the end balance too, and `run`'s last line says so.
    let [start, end] = summary.solver.energy.expect("an explicit run's energy");
    assert!(start.kinetic > 0.0 && end.fracture == 0.0);
    let at_end = (end.total() - start.total()).abs() / start.total().abs();
    assert!(at_end < 0.01, "{at_end}");
    let line = summary.result_line();
    assert!(
        line.contains("steps to t = ") && line.contains(" J: drift "),
        "{line}"
    );
    // An elastic bounce: the sphere leaves at (nearly) the speed it came with.
    let pd = model.bodies[0].as_pd().expect("deformable");
    let momentum: f64 = pd.v.iter().zip(&pd.mass).map(|(v, m)| v.z * m).sum();
    let mass: f64 = pd.mass.iter().sum();
    let vz = momentum / mass;
    assert!((vz - 1.0).abs() < 0.02, "rebound speed {vz}");
}

#[test]
fn unstable_time_step_is_caught() {
    let dir = temp_dir("unstable");
    let scene = Scene::parse(&drop_scene(3.0), "drop.toml", &dir).expect("scene");
    match run_scene(&scene, &quiet(&dir)) {
        Err(Error::Numerical(msg)) => {
            assert!(msg.contains("time step dt ="), "{msg}");
            assert!(msg.contains("step "), "{msg}");
        }
        other => panic!(
            "3x the stable step was not caught: {:?}",
            other.map(|r| r.1)
        ),
    }
    // summary.json says what happened.
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).expect("summary"))
            .expect("json");
    assert_eq!(s["converged"], false);
    assert!(s["error"].as_str().expect("error").contains("unstable"));
}

/// A quarter of a sphere's cap thrown slowly at a rigid plane: the one particle it lands on
/// sits on both symmetry planes and carries a quarter of its force, and the contact energy
/// must count only that quarter, or the energy balance reports growth that is not there.
#[test]
fn contact_on_symmetry_planes_keeps_the_energy_balance() {
    let dir = temp_dir("quarter-impact");
    let text = r#"
[solver]
kind = "explicit"
end_time = 2e-3
[output]
every = 100000
[[body]]
name = "cap"
generator = { shape = "sphere_cap", radius = 1.0, half_width = 0.9, depth = 0.9, spacing = 0.12 }
kinematics = "small"
velocity = [0.0, 0.0, -0.1]
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[body]]
name = "plane"
kind = "rigid"
generator = { shape = "plane", point = [0.0, 0.0, -1.0], normal = [0.0, 0.0, 1.0], size = 2.0 }
[[contact]]
slave = "cap"
master = "plane"
[[symmetry]]
body = "cap"
axis = "x"
[[symmetry]]
body = "cap"
axis = "y"
"#;
    let scene = Scene::parse(text, "quarter.toml", &dir).expect("scene");
    let (_, summary) = run_scene(&scene, &quiet(&dir)).expect("runs");
    assert!(summary.contact_pairs > 0, "{summary:?}");
    assert!(
        summary.solver.energy_drift < 1e-4,
        "energy drift {}",
        summary.solver.energy_drift
    );
}

/// Two deformable spheres (R = 0.5 m, generator spacing 0.08) stacked on a rigid floor,
/// quarter models, the upper one on the lower with two passes: both held only by contact.
/// Loads 4e5 N (upper) and 2e5 N (lower) on the quarters; solver `kind`.
fn stacked_spheres(kind: &str) -> String {
    format!(
        r#"
[solver]
kind = "{kind}"
tolerance = 1e-4
max_iterations = 50000
[output]
every = 100000
[[body]]
name = "low"
generator = {{ shape = "sphere", radius = 0.5, spacing = 0.08, center = [0.0, 0.0, -0.5] }}
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[body]]
name = "high"
generator = {{ shape = "sphere", radius = 0.5, spacing = 0.08, center = [0.0, 0.0, 0.5] }}
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[body]]
name = "floor"
kind = "rigid"
generator = {{ shape = "plane", point = [0.0, 0.0, -1.0], normal = [0.0, 0.0, 1.0], size = 2.0 }}
[[load]]
body = "low"
force = [0.0, 0.0, -2e5]
[[load]]
body = "high"
force = [0.0, 0.0, -4e5]
[[contact]]
slave = "high"
master = "low"
two_pass = true
radius = 0.5
[[contact]]
slave = "low"
master = "floor"
radius = 0.5
[[symmetry]]
body = "low"
axis = "x"
[[symmetry]]
body = "low"
axis = "y"
[[symmetry]]
body = "high"
axis = "x"
[[symmetry]]
body = "high"
axis = "y"
"#
    )
}

/// Two spheres stacked on a plane, quarter models by symmetry: deformable–deformable (two
/// passes) and deformable–rigid contact, loads balanced through the stack; by ADR and by the
/// static solver, both held only by contact (measured: ADR 756 iterations; static 9 Newton
/// iterations, 716 conjugate-gradient iterations).
#[test]
fn two_spheres_on_a_plane_balance() {
    for kind in ["adr", "static"] {
        let dir = temp_dir(&format!("stack-{kind}"));
        let text = stacked_spheres(kind);
        let scene = Scene::parse(&text, "stack.toml", &dir).expect("scene");
        let (model, summary) = run_scene(&scene, &quiet(&dir)).expect("runs");
        assert!(summary.converged, "{kind}");
        assert!(
            summary.force_balance_error < 1e-3,
            "{kind}: {}",
            summary.force_balance_error
        );
        // The floor carries both loads.
        assert!(
            (summary.total_contact_force[2] / 6e5 - 1.0).abs() < 1e-3,
            "{kind}: {:?}",
            summary.total_contact_force
        );
        // The upper sphere rests on the lower one: its contact force balances its own load.
        let high = model.bodies[1].as_pd().expect("deformable");
        let on_high: f64 = high.contact_force.iter().map(|f| f.z).sum();
        assert!(
            (on_high / 4e5 - 1.0).abs() < 2e-3,
            "{kind}: force on the upper sphere {on_high}"
        );
    }
}

/// A sphere pressed into a deformable block whose surface nodes lie under the sphere's pole
/// and meridians (single pass, Hertz penalty of the default radius). The block dents, its
/// segments tilt, and slaves over the dent's bottom node and edges project outside every
/// segment they are pressed into; they must still be held (along the mean normal there),
/// or they sink through the block and the run never balances.
#[test]
fn sphere_into_a_deformable_block_over_its_nodes() {
    let dir = temp_dir("dent");
    let text = r#"
[solver]
kind = "adr"
max_iterations = 20000
[output]
every = 100000
[[body]]
name = "ball"
generator = { shape = "sphere", radius = 0.3, spacing = 0.05, center = [0.0, 0.0, 0.3] }
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[body]]
name = "block"
generator = { shape = "box", min = [-0.5, -0.5, -0.3], max = [0.5, 0.5, 0.0], spacing = 0.0625 }
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[constraint]]
body = "block"
set = "bottom"
fix = ["x", "y", "z"]
[[load]]
body = "ball"
set = "top"
force = [0.0, 0.0, -1e5]
[[contact]]
slave = "ball"
master = "block"
"#;
    // Two passes: the summary's contact force is still the force on the slave body.
    // (The ball held laterally: with two passes the block's slaves push on its curved
    // surface, and a frictionless ball under a dead load has no lateral stiffness.)
    let two = format!(
        "{text}two_pass = true\n[[constraint]]\nbody = \"ball\"\nset = \"ball\"\nfix = [\"x\", \"y\"]\n"
    );
    let scene = Scene::parse(&two, "dent2.toml", &dir).expect("scene");
    let (_, summary) = run_scene(&scene, &quiet(&dir)).expect("runs");
    assert!(summary.converged, "residual {}", summary.residual);
    assert!(
        (summary.total_contact_force[2] / 1e5 - 1.0).abs() < 2e-3,
        "two passes: {:?}",
        summary.total_contact_force
    );
    let scene = Scene::parse(text, "dent.toml", &dir).expect("scene");
    let (model, summary) = run_scene(&scene, &quiet(&dir)).expect("runs");
    assert!(summary.converged, "residual {}", summary.residual);
    assert!(
        summary.force_balance_error < 2e-3,
        "{}",
        summary.force_balance_error
    );
    assert!(
        (summary.total_contact_force[2] / 1e5 - 1.0).abs() < 2e-3,
        "{:?}",
        summary.total_contact_force
    );
    // The pole, over the block's node at the origin, carries the largest contact force and
    // is pushed straight up.
    let ball = model.bodies[0].as_pd().expect("deformable");
    let pole = (0..ball.len())
        .min_by(|&i, &j| ball.reference[i].z.total_cmp(&ball.reference[j].z))
        .expect("particles");
    let f = ball.contact_force[pole];
    let largest = ball.contact_force.iter().map(|f| f.z).fold(0.0, f64::max);
    assert!(f.z > 0.99 * largest, "pole {f:?}, largest {largest}");
    assert!(f.x.abs() + f.y.abs() < 1e-6 * f.z, "pole {f:?}");
}
