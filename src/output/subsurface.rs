//! The stress below a contact against Hertz's (METHOD.md §7): the largest shear stress on the
//! contact's axis, where a Hertzian contact yields first (0.31 p0 at a depth of 0.48a for
//! ν = 0.3). The stress is the particles' recovered one ([`PdBody::stress`]).

use serde::Serialize;

use crate::body::stress::max_shear;
use crate::body::PdBody;
use crate::output::analysis::ContactPatch;

/// Particles this close to the axis, in spacings, sample it (the shear varies as the square
/// of the distance from the axis there).
const AXIS_REACH: f64 = 0.5;

/// The deepest sample, in contact radii (the peak lies at 0.4-0.8a for any ν).
const DEEPEST: f64 = 2.0;

/// The largest shear stress on the axis below a circular contact, recovered and Hertz's.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct SubsurfaceShear {
    /// The largest `(σ₁ − σ₃)/2` of the samples, over Hertz's `p0`.
    pub peak: f64,
    /// Its depth, over Hertz's `a`.
    pub depth: f64,
    /// Hertz's largest shear over `p0`, and its depth over `a`.
    pub theory_peak: f64,
    pub theory_depth: f64,
    /// `peak / theory_peak − 1`.
    pub error: f64,
    /// Particles on the axis below the surface row, up to 2a deep.
    pub samples: usize,
}

/// Hertz's `(σ₁ − σ₃)/2` over `p0` on the axis of a circular contact, at depth `ζ a`
/// (Johnson, Contact Mechanics, Eq. 3.46: `σ_z = −p0/(1 + ζ²)`,
/// `σ_r = −p0 [(1 + ν)(1 − ζ atan(1/ζ)) − 1/(2(1 + ζ²))]`).
pub fn hertz_axis_shear(poisson: f64, zeta: f64) -> f64 {
    let sz = -1.0 / (1.0 + zeta * zeta);
    let at = if zeta > 0.0 {
        zeta * (1.0 / zeta).atan()
    } else {
        0.0
    };
    let sr = -(1.0 + poisson) * (1.0 - at) + 0.5 / (1.0 + zeta * zeta);
    0.5 * (sz - sr).abs()
}

/// Hertz's largest shear on the axis over `p0`, and its depth over `a`, for Poisson's ratio
/// `poisson` (golden-section search over depths 0.1-1.5a, where the single peak lies).
pub fn hertz_shear_peak(poisson: f64) -> (f64, f64) {
    let f = |z: f64| -hertz_axis_shear(poisson, z);
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut lo, mut hi) = (0.1, 1.5);
    let mut c = hi - g * (hi - lo);
    let mut d = lo + g * (hi - lo);
    while hi - lo > 1e-10 {
        if f(c) < f(d) {
            hi = d;
        } else {
            lo = c;
        }
        c = hi - g * (hi - lo);
        d = lo + g * (hi - lo);
    }
    let z = 0.5 * (lo + hi);
    (hertz_axis_shear(poisson, z), z)
}

/// The largest recovered shear below `patch` (a circular contact of Hertz's radius `a` and
/// peak `p0`) on body `pd`, against Hertz's for the body's Poisson's ratio. The samples are
/// the particles within half a spacing of the axis through the patch's centre along its
/// force, up to 2a deep; the surface row is left out (the contact force acts on it as a body
/// force, and its neighbourhood lies on one side: its recovered stress is not the
/// continuum's at the surface). None with no sample.
pub fn subsurface_shear(
    pd: &PdBody,
    patch: &ContactPatch,
    a: f64,
    p0: f64,
) -> Option<SubsurfaceShear> {
    let reach = AXIS_REACH * pd.spacing();
    let n = pd.len();
    let axis: Vec<(usize, f64)> = (0..n)
        .filter(|&i| !pd.case.surface.is_surface[i])
        .filter_map(|i| {
            let d = pd.case.particles.position[i] - patch.centre;
            let depth = d.dot(&patch.direction);
            let off = (d - depth * patch.direction).norm();
            (depth > 0.0 && depth <= DEEPEST * a && off <= reach).then_some((i, depth))
        })
        .collect();
    let at: Vec<usize> = axis.iter().map(|s| s.0).collect();
    let stress = pd.stress(&pd.u, &at, None);
    let (peak, depth) = axis
        .iter()
        .zip(&stress)
        .map(|(s, t)| (max_shear(t) / p0, s.1 / a))
        .max_by(|x, y| x.0.total_cmp(&y.0))?;
    let (theory_peak, theory_depth) = hertz_shear_peak(pd.material.poisson);
    Some(SubsurfaceShear {
        peak,
        depth,
        theory_peak,
        theory_depth,
        error: peak / theory_peak - 1.0,
        samples: at.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hertz_peak_shear_at_the_textbook_depth() {
        // Johnson, Contact Mechanics, §3.4: 0.31 p0 at 0.48a for ν = 0.3.
        let (peak, depth) = hertz_shear_peak(0.3);
        assert!((peak - 0.31).abs() < 0.005, "{peak}");
        assert!((depth - 0.48).abs() < 0.01, "{depth}");
        // At the surface's centre: σ_z = −p0, σ_r = −(1 + 2ν)p0/2.
        assert!((hertz_axis_shear(0.3, 0.0) - 0.1).abs() < 1e-12);
    }
}
