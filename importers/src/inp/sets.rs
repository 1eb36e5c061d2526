//! Set members while the deck is read (labels and GENERATE ranges per unit) and their
//! resolution to mesh indices at the end.

use super::{element_index, node_index, Unit};
use crate::mesh::{Mesh, MISSING_NODE};

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
    for chunk in chunks {
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
                for &[first, last, step] in ranges {
                    let count = (last - first) / step + 1;
                    if count <= 4 * defined as u64 + 1024 {
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
                        // A huge range: filter the labels that exist instead of walking it.
                        let mut found = 0u64;
                        let in_range = |l: u64| {
                            l >= first && l <= last && (l - first).checked_rem(step) == Some(0)
                        };
                        let mut visit = |labels: &[u64]| {
                            for &l in labels {
                                if in_range(l) {
                                    if let Some(i) = lookup(*unit, l) {
                                        out.push(i);
                                        found += 1;
                                    }
                                }
                            }
                        };
                        if let Some(p) = u.part {
                            visit(if elem {
                                &units[p].block.elem_labels
                            } else {
                                &units[p].block.node_labels
                            });
                        }
                        visit(if elem {
                            &u.block.elem_labels
                        } else {
                            &u.block.node_labels
                        });
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
