//! The surface found again as bonds break: the eigenvalue method (paper Eqs. 11-16, METHOD.md
//! §3) over each particle's intact bonds, where bonds broke since the last time.
//!
//! The paper finds the surface from the particles rather than the mesh so that fracture's new
//! boundaries can be found as they open. The surface found at the build
//! ([`crate::case::surface`]) sums the kernel over every particle within reach; here the sums
//! run over the particle's bonds, once over all of them and once over the intact ones, at the
//! same kernel width `h = s_i`:
//!
//! - **Test (Eq. 15).** `L_i` over the intact bonds against `L_i` over the whole family: the
//!   smallest eigenvalue `μ` of `L_all^{-1/2} L_intact L_all^{-1/2}`. It is 1 where nothing
//!   broke, ½ where the bonds of a half-space are gone, 0 for a particle with no bond left; a
//!   particle with `μ ≤ 0.75` lies on a new surface. Taken against the whole family, not
//!   against the identity, the test asks only what the broken bonds took away: a sparse cloud
//!   that under-samples a direction (why the build confirms its candidates at a wider kernel)
//!   under-samples it in both sums, and a horizon shorter than the kernel's reach `3 s_i`
//!   shortens both.
//! - **Normal (Eq. 16).** `v = −L⁻¹ Σ ∇W V` over the intact bonds at the build's normal width
//!   `2 s_i` (within the horizon). On the faces of a cut through gmsh's tets it lies 2.4° from
//!   the cut's normal (median; at most 6.5° away from the body's sides, which tilt it towards
//!   their edge as they tilt the build's normals). Taking the whole family's sum as zero and
//!   pointing the normal at the broken bonds alone, at `h = s_i`, read 7° (median).
//! - **Occlusion.** A flagged particle with another flagged particle of its own side (still
//!   bonded to it) within `2 s_i`, inside the 45° cone about its normal and facing the same way,
//!   lies under the new surface rather than on it (the build's rule). A particle on the other
//!   side of the crack has lost its bond to it and covers nothing.
//!
//! Particles of the surface as built stay as they are. Every quantity is of the reference
//! configuration and the intact bonds, which every rank holds: the same bits on any thread or
//! rank count. Nothing of the mechanics reads it; it is what the frames (`surface`, `normal`,
//! `new_surface`) and the summary show, and it is brought up to date when they ask
//! ([`NewSurface::current`]): a particle that loses bonds over many steps is tested once a
//! frame, not once a step. The result does not depend on when it is asked (a particle's test
//! reads its own bonds only, and the occlusion test is taken again for the partners of every
//! particle tested).

use std::sync::{Mutex, MutexGuard};
use std::time::Instant;

use nalgebra::{Matrix3, SymmetricEigen};
use rayon::prelude::*;

use crate::case::surface::{outward_normal, NORMAL_KERNEL_WIDTH, OCCLUSION_RADIUS, SURFACE_LAMBDA};
use crate::case::PdCase;
use crate::math::Vec3;

/// The 45° cone of the occlusion test.
const OCCLUSION_COS: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// The kernels reach `3h` inclusive up to round-off, as the build's: `(r/2h)² ≤ 9 CUTOFF` for
/// the normals' kernel, `≤ 2.25 CUTOFF` for the test's.
const CUTOFF: f64 = 1.0 + 2e-9;

/// Particles per work item.
const CHUNK: usize = 64;

/// The surface that broken bonds opened in one body, brought up to date when asked.
#[derive(Debug, Default)]
pub struct NewSurface(Mutex<Found>);

impl Clone for NewSurface {
    fn clone(&self) -> NewSurface {
        NewSurface(Mutex::new(self.lock().clone()))
    }
}

impl NewSurface {
    /// Nothing broken among `particles`.
    pub fn new(particles: usize) -> NewSurface {
        NewSurface(Mutex::new(Found::new(particles)))
    }

    /// Notes that the bond between `i` and `j` broke ([`Found::broke`]).
    pub fn broke(&mut self, i: usize, j: usize) {
        self.0
            .get_mut()
            .unwrap_or_else(|e| e.into_inner())
            .broke(i, j);
    }

    /// The surface as the bonds `intact` now leave it ([`Found::update`]).
    pub fn current(
        &self,
        case: &PdCase,
        reference: &[Vec3],
        intact: &[bool],
    ) -> MutexGuard<'_, Found> {
        let mut found = self.lock();
        found.update(case, reference, intact);
        found
    }

    /// A panic elsewhere while the lock was held leaves the state as the last update made it.
    fn lock(&self) -> MutexGuard<'_, Found> {
        self.0.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// The state of a [`NewSurface`].
#[derive(Clone, Debug, Default)]
pub struct Found {
    /// Per particle: the smallest eigenvalue `μ` of the intact family's kernel matrix against
    /// the whole family's (1 where no bond broke).
    pub ratio: Vec<f64>,
    /// Per particle: on a surface that broken bonds opened (not on the surface as built).
    pub is_new: Vec<bool>,
    /// The outward unit normal (Eq. 16 over the intact bonds) of a particle tested with
    /// `μ ≤ 0.75`; zero elsewhere. Read it where `is_new`.
    pub normal: Vec<Vec3>,
    /// Particles that lost a bond since the last update.
    pending: Vec<u32>,
    /// The completed volumes `V/ω` of the particles and their images (the build's), kept
    /// from the first update.
    volume: Vec<f64>,
    /// Particles tested so far.
    pub tested: usize,
    /// Time spent finding it, s.
    pub seconds: f64,
}

impl Found {
    fn new(particles: usize) -> Found {
        Found {
            ratio: vec![1.0; particles],
            is_new: vec![false; particles],
            normal: vec![Vec3::zeros(); particles],
            ..Found::default()
        }
    }

    /// Particles on the new surface.
    pub fn count(&self) -> usize {
        self.is_new.iter().filter(|&&s| s).count()
    }

    /// Notes that the bond between `i` and `j` broke (`j` may be a mirror image, which is
    /// not tested).
    fn broke(&mut self, i: usize, j: usize) {
        let n = self.is_new.len();
        self.pending.push(i as u32);
        if j < n {
            self.pending.push(j as u32);
        }
    }

    /// Tests again the particles that lost a bond since the last update, with `intact` the
    /// bonds' state (per directed bond of `case.bonds`) and `reference` the reference
    /// positions, images included.
    fn update(&mut self, case: &PdCase, reference: &[Vec3], intact: &[bool]) {
        if self.pending.is_empty() {
            return;
        }
        let start = Instant::now();
        let mut pending = std::mem::take(&mut self.pending);
        pending.sort_unstable();
        pending.dedup();
        if self.volume.is_empty() {
            self.volume = case.ghosts.extend(&case.particles.completed_volume());
        }
        let volume = &self.volume;
        let bonds = &case.bonds;
        let surface = &case.surface;
        let tested: Vec<(f64, Vec3)> = pending
            .par_chunks(CHUNK)
            .flat_map_iter(|chunk| {
                chunk.iter().map(|&i| {
                    let i = i as usize;
                    let h = surface.spacing[i];
                    let wide = NORMAL_KERNEL_WIDTH * h;
                    let (mut all, mut kept) = (Matrix3::<f64>::zeros(), Matrix3::<f64>::zeros());
                    let (mut kept_wide, mut gradient) = (Matrix3::<f64>::zeros(), Vec3::zeros());
                    for b in bonds.range(i) {
                        let j = bonds.partner[b] as usize;
                        let d = reference[j] - reference[i];
                        // The kernel factor `−W'/r` of both widths up to constants, which
                        // neither the test (a ratio) nor the normal (a direction) sees: one
                        // exponential, `exp(−(r/h)²) = exp(−(r/2h)²)⁴`.
                        let q = d.norm_squared() / (wide * wide);
                        if q > 9.0 * CUTOFF {
                            continue;
                        }
                        let e = (-q).exp();
                        let g = e * volume[j];
                        let f = if q <= 2.25 * CUTOFF {
                            (e * e) * (e * e) * volume[j]
                        } else {
                            0.0
                        };
                        let dd = d * d.transpose();
                        all += dd * f;
                        if intact[b] {
                            kept += dd * f;
                            kept_wide += dd * g;
                            gradient += d * g;
                        }
                    }
                    let ratio = relative_eigenvalue(&all, &kept);
                    let normal = if ratio <= SURFACE_LAMBDA {
                        outward_normal(&kept_wide, &gradient, wide)
                    } else {
                        Vec3::zeros()
                    };
                    (ratio, normal)
                })
            })
            .collect();
        for (&i, (ratio, normal)) in pending.iter().zip(tested) {
            let i = i as usize;
            self.ratio[i] = ratio;
            self.normal[i] = normal;
        }
        // The occlusion test again wherever a flag changed nearby: the particles tested and
        // their partners.
        let n = self.is_new.len();
        let flagged = |i: usize| self.ratio[i] <= SURFACE_LAMBDA && !surface.is_surface[i];
        let mut again: Vec<u32> = pending.clone();
        for &i in &pending {
            again.extend(
                bonds.partner[bonds.range(i as usize)]
                    .iter()
                    .filter(|&&j| (j as usize) < n && flagged(j as usize)),
            );
        }
        again.sort_unstable();
        again.dedup();
        let state: Vec<bool> = again
            .par_chunks(CHUNK)
            .flat_map_iter(|chunk| {
                chunk.iter().map(|&i| {
                    let i = i as usize;
                    if !flagged(i) {
                        return false;
                    }
                    let (x, nrm) = (reference[i], self.normal[i]);
                    if nrm == Vec3::zeros() {
                        // No bond left, or none on one side: debris, on the surface.
                        return true;
                    }
                    let reach = OCCLUSION_RADIUS * surface.spacing[i];
                    let covered = bonds.range(i).any(|b| {
                        let j = bonds.partner[b] as usize;
                        if j >= n || !intact[b] || !flagged(j) {
                            return false;
                        }
                        let d = reference[j] - x;
                        let r = d.norm();
                        r <= reach
                            && d.dot(&nrm) > OCCLUSION_COS * r
                            && self.normal[j].dot(&nrm) > OCCLUSION_COS
                    });
                    !covered
                })
            })
            .collect();
        for (&i, s) in again.iter().zip(state) {
            self.is_new[i as usize] = s;
        }
        self.tested += pending.len();
        self.seconds += start.elapsed().as_secs_f64();
    }
}

/// The smallest eigenvalue of `A^{-1/2} B A^{-1/2}` (`A = G Gᵀ`, the same as that of
/// `G⁻¹ B G⁻ᵀ`): how far `B` falls short of `A` in its weakest direction. 0 where `A` has
/// no inverse (a family too small or flat to span space: nothing to compare).
fn relative_eigenvalue(all: &Matrix3<f64>, kept: &Matrix3<f64>) -> f64 {
    let Some(chol) = all.cholesky() else {
        return 0.0;
    };
    let Some(g_inv) = chol.l().try_inverse() else {
        return 0.0;
    };
    let c = g_inv * kept * g_inv.transpose();
    SymmetricEigen::new(0.5 * (c + c.transpose()))
        .eigenvalues
        .min()
}
