//! A quasi-static run needs every loaded body held. A body that its loads push where nothing
//! holds it has no equilibrium, and ADR relaxes it until its iteration limit (a 63 s run ending
//! in "did not converge"). What can be decided before solving is refused here, naming the
//! body's line and the direction it is pushed in; what cannot (a path that misses what it is
//! in contact with, where only the particles tell) is caught in the run
//! ([`crate::solver::Unheld`]). Explicit runs are left alone: a free flight is a result there.
//!
//! A body is pushed along the part of its loads that its own supports do not hold (the axes
//! its constraints fix, and the normals of its symmetry planes, whose images balance it; for
//! a free rigid body, the part along its axis). It is refused when
//!
//! * it is in no contact pair;
//! * its contacts are all rigid planes, and no particle moved along that direction meets one
//!   from its front (a plane beside it, behind it, or too small);
//! * the bodies it is in contact with, directly or through others, hold nothing along the
//!   group's net load: no fixed rigid body, and no constraint or symmetry plane along it (two
//!   free bodies pressed together by one load move off together);
//! * the bodies it touches stay where they are (a fixed rigid body, or a body no load moves)
//!   and none lies on its path: ahead of it, and across it within a particle spacing (bounding
//!   boxes in a frame along the direction).

use crate::body::Body;
use crate::case::segments::quad_area_normal;
use crate::error::Result;
use crate::math::Vec3;
use crate::model::Model;
use crate::scene::{num, Motion, Scene};

use super::checks::is_plane;

/// Loads below this fraction of the whole are taken as balanced (rounding of the sums).
const BALANCED: f64 = 1e-9;

/// Refuses a loaded body that nothing holds (see the module documentation).
pub(super) fn check_held(scene: &Scene, model: &Model) -> Result<()> {
    if !scene.solver.kind.is_quasi_static() {
        return Ok(());
    }
    let n = scene.bodies.len();
    let index = |name: &str| scene.bodies.iter().position(|b| b.name == name);
    let mut partners: Vec<Vec<usize>> = vec![Vec::new(); n];
    for c in &scene.contacts {
        if let (Some(s), Some(m)) = (index(&c.slave), index(&c.master)) {
            partners[s].push(m);
            partners[m].push(s);
        }
    }
    for list in &mut partners {
        list.sort_unstable();
        list.dedup();
    }
    let names = |list: &[usize]| -> String {
        let quoted: Vec<String> = list
            .iter()
            .map(|&k| format!("\"{}\"", scene.bodies[k].name))
            .collect();
        quoted.join(", ")
    };
    for b in 0..n {
        let Some(d) = pushed(scene, model, b) else {
            continue;
        };
        let refuse = |d: Vec3, why: String| {
            Err(scene.block_error(
                "[[body]]",
                b,
                format!(
                    "body \"{}\" is pushed along [{}, {}, {}] by its loads, but {why}: a quasi-static run has no equilibrium; add a constraint, or a contact in that direction",
                    scene.bodies[b].name,
                    num(d.x),
                    num(d.y),
                    num(d.z),
                ),
            ))
        };
        let unheld = match &model.bodies[b] {
            Body::Rigid(_) => "it is free along its axis",
            Body::Deformable(_)
                if scene
                    .constraints
                    .iter()
                    .any(|c| c.body == scene.bodies[b].name) =>
            {
                "its constraints do not hold it in that direction"
            }
            Body::Deformable(_) => "no constraint holds it",
        };
        let list = &partners[b];
        if list.is_empty() {
            return refuse(d, format!("{unheld} and it is in no contact pair"));
        }
        let all_planes = list
            .iter()
            .all(|&m| is_plane(scene, m) && model.bodies[m].as_rigid().is_some());
        if let (true, Some(pd)) = (all_planes, model.bodies[b].as_pd()) {
            let planes: Vec<&crate::body::RigidBody> = list
                .iter()
                .filter_map(|&m| model.bodies[m].as_rigid())
                .collect();
            if !meets_a_plane(&pd.case.particles.position, d, &planes) {
                return refuse(
                    d,
                    format!(
                        "{unheld}, and its path in that direction meets no plane it is in contact with ({}: beside it, behind it, or too small)",
                        names(list)
                    ),
                );
            }
            continue;
        }
        if let Some((drift, group)) = group_drift(scene, model, &partners, b) {
            return refuse(
                drift,
                format!(
                    "{unheld}, nor do the bodies it is in contact with, directly or through others ({}): none is a fixed rigid body or constrained in that direction",
                    names(&group)
                ),
            );
        }
        let still = |m: usize| match &model.bodies[m] {
            Body::Rigid(rb) => rb.motion == Motion::Fixed,
            Body::Deformable(_) => pushed(scene, model, m).is_none(),
        };
        if list.iter().all(|&m| still(m)) && !list.iter().any(|&m| on_path(model, b, m, d)) {
            return refuse(
                d,
                format!(
                    "{unheld}, and its path in that direction meets none of the bodies it is in contact with ({}: beside it or behind it)",
                    names(list)
                ),
            );
        }
    }
    Ok(())
}

/// The unit direction the loads of body `b` push it in, less what its own supports hold;
/// `None` for an unloaded, balanced or fully held body, and for a fixed or driven rigid body.
pub(super) fn pushed(scene: &Scene, model: &Model, b: usize) -> Option<Vec3> {
    let name = &scene.bodies[b].name;
    let loads = scene.loads.iter().filter(|l| &l.body == name);
    let load: Vec3 = loads.clone().map(|l| Vec3::from(l.force)).sum();
    let scale: f64 = loads.map(|l| Vec3::from(l.force).norm()).sum();
    let free = match &model.bodies[b] {
        Body::Rigid(rb) if rb.motion == Motion::Free => rb.axis * load.dot(&rb.axis),
        Body::Rigid(_) => return None,
        Body::Deformable(_) => {
            let mut free = load;
            for a in held_axes(scene, b) {
                free[a] = 0.0;
            }
            free
        }
    };
    (free.norm() > BALANCED * scale).then(|| free.normalize())
}

/// The axes that the constraints and symmetry planes of deformable body `b` hold.
fn held_axes(scene: &Scene, b: usize) -> Vec<usize> {
    let name = &scene.bodies[b].name;
    let mut axes: Vec<usize> = scene
        .constraints
        .iter()
        .filter(|c| &c.body == name)
        .flat_map(|c| c.fix.iter().map(|a| a.index()))
        .chain(
            scene
                .symmetries
                .iter()
                .filter(|s| &s.body == name)
                .map(|s| s.axis.index()),
        )
        .collect();
    axes.sort_unstable();
    axes.dedup();
    axes
}

/// Whether a particle at `x`, moved along `d`, meets a face of one of the planes from its
/// front side.
fn meets_a_plane(x: &[Vec3], d: Vec3, planes: &[&crate::body::RigidBody]) -> bool {
    planes.iter().any(|rb| {
        rb.faces.iter().any(|face| {
            let c = face.nodes.map(|i| rb.vertices[i as usize]);
            let (_, n) = quad_area_normal(c);
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
    })
}

/// The bodies connected to `b` through contact pairs, and the direction of their net load
/// that nothing among them holds, if there is one: no fixed or driven rigid body, and no
/// constraint, symmetry plane or free rigid body's guide along it.
fn group_drift(
    scene: &Scene,
    model: &Model,
    partners: &[Vec<usize>],
    b: usize,
) -> Option<(Vec3, Vec<usize>)> {
    let mut group = vec![b];
    let mut k = 0;
    while k < group.len() {
        for &m in &partners[group[k]] {
            if !group.contains(&m) {
                group.push(m);
            }
        }
        k += 1;
    }
    // Directions held, made orthonormal.
    let mut held: Vec<Vec3> = Vec::new();
    let mut hold = |v: Vec3| {
        let r = held.iter().fold(v, |r, q| r - q * q.dot(&r));
        if r.norm() > 1e-9 {
            held.push(r.normalize());
        }
    };
    let (mut load, mut scale) = (Vec3::zeros(), 0.0);
    for &m in &group {
        match &model.bodies[m] {
            Body::Rigid(rb) if rb.motion != Motion::Free => return None,
            Body::Rigid(rb) => {
                for e in [Vec3::x(), Vec3::y(), Vec3::z()] {
                    hold(e - rb.axis * rb.axis.dot(&e));
                }
            }
            Body::Deformable(_) => {
                for a in held_axes(scene, m) {
                    hold(Vec3::ith(a, 1.0));
                }
            }
        }
        for l in scene
            .loads
            .iter()
            .filter(|l| l.body == scene.bodies[m].name)
        {
            load += Vec3::from(l.force);
            scale += Vec3::from(l.force).norm();
        }
    }
    let drift = held.iter().fold(load, |r, q| r - q * q.dot(&r));
    group.retain(|&m| m != b);
    (drift.norm() > BALANCED * scale).then(|| (drift.normalize(), group))
}

/// Whether body `m` lies on the path of body `b` moved along `d`: ahead of it, and across
/// the path within a particle spacing (bounding boxes in a frame along `d`).
fn on_path(model: &Model, b: usize, m: usize, d: Vec3) -> bool {
    let e1 = if d.x.abs() < 0.9 {
        Vec3::x()
    } else {
        Vec3::y()
    };
    let e1 = (e1 - d * d.dot(&e1)).normalize();
    let e2 = d.cross(&e1);
    let frame = [d, e1, e2];
    let boxes = |k: usize| -> ([f64; 3], [f64; 3]) {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        let mut add = |p: &Vec3| {
            for (a, e) in frame.iter().enumerate() {
                lo[a] = lo[a].min(p.dot(e));
                hi[a] = hi[a].max(p.dot(e));
            }
        };
        match &model.bodies[k] {
            Body::Deformable(pd) => pd.case.particles.position.iter().for_each(&mut add),
            Body::Rigid(rb) => rb.vertices.iter().for_each(&mut add),
        }
        (lo, hi)
    };
    let margin = [b, m]
        .iter()
        .filter_map(|&k| model.bodies[k].as_pd())
        .map(|pd| pd.spacing())
        .fold(0.0, f64::max);
    let ((blo, bhi), (mlo, mhi)) = (boxes(b), boxes(m));
    mhi[0] > blo[0] - margin
        && (1..3).all(|a| mlo[a] <= bhi[a] + margin && blo[a] <= mhi[a] + margin)
}
