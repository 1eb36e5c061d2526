//! The `inspect` summary: the schema of the corpus manifest (`../shared/corpus/manifest.json`).

use serde::Serialize;

use crate::faces::boundary_faces;
use crate::mesh::{ElementKind, Format, Mesh};

/// Counts of 3D elements by kind.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct SolidCounts {
    pub hex8: usize,
    pub hex20: usize,
    pub tet4: usize,
    pub tet10: usize,
    pub wedge6: usize,
    pub wedge15: usize,
    pub pyramid5: usize,
    pub pyramid13: usize,
    pub total: usize,
}

/// A bounding box.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BBox {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

/// Boundary face counts.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct FaceCounts {
    pub tri: usize,
    pub quad: usize,
    pub total: usize,
}

/// One named set as `inspect` lists it.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct SetSummary {
    pub name: String,
    pub kind: &'static str,
    pub nodes: Option<usize>,
    pub elements: Option<usize>,
}

/// What `pdcontact inspect --json` prints.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeshSummary {
    pub format: &'static str,
    pub nodes_total: usize,
    pub corner_nodes_in_3d_elements: usize,
    pub elements_3d: SolidCounts,
    pub bbox: Option<BBox>,
    pub boundary_faces: FaceCounts,
    pub sets: Vec<SetSummary>,
    pub warnings: Vec<String>,
}

impl MeshSummary {
    /// Summarises a mesh read from a file of the given format.
    pub fn of(mesh: &Mesh, format: Format) -> MeshSummary {
        let mut elements_3d = SolidCounts::default();
        for &k in &mesh.element_kinds {
            let slot = match k {
                ElementKind::Hex8 => &mut elements_3d.hex8,
                ElementKind::Hex20 => &mut elements_3d.hex20,
                ElementKind::Tet4 => &mut elements_3d.tet4,
                ElementKind::Tet10 => &mut elements_3d.tet10,
                ElementKind::Wedge6 => &mut elements_3d.wedge6,
                ElementKind::Wedge15 => &mut elements_3d.wedge15,
                ElementKind::Pyramid5 => &mut elements_3d.pyramid5,
                ElementKind::Pyramid13 => &mut elements_3d.pyramid13,
                _ => continue,
            };
            *slot += 1;
            elements_3d.total += 1;
        }
        let faces = boundary_faces(mesh);
        let tri = faces.boundary.iter().filter(|f| f.is_triangle()).count();
        let mut warnings = mesh.warnings.clone();
        if faces.non_manifold > 0 {
            warnings.push(format!(
                "{} faces are shared by three or more solid elements (non-manifold mesh)",
                faces.non_manifold
            ));
        }
        MeshSummary {
            format: format.name(),
            nodes_total: mesh.node_count(),
            corner_nodes_in_3d_elements: mesh.solid_corner_mask().iter().filter(|&&b| b).count(),
            elements_3d,
            bbox: mesh.bbox().map(|(min, max)| BBox { min, max }),
            boundary_faces: FaceCounts {
                tri,
                quad: faces.boundary.len() - tri,
                total: faces.boundary.len(),
            },
            sets: mesh
                .sets
                .iter()
                .map(|s| SetSummary {
                    name: s.name.clone(),
                    kind: s.kind.name(),
                    nodes: s.nodes.as_ref().map(Vec::len),
                    elements: s.elements.as_ref().map(Vec::len),
                })
                .collect(),
            warnings,
        }
    }

    /// A readable multi-line summary for the terminal.
    pub fn to_text(&self, path: &str) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(s, "{path} ({})", self.format);
        let _ = writeln!(
            s,
            "  nodes: {} ({} corners of 3D elements)",
            self.nodes_total, self.corner_nodes_in_3d_elements
        );
        let e = &self.elements_3d;
        let kinds = [
            ("hex8", e.hex8),
            ("hex20", e.hex20),
            ("tet4", e.tet4),
            ("tet10", e.tet10),
            ("wedge6", e.wedge6),
            ("wedge15", e.wedge15),
            ("pyramid5", e.pyramid5),
            ("pyramid13", e.pyramid13),
        ];
        let listed: Vec<String> = kinds
            .iter()
            .filter(|(_, n)| *n > 0)
            .map(|(k, n)| format!("{n} {k}"))
            .collect();
        let _ = writeln!(
            s,
            "  3D elements: {}{}",
            e.total,
            if listed.is_empty() {
                String::new()
            } else {
                format!(" ({})", listed.join(", "))
            }
        );
        if let Some(b) = &self.bbox {
            let _ = writeln!(
                s,
                "  bounding box: [{:.6e}, {:.6e}, {:.6e}] .. [{:.6e}, {:.6e}, {:.6e}]",
                b.min[0], b.min[1], b.min[2], b.max[0], b.max[1], b.max[2]
            );
        }
        let f = &self.boundary_faces;
        let _ = writeln!(
            s,
            "  boundary faces: {} ({} quads, {} triangles)",
            f.total, f.quad, f.tri
        );
        if self.sets.is_empty() {
            let _ = writeln!(s, "  named sets: none");
        } else {
            let _ = writeln!(s, "  named sets:");
            for set in &self.sets {
                let mut what = Vec::new();
                if let Some(n) = set.nodes {
                    what.push(format!("{n} nodes"));
                }
                if let Some(n) = set.elements {
                    what.push(format!("{n} elements"));
                }
                let _ = writeln!(
                    s,
                    "    {:<24} {:<15} {}",
                    set.name,
                    set.kind,
                    what.join(", ")
                );
            }
        }
        for w in &self.warnings {
            let _ = writeln!(s, "  warning: {w}");
        }
        s
    }
}
