//! Every check of a scene that serde cannot make: names, references, values, and the
//! dimensions of the built-in shapes. Each error points at the line of the scene it concerns.

use pdcontact_importers::Format;

use super::{
    excerpt, locate, locate_in_body, num, BodyKind, BodySpec, ContactMethod, GeneratorSpec,
    MaterialModel, Motion, Scene, LPS_MAX_POISSON,
};
use crate::case::DEFAULT_HORIZON_FACTOR;
use crate::error::{Error, Result};
use crate::math::Vec3;

impl Scene {
    /// Checks what serde cannot: names, references, values.
    pub(super) fn check(&self, text: &str) -> Result<()> {
        let at = |needle: &str| locate(text, needle);
        let err = |needle: &str, msg: String| {
            let (l, c) = at(needle);
            Error::input(format!("{}:{l}:{c}: {msg}", self.source))
        };
        // An error at the `k`-th (0-based) block headed `header`.
        let block_err = |header: &str, k: usize, msg: String| self.block_error(header, k, msg);
        if self.bodies.is_empty() {
            return Err(err("", "the scene has no [[body]]".to_string()));
        }
        for (k, b) in self.bodies.iter().enumerate() {
            let key = format!("name = \"{}\"", b.name);
            let err = |needle: &str, msg: String| {
                let (l, c) = locate_in_body(text, &b.name, needle);
                Error::input(format!("{}:{l}:{c}: {msg}", self.source))
            };
            if b.name.chars().count() > MAX_NAME_CHARS {
                return Err(err(
                    "name",
                    format!(
                        "body name \"{}\" is too long: at most {MAX_NAME_CHARS} characters",
                        excerpt(&b.name)
                    ),
                ));
            }
            if self.bodies[..k].iter().any(|o| o.name == b.name) {
                return Err(err(&key, format!("two bodies are named \"{}\"", b.name)));
            }
            match (&b.mesh, &b.generator) {
                (None, None) => {
                    return Err(err(
                        &key,
                        format!("body \"{}\" needs `mesh` or `generator`", b.name),
                    ))
                }
                (Some(_), Some(_)) => {
                    return Err(err(
                        &key,
                        format!(
                            "body \"{}\" has both `mesh` and `generator`: keep one",
                            b.name
                        ),
                    ))
                }
                _ => {}
            }
            if b.kind == BodyKind::Deformable {
                let Some(m) = &b.material else {
                    return Err(err(
                        &key,
                        format!("deformable body \"{}\" needs a [body.material]", b.name),
                    ));
                };
                for (what, v) in [("youngs_modulus", m.youngs_modulus), ("density", m.density)] {
                    if !(v > 0.0 && v.is_finite()) {
                        return Err(err(
                            what,
                            format!(
                                "body \"{}\": {what} must be positive, got {}",
                                b.name,
                                num(v)
                            ),
                        ));
                    }
                }
                if m.model != MaterialModel::Lps && m.influence_function.is_some() {
                    return Err(err(
                        "influence_function",
                        format!(
                            "body \"{}\": influence_function is the linear peridynamic solid's (model = \"lps\" in [body.material]); bond-based PD here has none to choose",
                            b.name
                        ),
                    ));
                }
                super::check_fracture::fracture_keys(b, m, &err)?;
                match m.model {
                    MaterialModel::BondBased if (m.poisson_ratio - 0.25).abs() > 1e-9 => {
                        return Err(err(
                            "poisson_ratio",
                            format!(
                                "body \"{}\": bond-based peridynamics fixes Poisson's ratio at 0.25, got {} (use 0.25, or model = \"lps\" in [body.material] for any ratio)",
                                b.name, num(m.poisson_ratio)
                            ),
                        ));
                    }
                    MaterialModel::Lps
                        if !(m.poisson_ratio > -1.0 && m.poisson_ratio <= LPS_MAX_POISSON) =>
                    {
                        return Err(err(
                            "poisson_ratio",
                            format!(
                                "body \"{}\": the linear peridynamic solid takes Poisson's ratio in (-1, {LPS_MAX_POISSON}], got {}{}",
                                b.name,
                                num(m.poisson_ratio),
                                if m.poisson_ratio > LPS_MAX_POISSON && m.poisson_ratio < 1.0 {
                                    " (nearer 0.5 the bulk modulus outgrows the shear modulus so far that the dilatation locks the solution; a nearly incompressible material needs a mixed formulation this program does not have)"
                                } else {
                                    ""
                                }
                            ),
                        ));
                    }
                    _ => {}
                }
            }
            if let Some(m) = &b.material {
                for (what, v) in [("youngs_modulus", m.youngs_modulus), ("density", m.density)] {
                    if !(v > 0.0 && v.is_finite()) {
                        return Err(err(
                            what,
                            format!(
                                "body \"{}\": {what} must be positive, got {}",
                                b.name,
                                num(v)
                            ),
                        ));
                    }
                }
            }
            for (what, v) in [
                ("spacing", b.spacing),
                ("horizon_factor", b.horizon_factor),
                ("scale", b.scale),
            ] {
                if let Some(v) = v {
                    if !(v > 0.0 && v.is_finite()) {
                        return Err(err(
                            what,
                            format!(
                                "body \"{}\": {what} must be positive, got {}",
                                b.name,
                                num(v)
                            ),
                        ));
                    }
                }
            }
            // Vectors: finite, and directions not zero.
            let mut vectors: Vec<(&str, [f64; 3], bool)> = Vec::new();
            for (what, v) in [
                ("translate", b.translate),
                ("velocity", b.velocity),
                ("motion_velocity", b.motion_velocity),
                ("displacement", b.displacement),
            ] {
                if let Some(v) = v {
                    vectors.push((what, v, false));
                }
            }
            if let Some(a) = b.free_axis {
                vectors.push(("free_axis", a, true));
            }
            if let Some(r) = &b.rotate {
                vectors.push(("axis", r.axis, true));
                if let Some(c) = r.center {
                    vectors.push(("center", c, false));
                }
                if !r.angle_deg.is_finite() {
                    return Err(err(
                        "angle_deg",
                        format!(
                            "body \"{}\": rotate angle_deg must be finite, got {}",
                            b.name,
                            num(r.angle_deg)
                        ),
                    ));
                }
            }
            if let Some(g) = &b.generator {
                for (what, v, dir) in [
                    ("point", g.point, false),
                    ("normal", g.normal, true),
                    ("center", g.center, false),
                ] {
                    if let Some(v) = v {
                        vectors.push((what, v, dir));
                    }
                }
            }
            for (what, v, direction) in vectors {
                if v.iter().any(|x| !x.is_finite()) {
                    return Err(err(
                        what,
                        format!(
                            "body \"{}\": {what} must be three finite numbers, got [{}, {}, {}]",
                            b.name,
                            num(v[0]),
                            num(v[1]),
                            num(v[2])
                        ),
                    ));
                }
                if direction && v.iter().all(|&x| x == 0.0) {
                    return Err(err(
                        what,
                        format!(
                            "body \"{}\": {what} is a direction and cannot be [0, 0, 0]",
                            b.name
                        ),
                    ));
                }
            }
            if let Some(m) = b.horizon_factor {
                if m < 1.0 {
                    return Err(err(
                        "horizon_factor",
                        format!("body \"{}\": horizon_factor must be at least 1 (a horizon shorter than the spacing holds no bonds), got {}", b.name, num(m)),
                    ));
                }
            }
            if let Some(m) = b.mass {
                if !(m > 0.0 && m.is_finite()) {
                    return Err(err(
                        "mass",
                        format!("body \"{}\": mass must be positive, got {}", b.name, num(m)),
                    ));
                }
            }
            if b.kind == BodyKind::Rigid {
                match b.motion {
                    Motion::Velocity if b.motion_velocity.is_none() => {
                        return Err(err(&key, format!("rigid body \"{}\": motion = \"velocity\" needs motion_velocity = [vx, vy, vz]", b.name)))
                    }
                    Motion::Free if b.free_axis.is_none() => {
                        return Err(err(&key, format!("rigid body \"{}\": motion = \"free\" needs free_axis = [ax, ay, az]", b.name)))
                    }
                    Motion::Displacement if b.displacement.is_none() => {
                        return Err(err(&key, format!("rigid body \"{}\": motion = \"displacement\" needs displacement = [dx, dy, dz]", b.name)))
                    }
                    Motion::Displacement if !self.solver.kind.is_quasi_static() => {
                        return Err(err("displacement =", format!("rigid body \"{}\": motion = \"displacement\" is displacement control in a quasi-static run, in the solver's load_steps increments: use kind = \"adr\" or \"static\" in [solver] (an explicit run drives a body with motion = \"velocity\")", b.name)))
                    }
                    _ => {}
                }
            }
            check_shape(b, &err)?;
        }
        let body = |name: &str, needle: &str| -> Result<&BodySpec> {
            self.bodies.iter().find(|b| b.name == name).ok_or_else(|| {
                let names: Vec<String> = self
                    .bodies
                    .iter()
                    .map(|b| format!("\"{}\"", excerpt(&b.name)))
                    .collect();
                err(
                    needle,
                    format!(
                        "no body is named \"{}\" (the scene's bodies: {})",
                        excerpt(name),
                        names.join(", ")
                    ),
                )
            })
        };
        for (k, l) in self.loads.iter().enumerate() {
            body(&l.body, &format!("body = \"{}\"", l.body))?;
            if l.force.iter().any(|f| !(f.abs() <= MAX_FORCE)) {
                let [x, y, z] = l.force.map(num);
                return Err(block_err(
                    "[[load]]",
                    k,
                    format!("load on \"{}\": force must be finite and at most {} N per component, got [{x}, {y}, {z}]", excerpt(&l.body), num(MAX_FORCE)),
                ));
            }
        }
        for (k, c) in self.constraints.iter().enumerate() {
            let b = body(&c.body, &format!("body = \"{}\"", c.body))?;
            match (&c.set, &c.nearest) {
                (Some(_), None) => {}
                (None, Some(p)) if p.iter().all(|x| x.is_finite()) => {}
                (None, Some(p)) => {
                    let [x, y, z] = p.map(num);
                    return Err(block_err(
                        "[[constraint]]",
                        k,
                        format!("constraint on \"{}\": nearest must be a finite point [x, y, z], got [{x}, {y}, {z}]", excerpt(&c.body)),
                    ));
                }
                (set, nearest) => {
                    return Err(block_err(
                        "[[constraint]]",
                        k,
                        format!(
                            "constraint on \"{}\": expected one of `set = \"NAME\"` (a named set of the mesh) and `nearest = [x, y, z]` (the particle nearest a point), found {}",
                            excerpt(&c.body),
                            if set.is_some() && nearest.is_some() { "both" } else { "neither" }
                        ),
                    ));
                }
            }
            if b.kind == BodyKind::Rigid {
                return Err(err(
                    "fix",
                    format!("constraint on rigid body \"{}\": use its `motion`", c.body),
                ));
            }
        }
        for (k, s) in self.symmetries.iter().enumerate() {
            let b = body(&s.body, &format!("body = \"{}\"", s.body))?;
            if let Some(first) = self.symmetries[..k]
                .iter()
                .position(|o| o.body == s.body && o.axis == s.axis && o.at == s.at)
            {
                return Err(block_err(
                    "[[symmetry]]",
                    k,
                    format!(
                        "body \"{}\": the symmetry plane {} = {} is listed twice ([[symmetry]] blocks {} and {}): keep one",
                        s.body,
                        s.axis.name(),
                        num(s.at),
                        first + 1,
                        k + 1
                    ),
                ));
            }
            if b.kind == BodyKind::Rigid {
                return Err(err(
                    "axis",
                    format!(
                        "symmetry plane on rigid body \"{}\": rigid bodies need none",
                        s.body
                    ),
                ));
            }
        }
        self.check_precracks(&body)?;
        self.check_path()?;
        for (k, c) in self.contacts.iter().enumerate() {
            let same = |o: &super::ContactSpec| {
                (o.slave == c.slave && o.master == c.master)
                    || ((o.two_pass || c.two_pass) && o.slave == c.master && o.master == c.slave)
            };
            if let Some(first) = self.contacts[..k].iter().position(same) {
                return Err(block_err(
                    "[[contact]]",
                    k,
                    format!(
                        "the contact pair \"{}\" / \"{}\" is listed twice ([[contact]] blocks {} and {}): its penalty would act twice; keep one (two_pass = true checks both ways)",
                        excerpt(&c.slave),
                        excerpt(&c.master),
                        first + 1,
                        k + 1
                    ),
                ));
            }
            let s = body(&c.slave, &format!("slave = \"{}\"", c.slave))?;
            body(&c.master, &format!("master = \"{}\"", c.master))?;
            if let Some(r) = c.radius {
                if !(r > 0.0 && r.is_finite()) {
                    return Err(err(
                        "radius",
                        format!(
                            "contact radius (the Hertz penalty's R) must be positive, got {}",
                            num(r)
                        ),
                    ));
                }
            }
            if c.slave == c.master {
                // At the key within this pair's block (its body's name is in others too).
                let start = text
                    .match_indices("[[contact]]")
                    .nth(k)
                    .map_or(0, |(p, _)| p);
                let in_block = |needle: &str, msg: String| {
                    let at = text[start..].find(needle).map_or(start, |p| start + p);
                    let (l, c) = super::line_col(text, at);
                    Error::input(format!("{}:{l}:{c}: {msg}", self.source))
                };
                self.check_self_contact(c, &in_block)?;
            } else {
                Self::check_two_body_faces(c, &err)?;
            }
            if s.kind == BodyKind::Rigid {
                return Err(err(
                    &format!("slave = \"{}\"", c.slave),
                    format!("slave \"{}\" is rigid: the slave must be deformable (swap slave and master)", c.slave),
                ));
            }
            if c.method == ContactMethod::ShortRange {
                let m = body(&c.master, &format!("master = \"{}\"", c.master))?;
                let needle = if self.text.contains("short_range") {
                    "short_range"
                } else {
                    "short-range"
                };
                if m.kind == BodyKind::Rigid {
                    return Err(err(
                        needle,
                        format!("the short-range method pushes particles apart, and the rigid master \"{}\" has none: use method = \"point-to-surface\" or a deformable master", c.master),
                    ));
                }
                if c.radius.is_some() {
                    return Err(err(
                        "radius",
                        "radius sets the Hertz penalty of the point-to-surface method; the short-range method has no penalty radius".to_string(),
                    ));
                }
            }
        }
        self.check_solver(&err)?;
        if self.output.every == 0 {
            return Err(err("every", "output.every must be at least 1".to_string()));
        }
        Ok(())
    }
}

/// Longest body name: names are repeated in messages and output files.
const MAX_NAME_CHARS: usize = 64;

/// Largest load component, N. Far beyond any physical load (the weight of Mount Everest is
/// about 1e15 N), while leaving f64 room for the squares and sums of forces that the solvers
/// form (a force of 1e300 overflows them and used to be reported as "too few iterations").
const MAX_FORCE: f64 = 1e30;

/// Bytes that `particles` PD particles with horizon factor `m` take, roughly: per particle
/// about 400 B of state (a dozen 3-vectors, volumes, masks, correction factors), and per bond
/// 24 B (partner, length, state) times the `4/3 π m³` bonds of a lattice particle.
pub(crate) fn memory_bytes(particles: f64, m: f64) -> f64 {
    particles * (400.0 + 24.0 * 4.0 / 3.0 * std::f64::consts::PI * m.powi(3))
}

/// The most memory a model may need, bytes: `PDCONTACT_MEMORY_LIMIT` (bytes) where set, else
/// this machine's memory (`/proc/meminfo`; 64 GiB where it cannot be read).
pub(crate) fn memory_limit() -> f64 {
    if let Some(b) = std::env::var("PDCONTACT_MEMORY_LIMIT")
        .ok()
        .and_then(|v| v.trim().parse::<f64>().ok())
        .filter(|b| *b > 0.0)
    {
        return b;
    }
    std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("MemTotal:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        })
        .map_or(64.0 * (1u64 << 30) as f64, |kb| kb * 1024.0)
}

/// "12.3 GB".
fn gigabytes(bytes: f64) -> String {
    format!("{} GB", count(bytes / 1e9))
}

/// A count as a message shows it: "about 4.19e9", "about 720", or "more than 1e308" where
/// f64 overflowed.
fn count(x: f64) -> String {
    if !x.is_finite() {
        "more than 1e308".to_string()
    } else if x >= 1e4 {
        format!("about {x:.2e}")
    } else {
        format!("about {}", num((x * 10.0).round() / 10.0))
    }
}

/// The keys each generator shape reads; any other is refused.
fn shape_keys(shape: &str) -> Option<&'static [&'static str]> {
    Some(match shape {
        "sphere" => &["radius", "spacing", "center"],
        "cylinder" => &["radius", "length", "spacing", "center"],
        "box" => &["min", "max", "spacing"],
        "sphere_cap" => &["radius", "half_width", "depth", "spacing", "center"],
        "cylinder_cap" => &[
            "radius",
            "half_width",
            "depth",
            "length",
            "spacing",
            "center",
        ],
        "plane" => &["point", "normal", "size", "divisions"],
        _ => return None,
    })
}

/// The optional keys a generator gives.
fn given_keys(g: &GeneratorSpec) -> Vec<&'static str> {
    [
        ("radius", g.radius.is_some()),
        ("length", g.length.is_some()),
        ("spacing", g.spacing.is_some()),
        ("min", g.min.is_some()),
        ("max", g.max.is_some()),
        ("point", g.point.is_some()),
        ("normal", g.normal.is_some()),
        ("size", g.size.is_some()),
        ("divisions", g.divisions.is_some()),
        ("center", g.center.is_some()),
        ("half_width", g.half_width.is_some()),
        ("depth", g.depth.is_some()),
    ]
    .into_iter()
    .filter_map(|(k, given)| given.then_some(k))
    .collect()
}

/// The checks of a body's mesh or built-in shape that need no file: the mesh format's name,
/// the generator's dimensions, a plane's point, normal and size. `err` points at a key of the
/// body.
fn check_shape(b: &BodySpec, err: &dyn Fn(&str, String) -> Error) -> Result<()> {
    if let (Some(_), Some(f)) = (&b.mesh, &b.format) {
        if Format::from_name(f).is_none() {
            return Err(err(
                "format",
                format!(
                    "unknown mesh format \"{}\": use cdb, msh or inp",
                    excerpt(f)
                ),
            ));
        }
    }
    let Some(g) = &b.generator else {
        return Ok(());
    };
    if let Some(keys) = shape_keys(&g.shape) {
        if let Some(k) = given_keys(g).into_iter().find(|k| !keys.contains(k)) {
            let hint = if k == "spacing" && g.shape == "plane" {
                " (a rigid plane has no particles)"
            } else {
                ""
            };
            return Err(err(
                k,
                format!(
                    "body \"{}\": generator \"{}\" does not use `{k}`{hint}; it takes {}",
                    b.name,
                    g.shape,
                    keys.join(", ")
                ),
            ));
        }
    }
    if g.divisions == Some(0) {
        return Err(err(
            "divisions",
            format!("body \"{}\": divisions must be at least 1, got 0", b.name),
        ));
    }
    let need = |v: Option<f64>, what: &str| {
        v.filter(|x| *x > 0.0 && x.is_finite()).ok_or_else(|| {
            err(
                "generator",
                format!(
                    "body \"{}\": generator \"{}\" needs a positive {what}",
                    b.name, g.shape
                ),
            )
        })
    };
    let spacing = g.spacing.or(b.spacing);
    // Volume of a solid shape, m³, for the particle count; a plane returns when checked.
    let volume = match g.shape.as_str() {
        "sphere" => {
            let r = need(g.radius, "radius")?;
            need(spacing, "spacing")?;
            4.0 / 3.0 * std::f64::consts::PI * r.powi(3)
        }
        "cylinder" => {
            let r = need(g.radius, "radius")?;
            let l = need(g.length, "length")?;
            need(spacing, "spacing")?;
            std::f64::consts::PI * r * r * l
        }
        "box" => {
            let (Some(lo), Some(hi)) = (box_corner(&g.min), box_corner(&g.max)) else {
                return Err(err("generator", format!("body \"{}\": a box needs min and max, three numbers each", b.name)));
            };
            if lo.iter().chain(&hi).any(|x| !x.is_finite()) {
                return Err(err("generator", format!("body \"{}\": box min and max must be finite numbers", b.name)));
            }
            if (0..3).any(|k| hi[k] <= lo[k]) {
                return Err(err("generator", format!("body \"{}\": box max must exceed min on every axis", b.name)));
            }
            need(spacing, "spacing")?;
            (0..3).map(|k| hi[k] - lo[k]).product()
        }
        "sphere_cap" | "cylinder_cap" => {
            let r = need(g.radius, "radius")?;
            let half_width = need(g.half_width, "half_width")?;
            if half_width >= r {
                return Err(err("half_width", format!("body \"{}\": a cap's half_width must be less than its radius", b.name)));
            }
            let depth = need(g.depth, "depth")?;
            if depth >= r {
                return Err(err("depth", format!("body \"{}\": a cap's depth must be less than its radius", b.name)));
            }
            need(spacing, "spacing")?;
            if g.shape == "cylinder_cap" {
                let l = need(g.length, "length (the slice thickness along y)")?;
                2.0 * half_width * l * depth
            } else {
                4.0 * half_width * half_width * depth
            }
        }
        "plane" => {
            if b.kind == BodyKind::Deformable {
                return Err(err(
                    "plane",
                    format!("body \"{}\": a plane can only be rigid", b.name),
                ));
            }
            let (Some(_), Some(normal), Some(size)) = (g.point, g.normal, g.size) else {
                return Err(err(
                    "plane",
                    format!(
                        "body \"{}\": a plane needs point, normal and size",
                        b.name
                    ),
                ));
            };
            if !(Vec3::from(normal).amax() > 0.0 && size > 0.0 && size.is_finite()) {
                return Err(err(
                    "plane",
                    format!(
                        "body \"{}\": plane normal must be non-zero and size positive, got size {}",
                        b.name,
                        num(size)
                    ),
                ));
            }
            // (d+1)² vertices of 24 B and d² faces of 48 B (nodes, area, normal).
            let d = g.divisions.unwrap_or(1) as f64;
            let bytes = (d + 1.0).powi(2) * 24.0 + d * d * 48.0;
            let limit = memory_limit();
            if bytes > limit {
                return Err(err(
                    "divisions",
                    format!(
                        "body \"{}\": divisions = {} makes {} faces, {} of memory; the limit is {} (this machine's memory, or PDCONTACT_MEMORY_LIMIT)",
                        b.name,
                        g.divisions.unwrap_or(1),
                        num(d * d),
                        gigabytes(bytes),
                        gigabytes(limit)
                    ),
                ));
            }
            return Ok(());
        }
        other => {
            return Err(err(
                "shape",
                format!("body \"{}\": unknown generator shape \"{}\" (sphere, cylinder, box, sphere_cap, cylinder_cap, plane)", b.name, excerpt(other)),
            ))
        }
    };
    // Refused before the generator allocates: more particles than 32-bit indices hold, or
    // than this machine's memory.
    let dx = spacing.expect("spacing checked above");
    let particles = volume / dx.powi(3);
    let m = b.horizon_factor.unwrap_or(DEFAULT_HORIZON_FACTOR);
    let bytes = memory_bytes(particles, m);
    let limit = memory_limit();
    if !(particles < u32::MAX as f64 && bytes <= limit) {
        return Err(err(
            "spacing",
            format!(
                "body \"{}\": spacing {} makes {} particles, {} of memory (horizon factor {}); the limit is {} (this machine's memory, or PDCONTACT_MEMORY_LIMIT): raise the spacing",
                b.name,
                num(dx),
                count(particles),
                gigabytes(bytes),
                num(m),
                gigabytes(limit)
            ),
        ));
    }
    Ok(())
}

/// A box generator's corner: three numbers.
pub(crate) fn box_corner(v: &Option<Vec<f64>>) -> Option<[f64; 3]> {
    v.as_ref()
        .filter(|v| v.len() == 3)
        .map(|v| [v[0], v[1], v[2]])
}
