//! A quasi-static run needs every loaded body held: what can be decided before solving.

use crate::error::Result;
use crate::math::Vec3;
use crate::model::Model;
use crate::scene::Scene;

/// A quasi-static run needs every loaded body held: an unconstrained body whose only contacts
/// are rigid planes that its loads do not push it onto (a plane beside it or behind it, or one
/// its path misses) has no equilibrium, and ADR would relax until its iteration limit. Refused
/// before solving, naming the body and the direction of its loads. Bodies in contact with
/// another deformable body, constrained bodies and explicit runs (where a free flight is a
/// result) are left alone.
pub(super) fn check_held(scene: &Scene, model: &Model) -> Result<()> {
    if scene.solver.kind != crate::scene::SolverKind::Adr {
        return Ok(());
    }
    for (b, spec) in scene.bodies.iter().enumerate() {
        let Some(pd) = model.bodies[b].as_pd() else {
            continue;
        };
        let load: Vec3 = scene
            .loads
            .iter()
            .filter(|l| l.body == spec.name)
            .map(|l| Vec3::from(l.force))
            .sum();
        if load.norm() == 0.0 || scene.constraints.iter().any(|c| c.body == spec.name) {
            continue;
        }
        let d = load.normalize();
        let mut planes = Vec::new();
        let mut undecided = false;
        for c in scene.contacts.iter() {
            let other = if c.slave == spec.name {
                &c.master
            } else if c.master == spec.name {
                &c.slave
            } else {
                continue;
            };
            let Some(m) = scene.bodies.iter().position(|x| &x.name == other) else {
                continue;
            };
            let is_plane = scene.bodies[m]
                .generator
                .as_ref()
                .is_some_and(|g| g.shape == "plane");
            match (is_plane, model.bodies[m].as_rigid()) {
                (true, Some(rb)) if !rb.faces.is_empty() => planes.push((other, rb)),
                _ => undecided = true,
            }
        }
        if undecided {
            continue;
        }
        // Held if some particle, moved along d, meets a face of a plane from its front side.
        let x = &pd.case.particles.position;
        let held = planes.iter().any(|(_, rb)| {
            rb.faces.iter().any(|face| {
                let c = face.nodes.map(|i| rb.vertices[i as usize]);
                let (_, n) = crate::case::segments::quad_area_normal(c);
                let dn = d.dot(&n);
                if dn >= -1e-9 {
                    return false;
                }
                x.iter().any(|&q| {
                    let t = (c[0] - q).dot(&n) / dn;
                    let hit = q + d * t;
                    // Inside the quad: on the inner side of its four edges.
                    t >= 0.0
                        && (0..4).all(|e| {
                            let (a, b) = (c[e], c[(e + 1) % 4]);
                            (b - a).cross(&(hit - a)).dot(&n) >= -1e-9 * (b - a).norm_squared()
                        })
                })
            })
        });
        if !held {
            let why = if planes.is_empty() {
                "no constraint holds it and it is in no contact pair".to_string()
            } else {
                let names: Vec<String> = planes.iter().map(|(n, _)| format!("\"{n}\"")).collect();
                format!(
                    "no constraint holds it, and its path in that direction meets no plane it is in contact with ({}: beside it, behind it, or too small)",
                    names.join(", ")
                )
            };
            return Err(scene.block_error(
                "[[body]]",
                b,
                format!(
                "body \"{}\" is pushed along [{}, {}, {}] by its loads, but {why}: a quasi-static run has no equilibrium; add a constraint, or a contact in that direction",
                spec.name,
                crate::scene::num(d.x),
                crate::scene::num(d.y),
                crate::scene::num(d.z),
                ),
            ));
        }
    }
    Ok(())
}
