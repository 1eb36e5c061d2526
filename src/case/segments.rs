//! Master segments and tributary areas (paper Sec. 2.3 and Figs. 8-9, METHOD.md §4-5).
//!
//! A master segment is a boundary face of the mesh (a face used by one solid, wound outward)
//! whose corner nodes are all eigenvalue surface particles. Triangles are quads with their third
//! node repeated. Each particle's tributary area is a share (¼ of a quad, ⅓ of a triangle) of the
//! undeformed area of every boundary face it is a corner of: contact pressure is force over this
//! area, per undeformed area (METHOD.md §5).

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
    out
}
