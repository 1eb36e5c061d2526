//! The position-aware LPS (Mitchell, Silling & Littlewood, J. Mech. Mater. Struct. 10, 2015;
//! METHOD.md §8): per particle, influence functions that make its dilatation and its
//! strain energy the continuum's under every homogeneous deformation, wherever it lies.
//!
//! Where a particle's neighbourhood is cut by a surface (within a horizon of it, where a
//! sphere less a cap is not isotropic) or its quadrature is uneven (a gmsh tet mesh), the
//! plain LPS's moments of the neighbourhood are not the continuum's, and a bar along its free
//! faces comes out stiff (docs/VALIDATION.md, "Any Poisson's ratio"). Here particle `i`'s
//! dilatation weight is `ω_d = 1 + ξ̂ᵀA_iξ̂` and its deviatoric weight `ω = 1 + B_i::ξ̂⁴`
//! (`A_i` symmetric, `B_i` fully symmetric: 6 and 15 unknowns), the smallest departures from 1
//! (in the bond-volume-weighted sense) such that
//!
//! - `Σ_j ω_d v_c V_j ξ ⊗ ξ = (m_i/3) I`: `θ_i = tr ε` for every uniform strain ε, and
//! - `Σ_j ω v_c V_j ξ⊗ξ⊗ξ⊗ξ / |ξ|² = (m_i/15)(δδ + δδ + δδ)`: the deviatoric energy
//!   `(15μ/2m_i) Σ ω (e^d)² v_c V_j` is then `μ ε':ε'` for every uniform strain,
//!
//! with `m_i = Σ_j ω v_c V_j |ξ|²` as before (a half sphere's second and fourth moments are
//! isotropic, so at a flat face the weights stay 1). The force state keeps its form (the
//! pass is the gradient of `Σ_i V_i W_i`, forces equal and opposite); each weight enters it
//! per directed bond, the partner's evaluated in the partner's own neighbourhood (a mirror
//! image's is its source's, mirrored).

use nalgebra::{SMatrix, SVector};
use rayon::prelude::*;

use crate::case::{mirror_direction, PdCase};
use crate::math::Vec3;

/// The range every weight is kept within.
pub const BOUNDS: (f64, f64) = (0.25, 4.0);

/// The largest share `t ≤ 1` of a weight's departure `δ` from 1 with `1 + tδ` in [`BOUNDS`].
fn within(delta: f64) -> f64 {
    if 1.0 + delta < BOUNDS.0 {
        (1.0 - BOUNDS.0) / -delta
    } else if 1.0 + delta > BOUNDS.1 {
        (BOUNDS.1 - 1.0) / delta
    } else {
        1.0
    }
}

/// The quadratic monomials of a unit direction: the components of `u ⊗ u`.
fn quadratic(u: &Vec3) -> SVector<f64, 6> {
    let (x, y, z) = (u.x, u.y, u.z);
    SVector::<f64, 6>::from([x * x, y * y, z * z, x * y, x * z, y * z])
}

/// The quartic monomials of a unit direction: the components of `u ⊗ u ⊗ u ⊗ u`.
fn quartic(u: &Vec3) -> SVector<f64, 15> {
    let (x, y, z) = (u.x, u.y, u.z);
    let (xx, yy, zz) = (x * x, y * y, z * z);
    SVector::<f64, 15>::from([
        xx * xx,
        yy * yy,
        zz * zz,
        xx * x * y,
        xx * x * z,
        yy * y * x,
        yy * y * z,
        zz * z * x,
        zz * z * y,
        xx * yy,
        xx * zz,
        yy * zz,
        xx * y * z,
        yy * x * z,
        zz * x * y,
    ])
}

/// The continuum's moments per unit `m`: `Σ ω ξ⊗ξ = (m/3) I` and the isotropic fourth
/// moment's `m/5` (`u_x⁴`) and `m/15` (`u_x² u_y²`).
fn quadratic_target() -> SVector<f64, 6> {
    SVector::<f64, 6>::from([1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0, 0.0, 0.0, 0.0])
}

fn quartic_target() -> SVector<f64, 15> {
    let mut t = SVector::<f64, 15>::zeros();
    for k in 0..3 {
        t[k] = 0.2;
    }
    for k in 9..12 {
        t[k] = 1.0 / 15.0;
    }
    t
}

/// Per real particle, the coefficients of its two weights (zero where its neighbourhood does
/// not determine them: too few bond directions).
#[derive(Clone, Debug)]
pub struct Coefficients {
    pub dilatation: Vec<SVector<f64, 6>>,
    pub deviatoric: Vec<SVector<f64, 15>>,
}

/// The weights' coefficients of every real particle of `case`, `bond_volume` per directed
/// bond (`ω v_c V_j`) and `m` per particle.
pub fn coefficients(case: &PdCase, bond_volume: &[f64], m: &[f64]) -> Coefficients {
    let n = case.particles.len();
    let bonds = &case.bonds;
    let mut x = Vec::new();
    case.ghosts
        .extend_positions(&case.particles.position, &mut x);
    let (dilatation, deviatoric) = (0..n)
        .into_par_iter()
        .map(|i| {
            let mut g2 = SMatrix::<f64, 6, 6>::zeros();
            let mut g4 = SMatrix::<f64, 15, 15>::zeros();
            let mut r2 = quadratic_target() * m[i];
            let mut r4 = quartic_target() * m[i];
            for b in bonds.range(i) {
                let l = bonds.length(b);
                let u = (x[bonds.partner[b] as usize] - x[i]) / l;
                let w = bond_volume[b] * l * l;
                let (p2, p4) = (quadratic(&u), quartic(&u));
                g2.syger(w, &p2, &p2, 1.0);
                g4.syger(w, &p4, &p4, 1.0);
                r2 -= p2 * w;
                r4 -= p4 * w;
            }
            // Lower triangles only were updated: the Cholesky reads those.
            let a = g2
                .cholesky()
                .map(|c| c.solve(&r2))
                .unwrap_or_else(SVector::zeros);
            let b = g4
                .cholesky()
                .map(|c| c.solve(&r4))
                .unwrap_or_else(SVector::zeros);
            // Where the neighbourhood is a sliver (an edge's, a corner's: few bonds, near
            // the 15 unknowns) the exact weights swing far from 1 and turn negative, and a
            // negative deviatoric weight makes the energy indefinite: the correction is
            // scaled back until every weight of the particle lies within `BOUNDS`.
            let (mut ta, mut tb) = (1.0f64, 1.0f64);
            for bd in bonds.range(i) {
                let u = (x[bonds.partner[bd] as usize] - x[i]) / bonds.length(bd);
                ta = ta.min(within(a.dot(&quadratic(&u))));
                tb = tb.min(within(b.dot(&quartic(&u))));
            }
            (a * ta, b * tb)
        })
        .unzip();
    Coefficients {
        dilatation,
        deviatoric,
    }
}

/// Per directed bond of the case, `(ω_d own, ω_d partner, ω own, ω partner)`: particle `i`'s
/// weights of its bond to `j`, and `j`'s of its bond back to `i`.
pub fn bond_weights(case: &PdCase, c: &Coefficients) -> [Vec<f64>; 4] {
    let n = case.particles.len();
    let bonds = &case.bonds;
    let mut x = Vec::new();
    case.ghosts
        .extend_positions(&case.particles.position, &mut x);
    let weights = |k: usize, u: &Vec3| {
        (
            1.0 + c.dilatation[k].dot(&quadratic(u)),
            1.0 + c.deviatoric[k].dot(&quartic(u)),
        )
    };
    let mut out: [Vec<f64>; 4] = std::array::from_fn(|_| Vec::with_capacity(bonds.len()));
    for i in 0..n {
        for b in bonds.range(i) {
            let j = bonds.partner[b] as usize;
            let u = (x[j] - x[i]) / bonds.length(b);
            let (di, vi) = weights(i, &u);
            // Both weights are even in ξ̂: `j`'s of `−ξ` is its own at `u`.
            let (dj, vj) = if j < n {
                weights(j, &u)
            } else {
                let g = j - n;
                let mask = u32::from(case.ghosts.mask[g]);
                let src = case.ghosts.source[g] as usize;
                weights(src, &mirror_direction(u, mask, &case.ghosts.planes))
            };
            out[0].push(di);
            out[1].push(dj);
            out[2].push(vi);
            out[3].push(vj);
        }
    }
    out
}
