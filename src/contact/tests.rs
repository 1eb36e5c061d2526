use super::*;
use crate::scene::PenaltyLaw;

fn square(z: f64) -> [Vec3; 4] {
    [
        Vec3::new(0.0, 0.0, z),
        Vec3::new(1.0, 0.0, z),
        Vec3::new(1.0, 1.0, z),
        Vec3::new(0.0, 1.0, z),
    ]
}

/// A punch's bottom face (z = 0, x in [−1, 1], outward −z) and its side face (x = 1,
/// z in [0, 1], outward +x), as segments 0 and 1, against a slave at `p` whose outward
/// normal is `n` (the top of the block under the punch: +z).
fn at_punch_corner(p: Vec3, n: Vec3) -> Touch {
    let bottom = [
        Vec3::new(-1.0, 0.0, 0.0),
        Vec3::new(-1.0, 1.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
    ];
    let side = [
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(1.0, 1.0, 1.0),
        Vec3::new(1.0, 0.0, 1.0),
    ];
    let candidates = [bottom, side]
        .into_iter()
        .enumerate()
        .filter_map(|(k, x)| project(p, x, false).map(|pr| (k as u32, pr)));
    select_segment(candidates, || n, 0.04)
}

#[test]
fn slave_at_a_punch_corner_touches_the_right_face() {
    let up = Vec3::z();
    let face = |t: Touch| match t {
        Touch::Contact(seg, pr) => Some((seg, pr.gap)),
        _ => None,
    };
    // Pressed on the base, away from the edge.
    let t = face(at_punch_corner(Vec3::new(0.5, 0.5, 0.01), up)).expect("contact");
    assert_eq!(t.0, 0);
    assert!((t.1 + 0.01).abs() < 1e-12);
    // Pressed on the base just inside its edge, nearer the side face than the base: the
    // base holds it (not pushed out sideways).
    let t = face(at_punch_corner(Vec3::new(0.995, 0.5, 0.01), up)).expect("contact");
    assert_eq!(t.0, 0);
    // Beside the punch, drawn in around its corner: above the base by more than the window,
    // just inside the side face. It touches the side face edge-on.
    let t = face(at_punch_corner(Vec3::new(0.995, 0.5, 0.2), up)).expect("contact");
    assert_eq!(t.0, 1);
    assert!((t.1 + 0.005).abs() < 1e-12);
    // The same with the slave's normal turned a little (under 60 degrees) by the distortion.
    let tilted = Vec3::new(-0.5, 0.0, 1.0).normalize();
    assert_eq!(
        face(at_punch_corner(Vec3::new(0.995, 0.5, 0.2), tilted)).map(|t| t.0),
        Some(1)
    );
    // Outside the side face: in front of it, touching nothing.
    assert_eq!(at_punch_corner(Vec3::new(1.02, 0.5, 0.2), up), Touch::Clear);
    // Deep inside the punch, away from every face: it went through the base.
    assert!(matches!(
        at_punch_corner(Vec3::new(0.0, 0.5, 0.2), up),
        Touch::Missed(_, g) if (g + 0.2).abs() < 1e-12
    ));
    // Below the base: clear.
    assert_eq!(
        at_punch_corner(Vec3::new(0.5, 0.5, -0.01), up),
        Touch::Clear
    );
    // A slave facing away from the base (the back of a thin master) never touches it.
    assert_eq!(
        at_punch_corner(Vec3::new(0.5, 0.5, 0.01), -up),
        Touch::Clear
    );
}

/// Two unit quads meeting on the line x = 0 (nodes 1, 2 shared), each tilted by `slope`:
/// a valley (concave) for a positive slope, a ridge (convex) for a negative one.
fn fold(slope: f64) -> [([u32; 4], [Vec3; 4]); 2] {
    let z = |x: f64| slope * x.abs();
    let p = |x: f64, y: f64| Vec3::new(x, y, z(x));
    [
        (
            [0, 1, 2, 3],
            [p(-1.0, 0.0), p(0.0, 0.0), p(0.0, 1.0), p(-1.0, 1.0)],
        ),
        (
            [1, 4, 5, 2],
            [p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0), p(0.0, 1.0)],
        ),
    ]
}

/// Each quad's projection of `slave` that lands on it or beyond its boundary, with how far.
fn projections(slave: Vec3, faces: &[([u32; 4], [Vec3; 4])]) -> Vec<(u32, Projection, f64)> {
    faces
        .iter()
        .enumerate()
        .filter_map(|(k, (_, x))| project_any(slave, *x, false).map(|(p, o)| (k as u32, p, o)))
        .collect()
}

/// [`select_across_edge`] over `candidates` on `faces`, the slave facing down, window 0.5.
fn hold(
    slave: Vec3,
    faces: &[([u32; 4], [Vec3; 4])],
    candidates: Vec<(u32, Projection, f64)>,
) -> Option<(u32, Projection)> {
    select_across_edge(
        slave,
        candidates.into_iter(),
        |k| faces[k as usize].0,
        |k| faces[k as usize].1,
        || -Vec3::z(),
        0.5,
    )
}

fn across(slave: Vec3, slope: f64) -> Option<(u32, Projection)> {
    let f = fold(slope);
    hold(slave, &f, projections(slave, &f))
}

#[test]
fn slave_under_a_valley_line_is_held_along_the_mean_normal() {
    // Neither quad holds it: along each one's normal it lands beyond the shared edge.
    let slave = Vec3::new(0.0, 0.5, -0.05);
    let f = fold(0.2);
    assert!(f.iter().all(|(_, x)| project(slave, *x, false).is_none()));
    let (_, pr) = across(slave, 0.2).expect("held");
    assert!((pr.normal - Vec3::z()).norm() < 1e-12, "{:?}", pr.normal);
    assert!((pr.gap + 0.05).abs() < 1e-12, "{}", pr.gap);
    // The reaction goes to the shared edge's nodes.
    assert!(pr.weights[0].abs() < 1e-12 || pr.weights[1].abs() < 1e-12);
    // Deeper than the window, or beyond the edge by more than its depth: not held.
    assert!(across(Vec3::new(0.0, 0.5, -0.6), 0.2).is_none());
    assert!(across(Vec3::new(0.3, 0.5, 0.05), 0.2).is_none());
}

#[test]
fn slave_over_a_quad_valley_is_held_at_the_edges_nearest_point() {
    // The valley of `fold(0.2)` with each quad's far side sheared along y, opposite ways:
    // each clamps its projection onto the shared edge (nodes 1 and 2, x = 0) at another y.
    let z = |x: f64| 0.2 * x.abs();
    let p = |x: f64, y: f64| Vec3::new(x, y, z(x));
    let faces = [
        (
            [0, 1, 2, 3],
            [p(-1.0, 1.0), p(0.0, 0.0), p(0.0, 1.0), p(-1.0, 2.0)],
        ),
        (
            [1, 4, 5, 2],
            [p(0.0, 0.0), p(1.0, -1.0), p(1.0, 0.0), p(0.0, 1.0)],
        ),
    ];
    let slave = Vec3::new(0.0, 0.5, -0.05);
    let all = projections(slave, &faces);
    assert_eq!(all.len(), 2);
    // Each face's own clamp puts the slave elsewhere on the edge than the edge's nearest
    // point, y = 0.5, and elsewhere than the other face's clamp.
    let on_edge = |k: usize, w: [f64; 4]| {
        let x = faces[k].1;
        (0..4).map(|i| x[i] * w[i]).sum::<Vec3>()
    };
    let ys: Vec<f64> = all
        .iter()
        .map(|(k, p, _)| on_edge(*k as usize, p.weights).y)
        .collect();
    assert!((ys[0] - ys[1]).abs() > 0.01, "{ys:?}");
    // Held at y = 0.5 whichever face is picked: the pick forced by listing the other face
    // as too far outside to hold the slave (it still counts for the edge's mean normal).
    for pick in 0..2 {
        let listed: Vec<(u32, Projection, f64)> = all
            .iter()
            .map(|&(k, p, o)| (k, p, if k as usize == pick { o } else { o + 1.0 }))
            .collect();
        let (seg, pr) = hold(slave, &faces, listed).expect("held");
        assert_eq!(seg as usize, pick);
        let x = on_edge(pick, pr.weights);
        assert!((x - Vec3::new(0.0, 0.5, 0.0)).norm() < 1e-12, "{x:?}");
        assert!((pr.gap + 0.05).abs() < 1e-12, "{}", pr.gap);
    }
}

#[test]
fn slave_beside_a_ridge_is_not_held() {
    // Behind the left face's plane, and beyond its edge by less than that depth, but in
    // front of the right face: outside the master.
    let slave = Vec3::new(0.01, 0.5, 0.0);
    assert!(across(slave, -2.0).is_none());
    // The left face alone would hold it: the right face is what tells the edge is convex.
    let f = fold(-2.0);
    let left = project_any(slave, f[0].1, false).map(|(p, o)| (0u32, p, o));
    assert!(left.is_some_and(|(_, p, o)| o > 0.0 && o <= -p.gap));
    assert!(select_across_edge(
        slave,
        left.into_iter(),
        |k| f[k as usize].0,
        |k| f[k as usize].1,
        || -Vec3::z(),
        0.5
    )
    .is_some());
}

#[test]
fn projection_on_a_flat_square() {
    let p = project(Vec3::new(0.25, 0.75, -0.1), square(0.0), false).expect("inside");
    assert!((p.gap + 0.1).abs() < 1e-12);
    assert!((p.normal - Vec3::z()).norm() < 1e-12);
    // Bilinear weights at (r, t) = (−0.5, 0.5).
    let w = [0.1875, 0.0625, 0.1875, 0.5625];
    for k in 0..4 {
        assert!((p.weights[k] - w[k]).abs() < 1e-12, "{:?}", p.weights);
    }
    assert!(project(Vec3::new(1.2, 0.5, 0.0), square(0.0), false).is_none());
}

#[test]
fn projection_on_a_warped_quad_recovers_the_point() {
    let mut x = square(0.0);
    x[2].z = 0.3;
    x[1].x = 1.2;
    // A point of the bilinear surface at (r, t) = (0.3, −0.2), lifted along the normal.
    let (r, t) = (0.3, -0.2);
    let ri = [-1.0, 1.0, 1.0, -1.0];
    let ti = [-1.0, -1.0, 1.0, 1.0];
    let on: Vec3 = (0..4)
        .map(|k| x[k] * (0.25 * (1.0 + ri[k] * r) * (1.0 + ti[k] * t)))
        .sum();
    let e3 = (x[2] - x[0]).cross(&(x[3] - x[1])).normalize();
    let p = project(on - e3 * 0.05, x, false).expect("inside");
    assert!((p.gap + 0.05).abs() < 1e-9, "{}", p.gap);
    let back: Vec3 = (0..4).map(|k| x[k] * p.weights[k]).sum();
    assert!((back - on).norm() < 1e-9);
}

#[test]
fn triangle_barycentric() {
    let x = [Vec3::zeros(), Vec3::x(), Vec3::y(), Vec3::y()];
    let p = project(Vec3::new(0.25, 0.25, 0.2), x, true).expect("inside");
    assert!((p.gap - 0.2).abs() < 1e-12);
    assert!((p.weights.iter().sum::<f64>() - 1.0).abs() < 1e-12);
    assert!(project(Vec3::new(0.8, 0.8, 0.0), x, true).is_none());
}

#[test]
fn hertz_law_and_stiffness() {
    let m = (1.0 - 0.25f64 * 0.25) / 1e9;
    let k = hertz_stiffness(m, 0.0, 0.04);
    assert!((k - 4.0 / (3.0 * m) * 0.2).abs() < 1e-6 * k);
    let law = ContactLaw {
        law: PenaltyLaw::Hertz,
        stiffness: k,
        window: 0.04,
    };
    assert!((law.force(0.01) - k * 1e-3).abs() < 1e-9 * k);
    assert!((law.max_tangent() - 1.5 * k * 0.2).abs() < 1e-9 * k);
    // ADR's stiffness: dF/dδ by central difference where it is the tangent, the floor
    // below LIGHT_CONTACT of the window and the edge's tangent past the window.
    let h = 1e-7;
    let fd = (law.force(0.01 + h) - law.force(0.01 - h)) / (2.0 * h);
    assert!((law.relaxation_stiffness(0.01) - fd).abs() < 1e-6 * fd);
    let floor = law.tangent(law::LIGHT_CONTACT * 0.04);
    assert!((law.relaxation_stiffness(0.0) - floor).abs() < 1e-12 * floor);
    assert!((floor - 0.1 * law.max_tangent()).abs() < 1e-9 * floor);
    assert_eq!(law.relaxation_stiffness(1e-9), floor);
    assert_eq!(law.relaxation_stiffness(1.0), law.max_tangent());
}
