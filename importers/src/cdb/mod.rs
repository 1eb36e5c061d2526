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

mod command;
mod elements;
mod format;
#[cfg(test)]
mod tests;

use std::collections::HashMap;
use std::iter::Peekable;
use std::path::Path;

use crate::error::{describe_found, ImportError};
use crate::mesh::{Mesh, NamedSet, NodeIndex, SetKind, MISSING_NODE};
use crate::text::{lines, parse_int, parse_real};

use command::{Command, Parameters};
use elements::{Built, Class};
use format::{Column, Format};

/// Largest node number accepted; `u32::MAX` is [`MISSING_NODE`]. MAPDL itself stops at
/// 2^31 − 1.
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

/// What a line inside a block is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Row {
    Blank,
    Comment,
    /// First non-blank character `-` or a letter (or `/`, `*`): the block terminator
    /// (`N,R5.3,LOC,-1`, `-1`) or the next command (FORMATS.md §1.3, §1.4).
    End,
    Data,
}

fn row(line: &[u8]) -> Row {
    match line.trim_ascii_start().first() {
        None => Row::Blank,
        Some(b'!') => Row::Comment,
        Some(&b) if b == b'-' || b == b'/' || b == b'*' || b.is_ascii_alphabetic() => Row::End,
        Some(_) => Row::Data,
    }
}

/// An integer field of a data record, trimmed. Records hold millions of integers, so this
/// avoids the UTF-8 check and `str::parse` of [`parse_int`], to which it defers only for
/// more than 18 digits (where overflow becomes possible).
#[inline]
fn int_field(field: &[u8]) -> Option<i64> {
    int_trimmed(field.trim_ascii())
}

/// [`int_field`] on a field already trimmed.
#[inline]
fn int_trimmed(t: &[u8]) -> Option<i64> {
    let (negative, digits) = match t.first()? {
        b'-' => (true, &t[1..]),
        b'+' => (false, &t[1..]),
        _ => (false, t),
    };
    if digits.is_empty() {
        return None;
    }
    if digits.len() > 18 {
        return parse_int(t);
    }
    let mut v: i64 = 0;
    for &b in digits {
        let d = b.wrapping_sub(b'0');
        if d > 9 {
            return None;
        }
        v = v * 10 + i64::from(d);
    }
    Some(if negative { -v } else { v })
}

/// Describes a sliced field for an error: empty or blank fields are named as such.
fn found_field(field: &[u8]) -> String {
    if field.trim_ascii().is_empty() {
        "a blank field".to_string()
    } else {
        describe_found(field)
    }
}

/// A real as Fortran writes it: `E`/`e`/`D` exponents and plain decimals ([`parse_real`]), and
/// the exponent without a letter that `Ew.d` gives for |exp| > 99 (`1.0000000000000-100`,
/// FORMATS.md §1.8 item 2).
fn parse_fortran_real(field: &[u8]) -> Option<f64> {
    if let Some(v) = parse_real(field) {
        return Some(v);
    }
    let s = field.trim_ascii();
    let p = (1..s.len()).rev().find(|&i| {
        (s[i] == b'+' || s[i] == b'-') && (s[i - 1].is_ascii_digit() || s[i - 1] == b'.')
    })?;
    if s.len() >= 63 {
        return None;
    }
    let mut buf = [0u8; 64];
    buf[..p].copy_from_slice(&s[..p]);
    buf[p] = b'e';
    buf[p + 1..=s.len()].copy_from_slice(&s[p..]);
    parse_real(&buf[..=s.len()])
}

/// Entity of a CMBLOCK component.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Entity {
    Node,
    Element,
}

/// A component as read: closed intervals of node or element numbers (a negative item extends
/// the previous one into a range, FORMATS.md §1.5), resolved once the whole file is read.
struct Component {
    name: String,
    entity: Entity,
    intervals: Vec<(u64, u64)>,
}

/// Why elements were skipped; one warning per (type, reason).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum SkipReason {
    /// No ET/ETBLOCK defines the type (or no TYPE precedes a COMPACT block).
    NoType,
    /// Not a 3D solid.
    NotSolid { keyopt1: i64 },
    /// Repeated corners that form no hex, wedge, pyramid or tet.
    BadCollapse,
}

struct Skipped {
    itype: Option<i64>,
    ename: Option<i64>,
    reason: SkipReason,
    count: usize,
}

/// The record layouts of EBLOCK (FORMATS.md §1.4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum EblockKey {
    /// `EBLOCK,19,SOLID`: 11 leading fields, field 9 = node count, nodes 1..8 then one
    /// continuation line.
    Solid,
    /// `EBLOCK,10,,`: element number, type, real, material, coordinate system, then nodes.
    Plain,
    /// `EBLOCK,11,COMPACT`: element number then nodes; the type is the last `TYPE`.
    Compact,
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

/// `SOLID185`, or `element 999` for a number the reader does not know.
fn type_name(ename: i64) -> String {
    elements::element_name(ename).unwrap_or_else(|| format!("element {ename}"))
}

fn plural(n: usize, what: &str) -> String {
    if n == 1 {
        format!("1 {what}")
    } else {
        format!("{n} {what}s")
    }
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

    /// `ET,ITYPE,Ename[,KOP1,...]`; Ename may be `186`, `SOLID186` or a parameter, and ITYPE a
    /// parameter (`et,cid,174`, FORMATS.md §1.2). Redefining a type resets its KEYOPT(1).
    fn et(&mut self, no: usize, args: &[&[u8]]) {
        let itype = args.first().and_then(|a| self.params.integer(a));
        let ename = args
            .get(1)
            .and_then(|a| command::element_number(&self.params, a));
        match (itype, ename) {
            (Some(itype), Some(ename)) => {
                let k1 = args
                    .get(2)
                    .and_then(|a| self.params.integer(a))
                    .unwrap_or(0);
                self.define_type(itype, Some(ename), k1);
            }
            _ => self.warnings.push(format!(
                "line {no}: ET command ignored: cannot read a type number and an element name \
                 from {}",
                describe_found(&args.join(&b','))
            )),
        }
    }

    /// Skips lines up to the block's format line and parses it.
    fn format_line(
        &self,
        cur: &mut Cursor<'_>,
        block: &str,
        example: &str,
    ) -> Result<(usize, Format), ImportError> {
        let expected = || format!("the {block} format line, such as '{example}'");
        loop {
            let Some((no, line)) = cur.peek() else {
                return Err(self.err(cur.eof_line(), expected(), "end of file"));
            };
            if matches!(row(line), Row::Blank | Row::Comment) {
                cur.next();
                continue;
            }
            return match Format::parse(line) {
                Some(f) => {
                    cur.next();
                    Ok((no, f))
                }
                None => Err(self.err(no, expected(), describe_found(line))),
            };
        }
    }

    /// NBLOCK: records until the terminator, whatever the header counts say (they are missing
    /// or wrong in real files, FORMATS.md §1.3). Omitted trailing coordinates are 0.
    fn nblock(&mut self, args: &[&[u8]], cur: &mut Cursor<'_>) -> Result<(), ImportError> {
        let (fno, fmt) = self.format_line(cur, "NBLOCK", "(3i9,6e21.13e3)")?;
        let Some(layout) = fmt.node_layout() else {
            return Err(self.err(
                fno,
                "an NBLOCK format with integer columns then real columns, such as \
                 '(3i9,6e21.13e3)'",
                "a format without that layout",
            ));
        };
        // Capacity hint from the header, capped by what the file can hold.
        let declared = args
            .iter()
            .skip(2)
            .filter_map(|a| parse_int(a))
            .max()
            .unwrap_or(0)
            .max(0) as usize;
        let hint = declared.min(self.data_len / (layout.id.width + 2));
        self.mesh.node_ids.reserve(hint);
        self.mesh.coords.reserve(hint);
        self.node_lines.reserve(hint);
        const AXES: [&str; 3] = ["x", "y", "z"];
        loop {
            let Some((no, line)) = cur.peek() else {
                return Err(self.err(
                    cur.eof_line(),
                    "more NBLOCK records or the block terminator ('N,R5.3,LOC,-1' or '-1')",
                    "end of file",
                ));
            };
            match row(line) {
                Row::Blank | Row::Comment => {
                    cur.next();
                    continue;
                }
                Row::End => return Ok(()),
                Row::Data => {}
            }
            cur.next();
            let id_field = layout.id.slice(line);
            let id = match int_field(id_field) {
                Some(v) if (1..=MAX_NODE_ID).contains(&v) => v,
                _ => {
                    return Err(self.err(
                        no,
                        format!("a node number in {}", layout.id.describe()),
                        found_field(id_field),
                    ))
                }
            };
            let mut xyz = [0.0; 3];
            for (k, col) in layout.coords.iter().enumerate() {
                let Some(col) = col else { break };
                let f = col.slice(line);
                if f.trim_ascii().is_empty() {
                    continue;
                }
                xyz[k] = parse_fortran_real(f).ok_or_else(|| {
                    self.err(
                        no,
                        format!(
                            "the {} coordinate of node {id} in {}",
                            AXES[k],
                            col.describe()
                        ),
                        found_field(f),
                    )
                })?;
            }
            if line.len() > layout.end && !line[layout.end..].trim_ascii().is_empty() {
                return Err(self.err(
                    no,
                    format!(
                        "at most {} columns, as the NBLOCK format line gives",
                        layout.end
                    ),
                    describe_found(&line[layout.end..]),
                ));
            }
            self.mesh.push_node(id as u64, xyz);
            self.node_lines.push(lineno(no));
        }
    }

    /// Slices an integer record into `out` (reused buffer). Fields are trimmed (HyperMesh
    /// writes `'      0 '`, FORMATS.md §1.4); trailing blank fields end the record (MAPDL omits
    /// trailing zeros); a blank field before a non-blank one is an error.
    fn int_fields(
        &self,
        no: usize,
        line: &[u8],
        cols: &[Column],
        out: &mut Vec<i64>,
    ) -> Result<(), ImportError> {
        out.clear();
        let mut blank: Option<&Column> = None;
        for c in cols {
            if c.start >= line.len() {
                // Columns only move right: the rest are past the end of the line, so blank
                // (a format line may declare thousands of columns for a short record).
                break;
            }
            let f = c.slice(line);
            let t = f.trim_ascii();
            if t.is_empty() {
                blank.get_or_insert(c);
                continue;
            }
            if let Some(b) = blank {
                return Err(self.err(
                    no,
                    format!("an integer in {}", b.describe()),
                    "a blank field",
                ));
            }
            match int_trimmed(t) {
                Some(v) => out.push(v),
                None => {
                    return Err(self.err(
                        no,
                        format!("an integer in {}", c.describe()),
                        found_field(f),
                    ))
                }
            }
        }
        let end = cols.last().map_or(0, |c| c.start + c.width);
        if line.len() > end && !line[end..].trim_ascii().is_empty() {
            return Err(self.err(
                no,
                format!(
                    "at most {} fields ({end} columns), as the block's format line gives",
                    cols.len()
                ),
                describe_found(&line[end..]),
            ));
        }
        Ok(())
    }

    /// A node number from an element record: 0 means "no node" (a missing midside node,
    /// FORMATS.md §1.4) and stays 0 here.
    fn node_ref(&self, no: usize, v: i64) -> Result<u32, ImportError> {
        if (0..=MAX_NODE_ID).contains(&v) {
            Ok(v as u32)
        } else {
            Err(self.err(no, "a node number", v.to_string()))
        }
    }

    /// Reads the one continuation line of a record into `self.fields`.
    fn continuation(
        &mut self,
        cur: &mut Cursor<'_>,
        cols: &[Column],
        what: impl FnOnce() -> String,
    ) -> Result<usize, ImportError> {
        let Some((no, line)) = cur.peek() else {
            return Err(self.err(cur.eof_line(), what(), "end of file"));
        };
        match row(line) {
            Row::Data => {}
            // A record whose continuation fields are all missing (midside nodes 0) can be
            // written as an empty line; it reads as a continuation with no fields, as a
            // partly filled one does (mapdl-archive reads it so too).
            Row::Blank => {
                cur.next();
                self.fields.clear();
                return Ok(no);
            }
            _ => return Err(self.err(no, what(), describe_found(line))),
        }
        cur.next();
        let mut f = std::mem::take(&mut self.fields);
        let r = self.int_fields(no, line, cols, &mut f);
        self.fields = f;
        r.map(|()| no)
    }

    /// EBLOCK in any of its three layouts (FORMATS.md §1.4). Records run to a `-1` line, the
    /// next command, or the end of the file.
    fn eblock(
        &mut self,
        no: usize,
        args: &[&[u8]],
        cur: &mut Cursor<'_>,
    ) -> Result<(), ImportError> {
        let key_field = args.get(1).copied().unwrap_or(b"");
        let key = if key_field.is_empty() {
            EblockKey::Plain
        } else if key_field.eq_ignore_ascii_case(b"SOLID") {
            EblockKey::Solid
        } else if key_field.eq_ignore_ascii_case(b"COMPACT") {
            EblockKey::Compact
        } else {
            return Err(self.err(
                no,
                "an EBLOCK key SOLID, COMPACT or blank (EBLOCK,NUM,KEY,...)",
                describe_found(key_field),
            ));
        };
        // COMPACT: NUM is the record length (element number + nodes).
        let record_len = args
            .first()
            .and_then(|a| parse_int(a))
            .filter(|&n| (2..=64).contains(&n))
            .map(|n| n as usize);
        let (fno, fmt) = self.format_line(cur, "EBLOCK", "(19i9)")?;
        if !fmt.all_int() {
            return Err(self.err(
                fno,
                "an EBLOCK format of integer columns, such as '(19i9)'",
                "a format with other columns",
            ));
        }
        let cols = fmt.columns;
        loop {
            let Some((no, line)) = cur.peek() else {
                return Ok(());
            };
            match row(line) {
                Row::Blank | Row::Comment => {
                    cur.next();
                    continue;
                }
                Row::End => return Ok(()),
                Row::Data => {}
            }
            cur.next();
            let mut f = std::mem::take(&mut self.fields);
            let r = self.int_fields(no, line, &cols, &mut f);
            self.fields = f;
            r?;
            match key {
                EblockKey::Solid => self.solid_record(no, &cols, cur)?,
                EblockKey::Plain => self.plain_record(no, &cols, cur)?,
                EblockKey::Compact => self.compact_record(no, &cols, record_len, cur)?,
            }
        }
    }

    /// SOLID layout: material, type, real, section, coordinate system, birth/death, solid
    /// entity, shape, node count, unused, element number, then nodes; more than fit on the
    /// first line continue on exactly one following line. Field 9 may be below the nominal
    /// node count (TetBeam.cdb writes SOLID187 with 4) and short lines mean trailing zeros.
    fn solid_record(
        &mut self,
        no: usize,
        cols: &[Column],
        cur: &mut Cursor<'_>,
    ) -> Result<(), ImportError> {
        let f = &self.fields;
        if f.len() < 11 {
            return Err(self.err(
                no,
                "the 11 leading fields of a SOLID EBLOCK record (material, type, real, section, \
                 system, birth/death, entity, shape, node count, unused, element number)",
                format!("{} fields", f.len()),
            ));
        }
        let (itype, count, id) = (f[1], f[8], f[10]);
        let first_cap = cols.len().saturating_sub(11);
        let max = first_cap + cols.len();
        let count = match usize::try_from(count) {
            Ok(c) if c <= max => c,
            _ => {
                return Err(self.err(
                    no,
                    format!("a node count between 0 and {max} in field 9"),
                    count.to_string(),
                ))
            }
        };
        let on_first = f.len() - 11;
        if on_first > count {
            return Err(self.err(
                no,
                format!("{count} node numbers after the 11 leading fields, as field 9 says"),
                format!("{on_first}"),
            ));
        }
        let mut raw = std::mem::take(&mut self.raw);
        raw.clear();
        for &v in &f[11..] {
            raw.push(self.node_ref(no, v)?);
        }
        if count > first_cap {
            raw.resize(first_cap, 0);
            let cno = self.continuation(cur, cols, || {
                format!(
                    "the continuation line with nodes {}-{count} of element {id}",
                    first_cap + 1
                )
            })?;
            let rest = count - first_cap;
            if self.fields.len() > rest {
                return Err(self.err(
                    cno,
                    format!("{rest} node numbers on the continuation line of element {id} (field 9 says {count} nodes)"),
                    format!("{}", self.fields.len()),
                ));
            }
            for &v in &self.fields {
                raw.push(self.node_ref(cno, v)?);
            }
        }
        raw.resize(count, 0);
        let r = self.add_element(Some(itype), id, &raw, no);
        self.raw = raw;
        r
    }

    /// Non-SOLID layout (Workbench SURF154/CONTA174 blocks): element number, type, real,
    /// material, coordinate system, then nodes. There is no node count, so a full first line
    /// continues only for hex-family types, whose records then hold 20 nodes.
    fn plain_record(
        &mut self,
        no: usize,
        cols: &[Column],
        cur: &mut Cursor<'_>,
    ) -> Result<(), ImportError> {
        let f = &self.fields;
        if f.len() < 6 {
            return Err(self.err(
                no,
                "an EBLOCK record of element number, type, real constant, material, coordinate \
                 system and at least one node",
                format!("{} fields", f.len()),
            ));
        }
        let (id, itype) = (f[0], f[1]);
        let full = f.len() == cols.len();
        let mut raw = std::mem::take(&mut self.raw);
        raw.clear();
        for &v in &f[5..] {
            raw.push(self.node_ref(no, v)?);
        }
        let continues = full && self.class_of_type(itype) == Some(Class::Hex);
        if continues {
            let cno = self.continuation(cur, cols, || {
                format!("the continuation line with the remaining nodes of element {id}")
            })?;
            for &v in &self.fields {
                raw.push(self.node_ref(cno, v)?);
            }
        }
        let r = self.add_element(Some(itype), id, &raw, no);
        self.raw = raw;
        r
    }

    /// COMPACT layout: element number then nodes, the type from the last `TYPE` command. A
    /// record longer than one line continues while lines are full.
    fn compact_record(
        &mut self,
        no: usize,
        cols: &[Column],
        record_len: Option<usize>,
        cur: &mut Cursor<'_>,
    ) -> Result<(), ImportError> {
        let Some(&id) = self.fields.first() else {
            return Ok(());
        };
        let mut raw = std::mem::take(&mut self.raw);
        raw.clear();
        let mut line_no = no;
        let mut start = 1;
        loop {
            for &v in &self.fields[start..] {
                raw.push(self.node_ref(line_no, v)?);
            }
            let full = self.fields.len() == cols.len();
            match record_len {
                Some(len) if full && raw.len() + 1 < len => {
                    line_no = self.continuation(cur, cols, || {
                        format!("the continuation line of element {id} ({len} fields per record)")
                    })?;
                    start = 0;
                }
                _ => break,
            }
        }
        if let Some(len) = record_len {
            raw.truncate(len - 1);
        }
        let r = self.add_element(self.current_type, id, &raw, no);
        self.raw = raw;
        r
    }

    /// `(element number, KEYOPT(1))` of a type, if an ET or ETBLOCK defines it.
    fn type_info(&mut self, itype: i64) -> Option<(i64, i64)> {
        if let Some((t, info)) = self.type_cache {
            if t == itype {
                return info;
            }
        }
        let info = self
            .types
            .get(&itype)
            .map(|&ename| (ename, self.keyopt1.get(&itype).copied().unwrap_or(0)));
        self.type_cache = Some((itype, info));
        info
    }

    /// Records a type definition (ET, ETBLOCK) or a KEYOPT(1) change.
    fn define_type(&mut self, itype: i64, ename: Option<i64>, keyopt1: i64) {
        if let Some(ename) = ename {
            self.types.insert(itype, ename);
        }
        self.keyopt1.insert(itype, keyopt1);
        self.type_cache = None;
    }

    fn class_of_type(&mut self, itype: i64) -> Option<Class> {
        let (ename, k1) = self.type_info(itype)?;
        Some(elements::class_of(ename, k1))
    }

    fn skip(&mut self, itype: Option<i64>, ename: Option<i64>, reason: SkipReason) {
        match self
            .skipped
            .iter_mut()
            .find(|s| s.itype == itype && s.ename == ename && s.reason == reason)
        {
            Some(s) => s.count += 1,
            None => self.skipped.push(Skipped {
                itype,
                ename,
                reason,
                count: 1,
            }),
        }
    }

    /// Classifies a record and stores it if it is a 3D solid (file node numbers, resolved in
    /// [`Reader::finish`]).
    fn add_element(
        &mut self,
        itype: Option<i64>,
        id: i64,
        raw: &[u32],
        no: usize,
    ) -> Result<(), ImportError> {
        if id < 1 {
            return Err(self.err(no, "a positive element number", id.to_string()));
        }
        let Some(itype) = itype else {
            self.skip(None, None, SkipReason::NoType);
            return Ok(());
        };
        let Some((ename, keyopt1)) = self.type_info(itype) else {
            self.skip(Some(itype), None, SkipReason::NoType);
            return Ok(());
        };
        let built = match elements::class_of(ename, keyopt1) {
            Class::Hex => elements::build_hex(raw),
            Class::Tet => elements::build_tet(raw),
            Class::NotSolid => {
                self.skip(Some(itype), Some(ename), SkipReason::NotSolid { keyopt1 });
                return Ok(());
            }
        };
        match built {
            Built::Solid {
                kind,
                nodes,
                len,
                missing_midside,
            } => {
                self.mesh.push_element(id as u64, kind, &nodes[..len]);
                self.element_lines.push(lineno(no));
                self.missing_midside += usize::from(missing_midside);
                Ok(())
            }
            Built::TooFewNodes { need } => Err(self.err(
                no,
                format!(
                    "at least {need} nodes for {} element {id} (type {itype})",
                    type_name(ename)
                ),
                format!("{} nodes", raw.len()),
            )),
            Built::MissingCorner { corner } => Err(self.err(
                no,
                format!(
                    "a node number for corner {} of {} element {id}",
                    corner + 1,
                    type_name(ename)
                ),
                "node number 0",
            )),
            Built::BadCollapse => {
                self.skip(Some(itype), Some(ename), SkipReason::BadCollapse);
                Ok(())
            }
        }
    }

    /// ETBLOCK (MAPDL 2023 R1+): records `itype, element number, KEYOPT(1), ...` until `-1`
    /// (FORMATS.md §1.2).
    fn etblock(&mut self, cur: &mut Cursor<'_>) -> Result<(), ImportError> {
        let (fno, fmt) = self.format_line(cur, "ETBLOCK", "(2i9,19a9)")?;
        let cols = &fmt.columns;
        if cols.len() < 2 {
            return Err(self.err(
                fno,
                "an ETBLOCK format with at least two columns, such as '(2i9,19a9)'",
                "one column",
            ));
        }
        let mut warned_unaligned = false;
        loop {
            let Some((no, line)) = cur.peek() else {
                return Ok(());
            };
            match row(line) {
                Row::Blank | Row::Comment => {
                    cur.next();
                    continue;
                }
                Row::End => return Ok(()),
                Row::Data => {}
            }
            cur.next();
            // Some writers (mapdl-archive's `use_etblock`) separate the integers by single
            // blanks under a `(2i9,...)` format line. Integers cannot run together the way
            // NBLOCK's reals do, so a row whose columns fail but whose blank-separated tokens
            // are all integers is read by its tokens.
            let in_columns = (0..2).all(|k| int_field(cols[k].slice(line)).is_some());
            if !in_columns {
                let tokens: Option<Vec<i64>> = line
                    .split(|b| b.is_ascii_whitespace() || *b == b',')
                    .filter(|t| !t.is_empty())
                    .map(int_trimmed)
                    .collect();
                if let Some(t) = tokens.filter(|t| t.len() >= 2) {
                    if !warned_unaligned {
                        warned_unaligned = true;
                        self.warnings.push(format!(
                            "line {no}: ETBLOCK rows are not in the columns of their format \
                             (line {fno}); read as blank-separated integers"
                        ));
                    }
                    self.define_type(t[0], Some(t[1]), t.get(2).copied().unwrap_or(0));
                    continue;
                }
            }
            let int_at = |k: usize| -> Result<i64, ImportError> {
                let f = cols[k].slice(line);
                int_field(f).ok_or_else(|| {
                    self.err(
                        no,
                        format!(
                            "{} in {}",
                            ["an element type number", "an element number"][k],
                            cols[k].describe()
                        ),
                        found_field(f),
                    )
                })
            };
            let itype = int_at(0)?;
            let ename = int_at(1)?;
            let k1 = cols
                .get(2)
                .and_then(|c| int_field(c.slice(line)))
                .unwrap_or(0);
            self.define_type(itype, Some(ename), k1);
        }
    }

    /// CMBLOCK,Cname,Entity,NUMITEMS: NUMITEMS integers follow, a negative one ending a range
    /// that starts after the previous item (FORMATS.md §1.5). Lines may begin with `-`, so the
    /// block is read by its count, not up to a terminator.
    fn cmblock(
        &mut self,
        no: usize,
        args: &[&[u8]],
        cur: &mut Cursor<'_>,
    ) -> Result<(), ImportError> {
        let name_field = args.first().copied().unwrap_or(b"");
        if name_field.is_empty() {
            return Err(self.err(
                no,
                "a component name (CMBLOCK,Cname,Entity,NUMITEMS)",
                "none",
            ));
        }
        let name = String::from_utf8_lossy(name_field).into_owned();
        let entity_field = args.get(1).copied().unwrap_or(b"");
        let upper = entity_field.to_ascii_uppercase();
        let entity = if upper == b"NODE" {
            Some(Entity::Node)
        } else if upper.starts_with(b"ELEM") {
            Some(Entity::Element)
        } else {
            None
        };
        let count_field = args.get(2).copied().unwrap_or(b"");
        let Some(total) = parse_int(count_field).and_then(|v| u64::try_from(v).ok()) else {
            return Err(self.err(
                no,
                "an item count NUMITEMS (CMBLOCK,Cname,Entity,NUMITEMS)",
                if count_field.is_empty() {
                    "none".to_string()
                } else {
                    describe_found(count_field)
                },
            ));
        };
        let (fno, fmt) = self.format_line(cur, "CMBLOCK", "(8i10)")?;
        if !fmt.all_int() {
            return Err(self.err(
                fno,
                "a CMBLOCK format of integer columns, such as '(8i10)'",
                "a format with other columns",
            ));
        }
        let mut intervals: Vec<(u64, u64)> = Vec::new();
        let mut got = 0u64;
        let mut f = std::mem::take(&mut self.fields);
        let result = (|| {
            let expected = |got: u64| {
                format!(
                    "{} more items of component {name} (NUMITEMS = {total})",
                    total - got
                )
            };
            while got < total {
                let Some((lno, line)) = cur.peek() else {
                    return Err(self.err(cur.eof_line(), expected(got), "end of file"));
                };
                match row(line) {
                    Row::Blank | Row::Comment => {
                        cur.next();
                        continue;
                    }
                    Row::End if line.trim_ascii_start().first() != Some(&b'-') => {
                        return Err(self.err(lno, expected(got), describe_found(line)));
                    }
                    _ => {}
                }
                cur.next();
                self.int_fields(lno, line, &fmt.columns, &mut f)?;
                for &v in f.iter() {
                    if got == total {
                        return Err(self.err(
                            lno,
                            format!("{total} items in component {name}, as NUMITEMS says"),
                            "more items on this line",
                        ));
                    }
                    got += 1;
                    if v > 0 {
                        intervals.push((v as u64, v as u64));
                    } else if v < 0 {
                        let end = v.unsigned_abs();
                        match intervals.last_mut() {
                            Some(last) if end > last.1 => last.1 = end,
                            Some(last) => {
                                return Err(self.err(
                                    lno,
                                    format!(
                                        "a range end above {} (a negative item ends a range that \
                                         starts after the previous item)",
                                        last.1
                                    ),
                                    v.to_string(),
                                ))
                            }
                            None => {
                                return Err(self.err(
                                    lno,
                                    "a positive item before a negative (range) item",
                                    v.to_string(),
                                ))
                            }
                        }
                    } else {
                        return Err(self.err(lno, "a non-zero component item", "0"));
                    }
                }
            }
            Ok(())
        })();
        self.fields = f;
        result?;
        match entity {
            Some(entity) => self.components.push(Component {
                name: name.trim().to_string(),
                entity,
                intervals,
            }),
            None => self.warnings.push(format!(
                "line {no}: component {} of entity {} ignored: only NODE and ELEM components \
                 are read",
                name.trim(),
                String::from_utf8_lossy(entity_field)
            )),
        }
        Ok(())
    }

    /// Resolves file node numbers, builds the sets and the warnings.
    fn finish(mut self) -> Result<Mesh, ImportError> {
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

/// Dense indices of the ids in `intervals`, sorted and unique, and how many ids the intervals
/// name. Intervals are merged first; long ones are walked through a sorted id list, so neither
/// time nor memory depends on the size of a range in the file.
fn members(
    mut intervals: Vec<(u64, u64)>,
    index: &NodeIndex,
    ids: &[u64],
    sorted: &mut Option<Vec<(u64, u32)>>,
) -> (Vec<u32>, u128) {
    intervals.sort_unstable();
    let mut merged: Vec<(u64, u64)> = Vec::with_capacity(intervals.len());
    for (a, b) in intervals {
        match merged.last_mut() {
            Some(last) if a <= last.1.saturating_add(1) => last.1 = last.1.max(b),
            _ => merged.push((a, b)),
        }
    }
    let mut out = Vec::new();
    let mut declared = 0u128;
    for (a, b) in merged {
        declared += u128::from(b - a) + 1;
        if b - a < 64 {
            out.extend((a..=b).filter_map(|id| index.get(id)));
        } else {
            let s = sorted.get_or_insert_with(|| {
                let mut v: Vec<(u64, u32)> = ids
                    .iter()
                    .enumerate()
                    .map(|(i, &id)| (id, i as u32))
                    .collect();
                v.sort_unstable();
                v
            });
            let lo = s.partition_point(|&(id, _)| id < a);
            out.extend(
                s[lo..]
                    .iter()
                    .take_while(|&&(id, _)| id <= b)
                    .map(|&(_, i)| i),
            );
        }
    }
    out.sort_unstable();
    out.dedup();
    (out, declared)
}
