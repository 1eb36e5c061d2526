//! The skeleton's supports and solver: the pins that hold a body on the frictionless plane,
//! the contact that keeps a body's pieces apart, and the `[solver]` block.

use super::SkeletonLoad;
use crate::case::PdCase;

/// The pins that hold the body sideways on the frictionless plane, three to each piece (the
/// centre of its bounding box, the top of its vertical axis, a point off the axis held across
/// it), and where the mesh is several solids that share no node, the contact that keeps its
/// pieces apart ([`crate::contact::ContactPass::pieces`]).
/// `label` and `solid` are [`solids`]'s.
pub(super) fn pins_and_pieces(
    case: &PdCase,
    skeleton: &SkeletonLoad,
    (label, solid): &(Vec<u32>, Vec<usize>),
) -> String {
    let n = case.particles.len();
    let boxes: Vec<([f64; 3], [f64; 3])> = if solid.len() < 2 {
        vec![case.mesh.bbox().unwrap_or(([0.0; 3], [1.0; 3]))]
    } else {
        solid
            .iter()
            .map(|&k| {
                let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
                for x in (0..n)
                    .filter(|&i| label[i] as usize == k)
                    .map(|i| case.particles.position[i])
                {
                    for d in 0..3 {
                        lo[d] = lo[d].min(x[d]);
                        hi[d] = hi[d].max(x[d]);
                    }
                }
                (lo, hi)
            })
            .collect()
    };
    let mut out = String::from(PINS_INTRO);
    for (k, (lo, hi)) in boxes.iter().enumerate() {
        let of = if boxes.len() > 1 {
            format!(" of piece {}", k + 1)
        } else {
            String::new()
        };
        if k > 0 {
            out.push('\n');
        }
        out.push_str(&pins("part", lo, hi, &of));
    }
    if boxes.len() > 1 {
        out.push_str(&format!(
            r#"
# The mesh is {} solids that share no node: one body whose pieces no bond joins. This keeps
# them apart, each piece's surface particles against the other pieces' faces; without it they
# would pass through each other (docs/guide/scene.md, "Contact"). To give a piece a material of
# its own, make it a [[body]] of its own: this mesh with elements = "NAME" of its set.
[[contact]]
slave = "part"
master = "part"
{}"#,
            boxes.len(),
            skeleton
                .penalty_radius
                .map_or(String::new(), |r| format!("radius = {r:e}\n"))
        ));
    }
    out
}

/// Each particle's piece (a set of particles joined by bonds), and the pieces that are solids:
/// pieces of a few particles are particles a coarse horizon left without a bond.
pub(super) fn solids(case: &PdCase) -> (Vec<u32>, Vec<usize>) {
    let (label, sizes) = case.bonds.components(|_| true);
    let solid = (0..sizes.len()).filter(|&k| sizes[k] >= 4).collect();
    (label, solid)
}

/// The skeleton's `[solver]`: the static solver for one solid, which converged on every case
/// converted from the corpus and the stored meshes that ADR converged on (and one it did not),
/// to the same contact radius within 3e-5, 6-12 times faster on the gmsh spheres and cylinder
/// (docs/PERFORMANCE.md, "The cases `convert` writes"); ADR for parts and pieces, which may
/// start apart, a gap the static solver's Newton steps do not close (two boxes 0.2 m apart:
/// ADR 1,224 iterations, 0.4 s; static not in 200 s).
pub(super) fn solver_block(one_solid: bool) -> &'static str {
    if one_solid {
        r#"[solver]
kind = "static"           # quasi-static, Newton-Raphson; "adr" (dynamic relaxation) under mpirun, "explicit" for dynamics
tolerance = 1e-4          # out-of-balance force relative to the applied load
# max_iterations = 500    # give up (exit 1) after this many; by default 500 Newton iterations, 200000 ADR's
"#
    } else {
        r#"[solver]
kind = "adr"              # quasi-static, dynamic relaxation: the pieces may start apart, which "static" does not close
tolerance = 1e-4          # out-of-balance force relative to the applied load
max_iterations = 100000   # ADR: give up (exit 1) after this many iterations
"#
    }
}

/// What the pins are for, above them.
pub(super) const PINS_INTRO: &str =
    "# A frictionless plane holds the body along its normal only: these pins (each the particle
# nearest its point, held across the load) stop it sliding, rolling and spinning. The load and
# the contact balance, so they carry next to nothing; remove them where supports of your own
# hold the body sideways (docs/guide/scene.md, \"Loads, supports, symmetry\").
";

/// The three pins of `body` over the box `lo`-`hi` (`of` names the piece in their comments).
pub(super) fn pins(body: &str, lo: &[f64; 3], hi: &[f64; 3], of: &str) -> String {
    let c: Vec<f64> = (0..3).map(|d| 0.5 * (hi[d] + lo[d])).collect();
    // A pin takes the particle nearest its point: four digits place it.
    let (cx, cy, cz) = (pin(c[0]), pin(c[1]), pin(c[2]));
    let (tz, sx) = (pin(hi[2]), pin(c[0] + 0.25 * (hi[0] - lo[0])));
    format!(
        r#"[[constraint]]
body = "{body}"
nearest = [{cx}, {cy}, {cz}]   # the centre of its bounding box{of}
fix = ["x", "y"]

[[constraint]]
body = "{body}"
nearest = [{cx}, {cy}, {tz}]   # the top of its vertical axis{of}: with the centre, no rolling
fix = ["x", "y"]

[[constraint]]
body = "{body}"
nearest = [{sx}, {cy}, {cz}]   # off the axis{of}, held across it: no spinning about it
fix = ["y"]
"#
    )
}

/// A pin's coordinate to four significant digits, as TOML reads it.
fn pin(x: f64) -> String {
    format!("{x:.3e}")
}
