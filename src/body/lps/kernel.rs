//! The LPS pass's two sweeps over one particle's bonds in AVX2/FMA, four bonds a step.
//!
//! The scalar sweeps are bound by the divider unit: a square root a bond for the
//! dilatation, a square root and a division a bond for the forces (measured: keeping the
//! extensions between the sweeps, 24 bytes a bond less to stream, saved 3 % of the pass;
//! slices without bounds checks nothing). Here they are taken four at a time (`vsqrtpd`,
//! `vdivpd`: the same correctly rounded numbers per bond), and each sweep's sums are kept
//! per lane and added at the end, so a particle's sums have other bits than the scalar
//! loop's, the same on any thread count.

use std::arch::x86_64::*;

use crate::case::pairs::{gather4, hsum};
use crate::math::Vec3;

/// One particle's bonds: partners, reference lengths, `ω v_c V_j`, and the factors of the
/// particle's own deviatoric and dilatation weights and its partners' (each `W`/`D` of the
/// sweeps: present or never read).
pub(super) struct Row<'a> {
    pub partner: &'a [u32],
    pub length: &'a [f32],
    pub volume: &'a [f64],
    pub dev_own: &'a [f32],
    pub dev_partner: &'a [f32],
    pub dil_own: &'a [f32],
    pub dil_partner: &'a [f32],
}

/// Four single-precision values of `s` from `k`, the lanes past its end `pad`.
#[inline(always)]
unsafe fn load4s(s: &[f32], k: usize, pad: f32) -> __m256d {
    _mm256_cvtps_pd(match s.get(k..k + 4) {
        Some(q) => _mm_loadu_ps(q.as_ptr()),
        None => {
            let q: [f32; 4] = std::array::from_fn(|m| s.get(k + m).copied().unwrap_or(pad));
            _mm_loadu_ps(q.as_ptr())
        }
    })
}

/// Four reference lengths from `k`, the lanes past the row's end its first.
#[inline(always)]
unsafe fn lengths4(s: &[f32], k: usize) -> __m256d {
    load4s(s, k, s[0])
}

/// Four values of `s` from `k`, zero past its end.
#[inline(always)]
unsafe fn load4(s: &[f64], k: usize) -> __m256d {
    match s.get(k..k + 4) {
        Some(q) => _mm256_loadu_pd(q.as_ptr()),
        None => {
            let q: [f64; 4] = std::array::from_fn(|m| s.get(k + m).copied().unwrap_or(0.0));
            _mm256_loadu_pd(q.as_ptr())
        }
    }
}

/// Four partners from `k`, the lanes past the row's end its first partner (whose weight is
/// padded with zero).
#[inline(always)]
fn partners4(p: &[u32], k: usize) -> [u32; 4] {
    std::array::from_fn(|m| p.get(k + m).copied().unwrap_or(p[0]))
}

#[inline(always)]
unsafe fn splat(v: Vec3) -> [__m256d; 3] {
    [
        _mm256_set1_pd(v.x),
        _mm256_set1_pd(v.y),
        _mm256_set1_pd(v.z),
    ]
}

#[inline(always)]
unsafe fn dot(a: [__m256d; 3], b: [__m256d; 3]) -> __m256d {
    _mm256_fmadd_pd(
        a[2],
        b[2],
        _mm256_fmadd_pd(a[1], b[1], _mm256_mul_pd(a[0], b[0])),
    )
}

#[inline(always)]
unsafe fn sub(a: [__m256d; 3], b: [__m256d; 3]) -> [__m256d; 3] {
    [
        _mm256_sub_pd(a[0], b[0]),
        _mm256_sub_pd(a[1], b[1]),
        _mm256_sub_pd(a[2], b[2]),
    ]
}

/// Four bonds' extensions `e`, the vectors their forces act along and those vectors'
/// inverse lengths (finite kinematics: the deformed bond; `SMALL`: the reference bond,
/// `e = η·ξ/|ξ|`). `INVERSE`: whether the inverse is wanted (the force sweep).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
unsafe fn bonds4<const SMALL: bool, const INVERSE: bool>(
    pos: &[Vec3],
    reference: &[Vec3],
    j: &[u32; 4],
    at: [__m256d; 3],
    shift: [__m256d; 3],
    l: __m256d,
) -> (__m256d, [__m256d; 3], __m256d) {
    let one = _mm256_set1_pd(1.0);
    if SMALL {
        // ξ from the reference positions (`at` is X_i), η = (x_j − X_j) − (x_i − X_i).
        let xi = sub(gather4(reference, j), at);
        let eta = sub(sub(gather4(pos, j), gather4(reference, j)), shift);
        let inv = _mm256_div_pd(one, l);
        (_mm256_mul_pd(dot(eta, xi), inv), xi, inv)
    } else {
        let y = sub(gather4(pos, j), at);
        let r = _mm256_sqrt_pd(dot(y, y));
        let inv = if INVERSE { _mm256_div_pd(one, r) } else { one };
        (_mm256_sub_pd(r, l), y, inv)
    }
}

/// The dilatation sweep of particle `i` (AVX2/FMA): `Σ ω_d v_c V_j |ξ| e` and, with `W`,
/// `Σ v v_c V_j |ξ| e` over its bonds.
#[target_feature(enable = "avx2,fma")]
pub(super) unsafe fn dilatation_sums<const W: bool, const D: bool, const SMALL: bool>(
    row: &Row,
    pos: &[Vec3],
    reference: &[Vec3],
    i: usize,
) -> (f64, f64) {
    let (at, shift) = if SMALL {
        (splat(reference[i]), splat(pos[i] - reference[i]))
    } else {
        (splat(pos[i]), splat(Vec3::zeros()))
    };
    let (mut sum, mut dev) = (_mm256_setzero_pd(), _mm256_setzero_pd());
    let mut k = 0;
    while k < row.partner.len() {
        let j = partners4(row.partner, k);
        let l = lengths4(row.length, k);
        let (e, _, _) = bonds4::<SMALL, false>(pos, reference, &j, at, shift, l);
        let w = _mm256_mul_pd(_mm256_mul_pd(load4(row.volume, k), l), e);
        sum = if D {
            _mm256_fmadd_pd(w, load4s(row.dil_own, k, 0.0), sum)
        } else {
            _mm256_add_pd(sum, w)
        };
        if W {
            dev = _mm256_fmadd_pd(w, load4s(row.dev_own, k, 0.0), dev);
        }
        k += 4;
    }
    (hsum(sum), hsum(dev))
}

/// The force sweep of particle `i` (AVX2/FMA): `Σ t ω v_c V_j M` over its bonds, the scalar
/// state `t = a_i ω_d,i|ξ| + b_i v_i (e − c_i|ξ|) + a_j ω_d,j|ξ| + b_j v_j (e − c_j|ξ|)` from
/// the particles' constants `state` (a mirror image `j ≥ real` takes its `source`'s).
#[target_feature(enable = "avx2,fma")]
#[allow(clippy::too_many_arguments)]
pub(super) unsafe fn force_sum<const W: bool, const D: bool, const SMALL: bool>(
    row: &Row,
    pos: &[Vec3],
    reference: &[Vec3],
    state: &[Vec3],
    source: &[u32],
    real: usize,
    i: usize,
) -> Vec3 {
    let (at, shift) = if SMALL {
        (splat(reference[i]), splat(pos[i] - reference[i]))
    } else {
        (splat(pos[i]), splat(Vec3::zeros()))
    };
    let [ai, bi, ci] = splat(state[i]);
    let mut f = [_mm256_setzero_pd(); 3];
    let mut k = 0;
    while k < row.partner.len() {
        let j = partners4(row.partner, k);
        let src = j.map(|j| {
            let j = j as usize;
            if j < real {
                j as u32
            } else {
                source[j - real]
            }
        });
        let l = lengths4(row.length, k);
        let (e, dir, inv) = bonds4::<SMALL, true>(pos, reference, &j, at, shift, l);
        let [aj, bj, cj] = gather4(state, &src);
        let (vi, vj) = if W {
            (load4s(row.dev_own, k, 0.0), load4s(row.dev_partner, k, 0.0))
        } else {
            (_mm256_set1_pd(1.0), _mm256_set1_pd(1.0))
        };
        let (di, dj) = if D {
            (load4s(row.dil_own, k, 0.0), load4s(row.dil_partner, k, 0.0))
        } else {
            (_mm256_set1_pd(1.0), _mm256_set1_pd(1.0))
        };
        // a_i d_i l + a_j d_j l + b_i v_i (e − c_i l) + b_j v_j (e − c_j l)
        let dil = _mm256_mul_pd(_mm256_fmadd_pd(ai, di, _mm256_mul_pd(aj, dj)), l);
        let own = _mm256_mul_pd(_mm256_mul_pd(bi, vi), _mm256_fnmadd_pd(ci, l, e));
        let other = _mm256_mul_pd(_mm256_mul_pd(bj, vj), _mm256_fnmadd_pd(cj, l, e));
        let t = _mm256_add_pd(_mm256_add_pd(dil, own), other);
        let s = _mm256_mul_pd(_mm256_mul_pd(t, load4(row.volume, k)), inv);
        for (fa, d) in f.iter_mut().zip(dir) {
            *fa = _mm256_fmadd_pd(d, s, *fa);
        }
        k += 4;
    }
    Vec3::new(hsum(f[0]), hsum(f[1]), hsum(f[2]))
}
