//! The surface layer's volume per area: each smooth surface particle carries the volume of the
//! layer under its tributary area (METHOD.md §1's lumped volumes, evened on the surface).
//!
//! Lumped volumes (`V_i = Σ V_e / n_corners`, [`super::discretize`]) give a surface node the
//! share of its elements' volume, which follows the elements around it rather than the area of
//! surface it stands for. On a lattice, or radial layers, the two agree: every node of a face
//! holds half a cell under its quarter of the face's area. On an irregular surface they do not:
//! on tets split into hexes, three to six quadrilaterals meet at a node, and the volume per
//! tributary area (the thickness of the layer the node stands for) scatters by half its median.
//! A particle's bonds, and so the stiffness behind each square metre of its surface, scale with
//! its volume (Eq. 4, `V_i V_j`), and the penalty's pressure (Eq. 23) follows it: on a refined
//! sphere of hexes from tets the file's nodes carried 0.15 p0 above Hertz's (docs/VALIDATION.md,
//! "The surface layer's volume per area").
//!
//! [`even_surface_layer`] sets each smooth surface node's volume to its tributary area times
//! the thickness `ΣV/ΣA` over it and its ring of surface neighbours, and gives the difference to
//! (or takes it from) the interior nodes of its elements, in equal parts, so that the body's
//! volume is unchanged. A node on an edge or a corner, or one of its neighbours, keeps its
//! lumped volume: there the share of volume follows the solid angle (a lattice corner holds an
//! eighth of a cell under three quarters of a face's area) and is right as it is. Faces on
//! symmetry planes are cuts, not surface: they are left out before (`surface`), and a node on
//! a plane is evened over the faces of its half.

use pdcontact_importers::{BoundaryFace, Mesh};

use crate::case::segments::quad_area_normal;
use crate::math::Vec3;

/// Which volume a surface particle carries.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SurfaceVolume {
    /// Its tributary area times the thickness of the surface layer around it, on smooth
    /// surfaces away from edges ([`even_surface_layer`]).
    #[default]
    PerArea,
    /// The lumped share of its elements' volume, as for any node (METHOD.md §1).
    Lumped,
}

/// Surface faces whose normals around a node differ by more than this make it an edge or a
/// corner: a lattice's are 90° apart, a gmsh sphere of 10 elements per radius ≤ 15°.
const SMOOTH_ANGLE_DEG: f64 = 30.0;

/// Rings of surface neighbours whose layer thickness a node takes: the nodes of its own
/// faces. Two rings even the refined hexes from tets a little more (2.12 % against 2.58 %)
/// but reach past the curvature of a small contact (the demo's body meshed in tets:
/// 2.85 % against 1.94 %, lumped 1.88 %; docs/VALIDATION.md).
const RINGS: usize = 1;

/// No interior node gives away more than this share of its volume, so that no volume falls
/// to zero however thin a surface node's elements are.
const MAX_TAKEN: f64 = 0.5;

/// Evens the volume per area of the smooth surface nodes (module doc). `volume` holds one
/// entry per mesh node (lumped volumes; zero for a node that is not a solid's corner);
/// `surface` is the body's boundary with the faces on symmetry planes removed, and `boundary`
/// every face of the mesh's boundary (a node on any of them gives no volume). Returns how many
/// nodes changed.
pub fn even_surface_layer(
    mesh: &Mesh,
    volume: &mut [f64],
    surface: &[BoundaryFace],
    boundary: &[BoundaryFace],
) -> usize {
    let n = mesh.node_count();
    let p = |node: u32| Vec3::from(mesh.coords[node as usize]);
    let mut area = vec![0.0f64; n];
    let mut normals: Vec<Vec<Vec3>> = vec![Vec::new(); n];
    let mut ring: Vec<Vec<u32>> = vec![Vec::new(); n];
    for f in surface {
        let c = f.corners();
        // The master segments' area and normal (Eq. 18's diagonals; a triangle as `[a, b, c, c]`).
        let (a, normal) = quad_area_normal(f.nodes.map(p));
        if a <= 0.0 {
            continue;
        }
        for &node in c {
            let i = node as usize;
            area[i] += a / c.len() as f64;
            normals[i].push(normal);
            for &other in c {
                if other != node && !ring[i].contains(&other) {
                    ring[i].push(other);
                }
            }
        }
    }
    let cos_limit = SMOOTH_ANGLE_DEG.to_radians().cos();
    let smooth: Vec<bool> = normals
        .iter()
        .map(|ns| ns.iter().all(|a| ns.iter().all(|b| a.dot(b) >= cos_limit)))
        .collect();

    let mut on_boundary = vec![false; n];
    for f in boundary {
        for &node in f.corners() {
            on_boundary[node as usize] = true;
        }
    }
    // The interior corner nodes of the elements around each surface node.
    let mut inner: Vec<Vec<u32>> = vec![Vec::new(); n];
    for e in mesh.solids() {
        let corners = e.corners();
        for &a in corners {
            if area[a as usize] > 0.0 {
                for &b in corners {
                    if !on_boundary[b as usize] && !inner[a as usize].contains(&b) {
                        inner[a as usize].push(b);
                    }
                }
            }
        }
    }

    let lumped = volume.to_vec();
    let mut changed = 0;
    let mut near = Vec::new();
    let mut front = Vec::new();
    let mut next = Vec::new();
    for i in 0..n {
        if area[i] <= 0.0 || lumped[i] <= 0.0 || inner[i].is_empty() || !smooth[i] {
            continue;
        }
        near.clear();
        near.push(i as u32);
        front.clear();
        front.push(i as u32);
        for _ in 0..RINGS {
            next.clear();
            for &a in &front {
                for &b in &ring[a as usize] {
                    if !near.contains(&b) {
                        near.push(b);
                        next.push(b);
                    }
                }
            }
            std::mem::swap(&mut front, &mut next);
        }
        if near.iter().any(|&j| !smooth[j as usize]) {
            continue;
        }
        let (sum_v, sum_a) = near.iter().fold((0.0, 0.0), |(v, a), &j| {
            (v + lumped[j as usize], a + area[j as usize])
        });
        let excess = lumped[i] - area[i] * sum_v / sum_a;
        if excess == 0.0 {
            continue;
        }
        let share = excess / inner[i].len() as f64;
        // Where the interior nodes give volume, none gives more than MAX_TAKEN of its own.
        let scale = if share < 0.0 {
            inner[i]
                .iter()
                .map(|&b| MAX_TAKEN * volume[b as usize] / -share)
                .fold(1.0f64, f64::min)
        } else {
            1.0
        };
        volume[i] -= scale * excess;
        for &b in &inner[i] {
            volume[b as usize] += scale * share;
        }
        changed += 1;
    }
    changed
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::case::generators;
    use pdcontact_importers::boundary_faces;

    /// A block of `nx × ny × nz` hex8 cells of side `h` ([`generators::cuboid`]), its nodes
    /// displaced by `jitter(i, j, k)`; with the mesh node at each grid point
    /// `i + (nx + 1) (j + (ny + 1) k)`.
    fn block(
        n: [usize; 3],
        h: f64,
        jitter: impl Fn(usize, usize, usize) -> [f64; 3],
    ) -> (Mesh, Vec<u32>) {
        let mut mesh = generators::cuboid([0.0; 3], n.map(|c| c as f64 * h), h);
        let mut grid = vec![u32::MAX; (n[0] + 1) * (n[1] + 1) * (n[2] + 1)];
        for (node, xyz) in mesh.coords.iter_mut().enumerate() {
            let [i, j, k] = xyz.map(|x| (x / h).round() as usize);
            grid[i + (n[0] + 1) * (j + (n[1] + 1) * k)] = node as u32;
            let d = jitter(i, j, k);
            for (x, dx) in xyz.iter_mut().zip(d) {
                *x += dx;
            }
        }
        assert!(!grid.contains(&u32::MAX));
        (mesh, grid)
    }

    fn tributary_areas(mesh: &Mesh, faces: &[BoundaryFace]) -> Vec<f64> {
        let mut area = vec![0.0; mesh.node_count()];
        for f in faces {
            let c = f.corners();
            let p = |k: usize| Vec3::from(mesh.coords[c[k] as usize]);
            let a = 0.5 * (p(2) - p(0)).cross(&(p(3) - p(1))).norm();
            for &node in c {
                area[node as usize] += a / 4.0;
            }
        }
        area
    }

    fn lumped(mesh: &Mesh) -> Vec<f64> {
        let d = super::super::discretize::discretize(mesh, None).unwrap();
        let mut v = vec![0.0; mesh.node_count()];
        for (p, &node) in d.node.iter().enumerate() {
            v[node as usize] = d.volume[p];
        }
        v
    }

    #[test]
    fn a_lattice_keeps_its_lumped_volumes() {
        let (mesh, _) = block([8, 8, 8], 0.1, |_, _, _| [0.0; 3]);
        let faces = boundary_faces(&mesh).boundary;
        let before = lumped(&mesh);
        let mut v = before.clone();
        even_surface_layer(&mesh, &mut v, &faces, &faces);
        for (a, b) in before.iter().zip(&v) {
            assert!((a - b).abs() <= 1e-15, "{a} -> {b}");
        }
    }

    #[test]
    fn an_irregular_top_face_is_evened_and_the_volume_kept() {
        // The top face's nodes moved sideways by up to a third of a cell, the face kept flat:
        // a node's lumped volume then follows the cells under it (a hex's volume is about the
        // mean of its top and bottom faces' areas times its height), not its own area.
        let n = [10, 10, 4];
        let h = 0.1;
        let (mesh, grid) = block(n, h, |i, j, k| {
            let top = k == n[2] && (1..n[0]).contains(&i) && (1..n[1]).contains(&j);
            let s = |m: usize| [-1.0, 0.0, 1.0][m % 3] * h / 3.0;
            if top {
                [s(i * 7 + j * 3), s(i * 5 + j), 0.0]
            } else {
                [0.0; 3]
            }
        });
        let faces = boundary_faces(&mesh).boundary;
        let before = lumped(&mesh);
        let mut v = before.clone();
        let changed = even_surface_layer(&mesh, &mut v, &faces, &faces);
        assert!(changed > 0);
        let total: f64 = before.iter().sum();
        let after: f64 = v.iter().sum();
        assert!((total - after).abs() <= 1e-12 * total, "{total} -> {after}");
        assert!(v.iter().all(|&x| x >= 0.0));
        // Nodes three rings inside the top face's edges: the spread of their thickness V/A.
        let faces_area = tributary_areas(&mesh, &faces);
        let top = |i: usize, j: usize| grid[i + (n[0] + 1) * (j + (n[1] + 1) * n[2])] as usize;
        let spread = |vol: &[f64]| {
            let t: Vec<f64> = (3..n[0] - 2)
                .flat_map(|i| (3..n[1] - 2).map(move |j| (i, j)))
                .map(|(i, j)| vol[top(i, j)] / faces_area[top(i, j)])
                .collect();
            let mean = t.iter().sum::<f64>() / t.len() as f64;
            (t.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / t.len() as f64).sqrt() / mean
        };
        let (s0, s1) = (spread(&before), spread(&v));
        assert!(s0 > 0.1, "the jitter scatters the lumped thickness: {s0}");
        assert!(s1 < 0.3 * s0, "evened: {s0} -> {s1}");
    }
}
