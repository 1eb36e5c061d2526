//! `pdcontact convert`: a mesh to a PD case folder (`case.toml`, `particles.vtu`,
//! `segments.vtu`) and a JSON summary.

use std::path::Path;
use std::time::Instant;

use pdcontact_importers::{read_path, Format, Mesh, SetKind};
use serde::Serialize;

use crate::case::{CaseOptions, PdCase};
use crate::error::{Error, Result};
use crate::output::vtk::{write_atomically, write_vtu, CellSpec, Field};

/// Seconds spent per stage.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct ConvertSeconds {
    pub import: f64,
    pub discretize: f64,
    pub neighbours: f64,
    pub surface: f64,
    pub correction: f64,
    pub segments: f64,
    /// Writing `particles.vtu`, `segments.vtu` and `case.toml`.
    pub write: f64,
    pub total: f64,
}

/// What `convert --json` prints.
#[derive(Clone, Debug, Serialize)]
pub struct ConvertSummary {
    pub particles: usize,
    pub bonds: usize,
    pub spacing: f64,
    pub horizon: f64,
    pub total_volume: f64,
    pub mesh_volume: f64,
    pub surface_particles: usize,
    pub boundary_nodes: usize,
    pub surface_missed: usize,
    pub surface_extra: usize,
    pub master_segments: usize,
    pub dropped_faces: usize,
    /// Passes over the bonds the surface correction took, and its largest remaining
    /// strain-energy error under the three uniaxial loads (METHOD.md §2).
    pub correction_passes: usize,
    pub correction_energy_error: f64,
    /// Particles the correction left more than 1 % off the bulk energy.
    pub correction_unbalanced: usize,
    /// What the importer and the mesh quality checks found.
    pub warnings: Vec<String>,
    pub seconds: ConvertSeconds,
}

impl ConvertSummary {
    /// Summarises a built case.
    pub fn of(case: &PdCase, seconds: ConvertSeconds) -> ConvertSummary {
        let agreement = case.surface_agreement();
        ConvertSummary {
            particles: case.particles.len(),
            bonds: case.bonds.len(),
            spacing: case.particles.spacing,
            horizon: case.horizon,
            total_volume: case.particles.total_volume(),
            mesh_volume: case.particles.mesh_volume,
            surface_particles: agreement.surface_particles,
            boundary_nodes: agreement.boundary_nodes,
            surface_missed: agreement.missed,
            surface_extra: agreement.extra,
            master_segments: case.segments.segments.len(),
            dropped_faces: case.segments.dropped_faces,
            correction_passes: case.correction.passes,
            correction_energy_error: case.correction.max_energy_error,
            correction_unbalanced: case.correction.unbalanced,
            warnings: case.mesh.warnings.clone(),
            seconds,
        }
    }

    /// Readable lines for the terminal.
    pub fn to_text(&self) -> String {
        let mut text = format!(
            "particles {} (volume {:.6e}, mesh {:.6e}, {:+.3} %)\n\
             bonds {} ({:.1} per particle), spacing {:.6e}, horizon {:.6e}\n\
             surface particles {}, mesh boundary nodes {}: {} missed, {} extra\n\
             master segments {} ({} boundary faces dropped)\n\
             surface correction: {} passes, {} particles more than 1 % off the bulk energy \
             (largest {:.2} %)\n\
             seconds: import {:.3}, discretize {:.3}, neighbours {:.3}, surface {:.3}, \
             correction {:.3}, segments {:.3}, write {:.3}, total {:.3}\n",
            self.particles,
            self.total_volume,
            self.mesh_volume,
            100.0 * (self.total_volume / self.mesh_volume - 1.0),
            self.bonds,
            self.bonds as f64 / self.particles.max(1) as f64,
            self.spacing,
            self.horizon,
            self.surface_particles,
            self.boundary_nodes,
            self.surface_missed,
            self.surface_extra,
            self.master_segments,
            self.dropped_faces,
            self.correction_passes,
            self.correction_unbalanced,
            100.0 * self.correction_energy_error,
            self.seconds.import,
            self.seconds.discretize,
            self.seconds.neighbours,
            self.seconds.surface,
            self.seconds.correction,
            self.seconds.segments,
            self.seconds.write,
            self.seconds.total,
        );
        for w in &self.warnings {
            text.push_str(&format!("warning: {w}\n"));
        }
        text
    }
}

/// Runs `convert`: reads `mesh_path`, builds the case, writes the folder `out`.
pub fn convert(
    mesh_path: &Path,
    format: Option<Format>,
    out: &Path,
    options: CaseOptions,
) -> Result<(PdCase, ConvertSummary)> {
    let start = Instant::now();
    let mesh = read_path(mesh_path, format)?;
    let import = start.elapsed().as_secs_f64();
    let case = PdCase::build(mesh, options).map_err(|e| match e {
        Error::Input(msg) => Error::input(format!("{}: {msg}", mesh_path.display())),
        other => other,
    })?;
    std::fs::create_dir_all(out).map_err(|e| Error::output(out, e))?;
    let t = Instant::now();
    write_case_files(&case, mesh_path, out)?;
    let seconds = ConvertSeconds {
        import,
        discretize: case.times.discretize,
        neighbours: case.times.neighbours,
        surface: case.times.surface,
        correction: case.times.correction,
        segments: case.times.segments,
        write: t.elapsed().as_secs_f64(),
        total: start.elapsed().as_secs_f64(),
    };
    let summary = ConvertSummary::of(&case, seconds);
    Ok((case, summary))
}

/// Writes `particles.vtu`, `segments.vtu` and `case.toml`.
pub fn write_case_files(case: &PdCase, mesh_path: &Path, out: &Path) -> Result<()> {
    let p = &case.particles;
    let mesh = &case.mesh;
    write_vtu(
        &out.join("particles.vtu"),
        &p.position,
        CellSpec::Vertices,
        vec![
            Field::scalar("volume", p.volume.clone()),
            Field::scalar("lambda_min", case.surface.lambda_min.clone()),
            Field::scalar("kernel_fill", case.surface.kernel_fill.clone()),
            Field::flag("surface", &case.surface.is_surface),
            Field::vector("normal", case.surface.normal.clone()),
            Field::id(
                "node_id",
                p.node
                    .iter()
                    .map(|&n| mesh.node_ids[n as usize] as i64)
                    .collect(),
            ),
            Field::flag("boundary_node", &case.segments.boundary_node),
            Field::scalar("tributary_area", case.segments.tributary_area.clone()),
            Field::scalar("pressure_area", case.segments.pressure_area.clone()),
        ],
        vec![],
    )?;
    let segs = &case.segments.segments;
    write_vtu(
        &out.join("segments.vtu"),
        &p.position,
        CellSpec::Quads(segs.iter().map(|s| s.nodes).collect()),
        vec![],
        vec![
            Field::scalar("area", segs.iter().map(|s| s.area).collect()),
            Field::vector("normal", segs.iter().map(|s| s.normal).collect()),
        ],
    )?;
    let toml = case_toml(case, mesh_path, out);
    let path = out.join("case.toml");
    write_atomically(&path, |w| std::io::Write::write_all(w, toml.as_bytes()))
}

/// The scene skeleton: this body pressed by a load onto a rigid plane just below it.
fn case_toml(case: &PdCase, mesh_path: &Path, out: &Path) -> String {
    let mesh_ref = relative_mesh_path(mesh_path, out);
    let (lo, hi) = case.mesh.bbox().unwrap_or(([0.0; 3], [1.0; 3]));
    let size: Vec<f64> = (0..3).map(|k| hi[k] - lo[k]).collect();
    let centre: Vec<f64> = (0..3).map(|k| 0.5 * (hi[k] + lo[k])).collect();
    // A load that strains the body by about 1e-4: P ≈ 1e-4 E A over its footprint.
    let youngs = 1.0e9;
    let footprint = (size[0] * size[1]).max(1e-30);
    let load = 1e-4 * youngs * footprint;
    let mut sets = String::new();
    for s in &set_comments(&case.mesh) {
        sets.push_str(&format!("#   {s}\n"));
    }
    if sets.is_empty() {
        sets.push_str("#   (the mesh defines no named sets)\n");
    }
    let plane_size = 2.0 * size[0].max(size[1]).max(case.particles.spacing);
    format!(
        r#"# pdcontact scene made by `pdcontact convert` for {mesh_name}.
# Run it with:  pdcontact run {case_path}
# Every key is documented in the README ("Scene files"). Lengths in metres, forces in newtons.

[solver]
kind = "adr"              # "adr" (quasi-static, adaptive dynamic relaxation) or "explicit"
tolerance = 1e-4          # ADR: out-of-balance force relative to the applied load
max_iterations = 100000   # ADR: give up (exit 1) after this many iterations

[output]
folder = "out"            # relative to this file
every = 500               # write a .vtu every N iterations (and the last one)

[[body]]
name = "part"
mesh = "{mesh_ref}"
kind = "deformable"       # a PD body: particles, bonds, surface
spacing = {spacing:e}     # grid spacing Δ (median element edge of the mesh)
horizon_factor = {m}      # horizon δ = m Δ
# translate = [0.0, 0.0, 0.0]
# rotate = {{ axis = [0.0, 0.0, 1.0], angle_deg = 0.0 }}
# scale = 1.0
[body.material]
youngs_modulus = {youngs:e}   # E, Pa
poisson_ratio = 0.25          # bond-based PD requires 1/4
density = 1000.0              # kg/m3

# Named sets of this mesh, usable as `set = "..."` in loads and constraints:
{sets}
[[body]]
name = "plane"
kind = "rigid"            # surface only: no particles, no bonds
generator = {{ shape = "plane", point = [{cx:e}, {cy:e}, {pz:e}], normal = [0.0, 0.0, 1.0], size = {plane_size:e} }}
motion = "fixed"

[[load]]
body = "part"
# set = "top"             # a named node set; without it the force is spread over the whole body by volume
force = [0.0, 0.0, {fz:e}]  # total force, N

[[contact]]
slave = "part"
master = "plane"
"#,
        mesh_name = mesh_path.display(),
        case_path = out.join("case.toml").display(),
        spacing = case.particles.spacing,
        m = case.horizon_factor,
        cx = centre[0],
        cy = centre[1],
        pz = lo[2],
        fz = -load,
    )
}

/// One comment line per named set: name, kind, node count.
fn set_comments(m: &Mesh) -> Vec<String> {
    m.sets
        .iter()
        .map(|s| {
            let what = match s.kind {
                SetKind::NodeSet => "node set",
                SetKind::ElementSet => "element set",
                SetKind::PhysicalGroup => "physical group",
                SetKind::Component => "component",
            };
            let nodes = m.set_nodes(s).len();
            format!("{:<24} {what}, {nodes} nodes", format!("\"{}\"", s.name))
        })
        .collect()
}

fn relative_mesh_path(mesh_path: &Path, out: &Path) -> String {
    let abs = |p: &Path| std::fs::canonicalize(p).unwrap_or_else(|_| p.to_path_buf());
    let m = abs(mesh_path);
    let o = abs(out);
    let s = match pathdiff(&m, &o) {
        Some(rel) => rel,
        None => m.display().to_string(),
    };
    s.replace('\\', "/").replace('"', "\\\"")
}

/// `target` relative to `base`, when both are absolute.
fn pathdiff(target: &Path, base: &Path) -> Option<String> {
    let t: Vec<_> = target.components().collect();
    let b: Vec<_> = base.components().collect();
    let common = t.iter().zip(&b).take_while(|(x, y)| x == y).count();
    if common == 0 {
        return None;
    }
    let mut parts: Vec<String> = vec!["..".to_string(); b.len() - common];
    parts.extend(
        t[common..]
            .iter()
            .map(|c| c.as_os_str().to_string_lossy().into_owned()),
    );
    Some(parts.join("/"))
}
