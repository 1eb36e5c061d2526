//! Explicit dynamics by velocity Verlet (paper Sec. 2.3, METHOD.md §6): the stable time step
//! tightened for contact, the energy balance that catches a run that blows up, and the
//! mass-proportional damping that lets an explicit run settle to the static state.

use super::{
    check_finite, check_missed, free_factor, EnergyTerms, Monitor, RunStats, DEFAULT_SAFETY,
};
use crate::body::{Body, PdBody};
use crate::error::{Error, Result};
use crate::math::Vec3;
use crate::model::Model;
use crate::reduction::block_sums;
use crate::scene::{Motion, SolverSpec};

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
                    // Every slave of the body (its surface particles), also where a decomposed
                    // run's pass holds one rank's only.
                    for s in (0..pd.len()).filter(|&i| pd.case.surface.is_surface[i]) {
                        contact[s] += p.weight * p.law.max_tangent();
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
            for p in model.fragments.iter().filter(|p| p.body == k) {
                for (c, b) in contact.iter_mut().zip(p.stiffness_bound(pd)) {
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
fn highest_eigenvalue(pd: &PdBody, contact: &[f64]) -> f64 {
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

/// The energy's terms ([`EnergyTerms`]) but the rigid bodies' driven work, which the caller
/// accumulates: kinetic, strain, contact, the work of constant applied loads, the energy
/// damping removed (`dissipated`, per body and particle) with the work friction dissipated,
/// and the work of fracture. The particles' terms (a contact's energy on its slave) are
/// summed block by block of particles in a fixed order, so that the thread and rank counts
/// do not change their bits; the rigid bodies' (replicated on every rank) once.
fn energies(model: &Model, dissipated: &[Vec<f64>]) -> EnergyTerms {
    let mut contact: Vec<Vec<f64>> = vec![Vec::new(); model.bodies.len()];
    let mut book = |k: usize, i: usize, e: f64| {
        let c = &mut contact[k];
        if c.is_empty() {
            c.resize(model.bodies[k].as_pd().map_or(0, PdBody::len), 0.0);
        }
        c[i] += e;
    };
    for p in model.passes.iter().filter(|p| !p.contacts.is_empty()) {
        for c in &p.contacts {
            book(p.slave, c.slave as usize, p.energy(c));
        }
    }
    for p in &model.short_range {
        for (s, energy) in p.slave_energies() {
            book(p.slave, s as usize, energy);
        }
    }
    for p in &model.fragments {
        for (s, energy) in p.energies() {
            book(p.body, s as usize, energy);
        }
    }
    // The work friction has dissipated, on each slave (committed steps, and this step's).
    let mut slid: Vec<Vec<f64>> = vec![Vec::new(); model.bodies.len()];
    for p in model.passes.iter().filter(|p| p.friction > 0.0) {
        let e = &mut slid[p.slave];
        if e.is_empty() {
            e.resize(model.bodies[p.slave].as_pd().map_or(0, PdBody::len), 0.0);
        }
        for (&s, w) in p.slaves.iter().zip(&p.friction_work) {
            e[s as usize] += w;
        }
    }
    const TERMS: usize = 6;
    let mut mine = Vec::new();
    let mut pos = Vec::new();
    for (k, b) in model.bodies.iter().enumerate() {
        let Body::Deformable(pd) = b else { continue };
        pd.extended_positions(&mut pos);
        let (contact, dissipated, slid) = (&contact[k], &dissipated[k], &slid[k]);
        let work = pd.fracture.as_ref().map(|f| &f.work);
        let blocks = block_sums(
            pd.owned.clone(),
            || [0.0; TERMS],
            |i| {
                [
                    pd.kinetic_energy_of(i),
                    pd.strain_energy_of(i, &pos),
                    contact.get(i).copied().unwrap_or(0.0),
                    pd.load[i].dot(&pd.u[i]),
                    dissipated.get(i).copied().unwrap_or(0.0) + slid.get(i).copied().unwrap_or(0.0),
                    work.map_or(0.0, |w| w[i]),
                ]
            },
            |a, b| std::array::from_fn(|t| a[t] + b[t]),
        );
        mine.extend(blocks.iter().flatten());
    }
    let (sums, _) = model.sum_blocks(mine, TERMS, 0);
    let t = sums
        .iter()
        .fold([0.0; TERMS], |a, s| std::array::from_fn(|k| a[k] + s[k]));
    let mut e = EnergyTerms {
        kinetic: t[0],
        strain: t[1],
        contact: t[2],
        work: t[3],
        dissipated: t[4],
        fracture: t[5],
    };
    for b in &model.bodies {
        if let Body::Rigid(rb) = b {
            if rb.motion == Motion::Free {
                e.kinetic += 0.5 * rb.mass * rb.axial_speed * rb.axial_speed;
                e.work += rb.load.dot(&rb.axis) * rb.translation.dot(&rb.axis);
            }
        }
    }
    e
}

fn add3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
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
    // The kinetic energy damping removed, per body and particle (empty without damping).
    let mut dissipated: Vec<Vec<f64>> = model
        .bodies
        .iter()
        .map(|b| match b.as_pd() {
            Some(pd) if damping > 0.0 => vec![0.0; pd.len()],
            _ => Vec::new(),
        })
        .collect();
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
    model.commit_friction();
    let start = energies(model, &dissipated);
    let e0_phys = start.physical();
    let mut e0 = e0_phys - start.work;
    let mut last = start;
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
                    for i in pd.owned.clone() {
                        let ff = free_factor(pd.fixed[i]);
                        pd.v[i] =
                            (pd.v[i] + pd.force[i] * (0.5 * dt / pd.mass[i])).component_mul(&ff);
                        pd.u[i] += pd.v[i] * dt;
                    }
                }
                Body::Rigid(rb) => match rb.motion {
                    Motion::Fixed | Motion::Displacement => {}
                    Motion::Velocity => {
                        // Work done on the system by the driven body over the step, by the
                        // trapezoid rule: half with the force at the step's start here, half
                        // with the force at its end below. (The start's force alone counts the
                        // work of a first contact one step late: a body driven fast into
                        // another gave kinetic energy that no work had supplied yet.)
                        rigid_work += -0.5 * rb.contact_force.dot(&(rb.velocity * dt));
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
        // Each step starts from the stick points the last one found.
        model.commit_friction();
        for b in model.bodies.iter_mut() {
            match b {
                Body::Deformable(pd) => {
                    for i in pd.owned.clone() {
                        let ff = free_factor(pd.fixed[i]);
                        pd.v[i] =
                            (pd.v[i] + pd.force[i] * (0.5 * dt / pd.mass[i])).component_mul(&ff);
                    }
                }
                Body::Rigid(rb) if rb.motion == Motion::Free && rb.mass > 0.0 => {
                    let f = (rb.load + rb.contact_force).dot(&rb.axis);
                    rb.axial_speed += 0.5 * dt * f / rb.mass;
                }
                Body::Rigid(rb) if rb.motion == Motion::Velocity => {
                    rigid_work += -0.5 * rb.contact_force.dot(&(rb.velocity * dt));
                }
                Body::Rigid(_) => {}
            }
        }
        if damping > 0.0 {
            for (b, lost) in model.bodies.iter_mut().zip(&mut dissipated) {
                let Body::Deformable(pd) = b else { continue };
                for i in pd.owned.clone() {
                    lost[i] += pd.kinetic_energy_of(i) * (1.0 - decay * decay);
                    pd.v[i] *= decay;
                }
            }
        }
        let t = step as f64 * dt;
        stats.iterations = step;
        stats.time = t;
        // One sum over the ranks a step: non-finite values, the kinetic energy and the work of
        // the loads over this process's particles, and the stop flag.
        let mut mine = Vec::new();
        for pd in model.bodies.iter().filter_map(Body::as_pd) {
            let blocks = block_sums(
                pd.owned.clone(),
                || [0.0; 3],
                |i| {
                    let finite = pd.u[i].iter().chain(&pd.force[i]).all(|c| c.is_finite());
                    [
                        f64::from(u8::from(!finite)),
                        pd.kinetic_energy_of(i),
                        pd.load[i].dot(&pd.u[i]),
                    ]
                },
                add3,
            );
            mine.extend(blocks.iter().flatten());
        }
        mine.push(f64::from(u8::from(monitor.interrupted())));
        let (sums, flags) = model.sum_blocks(mine, 3, 1);
        let total = sums
            .iter()
            .fold([0.0; 3], |a, s| add3(a, [s[0], s[1], s[2]]));
        if total[0] > 0.0 {
            model.gather();
            check_finite(model, step, "step")?;
        }
        let interrupted = flags[0] > 0.0;
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
        let (mut kinetic, mut supplied) = (total[1], total[2] + rigid_work);
        for b in &model.bodies {
            if let Body::Rigid(rb) = b {
                kinetic += 0.5 * rb.mass * rb.axial_speed * rb.axial_speed;
                supplied += rb.load.dot(&rb.translation);
            }
        }
        let available = e0_phys.abs() + supplied.abs() + e_scale;
        if !(kinetic <= 1.5 * available + f64::MIN_POSITIVE) {
            return Err(Error::numerical(format!(
                "kinetic energy exploded to {kinetic:.3e} J at step {step} (t = {t:.4e} s), {:.1}x the energy the system holds: the explicit run is unstable; likely cause: the time step dt = {dt:.3e} s is above the stable step ({stable:.3e} s estimated), or the penalty stiffness is too high for it",
                kinetic / available.max(f64::MIN_POSITIVE)
            )));
        }
        if step.is_multiple_of(check_every) || step == steps {
            let mut now = energies(model, &dissipated);
            now.work += rigid_work;
            e_scale = e_scale.max(now.physical().abs());
            let total = now.total();
            last = now;
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
            let umax = model.max_over_ranks(
                model
                    .bodies
                    .iter()
                    .filter_map(Body::as_pd)
                    .flat_map(|pd| pd.u[pd.owned.clone()].iter())
                    .map(|u| u.norm())
                    .fold(0.0, f64::max),
            );
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
        if interrupted {
            stats.interrupted = true;
            break;
        }
    }
    stats.converged = !stats.interrupted;
    stats.energy = Some([start, last]);
    model.gather();
    monitor.finish(model, step, stats.time)?;
    Ok(stats)
}
