//! A body against itself (docs/FRACTURE.md, "Contact on new surfaces"): the two faces of a
//! pre-crack (the faces themselves: [`crate::case::crack_faces`]), a pass whose slaves are the
//! face particles of each side and whose segments are the other side's, every face particle
//! moved onto the crack plane; the pieces of a mesh that no bond joins; and the surfaces that
//! broken bonds opened, found again ([`crate::body::new_faces`]), each slave against the
//! segments whose corners no intact bond joins to it.

use std::sync::Arc;

use rayon::prelude::*;

use super::{ContactLaw, ContactPass};
use crate::body::new_faces::{NewFaces, SAME_FACE_COS};
use crate::body::{Body, PdBody};
use crate::math::Vec3;

/// How far beyond the other face's edge a crack's face particle still presses on it, in
/// spacings ([`ContactPass::crack`]).
pub const CRACK_EDGE_MARGIN: f64 = 0.25;

/// The two faces of a pre-crack in one pass.
#[derive(Clone, Debug)]
pub(super) struct CrackSides {
    /// Per slave, its side (0 or 1).
    pub(super) slave_side: Vec<u8>,
    /// Per segment of the master body, its side (`u8::MAX`: not of this crack).
    pub(super) segment_side: Vec<u8>,
    /// Whether a slave presses beyond the other face's edge ([`CRACK_EDGE_MARGIN`]): a
    /// crack's faces, moved onto its plane, meet edge to edge.
    pub(super) edge_margin: bool,
}

/// A body against the surfaces its broken bonds opened ([`ContactPass::found_faces`]).
#[derive(Clone, Debug)]
pub(super) struct FoundFaces {
    /// The body's segments as built; those from here on are the new faces'.
    pub(super) built: usize,
    /// Bonds broken when the faces were made, and the model's evaluation then.
    pub(super) broken: usize,
    pub(super) at: usize,
    /// Per particle of the body, its outward normal where it is a slave.
    pub(super) normal: Arc<Vec<Vec3>>,
    /// Per particle of the body, the offset that moves it as a slave onto the face across
    /// its crack ([`onto_faces`]); master nodes stand where they are.
    pub(super) onto: Vec<Vec3>,
}

impl FoundFaces {
    /// Whether slave `s` may press on a segment with corners `nodes`: none of them is `s`
    /// or still bonded to it (`partners`: `s`'s intact bonds' partners, sorted).
    pub(super) fn apart(s: u32, nodes: &[u32; 4], partners: &[u32]) -> bool {
        nodes
            .iter()
            .all(|&n| n != s && partners.binary_search(&n).is_err())
    }

    /// The gap of slave `s` to segment `seg` at the projection `pr`'s weights in the
    /// reference configuration, the slave's point and the master's nodes moved as the pass
    /// moves them (`master`: the nodes' offsets).
    pub(super) fn reference_gap(
        &self,
        sb: &PdBody,
        s: u32,
        seg: &crate::case::segments::MasterSegment,
        master: &[Vec3],
        pr: &super::Projection,
    ) -> f64 {
        let x = &sb.reference;
        let at: Vec3 = (0..4)
            .map(|k| {
                let n = seg.nodes[k] as usize;
                (x[n] + master.get(n).copied().unwrap_or_default()) * pr.weights[k]
            })
            .sum();
        (x[s as usize] + self.onto[s as usize] - at).dot(&pr.normal)
    }

    /// The partners of `s`'s intact bonds, sorted.
    pub(super) fn partners(sb: &PdBody, s: u32) -> Vec<u32> {
        let intact = sb.fracture.as_ref().map(|f| &f.intact);
        let bonds = &sb.case.bonds;
        let mut out: Vec<u32> = bonds
            .range(s as usize)
            .filter(|&b| intact.is_none_or(|f| f[b]))
            .map(|b| bonds.partner[b])
            .collect();
        out.sort_unstable();
        out
    }
}

impl ContactPass {
    /// The pass of a body against the surfaces its broken bonds opened
    /// ([`crate::body::new_faces`]): every particle on its surface, as built or found again,
    /// is a slave against every segment (the mesh's and `faces`'), with the weight of a
    /// two-pass pair, and presses only on segments whose corners no intact bond joins to it;
    /// each slave on a new face stands moved onto the face across the crack (see `onto_faces`).
    /// The body's segments must be those as built (`built` of them) followed by `faces`'.
    pub fn found_faces(
        bodies: &[Body],
        body: usize,
        faces: &NewFaces,
        built: usize,
        law: ContactLaw,
        at: usize,
    ) -> ContactPass {
        let pd = bodies[body].as_pd().expect("a breaking body is deformable");
        debug_assert_eq!(pd.segments().len(), built + faces.segments.len());
        let (master, slave) = onto_faces(pd, faces, built);
        // A segment of the surface as built beside a crack's edge has corners on the face,
        // moved onto its plane: where they move across the segment's other corners it turns
        // over (a side's triangle at the mouth of a gmsh tet4 block cut across faced into the
        // block, pushed the side's slaves in, and ADR did not settle), and a segment that the
        // move turned by more than 60° stands for no surface: left out, as the flat face's
        // slivers are.
        let turned = super::normal::reference_normals(super::MasterView::Shifted(pd, &master));
        let kept = |k: usize| {
            k >= built || {
                let n = pd.segments()[k].normal;
                turned[k].dot(&n) >= SAME_FACE_COS * n.norm()
            }
        };
        let mut pass =
            ContactPass::new_with(bodies, body, body, law, 0.5, faces.particles.clone(), kept);
        pass.reference_normals =
            super::normal::reference_normals(super::MasterView::Shifted(pd, &master));
        pass.shift = Arc::new(master);
        // A front of a pre-crack inside the body: its particles press with the share of their
        // bonds across that the pre-crack cut, as on its own faces (`ContactPass::crack`).
        if pd.crack_share.len() == pd.len() {
            pass.area_share = pd.crack_share.clone();
        }
        pass.found = Some(FoundFaces {
            onto: slave,
            built,
            broken: pd.fracture.as_ref().map_or(0, |f| f.broken),
            at,
            normal: Arc::new(faces.normal.clone()),
        });
        pass
    }

    /// Whether this pass presses a body on the surfaces its broken bonds opened
    /// ([`ContactPass::found_faces`]).
    pub fn is_found_faces(&self) -> bool {
        self.found.is_some()
    }

    /// For [`ContactPass::found_faces`]: the body's segments as built, the bonds broken when
    /// the faces were made, and the model's evaluation then.
    pub fn found_faces_made(&self) -> Option<(usize, usize, usize)> {
        self.found.as_ref().map(|f| (f.built, f.broken, f.at))
    }

    /// The pass that presses the two faces of a body's pre-crack together
    /// ([`crate::case::crack_faces`]): the face particles of each side are slaves against the
    /// other side's segments, with the weight of a two-pass pair, and every face particle,
    /// slave point and master node alike, is moved onto the crack plane by a fixed offset, so
    /// that the faces touch where the body was whole.
    pub fn crack(bodies: &[Body], body: usize, faces: usize, law: ContactLaw) -> ContactPass {
        let pd = bodies[body].as_pd().expect("a cracked body is deformable");
        let f = &pd.crack_faces[faces];
        let mut slaves: Vec<(u32, u8)> = f.particles[0]
            .iter()
            .map(|&p| (p, 0))
            .chain(f.particles[1].iter().map(|&p| (p, 1)))
            .collect();
        slaves.sort_unstable();
        slaves.dedup_by_key(|s| s.0);
        let segments = pd.segments().len();
        let segment_side: Vec<u8> = (0..segments)
            .map(|s| f.side_of_segment(s).unwrap_or(u8::MAX))
            .collect();
        let mut pass = ContactPass::new_with(
            bodies,
            body,
            body,
            law,
            0.5,
            slaves.iter().map(|s| s.0).collect(),
            |s| segment_side[s] != u8::MAX,
        );
        pass.crack = Some(CrackSides {
            slave_side: slaves.iter().map(|s| s.1).collect(),
            segment_side,
            edge_margin: true,
        });
        // Each face particle moved onto the crack plane: the two faces meet there, as the
        // body did before the cut.
        let mut shift = vec![Vec3::zeros(); pd.len()];
        for &(p, _) in &slaves {
            let x = pd.reference[p as usize];
            shift[p as usize] = -f.normal * f.normal.dot(&(x - f.point));
        }
        pass.reference_normals =
            super::normal::reference_normals(super::MasterView::Shifted(pd, &shift));
        pass.shift = std::sync::Arc::new(shift);
        pass.area_share = Arc::new(crate::case::crack_faces::CrackFaces::shares(
            std::slice::from_ref(f),
            pd.len(),
        ));
        pass
    }

    /// The pass that keeps a body's pieces apart: a mesh of solids that share no node (a
    /// ball and a plate in one file) is one body whose pieces no bond joins
    /// ([`crate::case::neighbours::BondList::components`]), and each piece's surface
    /// particles are slaves against the other pieces' segments, with the weight of a
    /// two-pass pair (each piece is the others' master as well). `piece`: each particle's.
    pub fn pieces(bodies: &[Body], body: usize, piece: &[u32], law: ContactLaw) -> ContactPass {
        let pd = bodies[body].as_pd().expect("checked deformable");
        let slaves: Vec<u32> = (0..pd.len() as u32)
            .filter(|&i| pd.case.surface.is_surface[i as usize])
            .collect();
        let side = |p: u32| piece[p as usize].min(u8::MAX as u32 - 1) as u8;
        let segment_side: Vec<u8> = pd.segments().iter().map(|s| side(s.nodes[0])).collect();
        let mut pass =
            ContactPass::new_with(bodies, body, body, law, 0.5, slaves.clone(), |_| true);
        pass.crack = Some(CrackSides {
            slave_side: slaves.iter().map(|&p| side(p)).collect(),
            segment_side,
            edge_margin: false,
        });
        pass
    }

    /// What multiplies the contact law's force and stiffness for slave `s` of `sb`: the
    /// pass's weight, the slave's share of its particle on a symmetry plane, and on a
    /// pre-crack's face the share of its cell its cut bonds carried (at a front inside the
    /// body the bonds beyond it carry the rest, and the contact there, which reads the
    /// compression of the material still bonded across as penetration, pressed the front's
    /// particles with tens of times the load's pressure).
    pub fn slave_scale(&self, sb: &PdBody, s: usize) -> f64 {
        let area = self.area_share.get(s).copied().unwrap_or(1.0);
        self.weight * sb.case.ghosts.share(s) * area
    }

    /// Whether this pass presses the faces of a pre-crack together ([`ContactPass::crack`]).
    pub fn is_crack(&self) -> bool {
        self.crack.as_ref().is_some_and(|c| c.edge_margin)
    }

    /// How far outside a segment a slave that projects inside none still presses on it: on a
    /// crack's faces (pre-crack or found again) [`CRACK_EDGE_MARGIN`] spacings, a face's edge
    /// particle on the other face's edge; elsewhere none.
    pub fn edge_margin(&self) -> f64 {
        if self.is_crack() || self.found.is_some() {
            CRACK_EDGE_MARGIN * self.spacing
        } else {
            0.0
        }
    }

    /// Whether this pass keeps a body's pieces apart ([`ContactPass::pieces`]).
    pub fn is_pieces(&self) -> bool {
        self.crack.as_ref().is_some_and(|c| !c.edge_margin)
    }
}

/// Where the faces that broken bonds opened stand, in the reference configuration: per
/// particle of the body, the offset of its point as a master node (`.0`) and as a slave
/// (`.1`); zero off the new faces.
///
/// A crack's faces are as rough as the particles beside it: on a lattice a flat row or
/// stairs, on an unstructured mesh particles at depths up to a spacing or so apart. On a flat
/// face ([`NewFaces::flat`]) each face particle's point is moved onto the face's plane;
/// elsewhere onto the plane through its face's particles about it
/// (every one still bonded to it, its horizon, their normals within 60° of its own, and
/// itself: the least-squares plane, through their centroid, normal to the direction they
/// spread least in), so the faces are smooth at the scale of the spacing. Over a smaller
/// patch (2 spacings) the planes followed the stairs of a lattice cut at 30°: faces
/// corrugated by a few degrees, on which the contact's tangential share (0.06 of its normal
/// force) held the halves back as a friction would (docs/FRACTURE.md). And each particle
/// stands for a cell about it, so the two faces of a crack,
/// their particles a row or so apart, touch where the body was whole: a slave's point is
/// moved further, onto the face across (the segment of a new face nearest to it, within
/// [`CRACK_EDGE_MARGIN`] of its edge and [`ONTO_REACH`] spacings in front of it, facing it,
/// none of its corners bonded to it, its corners smoothed), so that it touches that face with
/// no gap and no overlap before the load.
fn onto_faces(pd: &PdBody, faces: &NewFaces, built: usize) -> (Vec<Vec3>, Vec<Vec3>) {
    let n = pd.len();
    let spacing = pd.spacing();
    let x = &pd.reference;
    let intact = pd.fracture.as_ref().map(|f| &f.intact);
    let mut on_face = vec![false; n];
    for &i in &faces.new {
        on_face[i as usize] = true;
    }
    let smoothed: Vec<(u32, Vec3)> = faces
        .new
        .par_iter()
        .map(|&i| {
            let (xi, ni) = (x[i as usize], faces.normal[i as usize]);
            // On a flat face, onto its plane: each particle's own plane through its
            // neighbours' centroid stood at another depth beside the crack's edge, where the
            // neighbours are one-sided, and the segments there leant 27-35° from the crack,
            // holding the halves back as a friction would (docs/FRACTURE.md).
            if let Some(&(c, m)) = faces.planes.get(faces.flat[i as usize] as usize) {
                return (i, m * (c - xi).dot(&m));
            }
            let mut near = vec![Vec3::zeros()];
            for b in pd.case.bonds.range(i as usize) {
                let j = pd.case.bonds.partner[b] as usize;
                if j < n
                    && on_face[j]
                    && intact.is_none_or(|f| f[b])
                    && faces.normal[j].dot(&ni) >= 0.5
                {
                    near.push(x[j] - xi);
                }
            }
            if near.len() < 4 {
                return (i, Vec3::zeros());
            }
            // The least-squares plane through them: their centroid, and the direction in
            // which they spread least.
            let (c, m) = crate::math::least_squares_plane(&near);
            let m = if m.dot(&ni) < 0.0 { -m } else { m };
            if m.dot(&ni) < 0.5 {
                return (i, Vec3::zeros());
            }
            (i, m * c.dot(&m))
        })
        .collect();
    let mut master = vec![Vec3::zeros(); n];
    for (i, m) in smoothed {
        master[i as usize] = m;
    }
    let at = |i: u32| x[i as usize] + master[i as usize];
    let segments = &pd.segments()[built..];
    let centres: Vec<Vec3> = segments
        .iter()
        .map(|s| (at(s.nodes[0]) + at(s.nodes[1]) + at(s.nodes[2])) / 3.0)
        .collect();
    let view = super::MasterView::Shifted(pd, &master);
    let planes = super::shared_planes(pd, view);
    let reach = ONTO_REACH * spacing;
    let grid = crate::case::neighbours::CellGrid::new(&centres, reach);
    let moved: Vec<(u32, Vec3)> = faces
        .new
        .par_iter()
        .filter_map(|&s| {
            let (p, ns) = (at(s), faces.normal[s as usize]);
            let partners = FoundFaces::partners(pd, s);
            let mut best: Option<(f64, Vec3)> = None;
            grid.for_each_candidate(&p, reach, |k| {
                let seg = &segments[k as usize];
                if seg.normal.dot(&ns) > -0.5 || !FoundFaces::apart(s, &seg.nodes, &partners) {
                    return;
                }
                // At a face's edge, a little beyond its last segment (as a pre-crack's); on
                // a symmetry plane, on the segment's edge there, as the narrow phase projects.
                let Some((pr, outside)) =
                    super::project_plain(pd, view, &planes, s, p, (built + k as usize) as u32)
                else {
                    return;
                };
                // The nearest segment, the distance to its clamped projection: of a segment
                // the slave is just beside and the next, a hair further off, that it projects
                // into, the next, the one the narrow phase takes (by the gap alone the first
                // was taken, and the slave stood off the face it presses: +3.9 % compliance
                // on the gmsh tet4 block cut across, +1.2 % now, the pre-crack's own faces').
                let distance = pr.gap.hypot(outside);
                if outside <= CRACK_EDGE_MARGIN * spacing
                    && pr.gap >= 0.0
                    && pr.gap <= reach
                    && best.is_none_or(|b| distance < b.0)
                {
                    best = Some((distance, -pr.normal * pr.gap));
                }
            });
            best.map(|b| (s, b.1))
        })
        .collect();
    let mut slave = master.clone();
    for (s, m) in moved {
        slave[s as usize] += m;
    }
    (master, slave)
}

/// How far in front of a face particle the face across a crack may stand, in spacings.
const ONTO_REACH: f64 = 2.0;
