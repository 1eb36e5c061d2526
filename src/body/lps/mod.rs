//! The linear peridynamic solid (LPS, ordinary state-based PD; Silling, Epton, Weckner, Xu,
//! Askari, J. Elasticity 88, 2007; METHOD.md §8): any Poisson's ratio.
//!
//! With the influence function ω = 1 and the volume correction `v_c` of METHOD.md §2, per
//! particle the weighted volume `m_i = Σ_j ω |ξ|² v_c V_j` and the dilatation
//! `θ_i = (3/m_i) Σ_j ω |ξ| e v_c V_j` (`e = |ξ + η| − |ξ|`, or `η·ξ/|ξ|` linearised); the
//! scalar force state `t_i<ξ> = (3kθ_i/m_i) ω|ξ| + (15μ/m_i) ω (e − θ_i|ξ|/3)`, and the pair's
//! force on `i` is `(t_i<ξ> + t_j<−ξ>) M v_c V_j V_i` along the bond `M` (deformed, or the
//! reference bond linearised). Where the neighbourhood is whole the bulk has the continuum's
//! E and ν; `m_i` over a particle's actual neighbourhood corrects the dilatation near a
//! surface in part. The influence function may be position-aware ([`position_aware`]:
//! per bond a dilatation factor `ω_d` and a deviatoric factor on ω, the force state
//! `t_i<ξ> = (3ω_d|ξ|/m_i)(kθ_i − 15μ D_i/m_i) + (15μ/m_i) ω e^d`,
//! `D_i = Σ_j ω e^d |ξ| v_c V_j / 3`, the gradient of `Σ_i V_i W_i`), which makes every
//! particle's energy the continuum's under a uniform strain; `constant` (the default) keeps
//! ω = 1 and scales each particle's state by one factor ([`surface_factors`]).
//!
//! At ν = 1/4, `3k = 5μ`: the dilatation drops out and the force is bond-based PD's with a
//! micromodulus `15μ(1/m_i + 1/m_j)`.
//!
//! The pass goes over directed bonds (each pair from both ends), a particle summing its own
//! bonds in a fixed order (four lanes of AVX2 where the processor has it: `kernel`): the
//! same bits whatever the thread count. The factors of the weights are kept in single
//! precision, as the bond-based pass keeps its weights: the pass streams them. Symmetry planes: a partner's
//! whole volume in the sums, the particle's held share `V_i` on its force (as the bond-based
//! pass, [`crate::case::pairs`]); a mirror image takes its source's `m` and `θ`.

#[cfg(target_arch = "x86_64")]
mod kernel;
pub mod position_aware;
mod skin;
#[cfg(test)]
mod tests;

use std::ops::Range;

use rayon::prelude::*;

pub use skin::skin_factors;

use crate::case::correction::volume_correction;
use crate::case::{mirror_direction, PdCase};
use crate::math::Vec3;

/// Particles per work item.
const CHUNK: usize = 512;

/// The material constants and per-bond and per-particle data of an LPS body.
#[derive(Clone, Debug)]
pub struct Lps {
    /// Bulk modulus `k = E/(3(1 − 2ν))`, Pa.
    pub bulk: f64,
    /// Shear modulus `μ = E/(2(1 + ν))`, Pa.
    pub shear: f64,
    /// Per directed bond of the case: `ω v_c V_j` with `V_j` the partner's whole volume.
    pub bond_volume: Vec<f64>,
    /// Per real particle: the weighted volume `m_i`.
    pub weighted_volume: Vec<f64>,
    /// Per real particle: the surface correction `g_i` that scales its force state
    /// ([`surface_factors`]); 1 in the bulk, and everywhere in the position-aware LPS.
    pub correction: Vec<f64>,
    /// Whether the skin correction ([`skin`]) is in the deviatoric weights.
    pub skin: bool,
    /// Per directed bond `i → j`: the factor of its dilatation weight in particle `i`'s state
    /// and of `j → i` in `j`'s ([`position_aware`]; empty: 1).
    dilatation_own: Vec<f32>,
    dilatation_partner: Vec<f32>,
    /// Per directed bond `i → j`: the factor of its deviatoric weight in `i`'s state and of
    /// `j → i` in `j`'s (the position-aware weight times the skin's `s_i(ξ)`; empty: 1).
    deviatoric_own: Vec<f32>,
    deviatoric_partner: Vec<f32>,
    /// Per real particle: `m^s_i = Σ_j ω s_i |ξ|² v_c V_j` with the deviatoric factors (empty
    /// where they are 1).
    deviatoric_moment: Vec<f64>,
    /// Per real particle: the dilatation of the last pass (scratch).
    dilatation: Vec<f64>,
    /// Per real particle: `D_i = Σ_j ω s_i e^d |ξ| v_c V_j / 3` of the last pass, which the
    /// skin's weights make nonzero (scratch).
    deviation: Vec<f64>,
    /// Per real particle: the force state's three constants of the last pass (scratch; a
    /// `Vec3` so that a decomposed run sends them to ghosts as it sends displacements).
    state: Vec<Vec3>,
    /// The sweeps a bond at a time even where the processor has AVX2 (the tests' check of
    /// the vector sweeps).
    portable: bool,
}

/// How the bonds stretch in a pass.
#[derive(Clone, Copy, Debug)]
pub enum Stretch<'a> {
    /// `e = |y| − |ξ|` along the deformed bond.
    Finite,
    /// `e = η·ξ/|ξ|` along the reference bond, with the reference positions.
    Small(&'a [Vec3]),
}

impl Lps {
    /// The LPS of case `case` for Young's modulus `youngs` and Poisson's ratio `poisson`,
    /// its surface effect corrected by the position-aware influence functions
    /// ([`position_aware`]) or by a factor per particle ([`surface_factors`]).
    pub fn new(case: &PdCase, youngs: f64, poisson: f64, position_aware: bool) -> Lps {
        Lps::without(case, youngs, poisson, position_aware, &[])
    }

    /// [`Lps::new`] without the directed bonds `b` where `cut[b]` (a pre-crack's, cut before
    /// the run): their partners out of each particle's weighted volume, surface correction and
    /// position-aware weights, as though the case had been built without them. (Bonds that
    /// break during a run leave these as built.)
    pub fn without(
        case: &PdCase,
        youngs: f64,
        poisson: f64,
        position_aware: bool,
        cut: &[bool],
    ) -> Lps {
        let n = case.particles.len();
        let bonds = &case.bonds;
        let partner_vol = case.ghosts.partner_volumes(&case.particles.volume);
        // The volume correction at each bond's own horizon where it follows the mesh; m_i
        // normalises the state, so no micromodulus scaling goes with it.
        let spacing = case.particles.spacing;
        let local = case.local_spacing.as_ref().map(|s| case.ghosts.extend(s));
        let v_c = |i: usize, j: usize, l: f64| match &local {
            None => volume_correction(l, case.horizon, spacing),
            Some(s) => {
                let sij = 0.5 * (s[i] + s[j]);
                volume_correction(l, case.horizon * sij / spacing, sij)
            }
        };
        let mut bond_volume = Vec::with_capacity(bonds.len());
        let mut weighted_volume = vec![0.0; n];
        for (i, m) in weighted_volume.iter_mut().enumerate() {
            for b in bonds.range(i) {
                let j = bonds.partner[b] as usize;
                let l = bonds.length(b);
                let v = if cut.get(b) == Some(&true) {
                    0.0
                } else {
                    v_c(i, j, l) * partner_vol[j]
                };
                bond_volume.push(v);
                *m += v * l * l;
            }
        }
        let mut lps = Lps {
            bulk: youngs / (3.0 * (1.0 - 2.0 * poisson)),
            shear: youngs / (2.0 * (1.0 + poisson)),
            bond_volume,
            weighted_volume,
            correction: vec![1.0; n],
            skin: false,
            dilatation_own: Vec::new(),
            dilatation_partner: Vec::new(),
            deviatoric_own: Vec::new(),
            deviatoric_partner: Vec::new(),
            deviatoric_moment: Vec::new(),
            dilatation: vec![0.0; n],
            deviation: vec![0.0; n],
            state: vec![Vec3::zeros(); n],
            portable: false,
        };
        if position_aware {
            let c = position_aware::coefficients(case, &lps.bond_volume, &lps.weighted_volume);
            let [d_own, d_partner, v_own, v_partner] = position_aware::bond_weights(case, &c);
            lps.dilatation_own = single(d_own);
            lps.dilatation_partner = single(d_partner);
            lps.set_deviatoric(case, v_own, v_partner);
        } else {
            lps.correction = surface_factors(&lps, case, youngs, poisson);
        }
        lps
    }

    /// Takes directed bond `b` out of the dilatation and the force state (a broken bond).
    pub fn cut(&mut self, b: usize) {
        self.bond_volume[b] = 0.0;
    }

    /// Particle `i`'s dilatation factor of directed bond `b` and its partner's (1: none).
    #[inline]
    pub fn dilatation_factors(&self, b: usize) -> (f64, f64) {
        match (self.dilatation_own.get(b), self.dilatation_partner.get(b)) {
            (Some(&a), Some(&c)) => (f64::from(a), f64::from(c)),
            _ => (1.0, 1.0),
        }
    }

    /// Particle `i`'s deviatoric factor of directed bond `b` and its partner's (1: none).
    #[inline]
    pub fn deviatoric_factors(&self, b: usize) -> (f64, f64) {
        match (self.deviatoric_own.get(b), self.deviatoric_partner.get(b)) {
            (Some(&a), Some(&c)) => (f64::from(a), f64::from(c)),
            _ => (1.0, 1.0),
        }
    }

    /// Sets the deviatoric factors per directed bond, and with them each particle's moment
    /// (from the factors as stored, in single precision: the pass streams them, and a bond's
    /// factor in its particle's state is the same number as in its partner's, so the pass
    /// stays the gradient of an energy).
    fn set_deviatoric(&mut self, case: &PdCase, own: Vec<f64>, partner: Vec<f64>) {
        let bonds = &case.bonds;
        let own = single(own);
        self.deviatoric_moment = (0..case.particles.len())
            .map(|i| {
                bonds
                    .range(i)
                    .map(|b| self.bond_volume[b] * f64::from(own[b]) * bonds.length(b).powi(2))
                    .sum()
            })
            .collect();
        self.deviatoric_own = own;
        self.deviatoric_partner = single(partner);
    }

    /// Applies the skin correction ([`skin`]) with factors `k_i` per real particle along
    /// `normal_i` (1: none), on top of the deviatoric factors there are.
    pub fn set_skin(&mut self, case: &PdCase, factor: &[f64], normal: &[Vec3]) {
        let n = case.particles.len();
        let bonds = &case.bonds;
        let mut x = Vec::new();
        case.ghosts
            .extend_positions(&case.particles.position, &mut x);
        let mut own = Vec::with_capacity(bonds.len());
        let mut partner = Vec::with_capacity(bonds.len());
        for i in 0..n {
            for b in bonds.range(i) {
                let j = bonds.partner[b] as usize;
                let l = bonds.length(b);
                let dir = (x[j] - x[i]) / l;
                let si = 1.0 + (factor[i] - 1.0) * dir.dot(&normal[i]).powi(2);
                let (sj, nj) = if j < n {
                    (factor[j], normal[j])
                } else {
                    let g = j - n;
                    let src = case.ghosts.source[g] as usize;
                    let mask = u32::from(case.ghosts.mask[g]);
                    (
                        factor[src],
                        mirror_direction(normal[src], mask, &case.ghosts.planes),
                    )
                };
                let (vi, vj) = self.deviatoric_factors(b);
                own.push(vi * si);
                partner.push(vj * (1.0 + (sj - 1.0) * dir.dot(&nj).powi(2)));
            }
        }
        self.set_deviatoric(case, own, partner);
        self.skin = true;
    }

    /// A stiffness per directed bond (N/m) that bounds the LPS tangent's row as bond-based
    /// PD's `w_ij` does its own, for what sizes a step (ADR's density, the explicit stable
    /// step, the static solver's preconditioner): the deviatoric term `15μ(1/m_i + 1/m_j)
    /// v_c V_j V_i` and the dilatation's coupling through `θ_i` and `θ_j`,
    /// `3|3k − 5μ| |ξ| v_c V_j V_i (S_i/m_i² + S_j/m_j²)`, `S_i = Σ_l ω |ξ_l| v_c V_l`.
    pub fn bond_stiffness(&self, case: &PdCase) -> Vec<f64> {
        let n = case.particles.len();
        let bonds = &case.bonds;
        let vol = &case.particles.volume;
        let source = |j: usize| {
            if j < n {
                j
            } else {
                case.ghosts.source[j - n] as usize
            }
        };
        // Per particle, over its bonds c (weights w_c = ω v_c V_c |ξ_c|): S_i = Σ |ω_d,c| w_c and
        // Y_i = Σ |v_c − ω_d,c m^v_i/m_i| w_c. The state of bond b depends on the extension of
        // bond c through θ_i (`(9k ω_d,b − 15μ v_b)|ξ_b| ω_d,c w_c / m_i²`) and through D_i
        // (`15μ ω_d,b |ξ_b| (v_c − ω_d,c m^v/m) w_c / m_i²`); with every factor 1 the second
        // vanishes and the first is `3(3k − 5μ)|ξ| S_i/m_i²`.
        let sums: Vec<(f64, f64)> = (0..n)
            .map(|i| {
                let m = self.weighted_volume[i];
                let ratio = match self.deviatoric_moment.get(i) {
                    Some(&mv) if m > 0.0 => mv / m,
                    _ => 1.0,
                };
                bonds.range(i).fold((0.0, 0.0), |(s, y), c| {
                    let w = self.bond_volume[c] * bonds.length(c);
                    let d = self.dilatation_factors(c).0;
                    let v = self.deviatoric_factors(c).0;
                    (s + d.abs() * w, y + (v - d * ratio).abs() * w)
                })
            })
            .collect();
        let (k, mu) = (self.bulk, self.shear);
        let coupling = |d: f64, v: f64, (s, y): (f64, f64), m: f64| {
            ((9.0 * k * d - 15.0 * mu * v).abs() * s + 15.0 * mu * d.abs() * y) / (m * m)
        };
        let mut out = Vec::with_capacity(bonds.len());
        for i in 0..n {
            let mi = self.weighted_volume[i];
            for b in bonds.range(i) {
                let j = source(bonds.partner[b] as usize);
                let mj = self.weighted_volume[j];
                let vv = self.bond_volume[b] * vol[i];
                let (gi, gj) = (self.correction[i], self.correction[j]);
                let (si, sj) = self.deviatoric_factors(b);
                let (di, dj) = self.dilatation_factors(b);
                let deviatoric = 15.0 * self.shear * (gi * si.abs() / mi + gj * sj.abs() / mj);
                let dilatation = bonds.length(b)
                    * (gi * coupling(di, si, sums[i], mi) + gj * coupling(dj, sj, sums[j], mj));
                out.push(vv * (deviatoric + dilatation));
            }
        }
        out
    }

    /// The LPS forces at positions `pos` (real particles, then mirror images): for every real
    /// particle `i`, `finish(i, f_i, &mut out[i])` with `f_i` its total internal force (N).
    pub fn forces<T: Send>(
        &mut self,
        case: &PdCase,
        pos: &[Vec3],
        stretch: Stretch,
        out: &mut [T],
        finish: impl Fn(usize, Vec3, &mut T) + Sync,
    ) {
        let n = case.particles.len();
        self.forces_on(case, pos, stretch, 0..n, |_| {}, out, finish);
    }

    /// [`forces`](Self::forces) for the particles `own` alone (a rank's share of a decomposed
    /// run; `finish` is called for these only): their dilatations and force states, then
    /// `share` gives the other particles' states from their owners (every bond partner of
    /// `own`: the ghosts), then their forces. Each owned particle's force is the same sum in
    /// the same order as in one process, so the bits do not depend on the ranks.
    #[allow(clippy::too_many_arguments)]
    pub fn forces_on<T: Send>(
        &mut self,
        case: &PdCase,
        pos: &[Vec3],
        stretch: Stretch,
        own: Range<usize>,
        share: impl FnOnce(&mut [Vec3]),
        out: &mut [T],
        finish: impl Fn(usize, Vec3, &mut T) + Sync,
    ) {
        // The kinematics chosen once, outside the bond loops: each arm's constant `Stretch`
        // folds the match away (a match per bond kept the loops 25 % slower).
        match stretch {
            Stretch::Finite => self.pass(
                case,
                (pos, None),
                |i, j, l| extension(Stretch::Finite, pos, i, j, l),
                |i, j, l| extension_along(Stretch::Finite, pos, i, j, l),
                own,
                share,
                out,
                finish,
            ),
            Stretch::Small(r) => self.pass(
                case,
                (pos, Some(r)),
                |i, j, l| extension(Stretch::Small(r), pos, i, j, l),
                |i, j, l| extension_along(Stretch::Small(r), pos, i, j, l),
                own,
                share,
                out,
                finish,
            ),
        }
    }

    /// [`forces_on`](Self::forces_on) with the bonds' extension `e(i, j, l)`, and `d(i, j, l)`
    /// the extension with the direction its force acts along. The second sweep computes each
    /// extension again rather than reading it back: the direction takes the same root (or,
    /// linearised, the same reference bond). Whether there are deviatoric and dilatation
    /// factors is chosen here, once, for the loops ([`Self::sweeps`]).
    #[allow(clippy::too_many_arguments)]
    fn pass<T: Send>(
        &mut self,
        case: &PdCase,
        at: (&[Vec3], Option<&[Vec3]>),
        bond: impl Fn(usize, usize, f64) -> f64 + Sync,
        direction: impl Fn(usize, usize, f64) -> (f64, Vec3, f64) + Sync,
        own: Range<usize>,
        share: impl FnOnce(&mut [Vec3]),
        out: &mut [T],
        finish: impl Fn(usize, Vec3, &mut T) + Sync,
    ) {
        let weighted = !self.deviatoric_own.is_empty();
        let dilated = !self.dilatation_own.is_empty();
        match (weighted, dilated) {
            (false, false) => {
                self.sweeps::<false, false, T>(case, at, bond, direction, own, share, out, finish)
            }
            (true, false) => {
                self.sweeps::<true, false, T>(case, at, bond, direction, own, share, out, finish)
            }
            (false, true) => {
                self.sweeps::<false, true, T>(case, at, bond, direction, own, share, out, finish)
            }
            (true, true) => {
                self.sweeps::<true, true, T>(case, at, bond, direction, own, share, out, finish)
            }
        }
    }

    /// The pass's two sweeps over the bonds, `W`: with deviatoric factors, `D`: with
    /// dilatation factors; each particle's bonds four at a time in AVX2 where the processor
    /// has it ([`kernel`]), else one at a time.
    #[allow(clippy::too_many_arguments)]
    fn sweeps<const W: bool, const D: bool, T: Send>(
        &mut self,
        case: &PdCase,
        (pos, reference): (&[Vec3], Option<&[Vec3]>),
        bond: impl Fn(usize, usize, f64) -> f64 + Sync,
        direction: impl Fn(usize, usize, f64) -> (f64, Vec3, f64) + Sync,
        own: Range<usize>,
        share: impl FnOnce(&mut [Vec3]),
        out: &mut [T],
        finish: impl Fn(usize, Vec3, &mut T) + Sync,
    ) {
        let n = case.particles.len();
        let bonds = &case.bonds;
        let (bv, m) = (&self.bond_volume, &self.weighted_volume);
        let (v_own, v_partner, mv) = (
            &self.deviatoric_own,
            &self.deviatoric_partner,
            &self.deviatoric_moment,
        );
        let (d_own, d_partner) = (&self.dilatation_own, &self.dilatation_partner);
        #[cfg(target_arch = "x86_64")]
        let avx = !self.portable && crate::case::pairs::has_avx2_fma();
        #[cfg(target_arch = "x86_64")]
        let row = |r: Range<usize>| kernel::Row {
            partner: &bonds.partner[r.clone()],
            length: &bonds.length[r.clone()],
            volume: &bv[r.clone()],
            dev_own: if W { &v_own[r.clone()] } else { &[] },
            dev_partner: if W { &v_partner[r.clone()] } else { &[] },
            dil_own: if D { &d_own[r.clone()] } else { &[] },
            dil_partner: if D { &d_partner[r] } else { &[] },
        };
        // One particle's dilatation sums, a bond at a time.
        let dilatation_sums = |i: usize, r: Range<usize>| {
            let (mut sum, mut deviatoric) = (0.0, 0.0);
            for b in r {
                let (l, j) = (bonds.length(b), bonds.partner[b] as usize);
                let w = bv[b] * l * bond(i, j, l);
                sum += if D { w * f64::from(d_own[b]) } else { w };
                if W {
                    deviatoric += w * f64::from(v_own[b]);
                }
            }
            (sum, deviatoric)
        };
        self.dilatation
            .par_chunks_mut(CHUNK)
            .zip(self.deviation.par_chunks_mut(CHUNK))
            .enumerate()
            .for_each(|(c, (theta, dev))| {
                let start = c * CHUNK;
                for (q, (t, d)) in theta.iter_mut().zip(dev.iter_mut()).enumerate() {
                    let i = start + q;
                    if !own.contains(&i) {
                        continue;
                    }
                    let r = bonds.range(i);
                    #[cfg(target_arch = "x86_64")]
                    let (sum, deviatoric) = if avx {
                        let row = row(r);
                        // SAFETY: the processor has AVX2 and FMA; every access is checked.
                        unsafe {
                            match reference {
                                None => kernel::dilatation_sums::<W, D, false>(&row, pos, &[], i),
                                Some(x) => kernel::dilatation_sums::<W, D, true>(&row, pos, x, i),
                            }
                        }
                    } else {
                        dilatation_sums(i, r)
                    };
                    #[cfg(not(target_arch = "x86_64"))]
                    let (sum, deviatoric) = dilatation_sums(i, r);
                    *t = if m[i] > 0.0 { 3.0 * sum / m[i] } else { 0.0 };
                    // D_i = Σ ω v e^d |ξ| V / 3, which vanishes where v = 1 and the dilatation's
                    // weights are 1 (Σ ω e|ξ|V = mθ/3); position-aware dilatation weights
                    // come with deviatoric ones.
                    *d = if W {
                        (deviatoric - *t * mv[i] / 3.0) / 3.0
                    } else {
                        0.0
                    };
                }
            });
        // t_i<ξ> = g_i ((3 ω_d|ξ|/m_i)(kθ_i − 15μ D_i/m_i) + (15μ/m_i) v (e − θ_i|ξ|/3)), which
        // is ((3k − 5μ)θ|ξ| + 15μ e)/m where the factors are 1: per particle
        // `t = a ω_d|ξ| + b v (e − c|ξ|)`, its three constants computed once a pass rather
        // than at each of its bonds.
        let (k, mu) = (self.bulk, self.shear);
        let g = &self.correction;
        let (theta, deviation) = (&self.dilatation, &self.deviation);
        self.state
            .par_chunks_mut(CHUNK)
            .enumerate()
            .for_each(|(c, state)| {
                for (q, t) in state.iter_mut().enumerate() {
                    let i = c * CHUNK + q;
                    if !own.contains(&i) {
                        continue;
                    }
                    let mi = m[i];
                    *t = if mi > 0.0 {
                        Vec3::new(
                            g[i] * 3.0 / mi * (k * theta[i] - 15.0 * mu * deviation[i] / mi),
                            g[i] * 15.0 * mu / mi,
                            theta[i] / 3.0,
                        )
                    } else {
                        Vec3::zeros()
                    };
                }
            });
        share(&mut self.state);
        let state = &self.state;
        let source = |j: usize| {
            if j < n {
                j
            } else {
                case.ghosts.source[j - n] as usize
            }
        };
        // One particle's force, a bond at a time.
        let force_sum = |i: usize, r: Range<usize>| {
            let [ai, bi, ci] = state[i].into();
            let mut f = Vec3::zeros();
            for b in r {
                let l = bonds.length(b);
                let j = bonds.partner[b] as usize;
                let (e, dir, inv) = direction(i, j, l);
                let (vi, vj) = if W {
                    (f64::from(v_own[b]), f64::from(v_partner[b]))
                } else {
                    (1.0, 1.0)
                };
                let (di, dj) = if D {
                    (f64::from(d_own[b]), f64::from(d_partner[b]))
                } else {
                    (1.0, 1.0)
                };
                let [aj, bj, cj] = state[source(j)].into();
                let t = ai * di * l + bi * vi * (e - ci * l) + aj * dj * l + bj * vj * (e - cj * l);
                f += dir * (t * bv[b] * inv);
            }
            f
        };
        let vol = &case.particles.volume;
        out.par_chunks_mut(CHUNK).enumerate().for_each(|(c, out)| {
            for (q, o) in out.iter_mut().enumerate() {
                let i = c * CHUNK + q;
                if !own.contains(&i) {
                    continue;
                }
                let r = bonds.range(i);
                #[cfg(target_arch = "x86_64")]
                let f = if avx {
                    let row = row(r);
                    let src = &case.ghosts.source;
                    // SAFETY: the processor has AVX2 and FMA; every access is checked.
                    unsafe {
                        match reference {
                            None => {
                                kernel::force_sum::<W, D, false>(&row, pos, &[], state, src, n, i)
                            }
                            Some(x) => {
                                kernel::force_sum::<W, D, true>(&row, pos, x, state, src, n, i)
                            }
                        }
                    }
                } else {
                    force_sum(i, r)
                };
                #[cfg(not(target_arch = "x86_64"))]
                let f = force_sum(i, r);
                finish(i, f * vol[i], o);
            }
        });
    }

    /// The strain energy of particle `i` at positions `pos` (J), with the dilatation of the last
    /// pass: `V_i (k θ_i²/2 + (15μ/(2m_i)) Σ_j ω (e − θ_i|ξ|/3)² v_c V_j)`.
    pub fn strain_energy_of(&self, case: &PdCase, i: usize, pos: &[Vec3], stretch: Stretch) -> f64 {
        let bonds = &case.bonds;
        let m = self.weighted_volume[i];
        if !(m > 0.0) {
            return 0.0;
        }
        let theta = self.dilatation[i];
        let mut dev = 0.0;
        for b in bonds.range(i) {
            let l = bonds.length(b);
            let e = extension(stretch, pos, i, bonds.partner[b] as usize, l);
            let ed = e - theta * l / 3.0;
            let v = self.deviatoric_factors(b).0;
            dev += self.bond_volume[b] * v * ed * ed;
        }
        self.correction[i]
            * case.particles.volume[i]
            * (0.5 * self.bulk * theta * theta + 7.5 * self.shear / m * dev)
    }
}

/// Per-bond factors in single precision, as the pass streams them.
fn single(v: Vec<f64>) -> Vec<f32> {
    v.into_iter().map(|x| x as f32).collect()
}

/// The extension `e` of the bond from `i` to `j` (reference length `l`) at positions `pos`.
#[inline]
fn extension(stretch: Stretch, pos: &[Vec3], i: usize, j: usize, l: f64) -> f64 {
    match stretch {
        Stretch::Finite => (pos[j] - pos[i]).norm() - l,
        Stretch::Small(r) => ((pos[j] - r[j]) - (pos[i] - r[i])).dot(&(r[j] - r[i])) / l,
    }
}

/// The surface correction of the LPS: per particle, `g_i = 3 W∞ / Σ_a W_i(ε_a)`, its strain
/// energy density under the three homogeneous uniaxial stresses (`ε` along axis `a`, `−νε`
/// across it) against the continuum's `W∞ = E ε²/2`. `m_i` over the actual neighbourhood
/// makes the dilatation exact at a flat surface, where the half sphere's second moments are
/// the whole one's, but not within a horizon of it, where a sphere less a cap is not
/// isotropic: a gmsh tet bar pulled along its free faces came out 5-9 % too stiff. Scaling
/// the whole force state of particle `i` by `g_i` keeps the pass the gradient of an energy
/// (`Σ g_i W_i V_i`), so forces stay equal and opposite.
fn surface_factors(lps: &Lps, case: &PdCase, youngs: f64, poisson: f64) -> Vec<f64> {
    let n = case.particles.len();
    let bonds = &case.bonds;
    let mut x = Vec::new();
    case.ghosts
        .extend_positions(&case.particles.position, &mut x);
    let eps = 1e-3;
    let bulk_energy = 0.5 * youngs * eps * eps;
    let (k, mu) = (lps.bulk, lps.shear);
    (0..n)
        .into_par_iter()
        .map(|i| {
            let m = lps.weighted_volume[i];
            if !(m > 0.0) {
                return 1.0;
            }
            let mut energy = 0.0;
            for a in 0..3 {
                let mut strain = Vec3::repeat(-poisson * eps);
                strain[a] = eps;
                let extension = |b: usize| {
                    let xi = x[bonds.partner[b] as usize] - x[i];
                    xi.component_mul(&strain).dot(&xi) / bonds.length(b)
                };
                let theta = 3.0
                    * bonds
                        .range(i)
                        .map(|b| lps.bond_volume[b] * bonds.length(b) * extension(b))
                        .sum::<f64>()
                    / m;
                let dev: f64 = bonds
                    .range(i)
                    .map(|b| {
                        let ed = extension(b) - theta * bonds.length(b) / 3.0;
                        lps.bond_volume[b] * ed * ed
                    })
                    .sum();
                energy += 0.5 * k * theta * theta + 7.5 * mu / m * dev;
            }
            if energy > 0.0 {
                3.0 * bulk_energy / energy
            } else {
                1.0
            }
        })
        .collect()
}

/// The extension of the bond from `i` to `j` (reference length `l`) at positions `pos`, as
/// [`extension`] gives it, with the direction its force acts along as a vector `v` and the
/// inverse of its length (the direction `v/|v|`): one division a bond rather than three.
#[inline]
fn extension_along(stretch: Stretch, pos: &[Vec3], i: usize, j: usize, l: f64) -> (f64, Vec3, f64) {
    match stretch {
        Stretch::Finite => {
            let y = pos[j] - pos[i];
            let r = y.norm();
            (r - l, y, 1.0 / r)
        }
        Stretch::Small(r) => {
            let xi = r[j] - r[i];
            let inv = 1.0 / l;
            (((pos[j] - r[j]) - (pos[i] - r[i])).dot(&xi) * inv, xi, inv)
        }
    }
}
