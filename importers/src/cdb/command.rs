//! APDL command lines: comments, `$`-joined statements, abbreviated case-insensitive names,
//! comma-separated arguments and `*SET` parameters (FORMATS.md §1.1, §1.2).

use std::collections::HashMap;

use nom::bytes::complete::take_till;
use nom::character::complete::char;
use nom::multi::many0;
use nom::sequence::preceded;
use nom::{IResult, Parser};

use crate::text::{parse_int, parse_real};

/// The part of a line before its comment: `!` starts a comment outside single quotes
/// (`CMBLOCK,ECOMP1  ,ELEM,       4  ! users element component definition`).
pub(crate) fn strip_comment(line: &[u8]) -> &[u8] {
    let mut quoted = false;
    for (i, &b) in line.iter().enumerate() {
        match b {
            b'\'' => quoted = !quoted,
            b'!' if !quoted => return &line[..i],
            _ => {}
        }
    }
    line
}

/// The statements of a line: `$` separates commands (`TYPE, 1  $ MAT, 1  $ REAL, 1`,
/// FORMATS.md §1.1). Comments are removed first.
pub(crate) fn statements(line: &[u8]) -> impl Iterator<Item = &[u8]> + '_ {
    let mut rest = Some(strip_comment(line));
    std::iter::from_fn(move || {
        let s = rest?;
        let mut quoted = false;
        for (i, &b) in s.iter().enumerate() {
            match b {
                b'\'' => quoted = !quoted,
                b'$' if !quoted => {
                    rest = Some(&s[i + 1..]);
                    return Some(&s[..i]);
                }
                _ => {}
            }
        }
        rest = None;
        Some(s)
    })
}

/// The command name of a statement: the text before the first comma, trimmed.
pub(crate) fn name(statement: &[u8]) -> &[u8] {
    let end = memchr::memchr(b',', statement).unwrap_or(statement.len());
    statement[..end].trim_ascii()
}

/// The commands the reader acts on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Command {
    Nblock,
    Eblock,
    Cmblock,
    Etblock,
    Et,
    Keyopt,
    Type,
    Set,
}

/// Recognises a command name. APDL accepts abbreviations down to four characters and any case
/// (Workbench writes `keyo`, `nblock`); mapdl-archive compares the first 5-6 characters. So a
/// name matches when it is a case-insensitive prefix of the full name at least four characters
/// long; the short names `ET`, `TYPE` and `*SET` must match exactly (`ETCON` is not `ET`).
pub(crate) fn command(name: &[u8]) -> Option<Command> {
    const TABLE: [(&[u8], usize, Command); 8] = [
        (b"NBLOCK", 4, Command::Nblock),
        (b"EBLOCK", 4, Command::Eblock),
        (b"CMBLOCK", 4, Command::Cmblock),
        (b"ETBLOCK", 4, Command::Etblock),
        (b"KEYOPT", 4, Command::Keyopt),
        (b"ET", 2, Command::Et),
        (b"TYPE", 4, Command::Type),
        (b"*SET", 4, Command::Set),
    ];
    TABLE.iter().find_map(|&(full, min, cmd)| {
        (name.len() >= min
            && name.len() <= full.len()
            && name.eq_ignore_ascii_case(&full[..name.len()]))
        .then_some(cmd)
    })
}

/// The arguments of a statement after its name, each trimmed: `ET,        1,186` gives
/// `["1", "186"]`. Only called for the few commands the reader acts on.
pub(crate) fn arguments(statement: &[u8]) -> Vec<&[u8]> {
    fn args(input: &[u8]) -> IResult<&[u8], Vec<&[u8]>> {
        let (input, _name) = take_till(|c| c == b',')(input)?;
        many0(preceded(char(','), take_till(|c| c == b','))).parse(input)
    }
    match args(statement) {
        Ok((_, v)) => v.into_iter().map(<[u8]>::trim_ascii).collect(),
        Err(_) => Vec::new(),
    }
}

/// APDL scalar parameters from `*SET,NAME,VALUE` and `NAME = VALUE`, so that type numbers
/// given through parameters resolve (`*set,cid,3` then `et,cid,174`, FORMATS.md §1.2).
#[derive(Default, Debug)]
pub(crate) struct Parameters {
    values: HashMap<Vec<u8>, f64>,
}

impl Parameters {
    /// `*SET,NAME,VALUE`; a missing or non-numeric value (a string) deletes the parameter.
    pub fn set(&mut self, name: &[u8], value: Option<&[u8]>) {
        let key = name.trim_ascii().to_ascii_uppercase();
        if key.is_empty() {
            return;
        }
        match value.and_then(|v| self.number(v)) {
            Some(v) => {
                self.values.insert(key, v);
            }
            None => {
                self.values.remove(&key);
            }
        }
    }

    /// `NAME = VALUE` statements; returns false if the statement is not an assignment.
    pub fn assignment(&mut self, statement: &[u8]) -> bool {
        let Some(eq) = memchr::memchr(b'=', statement) else {
            return false;
        };
        let lhs = statement[..eq].trim_ascii();
        let ident = lhs
            .first()
            .is_some_and(|c| c.is_ascii_alphabetic() || *c == b'_')
            && lhs.iter().all(|c| c.is_ascii_alphanumeric() || *c == b'_');
        if !ident {
            return false;
        }
        let rhs = statement[eq + 1..].trim_ascii();
        self.set(lhs, Some(rhs));
        true
    }

    /// A number written literally or through a parameter.
    pub fn number(&self, field: &[u8]) -> Option<f64> {
        let f = field.trim_ascii();
        if f.is_empty() {
            return None;
        }
        if let Some(v) = parse_real(f) {
            return Some(v);
        }
        self.values.get(&f.to_ascii_uppercase()).copied()
    }

    /// An integer written literally (`3`, `3.`, `3.0`) or through a parameter.
    pub fn integer(&self, field: &[u8]) -> Option<i64> {
        if let Some(v) = parse_int(field) {
            return Some(v);
        }
        let v = self.number(field)?;
        (v.fract() == 0.0 && v.abs() < 9.0e15).then_some(v as i64)
    }
}

/// The element number of an `ET` or `ETBLOCK` name field: `186`, a parameter, or a name such as
/// `SOLID186` (the number after the letters, which is unique across element families).
pub(crate) fn element_number(params: &Parameters, field: &[u8]) -> Option<i64> {
    if let Some(v) = params.integer(field) {
        return Some(v);
    }
    let f = field.trim_ascii();
    let letters = f.iter().take_while(|c| c.is_ascii_alphabetic()).count();
    let digits = &f[letters..];
    if letters == 0 || digits.is_empty() || !digits.iter().all(u8::is_ascii_digit) {
        return None;
    }
    parse_int(digits)
}
