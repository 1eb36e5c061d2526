//! Unit tests of the MSH reader on small inline files written for these tests.

use std::path::Path;

use proptest::prelude::*;

use super::num::parse_f64;
use super::read;
use crate::error::{ImportError, Location};
use crate::mesh::{ElementKind, Mesh, SetKind};

mod binary;
mod node_order;

use binary::{msh22_binary, msh41_binary};

fn ok(text: &[u8]) -> Mesh {
    match read(Path::new("t.msh"), text) {
        Ok(m) => m,
        Err(e) => panic!("unexpected error: {e}"),
    }
}

fn err(text: &[u8]) -> ImportError {
    match read(Path::new("t.msh"), text) {
        Ok(_) => panic!("read without error"),
        Err(e) => e,
    }
}

fn line_of(e: &ImportError) -> usize {
    match e.location {
        Location::Line(n) => n,
        other => panic!("expected a line, got {other:?} in {e}"),
    }
}

fn byte_of(e: &ImportError) -> u64 {
    match e.location {
        Location::Byte(n) => n,
        other => panic!("expected a byte offset, got {other:?} in {e}"),
    }
}

/// (name, element count, node count) of each set.
fn sets(m: &Mesh) -> Vec<(String, usize, usize)> {
    m.sets
        .iter()
        .map(|s| {
            assert_eq!(s.kind, SetKind::PhysicalGroup);
            (
                s.name.clone(),
                s.elements.as_ref().map_or(0, Vec::len),
                s.nodes.as_ref().map_or(0, Vec::len),
            )
        })
        .collect()
}

fn ids_of(m: &Mesh, e: usize) -> Vec<u64> {
    m.element(e)
        .nodes
        .iter()
        .map(|&n| m.node_ids[n as usize])
        .collect()
}

fn find(hay: &[u8], needle: &[u8]) -> usize {
    hay.windows(needle.len())
        .position(|w| w == needle)
        .unwrap_or_else(|| panic!("{:?} not found", String::from_utf8_lossy(needle)))
}

const MSH22: &str = "$Comments
written by hand for a test
$EndComments
$MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
3
2 1 \"bottom face\"
3 1 \"solid\"
3 2 \"other\"
$EndPhysicalNames
$Nodes
5
10 0 0 0
20 1 0 0
30 0 1 0
40 0 0 1
50 1 1 1
$EndNodes
$NodeData
1
\"not read\"
$EndNodeData
$Elements
7
1 2 2 1 7 10 20 30
2 4 2 1 3 10 20 30 40
3 4 2 2 3 10 20 30 40
4 4 2 1 3 20 30 40 50
2 4 2 5 3 10 20 30 40
5 15 2 0 1 50
6 1 4 0 2 1 4 40 50
$EndElements
";

#[test]
fn msh22_ascii_repeated_elements_and_groups() {
    let m = ok(MSH22.as_bytes());
    assert_eq!(m.node_ids, vec![10, 20, 30, 40, 50]);
    assert_eq!(m.coords[4], [1.0, 1.0, 1.0]);
    // Element 2 is listed three times: again right after (gmsh: new number 3, same elementary
    // tag and nodes) and later with its own number in group 5.
    assert_eq!(m.element_ids, vec![1, 2, 4, 5, 6]);
    assert_eq!(
        m.element_kinds,
        vec![
            ElementKind::Triangle,
            ElementKind::Tet4,
            ElementKind::Tet4,
            ElementKind::Point,
            ElementKind::Line
        ]
    );
    assert_eq!(ids_of(&m, 1), vec![10, 20, 30, 40]);
    assert_eq!(
        sets(&m),
        vec![
            ("bottom face".to_string(), 1, 3),
            ("solid".to_string(), 2, 5),
            ("other".to_string(), 1, 4),
            ("PhysicalVolume5".to_string(), 1, 4),
        ]
    );
    assert_eq!(
        m.set("solid").and_then(|s| s.elements.clone()),
        Some(vec![1, 2])
    );
    assert!(m.warnings.iter().any(|w| w.contains("$NodeData")));
}

#[test]
fn msh22_repeat_with_other_nodes_is_an_error() {
    let text = MSH22.replace("2 4 2 5 3 10 20 30 40", "2 4 2 5 3 10 20 30 50");
    let e = err(text.as_bytes());
    assert_eq!(line_of(&e), 31, "{e}");
    assert!(e.to_string().contains("element 2"), "{e}");
}

#[test]
fn msh22_old_partitioned_tags_and_node_zero() {
    // Version "2", tags physical / elementary / partition, node and element numbers from 0.
    let text = "$MeshFormat\n2 0 8\n$EndMeshFormat\n$Nodes\n3\n0 0 0 0\n1 1 0 0\n2 0 1 0\n\
                $EndNodes\n$Elements\n2\n0 1 3 4 1 2 0 1\n1 2 3 6 1 3 0 1 2\n$EndElements\n";
    let m = ok(text.as_bytes());
    assert_eq!(m.node_ids, vec![0, 1, 2]);
    assert_eq!(
        sets(&m),
        vec![
            ("PhysicalLine4".to_string(), 1, 2),
            ("PhysicalSurface6".to_string(), 1, 3)
        ]
    );
    assert!(m.warnings.iter().any(|w| w.contains("tag 0")));
}

const MSH41: &str = "$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
2
2 1 \"skin\"
3 1 \"body\"
$EndPhysicalNames
$Entities
1 0 1 1
7 0 0 0 0
3 0 0 0 1 1 0 2 1 4 0
1 0 0 0 1 1 1 1 1 1 3
$EndEntities
$Nodes
3 6 2 1000
0 7 0 1
1000
0 0 0
2 3 1 2
5
2
1 0 0 0.5 0.5 0 1 0 0.25 0.75
3 1 0 3
9
100 40
0 0 1 1 1 1 0.5 0.5 0.5
$EndNodes
$Elements
3 4 11 20
2 3 2 1
11 1000 5 2
3 1 4 2
20 1000 5 2 9 12 5 2 9 40
0 7 15 1
13 1000
$EndElements
$Periodic
0
$EndPeriodic
";

#[test]
fn msh41_ascii_sparse_tags_several_per_line_parametric() {
    let m = ok(MSH41.as_bytes());
    assert_eq!(m.node_ids, vec![1000, 5, 2, 9, 100, 40]);
    assert_eq!(
        m.coords,
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 1.0, 1.0],
            [0.5, 0.5, 0.5]
        ]
    );
    assert_eq!(m.element_ids, vec![11, 20, 12, 13]);
    assert_eq!(ids_of(&m, 2), vec![5, 2, 9, 40]);
    assert_eq!(m.solids().count(), 2);
    // The surface entity is in groups (2,1) and (2,4); names are keyed by (dim, tag).
    assert_eq!(
        sets(&m),
        vec![
            ("skin".to_string(), 1, 3),
            ("PhysicalSurface4".to_string(), 1, 3),
            ("body".to_string(), 2, 5),
        ]
    );
    assert!(m.warnings.iter().any(|w| w.contains("$Periodic")));
}

#[test]
fn msh41_crlf_and_no_groups() {
    let text = "$MeshFormat\r\n4.1 0 8\r\n$EndMeshFormat\r\n$Nodes\r\n1 4 1 4\r\n3 1 0 4\r\n\
                1\r\n2\r\n3\r\n4\r\n0 0 0\r\n1 0 0\r\n0 1 0\r\n0 0 1\r\n$EndNodes\r\n\
                $Elements\r\n1 1 1 1\r\n3 1 4 1\r\n1 1 2 3 4\r\n$EndElements\r\n";
    let m = ok(text.as_bytes());
    assert_eq!(m.element_kinds, vec![ElementKind::Tet4]);
    assert!(m.sets.is_empty());
}

#[test]
fn msh41_partitioned_entities_carry_the_groups() {
    let text = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n\
                $PhysicalNames\n1\n3 9 \"part\"\n$EndPhysicalNames\n\
                $Entities\n0 0 0 1\n1 0 0 0 1 1 1 1 9 0\n$EndEntities\n\
                $PartitionedEntities\n2\n1\n5 2\n0 0 0 2\n\
                5 3 1 1 1 0 0 0 1 1 1 1 9 0\n6 3 1 1 2 0 0 0 1 1 1 0 0\n\
                $EndPartitionedEntities\n\
                $Nodes\n1 5 1 5\n3 5 0 5\n1 2 3 4 5\n0 0 0 1 0 0 0 1 0 0 0 1 1 1 1\n$EndNodes\n\
                $Elements\n2 2 1 2\n3 5 4 1\n1 1 2 3 4\n3 6 4 1\n2 2 3 4 5\n$EndElements\n\
                $GhostElements\n0\n$EndGhostElements\n";
    let m = ok(text.as_bytes());
    // Entity 5 has its own physical tag 9; entity 6 has none and takes its parent's (volume 1).
    assert_eq!(sets(&m), vec![("part".to_string(), 2, 5)]);
}

#[test]
fn located_errors_in_text_files() {
    let cases: Vec<(String, usize, &str)> = vec![
        // Unknown element type, at its line.
        (MSH41.replace("0 7 15 1", "0 7 999 1"), 35, "'999'"),
        // Undefined node tag.
        (
            MSH41.replace("11 1000 5 2", "11 1000 5 77"),
            32,
            "node tag 77",
        ),
        // A node tag defined twice: at the second one.
        (
            MSH41.replace("100 40", "100 5"),
            26,
            "node tag 5 a second time",
        ),
        // Lying counts.
        (MSH41.replace("3 6 2 1000", "3 7 2 1000"), 16, "7 nodes"),
        (MSH41.replace("0 7 15 1", "0 7 15 2"), 37, "'$EndElements'"),
        (
            MSH22.replace("$Elements\n7", "$Elements\n8"),
            34,
            "'$EndElements'",
        ),
        (MSH22.replace("$Elements\n7", "$Elements\n6"), 33, "'6'"),
        // Bad numbers.
        (MSH41.replace("1000\n0 0 0", "10x0\n0 0 0"), 18, "'10x0'"),
        (
            MSH41.replace("1000\n0 0 0", "18446744073709551616\n0 0 0"),
            18,
            "'18446744073709551616'",
        ),
        (MSH22.replace("30 0 1 0", "30 0 1.0.0 0"), 17, "'1.0.0'"),
        (MSH22.replace("30 0 1 0", "30 0 nan 0"), 17, "'nan'"),
        // NUL bytes in the data.
        (MSH22.replace("40 0 0 1", "40 0 0 \0\0\0"), 18, "NUL bytes"),
        // Version 4.0 and MSH 1.
        (MSH41.replace("4.1 0 8", "4 0 8"), 2, "4.0"),
        ("$NOD\n1\n1 0 0 0\n$ENDNOD\n".to_string(), 1, "MSH 1"),
        // $Elements before $Nodes.
        (
            "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Elements\n0\n$EndElements\n".to_string(),
            4,
            "$Elements",
        ),
        // A section that never ends.
        (MSH41.replace("$EndPeriodic\n", ""), 38, "end of file"),
        // A physical name without its closing quote.
        (MSH41.replace("\"skin\"", "\"skin"), 6, "closing"),
        // Fewer entities than the counts say.
        (
            MSH41.replace("3 0 0 0 1 1 0 2 1 4 0\n1 0 0 0 1 1 1 1 1 1 3\n", ""),
            12,
            "an entity tag, found '$EndEntities'",
        ),
    ];
    for (text, line, found) in cases {
        let e = err(text.as_bytes());
        assert_eq!(line_of(&e), line, "{e}");
        let msg = e.to_string();
        assert!(msg.contains("expected") && msg.contains(found), "{msg}");
    }
}

#[test]
fn empty_and_padding_files() {
    let e = err(b"");
    assert!(e.to_string().contains("$MeshFormat"), "{e}");
    let e = err(&[0u8; 64]);
    assert_eq!(line_of(&e), 1);
    assert!(e.to_string().contains("NUL bytes"), "{e}");
    let mut padded = MSH22.as_bytes().to_vec();
    padded.extend_from_slice(&[0u8; 100]);
    let e = err(&padded);
    assert!(e.to_string().contains("NUL bytes"), "{e}");
    let e = err(b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
    assert!(e.to_string().contains("$Nodes"), "{e}");
}

#[test]
fn every_truncation_is_an_error_or_a_smaller_mesh() {
    for text in [MSH22.as_bytes().to_vec(), MSH41.as_bytes().to_vec()] {
        for cut in 0..text.len() {
            // Must not panic; a cut inside a section must be an error.
            let r = read(Path::new("t.msh"), &text[..cut]);
            let inside_nodes = cut > find(&text, b"$Nodes") && cut < find(&text, b"$EndNodes") + 9;
            if inside_nodes {
                assert!(r.is_err(), "cut at {cut} read without error");
            }
        }
    }
    for text in [msh41_binary(true, true), msh22_binary(false, false)] {
        for cut in 0..text.len() {
            let r = read(Path::new("t.msh"), &text[..cut]);
            let inside = cut > find(&text, b"$Nodes") && cut < find(&text, b"$EndNodes") + 9;
            if inside {
                assert!(r.is_err(), "binary cut at {cut} read without error");
            }
        }
    }
}

#[test]
fn fast_float_path_matches_std() {
    for s in [
        "0",
        "-0",
        "1",
        "0.5",
        "-2.5e-3",
        "1e22",
        "1e23",
        "9007199254740993",
        "0.3333333333333324",
        "0.9999999000000001",
        "1.732050807568877",
        "-9.999999994736442e-08",
        "3.061616997868383e-17",
        "123456789012345678901234",
        ".5",
        "5.",
        "+7",
        "1E+05",
        "2.220446049250313e-16",
    ] {
        let want: f64 = s.parse().unwrap_or(f64::NAN);
        let got = parse_f64(s.as_bytes()).unwrap_or(f64::NAN);
        assert_eq!(got.to_bits(), want.to_bits(), "{s}");
    }
    for s in [
        "", ".", "e5", "1e", "1.0.0", "inf", "NaN", "1e400", "--1", "1 ",
    ] {
        assert_eq!(parse_f64(s.as_bytes()), None, "{s:?}");
    }
}

proptest! {
    #[test]
    fn floats_parse_like_std(m in any::<i64>(), frac in 0u32..20, e in -40i32..40, form in 0u8..3) {
        let s = match form {
            0 => format!("{}", m as f64 / 10f64.powi(frac as i32)),
            1 => format!("{m}e{e}"),
            _ => format!("{:.*e}", frac as usize, m as f64),
        };
        let want: Option<f64> = s.parse::<f64>().ok().filter(|v| v.is_finite());
        prop_assert_eq!(parse_f64(s.as_bytes()).map(f64::to_bits), want.map(f64::to_bits), "{}", s);
    }

    #[test]
    fn mutated_files_never_panic(
        which in 0usize..4,
        edits in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..6),
        cut in any::<prop::sample::Index>(),
    ) {
        let mut data = match which {
            0 => MSH22.as_bytes().to_vec(),
            1 => MSH41.as_bytes().to_vec(),
            2 => msh41_binary(false, true),
            _ => msh22_binary(true, true),
        };
        for (at, byte) in edits {
            let i = at.index(data.len());
            data[i] = byte;
        }
        let keep = cut.index(data.len() + 1);
        data.truncate(keep.max(data.len() / 2));
        if let Err(e) = read(Path::new("t.msh"), &data) {
            let msg = e.to_string();
            prop_assert!(msg.contains("expected") && msg.contains("found"), "{}", msg);
            prop_assert!(e.location != Location::File, "{}", msg);
        }
    }
}

#[test]
fn mesh_repeated_before_appended_view_data() {
    // gmsh.view.write(..., append=True) writes $MeshFormat and the whole mesh again, then the
    // view's $NodeData.
    let mesh = MSH41
        .split_once("$EndMeshFormat\n")
        .map_or("", |(_, rest)| rest);
    let first = ok(MSH41.as_bytes());
    let text = format!(
        "{MSH41}$MeshFormat\n4.1 0 8\n$EndMeshFormat\n{mesh}$NodeData\n1\n\"v\"\n$EndNodeData\n"
    );
    let m = ok(text.as_bytes());
    assert_eq!(m.node_count(), first.node_count());
    assert_eq!(m.element_count(), first.element_count());
    assert_eq!(sets(&m), sets(&first));
    // A second $MeshFormat with only data after it.
    let m = ok(format!(
        "{MSH41}$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$NodeData\n1\n\"v\"\n$EndNodeData\n"
    )
    .as_bytes());
    assert_eq!(m.node_count(), first.node_count());
    // A second mesh that differs is refused, as is another version.
    let other = mesh.replacen("0 0 1 1 1 1 0.5 0.5 0.5", "0 0 2 1 1 1 0.5 0.5 0.5", 1);
    assert_ne!(other, mesh);
    let e = err(format!("{MSH41}$MeshFormat\n4.1 0 8\n$EndMeshFormat\n{other}").as_bytes());
    assert!(e.to_string().contains("second"), "{e}");
    let e = err(format!("{MSH41}$MeshFormat\n2.2 0 8\n$EndMeshFormat\n").as_bytes());
    assert!(e.to_string().contains("version 2"), "{e}");
}

#[test]
fn surface_groups_without_a_volume_say_why_the_volume_is_missing() {
    // What gmsh saves for a meshed solid with a Physical Surface and no Physical Volume: the
    // surface's triangles only.
    let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n2 1 \"contact\"\n\
                $EndPhysicalNames\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n\
                $Elements\n2\n1 2 2 1 1 1 2 3\n2 2 2 1 1 1 2 4\n$EndElements\n";
    let m = ok(text.as_bytes());
    let w = m
        .warnings
        .iter()
        .find(|w| w.contains("no 3D solid elements"))
        .unwrap_or_else(|| panic!("no warning in {:?}", m.warnings));
    assert!(
        w.contains("Physical Volume") && w.contains("Mesh.SaveAll"),
        "{w}"
    );
    // A solid mesh has no such warning.
    let m = ok(MSH22.as_bytes());
    assert!(!m.warnings.iter().any(|w| w.contains("no 3D solid")));
}
