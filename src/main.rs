//! The `pdcontact` command line: a thin shell over the library.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};
use pdcontact::case::{CaseOptions, SecondOrder, DEFAULT_HORIZON_FACTOR};
use pdcontact::importers::{Format, MeshSummary};
use pdcontact::parallel::Comm;
use pdcontact::run::{run_scene, RunOptions};
use pdcontact::scene::Scene;
use pdcontact::studies::bench::LATTICE_HORIZON_FACTOR;
use pdcontact::studies::scenarios::{Problem, Set};
use pdcontact::studies::validate::{self, Study};
use pdcontact::Error;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// Peridynamic point-to-surface contact from finite-element meshes.
#[derive(Parser, Debug)]
#[command(name = "pdcontact", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
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
        #[arg(long, default_value_t = DEFAULT_HORIZON_FACTOR)]
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
        #[arg(long, value_name = "A_OVER_R", default_value_t = pdcontact::studies::user_mesh::CONTACT_RATIO, requires = "mesh")]
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
        /// The quasi-static solver: adaptive dynamic relaxation (adr, the default) or
        /// Newton-Raphson (static; docs/PERFORMANCE.md, "The static solver"), written into
        /// each scene. Not with --study
        #[arg(long, value_enum, default_value_t = SolverArg::Adr, conflicts_with = "study")]
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
        /// deep; 0.0015 for the plate; 0.05 for the cracked block].
        #[arg(long)]
        spacing: Option<f64>,
        /// The beam's thickness B, m.
        #[arg(long, default_value_t = 0.008)]
        thickness: f64,
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
        /// Grid spacing Δ, m [default: 0.03 for the sphere (a/Δ = 5), 0.01 for the block].
        #[arg(long)]
        spacing: Option<f64>,
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
enum ProblemArg {
    Sphere,
    Roller,
    Punch,
    All,
}

impl ProblemArg {
    fn problems(self) -> Vec<Problem> {
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
enum SolverArg {
    /// Adaptive dynamic relaxation.
    Adr,
    /// Newton-Raphson with a matrix-free tangent.
    Static,
}

/// `validate --influence`: the LPS's influence function.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum InfluenceArg {
    /// ω = 1, a factor per particle (the default).
    Constant,
    /// Position-aware: each particle's energy the continuum's under any uniform strain.
    PositionAware,
}

/// `validate --partner`: what the mesh is pressed on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum PartnerArg {
    /// A rigid plane.
    Plane,
    /// A copy of the mesh (two deformable bodies).
    Copy,
}

/// `validate --second-order`: which nodes of a second-order mesh become particles.
#[derive(Clone, Copy, Debug, ValueEnum)]
enum SecondOrderArg {
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
enum SetArg {
    Paper,
    Hertz,
    All,
}

impl SetArg {
    fn sets(self) -> Vec<Set> {
        match self {
            SetArg::Paper => vec![Set::Paper],
            SetArg::Hertz => vec![Set::Hertz],
            SetArg::All => vec![Set::Hertz, Set::Paper],
        }
    }
}

/// `validate --study`: the convergence studies.
#[derive(Clone, Copy, Debug, ValueEnum)]
enum StudyArg {
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
enum SweepProblem {
    Sphere,
}

/// `sweep --set`: and one scene set.
#[derive(Clone, Copy, Debug, ValueEnum)]
enum SweepSet {
    Hertz,
}

fn parse_format(s: &str) -> Result<Format, String> {
    Format::from_name(s).ok_or_else(|| format!("unknown format '{s}': use cdb, msh or inp"))
}

/// Exit code of a run stopped by Ctrl-C or SIGTERM (128 + SIGINT, as shells report Ctrl-C).
const EXIT_INTERRUPTED: u8 = 130;

/// `friction --case`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum FrictionCase {
    /// A sphere pressed, then pushed sideways: the stick radius and shear traction against
    /// Cattaneo-Mindlin.
    Mindlin,
    /// A block on a tilted plane: at rest for tan θ ≤ μ, else g (sin θ − μ cos θ).
    Sliding,
}

/// `fracture --case`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum FractureCase {
    /// A notched three-point bend beam broken under displacement control, against LEFM.
    Beam,
    /// The Kalthoff-Winkler plate hit between its notches at 32 m/s (explicit).
    Kalthoff,
    /// A block cut through and compressed, the cut's faces pressed together, against the
    /// block whole; and the block cut at 30° to the load.
    Closing,
}

/// How a command ended without an error.
enum Outcome {
    Done,
    /// A run stopped by Ctrl-C or SIGTERM: its frames so far are complete and listed.
    Interrupted,
}

fn interrupted(summary: &pdcontact::run::RunSummary) -> Outcome {
    if summary.interrupted {
        eprintln!(
            "interrupted at step {}: frames so far in {}, summary in {}",
            summary.iterations,
            summary.outputs.pvd.display(),
            summary.outputs.summary.display()
        );
        Outcome::Interrupted
    } else {
        Outcome::Done
    }
}

fn run(cli: Cli, comm: Option<Arc<dyn Comm>>) -> Result<Outcome, Error> {
    let decomposed = matches!(cli.command, Command::Run { check: false, .. })
        || matches!(
            cli.command,
            Command::Bench {
                lattice_sphere: Some(_),
                ..
            }
        );
    if comm.is_some() && !decomposed {
        return Err(Error::input(
            "under mpirun only `pdcontact run SCENE` and `pdcontact bench --lattice-sphere DX` run over several processes: run the other commands once, without mpirun",
        ));
    }
    match cli.command {
        Command::Inspect { file, format, json } => {
            let data = std::fs::read(&file).map_err(|e| {
                Error::Import(pdcontact::importers::ImportError::whole_file(
                    &file,
                    "a readable file",
                    e.to_string(),
                ))
            })?;
            let format = match format {
                Some(f) => f,
                None => pdcontact::importers::detect_format(&file, &data)?,
            };
            let mesh = pdcontact::importers::read_format(&file, &data, format)?;
            let summary = MeshSummary::of(&mesh, format);
            print_report(json, &summary, || {
                summary.to_text(&file.display().to_string())
            });
            Ok(Outcome::Done)
        }
        Command::Convert {
            mesh,
            output,
            spacing,
            horizon_factor,
            second_order,
            refine,
            format,
            json,
            quiet,
        } => {
            let options = CaseOptions {
                spacing,
                horizon_factor,
                second_order: second_order.map(Into::into).unwrap_or_default(),
                refine,
                ..Default::default()
            };
            let (_, summary) = pdcontact::convert::convert(&mesh, format, &output, options)?;
            if !quiet {
                for w in &summary.warnings {
                    eprintln!("warning: {w}");
                }
            }
            print_report(json, &summary, || {
                format!("{}wrote {}\n", summary.to_text(), output.display())
            });
            Ok(Outcome::Done)
        }
        Command::Demo {
            output,
            json,
            quiet,
        } => {
            let options = RunOptions {
                output: None,
                quiet,
                stop: Some(stop_flag()),
                comm: None,
            };
            let report = pdcontact::studies::demo::run_demo(&output, &options)?;
            print_report(json, &report, || report.to_text());
            Ok(interrupted(&report.summary))
        }
        Command::Fracture {
            case,
            spacing,
            thickness,
            displacement,
            steps,
            output,
            json,
            quiet,
        } => {
            let spacing = spacing.unwrap_or(match case {
                FractureCase::Beam => 0.002,
                FractureCase::Kalthoff => 0.0015,
                FractureCase::Closing => 0.05,
            });
            for (what, v) in [
                ("--spacing", spacing),
                ("--thickness", thickness),
                ("--displacement", displacement),
            ] {
                if !(v > 0.0 && v.is_finite()) {
                    return Err(Error::input(format!("{what} must be positive, got {v}")));
                }
            }
            if steps == 0 {
                return Err(Error::input("--steps must be at least 1"));
            }
            if case == FractureCase::Closing {
                let r = pdcontact::studies::fracture::run_closing(spacing, &output, quiet)?;
                print_report(json, &r, || r.to_text());
                return Ok(Outcome::Done);
            }
            if case == FractureCase::Kalthoff {
                let plate = pdcontact::studies::fracture::KalthoffPlate {
                    spacing,
                    end_time: pdcontact::studies::fracture::kalthoff::END_TIME,
                };
                let r = pdcontact::studies::fracture::run_kalthoff(&plate, &output, quiet)?;
                print_report(json, &r, || r.to_text());
                return Ok(Outcome::Done);
            }
            let beam = pdcontact::studies::fracture::NotchedBeam {
                spacing,
                thickness,
                displacement,
                steps,
            };
            let r = pdcontact::studies::fracture::run_beam(&beam, &output, quiet)?;
            print_report(json, &r, || r.to_text());
            Ok(Outcome::Done)
        }
        Command::Friction {
            case,
            spacing,
            friction,
            slope,
            push,
            steps,
            rigid_flat,
            output,
            json,
            quiet,
        } => {
            use pdcontact::studies::friction as f;
            let spacing = spacing.unwrap_or(match case {
                FrictionCase::Mindlin => 0.03,
                FrictionCase::Sliding => 0.01,
            });
            if !(spacing > 0.0 && spacing.is_finite()) {
                return Err(Error::input(format!(
                    "--spacing must be positive, got {spacing}"
                )));
            }
            if !(friction > 0.0 && friction.is_finite()) || steps == 0 {
                return Err(Error::input(format!(
                    "--friction must be positive (got {friction}) and --steps at least 1 (got {steps})"
                )));
            }
            if let Some(bad) = slope.iter().find(|t| !(t.is_finite() && **t >= 0.0)) {
                return Err(Error::input(format!(
                    "--slope takes tan θ of each slope, 0 or positive, got {bad}"
                )));
            }
            if case == FrictionCase::Sliding {
                let mut rows = Vec::new();
                for (k, &slope) in slope.iter().enumerate() {
                    let block = f::SlidingBlock {
                        slope,
                        friction,
                        spacing,
                        end_time: 0.1,
                    };
                    let r = f::run_sliding(&block, &output.join(format!("slope_{k}")), quiet)?;
                    if !json {
                        print!("{}", r.to_text());
                    }
                    rows.push(r);
                }
                if json {
                    print_report(true, &rows, String::new);
                }
                return Ok(Outcome::Done);
            }
            let mut scene = f::MindlinScene {
                contact_radius: 0.15,
                spacing,
                friction,
                push: 0.0,
                steps,
                rigid_flat,
            };
            scene.push = push * scene.full_slip_travel();
            let r = f::run_mindlin(&scene, &output, quiet)?;
            print_report(json, &r, || r.to_text());
            Ok(Outcome::Done)
        }
        Command::Validate {
            case,
            set,
            study,
            mesh,
            format,
            contact_ratio,
            horizon_factor,
            second_order,
            refine,
            skin_correction,
            solver,
            partner,
            poisson,
            influence,
            output,
            json,
            quiet,
        } => {
            let static_solver = solver == SolverArg::Static;
            if let Some(mesh) = mesh {
                let problem = match case.unwrap_or(ProblemArg::Sphere) {
                    ProblemArg::Sphere => Problem::Sphere,
                    ProblemArg::Roller if partner == PartnerArg::Copy => {
                        return Err(Error::input(
                            "validate --mesh --partner copy presses a sphere on its copy; a roller on its copy is not offered yet: use --case sphere, or --partner plane",
                        ))
                    }
                    ProblemArg::Roller => Problem::Roller,
                    ProblemArg::Punch | ProblemArg::All => {
                        return Err(Error::input(
                            "validate --mesh runs the Hertz sphere or roller: use --case sphere or --case roller",
                        ))
                    }
                };
                let report = pdcontact::studies::user_mesh::validate_mesh(
                    &mesh,
                    format,
                    problem,
                    contact_ratio,
                    &pdcontact::studies::user_mesh::BodyChoices {
                        horizon_factor,
                        second_order: second_order.map(Into::into).unwrap_or_default(),
                        refine: refine.unwrap_or(0),
                        skin_correction,
                        static_solver,
                        poisson,
                        influence: influence.map(|i| match i {
                            InfluenceArg::Constant => pdcontact::scene::InfluenceFunction::Constant,
                            InfluenceArg::PositionAware => {
                                pdcontact::scene::InfluenceFunction::PositionAware
                            }
                        }),
                        partner: match partner {
                            PartnerArg::Plane => pdcontact::studies::user_mesh::Partner::Plane,
                            PartnerArg::Copy => pdcontact::studies::user_mesh::Partner::Copy,
                        },
                        compare: refine.is_none()
                            && second_order.is_none()
                            && horizon_factor.is_none(),
                    },
                    &output,
                    quiet,
                )?;
                print_report(json, &report, || report.to_text());
                return Ok(Outcome::Done);
            }
            let case = case.unwrap_or(ProblemArg::All);
            let selection = match study {
                Some(s) => validate::run_study(s.into(), &output, quiet)?,
                None => validate::run_selection(
                    &case.problems(),
                    &set.sets(),
                    skin_correction,
                    static_solver,
                    &output,
                    quiet,
                )?,
            };
            print_report(json, &selection.rows, || validate::table(&selection.rows));
            for f in &selection.failures {
                eprintln!("error: {f}");
            }
            if selection.failures.is_empty() {
                Ok(Outcome::Done)
            } else {
                Err(pdcontact::Error::numerical(format!(
                    "{} of the validation cases failed",
                    selection.failures.len()
                )))
            }
        }
        Command::Sweep {
            case,
            set,
            output,
            json,
            quiet,
            stability,
        } => {
            if stability {
                let runs = pdcontact::studies::stability::run_stability(&output, quiet)?;
                print_report(json, &runs, || pdcontact::studies::stability::table(&runs));
                return Ok(Outcome::Done);
            }
            // One problem and one set so far: clap has refused any other.
            let (SweepProblem::Sphere, SweepSet::Hertz) = (case, set);
            let runs = pdcontact::studies::sweep::run_sweep(
                pdcontact::studies::sweep::sphere_grid(),
                &output,
                quiet,
            )?;
            print_report(json, &runs, || pdcontact::studies::sweep::table(&runs));
            Ok(Outcome::Done)
        }
        Command::Bench {
            lattice_sphere,
            adr,
            pipeline,
            spacing,
            horizon_factor,
            steps,
            threads,
            json,
        } => {
            if let Some(scene) = adr {
                let scene = pdcontact::scene::Scene::load(&scene)?;
                let report = pdcontact::studies::bench::run_adr(&scene, steps, threads)?;
                print_report(json, &report, || report.to_text());
                return Ok(Outcome::Done);
            }
            if let Some(mesh) = pipeline {
                let options = pdcontact::case::CaseOptions {
                    spacing,
                    horizon_factor: horizon_factor.unwrap_or(DEFAULT_HORIZON_FACTOR),
                    ..Default::default()
                };
                let report = pdcontact::studies::bench::run_pipeline(&mesh, options, threads)?;
                print_report(json, &report, || report.to_text());
                return Ok(Outcome::Done);
            }
            let Some(lattice_sphere) = lattice_sphere else {
                return Err(pdcontact::Error::input(
                    "bench needs --lattice-sphere DX or --adr SCENE",
                ));
            };
            let spec = pdcontact::studies::bench::LatticeSphere {
                spacing: lattice_sphere,
                horizon_factor: horizon_factor.unwrap_or(LATTICE_HORIZON_FACTOR),
                steps,
                threads,
            };
            let report = pdcontact::studies::bench::run_lattice_sphere(&spec, comm.as_deref())?;
            // Under mpirun the first rank speaks for all.
            if comm.as_ref().is_none_or(|c| c.rank() == 0) {
                print_report(json, &report, || report.to_text(&spec));
            }
            Ok(Outcome::Done)
        }
        Command::Run {
            scene,
            output,
            json,
            quiet,
            check,
        } => {
            let scene = Scene::load(&scene)?;
            if check {
                let (model, warnings, _) = pdcontact::run::check_scene(&scene)?;
                if !quiet {
                    for w in &warnings {
                        eprintln!("warning: {w}");
                    }
                    eprintln!(
                        "{}: ok ({} particles, {} bonds)",
                        scene.source,
                        model.particles(),
                        model.bonds()
                    );
                }
                return Ok(Outcome::Done);
            }
            let options = RunOptions {
                output,
                quiet,
                stop: Some(stop_flag()),
                comm,
            };
            let (model, summary) = run_scene(&scene, &options)?;
            if model.rank() != 0 {
                return Ok(Outcome::Done);
            }
            if json {
                println!("{}", to_json(&summary));
            } else if !quiet {
                eprintln!(
                    "{} iterations, residual {:.3e}, {} contacts, force balance error {:.3e}, {:.1} s; frames in {}",
                    summary.iterations,
                    summary.residual,
                    summary.contact_pairs,
                    summary.force_balance_error,
                    summary.wall_seconds,
                    summary.outputs.pvd.display()
                );
                if let Some(a) = &summary.accuracy {
                    eprintln!("{}", a.line());
                }
            }
            Ok(interrupted(&summary))
        }
    }
}

fn stop_flag() -> Arc<AtomicBool> {
    let flag = Arc::new(AtomicBool::new(false));
    let f = flag.clone();
    // Ctrl-C / SIGTERM: finish the current frame, close the .pvd, exit.
    let _ = ctrlc::set_handler(move || f.store(true, Ordering::Relaxed));
    flag
}

/// Prints `value` as JSON on stdout with `--json`, else its text.
fn print_report<T: serde::Serialize>(json: bool, value: &T, text: impl FnOnce() -> String) {
    if json {
        println!("{}", to_json(value));
    } else {
        print!("{}", text());
    }
}

fn to_json<T: serde::Serialize>(v: &T) -> String {
    serde_json::to_string_pretty(v).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
}

/// How MPI launchers (`mpirun`, `mpiexec`) tell each process the job's size and its rank.
const MPI_LAUNCHERS: [(&str, &str, &str); 3] = [
    ("Open MPI", "OMPI_COMM_WORLD_SIZE", "OMPI_COMM_WORLD_RANK"),
    ("MPICH or Intel MPI", "PMI_SIZE", "PMI_RANK"),
    ("MVAPICH", "MV2_COMM_WORLD_SIZE", "MV2_COMM_WORLD_RANK"),
];

/// This process's rank when an MPI launcher started several copies of it, with the error to
/// stop on: a one-process build run N times would run the whole scene N times, racing on one
/// output folder.
fn several_mpi_copies() -> Option<(usize, Error)> {
    let number = |var: &str| std::env::var(var).ok()?.trim().parse::<usize>().ok();
    MPI_LAUNCHERS
        .iter()
        .find_map(|&(launcher, size_var, rank_var)| {
            let size = number(size_var)?;
            (size > 1).then(|| {
                let error = Error::input(format!(
                "started by an MPI launcher as {size} processes ({launcher}: {size_var}={size}), \
                 but this pdcontact was built without MPI: each copy would run the whole job and \
                 write the same output folder. Run it once, without mpirun (it uses every core \
                 of the machine through threads; RAYON_NUM_THREADS sets how many), or build it \
                 with `cargo build --release --features mpi` to decompose a run over the processes"
            ));
                (number(rank_var).unwrap_or(0), error)
            })
        })
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let launched = several_mpi_copies();
    // Built with MPI and started as several processes: the run is decomposed over them.
    #[cfg(feature = "mpi")]
    let (_universe, comm) = match launched {
        Some(_) => match mpi::initialize() {
            Some(universe) => {
                let world: Arc<dyn Comm> =
                    Arc::new(pdcontact::parallel::mpi::MpiComm::world(universe.world()));
                (Some(universe), Some(world))
            }
            None => {
                eprintln!("error: MPI could not be initialised");
                return ExitCode::from(1);
            }
        },
        None => (None, None),
    };
    #[cfg(not(feature = "mpi"))]
    let comm: Option<Arc<dyn Comm>> = match launched {
        Some((rank, e)) => {
            // Said once, by the first rank; every rank stops.
            if rank == 0 {
                eprintln!("error: {e}");
            }
            return ExitCode::from(e.exit_code() as u8);
        }
        None => None,
    };
    match run(cli, comm.clone()) {
        Ok(Outcome::Done) => ExitCode::SUCCESS,
        Ok(Outcome::Interrupted) => ExitCode::from(EXIT_INTERRUPTED),
        Err(e) => {
            match comm {
                // Every rank reads the same input and reduces the same figures, so they fail
                // alike and the first says why; a frame or summary that cannot be written
                // fails on the first rank alone, which stops the others.
                Some(c) => {
                    if matches!(e, Error::Output { .. }) {
                        eprintln!("error (rank {}): {e}", c.rank());
                        c.abort(e.exit_code());
                    }
                    if c.rank() == 0 {
                        eprintln!("error: {e}");
                    }
                }
                None => eprintln!("error: {e}"),
            }
            ExitCode::from(e.exit_code() as u8)
        }
    }
}
