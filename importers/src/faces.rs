//! Boundary faces: element faces used by exactly one 3D element (METHOD.md §4, FORMATS.md §4.5).
//!
//! Faces are keyed by their sorted corner nodes, so a face shared by two elements is found
//! whatever order each element lists it in. Each face's winding is set from geometry, not from
//! a copied table (the ANSYS, Gmsh and Abaqus tables disagree on orientation, FORMATS.md §0):
//! the face normal (Newell's method) is made to point from the element's centroid toward the
//! face's centroid. This also holds for elements whose corner order is mirrored.

use crate::mesh::{ElementKind, Mesh, MISSING_NODE};

/// Which corners of each solid form its faces, in cyclic order.
///
/// For an element in the documented corner convention (see [`crate::mesh`]) every face is wound
/// outward (FORMATS.md §4 "outward" column). Boundary faces do not rely on this: their winding is
/// fixed by geometry. Element volumes do: a mirrored element gets a negative volume.
pub fn face_corners(kind: ElementKind) -> &'static [&'static [usize]] {
    match kind.linear() {
        ElementKind::Hex8 => &[
            &[0, 3, 2, 1],
            &[4, 5, 6, 7],
            &[0, 1, 5, 4],
            &[1, 2, 6, 5],
            &[2, 3, 7, 6],
            &[0, 4, 7, 3],
        ],
        ElementKind::Tet4 => &[&[0, 2, 1], &[0, 1, 3], &[1, 2, 3], &[0, 3, 2]],
        ElementKind::Wedge6 => &[
            &[0, 2, 1],
            &[3, 4, 5],
            &[0, 1, 4, 3],
            &[1, 2, 5, 4],
            &[2, 0, 3, 5],
        ],
        ElementKind::Pyramid5 => &[
            &[0, 1, 4],
            &[3, 0, 4],
            &[1, 2, 4],
            &[2, 3, 4],
            &[0, 3, 2, 1],
        ],
        _ => &[],
    }
}

/// A face on the boundary of the mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BoundaryFace {
    /// Corner nodes (dense indices) wound so that the right-hand normal points out of the body.
    /// A triangle is stored as a degenerate quad with its third node repeated: `[a, b, c, c]`.
    pub nodes: [u32; 4],
    /// The element that owns the face.
    pub element: u32,
}

impl BoundaryFace {
    /// True for a triangle (stored as `[a, b, c, c]`).
    pub fn is_triangle(&self) -> bool {
        self.nodes[3] == self.nodes[2]
    }

    /// The distinct corners: 3 for a triangle, 4 for a quad.
    pub fn corners(&self) -> &[u32] {
        if self.is_triangle() {
            &self.nodes[..3]
        } else {
            &self.nodes[..]
        }
    }
}

/// The result of face extraction.
#[derive(Clone, Debug, Default)]
pub struct FaceSet {
    /// Faces used by exactly one solid, ordered by owning element then local face.
    pub boundary: Vec<BoundaryFace>,
    /// Faces shared by three or more solids (a non-manifold mesh); they are not boundary faces.
    pub non_manifold: usize,
}

/// Finds the boundary faces of the mesh's 3D elements.
///
/// Faces are collected with their sorted-corner keys and sorted, so that the cost is
/// O(F log F) with no hashing and the result does not depend on hash order.
pub fn boundary_faces(mesh: &Mesh) -> FaceSet {
    struct Entry {
        key: [u32; 4],
        element: u32,
        local: u8,
    }
    let mut entries: Vec<Entry> = Vec::new();
    for e in mesh.solids() {
        let corners = e.corners();
        if corners.contains(&MISSING_NODE) {
            continue;
        }
        for (local, face) in face_corners(e.kind).iter().enumerate() {
            let mut key = [u32::MAX; 4];
            for (k, &c) in face.iter().enumerate() {
                key[k] = corners[c];
            }
            key.sort_unstable();
            entries.push(Entry {
                key,
                element: e.index,
                local: local as u8,
            });
        }
    }
    entries.sort_unstable_by_key(|e| e.key);

    let mut owners: Vec<(u32, u8)> = Vec::new();
    let mut non_manifold = 0;
    let mut i = 0;
    while i < entries.len() {
        let mut j = i + 1;
        while j < entries.len() && entries[j].key == entries[i].key {
            j += 1;
        }
        match j - i {
            1 => owners.push((entries[i].element, entries[i].local)),
            2 => {}
            _ => non_manifold += 1,
        }
        i = j;
    }
    drop(entries);
    owners.sort_unstable();

    let boundary = owners
        .into_iter()
        .map(|(element, local)| oriented_face(mesh, element, local as usize))
        .collect();
    FaceSet {
        boundary,
        non_manifold,
    }
}

/// Builds face `local` of `element`, wound outward.
fn oriented_face(mesh: &Mesh, element: u32, local: usize) -> BoundaryFace {
    let e = mesh.element(element as usize);
    let corners = e.corners();
    let face = face_corners(e.kind)[local];
    let mut nodes = [0u32; 4];
    for (k, &c) in face.iter().enumerate() {
        nodes[k] = corners[c];
    }
    if face.len() == 3 {
        nodes[3] = nodes[2];
    }
    let p = |n: u32| mesh.coords[n as usize];
    let centroid = |ns: &[u32]| {
        let mut c = [0.0; 3];
        for &n in ns {
            for (ck, pk) in c.iter_mut().zip(p(n)) {
                *ck += pk;
            }
        }
        c.map(|v| v / ns.len() as f64)
    };
    let fc = centroid(&nodes[..face.len()]);
    let ec = centroid(corners);
    let normal = newell_normal(
        &nodes[..face.len()]
            .iter()
            .map(|&n| p(n))
            .collect::<Vec<_>>(),
    );
    let outward = (0..3).map(|k| normal[k] * (fc[k] - ec[k])).sum::<f64>();
    if outward < 0.0 {
        // Reverse the winding, keeping the first node first.
        nodes[1..face.len()].reverse();
        if face.len() == 3 {
            nodes[3] = nodes[2];
        }
    }
    BoundaryFace { nodes, element }
}

/// Newell's polygon normal (not normalised); robust for warped quads.
pub fn newell_normal(points: &[[f64; 3]]) -> [f64; 3] {
    let mut n = [0.0; 3];
    for i in 0..points.len() {
        let a = points[i];
        let b = points[(i + 1) % points.len()];
        n[0] += (a[1] - b[1]) * (a[2] + b[2]);
        n[1] += (a[2] - b[2]) * (a[0] + b[0]);
        n[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_hex(m: &mut Mesh, origin: [f64; 3], ids: [u32; 8]) {
        let _ = origin;
        m.push_element(m.element_count() as u64 + 1, ElementKind::Hex8, &ids);
    }

    fn grid_2x1x1() -> Mesh {
        let mut m = Mesh::new();
        let mut id = 1;
        for k in 0..2 {
            for j in 0..2 {
                for i in 0..3 {
                    m.push_node(id, [i as f64, j as f64, k as f64]);
                    id += 1;
                }
            }
        }
        let n = |i: u32, j: u32, k: u32| i + 3 * j + 6 * k;
        for i in 0..2 {
            unit_hex(
                &mut m,
                [0.0; 3],
                [
                    n(i, 0, 0),
                    n(i + 1, 0, 0),
                    n(i + 1, 1, 0),
                    n(i, 1, 0),
                    n(i, 0, 1),
                    n(i + 1, 0, 1),
                    n(i + 1, 1, 1),
                    n(i, 1, 1),
                ],
            );
        }
        m
    }

    #[test]
    fn two_hexes_share_one_face() {
        let m = grid_2x1x1();
        let f = boundary_faces(&m);
        assert_eq!(f.boundary.len(), 10);
        assert_eq!(f.non_manifold, 0);
        // Every face points away from the body's centre (1, 0.5, 0.5).
        for face in &f.boundary {
            let pts: Vec<_> = face
                .corners()
                .iter()
                .map(|&n| m.coords[n as usize])
                .collect();
            let nrm = newell_normal(&pts);
            let c: Vec<f64> = (0..3)
                .map(|k| pts.iter().map(|p| p[k]).sum::<f64>() / 4.0)
                .collect();
            let d = [c[0] - 1.0, c[1] - 0.5, c[2] - 0.5];
            assert!(
                nrm[0] * d[0] + nrm[1] * d[1] + nrm[2] * d[2] > 0.0,
                "{face:?}"
            );
        }
    }

    #[test]
    fn mirrored_tet_still_outward() {
        let mut m = Mesh::new();
        for (i, p) in [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ]
        .iter()
        .enumerate()
        {
            m.push_node(i as u64 + 1, *p);
        }
        // Inverted corner order: 0-2-1 winds toward -z, apex at +z.
        m.push_element(1, ElementKind::Tet4, &[0, 2, 1, 3]);
        let f = boundary_faces(&m);
        assert_eq!(f.boundary.len(), 4);
        let centre = [0.25, 0.25, 0.25];
        for face in &f.boundary {
            assert!(face.is_triangle());
            let pts: Vec<_> = face
                .corners()
                .iter()
                .map(|&n| m.coords[n as usize])
                .collect();
            let nrm = newell_normal(&pts);
            let c: Vec<f64> = (0..3)
                .map(|k| pts.iter().map(|p| p[k]).sum::<f64>() / 3.0)
                .collect();
            let d: f64 = (0..3).map(|k| nrm[k] * (c[k] - centre[k])).sum();
            assert!(d > 0.0);
        }
    }
}
