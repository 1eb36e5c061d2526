//! What `validate --mesh` reports, and its printed form.

use std::path::PathBuf;

use serde::Serialize;

use super::{MeshShape, Remedy};
use crate::studies::comparison::ValidationRow;
use crate::studies::validate::table_with_peak;

/// What `validate --mesh` reports.
#[derive(Clone, Debug, Serialize)]
pub struct MeshValidation {
    pub mesh: PathBuf,
    pub format: String,
    pub shape: MeshShape,
    /// Hertz contact radius or half-width, m.
    pub theory_contact_radius: f64,
    /// The particle spacing Δ at the contact, m: the run's grid spacing, or on a mesh graded in
    /// size the local spacing there (the median over the particles within `a` of the contact
    /// point or line, [`crate::case::spacing`]).
    pub spacing: f64,
    /// `a/Δ`: particle spacings across the contact radius.
    pub contact_spacings: f64,
    pub warnings: Vec<String>,
    /// The scene that was run.
    pub scene: PathBuf,
    /// The mesh as it is, then, where [`Remedy`] ran, the finer particles.
    pub rows: Vec<ValidationRow>,
    /// The second row's particles, where the contact was poorly resolved on the mesh's own.
    pub remedy: Option<Remedy>,
    /// The quasi-static solver the scenes were run with: `"static"` (the default) or
    /// `"adr"`; the table's `iters` are its iterations.
    pub solver: String,
}

impl MeshValidation {
    /// The printed report: the shape, `a/Δ`, the table with the peak column.
    pub fn to_text(&self) -> String {
        let s = &self.shape;
        let mut out = format!(
            "{} ({}): {}, R = {:.6} m, centre [{:.4}, {:.4}, {:.4}]",
            self.mesh.display(),
            self.format,
            s.shape,
            s.radius,
            s.centre[0],
            s.centre[1],
            s.centre[2]
        );
        if let (Some(axis), Some(ends)) = (&s.axis, s.ends) {
            out.push_str(&format!(
                ", axis {axis} from {:.4} to {:.4} (symmetry planes: plane strain)",
                ends[0], ends[1]
            ));
        }
        out.push_str(&format!(
            "; boundary nodes within {:.2} % of R; pressed along {}\n",
            100.0 * s.max_deviation,
            s.pressed_along
        ));
        out.push_str(&format!(
            "a/Δ = {:.2}: the Hertz contact {} a = {:.4} m spans {:.1} particle spacings (Δ = {:.4} m)\n",
            self.contact_spacings,
            if s.axis.is_some() { "half-width" } else { "radius" },
            self.theory_contact_radius,
            self.contact_spacings,
            self.spacing
        ));
        for w in &self.warnings {
            out.push_str(&format!("warning: {w}\n"));
        }
        out.push('\n');
        out.push_str(&table_with_peak(&self.rows));
        out.push_str(match self.solver.as_str() {
            "static" => "iters: Newton iterations of the static solver, + ADR's where Newton stalled (`--solver adr` for ADR's alone, to the same figures)\n",
            _ => "iters: ADR iterations (the static solver, the default, gives the same figures in far fewer)\n",
        });
        if let Some(r) = self.rows.first() {
            out.push_str(&format!(
                "\nScene: {}\nFrames: {}\nChart: {}\n",
                self.scene.display(),
                r.output_pvd.display(),
                r.chart.display()
            ));
        }
        // The finer run has as many rows as the mesh's own (one, or one per body on its copy).
        let first = self.rows.len() / 2;
        if let (Some(m), Some(r)) = (&self.remedy, self.rows.get(first)) {
            out.push_str(&format!(
                "\n{}: the same mesh with `{}` on the body (a/Δ = {:.2}, Δ = {:.4} m): put that key in your scene's [[body]] for these figures.\nScene: {}\nFrames: {}\nChart: {}\n",
                rows_named(first, self.rows.len(), true),
                m.key,
                m.contact_spacings,
                m.spacing,
                m.scene.display(),
                r.output_pvd.display(),
                r.chart.display()
            ));
        }
        out
    }
}

/// "second row" for row 1 of 2, "rows 3 and 4" for rows 2-3 of 4 (0-based `first`, `len`
/// rows); `capital` for the start of a sentence.
pub(super) fn rows_named(first: usize, len: usize, capital: bool) -> String {
    let named = match len - first {
        1 if first == 1 => "second row".to_string(),
        1 => format!("row {}", first + 1),
        2 => format!("rows {} and {}", first + 1, first + 2),
        _ => format!("rows {} to {len}", first + 1),
    };
    if capital {
        let mut c = named.chars();
        c.next()
            .map(|f| f.to_uppercase().chain(c).collect())
            .unwrap_or_default()
    } else {
        named
    }
}

#[cfg(test)]
mod tests {
    use super::rows_named;

    /// The finer rows are named by where they stand: after the one row of a body on a rigid
    /// plane, or after the two of a mesh pressed on its copy.
    #[test]
    fn the_finer_rows_are_named_where_they_stand() {
        assert_eq!(rows_named(1, 2, true), "Second row");
        assert_eq!(rows_named(2, 4, true), "Rows 3 and 4");
        assert_eq!(rows_named(2, 4, false), "rows 3 and 4");
        assert_eq!(rows_named(2, 3, false), "row 3");
    }
}
