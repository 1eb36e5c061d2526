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
//! surface in part.
//!
//! At ν = 1/4, `3k = 5μ`: the dilatation drops out and the force is bond-based PD's with a
//! micromodulus `15μ(1/m_i + 1/m_j)`.
//!
//! The pass goes over directed bonds (each pair from both ends), a particle summing its own
//! bonds in order: the same bits whatever the thread count. Symmetry planes: a partner's
//! whole volume in the sums, the particle's held share `V_i` on its force (as the bond-based
//! pass, [`crate::case::pairs`]); a mirror image takes its source's `m` and `θ`.

mod skin;

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
    /// ([`surface_factors`]); 1 in the bulk.
    pub correction: Vec<f64>,
    /// The skin correction ([`skin`]): per directed bond `i → j`, the factor `s_i(ξ)` of its
    /// deviatoric weight in particle `i`'s state and `s_j(−ξ)` in `j`'s (empty: none).
    pub skin_own: Vec<f64>,
    pub skin_partner: Vec<f64>,
    /// Per real particle: `m^s_i = Σ_j ω s_i |ξ|² v_c V_j` (empty without the skin correction).
    skin_moment: Vec<f64>,
    /// Per real particle: the dilatation of the last pass (scratch).
    dilatation: Vec<f64>,
    /// Per real particle: `D_i = Σ_j ω s_i e^d |ξ| v_c V_j / 3` of the last pass, which the
    /// skin's weights make nonzero (scratch).
    deviation: Vec<f64>,
    /// Per real particle: the force state's three constants of the last pass (scratch; a
    /// `Vec3` so that a decomposed run sends them to ghosts as it sends displacements).
    state: Vec<Vec3>,
    /// Per directed bond: its extension in the last pass (scratch).
    extension: Vec<f64>,
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
    /// The LPS of case `case` for Young's modulus `youngs` and Poisson's ratio `poisson`.
    pub fn new(case: &PdCase, youngs: f64, poisson: f64) -> Lps {
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
                let v = v_c(i, j, l) * partner_vol[j];
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
            skin_own: Vec::new(),
            skin_partner: Vec::new(),
            skin_moment: Vec::new(),
            dilatation: vec![0.0; n],
            deviation: vec![0.0; n],
            state: vec![Vec3::zeros(); n],
            extension: Vec::new(),
        };
        lps.correction = surface_factors(&lps, case, youngs, poisson);
        lps
    }

    /// Applies the skin correction ([`skin`]) with factors `k_i` per real particle along
    /// `normal_i` (1: none).
    pub fn set_skin(&mut self, case: &PdCase, factor: &[f64], normal: &[Vec3]) {
        let n = case.particles.len();
        let bonds = &case.bonds;
        let mut x = Vec::new();
        case.ghosts
            .extend_positions(&case.particles.position, &mut x);
        let mut own = Vec::with_capacity(bonds.len());
        let mut partner = Vec::with_capacity(bonds.len());
        let mut moment = vec![0.0; n];
        for (i, m) in moment.iter_mut().enumerate() {
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
                own.push(si);
                partner.push(1.0 + (sj - 1.0) * dir.dot(&nj).powi(2));
                *m += self.bond_volume[b] * si * l * l;
            }
        }
        self.skin_own = own;
        self.skin_partner = partner;
        self.skin_moment = moment;
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
        let reach: Vec<f64> = (0..n)
            .map(|i| {
                bonds
                    .range(i)
                    .map(|b| self.bond_volume[b] * bonds.length(b))
                    .sum()
            })
            .collect();
        let coupling = 3.0 * (3.0 * self.bulk - 5.0 * self.shear).abs();
        let mut out = Vec::with_capacity(bonds.len());
        for i in 0..n {
            let mi = self.weighted_volume[i];
            for b in bonds.range(i) {
                let j = source(bonds.partner[b] as usize);
                let mj = self.weighted_volume[j];
                let vv = self.bond_volume[b] * vol[i];
                let (gi, gj) = (self.correction[i], self.correction[j]);
                let (si, sj) = match (self.skin_own.get(b), self.skin_partner.get(b)) {
                    (Some(&a), Some(&c)) => (a, c),
                    _ => (1.0, 1.0),
                };
                let deviatoric = 15.0 * self.shear * (gi * si / mi + gj * sj / mj);
                let dilatation = coupling
                    * bonds.length(b)
                    * (gi * reach[i] / (mi * mi) + gj * reach[j] / (mj * mj));
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
                |i, j, l| extension(Stretch::Finite, pos, i, j, l),
                |i, j, l| direction(Stretch::Finite, pos, i, j, l),
                own,
                share,
                out,
                finish,
            ),
            Stretch::Small(r) => self.pass(
                case,
                |i, j, l| extension(Stretch::Small(r), pos, i, j, l),
                |i, j, l| direction(Stretch::Small(r), pos, i, j, l),
                own,
                share,
                out,
                finish,
            ),
        }
    }

    /// [`forces_on`](Self::forces_on) with the bonds' extension `e(i, j, l)` and force
    /// direction `d(i, j, l)`.
    #[allow(clippy::too_many_arguments)]
    fn pass<T: Send>(
        &mut self,
        case: &PdCase,
        bond: impl Fn(usize, usize, f64) -> f64 + Sync,
        direction: impl Fn(usize, usize, f64) -> Vec3 + Sync,
        own: Range<usize>,
        share: impl FnOnce(&mut [Vec3]),
        out: &mut [T],
        finish: impl Fn(usize, Vec3, &mut T) + Sync,
    ) {
        let n = case.particles.len();
        let bonds = &case.bonds;
        let (bv, m) = (&self.bond_volume, &self.weighted_volume);
        let (s_own, s_partner, ms) = (&self.skin_own, &self.skin_partner, &self.skin_moment);
        let skin = !s_own.is_empty();
        // Each bond's extension, kept for the second pass.
        self.extension.resize(bonds.len(), 0.0);
        bonds
            .blocks(&mut self.extension, CHUNK)
            .into_par_iter()
            .zip(self.dilatation.par_chunks_mut(CHUNK))
            .zip(self.deviation.par_chunks_mut(CHUNK))
            .for_each(|(((range, ext), theta), dev)| {
                let first = bonds.offsets[range.start];
                for ((i, t), d) in range.zip(theta.iter_mut()).zip(dev.iter_mut()) {
                    if !own.contains(&i) {
                        continue;
                    }
                    let (mut sum, mut skinned) = (0.0, 0.0);
                    for b in bonds.range(i) {
                        let l = bonds.length(b);
                        let e = bond(i, bonds.partner[b] as usize, l);
                        ext[b - first] = e;
                        sum += bv[b] * l * e;
                        if skin {
                            skinned += bv[b] * s_own[b] * l * e;
                        }
                    }
                    *t = if m[i] > 0.0 { 3.0 * sum / m[i] } else { 0.0 };
                    // D_i = Σ ω s e^d |ξ| V / 3, which vanishes where s = 1 (Σ ω e|ξ|V = mθ/3).
                    *d = if skin {
                        (skinned - *t * ms[i] / 3.0) / 3.0
                    } else {
                        0.0
                    };
                }
            });
        // t_i<ξ> = g_i ((3|ξ|/m_i)(kθ_i − 15μ D_i/m_i) + (15μ/m_i) s (e − θ_i|ξ|/3)), which
        // is ((3k − 5μ)θ|ξ| + 15μ e)/m where s = 1: per particle `t = a|ξ| + b s (e − c|ξ|)`,
        // its three constants computed once a pass rather than at each of its bonds.
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
        let (state, extension) = (&self.state, &self.extension);
        let source = |j: usize| {
            if j < n {
                j
            } else {
                case.ghosts.source[j - n] as usize
            }
        };
        let vol = &case.particles.volume;
        out.par_chunks_mut(CHUNK).enumerate().for_each(|(c, out)| {
            for (q, o) in out.iter_mut().enumerate() {
                let i = c * CHUNK + q;
                if !own.contains(&i) {
                    continue;
                }
                let [ai, bi, ci] = state[i].into();
                let mut f = Vec3::zeros();
                for b in bonds.range(i) {
                    let l = bonds.length(b);
                    let j = bonds.partner[b] as usize;
                    let e = extension[b];
                    let dir = direction(i, j, l);
                    let (si, sj) = if skin {
                        (s_own[b], s_partner[b])
                    } else {
                        (1.0, 1.0)
                    };
                    let [aj, bj, cj] = state[source(j)].into();
                    let t = ai * l + bi * si * (e - ci * l) + aj * l + bj * sj * (e - cj * l);
                    f += dir * (t * bv[b]);
                }
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
            let s = self.skin_own.get(b).copied().unwrap_or(1.0);
            dev += self.bond_volume[b] * s * ed * ed;
        }
        self.correction[i]
            * case.particles.volume[i]
            * (0.5 * self.bulk * theta * theta + 7.5 * self.shear / m * dev)
    }
}

/// The extension `e` of the bond from `i` to `j` (reference length `l`) at positions `pos`.
#[inline]
fn extension(stretch: Stretch, pos: &[Vec3], i: usize, j: usize, l: f64) -> f64 {
    match stretch {
        Stretch::Finite => (pos[j] - pos[i]).norm() - l,
        Stretch::Small(r) => ((pos[j] - r[j]) - (pos[i] - r[i])).dot(&((r[j] - r[i]) / l)),
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

/// The direction the force of the bond from `i` to `j` (reference length `l`) acts along.
#[inline]
fn direction(stretch: Stretch, pos: &[Vec3], i: usize, j: usize, l: f64) -> Vec3 {
    match stretch {
        Stretch::Finite => {
            let y = pos[j] - pos[i];
            y / y.norm()
        }
        Stretch::Small(r) => (r[j] - r[i]) / l,
    }
}
