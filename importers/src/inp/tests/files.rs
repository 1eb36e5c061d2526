//! Decks read from files: the shared corpus and *INCLUDE / INPUT= files in a temporary directory.

use super::*;
use crate::summary::MeshSummary;
use crate::Format;

/// The shared corpus (not copied here): every inp entry of the manifest must match.
#[test]
fn corpus_manifest() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/corpus");
    let Ok(text) = std::fs::read_to_string(dir.join("manifest.json")) else {
        eprintln!("corpus not present; skipped");
        return;
    };
    let manifest: serde_json::Value = serde_json::from_str(&text).unwrap();
    let mut failures = Vec::new();
    for entry in manifest["files"].as_array().unwrap() {
        if entry["format"] != "inp" {
            continue;
        }
        let rel = entry["path"].as_str().unwrap();
        let path = dir.join(rel);
        let data = std::fs::read(&path).unwrap();
        let mesh = match read(&path, &data) {
            Ok(m) => m,
            Err(e) => {
                failures.push(format!("{rel}: {e}"));
                continue;
            }
        };
        let got = serde_json::to_value(MeshSummary::of(&mesh, Format::Inp)).unwrap();
        for key in [
            "nodes_total",
            "corner_nodes_in_3d_elements",
            "elements_3d",
            "boundary_faces",
        ] {
            if got[key] != entry[key] {
                failures.push(format!(
                    "{rel}: {key}: got {}, want {}",
                    got[key], entry[key]
                ));
            }
        }
        for side in ["min", "max"] {
            for k in 0..3 {
                let g = got["bbox"][side][k].as_f64().unwrap();
                let w = entry["bbox"][side][k].as_f64().unwrap();
                if (g - w).abs() > 1e-9 * w.abs().max(1.0) {
                    failures.push(format!("{rel}: bbox {side}[{k}] got {g}, want {w}"));
                }
            }
        }
        let strip = |v: &serde_json::Value| -> Vec<String> {
            v.as_array()
                .unwrap()
                .iter()
                .map(|s| {
                    format!(
                        "{} {} {} {}",
                        s["name"], s["kind"], s["nodes"], s["elements"]
                    )
                })
                .collect()
        };
        if strip(&got["sets"]) != strip(&entry["sets"]) {
            failures.push(format!(
                "{rel}: sets\n got  {:?}\n want {:?}",
                strip(&got["sets"]),
                strip(&entry["sets"])
            ));
        }
        eprintln!("{rel}: warnings {:?}", mesh.warnings);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A temporary directory removed on drop.
struct TempDir(PathBuf);

impl TempDir {
    fn new(tag: &str) -> TempDir {
        let p = std::env::temp_dir().join(format!("pdcontact-inp-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&p);
        std::fs::create_dir_all(p.join("sub")).unwrap();
        TempDir(p)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

#[test]
fn includes_nested_relative_and_data_only() {
    let dir = TempDir::new("inc");
    let main = dir.0.join("main.inp");
    std::fs::write(
        &main,
        "*HEADING\n*NODE, NSET=ALL\n*INCLUDE, INPUT=sub/nodes.inc\n8, 0, 1, 1\n*Element, type=C3D8, input=sub/elems.dat\n*NSET, NSET=TOP\n5, 6, 7, 8\n",
    )
    .unwrap();
    // Data-only include: continues the *NODE block; then a nested include relative to sub/.
    std::fs::write(
        dir.0.join("sub/nodes.inc"),
        "1,0,0,0\n2,1,0,0\n3,1,1,0\n4,0,1,0\n*INCLUDE, INPUT=more.inc\n",
    )
    .unwrap();
    std::fs::write(
        dir.0.join("sub/more.inc"),
        "*NODE, NSET=ALL\r\n5,0,0,1\r\n6,1,0,1\r\n7,1,1,1",
    )
    .unwrap();
    std::fs::write(dir.0.join("sub/elems.dat"), "1, 1,2,3,4,\n5,6,7,8\n").unwrap();
    let data = std::fs::read(&main).unwrap();
    let m = match read(&main, &data) {
        Ok(m) => m,
        Err(e) => panic!("{e}"),
    };
    assert_eq!(m.node_count(), 8);
    assert_eq!(m.element_count(), 1);
    assert_eq!(count(set(&m, "ALL")), 8);
    assert_eq!(count(set(&m, "TOP")), 4);

    // An error inside an included file names that file and its line.
    std::fs::write(dir.0.join("sub/more.inc"), "*NODE\n5,0,0,1\n6,1,0,oops\n").unwrap();
    let e = read(&main, &data).err().unwrap();
    assert!(e.path.ends_with("sub/more.inc"), "{e}");
    assert_eq!(line_of(&e), 3);

    // A missing file: the including file and line.
    std::fs::write(dir.0.join("sub/more.inc"), "*INCLUDE, INPUT=missing.inc\n").unwrap();
    let e = read(&main, &data).err().unwrap();
    assert!(e.path.ends_with("sub/more.inc"), "{e}");
    assert_eq!(line_of(&e), 1);
    assert!(e.found.contains("missing.inc"), "{e}");
    std::fs::write(&main, "*NODE\n1, 0, 0, 0\n\n*INCLUDE, INPUT=nowhere.inp\n").unwrap();
    let e = read(&main, &std::fs::read(&main).unwrap()).err().unwrap();
    assert!(e.path.ends_with("main.inp"), "{e}");
    assert_eq!(line_of(&e), 4);

    // A directory is not an include file.
    std::fs::write(&main, "*NODE\n9, 0, 0, 0\n*INCLUDE, INPUT=sub\n").unwrap();
    let e = read(&main, &std::fs::read(&main).unwrap()).err().unwrap();
    assert_eq!(line_of(&e), 3);

    // A Windows-style relative path.
    std::fs::write(dir.0.join("sub/more.inc"), "*NODE\n5,0,0,1\n").unwrap();
    std::fs::write(&main, "*NODE\n9, 0, 0, 0\n*INCLUDE, INPUT=sub\\more.inc\n").unwrap();
    let m = read(&main, &std::fs::read(&main).unwrap()).unwrap();
    assert_eq!(m.node_count(), 2);

    // A cycle.
    std::fs::write(&main, &data).unwrap();
    std::fs::write(dir.0.join("sub/more.inc"), "*INCLUDE, INPUT=nodes.inc\n").unwrap();
    let e = read(&main, &data).err().unwrap();
    assert!(e.path.ends_with("sub/more.inc"), "{e}");
    assert_eq!(line_of(&e), 1);
    assert!(e.expected.contains("cycle"), "{e}");
}
