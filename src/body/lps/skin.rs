//! The skin correction of the linear peridynamic solid: the surface row's state stiffened
//! along its normal, so that a traction entering through the surface (a contact's) does not
//! first compress a soft skin. The counterpart of the bond-based one ([`crate::case::skin`],
//! whose reasoning it follows; docs/VALIDATION.md, "Any Poisson's ratio").
//!
//! Under the uniform strain `ε n ⊗ n` (lateral strain held: the state under a contact's
//! centre), the continuum carries `σ_nn = (k + 4μ/3) ε` across the surface, `σ_nn A_i` through
//! a surface particle of pressure area `A_i`; the LPS surface particle's force, the
//! traction its neighbourhood misses, is smaller. Particle `i`'s deviatoric weight becomes
//! `ω s_i(ξ)`, `s_i = 1 + (k_i − 1)(n_i·ξ̂)²`, in its energy `W_i = g_i (kθ²/2 + (15μ/2m_i)
//! Σ_j ω s_i (e^d)² v_c V_j)` (the pass stays the gradient of an energy), which leaves bonds
//! along the surface as they were; `k_i` is the one that makes the particle's normal force
//! [`TRACTION_SHARE`] of the continuum's, its neighbours' states taken uncorrected (the force
//! is linear in `k_i`, so one solve; with the neighbours' factors, iterated, the factors move
//! by 5 % and the Hertz sphere by 0.1 points).

use rayon::prelude::*;

use super::Lps;
use crate::case::{mirror_direction, PdCase};
use crate::math::Vec3;

/// Share of the continuum traction the surface row carries under a uniform normal strain:
/// the whole of it. The bond-based correction's 0.8 (calibrated there) left the LPS Hertz
/// sphere 4 % too wide; 1 is the unscaled balance (docs/VALIDATION.md, "Any Poisson's ratio").
pub const TRACTION_SHARE: f64 = 1.0;

/// Bounds of a particle's factor. The deviatoric weight is a weak lever on the normal force
/// (the dilatation's share is untouched, and `D_i` takes back part of it): the factors come
/// out 10-30, most where ν is large.
const FACTOR_BOUNDS: (f64, f64) = (0.5, 40.0);

/// Particle `j`'s dilatation and `D_j` (the pass's, [`Lps`]) under the uniform strain
/// `ε f⊗f` (`f` in `j`'s own frame), with its dilatation and deviatoric factors as they are.
fn uniaxial(lps: &Lps, case: &PdCase, x: &[Vec3], j: usize, f: Vec3, eps: f64) -> (f64, f64) {
    let bonds = &case.bonds;
    let m = lps.weighted_volume[j];
    if !(m > 0.0) {
        return (0.0, 0.0);
    }
    let (mut sum, mut dev, mut moment) = (0.0, 0.0, 0.0);
    for b in bonds.range(j) {
        let l = bonds.length(b);
        let c = (x[bonds.partner[b] as usize] - x[j]).dot(&f) / l;
        let e = eps * l * c * c;
        let w = lps.bond_volume[b] * l;
        sum += w * e * lps.dilatation_factors(b).0;
        let v = lps.deviatoric_factors(b).0;
        dev += w * e * v;
        moment += w * l * v;
    }
    let theta = 3.0 * sum / m;
    (theta, (dev - theta * moment / 3.0) / 3.0)
}

/// Per real particle: the factor `k_i` (1 where none) and the normal it acts along; on the
/// surface particles `only` marks where it is given (every one where `None`: the bodies a
/// partner may press anywhere; [`crate::body::facing`]).
pub fn skin_factors(lps: &Lps, case: &PdCase, only: Option<&[bool]>) -> (Vec<f64>, Vec<Vec3>) {
    let n = case.particles.len();
    let bonds = &case.bonds;
    let mut x = Vec::new();
    case.ghosts
        .extend_positions(&case.particles.position, &mut x);
    let (m, bv, g) = (&lps.weighted_volume, &lps.bond_volume, &lps.correction);
    let (kb, mu) = (lps.bulk, lps.shear);
    let normal = &case.surface.normal;
    let area = case.segments.load_areas();
    let sigma = kb + 4.0 * mu / 3.0;
    let factor: Vec<f64> = (0..n)
        .into_par_iter()
        .map(|i| {
            if !case.surface.is_surface[i]
                || !(area[i] > 0.0)
                || !(m[i] > 0.0)
                || only.is_some_and(|o| !o[i])
            {
                return 1.0;
            }
            let nrm = normal[i];
            let eps = 1.0;
            let mi = m[i];
            let (theta_i, dev_i) = uniaxial(lps, case, &x, i, nrm, eps);
            // d_i: D_i per unit (k_i − 1).
            let mut d = 0.0;
            for b in bonds.range(i) {
                let l = bonds.length(b);
                let dir = (x[bonds.partner[b] as usize] - x[i]) / l;
                let c2 = dir.dot(&nrm).powi(2);
                let v = lps.deviatoric_factors(b).0;
                d += bv[b] * v * c2 * (eps * l * c2 * l - theta_i * l * l / 3.0);
            }
            d /= 3.0;
            // The force state `g((3 ω_d|ξ|/m)(kθ − 15μD/m) + (15μ/m) v (e − θ|ξ|/3))`.
            let state =
                |gm: f64, m: f64, theta: f64, dev: f64, w_d: f64, v: f64, l: f64, e: f64| {
                    gm * (3.0 * w_d * l / m * (kb * theta - 15.0 * mu * dev / m)
                        + 15.0 * mu / m * v * (e - theta * l / 3.0))
                };
            // f_i·n = a + (k_i − 1) b, per unit volume V_i.
            let (mut a, mut slope) = (0.0, 0.0);
            for b in bonds.range(i) {
                let l = bonds.length(b);
                let p = bonds.partner[b] as usize;
                let dir = (x[p] - x[i]) / l;
                let c = dir.dot(&nrm);
                let e = eps * l * c * c;
                // The partner's state in its own frame (a mirror image's field is mirrored).
                let (j, field_j) = if p < n {
                    (p, nrm)
                } else {
                    let q = p - n;
                    let mask = u32::from(case.ghosts.mask[q]);
                    (
                        case.ghosts.source[q] as usize,
                        mirror_direction(nrm, mask, &case.ghosts.planes),
                    )
                };
                let (di, dj) = lps.dilatation_factors(b);
                let (vi, vj) = lps.deviatoric_factors(b);
                let t_i = state(g[i], mi, theta_i, dev_i, di, vi, l, e);
                let t_j = if m[j] > 0.0 {
                    let (theta_j, dev_j) = uniaxial(lps, case, &x, j, field_j, eps);
                    state(g[j], m[j], theta_j, dev_j, dj, vj, l, e)
                } else {
                    0.0
                };
                let dt_i = g[i]
                    * (-3.0 * di * l / mi * 15.0 * mu * d / mi
                        + 15.0 * mu / mi * vi * c * c * (e - theta_i * l / 3.0));
                a += (t_i + t_j) * c * bv[b];
                slope += dt_i * c * bv[b];
            }
            // The continuum's: the surface particle's volume takes σ_nn A_i inwards.
            let target = -TRACTION_SHARE * sigma * eps * area[i] / case.particles.volume[i];
            if !(slope.abs() > 0.0) {
                return 1.0;
            }
            (1.0 + (target - a) / slope).clamp(FACTOR_BOUNDS.0, FACTOR_BOUNDS.1)
        })
        .collect();
    (factor, normal.clone())
}
