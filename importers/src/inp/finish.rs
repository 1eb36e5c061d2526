//! End of input: the last record and block checked, parts without instances placed, the
//! model placed, sets resolved, and the warnings per element type.

use super::sets::resolve;
use super::types::Class;
use super::units::UnitKind;
use super::{Level, Mode, Reader};
use crate::error::ImportError;
use crate::mesh::{Mesh, NamedSet, SetKind};

impl Reader {
    pub(super) fn finish(mut self) -> Result<Mesh, ImportError> {
        if self.pending.is_some() && self.pending_need().is_none() {
            if let Mode::Element { unit, ty, set } = self.mode {
                self.finish_element(unit, ty, set)?;
            }
        }
        if let Some(e) = self.overlong_record() {
            // A record that ended with a trailing comma after more node numbers than its type
            // has.
            return Err(e);
        }
        if let Some(p) = self.pending.take() {
            let need = self.pending_need().unwrap_or(0);
            return Err(self.err(
                p.file,
                p.line,
                format!(
                    "{} more node numbers of element {} on the following lines",
                    need.saturating_sub(self.tokens.len()),
                    p.label
                ),
                "end of file",
            ));
        }
        if let Mode::System { .. } = self.mode {
            let last = self.last_line;
            self.finish_system(0, last)?;
        }
        match self.level {
            Level::Model => {}
            _ => {
                let last = self.last_line;
                return Err(self.nesting_error(0, last, b""));
            }
        }
        // Parts of a deck without any *INSTANCE: one instance each.
        let parts: Vec<usize> = (0..self.units.len())
            .filter(|&u| self.units[u].kind == UnitKind::Part)
            .collect();
        if !self.saw_instance && !parts.is_empty() {
            for &p in &parts {
                let name = self.units[p].name.clone();
                let (f, l) = (self.units[p].file, self.units[p].line);
                let u = self.open_instance(name.clone(), p, f, l)?;
                self.place(u)?;
                self.warn(format!(
                    "part '{name}' has no *INSTANCE; it is read as one instance named '{name}' without transform"
                ));
            }
        } else {
            for &p in &parts {
                if !self.units[p].instanced {
                    let w = format!(
                        "part '{}' is not instanced; it is not in the mesh",
                        self.units[p].name
                    );
                    self.warn(w);
                }
            }
        }
        self.place(0)?;

        // Sets.
        let mut node_sets = Vec::new();
        let mut elem_sets = Vec::new();
        for &s in &self.global_order {
            let set = &self.sets[s];
            let mut missing = 0usize;
            let mut example = None;
            let members = resolve(
                &self.units,
                &self.mesh,
                set.elem,
                &set.chunks,
                &mut missing,
                &mut example,
            );
            if missing > 0 {
                let what = if set.elem { "elements" } else { "nodes" };
                let w = format!(
                    "set '{}': {missing} entries are not defined {what}{}; left out",
                    set.name,
                    example
                        .map(|l| format!(" (e.g. label {l})"))
                        .unwrap_or_default()
                );
                self.warnings.push(w);
            }
            let named = NamedSet {
                name: set.name.clone(),
                kind: if set.elem {
                    SetKind::ElementSet
                } else {
                    SetKind::NodeSet
                },
                nodes: (!set.elem).then(|| members.clone()),
                elements: set.elem.then_some(members),
            };
            if set.elem {
                elem_sets.push(named);
            } else {
                node_sets.push(named);
            }
        }
        self.mesh.sets = node_sets;
        self.mesh.sets.extend(elem_sets);

        for t in &self.types {
            if t.count == 0 {
                continue;
            }
            match t.class {
                Class::Solid { kind, read } if read > kind.node_count().unwrap_or(read) => {
                    self.warnings.push(format!(
                        "element type {}: {} elements read as {} (nodes {}..{} dropped)",
                        t.name,
                        t.count,
                        kind.name(),
                        kind.node_count().unwrap_or(0) + 1,
                        read
                    ));
                }
                Class::Solid { .. } => {}
                Class::Lower { kind, .. } => self.warnings.push(format!(
                    "element type {} is not a 3D solid: {} elements kept as {} for set membership only",
                    t.name,
                    t.count,
                    kind.name()
                )),
                Class::Skipped { .. } => self.warnings.push(format!(
                    "element type {} is not modelled: {} elements skipped",
                    t.name, t.count
                )),
            }
        }
        if self.mesh.node_count() == 0 {
            return Err(ImportError::whole_file(
                &self.files[0],
                "an Abaqus deck with *NODE data",
                "no nodes",
            ));
        }
        let mut mesh = self.mesh;
        mesh.warnings.extend(self.warnings);
        Ok(mesh)
    }
}
