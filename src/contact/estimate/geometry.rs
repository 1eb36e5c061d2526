//! The geometry of the estimate: the first contact by ray casting, the curvature fit, the
//! principal curvatures, mirror images (see the parent module).

use nalgebra::{DMatrix, DVector};

use super::{ContactSurface, CANDIDATES, FIT_POINTS};
use crate::case::mirror_images;
use crate::case::segments::MasterSegment;
use crate::math::Vec3;

/// The first contact point of `slave` moved along `approach` onto `master`, and the contact
/// normal there (from slave to master).
pub(super) fn first_contact(
    slave: &ContactSurface,
    master: &ContactSurface,
    approach: Vec3,
) -> Option<(Vec3, Vec3)> {
    let ahead = |s: &ContactSurface, dir: Vec3| {
        let mut nodes = s.facing_nodes(dir);
        let key = |n: &u32| -s.points[*n as usize].dot(&dir);
        if nodes.len() > CANDIDATES {
            nodes.select_nth_unstable_by(CANDIDATES, |a, b| key(a).total_cmp(&key(b)));
            nodes.truncate(CANDIDATES);
        }
        nodes
    };
    // Slave nodes onto master faces (normal −d), master nodes onto slave faces (normal d).
    let mut best: Option<(f64, Vec3, Vec3)> = None;
    for (from, onto, dir, sign) in [
        (slave, master, approach, -1.0),
        (master, slave, -approach, 1.0),
    ] {
        let faces: Vec<&MasterSegment> = onto
            .faces
            .iter()
            .filter(|f| f.normal.dot(&dir) < 0.0)
            .collect();
        // Bodies may start touching, or overlapping by a fraction of a face.
        let mut sizes: Vec<f64> = from.faces.iter().map(|f| f.area.sqrt()).collect();
        sizes.sort_by(f64::total_cmp);
        let tolerance = 0.5 * sizes.get(sizes.len() / 2).copied().unwrap_or(0.0);
        for n in ahead(from, dir) {
            let o = from.points[n as usize];
            for f in &faces {
                let c = f.nodes.map(|k| onto.points[k as usize]);
                let tris: &[[usize; 3]] = if f.is_triangle() {
                    &[[0, 1, 2]]
                } else {
                    &[[0, 1, 2], [0, 2, 3]]
                };
                for t in tris {
                    let Some(s) = ray_triangle(o, dir, c[t[0]], c[t[1]], c[t[2]]) else {
                        continue;
                    };
                    if s >= -tolerance && best.is_none_or(|b| s < b.0) {
                        best = Some((s, o + dir * s, f.normal * sign));
                    }
                }
            }
        }
    }
    best.map(|(_, q, d)| (q, d))
}

/// Möller-Trumbore: the ray parameter where `o + s·dir` crosses the triangle.
pub(super) fn ray_triangle(o: Vec3, dir: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Option<f64> {
    let (e1, e2) = (b - a, c - a);
    let p = dir.cross(&e2);
    let det = e1.dot(&p);
    if !(det.abs() > 1e-12 * e1.norm() * e2.norm()) {
        return None;
    }
    let s = o - a;
    let u = s.dot(&p) / det;
    let qv = s.cross(&e1);
    let v = dir.dot(&qv) / det;
    let eps = 1e-9;
    (u >= -eps && v >= -eps && u + v <= 1.0 + eps).then(|| e2.dot(&qv) / det)
}

/// Curvature tensor `[H_uu, H_uv, H_vv]` (1/m, positive where the surface curves away from the
/// other body) of a body's surface around `q`, and the fit window's radius. `sign` is −1 for
/// the slave (the surface lies behind `q` along `d`), +1 for the master. `None` when fewer than
/// [`FIT_POINTS`] facing nodes (images included; `4^refine` times that on a cut mesh,
/// [`ContactSurface::refine`]) are there to fit.
pub(super) fn fit_curvature(
    s: &ContactSurface,
    nodes: &[u32],
    q: Vec3,
    d: Vec3,
    e1: Vec3,
    e2: Vec3,
    sign: f64,
) -> Option<([f64; 3], f64)> {
    let mut samples: Vec<[f64; 3]> = Vec::new();
    for &n in nodes {
        for (y, _) in mirror_images(s.points[n as usize], s.planes) {
            let r = y - q;
            samples.push([r.dot(&e1), r.dot(&e2), sign * r.dot(&d)]);
        }
    }
    let fit_points = FIT_POINTS << (2 * s.refine.min(4));
    if samples.len() < fit_points {
        return None;
    }
    let dist = |p: &[f64; 3]| (p[0] * p[0] + p[1] * p[1]).sqrt();
    samples.sort_by(|a, b| dist(a).total_cmp(&dist(b)));
    let window = dist(&samples[fit_points - 1]) * (1.0 + 1e-9);
    // The nearest in the tangent plane, not behind the surface (a thin body's far side).
    samples.retain(|p| dist(p) <= window && p[2].abs() <= window);
    if samples.len() < 6 {
        return None;
    }
    Some((fit_paraboloid(&samples, window)?, window))
}

/// Least-squares `h = c₀ + c₁u + c₂v + ½(H_uu u² + 2H_uv uv + H_vv v²)` with the sagitta term
/// `½ κ h²` of the largest principal curvature moved to the data (exact on a sphere or a
/// cylinder: `r² = 2Rh − h²`).
pub(super) fn fit_paraboloid(samples: &[[f64; 3]], window: f64) -> Option<[f64; 3]> {
    let n = samples.len();
    let scaled = |i: usize| (samples[i][0] / window, samples[i][1] / window);
    let a = DMatrix::from_fn(n, 6, |i, j| {
        let (u, v) = scaled(i);
        [1.0, u, v, u * u, u * v, v * v][j]
    });
    let svd = a.svd(true, true);
    let (lo, hi) = svd
        .singular_values
        .iter()
        .fold((f64::MAX, 0.0f64), |(l, h), &s| (l.min(s), h.max(s)));
    if !(lo > 1e-8 * hi) {
        return None;
    }
    let h_min = samples.iter().map(|p| p[2]).fold(f64::MAX, f64::min);
    let mut kappa = 0.0;
    let mut hessian = [0.0; 3];
    // A fixed point: each pass shrinks the error by about (window/R)².
    for _ in 0..100 {
        let b = DVector::from_fn(n, |i, _| {
            let dh = samples[i][2] - h_min;
            samples[i][2] - 0.5 * kappa * dh * dh
        });
        let c = svd.solve(&b, 0.0).ok()?;
        let w2 = window * window;
        hessian = [2.0 * c[3] / w2, c[4] / w2, 2.0 * c[5] / w2];
        let next = principal(hessian, Vec3::x(), Vec3::y()).0.max(0.0);
        let done = (next - kappa).abs() <= 1e-12 * next;
        kappa = next;
        if done {
            break;
        }
    }
    hessian.iter().all(|x| x.is_finite()).then_some(hessian)
}

/// Principal curvatures `κ₁ ≥ κ₂` of `[H_uu, H_uv, H_vv]` in the frame `(e1, e2)`, and the
/// direction of `κ₁`.
pub(super) fn principal(h: [f64; 3], e1: Vec3, e2: Vec3) -> (f64, f64, Vec3) {
    let mean = 0.5 * (h[0] + h[2]);
    let r = (0.25 * (h[0] - h[2]).powi(2) + h[1] * h[1]).sqrt();
    let (k1, k2) = (mean + r, mean - r);
    let (a, b) = if h[0] >= h[2] {
        (k1 - h[2], h[1])
    } else {
        (h[1], k1 - h[0])
    };
    let dir = e1 * a + e2 * b;
    let dir = if dir.norm() > 0.0 {
        dir.normalize()
    } else {
        e1
    };
    (k1, k2, dir)
}

/// Diagonal of the bounding box of the nodes.
pub(super) fn extent(points: &[Vec3], nodes: &[u32]) -> f64 {
    let mut lo = Vec3::repeat(f64::MAX);
    let mut hi = Vec3::repeat(f64::MIN);
    for &n in nodes {
        lo = lo.inf(&points[n as usize]);
        hi = hi.sup(&points[n as usize]);
    }
    if nodes.is_empty() {
        0.0
    } else {
        (hi - lo).norm()
    }
}

/// Length of the slave's surface along a line contact: the extent, along the line, of the
/// facing nodes within a quarter of the fit window of the line (across it) and at most a window
/// behind the first contact. `None` for a line shorter than that band.
pub(super) fn line_length(
    s: &ContactSurface,
    nodes: &[u32],
    q: Vec3,
    d: Vec3,
    across: Vec3,
    window: f64,
) -> Option<f64> {
    let along = d.cross(&across);
    let band = 0.25 * window;
    let (mut lo, mut hi) = (f64::MAX, f64::MIN);
    for &n in nodes {
        let r = s.points[n as usize] - q;
        if r.dot(&across).abs() <= band && -r.dot(&d) <= window {
            lo = lo.min(r.dot(&along));
            hi = hi.max(r.dot(&along));
        }
    }
    (hi - lo > band).then_some(hi - lo)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::tangent_frame;

    /// Heights of points of a surface `h(u, v)` on a ring grid out to `reach`.
    fn grid(reach: f64, h: impl Fn(f64, f64) -> f64) -> Vec<[f64; 3]> {
        let mut out = Vec::new();
        for i in -6..=6 {
            for j in -6..=6 {
                let (u, v) = (reach * i as f64 / 6.0, reach * j as f64 / 6.0);
                if u * u + v * v <= reach * reach {
                    out.push([u, v, h(u, v)]);
                }
            }
        }
        out
    }

    #[test]
    fn the_sagitta_corrected_fit_is_exact_on_a_sphere_and_a_cylinder() {
        // Window half the radius: a plain paraboloid would be 10 % off.
        let r = 2.0;
        let sphere = grid(1.0, |u, v| r - (r * r - u * u - v * v).sqrt());
        let h = fit_paraboloid(&sphere, 1.0).unwrap();
        let (k1, k2, _) = principal(h, Vec3::x(), Vec3::y());
        assert!(
            (k1 * r - 1.0).abs() < 1e-9 && (k2 * r - 1.0).abs() < 1e-9,
            "{k1} {k2}"
        );
        let cylinder = grid(1.0, |u, _| r - (r * r - u * u).sqrt());
        let h = fit_paraboloid(&cylinder, 1.0).unwrap();
        let (k1, k2, dir) = principal(h, Vec3::x(), Vec3::y());
        assert!((k1 * r - 1.0).abs() < 1e-9 && k2.abs() < 1e-9, "{k1} {k2}");
        assert!((dir.x.abs() - 1.0).abs() < 1e-9, "{dir:?}");
        // A tilted plane and a bowl: no curvature, negative curvature.
        let plane = grid(1.0, |u, v| 0.1 * u - 0.2 * v + 0.3);
        let h = fit_paraboloid(&plane, 1.0).unwrap();
        assert!(h.iter().all(|x| x.abs() < 1e-12), "{h:?}");
        let bowl = grid(1.0, |u, v| -(u * u + v * v) / (2.0 * r));
        let (k1, _, _) = principal(fit_paraboloid(&bowl, 1.0).unwrap(), Vec3::x(), Vec3::y());
        assert!(k1 < 0.0);
        // Points on a line cannot give a surface.
        let line: Vec<[f64; 3]> = (0..10).map(|i| [i as f64, 0.0, 0.0]).collect();
        assert!(fit_paraboloid(&line, 1.0).is_none());
    }

    #[test]
    fn rays_hit_triangles_inside_only() {
        let (a, b, c) = (Vec3::zeros(), Vec3::x(), Vec3::y());
        let down = -Vec3::z();
        let s = ray_triangle(Vec3::new(0.2, 0.2, 1.5), down, a, b, c).unwrap();
        assert!((s - 1.5).abs() < 1e-12);
        assert!(ray_triangle(Vec3::new(0.8, 0.8, 1.0), down, a, b, c).is_none());
        assert!(ray_triangle(Vec3::new(0.2, 0.2, 1.0), Vec3::x(), a, b, c).is_none());
        let (e1, e2) = tangent_frame(down);
        assert!(e1.dot(&down).abs() < 1e-12 && e2.dot(&down).abs() < 1e-12);
        assert!((e1.cross(&e2).dot(&down) - 1.0).abs() < 1e-12);
    }
}
