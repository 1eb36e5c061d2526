//! `pdcontact validate`: the reference problems of the paper's Sec. 3, against theory
//! (METHOD.md §7).
//!
//! The scenes are in [`scenarios`](super::scenarios) (the two sets, hertz and paper), the
//! runs compared with theory in [`comparison`](super::comparison); this module selects and
//! runs them, prints the table, and runs the convergence studies.
//!
//! Every run writes its scene, frames, `summary.json` and a chart of `p/p0` against `r/a`.

use std::path::Path;

use plotters::prelude::*;

use crate::error::{Error, Result};
use crate::output::chart::{legend, write_svg};
use crate::output::vtk::write_atomically;
use crate::studies::comparison::{run_case, ValidationRow};
use crate::studies::scenarios::*;

/// The table `validate` prints.
pub fn table(rows: &[ValidationRow]) -> String {
    table_columns(rows, false)
}

/// The table with a column for the peak pressure against the theory's `p0` (`validate
/// --mesh`; "–" where a row has none).
pub fn table_with_peak(rows: &[ValidationRow]) -> String {
    table_columns(rows, true)
}

fn table_columns(rows: &[ValidationRow], peak: bool) -> String {
    let mut s = format!(
        "{:<7} {:<6} {:<12} {:>8} {:>5} {:>9} {:>8} {:>9}",
        "case", "set", "theory", "Δ (m)", "m", "particles", "MRE", "radius"
    );
    if peak {
        s.push_str(&format!(" {:>9} {:>9}", "peak", "shear"));
    }
    s.push_str(&format!(
        " {:>9} {:>10} {:>8}\n",
        "balance", "iters", "seconds"
    ));
    for r in rows {
        s.push_str(&format!(
            "{:<7} {:<6} {:<12} {:>8.4} {:>5.3} {:>9} {:>7.2}% {:>+8.2}%",
            r.case,
            r.set,
            r.variant,
            r.spacing,
            r.horizon_factor,
            r.particles,
            100.0 * r.mre,
            100.0 * r.radius_error,
        ));
        if peak {
            match r.peak_error {
                Some(e) => s.push_str(&format!(" {:>+8.2}%", 100.0 * e)),
                None => s.push_str(&format!(" {:>9}", "–")),
            }
            match &r.subsurface_shear {
                Some(t) => s.push_str(&format!(" {:>+8.2}%", 100.0 * t.error)),
                None => s.push_str(&format!(" {:>9}", "–")),
            }
        }
        // Newton's iterations, and ADR's where Newton stalled.
        let iters = match r.relaxation_iterations {
            0 => r.iterations.to_string(),
            n => format!("{}+{n}", r.iterations),
        };
        s.push_str(&format!(
            " {:>9.1e} {:>10} {:>8.1}\n",
            r.force_balance_error, iters, r.wall_seconds
        ));
    }
    s
}

/// Runs the problems of the sets into `folder`, and returns the rows.
pub fn run_selection(
    problems: &[Problem],
    sets: &[Set],
    skin_correction: bool,
    static_solver: bool,
    folder: &Path,
    quiet: bool,
) -> Result<Selection> {
    std::fs::create_dir_all(folder).map_err(|e| Error::output(folder, e))?;
    // The paper sphere runs on the stored gmsh mesh, written next to its run.
    let mesh = folder.join(SPHERE_MESH_NAME);
    write_atomically(&mesh, |w| std::io::Write::write_all(w, SPHERE_MESH))?;
    let mesh = std::fs::canonicalize(&mesh).unwrap_or(mesh);
    let mut rows = Vec::new();
    let mut failures = Vec::new();
    for c in cases(problems, sets, &mesh) {
        let c = if skin_correction {
            c
        } else {
            c.without_skin_correction()
        };
        let c = if static_solver {
            c.with_static_solver()
        } else {
            c
        };
        if !quiet {
            eprintln!(
                "{} ({} set): Δ = {:.4} m, m = {} ...",
                c.problem.name(),
                c.set.name(),
                c.spacing,
                c.horizon_factor
            );
        }
        // A case that fails is reported and the others still run.
        match run_case(&c, folder, quiet) {
            Ok(r) => rows.extend(r),
            Err(e) => failures.push(format!("{} ({} set): {e}", c.problem.name(), c.set.name())),
        }
    }
    Ok(Selection { rows, failures })
}

/// What `validate` ran: the rows of the cases that finished, and the errors of those that did
/// not.
#[derive(Debug)]
pub struct Selection {
    pub rows: Vec<ValidationRow>,
    pub failures: Vec<String>,
}

/// The convergence studies of the paper's Sec. 3.2, on the Hertz sphere.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Study {
    /// Δ = 0.12, 0.08, 0.06, 0.04 m at m = 3.
    Spacing,
    /// m = √8, 3, √10, √13 at Δ = 0.04 m.
    Horizon,
    /// Explicit dynamics at dt = 1e-5, 5e-6, 1e-6 s, Δ = 0.08 m, m = 3.
    Timestep,
}

impl Study {
    pub fn name(self) -> &'static str {
        match self {
            Study::Spacing => "spacing",
            Study::Horizon => "horizon",
            Study::Timestep => "timestep",
        }
    }

    /// The axis of the study's chart.
    fn axis(self) -> &'static str {
        match self {
            Study::Spacing => "Δ (m)",
            Study::Horizon => "m = δ/Δ",
            Study::Timestep => "dt (µs)",
        }
    }
}

/// Spacing of the horizon study at fixed Δ (the paper's reading), and the horizon of its
/// fixed-δ series (m-convergence: δ = 3 × 0.04 m held, Δ = δ/m).
const HORIZON_STUDY_SPACING: f64 = 0.04;

/// The horizon factors of the paper's study: its 7th to 10th nearest-neighbour shells.
const HORIZON_FACTORS: [(&str, f64); 4] = [("√8", 8.0), ("3", 9.0), ("√10", 10.0), ("√13", 13.0)];

/// One point of a study: its label, its x on the chart, the chart series it belongs to, and
/// the case.
pub struct StudyPoint {
    pub label: String,
    pub x: f64,
    pub series: &'static str,
    pub case: ValidationCase,
}

/// The study's points. The horizon study has two series: m varied at fixed Δ, as the paper
/// varies it (δ = mΔ grows with m), and m varied at fixed δ (Δ = δ/m shrinks with m), the
/// m-convergence of the peridynamics literature, whose limit is the model at that δ.
pub fn study_cases(study: Study) -> Vec<StudyPoint> {
    let a = STUDY_CONTACT_RADIUS;
    match study {
        Study::Spacing => [0.12, 0.08, 0.06, 0.04]
            .into_iter()
            .map(|dx| StudyPoint {
                label: format!("Δ = {dx} m"),
                x: dx,
                series: "m = 3",
                case: sphere_cap_case(
                    a,
                    dx,
                    3.0,
                    ADR_SOLVER,
                    STIFF_PENALTY,
                    &format!("study-spacing-{dx}"),
                ),
            })
            .collect(),
        Study::Horizon => {
            let dx = HORIZON_STUDY_SPACING;
            let delta = 3.0 * dx;
            let fixed_spacing = HORIZON_FACTORS.iter().map(|&(name, m2)| {
                let m = f64::sqrt(m2);
                StudyPoint {
                    label: format!("m = {name}, Δ = {dx} m"),
                    x: m,
                    series: "fixed Δ = 0.04 m (δ = mΔ)",
                    case: sphere_cap_case(
                        a,
                        dx,
                        m,
                        ADR_SOLVER,
                        STIFF_PENALTY,
                        &format!("study-horizon-{m:.3}"),
                    ),
                }
            });
            let fixed_horizon = HORIZON_FACTORS.iter().map(|&(name, m2)| {
                let m = f64::sqrt(m2);
                let spacing = delta / m;
                StudyPoint {
                    label: format!("m = {name}, δ = {delta} m"),
                    x: m,
                    series: "fixed δ = 0.12 m (Δ = δ/m)",
                    case: sphere_cap_case(
                        a,
                        spacing,
                        m,
                        ADR_SOLVER,
                        STIFF_PENALTY,
                        &format!("study-horizon-fixed-delta-{m:.3}"),
                    ),
                }
            });
            fixed_spacing.chain(fixed_horizon).collect()
        }
        Study::Timestep => [1e-5, 5e-6, 1e-6]
            .into_iter()
            .map(|dt: f64| {
                let solver = format!(
                    "kind = \"explicit\"\ndt = {dt:e}\ndamping = {STUDY_DAMPING}\nend_time = {STUDY_END_TIME}"
                );
                StudyPoint {
                    label: format!("dt = {dt:e} s"),
                    x: dt * 1e6,
                    series: "Δ = 0.08 m, m = 3",
                    // The paper's penalty (R = Δ/2): the stiff one would need dt < 1e-6 s.
                    case: sphere_cap_case(
                        a,
                        0.08,
                        3.0,
                        &solver,
                        "",
                        &format!("study-timestep-{dt:e}"),
                    ),
                }
            })
            .collect(),
    }
}

/// Runs a study into `folder`: one subfolder per point, the rows, the failures, and the chart
/// `study-<name>.svg` of MRE against the study's parameter.
pub fn run_study(study: Study, folder: &Path, quiet: bool) -> Result<Selection> {
    std::fs::create_dir_all(folder).map_err(|e| Error::output(folder, e))?;
    let mut rows = Vec::new();
    let mut failures = Vec::new();
    let mut points: Vec<(&str, f64, f64)> = Vec::new();
    for point in study_cases(study) {
        let name = &point.label;
        if !quiet {
            eprintln!("{} study: {name} ...", study.name());
        }
        match run_case(&point.case, folder, quiet) {
            Ok(r) => {
                for mut row in r {
                    points.push((point.series, point.x, 100.0 * row.mre));
                    row.variant = name.clone();
                    rows.push(row);
                }
            }
            Err(e) => failures.push(format!("{} study, {name}: {e}", study.name())),
        }
    }
    let chart = folder.join(format!("study-{}.svg", study.name()));
    write_study_chart(&chart, study, &points)?;
    Ok(Selection { rows, failures })
}

/// MRE (%) against the study's parameter, one line per series.
fn write_study_chart(path: &Path, study: Study, points: &[(&str, f64, f64)]) -> Result<()> {
    write_svg(path, (720, 480), |root, draw| {
        let xmax = points.iter().map(|p| p.1).fold(0.0, f64::max) * 1.15 + 1e-12;
        let xmin = points.iter().map(|p| p.1).fold(xmax, f64::min) * 0.85;
        let ymax = points.iter().map(|p| p.2).fold(0.0, f64::max) * 1.2 + 1.0;
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!(
                    "Hertz sphere, a/R = {STUDY_CONTACT_RADIUS}: MRE against {}",
                    study.name()
                ),
                ("sans-serif", 18),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(xmin..xmax, 0.0..ymax)
            .map_err(|e| draw(&e))?;
        chart
            .configure_mesh()
            .x_desc(study.axis())
            .y_desc("MRE (%)")
            .draw()
            .map_err(|e| draw(&e))?;
        let mut names: Vec<&str> = points.iter().map(|p| p.0).collect();
        names.dedup();
        let colours = [RED, BLUE, GREEN, MAGENTA];
        for (k, name) in names.iter().enumerate() {
            let colour = colours[k % colours.len()];
            let mut sorted: Vec<(f64, f64)> = points
                .iter()
                .filter(|p| p.0 == *name)
                .map(|p| (p.1, p.2))
                .collect();
            sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
            chart
                .draw_series(LineSeries::new(sorted.clone(), colour.stroke_width(1)))
                .map_err(|e| draw(&e))?
                .label(*name)
                .legend(move |(x, y)| Circle::new((x + 10, y), 4, colour.filled()));
            chart
                .draw_series(
                    sorted
                        .iter()
                        .map(|&(x, y)| Circle::new((x, y), 4, colour.filled())),
                )
                .map_err(|e| draw(&e))?;
        }
        if names.len() > 1 {
            legend(&mut chart).draw().map_err(|e| draw(&e))?;
        }
        Ok(())
    })
}
