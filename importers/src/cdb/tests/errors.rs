//! Located errors: huge counts, truncation, NUL bytes, undefined nodes, malformed records.

use super::*;

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
