//! Node and element records: `*NODE` (in the `*SYSTEM` in force) and `*ELEMENT` keyword lines
//! and data lines, element records continued over several lines.

use super::geom::{local_system, Affine};
use super::lex::{self, Keyword};
use super::sets::push_label;
use super::types::{self, Class};
use super::units::{node_index, UnitKind};
use super::{short_set_name, unquote, Mode, Pending, Reader, TypeStat, GLOBAL, MAX_LABEL};
use crate::error::{describe_found, ImportError};
use crate::mesh::ElementKind;

impl Reader {
    pub(super) fn kw_node(
        &mut self,
        kw: &Keyword,
        file: u32,
        line: usize,
        text: &[u8],
    ) -> Result<(), ImportError> {
        let unit = self.current_unit();
        let cylindrical = match kw.value("SYSTEM").map(|s| s.to_ascii_uppercase()) {
            None => false,
            Some(s) if s == "R" || s.is_empty() => false,
            Some(s) if s == "C" => true,
            Some(s) => {
                return Err(self.err(
                    file,
                    line,
                    "SYSTEM=R (rectangular) or SYSTEM=C (cylindrical); spherical input is not supported",
                    format!("SYSTEM={s} in {}", describe_found(text)),
                ))
            }
        };
        let set = match kw.value("NSET") {
            Some(n) if !n.is_empty() => Some(self.define_set(false, n, unit)),
            _ => None,
        };
        self.mode = Mode::Node {
            unit,
            set,
            cylindrical,
        };
        Ok(())
    }

    pub(super) fn kw_element(
        &mut self,
        kw: &Keyword,
        file: u32,
        line: usize,
        text: &[u8],
    ) -> Result<(), ImportError> {
        let unit = self.current_unit();
        let ty_name = self
            .required(kw, "TYPE", file, line, text)?
            .to_ascii_uppercase();
        let ty = match self.type_index.get(&ty_name) {
            Some(&t) => t,
            None => {
                let Some(class) = types::classify(&ty_name) else {
                    return Err(self.err(
                        file,
                        line,
                        format!("a known solid element type: {}", types::KNOWN_SOLIDS),
                        format!("TYPE={ty_name}, which is not an Abaqus solid type"),
                    ));
                };
                let t = self.types.len();
                self.types.push(TypeStat {
                    class,
                    name: short_set_name(&ty_name),
                    count: 0,
                });
                self.type_index.insert(ty_name, t);
                t
            }
        };
        let set = match kw.value("ELSET") {
            Some(n) if !n.is_empty() => Some(self.define_set(true, n, unit)),
            _ => None,
        };
        self.mode = Mode::Element { unit, ty, set };
        Ok(())
    }

    #[allow(clippy::too_many_arguments)]
    pub(super) fn node_line(
        &mut self,
        line: &[u8],
        file: u32,
        lineno: usize,
        u: usize,
        set: Option<usize>,
        cylindrical: bool,
    ) -> Result<(), ImportError> {
        let mut fs = lex::fields(line);
        let first = fs.next().unwrap_or(b"");
        let label = lex::label(first)
            .filter(|&v| v > 0 && v < MAX_LABEL)
            .ok_or_else(|| {
                self.err(
                    file,
                    lineno,
                    "a node label (positive integer)",
                    describe_found(first),
                )
            })?;
        let mut xyz = [0.0f64; 3];
        let mut n = 0usize;
        for f in fs {
            if lex::is_blank_field(f) {
                n += 1;
                continue;
            }
            let v = lex::real(f).ok_or_else(|| {
                self.err(
                    file,
                    lineno,
                    format!("a coordinate (real number) of node {label}"),
                    describe_found(f),
                )
            })?;
            if n < 3 {
                xyz[n] = v;
            } else if n >= 6 {
                return Err(self.err(
                    file,
                    lineno,
                    format!("at most 6 values after node label {label} (coordinates, normal)"),
                    describe_found(line),
                ));
            }
            n += 1;
        }
        if cylindrical {
            let (s, c) = xyz[1].to_radians().sin_cos();
            xyz = [xyz[0] * c, xyz[0] * s, xyz[2]];
        }
        if let Some(sys) = &self.system {
            xyz = sys.apply(xyz);
        }
        if let Some(p) = self.units[u].part {
            // Independent instances: a label of the part itself cannot be redefined here.
            let part_block = &self.units[p].block;
            if part_block.nodes.get(label).is_some() {
                let part_name = self.units[p].name.clone();
                return Err(self.err(
                    file,
                    lineno,
                    format!("a node label not defined by part '{part_name}' already"),
                    format!("node {label}"),
                ));
            }
        }
        let block = &mut self.units[u].block;
        let index = block.coords.len();
        match block.nodes.insert(label, index as u32) {
            None => {
                if index >= u32::MAX as usize - 1 {
                    return Err(self.err(file, lineno, "fewer than 4 billion nodes", "more"));
                }
                block.node_labels.push(label);
                block.coords.push(xyz);
            }
            Some(old) => {
                // Redefinition: the last coordinates win.
                block.nodes.insert(label, old);
                block.coords[old as usize] = xyz;
                block.redefined_nodes += 1;
            }
        }
        if let Some(s) = set {
            push_label(&mut self.sets[s].chunks, false, u, label);
        }
        Ok(())
    }

    pub(super) fn pending_need(&self) -> Option<usize> {
        match self.mode {
            Mode::Element { ty, .. } => self.types[ty].class.node_numbers(),
            _ => None,
        }
    }

    #[allow(clippy::too_many_arguments)]
    pub(super) fn element_line(
        &mut self,
        line: &[u8],
        file: u32,
        lineno: usize,
        u: usize,
        ty: usize,
        set: Option<usize>,
    ) -> Result<(), ImportError> {
        let class = self.types[ty].class;
        let mut fs = lex::fields(line).peekable();
        if self.pending.is_none() {
            let first = fs.next().unwrap_or(b"");
            let label = lex::label(first)
                .filter(|&v| v > 0 && v < MAX_LABEL)
                .ok_or_else(|| {
                    self.err(
                        file,
                        lineno,
                        "an element label (positive integer)",
                        describe_found(first),
                    )
                })?;
            self.pending = Some(Pending {
                label,
                file,
                line: lineno,
                last: (file, lineno),
            });
            self.tokens.clear();
        } else if let Some(p) = self.pending.as_mut() {
            p.last = (file, lineno);
        }
        let skipped = matches!(class, Class::Skipped { .. });
        let assembly_level = self.units[u].kind == UnitKind::Assembly;
        while let Some(f) = fs.next() {
            if lex::is_blank_field(f) {
                if fs.peek().is_none() {
                    break; // trailing comma
                }
                if !skipped {
                    return Err(self.err(
                        file,
                        lineno,
                        "a node number between two commas",
                        "an empty field",
                    ));
                }
            }
            if skipped {
                self.tokens.push(0);
                continue;
            }
            let t = match lex::label(f) {
                Some(v) if v < MAX_LABEL => v,
                _ => match assembly_level.then(|| self.instance_node(f)).flatten() {
                    Some(g) => GLOBAL | u64::from(g),
                    None => {
                        return Err(self.err(
                            file,
                            lineno,
                            format!("a node number (element type {})", self.types[ty].name),
                            describe_found(f),
                        ))
                    }
                },
            };
            self.tokens.push(t);
        }
        let done = match class.node_numbers() {
            Some(n) => {
                if self.tokens.len() > n && !skipped {
                    if lex::trailing_comma(line) {
                        // The record goes on: count all of it before refusing it.
                        return Ok(());
                    }
                    if let Some(e) = self.overlong_record() {
                        return Err(e);
                    }
                }
                self.tokens.len() >= n
            }
            None => !lex::trailing_comma(line),
        };
        if done {
            self.finish_element(u, ty, set)?;
        }
        Ok(())
    }

    /// The error for a pending record with more node numbers than its type has, if it has
    /// more: at the record's first line, counting the node numbers of all its lines so far.
    pub(super) fn overlong_record(&self) -> Option<ImportError> {
        let (Some(p), Mode::Element { ty, .. }) = (self.pending, self.mode) else {
            return None;
        };
        let t = &self.types[ty];
        let n = match t.class {
            Class::Skipped { .. } => return None,
            c => c.node_numbers()?,
        };
        if self.tokens.len() <= n {
            return None;
        }
        let lines = match p.last {
            (f, l) if f == p.file && l == p.line => String::new(),
            (f, l) if f == p.file => format!(" on lines {}-{l}", p.line),
            (f, l) => format!(
                " from line {} to {}:{l}",
                p.line,
                self.files[f as usize].display()
            ),
        };
        Some(self.err(
            p.file,
            p.line,
            format!(
                "{n} node numbers for element {} of type {}",
                p.label, t.name
            ),
            format!("{} node numbers{lines}", self.tokens.len()),
        ))
    }

    /// `instance.label` on an assembly-level element line: the node's mesh index.
    fn instance_node(&self, f: &[u8]) -> Option<u32> {
        let t = f.trim_ascii();
        let dot = t.iter().rposition(|&b| b == b'.')?;
        let inst = String::from_utf8_lossy(unquote(&t[..dot])).to_ascii_uppercase();
        let label = lex::label(&t[dot + 1..])?;
        let &iu = self.instance_names.get(&inst)?;
        if !self.units[iu].placed {
            return None;
        }
        node_index(&self.units, iu, label)
    }

    pub(super) fn finish_element(
        &mut self,
        u: usize,
        ty: usize,
        set: Option<usize>,
    ) -> Result<(), ImportError> {
        let Some(p) = self.pending.take() else {
            return Ok(());
        };
        self.types[ty].count += 1;
        let (kind, take) = match self.types[ty].class {
            Class::Solid { kind, .. } => (kind, kind.node_count().unwrap_or(0)),
            Class::Lower { kind, nodes } => (kind, nodes),
            Class::Skipped { .. } => return Ok(()),
        };
        let mut conn = [0u64; 27];
        let take = take.min(self.tokens.len()).min(27);
        conn[..take].copy_from_slice(&self.tokens[..take]);
        if kind == ElementKind::Line && take == 3 {
            conn.swap(1, 2);
        }
        for (k, &c) in conn[..kind.corner_count().min(take)].iter().enumerate() {
            if c == 0 {
                return Err(self.err(
                    p.file,
                    p.line,
                    format!("a node number for corner {} of element {}", k + 1, p.label),
                    "0",
                ));
            }
        }
        // Repeated labels are an error, also across an instance and its part.
        let unit = &self.units[u];
        let in_part = unit
            .part
            .is_some_and(|pp| self.units[pp].block.elems.get(p.label).is_some());
        let before = unit
            .block
            .elems
            .get(p.label)
            .and_then(|e| unit.block.elem_src.get(e as usize).copied());
        if in_part || before.is_some() {
            let at = match before {
                Some((f, l)) => format!(
                    " (first defined at {}:{l})",
                    self.files[f as usize].display()
                ),
                None => " (defined by the part)".to_string(),
            };
            return Err(self.err(
                p.file,
                p.line,
                "an element label not used before",
                format!("element {}{at}", p.label),
            ));
        }
        let block = &mut self.units[u].block;
        let index = block.elem_labels.len();
        if index >= u32::MAX as usize - 1 {
            return Err(self.err(p.file, p.line, "fewer than 4 billion elements", "more"));
        }
        block.elems.insert(p.label, index as u32);
        block.elem_labels.push(p.label);
        block.elem_kinds.push(kind);
        if block.elem_offsets.is_empty() {
            block.elem_offsets.push(0);
        }
        block.elem_tokens.extend_from_slice(&conn[..take]);
        block.elem_offsets.push(block.elem_tokens.len());
        block.elem_src.push((p.file, p.line as u32));
        if let Some(s) = set {
            push_label(&mut self.sets[s].chunks, false, u, p.label);
        }
        Ok(())
    }

    pub(super) fn system_line(
        &mut self,
        line: &[u8],
        file: u32,
        lineno: usize,
        lines: usize,
    ) -> Result<(), ImportError> {
        match lines {
            0 => {
                let (v, n) = self.reals::<6>(
                    line,
                    file,
                    lineno,
                    "*SYSTEM data 'xa, ya, za[, xb, yb, zb]'",
                )?;
                self.system_points
                    .extend_from_slice(&v[..if n > 3 { 6 } else { 3 }]);
            }
            1 => {
                let (v, _) = self.reals::<3>(line, file, lineno, "*SYSTEM data 'xc, yc, zc'")?;
                if self.system_points.len() < 6 {
                    return Err(self.err(
                        file,
                        lineno,
                        "a second *SYSTEM line only after a first line with point b",
                        describe_found(line),
                    ));
                }
                self.system_points.extend_from_slice(&v);
            }
            _ => {
                return Err(self.err(
                    file,
                    lineno,
                    "at most two data lines after *SYSTEM",
                    describe_found(line),
                ))
            }
        }
        self.mode = Mode::System { lines: lines + 1 };
        Ok(())
    }

    /// Builds the `*SYSTEM` transform once its data lines are read.
    pub(super) fn finish_system(&mut self, file: u32, line: usize) -> Result<(), ImportError> {
        let p = &self.system_points;
        let pt = |i: usize| [p[i], p[i + 1], p[i + 2]];
        self.system = match p.len() {
            0 => None,
            3 => Some(Affine::translation(pt(0))),
            6 => local_system(pt(0), Some(pt(3)), None),
            _ => local_system(pt(0), Some(pt(3)), Some(pt(6))),
        };
        if !p.is_empty() && self.system.is_none() {
            return Err(self.err(
                file,
                line,
                "*SYSTEM points that define axes (b apart from a, c off the line a-b)",
                "degenerate points in the *SYSTEM data before this line",
            ));
        }
        self.system_points.clear();
        self.mode = Mode::Skip;
        Ok(())
    }
}
