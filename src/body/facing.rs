//! Which surface particles of a body face a contact partner: the LPS skin correction
//! ([`super::lps::skin_factors`]) goes on those alone (docs/VALIDATION.md, "Any Poisson's
//! ratio", "The skin where a partner can press").
//!
//! The skin correction stiffens a surface particle's bonds along its normal so that a traction
//! entering through the face, a contact's, does not first compress a soft row. On a face no
//! contact can press it does harm: a face loaded along itself (the side of a block pressed from
//! above, whose row expands by Poisson's effect) is held by it, and a gmsh tet4 block in a
//! contact with a rigid plane that never touched it came out 29 % stiffer than the same block
//! without the contact. A face can be pressed by a partner only where the partner lies in front
//! of it: a particle faces a partner where the partner's nearest point lies within
//! [`FACING_CONE_DEG`] of its outward normal, or within a spacing of it (a body that starts
//! in touch).

use crate::case::segments::MasterSegment;
use crate::math::Vec3;

/// Half-angle of the cone about a surface particle's outward normal within which a partner's
/// nearest point makes the particle face it. Two equal spheres touching at their poles: a
/// particle at 17° from the pole (a Hertz contact's edge at a = 0.3R) sees the other's nearest
/// point at 33° from its normal, at 45° from the pole at 74°; a block's side face sees a plane
/// below it at 90°. 75° keeps the patch of a contact up to a = 0.7R on two equal spheres (the
/// whole sphere facing a plane up to 75° from its pole) and leaves a face at a right angle to
/// its partner alone with 15° to spare for the scatter of the normals of an unstructured mesh.
pub const FACING_CONE_DEG: f64 = 75.0;

/// A partner's surface as triangles (its boundary faces, a quadrilateral split in two), with a
/// bounding-volume hierarchy for the nearest point.
pub struct Outline {
    triangles: Vec<[Vec3; 3]>,
    nodes: Vec<Node>,
}

/// A node of the hierarchy: its box, and either its two children or a run of triangles.
struct Node {
    lo: Vec3,
    hi: Vec3,
    /// Children `[left, right]` (an inner node), or `[start, end)` into `triangles` (a leaf).
    span: [u32; 2],
    leaf: bool,
}

/// Triangles a leaf holds at most.
const LEAF: usize = 4;

impl Outline {
    /// The outline of `faces` (corner indices into `vertices`; a triangle repeats its third).
    pub fn new(vertices: &[Vec3], faces: &[MasterSegment]) -> Outline {
        let mut triangles = Vec::with_capacity(2 * faces.len());
        for f in faces {
            let [a, b, c, d] = f.nodes.map(|k| vertices[k as usize]);
            triangles.push([a, b, c]);
            if f.nodes[3] != f.nodes[2] {
                triangles.push([a, c, d]);
            }
        }
        let mut outline = Outline {
            triangles,
            nodes: Vec::new(),
        };
        if !outline.triangles.is_empty() {
            let n = outline.triangles.len();
            outline.split(0, n);
        }
        outline
    }

    /// Builds the node over `triangles[start..end]` (sorted in place along its box's longest
    /// side, halved at the median); returns its index.
    fn split(&mut self, start: usize, end: usize) -> u32 {
        let (mut lo, mut hi) = (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY));
        for t in &self.triangles[start..end] {
            for p in t {
                lo = lo.inf(p);
                hi = hi.sup(p);
            }
        }
        let index = self.nodes.len() as u32;
        self.nodes.push(Node {
            lo,
            hi,
            span: [start as u32, end as u32],
            leaf: true,
        });
        if end - start > LEAF {
            let axis = (hi - lo).imax();
            let centre = |t: &[Vec3; 3]| t[0][axis] + t[1][axis] + t[2][axis];
            let mid = (start + end) / 2;
            self.triangles[start..end]
                .select_nth_unstable_by(mid - start, |a, b| centre(a).total_cmp(&centre(b)));
            let left = self.split(start, mid);
            let right = self.split(mid, end);
            let node = &mut self.nodes[index as usize];
            node.span = [left, right];
            node.leaf = false;
        }
        index
    }

    /// The point of the outline nearest to `x` (`None` for an empty outline).
    pub fn nearest(&self, x: Vec3) -> Option<Vec3> {
        if self.nodes.is_empty() {
            return None;
        }
        let mut best = (f64::INFINITY, x);
        let mut stack = vec![0u32];
        while let Some(k) = stack.pop() {
            let node = &self.nodes[k as usize];
            if box_distance2(x, node.lo, node.hi) >= best.0 {
                continue;
            }
            if node.leaf {
                for t in &self.triangles[node.span[0] as usize..node.span[1] as usize] {
                    let p = closest_on_triangle(x, t);
                    let d2 = (p - x).norm_squared();
                    if d2 < best.0 {
                        best = (d2, p);
                    }
                }
            } else {
                // The nearer child last, so that it is searched first.
                let [a, b] = node.span;
                let da = box_distance2(x, self.nodes[a as usize].lo, self.nodes[a as usize].hi);
                let db = box_distance2(x, self.nodes[b as usize].lo, self.nodes[b as usize].hi);
                if da < db {
                    stack.extend([b, a]);
                } else {
                    stack.extend([a, b]);
                }
            }
        }
        Some(best.1)
    }
}

/// Squared distance from `x` to the box `[lo, hi]` (0 inside).
fn box_distance2(x: Vec3, lo: Vec3, hi: Vec3) -> f64 {
    (0..3)
        .map(|k| (lo[k] - x[k]).max(0.0).max(x[k] - hi[k]).powi(2))
        .sum()
}

/// The point of triangle `t` nearest to `x`, by the region of the triangle's plane that `x`
/// projects into (Ericson, "Real-Time Collision Detection", 5.1.5): a vertex, an edge, or the
/// inside.
fn closest_on_triangle(x: Vec3, t: &[Vec3; 3]) -> Vec3 {
    let [a, b, c] = *t;
    let (ab, ac, ap) = (b - a, c - a, x - a);
    let (d1, d2) = (ab.dot(&ap), ac.dot(&ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = x - b;
    let (d3, d4) = (ab.dot(&bp), ac.dot(&bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = x - c;
    let (d5, d6) = (ab.dot(&cp), ac.dot(&cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = va + vb + vc;
    if !(denom.abs() > 0.0) {
        // A degenerate triangle: its nearest vertex.
        return *t
            .iter()
            .min_by(|p, q| (*p - x).norm_squared().total_cmp(&(*q - x).norm_squared()))
            .expect("three vertices");
    }
    a + ab * (vb / denom) + ac * (vc / denom)
}

/// Per particle: whether it is a surface particle (`surface`) that faces one of `partners`
/// (the nearest point of one within [`FACING_CONE_DEG`] of its outward `normal`, or within
/// `spacing` of it).
pub fn facing(
    position: &[Vec3],
    normal: &[Vec3],
    surface: &[bool],
    partners: &[Outline],
    spacing: f64,
) -> Vec<bool> {
    use rayon::prelude::*;
    let cos = FACING_CONE_DEG.to_radians().cos();
    (0..position.len())
        .into_par_iter()
        .map(|i| {
            surface[i]
                && partners.iter().any(|o| {
                    o.nearest(position[i]).is_some_and(|p| {
                        let d = p - position[i];
                        let r = d.norm();
                        r <= spacing || normal[i].dot(&d) >= cos * r
                    })
                })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad(nodes: [u32; 4]) -> MasterSegment {
        MasterSegment {
            nodes,
            area: 1.0,
            normal: Vec3::z(),
        }
    }

    /// A cheap pseudo-random sequence in [0, 1), the same on every run.
    fn lcg(s: &mut u64) -> f64 {
        *s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*s >> 11) as f64 / (1u64 << 53) as f64
    }

    #[test]
    fn the_nearest_point_is_the_nearest_of_a_dense_sampling() {
        // A tilted triangle and a quadrilateral: the nearest point found against the best of
        // 20,000 points sampled on them, from points in every region about them.
        let v = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.1, 0.2),
            Vec3::new(0.2, 0.9, -0.1),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(3.0, 0.0, 0.5),
            Vec3::new(3.0, 1.0, 0.5),
            Vec3::new(2.0, 1.0, 0.0),
        ];
        let faces = [quad([0, 1, 2, 2]), quad([3, 4, 5, 6])];
        let o = Outline::new(&v, &faces);
        let mut s = 7u64;
        let mut samples = Vec::new();
        for (t, w) in [([0, 1, 2], 1.0), ([3, 4, 5], 0.5), ([3, 5, 6], 0.5)] {
            for _ in 0..(10_000.0 * w) as usize {
                let (mut p, mut q) = (lcg(&mut s), lcg(&mut s));
                if p + q > 1.0 {
                    (p, q) = (1.0 - p, 1.0 - q);
                }
                let [a, b, c] = t.map(|k| v[k]);
                samples.push(a + (b - a) * p + (c - a) * q);
            }
        }
        for _ in 0..200 {
            let x = Vec3::new(
                4.0 * lcg(&mut s) - 1.0,
                3.0 * lcg(&mut s) - 1.0,
                2.0 * lcg(&mut s) - 1.0,
            );
            let found = (o.nearest(x).unwrap() - x).norm();
            let sampled = samples
                .iter()
                .map(|p| (p - x).norm())
                .fold(f64::INFINITY, f64::min);
            assert!(found <= sampled + 1e-12, "{x:?}: {found} > {sampled}");
            assert!(found > sampled - 0.02, "{x:?}: {found} ≪ {sampled}");
        }
    }

    #[test]
    fn a_block_over_a_plane_faces_it_with_its_bottom_alone() {
        // The unit cube's faces' centres with their outward normals, a plane 5 below (one
        // quadrilateral of side 3), and a plane beside it at x = 1.5: the bottom faces the
        // first, the face x = 1 the second, no other face either.
        let plane = |z: f64| {
            let v = [(-1.5, -1.5), (1.5, -1.5), (1.5, 1.5), (-1.5, 1.5)]
                .map(|(x, y)| Vec3::new(x + 0.5, y + 0.5, z));
            Outline::new(&v, &[quad([0, 1, 2, 3])])
        };
        let side = Outline::new(
            &[
                Vec3::new(1.5, -1.0, -1.0),
                Vec3::new(1.5, 2.0, -1.0),
                Vec3::new(1.5, 2.0, 2.0),
                Vec3::new(1.5, -1.0, 2.0),
            ],
            &[quad([0, 1, 2, 3])],
        );
        let normals = [
            Vec3::x(),
            -Vec3::x(),
            Vec3::y(),
            -Vec3::y(),
            Vec3::z(),
            -Vec3::z(),
        ];
        let centres: Vec<Vec3> = normals
            .iter()
            .map(|n| Vec3::repeat(0.5) + n * 0.5)
            .collect();
        let surface = [true; 6];
        let below = facing(&centres, &normals, &surface, &[plane(-5.0)], 0.05);
        assert_eq!(below, [false, false, false, false, false, true]);
        let beside = facing(&centres, &normals, &surface, &[side], 0.05);
        assert_eq!(beside, [true, false, false, false, false, false]);
        // An interior particle faces nothing; one within a spacing of a partner faces it
        // whatever its normal.
        let touching = facing(
            &[Vec3::new(0.5, 0.5, -4.99), Vec3::new(0.5, 0.5, -4.99)],
            &[Vec3::z(), Vec3::z()],
            &[true, false],
            &[plane(-5.0)],
            0.05,
        );
        assert_eq!(touching, [true, false]);
    }

    #[test]
    fn a_sphere_over_a_plane_faces_it_up_to_the_cone() {
        // Points of a unit sphere whose pole touches the plane z = 0: those within the cone's
        // angle of the pole face it.
        let v =
            [(-9.0, -9.0), (9.0, -9.0), (9.0, 9.0), (-9.0, 9.0)].map(|(x, y)| Vec3::new(x, y, 0.0));
        let plane = Outline::new(&v, &[quad([0, 1, 2, 3])]);
        let angles: Vec<f64> = (1..=17).map(|k| 10.0 * k as f64).collect();
        let normals: Vec<Vec3> = angles
            .iter()
            .map(|a: &f64| {
                let a = a.to_radians();
                Vec3::new(a.sin(), 0.0, -a.cos())
            })
            .collect();
        let points: Vec<Vec3> = normals.iter().map(|n| Vec3::z() + n).collect();
        let f = facing(&points, &normals, &[true; 17], &[plane], 1e-3);
        for (a, f) in angles.iter().zip(f) {
            assert_eq!(f, *a <= FACING_CONE_DEG, "{a}°");
        }
    }
}
