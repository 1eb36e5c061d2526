//! Time integration: adaptive dynamic relaxation for quasi-static scenes and explicit velocity
//! Verlet for dynamics (paper Sec. 2.3, METHOD.md §6).
//!
//! **ADR** (Kilic & Madenci 2010, Eqs. 27-33, Δt = 1): a fictitious diagonal density
//! `λ_i ≥ ¼ Σ_j |K_ij|` (Eq. 31) from Gershgorin's bound on the bond stiffness `w n⊗n` plus the
//! contact's tangent stiffness `1.5 K δ^{1/2}` at the edge of the window (without it contact
//! makes ADR unstable); damping `c = 2 √(uᵀ ¹K u / uᵀ u)` with the local stiffness of Eq. 33;
//! the velocity update of Eq. 29 with its sign corrected:
//! `v^{n+½} = ((2 − c) v^{n−½} + 2 F/λ) / (2 + c)`. Converged when the out-of-balance force of
//! the free degrees of freedom, `‖R‖₂`, is below `tolerance · ‖F_applied‖₂`.
//!
//! **Explicit**: velocity Verlet with `Δt ≤ Δt_crit = min_i √(2 m_i / (Σ_j w_ij + k_c,i))`,
//! Silling & Askari's bound (`Σ_j (c/|ξ|) V_j` per unit volume) tightened by the contact's
//! largest tangent stiffness `k_c` on every slave particle.
//!
//! Both stop with an error naming the step and the likely cause on NaN, energy growth,
//! displacement growth, ADR divergence and missed contacts.

use rayon::prelude::*;

use crate::body::{Body, FIX_X, FIX_Y, FIX_Z};
use crate::error::{Error, Result};
use crate::math::Vec3;
use crate::model::Model;
use crate::reduction::ordered_reduce;
use crate::scene::{Motion, SolverKind, SolverSpec};

/// Default ADR tolerance.
pub const DEFAULT_TOLERANCE: f64 = 1e-4;
/// Default ADR iteration cap.
pub const DEFAULT_MAX_ITERATIONS: usize = 200_000;
/// Default fraction of the stable time step.
pub const DEFAULT_SAFETY: f64 = 0.8;
/// Gershgorin factor of a penalty contact block `k n⊗n` and its reaction: ½ max_α |n_α| ‖n‖₁.
const CONTACT_ROW: f64 = 0.683;

/// Receives the solver's progress and frames.
pub trait Monitor {
    /// Called after every step with the step number, the (pseudo-)time and the residual
    /// (ADR) or the kinetic energy (explicit). Return an error to stop the run.
    fn step(&mut self, model: &Model, step: usize, time: f64, measure: f64) -> Result<()>;
    /// Called once at the end with the last state.
    fn finish(&mut self, model: &Model, step: usize, time: f64) -> Result<()>;
    /// Whether the user asked to stop (Ctrl-C); the solver then writes the last frame and ends.
    fn interrupted(&self) -> bool {
        false
    }
}

/// A monitor that does nothing.
pub struct Silent;
impl Monitor for Silent {
    fn step(&mut self, _: &Model, _: usize, _: f64, _: f64) -> Result<()> {
        Ok(())
    }
    fn finish(&mut self, _: &Model, _: usize, _: f64) -> Result<()> {
        Ok(())
    }
}

/// What a run did.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct RunStats {
    /// "adr" or "explicit".
    pub solver: String,
    pub iterations: usize,
    pub converged: bool,
    /// ADR: final ‖R‖/‖F_applied‖; explicit: not used (0).
    pub residual: f64,
    /// Explicit: simulated time.
    pub time: f64,
    /// Explicit: time step used.
    pub dt: f64,
    /// Explicit: the stable time step estimate.
    pub stable_dt: f64,
    /// Explicit: largest relative drift of the total energy, measured every check.
    pub energy_drift: f64,
    /// Explicit: contact force was seen, then fell back to zero (the body bounced off).
    pub rebounded: bool,
    /// The run was interrupted by the user.
    pub interrupted: bool,
}

/// Fixed-component mask as a per-axis factor (0 fixed, 1 free).
#[inline]
fn free_factor(mask: u8) -> Vec3 {
    Vec3::new(
        (mask & FIX_X == 0) as u8 as f64,
        (mask & FIX_Y == 0) as u8 as f64,
        (mask & FIX_Z == 0) as u8 as f64,
    )
}

/// Runs the solver the scene asks for.
pub fn solve(model: &mut Model, spec: &SolverSpec, monitor: &mut dyn Monitor) -> Result<RunStats> {
    match spec.kind {
        SolverKind::Adr => adr(
            model,
            spec.tolerance.unwrap_or(DEFAULT_TOLERANCE),
            spec.max_iterations.unwrap_or(DEFAULT_MAX_ITERATIONS),
            spec.load_steps.unwrap_or(1),
            monitor,
        ),
        SolverKind::Explicit => explicit(model, spec, monitor),
    }
}

/// ADR's Gershgorin density of the bonds, per particle: ½ max_α Σ_j w_ij |n_α| ‖n‖₁.
fn bond_density(model: &Model) -> Vec<Vec<f64>> {
    model
        .bodies
        .iter()
        .map(|b| match b {
            Body::Deformable(pd) => {
                let mut x = Vec::new();
                pd.case
                    .ghosts
                    .extend_positions(&pd.case.particles.position, &mut x);
                let bonds = &pd.case.bonds;
                (0..pd.len())
                    .into_par_iter()
                    .map(|i| {
                        let mut row = [0.0f64; 3];
                        for b in bonds.range(i) {
                            let n = (x[bonds.partner[b] as usize] - x[i]) / bonds.length(b);
                            let l1 = n.x.abs() + n.y.abs() + n.z.abs();
                            for a in 0..3 {
                                row[a] += f64::from(pd.bond_weight[b]) * n[a].abs() * l1;
                            }
                        }
                        0.5 * row[0].max(row[1]).max(row[2])
                    })
                    .collect()
            }
            Body::Rigid(_) => Vec::new(),
        })
        .collect()
}

/// Norm of the applied loads (the ADR reference force).
fn applied_norm(model: &Model) -> f64 {
    let mut s = 0.0;
    for b in &model.bodies {
        match b {
            Body::Deformable(pd) => {
                for (f, &m) in pd.load.iter().zip(&pd.fixed) {
                    s += f.component_mul(&free_factor(m)).norm_squared();
                }
            }
            Body::Rigid(rb) if rb.motion == Motion::Free => s += rb.load.dot(&rb.axis).powi(2),
            Body::Rigid(_) => {}
        }
    }
    s.sqrt()
}

/// What ADR's per-iteration pass sums over the particles.
#[derive(Clone, Copy, Debug)]
struct AdrSums {
    /// Every displacement and force component finite.
    finite: bool,
    /// `‖R‖₂²` over free degrees of freedom.
    residual: f64,
    /// Numerator and denominator of the damping's Rayleigh quotient (Eq. 33).
    num: f64,
    den: f64,
}

impl Default for AdrSums {
    fn default() -> AdrSums {
        AdrSums {
            finite: true,
            residual: 0.0,
            num: 0.0,
            den: 0.0,
        }
    }
}

impl AdrSums {
    fn add(self, o: AdrSums) -> AdrSums {
        AdrSums {
            finite: self.finite && o.finite,
            residual: self.residual + o.residual,
            num: self.num + o.num,
            den: self.den + o.den,
        }
    }
}

fn check_finite(model: &Model, step: usize, what: &str) -> Result<()> {
    for b in &model.bodies {
        if let Body::Deformable(pd) = b {
            if pd
                .u
                .par_iter()
                .chain(pd.force.par_iter())
                .any(|v| !v.iter().all(|c| c.is_finite()))
            {
                return Err(Error::numerical(format!(
                    "non-finite displacement or force in body \"{}\" at {what} {step}: {}",
                    pd.name,
                    if what == "iteration" {
                        "ADR diverged (likely cause: a penalty stiffness far above the bond stiffness, or a load that pushes a body through a surface)"
                    } else {
                        "the explicit run blew up (likely cause: the time step is above the stable step)"
                    }
                )));
            }
        }
    }
    Ok(())
}

fn check_missed(model: &Model, step: usize, what: &str, dt: Option<f64>) -> Result<()> {
    let missed = model.missed_contacts();
    if missed > 0 {
        let short: usize = model.short_range.iter().map(|p| p.missed).sum();
        let cause = match dt {
            Some(dt) => format!(
                "the impact speed is too high for the time step dt = {dt:.3e} s (a particle moved through the window in one step), or the penalty is too soft for the load"
            ),
            None => "the load pushes particles through the surface: the penalty is too soft for the load (raise the contact radius R) or the load is too large".to_string(),
        };
        if short == missed {
            let d: Vec<String> = model
                .short_range
                .iter()
                .filter(|p| p.missed > 0)
                .map(|p| format!("{:.3e} m", p.distance))
                .collect();
            let cause = match dt {
                Some(dt) => format!(
                    "the impact speed is too high for the time step dt = {dt:.3e} s (a particle crossed the repulsion zone in one step)"
                ),
                None => "the load is more than the short-range repulsion can hold".to_string(),
            };
            return Err(Error::numerical(format!(
                "missed contact at {what} {step}: {missed} slave particles went through the master's surface (short-range contact, d = {}); likely cause: {cause}",
                d.join(", ")
            )));
        }
        let window: Vec<String> = model
            .passes
            .iter()
            .filter(|p| p.missed > 0)
            .map(|p| format!("{:.3e} m", p.law.window))
            .collect();
        return Err(Error::numerical(format!(
            "missed contact at {what} {step}: {missed} slave particles are behind a master segment by more than the contact window ({}); likely cause: {cause}",
            window.join(", ")
        )));
    }
    Ok(())
}

/// Adaptive dynamic relaxation to a static equilibrium, the load applied in `load_steps` equal
/// increments, each relaxed to `tolerance` before the next (1: all at once).
///
/// ADR reaches equilibrium by a damped pseudo-dynamic motion; under a load applied at once, a
/// free rigid body overshoots its equilibrium before the damping catches it. Where the overshoot
/// is large (a punch pressed at a tenth of E into a body with finite kinematics) the body can be
/// driven into a state it does not come back from; increments keep each overshoot small.
pub fn adr(
    model: &mut Model,
    tolerance: f64,
    max_iterations: usize,
    load_steps: usize,
    monitor: &mut dyn Monitor,
) -> Result<RunStats> {
    // Without a load or a moving body the equilibrium is the reference state: there is
    // nothing to iterate for, and no force to measure the residual against.
    let driven = model.bodies.iter().any(|b| match b {
        Body::Rigid(rb) => rb.motion == Motion::Velocity && rb.velocity.norm() > 0.0,
        Body::Deformable(_) => false,
    });
    if !driven && !(applied_norm(model) > 0.0) {
        return Err(Error::input(
            "nothing loads the model: an ADR (static) run needs a [[load]] with a non-zero force on a body part that is free to move, or a rigid body with motion = \"velocity\"".to_string(),
        ));
    }
    let density = bond_density(model);
    let mut stats = RunStats {
        solver: "adr".into(),
        ..Default::default()
    };
    let steps = load_steps.max(1);
    let full: Vec<(Vec<Vec3>, Vec3)> = model
        .bodies
        .iter()
        .map(|b| match b {
            Body::Deformable(pd) => (pd.load.clone(), Vec3::zeros()),
            Body::Rigid(rb) => (Vec::new(), rb.load),
        })
        .collect();
    let mut n = 0;
    for step in 1..=steps {
        let scale = step as f64 / steps as f64;
        if steps > 1 {
            for (b, (loads, rigid)) in model.bodies.iter_mut().zip(&full) {
                match b {
                    Body::Deformable(pd) => {
                        for (l, f) in pd.load.iter_mut().zip(loads) {
                            *l = f * scale;
                        }
                    }
                    Body::Rigid(rb) => rb.load = rigid * scale,
                }
            }
        }
        n = adr_increment(
            model,
            &density,
            tolerance,
            max_iterations,
            n,
            monitor,
            &mut stats,
        )?;
        if !stats.converged || stats.interrupted {
            break;
        }
    }
    monitor.finish(model, n, n as f64)?;
    Ok(stats)
}

/// One ADR relaxation from the current state to equilibrium under the current loads (Eqs.
/// 27-33), numbering iterations on from `n0`; returns the last iteration's number.
fn adr_increment(
    model: &mut Model,
    density: &[Vec<f64>],
    tolerance: f64,
    max_iterations: usize,
    n0: usize,
    monitor: &mut dyn Monitor,
    stats: &mut RunStats,
) -> Result<usize> {
    stats.converged = false;
    let reference = applied_norm(model);
    model.compute_forces();
    let reference = if reference > 0.0 {
        reference
    } else {
        // Displacement-driven scenes: measure against the contact forces.
        model
            .bodies
            .iter()
            .filter_map(Body::as_pd)
            .flat_map(|pd| pd.contact_force.iter())
            .map(|f| f.norm_squared())
            .sum::<f64>()
            .sqrt()
            .max(f64::MIN_POSITIVE)
    };
    let nb = model.bodies.len();
    let mut prev_f: Vec<Vec<Vec3>> = vec![Vec::new(); nb];
    let mut prev_rf = vec![0.0f64; nb];
    let mut rigid_lambda = vec![0.0f64; nb];
    // The fictitious density of a particle: its bonds' plus its current contact stiffness.
    // Computed where it is used, in the passes below, rather than stored.
    fn lambda_of(density: &[f64], contact_stiffness: &[f64], i: usize) -> f64 {
        density[i] + CONTACT_ROW * contact_stiffness[i]
    }

    let update_rigid_lambda = |model: &Model, rigid_lambda: &mut Vec<f64>| {
        for (k, b) in model.bodies.iter().enumerate() {
            match b {
                Body::Rigid(rb) if rb.motion == Motion::Free => {
                    // Before contact the free body has no stiffness: give it the density of
                    // full contact so that it does not jump.
                    let all: f64 = model
                        .passes
                        .iter()
                        .filter(|p| p.master == k)
                        .map(|p| p.weight * p.law.max_tangent() * p.slaves.len() as f64)
                        .sum();
                    rigid_lambda[k] = rb.contact_stiffness.max(0.05 * all).max(f64::MIN_POSITIVE);
                }
                Body::Rigid(_) | Body::Deformable(_) => {}
            }
        }
    };
    update_rigid_lambda(model, &mut rigid_lambda);

    // Eq. 30: v^{1/2} = F⁰/(2λ); then u¹ = u⁰ + v^{1/2}.
    for (k, b) in model.bodies.iter_mut().enumerate() {
        match b {
            Body::Deformable(pd) => {
                for i in 0..pd.len() {
                    let ff = free_factor(pd.fixed[i]);
                    pd.v[i] = pd.force[i].component_mul(&ff)
                        / (2.0 * lambda_of(&density[k], &pd.contact_stiffness, i));
                    pd.u[i] += pd.v[i];
                }
                prev_f[k] = pd.force.clone();
            }
            Body::Rigid(rb) if rb.motion == Motion::Free => {
                let f = (rb.load + rb.contact_force).dot(&rb.axis);
                rb.axial_speed = f / (2.0 * rigid_lambda[k]);
                rb.translation += rb.axis * rb.axial_speed;
                prev_rf[k] = f;
            }
            Body::Rigid(_) => {}
        }
    }

    let mut best = f64::INFINITY;
    let mut n = n0;
    loop {
        n += 1;
        model.compute_forces();
        update_rigid_lambda(model, &mut rigid_lambda);
        // One pass over each body's particles for the finiteness check, the residual and the
        // damping's Rayleigh quotient (Eqs. 32-33): the bookkeeping of an iteration is then
        // this pass and the update below, next to the force pass.
        let mut sum = AdrSums::default();
        for (k, b) in model.bodies.iter().enumerate() {
            match b {
                Body::Deformable(pd) => {
                    let (dens, prev) = (&density[k], &prev_f[k]);
                    let body = ordered_reduce(
                        pd.len(),
                        AdrSums::default,
                        |i| {
                            let ff = free_factor(pd.fixed[i]);
                            let (u, v, f) = (pd.u[i], pd.v[i], pd.force[i]);
                            let mut s = AdrSums {
                                finite: u.iter().chain(f.iter()).all(|c| c.is_finite()),
                                residual: f.component_mul(&ff).norm_squared(),
                                ..AdrSums::default()
                            };
                            let lam = lambda_of(dens, &pd.contact_stiffness, i);
                            for a in 0..3 {
                                if ff[a] == 0.0 {
                                    continue;
                                }
                                if v[a] != 0.0 {
                                    let k1 = -(f[a] - prev[i][a]) / (lam * v[a]);
                                    s.num += u[a] * k1 * u[a];
                                }
                                s.den += u[a] * u[a];
                            }
                            s
                        },
                        AdrSums::add,
                    );
                    if !body.finite {
                        return Err(Error::numerical(format!(
                            "non-finite displacement or force in body \"{}\" at iteration {n}: ADR diverged (likely cause: a penalty stiffness far above the bond stiffness, or a load that pushes a body through a surface)",
                            pd.name
                        )));
                    }
                    sum = sum.add(body);
                }
                Body::Rigid(rb) if rb.motion == Motion::Free => {
                    let f = (rb.load + rb.contact_force).dot(&rb.axis);
                    let z = rb.translation.dot(&rb.axis);
                    sum.residual += f * f;
                    if rb.axial_speed != 0.0 {
                        sum.num += z * z * (-(f - prev_rf[k]) / (rigid_lambda[k] * rb.axial_speed));
                    }
                    sum.den += z * z;
                }
                Body::Rigid(_) => {}
            }
        }
        check_missed(model, n, "iteration", None)?;
        let r = sum.residual.sqrt();
        let rel = r / reference;
        stats.residual = rel;
        stats.iterations = n;
        best = best.min(rel);
        if rel < tolerance {
            stats.converged = true;
            break;
        }
        if n >= max_iterations {
            break;
        }
        if rel > 1e6 * best.max(1e-12) && n > n0 + 100 {
            return Err(Error::numerical(format!(
                "ADR diverged at iteration {n}: the out-of-balance force grew to {rel:.3e} of the load (it was {best:.3e}); likely cause: contact stiffness far above the bond stiffness"
            )));
        }
        if monitor.interrupted() {
            stats.interrupted = true;
            break;
        }
        let (num, den) = (sum.num, sum.den);
        let c = if den > 0.0 && num > 0.0 {
            (2.0 * (num / den).sqrt()).min(1.9)
        } else {
            0.0
        };

        for (k, b) in model.bodies.iter_mut().enumerate() {
            match b {
                Body::Deformable(pd) => {
                    let dens = &density[k];
                    let pd = &mut **pd;
                    let kc = &pd.contact_stiffness;
                    pd.v.par_iter_mut()
                        .zip(pd.u.par_iter_mut())
                        .zip(prev_f[k].par_iter_mut())
                        .enumerate()
                        .with_min_len(1024)
                        .for_each(|(i, ((v, u), prev))| {
                            let ff = free_factor(pd.fixed[i]);
                            let f = pd.force[i];
                            let lam = lambda_of(dens, kc, i);
                            *v =
                                ((*v * (2.0 - c) + f * (2.0 / lam)) / (2.0 + c)).component_mul(&ff);
                            *u += *v;
                            *prev = f;
                        });
                }
                Body::Rigid(rb) if rb.motion == Motion::Free => {
                    let f = (rb.load + rb.contact_force).dot(&rb.axis);
                    rb.axial_speed =
                        (rb.axial_speed * (2.0 - c) + 2.0 * f / rigid_lambda[k]) / (2.0 + c);
                    rb.translation += rb.axis * rb.axial_speed;
                    prev_rf[k] = f;
                }
                Body::Rigid(rb) if rb.motion == Motion::Velocity => {
                    // A prescribed motion in ADR: one unit of pseudo-time per iteration.
                    rb.translation += rb.velocity;
                }
                Body::Rigid(_) => {}
            }
        }
        monitor.step(model, n, n as f64, rel)?;
    }
    Ok(n)
}

/// The stable explicit time step, tightened for contact: `2/ω_max`, with `ω_max²` the largest
/// eigenvalue of `M⁻¹K`. `K` is the bonds' tangent stiffness `w ξ̂⊗ξ̂` plus, on every slave
/// particle, the contact's largest tangent stiffness (at the edge of the window) along the
/// master normal, taken as the worst direction.
///
/// Silling & Askari's bound `√(2 m_i / Σ_j w_ij)` is safe but, for a horizon of 3Δ, about
/// three times too small: the highest PD mode does not stretch every bond of a particle. So
/// `ω_max²` is estimated by power iteration on `M^{-½} K M^{-½}` (60 steps from a fixed
/// pseudo-random start; the Rayleigh quotient approaches it from below) and raised by 5 %;
/// Gershgorin's bound caps it from above. The result is the step beyond which velocity Verlet
/// grows: 0.8 of it runs clean, 3 times it blows up (tests/dynamics.rs).
pub fn stable_time_step(model: &Model) -> f64 {
    let mut dt = f64::INFINITY;
    for (k, b) in model.bodies.iter().enumerate() {
        if let Body::Deformable(pd) = b {
            let mut contact = vec![0.0f64; pd.len()];
            for p in model.passes.iter() {
                if p.slave == k {
                    for &s in &p.slaves {
                        contact[s as usize] += p.weight * p.law.max_tangent();
                    }
                }
                if p.master == k {
                    for seg in pd.segments() {
                        for &n in &seg.nodes {
                            contact[n as usize] =
                                contact[n as usize].max(p.weight * p.law.max_tangent());
                        }
                    }
                }
            }
            for p in &model.short_range {
                for (c, b) in contact.iter_mut().zip(p.stiffness_bound(k, pd)) {
                    *c += b;
                }
            }
            let omega2 = highest_eigenvalue(pd, &contact);
            if omega2 > 0.0 {
                dt = dt.min(2.0 / omega2.sqrt());
            }
        }
    }
    dt
}

/// Largest eigenvalue of `M⁻¹K` of a body (bond tangent stiffness + a diagonal contact
/// stiffness per particle), by power iteration, bounded by Gershgorin.
fn highest_eigenvalue(pd: &crate::body::PdBody, contact: &[f64]) -> f64 {
    use rayon::prelude::*;
    let n = pd.len();
    let x = &pd.reference;
    let bonds = &pd.case.bonds;
    let ghosts = &pd.case.ghosts;
    let inv_sqrt_m: Vec<f64> = pd.mass.iter().map(|m| 1.0 / m.sqrt()).collect();
    // y = M^{-½} K M^{-½} v, with images mirroring their sources' components.
    let apply = |v: &[Vec3]| -> Vec<Vec3> {
        let scaled: Vec<Vec3> = v.iter().zip(&inv_sqrt_m).map(|(a, s)| a * *s).collect();
        let mut ext = Vec::new();
        ghosts.extend_positions(&scaled, &mut ext);
        // extend_positions reflects points; a displacement reflects the same way about the
        // origin of the plane, so subtract the reflected origin.
        for g in 0..ghosts.source.len() {
            ext[n + g] -= ghosts.reflect(Vec3::zeros(), ghosts.mask[g]);
        }
        (0..n)
            .into_par_iter()
            .map(|i| {
                let mut acc = Vec3::zeros();
                for b in bonds.range(i) {
                    let j = bonds.partner[b] as usize;
                    let e = (x[j] - x[i]) / bonds.length(b);
                    acc += e * (f64::from(pd.bond_weight[b]) * (ext[i] - ext[j]).dot(&e));
                }
                (acc + ext[i] * contact[i]) * inv_sqrt_m[i]
            })
            .collect()
    };
    // Gershgorin: |λ| ≤ max_i (Σ_j 2 w_ij |e_α| ‖e‖₁ + k_c) / m_i.
    let gershgorin = (0..n)
        .map(|i| {
            let mut row = [0.0f64; 3];
            for b in bonds.range(i) {
                let e = (x[bonds.partner[b] as usize] - x[i]) / bonds.length(b);
                let l1 = e.x.abs() + e.y.abs() + e.z.abs();
                for a in 0..3 {
                    row[a] += 2.0 * f64::from(pd.bond_weight[b]) * e[a].abs() * l1;
                }
            }
            (row[0].max(row[1]).max(row[2]) + contact[i]) / pd.mass[i]
        })
        .fold(0.0, f64::max);
    // A fixed pseudo-random start with components of every sign and size.
    let mut seed = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let mut v: Vec<Vec3> = (0..n).map(|_| Vec3::new(next(), next(), next())).collect();
    let mut lambda = 0.0;
    for _ in 0..60 {
        let norm = v.iter().map(|a| a.norm_squared()).sum::<f64>().sqrt();
        if !(norm > 0.0) {
            break;
        }
        v.iter_mut().for_each(|a| *a /= norm);
        let w = apply(&v);
        lambda = v.iter().zip(&w).map(|(a, b)| a.dot(b)).sum::<f64>();
        v = w;
    }
    (1.05 * lambda).min(gershgorin)
}

/// Total energy: kinetic + strain + contact − work of constant applied loads − work done by
/// moving rigid bodies (accumulated by the caller).
fn energies(model: &Model) -> (f64, f64) {
    let mut physical = 0.0;
    let mut work = 0.0;
    for b in &model.bodies {
        match b {
            Body::Deformable(pd) => {
                physical += pd.kinetic_energy() + pd.strain_energy();
                work += pd
                    .load
                    .iter()
                    .zip(&pd.u)
                    .map(|(f, u)| f.dot(u))
                    .sum::<f64>();
            }
            Body::Rigid(rb) if rb.motion == Motion::Free => {
                physical += 0.5 * rb.mass * rb.axial_speed * rb.axial_speed;
                work += rb.load.dot(&rb.axis) * rb.translation.dot(&rb.axis);
            }
            Body::Rigid(_) => {}
        }
    }
    physical += model.contact_energy();
    (physical, work)
}

/// Explicit dynamics by velocity Verlet.
pub fn explicit(
    model: &mut Model,
    spec: &SolverSpec,
    monitor: &mut dyn Monitor,
) -> Result<RunStats> {
    let stable = stable_time_step(model);
    let dt = spec
        .dt
        .unwrap_or(spec.safety.unwrap_or(DEFAULT_SAFETY) * stable);
    let end = spec.end_time.unwrap_or(0.0);
    if !(dt > 0.0 && dt.is_finite()) {
        return Err(Error::input(format!(
            "no usable time step (stable estimate {stable:.3e} s)"
        )));
    }
    let damping = spec.damping.unwrap_or(0.0);
    if !(damping >= 0.0 && damping.is_finite()) {
        return Err(Error::input(format!(
            "solver.damping must be a finite rate >= 0 (1/s), got {damping}"
        )));
    }
    // Velocities are scaled by this once a step; the kinetic energy it removes is booked as
    // dissipated so that the energy balance still holds.
    let decay = (-damping * dt).exp();
    let mut dissipated = 0.0;
    let steps = (end / dt).ceil() as usize;
    let mut stats = RunStats {
        solver: "explicit".into(),
        dt,
        stable_dt: stable,
        ..Default::default()
    };
    let size = model
        .bodies
        .iter()
        .filter_map(Body::as_pd)
        .map(|pd| {
            let (lo, hi) = pd.case.mesh.bbox().unwrap_or(([0.0; 3], [0.0; 3]));
            (Vec3::from(hi) - Vec3::from(lo)).norm()
        })
        .fold(0.0, f64::max);

    model.compute_forces();
    let (e0_phys, w0) = energies(model);
    let mut e0 = e0_phys - w0;
    let mut rigid_work = 0.0;
    let mut e_scale = e0_phys.abs();
    let mut touched = false;
    let mut free_steps = 0usize;
    let check_every = 10;
    let mut step = 0;
    while step < steps {
        step += 1;
        // First half kick and drift.
        for b in model.bodies.iter_mut() {
            match b {
                Body::Deformable(pd) => {
                    for i in 0..pd.len() {
                        let ff = free_factor(pd.fixed[i]);
                        pd.v[i] =
                            (pd.v[i] + pd.force[i] * (0.5 * dt / pd.mass[i])).component_mul(&ff);
                        pd.u[i] += pd.v[i] * dt;
                    }
                }
                Body::Rigid(rb) => match rb.motion {
                    Motion::Fixed => {}
                    Motion::Velocity => {
                        // Work done on the system by the driven body over the step.
                        rigid_work += -rb.contact_force.dot(&(rb.velocity * dt));
                        rb.translation += rb.velocity * dt;
                    }
                    Motion::Free => {
                        if rb.mass > 0.0 {
                            let f = (rb.load + rb.contact_force).dot(&rb.axis);
                            rb.axial_speed += 0.5 * dt * f / rb.mass;
                            rb.translation += rb.axis * (rb.axial_speed * dt);
                        }
                    }
                },
            }
        }
        model.compute_forces();
        for b in model.bodies.iter_mut() {
            match b {
                Body::Deformable(pd) => {
                    for i in 0..pd.len() {
                        let ff = free_factor(pd.fixed[i]);
                        pd.v[i] =
                            (pd.v[i] + pd.force[i] * (0.5 * dt / pd.mass[i])).component_mul(&ff);
                    }
                }
                Body::Rigid(rb) if rb.motion == Motion::Free && rb.mass > 0.0 => {
                    let f = (rb.load + rb.contact_force).dot(&rb.axis);
                    rb.axial_speed += 0.5 * dt * f / rb.mass;
                }
                Body::Rigid(_) => {}
            }
        }
        if damping > 0.0 {
            for pd in model.bodies.iter_mut().filter_map(Body::as_pd_mut) {
                let before = pd.kinetic_energy();
                pd.v.iter_mut().for_each(|v| *v *= decay);
                dissipated += before * (1.0 - decay * decay);
            }
        }
        let t = step as f64 * dt;
        stats.iterations = step;
        stats.time = t;
        check_finite(model, step, "step")?;
        check_missed(model, step, "step", Some(dt))?;
        let contacts = model.contact_count();
        if contacts > 0 {
            touched = true;
            free_steps = 0;
        } else if touched {
            free_steps += 1;
            // Out of contact for 100 steps: the body has left the surface.
            stats.rebounded |= free_steps >= 100;
        }
        // Every step, cheaply: kinetic energy cannot exceed the energy the system holds and
        // has been given. An unstable step makes it explode within a few steps.
        let kinetic: f64 = model
            .bodies
            .iter()
            .map(|b| match b {
                Body::Deformable(pd) => pd.kinetic_energy(),
                Body::Rigid(rb) => 0.5 * rb.mass * rb.axial_speed * rb.axial_speed,
            })
            .sum();
        let supplied: f64 = model
            .bodies
            .iter()
            .map(|b| match b {
                Body::Deformable(pd) => pd
                    .load
                    .iter()
                    .zip(&pd.u)
                    .map(|(f, u)| f.dot(u))
                    .sum::<f64>(),
                Body::Rigid(rb) => rb.load.dot(&rb.translation),
            })
            .sum::<f64>()
            + rigid_work;
        let available = e0_phys.abs() + supplied.abs() + e_scale;
        if !(kinetic <= 1.5 * available + f64::MIN_POSITIVE) {
            return Err(Error::numerical(format!(
                "kinetic energy exploded to {kinetic:.3e} J at step {step} (t = {t:.4e} s), {:.1}x the energy the system holds: the explicit run is unstable; likely cause: the time step dt = {dt:.3e} s is above the stable step ({stable:.3e} s estimated), or the penalty stiffness is too high for it",
                kinetic / available.max(f64::MIN_POSITIVE)
            )));
        }
        if step.is_multiple_of(check_every) || step == steps {
            let (phys, work) = energies(model);
            e_scale = e_scale.max(phys.abs());
            let total = phys - work - rigid_work + dissipated;
            if step == check_every && e0 == 0.0 {
                e0 = total;
            }
            let drift = (total - e0).abs() / e_scale.max(f64::MIN_POSITIVE);
            stats.energy_drift = stats.energy_drift.max(drift);
            if drift > 0.5 {
                return Err(Error::numerical(format!(
                    "energy grew by {:.0} % by step {step} (t = {t:.4e} s): the explicit run is unstable; likely cause: the time step dt = {dt:.3e} s is above the stable step ({stable:.3e} s estimated), or the penalty stiffness is too high for it",
                    100.0 * drift
                )));
            }
            let umax = model
                .bodies
                .iter()
                .filter_map(Body::as_pd)
                .flat_map(|pd| pd.u.iter())
                .map(|u| u.norm())
                .fold(0.0, f64::max);
            if umax > 10.0 * size.max(f64::MIN_POSITIVE) {
                return Err(Error::numerical(format!(
                    "displacement grew to {umax:.3e} m (10x the body size) by step {step}: the run blew up; likely cause: time step dt = {dt:.3e} s"
                )));
            }
        }
        monitor.step(model, step, t, stats.energy_drift)?;
        if spec.stop_after_rebound && stats.rebounded {
            break;
        }
        if monitor.interrupted() {
            stats.interrupted = true;
            break;
        }
    }
    stats.converged = !stats.interrupted;
    monitor.finish(model, step, stats.time)?;
    Ok(stats)
}
