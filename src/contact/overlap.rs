//! Bodies that start interpenetrating: the slave's surface particles that lie inside the
//! master before any step, deeper than a given depth ([`overlap`]).
//!
//! A slave behind the segment it faces by more than the contact window is a missed contact
//! (`narrow.rs`), and one deeper still, beyond the Verlet reach, is not seen at all: the
//! penalty can only push back particles that are within the window. A body placed that deep
//! in its master is a placement error, which `run` refuses before solving rather than let the
//! first iteration blame the load.
//!
//! Inside is decided by the nearest point of the master's segments, found with the narrow
//! phase's clamped projection ([`project_any`]: the gap `g` along the segment's normal and how
//! far `o` outside the segment, the distance being `√(g² + o²)`): a particle whose nearest
//! point lies within a segment (`o = 0`) and behind it lies inside the master by `−g`. For a
//! closed surface (a deformable body, a rigid solid mesh) this is exact: the line to the
//! nearest point crosses no other face. A particle whose nearest point is on an edge or a
//! vertex is not counted (outside a convex edge it is outside; inside a concave one its
//! neighbours nearer a face are counted). For a flat master (a rigid plane, a flat shell)
//! inside means behind the sheet within its extent, as the contact sees it, whatever the
//! distance.

use rayon::prelude::*;

use super::{project, project_any, MasterView};
use crate::body::PdBody;
use crate::case::neighbours::CellGrid;
use crate::case::segments::quad_area_normal;
use crate::math::Vec3;

/// The slave particles found inside a master.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Overlap {
    /// Surface particles inside the master by more than the depth asked for.
    pub count: usize,
    /// Surface particles of the slave (all that were looked at).
    pub of: usize,
    /// How deep the deepest of them lies, m (0 when none).
    pub deepest: f64,
}

/// The surface particles of `slave` that lie inside `master` by more than `depth`, at the
/// current positions (see the module documentation for what inside means).
pub fn overlap(slave: &PdBody, master: MasterView<'_>, depth: f64) -> Overlap {
    let particles: Vec<u32> = (0..slave.len() as u32)
        .filter(|&i| slave.case.surface.is_surface[i as usize])
        .collect();
    let segs = master.segments();
    let corners = (0..segs.len()).map(|s| master.corners(s)).collect();
    let triangle = segs.iter().map(|s| s.is_triangle()).collect();
    let found: Vec<f64> = match Surface::new(corners, triangle) {
        Some(surface) => particles
            .par_iter()
            .filter_map(|&i| surface.depth(slave.position(i as usize)))
            .filter(|&d| d > depth)
            .collect(),
        None => Vec::new(),
    };
    Overlap {
        count: found.len(),
        of: particles.len(),
        deepest: found.iter().copied().fold(0.0, f64::max),
    }
}

/// A master's segments, indexed for the nearest-segment search.
struct Surface {
    corners: Vec<[Vec3; 4]>,
    triangle: Vec<bool>,
    centre: Vec<Vec3>,
    /// Each segment lies within `reach` of its centre; `h` is the largest.
    reach: Vec<f64>,
    h: f64,
    /// Bounding box of the corners and its diagonal.
    lo: Vec3,
    hi: Vec3,
    span: f64,
    grid: CellGrid,
    /// The normal and a point of a master whose segments all lie in one plane.
    flat: Option<(Vec3, Vec3)>,
}

impl Surface {
    /// `None` without segments, or with segments of no finite size.
    fn new(corners: Vec<[Vec3; 4]>, triangle: Vec<bool>) -> Option<Surface> {
        let centre: Vec<Vec3> = corners
            .iter()
            .map(|c| (c[0] + c[1] + c[2] + c[3]) * 0.25)
            .collect();
        let reach: Vec<f64> = corners
            .iter()
            .zip(&centre)
            .map(|(c, m)| c.iter().map(|p| (p - m).norm()).fold(0.0, f64::max))
            .collect();
        let h = reach.iter().copied().fold(0.0, f64::max);
        if !(h > 0.0 && h.is_finite()) {
            return None;
        }
        let (mut lo, mut hi) = (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY));
        for p in corners.iter().flatten() {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        let grid = CellGrid::new(&centre, 2.0 * h);
        let flat = flat_normal(&corners);
        Some(Surface {
            span: (hi - lo).norm(),
            corners,
            triangle,
            centre,
            reach,
            h,
            lo,
            hi,
            grid,
            flat,
        })
    }

    /// How deep `p` lies inside the surface; `None` outside it, or nearest to an edge.
    fn depth(&self, p: Vec3) -> Option<f64> {
        let seg = |s: u32| (self.corners[s as usize], self.triangle[s as usize]);
        if let Some((n, x0)) = self.flat {
            // The segment under the point, if any: searched around its foot on the plane.
            let foot = p - n * (p - x0).dot(&n);
            let mut gap = None;
            self.grid.for_each_candidate(&foot, self.h, |s| {
                if gap.is_none() {
                    let (c, t) = seg(s);
                    gap = project(p, c, t).map(|pr| pr.gap);
                }
            });
            return gap.filter(|g| *g < 0.0).map(|g| -g);
        }
        // Inside a closed surface is inside its bounding box.
        if (0..3).any(|k| p[k] < self.lo[k] || p[k] > self.hi[k]) {
            return None;
        }
        // The nearest segment: a segment whose centre lies beyond r + h of the point is
        // farther than r, so a nearest found within r is the nearest of all.
        let mut r = self.grid.cell_size();
        loop {
            let mut best: Option<(f64, f64, f64)> = None; // (distance, outside, gap)
            self.grid.for_each_candidate(&p, r + self.h, |s| {
                let lower = (p - self.centre[s as usize]).norm() - self.reach[s as usize];
                if best.is_some_and(|b| lower > b.0) {
                    return;
                }
                let (c, t) = seg(s);
                if let Some((pr, o)) = project_any(p, c, t) {
                    let d = pr.gap.hypot(o);
                    if best.is_none_or(|b| d < b.0 || (d == b.0 && o < b.1)) {
                        best = Some((d, o, pr.gap));
                    }
                }
            });
            match best {
                Some((d, o, g)) if d <= r || r >= self.span => {
                    return (o == 0.0 && g < 0.0).then_some(-g);
                }
                None if r >= self.span => return None,
                _ => r *= 2.0,
            }
        }
    }
}

/// The normal and a point of segments that all lie in one plane, if they do.
fn flat_normal(corners: &[[Vec3; 4]]) -> Option<(Vec3, Vec3)> {
    let first = corners.first()?;
    let (_, n) = quad_area_normal(*first);
    let x0 = first[0];
    let scale = corners
        .iter()
        .flatten()
        .map(|p| (p - x0).norm())
        .fold(0.0, f64::max);
    let flat = n.norm() > 0.5
        && corners
            .iter()
            .flatten()
            .all(|p| (p - x0).dot(&n).abs() <= 1e-9 * scale)
        && corners.iter().all(|c| quad_area_normal(*c).1.dot(&n) > 0.0);
    flat.then_some((n, x0))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64) -> Vec3 {
        Vec3::new(x, y, z)
    }

    /// A unit cube of six faces wound outward, each split in four (segments about the
    /// spacing of its particles, as a body's are).
    fn cube() -> Surface {
        let faces = [
            [v(0., 0., 0.), v(0., 1., 0.), v(1., 1., 0.), v(1., 0., 0.)],
            [v(0., 0., 1.), v(1., 0., 1.), v(1., 1., 1.), v(0., 1., 1.)],
            [v(0., 0., 0.), v(1., 0., 0.), v(1., 0., 1.), v(0., 0., 1.)],
            [v(0., 1., 0.), v(0., 1., 1.), v(1., 1., 1.), v(1., 1., 0.)],
            [v(0., 0., 0.), v(0., 0., 1.), v(0., 1., 1.), v(0., 1., 0.)],
            [v(1., 0., 0.), v(1., 1., 0.), v(1., 1., 1.), v(1., 0., 1.)],
        ];
        let mut corners = Vec::new();
        for f in faces {
            let at = |a: f64, b: f64| {
                f[0] * ((1.0 - a) * (1.0 - b))
                    + f[1] * (a * (1.0 - b))
                    + f[2] * (a * b)
                    + f[3] * ((1.0 - a) * b)
            };
            for (a, b) in [(0.0, 0.0), (0.5, 0.0), (0.5, 0.5), (0.0, 0.5)] {
                corners.push([
                    at(a, b),
                    at(a + 0.5, b),
                    at(a + 0.5, b + 0.5),
                    at(a, b + 0.5),
                ]);
            }
        }
        let n = corners.len();
        Surface::new(corners, vec![false; n]).expect("segments")
    }

    #[test]
    fn depth_inside_a_cube_is_the_distance_to_its_nearest_face() {
        let c = cube();
        assert!(c.flat.is_none());
        let near = |p: Vec3, d: f64| (c.depth(p).expect("inside") - d).abs() < 1e-12;
        assert!(near(v(0.5, 0.5, 0.9), 0.1));
        assert!(near(v(0.3, 0.6, 0.5), 0.3));
        assert!(near(v(0.5, 0.5, 0.5), 0.5));
        for outside in [
            v(0.5, 0.5, 1.2),
            v(1.2, 0.5, 1.2),
            v(-0.1, -0.1, -0.1),
            v(3.0, 0.5, 0.5),
        ] {
            assert_eq!(c.depth(outside), None, "{outside:?}");
        }
    }

    #[test]
    fn behind_a_plane_counts_within_its_extent_only() {
        // A 2 x 2 plane of four quads at z = 0, facing +z.
        let mut corners = Vec::new();
        for (x, y) in [(-1.0, -1.0), (0.0, -1.0), (0.0, 0.0), (-1.0, 0.0)] {
            corners.push([
                v(x, y, 0.),
                v(x + 1., y, 0.),
                v(x + 1., y + 1., 0.),
                v(x, y + 1., 0.),
            ]);
        }
        let p = Surface::new(corners, vec![false; 4]).expect("segments");
        assert_eq!(p.flat.map(|f| f.0), Some(Vec3::z()));
        assert!((p.depth(v(0.5, 0.3, -0.2)).expect("behind") - 0.2).abs() < 1e-12);
        // Far behind it is still behind it; in front, or beside it, is not.
        assert!((p.depth(v(-0.5, 0.3, -50.0)).expect("behind") - 50.0).abs() < 1e-9);
        assert_eq!(p.depth(v(0.5, 0.3, 0.2)), None);
        assert_eq!(p.depth(v(1.5, 0.3, -0.2)), None);
    }
}
