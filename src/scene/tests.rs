use super::*;

const GOOD: &str = r#"
[solver]
kind = "adr"

[[body]]
name = "ball"
generator = { shape = "sphere", radius = 1.0, spacing = 0.2 }
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0

[[body]]
name = "plane"
kind = "rigid"
generator = { shape = "plane", point = [0.0, 0.0, -1.0], normal = [0.0, 0.0, 1.0], size = 4.0 }

[[load]]
body = "ball"
force = [0.0, 0.0, -1e6]

[[contact]]
slave = "ball"
master = "plane"
"#;

fn parse(s: &str) -> Result<Scene> {
    Scene::parse(s, "scene.toml", Path::new("."))
}

#[test]
fn good_scene_parses() {
    let s = parse(GOOD).expect("valid");
    assert_eq!(s.bodies.len(), 2);
    assert_eq!(s.contacts[0].penalty, PenaltyLaw::Hertz);
}

fn error_of(s: &str) -> String {
    match parse(s) {
        Ok(_) => panic!("accepted: {s}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn unknown_key_has_line_and_column() {
    let bad = GOOD.replace("kind = \"adr\"", "kind = \"adr\"\ntolerence = 1e-4");
    let e = error_of(&bad);
    assert!(e.starts_with("scene.toml:4:1:"), "{e}");
    assert!(e.contains("tolerence"), "{e}");
}

#[test]
fn wrong_type_has_line_and_column() {
    let bad = GOOD.replace("youngs_modulus = 1e9", "youngs_modulus = \"stiff\"");
    let e = error_of(&bad);
    assert!(e.starts_with("scene.toml:9:"), "{e}");
    // In a user's words, not Rust's: what was found and what was expected.
    assert!(
        e.contains("\"stiff\"") && e.contains("expected a number"),
        "{e}"
    );
    let e = error_of(&GOOD.replace("kind = \"adr\"", "kind = \"adr\"\nmax_iterations = -1"));
    assert!(
        e.contains("-1") && e.contains("a whole number, 0 or more"),
        "{e}"
    );
    assert!(!e.contains("usize"), "{e}");
    let e = error_of(&GOOD.replace("force = [0.0, 0.0, -1e6]", "force = \"-1 MN\""));
    assert!(e.contains("expected an array"), "{e}");
    let e = error_of(&GOOD.replace("[solver]\nkind = \"adr\"", ""));
    assert!(e.contains("[solver] table"), "{e}");
}

#[test]
fn semantic_errors_name_the_place() {
    let e = error_of(&GOOD.replace("poisson_ratio = 0.25", "poisson_ratio = 0.3"));
    assert!(e.contains("scene.toml:10:1") && e.contains("0.25"), "{e}");
    assert!(e.contains("model = \"lps\""), "{e}");
    // The LPS takes 0.3, and refuses what it cannot hold, saying why.
    let lps = GOOD.replace(
        "poisson_ratio = 0.25",
        "poisson_ratio = 0.3\nmodel = \"lps\"",
    );
    Scene::parse(&lps, "scene.toml", Path::new(".")).expect("LPS at 0.3");
    let e = error_of(&lps.replace("poisson_ratio = 0.3", "poisson_ratio = 0.495"));
    assert!(e.contains("(-1, 0.49]") && e.contains("locks"), "{e}");
    let e = error_of(&lps.replace("poisson_ratio = 0.3", "poisson_ratio = -1.0"));
    assert!(e.contains("(-1, 0.49]"), "{e}");
    let e = error_of(&GOOD.replace("youngs_modulus = 1e9", "youngs_modulus = -1e9"));
    assert!(
        e.contains("scene.toml:9:1") && e.contains("positive"),
        "{e}"
    );
    let e = error_of(&GOOD.replace("density = 1000.0", "density = 0.0"));
    assert!(e.contains("density must be positive"), "{e}");
    let e = error_of(&GOOD.replace("master = \"plane\"", "master = \"ball\""));
    assert!(
        e.contains("both slave and master") && e.contains(":23:"),
        "{e}"
    );
    let e = error_of(&GOOD.replace("master = \"plane\"", "master = \"floor\""));
    assert!(e.contains("no body is named \"floor\""), "{e}");
    assert!(e.contains("the scene's bodies: \"ball\", \"plane\""), "{e}");
}

#[test]
fn scene_mistakes_are_input_errors_that_name_the_key() {
    let cases: Vec<(String, &[&str])> = vec![
        // Keys a shape does not use, and no quads.
        (
            GOOD.replace("size = 4.0 }", "size = 4.0, spacing = 0.1 }"),
            &[":16:", "does not use `spacing`"],
        ),
        (
            GOOD.replace("size = 4.0 }", "size = 4.0, radius = 1.0 }"),
            &["does not use `radius`"],
        ),
        (
            GOOD.replace("spacing = 0.2 }", "spacing = 0.2, size = 1.0 }"),
            &["generator \"sphere\" does not use `size`"],
        ),
        (
            GOOD.replace("size = 4.0 }", "size = 4.0, divisions = 0 }"),
            &["divisions must be at least 1, got 0"],
        ),
        // Sizes that cannot fit: refused before allocating, with what they would need.
        (
            GOOD.replace("size = 4.0 }", "size = 4.0, divisions = 100000 }"),
            &["1e10 faces", "720 GB"],
        ),
        (
            GOOD.replace("spacing = 0.2 }", "spacing = 1e-300 }"),
            &[":7:", "spacing 1e-300 makes more than 1e308 particles", "GB of memory"],
        ),
        (GOOD.replace("kind = \"adr\"", "kind = \"adr\"\nmax_iterations = 0"), &[":4:1:", "max_iterations must be at least 1"]),
        (
            GOOD.replace("-1e6]", "-1e300]"),
            &[":18:1:", "at most 1e30 N", "-1e300"],
        ),
        (
            format!("{GOOD}\n[[contact]]\nslave = \"ball\"\nmaster = \"plane\"\n"),
            &[":26:1:", "listed twice ([[contact]] blocks 1 and 2)"],
        ),
        (
            format!("{GOOD}\n[[symmetry]]\nbody = \"ball\"\naxis = \"x\"\n[[symmetry]]\nbody = \"ball\"\naxis = \"x\"\n"),
            &[":29:1:", "x = 0 is listed twice"],
        ),
        // Values are repeated short: excerpts and exponents.
        (
            GOOD.replace("\"sphere\"", &format!("\"{}\"", "s".repeat(100_000))),
            &["(100000 characters)"],
        ),
        (
            GOOD.replace("density = 1000.0", "density = -1e-300"),
            &["got -1e-300"],
        ),
    ];
    for (text, wants) in cases {
        let e = error_of(&text);
        assert!(e.len() < 400, "{} chars: {}", e.len(), &e[..400]);
        for w in wants {
            assert!(e.contains(w), "{w:?} not in {e}");
        }
    }
}

#[test]
fn options_the_solver_ignores_are_warnings() {
    let s = parse(&GOOD.replace("kind = \"adr\"", "kind = \"adr\"\ndt = 1e-6")).unwrap();
    assert_eq!(
        s.warnings(),
        ["scene.toml:4:1: [solver] dt is ignored by the adr solver"]
    );
    let s = parse(&GOOD.replace(
        "kind = \"adr\"",
        "kind = \"explicit\"\nend_time = 1e-3\ntolerance = 1e-4",
    ))
    .unwrap();
    assert_eq!(
        s.warnings(),
        ["scene.toml:5:1: [solver] tolerance is ignored by the explicit solver"]
    );
    assert!(parse(GOOD).unwrap().warnings().is_empty());
}

#[test]
fn numbers_print_short() {
    assert_eq!(num(1e-300), "1e-300");
    assert_eq!(num(-0.0), "0");
    assert_eq!(num(0.25), "0.25");
    assert_eq!(num(3.84e7), "3.84e7");
    assert_eq!(excerpt("abc"), "abc");
}
