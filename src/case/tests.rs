use super::*;
use crate::case::crack_faces::CrackPatch;

#[test]
fn a_model_keeps_its_meshs_nodes_and_sets_without_the_elements() {
    let mesh = generators::cuboid([0.0, 0.0, 0.0], [0.5, 0.4, 0.3], 0.1);
    assert!(mesh.element_count() > 0 && mesh.sets.iter().any(|s| s.nodes.is_none()));
    let kept = nodes_and_sets(mesh.clone());
    assert_eq!(kept.element_count(), 0);
    assert_eq!(kept.coords, mesh.coords);
    assert_eq!(kept.node_ids, mesh.node_ids);
    assert_eq!(kept.sets.len(), mesh.sets.len());
    for (k, s) in kept.sets.iter().zip(&mesh.sets) {
        assert_eq!(k.name, s.name);
        assert_eq!(kept.set_nodes(k), mesh.set_nodes(s), "set {}", s.name);
    }
    // A case built for a model says what the elements were as one that kept them.
    let whole = PdCase::build(mesh.clone(), CaseOptions::default()).expect("whole");
    let lean = PdCase::build(
        mesh,
        CaseOptions {
            keep_elements: false,
            ..CaseOptions::default()
        },
    )
    .expect("lean");
    assert_eq!(lean.mesh.element_count(), 0);
    assert_eq!(lean.refinable(), whole.refinable());
    assert_eq!(
        lean.corners_of_second_order(),
        whole.corners_of_second_order()
    );
    assert_eq!(lean.bonds.partner, whole.bonds.partner);
    assert_eq!(lean.correction.bond_factor, whole.correction.bond_factor);
    // The same surface, without the eigenvalues that chose it.
    assert_eq!(lean.surface.is_surface, whole.surface.is_surface);
    assert_eq!(lean.surface.normal, whole.surface.normal);
    assert!(lean.surface.lambda_min.is_empty() && !whole.surface.lambda_min.is_empty());
}

#[test]
fn images_across_symmetry_planes() {
    let planes = [
        SymmetryPlane { axis: 0, at: 0.0 },
        SymmetryPlane { axis: 1, at: 1.0 },
    ];
    assert_eq!(mirror_images(Vec3::new(0.5, 0.5, 0.0), &planes).len(), 4);
    assert!(
        mirror_images(Vec3::new(0.5, 0.5, 0.0), &planes).contains(&(Vec3::new(-0.5, 1.5, 0.0), 3))
    );
    // A point on both planes is its own image.
    assert_eq!(mirror_images(Vec3::new(0.0, 1.0, 3.0), &planes).len(), 1);
    assert_eq!(mirror_images(Vec3::new(0.0, 0.5, 3.0), &planes).len(), 2);
}

#[test]
fn a_mirrored_direction_flips_once_per_reflection() {
    let planes = [
        SymmetryPlane { axis: 1, at: 0.0 },
        SymmetryPlane { axis: 1, at: 0.3 },
    ];
    let n = Vec3::new(0.1, 0.6, -0.8);
    // Across one plane the y component flips; across both (a translation by 0.6) it does not.
    assert_eq!(mirror_direction(n, 1, &planes), Vec3::new(0.1, -0.6, -0.8));
    assert_eq!(mirror_direction(n, 3, &planes), n);
    let images = mirror_images(Vec3::new(0.0, 0.1, 0.0), &planes);
    assert!(images.contains(&(Vec3::new(0.0, 0.7, 0.0), 3)));
}

use crate::case::generators;

/// A flat-faced hex block through the whole pipeline: lumped volumes, completed at the
/// faces, give the lattice values of the eigenvalue test for h = Δ.
#[test]
fn flat_faced_block_lattice_lambdas() {
    let mesh = generators::cuboid([0.0; 3], [1.4, 1.4, 1.4], 0.1);
    let case = PdCase::build(mesh, CaseOptions::default()).expect("valid block");
    let p = &case.particles;
    let find = |x: f64, y: f64, z: f64| {
        (0..p.len())
            .find(|&i| (p.position[i] - crate::math::Vec3::new(x, y, z)).norm() < 1e-9)
            .expect("lattice point")
    };
    let face = case.surface.lambda_min[find(0.7, 0.7, 0.0)];
    let first = case.surface.lambda_min[find(0.7, 0.7, 0.1)];
    let second = case.surface.lambda_min[find(0.7, 0.7, 0.2)];
    assert!((face - 0.50).abs() < 0.01, "face {face}");
    assert!((first - 0.91).abs() < 0.01, "first layer {first}");
    assert!(second > 0.95, "second layer {second}");
    // Every boundary node is found, and no interior node is flagged.
    let a = case.surface_agreement();
    assert_eq!((a.missed, a.extra), (0, 0), "{a:?}");
    assert_eq!(case.segments.segments.len(), case.faces.boundary.len());
}

/// A body whose pre-crack breaks its bonds (`faces = "found"`) gets, on the bonds it keeps,
/// the surface and skin corrections of the body cut there ([`PdCase::cut`]), with a symmetry
/// plane's images among the bonds; the broken bonds' factors 0.
#[test]
fn corrections_without_a_cuts_bonds_are_the_cut_bodys() {
    let mesh = generators::cuboid([0.0, 0.0, 0.0], [0.4, 0.3, 0.5], 0.05);
    let options = CaseOptions {
        symmetry: vec![SymmetryPlane { axis: 1, at: 0.0 }],
        ..CaseOptions::default()
    };
    let patch = CrackPatch::new(
        Vec3::new(0.2, 0.15, 0.26),
        Vec3::new(0.5, 0.0, 0.866_025_403_784_438_6),
        Vec3::new(0.0, 1.0, 0.0),
        [2.0, 2.0],
    );
    let mut cut = PdCase::build(mesh.clone(), options.clone()).expect("case");
    let mut kept = PdCase::build(mesh, options).expect("case");
    let as_built = kept.correction.bond_factor.clone();
    let mut position = Vec::new();
    kept.ghosts
        .extend_positions(&kept.particles.position, &mut position);
    let broken = patch.crossing(&kept.bonds, &position);
    assert!(!broken.is_empty());
    cut.cut(&[(0, patch)], CorrectionMethod::Balanced, true)
        .expect("cuts");
    kept.correct_without(&[(0, patch)], CorrectionMethod::Balanced, true)
        .expect("cuts");
    assert_eq!(kept.skin, cut.skin);
    let mut zeros = 0;
    for i in 0..kept.bonds.particles() {
        let mut on_cut = cut.bonds.range(i);
        for b in kept.bonds.range(i) {
            let factor = kept.correction.bond_factor[b];
            match on_cut.clone().next() {
                Some(c) if cut.bonds.partner[c] == kept.bonds.partner[b] => {
                    assert_eq!(factor, cut.correction.bond_factor[c], "bond {b}");
                    on_cut.next();
                }
                _ => {
                    assert_eq!(factor, 0.0);
                    zeros += 1;
                }
            }
        }
    }
    assert_eq!(zeros, kept.bonds.len() - cut.bonds.len());
    assert!(zeros >= broken.len());
    // The rows beside the cut are corrected anew (stiffer than as built).
    let stiffer = (0..as_built.len())
        .filter(|&b| kept.correction.bond_factor[b] > 1.01 * as_built[b])
        .count();
    assert!(stiffer > broken.len(), "{stiffer} bonds stiffer");
}
