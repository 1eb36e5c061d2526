//! The contact estimate before a run (src/contact/estimate): the Hertz radius each pair will
//! make under its loads against the theory, and the warnings of `run` and `convert` when the
//! slave's particles resolve it poorly. No solve: the estimate reads the scene as built.

use std::path::{Path, PathBuf};
use std::process::Command;

use pdcontact::contact::estimate::{ContactResolution, ContactShape, PENALTY_TARGET};
use pdcontact::model::Model;
use pdcontact::output::analysis::{e_star_rigid, hertz_cylinder, hertz_sphere};
use pdcontact::scene::Scene;
use pdcontact::studies::scenarios::{
    hertz_punch_case, hertz_roller_case, hertz_sphere_case, sphere_on_block_case, Reference,
};

const YOUNGS: f64 = 1.0e9;
const POISSON: f64 = 0.25;

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pdcontact-estimate-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// The whole-sphere Hertz scene (a body on a rigid plane at z = `floor`, loaded down by `load`) with a
/// short explicit solve, so that `pdcontact run` ends at once.
fn plane_scene(mesh: &Path, floor: f64, load: f64) -> String {
    plane_scene_with(mesh, floor, load, "")
}

/// [`plane_scene`] with `contact` (such as `radius = 1e4`) added to its `[[contact]]`.
fn plane_scene_with(mesh: &Path, floor: f64, load: f64, contact: &str) -> String {
    format!(
        r#"
[solver]
kind = "explicit"
end_time = 2e-7
dt = 1e-7
[output]
folder = "out"
every = 100000
[[body]]
name = "ball"
mesh = "{}"
[body.material]
youngs_modulus = {YOUNGS:e}
poisson_ratio = {POISSON}
density = 1000.0
[[body]]
name = "plane"
kind = "rigid"
generator = {{ shape = "plane", point = [0.0, 0.0, {floor}], normal = [0.0, 0.0, 1.0], size = 3.0 }}
[[load]]
body = "ball"
force = [0.0, 0.0, -{load:e}]
[[contact]]
slave = "ball"
master = "plane"
{contact}
"#,
        mesh.display()
    )
}

fn resolution_of(scene: &str) -> Vec<ContactResolution> {
    let scene = Scene::parse(scene, "test.toml", Path::new(".")).expect("scene parses");
    Model::from_scene(&scene)
        .expect("model builds")
        .contact_resolution()
}

fn only(mut r: Vec<ContactResolution>) -> ContactResolution {
    assert_eq!(r.len(), 1, "{r:?}");
    r.pop().unwrap()
}

#[test]
fn coarse_tet_sphere_under_a_small_load_warns_with_the_hertz_numbers() {
    // meshes/sphere_tet4.msh (gmsh, h = 0.15 m) with the load of the old convert skeleton.
    let load = 4.0e5;
    let r = only(resolution_of(&plane_scene(
        &repo("meshes/sphere_tet4.msh"),
        -1.0,
        load,
    )));
    let (a, _) = hertz_sphere(load, 1.0, e_star_rigid(YOUNGS, POISSON));
    let e = r.estimate.as_ref().expect("a sphere has an estimate");
    assert_eq!(e.shape, ContactShape::Point);
    assert!(
        (e.radius / a - 1.0).abs() < 0.02,
        "a {} against {a}",
        e.radius
    );
    assert!(
        (e.curvature_radius() - 1.0).abs() < 0.02,
        "R {}",
        e.curvature_radius()
    );
    assert!((e.load - load).abs() < 1e-6 * load);
    // Surface spacing: √ of the median tributary area, 0.87 h² per node of a triangulation.
    assert!(r.spacing > 0.12 && r.spacing < 0.15, "Δ {}", r.spacing);
    let n = r.spacings.expect("spacings");
    assert!((n - a / r.spacing).abs() < 0.02 * n && n < 1.0, "a/Δ {n}");
    let w = r.warnings();
    // The resolution, then the default penalty R = Δ/2, soft against a contact this small.
    assert_eq!(w.len(), 2, "{w:?}");
    assert_eq!(w[1], r.penalty_warning().expect("a soft penalty"));
    let expect = format!(
        "contact \"ball\"/\"plane\": expected contact radius ≈ 0.0655 m spans {n:.1} surface spacings (h = {:.3} m, √ of the median tributary area of the surface particles there; the body's spacing Δ = ",
        r.spacing
    );
    assert!(w[0].starts_with(&expect), "{}\nexpected {expect}", w[0]);
    assert!(
        w[0].contains(&format!(
            "refine the mesh near the contact to h ≤ {:.4} m",
            a / 5.0
        )),
        "{}",
        w[0]
    );
}

/// The stored tet10 sphere under the demo's load (a = 0.15 m): with its corners alone the
/// contact spans under 5 spacings and the warning names the mid-edge nodes; with
/// `second_order = "all-nodes"` the tributary spacing on the surface halves (four triangles
/// per face) and the hint goes.
#[test]
fn tet10_corners_warning_names_the_mid_edge_nodes() {
    let mesh = repo("meshes/sphere_tet10_h008.msh");
    let load = 4.8e6;
    let corners = only(resolution_of(&plane_scene(&mesh, -1.0, load)));
    assert!(corners.second_order_corners);
    let w = corners.resolution_warning().expect("under 5 spacings");
    assert!(w.contains("second_order = \"all-nodes\""), "{w}");
    let all_nodes = plane_scene(&mesh, -1.0, load).replace(
        "name = \"ball\"\n",
        "name = \"ball\"\nsecond_order = \"all-nodes\"\n",
    );
    let all = only(resolution_of(&all_nodes));
    assert!(!all.second_order_corners);
    let ratio = corners.spacing / all.spacing;
    assert!(
        (1.9..2.1).contains(&ratio),
        "surface spacing {} against {}",
        all.spacing,
        corners.spacing
    );
    assert!(!all
        .resolution_warning()
        .is_some_and(|w| w.contains("second_order")));
}

/// On a first-order tet mesh the same warning names `refine = 1`; with it in the body every
/// tet is cut into eight, the spacing on the surface halves and the hint goes.
#[test]
fn tet4_warning_names_refine() {
    let mesh = repo("meshes/sphere_tet4_h007.msh");
    let load = 4.8e6;
    let coarse = only(resolution_of(&plane_scene(&mesh, -1.0, load)));
    assert!(coarse.refinable && !coarse.second_order_corners);
    let w = coarse.resolution_warning().expect("under 5 spacings");
    assert!(w.contains("refine = 1"), "{w}");
    let refined_scene = plane_scene(&mesh, -1.0, load)
        .replace("name = \"ball\"\n", "name = \"ball\"\nrefine = 1\n");
    let refined = only(resolution_of(&refined_scene));
    assert!(!refined.refinable);
    let ratio = coarse.spacing / refined.spacing;
    assert!(
        (1.9..2.1).contains(&ratio),
        "surface spacing {} against {}",
        refined.spacing,
        coarse.spacing
    );
    assert!(!refined
        .resolution_warning()
        .is_some_and(|w| w.contains("refine = 1")));
}

#[test]
fn resolved_tet_sphere_under_a_resolved_load_does_not_warn() {
    // meshes/sphere_tet4_h007.msh with P = 3.84e7 N: a = 0.3 m, about 4.6 spacings.
    let load = 3.84e7;
    let r = only(resolution_of(&plane_scene(
        &repo("meshes/sphere_tet4_h007.msh"),
        -1.0,
        load,
    )));
    let (a, _) = hertz_sphere(load, 1.0, e_star_rigid(YOUNGS, POISSON));
    let e = r.estimate.as_ref().expect("estimate");
    assert!(
        (e.radius / a - 1.0).abs() < 0.02,
        "a {} against {a}",
        e.radius
    );
    assert!(r.spacings.unwrap() > 4.0, "{r:?}");
    // gmsh-default tets: areas 1.7:1, surface 0.85 of the body's spacing.
    assert!(r.area_ratio < 2.5, "{}", r.area_ratio);
    // The default penalty R = Δ/2 is soft here, and says so.
    assert_eq!(r.warnings(), vec![r.penalty_warning().expect("soft")]);
    let p = r.penalty.as_ref().expect("penalty");
    assert!(p.ratio > 0.1, "{p:?}");

    // With the radius the warning suggests, nothing is said; the ratio is the target's.
    let scene = plane_scene_with(
        &repo("meshes/sphere_tet4_h007.msh"),
        -1.0,
        load,
        &format!("radius = {:e}", p.suggested_radius),
    );
    let r = only(resolution_of(&scene));
    assert!(r.warnings().is_empty(), "{:?}", r.warnings());
    let q = r.penalty.as_ref().expect("penalty");
    assert!((q.ratio / PENALTY_TARGET - 1.0).abs() < 1e-6, "{q:?}");
    assert!((q.radius / p.suggested_radius - 1.0).abs() < 1e-9, "{q:?}");
}

#[test]
fn the_penalty_warning_measures_the_hertz_sink_of_a_particle() {
    // Eq. 23 at the peak of Hertz's pressure (Eqs. 34-36), from the theory and the scene
    // alone: p0 = 3P/(2πa²) on the median tributary area Δ², K = 4E*√R/3, δ = (F/K)^⅔,
    // against the approach a²/R of the sphere.
    let load = 3.84e7;
    let radius: f64 = 100.0;
    let r = only(resolution_of(&plane_scene_with(
        &repo("meshes/sphere_tet4_h007.msh"),
        -1.0,
        load,
        &format!("radius = {radius}"),
    )));
    let e_star = e_star_rigid(YOUNGS, POISSON);
    let (a, p0) = hertz_sphere(load, 1.0, e_star);
    let k = 4.0 / 3.0 * e_star * radius.sqrt();
    let sink = (p0 * r.spacing * r.spacing / k).powf(2.0 / 3.0);
    let p = r.penalty.as_ref().expect("penalty");
    assert!((p.radius / radius - 1.0).abs() < 1e-9, "{p:?}");
    // The estimate's a and R are fitted to the mesh: within 2 % of the sphere's.
    assert!(
        (p.penetration / sink - 1.0).abs() < 0.03,
        "{p:?} against {sink}"
    );
    assert!(
        (p.depth / (a * a) - 1.0).abs() < 0.05,
        "{p:?} against {}",
        a * a
    );
    // 1.4 % here (docs/VALIDATION.md, "The penalty"): above the warning's 1 %.
    assert!(p.ratio > 0.01 && p.ratio < 0.02, "{p:?}");
    let w = r.penalty_warning().expect("warns");
    assert!(
        w.contains("(radius = 100 m)") && w.contains("set radius = "),
        "{w}"
    );
    // The suggested radius is R (ratio/0.3 %)³: the sink falls as R^(-1/3).
    let want = radius * (p.ratio / PENALTY_TARGET).powi(3);
    assert!((p.suggested_radius / want - 1.0).abs() < 1e-9, "{p:?}");
}

#[test]
fn flat_block_on_a_plane_has_no_estimate_and_no_warning() {
    let r = only(resolution_of(&plane_scene(
        &repo("meshes/block_hex.msh"),
        0.0,
        1e5,
    )));
    assert!(r.estimate.is_none(), "{:?}", r.estimate);
    assert!(r.spacings.is_none());
    assert!((r.area_ratio - 1.0).abs() < 1e-9);
    assert!(r.warnings().is_empty(), "{:?}", r.warnings());
}

#[test]
fn validation_scenes_estimate_their_theory() {
    // A quarter sphere cap (two symmetry planes through the contact), a plane-strain roller
    // slice halved across its line, and a sphere on a deformable block (E* of two bodies).
    for case in [
        hertz_sphere_case(5.0),
        hertz_roller_case(5.0),
        sphere_on_block_case(
            0.15,
            0.03,
            3.0,
            "kind = \"adr\"",
            "method = \"point-to-surface\"\nradius = 100.0",
            0.0,
            "block",
        ),
    ] {
        let r = only(resolution_of(&case.scene));
        let e = r.estimate.as_ref().expect("estimate");
        let (shape, a) = match &case.reference {
            Reference::Sphere {
                load,
                radius,
                e_stars,
            } => (
                ContactShape::Point,
                hertz_sphere(*load, *radius, e_stars[0].1).0,
            ),
            Reference::Roller {
                load_per_length,
                radius,
                e_stars,
                ..
            } => (
                ContactShape::Line,
                hertz_cylinder(*load_per_length, *radius, e_stars[0].1).0,
            ),
            Reference::Punch { .. } | Reference::SpherePair { .. } => unreachable!(),
        };
        assert_eq!(e.shape, shape, "{}", case.label);
        assert!(
            (e.radius / a - 1.0).abs() < 0.05,
            "{}: a {} against {a}",
            case.label,
            e.radius
        );
        // a/Δ = 5 on even layers: resolved. Their penalty (R = 100 m) lets a particle sink
        // 1.5 % of the contact's depth at this coarse spacing, and the warning says so; at
        // the hertz set's a/Δ = 15 it is below 0.5 %.
        assert!((r.spacings.unwrap() - 5.0).abs() < 0.5, "{r:?}");
        assert!(
            r.resolution_warning().is_none()
                && r.area_warning().is_none()
                && r.graded_warning().is_none(),
            "{:?}",
            r.warnings()
        );
        let ratio = r.penalty.as_ref().expect("penalty").ratio;
        assert!(ratio < 0.02, "{}: {ratio}", case.label);
    }
    // A flat punch on a flat block: no Hertz contact, nothing said.
    let r = only(resolution_of(&hertz_punch_case(8.0).scene));
    assert!(r.estimate.is_none() && r.warnings().is_empty(), "{r:?}");
}

fn exe() -> Command {
    Command::new(env!("CARGO_BIN_EXE_pdcontact"))
}

#[test]
fn convert_chooses_a_resolved_load_or_says_how_fine_a_mesh_it_needs() {
    let dir = temp_dir("convert");
    let out = exe()
        .args(["convert", "--json", "-o"])
        .arg(&dir)
        .arg(repo("meshes/sphere_tet4.msh"))
        .output()
        .expect("runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let s: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    // a = 5Δ would take a = 0.68 m on R = 1 m: the load stops at a/R = 0.15 and says so.
    let w = s["warnings"].as_array().expect("warnings");
    assert_eq!(w.len(), 1, "{w:?}");
    let w = w[0].as_str().unwrap();
    assert!(
        w.contains("expected contact radius ≈ 0.150 m")
            && w.contains("refine the mesh near the contact to h ≤ 0.0300 m"),
        "{w}"
    );
    // The mesh is first-order tets: the warning names what the body can do about it.
    assert!(w.ends_with("; refine = 1 in the body cuts every tet and hex into eight at its edges' midpoints, about twice the spacings across the contact at about seven times the particles"), "{w}");
    assert_eq!(s["contact_estimates"][0]["refinable"], true);
    // It is also on stderr, as `run` prints its warnings; `--quiet` leaves it in the summary.
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(stderr.trim_end(), format!("warning: {w}"));
    let quiet = exe()
        .args(["convert", "--json", "--quiet", "-o"])
        .arg(dir.join("quiet"))
        .arg(repo("meshes/sphere_tet4.msh"))
        .output()
        .expect("runs");
    assert!(quiet.status.success() && quiet.stderr.is_empty());
    let q: serde_json::Value = serde_json::from_slice(&quiet.stdout).expect("json");
    assert_eq!(q["warnings"], s["warnings"]);
    let e = &s["contact_estimates"][0]["estimate"];
    let load = e["load"].as_f64().unwrap();
    let (a, _) = hertz_sphere(load, 1.0, e_star_rigid(YOUNGS, POISSON));
    assert!((a - 0.15).abs() < 1e-3, "load {load}: a {a}");
    // The case's load is the estimate's, written to six significant digits.
    let toml = std::fs::read_to_string(dir.join("case.toml")).expect("case.toml");
    let written: f64 = toml
        .lines()
        .find_map(|l| l.strip_prefix("force = [0.0, 0.0, "))
        .and_then(|rest| rest.split(']').next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no force line in {toml}"));
    assert!(
        (written + load).abs() <= 1e-5 * load,
        "{written} against {load}"
    );
    // The case runs as written and its run says the same of the contact.
    let scene = Scene::load(&dir.join("case.toml")).expect("case.toml loads");
    let r = only(Model::from_scene(&scene).unwrap().contact_resolution());
    assert!((r.estimate.unwrap().radius - 0.15).abs() < 1e-3);

    // A flat block keeps the strain load and says nothing.
    let out = exe()
        .args(["convert", "--json", "-o"])
        .arg(dir.join("block"))
        .arg(repo("meshes/block_hex.msh"))
        .output()
        .expect("runs");
    let s: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(s["warnings"], serde_json::json!([]));
    assert!(s["contact_estimates"][0]["estimate"].is_null());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn run_prints_the_warning_and_writes_it_in_the_summary() {
    let dir = temp_dir("run");
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        plane_scene(&repo("meshes/sphere_tet4.msh"), -1.0, 4.0e5),
    )
    .unwrap();
    let out = exe().arg("run").arg(&scene).output().expect("runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    let line = "warning: contact \"ball\"/\"plane\": expected contact radius ≈ 0.0655 m";
    assert!(stderr.contains(line), "{stderr}");
    let text = std::fs::read_to_string(dir.join("out/summary.json")).expect("summary");
    let s: serde_json::Value = serde_json::from_str(&text).unwrap();
    let w = s["warnings"][0].as_str().expect("a warning");
    assert!(w.starts_with(&line["warning: ".len()..]), "{w}");
    assert!(s["contact_estimates"][0]["spacings"].as_f64().unwrap() < 1.0);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `refine = 1` on a generated body: its hex lattice is cut into the lattice of half the cell,
/// and the spacing the horizon is measured in halves with it (the generator's cell is the
/// median edge of the mesh before it is cut), so the horizon stays three spacings.
#[test]
fn refined_generated_box_keeps_its_horizon_in_spacings() {
    let scene = |refine: u32| {
        format!(
            r#"[solver]
kind = "adr"

[[body]]
name = "block"
generator = {{ shape = "box", min = [0.0, 0.0, 0.0], max = [0.4, 0.4, 0.4], spacing = 0.1 }}
refine = {refine}
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
"#
        )
    };
    let case_of = |refine: u32| {
        let s = Scene::parse(&scene(refine), "test.toml", Path::new(".")).expect("scene parses");
        let model = Model::from_scene(&s).expect("model builds");
        model.bodies[0].as_pd().expect("a PD body").case.clone()
    };
    let (coarse, fine) = (case_of(0), case_of(1));
    // 5³ nodes, then 9³: the lattice of half the cell.
    assert_eq!(coarse.particles.len(), 125);
    assert_eq!(fine.particles.len(), 729);
    assert!((coarse.particles.spacing - 0.1).abs() < 1e-12);
    assert!((fine.particles.spacing - 0.05).abs() < 1e-12);
    assert!((fine.horizon - 3.0 * 0.05).abs() < 1e-12);
    let volume = |c: &pdcontact::case::PdCase| c.particles.volume.iter().sum::<f64>();
    assert!((volume(&fine) - 0.064).abs() < 1e-12 && (volume(&coarse) - 0.064).abs() < 1e-12);
}
