//! `pdcontact sweep --case sphere`: speed against accuracy over a grid of spacings, horizons,
//! contact methods and solvers, on the Hertz sphere of [`crate::studies::validate`].
//!
//! The sphere has a/R = 0.3 (the convergence studies' sphere, [`STUDY_CONTACT_RADIUS`]): at
//! a/R = 0.15 the same a/Δ costs eight times the particles, and the grid would not run in
//! minutes on two cores. The FE points are the same sphere at the same a/R = 0.3, solved by
//! CalculiX (`tools/fe_reference.sh --contact-radius 0.3`).
//!
//! The point-to-surface method runs on the validation scene (sphere on a rigid plane). The
//! short-range method needs particles on both sides and cannot push against a rigid plane,
//! so both methods also run on the sphere pressed on a deformable block
//! ([`sphere_on_block_case`]), compared with Hertz for two bodies: those points compare the
//! methods with each other, not with the rigid-plane scene.
//!
//! Each run is one row of `sweep.json`; `speed_accuracy.svg` draws MRE against wall time on
//! log axes, one series per scene, method and solver, with the Pareto front of the PD runs
//! and the CalculiX points of docs/FE_REFERENCE.md.

use std::path::Path;
use std::time::Instant;

use plotters::prelude::*;
use serde::Serialize;

use crate::error::{Error, Result};
use crate::output::chart::{legend, write_svg};
use crate::output::vtk::write_atomically;
use crate::studies::comparison::run_case;
use crate::studies::scenarios::{
    sphere_cap_case, sphere_on_block_case, ValidationCase, ADR_SOLVER, STIFF_PENALTY,
    STUDY_CONTACT_RADIUS, STUDY_DAMPING, STUDY_END_TIME,
};

/// CalculiX's figures for the Hertz sphere at a/R = 0.3 (the sweep's sphere), as measured by
/// `tools/fe_reference.sh --contact-radius 0.3 --quick` and tabulated in
/// docs/SPEED_ACCURACY.md: label, MRE, case wall time in seconds. The chart draws these
/// unless `sweep --fe FILE` gives the JSON of a CalculiX run made on the same machine.
pub const FE_POINTS: [(&str, f64, f64); 4] = [
    ("CAX8 a/10", 0.00391, 2.2),
    ("CAX8 a/20", 0.00361, 4.0),
    ("C3D10 a/5", 0.00456, 6.7),
    ("C3D10 a/10", 0.00369, 17.8),
];

/// One CalculiX case on the chart.
#[derive(Clone, Debug, PartialEq)]
pub struct FePoint {
    /// "CAX8 a/10" and the like.
    pub label: String,
    pub mre: f64,
    pub wall_seconds: f64,
}

/// [`FE_POINTS`] as chart points.
pub fn stored_fe_points() -> Vec<FePoint> {
    FE_POINTS
        .iter()
        .map(|&(label, mre, wall_seconds)| FePoint {
            label: label.into(),
            mre,
            wall_seconds,
        })
        .collect()
}

/// The cases of `tools/fe_reference.sh --json PATH` (a list of objects with `model`,
/// `h_over_a`, `mre` and `wall_seconds`), as chart points; an error names the file and the
/// record that cannot be read.
pub fn read_fe_points(path: &Path) -> Result<Vec<FePoint>> {
    let fail = |what: String| Error::input(format!("{}: {what}", path.display()));
    let text = std::fs::read_to_string(path).map_err(|e| fail(format!("cannot read: {e}")))?;
    let value: serde_json::Value = serde_json::from_str(&text).map_err(|e| {
        fail(format!(
            "line {}, column {}: not JSON ({e}); expected what tools/fe_reference.sh --json writes",
            e.line(),
            e.column()
        ))
    })?;
    let cases = value.as_array().ok_or_else(|| {
        fail("expected a list of CalculiX cases (tools/fe_reference.sh --json), found another JSON value".into())
    })?;
    cases
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let number = |key: &str| {
                c[key].as_f64().filter(|v| v.is_finite()).ok_or_else(|| {
                    fail(format!(
                        "case {} has no number \"{key}\" (found {})",
                        k + 1,
                        c[key]
                    ))
                })
            };
            let model = c["model"].as_str().ok_or_else(|| {
                fail(format!(
                    "case {} has no string \"model\" (found {})",
                    k + 1,
                    c["model"]
                ))
            })?;
            let h = number("h_over_a")?;
            let element = model.split('-').next().unwrap_or(model).to_uppercase();
            Ok(FePoint {
                label: format!("{element} a/{:.0}", 1.0 / h),
                mre: number("mre")?,
                wall_seconds: number("wall_seconds")?,
            })
        })
        .collect()
}

/// One run of the sweep.
#[derive(Clone, Debug, Serialize)]
pub struct SweepRun {
    /// "point-to-surface" or "short-range".
    pub method: String,
    /// "adr", "static" or "explicit".
    pub solver: String,
    /// "rigid plane" or "deformable block".
    pub scene: String,
    pub spacing: f64,
    /// a/Δ.
    pub a_over_spacing: f64,
    pub horizon_factor: f64,
    pub particles: usize,
    pub mre: f64,
    pub radius_error: f64,
    pub force_balance_error: f64,
    pub wall_seconds: f64,
    pub iterations: usize,
    /// Why the run failed (the other figures are then zero).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
}

/// A point of the grid before it runs.
pub struct SweepPoint {
    pub method: &'static str,
    pub solver: &'static str,
    pub scene: &'static str,
    pub case: ValidationCase,
}

/// The default grid: a/Δ = 2.5, 3.75, 5, 7.5 and 10 (Δ = 0.12, 0.08, 0.06, 0.04, 0.03 m),
/// m = 3 and √10 (m = 3 alone at Δ = 0.03 m); ADR and the static solver with the stiff
/// penalty of the "hertz" validation set (R = 100 m) and, at the two coarsest spacings,
/// damped explicit dynamics with the paper's penalty R = Δ/2 (as in `validate --study
/// timestep`: the stiff penalty would need a step too small for a grid of minutes). The
/// point-to-surface method runs on the rigid plane, and up to Δ = 0.06 m on the deformable
/// block (two passes, ADR and static) beside the short-range method (ADR and explicit, its
/// explicit runs simulating 0.06 s).
pub fn sphere_grid() -> Vec<SweepPoint> {
    let a = STUDY_CONTACT_RADIUS;
    let explicit =
        format!("kind = \"explicit\"\ndamping = {STUDY_DAMPING}\nend_time = {STUDY_END_TIME}");
    let static_solver = ADR_SOLVER.replace("\"adr\"", "\"static\"");
    let mut out = Vec::new();
    for dx in [0.12, 0.08, 0.06, 0.04, 0.03] {
        for (mname, m) in [("3", 3.0), ("sqrt10", 10f64.sqrt())] {
            // a/Δ = 10 with m = 3 only: the finest point of the front (about 46,000
            // particles), where m = 3 has been the more accurate horizon at every Δ.
            if dx < 0.035 && mname != "3" {
                continue;
            }
            for (solver, block, penalty) in [
                ("adr", ADR_SOLVER, STIFF_PENALTY),
                ("static", static_solver.as_str(), STIFF_PENALTY),
                ("explicit", explicit.as_str(), ""),
            ] {
                if solver == "explicit" && dx < 0.07 {
                    continue;
                }
                let tag = format!("{solver}-dx{dx}-m{mname}");
                out.push(SweepPoint {
                    method: "point-to-surface",
                    solver,
                    scene: "rigid plane",
                    case: sphere_cap_case(a, dx, m, block, penalty, &format!("p2s-plane-{tag}")),
                });
                if dx < 0.05 {
                    continue;
                }
                if solver != "explicit" {
                    // Both methods on one scene: the point-to-surface method between the two
                    // deformable bodies, both ways (as between bodies of equal spacing).
                    out.push(SweepPoint {
                        method: "point-to-surface",
                        solver,
                        scene: "deformable block",
                        case: sphere_on_block_case(
                            a,
                            dx,
                            m,
                            block,
                            &format!("{penalty}\ntwo_pass = true"),
                            0.0,
                            &format!("p2s-block-{tag}"),
                        ),
                    });
                }
                // The short-range method has no tangent in the static solver.
                if solver == "static" {
                    continue;
                }
                // The block's slowest mode is slower than the sector's: three times the
                // simulated time before the block runs settle (at 0.02 s the contact force
                // was still 6-13 % short of the load).
                let block = if solver == "explicit" {
                    block.replace(
                        &format!("end_time = {STUDY_END_TIME}"),
                        &format!("end_time = {}", 3.0 * STUDY_END_TIME),
                    )
                } else {
                    block.to_string()
                };
                out.push(SweepPoint {
                    method: "short-range",
                    solver,
                    scene: "deformable block",
                    case: sphere_on_block_case(
                        a,
                        dx,
                        m,
                        &block,
                        "method = \"short-range\"",
                        crate::contact::shortrange::DISTANCE * dx,
                        &format!("short-range-block-{tag}"),
                    ),
                });
            }
        }
    }
    out
}

/// Runs the points into `folder`, then writes `sweep.json` and `speed_accuracy.svg`.
/// `fe`: the CalculiX points the chart draws beside the runs.
pub fn run_sweep(
    points: Vec<SweepPoint>,
    folder: &Path,
    quiet: bool,
    fe: &[FePoint],
) -> Result<Vec<SweepRun>> {
    std::fs::create_dir_all(folder).map_err(|e| Error::output(folder, e))?;
    let total = points.len();
    let mut runs = Vec::new();
    for (k, p) in points.into_iter().enumerate() {
        if !quiet {
            eprintln!(
                "sweep {}/{total}: {} {} on the {}, Δ = {} m, m = {:.3} ...",
                k + 1,
                p.method,
                p.solver,
                p.scene,
                p.case.spacing,
                p.case.horizon_factor
            );
        }
        let start = Instant::now();
        let mut run = SweepRun {
            method: p.method.into(),
            solver: p.solver.into(),
            scene: p.scene.into(),
            spacing: p.case.spacing,
            a_over_spacing: STUDY_CONTACT_RADIUS / p.case.spacing,
            horizon_factor: p.case.horizon_factor,
            particles: 0,
            mre: 0.0,
            radius_error: 0.0,
            force_balance_error: 0.0,
            wall_seconds: 0.0,
            iterations: 0,
            error: None,
        };
        match run_case(&p.case, folder, true) {
            Ok(rows) => {
                let r = &rows[0];
                run.particles = r.particles;
                run.mre = r.mre;
                run.radius_error = r.radius_error;
                run.force_balance_error = r.force_balance_error;
                run.wall_seconds = r.wall_seconds;
                run.iterations = r.iterations;
            }
            Err(e) => {
                run.wall_seconds = start.elapsed().as_secs_f64();
                run.error = Some(e.to_string());
            }
        }
        runs.push(run);
    }
    let json = serde_json::to_string_pretty(&runs).map_err(|e| Error::output(folder, e))?;
    let path = folder.join("sweep.json");
    write_atomically(&path, |w| std::io::Write::write_all(w, json.as_bytes()))?;
    write_chart(&folder.join("speed_accuracy.svg"), &runs, fe)?;
    Ok(runs)
}

/// The runs on the rigid plane (the problem the FE points solve) that no other such run
/// beats in both wall time and MRE, fastest first. The block's runs are measured against
/// Hertz for two bodies, another problem.
pub fn pareto_front(runs: &[SweepRun]) -> Vec<&SweepRun> {
    let mut ok: Vec<&SweepRun> = runs
        .iter()
        .filter(|r| r.error.is_none() && r.scene == "rigid plane")
        .collect();
    ok.sort_by(|a, b| a.wall_seconds.total_cmp(&b.wall_seconds));
    let mut front = Vec::new();
    let mut best = f64::INFINITY;
    for r in ok {
        if r.mre < best {
            best = r.mre;
            front.push(r);
        }
    }
    front
}

/// The table of the runs (Markdown).
pub fn table(runs: &[SweepRun]) -> String {
    let mut s = String::from(
        "| scene | method | solver | Δ (m) | a/Δ | m | particles | MRE | radius error | force balance | iterations | wall s |\n|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in runs {
        match &r.error {
            None => s.push_str(&format!(
                "| {} | {} | {} | {} | {:.2} | {:.3} | {} | {:.2} % | {:+.2} % | {:.1e} | {} | {:.1} |\n",
                r.scene,
                r.method,
                r.solver,
                r.spacing,
                r.a_over_spacing,
                r.horizon_factor,
                r.particles,
                100.0 * r.mre,
                100.0 * r.radius_error,
                r.force_balance_error,
                r.iterations,
                r.wall_seconds
            )),
            Some(e) => s.push_str(&format!(
                "| {} | {} | {} | {} | {:.2} | {:.3} | failed: {} | | | | | {:.1} |\n",
                r.scene,
                r.method,
                r.solver,
                r.spacing,
                r.a_over_spacing,
                r.horizon_factor,
                e.replace('|', "/"),
                r.wall_seconds
            )),
        }
    }
    s
}

fn series_name(r: &SweepRun) -> String {
    format!("{}, {}, {}", r.method, r.solver, r.scene)
}

/// MRE (%) against wall time (s), log axes.
fn write_chart(path: &Path, runs: &[SweepRun], fe: &[FePoint]) -> Result<()> {
    let ok: Vec<&SweepRun> = runs
        .iter()
        .filter(|r| r.error.is_none() && r.mre > 0.0)
        .collect();
    let mut xs: Vec<f64> = ok.iter().map(|r| r.wall_seconds.max(1e-2)).collect();
    let mut ys: Vec<f64> = ok.iter().map(|r| 100.0 * r.mre).collect();
    xs.extend(fe.iter().map(|p| p.wall_seconds));
    ys.extend(fe.iter().map(|p| 100.0 * p.mre));
    let (xmin, xmax) = bounds(&xs);
    let (ymin, ymax) = bounds(&ys);
    write_svg(path, (960, 640), |root, draw| {
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!("Hertz sphere, a/R = {STUDY_CONTACT_RADIUS}: MRE against wall time"),
                ("sans-serif", 18),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d((xmin..xmax).log_scale(), (ymin..ymax).log_scale())
            .map_err(|e| draw(&e))?;
        chart
            .configure_mesh()
            .x_desc("wall time (s), 2 cores")
            .y_desc("MRE (%)")
            .draw()
            .map_err(|e| draw(&e))?;
        let front_runs = pareto_front(runs);
        let on_front = |r: &SweepRun| front_runs.iter().any(|f| std::ptr::eq(*f, r));
        let mut names: Vec<String> = ok.iter().map(|r| series_name(r)).collect();
        names.sort();
        names.dedup();
        let colours = [
            RED,
            BLUE,
            GREEN,
            MAGENTA,
            CYAN,
            BLACK,
            RGBColor(128, 0, 160),
            RGBColor(140, 90, 40),
        ];
        for (k, name) in names.iter().enumerate() {
            let c = colours[k % colours.len()];
            let pts: Vec<&&SweepRun> = ok.iter().filter(|r| &series_name(r) == name).collect();
            chart
                .draw_series(pts.iter().map(|r| {
                    let at = (r.wall_seconds.max(1e-2), 100.0 * r.mre);
                    // Only the front's points are named: the others would print over each
                    // other (the table names every run).
                    let label = if on_front(r) {
                        format!("Δ{} m{:.2}", r.spacing, r.horizon_factor)
                    } else {
                        String::new()
                    };
                    EmptyElement::at(at)
                        + Circle::new((0, 0), 4, c.filled())
                        + Text::new(label, (5, -10), ("sans-serif", 10).into_font())
                }))
                .map_err(|e| draw(&e))?
                .label(name.clone())
                .legend(move |(x, y)| Circle::new((x, y), 4, c.filled()));
        }
        let orange = RGBColor(230, 120, 0);
        chart
            .draw_series(fe.iter().map(|p| {
                EmptyElement::at((p.wall_seconds, 100.0 * p.mre))
                    + TriangleMarker::new((0, 0), 6, orange.filled())
                    + Text::new(p.label.clone(), (6, 4), ("sans-serif", 10).into_font())
            }))
            .map_err(|e| draw(&e))?
            .label("CalculiX FE, same sphere and a/R")
            .legend(move |(x, y)| TriangleMarker::new((x, y), 6, orange.filled()));
        let front: Vec<(f64, f64)> = front_runs
            .iter()
            .map(|r| (r.wall_seconds.max(1e-2), 100.0 * r.mre))
            .collect();
        chart
            .draw_series(LineSeries::new(front, BLACK.stroke_width(2)))
            .map_err(|e| draw(&e))?
            .label("Pareto front of the PD runs on the rigid plane")
            .legend(|(x, y)| PathElement::new(vec![(x - 8, y), (x + 8, y)], BLACK));
        legend(&mut chart)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(|e| draw(&e))?;
        Ok(())
    })
}

/// A log axis range around the values.
fn bounds(v: &[f64]) -> (f64, f64) {
    let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !(lo.is_finite() && hi.is_finite()) {
        return (0.1, 10.0);
    }
    (lo / 1.5, hi * 1.5)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(t: f64, mre: f64) -> SweepRun {
        SweepRun {
            method: "point-to-surface".into(),
            solver: "adr".into(),
            scene: "rigid plane".into(),
            spacing: 0.1,
            a_over_spacing: 3.0,
            horizon_factor: 3.0,
            particles: 1,
            mre,
            radius_error: 0.0,
            force_balance_error: 0.0,
            wall_seconds: t,
            iterations: 1,
            error: None,
        }
    }

    #[test]
    fn pareto_front_keeps_the_unbeaten_runs() {
        let mut failed = run(0.1, 0.001);
        failed.error = Some("blew up".into());
        // Another problem (Hertz for two bodies): not on the rigid plane's front.
        let mut block = run(0.2, 0.001);
        block.scene = "deformable block".into();
        let runs = vec![
            block,
            run(1.0, 0.05),
            run(2.0, 0.06),
            run(3.0, 0.02),
            failed,
            run(0.5, 0.08),
            run(9.0, 0.02),
        ];
        let front: Vec<(f64, f64)> = pareto_front(&runs)
            .iter()
            .map(|r| (r.wall_seconds, r.mre))
            .collect();
        assert_eq!(front, vec![(0.5, 0.08), (1.0, 0.05), (3.0, 0.02)]);
    }

    #[test]
    fn fe_points_come_from_the_reference_json_or_a_named_error() {
        let dir = std::env::temp_dir().join(format!("pdcontact-sweep-fe-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let good = dir.join("fe.json");
        std::fs::write(
            &good,
            r#"[{"model": "cax8-axisymmetric", "h_over_a": 0.1, "nodes": 1372, "mre": 0.00391,
                 "radius_error": -0.00998, "force_balance_error": 8.2e-5, "wall_seconds": 2.2},
                {"model": "c3d10-quarter", "h_over_a": 0.2, "nodes": 6811, "mre": 0.00456,
                 "radius_error": -0.00112, "force_balance_error": 5.4e-7, "wall_seconds": 6.7}]"#,
        )
        .unwrap();
        let points = read_fe_points(&good).unwrap();
        assert_eq!(points.len(), 2);
        assert_eq!(points[0].label, "CAX8 a/10");
        assert_eq!(points[1].label, "C3D10 a/5");
        assert_eq!((points[1].mre, points[1].wall_seconds), (0.00456, 6.7));
        let bad = dir.join("bad.json");
        std::fs::write(
            &bad,
            r#"[{"model": "cax8-axisymmetric", "h_over_a": 0.1, "mre": "x"}]"#,
        )
        .unwrap();
        let e = read_fe_points(&bad).unwrap_err().to_string();
        assert!(
            e.contains("bad.json") && e.contains("case 1") && e.contains("\"mre\""),
            "{e}"
        );
        std::fs::write(&bad, "{\n  \"model\": ").unwrap();
        let e = read_fe_points(&bad).unwrap_err().to_string();
        assert!(e.contains("bad.json") && e.contains("line 2"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
