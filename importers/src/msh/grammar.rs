//! The MSH grammar as nom 8 `complete` parsers: section headers and `$End` lines, the
//! `$MeshFormat` line, `$PhysicalNames` lines with quoted names, `$Entities` and
//! `$PartitionedEntities`, counts and block headers.
//!
//! Every parser takes a suffix of the whole file, so the offset of an error is
//! `file.len() - error.input.len()`. Errors carry the innermost `context` as "what was expected".
//! The number primitives ([`size_t`], [`int`], [`real`]) read either an ASCII token or a raw
//! binary value, so one grammar serves both encodings of MSH 4.1.

use std::collections::HashMap;

use nom::bytes::complete::{tag, take_till, take_till1, take_while1};
use nom::character::complete::{char, digit1, multispace0, space0};
use nom::error::{context, ContextError, ErrorKind, ParseError};
use nom::number::Endianness;
use nom::{IResult, Parser};

use super::num::{is_ws, parse_f64, parse_i64, parse_u64};

/// How the numbers of a section are encoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Enc {
    /// Whitespace-separated ASCII tokens.
    Ascii,
    /// Raw values: `int` is 4 bytes, `double` 8, `size_t` 8 bytes when `wide` else 4.
    Binary { big: bool, wide: bool },
}

impl Enc {
    pub(crate) fn is_binary(self) -> bool {
        matches!(self, Enc::Binary { .. })
    }
}

/// A parse error: where (the rest of the input) and the innermost context.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PErr<'a> {
    pub input: &'a [u8],
    pub expected: Option<&'static str>,
}

impl<'a> ParseError<&'a [u8]> for PErr<'a> {
    fn from_error_kind(input: &'a [u8], _kind: ErrorKind) -> Self {
        PErr {
            input,
            expected: None,
        }
    }

    fn append(_input: &'a [u8], _kind: ErrorKind, other: Self) -> Self {
        other
    }
}

impl<'a> ContextError<&'a [u8]> for PErr<'a> {
    fn add_context(_input: &'a [u8], ctx: &'static str, mut other: Self) -> Self {
        if other.expected.is_none() {
            other.expected = Some(ctx);
        }
        other
    }
}

pub(crate) type PResult<'a, O> = IResult<&'a [u8], O, PErr<'a>>;

fn reject<O>(input: &[u8]) -> PResult<'_, O> {
    Err(nom::Err::Error(PErr {
        input,
        expected: None,
    }))
}

fn endian(big: bool) -> Endianness {
    if big {
        Endianness::Big
    } else {
        Endianness::Little
    }
}

/// One ASCII token (after optional whitespace), up to whitespace or the end.
fn token(i: &[u8]) -> PResult<'_, &[u8]> {
    let (i, _) = multispace0(i)?;
    take_till1(is_ws)(i)
}

/// An ASCII token converted by `conv`; a token that does not convert is an error located at
/// the token (inputs are always suffixes of the file, so errors are too).
fn converted<T>(i: &[u8], conv: fn(&[u8]) -> Option<T>) -> PResult<'_, T> {
    let (i, _) = multispace0(i)?;
    let (r, t) = take_till1(is_ws)(i)?;
    match conv(t) {
        Some(v) => Ok((r, v)),
        None => reject(i),
    }
}

fn ascii_u64(i: &[u8]) -> PResult<'_, u64> {
    converted(i, parse_u64)
}

fn ascii_i64(i: &[u8]) -> PResult<'_, i64> {
    converted(i, parse_i64)
}

fn ascii_f64(i: &[u8]) -> PResult<'_, f64> {
    converted(i, parse_f64)
}

/// A `size_t` field: an unsigned ASCII integer, or `data-size` raw bytes.
pub(crate) fn size_t<'a>(
    enc: Enc,
    what: &'static str,
) -> impl Parser<&'a [u8], Output = u64, Error = PErr<'a>> {
    context(what, move |i: &'a [u8]| -> PResult<'a, u64> {
        match enc {
            Enc::Ascii => ascii_u64(i),
            Enc::Binary { big, wide: true } => nom::number::complete::u64(endian(big))(i),
            Enc::Binary { big, wide: false } => {
                let (r, v) = nom::number::complete::u32(endian(big))(i)?;
                Ok((r, u64::from(v)))
            }
        }
    })
}

/// An `int` field: a signed ASCII integer, or a raw 4-byte integer.
pub(crate) fn int<'a>(
    enc: Enc,
    what: &'static str,
) -> impl Parser<&'a [u8], Output = i64, Error = PErr<'a>> {
    context(what, move |i: &'a [u8]| -> PResult<'a, i64> {
        match enc {
            Enc::Ascii => ascii_i64(i),
            Enc::Binary { big, .. } => {
                let (r, v) = nom::number::complete::i32(endian(big))(i)?;
                Ok((r, i64::from(v)))
            }
        }
    })
}

/// A `double` field: a finite ASCII real, or 8 raw bytes holding a finite double.
pub(crate) fn real<'a>(
    enc: Enc,
    what: &'static str,
) -> impl Parser<&'a [u8], Output = f64, Error = PErr<'a>> {
    context(what, move |i: &'a [u8]| -> PResult<'a, f64> {
        match enc {
            Enc::Ascii => ascii_f64(i),
            Enc::Binary { big, .. } => {
                let (r, v) = nom::number::complete::f64(endian(big))(i)?;
                if v.is_finite() {
                    Ok((r, v))
                } else {
                    reject(i)
                }
            }
        }
    })
}

/// Blanks, an optional `\r`, then a newline or the end of the input.
fn line_end(i: &[u8]) -> PResult<'_, ()> {
    let (i, _) = space0(i)?;
    let i = i.strip_prefix(b"\r").unwrap_or(i);
    if i.is_empty() {
        return Ok((i, ()));
    }
    let (i, _) = char('\n')(i)?;
    Ok((i, ()))
}

/// A section header line `$Name`; returns the name. Leading whitespace is skipped.
pub(crate) fn section_header(i: &[u8]) -> PResult<'_, &[u8]> {
    let (i, _) = multispace0(i)?;
    let (i, _) = context("a section header such as $MeshFormat", char('$')).parse_complete(i)?;
    let (i, name) = context(
        "a section name after '$'",
        take_while1(|c: u8| c.is_ascii_alphanumeric() || c == b'_'),
    )
    .parse_complete(i)?;
    let (i, _) = context("the end of the section header line", line_end).parse_complete(i)?;
    Ok((i, name))
}

/// The `$EndName` line closing a section (after optional whitespace).
pub(crate) fn end_line<'a>(name: &'a [u8]) -> impl FnMut(&'a [u8]) -> PResult<'a, ()> {
    move |i: &'a [u8]| {
        let (i, _) = multispace0(i)?;
        let start = i;
        let (i, _) = tag(&b"$End"[..])(i)?;
        let (i, _) = tag(name)(i)?;
        if i.first().is_some_and(|&b| !is_ws(b)) {
            return reject(start);
        }
        let (i, _) = line_end(i)?;
        Ok((i, ()))
    }
}

/// The `$MeshFormat` line: version text, file type, data size.
pub(crate) fn mesh_format(i: &[u8]) -> PResult<'_, (&[u8], u64, u64)> {
    let (i, version) = context("a format version such as 4.1 or 2.2", token).parse_complete(i)?;
    let (i, file_type) =
        context("a file type (0 for ASCII, 1 for binary)", ascii_u64).parse_complete(i)?;
    let (i, data_size) = context("a data size (8)", ascii_u64).parse_complete(i)?;
    let (i, _) = context("the end of the $MeshFormat line", line_end).parse_complete(i)?;
    Ok((i, (version, file_type, data_size)))
}

/// A count alone on its line (MSH 2 binary files: raw data starts after the newline).
pub(crate) fn count_line<'a>(what: &'static str) -> impl FnMut(&'a [u8]) -> PResult<'a, u64> {
    move |i: &'a [u8]| {
        let (i, _) = multispace0(i)?;
        let start = i;
        let (i, digits) = context(what, digit1).parse_complete(i)?;
        let Some(v) = parse_u64(digits) else {
            return Err(nom::Err::Error(PErr {
                input: start,
                expected: Some(what),
            }));
        };
        let (i, _) = context("the end of the line after the count", line_end).parse_complete(i)?;
        Ok((i, v))
    }
}

/// A name in double quotes, or (leniently) a bare token.
fn name(i: &[u8]) -> PResult<'_, &[u8]> {
    if let Some(r) = i.strip_prefix(b"\"") {
        let (r, n) = take_till(|c| c == b'"' || c == b'\n')(r)?;
        let (r, _) = context("the closing '\"' of the name", char('"')).parse_complete(r)?;
        Ok((r, n))
    } else {
        take_till1(is_ws)(i)
    }
}

/// One `$PhysicalNames` line: `dimension tag "name"`.
pub(crate) fn physical_name(i: &[u8]) -> PResult<'_, (u8, i64, &[u8])> {
    let (i, _) = multispace0(i)?;
    let start = i;
    let (i, dim) = context("a physical group dimension (0 to 3)", ascii_i64).parse_complete(i)?;
    if !(0..=3).contains(&dim) {
        return Err(nom::Err::Error(PErr {
            input: start,
            expected: Some("a physical group dimension (0 to 3)"),
        }));
    }
    let (i, tag) = context("a physical tag", ascii_i64).parse_complete(i)?;
    let (i, _) = space0(i)?;
    let (i, n) = context("a physical name in double quotes", name).parse_complete(i)?;
    let (i, _) = context("the end of the $PhysicalNames line", line_end).parse_complete(i)?;
    Ok((i, (dim as u8, tag, n)))
}

/// Physical tags of each entity `(dim, tag)` from `$Entities` (MSH 4.1).
pub(crate) type EntityPhysicals = HashMap<(u8, i64), Vec<i64>>;

/// A partition entity of `$PartitionedEntities`: its parent and physical tags.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct PartEntity {
    pub parent: (u8, i64),
    pub physicals: Vec<i64>,
}

fn skip_count<'a, P>(i: &'a [u8], n: u64, mut p: P) -> PResult<'a, ()>
where
    P: Parser<&'a [u8], Output = i64, Error = PErr<'a>>,
{
    let mut i = i;
    for _ in 0..n {
        let (r, _) = p.parse_complete(i)?;
        i = r;
    }
    Ok((i, ()))
}

fn collect_count<'a, P>(i: &'a [u8], n: u64, mut p: P) -> PResult<'a, Vec<i64>>
where
    P: Parser<&'a [u8], Output = i64, Error = PErr<'a>>,
{
    let mut i = i;
    let mut out = Vec::new();
    for _ in 0..n {
        let (r, v) = p.parse_complete(i)?;
        out.push(v);
        i = r;
    }
    Ok((i, out))
}

fn entity_dim_counts(enc: Enc, i: &[u8]) -> PResult<'_, [u64; 4]> {
    let (i, (p, c, s, v)) = (
        size_t(enc, "the number of point entities"),
        size_t(enc, "the number of curve entities"),
        size_t(enc, "the number of surface entities"),
        size_t(enc, "the number of volume entities"),
    )
        .parse_complete(i)?;
    Ok((i, [p, c, s, v]))
}

/// Coordinates (3 for points, a bounding box of 6 otherwise), the physical tags, and for
/// curves and up the signed bounding entity tags.
fn entity_tail(enc: Enc, dim: u8, i: &[u8]) -> PResult<'_, Vec<i64>> {
    let what = if dim == 0 {
        "a point entity coordinate"
    } else {
        "an entity bounding box coordinate"
    };
    let mut i = i;
    for _ in 0..if dim == 0 { 3 } else { 6 } {
        let (r, _) = real(enc, what).parse_complete(i)?;
        i = r;
    }
    let (i, np) = size_t(enc, "the number of physical tags of the entity").parse_complete(i)?;
    let (i, mut phys) = collect_count(i, np, int(enc, "a physical tag"))?;
    // A tag listed twice would add the entity's elements to its group twice per block.
    phys.sort_unstable();
    phys.dedup();
    let i = if dim > 0 {
        let (i, nb) =
            size_t(enc, "the number of bounding entities of the entity").parse_complete(i)?;
        skip_count(i, nb, int(enc, "a bounding entity tag"))?.0
    } else {
        i
    };
    Ok((i, phys))
}

/// The body of `$Entities` (MSH 4.1): physical tags per entity.
pub(crate) fn entities(enc: Enc, i: &[u8]) -> PResult<'_, EntityPhysicals> {
    let (mut i, counts) = entity_dim_counts(enc, i)?;
    let mut map = EntityPhysicals::new();
    for (dim, &n) in counts.iter().enumerate() {
        for _ in 0..n {
            let (r, tag) = int(enc, "an entity tag").parse_complete(i)?;
            let (r, phys) = entity_tail(enc, dim as u8, r)?;
            map.entry((dim as u8, tag)).or_insert(phys);
            i = r;
        }
    }
    Ok((i, map))
}

/// The body of `$PartitionedEntities` (MSH 4.1): parent and physical tags per partition entity.
pub(crate) fn partitioned_entities(
    enc: Enc,
    i: &[u8],
) -> PResult<'_, HashMap<(u8, i64), PartEntity>> {
    let (i, _) = size_t(enc, "the number of partitions").parse_complete(i)?;
    let (mut i, ghosts) = size_t(enc, "the number of ghost entities").parse_complete(i)?;
    for _ in 0..ghosts {
        let (r, _) = (
            int(enc, "a ghost entity tag"),
            int(enc, "a ghost entity partition"),
        )
            .parse_complete(i)?;
        i = r;
    }
    let (mut i, counts) = entity_dim_counts(enc, i)?;
    let mut map = HashMap::new();
    for (dim, &n) in counts.iter().enumerate() {
        for _ in 0..n {
            let (r, (tag, parent_dim, parent_tag, nparts)) = (
                int(enc, "a partition entity tag"),
                int(enc, "a parent entity dimension"),
                int(enc, "a parent entity tag"),
                size_t(enc, "the number of partitions of the entity"),
            )
                .parse_complete(i)?;
            let (r, _) = skip_count(r, nparts, int(enc, "a partition tag"))?;
            let (r, phys) = entity_tail(enc, dim as u8, r)?;
            map.entry((dim as u8, tag)).or_insert(PartEntity {
                parent: (parent_dim.clamp(0, 3) as u8, parent_tag),
                physicals: phys,
            });
            i = r;
        }
    }
    Ok((i, map))
}
