//! Volume and surface corrections of bond-based PD (paper Eqs. 5-10, METHOD.md §2).
//!
//! * Volume correction (Eq. 10 with the conditions the paper dropped): `v_c = 1` for
//!   `|ξ| ≤ δ − r`, `(δ + r − |ξ|)/(2r)` for `δ − r < |ξ| ≤ δ + r`, else 0, with `r = Δ/2`.
//! * Surface correction (Eqs. 6-9, ellipsoid method of Madenci & Oterkus): under the uniaxial
//!   strains `u = ε x`, `ε y`, `ε z` the PD strain energy density
//!   `W_i = ¼ Σ_j c s² |ξ| v_c V_j` (Eq. 7) is compared with the bulk value
//!   `W_∞ = (3/5) E ε²` (the exact value of Eq. 7 for ν = 1/4; Eq. 8's 9/16 is inconsistent with
//!   Eqs. 5 and 7) to give `g_α = W_∞ / W_i^α`. A bond's factor is the ellipsoid
//!   `G_ij = [(n_x/ḡ_x)² + (n_y/ḡ_y)² + (n_z/ḡ_z)²]^(-1/2)`, `n = ξ/|ξ|`.
//!
//! Two ways to combine the ends and fix the `g` are offered ([`CorrectionMethod`]):
//!
//! * [`CorrectionMethod::Balanced`] (default): `ḡ = √(g_i g_j)` and the `g` refined until every
//!   particle's corrected energy `¼ Σ_j c G_ij s² |ξ| v_c V_j` is within 1 % of `W_∞` for all
//!   three loads. With the geometric mean, `G_ij` scales as `√g_i √g_j` along the axes, so the
//!   refinement `g_i ← g_i W_∞/W_i` is the symmetric matrix-scaling (Sinkhorn) iteration, which
//!   converges. METHOD.md's arithmetic mean does not: measured on a cubed-sphere mesh, one pass
//!   leaves 63 % of the particles more than 2 % off `W_∞` (up to 21 %), and the same refinement
//!   with the arithmetic mean stalls near 10 %.
//! * [`CorrectionMethod::Ellipsoid`]: METHOD.md §2 as written: `ḡ = (g_i + g_j)/2`, one pass.
//!
//! Stretches are linearised (`s = ε n_α²`): the factors are ratios of energies, so they are the
//! ε → 0 limit of the paper's computation and do not depend on the calibration strain.
//!
//! How the balanced factors are found quickly ([`balance`]): the unknowns are `x = ln(1/g)`
//! per particle and axis. Plain Sinkhorn, `x ← x + ln W`, is slow where `g` must be large
//! along one axis (the surface particles whose normal is a coordinate axis need `g ≈ 9` along
//! it): there the ellipsoid saturates, `W_α` hardly responds to `g_α`, and each pass moves the
//! factor a little. Two things fix that. The step is `J_i⁻¹ ln W_i`, with `J_i` the 3 × 3
//! response of `ln W_i` to a change of `x` shared by `i` and its partners, computed once from
//! the uncorrected bonds (a per-particle Newton step). And the steps are combined by Anderson
//! acceleration over the last few passes. On the 73k-particle cubed sphere the iteration then
//! reaches 1 % in 7 passes instead of 17 (over-relaxed Sinkhorn, ω = 1.8) or 32 (plain).

use std::collections::VecDeque;

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use rayon::prelude::*;

use crate::discretize::Vec3;
use crate::neighbours::BondList;

/// Strain of the calibration loads (METHOD.md §2); it cancels in the factors.
pub const CALIBRATION_STRAIN: f64 = 1e-3;

/// Largest relative energy error the balanced correction accepts.
pub const BALANCE_TOLERANCE: f64 = 0.01;

/// Most balancing passes of the balanced correction.
pub const MAX_PASSES: usize = 60;

/// Passes whose steps Anderson acceleration combines. Measured on the 73k-particle sphere:
/// 3 and 8 make no difference to 5.
pub const ANDERSON_DEPTH: usize = 5;

/// Mixing `β` of the Anderson step `x + β f − (ΔX + β ΔF) γ`: the Newton step `J⁻¹ ln W`
/// assumes that the partners move with the particle and is half the right one for a change
/// of one particle alone; β = 1.3 takes 7 passes on the sphere, 1.0 and 1.6 take 7 and 6-7.
pub const ANDERSON_MIXING: f64 = 1.3;

/// The error, relative to the smallest so far, at which the balanced iteration drops its
/// Anderson history and halves its steps.
const DIVERGENCE: f64 = 1.5;

/// Balancing passes without progress (the smallest error cut by 1 %) after which the balanced
/// iteration stops: a mesh on which the factors cannot balance every particle (the coarse
/// tetrahedral sphere of `meshes/` stalls at 7 %) then costs a few passes, not [`MAX_PASSES`].
const STALL: usize = 10;

/// Largest change of `ln g` per axis that one Newton step asks for (a factor e³ ≈ 20).
const MAX_STEP: f64 = 3.0;

/// How surface correction factors are computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CorrectionMethod {
    /// Geometric mean of the ends, refined until every particle's energy is balanced.
    Balanced,
    /// Arithmetic mean of the ends, one pass (METHOD.md §2 as written).
    Ellipsoid,
    /// No surface correction (volume correction only).
    None,
}

/// Bond-based micromodulus `c = 12E/(π δ⁴)` (Eq. 5 with ν = 1/4).
pub fn micromodulus(youngs: f64, horizon: f64) -> f64 {
    12.0 * youngs / (std::f64::consts::PI * horizon.powi(4))
}

/// Volume correction factor of Eq. 10 for a bond of reference length `len`.
#[inline]
pub fn volume_correction(len: f64, horizon: f64, spacing: f64) -> f64 {
    let r = 0.5 * spacing;
    if len <= horizon - r {
        1.0
    } else if len <= horizon + r {
        (horizon + r - len) / (2.0 * r)
    } else {
        0.0
    }
}

/// Surface correction factors and the per-bond factor `G_ij · v_c` they give.
#[derive(Clone, Debug, Default)]
pub struct SurfaceCorrection {
    /// `g_i` per axis.
    pub g: Vec<[f64; 3]>,
    /// `G_ij · v_c(|ξ_ij|)` per directed bond.
    pub bond_factor: Vec<f64>,
    /// Largest `|W_i^corrected / W_∞ − 1|` over particles and the three loads, computed in
    /// double precision from `bond_factor`.
    pub max_energy_error: f64,
    /// Passes over the bonds: for the balanced method the one that stores the pairs (and
    /// gives the uncorrected energies), the balancing passes, and the one that writes the
    /// factors.
    pub passes: usize,
}

/// The ellipsoid factor of a bond with direction cosines squared `n2`, given the products
/// `1/(ḡ_k)²` per axis.
#[inline]
fn ellipsoid(n2: [f64; 3], inv_gbar2: [f64; 3]) -> f64 {
    1.0 / (n2[0] * inv_gbar2[0] + n2[1] * inv_gbar2[1] + n2[2] * inv_gbar2[2]).sqrt()
}

/// `n_α²` of a bond `ξ` of length `len` (one division, not three).
#[inline]
fn direction_squared(xi: Vec3, len: f64) -> [f64; 3] {
    let inv = 1.0 / (len * len);
    [xi.x * xi.x * inv, xi.y * xi.y * inv, xi.z * xi.z * inv]
}

/// `¼ c ε² / W_∞`: with `c = 12E/(πδ⁴)` and `W_∞ = (3/5) E ε²` it is `5/(π δ⁴)`, so that a
/// bond adds `scale · n_α⁴ |ξ| v_c V_j G` to `W_i^α / W_∞` (Eq. 7, `s = ε n_α²`).
fn energy_scale(horizon: f64) -> f64 {
    5.0 / (std::f64::consts::PI * horizon.powi(4))
}

/// Rows per parallel work item of the passes over all directed bonds.
const ROW_BLOCK: usize = 512;

/// Splits `data`, indexed like the bonds of `offsets`, into the bonds of consecutive blocks
/// of `block` rows, so that the blocks can be filled in parallel.
fn row_blocks<'a, T>(
    offsets: &[usize],
    block: usize,
    mut data: &'a mut [T],
) -> Vec<(std::ops::Range<usize>, &'a mut [T])> {
    let n = offsets.len().saturating_sub(1);
    let mut out = Vec::with_capacity(n.div_ceil(block));
    let mut start = 0;
    while start < n {
        let end = (start + block).min(n);
        let (head, tail) = data.split_at_mut(offsets[end] - offsets[start]);
        out.push((start..end, head));
        data = tail;
        start = end;
    }
    out
}

/// One walk over every directed bond in double precision: the factor `G_ij · v_c(|ξ_ij|)` of
/// each bond, with `G_ij = factor(i, source_j, n²)`, and each particle's energies under the
/// three loads relative to `W_∞`.
fn bond_pass(
    position: &[Vec3],
    volume: &[f64],
    source: &[usize],
    bonds: &BondList,
    horizon: f64,
    spacing: f64,
    factor: impl Fn(usize, usize, [f64; 3]) -> f64 + Sync,
) -> (Vec<f64>, Vec<[f64; 3]>) {
    let scale = energy_scale(horizon);
    let mut bond_factor = vec![0.0; bonds.len()];
    let mut w = vec![[0.0; 3]; bonds.particles()];
    row_blocks(&bonds.offsets, ROW_BLOCK, &mut bond_factor)
        .into_par_iter()
        .zip(w.par_chunks_mut(ROW_BLOCK))
        .for_each(|((rows, out), w_out)| {
            let first = bonds.offsets[rows.start];
            for (i, wi) in rows.zip(w_out) {
                let mut acc = [0.0; 3];
                for b in bonds.range(i) {
                    let j = bonds.partner[b] as usize;
                    let len = bonds.length(b);
                    let n2 = direction_squared(position[j] - position[i], len);
                    let f = factor(i, source[j], n2) * volume_correction(len, horizon, spacing);
                    out[b - first] = f;
                    let a = len * f * volume[j];
                    for k in 0..3 {
                        acc[k] += a * n2[k] * n2[k];
                    }
                }
                *wi = acc.map(|x| x * scale);
            }
        });
    (bond_factor, w)
}

/// Energies relative to `W_∞` without surface correction (`G = 1`).
fn uncorrected_energies(
    position: &[Vec3],
    volume: &[f64],
    bonds: &BondList,
    horizon: f64,
    spacing: f64,
) -> Vec<[f64; 3]> {
    let scale = energy_scale(horizon);
    (0..bonds.particles())
        .into_par_iter()
        .with_min_len(64)
        .map(|i| {
            let mut w = [0.0; 3];
            for b in bonds.range(i) {
                let j = bonds.partner[b] as usize;
                let len = bonds.length(b);
                let n2 = direction_squared(position[j] - position[i], len);
                let a = len * volume_correction(len, horizon, spacing) * volume[j];
                for k in 0..3 {
                    w[k] += a * n2[k] * n2[k];
                }
            }
            w.map(|x| x * scale)
        })
        .collect()
}

/// One bond of [`PairGeometry`], 16 bytes.
#[derive(Clone, Copy, Default)]
#[repr(C)]
struct Pair {
    /// `n_x²` and `n_y²` of the bond's direction; `n_z² = 1 − n_x² − n_y²`.
    nx2: f32,
    ny2: f32,
    /// `scale · |ξ| v_c`, times the partner's volume for a bond to a mirror image.
    weight: f32,
    /// The partner, or for a bond to a mirror image the particle the image copies.
    partner: u32,
}

/// The uncorrected energies of a particle and their response to the factors, from one walk
/// over its bonds: `w` as in [`bond_pass`] with `G = 1`, and `J`, the 3 × 3 derivative of
/// `−ln W_α` with respect to `x_β = ln r_β` shared by the particle and all its partners.
/// `J_αβ = Σ_j a n_α⁴ n_β² / W_α` (the bond's `q = Σ n_β² r_iβ r_jβ` is 1 at `r = 1`, and its
/// `d q^{-1/2}` is `−n_β² dx_β` when both ends move), so each row sums to 1.
struct Uncorrected {
    w: [f64; 3],
    /// `Σ_j a n_α⁴ n_β²` for the pairs `αβ` of [`OFF_DIAGONAL`].
    cross: [f64; 6],
}

/// The off-diagonal entries of `J`, in the order [`Uncorrected::cross`] keeps them.
const OFF_DIAGONAL: [(usize, usize); 6] = [(0, 1), (0, 2), (1, 0), (1, 2), (2, 0), (2, 1)];

impl Uncorrected {
    /// `J⁻¹` (identity for a particle without bonds, or a singular `J`).
    fn inverse_response(&self) -> Matrix3<f64> {
        let mut j = Matrix3::identity();
        for (k, &(a, b)) in OFF_DIAGONAL.iter().enumerate() {
            if self.w[a] > 0.0 {
                j[(a, b)] = self.cross[k] / self.w[a];
                j[(a, a)] -= j[(a, b)];
            }
        }
        j.try_inverse()
            .filter(|m| m.iter().all(|v| v.is_finite()))
            .unwrap_or_else(Matrix3::identity)
    }
}

/// The bonds as the balanced iteration walks them. `G_ij = 1/√(Σ_α n_α² r_iα r_jα)` is
/// symmetric, so each pair of real particles is stored once, under its lower index, and its
/// energy added to both ends: half the memory traffic and half the square roots of a walk over
/// the directed bonds. A bond to a mirror image has no stored reverse and counts for its owner.
struct PairGeometry {
    /// `pair_offsets[i]..pair_offsets[i+1]`: the pairs `(i, j)`, `i < j`, of particle `i`.
    pair_offsets: Vec<usize>,
    pairs: Vec<Pair>,
    /// Bonds of particle `i` to mirror images, indexed likewise.
    image_offsets: Vec<usize>,
    images: Vec<Pair>,
    /// Rows of each parallel work item, and one past the highest particle its pairs reach.
    chunks: Vec<(std::ops::Range<usize>, usize)>,
}

/// Pairs per parallel work item of the balanced passes. Each item sums into its own array
/// over the particles its pairs reach; items fixed by pair count (not by thread count) make
/// the sums, and so the factors, the same on every machine.
const PAIRS_PER_CHUNK: usize = 1 << 19;

impl PairGeometry {
    /// The pairs, and what the balanced iteration needs of the uncorrected bonds, from one
    /// walk over the directed bonds.
    fn new(
        position: &[Vec3],
        volume: &[f64],
        source: &[usize],
        bonds: &BondList,
        horizon: f64,
        spacing: f64,
    ) -> (PairGeometry, Vec<Uncorrected>) {
        let n = bonds.particles();
        let scale = energy_scale(horizon);
        // Counts first, so that both arrays are filled in place, in parallel.
        let counts: Vec<(usize, usize)> = (0..n)
            .into_par_iter()
            .with_min_len(256)
            .map(|i| {
                let partners = &bonds.partner[bonds.range(i)];
                let pairs = partners
                    .iter()
                    .filter(|&&j| (j as usize) > i && (j as usize) < n)
                    .count();
                let images = partners.iter().filter(|&&j| j as usize >= n).count();
                (pairs, images)
            })
            .collect();
        let mut pair_offsets = Vec::with_capacity(n + 1);
        let mut image_offsets = Vec::with_capacity(n + 1);
        let (mut p, mut m) = (0, 0);
        pair_offsets.push(0);
        image_offsets.push(0);
        for &(cp, cm) in &counts {
            p += cp;
            m += cm;
            pair_offsets.push(p);
            image_offsets.push(m);
        }
        let mut pairs = vec![Pair::default(); p];
        let mut images = vec![Pair::default(); m];
        let uncorrected: Vec<Uncorrected> = row_blocks(&pair_offsets, ROW_BLOCK, &mut pairs)
            .into_par_iter()
            .zip(row_blocks(&image_offsets, ROW_BLOCK, &mut images))
            .flat_map_iter(|((rows, pair_out), (_, image_out))| {
                let (mut p, mut m) = (0, 0);
                let mut out = Vec::with_capacity(rows.len());
                for i in rows {
                    let mut w = [0.0; 3];
                    let mut cross = [0.0; 6];
                    for b in bonds.range(i) {
                        let j = bonds.partner[b] as usize;
                        let len = bonds.length(b);
                        let n2 = direction_squared(position[j] - position[i], len);
                        let base = scale * len * volume_correction(len, horizon, spacing);
                        let a = base * volume[j];
                        for k in 0..3 {
                            w[k] += a * n2[k] * n2[k];
                        }
                        for (c, &(k, l)) in cross.iter_mut().zip(&OFF_DIAGONAL) {
                            *c += a * n2[k] * n2[k] * n2[l];
                        }
                        let (out, at, weight, partner) = if j >= n {
                            (&mut *image_out, &mut m, a, source[j])
                        } else if j > i {
                            (&mut *pair_out, &mut p, base, j)
                        } else {
                            continue;
                        };
                        out[*at] = Pair {
                            nx2: n2[0] as f32,
                            ny2: n2[1] as f32,
                            weight: weight as f32,
                            partner: partner as u32,
                        };
                        *at += 1;
                    }
                    out.push(Uncorrected { w, cross });
                }
                out
            })
            .collect();
        // Work items of about PAIRS_PER_CHUNK pairs, and how far their pairs reach.
        let mut chunks = Vec::new();
        let mut start = 0;
        while start < n {
            let mut end = start + 1;
            while end < n && pair_offsets[end] - pair_offsets[start] < PAIRS_PER_CHUNK {
                end += 1;
            }
            let reach = pairs[pair_offsets[start]..pair_offsets[end]]
                .iter()
                .map(|p| p.partner as usize + 1)
                .fold(end, usize::max);
            chunks.push((start..end, reach));
            start = end;
        }
        let geometry = PairGeometry {
            pair_offsets,
            pairs,
            image_offsets,
            images,
            chunks,
        };
        (geometry, uncorrected)
    }

    /// Energies relative to `W_∞` under the three loads with the balanced factor
    /// `G_ij = 1/√(Σ_α n_α² r_iα r_jα)`; `state[i]` is `[r_x, r_y, r_z, V_i]`. Single
    /// precision: the passes are bound by memory, and they only have to reach 1 %.
    fn relative_energies(&self, state: &[[f32; 4]]) -> Vec<[f64; 3]> {
        let partial: Vec<(usize, Vec<[f32; 4]>)> = self
            .chunks
            .par_iter()
            .map(|(rows, reach)| {
                let origin = rows.start;
                let mut acc = vec![[0.0f32; 4]; reach - origin];
                for i in rows.clone() {
                    let si = state[i];
                    let mut wi = [0.0f32; 4];
                    for p in &self.pairs[self.pair_offsets[i]..self.pair_offsets[i + 1]] {
                        let j = p.partner as usize;
                        let sj = state[j];
                        let n2 = [p.nx2, p.ny2, 1.0 - p.nx2 - p.ny2];
                        let q =
                            n2[0] * si[0] * sj[0] + n2[1] * si[1] * sj[1] + n2[2] * si[2] * sj[2];
                        let a = p.weight / q.sqrt();
                        let t = [a * n2[0] * n2[0], a * n2[1] * n2[1], a * n2[2] * n2[2], 0.0];
                        let wj = &mut acc[j - origin];
                        for k in 0..4 {
                            wi[k] += t[k] * sj[3];
                            wj[k] += t[k] * si[3];
                        }
                    }
                    for p in &self.images[self.image_offsets[i]..self.image_offsets[i + 1]] {
                        let sj = state[p.partner as usize];
                        let n2 = [p.nx2, p.ny2, 1.0 - p.nx2 - p.ny2];
                        let q =
                            n2[0] * si[0] * sj[0] + n2[1] * si[1] * sj[1] + n2[2] * si[2] * sj[2];
                        let a = p.weight / q.sqrt();
                        for k in 0..3 {
                            wi[k] += a * n2[k] * n2[k];
                        }
                    }
                    let w = &mut acc[i - origin];
                    for k in 0..4 {
                        w[k] += wi[k];
                    }
                }
                (origin, acc)
            })
            .collect();
        // Sum the work items' arrays, in parallel over stretches of particles.
        let mut w = vec![[0.0f64; 3]; state.len()];
        const STRETCH: usize = 4096;
        w.par_chunks_mut(STRETCH).enumerate().for_each(|(s, out)| {
            let lo = s * STRETCH;
            let hi = lo + out.len();
            for (origin, acc) in &partial {
                for i in lo.max(*origin)..hi.min(origin + acc.len()) {
                    for k in 0..3 {
                        out[i - lo][k] += f64::from(acc[i - origin][k]);
                    }
                }
            }
        });
        w
    }
}

fn max_error(w: &[[f64; 3]]) -> f64 {
    w.iter()
        .flat_map(|e| e.iter().map(|&x| (x - 1.0).abs()))
        .fold(0.0, f64::max)
}

/// Computes the surface correction for a body. It does not depend on E: `c` cancels in `g`.
/// `position` and `volume` may extend past the bond owners (mirror images across symmetry
/// planes); `source` maps every index to the particle whose factors it shares.
pub fn surface_correction(
    position: &[Vec3],
    volume: &[f64],
    bonds: &BondList,
    horizon: f64,
    spacing: f64,
    method: CorrectionMethod,
) -> SurfaceCorrection {
    let source: Vec<usize> = (0..position.len()).collect();
    let share = vec![1.0; bonds.particles()];
    surface_correction_with(
        position, volume, &source, &share, bonds, horizon, spacing, method,
    )
}

/// [`surface_correction`] with an explicit image → source map, and the share of the whole
/// body's copies of each particle that the model holds (1, or ½ per symmetry plane the
/// particle lies on): the balanced iteration weighs the particles by it, so that a model cut
/// by symmetry planes gets the factors of the whole body.
#[allow(clippy::too_many_arguments)]
pub fn surface_correction_with(
    position: &[Vec3],
    volume: &[f64],
    source: &[usize],
    share: &[f64],
    bonds: &BondList,
    horizon: f64,
    spacing: f64,
    method: CorrectionMethod,
) -> SurfaceCorrection {
    let n = bonds.particles();
    match method {
        CorrectionMethod::None => {
            let (bond_factor, w) = bond_pass(
                position,
                volume,
                source,
                bonds,
                horizon,
                spacing,
                |_, _, _| 1.0,
            );
            SurfaceCorrection {
                g: vec![[1.0; 3]; n],
                bond_factor,
                max_energy_error: max_error(&w),
                passes: 1,
            }
        }
        CorrectionMethod::Ellipsoid => {
            let g: Vec<[f64; 3]> = uncorrected_energies(position, volume, bonds, horizon, spacing)
                .iter()
                .map(|w| w.map(|x| if x > 0.0 { 1.0 / x } else { 1.0 }))
                .collect();
            let (bond_factor, w) = bond_pass(
                position,
                volume,
                source,
                bonds,
                horizon,
                spacing,
                |i, j, n2| {
                    ellipsoid(
                        n2,
                        std::array::from_fn(|k| {
                            let m = 0.5 * (g[i][k] + g[j][k]);
                            1.0 / (m * m)
                        }),
                    )
                },
            );
            SurfaceCorrection {
                g,
                bond_factor,
                max_energy_error: max_error(&w),
                passes: 2,
            }
        }
        CorrectionMethod::Balanced => {
            let (geometry, uncorrected) =
                PairGeometry::new(position, volume, source, bonds, horizon, spacing);
            let mut state: Vec<[f32; 4]> = volume[..n]
                .iter()
                .map(|&v| [1.0, 1.0, 1.0, v as f32])
                .collect();
            let (r, passes) = balance(&uncorrected, share, |r| {
                for (s, ri) in state.iter_mut().zip(r) {
                    *s = [ri[0] as f32, ri[1] as f32, ri[2] as f32, s[3]];
                }
                geometry.relative_energies(&state)
            });
            drop(geometry);
            // The factors and their energies in double precision: the error reported is that
            // of the factors the body uses, not the single-precision iteration's estimate.
            let (bond_factor, w) = bond_pass(
                position,
                volume,
                source,
                bonds,
                horizon,
                spacing,
                |i, j, n2| ellipsoid(n2, std::array::from_fn(|k| r[i][k] * r[j][k])),
            );
            SurfaceCorrection {
                g: r.iter().map(|ri| ri.map(|x| 1.0 / x)).collect(),
                bond_factor,
                max_energy_error: max_error(&w),
                passes: passes + 2,
            }
        }
    }
}

/// The balanced iteration (see the module notes): `r = 1/g` such that every particle's
/// corrected energy is within [`BALANCE_TOLERANCE`] of `W_∞`, given the uncorrected bonds
/// and `energies(r)`, one balancing pass. Returns the `r` with the smallest error seen and
/// the number of passes.
///
/// Unknowns `x = ln r` (so `r > 0` whatever the step), residual `f = J⁻¹ ln W` (per-particle
/// Newton step), and Anderson acceleration (type II, depth [`ANDERSON_DEPTH`]): the next `x`
/// is `x + β f − (ΔX + β ΔF) γ`, `γ` minimising `|f − ΔF γ|²` over the differences of the last
/// iterates and residuals (sums over particles weighted by `share`). A step that makes the
/// error grow by [`DIVERGENCE`] returns to the best iterate and restarts with shorter steps;
/// [`STALL`] passes without progress end the iteration.
fn balance(
    uncorrected: &[Uncorrected],
    share: &[f64],
    mut energies: impl FnMut(&[[f64; 3]]) -> Vec<[f64; 3]>,
) -> (Vec<[f64; 3]>, usize) {
    let n = uncorrected.len();
    let inverse: Vec<Matrix3<f64>> = uncorrected
        .par_iter()
        .map(Uncorrected::inverse_response)
        .collect();
    // The residual f, flattened per particle and axis.
    let residual = |w: &[[f64; 3]]| -> Vec<f64> {
        w.par_iter()
            .zip(&inverse)
            .flat_map_iter(|(wi, inv)| {
                // A particle without bonds has W = 0 and keeps g = 1.
                let l = wi.map(|v| if v > 0.0 { v.ln() } else { 0.0 });
                let s = inv * Vector3::from(l);
                // A nearly singular J must not throw a factor out by orders of magnitude.
                [s[0], s[1], s[2]].map(|v| v.clamp(-MAX_STEP, MAX_STEP))
            })
            .collect()
    };
    // Sums over the whole body: a particle on a symmetry plane stands for fewer copies.
    // Partial sums over fixed stretches, added in order: the same result on any thread count.
    let dot = |a: &[f64], b: &[f64]| -> f64 {
        const STRETCH: usize = 4096;
        let partial: Vec<f64> = a
            .par_chunks(3 * STRETCH)
            .zip(b.par_chunks(3 * STRETCH))
            .zip(share.par_chunks(STRETCH))
            .map(|((a, b), share)| {
                a.chunks(3)
                    .zip(b.chunks(3))
                    .zip(share)
                    .map(|((u, v), s)| s * (u[0] * v[0] + u[1] * v[1] + u[2] * v[2]))
                    .sum::<f64>()
            })
            .collect();
        partial.iter().sum()
    };

    // The first iterate, x = 0 (g = 1), is the uncorrected bonds: no pass needed.
    let mut x = vec![0.0; 3 * n];
    let mut w: Vec<[f64; 3]> = uncorrected.iter().map(|u| u.w).collect();
    let mut error = max_error(&w);
    let mut best = (error, x.clone(), w.clone());
    let mut mixing = ANDERSON_MIXING;
    let mut dx: VecDeque<Vec<f64>> = VecDeque::new();
    let mut df: VecDeque<Vec<f64>> = VecDeque::new();
    let mut last: Option<(Vec<f64>, Vec<f64>)> = None;
    let mut passes = 0;
    // The last pass that cut the smallest error by a percent, and that error.
    let mut progress = (0, error);
    while error >= BALANCE_TOLERANCE && passes < MAX_PASSES && passes - progress.0 < STALL {
        if error > DIVERGENCE * best.0 {
            // The step made things worse: back to the best iterate, without the history
            // that led astray, and with shorter steps from now on.
            x.clone_from(&best.1);
            w.clone_from(&best.2);
            dx.clear();
            df.clear();
            last = None;
            mixing *= 0.5;
        }
        let f = residual(&w);
        if let Some((x_prev, f_prev)) = last.take() {
            dx.push_back(x.par_iter().zip(&x_prev).map(|(a, b)| a - b).collect());
            df.push_back(f.par_iter().zip(&f_prev).map(|(a, b)| a - b).collect());
            if dx.len() > ANDERSON_DEPTH {
                dx.pop_front();
                df.pop_front();
            }
        }
        let gamma = anderson_coefficients(&df, &f, dot);
        let next: Vec<f64> = (0..x.len())
            .into_par_iter()
            .map(|k| {
                let mut v = x[k] + mixing * f[k];
                for (p, g) in gamma.iter().enumerate() {
                    v -= g * (dx[p][k] + mixing * df[p][k]);
                }
                v
            })
            .collect();
        let next = if next.iter().all(|v| v.is_finite()) {
            next
        } else {
            dx.clear();
            df.clear();
            x.iter().zip(&f).map(|(a, b)| a + mixing * b).collect()
        };
        last = Some((std::mem::replace(&mut x, next), f));
        let r: Vec<[f64; 3]> = x
            .par_chunks(3)
            .map(|c| [c[0].exp(), c[1].exp(), c[2].exp()])
            .collect();
        w = energies(&r);
        passes += 1;
        error = max_error(&w);
        if error < best.0 {
            best = (error, x.clone(), w.clone());
        }
        if error < 0.99 * progress.1 {
            progress = (passes, error);
        }
    }
    let r = best
        .1
        .chunks(3)
        .map(|c| [c[0].exp(), c[1].exp(), c[2].exp()])
        .collect();
    (r, passes)
}

/// `γ` minimising `|f − ΔF γ|²`, by the normal equations (at most [`ANDERSON_DEPTH`]
/// unknowns), regularised so that nearly dependent differences cannot blow the step up.
fn anderson_coefficients(
    df: &VecDeque<Vec<f64>>,
    f: &[f64],
    dot: impl Fn(&[f64], &[f64]) -> f64,
) -> Vec<f64> {
    let m = df.len();
    if m == 0 {
        return Vec::new();
    }
    let mut a = DMatrix::<f64>::zeros(m, m);
    let mut b = DVector::<f64>::zeros(m);
    for p in 0..m {
        for q in 0..=p {
            let v = dot(&df[p], &df[q]);
            a[(p, q)] = v;
            a[(q, p)] = v;
        }
        b[p] = dot(&df[p], f);
    }
    let ridge = 1e-10 * a.trace() / m as f64;
    for p in 0..m {
        a[(p, p)] += ridge;
    }
    match a.cholesky() {
        Some(c) => {
            let g = c.solve(&b);
            if g.iter().all(|v| v.is_finite()) {
                g.iter().copied().collect()
            } else {
                vec![0.0; m]
            }
        }
        None => vec![0.0; m],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::neighbours::build_bonds;

    #[test]
    fn volume_correction_shape() {
        assert_eq!(volume_correction(2.0, 3.0, 1.0), 1.0);
        assert_eq!(volume_correction(2.5, 3.0, 1.0), 1.0);
        assert!((volume_correction(3.0, 3.0, 1.0) - 0.5).abs() < 1e-15);
        assert_eq!(volume_correction(3.5, 3.0, 1.0), 0.0);
    }

    /// A lattice block with the lumped volumes of a hex mesh on it.
    fn block(dims: [usize; 3], h: f64) -> (Vec<Vec3>, Vec<f64>) {
        let mut p = Vec::new();
        let mut v = Vec::new();
        for k in 0..dims[2] {
            for j in 0..dims[1] {
                for i in 0..dims[0] {
                    p.push(Vec3::new(i as f64, j as f64, k as f64) * h);
                    let half = |c: usize, n: usize| if c == 0 || c == n - 1 { 0.5 } else { 1.0 };
                    v.push(h * h * h * half(i, dims[0]) * half(j, dims[1]) * half(k, dims[2]));
                }
            }
        }
        (p, v)
    }

    /// Eq. 7 evaluated independently of the module: exact (not linearised) stretches under
    /// `u = ε x_axis`, with the factors the module returns and the material's own c.
    fn energy_ratio(
        p: &[Vec3],
        v: &[f64],
        bonds: &BondList,
        factor: &[f64],
        horizon: f64,
        i: usize,
        axis: usize,
    ) -> f64 {
        let youngs = 2.0e9;
        let c = micromodulus(youngs, horizon);
        let eps = CALIBRATION_STRAIN;
        let mut w = 0.0;
        for b in bonds.range(i) {
            let j = bonds.partner[b] as usize;
            let xi = p[j] - p[i];
            let mut y = xi;
            y[axis] *= 1.0 + eps;
            let s = (y.norm() - xi.norm()) / xi.norm();
            w += 0.25 * c * factor[b] * s * s * xi.norm() * v[j];
        }
        w / (0.6 * youngs * eps * eps)
    }

    #[test]
    fn balanced_energy_is_bulk_everywhere_in_a_block() {
        let (p, v) = block([12, 10, 8], 0.1);
        let (spacing, horizon) = (0.1, 0.3);
        let bonds = build_bonds(&p, (horizon + 0.5 * spacing) * (1.0 + 1e-9));
        let corr = surface_correction(&p, &v, &bonds, horizon, spacing, CorrectionMethod::Balanced);
        assert!(
            corr.max_energy_error < BALANCE_TOLERANCE,
            "{}",
            corr.max_energy_error
        );
        for axis in 0..3 {
            for i in 0..p.len() {
                let r = energy_ratio(&p, &v, &bonds, &corr.bond_factor, horizon, i, axis);
                // Exact stretches differ from the linearised ones by O(ε).
                assert!((r - 1.0).abs() < 0.02, "particle {i} axis {axis}: {r}");
            }
        }
    }

    #[test]
    fn single_pass_ellipsoid_is_exact_in_the_bulk_only() {
        // 16³: the centre's partners (within 3.5 spacings) all have full neighbourhoods too.
        let (p, v) = block([16, 16, 16], 0.1);
        let (spacing, horizon) = (0.1, 0.3);
        let bonds = build_bonds(&p, (horizon + 0.5 * spacing) * (1.0 + 1e-9));
        let corr = surface_correction(
            &p,
            &v,
            &bonds,
            horizon,
            spacing,
            CorrectionMethod::Ellipsoid,
        );
        let centre = 8 + 16 * (8 + 16 * 8);
        let r = energy_ratio(&p, &v, &bonds, &corr.bond_factor, horizon, centre, 0);
        assert!((r - 1.0).abs() < 2e-3, "{r}");
        // Near the corners one pass is far off: the reason for the balanced method.
        assert!(corr.max_energy_error > 0.1);
    }
}
