//! Fragments (docs/FRACTURE.md, "Contact on new surfaces", "Fragments"): a steel ball fired
//! through a brittle plate, explicit, after Silling & Askari (2005)'s sphere through a brittle
//! target.
//!
//! The scene (our own, stated): a square plate 20 × 20 × 2 mm of a glassy polymer
//! (E = 3 GPa, ν = 1/4, ρ = 1190 kg/m³, G0 = 400 J/m², near PMMA's), free at its edges; a
//! steel ball of 6 mm diameter (E = 200 GPa, ρ = 7800 kg/m³, elastic) at 100 m/s normal to the
//! plate at its middle, starting 1.5 Δ above it (1.5 mm above a meshed plate), clear of the
//! contact's reach. The ball and the plate meet through the short-range contact (the plate
//! the slave: the repulsion has the plate's coefficient, which keeps the stable step the
//! plate's), and the plate is its own short-range master, so that its pieces push each other
//! apart where they meet ([`crate::contact::fragments`]). The run lasts 120 µs, long enough
//! for the whole ball to pass the plate's far face.
//!
//! Measured: the fragments (groups of particles joined by intact bonds) and their sizes; the
//! deepest any particle of one piece went into another piece's surface and into the ball's,
//! over every step, in Δ; the energy balance (kinetic + strain + contact + the work of
//! breaking bonds, against the ball's kinetic energy at the start), at the end and its
//! largest drift over the run; the ball's speed after.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::run_in;
use crate::contact::fragments::FragmentPass;
use crate::error::Result;
use crate::model::Model;
use crate::solver::{EnergyTerms, Monitor};

/// The ball's speed at the start, m/s.
pub const SPEED: f64 = 100.0;
/// Simulated time, s.
pub const END_TIME: f64 = 1.2e-4;
/// Pieces of at least this many particles count as fragments; smaller ones as debris.
pub const FRAGMENT_PARTICLES: usize = 10;

/// The scene at plate spacing `dx` (the ball's generator gets the same spacing), frames
/// every `every` steps into `folder`; with `plate_mesh` the plate is that mesh (a box of the
/// same size, `tools/gmsh_plate.py`) and `dx` the ball's spacing alone.
pub fn perforation_scene(dx: f64, folder: &str, every: usize, plate_mesh: Option<&Path>) -> String {
    let plate = match plate_mesh {
        Some(m) => format!("mesh = {:?}", m.display().to_string()),
        None => format!(
            "generator = {{ shape = \"box\", min = [-0.01, -0.01, 0.0], max = [0.01, 0.01, 0.002], spacing = {dx} }}"
        ),
    };
    format!(
        "# A steel ball fired at 100 m/s through a brittle plate 20 x 20 x 2 mm (explicit).\n\
         [solver]\nkind = \"explicit\"\nend_time = {END_TIME:e}\n\n\
         [output]\nfolder = \"{folder}\"\nevery = {every}\n\n\
         [[body]]\nname = \"plate\"\n\
         {plate}\n\
         material = {{ youngs_modulus = 3e9, poisson_ratio = 0.25, density = 1190, fracture_energy = 400 }}\n\n\
         [[body]]\nname = \"ball\"\n\
         generator = {{ shape = \"sphere\", radius = 0.003, spacing = {dx}, center = [0.0, 0.0, {z}] }}\n\
         material = {{ youngs_modulus = 200e9, poisson_ratio = 0.25, density = 7800 }}\n\
         velocity = [0, 0, -{SPEED}]\n\n\
         # The ball on the plate, and the plate's pieces on each other.\n\
         [[contact]]\nslave = \"plate\"\nmaster = \"ball\"\nmethod = \"short-range\"\n\n\
         {PIECES}",
        // Clear of the short-range zone (1.35 Δ of the plate): a mesh's Δ is not known here.
        z = 0.005 + if plate_mesh.is_some() { 0.0015 } else { 1.5 * dx },
    )
}

/// The plate's contact with itself, which keeps its pieces apart.
const PIECES: &str =
    "[[contact]]\nslave = \"plate\"\nmaster = \"plate\"\nmethod = \"short-range\"\n";

/// Follows a run without the plate's contact with itself: how deep its pieces go into each
/// other, every [`PROBE_EVERY`] steps.
struct DepthProbe(Option<FragmentPass>);

/// Steps between two looks of [`DepthProbe`].
const PROBE_EVERY: usize = 5;

impl Monitor for DepthProbe {
    fn step(&mut self, model: &Model, step: usize, _: f64, _: f64) -> Result<()> {
        if step.is_multiple_of(PROBE_EVERY) {
            self.0
                .get_or_insert_with(|| FragmentPass::probe(&model.bodies, 0))
                .detect(&model.bodies);
        }
        Ok(())
    }

    fn finish(&mut self, _: &Model, _: usize, _: f64) -> Result<()> {
        Ok(())
    }
}

/// What the perforation gave.
#[derive(Clone, Debug, Serialize)]
pub struct PerforationResult {
    /// The plate's spacing Δ and horizon, m; particles of both bodies.
    pub spacing: f64,
    pub horizon: f64,
    pub particles: usize,
    /// Pieces of [`FRAGMENT_PARTICLES`] particles or more, their sizes (largest first, the
    /// plate's remains the first), and the pieces smaller than that (debris).
    pub fragments: usize,
    pub fragment_sizes: Vec<usize>,
    pub debris: usize,
    pub broken_bonds: usize,
    /// The plate's particles on the surfaces its broken bonds opened at the end
    /// ([`crate::body::new_surface`]), the particles tested to find them and the time that
    /// took (s).
    pub opened_surface: usize,
    pub surface_tested: usize,
    pub surface_seconds: f64,
    /// The deepest a particle of one piece went into another piece's surface over the run,
    /// in Δ, and a ball particle into the plate's.
    pub deepest_between_pieces: f64,
    pub deepest_ball: f64,
    /// The same run without the plate's contact with itself: the deepest its pieces went
    /// into each other (in Δ, looked at every few steps), its fragments and debris.
    pub without_contact_deepest: f64,
    pub without_contact_fragments: usize,
    /// The energy's terms at the start and at the end (J).
    pub energy: [EnergyTerms; 2],
    /// `|total(end) − total(start)| / total(start)`, and the largest drift over the run
    /// (checked every 10 steps, against the largest energy the bodies held).
    pub energy_error: f64,
    pub energy_drift: f64,
    /// The ball's mean velocity along the shot at the end, m/s (positive: on through).
    pub exit_speed: f64,
    /// The ball's centre below the plate's far face: it went through.
    pub perforated: bool,
    pub steps: usize,
    pub dt: f64,
    pub wall_seconds: f64,
    pub folder: PathBuf,
}

impl PerforationResult {
    pub fn to_text(&self) -> String {
        let [a, b] = &self.energy;
        format!(
            "Fragments: a steel ball through a brittle plate at {SPEED} m/s (explicit)\n\
             plate spacing {dx:.2} mm, horizon {d:.2} mm, {n} particles; {s} steps of {dt:.3e} s, {w:.1} s\n\
             ball {p} the plate; it leaves at {v:.1} m/s\n\
             {b_} bonds broken; {f} fragments of {FRAGMENT_PARTICLES} particles or more (sizes {sizes:?}), {deb} smaller pieces\n\
             surfaces the cracks opened: {os} particles, found again over the intact bonds ({st} particles tested, {ss:.3} s)\n\
             deepest into another piece's surface over the run: {dp:.3} Δ; ball into the plate: {db:.3} Δ\n\
             without the plate's contact with itself: {wd:.3} Δ, {wf} fragments\n\
             energy (J)         start        end\n\
             kinetic       {k0:>10.4e} {k1:>10.4e}\n\
             strain        {s0:>10.4e} {s1:>10.4e}\n\
             contact       {c0:>10.4e} {c1:>10.4e}\n\
             fracture work {f0:>10.4e} {f1:>10.4e}\n\
             total         {t0:>10.4e} {t1:>10.4e}   balance {e:.3} %, largest drift {drift:.3} %\n\
             frames in {dir}\n",
            dx = self.spacing * 1e3,
            d = self.horizon * 1e3,
            n = self.particles,
            s = self.steps,
            dt = self.dt,
            w = self.wall_seconds,
            p = if self.perforated {
                "went through"
            } else {
                "did not go through"
            },
            v = self.exit_speed,
            b_ = self.broken_bonds,
            f = self.fragments,
            sizes = self.fragment_sizes,
            deb = self.debris,
            os = self.opened_surface,
            st = self.surface_tested,
            ss = self.surface_seconds,
            dp = self.deepest_between_pieces,
            db = self.deepest_ball,
            wd = self.without_contact_deepest,
            wf = self.without_contact_fragments,
            k0 = a.kinetic,
            k1 = b.kinetic,
            s0 = a.strain,
            s1 = b.strain,
            c0 = a.contact,
            c1 = b.contact,
            f0 = a.fracture,
            f1 = b.fracture,
            t0 = a.total(),
            t1 = b.total(),
            e = 100.0 * self.energy_error,
            drift = 100.0 * self.energy_drift,
            dir = self.folder.display(),
        )
    }
}

/// Runs the perforation at plate spacing `dx` (or on the plate mesh `plate_mesh`) into
/// `folder`, frames every `every` steps; then again without the plate's contact with itself
/// into `folder/without_contact`.
pub fn run_perforation(
    dx: f64,
    plate_mesh: Option<&Path>,
    every: usize,
    folder: &Path,
    quiet: bool,
) -> Result<PerforationResult> {
    let mesh = match plate_mesh {
        Some(m) => Some(std::fs::canonicalize(m).map_err(|e| {
            crate::error::Error::input(format!("{}: cannot read the plate mesh: {e}", m.display()))
        })?),
        None => None,
    };
    let scene = perforation_scene(dx, ".", every, mesh.as_deref());
    let (model, summary, wall_seconds) = run_in(&scene, folder, quiet)?;
    let mut probe = DepthProbe(None);
    let (without, _, _) = super::super::run_in(
        &scene.replace(PIECES, ""),
        &folder.join("without_contact"),
        quiet,
        &mut probe,
    )?;
    let pieces = |m: &Model| {
        let pd = m.bodies[0].as_pd().expect("the plate is deformable");
        pd.fracture
            .as_ref()
            .map_or(vec![pd.len()], |f| f.fragments(&pd.case.bonds))
    };
    let without_contact_fragments = pieces(&without)
        .iter()
        .filter(|&&s| s >= FRAGMENT_PARTICLES)
        .count();
    let plate = model.bodies[0].as_pd().expect("the plate is deformable");
    let ball = model.bodies[1].as_pd().expect("the ball is deformable");
    let sizes = pieces(&model);
    let fragment_sizes: Vec<usize> = sizes
        .iter()
        .copied()
        .filter(|&s| s >= FRAGMENT_PARTICLES)
        .collect();
    let mass: f64 = ball.mass.iter().sum();
    let exit_speed = -(0..ball.len())
        .map(|i| ball.mass[i] * ball.v[i].z)
        .sum::<f64>()
        / mass;
    let centre_z = (0..ball.len())
        .map(|i| ball.mass[i] * ball.position(i).z)
        .sum::<f64>()
        / mass;
    let energy = summary.solver.energy.unwrap_or_default();
    let start = energy[0].total();
    let (opened_surface, surface_tested, surface_seconds) = plate
        .new_surface()
        .map_or((0, 0, 0.0), |f| (f.count(), f.tested, f.seconds));
    Ok(PerforationResult {
        spacing: plate.spacing(),
        horizon: plate.case.horizon,
        particles: summary.particles,
        fragments: fragment_sizes.len(),
        debris: sizes.len() - fragment_sizes.len(),
        fragment_sizes,
        broken_bonds: plate.fracture.as_ref().map_or(0, |f| f.broken),
        opened_surface,
        surface_tested,
        surface_seconds,
        deepest_between_pieces: model.fragments.first().map_or(0.0, |p| p.deepest.max(0.0)),
        deepest_ball: model
            .short_range
            .first()
            .map_or(0.0, |p| p.deepest.max(0.0) / plate.spacing()),
        without_contact_deepest: probe.0.map_or(0.0, |p| p.deepest.max(0.0)),
        without_contact_fragments,
        energy,
        energy_error: (energy[1].total() - start).abs() / start.abs().max(f64::MIN_POSITIVE),
        energy_drift: summary.solver.energy_drift,
        exit_speed,
        perforated: centre_z + 0.003 < 0.0,
        steps: summary.iterations,
        dt: summary.solver.dt,
        wall_seconds,
        folder: folder.to_path_buf(),
    })
}
