//! `pdcontact fracture`: bond failure against its references (METHOD.md §9,
//! docs/FRACTURE.md): a notched three-point bend beam broken under displacement control
//! against linear elastic fracture mechanics ([`beam`]), and the Kalthoff-Winkler plate hit
//! between its notches by a projectile, whose cracks leave the notch tips at about 70°
//! ([`kalthoff`]).

pub mod beam;
pub mod kalthoff;

pub use beam::{lefm_peak_load, run_beam, shape_factor, BeamResult, NotchedBeam};
pub use kalthoff::{run_kalthoff, KalthoffPlate, KalthoffResult};

use std::path::Path;
use std::time::Instant;

use crate::error::{Error, Result};
use crate::model::Model;
use crate::output::vtk::write_atomically;
use crate::run::{run_scene, RunOptions, RunSummary};
use crate::scene::Scene;

/// Writes `text` as `folder/scene.toml` (so that `pdcontact run` can run it again), runs it
/// into `folder`, and returns the model, its summary and the run's wall time (s).
fn run_in(text: &str, folder: &Path, quiet: bool) -> Result<(Model, RunSummary, f64)> {
    std::fs::create_dir_all(folder).map_err(|e| Error::output(folder, e))?;
    let path = folder.join("scene.toml");
    write_atomically(&path, |w| std::io::Write::write_all(w, text.as_bytes()))?;
    let scene = Scene::load(&path)?;
    let start = Instant::now();
    let (model, summary) = run_scene(
        &scene,
        &RunOptions {
            output: Some(folder.to_path_buf()),
            quiet,
            stop: None,
            comm: None,
        },
    )?;
    Ok((model, summary, start.elapsed().as_secs_f64()))
}
