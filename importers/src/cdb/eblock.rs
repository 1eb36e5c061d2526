//! EBLOCK: element records in the SOLID, plain and COMPACT layouts, their continuation
//! lines, and the classification of each record into a stored solid or a skipped element.

use super::elements::{self, Built, Class};
use super::format::Column;
use super::records::{row, Row};
use super::{lineno, Cursor, Reader, MAX_NODE_ID};
use crate::error::{describe_found, ImportError};
use crate::text::parse_int;

/// Why elements were skipped; one warning per (type, reason).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum SkipReason {
    /// No ET/ETBLOCK defines the type (or no TYPE precedes a COMPACT block).
    NoType,
    /// Not a 3D solid.
    NotSolid { keyopt1: i64 },
    /// Repeated corners that form no hex, wedge, pyramid or tet.
    BadCollapse,
}

pub(super) struct Skipped {
    pub(super) itype: Option<i64>,
    pub(super) ename: Option<i64>,
    pub(super) reason: SkipReason,
    pub(super) count: usize,
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

/// `SOLID185`, or `element 999` for a number the reader does not know.
fn type_name(ename: i64) -> String {
    elements::element_name(ename).unwrap_or_else(|| format!("element {ename}"))
}

impl Reader<'_> {
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
    pub(super) fn eblock(
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
}
