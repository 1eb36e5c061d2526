//! `pdcontact run`: a scene from file to frames and a `summary.json`; `checks.rs`: what is
//! refused once the model is built, before solving; `report.rs`: what a run says after it
//! (its contact against the estimate, bodies that drifted).

mod checks;
mod damping;
mod held;
pub mod report;
mod units;

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Instant;

use serde::Serialize;

use crate::body::{Body, PdBody};
use crate::contact::estimate::ContactResolution;
use crate::error::{Error, Result};
use crate::math::Vec3;
use crate::model::domain::Layout;
use crate::model::Model;
use crate::output::analysis::{contact_patch, fit_elliptic};
use crate::output::vtk::write_atomically;
use crate::output::{FrameWriter, RunMonitor};
use crate::parallel::Comm;
use crate::scene::{Motion, Scene, SolverKind};
use crate::solver::{solve, Monitor, RunStats};

/// Options of a run.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Output folder (default: the scene's `output.folder`).
    pub output: Option<PathBuf>,
    /// No progress on stderr.
    pub quiet: bool,
    /// Raised by Ctrl-C / SIGTERM: finish the current frame and stop.
    pub stop: Option<Arc<AtomicBool>>,
    /// The processes of an MPI run (`mpirun -n N pdcontact-mpi`): the
    /// model is decomposed over them ([`crate::model::domain`]); rank 0 prints and writes.
    pub comm: Option<Arc<dyn Comm>>,
    /// The scene was written by a study (`validate`), with a load, a penalty and a solver of
    /// its own choosing: the warnings on those values (the contact's spacings, strain and
    /// penalty, the solver's options) are the study's to give, in its own terms, and would
    /// send the user to change values they never wrote. The run then prints only what it
    /// found in the meshes; `summary.json` keeps every warning.
    pub study: bool,
}

/// Output paths of a run.
#[derive(Clone, Debug, Serialize)]
pub struct Outputs {
    pub pvd: PathBuf,
    pub last_frame: Option<PathBuf>,
    pub summary: PathBuf,
}

/// `summary.json`.
#[derive(Clone, Debug, Serialize)]
pub struct RunSummary {
    pub scene: String,
    /// Warnings about the meshes (skipped element types, unused or duplicate nodes,
    /// disconnected pieces), prefixed with the body's name, then solver options that the
    /// chosen solver ignores (`tolerance` in an explicit run, `dt` in ADR), then about the
    /// contacts (a
    /// contact expected to span fewer than 3 particle spacings, uneven tributary areas where
    /// it will be), prefixed with the pair; last, what the run found ([`report::drift_warnings`]:
    /// a body that slid or rolled).
    pub warnings: Vec<String>,
    /// The run's contact against the estimate's, where it applies (one pair, a circular point
    /// contact): [`report::AccuracyCheck`].
    pub accuracy: Option<report::AccuracyCheck>,
    /// Per contact pair: the Hertz estimate of its contact under the loads, the slave's
    /// particle spacing and tributary-area ratio there ([`crate::contact::estimate`]).
    pub contact_estimates: Vec<ContactResolution>,
    pub particles: usize,
    pub bonds: usize,
    pub iterations: usize,
    pub converged: bool,
    pub residual: f64,
    pub wall_seconds: f64,
    /// Of `wall_seconds`, the solver's loop (iterations or steps and the frames written
    /// during it); the rest is reading the meshes and building the model.
    pub solve_seconds: f64,
    /// The process's peak resident memory (`VmHWM`), MB, up to the summary (under `mpirun`:
    /// rank 0's; every rank's in `decomposition`); null where the system does not say.
    pub peak_memory_mb: Option<f64>,
    pub verlet_rebuilds: usize,
    pub contact_pairs: usize,
    pub missed_contacts: usize,
    /// Force exerted through contact by rigid bodies on deformable bodies (for scenes without
    /// rigid bodies: on the slave body of each contact pair, through both passes of a two-pass
    /// pair; a body pressed on itself exerts none on itself, so its own pairs are left out), N.
    pub total_contact_force: [f64; 3],
    /// Sum of the applied loads, N.
    pub applied_load: [f64; 3],
    /// `|Σ applied + Σ support reactions| / |Σ applied|`: the net out-of-balance force (along the
    /// axes that no symmetry plane cuts).
    pub force_balance_error: f64,
    /// Radius of a least-squares fit of `p0 √(1 − (r/a)²)` to the largest contact patch, m.
    pub contact_radius: f64,
    /// Largest contact pressure, Pa (per undeformed area).
    pub peak_pressure: f64,
    pub outputs: Outputs,
    pub solver: RunStats,
    /// The run was stopped by Ctrl-C or SIGTERM before it ended.
    pub interrupted: bool,
    /// Bodies whose bonds may fail or were cut by a pre-crack: what broke.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub fracture: Vec<report::FractureReport>,
    /// Bodies in a pair with friction: their tangential force and stick area.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub friction: Vec<report::FrictionReport>,
    /// Pairs with friction: the tangential force each puts on its slave body, and how much
    /// of its contact sticks.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub friction_pairs: Vec<report::FrictionPairReport>,
    /// A run over several MPI ranks: what each owned and received.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub decomposition: Option<Layout>,
    /// The error that stopped the run, if any.
    pub error: Option<String>,
}

impl RunSummary {
    /// The line `run` ends with: for a quasi-static run its iterations, residual, contacts
    /// and force balance; for an explicit one its steps and time, contacts and energy balance
    /// (the terms at the end against what the run started with, the work of fracture among
    /// them where bonds broke), and what broke.
    pub fn result_line(&self) -> String {
        let s = &self.solver;
        let head = match (&s.energy, s.solver.as_str()) {
            (Some([start, end]), "explicit") => {
                let mut terms = format!(
                    "kinetic {:.4e}, strain {:.4e}, contact {:.4e}",
                    end.kinetic, end.strain, end.contact
                );
                for (name, v) in [
                    ("work done", end.work),
                    ("dissipated", end.dissipated),
                    ("work of fracture", end.fracture),
                ] {
                    if v != 0.0 {
                        terms.push_str(&format!(", {name} {v:.4e}"));
                    }
                }
                format!(
                    "{} steps to t = {:.4e} s, {} contacts; energy {:.4e} J at the start, now {terms} J: drift {:.2} %",
                    self.iterations,
                    s.time,
                    self.contact_pairs,
                    start.total(),
                    100.0 * s.energy_drift
                )
            }
            _ => {
                let relaxed = match s.relaxation_iterations {
                    0 => String::new(),
                    n => format!(" (and {n} ADR iterations where Newton stalled)"),
                };
                format!(
                    "{} iterations{relaxed}, residual {:.3e}, {} contacts, force balance error {:.3e}",
                    self.iterations, self.residual, self.contact_pairs, self.force_balance_error
                )
            }
        };
        let broke: Vec<String> = self
            .fracture
            .iter()
            .filter(|f| f.broken_bonds > 0)
            .map(|f| {
                format!(
                    "\"{}\" {} bonds broken, {} pieces, {} particles on the surfaces they opened",
                    f.body, f.broken_bonds, f.fragments, f.new_surface_particles
                )
            })
            .collect();
        let broke = if broke.is_empty() {
            String::new()
        } else {
            format!("; {}", broke.join(", "))
        };
        let ranks = self
            .decomposition
            .as_ref()
            .map_or(String::new(), ranks_line);
        format!(
            "{head}{broke}{ranks}, {:.1} s; frames in {}",
            self.wall_seconds,
            self.outputs.pvd.display()
        )
    }
}

/// How a decomposed run was spread over its ranks, for `run`'s last line: each rank's peak
/// memory, its ghosts against the particles it owns and the bonds it holds against the
/// model's (`summary.json`'s `decomposition`).
fn ranks_line(d: &crate::model::domain::Layout) -> String {
    let range = |v: &[f64], digits: usize| {
        let (lo, hi) = v
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                (a.min(x), b.max(x))
            });
        if lo == hi {
            format!("{lo:.digits$}")
        } else {
            format!("{lo:.digits$}-{hi:.digits$}")
        }
    };
    let share: Vec<f64> = d
        .particles
        .iter()
        .zip(&d.ghosts)
        .map(|(&p, &g)| 100.0 * g as f64 / p.max(1) as f64)
        .collect();
    let memory: Vec<f64> = d.peak_memory_mb.iter().flatten().copied().collect();
    let memory = if memory.len() == d.ranks {
        format!("peak memory {} MB a rank, ", range(&memory, 0))
    } else {
        String::new()
    };
    let bonds: Vec<f64> = d
        .bonds
        .iter()
        .map(|&b| 100.0 * b as f64 / d.model_bonds.max(1) as f64)
        .collect();
    format!(
        "; {} ranks: {memory}ghosts {} % of a rank's particles, bonds held {} % of the model's",
        d.ranks,
        range(&share, 0),
        range(&bonds, 0)
    )
}

/// Reaction and balance figures of the current state.
pub fn force_balance(model: &Model) -> (Vec3, Vec3, f64) {
    let applied = model.applied_load();
    let mut contact = Vec3::zeros();
    let mut reactions = Vec3::zeros();
    let mut has_rigid = false;
    // Axes normal to a symmetry plane: the model's net force there is balanced by its images.
    let mut cut = [false; 3];
    for b in &model.bodies {
        match b {
            Body::Rigid(rb) => {
                has_rigid = true;
                contact -= rb.contact_force;
                if rb.motion != Motion::Free {
                    reactions -= rb.contact_force;
                } else {
                    // A free body's resistance off its axis is a support reaction too.
                    let f = rb.contact_force;
                    reactions -= f - rb.axis * f.dot(&rb.axis);
                }
            }
            Body::Deformable(pd) => {
                // Support reactions: the force the fixed components do not let move. Symmetry
                // planes are not supports: they carry the force between the model and its
                // mirror images.
                for ((f, &m), &s) in pd.force.iter().zip(&pd.fixed).zip(&pd.symmetric) {
                    let support = m & !s;
                    for a in 0..3 {
                        if support & (1 << a) != 0 {
                            reactions[a] -= f[a];
                        }
                    }
                }
                for plane in &pd.case.ghosts.planes {
                    cut[plane.axis] = true;
                }
            }
        }
    }
    if !has_rigid {
        // A body pressed on itself (its crack's faces, its pieces) pushes as much one way as
        // the other: its own contacts exert no force on it (`fracture[].precracks[]
        // .force_across` reads the force across a crack).
        for (k, p) in model.passes.iter().enumerate() {
            if p.slave == p.master {
                continue;
            }
            let on_slaves = model.slave_force(k);
            // The second pass of a two-pass pair pushes the pair's master: on the pair's
            // slave body it acts through its reactions, the opposite of its slave forces.
            let mirrored = model.passes[..k]
                .iter()
                .any(|q| q.slave == p.master && q.master == p.slave);
            if mirrored {
                contact -= on_slaves;
            } else {
                contact += on_slaves;
            }
        }
        for p in model.short_range.iter().filter(|p| p.slave != p.master) {
            contact += p.slave_force;
        }
    }
    let mut net = applied + reactions;
    for a in 0..3 {
        if cut[a] {
            net[a] = 0.0;
        }
    }
    // Measured against the loads body by body: two bodies loaded towards each other (a
    // sphere pressed on its copy) apply next to nothing in all.
    let scale: f64 = model
        .bodies
        .iter()
        .map(|b| match b {
            Body::Deformable(pd) => pd.load.iter().sum::<Vec3>().norm(),
            Body::Rigid(rb) => rb.load.norm(),
        })
        .sum();
    let error = if scale > 0.0 { net.norm() / scale } else { 0.0 };
    (contact, applied, error)
}

/// Contact radius and peak pressure of the body with the largest contact force.
fn patch_figures(model: &Model) -> (f64, f64) {
    let mut best: Option<(f64, usize)> = None;
    for (k, b) in model.bodies.iter().enumerate() {
        if let Some(pd) = b.as_pd() {
            let f: f64 = pd.contact_force.iter().sum::<Vec3>().norm();
            // Two bodies pressed together carry equal and opposite forces: the first of them
            // wins, not the one that rounding makes larger in its last bits.
            if f > 0.0 && best.is_none_or(|(g, _)| f > g * (1.0 + 1e-6)) {
                best = Some((f, k));
            }
        }
    }
    let Some((_, k)) = best else {
        return (0.0, 0.0);
    };
    match contact_patch(model, k, None) {
        Some(patch) => {
            let pts: Vec<(f64, f64)> = patch.points.iter().map(|&(_, r, p)| (r, p)).collect();
            let a = fit_elliptic(&pts).map_or(0.0, |f| f.0);
            (a, patch.peak)
        }
        None => (0.0, 0.0),
    }
}

/// Everything short of solving: the scene's model built (meshes read, particles, bonds,
/// surfaces, contact pairs) and checked, with the warnings and contact estimates a run reports.
/// `pdcontact run --check` stops here.
pub fn check_scene(scene: &Scene) -> Result<(Model, Vec<String>, Vec<ContactResolution>)> {
    check_scene_on(scene, None)
}

/// [`check_scene`] on a rank of a run decomposed over `comm` ([`Model::from_scene_on`]).
/// Collective.
pub fn check_scene_on(
    scene: &Scene,
    comm: Option<&Arc<dyn Comm>>,
) -> Result<(Model, Vec<String>, Vec<ContactResolution>)> {
    let (model, warnings, contact_estimates) = checked(scene, comm)?;
    let warnings = warnings.into_iter().map(|w| w.text).collect();
    Ok((model, warnings, contact_estimates))
}

/// A warning of [`check_scene`], and whether it is about the meshes alone, whatever the
/// scene's values: what the importers found, a body's unconnected pieces, the surface where
/// a contact will be (tributary areas that vary, a mesh graded toward the contact). Those
/// are what a run of a study's own scene prints ([`RunOptions::study`]).
struct Warning {
    text: String,
    on_mesh: bool,
}

/// [`check_scene_on`] with each warning tagged.
fn checked(
    scene: &Scene,
    comm: Option<&Arc<dyn Comm>>,
) -> Result<(Model, Vec<Warning>, Vec<ContactResolution>)> {
    let model = Model::from_scene_on(scene, comm)?;
    checks::check_model(scene, &model)?;
    let tag = |on_mesh: bool, texts: Vec<String>| {
        texts.into_iter().map(move |text| Warning { text, on_mesh })
    };
    let mut warnings: Vec<Warning> = tag(true, importer_warnings(&model)).collect();
    // Solver options that the chosen solver ignores.
    warnings.extend(tag(false, scene.warnings()));
    warnings.extend(tag(false, checks::one_pass_warnings(scene, &model)));
    warnings.extend(tag(true, checks::piece_warnings(scene, &model)));
    warnings.extend(tag(false, checks::lps_contact_warnings(scene, &model)));
    let contact_estimates = model.contact_resolution();
    for e in &contact_estimates {
        warnings.extend(
            e.tagged_warnings()
                .into_iter()
                .map(|(text, on_mesh)| Warning { text, on_mesh }),
        );
    }
    warnings.extend(tag(
        false,
        units::scale_warnings(scene, &model, &contact_estimates),
    ));
    warnings.extend(tag(
        false,
        damping::damping_warnings(scene, &model, &contact_estimates),
    ));
    Ok((model, warnings, contact_estimates))
}

/// What the importers and the quality checks found in the meshes, body by body; a body's
/// pieces as `checks::piece_warnings` sees them, with its bonds and its contacts (the mesh's
/// own warning said a contact was missing where the scene has one).
fn importer_warnings(model: &Model) -> Vec<String> {
    model
        .bodies
        .iter()
        .filter_map(Body::as_pd)
        .flat_map(|pd| {
            pd.case
                .mesh
                .warnings
                .iter()
                .filter(|w| !crate::importers::is_pieces_warning(w))
                .map(move |w| format!("body \"{}\": {w}", pd.name))
        })
        .collect()
}

/// Runs a scene; writes frames and `summary.json` into the output folder.
pub fn run_scene(scene: &Scene, options: &RunOptions) -> Result<(Model, RunSummary)> {
    run_scene_with(scene, options, &mut crate::solver::Silent)
}

/// Two monitors in one: the run's own (frames, progress), then an observer's.
struct Tee<'a> {
    run: &'a mut dyn Monitor,
    observer: &'a mut dyn Monitor,
}

impl Monitor for Tee<'_> {
    fn step(&mut self, model: &Model, step: usize, time: f64, measure: f64) -> Result<()> {
        self.run.step(model, step, time, measure)?;
        self.observer.step(model, step, time, measure)
    }
    fn load_increment(&mut self, model: &Model, factor: f64, iteration: usize) -> Result<()> {
        self.run.load_increment(model, factor, iteration)?;
        self.observer.load_increment(model, factor, iteration)
    }
    fn cut_back(&mut self, model: &Model, done: f64, target: f64, iteration: usize) -> Result<()> {
        self.run.cut_back(model, done, target, iteration)?;
        self.observer.cut_back(model, done, target, iteration)
    }
    fn increment_done(&mut self, model: &Model, factor: f64, iteration: usize) -> Result<()> {
        self.run.increment_done(model, factor, iteration)?;
        self.observer.increment_done(model, factor, iteration)
    }
    fn linear_iterations(&mut self, total: usize) {
        self.run.linear_iterations(total);
        self.observer.linear_iterations(total);
    }
    fn relaxation(&mut self, on: bool) {
        self.run.relaxation(on);
        self.observer.relaxation(on);
    }
    fn finish(&mut self, model: &Model, step: usize, time: f64) -> Result<()> {
        self.run.finish(model, step, time)?;
        self.observer.finish(model, step, time)
    }
    fn interrupted(&self) -> bool {
        self.run.interrupted() || self.observer.interrupted()
    }
}

/// [`run_scene`], with `observer` shown every step, load increment and the end as the run's
/// own monitor is (a study that follows a run as it goes: a history, each increment's state).
pub fn run_scene_with(
    scene: &Scene,
    options: &RunOptions,
    observer: &mut dyn Monitor,
) -> Result<(Model, RunSummary)> {
    let start = Instant::now();
    let folder = options
        .output
        .clone()
        .unwrap_or_else(|| scene.resolve(&scene.output.folder));
    // "dir/." reads badly in messages: drop "." components, but keep "." itself (a scene
    // run from its own folder with `folder = "."`: an empty path names no folder).
    let folder: PathBuf = folder
        .components()
        .filter(|c| !matches!(c, std::path::Component::CurDir))
        .collect();
    let folder = if folder.as_os_str().is_empty() {
        PathBuf::from(".")
    } else {
        folder
    };
    let comm = options.comm.clone().filter(|c| c.size() > 1);
    let (mut model, tagged, contact_estimates) = checked(scene, comm.as_ref())?;
    if let Some(comm) = comm {
        model.distribute(comm)?;
    }
    // The meshes' elements have made the model; a run keeps their nodes alone.
    for pd in model.bodies.iter_mut().filter_map(Body::as_pd_mut) {
        pd.case.release_elements();
    }
    // In a decomposed run the first rank speaks and writes; the others only compute.
    let root = model.rank() == 0;
    if !options.quiet && root {
        for w in tagged.iter().filter(|w| w.on_mesh || !options.study) {
            eprintln!("warning: {}", w.text);
        }
    }
    let warnings: Vec<String> = tagged.into_iter().map(|w| w.text).collect();
    let mut frames = if root {
        FrameWriter::new(&folder, scene.output.every)?
    } else {
        FrameWriter::for_pieces(&folder, scene.output.every)
    };
    if scene.solver.kind == SolverKind::Static {
        frames.iteration_word = "Newton iteration";
    }
    let pvd = frames.pvd_path();
    let stop = options.stop.clone().unwrap_or_default();
    let mut monitor = RunMonitor::new(
        Some(frames),
        options.quiet || !root,
        scene.solver.kind.is_quasi_static(),
        stop,
    );
    let solve_start = Instant::now();
    let result = solve(
        &mut model,
        &scene.solver,
        &mut Tee {
            run: &mut monitor,
            observer,
        },
    );
    let solve_seconds = solve_start.elapsed().as_secs_f64();
    let summary_path = folder.join("summary.json");
    let result = match result {
        // A run without equilibrium whose crack faces went through each other: that is why.
        Ok(s) if !s.converged && !s.interrupted && s.unheld.is_none() => {
            checks::crossed_cracks(&model, scene).map_or(Ok(s), |(e, _)| Err(Error::Numerical(e)))
        }
        // A run stopped by its own cause: the crack's faces are why where they went a quarter
        // spacing or more through each other; a shallower crossing is said beside the cause
        // (the Kalthoff plate at Δ = 1 mm: a crushed particle through the projectile, and the
        // notch's mouth beside it 0.03 Δ across).
        Err(Error::Numerical(m)) => Err(match checks::crossed_cracks(&model, scene) {
            Some((c, depth)) if depth >= 0.25 => {
                Error::Numerical(format!("{c} (the run stopped: {m})"))
            }
            Some((c, _)) => Error::Numerical(format!("{m}; beside it, {c}")),
            None => Error::Numerical(m),
        }),
        r => r,
    };
    // Where the force is left, on one process only: a rank of a decomposed run sees its own
    // particles alone.
    let decomposed = options.comm.as_ref().is_some_and(|c| c.size() > 1);
    let unbalanced = |model: &Model| match checks::unbalanced(model) {
        Some(m) if !decomposed => format!("; {m}"),
        _ => String::new(),
    };
    let (stats, error) = match result {
        // A body gone past everything it touches: the scene cannot be solved quasi-statically.
        Ok(s) if s.unheld.is_some() => {
            let u = s.unheld.clone().expect("matched");
            let e = scene.block_error("[[body]]", u.body, u.message);
            (s, Some(e))
        }
        // ADR that ends without reaching the tolerance (and was not interrupted) is a failed
        // run: the state is not an equilibrium.
        Ok(s) if scene.solver.kind == SolverKind::Static && !s.converged && !s.interrupted => {
            let e = Error::numerical(format!(
                "the static solver did not converge in {} Newton iterations (residual {:.3e}, tolerance {:.1e}, load factor {:.4} reached){}; likely cause: too few iterations (raise max_iterations) or loads that the supports and contacts cannot balance",
                s.iterations,
                s.residual,
                scene.solver.tolerance.unwrap_or(crate::solver::DEFAULT_TOLERANCE),
                s.load_factor,
                unbalanced(&model)
            ));
            (s, Some(e))
        }
        Ok(s) if scene.solver.kind == SolverKind::Adr && !s.converged && !s.interrupted => {
            let e = Error::numerical(format!(
                "ADR did not converge in {} iterations (residual {:.3e}, tolerance {:.1e}){}; likely cause: too few iterations (raise max_iterations) or loads that the supports and contacts cannot balance",
                s.iterations,
                s.residual,
                scene.solver.tolerance.unwrap_or(crate::solver::DEFAULT_TOLERANCE),
                unbalanced(&model)
            ));
            (s, Some(e))
        }
        Ok(s) => (s, None),
        // Input the solver refuses is the scene's: name it.
        Err(Error::Input(m)) => (
            RunStats::default(),
            Some(Error::input(format!("{}: {m}", scene.source))),
        ),
        // A numerical failure: the summary still says how far the run got.
        Err(e) => {
            let (step, time, measure) = monitor.last_step;
            let adr = scene.solver.kind.is_quasi_static();
            let stats = RunStats {
                solver: match scene.solver.kind {
                    SolverKind::Adr => "adr",
                    SolverKind::Static => "static",
                    SolverKind::Explicit => "explicit",
                }
                .into(),
                iterations: step,
                time,
                residual: if adr { measure } else { 0.0 },
                energy_drift: if adr { 0.0 } else { measure },
                ..RunStats::default()
            };
            (stats, Some(e))
        }
    };
    let decomposition = model.domain.as_ref().map(|d| d.layout(&model.bodies));
    let (contact, applied, balance) = force_balance(&model);
    let (radius, peak) = patch_figures(&model);
    let accuracy = report::AccuracyCheck::of(&model, &contact_estimates, radius, peak);
    let mut after = report::drift_warnings(&model);
    if scene.solver.kind == SolverKind::Explicit && error.is_none() {
        // Bonds that may fail, not pre-cracks alone (which cut bonds but break none).
        let breaks = model
            .bodies
            .iter()
            .any(|b| b.as_pd().is_some_and(PdBody::may_break));
        after.extend(report::energy_warning(stats.energy_drift, breaks));
    }
    if !options.quiet && root {
        for w in &after {
            eprintln!("warning: {w}");
        }
    }
    let mut warnings = warnings;
    warnings.extend(after);
    let summary = RunSummary {
        scene: scene.source.clone(),
        warnings,
        accuracy,
        contact_estimates,
        particles: model.particles(),
        bonds: model.bonds(),
        iterations: stats.iterations,
        converged: stats.converged && error.is_none(),
        residual: stats.residual,
        wall_seconds: start.elapsed().as_secs_f64(),
        solve_seconds,
        peak_memory_mb: crate::parallel::memory::peak_rss_mb(),
        verlet_rebuilds: model.verlet_rebuilds(),
        contact_pairs: model.contact_count(),
        missed_contacts: model.missed_contacts(),
        total_contact_force: contact.into(),
        applied_load: applied.into(),
        force_balance_error: balance,
        contact_radius: radius,
        peak_pressure: peak,
        outputs: Outputs {
            pvd,
            last_frame: monitor.frames.as_ref().and_then(FrameWriter::last_frame),
            summary: summary_path.clone(),
        },
        interrupted: stats.interrupted,
        fracture: report::fracture_reports(&model),
        friction: report::friction_reports(&model),
        friction_pairs: report::friction_pair_reports(&model),
        decomposition,
        solver: stats,
        error: error.as_ref().map(ToString::to_string),
    };
    if root {
        if !summary.solver.increments.is_empty() {
            crate::output::chart::write_load_displacement(
                &folder.join(LOAD_DISPLACEMENT_NAME),
                &summary.solver.increments,
            )?;
        }
        write_summary(&summary_path, &summary)?;
    }
    match error {
        Some(e) => Err(e),
        None => Ok((model, summary)),
    }
}

/// The chart of a run under displacement control, in its output folder.
pub const LOAD_DISPLACEMENT_NAME: &str = "load_displacement.svg";

/// Writes `summary.json` atomically.
pub fn write_summary(path: &Path, summary: &RunSummary) -> Result<()> {
    let text = serde_json::to_string_pretty(summary).map_err(|e| Error::output(path, e))?;
    write_atomically(path, |w| std::io::Write::write_all(w, text.as_bytes()))
}
