//! Frames of a run for ParaView, and progress on stderr.
//!
//! Every `every` steps (and at the last) two files are written: `particles_NNNNNN.vtu` with the
//! particles of all deformable bodies (point data `displacement`, `velocity`, `force`,
//! `contact_force`, `contact_pressure` in Pa per undeformed tributary area, `surface`,
//! `normal`, `body`, `volume`) and `segments_NNNNNN.vtu` with the deformed master segments of
//! every body and the rigid faces (cell data `body`). One `run.pvd` lists them as a time
//! series with two parts (ADR: pseudo-time = iteration). The `.pvd` is rewritten after each
//! frame, so an interrupted run still leaves a collection ParaView opens.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::body::Body;
use crate::error::{Error, Result};
use crate::math::Vec3;
use crate::model::Model;
use crate::output::analysis::contact_pressure;
use crate::output::vtk::{write_vtu, CellSpec, Field, PvdCollection};
use crate::solver::Monitor;

/// Name of the collection file.
pub const PVD_NAME: &str = "run.pvd";

/// A frame file this writer makes: `particles_` or `segments_`, six or more digits, `.vtu`.
fn is_frame_name(name: &str) -> bool {
    let Some(stem) = name.strip_suffix(".vtu") else {
        return false;
    };
    let digits = stem
        .strip_prefix("particles_")
        .or_else(|| stem.strip_prefix("segments_"));
    digits.is_some_and(|d| d.len() >= 6 && d.bytes().all(|b| b.is_ascii_digit()))
}

/// Writes the frames of a run.
pub struct FrameWriter {
    folder: PathBuf,
    every: usize,
    pvd: PvdCollection,
    frames: usize,
    last_written: Option<usize>,
}

impl FrameWriter {
    /// A writer into `folder` (created if missing). Frames of an earlier run in the folder
    /// (`particles_NNNNNN.vtu`, `segments_NNNNNN.vtu`) are removed, so that the folder never
    /// mixes two runs; other files are left alone.
    pub fn new(folder: &Path, every: usize) -> Result<FrameWriter> {
        std::fs::create_dir_all(folder).map_err(|e| Error::output(folder, e))?;
        let entries = std::fs::read_dir(folder).map_err(|e| Error::output(folder, e))?;
        for entry in entries.flatten() {
            let name = entry.file_name();
            let Some(name) = name.to_str() else { continue };
            if is_frame_name(name) {
                let path = entry.path();
                std::fs::remove_file(&path).map_err(|e| Error::output(&path, e))?;
            }
        }
        Ok(FrameWriter {
            folder: folder.to_path_buf(),
            every: every.max(1),
            pvd: PvdCollection::default(),
            frames: 0,
            last_written: None,
        })
    }

    /// Path of the `.pvd`.
    pub fn pvd_path(&self) -> PathBuf {
        self.folder.join(PVD_NAME)
    }

    /// Path of the last particles frame written.
    pub fn last_frame(&self) -> Option<PathBuf> {
        self.last_written
            .map(|s| self.folder.join(format!("particles_{s:06}.vtu")))
    }

    /// Writes the frame of `step` at time `t`.
    pub fn write(&mut self, model: &Model, step: usize, t: f64) -> Result<()> {
        if self.last_written == Some(step) {
            return Ok(());
        }
        let mut pos = Vec::new();
        let mut disp = Vec::new();
        let mut vel = Vec::new();
        let mut force = Vec::new();
        let mut cforce = Vec::new();
        let mut pressure = Vec::new();
        let mut surface = Vec::new();
        let mut normal = Vec::new();
        let mut body_id = Vec::new();
        let mut volume = Vec::new();
        let mut quads: Vec<[u32; 4]> = Vec::new();
        let mut seg_body = Vec::new();
        let mut seg_points: Vec<Vec3> = Vec::new();
        for (k, b) in model.bodies.iter().enumerate() {
            match b {
                Body::Deformable(pd) => {
                    let base = seg_points.len() as u32;
                    for i in 0..pd.len() {
                        let y = pd.position(i);
                        pos.push(y);
                        seg_points.push(y);
                    }
                    disp.extend_from_slice(&pd.u);
                    vel.extend_from_slice(&pd.v);
                    force.extend_from_slice(&pd.force);
                    cforce.extend_from_slice(&pd.contact_force);
                    pressure.extend(contact_pressure(model, k));
                    surface.extend(pd.case.surface.is_surface.iter().map(|&s| s as i32));
                    normal.extend_from_slice(&pd.case.surface.normal);
                    body_id.extend(std::iter::repeat_n(k as i32, pd.len()));
                    volume.extend_from_slice(&pd.case.particles.volume);
                    for s in pd.segments() {
                        quads.push(s.nodes.map(|n| n + base));
                        seg_body.push(k as i32);
                    }
                }
                Body::Rigid(rb) => {
                    let base = seg_points.len() as u32;
                    seg_points.extend((0..rb.vertices.len()).map(|i| rb.position(i)));
                    for f in &rb.faces {
                        quads.push(f.nodes.map(|n| n + base));
                        seg_body.push(k as i32);
                    }
                }
            }
        }
        let pname = format!("particles_{step:06}.vtu");
        let sname = format!("segments_{step:06}.vtu");
        write_vtu(
            &self.folder.join(&pname),
            &pos,
            CellSpec::Vertices,
            vec![
                Field::vector("displacement", disp),
                Field::vector("velocity", vel),
                Field::vector("force", force),
                Field::vector("contact_force", cforce),
                Field::scalar("contact_pressure", pressure),
                Field::int("surface", surface),
                Field::vector("normal", normal),
                Field::int("body", body_id),
                Field::scalar("volume", volume),
            ],
            vec![],
        )?;
        write_vtu(
            &self.folder.join(&sname),
            &seg_points,
            CellSpec::Quads(quads),
            vec![],
            vec![Field::int("body", seg_body)],
        )?;
        self.pvd.push(t, pname);
        self.pvd.push_part(t, sname, 1);
        self.pvd.write(&self.pvd_path())?;
        self.frames += 1;
        self.last_written = Some(step);
        Ok(())
    }
}

/// Progress bar + frames: the monitor of `run` and `demo`.
pub struct RunMonitor {
    pub frames: Option<FrameWriter>,
    bar: ProgressBar,
    label: &'static str,
    stop: Arc<AtomicBool>,
    /// The last step reported: number, (pseudo-)time and measure (residual or energy drift),
    /// so that a run that fails can still say how far it got.
    pub last_step: (usize, f64, f64),
}

impl RunMonitor {
    /// A monitor; `quiet` hides the progress bar; `stop` is raised by Ctrl-C.
    pub fn new(
        frames: Option<FrameWriter>,
        quiet: bool,
        adr: bool,
        stop: Arc<AtomicBool>,
    ) -> RunMonitor {
        let bar = if quiet {
            ProgressBar::hidden()
        } else {
            let b = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr_with_hz(4));
            b.set_style(
                ProgressStyle::with_template("{spinner} {elapsed_precise} {msg}")
                    .unwrap_or_else(|_| ProgressStyle::default_spinner()),
            );
            b
        };
        RunMonitor {
            frames,
            bar,
            label: if adr { "residual" } else { "energy drift" },
            stop,
            last_step: (0, 0.0, 0.0),
        }
    }
}

impl Monitor for RunMonitor {
    fn step(&mut self, model: &Model, step: usize, time: f64, measure: f64) -> Result<()> {
        self.last_step = (step, time, measure);
        if step.is_multiple_of(50) {
            self.bar.set_message(format!(
                "step {step}  {} {measure:.3e}  contacts {}  Verlet rebuilds {}",
                self.label,
                model.contact_count(),
                model.verlet_rebuilds()
            ));
            self.bar.tick();
        }
        if let Some(f) = &mut self.frames {
            if step.is_multiple_of(f.every) {
                f.write(model, step, time)?;
            }
        }
        Ok(())
    }

    fn finish(&mut self, model: &Model, step: usize, time: f64) -> Result<()> {
        self.bar.finish_and_clear();
        if let Some(f) = &mut self.frames {
            f.write(model, step, time)?;
        }
        Ok(())
    }

    fn interrupted(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }
}

#[cfg(test)]
mod tests {
    use super::is_frame_name;

    #[test]
    fn only_frame_files_are_recognised() {
        assert!(is_frame_name("particles_000120.vtu"));
        assert!(is_frame_name("segments_1234567.vtu"));
        assert!(!is_frame_name("particles_12.vtu"));
        assert!(!is_frame_name("particles_00012a.vtu"));
        assert!(!is_frame_name("my_particles_000120.vtu"));
        assert!(!is_frame_name("particles_000120.vtu.bak"));
        assert!(!is_frame_name("run.pvd"));
    }
}
