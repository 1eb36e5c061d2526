//! `pdcontact validate`: the reference problems of the paper's Sec. 3, against theory
//! (METHOD.md §7).
//!
//! Two sets of scenes:
//!
//! * **hertz** — loads scaled so that `a/R = 0.15`, where Hertz's small-strain theory holds;
//!   `E*` of a rigid plane; small (linearised) bond kinematics, the model Hertz describes;
//!   spacing fine enough that the contact radius spans 15 particles; a stiff penalty
//!   (`R = 100 m` in Eq. 23) so that penetration does not add compliance. Only what the
//!   contact needs is modelled: a quarter (sphere) or a half slice (roller, punch) by
//!   symmetry planes, and for the sphere and roller a shell sector of depth 3a around the
//!   contact, loaded on its inner face (the full-body comparison is in docs/VALIDATION.md).
//! * **paper** — the paper's inputs as stated where they are consistent: R = 1 m, E = 1 GPa,
//!   ν = 0.25, Δ = 0.08 m, m = 3, the paper's loads (P = 1e8 N sphere, 2e8 N/m roller), the
//!   paper's bond kinematics (deformed bonds, Eq. 26) and penalty (R = Δ/2), compared with the
//!   theory twice: with the `E*` the paper's own theoretical values imply (two elastic bodies,
//!   5.333e8 Pa) and with a rigid plane's `E*`.
//!
//! Every run writes its scene, frames, `summary.json` and a chart of `p/p0` against `r/a`.

use std::path::{Path, PathBuf};
use std::time::Instant;

use plotters::prelude::*;
use serde::Serialize;

use crate::error::{Error, Result};
use crate::math::Vec3;
use crate::output::analysis::{
    contact_patch, e_star_rigid, elliptic_accuracy, hertz_cylinder, hertz_sphere, punch_accuracy,
    Accuracy, ContactPatch,
};
use crate::output::vtk::write_atomically;
use crate::run::{run_scene, RunOptions};
use crate::scene::Scene;

/// Young's modulus, Poisson's ratio and density of every validation body.
pub const YOUNGS: f64 = 1.0e9;
pub const POISSON: f64 = 0.25;
pub const DENSITY: f64 = 1000.0;
/// `E*` that the paper's theoretical values imply (Eq. 38 with two bodies of E and ν).
pub const PAPER_E_STAR: f64 = YOUNGS / (2.0 * (1.0 - POISSON * POISSON));

/// The three problems.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Problem {
    Sphere,
    Roller,
    Punch,
}

impl Problem {
    pub fn name(self) -> &'static str {
        match self {
            Problem::Sphere => "sphere",
            Problem::Roller => "roller",
            Problem::Punch => "punch",
        }
    }
}

/// The two sets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Set {
    Paper,
    Hertz,
}

impl Set {
    pub fn name(self) -> &'static str {
        match self {
            Set::Paper => "paper",
            Set::Hertz => "hertz",
        }
    }
}

/// What a run is compared with.
#[derive(Clone, Debug)]
pub enum Reference {
    /// Hertz sphere: total load on the whole sphere, sphere radius, `(label, E*)` variants.
    Sphere {
        load: f64,
        radius: f64,
        e_stars: Vec<(String, f64)>,
    },
    /// Hertz cylinder: load per unit length, radius, `(label, E*)` variants.
    Roller {
        load_per_length: f64,
        radius: f64,
        e_stars: Vec<(String, f64)>,
    },
    /// Sadowsky punch: load per unit length, half-width.
    Punch {
        load_per_length: f64,
        half_width: f64,
    },
}

/// One validation run.
#[derive(Clone, Debug)]
pub struct ValidationCase {
    pub problem: Problem,
    pub set: Set,
    /// A name for the run's folder and the table ("hertz", "study-spacing-0.04", ...).
    pub label: String,
    pub spacing: f64,
    pub horizon_factor: f64,
    pub scene: String,
    pub reference: Reference,
}

/// One line of the table (a run compared with one variant of its reference).
#[derive(Clone, Debug, Serialize)]
pub struct ValidationRow {
    pub case: String,
    pub set: String,
    /// Which `E*` the theory used ("rigid plane", "paper"), or the study point.
    pub variant: String,
    pub spacing: f64,
    pub horizon_factor: f64,
    pub particles: usize,
    pub mre: f64,
    pub radius_error: f64,
    pub force_balance_error: f64,
    pub iterations: usize,
    pub wall_seconds: f64,
    pub output_pvd: PathBuf,
    pub theory_radius: f64,
    pub theory_peak_pressure: f64,
    pub fitted_radius: f64,
    pub peak_pressure: f64,
    pub samples: usize,
    pub chart: PathBuf,
}

fn material() -> String {
    format!("[body.material]\nyoungs_modulus = {YOUNGS:e}\npoisson_ratio = {POISSON}\ndensity = {DENSITY}\n")
}

/// The penalty of the "hertz" set: R = 100 m, so that the penetration stays far below the
/// approach and the penalty adds no compliance that Hertz does not have.
pub const STIFF_PENALTY: &str =
    "radius = 100.0              # a stiff penalty: penetration stays far below the approach";

/// The solver block of an ADR run.
pub const ADR_SOLVER: &str = "kind = \"adr\"\ntolerance = 1e-5\nmax_iterations = 100000";

/// Hertz sphere on a rigid plane, a/R = 0.15: a quarter of the shell sector of depth 3a.
pub fn hertz_sphere_case(a_over_dx: f64) -> ValidationCase {
    sphere_cap_case(
        0.15,
        0.15 / a_over_dx,
        3.0,
        ADR_SOLVER,
        STIFF_PENALTY,
        "hertz",
    )
}

/// A Hertz sphere (R = 1 m) on a rigid plane with contact radius `a`: a quarter of the shell
/// sector of depth 3a around the contact point, spacing `dx`, horizon `m Δ`, solved with the
/// `[solver]` block `solver` and the penalty lines `penalty` of the `[[contact]]` block.
pub fn sphere_cap_case(
    a: f64,
    dx: f64,
    m: f64,
    solver: &str,
    penalty: &str,
    label: &str,
) -> ValidationCase {
    let radius = 1.0;
    let e_star = e_star_rigid(YOUNGS, POISSON);
    let load = 4.0 * e_star * a * a * a / (3.0 * radius);
    let scene = format!(
        r#"# Hertz sphere: R = {radius} m, a/R = {ratio} against a rigid plane (pdcontact validate)
[solver]
{solver}

[output]
every = 1000000

[[body]]
name = "sphere"
# The shell sector of depth 3a around the contact point, radial layers.
generator = {{ shape = "sphere_cap", radius = {radius}, half_width = {hw}, depth = {depth}, spacing = {dx} }}
kinematics = "small"
horizon_factor = {m}
{mat}
[[body]]
name = "plane"
kind = "rigid"
generator = {{ shape = "plane", point = [0.0, 0.0, -{radius}], normal = [0.0, 0.0, 1.0], size = 2.0 }}

[[load]]
body = "sphere"
set = "top"                 # the inner face of the sector: the rest of the sphere's load path
force = [0.0, 0.0, -{quarter:e}]   # a quarter of P = {load:e} N

[[contact]]
slave = "sphere"
master = "plane"
{penalty}

[[symmetry]]
body = "sphere"
axis = "x"

[[symmetry]]
body = "sphere"
axis = "y"
"#,
        ratio = a / radius,
        hw = 3.0 * a,
        depth = 3.0 * a,
        mat = material(),
        quarter = load / 4.0,
    );
    ValidationCase {
        problem: Problem::Sphere,
        set: Set::Hertz,
        label: label.into(),
        spacing: dx,
        horizon_factor: m,
        scene,
        reference: Reference::Sphere {
            load,
            radius,
            e_stars: vec![("rigid plane".into(), e_star)],
        },
    }
}

/// A Hertz sphere (R = 1 m) pressed on a deformable block of the same material, contact
/// radius `a`: the quarter shell sector of [`sphere_cap_case`] on a quarter block 3a × 3a × 3a
/// fixed at its bottom, both with the symmetry planes x = 0 and y = 0, compared with Hertz for
/// two bodies (`E* = E/(2(1 − ν²))`). `contact` is the body of the `[[contact]]` block
/// (method and penalty lines); `lift` raises the sphere above the block's top face (the
/// short-range method holds the surfaces 1.35Δ apart: lift by that much so that the run starts
/// touching). The block is a finite half-space, so the figures are the method's and the
/// block's together: compare methods on this scene with each other.
pub fn sphere_on_block_case(
    a: f64,
    dx: f64,
    m: f64,
    solver: &str,
    contact: &str,
    lift: f64,
    label: &str,
) -> ValidationCase {
    let radius = 1.0;
    let e_star = PAPER_E_STAR;
    let load = 4.0 * e_star * a * a * a / (3.0 * radius);
    let scene = format!(
        r#"# Hertz sphere: R = {radius} m, a/R = {ratio} on a deformable block (pdcontact sweep)
[solver]
{solver}

[output]
every = 1000000

[[body]]
name = "sphere"
generator = {{ shape = "sphere_cap", radius = {radius}, half_width = {hw}, depth = {hw}, spacing = {dx}, center = [0.0, 0.0, {lift}] }}
kinematics = "small"
horizon_factor = {m}
{mat}
[[body]]
name = "block"
generator = {{ shape = "box", min = [0.0, 0.0, {bottom}], max = [{hw}, {hw}, -{radius}], spacing = {dx} }}
kinematics = "small"
horizon_factor = {m}
{mat}
[[load]]
body = "sphere"
set = "top"
force = [0.0, 0.0, -{quarter:e}]   # a quarter of P = {load:e} N

[[constraint]]
body = "block"
set = "bottom"
fix = ["x", "y", "z"]

[[contact]]
slave = "sphere"
master = "block"
{contact}

[[symmetry]]
body = "sphere"
axis = "x"

[[symmetry]]
body = "sphere"
axis = "y"

[[symmetry]]
body = "block"
axis = "x"

[[symmetry]]
body = "block"
axis = "y"
"#,
        ratio = a / radius,
        hw = 3.0 * a,
        bottom = -radius - 3.0 * a,
        mat = material(),
        quarter = load / 4.0,
    );
    ValidationCase {
        problem: Problem::Sphere,
        set: Set::Hertz,
        label: label.into(),
        spacing: dx,
        horizon_factor: m,
        scene,
        reference: Reference::Sphere {
            load,
            radius,
            e_stars: vec![("two bodies".into(), e_star)],
        },
    }
}

/// Hertz roller (plane strain) on a rigid plane, a/R = 0.15: a half of a slice of the shell
/// sector, with symmetry planes on both faces of the slice (plane strain) and at x = 0.
pub fn hertz_roller_case(a_over_dx: f64) -> ValidationCase {
    let (radius, a) = (1.0, 0.15);
    let e_star = e_star_rigid(YOUNGS, POISSON);
    let load_per_length = std::f64::consts::PI * e_star * a * a / (4.0 * radius);
    let dx = a / a_over_dx;
    // Thick enough for a particle's neighbourhood: at least a horizon and a half spacing.
    let thickness = (4.0 * dx).max(dx * (3.0 + 0.5) * 1.05);
    let scene = format!(
        r#"# Hertz roller (plane strain): R = {radius} m, a/R = 0.15 against a rigid plane
[solver]
kind = "adr"
tolerance = 1e-5
max_iterations = 100000

[output]
every = 1000000

[[body]]
name = "roller"
generator = {{ shape = "cylinder_cap", radius = {radius}, half_width = {hw}, depth = {depth}, length = {thickness}, spacing = {dx} }}
kinematics = "small"
horizon_factor = 3.0
{mat}
[[body]]
name = "plane"
kind = "rigid"
generator = {{ shape = "plane", point = [0.0, {mid}, -{radius}], normal = [0.0, 0.0, 1.0], size = 2.0 }}

[[load]]
body = "roller"
set = "top"
force = [0.0, 0.0, -{half:e}]   # P = {load_per_length:e} N/m over the slice, half by symmetry

[[contact]]
slave = "roller"
master = "plane"
radius = 100.0

[[symmetry]]
body = "roller"
axis = "x"

[[symmetry]]           # plane strain: mirror images on both faces of the slice
body = "roller"
axis = "y"
at = 0.0

[[symmetry]]
body = "roller"
axis = "y"
at = {thickness}
keep = "negative"
"#,
        hw = 3.0 * a,
        depth = 3.0 * a,
        mid = 0.5 * thickness,
        mat = material(),
        half = load_per_length * thickness / 2.0,
    );
    ValidationCase {
        problem: Problem::Roller,
        set: Set::Hertz,
        label: "hertz".into(),
        spacing: dx,
        horizon_factor: 3.0,
        scene,
        reference: Reference::Roller {
            load_per_length,
            radius,
            e_stars: vec![("rigid plane".into(), e_star)],
        },
    }
}

/// Rigid flat punch of half-width a on an elastic block (plane strain), half model.
fn punch_case(
    set: Set,
    a: f64,
    dx: f64,
    load_per_length: f64,
    kinematics: &str,
    penalty: &str,
) -> ValidationCase {
    let half = 4.0 * a;
    let depth = 4.0 * a;
    let thickness = (4.0 * dx).max(dx * 3.5 * 1.05);
    let scene = format!(
        r#"# Rigid flat punch, half-width a = {a} m, on an elastic block (plane strain)
[solver]
kind = "adr"
tolerance = 1e-5
max_iterations = 200000

[output]
every = 1000000

[[body]]
name = "block"
generator = {{ shape = "box", min = [0.0, 0.0, -{depth}], max = [{half}, {thickness}, 0.0], spacing = {dx} }}
kinematics = "{kinematics}"
horizon_factor = 3.0
{mat}
[[body]]
name = "punch"
kind = "rigid"
generator = {{ shape = "box", min = [-{a}, -{over}, 0.0], max = [{a}, {over_t}, {a}], spacing = {a} }}
motion = "free"
free_axis = [0.0, 0.0, 1.0]

[[load]]
body = "punch"
force = [0.0, 0.0, -{half_load:e}]   # P = {load_per_length:e} N/m over the slice, half by symmetry

[[constraint]]
body = "block"
set = "bottom"
fix = ["x", "y", "z"]

[[contact]]
slave = "block"
master = "punch"
{penalty}

[[symmetry]]
body = "block"
axis = "x"

[[symmetry]]
body = "block"
axis = "y"
at = 0.0

[[symmetry]]
body = "block"
axis = "y"
at = {thickness}
keep = "negative"
"#,
        over = thickness,
        over_t = 2.0 * thickness,
        mat = material(),
        half_load = load_per_length * thickness / 2.0,
    );
    ValidationCase {
        problem: Problem::Punch,
        set,
        label: set.name().into(),
        spacing: dx,
        horizon_factor: 3.0,
        scene,
        reference: Reference::Punch {
            load_per_length,
            half_width: a,
        },
    }
}

/// Hertz-set punch: a = 0.5 m, a/Δ = `a_over_dx`, mean pressure 0.05 E.
pub fn hertz_punch_case(a_over_dx: f64) -> ValidationCase {
    punch_at(a_over_dx, 0.05)
}

/// The Hertz set's punch scene (a = 0.5 m, small kinematics, stiff penalty) at a/Δ =
/// `a_over_dx` and mean pressure `mean_pressure` × E.
pub fn punch_at(a_over_dx: f64, mean_pressure: f64) -> ValidationCase {
    let a = 0.5;
    punch_case(
        Set::Hertz,
        a,
        a / a_over_dx,
        mean_pressure * YOUNGS * 2.0 * a,
        "small",
        "radius = 100.0",
    )
}

/// The paper's sphere: P = 1e8 N, the stored gmsh sphere (Δ = 0.083 m) cut to a quarter.
pub fn paper_sphere_case(mesh: &Path) -> ValidationCase {
    let load = 1e8;
    let scene = format!(
        r#"# The paper's sphere: R = 1 m, P = 1e8 N, Δ ≈ 0.08 m, m = 3 (pdcontact validate)
[solver]
kind = "adr"
tolerance = 1e-5
max_iterations = 200000

[output]
every = 1000000

[[body]]
name = "sphere"
mesh = "{mesh}"
horizon_factor = 3.0
{mat}
[[body]]
name = "plane"
kind = "rigid"
generator = {{ shape = "plane", point = [0.0, 0.0, -1.0], normal = [0.0, 0.0, 1.0], size = 3.0 }}

[[load]]
body = "sphere"
force = [0.0, 0.0, -{quarter:e}]   # a quarter of P = 1e8 N, spread by volume

[[contact]]
slave = "sphere"
master = "plane"

[[symmetry]]
body = "sphere"
axis = "x"

[[symmetry]]
body = "sphere"
axis = "y"
"#,
        mesh = mesh.display(),
        mat = material(),
        quarter = load / 4.0,
    );
    ValidationCase {
        problem: Problem::Sphere,
        set: Set::Paper,
        label: "paper".into(),
        spacing: 0.0829,
        horizon_factor: 3.0,
        scene,
        reference: Reference::Sphere {
            load,
            radius: 1.0,
            e_stars: vec![
                ("paper E*".into(), PAPER_E_STAR),
                ("rigid plane".into(), e_star_rigid(YOUNGS, POISSON)),
            ],
        },
    }
}

/// The paper's roller: R = 1 m, length 4 m, 2e8 N/m, Δ = 0.08 m: a quarter (half length,
/// half width) of the whole roller.
pub fn paper_roller_case() -> ValidationCase {
    let load_per_length = 2e8;
    let dx = 0.08;
    let scene = format!(
        r#"# The paper's roller: R = 1 m, length 4 m, P = 2e8 N/m, Δ = 0.08 m, m = 3
[solver]
kind = "adr"
tolerance = 1e-5
max_iterations = 200000

[output]
every = 1000000

[[body]]
name = "roller"
generator = {{ shape = "cylinder", radius = 1.0, length = 4.0, spacing = {dx} }}
horizon_factor = 3.0
{mat}
[[body]]
name = "plane"
kind = "rigid"
generator = {{ shape = "plane", point = [0.0, 0.0, -1.0], normal = [0.0, 0.0, 1.0], size = 5.0 }}

[[load]]
body = "roller"
force = [0.0, 0.0, -{quarter:e}]   # a quarter of 2e8 N/m x 4 m

[[contact]]
slave = "roller"
master = "plane"

[[symmetry]]
body = "roller"
axis = "x"

[[symmetry]]
body = "roller"
axis = "y"
"#,
        mat = material(),
        quarter = load_per_length * 4.0 / 4.0,
    );
    ValidationCase {
        problem: Problem::Roller,
        set: Set::Paper,
        label: "paper".into(),
        spacing: dx,
        horizon_factor: 3.0,
        scene,
        reference: Reference::Roller {
            load_per_length,
            radius: 1.0,
            e_stars: vec![
                ("paper E*".into(), PAPER_E_STAR),
                ("rigid plane".into(), e_star_rigid(YOUNGS, POISSON)),
            ],
        },
    }
}

/// The paper's punch: P = 8e8 N/m, Δ = 0.08 m. The paper gives the punch's "length" as 5 m
/// and no width; read as a base 5 m wide (a = 2.5 m), which puts its mean pressure (1.6e8 Pa)
/// beside the sphere's and the roller's. With the default penalty radius R = Δ/2 the
/// particles under the punch's edges, where Sadowsky's pressure is singular, are pushed
/// through the contact window (a missed contact); the penalty is stiffened with R = 100 m,
/// as in the "hertz" set. Bonds are linear ("small"), the paper's "linear elastic bonds": with
/// finite kinematics the block's surface layer under the punch's edge is driven through the
/// layers beneath it at this load (see docs/VALIDATION.md).
pub fn paper_punch_case() -> ValidationCase {
    punch_case(Set::Paper, 2.5, 0.08, 8e8, "small", "radius = 100.0")
}

/// The cases of a selection.
pub fn cases(problems: &[Problem], sets: &[Set], sphere_mesh: &Path) -> Vec<ValidationCase> {
    let mut out = Vec::new();
    for &set in sets {
        for &p in problems {
            out.push(match (set, p) {
                (Set::Hertz, Problem::Sphere) => hertz_sphere_case(15.0),
                (Set::Hertz, Problem::Roller) => hertz_roller_case(15.0),
                (Set::Hertz, Problem::Punch) => hertz_punch_case(20.0),
                (Set::Paper, Problem::Sphere) => paper_sphere_case(sphere_mesh),
                (Set::Paper, Problem::Roller) => paper_roller_case(),
                (Set::Paper, Problem::Punch) => paper_punch_case(),
            });
        }
    }
    out
}

/// Runs one case into `folder/<problem>-<label>/` and compares it with its reference.
pub fn run_case(case: &ValidationCase, folder: &Path, quiet: bool) -> Result<Vec<ValidationRow>> {
    let dir = folder.join(format!("{}-{}", case.problem.name(), case.label));
    std::fs::create_dir_all(&dir).map_err(|e| Error::output(&dir, e))?;
    let scene_path = dir.join("scene.toml");
    write_atomically(&scene_path, |w| {
        std::io::Write::write_all(w, case.scene.as_bytes())
    })?;
    let scene = Scene::load(&scene_path)?;
    let start = Instant::now();
    let (model, summary) = run_scene(
        &scene,
        &RunOptions {
            output: Some(dir.clone()),
            quiet,
            stop: None,
        },
    )?;
    let wall = start.elapsed().as_secs_f64();
    let strip = match case.problem {
        Problem::Sphere => None,
        _ => Some(Vec3::y()),
    };
    let patch = contact_patch(&model, 0, strip)
        .ok_or_else(|| Error::numerical(format!("{}: no contact formed", dir.display())))?;
    let mut rows = Vec::new();
    let mut charted: Vec<(String, f64, f64, Accuracy)> = Vec::new();
    let variants: Vec<(String, f64, f64, Accuracy)> = match &case.reference {
        Reference::Sphere {
            load,
            radius,
            e_stars,
        } => e_stars
            .iter()
            .map(|(label, e)| {
                let (a, p0) = hertz_sphere(*load, *radius, *e);
                (label.clone(), a, p0, elliptic_accuracy(&patch, a, p0))
            })
            .collect(),
        Reference::Roller {
            load_per_length,
            radius,
            e_stars,
        } => e_stars
            .iter()
            .map(|(label, e)| {
                let (a, p0) = hertz_cylinder(*load_per_length, *radius, *e);
                (label.clone(), a, p0, elliptic_accuracy(&patch, a, p0))
            })
            .collect(),
        Reference::Punch {
            load_per_length,
            half_width,
        } => {
            let p0 = load_per_length / (std::f64::consts::PI * half_width);
            vec![(
                "Sadowsky".to_string(),
                *half_width,
                p0,
                punch_accuracy(&patch, *half_width, *load_per_length),
            )]
        }
    };
    let chart = dir.join("pressure.svg");
    for (label, a, p0, acc) in &variants {
        rows.push(ValidationRow {
            case: case.problem.name().into(),
            set: case.set.name().into(),
            variant: label.clone(),
            spacing: case.spacing,
            horizon_factor: case.horizon_factor,
            particles: summary.particles,
            mre: acc.mre,
            radius_error: acc.radius_error,
            force_balance_error: summary.force_balance_error,
            iterations: summary.iterations,
            wall_seconds: wall,
            output_pvd: summary.outputs.pvd.clone(),
            theory_radius: *a,
            theory_peak_pressure: *p0,
            fitted_radius: acc.fitted_radius,
            peak_pressure: patch.peak,
            samples: acc.samples,
            chart: chart.clone(),
        });
        charted.push((label.clone(), *a, *p0, *acc));
    }
    write_chart(&chart, case, &patch, &charted)?;
    Ok(rows)
}

/// p/p0 against r/a: particles as points, theory as a line (the paper's Figs. 15, 23, 27).
fn write_chart(
    path: &Path,
    case: &ValidationCase,
    patch: &ContactPatch,
    variants: &[(String, f64, f64, Accuracy)],
) -> Result<()> {
    let Some((label, a, p0, acc)) = variants.last() else {
        return Ok(());
    };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (720, 480)).into_drawing_area();
        let draw = |e: &dyn std::fmt::Display| Error::output(path, e.to_string());
        root.fill(&WHITE).map_err(|e| draw(&e))?;
        let ymax = match case.problem {
            Problem::Punch => 3.0,
            _ => 1.3,
        };
        let title = format!(
            "{} ({} set): MRE {:.2} %, Δ = {:.4} m, m = {}",
            case.problem.name(),
            case.set.name(),
            100.0 * acc.mre,
            case.spacing,
            case.horizon_factor
        );
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 18))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(0.0..1.5f64, 0.0..ymax)
            .map_err(|e| draw(&e))?;
        chart
            .configure_mesh()
            .x_desc(if case.problem == Problem::Sphere {
                "r / a"
            } else {
                "x / a"
            })
            .y_desc("p / p0")
            .draw()
            .map_err(|e| draw(&e))?;
        let theory: Vec<(f64, f64)> = (0..=600)
            .map(|k| {
                let s = 1.5 * k as f64 / 600.0;
                let v = match case.problem {
                    Problem::Punch => {
                        if s < 0.999 {
                            1.0 / (1.0 - s * s).sqrt()
                        } else {
                            f64::NAN
                        }
                    }
                    _ => (1.0 - s * s).max(0.0).sqrt(),
                };
                (s, v)
            })
            .filter(|(_, v)| v.is_finite() && *v <= ymax)
            .collect();
        chart
            .draw_series(LineSeries::new(theory, BLACK.stroke_width(2)))
            .map_err(|e| draw(&e))?
            .label(match case.problem {
                Problem::Punch => "Sadowsky".to_string(),
                _ => format!("Hertz ({label})"),
            })
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(2)));
        chart
            .draw_series(
                patch
                    .points
                    .iter()
                    .filter(|(_, r, _)| r / a <= 1.5)
                    .map(|(_, r, p)| Circle::new((r / a, (p / p0).min(ymax)), 3, RED.filled())),
            )
            .map_err(|e| draw(&e))?
            .label("particles")
            .legend(|(x, y)| Circle::new((x + 10, y), 3, RED.filled()));
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(|e| draw(&e))?;
        root.present().map_err(|e| draw(&e))?;
    }
    write_atomically(path, |w| std::io::Write::write_all(w, svg.as_bytes()))
}

/// The table `validate` prints.
pub fn table(rows: &[ValidationRow]) -> String {
    let mut s = format!(
        "{:<7} {:<6} {:<12} {:>8} {:>5} {:>9} {:>8} {:>9} {:>9} {:>7} {:>8}\n",
        "case",
        "set",
        "theory",
        "Δ (m)",
        "m",
        "particles",
        "MRE",
        "radius",
        "balance",
        "iters",
        "seconds"
    );
    for r in rows {
        s.push_str(&format!(
            "{:<7} {:<6} {:<12} {:>8.4} {:>5.3} {:>9} {:>7.2}% {:>+8.2}% {:>9.1e} {:>7} {:>8.1}\n",
            r.case,
            r.set,
            r.variant,
            r.spacing,
            r.horizon_factor,
            r.particles,
            100.0 * r.mre,
            100.0 * r.radius_error,
            r.force_balance_error,
            r.iterations,
            r.wall_seconds
        ));
    }
    s
}

/// Parses `--case` and `--set`, runs the selection into `folder`, and returns the rows.
pub fn run_selection(case: &str, set: &str, folder: &Path, quiet: bool) -> Result<Selection> {
    let problems = match case {
        "sphere" => vec![Problem::Sphere],
        "roller" => vec![Problem::Roller],
        "punch" => vec![Problem::Punch],
        "all" => vec![Problem::Sphere, Problem::Roller, Problem::Punch],
        other => {
            return Err(Error::input(format!(
                "--case takes sphere, roller, punch or all, got \"{other}\""
            )))
        }
    };
    let sets = match set {
        "paper" => vec![Set::Paper],
        "hertz" => vec![Set::Hertz],
        "all" => vec![Set::Hertz, Set::Paper],
        other => {
            return Err(Error::input(format!(
                "--set takes paper, hertz or all, got \"{other}\""
            )))
        }
    };
    std::fs::create_dir_all(folder).map_err(|e| Error::output(folder, e))?;
    // The paper sphere runs on the stored gmsh mesh, written next to its run.
    let mesh = folder.join(crate::studies::demo::SPHERE_MESH_NAME);
    write_atomically(&mesh, |w| {
        std::io::Write::write_all(w, crate::studies::demo::SPHERE_MESH)
    })?;
    let mesh = std::fs::canonicalize(&mesh).unwrap_or(mesh);
    let mut rows = Vec::new();
    let mut failures = Vec::new();
    for c in cases(&problems, &sets, &mesh) {
        if !quiet {
            eprintln!(
                "{} ({} set): Δ = {:.4} m, m = {} ...",
                c.problem.name(),
                c.set.name(),
                c.spacing,
                c.horizon_factor
            );
        }
        // A case that fails is reported and the others still run.
        match run_case(&c, folder, quiet) {
            Ok(r) => rows.extend(r),
            Err(e) => failures.push(format!("{} ({} set): {e}", c.problem.name(), c.set.name())),
        }
    }
    Ok(Selection { rows, failures })
}

/// What `validate` ran: the rows of the cases that finished, and the errors of those that did
/// not.
#[derive(Debug)]
pub struct Selection {
    pub rows: Vec<ValidationRow>,
    pub failures: Vec<String>,
}

/// The convergence studies of the paper's Sec. 3.2, on the Hertz sphere.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Study {
    /// Δ = 0.12, 0.08, 0.06, 0.04 m at m = 3.
    Spacing,
    /// m = √8, 3, √10, √13 at Δ = 0.04 m.
    Horizon,
    /// Explicit dynamics at dt = 1e-5, 5e-6, 1e-6 s, Δ = 0.08 m, m = 3.
    Timestep,
}

impl Study {
    pub fn parse(s: &str) -> Result<Study> {
        match s {
            "spacing" => Ok(Study::Spacing),
            "horizon" => Ok(Study::Horizon),
            "timestep" => Ok(Study::Timestep),
            other => Err(Error::input(format!(
                "--study takes spacing, horizon or timestep, got \"{other}\""
            ))),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Study::Spacing => "spacing",
            Study::Horizon => "horizon",
            Study::Timestep => "timestep",
        }
    }

    /// The axis of the study's chart.
    fn axis(self) -> &'static str {
        match self {
            Study::Spacing => "Δ (m)",
            Study::Horizon => "m = δ/Δ",
            Study::Timestep => "dt (µs)",
        }
    }
}

/// Contact radius of the study sphere: a/R = 0.3, so that the coarsest spacing (0.12 m)
/// still puts two and a half particles across the contact radius and the finest (0.04 m)
/// seven and a half.
pub const STUDY_CONTACT_RADIUS: f64 = 0.3;
/// Damping rate of the explicit study runs (1/s): about a third of critical for the sector's
/// lowest mode, so that the run settles within [`STUDY_END_TIME`].
pub const STUDY_DAMPING: f64 = 1500.0;
/// Simulated time of the explicit study runs (s): the velocities have decayed by
/// e^{−c t} = e^{−30} by then.
pub const STUDY_END_TIME: f64 = 0.02;

/// Spacing of the horizon study at fixed Δ (the paper's reading), and the horizon of its
/// fixed-δ series (m-convergence: δ = 3 × 0.04 m held, Δ = δ/m).
const HORIZON_STUDY_SPACING: f64 = 0.04;

/// The horizon factors of the paper's study: its 7th to 10th nearest-neighbour shells.
const HORIZON_FACTORS: [(&str, f64); 4] = [("√8", 8.0), ("3", 9.0), ("√10", 10.0), ("√13", 13.0)];

/// One point of a study: its label, its x on the chart, the chart series it belongs to, and
/// the case.
pub struct StudyPoint {
    pub label: String,
    pub x: f64,
    pub series: &'static str,
    pub case: ValidationCase,
}

/// The study's points. The horizon study has two series: m varied at fixed Δ, as the paper
/// varies it (δ = mΔ grows with m), and m varied at fixed δ (Δ = δ/m shrinks with m), the
/// m-convergence of the peridynamics literature, whose limit is the model at that δ.
pub fn study_cases(study: Study) -> Vec<StudyPoint> {
    let a = STUDY_CONTACT_RADIUS;
    match study {
        Study::Spacing => [0.12, 0.08, 0.06, 0.04]
            .into_iter()
            .map(|dx| StudyPoint {
                label: format!("Δ = {dx} m"),
                x: dx,
                series: "m = 3",
                case: sphere_cap_case(
                    a,
                    dx,
                    3.0,
                    ADR_SOLVER,
                    STIFF_PENALTY,
                    &format!("study-spacing-{dx}"),
                ),
            })
            .collect(),
        Study::Horizon => {
            let dx = HORIZON_STUDY_SPACING;
            let delta = 3.0 * dx;
            let fixed_spacing = HORIZON_FACTORS.iter().map(|&(name, m2)| {
                let m = f64::sqrt(m2);
                StudyPoint {
                    label: format!("m = {name}, Δ = {dx} m"),
                    x: m,
                    series: "fixed Δ = 0.04 m (δ = mΔ)",
                    case: sphere_cap_case(
                        a,
                        dx,
                        m,
                        ADR_SOLVER,
                        STIFF_PENALTY,
                        &format!("study-horizon-{m:.3}"),
                    ),
                }
            });
            let fixed_horizon = HORIZON_FACTORS.iter().map(|&(name, m2)| {
                let m = f64::sqrt(m2);
                let spacing = delta / m;
                StudyPoint {
                    label: format!("m = {name}, δ = {delta} m"),
                    x: m,
                    series: "fixed δ = 0.12 m (Δ = δ/m)",
                    case: sphere_cap_case(
                        a,
                        spacing,
                        m,
                        ADR_SOLVER,
                        STIFF_PENALTY,
                        &format!("study-horizon-fixed-delta-{m:.3}"),
                    ),
                }
            });
            fixed_spacing.chain(fixed_horizon).collect()
        }
        Study::Timestep => [1e-5, 5e-6, 1e-6]
            .into_iter()
            .map(|dt: f64| {
                let solver = format!(
                    "kind = \"explicit\"\ndt = {dt:e}\ndamping = {STUDY_DAMPING}\nend_time = {STUDY_END_TIME}"
                );
                StudyPoint {
                    label: format!("dt = {dt:e} s"),
                    x: dt * 1e6,
                    series: "Δ = 0.08 m, m = 3",
                    // The paper's penalty (R = Δ/2): the stiff one would need dt < 1e-6 s.
                    case: sphere_cap_case(
                        a,
                        0.08,
                        3.0,
                        &solver,
                        "",
                        &format!("study-timestep-{dt:e}"),
                    ),
                }
            })
            .collect(),
    }
}

/// Runs a study into `folder`: one subfolder per point, the rows, the failures, and the chart
/// `study-<name>.svg` of MRE against the study's parameter.
pub fn run_study(study: Study, folder: &Path, quiet: bool) -> Result<Selection> {
    std::fs::create_dir_all(folder).map_err(|e| Error::output(folder, e))?;
    let mut rows = Vec::new();
    let mut failures = Vec::new();
    let mut points: Vec<(&str, f64, f64)> = Vec::new();
    for point in study_cases(study) {
        let name = &point.label;
        if !quiet {
            eprintln!("{} study: {name} ...", study.name());
        }
        match run_case(&point.case, folder, quiet) {
            Ok(r) => {
                for mut row in r {
                    points.push((point.series, point.x, 100.0 * row.mre));
                    row.variant = name.clone();
                    rows.push(row);
                }
            }
            Err(e) => failures.push(format!("{} study, {name}: {e}", study.name())),
        }
    }
    let chart = folder.join(format!("study-{}.svg", study.name()));
    write_study_chart(&chart, study, &points)?;
    Ok(Selection { rows, failures })
}

/// MRE (%) against the study's parameter, one line per series.
fn write_study_chart(path: &Path, study: Study, points: &[(&str, f64, f64)]) -> Result<()> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (720, 480)).into_drawing_area();
        let draw = |e: &dyn std::fmt::Display| Error::output(path, e.to_string());
        root.fill(&WHITE).map_err(|e| draw(&e))?;
        let xmax = points.iter().map(|p| p.1).fold(0.0, f64::max) * 1.15 + 1e-12;
        let xmin = points.iter().map(|p| p.1).fold(xmax, f64::min) * 0.85;
        let ymax = points.iter().map(|p| p.2).fold(0.0, f64::max) * 1.2 + 1.0;
        let mut chart = ChartBuilder::on(&root)
            .caption(
                format!(
                    "Hertz sphere, a/R = {STUDY_CONTACT_RADIUS}: MRE against {}",
                    study.name()
                ),
                ("sans-serif", 18),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(xmin..xmax, 0.0..ymax)
            .map_err(|e| draw(&e))?;
        chart
            .configure_mesh()
            .x_desc(study.axis())
            .y_desc("MRE (%)")
            .draw()
            .map_err(|e| draw(&e))?;
        let mut names: Vec<&str> = points.iter().map(|p| p.0).collect();
        names.dedup();
        let colours = [RED, BLUE, GREEN, MAGENTA];
        for (k, name) in names.iter().enumerate() {
            let colour = colours[k % colours.len()];
            let mut sorted: Vec<(f64, f64)> = points
                .iter()
                .filter(|p| p.0 == *name)
                .map(|p| (p.1, p.2))
                .collect();
            sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
            chart
                .draw_series(LineSeries::new(sorted.clone(), colour.stroke_width(1)))
                .map_err(|e| draw(&e))?
                .label(*name)
                .legend(move |(x, y)| Circle::new((x + 10, y), 4, colour.filled()));
            chart
                .draw_series(
                    sorted
                        .iter()
                        .map(|&(x, y)| Circle::new((x, y), 4, colour.filled())),
                )
                .map_err(|e| draw(&e))?;
        }
        if names.len() > 1 {
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .draw()
                .map_err(|e| draw(&e))?;
        }
        root.present().map_err(|e| draw(&e))?;
    }
    write_atomically(path, |w| std::io::Write::write_all(w, svg.as_bytes()))
}
