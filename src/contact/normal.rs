//! The direction of a contact's force on a faceted master: the normal interpolated from
//! nodal normals, over the neighbours each segment had at rest ([`ContactPass::smooth_normal`]),
//! and how it turns for the static solver's tangent: as the slave slides
//! ([`ContactPass::slide`]) and as the master's nodes move ([`ContactPass::nodal_turn`]).

use super::narrow::{project_any, Projection};
use super::{ContactPass, ContactPoint, MasterView, FEATURE_COS};
use crate::body::Body;
use crate::math::Vec3;
use nalgebra::Matrix3;

/// How a contact turns as its slave slides over the master, the master held still
/// ([`ContactPass::slide`]): the static solver's tangent between two deformable bodies.
pub struct Slide {
    /// `∇N_a`: the gradients of the corner weights (the reaction's shares), 1/m.
    pub weights: [Vec3; 4],
    /// `∂n/∂x`: the gradient of the force's direction (the smoothed normal), 1/m.
    pub normal: Matrix3<f64>,
}

/// Around a master node whose particle has lost bonds, a smooth neighbour at rest that has
/// turned from the segment a slave presses by more than [`FEATURE_ANGLE`](super::FEATURE_ANGLE) counts less in the
/// nodal normal, down to nothing at this angle (60°). The edge of a plate crushed by an
/// impact folds its faces over (158° between segments that were flush at rest on the
/// Kalthoff plate), and averaged in whole, such a face turned the force away from the
/// surface: a projectile's corner went through the plate at Δ = 0.75 mm. Where the material is
/// whole the neighbours stay those of rest (the normal a continuous function of the nodes);
/// where it has broken the weight falls continuously with the fold, so the normal changes
/// only when the node loses its first bond.
const FOLDED_COS: f64 = 0.5;

/// The weight of a smooth neighbour whose area vector `a` makes `dot = a · n` with the
/// normal `n` of the segment a slave presses (`norm = |a|`): 1 within [`FEATURE_ANGLE`](super::FEATURE_ANGLE),
/// falling linearly in the cosine to 0 at [`FOLDED_COS`]'s angle.
fn folded_weight(dot: f64, norm: f64) -> f64 {
    if dot >= FEATURE_COS * norm {
        1.0
    } else {
        ((dot / norm - FOLDED_COS) / (FEATURE_COS - FOLDED_COS)).clamp(0.0, 1.0)
    }
}

/// How a contact's force turns with each master node it depends on: `(node, F ∂n/∂x_node)`
/// ([`ContactPass::nodal_turn`]).
pub type NodalTurn = Vec<(u32, Matrix3<f64>)>;

/// One corner's part in the interpolated normal: its weight `N_a`, its nodal normal and the
/// length it was normalised from, the mask of the components a symmetry plane keeps, and the
/// smooth neighbours (segment, folded weight) its normal is made of.
struct CornerPart {
    weight: f64,
    normal: Vec3,
    length: f64,
    keep: Vec3,
    ring: Vec<(u32, f64)>,
}

/// Each segment's unit normal at rest (zero for a degenerate one): a deformable master's
/// reference positions (a crack's faces shifted onto its plane), a rigid one's vertices (it
/// only translates).
pub(super) fn reference_normals(view: MasterView) -> Vec<Vec3> {
    let reference = |n: u32| match view {
        MasterView::Pd(b) => b.reference[n as usize],
        MasterView::Shifted(b, shift) => b.reference[n as usize] + shift[n as usize],
        MasterView::Rigid(b) => b.vertices[n as usize],
    };
    view.segments()
        .iter()
        .map(|s| {
            let c = s.nodes.map(reference);
            (c[2] - c[0])
                .cross(&(c[3] - c[1]))
                .try_normalize(0.0)
                .unwrap_or_else(Vec3::zeros)
        })
        .collect()
}

impl ContactPass {
    /// The direction of a contact's force: the master's normal interpolated at the slave's
    /// projection, `Σ N_a n_a` normalised, from the nodal normals `n_a` of the segment's
    /// corners (the area-weighted mean of the current normals of the segments around each
    /// corner that lay within [`FEATURE_ANGLE`](super::FEATURE_ANGLE) of this one at rest, and around a node that has
    /// lost bonds those that have turned past it since weighed less, down to nothing at 60°
    /// ([`FOLDED_COS`]); on a symmetry plane of the master, in the plane, as the segments'
    /// mirror images make it).
    ///
    /// A faceted master's own normal turns by the angle between two facets where a slave
    /// crosses their edge, and a slave pressed onto a master node sits at the apex of the
    /// dimple it makes there, where every facet around tilts towards it: measured on two gmsh
    /// tet spheres pressed together, slaves on master nodes held lateral out-of-balance forces
    /// of a fifth of their contact force (the facets tilted 11°), and ADR stalled at a
    /// residual of 0.14. The interpolated normal is continuous across edges and vertices (as
    /// FE codes smooth a master surface); a feature edge (a punch's corner) keeps its facets'
    /// own normals, and a segment with no smooth neighbour (a rigid plane's large faces)
    /// keeps its own. The gap stays the one measured against the segment (Eq. 21).
    ///
    /// Which segments are smooth neighbours is decided once, at rest: chosen on the current
    /// normals, a neighbour dropped out of the mean wherever the slaves dimpled a deformable
    /// master by more than the feature angle, the normal jumped by 10° between iterations at
    /// the same projection, and with one pass between two gmsh tet spheres neither solver found
    /// an equilibrium (docs/VALIDATION.md, "Two deformable bodies", one pass).
    pub(super) fn smooth_normal(&self, view: MasterView, segment: u32, pr: &Projection) -> Vec3 {
        let segs = view.segments();
        let own = pr.normal;
        let nodes = segs[segment as usize].nodes;
        let corners = if segs[segment as usize].is_triangle() {
            3
        } else {
            4
        };
        let mut n = Vec3::zeros();
        for k in 0..corners {
            let w = pr.weights[k];
            if w == 0.0 {
                continue;
            }
            let node = nodes[k] as usize;
            let Some((nodal, _)) = self.nodal_sum(view, node, segment, own, |_, _| {}) else {
                n += own * w;
                continue;
            };
            n += nodal.try_normalize(0.0).unwrap_or(own) * w;
        }
        n.try_normalize(0.0).unwrap_or(own)
    }
}

impl ContactPass {
    /// [`Slide`] of contact `c`, in the slave's position: central differences of the
    /// projection and of [`ContactPass::smooth_normal`] at `±h` along two directions in the
    /// segment's plane, `h` a thousandth of the segment (zero where a difference falls off
    /// every segment).
    pub fn slide(&self, bodies: &[Body], c: &ContactPoint) -> Slide {
        let mut out = Slide {
            weights: [Vec3::zeros(); 4],
            normal: Matrix3::zeros(),
        };
        let shift = self.shift.clone();
        let view = self.view(bodies, &shift);
        let x = view.corners(c.segment as usize);
        let triangle = view.segments()[c.segment as usize].is_triangle();
        let n = c.gap_normal;
        let p: Vec3 = x
            .iter()
            .zip(&c.projection.weights)
            .map(|(x, w)| x * *w)
            .sum();
        let h = 1e-3 * (x[2] - x[0]).norm();
        let t1 = n.cross(&Vec3::x()).try_normalize(0.1);
        let Some(t1) = t1.or_else(|| n.cross(&Vec3::y()).try_normalize(0.1)) else {
            return out;
        };
        if !(h > 0.0) {
            return out;
        }
        for t in [t1, n.cross(&t1)] {
            let (Some((a, _)), Some((b, _))) = (
                project_any(p + t * h, x, triangle),
                project_any(p - t * h, x, triangle),
            ) else {
                return Slide {
                    weights: [Vec3::zeros(); 4],
                    normal: Matrix3::zeros(),
                };
            };
            for (g, (wa, wb)) in out.weights.iter_mut().zip(a.weights.iter().zip(&b.weights)) {
                *g += t * ((wa - wb) / (2.0 * h));
            }
            let turn =
                self.smooth_normal(view, c.segment, &a) - self.smooth_normal(view, c.segment, &b);
            out.normal += turn / (2.0 * h) * t.transpose();
        }
        out
    }
}

impl ContactPass {
    /// The master segments that meet at `node` (none where the node has no list).
    fn segments_around(&self, node: usize) -> Option<&[u32]> {
        self.node_seg_offsets
            .get(node)
            .zip(self.node_seg_offsets.get(node + 1))
            .map(|(&a, &b)| &self.node_segs[a as usize..b as usize])
    }

    /// The area vectors of the smooth neighbours of `segment` around `node`, summed (a
    /// folded neighbour's weighted, [`folded_weight`]; each neighbour and its weight passed
    /// to `each`), with the component normal to a symmetry plane the node lies on zeroed, and
    /// the mask that zeroes it; `None` where the node has no list of segments. The one sum
    /// behind [`ContactPass::smooth_normal`]'s nodal normals and
    /// [`ContactPass::nodal_turn`]'s derivative of them.
    fn nodal_sum(
        &self,
        view: MasterView,
        node: usize,
        segment: u32,
        own: Vec3,
        mut each: impl FnMut(u32, f64),
    ) -> Option<(Vec3, Vec3)> {
        let around = self.segments_around(node)?;
        let this = self.reference_normals[segment as usize];
        let broken = view.pd().is_some_and(|mb| mb.damage(node) > 0.0);
        let mut nodal = Vec3::zeros();
        for &t in around {
            // A smooth neighbour at rest stays one: the set does not change as the surface
            // deforms, so the normal is a continuous function of the nodes.
            if self.reference_normals[t as usize].dot(&this) > FEATURE_COS {
                let x = view.corners(t as usize);
                // Twice the area times the unit normal (Eq. 18's diagonals).
                let a = (x[2] - x[0]).cross(&(x[3] - x[1]));
                let fw = if broken {
                    folded_weight(a.dot(&own), a.norm())
                } else {
                    1.0
                };
                nodal += a * fw;
                each(t, fw);
            }
        }
        let mut keep = Vec3::repeat(1.0);
        if let Some(mb) = view.pd() {
            let on = mb.case.ghosts.on_plane.get(node).copied().unwrap_or(0);
            for (b, plane) in mb.case.ghosts.planes.iter().enumerate() {
                if on & (1 << b) != 0 {
                    nodal[plane.axis] = 0.0;
                    keep[plane.axis] = 0.0;
                }
            }
        }
        Some((nodal, keep))
    }

    /// How the force's direction of contact `c` turns as the master's nodes move, the slave
    /// held: `F ∂n/∂x_b` (`F` the normal force) for every node `b` of the segments whose
    /// area vectors make the nodal normals of `c`'s segment ([`ContactPass::smooth_normal`]),
    /// analytic: `n = m/|m|`, `m = Σ N_a n_a`, `n_a = Z a_a/|Z a_a|` (`Z` zeroes the component
    /// normal to a symmetry plane the node lies on), `a_a = Σ_t (x₂ − x₀) × (x₃ − x₁)` over
    /// the smooth neighbours `t` (a folded neighbour's weight held). The projection's weights
    /// are held: their change is [`ContactPass::slide`]'s, in the slave's motion relative to
    /// the segment. Between two gmsh tet4 spheres pressed together it took the tangent's
    /// product from 1.6·10⁻³ of a central difference of the forces to 1.3·10⁻⁴
    /// (`solver::krylov`'s test).
    pub fn nodal_turn(&self, bodies: &[Body], c: &ContactPoint) -> NodalTurn {
        let mut out: NodalTurn = Vec::new();
        let shift = self.shift.clone();
        let view = self.view(bodies, &shift);
        let segs = view.segments();
        let pr = &c.projection;
        let segment = c.segment;
        let own = pr.normal;
        let nodes = segs[segment as usize].nodes;
        let corners = if segs[segment as usize].is_triangle() {
            3
        } else {
            4
        };
        let cross = |v: Vec3| Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0);
        let mut add = |node: u32, m: Matrix3<f64>| match out.iter_mut().find(|(n, _)| *n == node) {
            Some((_, g)) => *g += m,
            None => out.push((node, m)),
        };
        // The interpolated normal before normalising, and each corner's part.
        let mut raw = Vec3::zeros();
        let mut parts: Vec<CornerPart> = Vec::new();
        for k in 0..corners {
            let w = pr.weights[k];
            if w == 0.0 {
                continue;
            }
            let node = nodes[k] as usize;
            let mut ring = Vec::new();
            let Some((nodal, keep)) =
                self.nodal_sum(view, node, segment, own, |t, fw| ring.push((t, fw)))
            else {
                raw += own * w;
                continue;
            };
            let len = nodal.norm();
            if !(len > 0.0) {
                raw += own * w;
                continue;
            }
            let nk = nodal / len;
            raw += nk * w;
            parts.push(CornerPart {
                weight: w,
                normal: nk,
                length: len,
                keep,
                ring,
            });
        }
        let len = raw.norm();
        if !(len > 0.0) {
            return out;
        }
        let ns = raw / len;
        let js = (Matrix3::identity() - ns * ns.transpose()) * (c.normal_force / len);
        for part in parts {
            let nk = part.normal;
            let jk = js
                * (Matrix3::identity() - nk * nk.transpose())
                * Matrix3::from_diagonal(&part.keep)
                * (part.weight / part.length);
            for (t, fw) in part.ring {
                let x = view.corners(t as usize);
                let tn = segs[t as usize].nodes;
                let (d20, d31) = (x[2] - x[0], x[3] - x[1]);
                let m = jk * fw;
                add(tn[0], m * cross(d31));
                add(tn[2], -(m * cross(d31)));
                add(tn[1], -(m * cross(d20)));
                add(tn[3], m * cross(d20));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_folded_neighbour_fades_out_continuously() {
        let w = |deg: f64| folded_weight(deg.to_radians().cos() * 2.0, 2.0);
        // Whole within the feature angle, nothing from 60° on, and no jump in between.
        assert_eq!(w(0.0), 1.0);
        assert_eq!(w(29.9), 1.0);
        assert!(w(60.0) < 1e-12 && w(60.1) == 0.0);
        assert_eq!(w(158.0), 0.0);
        assert!((w(30.0) - 1.0).abs() < 1e-9 && w(60.0 - 1e-6) < 1e-6 && w(45.0) > 0.3);
        let mut last = 1.0;
        for k in 0..=300 {
            let next = w(30.0 + 0.1 * f64::from(k));
            assert!(next <= last && last - next < 0.01, "{k}: {last} -> {next}");
            last = next;
        }
        // A degenerate segment (no area) adds nothing whatever its weight.
        assert_eq!(folded_weight(0.0, 0.0), 1.0);
    }
}
