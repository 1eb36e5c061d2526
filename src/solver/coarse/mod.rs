//! The coarse space of the static solver's preconditioner (METHOD.md §6): the rigid modes
//! (three translations, three rotations) of boxes of particles, so that the smooth part of
//! a linear solve is found at once instead of spreading one horizon a conjugate-gradient
//! iteration through block Jacobi (two-level additive Schwarz,
//! `M⁻¹ = D⁻¹ + P (Pᵀ K P)⁻¹ Pᵀ S`, `K = S A` symmetric: [`super::tangent`]).
//!
//! `Pᵀ K P` is assembled from the bonds' linearised tangent once (it does not change under
//! small kinematics; under finite ones it stands for the tangent in the preconditioner
//! only) and from each Newton iteration's contact springs ([`super::tangent::Tangent`]);
//! its inverse from the bonds' part factorised once and the springs' added on the boxes
//! they touch ([`factor`]).
//! An LPS body's part is its energy's (METHOD.md §8) linearised: the deviatoric term pair by
//! pair, as a bond-based body's, and the dilatation's `Σ_p V_p k' g_p θ_p²/2`
//! (`k' = k − 5μ/3`) as one rank-one term per particle ([`CoarseSpace::assemble_dilatation`]);
//! the position-aware and skin weights are left out of it (1), which the preconditioner
//! tolerates: it is exact for the constant influence function without the skin correction.

use std::collections::HashMap;
use std::ops::AddAssign;

use nalgebra::{DMatrix, DVector, Matrix3, SMatrix, SVector};
use rayon::prelude::*;

mod factor;

pub(super) use factor::CoarseFactor;
use factor::{regularise, Base};

use super::dofs::Dofs;
use super::free_factor;
use super::tangent::{Master, Spring};
use crate::body::{Body, FIX_X, FIX_Y, FIX_Z};
use crate::case::mirror_direction;
use crate::math::Vec3;
use crate::model::Model;

/// A particle's rows of `P`: its box and the 3×6 block of that box's modes.
pub(super) type Rows = (usize, SMatrix<f64, 3, 6>);

/// A 6 × 6 block of the coarse matrix (one box's modes against another's).
type Matrix6 = SMatrix<f64, 6, 6>;

/// Particles a box holds, about: fewer boxes leave the CG count high, more make the dense
/// coarse factorisation the cost (docs/PERFORMANCE.md, "The static solver" and "The main
/// thread in the pool, and boxes of 200 particles": 500 took the gmsh tet4 pair of 12,087
/// particles 144 tangent products, 200 takes it 96).
const PARTICLES_PER_BOX: usize = 200;
/// Boxes over the whole model at most (a coarse matrix of 6 × 128 = 768 rows, its bonds'
/// part factorised in a few milliseconds).
const MAX_BOXES: usize = 128;

/// The boxes and the bonds' part of `Pᵀ K P`.
pub(super) struct CoarseSpace {
    /// Per body, per particle: its box (empty for a rigid body).
    aggregate: Vec<Vec<u32>>,
    /// Per box: the centre its rotations turn about.
    centre: Vec<Vec3>,
    /// The bonds' part of `Pᵀ K P`.
    bonds: DMatrix<f64>,
    /// It factorised ([`factor`]); `None` where it is not positive definite.
    base: Option<Base>,
}

impl CoarseSpace {
    /// Boxes over each deformable body's reference box, about [`PARTICLES_PER_BOX`]
    /// particles each; `None` where the model has no deformable body.
    pub fn new(model: &Model) -> Option<CoarseSpace> {
        let mut sizes = Vec::new();
        for b in &model.bodies {
            if let Body::Deformable(pd) = b {
                sizes.push(pd.len());
            }
        }
        let total: usize = sizes.iter().sum();
        if total == 0 {
            return None;
        }
        let boxes = (total / PARTICLES_PER_BOX).clamp(1, MAX_BOXES);
        let mut aggregate = Vec::with_capacity(model.bodies.len());
        let mut centre: Vec<Vec3> = Vec::new();
        for b in &model.bodies {
            let Body::Deformable(pd) = b else {
                aggregate.push(Vec::new());
                continue;
            };
            let n = pd.len();
            let per_body = (boxes * n / total).max(1);
            let x = &pd.reference[..n];
            let (mut lo, mut hi) = (x[0], x[0]);
            for p in x {
                lo = lo.inf(p);
                hi = hi.sup(p);
            }
            let ext = (hi - lo).map(|e| e.max(1e-30));
            let side = (ext.x * ext.y * ext.z / per_body as f64).cbrt();
            let dims = ext.map(|e| ((e / side).round() as usize).max(1));
            let cell = |p: &Vec3| {
                let mut c = [0usize; 3];
                for d in 0..3 {
                    let t = ((p[d] - lo[d]) / ext[d] * dims[d] as f64) as usize;
                    c[d] = t.min(dims[d] - 1);
                }
                c[0] + dims[0] * (c[1] + dims[1] * c[2])
            };
            // Boxes numbered in the order their first particle comes: the same on any
            // thread count.
            let mut index = vec![u32::MAX; dims.x * dims.y * dims.z];
            let mut sums: Vec<(Vec3, f64)> = Vec::new();
            let base = centre.len();
            let agg: Vec<u32> = x
                .iter()
                .map(|p| {
                    let c = cell(p);
                    if index[c] == u32::MAX {
                        index[c] = (base + sums.len()) as u32;
                        sums.push((Vec3::zeros(), 0.0));
                    }
                    let a = index[c] as usize - base;
                    sums[a].0 += p;
                    sums[a].1 += 1.0;
                    index[c]
                })
                .collect();
            centre.extend(sums.iter().map(|(s, w)| s / *w));
            aggregate.push(agg);
        }
        let mut space = CoarseSpace {
            aggregate,
            centre,
            bonds: DMatrix::zeros(0, 0),
            base: None,
        };
        space.reassemble(model);
        Some(space)
    }

    /// Coarse unknowns.
    pub fn len(&self) -> usize {
        6 * self.centre.len()
    }

    /// Assembles the bonds' part again (bonds broke).
    pub fn reassemble(&mut self, model: &Model) {
        self.bonds = self.assemble_bonds(model);
        self.base = Base::new(&self.bonds);
    }

    /// Particle `i` of body `k`: its box and the modes' values there, fixed components
    /// removed (a mode does not move what a support holds).
    #[inline]
    pub fn rows(&self, model: &Model, k: usize, i: usize) -> Rows {
        let (a, r, f) = self.at(model, k, i);
        let mut m = SMatrix::<f64, 3, 6>::zeros();
        for d in 0..3 {
            let mut e = Vec3::zeros();
            e[d] = 1.0;
            m.set_column(d, &e.component_mul(&f));
            m.set_column(3 + d, &e.cross(&r).component_mul(&f));
        }
        (a, m)
    }

    /// Particle `i` of body `k`: its box, its place from the box's centre, and the factor
    /// that zeroes its fixed components (what [`Self::rows`] is made of).
    #[inline]
    fn at(&self, model: &Model, k: usize, i: usize) -> (usize, Vec3, Vec3) {
        let Body::Deformable(pd) = &model.bodies[k] else {
            unreachable!("a coarse row of a rigid body")
        };
        let a = self.aggregate[k][i] as usize;
        (
            a,
            pd.reference[i] - self.centre[a],
            free_factor(pd.fixed[i]),
        )
    }

    /// The springs' part of `Pᵀ K P`, block by block: `(a, b, block)` for boxes `a`, `b`
    /// (each spring couples its slave's rows to its master nodes', `C` between them).
    fn spring_blocks(&self, model: &Model, springs: &[Spring]) -> Vec<(usize, usize, Matrix6)> {
        let mut out = Vec::new();
        let mut d: Vec<Rows> = Vec::with_capacity(5);
        for s in springs {
            if model.bodies[s.body].as_pd().is_none() {
                continue;
            }
            let c = s.matrix();
            d.clear();
            d.push(self.rows(model, s.body, s.slave as usize));
            if let Master::Nodes {
                body,
                nodes,
                weights,
            } = s.master
            {
                for (n, w) in nodes.iter().zip(weights) {
                    if w != 0.0 {
                        let (a, m) = self.rows(model, body, *n as usize);
                        d.push((a, -m * w));
                    }
                }
            }
            for (a, ma) in &d {
                let left = ma.transpose() * c;
                for (b, mb) in &d {
                    out.push((*a, *b, left * mb));
                }
            }
        }
        out
    }

    /// `Pᵀ K P` of a tangent: the bonds' part and its `springs`'.
    #[cfg(test)]
    pub fn matrix(&self, model: &Model, springs: &[Spring]) -> DMatrix<f64> {
        self.with_springs(&self.spring_blocks(model, springs))
    }

    /// The bonds' part with the springs' `blocks` added, its diagonal raised.
    fn with_springs(&self, blocks: &[(usize, usize, Matrix6)]) -> DMatrix<f64> {
        let mut ac = self.bonds.clone();
        for (a, b, blk) in blocks {
            let mut at = ac.fixed_view_mut::<6, 6>(6 * a, 6 * b);
            at += blk;
        }
        regularise(&mut ac, factor::REGULAR);
        ac
    }

    /// `(Pᵀ K P)⁻¹` of a tangent with `springs`: the bonds' part's factor updated on the
    /// boxes the springs touch ([`factor`]), or where they touch many, the whole matrix
    /// factorised; `None` where it is not positive definite.
    pub fn factor(&self, model: &Model, springs: &[Spring]) -> Option<CoarseFactor> {
        let blocks = self.spring_blocks(model, springs);
        if let Some(base) = &self.base {
            let mut boxes: Vec<usize> = blocks.iter().map(|b| b.0).collect();
            boxes.sort_unstable();
            boxes.dedup();
            let mut local = HashMap::new();
            for (k, &a) in boxes.iter().enumerate() {
                local.insert(a, k);
            }
            let mut d = DMatrix::zeros(6 * boxes.len(), 6 * boxes.len());
            for (a, b, blk) in &blocks {
                let mut at = d.fixed_view_mut::<6, 6>(6 * local[a], 6 * local[b]);
                at += blk;
            }
            let rows = boxes.iter().flat_map(|&a| 6 * a..6 * a + 6).collect();
            if let Some(f) = CoarseFactor::updated(base, rows, d) {
                return Some(f);
            }
        }
        CoarseFactor::whole(&self.with_springs(&blocks))
    }

    /// `z += P (Pᵀ K P)⁻¹ Pᵀ S r`, `factor` the factorised `Pᵀ K P`. A particle's rows
    /// of `P` are applied without being built: `Pᵀ v = (f∘v, r × (f∘v))` and
    /// `P y = f∘(y_t + y_r × r)` (translations, then rotations about the box's centre).
    pub fn correct(&self, model: &Model, factor: &CoarseFactor, r: &Dofs, z: &mut Dofs) {
        let mut pr = DVector::zeros(self.len());
        for (k, rk) in r.pd.iter().enumerate() {
            let Some(pd) = model.bodies[k].as_pd() else {
                continue;
            };
            // Summed per chunk of particles, the chunks then in order (the same bits on any
            // thread count); on threads only for large bodies, as below.
            let ghosts = &pd.case.ghosts;
            let n = rk.len();
            let chunks: Vec<DVector<f64>> = rk
                .par_chunks(CHUNK)
                .zip(pd.reference[..n].par_chunks(CHUNK))
                .zip(pd.fixed[..n].par_chunks(CHUNK))
                .zip(self.aggregate[k].par_chunks(CHUNK))
                .enumerate()
                .with_min_len(SERIAL / CHUNK)
                .map(|(c, (((r, x), fixed), agg))| {
                    let mut sum = DVector::zeros(self.len());
                    for (o, (((ri, x), fixed), a)) in
                        r.iter().zip(x).zip(fixed).zip(agg).enumerate()
                    {
                        let a = *a as usize;
                        let v =
                            (ri * ghosts.share(c * CHUNK + o)).component_mul(&free_factor(*fixed));
                        let w = (x - self.centre[a]).cross(&v);
                        for d in 0..3 {
                            sum[6 * a + d] += v[d];
                            sum[6 * a + 3 + d] += w[d];
                        }
                    }
                    sum
                })
                .collect();
            for sum in chunks {
                pr += sum;
            }
        }
        let y = factor.solve(self.base.as_ref(), pr);
        // Each box's translation and rotation, then a particle's `f∘(t + rot × (X − C))`.
        let motion: Vec<(Vec3, Vec3, Vec3)> = (0..self.centre.len())
            .map(|a| {
                let t = Vec3::new(y[6 * a], y[6 * a + 1], y[6 * a + 2]);
                let rot = Vec3::new(y[6 * a + 3], y[6 * a + 4], y[6 * a + 5]);
                (t, rot, self.centre[a])
            })
            .collect();
        for (k, zk) in z.pd.iter_mut().enumerate() {
            let Some(pd) = model.bodies[k].as_pd() else {
                continue;
            };
            let n = zk.len();
            // Threads only for large bodies: below, waking them costs more than the sweep.
            zk.par_iter_mut()
                .zip(pd.reference[..n].par_iter())
                .zip(pd.fixed[..n].par_iter())
                .zip(self.aggregate[k].par_iter())
                .with_min_len(SERIAL)
                .for_each(|(((zi, x), fixed), a)| {
                    let (t, rot, c) = &motion[*a as usize];
                    *zi += (t + rot.cross(&(x - c))).component_mul(&free_factor(*fixed));
                });
        }
    }

    /// `Σ_i P_iᵀ (K P)_i` over every directed bond, linearised: each bond adds
    /// `w g_i (g_i − g_j)ᵀ`, `g = P e`, `e` the bond's reference direction (Eq. 26
    /// linearised); a bond to a mirror image moves with its source reflected. Per particle
    /// `i` the bonds are summed first, `P_iᵀ (Σ w e eᵀ) P_i` and `P_iᵀ Σ w e g_jᵀ` for each
    /// box its partners lie in, so that a bond costs a few dozen operations and not two
    /// 6 × 6 products. Summed per block of particles in a fixed order (the same bits on any
    /// thread count).
    fn assemble_bonds(&self, model: &Model) -> DMatrix<f64> {
        let nc = self.len();
        let mut ac = DMatrix::zeros(nc, nc);
        for (k, b) in model.bodies.iter().enumerate() {
            let Body::Deformable(pd) = b else { continue };
            let n = pd.len();
            let bonds = &pd.case.bonds;
            let ghosts = &pd.case.ghosts;
            let vol = &pd.case.particles.volume;
            let lps = pd.lps.as_ref().map(|l| (l, l.shear));
            let mirrored =
                |e: Vec3, g: usize| mirror_direction(e, u32::from(ghosts.mask[g]), &ghosts.planes);
            // A block of particles touches a few boxes and their neighbours: its sum is kept
            // as 6 × 6 blocks, not a whole coarse matrix (16 of those, zeroed and summed, were
            // half the assembly's time on the demo).
            let part = |range: std::ops::Range<usize>| {
                let mut m = Blocks::default();
                // Per box of the partners: `Σ w e g_jᵀ`, and apart, for the partners free in
                // every direction, `S = Σ w e eᵀ`: for them `g_j = (e, (X_j − C) × e)` and
                // `(X_j − C) × e = (X_i − C) × e` (the bond lies along `e`), so their sum is
                // `(S, S [X_i − C]ₓᵀ)`, a sum of six numbers per bond and not a 3 × 6. `w e eᵀ`
                // as `(w / |ξ|²) ξ ξᵀ`: no root.
                let mut across: Vec<Across> = Vec::new();
                for i in range {
                    let (ai, pi) = self.rows(model, k, i);
                    let mut own = [0.0; 6];
                    across.clear();
                    let mut last = 0;
                    for bd in bonds.range(i) {
                        let j = bonds.partner[bd] as usize;
                        let w = match lps {
                            // The deviatoric pair stiffness `15μ (g_i v_i/m_i + g_j v_j/m_j)
                            // v_c V_j V_i` (the dilatation apart); 0 for a broken bond.
                            Some((l, mu)) if pd.bond_weight[bd] != 0.0 => {
                                let s = if j < n {
                                    j
                                } else {
                                    ghosts.source[j - n] as usize
                                };
                                let (vi, vj) = l.deviatoric_factors(bd);
                                let (mi, ms) = (l.weighted_volume[i], l.weighted_volume[s]);
                                let share = |g: f64, v: f64, m: f64| {
                                    if m > 0.0 {
                                        g * v / m
                                    } else {
                                        0.0
                                    }
                                };
                                15.0 * mu
                                    * (share(l.correction[i], vi, mi)
                                        + share(l.correction[s], vj, ms))
                                    * l.bond_volume[bd]
                                    * vol[i]
                            }
                            Some(_) => 0.0,
                            None => f64::from(pd.bond_weight[bd]),
                        };
                        if w == 0.0 {
                            continue;
                        }
                        let xi = pd.reference[j] - pd.reference[i];
                        let q = xi * (w / xi.norm_squared());
                        let wee = [
                            q.x * xi.x,
                            q.x * xi.y,
                            q.x * xi.z,
                            q.y * xi.y,
                            q.y * xi.z,
                            q.z * xi.z,
                        ];
                        if j < n && pd.fixed[j] & (FIX_X | FIX_Y | FIX_Z) == 0 {
                            let aj = self.aggregate[k][j] as usize;
                            last = slot(&mut across, last, aj);
                            for (s, v) in across[last].2.iter_mut().zip(wee) {
                                *s += v;
                            }
                            continue;
                        }
                        for (s, v) in own.iter_mut().zip(wee) {
                            *s += v;
                        }
                        // `g_j = P_jᵀ e`; an image's rows are its source's reflected.
                        let e = xi / xi.norm();
                        let (aj, c, f, ej) = if j < n {
                            let (a, c, f) = self.at(model, k, j);
                            (a, c, f, e)
                        } else {
                            let (a, c, f) = self.at(model, k, ghosts.source[j - n] as usize);
                            (a, c, f, mirrored(e, j - n))
                        };
                        let t = ej.component_mul(&f);
                        let rot = c.cross(&t);
                        let mut gj = SMatrix::<f64, 1, 6>::zeros();
                        for d in 0..3 {
                            gj[d] = t[d];
                            gj[3 + d] = rot[d];
                        }
                        last = slot(&mut across, last, aj);
                        across[last].1 += (e * w) * gj;
                    }
                    // `Σ w e eᵀ` over every bond: the free partners' sums and the rest's.
                    for (_, _, free) in &across {
                        for (s, v) in own.iter_mut().zip(free) {
                            *s += v;
                        }
                    }
                    let own = symmetric(&own);
                    let pit = pi.transpose();
                    *m.at(ai, ai) += pit * own * pi;
                    for (aj, sum, free) in &mut across {
                        let c = pd.reference[i] - self.centre[*aj];
                        let free = symmetric(free);
                        sum.fixed_view_mut::<3, 3>(0, 0).add_assign(&free);
                        sum.fixed_view_mut::<3, 3>(0, 3)
                            .add_assign(&(free * c.cross_matrix().transpose()));
                        *m.at(ai, *aj) -= pit * *sum;
                    }
                }
                m
            };
            add_parts(&mut ac, n, part);
        }
        self.assemble_dilatation(model, &mut ac);
        // K is symmetric; the sum over directed bonds is so up to rounding.
        (&ac + ac.transpose()) * 0.5
    }

    /// An LPS body's dilatation term added to `ac`: `Σ_p V_p k' g_p c_p c_pᵀ` with
    /// `c_p = Pᵀ ∂θ_p/∂u = (3/m_p) Σ_q ω_d v_c V_q |ξ| (P_qᵀ n − P_pᵀ n)` and
    /// `k' = k − 5μ/3` (the LPS energy written as its dilatation's square and the deviatoric
    /// pairs': [`Self::assemble_bonds`]). Partners in the particle's own box, free in every
    /// direction, add nothing (a rigid mode does not dilate it). Summed per block of particles
    /// in a fixed order, as the bonds are.
    fn assemble_dilatation(&self, model: &Model, ac: &mut DMatrix<f64>) {
        for (k, b) in model.bodies.iter().enumerate() {
            let Body::Deformable(pd) = b else { continue };
            let Some(lps) = pd.lps.as_ref() else { continue };
            let k_prime = lps.bulk - 5.0 * lps.shear / 3.0;
            if k_prime == 0.0 {
                continue;
            }
            let n = pd.len();
            let bonds = &pd.case.bonds;
            let ghosts = &pd.case.ghosts;
            let vol = &pd.case.particles.volume;
            let mirrored =
                |e: Vec3, g: usize| mirror_direction(e, u32::from(ghosts.mask[g]), &ghosts.planes);
            // `P_qᵀ e` on q's box: `(e ∘ f, r × (e ∘ f))`, `r` from the box's centre.
            let mode = |r: Vec3, f: Vec3, e: Vec3| {
                let t = e.component_mul(&f);
                let rot = r.cross(&t);
                SVector::<f64, 6>::from_column_slice(&[t.x, t.y, t.z, rot.x, rot.y, rot.z])
            };
            let part = |range: std::ops::Range<usize>| {
                let mut m = Blocks::default();
                let mut c: Vec<(usize, SVector<f64, 6>)> = Vec::new();
                for p in range {
                    let mp = lps.weighted_volume[p];
                    if !(mp > 0.0) {
                        continue;
                    }
                    c.clear();
                    let (ap, cp, fp) = self.at(model, k, p);
                    let mut own = SVector::<f64, 6>::zeros();
                    for bd in bonds.range(p) {
                        let bv = lps.bond_volume[bd];
                        if bv == 0.0 || pd.bond_weight[bd] == 0.0 {
                            continue;
                        }
                        let q = bonds.partner[bd] as usize;
                        let xi = pd.reference[q] - pd.reference[p];
                        let len = xi.norm();
                        let e = xi / len;
                        let coef = 3.0 / mp * bv * len * lps.dilatation_factors(bd).0;
                        let (aq, cq, fq, eq) = if q < n {
                            let (a, c, f) = self.at(model, k, q);
                            (a, c, f, e)
                        } else {
                            let (a, c, f) = self.at(model, k, ghosts.source[q - n] as usize);
                            (a, c, f, mirrored(e, q - n))
                        };
                        own -= mode(cp, fp, e) * coef;
                        let g = mode(cq, fq, eq) * coef;
                        match c.iter_mut().find(|(a, _)| *a == aq) {
                            Some((_, v)) => *v += g,
                            None => c.push((aq, g)),
                        }
                    }
                    match c.iter_mut().find(|(a, _)| *a == ap) {
                        Some((_, v)) => *v += own,
                        None => c.push((ap, own)),
                    }
                    let weight = vol[p] * k_prime * lps.correction[p];
                    for (a, ca) in &c {
                        for (b, cb) in &c {
                            *m.at(*a, *b) += (ca * cb.transpose()) * weight;
                        }
                    }
                }
                m
            };
            add_parts(ac, n, part);
        }
    }
}

/// `part` of each of at most 16 blocks of a body's `n` particles, on the threads, added to
/// `ac` in the blocks' order (each entry's sum in the same order on any thread count).
fn add_parts(
    ac: &mut DMatrix<f64>,
    n: usize,
    part: impl Fn(std::ops::Range<usize>) -> Blocks + Sync,
) {
    let block = n.div_ceil(16).max(1024);
    let parts: Vec<Blocks> = (0..n.div_ceil(block))
        .into_par_iter()
        .map(|c| part(c * block..((c + 1) * block).min(n)))
        .collect();
    for p in parts {
        for (&(a, b), &k) in &p.index {
            let mut blk = ac.fixed_view_mut::<6, 6>(6 * a, 6 * b);
            blk += p.values[k];
        }
    }
}

/// Particles a thread takes at a time in [`CoarseSpace::correct`].
const CHUNK: usize = 2048;

/// Particles below which [`CoarseSpace::correct`] sweeps a body on one thread.
const SERIAL: usize = 1 << 15;

/// A particle's bonds into one box: `Σ w e g_jᵀ` over its partners with a fixed component,
/// `Σ w e eᵀ` over the free ones (its upper triangle by rows, [`symmetric`];
/// [`CoarseSpace::assemble_bonds`]).
type Across = (usize, SMatrix<f64, 3, 6>, [f64; 6]);

/// The symmetric matrix of an upper triangle by rows.
fn symmetric(u: &[f64; 6]) -> Matrix3<f64> {
    Matrix3::new(u[0], u[1], u[2], u[1], u[3], u[4], u[2], u[4], u[5])
}

/// The place of box `a`'s sums in `across` (added, zero, where new), `last` tried first: a
/// particle's partners come in runs of one box.
#[inline]
fn slot(across: &mut Vec<Across>, last: usize, a: usize) -> usize {
    if across.get(last).is_some_and(|s| s.0 == a) {
        return last;
    }
    across.iter().position(|s| s.0 == a).unwrap_or_else(|| {
        across.push((a, SMatrix::zeros(), [0.0; 6]));
        across.len() - 1
    })
}

/// A sum of 6 × 6 blocks of a coarse matrix, by (row box, column box).
#[derive(Default)]
struct Blocks {
    index: HashMap<(usize, usize), usize>,
    values: Vec<SMatrix<f64, 6, 6>>,
}

impl Blocks {
    /// The block at boxes `(a, b)`, zero where new.
    fn at(&mut self, a: usize, b: usize) -> &mut SMatrix<f64, 6, 6> {
        let k = *self.index.entry((a, b)).or_insert_with(|| {
            self.values.push(SMatrix::zeros());
            self.values.len() - 1
        });
        &mut self.values[k]
    }
}

#[cfg(test)]
pub(super) mod tests;
