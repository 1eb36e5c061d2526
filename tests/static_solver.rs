//! The static solver (`[solver] kind = "static"`, Newton-Raphson with a matrix-free tangent)
//! against ADR on the same scenes, and against Hertz.

mod common;

use std::path::{Path, PathBuf};

use pdcontact::run::{run_scene, RunOptions, RunSummary};
use pdcontact::scene::Scene;
use pdcontact::Error;

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pdcontact-static-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
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

/// The scene `text(kind)` run by ADR and by the static solver, each into its own folder of
/// `dir`: their summaries.
fn adr_and_static(dir: &Path, text: impl Fn(&str) -> String) -> (RunSummary, RunSummary) {
    let run = |kind: &str| {
        let scene = Scene::parse(&text(kind), "scene.toml", dir).expect("scene");
        run_scene(&scene, &quiet(&dir.join(kind))).expect("runs").1
    };
    (run("adr"), run("static"))
}

fn mesh(p: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(p)
        .display()
        .to_string()
}

/// The scene `validate --mesh` writes for the stored gmsh tet4 sphere (R = 1 m, 10,537
/// particles, whole sphere, a stiff penalty), Hertz a = 0.3 m, with the solver `kind`.
fn tet_sphere(kind: &str) -> String {
    format!(
        r#"
[solver]
kind = "{kind}"
tolerance = 1e-4
[output]
every = 1000000
[[body]]
name = "sphere"
mesh = "{mesh}"
kinematics = "small"
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[body]]
name = "plane"
kind = "rigid"
generator = {{ shape = "plane", point = [-0.00013051085395920925, -0.00012203344278993722, -1.0], normal = [0.0, 0.0, 1.0], size = 3.0 }}
[[load]]
body = "sphere"
force = [0.0, 0.0, -3.84e7]
[[contact]]
slave = "sphere"
master = "plane"
radius = 1e4
"#,
        mesh = mesh("meshes/sphere_tet4_h007.msh")
    )
}

/// Same equilibrium as ADR at the same tolerance: the fitted contact radius and peak within
/// 0.05 points of each other, both within 3 % / 5 % of Hertz (a = 0.3 m,
/// p0 = 3P/(2πa²)); measured: ADR 1,187 iterations, static 41 Newton iterations with 476
/// conjugate-gradient iterations and 103 force evaluations; radius 0.295029 / 0.295027 m,
/// peak 2.09833e8 / 2.09834e8 Pa. Since a whole step that brings slaves into contact is
/// taken whole, 25 Newton iterations (`validate --mesh meshes/sphere_tet4_h007.msh
/// --refine 0 --solver static`): the contact no longer grows one ring per iteration; 20 with
/// the coarse space; 12 since each solve is repeated with the contacts its step makes and the
/// stabilisation lets the load move the body a spacing (docs/PERFORMANCE.md, "The contacts a
/// Newton step makes").
#[test]
fn static_matches_adr_and_hertz_on_the_stored_tet_sphere() {
    let dir = temp_dir("tet");
    let (adr, newton) = adr_and_static(&dir, tet_sphere);
    assert!(adr.converged && newton.converged);
    assert_eq!(newton.solver.solver, "static");
    assert!(newton.residual < 1e-4, "{}", newton.residual);
    let (a, p0) = (0.3, 3.0 * 3.84e7 / (2.0 * std::f64::consts::PI * 0.09));
    let (ra, rs) = (adr.contact_radius, newton.contact_radius);
    let (pa, ps) = (adr.peak_pressure, newton.peak_pressure);
    assert!((rs - ra).abs() / a < 5e-4, "radius static {rs} adr {ra}");
    assert!((ps - pa).abs() / p0 < 5e-4, "peak static {ps} adr {pa}");
    assert!((rs / a - 1.0).abs() < 0.03, "radius {rs}");
    assert!((ps / p0 - 1.0).abs() < 0.05, "peak {ps} against {p0}");
    assert!(
        newton.force_balance_error < 1e-3,
        "{}",
        newton.force_balance_error
    );
    assert!(
        newton.solver.iterations <= 16,
        "{} Newton iterations",
        newton.solver.iterations
    );
    // Every force evaluation and tangent product is counted.
    assert!(newton.solver.force_evaluations > newton.solver.iterations);
    assert!(newton.solver.linear_iterations >= newton.solver.iterations);
}

/// What the static solver does not handle is refused before it solves, naming what to use.
#[test]
fn static_refuses_the_short_range_method_by_name() {
    let dir = temp_dir("short");
    let text = r#"
[solver]
kind = "static"
[output]
every = 100000
[[body]]
name = "low"
generator = { shape = "box", min = [0.0, 0.0, -0.4], max = [0.4, 0.4, 0.0], spacing = 0.1 }
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[body]]
name = "high"
generator = { shape = "box", min = [0.0, 0.0, 0.01], max = [0.4, 0.4, 0.41], spacing = 0.1 }
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[constraint]]
body = "low"
set = "bottom"
fix = ["x", "y", "z"]
[[load]]
body = "high"
force = [0.0, 0.0, -1e5]
[[contact]]
slave = "high"
master = "low"
method = "short-range"
"#;
    let scene = Scene::parse(text, "short.toml", &dir).expect("scene");
    match run_scene(&scene, &quiet(&dir)) {
        Err(Error::Input(m)) => assert!(m.contains("point-to-surface") && m.contains("adr"), "{m}"),
        other => panic!(
            "expected an input error, got {:?}",
            other.map(|r| r.1.converged)
        ),
    }
}

/// Displacement control: a rigid plane driven down onto a block (built-in box, fixed at its
/// bottom) in four increments. The static solver walks the same path as ADR, increment by
/// increment, and records the same load-displacement curve: each increment's reaction within
/// 1e-3 of ADR's, rising.
#[test]
fn static_walks_a_driven_body_s_path_as_adr_does() {
    let dir = temp_dir("driven");
    let scene = |kind: &str| {
        format!(
            r#"
[solver]
kind = "{kind}"
tolerance = 1e-5
load_steps = 4
[output]
every = 1000000
[[body]]
name = "block"
generator = {{ shape = "box", min = [0.0, 0.0, 0.0], max = [0.1, 0.1, 0.05], spacing = 0.01 }}
kinematics = "small"
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[constraint]]
body = "block"
set = "bottom"
fix = ["x", "y", "z"]
[[body]]
name = "punch"
kind = "rigid"
generator = {{ shape = "plane", point = [0.05, 0.05, 0.05], normal = [0.0, 0.0, -1.0], size = 0.3 }}
motion = "displacement"
displacement = [0.0, 0.0, -5e-5]
[[contact]]
slave = "block"
master = "punch"
radius = 1.0
"#
        )
    };
    let (adr, newton) = adr_and_static(&dir, scene);
    assert!(adr.converged && newton.converged);
    let (a, s) = (&adr.solver.increments, &newton.solver.increments);
    assert_eq!(a.len(), 4);
    assert_eq!(s.len(), 4);
    for (p, q) in a.iter().zip(s) {
        assert!((p.factor - q.factor).abs() < 1e-12);
        assert_eq!(p.displacement, q.displacement);
        let (fa, fs) = (p.reaction[2], q.reaction[2]);
        assert!(
            fa > 0.0 && (fs / fa - 1.0).abs() < 1e-3,
            "ADR {fa} static {fs}"
        );
    }
    assert!(s.windows(2).all(|w| w[1].reaction[2] > w[0].reaction[2]));
    assert!(dir.join("static").join("load_displacement.svg").exists());
}

/// A hex sphere cap (R = 1 m, a = 0.15 m, a/Δ = 5) loaded onto a block of the same material
/// fixed at its bottom, quarter models, one pass with the flat block the slave: the sphere is
/// held by nothing but the contact, and it is the master. The stabilisation that carries a
/// loose body to its first touch holds the master's nodes as it holds the slaves (before, the
/// static solver took 134 Newton iterations here, and at a/Δ = 10 it found no descent
/// direction). Measured: static 20 Newton iterations, ADR 649 iterations, the same
/// equilibrium.
#[test]
fn a_loose_master_reaches_its_contact_as_a_loose_slave_does() {
    let scene = |kind: &str| {
        format!(
            r#"[solver]
kind = "{kind}"
tolerance = 1e-5
max_iterations = 100000
[output]
every = 1000000
[[body]]
name = "sphere"
generator = {{ shape = "sphere_cap", radius = 1.0, half_width = 0.45, depth = 0.45, spacing = 0.03 }}
kinematics = "small"
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[symmetry]]
body = "sphere"
axis = "x"
[[symmetry]]
body = "sphere"
axis = "y"
[[load]]
body = "sphere"
force = [0.0, 0.0, -6.0e5]
[[body]]
name = "block"
generator = {{ shape = "box", min = [0.0, 0.0, -1.45], max = [0.45, 0.45, -1.0], spacing = 0.03 }}
kinematics = "small"
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[constraint]]
body = "block"
set = "bottom"
fix = ["x", "y", "z"]
[[symmetry]]
body = "block"
axis = "x"
[[symmetry]]
body = "block"
axis = "y"
[[contact]]
slave = "block"
master = "sphere"
radius = 100.0
"#
        )
    };
    let dir = temp_dir("loose-master");
    let (adr, newton) = adr_and_static(&dir, scene);
    assert!(adr.converged && newton.converged);
    assert!(
        newton.solver.iterations <= 40,
        "{} Newton iterations",
        newton.solver.iterations
    );
    let (ra, rs) = (adr.contact_radius, newton.contact_radius);
    let (pa, ps) = (adr.peak_pressure, newton.peak_pressure);
    assert!((rs / ra - 1.0).abs() < 1e-3, "radius static {rs} adr {ra}");
    assert!((ps / pa - 1.0).abs() < 1e-3, "peak static {ps} adr {pa}");
    assert!(newton.force_balance_error < 1e-3);
}

/// A body with nothing in contact (the stored gmsh tet4 bar, an eighth of 3.2 × 1.6 × 1.6 m
/// with three symmetry planes, pulled by 1 MPa on its end): the coarse space has no springs
/// to add to its bonds' part, and the static solver takes the bonds' factor alone (it
/// panicked on nalgebra's solve of the empty update before). Its end moves as ADR's and as
/// `σ L / E` says.
#[test]
fn the_static_solver_takes_a_body_with_nothing_in_contact() {
    let text = |kind: &str| common::bar_scene("bond-based", 0.25, kind, "small", true, 1e6);
    let dir = temp_dir("no-contact");
    let end = |kind: &str| {
        let scene = Scene::parse(&text(kind), "scene.toml", &dir).expect("scene");
        let (model, summary) = run_scene(&scene, &quiet(&dir.join(kind))).expect("runs");
        assert!(summary.converged, "{kind}: {summary:?}");
        let pd = model.bodies[0].as_pd().expect("deformable");
        let at: Vec<usize> = (0..pd.len())
            .filter(|&i| (pd.reference[i].x - 1.6).abs() < 1e-9)
            .collect();
        let u = at.iter().map(|&i| pd.u[i].x).sum::<f64>() / at.len() as f64;
        (u, summary.solver.iterations)
    };
    let (adr, _) = end("adr");
    let (newton, iterations) = end("static");
    eprintln!("end: ADR {adr:e}, static {newton:e} in {iterations} Newton iterations");
    assert!(
        (newton / adr - 1.0).abs() < 1e-4,
        "static {newton} ADR {adr}"
    );
    assert!(iterations <= 10, "{iterations} Newton iterations");
    // σ L / E = 1.6 mm.
    assert!((newton / 1.6e-3 - 1.0).abs() < 0.03, "end {newton}");
}
