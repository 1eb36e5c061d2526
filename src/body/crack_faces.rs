//! The two faces a pre-crack opens, made into contact surfaces (METHOD.md §9; the paper's
//! "new boundaries" of Sec. 1, which no mesh face marks).
//!
//! A `[[precrack]]` removes the bonds that cross its patch; the particles on either side of it
//! are then a free surface that no boundary face of the mesh describes. For each side:
//!
//! * **Face particles**: the particles that lost a bond to the patch and see it: one is
//!   dropped when another such particle of its side lies between it and the plane, within
//!   the 45° cone about the plane's normal (the same occlusion rule as the eigenvalue
//!   surface's, `case::surface`). On a lattice that is the row next to the crack.
//! * **Master segments**: the face particles' projections on the crack plane, triangulated
//!   (Delaunay: the triangulation of a point set that has the fewest slivers), wound outward
//!   (away from the side's own material); triangles longer than [`LONGEST_EDGE`] spacings on
//!   an edge are the hull's slivers across a gap and are left out.
//! * **Areas**: the face's area (its triangles') is shared by the particles' volumes, as a
//!   body takes a contact's load ([`crate::case::segments::pressure_areas`]): the pressure
//!   area over which a face particle's contact force is read as a pressure.
//!
//! A face's particles stand back from the crack plane by their own depth (half a spacing on a
//! lattice cut between two rows), so in the reference configuration the two faces are apart by
//! about a spacing, though the body was whole there. The contact moves each face particle onto
//! the crack plane by a fixed offset ([`crate::contact::ContactPass::crack`]): the faces touch
//! where the body was whole, and a compressed crack carries its load from the start.

use crate::case::neighbours::CellGrid;
use crate::case::segments::{quad_area_normal, MasterSegment};
use crate::math::Vec3;

use super::fracture::CrackPatch;
use super::PdBody;

/// Triangles with an edge longer than this many particle spacings are left out of a face
/// (the Delaunay hull bridges concave stretches of a face's outline with long slivers).
pub const LONGEST_EDGE: f64 = 2.5;

/// The faces of one pre-crack: side 0 lies behind the patch's normal (its outward normal is
/// the patch's `+n`), side 1 in front of it (outward `−n`).
#[derive(Clone, Debug)]
pub struct CrackFaces {
    /// Which `[[precrack]]` of the scene (its index) opened them.
    pub precrack: usize,
    /// The patch's unit normal, and its centre (a point of the crack plane).
    pub normal: Vec3,
    pub point: Vec3,
    /// The face particles of each side.
    pub particles: [Vec<u32>; 2],
    /// The side of each of the body's segments from `first_segment` on (0 or 1).
    pub segment_side: Vec<u8>,
    /// The index of this crack's first segment in the body's segment list.
    pub first_segment: usize,
}

impl CrackFaces {
    /// The side of the body's segment `s` (`None` for a segment not of this crack).
    pub fn side_of_segment(&self, s: usize) -> Option<u8> {
        s.checked_sub(self.first_segment)
            .and_then(|k| self.segment_side.get(k).copied())
    }
}

/// Finds the faces `patch` opened in `body` (`cut`: the bonds it removed, each `(i, bond)`),
/// appends their segments to the body's master segments, and makes the face particles
/// surface particles with the crack's normal. Errors say what is missing.
pub fn open_faces(
    body: &mut PdBody,
    precrack: usize,
    patch: &CrackPatch,
    cut: &[(u32, u32)],
) -> Result<CrackFaces, String> {
    let n = body.len();
    let spacing = body.spacing();
    let x = &body.reference;
    let depth = |i: usize| patch.normal.dot(&(x[i] - patch.point));
    let mut lost = vec![false; n];
    for &(i, b) in cut {
        lost[i as usize] = true;
        let j = body.case.bonds.partner[b as usize] as usize;
        if j < n {
            lost[j] = true;
        }
    }
    let candidates: Vec<u32> = (0..n as u32).filter(|&i| lost[i as usize]).collect();
    let points: Vec<Vec3> = candidates.iter().map(|&i| x[i as usize]).collect();
    let grid = CellGrid::new(&points, 2.0 * spacing);
    let mut particles: [Vec<u32>; 2] = [Vec::new(), Vec::new()];
    for (k, &i) in candidates.iter().enumerate() {
        let di = depth(i as usize);
        let side = usize::from(di >= 0.0);
        let mut covered = false;
        grid.for_each_candidate(&points[k], 2.0 * spacing, |m| {
            let j = candidates[m as usize] as usize;
            let dj = depth(j);
            if covered || (dj >= 0.0) != (di >= 0.0) {
                return;
            }
            // Nearer the plane by more than a tenth of a spacing, and within the 45° cone
            // from this particle towards the plane.
            let closer = di.abs() - dj.abs();
            if closer > 0.1 * spacing && closer <= 2.0 * spacing {
                let d = x[j] - x[i as usize];
                let lateral = (d - patch.normal * patch.normal.dot(&d)).norm();
                covered = lateral <= closer;
            }
        });
        if !covered {
            particles[side].push(i);
        }
    }
    let first_segment = body.case.segments.segments.len();
    let mut segment_side = Vec::new();
    for (side, list) in particles.iter().enumerate() {
        if list.len() < 3 {
            return Err(format!(
                "precrack {}: side {} of the crack has {} particle(s) facing it, too few for a contact surface (the patch must cut the body over a few spacings at least)",
                precrack + 1,
                side,
                list.len()
            ));
        }
        let outward = if side == 0 {
            patch.normal
        } else {
            -patch.normal
        };
        let plane: Vec<delaunator::Point> = list
            .iter()
            .map(|&i| {
                let d = x[i as usize] - patch.point;
                delaunator::Point {
                    x: patch.sides[0].dot(&d),
                    y: patch.sides[1].dot(&d),
                }
            })
            .collect();
        let triangulation = delaunator::triangulate(&plane);
        let mut face_area = 0.0;
        for t in triangulation.triangles.chunks_exact(3) {
            let mut nodes = [list[t[0]], list[t[1]], list[t[2]], list[t[2]]];
            let corners = nodes.map(|p| x[p as usize]);
            let longest = (0..3)
                .map(|a| (corners[a] - corners[(a + 1) % 3]).norm())
                .fold(0.0, f64::max);
            if longest > LONGEST_EDGE * spacing {
                continue;
            }
            let (area, mut normal) = quad_area_normal(corners);
            if area <= 0.0 {
                continue;
            }
            if normal.dot(&outward) < 0.0 {
                nodes.swap(1, 2);
                nodes[3] = nodes[2];
                normal = -normal;
            }
            face_area += area;
            for &p in &nodes[..3] {
                body.case.segments.boundary_node[p as usize] = true;
            }
            body.case.segments.segments.push(MasterSegment {
                nodes,
                area,
                normal,
            });
            segment_side.push(side as u8);
        }
        // The pressure area: the face's area shared by the particles' volumes, as a body
        // takes a contact's load (`case::segments::pressure_areas`); a third of each triangle
        // would give a lattice's particles 4 to 8 sixths of their cell, as the triangulation
        // happens to cut its squares.
        let volume: f64 = list
            .iter()
            .map(|&i| body.case.particles.volume[i as usize])
            .sum();
        for &i in list {
            let area = face_area * body.case.particles.volume[i as usize] / volume;
            body.case.segments.pressure_area[i as usize] += area;
            // Its reactions are its own: the opposite face's slaves land on its segments
            // wherever the two faces' particles happen to lie, not by its triangles' thirds.
            body.case.segments.tributary_area[i as usize] += area;
        }
        let surface = &mut body.case.surface;
        for &i in list {
            let i = i as usize;
            // A particle on the body's own boundary as well (the crack's edge on a face of
            // the body) faces both ways: between the two.
            surface.normal[i] = if surface.is_surface[i] {
                (surface.normal[i] + outward)
                    .try_normalize(0.0)
                    .unwrap_or(outward)
            } else {
                outward
            };
            surface.is_surface[i] = true;
        }
    }
    Ok(CrackFaces {
        precrack,
        normal: patch.normal,
        point: patch.point,
        particles,
        segment_side,
        first_segment,
    })
}

/// The particle pairs a `[[precrack]]` parted: `(precrack, normal, pairs)`, each pair
/// `(behind, in front)` of the patch's normal.
pub type PartedPairs = (usize, Vec3, Vec<(u32, u32)>);

/// The particle pairs whose bonds `patch` cut (`cut`: `(i, bond)`), mirror images left out,
/// each as `(behind, in front)` of the patch's normal.
pub fn parted_pairs(body: &PdBody, patch: &CrackPatch, cut: &[(u32, u32)]) -> Vec<(u32, u32)> {
    let n = body.len();
    cut.iter()
        .filter_map(|&(i, b)| {
            let j = body.case.bonds.partner[b as usize];
            ((j as usize) < n).then(|| {
                let d = patch
                    .normal
                    .dot(&(body.reference[j as usize] - body.reference[i as usize]));
                if d > 0.0 {
                    (i, j)
                } else {
                    (j, i)
                }
            })
        })
        .collect()
}

/// Where a body's pre-crack faces have passed through each other: the pair of particles that
/// crossed deepest, `(precrack, behind, in front, depth)`, the depth how far the particle in
/// front now lies behind its partner along the normal, m. `None` where none crossed.
pub fn crossed(body: &PdBody) -> Option<(usize, u32, u32, f64)> {
    let mut deepest: Option<(usize, u32, u32, f64)> = None;
    for (k, normal, pairs) in &body.precrack_pairs {
        for &(a, b) in pairs {
            let d = -normal.dot(&(body.position(b as usize) - body.position(a as usize)));
            if d > 0.0 && deepest.is_none_or(|x| d > x.3) {
                deepest = Some((*k, a, b, d));
            }
        }
    }
    deepest
}
