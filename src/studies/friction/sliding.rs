//! A block on a plane tilted at θ (METHOD.md §10): at rest for tan θ ≤ μ, else sliding with
//! acceleration `g (sin θ − μ cos θ)`. The plane is a rigid body at z = 0 and gravity is
//! turned by θ, which is the same problem; explicit dynamics, no damping.

use std::path::Path;

use serde::Serialize;

use super::run_in;
use crate::error::Result;
use crate::model::Model;
use crate::solver::Monitor;

/// Gravity, m/s².
pub const GRAVITY: f64 = 9.81;
/// The block: 0.1 × 0.1 × 0.05 m of a stiff rubber-like solid.
const SIZE: [f64; 3] = [0.1, 0.1, 0.05];
const DENSITY: f64 = 1000.0;
const YOUNGS: f64 = 1e8;

/// One block: the slope, the friction, the spacing and how long it runs.
#[derive(Clone, Debug)]
pub struct SlidingBlock {
    /// tan θ.
    pub slope: f64,
    /// Coulomb's μ.
    pub friction: f64,
    /// Grid spacing Δ, m.
    pub spacing: f64,
    /// Simulated time, s.
    pub end_time: f64,
}

impl SlidingBlock {
    /// The theory's acceleration along the slope: `g (sin θ − μ cos θ)`, or 0 where friction
    /// holds the block.
    pub fn acceleration(&self) -> f64 {
        let theta = self.slope.atan();
        (GRAVITY * (theta.sin() - self.friction * theta.cos())).max(0.0)
    }

    /// How deep the block's bottom particles sink into the plane at rest: the Hertz
    /// penalty's `(F/K)^{2/3}` (Eq. 23, R = Δ/2) under an even share of the weight's normal
    /// part. The block starts there, at rest: dropped from the surface it would bounce on the
    /// penalty, lose contact at the top of each bounce and take a fresh stick point each time
    /// it lands, creeping down a slope it should hold.
    pub fn resting_penetration(&self) -> f64 {
        let theta = self.slope.atan();
        let mass = DENSITY * SIZE[0] * SIZE[1] * SIZE[2];
        let columns =
            ((SIZE[0] / self.spacing).round() + 1.0) * ((SIZE[1] / self.spacing).round() + 1.0);
        let m = (1.0 - 0.25f64 * 0.25) / YOUNGS;
        let k =
            crate::contact::hertz_stiffness(m, 0.0, crate::contact::default_radius(self.spacing));
        (mass * GRAVITY * theta.cos() / columns / k).powf(2.0 / 3.0)
    }

    /// The scene.
    pub fn scene(&self) -> String {
        let theta = self.slope.atan();
        let mass = DENSITY * SIZE[0] * SIZE[1] * SIZE[2];
        let (fx, fz) = (mass * GRAVITY * theta.sin(), -mass * GRAVITY * theta.cos());
        format!(
            r#"# A block on a plane tilted at atan({slope}) (gravity turned instead), Coulomb friction
# mu = {mu}: `pdcontact friction --case sliding`.
[solver]
kind = "explicit"
end_time = {end}

[output]
folder = "."
every = 1000000

[[body]]
name = "block"
generator = {{ shape = "box", min = [0.0, 0.0, 0.0], max = [{sx}, {sy}, {sz}], spacing = {dx} }}
translate = [0.0, 0.0, -{sink:e}]   # resting on the penalty: the bottom sunk as at rest
kinematics = "small"
[body.material]
youngs_modulus = {YOUNGS:e}
poisson_ratio = 0.25
density = {DENSITY}

[[body]]
name = "plane"
kind = "rigid"
generator = {{ shape = "plane", point = [{cx}, {cy}, 0.0], normal = [0.0, 0.0, 1.0], size = 4.0, divisions = 1 }}

[[contact]]
slave = "block"
master = "plane"
friction = {mu}

[[load]]
body = "block"
force = [{fx:e}, 0.0, {fz:e}]
"#,
            slope = self.slope,
            mu = self.friction,
            end = self.end_time,
            sx = SIZE[0],
            sy = SIZE[1],
            sz = SIZE[2],
            dx = self.spacing,
            cx = 0.5 * SIZE[0],
            cy = 0.5 * SIZE[1],
            sink = self.resting_penetration(),
        )
    }
}

/// What one block did.
#[derive(Clone, Debug, Serialize)]
pub struct SlidingResult {
    pub slope: f64,
    pub friction: f64,
    pub spacing: f64,
    pub particles: usize,
    pub steps: usize,
    /// The theory's acceleration along the slope (0 where the block holds), m/s².
    pub theory: f64,
    /// The block's: a parabola fitted to its centre of mass over the last four fifths of
    /// the run, m/s².
    pub acceleration: f64,
    /// Its distance along the slope at the end, m, and what it would be without friction.
    pub distance: f64,
    pub frictionless_distance: f64,
    /// The block's particles in contact that stick and that slip at the end.
    pub sticking: usize,
    pub slipping: usize,
    pub energy_drift: f64,
    pub wall_seconds: f64,
}

impl SlidingResult {
    /// The acceleration's error against the theory's, relative to it (sliding), or to the
    /// frictionless acceleration (holding).
    pub fn error(&self) -> f64 {
        let theta = self.slope.atan();
        let scale = if self.theory > 0.0 {
            self.theory
        } else {
            GRAVITY * theta.sin()
        };
        (self.acceleration - self.theory) / scale
    }
}

/// The centre of mass's distance along x at each step.
struct History {
    samples: Vec<(f64, f64)>,
}

impl Monitor for History {
    fn step(&mut self, model: &Model, _: usize, time: f64, _: f64) -> Result<()> {
        let pd = model.bodies[0].as_pd().expect("the block is deformable");
        let (mut m, mut mx) = (0.0, 0.0);
        for (u, mass) in pd.u.iter().zip(&pd.mass) {
            m += mass;
            mx += mass * u.x;
        }
        self.samples.push((time, mx / m));
        Ok(())
    }
    fn finish(&mut self, _: &Model, _: usize, _: f64) -> Result<()> {
        Ok(())
    }
}

/// Least squares `x = c0 + c1 t + ½ a t²`: returns `a`.
fn fitted_acceleration(samples: &[(f64, f64)]) -> f64 {
    let mut ata = nalgebra::Matrix3::<f64>::zeros();
    let mut atb = nalgebra::Vector3::<f64>::zeros();
    for &(t, x) in samples {
        let row = nalgebra::Vector3::new(1.0, t, 0.5 * t * t);
        ata += row * row.transpose();
        atb += row * x;
    }
    ata.cholesky().map_or(f64::NAN, |c| c.solve(&atb)[2])
}

/// Runs one block into `folder`.
pub fn run_sliding(block: &SlidingBlock, folder: &Path, quiet: bool) -> Result<SlidingResult> {
    let mut history = History {
        samples: Vec::new(),
    };
    let (model, summary, wall) = run_in(&block.scene(), folder, quiet, &mut history)?;
    let t_end = block.end_time;
    let tail: Vec<(f64, f64)> = history
        .samples
        .iter()
        .copied()
        .filter(|&(t, _)| t >= 0.2 * t_end)
        .collect();
    let friction = summary.friction.first();
    let theta = block.slope.atan();
    Ok(SlidingResult {
        slope: block.slope,
        friction: block.friction,
        spacing: block.spacing,
        particles: model.particles(),
        steps: summary.iterations,
        theory: block.acceleration(),
        acceleration: fitted_acceleration(&tail),
        distance: history.samples.last().map_or(0.0, |s| s.1),
        frictionless_distance: 0.5 * GRAVITY * theta.sin() * t_end * t_end,
        sticking: friction.map_or(0, |f| f.sticking),
        slipping: friction.map_or(0, |f| f.slipping),
        energy_drift: summary.solver.energy_drift,
        wall_seconds: wall,
    })
}

impl SlidingResult {
    /// One line a user reads.
    pub fn to_text(&self) -> String {
        let theta = self.slope.atan().to_degrees();
        format!(
            "tan θ = {:.3} (θ = {:.2}°), μ = {}: acceleration {:.4} m/s² against {:.4} ({}), {:+.2} %; travelled {:.3e} m (frictionless {:.3e}); {} particles sticking, {} slipping; {} steps, energy drift {:.2} %, {:.1} s\n",
            self.slope,
            theta,
            self.friction,
            self.acceleration,
            self.theory,
            if self.theory > 0.0 { "slides" } else { "holds" },
            100.0 * self.error(),
            self.distance,
            self.frictionless_distance,
            self.sticking,
            self.slipping,
            self.steps,
            100.0 * self.energy_drift,
            self.wall_seconds
        )
    }
}
