//! Solids that the horizon leaves in pieces: an element longer than the bonds reach.
//!
//! A bond joins two particles within the horizon δ (plus half a spacing, Eq. 10), whatever
//! the mesh says; the mesh's elements join their nodes whatever their length. Where an
//! element is longer than the bonds reach (a coarse element beside fine ones, a thin plate's
//! long cells) one solid of the mesh falls into pieces that no bond joins. Such pieces are not
//! the mesh's own pieces (solids that share no node, which a `[[contact]]` of the body with
//! itself keeps apart): they pass through each other, or a contact between them pushes on
//! faces that are one solid, and the run does not settle. The case notes where it happens
//! ([`SolidSplit`]) and the horizon factor that would join them; `run` refuses the body with
//! that cause, and `convert` writes that factor.
//!
//! The mesh's own pieces are never joined: two solids that touch (a roller on a block, meshed
//! each on its own) are two solids, as for an FE code, and a bond between them would glue
//! them where they touch ([`and_between_pieces`]).

use rayon::prelude::*;

use crate::case::neighbours::{join, BondList};
use crate::case::sight::COINCIDENT;
use crate::case::Ghosts;
use crate::math::{Vec3, NOT_A_PARTICLE};
use pdcontact_importers::{solid_pieces, Mesh};

/// The mesh's pieces (its solids that share no node), as the bonds see them.
pub struct MeshPieces {
    /// Each particle's piece.
    pub label: Vec<u32>,
    /// Bonds no longer than this join nodes on top of each other, which
    /// [`crate::case::sight::refuse_coincident`] refuses by name: they are left to it
    /// (negative where the pieces are an assembly's parts: every bond between them goes).
    pub coincident: f64,
}

/// The mesh's pieces, or `None` where the mesh is one piece. `node`: each particle's mesh node;
/// `apart`: the pieces are the parts of an assembly, whose nodes may lie on each other.
pub fn mesh_pieces(mesh: &Mesh, node: &[u32], spacing: f64, apart: bool) -> Option<MeshPieces> {
    let (label, count) = solid_pieces(mesh);
    (count > 1).then(|| MeshPieces {
        label: node.iter().map(|&k| label[k as usize]).collect(),
        coincident: if apart { -1.0 } else { COINCIDENT * spacing },
    })
}

/// `across_gaps` (`(particle, bond)`, [`crate::case::sight::bonds_across_gaps`]) and the bonds
/// between particles of different pieces of the mesh (a bond to a mirror image by its
/// source's piece), each once. The bonds reach across a gap narrower than the
/// horizon, and where two pieces touch no gap cuts them ([`crate::case::sight`] cuts bonds
/// that leave the body and enter it again): a roller meshed apart from the block it lies on
/// was glued to it along their line of contact, and the pieces, one to the bonds, were not
/// kept apart by a contact.
pub fn and_between_pieces(
    mut across_gaps: Vec<(u32, u32)>,
    bonds: &BondList,
    pieces: Option<&MeshPieces>,
    ghosts: &Ghosts,
) -> Vec<(u32, u32)> {
    let Some(MeshPieces {
        label: piece,
        coincident,
    }) = pieces
    else {
        return across_gaps;
    };
    let n = bonds.particles();
    let between: Vec<(u32, u32)> = (0..n)
        .into_par_iter()
        .flat_map_iter(|i| {
            bonds.range(i).filter_map(move |b| {
                let j = ghosts.source_of(bonds.partner[b] as usize, n);
                let apart = bonds.length(b) > *coincident;
                (apart && piece[j] != piece[i]).then_some((i as u32, b as u32))
            })
        })
        .collect();
    across_gaps.extend(between);
    across_gaps.sort_unstable();
    across_gaps.dedup();
    across_gaps
}

/// Two particles that share a solid element, farther apart than the bonds surely reach.
#[derive(Clone, Copy, Debug)]
pub struct LongPair {
    pub a: u32,
    pub b: u32,
    pub length: f64,
    /// The element's number in the mesh file.
    pub element: u64,
}

/// Where one solid of the mesh is in pieces that no bond joins.
#[derive(Clone, Debug, PartialEq)]
pub struct SolidSplit {
    /// The longest element pair (mesh node numbers) that the joining needs.
    pub nodes: [u64; 2],
    /// Its element's number in the mesh file.
    pub element: u64,
    /// Its length, m.
    pub length: f64,
    /// How many more pieces the bonds leave than the mesh's solids are.
    pub extra_pieces: usize,
    /// The smallest horizon factor (a tenth above) whose bonds reach every such pair.
    pub horizon_factor: f64,
}

impl SolidSplit {
    /// What `run` says when it refuses the body.
    pub fn message(&self, spacing: f64, horizon_factor: f64) -> String {
        format!(
            "the bonds cut its mesh's solids into {} more piece{} than they are: element {} joins nodes {} and {}, {:.4e} m apart, beyond the bonds' reach (horizon δ = {:.4e} m: spacing Δ = {spacing:.4e} m × horizon factor {horizon_factor}, plus Δ/2); the pieces would pass through each other. Set horizon_factor = {} in its [[body]] (the smallest that joins them; `pdcontact convert` writes it), or mesh it finer where its elements are longest",
            self.extra_pieces,
            if self.extra_pieces == 1 { "" } else { "s" },
            self.element,
            self.nodes[0],
            self.nodes[1],
            self.length,
            horizon_factor * spacing,
            self.horizon_factor
        )
    }
}

/// The pairs of particles in one solid element longer than `beyond`, before the elements are
/// let go: none on a mesh whose elements the horizon spans (`beyond`: ¾ of the bonds' reach).
pub fn long_pairs(
    mesh: &Mesh,
    particle_of_node: &[u32],
    position: &[Vec3],
    beyond: f64,
) -> Vec<LongPair> {
    let mut out = Vec::new();
    let mut ps = Vec::new();
    for e in mesh.solids() {
        ps.clear();
        // Particles are corner nodes (mid-side ones may be missing: `MISSING_NODE`).
        ps.extend(
            e.corners()
                .iter()
                .filter_map(|&n| particle_of_node.get(n as usize).copied())
                .filter(|&p| p != NOT_A_PARTICLE),
        );
        for (k, &a) in ps.iter().enumerate() {
            for &b in &ps[k + 1..] {
                let length = (position[a as usize] - position[b as usize]).norm();
                if length > beyond {
                    out.push(LongPair {
                        a: a.min(b),
                        b: a.max(b),
                        length,
                        element: e.id,
                    });
                }
            }
        }
    }
    out
}

/// The split of the mesh's solids by the bonds, if any: the pairs of `pairs` whose particles
/// the bonds leave in different pieces (`label`, [`BondList::components`]), particles without
/// any bond left to the solver's own message. The horizon factor that joins them: the longest
/// pair that joining every piece to its element's neighbours needs (Kruskal over the pairs).
pub fn split(
    pairs: &[LongPair],
    bonds: &BondList,
    label: &[u32],
    node_ids: &[u64],
    particle_node: &[u32],
    spacing: f64,
) -> Option<SolidSplit> {
    let bonded = |p: u32| !bonds.range(p as usize).is_empty();
    let mut across: Vec<&LongPair> = pairs
        .iter()
        .filter(|q| label[q.a as usize] != label[q.b as usize] && bonded(q.a) && bonded(q.b))
        .collect();
    if across.is_empty() {
        return None;
    }
    // Shortest first, the same order on any run.
    across.sort_by(|x, y| {
        x.length
            .total_cmp(&y.length)
            .then(x.a.cmp(&y.a))
            .then(x.b.cmp(&y.b))
    });
    let pieces = label.iter().copied().max().map_or(0, |m| m as usize + 1);
    let mut parent: Vec<u32> = (0..pieces as u32).collect();
    let mut joined = 0;
    let mut last = across[0];
    for q in &across {
        if join(
            &mut parent,
            label[q.a as usize] as usize,
            label[q.b as usize] as usize,
        ) {
            joined += 1;
            last = q;
        }
    }
    // Bonds reach (m + ½) Δ (Eq. 10): in tenths, one above the factor that reaches `last`.
    let tenths = ((last.length / spacing - 0.5) * 10.0).ceil() + 1.0;
    let node = |p: u32| node_ids[particle_node[p as usize] as usize];
    Some(SolidSplit {
        nodes: [node(last.a), node(last.b)],
        element: last.element,
        length: last.length,
        extra_pieces: joined,
        horizon_factor: tenths / 10.0,
    })
}
