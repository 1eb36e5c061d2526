//! The validation scenes the studies share (`validate`, `sweep`, `stability`): the reference
//! problems of the paper's Sec. 3 as scene text, each with the theory it is compared with
//! (METHOD.md §7). A "case" here is one validation run ([`ValidationCase`]), not a PD case
//! ([`PdCase`](crate::case::PdCase)).
//!
//! Two sets of scenes:
//!
//! * **hertz** — loads scaled so that `a/R = 0.15`, where Hertz's small-strain theory holds;
//!   `E*` of a rigid plane; small (linearised) bond kinematics, the model Hertz describes;
//!   spacing fine enough that the contact radius spans 15 particles; a stiff penalty
//!   (`R = 100 m` in Eq. 23) so that penetration does not add compliance. Only what the
//!   contact needs is modelled: a quarter (sphere) or a half slice (roller, punch) by
//!   symmetry planes, and for the sphere and roller a shell sector around the contact (3a
//!   deep and wide for the sphere, 6a for the roller), loaded on its inner face (the full-body comparison is in docs/VALIDATION.md).
//! * **paper** — the paper's inputs as stated where they are consistent: R = 1 m, E = 1 GPa,
//!   ν = 0.25, Δ = 0.08 m, m = 3, the paper's loads (P = 1e8 N sphere, 2e8 N/m roller), the
//!   paper's bond kinematics (deformed bonds, Eq. 26) and penalty (R = Δ/2), compared with the
//!   theory twice: with the `E*` the paper's own theoretical values imply (two elastic bodies,
//!   5.333e8 Pa) and with a rigid plane's `E*`.
//!

use std::path::Path;

use crate::math::Vec3;
use crate::output::analysis::e_star_rigid;

/// The embedded sphere mesh.
pub const SPHERE_MESH: &[u8] = include_bytes!("../../meshes/sphere_r1_d008.msh");
/// Its file name.
pub const SPHERE_MESH_NAME: &str = "sphere_r1_d008.msh";

/// Young's modulus, Poisson's ratio and density of every validation body.
pub const YOUNGS: f64 = 1.0e9;
pub const POISSON: f64 = 0.25;
pub const DENSITY: f64 = 1000.0;
/// `E*` that the paper's theoretical values imply (Eq. 38 with two bodies of E and ν).
pub const PAPER_E_STAR: f64 = YOUNGS / (2.0 * (1.0 - POISSON * POISSON));

/// The three problems.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Problem {
    Sphere,
    Roller,
    Punch,
}

impl Problem {
    pub fn name(self) -> &'static str {
        match self {
            Problem::Sphere => "sphere",
            Problem::Roller => "roller",
            Problem::Punch => "punch",
        }
    }
}

/// The two sets, and a user's own mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Set {
    Paper,
    Hertz,
    /// The Hertz sphere or roller on a mesh the user gives (`validate --mesh`,
    /// [`user_mesh`](super::user_mesh)): not among the stored scenes of [`cases`].
    Mesh,
}

impl Set {
    pub fn name(self) -> &'static str {
        match self {
            Set::Paper => "paper",
            Set::Hertz => "hertz",
            Set::Mesh => "mesh",
        }
    }
}

/// What a run is compared with.
#[derive(Clone, Debug)]
pub enum Reference {
    /// Hertz sphere: total load on the whole sphere, sphere radius, `(label, E*)` variants.
    Sphere {
        load: f64,
        radius: f64,
        e_stars: Vec<(String, f64)>,
    },
    /// Hertz cylinder: load per unit length, radius, `(label, E*)` variants, and the
    /// cylinder's axis (the contact is a strip along it).
    Roller {
        load_per_length: f64,
        radius: f64,
        e_stars: Vec<(String, f64)>,
        axis: Vec3,
    },
    /// Hertz for two deformable spheres pressed together (METHOD.md §7): the load on the
    /// whole pair's contact, `R*` and `E*` of the pair; each deformable body's contact
    /// pressure is compared with it, one row per body, named after the body.
    SpherePair { load: f64, r_star: f64, e_star: f64 },
    /// Sadowsky punch: load per unit length, half-width.
    Punch {
        load_per_length: f64,
        half_width: f64,
    },
}

/// One validation run.
#[derive(Clone, Debug)]
pub struct ValidationCase {
    pub problem: Problem,
    pub set: Set,
    /// A name for the run's folder and the table ("hertz", "study-spacing-0.04", ...).
    pub label: String,
    pub spacing: f64,
    pub horizon_factor: f64,
    pub scene: String,
    pub reference: Reference,
}

impl ValidationCase {
    /// The same case solved by the static solver (`kind = "static"` in its `[solver]`).
    pub fn with_static_solver(mut self) -> Self {
        self.scene = static_solver(&self.scene);
        self
    }

    /// The same case with `skin_correction = false` on every deformable body (the balanced
    /// correction alone, [`crate::case::skin`]), run into `<problem>-<label>-noskin/`.
    pub fn without_skin_correction(mut self) -> Self {
        let mut out = String::with_capacity(self.scene.len() + 64);
        let mut lines = self.scene.lines().peekable();
        while let Some(line) = lines.next() {
            out.push_str(line);
            out.push('\n');
            if line.trim() != "[[body]]" {
                continue;
            }
            // The body's own keys run to the next table header that is not one of its
            // sub-tables.
            let mut block = Vec::new();
            while let Some(next) = lines.peek() {
                let t = next.trim_start();
                if t.starts_with('[') && !t.starts_with("[body.") {
                    break;
                }
                block.push(lines.next().unwrap_or_default());
            }
            if !block.iter().any(|l| l.replace(' ', "") == "kind=\"rigid\"") {
                out.push_str("skin_correction = false\n");
            }
            for l in block {
                out.push_str(l);
                out.push('\n');
            }
        }
        self.scene = out;
        self.label.push_str("-noskin");
        self
    }
}

fn material() -> String {
    format!("[body.material]\nyoungs_modulus = {YOUNGS:e}\npoisson_ratio = {POISSON}\ndensity = {DENSITY}\n")
}

/// The penalty of the "hertz" set: R = 100 m, so that the penetration stays far below the
/// approach and the penalty adds no compliance that Hertz does not have.
pub const STIFF_PENALTY: &str =
    "radius = 100.0              # a stiff penalty: penetration stays far below the approach";

/// The solver block of an ADR run.
pub const ADR_SOLVER: &str = "kind = \"adr\"\ntolerance = 1e-5\nmax_iterations = 100000";

/// Hertz sphere on a rigid plane, a/R = 0.15: a quarter of the shell sector of depth 3a.
pub fn hertz_sphere_case(a_over_dx: f64) -> ValidationCase {
    sphere_cap_case(
        0.15,
        0.15 / a_over_dx,
        3.0,
        ADR_SOLVER,
        STIFF_PENALTY,
        "hertz",
    )
}

/// A Hertz sphere (R = 1 m) on a rigid plane with contact radius `a`: a quarter of the shell
/// sector of depth 3a around the contact point, spacing `dx`, horizon `m Δ`, solved with the
/// `[solver]` block `solver` and the penalty lines `penalty` of the `[[contact]]` block.
pub fn sphere_cap_case(
    a: f64,
    dx: f64,
    m: f64,
    solver: &str,
    penalty: &str,
    label: &str,
) -> ValidationCase {
    let radius = 1.0;
    let e_star = e_star_rigid(YOUNGS, POISSON);
    let load = 4.0 * e_star * a * a * a / (3.0 * radius);
    let scene = format!(
        r#"# Hertz sphere: R = {radius} m, a/R = {ratio} against a rigid plane (pdcontact validate)
[solver]
{solver}

[output]
every = 1000000

[[body]]
name = "sphere"
# The shell sector of depth 3a around the contact point, radial layers.
generator = {{ shape = "sphere_cap", radius = {radius}, half_width = {hw}, depth = {depth}, spacing = {dx} }}
kinematics = "small"
horizon_factor = {m}
{mat}
[[body]]
name = "plane"
kind = "rigid"
generator = {{ shape = "plane", point = [0.0, 0.0, -{radius}], normal = [0.0, 0.0, 1.0], size = 2.0 }}

[[load]]
body = "sphere"
set = "top"                 # the inner face of the sector: the rest of the sphere's load path
force = [0.0, 0.0, -{quarter:e}]   # a quarter of P = {load:e} N

[[contact]]
slave = "sphere"
master = "plane"
{penalty}

[[symmetry]]
body = "sphere"
axis = "x"

[[symmetry]]
body = "sphere"
axis = "y"
"#,
        ratio = a / radius,
        hw = 3.0 * a,
        depth = 3.0 * a,
        mat = material(),
        quarter = load / 4.0,
    );
    ValidationCase {
        problem: Problem::Sphere,
        set: Set::Hertz,
        label: label.into(),
        spacing: dx,
        horizon_factor: m,
        scene,
        reference: Reference::Sphere {
            load,
            radius,
            e_stars: vec![("rigid plane".into(), e_star)],
        },
    }
}

/// A Hertz sphere (R = 1 m) pressed on a deformable block of the same material, contact
/// radius `a`: the quarter shell sector of [`sphere_cap_case`] on a quarter block 3a × 3a × 3a
/// fixed at its bottom, both with the symmetry planes x = 0 and y = 0, compared with Hertz for
/// two bodies (`E* = E/(2(1 − ν²))`). `contact` is the body of the `[[contact]]` block
/// (method and penalty lines); `lift` raises the sphere above the block's top face (the
/// short-range method holds the surfaces 1.35Δ apart: lift by that much so that the run starts
/// touching). The block is a finite half-space, so the figures are the method's and the
/// block's together: compare methods on this scene with each other.
pub fn sphere_on_block_case(
    a: f64,
    dx: f64,
    m: f64,
    solver: &str,
    contact: &str,
    lift: f64,
    label: &str,
) -> ValidationCase {
    let radius = 1.0;
    let e_star = PAPER_E_STAR;
    let load = 4.0 * e_star * a * a * a / (3.0 * radius);
    let scene = format!(
        r#"# Hertz sphere: R = {radius} m, a/R = {ratio} on a deformable block (pdcontact sweep)
[solver]
{solver}

[output]
every = 1000000

[[body]]
name = "sphere"
generator = {{ shape = "sphere_cap", radius = {radius}, half_width = {hw}, depth = {hw}, spacing = {dx}, center = [0.0, 0.0, {lift}] }}
kinematics = "small"
horizon_factor = {m}
{mat}
[[body]]
name = "block"
generator = {{ shape = "box", min = [0.0, 0.0, {bottom}], max = [{hw}, {hw}, -{radius}], spacing = {dx} }}
kinematics = "small"
horizon_factor = {m}
{mat}
[[load]]
body = "sphere"
set = "top"
force = [0.0, 0.0, -{quarter:e}]   # a quarter of P = {load:e} N

[[constraint]]
body = "block"
set = "bottom"
fix = ["x", "y", "z"]

[[contact]]
slave = "sphere"
master = "block"
{contact}

[[symmetry]]
body = "sphere"
axis = "x"

[[symmetry]]
body = "sphere"
axis = "y"

[[symmetry]]
body = "block"
axis = "x"

[[symmetry]]
body = "block"
axis = "y"
"#,
        ratio = a / radius,
        hw = 3.0 * a,
        bottom = -radius - 3.0 * a,
        mat = material(),
        quarter = load / 4.0,
    );
    ValidationCase {
        problem: Problem::Sphere,
        set: Set::Hertz,
        label: label.into(),
        spacing: dx,
        horizon_factor: m,
        scene,
        reference: Reference::Sphere {
            load,
            radius,
            e_stars: vec![("two bodies".into(), e_star)],
        },
    }
}

/// Hertz roller (plane strain) on a rigid plane, a/R = 0.15: a half of a slice of the shell
/// sector, with symmetry planes on both faces of the slice (plane strain) and at x = 0. The
/// sector is 6a deep and wide: in plane strain the stresses under a contact decay as 1/r, and
/// a sector 3a deep narrows the contact by about a point (docs/VALIDATION.md, "The skin
/// correction").
pub fn hertz_roller_case(a_over_dx: f64) -> ValidationCase {
    let (radius, a) = (1.0, 0.15);
    let e_star = e_star_rigid(YOUNGS, POISSON);
    let load_per_length = std::f64::consts::PI * e_star * a * a / (4.0 * radius);
    let dx = a / a_over_dx;
    // Thick enough for a particle's neighbourhood: at least a horizon and a half spacing.
    let thickness = (4.0 * dx).max(dx * (3.0 + 0.5) * 1.05);
    let scene = format!(
        r#"# Hertz roller (plane strain): R = {radius} m, a/R = 0.15 against a rigid plane
[solver]
kind = "adr"
tolerance = 1e-5
max_iterations = 100000

[output]
every = 1000000

[[body]]
name = "roller"
generator = {{ shape = "cylinder_cap", radius = {radius}, half_width = {hw}, depth = {depth}, length = {thickness}, spacing = {dx} }}
kinematics = "small"
horizon_factor = 3.0
{mat}
[[body]]
name = "plane"
kind = "rigid"
generator = {{ shape = "plane", point = [0.0, {mid}, -{radius}], normal = [0.0, 0.0, 1.0], size = 2.0 }}

[[load]]
body = "roller"
set = "top"
force = [0.0, 0.0, -{half:e}]   # P = {load_per_length:e} N/m over the slice, half by symmetry

[[contact]]
slave = "roller"
master = "plane"
radius = 100.0

[[symmetry]]
body = "roller"
axis = "x"

[[symmetry]]           # plane strain: mirror images on both faces of the slice
body = "roller"
axis = "y"
at = 0.0

[[symmetry]]
body = "roller"
axis = "y"
at = {thickness}
keep = "negative"
"#,
        hw = 6.0 * a,
        depth = 6.0 * a,
        mid = 0.5 * thickness,
        mat = material(),
        half = load_per_length * thickness / 2.0,
    );
    ValidationCase {
        problem: Problem::Roller,
        set: Set::Hertz,
        label: "hertz".into(),
        spacing: dx,
        horizon_factor: 3.0,
        scene,
        reference: Reference::Roller {
            load_per_length,
            radius,
            e_stars: vec![("rigid plane".into(), e_star)],
            axis: Vec3::y(),
        },
    }
}

/// Rigid flat punch of half-width a on an elastic block (plane strain), half model.
fn punch_case(
    set: Set,
    a: f64,
    dx: f64,
    load_per_length: f64,
    kinematics: &str,
    penalty: &str,
) -> ValidationCase {
    let half = 4.0 * a;
    let depth = 4.0 * a;
    let thickness = (4.0 * dx).max(dx * 3.5 * 1.05);
    let scene = format!(
        r#"# Rigid flat punch, half-width a = {a} m, on an elastic block (plane strain)
[solver]
kind = "adr"
tolerance = 1e-5
max_iterations = 200000

[output]
every = 1000000

[[body]]
name = "block"
generator = {{ shape = "box", min = [0.0, 0.0, -{depth}], max = [{half}, {thickness}, 0.0], spacing = {dx} }}
kinematics = "{kinematics}"
horizon_factor = 3.0
{mat}
[[body]]
name = "punch"
kind = "rigid"
generator = {{ shape = "box", min = [-{a}, -{over}, 0.0], max = [{a}, {over_t}, {a}], spacing = {a} }}
motion = "free"
free_axis = [0.0, 0.0, 1.0]

[[load]]
body = "punch"
force = [0.0, 0.0, -{half_load:e}]   # P = {load_per_length:e} N/m over the slice, half by symmetry

[[constraint]]
body = "block"
set = "bottom"
fix = ["x", "y", "z"]

[[contact]]
slave = "block"
master = "punch"
{penalty}

[[symmetry]]
body = "block"
axis = "x"

[[symmetry]]
body = "block"
axis = "y"
at = 0.0

[[symmetry]]
body = "block"
axis = "y"
at = {thickness}
keep = "negative"
"#,
        over = thickness,
        over_t = 2.0 * thickness,
        mat = material(),
        half_load = load_per_length * thickness / 2.0,
    );
    ValidationCase {
        problem: Problem::Punch,
        set,
        label: set.name().into(),
        spacing: dx,
        horizon_factor: 3.0,
        scene,
        reference: Reference::Punch {
            load_per_length,
            half_width: a,
        },
    }
}

/// Hertz-set punch: a = 0.5 m, a/Δ = `a_over_dx`, mean pressure 0.05 E.
pub fn hertz_punch_case(a_over_dx: f64) -> ValidationCase {
    punch_at(a_over_dx, 0.05)
}

/// The Hertz set's punch scene (a = 0.5 m, small kinematics, stiff penalty) at a/Δ =
/// `a_over_dx` and mean pressure `mean_pressure` × E.
pub fn punch_at(a_over_dx: f64, mean_pressure: f64) -> ValidationCase {
    let a = 0.5;
    punch_case(
        Set::Hertz,
        a,
        a / a_over_dx,
        mean_pressure * YOUNGS * 2.0 * a,
        "small",
        "radius = 100.0",
    )
}

/// The paper's sphere: P = 1e8 N, the stored gmsh sphere (Δ = 0.083 m) cut to a quarter.
pub fn paper_sphere_case(mesh: &Path) -> ValidationCase {
    let load = 1e8;
    let scene = format!(
        r#"# The paper's sphere: R = 1 m, P = 1e8 N, Δ ≈ 0.08 m, m = 3 (pdcontact validate)
[solver]
kind = "adr"
tolerance = 1e-5
max_iterations = 200000

[output]
every = 1000000

[[body]]
name = "sphere"
mesh = "{mesh}"
horizon_factor = 3.0
{mat}
[[body]]
name = "plane"
kind = "rigid"
generator = {{ shape = "plane", point = [0.0, 0.0, -1.0], normal = [0.0, 0.0, 1.0], size = 3.0 }}

[[load]]
body = "sphere"
force = [0.0, 0.0, -{quarter:e}]   # a quarter of P = 1e8 N, spread by volume

[[contact]]
slave = "sphere"
master = "plane"

[[symmetry]]
body = "sphere"
axis = "x"

[[symmetry]]
body = "sphere"
axis = "y"
"#,
        mesh = mesh.display(),
        mat = material(),
        quarter = load / 4.0,
    );
    ValidationCase {
        problem: Problem::Sphere,
        set: Set::Paper,
        label: "paper".into(),
        spacing: 0.0829,
        horizon_factor: 3.0,
        scene,
        reference: Reference::Sphere {
            load,
            radius: 1.0,
            e_stars: vec![
                ("paper E*".into(), PAPER_E_STAR),
                ("rigid plane".into(), e_star_rigid(YOUNGS, POISSON)),
            ],
        },
    }
}

/// The paper's roller: R = 1 m, length 4 m, 2e8 N/m, Δ = 0.08 m: a quarter (half length,
/// half width) of the whole roller.
pub fn paper_roller_case() -> ValidationCase {
    let load_per_length = 2e8;
    let dx = 0.08;
    let scene = format!(
        r#"# The paper's roller: R = 1 m, length 4 m, P = 2e8 N/m, Δ = 0.08 m, m = 3
[solver]
kind = "adr"
tolerance = 1e-5
max_iterations = 200000

[output]
every = 1000000

[[body]]
name = "roller"
generator = {{ shape = "cylinder", radius = 1.0, length = 4.0, spacing = {dx} }}
horizon_factor = 3.0
{mat}
[[body]]
name = "plane"
kind = "rigid"
generator = {{ shape = "plane", point = [0.0, 0.0, -1.0], normal = [0.0, 0.0, 1.0], size = 5.0 }}

[[load]]
body = "roller"
force = [0.0, 0.0, -{quarter:e}]   # a quarter of 2e8 N/m x 4 m

[[contact]]
slave = "roller"
master = "plane"

[[symmetry]]
body = "roller"
axis = "x"

[[symmetry]]
body = "roller"
axis = "y"
"#,
        mat = material(),
        quarter = load_per_length * 4.0 / 4.0,
    );
    ValidationCase {
        problem: Problem::Roller,
        set: Set::Paper,
        label: "paper".into(),
        spacing: dx,
        horizon_factor: 3.0,
        scene,
        reference: Reference::Roller {
            load_per_length,
            radius: 1.0,
            e_stars: vec![
                ("paper E*".into(), PAPER_E_STAR),
                ("rigid plane".into(), e_star_rigid(YOUNGS, POISSON)),
            ],
            axis: Vec3::y(),
        },
    }
}

/// The paper's punch: P = 8e8 N/m, Δ = 0.08 m. The paper gives the punch's "length" as 5 m
/// and no width; read as a base 5 m wide (a = 2.5 m), which puts its mean pressure (1.6e8 Pa)
/// beside the sphere's and the roller's. With the default penalty radius R = Δ/2 the
/// particles under the punch's edges, where Sadowsky's pressure is singular, are pushed
/// through the contact window (a missed contact); the penalty is stiffened with R = 100 m,
/// as in the "hertz" set. Bonds are linear ("small"), the paper's "linear elastic bonds": with
/// finite kinematics the block's surface layer under the punch's edge is driven through the
/// layers beneath it at this load (see docs/VALIDATION.md).
pub fn paper_punch_case() -> ValidationCase {
    punch_case(Set::Paper, 2.5, 0.08, 8e8, "small", "radius = 100.0")
}

/// The cases of a selection.
pub fn cases(problems: &[Problem], sets: &[Set], sphere_mesh: &Path) -> Vec<ValidationCase> {
    let mut out = Vec::new();
    for &set in sets {
        for &p in problems {
            out.push(match (set, p) {
                (Set::Hertz, Problem::Sphere) => hertz_sphere_case(15.0),
                (Set::Hertz, Problem::Roller) => hertz_roller_case(15.0),
                (Set::Hertz, Problem::Punch) => hertz_punch_case(20.0),
                (Set::Paper, Problem::Sphere) => paper_sphere_case(sphere_mesh),
                (Set::Paper, Problem::Roller) => paper_roller_case(),
                (Set::Paper, Problem::Punch) => paper_punch_case(),
                (Set::Mesh, _) => continue,
            });
        }
    }
    out
}

/// Contact radius of the study sphere: a/R = 0.3, so that the coarsest spacing (0.12 m)
/// still puts two and a half particles across the contact radius and the finest (0.04 m)
/// seven and a half.
pub const STUDY_CONTACT_RADIUS: f64 = 0.3;
/// Damping rate of the explicit study runs (1/s): about a third of critical for the sector's
/// lowest mode, so that the run settles within [`STUDY_END_TIME`].
pub const STUDY_DAMPING: f64 = 1500.0;
/// Simulated time of the explicit study runs (s): the velocities have decayed by
/// e^{−c t} = e^{−30} by then.
pub const STUDY_END_TIME: f64 = 0.02;

/// `scene` with its `[solver]`'s `kind = "adr"` turned into `kind = "static"` (the
/// static solver, [`crate::solver::newton`]); the other keys stay: its tolerance is ADR's,
/// and its `max_iterations`, far above what Newton takes, only caps it.
pub fn static_solver(scene: &str) -> String {
    let mut out = String::with_capacity(scene.len() + 16);
    let mut done = false;
    for line in scene.lines() {
        if !done && line.trim_start().starts_with("kind = \"adr\"") {
            out.push_str(
                "kind = \"static\"            # quasi-static: Newton-Raphson (the static solver)",
            );
            done = true;
        } else {
            out.push_str(line);
        }
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{BodyKind, Scene};

    /// `validate --solver static`: every stored scene parses with the static solver and
    /// keeps everything else (tolerance, bodies, contacts).
    #[test]
    fn static_solver_changes_the_solver_kind_only() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let mesh = root.join("meshes").join(SPHERE_MESH_NAME);
        let problems = [Problem::Sphere, Problem::Roller, Problem::Punch];
        for case in cases(&problems, &[Set::Paper, Set::Hertz], &mesh) {
            let plain = Scene::parse(&case.scene, "plain", root).expect("scene");
            let label = case.label.clone();
            let newton = case.with_static_solver();
            assert_eq!(newton.label, label);
            let parsed = Scene::parse(&newton.scene, "static", root).expect("static scene");
            assert_eq!(plain.solver.kind, crate::scene::SolverKind::Adr);
            assert_eq!(parsed.solver.kind, crate::scene::SolverKind::Static);
            assert_eq!(parsed.solver.tolerance, plain.solver.tolerance);
            assert_eq!(parsed.bodies.len(), plain.bodies.len());
            assert_eq!(parsed.contacts.len(), plain.contacts.len());
        }
    }

    /// `validate --skin-correction false`: every stored scene still parses and checks, with
    /// the key on each deformable body and on no rigid one, and runs into its own folder.
    #[test]
    fn no_skin_correction_marks_the_deformable_bodies() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let mesh = root.join("meshes").join(SPHERE_MESH_NAME);
        let problems = [Problem::Sphere, Problem::Roller, Problem::Punch];
        let all = cases(&problems, &[Set::Paper, Set::Hertz], &mesh);
        assert_eq!(all.len(), 6);
        for case in all {
            let plain = Scene::parse(&case.scene, "plain", root).expect("scene");
            let label = case.label.clone();
            let skin = case.without_skin_correction();
            assert_eq!(skin.label, format!("{label}-noskin"));
            let marked = Scene::parse(&skin.scene, "skin", root).expect("scene with the key");
            assert_eq!(plain.bodies.len(), marked.bodies.len());
            let mut deformable = 0;
            for (p, m) in plain.bodies.iter().zip(&marked.bodies) {
                assert_eq!(p.skin_correction, None);
                let want = (m.kind == BodyKind::Deformable).then_some(false);
                deformable += usize::from(want.is_some());
                assert_eq!(m.skin_correction, want, "{}: {}", skin.label, m.name);
            }
            assert!(deformable >= 1);
        }
    }
}
