//! Master segments on the surface that broken bonds opened (docs/FRACTURE.md, "Contact on new
//! surfaces"): the faces of a crack that runs, or of a pre-crack cut as bonds, which no mesh
//! face marks.
//!
//! The surface found again ([`crate::body::new_surface`], paper Eqs. 11-16 over the intact
//! bonds) gives particles and their normals, not faces. Each of its particles `i` is
//! triangulated with its neighbours on the same face, the *umbrella* of point-cloud surface
//! reconstruction:
//!
//! - **The crack's edge.** Where a crack meets the surface as built, the particles of its
//!   edge are on both: those of the surface as built that the test of Eq. 15 flags over their
//!   intact bonds, not under another such particle or one of the new surface (the occlusion
//!   test of the build: within `2 s_i`, in the 45° cone about the normal, facing the same
//!   way), face between the two (Eq. 16 over their intact bonds), as a pre-crack's edge does.
//! - **The face's neighbours.** The particles still bonded to `i` (a crack's other face has
//!   lost its bonds to it) within [`REACH`] spacings, on the new surface or on the surface
//!   as built (so that a crack's face reaches the body's sides), whose normal lies within 60°
//!   of `i`'s: the face's particles about it.
//! - **Its triangles.** They are projected on `i`'s tangent plane and triangulated there
//!   (Delaunay); the triangles with `i` as a corner, none of their edges longer than
//!   [`LONGEST_EDGE`] spacings, wound outward along `i`'s normal, are its segments (a face
//!   that is a graph over one plane is triangulated there whole, its outline's slivers
//!   peeled off as a pre-crack's are, [`face_triangles`]). A triangle found from several of its corners is kept once.
//!
//! - **A flat face.** A face whose particles off the surface as built lie within
//!   [`FLAT_DEVIATION`] spacings of one plane (a pre-crack cut as bonds, a straight crack) is
//!   that plane at this resolution: its particles stand up to a spacing or so off the cut as
//!   the cells beside it fall. Its plane is kept ([`NewFaces::flat`]); its master nodes stand
//!   on it (`contact::crack`'s `onto_faces`), and a triangle of its triangulation whose own
//!   normal turns more than 60° from the plane, a sliver of the crack's edge standing in the
//!   body's side (its corners the edge's particles, at depths a spacing apart), is left out:
//!   on the plane it has no area.
//!
//! Where the faces are flat the umbrellas tile them as a triangulation of the plane would
//! (on a lattice, the two triangles of each square); where a crack turns, the umbrellas of
//! the two sides of the turn overlap, as the narrow phase allows: a slave takes the segment
//! nearest to it among those it projects into.
//!
//! Every quantity is of the reference configuration and the intact bonds, read in particle
//! order: the same segments on any thread count.

use rayon::prelude::*;

use crate::body::new_surface::Found;
use crate::body::PdBody;
use crate::case::crack_faces::{face_triangles, LONGEST_EDGE};
use crate::case::segments::{quad_area_normal, MasterSegment};
use crate::case::surface::{OCCLUSION_RADIUS, SURFACE_LAMBDA};
use crate::math::Vec3;

/// How far a face's neighbours of a particle reach, in spacings.
pub const REACH: f64 = 2.0;

/// cos 60°: the neighbours' normals within 60° of the particle's (a crack's edge particle
/// faces 45° from its face).
pub const SAME_FACE_COS: f64 = 0.5;

/// A face whose particles off the surface as built lie within this many spacings of their
/// least-squares plane is flat: the particles beside a plane cut stand 0.4-1.2 spacings off
/// it on gmsh's tet4, tet10 and tets split into hexes and on a lattice cut at 30°.
pub const FLAT_DEVIATION: f64 = 2.0;

/// The 45° cone of the occlusion test, as the surface found again's.
const OCCLUSION_COS: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// The particles that meet a breaking body's own surfaces, and the segments of the faces
/// broken bonds opened.
#[derive(Clone, Debug, Default)]
pub struct NewFaces {
    /// Per particle of the body: its outward normal where it is on a surface (as built, or
    /// found again), zero elsewhere.
    pub normal: Vec<Vec3>,
    /// The particles on a surface, in order.
    pub particles: Vec<u32>,
    /// Those of them on a new face (the surface found again, and a crack's edge), in order.
    pub new: Vec<u32>,
    /// The segments of the new faces, corners wound outward.
    pub segments: Vec<MasterSegment>,
    /// The planes of the flat faces: a point on it, its unit normal (outward).
    pub planes: Vec<(Vec3, Vec3)>,
    /// Per particle of the body, the index in `planes` of its flat face (`u32::MAX`: none).
    pub flat: Vec<u32>,
}

impl NewFaces {
    /// Per particle of a body (reference positions `x`; `bounded`: on the surface as built
    /// or on a symmetry plane; particle spacing `spacing`): the area of the new faces over
    /// which it carries a contact's load, zero off them. Its share of each new segment, a
    /// third of a triangle, a quarter of a quad; on a flat face the segment's area on the
    /// face's plane (its particles stand up to a spacing off it, and the triangles between
    /// them lean). A particle stands for a cell, so where a face ends inside the body (a
    /// crack's front) the face reaches half a spacing beyond its last particles: each edge of
    /// the face's outline between two particles not `bounded` adds that strip to them, half
    /// each. Without it a front's particles had about half their cell, and the contact
    /// pressure there read up to four times the load (docs/FRACTURE.md, "The pressure on the
    /// faces found again"). Where the face meets the body's surface its particles are on it,
    /// and it ends there; across a symmetry plane it goes on.
    pub fn areas(&self, x: &[Vec3], bounded: &[bool], spacing: f64) -> Vec<f64> {
        let n = x.len().min(bounded.len());
        let mut area = vec![0.0; n];
        let mut edges: Vec<(u32, u32)> = Vec::new();
        for s in &self.segments {
            let corners: &[u32] = if s.is_triangle() {
                &s.nodes[..3]
            } else {
                &s.nodes
            };
            let plane = self.flat[corners[0] as usize];
            let on_plane =
                plane != u32::MAX && corners.iter().all(|&c| self.flat[c as usize] == plane);
            let a = if on_plane {
                s.area * s.normal.dot(&self.planes[plane as usize].1).abs()
            } else {
                s.area
            };
            for (k, &c) in corners.iter().enumerate() {
                area[c as usize] += a / corners.len() as f64;
                let d = corners[(k + 1) % corners.len()];
                edges.push((c.min(d), c.max(d)));
            }
        }
        // The outline: the edges of one segment alone.
        edges.sort_unstable();
        let mut k = 0;
        while k < edges.len() {
            let mut m = k + 1;
            while m < edges.len() && edges[m] == edges[k] {
                m += 1;
            }
            let (a, b) = (edges[k].0 as usize, edges[k].1 as usize);
            if m == k + 1 && !bounded[a] && !bounded[b] {
                let strip = 0.25 * (x[a] - x[b]).norm() * spacing;
                area[a] += strip;
                area[b] += strip;
            }
            k = m;
        }
        area
    }
}

impl PdBody {
    /// The new faces made of the surface its broken bonds opened ([`NewFaces`]): each of
    /// their particles takes its share of their area ([`NewFaces::areas`]) as its pressure
    /// area, in place of the one it was built with (so that `contact_pressure` reads on a
    /// crack's faces as on a mesh's), and the normals found again serve where the surface's
    /// are read.
    pub fn set_opened_faces(&mut self, faces: &NewFaces) {
        let n = self.len();
        let (built, _) = self
            .opened
            .take()
            .unwrap_or_else(|| (self.case.segments.pressure_area.clone(), Vec::new()));
        // The face ends at the surface as built and goes on across a symmetry plane.
        let bounded: Vec<bool> = (0..n)
            .map(|i| self.case.surface.is_surface[i] || self.case.ghosts.on_plane[i] != 0)
            .collect();
        let added = faces.areas(&self.reference[..n], &bounded, self.spacing());
        // A particle on the body's outer face as well (a crack's edge) takes the new face's
        // area in place of its outer face's, as a pre-crack's mouth does
        // ([`crate::case::crack_faces`]); with both, the faces' particles away from the sides
        // of the gmsh tet10 block cut across read 1.025 and 1.037 of the load (with the new
        // face's alone, 1.004 and 1.015).
        self.case.segments.pressure_area = built
            .iter()
            .zip(&added)
            .map(|(&a, &b)| if b > 0.0 { b } else { a })
            .collect();
        self.opened = Some((built, faces.normal.clone()));
    }

    /// Outward unit normals of the surface particles: those found again where the body is
    /// pressed on the faces its broken bonds opened ([`Self::set_opened_faces`]), else those
    /// as built.
    pub fn surface_normals(&self) -> &[Vec3] {
        match &self.opened {
            Some((_, normal)) if normal.len() == self.len() => normal,
            _ => &self.case.surface.normal,
        }
    }
}

/// The faces of `pd`'s surface that `found` holds (up to date; `None`: no bond broken), and
/// its surface particles.
pub fn new_faces(pd: &PdBody, found: Option<&Found>) -> NewFaces {
    let n = pd.len();
    let spacing = pd.spacing();
    let surface = &pd.case.surface;
    let x = &pd.reference;
    let intact = pd.fracture.as_ref().map(|f| &f.intact);
    let mut normal = vec![Vec3::zeros(); n];
    for i in 0..n {
        if surface.is_surface[i] {
            normal[i] = surface.normal[i];
        } else if let Some(f) = found.filter(|f| f.is_new[i]) {
            normal[i] = f.normal[i];
        }
    }
    // Where a crack meets the surface as built, the particles of its edge are on both: they
    // face between the two (Eq. 16 over their intact bonds), as a pre-crack's edge does.
    let edge = crack_edge(pd, found);
    for &i in &edge {
        normal[i as usize] = found.expect("an edge is found").normal[i as usize];
    }
    let on_face =
        |i: usize| found.is_some_and(|f| f.is_new[i]) || edge.binary_search(&(i as u32)).is_ok();
    let particles: Vec<u32> = (0..n as u32)
        .filter(|&i| normal[i as usize] != Vec3::zeros())
        .collect();
    let new: Vec<u32> = particles
        .iter()
        .copied()
        .filter(|&i| on_face(i as usize))
        .collect();
    let reach = REACH * spacing;
    // The face's neighbours of a particle: still bonded to it, near, facing its way.
    let neighbours = |i: usize| -> Vec<u32> {
        let ni = normal[i];
        pd.case
            .bonds
            .range(i)
            .filter_map(|b| {
                let j = pd.case.bonds.partner[b] as usize;
                (j < n
                    && intact.is_none_or(|f| f[b])
                    && normal[j].dot(&ni) >= SAME_FACE_COS
                    && (x[j] - x[i]).norm() <= reach)
                    .then_some(j as u32)
            })
            .collect()
    };
    // The faces, each a patch of new-face particles joined by their neighbours.
    let mut parent: Vec<u32> = (0..n as u32).collect();
    fn root(parent: &mut [u32], mut i: u32) -> u32 {
        while parent[i as usize] != i {
            parent[i as usize] = parent[parent[i as usize] as usize];
            i = parent[i as usize];
        }
        i
    }
    for &i in &new {
        for j in neighbours(i as usize) {
            if on_face(j as usize) {
                let (a, b) = (root(&mut parent, i), root(&mut parent, j));
                parent[a.max(b) as usize] = a.min(b);
            }
        }
    }
    let mut patches: std::collections::BTreeMap<u32, Vec<u32>> = Default::default();
    for &i in &new {
        let r = root(&mut parent, i);
        patches.entry(r).or_default().push(i);
    }
    let longest = LONGEST_EDGE * spacing;
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let mut planes = Vec::new();
    let mut flat = vec![u32::MAX; n];
    for members in patches.values() {
        match patch_plane(members, &normal, &surface.is_surface, x) {
            // A flat face: its plane, and no slivers standing across it.
            Some(m) => match flat_plane(members, m, &surface.is_surface, x, spacing) {
                Some((c, m)) => {
                    for &i in members {
                        flat[i as usize] = planes.len() as u32;
                    }
                    planes.push((c, m));
                    triangles.extend(planar(members, m, x, spacing).into_iter().filter(|t| {
                        let [a, b, c] = t.map(|i| x[i as usize]);
                        (b - a)
                            .cross(&(c - a))
                            .try_normalize(0.0)
                            .is_some_and(|u| u.dot(&m).abs() >= SAME_FACE_COS)
                    }));
                }
                // A face that is a graph over its plane: triangulated there as a whole, as a
                // pre-crack's faces are, one surface without overlaps.
                None => triangles.extend(planar(members, m, x, spacing)),
            },
            // One that turns too far: each particle's umbrella.
            None => triangles.extend(members.iter().flat_map(|&i| {
                let mut face = vec![i];
                face.extend(neighbours(i as usize));
                umbrella(&face, normal[i as usize], x, longest)
            })),
        }
    }
    // Each once, wound as the first umbrella that found it (in particle order).
    let mut keyed: Vec<([u32; 3], usize)> = triangles
        .iter()
        .enumerate()
        .map(|(k, t)| {
            let mut key = *t;
            key.sort_unstable();
            (key, k)
        })
        .collect();
    keyed.sort_unstable();
    keyed.dedup_by_key(|e| e.0);
    keyed.sort_unstable_by_key(|e| e.1);
    let kept: Vec<usize> = keyed.iter().map(|e| e.1).collect();
    triangles = kept.iter().map(|&k| triangles[k]).collect();
    let segments = triangles
        .into_iter()
        .filter_map(|t| {
            let nodes = [t[0], t[1], t[2], t[2]];
            let (area, normal) = quad_area_normal(nodes.map(|p| x[p as usize]));
            (area > 0.0).then_some(MasterSegment {
                nodes,
                area,
                normal,
            })
        })
        .collect();
    NewFaces {
        normal,
        particles,
        new,
        segments,
        planes,
        flat,
    }
}

/// The plane of a face (`members`, the normal of their least-squares plane `m`) if it is
/// flat: the least-squares plane of its particles off the surface as built (the crack's
/// edge, on the body's sides too, is left out of the fit), through their centroid, normal
/// along `m`, every one of them within [`FLAT_DEVIATION`] spacings of it.
fn flat_plane(
    members: &[u32],
    m: Vec3,
    on_surface: &[bool],
    x: &[Vec3],
    spacing: f64,
) -> Option<(Vec3, Vec3)> {
    let inner: Vec<Vec3> = members
        .iter()
        .filter(|&&i| !on_surface[i as usize])
        .map(|&i| x[i as usize])
        .collect();
    if inner.len() < 4 {
        return None;
    }
    let (c, n) = crate::math::least_squares_plane(&inner);
    let n = if n.dot(&m) < 0.0 { -n } else { n };
    inner
        .iter()
        .all(|p| (p - c).dot(&n).abs() <= FLAT_DEVIATION * spacing)
        .then_some((c, n))
}

/// The normal of the least-squares plane through a face's particles, turned along their
/// normals; `None` where more than a tenth of the normals of its particles off the surface
/// as built lie more than 60° from it (the face turns too far to be triangulated on one
/// plane) or they are too few. The crack's edge, on the body's sides too, faces between the
/// two by construction and says nothing of the face's turning: counted, the edge of a gmsh
/// tet4 block's crack at 30°, where it meets a side at 60°, made 22 of the lower face's 208
/// particles, and that face kept its particles' own planes, leaning at the edge (the slide
/// held back by 11 %).
fn patch_plane(members: &[u32], normal: &[Vec3], on_surface: &[bool], x: &[Vec3]) -> Option<Vec3> {
    if members.len() < 3 {
        return None;
    }
    let points: Vec<Vec3> = members.iter().map(|&i| x[i as usize]).collect();
    let (_, m) = crate::math::least_squares_plane(&points);
    let mean: Vec3 = members.iter().map(|&i| normal[i as usize]).sum();
    let m = if m.dot(&mean) < 0.0 { -m } else { m };
    let inner = members.iter().filter(|&&i| !on_surface[i as usize]).count();
    // A face all of whose particles were on the surface as built is judged by them all.
    let judged = |i: u32| inner < 3 || !on_surface[i as usize];
    let off = members
        .iter()
        .filter(|&&i| judged(i) && normal[i as usize].dot(&m) < SAME_FACE_COS)
        .count();
    (off * 10 <= members.iter().filter(|&&i| judged(i)).count()).then_some(m)
}

/// The Delaunay triangulation of a face's particles projected on the plane normal to `m`,
/// wound along `m`, the slivers of its outline and the triangles across its holes left out
/// as on a pre-crack's face ([`face_triangles`]).
fn planar(members: &[u32], m: Vec3, x: &[Vec3], spacing: f64) -> Vec<[u32; 3]> {
    triangulate_on(members, m, x, Edges::Face(spacing), |_| true)
}

/// Which triangles [`triangulate_on`] leaves out by their edges.
#[derive(Clone, Copy)]
enum Edges {
    /// Those with an edge longer than this.
    Longer(f64),
    /// A whole face's, by [`face_triangles`] at this spacing.
    Face(f64),
}

/// The triangles about `face[0]` of the Delaunay triangulation of `face` projected on the
/// plane normal to `n`, wound outward along `n`, none with an edge longer than `longest`.
fn umbrella(face: &[u32], n: Vec3, x: &[Vec3], longest: f64) -> Vec<[u32; 3]> {
    triangulate_on(face, n, x, Edges::Longer(longest), |t| t.contains(&0))
}

/// The triangles of the Delaunay triangulation of `points` projected on the plane normal to
/// `n` that `keep` keeps (by their indices into `points`) and `edges` does not leave out,
/// wound along `n`.
fn triangulate_on(
    points: &[u32],
    n: Vec3,
    x: &[Vec3],
    edges: Edges,
    keep: impl Fn(&[usize]) -> bool,
) -> Vec<[u32; 3]> {
    if points.len() < 3 {
        return Vec::new();
    }
    let e1 = n
        .cross(&Vec3::x())
        .try_normalize(1e-6)
        .unwrap_or_else(|| n.cross(&Vec3::y()).try_normalize(0.0).unwrap_or(Vec3::z()));
    let e2 = n.cross(&e1);
    let origin = x[points[0] as usize];
    let plane: Vec<delaunator::Point> = points
        .iter()
        .map(|&p| {
            let d = x[p as usize] - origin;
            delaunator::Point {
                x: e1.dot(&d),
                y: e2.dot(&d),
            }
        })
        .collect();
    let triangulation = delaunator::triangulate(&plane);
    let length = |a: usize, b: usize| (x[points[a] as usize] - x[points[b] as usize]).norm();
    let (face, longest) = match edges {
        Edges::Face(spacing) => (
            Some(face_triangles(&triangulation, length, spacing)),
            f64::INFINITY,
        ),
        Edges::Longer(longest) => (None, longest),
    };
    triangulation
        .triangles
        .chunks_exact(3)
        .enumerate()
        .filter(|(k, t)| keep(t) && face.as_ref().is_none_or(|f| f[*k]))
        .filter_map(|(_, t)| {
            let mut nodes = [points[t[0]], points[t[1]], points[t[2]]];
            let c = nodes.map(|p| x[p as usize]);
            let edge = (0..3)
                .map(|a| (c[a] - c[(a + 1) % 3]).norm())
                .fold(0.0, f64::max);
            if edge > longest {
                return None;
            }
            if (c[1] - c[0]).cross(&(c[2] - c[0])).dot(&n) < 0.0 {
                nodes.swap(1, 2);
            }
            Some(nodes)
        })
        .collect()
}

/// The particles of the surface as built on a crack's edge (see the module's notes), sorted.
fn crack_edge(pd: &PdBody, found: Option<&Found>) -> Vec<u32> {
    let Some(f) = found else {
        return Vec::new();
    };
    let n = pd.len();
    let surface = &pd.case.surface;
    let x = &pd.reference;
    let intact = pd.fracture.as_ref().map(|f| &f.intact);
    let flagged = |i: usize| {
        surface.is_surface[i] && f.ratio[i] <= SURFACE_LAMBDA && f.normal[i] != Vec3::zeros()
    };
    (0..n as u32)
        .into_par_iter()
        .filter(|&i| {
            let i = i as usize;
            if !flagged(i) {
                return false;
            }
            let nrm = f.normal[i];
            let reach = OCCLUSION_RADIUS * surface.spacing[i];
            !pd.case.bonds.range(i).any(|b| {
                let j = pd.case.bonds.partner[b] as usize;
                if j >= n || intact.is_some_and(|k| !k[b]) || !(flagged(j) || f.is_new[j]) {
                    return false;
                }
                let d = x[j] - x[i];
                let r = d.norm();
                r <= reach
                    && d.dot(&nrm) > OCCLUSION_COS * r
                    && f.normal[j].dot(&nrm) > OCCLUSION_COS
            })
        })
        .collect()
}
