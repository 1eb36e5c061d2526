//! Contact pressure recovered on the slave surface (METHOD.md §5, §7).
//!
//! A particle's own pressure `p_i = F_i / A*_i` (normal contact force over its pressure area,
//! [`pressure_areas`](crate::case::segments::pressure_areas)) is one sample of the contact
//! pressure. On an unstructured cloud the samples scatter about the field: the particles'
//! stiffnesses vary with their volumes and neighbourhoods, and the stiff penalty hands each
//! the force that its own stiffness calls for. Measured on gmsh-default meshes, the scatter
//! is 5 % (tets) to 9 % (tets split into hexes) of the local pressure, about as large as the
//! whole error against Hertz, and the largest single value lies 10-20 % above the field.
//!
//! The recovered pressure does what a finite-element code's patch recovery does with its
//! nodal values (Zienkiewicz-Zhu): at each loaded particle, a plane `c0 + c1 u + c2 v` in the
//! surface's tangent coordinates is fitted by weighted least squares to the own pressures of
//! the loaded particles within [`RECOVERY_RADIUS`] surface spacings (symmetry images
//! included, normals within 60°), weights `A*_j exp(−(d/(ρ/2))²)`, and `c0` is the recovered
//! value. A plane reproduces a linear field exactly, but it lowers a concave profile's crest
//! (by 1-2 % on a Hertz contact five spacings wide, more near its edge): a quadric fitted the
//! same way over [`CURVATURE_RADIUS`] spacings gives the profile's curvature, and the plane's
//! response to that curvature is taken off `c0`. The two fits together reproduce a quadratic
//! field exactly, so a structured mesh's smooth pressures come back unchanged, while the
//! scatter of an unstructured one is averaged over the plane's ~30 samples. Last, per contact
//! patch (the loaded particles connected within the plane's radius), the recovered values
//! are scaled by one factor so that the patch's pressure integrates to its contact force
//! exactly, `Σ p̃_i A*_i = Σ |F_i|` (the factor is within 0.3 % of 1 on the meshes measured).
//!
//! Particles with too few loaded neighbours to fit a plane (a contact a few particles wide)
//! keep their own pressure. Unloaded particles stay at zero: the recovery neither widens nor
//! narrows the contact.

use nalgebra::{Cholesky, DMatrix, DVector, Dyn};
use rayon::prelude::*;

use crate::case::neighbours::CellGrid;
use crate::case::{mirror_direction, mirror_images, SymmetryPlane};
use crate::math::{tangent_frame, Vec3};

/// Radius of the plane fit, in surface spacings (the square root of the median pressure area
/// of the loaded particles); ~30 samples. Measured on gmsh-default quarter caps of tets split
/// into hexes: radii 2.5 and 3 leave MRE 4.4 % and 4.1 % of 6.6 % (docs/VALIDATION.md).
pub const RECOVERY_RADIUS: f64 = 3.0;

/// Radius of the quadric fit that gives the profile's curvature, in surface spacings.
pub const CURVATURE_RADIUS: f64 = 5.0;

/// Fewest loaded particles for a plane fit (twice its three coefficients).
const MIN_SAMPLES: usize = 6;

/// Smallest eigenvalue ratio of a fit's normal matrix.
const CONDITION: f64 = 1e-10;

/// Largest curvature correction, as a fraction of the plane's value (a quadric fitted across
/// a contact's edge, where the profile is no quadric, can call for more).
const MAX_CORRECTION: f64 = 0.2;

/// Neighbours whose normals differ by more than 60° belong to another face of the body.
const SAME_FACE: f64 = 0.5;

/// The surface at one instant: reference positions, outward normals, pressure areas `A*_i`
/// and normal contact force magnitudes `|F_i|` of a body's particles (zeros off the surface).
pub struct SurfaceLoads<'a> {
    pub position: &'a [Vec3],
    pub normal: &'a [Vec3],
    pub area: &'a [f64],
    pub force: &'a [f64],
    pub planes: &'a [SymmetryPlane],
}

impl SurfaceLoads<'_> {
    /// The particle's own pressure `F_i / A*_i` (zero where it carries no force or no area).
    pub fn particle_pressure(&self) -> Vec<f64> {
        self.area
            .iter()
            .zip(self.force)
            .map(|(&a, &f)| if a > 0.0 && f > 0.0 { f / a } else { 0.0 })
            .collect()
    }

    /// The recovered contact pressure (module docs).
    pub fn recovered_pressure(&self) -> Vec<f64> {
        let own = self.particle_pressure();
        let loaded: Vec<usize> = (0..own.len()).filter(|&i| own[i] > 0.0).collect();
        if loaded.len() < MIN_SAMPLES {
            return own;
        }
        let mut roots: Vec<f64> = loaded.iter().map(|&i| self.area[i].sqrt()).collect();
        roots.sort_unstable_by(f64::total_cmp);
        let spacing = roots[roots.len() / 2];
        let (radius, reach) = (RECOVERY_RADIUS * spacing, CURVATURE_RADIUS * spacing);

        // The loaded particles and their mirror images, each with its source.
        let mut points = Vec::with_capacity(loaded.len());
        let mut source = Vec::with_capacity(loaded.len());
        let mut normals = Vec::with_capacity(loaded.len());
        for &i in &loaded {
            for (y, mask) in mirror_images(self.position[i], self.planes) {
                points.push(y);
                source.push(i);
                normals.push(mirror_direction(self.normal[i], mask, self.planes));
            }
        }
        let grid = CellGrid::new(&points, reach);

        let fits: Vec<(f64, Vec<usize>)> = loaded
            .par_iter()
            .map(|&i| {
                let (x, n) = (self.position[i], self.normal[i]);
                // A loaded boundary node that the eigenvalue surface missed has no normal to
                // give a tangent plane: it keeps its own value, a patch of its own.
                if !(n.norm() > 0.5) {
                    return (own[i], Vec::new());
                }
                let (t1, t2) = tangent_frame(n);
                // Tangent coordinates are scaled by `reach`, for the conditioning of the fits.
                let mut plane = Fit::new(3);
                let mut quadric = Fit::new(6);
                let mut near = Vec::new();
                grid.for_each_candidate(&x, reach, |g| {
                    let g = g as usize;
                    let j = source[g];
                    let d = points[g] - x;
                    let dist = d.norm();
                    if dist > reach {
                        return;
                    }
                    if dist <= radius {
                        near.push(j);
                    }
                    if normals[g].dot(&n) < SAME_FACE {
                        return;
                    }
                    let (u, v) = (d.dot(&t1) / reach, d.dot(&t2) / reach);
                    let rho2 = (u * u + v * v) * reach * reach;
                    let p = own[j];
                    let wq = self.area[j] * (-rho2 / (0.5 * reach).powi(2)).exp();
                    quadric.add(&[1.0, u, v, u * u, u * v, v * v], wq, p);
                    if dist <= radius {
                        let wp = self.area[j] * (-rho2 / (0.5 * radius).powi(2)).exp();
                        plane.add(&[1.0, u, v], wp, p);
                        plane.samples.push((u, v, wp));
                    }
                });
                near.sort_unstable();
                near.dedup();
                let value = plane.factor().map(|chol| {
                    let c0 = chol.solve(&plane.rhs)[0];
                    // The plane's bias from the field's curvature, taken off with the
                    // curvature of the wider quadric fit (where one fits).
                    let bias = quadric.factor().map_or(0.0, |q| {
                        let q = q.solve(&quadric.rhs);
                        let curved = |u: f64, v: f64| q[3] * u * u + q[4] * u * v + q[5] * v * v;
                        chol.solve(&plane.moments_of(curved))[0]
                    });
                    c0 - bias.clamp(-MAX_CORRECTION * c0.abs(), MAX_CORRECTION * c0.abs())
                });
                // A fitted value at or below zero (a loaded particle at a steep edge) keeps its
                // own.
                (value.filter(|&v| v > 0.0).unwrap_or(own[i]), near)
            })
            .collect();

        // Patches: loaded particles connected within the radius (union-find over `loaded`).
        let mut slot = vec![usize::MAX; own.len()];
        for (k, &i) in loaded.iter().enumerate() {
            slot[i] = k;
        }
        let mut parent: Vec<usize> = (0..loaded.len()).collect();
        fn root(parent: &mut [usize], mut k: usize) -> usize {
            while parent[k] != k {
                parent[k] = parent[parent[k]];
                k = parent[k];
            }
            k
        }
        for (k, (_, near)) in fits.iter().enumerate() {
            for &j in near {
                let (a, b) = (root(&mut parent, k), root(&mut parent, slot[j]));
                parent[a.max(b)] = a.min(b);
            }
        }
        let mut force = vec![0.0; loaded.len()];
        let mut integral = vec![0.0; loaded.len()];
        for (k, &i) in loaded.iter().enumerate() {
            let r = root(&mut parent, k);
            force[r] += self.force[i];
            integral[r] += fits[k].0 * self.area[i];
        }
        let mut out = vec![0.0; own.len()];
        for (k, &i) in loaded.iter().enumerate() {
            let r = root(&mut parent, k);
            out[i] = if integral[r] > 0.0 {
                fits[k].0 * (force[r] / integral[r])
            } else {
                own[i]
            };
        }
        out
    }
}

/// A weighted least-squares fit: the normal matrix and right-hand side of its basis.
struct Fit {
    m: DMatrix<f64>,
    rhs: DVector<f64>,
    count: usize,
    /// The plane keeps its samples' `(u, v, weight)` to evaluate its bias.
    samples: Vec<(f64, f64, f64)>,
}

impl Fit {
    fn new(terms: usize) -> Fit {
        Fit {
            m: DMatrix::zeros(terms, terms),
            rhs: DVector::zeros(terms),
            count: 0,
            samples: Vec::new(),
        }
    }

    fn add(&mut self, basis: &[f64], weight: f64, value: f64) {
        let b = DVector::from_column_slice(basis);
        self.m += &b * b.transpose() * weight;
        self.rhs += b * (weight * value);
        self.count += 1;
    }

    /// The factored normal matrix, or `None` where the samples are fewer than twice the
    /// coefficients or leave it near singular (samples along a line).
    fn factor(&self) -> Option<Cholesky<f64, Dyn>> {
        if self.count < 2 * self.rhs.len() {
            return None;
        }
        let eig = self.m.clone().symmetric_eigenvalues();
        if !(eig.min() > CONDITION * eig.max()) {
            return None;
        }
        self.m.clone().cholesky()
    }

    /// A plane's right-hand side for the values `f(u, v)` at its samples instead of the
    /// pressures, with the same weights.
    fn moments_of(&self, f: impl Fn(f64, f64) -> f64) -> DVector<f64> {
        let mut rhs = DVector::zeros(3);
        for &(u, v, w) in &self.samples {
            rhs += DVector::from_column_slice(&[1.0, u, v]) * (w * f(u, v));
        }
        rhs
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat square patch of particles on z = 0 with irregular areas and the given pressure
    /// field, forces `p A`; returns the surface and the recovered pressure.
    fn patch(
        field: impl Fn(f64, f64) -> f64,
        jitter: f64,
    ) -> (Vec<Vec3>, Vec<f64>, Vec<f64>, Vec<f64>) {
        let mut x = Vec::new();
        let mut area = Vec::new();
        let mut force = Vec::new();
        for i in 0..21 {
            for j in 0..21 {
                let (u, v) = (i as f64 * 0.1 - 1.0, j as f64 * 0.1 - 1.0);
                let a = 0.01 * (1.0 + 0.5 * ((7 * i + 3 * j) % 5) as f64 / 4.0);
                // Scatter of the force about the field, alternating in sign.
                let s = 1.0 + jitter * if (i + 2 * j) % 3 == 0 { 1.0 } else { -0.5 };
                x.push(Vec3::new(u, v, 0.0));
                area.push(a);
                force.push(field(u, v).max(0.0) * a * s);
            }
        }
        let normal = vec![Vec3::new(0.0, 0.0, -1.0); x.len()];
        let loads = SurfaceLoads {
            position: &x,
            normal: &normal,
            area: &area,
            force: &force,
            planes: &[],
        };
        let p = loads.recovered_pressure();
        (x, area, force, p)
    }

    /// The recovered `p` equals `field` within `tol` (relative) where |x|, |y| < `half`.
    fn assert_field(x: &[Vec3], p: &[f64], field: impl Fn(f64, f64) -> f64, half: f64, tol: f64) {
        for (i, y) in x.iter().enumerate() {
            if y.x.abs() < half && y.y.abs() < half {
                let want = field(y.x, y.y);
                assert!((p[i] / want - 1.0).abs() < tol, "{} vs {want}", p[i]);
            }
        }
    }

    #[test]
    fn a_linear_field_is_recovered_and_the_force_kept() {
        let f = |u: f64, v: f64| 1e6 * (2.0 + 0.5 * u - 0.3 * v);
        let (x, area, force, p) = patch(f, 0.0);
        // Interior particles (the fit's patch fully inside) get the field exactly.
        assert_field(&x, &p, f, 0.7, 1e-3);
        let total: f64 = force.iter().sum();
        let integral: f64 = p.iter().zip(&area).map(|(p, a)| p * a).sum();
        assert!((integral / total - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_curved_field_comes_back_unchanged() {
        // A crest like a contact's: the plane alone would lower it by its curvature.
        let f = |u: f64, v: f64| 1e6 * (2.0 - u * u - 0.5 * v * v + 0.3 * u * v);
        let (x, _, _, p) = patch(f, 0.0);
        assert_field(&x, &p, f, 0.4, 5e-3);
    }

    #[test]
    fn scatter_falls_and_the_contact_keeps_its_extent() {
        let f = |u: f64, v: f64| 1e6 * (1.0 - (u * u + v * v) / 0.64).max(0.0).sqrt();
        let (x, area, force, p) = patch(f, 0.2);
        let own: Vec<f64> = force.iter().zip(&area).map(|(f, a)| f / a).collect();
        let err = |q: &[f64]| {
            let inside: Vec<usize> = (0..x.len()).filter(|&i| x[i].xy().norm() < 0.5).collect();
            inside
                .iter()
                .map(|&i| (q[i] - f(x[i].x, x[i].y)).abs())
                .sum::<f64>()
                / inside.len() as f64
                / 1e6
        };
        assert!(
            err(&p) < 0.5 * err(&own),
            "recovered {} own {}",
            err(&p),
            err(&own)
        );
        for i in 0..x.len() {
            assert_eq!(
                p[i] > 0.0,
                own[i] > 0.0,
                "particle {i} changed sides of the contact edge"
            );
        }
        let total: f64 = force.iter().sum();
        let integral: f64 = p.iter().zip(&area).map(|(p, a)| p * a).sum();
        assert!((integral / total - 1.0).abs() < 1e-12);
    }
}
