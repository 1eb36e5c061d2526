//! `pdcontact validate --mesh FILE`: the Hertz sphere or roller on a user's own mesh, so that
//! what the mesh gives against theory can be seen before its results are trusted (METHOD.md §7).
//!
//! The shape is measured from the mesh's nodes, not assumed:
//!
//! * **sphere**: centre at the bounding box's centre, radius half its largest extent; the
//!   three extents must agree and every boundary node must lie on the sphere, within
//!   [`SHAPE_TOLERANCE`].
//! * **roller** (a circular cylinder): the axis is x, y or z, the one along which the mesh is a
//!   circle of constant radius with flat end faces (tried in the order y, x, z); radius half
//!   the larger of the two cross extents. The end faces become symmetry planes (mirror
//!   images, METHOD.md §6), so the body is an infinitely long roller in plane strain, as the
//!   structured roller slice of the "hertz" set ([`hertz_roller_case`]); any length works, a
//!   slice a few spacings long is the cheapest.
//!
//! The scene is the whole-sphere Hertz scene of docs/VALIDATION.md (METHOD.md §7): E = 1 GPa, ν = 0.25, small bond
//! kinematics, ADR, a stiff penalty (radius 10⁴ R), a rigid plane just touching the lowest
//! node, and the load spread over the body by volume so that Hertz's contact radius (sphere)
//! or half-width (roller) is `a = 0.3 R`. The body is pressed along −z, or along −x when a
//! roller's axis is z. The scene is written into the output folder so that it can be run
//! again with `pdcontact run`; the run, its frames, summary and chart are those of any
//! validation case ([`run_case`]).
//!
//! [`hertz_roller_case`]: super::scenarios::hertz_roller_case

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::case::discretize::{discretize, Discretization};
use crate::case::{SecondOrder, DEFAULT_HORIZON_FACTOR};
use crate::error::{Error, Result};
use crate::importers::Format;
use crate::math::Vec3;
use crate::output::analysis::e_star_rigid;
use crate::scene::InfluenceFunction;
use crate::studies::comparison::{run_case, ValidationRow};
use crate::studies::scenarios::{
    Problem, Reference, Set, ValidationCase, DENSITY, POISSON, YOUNGS,
};

mod partner;
mod report;
mod shape;
use partner::{copy_partner, plane_pins};
use report::rows_named;
pub use report::MeshValidation;
pub use shape::{measure, MeshShape, SHAPE_TOLERANCE};

/// Hertz contact radius (sphere) or half-width (roller) over the body's radius by default, as
/// in the whole-sphere scene of docs/VALIDATION.md.
pub const CONTACT_RATIO: f64 = 0.3;
/// The largest contact ratio accepted: past it the contact is no longer small against the
/// body, which Hertz theory assumes (METHOD.md §7).
pub const MAX_CONTACT_RATIO: f64 = 0.5;
/// Below this many particle spacings across the contact radius the figures are coarse.
pub const MIN_CONTACT_SPACINGS: f64 = 5.0;
/// The most particles [`Remedy`]'s run may have (the mesh's count times eight): about four
/// minutes on two cores.
pub const REMEDY_MAX_PARTICLES: usize = 400_000;
/// Penalty radius of the contact over the body's radius: 10⁴ m on R = 1 m, scaled with the
/// body. At a/Δ = 4.6 a particle at the peak sinks 0.3 % of Hertz's approach
/// ([`crate::contact::estimate::PENALTY_TARGET`]); the 100 R of the other validation scenes let
/// it sink 1.4 % there, which widened the contact by 1.5 points (docs/VALIDATION.md).
const PENALTY_RATIO: f64 = 1e4;

/// A TOML number that always reads back as a float (`0.0`, `1e-5`, `-1.0`).
fn num(x: f64) -> String {
    format!("{x:?}")
}

fn vector(v: [f64; 3]) -> String {
    format!("[{}, {}, {}]", num(v[0]), num(v[1]), num(v[2]))
}

/// What a user may set on the body of `validate --mesh`'s scene; the defaults are the command
/// line's (`run`'s, but the static solver).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyChoices {
    /// The horizon factor m (METHOD.md §2: δ = mΔ, 3 by default).
    pub horizon_factor: Option<f64>,
    /// Which nodes of a second-order mesh become particles.
    pub second_order: SecondOrder,
    /// Levels of uniform refinement ([`crate::case::refine`]).
    pub refine: u32,
    /// The skin correction ([`crate::case::skin`]; on, as in `run`, unless the user turns it
    /// off).
    pub skin_correction: bool,
    /// Solve with the static solver (`kind = "static"`) instead of ADR.
    pub static_solver: bool,
    /// Poisson's ratio of a linear peridynamic solid (`model = "lps"`); `None`: the
    /// bond-based model at ν = 1/4.
    pub poisson: Option<f64>,
    /// The LPS's influence function (`None`: the default).
    pub influence: Option<InfluenceFunction>,
    /// What the body is pressed on: a rigid plane, or a copy of itself.
    pub partner: Partner,
    /// Where the contact spans fewer than [`MIN_CONTACT_SPACINGS`] spacings, also run the body
    /// with the finer particles that the mesh allows ([`Remedy`]), as a second row: what the
    /// mesh gives as it is, and what one key in the scene gives. The command line sets it
    /// when the user chose none of the horizon, `refine` and `second_order`.
    pub compare: bool,
}

/// From this Poisson's ratio up, the contact's figures on tet and hex meshes are known to miss
/// Hertz's bounds at a/Δ of 5-7 (docs/VALIDATION.md, "Any Poisson's ratio"): measured at 0.3
/// within them on every gmsh mesh, at 0.4 outside them on every one (within them from
/// [`HIGH_POISSON_SPACINGS`]).
pub const HIGH_POISSON: f64 = 0.35;

/// The spacings across the contact from which the skin-corrected contact was within Hertz's
/// bounds at ν = 0.4 on every kind of gmsh mesh measured: tet4 at a/Δ = 7.5, tet10 (every
/// node a particle) at 7.0, tets split into hexes at 8.5; at 5.5-6.6 none was
/// (docs/VALIDATION.md, "Any Poisson's ratio").
pub const HIGH_POISSON_SPACINGS: f64 = 7.5;

/// The largest Poisson's ratio at which the contact was measured against Hertz.
const HIGH_POISSON_MEASURED: f64 = 0.4;

/// What `validate` says of a contact at Poisson's ratio `nu` ≥ [`HIGH_POISSON`] with
/// `spacings` (a/Δ) across it: which way the measured figures err with and without the
/// skin correction, and from what spacing they held; nothing where the contact spans the
/// spacings at which they held (a sphere with the skin correction, up to the ν measured).
fn high_poisson_warning(nu: f64, skin: bool, spacings: f64, sphere: bool) -> Option<String> {
    if sphere && skin && nu <= HIGH_POISSON_MEASURED + 1e-9 && spacings >= HIGH_POISSON_SPACINGS {
        return None;
    }
    let held = if sphere {
        format!("at ν = 0.4 a sphere's held from a/Δ = {HIGH_POISSON_SPACINGS} (tet4 7.5, tet10 with every node 7.0, hexes 8.5), and this contact spans {spacings:.1}")
    } else {
        "a roller's stayed narrow at a/Δ = 9-9.6 (radius 3.2-3.8 % short), and met them from a/Δ = 7 with `--influence position-aware --skin-correction false`".to_string()
    };
    let what = if skin {
        format!("with the skin correction the contact comes out narrow and high: at ν = 0.4 on gmsh-default tet4, tet10 and tets-split-into-hexes spheres at a/Δ = 5.5-7, radius 2.5-4.8 % short, MRE 2.2-5.0 %, peak up to +9 %; without it (`--skin-correction false --influence position-aware`) wide on tets (radius +3-4 %); {held}")
    } else {
        "without the skin correction the contact comes out wide on tets: at ν = 0.4 on gmsh-default tet4 spheres at a/Δ = 5.5-6, radius +3-4 % (`--influence position-aware`); with it, narrow (radius 2.5-4.8 % short)".to_string()
    };
    Some(format!(
        "ν = {nu} is {HIGH_POISSON} or more, where the contact misses Hertz's bounds on meshes measured so far: {what}; finer meshes err less (docs/VALIDATION.md, \"Any Poisson's ratio\")"
    ))
}

impl Default for BodyChoices {
    fn default() -> Self {
        BodyChoices {
            horizon_factor: None,
            second_order: SecondOrder::default(),
            refine: 0,
            skin_correction: true,
            static_solver: true,
            poisson: None,
            influence: None,
            partner: Partner::Plane,
            compare: false,
        }
    }
}

/// What `validate --mesh` presses the body on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub enum Partner {
    /// A rigid plane touching its lowest node (Hertz with `E* = E/(1 − ν²)`).
    #[default]
    Plane,
    /// A copy of the mesh, turned half a turn about a line through the contact point across
    /// the pressing direction, so that it touches the body there from the other side: two
    /// deformable bodies meshed alike (Hertz for two identical spheres, METHOD.md §7:
    /// `R* = R/2`, `E* = E/(2(1 − ν²))`, the same contact radius under the same load). Each is
    /// loaded by volume towards the other, two passes, and held by pins where the
    /// axisymmetric solution is at rest (the particles nearest them, `nearest` in
    /// `[[constraint]]`): seven on its axis held across it, and four round its centre held
    /// across their radius; frictionless spheres pressed together would otherwise slide off
    /// each other, tilt, or spin about the axis. Along the pressing axis nothing holds the
    /// pair: its loads are equal and opposite, so the pins carry next to nothing.
    Copy,
}

/// The finer particles `validate --mesh` runs beside the mesh's own when the contact is
/// poorly resolved ([`BodyChoices::compare`]).
#[derive(Clone, Debug, Serialize)]
pub struct Remedy {
    /// The scene key that gives it: `refine = 1` or `second_order = "all-nodes"`.
    pub key: String,
    /// The particle spacing at the contact with it, m.
    pub spacing: f64,
    /// `a/Δ` with it.
    pub contact_spacings: f64,
    /// Its scene.
    pub scene: PathBuf,
}

/// The validation case of `shape`, measured on the mesh at `mesh` (an absolute path), with
/// the particle spacing `spacing` (for the table), loaded so that Hertz's contact radius (or
/// half-width) is `ratio` times the body's radius; `body` holds what the user set on the body.
pub fn mesh_case(
    mesh: &Path,
    format: Option<Format>,
    shape: &MeshShape,
    spacing: f64,
    ratio: f64,
    body: &BodyChoices,
) -> ValidationCase {
    let horizon_factor = body.horizon_factor;
    let radius = shape.radius;
    let a = ratio * radius;
    let poisson = body.poisson.unwrap_or(POISSON);
    let e_star = e_star_rigid(YOUNGS, poisson);
    let mut unit = [0.0; 3];
    unit[shape.press] = 1.0;
    let mut point = shape.centre;
    point[shape.press] = shape.lowest;
    let (problem, name, load, total, size, reference) = match (shape.axis_index, shape.ends) {
        (Some(k), Some([y0, y1])) => {
            // Eq. 39 (METHOD.md §7): a² = 4PR/(πE*) for the load P per unit length.
            let per_length = std::f64::consts::PI * e_star * a * a / (4.0 * radius);
            let mut axis = Vec3::zeros();
            axis[k] = 1.0;
            (
                Problem::Roller,
                "roller",
                per_length,
                per_length * (y1 - y0),
                3.0 * radius.max(y1 - y0),
                Reference::Roller {
                    load_per_length: per_length,
                    radius,
                    e_stars: vec![("rigid plane".into(), e_star)],
                    axis,
                },
            )
        }
        _ => {
            // Eq. 34: a³ = 3PR/(4E*).
            let load = 4.0 * e_star * a * a * a / (3.0 * radius);
            (
                Problem::Sphere,
                "sphere",
                load,
                load,
                3.0 * radius,
                Reference::Sphere {
                    load,
                    radius,
                    e_stars: vec![("rigid plane".into(), e_star)],
                },
            )
        }
    };
    let mut force = [0.0; 3];
    force[shape.press] = -total;
    let quoted = toml::Value::String(mesh.display().to_string()).to_string();
    let format_line = format
        .map(|f| format!("format = \"{}\"\n", f.name()))
        .unwrap_or_default();
    let horizon_line = horizon_factor
        .map(|m| {
            format!(
                "horizon_factor = {}          # δ = mΔ (3 by default)\n",
                num(m)
            )
        })
        .unwrap_or_default();
    let second_order_line = match body.second_order {
        SecondOrder::Corners => String::new(),
        SecondOrder::AllNodes => {
            "second_order = \"all-nodes\"     # every node of a tet10 or hex20 a particle\n"
                .to_string()
        }
    };
    let refine_line = match body.refine {
        0 => String::new(),
        n => format!(
            "refine = {n}                    # each tet and hex cut into eight at its edges' midpoints\n"
        ),
    };
    let skin_line = if body.skin_correction {
        ""
    } else {
        "skin_correction = false         # the balanced correction alone: a softer surface row (docs/VALIDATION.md)\n"
    };
    let model_line = match (body.poisson, body.influence) {
        (None, _) => String::new(),
        (Some(_), influence) => format!(
            "model = \"lps\"               # the linear peridynamic solid: any Poisson's ratio\n{}",
            match influence {
                Some(InfluenceFunction::PositionAware) =>
                    "influence_function = \"position-aware\"\n",
                Some(InfluenceFunction::Constant) => "influence_function = \"constant\"\n",
                None => "",
            }
        ),
    };
    let load_note = match problem {
        Problem::Roller => format!("P = {} N/m over the length", num(load)),
        _ => format!("P = {} N", num(load)),
    };
    let mut scene = format!(
        r#"# Hertz {name} on a user's mesh against a rigid plane (pdcontact validate --mesh): R = {r} m
# measured from the mesh, load such that a = {ratio} R. Run it again with: pdcontact run scene.toml
[solver]
kind = "adr"               # quasi-static: adaptive dynamic relaxation
tolerance = 1e-4
max_iterations = 100000

[output]
every = 1000000

[[body]]
name = "{name}"
mesh = {quoted}
{format_line}{horizon_line}{second_order_line}{refine_line}{skin_line}kinematics = "small"         # Hertz theory is small-strain: compare like with like
[body.material]
youngs_modulus = {e:e}
poisson_ratio = {poisson}
{model_line}density = {density}

[[body]]
name = "plane"
kind = "rigid"
generator = {{ shape = "plane", point = {point}, normal = {normal}, size = {size} }}

[[load]]
body = "{name}"              # spread over the body by volume
force = {force}     # {load_note}

[[contact]]
slave = "{name}"
master = "plane"
radius = {penalty}             # a stiff penalty: penetration stays far below the approach
"#,
        r = num(radius),
        ratio = num(ratio),
        e = YOUNGS,
        density = num(DENSITY),
        point = vector(point),
        normal = vector(unit),
        size = num(size),
        force = vector(force),
        penalty = num(PENALTY_RATIO * radius),
    );
    let reference = match body.partner {
        Partner::Plane => reference,
        Partner::Copy => {
            scene = copy_partner(&scene, name, &quoted, &format_line, shape, total);
            Reference::SpherePair {
                load,
                r_star: 0.5 * radius,
                e_star: 0.5 * e_star,
            }
        }
    };
    if let (Some(k), Some([y0, y1])) = (shape.axis_index, shape.ends) {
        let axis = ["x", "y", "z"][k];
        scene.push_str(&format!(
            r#"
[[symmetry]]           # plane strain: mirror images on both end faces
body = "{name}"
axis = "{axis}"
at = {y0}

[[symmetry]]
body = "{name}"
axis = "{axis}"
at = {y1}
keep = "negative"
"#,
            y0 = num(y0),
            y1 = num(y1),
        ));
    }
    if body.static_solver {
        scene = crate::studies::scenarios::static_solver(&scene);
        if body.partner == Partner::Plane {
            scene.push_str(&plane_pins(name, shape));
        }
    }
    ValidationCase {
        problem,
        set: Set::Mesh,
        label: "mesh".into(),
        spacing,
        horizon_factor: horizon_factor.unwrap_or(DEFAULT_HORIZON_FACTOR),
        scene,
        reference,
    }
}

/// Reads the mesh at `path`, measures the shape, runs the Hertz scene with a contact radius
/// (or half-width) of `ratio` times the body's radius into `folder/<sphere|roller>-mesh/` and
/// compares it with theory. `body`: what the user sets on the body.
pub fn validate_mesh(
    path: &Path,
    format: Option<Format>,
    problem: Problem,
    ratio: f64,
    body: &BodyChoices,
    folder: &Path,
    quiet: bool,
) -> Result<MeshValidation> {
    let horizon_factor = body.horizon_factor;
    if problem == Problem::Punch {
        return Err(Error::input(
            "validate --mesh runs the Hertz sphere or roller: use --case sphere or --case roller",
        ));
    }
    if !(ratio > 0.0 && ratio <= MAX_CONTACT_RATIO) {
        return Err(Error::input(format!(
            "--contact-ratio {ratio}: expected the contact radius over the body's radius, above 0 and at most {MAX_CONTACT_RATIO} (Hertz theory assumes a contact small against the body; 0.15 or less is where it holds well)"
        )));
    }
    if let Some(m) = horizon_factor {
        if !(m.is_finite() && m >= 1.0) {
            return Err(Error::input(format!(
                "--horizon-factor {m}: expected the horizon in particle spacings, at least 1 (a horizon shorter than the spacing holds no bonds); 3 is the default"
            )));
        }
    }
    if body.refine > crate::case::MAX_REFINE {
        return Err(Error::input(format!(
            "--refine {}: expected at most {} levels (each cuts every element into eight, about seven times the particles)",
            body.refine,
            crate::case::MAX_REFINE
        )));
    }
    let data = std::fs::read(path).map_err(|e| {
        crate::importers::ImportError::whole_file(path, "a readable file", e.to_string())
    })?;
    let format_used = match format {
        Some(f) => f,
        None => crate::importers::detect_format(path, &data)?,
    };
    let mesh = crate::importers::read_format(path, &data, format_used)?;
    drop(data);
    let corners_of_second_order =
        body.second_order == SecondOrder::Corners && crate::importers::has_splittable(&mesh);
    let refinable = body.refine == 0 && crate::case::refinable_mesh(&mesh);
    // The finer particles the mesh allows, should the contact be poorly resolved on its own.
    let finer = if !body.compare {
        None
    } else if corners_of_second_order {
        Some(BodyChoices {
            second_order: SecondOrder::AllNodes,
            compare: false,
            ..*body
        })
    } else if refinable {
        Some(BodyChoices {
            refine: 1,
            compare: false,
            ..*body
        })
    } else {
        None
    };
    let mesh = crate::case::refine(body.second_order.apply(mesh), body.refine);
    let particles = discretize(&mesh, None).map_err(|e| match e {
        Error::Input(msg) => Error::input(format!("{}: {msg}", path.display())),
        other => other,
    })?;
    let spacing = particles.spacing;
    let shape = measure(&mesh, path, problem, 1e-6 * spacing)?;
    drop(mesh);
    let a = ratio * shape.radius;
    let contact_spacing = spacing_at_contact(&particles, &shape, a);
    let contact_spacings = a / contact_spacing;
    let count = particles.position.len();
    drop(particles);
    let mut warnings = Vec::new();
    let poor = contact_spacings < MIN_CONTACT_SPACINGS;
    // Rows per run: one, or one per body pressed on its copy.
    let bodies = match body.partner {
        Partner::Plane => 1,
        Partner::Copy => 2,
    };
    let finer = finer.filter(|_| poor && 8 * count <= REMEDY_MAX_PARTICLES);
    if poor {
        let skin = if body.skin_correction {
            ""
        } else {
            "; without the skin correction (`skin_correction = false`) the contact also comes out too wide and too low"
        };
        warnings.push(format!(
            "the contact spans only {contact_spacings:.1} spacings (a/Δ < {MIN_CONTACT_SPACINGS}); expect larger errors{skin}; refine the mesh near the contact (docs/VALIDATION.md)"
        ));
        let key = finer.as_ref().map(remedy_key);
        if let Some(key) = key {
            warnings.push(format!(
                "{} the same mesh with `{key}` on the body: about twice the spacings across the contact, at about seven times the particles",
                if bodies == 1 {
                    "the second row runs".to_string()
                } else {
                    format!("{} run", rows_named(bodies, 2 * bodies, false))
                }
            ));
        } else if corners_of_second_order {
            warnings.push(
                "the mesh is second order (tet10 or hex20) and its corners alone are the particles: --second-order all-nodes makes every node a particle (each element cut into eight), about twice the spacings across the contact".to_string(),
            );
        } else if refinable {
            warnings.push(
                "--refine 1 cuts every tet and hex into eight at its edges' midpoints: about twice the spacings across the contact, at about seven times the particles".to_string(),
            );
        }
    }
    if let Some(nu) = body.poisson.filter(|&nu| nu >= HIGH_POISSON) {
        warnings.extend(high_poisson_warning(
            nu,
            body.skin_correction,
            contact_spacings,
            problem == Problem::Sphere,
        ));
    }
    let absolute = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
    let case = mesh_case(&absolute, format, &shape, contact_spacing, ratio, body);
    if !quiet {
        eprintln!(
            "{} on {}: R = {:.4} m, Δ = {contact_spacing:.4} m, a/Δ = {contact_spacings:.1} ...",
            case.problem.name(),
            path.display(),
            shape.radius
        );
    }
    let mut rows = run_case(&case, folder, quiet)?;
    let scene = scene_path(folder, &case);
    let mut remedy = None;
    if let Some(choice) = finer {
        // The first row stands whatever becomes of the second: a failure there is a warning.
        match run_finer(
            format_used,
            &choice,
            &absolute,
            format,
            &shape,
            ratio,
            folder,
            quiet,
        ) {
            Ok((more, m)) => {
                rows.extend(more);
                remedy = Some(m);
            }
            Err(e) => warnings.push(format!(
                "the second row (`{}`) did not run: {e}",
                remedy_key(&choice)
            )),
        }
    }
    Ok(MeshValidation {
        mesh: path.to_path_buf(),
        format: format_used.name().into(),
        shape,
        theory_contact_radius: a,
        spacing: contact_spacing,
        contact_spacings,
        warnings,
        scene,
        rows,
        remedy,
        solver: if body.static_solver { "static" } else { "adr" }.into(),
    })
}

/// The second row of [`validate_mesh`]: the mesh at `absolute`, read again (only where the
/// row runs, rather than a copy of it held on every run), with the finer particles of
/// `choice`; its case written to `folder/<problem>-mesh-finer/`.
#[allow(clippy::too_many_arguments)]
fn run_finer(
    format_used: Format,
    choice: &BodyChoices,
    absolute: &Path,
    format: Option<Format>,
    shape: &MeshShape,
    ratio: f64,
    folder: &Path,
    quiet: bool,
) -> Result<(Vec<ValidationRow>, Remedy)> {
    let key = remedy_key(choice);
    let a = ratio * shape.radius;
    let data = std::fs::read(absolute).map_err(|e| {
        crate::importers::ImportError::whole_file(absolute, "a readable file", e.to_string())
    })?;
    let mesh = crate::importers::read_format(absolute, &data, format_used)?;
    drop(data);
    let mesh = crate::case::refine(choice.second_order.apply(mesh), choice.refine);
    let particles = discretize(&mesh, None)?;
    drop(mesh);
    let spacing = spacing_at_contact(&particles, shape, a);
    drop(particles);
    let mut case = mesh_case(absolute, format, shape, spacing, ratio, choice);
    case.label = "mesh-finer".into();
    if !quiet {
        eprintln!(
            "{} on {} with `{key}`: Δ = {spacing:.4} m, a/Δ = {:.1} ...",
            case.problem.name(),
            absolute.display(),
            a / spacing
        );
    }
    let mut rows = run_case(&case, folder, quiet)?;
    // The table's "theory" column names the row: 12 characters at most.
    let label = match choice.second_order {
        SecondOrder::AllNodes => "all nodes".to_string(),
        SecondOrder::Corners => key.clone(),
    };
    // Pressed on its copy, a row per body: the bodies keep their names, the set says which run.
    let several = rows.len() > 1;
    for row in &mut rows {
        if several {
            row.set = "finer".into();
        } else {
            row.variant = label.clone();
        }
    }
    let scene = scene_path(folder, &case);
    Ok((
        rows,
        Remedy {
            key,
            spacing,
            contact_spacings: a / spacing,
            scene,
        },
    ))
}

/// Where [`run_case`] writes the scene of `case`.
fn scene_path(folder: &Path, case: &ValidationCase) -> PathBuf {
    folder
        .join(format!("{}-{}", case.problem.name(), case.label))
        .join("scene.toml")
}

/// The scene key of a [`Remedy`].
fn remedy_key(choice: &BodyChoices) -> String {
    if choice.second_order == SecondOrder::AllNodes {
        "second_order = \"all-nodes\"".into()
    } else {
        format!("refine = {}", choice.refine)
    }
}

/// The particle spacing where the contact will be: Δ on a mesh of one size, the median local
/// spacing of the particles within `a` of the contact point (a roller: line) on a graded one,
/// whose horizon follows it ([`crate::case::HorizonKind::Local`]).
fn spacing_at_contact(particles: &Discretization, shape: &MeshShape, a: f64) -> f64 {
    let Some(local) = crate::case::spacing::graded_spacing(
        &particles.position,
        &particles.completed_volume(),
        particles.spacing,
    ) else {
        return particles.spacing;
    };
    let mut point = Vec3::from(shape.centre);
    point[shape.press] = shape.lowest;
    let mut near: Vec<f64> = particles
        .position
        .iter()
        .zip(&local)
        .filter(|(x, _)| {
            let mut d = *x - point;
            if let Some(k) = shape.axis_index {
                d[k] = 0.0;
            }
            d.norm() <= a
        })
        .map(|(_, &s)| s)
        .collect();
    if near.is_empty() {
        return particles.spacing;
    }
    let mid = near.len() / 2;
    *near.select_nth_unstable_by(mid, f64::total_cmp).1
}

#[cfg(test)]
mod tests {
    use super::{high_poisson_warning, HIGH_POISSON_SPACINGS};

    /// At ν = 0.4 the warning stands where the contact spans fewer spacings than those at
    /// which the figures held, and goes where it spans them, with the skin correction only
    /// and not beyond the ν measured; a roller's at every spacing.
    #[test]
    fn the_high_poisson_warning_follows_the_spacings_measured() {
        let coarse = high_poisson_warning(0.4, true, 5.5, true).expect("warned");
        assert!(coarse.contains("radius 2.5-4.8 % short") && coarse.contains("spans 5.5"));
        assert!(high_poisson_warning(0.4, true, HIGH_POISSON_SPACINGS, true).is_none());
        assert!(high_poisson_warning(0.4, false, 10.0, true).is_some());
        assert!(high_poisson_warning(0.45, true, 10.0, true).is_some());
        // A roller's contact stayed narrow at every spacing measured.
        let roller = high_poisson_warning(0.4, true, 10.0, false).expect("warned");
        assert!(roller.contains("roller's stayed narrow"), "{roller}");
    }
}
