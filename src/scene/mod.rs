//! Scene files: bodies, loads, constraints, symmetry planes, contact pairs, solver, output.
//!
//! A scene is TOML. Unknown keys, wrong types and missing keys are errors with the file's line
//! and column. Paths in a scene are relative to the scene file. docs/guide/scene.md documents
//! every key with an example per feature (`tests/guide.rs` checks each against this schema).
//!
//! This module is the schema (the serde types) and the scene's messages (errors that point at
//! a line of the file); `check.rs` holds every check of a scene's values and references that
//! serde cannot make. What can only be found by reading a body's mesh (a file that does not
//! exist, a symmetry plane that crosses an element, a set that holds no particle) is reported
//! where the mesh is read (`body`, `model`), at the scene line it concerns.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

mod check;
mod check_fracture;
mod check_path;
mod check_solver;
mod material;
pub use check_path::MAX_FRICTION;
pub use material::{
    FailureCriterion, InfluenceFunction, MaterialModel, MaterialSpec, LPS_MAX_POISSON,
};

pub(crate) use check::{box_corner, memory_limit};

use crate::case::correction::CorrectionMethod;
use crate::case::{HorizonKind, SecondOrder, SurfaceVolume};
use crate::error::{Error, Result};

/// The whole scene file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Solver settings.
    pub solver: SolverSpec,
    /// Output settings.
    #[serde(default)]
    pub output: OutputSpec,
    /// Bodies, deformable or rigid.
    #[serde(rename = "body", default)]
    pub bodies: Vec<BodySpec>,
    /// Applied forces.
    #[serde(rename = "load", default)]
    pub loads: Vec<LoadSpec>,
    /// Fixed displacement components.
    #[serde(rename = "constraint", default)]
    pub constraints: Vec<ConstraintSpec>,
    /// Symmetry planes.
    #[serde(rename = "symmetry", default)]
    pub symmetries: Vec<SymmetrySpec>,
    /// Contact pairs.
    #[serde(rename = "contact", default)]
    pub contacts: Vec<ContactSpec>,
    /// Cracks made before the run: the bonds that cross them are removed.
    #[serde(rename = "precrack", default)]
    pub precracks: Vec<PrecrackSpec>,
    /// Folder that relative paths are resolved against (the scene file's folder).
    #[serde(skip)]
    pub base: PathBuf,
    /// Where the scene came from, for messages.
    #[serde(skip)]
    pub source: String,
    /// The scene's text, to point at lines in later errors.
    #[serde(skip)]
    pub text: String,
}

/// `kind` of `[solver]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SolverKind {
    /// Adaptive dynamic relaxation (quasi-static).
    Adr,
    /// Newton-Raphson with a matrix-free tangent (quasi-static).
    Static,
    /// Explicit dynamics (velocity Verlet).
    Explicit,
}

impl SolverKind {
    /// ADR or the static solver: a run to an equilibrium, in load increments.
    pub fn is_quasi_static(self) -> bool {
        matches!(self, SolverKind::Adr | SolverKind::Static)
    }
}

/// `[solver]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSpec {
    pub kind: SolverKind,
    /// ADR: out-of-balance force relative to the applied load (default 1e-4).
    pub tolerance: Option<f64>,
    /// ADR: iteration cap (default 200000).
    pub max_iterations: Option<usize>,
    /// ADR: apply the loads in this many equal increments, each relaxed to the tolerance
    /// (default 1, all at once).
    pub load_steps: Option<usize>,
    /// Explicit: time step in seconds (default: `safety` × the stable step).
    pub dt: Option<f64>,
    /// Explicit: fraction of the stable time step (default 0.8).
    pub safety: Option<f64>,
    /// Explicit: simulated time in seconds.
    pub end_time: Option<f64>,
    /// Explicit: mass-proportional damping rate `c` in 1/s (velocities decay as `e^{−c t}`;
    /// default 0, no damping). With it an explicit run settles to the static state, which is
    /// how a quasi-static contact is solved explicitly.
    pub damping: Option<f64>,
    /// Explicit: stop when the contact force has fallen back to zero after a contact.
    #[serde(default)]
    pub stop_after_rebound: bool,
}

/// `[output]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Output folder, relative to the scene file (default "out").
    #[serde(default = "default_folder")]
    pub folder: PathBuf,
    /// Write a frame every N steps (the last step is always written).
    #[serde(default = "default_every")]
    pub every: usize,
}

impl Default for OutputSpec {
    fn default() -> Self {
        OutputSpec {
            folder: default_folder(),
            every: default_every(),
        }
    }
}

fn default_folder() -> PathBuf {
    PathBuf::from("out")
}
fn default_every() -> usize {
    1000
}

/// `kind` of a body.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum BodyKind {
    /// A PD body with particles and bonds.
    #[default]
    Deformable,
    /// A rigid surface: no particles, no bonds.
    Rigid,
}

/// Bond kinematics of a deformable body.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Kinematics {
    /// `s = (|ξ+η| − |ξ|)/|ξ|` along the deformed bond (Eq. 26): rotations cost nothing.
    #[default]
    Finite,
    /// `s = (η·ξ̂)/|ξ|` along the reference bond (Silling's linearised PD): the small-strain
    /// model that Hertz theory and linear finite elements describe.
    Small,
}

/// How a rigid body moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Motion {
    /// Does not move.
    #[default]
    Fixed,
    /// Moves at the constant `velocity`.
    Velocity,
    /// Free to translate along `free_axis` under its loads and contact forces.
    Free,
    /// Quasi-static runs: moved to `displacement` in the solver's `load_steps` equal
    /// increments, each relaxed to equilibrium (displacement control: the reaction force of
    /// each increment is reported).
    Displacement,
}

/// `[[body]]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    pub name: String,
    #[serde(default)]
    pub kind: BodyKind,
    /// A mesh file (CDB, MSH, INP), relative to the scene file.
    pub mesh: Option<PathBuf>,
    /// Force the mesh format (cdb, msh, inp).
    pub format: Option<String>,
    /// The body is the solids of this named set of its mesh (one part of an assembly).
    pub elements: Option<String>,
    /// A built-in shape instead of a mesh file.
    pub generator: Option<GeneratorSpec>,
    /// Applied after loading: scale, then rotate, then translate.
    pub scale: Option<f64>,
    pub rotate: Option<RotateSpec>,
    #[serde(default, deserialize_with = "three_opt")]
    pub translate: Option<[f64; 3]>,
    /// Grid spacing Δ (default: a generator's cell size; for a mesh, the lattice spacing of the
    /// particles' median volume).
    pub spacing: Option<f64>,
    /// Horizon factor m (default 3).
    pub horizon_factor: Option<f64>,
    /// Surface correction method (default "balanced").
    pub surface_correction: Option<CorrectionMethod>,
    /// "local" (default): on a mesh without a given `spacing`, each bond's horizon is m times
    /// the local spacing of its particles, so that a mesh refined towards the contact is as
    /// fine there in the model; "uniform": δ = mΔ everywhere.
    pub horizon: Option<HorizonKind>,
    /// Nodes of a second-order mesh that become particles: "corners" (default) or
    /// "all-nodes" (each tet10 cut into eight tet4 at its mid-edge nodes, each hex20 into eight
    /// hex8 with face and centre nodes added).
    pub second_order: Option<SecondOrder>,
    /// Levels of uniform refinement (default 0): each cuts every tet and hex into eight at its
    /// edges' midpoints before the nodes become particles, twice the spacings across a
    /// contact at about seven times the particles (at most 3).
    pub refine: Option<u32>,
    /// Volume of a smooth surface particle: "per-area" (default: its tributary area times the
    /// thickness of the surface layer around it, so that an irregular surface carries an even
    /// stiffness per area) or "lumped" (its elements' share, as every other node).
    pub surface_volume: Option<SurfaceVolume>,
    /// Stiffen the surface row's bonds along its normal so that it carries a contact's
    /// traction as the continuum does (default true; docs/VALIDATION.md, "The skin
    /// correction"): on tet meshes whose contact spans 4-7 spacings it takes the MRE from
    /// 2-6 % to 1-3 %; `false` gives the balanced correction alone.
    pub skin_correction: Option<bool>,
    /// Bond kinematics: "finite" (default; stretch of the deformed bond, paper Eq. 26) or
    /// "small" (linearised: extension along the reference bond, for small-strain comparisons).
    #[serde(default)]
    pub kinematics: Kinematics,
    /// Material of a deformable body (rigid bodies may give one for the contact stiffness;
    /// without it a rigid body is infinitely stiff).
    pub material: Option<MaterialSpec>,
    /// Initial velocity of a deformable body, m/s.
    #[serde(default, deserialize_with = "three_opt")]
    pub velocity: Option<[f64; 3]>,
    /// Rigid bodies: how the body moves.
    #[serde(default)]
    pub motion: Motion,
    /// Rigid bodies with `motion = "velocity"`: the velocity, m/s.
    #[serde(default, deserialize_with = "three_opt")]
    pub motion_velocity: Option<[f64; 3]>,
    /// Rigid bodies with `motion = "free"`: the axis it may translate along.
    #[serde(default, deserialize_with = "three_opt")]
    pub free_axis: Option<[f64; 3]>,
    /// Rigid bodies with `motion = "free"`: its mass, kg (explicit runs).
    pub mass: Option<f64>,
    /// Rigid bodies with `motion = "displacement"`: the total displacement, m.
    #[serde(default, deserialize_with = "three_opt")]
    pub displacement: Option<[f64; 3]>,
    /// Rigid bodies with `motion = "displacement"`: the share of the load path over which it
    /// moves ([`Ramp`]; default `[0, 1]`, the whole path).
    pub ramp: Option<[f64; 2]>,
}

/// Where a load, a prescribed displacement or a driven body's motion rises along a
/// quasi-static run's load path: `[start, end]` in the load factor λ ∈ [0, 1] that ADR's
/// `load_steps` advance; zero before `start`, linear between, whole after `end`. A sphere
/// pressed by P and then pushed sideways by Q (Cattaneo-Mindlin): the normal load on
/// `[0, 0.5]`, the tangential one on `[0.5, 1]`.
pub fn ramp_factor(ramp: Option<[f64; 2]>, lambda: f64) -> f64 {
    match ramp {
        None => lambda,
        Some([a, b]) => ((lambda - a) / (b - a)).clamp(0.0, 1.0),
    }
}

/// A built-in shape.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GeneratorSpec {
    /// sphere, cylinder, box, sphere_cap, cylinder_cap or plane.
    pub shape: String,
    pub radius: Option<f64>,
    pub length: Option<f64>,
    pub spacing: Option<f64>,
    /// Box: the lower corner `[x, y, z]`; caps: the footprint's lower corner `[x, y]`.
    pub min: Option<Vec<f64>>,
    /// Box: the upper corner; caps: the footprint's upper corner.
    pub max: Option<Vec<f64>>,
    /// Plane: a point on it.
    #[serde(default, deserialize_with = "three_opt")]
    pub point: Option<[f64; 3]>,
    /// Plane: its normal, pointing out of the rigid body (toward the other body).
    #[serde(default, deserialize_with = "three_opt")]
    pub normal: Option<[f64; 3]>,
    /// Plane: side length of the square patch.
    pub size: Option<f64>,
    /// Plane: quads along each side (default 1).
    pub divisions: Option<usize>,
    /// Centre of a sphere, cylinder or cap (default origin).
    #[serde(default, deserialize_with = "three_opt")]
    pub center: Option<[f64; 3]>,
    /// Cap: how far the contact surface reaches to each side of the lowest point.
    pub half_width: Option<f64>,
    /// Cap: radial thickness of the shell sector.
    pub depth: Option<f64>,
}

/// A rotation about an axis through `center` (default origin).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotateSpec {
    #[serde(deserialize_with = "three")]
    pub axis: [f64; 3],
    pub angle_deg: f64,
    #[serde(default, deserialize_with = "three_opt")]
    pub center: Option<[f64; 3]>,
}

/// `[[load]]`: a total force on a body.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadSpec {
    pub body: String,
    /// A named set of the body's mesh; without it, the whole body (as a body force by volume).
    pub set: Option<String>,
    /// Total force, N.
    #[serde(deserialize_with = "three")]
    pub force: [f64; 3],
    /// The share of the load path over which it is applied ([`ramp_factor`]; default
    /// `[0, 1]`).
    pub ramp: Option<[f64; 2]>,
}

/// `[[constraint]]`: fixed displacement components of a set, or of the one particle nearest a
/// point.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConstraintSpec {
    pub body: String,
    /// A named set (node or element set) of the body's mesh.
    #[serde(default)]
    pub set: Option<String>,
    /// Instead of a set: the particle nearest this point (m, where the body is placed). A
    /// pin that holds a body's rigid motion where its loads already balance (the centre of a
    /// sphere pressed on another, held sideways), with a reaction near zero.
    #[serde(default, deserialize_with = "three_opt")]
    pub nearest: Option<[f64; 3]>,
    /// Components held: any of "x", "y", "z"; at zero, or at `displacement`.
    pub fix: Vec<Axis>,
    /// The displacement the held components are brought to, m (quasi-static runs: along the
    /// load path, [`ramp_factor`]); components not held must be 0.
    #[serde(default, deserialize_with = "three_opt")]
    pub displacement: Option<[f64; 3]>,
    /// The share of the load path over which `displacement` is applied (default `[0, 1]`).
    pub ramp: Option<[f64; 2]>,
}

/// `[[precrack]]`: a planar crack in a body's reference configuration, a rectangle centred at
/// `point` in the plane of `normal`, `size[0]` long along `along` and `size[1]` along
/// `normal × along`. Every bond whose segment crosses it is removed before the run.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PrecrackSpec {
    pub body: String,
    /// The patch's centre, m (where the body is placed).
    #[serde(deserialize_with = "three")]
    pub point: [f64; 3],
    /// The crack plane's normal.
    #[serde(deserialize_with = "three")]
    pub normal: [f64; 3],
    /// The direction of the patch's first side (its part along `normal` is dropped).
    #[serde(deserialize_with = "three")]
    pub along: [f64; 3],
    /// Side lengths along `along` and `normal × along`, m.
    pub size: [f64; 2],
}

/// `[[symmetry]]`: a symmetry plane `axis = at` of a body.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SymmetrySpec {
    pub body: String,
    /// "x", "y" or "z": the plane's normal axis.
    pub axis: Axis,
    /// The plane's coordinate along that axis (default 0).
    #[serde(default)]
    pub at: f64,
    /// Which side of the plane the model keeps: "positive" (default) or "negative". A mesh
    /// that reaches across the plane is cut there (its elements must not straddle it).
    #[serde(default)]
    pub keep: Side,
}

/// A coordinate axis: "x", "y" or "z" (serde names a wrong value with its line and column).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Axis {
    X,
    Y,
    Z,
}

impl Axis {
    /// 0, 1 or 2.
    pub fn index(self) -> usize {
        match self {
            Axis::X => 0,
            Axis::Y => 1,
            Axis::Z => 2,
        }
    }

    /// "x", "y" or "z", as the scene writes it.
    pub fn name(self) -> &'static str {
        ["x", "y", "z"][self.index()]
    }
}

/// The side of a symmetry plane that the model keeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Side {
    /// Coordinates above the plane.
    #[default]
    Positive,
    /// Coordinates below the plane.
    Negative,
}

impl Side {
    /// "positive" or "negative", as the scene writes it.
    pub fn name(self) -> &'static str {
        match self {
            Side::Positive => "positive",
            Side::Negative => "negative",
        }
    }
}

/// Penalty law of a contact pair.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum PenaltyLaw {
    /// `F = K δ^{3/2}` with the Hertz stiffness (Eqs. 22-24).
    #[default]
    Hertz,
    /// `F = K δ` with `K` the Hertz stiffness times √(window), for comparison.
    Linear,
}

/// `[[contact]]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// The body whose surface particles are checked against the master's segments.
    pub slave: String,
    /// The body whose master segments are pressed on.
    pub master: String,
    /// Also check the master's particles against the slave's segments (deformable pairs).
    #[serde(default)]
    pub two_pass: bool,
    #[serde(default)]
    pub penalty: PenaltyLaw,
    /// R of the Hertz stiffness (default Δ/2 of the slave).
    pub radius: Option<f64>,
    /// Contact method: "point-to-surface" (default) or "short-range".
    #[serde(default)]
    pub method: ContactMethod,
    /// Coulomb's friction coefficient μ (default 0: frictionless; METHOD.md §10,
    /// [`crate::contact::friction`]).
    #[serde(default)]
    pub friction: f64,
    /// A body that is its own master ([`Scene::self_faces`]): "precrack" (the faces of its
    /// pre-cracks, triangulated on their planes) or "found" (the surfaces its broken bonds
    /// open, found again as they open: [`crate::body::new_faces`]).
    pub faces: Option<SelfFaces>,
}

/// Which faces a body that is its own contact master presses on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum SelfFaces {
    /// The faces of its `[[precrack]]`s, each triangulated on the crack's plane
    /// ([`crate::case::crack_faces`]).
    Precrack,
    /// The surfaces its broken bonds open (its pre-cracks' among them), found again as they
    /// open ([`crate::body::new_surface`], [`crate::body::new_faces`]).
    Found,
}

impl SelfFaces {
    pub fn name(self) -> &'static str {
        match self {
            SelfFaces::Precrack => "precrack",
            SelfFaces::Found => "found",
        }
    }
}

/// How a contact pair is resolved.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Default, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ContactMethod {
    /// The paper's method: slave particles against master segments, Hertz penalty
    /// ([`crate::contact`]).
    #[default]
    #[serde(alias = "point_to_surface")]
    PointToSurface,
    /// Node-to-node repulsion of PD codes (EMU, LAMMPS); the master must be deformable
    /// ([`crate::contact::shortrange`]).
    #[serde(alias = "short_range")]
    ShortRange,
}

impl ContactMethod {
    pub fn name(self) -> &'static str {
        match self {
            ContactMethod::PointToSurface => "point-to-surface",
            ContactMethod::ShortRange => "short-range",
        }
    }
}

impl Scene {
    /// Reads and checks a scene file.
    pub fn load(path: &Path) -> Result<Scene> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| Error::input(format!("{}: cannot read the scene: {e}", path.display())))?;
        let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Scene::parse(&text, &path.display().to_string(), &base)
    }

    /// Parses scene text; `source` names it in messages, `base` anchors relative paths.
    pub fn parse(text: &str, source: &str, base: &Path) -> Result<Scene> {
        let mut scene: Scene = toml::from_str(text).map_err(|e| {
            let (line, col) = e.span().map(|s| line_col(text, s.start)).unwrap_or((0, 0));
            let msg = short_message(&plain_message(&e.message().replace('\n', " ")));
            Error::input(format!("{source}:{line}:{col}: {msg}"))
        })?;
        scene.base = base.to_path_buf();
        scene.source = source.to_string();
        scene.text = text.to_string();
        scene.check(text)?;
        Ok(scene)
    }

    /// An input error at the first place the scene's text holds `needle`.
    pub fn error_at(&self, needle: &str, msg: &str) -> Error {
        let (l, c) = locate(&self.text, needle);
        Error::input(format!("{}:{l}:{c}: {msg}", self.source))
    }

    /// An input error at the first place `needle` appears in the `[[body]]` named `body`
    /// (from its `name` line on); an empty needle points at the `name` line itself.
    pub fn error_in_body(&self, body: &str, needle: &str, msg: &str) -> Error {
        let (l, c) = locate_in_body(&self.text, body, needle);
        Error::input(format!("{}:{l}:{c}: {msg}", self.source))
    }

    /// A path of the scene, resolved against the scene's folder.
    pub fn resolve(&self, p: &Path) -> PathBuf {
        if p.is_absolute() {
            p.to_path_buf()
        } else {
            self.base.join(p)
        }
    }
}

/// Longest excerpt of a scene's value that a message repeats (a 100 kB bad value is named by
/// its first characters, not printed whole).
pub(crate) const EXCERPT_CHARS: usize = 40;

/// `s`, or its first [`EXCERPT_CHARS`] characters and how long it is.
pub fn excerpt(s: &str) -> String {
    let n = s.chars().count();
    if n <= EXCERPT_CHARS {
        s.to_string()
    } else {
        let head: String = s.chars().take(EXCERPT_CHARS).collect();
        format!("{head}… ({n} characters)")
    }
}

impl Scene {
    /// An input error at the `k`-th (0-based) block of the scene text headed `header`
    /// (`[[body]]`, `[[contact]]`, …): "file:line:column: msg".
    pub fn block_error(&self, header: &str, k: usize, msg: String) -> Error {
        let (l, c) = self
            .text
            .match_indices(header)
            .nth(k)
            .or_else(|| self.text.match_indices(header).next())
            .map_or((1, 1), |(p, _)| line_col(&self.text, p));
        Error::input(format!("{}:{l}:{c}: {msg}", self.source))
    }
}

/// A number as a message shows it: plainly between 1e-4 and 1e6, else in short exponent form
/// (`1e-300`, not 300 digits).
pub fn num(v: f64) -> String {
    let v = v + 0.0; // -0 as 0
    let a = v.abs();
    if v == 0.0 || !v.is_finite() || (1e-4..1e6).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// A parse error's message with every long word cut to an excerpt (toml repeats a bad value,
/// however long) and the whole held to a few lines.
/// The TOML reader's words for a type (Rust's `f64`, `usize`, "a sequence") in a user's, and
/// what a missing `[solver]` means.
fn plain_message(msg: &str) -> String {
    const WORDS: [(&str, &str); 9] = [
        (
            "expected f64",
            "expected a number (in SI units, without a unit: 1e9, not \"1 GPa\")",
        ),
        ("expected f32", "expected a number"),
        ("expected usize", "expected a whole number, 0 or more"),
        ("expected u64", "expected a whole number, 0 or more"),
        ("expected u32", "expected a whole number, 0 or more"),
        ("expected u8", "expected a whole number, 0 or more"),
        ("expected i64", "expected a whole number"),
        (
            "expected a sequence",
            "expected an array, like [0.0, 0.0, -1.0]",
        ),
        (
            "missing field `solver`",
            "missing the [solver] table: a scene says how it is solved (kind = \"adr\", \"static\" or \"explicit\"; docs/guide/scene.md)",
        ),
    ];
    let mut out = msg.to_string();
    for (rust, user) in WORDS {
        // Whole words only: "expected u8" is not the start of "expected u80".
        if let Some(at) = out.find(rust) {
            let end = at + rust.len();
            if !out[end..].starts_with(|c: char| c.is_alphanumeric()) {
                out.replace_range(at..end, user);
            }
        }
    }
    if out.contains("invalid basic string") {
        out.push_str(" (a string opened with \" is not closed on its line)");
    }
    out
}

fn short_message(msg: &str) -> String {
    let words: Vec<String> = msg
        .split(' ')
        .map(|w| {
            // A long number (toml writes 1e300 in 301 digits) in short form.
            let core = w.trim_matches(|c: char| "`'\",;:()".contains(c));
            if core.len() > 20 {
                if let Ok(v) = core.parse::<f64>() {
                    return w.replace(core, &num(v));
                }
            }
            if w.chars().count() > EXCERPT_CHARS + 2 {
                excerpt(w)
            } else {
                w.to_string()
            }
        })
        .collect();
    let out = words.join(" ");
    if out.chars().count() > 400 {
        let head: String = out.chars().take(400).collect();
        format!("{head}…")
    } else {
        out
    }
}

/// 1-based line and column of a byte offset.
pub(crate) fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before
        .rfind('\n')
        .map_or(before.len(), |p| before.len() - p - 1)
        + 1;
    (line, col)
}

/// Byte offset of the line `name = "<body>"` (any spacing around `=`).
fn body_offset(text: &str, body: &str) -> Option<usize> {
    let quoted = format!("\"{body}\"");
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        let t = line.trim_start();
        if let Some(rest) = t.strip_prefix("name") {
            if let Some(value) = rest.trim_start().strip_prefix('=') {
                if value.trim().starts_with(&quoted) {
                    return Some(offset + (line.len() - t.len()));
                }
            }
        }
        offset += line.len();
    }
    None
}

/// Line and column of `needle` at or after the body's `name` line (that line itself for an
/// empty needle; the first occurrence anywhere when the body's line is not found).
fn locate_in_body(text: &str, body: &str, needle: &str) -> (usize, usize) {
    let Some(start) = body_offset(text, body) else {
        return locate(text, needle);
    };
    match text[start..].find(needle) {
        Some(p) => line_col(text, start + p),
        None => line_col(text, start),
    }
}

/// Line and column of the first occurrence of `needle` (1, 1 when absent or empty).
fn locate(text: &str, needle: &str) -> (usize, usize) {
    if needle.is_empty() {
        return (1, 1);
    }
    text.find(needle).map_or((1, 1), |p| line_col(text, p))
}

/// A vector of the scene: exactly three components `[x, y, z]`. A fourth (a typo, a value
/// meant for another key) is refused at its line rather than dropped.
fn three<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<[f64; 3], D::Error> {
    let v: Vec<f64> = Deserialize::deserialize(d)?;
    <[f64; 3]>::try_from(v.as_slice()).map_err(|_| {
        serde::de::Error::custom(format!(
            "expected a vector of 3 components [x, y, z], found {} component{}",
            v.len(),
            if v.len() == 1 { "" } else { "s" }
        ))
    })
}

/// [`three`] for an optional key.
fn three_opt<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> std::result::Result<Option<[f64; 3]>, D::Error> {
    three(d).map(Some)
}

#[cfg(test)]
mod tests;
