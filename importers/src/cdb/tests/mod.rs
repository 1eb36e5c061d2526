//! Unit tests on small hand-written snippets.

use std::path::Path;

use super::format::Format;
use super::read;
use crate::error::{ImportError, Location};
use crate::mesh::{ElementKind, Mesh, MISSING_NODE};

mod errors;
mod numbers;

fn read_str(s: &str) -> Result<Mesh, ImportError> {
    read(Path::new("t.cdb"), s.as_bytes())
}

fn ok(s: &str) -> Mesh {
    match read_str(s) {
        Ok(m) => m,
        Err(e) => panic!("unexpected error: {e}"),
    }
}

fn err(s: &str) -> ImportError {
    match read_str(s) {
        Ok(m) => panic!("expected an error, read {} nodes", m.node_count()),
        Err(e) => e,
    }
}

/// A format line that must parse.
fn fmt(line: &[u8]) -> Format {
    match Format::parse(line) {
        Some(f) => f,
        None => panic!("not parsed: {}", String::from_utf8_lossy(line)),
    }
}

fn line_of(e: &ImportError) -> usize {
    match e.location {
        Location::Line(n) => n,
        other => panic!("error without a line: {other:?} ({e})"),
    }
}

/// An NBLOCK `(3i9,6e21.13e3)` with the given nodes.
fn nblock(nodes: &[(u32, [f64; 3])]) -> String {
    let mut s = String::from("NBLOCK,6,SOLID\n(3i9,6e21.13e3)\n");
    for (id, p) in nodes {
        s += &format!("{id:9}{:9}{:9}", 0, 0);
        for v in p {
            s += &format!("{:>21}", format!("{v:.13E}"));
        }
        s.push('\n');
    }
    s += "N,R5.3,LOC,       -1,\n";
    s
}

/// A SOLID-layout EBLOCK `(19i9)` with records `(type, id, nodes)`.
fn eblock(records: &[(i64, i64, &[u32])]) -> String {
    let mut s = String::from("EBLOCK,19,SOLID\n(19i9)\n");
    for (ty, id, nodes) in records {
        for v in [1, *ty, 1, 1, 0, 0, 0, 0, nodes.len() as i64, 0, *id] {
            s += &format!("{v:9}");
        }
        for n in nodes.iter().take(8) {
            s += &format!("{n:9}");
        }
        s.push('\n');
        if nodes.len() > 8 {
            for n in &nodes[8..] {
                s += &format!("{n:9}");
            }
            s.push('\n');
        }
    }
    s += "       -1\n";
    s
}

/// The unit cube 1..8 in ANSYS order, an apex 9 above the top, and mid-side stand-ins 101..112.
fn cube_nodes() -> Vec<(u32, [f64; 3])> {
    let mut v = vec![
        (1, [0.0, 0.0, 0.0]),
        (2, [1.0, 0.0, 0.0]),
        (3, [1.0, 1.0, 0.0]),
        (4, [0.0, 1.0, 0.0]),
        (5, [0.0, 0.0, 1.0]),
        (6, [1.0, 0.0, 1.0]),
        (7, [1.0, 1.0, 1.0]),
        (8, [0.0, 1.0, 1.0]),
        (9, [0.5, 0.5, 1.0]),
    ];
    for k in 0..12 {
        v.push((101 + k, [2.0 + f64::from(k), 0.0, 0.0]));
    }
    v
}

/// File node numbers of element `e`.
fn file_nodes(m: &Mesh, e: usize) -> Vec<u64> {
    m.element(e)
        .nodes
        .iter()
        .map(|&n| {
            if n == MISSING_NODE {
                0
            } else {
                m.node_ids[n as usize]
            }
        })
        .collect()
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn triple(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    let x = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    x[0] * c[0] + x[1] * c[1] + x[2] * c[2]
}

/// The orientation test of the mesh.rs convention for each linear shape.
fn positive_volume(m: &Mesh, e: usize) -> bool {
    let el = m.element(e);
    let p = |i: usize| m.coords[el.nodes[i] as usize];
    match el.kind.linear() {
        ElementKind::Hex8 | ElementKind::Pyramid5 => {
            triple(sub(p(1), p(0)), sub(p(3), p(0)), sub(p(4), p(0))) > 0.0
        }
        ElementKind::Wedge6 | ElementKind::Tet4 => {
            triple(sub(p(1), p(0)), sub(p(2), p(0)), sub(p(3), p(0))) > 0.0
        }
        _ => false,
    }
}

#[test]
fn collapsed_bricks_linear() {
    let mut s = String::from("ET,2,185\n");
    s += &nblock(&cube_nodes());
    s += &eblock(&[
        (2, 10, &[1, 2, 3, 4, 5, 6, 7, 8]),
        (2, 11, &[1, 2, 3, 3, 5, 6, 7, 7]),
        (2, 12, &[1, 2, 3, 4, 9, 9, 9, 9]),
        (2, 13, &[1, 2, 3, 3, 5, 5, 5, 5]),
    ]);
    let m = ok(&s);
    assert_eq!(
        m.element_kinds,
        vec![
            ElementKind::Hex8,
            ElementKind::Wedge6,
            ElementKind::Pyramid5,
            ElementKind::Tet4
        ]
    );
    assert_eq!(file_nodes(&m, 0), vec![1, 2, 3, 4, 5, 6, 7, 8]);
    assert_eq!(file_nodes(&m, 1), vec![1, 2, 3, 5, 6, 7]);
    assert_eq!(file_nodes(&m, 2), vec![1, 2, 3, 4, 9]);
    assert_eq!(file_nodes(&m, 3), vec![1, 2, 3, 5]);
    for e in 0..4 {
        assert!(positive_volume(&m, e), "element {e}");
    }
    assert_eq!(m.element_ids, vec![10, 11, 12, 13]);
    // Boundary faces of the collapsed shapes come out with the right arities.
    let faces = crate::faces::boundary_faces(&m);
    assert_eq!(faces.non_manifold, 0);
}

#[test]
fn collapsed_bricks_quadratic_midside_mapping() {
    let mids: Vec<u32> = (101..=112).collect();
    let rec = |corners: [u32; 8]| -> Vec<u32> { corners.iter().chain(&mids).copied().collect() };
    let hex = rec([1, 2, 3, 4, 5, 6, 7, 8]);
    let wedge = rec([1, 2, 3, 3, 5, 6, 7, 7]);
    let pyr = rec([1, 2, 3, 4, 9, 9, 9, 9]);
    let tet = rec([1, 2, 3, 3, 5, 5, 5, 5]);
    let mut s = String::from("ET,1,SOLID186\n");
    s += &nblock(&cube_nodes());
    s += &eblock(&[(1, 1, &hex), (1, 2, &wedge), (1, 3, &pyr), (1, 4, &tet)]);
    let m = ok(&s);
    assert_eq!(
        m.element_kinds,
        vec![
            ElementKind::Hex20,
            ElementKind::Wedge15,
            ElementKind::Pyramid13,
            ElementKind::Tet10
        ]
    );
    let q = |k: u64| 100 + k; // Q = 101, R = 102, ... B = 112
    assert_eq!(
        file_nodes(&m, 0)[8..],
        (1..=12).map(q).collect::<Vec<_>>()[..]
    );
    // Wedge: Q R T | U V X | Y Z A.
    assert_eq!(
        file_nodes(&m, 1),
        vec![
            1,
            2,
            3,
            5,
            6,
            7,
            q(1),
            q(2),
            q(4),
            q(5),
            q(6),
            q(8),
            q(9),
            q(10),
            q(11)
        ]
    );
    // Pyramid: Q R S T | Y Z A B.
    assert_eq!(
        file_nodes(&m, 2),
        vec![
            1,
            2,
            3,
            4,
            9,
            q(1),
            q(2),
            q(3),
            q(4),
            q(9),
            q(10),
            q(11),
            q(12)
        ]
    );
    // Tet: Q R T Y Z A.
    assert_eq!(
        file_nodes(&m, 3),
        vec![1, 2, 3, 5, q(1), q(2), q(4), q(9), q(10), q(11)]
    );
    for e in 0..4 {
        assert!(positive_volume(&m, e), "element {e}");
    }
}

#[test]
fn midside_nodes_missing_or_absent() {
    let mut s = String::from("ET,1,186\nET,3,187\nET,4,92\n");
    s += &nblock(&cube_nodes());
    // A SOLID186 hex with some midside nodes 0, one with all 0 (linear), a SOLID187 with only
    // 4 nodes (TetBeam.cdb), a SOLID92 with 9 nodes and a 0 in a midside slot.
    let partial: Vec<u32> = [
        1, 2, 3, 4, 5, 6, 7, 8, 101, 0, 103, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    ]
    .to_vec();
    let none: Vec<u32> = [1, 2, 3, 4, 5, 6, 7, 8, 0, 0, 0, 0].to_vec();
    s += &eblock(&[
        (1, 1, &partial),
        (1, 2, &none),
        (3, 3, &[1, 2, 4, 5]),
        (4, 4, &[1, 2, 4, 5, 101, 0, 103, 104, 105]),
    ]);
    let m = ok(&s);
    assert_eq!(
        m.element_kinds,
        vec![
            ElementKind::Hex20,
            ElementKind::Hex8,
            ElementKind::Tet4,
            ElementKind::Tet10
        ]
    );
    assert_eq!(file_nodes(&m, 0)[8..12], [101, 0, 103, 0]);
    assert_eq!(
        file_nodes(&m, 3),
        vec![1, 2, 4, 5, 101, 0, 103, 104, 105, 0]
    );
    assert_eq!(m.element(3).nodes[9], MISSING_NODE);
    assert!(m
        .warnings
        .iter()
        .any(|w| w.starts_with("2 quadratic elements lack")));
}

#[test]
fn skipped_types_warn_once_per_type() {
    let mut s = String::from("ET,1,185\nET,2,154\n*SET,tid,5\n*set,cid,4\net,cid,174\nET,7,999\n");
    s += &nblock(&cube_nodes());
    s += &eblock(&[
        (1, 1, &[1, 2, 3, 4, 5, 6, 7, 8]),
        (9, 2, &[1, 2, 3, 4, 5, 6, 7, 8]),
        (7, 6, &[1, 2, 3, 4, 5, 6, 7, 8]),
    ]);
    // Non-SOLID Workbench blocks (15i9): element, type, real, mat, esys, nodes.
    s += "eblock,10,,,3\n(15i9)\n";
    for (id, ty) in [(3, 2), (4, 2), (5, 4)] {
        s += &format!(
            "{id:9}{ty:9}{ty:9}{ty:9}{:9}{:9}{:9}{:9}{:9}\n",
            0, 1, 2, 3, 4
        );
    }
    s += "-1\n";
    let m = ok(&s);
    assert_eq!(m.element_count(), 1);
    assert!(
        m.warnings
            .contains(&"skipped 2 SURF154 elements (type 2): not a 3D solid".to_string()),
        "{:?}",
        m.warnings
    );
    assert!(m
        .warnings
        .contains(&"skipped 1 CONTA174 element (type 4): not a 3D solid".to_string()));
    assert!(m.warnings.contains(
        &"skipped 1 element of type 9: no ET or ETBLOCK defines element type 9".to_string()
    ));
    assert!(m.warnings.contains(
        &"skipped 1 element of type 7 (element number 999, which this reader does not know): \
          not a 3D solid"
            .to_string()
    ));
}

#[test]
fn non_solid_layout_hex20_continues() {
    let mut s = String::from("ET,1,186\n");
    s += &nblock(&cube_nodes());
    s += "EBLOCK,10,,,1\n(15i9)\n";
    let mut line = String::new();
    for v in [77, 1, 1, 1, 0, 1, 2, 3, 4, 5, 6, 7, 8, 101, 102] {
        line += &format!("{v:9}");
    }
    s += &line;
    s += "\n";
    for v in 103..=112 {
        s += &format!("{v:9}");
    }
    s += "\n-1\n";
    let m = ok(&s);
    assert_eq!(m.element_kinds, vec![ElementKind::Hex20]);
    assert_eq!(m.element_ids, vec![77]);
    assert_eq!(file_nodes(&m, 0)[19], 112);
}

#[test]
fn mesh200_keyopt_and_etblock() {
    let mut s = String::from("ET,1,200\nKEYOP,1,1,10\nET,2,200,6\n");
    s += "ETBLOCK,        1,        1\n(2i9,19a9)\n        3      200        8        0\n       -1\n";
    s += &nblock(&cube_nodes());
    s += &eblock(&[
        (1, 1, &[1, 2, 3, 4, 5, 6, 7, 8]),
        (2, 2, &[1, 2, 3]),
        (3, 3, &[1, 2, 4, 5]),
    ]);
    let m = ok(&s);
    assert_eq!(m.element_kinds, vec![ElementKind::Hex8, ElementKind::Tet4]);
    assert!(m.warnings.contains(
        &"skipped 1 MESH200 element (type 2): KEYOPT(1) = 6 is not a 3D shape".to_string()
    ));
}

#[test]
fn compact_eblock_takes_type_from_type_command() {
    let mut s = String::from("et,1,187\net,2,185\n");
    s += &nblock(&cube_nodes());
    s += "MAT,1 $ type,1 $ REAL,1 ! tets\n";
    s += "eblock,5,COMPACT,,2\n(5i9)\n";
    s += &format!("{:9}{:9}{:9}{:9}{:9}\n", 31, 1, 2, 4, 5);
    s += &format!("{:9}{:9}{:9}{:9}{:9}\n", 32, 2, 3, 4, 7);
    s += "-1\n";
    // A hex whose record wraps: 9 fields over lines of 5.
    s += "TYPE,2\neblock,9,compact\n(5i9)\n";
    s += &format!(
        "{:9}{:9}{:9}{:9}{:9}\n{:9}{:9}{:9}{:9}\n",
        33, 1, 2, 3, 4, 5, 6, 7, 8
    );
    s += "-1\n";
    let m = ok(&s);
    assert_eq!(
        m.element_kinds,
        vec![ElementKind::Tet4, ElementKind::Tet4, ElementKind::Hex8]
    );
    assert_eq!(m.element_ids, vec![31, 32, 33]);
    assert_eq!(file_nodes(&m, 2), vec![1, 2, 3, 4, 5, 6, 7, 8]);
}

#[test]
fn cmblock_ranges_and_sets() {
    let mut s = String::from("ET,1,185\n");
    s += &nblock(&cube_nodes());
    s += &eblock(&[
        (1, 17, &[1, 2, 3, 4, 5, 6, 7, 8]),
        (1, 18, &[1, 2, 3, 4, 5, 6, 7, 9]),
        (1, 21, &[1, 2, 3, 4, 9, 9, 9, 9]),
    ]);
    s += "CMBLOCK,ECOMP1  ,ELEM,       4  ! users element component definition\n(8i10)\n";
    s += "        17       -18        21       -40\n";
    // Node ranges split across lines: a line may start with a negative item.
    s += "CMBLOCK,NCOMP,NODE,       5\n(8i10)\n         1        -3         9\n      -103         5\n";
    s += "cmblo,EMPTY,NODE,0\n(8i10)\n";
    let m = ok(&s);
    let names: Vec<&str> = m.sets.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, vec!["ECOMP1", "NCOMP", "EMPTY"]);
    assert_eq!(m.sets[0].elements, Some(vec![0, 1, 2]));
    assert_eq!(m.sets[0].nodes, None);
    // 1..3, 9..103 (9, 101, 102, 103 defined), 5 → dense indices.
    let ncomp: Vec<u64> = m.sets[1]
        .nodes
        .iter()
        .flatten()
        .map(|&i| m.node_ids[i as usize])
        .collect();
    assert_eq!(ncomp, vec![1, 2, 3, 5, 9, 101, 102, 103]);
    assert_eq!(m.sets[1].elements, None);
    assert_eq!(m.sets[2].nodes, Some(vec![]));
    assert!(m
        .warnings
        .iter()
        .any(|w| w.starts_with("component ECOMP1: 19 of 22 element numbers")));
    assert!(m
        .warnings
        .iter()
        .any(|w| w.starts_with("component NCOMP: 91 of 99 node numbers")));
}

#[test]
fn cmblock_errors() {
    let base = nblock(&[(1, [0.0; 3])]);
    let e = err(&format!(
        "{base}CMBLOCK,A,NODE,3\n(8i10)\n       -1         2\n"
    ));
    assert_eq!(line_of(&e), 7);
    assert!(
        e.to_string().contains("a positive item before a negative"),
        "{e}"
    );
    let e = err(&format!(
        "{base}CMBLOCK,A,NODE,3\n(8i10)\n         5        -2\n"
    ));
    assert!(e.to_string().contains("a range end above 5"), "{e}");
    let e = err(&format!(
        "{base}CMBLOCK,A,NODE,3\n(8i10)\n         1         2\nFINISH\n"
    ));
    assert_eq!(line_of(&e), 8);
    assert!(e.to_string().contains("1 more items of component A"), "{e}");
    let e = err(&format!(
        "{base}CMBLOCK,A,NODE,1\n(8i10)\n         1         2\n"
    ));
    assert!(e.to_string().contains("more items on this line"), "{e}");
    let e = err(&format!("{base}CMBLOCK,A,NODE\n(8i10)\n"));
    assert!(e.to_string().contains("NUMITEMS"), "{e}");
}

#[test]
fn several_blocks_terminators_and_abbreviations() {
    let s = "/prep7\n\
             nblo,3,,2\n(1i9,3e20.9e3)\n\
             \x20       1     0.000000000E+00\n\n\
             \x20       2     1.000000000E+00\n\
             N,R5.3,LOC,-1,\nN,R5.1,LOC,-1,\n\n\
             nblock,3\n(1i9,3e20.9e3)\n\
             \x20       3     0.000000000E+00     1.000000000E+00\n\
             \x20       4     0.000000000E+00     0.000000000E+00     1.000000000E+00\n\
             -1\n\
             et,1,SOLID285\n\
             eblo,19,solid,,1\n(19i9)\n\
             \x20       1        1        1        1        0        0        0        0        4        0        1        1        2        3        4\n\n\
             \x20      -1\n";
    let m = ok(s);
    assert_eq!(m.node_ids, vec![1, 2, 3, 4]);
    assert_eq!(m.element_kinds, vec![ElementKind::Tet4]);
    assert!(positive_volume(&m, 0));
}

#[test]
fn comments_quotes_and_unreadable_et() {
    let s = "*SET,_GUI,' a!b$c '   ! a comment with $ and ,\n\
             ET,1,SOLID186 $ ET,2,??? ! the second is unreadable\n\
             nblock,3\n\
             ! a comment before the format line\n\
             (1i9,3e20.9e3)\n\
             \x20       1     1.000000000E+00\n\
             -1\n";
    let m = ok(s);
    assert_eq!(m.coords, vec![[1.0, 0.0, 0.0]]);
    assert!(
        m.warnings
            .iter()
            .any(|w| w.starts_with("line 2: ET command ignored")),
        "{:?}",
        m.warnings
    );
}

#[test]
fn etblock_rows_separated_by_single_blanks() {
    // mapdl-archive's `use_etblock` writes the integers one blank apart under `(2i9,19a9)`.
    let mut s = String::from("ETBLOCK,1,0\n(2i9,19a9)\n        1 185 0 0 0 0\n-1\n");
    s += &nblock(&cube_nodes());
    s += &eblock(&[(1, 1, &[1, 2, 3, 4, 5, 6, 7, 8])]);
    let m = ok(&s);
    assert_eq!(m.element_kinds, vec![ElementKind::Hex8]);
    assert!(
        m.warnings
            .iter()
            .any(|w| w.contains("ETBLOCK rows are not in the columns")),
        "{:?}",
        m.warnings
    );
    // A row that is neither in columns nor integers is still an error.
    let e = err("ETBLOCK,1,0\n(2i9,19a9)\n        1 SOLID185\n-1\n");
    assert_eq!(line_of(&e), 3);
}

#[test]
fn empty_continuation_line_means_no_midside_nodes() {
    let mut s = String::from("ET,1,186\n");
    s += &nblock(&cube_nodes());
    s += "EBLOCK,19,SOLID\n(19i8)\n";
    s += "       1       1       1       1       0       0       0       0      20       0       1       1       2       3       4       5       6       7       8\n\n      -1\n";
    let m = ok(&s);
    assert_eq!(m.element_kinds, vec![ElementKind::Hex8]);
    assert_eq!(m.element_count(), 1);
}
