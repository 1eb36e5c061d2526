//! A rank's part of a case, in a run decomposed over processes ([`crate::parallel`]).
//!
//! Built whole, a case holds every particle's bonds, and the bond list and its per-bond
//! arrays are most of a model's memory. Built as a part, it holds the bonds of the particles
//! the rank owns, of its halo (their partners, one horizon deep) the bonds to later owned
//! particles (the pairs a pair list keeps in the halo's rows), and every per-particle
//! array whole (positions, volumes, surface, correction factors): so that a rank's memory
//! falls with the rank count and every rank still sees what one process sees of each
//! particle. The owned ranges are cut before any bond exists, by the bond counts of a
//! counting pass ([`crate::case::neighbours::count_bonds`]), along the Morton order as
//! [`crate::model::domain`] cuts them, and moved so that each rank's rows and its halo's
//! bonds to them come to equal shares ([`rows_of_rank`]).
//!
//! What a particle's own bonds decide (its correction factors in each Sinkhorn pass, its skin
//! factor, its stiffness) is computed by its owner from its complete row and sent to the
//! ranks that hold it in their halo, whose rows there are only in part. So the values are
//! one process's, bit for bit, and so are the forces the rank evaluates over its pairs.

use std::fmt;
use std::ops::Range;
use std::sync::Arc;

use super::neighbours::{self, build_bond_rows, count_bonds, BondList, Reach};
use super::Ghosts as MirrorImages;
use crate::math::Vec3;
use crate::parallel::{Comm, Ghosts};

/// This rank's part of a case.
#[derive(Clone)]
pub struct CasePart {
    comm: Arc<dyn Comm>,
    /// Every rank's owned range of the particles.
    pub ranges: Vec<Range<usize>>,
    /// The halo: particles this rank holds rows of without owning them, and who sends them.
    halo: Ghosts,
    /// Directed bonds over all ranks (the whole case's count).
    pub bonds: usize,
}

impl fmt::Debug for CasePart {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("CasePart")
            .field("rank", &self.comm.rank())
            .field("ranges", &self.ranges)
            .field("halo", &self.halo.count())
            .field("bonds", &self.bonds)
            .finish()
    }
}

impl CasePart {
    /// The part of `comm`'s rank: `ranges` over all ranks, `halo[j]` for the particles it
    /// holds rows of. Collective.
    pub fn new(comm: Arc<dyn Comm>, ranges: Vec<Range<usize>>, halo: &[bool]) -> CasePart {
        let halo = Ghosts::new(&*comm, &ranges, halo);
        CasePart {
            comm,
            ranges,
            halo,
            bonds: 0,
        }
    }

    /// This rank's particles.
    pub fn owned(&self) -> Range<usize> {
        self.ranges[self.comm.rank()].clone()
    }

    /// Particles this rank holds the rows of without owning them.
    pub fn halo_count(&self) -> usize {
        self.halo.count()
    }

    /// The message layer.
    pub fn comm(&self) -> &Arc<dyn Comm> {
        &self.comm
    }

    /// Gives the halo particles their owners' `values` (`K` numbers a particle). Collective.
    pub fn share<const K: usize>(&self, values: &mut [[f64; K]]) {
        let out: Vec<Vec<f64>> = self
            .halo
            .send
            .iter()
            .map(|list| {
                list.iter()
                    .flat_map(|&i| values[i as usize].iter().copied())
                    .collect()
            })
            .collect();
        let got = self.comm.exchange(&out);
        for (list, got) in self.halo.recv.iter().zip(&got) {
            for (&i, v) in list.iter().zip(got.chunks_exact(K)) {
                values[i as usize].copy_from_slice(v);
            }
        }
    }

    /// Every particle's value from its owner: `values` (whole length, `K` a particle) with
    /// each rank's owned range filled in by that rank. Collective.
    pub fn gather<const K: usize>(&self, values: &mut [[f64; K]]) {
        let mine: Vec<f64> = values[self.owned()]
            .iter()
            .flat_map(|v| v.iter().copied())
            .collect();
        for (range, got) in self.ranges.iter().zip(self.comm.all_gather_varcount(&mine)) {
            for (v, g) in values[range.clone()].iter_mut().zip(got.chunks_exact(K)) {
                v.copy_from_slice(g);
            }
        }
    }

    /// [`Self::gather`] of one number a particle.
    pub fn gather_scalar(&self, values: &mut [f64]) {
        let mut v: Vec<[f64; 1]> = values.iter().map(|&x| [x]).collect();
        self.gather(&mut v);
        for (x, g) in values.iter_mut().zip(v) {
            *x = g[0];
        }
    }

    /// The largest of every rank's `mine` (exact: a maximum does not depend on the order).
    pub fn max(&self, mine: f64) -> f64 {
        self.comm
            .all_gather(&[mine])
            .into_iter()
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// The sum of every rank's count.
    pub fn total(&self, mine: usize) -> usize {
        self.comm
            .all_gather(&[mine as f64])
            .into_iter()
            .map(|x| x as usize)
            .sum()
    }
}

/// The particles cut over the ranks of `comm` by `cost` (a particle's bonds, plus one): first
/// by the rows a rank will own, then again by those and its halo's bonds to them, which it
/// holds too (the halo is on the side of the earlier particles, so the later ranks' is the
/// larger). Collective.
pub fn cut_by_rows(
    position: &[Vec3],
    n: usize,
    reach: Reach,
    cost: &[usize],
    comm: &dyn crate::parallel::Comm,
) -> Vec<std::ops::Range<usize>> {
    let first = crate::parallel::split_by_cost(cost, comm.size(), crate::reduction::BLOCK);
    let mine = first[comm.rank()].clone();
    let before = neighbours::count_bonds_before(position, n, reach, mine);
    let held: Vec<usize> = comm
        .all_gather(&[before as f64])
        .into_iter()
        .map(|h| h as usize)
        .collect();
    crate::parallel::split_by_cost_held(cost, comm.size(), crate::reduction::BLOCK, &held)
}

/// The rows a rank of `comm` holds and its [`CasePart`]: the particles cut over the ranks by
/// their bond counts, the rows of its own particles whole, and of its halo (their partners'
/// sources) the bonds to later particles of its own alone: the pairs
/// [`PairList::restricted`](crate::case::pairs::PairList::restricted) keeps of the whole list. Collective.
pub(crate) fn rows_of_rank(
    position: &[Vec3],
    n: usize,
    reach: Reach,
    ghosts: &MirrorImages,
    comm: Arc<dyn Comm>,
) -> (BondList, CasePart) {
    let cost: Vec<usize> = count_bonds(position, n, reach)
        .into_iter()
        .map(|c| c + 1)
        .collect();
    let ranges = cut_by_rows(position, n, reach, &cost, comm.as_ref());
    drop(cost);
    let owned = ranges[comm.rank()].clone();
    let mut halo = vec![false; n];
    {
        let own = build_bond_rows(position, n, reach, |i| owned.contains(&i));
        for i in owned.clone() {
            for b in own.range(i) {
                let j = ghosts.source_of(own.partner[b] as usize, n);
                halo[j] |= !owned.contains(&j);
            }
        }
    }
    // Rows are searched for the particles of the range and the halo; a halo row keeps the
    // bonds to the range that a pair list holds in its row, those to later particles (the
    // pair `(i, j > i)` is `i`'s; a mirror image's bond belongs to its particle's row alone).
    let bonds = {
        let (owned, halo) = (&owned, &halo);
        let s = neighbours::Search::new(reach, n);
        let active = |i: usize| owned.contains(&i) || halo[i];
        neighbours::build_rows_with(position, n, &s, active, |i, j| {
            owned.contains(&i) || (i < j && owned.contains(&j))
        })
    };
    let part = CasePart::new(comm, ranges, &halo);
    (bonds, part)
}

/// What a directed bond costs a run at the most, bytes: its partner and length (8) and, while
/// the surface correction balances the particles, the per-bond geometry of its passes (20);
/// afterwards the correction factor (8), then its weight (4) and half a pair of the force
/// pass (6), the factor let go once the weights are made.
const BYTES_PER_BOND: f64 = 28.0;
/// What a particle costs beyond what is held when its bonds are made (its mesh node, its
/// place in the particle list, its surface): its state (displacement, velocity, forces, load,
/// reference position: seven vectors), mass, stiffnesses and ADR's density, bytes. With
/// [`BYTES_PER_BOND`]: 2,496 MB for the first of two 688k-particle spheres, whose run peaks
/// at 2,816 MB once the second is made too (docs/SCALING.md, "A run's memory per rank").
const BYTES_PER_PARTICLE: f64 = 300.0;

/// Refuses, before its bonds are made, a body of `n` particles (horizon factor `m`) that
/// would take this process past the memory it may use ([`crate::parallel::memory::limit_mb`]),
/// with what it would need; `share` is the part of its bonds this process holds (1 for one
/// process). Where `comm` is given every rank refuses alike (collective). `splits`: whether
/// more processes would hold less of it (a body built in parts), which the advice says. A
/// process without a limit pays nothing but the gather of two numbers on ranks.
pub fn check_memory(
    n: usize,
    m: f64,
    share: f64,
    comm: Option<&Arc<dyn Comm>>,
    splits: bool,
) -> crate::error::Result<()> {
    use crate::parallel::memory::{give_back_free_pages, limit_mb, resident_mb};
    // The lattice count of a horizon of m spacings reaching δ + Δ/2: an interior particle's
    // bonds (measured on gmsh spheres: 171 a particle at m = 3, this gives 180).
    let bonds = n as f64 * 4.0 / 3.0 * std::f64::consts::PI * (m + 0.5).powi(3);
    let limit = limit_mb();
    // What the process holds, not what its allocator kept of the last body's transients.
    if limit.is_some() {
        give_back_free_pages();
    }
    let held = resident_mb().unwrap_or(0.0);
    let need =
        |share: f64| held + (bonds * share * BYTES_PER_BOND + n as f64 * BYTES_PER_PARTICLE) / 1e6;
    let over = limit.filter(|&(l, _)| need(share) > l);
    let (size, worst) = match comm {
        Some(c) => {
            let mine = over.map_or([0.0, 0.0], |(l, _)| [need(share), l]);
            let all = c.all_gather(&mine);
            let worst = all
                .chunks_exact(2)
                .filter(|x| x[1] > 0.0)
                .max_by(|a, b| (a[0] - a[1]).total_cmp(&(b[0] - b[1])))
                .map(|x| (x[0], x[1]));
            (c.size(), worst)
        }
        None => (1, over.map(|(l, _)| (need(share), l))),
    };
    let Some((need_mb, limit_mb)) = worst else {
        return Ok(());
    };
    let what = limit.map_or("its memory limit", |(_, w)| w);
    // The fewest processes whose share of the bonds would fit (a halo adds about 8 %).
    let advice = (size.max(1) + 1..=256)
        .filter(|_| splits)
        .find(|&k| need(1.08 / k as f64) < limit_mb)
        .map_or_else(
            || "on a machine with more memory".to_string(),
            |k| format!("over {k} or more processes (`mpirun -n {k} pdcontact-mpi run`; each holds its particles' bonds, docs/guide/mpi.md)"),
        );
    Err(crate::error::Error::input(format!(
        "its {n} particles and about {:.0}M bonds would take this process to about {need_mb:.0} MB ({held:.0} MB held before them, about {BYTES_PER_BOND} bytes a bond and {BYTES_PER_PARTICLE} a particle{}), past the {limit_mb:.0} MB it may use ({what}): run it {advice}",
        bonds * share / 1e6,
        if size > 1 { ", on its rank's share of the bonds" } else { "" },
    )))
}
