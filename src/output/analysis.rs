//! Contact patches, reference solutions and accuracy figures (METHOD.md §7).
//!
//! * Sphere on a rigid plane (Eqs. 34-38): `a = (3PR/(4E*))^{1/3}`, `p0 = 3P/(2πa²)`,
//!   `p(r) = p0 √(1 − (r/a)²)`.
//! * Cylinder on a rigid plane, load `P` per unit length (Eqs. 39-42): `a = (4PR/(πE*))^{1/2}`,
//!   `p0 = 2P/(πa)`, the same profile across the contact strip.
//! * Rigid flat punch of half-width `a` (Eq. 43, Sadowsky): `p(x) = P/(π √(a² − x²))`.
//!
//! Accuracy, always all three figures: (1) `MRE = mean_i |p_i − p(r_i)| / p0` over the slave
//! surface particles that face the master and lie within `0.8 a` of the contact centre, whether
//! they carry force or not; (2) the radius (or half-width) of a least-squares fit of the
//! reference profile, relative to the theory; (3) force balance `|Σ F_contact − P| / P`.
//! Pressures are per undeformed pressure area, recovered on the surface ([`contact_pressure`],
//! which the frames write too; each particle's own value is [`particle_pressure`]).

use crate::body::{Body, PdBody};
use crate::math::Vec3;
use crate::model::Model;
use crate::output::recovery::SurfaceLoads;

/// Contact pressure of body `body`'s particles, recovered on its surface
/// ([`recovery`](crate::output::recovery): a least-squares plane through the loaded
/// particles' own pressures within 3 surface spacings, less its bias from the profile's
/// curvature, scaled per contact patch so that `Σ p_i A*_i` is the contact force exactly).
/// This is the `contact_pressure` of the frames.
pub fn contact_pressure(model: &Model, body: usize) -> Vec<f64> {
    match model.bodies[body].as_pd() {
        Some(pd) => surface_loads(pd, &normal_forces(pd), |s| s.recovered_pressure()),
        None => Vec::new(),
    }
}

/// Each particle's own pressure: normal contact force over its undeformed pressure area
/// (METHOD.md §5; the tributary area redistributed by the boundary layer's volume, see
/// [`pressure_areas`](crate::case::segments::pressure_areas)). The frames' `particle_pressure`.
pub fn particle_pressure(model: &Model, body: usize) -> Vec<f64> {
    match model.bodies[body].as_pd() {
        Some(pd) => surface_loads(pd, &normal_forces(pd), |s| s.particle_pressure()),
        None => Vec::new(),
    }
}

/// The magnitude of each particle's contact force as its pressure area carries it
/// ([`PdBody::pressure_force`]). The penalty force acts along the master segment's normal, so
/// this is the normal contact force; frictionless contact has no other.
pub fn normal_forces(pd: &PdBody) -> Vec<f64> {
    (0..pd.len()).map(|i| pd.pressure_force(i)).collect()
}

/// Runs `query` on body `pd`'s surface with the normal contact forces `force` (one per
/// particle; a decomposed run passes the values its owners sent).
pub fn surface_loads<T>(pd: &PdBody, force: &[f64], query: impl FnOnce(&SurfaceLoads) -> T) -> T {
    query(&SurfaceLoads {
        position: &pd.case.particles.position,
        normal: pd.surface_normals(),
        area: &pd.case.segments.pressure_area,
        force,
        planes: &pd.case.ghosts.planes,
    })
}

/// Hertz sphere on a rigid plane: contact radius and peak pressure.
pub fn hertz_sphere(load: f64, radius: f64, e_star: f64) -> (f64, f64) {
    let a = (3.0 * load * radius / (4.0 * e_star)).cbrt();
    (a, 3.0 * load / (2.0 * std::f64::consts::PI * a * a))
}

/// Hertz cylinder on a rigid plane, load per unit length: half-width and peak pressure.
pub fn hertz_cylinder(load_per_length: f64, radius: f64, e_star: f64) -> (f64, f64) {
    let a = (4.0 * load_per_length * radius / (std::f64::consts::PI * e_star)).sqrt();
    (a, 2.0 * load_per_length / (std::f64::consts::PI * a))
}

/// `E* = E/(1 − ν²)` of an elastic body on a rigid one (Eq. 38 with `E₂ → ∞`).
pub fn e_star_rigid(youngs: f64, poisson: f64) -> f64 {
    youngs / (1.0 - poisson * poisson)
}

/// The shape of a reference profile.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Profile {
    /// `p0 √(1 − (r/a)²)` with `r` the distance from the contact centre (sphere).
    Circular,
    /// The same across a strip: `r` is the distance from the contact line (roller).
    Strip,
}

/// Pressures of one body's slave particles facing a contact, in the contact's frame.
///
/// Positions are the particles' reference positions: pressures are per undeformed area
/// (METHOD.md §5), and in the small-strain theories they are compared with, `r` is a material
/// coordinate. (Measured on the deformed surface, `r` shrinks by up to (1 − 2ν)/3 · p0/E* · a,
/// about 1.7 % of `a` at p0/E = 0.1, which would move the figures by about 1 %.)
#[derive(Clone, Debug, Default)]
pub struct ContactPatch {
    /// Pressure-weighted centre of the contact (reference positions).
    pub centre: Vec3,
    /// Unit direction of the total contact force on the body.
    pub direction: Vec3,
    /// `(particle, r, pressure)` for every surface particle facing the contact.
    pub points: Vec<(u32, f64, f64)>,
    /// Largest pressure.
    pub peak: f64,
    /// Total contact force on the body.
    pub force: Vec3,
}

/// The contact patch of deformable body `body`. `strip_axis` gives the roller's axis: `r` is
/// then measured perpendicular to it.
pub fn contact_patch(model: &Model, body: usize, strip_axis: Option<Vec3>) -> Option<ContactPatch> {
    let Body::Deformable(pd) = &model.bodies[body] else {
        return None;
    };
    let p = contact_pressure(model, body);
    let force: Vec3 = pd.contact_force.iter().sum();
    let total: f64 = p
        .iter()
        .zip(&pd.case.segments.pressure_area)
        .map(|(p, a)| p * a)
        .sum();
    if !(total > 0.0) || !(force.norm() > 0.0) {
        return None;
    }
    let x = &pd.case.particles.position;
    let mut centre = Vec3::zeros();
    for i in 0..pd.len() {
        centre += x[i] * (p[i] * pd.case.segments.pressure_area[i] / total);
    }
    // A symmetry plane through the contact (a loaded particle on it) holds the whole
    // contact's centre, and the force of the whole body has no component across it: the
    // part's own force leans off the axis by the lateral forces its mirror images would
    // cancel (5° on a quarter gmsh sphere pressed on a block). A plane the contact does not
    // reach (a sphere's equator, a block's bottom) says neither.
    let mut direction = force;
    let ghosts = &pd.case.ghosts;
    for (k, plane) in ghosts.planes.iter().enumerate() {
        let through = (0..pd.len())
            .any(|i| p[i] > 0.0 && ghosts.on_plane.get(i).is_some_and(|m| m & (1 << k) != 0));
        if through {
            centre[plane.axis] = plane.at;
            direction[plane.axis] = 0.0;
        }
    }
    let direction = direction
        .try_normalize(0.0)
        .unwrap_or_else(|| force.normalize());
    let radial = |y: Vec3| {
        let d = y - centre;
        let mut inplane = d - direction * d.dot(&direction);
        if let Some(axis) = strip_axis {
            let ax = axis.normalize();
            inplane -= ax * inplane.dot(&ax);
        }
        inplane.norm()
    };
    // The contact surface lies within a band along the force: as far as the loaded particles
    // reach, plus two spacings. Surfaces deeper in the body that happen to face the same way
    // (the inner face of a thick shell) are not part of it.
    let height = |y: Vec3| (y - centre).dot(&direction).abs();
    let band = (0..pd.len())
        .filter(|&i| p[i] > 0.0)
        .map(|i| height(x[i]))
        .fold(0.0, f64::max)
        + 2.0 * pd.spacing();
    let mut points = Vec::new();
    let mut peak: f64 = 0.0;
    for i in 0..pd.len() {
        if !pd.case.surface.is_surface[i] || pd.case.segments.tributary_area[i] <= 0.0 {
            continue;
        }
        // Facing the contact: the outward normal points against the contact force.
        if pd.case.surface.normal[i].dot(&direction) > -0.5 || height(x[i]) > band {
            continue;
        }
        peak = peak.max(p[i]);
        points.push((i as u32, radial(x[i]), p[i]));
    }
    Some(ContactPatch {
        centre,
        direction,
        points,
        peak,
        force,
    })
}

/// Least-squares fit of `p0 √(1 − (r/a)²)₊` to `(r, p)` points: returns `(a, p0)`.
/// For each trial `a` the best `p0` is linear; `a` is found by golden-section search between
/// half and twice the largest loaded radius.
pub fn fit_elliptic(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    let rmax = points
        .iter()
        .filter(|(_, p)| *p > 0.0)
        .map(|(r, _)| *r)
        .fold(0.0, f64::max);
    if !(rmax > 0.0) {
        return None;
    }
    let cost = |a: f64| {
        let shape = |r: f64| (1.0 - (r / a).powi(2)).max(0.0).sqrt();
        let (mut sp, mut ss) = (0.0, 0.0);
        for &(r, p) in points {
            let s = shape(r);
            sp += s * p;
            ss += s * s;
        }
        let p0 = if ss > 0.0 { sp / ss } else { 0.0 };
        let c: f64 = points
            .iter()
            .map(|&(r, p)| (p - p0 * shape(r)).powi(2))
            .sum();
        (c, p0)
    };
    // Coarse scan first (the cost is not unimodal when few points carry load), then refine.
    let (lo, hi) = (0.5 * rmax, 2.0 * rmax);
    let mut best = (f64::INFINITY, lo);
    for k in 0..=200 {
        let a = lo + (hi - lo) * k as f64 / 200.0;
        let c = cost(a).0;
        if c < best.0 {
            best = (c, a);
        }
    }
    let step = (hi - lo) / 200.0;
    let (mut x0, mut x1) = ((best.1 - step).max(1e-12), best.1 + step);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..60 {
        let a = x1 - g * (x1 - x0);
        let b = x0 + g * (x1 - x0);
        if cost(a).0 < cost(b).0 {
            x1 = b;
        } else {
            x0 = a;
        }
    }
    let a = 0.5 * (x0 + x1);
    Some((a, cost(a).1))
}

/// The three accuracy figures of a Hertz-type contact.
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct Accuracy {
    /// Mean relative error of the pressure within 0.8 a, normalised by p0.
    pub mre: f64,
    /// Fitted radius (or half-width) relative to theory, minus 1 (signed).
    pub radius_error: f64,
    pub fitted_radius: f64,
    pub fitted_peak: f64,
    /// Particles inside 0.8 a.
    pub samples: usize,
}

/// MRE of METHOD.md §7: the mean of `|p_i − theory(r_i)| / p0` over the patch's particles
/// within `r_i ≤ 0.8 a`, loaded or not; with their count (NaN MRE when there are none).
fn mean_relative_error(
    patch: &ContactPatch,
    a: f64,
    p0: f64,
    theory: impl Fn(f64) -> f64,
) -> (f64, usize) {
    let (sum, n) = patch
        .points
        .iter()
        .filter(|(_, r, _)| *r <= 0.8 * a)
        .fold((0.0, 0usize), |(s, n), &(_, r, p)| {
            (s + (p - theory(r)).abs(), n + 1)
        });
    let mre = if n == 0 {
        f64::NAN
    } else {
        sum / (n as f64 * p0)
    };
    (mre, n)
}

/// Accuracy of a patch against `p(r) = p0 √(1 − (r/a)²)`.
pub fn elliptic_accuracy(patch: &ContactPatch, a: f64, p0: f64) -> Accuracy {
    let (mre, samples) = mean_relative_error(patch, a, p0, |r| {
        p0 * (1.0 - (r / a).powi(2)).max(0.0).sqrt()
    });
    let pts: Vec<(f64, f64)> = patch.points.iter().map(|&(_, r, p)| (r, p)).collect();
    let (fa, fp) = fit_elliptic(&pts).unwrap_or((f64::NAN, f64::NAN));
    Accuracy {
        mre,
        radius_error: fa / a - 1.0,
        fitted_radius: fa,
        fitted_peak: fp,
        samples,
    }
}

/// Sadowsky's rigid flat punch of half-width `a` under load `P` per unit length (Eq. 43):
/// `p(x) = P / (π √(a² − x²))`, singular at the edges. Its accuracy is measured against
/// `p0 = P/(π a)`, the pressure at the centre, over `|x| ≤ 0.8 a`.
pub fn punch_accuracy(patch: &ContactPatch, a: f64, load_per_length: f64) -> Accuracy {
    let p0 = load_per_length / (std::f64::consts::PI * a);
    let (mre, samples) = mean_relative_error(patch, a, p0, |x| {
        load_per_length / (std::f64::consts::PI * (a * a - x * x).max(0.0).sqrt())
    });
    // The loaded width: the farthest particle carrying pressure.
    let width = patch
        .points
        .iter()
        .filter(|(_, _, p)| *p > 0.0)
        .map(|(_, r, _)| *r)
        .fold(0.0, f64::max);
    Accuracy {
        mre,
        radius_error: width / a - 1.0,
        fitted_radius: width,
        fitted_peak: patch.peak,
        samples,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_theoretical_values() {
        // The paper's own numbers follow from P = 1e8 N and E* = 5.333e8 Pa (METHOD.md §7).
        let (a, p0) = hertz_sphere(1e8, 1.0, 1e9 / (2.0 * (1.0 - 0.0625)));
        assert!((a - 0.52002).abs() < 5e-5, "{a}");
        assert!((p0 / 1.76563e8 - 1.0).abs() < 2e-4, "{p0}");
        let (a, p0) = hertz_cylinder(2e8, 1.0, 1e9 / (2.0 * (1.0 - 0.0625)));
        assert!((a - 0.69099).abs() < 5e-5, "{a}");
        assert!((p0 / 1.84264e8 - 1.0).abs() < 2e-4, "{p0}");
    }

    #[test]
    fn fit_recovers_an_exact_profile() {
        let pts: Vec<(f64, f64)> = (0..40)
            .map(|k| {
                let r = k as f64 * 0.01;
                (r, 2.0e8 * (1.0 - (r / 0.3).powi(2)).max(0.0).sqrt())
            })
            .collect();
        let (a, p0) = fit_elliptic(&pts).expect("fit");
        assert!((a - 0.3).abs() < 1e-6, "{a}");
        assert!((p0 / 2.0e8 - 1.0).abs() < 1e-6, "{p0}");
    }
}
