//! Second-order solids split into first-order ones on all their nodes.
//!
//! A tet10 or hex20 has the resolution of all its nodes, not of its corners: an FE code takes
//! its mid-edge nodes as degrees of freedom, and gmsh places them on the curved geometry.
//!
//! * A **tet10**, cut at its mid-edge nodes, is eight tet4: one at each corner (the parent
//!   scaled by ½ about it) and four around a diagonal of the octahedron left in the middle,
//!   the shortest of its three (the red refinement of a tetrahedron, as gmsh's `RefineMesh`
//!   makes it). No node is added.
//! * A **hex20** is eight hex8 on the 3×3×3 grid of its parametric cube: its corners, its
//!   mid-edge nodes, and a node at the centre of each face and of the element, placed where the
//!   element's own serendipity shape functions put them (face centre `−¼ Σ corners + ½ Σ
//!   mid-edges` of the face; element centre `−¼ Σ corners + ¼ Σ mid-edges`). Neighbours share
//!   their face node; a face node belongs to a node set that holds its face's eight nodes, a
//!   centre node to one that holds the element's twenty.
//!
//! An element that lacks a mid-edge node (ANSYS writes 0) keeps its corners. Node numbers and
//! sets stay the file's; added nodes are numbered after its largest.

use std::collections::HashMap;

use crate::mesh::{ElementKind, Mesh, HEX20_EDGES, MISSING_NODE};

/// The three pairs of opposite vertices of the middle octahedron, as tet10 slots: the
/// mid-edges of opposite tet edges ((0,1)-(2,3), (1,2)-(0,3), (2,0)-(1,3)).
const OPPOSITE: [(usize, usize); 3] = [(4, 9), (5, 7), (6, 8)];

/// Signed volume ×6 of the tetrahedron `t` (positive in the convention of [`crate::mesh`]).
pub(crate) fn signed_volume6(coords: &[[f64; 3]], t: [u32; 4]) -> f64 {
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
    // Mid-edge slots (TET10_EDGES): 4 (0,1), 5 (1,2), 6 (2,0), 7 (0,3), 8 (1,3), 9 (2,3).
    let (m01, m12, m02, m03, m13, m23) = (n[4], n[5], n[6], n[7], n[8], n[9]);
    let mut out = [[0u32; 4]; 8];
    // The corners: the parent scaled by ½ about each vertex keeps its orientation.
    out[0] = [n[0], m01, m02, m03];
    out[1] = [m01, n[1], m12, m13];
    out[2] = [m02, m12, n[2], m23];
    out[3] = [m03, m13, m23, n[3]];
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

/// Hex8 corners in the parametric cube `{0, 2}³` (bottom 0-1-2-3, top 4-7 above it).
const HEX_CORNERS: [[usize; 3]; 8] = [
    [0, 0, 0],
    [2, 0, 0],
    [2, 2, 0],
    [0, 2, 0],
    [0, 0, 2],
    [2, 0, 2],
    [2, 2, 2],
    [0, 2, 2],
];

/// A position on the 3×3×3 grid of the hex's parametric cube, as an index.
fn grid(p: [usize; 3]) -> usize {
    p[0] + 3 * p[1] + 9 * p[2]
}

/// The hex20 elements whose twenty nodes are all given split into eight hex8, adding face and
/// centre nodes to `out` (keyed by their face's sorted corners so that neighbours share them).
struct HexNodes {
    faces: HashMap<[u32; 4], u32>,
    next_id: u64,
}

impl HexNodes {
    fn add(&mut self, out: &mut Mesh, xyz: [f64; 3]) -> u32 {
        self.next_id += 1;
        out.push_node(self.next_id, xyz)
    }

    /// The 27 grid nodes of hex20 `n` (corners first, then mid-edges), creating the face
    /// and centre nodes; each node created goes to `added` with the nodes that decide its set
    /// membership (a face node: its face's eight; the centre: all twenty).
    fn grid_nodes(
        &mut self,
        out: &mut Mesh,
        n: &[u32],
        added: &mut Vec<(u32, Vec<u32>)>,
    ) -> [u32; 27] {
        let mut g = [u32::MAX; 27];
        for (k, c) in HEX_CORNERS.iter().enumerate() {
            g[grid(*c)] = n[k];
        }
        for (k, &(a, b)) in HEX20_EDGES.iter().enumerate() {
            let mid = [0, 1, 2].map(|i| (HEX_CORNERS[a][i] + HEX_CORNERS[b][i]) / 2);
            g[grid(mid)] = n[8 + k];
        }
        let xyz = |m: &Mesh, v: u32| m.coords[v as usize];
        // Faces: the grid points with one coordinate at 0 or 2 and the other two at 1.
        for axis in 0..3 {
            for side in [0, 2] {
                let mut centre = [1, 1, 1];
                centre[axis] = side;
                let corners: Vec<u32> = HEX_CORNERS
                    .iter()
                    .enumerate()
                    .filter(|(_, c)| c[axis] == side)
                    .map(|(k, _)| n[k])
                    .collect();
                let mids: Vec<u32> = HEX20_EDGES
                    .iter()
                    .enumerate()
                    .filter(|(_, &(a, b))| {
                        HEX_CORNERS[a][axis] == side && HEX_CORNERS[b][axis] == side
                    })
                    .map(|(k, _)| n[8 + k])
                    .collect();
                let mut key = [corners[0], corners[1], corners[2], corners[3]];
                key.sort_unstable();
                let node = match self.faces.get(&key) {
                    Some(&v) => v,
                    None => {
                        let p = [0, 1, 2].map(|i| {
                            -0.25 * corners.iter().map(|&v| xyz(out, v)[i]).sum::<f64>()
                                + 0.5 * mids.iter().map(|&v| xyz(out, v)[i]).sum::<f64>()
                        });
                        let v = self.add(out, p);
                        self.faces.insert(key, v);
                        added.push((v, [corners, mids].concat()));
                        v
                    }
                };
                g[grid(centre)] = node;
            }
        }
        let p = [0, 1, 2].map(|i| {
            -0.25 * n[..8].iter().map(|&v| xyz(out, v)[i]).sum::<f64>()
                + 0.25 * n[8..20].iter().map(|&v| xyz(out, v)[i]).sum::<f64>()
        });
        let centre = self.add(out, p);
        added.push((centre, n.to_vec()));
        g[grid([1, 1, 1])] = centre;
        g
    }
}

/// The eight hex8 of the 3×3×3 grid `g`, each oriented as the parent.
fn hex_children(g: &[u32; 27]) -> [[u32; 8]; 8] {
    let mut out = [[0u32; 8]; 8];
    for (k, child) in out.iter_mut().enumerate() {
        let o = [k & 1, (k >> 1) & 1, (k >> 2) & 1];
        for (c, corner) in HEX_CORNERS.iter().enumerate() {
            child[c] = g[grid([0, 1, 2].map(|i| o[i] + corner[i] / 2))];
        }
    }
    out
}

/// Whether element `e` is a second-order solid this module splits: a tet10 or hex20 with all
/// its nodes.
fn splits(mesh: &Mesh, e: usize) -> bool {
    matches!(
        mesh.element_kinds[e],
        ElementKind::Tet10 | ElementKind::Hex20
    ) && !mesh.element(e).nodes.contains(&MISSING_NODE)
}

/// Whether `mesh` has a tet10 or hex20 with all its nodes: what [`split_second_order`] cuts.
pub fn has_splittable(mesh: &Mesh) -> bool {
    (0..mesh.element_count()).any(|e| splits(mesh, e))
}

/// `mesh` with every tet10 and hex20 whose nodes are all given split into eight first-order
/// elements on them (module documentation); `None` when it has no such element. The children
/// keep their parent's element number; element sets hold the children of their elements.
pub fn split_second_order(mesh: &Mesh) -> Option<Mesh> {
    if !has_splittable(mesh) {
        return None;
    }
    let mut out = mesh.nodes_only();
    let mut hex = HexNodes {
        faces: HashMap::new(),
        next_id: mesh.max_node_id(),
    };
    // Added nodes and the nodes that decide their set membership.
    let mut added: Vec<(u32, Vec<u32>)> = Vec::new();
    // New indices of each element's children: first..end.
    let mut first = Vec::with_capacity(mesh.element_count() + 1);
    for e in mesh.elements() {
        first.push(out.element_count() as u32);
        if !splits(mesh, e.index as usize) {
            out.push_element(e.id, e.kind, e.nodes);
        } else if e.kind == ElementKind::Tet10 {
            for t in split_tet10_nodes(&mesh.coords, e.nodes) {
                out.push_element(e.id, ElementKind::Tet4, &t);
            }
        } else {
            let g = hex.grid_nodes(&mut out, e.nodes, &mut added);
            for h in hex_children(&g) {
                out.push_element(e.id, ElementKind::Hex8, &h);
            }
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
            if let Some(nodes) = &mut s.nodes {
                let holds = |v: &u32| nodes.binary_search(v).is_ok();
                let extra: Vec<u32> = added
                    .iter()
                    .filter(|(_, owners)| owners.iter().all(holds))
                    .map(|(v, _)| *v)
                    .collect();
                nodes.extend(extra);
                nodes.sort_unstable();
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
        for (k, &(a, b)) in crate::mesh::TET10_EDGES.iter().enumerate() {
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
        let split = split_second_order(&m).expect("one tet10");
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
        let split = split_second_order(&m).expect("one tet10");
        assert_eq!(split.element_count(), 9);
        assert_eq!(split.element(8).id, 8);
        assert_eq!(split.sets[0].elements, Some((0..9).collect()));
    }

    /// An affine image of the cube [-1, 1]³ as a hex20, mid-edge nodes at the midpoints, and a
    /// node set holding the eight nodes of its face z = +1.
    fn hex20() -> (Mesh, [[f64; 3]; 3]) {
        let a = [[1.0, 0.2, -0.1], [0.3, 0.9, 0.2], [-0.2, 0.1, 1.1]];
        let map = |p: [f64; 3]| [0, 1, 2].map(|i| (0..3).map(|j| a[i][j] * p[j]).sum::<f64>());
        let mut m = Mesh::new();
        let cube = |c: [usize; 3]| c.map(|x| x as f64 - 1.0);
        for (k, c) in HEX_CORNERS.iter().enumerate() {
            m.push_node(k as u64 + 1, map(cube(*c)));
        }
        for (k, &(u, v)) in HEX20_EDGES.iter().enumerate() {
            let mid = [0, 1, 2].map(|i| (HEX_CORNERS[u][i] + HEX_CORNERS[v][i]) / 2);
            m.push_node(9 + k as u64, map(cube(mid)));
        }
        m.push_element(3, ElementKind::Hex20, &(0..20).collect::<Vec<u32>>());
        m.sets.push(crate::mesh::NamedSet {
            name: "top".into(),
            kind: crate::mesh::SetKind::NodeSet,
            nodes: Some(vec![4, 5, 6, 7, 12, 13, 14, 15]),
            elements: None,
        });
        (m, a)
    }

    /// Volume of a hex8 whose faces are planar (here: affine), as five tets.
    fn hex_volume(c: &[[f64; 3]], h: &[u32]) -> f64 {
        let t = |q: [usize; 4]| volume(c, q.map(|k| h[k]));
        t([0, 1, 3, 4]) + t([1, 2, 3, 6]) + t([1, 3, 4, 6]) + t([1, 4, 5, 6]) + t([3, 4, 6, 7])
    }

    #[test]
    fn a_hex20_is_eight_hex8_on_its_grid() {
        let (m, a) = hex20();
        let det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
            - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
            + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
        let parent = 8.0 * det;
        let split = split_second_order(&m).expect("one hex20");
        // 20 nodes, 6 face centres and the element's centre, the centre at the origin.
        assert_eq!(split.node_count(), 27);
        assert!(split.coords[26].iter().all(|x| x.abs() < 1e-12));
        assert_eq!(split.node_ids[20..], [21, 22, 23, 24, 25, 26, 27]);
        assert_eq!(split.element_count(), 8);
        for e in split.elements() {
            assert_eq!((e.kind, e.id), (ElementKind::Hex8, 3));
            let v = hex_volume(&split.coords, e.nodes);
            assert!(
                (v - parent / 8.0).abs() < 1e-12,
                "{v} against {}",
                parent / 8.0
            );
        }
        // The face node of z = +1 joins "top"; no other added node does.
        let top = split.sets[0].nodes.as_ref().expect("node set");
        assert_eq!(top.len(), 9);
        let added = top.iter().find(|&&v| v >= 20).expect("the face node");
        let want = [0, 1, 2].map(|i| a[i][2]);
        let got = split.coords[*added as usize];
        assert!((0..3).all(|i| (got[i] - want[i]).abs() < 1e-12), "{got:?}");
    }

    #[test]
    fn neighbouring_hex20_share_their_face_node() {
        let (mut m, _) = hex20();
        // A second hex20 stacked on the first's face z = +1: that face's nodes and new ones
        // above it.
        let lift = |p: [f64; 3], k: f64| [p[0], p[1], p[2] + k];
        let base: Vec<[f64; 3]> = m.coords.clone();
        let mut id = 100;
        let mut new = |m: &mut Mesh, p: [f64; 3]| {
            id += 1;
            m.push_node(id, p)
        };
        let up = 2.0 * (base[4][2] - base[0][2]).abs().max(1.0);
        let mut n = [0u32; 20];
        for k in 0..4 {
            n[k] = 4 + k as u32;
            n[4 + k] = new(&mut m, lift(base[4 + k], up));
        }
        for k in 0..4 {
            n[8 + k] = 12 + k as u32;
        }
        for k in 0..4 {
            let (u, v) = (n[4 + k], n[4 + (k + 1) % 4]);
            let p = [0, 1, 2].map(|i| 0.5 * (m.coords[u as usize][i] + m.coords[v as usize][i]));
            n[12 + k] = new(&mut m, p);
        }
        for k in 0..4 {
            let (u, v) = (n[k], n[4 + k]);
            let p = [0, 1, 2].map(|i| 0.5 * (m.coords[u as usize][i] + m.coords[v as usize][i]));
            n[16 + k] = new(&mut m, p);
        }
        m.push_element(4, ElementKind::Hex20, &n);
        let before = m.node_count();
        let split = split_second_order(&m).expect("two hex20");
        // Six faces each, one shared, and two centres.
        assert_eq!(split.node_count(), before + 11 + 2);
        assert_eq!(split.element_count(), 16);
    }

    #[test]
    fn a_tet10_without_all_its_nodes_keeps_its_corners() {
        let mut m = tet10();
        let last = m.connectivity.len() - 1;
        m.connectivity[last] = MISSING_NODE;
        assert!(split_second_order(&m).is_none());
    }
}
