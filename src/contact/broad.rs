//! The broad phase of point-to-surface contact (paper Sec. 2.2.2, Eq. 17, METHOD.md §5): the
//! Verlet list of candidate master segments per slave, and the rule that rebuilds it only when
//! the two largest displacements since the last rebuild exceed the skin.

use rayon::prelude::*;

use super::{ContactPass, FoundFaces, MasterView};
use crate::body::{Body, PdBody};
use crate::case::neighbours::CellGrid;
use crate::math::Vec3;

/// The Verlet list of one pass: candidate segments per slave.
#[derive(Clone, Debug, Default)]
pub struct VerletList {
    /// `offsets[k]..offsets[k+1]` are slave `k`'s candidates in `candidates`.
    pub(super) offsets: Vec<u32>,
    pub(super) candidates: Vec<u32>,
    /// Positions of the slaves and master nodes at the last rebuild.
    slave_ref: Vec<Vec3>,
    master_ref: Vec<Vec3>,
    /// Rebuilds so far.
    pub rebuilds: usize,
    built: bool,
}

/// The two largest of a set of moves: the Verlet list holds while their sum stays under the
/// skin (two particles closing on each other from opposite sides).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TopTwo(pub [f64; 2]);

impl TopTwo {
    /// Takes one more move.
    pub fn push(&mut self, d: f64) {
        let top = &mut self.0;
        if d > top[0] {
            top[1] = top[0];
            top[0] = d;
        } else if d > top[1] {
            top[1] = d;
        }
    }

    /// The two largest of both sets: what one set holding them all would give, when no move
    /// is in both.
    pub fn merge(mut self, other: TopTwo) -> TopTwo {
        for d in other.0 {
            self.push(d);
        }
        self
    }

    /// The largest two added.
    pub fn sum(&self) -> f64 {
        self.0[0] + self.0[1]
    }
}

impl ContactPass {
    /// Whether the two largest displacements since the last rebuild exceed the skin.
    pub(super) fn needs_rebuild(&self, sb: &PdBody, view: MasterView<'_>) -> bool {
        self.moves(sb, view, |_| true)
            .is_none_or(|top| top.sum() > self.skin)
    }

    /// The two largest moves since the last rebuild (`None` before the first) of the slaves
    /// and of the master nodes `counts` accepts: on a decomposed run each rank counts the
    /// master nodes it owns, so that no node's move is counted by two ranks.
    pub(super) fn moves(
        &self,
        sb: &PdBody,
        view: MasterView<'_>,
        counts: impl Fn(u32) -> bool,
    ) -> Option<TopTwo> {
        if !self.verlet.built {
            return None;
        }
        let mut top = TopTwo::default();
        for (k, &s) in self.slaves.iter().enumerate() {
            top.push((self.slave_point(sb, s) - self.verlet.slave_ref[k]).norm());
        }
        for (k, &n) in self.master_nodes.iter().enumerate() {
            if counts(n) {
                top.push((view.node(n) - self.verlet.master_ref[k]).norm());
            }
        }
        Some(top)
    }

    /// Rebuilds the candidate lists from current positions.
    pub(super) fn rebuild(&mut self, sb: &PdBody, view: MasterView<'_>) {
        let radius = self.cutoff + self.skin;
        let master_pos: Vec<Vec3> = self.master_nodes.iter().map(|&n| view.node(n)).collect();
        let grid = CellGrid::new(&master_pos, radius);
        let segs = view.segments();
        let big: Vec<(u32, Vec3, Vec3)> = self
            .big_segments
            .iter()
            .map(|&k| {
                let c = view.corners(k as usize);
                let lo = c.iter().fold(Vec3::repeat(f64::INFINITY), |a, p| a.inf(p));
                let hi = c
                    .iter()
                    .fold(Vec3::repeat(f64::NEG_INFINITY), |a, p| a.sup(p));
                (k, lo - Vec3::repeat(radius), hi + Vec3::repeat(radius))
            })
            .collect();
        let lists: Vec<Vec<u32>> = self
            .slaves
            .par_iter()
            .enumerate()
            .map(|(k, &s)| {
                let p = self.slave_point(sb, s);
                let mut out = Vec::new();
                grid.for_each_candidate(&p, radius, |m| {
                    if (master_pos[m as usize] - p).norm_squared() <= radius * radius {
                        let node = self.master_nodes[m as usize] as usize;
                        let (a, b) = (
                            self.node_seg_offsets[node] as usize,
                            self.node_seg_offsets[node + 1] as usize,
                        );
                        out.extend_from_slice(&self.node_segs[a..b]);
                    }
                });
                for (k, lo, hi) in &big {
                    if (0..3).all(|d| p[d] >= lo[d] && p[d] <= hi[d]) {
                        out.push(*k);
                    }
                }
                out.sort_unstable();
                out.dedup();
                if self.found.is_some() {
                    // Its own surface presses only where no intact bond holds it.
                    let partners = FoundFaces::partners(sb, s);
                    out.retain(|&seg| FoundFaces::apart(s, &segs[seg as usize].nodes, &partners));
                }
                if let Some(c) = &self.crack {
                    // A crack's face presses on the other face only.
                    out.retain(|&seg| {
                        let side = c.segment_side[seg as usize];
                        side != u8::MAX && side != c.slave_side[k]
                    });
                }
                out
            })
            .collect();
        let slave_ref: Vec<Vec3> = self
            .slaves
            .iter()
            .map(|&s| self.slave_point(sb, s))
            .collect();
        let v = &mut self.verlet;
        v.offsets.clear();
        v.candidates.clear();
        v.offsets.push(0);
        for l in lists {
            v.candidates.extend_from_slice(&l);
            v.offsets.push(v.candidates.len() as u32);
        }
        v.slave_ref = slave_ref;
        v.master_ref = master_pos;
        v.rebuilds += 1;
        v.built = true;
    }

    /// Rebuilds the Verlet list now, whatever the motion since the last rebuild (for timing).
    pub fn rebuild_verlet(&mut self, bodies: &[Body]) {
        let sb = bodies[self.slave].as_pd().expect("slave is deformable");
        let shift = self.shift.clone();
        self.rebuild(sb, self.view(bodies, &shift));
    }
}

pub(super) fn distinct(nodes: &[u32; 4]) -> impl Iterator<Item = u32> + '_ {
    nodes
        .iter()
        .enumerate()
        .filter(|(k, n)| !nodes[..*k].contains(n))
        .map(|(_, &n)| n)
}

#[cfg(test)]
mod tests {
    use super::TopTwo;

    fn top(moves: &[f64]) -> TopTwo {
        let mut t = TopTwo::default();
        for &d in moves {
            t.push(d);
        }
        t
    }

    #[test]
    fn the_two_largest_moves_of_parts_merge_to_the_wholes() {
        let moves: Vec<f64> = (0..97).map(|i| ((i * 37) % 89) as f64 / 1024.0).collect();
        let whole = top(&moves);
        assert_eq!(whole.0, [88.0 / 1024.0, 87.0 / 1024.0]);
        for parts in 1..=5 {
            let merged = moves
                .chunks(moves.len().div_ceil(parts))
                .map(top)
                .fold(TopTwo::default(), TopTwo::merge);
            assert_eq!(merged, whole, "{parts} parts");
        }
        // A move counted by two parts is counted twice: the sum is then larger than the
        // whole's, which is why each rank counts only the master nodes it owns.
        let twice = top(&[88.0 / 1024.0]).merge(whole);
        assert!(twice.sum() > whole.sum());
    }
}
