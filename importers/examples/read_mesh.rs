//! Reads one mesh file and prints a JSON line with node and element counts, the time taken
//! (reading the file from disk included), the speed in MB/s (1 MB = 10^6 bytes) and the peak
//! resident memory of the process (`VmHWM` from `/proc/self/status`, Linux only).
//!
//! ```text
//! cargo run --release -p pdcontact-importers --example read_mesh -- FILE [--format msh] [--summary]
//! ```
//!
//! `--summary` adds the `inspect` summary (counts by kind, bounding box, boundary faces, sets).

use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use pdcontact_importers::{detect_format, read_path, Format, MeshSummary};

fn peak_rss_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut file = None;
    let mut format = None;
    let mut summary = false;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--summary" => summary = true,
            "--format" => match it.next().and_then(|f| Format::from_name(f)) {
                Some(f) => format = Some(f),
                None => {
                    eprintln!("--format needs one of cdb, msh, inp");
                    return ExitCode::from(2);
                }
            },
            _ if file.is_none() => file = Some(a.clone()),
            _ => {
                eprintln!("usage: read_mesh FILE [--format F] [--summary]");
                return ExitCode::from(2);
            }
        }
    }
    let Some(file) = file else {
        eprintln!("usage: read_mesh FILE [--format F] [--summary]");
        return ExitCode::from(2);
    };
    let path = Path::new(&file);
    let bytes = std::fs::metadata(path).map(|m| m.len()).unwrap_or(0);
    let start = Instant::now();
    let mesh = match read_path(path, format) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::FAILURE;
        }
    };
    let seconds = start.elapsed().as_secs_f64();
    let mut out = serde_json::json!({
        "file": file,
        "bytes": bytes,
        "nodes": mesh.node_count(),
        "elements": mesh.element_count(),
        "solids": mesh.solids().count(),
        "seconds": seconds,
        "mb_per_s": bytes as f64 / 1e6 / seconds.max(1e-12),
        "peak_rss_mb": peak_rss_bytes().map(|b| b as f64 / 1e6),
    });
    if summary {
        let fmt = format.unwrap_or_else(|| {
            std::fs::read(path)
                .ok()
                .and_then(|d| detect_format(path, &d).ok())
                .unwrap_or(Format::Msh)
        });
        out["summary"] = serde_json::to_value(MeshSummary::of(&mesh, fmt)).unwrap_or_default();
    }
    println!("{out}");
    ExitCode::SUCCESS
}
