//! `pdcontact convert`: a mesh to a PD case folder (`case.toml`, `particles.vtu`,
//! `segments.vtu`) and a JSON summary.

use std::path::{Path, PathBuf};
use std::time::Instant;

use pdcontact_importers::{has_splittable, read_path, ElementKind, Format, Mesh, SetKind};
use serde::Serialize;

use crate::case::segments::MasterSegment;
use crate::case::{CaseOptions, PdCase, SecondOrder};
use crate::contact::estimate::{
    resolve, sig, ContactResolution, ContactSurface, HertzEstimate, PENALTY_TARGET,
    RESOLVED_SPACINGS, SMALL_STRAIN_RATIO, STRAIN_LIMIT,
};
use crate::contact::{default_radius, hertz_stiffness, ContactLaw, WINDOW};
use crate::error::{Error, Result};
use crate::math::Vec3;
use crate::output::vtk::{write_keeping_edits, write_vtu, CellSpec, Field};
use crate::scene::PenaltyLaw;

mod parts;
mod pins;

use pins::{pins_and_pieces, solids, solver_block};

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
    /// On a mesh graded in size, the smallest and largest local spacing `s_i`: each bond's
    /// horizon is m times its particles' mean (`HorizonKind::Local`); `None` where δ is one.
    pub local_spacing: Option<[f64; 2]>,
    pub total_volume: f64,
    pub mesh_volume: f64,
    pub surface_particles: usize,
    pub boundary_nodes: usize,
    /// Smooth surface particles whose volume was set to their area times the surface layer's
    /// thickness (`surface_volume = "per-area"`, the default).
    pub surface_layer_evened: usize,
    /// Bonds removed because they crossed a slot, notch or crack of the mesh narrower than the
    /// horizon (their line leaves the body and re-enters through a face facing the first).
    pub bonds_across_gaps: usize,
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
    /// What the importer and the mesh quality checks found, then what the contact estimate
    /// says of `case.toml`'s contact ([`SkeletonLoad`]).
    pub warnings: Vec<String>,
    /// The Hertz estimate of `case.toml`'s contact (the body on the plane under its load),
    /// the particle spacing and tributary-area ratio there.
    pub contact_estimates: Vec<ContactResolution>,
    pub seconds: ConvertSeconds,
}

impl ConvertSummary {
    /// Summarises a built case and the skeleton's contact.
    pub fn of(case: &PdCase, skeleton: &SkeletonLoad, seconds: ConvertSeconds) -> ConvertSummary {
        let agreement = case.surface_agreement();
        ConvertSummary {
            particles: case.particles.len(),
            bonds: case.bonds.len(),
            spacing: case.particles.spacing,
            horizon: case.horizon,
            local_spacing: case.local_spacing.as_ref().map(|s| {
                [
                    s.iter().copied().fold(f64::INFINITY, f64::min),
                    s.iter().copied().fold(0.0, f64::max),
                ]
            }),
            total_volume: case.particles.total_volume(),
            mesh_volume: case.particles.mesh_volume,
            surface_particles: agreement.surface_particles,
            boundary_nodes: agreement.boundary_nodes,
            surface_layer_evened: case.surface_layer_evened,
            bonds_across_gaps: case.bonds_across_gaps,
            surface_missed: agreement.missed,
            surface_extra: agreement.extra,
            master_segments: case.segments.segments.len(),
            dropped_faces: case.segments.dropped_faces,
            correction_passes: case.correction.passes,
            correction_energy_error: case.correction.max_energy_error,
            correction_unbalanced: case.correction.unbalanced,
            warnings: case
                .mesh
                .warnings
                .iter()
                .chain(&skeleton.warnings)
                .cloned()
                .collect(),
            contact_estimates: vec![skeleton.resolution.clone()],
            seconds,
        }
    }

    /// Readable lines for the terminal; the warnings are not among them (`pdcontact convert`
    /// prints those on stderr, as `run` does).
    pub fn to_text(&self) -> String {
        let mut text = format!(
            "particles {} (volume {:.6e}, mesh {:.6e}, {:+.3} %)\n\
             bonds {} ({:.1} per particle; {} across the mesh's gaps removed), spacing {:.6e}, horizon {:.6e}\n\
             surface particles {}, mesh boundary nodes {}: {} missed, {} extra; \
             {} with their volume evened to their area\n\
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
            self.bonds_across_gaps,
            self.spacing,
            self.horizon,
            self.surface_particles,
            self.boundary_nodes,
            self.surface_missed,
            self.surface_extra,
            self.surface_layer_evened,
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
        if let Some([lo, hi]) = self.local_spacing {
            text.push_str(&format!(
                "graded mesh: local spacing {lo:.4e} to {hi:.4e} ({:.1}:1); each bond's horizon is {:.3} times its particles' spacing\n",
                hi / lo,
                self.horizon / self.spacing
            ));
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
    let spacing = options.spacing;
    let mesh = read_path(mesh_path, format)?;
    let import = start.elapsed().as_secs_f64();
    let build = |mesh, options| {
        PdCase::build(mesh, options).map_err(|e| match e {
            Error::Input(msg) => Error::input(format!("{}: {msg}", mesh_path.display())),
            other => other,
        })
    };
    let given_factor = options.horizon_factor;
    // An assembly whose sets name its parts: they may touch, nodes of two on each other,
    // since each becomes a body of its own (the case as a whole would refuse such nodes).
    let options = CaseOptions {
        pieces_apart: options.pieces_apart || parts::named(&mesh),
        ..options
    };
    let mut case = build(mesh, options.clone())?;
    // Where the horizon leaves a solid in pieces (elements longer than the bonds reach), the
    // case written is the one that joins them: `run` would refuse the other.
    if let Some(split) = case.split.clone() {
        let options = CaseOptions {
            horizon_factor: split.horizon_factor,
            ..options
        };
        case = build(read_path(mesh_path, format)?, options)?;
        if let Some(still) = &case.split {
            return Err(Error::input(format!(
                "{}: {}",
                mesh_path.display(),
                still.message(case.particles.spacing, case.horizon_factor)
            )));
        }
        case.mesh.warnings.push(format!(
            "with horizon factor {given_factor} the bonds cut the mesh's solids into {} more piece{} than they are (element {}: nodes {} and {}, {:.4e} m apart, beyond the bonds' reach); the case has horizon_factor = {}, the smallest that joins them (or mesh it finer where its elements are longest)",
            split.extra_pieces, if split.extra_pieces == 1 { "" } else { "s" }, split.element, split.nodes[0], split.nodes[1], split.length, split.horizon_factor
        ));
    }
    std::fs::create_dir_all(out).map_err(|e| Error::output(out, e))?;
    let t = Instant::now();
    let skeleton = SkeletonLoad::choose(&case);
    let kept = write_case_files_with(&case, mesh_path, out, &skeleton, spacing)?;
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
    let mut summary = ConvertSummary::of(&case, &skeleton, seconds);
    if let Some(kept) = kept {
        summary.warnings.push(format!(
            "{} differed from the case this convert writes (edited?): it is kept as {}",
            out.join("case.toml").display(),
            kept.display()
        ));
    }
    Ok((case, summary))
}

/// Young's modulus and Poisson's ratio of the skeleton's material.
const SKELETON_YOUNGS: f64 = 1.0e9;
const SKELETON_POISSON: f64 = 0.25;

/// The load of `case.toml`, the body pressed on a rigid plane just under it, and what the
/// contact estimate says of the contact it makes ([`crate::contact::estimate`]).
///
/// Where the body's underside is convex, the load is the one whose Hertz contact radius spans
/// [`RESOLVED_SPACINGS`] particle spacings, the resolution of Hertz-level pressure, unless that
/// takes the contact beyond small strain (`a > 0.15 R`, METHOD.md §7): the load then stops at
/// `a = 0.15 R` and a warning says how fine a mesh the contact needs. Without an estimate (a
/// flat or concave underside) the load strains the body by about 1e-4 over its footprint.
#[derive(Clone, Debug)]
pub struct SkeletonLoad {
    /// Total force pressing the body down onto the plane, N.
    pub force: f64,
    /// Why this force (the comment on `case.toml`'s load line).
    pub reason: String,
    /// The estimate at this force.
    pub resolution: ContactResolution,
    /// What the estimate warns of.
    pub warnings: Vec<String>,
    /// The `[[contact]]`'s penalty radius R: the default Δ/2 where it keeps a particle at the
    /// expected peak within [`PENALTY_TARGET`] of the contact's depth, else the radius that
    /// does (`None` without an estimate: the default).
    pub penalty_radius: Option<f64>,
}

impl SkeletonLoad {
    /// Chooses the load for a case (the body named "part", the plane "plane").
    pub fn choose(case: &PdCase) -> SkeletonLoad {
        let (lo, hi) = case.mesh.bbox().unwrap_or(([0.0; 3], [1.0; 3]));
        let size = plane_size(case);
        let centre = [0.5 * (hi[0] + lo[0]), 0.5 * (hi[1] + lo[1]), lo[2]];
        let corners: Vec<Vec3> = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
            .iter()
            .map(|[x, y]| {
                Vec3::new(
                    centre[0] + 0.5 * size * x,
                    centre[1] + 0.5 * size * y,
                    lo[2],
                )
            })
            .collect();
        let faces = [MasterSegment {
            nodes: [0, 1, 2, 3],
            area: size * size,
            normal: Vec3::z(),
        }];
        let plane = ContactSurface {
            name: "plane",
            points: &corners,
            faces: &faces,
            planes: &[],
            tributary: None,
            load: Vec3::zeros(),
            compliance: 0.0,
            grid_spacing: 0.0,
            refine: 0,
        };
        let compliance = (1.0 - SKELETON_POISSON * SKELETON_POISSON) / SKELETON_YOUNGS;
        let at = |force: f64| {
            let part = ContactSurface::of_case("part", case, -force * Vec3::z(), compliance);
            resolve(&part, &plane).with_mesh_hints(case)
        };
        let footprint = ((hi[0] - lo[0]) * (hi[1] - lo[1])).max(1e-30);
        let mut force = 1e-4 * SKELETON_YOUNGS * footprint;
        let mut resolution = at(force);
        if resolution.estimate.is_none() || !(resolution.spacing > 0.0) {
            let warnings = resolution.warnings();
            return SkeletonLoad {
                force,
                reason: "strains the body by about 1e-4 over its footprint (its underside is not convex: no Hertz estimate)".into(),
                resolution,
                warnings,
                penalty_radius: None,
            };
        }
        // The spacing is measured within 2a of the contact: settle a and Δ together.
        let mut capped = false;
        for _ in 0..4 {
            let e = resolution.estimate.as_ref().expect("estimated");
            let most = SMALL_STRAIN_RATIO * e.curvature_radius();
            let target = RESOLVED_SPACINGS * resolution.spacing;
            capped = target > most;
            force *= e.load_factor(target.min(most));
            resolution = at(force);
        }
        // On an elongated contact `a = 0.15 R` (R the smaller radius of curvature) can still
        // strain the body past what `run` calls small strain: then the load stops there
        // (Hertz's p0 grows as the contact's radius or half-width does).
        let most_strain = 0.99 * STRAIN_LIMIT;
        if let Some(e) = resolution.estimate.clone() {
            let strain = e.peak_pressure() * compliance;
            if strain > most_strain {
                force *= e.load_factor(e.radius * most_strain / strain);
                resolution = at(force);
                capped = true;
            }
        }
        let e = resolution.estimate.clone().expect("estimated");
        let n = resolution.spacings.unwrap_or(0.0);
        // a/R: the small-strain cap as written, or below it where the strain capped the load.
        let ratio = |e: &HertzEstimate| {
            let r = e.radius / e.curvature_radius();
            if (r - SMALL_STRAIN_RATIO).abs() < 1e-3 {
                SMALL_STRAIN_RATIO.to_string()
            } else {
                sig(r)
            }
        };
        let (reason, mut warnings) = if capped && n < RESOLVED_SPACINGS {
            (
                format!(
                    "expected Hertz contact {} ≈ {} m = {} R (R = {} m), the most small strain allows; {RESOLVED_SPACINGS} surface spacings across it need h ≤ {} m (h: √ of the surface particles' median tributary area)",
                    e.what(), sig(e.radius), ratio(&e), sig(e.curvature_radius()), sig(e.radius / RESOLVED_SPACINGS)
                ),
                vec![format!(
                    "case.toml: the load {} N gives an expected contact {} ≈ {} m, the most small-strain Hertz allows on this body (a = {} R, R = {} m), which spans {n:.1} surface spacings (h = {} m{}); Hertz-level pressure needs ≥ {RESOLVED_SPACINGS} spacings across it — refine the mesh near the contact to h ≤ {} m{}",
                    sig(force), e.what(), sig(e.radius), ratio(&e), sig(e.curvature_radius()), sig(resolution.spacing), resolution.spacing_note(), sig(e.radius / RESOLVED_SPACINGS), resolution.mesh_hint()
                )],
            )
        } else {
            (
                format!(
                    "expected Hertz contact {} ≈ {} m = {n:.1} surface spacings (h = {} m, √ of the surface particles' median tributary area), the resolution of Hertz-level pressure",
                    e.what(), sig(e.radius), sig(resolution.spacing)
                ),
                resolution.resolution_warning().into_iter().collect(),
            )
        };
        warnings.extend(resolution.area_warning());
        warnings.extend(resolution.graded_warning());
        // The default penalty R = Δ/2 lets the particles sink by a tenth or more of a contact
        // a few spacings wide (METHOD.md §5): the case gets the radius that keeps it small.
        let law = |radius: f64| ContactLaw {
            law: PenaltyLaw::Hertz,
            stiffness: hertz_stiffness(compliance, 0.0, radius),
            window: WINDOW * case.particles.spacing,
        };
        let default = default_radius(case.particles.spacing);
        let radius = resolution
            .clone()
            .with_penalty(&law(default))
            .penalty
            .map_or(default, |p| p.suggested_radius);
        let resolution = resolution.with_penalty(&law(radius));
        SkeletonLoad {
            force,
            reason,
            resolution,
            warnings,
            penalty_radius: Some(radius),
        }
    }
}

/// Side of the skeleton's square plane: twice the body's footprint.
fn plane_size(case: &PdCase) -> f64 {
    let (lo, hi) = case.mesh.bbox().unwrap_or(([0.0; 3], [1.0; 3]));
    2.0 * (hi[0] - lo[0])
        .max(hi[1] - lo[1])
        .max(case.particles.spacing)
}

/// Writes `particles.vtu`, `segments.vtu` and `case.toml` (with [`SkeletonLoad::choose`]'s
/// load).
pub fn write_case_files(case: &PdCase, mesh_path: &Path, out: &Path) -> Result<()> {
    write_case_files_with(case, mesh_path, out, &SkeletonLoad::choose(case), None).map(|_| ())
}

/// Writes `particles.vtu`, `segments.vtu` and `case.toml` with the skeleton's load; `spacing`
/// is the spacing given to `convert` (`--spacing`), written as the body's; without it the
/// case leaves the spacing to `run`, which finds the same one from the mesh and, with a
/// `refine` added, from the refined mesh. A `case.toml` already there that differs (edited)
/// is kept under another name, returned.
pub fn write_case_files_with(
    case: &PdCase,
    mesh_path: &Path,
    out: &Path,
    skeleton: &SkeletonLoad,
    spacing: Option<f64>,
) -> Result<Option<PathBuf>> {
    let p = &case.particles;
    let mesh = &case.mesh;
    write_vtu(
        &out.join("particles.vtu"),
        &p.position,
        CellSpec::Vertices,
        vec![
            Field::scalar("volume", p.volume.clone()),
            Field::scalar(
                "horizon",
                match &case.local_spacing {
                    Some(s) => s.iter().map(|x| case.horizon_factor * x).collect(),
                    None => vec![case.horizon; p.len()],
                },
            ),
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
    let toml = case_toml(case, mesh_path, out, skeleton, spacing);
    write_keeping_edits(&out.join("case.toml"), &toml)
}

/// The scene skeleton: this body pressed by a load onto a rigid plane just below it.
fn case_toml(
    case: &PdCase,
    mesh_path: &Path,
    out: &Path,
    skeleton: &SkeletonLoad,
    given_spacing: Option<f64>,
) -> String {
    let mesh_ref = relative_mesh_path(mesh_path, out);
    let (lo, hi) = case.mesh.bbox().unwrap_or(([0.0; 3], [1.0; 3]));
    let centre: Vec<f64> = (0..3).map(|k| 0.5 * (hi[k] + lo[k])).collect();
    let youngs = SKELETON_YOUNGS;
    let mut sets = String::new();
    for s in &set_comments(&case.mesh) {
        sets.push_str(&format!("#   {s}\n"));
    }
    if sets.is_empty() {
        sets.push_str("#   (the mesh defines no named sets)\n");
    }
    let plane_size = plane_size(case);
    // One Δ: the spacing `run` finds from the mesh is the one this case was built with,
    // so the key stays a comment unless it was given; written, it would outlive a
    // `refine = 1` that halves the particles' spacing and double the horizon in spacings.
    let spacing_line = match given_spacing {
        Some(dx) => format!("spacing = {dx:e}     # grid spacing Δ, as given to convert\n"),
        None => format!(
            "# spacing = {:e}   # grid spacing Δ: by default, as here, the lattice spacing of the particles' median volume\n",
            case.particles.spacing
        ),
    };
    let second_order = match case.second_order {
        SecondOrder::AllNodes => {
            "second_order = \"all-nodes\"  # every node of a tet10 or hex20 a particle\n"
        }
        SecondOrder::Corners if has_splittable(&case.mesh) => {
            "# second_order = \"all-nodes\"  # every node of a tet10 or hex20 a particle: 7-8x the particles, half the spacing\n"
        }
        SecondOrder::Corners => "",
    };
    let refine = match case.refine {
        0 if case
            .mesh
            .solids()
            .all(|e| matches!(e.kind.linear(), ElementKind::Tet4 | ElementKind::Hex8)) =>
        {
            "# refine = 1              # cut each tet and hex into eight at its edges' midpoints: about 7x the particles, half the spacing\n".to_string()
        }
        0 => String::new(),
        n => format!("refine = {n}                # each tet and hex cut into eight at its edges' midpoints, {n} time(s)\n"),
    };
    let body = |name: &str, elements: &str| {
        let spacing_line = if elements.is_empty() || given_spacing.is_some() {
            spacing_line.clone()
        } else {
            "# spacing = Δ            # grid spacing: by default the lattice spacing of the part's particles' median volume\n".to_string()
        };
        format!(
            r#"[[body]]
name = "{name}"
mesh = "{mesh_ref}"
{elements}kind = "deformable"       # a PD body: particles, bonds, surface
{spacing_line}horizon_factor = {m}      # horizon δ = m Δ
kinematics = "small"      # small strain, as Hertz's theory and the estimate above; "finite" for large deformation
{second_order}{refine}# translate = [0.0, 0.0, 0.0]
# rotate = {{ axis = [0.0, 0.0, 1.0], angle_deg = 0.0 }}
# scale = 1.0
[body.material]
youngs_modulus = {youngs:e}   # E, Pa
poisson_ratio = {nu}          # bond-based PD fixes 1/4; another ν (steel 0.3, aluminium 0.33) needs the line below
# model = "lps"               # the linear peridynamic solid: any ν up to 0.49 (docs/guide/scene.md, "Bodies")
density = 1000.0              # kg/m3
"#,
            m = case.horizon_factor,
            nu = SKELETON_POISSON,
        )
    };
    // Six significant digits: 4.8e6, not the 4.799999999999983e6 of the sum it came from.
    let rounded = |f: f64| format!("{f:.5e}").parse::<f64>().unwrap_or(f);
    let penalty = skeleton.penalty_radius.map_or(String::new(), |r| format!(
        "radius = {r:e}     # penalty R of K = 4E*√R/3: a particle at the expected peak sinks at most {:.1} % of the contact's depth\n",
        100.0 * PENALTY_TARGET
    ));
    let parts = parts::parts(case);
    // The pieces no bond joins, found once for the solver and the pins.
    let pieces = solids(case);
    let solver = solver_block(parts.is_none() && pieces.1.len() < 2);
    let (bodies, rest) = match parts {
        Some(parts) => (
            parts
                .iter()
                .map(|p| body(&p.name, &parts::elements_line(&p.name)))
                .collect::<Vec<_>>()
                .join("\n"),
            parts::loads_contacts_pins(
                &parts,
                -skeleton.force,
                &skeleton.reason,
                &penalty,
                skeleton.penalty_radius,
                case.particles.spacing,
                rounded,
            ),
        ),
        None => (
            body("part", ""),
            format!(
                r#"[[load]]
body = "part"
# set = "top"             # a named node set; without it the force is spread over the whole body by volume
force = [0.0, 0.0, {fz:e}]  # total force, N: {reason}

[[contact]]
slave = "part"
master = "plane"
{penalty}
{pins}"#,
                fz = rounded(-skeleton.force),
                reason = skeleton.reason,
                pins = pins_and_pieces(case, skeleton, &pieces),
            ),
        ),
    };
    format!(
        r#"# pdcontact scene made by `pdcontact convert` for {mesh_name}.
# Run it with:  pdcontact run {case_path}
# Every key is documented in docs/guide/scene.md. Units are SI: metres, newtons, pascals, kg/m³.

{solver}
[output]
folder = "out"            # relative to this file
every = 500               # write a .vtu every N iterations (and the last one)

{bodies}
# Named sets of this mesh, usable as `set = "..."` in loads and constraints:
{sets}
[[body]]
name = "plane"
kind = "rigid"            # surface only: no particles, no bonds
generator = {{ shape = "plane", point = [{cx:e}, {cy:e}, {pz:e}], normal = [0.0, 0.0, 1.0], size = {plane_size:e} }}
motion = "fixed"

{rest}"#,
        mesh_name = mesh_path.display(),
        solver = solver,
        // Quoted where the shell would split it, so that the line can be pasted.
        case_path = {
            let p = out.join("case.toml").display().to_string();
            if p.contains(char::is_whitespace) {
                format!("\"{p}\"")
            } else {
                p
            }
        },
        cx = centre[0],
        cy = centre[1],
        pz = lo[2],
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
