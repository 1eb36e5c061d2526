//! Lexical layer of the INP reader, written with nom 8 `complete` parsers: keyword lines,
//! comma-separated data fields, labels and real numbers.
//!
//! Nothing here allocates per data line: [`Fields`] yields sub-slices of the line, and
//! [`label`] / [`real`] parse a field in place. Keyword lines (rare) are parsed into owned
//! strings.

use nom::branch::alt;
use nom::bytes::complete::take_till;
use nom::character::complete::{char, digit0, digit1, one_of, space0};
use nom::combinator::{all_consuming, map, opt, recognize};
use nom::multi::many0;
use nom::sequence::{delimited, preceded};
use nom::{IResult, Parser};

type Res<'a, O> = IResult<&'a [u8], O, nom::error::Error<&'a [u8]>>;

/// A parameter value as written: quoted values keep their blanks, plain values lose them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum RawValue<'a> {
    Quoted(&'a [u8]),
    Plain(&'a [u8]),
}

/// One `NAME[=value]` parameter of a keyword line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct Param {
    /// Upper case, blanks removed.
    pub name: String,
    /// As written (case kept); blanks removed unless the value was quoted.
    pub value: Option<String>,
}

/// A parsed keyword line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct Keyword {
    /// Upper case with blanks removed: `*End Part` gives `ENDPART`, `*NODE PRINT` `NODEPRINT`.
    pub name: String,
    pub params: Vec<Param>,
}

impl Keyword {
    /// The parameter `name` (upper case), if present.
    /// An abbreviation of three or more letters matches too (`TYP=` for `TYPE=`): Abaqus
    /// accepts unambiguous abbreviations (FORMATS.md §3.1).
    pub fn param(&self, name: &str) -> Option<&Param> {
        self.params.iter().find(|p| p.name == name).or_else(|| {
            self.params.iter().find(|p| {
                p.name.len() >= 3 && p.name.len() < name.len() && name.starts_with(&p.name)
            })
        })
    }

    /// The value of parameter `name`; `None` when absent or given without `=`.
    pub fn value(&self, name: &str) -> Option<&str> {
        self.param(name).and_then(|p| p.value.as_deref())
    }

    /// True when the parameter is present (with or without a value).
    pub fn flag(&self, name: &str) -> bool {
        self.param(name).is_some()
    }
}

fn is_blank(b: u8) -> bool {
    b == b' ' || b == b'\t'
}

/// Removes blanks (keyword lines ignore them) and converts to a `String`.
fn squeeze(s: &[u8], upper: bool) -> String {
    let kept: Vec<u8> = s
        .iter()
        .copied()
        .filter(|&b| !is_blank(b))
        .map(|b| if upper { b.to_ascii_uppercase() } else { b })
        .collect();
    String::from_utf8_lossy(&kept).into_owned()
}

fn quoted(i: &[u8]) -> Res<'_, &[u8]> {
    delimited(char('"'), take_till(|c| c == b'"'), char('"')).parse(i)
}

/// `= value`: a quoted string followed only by blanks, or plain text up to the next comma.
fn value(i: &[u8]) -> Res<'_, RawValue<'_>> {
    preceded(
        (char('='), space0),
        alt((
            map((quoted, space0), |(q, _)| RawValue::Quoted(q)),
            map(take_till(|c| c == b','), RawValue::Plain),
        )),
    )
    .parse(i)
}

/// `, NAME [= value]`.
fn param(i: &[u8]) -> Res<'_, RawParam<'_>> {
    preceded(
        char(','),
        (take_till(|c| c == b'=' || c == b','), opt(value)),
    )
    .parse(i)
}

/// `*NAME` followed by parameters, the whole line.
/// A parameter as written: its name and optional value.
type RawParam<'a> = (&'a [u8], Option<RawValue<'a>>);

fn keyword_line(i: &[u8]) -> Res<'_, (&[u8], Vec<RawParam<'_>>)> {
    all_consuming(preceded(
        char('*'),
        (take_till(|c| c == b','), many0(param)),
    ))
    .parse(i)
}

/// Parses a keyword line (leading blanks already removed, continuation lines joined).
/// On failure returns the byte offset where the line stops making sense and what was expected.
pub(super) fn keyword(line: &[u8]) -> Result<Keyword, (usize, &'static str)> {
    let (name, params) = match keyword_line(line) {
        Ok((_, v)) => v,
        Err(nom::Err::Error(e)) | Err(nom::Err::Failure(e)) => {
            let at = line.len() - e.input.len();
            // A quoted value whose closing quote is missing or followed by more text.
            return Err((at, "a keyword line '*NAME, PARAM=value, ...'"));
        }
        Err(nom::Err::Incomplete(_)) => return Err((line.len(), "a complete keyword line")),
    };
    let name_s = squeeze(name, true);
    if !name_s
        .as_bytes()
        .first()
        .is_some_and(u8::is_ascii_alphabetic)
    {
        return Err((1, "a keyword name after '*'"));
    }
    let mut out = Keyword {
        name: name_s,
        params: Vec::with_capacity(params.len()),
    };
    let mut offset = 1 + name.len();
    for (pname, pvalue) in params {
        let pname_s = squeeze(pname, true);
        let value = match pvalue {
            None => None,
            Some(RawValue::Quoted(q)) => Some(String::from_utf8_lossy(q).into_owned()),
            Some(RawValue::Plain(p)) => {
                if p.contains(&b'"') {
                    let at = offset + 1 + pname.len() + 1;
                    return Err((at, "a parameter value with matching double quotes"));
                }
                Some(squeeze(p, false))
            }
        };
        offset += 1 + pname.len();
        if pname_s.is_empty() {
            if value.is_some() {
                return Err((offset, "a parameter name before '='"));
            }
            // `*NODE,` or `,,`: an empty parameter, ignored.
            continue;
        }
        out.params.push(Param {
            name: pname_s,
            value,
        });
    }
    Ok(out)
}

/// The comma-separated fields of a data line, untrimmed. A line ending in a comma yields a
/// final empty field (see [`trailing_comma`]).
pub(super) struct Fields<'a> {
    rest: Option<&'a [u8]>,
}

pub(super) fn fields(line: &[u8]) -> Fields<'_> {
    Fields { rest: Some(line) }
}

impl<'a> Iterator for Fields<'a> {
    type Item = &'a [u8];

    #[inline]
    fn next(&mut self) -> Option<&'a [u8]> {
        let r = self.rest?;
        let parsed: Res<'a, &'a [u8]> = take_till(|c| c == b',').parse(r);
        let (rem, field) = parsed.ok()?;
        self.rest = match rem.split_first() {
            Some((_, after)) => Some(after),
            None => None,
        };
        Some(field)
    }
}

/// True when a data line ends in a comma (blanks after it ignored).
pub(super) fn trailing_comma(line: &[u8]) -> bool {
    line.trim_ascii_end().last() == Some(&b',')
}

/// Whether a line following a keyword line that ends in a comma continues its parameters:
/// its first item is `NAME=...` or one of the value-less flags of the modelled keywords.
/// (A data line such as `Sym12, 3` or `PART1, PART2` after `*NSET, NSET=X,` is data.)
pub(super) fn looks_like_parameters(line: &[u8]) -> bool {
    let first_item = line.split(|&b| b == b',').next().unwrap_or(b"");
    if !line.first().is_some_and(u8::is_ascii_alphabetic) {
        return false;
    }
    if first_item.contains(&b'=') {
        return true;
    }
    let name = squeeze(first_item, true);
    matches!(name.as_str(), "GENERATE" | "INTERNAL" | "UNSORTED")
}

/// A positive integer label (blanks around it allowed).
#[inline]
pub(super) fn label(field: &[u8]) -> Option<u64> {
    let parsed: Res<'_, u64> =
        all_consuming(delimited(space0, nom::character::complete::u64, space0)).parse(field);
    parsed.ok().map(|(_, v)| v)
}

/// The text of a real number: optional sign, digits with an optional fraction (or a fraction
/// alone), optional exponent with `E`, `e`, `D` or `d`.
fn real_text(i: &[u8]) -> Res<'_, &[u8]> {
    recognize((
        opt(one_of("+-")),
        alt((
            recognize((digit1, opt((char('.'), digit0)))),
            recognize((char('.'), digit1)),
        )),
        opt((one_of("eEdD"), opt(one_of("+-")), digit1)),
    ))
    .parse(i)
}

/// A real number (blanks around it allowed); `None` for anything else, including a blank field.
#[inline]
pub(super) fn real(field: &[u8]) -> Option<f64> {
    let parsed: Res<'_, &[u8]> = all_consuming(delimited(space0, real_text, space0)).parse(field);
    let (_, text) = parsed.ok()?;
    if text.len() > 64 {
        return None;
    }
    crate::text::parse_real(text)
}

/// True for a field holding only blanks.
#[inline]
pub(super) fn is_blank_field(field: &[u8]) -> bool {
    field.iter().all(|&b| is_blank(b))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keyword_lines() {
        let k = keyword(b"*Element, Type=C3d4, Elset=Cube").unwrap();
        assert_eq!(k.name, "ELEMENT");
        assert_eq!(k.value("TYPE"), Some("C3d4"));
        assert_eq!(k.value("ELSET"), Some("Cube"));
        let k = keyword(b"*NODE , Nset = nset_csys0").unwrap();
        assert_eq!(k.name, "NODE");
        assert_eq!(k.value("NSET"), Some("nset_csys0"));
        let k = keyword(b"*ELEMENT, TYPE=C3D20   , ELSET=B1").unwrap();
        assert_eq!(k.value("TYPE"), Some("C3D20"));
        let k = keyword(br#"*Instance, name="Part A-1", part="Part A""#).unwrap();
        assert_eq!(k.name, "INSTANCE");
        assert_eq!(k.value("NAME"), Some("Part A-1"));
        assert_eq!(k.value("PART"), Some("Part A"));
        let k = keyword(b"*Elset, elset=Set-3, instance=\"x y\", generate").unwrap();
        assert!(k.flag("GENERATE"));
        assert_eq!(k.value("GENERATE"), None);
        let k = keyword(b"*End Part").unwrap();
        assert_eq!(k.name, "ENDPART");
        let k = keyword(b"*NODE,").unwrap();
        assert!(k.params.is_empty());
        assert!(keyword(b"*Part, name=\"open").is_err());
        assert!(keyword(b"*Part, name=\"a\" b").is_err());
        assert!(keyword(b"*, x").is_err());
        assert!(keyword(b"*Node, =3").is_err());
    }

    #[test]
    fn data_fields() {
        let v: Vec<&[u8]> = fields(b"1, 2 ,3,").collect();
        assert_eq!(v, vec![&b"1"[..], b" 2 ", b"3", b""]);
        assert!(trailing_comma(b"1, 2,  "));
        assert!(!trailing_comma(b"1, 2"));
        assert_eq!(fields(b"").count(), 1);
        assert_eq!(label(b"  17 "), Some(17));
        assert_eq!(label(b"1.5"), None);
        assert_eq!(label(b"-3"), None);
        assert_eq!(label(b"99999999999999999999999"), None);
        assert_eq!(real(b" 1.0e1"), Some(10.0));
        assert_eq!(real(b"100.0E-1 "), Some(10.0));
        assert_eq!(real(b"1."), Some(1.0));
        assert_eq!(real(b"-.5"), Some(-0.5));
        assert_eq!(real(b"2.5D2"), Some(250.0));
        assert_eq!(real(b"nan"), None);
        assert_eq!(real(b"1.0 2"), None);
        assert_eq!(real(b""), None);
        assert!(is_blank_field(b"  "));
        assert!(looks_like_parameters(b"NSET=A, generate"));
        assert!(looks_like_parameters(b"generate"));
        assert!(!looks_like_parameters(b"Sym12, 3"));
        assert!(!looks_like_parameters(b"1, 2, 3"));
    }
}
