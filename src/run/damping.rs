//! Damping for an explicit run meant to settle (`damping > 0`): how fast the loaded body's
//! bounce on its contact dies, against `end_time`. A damped explicit run reaches the static
//! state only once that slowest mode has died; under mass-proportional damping `c` (velocities
//! decay as `e^{−ct}`) a mode of frequency ω decays at `c/2` when `c < 2ω` and at
//! `c/2 − √(c²/4 − ω²)` (its slow root) when overdamped, fastest at critical damping `c = 2ω`.
//! Measured on two gmsh spheres pressed together (docs/VALIDATION.md, "Two deformable
//! bodies"): at 0.05 s the force balance was 2.2e-3 at c = 300 1/s, 3e-6 at 600 (critical
//! for that bounce: 552) and 9.1e-2 at 1,500, as these rates say.

use crate::body::Body;
use crate::contact::estimate::ContactResolution;
use crate::model::Model;
use crate::scene::{Scene, SolverKind};

use super::checks::short;

/// What a settled run's contact force is within of the load: `e^{−rate t}` below it.
const SETTLED: f64 = 1e-3;

/// Below this share of critical damping the bounce rings on: at 0.54 of it the two spheres'
/// force balance still rang at 2-8e-3 after 0.6 s, where the rate alone says 1e-39 (the
/// contact's smoothed normal feeds a slow flutter that light damping does not outrun).
const LIGHT: f64 = 0.7;

/// How many times the settling time a damped explicit run between two deformable bodies
/// keeps its settled figures: the two gmsh spheres at c = 600 1/s (settled to 1e-3 in
/// 0.038 s by the rate) had ADR's figures to 0.01 points at 0.05 s (1.3 times it); at 0.1 s
/// (2.6 times) a flutter had grown (force balance 3.1e-4 against 3e-6, MRE moved 0.2
/// points; docs/VALIDATION.md, "Two deformable bodies").
const FLUTTER_AFTER: f64 = 2.0;

/// The decay rate (1/s) of a mode of frequency `omega` under mass-proportional damping `c`.
fn decay_rate(c: f64, omega: f64) -> f64 {
    if c < 2.0 * omega {
        0.5 * c
    } else {
        0.5 * c - (0.25 * c * c - omega * omega).sqrt()
    }
}

/// The bounce of each contact's loaded body on it: `ω = √(k/m)`, `k = 3P/(2δ)` from the Hertz
/// estimate ([`HertzEstimate::stiffness`](crate::contact::estimate::HertzEstimate::stiffness),
/// whose load `P` counts the mirror images across the symmetry planes through the contact)
/// and `m` the loaded body's mass with the same images. The loaded body is the pair's slave
/// where loads act on it, else its master; a line contact, or a pair with no loaded
/// deformable body, has none. Returns (slave, master, loaded body, ω).
fn bounces<'a>(
    model: &'a Model,
    estimates: &'a [ContactResolution],
) -> impl Iterator<Item = (&'a str, &'a str, &'a str, f64)> + 'a {
    estimates.iter().filter_map(move |r| {
        let e = r.estimate.as_ref()?;
        let k = e.stiffness()?;
        let loaded = [&r.slave, &r.master]
            .into_iter()
            .filter_map(|n| model.bodies.iter().find(|b| b.name() == n.as_str()))
            .filter_map(Body::as_pd)
            .find(|pd| pd.load.iter().any(|l| l.norm_squared() > 0.0))?;
        // The planes the estimate doubles its load across: through the contact, along it.
        let through = |pl: &&crate::case::SymmetryPlane| {
            e.normal[pl.axis].abs() < 0.1 && (e.centre[pl.axis] - pl.at).abs() <= 0.1 * e.window
        };
        let images = 2f64.powi(loaded.case.ghosts.planes.iter().filter(through).count() as i32);
        let mass =
            images * loaded.material.density * loaded.case.particles.volume.iter().sum::<f64>();
        let omega = (k / mass).sqrt();
        (omega.is_finite() && omega > 0.0).then_some((
            r.slave.as_str(),
            r.master.as_str(),
            loaded.name.as_str(),
            omega,
        ))
    })
}

/// Warnings for a damped explicit run whose `end_time` is too short for the bounce to settle
/// to [`SETTLED`], or whose damping is under [`LIGHT`] of critical; each names the critical
/// damping and the time it settles in.
pub(super) fn damping_warnings(
    scene: &Scene,
    model: &Model,
    estimates: &[ContactResolution],
) -> Vec<String> {
    let solver = &scene.solver;
    let Some(c) = solver.damping.filter(|c| *c > 0.0) else {
        return Vec::new();
    };
    if solver.kind != SolverKind::Explicit {
        return Vec::new();
    }
    let end = solver.end_time.unwrap_or(f64::INFINITY);
    bounces(model, estimates)
        .filter_map(|(slave, master, loaded, omega)| {
            let critical = 2.0 * omega;
            let settle = |c: f64| (1.0 / SETTLED).ln() / decay_rate(c, omega);
            let light = c < LIGHT * critical;
            let short_run = end < settle(c);
            let deformable = |name: &str| {
                model
                    .bodies
                    .iter()
                    .any(|b| b.name() == name && b.as_pd().is_some())
            };
            if !light && !short_run && deformable(slave) && deformable(master) {
                return (end > FLUTTER_AFTER * settle(c)).then(|| {
                    format!(
                        "contact \"{slave}\"/\"{master}\": between two deformable bodies a damped explicit run settles (here in about {} s) and then flutters: the contact's force follows the master's smoothed normal, which is not the gradient of an energy, and feeds a vibration that grows once the bounce has died; end_time = {} s is {:.1} times the time it settles in: end it by about {} s, or solve the scene with kind = \"adr\" or \"static\" (docs/VALIDATION.md, \"Two deformable bodies\")",
                        short(settle(c)),
                        short(end),
                        end / settle(c),
                        short(FLUTTER_AFTER * settle(c))
                    )
                });
            }
            (light || short_run).then(|| {
                let why = if light {
                    format!(
                        "damping = {} 1/s is {:.2} of critical, and below {LIGHT} of it the contact's force rings on",
                        short(c),
                        c / critical
                    )
                } else {
                    format!(
                        "under damping = {} 1/s it decays at {} 1/s and needs about {} s to settle to {SETTLED:e} of the load, longer than end_time = {} s",
                        short(c),
                        short(decay_rate(c, omega)),
                        short(settle(c)),
                        short(end)
                    )
                };
                format!(
                    "contact \"{slave}\"/\"{master}\": the loaded body \"{loaded}\" bounces on the contact at ω ≈ {} rad/s (the Hertz estimate's stiffness against its mass); {why}: damping ≈ {} 1/s (critical, 2ω) settles it fastest, in about {} s (docs/VALIDATION.md, \"Two deformable bodies\")",
                    short(omega),
                    short(critical),
                    short(settle(critical))
                )
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::decay_rate;

    /// `ẍ + c ẋ + ω² x = 0`: the slowest root's real part.
    #[test]
    fn decay_is_fastest_at_critical_damping() {
        let omega = 10.0;
        assert_eq!(decay_rate(4.0, omega), 2.0);
        assert!((decay_rate(20.0, omega) - 10.0).abs() < 1e-12);
        // Overdamped: the slow root c/2 − √(c²/4 − ω²) tends to ω²/c.
        let c = 1e4;
        assert!((decay_rate(c, omega) * c / (omega * omega) - 1.0).abs() < 1e-4);
        for c in [5.0, 15.0, 19.0, 21.0, 40.0] {
            assert!(decay_rate(c, omega) < decay_rate(2.0 * omega, omega));
        }
    }
}
