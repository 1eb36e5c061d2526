//! Element types: `ET`, `ETBLOCK` and KEYOPT(1), the table from a type number to its element
//! number and shape option that EBLOCK records are classified by.

use super::command;
use super::elements::{self, Class};
use super::records::{found_field, int_field, int_trimmed, row, Row};
use super::{Cursor, Reader};
use crate::error::{describe_found, ImportError};

impl Reader<'_> {
    /// `ET,ITYPE,Ename[,KOP1,...]`; Ename may be `186`, `SOLID186` or a parameter, and ITYPE a
    /// parameter (`et,cid,174`, FORMATS.md §1.2). Redefining a type resets its KEYOPT(1).
    pub(super) fn et(&mut self, no: usize, args: &[&[u8]]) {
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

    /// `(element number, KEYOPT(1))` of a type, if an ET or ETBLOCK defines it.
    pub(super) fn type_info(&mut self, itype: i64) -> Option<(i64, i64)> {
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
    pub(super) fn define_type(&mut self, itype: i64, ename: Option<i64>, keyopt1: i64) {
        if let Some(ename) = ename {
            self.types.insert(itype, ename);
        }
        self.keyopt1.insert(itype, keyopt1);
        self.type_cache = None;
    }

    pub(super) fn class_of_type(&mut self, itype: i64) -> Option<Class> {
        let (ename, k1) = self.type_info(itype)?;
        Some(elements::class_of(ename, k1))
    }

    /// ETBLOCK (MAPDL 2023 R1+): records `itype, element number, KEYOPT(1), ...` until `-1`
    /// (FORMATS.md §1.2).
    pub(super) fn etblock(&mut self, cur: &mut Cursor<'_>) -> Result<(), ImportError> {
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
}
