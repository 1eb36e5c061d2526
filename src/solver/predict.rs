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
//! is let go. The other half of the active set: a contact of the state whose linearised
//! force `F − k ∇g·(d_s − Σ N_a d_a)` the step would turn into a pull is let go too (its spring
//! out of the tangent, its force out of the right-hand side). Without it a body that the
//! first iterations pressed too deep was pulled out one ring of contacts a Newton iteration,
//! its springs holding it as if they were glued (gmsh's tet10 sphere on its copy, 58,726
//! particles: the contact 536 slaves wide, then 20 iterations down to 304; docs/PERFORMANCE.md,
//! "Contacts that the step would pull"). The residual and the line search are the model's own:
//! the prediction changes the step's direction, not the equilibrium.

use super::dofs::Dofs;
use super::tangent::{master_of, scale_and_mask, Spring, Tangent};
use crate::contact::ContactPass;
use crate::math::Vec3;
use crate::model::Model;

/// Linear solves a Newton iteration may repeat with the contacts it predicts.
pub const ROUNDS: usize = 4;

/// The slaves a step must not carry through their masters: those in contact at the step's
/// start and those open in front of a segment, each with its linearised gap. The contact
/// search reports a slave behind a segment by more than the window as a missed contact, but
/// only within its reach (a segment is a slave's candidate where a corner of it lies within
/// the pass's cutoff and skin, a spacing or so): a step that carries a body through its partner
/// by more than that (a Newton step whose tangent nothing held along a rigid mode: two gmsh
/// spheres, each held by the other alone, moved 3 m through each other) leaves every slave
/// out of reach, and the state reads as sound and out of contact.
#[derive(Default)]
pub(super) struct Reach {
    /// Each slave's spring (its normal or gap gradient, the master's motion), its gap at the
    /// start (negative: pressed in), and the depth past which the search no longer sees it
    /// (m: the pass's cutoff and skin).
    slaves: Vec<(Spring, f64, f64)>,
}

impl Reach {
    /// True if the step `alpha d` carries a slave deeper behind its segment than the contact
    /// search reaches, by the step's linearisation (on any rank). Within that reach the
    /// search itself tells a missed contact, so the linearisation's error on a slave sliding
    /// over a curved master does not cut steps the search would take.
    pub(super) fn through(&self, model: &Model, alpha: f64, d: &Dofs) -> bool {
        let here = self.slaves.iter().any(|(s, gap, deep)| {
            let u = d.pd[s.body][s.slave as usize] - s.master.motion(d);
            gap + alpha * s.gradient.dot(&u) < -deep
        });
        model.sum_over_ranks(vec![f64::from(u8::from(here))])[0] > 0.0
    }
}

/// Repeats the linear solve of the step `d` (`solve(model, tangent, rhs, d)`, from `d` as it
/// is) with the springs of the contacts it makes, until they stop changing or [`ROUNDS`]
/// times; returns the tangent products taken (0: none predicted) and the [`Reach`] of the
/// state's open and held slaves, for the line search.
pub(super) fn with_contacts(
    model: &mut Model,
    tangent: &mut Tangent,
    rhs: &Dofs,
    d: &mut Dofs,
    mut solve: impl FnMut(&mut Model, &mut Tangent, &Dofs, &mut Dofs) -> usize,
) -> (usize, Reach) {
    let open = open_slaves(model);
    let held = held_contacts(model, tangent);
    let reach = Reach {
        slaves: open
            .iter()
            .map(|o| (o.spring, o.gap))
            .chain(held.iter().map(|h| (h.spring, -h.penetration)))
            .map(|(s, gap)| {
                let pass = &model.passes[s.pass];
                (s, gap, pass.cutoff + pass.skin)
            })
            .collect(),
    };
    let mut products = 0;
    if open.is_empty() && held.is_empty() {
        return (products, reach);
    }
    let mut chosen = vec![false; open.len()];
    let mut released = vec![false; tangent.own()];
    let mut pressed = Dofs::zeros(model);
    for _ in 0..ROUNDS {
        let closed = choose(&open, d, &mut chosen);
        let opened = release(&held, d, &mut released);
        if !(closed || opened) {
            break;
        }
        let springs = springs_and_rhs(model, &open, &chosen, rhs, &mut pressed);
        let_go(model, &held, &released, &mut pressed);
        tangent.predict(springs, &released);
        products += solve(model, tangent, &pressed, d);
    }
    (products, reach)
}

/// A contact of the state: its spring's index in the tangent, the spring, and the force
/// on its slave (N, the pass's weight and the slave's share included).
struct Held {
    index: usize,
    spring: Spring,
    force: Vec3,
    normal_force: f64,
    /// How deep the slave is (m).
    penetration: f64,
}

/// The state's contacts, as the tangent's own springs hold them.
fn held_contacts(model: &Model, tangent: &Tangent) -> Vec<Held> {
    tangent
        .own_contacts()
        .filter_map(|(index, s)| {
            let c = model.passes[s.pass]
                .contacts
                .iter()
                .find(|c| c.slave == s.slave)?;
            Some(Held {
                index,
                spring: *s,
                force: c.force,
                normal_force: c.normal_force,
                penetration: c.penetration,
            })
        })
        .collect()
}

/// Which of `held` the step `d` lets go: those whose linearised normal force,
/// `F − k ∇g·(d_s − Σ N_a d_a)`, would pull. True if that changed.
fn release(held: &[Held], d: &Dofs, released: &mut [bool]) -> bool {
    let mut changed = false;
    for h in held {
        let s = &h.spring;
        let u = d.pd[s.body][s.slave as usize] - s.master.motion(d);
        let now = h.normal_force - s.k * s.gradient.dot(&u) <= 0.0;
        changed |= now != released[h.index];
        released[h.index] = now;
    }
    changed
}

/// Takes the released contacts' forces out of `out` (already scaled and masked): the step's
/// linear model has them open.
fn let_go(model: &Model, held: &[Held], released: &[bool], out: &mut Dofs) {
    if !held.iter().any(|h| released[h.index]) {
        return;
    }
    let mut gone = Dofs::zeros(model);
    for h in held.iter().filter(|h| released[h.index]) {
        let s = &h.spring;
        gone.pd[s.body][s.slave as usize] -= h.force;
        s.master.react(-h.force, &mut gone);
    }
    scale_and_mask(model, &mut gone);
    out.axpy(1.0, &gone);
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
                    k: pass.slave_scale(sb, s as usize) * k_law,
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

#[cfg(test)]
pub(in crate::solver) mod tests {
    use super::super::coarse::tests::stacked;
    use super::super::dofs::Dofs;
    use super::super::newton::newton;
    use super::super::state::State;
    use super::super::tangent::Tangent;
    use super::super::Silent;
    use super::{held_contacts, let_go, release, with_contacts, Reach};
    use crate::model::Model;

    /// The pressed gmsh tet4 pair at its equilibrium, and the reach of its contacts there.
    pub(in crate::solver) fn pressed_with_reach() -> (Model, Reach) {
        let mut model = stacked();
        newton(&mut model, 1e-5, 200, 1, &mut Silent).expect("the pair converges");
        let mut blocks = vec![None; model.bodies.len()];
        let mut tangent = Tangent::new(&model, 0.0, None, &mut blocks, false);
        let (rhs, mut d) = (Dofs::zeros(&model), Dofs::zeros(&model));
        let (_, reach) = with_contacts(&mut model, &mut tangent, &rhs, &mut d, |_, _, _, _| 0);
        (model, reach)
    }

    /// At the pressed gmsh tet4 pair's equilibrium: a step that leaves the bodies where they
    /// are keeps every contact; one that lifts the upper body by more than any contact's
    /// `F/k` lets every one go, and what the right-hand side loses balances between the bodies.
    #[test]
    fn a_step_that_pulls_a_contact_lets_it_go() {
        let mut model = stacked();
        newton(&mut model, 1e-5, 200, 1, &mut Silent).expect("the pair converges");
        let mut blocks = vec![None; model.bodies.len()];
        let tangent = Tangent::new(&model, 0.0, None, &mut blocks, false);
        let held = held_contacts(&model, &tangent);
        assert!(held.len() > 10, "{} contacts", held.len());
        let mut released = vec![false; tangent.own()];
        let still = Dofs::zeros(&model);
        assert!(!release(&held, &still, &mut released));
        assert!(released.iter().all(|r| !r));
        let lift = held
            .iter()
            .map(|h| h.normal_force / h.spring.k)
            .fold(0.0, f64::max);
        // The upper body (the first pass's slave) lifted whole, away from the lower one.
        let upper = model.passes[0].slave;
        let mut up = Dofs::zeros(&model);
        up.pd[upper].fill(crate::math::Vec3::z() * (3.0 * lift));
        assert!(release(&held, &up, &mut released));
        assert_eq!(released.iter().filter(|&&r| r).count(), held.len());
        let mut out = Dofs::zeros(&model);
        let_go(&model, &held, &released, &mut out);
        // The contacts' forces taken out: the upper body loses the lift the lower one gave
        // it, and the lower the reaction (along z no support holds a particle near the pole).
        let lifted = |b: usize| -> f64 {
            let pd = model.bodies[b].as_pd().expect("deformable");
            (0..pd.len())
                .map(|i| out.pd[b][i].z * pd.case.ghosts.share(i))
                .sum()
        };
        let (top, bottom) = (lifted(upper), lifted(model.passes[0].master));
        assert!(top < 0.0, "{top}");
        assert!(
            (top + bottom).abs() < 1e-9 * top.abs(),
            "{top} against {bottom}"
        );
    }

    /// A step that carries the upper body of the pressed pair 5 m down, through the lower
    /// one: the contact search at that state sees neither a contact nor a missed one (every
    /// slave is out of its reach), and the step's linearisation tells it went through; a step
    /// of a tenth of the window does not.
    #[test]
    fn a_step_through_the_partner_is_told_though_the_search_sees_nothing() {
        let (mut model, reach) = pressed_with_reach();
        let upper = model.passes[0].slave;
        let mut down = Dofs::zeros(&model);
        down.pd[upper].fill(-crate::math::Vec3::z() * 5.0);
        let window = model.passes[0].law.window;
        assert!(reach.through(&model, 1.0, &down));
        assert!(!reach.through(&model, 0.1 * window / 5.0, &down));
        assert!(!reach.through(&model, 0.0, &down));
        State::of(&model).apply(&mut model, Some((1.0, &down)));
        model.compute_forces();
        assert_eq!(model.contact_count(), 0);
        assert_eq!(model.missed_contacts(), 0);
    }
}
