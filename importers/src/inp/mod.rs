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
//!   Another `C3D` name (`C3D7`, `DC3D99`) is refused at its `*ELEMENT` line: its node count is
//!   unknown. A record with more node numbers than its type has is refused at its first line,
//!   with the count over all its lines (a trailing comma continues it).
//!   Node number 0 is accepted at mid-side positions (stored as
//!   [`MISSING_NODE`](crate::mesh::MISSING_NODE)) but not at corners.
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
//!
//! # Layout
//!
//! This file holds the reader's state; `driver.rs` feeds it the lines of the deck and its
//! includes, `keywords.rs` dispatches keyword and data lines, `records.rs` reads `*NODE` and
//! `*ELEMENT` data, `set_keywords.rs` `*NSET` / `*ELSET`, `assembly.rs` parts, the assembly and
//! instances (and places units into the mesh), and `finish.rs` ends the read. The units are
//! defined in `units.rs`, the set members in `sets.rs`.

mod assembly;
mod driver;
mod finish;
mod geom;
mod keywords;
mod labels;
mod lex;
mod records;
mod set_keywords;
mod sets;
mod types;
mod units;

#[cfg(test)]
mod tests;

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

use crate::error::{describe_found, ImportError};
use crate::mesh::Mesh;

use geom::Affine;
use lex::Keyword;
use sets::SetAcc;
use types::Class;
use units::{Unit, UnitKind};

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

/// Reads an Abaqus input deck. `path` names the file in errors and anchors `*INCLUDE` files.
pub fn read(path: &Path, data: &[u8]) -> Result<Mesh, ImportError> {
    let mut reader = Reader::new();
    reader.run(path, data)?;
    reader.finish()
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
    /// File and line of the last data line of the record read so far.
    last: (u32, usize),
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

    fn current_unit(&self) -> usize {
        match self.level {
            Level::Model => 0,
            Level::Part(u) | Level::Assembly(u) | Level::Instance(u, _) => u,
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
}
