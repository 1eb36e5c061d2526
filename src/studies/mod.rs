//! The studies: programs built on the library's public API, apart from the pipeline stages.
//!
//! | command | module |
//! |---|---|
//! | `pdcontact demo`: the sphere on a plane against Hertz | [`demo`] |
//! | the validation scenes, shared by the studies | [`scenarios`] |
//! | `pdcontact fracture`: a notched beam broken against LEFM | [`fracture`] |
//! | `pdcontact friction`: a sliding block, Cattaneo-Mindlin | [`friction`] |
//! | a scene run and compared with its theory | [`comparison`] |
//! | `pdcontact validate`: the scenes against theory, the convergence studies | [`validate`] |
//! | `pdcontact sweep`: speed against accuracy | [`sweep`] |
//! | `pdcontact sweep --stability`: where the solvers and contact methods stop working | [`stability`] |
//! | `pdcontact bench`: the kernels and stages timed | [`bench`](mod@bench) |
//! | `pdcontact validate --mesh`: the Hertz sphere or roller on a user's mesh | [`user_mesh`] |

pub mod bench;
pub mod comparison;
pub mod demo;
pub mod fracture;
pub mod friction;
pub mod scenarios;
pub mod stability;
pub mod sweep;
pub mod user_mesh;
pub mod validate;

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
/// run's wall time (s): how the fracture and friction studies run their scenes.
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
            study: false,
        },
        observer,
    )?;
    Ok((model, summary, start.elapsed().as_secs_f64()))
}
