//! Block data records: what a line inside a block is, the block's format line, and the
//! conversion of the fields sliced from a record (integers, Fortran reals).

use super::format::{Column, Format};
use super::{Cursor, Reader};
use crate::error::{describe_found, ImportError};
use crate::text::{parse_int, parse_real};

/// What a line inside a block is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Row {
    Blank,
    Comment,
    /// First non-blank character `-` or a letter (or `/`, `*`): the block terminator
    /// (`N,R5.3,LOC,-1`, `-1`) or the next command (FORMATS.md §1.3, §1.4).
    End,
    Data,
}

pub(super) fn row(line: &[u8]) -> Row {
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
pub(super) fn int_field(field: &[u8]) -> Option<i64> {
    int_trimmed(field.trim_ascii())
}

/// [`int_field`] on a field already trimmed.
#[inline]
pub(super) fn int_trimmed(t: &[u8]) -> Option<i64> {
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
pub(super) fn found_field(field: &[u8]) -> String {
    if field.trim_ascii().is_empty() {
        "a blank field".to_string()
    } else {
        describe_found(field)
    }
}

/// A real as Fortran writes it: `E`/`e`/`D` exponents and plain decimals ([`parse_real`]), and
/// the exponent without a letter that `Ew.d` gives for |exp| > 99 (`1.0000000000000-100`,
/// FORMATS.md §1.8 item 2).
pub(super) fn parse_fortran_real(field: &[u8]) -> Option<f64> {
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

impl Reader<'_> {
    /// Skips lines up to the block's format line and parses it.
    pub(super) fn format_line(
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

    /// Slices an integer record into `out` (reused buffer). Fields are trimmed (HyperMesh
    /// writes `'      0 '`, FORMATS.md §1.4); trailing blank fields end the record (MAPDL omits
    /// trailing zeros); a blank field before a non-blank one is an error.
    pub(super) fn int_fields(
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
}
