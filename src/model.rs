//! A scene turned into bodies and contact passes, and the force evaluation the solvers call.
//!
//! `compute_forces` is one evaluation of Eq. 28: bond forces of every deformable body (Eq. 26
//! with the surface and volume corrections), applied loads, and contact forces.

use rayon::prelude::*;

use crate::body::{build_body, Body, PdBody, FIX_X, FIX_Y, FIX_Z};
use crate::contact::{hertz_stiffness, ContactLaw, ContactPass, WINDOW};
use crate::discretize::{Vec3, NOT_A_PARTICLE};
use crate::error::Result;
use crate::neighbours::BondList;
use crate::scene::{BodyKind, ContactMethod, Kinematics, Scene};
use crate::shortrange::ShortRangePass;

/// Particles per parallel work item of the bond loop.
const CHUNK: usize = 256;

/// Bodies and contact passes of a scene.
#[derive(Clone, Debug)]
pub struct Model {
    pub bodies: Vec<Body>,
    pub passes: Vec<ContactPass>,
    /// Pairs resolved by the short-range method.
    pub short_range: Vec<ShortRangePass>,
    /// Force evaluations so far.
    pub evaluations: usize,
    /// Scratch: current positions of each deformable body.
    positions: Vec<Vec<Vec3>>,
}

impl Model {
    /// Builds bodies, loads, constraints and contact passes from a scene.
    pub fn from_scene(scene: &Scene) -> Result<Model> {
        let mut bodies = Vec::with_capacity(scene.bodies.len());
        for spec in &scene.bodies {
            bodies.push(build_body(scene, spec)?);
        }
        let index = |name: &str| scene.bodies.iter().position(|b| b.name == name);

        for load in &scene.loads {
            let k = index(&load.body).ok_or_else(|| scene.error_at(&load.body, "no such body"))?;
            let force = Vec3::from(load.force);
            match &mut bodies[k] {
                Body::Rigid(rb) => {
                    if load.set.is_some() {
                        return Err(scene.error_at(
                            "set",
                            &format!("load on rigid body \"{}\": a rigid body takes its load as a whole (drop `set`)", load.body),
                        ));
                    }
                    rb.load += force;
                }
                Body::Deformable(pd) => {
                    let particles = match &load.set {
                        Some(set) => set_particles(scene, pd, set)?,
                        None => (0..pd.len() as u32).collect(),
                    };
                    let total: f64 = particles
                        .iter()
                        .map(|&p| pd.case.particles.volume[p as usize])
                        .sum();
                    for &p in &particles {
                        pd.load[p as usize] +=
                            force * (pd.case.particles.volume[p as usize] / total);
                    }
                }
            }
        }
        for c in &scene.constraints {
            let k = index(&c.body).ok_or_else(|| scene.error_at(&c.body, "no such body"))?;
            let Some(pd) = bodies[k].as_pd_mut() else {
                continue;
            };
            let mut mask = 0;
            for f in &c.fix {
                mask |= match f.as_str() {
                    "x" => FIX_X,
                    "y" => FIX_Y,
                    _ => FIX_Z,
                };
            }
            for p in set_particles(scene, pd, &c.set)? {
                pd.fixed[p as usize] |= mask;
            }
        }

        let mut passes = Vec::new();
        let mut short_range = Vec::new();
        for c in &scene.contacts {
            let (Some(s), Some(m)) = (index(&c.slave), index(&c.master)) else {
                continue;
            };
            if c.method == ContactMethod::ShortRange {
                short_range.push(ShortRangePass::new(&bodies, s, m));
                continue;
            }
            let add = |s: usize, m: usize, weight: f64, bodies: &[Body]| {
                let sb = bodies[s].as_pd().expect("slave is deformable");
                let m_slave = sb.material.compliance();
                let m_master = match &bodies[m] {
                    Body::Deformable(b) => b.material.compliance(),
                    Body::Rigid(b) => b.material.map_or(0.0, |mat| mat.compliance()),
                };
                let radius = c.radius.unwrap_or(0.5 * sb.spacing());
                let law = ContactLaw {
                    law: c.penalty,
                    stiffness: hertz_stiffness(m_slave, m_master, radius),
                    window: WINDOW * sb.spacing(),
                };
                ContactPass::new(bodies, s, m, law, weight)
            };
            let two = c.two_pass && scene.bodies[m].kind == BodyKind::Deformable;
            let w = if two { 0.5 } else { 1.0 };
            passes.push(add(s, m, w, &bodies));
            if two {
                passes.push(add(m, s, w, &bodies));
            }
        }
        let positions = bodies
            .iter()
            .map(|b| {
                b.as_pd()
                    .map_or(Vec::new(), |pd| vec![Vec3::zeros(); pd.len()])
            })
            .collect();
        Ok(Model {
            bodies,
            passes,
            short_range,
            evaluations: 0,
            positions,
        })
    }

    /// Total particles.
    pub fn particles(&self) -> usize {
        self.bodies
            .iter()
            .filter_map(Body::as_pd)
            .map(PdBody::len)
            .sum()
    }

    /// Total directed bonds.
    pub fn bonds(&self) -> usize {
        self.bodies
            .iter()
            .filter_map(Body::as_pd)
            .map(|b| b.case.bonds.len())
            .sum()
    }

    /// Evaluates all forces at the current displacements.
    pub fn compute_forces(&mut self) {
        self.evaluations += 1;
        for (body, pos) in self.bodies.iter_mut().zip(&mut self.positions) {
            match body {
                Body::Deformable(pd) => internal_forces(pd, pos),
                Body::Rigid(rb) => {
                    rb.contact_force = Vec3::zeros();
                    rb.contact_stiffness = 0.0;
                }
            }
        }
        for k in 0..self.passes.len() {
            self.passes[k].detect(&self.bodies);
        }
        for pass in &mut self.short_range {
            pass.detect(&self.bodies);
        }
        for pass in &self.passes {
            pass.apply(&mut self.bodies);
        }
        for pass in &self.short_range {
            pass.apply(&mut self.bodies);
        }
    }

    /// Sum of the applied loads on all bodies.
    pub fn applied_load(&self) -> Vec3 {
        self.bodies
            .iter()
            .map(|b| match b {
                Body::Deformable(pd) => pd.load.iter().sum(),
                Body::Rigid(rb) => rb.load,
            })
            .sum()
    }

    /// Contacts found in the last evaluation.
    pub fn contact_count(&self) -> usize {
        self.passes.iter().map(|p| p.contacts.len()).sum::<usize>()
            + self.short_range.iter().map(|p| p.touching).sum::<usize>()
    }

    /// Missed contacts in the last evaluation.
    pub fn missed_contacts(&self) -> usize {
        self.passes.iter().map(|p| p.missed).sum::<usize>()
            + self.short_range.iter().map(|p| p.missed).sum::<usize>()
    }

    /// Verlet rebuilds so far.
    pub fn verlet_rebuilds(&self) -> usize {
        self.passes.iter().map(|p| p.verlet.rebuilds).sum()
    }

    /// Contact energy `Σ w K δ^{5/2} / (5/2)` (Hertz) or `½ w K' δ²` (linear), plus
    /// `½ k (d − |y|)²` per short-range pair.
    pub fn contact_energy(&self) -> f64 {
        self.short_range.iter().map(|p| p.energy).sum::<f64>()
            + self
                .passes
                .iter()
                .map(|p| {
                    p.contacts
                        .iter()
                        .map(|c| {
                            let d = c.penetration;
                            // ∫ F dδ for F = force(δ): force(d)·d·(2/5) for Hertz, ·(1/2) linear.
                            // The force applied, so that a slave on a symmetry plane counts
                            // only its share, as its force does.
                            let f = c.force.norm();
                            match p.law.law {
                                crate::scene::PenaltyLaw::Hertz => 0.4 * f * d,
                                crate::scene::PenaltyLaw::Linear => 0.5 * f * d,
                            }
                        })
                        .sum::<f64>()
                })
                .sum::<f64>()
    }
}

/// Bond forces plus applied loads into `pd.force`; resets contact accumulators. `pos` is
/// scratch space for the current positions (real particles, then mirror images).
pub fn internal_forces(pd: &mut PdBody, pos: &mut Vec<Vec3>) {
    let x = &pd.case.particles.position;
    let n = pd.len();
    let ghosts = &pd.case.ghosts;
    pos.resize(n + ghosts.source.len(), Vec3::zeros());
    let (real, images) = pos.split_at_mut(n);
    real.par_iter_mut()
        .zip(x.par_iter().zip(pd.u.par_iter()))
        .for_each(|(p, (x, u))| *p = x + u);
    for (g, img) in images.iter_mut().enumerate() {
        *img = ghosts.reflect(real[ghosts.source[g] as usize], ghosts.mask[g]);
    }
    let pos: &[Vec3] = pos;
    let bonds = &pd.case.bonds;
    let w = &pd.bond_weight;
    let load = &pd.load;
    let reference = &pd.reference;
    let small = pd.kinematics == Kinematics::Small;
    pd.force
        .par_chunks_mut(CHUNK)
        .enumerate()
        .for_each(|(c, out)| {
            for (k, f) in out.iter_mut().enumerate() {
                let i = c * CHUNK + k;
                let acc = if small {
                    bond_force_small(pos, reference, bonds, w, i)
                } else {
                    bond_force(pos, bonds, w, i)
                };
                *f = acc + load[i];
            }
        });
    pd.contact_force.iter_mut().for_each(|f| *f = Vec3::zeros());
    pd.contact_stiffness.iter_mut().for_each(|k| *k = 0.0);
}

/// The bond force on particle `i` (Eq. 26 times the volumes, finite kinematics):
/// `Σ_j w_ij (|y_ij| − L_ij) y_ij/|y_ij|` with `y_ij = pos[j] − pos[i]` and `w` the bond weights
/// `c G v_c V_i V_j / L` of [`PdBody::bond_weight`]. The one kernel that both the solvers and
/// `pdcontact bench` run.
///
/// Weights and lengths are stored in single precision (12 bytes a bond with the partner index),
/// the arithmetic is double. On x86-64 processors with AVX2 and FMA (checked once, at run time)
/// the same code runs compiled for them: the square roots and divisions that bound the loop then
/// go four to an instruction instead of two.
#[inline]
pub fn bond_force(pos: &[Vec3], bonds: &BondList, w: &[f32], i: usize) -> Vec3 {
    #[cfg(target_arch = "x86_64")]
    {
        if has_avx2_fma() {
            // SAFETY: the processor supports the features `bond_force_avx2` is compiled for.
            return unsafe { bond_force_avx2(pos, bonds, w, i) };
        }
    }
    bond_force_portable(pos, bonds, w, i)
}

/// The bond force on particle `i` with the bond kinematics linearised (Eq. 26 with the
/// extension measured along the reference bond ξ): `Σ_j w_ij ((η_ij·ξ_ij)/|ξ_ij|²) ξ_ij`, where
/// `η_ij = u_j − u_i` from the current and reference positions. Dispatched as [`bond_force`].
#[inline]
pub fn bond_force_small(
    pos: &[Vec3],
    reference: &[Vec3],
    bonds: &BondList,
    w: &[f32],
    i: usize,
) -> Vec3 {
    #[cfg(target_arch = "x86_64")]
    {
        if has_avx2_fma() {
            // SAFETY: the processor supports the features the function is compiled for.
            return unsafe { bond_force_small_avx2(pos, reference, bonds, w, i) };
        }
    }
    let ui = pos[i] - reference[i];
    let mut acc = Vec3::zeros();
    for b in bonds.range(i) {
        let j = bonds.partner[b] as usize;
        let xi = reference[j] - reference[i];
        let eta = pos[j] - reference[j] - ui;
        acc += xi * (f64::from(w[b]) * eta.dot(&xi) / xi.norm_squared());
    }
    acc
}

/// [`bond_force_small`] in AVX2/FMA intrinsics, four bonds per step (see [`bond_force_avx2`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn bond_force_small_avx2(
    pos: &[Vec3],
    reference: &[Vec3],
    bonds: &BondList,
    w: &[f32],
    i: usize,
) -> Vec3 {
    use std::arch::x86_64::*;
    let range = bonds.range(i);
    let partner = &bonds.partner[range.clone()];
    let w = &w[range];
    let (xi0, ui) = (reference[i], pos[i] - reference[i]);
    let (rx, ry, rz) = (
        _mm256_set1_pd(xi0.x),
        _mm256_set1_pd(xi0.y),
        _mm256_set1_pd(xi0.z),
    );
    let (ux, uy, uz) = (
        _mm256_set1_pd(ui.x),
        _mm256_set1_pd(ui.y),
        _mm256_set1_pd(ui.z),
    );
    let (mut ax, mut ay, mut az) = (
        _mm256_setzero_pd(),
        _mm256_setzero_pd(),
        _mm256_setzero_pd(),
    );
    // Indexing checks each partner against the arrays' lengths.
    let lanes = |v: &[Vec3], k: usize| -> [__m256d; 3] {
        let p: [*const f64; 4] =
            std::array::from_fn(|m| (&v[partner[k + m] as usize] as *const Vec3).cast::<f64>());
        let a = _mm256_insertf128_pd::<1>(
            _mm256_castpd128_pd256(_mm_loadu_pd(p[0])),
            _mm_loadu_pd(p[2]),
        );
        let b = _mm256_insertf128_pd::<1>(
            _mm256_castpd128_pd256(_mm_loadu_pd(p[1])),
            _mm_loadu_pd(p[3]),
        );
        [
            _mm256_unpacklo_pd(a, b),
            _mm256_unpackhi_pd(a, b),
            _mm256_set_pd(*p[3].add(2), *p[2].add(2), *p[1].add(2), *p[0].add(2)),
        ]
    };
    let groups = partner.len() / 4;
    for g in 0..groups {
        let k = 4 * g;
        let [px, py, pz] = lanes(pos, k);
        let [qx, qy, qz] = lanes(reference, k);
        // ξ = X_j − X_i; η = (y_j − X_j) − u_i.
        let (sx, sy, sz) = (
            _mm256_sub_pd(qx, rx),
            _mm256_sub_pd(qy, ry),
            _mm256_sub_pd(qz, rz),
        );
        let (ex, ey, ez) = (
            _mm256_sub_pd(_mm256_sub_pd(px, qx), ux),
            _mm256_sub_pd(_mm256_sub_pd(py, qy), uy),
            _mm256_sub_pd(_mm256_sub_pd(pz, qz), uz),
        );
        let dot = _mm256_fmadd_pd(ez, sz, _mm256_fmadd_pd(ey, sy, _mm256_mul_pd(ex, sx)));
        let len2 = _mm256_fmadd_pd(sz, sz, _mm256_fmadd_pd(sy, sy, _mm256_mul_pd(sx, sx)));
        let wb = _mm256_cvtps_pd(_mm_loadu_ps(w[k..k + 4].as_ptr()));
        let s = _mm256_div_pd(_mm256_mul_pd(wb, dot), len2);
        ax = _mm256_fmadd_pd(sx, s, ax);
        ay = _mm256_fmadd_pd(sy, s, ay);
        az = _mm256_fmadd_pd(sz, s, az);
    }
    let sum = |v: __m256d| -> f64 {
        let mut l = [0.0f64; 4];
        _mm256_storeu_pd(l.as_mut_ptr(), v);
        (l[0] + l[1]) + (l[2] + l[3])
    };
    let mut acc = Vec3::new(sum(ax), sum(ay), sum(az));
    for k in 4 * groups..partner.len() {
        let j = partner[k] as usize;
        let xi = reference[j] - xi0;
        let eta = pos[j] - reference[j] - ui;
        acc += xi * (f64::from(w[k]) * eta.dot(&xi) / xi.norm_squared());
    }
    acc
}

/// Whether the processor has AVX2 and FMA (the standard library caches the answer).
#[cfg(target_arch = "x86_64")]
#[inline]
fn has_avx2_fma() -> bool {
    std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
}

/// [`bond_force`] in AVX2/FMA intrinsics: four bonds per step; the partners' coordinates are
/// loaded as (x, y) pairs and z and transposed into lanes; `1/|y|` comes from the
/// single-precision estimate refined by two Newton steps (relative error about 1e-13), which
/// keeps the square root and the division off the divider unit that bounds the plain loop.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn bond_force_avx2(pos: &[Vec3], bonds: &BondList, w: &[f32], i: usize) -> Vec3 {
    use std::arch::x86_64::*;
    let range = bonds.range(i);
    let partner = &bonds.partner[range.clone()];
    let length = &bonds.length[range.clone()];
    let w = &w[range];
    let yi = pos[i];
    let (cx, cy, cz) = (
        _mm256_set1_pd(yi.x),
        _mm256_set1_pd(yi.y),
        _mm256_set1_pd(yi.z),
    );
    let one = _mm256_set1_pd(1.0);
    let three_halves = _mm256_set1_pd(1.5);
    let half = _mm256_set1_pd(0.5);
    let (mut ax, mut ay, mut az) = (
        _mm256_setzero_pd(),
        _mm256_setzero_pd(),
        _mm256_setzero_pd(),
    );
    // Indexing `pos` checks each partner against its length: a bad list panics, never reads
    // outside the array. A `Vec3` is three contiguous f64.
    let coords = |j: u32| -> *const f64 { (&pos[j as usize] as *const Vec3).cast::<f64>() };
    let groups = partner.len() / 4;
    for g in 0..groups {
        let k = 4 * g;
        let (p0, p1, p2, p3) = (
            coords(partner[k]),
            coords(partner[k + 1]),
            coords(partner[k + 2]),
            coords(partner[k + 3]),
        );
        let a =
            _mm256_insertf128_pd::<1>(_mm256_castpd128_pd256(_mm_loadu_pd(p0)), _mm_loadu_pd(p2));
        let b =
            _mm256_insertf128_pd::<1>(_mm256_castpd128_pd256(_mm_loadu_pd(p1)), _mm_loadu_pd(p3));
        let dx = _mm256_sub_pd(_mm256_unpacklo_pd(a, b), cx);
        let dy = _mm256_sub_pd(_mm256_unpackhi_pd(a, b), cy);
        let dz = _mm256_sub_pd(
            _mm256_set_pd(*p3.add(2), *p2.add(2), *p1.add(2), *p0.add(2)),
            cz,
        );
        let r2 = _mm256_fmadd_pd(dz, dz, _mm256_fmadd_pd(dy, dy, _mm256_mul_pd(dx, dx)));
        let mut inv = _mm256_cvtps_pd(_mm_rsqrt_ps(_mm256_cvtpd_ps(r2)));
        let h = _mm256_mul_pd(half, r2);
        for _ in 0..2 {
            let t = _mm256_mul_pd(inv, inv);
            inv = _mm256_mul_pd(inv, _mm256_fnmadd_pd(h, t, three_halves));
        }
        let l0 = _mm256_cvtps_pd(_mm_loadu_ps(length[k..k + 4].as_ptr()));
        let wb = _mm256_cvtps_pd(_mm_loadu_ps(w[k..k + 4].as_ptr()));
        // w (|y| − L)/|y| = w (1 − L/|y|)
        let s = _mm256_mul_pd(wb, _mm256_fnmadd_pd(l0, inv, one));
        ax = _mm256_fmadd_pd(dx, s, ax);
        ay = _mm256_fmadd_pd(dy, s, ay);
        az = _mm256_fmadd_pd(dz, s, az);
    }
    let sum = |v: __m256d| -> f64 {
        let mut lanes = [0.0f64; 4];
        _mm256_storeu_pd(lanes.as_mut_ptr(), v);
        (lanes[0] + lanes[1]) + (lanes[2] + lanes[3])
    };
    let mut f = Vec3::new(sum(ax), sum(ay), sum(az));
    for k in 4 * groups..partner.len() {
        let y = pos[partner[k] as usize] - yi;
        let l = y.norm();
        f += y * (f64::from(w[k]) * (l - f64::from(length[k])) / l);
    }
    f
}

#[inline(always)]
fn bond_force_portable(pos: &[Vec3], bonds: &BondList, w: &[f32], i: usize) -> Vec3 {
    // Bonds go in groups of LANES with the partners gathered into plain arrays, so that the
    // square roots and divisions run as packed SIMD instructions.
    const LANES: usize = 4;
    let yi = pos[i];
    let range = bonds.range(i);
    let partner = &bonds.partner[range.clone()];
    let length = &bonds.length[range.clone()];
    let w = &w[range];
    let mut acc = [[0.0f64; LANES]; 3];
    let groups = partner
        .chunks_exact(LANES)
        .zip(length.chunks_exact(LANES))
        .zip(w.chunks_exact(LANES));
    for ((p, l0), wb) in groups {
        let mut d = [[0.0f64; LANES]; 3];
        for k in 0..LANES {
            let y = pos[p[k] as usize] - yi;
            d[0][k] = y.x;
            d[1][k] = y.y;
            d[2][k] = y.z;
        }
        for k in 0..LANES {
            let l = (d[0][k] * d[0][k] + d[1][k] * d[1][k] + d[2][k] * d[2][k]).sqrt();
            let s = f64::from(wb[k]) * (l - f64::from(l0[k])) / l;
            for a in 0..3 {
                acc[a][k] += d[a][k] * s;
            }
        }
    }
    let mut f = Vec3::new(
        acc[0].iter().sum(),
        acc[1].iter().sum(),
        acc[2].iter().sum(),
    );
    let tail = partner.len() - partner.len() % LANES;
    for ((&j, &l0), &wb) in partner[tail..].iter().zip(&length[tail..]).zip(&w[tail..]) {
        let y = pos[j as usize] - yi;
        let l = y.norm();
        f += y * (f64::from(wb) * (l - f64::from(l0)) / l);
    }
    f
}

/// Particles of a named set of a body's mesh (its corner nodes that are particles).
fn set_particles(scene: &Scene, pd: &PdBody, name: &str) -> Result<Vec<u32>> {
    let mesh = &pd.case.mesh;
    let Some(set) = mesh.set(name) else {
        let known: Vec<&str> = mesh.sets.iter().map(|s| s.name.as_str()).collect();
        return Err(scene.error_at(
            &format!("set = \"{name}\""),
            &format!(
                "body \"{}\" has no set \"{name}\" (its sets: {})",
                pd.name,
                if known.is_empty() {
                    "none".to_string()
                } else {
                    known.join(", ")
                }
            ),
        ));
    };
    let particles: Vec<u32> = mesh
        .set_nodes(set)
        .into_iter()
        .map(|n| pd.case.particles.particle_of_node[n as usize])
        .filter(|&p| p != NOT_A_PARTICLE)
        .collect();
    if particles.is_empty() {
        return Err(scene.error_at(
            &format!("set = \"{name}\""),
            &format!(
                "set \"{name}\" of body \"{}\" holds no particle (no corner node of a 3D element)",
                pd.name
            ),
        ));
    }
    Ok(particles)
}
