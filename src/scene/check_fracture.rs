//! The scene checks of bond failure: the fracture keys of a material and the pre-cracks
//! (METHOD.md §9, [`crate::body::fracture`]).

use super::{excerpt, num, BodyKind, BodySpec, MaterialSpec, Result, Scene, SelfFaces};
use crate::error::Error;
use crate::math::Vec3;

/// `fracture_energy` and `critical_stretch` of body `b`'s material `m`: one of them, positive,
/// on a bond-based body; `err` points at a key of the body.
pub(super) fn fracture_keys(
    b: &BodySpec,
    m: &MaterialSpec,
    err: &dyn Fn(&str, String) -> Error,
) -> Result<()> {
    if let (Some(_), Some(_)) = (m.fracture_energy, m.critical_stretch) {
        return Err(err(
            "critical_stretch",
            format!(
                "body \"{}\": give fracture_energy or critical_stretch, not both (the critical stretch follows from the fracture energy)",
                b.name
            ),
        ));
    }
    if m.failure.is_some() && m.fracture_energy.is_none() && m.critical_stretch.is_none() {
        return Err(err(
            "failure",
            format!(
                "body \"{}\": failure chooses how bonds fail; give fracture_energy or critical_stretch as well, or leave failure out",
                b.name
            ),
        ));
    }
    for (what, v) in [
        ("fracture_energy", m.fracture_energy),
        ("critical_stretch", m.critical_stretch),
    ] {
        let Some(v) = v else { continue };
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
    Ok(())
}

impl Scene {
    /// Every `[[precrack]]`: a deformable body, a finite patch with a normal and a
    /// side not along it, positive sizes, not on one of the body's symmetry planes.
    /// `body(name, needle)` finds a body or says that none has the name.
    pub(super) fn check_precracks<'a>(
        &'a self,
        body: &dyn Fn(&str, &str) -> Result<&'a BodySpec>,
    ) -> Result<()> {
        for (k, c) in self.precracks.iter().enumerate() {
            let b = body(&c.body, &format!("body = \"{}\"", c.body))?;
            let perr = |msg: String| self.block_error("[[precrack]]", k, msg);
            if b.kind == BodyKind::Rigid {
                return Err(perr(format!(
                    "precrack in rigid body \"{}\": a rigid body has no bonds to cut",
                    c.body
                )));
            }
            let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
            if !(finite(&c.point) && finite(&c.normal) && finite(&c.along)) {
                return Err(perr(format!(
                    "precrack in \"{}\": point, normal and along must be finite",
                    excerpt(&c.body)
                )));
            }
            let (n, a) = (Vec3::from(c.normal), Vec3::from(c.along));
            if n.norm() == 0.0 || a.cross(&n).norm() <= 1e-9 * a.norm() * n.norm() {
                return Err(perr(format!(
                    "precrack in \"{}\": expected a non-zero normal and an `along` direction not parallel to it, got normal [{}, {}, {}] and along [{}, {}, {}]",
                    excerpt(&c.body),
                    num(c.normal[0]),
                    num(c.normal[1]),
                    num(c.normal[2]),
                    num(c.along[0]),
                    num(c.along[1]),
                    num(c.along[2])
                )));
            }
            // A crack on a symmetry plane cannot open: the particles on the plane are held
            // on it, and stay bonded to the body's side.
            if let Some(plane) = self.symmetries.iter().find(|s| {
                s.body == c.body
                    && n.cross(&Vec3::ith(s.axis.index(), 1.0)).norm() <= 1e-9 * n.norm()
                    && (c.point[s.axis.index()] - s.at).abs()
                        <= 1e-9 * c.size[0].abs().max(c.size[1].abs())
            }) {
                return Err(perr(format!(
                    "precrack in \"{}\" lies on its symmetry plane {} = {}: a crack there cannot open, since the particles on the plane are held on it and stay bonded to the body; model both sides of the crack (drop that [[symmetry]]) or put the crack off the plane",
                    excerpt(&c.body),
                    plane.axis.name(),
                    num(plane.at)
                )));
            }
            if !c.size.iter().all(|&l| l > 0.0 && l.is_finite()) {
                return Err(perr(format!(
                    "precrack in \"{}\": size = [length along `along`, length across] must be positive, got [{}, {}]",
                    excerpt(&c.body),
                    num(c.size[0]),
                    num(c.size[1])
                )));
            }
        }
        Ok(())
    }
}

impl Scene {
    /// Whether the bonds of body `name` fail (its material has a fracture energy or a
    /// critical stretch).
    pub fn breaks(&self, name: &str) -> bool {
        self.bodies
            .iter()
            .find(|b| b.name == name)
            .and_then(|b| b.material.as_ref())
            .is_some_and(|m| m.fracture_energy.is_some() || m.critical_stretch.is_some())
    }

    /// A pair of two bodies has no `faces` to choose.
    pub(super) fn check_two_body_faces(
        c: &super::ContactSpec,
        err: &dyn Fn(&str, String) -> Error,
    ) -> Result<()> {
        match c.faces {
            Some(f) => Err(err(
                "faces",
                format!(
                    "faces = \"{}\" is for a body that is its own master (slave = master): this pair has two bodies (leave faces out)",
                    f.name()
                ),
            )),
            None => Ok(()),
        }
    }

    /// Which faces the point-to-surface pair `c` of a body with itself presses on: its
    /// `faces`, or by default its pre-cracks' where it has one, the surfaces its broken bonds
    /// open where they fail; `None` for a pair of two bodies, the short-range method, or a
    /// body that neither (its mesh's pieces against each other).
    pub fn self_faces(&self, c: &super::ContactSpec) -> Option<SelfFaces> {
        if c.slave != c.master || c.method == super::ContactMethod::ShortRange {
            return None;
        }
        c.faces.or_else(|| {
            if self.precracks.iter().any(|p| p.body == c.slave) {
                Some(SelfFaces::Precrack)
            } else if self.breaks(&c.slave) {
                Some(SelfFaces::Found)
            } else {
                None
            }
        })
    }

    /// A `[[contact]]` whose slave and master are one body: with the short-range method the
    /// pieces of a body whose bonds fail ([`crate::contact::fragments`]); otherwise the faces
    /// of that body's pre-cracks pressed together ([`crate::case::crack_faces`]), or without
    /// one its pieces against each other ([`crate::contact::ContactPass::pieces`]); no
    /// friction yet; `err` points at a key of the block.
    pub(super) fn check_self_contact(
        &self,
        c: &super::ContactSpec,
        err: &dyn Fn(&str, String) -> Error,
    ) -> Result<()> {
        let slave = format!("slave = \"{}\"", c.slave);
        let breaks = self.breaks(&c.slave);
        let precracked = self.precracks.iter().any(|p| p.body == c.slave);
        if c.method == super::ContactMethod::ShortRange {
            if let Some(f) = c.faces {
                return Err(err(
                    "faces",
                    format!(
                        "faces = \"{}\" chooses the point-to-surface method's master segments; the short-range method has none (leave faces out)",
                        f.name()
                    ),
                ));
            }
            if breaks || precracked {
                return Ok(());
            }
            return Err(err(
                &slave,
                format!(
                    "contact pair names body \"{}\" as both slave and master with the short-range method: that keeps the pieces of a breaking body apart, and \"{}\" cannot break (give its material fracture_energy or critical_stretch, or a [[precrack]])",
                    excerpt(&c.slave),
                    excerpt(&c.slave)
                ),
            ));
        }
        // Without a pre-crack the body's pieces (solids of its mesh that no bond joins) are
        // each other's masters: whether a mesh has two is known once its bonds are
        // ([`crate::model::Model::from_scene`]); a generated shape is one.
        let generated = self
            .bodies
            .iter()
            .find(|b| b.name == c.slave)
            .is_some_and(|b| b.mesh.is_none());
        if c.faces == Some(SelfFaces::Precrack) && !precracked {
            return Err(err(
                "faces",
                format!(
                    "faces = \"precrack\" presses the faces of \"{}\"'s pre-cracks together, and it has no [[precrack]] (faces = \"found\" presses on the surfaces its broken bonds open)",
                    excerpt(&c.slave)
                ),
            ));
        }
        if generated && !precracked && !breaks && c.faces.is_none() {
            return Err(err(
                &slave,
                format!(
                    "contact pair names body \"{}\" as both slave and master: a body is its own master across the faces of its pre-cracks or between the pieces of its mesh (solids that share no node), and \"{}\" has no [[precrack]] and is a generated shape, one piece (contact between two bodies names two)",
                    excerpt(&c.slave),
                    excerpt(&c.slave)
                ),
            ));
        }
        if c.friction > 0.0 {
            return Err(err(
                "friction",
                format!(
                    "friction between \"{}\" and itself (the faces of its pre-cracks, or its pieces) is not implemented yet: that contact is frictionless (leave friction out)",
                    excerpt(&c.slave)
                ),
            ));
        }
        Ok(())
    }
}
