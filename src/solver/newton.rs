//! The static solver: Newton-Raphson on the out-of-balance force of Eq. 28 (METHOD.md §6),
//! with a matrix-free tangent ([`super::tangent`]) solved by conjugate gradients with a
//! block-Jacobi preconditioner (GMRES in an increment's tail, where the contacts between two
//! deformable bodies take their unsymmetric consistent springs: [`super::krylov`]), a line
//! search, and load increments that cut back by themselves.
//!
//! Each Newton iteration solves `A d = S⁻¹ R` (the tangent and the out-of-balance force of the
//! free degrees of freedom, rows divided by each particle's share) to a relative residual
//! `η` that tightens as the out-of-balance force nears the tolerance (inexact Newton: no
//! more conjugate-gradient iterations than the next Newton step can use), solved again with
//! the contacts that the step makes ([`super::predict`]) until they stop changing, then looks along
//! `d` for the point where the energy's slope `d·R(u + αd)` has fallen to half its value
//! at `α = 0` (regula falsi, at most [`LINE_SEARCH`] force evaluations; a trial state with a
//! missed contact, or one the step's linearisation carries a slave through its master
//! ([`predict::Reach`]), is a step too long), unless the whole step is sound and brings slaves into
//! contact that were not: that step is taken whole, so that the contact does not grow by one
//! ring of slaves per iteration. An increment whose residual stops falling once its
//! contacts have settled ([`STALL_WINDOW`]) is handed to ADR from the state Newton reached:
//! between two deformable bodies the rim of a stiff contact can cycle, each Newton step
//! pressing another rim slave in with a force its bonds do not carry yet, where ADR's damped
//! steps settle it (docs/PERFORMANCE.md, "The static solver"); so is one where Newton gives
//! up (no descent direction, no sound step along it, [`NEWTON_PER_INCREMENT`] iterations).
//! An increment that ADR does not bring to the tolerance either starts again from the last
//! equilibrium with half the load step, down to [`MIN_STEP`] of the load. Converged, as
//! ADR, when `‖R‖₂` over the free degrees of freedom is below `tolerance · ‖F_applied‖₂` (a
//! run driven by displacements alone: against the contact forces and the prescribed
//! displacements' reactions).
//!
//! The load path is ADR's ([`crate::model::path`]): ramped loads, prescribed displacements and
//! driven bodies set at each increment's load factor, and friction's stick points kept from
//! the end of one increment to the next (METHOD.md §10). Each increment after the second
//! starts from the line through the last two equilibria.

use super::coarse::CoarseSpace;
use super::dofs::Dofs;
use super::krylov;
use super::predict;
use super::state::State;
use super::tangent::{scale_and_mask, Tangent};
use super::{
    applied_norm, check_missed, displacement_reference, driven, free_factor, full_loads,
    record_increment, scale_loads, Monitor, RunStats,
};
use crate::body::Body;
use crate::error::{Error, Result};
use crate::model::Model;
use crate::scene::Motion;

/// Newton iterations an increment may take before ADR takes it over.
pub const NEWTON_PER_INCREMENT: usize = 60;
/// Force evaluations a line search may take.
pub const LINE_SEARCH: usize = 8;
/// The smallest load step before the solver gives up, as a share of the whole load.
pub const MIN_STEP: f64 = 1.0 / 1024.0;
/// Conjugate-gradient iterations a linear solve may take.
pub const MAX_LINEAR: usize = 3_000;
/// The loosest relative residual of a linear solve.
const ETA_MAX: f64 = 0.1;
/// Below this many tolerances (an increment past its first iterations, where the contacts
/// form) a contact between two deformable bodies gets its consistent spring
/// ([`super::springs`]), and Newton converges in fewer iterations. Above, the symmetric one
/// and conjugate gradients: the contact set is still moving. With the nodal normals'
/// derivative in the spring, 10⁴ took the gmsh sphere pairs in 8-46 % fewer Newton
/// iterations than the 100 before; 10⁶ sent a pair with one pass to GMRES solves of
/// thousands of products (docs/PERFORMANCE.md, "The nodal normals' derivative").
const CONSISTENT_BELOW: f64 = 1e4;
/// Newton iterations over which an increment whose contacts no longer change must at least
/// halve its best residual; else it has stalled and ADR takes over ([`stalled`]).
pub const STALL_WINDOW: usize = 10;
/// Bonds that may fail are tested once an increment's residual is within this many times the
/// tolerance. On the notched beam of `pdcontact fracture` (docs/FRACTURE.md) testing only at
/// the tolerance gave the same peak (63.71 N against 63.70) in 2.8 times the time (60 s, 834
/// Newton iterations, against 21 s, 322).
pub const FAILURE_TEST: f64 = 100.0;

/// Refuses what the static solver does not handle, with the reason and what to use instead.
fn supported(model: &Model) -> Result<()> {
    if model.domain.is_some() {
        return Err(Error::input(
            "the static solver runs in one process (its conjugate-gradient solves are not yet decomposed over MPI ranks): run it without mpirun, or use kind = \"adr\" under mpirun".to_string(),
        ));
    }
    if !model.short_range.is_empty() || !model.fragments.is_empty() {
        return Err(Error::input(
            "the static solver has the tangent of the point-to-surface contact only: use method = \"point-to-surface\" in every [[contact]], or kind = \"adr\" for the short-range method".to_string(),
        ));
    }
    for b in &model.bodies {
        if let Body::Rigid(rb) = b {
            if rb.motion == Motion::Velocity && rb.velocity.norm() > 0.0 {
                return Err(Error::input(format!(
                    "rigid body \"{}\" moves at a velocity, which has no meaning in a static run: give it motion = \"free\" with a [[load]], or use kind = \"adr\" (one unit of pseudo-time per iteration) or \"explicit\"",
                    rb.name
                )));
            }
        }
    }
    Ok(())
}

/// The out-of-balance force of the free degrees of freedom (the model's forces evaluated),
/// rows divided by the particles' shares (`S⁻¹ R`), and `‖R‖₂` unscaled.
pub(super) fn residual(model: &Model, out: &mut Dofs) -> f64 {
    let mut sq = 0.0;
    for (k, b) in model.bodies.iter().enumerate() {
        match b {
            Body::Deformable(pd) => {
                for (i, (o, f)) in out.pd[k].iter_mut().zip(&pd.force).enumerate() {
                    *o = f.component_mul(&free_factor(pd.fixed[i]));
                    sq += o.norm_squared();
                }
            }
            Body::Rigid(rb) => {
                out.rigid[k] = (rb.load + rb.contact_force).dot(&rb.axis);
                if rb.motion == Motion::Free {
                    sq += out.rigid[k].powi(2);
                }
            }
        }
    }
    scale_and_mask(model, out);
    sq.sqrt()
}

/// Whether the forces just evaluated are usable: finite, and no slave through its master.
fn sound(model: &Model) -> bool {
    model.missed_contacts() == 0
        && model.bodies.iter().all(|b| match b {
            Body::Deformable(pd) => pd
                .force
                .iter()
                .chain(&pd.u)
                .all(|v| v.iter().all(|c| c.is_finite())),
            Body::Rigid(rb) => rb.translation.iter().all(|c| c.is_finite()),
        })
}

/// What the solver counts.
#[derive(Default)]
struct Counts {
    newton: usize,
    linear: usize,
    /// ADR iterations where Newton stalled ([`relax`]).
    relaxed: usize,
}

impl Counts {
    /// The run's step number for progress and frames: Newton iterations and ADR's
    /// relaxation iterations together, so that frames follow one another.
    fn step(&self) -> usize {
        self.newton + self.relaxed
    }
}

/// How an increment ended.
enum Increment {
    Converged,
    /// No equilibrium within the iterations, or a line search that found no usable state.
    Failed(String),
    Interrupted,
}

/// Newton-Raphson to a static equilibrium, the load applied in `load_steps` equal increments
/// (cut back by halves where one does not converge); `max_iterations` caps the Newton
/// iterations of the whole run.
pub fn newton(
    model: &mut Model,
    tolerance: f64,
    max_iterations: usize,
    load_steps: usize,
    monitor: &mut dyn Monitor,
) -> Result<RunStats> {
    supported(model)?;
    model.hold_bonds = true;
    let out = solve(model, tolerance, max_iterations, load_steps, monitor);
    model.hold_bonds = false;
    out
}

/// [`newton`], its bonds held in force evaluations.
fn solve(
    model: &mut Model,
    tolerance: f64,
    max_iterations: usize,
    load_steps: usize,
    monitor: &mut dyn Monitor,
) -> Result<RunStats> {
    if !driven(model) && !(applied_norm(model) > 0.0) {
        return Err(Error::input(
            "nothing loads the model: a static run needs a [[load]] with a non-zero force on a body part that is free to move, a [[constraint]] with a non-zero displacement, or a rigid body with motion = \"displacement\"".to_string(),
        ));
    }
    let stiffness: Vec<Vec<f64>> = model
        .bodies
        .iter()
        .map(|b| b.as_pd().map_or(Vec::new(), |pd| pd.stiffness.clone()))
        .collect();
    super::adr::unbonded_particles(model, &stiffness)?;
    let mut stats = RunStats {
        solver: "static".into(),
        ..Default::default()
    };
    let full = full_loads(model);
    let nominal = 1.0 / load_steps.max(1) as f64;
    let mut step = nominal;
    let mut done = 0.0;
    let mut saved = State::of(model);
    // The equilibrium before the last and its load factor: the predictor's other point.
    let mut before: Option<(State, f64)> = None;
    let mut counts = Counts::default();
    let mut bond_blocks = vec![None; model.bodies.len()];
    let mut coarse = CoarseSpace::new(model);
    while done < 1.0 {
        let target = if done + step > 1.0 - 1e-12 {
            1.0
        } else {
            done + step
        };
        // Along a path walked in increments the equilibria lie on a smooth curve between
        // contact changes: start each increment from the line through the last two (a
        // secant predictor), which saves the Newton iterations that would rediscover it,
        // unless that line puts a slave through its master.
        if let Some((was, at)) = &before {
            saved.extrapolate(was, (target - done) / (done - at), model);
            scale_loads(model, &full, target);
            model.path.apply(&mut model.bodies, target);
            model.compute_forces();
            if !sound(model) {
                saved.apply(model, None);
            }
        }
        scale_loads(model, &full, target);
        // Driven bodies, prescribed displacements and ramped loads along the path.
        model.path.apply(&mut model.bodies, target);
        model.gather();
        monitor.load_increment(model, target, counts.step())?;
        let outcome = increment(
            model,
            tolerance,
            max_iterations,
            monitor,
            &mut counts,
            &mut bond_blocks,
            &mut coarse,
            &mut stats,
        )?;
        match outcome {
            Increment::Converged => {
                before = Some((std::mem::replace(&mut saved, State::of(model)), done));
                done = target;
                // The next increment's friction starts from the stick points this one
                // ended with (an increment cut back starts again from the same ones).
                model.commit_friction();
                stats.load_factor = done;
                stats.converged = true;
                record_increment(model, done, counts.step(), &mut stats);
                model.gather();
                monitor.increment_done(model, done, counts.step())?;
                step = (step * 2.0).min(nominal);
            }
            Increment::Interrupted => {
                stats.interrupted = true;
                break;
            }
            Increment::Failed(why) => {
                // ADR, taking over a stalled increment, found a body gone past everything it
                // touches: as in an ADR run, the scene has no static equilibrium to find.
                if counts.newton >= max_iterations || stats.unheld.is_some() {
                    stats.converged = false;
                    break;
                }
                // Half the step that failed (the last one may have been cut short at the
                // path's end: halving the nominal step would try the same target again).
                step = 0.5 * (target - done);
                stats.cutbacks += 1;
                if step < MIN_STEP {
                    return Err(Error::numerical(format!(
                        "the static solver found no equilibrium beyond load factor {done:.4} (the last try: {why}); likely cause: a load that the supports and contacts cannot balance, or contact that opens and closes between iterations; try kind = \"adr\", or more load_steps"
                    )));
                }
                saved.apply(model, None);
                model.compute_forces();
            }
        }
    }
    stats.converged = done >= 1.0 && !stats.interrupted;
    stats.iterations = counts.newton;
    stats.linear_iterations = counts.linear;
    stats.force_evaluations = model.evaluations;
    model.gather();
    monitor.finish(model, counts.step(), counts.step() as f64)?;
    Ok(stats)
}

/// ADR from the current state under the current loads (an increment whose Newton iterations
/// stalled: relaxation damps the rim's cycling that Newton's steps feed); true if it reached
/// the tolerance. Its iterations are counted apart (`relaxation_iterations`).
fn relax(
    model: &mut Model,
    tolerance: f64,
    monitor: &mut dyn Monitor,
    counts: &mut Counts,
    stats: &mut RunStats,
) -> Result<bool> {
    let density = super::adr::bond_density(model);
    let mut relaxed = RunStats::default();
    let start = counts.step();
    monitor.relaxation(true);
    let n = super::adr::adr_increment(
        model,
        &density,
        tolerance,
        start + super::DEFAULT_MAX_ITERATIONS,
        start,
        monitor,
        &mut relaxed,
    );
    monitor.relaxation(false);
    let n = n?;
    counts.relaxed += n - start;
    stats.relaxation_iterations = counts.relaxed;
    stats.residual = relaxed.residual;
    stats.interrupted |= relaxed.interrupted;
    if let Some(u) = relaxed.unheld {
        stats.unheld = Some(u);
    }
    Ok(relaxed.converged)
}

/// Newton iterations at the current loads from the current state.
#[allow(clippy::too_many_arguments)]
fn increment(
    model: &mut Model,
    tolerance: f64,
    max_iterations: usize,
    monitor: &mut dyn Monitor,
    counts: &mut Counts,
    bond_blocks: &mut [Option<Vec<nalgebra::Matrix3<f64>>>],
    coarse: &mut Option<CoarseSpace>,
    stats: &mut RunStats,
) -> Result<Increment> {
    let reference = applied_norm(model);
    model.compute_forces();
    let reference = if reference > 0.0 {
        reference
    } else {
        displacement_reference(model)
    };
    if !sound(model) {
        return Ok(Increment::Failed(
            "the state it starts from has a missed contact".into(),
        ));
    }
    let mut rhs = Dofs::zeros(model);
    let mut d = Dofs::zeros(model);
    let mut work = [Dofs::zeros(model), Dofs::zeros(model), Dofs::zeros(model)];
    let mut stabilise = 1.0;
    let mut previous: Option<f64> = None;
    let mut previous_tangent: Option<Tangent> = None;
    let mut history = Vec::with_capacity(NEWTON_PER_INCREMENT);
    // Newton iterations since the increment started or bonds last broke.
    let mut it = 0;
    // Why Newton gave up on this increment from a sound state: ADR takes over from there
    // before the step is cut back.
    let mut gave_up: Option<String> = None;
    loop {
        let r = residual(model, &mut rhs);
        let rel = r / reference;
        stats.residual = rel;
        monitor.step(model, counts.step(), counts.step() as f64, rel)?;
        // Bonds that may fail are tested once the increment is near its equilibrium, not at
        // the trial states of the line searches (METHOD.md §9): the overstretched ones break,
        // and the iterations go on from there at the same load, until none breaks.
        if rel < FAILURE_TEST * tolerance && model.break_overstretched() > 0 {
            restart(model, bond_blocks, coarse, stats);
            (previous_tangent, previous, it) = (None, None, 0);
            history.clear();
            gave_up = None;
            continue;
        }
        if rel < tolerance {
            check_missed(model, counts.step(), "iteration", None)?;
            return Ok(Increment::Converged);
        }
        history.push((rel, model.contact_count()));
        // The contact's rim cycles (slaves at the rim of a stiff contact between two
        // deformable bodies, each Newton step pressing another in by a fraction of a
        // millimetre with a force its bonds do not carry yet): ADR takes over from here.
        // So does ADR where Newton gave up (no descent direction, no sound step along it,
        // or too many iterations) from a sound state: cutting the step back and walking the
        // load again from the last equilibrium cost the unequal gmsh spheres of
        // docs/VALIDATION.md (154,470 particles, one pass) 7 cut-backs and 441 s, where ADR
        // from the start takes 50 s (docs/PERFORMANCE.md, "The static solver").
        if stalled(&history) || gave_up.is_some() {
            let relaxed = match relax(model, tolerance, monitor, counts, stats) {
                Ok(relaxed) => relaxed,
                // Where Newton gave up, ADR's transient may carry a slave through its master:
                // the step is cut back as it was before ADR took over.
                Err(Error::Numerical(e)) if gave_up.is_some() => {
                    // What went wrong, without the advice meant for an ADR run.
                    let what = e.split("; likely cause").next().unwrap_or(&e);
                    return Ok(Increment::Failed(format!(
                        "{}, and ADR from there stopped: {what}",
                        gave_up.unwrap_or_default()
                    )));
                }
                Err(e) => return Err(e),
            };
            // ADR, its bonds held too, found the equilibrium: its bonds are tested there.
            if relaxed && model.break_overstretched() > 0 {
                restart(model, bond_blocks, coarse, stats);
                (previous_tangent, previous, it) = (None, None, 0);
                history.clear();
                gave_up = None;
                continue;
            }
            return Ok(if relaxed {
                Increment::Converged
            } else if stats.interrupted {
                Increment::Interrupted
            } else {
                Increment::Failed(format!(
                    "{}, and ADR from there did not reach the tolerance",
                    gave_up.unwrap_or_else(|| format!("Newton stalled at residual {rel:.3e}"))
                ))
            });
        }
        if monitor.interrupted() {
            return Ok(Increment::Interrupted);
        }
        if counts.newton >= max_iterations {
            return Ok(Increment::Failed(format!(
                "max_iterations = {max_iterations} Newton iterations reached"
            )));
        }
        counts.newton += 1;
        // In the tail the contacts' consistent (unsymmetric) springs, solved by GMRES.
        let consistent = rel < CONSISTENT_BELOW * tolerance;
        let mut tangent = Tangent::new(
            model,
            stabilise,
            previous_tangent.as_ref(),
            bond_blocks,
            consistent,
        );
        if let Some(space) = coarse.as_ref() {
            tangent.build_coarse(model, space);
        }
        // Inexact Newton (Eisenstat and Walker's second choice): loose while the residual
        // falls slowly, tight as it falls fast, never much tighter than the tolerance needs.
        let eta = match previous {
            Some(p) => (0.9 * (rel / p).powi(2)).min(ETA_MAX),
            None => ETA_MAX,
        }
        .max(0.3 * tolerance / rel)
        .clamp(1e-8, ETA_MAX);
        previous = Some(rel);
        // From zero (`warm` false) or from `d` as it is.
        let mut solve = |m: &mut Model, t: &mut Tangent, b: &Dofs, x: &mut Dofs, warm: bool| {
            krylov::solve(t, coarse.as_ref(), m, b, eta, x, warm, &mut work)
        };
        counts.linear += solve(model, &mut tangent, &rhs, &mut d, false);
        // The contacts the step makes, predicted: the solve again with their springs.
        let (predicted, reach) =
            predict::with_contacts(model, &mut tangent, &rhs, &mut d, |m, t, b, x| {
                solve(m, t, b, x, true)
            });
        counts.linear += predicted;
        // The energy's slope along d: `dᵀR = dᵀS (S⁻¹R)`, the shares put back.
        let mut g0 = d.dot_shares(&rhs, model);
        // The predicted contacts' pull is no part of the residual: where the step they gave
        // does not go down the energy, the plain one.
        if !(g0 > 0.0) && predicted > 0 {
            tangent.predict([], &[]);
            counts.linear += solve(model, &mut tangent, &rhs, &mut d, false);
            g0 = d.dot_shares(&rhs, model);
        }
        monitor.linear_iterations(counts.linear);
        if !(g0 > 0.0) {
            gave_up = Some(format!(
                "Newton iteration {it}: the linear solve gave no descent direction"
            ));
            continue;
        }
        // A failed line search leaves the state it started from (sound).
        let Some(whole_sound) = line_search(model, &d, g0, &reach, &mut rhs) else {
            gave_up = Some(format!(
                "Newton iteration {it}: no step along the Newton direction keeps every slave outside its master"
            ));
            continue;
        };
        // The stabilisation fades while the whole Newton step stays sound. Where it carried a
        // slave through its master, the contacts do not hold the body yet: halved then, the
        // springs let the load move it twice as far at each iteration, and a body that its
        // contacts did not hold went metres through its partner (docs/VALIDATION.md, "A
        // Newton step through the partner").
        if whole_sound {
            stabilise *= 0.5;
        }
        previous_tangent = Some(tangent);
        it += 1;
        if it >= NEWTON_PER_INCREMENT {
            gave_up = Some(format!(
                "{NEWTON_PER_INCREMENT} Newton iterations without reaching the tolerance (residual {:.3e})",
                stats.residual
            ));
        }
    }
}

/// After bonds broke near an equilibrium: their tangent blocks go with them, and Newton starts
/// afresh at the same load from the forces of the bonds left.
fn restart(
    model: &mut Model,
    bond_blocks: &mut [Option<Vec<nalgebra::Matrix3<f64>>>],
    coarse: &mut Option<CoarseSpace>,
    stats: &mut RunStats,
) {
    bond_blocks.iter_mut().for_each(|b| *b = None);
    if let Some(space) = coarse.as_mut() {
        space.reassemble(model);
    }
    stats.refailed += 1;
    model.compute_forces();
}

/// Whether an increment has stalled, from its relative residuals and contact counts so far:
/// over the last `2 STALL_WINDOW` iterations the contact count stayed within 4 % (the contact
/// no longer grows: while it grows ring by ring the residual rises and falls with it), and the
/// best residual of the last [`STALL_WINDOW`] is not half the best of the ones before.
/// Measured: a converging increment halves it within two or three iterations once its
/// contacts settle; one whose rim cycles wanders within a factor of ten for tens of
/// iterations (docs/PERFORMANCE.md, "The static solver").
fn stalled(history: &[(f64, usize)]) -> bool {
    let n = history.len();
    if n < 2 * STALL_WINDOW {
        return false;
    }
    let recent = &history[n - 2 * STALL_WINDOW..];
    let (lo, hi) = recent
        .iter()
        .fold((usize::MAX, 0), |(lo, hi), &(_, c)| (lo.min(c), hi.max(c)));
    if hi - lo > (hi / 25).max(2) {
        return false;
    }
    let best = |h: &[(f64, usize)]| h.iter().map(|&(r, _)| r).fold(f64::INFINITY, f64::min);
    best(&recent[STALL_WINDOW..]) > 0.5 * best(&recent[..STALL_WINDOW])
}

/// Moves the model along `d` to where the energy's slope `d·R` (`R` the out-of-balance
/// force, not divided by the shares) has fallen to half of `g0` (its value at the start), by
/// regula falsi, or the whole step where that is sound and brings more slaves into contact;
/// ends with the forces evaluated at the state taken. `None` if no trial state was sound, else
/// whether the whole step was.
fn line_search(
    model: &mut Model,
    d: &Dofs,
    g0: f64,
    reach: &predict::Reach,
    scratch: &mut Dofs,
) -> Option<bool> {
    let start = State::of(model);
    let contacts = model.contact_count();
    let mut first = true;
    let (mut lo, mut g_lo) = (0.0f64, g0);
    let mut hi: Option<(f64, f64)> = None;
    let mut alpha = 1.0;
    let mut last_sound: Option<f64> = None;
    let mut at = f64::NAN;
    // Which end the last trial replaced: Illinois halves the other end's slope when one end
    // is replaced twice in a row, so that regula falsi does not stall against a convex slope.
    let mut last_side = 0i8;
    let mut whole_sound = true;
    for _ in 0..LINE_SEARCH {
        // A slave carried past the contact search's reach reads as out of contact, not
        // missed: the step's own linearisation tells it, before the forces are evaluated.
        let through = reach.through(model, alpha, d);
        if !through {
            start.apply(model, Some((alpha, d)));
            model.compute_forces();
            at = alpha;
        }
        if through || !sound(model) {
            // Too far: a slave went through. An upper bound with an unknown slope.
            whole_sound &= !first;
            first = false;
            hi = Some((alpha, f64::NEG_INFINITY));
            alpha = 0.5 * (lo + alpha);
            last_side = 0;
            continue;
        }
        residual(model, scratch);
        let g = d.dot_shares(scratch, model);
        last_sound = Some(alpha);
        // The whole step brought slaves into contact that the Newton direction knew nothing
        // of: taken whole, they enter the next tangent pressed in. Cut back to where they
        // just touch (where the energy's slope turns), the contact grew one ring of slaves
        // per iteration (docs/PERFORMANCE.md, "The static solver").
        if g.abs() <= 0.5 * g0 || (first && model.contact_count() > contacts) {
            return Some(whole_sound);
        }
        first = false;
        if g > 0.0 {
            if last_side == 1 {
                if let Some((_, g_hi)) = hi.as_mut() {
                    *g_hi *= 0.5;
                }
            }
            (lo, g_lo) = (alpha, g);
            last_side = 1;
        } else {
            if last_side == -1 {
                g_lo *= 0.5;
            }
            hi = Some((alpha, g));
            last_side = -1;
        }
        alpha = match hi {
            Some((a_hi, g_hi)) if g_hi.is_finite() => {
                let a = lo + g_lo * (a_hi - lo) / (g_lo - g_hi);
                // Keep off the ends: a root pressed against one end is found by halving.
                let (lo_end, hi_end) = (lo + 0.05 * (a_hi - lo), a_hi - 0.05 * (a_hi - lo));
                a.clamp(lo_end, hi_end)
            }
            Some((a_hi, _)) => 0.5 * (lo + a_hi),
            // Still going down at α = lo: further, up to four full steps.
            None if lo < 4.0 => (2.0 * lo).min(4.0),
            None => return Some(whole_sound),
        };
    }
    // The last trial was not good enough: take the last sound state, which lowered the
    // slope or at least kept every contact.
    match last_sound {
        Some(a) => {
            if a != at {
                start.apply(model, Some((a, d)));
                model.compute_forces();
            }
            sound(model).then_some(whole_sound)
        }
        None => {
            start.apply(model, None);
            model.compute_forces();
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::coarse::tests::stacked;
    use super::super::dofs::Dofs;
    use super::super::predict::tests::pressed_with_reach;
    use super::super::{applied_norm, RunStats, Silent};
    use super::{line_search, newton, relax, residual, stalled, Counts, STALL_WINDOW};

    /// Where an increment stalls, ADR takes over from the state Newton left ([`relax`]): on the
    /// two gmsh tet4 spheres pressed together, from Newton's state at a loose tolerance it
    /// reaches the tight one, its iterations counted apart, and the out-of-balance force
    /// evaluated afresh there is within the tolerance.
    #[test]
    fn adr_takes_over_from_where_newton_left_off() {
        let mut model = stacked();
        newton(&mut model, 1e-2, 200, 1, &mut Silent).expect("the pair converges loosely");
        let (mut counts, mut stats) = (Counts::default(), RunStats::default());
        let relaxed =
            relax(&mut model, 1e-5, &mut Silent, &mut counts, &mut stats).expect("ADR runs");
        assert!(relaxed, "ADR stopped at residual {:.3e}", stats.residual);
        assert!(counts.relaxed > 0 && stats.relaxation_iterations == counts.relaxed);
        model.compute_forces();
        let r = residual(&model, &mut Dofs::zeros(&model)) / applied_norm(&model);
        assert!(
            r < 1e-5,
            "residual {r:.3e} after {} ADR iterations",
            counts.relaxed
        );
    }

    /// The line search says whether the whole Newton step was sound, which decides whether
    /// the stabilisation fades: on the pressed pair, a step carrying the upper sphere five
    /// contact windows down is cut back to a sound state and reported as not sound whole; a
    /// step of a hundredth of the window is taken whole.
    #[test]
    fn the_line_search_tells_a_whole_step_that_went_through() {
        let (mut model, reach) = pressed_with_reach();
        let upper = model.passes[0].slave;
        let window = model.passes[0].law.window;
        let mut scratch = Dofs::zeros(&model);
        let step = |depth: f64| {
            let mut down = Dofs::zeros(&model);
            down.pd[upper].fill(-crate::math::Vec3::z() * depth);
            down
        };
        let (far, near) = (step(5.0 * window), step(0.01 * window));
        assert_eq!(
            line_search(&mut model, &far, 1.0, &reach, &mut scratch),
            Some(false)
        );
        assert_eq!(model.missed_contacts(), 0);
        let (mut model, _) = pressed_with_reach();
        assert_eq!(
            line_search(&mut model, &near, 1.0, &reach, &mut scratch),
            Some(true)
        );
    }

    /// The residuals and contact counts of the increments measured in docs/PERFORMANCE.md,
    /// "The static solver", in the shapes that tell them apart.
    #[test]
    fn a_stall_is_a_residual_that_wanders_while_the_contact_holds_still() {
        let n = 2 * STALL_WINDOW;
        // The rim cycling: 26 contacts throughout, the residual up and down between 1e-2
        // and 4e-2 (the gmsh tet4 pair at H = 0.07, one pass).
        let cycling: Vec<(f64, usize)> = (0..n)
            .map(|k| (if k % 2 == 0 { 3e-2 } else { 1e-2 }, 26))
            .collect();
        assert!(stalled(&cycling));
        // The same, one iteration short of the window: not yet.
        assert!(!stalled(&cycling[1..]));
        // Converging with the contact settled: the residual halves every other iteration.
        let converging: Vec<(f64, usize)> =
            (0..n).map(|k| (0.5f64.powi(k as i32 / 2), 69)).collect();
        assert!(!stalled(&converging));
        // The contact still growing ring by ring (the `convert` case): the residual rises
        // and falls with it, and nothing is handed over.
        let growing: Vec<(f64, usize)> = (0..n)
            .map(|k| (if k % 2 == 0 { 60.0 } else { 20.0 }, 3 + k))
            .collect();
        assert!(!stalled(&growing));
        // A count that flickers by one contact of 77 is still a settled contact.
        let flicker: Vec<(f64, usize)> = (0..n)
            .map(|k| (if k % 3 == 0 { 0.3 } else { 0.1 }, 76 + k % 2))
            .collect();
        assert!(stalled(&flicker));
    }
}
