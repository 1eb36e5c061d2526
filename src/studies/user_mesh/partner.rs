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
    // The far poles: a second pin on each body's axis holds it from turning about its centre.
    let mut top = shape.centre;
    top[press] = 2.0 * shape.centre[press] - shape.lowest;
    let mut bottom = shape.centre;
    bottom[press] = 2.0 * shape.lowest - top[press];
    // And a third, off the axis, held across its radius only: the spin about the pressing
    // axis, which pins on the axis leave free (the contact's small tangential forces turned
    // the two spheres opposite ways, and ADR crept for 16,000 iterations).
    let side_axis = (press + 1) % 3;
    let spin_axis = ["x", "y", "z"][3 - press - side_axis];
    let mut side = shape.centre;
    side[side_axis] += 0.5 * shape.radius;
    let mut side_copy = below;
    side_copy[side_axis] += 0.5 * shape.radius;
    let lateral: Vec<String> = (0..3)
        .filter(|&a| a != press)
        .map(|a| format!("\"{}\"", ["x", "y", "z"][a]))
        .collect();
    let lateral = lateral.join(", ");
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

[[constraint]]             # pins at the centre and the far pole of each hold them sideways
body = \"{name}\"           # and from turning; the loads balance, so they carry next to nothing
nearest = {centre}
fix = [{lateral}]

[[constraint]]
body = \"{name}\"
nearest = {top}
fix = [{lateral}]

[[constraint]]
body = \"copy\"
nearest = {below}
fix = [{lateral}]

[[constraint]]
body = \"copy\"
nearest = {bottom}
fix = [{lateral}]

[[constraint]]             # and one off the axis, across its radius, from spinning about it
body = \"{name}\"
nearest = {side}
fix = [\"{spin_axis}\"]

[[constraint]]
body = \"copy\"
nearest = {side_copy}
fix = [\"{spin_axis}\"]
",
        head = scene[..body_start].replacen(
            "against a rigid plane",
            "pressed on a turned copy of itself",
            1
        ),
        up = vector(up),
        centre = vector(shape.centre),
        below = vector(below),
        top = vector(top),
        bottom = vector(bottom),
        side = vector(side),
        side_copy = vector(side_copy),
    )
}
