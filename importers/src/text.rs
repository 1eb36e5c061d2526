//! Small text helpers shared by the line-based readers (CDB, INP, MSH ASCII).

/// Splits `data` into lines, yielding `(1-based line number, line without "\n" or "\r\n")`.
pub(crate) fn lines(data: &[u8]) -> impl Iterator<Item = (usize, &[u8])> + '_ {
    let mut rest = data;
    let mut number = 0usize;
    std::iter::from_fn(move || {
        if rest.is_empty() {
            return None;
        }
        number += 1;
        let (line, next) = match memchr::memchr(b'\n', rest) {
            Some(i) => (&rest[..i], &rest[i + 1..]),
            None => (rest, &rest[rest.len()..]),
        };
        rest = next;
        let line = line.strip_suffix(b"\r").unwrap_or(line);
        Some((number, line))
    })
}

/// Parses a real number as Fortran and C writers print it: optional sign, digits, optional
/// fraction, optional exponent with `E`, `e`, `D` or `d`. Surrounding blanks are ignored.
pub(crate) fn parse_real(field: &[u8]) -> Option<f64> {
    let s = field.trim_ascii();
    if s.is_empty() || s.len() > 64 {
        return None;
    }
    if s.iter().any(|&b| b == b'd' || b == b'D') {
        let mut buf = [0u8; 64];
        for (i, &b) in s.iter().enumerate() {
            buf[i] = if b == b'd' || b == b'D' { b'e' } else { b };
        }
        return std::str::from_utf8(&buf[..s.len()])
            .ok()?
            .parse()
            .ok()
            .filter(|v: &f64| v.is_finite());
    }
    let v: f64 = std::str::from_utf8(s).ok()?.parse().ok()?;
    // `inf` and `nan` parse in Rust but are not coordinates any mesh writer produces.
    v.is_finite().then_some(v)
}

/// Parses a signed integer field (surrounding blanks ignored).
pub(crate) fn parse_int(field: &[u8]) -> Option<i64> {
    let s = field.trim_ascii();
    std::str::from_utf8(s).ok()?.parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_splitting() {
        let v: Vec<_> = lines(b"a\r\nb\n\nc").collect();
        assert_eq!(
            v,
            vec![
                (1, &b"a"[..]),
                (2, &b"b"[..]),
                (3, &b""[..]),
                (4, &b"c"[..])
            ]
        );
    }

    #[test]
    fn reals() {
        assert_eq!(parse_real(b" 1.5D+02 "), Some(150.0));
        assert_eq!(parse_real(b"-6.01203"), Some(-6.01203));
        assert_eq!(parse_real(b"1.0e1"), Some(10.0));
        assert_eq!(parse_real(b"0.0000000000000E+000"), Some(0.0));
        assert_eq!(parse_real(b"nan"), None);
        assert_eq!(parse_real(b"1.0.0"), None);
        assert_eq!(parse_int(b"   -18"), Some(-18));
    }
}
