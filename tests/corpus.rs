//! Every file of the shared import corpus (`../shared/corpus`, present in CI) against the
//! expected values in its `manifest.json`, which two independent tools agreed on.
//!
//! `ok` files must reproduce the manifest exactly (bbox to 1e-9 relative); `error` files must
//! fail with a located error; `ok_or_error` files may do either, but if read must match.

use std::path::{Path, PathBuf};

use pdcontact::importers::{read_path, Location, MeshSummary};
use serde_json::Value;

fn corpus_dir() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/corpus");
    dir.join("manifest.json").exists().then_some(dir)
}

fn close(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= 1e-9 * b.abs().max(scale).max(1e-300)
}

/// Compares a summary with a manifest entry; returns one line per difference.
fn differences(got: &MeshSummary, want: &Value) -> Vec<String> {
    let mut out = Vec::new();
    let got = serde_json::to_value(got).expect("summary serialises");
    for key in [
        "format",
        "nodes_total",
        "corner_nodes_in_3d_elements",
        "elements_3d",
        "boundary_faces",
    ] {
        if got[key] != want[key] {
            out.push(format!("{key}: got {}, want {}", got[key], want[key]));
        }
    }
    match (&got["bbox"], &want["bbox"]) {
        (Value::Null, Value::Null) => {}
        (g, w) if g.is_object() && w.is_object() => {
            let num = |v: &Value, side: &str, k: usize| v[side][k].as_f64().unwrap_or(f64::NAN);
            let scale = (0..3)
                .map(|k| (num(w, "max", k) - num(w, "min", k)).abs())
                .fold(0.0, f64::max);
            for side in ["min", "max"] {
                for k in 0..3 {
                    if !close(num(g, side, k), num(w, side, k), scale) {
                        out.push(format!(
                            "bbox.{side}[{k}]: got {}, want {}",
                            g[side][k], w[side][k]
                        ));
                    }
                }
            }
        }
        (g, w) => out.push(format!("bbox: got {g}, want {w}")),
    }
    let strip = |v: &Value| -> Vec<Value> {
        v.as_array()
            .into_iter()
            .flatten()
            .map(|s| {
                serde_json::json!({"name": s["name"], "kind": s["kind"], "nodes": s["nodes"], "elements": s["elements"]})
            })
            .collect()
    };
    if strip(&got["sets"]) != strip(&want["sets"]) {
        out.push(format!(
            "sets:\n    got  {}\n    want {}",
            Value::Array(strip(&got["sets"])),
            Value::Array(strip(&want["sets"]))
        ));
    }
    out
}

fn run_corpus(format: &str) {
    let Some(dir) = corpus_dir() else {
        eprintln!("../shared/corpus not present: corpus test skipped");
        return;
    };
    let manifest: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("manifest.json")).expect("manifest readable"),
    )
    .expect("manifest is JSON");
    let mut failures = Vec::new();
    let mut checked = 0;
    for entry in manifest["files"].as_array().expect("files list") {
        if entry["format"] != format {
            continue;
        }
        checked += 1;
        let rel = entry["path"].as_str().expect("path");
        let path = dir.join(rel);
        let expect = entry["expect"].as_str().expect("expect");
        let result = std::panic::catch_unwind(|| read_path(&path, None));
        let result = match result {
            Ok(r) => r,
            Err(_) => {
                failures.push(format!("{rel}: PANIC"));
                continue;
            }
        };
        match (result, expect) {
            (Ok(mesh), "ok" | "ok_or_error") => {
                let fmt = pdcontact::importers::detect_format(
                    &path,
                    &std::fs::read(&path).expect("read"),
                )
                .expect("format");
                let summary = MeshSummary::of(&mesh, fmt);
                let d = differences(&summary, entry);
                if !d.is_empty() {
                    failures.push(format!("{rel}:\n  {}", d.join("\n  ")));
                }
            }
            (Ok(_), _) => failures.push(format!("{rel}: read without error, expected an error")),
            (Err(e), "error" | "ok_or_error") => {
                let msg = e.to_string();
                if e.location == Location::File && expect == "error" {
                    failures.push(format!("{rel}: error has no line or byte: {msg}"));
                }
                if !msg.contains("expected") || !msg.contains("found") {
                    failures.push(format!("{rel}: unclear error: {msg}"));
                }
            }
            (Err(e), _) => failures.push(format!("{rel}: {e}")),
        }
    }
    assert!(checked > 0, "no {format} files in the manifest");
    assert!(
        failures.is_empty(),
        "{} of {checked} {format} files differ:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

#[test]
fn corpus_cdb() {
    run_corpus("cdb");
}

#[test]
fn corpus_msh() {
    run_corpus("msh");
}

#[test]
fn corpus_inp() {
    run_corpus("inp");
}

/// The tet10 of the corpus (ANSYS SOLID187, Gmsh, Abaqus C3D10), cut into eight tet4 at their
/// mid-edge nodes (`second_order = "all-nodes"`): every child is positively oriented, the
/// children of a tet10 tile it (each child face is shared with a sibling or lies on one of the
/// parent's faces, and each parent face is covered by four child faces), and the particles of
/// the case are exactly the nodes of the solids, mid-edge nodes included, where a tet10 gives
/// all ten (ANSYS may leave one out; such a tet10 keeps its corners).
#[test]
fn corpus_tet10_split_on_all_their_nodes() {
    use pdcontact::case::{CaseOptions, PdCase, SecondOrder};
    use pdcontact::importers::{split_tet10, ElementKind, MISSING_NODE};
    use std::collections::{BTreeSet, HashMap};
    let Some(dir) = corpus_dir() else {
        eprintln!("../shared/corpus not present: corpus test skipped");
        return;
    };
    let manifest: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("manifest.json")).expect("manifest readable"),
    )
    .expect("manifest is JSON");
    let mut checked = 0;
    for entry in manifest["files"].as_array().expect("files list") {
        if entry["expect"] != "ok" || entry["elements_3d"]["tet10"].as_u64().unwrap_or(0) == 0 {
            continue;
        }
        let rel = entry["path"].as_str().expect("path");
        let mesh = read_path(&dir.join(rel), None).expect("an ok file reads");
        let split = split_tet10(&mesh).expect("tet10 to split");
        let c = &split.coords;
        let volume6 = |t: &[u32]| {
            let p = |k: usize| c[t[k] as usize];
            let d = |k: usize| [0, 1, 2].map(|i| p(k)[i] - p(0)[i]);
            let (a, b, e) = (d(1), d(2), d(3));
            a[0] * (b[1] * e[2] - b[2] * e[1]) - a[1] * (b[0] * e[2] - b[2] * e[0])
                + a[2] * (b[0] * e[1] - b[1] * e[0])
        };
        // Children in order, parent by parent: the split keeps element order.
        let mut next = 0;
        let mut complete = 0;
        for parent in mesh.elements() {
            let whole = parent.kind == ElementKind::Tet10 && !parent.nodes.contains(&MISSING_NODE);
            if !whole {
                assert_eq!(split.element(next).kind, parent.kind, "{rel}");
                next += 1;
                continue;
            }
            complete += 1;
            let children: Vec<&[u32]> = (next..next + 8).map(|e| split.element(e).nodes).collect();
            next += 8;
            let mut faces: HashMap<BTreeSet<u32>, usize> = HashMap::new();
            for t in &children {
                assert_eq!(t.len(), 4);
                assert!(
                    volume6(t) > 0.0,
                    "{rel}: element {} has an inverted child",
                    parent.id
                );
                for skip in 0..4 {
                    let f: BTreeSet<u32> = (0..4).filter(|&k| k != skip).map(|k| t[k]).collect();
                    *faces.entry(f).or_default() += 1;
                }
            }
            // The parent's faces, each with its three mid-edge nodes (tet10 convention).
            let n = parent.nodes;
            let parent_faces: [[usize; 6]; 4] = [
                [0, 1, 2, 4, 5, 6],
                [0, 1, 3, 4, 7, 8],
                [1, 2, 3, 5, 8, 9],
                [0, 2, 3, 6, 7, 9],
            ];
            let mut on_face = [0; 4];
            for (f, count) in &faces {
                let host = parent_faces
                    .iter()
                    .position(|pf| f.iter().all(|v| pf.iter().any(|&k| n[k] == *v)));
                match (count, host) {
                    (2, None) => {}
                    (1, Some(h)) => on_face[h] += 1,
                    _ => panic!(
                        "{rel}: element {}: child face {f:?} seen {count} times",
                        parent.id
                    ),
                }
            }
            assert_eq!(on_face, [4; 4], "{rel}: element {}", parent.id);
        }
        assert_eq!(next, split.element_count(), "{rel}");
        // The particles: every node of a solid, mid-edge nodes of whole tet10 included.
        let mut expected: BTreeSet<u32> = BTreeSet::new();
        for e in mesh.solids() {
            let whole = e.kind == ElementKind::Tet10 && !e.nodes.contains(&MISSING_NODE);
            let used = if whole { e.nodes } else { e.corners() };
            expected.extend(used.iter().copied());
        }
        let options = CaseOptions {
            second_order: SecondOrder::AllNodes,
            ..Default::default()
        };
        let case = PdCase::build(mesh, options).expect("the case builds");
        let got: BTreeSet<u32> = case.particles.node.iter().copied().collect();
        assert_eq!(got, expected, "{rel}: {complete} tet10 split");
        checked += 1;
    }
    assert!(checked >= 4, "{checked} corpus files with tet10");
}
