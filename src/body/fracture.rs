//! Bond failure (METHOD.md §9): a bond whose stretch passes the critical stretch `s0` fails for
//! good (Silling & Askari 2005), and pre-cracks remove the bonds that cross them before a run.
//!
//! `s0 = sqrt(5 G0 / (9 κ δ))` comes from the fracture energy: the work of breaking every bond
//! that crosses a unit area of a crack plane is `G0` (3D bond-based PD, κ the bulk modulus).
//! Where the horizon follows a graded mesh, a bond of horizon `δ_ij` gets its own
//! `s0 √(δ/δ_ij)`, which keeps the energy per crack area `G0` there too.
//!
//! What a broken bond leaves as built: the surface correction's factors and the skin
//! correction of the particles around it (a particle near a new crack face keeps the
//! stiffness of a bulk particle on its intact bonds), ADR's fictitious density (an upper bound
//! of the stiffness, so still stable), and the contact's master segments (a crack's faces
//! carry none). The eigenvalue surface is found again over the intact bonds where bonds broke
//! ([`crate::body::new_surface`]), for the frames and the summary.
//!
//! Threads and ranks: whether a bond fails depends only on the positions of its two
//! particles, so the set of bonds that fail in a step is the same whatever the thread or rank
//! count; each real pair is tested once, by the rank that owns its lower particle, and the
//! ranks share what failed, so every rank holds every bond's state.

use rayon::prelude::*;

use crate::body::lps::Lps;
use crate::body::new_surface::NewSurface;
use crate::case::correction::volume_correction;
pub use crate::case::crack_faces::CrackPatch;
use crate::case::neighbours::BondList;
use crate::case::pairs::PairList;
use crate::case::PdCase;
use crate::math::Vec3;
pub use crate::scene::FailureCriterion;
use crate::scene::Kinematics;

/// Particles per work item of the failure test.
const CHUNK: usize = 1024;

/// `s0 = sqrt(5 G0 / (9 κ δ))`, κ = E / (3 (1 − 2ν)) (METHOD.md §9).
pub fn critical_stretch(fracture_energy: f64, youngs: f64, poisson: f64, horizon: f64) -> f64 {
    let bulk = youngs / (3.0 * (1.0 - 2.0 * poisson));
    (5.0 * fracture_energy / (9.0 * bulk * horizon)).sqrt()
}

/// `s0 = sqrt(G0 / ((3μ + (3/4)⁴ (k − 5μ/3)) δ))` of the linear peridynamic solid, k and μ
/// from E and ν (Madenci & Oterkus, *Peridynamic Theory and Its Applications*, Springer 2014,
/// the ordinary state-based model in 3D; PeriLab's critical stretch for its state-based
/// materials): the work of breaking the bonds across a unit crack area with each bond's
/// share of the state's energy. At ν = 1/4 (`k = 5μ/3`) it is [`critical_stretch`]'s.
pub fn critical_stretch_lps(fracture_energy: f64, youngs: f64, poisson: f64, horizon: f64) -> f64 {
    let bulk = youngs / (3.0 * (1.0 - 2.0 * poisson));
    let shear = youngs / (2.0 * (1.0 + poisson));
    let stiffness = 3.0 * shear + 0.75f64.powi(4) * (bulk - 5.0 * shear / 3.0);
    (fracture_energy / (stiffness * horizon)).sqrt()
}

/// The state of a body's bonds once they may fail.
#[derive(Clone, Debug)]
pub struct Fracture {
    /// `s0` at the body's horizon δ; `None`: bonds do not fail (a body with pre-cracks only).
    pub critical_stretch: Option<f64>,
    /// What fails a bond past `s0` ([`FailureCriterion`]; the body applies it,
    /// [`crate::body::PdBody::spare_compressed`]).
    pub criterion: FailureCriterion,
    /// Per directed bond: the bound the pass tests, from the critical stretch `s0` at the
    /// bond's own horizon: `((1 + s0) L)²` against `|y|²` (finite kinematics, no square root
    /// per bond) or `s0 L²` against `η·ξ` (linearised); infinite where the bond is broken or
    /// is tested from its other end, so that the pass tests each real pair once without a
    /// branch.
    limit: Vec<f32>,
    /// Which of the two the bounds are for.
    kinematics: Kinematics,
    /// Per directed bond: still bonded.
    pub intact: Vec<bool>,
    /// Per directed bond: `v_c V_j`, its share of the particle's family volume.
    volume: Vec<f32>,
    /// Per particle: the family volume lost (`Σ_broken v_c V_j`) and the whole.
    lost: Vec<f64>,
    family: Vec<f64>,
    /// Bonds broken so far (each real pair once, a bond to a mirror image once).
    pub broken: usize,
    /// Per particle: the strain energy its bonds held when they broke (J), the work of
    /// fracture of the energy balance ([`crate::body::PdBody::break_failed`]); a pre-crack's
    /// bonds, cut before any load, hold none.
    pub work: Vec<f64>,
    /// The surface the broken bonds opened ([`crate::body::new_surface`]).
    pub surface: NewSurface,
}

impl Fracture {
    /// Every bond of `case` intact, failing at `critical_stretch` (at the horizon δ) under
    /// `kinematics`.
    pub fn new(case: &PdCase, critical_stretch: Option<f64>, kinematics: Kinematics) -> Fracture {
        let bonds = &case.bonds;
        let n = case.particles.len();
        let spacing = case.particles.spacing;
        let local = case.local_spacing.as_ref().map(|s| case.ghosts.extend(s));
        let partner_volume = case.ghosts.partner_volumes(&case.particles.volume);
        let mut limit = Vec::with_capacity(bonds.len());
        let mut volume = Vec::with_capacity(bonds.len());
        let mut family = vec![0.0; n];
        for (i, fam) in family.iter_mut().enumerate() {
            for b in bonds.range(i) {
                let j = bonds.partner[b] as usize;
                // The bond's own spacing and horizon where the horizon is local.
                let s = local.as_ref().map_or(spacing, |s| 0.5 * (s[i] + s[j]));
                let horizon = case.horizon * s / spacing;
                let s0 = critical_stretch.map_or(f64::INFINITY, |s0| s0 * (spacing / s).sqrt());
                let l = bonds.length(b);
                let bound = if j < n && j < i {
                    f64::INFINITY
                } else {
                    match kinematics {
                        Kinematics::Finite => ((1.0 + s0) * l).powi(2),
                        Kinematics::Small => s0 * l * l,
                    }
                };
                limit.push(bound as f32);
                let v = volume_correction(bonds.length(b), horizon, s) * partner_volume[j];
                volume.push(v as f32);
                *fam += v;
            }
        }
        Fracture {
            critical_stretch,
            criterion: FailureCriterion::Stretch,
            limit,
            kinematics,
            intact: vec![true; bonds.len()],
            volume,
            lost: vec![0.0; n],
            family,
            broken: 0,
            work: vec![0.0; n],
            surface: NewSurface::new(n),
        }
    }

    /// Damage `φ_i = 1 − Σ_intact v_c V_j / Σ_all v_c V_j` of particle `i` (METHOD.md §9).
    pub fn damage(&self, i: usize) -> f64 {
        if self.family[i] > 0.0 {
            (self.lost[i] / self.family[i]).min(1.0)
        } else {
            0.0
        }
    }

    /// The bonds among the rows `rows` that fail at positions `pos` (real particles, then
    /// images): `(i, b)`, each real pair once (from its lower particle), in row order. With
    /// linearised kinematics `reference` holds the reference positions.
    pub fn failing(
        &self,
        bonds: &BondList,
        pos: &[Vec3],
        reference: &[Vec3],
        rows: std::ops::Range<usize>,
    ) -> Vec<(u32, u32)> {
        if self.critical_stretch.is_none() {
            return Vec::new();
        }
        let small = self.kinematics == Kinematics::Small;
        let test = |rows: std::ops::Range<usize>| {
            let mut out = Vec::new();
            for i in rows {
                let range = bonds.range(i);
                let (partner, limit) = (&bonds.partner[range.clone()], &self.limit[range.clone()]);
                let yi = pos[i];
                for (k, (&j, &bound)) in partner.iter().zip(limit).enumerate() {
                    // Broken, or tested from the other end: no position to read.
                    if bound == f32::INFINITY {
                        continue;
                    }
                    let j = j as usize;
                    let d = pos[j] - yi;
                    let measure = if small {
                        let xi = reference[j] - reference[i];
                        (d - xi).dot(&xi)
                    } else {
                        d.norm_squared()
                    };
                    if measure > f64::from(bound) {
                        out.push((i as u32, (range.start + k) as u32));
                    }
                }
            }
            out
        };
        let (start, end) = (rows.start, rows.end);
        (start..end)
            .step_by(CHUNK)
            .collect::<Vec<_>>()
            .into_par_iter()
            .flat_map_iter(|a| test(a..(a + CHUNK).min(end)))
            .collect()
    }

    /// Breaks the bonds `(i, b)` (each real pair given once, from either end): both directions
    /// of a real pair, the bond alone to a mirror image. Their weights go to zero in
    /// `bond_weight`, in `pairs` (where the pair is in it: a rank's list holds its own) and,
    /// for an LPS body, in its bonds' `ω v_c V_j` (`lps`, [`Lps::cut`]: the bond leaves the
    /// dilatation and the force state; the weighted volume `m_i` stays as built, as
    /// Peridigm's LPS keeps it, so that a particle left with few bonds is not made stiffer).
    pub fn break_bonds(
        &mut self,
        bonds: &BondList,
        broken: &[(u32, u32)],
        bond_weight: &mut [f32],
        pairs: &mut PairList,
        mut lps: Option<&mut Lps>,
    ) {
        for &(i, b) in broken {
            let (i, b) = (i as usize, b as usize);
            if !self.intact[b] {
                continue;
            }
            let j = bonds.partner[b] as usize;
            let mut cut = |k: usize, c: usize| {
                self.intact[c] = false;
                self.limit[c] = f32::INFINITY;
                bond_weight[c] = 0.0;
                if let Some(l) = lps.as_deref_mut() {
                    l.cut(c);
                }
                self.lost[k] += f64::from(self.volume[c]);
            };
            cut(i, b);
            if let Some(c) = bonds.reverse(i, b) {
                cut(j, c);
            }
            pairs.remove(i, j);
            self.surface.broke(i, j);
            self.broken += 1;
        }
    }

    /// The bonds `(i, b)` that cross `patch` (reference positions `x`, images included), each
    /// real pair once ([`CrackPatch::crossing`]).
    pub fn crossing(bonds: &BondList, x: &[Vec3], patch: &CrackPatch) -> Vec<(u32, u32)> {
        patch.crossing(bonds, x)
    }

    /// Per directed bond of `case`: whether one of `patches` cuts it (both directions of a
    /// pair of real particles, as [`Fracture::break_bonds`] breaks them).
    pub fn crossing_bonds(case: &PdCase, patches: &[(usize, CrackPatch)]) -> Vec<bool> {
        let bonds = &case.bonds;
        let mut x = Vec::new();
        case.ghosts
            .extend_positions(&case.particles.position, &mut x);
        let mut cut = vec![false; bonds.len()];
        for (_, patch) in patches {
            for (i, b) in Fracture::crossing(bonds, &x, patch) {
                let (i, b) = (i as usize, b as usize);
                cut[b] = true;
                if let Some(c) = bonds.reverse(i, b) {
                    cut[c] = true;
                }
            }
        }
        cut
    }

    /// The fragments: groups of particles joined by intact bonds (mirror images aside), as
    /// the size of each, largest first.
    pub fn fragments(&self, bonds: &BondList) -> Vec<usize> {
        self.fragment_labels(bonds).1
    }

    /// Each particle's fragment, numbered from 0 by size, largest first (equal sizes in the
    /// order of their first particle), and the sizes in that order.
    pub fn fragment_labels(&self, bonds: &BondList) -> (Vec<u32>, Vec<usize>) {
        bonds.components(|b| self.intact[b])
    }
}

/// Under `failure = "tension"`, the normal stress along a failing bond must be tensile and at
/// least this share of the largest principal stress (in magnitude) of the stress at the bond:
/// a bond along the tension that dominates (a bar pulled along it, the radial bonds outside a
/// Hertz contact, the bonds across a mode I crack's path) has 1 or more, a bond stretched only
/// by Poisson's effect of a compression across it (below a contact, a bar pressed across it)
/// about 0.
pub const TENSION_SHARE: f64 = 0.5;

impl super::PdBody {
    /// The bonds of `failing` ([`Fracture::failing`], at the positions `pos`) that fail by the
    /// body's [`FailureCriterion`]: all of them by the stretch; by tension, those whose normal
    /// stress along the bond, `λ θ + 2 μ s`, is tensile and at least [`TENSION_SHARE`] of σ̄'s
    /// largest principal stress in magnitude. `s` is the bond's own stretch, `θ = tr σ̄ / 3κ`
    /// the dilatation of `σ̄`, the mean of its two particles' recovered stresses
    /// ([`super::PdBody::stress`], over their intact bonds; a mirror image's its source's,
    /// reflected). The stretch is the bond's, local: at a contact's edge it resolves the
    /// ring's tension, which the fit smooths into the compression inside, and at a crack tip
    /// it concentrates as the fitted strain does not, so cracks grow by the stretch wherever
    /// the material around them is not compressed. One process: the stresses are fitted over
    /// this process's particles.
    pub fn spare_compressed(&self, failing: Vec<(u32, u32)>, pos: &[Vec3]) -> Vec<(u32, u32)> {
        let Some(fr) = &self.fracture else {
            return failing;
        };
        if fr.criterion == FailureCriterion::Stretch || failing.is_empty() {
            return failing;
        }
        let n = self.len();
        let ghosts = &self.case.ghosts;
        let bonds = &self.case.bonds;
        let real = |j: usize| {
            if j < n {
                j
            } else {
                ghosts.source[j - n] as usize
            }
        };
        let mut at: Vec<usize> = failing
            .iter()
            .flat_map(|&(i, b)| [i as usize, real(bonds.partner[b as usize] as usize)])
            .collect();
        at.sort_unstable();
        at.dedup();
        let sigma = self.stress(&self.u, &at, None);
        let stress_of = |j: usize| {
            let k = at.binary_search(&real(j)).expect("gathered above");
            let mut s = sigma[k];
            if j >= n {
                // A reflection flips the sign of the components that pair a mirrored axis
                // with one that is not.
                let mask = ghosts.mask[j - n];
                for (p, plane) in ghosts.planes.iter().enumerate() {
                    if mask & (1 << p) != 0 {
                        let a = plane.axis;
                        for c in 0..3 {
                            if c != a {
                                s[(a, c)] = -s[(a, c)];
                                s[(c, a)] = -s[(c, a)];
                            }
                        }
                    }
                }
            }
            s
        };
        failing
            .into_iter()
            .filter(|&(i, b)| {
                let (i, b) = (i as usize, b as usize);
                let j = bonds.partner[b] as usize;
                let mean = 0.5 * (stress_of(i) + stress_of(j));
                let scale = mean
                    .symmetric_eigenvalues()
                    .iter()
                    .fold(0.0f64, |m, l| m.max(l.abs()));
                // `λ θ + 2 μ s = (ν tr σ̄ + E s) / (1 + ν)`, the bond's stretch s as
                // `Fracture::failing` measures it.
                let xi = self.reference[j] - self.reference[i];
                let d = pos[j] - pos[i];
                let stretch = match self.kinematics {
                    Kinematics::Small => (d - xi).dot(&xi) / xi.norm_squared(),
                    Kinematics::Finite => d.norm() / xi.norm() - 1.0,
                };
                let (youngs, nu) = (self.material.youngs, self.material.poisson);
                let normal = (nu * mean.trace() + youngs * stretch) / (1.0 + nu);
                // No stress to read (a particle left with too few bonds to fit one): the
                // stretch decides.
                scale == 0.0 || (normal > 0.0 && normal >= TENSION_SHARE * scale)
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lps_critical_stretch_is_the_bond_based_one_at_nu_one_quarter() {
        let (g0, e, d) = (300.0, 3e9, 3e-3);
        let bb = critical_stretch(g0, e, 0.25, d);
        assert!((critical_stretch_lps(g0, e, 0.25, d) / bb - 1.0).abs() < 1e-12);
        // At ν = 0.3: 3μ + (3/4)⁴(k − 5μ/3) = 1.2146 E.
        let s = critical_stretch_lps(g0, e, 0.3, d);
        let stiffness = 3.0 / 2.6 + 0.75f64.powi(4) * (1.0 / 1.2 - 5.0 / 7.8);
        assert!((s - (g0 / (stiffness * e * d)).sqrt()).abs() < 1e-15);
        assert!((stiffness - 1.2146).abs() < 1e-4);
    }

    #[test]
    fn the_critical_stretch_of_nu_one_quarter() {
        // ν = 1/4: s0 = sqrt(5 G0 / (6 E δ)).
        let (g0, e, d) = (100.0, 70e9, 1e-3);
        let s0 = critical_stretch(g0, e, 0.25, d);
        assert!((s0 - (5.0 * g0 / (6.0 * e * d)).sqrt()).abs() < 1e-15);
    }

    #[test]
    fn a_patch_cuts_the_segments_that_cross_it() {
        let p = CrackPatch::new(
            Vec3::zeros(),
            Vec3::x(),
            Vec3::new(0.3, 1.0, 0.0),
            [2.0, 1.0],
        );
        assert!(p.cuts(Vec3::new(-0.1, 0.5, 0.2), Vec3::new(0.1, 0.5, 0.2)));
        // Past the patch's side, on one side, or along the plane: no.
        assert!(!p.cuts(Vec3::new(-0.1, 1.5, 0.0), Vec3::new(0.1, 1.5, 0.0)));
        assert!(!p.cuts(Vec3::new(0.1, 0.0, 0.0), Vec3::new(0.2, 0.0, 0.0)));
        assert!(!p.cuts(Vec3::new(-0.1, 0.0, 0.6), Vec3::new(0.1, 0.0, 0.6)));
        // A point on the plane belongs to its positive side.
        assert!(p.cuts(Vec3::new(-0.1, 0.0, 0.0), Vec3::new(0.0, 0.0, 0.0)));
        assert!(!p.cuts(Vec3::new(0.1, 0.0, 0.0), Vec3::new(0.0, 0.0, 0.0)));
    }
}
