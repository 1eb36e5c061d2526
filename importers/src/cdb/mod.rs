//! ANSYS CDB reader: MAPDL blocked archives (CDWRITE) and Workbench solver input (FORMATS.md §1).
//!
//! One pass over the lines. Outside blocks, each line is split into `$`-joined statements with
//! `!` comments removed, and only the commands that define the mesh are acted on (`NBLOCK`,
//! `EBLOCK`, `CMBLOCK`, `ETBLOCK`, `ET`, `KEYOPT`, `TYPE`, `*SET`, `NAME=VALUE`), in any case
//! and abbreviated to four characters (§1.1). Block records are sliced by the widths of the
//! block's Fortran format line (`format.rs`), never split on whitespace (§1.8).
//!
//! Choices:
//! * Every NBLOCK and every EBLOCK is read (Workbench files have several, §1.1), so node and
//!   element counts cover the whole file, unlike mapdl-archive.
//! * A node number defined twice is an error naming both lines: CDWRITE never writes one twice,
//!   so a repeat means a concatenated or damaged file, and keeping either copy would silently
//!   move geometry. The same holds for element numbers.
//! * Only 3D solids are kept (§1.2, §1.6, §1.7). Shells, surfaces, contact, beams and 2-D
//!   MESH200 shapes are skipped with one warning per element type; so are elements whose type
//!   no `ET`/`ETBLOCK` defines. A file with nodes but no solids (a shell model) is read.
//! * Element records give node numbers; they are resolved to dense indices once all blocks are
//!   read, so an undefined node is reported as `expected a node defined in an NBLOCK`.
//! * A truncated NBLOCK (end of file before its terminator) and NUL bytes anywhere are errors:
//!   both mean a cut or padded file (corrupt_a/b.cdb, §1.8 item 6). An EBLOCK may end at the end
//!   of the file without `-1` (etblock.cdb).
//!
//! Layout: this file holds the command loop and the reader's state; each block has its
//! module (`nblock.rs`, `eblock.rs`, `cmblock.rs`, and `element_types.rs` for `ET`, `ETBLOCK`
//! and `KEYOPT`), over the record fields of `records.rs`; `finish.rs` resolves what was read.

mod cmblock;
mod command;
mod eblock;
mod element_types;
mod elements;
mod finish;
mod format;
mod nblock;
mod records;
#[cfg(test)]
mod tests;

use std::collections::HashMap;
use std::iter::Peekable;
use std::path::Path;

use crate::error::ImportError;
use crate::mesh::Mesh;
use crate::text::lines;

use cmblock::Component;
use command::{Command, Parameters};
use eblock::Skipped;

/// Largest node number accepted; `u32::MAX` is [`MISSING_NODE`](crate::mesh::MISSING_NODE).
/// MAPDL itself stops at 2^31 − 1.
const MAX_NODE_ID: i64 = u32::MAX as i64 - 1;

/// Reads an ANSYS CDB (or Workbench `.dat`) file held in `data`; `path` names it in errors.
pub fn read(path: &Path, data: &[u8]) -> Result<Mesh, ImportError> {
    let data = data.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(data);
    check_nul(path, data)?;
    let mut reader = Reader::new(path, data.len());
    let mut cursor = Cursor {
        lines: (Box::new(lines(data)) as Box<dyn Iterator<Item = Line<'_>> + '_>).peekable(),
        last: 0,
    };
    while let Some((no, line)) = cursor.next() {
        match line.trim_ascii_start().first() {
            // Data lines of blocks the reader does not use (RLBLOCK, *PREAD ...), stray
            // terminators and format lines.
            None | Some(b'0'..=b'9' | b'-' | b'+' | b'.' | b'(' | b'!') => continue,
            _ => {}
        }
        for statement in command::statements(line) {
            reader.statement(no, statement, &mut cursor)?;
        }
    }
    reader.finish()
}

/// NUL bytes never occur in a text archive; they are the padding of a cut file
/// (corrupt_a/b.cdb). One memchr over the file finds them before any parsing.
fn check_nul(path: &Path, data: &[u8]) -> Result<(), ImportError> {
    let Some(pos) = memchr::memchr(0, data) else {
        return Ok(());
    };
    let line = memchr::memchr_iter(b'\n', &data[..pos]).count() + 1;
    let start = memchr::memrchr(b'\n', &data[..pos]).map_or(0, |p| p + 1);
    Err(ImportError::at_line(
        path,
        line,
        "text (an ANSYS archive holds no NUL bytes; the file is truncated or corrupt)",
        format!("NUL bytes from column {}", pos - start + 1),
    ))
}

/// `(1-based line number, line without its end of line)`.
type Line<'a> = (usize, &'a [u8]);

/// The lines of the file with one line of lookahead, which block readers need to stop at a
/// terminator without consuming the next command.
struct Cursor<'a> {
    lines: Peekable<Box<dyn Iterator<Item = Line<'a>> + 'a>>,
    last: usize,
}

impl<'a> Cursor<'a> {
    fn next(&mut self) -> Option<Line<'a>> {
        let l = self.lines.next()?;
        self.last = l.0;
        Some(l)
    }

    fn peek(&mut self) -> Option<Line<'a>> {
        self.lines.peek().copied()
    }

    /// The line number to report for "found end of file".
    fn eof_line(&self) -> usize {
        self.last + 1
    }
}

struct Reader<'p> {
    path: &'p Path,
    data_len: usize,
    /// Nodes in file order; elements with *file* node numbers in `connectivity` until
    /// [`Reader::finish`] resolves them.
    mesh: Mesh,
    node_lines: Vec<u32>,
    element_lines: Vec<u32>,
    /// Element type number → element number (1 → 186).
    types: HashMap<i64, i64>,
    /// Element type number → KEYOPT(1) (MESH200 shapes).
    keyopt1: HashMap<i64, i64>,
    params: Parameters,
    /// The last lookup of [`Reader::type_info`]: records of one type come in runs.
    type_cache: Option<(i64, Option<(i64, i64)>)>,
    /// The last `TYPE` command, for COMPACT EBLOCKs.
    current_type: Option<i64>,
    skipped: Vec<Skipped>,
    components: Vec<Component>,
    missing_midside: usize,
    warnings: Vec<String>,
    /// Reused record buffers.
    fields: Vec<i64>,
    raw: Vec<u32>,
}

fn lineno(no: usize) -> u32 {
    u32::try_from(no).unwrap_or(u32::MAX)
}

impl<'p> Reader<'p> {
    fn new(path: &'p Path, data_len: usize) -> Self {
        Reader {
            path,
            data_len,
            mesh: Mesh::new(),
            node_lines: Vec::new(),
            element_lines: Vec::new(),
            types: HashMap::new(),
            keyopt1: HashMap::new(),
            type_cache: None,
            params: Parameters::default(),
            current_type: None,
            skipped: Vec::new(),
            components: Vec::new(),
            missing_midside: 0,
            warnings: Vec::new(),
            fields: Vec::new(),
            raw: Vec::new(),
        }
    }

    fn err(
        &self,
        line: usize,
        expected: impl Into<String>,
        found: impl Into<String>,
    ) -> ImportError {
        ImportError::at_line(self.path, line, expected, found)
    }

    /// Acts on one statement of a command line.
    fn statement(
        &mut self,
        no: usize,
        stmt: &[u8],
        cur: &mut Cursor<'_>,
    ) -> Result<(), ImportError> {
        let name = command::name(stmt);
        if name.is_empty() {
            return Ok(());
        }
        let Some(cmd) = command::command(name) else {
            self.params.assignment(stmt);
            return Ok(());
        };
        let args = command::arguments(stmt);
        match cmd {
            Command::Nblock => self.nblock(&args, cur),
            Command::Eblock => self.eblock(no, &args, cur),
            Command::Cmblock => self.cmblock(no, &args, cur),
            Command::Etblock => self.etblock(cur),
            Command::Et => {
                self.et(no, &args);
                Ok(())
            }
            Command::Keyopt => {
                // KEYOPT,ITYPE,KNUM,VALUE: only KEYOPT(1) matters (MESH200 shape, §1.2).
                let get = |i: usize| args.get(i).and_then(|a| self.params.integer(a));
                if let (Some(itype), Some(1), Some(value)) = (get(0), get(1), get(2)) {
                    self.define_type(itype, None, value);
                }
                Ok(())
            }
            Command::Type => {
                // TYPE with no argument selects type 1, as in MAPDL.
                self.current_type = match args.first() {
                    None | Some([]) => Some(1),
                    Some(a) => self.params.integer(a),
                };
                Ok(())
            }
            Command::Set => {
                if let Some(name) = args.first() {
                    self.params.set(name, args.get(1).copied());
                }
                Ok(())
            }
        }
    }
}
