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

use crate::discretize::Vec3;
use crate::neighbours::BondList;

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

    /// Pairs between real particles.
    pub fn pair_count(&self) -> usize {
        self.pairs.len()
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

    /// The pairs and their weights (partner, length, weight per pair of particle `i`).
    pub fn pairs(&self) -> (&BondList, &[f32]) {
        (&self.pairs, &self.pair_weight)
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
        (0..self.particles)
            .into_par_iter()
            .map(|i| {
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
            .sum()
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
    if let PairKinematics::Small(reference) = kinematics {
        assert!(reference.len() >= pos.len());
    }
    // Every partner indexes `pos` (real pairs below n): the vector kernels rely on it.
    debug_assert!(list.pairs.partner.iter().all(|&j| (j as usize) < n));
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
                let f = match kinematics {
                    PairKinematics::Finite => pair_force_finite(list, pos, i, buf),
                    PairKinematics::Small(x) => pair_force_small(list, pos, x, i, buf),
                };
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
            f += match kinematics {
                PairKinematics::Finite => image_force(list, pos, i, None),
                PairKinematics::Small(x) => image_force(list, pos, i, Some(x)),
            };
            finish(i, f, o);
        }
    });
}

/// The force of particle `i`'s bonds to mirror images (directed: on `i` only).
#[inline]
fn image_force(list: &PairList, pos: &[Vec3], i: usize, reference: Option<&[Vec3]>) -> Vec3 {
    if list.images.range(i).is_empty() {
        return Vec3::zeros();
    }
    match reference {
        None => directed_force(pos, &list.images, &list.image_weight, i),
        Some(x) => directed_force_small(pos, x, &list.images, &list.image_weight, i),
    }
}

/// The force of directed bonds (here: those to mirror images) on particle `i`, finite
/// kinematics: `Σ_j w_ij (|y_ij| − L_ij) y_ij/|y_ij|` with `y_ij = pos[j] − pos[i]`. AVX2/FMA
/// where the processor has them, as the pair kernels.
#[inline]
fn directed_force(pos: &[Vec3], bonds: &BondList, w: &[f32], i: usize) -> Vec3 {
    #[cfg(target_arch = "x86_64")]
    {
        if has_avx2_fma() {
            // SAFETY: the processor supports the features `directed_force_avx2` is compiled for.
            return unsafe { directed_force_avx2(pos, bonds, w, i) };
        }
    }
    directed_force_portable(pos, bonds, w, i)
}

/// The bond force on particle `i` with the bond kinematics linearised (Eq. 26 with the
/// extension measured along the reference bond ξ): `Σ_j w_ij ((η_ij·ξ_ij)/|ξ_ij|²) ξ_ij`, where
/// `η_ij = u_j − u_i` from the current and reference positions. Dispatched as [`directed_force`].
#[inline]
fn directed_force_small(
    pos: &[Vec3],
    reference: &[Vec3],
    bonds: &BondList,
    w: &[f32],
    i: usize,
) -> Vec3 {
    #[cfg(target_arch = "x86_64")]
    {
        if has_avx2_fma() {
            // SAFETY: the processor supports the features the function is compiled for.
            return unsafe { directed_force_small_avx2(pos, reference, bonds, w, i) };
        }
    }
    let ui = pos[i] - reference[i];
    let mut acc = Vec3::zeros();
    for b in bonds.range(i) {
        let j = bonds.partner[b] as usize;
        let xi = reference[j] - reference[i];
        let eta = pos[j] - reference[j] - ui;
        acc += xi * (f64::from(w[b]) * eta.dot(&xi) / xi.norm_squared());
    }
    acc
}

/// [`directed_force_small`] in AVX2/FMA intrinsics, four bonds per step (see [`directed_force_avx2`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn directed_force_small_avx2(
    pos: &[Vec3],
    reference: &[Vec3],
    bonds: &BondList,
    w: &[f32],
    i: usize,
) -> Vec3 {
    use std::arch::x86_64::*;
    let range = bonds.range(i);
    let partner = &bonds.partner[range.clone()];
    let w = &w[range];
    let (xi0, ui) = (reference[i], pos[i] - reference[i]);
    let (rx, ry, rz) = (
        _mm256_set1_pd(xi0.x),
        _mm256_set1_pd(xi0.y),
        _mm256_set1_pd(xi0.z),
    );
    let (ux, uy, uz) = (
        _mm256_set1_pd(ui.x),
        _mm256_set1_pd(ui.y),
        _mm256_set1_pd(ui.z),
    );
    let (mut ax, mut ay, mut az) = (
        _mm256_setzero_pd(),
        _mm256_setzero_pd(),
        _mm256_setzero_pd(),
    );
    // Indexing checks each partner against the arrays' lengths.
    let lanes = |v: &[Vec3], k: usize| -> [__m256d; 3] {
        let p: [*const f64; 4] =
            std::array::from_fn(|m| (&v[partner[k + m] as usize] as *const Vec3).cast::<f64>());
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
    };
    let groups = partner.len() / 4;
    for g in 0..groups {
        let k = 4 * g;
        let [px, py, pz] = lanes(pos, k);
        let [qx, qy, qz] = lanes(reference, k);
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
        let wb = _mm256_cvtps_pd(_mm_loadu_ps(w[k..k + 4].as_ptr()));
        let s = _mm256_div_pd(_mm256_mul_pd(wb, dot), len2);
        ax = _mm256_fmadd_pd(sx, s, ax);
        ay = _mm256_fmadd_pd(sy, s, ay);
        az = _mm256_fmadd_pd(sz, s, az);
    }
    let sum = |v: __m256d| -> f64 {
        let mut l = [0.0f64; 4];
        _mm256_storeu_pd(l.as_mut_ptr(), v);
        (l[0] + l[1]) + (l[2] + l[3])
    };
    let mut acc = Vec3::new(sum(ax), sum(ay), sum(az));
    for k in 4 * groups..partner.len() {
        let j = partner[k] as usize;
        let xi = reference[j] - xi0;
        let eta = pos[j] - reference[j] - ui;
        acc += xi * (f64::from(w[k]) * eta.dot(&xi) / xi.norm_squared());
    }
    acc
}

/// [`directed_force`] in AVX2/FMA intrinsics: four bonds per step; the partners' coordinates are
/// loaded as (x, y) pairs and z and transposed into lanes; `1/|y|` comes from the
/// single-precision estimate refined by two Newton steps (relative error about 1e-13), which
/// keeps the square root and the division off the divider unit that bounds the plain loop.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn directed_force_avx2(pos: &[Vec3], bonds: &BondList, w: &[f32], i: usize) -> Vec3 {
    use std::arch::x86_64::*;
    let range = bonds.range(i);
    let partner = &bonds.partner[range.clone()];
    let length = &bonds.length[range.clone()];
    let w = &w[range];
    let yi = pos[i];
    let (cx, cy, cz) = (
        _mm256_set1_pd(yi.x),
        _mm256_set1_pd(yi.y),
        _mm256_set1_pd(yi.z),
    );
    let one = _mm256_set1_pd(1.0);
    let three_halves = _mm256_set1_pd(1.5);
    let half = _mm256_set1_pd(0.5);
    let (mut ax, mut ay, mut az) = (
        _mm256_setzero_pd(),
        _mm256_setzero_pd(),
        _mm256_setzero_pd(),
    );
    // Indexing `pos` checks each partner against its length: a bad list panics, never reads
    // outside the array. A `Vec3` is three contiguous f64.
    let coords = |j: u32| -> *const f64 { (&pos[j as usize] as *const Vec3).cast::<f64>() };
    let groups = partner.len() / 4;
    for g in 0..groups {
        let k = 4 * g;
        let (p0, p1, p2, p3) = (
            coords(partner[k]),
            coords(partner[k + 1]),
            coords(partner[k + 2]),
            coords(partner[k + 3]),
        );
        let a =
            _mm256_insertf128_pd::<1>(_mm256_castpd128_pd256(_mm_loadu_pd(p0)), _mm_loadu_pd(p2));
        let b =
            _mm256_insertf128_pd::<1>(_mm256_castpd128_pd256(_mm_loadu_pd(p1)), _mm_loadu_pd(p3));
        let dx = _mm256_sub_pd(_mm256_unpacklo_pd(a, b), cx);
        let dy = _mm256_sub_pd(_mm256_unpackhi_pd(a, b), cy);
        let dz = _mm256_sub_pd(
            _mm256_set_pd(*p3.add(2), *p2.add(2), *p1.add(2), *p0.add(2)),
            cz,
        );
        let r2 = _mm256_fmadd_pd(dz, dz, _mm256_fmadd_pd(dy, dy, _mm256_mul_pd(dx, dx)));
        let mut inv = _mm256_cvtps_pd(_mm_rsqrt_ps(_mm256_cvtpd_ps(r2)));
        let h = _mm256_mul_pd(half, r2);
        for _ in 0..2 {
            let t = _mm256_mul_pd(inv, inv);
            inv = _mm256_mul_pd(inv, _mm256_fnmadd_pd(h, t, three_halves));
        }
        let l0 = _mm256_cvtps_pd(_mm_loadu_ps(length[k..k + 4].as_ptr()));
        let wb = _mm256_cvtps_pd(_mm_loadu_ps(w[k..k + 4].as_ptr()));
        // w (|y| − L)/|y| = w (1 − L/|y|)
        let s = _mm256_mul_pd(wb, _mm256_fnmadd_pd(l0, inv, one));
        ax = _mm256_fmadd_pd(dx, s, ax);
        ay = _mm256_fmadd_pd(dy, s, ay);
        az = _mm256_fmadd_pd(dz, s, az);
    }
    let sum = |v: __m256d| -> f64 {
        let mut lanes = [0.0f64; 4];
        _mm256_storeu_pd(lanes.as_mut_ptr(), v);
        (lanes[0] + lanes[1]) + (lanes[2] + lanes[3])
    };
    let mut f = Vec3::new(sum(ax), sum(ay), sum(az));
    for k in 4 * groups..partner.len() {
        let y = pos[partner[k] as usize] - yi;
        let l = y.norm();
        f += y * (f64::from(w[k]) * (l - f64::from(length[k])) / l);
    }
    f
}

#[inline(always)]
fn directed_force_portable(pos: &[Vec3], bonds: &BondList, w: &[f32], i: usize) -> Vec3 {
    // Bonds go in groups of LANES with the partners gathered into plain arrays, so that the
    // square roots and divisions run as packed SIMD instructions.
    const LANES: usize = 4;
    let yi = pos[i];
    let range = bonds.range(i);
    let partner = &bonds.partner[range.clone()];
    let length = &bonds.length[range.clone()];
    let w = &w[range];
    let mut acc = [[0.0f64; LANES]; 3];
    let groups = partner
        .chunks_exact(LANES)
        .zip(length.chunks_exact(LANES))
        .zip(w.chunks_exact(LANES));
    for ((p, l0), wb) in groups {
        let mut d = [[0.0f64; LANES]; 3];
        for k in 0..LANES {
            let y = pos[p[k] as usize] - yi;
            d[0][k] = y.x;
            d[1][k] = y.y;
            d[2][k] = y.z;
        }
        for k in 0..LANES {
            let l = (d[0][k] * d[0][k] + d[1][k] * d[1][k] + d[2][k] * d[2][k]).sqrt();
            let s = f64::from(wb[k]) * (l - f64::from(l0[k])) / l;
            for a in 0..3 {
                acc[a][k] += d[a][k] * s;
            }
        }
    }
    let mut f = Vec3::new(
        acc[0].iter().sum(),
        acc[1].iter().sum(),
        acc[2].iter().sum(),
    );
    let tail = partner.len() - partner.len() % LANES;
    for ((&j, &l0), &wb) in partner[tail..].iter().zip(&length[tail..]).zip(&w[tail..]) {
        let y = pos[j as usize] - yi;
        let l = y.norm();
        f += y * (f64::from(wb) * (l - f64::from(l0)) / l);
    }
    f
}

/// Particle `i`'s pairs, finite kinematics: returns the force on `i` and subtracts each
/// pair's force from `buf[j]`.
#[inline]
fn pair_force_finite(list: &PairList, pos: &[Vec3], i: usize, buf: &mut [Vec3]) -> Vec3 {
    #[cfg(target_arch = "x86_64")]
    {
        if has_avx2_fma() {
            // SAFETY: the processor has the features; partners are real particles, below
            // `pos.len()` and `buf.len()` (checked by indexing inside).
            return unsafe { pair_force_finite_avx2(list, pos, i, buf) };
        }
    }
    pair_force_finite_portable(list, pos, i, buf, list.pairs.range(i))
}

#[inline(always)]
fn pair_force_finite_portable(
    list: &PairList,
    pos: &[Vec3],
    i: usize,
    buf: &mut [Vec3],
    range: std::ops::Range<usize>,
) -> Vec3 {
    let pairs = &list.pairs;
    let yi = pos[i];
    let mut acc = Vec3::zeros();
    for b in range {
        let j = pairs.partner[b] as usize;
        let y = pos[j] - yi;
        let l = y.norm();
        let f = y * (f64::from(list.pair_weight[b]) * (l - pairs.length(b)) / l);
        acc += f;
        buf[j] -= f;
    }
    acc
}

/// Particle `i`'s pairs, linearised kinematics (see [`pair_force_finite`]).
#[inline]
fn pair_force_small(
    list: &PairList,
    pos: &[Vec3],
    reference: &[Vec3],
    i: usize,
    buf: &mut [Vec3],
) -> Vec3 {
    #[cfg(target_arch = "x86_64")]
    {
        if has_avx2_fma() {
            // SAFETY: as in `pair_force_finite`.
            return unsafe { pair_force_small_avx2(list, pos, reference, i, buf) };
        }
    }
    pair_force_small_portable(list, pos, reference, i, buf, list.pairs.range(i))
}

#[inline(always)]
fn pair_force_small_portable(
    list: &PairList,
    pos: &[Vec3],
    reference: &[Vec3],
    i: usize,
    buf: &mut [Vec3],
    range: std::ops::Range<usize>,
) -> Vec3 {
    let pairs = &list.pairs;
    let ui = pos[i] - reference[i];
    let mut acc = Vec3::zeros();
    for b in range {
        let j = pairs.partner[b] as usize;
        let xi = reference[j] - reference[i];
        let eta = pos[j] - reference[j] - ui;
        let f = xi * (f64::from(list.pair_weight[b]) * eta.dot(&xi) / xi.norm_squared());
        acc += f;
        buf[j] -= f;
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
unsafe fn scatter_sub4(
    buf: &mut [Vec3],
    j: &[u32],
    fx: std::arch::x86_64::__m256d,
    fy: std::arch::x86_64::__m256d,
    fz: std::arch::x86_64::__m256d,
) {
    use std::arch::x86_64::*;
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

/// [`pair_force_finite`] in AVX2/FMA, four pairs per step: `1/|y|` from the single-precision
/// estimate refined by two Newton steps (relative error about 1e-13), which keeps the square
/// root and the division off the divider unit that bounds the plain loop.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn pair_force_finite_avx2(
    list: &PairList,
    pos: &[Vec3],
    i: usize,
    buf: &mut [Vec3],
) -> Vec3 {
    use std::arch::x86_64::*;
    let range = list.pairs.range(i);
    let partner = &list.pairs.partner[range.clone()];
    let length = &list.pairs.length[range.clone()];
    let w = &list.pair_weight[range.clone()];
    let yi = pos[i];
    let (cx, cy, cz) = (
        _mm256_set1_pd(yi.x),
        _mm256_set1_pd(yi.y),
        _mm256_set1_pd(yi.z),
    );
    let one = _mm256_set1_pd(1.0);
    let three_halves = _mm256_set1_pd(1.5);
    let half = _mm256_set1_pd(0.5);
    let (mut ax, mut ay, mut az) = (
        _mm256_setzero_pd(),
        _mm256_setzero_pd(),
        _mm256_setzero_pd(),
    );
    let groups = partner.len() / 4;
    for g in 0..groups {
        let k = 4 * g;
        let j = &partner[k..k + 4];
        let [px, py, pz] = gather4(pos, j);
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
        let wb = _mm256_cvtps_pd(_mm_loadu_ps(w[k..k + 4].as_ptr()));
        // w (|y| − L)/|y| = w (1 − L/|y|)
        let s = _mm256_mul_pd(wb, _mm256_fnmadd_pd(l0, inv, one));
        let (fx, fy, fz) = (
            _mm256_mul_pd(dx, s),
            _mm256_mul_pd(dy, s),
            _mm256_mul_pd(dz, s),
        );
        ax = _mm256_add_pd(ax, fx);
        ay = _mm256_add_pd(ay, fy);
        az = _mm256_add_pd(az, fz);
        scatter_sub4(buf, j, fx, fy, fz);
    }
    let acc = Vec3::new(hsum(ax), hsum(ay), hsum(az));
    acc + pair_force_finite_portable(list, pos, i, buf, range.start + 4 * groups..range.end)
}

/// [`pair_force_small`] in AVX2/FMA, four pairs per step.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn pair_force_small_avx2(
    list: &PairList,
    pos: &[Vec3],
    reference: &[Vec3],
    i: usize,
    buf: &mut [Vec3],
) -> Vec3 {
    use std::arch::x86_64::*;
    let range = list.pairs.range(i);
    let partner = &list.pairs.partner[range.clone()];
    let w = &list.pair_weight[range.clone()];
    let (xi0, ui) = (reference[i], pos[i] - reference[i]);
    let (rx, ry, rz) = (
        _mm256_set1_pd(xi0.x),
        _mm256_set1_pd(xi0.y),
        _mm256_set1_pd(xi0.z),
    );
    let (ux, uy, uz) = (
        _mm256_set1_pd(ui.x),
        _mm256_set1_pd(ui.y),
        _mm256_set1_pd(ui.z),
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
        let [px, py, pz] = gather4(pos, j);
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
        let wb = _mm256_cvtps_pd(_mm_loadu_ps(w[k..k + 4].as_ptr()));
        let s = _mm256_div_pd(_mm256_mul_pd(wb, dot), len2);
        let (fx, fy, fz) = (
            _mm256_mul_pd(sx, s),
            _mm256_mul_pd(sy, s),
            _mm256_mul_pd(sz, s),
        );
        ax = _mm256_add_pd(ax, fx);
        ay = _mm256_add_pd(ay, fy);
        az = _mm256_add_pd(az, fz);
        scatter_sub4(buf, j, fx, fy, fz);
    }
    let acc = Vec3::new(hsum(ax), hsum(ay), hsum(az));
    acc + pair_force_small_portable(
        list,
        pos,
        reference,
        i,
        buf,
        range.start + 4 * groups..range.end,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::neighbours::build_bonds;

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
