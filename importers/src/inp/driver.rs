//! The driver: lines of the main file and its includes (`*INCLUDE` and `INPUT=`), keyword
//! lines joined with their continuation lines, each line handed to the reader.

use std::borrow::Cow;
use std::path::{Path, PathBuf};

use super::{lex, Reader};
use crate::error::ImportError;

/// Include nesting limit.
const MAX_INCLUDE_DEPTH: usize = 32;

/// Limit on the number of included files read in all (the same file counts each time): files
/// that include each other several times would otherwise multiply the work at every level.
const MAX_INCLUDES: usize = 10_000;

/// A file name from the deck for a message: quoted, control and non-ASCII characters escaped,
/// and of a long name only its last 57 characters (where the file's own name is).
fn shown(name: &str) -> String {
    let mut esc = String::new();
    for c in name.chars() {
        match c {
            ' '..='~' => esc.push(c),
            '\u{fffd}' => esc.push('?'),
            _ => esc.push_str(&c.escape_default().to_string()),
        }
    }
    let n = esc.chars().count();
    if n <= 60 {
        format!("'{esc}'")
    } else {
        let tail: String = esc.chars().skip(n - 57).collect();
        format!("'...{tail}'")
    }
}

impl Reader {
    pub(super) fn run(&mut self, path: &Path, data: &[u8]) -> Result<(), ImportError> {
        struct Frame<'a> {
            file: u32,
            data: Cow<'a, [u8]>,
            pos: usize,
            line: usize,
            canonical: Option<PathBuf>,
        }
        impl Frame<'_> {
            /// The next line as (number, start, end) with "\n" / "\r\n" removed.
            fn next_range(&mut self) -> Option<(usize, usize, usize)> {
                let d: &[u8] = &self.data;
                if self.pos >= d.len() {
                    return None;
                }
                let start = self.pos;
                let end = match memchr::memchr(b'\n', &d[start..]) {
                    Some(i) => start + i,
                    None => d.len(),
                };
                self.pos = end + 1;
                self.line += 1;
                let end = if end > start && d[end - 1] == b'\r' {
                    end - 1
                } else {
                    end
                };
                Some((self.line, start, end))
            }
        }
        fn strip_bom(d: &[u8]) -> usize {
            if d.starts_with(b"\xEF\xBB\xBF") {
                3
            } else {
                0
            }
        }

        self.files.push(path.to_path_buf());
        self.input_bytes = data.len();
        self.last_line = memchr::memchr_iter(b'\n', data).count()
            + usize::from(!data.is_empty() && !data.ends_with(b"\n"));
        let mut frames = vec![Frame {
            file: 0,
            data: Cow::Borrowed(data),
            pos: strip_bom(data),
            line: 0,
            canonical: std::fs::canonicalize(path).ok(),
        }];
        let mut kw_buf: Vec<u8> = Vec::new();
        while let Some(top) = frames.last_mut() {
            let Some((lineno, start, end)) = top.next_range() else {
                frames.pop();
                continue;
            };
            let file = top.file;
            let raw = &top.data[start..end];
            let line = raw.trim_ascii_start();
            if line.is_empty() || line.starts_with(b"**") {
                continue;
            }
            if line[0] != b'*' {
                self.data_line(line, file, lineno)?;
                continue;
            }
            // A keyword line, possibly continued on following lines.
            kw_buf.clear();
            kw_buf.extend_from_slice(line.trim_ascii_end());
            while lex::trailing_comma(&kw_buf) {
                let save = (top.pos, top.line);
                let Some((_, s, e)) = top.next_range() else {
                    break;
                };
                let next = top.data[s..e].trim_ascii();
                if lex::looks_like_parameters(next) {
                    kw_buf.extend_from_slice(next);
                } else {
                    (top.pos, top.line) = save;
                    break;
                }
            }
            let Some(include) = self.keyword(&kw_buf, file, lineno)? else {
                continue;
            };
            // Read the named file next.
            let including = self.files[file as usize].clone();
            let resolve = |t: &str| {
                let target = Path::new(t);
                if target.is_absolute() {
                    target.to_path_buf()
                } else {
                    including
                        .parent()
                        .map(|p| p.join(target))
                        .unwrap_or_else(|| target.to_path_buf())
                }
            };
            let mut resolved = resolve(&include.target);
            if !resolved.exists() && include.target.contains('\\') {
                // A deck written on Windows: `sub\part.inp`.
                let alt = resolve(&include.target.replace('\\', "/"));
                if alt.exists() {
                    resolved = alt;
                }
            }
            if frames.len() >= MAX_INCLUDE_DEPTH {
                return Err(self.err(
                    file,
                    lineno,
                    format!("*INCLUDE nested at most {MAX_INCLUDE_DEPTH} deep"),
                    format!("{} at depth {}", shown(&include.target), frames.len()),
                ));
            }
            let not_file = resolved.exists() && !resolved.is_file();
            if not_file {
                return Err(self.err(
                    file,
                    lineno,
                    format!("a regular file for INPUT={}", shown(&include.target)),
                    format!(
                        "{} (a directory or device)",
                        shown(&resolved.display().to_string())
                    ),
                ));
            }
            let bytes = std::fs::read(&resolved).map_err(|e| {
                self.err(
                    file,
                    lineno,
                    format!("a readable file for INPUT={}", shown(&include.target)),
                    format!("{} ({e})", shown(&resolved.display().to_string())),
                )
            })?;
            let canonical = std::fs::canonicalize(&resolved).ok();
            if let Some(c) = &canonical {
                if frames.iter().any(|f| f.canonical.as_ref() == Some(c)) {
                    return Err(self.err(
                        file,
                        lineno,
                        "an *INCLUDE that does not include a file being read (no cycle)",
                        format!(
                            "{}, which is already being read",
                            shown(&resolved.display().to_string())
                        ),
                    ));
                }
            }
            if self.files.len() > MAX_INCLUDES {
                return Err(self.err(
                    file,
                    lineno,
                    format!("at most {MAX_INCLUDES} *INCLUDE files read in all"),
                    format!("another one, {}", shown(&include.target)),
                ));
            }
            let index = u32::try_from(self.files.len())
                .map_err(|_| self.err(file, lineno, "fewer included files", "too many"))?;
            self.files.push(resolved);
            self.input_bytes = self.input_bytes.saturating_add(bytes.len());
            let pos = strip_bom(&bytes);
            frames.push(Frame {
                file: index,
                data: Cow::Owned(bytes),
                pos,
                line: 0,
                canonical,
            });
        }
        Ok(())
    }
}
