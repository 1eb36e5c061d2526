//! The Hertz sphere on meshes made as a user makes them: gmsh's default algorithms, only the
//! element size set, on a rigid plane under a = 0.3 R (docs/VALIDATION.md). meshes/sphere_tet4_h007.geo: unstructured tet4,
//! h = 0.07 m (force over tributary area gave MRE 20.6 %, radius +10.7 %, peak +38.8 %;
//! pressures are now recovered on the surface, docs/VALIDATION.md);
//! meshes/sphere_hex_h020.geo: the tets of h = 0.2 m each split into four hexes (the paper's
//! surface test flagged a quarter of the interior, MRE 23.9 %); meshes/sphere_tet10_h008.geo:
//! second-order tets, h = 0.08 m. docs/VALIDATION.md,
//! "Unstructured meshes", has the figures on finer meshes.

use std::path::{Path, PathBuf};

use pdcontact::case::{CaseOptions, PdCase};
use pdcontact::importers::read_path;
use pdcontact::model::Model;
use pdcontact::output::analysis::{
    contact_patch, contact_pressure, e_star_rigid, elliptic_accuracy, hertz_sphere,
    particle_pressure, Accuracy,
};
use pdcontact::run::{run_scene, RunOptions};
use pdcontact::scene::Scene;

const YOUNGS: f64 = 1.0e9;
const POISSON: f64 = 0.25;
const LOAD: f64 = 3.84e7;

fn mesh_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("meshes")
        .join(name)
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "pdcontact-unstructured-{name}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// Runs `scene` (TOML, written next to nothing: mesh paths are absolute) and returns the model.
fn run_text(scene: &str, tag: &str) -> Model {
    let dir = temp_dir(tag);
    let scene_path = dir.join("scene.toml");
    std::fs::write(&scene_path, scene).expect("scene written");
    let scene = Scene::load(&scene_path).expect("scene loads");
    let options = RunOptions {
        output: None,
        quiet: true,
        stop: None,
        comm: None,
        study: false,
    };
    let (model, summary) = run_scene(&scene, &options).expect("runs");
    assert!(summary.converged);
    assert_eq!(summary.missed_contacts, 0);
    let _ = std::fs::remove_dir_all(&dir);
    model
}

/// Runs the Hertz scene on `mesh` under the whole sphere's load `load` and returns the model,
/// Hertz's a and p0, the figures of METHOD.md §7 (every facing particle within 0.8a) and the
/// peak. `quarter`: the mesh is a quarter cap, cut by the planes x = 0 and y = 0 (symmetry),
/// carrying a quarter of the load on its set `top`; otherwise the load is spread over the body.
fn hertz_run(mesh: &Path, load: f64, quarter: bool, tag: &str) -> (Model, f64, f64, Accuracy, f64) {
    let (set, force, symmetry) = if quarter {
        (
            "set = \"top\"\n",
            load / 4.0,
            "[[symmetry]]\nbody = \"ball\"\naxis = \"x\"\n[[symmetry]]\nbody = \"ball\"\naxis = \"y\"\n",
        )
    } else {
        ("", load, "")
    };
    let model = run_text(
        &format!(
            r#"
[solver]
kind = "adr"
tolerance = 1e-4
max_iterations = 50000
[[body]]
name = "ball"
mesh = "{}"
kinematics = "small"
[body.material]
youngs_modulus = {YOUNGS:e}
poisson_ratio = {POISSON}
density = 1000.0
[[body]]
name = "plane"
kind = "rigid"
generator = {{ shape = "plane", point = [0.0, 0.0, -1.0], normal = [0.0, 0.0, 1.0], size = 3.0 }}
[[load]]
body = "ball"
{set}force = [0.0, 0.0, -{force:e}]
[[contact]]
slave = "ball"
master = "plane"
radius = 100.0
{symmetry}"#,
            mesh.display()
        ),
        tag,
    );
    let (a, p0) = hertz_sphere(load, 1.0, e_star_rigid(YOUNGS, POISSON));
    let patch = contact_patch(&model, 0, None).expect("in contact");
    let acc = elliptic_accuracy(&patch, a, p0);
    let peak = patch.peak;
    (model, a, p0, acc, peak)
}

/// The MRE of each particle's own pressure (METHOD.md §7's set: facing, within 0.8a).
fn own_pressure_mre(model: &Model, a: f64, p0: f64) -> f64 {
    let own = particle_pressure(model, 0);
    let patch = contact_patch(model, 0, None).expect("in contact");
    let inside: Vec<f64> = patch
        .points
        .iter()
        .filter(|(_, r, _)| *r <= 0.8 * a)
        .map(|&(i, r, _)| (own[i as usize] - p0 * (1.0 - (r / a).powi(2)).sqrt()).abs() / p0)
        .collect();
    inside.iter().sum::<f64>() / inside.len() as f64
}

/// Hertz where its theory holds (a/R = 0.15) on the demo's body meshed by gmsh's defaults:
/// meshes/sphere_cap_quarter_tet4.geo, tet4 of h = 0.02 m (a/h = 7.5, 2,744 particles), the
/// scene of `pdcontact demo` with that mesh (docs/VALIDATION.md, "Unstructured quarter caps").
#[test]
fn hertz_sphere_cap_on_a_gmsh_default_tet_mesh() {
    let (model, a, p0, acc, peak) = hertz_run(
        &mesh_path("sphere_cap_quarter_tet4.msh"),
        4.8e6,
        true,
        "cap-tet4",
    );
    // Measured: MRE 2.65 %, radius +0.30 %, peak +8.1 % (own pressures: MRE 4.16 %); without
    // the skin correction 1.94 %, +3.20 %, −1.9 % (own 3.30 %): the contact no longer too
    // wide, its centre a little high. The issue's aims: MRE 3 %, radius 3 %, peak 10 %.
    assert!(acc.mre < 0.03, "MRE {}", acc.mre);
    assert!(
        (acc.fitted_radius / a - 1.0).abs() < 0.03,
        "a {}",
        acc.fitted_radius / a
    );
    assert!((peak / p0 - 1.0).abs() < 0.1, "peak {}", peak / p0);
    let own = own_pressure_mre(&model, a, p0);
    assert!(own > acc.mre + 0.01, "own {own} recovered {}", acc.mre);
}

#[test]
fn hertz_sphere_on_a_gmsh_default_tet_mesh() {
    let (model, a, p0, acc, peak) =
        hertz_run(&mesh_path("sphere_tet4_h007.msh"), LOAD, false, "tet4");
    // Measured: MRE 2.81 %, radius −1.42 %, peak +2.0 % (each particle's own pressure: 2.73 %).
    // Without the skin correction 6.70 %, +5.70 %, −5.36 % (own 6.41 %): on tets the error
    // was the contact's width, the surface row's softness, not scatter.
    assert!(acc.mre < 0.035, "MRE {}", acc.mre);
    assert!(
        (acc.fitted_radius / a - 1.0).abs() < 0.03,
        "a {}",
        acc.fitted_radius / a
    );
    assert!((peak / p0 - 1.0).abs() < 0.05, "peak {}", peak / p0);
    // The recovered pressure field over the pressure areas A*_i integrates to the contact force.
    let pd = model.bodies[0].as_pd().expect("deformable");
    let p = contact_pressure(&model, 0);
    let integral: f64 = p
        .iter()
        .zip(&pd.case.segments.pressure_area)
        .map(|(p, a)| p * a)
        .sum();
    let force: f64 = pd.contact_force.iter().map(|f| f.norm()).sum();
    assert!(
        (integral / force - 1.0).abs() < 1e-12,
        "{integral} vs {force}"
    );
    // The pressure areas share out the boundary's area.
    let (trib, press): (f64, f64) = (
        pd.case.segments.tributary_area.iter().sum(),
        pd.case.segments.pressure_area.iter().sum(),
    );
    assert!((press / trib - 1.0).abs() < 1e-12);
}

/// Second-order tets (tet10, MSH 4.1 binary): one particle per corner node, the midside nodes
/// dropped (METHOD.md §1). At h = 0.08 m the contact is only 3.5 spacings across (a/Δ), so the
/// figures are those of a coarse mesh; `pdcontact validate --mesh` prints the same ones.
#[test]
fn hertz_sphere_on_a_gmsh_default_tet10_mesh() {
    let (model, a, p0, acc, peak) =
        hertz_run(&mesh_path("sphere_tet10_h008.msh"), LOAD, false, "tet10");
    // gmsh's mesh has 55,844 nodes, of which 7,435 are corners of its 38,508 tet10.
    assert_eq!(model.bodies[0].as_pd().expect("deformable").len(), 7435);
    // Measured: MRE 3.68 %, radius +0.62 %, peak +3.0 % (own pressures: 3.30 %); without the
    // skin correction 8.12 %, +4.96 %, −7.00 % (own 7.90 %).
    assert!(acc.mre < 0.045, "MRE {}", acc.mre);
    assert!(
        (acc.fitted_radius / a - 1.0).abs() < 0.03,
        "a {}",
        acc.fitted_radius / a
    );
    assert!((peak / p0 - 1.0).abs() < 0.06, "peak {}", peak / p0);
}

/// The eigenvalue surface on gmsh's tets split into hexes: exactly the mesh's boundary nodes
/// (the paper's test alone: 2,671 of 10,455 interior particles too), with normals within 5°
/// of the sphere's on average (measured 2.9°; before, 9.6°).
#[test]
fn eigenvalue_surface_on_tets_split_into_hexes() {
    let mesh = read_path(&mesh_path("sphere_hex_h020.msh"), None).expect("imports");
    let case = PdCase::build(mesh, CaseOptions::default()).expect("case");
    let agreement = case.surface_agreement();
    let interior = case.particles.len() - agreement.boundary_nodes;
    assert!(
        100 * agreement.missed < agreement.boundary_nodes,
        "{agreement:?}"
    );
    assert!(100 * agreement.extra < interior, "{agreement:?}");
    let boundary = &case.segments.boundary_node;
    let angles: Vec<f64> = (0..case.particles.len())
        .filter(|&i| boundary[i] && case.surface.is_surface[i])
        .map(|i| {
            let radial = case.particles.position[i].normalize();
            case.surface.normal[i]
                .dot(&radial)
                .clamp(-1.0, 1.0)
                .acos()
                .to_degrees()
        })
        .collect();
    let mean = angles.iter().sum::<f64>() / angles.len() as f64;
    assert!(mean < 5.0, "mean normal error {mean}°");
}

#[test]
fn hertz_sphere_on_tets_split_into_hexes() {
    let (model, a, p0, acc, peak) =
        hertz_run(&mesh_path("sphere_hex_h020.msh"), LOAD, false, "hex");
    // Measured: MRE 5.01 %, radius +0.80 %, peak +0.5 %, each particle's own pressure 5.85 %.
    // Before the skin correction, with lumped surface volumes: 6.22 %, +2.52 %, −0.67 %, own
    // 7.53 % (23.9 % while interior particles facing the plane counted as surface): the
    // recovery on the surface takes out the scatter of the irregular cloud.
    assert!(acc.mre < 0.06, "MRE {}", acc.mre);
    let own_mre = own_pressure_mre(&model, a, p0);
    assert!(
        own_mre > acc.mre + 0.005,
        "own {own_mre} recovered {}",
        acc.mre
    );
    assert!(
        (acc.fitted_radius / a - 1.0).abs() < 0.04,
        "a {}",
        acc.fitted_radius / a
    );
    assert!((peak / p0 - 1.0).abs() < 0.10, "peak {}", peak / p0);
}
