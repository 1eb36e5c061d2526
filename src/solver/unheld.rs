//! ADR: a loaded body that has gone past everything it is in contact with.
//!
//! `run` refuses before solving the bodies that nothing can hold (`run/held.rs`), from their
//! bounding boxes. Where those say a body may be held but its particles miss what it is in
//! contact with (a block pushed past the side of a ball), ADR would accelerate it along its
//! load until its iteration limit. So every [`EVERY`] iterations a body is checked that its
//! loads push along a direction `d` that no support of its own holds (fixed components,
//! symmetry planes; a free rigid body along its axis): once it carries no contact force, has
//! moved along `d`, and lies wholly beyond every body it is in contact with along `d`, by more
//! than twice the largest particle spacing (farther than any contact reaches), nothing can
//! stop it: those bodies lie behind it and can only push it further. The run stops there
//! ([`Unheld`]), typically within a few hundred iterations of passing them, instead of
//! relaxing to `max_iterations`. A body whose particles' paths cross a face of those bodies
//! went through them, not past them (a load far beyond what the penalty holds, 1e12 N on a
//! block): that is a numerical failure, which the run goes on to report as before, so such
//! a body is not stopped here, and not looked at again.

use rayon::prelude::*;
use serde::Serialize;

use super::free_factor;
use crate::body::Body;
use crate::contact::MasterView;
use crate::math::Vec3;
use crate::model::Model;
use crate::scene::Motion;

/// How often (iterations) ADR looks for a body gone past everything.
pub const EVERY: usize = 16;

/// A body that went past everything it is in contact with: the run has no equilibrium.
#[derive(Clone, Debug, Serialize)]
pub struct Unheld {
    /// Index of the body in the scene.
    pub body: usize,
    /// What happened, naming the body, the direction and the bodies it passed.
    pub message: String,
}

/// The unit direction the loads push body `k` in, less what its own supports hold.
pub(super) fn pushed(body: &Body) -> Option<Vec3> {
    match body {
        Body::Deformable(pd) => {
            let mut held = 0u8;
            let (mut load, mut scale) = (Vec3::zeros(), 0.0);
            for (f, &m) in pd.load.iter().zip(&pd.fixed) {
                held |= m;
                load += f;
                scale += f.norm();
            }
            let free = load.component_mul(&free_factor(held));
            (free.norm() > 1e-9 * scale).then(|| free.normalize())
        }
        Body::Rigid(rb) if rb.motion == Motion::Free => {
            let along = rb.load.dot(&rb.axis);
            (along.abs() > 1e-9 * rb.load.norm()).then(|| rb.axis * along.signum())
        }
        Body::Rigid(_) => None,
    }
}

/// Smallest and largest `y · d` over the body's current points.
fn extent(body: &Body, d: Vec3) -> (f64, f64) {
    let mut r = (f64::INFINITY, f64::NEG_INFINITY);
    let mut add = |p: Vec3| {
        let x = p.dot(&d);
        r = (r.0.min(x), r.1.max(x));
    };
    match body {
        Body::Deformable(pd) => (0..pd.len()).for_each(|i| add(pd.position(i))),
        Body::Rigid(rb) => (0..rb.vertices.len()).for_each(|i| add(rb.position(i))),
    }
    r
}

/// Whether a straight path of one of body `k`'s points (surface particles, or a rigid
/// body's vertices) from its reference position to its current one crosses a face of one of
/// the bodies `others`.
fn crossed(model: &Model, k: usize, others: &[usize]) -> bool {
    let paths: Vec<(Vec3, Vec3)> = match &model.bodies[k] {
        Body::Deformable(pd) => (0..pd.len())
            .filter(|&i| pd.case.surface.is_surface[i])
            .map(|i| (pd.case.particles.position[i], pd.position(i)))
            .collect(),
        Body::Rigid(rb) => (0..rb.vertices.len())
            .map(|i| (rb.vertices[i], rb.position(i)))
            .collect(),
    };
    others.iter().any(|&m| {
        let view = MasterView::of(&model.bodies[m]);
        (0..view.segments().len()).any(|s| {
            let c = view.corners(s);
            paths.par_iter().any(|&(a, b)| {
                hits_triangle(a, b, [c[0], c[1], c[2]]) || hits_triangle(a, b, [c[0], c[2], c[3]])
            })
        })
    })
}

/// Whether the segment from `a` to `b` meets the triangle `t` (Möller-Trumbore).
fn hits_triangle(a: Vec3, b: Vec3, t: [Vec3; 3]) -> bool {
    let (e1, e2, dir) = (t[1] - t[0], t[2] - t[0], b - a);
    let p = dir.cross(&e2);
    let det = e1.dot(&p);
    if !(det.abs() > 0.0) {
        return false;
    }
    let s = (a - t[0]) / det;
    let u = s.dot(&p);
    let q = s.cross(&e1);
    let v = dir.dot(&q);
    let w = e2.dot(&q);
    (0.0..=1.0).contains(&u) && v >= 0.0 && u + v <= 1.0 && (0.0..=1.0).contains(&w)
}

/// Bodies already found to have gone through what they touch: not looked at again.
#[derive(Clone, Debug, Default)]
pub(super) struct PastCheck {
    through: Vec<bool>,
}

impl PastCheck {
    /// The first body that went past everything it is in contact with, after `iteration`.
    pub(super) fn find(&mut self, model: &mut Model, iteration: usize) -> Option<Unheld> {
        self.through.resize(model.bodies.len(), false);
        if model.domain.is_some() {
            // Over the ranks, the first two tests (no contact force, moved along d) from each
            // rank's own particles; only a body that passes them needs the whole state.
            let mut mine = Vec::with_capacity(2 * model.bodies.len());
            for (k, body) in model.bodies.iter().enumerate() {
                let (touched, moved) = match (self.through[k], pushed(body), body) {
                    (false, Some(d), Body::Deformable(pd)) => {
                        let own = pd.owned.clone();
                        let touched = pd.contact_force[own.clone()]
                            .iter()
                            .any(|f| *f != Vec3::zeros());
                        (touched, pd.u[own].iter().map(|u| u.dot(&d)).sum::<f64>())
                    }
                    (false, Some(d), Body::Rigid(rb)) => (
                        rb.contact_force != Vec3::zeros(),
                        rb.translation.dot(&d).signum(),
                    ),
                    _ => (true, 0.0),
                };
                mine.extend([f64::from(u8::from(touched)), moved]);
            }
            let total = model.sum_over_ranks(mine);
            if !total.chunks_exact(2).any(|t| t[0] == 0.0 && t[1] > 0.0) {
                return None;
            }
            model.gather();
        }
        find_unheld(model, iteration, &mut self.through)
    }
}

/// The first body that went past everything it is in contact with, after `iteration`;
/// `through` marks the bodies that went through them instead.
fn find_unheld(model: &Model, iteration: usize, through: &mut [bool]) -> Option<Unheld> {
    let pairs = model.contact_pairs();
    for (k, body) in model.bodies.iter().enumerate() {
        if through[k] {
            continue;
        }
        let Some(d) = pushed(body) else {
            continue;
        };
        let (touched, moved) = match body {
            Body::Deformable(pd) => (
                pd.contact_force.iter().any(|f| *f != Vec3::zeros()),
                pd.u.iter().map(|u| u.dot(&d)).sum::<f64>() > 0.0,
            ),
            Body::Rigid(rb) => (
                rb.contact_force != Vec3::zeros(),
                rb.translation.dot(&d) > 0.0,
            ),
        };
        if touched || !moved {
            continue;
        }
        let mut others: Vec<usize> = pairs
            .iter()
            .filter_map(|&(s, m)| {
                if s == k {
                    Some(m)
                } else if m == k {
                    Some(s)
                } else {
                    None
                }
            })
            .collect();
        others.sort_unstable();
        others.dedup();
        let reach = 2.0
            * std::iter::once(k)
                .chain(others.iter().copied())
                .filter_map(|m| model.bodies[m].as_pd())
                .map(|pd| pd.spacing())
                .fold(0.0, f64::max);
        let (front, _) = extent(body, d);
        let behind = others
            .iter()
            .map(|&m| extent(&model.bodies[m], d).1)
            .fold(f64::NEG_INFINITY, f64::max);
        if front > behind + reach {
            if crossed(model, k, &others) {
                through[k] = true;
                continue;
            }
            let names: Vec<String> = others
                .iter()
                .map(|&m| format!("\"{}\"", model.bodies[m].name()))
                .collect();
            return Some(Unheld {
                body: k,
                message: format!(
                    "body \"{}\" went past every body it is in contact with ({}) along [{}, {}, {}], the direction of its loads, with no contact force (ADR iteration {iteration}): nothing holds it against its load, and a quasi-static run has no equilibrium; add a constraint, or a contact in that direction",
                    body.name(),
                    names.join(", "),
                    crate::scene::num(d.x),
                    crate::scene::num(d.y),
                    crate::scene::num(d.z),
                ),
            });
        }
    }
    None
}
