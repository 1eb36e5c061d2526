//! The narrow phase of point-to-surface contact (paper Secs. 2.2.2-2.2.3, Eqs. 18-21,
//! METHOD.md §5): a slave projected on a master segment ([`project`], [`project_any`]), the
//! segment it touches chosen among its candidates ([`select_segment`]), the rule for a slave
//! behind a concave edge or vertex ([`select_across_edge`]), and the slave's current normal
//! ([`slave_normal`]).

use crate::body::PdBody;
use crate::math::Vec3;
use crate::scene::Kinematics;

/// Tolerance on `|r|, |t| ≤ 1`.
pub const INSIDE_TOLERANCE: f64 = 1e-6;
/// A slave touches a segment first of all when their normals oppose: `n_s · n_m < −FACING`.
///
/// Without it, a slave just inside the edge of a convex master (a punch's corner) is closer to
/// the side face than to the face it pressed on, and is pushed out sideways.
pub const FACING: f64 = 0.1;

/// A slave that no facing segment holds in its window may touch a segment across its normal,
/// `|n_s · n_m| < EDGE_FACING`, within the window: the free surface beside a punch, drawn down
/// and inward around the punch's corner, meets the punch's side face edge-on. Faces turned
/// further away (the back of a thin master) are never touched.
pub const EDGE_FACING: f64 = 0.5;

/// The slave's outward normal now: the reference normal of the eigenvalue surface detection
/// (METHOD.md §3), turned by the rotation that takes the particle's reference neighbour
/// centroid offset to its current one. Exact for a rigid rotation (bar one about the offset
/// itself, which barely moves a normal that nearly opposes the offset); unchanged when the
/// body does not turn.
pub fn slave_normal(body: &PdBody, i: usize) -> Vec3 {
    turned_normal(body, i, body.case.surface.normal[i], None)
}

/// [`slave_normal`] from the reference normal `n_ref`, turned over the bonds `intact` keeps
/// (all where `None`): a particle of a face a crack opened turns with the particles still
/// bonded to it, not with the other face's.
pub fn turned_normal(body: &PdBody, i: usize, n_ref: Vec3, intact: Option<&[bool]>) -> Vec3 {
    if body.kinematics == Kinematics::Small {
        return n_ref;
    }
    let n = body.len();
    let (x_i, y_i) = (body.reference[i], body.position(i));
    let (mut c0, mut c) = (Vec3::zeros(), Vec3::zeros());
    for b in body.case.bonds.range(i) {
        let j = body.case.bonds.partner[b] as usize;
        if j < n && intact.is_none_or(|f| f[b]) {
            c0 += body.reference[j] - x_i;
            c += body.position(j) - y_i;
        }
    }
    match nalgebra::Rotation3::rotation_between(&c0, &c) {
        Some(r) if c0.norm() > 0.0 && c.norm() > 0.0 => r * n_ref,
        _ => n_ref,
    }
}

/// The slave is behind the segment, within the window: in contact (Eq. 21).
#[inline]
pub(super) fn within_window(pr: &Projection, window: f64) -> bool {
    pr.gap < 0.0 && -pr.gap <= window
}

/// What the narrow phase finds for one slave.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Touch {
    /// Pressed on this segment, within the window.
    Contact(u32, Projection),
    /// Behind the segment it faces by more than the window: it went through (the segment, and
    /// the gap, negative).
    Missed(u32, f64),
    /// Touching nothing.
    Clear,
}

/// Picks the segment a slave touches among the segments it projects inside (Sec. 2.2.3):
/// the facing segment (`n_s · n_m < −FACING`) nearest to it, if the slave is behind it within
/// the window; else, if the slave is behind every segment it projects on (inside a convex
/// master), the edge-on segment (`|n_s · n_m| < EDGE_FACING`) it has entered least. The slave's
/// normal `normal()` is computed only if a segment is found.
pub fn select_segment(
    candidates: impl Iterator<Item = (u32, Projection)>,
    normal: impl FnOnce() -> Vec3,
    window: f64,
) -> Touch {
    let n_s = std::cell::LazyCell::new(normal);
    let mut best: Option<(u32, Projection)> = None;
    let mut edge: Option<(u32, Projection)> = None;
    // In front of any segment it projects on, the slave is outside a convex master: then it
    // cannot be touching a face edge-on.
    let mut in_front = false;
    for (seg, pr) in candidates {
        let facing = n_s.dot(&pr.normal);
        in_front |= pr.gap >= 0.0;
        if facing < -FACING {
            if best
                .as_ref()
                .is_none_or(|(_, b)| pr.gap.abs() < b.gap.abs())
            {
                best = Some((seg, pr));
            }
        } else if facing < EDGE_FACING
            && within_window(&pr, window)
            && edge.as_ref().is_none_or(|(_, e)| pr.gap > e.gap)
        {
            edge = Some((seg, pr));
        }
    }
    let facing_holds = best
        .as_ref()
        .is_some_and(|(_, pr)| within_window(pr, window));
    if !facing_holds && !in_front && edge.is_some() {
        best = edge;
    }
    match best {
        Some((seg, pr)) if within_window(&pr, window) => Touch::Contact(seg, pr),
        Some((seg, pr)) if pr.gap < -window => Touch::Missed(seg, pr.gap),
        _ => Touch::Clear,
    }
}

/// Where a slave touches a segment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    /// Shape-function weights of the segment's four corners at `(r, t)`.
    pub weights: [f64; 4],
    /// Outward unit normal of the segment's projection plane (Eq. 18).
    pub normal: Vec3,
    /// Gap `g` (Eq. 21): negative when the slave is behind the segment.
    pub gap: f64,
}

/// Projects a slave point on a (deformed) segment with corners `x` (`x[2] == x[3]` for a
/// triangle). `None` when the projection falls outside the segment.
pub fn project(slave: Vec3, x: [Vec3; 4], triangle: bool) -> Option<Projection> {
    project_any(slave, x, triangle).and_then(|(pr, outside)| (outside == 0.0).then_some(pr))
}

/// [`project`], but a projection that falls outside the segment is moved onto its boundary
/// (`(r, t)` clamped to the square, or the nearest point of the triangle's edges); the second
/// value is how far outside, in the segment's plane (0 inside).
pub fn project_any(slave: Vec3, x: [Vec3; 4], triangle: bool) -> Option<(Projection, f64)> {
    // Eq. 18: e3 from the diagonals; (x2 − x0) × (x3 − x1) points out for outward winding.
    let e3 = (x[2] - x[0]).cross(&(x[3] - x[1]));
    let norm = e3.norm();
    if !(norm > 0.0) {
        return None;
    }
    let e3 = e3 / norm;
    if triangle {
        // Barycentric coordinates in the triangle's plane.
        let (a, b, c) = (x[0], x[1], x[2]);
        let n = (b - a).cross(&(c - a));
        let area2 = n.norm_squared();
        if !(area2 > 0.0) {
            return None;
        }
        let p = slave - e3 * (slave - a).dot(&e3);
        let l1 = (c - b).cross(&(p - b)).dot(&n) / area2;
        let l2 = (a - c).cross(&(p - c)).dot(&n) / area2;
        let l3 = 1.0 - l1 - l2;
        let tol = -INSIDE_TOLERANCE;
        if l1 < tol || l2 < tol || l3 < tol {
            // The nearest point on the edges, as barycentric weights.
            let mut best = (f64::INFINITY, [0.0; 3]);
            for (u, v, iu, iv) in [(a, b, 0, 1), (b, c, 1, 2), (c, a, 2, 0)] {
                let e = v - u;
                let s = ((p - u).dot(&e) / e.norm_squared()).clamp(0.0, 1.0);
                let d = (p - (u + e * s)).norm();
                if d < best.0 {
                    let mut w = [0.0; 3];
                    w[iu] = 1.0 - s;
                    w[iv] = s;
                    best = (d, w);
                }
            }
            let [w1, w2, w3] = best.1;
            let xc = a * w1 + b * w2 + c * w3;
            return Some((
                Projection {
                    weights: [w1, w2, w3, 0.0],
                    normal: e3,
                    gap: (slave - xc).dot(&e3),
                },
                best.0.max(f64::MIN_POSITIVE),
            ));
        }
        let xc = a * l1 + b * l2 + c * l3;
        return Some((
            Projection {
                weights: [l1, l2, l3, 0.0],
                normal: e3,
                gap: (slave - xc).dot(&e3),
            },
            0.0,
        ));
    }
    let r21 = x[1] - x[0];
    let e1 = r21 - e3 * r21.dot(&e3);
    let e1n = e1.norm();
    if !(e1n > 0.0) {
        return None;
    }
    let e1 = e1 / e1n;
    let e2 = e3.cross(&e1);
    let origin = (x[0] + x[1] + x[2] + x[3]) * 0.25;
    let to2 = |p: Vec3| {
        let d = p - origin;
        [d.dot(&e1), d.dot(&e2)]
    };
    let p = [to2(x[0]), to2(x[1]), to2(x[2]), to2(x[3])];
    let q = to2(slave);
    // Eqs. 19-20: N_i = ¼(1 + r_i r)(1 + t_i t), corners at (−1,−1), (1,−1), (1,1), (−1,1).
    const RI: [f64; 4] = [-1.0, 1.0, 1.0, -1.0];
    const TI: [f64; 4] = [-1.0, -1.0, 1.0, 1.0];
    let (mut r, mut t) = (0.0f64, 0.0f64);
    let scale = (p[2][0] - p[0][0]).abs()
        + (p[2][1] - p[0][1]).abs()
        + (p[3][0] - p[1][0]).abs()
        + (p[3][1] - p[1][1]).abs();
    let mut converged = false;
    for _ in 0..25 {
        let mut f = [-q[0], -q[1]];
        let mut j = [[0.0; 2]; 2];
        for k in 0..4 {
            let n = 0.25 * (1.0 + RI[k] * r) * (1.0 + TI[k] * t);
            let dr = 0.25 * RI[k] * (1.0 + TI[k] * t);
            let dt = 0.25 * TI[k] * (1.0 + RI[k] * r);
            for a in 0..2 {
                f[a] += n * p[k][a];
                j[a][0] += dr * p[k][a];
                j[a][1] += dt * p[k][a];
            }
        }
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        if !(det.abs() > 1e-300) {
            return None;
        }
        let dr = (f[0] * j[1][1] - f[1] * j[0][1]) / det;
        let dt = (j[0][0] * f[1] - j[1][0] * f[0]) / det;
        r -= dr;
        t -= dt;
        if !(r.is_finite() && t.is_finite()) || r.abs() > 10.0 || t.abs() > 10.0 {
            return None;
        }
        if (f[0].abs() + f[1].abs()) <= 1e-13 * scale && dr.abs() + dt.abs() < 1e-10 {
            converged = true;
            break;
        }
        if dr.abs() + dt.abs() < 1e-13 {
            converged = true;
            break;
        }
    }
    if !converged {
        return None;
    }
    let lim = 1.0 + INSIDE_TOLERANCE;
    let inside = r.abs() <= lim && t.abs() <= lim;
    let (r, t) = if inside {
        (r, t)
    } else {
        (r.clamp(-1.0, 1.0), t.clamp(-1.0, 1.0))
    };
    let mut weights = [0.0; 4];
    let mut xc = Vec3::zeros();
    for k in 0..4 {
        weights[k] = 0.25 * (1.0 + RI[k] * r) * (1.0 + TI[k] * t);
        xc += x[k] * weights[k];
    }
    let outside = if inside {
        0.0
    } else {
        let c = to2(xc);
        ((q[0] - c[0]).powi(2) + (q[1] - c[1]).powi(2))
            .sqrt()
            .max(f64::MIN_POSITIVE)
    };
    Some((
        Projection {
            weights,
            normal: e3,
            gap: (slave - xc).dot(&e3),
        },
        outside,
    ))
}

/// A slave behind a concave master edge or vertex (the dimple a deformable master takes
/// under load) projects outside every segment it is pressed into: along each segment's own
/// normal it lands beyond the shared edge, by its penetration times the tangent of the angle
/// between the segments. Without this rule it touches nothing and sinks through the master
/// (measured: a sphere on a deformable block whose pole lay over a block node never
/// converged). So when no segment holds the slave, the facing segment it falls outside by
/// no more than its penetration holds it at the nearest boundary point, provided the slave
/// is also behind every facing or edge-on segment that shares that edge or vertex; in front
/// of one of them, the edge is convex and the slave is outside the master. A segment that
/// shares only one corner of the edge meets it at that vertex at another angle and says
/// nothing of it: counted, two such segments let a slave 0.5 mm deep through between
/// iterations on two gmsh spheres pressed together with one pass, and ADR cycled. The force there
/// acts along the mean normal of the facing segments that share the edge or vertex (a slave
/// over the bottom vertex of a symmetric dimple is pushed straight out, not sideways by
/// whichever segment it picked), and the gap is measured along it, from the edge's point
/// nearest to the slave.
pub fn select_across_edge(
    slave: Vec3,
    candidates: impl Iterator<Item = (u32, Projection, f64)> + Clone,
    nodes: impl Fn(u32) -> [u32; 4],
    corners: impl Fn(u32) -> [Vec3; 4],
    normal: impl FnOnce() -> Vec3,
    window: f64,
) -> Option<(u32, Projection)> {
    // Most slaves touch nothing: the slave's normal (a pass over its bonds) is computed only
    // for one that is behind a segment it projects outside of.
    let n_s = std::cell::LazyCell::new(normal);
    let mut best: Option<(u32, Projection, f64)> = None;
    for (seg, pr, outside) in candidates.clone() {
        if outside > 0.0
            && within_window(&pr, window)
            && outside <= -pr.gap
            && n_s.dot(&pr.normal) < -FACING
            && best.as_ref().is_none_or(|(_, b, o)| {
                outside < *o || (outside == *o && pr.gap.abs() < b.gap.abs())
            })
        {
            best = Some((seg, pr, outside));
        }
    }
    let (seg, mut pr, _) = best?;
    let own = nodes(seg);
    let support: Vec<u32> = (0..4)
        .filter(|&k| pr.weights[k] > 1e-12)
        .map(|k| own[k])
        .collect();
    let mut mean = Vec3::zeros();
    for (other, q, q_outside) in candidates {
        // Only the segments that share the whole edge (or the vertex) the slave is held at
        // tell whether it is convex: one that shares a corner of that edge meets it at the
        // vertex, at another angle.
        let theirs = nodes(other);
        if !support.iter().all(|n| theirs.contains(n)) {
            continue;
        }
        let facing = n_s.dot(&q.normal);
        // In front of a segment that shares the edge or vertex, and near it: the edge is
        // convex. A segment the slave projects far outside of (beyond the window) tells
        // nothing of the edge: its plane passes elsewhere (a neighbour of the vertex at
        // another height on a curved, unstructured master vetoed slaves that its
        // neighbours held, and they sank through).
        if facing < EDGE_FACING && q.gap >= 0.0 && q_outside <= window {
            return None;
        }
        if facing < -FACING {
            mean += q.normal;
        }
    }
    let n = mean.try_normalize(0.0)?;
    let x = corners(seg);
    // Held at a quadrilateral's edge, the slave presses on the edge's point nearest to it,
    // whichever of the segments that share the edge was picked: each quadrilateral's
    // projection, clamped in its own (r, t), lands elsewhere on the edge, and a slave over
    // the dimple's edge picked the one and the other by turns (the segment it falls least
    // outside of) with a force that jumped by 1.5 % each time (two gmsh hex spheres pressed
    // together with one pass, H = 0.07 m: ADR 4,663 iterations, 2,908 with the edge's own
    // point). A triangle's clamp is that point already (the nearest point of its edges).
    if let (&[a, b], false) = (&support[..], own[2] == own[3]) {
        let corner = |node: u32| (0..4).find(|&k| own[k] == node);
        if let (Some(a), Some(b)) = (corner(a), corner(b)) {
            let e = x[b] - x[a];
            let t = ((slave - x[a]).dot(&e) / e.norm_squared()).clamp(0.0, 1.0);
            if t.is_finite() {
                pr.weights = [0.0; 4];
                pr.weights[a] = 1.0 - t;
                pr.weights[b] = t;
            }
        }
    }
    let xc: Vec3 = (0..4).map(|k| x[k] * pr.weights[k]).sum();
    pr.normal = n;
    pr.gap = (slave - xc).dot(&n);
    within_window(&pr, window).then_some((seg, pr))
}

/// A slave on a symmetry plane that its master shares, against a master segment with an edge
/// on that plane (corners `edge`; `axis` the plane's normal axis): projected on that edge,
/// along the segment's normal with its component across the plane removed.
///
/// The model holds one side of a symmetric contact: the segment's mirror image across the
/// plane is the master's surface there too. A slave on the plane is behind the segment and
/// its image by the same gap, and the force the whole contact puts on it lies in the plane,
/// along the mean of the two normals. Without the image the slave projects inside the segment
/// or just outside it by `|g n_axis|` (a hundredth of the spacing), as the sign of the
/// facet's small tilt across the plane decides, and in the second case nothing holds it:
/// measured on two gmsh tet spheres pressed together (quarter models), the slave on the plane
/// at the rim of the contact and the master node under it went in and out of contact
/// between iterations, and ADR never converged. Outside the edge's ends the projection is
/// clamped, and the second value says by how much (0 within), as [`project_any`]'s.
pub fn project_on_plane_edge(
    slave: Vec3,
    x: [Vec3; 4],
    edge: (usize, usize),
    axis: usize,
) -> Option<(Projection, f64)> {
    let (a, b) = (x[edge.0], x[edge.1]);
    let e = b - a;
    let len2 = e.norm_squared();
    if !(len2 > 0.0) {
        return None;
    }
    let mut n = (x[2] - x[0]).cross(&(x[3] - x[1]));
    n[axis] = 0.0;
    // In the plane and across the edge: the mean of the normals of the segment and its image.
    let n = (n - e * (n.dot(&e) / len2)).try_normalize(0.0)?;
    let s = (slave - a).dot(&e) / len2;
    let sc = s.clamp(0.0, 1.0);
    let outside = (s - sc).abs() * len2.sqrt();
    let xc = a + e * sc;
    let mut weights = [0.0; 4];
    weights[edge.0] = 1.0 - sc;
    weights[edge.1] = sc;
    let outside = if outside > INSIDE_TOLERANCE * len2.sqrt() {
        outside
    } else {
        0.0
    };
    Some((
        Projection {
            weights,
            normal: n,
            gap: (slave - xc).dot(&n),
        },
        outside,
    ))
}
