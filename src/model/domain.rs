//! A model decomposed over the ranks of a run ([`crate::parallel::Comm`]).
//!
//! Every rank builds the whole model (the meshes, the case, the bodies: the same input gives
//! the same model everywhere) and then owns a range of each deformable body's particles, cut
//! along the Morton order with equal bond counts ([`split_by_cost`]). A rank evaluates the
//! bond pairs that touch its particles ([`PairList::restricted`](crate::case::pairs::PairList::restricted)),
//! detects contact for its own slave particles, and moves only its own particles. Each force
//! evaluation it first receives the displacements of its ghosts from their owners: the bond
//! partners of its particles (one horizon deep, mirror images through their sources) and, on
//! a deformable master, every node of a master segment, so that any slave it owns can touch
//! any segment. After the contact pass the reactions of its contacts on master nodes go to the
//! nodes' owners, who add them in one process's order (contact by contact, rank after rank),
//! and the forces on rigid bodies are summed block by block of slave particles, so that the
//! forces have the same bits on any number of ranks. The Verlet lists are rebuilt when the two largest
//! moves over all ranks pass the skin, as in one process.
//!
//! Rigid bodies are replicated: every rank moves them alike from the summed forces. What needs
//! the whole state (frames, the summary, the unheld-body check) calls [`Domain::gather`]
//! first, which gives every rank every particle's state.

use std::fmt;
use std::ops::Range;
use std::sync::Arc;

use crate::body::Body;
use crate::contact::shortrange::ShortRangePass;
use crate::contact::{ContactPass, TopTwo};
use crate::math::Vec3;
use crate::parallel::{owner, split_by_cost, Comm, Ghosts};

/// Values per particle that [`Domain::gather`] moves: `u`, `v`, force, contact force, the
/// master's reactions among it (3 each) and the contact stiffness.
const STATE: usize = 16;
/// Particles a rank sends in one round of [`Domain::gather`].
const GATHER_ROUND: usize = 16_384;

/// How a run was decomposed (`summary.json`'s `decomposition`).
#[derive(Clone, Debug, serde::Serialize)]
pub struct Layout {
    pub ranks: usize,
    /// Per rank: the particles it owns.
    pub particles: Vec<usize>,
    /// Per rank: the ghosts it receives every force evaluation (bond partners one horizon
    /// deep and the nodes of deformable master surfaces).
    pub ghosts: Vec<usize>,
    /// Per rank: its peak resident memory so far (`VmHWM`), MB; null where unknown.
    pub peak_memory_mb: Vec<Option<f64>>,
    /// Per rank: the directed bonds it holds, over all bodies (a body built whole holds all
    /// of its own on every rank; one built as parts, its particles' and its halo's,
    /// [`crate::case::part`]).
    pub bonds: Vec<usize>,
    /// Directed bonds of the whole model.
    pub model_bonds: usize,
}

/// This rank's part of a decomposed model and the messages that keep it current.
#[derive(Clone)]
pub struct Domain {
    comm: Arc<dyn Comm>,
    /// Per body: every rank's owned range (empty for a rigid body).
    pub ranges: Vec<Vec<Range<usize>>>,
    /// Per body: this rank's ghosts (none for a rigid body).
    ghosts: Vec<Ghosts>,
    /// Per pass: contacts over all ranks in the last evaluation.
    pub contacts: Vec<usize>,
    /// Per pass: the force on its slaves over all ranks in the last evaluation.
    pub slave_forces: Vec<Vec3>,
}

impl fmt::Debug for Domain {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Domain")
            .field("rank", &self.comm.rank())
            .field("size", &self.comm.size())
            .field("ranges", &self.ranges)
            .finish()
    }
}

impl Domain {
    /// Cuts every deformable body of `bodies` over the ranks of `comm` and sets up the ghost
    /// exchanges. Collective.
    pub fn new(
        bodies: &[Body],
        passes: &[ContactPass],
        short_range: &[ShortRangePass],
        comm: Arc<dyn Comm>,
    ) -> Domain {
        let (rank, size) = (comm.rank(), comm.size());
        let master: Vec<bool> = (0..bodies.len())
            .map(|k| {
                matches!(bodies[k], Body::Deformable(_)) && passes.iter().any(|p| p.master == k)
            })
            .collect();
        let mut ranges = Vec::new();
        let mut ghosts = Vec::new();
        for (k, body) in bodies.iter().enumerate() {
            let Some(pd) = body.as_pd() else {
                ranges.push(Vec::new());
                ghosts.push(Ghosts::default());
                continue;
            };
            let n = pd.len();
            let bonds = &pd.case.bonds;
            // A case built as a part was cut before its bonds existed.
            let r = match &pd.case.part {
                Some(part) => part.ranges.clone(),
                None => {
                    let cost: Vec<usize> = (0..n).map(|i| bonds.range(i).len() + 1).collect();
                    split_by_cost(&cost, size, crate::reduction::BLOCK)
                }
            };
            let mut need = vec![false; n];
            for i in r[rank].clone() {
                for b in bonds.range(i) {
                    let j = bonds.partner[b] as usize;
                    let real = if j < n {
                        j
                    } else {
                        pd.case.ghosts.source[j - n] as usize
                    };
                    need[real] = true;
                }
            }
            if master[k] {
                for seg in pd.segments() {
                    for &node in &seg.nodes {
                        need[node as usize] = true;
                    }
                }
            }
            // The short-range method reads the other body's whole surface.
            for p in short_range.iter().filter(|p| p.slave == k || p.master == k) {
                let surface = if p.slave == k { &p.slaves } else { &p.masters };
                for &i in surface {
                    need[i as usize] = true;
                }
            }
            ghosts.push(Ghosts::new(&*comm, &r, &need));
            ranges.push(r);
        }
        Domain {
            comm,
            ranges,
            ghosts,
            contacts: vec![0; passes.len()],
            slave_forces: vec![Vec3::zeros(); passes.len()],
        }
    }

    /// This rank.
    pub fn rank(&self) -> usize {
        self.comm.rank()
    }

    /// The message layer.
    pub fn comm(&self) -> &dyn Comm {
        &*self.comm
    }

    /// Ghosts this rank receives, over all bodies.
    pub fn ghosts(&self) -> usize {
        self.ghosts.iter().map(Ghosts::count).sum()
    }

    /// Per rank: the particles it owns, the ghosts it receives each evaluation (over all
    /// bodies), the bonds it holds and its peak memory so far. Collective.
    pub fn layout(&self, bodies: &[Body]) -> Layout {
        let held: usize = bodies
            .iter()
            .filter_map(Body::as_pd)
            .map(|pd| pd.case.bonds.len())
            .sum();
        let model_bonds = bodies
            .iter()
            .filter_map(Body::as_pd)
            .map(|pd| pd.case.bond_count())
            .sum();
        let owned: usize = self
            .ranges
            .iter()
            .filter(|r| !r.is_empty())
            .map(|r| r[self.comm.rank()].len())
            .sum();
        let peak = crate::parallel::memory::peak_rss_mb().unwrap_or(f64::NAN);
        let all = self
            .comm
            .all_gather(&[owned as f64, self.ghosts() as f64, peak, held as f64]);
        Layout {
            ranks: self.comm.size(),
            particles: all.iter().step_by(4).map(|&x| x as usize).collect(),
            ghosts: all.iter().skip(1).step_by(4).map(|&x| x as usize).collect(),
            peak_memory_mb: all
                .iter()
                .skip(2)
                .step_by(4)
                .map(|&x| (!x.is_nan()).then_some(x))
                .collect(),
            bonds: all.iter().skip(3).step_by(4).map(|&x| x as usize).collect(),
            model_bonds,
        }
    }

    /// Gives every ghost its owner's displacement. Collective.
    pub fn share_displacements(&self, bodies: &mut [Body]) {
        let mut out: Vec<Vec<f64>> = vec![Vec::new(); self.comm.size()];
        for (body, g) in bodies.iter().zip(&self.ghosts) {
            if let Some(pd) = body.as_pd() {
                g.pack(&pd.u, &mut out);
            }
        }
        let got = self.comm.exchange(&out);
        let mut at = vec![0usize; got.len()];
        for (body, g) in bodies.iter_mut().zip(&self.ghosts) {
            if let Some(pd) = body.as_pd_mut() {
                g.unpack(&got, &mut at, &mut pd.u);
            }
        }
    }

    /// Gives the ghosts of body `k` their owners' `values` (one per particle). Collective.
    pub fn share(&self, k: usize, values: &mut [Vec3]) {
        self.ghosts[k].share(self.comm.as_ref(), values);
    }

    /// Body `k`'s displacements `u` with its ghosts' taken from their owners: a copy, so
    /// that a frame reads its neighbourhoods without touching the solver's state.
    /// Collective.
    pub fn displacements(&self, k: usize, u: &[Vec3]) -> Vec<Vec3> {
        let mut u = u.to_vec();
        self.share(k, &mut u);
        u
    }

    /// Which particles of body `k` (`n` of them) this rank owns among `nodes`, the nodes any
    /// rank names: each rank sends the nodes it names to their owners. Collective.
    pub fn mark_owned(&self, k: usize, nodes: &[u32], n: usize) -> Vec<bool> {
        let mut out: Vec<Vec<f64>> = vec![Vec::new(); self.comm.size()];
        for &node in nodes {
            out[owner(&self.ranges[k], node as usize)].push(f64::from(node));
        }
        let mut marked = vec![false; n];
        for node in self.comm.exchange(&out).into_iter().flatten() {
            marked[node as usize] = true;
        }
        marked
    }

    /// Applies the contact forces of every pass found on this rank (its own slaves): the
    /// reactions on a deformable master go to the nodes' owners, who add them contact by
    /// contact, rank after rank, pass after pass, as one process's [`ContactPass::apply`]
    /// does, so that a node's force has the same bits on any number of ranks. Then the forces
    /// on rigid bodies, the contacts and the missed contacts of every pass are summed over
    /// the ranks. Collective.
    pub fn apply_contact(&mut self, bodies: &mut [Body], passes: &mut [ContactPass]) {
        let size = self.comm.size();
        // Per pass with a deformable master, what each rank sends: per destination rank,
        // `[count, (node, fx, fy, fz, k) × count]`, pass after pass.
        let deformable: Vec<bool> = passes
            .iter()
            .map(|p| matches!(bodies[p.master], Body::Deformable(_)))
            .collect();
        let got = if deformable.iter().any(|&d| d) {
            let mut out: Vec<Vec<f64>> = vec![Vec::new(); size];
            for (p, _) in passes.iter().zip(&deformable).filter(|(_, &d)| d) {
                let mb = bodies[p.master]
                    .as_pd()
                    .expect("a deformable master has particles");
                let ranges = &self.ranges[p.master];
                let heads: Vec<usize> = out.iter().map(Vec::len).collect();
                for o in &mut out {
                    o.push(0.0);
                }
                for (n, f, k) in p.reactions(&mb.case.segments.segments) {
                    let q = owner(ranges, n as usize);
                    out[q].extend([f64::from(n), f.x, f.y, f.z, k]);
                    out[q][heads[q]] += 1.0;
                }
                // With friction, its part of the reactions for the frames:
                // `[count, (node, tx, ty, tz) × count]`.
                if p.friction > 0.0 {
                    let heads: Vec<usize> = out.iter().map(Vec::len).collect();
                    for o in &mut out {
                        o.push(0.0);
                    }
                    for (n, t) in p.friction_reactions(&mb.case.segments.segments) {
                        let q = owner(ranges, n as usize);
                        out[q].extend([f64::from(n), t.x, t.y, t.z]);
                        out[q][heads[q]] += 1.0;
                    }
                }
            }
            self.comm.exchange(&out)
        } else {
            Vec::new()
        };
        let mut at = vec![0usize; got.len()];
        for (k, p) in passes.iter().enumerate() {
            p.apply_to_slaves(bodies);
            if !deformable[k] {
                continue;
            }
            let mb = bodies[p.master]
                .as_pd_mut()
                .expect("a deformable master has particles");
            for (q, part) in got.iter().enumerate() {
                let count = part[at[q]] as usize;
                at[q] += 1;
                for r in part[at[q]..at[q] + 5 * count].chunks_exact(5) {
                    let (n, f) = (r[0] as usize, Vec3::new(r[1], r[2], r[3]));
                    mb.force[n] += f;
                    mb.contact_force[n] += f;
                    mb.reaction_force[n] += f;
                    mb.contact_stiffness[n] += r[4];
                }
                at[q] += 5 * count;
                if p.friction > 0.0 {
                    let count = part[at[q]] as usize;
                    at[q] += 1;
                    if let Some(fr) = &mut mb.friction {
                        for r in part[at[q]..at[q] + 4 * count].chunks_exact(4) {
                            let t = Vec3::new(r[1], r[2], r[3]);
                            fr.force[r[0] as usize] += t;
                            fr.reaction[r[0] as usize] += t;
                        }
                    }
                    at[q] += 4 * count;
                }
            }
        }
        // Per pass: contacts, missed contacts, then the block sums of its slaves' forces
        // (and of the stiffness on a rigid master), which every rank adds in block order.
        let mut mine = Vec::new();
        for p in passes.iter() {
            let axis = match &bodies[p.master] {
                Body::Rigid(rb) => Some(rb.axis),
                Body::Deformable(_) => None,
            };
            let blocks = p.block_sums(axis);
            mine.extend([
                p.contacts.len() as f64,
                p.missed as f64,
                blocks.len() as f64,
            ]);
            mine.extend(blocks.iter().flatten());
        }
        let parts = self.comm.all_gather_varcount(&mine);
        let mut per_pass: Vec<Vec<&[f64]>> = vec![Vec::new(); passes.len()];
        let mut counts = vec![[0usize; 2]; passes.len()];
        for part in &parts {
            let mut at = 0;
            for (k, c) in counts.iter_mut().enumerate() {
                c[0] += part[at] as usize;
                c[1] += part[at + 1] as usize;
                let nb = part[at + 2] as usize;
                at += 3;
                per_pass[k].extend(part[at..at + 4 * nb].chunks_exact(4));
                at += 4 * nb;
            }
        }
        // The same additions, in the same order, as one process's passes make.
        for body in bodies.iter_mut() {
            if let Body::Rigid(rb) = body {
                rb.contact_force = Vec3::zeros();
                rb.contact_stiffness = 0.0;
            }
        }
        for (k, p) in passes.iter_mut().enumerate() {
            self.contacts[k] = counts[k][0];
            p.missed = counts[k][1];
            let mut slave = Vec3::zeros();
            for g in &per_pass[k] {
                let f = Vec3::new(g[0], g[1], g[2]);
                slave += f;
                if let Body::Rigid(rb) = &mut bodies[p.master] {
                    rb.contact_force -= f;
                    rb.contact_stiffness += g[3];
                }
            }
            self.slave_forces[k] = slave;
        }
    }

    /// Makes every short-range pass's counts and sums those of all ranks: the touching,
    /// touched and missed particles summed, the slave force and the energy added block by
    /// block of slave particles in order, as one process adds them. Collective.
    pub fn finish_short_range(&self, passes: &mut [ShortRangePass]) {
        if passes.is_empty() {
            return;
        }
        let mut mine = Vec::new();
        for p in passes.iter() {
            let blocks = p.block_sums();
            mine.extend([
                p.touching as f64,
                p.touched as f64,
                p.missed as f64,
                blocks.len() as f64,
            ]);
            mine.extend(blocks.iter().flatten());
        }
        let parts = self.comm.all_gather_varcount(&mine);
        let mut at = vec![0usize; parts.len()];
        for p in passes.iter_mut() {
            let (mut counts, mut force, mut energy) = ([0usize; 3], Vec3::zeros(), 0.0);
            for (part, at) in parts.iter().zip(&mut at) {
                for (c, v) in counts.iter_mut().zip(&part[*at..*at + 3]) {
                    *c += *v as usize;
                }
                let nb = part[*at + 3] as usize;
                *at += 4;
                for g in part[*at..*at + 4 * nb].chunks_exact(4) {
                    force += Vec3::new(g[0], g[1], g[2]);
                    energy += g[3];
                }
                *at += 4 * nb;
            }
            [p.touching, p.touched, p.missed] = counts;
            p.slave_force = force;
            p.energy = energy;
        }
    }

    /// Per pass, whether its Verlet list is to be rebuilt: the two largest moves since the
    /// last rebuild, over all ranks' slaves and the master's nodes, pass the skin. Every
    /// rank holds every master node; each counts those it owns (a rigid master's, the first
    /// rank), or the largest node's move, counted by every rank, would rebuild the list
    /// sooner than one process does. Collective.
    pub fn rebuilds(&self, bodies: &[Body], passes: &[ContactPass]) -> Vec<bool> {
        let rank = self.comm.rank();
        let mine: Vec<f64> = passes
            .iter()
            .flat_map(|p| {
                let owned = self.ranges[p.master].get(rank).cloned();
                let counts = |n: u32| match &owned {
                    Some(r) => r.contains(&(n as usize)),
                    None => rank == 0,
                };
                p.largest_moves(bodies, counts)
                    .map_or([f64::INFINITY; 2], |t| t.0)
            })
            .collect();
        if mine.is_empty() {
            return Vec::new();
        }
        let all = self.comm.all_gather(&mine);
        let per_rank = mine.len();
        passes
            .iter()
            .enumerate()
            .map(|(k, p)| {
                all.chunks_exact(per_rank)
                    .map(|r| TopTwo([r[2 * k], r[2 * k + 1]]))
                    .fold(TopTwo::default(), TopTwo::merge)
                    .sum()
                    > p.skin
            })
            .collect()
    }

    /// `width` values of each particle of `items` (of body `k`), each given by its owner's
    /// `value`: every rank gets them all, in the order of `items`. What a frame's surface
    /// needs without gathering the whole state. Collective.
    pub fn collect(
        &self,
        k: usize,
        items: &[usize],
        width: usize,
        value: impl Fn(usize, &mut Vec<f64>),
    ) -> Vec<f64> {
        let ranges = &self.ranges[k];
        let mine_range = ranges[self.comm.rank()].clone();
        let mut mine = Vec::new();
        for &i in items.iter().filter(|&&i| mine_range.contains(&i)) {
            value(i, &mut mine);
        }
        let parts = self.comm.all_gather_varcount(&mine);
        let mut at = vec![0usize; parts.len()];
        let mut out = Vec::with_capacity(items.len() * width);
        for &i in items {
            let q = owner(ranges, i);
            out.extend_from_slice(&parts[q][at[q]..at[q] + width]);
            at[q] += width;
        }
        out
    }

    /// The bonds `(particle, bond)` that failed on any rank, rank after rank (collective).
    pub fn all_failed(&self, mine: &[(u32, u32)]) -> Vec<(u32, u32)> {
        let flat: Vec<f64> = mine
            .iter()
            .flat_map(|&(i, b)| [f64::from(i), f64::from(b)])
            .collect();
        self.comm
            .all_gather_varcount(&flat)
            .into_iter()
            .flat_map(|part| {
                part.chunks_exact(2)
                    .map(|c| (c[0] as u32, c[1] as u32))
                    .collect::<Vec<_>>()
            })
            .collect()
    }

    /// Gives every rank the state (displacement, velocity, forces, contact stiffness) of every
    /// particle, from its owner. Collective.
    pub fn gather(&self, bodies: &mut [Body]) {
        let rank = self.comm.rank();
        let deformable: Vec<usize> = (0..bodies.len())
            .filter(|&k| bodies[k].as_pd().is_some())
            .collect();
        // Particles `lo..hi` of rank `q`'s own, the bodies' ranges one after the other.
        let items = |q: usize, lo: usize, hi: usize| {
            let mut out = Vec::new();
            let mut at = 0;
            for &k in &deformable {
                let r = self.ranges[k][q].clone();
                let (a, b) = (lo.max(at), hi.min(at + r.len()));
                out.extend((a..b.max(a)).map(|t| (k, r.start + t - at)));
                at += r.len();
            }
            out
        };
        let longest = (0..self.comm.size())
            .map(|q| deformable.iter().map(|&k| self.ranges[k][q].len()).sum())
            .max()
            .unwrap_or(0);
        // In rounds of at most GATHER_ROUND particles a rank (every rank runs the same
        // rounds): what a rank receives at once is a few MB, not the whole state (128 bytes
        // a particle, beside the state itself).
        for lo in (0..longest).step_by(GATHER_ROUND) {
            let hi = lo + GATHER_ROUND;
            let mut mine = Vec::with_capacity(STATE * GATHER_ROUND);
            for (k, i) in items(rank, lo, hi) {
                let pd = bodies[k].as_pd().expect("a deformable body");
                mine.extend(pd.u[i].iter());
                mine.extend(pd.v[i].iter());
                mine.extend(pd.force[i].iter());
                mine.extend(pd.contact_force[i].iter());
                mine.extend(pd.reaction_force[i].iter());
                mine.push(pd.contact_stiffness[i]);
            }
            let (all, counts) = self.comm.all_gather_flat(&mine);
            drop(mine);
            let mut at = 0;
            for (q, count) in counts.into_iter().enumerate() {
                let mut values = all[at..at + count].chunks_exact(STATE);
                at += count;
                for (k, i) in items(q, lo, hi) {
                    let s = values.next().expect("every owner sends its whole range");
                    let pd = bodies[k].as_pd_mut().expect("a deformable body");
                    let v3 = |a: usize| Vec3::new(s[a], s[a + 1], s[a + 2]);
                    pd.u[i] = v3(0);
                    pd.v[i] = v3(3);
                    pd.force[i] = v3(6);
                    pd.contact_force[i] = v3(9);
                    pd.reaction_force[i] = v3(12);
                    pd.contact_stiffness[i] = s[15];
                }
            }
        }
        // The work of fracture, where a body's bonds may fail.
        if bodies
            .iter()
            .any(|b| b.as_pd().is_some_and(|pd| pd.fracture.is_some()))
        {
            let mut mine = Vec::new();
            for (k, body) in bodies.iter().enumerate() {
                let Some(f) = body.as_pd().and_then(|pd| pd.fracture.as_ref()) else {
                    continue;
                };
                mine.extend(&f.work[self.ranges[k][rank].clone()]);
            }
            let all = self.comm.all_gather_varcount(&mine);
            for (q, part) in all.iter().enumerate() {
                let mut values = part.iter();
                for (k, body) in bodies.iter_mut().enumerate() {
                    let Some(f) = body.as_pd_mut().and_then(|pd| pd.fracture.as_mut()) else {
                        continue;
                    };
                    for i in self.ranges[k][q].clone() {
                        f.work[i] = *values.next().expect("every owner sends its whole range");
                    }
                }
            }
        }
        // Friction's forces and states, where a body has them.
        if !bodies
            .iter()
            .any(|b| b.as_pd().is_some_and(|pd| pd.friction.is_some()))
        {
            return;
        }
        let mut mine = Vec::new();
        for (k, body) in bodies.iter().enumerate() {
            let Some(f) = body.as_pd().and_then(|pd| pd.friction.as_ref()) else {
                continue;
            };
            for i in self.ranges[k][rank].clone() {
                mine.extend(f.force[i].iter());
                mine.extend(f.reaction[i].iter());
                mine.push(f64::from(f.stick[i]));
            }
        }
        let all = self.comm.all_gather_varcount(&mine);
        for (q, part) in all.iter().enumerate() {
            let mut values = part.chunks_exact(7);
            for (k, body) in bodies.iter_mut().enumerate() {
                let Some(f) = body.as_pd_mut().and_then(|pd| pd.friction.as_mut()) else {
                    continue;
                };
                for i in self.ranges[k][q].clone() {
                    let s = values.next().expect("every owner sends its whole range");
                    f.force[i] = Vec3::new(s[0], s[1], s[2]);
                    f.reaction[i] = Vec3::new(s[3], s[4], s[5]);
                    f.stick[i] = s[6] as i8;
                }
            }
        }
    }
}
