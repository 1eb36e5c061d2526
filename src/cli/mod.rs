//! The command line: its arguments parsed ([`args`]), then checked and run through [`crate::run`],
//! [`crate::convert`] and the studies. The binaries are shells over [`main`]: `pdcontact`, and
//! `pdcontact-mpi` (the `pdcontact-mpi` package), which starts MPI when a launcher started it
//! as several processes and hands [`main`] the world communicator.

use std::process::ExitCode;

use crate::case::{CaseOptions, DEFAULT_HORIZON_FACTOR};
use crate::importers::MeshSummary;
use crate::parallel::Comm;
use crate::run::{run_scene, RunOptions};
use crate::scene::Scene;
use crate::studies::bench::LATTICE_HORIZON_FACTOR;
use crate::studies::scenarios::Problem;
use crate::studies::validate;
use crate::Error;
use clap::{CommandFactory, FromArgMatches};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

mod args;
use args::*;

/// Exit code of a run stopped by Ctrl-C or SIGTERM (128 + SIGINT, as shells report Ctrl-C).
const EXIT_INTERRUPTED: u8 = 130;

/// How a command ended without an error.
enum Outcome {
    Done,
    /// A run stopped by Ctrl-C or SIGTERM: its frames so far are complete and listed.
    Interrupted,
}

fn interrupted(summary: &crate::run::RunSummary) -> Outcome {
    if summary.interrupted {
        eprintln!(
            "interrupted at step {}: frames so far in {}, summary in {}",
            // A static run's steps number its Newton and ADR iterations together.
            summary.iterations + summary.solver.relaxation_iterations,
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
                Error::Import(crate::importers::ImportError::whole_file(
                    &file,
                    "a readable file",
                    e.to_string(),
                ))
            })?;
            let format = match format {
                Some(f) => f,
                None => crate::importers::detect_format(&file, &data)?,
            };
            let mesh = crate::importers::read_format(&file, &data, format)?;
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
            let (_, summary) = crate::convert::convert(&mesh, format, &output, options)?;
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
                study: false,
            };
            let report = crate::studies::demo::run_demo(&output, &options)?;
            print_report(json, &report, || report.to_text());
            Ok(interrupted(&report.summary))
        }
        Command::Fracture {
            case,
            spacing,
            plate_mesh,
            beam_mesh,
            solver,
            thickness,
            lps,
            failure,
            displacement,
            steps,
            output,
            json,
            quiet,
        } => {
            if lps.is_some() && case != FractureCase::Beam {
                return Err(Error::input(
                    "--lps applies to the notched beam (--case beam)",
                ));
            }
            let spacing = spacing.unwrap_or(match case {
                FractureCase::Beam => 0.002,
                FractureCase::Kalthoff => 0.0015,
                FractureCase::Closing => 0.05,
                FractureCase::Perforation => 0.0005,
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
                let r = crate::studies::fracture::run_closing(spacing, &output, quiet)?;
                print_report(json, &r, || r.to_text());
                return Ok(Outcome::Done);
            }
            if plate_mesh.is_some() && case != FractureCase::Perforation {
                return Err(Error::input(
                    "--plate-mesh is the perforated plate's (--case perforation)",
                ));
            }
            if beam_mesh.is_some() && case != FractureCase::Beam {
                return Err(Error::input(
                    "--beam-mesh is the notched beam's (--case beam)",
                ));
            }
            if case == FractureCase::Perforation {
                let r = crate::studies::fracture::run_perforation(
                    spacing,
                    plate_mesh.as_deref(),
                    500,
                    &output,
                    quiet,
                )?;
                print_report(json, &r, || r.to_text());
                return Ok(Outcome::Done);
            }
            if case == FractureCase::Kalthoff {
                let plate = crate::studies::fracture::KalthoffPlate {
                    spacing,
                    end_time: crate::studies::fracture::kalthoff::END_TIME,
                };
                let r = crate::studies::fracture::run_kalthoff(&plate, &output, quiet)?;
                print_report(json, &r, || r.to_text());
                return Ok(Outcome::Done);
            }
            let beam = crate::studies::fracture::NotchedBeam {
                spacing,
                thickness,
                displacement,
                steps,
                mesh: beam_mesh,
                static_solver: solver == BeamSolver::Static,
                lps_poisson: lps,
                failure: match failure {
                    BeamFailure::Stretch => crate::scene::FailureCriterion::Stretch,
                    BeamFailure::Tension => crate::scene::FailureCriterion::Tension,
                },
            };
            let r = crate::studies::fracture::run_beam(&beam, &output, quiet)?;
            print_report(json, &r, || r.to_text());
            Ok(Outcome::Done)
        }
        Command::Friction {
            case,
            spacing,
            contact_radius,
            friction,
            slope,
            push,
            steps,
            rigid_flat,
            solver,
            sphere_mesh,
            block_mesh,
            output,
            json,
            quiet,
        } => {
            use crate::studies::friction as f;
            if !(contact_radius > 0.0 && contact_radius < 0.5) {
                return Err(Error::input(format!(
                    "--contact-radius must lie between 0 and 0.5 m (the sphere's radius is 1 m), got {contact_radius}"
                )));
            }
            let spacing = spacing.unwrap_or(match case {
                FrictionCase::Mindlin => contact_radius / 5.0,
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
                contact_radius,
                spacing,
                friction,
                push: 0.0,
                steps,
                rigid_flat,
                static_solver: solver == SolverArg::Static,
                meshes: None,
            };
            if let (Some(sphere), Some(block)) = (sphere_mesh, block_mesh) {
                // Absolute: the scene is written into the output folder and read from there.
                let absolute = |p: std::path::PathBuf| {
                    std::fs::canonicalize(&p)
                        .map_err(|e| Error::input(format!("cannot read mesh {}: {e}", p.display())))
                };
                scene.meshes = Some((absolute(sphere)?, absolute(block)?));
            }
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
                let report = crate::studies::user_mesh::validate_mesh(
                    &mesh,
                    format,
                    problem,
                    contact_ratio,
                    &crate::studies::user_mesh::BodyChoices {
                        horizon_factor,
                        second_order: second_order.map(Into::into).unwrap_or_default(),
                        refine: refine.unwrap_or(0),
                        skin_correction,
                        static_solver,
                        poisson,
                        influence: influence.map(|i| match i {
                            InfluenceArg::Constant => crate::scene::InfluenceFunction::Constant,
                            InfluenceArg::PositionAware => {
                                crate::scene::InfluenceFunction::PositionAware
                            }
                        }),
                        partner: match partner {
                            PartnerArg::Plane => crate::studies::user_mesh::Partner::Plane,
                            PartnerArg::Copy => crate::studies::user_mesh::Partner::Copy,
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
                Err(crate::Error::numerical(format!(
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
            fe,
        } => {
            if stability {
                let runs = crate::studies::stability::run_stability(&output, quiet)?;
                print_report(json, &runs, || crate::studies::stability::table(&runs));
                return Ok(Outcome::Done);
            }
            // One problem and one set so far: clap has refused any other.
            let (SweepProblem::Sphere, SweepSet::Hertz) = (case, set);
            let fe = match &fe {
                Some(path) => crate::studies::sweep::read_fe_points(path)?,
                None => crate::studies::sweep::stored_fe_points(),
            };
            let runs = crate::studies::sweep::run_sweep(
                crate::studies::sweep::sphere_grid(),
                &output,
                quiet,
                &fe,
            )?;
            print_report(json, &runs, || crate::studies::sweep::table(&runs));
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
                let scene = crate::scene::Scene::load(&scene)?;
                let report = crate::studies::bench::run_adr(&scene, steps, threads)?;
                print_report(json, &report, || report.to_text());
                return Ok(Outcome::Done);
            }
            if let Some(mesh) = pipeline {
                let options = crate::case::CaseOptions {
                    spacing,
                    horizon_factor: horizon_factor.unwrap_or(DEFAULT_HORIZON_FACTOR),
                    ..Default::default()
                };
                let report = crate::studies::bench::run_pipeline(&mesh, options, threads)?;
                print_report(json, &report, || report.to_text());
                return Ok(Outcome::Done);
            }
            let Some(lattice_sphere) = lattice_sphere else {
                return Err(crate::Error::input(
                    "bench needs --lattice-sphere DX or --adr SCENE",
                ));
            };
            let spec = crate::studies::bench::LatticeSphere {
                spacing: lattice_sphere,
                horizon_factor: horizon_factor.unwrap_or(LATTICE_HORIZON_FACTOR),
                steps,
                threads,
            };
            let report = crate::studies::bench::run_lattice_sphere(&spec, comm.as_deref())?;
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
                let (model, warnings, _) = crate::run::check_scene(&scene)?;
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
                study: false,
            };
            let (model, summary) = run_scene(&scene, &options)?;
            if model.rank() != 0 {
                return Ok(Outcome::Done);
            }
            if json {
                println!("{}", to_json(&summary));
            } else if !quiet {
                eprintln!("{}", summary.result_line());
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
                 of the machine through threads; RAYON_NUM_THREADS sets how many), or run \
                 `pdcontact-mpi` (`cargo build --release -p pdcontact-mpi`; docs/guide/mpi.md), \
                 which decomposes a run over the processes"
            ));
                (number(rank_var).unwrap_or(0), error)
            })
        })
}

/// How a binary starts MPI when a launcher started it as several processes: the world
/// communicator, which finalises MPI when its last reference is dropped, or why it could not.
pub type StartMpi = fn() -> Result<Arc<dyn Comm>, String>;

/// The whole command line: arguments parsed, the command run, its error printed, the exit
/// code returned. `start_mpi` is `None` in a binary built without MPI: started by `mpirun`
/// as several processes, it then refuses rather than run the whole job in each.
pub fn main(start_mpi: Option<StartMpi>) -> ExitCode {
    // Help and usage name the binary that runs: `pdcontact-mpi` is the MPI build's.
    let name = if start_mpi.is_some() {
        "pdcontact-mpi"
    } else {
        "pdcontact"
    };
    let cli = match Cli::from_arg_matches(&Cli::command().name(name).bin_name(name).get_matches()) {
        Ok(cli) => cli,
        Err(e) => e.exit(),
    };
    // The main thread one of the pool's threads: a parallel loop it starts is then a job
    // of its own worker, not one sent to another thread while it sleeps on a lock (on a
    // 2-core VM that handover cost ~0.1 ms a loop: the static solver's linear iterations
    // spent a third of their time in it; docs/PERFORMANCE.md, "The main thread in the pool,
    // and boxes of 200 particles"). If a pool exists already (it cannot here), the default
    // one serves.
    let _ = rayon::ThreadPoolBuilder::new()
        .use_current_thread()
        .build_global();
    let comm: Option<Arc<dyn Comm>> = match (several_mpi_copies(), start_mpi) {
        (None, _) => None,
        // Built with MPI and started as several processes: the run is decomposed over them.
        (Some(_), Some(start)) => match start() {
            Ok(world) => Some(world),
            Err(why) => {
                eprintln!("error: MPI could not be initialised: {why}");
                return ExitCode::from(1);
            }
        },
        (Some((rank, e)), None) => {
            // Said once, by the first rank; every rank stops.
            if rank == 0 {
                eprintln!("error: {e}");
            }
            return ExitCode::from(e.exit_code() as u8);
        }
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
