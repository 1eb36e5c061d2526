//! The vector sweeps ([`super::kernel`]) against the sweeps a bond at a time.

use super::{Lps, Stretch};
use crate::case::{generators, CaseOptions, PdCase, SymmetryPlane};
use crate::math::Vec3;

/// Forces of both sweeps on a block with a symmetry plane (mirror images among the
/// partners), position-aware weights and skin factors (every factor array present), both
/// kinematics, at a displacement that is not uniform: the same to 1e-12 of the largest.
#[test]
fn the_vector_sweeps_give_the_portable_sweeps_forces() {
    let mesh = generators::cuboid([0.0; 3], [0.6, 0.5, 0.45], 0.05);
    let options = CaseOptions {
        symmetry: vec![SymmetryPlane { axis: 0, at: 0.0 }],
        ..CaseOptions::default()
    };
    let case = PdCase::build(mesh, options).expect("valid block");
    let n = case.particles.len();
    let mut lps = Lps::new(&case, 1e9, 0.3, true);
    let factor: Vec<f64> = (0..n).map(|i| 1.0 + (i % 7) as f64).collect();
    let normal = vec![Vec3::new(0.0, 0.6, 0.8); n];
    lps.set_skin(&case, &factor, &normal);
    let reference = &case.particles.position;
    let real: Vec<Vec3> = reference
        .iter()
        .map(|x| x + Vec3::new(1e-3 * x.y * x.z, -2e-3 * x.x * x.x, 1.5e-3 * x.y))
        .collect();
    let mut pos = Vec::new();
    case.ghosts.extend_positions(&real, &mut pos);
    let mut refs = Vec::new();
    case.ghosts.extend_positions(reference, &mut refs);
    for stretch in [Stretch::Finite, Stretch::Small(&refs)] {
        let mut forces = |portable: bool| {
            lps.portable = portable;
            let mut f = vec![Vec3::zeros(); n];
            lps.forces(&case, &pos, stretch, &mut f, |_, g, o| *o = g);
            f
        };
        let (vector, portable) = (forces(false), forces(true));
        let largest = portable.iter().map(|f| f.norm()).fold(0.0, f64::max);
        assert!(largest > 0.0);
        let worst = vector
            .iter()
            .zip(&portable)
            .map(|(a, b)| (a - b).norm())
            .fold(0.0, f64::max);
        assert!(worst < 1e-12 * largest, "{worst} of {largest}");
    }
}
