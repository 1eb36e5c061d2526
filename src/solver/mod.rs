//! Time integration: adaptive dynamic relaxation (or the static solver, Newton-Raphson) for
//! quasi-static scenes and explicit velocity Verlet for dynamics (paper Sec. 2.3, METHOD.md
//! §6).
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
//!
//! | what | where |
//! |---|---|
//! | ADR: the fictitious density, the load increments, the relaxation | `adr.rs` ([`adr`]) |
//! | velocity Verlet, the stable step, the energy balance | `explicit.rs` ([`explicit`], [`stable_time_step`]) |
//! | ADR: a loaded body gone past everything it is in contact with | `unheld.rs` ([`Unheld`]) |
//! | static: Newton-Raphson, conjugate gradients, line search, load cut-backs | `newton.rs` ([`newton`]) |
//! | the state an increment starts from, saved and put back when it is cut back | `state.rs` |
//! | static: the matrix-free tangent and its block-Jacobi preconditioner | `tangent.rs` |
//! | static: the preconditioner's coarse space, the rigid modes of boxes of particles, and its matrix's inverse | `coarse/` |
//! | the monitor, the statistics, the free-direction mask, the checks both share | this module |

mod adr;
mod cluster;
mod coarse;
mod dofs;
mod explicit;
mod krylov;
mod newton;
mod predict;
mod springs;
mod state;
mod tangent;
mod unheld;

use rayon::prelude::*;

pub use adr::adr;
pub use explicit::{explicit, stable_time_step};
pub use newton::newton;
pub use unheld::Unheld;

use crate::body::{Body, FIX_X, FIX_Y, FIX_Z};
use crate::error::{Error, Result};
use crate::math::Vec3;
use crate::model::Model;
use crate::scene::{Motion, SolverKind, SolverSpec};

/// Default ADR tolerance.
pub const DEFAULT_TOLERANCE: f64 = 1e-4;
/// Default ADR iteration cap.
pub const DEFAULT_MAX_ITERATIONS: usize = 200_000;
/// Default cap on the static solver's Newton iterations, over all load increments.
pub const DEFAULT_NEWTON_ITERATIONS: usize = 500;
/// Default fraction of the stable time step.
pub const DEFAULT_SAFETY: f64 = 0.8;
/// Receives the solver's progress and frames.
pub trait Monitor {
    /// Called after every step with the step number, the (pseudo-)time and the residual
    /// (ADR) or the kinetic energy (explicit). Return an error to stop the run.
    fn step(&mut self, model: &Model, step: usize, time: f64, measure: f64) -> Result<()>;
    /// ADR: called before each load increment with the fraction of the full load it applies
    /// (`1/load_steps`, …, 1) and the last iteration of the increment before (0 before the
    /// first), in the state that increment ended in.
    fn load_increment(&mut self, _model: &Model, _factor: f64, _iteration: usize) -> Result<()> {
        Ok(())
    }
    /// ADR: the increment that began with the last [`Monitor::load_increment`] lost a slave
    /// at `iteration` and starts again from the equilibrium at load factor `done` towards
    /// `target` (the next [`Monitor::load_increment`]).
    fn cut_back(
        &mut self,
        _model: &Model,
        _done: f64,
        _target: f64,
        _iteration: usize,
    ) -> Result<()> {
        Ok(())
    }
    /// ADR and the static solver: called after each load increment that reached
    /// equilibrium, with the load factor it reached and the last iteration, in that
    /// equilibrium (a decomposed model gathered).
    fn increment_done(&mut self, _model: &Model, _factor: f64, _iteration: usize) -> Result<()> {
        Ok(())
    }
    /// The static solver: called after each Newton iteration's linear solve with the
    /// conjugate-gradient iterations of the run so far (the next [`Monitor::step`] reports
    /// the iteration's residual).
    fn linear_iterations(&mut self, _total: usize) {}
    /// The static solver: ADR takes over from a stalled Newton increment (`true`) and hands
    /// back (`false`); its iterations come as [`Monitor::step`]s in between.
    fn relaxation(&mut self, _on: bool) {}
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
    /// "adr", "static" or "explicit".
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
    /// Explicit: the energy's terms at the start and at the end (J).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub energy: Option<[EnergyTerms; 2]>,
    /// Explicit: contact force was seen, then fell back to zero (the body bounced off).
    pub rebounded: bool,
    /// The run was interrupted by the user.
    pub interrupted: bool,
    /// ADR: the body that went past everything it is in contact with, which stopped the run
    /// ([`Unheld`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unheld: Option<Unheld>,
    /// Static: conjugate-gradient iterations over all Newton iterations.
    #[serde(skip_serializing_if = "is_zero")]
    pub linear_iterations: usize,
    /// Static: force evaluations (the residual at each Newton iteration and each line-search
    /// trial).
    #[serde(skip_serializing_if = "is_zero")]
    pub force_evaluations: usize,
    /// Static: ADR iterations taken where Newton stalled (from the state it stalled at).
    #[serde(skip_serializing_if = "is_zero")]
    pub relaxation_iterations: usize,
    /// Static: load steps halved because an increment did not converge; ADR: because a slave
    /// went through its master in an increment's transient.
    #[serde(skip_serializing_if = "is_zero")]
    pub cutbacks: usize,
    /// Static: equilibria found again at the same load after bonds broke at one.
    #[serde(skip_serializing_if = "is_zero")]
    pub refailed: usize,
    /// Static: the share of the load at the last equilibrium found (1 when converged).
    #[serde(skip_serializing_if = "is_zero_f64")]
    pub load_factor: f64,
    /// ADR under displacement control (a rigid body with `motion = "displacement"`): the
    /// state at the end of each increment, the points of a load-displacement curve.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub increments: Vec<Increment>,
}

/// The terms of an explicit run's energy balance at one instant (J): what the bodies hold
/// (`kinetic + strain + contact`) less the work done on them (`work`) plus what left the
/// mechanics (`dissipated` by damping and friction, `fracture`: the strain energy broken
/// bonds held when they broke) stays what it was at the start.
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct EnergyTerms {
    pub kinetic: f64,
    pub strain: f64,
    pub contact: f64,
    /// Work of the applied loads and of driven rigid bodies.
    pub work: f64,
    pub dissipated: f64,
    pub fracture: f64,
}

impl EnergyTerms {
    /// What the bodies hold.
    pub fn physical(&self) -> f64 {
        self.kinetic + self.strain + self.contact
    }

    /// The conserved total: `physical − work + dissipated + fracture`.
    pub fn total(&self) -> f64 {
        self.physical() - self.work + self.dissipated + self.fracture
    }
}

/// One load increment's end under displacement control.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct Increment {
    /// The share of the whole displacement (and of the loads) applied.
    pub factor: f64,
    /// The driven body's name and its displacement, m.
    pub body: String,
    pub displacement: [f64; 3],
    /// The contact force on the driven body: the reaction that drives the others, N.
    pub reaction: [f64; 3],
    /// Whether the increment relaxed to the tolerance, and its last iteration.
    pub converged: bool,
    pub iteration: usize,
    /// Bonds broken so far, over all bodies.
    pub broken_bonds: usize,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

fn is_zero_f64(x: &f64) -> bool {
    *x == 0.0
}

/// Fixed-component mask as a per-axis factor (0 fixed, 1 free).
#[inline]
pub fn free_factor(mask: u8) -> Vec3 {
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
        SolverKind::Static => newton(
            model,
            spec.tolerance.unwrap_or(DEFAULT_TOLERANCE),
            spec.max_iterations.unwrap_or(DEFAULT_NEWTON_ITERATIONS),
            spec.load_steps.unwrap_or(1),
            monitor,
        ),
        SolverKind::Explicit => explicit(model, spec, monitor),
    }
}

/// Norm of the applied loads on the free degrees of freedom at the current load factor: the
/// reference force of ADR's and the static solver's convergence test.
pub(super) fn applied_norm(model: &Model) -> f64 {
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

/// Every body's full loads (per particle, or a rigid body's whole), for [`scale_loads`].
pub(super) fn full_loads(model: &Model) -> Vec<(Vec<Vec3>, Vec3)> {
    model
        .bodies
        .iter()
        .map(|b| match b {
            Body::Deformable(pd) => (pd.load.clone(), Vec3::zeros()),
            Body::Rigid(rb) => (Vec::new(), rb.load),
        })
        .collect()
}

/// Sets every body's loads to `scale` times the full ones.
pub(super) fn scale_loads(model: &mut Model, full: &[(Vec<Vec3>, Vec3)], scale: f64) {
    for (b, (loads, rigid)) in model.bodies.iter_mut().zip(full) {
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

pub(super) fn check_finite(model: &Model, step: usize, what: &str) -> Result<()> {
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

/// Where every pass that missed a contact has a penalty that, by the Hertz estimate of its
/// pair under the full load, lets a particle sink less than a tenth of the window: the
/// penalty is not what let the slave through. Then what did: with one pass against a
/// deformable master, only the slave's particles are checked against the master's surface
/// (measured: two gmsh tet spheres pressed together, one pass, missed in ADR's first hundred
/// iterations with a penalty that lets a particle sink 2 % of the window; with two passes,
/// or the static solver, converged); else the solver's transient.
/// `None` in a decomposed run (the estimate is made on one process's particles).
fn penalty_not_the_cause(model: &Model) -> Option<String> {
    if model.domain.is_some() {
        return None;
    }
    let missed: Vec<&crate::contact::ContactPass> =
        model.passes.iter().filter(|p| p.missed > 0).collect();
    let estimates = model.contact_resolution();
    let mut worst = 0.0f64;
    for p in &missed {
        let (s, m) = (model.bodies[p.slave].name(), model.bodies[p.master].name());
        let pair = estimates
            .iter()
            .find(|r| (r.slave == s && r.master == m) || (r.slave == m && r.master == s))?;
        let sink = pair.penalty.as_ref()?.penetration;
        worst = worst.max(sink / p.law.window);
    }
    if missed.is_empty() || !(worst < 0.1) {
        return None;
    }
    let one_pass = missed.iter().any(|p| model.is_one_way_deformable(p));
    let what = if one_pass {
        "with one pass only the slave's particles are kept out of the master's surface, not the master's out of the slave's, and ADR's transient can carry a master node into the slave: solve with kind = \"static\" (it converged on every one-pass pair measured), apply the load in more steps (load_steps), or set `two_pass = true` on the [[contact]]"
    } else {
        "the solver's transient carried it through before the contacts took the load: apply the load in steps (load_steps) or solve with kind = \"static\""
    };
    Some(format!(
        "not the penalty, which by Hertz's estimate lets a particle sink {:.1} % of the window under the full load; {what}",
        100.0 * worst
    ))
}

/// The mesh's node number of particle `i` (what a user finds in their mesh).
fn node_id(pd: &crate::body::PdBody, i: u32) -> u64 {
    pd.case.mesh.node_ids[pd.case.particles.node[i as usize] as usize]
}

/// Which particle of pass `pass` went deepest through which segment, in the mesh's numbering.
fn describe_miss(model: &Model, pass: &crate::contact::ContactPass) -> Option<String> {
    let (slave, segment, gap) = pass.deepest_miss?;
    let sb = model.bodies[pass.slave].as_pd()?;
    let x = sb.position(slave as usize);
    let master = &model.bodies[pass.master];
    let corners = match master {
        Body::Deformable(mb) => {
            let mut nodes: Vec<String> = Vec::new();
            for &n in &mb.segments()[segment as usize].nodes {
                let id = node_id(mb, n).to_string();
                if !nodes.contains(&id) {
                    nodes.push(id);
                }
            }
            format!("the segment on nodes {}", nodes.join(", "))
        }
        Body::Rigid(_) => format!("face {segment}"),
    };
    // A breaking body's slave says how much of it is left (a crushed one is let go).
    let damage = if sb.fracture.is_some() {
        format!(", damage {:.2}", sb.damage(slave as usize))
    } else {
        String::new()
    };
    Some(format!(
        "node {} of \"{}\", now at [{:.4e}, {:.4e}, {:.4e}]{damage}, {:.3e} m behind {corners} of \"{}\"",
        node_id(sb, slave),
        sb.name,
        x.x,
        x.y,
        x.z,
        -gap,
        master.name()
    ))
}

/// The cause of a missed contact whose deepest slave is breaking (damage ≥ 0.1): the impact
/// has crushed the material there, and a particle that has lost its bonds behind it is held
/// against the master by the penalty alone (docs/FRACTURE.md, Kalthoff-Winkler).
fn crushed_slave(model: &Model) -> Option<String> {
    let (pass, slave, damage) = model
        .passes
        .iter()
        .filter_map(|p| {
            let (s, _, _) = p.deepest_miss?;
            Some((p, s, model.bodies[p.slave].as_pd()?.damage(s as usize)))
        })
        .find(|&(_, _, d)| d >= 0.1)?;
    let sb = model.bodies[pass.slave].as_pd()?;
    let node = node_id(sb, slave);
    Some(format!(
        "node {node} of \"{}\" is crushed material: it has lost {:.0} % of its bonds (the contact crushed the edge there), the bonds it has left hardly hold it, and the penalty, set for intact surfaces, alone keeps it out of \"{}\"",
        sb.name,
        100.0 * damage,
        model.bodies[pass.master].name()
    ))
}

pub(super) fn check_missed(model: &Model, step: usize, what: &str, dt: Option<f64>) -> Result<()> {
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
        let deepest: Vec<String> = model
            .passes
            .iter()
            .filter_map(|p| describe_miss(model, p))
            .collect();
        // A penalty that Hertz's estimate shows stiff enough did not let the slave through:
        // say so, and what did, rather than blame it.
        let cause = match (crushed_slave(model), penalty_not_the_cause(model)) {
            (Some(c), _) | (None, Some(c)) => c,
            (None, None) => cause,
        };
        let deepest = if deepest.is_empty() {
            String::new()
        } else {
            format!(" (the deepest: {})", deepest.join("; "))
        };
        return Err(Error::numerical(format!(
            "missed contact at {what} {step}: {missed} slave particles are behind a master segment by more than the contact window ({}){deepest}; likely cause: {cause}",
            window.join(", ")
        )));
    }
    Ok(())
}

/// Whether something other than a load drives the model: a rigid body moved at a velocity
/// or to a displacement, or a prescribed displacement.
pub(super) fn driven(model: &Model) -> bool {
    model.bodies.iter().any(|b| match b {
        Body::Rigid(rb) => match rb.motion {
            Motion::Velocity => rb.velocity.norm() > 0.0,
            Motion::Displacement => rb.displacement.norm() > 0.0,
            Motion::Fixed | Motion::Free => false,
        },
        Body::Deformable(_) => false,
    }) || model
        .path
        .prescribed
        .iter()
        .any(|p| p.displacement.norm() > 0.0)
}

/// What the residual of a displacement-driven increment (no applied load) is measured
/// against, with the forces evaluated: the contact forces and the reactions of the
/// prescribed displacements (in a decomposed run, every particle's, gathered first).
pub(super) fn displacement_reference(model: &mut Model) -> f64 {
    model.gather();
    let contact: f64 = model
        .bodies
        .iter()
        .filter_map(Body::as_pd)
        .flat_map(|pd| pd.contact_force.iter())
        .map(|f| f.norm_squared())
        .sum();
    // A prescribed displacement drives through the bonds of the particles it moves: their
    // held components' forces are its reactions.
    let mut held = 0.0;
    for p in &model.path.prescribed {
        let Some(pd) = model.bodies[p.body].as_pd() else {
            continue;
        };
        for &i in &p.particles {
            let f = pd.force[i as usize];
            for a in 0..3 {
                if p.mask & (1 << a) != 0 {
                    held += f[a] * f[a];
                }
            }
        }
    }
    (contact + held).sqrt().max(f64::MIN_POSITIVE)
}

/// The end of an increment under displacement control, for the load-displacement curve.
pub(super) fn record_increment(model: &Model, factor: f64, iteration: usize, stats: &mut RunStats) {
    let Some(rb) = model.bodies.iter().find_map(|b| match b {
        Body::Rigid(rb) if rb.motion == Motion::Displacement => Some(rb),
        _ => None,
    }) else {
        return;
    };
    let broken_bonds = model
        .bodies
        .iter()
        .filter_map(Body::as_pd)
        .filter_map(|pd| pd.fracture.as_ref())
        .map(|f| f.broken)
        .sum();
    stats.increments.push(Increment {
        factor,
        body: rb.name.clone(),
        displacement: rb.translation.into(),
        reaction: rb.contact_force.into(),
        converged: stats.converged,
        iteration,
        broken_bonds,
    });
}
