//! `*PART`, `*ASSEMBLY` and `*INSTANCE` blocks (and their ends), instance positioning, and
//! placement: copying units into the mesh.

use std::path::PathBuf;

use super::geom::{rotation_about, Affine};
use super::lex::Keyword;
use super::sets::remap_chunks;
use super::units::{node_index, Unit, UnitKind};
use super::{err, Level, Mode, Reader, GLOBAL};
use crate::error::{describe_found, ImportError};
use crate::mesh::MISSING_NODE;

impl Reader {
    pub(super) fn kw_part(
        &mut self,
        kw: &Keyword,
        file: u32,
        line: usize,
        text: &[u8],
    ) -> Result<(), ImportError> {
        if self.level != Level::Model {
            return Err(self.nesting_error(file, line, text));
        }
        let name = self.required(kw, "NAME", file, line, text)?;
        let key = name.to_ascii_uppercase();
        if self.part_names.contains_key(&key) {
            return Err(self.err(
                file,
                line,
                "a part name not used before",
                format!("NAME={name}"),
            ));
        }
        let u = self.units.len();
        self.units.push(Unit::new(UnitKind::Part, name, file, line));
        self.part_names.insert(key, u);
        self.level = Level::Part(u);
        self.system = None;
        Ok(())
    }

    pub(super) fn kw_end_part(
        &mut self,
        file: u32,
        line: usize,
        text: &[u8],
    ) -> Result<(), ImportError> {
        let Level::Part(u) = self.level else {
            return Err(self.nesting_error(file, line, text));
        };
        // Resolve the part's connectivity to its own node indices.
        let block = &self.units[u].block;
        let mut conn = Vec::with_capacity(block.elem_tokens.len());
        for e in 0..block.element_count() {
            for &t in &block.elem_tokens[block.element_range(e)] {
                if t == 0 {
                    conn.push(MISSING_NODE);
                } else if let Some(i) = block.nodes.get(t) {
                    conn.push(i);
                } else {
                    let (f, l) = block.elem_src[e];
                    return Err(self.undefined_node(f, l as usize, block.elem_labels[e], t));
                }
            }
        }
        let block = &mut self.units[u].block;
        block.local_conn = conn;
        block.elem_tokens = Vec::new();
        self.level = Level::Model;
        self.system = None;
        Ok(())
    }

    fn undefined_node(&self, file: u32, line: usize, element: u64, node: u64) -> ImportError {
        self.err(
            file,
            line,
            format!("node numbers of element {element} that are defined by *NODE"),
            format!("node {node}, which is not defined"),
        )
    }

    pub(super) fn nesting_error(&self, file: u32, line: usize, text: &[u8]) -> ImportError {
        let expected = match self.level {
            Level::Model => "a matching *PART, *ASSEMBLY or *INSTANCE before this line".to_string(),
            Level::Part(u) => format!("*END PART for the *PART at line {}", self.units[u].line),
            Level::Assembly(u) => format!(
                "*INSTANCE or *END ASSEMBLY in the *ASSEMBLY of line {}",
                self.units[u].line
            ),
            Level::Instance(u, _) => {
                format!(
                    "*END INSTANCE for the *INSTANCE at line {}",
                    self.units[u].line
                )
            }
        };
        self.err(file, line, expected, describe_found(text))
    }

    pub(super) fn kw_assembly(
        &mut self,
        kw: &Keyword,
        file: u32,
        line: usize,
        text: &[u8],
    ) -> Result<(), ImportError> {
        if self.level != Level::Model {
            return Err(self.nesting_error(file, line, text));
        }
        if self.units.iter().any(|u| u.kind == UnitKind::Assembly) {
            return Err(self.err(file, line, "one *ASSEMBLY per deck", describe_found(text)));
        }
        let name = kw.value("NAME").unwrap_or("").to_string();
        let u = self.units.len();
        self.units
            .push(Unit::new(UnitKind::Assembly, name, file, line));
        self.level = Level::Assembly(u);
        self.system = None;
        Ok(())
    }

    pub(super) fn kw_end_assembly(
        &mut self,
        file: u32,
        line: usize,
        text: &[u8],
    ) -> Result<(), ImportError> {
        let Level::Assembly(u) = self.level else {
            return Err(self.nesting_error(file, line, text));
        };
        self.place(u)?;
        self.level = Level::Model;
        self.system = None;
        Ok(())
    }

    pub(super) fn kw_instance(
        &mut self,
        kw: &Keyword,
        file: u32,
        line: usize,
        text: &[u8],
    ) -> Result<(), ImportError> {
        let Level::Assembly(a) = self.level else {
            return Err(self.nesting_error(file, line, text));
        };
        let name = self.required(kw, "NAME", file, line, text)?;
        let part_name = self.required(kw, "PART", file, line, text)?;
        let Some(&p) = self.part_names.get(&part_name.to_ascii_uppercase()) else {
            return Err(self.err(
                file,
                line,
                "PART= naming a *PART defined before",
                format!("PART={part_name}"),
            ));
        };
        let u = self.open_instance(name, p, file, line)?;
        self.level = Level::Instance(u, a);
        self.mode = Mode::InstanceData { unit: u, lines: 0 };
        self.system = None;
        Ok(())
    }

    pub(super) fn open_instance(
        &mut self,
        name: String,
        p: usize,
        file: u32,
        line: usize,
    ) -> Result<usize, ImportError> {
        let key = name.to_ascii_uppercase();
        if self.instance_names.contains_key(&key) {
            return Err(self.err(
                file,
                line,
                "an instance name not used before",
                format!("NAME={name}"),
            ));
        }
        self.saw_instance = true;
        let u = self.units.len();
        let mut unit = Unit::new(UnitKind::Instance, name, file, line);
        unit.part = Some(p);
        self.units.push(unit);
        self.units[p].instanced = true;
        self.instance_names.insert(key, u);
        // The part's sets, as this instance's.
        let order = self.units[p].set_order.clone();
        for s in order {
            let chunks = remap_chunks(&self.sets[s].chunks, p, u);
            let (elem, set_name) = (self.sets[s].elem, self.sets[s].name.clone());
            let g = self.define_set(elem, &set_name, u);
            self.sets[g].chunks.extend(chunks);
        }
        Ok(u)
    }

    pub(super) fn kw_end_instance(
        &mut self,
        file: u32,
        line: usize,
        text: &[u8],
    ) -> Result<(), ImportError> {
        let Level::Instance(u, a) = self.level else {
            return Err(self.nesting_error(file, line, text));
        };
        self.place(u)?;
        self.level = Level::Assembly(a);
        self.system = None;
        Ok(())
    }

    pub(super) fn instance_line(
        &mut self,
        line: &[u8],
        file: u32,
        lineno: usize,
        u: usize,
        lines: usize,
    ) -> Result<(), ImportError> {
        match lines {
            0 => {
                let (t, _) =
                    self.reals::<3>(line, file, lineno, "the instance translation 'x, y, z'")?;
                self.units[u].transform = Some(Affine::translation(t));
            }
            1 => {
                let (r, _) = self.reals::<7>(
                    line,
                    file,
                    lineno,
                    "the instance rotation 'ax, ay, az, bx, by, bz, angle'",
                )?;
                if r[6] != 0.0 {
                    let rot = rotation_about([r[0], r[1], r[2]], [r[3], r[4], r[5]], r[6])
                        .ok_or_else(|| {
                            self.err(
                                file,
                                lineno,
                                "a rotation axis through two different points",
                                describe_found(line),
                            )
                        })?;
                    let first = self.units[u]
                        .transform
                        .unwrap_or(Affine::translation([0.0; 3]));
                    self.units[u].transform = Some(rot.after(&first));
                }
            }
            _ => {
                return Err(self.err(
                    file,
                    lineno,
                    "at most two data lines after *INSTANCE (translation, rotation)",
                    describe_found(line),
                ))
            }
        }
        self.mode = Mode::InstanceData {
            unit: u,
            lines: lines + 1,
        };
        Ok(())
    }

    fn next_offsets(&self) -> (u64, u64) {
        let n = if self.mesh.node_count() == 0 {
            0
        } else {
            self.max_node_id
        };
        let e = if self.mesh.element_count() == 0 {
            0
        } else {
            self.max_elem_id
        };
        (n, e)
    }

    /// Places a model, assembly or instance unit: its part's copy (instances), then its own
    /// nodes and elements.
    pub(super) fn place(&mut self, u: usize) -> Result<(), ImportError> {
        let (node_off, elem_off) = self.next_offsets();
        let transform = self.units[u].transform;
        let too_large = |files: &[PathBuf], unit: &Unit| {
            err(
                files,
                unit.file,
                unit.line,
                "labels small enough to number the flattened model",
                "labels too large",
            )
        };
        // The part's nodes and elements.
        let part_node_base = self.mesh.node_count() as u32;
        let part_elem_base = self.mesh.element_count() as u32;
        if let Some(p) = self.units[u].part {
            let (units, mesh) = (&self.units, &mut self.mesh);
            let pb = &units[p].block;
            for (i, &label) in pb.node_labels.iter().enumerate() {
                let xyz = match &transform {
                    Some(t) => t.apply(pb.coords[i]),
                    None => pb.coords[i],
                };
                let id = label
                    .checked_add(node_off)
                    .ok_or_else(|| too_large(&self.files, &units[u]))?;
                self.max_node_id = self.max_node_id.max(id);
                mesh.push_node(id, xyz);
            }
            let mut conn: Vec<u32> = Vec::with_capacity(27);
            for e in 0..pb.element_count() {
                conn.clear();
                conn.extend(pb.local_conn[pb.element_range(e)].iter().map(|&c| {
                    if c == MISSING_NODE {
                        MISSING_NODE
                    } else {
                        c + part_node_base
                    }
                }));
                let id = pb.elem_labels[e]
                    .checked_add(elem_off)
                    .ok_or_else(|| too_large(&self.files, &units[u]))?;
                self.max_elem_id = self.max_elem_id.max(id);
                mesh.push_element(id, pb.elem_kinds[e], &conn);
            }
        }
        // Its own nodes.
        let own_node_base = self.mesh.node_count() as u32;
        let (ufile, uline) = (self.units[u].file, self.units[u].line);
        let too_large_here = |files: &[PathBuf]| {
            err(
                files,
                ufile,
                uline,
                "labels small enough to number the flattened model",
                "labels too large",
            )
        };
        {
            let unit = &mut self.units[u];
            unit.part_node_base = part_node_base;
            unit.part_elem_base = part_elem_base;
            unit.own_node_base = own_node_base;
            unit.placed = true;
            let b = &mut unit.block;
            for (i, &label) in b.node_labels.iter().enumerate() {
                let xyz = match &transform {
                    Some(t) => t.apply(b.coords[i]),
                    None => b.coords[i],
                };
                let id = label
                    .checked_add(node_off)
                    .ok_or_else(|| too_large_here(&self.files))?;
                self.max_node_id = self.max_node_id.max(id);
                self.mesh.push_node(id, xyz);
            }
            b.coords = Vec::new();
        }
        // Its own elements, whose nodes may be the part's or its own.
        let own_elem_base = self.mesh.element_count() as u32;
        self.units[u].own_elem_base = own_elem_base;
        let tokens = std::mem::take(&mut self.units[u].block.elem_tokens);
        let mut conn: Vec<u32> = Vec::with_capacity(27);
        let b = &self.units[u].block;
        for e in 0..b.element_count() {
            conn.clear();
            for &t in &tokens[b.element_range(e)] {
                let g = if t == 0 {
                    MISSING_NODE
                } else if t & GLOBAL != 0 {
                    (t & !GLOBAL) as u32
                } else {
                    match node_index(&self.units, u, t) {
                        Some(g) => g,
                        None => {
                            let (f, l) = b.elem_src[e];
                            return Err(self.undefined_node(f, l as usize, b.elem_labels[e], t));
                        }
                    }
                };
                conn.push(g);
            }
            let id = b.elem_labels[e]
                .checked_add(elem_off)
                .ok_or_else(|| too_large_here(&self.files))?;
            self.max_elem_id = self.max_elem_id.max(id);
            self.mesh.push_element(id, b.elem_kinds[e], &conn);
        }
        if b.redefined_nodes > 0 {
            let what = match self.units[u].kind {
                UnitKind::Model => String::new(),
                UnitKind::Instance => format!(" in instance '{}'", self.units[u].name),
                _ => format!(" in '{}'", self.units[u].name),
            };
            let w = format!(
                "{} node definitions{what} repeat a label defined before; the last coordinates are used",
                b.redefined_nodes
            );
            self.warn(w);
        }
        Ok(())
    }
}
