//! docs/guide/tutorial.md, run: its commands on the stored mesh, in its order, with its edits,
//! and the figures it quotes measured again (the refined run of its last step is not run
//! here: 80,000 particles take minutes). Each command and figure checked here must also be on
//! the page, so that the page and the program cannot part.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

/// Runs `pdcontact ARGS` in `dir`, as the tutorial's reader types it there.
fn pdcontact(dir: &Path, args: &[&str]) -> Output {
    let out = Command::new(env!("CARGO_BIN_EXE_pdcontact"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("runs");
    assert!(
        out.status.success(),
        "pdcontact {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// The number after `key` in `line` (up to the next space, `%` or `,`).
fn number_after(line: &str, key: &str) -> f64 {
    let rest = &line[line
        .find(key)
        .unwrap_or_else(|| panic!("{key:?} in {line}"))
        + key.len()..];
    let end = rest.find([' ', '%', ',', ')']).unwrap_or(rest.len());
    rest[..end]
        .trim_start_matches('+')
        .parse()
        .unwrap_or_else(|e| panic!("{rest}: {e}"))
}

#[test]
fn the_tutorial_runs_as_written() {
    let page = std::fs::read_to_string(repo("docs/guide/tutorial.md")).expect("tutorial.md");
    let on_page = |s: &str| assert!(page.contains(s), "tutorial.md lacks {s:?}");
    let dir = std::env::temp_dir().join(format!("pdcontact-tutorial-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // 1. The mesh: the stored copy of what meshes/sphere_tet4_h007.geo makes.
    on_page("cp meshes/sphere_tet4_h007.msh sphere.msh");
    std::fs::copy(repo("meshes/sphere_tet4_h007.msh"), dir.join("sphere.msh")).unwrap();

    // 2. Inspect.
    on_page("pdcontact inspect sphere.msh");
    let inspect = text(&pdcontact(&dir, &["inspect", "sphere.msh"]).stdout);
    for line in [
        "nodes: 10537 (10537 corners of 3D elements)",
        "3D elements: 55760 (55760 tet4)",
    ] {
        assert!(inspect.contains(line), "{inspect}");
        on_page(line);
    }

    // 3. Convert: the case, and the warning that the contact is coarse.
    on_page("pdcontact convert sphere.msh -o case");
    let convert = pdcontact(&dir, &["convert", "sphere.msh", "-o", "case"]);
    let (out, err) = (text(&convert.stdout), text(&convert.stderr));
    assert!(out.contains("particles 10537 "), "{out}");
    on_page("particles 10537 ");
    assert!(
        err.contains("which spans 2.3 surface spacings (h = 0.0649 m"),
        "{err}"
    );
    on_page("which spans 2.3 surface spacings (h = 0.0649 m");

    // 4. The edits: the material and the load.
    let case = dir.join("case/case.toml");
    let toml = std::fs::read_to_string(&case).unwrap();
    let edited = toml
        .lines()
        .map(|l| {
            if l.starts_with("youngs_modulus = ") {
                "youngs_modulus = 3e9          # E, Pa: 3 GPa".to_string()
            } else if l.starts_with("force = ") {
                "force = [0.0, 0.0, -1.44e7]   # 14.4 MN down".to_string()
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    on_page("youngs_modulus = 3e9          # E, Pa: 3 GPa");
    on_page("force = [0.0, 0.0, -1.44e7]   # 14.4 MN down");
    assert_ne!(edited, toml, "the edits found their lines");
    std::fs::write(&case, edited).unwrap();

    // 5. Check: the same warning, no unit slip, and the model's size.
    on_page("pdcontact run --check case/case.toml");
    let check = text(&pdcontact(&dir, &["run", "--check", "case/case.toml"]).stderr);
    assert!(!check.contains("Units are SI"), "{check}");
    let ok = "case/case.toml: ok (10537 particles, 1529238 bonds)";
    assert!(check.contains(ok), "{check}");
    on_page(ok);

    // 6. Run: converged, and the accuracy line, as on the page.
    on_page("pdcontact run case/case.toml");
    let run = text(&pdcontact(&dir, &["run", "case/case.toml"]).stderr);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("case/out/summary.json")).unwrap())
            .unwrap();
    assert_eq!(summary["converged"], true);
    let line = run
        .lines()
        .find(|l| l.starts_with("accuracy: "))
        .unwrap_or_else(|| panic!("no accuracy line: {run}"));
    let radius = number_after(line, "contact radius ");
    let radius_error = number_after(line, "m against Hertz's 0.1500 m (");
    let peak_error = number_after(line, "Pa against 3.0558e8 Pa (");
    // The page quotes 0.1672 m, +11.5 % and -9.5 %: the same to the rounding of threads.
    assert!((radius - 0.1672).abs() < 5e-4, "{line}");
    assert!(
        (radius_error - 11.5).abs() < 0.35 && (peak_error + 9.5).abs() < 0.35,
        "{line}"
    );
    for s in [
        "contact radius 0.1672 m against Hertz's 0.1500 m (+11.5 %)",
        "against 3.0558e8 Pa (-9.5 %)",
        "--contact-ratio 0.15",
    ] {
        assert!(line.contains(s), "{line}");
        on_page(s);
    }

    // 8. The mesh at this contact size, against Hertz: the same error, so it is the mesh's.
    let validate_args = [
        "validate",
        "--mesh",
        "sphere.msh",
        "--contact-ratio",
        "0.15",
        "--refine",
        "0",
    ];
    on_page(&format!("pdcontact {}", validate_args.join(" ")));
    let validate = text(&pdcontact(&dir, &validate_args).stdout);
    let row = validate
        .lines()
        .find(|l| l.starts_with("sphere  mesh"))
        .unwrap_or_else(|| panic!("{validate}"));
    let cells: Vec<&str> = row.split_whitespace().collect();
    // case set theory(2 words) Δ m particles MRE radius peak shear balance iters seconds
    let pct = |s: &str| s.trim_end_matches('%').parse::<f64>().unwrap();
    let (mre, r_err, p_err) = (pct(cells[7]), pct(cells[8]), pct(cells[9]));
    assert!(
        (mre - 10.86).abs() < 0.2 && (r_err - 10.31).abs() < 0.2 && (p_err + 9.90).abs() < 0.2,
        "{row}"
    );
    for s in ["10.86%", "+10.31%", "-9.90%"] {
        on_page(s);
    }
    let _ = std::fs::remove_dir_all(&dir);
}
