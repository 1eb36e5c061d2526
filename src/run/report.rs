//! What a run says after solving: its contact against the pre-run Hertz estimate, and bodies
//! that drifted sideways because nothing held them.

use serde::Serialize;

use crate::body::Body;
use crate::contact::estimate::{ContactResolution, ContactShape};
use crate::math::Vec3;
use crate::model::Model;

/// Above this relative difference between the run's contact and the estimate's, the accuracy
/// line points to `pdcontact validate --mesh`.
pub const ACCURACY_POINTER: f64 = 0.03;

/// Relative curvatures within this ratio make a circular contact, the one whose radius the
/// summary's fit (`p0 √(1 − (r/a)²)` about the contact centre) measures.
const CIRCULAR: f64 = 1.1;

/// A body whose mean displacement across its load exceeds this share of its spacing Δ has
/// drifted: nothing holds it sideways (a frictionless contact does not).
pub const DRIFT_SPACINGS: f64 = 0.1;

/// The run's contact against the Hertz estimate made before it (`contact_estimates`), where
/// the estimate applies: one contact pair, a circular point contact.
#[derive(Clone, Debug, Serialize)]
pub struct AccuracyCheck {
    /// The pair, as warnings name it.
    pub pair: String,
    /// Hertz's contact radius `a = (3PR/(4E*))^⅓` of the estimate, m.
    pub estimated_radius: f64,
    /// The summary's fitted contact radius, m.
    pub fitted_radius: f64,
    /// `fitted / estimated − 1`.
    pub radius_error: f64,
    /// Hertz's peak pressure `p0 = 3P/(2πa²)`, Pa.
    pub estimated_peak: f64,
    /// The summary's peak pressure, Pa.
    pub peak: f64,
    /// `peak / estimated − 1`.
    pub peak_error: f64,
    /// The estimate's `a/R`, `R` the slave's own radius of curvature: `validate --mesh
    /// --contact-ratio` at this value runs Hertz's test at the same contact size.
    pub contact_ratio: f64,
    /// The slave's Poisson's ratio where it is a linear peridynamic solid (`validate
    /// --poisson` runs the same material); none for the bond-based model.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub poisson: Option<f64>,
}

impl AccuracyCheck {
    /// The check, where one pair has a circular point-contact estimate and the run found a
    /// contact.
    pub fn of(
        model: &Model,
        estimates: &[ContactResolution],
        fitted_radius: f64,
        peak: f64,
    ) -> Option<Self> {
        let [only] = estimates else {
            return None;
        };
        let poisson = model
            .bodies
            .iter()
            .find(|b| b.name() == only.slave)
            .and_then(Body::as_pd)
            .filter(|pd| pd.lps.is_some())
            .map(|pd| pd.material.poisson);
        let e = only.estimate.as_ref()?;
        let [k1, k2] = e.curvatures;
        if e.shape != ContactShape::Point
            || !(k2 > 0.0 && k1 / k2 <= CIRCULAR)
            || !(fitted_radius > 0.0 && peak > 0.0 && e.radius > 0.0)
        {
            return None;
        }
        let estimated_peak = e.peak_pressure();
        Some(AccuracyCheck {
            pair: only.pair(),
            estimated_radius: e.radius,
            fitted_radius,
            radius_error: fitted_radius / e.radius - 1.0,
            estimated_peak,
            peak,
            peak_error: peak / estimated_peak - 1.0,
            contact_ratio: e.radius * e.slave_curvature,
            poisson,
        })
    }

    /// Whether the run's contact differs from the estimate's by more than
    /// [`ACCURACY_POINTER`].
    pub fn differs(&self) -> bool {
        self.radius_error.abs() > ACCURACY_POINTER || self.peak_error.abs() > ACCURACY_POINTER
    }

    /// One line: the fitted radius and the peak against the estimate, and where they differ by
    /// more than 3 %, what to run to learn why.
    pub fn line(&self) -> String {
        let mut line = format!(
            "accuracy: {} contact radius {:.4} m against Hertz's {:.4} m ({:+.1} %), peak pressure {:.4e} Pa against {:.4e} Pa ({:+.1} %)",
            self.pair,
            self.fitted_radius,
            self.estimated_radius,
            100.0 * self.radius_error,
            self.peak,
            self.estimated_peak,
            100.0 * self.peak_error
        );
        if self.differs() {
            let poisson = self
                .poisson
                .map_or(String::new(), |nu| format!(" --poisson {nu}"));
            line.push_str(&format!(
                "; more than {:.0} % apart: `pdcontact validate --mesh MESH --contact-ratio {:.2}{poisson}` runs Hertz's test on the mesh (a sphere or a cylinder) at this contact size and says what the mesh gives, or the scene is not Hertz's (a load not through the contact, a large strain, a second contact)",
                100.0 * ACCURACY_POINTER,
                self.contact_ratio
            ));
        }
        line
    }
}

/// The energy drift above which an explicit run that finished is warned of: the runs of
/// docs/FRACTURE.md that hold together end within 0.1-0.3 % (the ball through the plate) to
/// 4.4 % (the Kalthoff plate at Δ = 1.5 mm); one that let crushed particles through the
/// projectile ended 22 % off without a word.
pub const ENERGY_DRIFT_WARNING: f64 = 0.05;

/// The warning for an explicit run whose energy balance (kinetic, strain, contact and the work
/// of fracture, against the start's and the work done; `summary.json`, `solver.energy`)
/// drifted by more than [`ENERGY_DRIFT_WARNING`] over the run; `breaks`: a body's bonds may
/// fail.
pub fn energy_warning(drift: f64, breaks: bool) -> Option<String> {
    if !(drift > ENERGY_DRIFT_WARNING) {
        return None;
    }
    let suspects = if breaks {
        "a contact pressing crushed material (particles that have lost most of their bonds: the `damage` field), whose penalty was set for intact surfaces, and the time step against the stable step"
    } else {
        "the time step against the stable step, and a contact whose slaves slide over the edges of its master's segments"
    };
    Some(format!(
        "the energy balance drifted by {:.1} % over the run (more than {:.0} %; `solver.energy` in summary.json has the terms at the start and the end): the results do not conserve energy and may not be physical; suspects: {suspects}",
        100.0 * drift,
        100.0 * ENERGY_DRIFT_WARNING
    ))
}

/// Warnings for deformable bodies whose volume-weighted mean displacement across their applied
/// load is more than [`DRIFT_SPACINGS`] of their spacing: they slid or rolled, and the
/// contact they make is not where the scene put it.
pub fn drift_warnings(model: &Model) -> Vec<String> {
    let mut warnings = Vec::new();
    for b in &model.bodies {
        let Body::Deformable(pd) = b else {
            continue;
        };
        let load: Vec3 = pd.load.iter().sum();
        let volume = &pd.case.particles.volume;
        let total: f64 = volume.iter().sum();
        if !(load.norm() > 0.0 && total > 0.0) {
            continue;
        }
        let down = load.normalize();
        let mean: Vec3 = pd.u.iter().zip(volume).map(|(u, &v)| u * v).sum::<Vec3>() / total;
        let mut across = mean - down * mean.dot(&down);
        // A symmetry plane holds the model's mean on it: what is left there is rounding.
        for plane in &pd.case.ghosts.planes {
            across[plane.axis] = 0.0;
        }
        let spacing = pd.case.particles.spacing;
        if across.norm() > DRIFT_SPACINGS * spacing {
            warnings.push(format!(
                "body \"{}\": drifted {:.3e} m across its load during the run (mean displacement [{:.3e}, {:.3e}, {:.3e}] m; more than {DRIFT_SPACINGS} of its spacing Δ = {:.4e} m): nothing holds it sideways, and a frictionless contact does not, so it slid or rolled and its contact is not where the scene put it; hold it with pins (`[[constraint]]` with `nearest = [x, y, z]` and `fix = [\"x\", \"y\"]` at its centre and on its axis, as `pdcontact convert` writes them) or symmetry planes",
                pd.name,
                across.norm(),
                across[0],
                across[1],
                across[2],
                spacing
            ));
        }
    }
    warnings
}

/// What broke in a body whose bonds may fail or were cut by a pre-crack (`summary.json`).
#[derive(Clone, Debug, Serialize)]
pub struct FractureReport {
    pub body: String,
    /// `s0` at the body's horizon; absent where only pre-cracks cut bonds.
    pub critical_stretch: Option<f64>,
    /// What fails a bond past `s0`: `"stretch"` or `"tension"`.
    pub failure: crate::scene::FailureCriterion,
    /// Bonds broken, pre-cracks' included (a real pair once, a bond to a mirror image once).
    pub broken_bonds: usize,
    /// Particles with any damage, and the largest damage.
    pub damaged_particles: usize,
    pub max_damage: f64,
    /// Groups of particles held together by intact bonds (a particle with none is one), and
    /// the sizes of the largest five.
    pub fragments: usize,
    pub largest_fragments: Vec<usize>,
    /// The strain energy the broken bonds held when they broke (J; pre-cracks' none).
    pub fracture_work: f64,
    /// Where the body is its own short-range master ([`crate::contact::fragments`]): the
    /// deepest any of its particles went into another piece's surface over the run, in Δ.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub deepest_between_pieces: Option<f64>,
    /// The surface the broken bonds opened ([`crate::body::new_surface`]): its particles,
    /// the particles tested to find it, and the time that took (s).
    pub new_surface_particles: usize,
    pub new_surface_tested: usize,
    pub new_surface_seconds: f64,
    /// Where the body is its own master across its pre-cracks' faces: what each crack's faces
    /// carry across.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub precracks: Vec<PrecrackReport>,
}

/// A pre-crack's two faces pressed together ([`crate::contact::ContactPass::crack`]): the
/// force across them (`summary.json`).
#[derive(Clone, Debug, Serialize)]
pub struct PrecrackReport {
    /// Which `[[precrack]]` of the scene (its index, from 0).
    pub precrack: usize,
    /// The crack plane's unit normal.
    pub normal: [f64; 3],
    /// The face particles of each side: behind the normal, in front of it.
    pub particles: [usize; 2],
    /// The bonds it cut before the body was made, each pair of real particles once (not
    /// among `broken_bonds`, which counts the bonds that broke in the body as made).
    pub bonds_cut: usize,
    /// Those of them that a contact presses (as a slave, or as a segment's node).
    pub pressed: usize,
    /// The force the faces press each other with along the normal (N): the contact forces on
    /// the side behind the normal, along minus it. A closed crack under a load normal to it
    /// carries the load across here.
    pub force_across: f64,
}

/// The [`FractureReport`] of each body with a failure state.
pub fn fracture_reports(model: &Model) -> Vec<FractureReport> {
    model
        .bodies
        .iter()
        .enumerate()
        .filter_map(|(k, b)| Some((k, b.as_pd()?)))
        .filter_map(|(k, pd)| {
            let f = pd.fracture.as_ref()?;
            let damage: Vec<f64> = (0..pd.len()).map(|i| f.damage(i)).collect();
            let fragments = f.fragments(&pd.case.bonds);
            let surface = pd.new_surface()?;
            Some(FractureReport {
                body: pd.name.clone(),
                critical_stretch: f.critical_stretch,
                failure: f.criterion,
                broken_bonds: f.broken,
                damaged_particles: damage.iter().filter(|&&d| d > 0.0).count(),
                max_damage: damage.iter().copied().fold(0.0, f64::max),
                fragments: fragments.len(),
                largest_fragments: fragments.into_iter().take(5).collect(),
                fracture_work: f.work.iter().sum(),
                deepest_between_pieces: model
                    .fragments
                    .iter()
                    .find(|p| p.body == k)
                    .map(|p| p.deepest.max(0.0)),
                new_surface_particles: surface.count(),
                new_surface_tested: surface.tested,
                new_surface_seconds: surface.seconds,
                precracks: pd
                    .crack_faces
                    .iter()
                    .map(|c| PrecrackReport {
                        precrack: c.precrack,
                        normal: c.normal.into(),
                        particles: c.particles.each_ref().map(Vec::len),
                        bonds_cut: pd
                            .precrack_pairs
                            .iter()
                            .filter(|(k, _, _)| *k == c.precrack)
                            .map(|(_, _, pairs)| pairs.len())
                            .sum(),
                        pressed: c
                            .particles
                            .iter()
                            .flatten()
                            .filter(|&&i| pd.contact_force[i as usize] != Vec3::zeros())
                            .count(),
                        force_across: -c.particles[0]
                            .iter()
                            .map(|&i| pd.contact_force[i as usize].dot(&c.normal))
                            .sum::<f64>(),
                    })
                    .collect(),
            })
        })
        .collect()
}

/// Friction in a body of a pair with friction (`summary.json`): its tangential contact force
/// and how much of its contact sticks.
#[derive(Clone, Debug, Serialize)]
pub struct FrictionReport {
    pub body: String,
    /// The tangential part of the contact forces on the body (as slave and as master), N.
    pub tangential_force: [f64; 3],
    /// Its slave particles in contact that stick and that slip.
    pub sticking: usize,
    pub slipping: usize,
    /// The pressure areas of those particles, m² (in a model cut by symmetry planes, of the
    /// model's part).
    pub stick_area: f64,
    pub slip_area: f64,
}

/// The [`FrictionReport`] of each body in a pair with friction.
pub fn friction_reports(model: &Model) -> Vec<FrictionReport> {
    model
        .bodies
        .iter()
        .filter_map(Body::as_pd)
        .filter_map(|pd| {
            let f = pd.friction.as_ref()?;
            let area = |state: i8| {
                let on: Vec<usize> = (0..pd.len()).filter(|&i| f.stick[i] == state).collect();
                let a: f64 = on.iter().map(|&i| pd.case.segments.pressure_area[i]).sum();
                (on.len(), a)
            };
            let (sticking, stick_area) = area(1);
            let (slipping, slip_area) = area(0);
            Some(FrictionReport {
                body: pd.name.clone(),
                tangential_force: f.force.iter().sum::<crate::math::Vec3>().into(),
                sticking,
                slipping,
                stick_area,
                slip_area,
            })
        })
        .collect()
}

/// How the slaves of one pass of a pair with friction touch: those in contact that stick and
/// that slip, and their pressure areas, m² (in a model cut by symmetry planes, of the
/// model's part).
#[derive(Clone, Debug, Default, Serialize)]
pub struct StickState {
    /// The body whose particles these are (the pass's slave).
    pub body: String,
    pub sticking: usize,
    pub slipping: usize,
    pub stick_area: f64,
    pub slip_area: f64,
}

/// Friction in one `[[contact]]` pair with friction (`summary.json`'s `friction_pairs`).
#[derive(Clone, Debug, Serialize)]
pub struct FrictionPairReport {
    pub slave: String,
    pub master: String,
    /// Coulomb's μ.
    pub friction: f64,
    /// The pair's tangential force on the slave body, N (the master takes the opposite):
    /// friction's part of the contact forces, over both passes of a two-pass pair.
    pub tangential_force: [f64; 3],
    /// The pair's normal force, N: the sum of its contacts' normal forces (both passes).
    pub normal_force: f64,
    /// The slave's particles as slaves, then, with two passes, the master's.
    pub passes: Vec<StickState>,
}

/// Values per block of slave particles that [`friction_pair_reports`] sums: the tangential
/// force (3), the normal force, sticking and slipping counts and areas.
const PASS_SUMS: usize = 8;

/// The [`FrictionPairReport`] of each pair with friction. Each pass's contacts are summed
/// block by block of slave particles, the blocks in order over the ranks, so that a
/// decomposed run reports the bits of one process. Collective.
pub fn friction_pair_reports(model: &Model) -> Vec<FrictionPairReport> {
    // Per pass with friction (not a body's own crack faces): its block sums.
    let passes: Vec<usize> = (0..model.passes.len())
        .filter(|&k| {
            let p = &model.passes[k];
            p.friction > 0.0 && p.slave != p.master
        })
        .collect();
    if passes.is_empty() {
        return Vec::new();
    }
    let mut mine = Vec::new();
    for &k in &passes {
        let p = &model.passes[k];
        let area = model.bodies[p.slave]
            .as_pd()
            .map(|pd| &pd.case.segments.pressure_area[..]);
        let blocks = p.sum_by_block(|c, g: &mut [f64; PASS_SUMS]| {
            let t = c.tangential_force();
            for a in 0..3 {
                g[a] += t[a];
            }
            g[3] += c.normal_force;
            let a = area.map_or(0.0, |a| a[c.slave as usize]);
            match c.stick {
                Some(true) => {
                    g[4] += 1.0;
                    g[6] += a;
                }
                Some(false) => {
                    g[5] += 1.0;
                    g[7] += a;
                }
                None => {}
            }
        });
        mine.push(blocks.len() as f64);
        mine.extend(blocks.iter().flatten());
    }
    let parts = match &model.domain {
        Some(d) => d.comm().all_gather_varcount(&mine),
        None => vec![mine],
    };
    let mut sums = vec![[0.0; PASS_SUMS]; passes.len()];
    for part in &parts {
        let mut at = 0;
        for s in sums.iter_mut() {
            let nb = part[at] as usize;
            at += 1;
            for g in part[at..at + PASS_SUMS * nb].chunks_exact(PASS_SUMS) {
                for (x, v) in s.iter_mut().zip(g) {
                    *x += v;
                }
            }
            at += PASS_SUMS * nb;
        }
    }
    let name = |k: usize| match &model.bodies[k] {
        Body::Deformable(pd) => pd.name.clone(),
        Body::Rigid(rb) => rb.name.clone(),
    };
    let state = |k: usize, s: &[f64; PASS_SUMS]| StickState {
        body: name(model.passes[k].slave),
        sticking: s[4] as usize,
        slipping: s[5] as usize,
        stick_area: s[6],
        slip_area: s[7],
    };
    // A two-pass pair is two passes in a row, each with half the pair's stiffness, the
    // second the first turned round.
    let mut out = Vec::new();
    let mut q = 0;
    while q < passes.len() {
        let (k, s) = (passes[q], &sums[q]);
        let p = &model.passes[k];
        let mut report = FrictionPairReport {
            slave: name(p.slave),
            master: name(p.master),
            friction: p.friction,
            tangential_force: [s[0], s[1], s[2]],
            normal_force: s[3],
            passes: vec![state(k, s)],
        };
        let second = passes.get(q + 1).filter(|&&k2| {
            let p2 = &model.passes[k2];
            p.weight < 1.0 && p2.slave == p.master && p2.master == p.slave
        });
        if let Some(&k2) = second {
            let s2 = &sums[q + 1];
            // The second pass's slaves are the master's: their force is the reaction's.
            for a in 0..3 {
                report.tangential_force[a] -= s2[a];
            }
            report.normal_force += s2[3];
            report.passes.push(state(k2, s2));
            q += 1;
        }
        out.push(report);
        q += 1;
    }
    out
}
