//! A PD case: a mesh turned into particles, bonds, corrections, surface and master segments
//! (METHOD.md §1-4). This is what `pdcontact convert` writes and what each deformable body of a
//! scene is built from.

use std::time::Instant;

use pdcontact_importers::{boundary_faces, FaceSet, Mesh};

use crate::correction::{surface_correction, CorrectionMethod, SurfaceCorrection};
use crate::discretize::{discretize, Discretization};
use crate::error::{Error, Result};
use crate::neighbours::{build_bonds, BondList};
use crate::segments::{master_segments, SegmentSet};
use crate::surface::{detect_surface, SurfaceDetection};

/// Default horizon factor `m` (δ = m·Δ).
pub const DEFAULT_HORIZON_FACTOR: f64 = 3.0;

/// Options of the discretisation.
#[derive(Clone, Copy, Debug)]
pub struct CaseOptions {
    /// Grid spacing Δ; `None` takes the median element edge.
    pub spacing: Option<f64>,
    /// Horizon factor m.
    pub horizon_factor: f64,
    /// How to compute surface correction factors.
    pub correction: CorrectionMethod,
}

impl Default for CaseOptions {
    fn default() -> Self {
        CaseOptions {
            spacing: None,
            horizon_factor: DEFAULT_HORIZON_FACTOR,
            correction: CorrectionMethod::Balanced,
        }
    }
}

/// Wall time of each stage, in seconds.
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct StageTimes {
    pub neighbours: f64,
    pub surface: f64,
    pub correction: f64,
    pub segments: f64,
}

/// Agreement between eigenvalue surface particles and mesh boundary nodes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SurfaceAgreement {
    pub surface_particles: usize,
    pub boundary_nodes: usize,
    /// Boundary nodes the eigenvalue method did not flag.
    pub missed: usize,
    /// Interior nodes the eigenvalue method flagged.
    pub extra: usize,
}

/// Everything the pipeline derives from one mesh.
#[derive(Clone, Debug)]
pub struct PdCase {
    pub mesh: Mesh,
    pub faces: FaceSet,
    pub particles: Discretization,
    /// Horizon δ.
    pub horizon: f64,
    pub horizon_factor: f64,
    pub bonds: BondList,
    pub surface: SurfaceDetection,
    pub correction: SurfaceCorrection,
    pub segments: SegmentSet,
    pub times: StageTimes,
}

impl PdCase {
    /// Builds the case from a mesh.
    pub fn build(mesh: Mesh, options: CaseOptions) -> Result<PdCase> {
        if !(options.horizon_factor > 0.0 && options.horizon_factor.is_finite()) {
            return Err(Error::input(format!(
                "horizon factor must be positive, got {}",
                options.horizon_factor
            )));
        }
        let particles = discretize(&mesh, options.spacing)?;
        let spacing = particles.spacing;
        let horizon = options.horizon_factor * spacing;
        let mut times = StageTimes::default();

        let t = Instant::now();
        // Bonds reach δ + r (r = Δ/2, Eq. 10); the surface kernel reaches 3h = 3Δ. One list
        // serves both; the 1e-9 keeps lattice bonds exactly at the edge.
        let reach = (horizon + 0.5 * spacing).max(3.0 * spacing) * (1.0 + 1e-9);
        let bonds = build_bonds(&particles.position, reach);
        times.neighbours = t.elapsed().as_secs_f64();

        let t = Instant::now();
        let surface = detect_surface(
            &particles.position,
            &particles.completed_volume(),
            &bonds,
            spacing,
        );
        times.surface = t.elapsed().as_secs_f64();

        // Drop the pairs that only the surface kernel needed.
        let bonds = trim_bonds(bonds, (horizon + 0.5 * spacing) * (1.0 + 1e-9));

        let t = Instant::now();
        let correction = surface_correction(
            &particles.position,
            &particles.volume,
            &bonds,
            horizon,
            spacing,
            options.correction,
        );
        times.correction = t.elapsed().as_secs_f64();

        let t = Instant::now();
        let faces = boundary_faces(&mesh);
        let segments = master_segments(&faces, &particles, &surface.is_surface);
        times.segments = t.elapsed().as_secs_f64();

        Ok(PdCase {
            mesh,
            faces,
            particles,
            horizon,
            horizon_factor: options.horizon_factor,
            bonds,
            surface,
            correction,
            segments,
            times,
        })
    }

    /// Compares eigenvalue surface particles with mesh boundary nodes.
    pub fn surface_agreement(&self) -> SurfaceAgreement {
        let mut a = SurfaceAgreement::default();
        for (&s, &b) in self
            .surface
            .is_surface
            .iter()
            .zip(&self.segments.boundary_node)
        {
            a.surface_particles += s as usize;
            a.boundary_nodes += b as usize;
            a.missed += (b && !s) as usize;
            a.extra += (s && !b) as usize;
        }
        a
    }
}

/// Keeps only bonds not longer than `reach`.
fn trim_bonds(bonds: BondList, reach: f64) -> BondList {
    if bonds.length.iter().all(|&l| l <= reach) {
        return bonds;
    }
    let n = bonds.particles();
    let mut out = BondList {
        offsets: Vec::with_capacity(n + 1),
        partner: Vec::new(),
        length: Vec::new(),
    };
    out.offsets.push(0);
    for i in 0..n {
        for b in bonds.range(i) {
            if bonds.length[b] <= reach {
                out.partner.push(bonds.partner[b]);
                out.length.push(bonds.length[b]);
            }
        }
        out.offsets.push(out.partner.len());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generators;

    /// A flat-faced hex block through the whole pipeline: lumped volumes, completed at the
    /// faces, give the lattice values of the eigenvalue test for h = Δ.
    #[test]
    fn flat_faced_block_lattice_lambdas() {
        let mesh = generators::cuboid([0.0; 3], [1.4, 1.4, 1.4], 0.1);
        let case = PdCase::build(mesh, CaseOptions::default()).expect("valid block");
        let p = &case.particles;
        let find = |x: f64, y: f64, z: f64| {
            (0..p.len())
                .find(|&i| (p.position[i] - crate::discretize::Vec3::new(x, y, z)).norm() < 1e-9)
                .expect("lattice point")
        };
        let face = case.surface.lambda_min[find(0.7, 0.7, 0.0)];
        let first = case.surface.lambda_min[find(0.7, 0.7, 0.1)];
        let second = case.surface.lambda_min[find(0.7, 0.7, 0.2)];
        assert!((face - 0.50).abs() < 0.01, "face {face}");
        assert!((first - 0.91).abs() < 0.01, "first layer {first}");
        assert!(second > 0.95, "second layer {second}");
        // Every boundary node is found, and no interior node is flagged.
        let a = case.surface_agreement();
        assert_eq!((a.missed, a.extra), (0, 0), "{a:?}");
        assert_eq!(case.segments.segments.len(), case.faces.boundary.len());
    }
}
