//! `pdcontact bench --adr SCENE`: one ADR iteration against one bare bond-force pass.

use std::time::Instant;

use crate::error::{Error, Result};
use crate::parallel::memory::peak_rss_mb;

/// Times an ADR run from the end of its first iteration to the end of its last.
#[derive(Default)]
struct StepClock {
    first: Option<Instant>,
    last: Option<Instant>,
    steps: usize,
}

impl crate::solver::Monitor for StepClock {
    fn step(&mut self, _: &crate::model::Model, _: usize, _: f64, _: f64) -> Result<()> {
        let now = Instant::now();
        self.first.get_or_insert(now);
        self.last = Some(now);
        self.steps += 1;
        Ok(())
    }
    fn finish(&mut self, _: &crate::model::Model, _: usize, _: f64) -> Result<()> {
        Ok(())
    }
}

/// `pdcontact bench --adr SCENE`: what one ADR iteration costs against one bare bond-force
/// pass ([`internal_forces`](crate::model::internal_forces): bonds and loads, every deformable
/// body) on the scene's bodies. The ADR iterations are the solver's own (contact, residual,
/// fictitious density, damping, update included), run with a tolerance of zero so that none
/// stops early; the solver's setup (densities, first force evaluation) is left out by timing a
/// one-iteration run and an `N + 1`-iteration run and dividing the difference by `N`.
#[derive(Clone, Debug, serde::Serialize)]
pub struct AdrReport {
    pub scene: String,
    pub particles: usize,
    pub bonds: usize,
    pub iterations: usize,
    pub threads: usize,
    /// Seconds per bare bond-force pass.
    pub bond_pass_seconds: f64,
    /// Seconds per ADR iteration.
    pub adr_iteration_seconds: f64,
    /// `adr_iteration_seconds / bond_pass_seconds`.
    pub ratio: f64,
    /// Slave (surface) particles over all point-to-surface contact passes.
    pub slave_particles: usize,
    /// Seconds per Verlet-list rebuild of every pass (broad phase).
    pub verlet_rebuild_seconds: f64,
    /// Seconds per point-to-surface pass over every pass's slaves (narrow phase: projection,
    /// gap, contact force; no rebuild).
    pub contact_pass_seconds: f64,
    /// Peak resident memory of the process, MB.
    pub peak_rss_mb: Option<f64>,
}

impl AdrReport {
    pub fn to_text(&self) -> String {
        format!(
            "{}: {} particles, {} bonds, {} threads\n\
             bare bond-force pass: {:.4e} s\n\
             ADR iteration:        {:.4e} s ({} iterations)\n\
             ratio:                {:.3}\n\
             Verlet rebuild:       {:.4e} s ({:.3e} slave particles/s)\n\
             contact pass:         {:.4e} s ({:.3e} slave particles/s)\n\
             peak memory:          {}\n",
            self.scene,
            self.particles,
            self.bonds,
            self.threads,
            self.bond_pass_seconds,
            self.adr_iteration_seconds,
            self.iterations,
            self.ratio,
            self.verlet_rebuild_seconds,
            self.slave_particles as f64 / self.verlet_rebuild_seconds.max(1e-12),
            self.contact_pass_seconds,
            self.slave_particles as f64 / self.contact_pass_seconds.max(1e-12),
            self.peak_rss_mb
                .map_or("-".into(), |m| format!("{m:.0} MB")),
        )
    }
}

/// Times `iterations` bare bond-force passes and `iterations` ADR iterations on `scene`.
pub fn run_adr(
    scene: &crate::scene::Scene,
    iterations: usize,
    threads: Option<usize>,
) -> Result<AdrReport> {
    let run = || -> Result<AdrReport> {
        let iterations = iterations.max(1);
        let mut model = crate::model::Model::from_scene(scene)?;
        let mut scratch = Vec::new();
        // Warm up (first touch of every array), then time.
        for pd in model
            .bodies
            .iter_mut()
            .filter_map(crate::body::Body::as_pd_mut)
        {
            crate::model::internal_forces(pd, &mut scratch);
        }
        let start = Instant::now();
        for _ in 0..iterations {
            for pd in model
                .bodies
                .iter_mut()
                .filter_map(crate::body::Body::as_pd_mut)
            {
                crate::model::internal_forces(pd, &mut scratch);
            }
        }
        let bond_pass = start.elapsed().as_secs_f64() / iterations as f64;

        // Contact search at the initial positions: rebuilds, then passes that reuse the list.
        let slave_particles = model.passes.iter().map(|p| p.slaves.len()).sum();
        let start = Instant::now();
        for _ in 0..iterations {
            for k in 0..model.passes.len() {
                model.passes[k].rebuild_verlet(&model.bodies);
            }
        }
        let verlet_rebuild = start.elapsed().as_secs_f64() / iterations as f64;
        let start = Instant::now();
        for _ in 0..iterations {
            for k in 0..model.passes.len() {
                model.passes[k].detect(&model.bodies);
            }
        }
        let contact_pass = start.elapsed().as_secs_f64() / iterations as f64;

        // ADR's setup (densities, first force evaluation, first step) is paid once: the clock
        // runs from the end of the first iteration to the end of the last, in one run (two
        // runs timed apart and subtracted can come out negative on a busy machine). ADR's
        // first iteration is its setup step, which the monitor does not see: `iterations + 2`
        // gives `iterations + 1` monitored ends, `iterations` intervals between them.
        let mut model = crate::model::Model::from_scene(scene)?;
        let mut clock = StepClock::default();
        crate::solver::adr(&mut model, 0.0, iterations + 2, 1, &mut clock)?;
        let timed_iterations = clock.steps.saturating_sub(1);
        let adr = match (clock.first, clock.last) {
            (Some(first), Some(last)) if timed_iterations > 0 => {
                (last - first).as_secs_f64() / timed_iterations as f64
            }
            _ => 0.0,
        };
        Ok(AdrReport {
            scene: scene.source.clone(),
            particles: model.particles(),
            bonds: model.bonds(),
            iterations: timed_iterations,
            threads: rayon::current_num_threads(),
            bond_pass_seconds: bond_pass,
            adr_iteration_seconds: adr,
            ratio: adr / bond_pass,
            slave_particles,
            verlet_rebuild_seconds: verlet_rebuild,
            contact_pass_seconds: contact_pass,
            peak_rss_mb: peak_rss_mb(),
        })
    };
    match threads {
        Some(t) => rayon::ThreadPoolBuilder::new()
            .num_threads(t.max(1))
            .build()
            .map_err(|e| Error::input(format!("cannot start {t} threads: {e}")))?
            .install(run),
        None => run(),
    }
}
