//! Scene files that cannot be used: `pdcontact run` exits with 2 and one line
//! `FILE:LINE:COL: message` that points at the place in the scene and says what is wrong.

use std::path::{Path, PathBuf};
use std::process::Command;

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pdcontact-scene-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

fn sphere_mesh() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("meshes/sphere_r1_d012.msh")
        .display()
        .to_string()
}

/// A small runnable scene: a box pressed on a rigid plane.
const GOOD: &str = r#"[solver]
kind = "adr"
max_iterations = 20000

[output]
every = 100000

[[body]]
name = "block"
generator = { shape = "box", min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 0.5], spacing = 0.25 }
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0

[[body]]
name = "floor"
kind = "rigid"
generator = { shape = "plane", point = [0.0, 0.0, -0.01], normal = [0.0, 0.0, 1.0], size = 3.0 }

[[load]]
body = "block"
set = "top"
force = [0.0, 0.0, -1e5]

[[contact]]
slave = "block"
master = "floor"
radius = 0.5
"#;

/// Runs `pdcontact run` on `text` and returns the scene's path and the error line.
/// Asserts exit code 2 and a single line on stderr.
fn error_of(case: &str, text: &str) -> (String, String) {
    let dir = temp_dir(case);
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, text).expect("write scene");
    let out = Command::new(env!("CARGO_BIN_EXE_pdcontact"))
        .args(["run", "--quiet"])
        .arg(&scene)
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(2), "{case}: {err}");
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "{case}: not one line: {err}");
    let _ = std::fs::remove_dir_all(&dir);
    (scene.display().to_string(), lines[0].to_string())
}

/// 1-based line of the first line of `text` holding `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("{needle} not in the scene"))
        + 1
}

/// The error names the scene, the line holding `at` (with a column), and contains `what`.
fn assert_error(case: &str, text: &str, at: &str, what: &[&str]) {
    let (path, line) = error_of(case, text);
    let want = format!("error: {path}:{}:", line_of(text, at));
    assert!(
        line.starts_with(&want),
        "{case}: expected {want}…, got {line}"
    );
    let rest = &line[want.len()..];
    let (col, msg) = rest.split_once(": ").expect("FILE:LINE:COL: message");
    let col: usize = col
        .parse()
        .unwrap_or_else(|_| panic!("{case}: no column in {line}"));
    assert!(col >= 1, "{case}: {line}");
    for w in what {
        assert!(msg.contains(w), "{case}: {line} lacks {w:?}");
    }
}

#[test]
fn good_scene_runs() {
    let dir = temp_dir("good");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, GOOD).expect("write scene");
    let out = Command::new(env!("CARGO_BIN_EXE_pdcontact"))
        .args(["run", "--quiet", "--json"])
        .arg(&scene)
        .output()
        .expect("runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let s: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(s["converged"], true);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn unknown_keys() {
    let text = GOOD.replace("youngs_modulus = 1e9", "youngs_modulis = 1e9");
    assert_error(
        "unknown-material",
        &text,
        "youngs_modulis",
        &["youngs_modulis"],
    );
    let text = GOOD.replace("radius = 0.5", "radius = 0.5\nadhesion = 0.3");
    assert_error("unknown-contact", &text, "adhesion", &["adhesion"]);
    let text = GOOD.replace("[output]", "[outputs]");
    assert_error("unknown-table", &text, "[outputs]", &["outputs"]);
    let text = GOOD.replace("spacing = 0.25 }", "spacing = 0.25, radious = 1.0 }");
    assert_error("unknown-generator", &text, "radious", &["radious"]);
}

#[test]
fn wrong_types() {
    let text = GOOD.replace("density = 1000.0", "density = \"steel\"");
    assert_error(
        "type-string",
        &text,
        "density",
        &["string", "expected a number"],
    );
    let text = GOOD.replace("max_iterations = 20000", "max_iterations = 2.5");
    assert_error("type-float", &text, "max_iterations", &["float"]);
    let text = GOOD.replace("force = [0.0, 0.0, -1e5]", "force = [0.0, -1e5]");
    assert_error("type-length", &text, "force =", &["3"]);
    let text = GOOD.replace("kind = \"adr\"", "kind = \"implicit\"");
    assert_error("type-variant", &text, "implicit", &["implicit", "adr"]);
}

#[test]
fn missing_mesh_file() {
    let text = GOOD.replace(
        "generator = { shape = \"box\", min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 0.5], spacing = 0.25 }",
        "mesh = \"no_such_mesh.msh\"",
    );
    assert_error(
        "missing-mesh",
        &text,
        "no_such_mesh.msh",
        &["block", "no_such_mesh.msh", "does not exist"],
    );
}

#[test]
fn sets_that_do_not_exist() {
    let text = GOOD.replace("set = \"top\"", "set = \"lid\"");
    assert_error(
        "set-generator",
        &text,
        "set = \"lid\"",
        &["no set \"lid\"", "top"],
    );
    // A stored mesh: its physical groups are the sets.
    let text = GOOD
        .replace(
            "generator = { shape = \"box\", min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 0.5], spacing = 0.25 }",
            &format!("mesh = \"{}\"", sphere_mesh()),
        )
        .replace("set = \"top\"", "set = \"north_pole\"")
        .replace("-0.01", "-1.01");
    assert_error(
        "set-mesh",
        &text,
        "north_pole",
        &["body \"block\"", "no set \"north_pole\""],
    );
    // A constraint too.
    let text = format!("{GOOD}\n[[constraint]]\nbody = \"block\"\nset = \"base\"\nfix = [\"x\"]\n");
    assert_error(
        "set-constraint",
        &text,
        "set = \"base\"",
        &["no set \"base\""],
    );
}

/// A vector has three components: a fourth (or a missing one) is refused at its line, not
/// dropped.
#[test]
fn vectors_have_three_components() {
    let four = GOOD.replacen(
        "normal = [0.0, 0.0, 1.0]",
        "normal = [0.0, 0.0, 1.0, 0.0]",
        1,
    );
    assert_ne!(four, GOOD);
    assert_error(
        "vector-four",
        &four,
        "normal = [0.0, 0.0, 1.0, 0.0]",
        &["expected a vector of 3 components [x, y, z], found 4 components"],
    );
    let text =
        format!("{GOOD}\n[[constraint]]\nbody = \"block\"\nnearest = [0.0, 0.0]\nfix = [\"x\"]\n");
    assert_error(
        "vector-two",
        &text,
        "nearest = [0.0, 0.0]",
        &["found 2 components"],
    );
}

/// A constraint names one set or one point (`nearest`), not both nor neither.
#[test]
fn constraint_needs_a_set_or_a_point() {
    for (case, lines, what) in [
        (
            "constraint-both",
            "set = \"bottom\"\nnearest = [0.0, 0.0, 0.0]\n",
            "found both",
        ),
        ("constraint-neither", "", "found neither"),
        (
            "constraint-nan",
            "nearest = [0.0, nan, 0.0]\n",
            "nearest must be a finite point",
        ),
    ] {
        let text = format!("{GOOD}\n[[constraint]]\nbody = \"block\"\n{lines}fix = [\"x\"]\n");
        assert_error(
            case,
            &text,
            "[[constraint]]",
            &[what, "constraint on \"block\""],
        );
    }
}

#[test]
fn material_constants() {
    let text = GOOD.replace("youngs_modulus = 1e9", "youngs_modulus = -1e9");
    assert_error(
        "negative-e",
        &text,
        "youngs_modulus",
        &["youngs_modulus", "positive", "got -1e9"],
    );
    let text = GOOD.replace("youngs_modulus = 1e9", "youngs_modulus = 0.0");
    assert_error(
        "zero-e",
        &text,
        "youngs_modulus",
        &["youngs_modulus", "positive"],
    );
    let text = GOOD.replace("density = 1000.0", "density = 0.0");
    assert_error("zero-density", &text, "density", &["density", "positive"]);
    let text = GOOD.replace("density = 1000.0", "density = -7800.0");
    assert_error(
        "negative-density",
        &text,
        "density",
        &["density", "positive"],
    );
    let text = GOOD.replace("poisson_ratio = 0.25", "poisson_ratio = 0.3");
    assert_error(
        "poisson",
        &text,
        "poisson_ratio",
        &["0.25", "0.3", "bond-based"],
    );
    // The LPS's influence function on a bond-based body, and a name it does not know.
    let text = GOOD.replace(
        "density = 1000.0",
        "density = 1000.0\ninfluence_function = \"constant\"",
    );
    assert_error(
        "influence-bond-based",
        &text,
        "influence_function",
        &["block", "lps"],
    );
    let text = GOOD.replace(
        "density = 1000.0",
        "density = 1000.0\nmodel = \"lps\"\ninfluence_function = \"gaussian\"",
    );
    assert_error(
        "influence-unknown",
        &text,
        "gaussian",
        &["position-aware", "constant"],
    );
    // A rigid body's optional material is checked as well.
    let text = GOOD.replace(
        "kind = \"rigid\"",
        "kind = \"rigid\"\nmaterial = { youngs_modulus = -2e11, poisson_ratio = 0.3, density = 7800.0 }",
    );
    assert_error("rigid-material", &text, "-2e11", &["floor", "positive"]);
}

#[test]
fn bodies_without_particles() {
    // A symmetry plane above the whole block keeps nothing of it.
    let text = format!(
        "{GOOD}\n[[symmetry]]\nbody = \"block\"\naxis = \"z\"\nat = 2.0\nkeep = \"positive\"\n"
    );
    assert_error(
        "clipped-away",
        &text,
        "name = \"block\"",
        &["block", "no particles"],
    );
    // The second body is the empty one: the message points at it, not at the first body.
    let text = format!(
        "{GOOD}\n[[body]]\nname = \"lid\"\ngenerator = {{ shape = \"box\", min = [0.0, 0.0, 1.0], max = [1.0, 1.0, 1.5], spacing = 0.25 }}\n[body.material]\nyoungs_modulus = 1e9\npoisson_ratio = 0.25\ndensity = 1000.0\n\n[[symmetry]]\nbody = \"lid\"\naxis = \"x\"\nat = 0.0\nkeep = \"negative\"\n"
    );
    assert_error(
        "clipped-second",
        &text,
        "name = \"lid\"",
        &["lid", "no particles"],
    );
}

#[test]
fn contact_pairs() {
    let text = GOOD.replace("master = \"floor\"", "master = \"block\"");
    assert_error(
        "same-body",
        &text,
        "slave = \"block\"",
        &["\"block\"", "both slave and master"],
    );
    let text = GOOD.replace("master = \"floor\"", "master = \"ground\"");
    assert_error(
        "contact-master",
        &text,
        "ground",
        &["no body is named \"ground\""],
    );
    let text = GOOD.replace("slave = \"block\"", "slave = \"ball\"");
    assert_error(
        "contact-slave",
        &text,
        "ball",
        &["no body is named \"ball\""],
    );
}

#[test]
fn references_to_missing_bodies() {
    let text = GOOD.replace("body = \"block\"\nset", "body = \"brick\"\nset");
    assert_error("load", &text, "brick", &["no body is named \"brick\""]);
    let text =
        format!("{GOOD}\n[[constraint]]\nbody = \"slab\"\nset = \"bottom\"\nfix = [\"z\"]\n");
    assert_error("constraint", &text, "slab", &["no body is named \"slab\""]);
    let text = format!("{GOOD}\n[[symmetry]]\nbody = \"half\"\naxis = \"x\"\n");
    assert_error("symmetry", &text, "half", &["no body is named \"half\""]);
}

/// A hand-written Gmsh 2.2 mesh of one hex8 whose corners are listed in mirrored order: its
/// volume is negative, which would corrupt the particle volumes.
#[test]
fn inverted_element_is_named() {
    let dir = temp_dir("inverted-mesh");
    let mesh = dir.join("inverted.msh");
    let mut text = String::from("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n8\n");
    let corners = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
    ];
    for (k, c) in corners.iter().enumerate() {
        text.push_str(&format!("{} {} {} {}\n", k + 1, c[0], c[1], c[2]));
    }
    text.push_str("$EndNodes\n$Elements\n1\n17 5 2 1 1 1 4 3 2 5 8 7 6\n$EndElements\n");
    std::fs::write(&mesh, text).expect("mesh");
    let scene = GOOD.replace(
        "generator = { shape = \"box\", min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 0.5], spacing = 0.25 }",
        &format!("mesh = \"{}\"", mesh.display()),
    )
    .replace("set = \"top\"\n", "");
    assert_error(
        "inverted",
        &scene,
        "name = \"block\"",
        &["element 17", "hex8", "negative volume", "inverted"],
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn numbers_that_cannot_be_used() {
    for (case, from, to, at, what) in [
        (
            "radius-zero",
            "radius = 0.5",
            "radius = 0.0",
            "radius = 0.0",
            "must be positive",
        ),
        (
            "radius-nan",
            "radius = 0.5",
            "radius = nan",
            "radius = nan",
            "must be positive",
        ),
        (
            "plane-normal-zero",
            "normal = [0.0, 0.0, 1.0]",
            "normal = [0.0, 0.0, 0.0]",
            "normal",
            "cannot be [0, 0, 0]",
        ),
        (
            "plane-point-inf",
            "point = [0.0, 0.0, -0.01]",
            "point = [0.0, 0.0, inf]",
            "point",
            "finite",
        ),
        (
            "translate-nan",
            "name = \"block\"",
            "name = \"block\"\ntranslate = [nan, 0.0, 0.0]",
            "translate",
            "finite",
        ),
    ] {
        let text = GOOD.replace(from, to);
        assert_ne!(text, GOOD, "{case}");
        assert_error(case, &text, at, &[what]);
    }
    let text = GOOD.replace("name = \"block\"", "name = \"block\"\nhorizon_factor = 0.5");
    assert_error(
        "horizon-below-one",
        &text,
        "horizon_factor",
        &["at least 1"],
    );
    let text = GOOD.replace(
        "kind = \"adr\"\nmax_iterations = 20000",
        "kind = \"explicit\"\nend_time = 0.0",
    );
    assert_error(
        "end-time-zero",
        &text,
        "end_time",
        &["end_time must be positive"],
    );
}

#[test]
fn spacing_with_no_bonds_and_a_scene_without_load() {
    let text = GOOD.replace("spacing = 0.25 }", "spacing = 0.25 }\nspacing = 1e-4");
    let (path, line) = error_of("no-bonds", &text);
    assert!(line.contains(&path), "{line}");
    assert!(line.contains("have no bond"), "{line}");
    let text = GOOD.replace("force = [0.0, 0.0, -1e5]", "force = [0.0, 0.0, 0.0]");
    let (path, line) = error_of("no-load", &text);
    assert!(line.contains(&path), "{line}");
    assert!(line.contains("nothing loads the model"), "{line}");
}

#[test]
fn check_builds_the_model_and_writes_nothing() {
    let dir = temp_dir("check");
    let scene = dir.join("scene.toml");
    let text = GOOD.replace(
        "max_iterations = 20000",
        "max_iterations = 20000\ndt = 1e-6",
    );
    std::fs::write(&scene, &text).expect("write scene");
    let out = Command::new(env!("CARGO_BIN_EXE_pdcontact"))
        .args(["run", "--check"])
        .arg(&scene)
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("dt is ignored by the adr solver"), "{err}");
    assert!(err.contains("ok (") && err.contains("particles"), "{err}");
    assert!(!dir.join("out").exists(), "--check wrote output");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn scene_mistakes_found_by_the_check_exit_2() {
    // A plane facing away from its slave: named with the pair, before solving.
    assert_error(
        "plane-backwards",
        &GOOD.replace("normal = [0.0, 0.0, 1.0]", "normal = [0.0, 0.0, -1.0]"),
        "[[contact]]",
        &[
            "contact pair \"block\" / \"floor\"",
            "behind the plane \"floor\"",
            "flip it",
        ],
    );
    // The normal as meant, the plane on the far side of the body: where it would clear it.
    assert_error(
        "plane-above",
        &GOOD.replace("point = [0.0, 0.0, -0.01]", "point = [0.0, 0.0, 1.0]"),
        "[[contact]]",
        &[
            "wrong side of the body",
            "would clear the body at [0, 0, 0]",
        ],
    );
    // Numerical failures before: max_iterations = 0, a symmetry plane listed twice.
    assert_error(
        "zero-iterations",
        &GOOD.replace("max_iterations = 20000", "max_iterations = 0"),
        "max_iterations",
        &["max_iterations must be at least 1, got 0"],
    );
    let sym = "\n[[symmetry]]\nbody = \"block\"\naxis = \"x\"\nat = 0.5\n";
    let text = format!("{GOOD}{sym}{sym}");
    let (path, line) = error_of("symmetry-twice", &text);
    let second = text.match_indices("[[symmetry]]").nth(1).unwrap().0;
    let want = format!("error: {path}:{}:", text[..second].lines().count() + 1);
    assert!(
        line.starts_with(&want) && line.contains("listed twice"),
        "{line}"
    );
    // "Too few iterations" before: a force of 1e300.
    assert_error(
        "huge-force",
        &GOOD.replace("-1e5]", "-1e300]"),
        "[[load]]",
        &["at most 1e30 N", "-1e300"],
    );
}

/// A loaded body that nothing holds: its path misses the plane (moved aside), the plane lies
/// behind its load (above it), or it is in no contact pair. Refused before solving, naming
/// the body's line and the direction of its loads, instead of relaxing to the iteration limit.
#[test]
fn a_loaded_body_that_nothing_holds_is_refused() {
    let beside = GOOD.replace("point = [0.0, 0.0, -0.01]", "point = [5.0, 0.0, -0.01]");
    let above = GOOD.replace(
        "point = [0.0, 0.0, -0.01], normal = [0.0, 0.0, 1.0]",
        "point = [0.0, 0.0, 0.6], normal = [0.0, 0.0, -1.0]",
    );
    let free = GOOD.split("[[contact]]").next().expect("scene").to_string();
    for (case, text, why) in [
        ("beside", &beside, "meets no plane"),
        ("above", &above, "meets no plane"),
        ("free", &free, "in no contact pair"),
    ] {
        let (path, line) = error_of(&format!("held-{case}"), text);
        assert!(
            line.contains(&format!(
                "{path}:{}:1:",
                line_of(text, "name = \"block\"") - 1
            )) && line.contains("body \"block\" is pushed along [0, 0, -1]")
                && line.contains(why),
            "{case}: {line}"
        );
    }
    // Held by a constraint instead: accepted (the check, not a solve).
    let fixed = format!(
        "{free}\n[[constraint]]\nbody = \"block\"\nset = \"bottom\"\nfix = [\"x\", \"y\", \"z\"]\n"
    );
    let dir = temp_dir("held-fixed");
    std::fs::write(dir.join("scene.toml"), &fixed).expect("write scene");
    let out = Command::new(env!("CARGO_BIN_EXE_pdcontact"))
        .args(["run", "--check"])
        .arg(dir.join("scene.toml"))
        .output()
        .expect("runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Fracture keys and pre-cracks: what cannot be run is named where it is written.
#[test]
fn fracture_errors() {
    let text = GOOD.replace(
        "density = 1000.0",
        "density = 1000.0\nfracture_energy = 100.0\ncritical_stretch = 0.01",
    );
    assert_error("both-keys", &text, "critical_stretch", &["not both"]);
    let text = GOOD.replace(
        "density = 1000.0",
        "density = 1000.0\nfracture_energy = -1.0",
    );
    assert_error("negative-g0", &text, "fracture_energy", &["positive", "-1"]);
    let text = GOOD.replace(
        "density = 1000.0",
        "density = 1000.0\nfailure = \"tension\"",
    );
    assert_error(
        "failure-alone",
        &text,
        "failure",
        &["fracture_energy or critical_stretch"],
    );
    let crack = |point: &str, normal: &str| {
        format!(
            "{GOOD}\n[[precrack]]\nbody = \"block\"\npoint = {point}\nnormal = {normal}\nalong = [0.0, 1.0, 0.0]\nsize = [0.5, 2.0]\n"
        )
    };
    let text = crack("[0.5, 0.5, 0.25]", "[0.0, 1.0, 0.0]");
    assert_error("parallel", &text, "[[precrack]]", &["along", "parallel"]);
    let text = crack("[5.0, 0.5, 0.25]", "[1.0, 0.0, 0.0]");
    assert_error("outside", &text, "[[precrack]]", &["cuts no bond", "block"]);
    let text = format!(
        "{}\n[[symmetry]]\nbody = \"block\"\naxis = \"x\"\nat = 0.5\n",
        crack("[0.5, 0.5, 0.25]", "[1.0, 0.0, 0.0]")
    );
    assert_error(
        "on-symmetry",
        &text,
        "[[precrack]]",
        &["symmetry plane x = 0.5", "cannot open"],
    );
    let text = GOOD.replace("size = 3.0 }", "size = 3.0 }\nmotion = \"displacement\"");
    assert_error(
        "no-displacement",
        &text,
        "name = \"floor\"",
        &["displacement = [dx, dy, dz]"],
    );
    let text = GOOD
        .replace(
            "size = 3.0 }",
            "size = 3.0 }\nmotion = \"displacement\"\ndisplacement = [0.0, 0.0, 0.01]",
        )
        .replace("kind = \"adr\"", "kind = \"explicit\"\nend_time = 1e-3");
    assert_error(
        "explicit-displacement",
        &text,
        "displacement = [",
        &["kind = \"adr\"", "velocity"],
    );
    // A body that cannot break is not its own short-range master: it has no pieces.
    let own = "\n[[contact]]\nslave = \"block\"\nmaster = \"block\"\nmethod = \"short-range\"\n";
    let text = format!("{GOOD}{own}");
    let (path, line) = error_of("pieces-of-a-whole-body", &text);
    // At the pair's own `slave` line, not the first pair's.
    let at = text.lines().count() - 2;
    assert!(
        line.starts_with(&format!("error: {path}:{at}:1: ")),
        "{line}"
    );
    assert!(
        line.contains("cannot break") && line.contains("fracture_energy"),
        "{line}"
    );
}

#[test]
fn friction_and_load_path_errors() {
    let with = |key: &str| GOOD.replace("radius = 0.5", &format!("radius = 0.5\n{key}"));
    assert_error(
        "negative-friction",
        &with("friction = -0.1"),
        "[[contact]]",
        &["friction", "-0.1"],
    );
    assert_error(
        "percent-friction",
        &with("friction = 30.0"),
        "[[contact]]",
        &["percent"],
    );
    assert_error(
        "one-step-friction",
        &with("friction = 0.3"),
        "[[contact]]",
        &["load_steps", "frictionless"],
    );
    let text = with("friction = 0.3").replace("kind = \"adr\"", "kind = \"static\"");
    assert_error(
        "static-one-step-friction",
        &text,
        "[[contact]]",
        &["kind = \"static\"", "load_steps"],
    );
    let ramped = |ramp: &str| {
        GOOD.replace(
            "force = [0.0, 0.0, -1e5]",
            &format!("force = [0.0, 0.0, -1e5]\nramp = {ramp}"),
        )
    };
    assert_error(
        "backward-ramp",
        &ramped("[0.6, 0.4]"),
        "[[load]]",
        &["ramp", "0.6", "0.4"],
    );
    let text =
        ramped("[0.0, 0.5]").replace("kind = \"adr\"", "kind = \"explicit\"\nend_time = 1e-4");
    assert_error("explicit-ramp", &text, "[[load]]", &["explicit", "adr"]);
    assert_error(
        "one-step-ramp",
        &ramped("[0.0, 0.5]"),
        "ramp",
        &["load_steps"],
    );
    let text = format!(
        "{GOOD}\n[[constraint]]\nbody = \"block\"\nset = \"top\"\nfix = [\"x\"]\ndisplacement = [0.0, 0.001, 0.0]\n"
    );
    assert_error(
        "unheld-displacement",
        &text,
        "[[constraint]]",
        &["fix", "along y"],
    );
}
