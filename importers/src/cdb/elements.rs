//! ANSYS element types: which are 3D solids, and how a record's nodes become one of the
//! [`ElementKind`] solids in the convention of [`crate::mesh`] (FORMATS.md §1.2, §1.6, §1.7).

use crate::mesh::{ElementKind, MISSING_NODE};

/// Hex-family solids: 8 or 20 node bricks whose repeated corners encode wedges, pyramids and
/// tets (FORMATS.md §1.2, class 4 of mapdl-archive; FLUID30/80/220 included).
const HEX_FAMILY: [i64; 25] = [
    5, 30, 45, 46, 62, 64, 65, 69, 70, 80, 90, 95, 96, 97, 122, 164, 185, 186, 220, 226, 231, 236,
    239, 278, 279,
];

/// Tet-family solids: 4 corners then up to 6 mid-edge nodes (FORMATS.md §1.2, class 5;
/// FLUID221 included).
const TET_FAMILY: [i64; 13] = [87, 92, 98, 123, 168, 187, 221, 227, 232, 237, 240, 285, 291];

/// MESH200, whose shape comes from KEYOPT(1) (FORMATS.md §1.2).
pub(crate) const MESH200: i64 = 200;

/// How the reader treats an element type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Class {
    /// 8/20-node brick, possibly collapsed.
    Hex,
    /// 4/10-node tetrahedron.
    Tet,
    /// Anything else: shells, surfaces, contact, beams, 2-D MESH200 shapes.
    NotSolid,
}

/// The class of element number `ename` (186 for SOLID186) with KEYOPT(1) `keyopt1`.
pub(crate) fn class_of(ename: i64, keyopt1: i64) -> Class {
    if ename == MESH200 {
        // KEYOPT(1): 8 = 4-node tet, 9 = 10-node tet, 10 = 8-node hex, 11 = 20-node hex.
        return match keyopt1 {
            8 | 9 => Class::Tet,
            10 | 11 => Class::Hex,
            _ => Class::NotSolid,
        };
    }
    if HEX_FAMILY.contains(&ename) {
        Class::Hex
    } else if TET_FAMILY.contains(&ename) {
        Class::Tet
    } else {
        Class::NotSolid
    }
}

/// ANSYS element names, for warnings ("skipped 22 SURF154 elements").
const NAMES: &str = "LINK1 PLANE2 BEAM3 BEAM4 SOLID5 COMBIN7 LINK8 INFIN9 LINK10 LINK11 CONTAC12 \
PLANE13 COMBIN14 FLUID15 PIPE16 PIPE17 PIPE18 SURF19 PIPE20 MASS21 SURF22 BEAM23 BEAM24 PLANE25 \
MATRIX27 SHELL28 FLUID29 FLUID30 LINK31 LINK32 LINK33 LINK34 PLANE35 SOURC36 COMBIN37 FLUID38 \
COMBIN39 COMBIN40 SHELL41 PLANE42 SHELL43 BEAM44 SOLID45 SOLID46 INFIN47 MATRIX50 SHELL51 \
CONTAC52 PLANE53 BEAM54 PLANE55 SHELL57 PIPE59 PIPE60 SHELL61 SOLID62 SHELL63 SOLID64 SOLID65 \
FLUID66 PLANE67 LINK68 SOLID69 SOLID70 MASS71 PLANE75 PLANE77 PLANE78 FLUID79 FLUID80 FLUID81 \
PLANE82 PLANE83 SOLID87 VISCO88 VISCO89 SOLID90 SHELL91 SOLID92 SHELL93 CIRCU94 SOLID95 SOLID96 \
SOLID97 SOLID98 SHELL99 USER100 USER101 USER102 USER103 USER104 USER105 VISCO106 VISCO107 \
VISCO108 TRANS109 INFIN110 INFIN111 ROT112 INTER115 FLUID116 EDGE117 HF118 HF119 HF120 PLANE121 \
SOLID122 SOLID123 CIRCU124 CIRCU125 TRANS126 FLUID129 FLUID130 SHELL131 SHELL132 TRANS135 \
FLUID136 FLUID137 FLUID138 FLUID139 ROM140 SHELL143 ROM144 SURF151 SURF152 SURF153 SURF154 \
SURF155 SURF156 SHELL157 SURF159 BEAM161 SHELL163 SOLID164 SOLID168 TARGE169 TARGE170 CONTA171 \
CONTA172 CONTA173 CONTA174 CONTA175 CONTA176 CONTA177 CONTA178 PRETS179 LINK180 SHELL181 \
PLANE182 PLANE183 RBAR184 SOLID185 SOLID186 SOLID187 BEAM188 BEAM189 SOLSH190 SOLID191 \
INTER192 INTER193 INTER194 INTER195 LAYER196 LAYER197 MESH200 FOLLW201 INTER202 INTER203 \
INTER204 INTER205 INTER206 SHELL208 SHELL209 CPT212 CPT213 COMBI214 CPT215 CPT216 CPT217 \
FLUID218 FLUID219 FLUID220 FLUID221 PLANE222 PLANE223 SOLID225 SOLID226 SOLID227 PLANE230 \
SOLID231 SOLID232 PLANE233 SOLID236 SOLID237 PLANE238 SOLID239 SOLID240 HSFLD241 HSFLD242 \
COMBI250 SURF251 SURF252 INFIN257 INFIN258 INFIN259 GLINK262 REINF263 REINF264 REINF265 \
SOLID272 SOLID273 SOLID278 SOLID279 CABLE280 SHELL281 SHELL282 SHELL283 SOLID285 PIPE288 \
PIPE289 ELBOW290 SOLID291 PLANE292 PLANE293 USER300";

/// The name of element number `ename` (`SURF154`), if it is one.
pub(crate) fn element_name(ename: i64) -> Option<String> {
    let digits = ename.to_string();
    NAMES
        .split_ascii_whitespace()
        .find(|n| {
            n.strip_suffix(digits.as_str())
                .is_some_and(|p| !p.is_empty() && p.bytes().all(|c| c.is_ascii_alphabetic()))
        })
        .map(str::to_string)
}

/// ANSYS mid-edge slots (0-based in the 20-node record, Q = 8 … B = 19) that hold the
/// mid-edge nodes of each real shape, in the order of [`crate::mesh`] (FORMATS.md §1.6, §1.7).
/// Hex20 is ANSYS = VTK order. For collapsed shapes the collapsed edges' slots (S, U–X, B for a
/// tet) hold arbitrary duplicates and are not used.
const HEX20_MIDS: [usize; 12] = [8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19];
/// Wedge: Q(I-J) R(J-K) T(K-I) | U(M-N) V(N-O) X(O-M) | Y(I-M) Z(J-N) A(K-O).
const WEDGE15_MIDS: [usize; 9] = [8, 9, 11, 12, 13, 15, 16, 17, 18];
/// Pyramid: Q R S T on the base, Y Z A B to the apex.
const PYRAMID13_MIDS: [usize; 8] = [8, 9, 10, 11, 16, 17, 18, 19];
/// Tet: Q(I-J) R(J-K) T(K-I) Y(I-M) Z(J-M) A(K-M).
const TET10_FROM_HEX_MIDS: [usize; 6] = [8, 9, 11, 16, 17, 18];
/// SOLID187/92 tet10: I J K L then M N O P Q R, already the mesh order.
const TET10_MIDS: [usize; 6] = [4, 5, 6, 7, 8, 9];

/// A record turned into a solid, or why it cannot be one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Built {
    /// `nodes[..len]` in the mesh convention; file node numbers, [`MISSING_NODE`] for a
    /// mid-side node the file leaves out.
    Solid {
        kind: ElementKind,
        nodes: [u32; 20],
        len: usize,
        /// Some used mid-side slot was 0.
        missing_midside: bool,
    },
    /// Fewer nodes than the corners need.
    TooFewNodes { need: usize },
    /// A corner slot holds node number 0.
    MissingCorner { corner: usize },
    /// Repeated corners in a pattern that is no hex, wedge, pyramid or tet.
    BadCollapse,
}

fn distinct(c: &[u32], idx: &[usize]) -> bool {
    idx.iter()
        .enumerate()
        .all(|(i, &a)| idx[i + 1..].iter().all(|&b| c[a] != c[b]))
}

/// Builds a hex-family element from its record nodes (`raw`, file node numbers, 0 = none).
///
/// The shape comes from the distinct corners (FORMATS.md §1.6): all 8 distinct → hex;
/// K=L and O=P → wedge `I J K M N O`; M=N=O=P → pyramid `I J K L M`; K=L and M=N=O=P → tet
/// `I J K M`. These keep the ANSYS handedness, which is the mesh convention's. The element is
/// quadratic when the record has more than 8 nodes and one of the real shape's mid-edge slots
/// is filled (TetBeam.cdb-style records without midside nodes stay linear).
pub(crate) fn build_hex(raw: &[u32]) -> Built {
    if raw.len() < 8 {
        return Built::TooFewNodes { need: 8 };
    }
    let c = &raw[..8];
    if let Some(corner) = c.iter().position(|&n| n == 0) {
        return Built::MissingCorner { corner };
    }
    let (kind, corners, mids): (ElementKind, &[usize], &[usize]) =
        if distinct(c, &[0, 1, 2, 3, 4, 5, 6, 7]) {
            (ElementKind::Hex8, &[0, 1, 2, 3, 4, 5, 6, 7], &HEX20_MIDS)
        } else if c[2] == c[3] && c[6] == c[7] && distinct(c, &[0, 1, 2, 4, 5, 6]) {
            (ElementKind::Wedge6, &[0, 1, 2, 4, 5, 6], &WEDGE15_MIDS)
        } else if c[4] == c[5] && c[5] == c[6] && c[6] == c[7] && distinct(c, &[0, 1, 2, 3, 4]) {
            (ElementKind::Pyramid5, &[0, 1, 2, 3, 4], &PYRAMID13_MIDS)
        } else if c[2] == c[3]
            && c[4] == c[5]
            && c[5] == c[6]
            && c[6] == c[7]
            && distinct(c, &[0, 1, 2, 4])
        {
            (ElementKind::Tet4, &[0, 1, 2, 4], &TET10_FROM_HEX_MIDS)
        } else {
            return Built::BadCollapse;
        };
    assemble(raw, kind, corners, mids, 8)
}

/// Builds a tet-family element: corners I J K L, then mid-edge nodes in SOLID187 order, which
/// is the mesh convention's (FORMATS.md §1.7). Four-node records are tet4.
pub(crate) fn build_tet(raw: &[u32]) -> Built {
    if raw.len() < 4 {
        return Built::TooFewNodes { need: 4 };
    }
    let c = &raw[..4];
    if let Some(corner) = c.iter().position(|&n| n == 0) {
        return Built::MissingCorner { corner };
    }
    if !distinct(c, &[0, 1, 2, 3]) {
        return Built::BadCollapse;
    }
    assemble(raw, ElementKind::Tet4, &[0, 1, 2, 3], &TET10_MIDS, 4)
}

fn assemble(
    raw: &[u32],
    linear: ElementKind,
    corners: &[usize],
    mids: &[usize],
    corner_slots: usize,
) -> Built {
    let slot = |s: usize| raw.get(s).copied().unwrap_or(0);
    let quadratic = raw.len() > corner_slots && mids.iter().any(|&s| slot(s) != 0);
    let mut nodes = [MISSING_NODE; 20];
    let mut len = 0;
    for &s in corners {
        nodes[len] = raw[s];
        len += 1;
    }
    let mut missing_midside = false;
    let kind = if quadratic {
        for &s in mids {
            let n = slot(s);
            if n == 0 {
                missing_midside = true;
            } else {
                nodes[len] = n;
            }
            len += 1;
        }
        linear.quadratic()
    } else {
        linear
    };
    Built::Solid {
        kind,
        nodes,
        len,
        missing_midside,
    }
}
