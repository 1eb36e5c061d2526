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
