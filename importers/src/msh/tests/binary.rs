//! Binary MSH files: a writer of raw values in either byte order and the tests on its output.

use super::*;

/// Writes raw values of a binary MSH file in either byte order.
struct Bin {
    big: bool,
    wide: bool,
    out: Vec<u8>,
}

impl Bin {
    fn new(big: bool, wide: bool) -> Bin {
        Bin {
            big,
            wide,
            out: Vec::new(),
        }
    }
    fn text(&mut self, s: &str) -> &mut Self {
        self.out.extend_from_slice(s.as_bytes());
        self
    }
    fn i(&mut self, v: i32) -> &mut Self {
        let b = if self.big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        };
        self.out.extend_from_slice(&b);
        self
    }
    fn st(&mut self, v: u64) -> &mut Self {
        if self.wide {
            let b = if self.big {
                v.to_be_bytes()
            } else {
                v.to_le_bytes()
            };
            self.out.extend_from_slice(&b);
        } else {
            let v = v as u32;
            let b = if self.big {
                v.to_be_bytes()
            } else {
                v.to_le_bytes()
            };
            self.out.extend_from_slice(&b);
        }
        self
    }
    fn f(&mut self, v: f64) -> &mut Self {
        let b = if self.big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        };
        self.out.extend_from_slice(&b);
        self
    }
}

const TET_XYZ: [[f64; 3]; 5] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [1.0, 1.0, 1.0],
];
const TET_TAGS: [u64; 5] = [9, 3, 1, 7, 5];

pub(super) fn msh41_binary(big: bool, wide: bool) -> Vec<u8> {
    let mut b = Bin::new(big, wide);
    b.text(&format!(
        "$MeshFormat\n4.1 1 {}\n",
        if wide { 8 } else { 4 }
    ))
    .i(1)
    .text("\n$EndMeshFormat\n$PhysicalNames\n1\n3 5 \"vol\"\n$EndPhysicalNames\n$Entities\n");
    b.st(0).st(0).st(0).st(1);
    b.i(2);
    for v in [0.0, 0.0, 0.0, 1.0, 1.0, 1.0] {
        b.f(v);
    }
    b.st(1).i(5).st(0);
    b.text("\n$EndEntities\n$Nodes\n");
    b.st(1).st(5).st(1).st(9);
    b.i(3).i(2).i(0).st(5);
    for t in TET_TAGS {
        b.st(t);
    }
    for p in TET_XYZ {
        b.f(p[0]).f(p[1]).f(p[2]);
    }
    b.text("\n$EndNodes\n$Elements\n");
    b.st(1).st(2).st(1).st(2);
    b.i(3).i(2).i(4).st(2);
    b.st(1).st(9).st(3).st(1).st(7);
    b.st(2).st(3).st(1).st(7).st(5);
    b.text("\n$EndElements\n$Periodic\n");
    // A skipped section may hold any bytes, even "$End" not at a line start.
    b.out
        .extend_from_slice(&[0, 1, 2, b'$', b'E', b'n', b'd', 0xff, b'\n', 0]);
    b.text("\n$EndPeriodic\n");
    b.out
}

#[test]
fn msh41_binary_both_byte_orders_and_size_t_widths() {
    for big in [false, true] {
        for wide in [true, false] {
            let m = ok(&msh41_binary(big, wide));
            assert_eq!(m.node_ids, TET_TAGS.to_vec(), "big {big} wide {wide}");
            assert_eq!(m.coords, TET_XYZ.to_vec());
            assert_eq!(m.element_ids, vec![1, 2]);
            assert_eq!(ids_of(&m, 0), vec![9, 3, 1, 7]);
            assert_eq!(ids_of(&m, 1), vec![3, 1, 7, 5]);
            assert_eq!(sets(&m), vec![("vol".to_string(), 2, 5)]);
        }
    }
}

#[test]
fn msh41_binary_errors_are_byte_offsets() {
    let full = msh41_binary(false, true);
    // Cut 4 bytes into the third coordinate: after the header (4 size_t), the block header
    // (3 int, 1 size_t) and the 5 tags.
    let nodes = find(&full, b"$Nodes\n") + 7;
    let cut = nodes + 32 + 20 + 40 + 20;
    let e = err(&full[..cut]);
    assert_eq!(byte_of(&e), cut as u64 - 4, "{e}");
    assert!(e.to_string().contains("end of file"), "{e}");

    // A node block that claims 2^40 nodes: an error at the end, no huge allocation.
    let mut lying = full.clone();
    let nodes = find(&lying, b"$Nodes\n") + 7;
    let count_at = nodes + 4 * 8 + 12;
    lying[count_at..count_at + 8].copy_from_slice(&(1u64 << 40).to_le_bytes());
    let e = err(&lying);
    byte_of(&e);

    // Bad byte-order check.
    let mut bad = full.clone();
    let check = find(&bad, b"4.1 1 8\n") + 8;
    bad[check] = 7;
    let e = err(&bad);
    assert_eq!(byte_of(&e), check as u64, "{e}");

    // Unknown element type 999 in the block header.
    let mut ty = full.clone();
    let elems = find(&ty, b"$Elements\n") + 10;
    let type_at = elems + 4 * 8 + 8;
    ty[type_at..type_at + 4].copy_from_slice(&999i32.to_le_bytes());
    let e = err(&ty);
    assert_eq!(byte_of(&e), type_at as u64, "{e}");
    assert!(e.to_string().contains("type 999"), "{e}");
}

#[test]
fn msh41_repeated_element_tag_is_an_error() {
    // ASCII: the point element 13 renumbered 11, the tag of the triangle on line 32.
    let text = MSH41.replace("13 1000\n", "11 1000\n");
    let e = err(text.as_bytes());
    let line = 1 + text[..text.find("11 1000\n").unwrap()]
        .matches('\n')
        .count();
    assert_eq!(line_of(&e), line, "{e}");
    assert_eq!(e.expected, "an element tag not used before");
    assert_eq!(
        e.found, "element tag 11 a second time (first at line 32)",
        "{e}"
    );
    // Binary, both size_t widths: the second tet renumbered 1.
    for wide in [true, false] {
        let w = if wide { 8 } else { 4 };
        let mut data = msh41_binary(false, wide);
        let first = find(&data, b"$Elements\n") + 10 + 4 * w + 12 + w;
        let second = first + 5 * w;
        data[second] = 1;
        let e = err(&data);
        assert_eq!(byte_of(&e), second as u64, "{e}");
        assert_eq!(
            e.found,
            format!("element tag 1 a second time (first at byte {first})")
        );
    }
}

pub(super) fn msh22_binary(big: bool, one_per_header: bool) -> Vec<u8> {
    let mut b = Bin::new(big, true);
    b.text("$MeshFormat\n2.2 1 8\n")
        .i(1)
        .text("\n$EndMeshFormat\n$Nodes\n5\n");
    for (t, p) in TET_TAGS.iter().zip(TET_XYZ) {
        b.i(*t as i32).f(p[0]).f(p[1]).f(p[2]);
    }
    b.text("\n$EndNodes\n$Elements\n5\n");
    // Two tets in physical 5 (elementary 2), the first again in physical 6 with a new number
    // (as gmsh writes it), then a triangle with no tags.
    let records: [(i32, i32, i32, &[i32]); 4] = [
        (1, 5, 2, &[9, 3, 1, 7]),
        (2, 6, 2, &[9, 3, 1, 7]),
        (3, 5, 2, &[3, 1, 7, 5]),
        (4, 5, 2, &[3, 1, 7, 5]),
    ];
    if one_per_header {
        for (n, phys, ent, nodes) in records {
            b.i(4).i(1).i(2).i(n).i(phys).i(ent);
            for &x in nodes {
                b.i(x);
            }
        }
    } else {
        b.i(4).i(4).i(2);
        for (n, phys, ent, nodes) in records {
            b.i(n).i(phys).i(ent);
            for &x in nodes {
                b.i(x);
            }
        }
    }
    b.i(2).i(1).i(0).i(7).i(9).i(3).i(1);
    b.text("\n$EndElements\n");
    b.out
}

#[test]
fn msh22_binary_both_byte_orders_and_block_shapes() {
    for big in [false, true] {
        for one in [true, false] {
            let m = ok(&msh22_binary(big, one));
            assert_eq!(m.node_ids, TET_TAGS.to_vec());
            assert_eq!(m.coords, TET_XYZ.to_vec());
            assert_eq!(m.element_ids, vec![1, 3, 7], "big {big} one {one}");
            assert_eq!(
                sets(&m),
                vec![
                    ("PhysicalVolume5".to_string(), 2, 5),
                    ("PhysicalVolume6".to_string(), 1, 4)
                ]
            );
        }
    }
}

#[test]
fn msh22_binary_lying_block_count() {
    let mut data = msh22_binary(false, false);
    let at = find(&data, b"$Elements\n5\n") + 12;
    data[at + 4..at + 8].copy_from_slice(&9i32.to_le_bytes());
    let e = err(&data);
    assert_eq!(byte_of(&e), at as u64 + 4, "{e}");
}
