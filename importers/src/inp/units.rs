//! Model structure: the label name spaces (*units*: the model level, parts, the assembly,
//! instances), the nodes and elements each defines, and the lookup of a placed unit's labels.

use std::collections::HashMap;

use super::geom::Affine;
use super::labels::LabelMap;
use crate::mesh::ElementKind;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum UnitKind {
    Model,
    Part,
    Assembly,
    Instance,
}

/// Nodes and elements defined directly in one unit, by the unit's own labels.
#[derive(Debug, Default)]
pub(super) struct Block {
    pub(super) node_labels: Vec<u64>,
    pub(super) coords: Vec<[f64; 3]>,
    pub(super) nodes: LabelMap,
    pub(super) elem_labels: Vec<u64>,
    pub(super) elem_kinds: Vec<ElementKind>,
    /// `elem_offsets[e]..elem_offsets[e + 1]` in `elem_tokens`; starts empty, `[0, ..]` after
    /// the first element.
    pub(super) elem_offsets: Vec<usize>,
    /// Node labels as written (0 = missing mid-side node, [`GLOBAL`](super::GLOBAL)-tagged =
    /// mesh index).
    pub(super) elem_tokens: Vec<u64>,
    /// (file, line) of each element record, for errors found when it is resolved.
    pub(super) elem_src: Vec<(u32, u32)>,
    pub(super) elems: LabelMap,
    /// Parts only: connectivity resolved to indices into `coords`, same layout as tokens.
    pub(super) local_conn: Vec<u32>,
    pub(super) redefined_nodes: usize,
}

impl Block {
    pub(super) fn element_count(&self) -> usize {
        self.elem_labels.len()
    }

    pub(super) fn element_range(&self, e: usize) -> std::ops::Range<usize> {
        self.elem_offsets[e]..self.elem_offsets[e + 1]
    }
}

/// A label name space: the model level, a part, the assembly, or an instance.
#[derive(Debug)]
pub(super) struct Unit {
    pub(super) kind: UnitKind,
    pub(super) name: String,
    /// Instances: the part they copy.
    pub(super) part: Option<usize>,
    pub(super) block: Block,
    /// Parts: their own set name space (arena indices) and definition order.
    pub(super) set_names: HashMap<(bool, String), usize>,
    pub(super) set_order: Vec<usize>,
    /// Instances: positioning from the data lines.
    pub(super) transform: Option<Affine>,
    pub(super) placed: bool,
    pub(super) part_node_base: u32,
    pub(super) part_elem_base: u32,
    pub(super) own_node_base: u32,
    pub(super) own_elem_base: u32,
    /// Parts: whether some instance uses them.
    pub(super) instanced: bool,
    /// Where the unit was opened.
    pub(super) file: u32,
    pub(super) line: usize,
}

impl Unit {
    pub(super) fn new(kind: UnitKind, name: String, file: u32, line: usize) -> Unit {
        Unit {
            kind,
            name,
            part: None,
            block: Block::default(),
            set_names: HashMap::new(),
            set_order: Vec::new(),
            transform: None,
            placed: false,
            part_node_base: 0,
            part_elem_base: 0,
            own_node_base: 0,
            own_elem_base: 0,
            instanced: false,
            file,
            line,
        }
    }
}

/// Global mesh index of a node label of a placed unit.
pub(super) fn node_index(units: &[Unit], u: usize, label: u64) -> Option<u32> {
    let unit = &units[u];
    if let Some(p) = unit.part {
        if let Some(i) = units[p].block.nodes.get(label) {
            return Some(unit.part_node_base + i);
        }
    }
    unit.block.nodes.get(label).map(|i| unit.own_node_base + i)
}

/// Global mesh index of an element label of a placed unit.
pub(super) fn element_index(units: &[Unit], u: usize, label: u64) -> Option<u32> {
    let unit = &units[u];
    if let Some(p) = unit.part {
        if let Some(i) = units[p].block.elems.get(label) {
            return Some(unit.part_elem_base + i);
        }
    }
    unit.block.elems.get(label).map(|i| unit.own_elem_base + i)
}
