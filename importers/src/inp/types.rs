//! Abaqus element types: which shape a `TYPE=` name is, and how many node numbers its data
//! lines carry (FORMATS.md §3.3).
//!
//! Solids are classified by the digits after `C3D` (`C3D8R`, `DC3D10`, `C3d4` ...), plus the
//! continuum shells `SC6R`/`SC8R` and the cohesive `COH3D6`/`COH3D8`. Shells, membranes, surface,
//! rigid, 2-D continuum, beam and truss elements are kept as triangles, quadrilaterals or lines
//! for set membership only. Anything else is skipped; its data lines are still consumed. A
//! solid-looking name that is no known solid (`C3D7`, `C3D99`, `DC3D`) is refused: its node
//! count would only be a guess, and dropping it would lose part of the mesh.

use crate::mesh::ElementKind;

/// What the reader does with an element type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Class {
    /// A 3D solid. Its data lines carry `read` node numbers; the first `kind.node_count()` are
    /// kept (`read` is larger only for C3D27 and C3D15V, whose extra nodes are dropped).
    Solid { kind: ElementKind, read: usize },
    /// A lower-dimensional element kept for set membership: `nodes` node numbers, corners first
    /// after reordering (3-node lines are written end, middle, end and stored end, end, middle).
    Lower { kind: ElementKind, nodes: usize },
    /// Not modelled: the element is consumed and dropped. `nodes` is the node count when the
    /// type is known; otherwise a record continues only after a trailing comma.
    Skipped { nodes: Option<usize> },
}

impl Class {
    /// How many node numbers a record of this type carries, if known.
    pub fn node_numbers(self) -> Option<usize> {
        match self {
            Class::Solid { read, .. } => Some(read),
            Class::Lower { nodes, .. } => Some(nodes),
            Class::Skipped { nodes } => nodes,
        }
    }
}

/// Digits right after `prefix` at the start of `t`: their value and the text after them.
fn digits_after<'a>(t: &'a str, prefix: &str) -> Option<(usize, &'a str)> {
    let rest = t.strip_prefix(prefix)?;
    let n = rest.bytes().take_while(u8::is_ascii_digit).count();
    if n == 0 || n > 3 {
        return None;
    }
    let value = rest[..n].parse().ok()?;
    Some((value, &rest[n..]))
}

fn solid(digits: usize, rest: &str) -> Option<Class> {
    let (kind, read) = match digits {
        4 => (ElementKind::Tet4, 4),
        5 => (ElementKind::Pyramid5, 5),
        6 => (ElementKind::Wedge6, 6),
        8 => (ElementKind::Hex8, 8),
        10 => (ElementKind::Tet10, 10),
        13 => (ElementKind::Pyramid13, 13),
        // C3D15V has 15 to 18 nodes; the extra face nodes are dropped.
        15 if rest.starts_with('V') => (ElementKind::Wedge15, 18),
        15 => (ElementKind::Wedge15, 15),
        20 => (ElementKind::Hex20, 20),
        // C3D27: 20 nodes as C3D20, then face centres and the centre, which are dropped.
        27 => (ElementKind::Hex20, 27),
        _ => return None,
    };
    Some(Class::Solid { kind, read })
}

/// A surface-like element with `n` nodes: 3 or 6 are triangles, 4, 8 or 9 quadrilaterals.
fn surface(n: usize) -> Option<Class> {
    let kind = match n {
        3 | 6 => ElementKind::Triangle,
        4 | 8 | 9 => ElementKind::Quadrilateral,
        _ => return None,
    };
    Some(Class::Lower { kind, nodes: n })
}

fn line(n: usize) -> Option<Class> {
    matches!(n, 2 | 3).then_some(Class::Lower {
        kind: ElementKind::Line,
        nodes: n,
    })
}

/// The solid types [`classify`] knows, for the message that refuses an unknown one.
pub(super) const KNOWN_SOLIDS: &str =
    "C3D4, C3D5, C3D6, C3D8, C3D10, C3D13, C3D15, C3D20 or C3D27, \
    with any suffix (C3D8R, C3D10M ...) or prefix (DC3D8 ...)";

/// Classifies an element type name (any case). `None` for a solid-looking name (`C3D`, after
/// letters only, as in `DC3D`) whose digits are no known solid: it is refused, not skipped.
pub(super) fn classify(name: &str) -> Option<Class> {
    let t = name.trim().to_ascii_uppercase();
    if let Some(c) = classify_upper(&t) {
        return Some(c);
    }
    if solid_like(&t) {
        return None;
    }
    Some(Class::Skipped {
        nodes: skipped_nodes(&t),
    })
}

/// `C3D` after letters only (`C3D7`, `DC3D99`, `C3DX`): a name of the 3D solid family.
fn solid_like(t: &str) -> bool {
    t.find("C3D")
        .is_some_and(|pos| t[..pos].bytes().all(|b| b.is_ascii_alphabetic()))
}

fn classify_upper(t: &str) -> Option<Class> {
    // 3D solids: C3D*, DC3D*, AC3D*, EC3D* ..., classified by the digits after "C3D".
    if solid_like(t) {
        let pos = t.find("C3D")?;
        let (d, rest) = digits_after(&t[pos..], "C3D")?;
        return solid(d, rest);
    }
    for (prefix, hex, wedge) in [("COH3D", 8, 6), ("SC", 8, 6)] {
        if let Some((d, rest)) = digits_after(t, prefix) {
            if rest.is_empty() || rest.bytes().all(|b| b.is_ascii_alphabetic()) {
                if d == hex {
                    return solid(8, "");
                }
                if d == wedge {
                    return solid(6, "");
                }
            }
        }
    }
    // Triangular shells: STRI3, STRI65 (6 nodes).
    if let Some((d, _)) = digits_after(t, "STRI") {
        return surface(if d == 65 { 6 } else { d });
    }
    // Surface-like elements: the digits after the prefix are the node count.
    for prefix in [
        "SFM3D", "M3D", "R3D", "DS", "S", "CPEG", "CPS", "CPE", "CGAX", "CAX", "DC2D", "DCAX",
        "AC2D", "ACAX", "COH2D", "COHAX",
    ] {
        if let Some((d, _)) = digits_after(t, prefix) {
            return surface(d);
        }
    }
    // Beams and pipes: B21/B31 (2 nodes), B22/B32 (3), B23/B33 (2).
    for prefix in ["B", "PIPE", "ELBOW"] {
        if let Some((d, _)) = digits_after(t, prefix) {
            return match d {
                21 | 23 | 31 | 33 => line(2),
                22 | 32 => line(3),
                _ => None,
            };
        }
    }
    // Trusses, links, 2-D rigid elements: the digits are the node count.
    for prefix in ["T2D", "T3D", "DC1D", "R2D", "RB2D", "RB3D", "RAX"] {
        if let Some((d, _)) = digits_after(t, prefix) {
            return line(d);
        }
    }
    // Axisymmetric shells and membranes: 1 = linear (2 nodes), 2 = quadratic (3 nodes).
    for prefix in ["SAX", "DSAX", "MAX", "MGAX", "SFMAX", "SFMGAX"] {
        if let Some((d, _)) = digits_after(t, prefix) {
            return line(d + 1);
        }
    }
    None
}

/// Node counts of common types that are skipped, so that their records are consumed right.
fn skipped_nodes(t: &str) -> Option<usize> {
    const ONE: [&str; 7] = [
        "MASS", "ROTARYI", "HEATCAP", "SPRING1", "DASHPOT1", "DCOUP3D", "DCOUP2D",
    ];
    const TWO: [&str; 10] = [
        "SPRING2", "SPRINGA", "DASHPOT2", "DASHPOTA", "CONN3D2", "CONN2D2", "GAPUNI", "GAPCYL",
        "GAPSPHER", "JOINTC",
    ];
    if ONE.contains(&t) {
        Some(1)
    } else if TWO.contains(&t) {
        Some(2)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kind(t: &str) -> Option<ElementKind> {
        match classify(t) {
            Some(Class::Solid { kind, .. } | Class::Lower { kind, .. }) => Some(kind),
            Some(Class::Skipped { .. }) | None => None,
        }
    }

    #[test]
    fn solids_by_digits() {
        use ElementKind::*;
        for (t, k) in [
            ("C3D8", Hex8),
            ("C3D8R", Hex8),
            ("c3d8rh", Hex8),
            ("C3D8IH", Hex8),
            ("C3D8T", Hex8),
            ("DC3D8", Hex8),
            ("SC8R", Hex8),
            ("COH3D8", Hex8),
            ("C3D20RH", Hex20),
            ("DC3D20", Hex20),
            ("C3d4", Tet4),
            ("C3D4H", Tet4),
            ("DC3D4", Tet4),
            ("C3D10MH", Tet10),
            ("C3D10HS", Tet10),
            ("DC3D10", Tet10),
            ("C3D6H", Wedge6),
            ("SC6R", Wedge6),
            ("COH3D6", Wedge6),
            ("C3D15H", Wedge15),
            ("DC3D15", Wedge15),
            ("C3D5", Pyramid5),
            ("C3D13", Pyramid13),
            ("C3D27", Hex20),
        ] {
            assert_eq!(kind(t), Some(k), "{t}");
        }
        assert_eq!(
            classify("C3D27"),
            Some(Class::Solid {
                kind: Hex20,
                read: 27
            })
        );
        // Solid-looking names that are no known solid are refused, not read with a guessed
        // node count.
        for t in ["C3D7", "C3D18", "c3d99", "DC3D7", "C3D", "C3DX", "C3D1000"] {
            assert_eq!(classify(t), None, "{t}");
        }
    }

    #[test]
    fn lower_and_skipped() {
        use ElementKind::*;
        for (t, k, n) in [
            ("S4R", Quadrilateral, 4),
            ("S4R5", Quadrilateral, 4),
            ("S3", Triangle, 3),
            ("STRI3", Triangle, 3),
            ("STRI65", Triangle, 6),
            ("S8R", Quadrilateral, 8),
            ("M3D4R", Quadrilateral, 4),
            ("R3D3", Triangle, 3),
            ("SFM3D8R", Quadrilateral, 8),
            ("CPS4R", Quadrilateral, 4),
            ("CPE6M", Triangle, 6),
            ("CAX8R", Quadrilateral, 8),
            ("CPEG3", Triangle, 3),
            ("B31", Line, 2),
            ("B32", Line, 3),
            ("T3D2", Line, 2),
            ("T3D3", Line, 3),
        ] {
            assert_eq!(classify(t), Some(Class::Lower { kind: k, nodes: n }), "{t}");
        }
        assert_eq!(classify("MASS"), Some(Class::Skipped { nodes: Some(1) }));
        assert_eq!(classify("SPRINGA"), Some(Class::Skipped { nodes: Some(2) }));
        assert_eq!(classify("U1"), Some(Class::Skipped { nodes: None }));
        assert_eq!(classify("FOO4"), Some(Class::Skipped { nodes: None }));
    }
}
