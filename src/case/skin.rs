//! The skin correction: stiffens the bonds of the surface row along its normal, so that a
//! traction entering through the surface does not first compress a soft skin.
//!
//! The surface correction (METHOD.md §3, [`surface_correction`](super::correction)) makes
//! each particle's strain energy the bulk's under a uniform strain. It does not make that
//! strain an *equilibrium* where a traction enters through the surface row alone, as a
//! contact's does: under a uniform strain along the surface normal `n`, the bonds of a
//! surface particle carry less than the continuum traction `σ_nn A_i` that its tributary
//! area `A_i` takes (the rows beneath carry the rest), and the row sinks by about 0.7-1.0
//! spacings times the strain below the bulk's line (docs/VALIDATION.md, "The surface row's
//! compliance"). Against Hertz that is an extra approach of about `2Δ/(πa)`: a contact too
//! wide and too low where it spans few spacings.
//!
//! For each surface particle `i` with a tributary area, the factor `k_i` makes its bonds
//! carry the share [`TRACTION_SHARE`] of that traction under the uniform strain `ε n ⊗ n`
//! (lateral strain held, the state under a contact's centre): the normal force density of
//! Eq. 6 is `c ε Σ_j f_ij (e_ij·n)³ V_j`, and each bond's factor becomes
//! `f_ij (1 + (k_i − 1)(e_ij·n_i)²)`, which leaves bonds along the surface as they were.
//! A share of 1 over-stiffens every contact by 2-3.5 %: the rows beneath carry part of the
//! traction in the affine state and their bonds are not scaled. The share 0.8 is a
//! calibrated constant, not derived; docs/VALIDATION.md gives the meshes it was chosen on and
//! those it was checked on. On by default (`skin_correction = false` on a body turns it off).

use crate::case::correction::micromodulus;
use crate::case::neighbours::BondList;
use crate::case::part::CasePart;
use crate::case::{mirror_direction, Ghosts};
use crate::math::Vec3;

/// Share of the continuum traction the surface row carries under a uniform normal strain.
pub const TRACTION_SHARE: f64 = 0.8;

/// Bounds of a particle's factor: a particle whose neighbourhood is too irregular for the
/// balance keeps at most this much of its own.
const FACTOR_BOUNDS: (f64, f64) = (0.5, 10.0);

/// What the skin correction did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SkinCorrection {
    /// Surface particles whose normal bonds were scaled.
    pub particles: usize,
    /// Their factors `k_i`: 10th percentile, median, 90th percentile.
    pub factor_percentiles: [f64; 3],
}

/// The particles' geometry the correction reads.
pub struct SkinInput<'a> {
    /// Real positions followed by their mirror images.
    pub position: &'a [Vec3],
    /// Partner volumes ([`Ghosts::partner_volumes`]).
    pub partner_volume: &'a [f64],
    /// Real particles' volumes.
    pub volume: &'a [f64],
    pub is_surface: &'a [bool],
    /// Outward unit normals of the surface particles.
    pub normal: &'a [Vec3],
    /// Area over which a surface particle's contact force acts (0 where none).
    pub pressure_area: &'a [f64],
    pub ghosts: &'a Ghosts,
    /// Horizon δ, the reference of the micromodulus.
    pub horizon: f64,
}

/// Scales `bond_factor` in place (see the module's doc). On a rank's `part` of a decomposed
/// case each particle's factor comes from its owner, whose row of bonds is complete.
pub fn skin_correction(
    input: &SkinInput,
    bonds: &BondList,
    bond_factor: &mut [f64],
    part: Option<&CasePart>,
) -> SkinCorrection {
    let n = input.volume.len();
    // σ_nn / (c ε) for the uniaxial strain of a bond-based solid (ν = 1/4): (λ + 2μ) / c
    // = 1.2 E π δ⁴ / (12 E).
    let modulus_over_c = 1.2 / micromodulus(1.0, input.horizon);
    let mut factor: Vec<f64> = (0..n)
        .map(|i| {
            if !input.is_surface[i] || input.pressure_area[i] <= 0.0 {
                return 1.0;
            }
            let normal = input.normal[i];
            let (mut s3, mut s5) = (0.0, 0.0);
            for b in bonds.range(i) {
                let j = bonds.partner[b] as usize;
                let c = (input.position[j] - input.position[i])
                    .normalize()
                    .dot(&normal);
                let w = bond_factor[b] * c * c * c * input.partner_volume[j];
                s3 += w;
                s5 += w * c * c;
            }
            // Both sums are negative where the bonds point inwards; elsewhere the particle
            // has no inward neighbourhood to balance.
            if s3 >= 0.0 || s5 >= 0.0 {
                return 1.0;
            }
            let need = TRACTION_SHARE * modulus_over_c * input.pressure_area[i] / input.volume[i];
            // −Σ f (1 + (k − 1) c²) c³ V = need.
            (1.0 + (need + s3) / -s5).clamp(FACTOR_BOUNDS.0, FACTOR_BOUNDS.1)
        })
        .collect();
    if let Some(p) = part {
        p.gather_scalar(&mut factor);
    }
    let ghosts = input.ghosts;
    for i in 0..bonds.particles() {
        for b in bonds.range(i) {
            let partner = bonds.partner[b] as usize;
            let j = ghosts.source_of(partner, n);
            if factor[i] == 1.0 && factor[j] == 1.0 {
                continue;
            }
            let e = (input.position[partner] - input.position[i]).normalize();
            let mut f = 1.0;
            if factor[i] != 1.0 {
                let c = e.dot(&input.normal[i]);
                f *= 1.0 + (factor[i] - 1.0) * c * c;
            }
            if factor[j] != 1.0 {
                // An image's normal is its source's, mirrored.
                let normal_j = if partner < n {
                    input.normal[j]
                } else {
                    let mask = ghosts.mask[partner - n] as u32;
                    mirror_direction(input.normal[j], mask, &ghosts.planes)
                };
                let c = e.dot(&normal_j);
                f *= 1.0 + (factor[j] - 1.0) * c * c;
            }
            bond_factor[b] *= f;
        }
    }
    let mut scaled: Vec<f64> = factor.into_iter().filter(|&k| k != 1.0).collect();
    scaled.sort_by(f64::total_cmp);
    let at = |q: f64| {
        scaled
            .get(((scaled.len() as f64 - 1.0) * q).round() as usize)
            .copied()
            .unwrap_or(1.0)
    };
    SkinCorrection {
        particles: scaled.len(),
        factor_percentiles: [at(0.1), at(0.5), at(0.9)],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::case::{generators, CaseOptions, PdCase, SymmetryPlane};

    fn block(min: [f64; 3], max: [f64; 3], skin: bool, symmetry: Vec<SymmetryPlane>) -> PdCase {
        PdCase::build(
            generators::cuboid(min, max, 0.1),
            CaseOptions {
                skin_correction: skin,
                symmetry,
                ..CaseOptions::default()
            },
        )
        .expect("valid block")
    }

    fn find(case: &PdCase, p: Vec3) -> usize {
        (0..case.particles.len())
            .find(|&i| (case.particles.position[i] - p).norm() < 1e-9)
            .expect("lattice point")
    }

    /// At the middle of a flat face, under the uniform strain along the normal, the surface
    /// particle's bonds carry TRACTION_SHARE of the continuum traction on its area; bonds
    /// along the face keep the factor the surface correction gave them.
    #[test]
    fn a_flat_face_carries_its_share_of_the_traction() {
        let plain = block([0.0; 3], [1.4; 3], false, Vec::new());
        let skin = block([0.0; 3], [1.4; 3], true, Vec::new());
        let stats = skin.skin.as_ref().expect("asked for");
        assert!(stats.particles > 0);
        let i = find(&skin, Vec3::new(0.7, 0.7, 0.0));
        assert!(skin.surface.is_surface[i]);
        let n = skin.surface.normal[i];
        assert!((n - Vec3::new(0.0, 0.0, -1.0)).norm() < 1e-6, "{n:?}");
        let volume = skin.ghosts.partner_volumes(&skin.particles.volume);
        let carried = |case: &PdCase| -> f64 {
            case.bonds
                .range(i)
                .map(|b| {
                    let j = case.bonds.partner[b] as usize;
                    let c = (case.particles.position[j] - case.particles.position[i])
                        .normalize()
                        .dot(&n);
                    -case.correction.bond_factor[b] * c * c * c * volume[j]
                })
                .sum()
        };
        let need = TRACTION_SHARE * 1.2 / micromodulus(1.0, skin.horizon)
            * skin.segments.pressure_area[i]
            / skin.particles.volume[i];
        assert!(
            (carried(&skin) / need - 1.0).abs() < 1e-9,
            "carried {} against {need}",
            carried(&skin)
        );
        // The surface correction alone leaves the row carrying less: the softness corrected.
        assert!(carried(&plain) < 0.9 * need, "{}", carried(&plain));
        let k = stats.factor_percentiles[1];
        assert!(k > 1.0 && k < FACTOR_BOUNDS.1, "median factor {k}");
        for b in skin.bonds.range(i) {
            let j = skin.bonds.partner[b] as usize;
            let along = skin.particles.position[j].z.abs() < 1e-9;
            let (fs, fp) = (
                skin.correction.bond_factor[b],
                plain.correction.bond_factor[b],
            );
            if along {
                // (The normals of the eigenvalue test tilt by about 1e-3 rad.)
                assert!(
                    (fs / fp - 1.0).abs() < 1e-5,
                    "bond along the face: {fs} vs {fp}"
                );
            }
        }
        // Away from the surface nothing changes.
        let deep = find(&skin, Vec3::new(0.7, 0.7, 0.7));
        for b in skin.bonds.range(deep) {
            assert_eq!(
                skin.correction.bond_factor[b],
                plain.correction.bond_factor[b]
            );
        }
    }

    /// A quarter of a box with two symmetry planes gives each particle the bonds' factors of
    /// the whole box, through its partners' mirror images and their mirrored normals.
    #[test]
    fn a_quarter_box_matches_the_whole_box() {
        let whole = block([-0.8, -0.8, 0.0], [0.8, 0.8, 0.6], true, Vec::new());
        let quarter = block(
            [0.0; 3],
            [0.8, 0.8, 0.6],
            true,
            vec![
                SymmetryPlane { axis: 0, at: 0.0 },
                SymmetryPlane { axis: 1, at: 0.0 },
            ],
        );
        let mut positions = Vec::new();
        quarter
            .ghosts
            .extend_positions(&quarter.particles.position, &mut positions);
        for (q, p) in quarter.particles.position.iter().enumerate() {
            let w = find(&whole, *p);
            // Each bond of the quarter's particle is one of the whole's, partner by position.
            let whole_factor = |partner: Vec3| {
                whole
                    .bonds
                    .range(w)
                    .find(|&b| {
                        (whole.particles.position[whole.bonds.partner[b] as usize] - partner).norm()
                            < 1e-9
                    })
                    .map(|b| whole.correction.bond_factor[b])
                    .expect("the same bond")
            };
            for b in quarter.bonds.range(q) {
                let partner = positions[quarter.bonds.partner[b] as usize];
                let (fq, fw) = (quarter.correction.bond_factor[b], whole_factor(partner));
                assert!(
                    (fq / fw - 1.0).abs() < 2e-3,
                    "bond {:?} -> {:?}: quarter {fq}, whole {fw}",
                    p.as_slice(),
                    partner.as_slice()
                );
            }
        }
    }
}
