//! Short-range force contact: the classical peridynamic node-to-node repulsion, the form of
//! EMU and of LAMMPS's `pair_style peri/pmb`, as an alternative to the point-to-surface
//! method of [`crate::contact`] (`[[contact]] method = "short-range"`).
//!
//! Two particles `i` and `j` of different bodies closer than `d` push each other apart along
//! `y = y_i − y_j` with the force
//!
//! `F_ij = 15 c V_i V_j (d − |y|)/δ · y/|y|`  for `|y| < d`, else 0,
//!
//! `c = 12E/(πδ⁴)` the PMB micromodulus and `δ` the horizon of the slave body. (LAMMPS writes
//! the coefficient as `15·18K/(πδ⁴)` with the bulk modulus `K = E/(3(1−2ν)) = 2E/3` at
//! ν = 1/4: the same `15 c`.) The tangent stiffness of a pair is `15 c V_i V_j/δ` (N/m).
//!
//! **The contact distance.** LAMMPS uses `d = min(0.9 |x_i − x_j|, 1.35 l)` with the reference
//! distance of the pair and the lattice constant `l`, so that particles that started close do not
//! repel. Two bodies of a scene have no common reference configuration: where they are placed
//! relative to each other is arbitrary, and two bodies placed in touch would get `d ≈ 0` and pass
//! through each other. So here every pair of particles of different bodies has
//! `d = 1.35 Δ` with `Δ` the slave's spacing, the cap of the LAMMPS rule.
//!
//! Particles here are mesh nodes on the body's surface, not cell centres half a cell inside it
//! (as in EMU). The repulsion holds the two surfaces about `d` apart: the bodies meet with a gap
//! of 1.35Δ less the overlap that carries the load. Against a flat master this shifts the
//! contact as a whole and leaves the pressure distribution alone.
//!
//! Only the surface particles of the two bodies take part (an interior particle cannot come
//! within `d` of the other body without a surface particle doing so first); of a body whose
//! bonds fail, also every particle that has lost a bond, since it may lie on a face the run
//! opened (a projectile meets the walls of its hole: docs/FRACTURE.md, "Fragments"). Those
//! have no outward normal and are never found behind the other body's surface. The master must be
//! deformable: a rigid body has no particles (the scene refuses a rigid master). Mirror images
//! of symmetry planes take part, so that a half or quarter model carries the force of the whole.
//!
//! The search is a cell grid over the other body's surface particles and their images, built at
//! every evaluation, and the pairs are summed in parallel per particle. In a decomposed run a
//! rank evaluates its own surface particles of both bodies ([`ShortRangePass::keep_own`]),
//! the other body's whole surface being among its ghosts. Each side of the pair is
//! evaluated from its own particle (the slave's from the master's particles, the master's from
//! the slave's) with the same formula, so the forces are equal and opposite pair by pair.
//! With a symmetry plane a particle on it holds its share of the volume and sees the whole
//! volume of its partners, as bonds do ([`crate::case::Ghosts::partner_volumes`]).
//!
//! A slave particle whose nearest master surface particle (within `d` plus the skin) sees it on
//! the inner side of its outward normal has gone through the surface: a missed contact, which
//! the solvers stop on as they do for the point-to-surface method. The repulsion is capped at
//! `15 c V_i V_j d/δ` per pair, so a fast enough particle crosses the zone whatever the time
//! step (docs/STABILITY.md).

use rayon::prelude::*;

use crate::body::{Body, PdBody};
use crate::case::neighbours::CellGrid;
use crate::contact::{slave_normal, SKIN};
use crate::math::Vec3;

/// The contact distance `d`, in slave spacings (LAMMPS's cap `1.35 l`).
pub const DISTANCE: f64 = 1.35;

/// `15 c / δ` with `c = 12E/(πδ⁴)`: pair force per `V_i V_j` and per metre of overlap
/// (N/m⁷).
pub fn coefficient(youngs: f64, horizon: f64) -> f64 {
    let c = 12.0 * youngs / (std::f64::consts::PI * horizon.powi(4));
    15.0 * c / horizon
}

/// Force on `i` from `j` of the short-range law: `coef V_i V_j (d − |y|) y/|y|` when
/// `|y| < d`, with `y = y_i − y_j`; zero otherwise (and for coincident particles, which have
/// no direction).
#[inline]
pub fn pair_force(coef: f64, v_i: f64, v_j: f64, d: f64, y: Vec3) -> Vec3 {
    let r = y.norm();
    if r >= d || r == 0.0 {
        return Vec3::zeros();
    }
    y * (coef * v_i * v_j * (d - r) / r)
}

/// One short-range contact pair of bodies.
#[derive(Clone, Debug)]
pub struct ShortRangePass {
    pub slave: usize,
    pub master: usize,
    /// `15 c/δ` of the slave body (N/m⁷).
    pub coefficient: f64,
    /// The contact distance `d` (m).
    pub distance: f64,
    /// Surface particles of the slave and of the master.
    pub slaves: Vec<u32>,
    pub masters: Vec<u32>,
    /// The surface particles whose forces this process evaluates: all, or a rank's own
    /// ([`keep_own`](Self::keep_own)). Each side's force is evaluated from its own particle,
    /// so a rank needs no reactions from the others, only the other surface's positions.
    own_slaves: Vec<u32>,
    own_masters: Vec<u32>,
    /// Slave particles that touched the master in the last evaluation.
    pub touching: usize,
    /// Master particles that touched the slave in the last evaluation.
    pub touched: usize,
    /// Slave particles found behind the master's surface in the last evaluation: nearer to a
    /// master surface particle than `d` plus the skin, and on the inner side of its outward
    /// normal. They went through the surface within a step (too fast for the step) or were
    /// pushed through it (a load the repulsion cannot hold).
    pub missed: usize,
    /// The deepest a slave particle has gone into the master's surface over the run (m):
    /// `(Δ_s + Δ_m)/2 − |y|` of the nearest pair, each particle standing for a cell of its
    /// body's spacing (negative: the repulsion kept them apart).
    pub deepest: f64,
    /// Sum of the overlap energies `½ k (d − |y|)²` of the slave side's pairs (J).
    pub energy: f64,
    /// Total force on the slave from the master in the last evaluation (N).
    pub slave_force: Vec3,
    /// Per own slave particle then per own master particle, the force and the stiffness of
    /// the last evaluation (kept to be applied after all passes have looked at the same
    /// positions), and for a slave its pairs' energy.
    slave_out: Vec<(Vec3, f64, f64)>,
    master_out: Vec<(Vec3, f64)>,
}

/// Surface particles of a body followed by the images of its surface particles: positions,
/// the real particle each stands for, the image's mask, and the whole volume of each.
struct Side {
    pos: Vec<Vec3>,
    volume: Vec<f64>,
    /// Outward normals now ([`slave_normal`]).
    normal: Vec<Vec3>,
}

/// Whether particle `i` of `b` is on a surface now: the outer surface, or (where bonds fail)
/// a new one, having lost a bond. A particle of a new surface has no outward normal (zero),
/// so it is never found behind the other body's surface.
fn exposed(b: &PdBody, i: usize) -> bool {
    b.case.surface.is_surface[i] || (b.may_break() && b.damage(i) > 0.0)
}

/// The outward normal of surface particle `i` now ([`slave_normal`]); none (zero) where it
/// has lost a bond in a run, since a broken surface has no outward side to be behind.
fn normal(b: &PdBody, i: usize) -> Vec3 {
    if b.may_break() && b.damage(i) > 0.0 {
        Vec3::zeros()
    } else {
        slave_normal(b, i)
    }
}

fn side(b: &PdBody, surface: &[u32]) -> Side {
    let g = &b.case.ghosts;
    let vol = &b.case.particles.volume;
    let mut s = Side {
        pos: Vec::new(),
        volume: Vec::new(),
        normal: Vec::new(),
    };
    for &i in surface.iter().filter(|&&i| exposed(b, i as usize)) {
        s.pos.push(b.position(i as usize));
        s.volume.push(vol[i as usize] / g.share(i as usize));
        s.normal.push(normal(b, i as usize));
    }
    let is_surface = &b.case.surface.is_surface;
    for (&src, &mask) in g.source.iter().zip(&g.mask) {
        if is_surface[src as usize] || (b.may_break() && b.damage(src as usize) > 0.0) {
            s.pos.push(g.reflect(b.position(src as usize), mask));
            s.volume.push(vol[src as usize] / g.share(src as usize));
            let n = normal(b, src as usize);
            s.normal
                .push(g.reflect(n, mask) - g.reflect(Vec3::zeros(), mask));
        }
    }
    s
}

impl ShortRangePass {
    /// Sets up a pass between two deformable bodies.
    pub fn new(bodies: &[Body], slave: usize, master: usize) -> ShortRangePass {
        let sb = bodies[slave].as_pd().expect("slave is deformable");
        let mb = bodies[master]
            .as_pd()
            .expect("short-range master is deformable (checked by the scene)");
        // A body whose bonds fail may show any particle on a new surface: all take part, those
        // exposed at the evaluation ([`exposed`]).
        let surface = |b: &PdBody| -> Vec<u32> {
            (0..b.len() as u32)
                .filter(|&i| b.may_break() || b.case.surface.is_surface[i as usize])
                .collect()
        };
        let slaves = surface(sb);
        let masters = surface(mb);
        ShortRangePass {
            slave,
            master,
            coefficient: coefficient(sb.material.youngs, sb.case.horizon),
            distance: DISTANCE * sb.spacing(),
            slave_out: vec![(Vec3::zeros(), 0.0, 0.0); slaves.len()],
            master_out: vec![(Vec3::zeros(), 0.0); masters.len()],
            own_slaves: slaves.clone(),
            own_masters: masters.clone(),
            slaves,
            masters,
            touching: 0,
            touched: 0,
            missed: 0,
            deepest: f64::NEG_INFINITY,
            energy: 0.0,
            slave_force: Vec3::zeros(),
        }
    }

    /// Keeps the particles of `slaves` and `masters` (ranges of the two bodies) as this
    /// process's own: a rank of a decomposed run evaluates the forces on its own particles.
    pub fn keep_own(&mut self, slaves: std::ops::Range<usize>, masters: std::ops::Range<usize>) {
        self.own_slaves = self
            .slaves
            .iter()
            .copied()
            .filter(|&i| slaves.contains(&(i as usize)))
            .collect();
        self.own_masters = self
            .masters
            .iter()
            .copied()
            .filter(|&i| masters.contains(&(i as usize)))
            .collect();
    }

    /// Per block of [`BLOCK`](crate::reduction::BLOCK) slave particles (in order, those with
    /// a surface particle of this process): the force on its slaves and their pairs' energy,
    /// `[fx, fy, fz, e]`. Added block by block in order over the ranks of a decomposed run
    /// (whose ranges hold whole blocks), they give one process's sums.
    pub fn block_sums(&self) -> Vec<[f64; 4]> {
        let mut out: Vec<[f64; 4]> = Vec::new();
        let mut block = usize::MAX;
        for (&s, &(f, _, e)) in self.own_slaves.iter().zip(&self.slave_out) {
            let b = s as usize / crate::reduction::BLOCK;
            if b != block {
                out.push([0.0; 4]);
                block = b;
            }
            let g = out.last_mut().expect("pushed above");
            for a in 0..3 {
                g[a] += f[a];
            }
            g[3] += e;
        }
        out
    }

    /// The pairs' energy on each own slave particle: `(particle, energy)`.
    pub fn slave_energies(&self) -> impl Iterator<Item = (u32, f64)> + '_ {
        self.own_slaves
            .iter()
            .zip(&self.slave_out)
            .map(|(&s, r)| (s, r.2))
    }

    /// Tangent stiffness of a pair of particles of volumes `v_i`, `v_j` (N/m).
    pub fn pair_stiffness(&self, v_i: f64, v_j: f64) -> f64 {
        self.coefficient * v_i * v_j
    }

    /// Forces on the particles `own` of body `a` from the surface particles of `other`, and
    /// per particle the stiffness of every pair within `d` plus the skin (which may close
    /// within a step). Returns per particle its force, stiffness and energy, whether it lies
    /// behind the nearest surface particle of `other`, and the distance to that one.
    fn one_side(&self, a: &PdBody, own: &[u32], other: &Side) -> Vec<(Vec3, f64, f64, bool, f64)> {
        let d = self.distance;
        let reach = d + SKIN * a.spacing();
        let grid = CellGrid::new(&other.pos, reach);
        let vol = &a.case.particles.volume;
        own.par_iter()
            .map(|&i| {
                if !exposed(a, i as usize) {
                    return (Vec3::zeros(), 0.0, 0.0, false, f64::INFINITY);
                }
                let p = a.position(i as usize);
                let v_i = vol[i as usize];
                let (mut f, mut k, mut e) = (Vec3::zeros(), 0.0, 0.0);
                let mut nearest = (f64::INFINITY, false);
                grid.for_each_candidate(&p, reach, |j| {
                    let y = p - other.pos[j as usize];
                    let r2 = y.norm_squared();
                    if r2 < reach * reach {
                        if r2 < nearest.0 {
                            nearest = (r2, y.dot(&other.normal[j as usize]) < 0.0);
                        }
                        let v_j = other.volume[j as usize];
                        let kp = self.pair_stiffness(v_i, v_j);
                        k += kp;
                        if r2 < d * d {
                            f += pair_force(self.coefficient, v_i, v_j, d, y);
                            let o = d - r2.sqrt();
                            e += 0.5 * kp * o * o;
                        }
                    }
                });
                (f, k, e, nearest.1, nearest.0.sqrt())
            })
            .collect()
    }

    /// Finds the pairs in contact at the current positions and their forces; they are added
    /// to the bodies by [`ShortRangePass::apply`].
    pub fn detect(&mut self, bodies: &[Body]) {
        let sb = bodies[self.slave].as_pd().expect("slave is deformable");
        let mb = bodies[self.master].as_pd().expect("master is deformable");
        let on_slave = self.one_side(sb, &self.own_slaves, &side(mb, &self.masters));
        let on_master = self.one_side(mb, &self.own_masters, &side(sb, &self.slaves));
        self.touching = on_slave.iter().filter(|r| r.0 != Vec3::zeros()).count();
        self.touched = on_master.iter().filter(|r| r.0 != Vec3::zeros()).count();
        self.missed = on_slave.iter().filter(|r| r.3).count();
        let touch = 0.5 * (sb.spacing() + mb.spacing());
        let nearest = on_slave.iter().map(|r| r.4).fold(f64::INFINITY, f64::min);
        self.deepest = self.deepest.max(touch - nearest);
        self.slave_out = on_slave.iter().map(|r| (r.0, r.1, r.2)).collect();
        self.master_out = on_master.iter().map(|r| (r.0, r.1)).collect();
        // Summed block by block, so that a decomposed run (which adds every rank's blocks in
        // order) gets the same bits.
        let (mut energy, mut force) = (0.0, Vec3::zeros());
        for g in self.block_sums() {
            force += Vec3::new(g[0], g[1], g[2]);
            energy += g[3];
        }
        self.energy = energy;
        self.slave_force = force;
    }

    /// Adds the forces and contact stiffnesses of the last [`ShortRangePass::detect`].
    pub fn apply(&self, bodies: &mut [Body]) {
        let slave_side = self.slave_out.iter().map(|r| (r.0, r.1));
        let master_side = self.master_out.iter().copied();
        let b = bodies[self.slave].as_pd_mut().expect("deformable");
        for (&i, (f, k)) in self.own_slaves.iter().zip(slave_side) {
            b.force[i as usize] += f;
            b.contact_force[i as usize] += f;
            b.contact_stiffness[i as usize] += k;
        }
        let b = bodies[self.master].as_pd_mut().expect("deformable");
        for (&i, (f, k)) in self.own_masters.iter().zip(master_side) {
            b.force[i as usize] += f;
            b.contact_force[i as usize] += f;
            b.contact_stiffness[i as usize] += k;
        }
    }

    /// A bound of the contact stiffness each particle of body `k` may see, for the stable
    /// time step before any contact: a surface particle of either body facing a surface as
    /// dense as its own has at most as many partners within `d` plus the skin as it has
    /// neighbours on its own surface within that reach.
    pub fn stiffness_bound(&self, k: usize, pd: &PdBody) -> Vec<f64> {
        let mut out = vec![0.0; pd.len()];
        let own = if k == self.slave {
            &self.slaves
        } else if k == self.master {
            &self.masters
        } else {
            return out;
        };
        let reach = self.distance + SKIN * pd.spacing();
        let pos: Vec<Vec3> = own.iter().map(|&i| pd.reference[i as usize]).collect();
        let grid = CellGrid::new(&pos, reach);
        let vol = &pd.case.particles.volume;
        for (a, &i) in own.iter().enumerate() {
            let mut kk = 0.0;
            grid.for_each_candidate(&pos[a], reach, |b| {
                if (pos[b as usize] - pos[a]).norm_squared() < reach * reach {
                    let j = own[b as usize] as usize;
                    kk += self.pair_stiffness(vol[i as usize], vol[j] / pd.case.ghosts.share(j));
                }
            });
            out[i as usize] = kk;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn force_law() {
        let (e, delta) = (1.0e9, 0.3);
        let coef = coefficient(e, delta);
        let c = 12.0 * e / (std::f64::consts::PI * delta.powi(4));
        assert!((coef - 15.0 * c / delta).abs() < 1e-9 * coef);
        let (vi, vj, d) = (1e-3, 2e-3, 0.135);
        // Along y, pushing i away from j, linear in the overlap.
        let y = Vec3::new(0.0, 0.06, 0.08);
        let f = pair_force(coef, vi, vj, d, y);
        let expect = coef * vi * vj * (d - 0.1);
        assert!((f.norm() - expect).abs() < 1e-9 * expect, "{f:?}");
        assert!((f.normalize() - y / 0.1).norm() < 1e-12);
        // Equal and opposite.
        assert!((pair_force(coef, vj, vi, d, -y) + f).norm() < 1e-9 * expect);
        // Nothing at or beyond d, nothing for coincident particles.
        assert_eq!(
            pair_force(coef, vi, vj, d, Vec3::new(d, 0.0, 0.0)),
            Vec3::zeros()
        );
        assert_eq!(pair_force(coef, vi, vj, d, Vec3::zeros()), Vec3::zeros());
        // Half the overlap, half the force.
        let f2 = pair_force(coef, vi, vj, d, y * ((d - 0.5 * (d - 0.1)) / 0.1));
        assert!((f2.norm() - 0.5 * expect).abs() < 1e-9 * expect);
    }
}
