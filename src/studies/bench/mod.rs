//! `pdcontact bench`: the bond-force kernel timed on the problem LAMMPS's `pair_style peri/pmb`
//! is compared on (docs/PERFORMANCE.md).
//!
//! The body is a sphere of radius 1 m whose particles are the points of a simple cubic lattice
//! of spacing Δ inside it, each of volume Δ³ (what LAMMPS's `lattice sc` and `create_atoms`
//! make), sorted in Morton order as [`discretize`](crate::case::discretize) sorts mesh nodes. Bonds
//! come from [`build_pairs`] (each pair once), weights are the bond-based PMB ones, `w = c v_c V_i V_j / L` with
//! `c = 12E/(πδ⁴)` (Eq. 5) and the volume correction `v_c` of Eq. 10, which is the partial
//! volume LAMMPS applies to bonds near the edge of the horizon. There is no surface correction
//! (LAMMPS has none) and no contact. Every step is velocity Verlet with the forces of
//! [`pair_forces`], the pass the solvers run.
//!
//! As LAMMPS's `Loop time`, the loop time excludes the setup (lattice, bonds, weights, the
//! first force evaluation); the setup is timed separately.

mod adr;
mod pipeline;

use std::time::Instant;

use rayon::prelude::*;

use crate::case::correction::{micromodulus, volume_correction};
use crate::case::discretize::sort_morton;
use crate::case::neighbours::{build_pairs, build_pairs_touching, count_pairs, BondList, Reach};
use crate::case::pairs::{pair_forces, ForceBuffers, PairKinematics, PairList};
use crate::case::part::cut_by_rows;
use crate::error::{Error, Result};
use crate::math::Vec3;
use crate::parallel::memory::{peak_rss_mb, resident_mb};
use crate::parallel::{Comm, Ghosts};

pub use adr::{run_adr, AdrReport};
pub use pipeline::{run_pipeline, PipelineReport, StageReport};

/// Radius of the sphere, m.
pub const RADIUS: f64 = 1.0;
/// Young's modulus, Pa.
pub const YOUNGS: f64 = 1e9;
/// Density, kg/m³.
pub const DENSITY: f64 = 1000.0;
/// Time step, s.
pub const DT: f64 = 1e-5;
/// Initial velocity `v = RATE · x` (a uniform expansion), 1/s.
pub const RATE: f64 = 0.1;
/// The horizon factor LAMMPS's examples use on a lattice: 3 with a margin, so that bonds of
/// length exactly 3Δ are inside the horizon whatever the rounding. A mesh's particles are not
/// on a lattice: their default is [`crate::case::DEFAULT_HORIZON_FACTOR`] (3).
pub const LATTICE_HORIZON_FACTOR: f64 = 3.0002;
/// Particles per parallel work item.
const CHUNK: usize = 256;
/// Largest lattice accepted (partner indices are 32-bit).
const MAX_PARTICLES: f64 = 2.0e9;

/// What to run.
#[derive(Clone, Debug)]
pub struct LatticeSphere {
    /// Lattice spacing Δ, m.
    pub spacing: f64,
    /// Horizon δ = factor · Δ.
    pub horizon_factor: f64,
    /// Time steps of the timed loop.
    pub steps: usize,
    /// Threads of the rayon pool (default: rayon's, one per core).
    pub threads: Option<usize>,
}

/// What a benchmark run measured.
#[derive(Clone, Debug, serde::Serialize)]
pub struct BenchReport {
    pub particles: usize,
    /// Directed bonds per particle (each pair counted twice, as LAMMPS counts them).
    pub bonds_per_particle: f64,
    pub steps: usize,
    pub threads: usize,
    /// Wall time of the time-step loop, s.
    pub loop_seconds: f64,
    /// Wall time of the lattice, bonds, weights and first force evaluation, s.
    pub setup_seconds: f64,
    /// Directed bonds × steps / loop seconds.
    pub bond_updates_per_second: f64,
    /// Peak resident memory of the process (`VmHWM`), MB (10⁶ bytes); null where unknown.
    pub peak_rss_mb: Option<f64>,
    /// Kinetic + strain energy before the loop, J.
    pub initial_energy: f64,
    /// Kinetic + strain energy after the loop, J.
    pub final_energy: f64,
    /// `|final − initial| / initial`.
    pub energy_drift: f64,
    /// Bytes the bond arrays hold per directed bond (partner, length, weight, offsets).
    pub bytes_per_bond: f64,
    /// Pairs evaluated twice per pair (those that join two threads' ranges, which each
    /// thread evaluates so that every particle's force is summed in one order): what the
    /// threads cost beyond one; 0 on one thread. Of the first rank under `mpirun`.
    pub halo_pairs_per_pair: f64,
    /// Processes (`mpirun -n`; 1 without).
    pub ranks: usize,
    /// Per process: what it owned, received and held.
    pub per_rank: Vec<RankFigures>,
}

/// One process of a benchmark run.
#[derive(Clone, Debug, serde::Serialize)]
pub struct RankFigures {
    /// Particles it owns (moves and computes the forces of).
    pub particles: usize,
    /// Ghost particles it receives every step (bond partners of its particles).
    pub ghosts: usize,
    /// Directed bonds it evaluates (its pairs, those shared with another rank included).
    pub directed_bonds: usize,
    /// Peak resident memory (`VmHWM`), MB, the setup included: a rank counts every
    /// particle's pairs but builds only those of its part.
    pub peak_rss_mb: Option<f64>,
    /// Resident memory after the time-step loop (`VmRSS`), MB: what a rank holds while it runs.
    pub resident_mb: Option<f64>,
    /// Its own loop time, s.
    pub loop_seconds: f64,
}

impl BenchReport {
    /// A two-column table for the terminal.
    pub fn to_text(&self, spec: &LatticeSphere) -> String {
        let rss = self
            .peak_rss_mb
            .map_or("unknown".to_string(), |m| format!("{m:.0}"));
        let rows = [
            (
                "problem".to_string(),
                format!(
                    "lattice sphere R = {RADIUS} m, Δ = {} m, δ = {}Δ, PMB, velocity Verlet, dt = {DT:e} s",
                    spec.spacing, spec.horizon_factor
                ),
            ),
            ("particles".into(), self.particles.to_string()),
            (
                "bonds per particle (directed)".into(),
                format!("{:.3}", self.bonds_per_particle),
            ),
            ("steps".into(), self.steps.to_string()),
            ("threads".into(), self.threads.to_string()),
            ("setup seconds".into(), format!("{:.3}", self.setup_seconds)),
            ("loop seconds".into(), format!("{:.3}", self.loop_seconds)),
            (
                "seconds per step".into(),
                format!("{:.4e}", self.loop_seconds / self.steps as f64),
            ),
            (
                "bond updates per second".into(),
                format!("{:.4e}", self.bond_updates_per_second),
            ),
            ("bytes per bond".into(), format!("{:.1}", self.bytes_per_bond)),
            (
                "pairs evaluated twice per pair".into(),
                format!("{:.4}", self.halo_pairs_per_pair),
            ),
            ("peak RSS (MB)".into(), rss),
            ("processes".into(), self.ranks.to_string()),
            (
                "energy (J) before / after".into(),
                format!("{:.6e} / {:.6e}", self.initial_energy, self.final_energy),
            ),
            ("energy drift".into(), format!("{:.3e}", self.energy_drift)),
        ];
        let mut rows = rows.to_vec();
        if self.ranks > 1 {
            let mb = |m: Option<f64>| m.map_or("-".to_string(), |m| format!("{m:.0}"));
            for (q, r) in self.per_rank.iter().enumerate() {
                rows.push((
                    format!("rank {q}"),
                    format!(
                        "{} particles, {} ghosts, {} directed bonds, {:.3} s; peak / resident MB {} / {}",
                        r.particles,
                        r.ghosts,
                        r.directed_bonds,
                        r.loop_seconds,
                        mb(r.peak_rss_mb),
                        mb(r.resident_mb)
                    ),
                ));
            }
        }
        let width = rows.iter().map(|r| r.0.chars().count()).max().unwrap_or(0);
        rows.iter()
            .map(|(k, v)| format!("{k:<width$}  {v}\n"))
            .collect()
    }
}

/// Runs the benchmark in a rayon pool of the requested size; with `comm` (the ranks of
/// `mpirun`), decomposed as `pdcontact run` decomposes a body: each rank owns a range of the
/// Morton-ordered particles with equal bond counts, builds and evaluates only the pairs that
/// touch them and receives its ghosts' positions every step. The energies are summed in
/// blocks in a fixed order, so any number of threads and ranks reports the same bits.
pub fn run_lattice_sphere(spec: &LatticeSphere, comm: Option<&dyn Comm>) -> Result<BenchReport> {
    if !(spec.spacing > 0.0 && spec.spacing.is_finite() && spec.spacing < RADIUS) {
        return Err(Error::input(format!(
            "--lattice-sphere: the spacing must be a length in (0, {RADIUS}) m, got {}",
            spec.spacing
        )));
    }
    if !(spec.horizon_factor >= 1.0 && spec.horizon_factor <= 10.0) {
        return Err(Error::input(format!(
            "--horizon-factor must be in [1, 10], got {}",
            spec.horizon_factor
        )));
    }
    if spec.steps == 0 {
        return Err(Error::input("--steps must be at least 1"));
    }
    let estimate = 4.0 / 3.0 * std::f64::consts::PI * (RADIUS / spec.spacing).powi(3);
    if estimate > MAX_PARTICLES {
        return Err(Error::input(format!(
            "--lattice-sphere {}: about {estimate:.2e} particles, more than {MAX_PARTICLES:.0e}",
            spec.spacing
        )));
    }
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(n) = spec.threads {
        if n == 0 {
            return Err(Error::input("--threads must be at least 1"));
        }
        builder = builder.num_threads(n);
    }
    let pool = builder
        .build()
        .map_err(|e| Error::input(format!("cannot start the thread pool: {e}")))?;
    let comm = comm.filter(|c| c.size() > 1);
    Ok(pool.install(|| run_in_pool(spec, comm)))
}

/// The lattice points of spacing `dx` within the sphere, in Morton order.
pub fn lattice_sphere(dx: f64) -> Vec<Vec3> {
    let n = (RADIUS / dx).floor() as i64 + 1;
    let mut points = Vec::new();
    for k in -n..=n {
        for j in -n..=n {
            for i in -n..=n {
                let p = Vec3::new(i as f64 * dx, j as f64 * dx, k as f64 * dx);
                // As LAMMPS's `region sphere`: inside when r ≤ R.
                if p.norm() <= RADIUS {
                    points.push(p);
                }
            }
        }
    }
    let coords: Vec<[f64; 3]> = points.iter().map(|p| [p.x, p.y, p.z]).collect();
    let mut order: Vec<u32> = (0..points.len() as u32).collect();
    sort_morton(&mut order, &coords, dx);
    order.iter().map(|&k| points[k as usize]).collect()
}

fn run_in_pool(spec: &LatticeSphere, comm: Option<&dyn Comm>) -> BenchReport {
    let threads = rayon::current_num_threads();
    let start = Instant::now();
    let dx = spec.spacing;
    let horizon = spec.horizon_factor * dx;
    let x = lattice_sphere(dx);
    let n = x.len();
    let volume = dx * dx * dx;
    let c = micromodulus(YOUNGS, horizon);
    let weight = |pairs: &BondList, _: usize, b: usize| {
        let l = pairs.length(b);
        (c * volume_correction(l, horizon, dx) * volume * volume / l) as f32
    };
    // A rank builds only the pairs that touch its particles (counted first, to cut the
    // particles by cost) and learns which ghosts it reads; its memory is its part's.
    let (list, own, ghosts, directed, bond_bytes) = match comm {
        Some(c) => {
            let rows = count_pairs(&x, horizon);
            let pairs: usize = rows.iter().sum();
            let cost: Vec<usize> = rows.iter().map(|r| r + 1).collect();
            drop(rows);
            // Each rank's rows and the pairs reaching into them from earlier particles, which
            // it holds too, come to equal shares.
            let ranges = cut_by_rows(&x, n, Reach::Uniform(horizon), &cost, c);
            drop(cost);
            let own = ranges[c.rank()].clone();
            let list = PairList::from_pairs(build_pairs_touching(&x, horizon, own.clone()), weight)
                .owning(own.clone());
            let ghosts = Ghosts::new(c, &ranges, &list.particles_read());
            // The whole list's figures, as one process reports them: a pair holds a partner,
            // a length and a weight (4 bytes each); the offsets two words a particle.
            let bytes = 12 * pairs + 2 * (n + 1) * std::mem::size_of::<usize>();
            (list, own, ghosts, 2 * pairs, bytes)
        }
        None => {
            let whole = PairList::from_pairs(build_pairs(&x, horizon), weight);
            let (directed, bytes) = (whole.directed_bonds(), whole.bytes());
            (whole, 0..n, Ghosts::default(), directed, bytes)
        }
    };
    let mass = DENSITY * volume;
    // Force and velocity of each own particle, side by side: the force pass kicks the
    // velocity. The reference positions are not needed again (finite kinematics).
    let mut state: Vec<(Vec3, Vec3)> = x[own.clone()]
        .par_iter()
        .map(|p| (Vec3::zeros(), p * RATE))
        .collect();
    let mut y = x;
    let mut buffers = ForceBuffers::default();
    pair_forces(
        &list,
        &y,
        PairKinematics::Finite,
        &mut buffers,
        &mut state,
        |_, force, s| s.0 = force,
    );
    let setup_seconds = start.elapsed().as_secs_f64();
    let initial_energy = energy(&y, &state, &list, mass, own.clone(), comm);

    let half = 0.5 * DT / mass;
    let start = Instant::now();
    for _ in 0..spec.steps {
        // Half kick and drift of this process's particles.
        state
            .par_chunks_mut(CHUNK)
            .zip(y[own.clone()].par_chunks_mut(CHUNK))
            .for_each(|(s, y)| {
                for ((f, v), y) in s.iter_mut().zip(y) {
                    *v += *f * half;
                    *y += *v * DT;
                }
            });
        if let Some(c) = comm {
            ghosts.share(c, &mut y);
        }
        // Forces at the new positions, with the second half kick in the same pass.
        pair_forces(
            &list,
            &y,
            PairKinematics::Finite,
            &mut buffers,
            &mut state,
            |_, force, (f, v)| {
                *f = force;
                *v += force * half;
            },
        );
    }
    let loop_seconds = start.elapsed().as_secs_f64();
    let final_energy = energy(&y, &state, &list, mass, own.clone(), comm);
    let mine = RankFigures {
        particles: own.len(),
        ghosts: ghosts.count(),
        directed_bonds: list.directed_bonds(),
        peak_rss_mb: peak_rss_mb(),
        resident_mb: resident_mb(),
        loop_seconds,
    };
    let per_rank = match comm {
        Some(c) => {
            let mb = |m: Option<f64>| m.unwrap_or(f64::NAN);
            let all = c.all_gather(&[
                mine.particles as f64,
                mine.ghosts as f64,
                mine.directed_bonds as f64,
                mb(mine.peak_rss_mb),
                mb(mine.resident_mb),
                mine.loop_seconds,
            ]);
            let known = |v: f64| (!v.is_nan()).then_some(v);
            all.chunks_exact(6)
                .map(|r| RankFigures {
                    particles: r[0] as usize,
                    ghosts: r[1] as usize,
                    directed_bonds: r[2] as usize,
                    peak_rss_mb: known(r[3]),
                    resident_mb: known(r[4]),
                    loop_seconds: r[5],
                })
                .collect()
        }
        None => vec![mine],
    };
    // The run takes as long as its slowest rank.
    let loop_seconds = per_rank.iter().map(|r| r.loop_seconds).fold(0.0, f64::max);
    BenchReport {
        particles: n,
        bonds_per_particle: directed as f64 / n.max(1) as f64,
        steps: spec.steps,
        threads,
        loop_seconds,
        setup_seconds,
        bond_updates_per_second: directed as f64 * spec.steps as f64 / loop_seconds,
        peak_rss_mb: peak_rss_mb(),
        initial_energy,
        final_energy,
        energy_drift: (final_energy - initial_energy).abs() / initial_energy.abs(),
        bytes_per_bond: bond_bytes as f64 / directed.max(1) as f64,
        halo_pairs_per_pair: buffers.halo_pairs_per_pair(&list),
        ranks: per_rank.len(),
        per_rank,
    }
}

/// Kinetic energy `Σ ½ m v²` plus strain energy `½ Σ_pairs w (|y| − L)²`, over the particles
/// `own` (all without `comm`; `state` holds those alone) and summed over the ranks. Both sums
/// go block by block of particles in a fixed order, so that the energies reported show whether
/// two runs (of any thread or rank count) agree bit for bit. Collective with `comm`; the
/// ghosts' positions must be current.
fn energy(
    y: &[Vec3],
    state: &[(Vec3, Vec3)],
    list: &PairList,
    mass: f64,
    own: std::ops::Range<usize>,
    comm: Option<&dyn Comm>,
) -> f64 {
    let first = own.start;
    let mut mine = crate::reduction::block_sums(
        own,
        || 0.0,
        |i| 0.5 * mass * state[i - first].1.norm_squared(),
        |a, b| a + b,
    );
    mine.extend(list.strain_blocks(y));
    let parts = match comm {
        Some(c) => c.all_gather_varcount(&mine),
        None => vec![mine],
    };
    // Every rank holds as many strain blocks as kinetic ones (its rows are its particles).
    let fold = |second: bool| {
        parts.iter().fold(0.0, |a, p| {
            let (k, s) = p.split_at(p.len() / 2);
            (if second { s } else { k }).iter().fold(a, |a, b| a + b)
        })
    };
    fold(false) + fold(true)
}

#[cfg(test)]
mod tests;
