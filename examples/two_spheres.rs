//! Hertz between two deformable spheres: runs a scene and compares each body's contact
//! pressure with Hertz's (METHOD.md §7: 1/R* = 1/R1 + 1/R2, 1/E* = Σ(1 − ν²)/E), as
//! docs/VALIDATION.md, "Two deformable bodies", reports it.
//!
//!     cargo run --release --example two_spheres -- SCENE OUT P R1 R2 E1 E2 [NU1 [NU2]]
//!
//! P is the load on the whole sphere (a quarter model carries P/4); ν is 0.25 by default, the
//! second body's the first's unless given.

use std::path::PathBuf;

use pdcontact::output::analysis::{contact_patch, elliptic_accuracy, hertz_sphere};
use pdcontact::run::{run_scene, RunOptions};
use pdcontact::scene::Scene;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 7 {
        return Err("usage: two_spheres SCENE OUT P R1 R2 E1 E2 [NU1 [NU2]]".into());
    }
    let num = |k: usize| args[k].parse::<f64>();
    let (load, r1, r2, e1, e2) = (num(2)?, num(3)?, num(4)?, num(5)?, num(6)?);
    let nu1 = if args.len() > 7 { num(7)? } else { 0.25 };
    let nu2 = if args.len() > 8 { num(8)? } else { nu1 };
    let r_star = 1.0 / (1.0 / r1 + 1.0 / r2);
    let e_star = 1.0 / ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2);
    let (a, p0) = hertz_sphere(load, r_star, e_star);
    let scene = Scene::load(&PathBuf::from(&args[0]))?;
    let (model, summary) = run_scene(
        &scene,
        &RunOptions {
            output: Some(PathBuf::from(&args[1])),
            quiet: true,
            stop: None,
            comm: None,
            study: false,
        },
    )?;
    println!(
        "{}: {} particles, {} iterations, converged {}, residual {:.2e}, {:.1} s; Hertz a = {a:.4} m, p0 = {p0:.4e} Pa",
        args[0],
        summary.particles,
        summary.iterations,
        summary.converged,
        summary.residual,
        summary.wall_seconds
    );
    let applied = nalgebra::Vector3::from(summary.applied_load);
    let along = applied.normalize();
    for (k, body) in model.bodies.iter().enumerate() {
        let Some(patch) = contact_patch(&model, k, None) else {
            continue;
        };
        let acc = elliptic_accuracy(&patch, a, p0);
        println!(
            "  {:<8} MRE {:.2} % ({} particles within 0.8a), radius {:+.2} %, peak {:+.2} %, contact force / load - 1 = {:.1e}",
            body.name(),
            100.0 * acc.mre,
            acc.samples,
            100.0 * acc.radius_error,
            100.0 * (patch.peak / p0 - 1.0),
            (patch.force.dot(&along) / applied.norm()).abs() - 1.0
        );
    }
    Ok(())
}
