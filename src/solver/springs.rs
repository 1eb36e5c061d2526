//! The contact springs of the static solver's tangent ([`super::tangent`]): one per slave in
//! contact (the normal law's `dF/dδ` along the master's normal, friction's in its tangent
//! plane), and the stabilisation's on the slaves that may touch. Between two deformable
//! bodies, in the tail of an increment, a contact's spring is the consistent one, not
//! symmetric: the gap's gradient is the segment's own normal where the force acts along the
//! smoothed one, and the force's direction and the reaction's shares turn as the slave slides
//! ([`crate::contact::Slide`]); the force's direction turns with the master's nodes too
//! ([`crate::contact::ContactPass::nodal_turn`], held by [`super::tangent::Tangent`]).

use nalgebra::Matrix3;

use super::dofs::Dofs;
use crate::body::Body;
use crate::contact::ContactPass;
use crate::math::Vec3;
use crate::model::Model;
use crate::scene::Motion;

/// Where a contact's reaction goes.
#[derive(Clone, Copy, Debug)]
pub(super) enum Master {
    /// A deformable body's segment: its corner nodes with the weights `N_a`.
    Nodes {
        body: usize,
        nodes: [u32; 4],
        weights: [f64; 4],
    },
    /// A free rigid body, translating along `axis`.
    Free { body: usize, axis: Vec3 },
    /// Nothing that moves (a fixed rigid body, or the stabilisation's ground).
    Ground,
}

impl Master {
    /// The master's motion where the slave touches it, from the unknowns `v`.
    pub fn motion(&self, v: &Dofs) -> Vec3 {
        match *self {
            Master::Nodes {
                body,
                nodes,
                weights,
            } => nodes
                .iter()
                .zip(weights)
                .map(|(n, w)| v.pd[body][*n as usize] * w)
                .sum(),
            Master::Free { body, axis } => axis * v.rigid[body],
            Master::Ground => Vec3::zeros(),
        }
    }

    /// Adds to `out` the master's reaction to the force `f` on the slave.
    pub fn react(&self, f: Vec3, out: &mut Dofs) {
        match *self {
            Master::Nodes {
                body,
                nodes,
                weights,
            } => {
                for (n, w) in nodes.iter().zip(weights) {
                    out.pd[body][*n as usize] -= f * w;
                }
            }
            Master::Free { body, axis } => out.rigid[body] -= f.dot(&axis),
            Master::Ground => {}
        }
    }
}

/// One penalty spring of the tangent between a slave particle and its master:
/// `C = k n⊗n + k_s (I − n⊗n − s⊗s)`, the normal law's `k` and, with friction, the
/// tangential law's `k_s` in the master's tangent plane, less the slip direction `s` where
/// the slave slips.
#[derive(Clone, Copy, Debug)]
pub(super) struct Spring {
    /// The contact pass, and whether the spring is a contact's (not the stabilisation's).
    pub pass: usize,
    pub contact: bool,
    pub body: usize,
    pub slave: u32,
    /// The direction of the force.
    pub normal: Vec3,
    /// The gap's gradient in the slave's motion: the master segment's own normal where
    /// `normal` is smoothed over its neighbours, so that `k normal ⊗ gradient` is not
    /// symmetric (between two deformable bodies, 2-4° apart on a gmsh sphere's tet4 facets).
    pub gradient: Vec3,
    /// A deformable master's corners: the normal force times `∇N_a`, how the reaction's
    /// shares move as the slave slides over the segment (zero otherwise).
    pub slide: [Vec3; 4],
    /// A deformable master: the normal force times `∂n/∂x`, how the force's direction turns
    /// as the slave slides (zero otherwise).
    pub turn: Matrix3<f64>,
    /// N/m, the pass's weight and the slave's share included (the force's own factors).
    pub k: f64,
    /// Friction's stiffness in the tangent plane, N/m (0 without friction).
    pub shear: f64,
    /// The unit slip direction of a slipping slave; zero while it sticks.
    pub slip: Vec3,
    pub master: Master,
}

impl Spring {
    /// `C` with the gap's gradient taken along the normal: symmetric, the preconditioner's.
    pub fn matrix(&self) -> Matrix3<f64> {
        let nn = self.normal * self.normal.transpose();
        let mut c = nn * self.k;
        if self.shear > 0.0 {
            c += (Matrix3::identity() - nn - self.slip * self.slip.transpose()) * self.shear;
        }
        c
    }

    /// `C dv`.
    #[inline]
    pub fn force(&self, dv: Vec3) -> Vec3 {
        let n = self.normal;
        let along = n.dot(&dv);
        let mut f = n * (self.k * self.gradient.dot(&dv));
        if self.shear > 0.0 {
            f += (dv - n * along - self.slip * self.slip.dot(&dv)) * self.shear;
        }
        f
    }
}

/// Where the reaction of `pass`'s contact on a segment with corners `nodes` at `weights` goes.
pub(super) fn master_of(
    model: &Model,
    pass: &ContactPass,
    nodes: [u32; 4],
    weights: [f64; 4],
) -> Master {
    match &model.bodies[pass.master] {
        Body::Deformable(_) => Master::Nodes {
            body: pass.master,
            nodes,
            weights,
        },
        Body::Rigid(rb) if rb.motion == Motion::Free => Master::Free {
            body: pass.master,
            axis: rb.axis,
        },
        Body::Rigid(_) => Master::Ground,
    }
}

/// The master segments of `pass`.
pub(super) fn master_segments<'a>(
    model: &'a Model,
    pass: &ContactPass,
) -> &'a [crate::case::segments::MasterSegment] {
    match &model.bodies[pass.master] {
        Body::Deformable(mb) => mb.segments(),
        Body::Rigid(rb) => &rb.faces[..],
    }
}

/// The springs of one contact pass: its contacts, and the stabilisation of the slaves that
/// may touch and do not.
pub(super) fn pass_springs(
    model: &Model,
    q: usize,
    pass: &ContactPass,
    stabilise: f64,
    settled: &[u32],
    consistent: bool,
) -> Vec<Spring> {
    let Some(sb) = model.bodies[pass.slave].as_pd() else {
        return Vec::new();
    };
    let master_of = |nodes, weights| master_of(model, pass, nodes, weights);
    let segments = master_segments(model, pass);
    // Between two deformable bodies, the contact's consistent tangent: the gap's gradient,
    // and how the force's direction and the reaction's shares turn as the slave slides. A
    // rigid master keeps the symmetric one (conjugate gradients, the figures measured on it).
    let deformable = model.bodies[pass.master].as_pd().is_some();
    let mut out = Vec::with_capacity(pass.contacts.len());
    let mut touching = vec![false; sb.len()];
    for c in &pass.contacts {
        let s = c.slave as usize;
        touching[s] = true;
        // A contact just made has next to no tangent (`1.5 K δ^{1/2}`), and a Newton step
        // that trusts it pushes its slave through: it gets at least ADR's light-contact
        // stiffness, the tangent at a hundredth of the window. A contact that held since the
        // iteration before has its own tangent, for Newton's convergence.
        let tangent = if settled.binary_search(&c.slave).is_ok() {
            pass.law.tangent(c.penetration)
        } else {
            pass.law.relaxation_stiffness(c.penetration)
        };
        let k = pass.slave_scale(sb, s) * tangent.min(pass.law.max_tangent());
        // Friction (METHOD.md §10): sticking, the tangential penalty `k_t` across the
        // tangent plane; slipping, the force turns with the slip at the cone's radius, so
        // only its stiffness across the slip, `k_t μ F_n / |k_t g_t|`, is kept. What is left
        // out (how `μ F_n` grows with the penetration, and `k_t` with it) would make the
        // tangent unsymmetric, which conjugate gradients cannot take: Newton converges
        // linearly rather than quadratically while slaves slip.
        let (shear, slip) = match c.stick {
            Some(stick) => {
                let t = c.tangential_force();
                let slip = if stick || !(t.norm() > 0.0) {
                    Vec3::zeros()
                } else {
                    t / t.norm()
                };
                (c.shear_stiffness, slip)
            }
            None => (0.0, Vec3::zeros()),
        };
        let (gradient, slide, turn) =
            if consistent && deformable && settled.binary_search(&c.slave).is_ok() {
                let slide = pass.slide(&model.bodies, c);
                let f = c.normal_force;
                (c.gap_normal, slide.weights.map(|g| g * f), slide.normal * f)
            } else {
                (c.projection.normal, [Vec3::zeros(); 4], Matrix3::zeros())
            };
        out.push(Spring {
            pass: q,
            contact: true,
            body: pass.slave,
            slave: c.slave,
            normal: c.projection.normal,
            gradient,
            slide,
            turn,
            k,
            shear,
            slip,
            master: master_of(segments[c.segment as usize].nodes, c.projection.weights),
        });
    }
    if stabilise > 0.0 {
        let k0 = stabilise * stabilisation_stiffness(model, pass);
        let master = &model.bodies[pass.master];
        let loose_master = master.as_pd().is_some() && super::unheld::pushed(master).is_some();
        for (k, &s) in pass.slaves.iter().enumerate() {
            if touching[s as usize] || !pass.may_touch(k) {
                continue;
            }
            let master = match &model.bodies[pass.master] {
                Body::Rigid(rb) if rb.motion == Motion::Free => Master::Free {
                    body: pass.master,
                    axis: rb.axis,
                },
                _ => Master::Ground,
            };
            // The master's normal opposes the slave's where they touch.
            let normal = -sb.case.surface.normal[s as usize];
            let k_s = k0 * sb.case.ghosts.share(s as usize);
            out.push(Spring {
                pass: q,
                contact: false,
                body: pass.slave,
                slave: s,
                normal,
                gradient: normal,
                slide: [Vec3::zeros(); 4],
                turn: Matrix3::zeros(),
                k: k_s,
                shear: 0.0,
                slip: Vec3::zeros(),
                master,
            });
            // A deformable master that its loads push where no support holds it (a sphere
            // pressed on a fixed block that is the slave) is as loose before it touches: the
            // nodes of a candidate segment of the slave's get the same spring, shared among
            // them.
            if let (true, Some(&seg)) = (loose_master, pass.candidates(k).first()) {
                let segment = &segments[seg as usize];
                let corners = if segment.is_triangle() { 3 } else { 4 };
                for &node in &segment.nodes[..corners] {
                    out.push(Spring {
                        pass: q,
                        contact: false,
                        body: pass.master,
                        slave: node,
                        normal,
                        gradient: normal,
                        slide: [Vec3::zeros(); 4],
                        turn: Matrix3::zeros(),
                        k: k_s / corners as f64,
                        shear: 0.0,
                        slip: Vec3::zeros(),
                        master: Master::Ground,
                    });
                }
            }
        }
    }
    out
}

/// The stabilisation's spring on each slave of `pass` that may touch, at its full strength:
/// ADR's light-contact stiffness, or less where that would hold the body still. A body held
/// only by contact should reach its contact in the first Newton step: the springs together
/// let the load pressing the pair together (the larger resultant of the two bodies' loads)
/// move it by one slave spacing, `|F| / (n Δ)` over the `n` slaves that may touch. ADR's
/// light-contact stiffness held the demo's sphere within Δ/236 of where it started, and its
/// contact grew a ring of slaves per Newton iteration (docs/PERFORMANCE.md, "The
/// contacts a Newton step makes").
fn stabilisation_stiffness(model: &Model, pass: &ContactPass) -> f64 {
    let light = pass.weight * pass.law.relaxation_stiffness(0.0);
    let resultant = |b: &Body| match b {
        Body::Deformable(pd) => pd.load.iter().sum::<Vec3>().norm(),
        Body::Rigid(rb) if rb.motion == Motion::Free => rb.load.dot(&rb.axis).abs(),
        Body::Rigid(_) => 0.0,
    };
    let load = resultant(&model.bodies[pass.slave]).max(resultant(&model.bodies[pass.master]));
    let n = (0..pass.slaves.len())
        .filter(|&k| pass.may_touch(k))
        .count();
    if !(load > 0.0) || n == 0 || !(pass.spacing > 0.0) {
        return light;
    }
    light.min(pass.weight * load / (n as f64 * pass.spacing))
}
