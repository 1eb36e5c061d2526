//! What the integration tests share.
// Each test file uses some of these.
#![allow(dead_code)]

use std::path::Path;
use std::process::Command;

mod tools;
#[allow(unused_imports)]
pub use tools::*;

/// The bar of tests/lps.rs and tests/stress.rs: an eighth of a 3.2 × 1.6 × 1.6 m bar of
/// gmsh-default tets (`meshes/bar_tet4_h005.geo`, symmetry planes x = 0, y = 0, z = 0),
/// E = 1 GPa, pulled on its end face by `traction` (Pa; none where 0), solved by `solver` to
/// 1e-6.
pub fn bar_scene(
    model: &str,
    poisson: f64,
    solver: &str,
    kinematics: &str,
    skin: bool,
    traction: f64,
) -> String {
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/bar_tet4_h005.msh");
    let load = if traction != 0.0 {
        format!(
            "[[load]]\nbody = \"bar\"\nset = \"end\"\nforce = [{:e}, 0.0, 0.0]\n",
            traction * 0.8 * 0.8
        )
    } else {
        String::new()
    };
    format!(
        r#"[solver]
kind = "{solver}"
tolerance = 1e-6
max_iterations = 100000
[output]
every = 1000000
[[body]]
name = "bar"
mesh = {mesh:?}
kinematics = "{kinematics}"
skin_correction = {skin}
[body.material]
youngs_modulus = 1e9
poisson_ratio = {poisson}
density = 1000.0
model = "{model}"
{load}[[symmetry]]
body = "bar"
axis = "x"
[[symmetry]]
body = "bar"
axis = "y"
[[symmetry]]
body = "bar"
axis = "z"
"#,
        mesh = mesh.display().to_string(),
    )
}

/// Scene `text` with its LPS bodies' influence function set to `influence`.
pub fn with_influence(text: &str, influence: &str) -> String {
    text.replace(
        "model = \"lps\"",
        &format!("model = \"lps\"\ninfluence_function = \"{influence}\""),
    )
}

/// A fresh temporary folder `pdcontact-<name>-<pid>`.
pub fn temp_dir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("pdcontact-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// Runs the scene `text` in a temporary folder named for `name`, removed after.
pub fn run_text(text: &str, name: &str) -> (pdcontact::model::Model, pdcontact::run::RunSummary) {
    try_run_text(text, name).expect("runs")
}

/// [`run_text`], the run's error returned (a scene that does not load fails the test).
pub fn try_run_text(
    text: &str,
    name: &str,
) -> pdcontact::Result<(pdcontact::model::Model, pdcontact::run::RunSummary)> {
    let dir = temp_dir(name);
    let out = run_text_in(text, &dir);
    let _ = std::fs::remove_dir_all(&dir);
    out
}

/// Runs the scene `text` with its outputs in `dir` (kept).
pub fn run_text_in(
    text: &str,
    dir: &Path,
) -> pdcontact::Result<(pdcontact::model::Model, pdcontact::run::RunSummary)> {
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).expect("scene");
    let scene = pdcontact::scene::Scene::load(&path).expect("scene loads");
    pdcontact::run::run_scene(
        &scene,
        &pdcontact::run::RunOptions {
            output: Some(dir.to_path_buf()),
            quiet: true,
            stop: None,
            comm: None,
            study: false,
        },
    )
}

/// A path in the repository.
pub fn repo(p: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

/// `pdcontact validate ARGS..`.
pub fn validate(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_pdcontact"))
        .arg("validate")
        .args(args)
        .output()
        .expect("pdcontact runs")
}

/// `validate --mesh MESH EXTRA.. --json --quiet -o DIR`, which must succeed: its JSON report.
pub fn validate_json(mesh: &Path, extra: &[&str], dir: &Path) -> serde_json::Value {
    let mut args = vec!["--mesh", mesh.to_str().expect("utf-8 path")];
    args.extend_from_slice(extra);
    args.extend(["--json", "--quiet", "-o", dir.to_str().expect("utf-8 path")]);
    let out = validate(&args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("JSON")
}

/// The values of attribute `attr` of the elements `tag` in `xml`, in order.
pub fn attributes(xml: &str, tag: &str, attr: &str) -> Vec<String> {
    xml.split(&format!("<{tag} "))
        .skip(1)
        .filter_map(|e| {
            let e = format!(" {}", e.split('>').next()?);
            let v = e.split_once(&format!(" {attr}=\""))?.1;
            Some(v.split('"').next()?.to_string())
        })
        .collect()
}

/// `.pvd` entries: (timestep, file).
pub fn pvd(out: &Path) -> Vec<(f64, String)> {
    let text = std::fs::read_to_string(out.join("run.pvd")).expect("run.pvd");
    let t = attributes(&text, "DataSet", "timestep");
    let f = attributes(&text, "DataSet", "file");
    assert_eq!(t.len(), f.len());
    t.iter()
        .map(|t| t.parse().expect("number"))
        .zip(f)
        .collect()
}
