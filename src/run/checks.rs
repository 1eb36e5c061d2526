//! The checks of a scene that need its model built (meshes read, particles, surfaces,
//! contact passes), made before solving: each refuses with the scene line it concerns.
//! `held.rs`: the loaded bodies that nothing holds.

use crate::body::Body;
use crate::case::segments::quad_area_normal;
use crate::contact::overlap::overlap;
use crate::contact::{MasterView, WINDOW};
use crate::error::{Error, Result};
use crate::math::Vec3;
use crate::model::Model;
use crate::scene::{num, Scene};

/// Every check below, in the order that names the cause best: a plane placed absurdly
/// before the side it faces, a backwards plane before the particles behind it.
pub(super) fn check_model(scene: &Scene, model: &Model) -> Result<()> {
    check_planes(scene, model)?;
    check_plane_sides(scene, model)?;
    check_overlaps(scene, model)?;
    check_split(model)?;
    super::held::check_held(scene, model)
}

/// Refuses a body whose bonds leave a solid of its mesh in pieces: an element longer than
/// the bonds reach ([`crate::case::unbonded`]). Its pieces would pass through each other,
/// and a contact of the body with itself would push on faces inside one solid.
fn check_split(model: &Model) -> Result<()> {
    for pd in model.bodies.iter().filter_map(|b| b.as_pd()) {
        if let Some(split) = &pd.case.split {
            return Err(Error::input(format!(
                "body \"{}\": {}",
                pd.name,
                split.message(pd.spacing(), pd.case.horizon_factor)
            )));
        }
    }
    Ok(())
}

/// Whether the `k`-th body of the scene is a generated rigid plane.
pub(super) fn is_plane(scene: &Scene, k: usize) -> bool {
    scene.bodies[k]
        .generator
        .as_ref()
        .is_some_and(|g| g.shape == "plane")
}

/// A number to three significant digits, as messages show it.
pub(super) fn short(x: f64) -> String {
    num(format!("{x:.2e}").parse().unwrap_or(x))
}

/// How far a plane's size and distance may depart from the scene's other bodies: a plane
/// needs to be little larger than what it touches and near it. Far beyond this factor its
/// faces' areas and normals over- or underflow (`size = 1e300` made NaN normals, and the
/// run blamed the body's path; `point = [0, 0, 1e300]` was reported as a backwards plane).
const PLANE_RANGE: f64 = 1e6;

/// Refuses a rigid plane whose size (`size` times `scale`) is not finite or lies outside
/// [`PLANE_RANGE`] times the extent of the scene's other bodies either way, or that lies
/// farther than that from them, at the key that sets it.
fn check_planes(scene: &Scene, model: &Model) -> Result<()> {
    // The bounding box of every body but the planes: particles and rigid mesh vertices.
    let (mut lo, mut hi) = (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY));
    for (k, b) in model.bodies.iter().enumerate() {
        let points: Box<dyn Iterator<Item = Vec3>> = match b {
            Body::Deformable(pd) => Box::new(pd.case.particles.position.iter().copied()),
            Body::Rigid(_) if is_plane(scene, k) => continue,
            Body::Rigid(rb) => Box::new(rb.vertices.iter().copied()),
        };
        for p in points {
            lo = lo.inf(&p);
            hi = hi.sup(&p);
        }
    }
    let extent = (hi - lo).norm();
    if !(extent > 0.0 && extent.is_finite()) {
        return Ok(());
    }
    for (k, spec) in scene.bodies.iter().enumerate() {
        let (true, Some(rb), Some(g)) = (
            is_plane(scene, k),
            model.bodies[k].as_rigid(),
            spec.generator.as_ref(),
        ) else {
            continue;
        };
        let size = g.size.unwrap_or(0.0) * spec.scale.unwrap_or(1.0);
        let (key, what) = if spec.scale.is_some() {
            ("scale", "size times scale")
        } else {
            ("size", "size")
        };
        // The plane's centre, and how far its nearest edge lies from the bodies' box.
        let (mut plo, mut phi) = (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY));
        for p in &rb.vertices {
            plo = plo.inf(p);
            phi = phi.sup(p);
        }
        let centre = plo * 0.5 + phi * 0.5;
        let outside = crate::math::length(centre - centre.sup(&lo).inf(&hi));
        let gap = outside - size * std::f64::consts::FRAC_1_SQRT_2;
        if !(gap <= PLANE_RANGE * extent) {
            let key = if spec.translate.is_some() {
                "translate"
            } else {
                "point"
            };
            return Err(scene.error_in_body(
                &spec.name,
                key,
                &format!(
                    "body \"{}\": the plane lies {} m from the scene's other bodies ({} m across), more than {} times their extent: it can touch nothing; check its point{}",
                    spec.name,
                    short(gap),
                    short(extent),
                    num(PLANE_RANGE),
                    if key == "translate" { " and translate" } else { "" }
                ),
            ));
        }
        let faces_ok = rb.faces.iter().all(|f| {
            let (a, n) = quad_area_normal(f.nodes.map(|i| rb.vertices[i as usize]));
            a > 0.0 && a.is_finite() && n.iter().all(|c| c.is_finite())
        });
        let within = |x: f64| x <= PLANE_RANGE * extent && x * PLANE_RANGE >= extent;
        if !(size.is_finite() && within(size) && faces_ok) {
            return Err(scene.error_in_body(
                &spec.name,
                key,
                &format!(
                    "body \"{}\": the plane's {what} {} is out of scale with the scene's other bodies ({} m across): a plane from {} to {} times their extent is supported (it needs to be a little larger than what it touches)",
                    spec.name,
                    num(size),
                    short(extent),
                    num(1.0 / PLANE_RANGE),
                    num(PLANE_RANGE)
                ),
            ));
        }
    }
    Ok(())
}

/// A rigid plane whose normal points away from its slave body pushes the slave through itself:
/// refused before solving when most of the slave's particles lie behind the plane.
fn check_plane_sides(scene: &Scene, model: &Model) -> Result<()> {
    for (k, c) in scene.contacts.iter().enumerate() {
        let index = |name: &str| scene.bodies.iter().position(|b| b.name == name);
        let (Some(s), Some(m)) = (index(&c.slave), index(&c.master)) else {
            continue;
        };
        let (Some(pd), Some(rb)) = (model.bodies[s].as_pd(), model.bodies[m].as_rigid()) else {
            continue;
        };
        let (true, Some(face)) = (is_plane(scene, m), rb.faces.first()) else {
            continue;
        };
        // From the placed vertices: the plane may have been rotated after its faces were made.
        let corners = face.nodes.map(|i| rb.vertices[i as usize]);
        let (_, n) = quad_area_normal(corners);
        let p = corners[0];
        let x = &pd.case.particles.position;
        let behind = x.iter().filter(|&&q| (q - p).dot(&n) < 0.0).count();
        if 2 * behind > x.len() {
            // Two mistakes give this: a normal the wrong way, or the plane put on the far side
            // of the body (or through it). Where the plane would stand clear of the body
            // under its normal as given.
            let deepest = x.iter().map(|&q| (q - p).dot(&n)).fold(0.0, f64::min);
            let centre = corners.iter().fold(Vec3::zeros(), |a, c| a + c) / 4.0;
            let clear = centre + n * deepest;
            return Err(scene.block_error(
                "[[contact]]",
                k,
                format!(
                "contact pair \"{}\" / \"{}\": {behind} of {} particles of \"{}\" lie behind the plane \"{}\" (on the side its normal [{}, {}, {}] points away from): the normal must point out of the plane toward the slave (flip it), or, if the normal is as meant, the plane stands on the wrong side of the body or through it (its point would clear the body at [{}, {}, {}])",
                c.slave,
                c.master,
                x.len(),
                c.slave,
                c.master,
                num(n.x),
                num(n.y),
                num(n.z),
                num(clear.x),
                num(clear.y),
                num(clear.z),
                ),
            ));
        }
    }
    Ok(())
}

/// Bodies of a contact pair that start interpenetrating: surface particles of the slave (and,
/// for a two-pass pair, of the master) that lie inside the other body, or behind a rigid
/// plane within its extent, deeper than the contact window 0.5Δ. The penalty pushes back only
/// what lies within the window; deeper, the first iteration would stop on a missed contact
/// and blame the load, or miss the particles altogether. Bodies placed touching, or a few
/// particles within the window, are accepted.
fn check_overlaps(scene: &Scene, model: &Model) -> Result<()> {
    for (k, c) in scene.contacts.iter().enumerate() {
        let index = |name: &str| scene.bodies.iter().position(|b| b.name == name);
        let (Some(s), Some(m)) = (index(&c.slave), index(&c.master)) else {
            continue;
        };
        // A body's crack faces touch from the start, where the body was whole.
        if s == m {
            continue;
        }
        let mut directions = vec![(s, m)];
        if c.two_pass && model.bodies[m].as_pd().is_some() {
            directions.push((m, s));
        }
        for (a, b) in directions {
            let Some(pd) = model.bodies[a].as_pd() else {
                continue;
            };
            let window = WINDOW * pd.spacing();
            let found = overlap(pd, MasterView::of(&model.bodies[b]), window);
            if found.count == 0 {
                continue;
            }
            let (name, other) = (model.bodies[a].name(), model.bodies[b].name());
            let place = if is_plane(scene, b) {
                format!("behind the plane \"{other}\"")
            } else {
                format!("inside \"{other}\"")
            };
            return Err(scene.block_error(
                "[[contact]]",
                k,
                format!(
                    "contact pair \"{}\" / \"{}\": the bodies start interpenetrating: {} of {} surface particles of \"{name}\" lie {place}, up to {} m deep, beyond the contact window ({} Δ = {} m) within which the penalty pushes back; move them apart (touching is fine)",
                    c.slave,
                    c.master,
                    found.count,
                    found.of,
                    short(found.deepest),
                    num(WINDOW),
                    short(window)
                ),
            ));
        }
    }
    Ok(())
}

/// A master coarser than this many slave spacings is what one pass is for: its pressure is
/// read coarsely anyway. Finer, one pass leaves a pressure the master's own mesh could show.
const ONE_PASS_RATIO: f64 = 2.0;

/// Warnings for contact pairs of two deformable bodies checked one way only (`two_pass`
/// off) whose master is about as fine as the slave: the master's contact pressure is then its
/// reactions to the slaves alone, and reads rough. Measured on twelve pairs of gmsh spheres
/// pressed together (docs/VALIDATION.md, "One pass, and pairs of other sizes"): the slave's
/// figures are its mesh's either way, the master's MRE 2.2-12.7 % with one pass against
/// 1.45-4.1 % with two.
pub(super) fn one_pass_warnings(scene: &Scene, model: &Model) -> Vec<String> {
    let index = |name: &str| scene.bodies.iter().position(|b| b.name == name);
    scene
        .contacts
        .iter()
        .filter(|c| !c.two_pass && c.method == crate::scene::ContactMethod::PointToSurface)
        // A crack's faces are each other's slaves already.
        .filter(|c| c.slave != c.master)
        .filter_map(|c| {
            let (s, m) = (index(&c.slave)?, index(&c.master)?);
            let (sb, mb) = (model.bodies[s].as_pd()?, model.bodies[m].as_pd()?);
            (mb.spacing() < ONE_PASS_RATIO * sb.spacing()).then(|| {
                format!(
                    "contact \"{}\"/\"{}\": two deformable bodies checked one way (two_pass = false) with a master about as fine as the slave (Δ = {} m against {} m): the master's contact pressure comes from its reactions to the slave's particles alone and reads rough; set two_pass = true to read both bodies' pressure (docs/VALIDATION.md, \"Two deformable bodies\")",
                    c.slave,
                    c.master,
                    short(mb.spacing()),
                    short(sb.spacing())
                )
            })
        })
        .collect()
}

/// Warnings for bodies of several pieces that no bond joins (solids of one mesh that share
/// no node) and that no contact keeps apart: a contact acts between bodies, or between a
/// body's pieces only where a `[[contact]]` names the body as its own slave and master
/// ([`crate::contact::ContactPass::pieces`]); without one the pieces pass through each other.
pub(super) fn piece_warnings(scene: &Scene, model: &Model) -> Vec<String> {
    model
        .bodies
        .iter()
        .filter_map(|b| b.as_pd())
        .filter(|pd| {
            // A pre-crack's faces have warnings and errors of their own.
            !scene.precracks.iter().any(|p| p.body == pd.name)
                && !scene
                    .contacts
                    .iter()
                    .any(|c| c.slave == pd.name && c.master == pd.name)
        })
        .filter_map(|pd| {
            let (_, sizes) = pd.case.bonds.components(|_| true);
            let solid = sizes.iter().filter(|&&n| n >= MIN_PIECE).count();
            (solid > 1).then(|| {
                format!(
                    "body \"{}\" is {solid} pieces that no bond joins (solids of its mesh that share no node; {} particles in the largest, {} in the next) and no contact keeps them apart: they pass through each other; add a [[contact]] with slave = \"{}\" and master = \"{}\" (its pieces against each other), or mesh each in a file of its own as a body of its own",
                    pd.name, sizes[0], sizes[1], pd.name, pd.name
                )
            })
        })
        .collect()
}

/// The fewest particles of a piece that [`piece_warnings`] counts as a solid (fewer are
/// particles a coarse horizon left without a bond, which the run refuses by itself).
const MIN_PIECE: usize = 4;

/// Warnings for bodies of the linear peridynamic solid in a contact where its figures fall
/// short (docs/VALIDATION.md, "Any Poisson's ratio"; the Hertz sphere on gmsh tet4): without
/// the skin correction a contact comes out 6-10 % too wide; with it, above ν = 0.35, 3-4 %
/// too narrow with a peak 13-14 % high (within 3 % at ν = 0.3).
pub(super) fn lps_contact_warnings(scene: &Scene, model: &Model) -> Vec<String> {
    model
        .bodies
        .iter()
        .filter_map(|b| b.as_pd())
        .filter(|pd| pd.lps.is_some())
        .filter(|pd| {
            scene
                .contacts
                .iter()
                .any(|c| c.slave != c.master && (c.slave == pd.name || c.master == pd.name))
        })
        .filter_map(|pd| {
            // Asked for, it is on the faces a partner faces alone (`body::facing`).
            let asked = scene
                .bodies
                .iter()
                .find(|b| b.name == pd.name)
                .and_then(|b| b.skin_correction)
                .unwrap_or(true);
            let skin = pd.lps.as_ref().is_some_and(|l| l.skin);
            let nu = pd.material.poisson;
            if !asked {
                Some(format!(
                    "body \"{}\": model = \"lps\" without the skin correction: a contact on its surface comes out 6-10 % too wide on a gmsh tet sphere (docs/VALIDATION.md, \"Any Poisson's ratio\"); drop skin_correction = false",
                    pd.name
                ))
            } else if !skin {
                Some(format!(
                    "body \"{}\": model = \"lps\": none of its surface faces a body it is in a contact with as the scene places them, so none takes the skin correction (it goes on the faces within {}° of a partner's nearest point), and a contact that reaches it later comes out 6-10 % too wide on a gmsh tet sphere (docs/VALIDATION.md, \"The skin where a partner can press\"); place the bodies so that the faces to be pressed face each other",
                    pd.name,
                    crate::body::facing::FACING_CONE_DEG
                ))
            } else if nu > LPS_SKIN_NU {
                Some(format!(
                    "body \"{}\": model = \"lps\" at ν = {nu}: above {LPS_SKIN_NU} its skin correction over-stiffens a contact, 3-4 % too narrow with a peak 13-14 % above Hertz's on a gmsh tet sphere at ν = 0.4 (docs/VALIDATION.md, \"Any Poisson's ratio\")",
                    pd.name
                ))
            } else {
                None
            }
        })
        .collect()
}

/// The Poisson's ratio up to which the LPS skin correction was measured to hold the Hertz
/// sphere within 3 % (0.3 holds, 0.4 does not).
const LPS_SKIN_NU: f64 = 0.35;

/// After a run that did not find equilibrium: the pre-crack whose faces passed through each
/// other, which nothing pressed together (no `[[contact]]` names the body as its own master),
/// named with the deepest pair of particles (the message of a numerical failure), and how
/// deep, in the body's spacings; `None` where no face crossed.
pub fn crossed_cracks(model: &Model, scene: &Scene) -> Option<(String, f64)> {
    for body in &model.bodies {
        let Some(pd) = body.as_pd() else { continue };
        let Some((k, a, b, depth)) = pd.crossed_crack() else {
            continue;
        };
        let pressed = scene
            .contacts
            .iter()
            .any(|c| c.slave == pd.name && c.master == pd.name);
        let why = if pressed {
            "though their contact pressed them together: the load is more than the crack faces' penalty holds"
        } else {
            "nothing presses the faces of a pre-crack together unless a [[contact]] names the body as its own slave and master"
        };
        let (xa, xb) = (pd.reference[a as usize], pd.reference[b as usize]);
        let spacings = depth / pd.spacing();
        // Where the run failed, not what was read: a numerical failure at the block's line.
        return Some((
            scene
                .block_error(
                        "[[precrack]]",
                        k,
                        format!(
                            "the faces of this pre-crack in \"{}\" passed through each other: particle {b} (at [{}, {}, {}]) lies {} m ({spacings:.2} Δ) behind particle {a} (at [{}, {}, {}]) across the crack; {why}",
                            pd.name,
                            num(xb.x),
                            num(xb.y),
                            num(xb.z),
                            num(depth),
                            num(xa.x),
                            num(xa.y),
                            num(xa.z),
                        ),
                    )
                .to_string(),
            spacings,
        ));
    }
    None
}

/// Where a quasi-static run that did not settle left its out-of-balance force: the particle
/// that carries the most of it (its free components, as the residual counts them), and the
/// contact force on it. A contact there that comes and goes or slides back and forth between
/// iterations (a slave at a face's edge or corner) is what a user can act on; "too few
/// iterations" alone is not. The run keeps no history of that contact, so the message names
/// both readings: on the tet10 block cut at 30° the contacts there held for thousands of
/// iterations while the top crept (docs/FRACTURE.md). `None` where no force is left.
pub fn unbalanced(model: &Model) -> Option<String> {
    let mut total = 0.0;
    let mut best: Option<(f64, &crate::body::PdBody, usize)> = None;
    for pd in model.bodies.iter().filter_map(Body::as_pd) {
        for i in pd.owned.clone() {
            let f = pd.force[i]
                .component_mul(&crate::solver::free_factor(pd.fixed[i]))
                .norm_squared();
            total += f;
            if best.is_none_or(|b| f > b.0) {
                best = Some((f, pd, i));
            }
        }
    }
    let (f, pd, i) = best?;
    if !(f > 0.0) {
        return None;
    }
    let x = pd.reference[i];
    let mut m = format!(
        "the largest out-of-balance force, {:.3e} N ({:.0} % of the residual's square), is on particle {i} of \"{}\" at [{}, {}, {}]",
        f.sqrt(),
        100.0 * f / total,
        pd.name,
        num(x.x),
        num(x.y),
        num(x.z)
    );
    let contact = pd.contact_force[i].norm();
    if contact > 0.0 {
        m.push_str(&format!(
            ", which a contact pushes with {contact:.3e} N: either that contact comes and goes, or slides back and forth, between iterations (a slave at a face's edge or corner), which keeps the run from settling, or it holds and the residual falls slowly there"
        ));
    } else if let Some(piece) = falling_piece(pd, i) {
        m.push_str(&piece);
    }
    Some(m)
}

/// The piece of `pd` (particles joined by intact bonds) that holds particle `i`, where that
/// piece touches nothing and most of its load is out of balance: it is still on its way to
/// whatever it will rest on. ADR moves such a piece at the speed its load over its damped
/// fictitious mass allows, and that mass follows the stiffness of its particles' bonds, so a
/// small piece of fine particles that starts apart travels slowly (a corpus CDB of one
/// element per piece: 6 particles 73 mm above the plane, 0.25 µm an iteration). Saying so
/// names the cause; "raise max_iterations" alone does not.
fn falling_piece(pd: &crate::body::PdBody, i: usize) -> Option<String> {
    let bonds = &pd.case.bonds;
    let (labels, sizes) = match &pd.fracture {
        Some(f) => f.fragment_labels(bonds),
        None => bonds.components(|_| true),
    };
    let piece = labels[i];
    let (mut load, mut out, mut moved, mut centre, mut n) = (
        Vec3::zeros(),
        Vec3::zeros(),
        Vec3::zeros(),
        Vec3::zeros(),
        0usize,
    );
    for j in pd.owned.clone().filter(|&j| labels[j] == piece) {
        if pd.contact_force[j].norm() > 0.0 {
            return None;
        }
        let free = crate::solver::free_factor(pd.fixed[j]);
        load += pd.load[j].component_mul(&free);
        out += pd.force[j].component_mul(&free);
        moved += pd.u[j];
        centre += pd.reference[j];
        n += 1;
    }
    // Most of the load unbalanced and along it: the piece is carried by nothing.
    if n == 0 || !(load.norm() > 0.0) || out.dot(&load) < 0.5 * load.norm_squared() {
        return None;
    }
    let (moved, centre) = (moved / n as f64, centre / n as f64);
    // Its direction to two decimals, without a "-0.00" for a component that is nil.
    let along = moved
        .map(|c| c / moved.norm().max(f64::MIN_POSITIVE))
        .map(|c| if c.abs() < 0.005 { 0.0 } else { c });
    let whole = if sizes.len() > 1 {
        format!("one of its {} pieces that no bond joins", sizes.len())
    } else {
        "the whole body".to_string()
    };
    Some(format!(
        "; that particle's piece ({n} particles about [{}, {}, {}], {whole}) touches nothing and {:.0} % of its load, {:.3e} N, is out of balance: it is still on its way to what it will rest on (it has moved {:.3e} m so far, along [{:.2}, {:.2}, {:.2}]). A piece that starts apart closes slowly under ADR, the more slowly the finer its particles, and not by Newton's steps, whose tangent nothing holds it in: start it in touch with what holds it, or hold it",
        num(centre.x),
        num(centre.y),
        num(centre.z),
        100.0 * out.dot(&load) / load.norm_squared(),
        load.norm(),
        moved.norm(),
        along.x,
        along.y,
        along.z,
    ))
}
