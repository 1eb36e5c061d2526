//! Discretisation: one particle per corner node of the mesh's 3D elements (METHOD.md §1).
//!
//! A node's volume is the sum, over the solids that use it, of the solid's exact volume divided
//! by its corner count (hex8: 1/8 each). Second-order elements contribute their corners only.
//! Element volumes are exact for the trilinear/bilinear shapes (see [`element_volume`]).
//! The grid spacing Δ is the scene's, a generator's cell size (its median edge), or, for an
//! imported mesh, the spacing of a lattice with the particles' median volume ([`lattice_spacing`]).
//!
//! Particles are stored in Morton (Z-curve) order of their position, so that particles close in
//! space are close in memory: the bond loop then reads partner data from cache.

use pdcontact_importers::{face_corners, ElementKind, ElementRef, Mesh, MISSING_NODE};

use crate::error::{Error, Result};
use crate::math::{Vec3, NOT_A_PARTICLE};

/// The particles of one body in their reference configuration.
#[derive(Clone, Debug, Default)]
pub struct Discretization {
    /// Reference positions `x_i`.
    pub position: Vec<Vec3>,
    /// Lumped nodal volumes `V_i`.
    pub volume: Vec<f64>,
    /// Mesh node index of each particle.
    pub node: Vec<u32>,
    /// Particle index of each mesh node, or [`NOT_A_PARTICLE`].
    pub particle_of_node: Vec<u32>,
    /// Grid spacing Δ.
    pub spacing: f64,
    /// Sum of the exact element volumes.
    pub mesh_volume: f64,
    /// Fraction of the full solid angle around each particle that lies inside the body:
    /// 1 inside, ½ on a smooth surface or flat face, ¼ on a right-angled edge, ⅛ at a corner.
    pub solid_fraction: Vec<f64>,
}

impl Discretization {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.position.len()
    }

    /// True when there are no particles.
    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    /// Total particle volume.
    pub fn total_volume(&self) -> f64 {
        self.volume.iter().sum()
    }

    /// Each particle's volume as if the body continued beyond its surface: `V_i / ω_i`, with
    /// `ω_i` the [`solid_fraction`](Self::solid_fraction). A node on a flat face of a hex mesh
    /// holds half a cell of lumped volume; completed, it holds a whole cell, as a lattice
    /// particle does. The eigenvalue detector sums over these volumes, so that a particle one
    /// spacing below a flat face sees the lattice value λ ≈ 0.91 rather than the 0.71 that the
    /// halved volumes of the face give (which would fall under the 0.75 threshold).
    pub fn completed_volume(&self) -> Vec<f64> {
        self.volume
            .iter()
            .zip(&self.solid_fraction)
            .map(|(&v, &w)| if w > 0.0 { v / w } else { v })
            .collect()
    }
}

/// Turns a mesh into particles. `spacing` overrides the default (the lattice spacing of the
/// particles' median volume).
///
/// Errors: a mesh without 3D elements, an element with zero or negative volume (named by its
/// id), or a non-positive spacing.
pub fn discretize(mesh: &Mesh, spacing: Option<f64>) -> Result<Discretization> {
    let solids: Vec<ElementRef<'_>> = mesh.solids().collect();
    if solids.is_empty() {
        // The MSH reader's warning says why, where it knows (gmsh's physical groups).
        let why = mesh
            .warnings
            .iter()
            .filter(|w| w.starts_with("no 3D solid elements ("))
            .find_map(|w| w.split_once("): "))
            .map_or(String::new(), |(_, why)| format!(": {why}"));
        return Err(Error::input(format!(
            "the mesh has no 3D solid elements: nothing to turn into particles{why}"
        )));
    }
    let mut node_volume = vec![0.0f64; mesh.node_count()];
    let mut node_angle = vec![0.0f64; mesh.node_count()];
    let mut is_corner = vec![false; mesh.node_count()];
    let mut mesh_volume = 0.0;
    for e in &solids {
        let corners = e.corners();
        if corners.contains(&MISSING_NODE) {
            return Err(Error::input(format!(
                "element {} lacks a corner node",
                e.id
            )));
        }
        let v = element_volume(e.kind, corners, &mesh.coords);
        let scale = max_edge(e.kind, corners, &mesh.coords).powi(3);
        if v.is_nan() || v <= 1e-10 * scale {
            // How many more: every element inverted is a node order of the other handedness,
            // not a bad element.
            let inverted = solids
                .iter()
                .filter(|e| {
                    let c = e.corners();
                    !c.contains(&MISSING_NODE)
                        && element_volume(e.kind, c, &mesh.coords)
                            < -1e-10 * max_edge(e.kind, c, &mesh.coords).powi(3)
                })
                .count();
            let first = format!(
                "element {} ({}) has {} volume {:.3e}",
                e.id,
                e.kind.name(),
                if v.abs() <= 1e-10 * scale {
                    "zero"
                } else {
                    "negative"
                },
                v
            );
            return Err(Error::input(
                if inverted == solids.len() && solids.len() > 1 {
                    format!(
                    "{first}, as do all {} solid elements: their node order is mirrored against the format's (the other handedness, as some tools write it); renumber each element's nodes in the format's order (docs/guide/mesh-files.md) or mirror the mesh",
                    solids.len()
                )
                } else if inverted > 1 {
                    format!(
                    "{first}: it is inverted or degenerate ({inverted} of the {} solid elements have a negative volume)",
                    solids.len()
                )
                } else {
                    format!("{first}: it is inverted or degenerate")
                },
            ));
        }
        mesh_volume += v;
        let share = v / corners.len() as f64;
        for (local, &n) in corners.iter().enumerate() {
            node_volume[n as usize] += share;
            node_angle[n as usize] += corner_solid_angle(e.kind, corners, &mesh.coords, local);
            is_corner[n as usize] = true;
        }
    }
    let spacing = match spacing {
        Some(d) if d > 0.0 && d.is_finite() => d,
        Some(d) => {
            return Err(Error::input(format!(
                "grid spacing must be positive, got {d}"
            )))
        }
        None => lattice_spacing(&node_volume, &node_angle, &is_corner),
    };

    let mut nodes: Vec<u32> = (0..mesh.node_count() as u32)
        .filter(|&n| is_corner[n as usize])
        .collect();
    sort_morton(&mut nodes, &mesh.coords, spacing);

    let mut particle_of_node = vec![NOT_A_PARTICLE; mesh.node_count()];
    for (p, &n) in nodes.iter().enumerate() {
        particle_of_node[n as usize] = p as u32;
    }
    Ok(Discretization {
        position: nodes
            .iter()
            .map(|&n| Vec3::from(mesh.coords[n as usize]))
            .collect(),
        volume: nodes.iter().map(|&n| node_volume[n as usize]).collect(),
        solid_fraction: nodes
            .iter()
            .map(|&n| (node_angle[n as usize] / (4.0 * std::f64::consts::PI)).min(1.0))
            .collect(),
        node: nodes,
        particle_of_node,
        spacing,
        mesh_volume,
    })
}

/// Exact signed volume of a linear solid (corner nodes only), by the divergence theorem:
/// `V = ⅓ Σ_faces ∫ (x − c)·n dA`. Quad faces are bilinear surfaces, whose integrand is
/// biquadratic in the face coordinates, so 2×2 Gauss points integrate it exactly; triangles are
/// planar. The bilinear faces bound exactly the trilinear hex (and the wedge and pyramid maps),
/// so the result is the element's true volume, also for warped faces. Negative when the corner
/// order is mirrored.
pub fn element_volume(kind: ElementKind, corners: &[u32], coords: &[[f64; 3]]) -> f64 {
    let p = |i: usize| Vec3::from(coords[corners[i] as usize]);
    let n = corners.len();
    let centre = (0..n).map(p).sum::<Vec3>() / n as f64;
    let rel = |i: usize| p(i) - centre;
    let g = 1.0 / 3f64.sqrt();
    let mut flux = 0.0;
    for face in face_corners(kind) {
        match face.len() {
            3 => {
                let (a, b, c) = (rel(face[0]), rel(face[1]), rel(face[2]));
                flux += ((a + b + c) / 3.0).dot(&((b - a).cross(&(c - a)) * 0.5));
            }
            4 => {
                let x = [rel(face[0]), rel(face[1]), rel(face[2]), rel(face[3])];
                for (u, v) in [(-g, -g), (g, -g), (g, g), (-g, g)] {
                    let pos = (x[0] * ((1.0 - u) * (1.0 - v))
                        + x[1] * ((1.0 + u) * (1.0 - v))
                        + x[2] * ((1.0 + u) * (1.0 + v))
                        + x[3] * ((1.0 - u) * (1.0 + v)))
                        * 0.25;
                    let du = (-x[0] * (1.0 - v) + x[1] * (1.0 - v) + x[2] * (1.0 + v)
                        - x[3] * (1.0 + v))
                        * 0.25;
                    let dv = (-x[0] * (1.0 - u) - x[1] * (1.0 + u)
                        + x[2] * (1.0 + u)
                        + x[3] * (1.0 - u))
                        * 0.25;
                    flux += pos.dot(&du.cross(&dv));
                }
            }
            _ => {}
        }
    }
    flux / 3.0
}

/// Solid angle of an element at one of its corners: the cone spanned by the edges that meet
/// there (Van Oosterom & Strackee's formula per triangle of edge directions). Exact for planar
/// faces; summed over the elements around an interior node it gives 4π.
pub fn corner_solid_angle(
    kind: ElementKind,
    corners: &[u32],
    coords: &[[f64; 3]],
    local: usize,
) -> f64 {
    let p = |i: usize| Vec3::from(coords[corners[i] as usize]);
    // Edge directions from this corner, in cyclic order around it (taken from the faces that
    // contain it, each face contributing the neighbour that follows the corner).
    let mut ring: Vec<usize> = Vec::with_capacity(4);
    let faces = face_corners(kind);
    let mut next_of = Vec::with_capacity(4);
    for f in faces {
        if let Some(pos) = f.iter().position(|&c| c == local) {
            let next = f[(pos + 1) % f.len()];
            let prev = f[(pos + f.len() - 1) % f.len()];
            next_of.push((prev, next));
        }
    }
    if next_of.is_empty() {
        return 0.0;
    }
    // Walk prev → next links: each face around the corner joins two of its edges.
    let mut current = next_of[0].0;
    for _ in 0..next_of.len() {
        ring.push(current);
        match next_of.iter().find(|&&(a, _)| a == current) {
            Some(&(_, b)) => current = b,
            None => break,
        }
    }
    let apex = p(local);
    let dirs: Vec<Vec3> = ring.iter().map(|&c| p(c) - apex).collect();
    let mut omega = 0.0;
    for k in 1..dirs.len().saturating_sub(1) {
        let (a, b, c) = (dirs[0], dirs[k], dirs[k + 1]);
        let (la, lb, lc) = (a.norm(), b.norm(), c.norm());
        let num = a.dot(&b.cross(&c)).abs();
        let den = la * lb * lc + a.dot(&b) * lc + a.dot(&c) * lb + b.dot(&c) * la;
        omega += 2.0 * num.atan2(den);
    }
    omega
}

/// Corner-edge lists of the linear shapes.
pub fn edges(kind: ElementKind) -> &'static [[usize; 2]] {
    match kind.linear() {
        ElementKind::Hex8 => &[
            [0, 1],
            [1, 2],
            [2, 3],
            [3, 0],
            [4, 5],
            [5, 6],
            [6, 7],
            [7, 4],
            [0, 4],
            [1, 5],
            [2, 6],
            [3, 7],
        ],
        ElementKind::Tet4 => &[[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]],
        ElementKind::Wedge6 => &[
            [0, 1],
            [1, 2],
            [2, 0],
            [3, 4],
            [4, 5],
            [5, 3],
            [0, 3],
            [1, 4],
            [2, 5],
        ],
        ElementKind::Pyramid5 => &[
            [0, 1],
            [1, 2],
            [2, 3],
            [3, 0],
            [0, 4],
            [1, 4],
            [2, 4],
            [3, 4],
        ],
        _ => &[],
    }
}

fn edge_length(corners: &[u32], coords: &[[f64; 3]], e: [usize; 2]) -> f64 {
    (Vec3::from(coords[corners[e[0]] as usize]) - Vec3::from(coords[corners[e[1]] as usize])).norm()
}

fn max_edge(kind: ElementKind, corners: &[u32], coords: &[[f64; 3]]) -> f64 {
    edges(kind)
        .iter()
        .map(|&e| edge_length(corners, coords, e))
        .fold(0.0, f64::max)
}

/// The spacing of the lattice whose cell holds the median particle's volume: the median over the
/// corner nodes of `(V_i / ω_i)^⅓`, with `ω_i` the node's solid fraction (a boundary node's
/// lumped volume completed to a whole cell, as [`Discretization::completed_volume`] does).
///
/// The formulas that use Δ (horizon δ = mΔ, volume correction, the detector's kernel width)
/// assume a lattice of spacing Δ, one particle per Δ³. On a hex8 mesh that is about the median
/// edge (gmsh's cubed spheres: 0.080 against 0.083 m); on a tet mesh the edges are longer than
/// the spacing of a lattice with as many particles (gmsh tet4 of size 0.05 m: median edge
/// 0.0646 m, lattice spacing 0.0533 m), and a horizon of m median edges held 1.7 times the bonds
/// and a wider, softer contact than the particle density calls for (docs/VALIDATION.md,
/// "Unstructured meshes").
pub fn lattice_spacing(node_volume: &[f64], node_angle: &[f64], is_corner: &[bool]) -> f64 {
    let mut sides: Vec<f64> = (0..node_volume.len())
        .filter(|&n| is_corner[n])
        .map(|n| {
            let fraction = (node_angle[n] / (4.0 * std::f64::consts::PI)).min(1.0);
            if fraction > 0.0 {
                (node_volume[n] / fraction).cbrt()
            } else {
                node_volume[n].cbrt()
            }
        })
        .collect();
    if sides.is_empty() {
        return 0.0;
    }
    let mid = sides.len() / 2;
    let (_, m, _) = sides.select_nth_unstable_by(mid, f64::total_cmp);
    *m
}

/// Median corner-edge length of a mesh's solids: a generated body's grid spacing.
pub fn mesh_median_edge(mesh: &Mesh) -> f64 {
    let solids: Vec<ElementRef<'_>> = mesh.solids().collect();
    median_edge(&solids, &mesh.coords)
}

/// Median corner-edge length over all solids (each element's edges counted once per element).
pub fn median_edge(solids: &[ElementRef<'_>], coords: &[[f64; 3]]) -> f64 {
    let mut lengths: Vec<f64> = solids
        .iter()
        .flat_map(|e| {
            let c = e.corners();
            edges(e.kind)
                .iter()
                .map(move |&ed| edge_length(c, coords, ed))
        })
        .collect();
    if lengths.is_empty() {
        return 0.0;
    }
    let mid = lengths.len() / 2;
    let (_, m, _) = lengths.select_nth_unstable_by(mid, f64::total_cmp);
    *m
}

/// Sorts node indices by the Morton code of their cell (cell size `spacing`).
pub fn sort_morton(nodes: &mut [u32], coords: &[[f64; 3]], spacing: f64) {
    if nodes.is_empty() {
        return;
    }
    let mut lo = [f64::INFINITY; 3];
    for &n in nodes.iter() {
        for k in 0..3 {
            lo[k] = lo[k].min(coords[n as usize][k]);
        }
    }
    let key = |n: u32| {
        let c = coords[n as usize];
        let mut code = 0u64;
        let cell: [u64; 3] = std::array::from_fn(|k| {
            (((c[k] - lo[k]) / spacing).max(0.0) as u64).min((1 << 21) - 1)
        });
        for bit in 0..21 {
            for (k, &ck) in cell.iter().enumerate() {
                code |= ((ck >> bit) & 1) << (3 * bit + k);
            }
        }
        code
    };
    nodes.sort_by_cached_key(|&n| (key(n), n));
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube_coords() -> Vec<[f64; 3]> {
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [1.0, 1.0, 1.0],
            [0.0, 1.0, 1.0],
        ]
    }

    #[test]
    fn exact_volumes_of_each_shape() {
        let c = cube_coords();
        let hex = element_volume(ElementKind::Hex8, &[0, 1, 2, 3, 4, 5, 6, 7], &c);
        assert!((hex - 1.0).abs() < 1e-14);
        let tet = element_volume(ElementKind::Tet4, &[0, 1, 3, 4], &c);
        assert!((tet - 1.0 / 6.0).abs() < 1e-14);
        let wedge = element_volume(ElementKind::Wedge6, &[0, 1, 3, 4, 5, 7], &c);
        assert!((wedge - 0.5).abs() < 1e-14);
        let pyr = element_volume(ElementKind::Pyramid5, &[0, 1, 2, 3, 4], &c);
        assert!((pyr - 1.0 / 3.0).abs() < 1e-14);
        let mirrored = element_volume(ElementKind::Hex8, &[0, 3, 2, 1, 4, 7, 6, 5], &c);
        assert!((mirrored + 1.0).abs() < 1e-14);
    }

    #[test]
    fn corner_solid_angles() {
        use std::f64::consts::PI;
        let c = cube_coords();
        let hex = [0, 1, 2, 3, 4, 5, 6, 7];
        for local in 0..8 {
            let w = corner_solid_angle(ElementKind::Hex8, &hex, &c, local);
            assert!((w - PI / 2.0).abs() < 1e-12, "{local}: {w}");
        }
        // The apex of a pyramid on a unit square base at height 1/2 sees a sixth of the sphere
        // (six such pyramids fill a cube around its centre).
        let mut pc = c.clone();
        pc.push([0.5, 0.5, 0.5]);
        let w = corner_solid_angle(ElementKind::Pyramid5, &[0, 1, 2, 3, 8], &pc, 4);
        assert!((w - 4.0 * PI / 6.0).abs() < 1e-12, "{w}");
        // Tet corner at the right angle: an eighth of the sphere.
        let w = corner_solid_angle(ElementKind::Tet4, &[0, 1, 3, 4], &c, 0);
        assert!((w - PI / 2.0).abs() < 1e-12, "{w}");
    }

    #[test]
    fn warped_hex_volume_matches_tet_split_average() {
        // Lift one top corner: the top face becomes a hyperbolic paraboloid. The trilinear
        // volume is the mean of the cube and of the full lift's effect: 1 + 0.5/4.
        let mut c = cube_coords();
        c[6][2] = 1.5;
        let v = element_volume(ElementKind::Hex8, &[0, 1, 2, 3, 4, 5, 6, 7], &c);
        assert!((v - 1.125).abs() < 1e-12, "{v}");
    }

    #[test]
    fn inverted_element_is_named() {
        let mut m = Mesh::new();
        for (i, p) in cube_coords().iter().enumerate() {
            m.push_node(i as u64 + 1, *p);
        }
        m.push_element(42, ElementKind::Hex8, &[0, 3, 2, 1, 4, 7, 6, 5]);
        let err = discretize(&m, None).expect_err("inverted");
        assert!(err.to_string().contains("element 42"), "{err}");
        // Every element mirrored: the node order's handedness, said as such.
        let mut shifted = cube_coords();
        for p in cube_coords() {
            shifted.push([p[0] + 1.0, p[1], p[2]]);
        }
        let mut m = Mesh::new();
        for (i, p) in shifted.iter().enumerate() {
            m.push_node(i as u64 + 1, *p);
        }
        m.push_element(1, ElementKind::Hex8, &[0, 3, 2, 1, 4, 7, 6, 5]);
        m.push_element(2, ElementKind::Hex8, &[8, 11, 10, 9, 12, 15, 14, 13]);
        let err = discretize(&m, None).expect_err("mirrored").to_string();
        assert!(
            err.contains("all 2 solid elements") && err.contains("mirrored"),
            "{err}"
        );
    }
}
