//! `validate --mesh FILE --partner copy`: the scene of a mesh pressed on a copy of itself
//! (docs/VALIDATION.md, "A mesh pressed on its copy").

use super::{vector, MeshShape};

/// [`Partner::Copy`]: the rigid plane of the scene `scene` replaced by a copy of the body
/// (`name`, mesh line `quoted`, `format_line`), turned half a turn about a line across the
/// pressing direction through the contact point; the copy loaded by `total` towards the
/// body; each held sideways at its centre; two passes.
pub(super) fn copy_partner(
    scene: &str,
    name: &str,
    quoted: &str,
    format_line: &str,
    shape: &MeshShape,
    total: f64,
) -> String {
    let press = shape.press;
    let mut point = shape.centre;
    point[press] = shape.lowest;
    // The line of the half turn: across the pressing direction.
    let mut turn = [0.0; 3];
    turn[(press + 1) % 3] = 1.0;
    let mut below = shape.centre;
    below[press] = 2.0 * shape.lowest - shape.centre[press];
    let mut up = [0.0; 3];
    up[press] = total;
    // The body's block is the scene's up to the plane's; keep the body's lines (and its
    // options) for the copy.
    let body_start = scene.find("[[body]]").unwrap_or(0);
    let plane_start = scene
        .find("[[body]]\nname = \"plane\"")
        .unwrap_or(scene.len());
    let body_block = &scene[body_start..plane_start];
    let copy_block = body_block
        .replacen(&format!("name = \"{name}\""), "name = \"copy\"", 1)
        .replacen(
            &format!("mesh = {quoted}\n{format_line}"),
            &format!(
                "mesh = {quoted}\n{format_line}rotate = {{ axis = {}, angle_deg = 180.0, center = {} }}   # half a turn about a line through the contact point\n",
                vector(turn),
                vector(point)
            ),
            1,
        );
    let after_plane = scene[plane_start..]
        .find("[[load]]")
        .map_or("", |k| &scene[plane_start + k..]);
    let after_plane = after_plane
        .replace(
            "master = \"plane\"",
            "master = \"copy\"\ntwo_pass = true           # both bodies' particles against the other's surface",
        );
    format!(
        "{head}{body_block}{copy_block}{after_plane}
[[load]]
body = \"copy\"              # spread over the copy by volume, towards the body
force = {up}
{pins}",
        head = scene[..body_start].replacen(
            "against a rigid plane",
            "pressed on a turned copy of itself",
            1
        ),
        up = vector(up),
        pins = [(name, shape.centre), ("copy", below)]
            .iter()
            .map(|&(body, centre)| pins(body, centre, shape))
            .collect::<String>(),
    )
}

/// Where along a body's axis [`pins`] holds it sideways, as multiples of the radius from its
/// centre away from the contact: from half a radius short of the centre to the far pole.
const AXIS_PINS: [f64; 7] = [-0.5, -0.25, 0.0, 0.25, 0.5, 0.75, 1.0];

/// The `[[constraint]]`s that hold body `body` (centre `centre`, pressed along `shape.press`
/// towards the contact) from sliding, tilting and spinning, where frictionless spheres
/// pressed together are free to (their loads balance along the axis, which nothing holds).
///
/// Each holds what the axisymmetric solution leaves at rest, so that they carry next to
/// nothing: the particles nearest the axis at [`AXIS_PINS`] held across it, and four in the
/// centre's plane, half a radius out, held across their radius (the hoop direction). A pin
/// or two per direction held the pair as soft springs, a particle's bonds each: the two
/// bodies' slide and turn, which the segments' small tangential forces drive, was then ADR's
/// slowest mode and the static solver's worst, up to 7.6 times the ADR iterations on the
/// rigid plane (docs/VALIDATION.md, "A mesh pressed on its copy").
fn pins(body: &str, centre: [f64; 3], shape: &MeshShape) -> String {
    let press = shape.press;
    let name = ["x", "y", "z"];
    // The two directions across the axis.
    let (side_axis, spin_axis) = ((press + 1) % 3, (press + 2) % 3);
    let lateral = format!(
        "\"{}\", \"{}\"",
        name[side_axis.min(spin_axis)],
        name[side_axis.max(spin_axis)]
    );
    // Away from the contact point (at `shape.lowest` along the axis): the body's centre lies
    // above it, the copy's below.
    let away = if centre[press] > shape.lowest {
        1.0
    } else {
        -1.0
    };
    let mut out = format!(
        "\n# \"{body}\": pins where the axisymmetric solution is at rest hold it from sliding, tilting\n# and spinning; the loads balance, so they carry next to nothing. On its axis, across it:\n"
    );
    let pin = |p: [f64; 3], fix: &str| {
        format!(
            "\n[[constraint]]\nbody = \"{body}\"\nnearest = {}\nfix = [{fix}]\n",
            vector(p)
        )
    };
    for t in AXIS_PINS {
        let mut p = centre;
        p[press] += away * t * shape.radius;
        out += &pin(p, &lateral);
    }
    out += "\n# Round its centre, half a radius out, across their radius:\n";
    for (axis, across) in [(side_axis, spin_axis), (spin_axis, side_axis)] {
        for sign in [1.0, -1.0] {
            let mut p = centre;
            p[axis] += sign * 0.5 * shape.radius;
            out += &pin(p, &format!("\"{}\"", name[across]));
        }
    }
    out
}

/// The `[[constraint]]`s that hold a sphere or roller on `validate --mesh`'s rigid plane
/// from what a frictionless plane leaves free, for the static solver: sliding across the
/// pressing direction and turning about it (a roller, plane strain, held along its axis by
/// its end faces: sliding across it and rolling about it). ADR's path keeps those modes at
/// rest (the loads and the plane's forces have no part along them); Newton's inexact steps do
/// not, and a whole sphere slid 1-2.5 cm, a sixth to a third of a spacing, to the same
/// figures. As many single-direction pins as free modes, at the particles nearest the
/// centre and half a radius from it: a statically determinate support, so at equilibrium
/// they carry nothing (no load has a part along the modes they hold), and the figures are
/// ADR's. Pins where the axisymmetric solution is at rest, as the copy's ([`pins`]), hold
/// more than the free modes: on the stored tet4 sphere at ν = 0.3 they moved the contact
/// radius by 2 points.
pub(super) fn plane_pins(body: &str, shape: &MeshShape) -> String {
    let press = shape.press;
    let name = ["x", "y", "z"];
    let pin = |p: [f64; 3], fix: usize| {
        format!(
            "\n[[constraint]]\nbody = \"{body}\"\nnearest = {}\nfix = [\"{}\"]\n",
            vector(p),
            name[fix]
        )
    };
    let mut out = format!(
        "\n# \"{body}\": pins for the static solver, one per motion a frictionless plane leaves free;\n# they carry nothing at equilibrium.\n"
    );
    let centre = shape.centre;
    let offset = |axis: usize| {
        let mut p = centre;
        p[axis] += 0.5 * shape.radius;
        p
    };
    match shape.axis_index {
        // Across the roller's axis and the pressing direction: sliding, and rolling about
        // the axis (the pin above the centre).
        Some(k) => {
            let across = 3 - press - k;
            out += &pin(centre, across);
            let above = if centre[press] > shape.lowest {
                1.0
            } else {
                -1.0
            };
            let mut p = centre;
            p[press] += above * 0.5 * shape.radius;
            out += &pin(p, across);
        }
        // Across the pressing direction: sliding both ways, and turning about it.
        None => {
            let (a, b) = ((press + 1) % 3, (press + 2) % 3);
            out += &pin(centre, a);
            out += &pin(centre, b);
            out += &pin(offset(a), b);
        }
    }
    out
}
