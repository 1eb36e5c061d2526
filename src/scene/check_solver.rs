//! The scene checks of `[solver]`: its values, and the options the chosen solver ignores.

use super::{locate, num, Scene, SolverKind};
use crate::error::{Error, Result};

impl Scene {
    /// The solver's values in range (`err` points at the key's line).
    pub(super) fn check_solver(&self, err: &dyn Fn(&str, String) -> Error) -> Result<()> {
        match self.solver.kind {
            SolverKind::Adr | SolverKind::Static => {
                if let Some(t) = self.solver.tolerance {
                    if !(t > 0.0 && t < 1.0) {
                        return Err(err(
                            "tolerance",
                            format!("tolerance must be in (0, 1), got {}", num(t)),
                        ));
                    }
                }
                if self.solver.max_iterations == Some(0) {
                    return Err(err(
                        "max_iterations",
                        "max_iterations must be at least 1, got 0".to_string(),
                    ));
                }
                if self.solver.load_steps == Some(0) {
                    return Err(err(
                        "load_steps",
                        "load_steps must be at least 1, got 0".to_string(),
                    ));
                }
            }
            SolverKind::Explicit => {
                match self.solver.end_time {
                    None => {
                        return Err(err("kind", "an explicit solver needs end_time".to_string()))
                    }
                    Some(t) if !(t > 0.0 && t.is_finite()) => {
                        return Err(err(
                            "end_time",
                            format!("end_time must be positive, got {}", num(t)),
                        ))
                    }
                    _ => {}
                }
                if let Some(dt) = self.solver.dt {
                    if !(dt > 0.0 && dt.is_finite()) {
                        return Err(err("dt", format!("dt must be positive, got {}", num(dt))));
                    }
                }
            }
        }
        Ok(())
    }
}

impl Scene {
    /// Options that the chosen solver ignores: harmless, so warnings rather than errors.
    pub fn warnings(&self) -> Vec<String> {
        let s = &self.solver;
        let (kind, ignored): (&str, Vec<(&str, bool)>) = match s.kind {
            SolverKind::Adr | SolverKind::Static => (
                if s.kind == SolverKind::Adr {
                    "adr"
                } else {
                    "static"
                },
                vec![
                    ("dt", s.dt.is_some()),
                    ("safety", s.safety.is_some()),
                    ("end_time", s.end_time.is_some()),
                    ("damping", s.damping.is_some()),
                    ("stop_after_rebound", s.stop_after_rebound),
                ],
            ),
            SolverKind::Explicit => (
                "explicit",
                vec![
                    ("tolerance", s.tolerance.is_some()),
                    ("max_iterations", s.max_iterations.is_some()),
                    ("load_steps", s.load_steps.is_some()),
                ],
            ),
        };
        ignored
            .into_iter()
            .filter(|(_, given)| *given)
            .map(|(key, _)| {
                let (l, c) = solver_key(&self.text, key);
                format!(
                    "{}:{l}:{c}: [solver] {key} is ignored by the {kind} solver",
                    self.source
                )
            })
            .collect()
    }
}

/// Line and column of the line of `[solver]` that sets `key` (`dt` is also in `half_width`).
fn solver_key(text: &str, key: &str) -> (usize, usize) {
    let mut in_solver = false;
    for (k, line) in text.lines().enumerate() {
        let t = line.trim_start();
        if t.starts_with('[') {
            in_solver = t.starts_with("[solver]");
        } else if in_solver
            && t.strip_prefix(key)
                .is_some_and(|r| r.trim_start().starts_with('='))
        {
            return (k + 1, line.len() - t.len() + 1);
        }
    }
    locate(text, key)
}
