//! Unit tests on small hand-written snippets.

use std::path::Path;

use super::format::{Format, Kind};
use super::read;
use crate::error::{ImportError, Location};
use crate::mesh::{ElementKind, Mesh, MISSING_NODE};

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
fn format_lines() {
    let f = fmt(b"(3i9,6e21.13e3)");
    assert_eq!(f.columns.len(), 9);
    assert_eq!(f.width, 27 + 6 * 21);
    let Some(l) = f.node_layout() else {
        panic!("no node layout")
    };
    assert_eq!(l.id.width, 9);
    assert_eq!(l.coords[0].map(|c| c.start), Some(27));
    assert_eq!(l.coords[2].map(|c| (c.start, c.width)), Some((69, 21)));

    let f = fmt(b"(1i7,2i9,6e21.13)");
    assert_eq!(f.columns[0].width, 7);
    assert_eq!(f.columns[1].start, 7);
    assert_eq!(
        f.node_layout().and_then(|l| l.coords[0]).map(|c| c.start),
        Some(25)
    );

    let f = fmt(b" ( 2i9 , 19a9 ) ");
    assert_eq!(f.columns.len(), 21);
    assert_eq!(f.columns[2].kind, Kind::Text);
    assert!(!f.all_int());
    assert!(Format::parse(b"(19i10)").is_some_and(|f| f.all_int() && f.width == 190));
    assert!(Format::parse(b"(8i10)").is_some());
    assert!(Format::parse(b"(3i8,6e16.9)").is_some());
    assert!(Format::parse(b"(1i9,3e20.9e3)").is_some());
    assert!(Format::parse(b"(2i8,6g16.9)").is_some());
    let f = fmt(b"(1i9,1p,3e20.9)");
    assert_eq!(f.columns.len(), 4);
    let f = fmt(b"(i8,2x,1p3e16.9)");
    assert_eq!(f.columns[1].start, 10);
    // Not format lines, or absurd ones.
    for bad in [
        &b"(abc)"[..],
        b"3i9,6e21.13",
        b"(3i9,6e21.13",
        b"()",
        b"(999999i9)",
        b"(3i0)",
        b"NBLOCK,6,SOLID",
    ] {
        assert!(
            Format::parse(bad).is_none(),
            "{}",
            String::from_utf8_lossy(bad)
        );
    }
}

#[test]
fn numbers_run_together_and_omitted_zeros() {
    let m = ok("NBLOCK,6,SOLID,       4,       4\n\
                (3i8,6e20.13)\n\
                \x20    635       0       0 3.7826539829200E+00 1.2788958692644E+00-1.0220880953640E+00\n\
                \x20      2      21       0-5.0000000000000E-01-2.5000000000000E-01\n\
                \x20      3       0       0 1.0000000000000E+00\n\
                \x20      4       0       0\n\
                N,R5.3,LOC,       -1,\n");
    assert_eq!(m.node_ids, vec![635, 2, 3, 4]);
    assert_eq!(
        m.coords[0],
        [3.78265398292, 1.2788958692644, -1.022088095364]
    );
    assert_eq!(m.coords[1], [-0.5, -0.25, 0.0]);
    assert_eq!(m.coords[2], [1.0, 0.0, 0.0]);
    assert_eq!(m.coords[3], [0.0, 0.0, 0.0]);
    assert!(m.warnings.iter().any(|w| w.contains("no 3D solid")));
}

#[test]
fn exponent_spellings_and_one_integer_column() {
    // Workbench (1i9,3e20.9e3), lowercase commands, D and lowercase exponents, plain decimals,
    // the letterless exponent of Ew.d beyond 99, a bare -1 terminator.
    let rec = |id: u32, fields: [&str; 3]| {
        let mut s = format!("{id:9}");
        for f in fields {
            s += &format!("{f:>20}");
        }
        s + "\n"
    };
    let mut s = String::from("nblock,3\n(1i9,3e20.9e3)\n");
    s += &rec(
        1,
        ["2.500000000D-02", "2.500000000e-02", "-1.000000000E-03"],
    );
    s += &rec(2, ["-6.01203", "0.5", "1.0000000000-100"]);
    s += "-1\n";
    let m = ok(&s);
    assert_eq!(m.coords[0], [0.025, 0.025, -0.001]);
    assert_eq!(m.coords[1], [-6.01203, 0.5, 1.0e-100]);
    let mut s = String::from("nblock,3\n(1i9,3e20.9e3)\n");
    s += &rec(1, ["0.5", "0.5x", "0"]);
    let e = err(&s);
    assert_eq!(line_of(&e), 3);
    assert!(
        e.to_string()
            .contains("the y coordinate of node 1 in columns 30-49"),
        "{e}"
    );
    assert!(e.to_string().contains("found '0.5x'"), "{e}");
}

#[test]
fn letterless_exponent() {
    let m = ok("nblock,3\n(1i9,3e20.9e3)\n        1    1.0000000000-100     2.500000000+101\n-1\n");
    assert_eq!(m.coords[0], [1.0e-100, 2.5e101, 0.0]);
}

#[test]
fn hypermesh_fields_crlf_no_final_newline() {
    let m = ok("!! HyperMesh\r\n\
                NBLOCK,6,SOLID,3\r\n\
                (3i8,6e16.9)\r\n\
                \x20      1       0       0        -6.01203         2.98129         2.38556 \r\n\
                \x20      2       0       0              1.             0.0             0.0\r\n\
                \x20      3       0       0             0.0              1.\r\n\
                \x20      4       0       0             0.0             0.0              1.\r\n\
                N,R5.3,LOC,     -1,\r\n\
                ET,1,185\r\n\
                TYPE, 1  $ MAT, 1  $ REAL, 1\r\n\
                EBLOCK,19,SOLID      ,1\r\n\
                (19i8)\r\n\
                \x20      1       1       1       0       0       0       0      0        8       0       7       1       2       3       3       4       4       4       4\r\n\
                \x20     -1");
    assert_eq!(m.coords[0], [-6.01203, 2.98129, 2.38556]);
    assert_eq!(m.element_kinds, vec![ElementKind::Tet4]);
    assert_eq!(file_nodes(&m, 0), vec![1, 2, 3, 4]);
    assert_eq!(m.element_ids, vec![7]);
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
fn huge_declared_counts_and_ranges() {
    let mut s =
        String::from("NBLOCK,6,SOLID,999999999999999999,999999999999999999\n(3i9,6e21.13e3)\n");
    s += "        1        0        0 1.0\n        2        0        0 2.0\nN,R5.3,LOC,-1,\n";
    s += "EBLOCK,19,SOLID,99999999999999,99999999999999\n(19i9)\n-1\n";
    s += "CMBLOCK,ALL,NODE,2\n(8i10)\n         1-999999999\n";
    let m = ok(&s);
    assert_eq!(m.node_count(), 2);
    assert_eq!(m.sets[0].nodes, Some(vec![0, 1]));
    // A CMBLOCK that promises 10^18 items and ends.
    let e = err(&format!(
        "{s}CMBLOCK,B,NODE,1000000000000000000\n(8i10)\n         1"
    ));
    assert!(e.to_string().contains("end of file"), "{e}");
    // A node count beyond anything a record holds.
    let mut t = String::from("ET,1,185\n");
    t += &nblock(&cube_nodes());
    t += "EBLOCK,19,SOLID\n(19i9)\n        1        1        1        1        0        0        0        0999999999        0        1\n";
    let e = err(&t);
    assert!(
        e.to_string()
            .contains("a node count between 0 and 27 in field 9"),
        "{e}"
    );
}

#[test]
fn truncated_inputs_give_located_errors() {
    // NBLOCK cut after a record (no terminator).
    let e = err(
        "/PREP7\nNBLOCK,6,SOLID,  4961, 4961\n(3i9,6e21.13e3)\n        1        0        0 1.0\n",
    );
    assert_eq!(line_of(&e), 5);
    assert!(e.to_string().contains("found end of file"), "{e}");
    // NBLOCK cut in the middle of a number.
    let e = err("NBLOCK,6,SOLID\n(3i9,6e21.13e3)\n        1        0        0 3.0000000000000E-001 8.0000000E");
    assert_eq!(line_of(&e), 3);
    // Header without its format line.
    let e = err("NBLOCK,6,SOLID");
    assert!(e.to_string().contains("the NBLOCK format line"), "{e}");
    assert_eq!(line_of(&e), 2);
    // A 20-node record whose continuation line is missing.
    let mut s = String::from("ET,1,186\n");
    s += &nblock(&cube_nodes());
    let full = s.clone();
    s += "EBLOCK,19,SOLID\n(19i9)\n";
    s += "        1        1        1        1        0        0        0        0       20        0        1        1        2        3        4        5        6        7        8\n";
    let e = err(&s);
    assert!(
        e.to_string()
            .contains("the continuation line with nodes 9-20 of element 1"),
        "{e}"
    );
    assert!(e.to_string().contains("end of file"), "{e}");
    let e = err(&format!("{s}       -1\n"));
    assert!(e.to_string().contains("found '-1'"), "{e}");
    // EBLOCK at the end of the file without -1 is accepted (etblock.cdb).
    let m = ok(&format!(
        "{full}EBLOCK,19,SOLID\n(19i9)\n        1        1        1        1        0        0        0        0        8        0        1        1        2        3        4        5        6        7        8"
    ));
    assert_eq!(m.element_count(), 1);
}

#[test]
fn nul_bytes_are_corruption() {
    let mut data = b"NBLOCK,6,SOLID\n(3i9,6e21.13e3)\n        1        0        0 1.0\n".to_vec();
    data.extend_from_slice(&[0u8; 333]);
    let e = err(&String::from_utf8_lossy(&data));
    assert_eq!(line_of(&e), 4);
    assert!(
        e.to_string().contains("found NUL bytes from column 1"),
        "{e}"
    );
    let mut data =
        b"NBLOCK,6,SOLID\n(3i9,6e21.13e3)\n        1        0        0 3.0000000".to_vec();
    data.extend_from_slice(&[0u8; 20]);
    let e = err(&String::from_utf8_lossy(&data));
    assert_eq!(line_of(&e), 3);
}

#[test]
fn undefined_and_repeated_nodes() {
    let mut s = String::from("ET,1,185\n");
    s += &nblock(&cube_nodes());
    let e = err(&format!(
        "{s}{}",
        eblock(&[(1, 1, &[1, 2, 3, 4, 5, 6, 7, 1234])])
    ));
    assert_eq!(
        e.to_string(),
        format!(
            "t.cdb:{}: expected a node defined in an NBLOCK, found node 1234",
            s.lines().count() + 3
        )
    );
    let e = err(&format!("{s}{}", nblock(&[(7, [0.0; 3])])));
    let first = 3 + 7; // ET, NBLOCK header, format line, then nodes 1..7
    assert!(
        e.to_string().contains(&format!(
            "found node 7 again (first defined on line {first})"
        )),
        "{e}"
    );
    assert_eq!(line_of(&e), s.lines().count() + 3);
    let e = err(&format!(
        "{s}{}",
        eblock(&[
            (1, 5, &[1, 2, 3, 4, 5, 6, 7, 8]),
            (1, 5, &[1, 2, 3, 4, 5, 6, 7, 8])
        ])
    ));
    assert!(e.to_string().contains("element 5 again"), "{e}");
}

#[test]
fn malformed_records() {
    let mut s = String::from("ET,1,185\n");
    s += &nblock(&cube_nodes());
    let n = s.lines().count();
    // Corner node 0.
    let e = err(&format!(
        "{s}{}",
        eblock(&[(1, 1, &[1, 2, 3, 0, 5, 6, 7, 8])])
    ));
    assert!(
        e.to_string().contains("corner 4 of SOLID185 element 1"),
        "{e}"
    );
    assert_eq!(line_of(&e), n + 3);
    // Too few nodes for a brick.
    let e = err(&format!("{s}{}", eblock(&[(1, 1, &[1, 2, 3, 4])])));
    assert!(e.to_string().contains("at least 8 nodes"), "{e}");
    // A letter inside a field.
    let e = err(&format!(
        "{s}EBLOCK,19,SOLID\n(19i9)\n        1        1       x1\n"
    ));
    assert!(
        e.to_string()
            .contains("an integer in columns 19-27, found 'x1'"),
        "{e}"
    );
    // Fewer than 11 leading fields.
    let e = err(&format!(
        "{s}EBLOCK,19,SOLID\n(19i9)\n        1        1        1\n"
    ));
    assert!(e.to_string().contains("the 11 leading fields"), "{e}");
    // More nodes than field 9 says.
    let e = err(&format!(
        "{s}EBLOCK,19,SOLID\n(19i9)\n        1        1        1        1        0        0        0        0        4        0        1        1        2        3        4        5\n"
    ));
    assert!(
        e.to_string()
            .contains("4 node numbers after the 11 leading fields"),
        "{e}"
    );
    // Unknown EBLOCK key, bad format line.
    assert!(err(&format!("{s}EBLOCK,19,LONG\n(19i9)\n"))
        .to_string()
        .contains("EBLOCK key"));
    let e = err(&format!("{s}EBLOCK,19,SOLID\n19i9\n"));
    assert!(
        e.to_string()
            .contains("the EBLOCK format line, such as '(19i9)', found '19i9'"),
        "{e}"
    );
    // Unsupported collapse is skipped with a warning.
    let m = ok(&format!(
        "{s}{}",
        eblock(&[(1, 1, &[1, 1, 3, 4, 5, 6, 7, 8])])
    ));
    assert_eq!(m.element_count(), 0);
    assert!(m
        .warnings
        .iter()
        .any(|w| w.contains("form no hex, wedge, pyramid or tet")));
}

#[test]
fn no_nodes_is_an_error() {
    let e = err("/COM,parameters only\n*DIM,A,ARRAY,2\n*PREAD,A\n1.0\n2.0\nEND PREAD\n");
    assert_eq!(e.location, Location::File);
    assert!(e.to_string().contains("holds no nodes"), "{e}");
    assert!(err("").to_string().contains("holds no nodes"));
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
