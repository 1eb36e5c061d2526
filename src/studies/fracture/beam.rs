//! A notched three-point bend beam broken under displacement control
//! against linear elastic fracture mechanics (METHOD.md §9, docs/FRACTURE.md).
//!
//! ASTM E399 proportions: height W, span S = 4W, notch depth a = W/2. The beam lies on two
//! rigid rollers and a third roller is driven down onto its middle, all through the
//! point-to-surface contact; the notch is a `[[precrack]]` through the thickness. LEFM's peak
//! load is `P = K_Ic B W^{3/2} / (S f(a/W))` with `K_Ic = sqrt(E' G0)`.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::run_in;
use crate::error::Result;
use crate::run::LOAD_DISPLACEMENT_NAME;

/// The beam's height W, m.
pub const HEIGHT: f64 = 0.04;
/// Young's modulus, Pa, and the fracture energy, J/m² (a PMMA-like polymer; K_Ic ≈ 0.95
/// MPa √m).
pub const YOUNGS: f64 = 3e9;
pub const FRACTURE_ENERGY: f64 = 300.0;
/// The rollers' radius, m.
const ROLLER: f64 = 0.005;

/// `f(a/W)` of the single-edge notched bend specimen, S = 4W (METHOD.md §9).
pub fn shape_factor(x: f64) -> f64 {
    3.0 * x.sqrt() * (1.99 - x * (1.0 - x) * (2.15 - 3.93 * x + 2.7 * x * x))
        / (2.0 * (1.0 + 2.0 * x) * (1.0 - x).powf(1.5))
}

/// LEFM's peak load of a beam of thickness `thickness`, N, with `K_Ic = sqrt(E' G0)`.
pub fn lefm_peak_load(e_prime: f64, fracture_energy: f64, thickness: f64) -> f64 {
    let k = (e_prime * fracture_energy).sqrt();
    let (w, s) = (HEIGHT, 4.0 * HEIGHT);
    k * thickness * w.powf(1.5) / (s * shape_factor(0.5))
}

/// The static solver's beam held along its length at the particle under the striker. On
/// frictionless rollers, pressed from above, the beam sliding along its length lowers it on
/// both rollers: the symmetric state is unstable along x. ADR's path keeps the symmetry of
/// the scene to the bit and stays there; Newton's inexact steps do not, and the beam slid 1 mm
/// off at a quarter of the travel. By symmetry the particle under the striker hardly moves
/// along x in the symmetric state.
const PIN: &str = "# The beam held along its length under the striker (frictionless rollers leave it free to slide).\n\
                   [[constraint]]\nbody = \"beam\"\nnearest = [0.0, 0.0, 0.04]\nfix = [\"x\"]\n\n";

/// One beam: its particle spacing, thickness, and the drive.
#[derive(Clone, Debug)]
pub struct NotchedBeam {
    /// Grid spacing Δ, m (the horizon is 3Δ).
    pub spacing: f64,
    /// Thickness B, m (half of it is modelled, with a symmetry plane at mid-thickness).
    pub thickness: f64,
    /// The loading roller's whole travel, m, in `steps` increments.
    pub displacement: f64,
    pub steps: usize,
    /// The beam as a mesh with its notch cut out as a slot (`tools/gmsh_beam.py`), in place
    /// of the box generator and the `[[precrack]]`; `spacing` is then the mesh's.
    pub mesh: Option<PathBuf>,
    /// The static solver instead of ADR (its bonds tested near each equilibrium).
    pub static_solver: bool,
    /// The linear peridynamic solid with this Poisson's ratio (its critical stretch from the
    /// same fracture energy, [`crate::body::fracture::critical_stretch_lps`]) instead of the
    /// bond-based model (ν = 1/4).
    pub lps_poisson: Option<f64>,
    /// What fails a bond past its critical stretch (`[body.material] failure`).
    pub failure: crate::scene::FailureCriterion,
}

impl NotchedBeam {
    /// The scene: the whole span (a crack on a symmetry plane cannot open), half the
    /// thickness.
    pub fn scene(&self, folder: &str) -> String {
        let (w, s) = (HEIGHT, 4.0 * HEIGHT);
        let half_length = 0.5 * s + 2.0 * ROLLER;
        let (body, notch) = match &self.mesh {
            // The mesh's slot is the notch: the bonds across it go with the case
            // (`case::sight`).
            Some(m) => (format!("mesh = {:?}", m.display().to_string()), String::new()),
            None => (
                format!(
                    "generator = {{ shape = \"box\", min = [{x0}, 0, 0], max = [{half_length}, {b}, {w}], spacing = {dx} }}",
                    x0 = -half_length,
                    b = 0.5 * self.thickness,
                    dx = self.spacing,
                ),
                format!(
                    "# The notch: bonds across x = 0 from the bottom face up to a = W/2 removed.\n\
                     [[precrack]]\nbody = \"beam\"\npoint = [0, 0, {ac}]\nnormal = [1, 0, 0]\nalong = [0, 0, 1]\nsize = [{a}, 1.0]\n\n",
                    ac = 0.25 * w,
                    a = 0.5 * w,
                ),
            ),
        };
        self.scene_with(folder, &body, &notch)
    }

    /// The beam's Poisson's ratio.
    pub fn poisson(&self) -> f64 {
        self.lps_poisson.unwrap_or(0.25)
    }

    fn scene_with(&self, folder: &str, body: &str, notch: &str) -> String {
        let (w, s) = (HEIGHT, 4.0 * HEIGHT);
        let r = ROLLER;
        let roller = |name: &str, x: f64, z: f64, extra: &str| {
            format!(
                "[[body]]\nname = \"{name}\"\nkind = \"rigid\"\ngenerator = {{ shape = \"cylinder\", radius = {r}, length = {len}, spacing = {sp}, center = [{x}, 0, {z}] }}\n{extra}\n[[contact]]\nslave = \"beam\"\nmaster = \"{name}\"\n\n",
                len = 4.0 * self.thickness,
                sp = r / 4.0,
            )
        };
        format!(
            "# A notched three-point bend beam (ASTM E399: S = 4W, a/W = 0.5) broken under displacement control.\n\
             [solver]\nkind = \"{kind}\"\nload_steps = {steps}\nmax_iterations = 1000000\n\n\
             [output]\nfolder = \"{folder}\"\nevery = 100000\n\n\
             [[body]]\nname = \"beam\"\n\
             {body}\n\
             kinematics = \"small\"\n{skin}\
             material = {{ youngs_modulus = {YOUNGS:e}, poisson_ratio = {nu}, density = 1200, fracture_energy = {FRACTURE_ENERGY}{model}{failure} }}\n\n\
             [[symmetry]]\nbody = \"beam\"\naxis = \"y\"\n\n\
             {notch}{pin}{left}{right}{striker}",
            kind = if self.static_solver { "static" } else { "adr" },
            nu = self.poisson(),
            // The LPS's skin correction (for contact pressure) stiffens a slender body: on this
            // beam, 8 mm thick against a 6 mm horizon, every particle is within a horizon of a
            // face, and with it the beam came out 1.6 times as stiff and its peak +57 %
            // (docs/FRACTURE.md, "The linear peridynamic solid").
            skin = if self.lps_poisson.is_some() {
                "skin_correction = false\n"
            } else {
                ""
            },
            model = if self.lps_poisson.is_some() {
                ", model = \"lps\""
            } else {
                ""
            },
            failure = match self.failure {
                crate::scene::FailureCriterion::Stretch => "",
                crate::scene::FailureCriterion::Tension => ", failure = \"tension\"",
            },
            pin = if self.static_solver { PIN } else { "" },
            steps = self.steps,
            left = roller("left", -0.5 * s, -r, ""),
            right = roller("right", 0.5 * s, -r, ""),
            striker = roller(
                "striker",
                0.0,
                w + r,
                &format!(
                    "motion = \"displacement\"\ndisplacement = [0, 0, {}]\n",
                    -self.displacement
                )
            ),
        )
    }
}

/// What a beam gave.
#[derive(Clone, Debug, Serialize)]
pub struct BeamResult {
    /// `"bond-based"` or `"lps"`, and Poisson's ratio.
    pub model: String,
    pub poisson: f64,
    pub spacing: f64,
    pub horizon: f64,
    pub thickness: f64,
    pub particles: usize,
    /// Peak of the reaction on the loading roller over the increments (the whole beam's, both
    /// halves of the thickness), N, and the displacement where it came.
    pub peak_load: f64,
    pub peak_displacement: f64,
    /// LEFM's peak in plane stress (E' = E) and plane strain (E' = E/(1 − ν²)), N.
    pub lefm_plane_stress: f64,
    pub lefm_plane_strain: f64,
    /// The load at the last increment against the peak: below 1 once the beam softens.
    pub last_over_peak: f64,
    /// The crack's reach: the highest particle with damage ≥ 0.3 within 2δ of the notch's
    /// plane that a chain of such particles, none more than 2Δ above the last, joins to the
    /// notch tip, m above the bottom face; and the farthest of the chain from that plane, m.
    pub crack_tip_height: f64,
    pub crack_offset: f64,
    pub broken_bonds: usize,
    /// The solver (`"adr"` or `"static"`) and its iterations (Newton's for the static one).
    pub solver: String,
    pub iterations: usize,
    pub wall_seconds: f64,
    /// The load-displacement chart.
    pub chart: PathBuf,
}

impl BeamResult {
    /// The table a person reads.
    pub fn to_text(&self) -> String {
        let pct = |p: f64| 100.0 * (self.peak_load / p - 1.0);
        format!(
            concat!(
                "notched three-point bend beam, W = {w} mm, B = {b} mm, a/W = 0.5, {model} ν = {nu}: Δ = {dx:.3} mm, δ = {d:.2} mm (a/δ = {ad:.1}), {n} particles\n",
                "peak load {p:.1} N at {u:.3} mm; LEFM {ps:.1} N in plane stress ({e1:+.1} %), {pe:.1} N in plane strain ({e2:+.1} %)\n",
                "after the peak the load fell to {soft:.0} % of it; crack tip {tip:.1} mm above the bottom face (notch tip {a} mm), at most {off:.1} mm off the notch's plane\n",
                "{bonds} bonds broken, {it} {word}, {wall:.1} s; chart {chart}\n",
            ),
            w = HEIGHT * 1e3,
            model = self.model,
            nu = self.poisson,
            b = self.thickness * 1e3,
            dx = self.spacing * 1e3,
            d = self.horizon * 1e3,
            ad = 0.5 * HEIGHT / self.horizon,
            n = self.particles,
            p = self.peak_load,
            u = self.peak_displacement * 1e3,
            ps = self.lefm_plane_stress,
            e1 = pct(self.lefm_plane_stress),
            pe = self.lefm_plane_strain,
            e2 = pct(self.lefm_plane_strain),
            soft = 100.0 * self.last_over_peak,
            tip = self.crack_tip_height * 1e3,
            a = 0.5 * HEIGHT * 1e3,
            off = self.crack_offset * 1e3,
            bonds = self.broken_bonds,
            it = self.iterations,
            word = if self.solver == "static" {
                "Newton iterations (static solver)"
            } else {
                "ADR iterations"
            },
            wall = self.wall_seconds,
            chart = self.chart.display(),
        )
    }
}

/// Runs `beam` into `folder` and measures it.
pub fn run_beam(beam: &NotchedBeam, folder: &Path, quiet: bool) -> Result<BeamResult> {
    let mut beam = beam.clone();
    if let Some(m) = &beam.mesh {
        beam.mesh = Some(std::fs::canonicalize(m).map_err(|e| {
            crate::error::Error::input(format!("{}: cannot read the beam mesh: {e}", m.display()))
        })?);
    }
    let (model, summary, wall_seconds) = run_in(&beam.scene("."), folder, quiet)?;
    // Half the thickness is modelled: the whole beam carries twice the reaction.
    let (peak_load, peak_displacement) = summary
        .solver
        .increments
        .iter()
        .map(|s| (2.0 * s.reaction[2], -s.displacement[2]))
        .fold((0.0, 0.0), |a, b| if b.0 > a.0 { b } else { a });
    let last = summary
        .solver
        .increments
        .last()
        .map_or(0.0, |s| 2.0 * s.reaction[2]);
    let pd = model
        .bodies
        .iter()
        .find_map(|b| b.as_pd())
        .expect("the beam is deformable");
    let horizon = pd.case.horizon;
    // The crack: damaged particles (≥ 0.3, a particle beside an open crack has lost about
    // half its family) near the notch's plane, followed up from the notch tip while each is
    // within two spacings of the last; damage under the loading roller, apart from it, is
    // not the crack.
    let mut column: Vec<(f64, f64)> = (0..pd.len())
        .map(|i| (pd.case.particles.position[i], pd.damage(i)))
        .filter(|(x, d)| *d >= 0.3 && x.x.abs() <= 2.0 * horizon && x.z > 0.5 * HEIGHT)
        .map(|(x, _)| (x.z, x.x.abs()))
        .collect();
    column.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (mut tip, mut offset) = (0.5 * HEIGHT, 0.0f64);
    for (z, off) in column {
        if z > tip + 2.0 * pd.spacing() {
            break;
        }
        tip = tip.max(z);
        offset = offset.max(off);
    }
    let nu = beam.poisson();
    Ok(BeamResult {
        model: if beam.lps_poisson.is_some() {
            "lps"
        } else {
            "bond-based"
        }
        .to_string(),
        poisson: nu,
        spacing: if beam.mesh.is_some() {
            pd.spacing()
        } else {
            beam.spacing
        },
        horizon,
        thickness: beam.thickness,
        particles: summary.particles,
        peak_load,
        peak_displacement,
        lefm_plane_stress: lefm_peak_load(YOUNGS, FRACTURE_ENERGY, beam.thickness),
        lefm_plane_strain: lefm_peak_load(
            YOUNGS / (1.0 - nu * nu),
            FRACTURE_ENERGY,
            beam.thickness,
        ),
        last_over_peak: if peak_load > 0.0 {
            last / peak_load
        } else {
            0.0
        },
        crack_tip_height: tip,
        crack_offset: offset,
        broken_bonds: summary.fracture.first().map_or(0, |f| f.broken_bonds),
        solver: summary.solver.solver.clone(),
        iterations: summary.iterations,
        wall_seconds,
        chart: folder.join(LOAD_DISPLACEMENT_NAME),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shape_factor_at_half_depth() {
        // ASTM E399's tabulated f(0.5) = 2.66.
        assert!(
            (shape_factor(0.5) - 2.66).abs() < 0.005,
            "{}",
            shape_factor(0.5)
        );
    }
}
