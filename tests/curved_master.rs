//! A sphere pressed by a rigid ball as curved as itself, against the same sphere on a rigid
//! plane (docs/VALIDATION.md, "Two deformable bodies", "A master more curved than the
//! slave"): the gmsh tet4 sphere of `meshes/two_spheres_lower_h006.geo` (R = 1 m, h = 0.06 m)
//! under the rigid ball of `meshes/rigid_ball_r1_h006.geo` (RB = 1 m) or a plane, loaded so
//! that Hertz's contact radius is a = 0.3 m either way (R* = 0.5 m or 1 m).
//!
//! Hertz's theory takes the pressure along the axis; the contact pushes along the master's
//! normal, which on the ball turns by up to a/RB = 0.3 rad within the contact. CalculiX on
//! the same two scenes (axisymmetric CAX8, a/20, small strain, contact in the displaced
//! configuration: `python3 -m fe_reference --case cax8-axisymmetric:0.05 --contact-radius 0.3
//! --loading equator [--ball 1]`) finds the ball's pressure more peaked than Hertz's where the
//! plane's is Hertz's: centre +6.2 % against +0.05 %, fitted radius −1.8 % against −0.9 %.
//! pdcontact must see the same turn: a build that pushed every contact along the axis read the
//! ball's pressure flatter than the plane's on the finer meshes of that section.
//!
//! And the other way round: a flat block the slave of a rigid ball where Hertz holds
//! (a/R = 0.1), its pressure Hertz's within the bounds on gmsh's graded tet4.

mod common;

use pdcontact::output::analysis::{contact_patch, elliptic_accuracy, hertz_sphere};

const YOUNGS: f64 = 1e9;
const POISSON: f64 = 0.25;
const A: f64 = 0.3;

/// A stored mesh's path as a TOML string.
fn mesh(name: &str) -> String {
    format!(
        "{:?}",
        common::repo(&format!("meshes/{name}"))
            .display()
            .to_string()
    )
}

/// The deformable body of `slave_mesh` (a quarter by the symmetry planes x = 0, y = 0 and
/// z = `bottom`) pressed by a rigid `master` surface (its `[[body]]` keys), which carries
/// `load` on the whole body (a quarter here) and is free along z; penalty `radius`. Runs it,
/// checks that it settles with no missed contact and that the slave carries the load, and
/// returns the slave's contact patch.
fn pressed(
    name: &str,
    master: &str,
    slave_mesh: &str,
    bottom: f64,
    radius: f64,
    load: f64,
) -> pdcontact::output::analysis::ContactPatch {
    let text = format!(
        r#"[solver]
kind = "adr"
tolerance = 1e-4
max_iterations = 20000
[output]
every = 1000000
[[body]]
name = "ball"
kind = "rigid"
{master}
motion = "free"
free_axis = [0.0, 0.0, 1.0]
[[body]]
name = "slave"
mesh = {slave}
kinematics = "small"
[body.material]
youngs_modulus = {YOUNGS:e}
poisson_ratio = {POISSON}
density = 1000.0
[[load]]
body = "ball"
force = [0.0, 0.0, {quarter:e}]
[[contact]]
slave = "slave"
master = "ball"
radius = {radius}
[[symmetry]]
body = "slave"
axis = "x"
[[symmetry]]
body = "slave"
axis = "y"
[[symmetry]]
body = "slave"
axis = "z"
at = {bottom}
keep = "positive"
"#,
        slave = mesh(slave_mesh),
        quarter = -load / 4.0,
    );
    let (model, summary) = common::try_run_text(&text, &format!("curved-{name}"))
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    assert!(summary.converged, "{name}: residual {}", summary.residual);
    assert_eq!(summary.missed_contacts, 0, "{name}");
    let slave = model
        .bodies
        .iter()
        .position(|b| b.as_pd().is_some())
        .expect("the slave");
    let patch = contact_patch(&model, slave, None).expect("a contact patch");
    // The slave carries the load.
    assert!(
        (patch.force.z.abs() / (load / 4.0) - 1.0).abs() < 1e-3,
        "{name}: contact force {} against {}",
        patch.force.z,
        load / 4.0
    );
    patch
}

/// (fitted peak / p0 − 1, fitted radius / a − 1, MRE) of the sphere pressed by `master`
/// (`None`: the plane; `Some(RB)`: the stored ball).
fn pressed_by(ball: Option<f64>) -> (f64, f64, f64) {
    let (surface, r_star, name) = match ball {
        None => (
            r#"generator = { shape = "plane", point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, -1.0], size = 3.0 }"#.to_string(),
            1.0,
            "plane",
        ),
        Some(rb) => (
            format!("mesh = {}", mesh("rigid_ball_r1_h006.msh")),
            1.0 / (1.0 + 1.0 / rb),
            "ball",
        ),
    };
    let e_star = YOUNGS / (1.0 - POISSON * POISSON);
    // Hertz: a³ = 3PR*/(4E*).
    let load = 4.0 * e_star * A.powi(3) / (3.0 * r_star);
    let patch = pressed(
        name,
        &surface,
        "two_spheres_lower_h006.msh",
        -1.0,
        2290.0,
        load,
    );
    let (a, p0) = hertz_sphere(load, r_star, e_star);
    assert!((a - A).abs() < 1e-12);
    let acc = elliptic_accuracy(&patch, a, p0);
    (acc.fitted_peak / p0 - 1.0, acc.radius_error, acc.mre)
}

/// Measured (the fit `validate` makes): the plane peak +2.1 %, radius −0.89 %, MRE 2.9 %; the
/// ball peak +4.6 %, radius −1.06 %, MRE 4.3 %: more peaked by 2.5 points and narrower by 0.17,
/// where CalculiX's pressure is higher at the centre by 6.2 points and narrower by 0.95.
#[test]
fn a_ball_as_curved_as_the_sphere_peaks_its_pressure_as_calculix_does() {
    let (plane_peak, plane_radius, plane_mre) = pressed_by(None);
    let (ball_peak, ball_radius, ball_mre) = pressed_by(Some(1.0));
    // On the plane the mesh meets Hertz as gmsh's tet4 spheres do at a/Δ = 5.
    assert!(
        plane_mre < 0.035 && plane_radius.abs() < 0.02,
        "plane: MRE {plane_mre}, radius {plane_radius}"
    );
    // Under the ball the pressure is more peaked, by an amount of CalculiX's order (pushed
    // along the axis it came out flatter than the plane's), and the contact no wider.
    let peaked = ball_peak - plane_peak;
    assert!(
        (0.01..0.10).contains(&peaked),
        "peak: ball {ball_peak}, plane {plane_peak}"
    );
    assert!(
        ball_radius < plane_radius + 0.005,
        "radius: ball {ball_radius}, plane {plane_radius}"
    );
    assert!(
        ball_mre > plane_mre,
        "MRE: ball {ball_mre}, plane {plane_mre}"
    );
}

/// A flat block pressed by a rigid ball where Hertz holds (a = 0.1 m, a/R = 0.1): the block's
/// own surface particles the slaves, the ball's facets the master (docs/VALIDATION.md, "A
/// sphere pressed into a block", "Where Hertz holds"). The stored block
/// (`meshes/block_graded_tet4_h002.geo`, gmsh's tet4 graded to 0.02 m at the contact, a/Δ
/// about 5) under `meshes/rigid_ball_cap_r1_h0015.geo`. Measured: MRE 2.67 %, radius
/// +0.78 %, fitted peak +1.4 %; without the skin correction 4.25 % and
/// +7.69 %: on a flat face as on a sphere, the skin correction is what brings the contact
/// within the bounds.
#[test]
fn a_flat_block_under_a_rigid_ball_meets_hertz_where_hertz_holds() {
    let a = 0.1;
    let e_star = YOUNGS / (1.0 - POISSON * POISSON);
    let load = 4.0 * e_star * a * a * a / 3.0;
    let patch = pressed(
        "flat-block",
        &format!("mesh = {}", mesh("rigid_ball_cap_r1_h0015.msh")),
        "block_graded_tet4_h002.msh",
        -2.0,
        4492.0,
        load,
    );
    let (ha, p0) = hertz_sphere(load, 1.0, e_star);
    assert!((ha - a).abs() < 1e-12);
    let acc = elliptic_accuracy(&patch, ha, p0);
    println!(
        "flat block under a ball: MRE {:.4}, radius {:+.4}, fitted peak {:+.4}",
        acc.mre,
        acc.radius_error,
        acc.fitted_peak / p0 - 1.0
    );
    assert!(
        acc.mre < 0.03
            && acc.radius_error.abs() < 0.03
            && (acc.fitted_peak / p0 - 1.0).abs() < 0.05,
        "MRE {}, radius {}, fitted peak {}",
        acc.mre,
        acc.radius_error,
        acc.fitted_peak / p0 - 1.0
    );
}
