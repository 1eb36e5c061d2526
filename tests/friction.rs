//! Coulomb friction (METHOD.md §10, docs/VALIDATION.md "Friction"): a block on a tilted plane
//! that holds below tan θ = μ and slides at g (sin θ − μ cos θ) above it (explicit), a sphere
//! pressed into a block of the same material and pushed sideways against Cattaneo-Mindlin
//! (ADR and the static solver), the same bits on any thread count, and frictionless scenes
//! untouched.

use pdcontact::run::RunSummary;
use pdcontact::studies::friction::{
    run_mindlin, run_sliding, MindlinResult, MindlinScene, SlidingBlock,
};

mod common;

fn temp_dir(name: &str) -> std::path::PathBuf {
    common::temp_dir(&format!("friction-{name}"))
}

/// Runs the scene `text` in a temporary folder named for `name`: its summary.
fn run_text(text: &str, name: &str) -> RunSummary {
    common::run_text(text, &format!("friction-{name}")).1
}

fn block(slope: f64) -> SlidingBlock {
    SlidingBlock {
        slope,
        friction: 0.3,
        spacing: 0.01,
        end_time: 0.1,
    }
}

/// μ = 0.3: at tan θ = 0.5 and 1 the block slides at g (sin θ − μ cos θ) within 0.1 %
/// (measured: −0.00 %); at tan θ = 0.2 it holds: its acceleration under 0.1 % of the
/// frictionless one and its travel the tangential penalty's give, under 1e-4 of the
/// frictionless travel (measured: 9e-7 m against 9.6e-3 m).
#[test]
fn a_block_slides_above_the_friction_angle_and_holds_below() {
    for slope in [0.5, 1.0, 0.2] {
        let r =
            run_sliding(&block(slope), &temp_dir(&format!("slope{slope}")), true).expect("runs");
        assert!(r.error().abs() < 1e-3, "{}", r.to_text());
        assert!(r.energy_drift < 0.02, "{}", r.to_text());
        if slope < 0.3 {
            assert!(
                r.distance.abs() < 1e-4 * r.frictionless_distance,
                "{}",
                r.to_text()
            );
            assert!(r.sticking > 0 && r.slipping == 0, "{}", r.to_text());
        } else {
            assert!(r.slipping > 0 && r.sticking == 0, "{}", r.to_text());
        }
    }
}

fn mindlin(spacing: f64, steps: usize) -> MindlinScene {
    let mut s = MindlinScene {
        contact_radius: 0.15,
        spacing,
        friction: 0.3,
        push: 0.0,
        steps,
        rigid_flat: false,
        static_solver: false,
        meshes: None,
    };
    s.push = 1.5 * s.full_slip_travel();
    s
}

/// The scene where Mindlin's half-space theory holds, a/R = 0.05, at a/Δ = `resolution`,
/// by the static solver.
fn mindlin_half_space(resolution: f64) -> MindlinScene {
    let mut s = MindlinScene {
        contact_radius: 0.05,
        spacing: 0.05 / resolution,
        static_solver: true,
        ..mindlin(0.01, 8)
    };
    s.push = 1.5 * s.full_slip_travel();
    s
}

/// The sphere pressed into a block of the same material (β = 0) at a/R = 0.05 and a/Δ = 5,
/// then pushed: at each increment of the push with 0.15 ≤ Q/(μP) ≤ 0.9 the shear traction
/// within 5 % of μ p0 (mean within 0.8 a), the stick radius within 0.08 a of
/// `a (1 − Q/(μP))^{1/3}` and the contact's tangential travel within 3 % of Mindlin's.
/// Measured: shear 1.8-4.6 %, stick radius +0.034 to +0.073 a (within 0.022 a from
/// a/Δ = 7.5), travel −1.4 to +1.3 %; docs/VALIDATION.md has the finer rows.
#[test]
fn a_pushed_sphere_sticks_within_mindlins_radius() {
    let r: MindlinResult =
        run_mindlin(&mindlin_half_space(5.0), &temp_dir("mindlin"), true).expect("runs");
    let pushed: Vec<_> = r
        .points
        .iter()
        .filter(|p| (0.15..=0.9).contains(&p.ratio))
        .collect();
    assert!(pushed.len() >= 4, "{}", r.to_text());
    // Q rises with the push, to full slip.
    assert!(
        r.points.windows(2).all(|w| w[1].ratio >= w[0].ratio),
        "{}",
        r.to_text()
    );
    for p in pushed {
        assert!(p.shear_mre < 0.05, "{}", r.to_text());
        assert!(
            (p.stick_ratio - p.theory_stick_ratio).abs() < 0.08,
            "{}",
            r.to_text()
        );
        assert!(
            (p.slip_travel / p.theory_slip_travel - 1.0).abs() < 0.03,
            "{}",
            r.to_text()
        );
    }
}

/// Mindlin's theory is the half-space's: pressing a sphere leaves no shear in the contact of
/// two bodies of the same material. A sphere's curvature leaves one, growing with a/R, which
/// the theory leaves out (docs/VALIDATION.md, "Where the half-space theory holds"): at
/// a/Δ = 3, the pressing's shear at a/R = 0.15 more than twice that at a/R = 0.05, and that
/// under 2.5 % of μ p0. Measured: 3.88 % and 1.54 % (4.84 % and 1.77 % at a/Δ = 5, whatever
/// the spacing and the bodies' size).
#[test]
fn the_pressing_leaves_a_shear_that_grows_with_the_contact_over_the_radius() {
    let shear = |s: MindlinScene, name: &str| {
        let r = run_mindlin(&s, &temp_dir(name), true).expect("runs");
        (
            r.pressing_shear.expect("the pressing's end measured"),
            r.to_text(),
        )
    };
    let wide = MindlinScene {
        static_solver: true,
        ..mindlin(0.05, 8)
    };
    let (curved, a) = shear(wide, "pressing-wide");
    let (flat, b) = shear(mindlin_half_space(3.0), "pressing-narrow");
    assert!(curved > 2.0 * flat, "{a}{b}");
    assert!(flat < 0.025, "{a}{b}");
}

/// The static solver walks the same load path to the same equilibria as ADR: the holder's
/// prescribed displacements increment by increment, the stick points committed at each
/// increment's end. Every point of the push (Q/(μP), stick radius, shear traction, travel)
/// within the two solvers' tolerance of each other, in a tenth of ADR's iterations.
#[test]
fn the_static_solver_pushes_as_adr_does() {
    let adr = mindlin(0.05, 3);
    let newton = MindlinScene {
        static_solver: true,
        ..adr.clone()
    };
    let a = run_mindlin(&adr, &temp_dir("mindlin-adr"), true).expect("ADR runs");
    let s = run_mindlin(&newton, &temp_dir("mindlin-static"), true).expect("static runs");
    let text = format!("{}{}", a.to_text(), s.to_text());
    assert_eq!(s.solver, "static");
    assert_eq!(a.points.len(), s.points.len(), "{text}");
    assert!(a.points.len() >= 3, "{text}");
    for (p, q) in a.points.iter().zip(&s.points) {
        assert!((p.ratio - q.ratio).abs() < 1e-3, "{text}");
        assert!((p.stick_ratio - q.stick_ratio).abs() < 1e-3, "{text}");
        assert!((p.shear_mre - q.shear_mre).abs() < 1e-3, "{text}");
        assert!((q.slip_travel / p.slip_travel - 1.0).abs() < 1e-2, "{text}");
    }
    assert!(10 * s.iterations < a.iterations, "{text}");
}

/// Cattaneo-Mindlin on gmsh's tets (meshes/mindlin_*_tet4_h004.msh, a/Δ = 3.7 on the
/// sphere, by the static solver): at each increment of the push up to Q/(μP) = 0.95 the
/// stick radius within 0.08 a of Mindlin's, the contact's travel within 5 % of his, the
/// shear traction within 12 % of μ p0. Measured: +0.024 to +0.069 a, −3.4 to +2.7 %,
/// 6.8-10.6 %; the finer meshes of docs/VALIDATION.md do better.
#[test]
fn a_sphere_meshed_by_gmsh_sticks_within_mindlins_radius() {
    let stored = |f: &str| {
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("meshes")
            .join(f)
    };
    let scene = MindlinScene {
        static_solver: true,
        meshes: Some((
            stored("mindlin_sphere_tet4_h004.msh"),
            stored("mindlin_block_tet4_h004.msh"),
        )),
        ..mindlin(0.04, 4)
    };
    let r = run_mindlin(&scene, &temp_dir("mindlin-gmsh"), true).expect("runs");
    let text = r.to_text();
    assert_eq!(r.particles, 7_281, "{text}");
    assert!((r.contact_radius / r.spacing - 3.7).abs() < 0.1, "{text}");
    let pushed: Vec<_> = r.points.iter().filter(|p| p.ratio <= 0.95).collect();
    assert!(pushed.len() >= 3, "{text}");
    for p in pushed {
        assert!(
            (p.stick_ratio - p.theory_stick_ratio).abs() < 0.08,
            "{text}"
        );
        assert!(
            (p.slip_travel / p.theory_slip_travel - 1.0).abs() < 0.05,
            "{text}"
        );
        assert!(p.shear_mre < 0.12, "{text}");
    }
}

/// A sphere's mesh made for one contact radius, run at another: refused before any solve,
/// naming the radius it was made for.
#[test]
fn a_sphere_mesh_for_another_contact_radius_is_refused() {
    let stored = |f: &str| {
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("meshes")
            .join(f)
    };
    let scene = MindlinScene {
        meshes: Some((
            stored("mindlin_sphere_tet4_h004.msh"),
            stored("mindlin_block_tet4_h004.msh"),
        )),
        ..mindlin_half_space(5.0)
    };
    let e = run_mindlin(&scene, &temp_dir("mindlin-mismatch"), true)
        .expect_err("a mesh for a = 0.15 m at a = 0.05 m")
        .to_string();
    assert!(e.contains("made for a = 0.15"), "{e}");
    assert!(e.contains("mindlin_sphere_tet4_h004.msh"), "{e}");
}

/// The same bits on one and on two threads: the stick points are each slave's own.
#[test]
fn friction_alike_on_any_thread_count() {
    let scene = mindlin(0.05, 3).scene();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        pool.install(|| run_text(&scene, &format!("threads{threads}")))
    };
    let (a, b) = (run(1), run(2));
    let json = |s: &RunSummary| serde_json::to_value(s).expect("json");
    let (a, b) = (json(&a), json(&b));
    for key in [
        "friction",
        "friction_pairs",
        "total_contact_force",
        "contact_radius",
        "iterations",
    ] {
        assert_eq!(a[key], b[key], "{key}");
    }
    assert!(a["friction"][0]["slipping"].as_u64() > Some(0), "{a}");
    // The pair's report: the sphere's tangential force is all from this pair, and its two
    // passes' slaves are the two bodies' particles that stick and slip.
    let (body, pair) = (&a["friction"], &a["friction_pairs"][0]);
    assert_eq!(pair["slave"], "sphere");
    assert_eq!(pair["passes"].as_array().map(Vec::len), Some(2), "{pair}");
    for c in 0..3 {
        let (x, y) = (
            pair["tangential_force"][c].as_f64().expect("number"),
            body[0]["tangential_force"][c].as_f64().expect("number"),
        );
        assert!((x - y).abs() <= 1e-9 * y.abs().max(1.0), "{pair} {body}");
    }
    for (k, side) in pair["passes"]
        .as_array()
        .expect("passes")
        .iter()
        .enumerate()
    {
        assert_eq!(side["body"], body[k]["body"]);
        for key in ["sticking", "slipping", "stick_area", "slip_area"] {
            assert_eq!(side[key], body[k][key], "{key}");
        }
    }
    assert!(pair["normal_force"].as_f64() > Some(0.0), "{pair}");
}

/// `friction = 0.0` and a ramp over the whole path are the scene without them, bit for bit.
#[test]
fn frictionless_and_unramped_scenes_are_untouched() {
    let base = mindlin(0.05, 2).scene();
    let plain = base
        .replace("friction = 0.3\n", "")
        .replace("ramp = [0.0, 0.5]\n", "")
        .replace("ramp = [0.5, 1.0]\n", "");
    let keyed = plain
        .replace("radius = 100.0\n", "radius = 100.0\nfriction = 0.0\n")
        .replace(
            "force = [0.0, 0.0,",
            "ramp = [0.0, 1.0]\nforce = [0.0, 0.0,",
        );
    assert_ne!(plain, keyed);
    let json = |s: RunSummary| {
        let mut v = serde_json::to_value(s).expect("json");
        // The times, paths and the process's peak memory (the second run's counts the
        // first's, or another test's in the same process) are not the run's results.
        for k in [
            "wall_seconds",
            "solve_seconds",
            "outputs",
            "scene",
            "peak_memory_mb",
        ] {
            v[k] = serde_json::Value::Null;
        }
        v
    };
    assert_eq!(
        json(run_text(&plain, "plain")),
        json(run_text(&keyed, "keyed"))
    );
}
