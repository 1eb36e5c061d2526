//! The user guide cannot drift from the program: every scene key that docs/guide/scene.md
//! shows (set or commented out as an alternative) is accepted by the scene parser, and every
//! option that a command's `--help` lists is in docs/guide/commands.md.

use std::path::Path;

use pdcontact::scene::Scene;

/// A valid scene with one of each block, into which each documented key is put in turn.
const BASE: &str = r#"
[solver]
kind = "adr"

[output]
folder = "out"

[[body]]
name = "ball"
generator = { shape = "sphere", radius = 1.0, spacing = 0.25 }
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0

[[body]]
name = "floor"
kind = "rigid"
generator = { shape = "plane", point = [0.0, 0.0, -1.0], normal = [0.0, 0.0, 1.0], size = 3.0 }

[[load]]
body = "ball"
force = [0.0, 0.0, -1e6]

[[constraint]]
body = "ball"
nearest = [0.0, 0.0, 0.0]
fix = ["x", "y"]

[[symmetry]]
body = "ball"
axis = "x"

[[contact]]
slave = "ball"
master = "floor"

[[precrack]]
body = "ball"
point = [0.0, 0.0, 0.5]
normal = [0.0, 0.0, 1.0]
along = [1.0, 0.0, 0.0]
size = [0.5, 0.5]
"#;

/// `(section, line)` for every `key = value` line of the page's TOML blocks, commented-out
/// alternatives (`# key = value`) included; the section is the block's last table header.
fn documented_keys(page: &str) -> Vec<(String, String)> {
    let mut keys = Vec::new();
    let mut in_toml = false;
    let mut section = String::new();
    for line in page.lines() {
        if line.starts_with("```") {
            in_toml = line.trim() == "```toml";
            continue;
        }
        if !in_toml {
            continue;
        }
        let t = line.trim();
        if t.starts_with('[') {
            section = t.trim_matches(|c| c == '[' || c == ']').to_string();
            continue;
        }
        let body = t.strip_prefix('#').map_or(t, str::trim_start);
        let is_key = body.split_once('=').is_some_and(|(k, _)| {
            let k = k.trim();
            !k.is_empty() && k.chars().all(|c| c.is_ascii_lowercase() || c == '_')
        });
        if is_key {
            keys.push((section.clone(), body.to_string()));
        }
    }
    keys
}

#[test]
fn every_scene_key_in_the_guide_is_one_the_parser_accepts() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/guide/scene.md");
    let page = std::fs::read_to_string(&path).expect("docs/guide/scene.md");
    let keys = documented_keys(&page);
    // The page documents every block: a parse of it that found few keys is a broken test.
    assert!(keys.len() > 50, "{} keys found", keys.len());
    for section in [
        "solver",
        "output",
        "body",
        "body.material",
        "load",
        "constraint",
        "symmetry",
        "contact",
        "precrack",
    ] {
        assert!(
            keys.iter().any(|(s, _)| s == section),
            "no key under [{section}]"
        );
    }
    for (section, line) in &keys {
        let entry: toml::Table = toml::from_str(line)
            .unwrap_or_else(|e| panic!("[{section}] `{line}` is not TOML: {e}"));
        let mut scene: toml::Table = toml::from_str(BASE).expect("base scene");
        let table = match section.as_str() {
            "solver" | "output" => scene[section.as_str()].as_table_mut(),
            "body.material" => scene["body"].as_array_mut().and_then(|a| {
                a[0].as_table_mut()
                    .and_then(|b| b.get_mut("material"))
                    .and_then(toml::Value::as_table_mut)
            }),
            "body" | "load" | "constraint" | "symmetry" | "contact" | "precrack" => scene
                [section.as_str()]
            .as_array_mut()
            .and_then(|a| a[0].as_table_mut()),
            other => panic!("`{line}` under an unknown section [{other}] in scene.md"),
        }
        .expect("the base scene has the section");
        for (k, v) in entry {
            table.insert(k, v);
        }
        let text = toml::to_string(&scene).expect("serialises");
        // The value may not suit the base scene (a mesh file that is not there, a kind that
        // wants other keys): only an unknown key is the page's fault.
        if let Err(e) = Scene::parse(&text, "scene.md", Path::new(".")) {
            let e = e.to_string();
            assert!(
                !e.contains("unknown field") && !e.contains("unknown key"),
                "docs/guide/scene.md, [{section}] `{line}`: {e}"
            );
        }
    }
}

/// Every option that `pdcontact COMMAND --help` lists is in docs/guide/commands.md: an option
/// added to the program without its line in the guide fails here.
#[test]
fn every_command_option_is_in_the_guide() {
    let page = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/guide/commands.md"),
    )
    .expect("docs/guide/commands.md");
    let mut checked = 0;
    for command in [
        "inspect", "convert", "run", "demo", "validate", "fracture", "sweep", "bench",
    ] {
        assert!(
            page.contains(&format!("## {command}")),
            "commands.md has no section for {command}"
        );
        let help = std::process::Command::new(env!("CARGO_BIN_EXE_pdcontact"))
            .args([command, "--help"])
            .output()
            .expect("runs");
        let help = String::from_utf8_lossy(&help.stdout);
        for option in help
            .split_whitespace()
            .filter(|w| w.starts_with("--") && w.len() > 2)
            .map(|w| w.trim_end_matches([',', '.', ')', ']', ':', ';', '`']))
            .filter(|w| *w != "--help")
        {
            assert!(
                page.contains(option),
                "`pdcontact {command} --help` lists {option}, docs/guide/commands.md does not"
            );
            checked += 1;
        }
    }
    assert!(checked > 30, "{checked} options checked");
}
