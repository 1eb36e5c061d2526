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
    cur.end_of("Elements")
}
