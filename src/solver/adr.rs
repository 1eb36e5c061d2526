//! Adaptive dynamic relaxation (Kilic & Madenci 2010; paper Sec. 2.3, Eqs. 27-33, METHOD.md
//! §6): the fictitious diagonal density from Gershgorin's bound on the bond and contact
//! stiffness (Eq. 31), the damping of Eq. 33, the velocity update of Eq. 29 with its sign
//! corrected, and the load applied in equal increments.

use rayon::prelude::*;

use super::state::State;
use super::unheld::{PastCheck, EVERY};
use super::{
    applied_norm, check_missed, displacement_reference, driven, free_factor, full_loads,
    record_increment, scale_loads, Monitor, RunStats,
};
use crate::body::{Body, PdBody};
use crate::error::{Error, Result};
use crate::math::Vec3;
use crate::model::Model;
use crate::reduction::block_sums;
use crate::scene::Motion;

/// Gershgorin factor of a penalty contact block `k n⊗n` and its reaction: ½ max_α |n_α| ‖n‖₁.
const CONTACT_ROW: f64 = 0.683;

/// How much of a particle's contact stiffness ADR's density keeps from one iteration to the
/// next after its contacts open, on a deformable master checked one way
/// ([`Model::is_one_way_deformable`]): its density follows the larger of its current contact
/// stiffness and this share of the density's last contact part.
///
/// Such a master's nodes are nobody's slaves, and they had no floor then (now a light
/// contact's while a slave may touch them, [`touchable_master_nodes`], far below a pressed
/// contact's): when the slave pressing a node lifted off, the node's density fell to its
/// bonds' alone (100-500 times less), the bonds' force stored under the contact threw it a
/// centimetre in one iteration, into the slave, which then met it 1 cm deep. Measured on twelve pairs of gmsh
/// spheres pressed together with one pass (docs/VALIDATION.md, "One pass, and pairs of other
/// sizes"): without it ADR lost a slave on every one; at 0.9 or 0.93 it converged on 11 of the
/// 12 (not the tet10 pair at h = 0.1), at 0.8 or 0.85 on 10: too short a memory, or so long
/// that a master node held too heavy lets the slave sink.
pub const OPENED_CONTACT_MEMORY: f64 = 0.9;

/// The nodes of deformable master `k` that a slave of a one-way pass
/// ([`Model::is_one_way_deformable`]) may touch within a step (a corner of a segment among
/// that slave's candidates), over all ranks, and the light-contact stiffness of those passes.
///
/// A slave that may touch gets ADR's light-contact stiffness; such a master's nodes are
/// nobody's slaves and got none until a contact pressed them, so in ADR's transient they moved
/// at their bonds' density, 100-500 times lighter: the nodes under the slaves slid sideways
/// by centimetres, and the pair's slow modes took longer to settle. Given the same floor as
/// the slaves facing them (added to their contact stiffness: the larger of the two settled
/// fewer pairs), the one-pass pairs of docs/VALIDATION.md ("Two deformable bodies", cause 9)
/// settle in 1.03-1.89 times the iterations of the same slave mesh on a rigid plane, where
/// they took up to 2.4 times, to the same figures.
fn touchable_master_nodes(model: &Model, k: usize) -> (Vec<bool>, f64) {
    let Body::Deformable(pd) = &model.bodies[k] else {
        return (Vec::new(), 0.0);
    };
    let segments = &pd.case.segments.segments;
    let mut nodes = Vec::new();
    let mut light = 0.0f64;
    for p in model
        .passes
        .iter()
        .filter(|p| p.master == k && model.is_one_way_deformable(p))
    {
        light = light.max(p.weight * p.law.relaxation_stiffness(0.0));
        for s in 0..p.slaves.len() {
            for &seg in p.candidates(s) {
                nodes.extend(segments[seg as usize].nodes);
            }
        }
    }
    nodes.sort_unstable();
    nodes.dedup();
    let marked = match &model.domain {
        Some(dom) => dom.mark_owned(k, &nodes, pd.len()),
        None => {
            let mut m = vec![false; pd.len()];
            for &n in &nodes {
                m[n as usize] = true;
            }
            m
        }
    };
    (marked, light)
}

/// The contact part of a body's ADR density: the remembered one where the body keeps
/// [`OPENED_CONTACT_MEMORY`] (`memory > 0`), else its current contact stiffness.
fn contact_part<'a>(memory: f64, remembered: &'a [f64], current: &'a [f64]) -> &'a [f64] {
    if memory > 0.0 {
        remembered
    } else {
        current
    }
}

/// A particle without a bond has no stiffness: ADR's fictitious density (Eq. 30) is zero there
/// and the first step divides by it. Said before the run, with its cause, instead of the NaN
/// it would end in.
pub(super) fn unbonded_particles(model: &Model, density: &[Vec<f64>]) -> Result<()> {
    for (b, d) in model.bodies.iter().zip(density) {
        let Body::Deformable(pd) = b else { continue };
        // Each rank checks its own particles (a rank's part holds no others' bonds); the
        // count and the first are over all ranks, so that every rank refuses alike.
        let lonely: Vec<usize> = pd.owned.clone().filter(|&i| !(d[i] > 0.0)).collect();
        let (count, first) = match &model.domain {
            Some(dom) => {
                let first = lonely.first().map_or(f64::INFINITY, |&i| i as f64);
                let all = dom.comm().all_gather(&[lonely.len() as f64, first]);
                let count: f64 = all.iter().step_by(2).sum();
                let first = all
                    .iter()
                    .skip(1)
                    .step_by(2)
                    .copied()
                    .fold(f64::INFINITY, f64::min);
                (count as usize, first.is_finite().then_some(first as usize))
            }
            None => (lonely.len(), lonely.first().copied()),
        };
        let Some(first) = first else {
            continue;
        };
        let case = &pd.case;
        let node = case.mesh.node_ids[case.particles.node[first] as usize];
        let x = case.particles.position[first];
        // Where the horizon already follows a graded mesh, the advice to let it is no help.
        let why = match &case.local_spacing {
            Some(s) => format!(
                "the horizon follows the graded mesh (δ = {:.4e} m there, its local spacing {:.4e} m times {}), and is still shorter than the distance to their nearest neighbours; the mesh coarsens faster there than the local spacing follows. Grade the mesh more gently towards that region, or give a larger `horizon_factor`",
                case.horizon_factor * s[first],
                s[first],
                case.horizon_factor
            ),
            None => format!(
                "the horizon δ = {:.4e} m (Δ = {:.4e} m times {}) is shorter than the distance to their nearest neighbours; the mesh is coarser there than elsewhere. Leave the body's `spacing` unset and `horizon = \"local\"` (the default), so that the horizon follows a graded mesh, or give a larger `spacing`",
                case.horizon,
                case.particles.spacing,
                case.horizon_factor
            ),
        };
        return Err(Error::input(format!(
            "body \"{}\": {} of its {} particles have no bond (the first: node {node} at [{:.4}, {:.4}, {:.4}]), so a static run cannot hold them: {why}",
            pd.name,
            count,
            pd.len(),
            x.x,
            x.y,
            x.z,
        )));
    }
    Ok(())
}

/// ADR's Gershgorin density of the bonds, per particle: ½ max_α Σ_j w_ij |n_α| ‖n‖₁.
pub(super) fn bond_density(model: &Model) -> Vec<Vec<f64>> {
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

/// Adaptive dynamic relaxation to a static equilibrium, the load applied in `load_steps` equal
/// increments, each relaxed to `tolerance` before the next (1: all at once).
///
/// ADR reaches equilibrium by a damped pseudo-dynamic motion; under a load applied at once, a
/// free rigid body overshoots its equilibrium before the damping catches it. Where the overshoot
/// is large (a punch pressed at a tenth of E into a body with finite kinematics) the body can be
/// driven into a state it does not come back from; increments keep each overshoot small.
///
/// The same overshoot can carry a slave through its master before the contact holds it
/// (one pass between deformable bodies: a master node moved into the slave, docs/VALIDATION.md,
/// "One pass, and pairs of other sizes"), where the equilibrium has no such miss. An
/// increment that loses a slave starts again from the last equilibrium with half its load
/// step, up to [`MAX_CUTBACKS`] times, each step after one that converged twice as long, up
/// to the increment's end: the static solver's cut-backs (`solver.cutbacks`). Not in bodies
/// whose bonds may break, which would stay broken when the increment is walked again.
pub fn adr(
    model: &mut Model,
    tolerance: f64,
    max_iterations: usize,
    load_steps: usize,
    monitor: &mut dyn Monitor,
) -> Result<RunStats> {
    // Without a load or a moving body the equilibrium is the reference state: there is
    // nothing to iterate for, and no force to measure the residual against.
    let driven = driven(model);
    if !driven && !(applied_norm(model) > 0.0) {
        return Err(Error::input(
            "nothing loads the model: an ADR (static) run needs a [[load]] with a non-zero force on a body part that is free to move, a [[constraint]] with a non-zero displacement, or a rigid body with motion = \"velocity\" or \"displacement\"".to_string(),
        ));
    }
    let density = bond_density(model);
    unbonded_particles(model, &density)?;
    let mut stats = RunStats {
        solver: "adr".into(),
        ..Default::default()
    };
    let steps = load_steps.max(1);
    let full = full_loads(model);
    // Bonds that break in an increment that is then cut back would stay broken: the path
    // would not be the one walked again. Such runs take their increments as given.
    let may_cut = !model
        .bodies
        .iter()
        .filter_map(Body::as_pd)
        .any(PdBody::may_break);
    let mut n = 0;
    let mut done = 0.0;
    'steps: for step in 1..=steps {
        let nominal = step as f64 / steps as f64;
        let mut target = nominal;
        let mut saved = State::of(model);
        let mut halved = 0;
        loop {
            if steps > 1 || stats.cutbacks > 0 {
                scale_loads(model, &full, target);
            }
            // Driven bodies, prescribed displacements and ramped loads along the path.
            model.path.apply(&mut model.bodies, target);
            model.gather();
            monitor.load_increment(model, target, n)?;
            match adr_increment(
                model,
                &density,
                tolerance,
                max_iterations,
                n,
                monitor,
                &mut stats,
            ) {
                Ok(last) => n = last,
                // A slave carried through its master by the increment's transient (the
                // static equilibrium has no such miss): the increment starts again from the
                // last equilibrium with half the load step, as the static solver's does.
                Err(e) if may_cut && model.missed_contacts() > 0 => {
                    if halved == MAX_CUTBACKS || stats.iterations >= max_iterations {
                        return Err(cut_back_note(e, halved, done, target));
                    }
                    halved += 1;
                    stats.cutbacks += 1;
                    n = stats.iterations;
                    target = done + 0.5 * (target - done);
                    // ADR's first iteration sets the velocities from the forces afresh.
                    saved.apply(model, None);
                    monitor.cut_back(model, done, target, n)?;
                    continue;
                }
                Err(e) => return Err(e),
            }
            // The next increment's friction starts from the stick points this one ended with.
            model.commit_friction();
            record_increment(model, target, n, &mut stats);
            if !stats.converged || stats.interrupted {
                break 'steps;
            }
            model.gather();
            monitor.increment_done(model, target, n)?;
            let size = target - done;
            done = target;
            if target == nominal {
                break;
            }
            // The rest of the nominal increment, in steps twice as long as the last.
            saved = State::of(model);
            target = (done + 2.0 * size).min(nominal);
        }
    }
    model.gather();
    monitor.finish(model, n, n as f64)?;
    Ok(stats)
}

/// How many times one load increment is halved after a missed contact before ADR gives up.
const MAX_CUTBACKS: usize = 4;

/// The missed-contact error of an increment halved `halved` times, with what was tried.
fn cut_back_note(e: Error, halved: usize, done: f64, target: f64) -> Error {
    match e {
        Error::Numerical(m) if halved > 0 => Error::numerical(format!(
            "{m} (ADR cut this load increment back {halved} times, each time to half the step that lost a slave; the last try went from the equilibrium at load factor {done:.4} towards {target:.4})"
        )),
        e => e,
    }
}

/// One ADR relaxation from the current state to equilibrium under the current loads (Eqs.
/// 27-33), numbering iterations on from `n0`; returns the last iteration's number.
pub(super) fn adr_increment(
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
        displacement_reference(model)
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
                        .map(|p| p.weight * p.law.max_tangent() * p.slave_count as f64)
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
                for i in pd.owned.clone() {
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

    // The contact part of each particle's density, remembered on one-way deformable
    // masters ([`OPENED_CONTACT_MEMORY`]); elsewhere the current contact stiffness.
    let memory: Vec<f64> = (0..model.bodies.len())
        .map(|k| {
            let one_way = model
                .passes
                .iter()
                .any(|p| p.master == k && model.is_one_way_deformable(p));
            if one_way {
                OPENED_CONTACT_MEMORY
            } else {
                0.0
            }
        })
        .collect();
    let mut contact_density: Vec<Vec<f64>> = model
        .bodies
        .iter()
        .zip(&memory)
        .map(|(b, &keep)| match b {
            Body::Deformable(pd) if keep > 0.0 => pd.contact_stiffness.clone(),
            _ => Vec::new(),
        })
        .collect();
    // Per body, the nodes [`touchable_master_nodes`] marks and its light-contact stiffness, as
    // of the Verlet rebuild count they were found at.
    let mut touchable: Vec<(Option<usize>, Vec<bool>, f64)> = vec![(None, Vec::new(), 0.0); nb];
    let mut best = f64::INFINITY;
    let mut past = PastCheck::default();
    let mut n = n0;
    loop {
        n += 1;
        model.compute_forces();
        update_rigid_lambda(model, &mut rigid_lambda);
        for (k, keep) in memory.iter().enumerate() {
            if *keep == 0.0 {
                continue;
            }
            // The candidates change only when a Verlet list is rebuilt.
            let rebuilds: usize = model
                .passes
                .iter()
                .filter(|p| p.master == k)
                .map(|p| p.verlet.rebuilds)
                .sum();
            if touchable[k].0 != Some(rebuilds) {
                let (marked, light) = touchable_master_nodes(model, k);
                touchable[k] = (Some(rebuilds), marked, light);
            }
            let (_, marked, light) = &touchable[k];
            let Body::Deformable(pd) = &model.bodies[k] else {
                continue;
            };
            let kc = &mut contact_density[k];
            for i in pd.owned.clone() {
                let floor = if marked[i] { *light } else { 0.0 };
                kc[i] = (pd.contact_stiffness[i] + floor).max(keep * kc[i]);
            }
        }
        // One pass over each body's particles for the finiteness check, the residual and the
        // damping's Rayleigh quotient (Eqs. 32-33): the bookkeeping of an iteration is then
        // this pass and the update below, next to the force pass.
        // Per deformable body, block by block over this process's particles; then the blocks
        // of all ranks in order, with the stop flag (every rank stops at the same iteration).
        let mut local = Vec::new();
        for (k, b) in model.bodies.iter().enumerate() {
            if let Body::Deformable(pd) = b {
                let (dens, prev) = (&density[k], &prev_f[k]);
                let kc = contact_part(memory[k], &contact_density[k], &pd.contact_stiffness);
                let blocks = block_sums(
                    pd.owned.clone(),
                    AdrSums::default,
                    |i| {
                        let ff = free_factor(pd.fixed[i]);
                        let (u, v, f) = (pd.u[i], pd.v[i], pd.force[i]);
                        let mut s = AdrSums {
                            finite: u.iter().chain(f.iter()).all(|c| c.is_finite()),
                            residual: f.component_mul(&ff).norm_squared(),
                            ..AdrSums::default()
                        };
                        let lam = lambda_of(dens, kc, i);
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
                for s in blocks {
                    local.extend([f64::from(u8::from(!s.finite)), s.residual, s.num, s.den]);
                }
            }
        }
        local.push(f64::from(u8::from(monitor.interrupted())));
        let (bodies, flags) = model.sum_blocks(local, 4, 1);
        let interrupted = flags[0] > 0.0;
        let mut sum = AdrSums::default();
        let mut totals = bodies.iter();
        for (k, b) in model.bodies.iter().enumerate() {
            match b {
                Body::Deformable(pd) => {
                    let t = totals.next().expect("one total per deformable body");
                    if t[0] > 0.0 {
                        return Err(Error::numerical(format!(
                            "non-finite displacement or force in body \"{}\" at iteration {n}: ADR diverged (likely cause: a penalty stiffness far above the bond stiffness, or a load that pushes a body through a surface)",
                            pd.name
                        )));
                    }
                    sum = sum.add(AdrSums {
                        finite: true,
                        residual: t[1],
                        num: t[2],
                        den: t[3],
                    });
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
        // Counted before the check: an increment cut back on a miss goes on numbering from here.
        stats.iterations = n;
        check_missed(model, n, "iteration", None)?;
        let r = sum.residual.sqrt();
        let rel = r / reference;
        stats.residual = rel;
        best = best.min(rel);
        if rel < tolerance {
            stats.converged = true;
            break;
        }
        if n >= max_iterations {
            break;
        }
        if n.is_multiple_of(EVERY) {
            if let Some(u) = past.find(model, n) {
                stats.unheld = Some(u);
                break;
            }
        }
        if rel > 1e6 * best.max(1e-12) && n > n0 + 100 {
            return Err(Error::numerical(format!(
                "ADR diverged at iteration {n}: the out-of-balance force grew to {rel:.3e} of the load (it was {best:.3e}); likely cause: contact stiffness far above the bond stiffness"
            )));
        }
        if interrupted {
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
                    let kc = contact_part(memory[k], &contact_density[k], &pd.contact_stiffness);
                    let own = pd.owned.clone();
                    pd.v[own.clone()]
                        .par_iter_mut()
                        .zip(pd.u[own.clone()].par_iter_mut())
                        .zip(prev_f[k][own.clone()].par_iter_mut())
                        .enumerate()
                        .with_min_len(1024)
                        .for_each(|(i, ((v, u), prev))| {
                            let i = own.start + i;
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
