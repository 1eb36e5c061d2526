//! Bonds across the mesh's own gaps: a slot, a notch or a crack that the mesh has and that is
//! narrower than the horizon (METHOD.md §1).
//!
//! A particle's family is every particle within its horizon (Eq. 10), whatever lies between
//! them; a slot the mesh has, a machined notch or a crack meshed with two faces, narrower than
//! δ, would be bridged by the bonds across it and carry load as if it were not there. Such a
//! bond is removed here, before the corrections, which then see the gap's faces as free
//! faces: its straight line leaves the body through one boundary face and enters it again
//! through another that faces it (their outward normals within [`FACING`] of opposite), or
//! leaves or enters through such a wall and turns by more than [`ROUNDING`] on the way (it
//! rounds the slot's end through the slot). Elsewhere, bonds that graze a concave surface (a
//! chord of a hole, a cap's inner face, a re-entrant corner) are kept, as are bonds to a
//! symmetry plane's mirror images that no face separates. Only faces with a facing face
//! within reach, and the faces near them, are searched: a convex or gently curved body costs
//! one search over its faces (docs/FRACTURE.md, "The notch as the mesh has it"). Nodes on
//! top of each other, whose bond would have no length, are refused ([`refuse_coincident`]).

use rayon::prelude::*;

use pdcontact_importers::FaceSet;

use crate::case::neighbours::{BondList, CellGrid};
use crate::case::Ghosts;
use crate::math::Vec3;

/// Nodes closer than this many spacings are on top of each other ([`refuse_coincident`]).
pub const COINCIDENT: f64 = 1e-6;

/// The outward normals of the faces a bond leaves and re-enters the body by must be within
/// this of opposite (`n_exit · n_entry < −cos 25°`): the two walls of a slot or a notch
/// opening by less than 25°, the two faces of a meshed crack.
pub const FACING: f64 = 0.906;

/// A bond that leaves or enters by a gap's wall is cut where the faces it leaves and enters by
/// turn by more than 60° (`n_exit · n_entry < cos 60°`): it rounds the gap's end (a slot's
/// wall and its end meet at 90°), rather than running along one curved wall.
pub const ROUNDING: f64 = 0.5;

/// A boundary triangle: its corners and outward unit normal.
#[derive(Clone, Copy, Debug)]
struct Triangle {
    p: [Vec3; 3],
    n: Vec3,
}

/// The body's boundary faces as triangles (quads split along a diagonal), with their mirror
/// images across every combination of the symmetry planes, so that a bond to an image meets
/// the faces it would cross in the whole body.
fn triangles(faces: &FaceSet, coords: &[[f64; 3]], ghosts: &Ghosts) -> Vec<Triangle> {
    let x = |k: u32| Vec3::from(coords[k as usize]);
    let mut base = Vec::with_capacity(2 * faces.boundary.len());
    for f in &faces.boundary {
        let [a, b, c, d] = f.nodes;
        let mut push = |p: [Vec3; 3]| {
            let n = (p[1] - p[0]).cross(&(p[2] - p[0]));
            let l = n.norm();
            if l > 0.0 {
                base.push(Triangle { p, n: n / l });
            }
        };
        push([x(a), x(b), x(c)]);
        if !f.is_triangle() {
            push([x(a), x(c), x(d)]);
        }
    }
    let masks = 1u8 << ghosts.planes.len();
    let mut out = base.clone();
    for mask in 1..masks {
        out.extend(base.iter().map(|t| {
            let p = t.p.map(|q| ghosts.reflect(q, mask));
            // A reflection turns the winding inside out: the normal is the reflected one.
            let n = ghosts.reflect(t.n + t.p[0], mask) - p[0];
            Triangle { p, n }
        }));
    }
    out
}

/// Where the segment `a → a + d` meets the triangle: its parameter `t` in [0, 1], with a
/// margin of `1e-9` at the ends and on the triangle's edges so that a segment from a node of
/// the face, or through an edge, is counted (Möller and Trumbore).
fn crossing(a: Vec3, d: Vec3, t: &Triangle) -> Option<f64> {
    const EPS: f64 = 1e-9;
    let e1 = t.p[1] - t.p[0];
    let e2 = t.p[2] - t.p[0];
    let h = d.cross(&e2);
    let det = e1.dot(&h);
    if det.abs() <= 1e-12 * e1.norm() * e2.norm() * d.norm() {
        return None; // parallel: the segment grazes the face's plane
    }
    let s = a - t.p[0];
    let u = s.dot(&h) / det;
    if !(-EPS..=1.0 + EPS).contains(&u) {
        return None;
    }
    let q = s.cross(&e1);
    let v = d.dot(&q) / det;
    if v < -EPS || u + v > 1.0 + EPS {
        return None;
    }
    let tt = e2.dot(&q) / det;
    (-EPS..=1.0 + EPS).contains(&tt).then_some(tt)
}

/// Whether the bond from `a` to `b` leaves the body through one of `candidates` and enters it
/// again through one that faces it, or leaves or enters through a gap's wall (`wall`: a face
/// with a facing face within reach) and turns by more than [`ROUNDING`] on the way: a bond
/// that rounds the end of a slot through the slot.
fn crosses_a_gap(a: Vec3, b: Vec3, candidates: &[u32], tris: &[Triangle], wall: &[bool]) -> bool {
    let d = b - a;
    let mut hits: Vec<(f64, u32)> = candidates
        .iter()
        .filter_map(|&k| crossing(a, d, &tris[k as usize]).map(|s| (s, k)))
        .collect();
    if hits.len() < 2 {
        return false;
    }
    hits.sort_by(|x, y| x.0.total_cmp(&y.0));
    // Walk along the bond from inside: an exit (heading along the face's outward normal)
    // opens a stretch outside, the next entry closes it.
    let mut exit: Option<u32> = None;
    for (_, k) in hits {
        let n = tris[k as usize].n;
        let along = d.dot(&n);
        match exit {
            None if along > 0.0 => exit = Some(k),
            Some(e) if along < 0.0 => {
                let turn = tris[e as usize].n.dot(&n);
                if turn < -FACING || ((wall[e as usize] || wall[k as usize]) && turn < ROUNDING) {
                    return true;
                }
                exit = None;
            }
            _ => {}
        }
    }
    false
}

/// The bonds of `bonds` (over `position`, real particles then mirror images) that cross a gap
/// of the body bounded by `faces`: `(particle, bond index)` of one direction of each; each
/// particle's reach is at most `reach`.
pub fn bonds_across_gaps(
    faces: &FaceSet,
    coords: &[[f64; 3]],
    ghosts: &Ghosts,
    position: &[Vec3],
    bonds: &BondList,
    reach: f64,
    spacing: f64,
) -> Vec<(u32, u32)> {
    let tris = triangles(faces, coords, ghosts);
    if tris.is_empty() {
        return Vec::new();
    }
    // Only a face with another facing it within reach can bound a gap: on a convex or
    // gently curved body there is none, and nothing more is done.
    let centres: Vec<Vec3> = tris
        .iter()
        .map(|t| (t.p[0] + t.p[1] + t.p[2]) / 3.0)
        .collect();
    let radii: Vec<f64> = tris
        .iter()
        .zip(&centres)
        .map(|(t, c)| t.p.iter().map(|p| (p - c).norm()).fold(0.0, f64::max))
        .collect();
    let widest = radii.iter().copied().fold(0.0, f64::max);
    let face_grid = CellGrid::new(&centres, reach);
    let facing: Vec<u32> = (0..tris.len() as u32)
        .into_par_iter()
        .filter(|&k| {
            let k = k as usize;
            let mut found = false;
            face_grid.for_each_candidate(&centres[k], reach + radii[k] + widest, |m| {
                let m = m as usize;
                found |= tris[m].n.dot(&tris[k].n) < -FACING
                    && (centres[m] - centres[k]).norm() <= reach + radii[k] + radii[m];
            });
            found
        })
        .collect();
    if facing.is_empty() {
        return Vec::new();
    }
    let mut wall = vec![false; tris.len()];
    for &k in &facing {
        wall[k as usize] = true;
    }
    // The faces a bond through a gap can leave or enter by: its walls and every face within
    // reach of them (the slot's end, the faces around its mouth).
    let mut near = vec![false; tris.len()];
    for &k in &facing {
        let k = k as usize;
        face_grid.for_each_candidate(&centres[k], 2.0 * reach + radii[k] + widest, |m| {
            let m = m as usize;
            near[m] |= (centres[m] - centres[k]).norm() <= 2.0 * reach + radii[k] + radii[m];
        });
    }
    let near: Vec<u32> = (0..tris.len() as u32)
        .filter(|&k| near[k as usize])
        .collect();
    // A bond can cross a face only if one of its ends lies outside the face's plane: list,
    // per particle, the faces near a gap whose plane it lies outside.
    let grid = CellGrid::new(position, reach);
    let eps = 1e-6 * spacing;
    let outside_pairs: Vec<(u32, u32)> = near
        .par_iter()
        .flat_map_iter(|&k| {
            let t = &tris[k as usize];
            let mut found = Vec::new();
            grid.for_each_candidate(&centres[k as usize], reach + radii[k as usize], |j| {
                if (position[j as usize] - t.p[0]).dot(&t.n) > eps {
                    found.push((j, k));
                }
            });
            found
        })
        .collect();
    if outside_pairs.is_empty() {
        return Vec::new();
    }
    let mut outside: Vec<Vec<u32>> = vec![Vec::new(); position.len()];
    for (j, k) in outside_pairs {
        outside[j as usize].push(k);
    }
    let n = bonds.particles();
    (0..n)
        .into_par_iter()
        .flat_map_iter(|i| {
            let mut cut = Vec::new();
            let mut candidates = Vec::new();
            for b in bonds.range(i) {
                let j = bonds.partner[b] as usize;
                if (j < n && j < i) || (outside[i].is_empty() && outside[j].is_empty()) {
                    continue;
                }
                candidates.clear();
                candidates.extend_from_slice(&outside[i]);
                candidates.extend_from_slice(&outside[j]);
                candidates.sort_unstable();
                candidates.dedup();
                if crosses_a_gap(position[i], position[j], &candidates, &tris, &wall) {
                    cut.push((i as u32, b as u32));
                }
            }
            cut
        })
        .collect()
}

/// Refuses a mesh with nodes on top of each other (closer than a millionth of the spacing
/// along a bond of `owned`'s rows; every rank of a decomposed build alike): two solids meshed
/// apart that share a face but not its nodes. Their bond has no length and no direction, and
/// every later stage would divide by it; the error names two of them and what to do.
pub fn refuse_coincident(
    bonds: &BondList,
    owned: &std::ops::Range<usize>,
    particles: &crate::case::discretize::Discretization,
    mesh: &pdcontact_importers::Mesh,
    part: Option<&crate::case::part::CasePart>,
) -> crate::error::Result<()> {
    let n = particles.len();
    let tiny = COINCIDENT * particles.spacing;
    let coincident = owned.clone().find_map(|i| {
        bonds
            .range(i)
            .find(|&b| bonds.length(b) <= tiny && (bonds.partner[b] as usize) < n)
            .map(|b| (i, bonds.partner[b] as usize))
    });
    let found = coincident.is_some() as usize;
    if part.map_or(found, |p| p.total(found)) == 0 {
        return Ok(());
    }
    let node = |i: usize| {
        particles
            .node
            .get(i)
            .and_then(|&k| mesh.node_ids.get(k as usize))
            .map_or(format!("particle {i}"), |id| format!("node {id}"))
    };
    let which = coincident.map_or(String::new(), |(i, j)| {
        let x = particles.position[i];
        format!(
            " ({} and {} at [{:.6e}, {:.6e}, {:.6e}])",
            node(i),
            node(j),
            x.x,
            x.y,
            x.z
        )
    });
    Err(crate::error::Error::input(format!(
        "the mesh has nodes on top of each other{which}, closer than a millionth of the spacing: two solids meshed apart that share a face but not its nodes? Merge the coincident nodes (gmsh: fragment the volumes before meshing, BooleanFragments, so that they share the face's nodes, or Coherence Mesh) to join the solids, or move them apart to keep them separate (a [[contact]] naming the body as its own slave and master then keeps its pieces apart)"
    )))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::case::generators::cuboid;
    use crate::case::neighbours::build_bonds_from;
    use pdcontact_importers::{boundary_faces, Mesh};

    /// Two boxes of one mesh, a gap of `gap` between them along x: no element joins them.
    fn two_boxes(gap: f64, dx: f64) -> Mesh {
        let mut out = Mesh::new();
        for m in [
            cuboid([0.0, 0.0, 0.0], [0.5, 0.4, 0.4], dx),
            cuboid([0.5 + gap, 0.0, 0.0], [1.0 + gap, 0.4, 0.4], dx),
        ] {
            let first = out.node_count() as u32;
            for &c in &m.coords {
                out.push_node(out.node_count() as u64 + 1, c);
            }
            for e in m.elements() {
                let nodes: Vec<u32> = e.nodes.iter().map(|&k| k + first).collect();
                out.push_element(out.element_count() as u64 + 1, e.kind, &nodes);
            }
        }
        out
    }

    /// The bonds cut, and the bonds between the nodes below `first` and the others.
    fn cut_count(mesh: &Mesh, dx: f64, first: usize) -> (usize, usize) {
        let faces = boundary_faces(mesh);
        let position: Vec<Vec3> = mesh.coords.iter().map(|&c| Vec3::from(c)).collect();
        let reach = 3.5 * dx;
        let bonds = build_bonds_from(&position, position.len(), reach);
        let cut = bonds_across_gaps(
            &faces,
            &mesh.coords,
            &Ghosts::default(),
            &position,
            &bonds,
            reach,
            dx,
        );
        let across = (0..bonds.particles())
            .flat_map(|i| bonds.range(i).map(move |b| (i, b)))
            .filter(|&(i, b)| {
                let j = bonds.partner[b] as usize;
                j > i && (i < first) != (j < first)
            })
            .count();
        (cut.len(), across)
    }

    #[test]
    fn a_gap_narrower_than_the_horizon_cuts_every_bond_across_it_and_no_other() {
        let dx = 0.05;
        let first = cuboid([0.0, 0.0, 0.0], [0.5, 0.4, 0.4], dx).node_count();
        for gap in [0.5 * dx, 0.02 * dx] {
            let mesh = two_boxes(gap, dx);
            let (cut, across) = cut_count(&mesh, dx, first);
            assert!(across > 100, "{across}");
            // Every bond whose ends lie on either side of the gap is cut, and no other.
            assert_eq!(cut, across, "gap {gap}");
        }
    }

    #[test]
    fn a_convex_body_and_a_concave_cap_keep_every_bond() {
        let dx = 0.05;
        let block = cuboid([0.0, 0.0, 0.0], [0.5, 0.4, 0.3], dx);
        assert_eq!(cut_count(&block, dx, 0).0, 0);
        // A shell sector whose inner face (radius 0.55 m) is concave.
        let cap = crate::case::generators::cap(
            crate::case::generators::CapShape::Sphere(1.0),
            0.4,
            0.45,
            dx,
        );
        assert_eq!(cut_count(&cap, dx, 0).0, 0);
    }
}
