//! Fortran format lines such as `(3i9,6e21.13e3)`, `(19i10)` or `(2i9,19a9)`, which give the
//! column widths of the data records that follow a block header (FORMATS.md §1.3, §1.4, §1.5).
//!
//! Records are sliced by these widths, never split on whitespace: reals run together when a
//! minus sign fills the separating blank (`1.0E+00-5.0E-01`, FORMATS.md §1.8 item 1), and the
//! integer widths of one line may differ (`(1i7,2i9,6e21.13)`, item 4).

use nom::bytes::complete::take_while;
use nom::character::complete::{char, one_of, space0, u32 as dec_u32};
use nom::combinator::{all_consuming, opt};
use nom::multi::separated_list1;
use nom::sequence::{delimited, preceded};
use nom::{IResult, Parser};

/// What a column holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    /// `Iw`: an integer.
    Int,
    /// `Ew.d`, `Dw.d`, `Gw.d`, `Fw.d` (with optional `Ee` exponent width): a real.
    Real,
    /// `Aw`: text (ETBLOCK writes its KEYOPT values as `a9`).
    Text,
    /// `nX`: blanks to skip.
    Skip,
}

/// One edit descriptor with its repeat count: `6e21.13e3` is 6 reals of width 21.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Group {
    pub count: usize,
    pub kind: Kind,
    pub width: usize,
}

/// One column of a record: bytes `start..start + width` of the line (0-based).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Column {
    pub start: usize,
    pub width: usize,
    pub kind: Kind,
}

impl Column {
    /// The column's bytes in `line`; shorter (or empty) where the line ends early, since
    /// writers leave out trailing zero fields (FORMATS.md §1.8 item 3).
    #[inline]
    pub fn slice<'a>(&self, line: &'a [u8]) -> &'a [u8] {
        let s = self.start.min(line.len());
        let e = (self.start + self.width).min(line.len());
        &line[s..e]
    }

    /// `columns 10-18`, 1-based as an editor shows them.
    pub fn describe(&self) -> String {
        format!("columns {}-{}", self.start + 1, self.start + self.width)
    }
}

/// Caps that keep a hostile format line from sizing an allocation: real lines hold at most a
/// few dozen columns of at most ~30 characters.
const MAX_COLUMNS: usize = 4096;
const MAX_WIDTH: usize = 1000;

/// A parsed format line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Format {
    /// The data columns in order (skips only move the start of the next column).
    pub columns: Vec<Column>,
    /// Total record width.
    pub width: usize,
}

/// Where the node number and the coordinates sit in an NBLOCK record.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct NodeLayout {
    pub id: Column,
    /// x, y, z; `None` where the format has fewer than three real columns.
    pub coords: [Option<Column>; 3],
    /// End of the last column: anything non-blank after it is not part of the record.
    pub end: usize,
}

impl Format {
    /// Parses a format line (surrounding blanks allowed). `None` if it is not one, or if it
    /// declares absurd widths or column counts.
    pub fn parse(line: &[u8]) -> Option<Format> {
        let (_, groups) = format_line(line).ok()?;
        let mut columns = Vec::new();
        let mut start = 0usize;
        for g in groups.into_iter().flatten() {
            if g.width == 0 || g.width > MAX_WIDTH || g.count > MAX_COLUMNS {
                return None;
            }
            if g.kind == Kind::Skip {
                start += g.width * g.count;
                continue;
            }
            if columns.len() + g.count > MAX_COLUMNS {
                return None;
            }
            for _ in 0..g.count {
                columns.push(Column {
                    start,
                    width: g.width,
                    kind: g.kind,
                });
                start += g.width;
            }
        }
        if columns.is_empty() {
            return None;
        }
        Some(Format {
            columns,
            width: start,
        })
    }

    /// The NBLOCK layout: one or more integer columns (node number first; solid entity and
    /// line location, if present, are ignored), then the reals (FORMATS.md §1.3: `(1i9,…)`
    /// Workbench blocks have a single integer column).
    pub fn node_layout(&self) -> Option<NodeLayout> {
        let mut ints = 0;
        let mut coords = [None; 3];
        let mut reals = 0;
        for c in &self.columns {
            match c.kind {
                Kind::Int if reals == 0 => ints += 1,
                Kind::Real if ints > 0 => {
                    if reals < 3 {
                        coords[reals] = Some(*c);
                    }
                    reals += 1;
                }
                _ => return None,
            }
        }
        if reals == 0 {
            return None;
        }
        Some(NodeLayout {
            id: self.columns[0],
            coords,
            end: self.width,
        })
    }

    /// True if every column is an integer column (EBLOCK, CMBLOCK).
    pub fn all_int(&self) -> bool {
        self.columns.iter().all(|c| c.kind == Kind::Int)
    }
}

type Res<'a, T> = IResult<&'a [u8], T>;

/// `(` descriptor {`,` descriptor} `)`, blanks allowed around the parentheses and commas.
fn format_line(input: &[u8]) -> Res<'_, Vec<Option<Group>>> {
    all_consuming(delimited(
        (space0, char('('), space0),
        separated_list1((space0, char(','), space0), descriptor),
        (space0, char(')'), space0),
    ))
    .parse(input)
}

/// An optional scale factor `kP`, then an optional edit descriptor; at least one of the two.
/// A bare scale factor (`1p,6e21.13`) yields `None`.
fn descriptor(input: &[u8]) -> Res<'_, Option<Group>> {
    let (input, scale) = opt((dec_u32, one_of("pP"))).parse(input)?;
    let (rest, edit) = opt(edit).parse(input)?;
    match (scale, edit) {
        (None, None) => Err(nom::Err::Error(nom::error::Error::new(
            input,
            nom::error::ErrorKind::Alt,
        ))),
        (_, e) => Ok((rest, e)),
    }
}

/// `[r]Iw[.m]`, `[r]Ew.d[Ee]` (also `ES`, `EN`, `D`, `G`, `F`), `[r]Aw`, `nX`.
fn edit(input: &[u8]) -> Res<'_, Group> {
    let (input, repeat) = opt(dec_u32).parse(input)?;
    let (input, letter) = one_of("iIeEdDgGfFaAxX").parse(input)?;
    let count = repeat.unwrap_or(1) as usize;
    match letter.to_ascii_lowercase() {
        'x' => Ok((
            input,
            Group {
                count: 1,
                kind: Kind::Skip,
                width: count,
            },
        )),
        'i' => {
            let (input, width) = dec_u32(input)?;
            let (input, _) = opt(preceded(char('.'), dec_u32)).parse(input)?;
            Ok((input, group(count, Kind::Int, width)))
        }
        'a' => {
            let (input, width) = dec_u32(input)?;
            Ok((input, group(count, Kind::Text, width)))
        }
        _ => {
            // ES / EN variants of E.
            let (input, _) = if letter.eq_ignore_ascii_case(&'e') {
                opt(one_of("sSnN")).parse(input)?
            } else {
                (input, None)
            };
            let (input, width) = dec_u32(input)?;
            let (input, _) = opt(preceded(
                char('.'),
                (
                    take_while(|c: u8| c.is_ascii_digit()),
                    opt(preceded(one_of("eE"), dec_u32)),
                ),
            ))
            .parse(input)?;
            Ok((input, group(count, Kind::Real, width)))
        }
    }
}

fn group(count: usize, kind: Kind, width: u32) -> Group {
    Group {
        count,
        kind,
        width: width as usize,
    }
}
