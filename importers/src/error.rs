//! Import errors: where in which file, what was expected, what was found.
//!
//! Every reader reports a problem as `FILE:LINE: expected X, found Y` (text) or
//! `FILE:byte N: expected X, found Y` (binary sections), so that a user can open the file at
//! the place and see what is wrong.

use std::fmt;
use std::path::{Path, PathBuf};

/// Where in a file a problem was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Location {
    /// 1-based line number in a text file or text section.
    Line(usize),
    /// 0-based byte offset in a binary section.
    Byte(u64),
    /// The file as a whole (it could not be opened, or holds nothing to read).
    File,
}

/// A file that cannot be read as a mesh.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ImportError {
    pub path: PathBuf,
    pub location: Location,
    pub expected: String,
    pub found: String,
}

impl ImportError {
    /// An error at a line.
    pub fn at_line(
        path: &Path,
        line: usize,
        expected: impl Into<String>,
        found: impl Into<String>,
    ) -> ImportError {
        ImportError {
            path: path.to_path_buf(),
            location: Location::Line(line),
            expected: clip(expected.into(), MAX_EXPECTED),
            found: clip(found.into(), MAX_FOUND),
        }
    }

    /// An error at a byte offset of a binary section.
    pub fn at_byte(
        path: &Path,
        offset: u64,
        expected: impl Into<String>,
        found: impl Into<String>,
    ) -> ImportError {
        ImportError {
            path: path.to_path_buf(),
            location: Location::Byte(offset),
            expected: clip(expected.into(), MAX_EXPECTED),
            found: clip(found.into(), MAX_FOUND),
        }
    }

    /// An error about the whole file.
    pub fn whole_file(
        path: &Path,
        expected: impl Into<String>,
        found: impl Into<String>,
    ) -> ImportError {
        ImportError {
            path: path.to_path_buf(),
            location: Location::File,
            expected: clip(expected.into(), MAX_EXPECTED),
            found: clip(found.into(), MAX_FOUND),
        }
    }
}

impl fmt::Display for ImportError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let p = self.path.display();
        match self.location {
            Location::Line(n) => write!(f, "{p}:{n}: ")?,
            Location::Byte(o) => write!(f, "{p}:byte {o}: ")?,
            Location::File => write!(f, "{p}: ")?,
        }
        write!(f, "expected {}, found {}", self.expected, self.found)
    }
}

impl std::error::Error for ImportError {}

/// Longest "expected" half of a message, in characters; longer text (a name taken from the
/// file) is cut with "...". With [`MAX_FOUND`] this keeps a message, after the file name,
/// within 280 characters.
pub const MAX_EXPECTED: usize = 160;
/// Longest "found" half of a message, in characters.
pub const MAX_FOUND: usize = 80;

/// Cuts `s` to at most `max` characters, ending in "..." when cut.
fn clip(mut s: String, max: usize) -> String {
    if let Some((cut, _)) = s.char_indices().nth(max.saturating_sub(3)) {
        if s.chars().count() > max {
            s.truncate(cut);
            s.push_str("...");
        }
    }
    s
}

/// Describes a piece of input for the "found" half of a message: quoted, at most 40
/// characters, control and non-ASCII bytes escaped, and named when it is empty or NUL padding.
pub fn describe_found(bytes: &[u8]) -> String {
    let trimmed = trim_ascii(bytes);
    if bytes.is_empty() {
        return "end of file".to_string();
    }
    if trimmed.is_empty() {
        return if bytes.contains(&0) {
            "NUL bytes".to_string()
        } else {
            "a blank line".to_string()
        };
    }
    if trimmed.iter().all(|&b| b == 0) {
        return "NUL bytes".to_string();
    }
    let mut s = String::from("'");
    for (count, &b) in trimmed.iter().enumerate() {
        if count >= 40 {
            s.push_str("...");
            break;
        }
        match b {
            0x20..=0x7e => s.push(b as char),
            b'\t' => s.push_str("\\t"),
            _ => s.push_str(&format!("\\x{b:02x}")),
        }
    }
    s.push('\'');
    s
}

fn trim_ascii(b: &[u8]) -> &[u8] {
    let start = b
        .iter()
        .position(|c| !c.is_ascii_whitespace())
        .unwrap_or(b.len());
    let end = b
        .iter()
        .rposition(|c| !c.is_ascii_whitespace())
        .map_or(start, |e| e + 1);
    &b[start..end.max(start)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_forms() {
        let p = Path::new("a.msh");
        assert_eq!(
            ImportError::at_line(p, 3, "a node count", "'x'").to_string(),
            "a.msh:3: expected a node count, found 'x'"
        );
        assert_eq!(
            ImportError::at_byte(p, 17, "8 bytes", "end of file").to_string(),
            "a.msh:byte 17: expected 8 bytes, found end of file"
        );
    }

    #[test]
    fn found_descriptions() {
        assert_eq!(describe_found(b""), "end of file");
        assert_eq!(describe_found(b"\0\0\0"), "NUL bytes");
        assert_eq!(describe_found(b"  \r\n"), "a blank line");
        assert_eq!(describe_found(b" 1.0e\x01 "), "'1.0e\\x01'");
        assert!(describe_found(&[b'a'; 100]).ends_with("...'"));
    }

    #[test]
    fn long_halves_are_clipped() {
        let p = Path::new("a.inp");
        let e = ImportError::at_line(p, 1, "x".repeat(1000), "\u{e9}".repeat(1000));
        assert_eq!(e.expected.chars().count(), MAX_EXPECTED);
        assert!(e.expected.ends_with("..."));
        assert_eq!(e.found.chars().count(), MAX_FOUND);
        assert_eq!(ImportError::at_byte(p, 0, "short", "y").found, "y");
    }
}
