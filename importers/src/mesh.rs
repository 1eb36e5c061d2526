//! The one mesh type every importer produces.
//!
//! # Node-order convention
//!
//! All three formats agree on the corner order of linear solids (FORMATS.md §0), so corners are
//! stored as every format writes them:
//!
//! * **hex8**: bottom quad 0-1-2-3, counter-clockwise seen from the top (so `(n1−n0)×(n3−n0)`
//!   points toward nodes 4..7), then the top quad 4-5-6-7 above 0-1-2-3.
//! * **tet4**: base 0-1-2, apex 3 on the side that 0-1-2 winds counter-clockwise toward.
//! * **wedge6**: bottom triangle 0-1-2 with `(n1−n0)×(n2−n0)` pointing toward the top triangle
//!   3-4-5 (Gmsh prism = Abaqus C3D6 = ANSYS `I J K M N O`; VTK before 9.7 is mirrored).
//! * **pyramid5**: base 0-1-2-3 as the hex bottom, apex 4.
//!
//! Second-order elements keep their corners first, unchanged, and store mid-edge nodes in the
//! VTK / Abaqus / ANSYS order (Gmsh's own order is permuted on import, FORMATS.md §2.6):
//!
//! * **hex20**: 8..11 on edges (0,1)(1,2)(2,3)(3,0); 12..15 on (4,5)(5,6)(6,7)(7,4);
//!   16..19 on (0,4)(1,5)(2,6)(3,7).
//! * **tet10**: 4..9 on (0,1)(1,2)(2,0)(0,3)(1,3)(2,3).
//! * **wedge15**: 6..8 on (0,1)(1,2)(2,0); 9..11 on (3,4)(4,5)(5,3); 12..14 on (0,3)(1,4)(2,5).
//! * **pyramid13**: 5..8 on (0,1)(1,2)(2,3)(3,0); 9..12 on (0,4)(1,4)(2,4)(3,4).
//!
//! A mid-side node that the file leaves out (ANSYS writes node number 0 for it) is stored as
//! [`MISSING_NODE`]. Nothing in the PD pipeline reads mid-side nodes: particles are corner nodes.
//!
//! Lower-dimensional elements (points, lines, triangles, quadrilaterals of any order) are kept
//! because they carry set membership (a Gmsh physical surface, an Abaqus shell elset); their
//! connectivity lists corners first and its length gives the node count.

use std::collections::HashMap;

/// Stand-in for a mid-side node the file does not give (ANSYS writes node number 0).
pub const MISSING_NODE: u32 = u32::MAX;

/// The corners of each tet10 mid-edge node 4..9 (module documentation).
pub const TET10_EDGES: [(usize, usize); 6] = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)];

/// The corners of each hex20 mid-edge node 8..19 (module documentation).
pub const HEX20_EDGES: [(usize, usize); 12] = [
    (0, 1),
    (1, 2),
    (2, 3),
    (3, 0),
    (4, 5),
    (5, 6),
    (6, 7),
    (7, 4),
    (0, 4),
    (1, 5),
    (2, 6),
    (3, 7),
];

/// The file format a mesh came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// ANSYS MAPDL blocked archive (CDWRITE) or Workbench solver input.
    Cdb,
    /// Gmsh MSH 2.x or 4.1, ASCII or binary.
    Msh,
    /// Abaqus / CalculiX input deck.
    Inp,
}

impl Format {
    /// The short name used on the command line and in JSON (`cdb`, `msh`, `inp`).
    pub fn name(self) -> &'static str {
        match self {
            Format::Cdb => "cdb",
            Format::Msh => "msh",
            Format::Inp => "inp",
        }
    }

    /// Parses a `--format` value.
    pub fn from_name(s: &str) -> Option<Format> {
        match s.to_ascii_lowercase().as_str() {
            "cdb" | "ansys" | "dat" => Some(Format::Cdb),
            "msh" | "gmsh" => Some(Format::Msh),
            "inp" | "abaqus" | "calculix" => Some(Format::Inp),
            _ => None,
        }
    }
}

/// Element shapes. The eight solids are the ones the PD pipeline discretises; the four
/// lower-dimensional kinds are kept only for set membership.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ElementKind {
    Hex8,
    Hex20,
    Tet4,
    Tet10,
    Wedge6,
    Wedge15,
    Pyramid5,
    Pyramid13,
    /// A 0-D element (one node).
    Point,
    /// A 1-D element of any order (corners first).
    Line,
    /// A triangle of any order (3 corners first).
    Triangle,
    /// A quadrilateral of any order (4 corners first).
    Quadrilateral,
}

impl ElementKind {
    /// The eight solid kinds, in the order `inspect` reports them.
    pub const SOLIDS: [ElementKind; 8] = [
        ElementKind::Hex8,
        ElementKind::Hex20,
        ElementKind::Tet4,
        ElementKind::Tet10,
        ElementKind::Wedge6,
        ElementKind::Wedge15,
        ElementKind::Pyramid5,
        ElementKind::Pyramid13,
    ];

    /// Topological dimension.
    pub fn dim(self) -> u8 {
        match self {
            ElementKind::Point => 0,
            ElementKind::Line => 1,
            ElementKind::Triangle | ElementKind::Quadrilateral => 2,
            _ => 3,
        }
    }

    /// True for the eight 3D solid kinds.
    pub fn is_solid(self) -> bool {
        self.dim() == 3
    }

    /// Number of corner (vertex) nodes, which come first in the connectivity.
    pub fn corner_count(self) -> usize {
        match self {
            ElementKind::Hex8 | ElementKind::Hex20 => 8,
            ElementKind::Tet4 | ElementKind::Tet10 => 4,
            ElementKind::Wedge6 | ElementKind::Wedge15 => 6,
            ElementKind::Pyramid5 | ElementKind::Pyramid13 => 5,
            ElementKind::Point => 1,
            ElementKind::Line => 2,
            ElementKind::Triangle => 3,
            ElementKind::Quadrilateral => 4,
        }
    }

    /// Total node count of a solid kind; `None` for lower-dimensional kinds, whose order varies.
    pub fn node_count(self) -> Option<usize> {
        match self {
            ElementKind::Hex8 => Some(8),
            ElementKind::Hex20 => Some(20),
            ElementKind::Tet4 => Some(4),
            ElementKind::Tet10 => Some(10),
            ElementKind::Wedge6 => Some(6),
            ElementKind::Wedge15 => Some(15),
            ElementKind::Pyramid5 => Some(5),
            ElementKind::Pyramid13 => Some(13),
            _ => None,
        }
    }

    /// The linear shape with the same corners (hex20 → hex8, ...).
    pub fn linear(self) -> ElementKind {
        match self {
            ElementKind::Hex20 => ElementKind::Hex8,
            ElementKind::Tet10 => ElementKind::Tet4,
            ElementKind::Wedge15 => ElementKind::Wedge6,
            ElementKind::Pyramid13 => ElementKind::Pyramid5,
            k => k,
        }
    }

    /// The quadratic solid with the same corners (hex8 → hex20, ...); identity otherwise.
    pub fn quadratic(self) -> ElementKind {
        match self {
            ElementKind::Hex8 => ElementKind::Hex20,
            ElementKind::Tet4 => ElementKind::Tet10,
            ElementKind::Wedge6 => ElementKind::Wedge15,
            ElementKind::Pyramid5 => ElementKind::Pyramid13,
            k => k,
        }
    }

    /// The name used by `inspect` (`hex8`, `tet10`, ...).
    pub fn name(self) -> &'static str {
        match self {
            ElementKind::Hex8 => "hex8",
            ElementKind::Hex20 => "hex20",
            ElementKind::Tet4 => "tet4",
            ElementKind::Tet10 => "tet10",
            ElementKind::Wedge6 => "wedge6",
            ElementKind::Wedge15 => "wedge15",
            ElementKind::Pyramid5 => "pyramid5",
            ElementKind::Pyramid13 => "pyramid13",
            ElementKind::Point => "point",
            ElementKind::Line => "line",
            ElementKind::Triangle => "triangle",
            ElementKind::Quadrilateral => "quadrilateral",
        }
    }
}

/// What kind of named set this is, after the format that defined it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SetKind {
    /// A Gmsh physical group: both its elements and their nodes.
    PhysicalGroup,
    /// An Abaqus `*NSET` (or `NSET=` on `*NODE`).
    NodeSet,
    /// An Abaqus `*ELSET` (or `ELSET=` on `*ELEMENT`).
    ElementSet,
    /// An ANSYS `CMBLOCK` component (node or element).
    Component,
}

impl SetKind {
    /// The name used by `inspect --json`.
    pub fn name(self) -> &'static str {
        match self {
            SetKind::PhysicalGroup => "physical_group",
            SetKind::NodeSet => "nset",
            SetKind::ElementSet => "elset",
            SetKind::Component => "component",
        }
    }
}

/// A named set of nodes and/or elements, by dense index into the mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedSet {
    /// The name as first written in the file (trimmed).
    pub name: String,
    pub kind: SetKind,
    /// Dense node indices, sorted and unique; `None` for a pure element set.
    pub nodes: Option<Vec<u32>>,
    /// Dense element indices, sorted and unique; `None` for a pure node set.
    pub elements: Option<Vec<u32>>,
}

/// A finite-element mesh: nodes with their original ids, typed elements, named sets.
///
/// Nodes and elements are addressed by dense `u32` indices; the file's own numbers are kept in
/// `node_ids` and `element_ids`. Element connectivity is stored flat: element `e` uses
/// `connectivity[element_offsets[e]..element_offsets[e + 1]]`.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    /// Original node numbers (ANSYS node number, Gmsh node tag, Abaqus label after flattening).
    pub node_ids: Vec<u64>,
    /// Node coordinates.
    pub coords: Vec<[f64; 3]>,
    /// Original element numbers.
    pub element_ids: Vec<u64>,
    /// Element shapes.
    pub element_kinds: Vec<ElementKind>,
    /// `element_offsets[e]..element_offsets[e+1]` is element `e`'s range in `connectivity`.
    /// Always one longer than `element_kinds`.
    pub element_offsets: Vec<usize>,
    /// Dense node indices of every element, in the convention documented at module level.
    pub connectivity: Vec<u32>,
    /// Named node and element sets, in the order the file defines them (Gmsh: by dimension, tag).
    pub sets: Vec<NamedSet>,
    /// What the reader skipped or repaired, one line each (element types it does not model...).
    pub warnings: Vec<String>,
}

/// A borrowed view of one element.
#[derive(Clone, Copy, Debug)]
pub struct ElementRef<'a> {
    pub index: u32,
    pub id: u64,
    pub kind: ElementKind,
    pub nodes: &'a [u32],
}

impl<'a> ElementRef<'a> {
    /// The corner nodes (first `corner_count` entries).
    pub fn corners(&self) -> &'a [u32] {
        &self.nodes[..self.kind.corner_count().min(self.nodes.len())]
    }
}

impl Mesh {
    /// Gives back what the readers' growing arrays hold beyond their length (up to half of
    /// a large mesh's memory, which a run keeps to its end).
    pub fn shrink_to_fit(&mut self) {
        self.node_ids.shrink_to_fit();
        self.coords.shrink_to_fit();
        self.element_ids.shrink_to_fit();
        self.element_kinds.shrink_to_fit();
        self.element_offsets.shrink_to_fit();
        self.connectivity.shrink_to_fit();
    }

    /// An empty mesh with `element_offsets` initialised.
    pub fn new() -> Mesh {
        Mesh {
            element_offsets: vec![0],
            ..Default::default()
        }
    }

    /// The same nodes (numbers, coordinates) and warnings, without elements or sets: where a
    /// mesh is rebuilt element by element on the nodes of another.
    pub fn nodes_only(&self) -> Mesh {
        Mesh {
            node_ids: self.node_ids.clone(),
            coords: self.coords.clone(),
            warnings: self.warnings.clone(),
            ..Mesh::new()
        }
    }

    /// The largest node number (0 without nodes): nodes added to the mesh are numbered after it.
    pub fn max_node_id(&self) -> u64 {
        self.node_ids.iter().copied().max().unwrap_or(0)
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.coords.len()
    }

    /// Number of elements of every dimension.
    pub fn element_count(&self) -> usize {
        self.element_kinds.len()
    }

    /// Appends a node and returns its dense index.
    pub fn push_node(&mut self, id: u64, xyz: [f64; 3]) -> u32 {
        self.node_ids.push(id);
        self.coords.push(xyz);
        (self.coords.len() - 1) as u32
    }

    /// Appends an element whose `nodes` are already dense indices in the module's convention.
    pub fn push_element(&mut self, id: u64, kind: ElementKind, nodes: &[u32]) -> u32 {
        if self.element_offsets.is_empty() {
            self.element_offsets.push(0);
        }
        self.element_ids.push(id);
        self.element_kinds.push(kind);
        self.connectivity.extend_from_slice(nodes);
        self.element_offsets.push(self.connectivity.len());
        (self.element_kinds.len() - 1) as u32
    }

    /// Element `e`.
    pub fn element(&self, e: usize) -> ElementRef<'_> {
        ElementRef {
            index: e as u32,
            id: self.element_ids[e],
            kind: self.element_kinds[e],
            nodes: &self.connectivity[self.element_offsets[e]..self.element_offsets[e + 1]],
        }
    }

    /// All elements, of every dimension.
    pub fn elements(&self) -> impl Iterator<Item = ElementRef<'_>> + '_ {
        (0..self.element_count()).map(move |e| self.element(e))
    }

    /// The 3D solid elements only.
    pub fn solids(&self) -> impl Iterator<Item = ElementRef<'_>> + '_ {
        self.elements().filter(|e| e.kind.is_solid())
    }

    /// A set by name; Abaqus and ANSYS names are case-insensitive, so the match is too.
    pub fn set(&self, name: &str) -> Option<&NamedSet> {
        self.sets
            .iter()
            .find(|s| s.name == name)
            .or_else(|| self.sets.iter().find(|s| s.name.eq_ignore_ascii_case(name)))
    }

    /// The nodes of a set: its node list, or the nodes of its elements for an element set.
    pub fn set_nodes(&self, set: &NamedSet) -> Vec<u32> {
        if let Some(n) = &set.nodes {
            return n.clone();
        }
        let mut nodes: Vec<u32> = set
            .elements
            .iter()
            .flatten()
            .flat_map(|&e| self.element(e as usize).nodes.iter().copied())
            .filter(|&n| n != MISSING_NODE)
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        nodes
    }

    /// The elements `keep` accepts and the nodes they use (numbers, coordinates, in their
    /// order here), the named sets restricted to them, the warnings: a part of the mesh.
    pub fn retain_elements(&self, mut keep: impl FnMut(ElementRef<'_>) -> bool) -> Mesh {
        let mut out = Mesh::new();
        let mut new_index = vec![u32::MAX; self.node_count()];
        let mut kept_elements = vec![u32::MAX; self.element_count()];
        for e in self.elements() {
            if !keep(e) {
                continue;
            }
            let nodes: Vec<u32> = e
                .nodes
                .iter()
                .map(|&n| {
                    if n == MISSING_NODE {
                        return n;
                    }
                    if new_index[n as usize] == u32::MAX {
                        new_index[n as usize] =
                            out.push_node(self.node_ids[n as usize], self.coords[n as usize]);
                    }
                    new_index[n as usize]
                })
                .collect();
            kept_elements[e.index as usize] = out.push_element(e.id, e.kind, &nodes);
        }
        for s in &self.sets {
            let mut set = s.clone();
            let kept = |list: &mut Vec<u32>, map: &[u32]| {
                *list = list
                    .iter()
                    .map(|&k| map[k as usize])
                    .filter(|&k| k != u32::MAX)
                    .collect();
                list.sort_unstable();
            };
            if let Some(nodes) = &mut set.nodes {
                kept(nodes, &new_index);
            }
            if let Some(elements) = &mut set.elements {
                kept(elements, &kept_elements);
            }
            out.sets.push(set);
        }
        out.warnings = self.warnings.clone();
        out
    }

    /// The solid elements of `set` (a physical volume, a component, an `*ELSET`), the
    /// elements of lower dimension on their nodes alone (faces a load or a support names), and
    /// those nodes: one body of an assembly meshed in one file. `None` where the set holds no
    /// solid element.
    pub fn solids_of(&self, set: &NamedSet) -> Option<Mesh> {
        let mut chosen = vec![false; self.element_count()];
        for &e in set.elements.iter().flatten() {
            chosen[e as usize] = self.element_kinds[e as usize].is_solid();
        }
        let mut used = vec![false; self.node_count()];
        for e in self.solids().filter(|e| chosen[e.index as usize]) {
            for &n in e.nodes.iter().filter(|&&n| n != MISSING_NODE) {
                used[n as usize] = true;
            }
        }
        chosen.iter().any(|&c| c).then(|| {
            let mut part = self.retain_elements(|e| {
                if e.kind.is_solid() {
                    chosen[e.index as usize]
                } else {
                    e.nodes
                        .iter()
                        .all(|&n| n == MISSING_NODE || used[n as usize])
                }
            });
            // The quality checks are the part's (the whole file's pieces are its parts).
            let whole = crate::quality::quality_warnings(self);
            part.warnings.retain(|w| !whole.contains(w));
            part.warnings
                .extend(crate::quality::quality_warnings(&part));
            part
        })
    }

    /// Whether each node is a corner of at least one 3D solid element.
    pub fn solid_corner_mask(&self) -> Vec<bool> {
        let mut mask = vec![false; self.node_count()];
        for e in self.solids() {
            for &n in e.corners() {
                if n != MISSING_NODE {
                    mask[n as usize] = true;
                }
            }
        }
        mask
    }

    /// Axis-aligned bounding box over all nodes; `None` for a mesh without nodes.
    pub fn bbox(&self) -> Option<([f64; 3], [f64; 3])> {
        let first = *self.coords.first()?;
        let mut lo = first;
        let mut hi = first;
        for p in &self.coords {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        Some((lo, hi))
    }
}

/// Maps original node numbers to dense indices.
///
/// Real files number nodes sparsely (ANSYS ids up to 434813 for 584 nodes, Gmsh tags up to twice
/// the count), so a direct table is used when the ids are dense enough and a hash map otherwise.
#[derive(Clone, Debug)]
pub enum NodeIndex {
    Table { table: Vec<u32> },
    Map(HashMap<u64, u32>),
}

impl NodeIndex {
    /// Builds the index; returns the first repeated id as `Err` (a node defined twice).
    pub fn build(ids: &[u64]) -> Result<NodeIndex, u64> {
        let max = ids.iter().copied().max().unwrap_or(0);
        if (max as u128) < 4 * ids.len() as u128 + 1024 {
            let mut table = vec![u32::MAX; max as usize + 1];
            for (i, &id) in ids.iter().enumerate() {
                let slot = &mut table[id as usize];
                if *slot != u32::MAX {
                    return Err(id);
                }
                *slot = i as u32;
            }
            Ok(NodeIndex::Table { table })
        } else {
            let mut map = HashMap::with_capacity(ids.len());
            for (i, &id) in ids.iter().enumerate() {
                if map.insert(id, i as u32).is_some() {
                    return Err(id);
                }
            }
            Ok(NodeIndex::Map(map))
        }
    }

    /// Dense index of an original id.
    #[inline]
    pub fn get(&self, id: u64) -> Option<u32> {
        match self {
            NodeIndex::Table { table } => match table.get(id as usize) {
                Some(&i) if i != u32::MAX => Some(i),
                _ => None,
            },
            NodeIndex::Map(m) => m.get(&id).copied(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn node_index_dense_and_sparse() {
        let dense = NodeIndex::build(&[3, 1, 2]).expect("unique");
        assert!(matches!(dense, NodeIndex::Table { .. }));
        assert_eq!(dense.get(1), Some(1));
        assert_eq!(dense.get(7), None);
        let sparse = NodeIndex::build(&[1, 1_000_000_000]).expect("unique");
        assert!(matches!(sparse, NodeIndex::Map(_)));
        assert_eq!(sparse.get(1_000_000_000), Some(1));
        assert_eq!(NodeIndex::build(&[5, 6, 5]).err(), Some(5));
    }

    #[test]
    fn element_views() {
        let mut m = Mesh::new();
        for i in 0..8 {
            m.push_node(i + 1, [0.0; 3]);
        }
        m.push_element(10, ElementKind::Hex8, &[0, 1, 2, 3, 4, 5, 6, 7]);
        m.push_element(11, ElementKind::Triangle, &[0, 1, 2]);
        assert_eq!(m.solids().count(), 1);
        assert_eq!(m.element(1).corners(), &[0, 1, 2]);
        assert_eq!(m.solid_corner_mask().iter().filter(|&&b| b).count(), 8);
    }
}
