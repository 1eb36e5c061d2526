//! The shape `validate --mesh` measures from a user's mesh (a sphere, or a circular cylinder
//! along x, y or z), and how far the mesh departs from it (see the parent module).

use std::path::Path;

use serde::Serialize;

use crate::error::{Error, Result};
use crate::importers::{boundary_faces, Mesh};
use crate::math::Vec3;
use crate::studies::scenarios::Problem;

/// How far the mesh may depart from the shape: extents that should agree, and boundary nodes'
/// distances from the centre (sphere) or axis (roller), relative to the radius.
pub const SHAPE_TOLERANCE: f64 = 0.03;

/// The shape measured from a mesh.
#[derive(Clone, Debug, Serialize)]
pub struct MeshShape {
    /// "sphere" or "roller".
    pub shape: String,
    /// Centre of the bounding box of the solids' corner nodes.
    pub centre: [f64; 3],
    /// Radius, m: half the largest extent across the axis (sphere: of the three).
    pub radius: f64,
    /// Roller: the axis ("x", "y" or "z").
    pub axis: Option<String>,
    /// Roller: the coordinates of its end faces along the axis.
    pub ends: Option<[f64; 2]>,
    /// The largest distance of a boundary node (end faces aside) from the sphere or the
    /// cylinder's surface, relative to the radius.
    pub max_deviation: f64,
    /// Which way the body is pressed onto the plane ("-z", or "-x" for a roller along z).
    pub pressed_along: String,
    #[serde(skip)]
    pub(super) axis_index: Option<usize>,
    #[serde(skip)]
    pub(super) press: usize,
    #[serde(skip)]
    pub(super) lowest: f64,
}

/// Measures the shape `problem` (sphere or roller) of `mesh`, read from `path`; `tol` decides
/// which nodes lie on a flat end face (the case's own tolerance for symmetry planes).
pub fn measure(mesh: &Mesh, path: &Path, problem: Problem, tol: f64) -> Result<MeshShape> {
    let corner = mesh.solid_corner_mask();
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for (n, p) in mesh.coords.iter().enumerate() {
        if corner[n] {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
    }
    if !lo[0].is_finite() {
        return Err(Error::input(format!(
            "{}: no 3D elements: validate --mesh needs a solid mesh",
            path.display()
        )));
    }
    let ext = [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]];
    let centre = [
        0.5 * (lo[0] + hi[0]),
        0.5 * (lo[1] + hi[1]),
        0.5 * (lo[2] + hi[2]),
    ];
    let faces = boundary_faces(mesh);
    let boundary = |keep: &dyn Fn(&[u32]) -> bool| -> Vec<u32> {
        let mut nodes: Vec<u32> = faces
            .boundary
            .iter()
            .filter(|f| keep(f.corners()))
            .flat_map(|f| f.corners().iter().copied())
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        nodes
    };
    let dims = format!("{:.4} × {:.4} × {:.4} m", ext[0], ext[1], ext[2]);
    match problem {
        Problem::Sphere => {
            let hint = "validate --mesh --case sphere needs a solid sphere";
            let radius = 0.5 * ext.iter().fold(0.0f64, |a, &b| a.max(b));
            let narrow = ext.iter().fold(f64::INFINITY, |a, &b| a.min(b)) / (2.0 * radius);
            if !(radius > 0.0) || narrow < 1.0 - SHAPE_TOLERANCE {
                return Err(Error::input(format!(
                    "{}: not a sphere: its bounding box is {dims}; a sphere's three extents agree within {} % ({hint})",
                    path.display(),
                    100.0 * SHAPE_TOLERANCE
                )));
            }
            let c = Vec3::from(centre);
            let off = |n: u32| (Vec3::from(mesh.coords[n as usize]) - c).norm() / radius - 1.0;
            let (node, dev) = worst(&boundary(&|_| true), off);
            if dev > SHAPE_TOLERANCE {
                return Err(Error::input(format!(
                    "{}: not a sphere: boundary node {} lies {:.4} m from the centre [{:.4}, {:.4}, {:.4}], {:+.1} % off the radius {radius:.4} m; a solid sphere's boundary nodes lie on it within {} % ({hint})",
                    path.display(),
                    mesh.node_ids[node as usize],
                    radius * (1.0 + off(node)),
                    centre[0],
                    centre[1],
                    centre[2],
                    100.0 * off(node),
                    100.0 * SHAPE_TOLERANCE
                )));
            }
            Ok(MeshShape {
                shape: "sphere".into(),
                centre,
                radius,
                axis: None,
                ends: None,
                max_deviation: dev,
                pressed_along: "-z".into(),
                axis_index: None,
                press: 2,
                lowest: lo[2],
            })
        }
        _ => {
            let hint = "validate --mesh --case roller needs a solid circular cylinder with its axis along x, y or z and flat end faces";
            let mut reasons = Vec::new();
            for k in [1, 0, 2] {
                let (i, j) = if k == 0 {
                    (1, 2)
                } else if k == 1 {
                    (0, 2)
                } else {
                    (0, 1)
                };
                let radius = 0.5 * ext[i].max(ext[j]);
                let name = ["x", "y", "z"][k];
                if !(radius > 0.0) || ext[i].min(ext[j]) / (2.0 * radius) < 1.0 - SHAPE_TOLERANCE {
                    reasons.push(format!(
                        "with its axis along {name}, its {} × {} extents {:.4} × {:.4} m are not a circle's (within {} %)",
                        ["x", "y", "z"][i],
                        ["x", "y", "z"][j],
                        ext[i],
                        ext[j],
                        100.0 * SHAPE_TOLERANCE
                    ));
                    continue;
                }
                let on_end = |n: u32| {
                    let y = mesh.coords[n as usize][k];
                    (y - lo[k]).abs() <= tol || (y - hi[k]).abs() <= tol
                };
                let side = boundary(&|f: &[u32]| !f.iter().all(|&n| on_end(n)));
                let off = |n: u32| {
                    let p = mesh.coords[n as usize];
                    (p[i] - centre[i]).hypot(p[j] - centre[j]) / radius - 1.0
                };
                let (node, dev) = worst(&side, off);
                if dev > SHAPE_TOLERANCE {
                    reasons.push(format!(
                        "with its axis along {name}, boundary node {} (off the end faces {name} = {:.4} and {:.4}) lies {:.4} m from the axis, {:+.1} % off the radius {radius:.4} m (within {} % needed)",
                        mesh.node_ids[node as usize],
                        lo[k],
                        hi[k],
                        radius * (1.0 + off(node)),
                        100.0 * off(node),
                        100.0 * SHAPE_TOLERANCE
                    ));
                    continue;
                }
                let press = if k == 2 { 0 } else { 2 };
                return Ok(MeshShape {
                    shape: "roller".into(),
                    centre,
                    radius,
                    axis: Some(name.into()),
                    ends: Some([lo[k], hi[k]]),
                    max_deviation: dev,
                    pressed_along: format!("-{}", ["x", "y", "z"][press]),
                    axis_index: Some(k),
                    press,
                    lowest: lo[press],
                });
            }
            Err(Error::input(format!(
                "{}: not a circular cylinder (bounding box {dims}): {} ({hint})",
                path.display(),
                reasons.join("; ")
            )))
        }
    }
}

/// The node of `nodes` farthest off the surface, and its `|off|`.
fn worst(nodes: &[u32], off: impl Fn(u32) -> f64) -> (u32, f64) {
    nodes
        .iter()
        .map(|&n| (n, off(n).abs()))
        .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a })
}
