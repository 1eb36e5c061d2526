//! A validation scene run and compared with its theory (METHOD.md §7): the table's row per
//! reference variant (MRE, radius error, force balance) and the chart of `p/p0` against `r/a`.

use std::path::{Path, PathBuf};
use std::time::Instant;

use plotters::prelude::*;
use serde::Serialize;

use crate::error::{Error, Result};
use crate::math::Vec3;
use crate::output::analysis::{
    contact_patch, elliptic_accuracy, hertz_cylinder, hertz_sphere, punch_accuracy, Accuracy,
    ContactPatch,
};
use crate::output::chart::{legend, write_svg};
use crate::output::subsurface::{subsurface_shear, SubsurfaceShear};
use crate::output::vtk::write_atomically;
use crate::run::{run_scene, RunOptions};
use crate::scene::Scene;
use crate::studies::scenarios::{Problem, Reference, ValidationCase};

/// One line of the table (a run compared with one variant of its reference).
#[derive(Clone, Debug, Serialize)]
pub struct ValidationRow {
    pub case: String,
    pub set: String,
    /// Which `E*` the theory used ("rigid plane", "paper"), or the study point.
    pub variant: String,
    pub spacing: f64,
    pub horizon_factor: f64,
    pub particles: usize,
    pub mre: f64,
    pub radius_error: f64,
    pub force_balance_error: f64,
    pub iterations: usize,
    /// The static solver: ADR iterations taken where Newton stalled, after `iterations`
    /// (0 for ADR's own runs).
    pub relaxation_iterations: usize,
    pub wall_seconds: f64,
    pub output_pvd: PathBuf,
    pub theory_radius: f64,
    pub theory_peak_pressure: f64,
    pub fitted_radius: f64,
    /// `p0` of the least-squares fit of the reference profile (Hertz rows).
    pub fitted_peak_pressure: f64,
    pub peak_pressure: f64,
    pub samples: usize,
    /// Peak pressure against the theory's `p0`, relative (Hertz rows; none for the punch,
    /// whose theory is singular at the edges).
    pub peak_error: Option<f64>,
    /// The largest shear stress below the contact against Hertz's (sphere rows of a body
    /// pressed by a rigid partner, [`subsurface_shear`]).
    pub subsurface_shear: Option<SubsurfaceShear>,
    pub chart: PathBuf,
}

/// Runs one case into `folder/<problem>-<label>/` and compares it with its reference.
pub fn run_case(case: &ValidationCase, folder: &Path, quiet: bool) -> Result<Vec<ValidationRow>> {
    let dir = folder.join(format!("{}-{}", case.problem.name(), case.label));
    std::fs::create_dir_all(&dir).map_err(|e| Error::output(&dir, e))?;
    let scene_path = dir.join("scene.toml");
    write_atomically(&scene_path, |w| {
        std::io::Write::write_all(w, case.scene.as_bytes())
    })?;
    let scene = Scene::load(&scene_path)?;
    let start = Instant::now();
    let (model, summary) = run_scene(
        &scene,
        &RunOptions {
            output: Some(dir.clone()),
            quiet,
            stop: None,
            comm: None,
            study: true,
        },
    )?;
    let wall = start.elapsed().as_secs_f64();
    let strip = match &case.reference {
        Reference::Sphere { .. } | Reference::SpherePair { .. } => None,
        Reference::Roller { axis, .. } => Some(*axis),
        Reference::Punch { .. } => Some(Vec3::y()),
    };
    let patch = contact_patch(&model, 0, strip)
        .ok_or_else(|| Error::numerical(format!("{}: no contact formed", dir.display())))?;
    let mut rows = Vec::new();
    let mut charted: Vec<(String, f64, f64, Accuracy)> = Vec::new();
    // The stress below a sphere's contact: Hertz's on its axis needs the partner's E* in
    // the row, so only against a rigid partner (every other row is a rigid plane's).
    let below = |a: f64, p0: f64| match &case.reference {
        Reference::Sphere { .. } => model.bodies[0]
            .as_pd()
            .and_then(|pd| subsurface_shear(pd, &patch, a, p0)),
        _ => None,
    };
    // (label, a, p0, accuracy, peak pressure) per row.
    let variants: Vec<(String, f64, f64, Accuracy, f64)> = match &case.reference {
        Reference::Sphere {
            load,
            radius,
            e_stars,
        } => e_stars
            .iter()
            .map(|(label, e)| {
                let (a, p0) = hertz_sphere(*load, *radius, *e);
                (
                    label.clone(),
                    a,
                    p0,
                    elliptic_accuracy(&patch, a, p0),
                    patch.peak,
                )
            })
            .collect(),
        Reference::SpherePair {
            load,
            r_star,
            e_star,
        } => {
            let (a, p0) = hertz_sphere(*load, *r_star, *e_star);
            (0..model.bodies.len())
                .filter_map(|k| {
                    let p = contact_patch(&model, k, None)?;
                    let name = model.bodies[k].name().to_string();
                    Some((name, a, p0, elliptic_accuracy(&p, a, p0), p.peak))
                })
                .collect()
        }
        Reference::Roller {
            load_per_length,
            radius,
            e_stars,
            ..
        } => e_stars
            .iter()
            .map(|(label, e)| {
                let (a, p0) = hertz_cylinder(*load_per_length, *radius, *e);
                (
                    label.clone(),
                    a,
                    p0,
                    elliptic_accuracy(&patch, a, p0),
                    patch.peak,
                )
            })
            .collect(),
        Reference::Punch {
            load_per_length,
            half_width,
        } => {
            let p0 = load_per_length / (std::f64::consts::PI * half_width);
            vec![(
                "Sadowsky".to_string(),
                *half_width,
                p0,
                punch_accuracy(&patch, *half_width, *load_per_length),
                patch.peak,
            )]
        }
    };
    let chart = dir.join("pressure.svg");
    for (label, a, p0, acc, peak) in &variants {
        rows.push(ValidationRow {
            case: case.problem.name().into(),
            set: case.set.name().into(),
            variant: label.clone(),
            spacing: case.spacing,
            horizon_factor: case.horizon_factor,
            particles: summary.particles,
            mre: acc.mre,
            radius_error: acc.radius_error,
            force_balance_error: summary.force_balance_error,
            iterations: summary.iterations,
            relaxation_iterations: summary.solver.relaxation_iterations,
            wall_seconds: wall,
            output_pvd: summary.outputs.pvd.clone(),
            theory_radius: *a,
            theory_peak_pressure: *p0,
            fitted_radius: acc.fitted_radius,
            fitted_peak_pressure: acc.fitted_peak,
            peak_pressure: *peak,
            samples: acc.samples,
            peak_error: match case.problem {
                Problem::Punch => None,
                _ => Some(peak / p0 - 1.0),
            },
            subsurface_shear: if label == "rigid plane" {
                below(*a, *p0)
            } else {
                None
            },
            chart: chart.clone(),
        });
        charted.push((label.clone(), *a, *p0, *acc));
    }
    write_chart(&chart, case, &patch, &charted)?;
    Ok(rows)
}

/// p/p0 against r/a: particles as points, theory as a line (the paper's Figs. 15, 23, 27).
fn write_chart(
    path: &Path,
    case: &ValidationCase,
    patch: &ContactPatch,
    variants: &[(String, f64, f64, Accuracy)],
) -> Result<()> {
    let Some((label, a, p0, acc)) = variants.last() else {
        return Ok(());
    };
    write_svg(path, (720, 480), |root, draw| {
        let ymax = match case.problem {
            Problem::Punch => 3.0,
            _ => 1.3,
        };
        let title = format!(
            "{} ({} set): MRE {:.2} %, Δ = {:.4} m, m = {}",
            case.problem.name(),
            case.set.name(),
            100.0 * acc.mre,
            case.spacing,
            case.horizon_factor
        );
        let mut chart = ChartBuilder::on(root)
            .caption(title, ("sans-serif", 18))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(0.0..1.5f64, 0.0..ymax)
            .map_err(|e| draw(&e))?;
        chart
            .configure_mesh()
            .x_desc(if case.problem == Problem::Sphere {
                "r / a"
            } else {
                "x / a"
            })
            .y_desc("p / p0")
            .draw()
            .map_err(|e| draw(&e))?;
        let theory: Vec<(f64, f64)> = (0..=600)
            .map(|k| {
                let s = 1.5 * k as f64 / 600.0;
                let v = match case.problem {
                    Problem::Punch => {
                        if s < 0.999 {
                            1.0 / (1.0 - s * s).sqrt()
                        } else {
                            f64::NAN
                        }
                    }
                    _ => (1.0 - s * s).max(0.0).sqrt(),
                };
                (s, v)
            })
            .filter(|(_, v)| v.is_finite() && *v <= ymax)
            .collect();
        chart
            .draw_series(LineSeries::new(theory, BLACK.stroke_width(2)))
            .map_err(|e| draw(&e))?
            .label(match case.problem {
                Problem::Punch => "Sadowsky".to_string(),
                _ => format!("Hertz ({label})"),
            })
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(2)));
        chart
            .draw_series(
                patch
                    .points
                    .iter()
                    .filter(|(_, r, _)| r / a <= 1.5)
                    .map(|(_, r, p)| Circle::new((r / a, (p / p0).min(ymax)), 3, RED.filled())),
            )
            .map_err(|e| draw(&e))?
            .label("particles")
            .legend(|(x, y)| Circle::new((x + 10, y), 3, RED.filled()));
        legend(&mut chart).draw().map_err(|e| draw(&e))?;
        Ok(())
    })
}
