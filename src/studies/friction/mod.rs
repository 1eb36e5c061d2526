//! `pdcontact friction`: Coulomb friction against its references (METHOD.md §10,
//! docs/VALIDATION.md "Friction"): a block on a tilted plane that stays or slides
//! ([`sliding`]), and a sphere pressed and then pushed sideways, whose contact sticks in a
//! disc and slips around it as Cattaneo and Mindlin found ([`mindlin`]).

pub mod mindlin;
pub mod sliding;

pub use mindlin::{run_mindlin, MindlinResult, MindlinScene};
pub use sliding::{run_sliding, SlidingBlock, SlidingResult};

use std::path::Path;
use std::time::Instant;

use crate::error::{Error, Result};
use crate::model::Model;
use crate::output::vtk::write_atomically;
use crate::run::{run_scene_with, RunOptions, RunSummary};
use crate::scene::Scene;
use crate::solver::Monitor;

/// Writes `text` as `folder/scene.toml` (so that `pdcontact run` can run it again), runs it
/// into `folder` with `observer` following it, and returns the model, its summary and the
/// run's wall time (s).
fn run_in(
    text: &str,
    folder: &Path,
    quiet: bool,
    observer: &mut dyn Monitor,
) -> Result<(Model, RunSummary, f64)> {
    std::fs::create_dir_all(folder).map_err(|e| Error::output(folder, e))?;
    let path = folder.join("scene.toml");
    write_atomically(&path, |w| std::io::Write::write_all(w, text.as_bytes()))?;
    let scene = Scene::load(&path)?;
    let start = Instant::now();
    let (model, summary) = run_scene_with(
        &scene,
        &RunOptions {
            output: Some(folder.to_path_buf()),
            quiet,
            stop: None,
            comm: None,
        },
        observer,
    )?;
    Ok((model, summary, start.elapsed().as_secs_f64()))
}
