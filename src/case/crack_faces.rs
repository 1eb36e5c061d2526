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
//!   (away from the side's own material); the hull's slivers across a concave stretch of the
//!   outline (an exposed edge over [`LONGEST_EDGE`] spacings) are peeled off, and triangles
//!   across a hole left out ([`face_triangles`]).
//! * **Areas**: each face particle's cell of the face (its mixed Voronoi area in the
//!   triangulation), shared out again by volume over the particles within two spacings, as a
//!   body takes a contact's load ([`crate::case::segments::pressure_areas`]): the pressure area
//!   over which a face particle's contact force is read as a pressure.
//!
//! A face's particles stand back from the crack plane by their own depth (half a spacing on a
//! lattice cut between two rows), so in the reference configuration the two faces are apart by
//! about a spacing, though the body was whole there. The contact moves each face particle onto
//! the crack plane by a fixed offset ([`crate::contact::ContactPass::crack`]): the faces touch
//! where the body was whole, and a compressed crack carries its load from the start.

use crate::case::correction::{
    surface_correction_with, CorrectionMethod, Horizon, SurfaceCorrection,
};
use crate::case::neighbours::{BondList, CellGrid};
use crate::case::segments::{quad_area_normal, MasterSegment};
use crate::case::skin::{skin_correction, SkinInput};
use crate::case::PdCase;
use crate::math::Vec3;

/// A planar rectangular crack patch in the reference configuration.
#[derive(Clone, Copy, Debug)]
pub struct CrackPatch {
    pub point: Vec3,
    /// Unit normal.
    pub normal: Vec3,
    /// Unit in-plane directions of the two sides.
    pub sides: [Vec3; 2],
    /// Half lengths along `sides`.
    pub half: [f64; 2],
}

impl CrackPatch {
    /// The patch centred at `point` with normal `normal`, its first side along `along`
    /// (projected into the plane) and side lengths `size`.
    pub fn new(point: Vec3, normal: Vec3, along: Vec3, size: [f64; 2]) -> CrackPatch {
        let n = normal.normalize();
        let e1 = (along - n * n.dot(&along)).normalize();
        CrackPatch {
            point,
            normal: n,
            sides: [e1, n.cross(&e1)],
            half: [0.5 * size[0], 0.5 * size[1]],
        }
    }

    /// Whether the segment from `a` to `b` crosses the patch (a point on the plane counts on
    /// its positive side).
    pub fn cuts(&self, a: Vec3, b: Vec3) -> bool {
        let (da, db) = (
            self.normal.dot(&(a - self.point)),
            self.normal.dot(&(b - self.point)),
        );
        if (da < 0.0) == (db < 0.0) {
            return false;
        }
        let q = a + (b - a) * (da / (da - db)) - self.point;
        (0..2).all(|k| self.sides[k].dot(&q).abs() <= self.half[k])
    }

    /// The bonds `(i, bond)` that cross the patch (reference positions `x`, images included),
    /// each real pair once.
    pub fn crossing(&self, bonds: &BondList, x: &[Vec3]) -> Vec<(u32, u32)> {
        let n = bonds.particles();
        (0..n)
            .flat_map(|i| bonds.range(i).map(move |b| (i, b)))
            .filter(|&(i, b)| {
                let j = bonds.partner[b] as usize;
                (j > i || j >= n) && self.cuts(x[i], x[j])
            })
            .map(|(i, b)| (i as u32, b as u32))
            .collect()
    }
}

/// The radius of the ring of face particles over which the pressure area is shared by
/// volume, in spacings.
const RING: f64 = 2.0;

/// The mixed Voronoi areas of a triangle's corners (Meyer et al. 2003): each corner's share of
/// the triangle's part of its Voronoi cell, `(|PR|² cot Q + |PQ|² cot R)/8`; where the
/// triangle is obtuse (the circumcentre outside), half the area to the obtuse corner and a
/// quarter to the others. The shares add up to the triangle's area.
fn mixed_areas(p: [&delaunator::Point; 3]) -> [f64; 3] {
    let v = |a: usize, b: usize| (p[b].x - p[a].x, p[b].y - p[a].y);
    let dot = |u: (f64, f64), w: (f64, f64)| u.0 * w.0 + u.1 * w.1;
    let cross = |u: (f64, f64), w: (f64, f64)| (u.0 * w.1 - u.1 * w.0).abs();
    let area = 0.5 * cross(v(0, 1), v(0, 2));
    if area <= 0.0 {
        return [0.0; 3];
    }
    // The cotangent of the angle at corner k.
    let cot = |k: usize| {
        let (a, b) = (v(k, (k + 1) % 3), v(k, (k + 2) % 3));
        dot(a, b) / cross(a, b)
    };
    let obtuse = (0..3).find(|&k| cot(k) < 0.0);
    std::array::from_fn(|k| match obtuse {
        Some(o) if o == k => 0.5 * area,
        Some(_) => 0.25 * area,
        None => {
            let (q, r) = ((k + 1) % 3, (k + 2) % 3);
            let len2 = |a: usize, b: usize| dot(v(a, b), v(a, b));
            (len2(k, r) * cot(q) + len2(k, q) * cot(r)) / 8.0
        }
    })
}

/// The particle pairs a `[[precrack]]` parted: `(precrack, normal, pairs)`, each pair
/// `(behind, in front)` of the patch's normal.
pub type PartedPairs = (usize, Vec3, Vec<(u32, u32)>);

/// What cutting a case gave ([`PdCase::cut`]): the faces of each patch, and the pairs it
/// parted.
#[derive(Clone, Debug, Default)]
pub struct Cut {
    pub faces: Vec<CrackFaces>,
    pub parted: Vec<PartedPairs>,
}

impl PdCase {
    /// Cuts the case along `patches` (`(precrack, patch)`) for contact between the faces they
    /// open: every bond that crosses a patch is removed, each patch's two faces are made into
    /// surface particles and master segments ([`open_faces`]), and the surface and skin
    /// corrections are computed again over the bonds left, as for the mesh's own faces (a row
    /// beside a cut has lost the bonds across it, and its correction for the body whole
    /// leaves it soft: METHOD.md §2). `Err((precrack, message))` where a patch cuts nothing
    /// or opens too small a face.
    pub fn cut(
        &mut self,
        patches: &[(usize, CrackPatch)],
        method: CorrectionMethod,
        skin: bool,
    ) -> Result<Cut, (usize, String)> {
        let n = self.particles.len();
        let mut position = Vec::new();
        self.ghosts
            .extend_positions(&self.particles.position, &mut position);
        let mut out = Cut::default();
        let mut removed: Vec<(u32, u32)> = Vec::new();
        let mut lost_of: Vec<Vec<f64>> = Vec::new();
        let partner_volume = self.ghosts.partner_volumes(&self.particles.volume);
        for &(k, patch) in patches {
            let cut = patch.crossing(&self.bonds, &position);
            if cut.is_empty() {
                return Err((k, "cuts no bond".to_string()));
            }
            // What each particle's bonds across the crack's plane carry under a strain
            // normal to it (Eq. 6's `(e·n)³ V`): those the patch cuts, and the rest.
            let across = |i: usize, j: usize| {
                let e = (position[j] - position[i]).normalize();
                e.dot(&patch.normal).abs().powi(3) * partner_volume[j]
            };
            let mut cut_weight = vec![0.0; n];
            let mut pairs = Vec::new();
            for &(i, b) in &cut {
                let j = self.bonds.partner[b as usize];
                let w = across(i as usize, j as usize);
                cut_weight[i as usize] += w;
                if (j as usize) < n {
                    cut_weight[j as usize] += w;
                    let d = patch
                        .normal
                        .dot(&(position[j as usize] - position[i as usize]));
                    pairs.push(if d > 0.0 { (i, j) } else { (j, i) });
                }
            }
            out.parted.push((k, patch.normal, pairs));
            // The share of its bonds across the plane each particle lost: 1 on a crack
            // through the body, less at a crack's front inside it, whose particles still
            // carry part of a load across by the bonds beyond the front.
            let mut kept_weight = vec![0.0; n];
            for (i, kept) in kept_weight.iter_mut().enumerate() {
                if cut_weight[i] == 0.0 {
                    continue;
                }
                let side = patch.normal.dot(&(position[i] - patch.point)) >= 0.0;
                for b in self.bonds.range(i) {
                    let j = self.bonds.partner[b] as usize;
                    let other = patch.normal.dot(&(position[j] - patch.point)) >= 0.0;
                    if other != side && !patch.cuts(position[i], position[j]) {
                        *kept += across(i, j);
                    }
                }
            }
            lost_of.push(
                cut_weight
                    .iter()
                    .zip(&kept_weight)
                    .map(|(&c, &k)| {
                        if k == 0.0 {
                            f64::from(c > 0.0)
                        } else {
                            c / (c + k)
                        }
                    })
                    .collect(),
            );
            removed.extend(cut);
        }
        self.bonds = self.bonds.without(&removed);
        self.correction = self.correction_over(&self.bonds, &position, method);
        let mut outer = self.surface.is_surface.clone();
        for (&(k, patch), lost) in patches.iter().zip(&lost_of) {
            out.faces
                .push(open_faces(self, k, &patch, lost, &mut outer).map_err(|m| (k, m))?);
        }
        if skin {
            let partner_volume = self.ghosts.partner_volumes(&self.particles.volume);
            let input = SkinInput {
                position: &position,
                partner_volume: &partner_volume,
                volume: &self.particles.volume,
                is_surface: &self.surface.is_surface,
                normal: &self.surface.normal,
                pressure_area: self.segments.load_areas(),
                ghosts: &self.ghosts,
                horizon: self.horizon,
            };
            self.skin = Some(skin_correction(
                &input,
                &self.bonds,
                &mut self.correction.bond_factor,
                None,
            ));
        }
        Ok(out)
    }

    /// The surface correction (METHOD.md §2) over `bonds` instead of the case's own
    /// (`position`: reference positions, images included).
    fn correction_over(
        &self,
        bonds: &BondList,
        position: &[Vec3],
        method: CorrectionMethod,
    ) -> SurfaceCorrection {
        let source: Vec<usize> = (0..position.len())
            .map(|j| self.ghosts.source_of(j, self.particles.len()))
            .collect();
        let partner_volume = self.ghosts.partner_volumes(&self.particles.volume);
        let local = self.local_spacing.as_ref().map(|s| self.ghosts.extend(s));
        surface_correction_with(
            position,
            &partner_volume,
            &source,
            bonds,
            &Horizon {
                radius: self.horizon,
                spacing: self.particles.spacing,
                local: local.as_deref(),
            },
            method,
            None,
        )
    }

    /// Computes the surface and skin corrections again as if the bonds that cross `patches`
    /// were not there, and keeps the bonds: a body whose pre-cracks break bonds at the start,
    /// to find its faces from the broken bonds (`faces = "found"`), gets the corrections that
    /// [`Self::cut`] gives the pre-crack's own faces (those of a copy cut there). The rows
    /// beside a cut lost the bonds across it, and their correction for the body whole leaves
    /// them soft; the skin correction stiffens the faces' rows and, computed again over all
    /// the bonds, the outer faces' rows as built (docs/FRACTURE.md, "Master segments on the
    /// faces found again"). The crossing bonds' factors are 0. Returns, per particle, the
    /// share of its bonds across a crack's plane that the patches cut ([`CrackFaces::share`];
    /// 1 off the faces). `Err` as [`Self::cut`]'s.
    pub fn correct_without(
        &mut self,
        patches: &[(usize, CrackPatch)],
        method: CorrectionMethod,
        skin: bool,
    ) -> Result<Vec<f64>, (usize, String)> {
        let mut cut = self.clone();
        let faces = cut.cut(patches, method, skin)?.faces;
        let share = CrackFaces::shares(&faces, self.particles.len());
        // `without` keeps each particle's bonds in their order: walk both lists together.
        let mut factor = vec![0.0; self.bonds.len()];
        for i in 0..self.bonds.particles() {
            let mut next = cut.bonds.range(i).peekable();
            for b in self.bonds.range(i) {
                if let Some(&c) = next.peek() {
                    if cut.bonds.partner[c] == self.bonds.partner[b] {
                        factor[b] = cut.correction.bond_factor[c];
                        next.next();
                    }
                }
            }
        }
        self.correction = cut.correction;
        self.correction.bond_factor = factor;
        self.skin = cut.skin;
        Ok(share)
    }
}

/// Triangles with an edge longer than this many particle spacings on a face's outline are
/// left out of it (the Delaunay hull bridges concave stretches of a face's outline with long
/// slivers): see [`face_triangles`].
pub const LONGEST_EDGE: f64 = 2.5;

/// A triangle with an edge longer than this many particle spacings anywhere in a face spans
/// a hole in it (a crack across a tube) and is left out: see [`face_triangles`].
pub const HOLE_EDGE: f64 = 2.0 * LONGEST_EDGE;

/// Which triangles of a face's Delaunay triangulation `tri` make the face. The hull's
/// triangles are peeled off one after another while an exposed edge (on the hull, or against
/// a triangle already peeled) is longer than [`LONGEST_EDGE`] spacings: the slivers across a
/// concave stretch of the outline; a triangle with any edge over [`HOLE_EDGE`] spacings
/// spans a hole and goes, its neighbours peeled from it likewise. The triangles within the
/// face stay whatever their size: where a face's particles lie sparser than the body's
/// spacing (the gmsh tets split into hexes, whose spacing the many small cells of the split
/// set) its triangles run to three spacings, and leaving those out left holes of a tenth of
/// the face (docs/FRACTURE.md, "The face's holes"). `length(a, b)`: the edge between points
/// `a` and `b`. Sequential, in the triangulation's order: the same on any thread count.
pub fn face_triangles(
    tri: &delaunator::Triangulation,
    length: impl Fn(usize, usize) -> f64,
    spacing: f64,
) -> Vec<bool> {
    let count = tri.triangles.len() / 3;
    let mut kept = vec![true; count];
    let edge = |e: usize| {
        length(
            tri.triangles[e],
            tri.triangles[delaunator::next_halfedge(e)],
        )
    };
    let mut stack: Vec<usize> = Vec::new();
    for (t, k) in kept.iter_mut().enumerate() {
        if (3 * t..3 * t + 3).any(|e| edge(e) > HOLE_EDGE * spacing) {
            *k = false;
            stack.extend(
                (3 * t..3 * t + 3)
                    .map(|e| tri.halfedges[e])
                    .filter(|&h| h != delaunator::EMPTY)
                    .map(|h| h / 3),
            );
        }
    }
    stack.extend(
        (0..tri.halfedges.len())
            .filter(|&e| tri.halfedges[e] == delaunator::EMPTY)
            .map(|e| e / 3),
    );
    while let Some(t) = stack.pop() {
        if !kept[t] {
            continue;
        }
        let exposed_long = (3 * t..3 * t + 3).any(|e| {
            let h = tri.halfedges[e];
            (h == delaunator::EMPTY || !kept[h / 3]) && edge(e) > LONGEST_EDGE * spacing
        });
        if exposed_long {
            kept[t] = false;
            stack.extend(
                (3 * t..3 * t + 3)
                    .map(|e| tri.halfedges[e])
                    .filter(|&h| h != delaunator::EMPTY)
                    .map(|h| h / 3),
            );
        }
    }
    kept
}

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
    /// Per face particle of each side (as `particles`), the share of its bonds across the
    /// crack's plane that the patch cut: 1 on a crack through the body, less at a front
    /// inside it, where the bonds beyond the front carry the rest of a load across.
    pub share: [Vec<f64>; 2],
    /// The side of each of the body's segments from `first_segment` on (0 or 1).
    pub segment_side: Vec<u8>,
    /// The index of this crack's first segment in the body's segment list.
    pub first_segment: usize,
}

impl CrackFaces {
    /// Per particle of a body of `n`: the share of its bonds across a crack's plane that the
    /// cracks `faces` cut (the smallest where it is on several; 1 off their faces).
    pub fn shares(faces: &[CrackFaces], n: usize) -> Vec<f64> {
        let mut share = vec![1.0; n];
        for f in faces {
            for (list, lost) in f.particles.iter().zip(&f.share) {
                for (&p, &a) in list.iter().zip(lost) {
                    share[p as usize] = f64::min(share[p as usize], a);
                }
            }
        }
        share
    }

    /// The side of the body's segment `s` (`None` for a segment not of this crack).
    pub fn side_of_segment(&self, s: usize) -> Option<u8> {
        s.checked_sub(self.first_segment)
            .and_then(|k| self.segment_side.get(k).copied())
    }
}

/// Finds the faces `patch` opened in `case` (`lost`: per particle, the share of its bonds
/// across the crack's plane that the patch cut, 0 where none), appends their segments to the
/// case's master segments, and makes the face particles surface particles with the crack's
/// normal. `outer`: the particles whose areas are still their outer faces' (cleared where
/// this crack's faces take them over). Errors say what is missing.
pub fn open_faces(
    case: &mut PdCase,
    precrack: usize,
    patch: &CrackPatch,
    lost: &[f64],
    outer: &mut [bool],
) -> Result<CrackFaces, String> {
    let n = case.particles.len();
    let spacing = case.particles.spacing;
    let x = &case.particles.position;
    let depth = |i: usize| patch.normal.dot(&(x[i] - patch.point));
    let candidates: Vec<u32> = (0..n as u32).filter(|&i| lost[i as usize] > 0.0).collect();
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
    let first_segment = case.segments.segments.len();
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
        let kept = face_triangles(
            &triangulation,
            |a, b| (x[list[a] as usize] - x[list[b] as usize]).norm(),
            spacing,
        );
        let mut cell = vec![0.0; list.len()];
        for (t, _) in triangulation
            .triangles
            .chunks_exact(3)
            .zip(&kept)
            .filter(|(_, &k)| k)
        {
            let mut nodes = [list[t[0]], list[t[1]], list[t[2]], list[t[2]]];
            let corners = nodes.map(|p| x[p as usize]);
            let (area, mut normal) = quad_area_normal(corners);
            if area <= 0.0 {
                continue;
            }
            if normal.dot(&outward) < 0.0 {
                nodes.swap(1, 2);
                nodes[3] = nodes[2];
                normal = -normal;
            }
            for (k, a) in mixed_areas([t[0], t[1], t[2]].map(|k| &plane[k]))
                .into_iter()
                .enumerate()
            {
                cell[t[k]] += a;
            }
            for &p in &nodes[..3] {
                case.segments.boundary_node[p as usize] = true;
            }
            case.segments.segments.push(MasterSegment {
                nodes,
                area,
                normal,
            });
            segment_side.push(side as u8);
        }
        // The pressure area: a particle's cell of the face (its mixed Voronoi area), the
        // cells around it redistributed by their volumes, as `case::segments::pressure_areas`
        // does for a mesh face, since a body takes a contact's load by volume. A third of each
        // triangle would give a lattice's particles 4 to 8 sixths of their cell, as the
        // triangulation happens to cut its squares; the Voronoi cell is a lattice's square
        // whichever way.
        let flat: Vec<Vec3> = plane.iter().map(|p| Vec3::new(p.x, p.y, 0.0)).collect();
        let grid = CellGrid::new(&flat, RING * spacing);
        let volume = |k: usize| case.particles.volume[list[k] as usize];
        let mut area: Vec<f64> = (0..list.len())
            .map(|k| {
                let (mut a, mut v) = (0.0, 0.0);
                grid.for_each_candidate(&flat[k], RING * spacing, |m| {
                    let m = m as usize;
                    if (flat[m] - flat[k]).norm() <= RING * spacing {
                        a += cell[m];
                        v += volume(m);
                    }
                });
                if v > 0.0 {
                    volume(k) * a / v
                } else {
                    cell[k]
                }
            })
            .collect();
        // Shared out to the face's area on the crack plane (the cells', which tile the
        // triangulation's projection), not the triangles' own: on an unstructured mesh the
        // face particles lie at depths up to a spacing or so from the plane, and triangles
        // between them, tilted, add up to more than the face (the gmsh tet bar's by 26 %).
        let planar: f64 = cell.iter().sum();
        let total: f64 = area.iter().sum();
        if total > 0.0 {
            area.iter_mut().for_each(|a| *a *= planar / total);
        }
        if case.segments.load_area.is_empty() {
            case.segments.load_area = case.segments.pressure_area.clone();
        }
        for (&i, &a) in list.iter().zip(&area) {
            // A particle on the body's outer boundary as well (the crack's mouth) takes the
            // crack face's areas in place of its outer face's: summed, they made its skin
            // correction carry both faces' tractions along the one normal between them, and
            // the rows at the mouth drew half as much again as their share of the load across
            // the crack (docs/FRACTURE.md, "The crack's mouth").
            let segments = &mut case.segments;
            if std::mem::take(&mut outer[i as usize]) {
                segments.pressure_area[i as usize] = 0.0;
                segments.load_area[i as usize] = 0.0;
                segments.tributary_area[i as usize] = 0.0;
            }
            segments.pressure_area[i as usize] += a;
            // A particle at a crack's front inside the body takes the share of a load across
            // that its cut bonds carried: the bonds beyond the front carry the rest, and with
            // its whole cell the skin correction stiffened those bonds (up to ten times)
            // until a crack closed in compression made the body stiffer than uncut (a gmsh
            // tet4 block with a crack over a third of its section: 10 % stiffer).
            segments.load_area[i as usize] += a * lost[i as usize];
            // Its reactions are its own: the opposite face's slaves land on its segments
            // wherever the two faces' particles happen to lie, not by its triangles' thirds.
            case.segments.tributary_area[i as usize] += a;
        }
        let surface = &mut case.surface;
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
    let share = particles
        .each_ref()
        .map(|list| list.iter().map(|&i| lost[i as usize]).collect());
    Ok(CrackFaces {
        precrack,
        normal: patch.normal,
        point: patch.point,
        particles,
        share,
        segment_side,
        first_segment,
    })
}

#[cfg(test)]
mod tests {
    use super::face_triangles;
    use delaunator::{triangulate, Point};

    /// The area of the triangles `face_triangles` keeps of the points' Delaunay triangulation.
    fn kept_area(points: &[Point], spacing: f64) -> f64 {
        let tri = triangulate(points);
        let length = |a: usize, b: usize| {
            let (p, q) = (&points[a], &points[b]);
            (p.x - q.x).hypot(p.y - q.y)
        };
        let kept = face_triangles(&tri, length, spacing);
        tri.triangles
            .chunks_exact(3)
            .zip(&kept)
            .filter(|(_, &k)| k)
            .map(|(t, _)| {
                let (a, b, c) = (&points[t[0]], &points[t[1]], &points[t[2]]);
                0.5 * ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y)).abs()
            })
            .sum()
    }

    fn grid(n: usize, keep: impl Fn(usize, usize) -> bool) -> Vec<Point> {
        let mut points = Vec::new();
        for i in 0..=n {
            for j in 0..=n {
                if keep(i, j) {
                    // A small shear keeps the lattice's squares from being cocircular.
                    let (x, y) = (i as f64, j as f64);
                    points.push(Point {
                        x: x + 0.013 * y,
                        y,
                    });
                }
            }
        }
        points
    }

    #[test]
    fn the_outline_of_a_concave_face_is_peeled_and_its_inside_kept() {
        // An L of unit spacing, 12 × 12 less its 8 × 8 corner: the hull bridges the notch.
        let l = grid(12, |i, j| i <= 4 || j <= 4);
        // A re-entrant corner keeps the short triangles across it (edges under 2.5
        // spacings), a spacing squared or so; the rest of the notch goes.
        let area = kept_area(&l, 1.0);
        assert!((80.0..=81.5).contains(&area), "L: {area}");
        // The same square with a sparse stretch inside (points 3 spacings apart over
        // 4 ≤ i, j ≤ 10): triangles of 3 spacings on a side inside the face stay.
        let sparse = grid(12, |i, j| {
            !(4..=10).contains(&i) || !(4..=10).contains(&j) || (i % 3 == 1 && j % 3 == 1)
        });
        let area = kept_area(&sparse, 1.0);
        assert!((area - 144.0).abs() < 1e-9, "sparse: {area}");
        // A square hole of 8 spacings (a crack across a tube) is left out.
        let hole = grid(12, |i, j| !(3..=9).contains(&i) || !(3..=9).contains(&j));
        let area = kept_area(&hole, 1.0);
        // Its four corners keep a spacing squared each, as the L's.
        assert!((80.0..=86.0).contains(&area), "hole: {area}");
    }
}
