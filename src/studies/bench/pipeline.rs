//! `pdcontact bench --pipeline MESH`: every stage from the mesh file to the case folder, timed.

use std::time::Instant;

use crate::error::{Error, Result};
use crate::parallel::memory::peak_rss_mb;

/// One stage of [`run_pipeline`].
#[derive(Clone, Debug, serde::Serialize)]
pub struct StageReport {
    pub stage: String,
    pub seconds: f64,
    /// Items per second in `unit` (MB of input or output, particles, bonds).
    pub throughput: f64,
    pub unit: String,
    /// Peak resident memory of the process during the stage (the high-water mark is reset
    /// before it where the kernel allows), MB.
    pub peak_rss_mb: Option<f64>,
}

/// `pdcontact bench --pipeline MESH`: every stage from the file to the case folder, timed on
/// one mesh.
#[derive(Clone, Debug, serde::Serialize)]
pub struct PipelineReport {
    pub mesh: String,
    pub file_mb: f64,
    pub particles: usize,
    pub bonds: usize,
    pub threads: usize,
    pub stages: Vec<StageReport>,
}

impl PipelineReport {
    pub fn to_text(&self) -> String {
        let mut out = format!(
            "{}: {:.1} MB, {} particles, {} bonds, {} threads\n{:<22} {:>9} {:>14} {:<12} {:>10}\n",
            self.mesh,
            self.file_mb,
            self.particles,
            self.bonds,
            self.threads,
            "stage",
            "seconds",
            "throughput",
            "",
            "peak MB"
        );
        for s in &self.stages {
            out.push_str(&format!(
                "{:<22} {:>9.4} {:>14.4e} {:<12} {:>10}\n",
                s.stage,
                s.seconds,
                s.throughput,
                s.unit,
                s.peak_rss_mb.map_or("-".into(), |m| format!("{m:.0}"))
            ));
        }
        out
    }
}

/// Resets the peak-RSS mark of this process (Linux `clear_refs` 5); false where not allowed.
fn reset_peak_rss() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// Runs `f`, returning its value, seconds and the peak RSS during it.
fn stage<T>(f: impl FnOnce() -> T) -> (T, f64, Option<f64>) {
    let reset = reset_peak_rss();
    let start = Instant::now();
    let value = f();
    let seconds = start.elapsed().as_secs_f64();
    (value, seconds, if reset { peak_rss_mb() } else { None })
}

/// Times each stage of the pipeline on `mesh`: import, discretisation, neighbour list,
/// eigenvalue surface detection, surface correction, master segments (those four as
/// [`PdCase::build`](crate::case::PdCase::build) times them, and the neighbour list and
/// surface detection once more alone, for their memory), and writing the case folder.
pub fn run_pipeline(
    mesh_path: &std::path::Path,
    options: crate::case::CaseOptions,
    threads: Option<usize>,
) -> Result<PipelineReport> {
    let run = || -> Result<PipelineReport> {
        let file_bytes = std::fs::metadata(mesh_path)
            .map_err(|e| Error::input(format!("{}: {e}", mesh_path.display())))?
            .len() as f64;
        let mb = file_bytes / 1e6;
        let mut stages = Vec::new();
        let mut push = |name: &str, seconds: f64, items: f64, unit: &str, peak: Option<f64>| {
            stages.push(StageReport {
                stage: name.to_string(),
                seconds,
                throughput: items / seconds.max(1e-12),
                unit: unit.to_string(),
                peak_rss_mb: peak,
            })
        };

        let (mesh, seconds, peak) = stage(|| pdcontact_importers::read_path(mesh_path, None));
        let mesh = mesh?;
        push("import", seconds, mb, "MB/s", peak);

        let (case, seconds, peak) = stage(|| crate::case::PdCase::build(mesh, options));
        let case = case?;
        let n = case.particles.len() as f64;
        let t = case.times;
        push("discretize", t.discretize, n, "particles/s", None);
        push(
            "neighbours",
            t.neighbours,
            case.bonds.len() as f64,
            "bonds/s",
            None,
        );
        push("surface", t.surface, n, "particles/s", None);
        push(
            "correction",
            t.correction,
            case.bonds.len() as f64,
            "bonds/s",
            None,
        );
        push(
            "segments",
            t.segments,
            case.segments.segments.len() as f64,
            "segments/s",
            None,
        );
        push("case build, total", seconds, n, "particles/s", peak);

        let reach = (case.horizon + 0.5 * case.particles.spacing) * (1.0 + 1e-9);
        let (bonds, seconds, peak) =
            stage(|| crate::case::neighbours::build_bonds(&case.particles.position, reach));
        push(
            "neighbours alone",
            seconds,
            bonds.len() as f64,
            "bonds/s",
            peak,
        );
        drop(bonds);
        let volume = case.particles.completed_volume();
        let (_, seconds, peak) = stage(|| {
            crate::case::surface::detect_surface(
                &case.particles.position,
                &volume,
                volume.len(),
                case.particles.spacing,
                &[],
            )
        });
        push("surface alone", seconds, n, "particles/s", peak);

        let folder = std::env::temp_dir().join(format!("pdcontact-bench-{}", std::process::id()));
        std::fs::create_dir_all(&folder).map_err(|e| Error::output(&folder, e))?;
        let (written, seconds, peak) = stage(|| -> Result<f64> {
            crate::convert::write_case_files(&case, mesh_path, &folder)?;
            let mut bytes = 0.0;
            for name in ["particles.vtu", "segments.vtu", "case.toml"] {
                bytes += std::fs::metadata(folder.join(name))
                    .map(|m| m.len() as f64)
                    .unwrap_or(0.0);
            }
            Ok(bytes)
        });
        let _ = std::fs::remove_dir_all(&folder);
        push("write case folder", seconds, written? / 1e6, "MB/s", peak);

        Ok(PipelineReport {
            mesh: mesh_path.display().to_string(),
            file_mb: mb,
            particles: case.particles.len(),
            bonds: case.bonds.len(),
            threads: rayon::current_num_threads(),
            stages,
        })
    };
    match threads {
        Some(t) => rayon::ThreadPoolBuilder::new()
            .num_threads(t.max(1))
            .build()
            .map_err(|e| Error::input(format!("cannot start {t} threads: {e}")))?
            .install(run),
        None => run(),
    }
}
