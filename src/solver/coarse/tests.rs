//! The coarse space's tests, and the stacked spheres the solver's other tests share.

use std::path::Path;

use super::super::dofs::Dofs;
use super::super::free_factor;
use super::super::tangent::Tangent;
use super::CoarseSpace;
use crate::body::Body;
use crate::math::Vec3;
use crate::model::Model;
use crate::scene::Scene;

/// The two gmsh tet4 quarter spheres of `tests/two_bodies.rs` (symmetry planes x = 0 and
/// y = 0 on both, z = −1 on the lower: particles on one plane and on two), touching at
/// the origin, two passes: springs to master nodes and, by the stabilisation, to the
/// ground.
pub(in crate::solver) fn stacked() -> Model {
    stacked_of("poisson_ratio = 0.25", "")
}

/// [`stacked`] with `material` in each body's `[body.material]` and `body` in its
/// `[[body]]`.
pub(in crate::solver) fn stacked_of(material: &str, extra: &str) -> Model {
    let mesh = |name: &str| {
        format!(
            "{:?}",
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("meshes")
                .join(name)
                .display()
                .to_string()
        )
    };
    let body = |name: &str, file: &str, planes: &str| {
        format!(
            r#"[[body]]
name = "{name}"
mesh = {}
kinematics = "small"
{extra}
[body.material]
youngs_modulus = 1e9
{material}
density = 1000.0
[[symmetry]]
body = "{name}"
axis = "x"
[[symmetry]]
body = "{name}"
axis = "y"
{planes}"#,
            mesh(file)
        )
    };
    let text = format!(
        r#"[solver]
kind = "static"
[output]
every = 100000
{}{}[[load]]
body = "upper"
force = [0.0, 0.0, -9.6e6]
[[contact]]
slave = "upper"
master = "lower"
radius = 2290.0
two_pass = true
"#,
        body("upper", "two_spheres_upper_h006.msh", ""),
        body(
            "lower",
            "two_spheres_lower_h006.msh",
            "[[symmetry]]\nbody = \"lower\"\naxis = \"z\"\nat = -1.0\nkeep = \"positive\"\n"
        ),
    );
    let scene = Scene::parse(&text, "scene.toml", Path::new(".")).expect("scene");
    let mut model = Model::from_scene(&scene).expect("model");
    model.compute_forces();
    model
}

/// A vector of the free components, deterministic.
pub(in crate::solver) fn vector(model: &Model, seed: u64) -> Dofs {
    let mut state = seed;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let mut v = Dofs::zeros(model);
    for (k, b) in model.bodies.iter().enumerate() {
        if let Body::Deformable(pd) = b {
            for (i, x) in v.pd[k].iter_mut().enumerate() {
                *x = Vec3::new(next(), next(), next()).component_mul(&free_factor(pd.fixed[i]));
            }
        }
    }
    v
}

/// The bonds' factor updated by a tangent's springs on the boxes they touch solves as
/// the whole matrix factorised does (the upper sphere held only by contact: `B` alone
/// is singular along its fall).
#[test]
fn the_updated_factor_solves_as_the_whole_one() {
    let model = stacked();
    let mut blocks = vec![None; model.bodies.len()];
    let tangent = Tangent::new(&model, 1.0, None, &mut blocks, false);
    let space = CoarseSpace::new(&model).expect("a coarse space");
    let nc = space.len();
    let updated = space.factor(&model, tangent.springs()).expect("factorises");
    let super::CoarseFactor::Updated { rows, .. } = &updated else {
        panic!("the whole matrix factorised");
    };
    assert!(
        !rows.is_empty() && rows.len() < nc / 4,
        "{} of {nc}",
        rows.len()
    );
    let whole =
        super::CoarseFactor::whole(&space.matrix(&model, tangent.springs())).expect("factorises");
    for seed in 1..4 {
        let v = nalgebra::DVector::from_iterator(
            nc,
            (0..nc).map(|i| ((i as u64 * 2654435761 + seed) % 1000) as f64 - 500.0),
        );
        let want = whole.solve(space.base.as_ref(), v.clone());
        let got = updated.solve(space.base.as_ref(), v);
        let gap = (&got - &want).norm() / want.norm();
        eprintln!("seed {seed}: {gap:e}, {} rows of {nc}", rows.len());
        assert!(gap < 1e-6, "seed {seed}: {gap:e}");
    }
}

/// `K = S A` is symmetric: `b·S A a = a·S A b` to rounding, while the plain `b·A a`
/// differs (the inner product the conjugate gradients once used); and the coarse
/// matrix assembled from the bonds and springs is `Pᵀ K P` as the product gives it,
/// column by column.
#[test]
fn the_tangent_is_symmetric_in_the_shares_and_the_coarse_matrix_is_its_projection() {
    let mut model = stacked();
    let mut blocks = vec![None; model.bodies.len()];
    let mut tangent = Tangent::new(&model, 1.0, None, &mut blocks, false);
    assert!(!tangent.springs().is_empty());
    let (a, b) = (vector(&model, 1), vector(&model, 2));
    let (mut aa, mut ab) = (Dofs::zeros(&model), Dofs::zeros(&model));
    tangent.apply(&mut model, &a, &mut aa);
    tangent.apply(&mut model, &b, &mut ab);
    let scale = a.dot_shares(&aa, &model);
    let shares = b.dot_shares(&aa, &model) - a.dot_shares(&ab, &model);
    let plain = b.dot(&aa) - a.dot(&ab);
    assert!(shares.abs() < 1e-12 * scale, "{shares} against {scale}");
    assert!(plain.abs() > 1e-6 * scale, "{plain} against {scale}");

    let space = CoarseSpace::new(&model).expect("a coarse space");
    let gap = projection_gap(&mut model, &mut tangent, &space);
    assert!(gap < 1e-8, "assembled against probed: {gap:e}");
    let nc = space.len();

    // The correction applies `P` and `Pᵀ` without building them: with `(Pᵀ K P)⁻¹`
    // replaced by the identity it gives `P Pᵀ S r`, as the rows built give it.
    let identity = super::CoarseFactor::whole(&nalgebra::DMatrix::identity(nc, nc))
        .expect("the identity factorises");
    let mut z = Dofs::zeros(&model);
    space.correct(&model, &identity, &a, &mut z);
    let mut pr = nalgebra::DVector::<f64>::zeros(nc);
    for (k, body) in model.bodies.iter().enumerate() {
        let Some(pd) = body.as_pd() else { continue };
        for (i, ai) in a.pd[k].iter().enumerate() {
            let (box_, m) = space.rows(&model, k, i);
            let mut seg = pr.fixed_rows_mut::<6>(6 * box_);
            seg += m.transpose() * (ai * pd.case.ghosts.share(i));
        }
    }
    let (mut worst, mut largest) = (0.0f64, 0.0f64);
    for k in 0..z.pd.len() {
        for i in 0..z.pd[k].len() {
            let (box_, m) = space.rows(&model, k, i);
            let built = m * pr.fixed_rows::<6>(6 * box_);
            worst = worst.max((z.pd[k][i] - built).norm());
            largest = largest.max(built.norm());
        }
    }
    assert!(
        largest > 0.0 && worst < 1e-12 * largest,
        "{worst:e} against {largest:e}"
    );
}

/// `|A − Pᵀ K P| / |Pᵀ K P|`: the coarse matrix assembled from the bonds and the springs
/// against `Pᵀ K P` as the tangent's product gives it, column by column.
fn projection_gap(model: &mut Model, tangent: &mut Tangent, space: &CoarseSpace) -> f64 {
    let model = &mut *model;
    let assembled = space.matrix(model, tangent.springs());
    let nc = space.len();
    let mut probed = nalgebra::DMatrix::<f64>::zeros(nc, nc);
    let (mut v, mut out) = (Dofs::zeros(model), Dofs::zeros(model));
    for c in 0..nc {
        v.fill_zero();
        for k in 0..v.pd.len() {
            for i in 0..v.pd[k].len() {
                let (box_, m) = space.rows(model, k, i);
                if box_ == c / 6 {
                    v.pd[k][i] = m.column(c % 6).into_owned();
                }
            }
        }
        tangent.apply(model, &v, &mut out);
        for (k, body) in model.bodies.iter().enumerate() {
            let Some(pd) = body.as_pd() else { continue };
            for i in 0..out.pd[k].len() {
                let (box_, m) = space.rows(model, k, i);
                let mut col = probed.fixed_view_mut::<6, 1>(6 * box_, c);
                col += m.transpose() * out.pd[k][i] * pd.case.ghosts.share(i);
            }
        }
    }
    (&assembled - &probed).norm() / probed.norm()
}

/// An LPS body's coarse matrix is `Pᵀ K P` too: its deviatoric pairs and its
/// dilatation's rank-one terms, at ν = 0.3 and at ν = 0.2 (where `k − 5μ/3 < 0`), with
/// the constant influence function and no skin correction (where the assembly is exact).
#[test]
fn an_lps_bodys_coarse_matrix_is_its_projection() {
    for nu in [0.3, 0.2] {
        let mut model = stacked_of(
            &format!("model = \"lps\"\npoisson_ratio = {nu}"),
            "skin_correction = false",
        );
        let mut blocks = vec![None; model.bodies.len()];
        let mut tangent = Tangent::new(&model, 1.0, None, &mut blocks, false);
        let space = CoarseSpace::new(&model).expect("a coarse space");
        let gap = projection_gap(&mut model, &mut tangent, &space);
        assert!(gap < 1e-8, "ν = {nu}: assembled against probed: {gap:e}");
    }
}
