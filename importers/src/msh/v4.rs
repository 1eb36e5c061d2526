//! MSH 4.1 `$Nodes` and `$Elements`. ASCII and binary files share the layout, so one reader
//! serves both: block headers go through the nom grammar, records through the tight readers.

use super::grammar::{int, size_t};
use super::lex::Cur;
use super::types::ElemType;
use super::{cap, element_type, fail, node_of, push_converted, Ctx, Res};
use crate::mesh::{Mesh, NodeIndex};

/// Checks an entity dimension read in the block header starting at `at`.
fn entity_dim(cur: &Cur<'_>, at: usize, dim: i64) -> Res<u8> {
    if (0..=3).contains(&dim) {
        Ok(dim as u8)
    } else if cur.enc.is_binary() {
        Err(fail(
            at,
            "an entity dimension (0 to 3)",
            format!("dimension {dim}"),
        ))
    } else {
        Err(cur.fail_at(at, "an entity dimension (0 to 3)"))
    }
}

/// The tags, then the coordinates, of the `n` nodes of one block (`ASCII` must match the
/// cursor's encoding; it only lets the compiler drop the encoding test from the loops).
fn node_block<const ASCII: bool>(
    cur: &mut Cur<'_>,
    ids: &mut Vec<u64>,
    xyz: &mut Vec<[f64; 3]>,
    n: u64,
    params: usize,
    offsets: &mut Option<&mut Vec<usize>>,
) -> Res<()> {
    for _ in 0..n {
        if let Some(o) = offsets.as_deref_mut() {
            o.push(cur.token_start());
        }
        ids.push(cur.size_t_as::<ASCII>("a node tag")?);
    }
    for _ in 0..n {
        let x = cur.real_as::<ASCII>("a node x coordinate")?;
        let y = cur.real_as::<ASCII>("a node y coordinate")?;
        let z = cur.real_as::<ASCII>("a node z coordinate")?;
        for _ in 0..params {
            cur.real_as::<ASCII>("a parametric coordinate of the node")?;
        }
        xyz.push([x, y, z]);
    }
    Ok(())
}

/// What the records of one element block need.
struct Block<'b> {
    index: &'b NodeIndex,
    ty: &'b ElemType,
    raw: &'b mut Vec<u32>,
    conv: &'b mut Vec<u32>,
}

impl Block<'_> {
    /// Reads `n` records `tag node...` (`ASCII` must match the cursor's encoding).
    fn read<const ASCII: bool>(
        &mut self,
        cur: &mut Cur<'_>,
        mesh: &mut Mesh,
        dropped: &mut Vec<(u32, u32)>,
        n: u64,
    ) -> Res<()> {
        let nodes = self.ty.nodes;
        for _ in 0..n {
            let id = cur.size_t_as::<ASCII>("an element tag")?;
            self.raw.clear();
            for _ in 0..nodes {
                let at = cur.p;
                let tag = cur.size_t_as::<ASCII>("a node tag of the element")?;
                self.raw.push(node_of(self.index, tag, cur, at)?);
            }
            push_converted(mesh, dropped, id, self.ty, self.raw, self.conv);
        }
        Ok(())
    }
}

/// Reads the `$Nodes` body up to and including `$EndNodes`. With `offsets`, also records where
/// each node tag starts (used only to locate a repeated tag).
pub(super) fn nodes(
    cur: &mut Cur<'_>,
    ids: &mut Vec<u64>,
    xyz: &mut Vec<[f64; 3]>,
    mut offsets: Option<&mut Vec<usize>>,
) -> Res<()> {
    let enc = cur.enc;
    let header = cur.token_start();
    let (blocks, count, _, _) = cur.run(
        (
            size_t(enc, "the number of node blocks"),
            size_t(enc, "the number of nodes"),
            size_t(enc, "the smallest node tag"),
            size_t(enc, "the largest node tag"),
        ),
        "a $Nodes header",
    )?;
    let hint = cap(count, cur.left() / (cur.min_size_t() + 3 * cur.min_real()));
    ids.reserve(hint);
    xyz.reserve(hint);
    let mut total = 0u64;
    for _ in 0..blocks {
        let at = cur.token_start();
        let (dim, _tag) = cur.run(
            (
                int(enc, "an entity dimension (0 to 3)"),
                int(enc, "an entity tag"),
            ),
            "a node block header",
        )?;
        let dim = entity_dim(cur, at, dim)?;
        let flag_at = cur.token_start();
        let parametric = cur.run(
            int(enc, "the parametric flag (0 or 1)"),
            "a node block header",
        )?;
        let params = match parametric {
            0 => 0,
            1 => usize::from(dim),
            _ if enc.is_binary() => {
                return Err(fail(
                    flag_at,
                    "the parametric flag (0 or 1)",
                    format!("{parametric}"),
                ))
            }
            _ => return Err(cur.fail_at(flag_at, "the parametric flag (0 or 1)")),
        };
        let n = cur.run(
            size_t(enc, "the number of nodes in the block"),
            "a node block header",
        )?;
        if enc.is_binary() {
            node_block::<false>(cur, ids, xyz, n, params, &mut offsets)?;
        } else {
            node_block::<true>(cur, ids, xyz, n, params, &mut offsets)?;
        }
        total += n;
    }
    if total != count {
        return Err(fail(
            header,
            format!("{count} nodes, as the $Nodes header says"),
            format!("{total} nodes in its blocks"),
        ));
    }
    cur.end_of("Nodes")
}

/// Reads the `$Elements` body up to and including `$EndElements`.
pub(super) fn elements(cx: &mut Ctx<'_>, cur: &mut Cur<'_>) -> Res<()> {
    let enc = cur.enc;
    let Some(index) = cx.index.take() else {
        return Err(fail(cur.p, "$Nodes before $Elements", "$Elements"));
    };
    let body = cur.p;
    let start = cx.mesh.element_count();
    let header = cur.token_start();
    let (blocks, count, _, _) = cur.run(
        (
            size_t(enc, "the number of element blocks"),
            size_t(enc, "the number of elements"),
            size_t(enc, "the smallest element tag"),
            size_t(enc, "the largest element tag"),
        ),
        "an $Elements header",
    )?;
    let hint = cap(count, cur.left() / (2 * cur.min_size_t()));
    cx.mesh.element_ids.reserve(hint);
    cx.mesh.element_kinds.reserve(hint);
    cx.mesh.element_offsets.reserve(hint);
    let mut raw: Vec<u32> = Vec::new();
    let mut conv: Vec<u32> = Vec::new();
    let mut total = 0u64;
    for _ in 0..blocks {
        let at = cur.token_start();
        let (dim, entity) = cur.run(
            (
                int(enc, "an entity dimension (0 to 3)"),
                int(enc, "an entity tag"),
            ),
            "an element block header",
        )?;
        let dim = entity_dim(cur, at, dim)?;
        let type_at = cur.token_start();
        let code = cur.run(int(enc, "an element type"), "an element block header")?;
        let ty = element_type(cur, type_at, code)?;
        let n = cur.run(
            size_t(enc, "the number of elements in the block"),
            "an element block header",
        )?;
        let first = cx.mesh.element_count();
        let fit = cap(n, cur.left() / ((ty.nodes + 1) * cur.min_size_t()));
        let stored = ty.take.map_or(ty.nodes, <[u8]>::len);
        cx.mesh.element_ids.reserve(fit);
        cx.mesh.element_kinds.reserve(fit);
        cx.mesh.element_offsets.reserve(fit);
        cx.mesh.connectivity.reserve(fit * stored);
        let (mesh, dropped) = (&mut cx.mesh, &mut cx.dropped);
        let mut block = Block {
            index: &index,
            ty: &ty,
            raw: &mut raw,
            conv: &mut conv,
        };
        if enc.is_binary() {
            block.read::<false>(cur, mesh, dropped, n)?;
        } else {
            block.read::<true>(cur, mesh, dropped, n)?;
        }
        total += n;
        let last = cx.mesh.element_count();
        cx.note_reduced(&ty, last - first);
        let physicals = cx.physicals_of(dim, entity).to_vec();
        for p in physicals {
            cx.groups
                .entry((dim, p))
                .or_default()
                .extend(first as u32..last as u32);
        }
    }
    cx.index = Some(index);
    if total != count {
        return Err(fail(
            header,
            format!("{count} elements, as the $Elements header says"),
            format!("{total} elements in its blocks"),
        ));
    }
    cur.end_of("Elements")?;
    match first_repeat(&cx.mesh.element_ids[start..]) {
        None => Ok(()),
        Some((first, second)) => {
            let tag = cx.mesh.element_ids[start + second];
            let first_at = record_offset(cur.d, enc, body, first)?;
            let second_at = record_offset(cur.d, enc, body, second)?;
            Err(fail(
                second_at,
                "an element tag not used before",
                format!(
                    "element tag {tag} a second time (first at {})",
                    cx.place(first_at)
                ),
            ))
        }
    }
}

/// The first element tag that repeats an earlier one, in file order: (index of its first
/// record, index of the repeat). Tags that only increase (gmsh numbers them so) are checked in
/// one pass; others with a bitset over their range, or by sorting when the range is too wide.
fn first_repeat(ids: &[u64]) -> Option<(usize, usize)> {
    if ids.windows(2).all(|w| w[0] < w[1]) {
        return None;
    }
    let lo = ids.iter().copied().min()?;
    let hi = ids.iter().copied().max()?;
    let words = (hi - lo) / 64 + 1;
    if words <= ids.len() as u64 {
        let mut seen = vec![0u64; words as usize];
        for (k, &id) in ids.iter().enumerate() {
            let b = id - lo;
            let (w, bit) = ((b / 64) as usize, 1u64 << (b % 64));
            if seen[w] & bit != 0 {
                return Some((ids.iter().position(|&t| t == id)?, k));
            }
            seen[w] |= bit;
        }
        None
    } else {
        let mut order: Vec<usize> = (0..ids.len()).collect();
        order.sort_unstable_by_key(|&k| (ids[k], k));
        order
            .windows(2)
            .filter(|w| ids[w[0]] == ids[w[1]])
            .map(|w| (w[0], w[1]))
            .min_by_key(|&(_, second)| second)
    }
}

/// Where the record of element `k` (0-based, in file order) of the `$Elements` body at `body`
/// starts. Only for error messages: the body has been read without error already.
#[cold]
#[inline(never)]
fn record_offset(data: &[u8], enc: super::grammar::Enc, body: usize, k: usize) -> Res<usize> {
    let mut cur = Cur::new(data, body, enc);
    cur.run(
        (
            size_t(enc, "the number of element blocks"),
            size_t(enc, "the number of elements"),
            size_t(enc, "the smallest element tag"),
            size_t(enc, "the largest element tag"),
        ),
        "an $Elements header",
    )?;
    let mut k = k as u64;
    loop {
        cur.run(
            (
                int(enc, "an entity dimension (0 to 3)"),
                int(enc, "an entity tag"),
            ),
            "an element block header",
        )?;
        let type_at = cur.token_start();
        let code = cur.run(int(enc, "an element type"), "an element block header")?;
        let ty = element_type(&cur, type_at, code)?;
        let n = cur.run(
            size_t(enc, "the number of elements in the block"),
            "an element block header",
        )?;
        let skip = k.min(n) * (ty.nodes as u64 + 1);
        for _ in 0..skip {
            cur.size_t("an element record")?;
        }
        if k < n {
            return Ok(cur.token_start());
        }
        k -= n;
    }
}

#[cfg(test)]
mod tests {
    use super::first_repeat;

    #[test]
    fn first_repeat_in_file_order() {
        assert_eq!(first_repeat(&[]), None);
        assert_eq!(first_repeat(&[1, 2, 5, 9]), None);
        // Not increasing: the bitset over the range.
        assert_eq!(first_repeat(&[11, 20, 12, 13]), None);
        assert_eq!(first_repeat(&[5, 3, 4, 3, 5]), Some((1, 3)));
        // A range too wide for a bitset: sorted.
        let far = 1u64 << 50;
        assert_eq!(first_repeat(&[far, 1, far - 1]), None);
        assert_eq!(first_repeat(&[far, 7, 1, 7, far]), Some((1, 3)));
        assert_eq!(first_repeat(&[far, 1, 2, far, 1]), Some((0, 3)));
    }
}
