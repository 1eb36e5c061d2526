//! Cattaneo-Mindlin (METHOD.md §10, Johnson §7.1): a sphere pressed by P into a block of the
//! same material (Dundurs β = 0, where the theory is exact), then pushed sideways: the contact
//! sticks in a disc of radius `c = a (1 − Q/(μP))^{1/3}` and slips in the annulus around it,
//! where the shear traction is `μ p`.
//!
//! The sphere is the shell sector of `validate`'s Hertz sphere (R = 1 m, E = 1 GPa, ν = 1/4),
//! the block 6a × 3a × 3a fixed at its bottom, both halved by the symmetry plane y = 0 (the
//! push is along x). The sector's inner face is held as a rigid holder would hold it: moved
//! down by a prescribed displacement over the first half of the load path (P comes out as
//! the contact's force, and the theory is taken at that P), then along x over the second
//! half, never tilted, so that the tangential force Q comes out as the contact's reaction,
//! increment by increment, and each increment is a point of the theory's curve. (With P as
//! a load on the face and only x held, the sector tilted under Q by about 0.05 rad and the
//! slip zone gathered on its trailing side.)

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::run_in;
use crate::body::PdBody;
use crate::error::{Error, Result};
use crate::model::Model;
use crate::solver::Monitor;
use crate::studies::scenarios::{DENSITY, PAPER_E_STAR, POISSON, YOUNGS};

/// The sphere's radius, m.
const RADIUS: f64 = 1.0;

/// One Cattaneo-Mindlin scene.
#[derive(Clone, Debug)]
pub struct MindlinScene {
    /// Hertz's contact radius under P, m.
    pub contact_radius: f64,
    /// Grid spacing Δ, m.
    pub spacing: f64,
    /// Coulomb's μ.
    pub friction: f64,
    /// The inner face's travel along x over the push, m.
    pub push: f64,
    /// Load increments of each half of the path.
    pub steps: usize,
    /// `true`: the block is rigid (a flat, where the theory holds approximately: β ≠ 0).
    pub rigid_flat: bool,
    /// `true`: the static solver walks the path (Newton in each increment); ADR otherwise.
    pub static_solver: bool,
    /// The sphere's and the block's meshes, in place of the built-in generators
    /// (`tools/gmsh_mindlin.py` writes them: the sphere's inner face the set `top`, the
    /// block's bottom `bottom`, both on y ≥ 0); `spacing` then only names the run.
    pub meshes: Option<(PathBuf, PathBuf)>,
}

impl MindlinScene {
    /// E* of the pair.
    fn e_star(&self) -> f64 {
        if self.rigid_flat {
            YOUNGS / (1.0 - POISSON * POISSON)
        } else {
            PAPER_E_STAR
        }
    }

    /// The whole normal load P, N (Hertz: `4 E* a³ / (3R)`).
    pub fn load(&self) -> f64 {
        4.0 * self.e_star() * self.contact_radius.powi(3) / (3.0 * RADIUS)
    }

    /// How far the inner face is pressed down: `0.9 a²/R` of Hertz's approach `a²/R`, which
    /// gave 0.9 of it under P on the sector and the block (the sector is not a whole sphere:
    /// measured with P as a load, 0.0203 m at a = 0.15 m). P is then measured from the
    /// contact, and the theory's figures taken at that P.
    pub fn approach(&self) -> f64 {
        0.9 * self.contact_radius.powi(2) / RADIUS
    }

    /// Hertz's contact radius and peak pressure under `load`, N.
    pub fn hertz(&self, load: f64) -> (f64, f64) {
        let a = (3.0 * load * RADIUS / (4.0 * self.e_star())).cbrt();
        (a, 3.0 * load / (2.0 * std::f64::consts::PI * a * a))
    }

    /// The scene.
    pub fn scene(&self) -> String {
        let a = self.contact_radius;
        let hw = 3.0 * a;
        let block = if self.rigid_flat {
            format!(
                "[[body]]\nname = \"block\"\nkind = \"rigid\"\ngenerator = {{ shape = \"plane\", point = [0.0, 0.0, -{RADIUS}], normal = [0.0, 0.0, 1.0], size = {s} }}\n",
                s = 4.0 * hw
            )
        } else {
            let shape = match &self.meshes {
                Some((_, block)) => format!("mesh = {}", toml_path(block)),
                None => format!(
                    "generator = {{ shape = \"box\", min = [-{hw}, 0.0, {}], max = [{hw}, {hw}, -{RADIUS}], spacing = {} }}",
                    -RADIUS - hw,
                    self.spacing
                ),
            };
            format!(
                r#"[[body]]
name = "block"
{shape}
kinematics = "small"
{mat}
[[constraint]]
body = "block"
set = "bottom"
fix = ["x", "y", "z"]

[[symmetry]]
body = "block"
axis = "y"
"#,
                mat = material(),
            )
        };
        let sphere = match &self.meshes {
            Some((sphere, _)) => format!("mesh = {}", toml_path(sphere)),
            None => format!(
                "generator = {{ shape = \"sphere_cap\", radius = {RADIUS}, half_width = {hw}, depth = {hw}, spacing = {} }}",
                self.spacing
            ),
        };
        let two_pass = if self.rigid_flat {
            ""
        } else {
            "two_pass = true\n"
        };
        format!(
            r#"# Cattaneo-Mindlin: a sphere (R = {RADIUS} m) pressed into {what} (its inner face moved down
# {approach:e} m: about P = {p:e} N, a = {a} m), then pushed along x by {push:e} m; friction
# mu = {mu}: `pdcontact friction --case mindlin`.
[solver]
kind = "{kind}"
tolerance = 1e-5
max_iterations = 200000
load_steps = {steps}

[output]
folder = "."
every = 1000000

[[body]]
name = "sphere"
{sphere}
kinematics = "small"
{mat}
[[symmetry]]
body = "sphere"
axis = "y"

# The inner face is a rigid holder: pressed down, then pushed along x, never tilted.
[[constraint]]
body = "sphere"
set = "top"
fix = ["z"]
displacement = [0.0, 0.0, -{approach:e}]
ramp = [0.0, 0.5]

[[constraint]]
body = "sphere"
set = "top"
fix = ["x"]
displacement = [{push:e}, 0.0, 0.0]
ramp = [0.5, 1.0]

{block}
[[contact]]
slave = "sphere"
master = "block"
radius = 100.0
friction = {mu}
{two_pass}"#,
            p = self.load(),
            a = self.contact_radius,
            what = if self.rigid_flat {
                "a rigid flat"
            } else {
                "a block of the same material"
            },
            push = self.push,
            mu = self.friction,
            steps = 2 * self.steps,
            mat = material(),
            approach = self.approach(),
            kind = if self.static_solver { "static" } else { "adr" },
        )
    }
}

/// A path as a TOML string.
fn toml_path(p: &Path) -> String {
    toml::Value::String(p.display().to_string()).to_string()
}

fn material() -> String {
    format!("[body.material]\nyoungs_modulus = {YOUNGS:e}\npoisson_ratio = {POISSON}\ndensity = {DENSITY}\n")
}

/// One increment of the push against the theory.
#[derive(Clone, Debug, Serialize)]
pub struct MindlinPoint {
    /// The tangential force over its limit, `Q / (μ P)`, both from the contact.
    pub ratio: f64,
    /// Q on the model (half the sphere's), N.
    pub tangential_force: f64,
    /// P on the whole sphere, from the contact, N, and Hertz's contact radius under it, m.
    pub load: f64,
    pub hertz_radius: f64,
    /// Mindlin's compliance part of the push, measured (the push less what the same scene
    /// fully stuck takes for the bodies' own shear at this Q) and by the theory,
    /// `(3μP/(16a)) Σ(2 − ν)/G [1 − (1 − Q/(μP))^{2/3}]`, m; 0 until measured.
    pub slip_travel: f64,
    pub theory_slip_travel: f64,
    /// The inner face's travel, m.
    pub push: f64,
    /// The stick radius over Hertz's contact radius, measured ([`stick_radius`]) and by the
    /// theory, `(1 − Q/(μP))^{1/3}`.
    pub stick_ratio: f64,
    pub theory_stick_ratio: f64,
    /// The shear traction's mean error within 0.8 a, over `μ p0`.
    pub shear_mre: f64,
    /// Particles in contact within 0.8 a.
    pub samples: usize,
    /// Each particle in contact: its radius over a and its shear traction over μ p0.
    pub profile: Vec<(f64, f64)>,
}

/// What one scene gave.
#[derive(Clone, Debug, Serialize)]
pub struct MindlinResult {
    pub spacing: f64,
    pub contact_radius: f64,
    pub friction: f64,
    pub rigid_flat: bool,
    pub particles: usize,
    /// "adr" or "static": the solver of the run (the stuck reference runs by ADR).
    pub solver: String,
    /// ADR iterations, or Newton iterations of the static solver.
    pub iterations: usize,
    /// The run's wall time, s.
    pub wall_seconds: f64,
    /// The stuck reference's wall time, s.
    pub reference_wall_seconds: f64,
    /// The shear traction the pressing leaves, before any push: the mean `|q_x|` within
    /// 0.8 a over `μ p0` (Mindlin's theory, the half-space's, has none: what a sphere's
    /// curvature brings at a/R is left out of it).
    pub pressing_shear: Option<f64>,
    pub points: Vec<MindlinPoint>,
}

/// Mindlin's shear traction at radius `r` with stick radius `c`, over `μ p0`.
pub fn mindlin_shear(r: f64, a: f64, c: f64) -> f64 {
    let outer = (1.0 - (r / a).powi(2)).max(0.0).sqrt();
    if r < c {
        outer - (c / a) * (1.0 - (r / c).powi(2)).max(0.0).sqrt()
    } else {
        outer
    }
}

/// The stick zone's radius: the circle about the contact's centre (on the sphere as it is
/// now, `centre` along x) that best parts the sticking particles inside it from the slipping
/// ones outside, the particles weighted by their pressure areas. A particle is wholly on one
/// side of the boundary, so this is within half a spacing of it; the share of the areas that
/// stick would read the slip annulus's ragged edge as stick.
pub fn stick_radius(sphere: &PdBody, f: &crate::body::FrictionForces, centre: f64) -> f64 {
    let mut rings: Vec<(f64, bool, f64)> = (0..sphere.len())
        .filter(|&i| f.stick[i] >= 0)
        .map(|i| {
            let x = sphere.case.particles.position[i] + sphere.u[i];
            (
                ((x.x - centre).powi(2) + x.y * x.y).sqrt(),
                f.stick[i] == 1,
                sphere.case.segments.pressure_area[i],
            )
        })
        .collect();
    rings.sort_by(|a, b| a.0.total_cmp(&b.0));
    // Misplaced area with the boundary after the k-th particle: slipping inside, sticking
    // outside.
    let mut misplaced: f64 = rings.iter().filter(|r| r.1).map(|r| r.2).sum();
    let mut best = (misplaced, 0.0);
    for k in 0..rings.len() {
        misplaced += if rings[k].1 { -rings[k].2 } else { rings[k].2 };
        let c = match rings.get(k + 1) {
            Some(next) => 0.5 * (rings[k].0 + next.0),
            None => rings[k].0,
        };
        if misplaced < best.0 {
            best = (misplaced, c);
        }
    }
    best.1
}

/// Follows the push increment by increment.
struct Push<'a> {
    scene: &'a MindlinScene,
    points: Vec<MindlinPoint>,
    /// The state where the pressing ends, before any push.
    pressed: Option<MindlinPoint>,
}

impl Push<'_> {
    /// The state at the end of an increment of the push.
    fn measure(&self, model: &Model, factor: f64) -> Option<MindlinPoint> {
        let sphere: &PdBody = model.bodies[0].as_pd()?;
        let f = sphere.friction.as_ref()?;
        let s = self.scene;
        let (p_half, q_half) = (
            sphere.contact_force.iter().map(|v| v.z).sum::<f64>(),
            sphere.contact_force.iter().map(|v| v.x).sum::<f64>(),
        );
        let limit = s.friction * p_half.abs();
        if !(limit > 0.0) {
            return None;
        }
        let ratio = q_half.abs() / limit;
        let theory = (1.0 - ratio).max(0.0).cbrt();
        // Hertz's contact under the P the holder's approach gave (the whole sphere's).
        let (a, p0) = s.hertz(2.0 * p_half.abs());
        let q0 = s.friction * p0;
        // Radii from the contact's centre, where the pressure centres it on the sphere as it
        // is now (the push tilts the sector and moves its contact along x; y = 0 is a
        // symmetry plane).
        let (mut w, mut wx) = (0.0, 0.0);
        for i in 0..sphere.len() {
            if f.stick[i] >= 0 {
                let p = sphere.pressure_force(i);
                w += p;
                wx += p * (sphere.case.particles.position[i].x + sphere.u[i].x);
            }
        }
        let centre = if w > 0.0 { wx / w } else { 0.0 };
        let (mut err, mut samples, mut profile) = (0.0, 0usize, Vec::new());
        for i in 0..sphere.len() {
            let area = sphere.case.segments.pressure_area[i];
            if f.stick[i] < 0 || !(area > 0.0) {
                continue;
            }
            let x = sphere.case.particles.position[i] + sphere.u[i];
            let r = ((x.x - centre).powi(2) + x.y * x.y).sqrt();
            let q = (sphere.friction_force(i).x / area).abs();
            profile.push((r / a, q / q0));
            if r > 0.8 * a {
                continue;
            }
            err += (q / q0 - mindlin_shear(r, a, theory * a)).abs();
            samples += 1;
        }
        let stick_ratio = stick_radius(sphere, f, centre) / a;
        // The push of the increment measured (the solver has set the next one's already).
        let push = self.scene.push * crate::scene::ramp_factor(Some([0.5, 1.0]), factor);
        Some(MindlinPoint {
            ratio,
            tangential_force: q_half.abs(),
            slip_travel: 0.0,
            theory_slip_travel: s.full_slip_travel_at(2.0 * p_half.abs())
                * (1.0 - (1.0 - ratio).max(0.0).powf(2.0 / 3.0)),
            load: 2.0 * p_half.abs(),
            hertz_radius: a,
            push,
            stick_ratio,
            theory_stick_ratio: theory,
            shear_mre: err / samples.max(1) as f64,
            samples,
            profile,
        })
    }
}

impl Monitor for Push<'_> {
    fn step(&mut self, _: &Model, _: usize, _: f64, _: f64) -> Result<()> {
        Ok(())
    }
    /// Each increment of the push (past the middle of the path) in the equilibrium it
    /// reached.
    fn increment_done(&mut self, model: &Model, factor: f64, _: usize) -> Result<()> {
        // The pressing's end: Mindlin's theory has no shear there.
        if (factor - 0.5).abs() < 1e-9 {
            self.pressed = self.measure(model, factor);
        }
        if factor > 0.5 + 1e-9 {
            if let Some(p) = self.measure(model, factor) {
                self.points.push(p);
            }
        }
        Ok(())
    }
    fn finish(&mut self, _: &Model, _: usize, _: f64) -> Result<()> {
        Ok(())
    }
}

/// Runs one scene into `folder`.
pub fn run_mindlin(scene: &MindlinScene, folder: &Path, quiet: bool) -> Result<MindlinResult> {
    if let Some((sphere, _)) = &scene.meshes {
        check_sphere_mesh(sphere, scene.contact_radius)?;
    }
    let mut push = Push {
        scene,
        points: Vec::new(),
        pressed: None,
    };
    let (model, summary, wall) = run_in(&scene.scene(), folder, quiet, &mut push)?;
    if let Some(e) = &summary.error {
        return Err(Error::numerical(e.clone()));
    }
    write_shear_chart(&folder.join(SHEAR_CHART), &push.points)?;
    // The same scene stuck (μ = 10: no particle slips): its push over Q is the bodies' own
    // shear compliance plus the contact's without slip, `Σ(2 − ν)/(8Ga)` (Mindlin's slope at
    // Q = 0); what the push takes beyond the bodies' own shear is the contact's travel.
    // It runs by ADR whatever solver the scene takes: at μ = 10 a slave at the rim slips
    // with a force ten times as sensitive to its penetration as the normal force, which the
    // static solver's symmetric tangent leaves out, and Newton stalls on it (μ up to 3
    // converges). The equilibrium is the same to the tolerance either way.
    let stuck = MindlinScene {
        friction: crate::scene::MAX_FRICTION,
        static_solver: false,
        ..scene.clone()
    };
    let mut reference = Push {
        scene: &stuck,
        points: Vec::new(),
        pressed: None,
    };
    let (_, stuck_summary, stuck_wall) =
        run_in(&stuck.scene(), &folder.join("stuck"), quiet, &mut reference)?;
    if let Some(e) = &stuck_summary.error {
        return Err(Error::numerical(e.clone()));
    }
    if let Some(last) = reference.points.last().filter(|p| p.tangential_force > 0.0) {
        // Mindlin's slope at Q = 0, on the half model's Q: `Σ(2 − ν)/(8Ga)` times 2.
        let no_slip_slope =
            scene.full_slip_travel_at(last.load) * 2.0 / 3.0 / (scene.friction * 0.5 * last.load);
        let own = last.push / last.tangential_force - no_slip_slope;
        for p in &mut push.points {
            p.slip_travel = p.push - own * p.tangential_force;
        }
    }
    // On a user's meshes the spacing is the sphere's own.
    let spacing = match (&scene.meshes, model.bodies[0].as_pd()) {
        (Some(_), Some(sphere)) => sphere.spacing(),
        _ => scene.spacing,
    };
    Ok(MindlinResult {
        spacing,
        contact_radius: scene.contact_radius,
        friction: scene.friction,
        rigid_flat: scene.rigid_flat,
        particles: model.particles(),
        solver: if scene.static_solver { "static" } else { "adr" }.to_string(),
        iterations: summary.iterations,
        wall_seconds: wall,
        reference_wall_seconds: stuck_wall,
        pressing_shear: push.pressed.map(|p| p.shear_mre),
        points: push.points,
    })
}

/// Refuses a sphere's mesh made for another contact radius: the scene's holder, push and
/// theory are all scaled with `a`, and the mesh's half cap spans 6a along x.
fn check_sphere_mesh(path: &Path, a: f64) -> Result<()> {
    let mesh = pdcontact_importers::read_path(path, None)?;
    let Some((lo, hi)) = mesh.bbox() else {
        return Ok(());
    };
    let width = hi[0] - lo[0];
    if (width / (6.0 * a) - 1.0).abs() > 0.1 {
        return Err(Error::input(format!(
            "the sphere's mesh {} spans {width:.4} m along x, where the scene at a = {a} m needs 6a = {:.4} m: it was made for a = {:.4} m (tools/gmsh_mindlin.py --a); give that --contact-radius, or mesh it again with --a {a}",
            path.display(),
            6.0 * a,
            width / 6.0
        )));
    }
    Ok(())
}

impl MindlinScene {
    /// Mindlin's tangential travel at full slip, `(3μP/(16a)) Σ (2 − ν)/G`: the relative
    /// displacement of distant points when Q reaches μP.
    pub fn full_slip_travel(&self) -> f64 {
        self.full_slip_travel_at(self.load())
    }

    /// [`Self::full_slip_travel`] under the normal load `load`, N.
    pub fn full_slip_travel_at(&self, load: f64) -> f64 {
        let g = YOUNGS / (2.0 * (1.0 + POISSON));
        let bodies = if self.rigid_flat { 1.0 } else { 2.0 };
        let (a, _) = self.hertz(load);
        3.0 * self.friction * load / (16.0 * a) * bodies * (2.0 - POISSON) / g
    }
}

impl MindlinResult {
    /// The table a user reads.
    pub fn to_text(&self) -> String {
        let mut s = format!(
            "Cattaneo-Mindlin: sphere R = {RADIUS} m on {}, a = {} m, Δ = {:.4} m (a/Δ = {:.1}), μ = {}; {} particles, {} {} iterations, {:.1} s (the stuck reference by ADR: {:.1} s)\n",
            if self.rigid_flat {
                "a rigid flat (β ≠ 0: the theory is approximate)"
            } else {
                "a block of the same material (β = 0)"
            },
            self.contact_radius,
            self.spacing,
            self.contact_radius / self.spacing,
            self.friction,
            self.particles,
            self.iterations,
            if self.solver == "static" {
                "Newton"
            } else {
                "ADR"
            },
            self.wall_seconds,
            self.reference_wall_seconds
        );
        if let Some(shear) = self.pressing_shear {
            s.push_str(&format!(
                "  the pressing's end (Q = 0): shear {:.2} % of μp0 within 0.8a, where the half-space theory has none (a/R = {})\n",
                100.0 * shear,
                self.contact_radius / RADIUS
            ));
        }
        s.push_str("  Q/(μP)   c/a     theory   error (of a)   shear MRE (of μp0, r ≤ 0.8a)   contact's travel (m), theory, error\n");
        for p in &self.points {
            s.push_str(&format!(
                "  {:6.3}   {:6.3}   {:6.3}   {:+7.3}        {:6.2} % ({} particles)          {:9.3e}  {:9.3e}  {:+6.1} %\n",
                p.ratio,
                p.stick_ratio,
                p.theory_stick_ratio,
                p.stick_ratio - p.theory_stick_ratio,
                100.0 * p.shear_mre,
                p.samples,
                p.slip_travel,
                p.theory_slip_travel,
                100.0 * (p.slip_travel / p.theory_slip_travel - 1.0)
            ));
        }
        s
    }
}

/// The chart of the shear traction against Cattaneo-Mindlin's that [`run_mindlin`] writes.
pub const SHEAR_CHART: &str = "friction_shear.svg";

/// The shear traction of the particles against the radius, at the increments nearest
/// Q/(μP) = 0.25, 0.5 and 0.75, with Mindlin's curves at their Q.
fn write_shear_chart(path: &Path, points: &[MindlinPoint]) -> Result<()> {
    use plotters::prelude::*;
    let mut chosen: Vec<&MindlinPoint> = Vec::new();
    for target in [0.25, 0.5, 0.75] {
        if let Some(p) = points.iter().min_by(|a, b| {
            (a.ratio - target)
                .abs()
                .total_cmp(&(b.ratio - target).abs())
        }) {
            if !chosen.iter().any(|c| std::ptr::eq(*c, p)) {
                chosen.push(p);
            }
        }
    }
    let colours = [BLUE, RED, GREEN];
    crate::output::chart::write_svg(path, (720, 480), |root, draw| {
        let mut chart = ChartBuilder::on(root)
            .caption(
                "Shear traction against Cattaneo-Mindlin",
                ("sans-serif", 18),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..1.3f64, 0.0..1.2f64)
            .map_err(|e| draw(&e))?;
        chart
            .configure_mesh()
            .x_desc("r / a")
            .y_desc("|q_x| / (μ p0)")
            .draw()
            .map_err(|e| draw(&e))?;
        for (p, colour) in chosen.iter().zip(colours) {
            let c = p.theory_stick_ratio;
            let curve: Vec<(f64, f64)> = (0..=200)
                .map(|k| {
                    let r = k as f64 / 200.0;
                    (r, mindlin_shear(r, 1.0, c))
                })
                .collect();
            chart
                .draw_series(LineSeries::new(curve, colour.stroke_width(2)))
                .map_err(|e| draw(&e))?
                .label(format!("Q/(μP) = {:.2}: Mindlin", p.ratio))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2))
                });
            chart
                .draw_series(
                    p.profile
                        .iter()
                        .map(|&(r, q)| Circle::new((r, q), 3, colour.filled())),
                )
                .map_err(|e| draw(&e))?
                .label("particles")
                .legend(move |(x, y)| Circle::new((x + 9, y), 3, colour.filled()));
        }
        crate::output::chart::legend(&mut chart)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(|e| draw(&e))?;
        Ok(())
    })
}
