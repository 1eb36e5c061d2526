//! Format lines and the numbers read by them: widths, exponents, fields run together.

use super::*;
use crate::cdb::format::Kind;

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
