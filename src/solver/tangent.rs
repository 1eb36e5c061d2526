//! The tangent stiffness of the static solver ([`super::newton`]), matrix-free: its product
//! with a vector and its block-diagonal preconditioner (METHOD.md §6).
//!
//! The unknowns are the displacements of every deformable body's particles and the
//! translation of every free rigid body along its axis ([`Dofs`]). The operator is
//! `A = S⁻¹ K`, `K = −∂F/∂u` the tangent of the out-of-balance force of Eq. 28 and `S` the
//! share of each particle's volume that the model holds (½ per symmetry plane it lies on).
//! `K` is symmetric (it is the Hessian of the model's energy: a particle on a symmetry plane
//! bonds to a neighbour and to its image, and holds half its own volume), `A` is not where a
//! body has symmetry planes; `A` is symmetric in the inner product `⟨x, y⟩ = xᵀ S y`
//! ([`Dofs::dot_shares`]), in which the conjugate gradients of [`super::newton`] run. (Run
//! in the plain one they lost their conjugacy: the coarse space of [`super::coarse`] then
//! diverged on a body held only by contact.)
//!
//! * **Bonds.** Linearised kinematics: Eq. 26 is linear in the displacements, so the product
//!   is one bond-force pass at the positions `X + v` (the force pass itself, sign reversed).
//!   Finite kinematics: the bond's tangent `w [(1 − L/l) I + (L/l) e⊗e]` (`e = y/l`) at the
//!   current positions, over the directed bonds. A bond to a mirror image moves with its
//!   source reflected (`R v_src`).
//! * **Contact.** Each contact's Hertz penalty `F = K δ^{3/2}` (Eq. 23) on the projected
//!   normal `n` of its master segment: the gap's variation `dg = (v_s − Σ_a N_a v_a)·n`
//!   (Eqs. 19-21 with the segment's weights `N_a`; a rigid master: its translation) and the
//!   stiffness `dF/dδ = 1.5 K δ^{1/2}`: `k dg n` on the slave, `−N_a k dg n` on the master's
//!   nodes. The variation of `n` and of `(r, t)` is left out (a frictionless contact on a
//!   smooth surface hardly turns them), so this is the tangent on the projected normal.
//! * **Friction** (METHOD.md §10). A sticking slave adds the tangential penalty `k_t (I − n⊗n)`
//!   on the same relative motion; a slipping one `k_t (μF_n/|k_t g_t|)` across its slip only
//!   (along it the force stays `μF_n`); a slave without a committed stick point nothing (its
//!   force is nil until the increment ends). How `μF_n` and `k_t` vary with the penetration is
//!   left out: it would make the tangent unsymmetric.
//! * **Stabilisation.** A body held only by contact has no stiffness along its load before
//!   it touches, and the first Newton step would carry it away. Every slave that may touch
//!   (a Verlet candidate, [`ContactPass::may_touch`]) gets, in the tangent only, the
//!   light-contact stiffness that ADR gives it ([`ContactLaw::relaxation_stiffness`] at 0),
//!   or less, as little as lets the load move the body a spacing ([`stabilisation_stiffness`]),
//!   along its own normal, and a deformable master that its loads push where no support
//!   holds it the same on the nodes of a segment the slave may touch (the body held only by
//!   contact may be the master), times a factor that the Newton loop halves after each
//!   iteration whose whole step was sound (one that carried a slave through its master
//!   leaves it: the body is not held yet). The residual is untouched, so the equilibrium is
//!   the same; only the path to it changes.

use nalgebra::Matrix3;

use super::cluster::Cluster;
use super::coarse::{CoarseFactor, CoarseSpace};
use super::dofs::Dofs;
use super::springs::pass_springs;
pub(super) use super::springs::{master_of, master_segments, Master, Spring};
use rayon::prelude::*;

use super::free_factor;
use crate::body::lps::Stretch;
use crate::body::{Body, PdBody};
use crate::case::pairs::{pair_forces, PairKinematics};
use crate::math::Vec3;
use crate::model::Model;
use crate::scene::{Kinematics, Motion};

/// The tangent at one state, and its preconditioner.
pub(super) struct Tangent {
    springs: Vec<Spring>,
    /// Per deformable body: the current positions of particles and images (finite
    /// kinematics; empty for linearised ones).
    current: Vec<Vec<Vec3>>,
    /// Per deformable body and particle: the inverse of the diagonal block of `A`, fixed
    /// components removed.
    block_inverse: Vec<Vec<Matrix3<f64>>>,
    /// Per free rigid body: the inverse of its diagonal entry (0 otherwise).
    rigid_inverse: Vec<f64>,
    /// Scratch positions for the linearised product.
    scratch: Vec<Vec<Vec3>>,
    /// The factorised `Pᵀ K P` of the coarse space, where one is used.
    coarse: Option<CoarseFactor>,
    /// How many of `springs` are the state's own; the rest are the predicted contacts'
    /// ([`super::predict`]).
    own: usize,
    /// Per own spring: whether the step's contacts left it out (a contact whose linearised
    /// force would pull, [`super::predict`]).
    released: Vec<bool>,
    /// Consistent contacts between two deformable bodies: the spring's index and how its
    /// force turns with the master's nodes ([`crate::contact::ContactPass::nodal_turn`]).
    rings: Vec<(usize, crate::contact::NodalTurn)>,
    /// GMRES's basis vectors, kept between the solves of this tangent ([`super::krylov`]).
    pub(super) pool: Vec<Dofs>,
    /// The contact cluster's block of the preconditioner, where springs join two
    /// deformable bodies.
    cluster: Option<Cluster>,
}

/// The tangent of a bond `w n⊗n`-like block: `ξξᵀ/|ξ|²` (linearised) or
/// `(1 − L/l) I + (L/l) e eᵀ` (finite, at the current bond `y`).
#[inline]
fn bond_block(xi: Vec3, y: Option<(Vec3, f64)>) -> Matrix3<f64> {
    match y {
        None => xi * xi.transpose() / xi.norm_squared(),
        Some((y, length)) => {
            let l = y.norm();
            let e = y / l;
            Matrix3::identity() * (1.0 - length / l) + e * e.transpose() * (length / l)
        }
    }
}

/// The linear part of a reflection across the planes of `mask`.
#[inline]
fn reflect_vector(pd: &PdBody, v: Vec3, mask: u8) -> Vec3 {
    let mut v = v;
    for (k, plane) in pd.case.ghosts.planes.iter().enumerate() {
        if mask & (1 << k) != 0 {
            v[plane.axis] = -v[plane.axis];
        }
    }
    v
}

impl Tangent {
    /// The tangent at the model's current state (forces evaluated there), with the
    /// stabilisation's factor `stabilise` (0: none). The slaves that were in contact in the
    /// `previous` tangent get their contact's own tangent (the others at least the
    /// light-contact stiffness). `bond_blocks` caches the bonds' diagonal
    /// blocks of linearised bodies, which do not change.
    pub fn new(
        model: &Model,
        stabilise: f64,
        previous: Option<&Tangent>,
        bond_blocks: &mut [Option<Vec<Matrix3<f64>>>],
        consistent: bool,
    ) -> Tangent {
        let nb = model.bodies.len();
        // The previous iteration's contacts, per pass, sorted.
        let mut settled: Vec<Vec<u32>> = vec![Vec::new(); model.passes.len()];
        for s in previous.map_or(&[][..], |t| &t.springs[..]) {
            if s.contact {
                settled[s.pass].push(s.slave);
            }
        }
        settled.iter_mut().for_each(|v| v.sort_unstable());
        let mut springs = Vec::new();
        for (q, pass) in model.passes.iter().enumerate() {
            springs.extend(pass_springs(
                model,
                q,
                pass,
                stabilise,
                &settled[q],
                consistent,
            ));
        }
        // A contact that opened since the iteration before keeps its spring in the tangent
        // for one iteration: without it the step lets the slave fall freely back through
        // the master, deep, and the contact opens and closes from one iteration to the
        // next (two slaves facing each other's nodes across a two-pass pair did so).
        if let Some(prev) = previous {
            let mut now: Vec<(usize, u32)> = springs
                .iter()
                .filter(|s| s.contact)
                .map(|s| (s.pass, s.slave))
                .collect();
            now.sort_unstable();
            springs.extend(
                prev.springs
                    .iter()
                    .filter(|s| s.contact && now.binary_search(&(s.pass, s.slave)).is_err())
                    .map(|s| Spring {
                        contact: false,
                        ..*s
                    }),
            );
        }
        let current: Vec<Vec<Vec3>> = model
            .bodies
            .iter()
            .map(|b| match b {
                Body::Deformable(pd) if pd.kinematics == Kinematics::Finite => {
                    let mut x = Vec::new();
                    pd.extended_positions(&mut x);
                    x
                }
                _ => Vec::new(),
            })
            .collect();
        // The diagonal blocks of K: bonds, then the springs' own blocks.
        let mut blocks: Vec<Vec<Matrix3<f64>>> = Vec::with_capacity(nb);
        for (k, b) in model.bodies.iter().enumerate() {
            let Body::Deformable(pd) = b else {
                blocks.push(Vec::new());
                continue;
            };
            let blk = match (&bond_blocks[k], pd.kinematics) {
                (Some(cached), Kinematics::Small) => cached.clone(),
                _ => {
                    let x = (!current[k].is_empty()).then_some(&current[k][..]);
                    let made = bond_diagonal(pd, x);
                    if pd.kinematics == Kinematics::Small {
                        bond_blocks[k] = Some(made.clone());
                    }
                    made
                }
            };
            blocks.push(blk);
        }
        let mut rigid_diag = vec![0.0; nb];
        for s in &springs {
            let c = s.matrix();
            blocks[s.body][s.slave as usize] += c;
            match s.master {
                Master::Nodes {
                    body,
                    nodes,
                    weights,
                } => {
                    for (n, w) in nodes.iter().zip(weights) {
                        if w != 0.0 {
                            blocks[body][*n as usize] += c * (w * w);
                        }
                    }
                }
                Master::Free { body, axis } => rigid_diag[body] += axis.dot(&(c * axis)),
                Master::Ground => {}
            }
        }
        // Slaves and master nodes that a spring between two deformable bodies joins: solved
        // together in the preconditioner, their coupling being what block Jacobi misses.
        let cluster = Cluster::new(model, &springs, &blocks);
        let block_inverse = model
            .bodies
            .iter()
            .zip(blocks)
            .map(|(b, blk)| match b {
                Body::Deformable(pd) => blk
                    .into_par_iter()
                    .enumerate()
                    .map(|(i, m)| invert_block(m / pd.case.ghosts.share(i), pd.fixed[i]))
                    .collect(),
                Body::Rigid(_) => Vec::new(),
            })
            .collect();
        let rigid_inverse = model
            .bodies
            .iter()
            .zip(&rigid_diag)
            .map(|(b, &d)| match b {
                Body::Rigid(rb) if rb.motion == Motion::Free && d > 0.0 => 1.0 / d,
                _ => 0.0,
            })
            .collect();
        let springs_len = springs.len();
        // A consistent spring's force also turns as the master's nodes move (the nodal
        // normals it is interpolated from follow their segments).
        let mut rings = Vec::new();
        for (i, s) in springs.iter().enumerate() {
            if !s.contact || s.turn == Matrix3::zeros() {
                continue;
            }
            let pass = &model.passes[s.pass];
            if let Some(c) = pass.contacts.iter().find(|c| c.slave == s.slave) {
                rings.push((i, pass.nodal_turn(&model.bodies, c)));
            }
        }
        Tangent {
            cluster,
            pool: Vec::new(),
            rings,
            springs,
            current,
            block_inverse,
            rigid_inverse,
            scratch: vec![Vec::new(); nb],
            coarse: None,
            own: springs_len,
            released: vec![false; springs_len],
        }
    }

    /// The coarse correction of the preconditioner ([`super::coarse`]): `space`'s
    /// `Pᵀ K P`, the bonds' part and this tangent's springs' (the stabilisation's among
    /// them: a body held only by contact has modes that only they resist), factorised.
    /// Left out where the factorisation fails: block Jacobi alone.
    pub fn build_coarse(&mut self, model: &Model, space: &CoarseSpace) {
        self.coarse = space.factor(model, &self.springs);
    }

    /// Whether every spring is symmetric (its gap's gradient along its force), so that
    /// conjugate gradients can take the tangent.
    pub fn symmetric(&self) -> bool {
        self.springs.iter().all(|s| {
            s.gradient == s.normal && s.slide == [Vec3::zeros(); 4] && s.turn == Matrix3::zeros()
        })
    }

    /// Whether the preconditioner solves a contact cluster whole.
    #[cfg(test)]
    pub fn has_cluster(&self) -> bool {
        self.cluster.is_some()
    }

    /// Block Jacobi alone, where it took a contact cluster whole.
    #[cfg(test)]
    pub fn drop_cluster(&mut self) {
        self.cluster = None;
    }

    /// The springs of this tangent (contacts and the stabilisation's).
    #[cfg(test)]
    pub fn springs(&self) -> &[Spring] {
        &self.springs
    }

    /// Replaces the predicted contacts' springs ([`super::predict`]) by `predicted`, and
    /// leaves out the own springs flagged in `released` (all kept where it is empty); the
    /// preconditioner stays the state's own.
    pub fn predict(&mut self, predicted: impl IntoIterator<Item = Spring>, released: &[bool]) {
        self.springs.truncate(self.own);
        self.springs.extend(predicted);
        self.released.fill(false);
        for (r, &off) in self.released.iter_mut().zip(released) {
            *r = off;
        }
    }

    /// The state's own contact springs, with their index.
    pub fn own_contacts(&self) -> impl Iterator<Item = (usize, &Spring)> {
        self.springs[..self.own]
            .iter()
            .enumerate()
            .filter(|(_, s)| s.contact)
    }

    /// How many springs are the state's own.
    pub fn own(&self) -> usize {
        self.own
    }

    /// `out = A v` (fixed components zero).
    pub fn apply(&mut self, model: &mut Model, v: &Dofs, out: &mut Dofs) {
        for (k, body) in model.bodies.iter_mut().enumerate() {
            let Body::Deformable(pd) = body else {
                out.rigid[k] = 0.0;
                continue;
            };
            let (vk, ok) = (&v.pd[k], &mut out.pd[k]);
            if pd.kinematics == Kinematics::Small {
                // Eq. 26 linearised is linear in the displacements: the force pass at X + v
                // is −K v.
                let pos = &mut self.scratch[k];
                let n = pd.len();
                pos.resize(pd.reference.len(), Vec3::zeros());
                let ghosts = &pd.case.ghosts;
                let (real, images) = pos.split_at_mut(n);
                real.par_iter_mut()
                    .zip(pd.reference[..n].par_iter().zip(vk.par_iter()))
                    .with_min_len(1024)
                    .for_each(|(p, (x, d))| *p = x + d);
                for (g, img) in images.iter_mut().enumerate() {
                    *img = ghosts.reflect(real[ghosts.source[g] as usize], ghosts.mask[g]);
                }
                match &mut pd.lps {
                    Some(lps) => lps.forces(
                        &pd.case,
                        pos,
                        Stretch::Small(&pd.reference),
                        ok,
                        |_, f, o| *o = -f,
                    ),
                    None => pair_forces(
                        &pd.pairs,
                        pos,
                        PairKinematics::Small(&pd.reference),
                        &mut pd.force_buffers,
                        ok,
                        |_, f, o| *o = -f,
                    ),
                }
            } else if pd.lps.is_some() {
                lps_finite_product(pd, &self.current[k], vk, ok, &mut self.scratch[k]);
            } else {
                finite_product(pd, &self.current[k], vk, ok);
            }
            out.rigid[k] = 0.0;
        }
        for (i, s) in self.springs.iter().enumerate() {
            if self.released.get(i) == Some(&true) {
                continue;
            }
            let vs = v.pd[s.body][s.slave as usize];
            let vm = s.master.motion(v);
            let u = vs - vm;
            let f = s.force(u) - s.turn * u;
            out.pd[s.body][s.slave as usize] += f;
            s.master.react(f, out);
            if let Master::Nodes { body, nodes, .. } = s.master {
                for (n, g) in nodes.iter().zip(&s.slide) {
                    out.pd[body][*n as usize] += s.normal * g.dot(&u);
                }
            }
        }
        for (i, ring) in &self.rings {
            if self.released[*i] {
                continue;
            }
            let s = &self.springs[*i];
            if let Master::Nodes { body, .. } = s.master {
                let mut f = Vec3::zeros();
                for (b, g) in ring {
                    f -= g * v.pd[body][*b as usize];
                }
                out.pd[s.body][s.slave as usize] += f;
                s.master.react(f, out);
            }
        }
        scale_and_mask(model, out);
    }

    /// `z = M⁻¹ r`: block Jacobi (the contact cluster's block solved whole), plus the coarse
    /// space's correction
    /// `P (Pᵀ K P)⁻¹ Pᵀ S r` where one is given.
    pub fn precondition(&self, space: Option<&CoarseSpace>, model: &Model, r: &Dofs, z: &mut Dofs) {
        for ((z, r), inv) in z.pd.iter_mut().zip(&r.pd).zip(&self.block_inverse) {
            z.par_iter_mut()
                .zip(r.par_iter().zip(inv.par_iter()))
                .with_min_len(1024)
                .for_each(|(z, (r, m))| *z = m * r);
        }
        for ((z, r), inv) in z.rigid.iter_mut().zip(&r.rigid).zip(&self.rigid_inverse) {
            *z = r * inv;
        }
        if let Some(c) = &self.cluster {
            c.apply(model, r, z);
        }
        if let (Some(space), Some(factor)) = (space, &self.coarse) {
            space.correct(model, factor, r, z);
        }
    }
}

/// `S⁻¹` on every particle's row and the fixed components zeroed; a rigid body that is not
/// free has no unknown.
pub(super) fn scale_and_mask(model: &Model, out: &mut Dofs) {
    for (k, b) in model.bodies.iter().enumerate() {
        match b {
            Body::Deformable(pd) => {
                let ghosts = &pd.case.ghosts;
                out.pd[k]
                    .par_iter_mut()
                    .enumerate()
                    .with_min_len(1024)
                    .for_each(|(i, o)| {
                        *o = o.component_mul(&free_factor(pd.fixed[i])) / ghosts.share(i);
                    });
            }
            Body::Rigid(rb) => {
                if rb.motion != Motion::Free {
                    out.rigid[k] = 0.0;
                }
            }
        }
    }
}

/// The bonds' diagonal blocks of `K` for each particle: `Σ_b w_b B_b` (with a bond to the
/// particle's own mirror image, `w_b B_b (I − R)`).
fn bond_diagonal(pd: &PdBody, current: Option<&[Vec3]>) -> Vec<Matrix3<f64>> {
    let bonds = &pd.case.bonds;
    let n = pd.len();
    let ghosts = &pd.case.ghosts;
    (0..n)
        .into_par_iter()
        .with_min_len(256)
        .map(|i| {
            let mut m = Matrix3::zeros();
            for b in bonds.range(i) {
                let j = bonds.partner[b] as usize;
                let xi = pd.reference[j] - pd.reference[i];
                let y = current.map(|x| (x[j] - x[i], f64::from(bonds.length[b])));
                let blk = bond_block(xi, y) * f64::from(pd.bond_weight[b]);
                m += blk;
                if j >= n && ghosts.source[j - n] as usize == i {
                    // The image moves with the particle itself: −w B R.
                    let mask = ghosts.mask[j - n];
                    let mut r = Matrix3::identity();
                    for (k, plane) in ghosts.planes.iter().enumerate() {
                        if mask & (1 << k) != 0 {
                            r[(plane.axis, plane.axis)] = -1.0;
                        }
                    }
                    m -= blk * r;
                }
            }
            m
        })
        .collect()
}

/// The inverse of a diagonal block with its fixed components removed (identity there); the
/// inverse of its diagonal if the block is singular (a particle whose bonds are collinear).
fn invert_block(mut m: Matrix3<f64>, fixed: u8) -> Matrix3<f64> {
    let free = free_factor(fixed);
    for a in 0..3 {
        if free[a] == 0.0 {
            for b in 0..3 {
                m[(a, b)] = 0.0;
                m[(b, a)] = 0.0;
            }
            m[(a, a)] = 1.0;
        }
    }
    // Symmetrise: the finite-kinematics block is symmetric up to rounding.
    let m = (m + m.transpose()) * 0.5;
    match m.try_inverse() {
        Some(inv) if inv.iter().all(|x| x.is_finite()) => inv,
        _ => Matrix3::from_diagonal(&m.diagonal().map(|d| if d > 0.0 { 1.0 / d } else { 0.0 })),
    }
}

/// `out = K v` of the bonds with finite kinematics, at the current positions `x` (particles
/// and images): `Σ_j w [(1 − L/l) η + (L/l) e (e·η)]` reversed, `η = v_j − v_i`.
fn finite_product(pd: &PdBody, x: &[Vec3], v: &[Vec3], out: &mut [Vec3]) {
    let bonds = &pd.case.bonds;
    let n = pd.len();
    let ghosts = &pd.case.ghosts;
    out.par_iter_mut()
        .enumerate()
        .with_min_len(256)
        .for_each(|(i, o)| {
            let mut acc = Vec3::zeros();
            for b in bonds.range(i) {
                let j = bonds.partner[b] as usize;
                let vj = if j < n {
                    v[j]
                } else {
                    let g = j - n;
                    reflect_vector(pd, v[ghosts.source[g] as usize], ghosts.mask[g])
                };
                let eta = vj - v[i];
                let y = x[j] - x[i];
                let l = y.norm();
                let e = y / l;
                let length = f64::from(bonds.length[b]);
                acc += (eta * (1.0 - length / l) + e * (e.dot(&eta) * length / l))
                    * f64::from(pd.bond_weight[b]);
            }
            *o = -acc;
        });
}

/// `−K v` of an LPS body at positions `x` (real particles, then images) with finite
/// kinematics, by a central difference of its force pass along `v`: the state's tangent
/// couples every pair of a particle's bonds through the dilatation, which a difference of
/// two passes gives at the cost of a pass each. The step is a millionth of the spacing at
/// the largest component of `v`.
fn lps_finite_product(
    pd: &mut PdBody,
    x: &[Vec3],
    v: &[Vec3],
    out: &mut [Vec3],
    pos: &mut Vec<Vec3>,
) {
    let n = pd.len();
    let largest = v.iter().map(|a| a.amax()).fold(0.0, f64::max);
    if !(largest > 0.0) {
        out.iter_mut().for_each(|o| *o = Vec3::zeros());
        return;
    }
    let h = 1e-6 * pd.spacing() / largest;
    let Some(lps) = pd.lps.as_mut() else {
        return;
    };
    let ghosts = &pd.case.ghosts;
    let mut plus = vec![Vec3::zeros(); n];
    for (sign, into) in [(1.0, true), (-1.0, false)] {
        pos.resize(x.len(), Vec3::zeros());
        let (real, images) = pos.split_at_mut(n);
        for i in 0..n {
            real[i] = x[i] + v[i] * (sign * h);
        }
        for (g, img) in images.iter_mut().enumerate() {
            *img = ghosts.reflect(real[ghosts.source[g] as usize], ghosts.mask[g]);
        }
        if into {
            lps.forces(&pd.case, pos, Stretch::Finite, &mut plus, |_, f, o| *o = f);
        } else {
            lps.forces(&pd.case, pos, Stretch::Finite, out, |i, f, o| {
                *o = -(plus[i] - f) / (2.0 * h)
            });
        }
    }
}
