//! Node order of second-order and higher-order solids against gmsh's reference coordinates.

use super::*;
use crate::mesh::{HEX20_EDGES, TET10_EDGES};

/// Gmsh reference coordinates of each node (`getElementProperties`, gmsh 4.15.2).
fn gmsh_reference(code: u32) -> Vec<[f64; 3]> {
    let hex = [
        [-1., -1., -1.],
        [1., -1., -1.],
        [1., 1., -1.],
        [-1., 1., -1.],
        [-1., -1., 1.],
        [1., -1., 1.],
        [1., 1., 1.],
        [-1., 1., 1.],
        [0., -1., -1.],
        [-1., 0., -1.],
        [-1., -1., 0.],
        [1., 0., -1.],
        [1., -1., 0.],
        [0., 1., -1.],
        [1., 1., 0.],
        [-1., 1., 0.],
        [0., -1., 1.],
        [-1., 0., 1.],
        [1., 0., 1.],
        [0., 1., 1.],
        [0., 0., -1.],
        [0., -1., 0.],
        [-1., 0., 0.],
        [1., 0., 0.],
        [0., 1., 0.],
        [0., 0., 1.],
        [0., 0., 0.],
    ];
    let prism = [
        [0., 0., -1.],
        [1., 0., -1.],
        [0., 1., -1.],
        [0., 0., 1.],
        [1., 0., 1.],
        [0., 1., 1.],
        [0.5, 0., -1.],
        [0., 0.5, -1.],
        [0., 0., 0.],
        [0.5, 0.5, -1.],
        [1., 0., 0.],
        [0., 1., 0.],
        [0.5, 0., 1.],
        [0., 0.5, 1.],
        [0.5, 0.5, 1.],
        [0.5, 0., 0.],
        [0., 0.5, 0.],
        [0.5, 0.5, 0.],
    ];
    let pyramid = [
        [-1., -1., 0.],
        [1., -1., 0.],
        [1., 1., 0.],
        [-1., 1., 0.],
        [0., 0., 1.],
        [0., -1., 0.],
        [-1., 0., 0.],
        [-0.5, -0.5, 0.5],
        [1., 0., 0.],
        [0.5, -0.5, 0.5],
        [0., 1., 0.],
        [0.5, 0.5, 0.5],
        [-0.5, 0.5, 0.5],
        [0., 0., 0.],
    ];
    let tet10 = [
        [0., 0., 0.],
        [1., 0., 0.],
        [0., 1., 0.],
        [0., 0., 1.],
        [0.5, 0., 0.],
        [0.5, 0.5, 0.],
        [0., 0.5, 0.],
        [0., 0., 0.5],
        [0., 0.5, 0.5],
        [0.5, 0., 0.5],
    ];
    match code {
        11 => tet10.to_vec(),
        17 => hex[..20].to_vec(),
        12 => hex.to_vec(),
        18 => prism[..15].to_vec(),
        13 => prism.to_vec(),
        19 => pyramid[..13].to_vec(),
        14 => pyramid.to_vec(),
        _ => unreachable!(),
    }
}

/// Mid-edge nodes of the mesh convention (mesh.rs): (stored index, edge corners); tet10 and
/// hex20 from the tables that `split` cuts by.
fn convention_edges(kind: ElementKind) -> Vec<(usize, usize, usize)> {
    let edges: &[(usize, usize)] = match kind {
        ElementKind::Hex20 => &HEX20_EDGES,
        ElementKind::Tet10 => &TET10_EDGES,
        ElementKind::Wedge15 => &[
            (0, 1),
            (1, 2),
            (2, 0),
            (3, 4),
            (4, 5),
            (5, 3),
            (0, 3),
            (1, 4),
            (2, 5),
        ],
        ElementKind::Pyramid13 => &[
            (0, 1),
            (1, 2),
            (2, 3),
            (3, 0),
            (0, 4),
            (1, 4),
            (2, 4),
            (3, 4),
        ],
        _ => unreachable!(),
    };
    let corners = kind.corner_count();
    edges
        .iter()
        .enumerate()
        .map(|(k, &(a, b))| (corners + k, a, b))
        .collect()
}

/// One element of gmsh type `code` with its nodes at gmsh's reference coordinates, scaled and
/// shifted so no coordinate is special.
fn one_element_file(code: u32) -> String {
    let pts = gmsh_reference(code);
    let n = pts.len();
    let mut s = format!("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 {n} 1 {n}\n3 1 0 {n}\n");
    for i in 1..=n {
        s += &format!("{i}\n");
    }
    for p in &pts {
        s += &format!(
            "{} {} {}\n",
            2.0 * p[0] + 3.0,
            4.0 * p[1] - 1.0,
            8.0 * p[2] + 0.5
        );
    }
    s += &format!("$EndNodes\n$Elements\n1 1 1 1\n3 1 {code} 1\n1");
    for i in 1..=n {
        s += &format!(" {i}");
    }
    s += "\n$EndElements\n";
    s
}

#[test]
fn second_order_node_order_matches_geometry() {
    for (code, kind, reduced) in [
        (11, ElementKind::Tet10, false),
        (17, ElementKind::Hex20, false),
        (12, ElementKind::Hex20, true),
        (18, ElementKind::Wedge15, false),
        (13, ElementKind::Wedge15, true),
        (19, ElementKind::Pyramid13, false),
        (14, ElementKind::Pyramid13, true),
    ] {
        let m = ok(one_element_file(code).as_bytes());
        let e = m.element(0);
        assert_eq!(e.kind, kind, "type {code}");
        assert_eq!(Some(e.nodes.len()), kind.node_count(), "type {code}");
        for (k, &n) in e.corners().iter().enumerate() {
            assert_eq!(
                m.node_ids[n as usize],
                k as u64 + 1,
                "type {code}: corners unchanged"
            );
        }
        for (k, a, b) in convention_edges(kind) {
            let p = m.coords[e.nodes[k] as usize];
            let (pa, pb) = (m.coords[e.nodes[a] as usize], m.coords[e.nodes[b] as usize]);
            for d in 0..3 {
                assert!(
                    (p[d] - 0.5 * (pa[d] + pb[d])).abs() < 1e-12,
                    "type {code}: node {k} is not the midpoint of edge ({a},{b})"
                );
            }
        }
        assert_eq!(
            reduced,
            !m.warnings.is_empty(),
            "type {code}: {:?}",
            m.warnings
        );
    }
}

#[test]
fn reduced_elements_keep_all_their_nodes_in_groups() {
    let text = one_element_file(12).replace(
        "$Nodes",
        "$Entities\n0 0 0 1\n1 0 0 0 1 1 1 1 4 0\n$EndEntities\n$Nodes",
    );
    let m = ok(text.as_bytes());
    assert_eq!(m.element(0).nodes.len(), 20);
    assert_eq!(sets(&m), vec![("PhysicalVolume4".to_string(), 1, 27)]);
}

#[test]
fn higher_order_solids_are_read_by_corners() {
    // A hex64 (type 92) with 64 nodes: corners first.
    let n = 64;
    let mut s = format!("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 {n} 1 {n}\n3 1 0 {n}\n");
    for i in 1..=n {
        s += &format!("{i}\n");
    }
    for i in 0..n {
        s += &format!("{i} 0 0\n");
    }
    s += "$EndNodes\n$Elements\n1 1 1 1\n3 1 92 1\n1";
    for i in 1..=n {
        s += &format!(" {i}");
    }
    s += "\n$EndElements\n";
    let m = ok(s.as_bytes());
    assert_eq!(m.element_kinds, vec![ElementKind::Hex8]);
    assert_eq!(ids_of(&m, 0), (1..=8).collect::<Vec<u64>>());
    assert!(m.warnings[0].contains("hex64"), "{:?}", m.warnings);
}
