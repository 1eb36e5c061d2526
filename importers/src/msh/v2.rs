//! MSH 2.x `$Nodes` and `$Elements`, ASCII and binary.
//!
//! ASCII: `count`, then `tag x y z` per node and `number type ntags tags... nodes...` per
//! element (read as tokens). Binary: an ASCII count line, then raw records; elements come in
//! blocks headed by `type, count, ntags` (int32), one or many elements per header.
//!
//! An element in k physical groups is written k times; the repeats are merged by element
//! number (they must have the same type and nodes) and every physical tag is kept.

use std::collections::HashMap;

use super::grammar::{count_line, int, size_t, Enc};
use super::lex::Cur;
use super::types::ElemType;
use super::{cap, element_type, fail, node_of, push_converted, Ctx, Res};
use crate::mesh::ElementRef;

/// The count that opens `$Nodes` and `$Elements`: a token in ASCII files, a line in binary ones.
fn count(cur: &mut Cur<'_>, what: &'static str) -> Res<u64> {
    if cur.enc.is_binary() {
        cur.run(count_line(what), what)
    } else {
        cur.run(size_t(Enc::Ascii, what), what)
    }
}

/// A non-negative MSH 2 integer (node tag, element number): a token or a raw int32.
#[inline(always)]
fn tag(cur: &mut Cur<'_>, what: &'static str) -> Res<u64> {
    let at = cur.token_start();
    let v = cur.int(what)?;
    if v < 0 {
        return Err(negative(cur, at, what, v));
    }
    Ok(v as u64)
}

#[cold]
#[inline(never)]
fn negative(cur: &Cur<'_>, at: usize, what: &'static str, v: i64) -> Box<super::Fail> {
    let expected = format!("{what} (not negative)");
    if cur.enc.is_binary() {
        fail(at, expected, format!("{v}"))
    } else {
        cur.fail_at(at, expected)
    }
}

/// Reads the `$Nodes` body up to and including `$EndNodes`.
pub(super) fn nodes(
    cur: &mut Cur<'_>,
    ids: &mut Vec<u64>,
    xyz: &mut Vec<[f64; 3]>,
    mut offsets: Option<&mut Vec<usize>>,
) -> Res<()> {
    let n = count(cur, "the number of nodes")?;
    let per_node = if cur.enc.is_binary() { 28 } else { 8 };
    let hint = cap(n, cur.left() / per_node);
    ids.reserve(hint);
    xyz.reserve(hint);
    for _ in 0..n {
        if let Some(o) = offsets.as_deref_mut() {
            o.push(cur.token_start());
        }
        ids.push(tag(cur, "a node tag")?);
        let x = cur.real("a node x coordinate")?;
        let y = cur.real("a node y coordinate")?;
        let z = cur.real("a node z coordinate")?;
        xyz.push([x, y, z]);
    }
    cur.end_of("Nodes")
}

/// Finds the earlier listing of an element. Gmsh writes an element that is in k physical groups
/// k times in a row, with the same type, elementary tag and nodes but (in every gmsh version
/// checked, up to 4.15) a new element number each time; other writers repeat the number. So a
/// record is merged with the one just before it when type, elementary tag and nodes agree, and
/// with any earlier record of the same number (which must then agree too).
///
/// While element numbers only increase (the usual case) no map is needed; the first number
/// that does not increase builds one from the numbers so far.
struct Repeats {
    last: Option<u64>,
    map: Option<HashMap<u64, u32>>,
    prev: Option<(u32, i64)>,
}

impl Repeats {
    fn find(&mut self, number: u64, ids: &[u64]) -> Option<u32> {
        if self.map.is_none() {
            match self.last {
                Some(last) if number <= last => {
                    let mut map = HashMap::with_capacity(ids.len());
                    for (i, &id) in ids.iter().enumerate() {
                        map.entry(id).or_insert(i as u32);
                    }
                    self.map = Some(map);
                }
                _ => return None,
            }
        }
        self.map.as_ref().and_then(|m| m.get(&number).copied())
    }

    fn added(&mut self, number: u64, index: u32) {
        self.last = Some(self.last.map_or(number, |l| l.max(number)));
        if let Some(m) = &mut self.map {
            m.insert(number, index);
        }
    }
}

/// Whether a stored element has the type and (converted) nodes of a record.
fn same_element(first: ElementRef<'_>, ty: &ElemType, raw: &[u32]) -> bool {
    first.kind == ty.kind
        && match ty.take {
            None => first.nodes == raw,
            Some(map) => {
                map.len() == first.nodes.len()
                    && map
                        .iter()
                        .zip(first.nodes)
                        .all(|(&k, &n)| raw[k as usize] == n)
            }
        }
}

/// One element record: its tags and nodes in file order (dense indices).
struct Record<'r> {
    at: usize,
    number: u64,
    elementary: i64,
    physical: i64,
    raw: &'r [u32],
}

/// Stores a record, or merges it with its earlier listing.
fn add(
    cx: &mut Ctx<'_>,
    repeats: &mut Repeats,
    ty: &ElemType,
    rec: Record<'_>,
    conv: &mut Vec<u32>,
) -> Res<()> {
    let after = repeats.prev.and_then(|(p, elementary)| {
        (elementary == rec.elementary && same_element(cx.mesh.element(p as usize), ty, rec.raw))
            .then_some(p)
    });
    let index = match after {
        Some(p) => p,
        None => match repeats.find(rec.number, &cx.mesh.element_ids) {
            Some(e) => {
                if !same_element(cx.mesh.element(e as usize), ty, rec.raw) {
                    let n = rec.number;
                    return Err(fail(
                        rec.at,
                        format!("element {n} repeated with the type and nodes it had before"),
                        format!("element {n} listed again with another type or other nodes"),
                    ));
                }
                e
            }
            None => {
                let e =
                    push_converted(&mut cx.mesh, &mut cx.dropped, rec.number, ty, rec.raw, conv);
                repeats.added(rec.number, e);
                cx.note_reduced(ty, 1);
                e
            }
        },
    };
    repeats.prev = Some((index, rec.elementary));
    if rec.physical != 0 {
        let key = (ty.kind.dim(), rec.physical);
        cx.groups.entry(key).or_default().push(index);
    }
    Ok(())
}

/// Reads `ntags` tags and returns (physical, elementary): the first two, 0 when absent.
#[inline]
fn tags(cur: &mut Cur<'_>, ntags: u64) -> Res<(i64, i64)> {
    let (mut physical, mut elementary) = (0, 0);
    for k in 0..ntags {
        let t = cur.int("an element tag")?;
        match k {
            0 => physical = t,
            1 => elementary = t,
            _ => {}
        }
    }
    Ok((physical, elementary))
}

/// Reads the `$Elements` body up to and including `$EndElements`.
pub(super) fn elements(cx: &mut Ctx<'_>, cur: &mut Cur<'_>) -> Res<()> {
    let Some(index) = cx.index.take() else {
        return Err(fail(cur.p, "$Nodes before $Elements", "$Elements"));
    };
    let total = count(cur, "the number of elements")?;
    let hint = cap(
        total,
        cur.left() / if cur.enc.is_binary() { 16 } else { 10 },
    );
    cx.mesh.element_ids.reserve(hint);
    cx.mesh.element_kinds.reserve(hint);
    cx.mesh.element_offsets.reserve(hint);
    let mut repeats = Repeats {
        last: None,
        map: None,
        prev: None,
    };
    let mut raw: Vec<u32> = Vec::new();
    let mut conv: Vec<u32> = Vec::new();
    if cur.enc.is_binary() {
        let enc = cur.enc;
        let mut done = 0u64;
        while done < total {
            let at = cur.p;
            let (code, follow, ntags) = cur.run(
                (
                    int(enc, "an element type"),
                    int(enc, "the number of elements following the header"),
                    int(enc, "the number of tags"),
                ),
                "an element block header",
            )?;
            let ty = element_type(cur, at, code)?;
            if follow < 1 || follow as u64 > total - done {
                return Err(fail(
                    at + 4,
                    format!(
                        "a number of elements from 1 to {} (the rest of the count)",
                        total - done
                    ),
                    format!("{follow}"),
                ));
            }
            if ntags < 0 {
                return Err(fail(
                    at + 8,
                    "a number of tags (not negative)",
                    format!("{ntags}"),
                ));
            }
            for _ in 0..follow {
                let rec = cur.p;
                let number = tag(cur, "an element number")?;
                let (physical, elementary) = tags(cur, ntags as u64)?;
                raw.clear();
                for _ in 0..ty.nodes {
                    let at = cur.p;
                    let t = tag(cur, "a node number of the element")?;
                    raw.push(node_of(&index, t, cur, at)?);
                }
                let rec = Record {
                    at: rec,
                    number,
                    elementary,
                    physical,
                    raw: &raw,
                };
                add(cx, &mut repeats, &ty, rec, &mut conv)?;
            }
            done += follow as u64;
        }
    } else {
        for _ in 0..total {
            let rec = cur.token_start();
            let number = tag(cur, "an element number")?;
            let type_at = cur.token_start();
            let code = cur.int("an element type")?;
            let ty = element_type(cur, type_at, code)?;
            let ntags = tag(cur, "the number of tags")?;
            let (physical, elementary) = tags(cur, ntags)?;
            raw.clear();
            for _ in 0..ty.nodes {
                let at = cur.p;
                let t = tag(cur, "a node number of the element")?;
                raw.push(node_of(&index, t, cur, at)?);
            }
            let rec = Record {
                at: rec,
                number,
                elementary,
                physical,
                raw: &raw,
            };
            add(cx, &mut repeats, &ty, rec, &mut conv)?;
        }
    }
    cx.index = Some(index);
    cur.end_of("Elements")
}
