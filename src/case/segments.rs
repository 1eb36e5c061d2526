//! Master segments and tributary areas (paper Sec. 2.3 and Figs. 8-9, METHOD.md §4-5).
//!
//! A master segment is a boundary face of the mesh (a face used by one solid, wound outward)
//! whose corner nodes are all eigenvalue surface particles. Triangles are quads with their third
//! node repeated. Each particle's tributary area is a share (¼ of a quad, ⅓ of a triangle) of the
//! undeformed area of every boundary face it is a corner of. Contact pressure is force over the
//! particle's pressure area, the tributary area redistributed by the boundary layer's volume
//! ([`pressure_areas`]), per undeformed area (METHOD.md §5).

use pdcontact_importers::FaceSet;

use crate::case::discretize::Discretization;
use crate::math::{Vec3, NOT_A_PARTICLE};

/// A quadrilateral (or degenerate triangular) surface patch that slaves can press on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MasterSegment {
    /// Corner particles, wound outward; a triangle is `[a, b, c, c]`.
    pub nodes: [u32; 4],
    /// Undeformed area.
    pub area: f64,
    /// Undeformed outward unit normal (from the diagonals, Eq. 18).
    pub normal: Vec3,
}

impl MasterSegment {
    /// True for a triangle stored as a degenerate quad.
    pub fn is_triangle(&self) -> bool {
        self.nodes[2] == self.nodes[3]
    }
}

/// Area and unit normal of a quad from its diagonals: `½ (x₂ − x₀) × (x₃ − x₁)`. Exact for
/// planar quads and triangles stored as `[a, b, c, c]`; for warped quads it is the area of the
/// projection on the mean plane, the plane Eq. 18 uses.
pub fn quad_area_normal(p: [Vec3; 4]) -> (f64, Vec3) {
    let n = (p[2] - p[0]).cross(&(p[3] - p[1])) * 0.5;
    let a = n.norm();
    (a, if a > 0.0 { n / a } else { Vec3::zeros() })
}

/// Master segments of a body, the faces left out, and per-particle boundary data.
#[derive(Clone, Debug, Default)]
pub struct SegmentSet {
    pub segments: Vec<MasterSegment>,
    /// Boundary faces with a corner that is not an eigenvalue surface particle.
    pub dropped_faces: usize,
    /// Whether each particle is a corner of a boundary face.
    pub boundary_node: Vec<bool>,
    /// Tributary area of each particle (zero off the boundary).
    pub tributary_area: Vec<f64>,
    /// Pressure area of each particle (zero off the boundary): the share of the boundary's
    /// area over which its contact force acts (see [`pressure_areas`]).
    pub pressure_area: Vec<f64>,
    /// Where a pre-crack's face ends inside the body: per particle, the area through which a
    /// load across the crack enters it by contact, its face's cell times the share of its
    /// bonds across that the crack cut (the bonds beyond the front carry the rest); empty
    /// where no face does, the pressure area then ([`Self::load_areas`]).
    pub load_area: Vec<f64>,
}

impl SegmentSet {
    /// Per particle, the area through which a contact's load enters it: what the skin
    /// correction balances a surface particle against ([`crate::case::skin`]).
    pub fn load_areas(&self) -> &[f64] {
        if self.load_area.is_empty() {
            &self.pressure_area
        } else {
            &self.load_area
        }
    }
}

/// Builds master segments from the mesh's boundary faces and the surface flags.
pub fn master_segments(faces: &FaceSet, disc: &Discretization, is_surface: &[bool]) -> SegmentSet {
    let n = disc.len();
    let mut out = SegmentSet {
        boundary_node: vec![false; n],
        tributary_area: vec![0.0; n],
        ..Default::default()
    };
    for face in &faces.boundary {
        let nodes = face.nodes.map(|m| disc.particle_of_node[m as usize]);
        if nodes.contains(&NOT_A_PARTICLE) {
            // Cannot happen for faces of solids: their corners are particles.
            out.dropped_faces += 1;
            continue;
        }
        let (area, normal) = quad_area_normal(nodes.map(|p| disc.position[p as usize]));
        let corners: &[u32] = if face.is_triangle() {
            &nodes[..3]
        } else {
            &nodes
        };
        for &p in corners {
            out.boundary_node[p as usize] = true;
            out.tributary_area[p as usize] += area / corners.len() as f64;
        }
        if corners.iter().all(|&p| is_surface[p as usize]) {
            out.segments.push(MasterSegment {
                nodes,
                area,
                normal,
            });
        } else {
            out.dropped_faces += 1;
        }
    }
    out.pressure_area = pressure_areas(faces, disc, &out.tributary_area);
    out
}

/// The area over which each boundary particle's contact force acts: `A*_i = V_i / t_i`,
/// scaled so that the areas add up to the boundary's.
///
/// A PD body carries loads as force densities, so a pressed particle takes its volume times a
/// smooth field: on a gmsh tet4 sphere (size 0.05 m) pressed on a rigid plane, the correlation
/// of `F_i / p_Hertz(r_i)` with `V_i` is 1.00, with the tributary area `A_i` 0.44. An
/// unstructured mesh's boundary nodes hold lumped volumes per tributary area that vary 5:1, so
/// `F_i / A_i` scattered by ±29 % about Hertz where the force density did not. The pressure
/// is the force density times the thickness of the boundary layer, `p_i = (F_i / V_i) t_i`,
/// with `t_i = Σ V_j / Σ A_j` over the boundary particles within two face rings of `i` (the
/// mesh's own neighbourhood, which does not reach across a thin body). The pressure field is
/// `p_i` over the area `A*_i`; the areas are scaled by one factor per body so that they add up
/// to the boundary's area, and that field integrates to the contact force exactly:
/// `Σ p_i A*_i = Σ F_i`. Where the boundary layer is even (structured hex meshes, the
/// generators' radial layers), `A*_i = A_i` and the pressure is force over tributary area.
pub fn pressure_areas(faces: &FaceSet, disc: &Discretization, tributary_area: &[f64]) -> Vec<f64> {
    let n = disc.len();
    let mut ring1: Vec<Vec<u32>> = vec![Vec::new(); n];
    for face in &faces.boundary {
        let nodes = face.nodes.map(|m| disc.particle_of_node[m as usize]);
        if nodes.contains(&NOT_A_PARTICLE) {
            continue;
        }
        for &a in &nodes {
            ring1[a as usize].extend(nodes.iter().filter(|&&b| b != a));
        }
    }
    for list in &mut ring1 {
        list.sort_unstable();
        list.dedup();
    }
    let mut area = vec![0.0; n];
    let mut ring: Vec<u32> = Vec::new();
    for i in 0..n {
        if tributary_area[i] <= 0.0 {
            continue;
        }
        ring.clear();
        ring.push(i as u32);
        for &j in &ring1[i] {
            ring.push(j);
            ring.extend_from_slice(&ring1[j as usize]);
        }
        ring.sort_unstable();
        ring.dedup();
        let (v, a) = ring.iter().fold((0.0, 0.0), |(v, a), &j| {
            (v + disc.volume[j as usize], a + tributary_area[j as usize])
        });
        area[i] = if v > 0.0 {
            disc.volume[i] * a / v
        } else {
            tributary_area[i]
        };
    }
    let total: f64 = tributary_area.iter().sum();
    let recovered: f64 = area.iter().sum();
    if recovered > 0.0 {
        let scale = total / recovered;
        area.iter_mut().for_each(|x| *x *= scale);
    }
    area
}
