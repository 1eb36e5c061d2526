//! The per-thread force buffers of [`pair_forces`](super::pair_forces), touched only where a
//! thread writes.
//!
//! A thread that owns the particles `a..b` adds each pair's force to `i` (its own) and to `j`
//! (`j > i`, often in another thread's range). Each thread needs a buffer indexed like the
//! particles, but it writes only its own range and the partners of its particles: in Morton
//! order a compact region and a layer one horizon deep around it. Clearing and summing whole
//! buffers moves `2 T N × 24` bytes a pass with `T` threads, which grows with `T` until it
//! outweighs the bonds themselves (`12` bytes a pair) at about 16 threads; here each thread
//! clears, and the summing pass reads, only the blocks of [`BLOCK`] particles it writes, so a
//! pass moves `2 N (1 + h) × 24` bytes, `h` the halo's share, whatever `T`.
//!
//! The buffers are allocated zeroed (`calloc`, which maps the pages lazily), so a block that a
//! thread never writes costs no memory either. A block's sum adds the buffers of its writers in
//! thread order: the same bits as adding every buffer, zeros included, in that order.

use std::ops::Range;

use rayon::prelude::*;

use super::PairList;
use crate::math::Vec3;

/// Particles per block: a 4 × 4 × 4 cube of Morton-ordered lattice points, 1.5 kB of forces.
pub(super) const BLOCK: usize = 64;

/// Per-thread scratch of [`pair_forces`](super::pair_forces), kept between calls so that the
/// time loop neither allocates nor recomputes which blocks each thread writes.
#[derive(Clone, Debug, Default)]
pub struct ForceBuffers {
    /// The pair list (its `id`) and thread count the layout was made for.
    key: Option<(u64, usize)>,
    /// Per thread: its particles (about equal numbers of pairs).
    pub(super) ranges: Vec<Range<usize>>,
    /// Per thread: forces over all particles; only its blocks are ever written.
    pub(super) buffers: Vec<Vec<Vec3>>,
    /// Per thread: the blocks it writes, ascending.
    pub(super) blocks: Vec<Vec<u32>>,
    /// Per block `k`: `writers[writer_offsets[k]..writer_offsets[k + 1]]` are the threads that
    /// write it, ascending.
    pub(super) writer_offsets: Vec<u32>,
    pub(super) writers: Vec<u8>,
}

impl ForceBuffers {
    /// Makes the layout for `list` over `parts` threads, unless it is the one in place.
    pub(super) fn prepare(&mut self, list: &PairList, parts: usize) {
        if self.key == Some((list.id, parts)) {
            return;
        }
        let n = list.particles;
        let nblocks = n.div_ceil(BLOCK);
        let ranges = list.partition(parts);
        let pairs = &list.pairs;
        let blocks: Vec<Vec<u32>> = ranges
            .par_iter()
            .map(|range| {
                let mut mark = vec![false; nblocks];
                for i in range.clone() {
                    mark[i / BLOCK] = true;
                    for &j in &pairs.partner[pairs.range(i)] {
                        mark[j as usize / BLOCK] = true;
                    }
                }
                (0..nblocks as u32).filter(|&k| mark[k as usize]).collect()
            })
            .collect();
        let mut count = vec![0u32; nblocks + 1];
        for b in blocks.iter().flatten() {
            count[*b as usize + 1] += 1;
        }
        for k in 0..nblocks {
            count[k + 1] += count[k];
        }
        let mut writers = vec![0u8; count[nblocks] as usize];
        let mut next = count.clone();
        // Threads in order, so that each block's writers come out ascending.
        for (t, bs) in blocks.iter().enumerate() {
            for &b in bs {
                writers[next[b as usize] as usize] = t as u8;
                next[b as usize] += 1;
            }
        }
        // Fresh buffers: blocks a previous layout wrote may not be cleared by this one.
        self.buffers = (0..parts).map(|_| bytemuck::zeroed_vec(n)).collect();
        self.ranges = ranges;
        self.blocks = blocks;
        self.writer_offsets = count;
        self.writers = writers;
        self.key = Some((list.id, parts));
    }

    /// The threads that write block `k`.
    #[inline]
    pub(super) fn writers(&self, k: usize) -> &[u8] {
        &self.writers[self.writer_offsets[k] as usize..self.writer_offsets[k + 1] as usize]
    }

    /// Blocks written, summed over the threads, per block of particles: `1 + h`, the number
    /// the bytes of clearing and summing grow by from one thread to `T`.
    pub fn written_blocks_per_block(&self) -> f64 {
        let nblocks = self.writer_offsets.len().saturating_sub(1);
        self.writers.len() as f64 / nblocks.max(1) as f64
    }
}

/// Zeroes the blocks `blocks` of `buf` (over `n` particles).
pub(super) fn clear_blocks(buf: &mut [Vec3], blocks: &[u32]) {
    let n = buf.len();
    for &b in blocks {
        let start = b as usize * BLOCK;
        buf[start..(start + BLOCK).min(n)].fill(Vec3::zeros());
    }
}
