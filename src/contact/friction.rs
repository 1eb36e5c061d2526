//! Coulomb friction in the point-to-surface contact (METHOD.md §10): a tangential penalty
//! holds a sticking slave to its stick point, a material point of the master's surface kept
//! as a segment and its shape-function weights (Eqs. 19-20), and a return mapping brings a
//! trial force past `μ F_n` back onto the slip cone, moving the stick point after the slave.
//!
//! The stick point is history: a pass keeps the one committed at the end of the last load
//! increment (ADR) or time step (explicit) and works from it, so that within an increment the
//! friction force depends on the state alone (an elastic predictor from the committed point,
//! a slip corrector), as an implicit FE code's return mapping does.

use super::{project_any, ContactPass, ContactPoint, MasterView};
use crate::case::segments::MasterSegment;
use crate::math::Vec3;

/// A material point of a master's surface: a segment and the weights `N_a(r, t)` of its
/// corners (Eqs. 19-20). It moves with the master's nodes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Anchor {
    pub segment: u32,
    pub weights: [f64; 4],
}

impl Anchor {
    /// Its current position, from the segment's current corners.
    pub fn at(&self, corners: [Vec3; 4]) -> Vec3 {
        (0..4).map(|k| corners[k] * self.weights[k]).sum()
    }
}

/// The tangential force of one contact and where its stick point goes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tangential {
    /// Force on the slave, in the master's tangent plane, N.
    pub force: Vec3,
    /// Whether the slave slips (its trial force was beyond `μ F_n`).
    pub slip: bool,
    /// Where a slipping slave's stick point moves: `limit / k_t` behind the contact point,
    /// against the slip (`None` while it sticks: the stick point stays).
    pub moved_to: Option<Vec3>,
    /// The force's stiffness across the slip in the tangent plane, N/m: `k_t` while it
    /// sticks, `k_t μ F_n / |k_t g_t|` while it slips (the slip cone's radius over the trial
    /// force's: turning the slip turns the force, it does not grow it).
    pub stiffness: f64,
}

/// The return mapping of Coulomb's law with a tangential penalty `k_t` (N/m): the slave's
/// contact point `contact` on the master, its stick point `anchor`, the master's normal `n`,
/// the normal force `normal_force` (N) and the coefficient `mu`.
///
/// The trial force `−k_t g_t` from the tangential slip `g_t = (I − n⊗n)(contact − anchor)`
/// sticks while `|k_t g_t| ≤ μ F_n`; past it the force is `μ F_n` against `g_t`, and the stick
/// point moves to where that force is the penalty's (`μ F_n / k_t` behind the contact point).
pub fn return_map(
    mu: f64,
    normal_force: f64,
    k_t: f64,
    n: Vec3,
    contact: Vec3,
    anchor: Vec3,
) -> Tangential {
    let d = contact - anchor;
    let g = d - n * n.dot(&d);
    let trial = g * -k_t;
    let limit = mu * normal_force;
    let size = trial.norm();
    if size <= limit || !(size > 0.0) {
        return Tangential {
            force: trial,
            slip: false,
            moved_to: None,
            stiffness: k_t,
        };
    }
    let dir = g / g.norm();
    Tangential {
        force: dir * -limit,
        slip: true,
        moved_to: Some(contact - dir * (limit / k_t)),
        stiffness: k_t * limit / size,
    }
}

impl ContactPass {
    /// The pass with Coulomb friction of coefficient `mu` (METHOD.md §10; 0 leaves it
    /// frictionless).
    pub fn with_friction(mut self, mu: f64) -> ContactPass {
        self.friction = mu;
        if mu > 0.0 {
            self.reset_friction();
        }
        self
    }

    /// Keeps the stick points the last evaluation found as the history the next increment
    /// (ADR) or step (explicit) starts from; a slave out of contact forgets its own.
    pub fn commit_friction(&mut self) {
        if self.friction > 0.0 {
            for ((stick, work), trial) in self
                .sticks
                .iter_mut()
                .zip(&mut self.friction_work)
                .zip(&self.trial)
            {
                *stick = trial.map(|t| t.0);
                *work += trial.map_or(0.0, |t| t.1);
            }
        }
    }

    /// No stick points and no work, for the slaves the pass holds now.
    pub(super) fn reset_friction(&mut self) {
        self.sticks = vec![None; self.slaves.len()];
        self.trial = vec![None; self.slaves.len()];
        self.friction_work = vec![0.0; self.slaves.len()];
    }

    /// Friction on a contact just found (`point`, of the pass's `k`-th slave, its normal force
    /// set), with the tangential penalty `k_t`: the stick point it works from (the committed
    /// one, or where the slave touches now if it has none), the return mapping's force added
    /// to the slave's, its state and energies; returns the stick point this evaluation finds.
    pub(super) fn add_friction(
        &self,
        view: MasterView,
        k: usize,
        point: &mut ContactPoint,
        k_t: f64,
    ) -> Anchor {
        let (segment, pr) = (point.segment, point.projection);
        let corners = view.corners(segment as usize);
        let here = Anchor {
            segment,
            weights: pr.weights,
        };
        let stuck = self.sticks[k].unwrap_or(here);
        let from = stuck.at(view.corners(stuck.segment as usize));
        let t = return_map(
            self.friction,
            point.normal_force,
            k_t,
            pr.normal,
            here.at(corners),
            from,
        );
        point.force += t.force;
        point.stick = Some(!t.slip);
        // A slave without a committed stick point works from where it touches now: its
        // force is nil whatever it does until the increment ends, and so is its stiffness.
        point.shear_stiffness = if self.sticks[k].is_some() {
            t.stiffness
        } else {
            0.0
        };
        point.tangential_energy = 0.5 * t.force.norm_squared() / k_t;
        let Some(x) = t.moved_to else {
            return stuck;
        };
        // A slipping slave's stick point is carried on the segment it touches now, where it
        // lies within μ F_n / k_t of the contact point (on its boundary if past an edge).
        let triangle = view.segments()[segment as usize].is_triangle();
        let moved = project_any(x, corners, triangle).map_or(here, |(p, _)| Anchor {
            segment,
            weights: p.weights,
        });
        let d = moved.at(corners) - from;
        point.slip_work = t.force.norm() * (d - pr.normal * pr.normal.dot(&d)).norm();
        moved
    }

    /// What a contact's stiffness counts in ADR's density: its normal tangent, twice with
    /// friction (the tangential penalty is as stiff, across the normal).
    pub(super) fn stiffness_factor(&self) -> f64 {
        if self.friction > 0.0 {
            2.0
        } else {
            1.0
        }
    }

    /// Friction's part of [`reactions`](Self::reactions): `(node, tangential force)`.
    pub fn friction_reactions<'a>(
        &'a self,
        segments: &'a [MasterSegment],
    ) -> impl Iterator<Item = (u32, Vec3)> + 'a {
        self.contacts
            .iter()
            .filter(|c| c.stick.is_some())
            .flat_map(move |c| {
                let nodes = segments[c.segment as usize].nodes;
                let t = c.tangential_force();
                (0..4).filter_map(move |k| {
                    let w = c.projection.weights[k];
                    (w != 0.0).then(|| (nodes[k], -(t * w)))
                })
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sticks_within_the_cone_and_slips_onto_it() {
        let n = Vec3::z();
        let anchor = Vec3::new(0.0, 0.0, 0.0);
        // 1 mm of slip at k_t = 1e6 N/m asks for 1000 N; μ F_n = 0.5 × 4000 = 2000 N: sticks.
        let t = return_map(0.5, 4000.0, 1e6, n, Vec3::new(1e-3, 0.0, -2e-3), anchor);
        assert!(!t.slip && t.moved_to.is_none());
        assert!((t.force - Vec3::new(-1000.0, 0.0, 0.0)).norm() < 1e-9);
        assert_eq!(t.stiffness, 1e6);
        // 3 mm asks for 3000 N: slips at 2000 N, against the slip; the stick point follows
        // to 2 mm behind the contact point, where the penalty gives exactly the limit.
        let c = Vec3::new(0.0, 3e-3, 0.0);
        let t = return_map(0.5, 4000.0, 1e6, n, c, anchor);
        assert!(t.slip);
        assert!((t.force - Vec3::new(0.0, -2000.0, 0.0)).norm() < 1e-9);
        // Across the slip the force turns at the cone's radius: 2000 N over 3 mm.
        assert!((t.stiffness - 2000.0 / 3e-3).abs() < 1e-6);
        let across = Vec3::new(1e-6, 3e-3, 0.0);
        let turned = return_map(0.5, 4000.0, 1e6, n, across, anchor).force - t.force;
        assert!((turned.x / -1e-6 - t.stiffness).abs() < 1e-3 * t.stiffness);
        let moved = t.moved_to.expect("moved");
        assert!((moved - Vec3::new(0.0, 1e-3, 0.0)).norm() < 1e-15);
        let again = return_map(0.5, 4000.0, 1e6, n, c, moved);
        assert!(!again.slip && (again.force - t.force).norm() < 1e-9);
        // No normal force, no friction; no slip, no force.
        assert_eq!(return_map(0.5, 0.0, 1e6, n, c, anchor).force.norm(), 0.0);
        assert_eq!(
            return_map(0.5, 10.0, 1e6, n, anchor, anchor).force.norm(),
            0.0
        );
    }
}
