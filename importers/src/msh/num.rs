//! ASCII number tokens: the blanks that separate them and the integer and real conversions,
//! shared by the record tokenizer (`lex.rs`) and the nom grammar (`grammar.rs`).
//!
//! Integers are converted digit by digit; reals take an exact fast path or `str::parse::<f64>`.

/// The blanks that separate ASCII tokens. NUL is not one of them, so NUL padding is an error.
#[inline(always)]
pub(crate) fn is_ws(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\n' | b'\r' | 0x0b | 0x0c)
}

/// Digits only (no sign), at most `u64::MAX`.
#[inline]
pub(crate) fn parse_u64(t: &[u8]) -> Option<u64> {
    if t.is_empty() {
        return None;
    }
    if t.len() <= 19 {
        let mut v = 0u64;
        for &b in t {
            let d = b.wrapping_sub(b'0');
            if d > 9 {
                return None;
            }
            v = v * 10 + u64::from(d);
        }
        return Some(v);
    }
    t.iter().try_fold(0u64, |v, &b| {
        let d = b.wrapping_sub(b'0');
        if d > 9 {
            return None;
        }
        v.checked_mul(10)?.checked_add(u64::from(d))
    })
}

/// An optional sign and digits.
#[inline]
pub(crate) fn parse_i64(t: &[u8]) -> Option<i64> {
    let (neg, digits) = match t.first() {
        Some(b'-') => (true, &t[1..]),
        Some(b'+') => (false, &t[1..]),
        _ => (false, t),
    };
    let v = parse_u64(digits)?;
    if neg {
        0i64.checked_sub_unsigned(v)
    } else {
        i64::try_from(v).ok()
    }
}

/// A finite real as C's `%g`/`%f`/`%e` print it (Rust's float grammar; `inf` and `nan` are
/// refused because no mesh writer means them as coordinates).
///
/// Fast path (Clinger): with at most 19 digits, a mantissa up to 2^53 and a decimal exponent
/// within ±22, both the mantissa and the power of ten are exact doubles, so one IEEE division
/// or multiplication gives the correctly rounded result, the same bits as `str::parse`. Gmsh's
/// `%.16g` output mostly takes this path; anything else goes through `str::parse::<f64>`.
#[inline]
pub(crate) fn parse_f64(t: &[u8]) -> Option<f64> {
    match fast_f64(t) {
        Some(v) => Some(v),
        None => slow_f64(t),
    }
}

#[inline(never)]
fn slow_f64(t: &[u8]) -> Option<f64> {
    let v: f64 = std::str::from_utf8(t).ok()?.parse().ok()?;
    v.is_finite().then_some(v)
}

const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

#[inline(always)]
fn fast_f64(t: &[u8]) -> Option<f64> {
    let n = t.len();
    let mut i = 0;
    let neg = match t.first() {
        Some(b'-') => {
            i = 1;
            true
        }
        Some(b'+') => {
            i = 1;
            false
        }
        _ => false,
    };
    let mut mant: u64 = 0;
    let mut digits = 0usize;
    while i < n {
        let x = t[i].wrapping_sub(b'0');
        if x > 9 {
            break;
        }
        mant = mant.wrapping_mul(10).wrapping_add(u64::from(x));
        digits += 1;
        i += 1;
    }
    let mut exp: i64 = 0;
    if i < n && t[i] == b'.' {
        i += 1;
        let from = i;
        while i < n {
            let x = t[i].wrapping_sub(b'0');
            if x > 9 {
                break;
            }
            mant = mant.wrapping_mul(10).wrapping_add(u64::from(x));
            i += 1;
        }
        digits += i - from;
        exp -= (i - from) as i64;
    }
    if digits == 0 || digits > 19 {
        return None;
    }
    if i < n && (t[i] | 0x20) == b'e' {
        i += 1;
        let eneg = match t.get(i) {
            Some(b'-') => {
                i += 1;
                true
            }
            Some(b'+') => {
                i += 1;
                false
            }
            _ => false,
        };
        let from = i;
        let mut e: i64 = 0;
        while i < n && i - from < 6 {
            let x = t[i].wrapping_sub(b'0');
            if x > 9 {
                break;
            }
            e = e * 10 + i64::from(x);
            i += 1;
        }
        if i == from {
            return None;
        }
        exp += if eneg { -e } else { e };
    }
    if i != n || mant > (1u64 << 53) || !(-22..=22).contains(&exp) {
        return None;
    }
    let m = mant as f64;
    let v = if exp < 0 {
        m / POW10[(-exp) as usize]
    } else {
        m * POW10[exp as usize]
    };
    Some(if neg { -v } else { v })
}
