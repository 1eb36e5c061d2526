//! The scene checks of a quasi-static load path and of friction: `ramp` on loads, prescribed
//! displacements and driven bodies; `displacement` on a constraint; `friction` on a contact
//! (METHOD.md §10).

use super::{excerpt, num, Axis, BodyKind, ContactMethod, Motion, Result, Scene, SolverKind};

/// The largest friction coefficient taken: past it a contact sticks under any load a penalty
/// can carry, and a typo (a percentage, 30 for 0.3) is likelier than a material.
pub const MAX_FRICTION: f64 = 10.0;

impl Scene {
    /// Every `ramp` within [0, 1] and rising; ramps and prescribed displacements only where a
    /// load path is walked (ADR, the static solver); `friction` finite, non-negative, on a
    /// point-to-surface pair.
    pub(super) fn check_path(&self) -> Result<()> {
        let quasi_static = matches!(self.solver.kind, SolverKind::Adr | SolverKind::Static);
        let solver = match self.solver.kind {
            SolverKind::Adr => "adr",
            SolverKind::Static => "static",
            SolverKind::Explicit => "explicit",
        };
        let ramp_ok = |r: [f64; 2]| r[0] >= 0.0 && r[1] <= 1.0 && r[0] < r[1];
        let bad_ramp = |r: [f64; 2]| {
            format!(
                "ramp must be [start, end] with 0 ≤ start < end ≤ 1 (the share of the load path, in ADR's load factor), got [{}, {}]",
                num(r[0]),
                num(r[1])
            )
        };
        let not_here = |what: &str| {
            format!(
                "{what} shapes the load path of a quasi-static run that ADR and the static solver walk in load_steps; kind = \"{solver}\" applies every load at once: use kind = \"adr\" or \"static\""
            )
        };
        for (k, l) in self.loads.iter().enumerate() {
            let Some(r) = l.ramp else { continue };
            let msg = if !ramp_ok(r) {
                bad_ramp(r)
            } else if !quasi_static {
                not_here("a load's ramp")
            } else {
                continue;
            };
            return Err(self.block_error(
                "[[load]]",
                k,
                format!("load on \"{}\": {msg}", excerpt(&l.body)),
            ));
        }
        for (k, c) in self.constraints.iter().enumerate() {
            let at = |msg: String| {
                self.block_error(
                    "[[constraint]]",
                    k,
                    format!("constraint on \"{}\": {msg}", excerpt(&c.body)),
                )
            };
            if let Some(d) = c.displacement {
                let held = |a: usize| {
                    c.fix
                        .iter()
                        .any(|f| matches!((f, a), (Axis::X, 0) | (Axis::Y, 1) | (Axis::Z, 2)))
                };
                if !d.iter().all(|x| x.is_finite()) {
                    let [x, y, z] = d.map(num);
                    return Err(at(format!(
                        "displacement must be finite [x, y, z], got [{x}, {y}, {z}]"
                    )));
                }
                if let Some(a) = (0..3).find(|&a| d[a] != 0.0 && !held(a)) {
                    return Err(at(format!(
                        "displacement {} m along {} on a component that `fix` does not hold: add \"{}\" to fix, or set it to 0",
                        num(d[a]),
                        ["x", "y", "z"][a],
                        ["x", "y", "z"][a]
                    )));
                }
                if !quasi_static && d.iter().any(|&x| x != 0.0) {
                    return Err(at(not_here("a prescribed displacement")));
                }
            }
            if let Some(r) = c.ramp {
                if !ramp_ok(r) {
                    return Err(at(bad_ramp(r)));
                }
                if c.displacement.is_none() {
                    return Err(at(
                        "ramp without displacement: the ramp says when a prescribed displacement is applied; give `displacement = [x, y, z]`".to_string(),
                    ));
                }
            }
        }
        for b in &self.bodies {
            let Some(r) = b.ramp else { continue };
            let msg = if !ramp_ok(r) {
                bad_ramp(r)
            } else if b.kind != BodyKind::Rigid || b.motion != Motion::Displacement {
                "ramp applies to a rigid body with motion = \"displacement\": it says when the body moves along the load path".to_string()
            } else if !quasi_static {
                not_here("a driven body's ramp")
            } else {
                continue;
            };
            let (l, col) = super::locate_in_body(&self.text, &b.name, "ramp");
            return Err(crate::error::Error::input(format!(
                "{}:{l}:{col}: body \"{}\": {msg}",
                self.source, b.name
            )));
        }
        // A path walked in one step has no history: every ramp jumps to its whole, and no
        // slave has a stick point before the one increment ends.
        let one_step = quasi_static && self.solver.load_steps.unwrap_or(1) < 2;
        let ramped = self.loads.iter().any(|l| l.ramp.is_some())
            || self.constraints.iter().any(|c| c.ramp.is_some())
            || self.bodies.iter().any(|b| b.ramp.is_some());
        if one_step && ramped {
            let (l, col) = super::locate(&self.text, "ramp");
            return Err(crate::error::Error::input(format!(
                "{}:{l}:{col}: a ramp shapes the load path that ADR and the static solver walk in load_steps increments, and load_steps is 1: the whole path is one step; give load_steps = 2 or more under [solver]",
                self.source
            )));
        }
        for (k, c) in self.contacts.iter().enumerate() {
            let mu = c.friction;
            let msg = if !(mu.is_finite() && mu >= 0.0) {
                format!(
                    "friction (Coulomb's μ) must be 0 or positive, got {}",
                    num(mu)
                )
            } else if mu > MAX_FRICTION {
                format!("friction μ = {} is above {MAX_FRICTION}: was it written in percent (μ = 0.3 for 30 %)?", num(mu))
            } else if mu > 0.0 && c.method == ContactMethod::ShortRange {
                "friction needs the contact point on the master's surface that the point-to-surface method finds; the short-range method has none: use method = \"point-to-surface\"".to_string()
            } else if mu > 0.0 && one_step {
                format!("friction in a quasi-static run (kind = \"{solver}\") works from the stick points each load increment ends with, and with load_steps = 1 no slave has one before the run ends: the run would be frictionless; give load_steps = 2 or more under [solver] (the normal load in the first ones)")
            } else {
                continue;
            };
            return Err(self.block_error(
                "[[contact]]",
                k,
                format!(
                    "contact \"{}\" / \"{}\": {msg}",
                    excerpt(&c.slave),
                    excerpt(&c.master)
                ),
            ));
        }
        Ok(())
    }
}
