//! Located errors on malformed and truncated decks, and decks corrupted byte by byte.

use super::*;

#[test]
fn structure_errors_are_located() {
    let e = fail(&format!("*Part, name=P\n{HEX}"));
    assert!(e.expected.contains("*END PART"), "{e}");
    assert_eq!(line_of(&e), 10);
    let e = fail("*NODE\n1,0,0,0\n*End Part\n");
    assert_eq!(line_of(&e), 3);
    let e = fail("*Part, name=P\n*Part, name=Q\n");
    assert_eq!(line_of(&e), 2);
    let e = fail("*Assembly, name=A\n*Instance, name=I, part=Nope\n*End Instance\n*End Assembly\n");
    assert_eq!(line_of(&e), 2);
    assert!(e.found.contains("Nope"));
    let e = fail(&format!(
        "*Part, name=P\n{HEX}*End Part\n*Instance, name=I, part=P\n"
    ));
    assert_eq!(line_of(&e), 12);
    let e = fail("*Part\n");
    assert!(e.expected.contains("NAME="), "{e}");
    let e = fail("*Element\n1, 1, 2, 3, 4\n");
    assert!(e.expected.contains("TYPE="), "{e}");
    let e = fail("*Part, name=\"P\n");
    assert_eq!(line_of(&e), 1);
    let e = fail("*NODE, NSET=\"a\" b\n");
    assert_eq!(line_of(&e), 1);
    // Unmodelled keywords with odd lines are skipped, not refused.
    let m = ok("*NODE\n1,0,0,0\n*Surface, name=\"odd\" x\n1, S1\n*NGENX\n");
    assert_eq!(m.node_count(), 1);
    let e = fail("*NODE\n1,0,0,0\n*NGEN, NSET=X\n1, 5\n");
    assert_eq!(line_of(&e), 3);
}

#[test]
fn a_set_of_gmsh_entity_tags_written_by_meshio_is_named() {
    // meshio's Abaqus writer turns the cell set its gmsh reader makes of the entity tags
    // into an *ELSET (here as meshio 5.3 writes it: 0, -1, 4, 3).
    let e = fail(&format!(
        "{HEX}*ELEMENT, TYPE=C3D8\n1, 1,2,3,4,5,6,7,8\n*ELSET, ELSET=gmsh:bounding_entities\n0,-1,4,3\n"
    ));
    assert_eq!(line_of(&e), 13, "{e}");
    assert!(e.expected.contains("'gmsh:bounding_entities'"), "{e}");
    assert!(e.expected.contains("meshio"), "{e}");
    assert!(e.found.contains('0'), "{e}");
    let e = fail(&format!(
        "{HEX}*ELEMENT, TYPE=C3D8\n1, 1,2,3,4,5,6,7,8\n*ELSET, ELSET=mine\n1, 0\n"
    ));
    assert!(
        e.expected.contains("'mine'") && !e.expected.contains("meshio"),
        "{e}"
    );
}

#[test]
fn bad_elements_are_located() {
    // Undefined node.
    let e = fail(&format!(
        "{HEX}*ELEMENT, TYPE=C3D8\n1, 1,2,3,4,5,6,7,8\n2, 1,2,3,4,5,6,7,99\n"
    ));
    assert_eq!(line_of(&e), 12);
    assert!(e.found.contains("99"), "{e}");
    // Undefined node inside a part, reported in the part.
    let e = fail(&format!(
        "*Part, name=P\n{HEX}*ELEMENT, TYPE=C3D8\n7, 1,2,3,4,5,6,7,9\n*End Part\n"
    ));
    assert_eq!(line_of(&e), 12);
    // Repeated element label.
    let e = fail(&format!(
        "{HEX}*ELEMENT, TYPE=C3D8\n1, 1,2,3,4,5,6,7,8\n*ELEMENT, TYPE=C3D4\n1, 1,2,3,5\n"
    ));
    assert_eq!(line_of(&e), 13);
    assert!(e.found.contains("test.inp:11"), "{e}");
    // Corner node 0; mid-side 0 is accepted.
    let e = fail(&format!("{HEX}*ELEMENT, TYPE=C3D4\n1, 1,0,3,5\n"));
    assert_eq!(line_of(&e), 11);
    let mut deck = String::from("*NODE\n");
    for i in 1..=10 {
        deck.push_str(&format!("{i}, {i}, {}, 0\n", i % 3));
    }
    let m = ok(&format!(
        "{deck}*ELEMENT, TYPE=C3D10\n1, 1,2,3,4,5,0,7,8,9,10\n"
    ));
    assert_eq!(m.element(0).nodes[5], MISSING_NODE);
    // Garbled node number, empty middle field, bad label.
    let e = fail(&format!("{HEX}*ELEMENT, TYPE=C3D8\n1, 1,2,3,4,5,6,7,x8\n"));
    assert_eq!(line_of(&e), 11);
    let e = fail(&format!("{HEX}*ELEMENT, TYPE=C3D8\n1, 1,2,,4,5,6,7,8\n"));
    assert_eq!(line_of(&e), 11);
    let e = fail(&format!("{HEX}*ELEMENT, TYPE=C3D8\n-1, 1,2,3,4,5,6,7,8\n"));
    assert_eq!(line_of(&e), 11);
}

#[test]
fn unknown_solid_types_are_refused_at_the_element_line() {
    // No Abaqus solid is called C3D7: refused at its *ELEMENT line (10), not read with a
    // guessed 7 nodes and blamed on a later line.
    for ty in ["C3D7", "C3D99", "dc3d7", "C3D"] {
        let e = fail(&format!(
            "{HEX}*ELEMENT, TYPE={ty}, ELSET=V\n1, 1,2,3,4,5,6,7,\n8\n*ELSET, ELSET=X\n1\n"
        ));
        assert_eq!(line_of(&e), 10, "{e}");
        let upper = ty.to_ascii_uppercase();
        assert!(e.found.contains(&format!("TYPE={upper},")), "{e}");
        assert!(
            e.expected.contains("C3D8") && e.expected.contains("C3D10"),
            "{e}"
        );
    }
    // An unknown type of no solid family is still consumed and dropped with a warning.
    let m = ok(&format!(
        "{HEX}*ELEMENT, TYPE=C3D8\n1, 1,2,3,4,5,6,7,8\n*ELEMENT, TYPE=FOO4\n2, 1,2,3,4\n"
    ));
    assert_eq!(m.element_count(), 1);
    assert!(
        m.warnings.iter().any(|w| w.contains("FOO4")),
        "{:?}",
        m.warnings
    );
}

#[test]
fn overlong_records_are_counted_over_all_their_lines() {
    // Gmsh writes 18-node prisms as C3D6, 15 node numbers on the first line and 3 on the next.
    let mut nodes = String::from("*NODE\n");
    for i in 1..=18 {
        nodes.push_str(&format!("{i}, {i}, 0, 0\n"));
    }
    let head = format!("{nodes}*ELEMENT, TYPE=C3D6, ELSET=V\n"); // element on line 21
    let first = "1, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, \n";
    for tail in [
        "16, 17, 18\n*ELSET, ELSET=X\n1\n",
        "16, 17, 18,\n*ELSET, ELSET=X\n1\n",
        "16, 17, 18,",
    ] {
        let e = fail(&format!("{head}{first}{tail}"));
        assert_eq!(line_of(&e), 21, "{e}");
        assert_eq!(e.expected, "6 node numbers for element 1 of type C3D6");
        assert_eq!(e.found, "18 node numbers on lines 21-22", "{e}");
    }
    // A record on one line is counted as before.
    let e = fail(&format!("{head}1, 1, 2, 3, 4, 5, 6, 7\n"));
    assert_eq!(line_of(&e), 21, "{e}");
    assert_eq!(e.found, "7 node numbers");
}

#[test]
fn truncated_inputs_are_located() {
    // A record cut before its continuation line, at the end of the file and before a keyword.
    let e = fail(&format!("{HEX}*ELEMENT, TYPE=C3D8\n1, 1,2,3,4,"));
    assert_eq!(line_of(&e), 11);
    assert_eq!(e.found, "end of file");
    let e = fail(&format!(
        "{HEX}*ELEMENT, TYPE=C3D8\n1, 1,2,3,4,\n*NSET, NSET=X\n1\n"
    ));
    assert_eq!(line_of(&e), 12);
    assert!(e.expected.contains("4 more node numbers"), "{e}");
    // Data before any keyword, NUL padding, an empty file.
    let e = fail("1, 0, 0, 0\n*NODE\n");
    assert_eq!(line_of(&e), 1);
    let e = fail("*NODE\n1, 0, 0, 0\n2, 1, 0\0\0\0\0\n");
    assert_eq!(line_of(&e), 3);
    let e = fail("*NODE\n1, 0, 0, 0\n\0\0\0\0\0\0\0\n");
    assert_eq!(e.found, "NUL bytes");
    let e = fail("");
    assert!(e.to_string().contains("expected"));
    let e = fail("** only a comment\n*HEADING\n");
    assert!(e.found.contains("no nodes"));
}

/// Every prefix and many one-byte corruptions of a deck give a mesh or a located error,
/// never a panic.
#[test]
fn truncation_and_corruption_never_panic() {
    let deck = "*Heading\n*Part, name=\"P 1\"\n*Node, nset=N\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n\
                5, 1, 1, 1\n*Element, type=C3D10, elset=E\n1, 1, 2, 3, 4, 5, 5,\n5, 5, 5, 5\n*Nset, nset=G, generate\n1, 5, 2\n\
                *End Part\n*Assembly, name=A\n*Instance, name=I, part=\"P 1\"\n1, 2, 3\n0,0,0, 1,0,0, 45\n*End Instance\n\
                *Elset, elset=S, instance=I\n1,\n*Nset, nset=T\nI.3, I.N\n*End Assembly\n*Step\n*Static\n*End Step\n";
    let m = ok(deck);
    assert_eq!(m.node_count(), 5);
    let bytes = deck.as_bytes();
    for cut in 0..bytes.len() {
        let r = read(Path::new("t.inp"), &bytes[..cut]);
        if let Err(e) = r {
            assert!(!e.expected.is_empty() && !e.found.is_empty());
        }
    }
    for pos in 0..bytes.len() {
        for b in [b'*', b',', b'\n', b'"', b'0', b'x', 0u8, 0xff, b'.', b'-'] {
            let mut v = bytes.to_vec();
            v[pos] = b;
            let _ = read(Path::new("t.inp"), &v);
        }
    }
}
