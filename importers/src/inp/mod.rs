//! Abaqus / CalculiX input deck (`.inp`) reader (FORMATS.md §3).
//!
//! # What is read
//!
//! * **Lexical rules**: keyword lines `*KEYWORD, PARAM=value, PARAM="quoted value", FLAG` in
//!   any case, blanks ignored (`*End Part` is `*ENDPART`; `*NODE PRINT` is another keyword than
//!   `*NODE`); a keyword line ending in a comma continues on the next line when that line starts
//!   with a parameter (`NAME=...`, `GENERATE`, `INTERNAL`, `UNSORTED`; a set name or a label
//!   there is data); `**` comments anywhere (also between an element record and its
//!   continuation); blank lines ignored; comma-separated data with trailing commas; CRLF; a
//!   missing final newline; a UTF-8 byte-order mark. The parsers are nom 8 `complete` parsers
//!   (`inp/lex.rs`).
//! * **`*NODE`** `[NSET=] [SYSTEM=R|C] [INPUT=]`: `label, x[, y[, z]]`, missing or blank
//!   coordinates are 0; up to three more values (the shell normal) are accepted and ignored.
//!   `SYSTEM=C` (cylindrical `r, θ in degrees, z`) is converted to Cartesian. `SYSTEM=S`
//!   (spherical) is refused with a located error: its angle convention is not confirmed.
//!   `*SYSTEM` (a local rectangular system for the following `*NODE` blocks) is applied as the
//!   Abaqus keyword page describes. A node label defined twice in the same part (or model) takes
//!   the last coordinates, with one warning.
//! * **`*ELEMENT, TYPE=`** `[ELSET=] [INPUT=]`: records continue on following lines until the
//!   type's node count is read (a trailing comma is not required); types are classified in
//!   `inp/types.rs`: solids by the digits after `C3D` (any case), `SC6R`/`SC8R`,
//!   `COH3D6`/`COH3D8`.
//!   C3D27 and C3D15V are read as hex20 / wedge15 with their extra nodes dropped (warning).
//!   Node number 0 is accepted at mid-side positions (stored as [`MISSING_NODE`]) but not at
//!   corners.
//! * **Element types that are not 3D solids** give one warning per type. Shells, membranes,
//!   surface, rigid and 2-D continuum elements are kept as `Triangle`/`Quadrilateral`, beams
//!   and trusses as `Line` (3-node lines reordered end, end, middle), only so that their
//!   `ELSET=` keeps its members; faces and particles use solids only. Other types (MASS,
//!   SPRINGA, CONN3D2, user elements ...) are consumed and dropped; a record of a type whose
//!   node count is unknown continues only after a trailing comma. An `ELSET=` on a dropped block
//!   still defines the set (with the elements that were kept, possibly none).
//! * **`*NSET` / `*ELSET`** with labels and set names on data lines, `GENERATE`
//!   (`first, last[, increment]`, default increment 1, several lines), `INSTANCE=`, `INTERNAL`,
//!   `UNSORTED` (ignored: sets are stored sorted), and `*NSET, ELSET=` (the nodes of an element
//!   set). Several blocks with the same name (any case) accumulate; the spelling written first
//!   is kept. A set name on a data line takes the members of that set at that point of the
//!   file. Node and element sets are separate name spaces.
//! * **`*INCLUDE, INPUT=`**: relative to the including file, nested; the included lines are
//!   read as if they stood in place of the keyword line (so a file holding only data lines
//!   continues the current block). A missing file, a directory, a cycle or nesting deeper than
//!   32 is an error naming the including file and line. A path with backslashes that does not
//!   exist is retried with slashes (decks written on Windows). `INPUT=` on `*NODE`,
//!   `*ELEMENT`, `*NSET` and `*ELSET` reads the data lines from that file the same way.
//! * **`*PART` … `*END PART`, `*ASSEMBLY` … `*END ASSEMBLY`, `*INSTANCE` … `*END INSTANCE`** are
//!   flattened: every instance copies its part's nodes, elements and sets. Instance data line 1
//!   is the translation, optional line 2 the rotation `ax, ay, az, bx, by, bz, angle` (degrees,
//!   right-handed about the axis from a to b); the translation is applied first. Nodes, elements
//!   and sets may also be defined inside an instance block (for independent instances; they
//!   are positioned like the part's nodes) and at assembly level (reference points). Assembly
//!   sets reference instances with `INSTANCE=` or `instance.label` / `instance.set` entries.
//!   A deck with parts but no `*INSTANCE` at all gets one instance per part, named after it
//!   (warning); a part that is never instanced while others are is left out (warning).
//! * Every other keyword (`*MATERIAL`, `*STEP`, `*BOUNDARY`, `*SURFACE`, `*HEADING`, `*MEMBRANE`,
//!   output requests ...) ends the current data block and its data lines are skipped. Keyword
//!   lines of such keywords are not checked beyond their name. Mesh-generation keywords
//!   (`*NGEN`, `*NFILL`, `*NCOPY`, `*NMAP`, `*ELGEN`, `*ELCOPY`) are refused with a located
//!   error, because skipping them would give a wrong mesh silently.
//!
//! # Ids after flattening
//!
//! Labels are local to each part, model, assembly and instance. The first of these *units* to
//! place nodes in the mesh keeps its labels as node ids; every later unit adds the largest node
//! id used before it. Element ids work the same way. A flat deck, or a deck with one instance,
//! therefore keeps the file's labels. Units are placed in this order: each instance at its
//! `*END INSTANCE` (part nodes, then nodes of the instance block), the assembly's own nodes at
//! `*END ASSEMBLY`, nodes outside any part or assembly at the end of the file.
//!
//! # Set names
//!
//! Sets defined at model or assembly level keep their names. Sets defined in a part become
//! `InstanceName.SetName` for each instance (always, even with one instance: Abaqus/CAE often
//! writes a part set and an assembly set with the same name). Sets defined inside an instance
//! block are named the same way. `mesh.sets` lists all node sets in order of first definition,
//! then all element sets.
//!
//! # Errors and limits
//!
//! A malformed line gives an [`ImportError`] with the file (the included file where the problem
//! is), the 1-based line, what was expected and what was found. An element using an undefined
//! node is an error at the element's line (checked when its part, instance, assembly or the
//! model is complete, so nodes may follow elements); so is a repeated element label. Set
//! entries naming undefined labels, sets or instances are left out with one warning per set,
//! not refused: sets are auxiliary to the mesh, and real decks name sets defined nowhere
//! (c3d6.inp has `*MEMBRANE, ELSET=P1` for an undefined `P1`; that keyword is not modelled, so
//! it is not even a reference here).
//! `GENERATE` ranges are stored as ranges, not expanded: at the end a range is walked only when
//! it is at most a few times larger than the number of labels defined, otherwise the defined
//! labels are filtered by it, so `1, 10000000000000` costs no memory. Labels must be below
//! 2^62. Nothing is allocated from a count written in the file.

mod geom;
mod labels;
mod lex;
mod sets;
mod types;

#[cfg(test)]
mod tests;

use std::borrow::Cow;
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

use crate::error::{describe_found, ImportError};
use crate::mesh::{ElementKind, Mesh, NamedSet, SetKind, MISSING_NODE};

use geom::{local_system, rotation_about, Affine};
use labels::LabelMap;
use lex::Keyword;
use sets::{append_chunks, chunk_members, push_label, push_range, remap_chunks, resolve, Chunk};
use types::Class;

/// Labels above this are refused (they would collide with [`GLOBAL`]-tagged node references).
const MAX_LABEL: u64 = 1 << 62;
/// Tags an element's node reference that is already a dense mesh index (assembly-level
/// elements naming `instance.label` nodes).
const GLOBAL: u64 = 1 << 63;
/// Set members that set names on data lines may copy, per byte of input (see
/// [`Reader::set_reference`]).
const MEMBERS_PER_BYTE: usize = 8;

/// A set or type name for a message: at most 40 characters, control characters and the
/// replacement character of bytes that are not UTF-8 shown as '?'.
fn short_set_name(name: &str) -> String {
    let mut s: String = name
        .chars()
        .take(40)
        .map(|c| {
            if c.is_control() || c == '\u{fffd}' {
                '?'
            } else {
                c
            }
        })
        .collect();
    if name.chars().nth(40).is_some() {
        s.push_str("...");
    }
    s
}

/// Include nesting limit.
const MAX_INCLUDE_DEPTH: usize = 32;
/// Limit on the number of included files read in all (the same file counts each time): files
/// that include each other several times would otherwise multiply the work at every level.
const MAX_INCLUDES: usize = 10_000;

/// A file name from the deck for a message: quoted, control and non-ASCII characters escaped,
/// and of a long name only its last 57 characters (where the file's own name is).
fn shown(name: &str) -> String {
    let mut esc = String::new();
    for c in name.chars() {
        match c {
            ' '..='~' => esc.push(c),
            '\u{fffd}' => esc.push('?'),
            _ => esc.push_str(&c.escape_default().to_string()),
        }
    }
    let n = esc.chars().count();
    if n <= 60 {
        format!("'{esc}'")
    } else {
        let tail: String = esc.chars().skip(n - 57).collect();
        format!("'...{tail}'")
    }
}

/// Reads an Abaqus input deck. `path` names the file in errors and anchors `*INCLUDE` files.
pub fn read(path: &Path, data: &[u8]) -> Result<Mesh, ImportError> {
    let mut reader = Reader::new();
    reader.run(path, data)?;
    reader.finish()
}

// ---------------------------------------------------------------------------------------------
// Model structure

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum UnitKind {
    Model,
    Part,
    Assembly,
    Instance,
}

/// Nodes and elements defined directly in one unit, by the unit's own labels.
#[derive(Debug, Default)]
struct Block {
    node_labels: Vec<u64>,
    coords: Vec<[f64; 3]>,
    nodes: LabelMap,
    elem_labels: Vec<u64>,
    elem_kinds: Vec<ElementKind>,
    /// `elem_offsets[e]..elem_offsets[e + 1]` in `elem_tokens`; starts empty, `[0, ..]` after
    /// the first element.
    elem_offsets: Vec<usize>,
    /// Node labels as written (0 = missing mid-side node, [`GLOBAL`]-tagged = mesh index).
    elem_tokens: Vec<u64>,
    /// (file, line) of each element record, for errors found when it is resolved.
    elem_src: Vec<(u32, u32)>,
    elems: LabelMap,
    /// Parts only: connectivity resolved to indices into `coords`, same layout as tokens.
    local_conn: Vec<u32>,
    redefined_nodes: usize,
}

impl Block {
    fn element_count(&self) -> usize {
        self.elem_labels.len()
    }

    fn element_range(&self, e: usize) -> std::ops::Range<usize> {
        self.elem_offsets[e]..self.elem_offsets[e + 1]
    }
}

/// A label name space: the model level, a part, the assembly, or an instance.
#[derive(Debug)]
struct Unit {
    kind: UnitKind,
    name: String,
    /// Instances: the part they copy.
    part: Option<usize>,
    block: Block,
    /// Parts: their own set name space (arena indices) and definition order.
    set_names: HashMap<(bool, String), usize>,
    set_order: Vec<usize>,
    /// Instances: positioning from the data lines.
    transform: Option<Affine>,
    placed: bool,
    part_node_base: u32,
    part_elem_base: u32,
    own_node_base: u32,
    own_elem_base: u32,
    /// Parts: whether some instance uses them.
    instanced: bool,
    /// Where the unit was opened.
    file: u32,
    line: usize,
}

impl Unit {
    fn new(kind: UnitKind, name: String, file: u32, line: usize) -> Unit {
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
fn node_index(units: &[Unit], u: usize, label: u64) -> Option<u32> {
    let unit = &units[u];
    if let Some(p) = unit.part {
        if let Some(i) = units[p].block.nodes.get(label) {
            return Some(unit.part_node_base + i);
        }
    }
    unit.block.nodes.get(label).map(|i| unit.own_node_base + i)
}

/// Global mesh index of an element label of a placed unit.
fn element_index(units: &[Unit], u: usize, label: u64) -> Option<u32> {
    let unit = &units[u];
    if let Some(p) = unit.part {
        if let Some(i) = units[p].block.elems.get(label) {
            return Some(unit.part_elem_base + i);
        }
    }
    unit.block.elems.get(label).map(|i| unit.own_elem_base + i)
}

/// A named set while the deck is read.
#[derive(Debug)]
struct SetAcc {
    name: String,
    elem: bool,
    chunks: Vec<Chunk>,
}

/// Per element type: how it is classified and how many records were read.
#[derive(Debug)]
struct TypeStat {
    name: String,
    class: Class,
    count: usize,
}

/// What data lines mean at the moment.
#[derive(Clone, Copy, Debug)]
enum Mode {
    /// Before the first keyword line: data lines are an error.
    Start,
    /// Data lines of a keyword this reader does not model.
    Skip,
    Node {
        unit: usize,
        set: Option<usize>,
        cylindrical: bool,
    },
    Element {
        unit: usize,
        ty: usize,
        set: Option<usize>,
    },
    Set {
        set: usize,
        /// Labels on data lines (and GENERATE) are in this unit.
        unit: usize,
        /// Set names on data lines are looked up from this unit (with `INSTANCE=`: that
        /// instance's sets first).
        scope: usize,
        instance: Option<usize>,
        generate: bool,
        /// `*NSET, ELSET=`: entries are elements whose nodes join the set.
        via_elements: bool,
    },
    InstanceData {
        unit: usize,
        lines: usize,
    },
    System {
        lines: usize,
    },
}

/// An element record not finished yet (its node numbers continue on the next line).
#[derive(Clone, Copy, Debug)]
struct Pending {
    label: u64,
    file: u32,
    line: usize,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Level {
    Model,
    Part(usize),
    Assembly(usize),
    Instance(usize, usize),
}

/// Asks the driver to read another file's lines next.
struct Include {
    /// As written in `INPUT=`.
    target: String,
}

struct Reader {
    files: Vec<PathBuf>,
    /// Bytes of the deck and the files it included so far (the budget of copied set members).
    input_bytes: usize,
    /// Set members (labels and ranges) copied by set names on data lines so far.
    copied_members: usize,
    units: Vec<Unit>,
    level: Level,
    part_names: HashMap<String, usize>,
    instance_names: HashMap<String, usize>,
    saw_instance: bool,
    sets: Vec<SetAcc>,
    global_sets: HashMap<(bool, String), usize>,
    global_order: Vec<usize>,
    mode: Mode,
    pending: Option<Pending>,
    /// Node numbers of the pending element.
    tokens: Vec<u64>,
    types: Vec<TypeStat>,
    type_index: HashMap<String, usize>,
    /// `*SYSTEM` in force for `*NODE` blocks of the current level.
    system: Option<Affine>,
    system_points: Vec<f64>,
    warnings: Vec<String>,
    warned: HashSet<String>,
    mesh: Mesh,
    max_node_id: u64,
    max_elem_id: u64,
    /// Last line of the main file, for errors at its end.
    last_line: usize,
}

fn err(
    files: &[PathBuf],
    file: u32,
    line: usize,
    expected: impl Into<String>,
    found: impl Into<String>,
) -> ImportError {
    let path = files
        .get(file as usize)
        .map(PathBuf::as_path)
        .unwrap_or(Path::new(""));
    if line == 0 {
        // Not tied to a line (the model level has none).
        return ImportError::whole_file(path, expected, found);
    }
    ImportError::at_line(path, line, expected, found)
}

/// Name of a keyword as used in messages.
fn kw_display(name: &str) -> String {
    match name {
        "ENDPART" => "*END PART".to_string(),
        "ENDASSEMBLY" => "*END ASSEMBLY".to_string(),
        "ENDINSTANCE" => "*END INSTANCE".to_string(),
        n => format!("*{n}"),
    }
}

/// Strips one pair of surrounding double quotes and blanks.
fn unquote(s: &[u8]) -> &[u8] {
    let t = s.trim_ascii();
    if t.len() >= 2 && t[0] == b'"' && t[t.len() - 1] == b'"' {
        &t[1..t.len() - 1]
    } else {
        t
    }
}

impl Reader {
    fn new() -> Reader {
        Reader {
            files: Vec::new(),
            input_bytes: 0,
            copied_members: 0,
            units: vec![Unit::new(UnitKind::Model, String::new(), 0, 0)],
            level: Level::Model,
            part_names: HashMap::new(),
            instance_names: HashMap::new(),
            saw_instance: false,
            sets: Vec::new(),
            global_sets: HashMap::new(),
            global_order: Vec::new(),
            mode: Mode::Start,
            pending: None,
            tokens: Vec::new(),
            types: Vec::new(),
            type_index: HashMap::new(),
            system: None,
            system_points: Vec::new(),
            warnings: Vec::new(),
            warned: HashSet::new(),
            mesh: Mesh::new(),
            max_node_id: 0,
            max_elem_id: 0,
            last_line: 0,
        }
    }

    fn warn(&mut self, w: String) {
        if self.warned.insert(w.clone()) {
            self.warnings.push(w);
        }
    }

    fn err(
        &self,
        file: u32,
        line: usize,
        expected: impl Into<String>,
        found: impl Into<String>,
    ) -> ImportError {
        err(&self.files, file, line, expected, found)
    }

    fn current_unit(&self) -> usize {
        match self.level {
            Level::Model => 0,
            Level::Part(u) | Level::Assembly(u) | Level::Instance(u, _) => u,
        }
    }

    // -----------------------------------------------------------------------------------------
    // Driver: lines of the main file and its includes

    fn run(&mut self, path: &Path, data: &[u8]) -> Result<(), ImportError> {
        struct Frame<'a> {
            file: u32,
            data: Cow<'a, [u8]>,
            pos: usize,
            line: usize,
            canonical: Option<PathBuf>,
        }
        impl Frame<'_> {
            /// The next line as (number, start, end) with "\n" / "\r\n" removed.
            fn next_range(&mut self) -> Option<(usize, usize, usize)> {
                let d: &[u8] = &self.data;
                if self.pos >= d.len() {
                    return None;
                }
                let start = self.pos;
                let end = match memchr::memchr(b'\n', &d[start..]) {
                    Some(i) => start + i,
                    None => d.len(),
                };
                self.pos = end + 1;
                self.line += 1;
                let end = if end > start && d[end - 1] == b'\r' {
                    end - 1
                } else {
                    end
                };
                Some((self.line, start, end))
            }
        }
        fn strip_bom(d: &[u8]) -> usize {
            if d.starts_with(b"\xEF\xBB\xBF") {
                3
            } else {
                0
            }
        }

        self.files.push(path.to_path_buf());
        self.input_bytes = data.len();
        self.last_line = memchr::memchr_iter(b'\n', data).count()
            + usize::from(!data.is_empty() && !data.ends_with(b"\n"));
        let mut frames = vec![Frame {
            file: 0,
            data: Cow::Borrowed(data),
            pos: strip_bom(data),
            line: 0,
            canonical: std::fs::canonicalize(path).ok(),
        }];
        let mut kw_buf: Vec<u8> = Vec::new();
        while let Some(top) = frames.last_mut() {
            let Some((lineno, start, end)) = top.next_range() else {
                frames.pop();
                continue;
            };
            let file = top.file;
            let raw = &top.data[start..end];
            let line = raw.trim_ascii_start();
            if line.is_empty() || line.starts_with(b"**") {
                continue;
            }
            if line[0] != b'*' {
                self.data_line(line, file, lineno)?;
                continue;
            }
            // A keyword line, possibly continued on following lines.
            kw_buf.clear();
            kw_buf.extend_from_slice(line.trim_ascii_end());
            while lex::trailing_comma(&kw_buf) {
                let save = (top.pos, top.line);
                let Some((_, s, e)) = top.next_range() else {
                    break;
                };
                let next = top.data[s..e].trim_ascii();
                if lex::looks_like_parameters(next) {
                    kw_buf.extend_from_slice(next);
                } else {
                    (top.pos, top.line) = save;
                    break;
                }
            }
            let Some(include) = self.keyword(&kw_buf, file, lineno)? else {
                continue;
            };
            // Read the named file next.
            let including = self.files[file as usize].clone();
            let resolve = |t: &str| {
                let target = Path::new(t);
                if target.is_absolute() {
                    target.to_path_buf()
                } else {
                    including
                        .parent()
                        .map(|p| p.join(target))
                        .unwrap_or_else(|| target.to_path_buf())
                }
            };
            let mut resolved = resolve(&include.target);
            if !resolved.exists() && include.target.contains('\\') {
                // A deck written on Windows: `sub\part.inp`.
                let alt = resolve(&include.target.replace('\\', "/"));
                if alt.exists() {
                    resolved = alt;
                }
            }
            if frames.len() >= MAX_INCLUDE_DEPTH {
                return Err(self.err(
                    file,
                    lineno,
                    format!("*INCLUDE nested at most {MAX_INCLUDE_DEPTH} deep"),
                    format!("{} at depth {}", shown(&include.target), frames.len()),
                ));
            }
            let not_file = resolved.exists() && !resolved.is_file();
            if not_file {
                return Err(self.err(
                    file,
                    lineno,
                    format!("a regular file for INPUT={}", shown(&include.target)),
                    format!(
                        "{} (a directory or device)",
                        shown(&resolved.display().to_string())
                    ),
                ));
            }
            let bytes = std::fs::read(&resolved).map_err(|e| {
                self.err(
                    file,
                    lineno,
                    format!("a readable file for INPUT={}", shown(&include.target)),
                    format!("{} ({e})", shown(&resolved.display().to_string())),
                )
            })?;
            let canonical = std::fs::canonicalize(&resolved).ok();
            if let Some(c) = &canonical {
                if frames.iter().any(|f| f.canonical.as_ref() == Some(c)) {
                    return Err(self.err(
                        file,
                        lineno,
                        "an *INCLUDE that does not include a file being read (no cycle)",
                        format!(
                            "{}, which is already being read",
                            shown(&resolved.display().to_string())
                        ),
                    ));
                }
            }
            if self.files.len() > MAX_INCLUDES {
                return Err(self.err(
                    file,
                    lineno,
                    format!("at most {MAX_INCLUDES} *INCLUDE files read in all"),
                    format!("another one, {}", shown(&include.target)),
                ));
            }
            let index = u32::try_from(self.files.len())
                .map_err(|_| self.err(file, lineno, "fewer included files", "too many"))?;
            self.files.push(resolved);
            self.input_bytes = self.input_bytes.saturating_add(bytes.len());
            let pos = strip_bom(&bytes);
            frames.push(Frame {
                file: index,
                data: Cow::Owned(bytes),
                pos,
                line: 0,
                canonical,
            });
        }
        Ok(())
    }

    // -----------------------------------------------------------------------------------------
    // Keyword lines

    fn keyword(
        &mut self,
        text: &[u8],
        file: u32,
        line: usize,
    ) -> Result<Option<Include>, ImportError> {
        let kw = match lex::keyword(text) {
            Ok(k) => k,
            Err((at, expected)) => {
                let name_end = text.iter().position(|&b| b == b',').unwrap_or(text.len());
                let name: String = text[1..name_end]
                    .iter()
                    .filter(|b| !b.is_ascii_whitespace())
                    .map(|b| b.to_ascii_uppercase() as char)
                    .collect();
                if MODELLED.contains(&name.as_str()) {
                    return Err(self.err(
                        file,
                        line,
                        expected,
                        describe_found(&text[at.min(text.len())..]),
                    ));
                }
                self.end_block(file, line, text)?;
                self.mode = Mode::Skip;
                return Ok(None);
            }
        };
        let mut kw = kw;
        if let Some(full) = self.expand_abbreviation(&kw.name, file, line)? {
            kw.name = full.to_string();
        }
        if kw.name == "INCLUDE" {
            // The included lines stand in place of this line: the current block goes on.
            let target = self.required(&kw, "INPUT", file, line, text)?;
            return Ok(Some(Include { target }));
        }
        self.end_block(file, line, text)?;
        self.mode = Mode::Skip;
        let name = kw.name.clone();
        match name.as_str() {
            "NODE" => self.kw_node(&kw, file, line, text)?,
            "ELEMENT" => self.kw_element(&kw, file, line, text)?,
            "NSET" | "ELSET" => self.kw_set(&kw, name == "ELSET", file, line, text)?,
            "PART" => self.kw_part(&kw, file, line, text)?,
            "ENDPART" => self.kw_end_part(file, line, text)?,
            "ASSEMBLY" => self.kw_assembly(&kw, file, line, text)?,
            "ENDASSEMBLY" => self.kw_end_assembly(file, line, text)?,
            "INSTANCE" => self.kw_instance(&kw, file, line, text)?,
            "ENDINSTANCE" => self.kw_end_instance(file, line, text)?,
            "SYSTEM" => {
                self.system = None;
                self.system_points.clear();
                self.mode = Mode::System { lines: 0 };
            }
            "NGEN" | "NFILL" | "NCOPY" | "NMAP" | "ELGEN" | "ELCOPY" => {
                return Err(self.err(
                    file,
                    line,
                    "nodes and elements listed one by one (mesh generation keywords are not supported)",
                    describe_found(text),
                ));
            }
            _ => {}
        }
        // `INPUT=` on a data keyword: its data lines come from that file.
        if matches!(name.as_str(), "NODE" | "ELEMENT" | "NSET" | "ELSET") {
            if let Some(input) = kw.value("INPUT") {
                return Ok(Some(Include {
                    target: input.to_string(),
                }));
            }
        }
        Ok(None)
    }

    /// The keyword this reader acts on that `name` abbreviates, if it is one: Abaqus accepts
    /// unambiguous abbreviations (FORMATS.md §3.1), such as `*ELEM` for `*ELEMENT`. An
    /// abbreviation of one of them that could also stand for another Abaqus keyword (`*NOD`:
    /// `*NODE` or `*NODAL THICKNESS`) is an error rather than a guess, since skipping it would
    /// drop its data.
    fn expand_abbreviation(
        &mut self,
        name: &str,
        file: u32,
        line: usize,
    ) -> Result<Option<&'static str>, ImportError> {
        if name.len() < 3 || ACTED_ON.contains(&name) {
            return Ok(None);
        }
        // (written form, blanks removed)
        let mut candidates: Vec<(&str, String)> = ACTED_ON
            .iter()
            .chain(LOOK_ALIKES.iter())
            .map(|k| (*k, k.replace(' ', "")))
            .filter(|(_, k)| k.starts_with(name))
            .collect();
        let Some(&(first, _)) = candidates.first() else {
            return Ok(None);
        };
        if !ACTED_ON.contains(&first) {
            return Ok(None);
        }
        // `*ELEM` also begins `*ELEMENT OUTPUT` and the like, which begin with `*ELEMENT`.
        candidates.retain(|(_, k)| !(k.starts_with(first) && k != first));
        if candidates.len() > 1 {
            let names: Vec<String> = candidates.iter().map(|(k, _)| format!("*{k}")).collect();
            return Err(self.err(
                file,
                line,
                format!("a keyword written out in full ({})", names.join(" or ")),
                format!("*{name}, an abbreviation of more than one keyword"),
            ));
        }
        let full = first;
        let shown = if file == 0 {
            format!("line {line}")
        } else {
            format!("{}:{line}", self.files[file as usize].display())
        };
        self.warn(format!("{shown}: *{name} read as *{full}"));
        Ok(Some(full))
    }

    /// Ends the current data block before a keyword line: an unfinished element record is an
    /// error (unless its type's node count is unknown), `*SYSTEM` data takes effect.
    fn end_block(&mut self, file: u32, line: usize, text: &[u8]) -> Result<(), ImportError> {
        if self.pending.is_some() && self.pending_need().is_none() {
            // A record of a type with unknown node count ended with a trailing comma.
            if let Mode::Element { unit, ty, set } = self.mode {
                self.finish_element(unit, ty, set)?;
            }
        }
        if let Some(p) = self.pending.take() {
            let need = self.pending_need().unwrap_or(0);
            return Err(self.err(
                file,
                line,
                format!(
                    "{} more node numbers of element {} (record started at {})",
                    need.saturating_sub(self.tokens.len()),
                    p.label,
                    if p.file == file {
                        format!("line {}", p.line)
                    } else {
                        format!("{}:{}", self.files[p.file as usize].display(), p.line)
                    }
                ),
                describe_found(text),
            ));
        }
        if let Mode::System { .. } = self.mode {
            self.finish_system(file, line)?;
        }
        Ok(())
    }

    fn required(
        &self,
        kw: &Keyword,
        param: &str,
        file: u32,
        line: usize,
        text: &[u8],
    ) -> Result<String, ImportError> {
        match kw.value(param) {
            Some(v) if !v.is_empty() => Ok(v.to_string()),
            _ => Err(self.err(
                file,
                line,
                format!("{param}= on {}", kw_display(&kw.name)),
                describe_found(text),
            )),
        }
    }

    fn kw_node(
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

    fn kw_element(
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
                let t = self.types.len();
                self.types.push(TypeStat {
                    class: types::classify(&ty_name),
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

    fn kw_set(
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

    fn kw_part(
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

    fn kw_end_part(&mut self, file: u32, line: usize, text: &[u8]) -> Result<(), ImportError> {
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

    fn nesting_error(&self, file: u32, line: usize, text: &[u8]) -> ImportError {
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

    fn kw_assembly(
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

    fn kw_end_assembly(&mut self, file: u32, line: usize, text: &[u8]) -> Result<(), ImportError> {
        let Level::Assembly(u) = self.level else {
            return Err(self.nesting_error(file, line, text));
        };
        self.place(u)?;
        self.level = Level::Model;
        self.system = None;
        Ok(())
    }

    fn kw_instance(
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

    fn open_instance(
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

    fn kw_end_instance(&mut self, file: u32, line: usize, text: &[u8]) -> Result<(), ImportError> {
        let Level::Instance(u, a) = self.level else {
            return Err(self.nesting_error(file, line, text));
        };
        self.place(u)?;
        self.level = Level::Assembly(a);
        self.system = None;
        Ok(())
    }

    // -----------------------------------------------------------------------------------------
    // Sets

    /// The set `name` of kind `elem` defined in unit `u`'s name space, created if new.
    fn define_set(&mut self, elem: bool, name: &str, u: usize) -> usize {
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
    fn set_reference(&mut self, name: &str, file: u32, line: usize) -> Result<(), ImportError> {
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

    fn set_line(&mut self, line: &[u8], file: u32, lineno: usize) -> Result<(), ImportError> {
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
                        return Err(self.err(
                            file,
                            lineno,
                            "a positive integer label or a set name",
                            describe_found(f),
                        ))
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

    // -----------------------------------------------------------------------------------------
    // Data lines

    fn data_line(&mut self, line: &[u8], file: u32, lineno: usize) -> Result<(), ImportError> {
        match self.mode {
            Mode::Start => Err(self.err(
                file,
                lineno,
                "a keyword line starting with '*' (or a '**' comment) first",
                describe_found(line),
            )),
            Mode::Skip => Ok(()),
            Mode::Node {
                unit,
                set,
                cylindrical,
            } => self.node_line(line, file, lineno, unit, set, cylindrical),
            Mode::Element { unit, ty, set } => self.element_line(line, file, lineno, unit, ty, set),
            Mode::Set { .. } => self.set_line(line, file, lineno),
            Mode::InstanceData { unit, lines } => {
                self.instance_line(line, file, lineno, unit, lines)
            }
            Mode::System { lines } => self.system_line(line, file, lineno, lines),
        }
    }

    fn reals<const N: usize>(
        &self,
        line: &[u8],
        file: u32,
        lineno: usize,
        what: &str,
    ) -> Result<([f64; N], usize), ImportError> {
        let mut out = [0.0; N];
        let mut n = 0;
        for f in lex::fields(line) {
            if n >= N {
                if lex::is_blank_field(f) {
                    continue;
                }
                return Err(self.err(
                    file,
                    lineno,
                    format!("at most {N} values in {what}"),
                    describe_found(line),
                ));
            }
            if !lex::is_blank_field(f) {
                out[n] = lex::real(f).ok_or_else(|| {
                    self.err(
                        file,
                        lineno,
                        format!("a real number in {what}"),
                        describe_found(f),
                    )
                })?;
            }
            n += 1;
        }
        Ok((out, n))
    }

    fn instance_line(
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

    fn system_line(
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
    fn finish_system(&mut self, file: u32, line: usize) -> Result<(), ImportError> {
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

    #[allow(clippy::too_many_arguments)]
    fn node_line(
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

    fn pending_need(&self) -> Option<usize> {
        match self.mode {
            Mode::Element { ty, .. } => self.types[ty].class.node_numbers(),
            _ => None,
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn element_line(
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
            });
            self.tokens.clear();
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
                    let p = self.pending.map_or(0, |p| p.label);
                    return Err(self.err(
                        file,
                        lineno,
                        format!(
                            "{n} node numbers for element {p} of type {}",
                            self.types[ty].name
                        ),
                        format!("{} node numbers", self.tokens.len()),
                    ));
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

    fn finish_element(
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

    // -----------------------------------------------------------------------------------------
    // Placement: copying units into the mesh

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
    fn place(&mut self, u: usize) -> Result<(), ImportError> {
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

    // -----------------------------------------------------------------------------------------
    // End of input

    fn finish(mut self) -> Result<Mesh, ImportError> {
        if self.pending.is_some() && self.pending_need().is_none() {
            if let Mode::Element { unit, ty, set } = self.mode {
                self.finish_element(unit, ty, set)?;
            }
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

/// Keywords this reader acts on (reads, or refuses as unsupported).
const ACTED_ON: [&str; 18] = [
    "NODE",
    "ELEMENT",
    "NSET",
    "ELSET",
    "PART",
    "ENDPART",
    "ASSEMBLY",
    "ENDASSEMBLY",
    "INSTANCE",
    "ENDINSTANCE",
    "SYSTEM",
    "INCLUDE",
    "NGEN",
    "NFILL",
    "NCOPY",
    "NMAP",
    "ELGEN",
    "ELCOPY",
];

/// Other Abaqus keywords that begin with the same three or more letters as one in
/// [`ACTED_ON`]: an abbreviation (blanks removed) that begins one of these is ambiguous.
const LOOK_ALIKES: [&str; 14] = [
    "NODAL THICKNESS",
    "NODAL ENERGY RATE",
    "NODE OUTPUT",
    "NODE PRINT",
    "NODE FILE",
    "ELEMENT OUTPUT",
    "ELEMENT PROPERTIES",
    "ELECTRICAL CONDUCTIVITY",
    "PARAMETER",
    "ASSEMBLED FASTENER",
    "INCIDENT WAVE",
    "INCREMENTATION OUTPUT",
    "END STEP",
    "END LOAD CASE",
];

/// Keywords whose keyword lines must parse (others are skipped even when malformed).
const MODELLED: [&str; 12] = [
    "ENDPART",
    "ENDASSEMBLY",
    "NODE",
    "ELEMENT",
    "NSET",
    "ELSET",
    "INCLUDE",
    "PART",
    "ASSEMBLY",
    "INSTANCE",
    "SYSTEM",
    "ENDINSTANCE",
];
