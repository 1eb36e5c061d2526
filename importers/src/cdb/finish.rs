//! The end of a read: file node numbers resolved to indices, repeated numbers reported,
//! components turned into sets, and the warnings for skipped and incomplete elements.

use super::cmblock::{members, Entity};
use super::eblock::SkipReason;
use super::elements;
use super::Reader;
use crate::error::ImportError;
use crate::mesh::{Mesh, NamedSet, NodeIndex, SetKind, MISSING_NODE};

fn plural(n: usize, what: &str) -> String {
    if n == 1 {
        format!("1 {what}")
    } else {
        format!("{n} {what}s")
    }
}

impl Reader<'_> {
    /// Resolves file node numbers, builds the sets and the warnings.
    pub(super) fn finish(mut self) -> Result<Mesh, ImportError> {
        if self.mesh.node_ids.is_empty() {
            return Err(ImportError::whole_file(
                self.path,
                "an ANSYS archive with nodes (an NBLOCK)",
                "a file that holds no nodes",
            ));
        }
        let nodes = match NodeIndex::build(&self.mesh.node_ids) {
            Ok(i) => i,
            Err(dup) => {
                return Err(self.repeated(&self.mesh.node_ids, &self.node_lines, dup, "node"))
            }
        };
        for e in 0..self.mesh.element_count() {
            let (s, t) = (
                self.mesh.element_offsets[e],
                self.mesh.element_offsets[e + 1],
            );
            for slot in &mut self.mesh.connectivity[s..t] {
                if *slot == MISSING_NODE {
                    continue;
                }
                match nodes.get(u64::from(*slot)) {
                    Some(i) => *slot = i,
                    None => {
                        return Err(ImportError::at_line(
                            self.path,
                            self.element_lines[e] as usize,
                            "a node defined in an NBLOCK",
                            format!("node {}", *slot),
                        ))
                    }
                }
            }
        }
        let elems = match NodeIndex::build(&self.mesh.element_ids) {
            Ok(i) => i,
            Err(dup) => {
                return Err(self.repeated(
                    &self.mesh.element_ids,
                    &self.element_lines,
                    dup,
                    "element",
                ))
            }
        };

        let mut sorted_nodes = None;
        let mut sorted_elems = None;
        let mut warnings = std::mem::take(&mut self.warnings);
        for c in std::mem::take(&mut self.components) {
            let (index, ids, sorted, what) = match c.entity {
                Entity::Node => (&nodes, &self.mesh.node_ids, &mut sorted_nodes, "node"),
                Entity::Element => (&elems, &self.mesh.element_ids, &mut sorted_elems, "element"),
            };
            let (members, declared) = members(c.intervals, index, ids, sorted);
            let missing = declared - members.len() as u128;
            if missing > 0 {
                warnings.push(format!(
                    "component {}: {missing} of {declared} {what} numbers are not {} in this file; \
                     they are left out",
                    c.name,
                    if c.entity == Entity::Node {
                        "nodes defined"
                    } else {
                        "3D solid elements read"
                    }
                ));
            }
            let (nodes_field, elements_field) = match c.entity {
                Entity::Node => (Some(members), None),
                Entity::Element => (None, Some(members)),
            };
            self.mesh.sets.push(NamedSet {
                name: c.name,
                kind: SetKind::Component,
                nodes: nodes_field,
                elements: elements_field,
            });
        }

        for s in &self.skipped {
            let what = match (s.ename, s.itype) {
                (Some(e), Some(t)) => match elements::element_name(e) {
                    Some(n) => format!("{} (type {t})", plural(s.count, &format!("{n} element"))),
                    None => format!(
                        "{} of type {t} (element number {e}, which this reader does not know)",
                        plural(s.count, "element")
                    ),
                },
                (None, Some(t)) => format!("{} of type {t}", plural(s.count, "element")),
                (_, None) => format!("{} of a COMPACT EBLOCK", plural(s.count, "element")),
            };
            let why = match (s.reason, s.itype) {
                (SkipReason::NoType, Some(t)) => {
                    format!("no ET or ETBLOCK defines element type {t}")
                }
                (SkipReason::NoType, None) => {
                    "no TYPE command gives their element type".to_string()
                }
                (SkipReason::NotSolid { keyopt1 }, _) if s.ename == Some(elements::MESH200) => {
                    format!("KEYOPT(1) = {keyopt1} is not a 3D shape")
                }
                (SkipReason::NotSolid { .. }, _) => "not a 3D solid".to_string(),
                (SkipReason::BadCollapse, _) => {
                    "repeated corner nodes that form no hex, wedge, pyramid or tet".to_string()
                }
            };
            warnings.push(format!("skipped {what}: {why}"));
        }
        if self.missing_midside > 0 {
            warnings.push(format!(
                "{} quadratic elements lack some midside nodes (node number 0); those are stored \
                 as missing",
                self.missing_midside
            ));
        }
        if self.mesh.element_count() == 0 {
            warnings.push("the file defines no 3D solid elements".to_string());
        }
        self.mesh.warnings = warnings;
        Ok(self.mesh)
    }

    /// The error for an id defined twice, naming both lines.
    fn repeated(&self, ids: &[u64], lines: &[u32], dup: u64, what: &str) -> ImportError {
        let mut at = ids
            .iter()
            .enumerate()
            .filter(|(_, &id)| id == dup)
            .map(|(i, _)| i);
        let first = at.next().unwrap_or(0);
        let second = at.next().unwrap_or(first);
        let line = |i: usize| lines.get(i).copied().unwrap_or(0) as usize;
        self.err(
            line(second),
            format!("each {what} number defined once"),
            format!("{what} {dup} again (first defined on line {})", line(first)),
        )
    }
}
