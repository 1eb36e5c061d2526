//! Tests of the INP reader on small inline decks, plus the shared corpus when it is present.

use super::*;
use crate::mesh::{ElementKind, NamedSet, SetKind, MISSING_NODE};

mod errors;
mod files;
mod large;

fn read_str(s: &str) -> Result<Mesh, ImportError> {
    read(Path::new("test.inp"), s.as_bytes())
}

fn ok(s: &str) -> Mesh {
    match read_str(s) {
        Ok(m) => m,
        Err(e) => panic!("unexpected error: {e}"),
    }
}

fn fail(s: &str) -> ImportError {
    match read_str(s) {
        Ok(_) => panic!("expected an error"),
        Err(e) => e,
    }
}

fn line_of(e: &ImportError) -> usize {
    match e.location {
        crate::Location::Line(l) => l,
        other => panic!("no line in {e} ({other:?})"),
    }
}

fn set<'a>(m: &'a Mesh, name: &str) -> &'a NamedSet {
    m.sets.iter().find(|s| s.name == name).unwrap_or_else(|| {
        panic!(
            "no set {name} in {:?}",
            m.sets.iter().map(|s| &s.name).collect::<Vec<_>>()
        )
    })
}

fn count(s: &NamedSet) -> usize {
    s.nodes.as_ref().or(s.elements.as_ref()).map_or(0, Vec::len)
}

fn close(a: [f64; 3], b: [f64; 3]) -> bool {
    (0..3).all(|k| (a[k] - b[k]).abs() < 1e-12)
}

const HEX: &str = "*NODE\n1,0,0,0\n2,1,0,0\n3,1,1,0\n4,0,1,0\n5,0,0,1\n6,1,0,1\n7,1,1,1\n8,0,1,1\n";

#[test]
fn mixed_case_crlf_comments_and_no_final_newline() {
    let deck = "** header comment\r\n*Heading\r\nsome title, with commas\r\n\r\n*Node, Nset=All\r\n\
                1, 0., 0., 0.\r\n2,1.0e0,0,0\r\n**comment inside a block\r\n3, 0, 100.0E-2, 0\r\n   4 , 0 , 0 , 1.\r\n\
                *eLeMeNt, TyPe=C3d4, ELSET=Solid\r\n1, 1, 2, 3, 4";
    let m = ok(deck);
    assert_eq!(m.node_count(), 4);
    assert_eq!(m.element_count(), 1);
    assert_eq!(m.element_kinds[0], ElementKind::Tet4);
    assert_eq!(m.coords[2], [0.0, 1.0, 0.0]);
    assert_eq!(m.node_ids, vec![1, 2, 3, 4]);
    assert_eq!(count(set(&m, "All")), 4);
    assert_eq!(count(set(&m, "Solid")), 1);
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    // A byte-order mark and blanks before the keyword are fine too.
    let m = ok("\u{feff}  *NODE\n1,0,0,0\n");
    assert_eq!(m.node_count(), 1);
}

#[test]
fn continuation_lines_by_node_count() {
    // Hex20: 11 + 10 entries with a trailing comma (CalculiX), then 16 + 5 without one (gmsh).
    let mut deck = String::from("*NODE\n");
    for i in 1..=20 {
        deck.push_str(&format!("{i}, {}, 0, 0\n", i as f64));
    }
    deck.push_str("*ELEMENT, TYPE=C3D20R, ELSET=E\n");
    deck.push_str("1, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10,\n 11, 12, 13, 14, 15, 16, 17, 18, 19, 20\n");
    deck.push_str("** a comment between record lines\n");
    deck.push_str("2, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15\n16, 17, 18, 19, 20\n");
    deck.push_str("*ELEMENT, TYPE=C3D10\n3, 1, 2, 3, 4, 5, 6, 7,\n8, 9, 10,\n");
    let m = ok(&deck);
    assert_eq!(m.element_count(), 3);
    let e = m.element(1);
    assert_eq!(e.kind, ElementKind::Hex20);
    assert_eq!(e.nodes, (0..20).collect::<Vec<u32>>().as_slice());
    assert_eq!(m.element(2).kind, ElementKind::Tet10);
    assert_eq!(m.element(2).nodes.len(), 10);
    assert_eq!(count(set(&m, "E")), 2);
    // Too many node numbers for the type.
    let e = fail(&format!("{HEX}*ELEMENT, TYPE=C3D8\n1, 1,2,3,4,5,6,7,8,9\n"));
    assert_eq!(line_of(&e), 11);
    assert!(e.to_string().contains("8 node numbers"), "{e}");
}

#[test]
fn generate_with_and_without_increment() {
    let mut deck = String::from("*NODE, NSET=ALL\n");
    for i in 1..=20 {
        deck.push_str(&format!("{i}, {i}., 0, 0\n"));
    }
    deck.push_str("*NSET, NSET=A, GENERATE\n1, 10\n15, 20, 5\n");
    deck.push_str("*NSET,NSET=B,GENERATE\n2,20,2,\n");
    let m = ok(&deck);
    assert_eq!(
        set(&m, "A").nodes.as_deref(),
        Some(&[0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 14, 19][..])
    );
    assert_eq!(count(set(&m, "B")), 10);
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    // first > last, a zero label, a missing value: located errors.
    for (bad, line) in [
        ("5, 1", 28),
        ("0, 4", 28),
        ("7", 28),
        ("1, x", 28),
        ("1,2,3,4", 28),
    ] {
        let e = fail(&format!("{deck}*NSET, NSET=C, GENERATE\n{bad}\n"));
        assert_eq!(line_of(&e), line, "{bad}: {e}");
    }
}

#[test]
fn huge_generate_range_costs_no_memory() {
    let deck = format!(
        "{HEX}*NSET, NSET=BIG, GENERATE\n1, 100000000000000\n*ELSET, ELSET=EB, GENERATE\n1, 99999999999, 2\n\
         *ELEMENT, TYPE=C3D8\n1, 1,2,3,4,5,6,7,8\n"
    );
    let start = std::time::Instant::now();
    let m = ok(&deck);
    assert!(start.elapsed().as_secs() < 5);
    assert_eq!(count(set(&m, "BIG")), 8);
    assert_eq!(count(set(&m, "EB")), 1);
    assert!(
        m.warnings.iter().any(|w| w.contains("'BIG'")),
        "{:?}",
        m.warnings
    );
}

#[test]
fn sets_accumulate_reference_and_keep_first_spelling() {
    let deck = format!(
        "{HEX}*ELEMENT, TYPE=C3D8, ELSET=Body\n1, 1,2,3,4,5,6,7,8\n\
         *NSET, NSET=Bottom\n1, 2,\n*nset, nset=BOTTOM\n3, 4\n\
         *NSET, NSET=Top\n5,6,7,8\n*NSET, NSET=Both, UNSORTED\nbottom, Top, 1\n\
         *ELSET, ELSET=body\n1\n*ELSET, ELSET=Copy, INTERNAL\nBODY\n\
         *NSET, NSET=Corners, ELSET=Body\n*NSET, NSET=Bad\nNoSuchSet, 2\n"
    );
    let m = ok(&deck);
    let names: Vec<(&str, SetKind)> = m.sets.iter().map(|s| (s.name.as_str(), s.kind)).collect();
    assert_eq!(
        names,
        vec![
            ("Bottom", SetKind::NodeSet),
            ("Top", SetKind::NodeSet),
            ("Both", SetKind::NodeSet),
            ("Corners", SetKind::NodeSet),
            ("Bad", SetKind::NodeSet),
            ("Body", SetKind::ElementSet),
            ("Copy", SetKind::ElementSet),
        ]
    );
    assert_eq!(count(set(&m, "Bottom")), 4);
    assert_eq!(count(set(&m, "Both")), 8);
    assert_eq!(count(set(&m, "Body")), 1);
    assert!(set(&m, "Body").nodes.is_none());
    assert!(set(&m, "Top").elements.is_none());
    assert_eq!(count(set(&m, "Copy")), 1);
    assert_eq!(count(set(&m, "Corners")), 8);
    assert_eq!(count(set(&m, "Bad")), 1);
    assert!(
        m.warnings.iter().any(|w| w.contains("NoSuchSet")),
        "{:?}",
        m.warnings
    );
    // Undefined labels are left out with a warning.
    let m = ok(&format!("{HEX}*NSET, NSET=S\n1, 99\n"));
    assert_eq!(count(set(&m, "S")), 1);
    assert!(
        m.warnings.iter().any(|w| w.contains("99")),
        "{:?}",
        m.warnings
    );
    // A label that is not a number.
    let e = fail(&format!("{HEX}*NSET, NSET=S\n1, 2.5\n"));
    assert_eq!(line_of(&e), 11);
}

#[test]
fn two_and_one_coordinate_nodes_and_blank_fields() {
    let m = ok("*NODE\n1, 1., 2.\n2, 3.\n3, , 4., \n4\n5, 1, 2, 3, 0, 0, 1\n");
    assert_eq!(
        m.coords,
        vec![
            [1.0, 2.0, 0.0],
            [3.0, 0.0, 0.0],
            [0.0, 4.0, 0.0],
            [0.0; 3],
            [1.0, 2.0, 3.0]
        ]
    );
    let e = fail("*NODE\n1, 1., 2.\n2, 1, 2, 3, 4, 5, 6, 7\n");
    assert_eq!(line_of(&e), 3);
    let e = fail("*NODE\n1, 1., abc\n");
    assert_eq!(line_of(&e), 2);
    assert!(e.found.contains("abc"), "{e}");
    let e = fail("*NODE\nx, 1., 2.\n");
    assert!(e.expected.contains("node label"), "{e}");
}

#[test]
fn redefined_node_takes_last_coordinates() {
    let m = ok("*NODE\n1, 0, 0, 0\n1, 5, 0, 0\n");
    assert_eq!(m.node_count(), 1);
    assert_eq!(m.coords[0], [5.0, 0.0, 0.0]);
    assert_eq!(m.warnings.len(), 1);
}

#[test]
fn cylindrical_nodes_and_local_system() {
    let m = ok("*NODE, SYSTEM=C\n1, 2., 90., 3.\n");
    assert!(close(m.coords[0], [0.0, 2.0, 3.0]), "{:?}", m.coords[0]);
    let e = fail("*NODE, SYSTEM=S\n1, 2., 90., 3.\n");
    assert_eq!(line_of(&e), 1);
    // *SYSTEM: translation, then a rotated system (x1 along global Y, y1 along -X).
    let m = ok("*SYSTEM\n10, 0, 0\n*NODE\n1, 1, 2, 3\n*SYSTEM\n0,0,0, 0,1,0\n*NODE\n2, 1, 0, 0\n3, 0, 1, 0\n*SYSTEM\n*NODE\n4, 1, 1, 1\n");
    assert!(close(m.coords[0], [11.0, 2.0, 3.0]));
    assert!(close(m.coords[1], [0.0, 1.0, 0.0]), "{:?}", m.coords[1]);
    assert!(close(m.coords[2], [-1.0, 0.0, 0.0]), "{:?}", m.coords[2]);
    assert!(close(m.coords[3], [1.0, 1.0, 1.0]));
    // Three points: x1 along Z, x-y plane through +X.
    let m = ok("*SYSTEM\n0,0,0, 0,0,2\n1,0,0\n*NODE\n1, 1, 0, 0\n2, 0, 1, 0\n3, 0, 0, 1\n");
    assert!(close(m.coords[0], [0.0, 0.0, 1.0]));
    assert!(close(m.coords[1], [1.0, 0.0, 0.0]));
    assert!(close(m.coords[2], [0.0, 1.0, 0.0]));
}

#[test]
fn shells_and_other_types_are_consumed_with_one_warning_per_type() {
    let deck = format!(
        "{HEX}*ELEMENT, TYPE=C3D8, ELSET=SOLID\n1, 1,2,3,4,5,6,7,8\n\
         *ELEMENT, TYPE=S4R, ELSET=SKIN\n10, 1, 2, 3, 4\n11, 5, 6, 7, 8\n\
         *ELEMENT, TYPE=S8R, ELSET=SKIN\n12, 1, 2, 3, 4,\n5, 6, 7, 8\n\
         *ELEMENT, TYPE=B32, ELSET=BEAM\n13, 1, 2, 3\n\
         *ELEMENT, TYPE=MASS, ELSET=PT\n14, 1\n\
         *ELEMENT, TYPE=U1, ELSET=USER\n15, 1, 2, 3,\n4, 5\n16, 1\n\
         *ELEMENT, TYPE=CPS3\n17, 1, 2, 3\n"
    );
    let m = ok(&deck);
    let kinds: Vec<ElementKind> = m.element_kinds.clone();
    assert_eq!(
        kinds,
        vec![
            ElementKind::Hex8,
            ElementKind::Quadrilateral,
            ElementKind::Quadrilateral,
            ElementKind::Quadrilateral,
            ElementKind::Line,
            ElementKind::Triangle,
        ]
    );
    // 3-node lines are stored end, end, middle.
    assert_eq!(m.element(4).nodes, &[0, 2, 1]);
    assert_eq!(m.element(3).nodes.len(), 8);
    assert_eq!(count(set(&m, "SKIN")), 3);
    assert_eq!(count(set(&m, "BEAM")), 1);
    assert_eq!(count(set(&m, "PT")), 0);
    assert_eq!(count(set(&m, "USER")), 0);
    assert_eq!(m.solids().count(), 1);
    for t in ["S4R", "S8R", "B32", "MASS", "U1", "CPS3"] {
        let n = m
            .warnings
            .iter()
            .filter(|w| w.contains(&format!("type {t} ")))
            .count();
        assert_eq!(n, 1, "{t}: {:?}", m.warnings);
    }
    assert!(m
        .warnings
        .iter()
        .any(|w| w.contains("U1") && w.contains("2 elements")));
    // C3D27 keeps its first 20 nodes.
    let mut deck = String::from("*NODE\n");
    for i in 1..=27 {
        deck.push_str(&format!("{i}, {i}, 0, 0\n"));
    }
    deck.push_str("*ELEMENT, TYPE=C3D27\n1, 1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,\n16,17,18,19,20,21,22,23,24,25,26,27\n");
    let m = ok(&deck);
    assert_eq!(m.element_kinds, vec![ElementKind::Hex20]);
    assert_eq!(m.element(0).nodes.len(), 20);
    assert_eq!(m.warnings.len(), 1);
}

#[test]
fn quoted_names_with_spaces() {
    let deck = format!(
        "*Part, name=\"My Part 1\"\n{HEX}*Element, type=C3D8R, elset=\"Whole Body\"\n1, 1,2,3,4,5,6,7,8\n\
         *Nset, nset=\"Base nodes\"\n1,2,3,4\n*End Part\n\
         *Assembly, name=Assembly\n*Instance, name=\"My Part 1-1\", part=\"my part 1\"\n*End Instance\n\
         *Elset, elset=\"All elements\", instance=\"My Part 1-1\"\n1,\n\
         *Nset, nset=Picked\n\"My Part 1-1\".5, \"My Part 1-1\".Base nodes\n*End Assembly\n"
    );
    let m = ok(&deck);
    assert_eq!(m.node_count(), 8);
    let names: Vec<&str> = m.sets.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(
        names,
        vec![
            "My Part 1-1.Base nodes",
            "Picked",
            "My Part 1-1.Whole Body",
            "All elements"
        ]
    );
    assert_eq!(count(set(&m, "Picked")), 5);
    assert_eq!(count(set(&m, "All elements")), 1);
}

/// A unit cube part instanced twice: the second instance translated by (2, 0, 0) and then
/// rotated by 90 degrees about the vertical axis through (1, 1, 0).
#[test]
fn two_instances_with_translation_and_rotation() {
    let deck = format!(
        "*Heading\n*Part, name=Cube\n{HEX}*Element, type=C3D8, elset=Body\n1, 1,2,3,4,5,6,7,8\n\
         *Nset, nset=Bottom\n1, 2, 3, 4\n*End Part\n\
         *Assembly, name=A\n\
         *Instance, name=C1, part=Cube\n*End Instance\n\
         *Instance, name=C2, part=CUBE\n2., 0., 0.\n1., 1., 0., 1., 1., 1., 90.\n*End Instance\n\
         *Node\n1, 9, 9, 9\n\
         *Nset, nset=Mixed\nC1.1, C2.1, 1\n*Nset, nset=Second, instance=C2\n5, 6\n\
         *Elset, elset=Both\nC1.Body, C2.Body\n*End Assembly\n"
    );
    let m = ok(&deck);
    assert_eq!(m.node_count(), 17);
    assert_eq!(m.element_count(), 2);
    // Ids: the first instance keeps its labels, the second is shifted past 8, the reference
    // point past 16.
    assert_eq!(m.node_ids[..8], [1, 2, 3, 4, 5, 6, 7, 8]);
    assert_eq!(m.node_ids[8..16], [9, 10, 11, 12, 13, 14, 15, 16]);
    assert_eq!(m.node_ids[16], 17);
    assert_eq!(m.element_ids, vec![1, 2]);
    // Instance 1 is unchanged.
    assert_eq!(m.coords[6], [1.0, 1.0, 1.0]);
    // Instance 2: p -> translate -> rotate 90 degrees about (1,1,z): (x,y) -> (1-(y-1), 1+(x-1)).
    let rot = |p: [f64; 3]| {
        let q = [p[0] + 2.0, p[1], p[2]];
        [1.0 - (q[1] - 1.0), 1.0 + (q[0] - 1.0), q[2]]
    };
    let part = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
    ];
    for (k, p) in part.iter().enumerate() {
        assert!(
            close(m.coords[8 + k], rot(*p)),
            "node {k}: {:?} vs {:?}",
            m.coords[8 + k],
            rot(*p)
        );
    }
    assert!(close(m.coords[8], [2.0, 2.0, 0.0]));
    assert!(close(m.coords[14], [1.0, 3.0, 1.0]));
    assert_eq!(m.coords[16], [9.0, 9.0, 9.0]);
    // The second element uses the second instance's nodes.
    assert_eq!(m.element(1).nodes, &[8, 9, 10, 11, 12, 13, 14, 15]);
    let names: Vec<&str> = m.sets.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(
        names,
        vec![
            "C1.Bottom",
            "C2.Bottom",
            "Mixed",
            "Second",
            "C1.Body",
            "C2.Body",
            "Both"
        ]
    );
    assert_eq!(
        set(&m, "C2.Bottom").nodes.as_deref(),
        Some(&[8, 9, 10, 11][..])
    );
    assert_eq!(set(&m, "Mixed").nodes.as_deref(), Some(&[0, 8, 16][..]));
    assert_eq!(set(&m, "Second").nodes.as_deref(), Some(&[12, 13][..]));
    assert_eq!(set(&m, "Both").elements.as_deref(), Some(&[0, 1][..]));
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
}

#[test]
fn independent_instance_and_parts_without_instances() {
    // Nodes and elements inside the instance block are positioned like part nodes.
    let deck = format!(
        "*Part, name=P\n*End Part\n*Assembly, name=A\n*Instance, name=I, part=P\n0, 0, 5\n\
         {HEX}*Element, type=C3D8\n1, 1,2,3,4,5,6,7,8\n*Nset, nset=N\n1\n*End Instance\n*End Assembly\n"
    );
    let m = ok(&deck);
    assert_eq!(m.coords[0], [0.0, 0.0, 5.0]);
    assert_eq!(m.element_count(), 1);
    assert_eq!(count(set(&m, "I.N")), 1);
    // Parts and no instance at all: each part read once, with a warning.
    let m = ok(&format!("*Part, name=Only\n{HEX}*End Part\n"));
    assert_eq!(m.node_count(), 8);
    assert_eq!(m.warnings.len(), 1);
    // A part never instanced while another is: left out with a warning.
    let deck = format!(
        "*Part, name=A\n{HEX}*End Part\n*Part, name=B\n{HEX}*End Part\n*Assembly, name=X\n\
         *Instance, name=A-1, part=A\n*End Instance\n*End Assembly\n"
    );
    let m = ok(&deck);
    assert_eq!(m.node_count(), 8);
    assert!(
        m.warnings.iter().any(|w| w.contains("'B'")),
        "{:?}",
        m.warnings
    );
}

#[test]
fn keyword_line_continuation() {
    let m = ok("*NODE,\n  NSET=Cont\n1, 0, 0, 0\n*NODE,\n2, 1, 1, 1\n*NSET, NSET=S,\nCont\n*NSET, NSET=G,\nGenerate\n1, 2\n");
    assert_eq!(count(set(&m, "Cont")), 1);
    assert_eq!(m.node_count(), 2);
    assert_eq!(count(set(&m, "S")), 1);
    assert_eq!(count(set(&m, "G")), 2);
}

#[test]
fn assembly_elements_may_name_instance_nodes() {
    let deck = format!(
        "*Part, name=P\n{HEX}*End Part\n*Assembly, name=A\n*Instance, name=I, part=P\n*End Instance\n\
         *Instance, name=J, part=P\n0, 0, 1\n*End Instance\n\
         *Element, type=CONN3D2, elset=Wire\n1, I.5, J.1\n*Element, type=T3D2, elset=Truss\n2, I.5, J.1\n*End Assembly\n"
    );
    let m = ok(&deck);
    assert_eq!(m.element_count(), 1);
    assert_eq!(m.element(0).kind, ElementKind::Line);
    assert_eq!(m.element(0).nodes, &[4, 8]);
    assert_eq!(count(set(&m, "Truss")), 1);
    assert_eq!(count(set(&m, "Wire")), 0);
}

#[test]
fn abbreviated_keywords_and_parameters() {
    let m = ok("*NODE\n1,0,0,0\n2,1,0,0\n3,0,1,0\n4,0,0,1\n*ELEM, TYP=C3D4, ELS=Solid\n1, 1, 2, 3, 4\n*NSE, NSE=Base\n1, 2, 3\n");
    assert_eq!(m.element_count(), 1);
    assert_eq!(count(set(&m, "Solid")), 1);
    assert_eq!(count(set(&m, "Base")), 3);
    assert!(
        m.warnings
            .iter()
            .any(|w| w.contains("*ELEM read as *ELEMENT")),
        "{:?}",
        m.warnings
    );
    // *NOD could be *NODE or *NODAL THICKNESS: refused, not skipped with its nodes.
    let e = fail("*NOD\n1,0,0,0\n");
    assert_eq!(line_of(&e), 1);
    assert!(e.to_string().contains("*NODAL THICKNESS"), "{e}");
    // Keywords written out in full that merely begin like ours are not touched.
    let m = ok("*NODE\n1,0,0,0\n*NODE OUTPUT\nU\n*ELEMENT OUTPUT\nS\n");
    assert_eq!(m.node_count(), 1);
}
