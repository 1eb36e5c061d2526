//! Every file of the shared import corpus (`../shared/corpus`, present in CI) against the
//! expected values in its `manifest.json`, which two independent tools agreed on.
//!
//! `ok` files must reproduce the manifest exactly (bbox to 1e-9 relative); `error` files must
//! fail with a located error; `ok_or_error` files may do either, but if read must match.

mod common;

use std::path::{Path, PathBuf};

use pdcontact::importers::{read_path, Location, MeshSummary};
use serde_json::Value;

fn corpus_dir() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/corpus");
    dir.join("manifest.json").exists().then_some(dir)
}

/// The corpus's `manifest.json`.
fn manifest(dir: &Path) -> Value {
    serde_json::from_str(
        &std::fs::read_to_string(dir.join("manifest.json")).expect("manifest readable"),
    )
    .expect("manifest is JSON")
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
        common::skipped("corpus test", "../shared/corpus not present");
        return;
    };
    let manifest = manifest(&dir);
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

/// The tet10 and hex20 of the corpus (ANSYS SOLID187/186, Gmsh, Abaqus C3D10/C3D20) cut into
/// eight first-order elements on all their nodes (`second_order = "all-nodes"`): every child
/// has a positive volume, the children of an element tile it (each child face is shared with
/// one sibling or lies on one of the parent's faces, which four child faces cover), and the
/// particles of the case are the nodes of the solids, mid-edge nodes of the split elements
/// included, plus the face and centre nodes added to each hex20 (ANSYS may leave a mid-edge
/// node out; such an element keeps its corners).
#[test]
fn corpus_second_order_split_on_all_their_nodes() {
    use pdcontact::case::discretize::element_volume;
    use pdcontact::case::{CaseOptions, PdCase, SecondOrder};
    use pdcontact::importers::{split_second_order, ElementKind, MISSING_NODE};
    use std::collections::{BTreeSet, HashMap};
    let Some(dir) = corpus_dir() else {
        common::skipped("corpus test", "../shared/corpus not present");
        return;
    };
    let manifest = manifest(&dir);
    // Faces of the first-order children, and of the parents by their corner slots and
    // mid-edge slots (the conventions of `pdcontact::importers::mesh`).
    const TET_FACES: [&[usize]; 4] = [&[0, 1, 2], &[0, 1, 3], &[1, 2, 3], &[0, 2, 3]];
    const HEX_FACES: [&[usize]; 6] = [
        &[0, 1, 2, 3],
        &[4, 5, 6, 7],
        &[0, 1, 5, 4],
        &[1, 2, 6, 5],
        &[2, 3, 7, 6],
        &[3, 0, 4, 7],
    ];
    const TET10_FACES: [[usize; 6]; 4] = [
        [0, 1, 2, 4, 5, 6],
        [0, 1, 3, 4, 7, 8],
        [1, 2, 3, 5, 8, 9],
        [0, 2, 3, 6, 7, 9],
    ];
    const HEX20_FACES: [[usize; 8]; 6] = [
        [0, 1, 2, 3, 8, 9, 10, 11],
        [4, 5, 6, 7, 12, 13, 14, 15],
        [0, 1, 5, 4, 8, 17, 12, 16],
        [1, 2, 6, 5, 9, 18, 13, 17],
        [2, 3, 7, 6, 10, 19, 14, 18],
        [3, 0, 4, 7, 11, 16, 15, 19],
    ];
    let mut kinds = BTreeSet::new();
    let mut checked = 0;
    for entry in manifest["files"].as_array().expect("files list") {
        let count = |k: &str| entry["elements_3d"][k].as_u64().unwrap_or(0);
        if entry["expect"] != "ok" || count("tet10") + count("hex20") == 0 {
            continue;
        }
        let rel = entry["path"].as_str().expect("path");
        let mesh = read_path(&dir.join(rel), None).expect("an ok file reads");
        let split = split_second_order(&mesh).expect("elements to split");
        let original = mesh.node_count() as u32;
        let mut next = 0;
        let mut added_by_hex = 0;
        for parent in mesh.elements() {
            let cut = matches!(parent.kind, ElementKind::Tet10 | ElementKind::Hex20)
                && !parent.nodes.contains(&MISSING_NODE);
            if !cut {
                assert_eq!(split.element(next).kind, parent.kind, "{rel}");
                next += 1;
                continue;
            }
            kinds.insert(parent.kind.name());
            let (child_kind, child_faces, parent_faces): (_, &[&[usize]], Vec<Vec<usize>>) =
                match parent.kind {
                    ElementKind::Tet10 => (
                        ElementKind::Tet4,
                        &TET_FACES,
                        TET10_FACES.iter().map(|f| f.to_vec()).collect(),
                    ),
                    _ => (
                        ElementKind::Hex8,
                        &HEX_FACES,
                        HEX20_FACES.iter().map(|f| f.to_vec()).collect(),
                    ),
                };
            let mut faces: HashMap<BTreeSet<u32>, usize> = HashMap::new();
            for e in next..next + 8 {
                let child = split.element(e);
                assert_eq!(child.kind, child_kind, "{rel}");
                let v = element_volume(child.kind, child.nodes, &split.coords);
                assert!(
                    v > 0.0,
                    "{rel}: element {} has a child of volume {v}",
                    parent.id
                );
                for f in child_faces {
                    *faces
                        .entry(f.iter().map(|&k| child.nodes[k]).collect())
                        .or_default() += 1;
                }
            }
            next += 8;
            let mut on_face = vec![0; parent_faces.len()];
            let mut added: BTreeSet<u32> = BTreeSet::new();
            for (f, count) in &faces {
                added.extend(f.iter().filter(|&&v| v >= original));
                let own: Vec<u32> = f.iter().copied().filter(|&v| v < original).collect();
                let host = parent_faces.iter().position(|pf| {
                    own.len() + 1 >= f.len()
                        && own
                            .iter()
                            .all(|v| pf.iter().any(|&k| parent.nodes[k] == *v))
                });
                match (count, host) {
                    (2, _) => {}
                    (1, Some(h)) => on_face[h] += 1,
                    _ => panic!(
                        "{rel}: element {}: child face {f:?} seen {count} times",
                        parent.id
                    ),
                }
            }
            assert!(
                on_face.iter().all(|&n| n == 4),
                "{rel}: element {}: {on_face:?}",
                parent.id
            );
            if parent.kind == ElementKind::Hex20 {
                // Six face nodes (some shared with a neighbour) and a centre.
                assert_eq!(added.len(), 7, "{rel}: element {}", parent.id);
                added_by_hex += 1;
            }
        }
        assert_eq!(next, split.element_count(), "{rel}");
        // The particles: the solids' nodes, mid-edge nodes of the split elements included,
        // and every added node.
        let mut expected: BTreeSet<u32> = (original..split.node_count() as u32).collect();
        let mut kept = 0;
        for e in mesh.solids() {
            let cut = matches!(e.kind, ElementKind::Tet10 | ElementKind::Hex20)
                && !e.nodes.contains(&MISSING_NODE);
            kept += usize::from(!cut && e.kind != e.kind.linear());
            expected.extend(if cut { e.nodes } else { e.corners() }.iter().copied());
        }
        assert!(
            added_by_hex == 0 || split.node_count() as u32 > original,
            "{rel}"
        );
        let options = CaseOptions {
            second_order: SecondOrder::AllNodes,
            ..Default::default()
        };
        let case = PdCase::build(mesh, options).expect("the case builds");
        let got: BTreeSet<u32> = case.particles.node.iter().copied().collect();
        assert_eq!(got, expected, "{rel}");
        // Second-order elements left whole are named in the warnings `run` prints.
        let said = format!("{kept} second-order elements keep their corners only");
        let warned = case.mesh.warnings.iter().any(|w| w.contains(&said));
        assert_eq!(
            warned,
            kept > 0,
            "{rel}: {kept} kept, {:?}",
            case.mesh.warnings
        );
        checked += 1;
    }
    assert!(checked >= 6, "{checked} corpus files with tet10 or hex20");
    assert_eq!(kinds.len(), 2, "{kinds:?}");
}

/// Every ok corpus file cut once at its edges' midpoints (`refine = 1`): each tet and hex into
/// eight, the volume of the solids unchanged, no child inverted where its parent is not, and
/// the boundary as it was: the area of the boundary faces unchanged (a face left unmatched
/// between neighbours would be a surface inside the body and add its area twice). The nodes
/// are the file's, one per edge, and for hexes one per face and one per element. A file
/// with wedges or pyramids is left as it is, and the case says so.
#[test]
fn corpus_refined_once() {
    use pdcontact::case::discretize::element_volume;
    use pdcontact::case::{CaseOptions, PdCase};
    use pdcontact::importers::{boundary_faces, refine_uniform, ElementKind, Mesh, RefineRefusal};
    use std::collections::BTreeSet;
    let Some(dir) = corpus_dir() else {
        common::skipped("corpus test", "../shared/corpus not present");
        return;
    };
    let manifest = manifest(&dir);
    let volume = |m: &Mesh| -> (f64, usize) {
        let mut total = 0.0;
        let mut inverted = 0;
        for e in m.solids() {
            let v = element_volume(e.kind.linear(), e.corners(), &m.coords);
            total += v;
            inverted += usize::from(v <= 0.0);
        }
        (total, inverted)
    };
    // The area of the boundary: a triangle's, a quadrilateral's as the bilinear patch of its
    // corners (Gauss-Legendre, 4 × 4 points), which its four children tile exactly.
    let area = |m: &Mesh| -> f64 {
        let p = |v: u32| nalgebra::Vector3::from(m.coords[v as usize]);
        let g = [
            (-0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
            (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
            (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
            (0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
        ];
        boundary_faces(m)
            .boundary
            .iter()
            .map(|f| {
                let [a, b, c, d] = f.nodes.map(p);
                if f.is_triangle() {
                    return 0.5 * (b - a).cross(&(c - a)).norm();
                }
                let mut sum = 0.0;
                for (u, wu) in g {
                    for (v, wv) in g {
                        // x(u, v) = ¼[(1−u)(1−v)a + (1+u)(1−v)b + (1+u)(1+v)c + (1−u)(1+v)d]
                        let du = ((1.0 - v) * (b - a) + (1.0 + v) * (c - d)) * 0.25;
                        let dv = ((1.0 - u) * (d - a) + (1.0 + u) * (c - b)) * 0.25;
                        sum += wu * wv * du.cross(&dv).norm();
                    }
                }
                sum
            })
            .sum()
    };
    let (mut cut_files, mut refused_files) = (0, 0);
    for entry in manifest["files"].as_array().expect("files list") {
        if entry["expect"] != "ok" {
            continue;
        }
        let rel = entry["path"].as_str().expect("path");
        let mesh = read_path(&dir.join(rel), None).expect("an ok file reads");
        let whole = mesh
            .solids()
            .filter(|e| !matches!(e.kind.linear(), ElementKind::Tet4 | ElementKind::Hex8))
            .count();
        let solids = mesh.solids().count();
        match refine_uniform(&mesh) {
            Err(why) => {
                let expected = if whole > 0 {
                    RefineRefusal::WedgesOrPyramids(whole)
                } else {
                    RefineRefusal::NoSolids
                };
                assert_eq!(why, expected, "{rel}");
                let options = CaseOptions {
                    refine: 1,
                    ..Default::default()
                };
                if let Ok(case) = PdCase::build(mesh, options) {
                    assert!(
                        case.mesh
                            .warnings
                            .iter()
                            .any(|w| w.starts_with("refine has no effect")),
                        "{rel}: {:?}",
                        case.mesh.warnings
                    );
                }
                refused_files += 1;
            }
            Ok(fine) => {
                assert_eq!(whole, 0, "{rel}");
                assert_eq!(fine.solids().count(), 8 * solids, "{rel}");
                let (v0, bad0) = volume(&mesh);
                let (v1, bad1) = volume(&fine);
                assert!(((v1 - v0) / v0).abs() < 1e-9, "{rel}: volume {v0} -> {v1}");
                if bad0 == 0 {
                    assert_eq!(bad1, 0, "{rel}: inverted children");
                }
                let (a0, a1) = (area(&mesh), area(&fine));
                assert!(((a1 - a0) / a0).abs() < 1e-6, "{rel}: area {a0} -> {a1}");
                // One node per edge of the solids (and of the faces, lines kept for sets), one
                // per hex face and one per hex.
                let mut edges = BTreeSet::new();
                let mut faces = BTreeSet::new();
                let mut hexes = 0;
                for e in mesh.elements() {
                    let c = e.corners();
                    let pairs: &[(usize, usize)] = match e.kind.linear() {
                        ElementKind::Tet4 => &pdcontact::importers::mesh::TET10_EDGES,
                        ElementKind::Hex8 => &pdcontact::importers::mesh::HEX20_EDGES,
                        ElementKind::Line => &[(0, 1)],
                        ElementKind::Triangle => &[(0, 1), (1, 2), (2, 0)],
                        ElementKind::Quadrilateral => &[(0, 1), (1, 2), (2, 3), (3, 0)],
                        _ => &[],
                    };
                    for &(a, b) in pairs {
                        edges.insert((c[a].min(c[b]), c[a].max(c[b])));
                    }
                    if e.kind.linear() == ElementKind::Hex8 {
                        hexes += 1;
                        for f in pdcontact::importers::face_corners(ElementKind::Hex8) {
                            let key: BTreeSet<u32> = f.iter().map(|&k| c[k]).collect();
                            faces.insert(key);
                        }
                    }
                }
                assert_eq!(
                    fine.node_count(),
                    mesh.node_count() + edges.len() + faces.len() + hexes,
                    "{rel}"
                );
                cut_files += 1;
            }
        }
    }
    assert!(cut_files >= 10, "{cut_files} files cut");
    assert!(refused_files >= 1, "{refused_files} files refused");
}
