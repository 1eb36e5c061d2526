//! Scenes whose bodies are placed where they cannot be solved: bodies that start
//! interpenetrating, planes out of scale with the bodies, bodies placed where f64 cannot tell
//! their nodes apart, and loaded bodies that nothing holds. `pdcontact run` exits with 2 and
//! one line `FILE:LINE:COL: message` naming the scene line and the bodies.

use std::path::PathBuf;
use std::process::{Command, Output};

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pdcontact-place-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// A box resting on a rigid plane (spacing 0.25 m: contact window 0.125 m).
const ON_PLANE: &str = r#"[solver]
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

/// A ball (spacing 0.18 m: contact window 0.09 m) on a deformable base whose top is at
/// `TOP` (-1 touches the ball), fixed at its bottom.
const ON_BASE: &str = r#"[solver]
kind = "adr"
max_iterations = 200000

[output]
every = 100000

[[body]]
name = "ball"
generator = { shape = "sphere", radius = 1.0, spacing = 0.25 }
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0

[[body]]
name = "base"
generator = { shape = "box", min = [-1.5, -1.5, -1.5], max = [1.5, 1.5, TOP], spacing = 0.25 }
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0

[[constraint]]
body = "base"
set = "bottom"
fix = ["x", "y", "z"]

[[load]]
body = "ball"
force = [0.0, 0.0, -1e5]

[[contact]]
slave = "ball"
master = "base"
"#;

/// Runs `pdcontact run` (with `--check` when `check`) on `text` in its own folder.
fn run(case: &str, text: &str, check: bool) -> (PathBuf, Output) {
    let dir = temp_dir(case);
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, text).expect("write scene");
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_pdcontact"));
    cmd.arg("run");
    if check {
        cmd.arg("--check");
    } else {
        cmd.arg("--quiet");
    }
    let out = cmd.arg(&scene).output().expect("runs");
    (dir, out)
}

/// 1-based line of the first line of `text` holding `needle` (the `nth` such line).
fn line_of(text: &str, needle: &str, nth: usize) -> usize {
    text.lines()
        .enumerate()
        .filter(|(_, l)| l.contains(needle))
        .nth(nth)
        .unwrap_or_else(|| panic!("{needle} not in the scene"))
        .0
        + 1
}

/// Asserts exit code 2 and one line `error: SCENE:LINE:COL: …` at the `nth` line holding
/// `at`, containing each of `what`; returns the line.
fn assert_refused(case: &str, text: &str, check: bool, at: (&str, usize), what: &[&str]) -> String {
    let (dir, out) = run(case, text, check);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(2), "{case}: {err}");
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "{case}: not one line: {err}");
    let want = format!(
        "error: {}:{}:",
        dir.join("scene.toml").display(),
        line_of(text, at.0, at.1)
    );
    assert!(
        lines[0].starts_with(&want),
        "{case}: expected {want}…, got {err}"
    );
    for w in what {
        assert!(lines[0].contains(w), "{case}: {err} lacks {w:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
    lines[0].to_string()
}

/// Asserts that `run --check` accepts the scene.
fn assert_accepted(case: &str, text: &str) {
    let (dir, out) = run(case, text, true);
    assert!(
        out.status.success(),
        "{case}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_body_placed_through_a_plane_is_refused_one_touching_it_is_not() {
    // The box's bottom layer 0.2 m behind the plane: a third of its particles, deeper than
    // the window. It used to fail at iteration 1 blaming the load ("missed contact").
    assert_refused(
        "sunk",
        &ON_PLANE.replace("-0.01]", "0.2]"),
        false,
        ("[[contact]]", 0),
        &[
            "contact pair \"block\" / \"floor\": the bodies start interpenetrating",
            "25 of 66 surface particles of \"block\" lie behind the plane \"floor\"",
            "up to 0.2 m deep",
            "contact window (0.5 Δ = 0.125 m)",
        ],
    );
    // Touching: the bottom layer 0.05 m behind the plane, within the window.
    assert_accepted("touching-plane", &ON_PLANE.replace("-0.01]", "0.05]"));
}

#[test]
fn bodies_that_start_inside_each_other_are_refused() {
    for (case, top, what) in [
        (
            "overlap-shallow",
            "-0.8",
            "lie inside \"base\", up to 0.2 m deep",
        ),
        (
            "overlap-deep",
            "0.5",
            "lie inside \"base\", up to 0.923 m deep",
        ),
    ] {
        assert_refused(
            case,
            &ON_BASE.replace("TOP", top),
            true,
            ("[[contact]]", 0),
            &[
                "contact pair \"ball\" / \"base\": the bodies start interpenetrating",
                "surface particles of \"ball\"",
                what,
            ],
        );
    }
    // Touching, and within the window (0.05 m into the base).
    assert_accepted("overlap-touching", &ON_BASE.replace("TOP", "-1.0"));
    assert_accepted("overlap-within", &ON_BASE.replace("TOP", "-0.95"));
    // A two-pass pair is checked both ways. The base as slave, coarse (window 0.25 m): its
    // particles lie at most 0.2 m inside the ball, but the ball's 0.2 m inside it.
    let one_pass = ON_BASE
        .replace("TOP], spacing = 0.25", "-0.8], spacing = 0.5")
        .replace(
            "slave = \"ball\"\nmaster = \"base\"",
            "slave = \"base\"\nmaster = \"ball\"",
        );
    assert_accepted("overlap-one-pass", &one_pass);
    assert_refused(
        "overlap-two-pass",
        &format!("{one_pass}two_pass = true\n"),
        true,
        ("[[contact]]", 0),
        &[
            "contact pair \"base\" / \"ball\": the bodies start interpenetrating",
            "surface particles of \"ball\" lie inside \"base\"",
        ],
    );
}

#[test]
fn planes_and_bodies_out_of_scale_are_refused() {
    let plane = ("generator = { shape = \"plane\"", 0);
    for (case, from, to, at, what) in [
        (
            "size-huge",
            "size = 3.0",
            "size = 1e300",
            plane,
            "the plane's size 1e300 is out of scale with the scene's other bodies",
        ),
        (
            "size-tiny",
            "size = 3.0",
            "size = 1e-300",
            plane,
            "the plane's size 1e-300 is out of scale",
        ),
        (
            "point-far",
            "point = [0.0, 0.0, -0.01]",
            "point = [0.0, 0.0, 1e300]",
            plane,
            "the plane lies 1e300 m from the scene's other bodies",
        ),
        (
            "plane-scale",
            "name = \"floor\"",
            "name = \"floor\"\nscale = 1e300",
            ("scale = 1e300", 0),
            "the plane's size times scale 3e300 is out of scale",
        ),
        (
            "body-far",
            "name = \"block\"",
            "name = \"block\"\ntranslate = [0.0, 0.0, 1e20]",
            ("translate", 0),
            "body \"block\" lies 1e20 m from the origin once placed, more than 1e8 times its size",
        ),
    ] {
        let text = ON_PLANE.replace(from, to);
        assert_ne!(text, ON_PLANE, "{case}");
        assert_refused(case, &text, true, at, &[what]);
    }
    // Directions with huge or tiny components are the directions they point in (their norm
    // used to overflow into a zero normal, blamed on the plane's size).
    for (case, normal) in [
        ("normal-huge", "[0.0, 1e-300, 1e300]"),
        ("normal-tiny", "[0.0, 0.0, 1e-300]"),
    ] {
        let text = ON_PLANE.replace("normal = [0.0, 0.0, 1.0]", &format!("normal = {normal}"));
        assert_accepted(case, &text);
    }
}

#[test]
fn a_loaded_body_on_bodies_that_nothing_holds_is_refused() {
    let ball = "name = \"ball\"";
    // The base is free: the ball's load would carry both away.
    let text = ON_BASE.replace("TOP", "-1.0").replace(
        "[[constraint]]\nbody = \"base\"\nset = \"bottom\"\nfix = [\"x\", \"y\", \"z\"]\n",
        "",
    );
    let line = assert_refused(
        "group-free",
        &text,
        true,
        ("[[body]]", 0),
        &[
            "body \"ball\" is pushed along [0, 0, -1] by its loads",
            "nor do the bodies it is in contact with, directly or through others (\"base\")",
        ],
    );
    // The message names the [[body]] line above the name.
    assert!(
        line.contains(&format!(":{}:1:", line_of(&text, ball, 0) - 1)),
        "{line}"
    );
    // The base fixed beside the ball's path, or under it while the load pulls the ball up.
    for (case, text) in [
        (
            "beside",
            ON_BASE
                .replace("TOP", "-1.0")
                .replace("min = [-1.5, -1.5, -1.5]", "min = [3.0, -1.5, -1.5]")
                .replace("max = [1.5, 1.5, -1.0]", "max = [6.0, 1.5, -1.0]"),
        ),
        (
            "away",
            ON_BASE
                .replace("[-1.5, -1.5, -1.5]", "[-1.5, -1.5, -2.5]")
                .replace("TOP", "-1.5")
                .replace("-1e5]", "1e5]"),
        ),
    ] {
        assert_refused(
            case,
            &text,
            true,
            ("[[body]]", 0),
            &[
                "body \"ball\" is pushed along",
                "its path in that direction meets none of the bodies it is in contact with (\"base\": beside it or behind it)",
            ],
        );
    }
}

/// A block pushed down past the side of a fixed ball: the boxes of the two overlap, so the
/// check before solving cannot tell, and ADR used to accelerate the block until
/// `max_iterations` (200000 here). The run stops once the block is past the ball.
#[test]
fn a_body_that_goes_past_what_it_touches_stops_the_run() {
    let text = ON_BASE
        .replace("TOP", "-1.0")
        .replace("name = \"base\"", "name = \"block\"")
        .replace(
            "min = [-1.5, -1.5, -1.5], max = [1.5, 1.5, -1.0], spacing = 0.25",
            "min = [0.85, 0.85, 1.2], max = [1.35, 1.35, 1.45], spacing = 0.125",
        )
        .replace(
            "body = \"base\"\nset = \"bottom\"",
            "body = \"ball\"\nset = \"top\"",
        )
        .replace("body = \"ball\"\nforce", "body = \"block\"\nforce")
        .replace(
            "slave = \"ball\"\nmaster = \"base\"",
            "slave = \"block\"\nmaster = \"ball\"",
        );
    assert_accepted("past-check", &text);
    let (dir, out) = run("past", &text, false);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(2), "{err}");
    let want = format!(
        "error: {}:{}:1: body \"block\" went past every body it is in contact with (\"ball\") along [0, 0, -1], the direction of its loads, with no contact force",
        dir.join("scene.toml").display(),
        line_of(&text, "[[body]]", 1)
    );
    assert!(err.starts_with(&want) && err.lines().count() == 1, "{err}");
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("out/summary.json")).expect("summary"),
    )
    .expect("json");
    let iterations = summary["iterations"].as_u64().expect("iterations");
    assert!(iterations < 5000, "{iterations} iterations");
    assert!(summary["error"]
        .as_str()
        .is_some_and(|e| e.contains("went past")));
    let _ = std::fs::remove_dir_all(&dir);
}
