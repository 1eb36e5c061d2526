//! Coulomb friction in the point-to-surface contact (METHOD.md §10): a tangential penalty
//! holds a sticking slave to its stick point, a material point of the master's surface kept
//! as a segment and its shape-function weights (Eqs. 19-20), and a return mapping brings a
//! trial force past `μ F_n` back onto the slip cone, moving the stick point after the slave.
//!
//! The stick point is history: a pass keeps the one committed at the end of the last load
//! increment (ADR) or time step (explicit) and works from it, so that within an increment the
//! friction force depends on the state alone (an elastic predictor from the committed point,
//! a slip corrector), as an implicit FE code's return mapping does.

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
        };
    }
    let dir = g / g.norm();
    Tangential {
        force: dir * -limit,
        slip: true,
        moved_to: Some(contact - dir * (limit / k_t)),
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
        // 3 mm asks for 3000 N: slips at 2000 N, against the slip; the stick point follows
        // to 2 mm behind the contact point, where the penalty gives exactly the limit.
        let c = Vec3::new(0.0, 3e-3, 0.0);
        let t = return_map(0.5, 4000.0, 1e6, n, c, anchor);
        assert!(t.slip);
        assert!((t.force - Vec3::new(0.0, -2000.0, 0.0)).norm() < 1e-9);
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
