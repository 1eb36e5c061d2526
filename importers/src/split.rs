//! Second-order tetrahedra split into first-order ones on all their nodes.
//!
//! A tet10 has the resolution of its ten nodes, not of its four corners: an FE code takes its
//! mid-edge nodes as degrees of freedom, and gmsh places them on the curved geometry. Cut at its
//! mid-edge nodes, a tet10 is eight tet4: one at each corner (the parent scaled by ½ about it)
//! and four around a diagonal of the octahedron left in the middle, the shortest of its three
//! (the usual red refinement of a tetrahedron, the one gmsh's `RefineMesh` makes). No node is
//! added or moved, so node sets, node numbers and the boundary stay the file's own.

use crate::mesh::{ElementKind, Mesh, MISSING_NODE};

/// Mid-edge slot of edge `(a, b)` in the tet10 convention of [`crate::mesh`]:
/// 4..9 on (0,1)(1,2)(2,0)(0,3)(1,3)(2,3).
const EDGES: [(usize, usize); 6] = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)];

/// The three pairs of opposite vertices of the middle octahedron, as tet10 slots: the
/// mid-edges of opposite tet edges ((0,1)-(2,3), (1,2)-(0,3), (2,0)-(1,3)).
const OPPOSITE: [(usize, usize); 3] = [(4, 9), (5, 7), (6, 8)];

/// Signed volume ×6 of the tetrahedron `t` (positive in the convention of [`crate::mesh`]).
fn signed_volume6(coords: &[[f64; 3]], t: [u32; 4]) -> f64 {
    let p = t.map(|n| coords[n as usize]);
    let d = |k: usize| [p[k][0] - p[0][0], p[k][1] - p[0][1], p[k][2] - p[0][2]];
    let (a, b, c) = (d(1), d(2), d(3));
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
}

fn distance2(coords: &[[f64; 3]], a: u32, b: u32) -> f64 {
    let (p, q) = (coords[a as usize], coords[b as usize]);
    (0..3).map(|k| (p[k] - q[k]).powi(2)).sum()
}

/// The eight tet4 of a tet10 with nodes `n` (corners first), each oriented as its parent.
pub fn split_tet10_nodes(coords: &[[f64; 3]], n: &[u32]) -> [[u32; 4]; 8] {
    let m = |a: usize, b: usize| {
        let k = EDGES
            .iter()
            .position(|&e| e == (a, b) || e == (b, a))
            .expect("an edge of the tetrahedron");
        n[4 + k]
    };
    let mut out = [[0u32; 4]; 8];
    // The corners: the parent scaled by ½ about each vertex keeps its orientation.
    out[0] = [n[0], m(0, 1), m(0, 2), m(0, 3)];
    out[1] = [m(0, 1), n[1], m(1, 2), m(1, 3)];
    out[2] = [m(0, 2), m(1, 2), n[2], m(2, 3)];
    out[3] = [m(0, 3), m(1, 3), m(2, 3), n[3]];
    // The octahedron: four tets around its shortest diagonal (p, q); the other four vertices,
    // two opposite pairs (a, a') and (b, b'), make the ring a, b, a', b' around it.
    let (diagonal, _) = OPPOSITE
        .iter()
        .enumerate()
        .map(|(k, &(p, q))| (k, distance2(coords, n[p], n[q])))
        .fold(
            (0, f64::INFINITY),
            |best, c| if c.1 < best.1 { c } else { best },
        );
    let (p, q) = OPPOSITE[diagonal];
    let (a, a2) = OPPOSITE[(diagonal + 1) % 3];
    let (b, b2) = OPPOSITE[(diagonal + 2) % 3];
    let ring = [n[a], n[b], n[a2], n[b2]];
    for k in 0..4 {
        let mut t = [n[p], n[q], ring[k], ring[(k + 1) % 4]];
        if signed_volume6(coords, t) < 0.0 {
            t.swap(2, 3);
        }
        out[4 + k] = t;
    }
    out
}

/// `mesh` with every tet10 whose ten nodes are all given split into eight tet4 on them
/// (a tet10 that lacks a mid-edge node keeps its corners, as before); `None` when it has no
/// such tet10. The children keep their parent's element number; element sets hold the
/// children of their elements.
pub fn split_tet10(mesh: &Mesh) -> Option<Mesh> {
    let splits = |e: usize| {
        mesh.element_kinds[e] == ElementKind::Tet10
            && !mesh.element(e).nodes.contains(&MISSING_NODE)
    };
    if !(0..mesh.element_count()).any(splits) {
        return None;
    }
    let mut out = Mesh {
        node_ids: mesh.node_ids.clone(),
        coords: mesh.coords.clone(),
        warnings: mesh.warnings.clone(),
        ..Mesh::new()
    };
    // New indices of each element's children: first..end.
    let mut first = Vec::with_capacity(mesh.element_count() + 1);
    for e in mesh.elements() {
        first.push(out.element_count() as u32);
        if splits(e.index as usize) {
            for t in split_tet10_nodes(&mesh.coords, e.nodes) {
                out.push_element(e.id, ElementKind::Tet4, &t);
            }
        } else {
            out.push_element(e.id, e.kind, e.nodes);
        }
    }
    first.push(out.element_count() as u32);
    out.sets = mesh
        .sets
        .iter()
        .map(|s| {
            let mut s = s.clone();
            if let Some(el) = &mut s.elements {
                *el = el
                    .iter()
                    .flat_map(|&e| first[e as usize]..first[e as usize + 1])
                    .collect();
            }
            s
        })
        .collect();
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn volume(coords: &[[f64; 3]], t: [u32; 4]) -> f64 {
        signed_volume6(coords, t) / 6.0
    }

    /// A skewed tet10 with its mid-edge nodes at the edges' midpoints.
    fn tet10() -> Mesh {
        let mut m = Mesh::new();
        let corners = [
            [0.1, -0.2, 0.0],
            [1.3, 0.1, 0.2],
            [0.2, 0.9, -0.1],
            [0.4, 0.3, 1.1],
        ];
        for (k, c) in corners.iter().enumerate() {
            m.push_node(k as u64 + 1, *c);
        }
        for (k, &(a, b)) in EDGES.iter().enumerate() {
            let mid = [0, 1, 2].map(|i| 0.5 * (corners[a][i] + corners[b][i]));
            m.push_node(5 + k as u64, mid);
        }
        m.push_element(7, ElementKind::Tet10, &(0..10).collect::<Vec<u32>>());
        m
    }

    #[test]
    fn eight_children_fill_the_parent_each_an_eighth() {
        let m = tet10();
        let parent = volume(&m.coords, [0, 1, 2, 3]);
        assert!(parent > 0.0);
        let split = split_tet10(&m).expect("one tet10");
        assert_eq!(split.element_count(), 8);
        assert_eq!(split.node_count(), 10);
        let mut total = 0.0;
        let mut used = [false; 10];
        for e in split.elements() {
            assert_eq!((e.kind, e.id), (ElementKind::Tet4, 7));
            let t = [e.nodes[0], e.nodes[1], e.nodes[2], e.nodes[3]];
            let v = volume(&split.coords, t);
            // Red refinement of a straight-sided tet: all eight have the same volume.
            assert!(
                (v - parent / 8.0).abs() < 1e-12,
                "{v} against {}",
                parent / 8.0
            );
            total += v;
            t.iter().for_each(|&n| used[n as usize] = true);
        }
        assert!((total - parent).abs() < 1e-12);
        assert!(used.iter().all(|&u| u));
    }

    #[test]
    fn element_sets_follow_their_children_and_tet4_stay() {
        let mut m = tet10();
        m.push_node(11, [0.0, 0.0, -1.0]);
        m.push_element(8, ElementKind::Tet4, &[0, 2, 1, 10]);
        m.sets.push(crate::mesh::NamedSet {
            name: "both".into(),
            kind: crate::mesh::SetKind::ElementSet,
            nodes: None,
            elements: Some(vec![0, 1]),
        });
        let split = split_tet10(&m).expect("one tet10");
        assert_eq!(split.element_count(), 9);
        assert_eq!(split.element(8).id, 8);
        assert_eq!(split.sets[0].elements, Some((0..9).collect()));
    }

    #[test]
    fn a_tet10_without_all_its_nodes_keeps_its_corners() {
        let mut m = tet10();
        let last = m.connectivity.len() - 1;
        m.connectivity[last] = MISSING_NODE;
        assert!(split_tet10(&m).is_none());
    }
}
