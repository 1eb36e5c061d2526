//! The linear peridynamic solid (`model = "lps"`, METHOD.md §8) against the continuum: a bar of
//! gmsh-default tets (`meshes/bar_tet4_h005.geo`: an eighth of a 3.2 × 1.6 × 1.6 m bar, h =
//! 0.05 m, three symmetry planes) pulled on its end faces by σ = 1 MPa. In its middle half, away
//! from the ends and a horizon inside the free faces, the axial strain gives the apparent
//! Young's modulus σ/ε_x and the lateral strains Poisson's ratio −ε_y/ε_x, −ε_z/ε_x (least
//! squares over the particles' displacements), against E = 1 GPa and the ν asked for
//! (docs/VALIDATION.md, "Any Poisson's ratio").

mod common;

use std::path::Path;

use nalgebra::{DMatrix, DVector};
use pdcontact::body::lps::Stretch;
use pdcontact::model::Model;
use pdcontact::output::analysis::{contact_patch, e_star_rigid, elliptic_accuracy, hertz_sphere};
use pdcontact::run::{run_scene, RunOptions};
use pdcontact::scene::Scene;

const YOUNGS: f64 = 1e9;
const STRESS: f64 = 1e6;
const LENGTH: f64 = 1.6;
const HALF_WIDTH: f64 = 0.8;

/// The bar (`tests/common`) pulled by `STRESS`.
fn scene(model: &str, poisson: f64, solver: &str, skin: bool) -> String {
    common::bar_scene(model, poisson, solver, "small", skin, STRESS)
}

/// Runs scene `text` to convergence, its frames in a folder of its own (the tests of this
/// file run at once: one folder for all had one run's frames removed under another).
fn run(text: &str) -> Model {
    run_with_summary(text).0
}

/// [`run`], with the run's summary.
fn run_with_summary(text: &str) -> (Model, pdcontact::run::RunSummary) {
    static RUNS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = RUNS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("pdcontact-lps-{}-{n}", std::process::id()));
    let scene = Scene::parse(text, "scene.toml", Path::new(".")).expect("scene");
    let options = RunOptions {
        output: Some(dir.clone()),
        quiet: true,
        stop: None,
        comm: None,
        study: false,
    };
    let (model, summary) = run_scene(&scene, &options).expect("the scene runs");
    let _ = std::fs::remove_dir_all(&dir);
    assert!(summary.converged, "residual {}", summary.residual);
    (model, summary)
}

/// (apparent E, ν from y, ν from z) of the bar in `model` with Poisson's ratio `poisson`.
fn bar(model: &str, poisson: f64) -> (f64, f64, f64) {
    bar_by(model, poisson, "adr", false).0
}

/// The bar's figures (`influence`: the LPS's influence function, or "" for the default), by
/// the static solver: ADR's to the digits docs/VALIDATION.md shows, in under half the time.
fn bar_with(model: &str, poisson: f64, influence: &str) -> (f64, f64, f64) {
    let text = common::with_influence(&scene(model, poisson, "static", false), influence);
    figures(&run(&text)).0
}

/// The bar's figures by solver `solver`, and its displacements.
fn bar_by(model: &str, poisson: f64, solver: &str, skin: bool) -> ((f64, f64, f64), Vec<[f64; 3]>) {
    figures(&run(&scene(model, poisson, solver, skin)))
}

/// The bar's (E, ν from y, ν from z) and displacements.
fn figures(model: &Model) -> ((f64, f64, f64), Vec<[f64; 3]>) {
    let pd = model.bodies[0].as_pd().expect("deformable");
    let x = &pd.case.particles.position;
    let inside = HALF_WIDTH - pd.case.horizon;
    let rows: Vec<usize> = (0..pd.len())
        .filter(|&i| {
            x[i].x > 0.25 * LENGTH && x[i].x < 0.75 * LENGTH && x[i].y < inside && x[i].z < inside
        })
        .collect();
    assert!(rows.len() > 1000, "{} particles in the middle", rows.len());
    // u_a = c0 + c1 x + c2 y + c3 z per component: the strains are the slopes.
    let a = DMatrix::from_fn(
        rows.len(),
        4,
        |r, c| if c == 0 { 1.0 } else { x[rows[r]][c - 1] },
    );
    let slope = |axis: usize| {
        let b = DVector::from_fn(rows.len(), |r, _| pd.u[rows[r]][axis]);
        let fit = a
            .clone()
            .svd(true, true)
            .solve(&b, 1e-12)
            .expect("least squares");
        fit[axis + 1]
    };
    let (ex, ey, ez) = (slope(0), slope(1), slope(2));
    (
        (STRESS / ex, -ey / ex, -ez / ex),
        pd.u.iter().map(|u| [u.x, u.y, u.z]).collect(),
    )
}

/// Without the skin correction (a bar that sees no contact), the position-aware influence
/// function: E and ν (the mean of the two axes) within 2 % (ν within 0.005 at ν = 0) from
/// ν = 0 to 0.49. Measured: E +0.38 to +1.29 %, ν within 0.0055 of the value asked on either
/// axis, within 0.0022 as the mean of the two. With ω = 1 and a factor per particle (the
/// default, `influence_function = "constant"`) E +2.7 to +3.3 % up to ν = 0.45 and −3.4 % at
/// 0.49: the bar's skin, a horizon thick, is stiffer along its faces than the bulk
/// (docs/VALIDATION.md).
#[test]
fn a_bar_has_the_youngs_modulus_and_poissons_ratio_asked_for() {
    for poisson in [0.0, 0.15, 0.3, 0.4, 0.45, 0.47, 0.49] {
        let (e, nu_y, nu_z) = bar_with("lps", poisson, "position-aware");
        eprintln!(
            "LPS ν = {poisson}: E {:+.2} %, ν {nu_y:.4} (y), {nu_z:.4} (z)",
            100.0 * (e / YOUNGS - 1.0)
        );
        assert!(
            (e / YOUNGS - 1.0).abs() < 0.02,
            "ν = {poisson}: E = {e:.4e}"
        );
        let nu = 0.5 * (nu_y + nu_z);
        assert!(
            (nu - poisson).abs() < (0.02 * poisson).max(0.005),
            "ν = {poisson}: measured {nu_y} (y), {nu_z} (z)"
        );
    }
    let (e, _, _) = bar_with("lps", 0.3, "constant");
    eprintln!("constant, ν = 0.3: E {:+.2} %", 100.0 * (e / YOUNGS - 1.0));
    assert!((e / YOUNGS - 1.0).abs() < 0.04, "constant: E = {e:.4e}");
}

/// At ν = 1/4 the LPS is a bond-based solid (its dilatation term vanishes, 3k = 5μ) with
/// another influence function and no bond-based surface correction: both give the same
/// elastic constants in the bulk.
#[test]
fn at_a_quarter_the_lps_and_the_bond_based_bar_agree() {
    let (e_lps, nu_lps, _) = bar("lps", 0.25);
    let (e_bb, nu_bb, _) = bar("bond-based", 0.25);
    eprintln!("ν = 0.25: LPS E {e_lps:.4e}, ν {nu_lps:.4}; bond-based E {e_bb:.4e}, ν {nu_bb:.4}");
    assert!(
        (e_lps / e_bb - 1.0).abs() < 0.04,
        "LPS {e_lps}, bond-based {e_bb}"
    );
    assert!(
        (nu_lps - nu_bb).abs() < 0.01,
        "LPS {nu_lps}, bond-based {nu_bb}"
    );
}

/// The static solver (Newton on the LPS pass, which is linear in the displacements with small
/// kinematics) reaches ADR's bar; the pass has the same bits on one thread as on two; and a
/// body in no contact takes no skin correction, `skin_correction = true` or not (it would
/// stiffen the bar's faces: E +11 %).
#[test]
fn the_static_solver_and_any_thread_count_give_the_same_bar() {
    let (adr, _) = bar_by("lps", 0.3, "adr", true);
    let (newton, u2) = bar_by("lps", 0.3, "static", true);
    eprintln!(
        "ν = 0.3: ADR E {:.5e} ν {:.5}; static E {:.5e} ν {:.5}",
        adr.0, adr.1, newton.0, newton.1
    );
    assert!(
        (adr.0 / newton.0 - 1.0).abs() < 1e-3,
        "E: ADR {} static {}",
        adr.0,
        newton.0
    );
    assert!(
        (adr.1 - newton.1).abs() < 1e-3,
        "ν: ADR {} static {}",
        adr.1,
        newton.1
    );
    let (_, without) = bar_by("lps", 0.3, "static", false);
    assert!(
        without == u2,
        "the skin correction reached a body in no contact"
    );
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("pool");
    let (_, u1) = one.install(|| bar_by("lps", 0.3, "static", true));
    assert!(u1 == u2, "one thread and the default pool differ");
}

/// The skin correction goes on the faces a contact partner can press alone
/// (`body::facing`): the bar in a contact with a rigid plane 5 m below its symmetry plane
/// z = 0, which no face of it faces, is the bar in no contact to the bit (before, every surface
/// particle took the skin in any contact with another body: E +11 %); with the plane 5 m above
/// its face z = 0.8 that face alone takes it, and the bar comes out stiffer than without.
#[test]
fn the_skin_goes_on_the_faces_a_partner_can_press() {
    let with_plane = |z: f64, normal: f64| {
        format!(
            "{}[[body]]\nname = \"plane\"\nkind = \"rigid\"\ngenerator = {{ shape = \"plane\", point = [0.8, 0.4, {z}], normal = [0.0, 0.0, {normal}], size = 4.0 }}\n[[contact]]\nslave = \"bar\"\nmaster = \"plane\"\n",
            scene("lps", 0.3, "static", true)
        )
    };
    let (alone, u_alone) = bar_by("lps", 0.3, "static", false);
    let (model_below, summary) = run_with_summary(&with_plane(-5.0, 1.0));
    // `run` says that no face takes the skin, and why.
    assert!(
        summary
            .warnings
            .iter()
            .any(|w| w.contains("none of its surface faces a body it is in a contact with")),
        "{:?}",
        summary.warnings
    );
    let (below, u_below) = figures(&model_below);
    eprintln!(
        "ν = 0.3: no contact E {:+.2} %; plane below E {:+.2} %",
        100.0 * (alone.0 / YOUNGS - 1.0),
        100.0 * (below.0 / YOUNGS - 1.0)
    );
    assert!(
        u_below == u_alone,
        "a face that faces no partner took the skin"
    );
    let (above, _) = figures(&run(&with_plane(5.8, -1.0)));
    eprintln!(
        "plane above the face z = 0.8: E {:+.2} %",
        100.0 * (above.0 / YOUNGS - 1.0)
    );
    assert!(
        above.0 > 1.01 * alone.0,
        "the face the plane faces took no skin: E {} against {}",
        above.0,
        alone.0
    );
}

/// The Hertz sphere where its theory holds (a/R = 0.15) on a gmsh-default tet4 mesh
/// (`meshes/sphere_cap_quarter_tet4.geo`: the demo's quarter cap, h = 0.02 m, 2,744
/// particles) on a rigid plane, LPS at ν = 0.3 and 0.4, with and without the skin correction
/// (docs/VALIDATION.md, "Any Poisson's ratio"): (MRE, radius error, peak error).
fn cap(poisson: f64, skin: bool) -> (f64, f64, f64) {
    let model = run(&cap_scene(poisson, skin));
    let load = 4.8e6;
    let (a, p0) = hertz_sphere(load, 1.0, e_star_rigid(YOUNGS, poisson));
    let patch = contact_patch(&model, 0, None).expect("in contact");
    let acc = elliptic_accuracy(&patch, a, p0);
    (acc.mre, acc.radius_error, patch.peak / p0 - 1.0)
}

/// The cap's scene.
fn cap_scene(poisson: f64, skin: bool) -> String {
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/sphere_cap_quarter_tet4.msh");
    let load = 4.8e6;
    format!(
        r#"[solver]
kind = "adr"
tolerance = 1e-4
max_iterations = 50000
[output]
every = 1000000
[[body]]
name = "ball"
mesh = {mesh:?}
kinematics = "small"
skin_correction = {skin}
[body.material]
youngs_modulus = {YOUNGS:e}
poisson_ratio = {poisson}
density = 1000.0
model = "lps"
[[body]]
name = "plane"
kind = "rigid"
generator = {{ shape = "plane", point = [0.0, 0.0, -1.0], normal = [0.0, 0.0, 1.0], size = 3.0 }}
[[load]]
body = "ball"
set = "top"
force = [0.0, 0.0, {quarter:e}]
[[contact]]
slave = "ball"
master = "plane"
radius = 100.0
[[symmetry]]
body = "ball"
axis = "x"
[[symmetry]]
body = "ball"
axis = "y"
"#,
        mesh = mesh.display().to_string(),
        quarter = -load / 4.0,
    )
}

/// Measured (ADR, the 2-core VM, 7 s for the four runs): ν = 0.3: MRE 2.52 %, radius +1.05 %,
/// peak +8.0 %, without the skin correction 6.04 %, +5.89 %, −7.6 %; ν = 0.4: 6.10 %, −2.95 %,
/// +12.9 %, without it 3.17 %, +4.18 %, −3.3 %: the skin correction puts ν = 0.3 within the
/// bounds and over-stiffens the contact at 0.4 (docs/VALIDATION.md; with the position-aware
/// influence function 3.48 %, +0.20 %, +8.9 % and 7.44 %, −4.30 %, +14.5 %).
#[test]
fn the_hertz_cap_with_the_lps() {
    let mut got = Vec::new();
    for poisson in [0.3, 0.4] {
        let (mre, radius, peak) = cap(poisson, true);
        let (mre0, radius0, peak0) = cap(poisson, false);
        eprintln!(
            "ν = {poisson}: MRE {:.2} %, radius {:+.2} %, peak {:+.1} %; without the skin correction {:.2} %, {:+.2} %, {:+.1} %",
            100.0 * mre, 100.0 * radius, 100.0 * peak, 100.0 * mre0, 100.0 * radius0, 100.0 * peak0
        );
        got.push(((mre, radius, peak), (mre0, radius0)));
    }
    let ((mre, radius, peak), (_, radius0)) = got[0];
    assert!(
        mre < 0.03 && radius.abs() < 0.03 && peak.abs() < 0.1,
        "ν = 0.3: {:?}",
        got[0]
    );
    assert!(
        radius0 > 0.04,
        "ν = 0.3 without the skin correction: radius {radius0}"
    );
    let ((mre, radius, _), _) = got[1];
    assert!(mre < 0.07 && radius.abs() < 0.04, "ν = 0.4: {:?}", got[1]);
}

/// The position-aware influence function's defining property (METHOD.md §8,
/// `body::lps::position_aware`): under a uniform strain every particle's strain energy is the
/// continuum's `λ(tr ε)²/2 + μ ε:ε` (to 1e-6, the weights' solve's rounding), at the free faces and in the bulk of a gmsh tet mesh alike,
/// except where a neighbourhood too thin to fix it (an edge's, a corner's) had its correction
/// scaled back. The symmetry planes' images take the strain mirrored, so it is diagonal here.
#[test]
fn the_position_aware_lps_has_the_continuums_energy_under_any_uniform_strain() {
    for (influence, want) in [("position-aware", 0.95), ("constant", 0.0)] {
        let text = common::with_influence(&scene("lps", 0.3, "adr", false), influence);
        let scene = Scene::parse(&text, "scene.toml", Path::new(".")).expect("scene");
        let model = Model::from_scene(&scene).expect("builds");
        let pd = model.bodies[0].as_pd().expect("deformable");
        let case = &pd.case;
        let mut lps = pd.lps.clone().expect("an LPS body");
        let strain = nalgebra::Vector3::new(1e-3, -0.4e-3, 0.7e-3);
        let mut reference = Vec::new();
        case.ghosts
            .extend_positions(&case.particles.position, &mut reference);
        let pos: Vec<_> = reference
            .iter()
            .map(|x| x + x.component_mul(&strain))
            .collect();
        let mut force = vec![nalgebra::Vector3::zeros(); pd.len()];
        lps.forces(
            case,
            &pos,
            Stretch::Small(&reference),
            &mut force,
            |_, f, o| *o = f,
        );
        let (lambda, mu) = pd.material.lame();
        let trace = strain.sum();
        let continuum = 0.5 * lambda * trace * trace + mu * strain.norm_squared();
        let errors: Vec<f64> = (0..pd.len())
            .map(|i| {
                let w = lps.strain_energy_of(case, i, &pos, Stretch::Small(&reference))
                    / case.particles.volume[i];
                (w / continuum - 1.0).abs()
            })
            .collect();
        let exact = errors.iter().filter(|&&e| e < 1e-6).count() as f64 / errors.len() as f64;
        let mean = errors.iter().sum::<f64>() / errors.len() as f64;
        eprintln!(
            "{influence}: {:.1} % of {} particles within 1e-6 of the continuum's energy, mean error {:.2e}",
            100.0 * exact,
            errors.len(),
            mean
        );
        if want > 0.0 {
            assert!(exact > want, "{influence}: {exact}");
            assert!(mean < 1e-3, "{influence}: mean {mean}");
        } else {
            assert!(exact < 0.01 && mean > 1e-3, "{influence}: {exact}, {mean}");
        }
    }
}

/// The LPS pass is the gradient of an energy (the static solver's symmetric tangent, ADR's
/// convergence, rely on it): with small kinematics it is linear, `f = −K u`, and
/// `w·f(u) = u·f(w)` for any two displacements, with each influence function, and with the skin
/// correction (the cap, in a contact). Without its symmetry planes: a particle on one holds
/// part of its volume and its partners count the whole, which weights the rows.
#[test]
fn the_lps_tangent_is_symmetric() {
    for influence in ["constant", "position-aware"] {
        let text = cap_scene(0.3, true);
        let text = common::with_influence(
            &text[..text.find("[[symmetry]]").expect("planes")],
            influence,
        );
        let scene = Scene::parse(&text, "scene.toml", Path::new(".")).expect("scene");
        let model = Model::from_scene(&scene).expect("builds");
        let pd = model.bodies[0].as_pd().expect("deformable");
        let case = &pd.case;
        let mut lps = pd.lps.clone().expect("an LPS body");
        assert!(lps.skin, "the cap is in a contact");
        let n = pd.len();
        let mut reference = Vec::new();
        case.ghosts
            .extend_positions(&case.particles.position, &mut reference);
        // Two smooth displacement fields, not uniform strains.
        let field = |k: f64| -> Vec<nalgebra::Vector3<f64>> {
            case.particles
                .position
                .iter()
                .map(|x| {
                    1e-4 * nalgebra::Vector3::new(
                        (k * x.y + 1.0).sin(),
                        (k * x.z * x.x).cos(),
                        (k * x.x + 2.0 * x.y).sin(),
                    )
                })
                .collect()
        };
        let mut force = |u: &[nalgebra::Vector3<f64>]| {
            let real: Vec<_> = (0..n).map(|i| case.particles.position[i] + u[i]).collect();
            let mut pos = Vec::new();
            case.ghosts.extend_positions(&real, &mut pos);
            let mut f = vec![nalgebra::Vector3::zeros(); n];
            lps.forces(case, &pos, Stretch::Small(&reference), &mut f, |_, g, o| {
                *o = g
            });
            f
        };
        let (u, w) = (field(7.0), field(11.0));
        let (fu, fw) = (force(&u), force(&w));
        let dot = |a: &[nalgebra::Vector3<f64>], b: &[nalgebra::Vector3<f64>]| {
            a.iter().zip(b).map(|(x, y)| x.dot(y)).sum::<f64>()
        };
        let (wfu, ufw) = (dot(&w, &fu), dot(&u, &fw));
        let scale = dot(&u, &fu).abs().max(dot(&w, &fw).abs());
        eprintln!(
            "{influence}: w·f(u) {wfu:.6e}, u·f(w) {ufw:.6e}, u·f(u) {:.6e}",
            dot(&u, &fu)
        );
        assert!(
            (wfu - ufw).abs() < 1e-9 * scale,
            "{influence}: {wfu} against {ufw}"
        );
    }
}
