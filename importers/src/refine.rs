//! Uniform refinement: every tet and hex cut into eight at the midpoints of its edges.
//!
//! A first-order mesh whose nodes are too few for the contact (a peridynamic horizon of three
//! spacings against a contact radius of five, docs/VALIDATION.md) gets twice the resolution
//! without being meshed again. Each element becomes its second-order counterpart with a node at
//! the midpoint of every edge (a tet4 a tet10, a hex8 a hex20, lines, triangles and
//! quadrilaterals likewise, so that sets given by elements hold the new nodes), and
//! [`crate::split_second_order`] cuts it into eight on those nodes: a hex gets a node at the
//! centre of each face and of the element. New nodes lie on the straight edges, so a curved
//! boundary stays the facets of the file's mesh (a second-order mesh's own mid-edge nodes lie on
//! the geometry: that is `split_second_order` alone).
//!
//! A node added on edge `(a, b)` joins a node set that holds `a` and `b` and a whole face of an
//! element through that edge (so an edge that cuts through the body between two surface nodes
//! does not join the surface's set); in a set that holds no whole face (the nodes of a curve),
//! holding both ends is enough. Wedges and pyramids are not cut, and a mesh that has any is
//! left as it is: cut tets beside a whole wedge would leave faces unmatched, and those faces
//! would become a surface inside the body.

use std::collections::{HashMap, HashSet};

use crate::faces::face_corners;
use crate::mesh::{ElementKind, Mesh, HEX20_EDGES, MISSING_NODE, TET10_EDGES};
use crate::split::split_second_order;

/// Why [`refine_uniform`] left a mesh as it is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RefineRefusal {
    /// The mesh has no tet or hex.
    NoSolids,
    /// The mesh has this many wedges and pyramids, which are not cut.
    WedgesOrPyramids(usize),
}

/// The edges of a lower-dimensional element with `corners` corners, as pairs of slots.
fn outline_edges(corners: usize) -> &'static [(usize, usize)] {
    match corners {
        2 => &[(0, 1)],
        3 => &[(0, 1), (1, 2), (2, 0)],
        4 => &[(0, 1), (1, 2), (2, 3), (3, 0)],
        _ => &[],
    }
}

/// Midpoint nodes, one per edge, keyed by its sorted ends.
struct Midpoints {
    edges: HashMap<(u32, u32), u32>,
    next_id: u64,
}

impl Midpoints {
    fn of(&mut self, out: &mut Mesh, a: u32, b: u32) -> u32 {
        let key = (a.min(b), a.max(b));
        if let Some(&v) = self.edges.get(&key) {
            return v;
        }
        let (p, q) = (out.coords[a as usize], out.coords[b as usize]);
        self.next_id += 1;
        let v = out.push_node(self.next_id, [0, 1, 2].map(|i| 0.5 * (p[i] + q[i])));
        self.edges.insert(key, v);
        v
    }
}

/// `mesh` with every element given a node at the midpoint of each edge: tets and hexes become
/// tet10 and hex20, a line, triangle or quadrilateral its quadratic form; second-order elements
/// are taken on their corners. Element numbers, order and sets are kept.
fn with_midpoints(mesh: &Mesh) -> Mesh {
    let mut out = mesh.nodes_only();
    let mut mids = Midpoints {
        edges: HashMap::new(),
        next_id: mesh.max_node_id(),
    };
    for e in mesh.elements() {
        let corners = e.corners();
        let (kind, edges): (ElementKind, &[(usize, usize)]) = match e.kind.linear() {
            ElementKind::Tet4 => (ElementKind::Tet10, &TET10_EDGES),
            ElementKind::Hex8 => (ElementKind::Hex20, &HEX20_EDGES),
            k if !k.is_solid() && k != ElementKind::Point => (k, outline_edges(corners.len())),
            k => (k, &[]),
        };
        let mut nodes = corners.to_vec();
        for &(a, b) in edges {
            let v = mids.of(&mut out, corners[a], corners[b]);
            nodes.push(v);
        }
        out.push_element(e.id, kind, &nodes);
    }
    let added: Vec<((u32, u32), u32)> = mids.edges.into_iter().collect();
    out.sets = mesh
        .sets
        .iter()
        .map(|s| {
            let mut s = s.clone();
            if let Some(nodes) = &mut s.nodes {
                let extra = set_midpoints(mesh, nodes, &added);
                nodes.extend(extra);
                nodes.sort_unstable();
            }
            s
        })
        .collect();
    out
}

/// The midpoint nodes of `added` that join the node set `nodes` (sorted): module documentation.
fn set_midpoints(mesh: &Mesh, nodes: &[u32], added: &[((u32, u32), u32)]) -> Vec<u32> {
    let holds = |v: u32| nodes.binary_search(&v).is_ok();
    let key = |a: u32, b: u32| (a.min(b), a.max(b));
    // The edges of every element face whose corners the set holds.
    let mut face_edges: HashSet<(u32, u32)> = HashSet::new();
    for e in mesh.solids() {
        for face in face_corners(e.kind) {
            let corners: Vec<u32> = face.iter().map(|&k| e.nodes[k]).collect();
            if corners.iter().all(|&v| v != MISSING_NODE && holds(v)) {
                for k in 0..corners.len() {
                    let (a, b) = (corners[k], corners[(k + 1) % corners.len()]);
                    face_edges.insert(key(a, b));
                }
            }
        }
    }
    added
        .iter()
        .filter(|((a, b), _)| {
            holds(*a) && holds(*b) && (face_edges.is_empty() || face_edges.contains(&key(*a, *b)))
        })
        .map(|(_, v)| *v)
        .collect()
}

/// `mesh` with every tet and hex cut into eight at its edges' midpoints (module documentation):
/// eight times the elements and about seven times the nodes. Refused, with the reason, where
/// the mesh has no tet or hex, or has wedges or pyramids.
pub fn refine_uniform(mesh: &Mesh) -> Result<Mesh, RefineRefusal> {
    let mut cut = 0;
    let mut whole = 0;
    for e in mesh.solids() {
        match e.kind.linear() {
            ElementKind::Tet4 | ElementKind::Hex8 => cut += 1,
            _ => whole += 1,
        }
    }
    if whole > 0 {
        return Err(RefineRefusal::WedgesOrPyramids(whole));
    }
    if cut == 0 {
        return Err(RefineRefusal::NoSolids);
    }
    let elevated = with_midpoints(mesh);
    Ok(split_second_order(&elevated).unwrap_or(elevated))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::NamedSet;
    use crate::SetKind;

    fn tet_volume(c: &[[f64; 3]], n: &[u32]) -> f64 {
        crate::split::signed_volume6(c, [n[0], n[1], n[2], n[3]]) / 6.0
    }

    /// Two tets sharing face 1-2-3, the set "bottom" on the plane z = 0 (nodes 0, 1, 2) with
    /// a triangle element, the set "tips" of two nodes with no whole face.
    fn two_tets() -> Mesh {
        let mut m = Mesh::new();
        for (k, p) in [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.2, 0.3, 1.0],
            [1.0, 1.0, 1.0],
        ]
        .iter()
        .enumerate()
        {
            m.push_node(10 + k as u64, *p);
        }
        m.push_element(1, ElementKind::Tet4, &[0, 1, 2, 3]);
        m.push_element(2, ElementKind::Tet4, &[1, 4, 2, 3]);
        m.push_element(3, ElementKind::Triangle, &[0, 1, 2]);
        m.sets.push(NamedSet {
            name: "bottom".into(),
            kind: SetKind::PhysicalGroup,
            nodes: Some(vec![0, 1, 2]),
            elements: Some(vec![2]),
        });
        m.sets.push(NamedSet {
            name: "tips".into(),
            kind: SetKind::NodeSet,
            nodes: Some(vec![3, 4]),
            elements: None,
        });
        m
    }

    #[test]
    fn two_tets_become_sixteen_of_the_same_volume_on_shared_nodes() {
        let m = two_tets();
        let r = refine_uniform(&m).expect("tets");
        let volume = |mesh: &Mesh| -> f64 {
            mesh.solids()
                .map(|e| tet_volume(&mesh.coords, e.nodes))
                .sum()
        };
        assert_eq!(r.solids().count(), 16);
        // 5 corners and 9 edges (6 + 6 − 3 shared).
        assert_eq!(r.node_count(), 14);
        assert!((volume(&r) - volume(&m)).abs() < 1e-12);
        for e in r.solids() {
            assert!(tet_volume(&r.coords, e.nodes) > 0.0, "child {:?}", e.nodes);
        }
        // New ids after the file's largest (14).
        assert!(r.node_ids[5..].iter().all(|&id| id > 14));
    }

    #[test]
    fn set_members_are_the_midpoints_of_their_faces_only() {
        let r = refine_uniform(&two_tets()).expect("tets");
        let bottom = r.set("bottom").expect("set");
        let nodes = r.set_nodes(bottom);
        // The three corners and the midpoints of the triangle's three edges, all on z = 0.
        assert_eq!(nodes.len(), 6);
        assert!(nodes.iter().all(|&v| r.coords[v as usize][2] == 0.0));
        // The triangle element holds its midpoints too.
        let tri = r.element(bottom.elements.as_ref().expect("elements")[0] as usize);
        assert_eq!(tri.nodes.len(), 6);
        // "tips" holds no face: both ends are enough for the edge 3-4.
        let tips = r.set_nodes(r.set("tips").expect("set"));
        assert_eq!(tips.len(), 3);
    }

    #[test]
    fn a_hex_becomes_eight_on_its_grid_and_a_wedge_is_refused() {
        let mut m = Mesh::new();
        for k in 0..8u64 {
            let c = [(k ^ (k >> 1)) & 1, (k >> 1) & 1, k >> 2];
            m.push_node(k + 1, c.map(|x| x as f64));
        }
        m.push_element(1, ElementKind::Hex8, &[0, 1, 2, 3, 4, 5, 6, 7]);
        let r = refine_uniform(&m).expect("hex");
        assert_eq!(r.solids().count(), 8);
        assert_eq!(r.node_count(), 27);
        let centre = r
            .coords
            .iter()
            .filter(|p| p.iter().all(|&x| (x - 0.5).abs() < 1e-12))
            .count();
        assert_eq!(centre, 1);

        let mut w = Mesh::new();
        for k in 0..6u64 {
            w.push_node(
                k + 1,
                [(k % 3) as f64, (k % 3 == 2) as u8 as f64, (k / 3) as f64],
            );
        }
        w.push_element(1, ElementKind::Wedge6, &[0, 1, 2, 3, 4, 5]);
        assert_eq!(
            refine_uniform(&w).unwrap_err(),
            RefineRefusal::WedgesOrPyramids(1)
        );
        let empty = Mesh::new();
        assert_eq!(refine_uniform(&empty).unwrap_err(), RefineRefusal::NoSolids);
    }
}
