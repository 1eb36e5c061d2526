//! What the studies' SVG charts share: a white canvas of the given size, drawn into a string
//! by plotters and written atomically, with plotters' errors named by the file; and the legend
//! box.

use std::path::Path;

use plotters::chart::SeriesLabelStyle;
use plotters::coord::CoordTranslate;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::vtk::write_atomically;
use crate::error::{Error, Result};

/// The canvas a chart draws on.
pub type Canvas<'a> = DrawingArea<SVGBackend<'a>, Shift>;

/// Turns a plotters error into an output error on the chart's file.
pub type DrawError<'a> = dyn Fn(&dyn std::fmt::Display) -> Error + 'a;

/// Draws a chart of `size` pixels with `draw` on a white canvas and writes it to `path`.
pub fn write_svg(
    path: &Path,
    size: (u32, u32),
    draw: impl FnOnce(&Canvas<'_>, &DrawError<'_>) -> Result<()>,
) -> Result<()> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        let error = |e: &dyn std::fmt::Display| Error::output(path, e.to_string());
        root.fill(&WHITE).map_err(|e| error(&e))?;
        draw(&root, &error)?;
        root.present().map_err(|e| error(&e))?;
    }
    write_atomically(path, |w| std::io::Write::write_all(w, svg.as_bytes()))
}

/// A chart's legend box: white, 80 % opaque, with a black border (position and draw to the
/// caller).
pub fn legend<'a, 'b, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &'b mut ChartContext<'a, DB, CT>,
) -> SeriesLabelStyle<'a, 'b, DB, CT> {
    let mut style = chart.configure_series_labels();
    style.background_style(WHITE.mix(0.8)).border_style(BLACK);
    style
}

/// The load-displacement curve of a run under displacement control: the reaction on the
/// driven body along its displacement against the displacement, one point per increment
/// (mm and kN where the numbers suit them, else m and N).
pub fn write_load_displacement(path: &Path, increments: &[crate::solver::Increment]) -> Result<()> {
    let Some(last) = increments.last() else {
        return Ok(());
    };
    let dir = crate::math::Vec3::from(last.displacement);
    let dir = if dir.norm() > 0.0 {
        dir.normalize()
    } else {
        crate::math::Vec3::z()
    };
    // The reaction opposes the drive: the force the driven body exerts, along its motion.
    let points: Vec<(f64, f64)> = std::iter::once((0.0, 0.0))
        .chain(increments.iter().map(|s| {
            (
                crate::math::Vec3::from(s.displacement).dot(&dir),
                -crate::math::Vec3::from(s.reaction).dot(&dir),
            )
        }))
        .collect();
    let dmax = points.iter().map(|p| p.0.abs()).fold(0.0, f64::max);
    let fmax = points.iter().map(|p| p.1.abs()).fold(0.0, f64::max);
    let (du, dname) = if dmax < 0.1 { (1e3, "mm") } else { (1.0, "m") };
    let (fu, fname) = if fmax > 1e4 { (1e-3, "kN") } else { (1.0, "N") };
    let scaled: Vec<(f64, f64)> = points.iter().map(|&(d, f)| (d * du, f * fu)).collect();
    let xmax = dmax * du * 1.05 + 1e-12;
    let ymin = scaled.iter().map(|p| p.1).fold(0.0, f64::min) * 1.1;
    let ymax = scaled.iter().map(|p| p.1).fold(0.0, f64::max) * 1.1 + 1e-12;
    write_svg(path, (720, 480), |root, draw| {
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!("Load against displacement of \"{}\"", last.body),
                ("sans-serif", 18),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..xmax, ymin..ymax)
            .map_err(|e| draw(&e))?;
        chart
            .configure_mesh()
            .x_desc(format!("displacement ({dname})"))
            .y_desc(format!("reaction ({fname})"))
            .draw()
            .map_err(|e| draw(&e))?;
        chart
            .draw_series(LineSeries::new(scaled.clone(), BLUE.stroke_width(2)))
            .map_err(|e| draw(&e))?;
        chart
            .draw_series(scaled.iter().map(|&p| Circle::new(p, 3, BLUE.filled())))
            .map_err(|e| draw(&e))?;
        Ok(())
    })
}
