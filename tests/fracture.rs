//! Bond failure (METHOD.md §9, docs/FRACTURE.md): a notched three-point bend beam broken
//! through the contact of three rigid rollers against LEFM, the Kalthoff-Winkler plate hit
//! by a projectile through the contact, the same bits on any thread count, and elastic
//! scenes untouched by the failure machinery.

use pdcontact::studies::fracture::{run_beam, run_kalthoff, KalthoffPlate, NotchedBeam};

mod common;

fn temp_dir(name: &str) -> std::path::PathBuf {
    common::temp_dir(&format!("fracture-{name}"))
}

/// Runs the scene `text` in a temporary folder named for `name`.
fn run_text(text: &str, name: &str) -> (pdcontact::model::Model, pdcontact::run::RunSummary) {
    common::run_text(text, &format!("fracture-{name}"))
}

/// The coarse beam (Δ = 2 mm, δ = 6 mm against a 20 mm notch) driven 0.6 mm in 12
/// increments: past its peak.
fn coarse() -> NotchedBeam {
    NotchedBeam {
        spacing: 0.002,
        thickness: 0.008,
        displacement: 0.0006,
        steps: 12,
        mesh: None,
        static_solver: false,
        lps_poisson: None,
        failure: Default::default(),
    }
}

/// A broken beam: its peak within `bound` of LEFM's in plane stress, the load fallen after
/// it, and the crack run from the notch tip (20 mm) by more than a horizon, on the notch's
/// plane.
fn assert_broken_near_lefm(r: &pdcontact::studies::fracture::BeamResult, bound: f64) {
    let error = r.peak_load / r.lefm_plane_stress - 1.0;
    assert!(
        error.abs() < bound,
        "peak {} N against LEFM {} N",
        r.peak_load,
        r.lefm_plane_stress
    );
    assert!(r.last_over_peak < 0.7, "no softening: {}", r.last_over_peak);
    assert!(
        r.crack_tip_height > 0.02 + r.horizon,
        "crack tip {}",
        r.crack_tip_height
    );
    assert!(
        r.crack_offset <= r.horizon,
        "crack off its plane by {}",
        r.crack_offset
    );
}

/// The beam's peak load against LEFM's `K_Ic B W^1.5 / (S f(a/W))`, `K_Ic = sqrt(E G0)`
/// (plane stress: B = W/5). Measured: −11.6 % at δ = 0.3a (docs/FRACTURE.md has the finer
/// rows); the load then falls as the crack runs from the notch tip up its plane toward the
/// loading roller. The static solver breaks it alike.
#[test]
fn a_notched_beam_breaks_near_the_lefm_load() {
    let dir = temp_dir("beam");
    let r = run_beam(&coarse(), &dir, true).expect("runs");
    assert_broken_near_lefm(&r, 0.15);
    assert!(dir.join("load_displacement.svg").is_file());
    let _ = std::fs::remove_dir_all(&dir);
    // The static solver, its bonds tested near each equilibrium instead of at every ADR
    // iteration, breaks the same beam at the same peak (measured: 1.2 % above ADR's at the
    // study's default) with the same crack.
    let dir = temp_dir("beam-static");
    let s = run_beam(
        &NotchedBeam {
            static_solver: true,
            ..coarse()
        },
        &dir,
        true,
    )
    .expect("runs");
    assert_eq!(s.solver, "static");
    let error = s.peak_load / r.peak_load - 1.0;
    assert!(
        error.abs() < 0.03,
        "static peak {} N against ADR's {} N",
        s.peak_load,
        r.peak_load
    );
    assert!(s.last_over_peak < 0.7, "no softening: {}", s.last_over_peak);
    assert!(
        (s.crack_tip_height - r.crack_tip_height).abs() <= 2.0 * r.spacing,
        "crack tip {} against ADR's {}",
        s.crack_tip_height,
        r.crack_tip_height
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The same beam as a linear peridynamic solid at ν = 0.3 (its critical stretch
/// `sqrt(G0 / ((3μ + (3/4)⁴(k − 5μ/3)) δ))`, the pre-crack's and the broken bonds out of its
/// dilatations and force states), broken by the static solver: the peak against LEFM in
/// plane stress (measured −5.6 %; ADR −5.4 %, the bond-based beam −11.6 %), then the load
/// falls as the crack runs up the notch's plane. (ADR breaks an LPS beam in
/// `mpi/tests/mpi.rs`, on one process and on three.)
#[test]
fn an_lps_beam_breaks_near_the_lefm_load() {
    let dir = temp_dir("beam-lps");
    let r = run_beam(
        &NotchedBeam {
            lps_poisson: Some(0.3),
            static_solver: true,
            ..coarse()
        },
        &dir,
        true,
    )
    .expect("runs");
    assert_eq!((r.model.as_str(), r.poisson), ("lps", 0.3));
    assert_eq!(r.solver, "static");
    assert_broken_near_lefm(&r, 0.1);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The beam as a user meshes it (`meshes/beam_slot_tet4_h002.msh`: gmsh tet4, h = 2 mm, the
/// notch a slot 0.5 mm wide cut out of the solid, no pre-crack): the bonds across the slot,
/// which the horizon (5.6 mm) reaches over, are removed when the case is built, and none
/// other; loaded by 0.05 mm, the beam is as compliant as the box generator's with its
/// pre-crack (measured: 11.1 N against 13.7 N; with the bonds across the slot left in
/// place, 19.3 N: the slot bridged, the beam stiffer than an unnotched one would be).
#[test]
fn a_slot_in_the_mesh_is_a_notch() {
    let mesh =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/beam_slot_tet4_h002.msh");
    let slotted = NotchedBeam {
        displacement: 5e-5,
        steps: 1,
        mesh: Some(mesh),
        static_solver: false,
        ..coarse()
    };
    let (model, summary) = run_text(&slotted.scene("."), "slot");
    let pd = model.bodies[0].as_pd().expect("the beam");
    let case = &pd.case;
    assert!(case.bonds_across_gaps > 1000, "{}", case.bonds_across_gaps);
    // No bond left crosses the slot: its ends on either side of x = 0, crossing it below the
    // slot's top (z = 20 mm), mirror images across y = 0 included.
    let mut x = Vec::new();
    case.ghosts
        .extend_positions(&case.particles.position, &mut x);
    let mut crossing = 0;
    for i in 0..case.particles.len() {
        for b in case.bonds.range(i) {
            let (p, q) = (x[i], x[case.bonds.partner[b] as usize]);
            if p.x * q.x < 0.0 {
                let t = p.x / (p.x - q.x);
                if p.z + t * (q.z - p.z) < 0.02 - 1e-9 {
                    crossing += 1;
                }
            }
        }
    }
    assert_eq!(crossing, 0);
    let load = |s: &pdcontact::run::RunSummary| 2.0 * s.solver.increments[0].reaction[2];
    let (_, boxed) = run_text(
        &NotchedBeam {
            displacement: 5e-5,
            steps: 1,
            ..coarse()
        }
        .scene("."),
        "slot-box",
    );
    let ratio = load(&summary) / load(&boxed);
    assert!(
        ratio > 0.7 && ratio < 1.0,
        "{} N against {} N",
        load(&summary),
        load(&boxed)
    );
}

/// The increments' reactions and the bonds broken, bit for bit, on one and on two threads
/// (a coarser beam than the LEFM tests': Δ = 2.5 mm, 3 increments).
#[test]
fn bonds_fail_alike_on_any_thread_count() {
    let beam = NotchedBeam {
        spacing: 0.0025,
        thickness: 0.01,
        displacement: 0.0005,
        steps: 3,
        ..coarse()
    };
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        let (model, summary) =
            pool.install(|| run_text(&beam.scene("."), &format!("threads{threads}")));
        (summary, model.bodies[0].as_pd().expect("beam").clone())
    };
    let (a, pa) = run(1);
    let (b, pb) = run(2);
    let f = |s: &pdcontact::run::RunSummary| {
        s.solver
            .increments
            .iter()
            .map(|i| (i.reaction, i.broken_bonds, i.iteration))
            .collect::<Vec<_>>()
    };
    assert_eq!(f(&a), f(&b));
    let precrack = f(&a)[0].1;
    assert!(
        a.fracture[0].broken_bonds > precrack,
        "no bond failed past the pre-crack's {precrack}"
    );
    assert_eq!(pa.u, pb.u);
    let damage =
        |p: &pdcontact::body::PdBody| (0..p.len()).map(|i| p.damage(i)).collect::<Vec<_>>();
    assert_eq!(damage(&pa), damage(&pb));
}

/// A body whose bonds could fail but do not gives the bits of the body without the key.
#[test]
fn bonds_that_hold_change_nothing() {
    let beam = NotchedBeam {
        displacement: 0.0002,
        steps: 2,
        ..coarse()
    };
    let plain = beam.scene(".");
    // No pre-crack, no fracture energy: an elastic beam.
    let start = plain.find("[[precrack]]").expect("precrack");
    let end = start + plain[start..].find("\n\n").expect("block end");
    let elastic =
        format!("{}{}", &plain[..start], &plain[end..]).replace(", fracture_energy = 300", "");
    let unbreakable = elastic.replace("density = 1200", "density = 1200, critical_stretch = 10.0");
    assert_ne!(elastic, unbreakable);
    let run = |text: &str, name: &str| {
        let (model, summary) = run_text(text, name);
        (model.bodies[0].as_pd().expect("beam").u.clone(), summary)
    };
    let (ua, a) = run(&elastic, "elastic");
    let (ub, b) = run(&unbreakable, "unbreakable");
    assert_eq!(ua, ub);
    assert_eq!(a.solver.iterations, b.solver.iterations);
    assert!(a.fracture.is_empty());
    assert_eq!(b.fracture[0].broken_bonds, 0);
    assert_eq!(b.fracture[0].fragments, 1);
}

/// Kalthoff-Winkler at Δ = 1.5 mm: the crack leaves the notch tip forward and away from the
/// hit zone and crosses most of the plate. Its angle to the notch, 59° here (the experiment
/// about 70°, docs/FRACTURE.md), is asserted only to lie between the notch's direction and
/// the normal to it, well clear of both.
#[test]
fn the_kalthoff_plate_cracks_from_its_notch_tip() {
    let dir = temp_dir("kalthoff");
    let plate = KalthoffPlate {
        spacing: 0.0015,
        end_time: pdcontact::studies::fracture::kalthoff::END_TIME,
    };
    let r = run_kalthoff(&plate, &dir, true).expect("runs");
    assert!(r.crack_particles > 100, "{r:?}");
    assert!(r.crack_reach > 0.08, "{r:?}");
    assert!(
        r.crack_angle_deg > 45.0 && r.crack_angle_deg < 80.0,
        "{r:?}"
    );
    // It leaves the tip flatter than it runs on (51° over its first 25 mm at this spacing,
    // 62-64° at 0.75 and 0.9 mm), never along the notch nor across it.
    assert!(
        r.leaving_angle_deg > 40.0 && r.leaving_angle_deg < r.crack_angle_deg,
        "{r:?}"
    );
    // The plate holds together: the cracks do not cut it through in 90 µs.
    assert!(r.broken_bonds > 0 && r.fragments < 10, "{r:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The Kalthoff plate without its notches (Δ = 1.5 mm) hit at 200 m/s: the projectile's
/// corner crushes the plate's edge, and a plate particle that has lost most of its bonds goes
/// through the projectile's face at step 86 (docs/FRACTURE.md). The error says so by its
/// cause (how much of the particle is left), not by the time step's or the penalty's.
#[test]
fn a_crushed_slave_is_named_as_the_cause_of_a_missed_contact() {
    let plate = KalthoffPlate {
        spacing: 0.0015,
        end_time: pdcontact::studies::fracture::kalthoff::END_TIME,
    };
    let scene = plate.scene(".");
    let (a, b) = (
        scene.find("[[precrack]]").expect("the notch"),
        scene
            .find("[[body]]\nname = \"projectile\"")
            .expect("the projectile"),
    );
    let scene = format!("{}{}", &scene[..a], &scene[b..])
        .replace("velocity = [32, 0, 0]", "velocity = [200, 0, 0]");
    let err = match common::try_run_text(&scene, "fracture-crushed") {
        Ok(_) => panic!("the plate's edge is crushed through the projectile's face"),
        Err(e) => e.to_string(),
    };
    assert!(err.contains("missed contact at step"), "{err}");
    assert!(
        err.contains("damage 0.") && err.contains("is crushed material"),
        "{err}"
    );
    assert!(!err.contains("impact speed is too high"), "{err}");
}

/// The same plate with its notch, hit at 200 m/s: the crushed edge pushes the notch's faces,
/// which nothing presses together, 0.69 Δ through each other at its mouth, and a crushed
/// particle through the projectile's face stops the run at step 61. The error names both, the
/// crossing first (a quarter spacing or more: why the run failed), the stop beside it; at
/// 32 m/s and Δ = 1 mm, where the faces crossed by 0.03 Δ, the stop comes first.
#[test]
fn a_stop_beside_crossed_crack_faces_names_both() {
    let plate = KalthoffPlate {
        spacing: 0.0015,
        end_time: pdcontact::studies::fracture::kalthoff::END_TIME,
    };
    let scene = plate
        .scene(".")
        .replace("velocity = [32, 0, 0]", "velocity = [200, 0, 0]");
    let err = match common::try_run_text(&scene, "fracture-crossed") {
        Ok(_) => panic!("the plate's edge is crushed through the projectile's face"),
        Err(e) => e.to_string(),
    };
    let (crack, stop) = (
        err.find("passed through each other").expect(&err),
        err.find("(the run stopped: missed contact at step")
            .expect(&err),
    );
    assert!(crack < stop, "{err}");
    assert!(err.contains("is crushed material"), "{err}");
    let depth: f64 = err
        .split(" Δ) behind particle")
        .next()
        .and_then(|h| h.rsplit('(').next())
        .and_then(|d| d.trim().parse().ok())
        .expect(&err);
    assert!(depth >= 0.25, "{err}");
}

/// The bonds of the elastic state of `scene` that pass the critical stretch `s0`, by the
/// stretch alone and with `failure = "tension"` ([`pdcontact::body::PdBody::spare_compressed`]):
/// `(i, partner, stretch)` each, the body's reference positions with them.
type Failing = Vec<(usize, usize, f64)>;
fn failing_both_ways(
    scene: &str,
    name: &str,
    s0: f64,
) -> (Failing, Failing, Vec<pdcontact::math::Vec3>, f64) {
    let (mut model, summary) = run_text(scene, name);
    let pd = model.bodies[0].as_pd_mut().expect("deformable");
    pd.enable_fracture(Some(s0));
    let mut pos = Vec::new();
    pd.extended_positions(&mut pos);
    let all = pd.fracture.as_ref().expect("enabled").failing(
        &pd.case.bonds,
        &pos,
        &pd.reference,
        pd.owned.clone(),
    );
    let listed = |v: &[(u32, u32)]| -> Failing {
        v.iter()
            .map(|&(i, b)| {
                let (i, b) = (i as usize, b as usize);
                let j = pd.case.bonds.partner[b] as usize;
                let xi = pd.reference[j] - pd.reference[i];
                let stretch = (pos[j] - pos[i] - xi).dot(&xi) / xi.norm_squared();
                (i, j, stretch)
            })
            .collect()
    };
    let by_stretch = listed(&all);
    pd.fracture.as_mut().expect("enabled").criterion = pdcontact::scene::FailureCriterion::Tension;
    let by_tension = listed(&pd.spare_compressed(all, &pos));
    (by_stretch, by_tension, pos, summary.contact_radius)
}

/// A cube pressed or pulled along z by its top face (bottom held along z, symmetry planes
/// x = 0 and y = 0, so free to spread), small kinematics, the static solver.
fn cube(top: f64) -> String {
    format!(
        "[solver]\nkind = \"static\"\n\n\
         [[body]]\nname = \"cube\"\n\
         generator = {{ shape = \"box\", min = [0, 0, 0], max = [1, 1, 1], spacing = 0.1 }}\n\
         kinematics = \"small\"\n\
         material = {{ youngs_modulus = 1e9, poisson_ratio = 0.25, density = 1000 }}\n\n\
         [[constraint]]\nbody = \"cube\"\nset = \"bottom\"\nfix = [\"z\"]\n\n\
         [[constraint]]\nbody = \"cube\"\nset = \"top\"\nfix = [\"z\"]\ndisplacement = [0, 0, {top}]\n\n\
         [[symmetry]]\nbody = \"cube\"\naxis = \"x\"\n\n[[symmetry]]\nbody = \"cube\"\naxis = \"y\"\n"
    )
}

/// `failure = "tension"` against the stretch alone, on the two states that tell them apart.
/// Pressed by 1 % along z, the cube spreads by ν ε = 0.25 % across: past s0 = 0.2 % its
/// bonds across z fail by the stretch, and none by tension (the stress along them is nil).
/// Pulled by 1 % with s0 = 0.9 %, the bonds that fail lie within 17° of the pull, along the
/// tension: the same bonds fail either way.
#[test]
fn tension_spares_the_bonds_that_poissons_effect_stretched() {
    let (stretch, tension, _, _) = failing_both_ways(&cube(-0.01), "cube-pressed", 0.002);
    assert!(stretch.len() > 100, "{} bonds", stretch.len());
    assert!(
        tension.is_empty(),
        "{} bonds failed by tension",
        tension.len()
    );
    let (stretch, tension, _, _) = failing_both_ways(&cube(0.01), "cube-pulled", 0.009);
    assert!(stretch.len() > 100, "{} bonds", stretch.len());
    let key = |v: &Failing| v.iter().map(|&(i, j, _)| (i, j)).collect::<Vec<_>>();
    assert_eq!(key(&stretch), key(&tension));
}

/// Hertzian indentation (docs/FRACTURE.md, "Not done yet"): a rigid sphere (R = 10 mm)
/// driven 0.24 mm into a quarter glass block 5 × 5 × 4 mm (Δ = 0.2 mm, m = 2), elastic.
/// The most stretched bond lies below the contact, in Hertz's shear zone, where all three
/// principal stresses are compressive: the stretch alone fails it first, which no brittle
/// solid does. With `failure = "tension"` the first is on the surface outside the contact,
/// where the radial tension of the ring crack peaks (measured: 1.21a of the fitted contact
/// radius at this spacing).
#[test]
fn tension_fails_a_hertz_contact_first_outside_its_edge() {
    let scene = "[solver]\nkind = \"static\"\nload_steps = 6\n\n\
        [[body]]\nname = \"block\"\n\
        generator = { shape = \"box\", min = [0.0, 0.0, -0.004], max = [0.005, 0.005, 0.0], spacing = 0.0002 }\n\
        horizon_factor = 2.0\nkinematics = \"small\"\n\
        material = { youngs_modulus = 70e9, poisson_ratio = 0.25, density = 2500 }\n\n\
        [[body]]\nname = \"ball\"\nkind = \"rigid\"\n\
        generator = { shape = \"sphere_cap\", radius = 0.01, half_width = 0.004, depth = 0.0015, spacing = 0.0001, center = [0.0, 0.0, 0.01] }\n\
        motion = \"displacement\"\ndisplacement = [0.0, 0.0, -0.00024]\n\n\
        [[contact]]\nslave = \"block\"\nmaster = \"ball\"\n\n\
        [[constraint]]\nbody = \"block\"\nset = \"bottom\"\nfix = [\"z\"]\n\n\
        [[symmetry]]\nbody = \"block\"\naxis = \"x\"\n\n[[symmetry]]\nbody = \"block\"\naxis = \"y\"\n";
    let (stretch, tension, pos, a) = failing_both_ways(scene, "hertz", 1e-4);
    let first = |v: &Failing| {
        let &(i, j, s) = v
            .iter()
            .max_by(|p, q| p.2.total_cmp(&q.2))
            .expect("bonds past s0");
        let mid = 0.5 * (pos[i] + pos[j]);
        (mid.x.hypot(mid.y), -mid.z, s)
    };
    let dx = 0.0002;
    let (r, depth, s) = first(&stretch);
    assert!(
        depth > 2.0 * dx && r < a,
        "by the stretch: r = {r}, depth {depth} (a = {a}), s = {s}"
    );
    let (r, depth, s) = first(&tension);
    assert!(
        depth < 0.5 * dx && r > a && r < 1.4 * a,
        "by tension: r = {r}, depth {depth} (a = {a}), s = {s}"
    );
}
