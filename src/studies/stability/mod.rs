//! `pdcontact sweep --stability`: where the explicit solver and the contact methods stop
//! working, on coarse spheres (Δ = 0.12 m, a/R = 0.3, the scenes of [`crate::studies::sweep`]).
//!
//! Three parameters, mapped two at a time, each map through the defaults of the third
//! (dt = 0.8 of the stable estimate, the solver's default; the paper's penalty; a static load):
//!
//! * **time step**: dt = 0.25 … 4 times the estimated stable step (re-estimated for each run);
//! * **penalty** (point-to-surface only): the Hertz K times 0.01 … 100, through the penalty
//!   radius R = (Δ/2)·f² (K ∝ √R);
//! * **impact speed**: 0.1 … 10⁴ m/s, up to and past the speed that moves a particle through
//!   the contact window 0.5Δ in one step, or **static**: the sphere pressed by Hertz's load and
//!   damped to rest.
//!
//! Maps: point-to-surface dt × penalty (static), dt × speed and penalty × speed; short-range
//! dt × speed (it has no penalty). A run is classed by what the solver itself reports:
//! **blew up** (NaN, kinetic energy exploded, energy growth, displacement growth), **missed
//! contacts** (a slave particle behind a master segment beyond the window, or through the
//! master's surface for the short-range method), otherwise **stable and accurate** (MRE ≤ 10 %)
//! or **stable but inaccurate**. An impact has no static answer: it is stable or not.
//!
//! Static runs stop once settled ([`SETTLED`]); an impact (no load, undamped) stops once the
//! sphere's momentum has turned back: its penetration has peaked by then.

use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use serde::{Deserialize, Serialize};

mod report;

pub use report::{table, write_chart};

use crate::body::Body;
use crate::error::{Error, Result};
use crate::model::Model;
use crate::output::analysis::{contact_patch, elliptic_accuracy, hertz_sphere};
use crate::output::vtk::write_atomically;
use crate::scene::{ContactMethod, Scene};
use crate::solver::{free_factor, solve, stable_time_step, Monitor, DEFAULT_SAFETY};
use crate::studies::scenarios::{
    sphere_cap_case, sphere_on_block_case, Reference, ValidationCase, STUDY_CONTACT_RADIUS,
    STUDY_DAMPING, STUDY_END_TIME,
};

/// Spacing of the stability scenes (m).
pub const SPACING: f64 = 0.12;
/// MRE above which a stable run counts as inaccurate.
pub const ACCURATE: f64 = 0.10;
/// dt over the estimated stable step.
pub const DT_MULTIPLES: [f64; 7] = [0.25, 0.5, 0.8, 1.0, 1.5, 2.0, 4.0];
/// K over the Hertz K of R = Δ/2 (point-to-surface).
pub const PENALTY_MULTIPLES: [f64; 5] = [0.01, 0.1, 1.0, 10.0, 100.0];
/// Impact speeds (m/s), half a decade apart.
pub const IMPACT_SPEEDS: [f64; 11] = [
    0.1, 0.316, 1.0, 3.16, 10.0, 31.6, 100.0, 316.0, 1000.0, 3160.0, 10000.0,
];
/// A static run has settled when the out-of-balance force is below this fraction of the
/// load: its MRE is then within 0.3 % (absolute) of a run twice as long, on both scenes.
pub const SETTLED: f64 = 5e-3;
/// Longest simulated impact (s): the slowest, softest impact turns back after 0.1 s.
pub const IMPACT_END_TIME: f64 = 0.2;

/// How the sphere is loaded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Loading {
    /// Hertz's load, damped to rest: compared with Hertz.
    Static,
    /// Thrown at the master at this speed (m/s), no load, undamped.
    Impact(f64),
}

/// The parameters of one run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunPoint {
    pub method: ContactMethod,
    pub dt_multiple: f64,
    /// 1 for short-range, which has no penalty.
    pub penalty_multiple: f64,
    pub loading: Loading,
}

impl RunPoint {
    fn label(&self) -> String {
        let method = match self.method {
            ContactMethod::PointToSurface => "pts",
            ContactMethod::ShortRange => "sr",
        };
        let loading = match self.loading {
            Loading::Static => "static".to_string(),
            Loading::Impact(v) => format!("v{v}"),
        };
        format!(
            "{method}-dt{}-k{}-{loading}",
            self.dt_multiple, self.penalty_multiple
        )
    }
}

/// A map's axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    TimeStep,
    Penalty,
    /// The impact speeds and a "static" row.
    Speed,
}

/// One map: a method, two parameters; the third stays at its default.
#[derive(Clone, Copy, Debug)]
pub struct Map {
    pub method: ContactMethod,
    pub x: Axis,
    pub y: Axis,
}

/// The four maps.
pub const MAPS: [Map; 4] = [
    Map {
        method: ContactMethod::PointToSurface,
        x: Axis::TimeStep,
        y: Axis::Penalty,
    },
    Map {
        method: ContactMethod::PointToSurface,
        x: Axis::TimeStep,
        y: Axis::Speed,
    },
    Map {
        method: ContactMethod::PointToSurface,
        x: Axis::Penalty,
        y: Axis::Speed,
    },
    Map {
        method: ContactMethod::ShortRange,
        x: Axis::TimeStep,
        y: Axis::Speed,
    },
];

/// A parameter's value: a multiple, or a loading for [`Axis::Speed`].
#[derive(Clone, Copy, Debug, PartialEq)]
enum Value {
    Multiple(f64),
    Loading(Loading),
}

impl Axis {
    fn values(self) -> Vec<Value> {
        match self {
            Axis::TimeStep => DT_MULTIPLES.iter().map(|&v| Value::Multiple(v)).collect(),
            Axis::Penalty => PENALTY_MULTIPLES
                .iter()
                .map(|&v| Value::Multiple(v))
                .collect(),
            Axis::Speed => std::iter::once(Value::Loading(Loading::Static))
                .chain(
                    IMPACT_SPEEDS
                        .iter()
                        .map(|&v| Value::Loading(Loading::Impact(v))),
                )
                .collect(),
        }
    }

    /// Where a value sits on the chart: speeds as they are, "static" a decade below them.
    fn position(self, v: Value) -> f64 {
        match v {
            Value::Multiple(m) => m,
            Value::Loading(Loading::Impact(s)) => s,
            Value::Loading(Loading::Static) => STATIC_ROW,
        }
    }

    fn describe(self) -> &'static str {
        match self {
            Axis::TimeStep => "dt / estimated stable step",
            Axis::Penalty => "K / Hertz K (R = Δ/2)",
            Axis::Speed => "impact speed (m/s)",
        }
    }
}

/// Where the static row of a speed axis is drawn (a decade below the slowest impact).
const STATIC_ROW: f64 = 0.01;

impl Map {
    fn point(&self, x: Value, y: Value) -> RunPoint {
        let mut p = RunPoint {
            method: self.method,
            dt_multiple: DEFAULT_SAFETY,
            penalty_multiple: 1.0,
            loading: Loading::Static,
        };
        for (axis, v) in [(self.x, x), (self.y, y)] {
            match (axis, v) {
                (Axis::TimeStep, Value::Multiple(m)) => p.dt_multiple = m,
                (Axis::Penalty, Value::Multiple(m)) => p.penalty_multiple = m,
                (Axis::Speed, Value::Loading(l)) => p.loading = l,
                _ => {}
            }
        }
        p
    }

    /// Whether a run is a cell of this map: its method, and the third parameter at its default.
    #[cfg(test)]
    fn contains(&self, p: &RunPoint) -> bool {
        let free = |a: Axis| self.x == a || self.y == a;
        p.method == self.method
            && (free(Axis::TimeStep) || p.dt_multiple == DEFAULT_SAFETY)
            && (free(Axis::Penalty) || p.penalty_multiple == 1.0)
            && (free(Axis::Speed) || p.loading == Loading::Static)
    }

    fn title(&self) -> String {
        let name = |a: Axis| match a {
            Axis::TimeStep => "time step",
            Axis::Penalty => "penalty",
            Axis::Speed => "impact speed",
        };
        let rest = match (self.method, self.x, self.y) {
            (ContactMethod::ShortRange, ..) => "",
            (_, Axis::TimeStep, Axis::Penalty) => " (static load)",
            (_, Axis::TimeStep, Axis::Speed) => " (penalty R = Δ/2)",
            _ => " (dt = 0.8 × stable)",
        };
        format!(
            "{}: {} × {}{rest}",
            self.method.name(),
            name(self.x),
            name(self.y)
        )
    }
}

/// Every run the maps need, each once.
pub fn plan() -> Vec<RunPoint> {
    let mut out: Vec<RunPoint> = Vec::new();
    for map in MAPS {
        for x in map.x.values() {
            for y in map.y.values() {
                let p = map.point(x, y);
                if !out.contains(&p) {
                    out.push(p);
                }
            }
        }
    }
    out
}

/// One run of the maps.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct StabilityRun {
    pub method: String,
    /// "static" (Hertz's load, damped to rest) or "impact" (thrown, no load, undamped).
    pub loading: String,
    /// dt over the estimated stable step.
    pub dt_multiple: f64,
    /// The time step (s) and the stable estimate it is a multiple of.
    pub dt: f64,
    pub stable_dt: f64,
    /// K over the Hertz K of R = Δ/2 (point-to-surface; 1 for short-range).
    pub penalty_multiple: f64,
    /// Impact speed (m/s; 0 for the static runs).
    pub impact_speed: f64,
    /// The contact window 0.5Δ of the sphere (m).
    pub window: f64,
    /// Distance a particle moves in one step at the impact speed, over the window.
    pub step_over_window: f64,
    /// "stable and accurate", "stable but inaccurate", "stable" (impact), "missed contacts"
    /// or "blew up".
    pub outcome: String,
    pub mre: Option<f64>,
    /// Largest penetration over the window (point-to-surface).
    pub peak_penetration: Option<f64>,
    /// "settled", "turned back" (impact), "end time" or "error".
    pub ended: String,
    pub steps: usize,
    /// Largest relative drift of the total energy (runs that did not fail).
    pub energy_drift: Option<f64>,
    pub wall_seconds: f64,
    /// The solver's message when it stopped.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
}

impl StabilityRun {
    fn point(&self) -> RunPoint {
        RunPoint {
            method: if self.method == ContactMethod::ShortRange.name() {
                ContactMethod::ShortRange
            } else {
                ContactMethod::PointToSurface
            },
            dt_multiple: self.dt_multiple,
            penalty_multiple: self.penalty_multiple,
            loading: if self.loading == "impact" {
                Loading::Impact(self.impact_speed)
            } else {
                Loading::Static
            },
        }
    }
}

/// Classes a solver error by the failure it names.
pub fn classify_error(message: &str) -> &'static str {
    if message.contains("missed contact") {
        "missed contacts"
    } else {
        "blew up"
    }
}

/// The scene of a run. `sphere_spacing` is the spacing the cap generator gives the sphere (it
/// fits its layers to the sector): an impact on the block starts with the sphere at the
/// short-range distance d, the edge of the repulsion zone.
pub fn case(p: &RunPoint, sphere_spacing: f64) -> ValidationCase {
    let a = STUDY_CONTACT_RADIUS;
    // The block settles more slowly than the sector (docs/SPEED_ACCURACY.md).
    let settle = match p.method {
        ContactMethod::ShortRange => 3.0 * STUDY_END_TIME,
        ContactMethod::PointToSurface => STUDY_END_TIME,
    };
    let solver = match p.loading {
        Loading::Static => format!(
            "kind = \"explicit\"\nsafety = {}\ndamping = {STUDY_DAMPING}\nend_time = {settle}",
            p.dt_multiple
        ),
        Loading::Impact(_) => format!(
            "kind = \"explicit\"\nsafety = {}\nend_time = {IMPACT_END_TIME}",
            p.dt_multiple
        ),
    };
    let label = p.label();
    let mut case = match p.method {
        ContactMethod::ShortRange => {
            let d = crate::contact::shortrange::DISTANCE;
            let lift = match p.loading {
                Loading::Static => d * SPACING,
                Loading::Impact(_) => d * sphere_spacing,
            };
            sphere_on_block_case(
                a,
                SPACING,
                3.0,
                &solver,
                "method = \"short-range\"",
                lift,
                &label,
            )
        }
        ContactMethod::PointToSurface => {
            let radius = 0.5 * SPACING * p.penalty_multiple * p.penalty_multiple;
            sphere_cap_case(
                a,
                SPACING,
                3.0,
                &solver,
                &format!("radius = {radius:e}"),
                &label,
            )
        }
    };
    if let Loading::Impact(speed) = p.loading {
        case.scene = thrown(&case.scene, speed);
    }
    case
}

/// The scene with its first body (the sphere) thrown down at `speed` and no load.
fn thrown(scene: &str, speed: f64) -> String {
    let mut s = scene.replacen(
        "kinematics = \"small\"",
        &format!("kinematics = \"small\"\nvelocity = [0.0, 0.0, -{speed:e}]"),
        1,
    );
    while let Some(start) = s.find("[[load]]") {
        let end = s[start..].find("\n\n").map_or(s.len(), |e| start + e + 1);
        s.replace_range(start..end, "");
    }
    s
}

/// Out-of-balance force over the free degrees of freedom (masked as the solver masks them).
fn out_of_balance(model: &Model) -> f64 {
    let mut s = 0.0;
    for pd in model.bodies.iter().filter_map(Body::as_pd) {
        for (f, &mask) in pd.force.iter().zip(&pd.fixed) {
            // Component by component onto the running sum, as before the mask was shared: a
            // fixed component adds an exact zero.
            let r = f.component_mul(&free_factor(mask));
            for a in 0..3 {
                s += r[a] * r[a];
            }
        }
    }
    s.sqrt()
}

/// Stops a static run once it has settled and an impact once the sphere turns back; keeps
/// the largest penetration.
struct Watch {
    /// The static load's norm; `None` for an impact.
    load: Option<f64>,
    touched: bool,
    done: bool,
    steps: usize,
    peak_penetration: f64,
}

impl Monitor for Watch {
    fn step(&mut self, model: &Model, step: usize, _time: f64, _measure: f64) -> Result<()> {
        self.steps = step;
        for p in &model.passes {
            for c in &p.contacts {
                self.peak_penetration = self.peak_penetration.max(c.penetration / p.law.window);
            }
        }
        match self.load {
            Some(load) => {
                if step.is_multiple_of(10) && out_of_balance(model) <= SETTLED * load {
                    self.done = true;
                }
            }
            None => {
                self.touched |= model.contact_count() > 0;
                // The sphere is thrown along −z.
                let down: f64 = model.bodies[0].as_pd().map_or(0.0, |pd| {
                    pd.v.iter().zip(&pd.mass).map(|(v, m)| -v.z * m).sum()
                });
                if self.touched && down <= 0.0 {
                    self.done = true;
                }
            }
        }
        Ok(())
    }
    fn finish(&mut self, _: &Model, _: usize, _: f64) -> Result<()> {
        Ok(())
    }
    fn interrupted(&self) -> bool {
        self.done
    }
}

/// Runs one point in `folder/<label>/` (its scene is written there, to be rerun with
/// `pdcontact run`).
pub fn run_point(p: &RunPoint, folder: &Path, sphere_spacing: f64) -> Result<StabilityRun> {
    let case = case(p, sphere_spacing);
    let dir = folder.join(p.label());
    std::fs::create_dir_all(&dir).map_err(|e| Error::output(&dir, e))?;
    let path = dir.join("scene.toml");
    write_atomically(&path, |w| {
        std::io::Write::write_all(w, case.scene.as_bytes())
    })?;
    let start = Instant::now();
    let scene = Scene::parse(&case.scene, &path.display().to_string(), &dir)?;
    let mut model = Model::from_scene(&scene)?;
    let stable = stable_time_step(&model);
    let dt = p.dt_multiple * stable;
    let load = match p.loading {
        Loading::Static => {
            let load: f64 = model
                .bodies
                .iter()
                .filter_map(Body::as_pd)
                .flat_map(|pd| pd.load.iter())
                .map(|f| f.norm_squared())
                .sum();
            Some(load.sqrt())
        }
        Loading::Impact(_) => None,
    };
    let mut watch = Watch {
        load,
        touched: false,
        done: false,
        steps: 0,
        peak_penetration: 0.0,
    };
    let result = solve(&mut model, &scene.solver, &mut watch);
    let wall_seconds = start.elapsed().as_secs_f64();
    let speed = match p.loading {
        Loading::Static => 0.0,
        Loading::Impact(v) => v,
    };
    let window = crate::contact::WINDOW * sphere_spacing;
    let mut run = StabilityRun {
        method: p.method.name().into(),
        loading: match p.loading {
            Loading::Static => "static".into(),
            Loading::Impact(_) => "impact".into(),
        },
        dt_multiple: p.dt_multiple,
        dt,
        stable_dt: stable,
        penalty_multiple: p.penalty_multiple,
        impact_speed: speed,
        window,
        step_over_window: speed * dt / window,
        outcome: String::new(),
        mre: None,
        peak_penetration: (p.method == ContactMethod::PointToSurface)
            .then_some(watch.peak_penetration),
        ended: if watch.done {
            match p.loading {
                Loading::Static => "settled".into(),
                Loading::Impact(_) => "turned back".into(),
            }
        } else {
            "end time".into()
        },
        steps: watch.steps,
        energy_drift: None,
        wall_seconds,
        error: None,
    };
    match result {
        Ok(stats) => {
            run.energy_drift = Some(stats.energy_drift);
            run.outcome = match p.loading {
                Loading::Impact(_) => "stable".into(),
                Loading::Static => match static_mre(&model, &case) {
                    Some(mre) => {
                        run.mre = Some(mre);
                        if mre <= ACCURATE {
                            "stable and accurate".into()
                        } else {
                            "stable but inaccurate".into()
                        }
                    }
                    None => {
                        run.error = Some("no contact formed".into());
                        "stable but inaccurate".into()
                    }
                },
            };
        }
        Err(e) => {
            let msg = e.to_string();
            run.outcome = classify_error(&msg).into();
            run.ended = "error".into();
            run.error = Some(msg);
        }
    }
    Ok(run)
}

/// MRE of a settled static run against Hertz.
fn static_mre(model: &Model, case: &ValidationCase) -> Option<f64> {
    let Reference::Sphere {
        load,
        radius,
        e_stars,
    } = &case.reference
    else {
        return None;
    };
    let (_, e_star) = e_stars.first()?;
    let (a, p0) = hertz_sphere(*load, *radius, *e_star);
    let patch = contact_patch(model, 0, None)?;
    Some(elliptic_accuracy(&patch, a, p0).mre)
}

/// The spacing the cap generator gives the sphere of the scenes.
pub fn sphere_spacing(folder: &Path) -> Result<f64> {
    let p = RunPoint {
        method: ContactMethod::PointToSurface,
        dt_multiple: DEFAULT_SAFETY,
        penalty_multiple: 1.0,
        loading: Loading::Static,
    };
    let case = case(&p, SPACING);
    let scene = Scene::parse(&case.scene, &case.label, folder)?;
    let model = Model::from_scene(&scene)?;
    Ok(model.bodies[0].as_pd().map_or(SPACING, |b| b.spacing()))
}

/// Runs the maps into `folder`, as many runs at a time as there are cores (each on one
/// thread: these bodies are too small to share); writes `stability.json` and `stability.svg`.
pub fn run_stability(folder: &Path, quiet: bool) -> Result<Vec<StabilityRun>> {
    std::fs::create_dir_all(folder).map_err(|e| Error::output(folder, e))?;
    let spacing = sphere_spacing(folder)?;
    let mut points = plan();
    // The longest first, so that the workers finish together: static runs, stiff penalties,
    // small steps, slow impacts.
    let cost = |p: &RunPoint| {
        let settle = if p.loading == Loading::Static {
            4.0
        } else {
            1.0
        };
        settle * p.penalty_multiple.max(1.0).sqrt() / p.dt_multiple
    };
    points.sort_by(|a, b| cost(b).total_cmp(&cost(a)));
    let total = points.len();
    let workers = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(total);
    let next = AtomicUsize::new(0);
    let done = AtomicUsize::new(0);
    let failed = AtomicBool::new(false);
    let results: Mutex<Vec<StabilityRun>> = Mutex::new(Vec::with_capacity(total));
    let first_error: Mutex<Option<Error>> = Mutex::new(None);
    std::thread::scope(|s| {
        for _ in 0..workers {
            s.spawn(|| {
                let pool = match rayon::ThreadPoolBuilder::new().num_threads(1).build() {
                    Ok(pool) => pool,
                    Err(e) => {
                        failed.store(true, Ordering::SeqCst);
                        if let Ok(mut slot) = first_error.lock() {
                            slot.get_or_insert(Error::numerical(format!(
                                "cannot start a worker thread: {e}"
                            )));
                        }
                        return;
                    }
                };
                loop {
                    let k = next.fetch_add(1, Ordering::SeqCst);
                    if k >= total || failed.load(Ordering::SeqCst) {
                        return;
                    }
                    let p = &points[k];
                    match pool.install(|| run_point(p, folder, spacing)) {
                        Ok(run) => {
                            let n = done.fetch_add(1, Ordering::SeqCst) + 1;
                            if !quiet {
                                eprintln!("stability {n}/{total}: {}", describe(&run));
                            }
                            if let Ok(mut r) = results.lock() {
                                r.push(run);
                            }
                        }
                        Err(e) => {
                            failed.store(true, Ordering::SeqCst);
                            if let Ok(mut slot) = first_error.lock() {
                                slot.get_or_insert(e);
                            }
                            return;
                        }
                    }
                }
            });
        }
    });
    if let Some(e) = first_error.into_inner().ok().flatten() {
        return Err(e);
    }
    let mut runs = results.into_inner().unwrap_or_default();
    let order = plan();
    runs.sort_by_key(|r| order.iter().position(|p| *p == r.point()));
    let json = serde_json::to_string_pretty(&runs).map_err(|e| Error::output(folder, e))?;
    write_atomically(&folder.join("stability.json"), |w| {
        std::io::Write::write_all(w, json.as_bytes())
    })?;
    write_chart(&folder.join("stability.svg"), &runs)?;
    Ok(runs)
}

/// One line of progress.
fn describe(r: &StabilityRun) -> String {
    let loading = if r.loading == "impact" {
        format!("impact at {} m/s", r.impact_speed)
    } else {
        "static".into()
    };
    let mre = r
        .mre
        .map_or(String::new(), |m| format!(", MRE {:.1} %", 100.0 * m));
    format!(
        "{}, {loading}, dt x{}, K x{}: {}{mre} ({:.1} s)",
        r.method, r.dt_multiple, r.penalty_multiple, r.outcome, r.wall_seconds
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn failures_are_classed_by_the_solver_message() {
        assert_eq!(
            classify_error("missed contact at step 3: 25 slave particles are behind"),
            "missed contacts"
        );
        assert_eq!(
            classify_error("kinetic energy exploded to 4.3e3 J at step 25"),
            "blew up"
        );
    }

    /// Every cell of every map is one run, and the maps share the runs at their defaults.
    #[test]
    fn the_plan_fills_every_map_once() {
        let plan = plan();
        for map in MAPS {
            let cells = map.x.values().len() * map.y.values().len();
            assert_eq!(plan.iter().filter(|p| map.contains(p)).count(), cells);
        }
        let (dt, k, v) = (
            DT_MULTIPLES.len(),
            PENALTY_MULTIPLES.len(),
            IMPACT_SPEEDS.len(),
        );
        // Point-to-surface: dt × K static, dt × v at K = 1, K × v at dt = 0.8 less the
        // shared row; short-range: dt × (v and static).
        assert_eq!(plan.len(), dt * k + dt * v + (k - 1) * v + dt * (v + 1));
    }

    /// An impact scene has no load, the sphere's velocity, and an undamped solver.
    #[test]
    fn impact_scenes_throw_the_sphere_without_a_load() {
        for method in [ContactMethod::PointToSurface, ContactMethod::ShortRange] {
            let p = RunPoint {
                method,
                dt_multiple: 0.5,
                penalty_multiple: 1.0,
                loading: Loading::Impact(3.16),
            };
            let case = case(&p, 0.088);
            let scene = Scene::parse(&case.scene, "impact", Path::new(".")).expect("parses");
            assert!(scene.loads.is_empty(), "{}", case.scene);
            assert_eq!(scene.bodies[0].velocity, Some([0.0, 0.0, -3.16]));
            assert_eq!(scene.solver.safety, Some(0.5));
            assert_eq!(scene.solver.damping, None);
        }
    }
}
