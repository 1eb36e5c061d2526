//! `pdcontact sweep --stability`: where the explicit solver and the contact methods stop
//! working, on coarse spheres (Δ = 0.12 m, a/R = 0.3, the scenes of [`crate::sweep`]).
//!
//! Three one-parameter scans, each from the defaults of the others:
//!
//! * **time step**: dt = 0.25 … 4 times the estimated stable step, damped quasi-static runs;
//! * **penalty** (point-to-surface only): the Hertz K times 0.01 … 100, through the penalty
//!   radius R = (Δ/2)·f² (K ∝ √R), at 0.8 of the stable step (re-estimated for each K);
//! * **impact speed**: the sphere thrown at the master (undamped, [`IMPACT_STEPS`] steps), at
//!   speeds that move a particle 0.003 … 1 times the contact window (0.5Δ) in one step at 0.8
//!   of the stable step.
//!
//! Each run is classed by what the solver itself reports: **blew up** (NaN, kinetic energy
//! exploded, energy growth, displacement growth, ADR divergence), **missed contacts** (a slave
//! particle behind a master segment beyond the window, or through the master's surface for the
//! short-range method), otherwise **stable and accurate** (MRE ≤ 10 %) or **stable but
//! inaccurate**. Impact runs have no static answer: they are stable or not.

use std::path::Path;

use plotters::prelude::*;
use serde::Serialize;

use crate::error::{Error, Result};
use crate::model::Model;
use crate::scene::Scene;
use crate::solver::stable_time_step;
use crate::validate::{
    run_case, sphere_cap_case, sphere_on_block_case, ValidationCase, STUDY_CONTACT_RADIUS,
    STUDY_DAMPING, STUDY_END_TIME,
};
use crate::vtk::write_atomically;

/// Spacing of the stability scenes (m).
pub const SPACING: f64 = 0.12;
/// Steps of an impact run (5 ms at Δ = 0.12 m: the sphere is stopped and thrown back).
pub const IMPACT_STEPS: usize = 600;
/// MRE above which a stable run counts as inaccurate.
pub const ACCURATE: f64 = 0.10;

/// One run of the stability scans.
#[derive(Clone, Debug, Serialize)]
pub struct StabilityRun {
    /// "time step", "penalty" or "impact".
    pub scan: String,
    pub method: String,
    /// dt over the estimated stable step.
    pub dt_multiple: f64,
    /// K over the Hertz K of R = Δ/2 (point-to-surface; 1 for short-range).
    pub penalty_multiple: f64,
    /// Impact speed (m/s; 0 for the quasi-static runs).
    pub impact_speed: f64,
    /// Distance a particle moves in one step over the contact window 0.5Δ.
    pub step_over_window: f64,
    /// "stable and accurate", "stable but inaccurate", "missed contacts" or "blew up".
    pub outcome: String,
    pub mre: Option<f64>,
    pub wall_seconds: f64,
    /// The solver's message when it stopped.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
}

/// Classes a solver error by the failure it names.
pub fn classify_error(message: &str) -> &'static str {
    if message.contains("missed contact") {
        "missed contacts"
    } else {
        "blew up"
    }
}

fn explicit_solver(safety: f64, end_time: f64, damping: f64) -> String {
    format!("kind = \"explicit\"\nsafety = {safety}\ndamping = {damping}\nend_time = {end_time}")
}

fn case_for(method: &str, solver: &str, penalty: f64, label: &str) -> ValidationCase {
    let a = STUDY_CONTACT_RADIUS;
    if method == "short-range" {
        sphere_on_block_case(
            a,
            SPACING,
            3.0,
            solver,
            "method = \"short-range\"",
            crate::shortrange::DISTANCE * SPACING,
            label,
        )
    } else {
        let radius = 0.5 * SPACING * penalty * penalty;
        sphere_cap_case(
            a,
            SPACING,
            3.0,
            solver,
            &format!("radius = {radius:e}"),
            label,
        )
    }
}

/// The estimated stable step of a case's scene and the sphere's spacing (the cap generator
/// fits its layers to the sector, so the spacing is not exactly the requested one).
fn stable_step(case: &ValidationCase, folder: &Path) -> Result<(f64, f64)> {
    let scene = Scene::parse(&case.scene, &case.label, folder)?;
    let model = Model::from_scene(&scene)?;
    let spacing = model.bodies[0].as_pd().map_or(SPACING, |b| b.spacing());
    Ok((stable_time_step(&model), spacing))
}

/// The sphere of `case` thrown at the master at `speed` (undamped), for `steps` steps at
/// `safety` of the stable step `dt`.
fn impact(case: &mut ValidationCase, speed: f64, dt: f64, steps: usize) {
    case.scene = case.scene.replacen(
        "kinematics = \"small\"",
        &format!("kinematics = \"small\"\nvelocity = [0.0, 0.0, -{speed:e}]"),
        1,
    );
    let solver_start = case.scene.find("[solver]").unwrap_or(0);
    let solver_end = case.scene[solver_start..]
        .find("\n\n")
        .map_or(case.scene.len(), |e| solver_start + e);
    case.scene.replace_range(
        solver_start..solver_end,
        &format!(
            "[solver]\nkind = \"explicit\"\ndt = {dt:e}\nend_time = {:e}",
            dt * steps as f64
        ),
    );
}

/// Runs the three scans into `folder`; writes `stability.json` and `stability.svg`.
pub fn run_stability(folder: &Path, quiet: bool) -> Result<Vec<StabilityRun>> {
    std::fs::create_dir_all(folder).map_err(|e| Error::output(folder, e))?;
    let mut runs = Vec::new();
    let methods = ["point-to-surface", "short-range"];
    let mut plan: Vec<(String, String, f64, f64, f64)> = Vec::new();
    for method in methods {
        for f in [0.25, 0.5, 1.0, 1.5, 2.0, 4.0] {
            plan.push(("time step".into(), method.into(), f, 1.0, 0.0));
        }
    }
    for f in [0.01, 0.1, 1.0, 10.0, 100.0] {
        plan.push(("penalty".into(), methods[0].into(), 0.8, f, 0.0));
    }
    for method in methods {
        for frac in [0.003, 0.01, 0.03, 0.1, 0.3, 1.0] {
            plan.push(("impact".into(), method.into(), 0.8, 1.0, frac));
        }
    }
    let total = plan.len();
    for (k, (scan, method, dtm, pen, frac)) in plan.into_iter().enumerate() {
        let label = format!(
            "stability-{}-{}-dt{dtm}-k{pen}-v{frac}",
            scan.replace(' ', "-"),
            method
        );
        // The block settles more slowly than the sector (docs/SPEED_ACCURACY.md).
        let end = if method == "short-range" {
            3.0 * STUDY_END_TIME
        } else {
            STUDY_END_TIME
        };
        let mut case = case_for(
            &method,
            &explicit_solver(dtm, end, STUDY_DAMPING),
            pen,
            &label,
        );
        let mut speed = 0.0;
        let mut step_over_window = 0.0;
        if scan == "impact" {
            let (stable, spacing) = stable_step(&case, folder)?;
            let dt = 0.8 * stable;
            speed = frac * crate::contact::WINDOW * spacing / dt;
            step_over_window = frac;
            impact(&mut case, speed, dt, IMPACT_STEPS);
        }
        if !quiet {
            eprintln!(
                "stability {}/{total}: {scan}, {method}, dt x{dtm}, K x{pen}, v = {speed:.3e} m/s ...",
                k + 1
            );
        }
        let start = std::time::Instant::now();
        let result = run_case(&case, folder, true);
        let wall_seconds = start.elapsed().as_secs_f64();
        let (outcome, mre, error) = match result {
            Ok(_) if scan == "impact" => ("stable".to_string(), None, None),
            Ok(rows) => {
                let mre = rows.first().map_or(f64::NAN, |r| r.mre);
                let o = if mre <= ACCURATE {
                    "stable and accurate"
                } else {
                    "stable but inaccurate"
                };
                (o.to_string(), Some(mre), None)
            }
            Err(e) => {
                let msg = e.to_string();
                if msg.contains("no contact formed") && scan == "impact" {
                    ("stable".to_string(), None, None)
                } else {
                    (classify_error(&msg).to_string(), None, Some(msg))
                }
            }
        };
        runs.push(StabilityRun {
            scan,
            method,
            dt_multiple: dtm,
            penalty_multiple: pen,
            impact_speed: speed,
            step_over_window,
            outcome,
            mre,
            wall_seconds,
            error,
        });
    }
    let json = serde_json::to_string_pretty(&runs).map_err(|e| Error::output(folder, e))?;
    write_atomically(&folder.join("stability.json"), |w| {
        std::io::Write::write_all(w, json.as_bytes())
    })?;
    write_chart(&folder.join("stability.svg"), &runs)?;
    Ok(runs)
}

/// The table of the runs (Markdown).
pub fn table(runs: &[StabilityRun]) -> String {
    let mut s = String::from("| scan | method | dt / stable | K / Hertz K | impact speed (m/s) | step / window | outcome | MRE | wall s |\n|---|---|---:|---:|---:|---:|---|---:|---:|\n");
    for r in runs {
        s.push_str(&format!(
            "| {} | {} | {} | {} | {:.3e} | {} | {} | {} | {:.1} |\n",
            r.scan,
            r.method,
            r.dt_multiple,
            r.penalty_multiple,
            r.impact_speed,
            r.step_over_window,
            r.outcome,
            r.mre
                .map_or(String::new(), |m| format!("{:.2} %", 100.0 * m)),
            r.wall_seconds
        ));
    }
    s
}

fn colour(outcome: &str) -> RGBColor {
    match outcome {
        "stable and accurate" | "stable" => RGBColor(0, 150, 0),
        "stable but inaccurate" => RGBColor(230, 160, 0),
        "missed contacts" => RGBColor(0, 90, 220),
        _ => RGBColor(210, 0, 0),
    }
}

/// One panel per scan: the parameter (log axis) against the method, coloured by outcome.
fn write_chart(path: &Path, runs: &[StabilityRun]) -> Result<()> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (1200, 420)).into_drawing_area();
        let draw = |e: &dyn std::fmt::Display| Error::output(path, e.to_string());
        root.fill(&WHITE).map_err(|e| draw(&e))?;
        let (top, bottom) = root.split_vertically(370);
        let panels = top.split_evenly((1, 3));
        let scans: [(&str, &str, f64, f64); 3] = [
            ("time step", "dt / estimated stable step", 0.15, 7.0),
            ("penalty", "K / Hertz K (R = Δ/2)", 0.005, 200.0),
            ("impact", "step of a particle / window 0.5Δ", 0.002, 1.5),
        ];
        for (panel, (scan, axis, lo, hi)) in panels.iter().zip(scans) {
            let mut chart = ChartBuilder::on(panel)
                .caption(scan, ("sans-serif", 16))
                .margin(10)
                .x_label_area_size(35)
                .y_label_area_size(110)
                .build_cartesian_2d((lo..hi).log_scale(), -0.5f64..1.5f64)
                .map_err(|e| draw(&e))?;
            chart
                .configure_mesh()
                .x_desc(axis)
                .y_labels(2)
                .y_label_formatter(&|y| {
                    if *y < 0.5 {
                        "point-to-surface".into()
                    } else {
                        "short-range".into()
                    }
                })
                .disable_y_mesh()
                .draw()
                .map_err(|e| draw(&e))?;
            let pts = runs.iter().filter(|r| r.scan == scan).map(|r| {
                let x = match scan {
                    "time step" => r.dt_multiple,
                    "penalty" => r.penalty_multiple,
                    _ => r.step_over_window,
                };
                let y = if r.method == "short-range" { 1.0 } else { 0.0 };
                Circle::new((x, y), 7, colour(&r.outcome).filled())
            });
            chart.draw_series(pts).map_err(|e| draw(&e))?;
        }
        let legend = [
            "stable and accurate (impact: stable)",
            "stable but inaccurate (MRE > 10 %)",
            "missed contacts",
            "blew up",
        ];
        let outcomes = [
            "stable",
            "stable but inaccurate",
            "missed contacts",
            "blew up",
        ];
        for (k, (text, o)) in legend.iter().zip(outcomes).enumerate() {
            let x = 20 + 290 * k as i32;
            bottom
                .draw(&Circle::new((x, 25), 7, colour(o).filled()))
                .map_err(|e| draw(&e))?;
            bottom
                .draw(&Text::new(*text, (x + 12, 18), ("sans-serif", 14)))
                .map_err(|e| draw(&e))?;
        }
        root.present().map_err(|e| draw(&e))?;
    }
    write_atomically(path, |w| std::io::Write::write_all(w, svg.as_bytes()))
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
}
