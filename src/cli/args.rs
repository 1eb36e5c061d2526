//! The command line's arguments: what each command takes, parsed by clap, before `mod.rs`
//! checks and runs them.

use std::path::PathBuf;

use crate::case::{SecondOrder, DEFAULT_HORIZON_FACTOR};
use crate::importers::Format;
use crate::studies::scenarios::{Problem, Set};
use crate::studies::validate::Study;
use clap::{Parser, Subcommand, ValueEnum};

/// Peridynamic point-to-surface contact from finite-element meshes.
#[derive(Parser, Debug)]
#[command(name = "pdcontact", version, about, long_about = None)]
pub(crate) struct Cli {
    #[command(subcommand)]
    pub(crate) command: Command,
}

#[derive(Subcommand, Debug)]
pub(crate) enum Command {
    /// Summarise a mesh file (ANSYS CDB, Gmsh MSH, Abaqus INP).
    Inspect {
        /// The mesh file.
        file: PathBuf,
        /// Force the format instead of guessing it: cdb, msh or inp.
        #[arg(long, value_parser = parse_format)]
        format: Option<Format>,
        /// Print the summary as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Turn a mesh into a PD case folder (particles, surface, master segments, scene skeleton).
    Convert {
        /// The mesh file.
        mesh: PathBuf,
        /// Output folder.
        #[arg(short, long)]
        output: PathBuf,
        /// Grid spacing Δ (default: the lattice spacing of the particles' median volume).
        #[arg(long)]
        spacing: Option<f64>,
        /// Horizon factor m (δ = m·Δ).
        #[arg(long, default_value_t = DEFAULT_HORIZON_FACTOR, value_parser = parse_horizon_factor)]
        horizon_factor: f64,
        /// Which nodes of a second-order mesh become particles: its corners (default), or all
        /// of them (each tet10 cut into eight tet4, each hex20 into eight hex8).
        #[arg(long, value_enum, value_name = "NODES")]
        second_order: Option<SecondOrderArg>,
        /// Cut every tet and hex into eight at its edges' midpoints, N times, before the nodes
        /// become particles (about seven times the particles per level, at most 3).
        #[arg(long, value_name = "N", default_value_t = 0)]
        refine: u32,
        /// Force the mesh format: cdb, msh or inp.
        #[arg(long, value_parser = parse_format)]
        format: Option<Format>,
        /// Print the summary as JSON on stdout.
        #[arg(long)]
        json: bool,
        /// Do not print the warnings on stderr (they stay in the summary).
        #[arg(long)]
        quiet: bool,
    },
    /// The main job: an elastic sphere pressed onto a rigid plane, compared with Hertz.
    Demo {
        /// Output folder (frames, summary.json, and the scene and mesh to run it again).
        #[arg(short, long, default_value = "pdcontact-demo")]
        output: PathBuf,
        /// Print the comparison and summary as JSON on stdout.
        #[arg(long)]
        json: bool,
        /// No progress on stderr.
        #[arg(long)]
        quiet: bool,
    },
    /// Validate against theory: Hertz sphere and roller, Sadowsky punch (paper and hertz sets),
    /// or the Hertz sphere or roller on your own mesh (--mesh).
    Validate {
        /// The problems [default: all; with --mesh: sphere].
        #[arg(long, value_enum)]
        case: Option<ProblemArg>,
        /// The scene sets.
        #[arg(long, value_enum, default_value_t = SetArg::Hertz)]
        set: SetArg,
        /// Run a convergence study of the sphere instead.
        #[arg(long, value_enum)]
        study: Option<StudyArg>,
        /// Run the Hertz scene on this mesh instead (CDB, MSH, INP): a solid sphere (--case
        /// sphere) or circular cylinder with its axis along x, y or z (--case roller), of any
        /// size and position; the roller's end faces become symmetry planes (plane strain).
        #[arg(long, value_name = "FILE", conflicts_with_all = ["set", "study"])]
        mesh: Option<PathBuf>,
        /// With --mesh: force the mesh format (cdb, msh or inp) instead of guessing it.
        #[arg(long, value_parser = parse_format, requires = "mesh")]
        format: Option<Format>,
        /// With --mesh: load so that Hertz's contact radius (or half-width) is this fraction of
        /// the body's radius (at most 0.5; Hertz theory holds best at 0.15 or less, where the
        /// mesh needs a/Δ >= 5 across the contact).
        #[arg(long, value_name = "A_OVER_R", default_value_t = crate::studies::user_mesh::CONTACT_RATIO, requires = "mesh")]
        contact_ratio: f64,
        /// With --mesh: the horizon δ = MΔ in particle spacings (default 3); see
        /// docs/VALIDATION.md, "Few spacings across the contact".
        #[arg(long, value_name = "M", requires = "mesh")]
        horizon_factor: Option<f64>,
        /// With --mesh: which nodes of a second-order mesh become particles: its corners
        /// (default), or all of them (each tet10 cut into eight tet4, each hex20 into eight
        /// hex8; 7-8 times the particles, twice the spacings across the contact).
        #[arg(long, value_enum, value_name = "NODES", requires = "mesh")]
        second_order: Option<SecondOrderArg>,
        /// With --mesh: cut every tet and hex into eight at its edges' midpoints, N times,
        /// before the nodes become particles (twice the spacings across the contact per level,
        /// about seven times the particles; written into the scene). Default 0; where the
        /// contact spans fewer than 5 spacings and none of --refine, --second-order and
        /// --horizon-factor is given, a second row shows the mesh refined once (a second-order
        /// mesh: with all its nodes).
        #[arg(long, value_name = "N", requires = "mesh")]
        refine: Option<u32>,
        /// The skin correction: the surface row's bonds stiffened along its normal so that it
        /// carries a contact's traction as the continuum does (the default, as in `run`).
        /// `false` writes `skin_correction = false` on every deformable body: the balanced
        /// correction alone, a softer surface row (on tet meshes whose contact spans 4-7
        /// spacings, MRE 2-6 % instead of 1-3 %; docs/VALIDATION.md, "The skin correction").
        /// Not with --study
        #[arg(long, value_name = "BOOL", default_value_t = true, action = clap::ArgAction::Set, conflicts_with = "study")]
        skin_correction: bool,
        /// The quasi-static solver written into each scene: Newton-Raphson (static, the
        /// default: the same figures as ADR's to 0.01 points, in a fifth to a half of the
        /// time; docs/PERFORMANCE.md, "The static solver") or adaptive dynamic relaxation
        /// (adr: the iteration counts of docs/VALIDATION.md). Not with --study
        #[arg(long, value_enum, default_value_t = SolverArg::Static, conflicts_with = "study")]
        solver: SolverArg,
        /// With --mesh: press the sphere on a rigid plane (default), or on a copy of itself
        /// (two deformable bodies meshed alike, each held sideways at its centre; Hertz for two
        /// identical spheres, one row per body; docs/VALIDATION.md, "Two deformable bodies").
        #[arg(long, value_enum, default_value_t = PartnerArg::Plane, requires = "mesh")]
        partner: PartnerArg,
        /// With --mesh: the body's Poisson's ratio, in the linear peridynamic solid
        /// (`model = "lps"`, any ν up to 0.49; Hertz's E* with it). Without it the bond-based
        /// model at ν = 0.25 (docs/VALIDATION.md, "Any Poisson's ratio").
        #[arg(long, value_name = "NU", requires = "mesh")]
        poisson: Option<f64>,
        /// With --poisson: the linear peridynamic solid's influence function
        /// (`influence_function` in `[body.material]`; docs/VALIDATION.md, "Any Poisson's
        /// ratio").
        #[arg(long, value_enum, requires = "poisson")]
        influence: Option<InfluenceArg>,
        /// Output folder (one subfolder per run).
        #[arg(short, long, default_value = "pdcontact-validate")]
        output: PathBuf,
        /// Print the rows as JSON on stdout.
        #[arg(long)]
        json: bool,
        /// No progress on stderr.
        #[arg(long)]
        quiet: bool,
    },
    /// Fracture against LEFM: a notched three-point bend beam (S = 4W, a/W = 0.5) on two rigid
    /// rollers, broken by a third driven down through the contact; prints the peak load
    /// against LEFM's and writes the load-displacement chart (docs/FRACTURE.md).
    Fracture {
        /// The benchmark: the notched beam against LEFM, the Kalthoff-Winkler plate, or a crack
        /// closed by its load.
        #[arg(long, value_enum, default_value_t = FractureCase::Beam)]
        case: FractureCase,
        /// Grid spacing Δ, m, the horizon 3Δ [default: 0.002 for the beam, whose notch is 20 mm
        /// deep; 0.0015 for the Kalthoff plate; 0.05 for the cracked block; 0.0005 for the perforated
        /// plate].
        #[arg(long)]
        spacing: Option<f64>,
        /// The perforated plate as a mesh (a 20 × 20 × 2 mm box, `tools/gmsh_plate.py`)
        /// instead of the box generator; --spacing is then the ball's.
        #[arg(long)]
        plate_mesh: Option<PathBuf>,
        /// The notched beam as a mesh with its notch cut out as a slot (`tools/gmsh_beam.py`)
        /// instead of the box generator and a pre-crack; its spacing is the mesh's.
        #[arg(long)]
        beam_mesh: Option<PathBuf>,
        /// The notched beam's solver: ADR, or the static solver (Newton, its bonds tested
        /// near each equilibrium; the beam then held along its length under the striker).
        #[arg(long, value_enum, default_value_t = BeamSolver::Adr)]
        solver: BeamSolver,
        /// The beam's thickness B, m.
        #[arg(long, default_value_t = 0.008)]
        thickness: f64,
        /// The notched beam as a linear peridynamic solid (`model = "lps"`) with this
        /// Poisson's ratio, its critical stretch from the same fracture energy; without it
        /// the bond-based model (ν = 1/4).
        #[arg(long, value_name = "NU")]
        lps: Option<f64>,
        /// What fails the notched beam's bonds past their critical stretch: the stretch
        /// alone, or only a tension along the bond (`[body.material] failure`).
        #[arg(long, value_enum, default_value_t = BeamFailure::Stretch)]
        failure: BeamFailure,
        /// The loading roller's travel, m.
        #[arg(long, default_value_t = 0.0008)]
        displacement: f64,
        /// Increments of the travel.
        #[arg(long, default_value_t = 16)]
        steps: usize,
        /// Output folder.
        #[arg(short, long, default_value = "pdcontact-fracture")]
        output: PathBuf,
        /// Print the result as JSON on stdout.
        #[arg(long)]
        json: bool,
        /// No progress on stderr.
        #[arg(long)]
        quiet: bool,
    },
    /// Friction against its references: a block on a tilted plane that holds or slides
    /// (explicit), and Cattaneo-Mindlin, a sphere pressed and then pushed sideways, whose
    /// contact sticks within c = a (1 − Q/(μP))^(1/3) (ADR; docs/VALIDATION.md "Friction").
    Friction {
        /// The benchmark.
        #[arg(long, value_enum, default_value_t = FrictionCase::Mindlin)]
        case: FrictionCase,
        /// Grid spacing Δ, m [default: a/5 for the sphere, 0.01 for the block].
        #[arg(long)]
        spacing: Option<f64>,
        /// Mindlin: Hertz's contact radius a under P, m, on the sphere of R = 1 m. The theory
        /// is the half-space's (a ≪ R): the pressing alone leaves a shear in the contact that
        /// grows with a/R, about 1.7 % of μ p0 at 0.05 and 4.5 % at 0.15 (docs/VALIDATION.md).
        #[arg(long, default_value_t = 0.05)]
        contact_radius: f64,
        /// Coulomb's μ.
        #[arg(long, default_value_t = 0.3)]
        friction: f64,
        /// The block's slopes tan θ, one run each.
        #[arg(long, value_delimiter = ',', default_value = "0.2,0.5")]
        slope: Vec<f64>,
        /// Mindlin: the push, as a share of the theory's travel at full slip (the sector and
        /// the block shear as well: 1.5 takes Q to about 0.9 μP).
        #[arg(long, default_value_t = 1.5)]
        push: f64,
        /// Mindlin: increments of the pressing and of the push.
        #[arg(long, default_value_t = 8)]
        steps: usize,
        /// Mindlin: on a rigid flat (β ≠ 0) instead of a block of the same material.
        #[arg(long)]
        rigid_flat: bool,
        /// Mindlin: the quasi-static solver that walks the path, adaptive dynamic relaxation
        /// (adr) or Newton-Raphson (static).
        #[arg(long, value_enum, default_value_t = SolverArg::Adr)]
        solver: SolverArg,
        /// Mindlin: the sphere's mesh in place of the built-in one (its inner face the set
        /// `top`, on y ≥ 0: what tools/gmsh_mindlin.py writes); with --block-mesh.
        #[arg(
            long,
            value_name = "FILE",
            requires = "block_mesh",
            conflicts_with = "rigid_flat"
        )]
        sphere_mesh: Option<PathBuf>,
        /// Mindlin: the block's mesh (its bottom face the set `bottom`, on y ≥ 0).
        #[arg(long, value_name = "FILE", requires = "sphere_mesh")]
        block_mesh: Option<PathBuf>,
        /// Output folder.
        #[arg(short, long, default_value = "pdcontact-friction")]
        output: PathBuf,
        /// Print the results as JSON on stdout.
        #[arg(long)]
        json: bool,
        /// No progress on stderr.
        #[arg(long)]
        quiet: bool,
    },
    /// Speed against accuracy: the Hertz sphere over a grid of spacings, horizons, contact
    /// methods and solvers; writes sweep.json and speed_accuracy.svg.
    Sweep {
        /// The problem.
        #[arg(long, value_enum, default_value_t = SweepProblem::Sphere)]
        case: SweepProblem,
        /// The scene set.
        #[arg(long, value_enum, default_value_t = SweepSet::Hertz)]
        set: SweepSet,
        /// Output folder (one subfolder per run).
        #[arg(short, long, default_value = "pdcontact-sweep")]
        output: PathBuf,
        /// Print the runs as JSON on stdout instead of a table.
        #[arg(long)]
        json: bool,
        /// No progress on stderr.
        #[arg(long)]
        quiet: bool,
        /// Map the explicit time step, the penalty stiffness and the impact speed, two at a
        /// time, instead; writes stability.json and stability.svg.
        #[arg(long)]
        stability: bool,
        /// The CalculiX cases to draw beside the runs: the JSON that
        /// `tools/fe_reference.sh --contact-radius 0.3 --json FILE` writes on this machine
        /// (default: the cases measured in docs/SPEED_ACCURACY.md).
        #[arg(long, value_name = "FILE")]
        fe: Option<PathBuf>,
    },
    /// Time the bond-force kernel on the LAMMPS peri/pmb comparison problem: a sphere
    /// (R = 1 m) of simple cubic lattice points, explicit velocity Verlet.
    Bench {
        /// Lattice spacing Δ in metres (0.04 gives 65,267 particles).
        #[arg(
            long,
            value_name = "DX",
            required_unless_present_any = ["adr", "pipeline"],
            conflicts_with_all = ["adr", "pipeline"]
        )]
        lattice_sphere: Option<f64>,
        /// Instead: time one ADR iteration against one bare bond-force pass on this scene, and
        /// its contact search (Verlet rebuild, point-to-surface pass).
        #[arg(long, value_name = "SCENE", conflicts_with = "pipeline")]
        adr: Option<PathBuf>,
        /// Instead: time each stage from this mesh file to a case folder (import, neighbours,
        /// surface detection, correction, VTU writing), with throughput and peak memory.
        #[arg(long, value_name = "MESH")]
        pipeline: Option<PathBuf>,
        /// With --pipeline: grid spacing Δ (default: the lattice spacing of the particles' median
        /// volume).
        #[arg(long)]
        spacing: Option<f64>,
        /// Horizon factor m (δ = m·Δ) [default: 3.0002 on the lattice, which keeps bonds of
        /// length exactly 3Δ in; 3 with --pipeline]
        #[arg(long)]
        horizon_factor: Option<f64>,
        /// Time steps (or, with --adr, passes and iterations) to time.
        #[arg(long, default_value_t = 200)]
        steps: usize,
        /// Threads (default: one per core).
        #[arg(long)]
        threads: Option<usize>,
        /// Print the measurements as JSON on stdout.
        #[arg(long)]
        json: bool,
    },
    /// Run a scene file: frames for ParaView and summary.json in the output folder.
    Run {
        /// The scene (TOML).
        scene: PathBuf,
        /// Output folder (default: the scene's output.folder).
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Print summary.json on stdout.
        #[arg(long)]
        json: bool,
        /// No progress on stderr.
        #[arg(long)]
        quiet: bool,
        /// Check the scene and stop: read the meshes, build the particles, bonds, surfaces
        /// and contact pairs, print the warnings, solve nothing and write nothing (exit 0 if
        /// the scene can run, 2 if not).
        #[arg(long, conflicts_with_all = ["output", "json"])]
        check: bool,
    },
}

/// `validate --case`: the problems (a validation "case" is a problem and a set).
#[derive(Clone, Copy, Debug, ValueEnum)]
pub(crate) enum ProblemArg {
    Sphere,
    Roller,
    Punch,
    All,
}

impl ProblemArg {
    pub(crate) fn problems(self) -> Vec<Problem> {
        match self {
            ProblemArg::Sphere => vec![Problem::Sphere],
            ProblemArg::Roller => vec![Problem::Roller],
            ProblemArg::Punch => vec![Problem::Punch],
            ProblemArg::All => vec![Problem::Sphere, Problem::Roller, Problem::Punch],
        }
    }
}

/// `validate --solver`: the quasi-static solver written into the scenes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum SolverArg {
    /// Adaptive dynamic relaxation.
    Adr,
    /// Newton-Raphson with a matrix-free tangent.
    Static,
}

/// `validate --influence`: the LPS's influence function.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum InfluenceArg {
    /// ω = 1, a factor per particle (the default).
    Constant,
    /// Position-aware: each particle's energy the continuum's under any uniform strain.
    PositionAware,
}

/// `validate --partner`: what the mesh is pressed on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum PartnerArg {
    /// A rigid plane.
    Plane,
    /// A copy of the mesh (two deformable bodies).
    Copy,
}

/// `validate --second-order`: which nodes of a second-order mesh become particles.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub(crate) enum SecondOrderArg {
    Corners,
    AllNodes,
}

impl From<SecondOrderArg> for SecondOrder {
    fn from(s: SecondOrderArg) -> SecondOrder {
        match s {
            SecondOrderArg::Corners => SecondOrder::Corners,
            SecondOrderArg::AllNodes => SecondOrder::AllNodes,
        }
    }
}

/// `validate --set`: the scene sets.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub(crate) enum SetArg {
    Paper,
    Hertz,
    All,
}

impl SetArg {
    pub(crate) fn sets(self) -> Vec<Set> {
        match self {
            SetArg::Paper => vec![Set::Paper],
            SetArg::Hertz => vec![Set::Hertz],
            SetArg::All => vec![Set::Hertz, Set::Paper],
        }
    }
}

/// `validate --study`: the convergence studies.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub(crate) enum StudyArg {
    Spacing,
    Horizon,
    Timestep,
}

impl From<StudyArg> for Study {
    fn from(s: StudyArg) -> Study {
        match s {
            StudyArg::Spacing => Study::Spacing,
            StudyArg::Horizon => Study::Horizon,
            StudyArg::Timestep => Study::Timestep,
        }
    }
}

/// `sweep --case`: the sweep has one problem so far.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub(crate) enum SweepProblem {
    Sphere,
}

/// `sweep --set`: and one scene set.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub(crate) enum SweepSet {
    Hertz,
}

/// A horizon factor as a scene takes it: at least 1 (a horizon shorter than the spacing
/// holds no bonds), finite.
pub(crate) fn parse_horizon_factor(s: &str) -> Result<f64, String> {
    let m: f64 = s
        .parse()
        .map_err(|_| format!("expected a number, found '{s}'"))?;
    if m.is_finite() && m >= 1.0 {
        Ok(m)
    } else {
        Err(format!(
            "the horizon factor must be at least 1 (a horizon shorter than the spacing holds no bonds), got {s}"
        ))
    }
}

pub(crate) fn parse_format(s: &str) -> Result<Format, String> {
    Format::from_name(s).ok_or_else(|| format!("unknown format '{s}': use cdb, msh or inp"))
}

/// `friction --case`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum FrictionCase {
    /// A sphere pressed, then pushed sideways: the stick radius and shear traction against
    /// Cattaneo-Mindlin.
    Mindlin,
    /// A block on a tilted plane: at rest for tan θ ≤ μ, else g (sin θ − μ cos θ).
    Sliding,
}

/// `fracture --solver` (the notched beam).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum BeamSolver {
    /// Adaptive dynamic relaxation, bonds tested at every iteration.
    Adr,
    /// Newton's method, bonds tested near each equilibrium.
    Static,
}

/// `fracture --failure` (the notched beam).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum BeamFailure {
    /// The stretch alone (Silling & Askari 2005).
    Stretch,
    /// The stretch, where a tension along the bond stretched it.
    Tension,
}

/// `fracture --case`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum FractureCase {
    /// A notched three-point bend beam broken under displacement control, against LEFM.
    Beam,
    /// The Kalthoff-Winkler plate hit between its notches at 32 m/s (explicit).
    Kalthoff,
    /// A block cut through and compressed, the cut's faces pressed together, against the
    /// block whole; and the block cut at 30° to the load.
    Closing,
    /// A steel ball fired at 100 m/s through a brittle plate (explicit): fragments, how deep
    /// one went into another, the energy balance.
    Perforation,
}
