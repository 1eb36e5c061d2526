//! The stress at each particle, recovered from its neighbourhood's displacements: what an FE
//! user reads in ParaView (the frames' `stress`, `von_mises`) and what the subsurface shear
//! of a Hertz contact is checked by (METHOD.md §7-8).
//!
//! The displacement gradient at particle `i` is the weighted least-squares fit of a linear
//! field to its bonds, the shape tensor of correspondence PD (Silling et al. 2007, §15):
//! `H_i = (Σ_j w_j η ⊗ ξ) K_i⁻¹` with `K_i = Σ_j w_j ξ ⊗ ξ`, `η = u_j − u_i`, over the bonds
//! of the case still intact (mirror images included, so a particle on a symmetry plane sees
//! the whole neighbourhood; a broken bond left out, so a crack's opening reads as no strain
//! on either face). It is exact for any linear displacement field whatever the
//! neighbourhood's shape, at a surface too, where a force-based stress (Σ f ⊗ ξ) lacks the
//! missing half. The stress is then the continuum's for the body's E and ν (the constants
//! its bulk reproduces, bond-based at ν = 1/4 as the LPS at any ν): small kinematics
//! `σ = λ tr ε I + 2μ ε`, `ε = sym H`; finite kinematics the Cauchy stress of a
//! St Venant-Kirchhoff solid, `σ = F S Fᵀ / det F`, `S = λ tr E I + 2μ E`, `E = ½(FᵀF − I)`,
//! `F = I + H`.
//!
//! The weights `w_j = V_j (1 − |ξ|/r)²` fall to zero at the bonds' reach `r = δ + Δ/2`: a fit
//! over the whole horizon (`w_j = V_j`) averages a field over ±δ and lowers a peak that is
//! narrower than that (the subsurface shear under a Hertz contact a few horizons wide).
//!
//! Where a surface particle carries a contact pressure `p` (given), the traction is imposed
//! as an FE code's recovery imposes its boundary conditions: the strain's components in the
//! surface's tangent plane are the fit's, the rest follow from `σ n = −p n` (frictionless):
//! `ε_nt = 0`, `ε_nn = (−p − λ tr ε_t)/(λ + 2μ)`. The fit alone reads the surface row's strain
//! across the surface wrong: the contact force acts on that row as a body force, spread over
//! its bonds, and its neighbourhood lies on one side. Measured under a Hertz contact (gmsh
//! tet sphere, a/Δ = 11, ν = 0.3): the fit gave σ_zz = −1.55 p0 at the centre and σ_rr within
//! 0.22 p0 of Hertz's on average over r < 0.9a; with the traction imposed, −0.96 p0 and
//! 0.03 p0. At finite kinematics it is imposed on the second Piola-Kirchhoff stress along the
//! reference normal (the same to first order).

use nalgebra::Matrix3;
use rayon::prelude::*;

use super::PdBody;
use crate::math::Vec3;
use crate::scene::Kinematics;

/// A 3×3 tensor of f64.
pub type Tensor = Matrix3<f64>;

/// The smallest `det K / (tr K / 3)³` of a neighbourhood that fixes a gradient: below it the
/// bonds lie nearly in a plane or on a line (a particle with one or two partners) and the
/// particle's stress is reported as zero.
const FLAT_NEIGHBOURHOOD: f64 = 1e-6;

impl PdBody {
    /// The Cauchy stress (Pa) at the particles `at`, from the displacements `u` of the
    /// body's particles (the particles' own and, in a decomposed run, their ghosts'), with
    /// the contact pressure `pressure` (per particle, Pa) imposed on the surface particles
    /// that carry one. See the module docs.
    pub fn stress(&self, u: &[Vec3], at: &[usize], pressure: Option<&[f64]>) -> Vec<Tensor> {
        let case = &self.case;
        let n = self.len();
        let bonds = &case.bonds;
        // At rest (a run's first frame), untouched: every gradient is zero.
        let pressed = |i: usize| pressure.is_some_and(|p| p[i] > 0.0);
        if u.iter().all(|d| *d == Vec3::zeros()) && !(0..n).any(pressed) {
            return vec![Tensor::zeros(); at.len()];
        }
        let volume = case.ghosts.partner_volumes(&case.particles.volume);
        // The bonds' reach at each particle, `δ + Δ/2` (Eq. 10; it follows the mesh where
        // the spacing does).
        let spacing = case.particles.spacing;
        let reach_of = |i: usize| {
            let s = case.local_spacing.as_ref().map_or(spacing, |s| s[i]);
            (case.horizon / spacing + 0.5) * s
        };
        // The displacement of a bond's partner: a mirror image's is its source's, reflected.
        let displacement = |j: usize| {
            if j < n {
                u[j]
            } else {
                let g = j - n;
                let s = case.ghosts.source[g] as usize;
                let mask = case.ghosts.mask[g];
                // A reflection is linear: reflect the displaced point, take off the image.
                case.ghosts.reflect(self.reference[s] + u[s], mask) - self.reference[j]
            }
        };
        // A broken bond joins nothing: the displacement jump across a crack is no strain.
        let intact = self.fracture.as_ref().map(|f| &f.intact);
        let (lambda, mu) = self.material.lame();
        at.par_iter()
            .map(|&i| {
                let xi0 = self.reference[i];
                let reach = reach_of(i);
                let mut shape = Tensor::zeros();
                let mut stretch = Tensor::zeros();
                let ui = u[i];
                for b in bonds.range(i) {
                    if intact.is_some_and(|k| !k[b]) {
                        continue;
                    }
                    let j = bonds.partner[b] as usize;
                    let xi = self.reference[j] - xi0;
                    let r = 1.0 - bonds.length(b) / reach;
                    let wxi = (volume[j] * r.max(0.0).powi(2)) * xi;
                    shape.ger(1.0, &xi, &wxi, 1.0);
                    stretch.ger(1.0, &(displacement(j) - ui), &wxi, 1.0);
                }
                let scale = shape.trace() / 3.0;
                if !(scale > 0.0) || shape.determinant() < FLAT_NEIGHBOURHOOD * scale.powi(3) {
                    return Tensor::zeros();
                }
                let Some(inverse) = shape.try_inverse() else {
                    return Tensor::zeros();
                };
                let grad = stretch * inverse;
                let hooke = |e: Tensor| Tensor::identity() * (lambda * e.trace()) + 2.0 * mu * e;
                // A loaded surface particle: the traction across its surface imposed.
                let loaded = pressure
                    .map(|p| p[i])
                    .filter(|&p| p > 0.0 && case.surface.is_surface[i])
                    .and_then(|p| Some((p, case.surface.normal[i].try_normalize(0.0)?)));
                let traction = |e: Tensor| match loaded {
                    Some((p, n)) => {
                        let across = Tensor::identity() - n * n.transpose();
                        let along = across * e * across;
                        let normal = (-p - lambda * along.trace()) / (lambda + 2.0 * mu);
                        along + normal * n * n.transpose()
                    }
                    None => e,
                };
                match self.kinematics {
                    Kinematics::Small => hooke(traction(0.5 * (grad + grad.transpose()))),
                    Kinematics::Finite => {
                        let f = Tensor::identity() + grad;
                        let green = traction(0.5 * (f.transpose() * f - Tensor::identity()));
                        let det = f.determinant();
                        if det > 0.0 {
                            f * hooke(green) * f.transpose() / det
                        } else {
                            // An inverted neighbourhood has no stress to speak of.
                            Tensor::zeros()
                        }
                    }
                }
            })
            .collect()
    }
}

/// The von Mises equivalent stress `√(3/2 s:s)` of `sigma`, `s` its deviator.
pub fn von_mises(sigma: &Tensor) -> f64 {
    let s = sigma - Tensor::identity() * (sigma.trace() / 3.0);
    (1.5 * s.component_mul(&s).sum()).sqrt()
}

/// The largest shear stress `(σ₁ − σ₃)/2` of `sigma` (Tresca's half difference of the
/// extreme principal stresses).
pub fn max_shear(sigma: &Tensor) -> f64 {
    let e = sigma.symmetric_eigenvalues();
    0.5 * (e.max() - e.min())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn von_mises_of_uniaxial_and_pure_shear() {
        let uni = Tensor::from_diagonal(&Vec3::new(0.0, 0.0, 5.0));
        assert!((von_mises(&uni) - 5.0).abs() < 1e-12);
        assert!((max_shear(&uni) - 2.5).abs() < 1e-12);
        let mut shear = Tensor::zeros();
        shear[(0, 1)] = 2.0;
        shear[(1, 0)] = 2.0;
        assert!((von_mises(&shear) - 2.0 * 3f64.sqrt()).abs() < 1e-12);
        assert!((max_shear(&shear) - 2.0).abs() < 1e-12);
    }
}
