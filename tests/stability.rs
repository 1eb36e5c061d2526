//! Single cells of `sweep --stability`, each driven past one limit: the class comes from what
//! the solver reports. The cells are the cheap ones (large steps, early failures).

use std::path::PathBuf;

use pdcontact::scene::ContactMethod;
use pdcontact::studies::stability::{run_point, sphere_spacing, Loading, RunPoint, StabilityRun};

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pdcontact-stab-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

fn run(name: &str, method: ContactMethod, dt: f64, penalty: f64, loading: Loading) -> StabilityRun {
    let dir = temp_dir(name);
    let spacing = sphere_spacing(&dir).expect("sphere");
    let p = RunPoint {
        method,
        dt_multiple: dt,
        penalty_multiple: penalty,
        loading,
    };
    let r = run_point(&p, &dir, spacing).expect("runs");
    let _ = std::fs::remove_dir_all(&dir);
    r
}

const PTS: ContactMethod = ContactMethod::PointToSurface;
const SR: ContactMethod = ContactMethod::ShortRange;

/// 4 × the stable estimate of the block, which the bonds set: unstable at once.
#[test]
fn a_step_past_the_bonds_limit_blows_up() {
    let r = run("blow-up", SR, 4.0, 1.0, Loading::Static);
    assert_eq!(r.outcome, "blew up", "{r:?}");
    let msg = r.error.expect("message");
    assert!(msg.contains("the explicit run is unstable"), "{msg}");
}

/// A hundredth of Hertz's K cannot hold the static load within the window.
#[test]
fn a_soft_penalty_misses_the_static_contact() {
    let r = run("soft", PTS, 0.8, 0.01, Loading::Static);
    assert_eq!(r.outcome, "missed contacts", "{r:?}");
    let msg = r.error.expect("message");
    assert!(msg.contains("penalty is too soft"), "{msg}");
}

/// 100 m/s with the paper's penalty: the particle is pushed through the window over many
/// steps, each far shorter than the window.
#[test]
fn a_fast_impact_pushes_through_the_paper_penalty() {
    let r = run("fast", PTS, 0.8, 1.0, Loading::Impact(100.0));
    assert_eq!(r.outcome, "missed contacts", "{r:?}");
    assert!(r.step_over_window < 0.1 && r.steps > 50, "{r:?}");
    assert!(r.peak_penetration.expect("penetration") > 0.9, "{r:?}");
}

/// The short-range repulsion is capped: 100 m/s goes through the block's surface.
#[test]
fn a_fast_impact_goes_through_the_short_range_zone() {
    let r = run("fast-sr", SR, 1.0, 1.0, Loading::Impact(100.0));
    assert_eq!(r.outcome, "missed contacts", "{r:?}");
    let msg = r.error.expect("message");
    assert!(msg.contains("went through the master's surface"), "{msg}");
}

/// 31.6 m/s with the paper's penalty, at 4 × its (conservative) estimate: the sphere turns
/// back without a missed contact.
#[test]
fn a_slower_impact_turns_back() {
    let r = run("slow", PTS, 4.0, 1.0, Loading::Impact(31.6));
    assert_eq!(r.outcome, "stable", "{r:?}");
    assert_eq!(r.ended, "turned back");
    assert!(r.energy_drift.expect("drift") < 1e-2, "{r:?}");
}

/// Static: the paper's penalty is 22 % off Hertz, a hundred times stiffer is within 10 %
/// (ten times stiffer sits at the 10 % line, 8-10 % depending on when the run is judged settled).
#[test]
fn the_penalty_sets_the_static_accuracy() {
    let paper = run("paper", PTS, 4.0, 1.0, Loading::Static);
    assert_eq!(paper.outcome, "stable but inaccurate", "{paper:?}");
    assert_eq!(paper.ended, "settled");
    assert!(paper.mre.expect("mre") > 0.15, "{paper:?}");
    let stiff = run("stiff", PTS, 4.0, 100.0, Loading::Static);
    assert_eq!(stiff.outcome, "stable and accurate", "{stiff:?}");
    assert!(stiff.mre.expect("mre") < 0.10, "{stiff:?}");
}
