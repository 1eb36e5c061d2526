//! Bodies of a scene: deformable PD bodies (particles and bonds) and rigid surfaces
//! (METHOD.md §4-6).
//!
//! A deformable body stores, per directed bond, the partner, the reference length `L` and the
//! weight `w = c G v_c V_i V_j / L` (N/m), so that the bond's force on particle `i` is
//! `w (|y| − L) y/|y|` with `y` the deformed bond: Eq. 26 (`c s n`) times the volumes, with the
//! surface factor `G` and the volume correction `v_c` folded in once. Because `G` and `v_c` are
//! symmetric, `w_ij = w_ji`: internal forces are equal and opposite and sum to zero.

use nalgebra::{Rotation3, Unit};
use pdcontact_importers::{boundary_faces, read_path, ElementKind, Format, Mesh};

use crate::case::correction::{micromodulus, CorrectionMethod};
use crate::case::generators;
use crate::case::pairs::{ForceBuffers, PairList};
use crate::case::segments::{quad_area_normal, MasterSegment};
use crate::case::{CaseOptions, PdCase, SymmetryPlane, DEFAULT_HORIZON_FACTOR};
use crate::error::{Error, Result};
use crate::math::{Vec3, NOT_A_PARTICLE};
use crate::scene::{BodyKind, BodySpec, Kinematics, Motion, Scene};

/// Linear elastic material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    pub youngs: f64,
    pub poisson: f64,
    pub density: f64,
}

impl Material {
    /// `m = (1 − ν²)/E` of Eq. 24.
    pub fn compliance(&self) -> f64 {
        (1.0 - self.poisson * self.poisson) / self.youngs
    }
}

/// Bit mask of fixed displacement components.
pub type FixMask = u8;
/// x fixed.
pub const FIX_X: FixMask = 1;
/// y fixed.
pub const FIX_Y: FixMask = 2;
/// z fixed.
pub const FIX_Z: FixMask = 4;

/// A deformable PD body and its state.
#[derive(Clone, Debug)]
pub struct PdBody {
    pub name: String,
    pub case: PdCase,
    pub material: Material,
    /// Bond kinematics.
    pub kinematics: Kinematics,
    /// Reference positions of the particles followed by their mirror images.
    pub reference: Vec<Vec3>,
    /// Micromodulus `c`.
    pub micromodulus: f64,
    /// Per directed bond: `c G v_c V_i V_j / L`, N/m.
    pub bond_weight: Vec<f32>,
    /// Per particle: `Σ_j w_ij`, the sum of its bond stiffnesses (N/m).
    pub stiffness: Vec<f64>,
    /// The bonds each pair once, with their weights: what the force pass walks.
    pub pairs: PairList,
    /// Per-thread scratch of the force pass.
    pub force_buffers: ForceBuffers,
    /// `ρ V_i`.
    pub mass: Vec<f64>,
    /// Fixed components per particle (supports and symmetry planes).
    pub fixed: Vec<FixMask>,
    /// The components of `fixed` that symmetry planes hold (not supports).
    pub symmetric: Vec<FixMask>,
    /// Applied force per particle, N.
    pub load: Vec<Vec3>,
    /// Displacement.
    pub u: Vec<Vec3>,
    /// Velocity.
    pub v: Vec<Vec3>,
    /// Total force (internal + applied + contact), N.
    pub force: Vec<Vec3>,
    /// Contact force alone, N.
    pub contact_force: Vec<Vec3>,
    /// Extra stiffness from contact, for ADR's fictitious density and the stable step (N/m).
    pub contact_stiffness: Vec<f64>,
}

impl PdBody {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.u.len()
    }

    /// True without particles.
    pub fn is_empty(&self) -> bool {
        self.u.is_empty()
    }

    /// Current position of particle `i`.
    #[inline]
    pub fn position(&self, i: usize) -> Vec3 {
        self.case.particles.position[i] + self.u[i]
    }

    /// Grid spacing Δ.
    pub fn spacing(&self) -> f64 {
        self.case.particles.spacing
    }

    /// Master segments.
    pub fn segments(&self) -> &[MasterSegment] {
        &self.case.segments.segments
    }

    /// Builds the body from a PD case and a material.
    pub fn new(name: &str, case: PdCase, material: Material) -> PdBody {
        let c = micromodulus(material.youngs, case.horizon);
        let n = case.particles.len();
        let vol = &case.particles.volume;
        let partner_vol = case.ghosts.partner_volumes(vol);
        let bonds = &case.bonds;
        let mut bond_weight = Vec::with_capacity(bonds.len());
        let mut stiffness = vec![0.0; n];
        for i in 0..n {
            for b in bonds.range(i) {
                let j = bonds.partner[b] as usize;
                let w =
                    c * case.correction.bond_factor[b] * vol[i] * partner_vol[j] / bonds.length(b);
                bond_weight.push(w as f32);
                stiffness[i] += w;
            }
        }
        // Particles on a symmetry plane cannot move across it.
        let fixed: Vec<FixMask> = (0..n)
            .map(|i| {
                case.ghosts
                    .planes
                    .iter()
                    .enumerate()
                    .filter(|(k, _)| case.ghosts.on_plane[i] & (1 << k) != 0)
                    .fold(0, |m, (_, pl)| m | (1 << pl.axis))
            })
            .collect();
        let mut reference = Vec::new();
        case.ghosts
            .extend_positions(&case.particles.position, &mut reference);
        let symmetric: Vec<FixMask> = fixed.clone();
        PdBody {
            name: name.to_string(),
            symmetric,
            kinematics: Kinematics::Finite,
            reference,
            micromodulus: c,
            mass: vol[..n].iter().map(|v| v * material.density).collect(),
            fixed,
            load: vec![Vec3::zeros(); n],
            u: vec![Vec3::zeros(); n],
            v: vec![Vec3::zeros(); n],
            force: vec![Vec3::zeros(); n],
            contact_force: vec![Vec3::zeros(); n],
            contact_stiffness: vec![0.0; n],
            pairs: PairList::from_bonds(
                bonds,
                &bond_weight,
                &(0..n).map(|i| case.ghosts.share(i)).collect::<Vec<_>>(),
                n,
            ),
            force_buffers: ForceBuffers::default(),
            bond_weight,
            stiffness,
            case,
            material,
        }
    }

    /// Sets the velocity of every particle.
    pub fn set_velocity(&mut self, v: Vec3) {
        self.v.iter_mut().for_each(|x| *x = v);
    }

    /// Current positions of the particles followed by their mirror images.
    pub fn extended_positions(&self, out: &mut Vec<Vec3>) {
        let real: Vec<Vec3> = (0..self.len()).map(|i| self.position(i)).collect();
        self.case.ghosts.extend_positions(&real, out);
    }

    /// Strain energy `¼ Σ_directed w (|y| − L)²` (each pair counted twice; a bond to a mirror
    /// image carries the half of its mirrored pair that belongs to this model).
    pub fn strain_energy(&self) -> f64 {
        let bonds = &self.case.bonds;
        let mut pos = Vec::new();
        self.extended_positions(&mut pos);
        (0..self.len())
            .map(|i| {
                let yi = pos[i];
                bonds
                    .range(i)
                    .map(|b| {
                        let j = bonds.partner[b] as usize;
                        let stretch = match self.kinematics {
                            Kinematics::Finite => (pos[j] - yi).norm() - bonds.length(b),
                            Kinematics::Small => {
                                let xi = self.reference[j] - self.reference[i];
                                (pos[j] - yi - xi).dot(&xi) / bonds.length(b)
                            }
                        };
                        0.25 * f64::from(self.bond_weight[b]) * stretch * stretch
                    })
                    .sum::<f64>()
            })
            .sum()
    }

    /// Kinetic energy.
    pub fn kinetic_energy(&self) -> f64 {
        self.v
            .iter()
            .zip(&self.mass)
            .map(|(v, m)| 0.5 * m * v.norm_squared())
            .sum()
    }
}

/// A rigid surface: faces only, moved as a whole.
#[derive(Clone, Debug)]
pub struct RigidBody {
    pub name: String,
    /// Reference vertex positions.
    pub vertices: Vec<Vec3>,
    /// Outward faces (`[a, b, c, c]` for triangles).
    pub faces: Vec<MasterSegment>,
    /// Material for the contact stiffness; `None` is infinitely stiff (`m = 0` in Eq. 24).
    pub material: Option<Material>,
    pub motion: Motion,
    /// Prescribed velocity (`Motion::Velocity`).
    pub velocity: Vec3,
    /// Unit axis (`Motion::Free`).
    pub axis: Vec3,
    /// Mass (`Motion::Free`, explicit runs).
    pub mass: f64,
    /// Current translation from the reference position.
    pub translation: Vec3,
    /// Speed along `axis` (`Motion::Free`).
    pub axial_speed: f64,
    /// Total applied force, N.
    pub load: Vec3,
    /// Total contact force on the body, N.
    pub contact_force: Vec3,
    /// Contact stiffness along the axis (for ADR's fictitious density).
    pub contact_stiffness: f64,
}

impl RigidBody {
    /// Current position of vertex `i`.
    #[inline]
    pub fn position(&self, i: usize) -> Vec3 {
        self.vertices[i] + self.translation
    }
}

/// A body of a scene.
#[derive(Clone, Debug)]
pub enum Body {
    Deformable(Box<PdBody>),
    Rigid(Box<RigidBody>),
}

impl Body {
    /// The body's name.
    pub fn name(&self) -> &str {
        match self {
            Body::Deformable(b) => &b.name,
            Body::Rigid(b) => &b.name,
        }
    }

    /// The deformable body, if it is one.
    pub fn as_pd(&self) -> Option<&PdBody> {
        match self {
            Body::Deformable(b) => Some(b),
            Body::Rigid(_) => None,
        }
    }

    /// The deformable body, mutably.
    pub fn as_pd_mut(&mut self) -> Option<&mut PdBody> {
        match self {
            Body::Deformable(b) => Some(b),
            Body::Rigid(_) => None,
        }
    }

    /// The rigid body, if it is one.
    pub fn as_rigid(&self) -> Option<&RigidBody> {
        match self {
            Body::Rigid(b) => Some(b),
            Body::Deformable(_) => None,
        }
    }
}

/// Loads the mesh of a body spec (file or generator), transformed.
pub fn body_mesh(scene: &Scene, spec: &BodySpec) -> Result<Option<Mesh>> {
    let mut mesh = if let Some(path) = &spec.mesh {
        let path = scene.resolve(path);
        let format = match &spec.format {
            Some(f) => Some(Format::from_name(f).ok_or_else(|| {
                scene.error_in_body(
                    &spec.name,
                    "format",
                    &format!("unknown mesh format \"{f}\": use cdb, msh or inp"),
                )
            })?),
            None => None,
        };
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
                &format!(
                    "body \"{}\": mesh file {} does not exist",
                    spec.name,
                    path.display()
                ),
            ));
        }
        read_path(&path, format)?
    } else if let Some(g) = &spec.generator {
        let need = |v: Option<f64>, what: &str| {
            v.filter(|x| *x > 0.0 && x.is_finite()).ok_or_else(|| {
                scene.error_in_body(
                    &spec.name,
                    "generator",
                    &format!(
                        "body \"{}\": generator \"{}\" needs a positive {what}",
                        spec.name, g.shape
                    ),
                )
            })
        };
        let centre = Vec3::from(g.center.unwrap_or([0.0; 3]));
        let mut m = match g.shape.as_str() {
            "sphere" => generators::sphere(need(g.radius, "radius")?, need(g.spacing.or(spec.spacing), "spacing")?),
            "cylinder" => generators::cylinder(
                need(g.radius, "radius")?,
                need(g.length, "length")?,
                need(g.spacing.or(spec.spacing), "spacing")?,
            ),
            "box" => {
                let corner = |v: &Option<Vec<f64>>| v.as_ref().filter(|v| v.len() == 3).map(|v| [v[0], v[1], v[2]]);
                let (Some(lo), Some(hi)) = (corner(&g.min), corner(&g.max)) else {
                    return Err(scene.error_in_body(&spec.name, "generator", &format!("body \"{}\": a box needs min and max, three numbers each", spec.name)));
                };
                if (0..3).any(|k| hi[k] <= lo[k]) {
                    return Err(scene.error_in_body(&spec.name, "generator", &format!("body \"{}\": box max must exceed min on every axis", spec.name)));
                }
                generators::cuboid(lo, hi, need(g.spacing.or(spec.spacing), "spacing")?)
            }
            "sphere_cap" | "cylinder_cap" => {
                let r = need(g.radius, "radius")?;
                let half_width = need(g.half_width, "half_width")?;
                if half_width >= r {
                    return Err(scene.error_in_body(&spec.name, "half_width", &format!("body \"{}\": a cap's half_width must be less than its radius", spec.name)));
                }
                let depth = need(g.depth, "depth")?;
                if depth >= r {
                    return Err(scene.error_in_body(&spec.name, "depth", &format!("body \"{}\": a cap's depth must be less than its radius", spec.name)));
                }
                let shape = if g.shape == "sphere_cap" {
                    generators::CapShape::Sphere(r)
                } else {
                    generators::CapShape::Cylinder { radius: r, thickness: need(g.length, "length (the slice thickness along y)")? }
                };
                generators::cap(shape, half_width, depth, need(g.spacing.or(spec.spacing), "spacing")?)
            }
            "plane" => return Ok(None),
            other => {
                return Err(scene.error_in_body(&spec.name,
                    "shape",
                    &format!("body \"{}\": unknown generator shape \"{other}\" (sphere, cylinder, box, sphere_cap, cylinder_cap, plane)", spec.name),
                ))
            }
        };
        if !matches!(g.shape.as_str(), "box") {
            for p in &mut m.coords {
                *p = (Vec3::from(*p) + centre).into();
            }
        }
        m
    } else {
        return Err(scene.error_in_body(
            &spec.name,
            "",
            &format!("body \"{}\" has no mesh", spec.name),
        ));
    };
    transform(&mut mesh, spec);
    Ok(Some(mesh))
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
        (axis.norm() > 0.0).then(|| {
            (
                Rotation3::from_axis_angle(&Unit::new_normalize(axis), r.angle_deg.to_radians()),
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
    let mut out = Mesh::new();
    let mut new_index = vec![u32::MAX; mesh.node_count()];
    let mut kept_elements = vec![u32::MAX; mesh.element_count()];
    for e in mesh.elements() {
        let sides: Vec<i32> = e
            .nodes
            .iter()
            .filter(|&&n| n != pdcontact_importers::MISSING_NODE)
            .map(|&n| side(n))
            .collect();
        let has = |s: i32| sides.contains(&s);
        if has(1) && has(-1) {
            return Err(format!(
                "element {} crosses the symmetry plane {} = {at}: the mesh must be cut along the plane",
                e.id,
                ["x", "y", "z"][axis]
            ));
        }
        if !has(want) && e.kind.is_solid() {
            continue;
        }
        if !has(want) && !sides.iter().all(|&s| s == 0) {
            continue;
        }
        let nodes: Vec<u32> = e
            .nodes
            .iter()
            .map(|&n| {
                if n == pdcontact_importers::MISSING_NODE {
                    return n;
                }
                if new_index[n as usize] == u32::MAX {
                    new_index[n as usize] =
                        out.push_node(mesh.node_ids[n as usize], mesh.coords[n as usize]);
                }
                new_index[n as usize]
            })
            .collect();
        kept_elements[e.index as usize] = out.push_element(e.id, e.kind, &nodes);
    }
    for s in &mesh.sets {
        let mut set = s.clone();
        if let Some(nodes) = &mut set.nodes {
            *nodes = nodes
                .iter()
                .map(|&n| new_index[n as usize])
                .filter(|&n| n != u32::MAX)
                .collect();
            nodes.sort_unstable();
        }
        if let Some(elements) = &mut set.elements {
            *elements = elements
                .iter()
                .map(|&e| kept_elements[e as usize])
                .filter(|&e| e != u32::MAX)
                .collect();
        }
        out.sets.push(set);
    }
    out.warnings = mesh.warnings.clone();
    Ok(out)
}

/// Builds the body of a spec.
pub fn build_body(scene: &Scene, spec: &BodySpec) -> Result<Body> {
    let mut mesh = body_mesh(scene, spec)?;
    if let Some(m) = &mut mesh {
        for s in scene.symmetries.iter().filter(|s| s.body == spec.name) {
            let axis = match s.axis.as_str() {
                "x" => 0,
                "y" => 1,
                _ => 2,
            };
            let (lo, hi) = m.bbox().unwrap_or(([0.0; 3], [0.0; 3]));
            let tol = 1e-9 * (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
            *m = clip_mesh(m, axis, s.at, s.keep != "negative", tol).map_err(|msg| {
                scene.error_in_body(
                    &spec.name,
                    &format!("axis = \"{}\"", s.axis),
                    &format!("body \"{}\": {msg}", spec.name),
                )
            })?;
            if spec.kind == BodyKind::Deformable && m.solids().next().is_none() {
                return Err(scene.error_in_body(
                    &spec.name,
                    "",
                    &format!(
                        "body \"{}\" has no particles: the symmetry plane {} = {} (keep = \"{}\") leaves none of its elements",
                        spec.name, s.axis, s.at, s.keep
                    ),
                ));
            }
        }
    }
    match spec.kind {
        BodyKind::Deformable => {
            let Some(mesh) = mesh else {
                return Err(scene.error_in_body(
                    &spec.name,
                    "plane",
                    &format!("body \"{}\": a plane can only be rigid", spec.name),
                ));
            };
            let m = spec.material.ok_or_else(|| {
                scene.error_in_body(
                    &spec.name,
                    "",
                    &format!("body \"{}\" needs a material", spec.name),
                )
            })?;
            let symmetry = scene
                .symmetries
                .iter()
                .filter(|s| s.body == spec.name)
                .map(|s| SymmetryPlane {
                    axis: match s.axis.as_str() {
                        "x" => 0,
                        "y" => 1,
                        _ => 2,
                    },
                    at: s.at,
                })
                .collect();
            let options = CaseOptions {
                spacing: spec.spacing,
                horizon_factor: spec.horizon_factor.unwrap_or(DEFAULT_HORIZON_FACTOR),
                correction: spec
                    .surface_correction
                    .unwrap_or(CorrectionMethod::Balanced),
                symmetry,
            };
            let case = PdCase::build(mesh, options).map_err(|e| match e {
                Error::Input(msg) => {
                    scene.error_in_body(&spec.name, "", &format!("body \"{}\": {msg}", spec.name))
                }
                other => other,
            })?;
            if case.particles.is_empty() {
                return Err(scene.error_in_body(
                    &spec.name,
                    "",
                    &format!("body \"{}\" has no particles", spec.name),
                ));
            }
            let mut body = PdBody::new(
                &spec.name,
                case,
                Material {
                    youngs: m.youngs_modulus,
                    poisson: m.poisson_ratio,
                    density: m.density,
                },
            );
            body.kinematics = spec.kinematics;
            if let Some(v) = spec.velocity {
                body.set_velocity(Vec3::from(v));
            }
            Ok(Body::Deformable(Box::new(body)))
        }
        BodyKind::Rigid => {
            let (vertices, faces) = match mesh {
                Some(mesh) => rigid_faces(&mesh),
                None => plane_faces(scene, spec)?,
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
                }),
                motion: spec.motion,
                velocity: Vec3::from(spec.motion_velocity.unwrap_or([0.0; 3])),
                axis: if axis.norm() > 0.0 {
                    axis.normalize()
                } else {
                    Vec3::z()
                },
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
fn plane_faces(scene: &Scene, spec: &BodySpec) -> Result<(Vec<Vec3>, Vec<MasterSegment>)> {
    let Some(g) = &spec.generator else {
        return Err(scene.error_in_body(
            &spec.name,
            "",
            &format!("body \"{}\" has no surface", spec.name),
        ));
    };
    let (Some(point), Some(normal), Some(size)) = (g.point, g.normal, g.size) else {
        return Err(scene.error_in_body(
            &spec.name,
            "plane",
            &format!(
                "body \"{}\": a plane needs point, normal and size",
                spec.name
            ),
        ));
    };
    let n = Vec3::from(normal);
    if !(n.norm() > 0.0) || !(size > 0.0) {
        return Err(scene.error_in_body(
            &spec.name,
            "plane",
            &format!(
                "body \"{}\": plane normal and size must be non-zero",
                spec.name
            ),
        ));
    }
    let n = n.normalize();
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
    Ok((vertices, faces))
}
