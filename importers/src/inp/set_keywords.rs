//! `*NSET` and `*ELSET`: keyword lines, the set name spaces of parts, instances and the
//! model, and data lines (labels, `GENERATE`, `instance.label`, set names).

use super::lex::{self, Keyword};
use super::sets::{append_chunks, chunk_members, push_label, push_range, Chunk, SetAcc};
use super::units::UnitKind;
use super::{short_set_name, unquote, Mode, Reader, MAX_LABEL, MEMBERS_PER_BYTE};
use crate::error::{describe_found, ImportError};

impl Reader {
    pub(super) fn kw_set(
        &mut self,
        kw: &Keyword,
        elem: bool,
        file: u32,
        line: usize,
        text: &[u8],
    ) -> Result<(), ImportError> {
        let param = if elem { "ELSET" } else { "NSET" };
        let name = self.required(kw, param, file, line, text)?;
        let here = self.current_unit();
        let instance = match kw.value("INSTANCE") {
            Some(i) => {
                if !matches!(self.units[here].kind, UnitKind::Assembly | UnitKind::Model) {
                    return Err(self.err(
                        file,
                        line,
                        "INSTANCE= only on assembly-level sets",
                        describe_found(text),
                    ));
                }
                match self.instance_names.get(&i.to_ascii_uppercase()) {
                    Some(&u) => Some(u),
                    None => {
                        return Err(self.err(
                            file,
                            line,
                            "INSTANCE= naming an instance defined before",
                            format!("INSTANCE={i}"),
                        ))
                    }
                }
            }
            None => None,
        };
        let set = self.define_set(elem, &name, here);
        let via_elements = !elem && kw.value("ELSET").is_some();
        self.mode = Mode::Set {
            set,
            unit: instance.unwrap_or(here),
            scope: here,
            instance,
            generate: kw.flag("GENERATE"),
            via_elements,
        };
        if via_elements {
            if let Some(es) = kw.value("ELSET") {
                let es = es.to_string();
                self.set_reference(&es, file, line)?;
            }
        }
        Ok(())
    }

    /// The set `name` of kind `elem` defined in unit `u`'s name space, created if new.
    pub(super) fn define_set(&mut self, elem: bool, name: &str, u: usize) -> usize {
        let (display, key) = match self.units[u].kind {
            UnitKind::Instance => {
                let d = format!("{}.{}", self.units[u].name, name);
                let k = d.to_ascii_uppercase();
                (d, k)
            }
            _ => (name.to_string(), name.to_ascii_uppercase()),
        };
        let existing = if self.units[u].kind == UnitKind::Part {
            self.units[u].set_names.get(&(elem, key.clone())).copied()
        } else {
            self.global_sets.get(&(elem, key.clone())).copied()
        };
        if let Some(s) = existing {
            return s;
        }
        let s = self.sets.len();
        self.sets.push(SetAcc {
            name: display,
            elem,
            chunks: Vec::new(),
        });
        if self.units[u].kind == UnitKind::Part {
            self.units[u].set_names.insert((elem, key), s);
            self.units[u].set_order.push(s);
        } else {
            self.global_sets.insert((elem, key), s);
            self.global_order.push(s);
        }
        s
    }

    /// Looks up a set named on a data line.
    fn find_set(
        &self,
        elem: bool,
        name: &str,
        scope: usize,
        instance: Option<usize>,
    ) -> Option<usize> {
        let key = name.to_ascii_uppercase();
        match self.units[scope].kind {
            UnitKind::Part => self.units[scope].set_names.get(&(elem, key)).copied(),
            UnitKind::Instance => {
                let k = format!("{}.{}", self.units[scope].name, name).to_ascii_uppercase();
                self.global_sets.get(&(elem, k)).copied()
            }
            UnitKind::Model | UnitKind::Assembly => {
                if let Some(i) = instance {
                    let k = format!("{}.{}", self.units[i].name, name).to_ascii_uppercase();
                    if let Some(&s) = self.global_sets.get(&(elem, k)) {
                        return Some(s);
                    }
                }
                self.global_sets.get(&(elem, key)).copied()
            }
        }
    }

    /// Adds the members of the set named `name` to the current set.
    pub(super) fn set_reference(
        &mut self,
        name: &str,
        file: u32,
        line: usize,
    ) -> Result<(), ImportError> {
        let Mode::Set {
            set,
            scope,
            instance,
            via_elements,
            ..
        } = self.mode
        else {
            return Ok(());
        };
        let elem = self.sets[set].elem || via_elements;
        match self.find_set(elem, name, scope, instance) {
            Some(r) => {
                // A set named k times in a set that is named k times ... doubles at each step:
                // the copies are limited by the size of the input.
                let members = chunk_members(&self.sets[r].chunks);
                let budget = self
                    .input_bytes
                    .saturating_mul(MEMBERS_PER_BYTE)
                    .saturating_add(1 << 16);
                self.copied_members = self.copied_members.saturating_add(members);
                if self.copied_members > budget {
                    return Err(self.err(
                        file,
                        line,
                        format!(
                            "set names on data lines that copy at most {budget} set members in \
                             all ({MEMBERS_PER_BYTE} per byte of input)"
                        ),
                        format!(
                            "set '{}' copied again ({members} members)",
                            short_set_name(name)
                        ),
                    ));
                }
                let chunks = self.sets[r].chunks.clone();
                let target = &mut self.sets[set].chunks;
                if via_elements {
                    target.push(Chunk::NodesOf(chunks));
                } else {
                    append_chunks(target, chunks);
                }
            }
            None => {
                let what = if elem { "element" } else { "node" };
                let w = format!(
                    "set '{}' refers to {what} set '{name}', which is not defined before; left out",
                    self.sets[set].name
                );
                self.warn(w);
            }
        }
        Ok(())
    }

    pub(super) fn set_line(
        &mut self,
        line: &[u8],
        file: u32,
        lineno: usize,
    ) -> Result<(), ImportError> {
        let Mode::Set {
            set,
            unit,
            scope,
            generate,
            via_elements,
            ..
        } = self.mode
        else {
            return Ok(());
        };
        if generate {
            let mut vals = [0u64; 3];
            let mut n = 0;
            for f in lex::fields(line) {
                if lex::is_blank_field(f) {
                    continue;
                }
                let v = lex::label(f).filter(|&v| v > 0 && v < MAX_LABEL);
                match v {
                    Some(v) if n < 3 => {
                        vals[n] = v;
                        n += 1;
                    }
                    Some(_) => {
                        return Err(self.err(
                            file,
                            lineno,
                            "GENERATE data 'first, last[, increment]'",
                            describe_found(line),
                        ))
                    }
                    None => {
                        return Err(self.err(
                            file,
                            lineno,
                            "a positive integer in GENERATE data 'first, last[, increment]'",
                            describe_found(f),
                        ))
                    }
                }
            }
            if n < 2 {
                return Err(self.err(
                    file,
                    lineno,
                    "GENERATE data 'first, last[, increment]'",
                    describe_found(line),
                ));
            }
            let step = if n == 3 { vals[2] } else { 1 };
            if vals[0] > vals[1] {
                return Err(self.err(
                    file,
                    lineno,
                    "GENERATE data with first <= last",
                    describe_found(line),
                ));
            }
            push_range(
                &mut self.sets[set].chunks,
                via_elements,
                unit,
                [vals[0], vals[1], step],
            );
            return Ok(());
        }
        for f in lex::fields(line) {
            let t = f.trim_ascii();
            if t.is_empty() {
                continue;
            }
            if t[0].is_ascii_digit() || t[0] == b'-' || t[0] == b'+' {
                match lex::label(t).filter(|&v| v > 0 && v < MAX_LABEL) {
                    Some(l) => push_label(&mut self.sets[set].chunks, via_elements, unit, l),
                    None => {
                        let name = &self.sets[set].name;
                        // meshio writes the cell sets its gmsh reader made of gmsh's own
                        // entity data ("gmsh:bounding_entities": entity tags, 0 and -1
                        // among them) into an Abaqus file as element sets.
                        let cause = if name.starts_with("gmsh:") {
                            " (meshio's copy of gmsh's entity tags: write the file without its gmsh: cell sets)"
                        } else {
                            ""
                        };
                        return Err(self.err(
                            file,
                            lineno,
                            format!(
                                "a positive integer label or a set name in set '{name}'{cause}"
                            ),
                            describe_found(f),
                        ));
                    }
                }
                continue;
            }
            // `instance.label` at model or assembly level.
            if matches!(self.units[scope].kind, UnitKind::Model | UnitKind::Assembly) {
                if let Some(dot) = t.iter().rposition(|&b| b == b'.') {
                    let (inst, rest) = (&t[..dot], &t[dot + 1..]);
                    if !rest.is_empty() && rest.iter().all(u8::is_ascii_digit) {
                        let inst_name = String::from_utf8_lossy(unquote(inst)).to_ascii_uppercase();
                        let label = lex::label(rest).filter(|&v| v > 0 && v < MAX_LABEL);
                        match (self.instance_names.get(&inst_name), label) {
                            (Some(&iu), Some(l)) => {
                                push_label(&mut self.sets[set].chunks, via_elements, iu, l)
                            }
                            _ => {
                                let w = format!(
                                    "set '{}' names '{}', which is not a label of a defined instance; left out",
                                    self.sets[set].name,
                                    String::from_utf8_lossy(t)
                                );
                                self.warn(w);
                            }
                        }
                        continue;
                    }
                }
            }
            // A set name, possibly quoted or `"instance name".set`.
            let unquoted: Vec<u8> = t.iter().copied().filter(|&b| b != b'"').collect();
            let name = String::from_utf8_lossy(&unquoted).into_owned();
            self.set_reference(&name, file, lineno)?;
        }
        Ok(())
    }
}
