//! Mesh quality checks that a reader cannot see record by record: nodes that no element uses,
//! nodes at the same place (a mesh exported part by part, whose parts are not merged), and
//! solid elements in pieces that share no node. Each gives one warning naming ids; none is an
//! error, because each can be intended (two bodies in one file, a spare node), but each changes
//! what a PD model of the mesh is. Inverted and degenerate elements are errors, found where
//! element volumes are computed.

use std::collections::HashMap;

use crate::mesh::Mesh;

/// At most this many ids are listed in a warning.
const LISTED: usize = 5;

/// The warnings of every check, one line each.
pub fn quality_warnings(mesh: &Mesh) -> Vec<String> {
    let mut out = Vec::new();
    out.extend(unused_nodes(mesh));
    out.extend(duplicate_nodes(mesh));
    out.extend(disconnected_pieces(mesh));
    out
}

fn list(ids: impl Iterator<Item = u64>, total: usize) -> String {
    let shown: Vec<String> = ids.take(LISTED).map(|i| i.to_string()).collect();
    if total > shown.len() {
        format!("{}, … ({total} in all)", shown.join(", "))
    } else {
        shown.join(", ")
    }
}

/// Nodes that no element of any dimension uses.
fn unused_nodes(mesh: &Mesh) -> Option<String> {
    let mut used = vec![false; mesh.node_count()];
    for &n in &mesh.connectivity {
        if let Some(u) = used.get_mut(n as usize) {
            *u = true;
        }
    }
    let unused: Vec<usize> = (0..used.len()).filter(|&i| !used[i]).collect();
    if unused.is_empty() {
        return None;
    }
    Some(format!(
        "{} nodes are used by no element (ids {}); they are not part of any body",
        unused.len(),
        list(unused.iter().map(|&i| mesh.node_ids[i]), unused.len())
    ))
}

/// Corner nodes of solid elements at the same place (to 1e-9 of the mesh's size).
fn duplicate_nodes(mesh: &Mesh) -> Option<String> {
    let (lo, hi) = mesh.bbox()?;
    let size = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
    if size.is_nan() || size <= 0.0 {
        return None;
    }
    let tol = 1e-9 * size;
    let corners = mesh.solid_corner_mask();
    let mut seen: HashMap<[i64; 3], usize> = HashMap::new();
    let mut pairs: Vec<(u64, u64)> = Vec::new();
    for (i, c) in mesh.coords.iter().enumerate() {
        if !corners.get(i).copied().unwrap_or(false) {
            continue;
        }
        let key = c.map(|x| (x / tol).round() as i64);
        match seen.get(&key) {
            Some(&j) => pairs.push((mesh.node_ids[j], mesh.node_ids[i])),
            None => {
                seen.insert(key, i);
            }
        }
    }
    if pairs.is_empty() {
        return None;
    }
    let shown: Vec<String> = pairs
        .iter()
        .take(LISTED)
        .map(|(a, b)| format!("{a} and {b}"))
        .collect();
    let more = if pairs.len() > LISTED {
        format!(", … ({} pairs in all)", pairs.len())
    } else {
        String::new()
    };
    Some(format!(
        "{} element corner nodes lie on another one (nodes {}{more}); the elements on either side are not connected there: merge the nodes if they should be",
        pairs.len(),
        shown.join("; ")
    ))
}

/// The pieces of a mesh's solid elements that share no node: each node's piece (numbered
/// from 0 in the order of each piece's first solid element), [`NO_PIECE`] for a node that no
/// solid uses, and the number of pieces. Two pieces are two solids, whatever lies between
/// them: touching, they are not joined.
pub fn solid_pieces(mesh: &Mesh) -> (Vec<u32>, usize) {
    let mut parent: Vec<u32> = (0..mesh.node_count() as u32).collect();
    fn find(parent: &mut [u32], mut x: u32) -> u32 {
        while parent[x as usize] != x {
            let up = parent[parent[x as usize] as usize];
            parent[x as usize] = up;
            x = up;
        }
        x
    }
    let nodes_in_mesh = parent.len();
    let in_range = move |n: &&u32| (**n as usize) < nodes_in_mesh;
    for e in mesh.solids() {
        let mut nodes = e.nodes.iter().filter(in_range);
        let Some(&first) = nodes.next() else {
            continue;
        };
        let a = find(&mut parent, first);
        for &n in nodes {
            let b = find(&mut parent, n);
            if a != b {
                parent[b as usize] = a;
            }
        }
    }
    let mut label = vec![NO_PIECE; nodes_in_mesh];
    let mut of_root: HashMap<u32, u32> = HashMap::new();
    for e in mesh.solids() {
        for &n in e.nodes.iter().filter(in_range) {
            let root = find(&mut parent, n);
            let next = of_root.len() as u32;
            label[n as usize] = *of_root.entry(root).or_insert(next);
        }
    }
    (label, of_root.len())
}

/// The piece of a node that no solid element uses ([`solid_pieces`]).
pub const NO_PIECE: u32 = u32::MAX;

/// How the warning of solids in pieces that share no node starts ([`is_pieces_warning`]).
const PIECES: &str = "the solid elements form ";

/// Whether `warning` is the one of solids in pieces that share no node: a run says what it
/// makes of a body's pieces itself, once it knows its bonds and its contacts.
pub fn is_pieces_warning(warning: &str) -> bool {
    warning.starts_with(PIECES)
}

/// Solid elements in pieces that share no node.
fn disconnected_pieces(mesh: &Mesh) -> Option<String> {
    let (label, count) = solid_pieces(mesh);
    if count < 2 {
        return None;
    }
    // Elements per piece, and the first element id of each.
    let mut pieces: HashMap<u32, (usize, u64)> = HashMap::new();
    for e in mesh.solids() {
        let Some(&piece) = e.nodes.iter().find_map(|&n| label.get(n as usize)) else {
            continue;
        };
        let entry = pieces.entry(piece).or_insert((0, e.id));
        entry.0 += 1;
    }
    if pieces.len() < 2 {
        return None;
    }
    let mut sizes: Vec<(usize, u64)> = pieces.into_values().collect();
    sizes.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)));
    let shown: Vec<String> = sizes
        .iter()
        .take(LISTED)
        .map(|(n, id)| format!("{n} elements from element {id}"))
        .collect();
    Some(format!(
        "{PIECES}{} pieces that share no node ({}{}): one body in pieces, which no contact keeps apart unless a [[contact]] names the body as its own slave and master (pdcontact convert writes one)",
        sizes.len(),
        shown.join("; "),
        if sizes.len() > LISTED { ", …" } else { "" }
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::ElementKind;

    /// A unit cube of one hex8 at `x0`, node ids from `id0`.
    fn cube(mesh: &mut Mesh, x0: f64, id0: u64, elem: u64) {
        let mut n = Vec::new();
        for (k, c) in [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [1.0, 1.0, 1.0],
            [0.0, 1.0, 1.0],
        ]
        .iter()
        .enumerate()
        {
            n.push(mesh.push_node(id0 + k as u64, [c[0] + x0, c[1], c[2]]));
        }
        mesh.push_element(elem, ElementKind::Hex8, &n);
    }

    #[test]
    fn a_clean_cube_has_no_warning() {
        let mut m = Mesh::new();
        cube(&mut m, 0.0, 1, 1);
        assert!(quality_warnings(&m).is_empty());
    }

    #[test]
    fn unused_duplicate_and_disconnected_are_named() {
        let mut m = Mesh::new();
        cube(&mut m, 0.0, 1, 1);
        // A second cube touching the first at x = 1 with its own nodes: duplicates, and a
        // separate piece.
        cube(&mut m, 1.0, 101, 2);
        m.push_node(999, [5.0, 5.0, 5.0]);
        let w = quality_warnings(&m);
        assert_eq!(w.len(), 3, "{w:?}");
        assert!(
            w[0].contains("1 nodes are used by no element (ids 999)"),
            "{}",
            w[0]
        );
        assert!(
            w[1].starts_with("4 element corner nodes lie on another one (nodes 2 and 101"),
            "{}",
            w[1]
        );
        assert!(w[2].contains("2 pieces"), "{}", w[2]);
        assert!(
            w[2].contains("from element 1") && w[2].contains("from element 2"),
            "{}",
            w[2]
        );
    }
}
