//! Gmsh element types: node count per type number and the map to the mesh convention.
//!
//! The table lists every type `gmsh.model.mesh.getElementProperties` knows in gmsh 4.15.2, plus
//! the complete and serendipity prisms of `GmshDefines.h` (90, 91, 106-117) that the API does not
//! report. Gmsh writes the corner (primary) nodes of every element first, so any element can be
//! reduced to its corners. Types with no fixed node count (polygons, polyhedra), order-0 and
//! sub-elements are reported as unsupported; numbers missing from the table as unknown.

use crate::mesh::ElementKind;

/// `convention[k] = gmsh[HEX20[k]]`: hex20 mid-edge nodes from Gmsh to VTK/Abaqus order
/// (gmsh `MHexahedron20::getVertexVTK`). Also valid for the first 20 nodes of a hex27.
pub(crate) const HEX20: [u8; 20] = [
    0, 1, 2, 3, 4, 5, 6, 7, 8, 11, 13, 9, 16, 18, 19, 17, 10, 12, 14, 15,
];
/// Tet10: Gmsh swaps the last two mid-edge nodes (edges (3,2) and (3,1)).
pub(crate) const TET10: [u8; 10] = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8];
/// Prism15 (also the first 15 nodes of a prism18).
pub(crate) const PRISM15: [u8; 15] = [0, 1, 2, 3, 4, 5, 6, 9, 7, 12, 14, 13, 8, 10, 11];
/// Pyramid13 (also the first 13 nodes of a pyramid14): Gmsh mid-edge nodes 5..12 lie on
/// (0,1)(0,3)(0,4)(1,2)(1,4)(2,3)(2,4)(3,4).
pub(crate) const PYRAMID13: [u8; 13] = [0, 1, 2, 3, 4, 5, 8, 10, 6, 7, 9, 11, 12];

const CORNERS: [u8; 8] = [0, 1, 2, 3, 4, 5, 6, 7];

/// Shape family of a Gmsh element type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Family {
    Point,
    Line,
    Tri,
    Quad,
    Tet,
    Hex,
    Prism,
    Pyramid,
}

/// How one Gmsh element type is read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct ElemType {
    /// Gmsh type number.
    pub code: i64,
    /// Gmsh-like name (`hex27`).
    pub name: &'static str,
    /// Number of node tags in the file record.
    pub nodes: usize,
    /// The kind stored in the mesh.
    pub kind: ElementKind,
    /// `None`: all nodes in file order; `Some(map)`: stored node `k` is file node `map[k]`.
    pub take: Option<&'static [u8]>,
    /// For elements stored in a reduced form: how (for one warning per type).
    pub note: Option<&'static str>,
}

/// The result of looking a type number up.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Lookup {
    Known(ElemType),
    /// A type gmsh defines that has no place in the mesh (name, reason).
    Unsupported(&'static str, &'static str),
    Unknown,
}

/// Looks up a Gmsh element type number.
pub(crate) fn lookup(code: i64) -> Lookup {
    use Family::*;
    let (name, nodes, family) = match code {
        1 => ("line2", 2, Line),
        2 => ("tri3", 3, Tri),
        3 => ("quad4", 4, Quad),
        4 => ("tet4", 4, Tet),
        5 => ("hex8", 8, Hex),
        6 => ("prism6", 6, Prism),
        7 => ("pyramid5", 5, Pyramid),
        8 => ("line3", 3, Line),
        9 => ("tri6", 6, Tri),
        10 => ("quad9", 9, Quad),
        11 => ("tet10", 10, Tet),
        12 => ("hex27", 27, Hex),
        13 => ("prism18", 18, Prism),
        14 => ("pyramid14", 14, Pyramid),
        15 => ("point", 1, Point),
        16 => ("quad8", 8, Quad),
        17 => ("hex20", 20, Hex),
        18 => ("prism15", 15, Prism),
        19 => ("pyramid13", 13, Pyramid),
        20 => ("tri9", 9, Tri),
        21 => ("tri10", 10, Tri),
        22 => ("tri12", 12, Tri),
        23 => ("tri15", 15, Tri),
        24 => ("tri15i", 15, Tri),
        25 => ("tri21", 21, Tri),
        26 => ("line4", 4, Line),
        27 => ("line5", 5, Line),
        28 => ("line6", 6, Line),
        29 => ("tet20", 20, Tet),
        30 => ("tet35", 35, Tet),
        31 => ("tet56", 56, Tet),
        32 => ("tet22", 22, Tet),
        33 => ("tet28", 28, Tet),
        36 => ("quad16", 16, Quad),
        37 => ("quad25", 25, Quad),
        38 => ("quad36", 36, Quad),
        39 => ("quad12", 12, Quad),
        40 => ("quad16i", 16, Quad),
        41 => ("quad20", 20, Quad),
        42 => ("tri28", 28, Tri),
        43 => ("tri36", 36, Tri),
        44 => ("tri45", 45, Tri),
        45 => ("tri55", 55, Tri),
        46 => ("tri66", 66, Tri),
        47 => ("quad49", 49, Quad),
        48 => ("quad64", 64, Quad),
        49 => ("quad81", 81, Quad),
        50 => ("quad100", 100, Quad),
        51 => ("quad121", 121, Quad),
        52 => ("tri18", 18, Tri),
        53 => ("tri21i", 21, Tri),
        54 => ("tri24", 24, Tri),
        55 => ("tri27", 27, Tri),
        56 => ("tri30", 30, Tri),
        57 => ("quad24", 24, Quad),
        58 => ("quad28", 28, Quad),
        59 => ("quad32", 32, Quad),
        60 => ("quad36i", 36, Quad),
        61 => ("quad40", 40, Quad),
        62 => ("line7", 7, Line),
        63 => ("line8", 8, Line),
        64 => ("line9", 9, Line),
        65 => ("line10", 10, Line),
        66 => ("line11", 11, Line),
        71 => ("tet84", 84, Tet),
        72 => ("tet120", 120, Tet),
        73 => ("tet165", 165, Tet),
        74 => ("tet220", 220, Tet),
        75 => ("tet286", 286, Tet),
        79 => ("tet34", 34, Tet),
        80 => ("tet40", 40, Tet),
        81 => ("tet46", 46, Tet),
        82 => ("tet52", 52, Tet),
        83 => ("tet58", 58, Tet),
        90 => ("prism40", 40, Prism),
        91 => ("prism75", 75, Prism),
        92 => ("hex64", 64, Hex),
        93 => ("hex125", 125, Hex),
        94 => ("hex216", 216, Hex),
        95 => ("hex343", 343, Hex),
        96 => ("hex512", 512, Hex),
        97 => ("hex729", 729, Hex),
        98 => ("hex1000", 1000, Hex),
        99 => ("hex32", 32, Hex),
        100 => ("hex44", 44, Hex),
        101 => ("hex56", 56, Hex),
        102 => ("hex68", 68, Hex),
        103 => ("hex80", 80, Hex),
        104 => ("hex92", 92, Hex),
        105 => ("hex104", 104, Hex),
        106 => ("prism126", 126, Prism),
        107 => ("prism196", 196, Prism),
        108 => ("prism288", 288, Prism),
        109 => ("prism405", 405, Prism),
        110 => ("prism550", 550, Prism),
        111 => ("prism24", 24, Prism),
        112 => ("prism33", 33, Prism),
        113 => ("prism42", 42, Prism),
        114 => ("prism51", 51, Prism),
        115 => ("prism60", 60, Prism),
        116 => ("prism69", 69, Prism),
        117 => ("prism78", 78, Prism),
        118 => ("pyramid30", 30, Pyramid),
        119 => ("pyramid55", 55, Pyramid),
        120 => ("pyramid91", 91, Pyramid),
        121 => ("pyramid140", 140, Pyramid),
        122 => ("pyramid204", 204, Pyramid),
        123 => ("pyramid285", 285, Pyramid),
        124 => ("pyramid385", 385, Pyramid),
        125 => ("pyramid21", 21, Pyramid),
        126 => ("pyramid29", 29, Pyramid),
        127 => ("pyramid37", 37, Pyramid),
        128 => ("pyramid45", 45, Pyramid),
        129 => ("pyramid53", 53, Pyramid),
        130 => ("pyramid61", 61, Pyramid),
        131 => ("pyramid69", 69, Pyramid),
        137 => ("tet16", 16, Tet),
        34 => return Lookup::Unsupported("polygon", "its node count varies"),
        35 => return Lookup::Unsupported("polyhedron", "its node count varies"),
        69 => return Lookup::Unsupported("polygon border", "its node count varies"),
        84..=89 | 132 => return Lookup::Unsupported("order-0 element", "it has no corner nodes"),
        133..=136 => return Lookup::Unsupported("sub-element", "it is not a mesh element"),
        138 | 139 => return Lookup::Unsupported("mini element", "it has a bubble node"),
        140 => return Lookup::Unsupported("trihedron", "the mesh has no such shape"),
        _ => return Lookup::Unknown,
    };
    Lookup::Known(make(code, name, nodes, family))
}

fn make(code: i64, name: &'static str, nodes: usize, family: Family) -> ElemType {
    let (kind, take, note): (ElementKind, Option<&'static [u8]>, Option<&'static str>) =
        match (family, nodes) {
            (Family::Point, _) => (ElementKind::Point, None, None),
            (Family::Line, _) => (ElementKind::Line, None, None),
            (Family::Tri, _) => (ElementKind::Triangle, None, None),
            (Family::Quad, _) => (ElementKind::Quadrilateral, None, None),
            (Family::Tet, 4) => (ElementKind::Tet4, None, None),
            (Family::Tet, 10) => (ElementKind::Tet10, Some(&TET10), None),
            (Family::Tet, _) => (
                ElementKind::Tet4,
                Some(&CORNERS[..4]),
                Some("read as tet4 by their corners (higher-order nodes dropped)"),
            ),
            (Family::Hex, 8) => (ElementKind::Hex8, None, None),
            (Family::Hex, 20) => (ElementKind::Hex20, Some(&HEX20), None),
            (Family::Hex, 27) => (
                ElementKind::Hex20,
                Some(&HEX20),
                Some("read as hex20 (face and volume centre nodes dropped)"),
            ),
            (Family::Hex, _) => (
                ElementKind::Hex8,
                Some(&CORNERS[..8]),
                Some("read as hex8 by their corners (higher-order nodes dropped)"),
            ),
            (Family::Prism, 6) => (ElementKind::Wedge6, None, None),
            (Family::Prism, 15) => (ElementKind::Wedge15, Some(&PRISM15), None),
            (Family::Prism, 18) => (
                ElementKind::Wedge15,
                Some(&PRISM15),
                Some("read as wedge15 (quadrilateral face centre nodes dropped)"),
            ),
            (Family::Prism, _) => (
                ElementKind::Wedge6,
                Some(&CORNERS[..6]),
                Some("read as wedge6 by their corners (higher-order nodes dropped)"),
            ),
            (Family::Pyramid, 5) => (ElementKind::Pyramid5, None, None),
            (Family::Pyramid, 13) => (ElementKind::Pyramid13, Some(&PYRAMID13), None),
            (Family::Pyramid, 14) => (
                ElementKind::Pyramid13,
                Some(&PYRAMID13),
                Some("read as pyramid13 (base centre node dropped)"),
            ),
            (Family::Pyramid, _) => (
                ElementKind::Pyramid5,
                Some(&CORNERS[..5]),
                Some("read as pyramid5 by their corners (higher-order nodes dropped)"),
            ),
        };
    ElemType {
        code,
        name,
        nodes,
        kind,
        take,
        note,
    }
}
