//! How [`pair_forces`](super::pair_forces) shares a pass among threads so that every particle's
//! force is summed in the order one thread would sum it.
//!
//! A pair `(k, j)`, `k < j`, adds its force to `k` and subtracts it from `j`. One thread going
//! through the particles in order gives particle `i` the forces of its pairs with each `k < i`,
//! `k` ascending, and then the sum of its own pairs (those with `j > i`). With `T` threads,
//! each owning a range `a..b` of particles (about equal pair counts), a thread first evaluates
//! the pairs that reach into its range from earlier particles (its halo: the pairs `(k, j)`
//! with `k < a ≤ j < b`, `k` ascending), then its own particles' pairs, keeping only what lands
//! in its range. So each particle's force is the same sum in the same order whatever the
//! thread count, and whatever the ranks of a decomposed run (a rank's particles are one such
//! range): the same bits. The price is the halo's pairs, evaluated twice (by the two threads
//! they join); in return the forces go into one buffer, each thread writing only its range,
//! which nothing has to clear or add up beyond the particles themselves.

use std::ops::Range;

use rayon::prelude::*;

use super::PairList;
use crate::case::neighbours::BondList;
use crate::math::Vec3;

/// The pairs that reach into a thread's range from earlier particles.
#[derive(Clone, Debug, Default)]
pub(super) struct Halo {
    /// The particle of each row, ascending.
    pub rows: Vec<u32>,
    /// Per row, its pairs into the range (partner and length), in the list's order.
    pub bonds: BondList,
    pub weight: Vec<f32>,
}

/// The thread layout of [`pair_forces`](super::pair_forces) and its force buffer, kept between
/// calls so that the time loop neither allocates nor recomputes the halos.
#[derive(Clone, Debug, Default)]
pub struct ForceBuffers {
    /// The pair list (its `id`) and thread count the layout was made for.
    key: Option<(u64, usize)>,
    /// Per thread: its particles (consecutive, covering the list's rows).
    pub(super) ranges: Vec<Range<usize>>,
    /// Per thread: its halo.
    pub(super) halos: Vec<Halo>,
    /// The bond force of each row particle, from `ranges[0].start` on.
    pub(super) sum: Vec<Vec3>,
}

impl ForceBuffers {
    /// Makes the layout for `list` over `parts` threads, unless it is the one in place.
    pub(super) fn prepare(&mut self, list: &PairList, parts: usize) {
        if self.key == Some((list.id, parts)) {
            return;
        }
        // Cut once, then again with each part's halo counted (twice: its rows are short,
        // and run one bond at a time), so that the threads finish together.
        let mut ranges = list.partition(parts, &[]);
        let mut halos = Self::halos(list, &ranges);
        if parts > 1 {
            let extra: Vec<usize> = halos.iter().map(|h| 2 * h.bonds.len()).collect();
            ranges = list.partition(parts, &extra);
            halos = Self::halos(list, &ranges);
        }
        self.sum = vec![Vec3::zeros(); list.rows.len()];
        self.ranges = ranges;
        self.halos = halos;
        self.key = Some((list.id, parts));
    }

    /// Each range's halo.
    fn halos(list: &PairList, ranges: &[Range<usize>]) -> Vec<Halo> {
        let pairs = &list.pairs;
        ranges
            .par_iter()
            .map(|range| {
                let mut halo = Halo::default();
                halo.bonds.offsets.push(0);
                // Pairs are stored under their lower particle: every k below the range,
                // whether a row of the list or a rank's ghost.
                for k in 0..range.start {
                    let before = halo.bonds.partner.len();
                    for b in pairs.range(k) {
                        if range.contains(&(pairs.partner[b] as usize)) {
                            halo.bonds.partner.push(pairs.partner[b]);
                            halo.bonds.length.push(pairs.length[b]);
                            halo.weight.push(list.pair_weight[b]);
                        }
                    }
                    if halo.bonds.partner.len() > before {
                        halo.rows.push(k as u32);
                        halo.bonds.offsets.push(halo.bonds.partner.len());
                    }
                }
                halo
            })
            .collect()
    }

    /// Pairs evaluated twice (the halos') per pair of the list: what `T` threads cost beyond
    /// one.
    pub fn halo_pairs_per_pair(&self, list: &PairList) -> f64 {
        let halo: usize = self.halos.iter().map(|h| h.bonds.len()).sum();
        halo as f64 / list.pairs.len().max(1) as f64
    }
}
