use super::*;
use crate::case::generators;
use crate::math::Vec3;

/// A quarter of a box with two symmetry planes reproduces the whole box particle by
/// particle: eigenvalues, surface flags, normals and correction factors.
#[test]
fn quarter_box_matches_the_whole_box() {
    let whole = PdCase::build(
        generators::cuboid([-0.8, -0.8, 0.0], [0.8, 0.8, 0.6], 0.1),
        CaseOptions::default(),
    )
    .expect("whole box");
    let quarter = PdCase::build(
        generators::cuboid([0.0, 0.0, 0.0], [0.8, 0.8, 0.6], 0.1),
        CaseOptions {
            symmetry: vec![
                SymmetryPlane { axis: 0, at: 0.0 },
                SymmetryPlane { axis: 1, at: 0.0 },
            ],
            ..CaseOptions::default()
        },
    )
    .expect("quarter box");
    let find = |case: &PdCase, p: Vec3| {
        (0..case.particles.len())
            .find(|&i| (case.particles.position[i] - p).norm() < 1e-9)
            .expect("same lattice")
    };
    for (q, p) in quarter.particles.position.iter().enumerate() {
        let w = find(&whole, *p);
        let (lq, lw) = (quarter.surface.lambda_min[q], whole.surface.lambda_min[w]);
        assert!(
            (lq - lw).abs() < 1e-9,
            "λ at {:?}: quarter {lq}, whole {lw}",
            p.as_slice()
        );
        assert_eq!(
            quarter.surface.is_surface[q],
            whole.surface.is_surface[w],
            "at {:?}",
            p.as_slice()
        );
        assert!(
            (quarter.surface.normal[q] - whole.surface.normal[w]).norm() < 1e-6,
            "normal at {:?}: {:?} vs {:?}",
            p.as_slice(),
            quarter.surface.normal[q],
            whole.surface.normal[w]
        );
        for k in 0..3 {
            let (gq, gw) = (quarter.correction.g[q][k], whole.correction.g[w][k]);
            assert!(
                (gq / gw - 1.0).abs() < 1e-3,
                "g at {:?}: {gq} vs {gw}",
                p.as_slice()
            );
        }
    }
    // Faces on the cut planes are not master segments.
    assert!(quarter
        .segments
        .segments
        .iter()
        .all(|s| s
            .nodes
            .iter()
            .any(|&n| quarter.particles.position[n as usize].x > 1e-9)
            && s.nodes
                .iter()
                .any(|&n| quarter.particles.position[n as usize].y > 1e-9)));
}
