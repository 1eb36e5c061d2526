//! `pdcontact demo`: the main job on an embedded default.
//!
//! An elastic sphere (R = 1 m, E = 1 GPa, ν = 0.25) pressed onto a rigid plane so that Hertz's
//! contact radius is a = 0.15 m (a/R = 0.15, where the theory holds: METHOD.md §7), solved
//! quasi-statically by the static solver (Newton-Raphson, METHOD.md §6; ADR under `mpirun`,
//! where the static solver does not run) and compared with Hertz. The model is what the contact needs: a
//! quarter of the shell 2a deep around the pole, with symmetry planes x = 0 and y = 0, meshed
//! with hex8 by gmsh (`meshes/sphere_cap_quarter.msh`, 12 cells across the contact radius,
//! embedded in the binary), the load on its inner face. The mesh and the scene are written into
//! the output folder first, so that the run can be repeated and changed with
//! `pdcontact run DIR/scene.toml`.

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::error::{Error, Result};
use crate::output::analysis::{
    contact_patch, e_star_rigid, elliptic_accuracy, hertz_sphere, Accuracy,
};
use crate::output::vtk::{write_atomically, write_keeping_edits};
use crate::run::{run_scene, RunOptions, RunSummary};
use crate::scene::Scene;

/// The demo's mesh (`meshes/sphere_cap_quarter.geo`), and the name it is written under.
pub const DEMO_MESH: &[u8] = include_bytes!("../../meshes/sphere_cap_quarter.msh");
pub const DEMO_MESH_NAME: &str = "sphere_cap_quarter.msh";

/// Sphere radius, Young's modulus, Poisson's ratio and load of the demo.
pub const RADIUS: f64 = 1.0;
pub const YOUNGS: f64 = 1.0e9;
pub const POISSON: f64 = 0.25;
/// Total load on the whole sphere: Hertz contact radius 0.15 m against a rigid plane
/// (a/R = 0.15, `P = 4 E* a³ / 3R`). The quarter model carries a quarter of it.
pub const LOAD: f64 = 4.8e6;

/// The demo's solver: the static solver where it runs (one process), faster than ADR on this
/// scene (docs/PERFORMANCE.md, "The static solver"); ADR over MPI ranks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DemoSolver {
    Static,
    Adr,
}

impl DemoSolver {
    /// The static solver in one process, ADR over several.
    pub fn for_options(options: &RunOptions) -> DemoSolver {
        match &options.comm {
            Some(c) if c.size() > 1 => DemoSolver::Adr,
            _ => DemoSolver::Static,
        }
    }

    /// The scene's `[solver]` and `[output]` tables.
    fn tables(self) -> &'static str {
        match self {
            DemoSolver::Static => {
                r#"[solver]
kind = "static"            # quasi-static: Newton-Raphson (one process; under mpirun, "adr")
tolerance = 1e-4           # out-of-balance force / applied load
max_iterations = 200

[output]
folder = "."               # frames and summary.json next to this file
every = 5                  # a frame every 5 Newton iterations: watch the contact form in ParaView
"#
            }
            DemoSolver::Adr => {
                r#"[solver]
kind = "adr"               # quasi-static: adaptive dynamic relaxation (the static solver
                           # runs in one process only)
tolerance = 1e-4           # out-of-balance force / applied load
max_iterations = 50000

[output]
folder = "."               # frames and summary.json next to this file
every = 100                # a frame every 100 iterations: watch the contact form in ParaView
"#
            }
        }
    }
}

/// The demo scene (documented: it is the user's first example).
pub fn scene_text(solver: DemoSolver) -> String {
    format!(
        r#"# pdcontact demo: an elastic sphere pressed onto a rigid plane, compared with Hertz.
# Run it again (or change it) with:  pdcontact run scene.toml

{tables}
[[body]]
name = "ball"
mesh = "{mesh}"  # a quarter of the sphere's shell around its
                           # south pole, 0.3 m deep (R = 1 m, hex8 of 0.0125 m, gmsh)
kinematics = "small"       # Hertz theory is small-strain: compare like with like
[body.material]
youngs_modulus = {e:e}
poisson_ratio = {nu}
density = 1000.0

[[body]]
name = "plane"
kind = "rigid"
generator = {{ shape = "plane", point = [0.0, 0.0, -1.0], normal = [0.0, 0.0, 1.0], size = 3.0 }}

[[load]]
body = "ball"
set = "top"                # the shell's inner face, where the rest of the sphere would push
force = [0.0, 0.0, -{quarter:e}]   # a quarter of P = {p:e} N: the model is a quarter

[[contact]]
slave = "ball"
master = "plane"
radius = 100.0             # R of the Hertz penalty K = 4/3 E* sqrt(R): far stiffer than the
                           # default R = Δ/2, so that the penetration stays far below the
                           # approach and adds no compliance that Hertz does not have

[[symmetry]]               # the mirror images across x = 0 and y = 0 complete the sphere's
body = "ball"              # neighbourhoods, so the quarter behaves as the whole
axis = "x"

[[symmetry]]
body = "ball"
axis = "y"
"#,
        tables = solver.tables(),
        mesh = DEMO_MESH_NAME,
        e = YOUNGS,
        nu = POISSON,
        p = LOAD,
        quarter = LOAD / 4.0,
    )
}

/// Computed against theory.
#[derive(Clone, Debug, Serialize)]
pub struct DemoReport {
    pub theory_radius: f64,
    pub theory_peak_pressure: f64,
    pub contact_radius: f64,
    pub peak_pressure: f64,
    pub accuracy: Accuracy,
    pub summary: RunSummary,
}

impl DemoReport {
    /// The printed table.
    pub fn to_text(&self) -> String {
        let s = &self.summary;
        let rel = |x: f64, t: f64| 100.0 * (x / t - 1.0);
        format!(
            "Elastic sphere on a rigid plane: R = {RADIUS} m, E = {YOUNGS:.1e} Pa, nu = {POISSON}, P = {LOAD:.3e} N; a quarter of the sphere with symmetry planes x = 0, y = 0\n\
             {} particles, {} bonds; {}, residual {:.2e}, {:.1} s\n\n\
             {:<32} {:>14} {:>14} {:>9}\n\
             {:<32} {:>14.4} {:>14.4} {:>+8.2}%\n\
             {:<32} {:>14.4e} {:>14.4e} {:>+8.2}%\n\
             {:<32} {:>14} {:>14} {:>8.2}%\n\
             {:<32} {:>14.4e} {:>14.4e} {:>8.3}%\n\n\
             Frames: {}\n",
            s.particles,
            s.bonds,
            iterations(s),
            s.residual,
            s.wall_seconds,
            "",
            "computed",
            "Hertz",
            "error",
            "contact radius a (m, fitted)",
            self.contact_radius,
            self.theory_radius,
            rel(self.contact_radius, self.theory_radius),
            "peak pressure p0 (Pa)",
            self.peak_pressure,
            self.theory_peak_pressure,
            rel(self.peak_pressure, self.theory_peak_pressure),
            "mean error of p(r), r <= 0.8a",
            "",
            "",
            100.0 * self.accuracy.mre,
            "contact force on the quarter (N)",
            s.total_contact_force[2],
            LOAD / 4.0,
            100.0 * s.force_balance_error,
            s.outputs.pvd.display(),
        )
    }
}

/// "ADR 523 iterations", or the static solver's Newton and linear iterations.
fn iterations(s: &RunSummary) -> String {
    if s.solver.solver == "static" {
        let relaxed = if s.solver.relaxation_iterations > 0 {
            format!(" + {} ADR", s.solver.relaxation_iterations)
        } else {
            String::new()
        };
        format!(
            "static solver {} Newton iterations{relaxed} ({} linear)",
            s.iterations, s.solver.linear_iterations
        )
    } else {
        format!("ADR {} iterations", s.iterations)
    }
}

/// Runs the demo into `folder`.
pub fn run_demo(folder: &Path, options: &RunOptions) -> Result<DemoReport> {
    std::fs::create_dir_all(folder).map_err(|e| Error::output(folder, e))?;
    let mesh_path = folder.join(DEMO_MESH_NAME);
    write_atomically(&mesh_path, |w| std::io::Write::write_all(w, DEMO_MESH))?;
    let scene_path: PathBuf = folder.join("scene.toml");
    if let Some(kept) =
        write_keeping_edits(&scene_path, &scene_text(DemoSolver::for_options(options)))?
    {
        if !options.quiet {
            eprintln!(
                "warning: {} differed from the demo's scene (edited?): it is kept as {}",
                scene_path.display(),
                kept.display()
            );
        }
    }
    let scene = Scene::load(&scene_path)?;
    let (model, summary) = run_scene(&scene, options)?;
    let (a, p0) = hertz_sphere(LOAD, RADIUS, e_star_rigid(YOUNGS, POISSON));
    let patch = contact_patch(&model, 0, None)
        .ok_or_else(|| Error::numerical("the sphere did not touch the plane"))?;
    let accuracy = elliptic_accuracy(&patch, a, p0);
    Ok(DemoReport {
        theory_radius: a,
        theory_peak_pressure: p0,
        contact_radius: accuracy.fitted_radius,
        peak_pressure: patch.peak,
        accuracy,
        summary,
    })
}
