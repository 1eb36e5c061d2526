//! Two deformable bodies in contact, meshed as users mesh them (docs/VALIDATION.md, "Two
//! deformable bodies"): two gmsh-default tet4 spheres (R = 1 m, h = 0.06 m, quarter models,
//! `meshes/two_spheres_*_h006.geo`) pressed together so that Hertz's contact radius for two
//! identical spheres is a = 0.3 m (METHOD.md §7: R* = R/2, E* = E/(2(1 − ν²))). Before the
//! contact fixes of that section neither solver converged on such a pair.

mod common;

use std::path::{Path, PathBuf};

use pdcontact::output::analysis::{contact_patch, elliptic_accuracy, hertz_sphere};
use pdcontact::run::{check_scene, run_scene, RunOptions, RunSummary};
use pdcontact::scene::Scene;

const YOUNGS: f64 = 1e9;
const POISSON: f64 = 0.25;
/// The load on the whole upper sphere; the quarter model carries a quarter.
const LOAD: f64 = 3.84e7;

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pdcontact-two-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

fn mesh(name: &str) -> String {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("meshes")
        .join(name);
    toml_string(&p)
}

fn toml_string(p: &Path) -> String {
    format!("{:?}", p.display().to_string())
}

/// The scene of `tools/gmsh_two_spheres.py` on the stored meshes: the lower sphere
/// deformable (two passes or one) or a rigid plane at its pole; `lower = "tet10"` takes the
/// tet10 pair (h = 0.1 m, every node a particle) for both spheres.
fn scene(kind: &str, lower: &str, two_pass: bool) -> String {
    let (upper, lower_mesh, order) = if lower == "tet10" {
        (
            mesh("two_spheres_upper_tet10_h01.msh"),
            mesh("two_spheres_lower_tet10_h01.msh"),
            "second_order = \"all-nodes\"\n",
        )
    } else {
        (
            mesh("two_spheres_upper_h006.msh"),
            mesh("two_spheres_lower_h006.msh"),
            "",
        )
    };
    let lower_body = match lower {
        "rigid" => r#"[[body]]
name = "lower"
kind = "rigid"
generator = { shape = "plane", point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0], size = 3.0 }
"#
        .to_string(),
        _ => format!(
            r#"[[body]]
name = "lower"
mesh = {lower_mesh}
kinematics = "small"
{order}[body.material]
youngs_modulus = {YOUNGS:e}
poisson_ratio = {POISSON}
density = 1000.0
[[symmetry]]
body = "lower"
axis = "x"
[[symmetry]]
body = "lower"
axis = "y"
[[symmetry]]
body = "lower"
axis = "z"
at = -1.0
keep = "positive"
"#
        ),
    };
    format!(
        r#"[solver]
kind = "{kind}"
tolerance = 1e-4
max_iterations = 20000
[output]
every = 1000000
[[body]]
name = "upper"
mesh = {upper}
kinematics = "small"
{order}[body.material]
youngs_modulus = {YOUNGS:e}
poisson_ratio = {POISSON}
density = 1000.0
[[symmetry]]
body = "upper"
axis = "x"
[[symmetry]]
body = "upper"
axis = "y"
{lower_body}
[[load]]
body = "upper"
force = [0.0, 0.0, {quarter:e}]
[[contact]]
slave = "upper"
master = "lower"
radius = 2290.0
two_pass = {two_pass}
"#,
        quarter = -LOAD / 4.0
    )
}

/// Per deformable body: (MRE, radius error, contact force along the load over the load − 1).
struct Figures {
    summary: RunSummary,
    bodies: Vec<(f64, f64, f64)>,
}

fn run(name: &str, text: &str, e_star: f64, r_star: f64) -> Figures {
    run_in(name, text, e_star, r_star, |_| {})
}

/// [`run`], then `look` at the output folder before it is removed.
fn run_in(name: &str, text: &str, e_star: f64, r_star: f64, look: impl FnOnce(&Path)) -> Figures {
    let dir = temp_dir(name);
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).expect("scene written");
    let scene = Scene::load(&path).expect("scene reads");
    let (model, summary) = run_scene(
        &scene,
        &RunOptions {
            output: Some(dir.join("out")),
            quiet: true,
            stop: None,
            comm: None,
            study: false,
        },
    )
    .unwrap_or_else(|e| panic!("{name}: {e}"));
    let (a, p0) = hertz_sphere(LOAD, r_star, e_star);
    let load = LOAD / 4.0;
    let bodies = (0..model.bodies.len())
        .filter_map(|k| contact_patch(&model, k, None))
        .map(|patch| {
            let acc = elliptic_accuracy(&patch, a, p0);
            (acc.mre, acc.radius_error, patch.force.z.abs() / load - 1.0)
        })
        .collect();
    look(&dir.join("out"));
    let _ = std::fs::remove_dir_all(&dir);
    Figures { summary, bodies }
}

/// ADR's and the static solver's figures of a body (MRE, radius error, force): the same MRE
/// and radius error within 0.1 points.
fn assert_same_figures(adr: (f64, f64, f64), newton: (f64, f64, f64)) {
    assert!(
        (adr.0 - newton.0).abs() < 1e-3,
        "MRE: ADR {} static {}",
        adr.0,
        newton.0
    );
    assert!(
        (adr.1 - newton.1).abs() < 1e-3,
        "radius: ADR {} static {}",
        adr.1,
        newton.1
    );
}

fn two_spheres_e_star() -> f64 {
    YOUNGS / (2.0 * (1.0 - POISSON * POISSON))
}

/// Both solvers converge on the pair, ADR within twice the iterations of the same upper mesh
/// on a rigid plane; each body's pressure agrees with Hertz for two spheres as the upper
/// mesh's does with Hertz on a rigid plane, and carries the load.
#[test]
fn two_gmsh_tet_spheres_pressed_together_agree_with_hertz() {
    let rigid = run(
        "rigid",
        &scene("adr", "rigid", false),
        YOUNGS / (1.0 - POISSON * POISSON),
        1.0,
    );
    assert!(rigid.summary.converged, "{:?}", rigid.summary.residual);
    let adr = run(
        "adr",
        &scene("adr", "tet4", true),
        two_spheres_e_star(),
        0.5,
    );
    let s = &adr.summary;
    assert!(
        s.converged,
        "ADR: residual {} after {}",
        s.residual, s.iterations
    );
    // Measured: 840 against 500.
    assert!(
        s.iterations <= 2 * rigid.summary.iterations,
        "ADR: {} iterations, the same mesh on a rigid plane {}",
        s.iterations,
        rigid.summary.iterations
    );
    assert_eq!(s.missed_contacts, 0);
    assert!(
        !s.warnings.iter().any(|w| w.contains("two_pass")),
        "{:?}",
        s.warnings
    );
    // The run's own report on the pair: the contact ratio and the strain a body sees, not the
    // pair's relative curvature (R* = R/2) and E* (half a body's), which would read twice as
    // large; the same on the plane.
    for (f, what) in [(&adr, "the pair"), (&rigid, "the plane")] {
        let a = f.summary.accuracy.as_ref().expect("an accuracy check");
        assert!(
            (a.contact_ratio - 0.3).abs() < 0.01,
            "{what}: a/R {}",
            a.contact_ratio
        );
        assert!(
            !f.summary
                .warnings
                .iter()
                .any(|w| w.contains("strain") && !w.contains(" at 19 %")),
            "{what}: {:?}",
            f.summary.warnings
        );
    }
    assert_eq!(adr.bodies.len(), 2);
    // Measured: upper MRE 4.29 %, radius +1.72 %; lower 2.75 %, −0.54 %; on the rigid plane
    // 4.40 %, +1.74 %. At a/Δ ≈ 5 the mesh, not the second body, sets the error.
    for (k, &(mre, radius, force)) in adr.bodies.iter().enumerate() {
        assert!(mre < 0.05, "body {k}: MRE {mre}");
        assert!(radius.abs() < 0.03, "body {k}: radius error {radius}");
        assert!(
            force.abs() < 1e-3,
            "body {k}: contact force off the load by {force}"
        );
    }
    let (mre_rigid, radius_rigid, _) = rigid.bodies[0];
    assert!(
        (adr.bodies[0].0 - mre_rigid).abs() < 0.01,
        "upper MRE {} on the sphere, {mre_rigid} on the plane",
        adr.bodies[0].0
    );
    assert!(
        (adr.bodies[0].1 - radius_rigid).abs() < 0.01,
        "upper radius error {} on the sphere, {radius_rigid} on the plane",
        adr.bodies[0].1
    );
    // The static solver: the same equilibrium in tens of Newton iterations (measured 36).
    let newton = run(
        "static",
        &scene("static", "tet4", true),
        two_spheres_e_star(),
        0.5,
    );
    assert!(newton.summary.converged, "{}", newton.summary.residual);
    assert!(
        newton.summary.iterations <= 60,
        "{}",
        newton.summary.iterations
    );
    for (a, b) in adr.bodies.iter().zip(&newton.bodies) {
        assert_same_figures(*a, *b);
    }
}

/// A deformable partner of another Poisson's ratio: the upper sphere in the LPS at ν = 0.3,
/// the lower bond-based (ν = 0.25), Hertz with `1/E* = Σ (1 − ν²)/E`. Measured on this pair
/// (h = 0.06, 6 s): upper MRE 2.24 %, radius +2.49 %, lower 2.75 %, −0.38 %; at h = 0.05
/// (`tools/gmsh_two_spheres.py`): upper 1.74 %, +1.73 %, lower 2.42 %, −1.27 %
/// (docs/VALIDATION.md, "Any Poisson's ratio").
#[test]
fn an_lps_sphere_on_a_bond_based_one() {
    let text = scene("adr", "tet4", true);
    let upper = text
        .find("poisson_ratio = 0.25")
        .expect("the upper material");
    let text = format!(
        "{}poisson_ratio = 0.3\nmodel = \"lps\"{}",
        &text[..upper],
        &text[upper + "poisson_ratio = 0.25".len()..]
    );
    let e_star = 1.0 / ((1.0 - 0.09) / YOUNGS + (1.0 - POISSON * POISSON) / YOUNGS);
    let f = run("lps-pair", &text, e_star, 0.5);
    assert!(f.summary.converged, "{}", f.summary.residual);
    assert_eq!(f.bodies.len(), 2);
    for (k, &(mre, radius, force)) in f.bodies.iter().enumerate() {
        eprintln!(
            "body {k}: MRE {:.2} %, radius {:+.2} %, force {force:.1e}",
            100.0 * mre,
            100.0 * radius
        );
        assert!(mre < 0.05, "body {k}: MRE {mre}");
        assert!(radius.abs() < 0.03, "body {k}: radius error {radius}");
        assert!(
            force.abs() < 1e-3,
            "body {k}: contact force off the load by {force}"
        );
    }
}

/// With one pass both solvers converge to the same equilibrium, and the slave's figures are
/// its mesh's (measured on this pair: ADR 944 iterations, static 58 Newton iterations;
/// upper MRE 4.65 %, radius −1.10 %; two passes 4.29 %, +1.72 %; the upper mesh on a rigid
/// plane 4.40 %, +1.74 %, in 500 ADR iterations). ADR takes at most twice the iterations of
/// the same slave mesh on a rigid plane (1,202, 2.4 times, before the master's nodes that a
/// slave may touch got ADR's light-contact density). The static solver's Newton iterations
/// stalled here once the contact had settled (its rim cycling) and ADR finished the increment
/// from where they stopped (41 Newton, 285 ADR), until the line search followed the energy's
/// slope.
/// Before the run, `run --check` says that the master's pressure reads rough.
#[test]
fn one_pass_converges_to_the_slaves_figures() {
    let dir = temp_dir("one-pass");
    let path = dir.join("scene.toml");
    std::fs::write(&path, scene("adr", "tet4", false)).expect("scene written");
    let checked = Scene::load(&path).expect("scene reads");
    let (_, warnings, _) = check_scene(&checked).expect("the scene checks");
    assert!(
        warnings.iter().any(|w| w.contains("two_pass = false")
            && w.contains("reads rough")
            && w.contains("set two_pass = true")),
        "{warnings:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
    let adr = run(
        "one-pass-adr",
        &scene("adr", "tet4", false),
        two_spheres_e_star(),
        0.5,
    );
    let newton = run(
        "one-pass-static",
        &scene("static", "tet4", false),
        two_spheres_e_star(),
        0.5,
    );
    let rigid = run(
        "one-pass-rigid",
        &scene("adr", "rigid", false),
        YOUNGS / (1.0 - POISSON * POISSON),
        1.0,
    );
    assert!(
        adr.summary.iterations <= 2 * rigid.summary.iterations,
        "ADR: {} iterations, the same mesh on a rigid plane {}",
        adr.summary.iterations,
        rigid.summary.iterations
    );
    for (what, f) in [("ADR", &adr), ("static", &newton)] {
        assert!(
            f.summary.converged,
            "{what}: residual {} after {}",
            f.summary.residual, f.summary.iterations
        );
        let (mre, radius, force) = f.bodies[0];
        assert!(mre < 0.05, "{what}: upper MRE {mre}");
        assert!(radius.abs() < 0.03, "{what}: upper radius error {radius}");
        assert!(force.abs() < 1e-3, "{what}: contact force off by {force}");
    }
    assert!(
        newton.summary.iterations <= 60,
        "{}",
        newton.summary.iterations
    );
    // Where Newton stalls, ADR finishes from near the equilibrium, in fewer iterations than
    // ADR from the start. (Since the line search follows the energy's slope, `dᵀS(S⁻¹R)`,
    // Newton converges here by itself: 58 iterations, no ADR; it took 41 and 285 of ADR.)
    let relaxed = newton.summary.solver.relaxation_iterations;
    assert!(
        relaxed < adr.summary.iterations,
        "ADR after Newton: {relaxed}, ADR alone: {}",
        adr.summary.iterations
    );
    assert_same_figures(adr.bodies[0], newton.bodies[0]);
}

/// Where ADR's transient loses a slave under the whole load (one pass on the tet10 pair, a
/// master node carried into the slave before the contact held it: docs/VALIDATION.md, "One
/// pass, and pairs of other sizes"), the increment starts again from the last equilibrium
/// with half the load step and converges to the static solver's equilibrium. Measured on
/// this pair: the slave lost at iteration 162, then 2,803 iterations in all; the upper
/// sphere's MRE 1.65 %, radius −0.68 %; static 1.65 %, −0.68 %. The frames of the try that
/// lost it, states off the load path, are not kept: the frames left rise in load factor.
#[test]
fn one_pass_adr_cuts_back_an_increment_that_loses_a_slave() {
    let mut frames = Vec::new();
    let adr = run_in(
        "cut-back-adr",
        &scene("adr", "tet10", false).replace("every = 1000000", "every = 100"),
        two_spheres_e_star(),
        0.5,
        |out| {
            frames = common::pvd(out);
            for (_, file) in &frames {
                assert!(out.join(file).is_file(), "{file} listed, not written");
            }
            let written = std::fs::read_dir(out)
                .expect("the output folder")
                .flatten()
                .filter(|e| e.file_name().to_string_lossy().ends_with(".vtm"))
                .count();
            assert_eq!(written, frames.len(), "frames written but not listed");
        },
    );
    assert!(
        frames.windows(2).all(|w| w[0].0 < w[1].0) && frames.len() > 20,
        "{frames:?}"
    );
    assert!(
        !frames.iter().any(|(_, f)| f == "frame_000100.vtm"),
        "{frames:?}"
    );
    let newton = run(
        "cut-back-static",
        &scene("static", "tet10", false),
        two_spheres_e_star(),
        0.5,
    );
    assert!(
        adr.summary.converged,
        "residual {} after {}",
        adr.summary.residual, adr.summary.iterations
    );
    assert!(adr.summary.solver.cutbacks >= 1, "{:?}", adr.summary.solver);
    let (mre, radius, force) = adr.bodies[0];
    assert!(mre < 0.03, "upper MRE {mre}");
    assert!(radius.abs() < 0.03, "upper radius error {radius}");
    assert!(force.abs() < 1e-3, "contact force off by {force}");
    assert_same_figures(adr.bodies[0], newton.bodies[0]);
}

/// Before a damped explicit run, `run --check` names the damping that settles the loaded
/// sphere's bounce on the contact fastest: critical, `2ω` with `ω² = (3P/(2δ))/m` (Hertz's
/// approach `δ = a²/R*`, the whole sphere's mass: ω = 276 rad/s). Measured on this pair
/// (docs/VALIDATION.md, "Two deformable bodies"): the force balance at 0.05 s was 2.2e-3 at
/// c = 300 1/s, 3e-6 at 600 and 9.1e-2 at 1,500.
#[test]
fn run_check_gives_the_damping_that_settles_an_explicit_run() {
    let dir = temp_dir("damping");
    let path = dir.join("scene.toml");
    // The warnings about `about` for the pair damped by `damping` to `end_time`.
    let warned = |damping: f64, end_time: f64, about: &str| -> Vec<String> {
        let text = scene("explicit", "tet4", true).replace(
            "kind = \"explicit\"",
            &format!("kind = \"explicit\"\nend_time = {end_time:e}\ndamping = {damping:e}"),
        );
        std::fs::write(&path, text).expect("scene written");
        let (_, warnings, _) =
            check_scene(&Scene::load(&path).expect("scene reads")).expect("the scene checks");
        warnings.into_iter().filter(|w| w.contains(about)).collect()
    };
    let bounce = |damping: f64, end_time: f64| warned(damping, end_time, "bounces on the contact");
    let (a, _) = hertz_sphere(LOAD, 0.5, two_spheres_e_star());
    let mass = 1000.0 * 4.0 / 3.0 * std::f64::consts::PI;
    let omega = (1.5 * LOAD / (a * a / 0.5) / mass).sqrt();
    let light = bounce(300.0, 0.05);
    assert_eq!(light.len(), 1, "{light:?}");
    let critical: f64 = light[0]
        .split("damping ≈ ")
        .nth(1)
        .and_then(|t| t.split(' ').next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("no critical damping in {:?}", light[0]));
    assert!(
        (critical / (2.0 * omega) - 1.0).abs() < 0.05,
        "critical {critical} against 2ω = {}",
        2.0 * omega
    );
    assert!(light[0].contains("of critical"), "{}", light[0]);
    assert!(bounce(600.0, 0.05).is_empty());
    // Run far past the time it settles in, the pair flutters: the advice says when to end.
    let flutter = |end_time: f64| warned(600.0, end_time, "then flutters");
    let long = flutter(0.1);
    assert!(
        long.len() == 1 && long[0].contains("end it by about 0.07"),
        "{long:?}"
    );
    assert!(flutter(0.05).is_empty());
    let short = bounce(600.0, 0.01);
    assert!(
        short.len() == 1 && short[0].contains("longer than end_time"),
        "{short:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
