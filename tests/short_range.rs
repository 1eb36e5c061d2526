//! The short-range contact method on small scenes: a block pressed on a block, the forces it
//! balances and the pressure it carries, and the scene errors of the method.

use std::path::PathBuf;

use pdcontact::run::{run_scene, RunOptions};
use pdcontact::scene::Scene;

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pdcontact-sr-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// A 0.4 m cube (Δ = 0.1 m) held 0.12 m above a 1 × 1 × 0.4 m block fixed at its bottom,
/// pressed down by `load` N on its top face.
fn punch_scene(load: f64, method: &str) -> String {
    format!(
        r#"[solver]
kind = "adr"
tolerance = 1e-5
max_iterations = 100000
[output]
every = 1000000
[[body]]
name = "punch"
generator = {{ shape = "box", min = [0.3, 0.3, 0.52], max = [0.7, 0.7, 0.92], spacing = 0.1 }}
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[body]]
name = "block"
generator = {{ shape = "box", min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 0.4], spacing = 0.1 }}
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[load]]
body = "punch"
set = "top"
force = [0.0, 0.0, -{load:e}]
[[constraint]]
body = "block"
set = "bottom"
fix = ["x", "y", "z"]
[[contact]]
slave = "punch"
master = "block"
{method}
"#
    )
}

#[test]
fn short_range_punch_balances_and_carries_its_load() {
    let dir = temp_dir("punch");
    let load = 4.0e6; // 25 MPa over the 0.16 m² face
    let scene = Scene::parse(
        &punch_scene(load, "method = \"short-range\""),
        "punch.toml",
        &dir,
    )
    .expect("scene");
    let (model, summary) = run_scene(
        &scene,
        &RunOptions {
            output: Some(dir.clone()),
            quiet: true,
            stop: None,
            comm: None,
            study: false,
        },
    )
    .expect("runs");
    assert!(summary.converged);
    assert!(
        summary.force_balance_error < 1e-3,
        "{}",
        summary.force_balance_error
    );
    // Every bottom particle of the punch touches, and the block takes what the punch gives.
    assert!(summary.contact_pairs >= 25, "{}", summary.contact_pairs);
    let punch = model.bodies[0].as_pd().expect("deformable");
    let block = model.bodies[1].as_pd().expect("deformable");
    let on_punch: f64 = punch.contact_force.iter().map(|f| f.z).sum();
    let on_block: f64 = block.contact_force.iter().map(|f| f.z).sum();
    assert!((on_punch / load - 1.0).abs() < 1e-3, "{on_punch}");
    assert!((on_block / on_punch + 1.0).abs() < 1e-9, "{on_block}");
    // The centre particle of the punch's face carries the mean pressure within 30 %.
    let mean = load / 0.16;
    let centre = (0..punch.len())
        .min_by(|&a, &b| {
            let d = |i: usize| {
                let p = punch.case.particles.position[i];
                (p.x - 0.5).powi(2) + (p.y - 0.5).powi(2) + (p.z - 0.52).powi(2)
            };
            d(a).total_cmp(&d(b))
        })
        .expect("particles");
    let p_centre = punch.contact_force[centre].z / (0.1 * 0.1);
    assert!(
        (p_centre / mean - 1.0).abs() < 0.3,
        "centre pressure {p_centre:.3e} Pa, mean {mean:.3e} Pa"
    );
    // The surfaces stay about d = 1.35 Δ apart, less the overlap that carries the load.
    let gap = punch.position(centre).z
        - (0..block.len())
            .map(|i| block.position(i).z)
            .fold(f64::NEG_INFINITY, f64::max);
    assert!(gap > 0.08 && gap < 0.135, "gap {gap}");
}

#[test]
fn short_range_refuses_a_rigid_master_and_a_penalty_radius() {
    let dir = temp_dir("errors");
    let rigid = r#"[solver]
kind = "adr"
[[body]]
name = "ball"
generator = { shape = "sphere", radius = 0.5, spacing = 0.1 }
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[body]]
name = "floor"
kind = "rigid"
generator = { shape = "plane", point = [0.0, 0.0, -0.5], normal = [0.0, 0.0, 1.0], size = 2.0 }
[[contact]]
slave = "ball"
master = "floor"
method = "short_range"
"#;
    let e = Scene::parse(rigid, "rigid.toml", &dir)
        .expect_err("rigid master")
        .to_string();
    assert!(e.starts_with("rigid.toml:17:"), "{e}");
    assert!(e.contains("rigid master \"floor\""), "{e}");
    let radius = punch_scene(1e6, "method = \"short-range\"\nradius = 1.0");
    let e = Scene::parse(&radius, "radius.toml", &dir)
        .expect_err("radius")
        .to_string();
    assert!(e.contains("no penalty radius"), "{e}");
    let unknown = punch_scene(1e6, "method = \"node-to-node\"");
    let e = Scene::parse(&unknown, "unknown.toml", &dir)
        .expect_err("unknown method")
        .to_string();
    assert!(e.contains("short-range"), "{e}");
}
