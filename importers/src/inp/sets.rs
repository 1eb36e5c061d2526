//! Set members while the deck is read (labels and GENERATE ranges per unit) and their
//! resolution to mesh indices at the end.

use super::units::{element_index, node_index, Unit};
use crate::mesh::{Mesh, MISSING_NODE};

/// A named set while the deck is read.
#[derive(Debug)]
pub(super) struct SetAcc {
    pub(super) name: String,
    pub(super) elem: bool,
    pub(super) chunks: Vec<Chunk>,
}

/// Members of a set being read, by label in a unit.
#[derive(Clone, Debug)]
pub(super) enum Chunk {
    Labels {
        unit: usize,
        labels: Vec<u64>,
    },
    Ranges {
        unit: usize,
        ranges: Vec<[u64; 3]>,
    },
    /// The nodes of the elements these chunks name (`*NSET, ELSET=`).
    NodesOf(Vec<Chunk>),
}

pub(super) fn remap_chunks(chunks: &[Chunk], from: usize, to: usize) -> Vec<Chunk> {
    let map = |u: usize| if u == from { to } else { u };
    chunks
        .iter()
        .map(|c| match c {
            Chunk::Labels { unit, labels } => Chunk::Labels {
                unit: map(*unit),
                labels: labels.clone(),
            },
            Chunk::Ranges { unit, ranges } => Chunk::Ranges {
                unit: map(*unit),
                ranges: ranges.clone(),
            },
            Chunk::NodesOf(inner) => Chunk::NodesOf(remap_chunks(inner, from, to)),
        })
        .collect()
}

/// The number of labels and ranges in `chunks` (what copying them costs).
pub(super) fn chunk_members(chunks: &[Chunk]) -> usize {
    chunks
        .iter()
        .map(|c| match c {
            Chunk::Labels { labels, .. } => labels.len(),
            Chunk::Ranges { ranges, .. } => ranges.len(),
            Chunk::NodesOf(inner) => chunk_members(inner),
        })
        .fold(0usize, usize::saturating_add)
}

/// Appends copied chunks, merging labels and ranges into the last chunk where the unit is the
/// same (so that a set copied many times stays a few long lists, not many short ones).
pub(super) fn append_chunks(chunks: &mut Vec<Chunk>, copied: Vec<Chunk>) {
    for c in copied {
        match c {
            Chunk::Labels { unit, labels } => match chunks.last_mut() {
                Some(Chunk::Labels { unit: u, labels: l }) if *u == unit => l.extend(labels),
                _ => chunks.push(Chunk::Labels { unit, labels }),
            },
            Chunk::Ranges { unit, ranges } => match chunks.last_mut() {
                Some(Chunk::Ranges { unit: u, ranges: r }) if *u == unit => r.extend(ranges),
                _ => chunks.push(Chunk::Ranges { unit, ranges }),
            },
            nodes_of => chunks.push(nodes_of),
        }
    }
}

/// Adds a label; with `via`, to the element list of a trailing `NodesOf` chunk.
pub(super) fn push_label(chunks: &mut Vec<Chunk>, via: bool, u: usize, label: u64) {
    if via {
        match chunks.last_mut() {
            Some(Chunk::NodesOf(inner)) => push_label(inner, false, u, label),
            _ => chunks.push(Chunk::NodesOf(vec![Chunk::Labels {
                unit: u,
                labels: vec![label],
            }])),
        }
        return;
    }
    if let Some(Chunk::Labels { unit, labels }) = chunks.last_mut() {
        if *unit == u {
            labels.push(label);
            return;
        }
    }
    chunks.push(Chunk::Labels {
        unit: u,
        labels: vec![label],
    });
}

/// Adds a GENERATE range; with `via`, to the element list of a trailing `NodesOf` chunk.
pub(super) fn push_range(chunks: &mut Vec<Chunk>, via: bool, u: usize, range: [u64; 3]) {
    if via {
        match chunks.last_mut() {
            Some(Chunk::NodesOf(inner)) => push_range(inner, false, u, range),
            _ => chunks.push(Chunk::NodesOf(vec![Chunk::Ranges {
                unit: u,
                ranges: vec![range],
            }])),
        }
        return;
    }
    if let Some(Chunk::Ranges { unit, ranges }) = chunks.last_mut() {
        if *unit == u {
            ranges.push(range);
            return;
        }
    }
    chunks.push(Chunk::Ranges {
        unit: u,
        ranges: vec![range],
    });
}

/// GENERATE ranges sorted, without repeats, and with overlapping or adjacent ranges of
/// increment 1 merged.
fn normalised(ranges: &[[u64; 3]]) -> Vec<[u64; 3]> {
    let mut v = ranges.to_vec();
    v.sort_unstable_by_key(|&[first, last, step]| (step, first, last));
    v.dedup();
    let mut out: Vec<[u64; 3]> = Vec::with_capacity(v.len());
    for r in v {
        match out.last_mut() {
            Some(prev) if r[2] == 1 && prev[2] == 1 && r[0] <= prev[1].saturating_add(1) => {
                prev[1] = prev[1].max(r[1]);
            }
            _ => out.push(r),
        }
    }
    out
}

/// Resolves set chunks to sorted, unique mesh indices; counts entries that name nothing.
pub(super) fn resolve(
    units: &[Unit],
    mesh: &Mesh,
    elem: bool,
    chunks: &[Chunk],
    missing: &mut usize,
    example: &mut Option<u64>,
) -> Vec<u32> {
    let lookup = |u: usize, l: u64| {
        if !units[u].placed {
            None
        } else if elem {
            element_index(units, u, l)
        } else {
            node_index(units, u, l)
        }
    };
    let mut out: Vec<u32> = Vec::new();
    // Overlapping GENERATE ranges and copied sets list members many times: the list is made
    // unique whenever it grows past twice the number of nodes or elements that can be in it.
    let bound = 2 * if elem {
        mesh.element_count()
    } else {
        mesh.node_count()
    } + 4096;
    let mut squeeze_at = bound;
    for chunk in chunks {
        if out.len() > squeeze_at {
            out.sort_unstable();
            out.dedup();
            squeeze_at = out.len() + bound;
        }
        match chunk {
            Chunk::Labels { unit, labels } => {
                for &l in labels {
                    match lookup(*unit, l) {
                        Some(i) => out.push(i),
                        None => {
                            *missing += 1;
                            example.get_or_insert(l);
                        }
                    }
                }
            }
            Chunk::Ranges { unit, ranges } => {
                let u = &units[*unit];
                let defined: usize = {
                    let own = if elem {
                        u.block.elems.len()
                    } else {
                        u.block.nodes.len()
                    };
                    let part = u.part.map_or(0, |p| {
                        if elem {
                            units[p].block.elems.len()
                        } else {
                            units[p].block.nodes.len()
                        }
                    });
                    own + part
                };
                // Repeated and overlapping ranges are merged first, so that each label is
                // visited once however often the deck names it.
                let ranges = normalised(ranges);
                // Labels defined in the unit (and its part), sorted, made when a range is
                // searched instead of walked.
                let mut sorted: Option<Vec<u64>> = None;
                // Labels walked one by one so far; past this budget ranges are searched.
                let mut walk_left = 8 * defined as u64 + 4096;
                for [first, last, step] in ranges {
                    if out.len() > squeeze_at {
                        out.sort_unstable();
                        out.dedup();
                        squeeze_at = out.len() + bound;
                    }
                    let count = (last - first) / step + 1;
                    if count <= 4 * defined as u64 + 1024 && count <= walk_left {
                        walk_left -= count;
                        let mut l = first;
                        loop {
                            match lookup(*unit, l) {
                                Some(i) => out.push(i),
                                None => {
                                    *missing += 1;
                                    example.get_or_insert(l);
                                }
                            }
                            match l.checked_add(step) {
                                Some(n) if n <= last => l = n,
                                _ => break,
                            }
                        }
                    } else {
                        // A huge range (or many): take the defined labels inside it.
                        let labels = sorted.get_or_insert_with(|| {
                            let mut v: Vec<u64> = Vec::new();
                            if let Some(p) = u.part {
                                v.extend_from_slice(if elem {
                                    &units[p].block.elem_labels
                                } else {
                                    &units[p].block.node_labels
                                });
                            }
                            v.extend_from_slice(if elem {
                                &u.block.elem_labels
                            } else {
                                &u.block.node_labels
                            });
                            v.sort_unstable();
                            v.dedup();
                            v
                        });
                        let from = labels.partition_point(|&l| l < first);
                        let mut found = 0u64;
                        for &l in labels[from..].iter().take_while(|&&l| l <= last) {
                            if (l - first) % step == 0 {
                                if let Some(i) = lookup(*unit, l) {
                                    out.push(i);
                                    found += 1;
                                }
                            }
                        }
                        let lost = count.saturating_sub(found);
                        *missing =
                            missing.saturating_add(usize::try_from(lost).unwrap_or(usize::MAX));
                        if lost > 0 && example.is_none() {
                            *example = Some(first);
                        }
                    }
                }
            }
            Chunk::NodesOf(inner) => {
                let mut inner_missing = 0;
                let elements = resolve(units, mesh, true, inner, &mut inner_missing, example);
                *missing += inner_missing;
                for e in elements {
                    out.extend(
                        mesh.element(e as usize)
                            .nodes
                            .iter()
                            .copied()
                            .filter(|&n| n != MISSING_NODE),
                    );
                }
            }
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}
