//! Every check of a scene that serde cannot make: names, references, values, and the
//! dimensions of the built-in shapes. Each error points at the line of the scene it concerns.

use pdcontact_importers::Format;

use super::{locate, locate_in_body, BodyKind, BodySpec, ContactMethod, Motion, Scene, SolverKind};
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
        if self.bodies.is_empty() {
            return Err(err("", "the scene has no [[body]]".to_string()));
        }
        for (k, b) in self.bodies.iter().enumerate() {
            let key = format!("name = \"{}\"", b.name);
            let err = |needle: &str, msg: String| {
                let (l, c) = locate_in_body(text, &b.name, needle);
                Error::input(format!("{}:{l}:{c}: {msg}", self.source))
            };
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
                            format!("body \"{}\": {what} must be positive, got {v}", b.name),
                        ));
                    }
                }
                if (m.poisson_ratio - 0.25).abs() > 1e-9 {
                    return Err(err(
                        "poisson_ratio",
                        format!(
                            "body \"{}\": bond-based peridynamics fixes Poisson's ratio at 0.25, got {} (use 0.25)",
                            b.name, m.poisson_ratio
                        ),
                    ));
                }
            }
            if let Some(m) = &b.material {
                for (what, v) in [("youngs_modulus", m.youngs_modulus), ("density", m.density)] {
                    if !(v > 0.0 && v.is_finite()) {
                        return Err(err(
                            what,
                            format!("body \"{}\": {what} must be positive, got {v}", b.name),
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
                            format!("body \"{}\": {what} must be positive, got {v}", b.name),
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
                            b.name, r.angle_deg
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
                            "body \"{}\": {what} must be three finite numbers, got {v:?}",
                            b.name
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
                        format!("body \"{}\": horizon_factor must be at least 1 (a horizon shorter than the spacing holds no bonds), got {m}", b.name),
                    ));
                }
            }
            if let Some(m) = b.mass {
                if !(m > 0.0 && m.is_finite()) {
                    return Err(err(
                        "mass",
                        format!("body \"{}\": mass must be positive, got {m}", b.name),
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
                    _ => {}
                }
            }
            check_shape(b, &err)?;
        }
        let body = |name: &str, needle: &str| -> Result<&BodySpec> {
            self.bodies
                .iter()
                .find(|b| b.name == name)
                .ok_or_else(|| err(needle, format!("no body is named \"{name}\"")))
        };
        for l in &self.loads {
            body(&l.body, &format!("body = \"{}\"", l.body))?;
            if l.force.iter().any(|f| !f.is_finite()) {
                return Err(err("force", "load force must be finite".to_string()));
            }
        }
        for c in &self.constraints {
            let b = body(&c.body, &format!("body = \"{}\"", c.body))?;
            if b.kind == BodyKind::Rigid {
                return Err(err(
                    "fix",
                    format!("constraint on rigid body \"{}\": use its `motion`", c.body),
                ));
            }
        }
        for s in &self.symmetries {
            let b = body(&s.body, &format!("body = \"{}\"", s.body))?;
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
        for c in &self.contacts {
            let s = body(&c.slave, &format!("slave = \"{}\"", c.slave))?;
            body(&c.master, &format!("master = \"{}\"", c.master))?;
            if let Some(r) = c.radius {
                if !(r > 0.0 && r.is_finite()) {
                    return Err(err(
                        "radius",
                        format!("contact radius (the Hertz penalty's R) must be positive, got {r}"),
                    ));
                }
            }
            if c.slave == c.master {
                return Err(err(
                    &format!("slave = \"{}\"", c.slave),
                    format!(
                        "contact pair names body \"{}\" as both slave and master",
                        c.slave
                    ),
                ));
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
        match self.solver.kind {
            SolverKind::Adr => {
                if let Some(t) = self.solver.tolerance {
                    if !(t > 0.0 && t < 1.0) {
                        return Err(err(
                            "tolerance",
                            format!("tolerance must be in (0, 1), got {t}"),
                        ));
                    }
                }
                if self.solver.load_steps == Some(0) {
                    return Err(err(
                        "load_steps",
                        "load_steps must be at least 1, got 0".to_string(),
                    ));
                }
            }
            SolverKind::Explicit => {
                match self.solver.end_time {
                    None => {
                        return Err(err("kind", "an explicit solver needs end_time".to_string()))
                    }
                    Some(t) if !(t > 0.0 && t.is_finite()) => {
                        return Err(err(
                            "end_time",
                            format!("end_time must be positive, got {t}"),
                        ))
                    }
                    _ => {}
                }
                if let Some(dt) = self.solver.dt {
                    if !(dt > 0.0 && dt.is_finite()) {
                        return Err(err("dt", format!("dt must be positive, got {dt}")));
                    }
                }
            }
        }
        if self.output.every == 0 {
            return Err(err("every", "output.every must be at least 1".to_string()));
        }
        Ok(())
    }
}

/// The checks of a body's mesh or built-in shape that need no file: the mesh format's name,
/// the generator's dimensions, a plane's point, normal and size. `err` points at a key of the
/// body.
fn check_shape(b: &BodySpec, err: &dyn Fn(&str, String) -> Error) -> Result<()> {
    if let (Some(_), Some(f)) = (&b.mesh, &b.format) {
        if Format::from_name(f).is_none() {
            return Err(err(
                "format",
                format!("unknown mesh format \"{f}\": use cdb, msh or inp"),
            ));
        }
    }
    let Some(g) = &b.generator else {
        return Ok(());
    };
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
    match g.shape.as_str() {
        "sphere" => {
            need(g.radius, "radius")?;
            need(spacing, "spacing")?;
        }
        "cylinder" => {
            need(g.radius, "radius")?;
            need(g.length, "length")?;
            need(spacing, "spacing")?;
        }
        "box" => {
            let (Some(lo), Some(hi)) = (box_corner(&g.min), box_corner(&g.max)) else {
                return Err(err("generator", format!("body \"{}\": a box needs min and max, three numbers each", b.name)));
            };
            if (0..3).any(|k| hi[k] <= lo[k]) {
                return Err(err("generator", format!("body \"{}\": box max must exceed min on every axis", b.name)));
            }
            need(spacing, "spacing")?;
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
            if g.shape == "cylinder_cap" {
                need(g.length, "length (the slice thickness along y)")?;
            }
            need(spacing, "spacing")?;
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
            if !(Vec3::from(normal).norm() > 0.0) || !(size > 0.0) {
                return Err(err(
                    "plane",
                    format!(
                        "body \"{}\": plane normal and size must be non-zero",
                        b.name
                    ),
                ));
            }
        }
        other => {
            return Err(err(
                "shape",
                format!("body \"{}\": unknown generator shape \"{other}\" (sphere, cylinder, box, sphere_cap, cylinder_cap, plane)", b.name),
            ))
        }
    }
    Ok(())
}

/// A box generator's corner: three numbers.
pub(crate) fn box_corner(v: &Option<Vec<f64>>) -> Option<[f64; 3]> {
    v.as_ref()
        .filter(|v| v.len() == 3)
        .map(|v| [v[0], v[1], v[2]])
}
