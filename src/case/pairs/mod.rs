//! The bond-force pass over each bond pair once (Newton's third law), as LAMMPS's `newton on`
//! half neighbour lists do.
//!
//! A bond's force on `i` is `w (|y| − L) y/|y|` (Eq. 26 times the volumes, finite kinematics)
//! or `w ((η·ξ)/|ξ|²) ξ` (linearised), and its force on `j` is the opposite, because the
//! weight `w = c G v_c V_i V_j / L` is symmetric (see [`crate::body`]). So each pair `i < j`
//! is stored once, with its partner, length and weight (12 bytes a pair, 6 a directed bond),
//! evaluated once, and added to both ends. The pass streams half the bytes and does half the
//! arithmetic of a pass over directed bonds; that matters most with several threads, which
//! share the memory bandwidth.
//!
//! Threads: the particles are cut into as many ranges as there are threads, with equal pair
//! counts; each thread sums its own particles' forces in the order one thread would, first
//! evaluating the pairs that reach into its range from earlier particles ([`buffers`]). The
//! result has the same bits whatever the thread count, and whatever the ranks of a decomposed
//! run ([`PairList::restricted`]); each bond's force has the same bits whichever group of the
//! vector kernel it falls in ([`kernel`]).
//!
//! Symmetry planes: bonds to mirror images (partners at or past the particle count) act on
//! the real particle only, so they stay directed, in a list of their own. A particle on a
//! plane holds a share `s_i` (½ per plane) of its volume while its partners see the whole, so
//! `w_ij = K V_i V_j / s_j` and `w_ji = K V_i V_j / s_i` differ; `w_ij / s_i` does not. The
//! pairs store that, and a particle's summed force is multiplied by its own share at the end.

mod buffers;
mod kernel;

use std::sync::atomic::{AtomicU64, Ordering};

use rayon::prelude::*;

pub use buffers::ForceBuffers;
use kernel::{bond_sum, Scatter};
#[cfg(target_arch = "x86_64")]
pub(crate) use kernel::{gather4, has_avx2_fma, hsum};

use crate::case::neighbours::BondList;
use crate::math::Vec3;

/// A number for each pair list made, so that [`ForceBuffers`] know the list they were laid
/// out for.
fn next_id() -> u64 {
    static NEXT: AtomicU64 = AtomicU64::new(1);
    NEXT.fetch_add(1, Ordering::Relaxed)
}

/// Particles per work item of the summing pass.
const CHUNK: usize = 1024;

/// Bond pairs `i < j` between real particles (each once), and the directed bonds to mirror
/// images, each with its weight `w` (N/m).
#[derive(Clone, Debug, Default)]
pub struct PairList {
    /// This list's number (a clone keeps it: same pairs).
    id: u64,
    /// Real particles.
    particles: usize,
    /// The particles whose forces a pass computes: all, or a rank's own ([`Self::restricted`]).
    rows: std::ops::Range<usize>,
    /// Per real particle: the share of its volume the model holds (empty: all 1).
    share: Vec<f64>,
    /// Pairs `(i, j > i)`: partner, reference length and weight, in compressed-row form.
    pairs: BondList,
    pair_weight: Vec<f32>,
    /// Directed bonds from a real particle to a mirror image.
    images: BondList,
    image_weight: Vec<f32>,
}

impl PairList {
    /// The pairs of a directed bond list over `particles` real particles (partners at or past
    /// it are mirror images), with the weight of each directed bond and the share of each
    /// particle (empty: no symmetry planes). The weight of a pair is that of its bond
    /// `i → j`, `i < j`, divided by `share[i]`.
    pub fn from_bonds(
        bonds: &BondList,
        weight: &[f32],
        share: &[f64],
        particles: usize,
    ) -> PairList {
        let share = if share.iter().all(|&s| s == 1.0) {
            Vec::new()
        } else {
            share.to_vec()
        };
        let scale = |i: usize| share.get(i).map_or(1.0, |&s| 1.0 / s);
        let split = |keep: &dyn Fn(usize, usize) -> bool| {
            // Counted first, so that the lists take their length and no more (grown by
            // doubling they would hold up to twice it: most of a model's memory).
            let total = (0..particles)
                .flat_map(|i| bonds.range(i).map(move |b| (i, b)))
                .filter(|&(i, b)| keep(i, bonds.partner[b] as usize))
                .count();
            let mut list = BondList {
                offsets: Vec::with_capacity(particles + 1),
                partner: Vec::with_capacity(total),
                length: Vec::with_capacity(total),
            };
            let mut w = Vec::with_capacity(total);
            list.offsets.push(0);
            for i in 0..particles {
                for b in bonds.range(i) {
                    let j = bonds.partner[b] as usize;
                    if keep(i, j) {
                        list.partner.push(j as u32);
                        list.length.push(bonds.length[b]);
                        // Pairs: w_ij / s_i (symmetric); images: w_ij as it is.
                        let scale = if j < particles { scale(i) } else { 1.0 };
                        w.push((f64::from(weight[b]) * scale) as f32);
                    }
                }
                list.offsets.push(list.partner.len());
            }
            (list, w)
        };
        let (pairs, pair_weight) = split(&|i, j| i < j && j < particles);
        let (images, image_weight) = split(&|_, j| j >= particles);
        PairList {
            id: next_id(),
            particles,
            rows: 0..particles,
            share,
            pairs,
            pair_weight,
            images,
            image_weight,
        }
    }

    /// A pair list made directly (each pair once, no mirror images), with
    /// `weight(pairs, i, b)` the weight of pair `b` of particle `i`.
    pub fn from_pairs(
        pairs: BondList,
        weight: impl Fn(&BondList, usize, usize) -> f32 + Sync,
    ) -> PairList {
        let particles = pairs.particles();
        let mut pair_weight = vec![0f32; pairs.len()];
        pairs
            .blocks(&mut pair_weight, CHUNK)
            .into_par_iter()
            .for_each(|(range, w)| {
                let base = pairs.offsets[range.start];
                for i in range {
                    for b in pairs.range(i) {
                        w[b - base] = weight(&pairs, i, b);
                    }
                }
            });
        PairList {
            id: next_id(),
            particles,
            rows: 0..particles,
            share: Vec::new(),
            images: BondList {
                offsets: vec![0; particles + 1],
                ..BondList::default()
            },
            image_weight: Vec::new(),
            pairs,
            pair_weight,
        }
    }

    /// This list as a rank's part: the pairs given (from
    /// [`build_pairs_touching`](crate::case::neighbours::build_pairs_touching)) are those that
    /// act on `owned`, as [`Self::restricted`] would have kept them of the whole list.
    pub fn owning(mut self, owned: std::ops::Range<usize>) -> PairList {
        self.rows = owned;
        self
    }

    /// The pairs and image bonds that act on the particles of `owned`: a pair `(i, j)` with
    /// either end in the range, an image bond whose particle is in it. A pass over the result
    /// gives every particle of `owned` its whole force (the others a part of theirs): what one
    /// rank of a decomposed run evaluates ([`crate::parallel`]).
    pub fn restricted(&self, owned: std::ops::Range<usize>) -> PairList {
        let keep = |list: &BondList, w: &[f32], both: bool| {
            let mut out = BondList {
                offsets: Vec::with_capacity(self.particles + 1),
                ..BondList::default()
            };
            let mut weight = Vec::new();
            out.offsets.push(0);
            for i in 0..self.particles {
                let mine = owned.contains(&i);
                for b in list.range(i) {
                    let j = list.partner[b] as usize;
                    if mine || (both && owned.contains(&j)) {
                        out.partner.push(list.partner[b]);
                        out.length.push(list.length[b]);
                        weight.push(w[b]);
                    }
                }
                out.offsets.push(out.partner.len());
            }
            // A rank's part of the list, which lives as long as the run: no slack.
            out.partner.shrink_to_fit();
            out.length.shrink_to_fit();
            weight.shrink_to_fit();
            (out, weight)
        };
        let (pairs, pair_weight) = keep(&self.pairs, &self.pair_weight, true);
        let (images, image_weight) = keep(&self.images, &self.image_weight, false);
        PairList {
            id: next_id(),
            particles: self.particles,
            rows: owned,
            share: self.share.clone(),
            pairs,
            pair_weight,
            images,
            image_weight,
        }
    }

    /// Removes the bond between `i` and `j` (a real pair, either way round, or `i`'s bond to
    /// the mirror image `j`) by zeroing its weight, where the list holds it. The list gets a
    /// new number, so that [`ForceBuffers`] lay out their copies of the weights again.
    pub fn remove(&mut self, i: usize, j: usize) {
        let (list, weight, row, partner) = if j < self.particles {
            (&self.pairs, &mut self.pair_weight, i.min(j), i.max(j))
        } else {
            (&self.images, &mut self.image_weight, i, j)
        };
        if let Some(b) = list
            .range(row)
            .find(|&b| list.partner[b] as usize == partner)
        {
            weight[b] = 0.0;
            self.id = next_id();
        }
    }

    /// Real particles.
    pub fn particles(&self) -> usize {
        self.particles
    }

    /// Directed bonds: each pair counts twice, a bond to a mirror image once.
    pub fn directed_bonds(&self) -> usize {
        2 * self.pairs.len() + self.images.len()
    }

    /// Bytes held by the arrays.
    pub fn bytes(&self) -> usize {
        self.pairs.bytes()
            + self.images.bytes()
            + 4 * (self.pair_weight.len() + self.image_weight.len())
    }

    /// Strain energy `¼ Σ_pairs (w_ij + w_ji) (|y| − L)² + ¼ Σ_images w (|y| − L)²` at
    /// positions `pos` (finite kinematics): a bond to an image carries the half of its
    /// mirrored pair that belongs to this model.
    pub fn strain_energy(&self, pos: &[Vec3]) -> f64 {
        self.strain_blocks(pos).into_iter().fold(0.0, |a, b| a + b)
    }

    /// [`strain_energy`](Self::strain_energy) of the rows' pairs (pair `(i, j > i)` counted
    /// in row `i`), summed over each block of [`BLOCK`](crate::reduction::BLOCK) rows: the
    /// blocks of all ranks' restricted lists, added in order, give the whole list's bits.
    pub fn strain_blocks(&self, pos: &[Vec3]) -> Vec<f64> {
        let term = |list: &BondList, w: &[f32], i: usize| -> f64 {
            list.range(i)
                .map(|b| {
                    let s = (pos[list.partner[b] as usize] - pos[i]).norm() - list.length(b);
                    f64::from(w[b]) * s * s
                })
                .sum()
        };
        crate::reduction::block_sums(
            self.rows.clone(),
            || 0.0,
            |i| {
                let si = self.share.get(i).copied().unwrap_or(1.0);
                let pairs = &self.pairs;
                let paired: f64 = pairs
                    .range(i)
                    .map(|b| {
                        let j = pairs.partner[b] as usize;
                        let sj = self.share.get(j).copied().unwrap_or(1.0);
                        let s = (pos[j] - pos[i]).norm() - pairs.length(b);
                        (si + sj) * f64::from(self.pair_weight[b]) * s * s
                    })
                    .sum();
                0.25 * paired + 0.25 * term(&self.images, &self.image_weight, i)
            },
            |a, b| a + b,
        )
    }

    /// Pairs in row `i` (partners `j > i`): its share of a force pass's work.
    pub fn row_pairs(&self, i: usize) -> usize {
        self.pairs.range(i).len()
    }

    /// The real particles whose positions a pass over this list reads: both ends of its
    /// pairs, and the particles of its image bonds.
    pub fn particles_read(&self) -> Vec<bool> {
        let mut read = vec![false; self.particles];
        for i in 0..self.particles {
            let (pairs, images) = (self.pairs.range(i), self.images.range(i));
            if !pairs.is_empty() || !images.is_empty() {
                read[i] = true;
            }
            for b in pairs {
                read[self.pairs.partner[b] as usize] = true;
            }
        }
        read
    }

    /// The rows cut into consecutive ranges with about equal work, one per part: a range's
    /// pairs, one unit per particle, and `extra[p]` for part `p` (its halo; empty: none).
    fn partition(&self, parts: usize, extra: &[usize]) -> Vec<std::ops::Range<usize>> {
        let (first, last) = (self.rows.start, self.rows.end);
        let offsets = &self.pairs.offsets;
        // Work up to particle k: its pairs plus one unit per particle.
        let work = |k: usize| offsets[k] + k - offsets[first] - first;
        let extra = |p: usize| extra.get(p).copied().unwrap_or(0);
        let total = work(last) + (0..parts).map(extra).sum::<usize>();
        let mut bounds = vec![first];
        let mut before = 0;
        for p in 1..parts {
            // Parts 0..p take p shares of the whole, their extra work included.
            before += extra(p - 1);
            let target = (total * p / parts).saturating_sub(before);
            let (mut lo, mut hi) = (*bounds.last().unwrap_or(&first), last);
            while lo < hi {
                let mid = (lo + hi) / 2;
                if work(mid) < target {
                    lo = mid + 1;
                } else {
                    hi = mid;
                }
            }
            bounds.push(lo);
        }
        bounds.push(last);
        bounds.windows(2).map(|w| w[0]..w[1]).collect()
    }
}

/// How bonds stretch.
#[derive(Clone, Copy, Debug)]
pub enum PairKinematics<'a> {
    /// `w (|y| − L) y/|y|`.
    Finite,
    /// `w ((η·ξ)/|ξ|²) ξ`, with the reference positions (real particles, then images).
    Small(&'a [Vec3]),
}

/// Bond forces at positions `pos` (real particles, then mirror images): for every real
/// particle `i` of the list's rows (all but in a rank's restricted list), `finish(i, f_i)`
/// receives its total bond force and returns the value stored in `out[i]` (so that a solver
/// can add loads or kick velocities in the same pass). `out` holds every real particle, or
/// the rows alone (a rank that keeps values for its own particles only): `out[i − rows.start]`.
pub fn pair_forces<T: Send>(
    list: &PairList,
    pos: &[Vec3],
    kinematics: PairKinematics,
    buffers: &mut ForceBuffers,
    out: &mut [T],
    finish: impl Fn(usize, Vec3, &mut T) + Sync,
) {
    let n = list.particles;
    assert!((out.len() == n || out.len() == list.rows.len()) && pos.len() >= n);
    // The kernels take the reference positions for linearised kinematics, none for finite.
    let reference = match kinematics {
        PairKinematics::Finite => None,
        PairKinematics::Small(x) => {
            assert!(x.len() >= pos.len());
            Some(x)
        }
    };
    let rows = list.rows.clone();
    let parts = rayon::current_num_threads()
        .clamp(1, 64)
        .min(rows.len().max(1));
    buffers.prepare(list, parts);
    let ForceBuffers {
        ranges, halos, sum, ..
    } = buffers;
    // Each thread's part of the one buffer.
    let mut parts_of_sum = Vec::with_capacity(ranges.len());
    let mut rest = &mut sum[..];
    for r in ranges.iter() {
        let (head, tail) = std::mem::take(&mut rest).split_at_mut(r.len());
        parts_of_sum.push(head);
        rest = tail;
    }
    parts_of_sum
        .into_par_iter()
        .zip(ranges.par_iter())
        .zip(halos.par_iter())
        .for_each(|((buf, range), halo)| {
            buf.fill(Vec3::zeros());
            let mut out = Scatter {
                buf,
                first: range.start,
            };
            // The pairs from earlier particles first, in their order, as one thread adds them.
            for (h, &k) in halo.rows.iter().enumerate() {
                bond_sum::<true>(
                    &halo.bonds,
                    &halo.weight,
                    pos,
                    reference,
                    h,
                    k as usize,
                    &mut out,
                );
            }
            for i in range.clone() {
                if list.pairs.range(i).is_empty() {
                    continue;
                }
                let f = bond_sum::<true>(
                    &list.pairs,
                    &list.pair_weight,
                    pos,
                    reference,
                    i,
                    i,
                    &mut out,
                );
                out.buf[i - range.start] += f;
            }
        });
    let sum = &buffers.sum;
    let out = if out.len() == n {
        &mut out[rows.clone()]
    } else {
        out
    };
    out.par_chunks_mut(CHUNK).enumerate().for_each(|(c, out)| {
        for (k, o) in out.iter_mut().enumerate() {
            let i = rows.start + c * CHUNK + k;
            let mut f = sum[i - rows.start];
            if let Some(&s) = list.share.get(i) {
                f *= s;
            }
            // Bonds to mirror images act on `i` alone.
            if !list.images.range(i).is_empty() {
                f += bond_sum::<false>(
                    &list.images,
                    &list.image_weight,
                    pos,
                    reference,
                    i,
                    i,
                    &mut Scatter::none(),
                );
            }
            finish(i, f, o);
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::case::neighbours::build_bonds;

    /// Forces of the pair pass against a direct sum over directed bonds, for both
    /// kinematics and several thread counts.
    #[test]
    fn pair_pass_matches_directed_sum() {
        let n = 9;
        let x: Vec<Vec3> = (0..n * n * n)
            .map(|i| Vec3::new((i % n) as f64, ((i / n) % n) as f64, (i / (n * n)) as f64) * 0.1)
            .collect();
        let bonds = build_bonds(&x, 0.35);
        // Shares of particles on symmetry planes (½ per plane) and the directed weights they
        // give, `w_ij = K_ij / s_j` with `K` symmetric and varying from bond to bond.
        let share: Vec<f64> = (0..x.len()).map(|i| [1.0, 0.5, 1.0, 0.25][i % 4]).collect();
        let mut weight = vec![0f32; bonds.len()];
        for i in 0..x.len() {
            for b in bonds.range(i) {
                let j = bonds.partner[b] as usize;
                let k = (1.0 + ((i.min(j) * 7 + i.max(j) * 13) % 11) as f64) * 1e3;
                weight[b] = (k / share[j]) as f32;
            }
        }
        let y: Vec<Vec3> = x
            .iter()
            .map(|p| p + Vec3::new((p.y * 7.0).sin(), (p.z * 5.0).cos(), p.x * p.y) * 0.01)
            .collect();
        let list = PairList::from_bonds(&bonds, &weight, &share, x.len());
        assert_eq!(list.directed_bonds(), bonds.len());
        // The strain energy against the directed sum `¼ Σ w_ij s²`.
        let directed_energy: f64 = (0..x.len())
            .flat_map(|i| bonds.range(i).map(move |b| (i, b)))
            .map(|(i, b)| {
                let s = (y[bonds.partner[b] as usize] - y[i]).norm() - bonds.length(b);
                0.25 * f64::from(weight[b]) * s * s
            })
            .sum();
        let e = list.strain_energy(&y);
        assert!(
            (e - directed_energy).abs() < 1e-9 * directed_energy,
            "{e} vs {directed_energy}"
        );
        for small in [false, true] {
            let direct: Vec<Vec3> = (0..x.len())
                .map(|i| {
                    bonds
                        .range(i)
                        .map(|b| {
                            let j = bonds.partner[b] as usize;
                            let w = f64::from(weight[b]);
                            if small {
                                let xi = x[j] - x[i];
                                xi * (w * (y[j] - x[j] - (y[i] - x[i])).dot(&xi)
                                    / xi.norm_squared())
                            } else {
                                let d = y[j] - y[i];
                                d * (w * (d.norm() - bonds.length(b)) / d.norm())
                            }
                        })
                        .sum()
                })
                .collect();
            for threads in [1, 2, 3] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let mut out = vec![Vec3::zeros(); x.len()];
                let mut buffers = ForceBuffers::default();
                pool.install(|| {
                    let kin = if small {
                        PairKinematics::Small(&x)
                    } else {
                        PairKinematics::Finite
                    };
                    pair_forces(&list, &y, kin, &mut buffers, &mut out, |_, f, o| *o = f);
                });
                for i in 0..x.len() {
                    let scale = direct[i].norm().max(1.0);
                    assert!(
                        (out[i] - direct[i]).norm() < 1e-9 * scale,
                        "small {small} threads {threads} particle {i}: {} vs {}",
                        out[i],
                        direct[i]
                    );
                }
                // Newton's third law, with each particle's share: Σ f_i / s_i = 0.
                let total: Vec3 = out.iter().zip(&share).map(|(f, s)| f / *s).sum();
                assert!(total.norm() < 1e-6, "{total}");
            }
        }
    }

    #[test]
    fn partition_covers_the_particles() {
        let n = 6;
        let x: Vec<Vec3> = (0..n * n * n)
            .map(|i| Vec3::new((i % n) as f64, ((i / n) % n) as f64, (i / (n * n)) as f64))
            .collect();
        let bonds = build_bonds(&x, 2.1);
        let list = PairList::from_bonds(&bonds, &vec![1.0; bonds.len()], &[], x.len());
        for parts in 1..8 {
            let r = list.partition(parts, &[]);
            assert_eq!(r.len(), parts);
            assert_eq!(r[0].start, 0);
            assert_eq!(r[parts - 1].end, x.len());
            for w in r.windows(2) {
                assert_eq!(w[0].end, w[1].start);
            }
        }
    }

    /// A Morton-ordered cubic lattice of `n³` points (spacing 1) and its pairs within 3.0002.
    fn morton_lattice(n: usize) -> (Vec<Vec3>, PairList) {
        let coords: Vec<[f64; 3]> = (0..n * n * n)
            .map(|i| [(i % n) as f64, ((i / n) % n) as f64, (i / (n * n)) as f64])
            .collect();
        let mut order: Vec<u32> = (0..coords.len() as u32).collect();
        crate::case::discretize::sort_morton(&mut order, &coords, 1.0);
        let x: Vec<Vec3> = order
            .iter()
            .map(|&k| Vec3::from(coords[k as usize]))
            .collect();
        let bonds = build_bonds(&x, 3.0002);
        let list = PairList::from_bonds(&bonds, &vec![1.0; bonds.len()], &[], x.len());
        (x, list)
    }

    /// Forces of a stretched lattice on `threads` threads.
    fn forces(
        list: &PairList,
        y: &[Vec3],
        threads: usize,
        buffers: &mut ForceBuffers,
    ) -> Vec<Vec3> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut out = vec![Vec3::zeros(); y.len()];
        pool.install(|| {
            pair_forces(
                list,
                y,
                PairKinematics::Finite,
                buffers,
                &mut out,
                |_, f, o| *o = f,
            )
        });
        out
    }

    /// Every thread count gives the one-thread forces, bit for bit, and the pairs evaluated
    /// twice (the halos) stay a small share of the pairs.
    #[test]
    fn any_thread_count_gives_the_one_thread_bits() {
        let (x, list) = morton_lattice(32);
        let y: Vec<Vec3> = x
            .iter()
            .map(|p| p * 1.001 + Vec3::new(0.0, 0.0, 1e-4 * p.x * p.x))
            .collect();
        let mut reference = ForceBuffers::default();
        let one = forces(&list, &y, 1, &mut reference);
        assert_eq!(reference.halo_pairs_per_pair(&list), 0.0);
        for threads in [2, 3, 4, 8, 16] {
            let mut buffers = ForceBuffers::default();
            let f = forces(&list, &y, threads, &mut buffers);
            assert_eq!(f, one, "{threads} threads");
            let halo = buffers.halo_pairs_per_pair(&list);
            assert!(halo < 0.05 * threads as f64, "{threads} threads: {halo}");
            // Same bits from call to call on the same buffers.
            assert_eq!(f, forces(&list, &y, threads, &mut buffers));
        }
    }

    /// A rank's restricted list gives its particles the bits of the whole list.
    #[test]
    fn a_restricted_list_gives_its_rows_the_whole_lists_bits() {
        let (x, list) = morton_lattice(16);
        let y: Vec<Vec3> = x
            .iter()
            .map(|p| p * 1.002 + Vec3::new(1e-3 * p.y * p.z, 0.0, 0.0))
            .collect();
        let whole = forces(&list, &y, 1, &mut ForceBuffers::default());
        let n = x.len();
        for owned in [0..n / 3, n / 3..2 * n / 3 + 5, 2 * n / 3 + 5..n] {
            let part = list.restricted(owned.clone());
            for threads in [1, 2] {
                let f = forces(&part, &y, threads, &mut ForceBuffers::default());
                assert_eq!(
                    f[owned.clone()],
                    whole[owned.clone()],
                    "{owned:?}, {threads}"
                );
            }
        }
    }

    /// Buffers laid out for one pair list and reused for another of the same size give the
    /// other's forces (the layout is redone, not taken for the old list's).
    #[test]
    fn buffers_follow_their_pair_list() {
        let (x, list) = morton_lattice(12);
        // The same particles in reverse order: other partners, other blocks.
        let xr: Vec<Vec3> = x.iter().rev().copied().collect();
        let bonds = build_bonds(&xr, 3.0002);
        let reversed = PairList::from_bonds(&bonds, &vec![1.0; bonds.len()], &[], xr.len());
        let stretch = |p: &Vec3| p * 1.002 + Vec3::new(1e-3 * p.y * p.z, 0.0, 0.0);
        let (y, yr): (Vec<Vec3>, Vec<Vec3>) = (
            x.iter().map(stretch).collect(),
            xr.iter().map(stretch).collect(),
        );
        let mut shared = ForceBuffers::default();
        let a = forces(&list, &y, 3, &mut shared);
        let b = forces(&reversed, &yr, 3, &mut shared);
        assert_eq!(a, forces(&list, &y, 3, &mut ForceBuffers::default()));
        assert_eq!(b, forces(&reversed, &yr, 3, &mut ForceBuffers::default()));
        assert_eq!(a, forces(&list, &y, 3, &mut shared));
    }
}
