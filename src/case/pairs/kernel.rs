//! The bond-force kernels of [`pair_forces`](super::pair_forces): the sum of one particle's bonds,
//! portable and in AVX2/FMA.

use crate::case::neighbours::BondList;
use crate::math::Vec3;

/// Where a pass subtracts each bond's force from its partner `j`: `buf[j − first]`, for the
/// partners within `first..first + buf.len()` (a thread's particles); the others are not its
/// to write.
pub(super) struct Scatter<'a> {
    pub buf: &'a mut [Vec3],
    pub first: usize,
}

impl Scatter<'_> {
    /// Nowhere: the bonds to mirror images act on their particle only.
    pub fn none() -> Scatter<'static> {
        Scatter {
            buf: &mut [],
            first: 0,
        }
    }

    #[inline(always)]
    fn at(&mut self, j: usize) -> Option<&mut Vec3> {
        self.buf.get_mut(j.wrapping_sub(self.first))
    }
}

/// The force of the bonds in row `row` of `bonds` (weights `w`) on their particle `i`: with
/// finite kinematics (`reference` is `None`) `Σ_j w_ij (|y_ij| − L_ij) y_ij/|y_ij|`,
/// `y_ij = pos[j] − pos[i]` (Eq. 26 times the volumes); linearised,
/// `Σ_j w_ij ((η_ij·ξ_ij)/|ξ_ij|²) ξ_ij` with `ξ_ij = X_j − X_i` and `η_ij = u_j − u_i` from
/// `reference`. With `SCATTER`, each bond's force is also subtracted from its partner's entry
/// in `out` (the pairs). Each bond's force has the same bits whichever row and group it is
/// computed in. AVX2/FMA where the processor has them.
#[inline]
#[allow(clippy::too_many_arguments)]
pub(super) fn bond_sum<const SCATTER: bool>(
    bonds: &BondList,
    w: &[f32],
    pos: &[Vec3],
    reference: Option<&[Vec3]>,
    row: usize,
    i: usize,
    out: &mut Scatter,
) -> Vec3 {
    #[cfg(target_arch = "x86_64")]
    {
        if has_avx2_fma() {
            // SAFETY: the processor has the features; every access is bounds-checked.
            return unsafe { bond_sum_avx2::<SCATTER>(bonds, w, pos, reference, row, i, out) };
        }
    }
    bond_sum_portable::<SCATTER>(bonds, w, pos, reference, row, i, out)
}

/// [`bond_sum`] one bond at a time.
#[inline(always)]
fn bond_sum_portable<const SCATTER: bool>(
    bonds: &BondList,
    w: &[f32],
    pos: &[Vec3],
    reference: Option<&[Vec3]>,
    row: usize,
    i: usize,
    out: &mut Scatter,
) -> Vec3 {
    let mut acc = Vec3::zeros();
    for b in bonds.range(row) {
        let j = bonds.partner[b] as usize;
        let wb = f64::from(w[b]);
        let f = match reference {
            None => {
                let y = pos[j] - pos[i];
                let l = y.norm();
                y * (wb * (l - bonds.length(b)) / l)
            }
            Some(x) => {
                let xi = x[j] - x[i];
                let eta = pos[j] - x[j] - (pos[i] - x[i]);
                xi * (wb * eta.dot(&xi) / xi.norm_squared())
            }
        };
        acc += f;
        if SCATTER {
            if let Some(e) = out.at(j) {
                *e -= f;
            }
        }
    }
    acc
}

/// Whether the processor has AVX2 and FMA (the standard library caches the answer).
#[cfg(target_arch = "x86_64")]
#[inline]
pub(crate) fn has_avx2_fma() -> bool {
    std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
}

/// The coordinates of four partners, transposed into x, y and z lanes. Indexing checks each
/// partner against the array's length: a bad list panics, never reads outside it.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
pub(crate) unsafe fn gather4(v: &[Vec3], j: &[u32]) -> [std::arch::x86_64::__m256d; 3] {
    use std::arch::x86_64::*;
    let p: [*const f64; 4] =
        std::array::from_fn(|m| (&v[j[m] as usize] as *const Vec3).cast::<f64>());
    let a = _mm256_insertf128_pd::<1>(
        _mm256_castpd128_pd256(_mm_loadu_pd(p[0])),
        _mm_loadu_pd(p[2]),
    );
    let b = _mm256_insertf128_pd::<1>(
        _mm256_castpd128_pd256(_mm_loadu_pd(p[1])),
        _mm_loadu_pd(p[3]),
    );
    [
        _mm256_unpacklo_pd(a, b),
        _mm256_unpackhi_pd(a, b),
        _mm256_set_pd(*p[3].add(2), *p[2].add(2), *p[1].add(2), *p[0].add(2)),
    ]
}

/// Subtracts the forces of the first `j.len()` (at most four) lanes (x, y, z) from their
/// partners' entries in `out` (`len` entries for the particles from `first` on), where they
/// are its to write.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
unsafe fn scatter_sub4(
    out: *mut Vec3,
    len: usize,
    first: usize,
    j: &[u32],
    f: [std::arch::x86_64::__m256d; 3],
) {
    use std::arch::x86_64::*;
    let [fx, fy, fz] = f;
    // (x, y) pairs of lanes 0 and 2, 1 and 3: the transpose of `gather4`.
    let a = _mm256_unpacklo_pd(fx, fy);
    let b = _mm256_unpackhi_pd(fx, fy);
    let xy = [
        _mm256_castpd256_pd128(a),
        _mm256_castpd256_pd128(b),
        _mm256_extractf128_pd::<1>(a),
        _mm256_extractf128_pd::<1>(b),
    ];
    let mut z = [0.0f64; 4];
    _mm256_storeu_pd(z.as_mut_ptr(), fz);
    for m in 0..j.len() {
        let at = (j[m] as usize).wrapping_sub(first);
        if at < len {
            // SAFETY: `at` is within the `len` entries behind `out`.
            let p = out.add(at).cast::<f64>();
            _mm_storeu_pd(p, _mm_sub_pd(_mm_loadu_pd(p), xy[m]));
            *p.add(2) -= z[m];
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
pub(crate) unsafe fn hsum(v: std::arch::x86_64::__m256d) -> f64 {
    use std::arch::x86_64::*;
    let mut l = [0.0f64; 4];
    _mm256_storeu_pd(l.as_mut_ptr(), v);
    (l[0] + l[1]) + (l[2] + l[3])
}

/// [`bond_sum`] in AVX2/FMA, four bonds per step, the last group padded. Finite kinematics:
/// `1/|y|` from the single-precision estimate refined by two Newton steps (relative error
/// about 1e-13), which keeps the square root and the division off the divider unit that
/// bounds the plain loop.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn bond_sum_avx2<const SCATTER: bool>(
    bonds: &BondList,
    w: &[f32],
    pos: &[Vec3],
    reference: Option<&[Vec3]>,
    row: usize,
    i: usize,
    out: &mut Scatter,
) -> Vec3 {
    // One loop per kinematics, so that the choice is not made per group of bonds.
    match reference {
        None => bond_group_sum::<SCATTER, false>(bonds, w, pos, &[], row, i, out),
        Some(x) => bond_group_sum::<SCATTER, true>(bonds, w, pos, x, row, i, out),
    }
}

/// The groups of four of [`bond_sum_avx2`]; `SMALL` selects the linearised kinematics (then
/// `reference` holds the reference positions).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
#[allow(clippy::too_many_arguments)]
unsafe fn bond_group_sum<const SCATTER: bool, const SMALL: bool>(
    bonds: &BondList,
    w: &[f32],
    pos: &[Vec3],
    reference: &[Vec3],
    row: usize,
    i: usize,
    out: &mut Scatter,
) -> Vec3 {
    use std::arch::x86_64::*;
    let range = bonds.range(row);
    let (base, len_out, first) = (out.buf.as_mut_ptr(), out.buf.len(), out.first);
    let partner = &bonds.partner[range.clone()];
    let length = &bonds.length[range.clone()];
    let w4 = &w[range.clone()];
    let splat = |v: Vec3| {
        [
            _mm256_set1_pd(v.x),
            _mm256_set1_pd(v.y),
            _mm256_set1_pd(v.z),
        ]
    };
    let [cx, cy, cz] = splat(pos[i]);
    let xi0 = if SMALL { reference[i] } else { Vec3::zeros() };
    let [rx, ry, rz] = splat(xi0);
    let [ux, uy, uz] = splat(if SMALL { pos[i] - xi0 } else { Vec3::zeros() });
    let (one, three_halves, half) = (
        _mm256_set1_pd(1.0),
        _mm256_set1_pd(1.5),
        _mm256_set1_pd(0.5),
    );
    let (mut ax, mut ay, mut az) = (
        _mm256_setzero_pd(),
        _mm256_setzero_pd(),
        _mm256_setzero_pd(),
    );
    let len = partner.len();
    for g in 0..len / 4 {
        let k = 4 * g;
        let j = &partner[k..k + 4];
        let wb = _mm256_cvtps_pd(_mm_loadu_ps(w4[k..k + 4].as_ptr()));
        let [px, py, pz] = gather4(pos, j);
        let f = if !SMALL {
            let (dx, dy, dz) = (
                _mm256_sub_pd(px, cx),
                _mm256_sub_pd(py, cy),
                _mm256_sub_pd(pz, cz),
            );
            let r2 = _mm256_fmadd_pd(dz, dz, _mm256_fmadd_pd(dy, dy, _mm256_mul_pd(dx, dx)));
            let mut inv = _mm256_cvtps_pd(_mm_rsqrt_ps(_mm256_cvtpd_ps(r2)));
            let h = _mm256_mul_pd(half, r2);
            for _ in 0..2 {
                let t = _mm256_mul_pd(inv, inv);
                inv = _mm256_mul_pd(inv, _mm256_fnmadd_pd(h, t, three_halves));
            }
            let l0 = _mm256_cvtps_pd(_mm_loadu_ps(length[k..k + 4].as_ptr()));
            // w (|y| − L)/|y| = w (1 − L/|y|)
            let s = _mm256_mul_pd(wb, _mm256_fnmadd_pd(l0, inv, one));
            [
                _mm256_mul_pd(dx, s),
                _mm256_mul_pd(dy, s),
                _mm256_mul_pd(dz, s),
            ]
        } else {
            let [qx, qy, qz] = gather4(reference, j);
            // ξ = X_j − X_i; η = (y_j − X_j) − u_i.
            let (sx, sy, sz) = (
                _mm256_sub_pd(qx, rx),
                _mm256_sub_pd(qy, ry),
                _mm256_sub_pd(qz, rz),
            );
            let (ex, ey, ez) = (
                _mm256_sub_pd(_mm256_sub_pd(px, qx), ux),
                _mm256_sub_pd(_mm256_sub_pd(py, qy), uy),
                _mm256_sub_pd(_mm256_sub_pd(pz, qz), uz),
            );
            let dot = _mm256_fmadd_pd(ez, sz, _mm256_fmadd_pd(ey, sy, _mm256_mul_pd(ex, sx)));
            let len2 = _mm256_fmadd_pd(sz, sz, _mm256_fmadd_pd(sy, sy, _mm256_mul_pd(sx, sx)));
            let s = _mm256_div_pd(_mm256_mul_pd(wb, dot), len2);
            [
                _mm256_mul_pd(sx, s),
                _mm256_mul_pd(sy, s),
                _mm256_mul_pd(sz, s),
            ]
        };
        ax = _mm256_add_pd(ax, f[0]);
        ay = _mm256_add_pd(ay, f[1]);
        az = _mm256_add_pd(az, f[2]);
        if SCATTER {
            scatter_sub4(base, len_out, first, j, f);
        }
    }
    // The last bonds one at a time, with the operations of a lane above, so that a bond's
    // force has the same bits whether it falls in a group or here: a list cut short (a
    // thread's halo, a rank's ghost rows) gives its bonds the bits of the whole list.
    let mut tail = Vec3::zeros();
    for k in 4 * (len / 4)..len {
        let jk = partner[k] as usize;
        let wb = f64::from(w4[k]);
        let p = pos[jk];
        let f = if !SMALL {
            let d = p - pos[i];
            let r2 = d.z.mul_add(d.z, d.y.mul_add(d.y, d.x * d.x));
            let mut inv = f64::from(_mm_cvtss_f32(_mm_rsqrt_ps(_mm_set1_ps(r2 as f32))));
            let h = 0.5 * r2;
            for _ in 0..2 {
                let t = inv * inv;
                inv *= (-h).mul_add(t, 1.5);
            }
            d * (wb * (-f64::from(length[k])).mul_add(inv, 1.0))
        } else {
            let q = reference[jk];
            let sx = q - xi0;
            let e = (p - q) - (pos[i] - xi0);
            let dot = e.z.mul_add(sx.z, e.y.mul_add(sx.y, e.x * sx.x));
            let len2 = sx.z.mul_add(sx.z, sx.y.mul_add(sx.y, sx.x * sx.x));
            sx * ((wb * dot) / len2)
        };
        tail += f;
        if SCATTER {
            let at = jk.wrapping_sub(first);
            if at < len_out {
                // SAFETY: `at` is within the `len_out` entries behind `base`.
                *base.add(at) -= f;
            }
        }
    }
    Vec3::new(hsum(ax), hsum(ay), hsum(az)) + tail
}
