//! What the studies' SVG charts share: a white canvas of the given size, drawn into a string
//! by plotters and written atomically, with plotters' errors named by the file; and the legend
//! box.

use std::path::Path;

use plotters::chart::SeriesLabelStyle;
use plotters::coord::CoordTranslate;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::error::{Error, Result};
use crate::output::vtk::write_atomically;

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
