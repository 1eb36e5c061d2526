//! Contact between the pieces of a breaking body: the short-range repulsion of
//! [`crate::contact::shortrange`] between particles of one body that no intact bond joins
//! (`[[contact]] slave = master = the body, method = "short-range"`), the way Silling & Askari
//! (2005) keep fragments from passing through each other.
//!
//! A crack's faces and a fragment's new surface are made of particles that were inside the
//! body when it was built, so no surface found at the build covers them; a particle-to-particle
//! law needs none. Two particles `i`, `j` of the body repel when no intact bond joins them and
//! `|y_ij| < d_ij = min(0.9 |x_ij|, 1.35 Δ)` (LAMMPS's `peri/pmb` rule: particles that started
//! close repel only once pressed 10 % nearer than they started), with the force of
//! [`pair_force`] and the coefficient `15 c/δ` of the body. Bonded pairs never do: the
//! repulsion leaves the elastic response alone.
//!
//! Only particles that may be on a surface take part: those on the body's outer surface and
//! those that have lost a bond (an intact interior particle cannot meet another piece without
//! one of those meeting it first). Mirror images of symmetry planes do not: a particle on the
//! plane is held on it and cannot cross into its image.
//!
//! **Penetration.** Each particle stands for a cell of side Δ, so a piece's surface lies about
//! Δ/2 outside its outer particles, and two pieces at rest in touch have their particles
//! `min(|x_ij|, Δ)` apart. The pass records the depth `min(|x_ij|, Δ) − |y_ij|` of the deepest
//! unbonded pair it sees, in Δ: the depth to which one piece's surface particle has gone into
//! another's surface ([`FragmentPass::depth`], its largest over a run
//! [`FragmentPass::deepest`]).
//!
//! One process only (every candidate pair is read from the whole body's positions).

use rayon::prelude::*;

use super::shortrange::{coefficient, pair_force, DISTANCE};
use super::SKIN;
use crate::body::{Body, PdBody};
use crate::case::neighbours::CellGrid;
use crate::math::Vec3;

/// The share of a broken pair's reference distance at which its particles start to repel
/// (LAMMPS's `0.9 |x_ij|`).
const RELEASE: f64 = 0.9;

/// The repulsion between the pieces of one breaking body.
#[derive(Clone, Debug)]
pub struct FragmentPass {
    /// The body.
    pub body: usize,
    /// `15 c/δ` of the body (N/m⁷).
    pub coefficient: f64,
    /// The body's spacing Δ (m).
    pub spacing: f64,
    /// The cap of the contact distance, `1.35 Δ` (m).
    pub distance: f64,
    /// Per particle with a force or a stiffness in the last evaluation: the particle, its
    /// force, the stiffness of its pairs within reach (N/m) and its half of its pairs' energy.
    out: Vec<(u32, Vec3, f64, f64)>,
    /// Particles pushed by another piece in the last evaluation.
    pub touching: usize,
    /// The deepest unbonded pair of the last evaluation, in Δ (negative: none in touch).
    pub depth: f64,
    /// The largest `depth` so far.
    pub deepest: f64,
}

/// Whether particle `i` of `pd` may lie on a surface: an outer surface particle, or one that
/// has lost a bond.
fn exposed(pd: &PdBody, i: usize) -> bool {
    pd.case.surface.is_surface[i] || pd.damage(i) > 0.0
}

/// Whether an intact bond joins `i` to `j`.
fn bonded(pd: &PdBody, i: usize, j: usize) -> bool {
    let bonds = &pd.case.bonds;
    let range = bonds.range(i);
    match bonds.partner[range.clone()]
        .iter()
        .position(|&p| p as usize == j)
    {
        Some(k) => pd
            .fracture
            .as_ref()
            .is_none_or(|f| f.intact[range.start + k]),
        None => false,
    }
}

impl FragmentPass {
    /// The pass of body `body` (deformable).
    pub fn new(bodies: &[Body], body: usize) -> FragmentPass {
        let pd = bodies[body].as_pd().expect("checked deformable");
        FragmentPass {
            body,
            coefficient: coefficient(pd.material.youngs, pd.case.horizon),
            spacing: pd.spacing(),
            distance: DISTANCE * pd.spacing(),
            out: Vec::new(),
            touching: 0,
            depth: f64::NEG_INFINITY,
            deepest: f64::NEG_INFINITY,
        }
    }

    /// A pass that measures and pushes nothing: the depth to which the pieces of a body
    /// without the contact go into each other ([`FragmentPass::depth`]).
    pub fn probe(bodies: &[Body], body: usize) -> FragmentPass {
        FragmentPass {
            coefficient: 0.0,
            ..FragmentPass::new(bodies, body)
        }
    }

    /// The reach of the search: the contact distance and a skin, so that the stiffness of a
    /// pair about to close within a step counts.
    fn reach(&self) -> f64 {
        self.distance + SKIN * self.spacing
    }

    /// Finds the unbonded pairs in touch at the current positions and their forces; they are
    /// added to the body by [`FragmentPass::apply`].
    pub fn detect(&mut self, bodies: &[Body]) {
        let pd = bodies[self.body].as_pd().expect("deformable");
        let candidates: Vec<u32> = (0..pd.len() as u32)
            .filter(|&i| exposed(pd, i as usize))
            .collect();
        let pos: Vec<Vec3> = candidates
            .iter()
            .map(|&i| pd.position(i as usize))
            .collect();
        let reach = self.reach();
        let (dx, cap) = (self.spacing, self.distance);
        let grid = CellGrid::new(&pos, reach);
        let (x, vol) = (&pd.reference, &pd.case.particles.volume);
        let horizon = pd.case.horizon * (1.0 + 1e-6);
        let found: Vec<(u32, Vec3, f64, f64, f64)> = (0..candidates.len())
            .into_par_iter()
            .filter_map(|a| {
                let i = candidates[a] as usize;
                let (mut f, mut k, mut e, mut depth) = (Vec3::zeros(), 0.0, 0.0, f64::NEG_INFINITY);
                grid.for_each_candidate(&pos[a], reach, |b| {
                    let j = candidates[b as usize] as usize;
                    if j == i {
                        return;
                    }
                    let y = pos[a] - pos[b as usize];
                    let r2 = y.norm_squared();
                    if r2 >= reach * reach {
                        return;
                    }
                    let r0 = (x[j] - x[i]).norm();
                    // Only pairs within a horizon at rest can have a bond.
                    if r0 <= horizon && bonded(pd, i, j) {
                        return;
                    }
                    let r = r2.sqrt();
                    depth = depth.max((r0.min(dx) - r) / dx);
                    let kp = self.coefficient * vol[i] * vol[j];
                    k += kp;
                    let d = (RELEASE * r0).min(cap);
                    if r < d {
                        f += pair_force(self.coefficient, vol[i], vol[j], d, y);
                        // Each side books half of the pair's energy ½ k (d − r)².
                        e += 0.25 * kp * (d - r) * (d - r);
                    }
                });
                (depth > f64::NEG_INFINITY).then_some((i as u32, f, k, e, depth))
            })
            .collect();
        self.touching = found.iter().filter(|r| r.1 != Vec3::zeros()).count();
        self.depth = found.iter().map(|r| r.4).fold(f64::NEG_INFINITY, f64::max);
        self.deepest = self.deepest.max(self.depth);
        self.out = found.into_iter().map(|r| (r.0, r.1, r.2, r.3)).collect();
    }

    /// Adds the forces and stiffnesses of the last [`FragmentPass::detect`].
    pub fn apply(&self, bodies: &mut [Body]) {
        let pd = bodies[self.body].as_pd_mut().expect("deformable");
        for &(i, f, k, _) in &self.out {
            let i = i as usize;
            pd.force[i] += f;
            pd.contact_force[i] += f;
            pd.contact_stiffness[i] += k;
        }
    }

    /// The energy of the last evaluation's pairs, per particle (each pair's half on each of
    /// its particles).
    pub fn energies(&self) -> impl Iterator<Item = (u32, f64)> + '_ {
        self.out.iter().filter(|r| r.3 > 0.0).map(|r| (r.0, r.3))
    }

    /// A bound of the repulsion's stiffness on each particle of the body, for the stable time
    /// step: a particle with as many partners within reach as it has neighbours at rest (a
    /// piece pressed back onto the face it broke from).
    pub fn stiffness_bound(&self, pd: &PdBody) -> Vec<f64> {
        let reach = self.reach();
        let x = &pd.reference[..pd.len()];
        let grid = CellGrid::new(x, reach);
        let vol = &pd.case.particles.volume;
        (0..pd.len())
            .into_par_iter()
            .map(|i| {
                let mut k = 0.0;
                grid.for_each_candidate(&x[i], reach, |j| {
                    let j = j as usize;
                    if j != i && (x[j] - x[i]).norm_squared() < reach * reach {
                        k += self.coefficient * vol[i] * vol[j];
                    }
                });
                k
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_broken_pair_repels_only_once_pressed_nearer_than_it_started() {
        // LAMMPS's rule: d = min(0.9 |x|, 1.35 Δ).
        let dx = 1.0;
        let d = |r0: f64| (RELEASE * r0).min(DISTANCE * dx);
        assert!((d(1.0) - 0.9).abs() < 1e-12);
        assert!((d(3.0) - 1.35).abs() < 1e-12);
        let coef = 2.0;
        // At its reference distance a broken neighbour pair feels nothing ...
        assert_eq!(
            pair_force(coef, 1.0, 1.0, d(1.0), Vec3::new(1.0, 0.0, 0.0)),
            Vec3::zeros()
        );
        // ... and is pushed apart once 20 % nearer.
        let f = pair_force(coef, 1.0, 1.0, d(1.0), Vec3::new(0.8, 0.0, 0.0));
        assert!((f.x - coef * 0.1).abs() < 1e-12 && f.x > 0.0);
    }
}
