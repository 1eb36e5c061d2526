//! Several processes on one run: the messages a decomposed model needs, behind a trait, so
//! that the library does not depend on an MPI installation.
//!
//! [`Comm`] is what [`crate::model::domain`] asks of a message-passing layer: the rank and
//! size, sums in rank order, and an exchange of `f64` buffers between every pair of ranks.
//! The `pdcontact-mpi` package (`mpi/`) implements it on the system's MPI (rsmpi); in the
//! `pdcontact` binary there is one process and nothing here is used.
//!
//! Indices travel as `f64`: a particle index is below 2⁵³, so it is exact, and one buffer
//! type keeps the trait small.

pub mod memory;

use std::ops::Range;

use crate::math::Vec3;

/// A message-passing layer over `size()` processes. Every method is collective: all ranks
/// call it, in the same order.
pub trait Comm: Send + Sync {
    /// This process's rank, `0..size()`.
    fn rank(&self) -> usize;
    /// Number of processes.
    fn size(&self) -> usize;
    /// Every rank's `mine`, concatenated in rank order (`mine` has the same length on all
    /// ranks).
    fn all_gather(&self, mine: &[f64]) -> Vec<f64>;
    /// Every rank's `mine`, one vector per rank (lengths may differ).
    fn all_gather_varcount(&self, mine: &[f64]) -> Vec<Vec<f64>>;
    /// [`Self::all_gather_varcount`] in one vector, rank after rank, with each rank's
    /// length: what a gather of the whole state takes, without a second copy of it.
    fn all_gather_flat(&self, mine: &[f64]) -> (Vec<f64>, Vec<usize>) {
        let parts = self.all_gather_varcount(mine);
        let counts = parts.iter().map(Vec::len).collect();
        (parts.concat(), counts)
    }
    /// Sends `send[q]` to rank `q` and returns what each rank sent to this one.
    fn exchange(&self, send: &[Vec<f64>]) -> Vec<Vec<f64>>;
    /// Stops every rank with `code`: what a rank does when it fails alone (the others would
    /// wait for it in the next collective call).
    fn abort(&self, code: i32) -> !;

    /// `Σ_ranks mine[k]` for each `k`, the ranks' terms added in rank order, so that the same
    /// decomposition gives the same bits whatever the scheduling.
    fn sum(&self, mine: &[f64]) -> Vec<f64> {
        let all = self.all_gather(mine);
        let n = mine.len();
        let mut out = vec![0.0; n];
        for part in all.chunks_exact(n.max(1)).take(self.size()) {
            for (o, v) in out.iter_mut().zip(part) {
                *o += v;
            }
        }
        out
    }

    /// Whether any rank says yes.
    fn any(&self, mine: bool) -> bool {
        self.sum(&[f64::from(u8::from(mine))])[0] > 0.0
    }
}

impl std::fmt::Debug for dyn Comm {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "rank {} of {}", self.rank(), self.size())
    }
}

/// Cuts `0..cost.len()` into `parts` consecutive ranges of about equal total cost (`cost[i]`
/// is item `i`'s, e.g. its bond count): the owned ranges of a decomposition. Items are in
/// Morton order ([`crate::case::discretize`]), so a range of them is a compact piece of the
/// body, as a space-filling-curve partitioner makes.
///
/// Each cut is rounded to a multiple of `align` (the block of
/// [`ordered_reduce`](crate::reduction::ordered_reduce)), so that no block of a fixed-order
/// sum straddles two ranks: summed block by block, the ranks' terms give the bits of one
/// process.
pub fn split_by_cost(cost: &[usize], parts: usize, align: usize) -> Vec<Range<usize>> {
    split_by_cost_held(cost, parts, align, &[])
}

/// [`split_by_cost`] where part `r` also holds `held[r]` beside its items' costs (a rank's
/// halo rows, [`crate::case`]): each cut moves so that a part's items and its `held`
/// together come to an equal share, `held` taken as staying with its part as the cut moves.
/// A missing `held[r]` is 0.
pub fn split_by_cost_held(
    cost: &[usize],
    parts: usize,
    align: usize,
    held: &[usize],
) -> Vec<Range<usize>> {
    let align = align.max(1);
    let parts = parts.max(1);
    let mut prefix = Vec::with_capacity(cost.len() + 1);
    prefix.push(0usize);
    for c in cost {
        prefix.push(prefix.last().copied().unwrap_or(0) + c);
    }
    let held_of = |r: usize| held.get(r).copied().unwrap_or(0);
    let total =
        *prefix.last().unwrap_or(&0) as u128 + held.iter().map(|&h| h as u128).sum::<u128>();
    let mut cuts = vec![0usize; parts + 1];
    let mut held_before = 0u128;
    for r in 1..=parts {
        held_before += held_of(r - 1) as u128;
        cuts[r] = if r == parts {
            cost.len()
        } else {
            // The first item whose cumulative cost, with what the parts before it hold,
            // reaches the part's share.
            let target = (total * r as u128 / parts as u128).saturating_sub(held_before) as usize;
            let at = prefix.partition_point(|&p| p < target).min(cost.len());
            ((at + align / 2) / align * align).min(cost.len())
        }
        .max(cuts[r - 1]);
    }
    cuts.windows(2).map(|w| w[0]..w[1]).collect()
}

/// The ghosts of one rank in one body: the particles it reads but does not own, received
/// from their owners before every force evaluation, and those it sends to the other ranks.
#[derive(Clone, Debug, Default)]
pub struct Ghosts {
    /// Per rank: the particles this rank sends to it.
    pub send: Vec<Vec<u32>>,
    /// Per rank: the ghosts this rank receives from it, in the order they are sent.
    pub recv: Vec<Vec<u32>>,
}

impl Ghosts {
    /// The ghosts of this rank: the particles `j` with `need[j]` outside its own range of
    /// `ranges`, asked of their owners. Collective.
    pub fn new(comm: &dyn Comm, ranges: &[Range<usize>], need: &[bool]) -> Ghosts {
        let size = comm.size();
        let mine = ranges[comm.rank()].clone();
        let mut asks: Vec<Vec<f64>> = vec![Vec::new(); size];
        let mut recv: Vec<Vec<u32>> = vec![Vec::new(); size];
        for (j, _) in need
            .iter()
            .enumerate()
            .filter(|(j, &x)| x && !mine.contains(j))
        {
            let q = owner(ranges, j);
            asks[q].push(j as f64);
            recv[q].push(j as u32);
        }
        let send = comm
            .exchange(&asks)
            .into_iter()
            .map(|v| v.into_iter().map(|j| j as u32).collect())
            .collect();
        Ghosts { send, recv }
    }

    /// Ghosts received, from all ranks.
    pub fn count(&self) -> usize {
        self.recv.iter().map(Vec::len).sum()
    }

    /// Appends to `out[q]` the values this rank sends to rank `q`.
    pub fn pack(&self, values: &[Vec3], out: &mut [Vec<f64>]) {
        for (o, list) in out.iter_mut().zip(&self.send) {
            o.extend(
                list.iter()
                    .flat_map(|&i| values[i as usize].iter().copied()),
            );
        }
    }

    /// Takes this rank's ghosts from `got[q]` (what rank `q` sent), from `at[q]` on.
    pub fn unpack(&self, got: &[Vec<f64>], at: &mut [usize], values: &mut [Vec3]) {
        for (q, list) in self.recv.iter().enumerate() {
            for &i in list {
                let v = &got[q][at[q]..at[q] + 3];
                values[i as usize] = Vec3::new(v[0], v[1], v[2]);
                at[q] += 3;
            }
        }
    }

    /// Gives every ghost its owner's value. Collective.
    pub fn share(&self, comm: &dyn Comm, values: &mut [Vec3]) {
        let mut out = vec![Vec::new(); comm.size()];
        self.pack(values, &mut out);
        let got = comm.exchange(&out);
        self.unpack(&got, &mut vec![0; got.len()], values);
    }
}

/// The rank whose range holds `i`.
pub fn owner(ranges: &[Range<usize>], i: usize) -> usize {
    ranges.partition_point(|r| r.end <= i).min(ranges.len() - 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_balances_cost_and_covers_every_item_once() {
        let cost: Vec<usize> = (0..1000).map(|i| 10 + (i * 37) % 50).collect();
        for parts in 1..=7 {
            let r = split_by_cost(&cost, parts, 1);
            assert_eq!(r.len(), parts);
            assert_eq!(r[0].start, 0);
            assert_eq!(r[parts - 1].end, cost.len());
            for w in r.windows(2) {
                assert_eq!(w[0].end, w[1].start);
            }
            let total: usize = cost.iter().sum();
            for range in &r {
                let c: usize = cost[range.clone()].iter().sum();
                let share = total as f64 / parts as f64;
                assert!((c as f64 - share).abs() <= 60.0, "{parts}: {c} vs {share}");
            }
            for i in [0, 1, 499, 999] {
                assert!(r[owner(&r, i)].contains(&i));
            }
        }
    }

    #[test]
    fn aligned_cuts_fall_on_block_boundaries() {
        let cost: Vec<usize> = (0..10_000).map(|i| 50 + (i * 31) % 40).collect();
        for parts in 1..=5 {
            let r = split_by_cost(&cost, parts, 256);
            assert_eq!(r[parts - 1].end, cost.len());
            for w in r.windows(2) {
                assert_eq!(w[0].end, w[1].start);
                assert_eq!(w[0].end % 256, 0, "{parts}: {r:?}");
            }
            // Within half a block of the balanced cut.
            let total: usize = cost.iter().sum();
            for range in &r {
                let c: usize = cost[range.clone()].iter().sum();
                assert!((c as f64 - total as f64 / parts as f64).abs() <= 256.0 * 90.0);
            }
        }
    }

    #[test]
    fn what_a_part_holds_beside_its_items_moves_the_cuts() {
        let cost = vec![10usize; 1000];
        // The later parts hold more (a rank's halo rows to its earlier neighbour).
        let held = [0, 400, 800, 1600];
        let r = split_by_cost_held(&cost, 4, 1, &held);
        assert_eq!(r[0].start, 0);
        assert_eq!(r[3].end, 1000);
        let share = (10_000 + 2800) as f64 / 4.0;
        for (range, h) in r.iter().zip(held) {
            let c = 10 * range.len() + h;
            assert!((c as f64 - share).abs() <= 10.0, "{r:?}: {c} vs {share}");
        }
        assert_eq!(
            split_by_cost_held(&cost, 4, 1, &[]),
            split_by_cost(&cost, 4, 1)
        );
    }

    #[test]
    fn split_of_fewer_items_than_parts_leaves_ranges_empty() {
        let r = split_by_cost(&[5, 5], 4, 1);
        assert_eq!(r.iter().map(|r| r.len()).sum::<usize>(), 2);
        assert_eq!(owner(&r, 1), r.iter().position(|x| x.contains(&1)).unwrap());
    }
}
