//! The bond-force pass over each bond pair once (Newton's third law), as LAMMPS's `newton on`
//! half neighbour lists do.
//!
//! A bond's force on `i` is `w (|y| − L) y/|y|` (Eq. 26 times the volumes, finite kinematics)
//! or `w ((η·ξ)/|ξ|²) ξ` (linearised), and its force on `j` is the opposite, because the
//! weight `w = c G v_c V_i V_j / L` is symmetric (see [`crate::body`]). So each pair `i < j`
//! is stored once, with its partner, length and weight (12 bytes a pair, 6 a directed bond),
//! evaluated once, and added to both ends. The pass streams half the bytes and does half the
//! arithmetic of a pass over directed bonds; that matters most with several threads, which
//! share the memory bandwidth.
//!
//! Threads: the particles are cut into as many ranges as there are threads, with equal pair
//! counts; each range adds its forces into a buffer of its own (a pair's `j` may belong to
//! another range), and the buffers are summed in a fixed order. The result depends on the
//! thread count only through rounding, and is the same from run to run.
//!
//! Symmetry planes: bonds to mirror images (partners at or past the particle count) act on
//! the real particle only, so they stay directed, in a list of their own. A particle on a
//! plane holds a share `s_i` (½ per plane) of its volume while its partners see the whole, so
//! `w_ij = K V_i V_j / s_j` and `w_ji = K V_i V_j / s_i` differ; `w_ij / s_i` does not. The
//! pairs store that, and a particle's summed force is multiplied by its own share at the end.

use rayon::prelude::*;

use crate::case::neighbours::BondList;
use crate::math::Vec3;

/// Particles per work item of the summing pass.
const CHUNK: usize = 1024;

/// Bond pairs `i < j` between real particles (each once), and the directed bonds to mirror
/// images, each with its weight `w` (N/m).
#[derive(Clone, Debug, Default)]
pub struct PairList {
    /// Real particles.
    particles: usize,
    /// Per real particle: the share of its volume the model holds (empty: all 1).
    share: Vec<f64>,
    /// Pairs `(i, j > i)`: partner, reference length and weight, in compressed-row form.
    pairs: BondList,
    pair_weight: Vec<f32>,
    /// Directed bonds from a real particle to a mirror image.
    images: BondList,
    image_weight: Vec<f32>,
}

impl PairList {
    /// The pairs of a directed bond list over `particles` real particles (partners at or past
    /// it are mirror images), with the weight of each directed bond and the share of each
    /// particle (empty: no symmetry planes). The weight of a pair is that of its bond
    /// `i → j`, `i < j`, divided by `share[i]`.
    pub fn from_bonds(
        bonds: &BondList,
        weight: &[f32],
        share: &[f64],
        particles: usize,
    ) -> PairList {
        let share = if share.iter().all(|&s| s == 1.0) {
            Vec::new()
        } else {
            share.to_vec()
        };
        let scale = |i: usize| share.get(i).map_or(1.0, |&s| 1.0 / s);
        let split = |keep: &dyn Fn(usize, usize) -> bool| {
            let mut list = BondList {
                offsets: Vec::with_capacity(particles + 1),
                ..BondList::default()
            };
            let mut w = Vec::new();
            list.offsets.push(0);
            for i in 0..particles {
                for b in bonds.range(i) {
                    let j = bonds.partner[b] as usize;
                    if keep(i, j) {
                        list.partner.push(j as u32);
                        list.length.push(bonds.length[b]);
                        // Pairs: w_ij / s_i (symmetric); images: w_ij as it is.
                        let scale = if j < particles { scale(i) } else { 1.0 };
                        w.push((f64::from(weight[b]) * scale) as f32);
                    }
                }
                list.offsets.push(list.partner.len());
            }
            (list, w)
        };
        let (pairs, pair_weight) = split(&|i, j| i < j && j < particles);
        let (images, image_weight) = split(&|_, j| j >= particles);
        PairList {
            particles,
            share,
            pairs,
            pair_weight,
            images,
            image_weight,
        }
    }

    /// A pair list made directly (each pair once, no mirror images), with
    /// `weight(pairs, i, b)` the weight of pair `b` of particle `i`.
    pub fn from_pairs(
        pairs: BondList,
        weight: impl Fn(&BondList, usize, usize) -> f32 + Sync,
    ) -> PairList {
        let particles = pairs.particles();
        let mut pair_weight = vec![0f32; pairs.len()];
        pairs
            .blocks(&mut pair_weight, CHUNK)
            .into_par_iter()
            .for_each(|(range, w)| {
                let base = pairs.offsets[range.start];
                for i in range {
                    for b in pairs.range(i) {
                        w[b - base] = weight(&pairs, i, b);
                    }
                }
            });
        PairList {
            particles,
            share: Vec::new(),
            images: BondList {
                offsets: vec![0; particles + 1],
                ..BondList::default()
            },
            image_weight: Vec::new(),
            pairs,
            pair_weight,
        }
    }

    /// Real particles.
    pub fn particles(&self) -> usize {
        self.particles
    }

    /// Directed bonds: each pair counts twice, a bond to a mirror image once.
    pub fn directed_bonds(&self) -> usize {
        2 * self.pairs.len() + self.images.len()
    }

    /// Bytes held by the arrays.
    pub fn bytes(&self) -> usize {
        self.pairs.bytes()
            + self.images.bytes()
            + 4 * (self.pair_weight.len() + self.image_weight.len())
    }

    /// Strain energy `¼ Σ_pairs (w_ij + w_ji) (|y| − L)² + ¼ Σ_images w (|y| − L)²` at
    /// positions `pos` (finite kinematics): a bond to an image carries the half of its
    /// mirrored pair that belongs to this model.
    pub fn strain_energy(&self, pos: &[Vec3]) -> f64 {
        let term = |list: &BondList, w: &[f32], i: usize| -> f64 {
            list.range(i)
                .map(|b| {
                    let s = (pos[list.partner[b] as usize] - pos[i]).norm() - list.length(b);
                    f64::from(w[b]) * s * s
                })
                .sum()
        };
        crate::reduction::ordered_sum(self.particles, |i| {
            let si = self.share.get(i).copied().unwrap_or(1.0);
            let pairs = &self.pairs;
            let paired: f64 = pairs
                .range(i)
                .map(|b| {
                    let j = pairs.partner[b] as usize;
                    let sj = self.share.get(j).copied().unwrap_or(1.0);
                    let s = (pos[j] - pos[i]).norm() - pairs.length(b);
                    (si + sj) * f64::from(self.pair_weight[b]) * s * s
                })
                .sum();
            0.25 * paired + 0.25 * term(&self.images, &self.image_weight, i)
        })
    }

    /// Ranges of particles with about equal numbers of pairs, one per part.
    fn partition(&self, parts: usize) -> Vec<std::ops::Range<usize>> {
        let n = self.particles;
        let offsets = &self.pairs.offsets;
        let total = self.pairs.len() + n;
        // Work up to particle k: its pairs plus one unit per particle.
        let work = |k: usize| offsets[k] + k;
        let mut bounds = vec![0];
        for p in 1..parts {
            let target = total * p / parts;
            let (mut lo, mut hi) = (*bounds.last().unwrap_or(&0), n);
            while lo < hi {
                let mid = (lo + hi) / 2;
                if work(mid) < target {
                    lo = mid + 1;
                } else {
                    hi = mid;
                }
            }
            bounds.push(lo);
        }
        bounds.push(n);
        bounds.windows(2).map(|w| w[0]..w[1]).collect()
    }
}

/// Per-thread force buffers of [`pair_forces`], kept between calls so that the time loop does
/// not allocate.
#[derive(Clone, Debug, Default)]
pub struct ForceBuffers {
    buffers: Vec<Vec<Vec3>>,
}

/// How bonds stretch.
#[derive(Clone, Copy, Debug)]
pub enum PairKinematics<'a> {
    /// `w (|y| − L) y/|y|`.
    Finite,
    /// `w ((η·ξ)/|ξ|²) ξ`, with the reference positions (real particles, then images).
    Small(&'a [Vec3]),
}

/// Bond forces at positions `pos` (real particles, then mirror images): for every real
/// particle `i`, `finish(i, f_i)` receives its total bond force and returns the value stored
/// in `out[i]` (so that a solver can add loads or kick velocities in the same pass).
pub fn pair_forces<T: Send>(
    list: &PairList,
    pos: &[Vec3],
    kinematics: PairKinematics,
    buffers: &mut ForceBuffers,
    out: &mut [T],
    finish: impl Fn(usize, Vec3, &mut T) + Sync,
) {
    let n = list.particles;
    assert!(out.len() == n && pos.len() >= n);
    // The kernels take the reference positions for linearised kinematics, none for finite.
    let reference = match kinematics {
        PairKinematics::Finite => None,
        PairKinematics::Small(x) => {
            assert!(x.len() >= pos.len());
            Some(x)
        }
    };
    let parts = rayon::current_num_threads().clamp(1, 64).min(n.max(1));
    let ranges = list.partition(parts);
    buffers.buffers.resize_with(parts, Vec::new);
    buffers.buffers.truncate(parts);
    buffers
        .buffers
        .par_iter_mut()
        .zip(ranges.par_iter())
        .for_each(|(buf, range)| {
            buf.clear();
            buf.resize(n, Vec3::zeros());
            for i in range.clone() {
                let f = bond_sum::<true>(&list.pairs, &list.pair_weight, pos, reference, i, buf);
                buf[i] += f;
            }
        });
    let buffers = &buffers.buffers;
    out.par_chunks_mut(CHUNK).enumerate().for_each(|(c, out)| {
        for (k, o) in out.iter_mut().enumerate() {
            let i = c * CHUNK + k;
            let mut f = buffers[0][i];
            for b in &buffers[1..] {
                f += b[i];
            }
            if let Some(&s) = list.share.get(i) {
                f *= s;
            }
            // Bonds to mirror images act on `i` alone.
            if !list.images.range(i).is_empty() {
                f +=
                    bond_sum::<false>(&list.images, &list.image_weight, pos, reference, i, &mut []);
            }
            finish(i, f, o);
        }
    });
}

/// The force of particle `i`'s bonds in `bonds` (weights `w`) on `i`: with finite kinematics
/// (`reference` is `None`) `Σ_j w_ij (|y_ij| − L_ij) y_ij/|y_ij|`, `y_ij = pos[j] − pos[i]`
/// (Eq. 26 times the volumes); linearised, `Σ_j w_ij ((η_ij·ξ_ij)/|ξ_ij|²) ξ_ij` with
/// `ξ_ij = X_j − X_i` and `η_ij = u_j − u_i` from `reference`. With `SCATTER`, each bond's
/// force is also subtracted from `buf[j]` (the pairs); without, `buf` is not touched (the
/// directed bonds to mirror images). AVX2/FMA where the processor has them.
#[inline]
fn bond_sum<const SCATTER: bool>(
    bonds: &BondList,
    w: &[f32],
    pos: &[Vec3],
    reference: Option<&[Vec3]>,
    i: usize,
    buf: &mut [Vec3],
) -> Vec3 {
    #[cfg(target_arch = "x86_64")]
    {
        if has_avx2_fma() {
            // SAFETY: the processor has the features; every access is bounds-checked.
            return unsafe { bond_sum_avx2::<SCATTER>(bonds, w, pos, reference, i, buf) };
        }
    }
    bond_sum_portable::<SCATTER>(bonds, w, pos, reference, i, buf, bonds.range(i))
}

/// [`bond_sum`] over the bonds `range`, one at a time.
#[inline(always)]
fn bond_sum_portable<const SCATTER: bool>(
    bonds: &BondList,
    w: &[f32],
    pos: &[Vec3],
    reference: Option<&[Vec3]>,
    i: usize,
    buf: &mut [Vec3],
    range: std::ops::Range<usize>,
) -> Vec3 {
    let mut acc = Vec3::zeros();
    for b in range {
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
            buf[j] -= f;
        }
    }
    acc
}

/// Whether the processor has AVX2 and FMA (the standard library caches the answer).
#[cfg(target_arch = "x86_64")]
#[inline]
fn has_avx2_fma() -> bool {
    std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
}

/// The coordinates of four partners, transposed into x, y and z lanes. Indexing checks each
/// partner against the array's length: a bad list panics, never reads outside it.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
unsafe fn gather4(v: &[Vec3], j: &[u32]) -> [std::arch::x86_64::__m256d; 3] {
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

/// Subtracts four forces (x, y, z lanes) from the buffer entries of four distinct partners.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
unsafe fn scatter_sub4(buf: &mut [Vec3], j: &[u32], f: [std::arch::x86_64::__m256d; 3]) {
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
    for m in 0..4 {
        let p = (&mut buf[j[m] as usize] as *mut Vec3).cast::<f64>();
        _mm_storeu_pd(p, _mm_sub_pd(_mm_loadu_pd(p), xy[m]));
        *p.add(2) -= z[m];
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
unsafe fn hsum(v: std::arch::x86_64::__m256d) -> f64 {
    use std::arch::x86_64::*;
    let mut l = [0.0f64; 4];
    _mm256_storeu_pd(l.as_mut_ptr(), v);
    (l[0] + l[1]) + (l[2] + l[3])
}

/// [`bond_sum`] in AVX2/FMA, four bonds per step, the rest one at a time. Finite kinematics:
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
    i: usize,
    buf: &mut [Vec3],
) -> Vec3 {
    // One loop per kinematics, so that the choice is not made per group of bonds.
    let acc = match reference {
        None => bond_group_sum::<SCATTER, false>(bonds, w, pos, &[], i, buf),
        Some(x) => bond_group_sum::<SCATTER, true>(bonds, w, pos, x, i, buf),
    };
    let range = bonds.range(i);
    let rest = range.start + 4 * (range.len() / 4)..range.end;
    acc + bond_sum_portable::<SCATTER>(bonds, w, pos, reference, i, buf, rest)
}

/// The groups of four of [`bond_sum_avx2`]; `SMALL` selects the linearised kinematics (then
/// `reference` holds the reference positions).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
unsafe fn bond_group_sum<const SCATTER: bool, const SMALL: bool>(
    bonds: &BondList,
    w: &[f32],
    pos: &[Vec3],
    reference: &[Vec3],
    i: usize,
    buf: &mut [Vec3],
) -> Vec3 {
    use std::arch::x86_64::*;
    let range = bonds.range(i);
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
    let groups = partner.len() / 4;
    for g in 0..groups {
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
            scatter_sub4(buf, j, f);
        }
    }
    Vec3::new(hsum(ax), hsum(ay), hsum(az))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::case::neighbours::build_bonds;

    /// Forces of the pair pass against a direct sum over directed bonds, for both
    /// kinematics and several thread counts.
    #[test]
    fn pair_pass_matches_directed_sum() {
        let n = 9;
        let x: Vec<Vec3> = (0..n * n * n)
            .map(|i| Vec3::new((i % n) as f64, ((i / n) % n) as f64, (i / (n * n)) as f64) * 0.1)
            .collect();
        let bonds = build_bonds(&x, 0.35);
        // Shares of particles on symmetry planes (½ per plane) and the directed weights they
        // give, `w_ij = K_ij / s_j` with `K` symmetric and varying from bond to bond.
        let share: Vec<f64> = (0..x.len()).map(|i| [1.0, 0.5, 1.0, 0.25][i % 4]).collect();
        let mut weight = vec![0f32; bonds.len()];
        for i in 0..x.len() {
            for b in bonds.range(i) {
                let j = bonds.partner[b] as usize;
                let k = (1.0 + ((i.min(j) * 7 + i.max(j) * 13) % 11) as f64) * 1e3;
                weight[b] = (k / share[j]) as f32;
            }
        }
        let y: Vec<Vec3> = x
            .iter()
            .map(|p| p + Vec3::new((p.y * 7.0).sin(), (p.z * 5.0).cos(), p.x * p.y) * 0.01)
            .collect();
        let list = PairList::from_bonds(&bonds, &weight, &share, x.len());
        assert_eq!(list.directed_bonds(), bonds.len());
        // The strain energy against the directed sum `¼ Σ w_ij s²`.
        let directed_energy: f64 = (0..x.len())
            .flat_map(|i| bonds.range(i).map(move |b| (i, b)))
            .map(|(i, b)| {
                let s = (y[bonds.partner[b] as usize] - y[i]).norm() - bonds.length(b);
                0.25 * f64::from(weight[b]) * s * s
            })
            .sum();
        let e = list.strain_energy(&y);
        assert!(
            (e - directed_energy).abs() < 1e-9 * directed_energy,
            "{e} vs {directed_energy}"
        );
        for small in [false, true] {
            let direct: Vec<Vec3> = (0..x.len())
                .map(|i| {
                    bonds
                        .range(i)
                        .map(|b| {
                            let j = bonds.partner[b] as usize;
                            let w = f64::from(weight[b]);
                            if small {
                                let xi = x[j] - x[i];
                                xi * (w * (y[j] - x[j] - (y[i] - x[i])).dot(&xi)
                                    / xi.norm_squared())
                            } else {
                                let d = y[j] - y[i];
                                d * (w * (d.norm() - bonds.length(b)) / d.norm())
                            }
                        })
                        .sum()
                })
                .collect();
            for threads in [1, 2, 3] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let mut out = vec![Vec3::zeros(); x.len()];
                let mut buffers = ForceBuffers::default();
                pool.install(|| {
                    let kin = if small {
                        PairKinematics::Small(&x)
                    } else {
                        PairKinematics::Finite
                    };
                    pair_forces(&list, &y, kin, &mut buffers, &mut out, |_, f, o| *o = f);
                });
                for i in 0..x.len() {
                    let scale = direct[i].norm().max(1.0);
                    assert!(
                        (out[i] - direct[i]).norm() < 1e-9 * scale,
                        "small {small} threads {threads} particle {i}: {} vs {}",
                        out[i],
                        direct[i]
                    );
                }
                // Newton's third law, with each particle's share: Σ f_i / s_i = 0.
                let total: Vec3 = out.iter().zip(&share).map(|(f, s)| f / *s).sum();
                assert!(total.norm() < 1e-6, "{total}");
            }
        }
    }

    #[test]
    fn partition_covers_the_particles() {
        let n = 6;
        let x: Vec<Vec3> = (0..n * n * n)
            .map(|i| Vec3::new((i % n) as f64, ((i / n) % n) as f64, (i / (n * n)) as f64))
            .collect();
        let bonds = build_bonds(&x, 2.1);
        let list = PairList::from_bonds(&bonds, &vec![1.0; bonds.len()], &[], x.len());
        for parts in 1..8 {
            let r = list.partition(parts);
            assert_eq!(r.len(), parts);
            assert_eq!(r[0].start, 0);
            assert_eq!(r[parts - 1].end, x.len());
            for w in r.windows(2) {
                assert_eq!(w[0].end, w[1].start);
            }
        }
    }
}
