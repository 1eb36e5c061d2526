//! The contacts a Newton step makes (METHOD.md §6): the static solver's linear solve knows
//! only the contacts of the state it starts from, and a step that presses a body onto its
//! master brings slaves into contact that its direction knew nothing of. Taken whole, they
//! enter deep (with the demo's stiff penalty, a residual up to 50 times the load's); cut back
//! to where they touch, the contact grows by one ring of slaves a Newton iteration
//! (docs/PERFORMANCE.md, "The contacts a Newton step makes").
//!
//! So the solve is repeated with the contacts it predicts (a primal-dual active set over the
//! linearised gaps): each open slave in front of a segment ([`ContactPass::open_gaps`]) whose
//! gap the step closes, `g + n·(d_s − Σ N_a d_a) < 0`, gets a spring that starts where it
//! touches, `f = −k (g + n·Δd) n`: the stiffness `k n⊗n` in the tangent and `−k g n` (its
//! reaction on the master's nodes) on the right-hand side; a slave whose spring would pull
//! is let go. The residual and the line search are the model's own: the prediction changes
//! the step's direction, not the equilibrium.

use super::dofs::Dofs;
use super::tangent::{master_of, scale_and_mask, Spring, Tangent};
use crate::contact::ContactPass;
use crate::math::Vec3;
use crate::model::Model;

/// Linear solves a Newton iteration may repeat with the contacts it predicts.
pub const ROUNDS: usize = 4;

/// Repeats the linear solve of the step `d` (`solve(model, tangent, rhs, d)`, from `d` as it
/// is) with the springs of the contacts it makes, until they stop changing or [`ROUNDS`]
/// times; returns the tangent products taken (0: none predicted).
pub(super) fn with_contacts(
    model: &mut Model,
    tangent: &mut Tangent,
    rhs: &Dofs,
    d: &mut Dofs,
    mut solve: impl FnMut(&mut Model, &mut Tangent, &Dofs, &mut Dofs) -> usize,
) -> usize {
    let open = open_slaves(model);
    let mut products = 0;
    if open.is_empty() {
        return products;
    }
    let mut chosen = vec![false; open.len()];
    let mut pressed = Dofs::zeros(model);
    for _ in 0..ROUNDS {
        if !choose(&open, d, &mut chosen) {
            break;
        }
        let springs = springs_and_rhs(model, &open, &chosen, rhs, &mut pressed);
        tangent.predict(springs);
        products += solve(model, tangent, &pressed, d);
    }
    products
}

/// An open slave in front of a master segment: the spring it would get.
pub(super) struct Open {
    spring: Spring,
    /// The gap, m (open: positive).
    gap: f64,
}

/// The open slaves of every contact pass at the current state, each with the spring a
/// contact would give it: the pass's law at the mean penetration of its contacts (ADR's
/// light-contact stiffness where it has none, and at least that).
fn open_slaves(model: &Model) -> Vec<Open> {
    let mut out = Vec::new();
    for (q, pass) in model.passes.iter().enumerate() {
        let Some(sb) = model.bodies[pass.slave].as_pd() else {
            continue;
        };
        let k_law = law_stiffness(pass);
        let segments = super::tangent::master_segments(model, pass);
        for (s, seg, pr) in pass.open_gaps(&model.bodies) {
            out.push(Open {
                spring: Spring {
                    pass: q,
                    contact: false,
                    body: pass.slave,
                    slave: s,
                    normal: pr.normal,
                    gradient: pr.normal,
                    slide: [Vec3::zeros(); 4],
                    turn: nalgebra::Matrix3::zeros(),
                    k: pass.weight * sb.case.ghosts.share(s as usize) * k_law,
                    shear: 0.0,
                    slip: Vec3::zeros(),
                    master: master_of(model, pass, segments[seg as usize].nodes, pr.weights),
                },
                gap: pr.gap,
            });
        }
    }
    out
}

/// The stiffness a predicted contact of `pass` gets, per unit weight and share.
fn law_stiffness(pass: &ContactPass) -> f64 {
    let light = pass.law.relaxation_stiffness(0.0);
    if pass.contacts.is_empty() {
        return light;
    }
    let mean =
        pass.contacts.iter().map(|c| c.penetration).sum::<f64>() / pass.contacts.len() as f64;
    pass.law
        .tangent(mean)
        .max(light)
        .min(pass.law.max_tangent())
}

/// The linearised gap of `o` after the step `d`.
fn gap_after(o: &Open, d: &Dofs) -> f64 {
    let s = &o.spring;
    let vm = s.master.motion(d);
    o.gap + s.normal.dot(&(d.pd[s.body][s.slave as usize] - vm))
}

/// Which of `open` the step `d` leaves in contact: those it closes, and of those already
/// chosen (`chosen`), the ones their springs still press (not pulled). True if that changed.
fn choose(open: &[Open], d: &Dofs, chosen: &mut [bool]) -> bool {
    let mut changed = false;
    for (o, c) in open.iter().zip(chosen.iter_mut()) {
        let now = gap_after(o, d) < 0.0;
        changed |= now != *c;
        *c = now;
    }
    changed
}

/// The chosen open slaves' springs, and `rhs` plus their pull towards where they touch
/// (`−k g n` on the slave, its reaction on the master), divided by the shares and masked as
/// the residual is.
fn springs_and_rhs(
    model: &Model,
    open: &[Open],
    chosen: &[bool],
    rhs: &Dofs,
    out: &mut Dofs,
) -> Vec<Spring> {
    out.fill_zero();
    let mut springs = Vec::new();
    for (o, _) in open.iter().zip(chosen).filter(|(_, &c)| c) {
        let s = o.spring;
        let f = -s.normal * (s.k * o.gap);
        out.pd[s.body][s.slave as usize] += f;
        s.master.react(f, out);
        springs.push(s);
    }
    scale_and_mask(model, out);
    out.axpy(1.0, rhs);
    springs
}
