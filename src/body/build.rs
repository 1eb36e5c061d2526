//! A body built from its `[[body]]` of a scene: the mesh read (or generated) and transformed,
//! cut at its symmetry planes, turned into a PD case (deformable) or a set of faces (rigid)
//! (METHOD.md §1, §4, §6). The scene has checked the spec's values (scene/check.rs); what
//! only the mesh shows is reported here, at the body's line.

use std::sync::Arc;

use nalgebra::{Rotation3, Unit};
use pdcontact_importers::{boundary_faces, read_path, ElementKind, Format, Mesh};

use super::facing::{self, Outline};
use super::fracture::{self, CrackPatch, Fracture};
use super::{Body, Material, PdBody, RigidBody};
use crate::case::correction::CorrectionMethod;
use crate::case::discretize::mesh_median_edge;
use crate::case::generators;
use crate::case::segments::{quad_area_normal, MasterSegment};
use crate::case::{CaseOptions, PdCase, SymmetryPlane, DEFAULT_HORIZON_FACTOR, MAX_REFINE};
use crate::error::{Error, Result};
use crate::math::{unit, Vec3, NOT_A_PARTICLE};
use crate::parallel::Comm;
use crate::scene::{
    box_corner, BodyKind, BodySpec, MaterialModel, PrecrackSpec, Scene, Side, SolverKind,
};

/// Loads the mesh of a body spec (file or generator), transformed.
pub fn body_mesh(scene: &Scene, spec: &BodySpec) -> Result<Option<Mesh>> {
    let mut mesh = if let Some(path) = &spec.mesh {
        let path = scene.resolve(path);
        let format = spec
            .format
            .as_deref()
            .map(|f| Format::from_name(f).expect("mesh format checked by the scene"));
        if !path.exists() {
            return Err(scene.error_in_body(
                &spec.name,
                &format!(
                    "mesh = \"{}\"",
                    spec.mesh
                        .as_ref()
                        .map(|p| p.display().to_string())
                        .unwrap_or_default()
                ),
                &format!("body \"{}\": mesh file {} does not exist", spec.name, {
                    // Whole where a path can be that long; a 100 kB one as an excerpt.
                    let shown = path.display().to_string();
                    if shown.chars().count() > 256 {
                        crate::scene::excerpt(&shown)
                    } else {
                        shown
                    }
                }),
            ));
        }
        let mesh = read_path(&path, format)?;
        match &spec.elements {
            Some(name) => solids_of(scene, spec, &mesh, name)?,
            None => mesh,
        }
    } else if let Some(g) = &spec.generator {
        if let Some(name) = &spec.elements {
            return Err(scene.error_in_body(
                &spec.name,
                "elements",
                &format!("body \"{}\": elements = \"{}\" names a set of a mesh file, and a generated shape has none", spec.name, crate::scene::excerpt(name)),
            ));
        }
        // The scene has checked every dimension (scene/check.rs): each is there and positive.
        let need = |v: Option<f64>| v.expect("generator checked by the scene");
        let centre = Vec3::from(g.center.unwrap_or([0.0; 3]));
        let spacing = || need(g.spacing.or(spec.spacing));
        let mut m = match g.shape.as_str() {
            "sphere" => generators::sphere(need(g.radius), spacing()),
            "cylinder" => generators::cylinder(need(g.radius), need(g.length), spacing()),
            "box" => {
                let corner = |v| box_corner(v).expect("box checked by the scene");
                generators::cuboid(corner(&g.min), corner(&g.max), spacing())
            }
            "sphere_cap" | "cylinder_cap" => {
                let r = need(g.radius);
                let shape = if g.shape == "sphere_cap" {
                    generators::CapShape::Sphere(r)
                } else {
                    generators::CapShape::Cylinder {
                        radius: r,
                        thickness: need(g.length),
                    }
                };
                generators::cap(shape, need(g.half_width), need(g.depth), spacing())
            }
            "plane" => return Ok(None),
            other => unreachable!("generator shape \"{other}\" checked by the scene"),
        };
        if !matches!(g.shape.as_str(), "box") {
            for p in &mut m.coords {
                *p = (Vec3::from(*p) + centre).into();
            }
        }
        m
    } else {
        unreachable!("a body without mesh or generator is refused by the scene")
    };
    transform(&mut mesh, spec);
    check_size(scene, spec, &mesh)?;
    Ok(Some(mesh))
}

/// The body's part of an assembly meshed in one file: the solids of the named set `name`
/// (`elements = "..."`), or an error that names the sets that hold solids.
fn solids_of(scene: &Scene, spec: &BodySpec, mesh: &Mesh, name: &str) -> Result<Mesh> {
    let found = mesh.set(name).and_then(|set| mesh.solids_of(set));
    found.ok_or_else(|| {
        let with_solids: Vec<String> = mesh
            .sets
            .iter()
            .filter(|s| {
                s.elements
                    .iter()
                    .flatten()
                    .any(|&e| mesh.element(e as usize).kind.is_solid())
            })
            .map(|s| format!("\"{}\"", s.name))
            .collect();
        let what = if mesh.set(name).is_some() {
            "holds no solid element"
        } else {
            "is not a set of the mesh"
        };
        let sets = if with_solids.is_empty() {
            "none of its sets holds solid elements (leave elements out: the body is every solid)"
                .to_string()
        } else {
            format!("the sets that hold solids: {}", with_solids.join(", "))
        };
        scene.error_in_body(
            &spec.name,
            "elements",
            &format!(
                "body \"{}\": elements = \"{}\" {what}; {sets}",
                spec.name,
                crate::scene::excerpt(name)
            ),
        )
    })
}

/// Body sizes that f64 holds with room to spare: element volumes go as L³ and bond stiffnesses
/// as 1/δ⁴, so a femtometre to 1e15 m keeps every product far from over- and underflow (a
/// `scale = 1e300` used to be reported as an inverted element of volume NaN).
const BODY_SIZE: (f64, f64) = (1e-15, 1e15);

/// How far from the origin a body may lie, in its own sizes: there f64's 16 digits still keep
/// 8 for the body's own geometry, what bond stretches of 1e-6 (small loads) need.
const PLACEMENT_RANGE: f64 = 1e8;

/// Refuses a placed mesh whose coordinates are not finite, whose size is out of
/// [`BODY_SIZE`] or which lies farther than [`PLACEMENT_RANGE`] of its sizes from the origin;
/// and, when the body gives its spacing, one whose bonds cannot fit in memory.
fn check_size(scene: &Scene, spec: &BodySpec, mesh: &Mesh) -> Result<()> {
    let Some((lo, hi)) = mesh.bbox() else {
        return Ok(());
    };
    let size = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
    let needle = if spec.scale.is_some() { "scale" } else { "" };
    let finite = lo.iter().chain(&hi).all(|x| x.is_finite()) && size.is_finite();
    if !finite || !(BODY_SIZE.0..=BODY_SIZE.1).contains(&size) {
        return Err(scene.error_in_body(
            &spec.name,
            needle,
            &format!(
                "body \"{}\" is {} m across once placed (scale {}): bodies from {} to {} m are supported; check scale and the mesh's units",
                spec.name,
                crate::scene::num(size),
                crate::scene::num(spec.scale.unwrap_or(1.0)),
                crate::scene::num(BODY_SIZE.0),
                crate::scene::num(BODY_SIZE.1)
            ),
        ));
    }
    // Far from the origin, f64 keeps too few digits to tell the body's nodes apart (a sphere
    // at `center = [0, 0, 1e20]` used to be reported as a degenerate element).
    let far = lo.iter().chain(&hi).map(|x| x.abs()).fold(0.0, f64::max);
    if far > PLACEMENT_RANGE * size {
        let needle = if spec.translate.is_some() {
            "translate"
        } else if spec.generator.as_ref().is_some_and(|g| g.center.is_some()) {
            "center"
        } else {
            ""
        };
        return Err(scene.error_in_body(
            &spec.name,
            needle,
            &format!(
                "body \"{}\" lies {} m from the origin once placed, more than {} times its size ({} m): f64 has too few digits there to tell its nodes apart; check center, translate and the mesh's units",
                spec.name,
                crate::scene::num(far),
                crate::scene::num(PLACEMENT_RANGE),
                crate::scene::num(size)
            ),
        ));
    }
    // A given spacing sets the horizon: one far above the elements bonds every particle to
    // every other, n² bonds.
    if let (Some(dx), BodyKind::Deformable) = (spec.spacing, spec.kind) {
        let n = mesh.solids().count() as f64;
        let volume = (0..3)
            .map(|k| (hi[k] - lo[k]).max(size * 1e-3))
            .product::<f64>();
        let m = spec.horizon_factor.unwrap_or(DEFAULT_HORIZON_FACTOR);
        let bonds = (4.0 / 3.0 * std::f64::consts::PI * (m * dx).powi(3) * n / volume).min(n);
        let bytes = n * (400.0 + 24.0 * bonds);
        let limit = crate::scene::memory_limit();
        if bytes > limit {
            return Err(scene.error_in_body(
                &spec.name,
                "spacing",
                &format!(
                    "body \"{}\": spacing {} gives each of its {} particles about {} bonds, about {} GB of memory; the limit is {} GB (this machine's memory, or PDCONTACT_MEMORY_LIMIT): give a spacing near the mesh's element size",
                    spec.name,
                    crate::scene::num(dx),
                    n,
                    crate::scene::num(bonds.round()),
                    crate::scene::num((bytes / 1e8).round() / 10.0),
                    crate::scene::num((limit / 1e8).round() / 10.0)
                ),
            ));
        }
    }
    Ok(())
}

/// Applies scale, then rotation, then translation to a mesh.
fn transform(mesh: &mut Mesh, spec: &BodySpec) {
    let mut points: Vec<Vec3> = mesh.coords.iter().map(|p| Vec3::from(*p)).collect();
    transform_points(&mut points, spec);
    for (c, p) in mesh.coords.iter_mut().zip(points) {
        *c = p.into();
    }
}

/// Applies scale, then rotation, then translation to points.
fn transform_points(points: &mut [Vec3], spec: &BodySpec) {
    let scale = spec.scale.unwrap_or(1.0);
    let rotation = spec.rotate.as_ref().and_then(|r| {
        let axis = Vec3::from(r.axis);
        (axis.amax() > 0.0).then(|| {
            (
                Rotation3::from_axis_angle(
                    &Unit::new_unchecked(unit(axis)),
                    r.angle_deg.to_radians(),
                ),
                Vec3::from(r.center.unwrap_or([0.0; 3])),
            )
        })
    });
    let shift = Vec3::from(spec.translate.unwrap_or([0.0; 3]));
    for p in points {
        let mut x = *p * scale;
        if let Some((rot, c)) = &rotation {
            x = rot * (x - c) + c;
        }
        *p = x + shift;
    }
}

/// Keeps the elements on one side of the plane `x_axis = at` and the nodes they use.
///
/// Errors when an element has corners strictly on both sides: the mesh must be cut along the
/// plane for a symmetric model to be exact.
pub fn clip_mesh(
    mesh: &Mesh,
    axis: usize,
    at: f64,
    keep_positive: bool,
    tol: f64,
) -> std::result::Result<Mesh, String> {
    let side = |n: u32| {
        let d = mesh.coords[n as usize][axis] - at;
        if d > tol {
            1
        } else if d < -tol {
            -1
        } else {
            0
        }
    };
    let want = if keep_positive { 1 } else { -1 };
    let sides = |e: &pdcontact_importers::ElementRef<'_>| -> Vec<i32> {
        e.nodes
            .iter()
            .filter(|&&n| n != pdcontact_importers::MISSING_NODE)
            .map(|&n| side(n))
            .collect()
    };
    if let Some(e) = mesh.elements().find(|e| {
        let s = sides(e);
        s.contains(&1) && s.contains(&-1)
    }) {
        return Err(format!(
            "element {} crosses the symmetry plane {} = {at}: the mesh must be cut along the plane",
            e.id,
            ["x", "y", "z"][axis]
        ));
    }
    // A solid on the kept side; a face there or in the plane.
    Ok(mesh.retain_elements(|e| {
        let s = sides(&e);
        s.contains(&want) || (!e.kind.is_solid() && s.iter().all(|&k| k == 0))
    }))
}

/// Builds the body of a spec.
pub fn build_body(scene: &Scene, spec: &BodySpec) -> Result<Body> {
    build_body_on(scene, spec, None)
}

/// Whether a rank of a decomposed run builds only its part of the body's case
/// ([`crate::case::part`]): a bond-based body without bond failure under ADR. The LPS's
/// states, fracture's damage and the explicit solver's stable step still read every
/// particle's bonds, so those bodies are built whole on every rank.
fn built_in_parts(scene: &Scene, spec: &BodySpec) -> bool {
    let Some(m) = spec.material else {
        return false;
    };
    m.model == MaterialModel::BondBased
        && m.fracture_energy.is_none()
        && m.critical_stretch.is_none()
        && !scene.precracks.iter().any(|c| c.body == spec.name)
        && scene.solver.kind == SolverKind::Adr
}

/// [`build_body`] in a run decomposed over the ranks of `comm`: a body that can be
/// ([`built_in_parts`]) is built as this rank's part. Collective.
pub fn build_body_on(scene: &Scene, spec: &BodySpec, comm: Option<&Arc<dyn Comm>>) -> Result<Body> {
    let mut mesh = body_mesh(scene, spec)?;
    if let Some(m) = &mut mesh {
        for s in scene.symmetries.iter().filter(|s| s.body == spec.name) {
            let axis = s.axis.index();
            let (lo, hi) = m.bbox().unwrap_or(([0.0; 3], [0.0; 3]));
            let tol = 1e-9 * (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
            *m = clip_mesh(m, axis, s.at, s.keep == Side::Positive, tol).map_err(|msg| {
                scene.error_in_body(
                    &spec.name,
                    &format!("axis = \"{}\"", s.axis.name()),
                    &format!("body \"{}\": {msg}", spec.name),
                )
            })?;
            if spec.kind == BodyKind::Deformable && m.solids().next().is_none() {
                return Err(scene.error_in_body(
                    &spec.name,
                    "",
                    &format!(
                        "body \"{}\" has no particles: the symmetry plane {} = {} (keep = \"{}\") leaves none of its elements",
                        spec.name,
                        s.axis.name(),
                        s.at,
                        s.keep.name()
                    ),
                ));
            }
        }
    }
    match spec.kind {
        BodyKind::Deformable => {
            // The scene refuses a deformable plane and a deformable body without a material.
            let mesh = mesh.expect("a deformable body has a mesh");
            let m = spec.material.expect("material checked by the scene");
            let symmetry = scene
                .symmetries
                .iter()
                .filter(|s| s.body == spec.name)
                .map(|s| SymmetryPlane {
                    axis: s.axis.index(),
                    at: s.at,
                })
                .collect();
            // A generated body's grid spacing is its generator's cell size, the median edge of
            // its hex lattice (halved by each level of `refine`, which halves every edge); an
            // imported mesh's is estimated from its particles' volumes.
            let refine = spec.refine.unwrap_or(0);
            let spacing = spec.spacing.or_else(|| {
                spec.generator
                    .is_some()
                    .then(|| mesh_median_edge(&mesh) / 2f64.powi(refine.min(MAX_REFINE) as i32))
            });
            let options = CaseOptions {
                spacing,
                horizon_factor: spec.horizon_factor.unwrap_or(DEFAULT_HORIZON_FACTOR),
                correction: spec
                    .surface_correction
                    .unwrap_or(CorrectionMethod::Balanced),
                symmetry,
                horizon: spec.horizon.unwrap_or_default(),
                second_order: spec.second_order.unwrap_or_default(),
                refine,
                surface_volume: spec.surface_volume.unwrap_or_default(),
                // The LPS's skin correction stiffens the surface row of a slender body that sees
                // no contact as well (a gmsh tet bar: E +11 to +20 %), so it is for the bodies
                // in a contact with another body alone (docs/VALIDATION.md, "Any Poisson's
                // ratio"). Pressed on itself across a pre-crack, it made a gmsh tet4 block
                // 33 % stiffer than whole across the crack and 35 % stiffer than CalculiX cut
                // at 30° (without: +2.3 %, +0.4 %; docs/FRACTURE.md, "An LPS body's cracks").
                skin_correction: spec.skin_correction.unwrap_or(true)
                    && (m.model != MaterialModel::Lps
                        || scene.contacts.iter().any(|c| {
                            c.slave != c.master && (c.slave == spec.name || c.master == spec.name)
                        })),
                keep_elements: false,
                pieces_apart: false,
            };
            let (method, skin) = (options.correction, options.skin_correction);
            let in_parts = built_in_parts(scene, spec);
            let mut case = PdCase::build_part(mesh, options, comm.cloned(), in_parts).map_err(
                |e| match e {
                    Error::Input(msg) => scene.error_in_body(
                        &spec.name,
                        "",
                        &format!("body \"{}\": {msg}", spec.name),
                    ),
                    other => other,
                },
            )?;
            if case.particles.is_empty() {
                return Err(scene.error_in_body(
                    &spec.name,
                    "",
                    &format!("body \"{}\" has no particles", spec.name),
                ));
            }
            let precracks: Vec<(usize, &PrecrackSpec)> = scene
                .precracks
                .iter()
                .enumerate()
                .filter(|(_, c)| c.body == spec.name)
                .collect();
            let patches: Vec<(usize, CrackPatch)> = precracks
                .iter()
                .map(|&(k, c)| {
                    let patch = CrackPatch::new(
                        Vec3::from(c.point),
                        Vec3::from(c.normal),
                        Vec3::from(c.along),
                        c.size,
                    );
                    (k, patch)
                })
                .collect();
            let cuts_nothing = |k: usize| {
                let c = &scene.precracks[k];
                scene.block_error(
                    "[[precrack]]",
                    k,
                    format!(
                        "precrack in \"{}\" cuts no bond: its patch (centre [{}, {}, {}], size [{}, {}]) does not pass between any two of the body's particles; check point, normal and size against where the body is placed",
                        spec.name,
                        crate::scene::num(c.point[0]),
                        crate::scene::num(c.point[1]),
                        crate::scene::num(c.point[2]),
                        crate::scene::num(c.size[0]),
                        crate::scene::num(c.size[1])
                    ),
                )
            };
            // `PdCase::cut`'s refusal of a pre-crack, as the scene's error at its block.
            let cut_error = |(k, msg): (usize, String)| {
                if msg == "cuts no bond" {
                    cuts_nothing(k)
                } else {
                    scene.block_error("[[precrack]]", k, msg)
                }
            };
            // A body that is its own contact master presses its pre-cracks' faces together:
            // the case is cut before the body is made, so that its corrections see the faces.
            // (Pressed on the surfaces found again instead, its pre-cracks break bonds as
            // without contact, and the surface is found from the broken bonds.)
            let self_contact = scene.contacts.iter().any(|c| {
                c.slave == spec.name
                    && c.master == spec.name
                    && scene.self_faces(c) != Some(crate::scene::SelfFaces::Found)
            });
            let cut = if self_contact && !patches.is_empty() {
                Some(case.cut(&patches, method, skin).map_err(cut_error)?)
            } else {
                None
            };
            // A body pressed on the surfaces found again: the rows beside its pre-cracks get
            // the corrections of a body without the bonds across (as `cut` gives its faces).
            let found_faces = scene.contacts.iter().any(|c| {
                c.slave == spec.name && scene.self_faces(c) == Some(crate::scene::SelfFaces::Found)
            });
            // An LPS body's weighted volumes likewise: without them, a gmsh tet4 block cut
            // across closed 12 % softer than on the pre-crack's own faces (docs/FRACTURE.md,
            // "An LPS body's cracks").
            let mut cut_bonds = Vec::new();
            let mut crack_share = Vec::new();
            if found_faces && !patches.is_empty() {
                crack_share = case
                    .correct_without(&patches, method, skin)
                    .map_err(cut_error)?;
                if m.model == MaterialModel::Lps {
                    cut_bonds = Fracture::crossing_bonds(&case, &patches);
                }
            }
            // An LPS body's skin correction on the faces a partner can press alone.
            let skin_on = (m.model == MaterialModel::Lps && skin)
                .then(|| -> Result<Vec<bool>> {
                    let partners = partner_outlines(scene, spec)?;
                    Ok(facing::facing(
                        &case.particles.position,
                        &case.surface.normal,
                        &case.surface.is_surface,
                        &partners,
                        case.particles.spacing,
                    ))
                })
                .transpose()?;
            let mut body = PdBody::without(
                &spec.name,
                case,
                Material {
                    youngs: m.youngs_modulus,
                    poisson: m.poisson_ratio,
                    density: m.density,
                    model: m.model,
                    influence: m.influence_function.unwrap_or_default(),
                },
                &cut_bonds,
                skin_on.as_deref(),
            );
            body.kinematics = spec.kinematics;
            body.crack_share = Arc::new(crack_share);
            let s0 = match (m.fracture_energy, m.critical_stretch) {
                (Some(g0), _) => Some(match m.model {
                    MaterialModel::Lps => fracture::critical_stretch_lps,
                    MaterialModel::BondBased => fracture::critical_stretch,
                }(
                    g0, m.youngs_modulus, m.poisson_ratio, body.case.horizon
                )),
                (None, s0) => s0,
            };
            if s0.is_some() || !precracks.is_empty() {
                body.enable_fracture(s0);
                if let Some(f) = &mut body.fracture {
                    f.criterion = m.failure.unwrap_or_default();
                }
            }
            match cut {
                Some(cut) => {
                    body.crack_faces = cut.faces;
                    body.precrack_pairs = cut.parted;
                }
                None => {
                    for (k, patch) in patches {
                        let cut = Fracture::crossing(&body.case.bonds, &body.reference, &patch);
                        if cut.is_empty() {
                            return Err(cuts_nothing(k));
                        }
                        body.break_bonds(&cut);
                        let pairs = parted(&body, &patch, &cut);
                        body.precrack_pairs.push((k, patch.normal, pairs));
                    }
                }
            }
            if let Some(v) = spec.velocity {
                body.set_velocity(Vec3::from(v));
            }
            Ok(Body::Deformable(Box::new(body)))
        }
        BodyKind::Rigid => {
            let (vertices, faces) = match mesh {
                Some(mesh) => rigid_faces(&mesh),
                None => plane_faces(spec),
            };
            if faces.is_empty() {
                return Err(scene.error_in_body(&spec.name,
                    "name",
                    &format!("rigid body \"{}\" has no faces (a mesh of 3D solids, or of shells, is needed)", spec.name),
                ));
            }
            let axis = Vec3::from(spec.free_axis.unwrap_or([0.0, 0.0, 1.0]));
            Ok(Body::Rigid(Box::new(RigidBody {
                name: spec.name.clone(),
                vertices,
                faces,
                material: spec.material.map(|m| Material {
                    youngs: m.youngs_modulus,
                    poisson: m.poisson_ratio,
                    density: m.density,
                    model: m.model,
                    influence: m.influence_function.unwrap_or_default(),
                }),
                motion: spec.motion,
                velocity: Vec3::from(spec.motion_velocity.unwrap_or([0.0; 3])),
                axis: if axis.amax() > 0.0 {
                    unit(axis)
                } else {
                    Vec3::z()
                },
                displacement: Vec3::from(spec.displacement.unwrap_or([0.0; 3])),
                ramp: spec.ramp,
                mass: spec.mass.unwrap_or(0.0),
                translation: Vec3::zeros(),
                axial_speed: 0.0,
                load: Vec3::zeros(),
                contact_force: Vec3::zeros(),
                contact_stiffness: 0.0,
            })))
        }
    }
}

/// The surfaces of the bodies in a contact with `spec`'s other than itself, as their meshes
/// place them (the whole mesh, before any symmetry plane cuts it; a plane's patch).
fn partner_outlines(scene: &Scene, spec: &BodySpec) -> Result<Vec<Outline>> {
    let mut names: Vec<&str> = scene
        .contacts
        .iter()
        .filter(|c| c.slave != c.master)
        .filter_map(|c| {
            if c.slave == spec.name {
                Some(c.master.as_str())
            } else if c.master == spec.name {
                Some(c.slave.as_str())
            } else {
                None
            }
        })
        .collect();
    names.sort_unstable();
    names.dedup();
    let mut outlines = Vec::with_capacity(names.len());
    for name in names {
        let Some(partner) = scene.bodies.iter().find(|b| b.name == name) else {
            continue;
        };
        let (vertices, faces) = match body_mesh(scene, partner)? {
            Some(mesh) => rigid_faces(&mesh),
            None => plane_faces(partner),
        };
        outlines.push(Outline::new(&vertices, &faces));
    }
    Ok(outlines)
}

/// Faces of a rigid mesh: boundary faces of its solids, or its 2-D elements as written.
fn rigid_faces(mesh: &Mesh) -> (Vec<Vec3>, Vec<MasterSegment>) {
    let vertices: Vec<Vec3> = mesh.coords.iter().map(|p| Vec3::from(*p)).collect();
    let mut quads: Vec<[u32; 4]> = boundary_faces(mesh)
        .boundary
        .iter()
        .map(|f| f.nodes)
        .collect();
    if quads.is_empty() {
        for e in mesh.elements() {
            let c = e.corners();
            match e.kind {
                ElementKind::Triangle => quads.push([c[0], c[1], c[2], c[2]]),
                ElementKind::Quadrilateral => quads.push([c[0], c[1], c[2], c[3]]),
                _ => {}
            }
        }
    }
    let faces = quads
        .into_iter()
        .filter(|q| q.iter().all(|&n| n != NOT_A_PARTICLE))
        .map(|nodes| {
            let (area, normal) = quad_area_normal(nodes.map(|n| vertices[n as usize]));
            MasterSegment {
                nodes,
                area,
                normal,
            }
        })
        .filter(|s| s.area > 0.0)
        .collect();
    (vertices, faces)
}

/// A square patch of `divisions²` quads centred at `point`, facing `normal`.
fn plane_faces(spec: &BodySpec) -> (Vec<Vec3>, Vec<MasterSegment>) {
    // The scene has checked that a plane has a point, a non-zero normal and a positive size.
    let g = spec
        .generator
        .as_ref()
        .expect("a rigid body without mesh is a plane");
    let (Some(point), Some(normal), Some(size)) = (g.point, g.normal, g.size) else {
        unreachable!("plane checked by the scene")
    };
    let n = unit(Vec3::from(normal));
    let t1 = if n.x.abs() < 0.9 {
        Vec3::x()
    } else {
        Vec3::y()
    };
    let e1 = (t1 - n * n.dot(&t1)).normalize();
    let e2 = n.cross(&e1);
    let k = g.divisions.unwrap_or(1).max(1);
    let p0 = Vec3::from(point);
    let mut vertices = Vec::with_capacity((k + 1) * (k + 1));
    for j in 0..=k {
        for i in 0..=k {
            let a = -0.5 * size + size * i as f64 / k as f64;
            let b = -0.5 * size + size * j as f64 / k as f64;
            vertices.push(p0 + e1 * a + e2 * b);
        }
    }
    let mut faces = Vec::with_capacity(k * k);
    for j in 0..k {
        for i in 0..k {
            let v = |ii: usize, jj: usize| (ii + (k + 1) * jj) as u32;
            // e1 × e2 = n: counter-clockwise seen from the normal side.
            let nodes = [v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)];
            let (area, normal) = quad_area_normal(nodes.map(|q| vertices[q as usize]));
            faces.push(MasterSegment {
                nodes,
                area,
                normal,
            });
        }
    }
    transform_points(&mut vertices, spec);
    (vertices, faces)
}

/// The real particle pairs whose bonds `cut` (`(i, bond)`) removed, each as `(behind, in
/// front)` of `patch`'s normal (what [`PdBody::crossed_crack`] watches).
fn parted(body: &PdBody, patch: &CrackPatch, cut: &[(u32, u32)]) -> Vec<(u32, u32)> {
    let n = body.len();
    cut.iter()
        .filter_map(|&(i, b)| {
            let j = body.case.bonds.partner[b as usize];
            ((j as usize) < n).then(|| {
                let d = patch
                    .normal
                    .dot(&(body.reference[j as usize] - body.reference[i as usize]));
                if d > 0.0 {
                    (i, j)
                } else {
                    (j, i)
                }
            })
        })
        .collect()
}
