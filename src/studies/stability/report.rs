//! The stability maps reported: the Markdown tables `pdcontact sweep --stability` prints and
//! the chart `stability.svg`, one panel per map (docs/STABILITY.md).

use plotters::coord::combinators::BindKeyPoints;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::*;
use crate::output::chart::write_svg;

/// A cell's short text: the outcome, with the MRE of a static run.
fn cell_text(r: &StabilityRun) -> String {
    match (r.outcome.as_str(), r.mre) {
        ("stable and accurate", Some(m)) => format!("accurate {:.1} %", 100.0 * m),
        ("stable but inaccurate", Some(m)) => format!("inaccurate {:.1} %", 100.0 * m),
        ("missed contacts", _) => "missed".into(),
        (o, _) => o.into(),
    }
}

fn value_text(v: Value) -> String {
    match v {
        Value::Multiple(m) => format!("{m}"),
        Value::Loading(Loading::Static) => "static".into(),
        Value::Loading(Loading::Impact(s)) => format!("{s}"),
    }
}

/// The maps as Markdown tables (rows: the map's vertical axis, largest first).
pub fn table(runs: &[StabilityRun]) -> String {
    let mut s = String::new();
    for map in MAPS {
        let xs = map.x.values();
        let mut ys = map.y.values();
        ys.reverse();
        s.push_str(&format!(
            "\n{}\n\n| {} \\ {} |",
            map.title(),
            map.y.describe(),
            map.x.describe()
        ));
        for &x in &xs {
            s.push_str(&format!(" {} |", value_text(x)));
        }
        s.push_str("\n|---|");
        s.push_str(&"---|".repeat(xs.len()));
        for &y in &ys {
            s.push_str(&format!("\n| {} |", value_text(y)));
            for &x in &xs {
                let p = map.point(x, y);
                let text = runs
                    .iter()
                    .find(|r| r.point() == p)
                    .map_or(String::new(), cell_text);
                s.push_str(&format!(" {text} |"));
            }
        }
        s.push('\n');
    }
    s
}

fn colour(outcome: &str) -> RGBColor {
    match outcome {
        "stable and accurate" => RGBColor(0, 150, 60),
        "stable" => RGBColor(120, 200, 120),
        "stable but inaccurate" => RGBColor(240, 170, 0),
        "missed contacts" => RGBColor(40, 100, 220),
        _ => RGBColor(210, 30, 30),
    }
}

/// The cell edges of an axis's values: halfway between neighbours on a log scale.
fn edges(values: &[f64]) -> Vec<(f64, f64)> {
    let n = values.len();
    (0..n)
        .map(|k| {
            let lo = if k > 0 {
                (values[k - 1] * values[k]).sqrt()
            } else {
                values[0] / (values[1] / values[0]).sqrt()
            };
            let hi = if k + 1 < n {
                (values[k] * values[k + 1]).sqrt()
            } else {
                values[n - 1] * (values[n - 1] / values[n - 2]).sqrt()
            };
            (lo, hi)
        })
        .collect()
}

/// One panel per map: coloured cells on log axes, the MRE of static runs written in, and on
/// the speed maps the speed at which a particle crosses the window 0.5Δ in one step.
pub fn write_chart(path: &Path, runs: &[StabilityRun]) -> Result<()> {
    write_svg(path, (1400, 1180), |root, draw| {
        let (top, bottom) = root.split_vertically(1120);
        let panels = top.split_evenly((2, 2));
        for (panel, map) in panels.iter().zip(MAPS) {
            let xs = map.x.values();
            let ys = map.y.values();
            let xpos: Vec<f64> = xs.iter().map(|&v| map.x.position(v)).collect();
            let ypos: Vec<f64> = ys.iter().map(|&v| map.y.position(v)).collect();
            // The static row is a cell of the same height, apart from the speeds.
            let xe = edges(&xpos);
            let ye = if map.y == Axis::Speed {
                let mut e = vec![(STATIC_ROW / 10f64.powf(0.25), STATIC_ROW * 10f64.powf(0.25))];
                e.extend(edges(&ypos[1..]));
                e
            } else {
                edges(&ypos)
            };
            let (x0, x1) = (xe[0].0, xe[xe.len() - 1].1);
            let (y0, y1) = (ye[0].0, ye[ye.len() - 1].1);
            let mut chart = ChartBuilder::on(panel)
                .caption(map.title(), ("sans-serif", 18))
                .margin(14)
                .x_label_area_size(45)
                .y_label_area_size(70)
                .build_cartesian_2d(
                    (x0..x1).log_scale().with_key_points(xpos.clone()),
                    (y0..y1).log_scale().with_key_points(ypos.clone()),
                )
                .map_err(|e| draw(&e))?;
            let number = |v: &f64| format!("{v}");
            let speed = |v: &f64| {
                if *v == STATIC_ROW {
                    "static".to_string()
                } else {
                    format!("{v}")
                }
            };
            chart
                .configure_mesh()
                .disable_mesh()
                .x_desc(map.x.describe())
                .y_desc(map.y.describe())
                .x_label_formatter(&number)
                .y_label_formatter(if map.y == Axis::Speed {
                    &speed
                } else {
                    &number
                })
                .label_style(("sans-serif", 13))
                .draw()
                .map_err(|e| draw(&e))?;
            let centre = TextStyle::from(("sans-serif", 13).into_font())
                .pos(Pos::new(HPos::Center, VPos::Center));
            for (i, &x) in xs.iter().enumerate() {
                for (j, &y) in ys.iter().enumerate() {
                    let p = map.point(x, y);
                    let Some(r) = runs.iter().find(|r| r.point() == p) else {
                        continue;
                    };
                    let (lo, hi) = (xe[i], ye[j]);
                    chart
                        .draw_series(std::iter::once(Rectangle::new(
                            [(lo.0, hi.0), (lo.1, hi.1)],
                            colour(&r.outcome).filled(),
                        )))
                        .map_err(|e| draw(&e))?;
                    chart
                        .draw_series(std::iter::once(Rectangle::new(
                            [(lo.0, hi.0), (lo.1, hi.1)],
                            WHITE.stroke_width(1),
                        )))
                        .map_err(|e| draw(&e))?;
                    if let Some(m) = r.mre {
                        let c = ((lo.0 * lo.1).sqrt(), (hi.0 * hi.1).sqrt());
                        chart
                            .draw_series(std::iter::once(Text::new(
                                format!("{:.0} %", 100.0 * m),
                                c,
                                centre.clone(),
                            )))
                            .map_err(|e| draw(&e))?;
                    }
                }
            }
            if map.y == Axis::Speed {
                // v dt = 0.5Δ, with each column's time step.
                let line: Vec<(f64, f64)> = xs
                    .iter()
                    .zip(&xpos)
                    .filter_map(|(&x, &xp)| {
                        let p = map.point(x, Value::Loading(Loading::Impact(IMPACT_SPEEDS[0])));
                        let r = runs.iter().find(|r| r.point() == p && r.dt > 0.0)?;
                        Some((xp, r.window / r.dt))
                    })
                    .collect();
                chart
                    .draw_series(LineSeries::new(line, BLACK.stroke_width(2)))
                    .map_err(|e| draw(&e))?;
            }
        }
        let legend = [
            ("stable and accurate", "stable and accurate (MRE ≤ 10 %)"),
            (
                "stable but inaccurate",
                "stable but inaccurate (MRE > 10 %)",
            ),
            ("stable", "stable (impact)"),
            ("missed contacts", "missed contacts"),
            ("blew up", "blew up"),
        ];
        // Laid out by an estimate of the text's width (7 px a character at 14 px).
        let mut x = 20;
        for (outcome, text) in legend {
            bottom
                .draw(&Rectangle::new(
                    [(x, 14), (x + 18, 32)],
                    colour(outcome).filled(),
                ))
                .map_err(|e| draw(&e))?;
            bottom
                .draw(&Text::new(text, (x + 24, 16), ("sans-serif", 14)))
                .map_err(|e| draw(&e))?;
            x += 24 + 7 * text.chars().count() as i32 + 30;
        }
        bottom
            .draw(&PathElement::new(
                vec![(x, 23), (x + 30, 23)],
                BLACK.stroke_width(2),
            ))
            .map_err(|e| draw(&e))?;
        bottom
            .draw(&Text::new(
                "v·dt = 0.5Δ: one step crosses the window",
                (x + 36, 16),
                ("sans-serif", 14),
            ))
            .map_err(|e| draw(&e))?;
        Ok(())
    })
}
