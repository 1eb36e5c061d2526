//! Built-in shapes meshed with hex8 elements: sphere, cylinder, box (METHOD.md §1).
//!
//! They produce a [`Mesh`] like the importers do, so a generated body takes the same road as an
//! imported one (faces, particles, surface, segments). The sphere and the cylinder are
//! block-structured ("cubed sphere", "squared circle"): an inner cube or square surrounded by
//! shells whose outer faces lie on the curved surface, with equal angles between surface nodes
//! (equiangular mapping), so the surface spacing is nearly uniform and a face centre sits on each
//! axis pole: the sphere's south pole (0, 0, −R), where it touches a plane below, is a regular
//! grid point.

use std::collections::HashMap;

use pdcontact_importers::{ElementKind, Mesh, NamedSet, SetKind};

use crate::case::discretize::element_volume;
use crate::math::Vec3;

/// Builds a hex mesh block by block, merging coincident nodes.
struct HexBuilder {
    mesh: Mesh,
    merge: HashMap<[i64; 3], u32>,
    quantum: f64,
}

impl HexBuilder {
    fn new(size: f64) -> HexBuilder {
        HexBuilder {
            mesh: Mesh::new(),
            merge: HashMap::new(),
            quantum: size * 1e-9,
        }
    }

    fn node(&mut self, p: Vec3) -> u32 {
        let key = [p.x, p.y, p.z].map(|c| (c / self.quantum).round() as i64);
        if let Some(&n) = self.merge.get(&key) {
            return n;
        }
        let id = self.mesh.node_count() as u64 + 1;
        let n = self.mesh.push_node(id, [p.x, p.y, p.z]);
        self.merge.insert(key, n);
        n
    }

    /// Adds an `ni × nj × nk` block of hexes whose node `(i, j, k)` sits at `at(i, j, k)`.
    fn block(&mut self, ni: usize, nj: usize, nk: usize, at: impl Fn(usize, usize, usize) -> Vec3) {
        let mut ids = vec![0u32; (ni + 1) * (nj + 1) * (nk + 1)];
        let idx = |i: usize, j: usize, k: usize| i + (ni + 1) * (j + (nj + 1) * k);
        for k in 0..=nk {
            for j in 0..=nj {
                for i in 0..=ni {
                    ids[idx(i, j, k)] = self.node(at(i, j, k));
                }
            }
        }
        for k in 0..nk {
            for j in 0..nj {
                for i in 0..ni {
                    let mut c = [
                        ids[idx(i, j, k)],
                        ids[idx(i + 1, j, k)],
                        ids[idx(i + 1, j + 1, k)],
                        ids[idx(i, j + 1, k)],
                        ids[idx(i, j, k + 1)],
                        ids[idx(i + 1, j, k + 1)],
                        ids[idx(i + 1, j + 1, k + 1)],
                        ids[idx(i, j + 1, k + 1)],
                    ];
                    if element_volume(ElementKind::Hex8, &c, &self.mesh.coords) < 0.0 {
                        c.swap(1, 3);
                        c.swap(5, 7);
                    }
                    let id = self.mesh.element_count() as u64 + 1;
                    self.mesh.push_element(id, ElementKind::Hex8, &c);
                }
            }
        }
    }

    /// Adds a node set of the nodes for which `keep` holds.
    fn node_set(&mut self, name: &str, keep: impl Fn(Vec3) -> bool) {
        let nodes: Vec<u32> = (0..self.mesh.node_count() as u32)
            .filter(|&n| keep(Vec3::from(self.mesh.coords[n as usize])))
            .collect();
        self.mesh.sets.push(NamedSet {
            name: name.to_string(),
            kind: SetKind::NodeSet,
            nodes: Some(nodes),
            elements: None,
        });
    }

    fn finish(mut self, body: &str) -> Mesh {
        let all: Vec<u32> = (0..self.mesh.element_count() as u32).collect();
        self.mesh.sets.insert(
            0,
            NamedSet {
                name: body.to_string(),
                kind: SetKind::ElementSet,
                nodes: None,
                elements: Some(all),
            },
        );
        self.mesh
    }
}

/// Divisions for a length at a target spacing (at least `min`).
fn divisions(length: f64, spacing: f64, min: usize) -> usize {
    ((length / spacing).round() as usize).max(min)
}

/// A solid sphere of radius `radius` centred at the origin, hex8, surface spacing ≈ `spacing`.
///
/// Sets: element set `ball`; node sets `surface` (all nodes on the sphere) and `top` (surface
/// nodes with z ≥ 0.9 R, a place to apply a load).
pub fn sphere(radius: f64, spacing: f64) -> Mesh {
    // An even count puts node planes on x = 0, y = 0, z = 0 (symmetry cuts).
    let n = 2 * divisions(std::f64::consts::FRAC_PI_4 * radius, spacing, 1);
    // Inner cube half-side: its corners must stay well inside the sphere (a√3 < R).
    let a = 0.55 * radius;
    let nr = divisions(radius - a, spacing, 1);
    let mut b = HexBuilder::new(radius);
    b.block(n, n, n, |i, j, k| {
        Vec3::new(i as f64, j as f64, k as f64) * (2.0 * a / n as f64) - Vec3::repeat(a)
    });
    for axis in 0..3 {
        for sign in [-1.0, 1.0] {
            let (d1, d2) = ((axis + 1) % 3, (axis + 2) % 3);
            b.block(n, n, nr, |i, j, k| {
                let u = -1.0 + 2.0 * i as f64 / n as f64;
                let v = -1.0 + 2.0 * j as f64 / n as f64;
                let t = k as f64 / nr as f64;
                let mut q = Vec3::zeros();
                q[axis] = sign;
                q[d1] = u;
                q[d2] = v;
                let inner = q * a;
                let mut e = q;
                e[d1] = (std::f64::consts::FRAC_PI_4 * u).tan();
                e[d2] = (std::f64::consts::FRAC_PI_4 * v).tan();
                let outer = e.normalize() * radius;
                inner + (outer - inner) * t
            });
        }
    }
    let tol = 1e-9 * radius;
    b.node_set("surface", |p| (p.norm() - radius).abs() < tol);
    b.node_set("top", |p| {
        (p.norm() - radius).abs() < tol && p.z >= 0.9 * radius
    });
    b.finish("ball")
}

/// A solid cylinder of radius `radius` and length `length` along the y axis, centred at the
/// origin, hex8, spacing ≈ `spacing`.
///
/// Sets: element set `roller`; node sets `surface` (the curved surface), `ymin`, `ymax` (the
/// end faces) and `top` (curved-surface nodes with z ≥ 0.9 R).
pub fn cylinder(radius: f64, length: f64, spacing: f64) -> Mesh {
    let n = 2 * divisions(std::f64::consts::FRAC_PI_4 * radius, spacing, 1);
    let a = 0.55 * radius;
    let nr = divisions(radius - a, spacing, 1);
    let ny = divisions(length, spacing, 1);
    let y = |j: usize| -0.5 * length + length * j as f64 / ny as f64;
    let mut b = HexBuilder::new(radius.max(length));
    b.block(n, ny, n, |i, j, k| {
        let s = 2.0 * a / n as f64;
        Vec3::new(-a + s * i as f64, y(j), -a + s * k as f64)
    });
    // Four shells around the square in the x-z plane.
    for (axis, sign) in [(0usize, -1.0), (0, 1.0), (2, -1.0), (2, 1.0)] {
        let other = 2 - axis;
        b.block(n, ny, nr, |i, j, k| {
            let u = -1.0 + 2.0 * i as f64 / n as f64;
            let t = k as f64 / nr as f64;
            let mut q = [0.0f64; 3];
            q[axis] = sign;
            q[other] = u;
            let inner = Vec3::new(q[0] * a, 0.0, q[2] * a);
            let mut e = q;
            e[other] = (std::f64::consts::FRAC_PI_4 * u).tan();
            let dir = Vec3::new(e[0], 0.0, e[2]).normalize();
            let outer = dir * radius;
            let mut p = inner + (outer - inner) * t;
            p.y = y(j);
            p
        });
    }
    let tol = 1e-9 * radius.max(length);
    let r_xz = |p: Vec3| (p.x * p.x + p.z * p.z).sqrt();
    b.node_set("surface", |p| (r_xz(p) - radius).abs() < tol);
    b.node_set("ymin", |p| (p.y + 0.5 * length).abs() < tol);
    b.node_set("ymax", |p| (p.y - 0.5 * length).abs() < tol);
    b.node_set("top", |p| {
        (r_xz(p) - radius).abs() < tol && p.z >= 0.9 * radius
    });
    b.finish("roller")
}

/// A box from `lo` to `hi`, hex8, spacing ≈ `spacing` along each axis.
///
/// Sets: element set `block`; node sets `xmin`, `xmax`, `ymin`, `ymax`, `zmin` (also `bottom`),
/// `zmax` (also `top`).
pub fn cuboid(lo: [f64; 3], hi: [f64; 3], spacing: f64) -> Mesh {
    let size: [f64; 3] = std::array::from_fn(|k| hi[k] - lo[k]);
    let nd: [usize; 3] = std::array::from_fn(|k| divisions(size[k], spacing, 1));
    let mut b = HexBuilder::new(size.iter().copied().fold(0.0, f64::max));
    b.block(nd[0], nd[1], nd[2], |i, j, k| {
        Vec3::new(
            lo[0] + size[0] * i as f64 / nd[0] as f64,
            lo[1] + size[1] * j as f64 / nd[1] as f64,
            lo[2] + size[2] * k as f64 / nd[2] as f64,
        )
    });
    let tol = 1e-9 * size.iter().copied().fold(0.0, f64::max);
    for (k, axis) in ["x", "y", "z"].iter().enumerate() {
        b.node_set(&format!("{axis}min"), |p| (p[k] - lo[k]).abs() < tol);
        b.node_set(&format!("{axis}max"), |p| (p[k] - hi[k]).abs() < tol);
    }
    b.node_set("bottom", |p| (p.z - lo[2]).abs() < tol);
    b.node_set("top", |p| (p.z - hi[2]).abs() < tol);
    b.finish("block")
}

/// The curved bottom of a truncated cap.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CapShape {
    /// A sphere of this radius, centred at the origin.
    Sphere(f64),
    /// A cylinder of this radius along the y axis (axis through the origin), over
    /// `0 ≤ y ≤ thickness`.
    Cylinder { radius: f64, thickness: f64 },
}

/// The part of a sphere or cylinder around its lowest point `(0, 0, −R)` that a contact there
/// needs: a shell sector between radii `R − depth` and `R`, over the surface patch that reaches
/// `half_width` to each side of the lowest point, meshed with hex8 in radial layers under an
/// equiangular surface grid (node spacing ≈ `spacing` on the surface, a node at the lowest
/// point and node planes on x = 0 and y = 0 for symmetry cuts).
///
/// Radial layers matter: a mesh of vertical columns under the same surface (tried first) gave
/// a contact pressure 2.5 points of MRE worse than the whole sphere at the same spacing, while
/// this sector matches the whole sphere (measured, docs/VALIDATION.md).
///
/// Sets: element set `cap`; node sets `surface` (the outer, contact surface), `top` (the inner
/// surface, where a load can be applied), and for the cylinder `ymin`, `ymax`.
pub fn cap(shape: CapShape, half_width: f64, depth: f64, spacing: f64) -> Mesh {
    let radius = match shape {
        CapShape::Sphere(r) | CapShape::Cylinder { radius: r, .. } => r,
    };
    let half_angle = (half_width / radius).clamp(-1.0, 1.0).asin();
    // Even counts put node planes at x = 0 and y = 0.
    let n = 2 * divisions(radius * half_angle, spacing, 1);
    let nr = divisions(depth, spacing, 1);
    let inner = radius - depth;
    let mut b = HexBuilder::new(radius);
    match shape {
        CapShape::Sphere(_) => {
            b.block(n, n, nr, |i, j, k| {
                let u = half_angle * (-1.0 + 2.0 * i as f64 / n as f64);
                let v = half_angle * (-1.0 + 2.0 * j as f64 / n as f64);
                let dir = Vec3::new(u.tan(), v.tan(), -1.0).normalize();
                dir * (radius - depth * k as f64 / nr as f64)
            });
        }
        CapShape::Cylinder { thickness, .. } => {
            let ny = divisions(thickness, spacing, 1);
            b.block(n, ny, nr, |i, j, k| {
                let u = half_angle * (-1.0 + 2.0 * i as f64 / n as f64);
                let r = radius - depth * k as f64 / nr as f64;
                Vec3::new(r * u.sin(), thickness * j as f64 / ny as f64, -r * u.cos())
            });
        }
    }
    let tol = 1e-9 * radius;
    let dist = |p: Vec3| match shape {
        CapShape::Sphere(_) => p.norm(),
        CapShape::Cylinder { .. } => (p.x * p.x + p.z * p.z).sqrt(),
    };
    b.node_set("surface", |p| (dist(p) - radius).abs() < tol);
    b.node_set("top", |p| (dist(p) - inner).abs() < tol);
    if let CapShape::Cylinder { thickness, .. } = shape {
        b.node_set("ymin", |p| p.y.abs() < tol);
        b.node_set("ymax", |p| (p.y - thickness).abs() < tol);
    }
    b.finish("cap")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::case::discretize::discretize;
    use pdcontact_importers::boundary_faces;

    #[test]
    fn sphere_is_closed_and_close_to_its_volume() {
        let m = sphere(1.0, 0.2);
        let d = discretize(&m, None).expect("valid");
        let exact = 4.0 / 3.0 * std::f64::consts::PI;
        // A faceted sphere at this coarse spacing is a little smaller than the true one.
        assert!(
            (d.mesh_volume - exact).abs() / exact < 0.02,
            "{}",
            d.mesh_volume
        );
        assert!((d.total_volume() - d.mesh_volume).abs() < 1e-9);
        // Every boundary face lies on the sphere.
        let faces = boundary_faces(&m);
        for f in &faces.boundary {
            for &n in f.corners() {
                assert!((Vec3::from(m.coords[n as usize]).norm() - 1.0).abs() < 1e-9);
            }
        }
        let on_surface = m
            .set("surface")
            .and_then(|s| s.nodes.as_ref())
            .map_or(0, Vec::len);
        let mut face_nodes: Vec<u32> = faces.boundary.iter().flat_map(|f| f.nodes).collect();
        face_nodes.sort_unstable();
        face_nodes.dedup();
        assert_eq!(face_nodes.len(), on_surface);
        // The south pole is a node.
        assert!(m
            .coords
            .iter()
            .any(|p| (Vec3::from(*p) - Vec3::new(0.0, 0.0, -1.0)).norm() < 1e-12));
    }

    #[test]
    fn cap_volume_and_surface() {
        // A spherical shell sector: the volume between radii R − d and R under the patch.
        let (r, d) = (1.0f64, 0.3f64);
        let m = cap(CapShape::Sphere(r), 0.4, d, 0.02);
        let v = discretize(&m, None).expect("valid cap").mesh_volume;
        // Solid angle of the patch (|u|, |v| ≤ α in the equiangular map) times (R³ − (R−d)³)/3.
        let alpha = 0.4f64.asin();
        let t = alpha.tan();
        let solid_angle = 4.0 * (t * t / (1.0 + t * t)).asin();
        let exact = solid_angle * (r.powi(3) - (r - d).powi(3)) / 3.0;
        // Flat-faced elements under a curved surface: within O(Δ²).
        assert!((v / exact - 1.0).abs() < 2e-3, "{v} vs {exact}");
        let surface = m
            .set("surface")
            .and_then(|s| s.nodes.as_ref())
            .expect("surface set");
        for &n in surface {
            assert!((Vec3::from(m.coords[n as usize]).norm() - 1.0).abs() < 1e-12);
        }
        assert!(m
            .coords
            .iter()
            .any(|p| (Vec3::from(*p) - Vec3::new(0.0, 0.0, -1.0)).norm() < 1e-12));
        // A cylinder sector: thickness × (R² − (R−d)²) α_total / 2.
        let c = cap(
            CapShape::Cylinder {
                radius: 1.0,
                thickness: 0.1,
            },
            0.4,
            d,
            0.02,
        );
        let v = discretize(&c, None).expect("valid").mesh_volume;
        let exact = 0.1 * (1.0 - 0.49) * alpha;
        assert!((v / exact - 1.0).abs() < 2e-3, "{v} vs {exact}");
    }

    #[test]
    fn cylinder_and_box_volumes() {
        let c = cylinder(1.0, 2.0, 0.25);
        let v = discretize(&c, None).expect("valid").mesh_volume;
        let exact = std::f64::consts::PI * 2.0;
        assert!((v - exact).abs() / exact < 0.02, "{v}");
        let b = cuboid([0.0; 3], [1.0, 2.0, 0.5], 0.1);
        let d = discretize(&b, None).expect("valid");
        assert!((d.mesh_volume - 1.0).abs() < 1e-12);
        assert_eq!(d.len(), 11 * 21 * 6);
        assert!((d.spacing - 0.1).abs() < 1e-12);
    }
}
