//! The bulk reader: a cursor over the whole file with tight number readers for node and
//! element records, plus a bridge that runs the nom grammar ([`super::grammar`]) at the cursor.
//!
//! ASCII records are read token by token (MSH is whitespace-separated, not line-based): skip
//! blanks, take the bytes up to the next blank, convert them. Integers are converted digit by
//! digit; reals go through `str::parse::<f64>` (correctly rounded) after a UTF-8 check that is
//! cheap on ASCII. Binary records are read as raw 4- or 8-byte values in the file's byte order.
//! Nothing here allocates; every error is built in a `#[cold]` function from the offset.

use std::borrow::Cow;

use nom::Parser;

use super::grammar::{Enc, PErr};
use super::num::{is_ws, parse_f64, parse_i64, parse_u64};
use super::{fail, Res};
use crate::error::describe_found;

/// A position in the file and the encoding of the section being read.
pub(crate) struct Cur<'a> {
    pub d: &'a [u8],
    pub p: usize,
    pub enc: Enc,
}

impl<'a> Cur<'a> {
    pub(crate) fn new(d: &'a [u8], p: usize, enc: Enc) -> Cur<'a> {
        Cur { d, p, enc }
    }

    /// The input from the cursor on.
    pub(crate) fn rest(&self) -> &'a [u8] {
        self.d.get(self.p..).unwrap_or_default()
    }

    /// Bytes left after the cursor (for capacity hints).
    pub(crate) fn left(&self) -> usize {
        self.d.len().saturating_sub(self.p)
    }

    /// Runs a nom parser at the cursor and moves past what it consumed.
    pub(crate) fn run<O>(
        &mut self,
        mut parser: impl Parser<&'a [u8], Output = O, Error = PErr<'a>>,
        fallback: &'static str,
    ) -> Res<O> {
        match parser.parse_complete(self.rest()) {
            Ok((rest, out)) => {
                self.p = self.d.len() - rest.len();
                Ok(out)
            }
            Err(nom::Err::Error(e) | nom::Err::Failure(e)) => {
                let at = self.d.len() - e.input.len();
                let expected = e.expected.unwrap_or(fallback);
                match e.input.len() {
                    // Raw values fail only when the file ends within them.
                    n @ 1..=7 if self.enc.is_binary() => {
                        Err(fail(at, expected, format!("end of file after {n} bytes")))
                    }
                    _ => Err(self.fail_at(at, expected)),
                }
            }
            Err(nom::Err::Incomplete(_)) => Err(self.fail_at(self.d.len(), fallback)),
        }
    }

    /// Expects the `$EndName` line of a section.
    pub(crate) fn end_of(&mut self, name: &'static str) -> Res<()> {
        let mut p = super::grammar::end_line(name.as_bytes());
        match p.parse_complete(self.rest()) {
            Ok((rest, ())) => {
                self.p = self.d.len() - rest.len();
                Ok(())
            }
            Err(_) => {
                let mut at = self.p;
                while at < self.d.len() && is_ws(self.d[at]) {
                    at += 1;
                }
                Err(self.fail_at(at, format!("$End{name}")))
            }
        }
    }

    /// An error about the token at `at`: "expected `expected`, found `<token>`". Blanks before
    /// the token are skipped within the line; a newline is reported as the end of the line.
    #[cold]
    #[inline(never)]
    pub(crate) fn fail_at(
        &self,
        at: usize,
        expected: impl Into<Cow<'static, str>>,
    ) -> Box<super::Fail> {
        let d = self.d;
        let mut s = at.min(d.len());
        while s < d.len() && (d[s] == b' ' || d[s] == b'\t') {
            s += 1;
        }
        if s < d.len() && (d[s] == b'\n' || d[s] == b'\r') {
            return fail(s, expected, "the end of the line");
        }
        let mut e = s;
        while e < d.len() && e - s < 48 && !is_ws(d[e]) {
            e += 1;
        }
        fail(s, expected, describe_found(&d[s..e]))
    }

    /// An error for a raw value cut off by the end of the file.
    #[cold]
    #[inline(never)]
    fn eof_at(&self, at: usize, need: usize, what: &'static str) -> Box<super::Fail> {
        let left = self.d.len().saturating_sub(at);
        fail(
            at,
            format!("{what} ({need} bytes)"),
            if left == 0 {
                "end of file".to_string()
            } else {
                format!("end of file after {left} bytes")
            },
        )
    }

    #[inline(always)]
    fn skip_ws(&mut self) {
        let d = self.d;
        let mut p = self.p;
        while p < d.len() && is_ws(d[p]) {
            p += 1;
        }
        self.p = p;
    }

    /// The start of the next ASCII token (skipping blanks), or the cursor for binary data.
    #[inline(always)]
    pub(crate) fn token_start(&mut self) -> usize {
        if !self.enc.is_binary() {
            self.skip_ws();
        }
        self.p
    }

    /// Next ASCII token as (start, end); empty at the end of the input.
    #[inline(always)]
    fn a_token(&mut self) -> (usize, usize) {
        self.skip_ws();
        let d = self.d;
        let start = self.p;
        let mut p = start;
        while p < d.len() && !is_ws(d[p]) {
            p += 1;
        }
        (start, p)
    }

    /// An unsigned ASCII integer, converted while it is scanned; tokens of more than 19
    /// digits and errors take the slow path.
    #[inline(always)]
    fn a_u64(&mut self, what: &'static str) -> Res<u64> {
        self.skip_ws();
        let d = self.d;
        let s = self.p;
        let mut p = s;
        let mut v: u64 = 0;
        while p < d.len() {
            let x = d[p].wrapping_sub(b'0');
            if x > 9 {
                break;
            }
            v = v.wrapping_mul(10).wrapping_add(u64::from(x));
            p += 1;
        }
        if p == s || p - s > 19 || (p < d.len() && !is_ws(d[p])) {
            return self.a_u64_slow(what);
        }
        self.p = p;
        Ok(v)
    }

    #[cold]
    #[inline(never)]
    fn a_u64_slow(&mut self, what: &'static str) -> Res<u64> {
        let (s, e) = self.a_token();
        match parse_u64(&self.d[s..e]) {
            Some(v) => {
                self.p = e;
                Ok(v)
            }
            None => Err(self.fail_at(s, what)),
        }
    }

    #[inline(always)]
    fn a_i64(&mut self, what: &'static str) -> Res<i64> {
        let (s, e) = self.a_token();
        match parse_i64(&self.d[s..e]) {
            Some(v) => {
                self.p = e;
                Ok(v)
            }
            None => Err(self.fail_at(s, what)),
        }
    }

    #[inline(always)]
    fn a_f64(&mut self, what: &'static str) -> Res<f64> {
        let (s, e) = self.a_token();
        match parse_f64(&self.d[s..e]) {
            Some(v) => {
                self.p = e;
                Ok(v)
            }
            None => Err(self.fail_at(s, what)),
        }
    }

    #[inline(always)]
    fn raw<const N: usize>(&mut self, what: &'static str) -> Res<[u8; N]> {
        let p = self.p;
        match self.d.get(p..p + N) {
            Some(s) => {
                let mut a = [0u8; N];
                a.copy_from_slice(s);
                self.p = p + N;
                Ok(a)
            }
            None => Err(self.eof_at(p, N, what)),
        }
    }

    /// [`Cur::size_t`] with the encoding known at compile time (`ASCII` must match `enc`), for
    /// the record loops.
    #[inline(always)]
    pub(crate) fn size_t_as<const ASCII: bool>(&mut self, what: &'static str) -> Res<u64> {
        if ASCII {
            self.a_u64(what)
        } else {
            self.size_t(what)
        }
    }

    /// [`Cur::real`] with the encoding known at compile time.
    #[inline(always)]
    pub(crate) fn real_as<const ASCII: bool>(&mut self, what: &'static str) -> Res<f64> {
        if ASCII {
            self.a_f64(what)
        } else {
            self.real(what)
        }
    }

    /// A `size_t` value (MSH 4.1 counts and tags).
    #[inline(always)]
    pub(crate) fn size_t(&mut self, what: &'static str) -> Res<u64> {
        match self.enc {
            Enc::Ascii => self.a_u64(what),
            Enc::Binary { big, wide: true } => {
                let a = self.raw::<8>(what)?;
                Ok(if big {
                    u64::from_be_bytes(a)
                } else {
                    u64::from_le_bytes(a)
                })
            }
            Enc::Binary { big, wide: false } => {
                let a = self.raw::<4>(what)?;
                Ok(u64::from(if big {
                    u32::from_be_bytes(a)
                } else {
                    u32::from_le_bytes(a)
                }))
            }
        }
    }

    /// An `int` value (4 bytes in binary files).
    #[inline(always)]
    pub(crate) fn int(&mut self, what: &'static str) -> Res<i64> {
        match self.enc {
            Enc::Ascii => self.a_i64(what),
            Enc::Binary { big, .. } => {
                let a = self.raw::<4>(what)?;
                Ok(i64::from(if big {
                    i32::from_be_bytes(a)
                } else {
                    i32::from_le_bytes(a)
                }))
            }
        }
    }

    /// A finite `double`.
    #[inline(always)]
    pub(crate) fn real(&mut self, what: &'static str) -> Res<f64> {
        match self.enc {
            Enc::Ascii => self.a_f64(what),
            Enc::Binary { big, .. } => {
                let a = self.raw::<8>(what)?;
                let v = if big {
                    f64::from_be_bytes(a)
                } else {
                    f64::from_le_bytes(a)
                };
                if v.is_finite() {
                    Ok(v)
                } else {
                    Err(self.not_finite(self.p - 8, what))
                }
            }
        }
    }

    #[cold]
    #[inline(never)]
    fn not_finite(&self, at: usize, what: &'static str) -> Box<super::Fail> {
        fail(at, format!("{what} (a finite double)"), "NaN or infinity")
    }

    /// Smallest number of bytes one `size_t` can take (for capacity hints).
    pub(crate) fn min_size_t(&self) -> usize {
        match self.enc {
            Enc::Ascii => 2,
            Enc::Binary { wide: true, .. } => 8,
            Enc::Binary { wide: false, .. } => 4,
        }
    }

    /// Smallest number of bytes one `double` can take.
    pub(crate) fn min_real(&self) -> usize {
        match self.enc {
            Enc::Ascii => 2,
            Enc::Binary { .. } => 8,
        }
    }
}
