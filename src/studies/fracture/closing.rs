//! A crack closed by its load (docs/FRACTURE.md, "Contact on new surfaces"): a block cut across
//! its whole section by a `[[precrack]]` and compressed across the cut, its two faces pressed
//! together by the body's contact with itself ([`crate::case::crack_faces`]), against the same
//! block whole; and the block cut at 30° to the load, whose frictionless faces slide.
//!
//! The block: a quarter of a 1 × 1 × 2 m block (the hex8 box generator, symmetry planes x = 0,
//! y = 0, z = 0), E = 1 GPa, ν = 1/4, 1 MPa on its top face, cut midway between the two particle
//! rows about z = 0.5 m. The inclined cut: half of the block (symmetry planes y = 0 and z = 0),
//! its top and bottom faces held along x, cut through its middle by a plane whose normal leans
//! 30° from the load; frictionless, its faces carry the load along their normal alone,
//! `N = P / cos 30°`.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::run_in;
use crate::body::PdBody;
use crate::error::Result;
use crate::math::Vec3;

/// The applied stress, Pa.
pub const STRESS: f64 = 1e6;

/// The contact that presses a body's crack faces together.
pub const SELF_CONTACT: &str = "[[contact]]\nslave = \"block\"\nmaster = \"block\"\n";

/// The quarter block at spacing `dx`, ADR to 1e-6 in at most `max_iterations`, with `extra`
/// appended.
pub fn block_scene(dx: f64, max_iterations: usize, extra: &str) -> String {
    format!(
        "[solver]\nkind = \"adr\"\ntolerance = 1e-6\nmax_iterations = {max_iterations}\n\
         [output]\nfolder = \".\"\nevery = 1000000\n\
         [[body]]\nname = \"block\"\n\
         generator = {{ shape = \"box\", min = [0, 0, 0], max = [0.5, 0.5, 1.0], spacing = {dx} }}\n\
         kinematics = \"small\"\n\
         material = {{ youngs_modulus = 1e9, poisson_ratio = 0.25, density = 1000 }}\n\
         [[symmetry]]\nbody = \"block\"\naxis = \"x\"\n\
         [[symmetry]]\nbody = \"block\"\naxis = \"y\"\n\
         [[symmetry]]\nbody = \"block\"\naxis = \"z\"\n\
         [[load]]\nbody = \"block\"\nset = \"top\"\nforce = [0, 0, {f:e}]\n{extra}",
        f = -STRESS * 0.25,
    )
}

/// The cut across the quarter block at spacing `dx`: between the rows about z = 0.5 m.
pub fn block_precrack(dx: f64) -> String {
    let z = ((0.5 / dx).round() + 0.5) * dx;
    format!(
        "[[precrack]]\nbody = \"block\"\npoint = [0.25, 0.25, {z}]\nnormal = [0, 0, 1]\nalong = [1, 0, 0]\nsize = [2, 2]\n"
    )
}

/// The height at x = 0 of the 30° cut at spacing `dx` (between particle rows there).
pub fn inclined_height(dx: f64) -> f64 {
    ((0.5 / dx).round() + 0.25) * dx
}

/// The half block cut at 30° to the load, at spacing `dx`; `cut = false`: the same block
/// whole.
pub fn inclined_scene(dx: f64, cut: bool) -> String {
    let z = inclined_height(dx);
    let (s, c) = 30f64.to_radians().sin_cos();
    let crack = if cut {
        format!(
            "[[precrack]]\nbody = \"block\"\npoint = [0, 0.25, {z}]\nnormal = [{s}, 0, {c}]\nalong = [0, 1, 0]\nsize = [2, 3]\n{SELF_CONTACT}"
        )
    } else {
        String::new()
    };
    format!(
        "[solver]\nkind = \"adr\"\ntolerance = 1e-6\nmax_iterations = 100000\n\
         [output]\nfolder = \".\"\nevery = 1000000\n\
         [[body]]\nname = \"block\"\n\
         generator = {{ shape = \"box\", min = [-0.5, 0, 0], max = [0.5, 0.5, 1.0], spacing = {dx} }}\n\
         kinematics = \"small\"\n\
         material = {{ youngs_modulus = 1e9, poisson_ratio = 0.25, density = 1000 }}\n\
         [[symmetry]]\nbody = \"block\"\naxis = \"y\"\n\
         [[symmetry]]\nbody = \"block\"\naxis = \"z\"\n\
         [[constraint]]\nbody = \"block\"\nset = \"top\"\nfix = [\"x\"]\n\
         [[constraint]]\nbody = \"block\"\nset = \"bottom\"\nfix = [\"x\"]\n\
         [[load]]\nbody = \"block\"\nset = \"top\"\nforce = [0, 0, {f:e}]\n{crack}",
        f = -STRESS * 0.5,
    )
}

/// Mean displacement along z of the particles on the top face z = 1 m.
pub fn top_displacement(pd: &PdBody) -> f64 {
    let top: Vec<usize> = (0..pd.len())
        .filter(|&i| (pd.reference[i].z - 1.0).abs() < 1e-9)
        .collect();
    top.iter().map(|&i| pd.u[i].z).sum::<f64>() / top.len() as f64
}

/// The slide of the 30° cut, m: the jump across the cut of the displacement along its
/// downhill direction (in the x-z plane), at the cut. On each side, over the particles within
/// two spacings of the cut and away from the block's sides (|x|, y < 0.4 m), the displacement
/// along the cut fitted by least squares as a line in the distance from the cut and taken
/// where that is nil. The particles stand back from the cut (half a spacing on the lattice, up
/// to 1.4 spacings on gmsh's tets) and the displacement along the cut changes across it by
/// about 2 % of the slide a spacing (the parts shear as they slide): a mean over the face
/// particles read 4-6 % short of the jump at the cut that an FE model's face nodes give
/// (docs/FRACTURE.md, "The 30° crack against CalculiX").
pub fn inclined_slide(pd: &PdBody) -> f64 {
    let f = &pd.crack_faces[0];
    slide_at(pd, f.point, f.normal)
}

/// [`inclined_slide`] across the plane through `point` with unit normal `normal` in the x-z
/// plane: the cut where the body keeps no faces of its own (a pre-crack's faces found again).
pub fn slide_at(pd: &PdBody, point: Vec3, normal: Vec3) -> f64 {
    let downhill = Vec3::new(normal.z, 0.0, -normal.x);
    let reach = 2.0 * pd.spacing();
    // Per side: n, Σd, Σd², Σu, Σdu.
    let mut sums = [[0.0f64; 5]; 2];
    for i in 0..pd.len() {
        let x = pd.reference[i];
        let d = normal.dot(&(x - point));
        if x.x.abs() < 0.4 && x.y < 0.4 && d != 0.0 && d.abs() < reach {
            let u = pd.u[i].dot(&downhill);
            let s = &mut sums[usize::from(d > 0.0)];
            for (k, v) in [1.0, d, d * d, u, d * u].into_iter().enumerate() {
                s[k] += v;
            }
        }
    }
    // The line's value at d = 0: (Σd² Σu − Σd Σdu) / (n Σd² − (Σd)²).
    let at_cut = |s: &[f64; 5]| (s[2] * s[3] - s[1] * s[4]) / (s[0] * s[2] - s[1] * s[1]);
    at_cut(&sums[1]) - at_cut(&sums[0])
}

/// The deepest penetration of one crack face into the other, m.
fn deepest(model: &crate::model::Model) -> f64 {
    model
        .passes
        .iter()
        .flat_map(|p| p.contacts.iter().map(|c| c.penetration))
        .fold(0.0, f64::max)
}

/// What the study measured.
#[derive(Clone, Debug, Serialize)]
pub struct ClosingResult {
    pub spacing: f64,
    pub particles: usize,
    /// ADR iterations and wall time of the whole and of the cut block.
    pub intact_iterations: usize,
    pub cut_iterations: usize,
    pub intact_seconds: f64,
    pub cut_seconds: f64,
    /// The top's mean displacement, m, whole and cut.
    pub intact_displacement: f64,
    pub cut_displacement: f64,
    /// Contact pressure over the applied stress on the faces' particles away from the free
    /// sides (x, y < 0.4 m) and off the symmetry planes: mean, least, most.
    pub pressure: [f64; 3],
    /// The force across each face over the load.
    pub face_force: f64,
    /// The deepest penetration of one face into the other, m.
    pub deepest: f64,
    pub fragments: usize,
    /// The 30° cut: the faces' normal force over `P / cos 30°`, the angle between their force
    /// and the crack's reference normal (degrees), ADR iterations and wall time.
    pub inclined_normal: f64,
    pub inclined_angle_deg: f64,
    pub inclined_iterations: usize,
    pub inclined_seconds: f64,
    /// The 30° cut: its particles, the top's mean displacement along z (m) cut and whole,
    /// and the slide ([`inclined_slide`], m).
    pub inclined_particles: usize,
    pub inclined_displacement: f64,
    pub inclined_whole_displacement: f64,
    pub inclined_slide: f64,
    pub folder: PathBuf,
}

impl ClosingResult {
    /// The printed table.
    pub fn to_text(&self) -> String {
        format!(
            concat!(
                "A crack closed by its load: a quarter of a 1 x 1 x 2 m block, hex8, Δ = {dx} m, {n} particles, 1 MPa across a cut through its whole section\n",
                "                      whole          cut\n",
                "ADR iterations  {ii:>12} {ci:>12}\n",
                "wall            {iw:>10.2} s {cw:>10.2} s\n",
                "top displacement {id:>9.4} mm {cd:>9.4} mm ({r:+.2} %)\n",
                "contact pressure on the faces away from the free sides: mean {pm:.3}, {p0:.3}-{p1:.3} of the applied stress; force across each face {ff:.5} of the load\n",
                "deepest penetration of one face into the other {dp:.2e} m ({dd:.1e} Δ); {fr} fragments\n",
                "cut at 30° to the load, frictionless: normal force {nr:.4} of P / cos 30°, its direction {ang:.2}° from the crack's normal; {ni} iterations, {nw:.2} s\n",
                "  top displacement {itop:.4} mm (whole {iwhole:.4} mm), the faces' slide along the cut {islide:.4} mm\n",
                "frames in {dir}\n",
            ),
            dx = self.spacing,
            n = self.particles,
            ii = self.intact_iterations,
            ci = self.cut_iterations,
            iw = self.intact_seconds,
            cw = self.cut_seconds,
            id = self.intact_displacement * 1e3,
            cd = self.cut_displacement * 1e3,
            r = (self.cut_displacement / self.intact_displacement - 1.0) * 100.0,
            pm = self.pressure[0],
            p0 = self.pressure[1],
            p1 = self.pressure[2],
            ff = self.face_force,
            dp = self.deepest,
            dd = self.deepest / self.spacing,
            fr = self.fragments,
            nr = self.inclined_normal,
            ang = self.inclined_angle_deg,
            ni = self.inclined_iterations,
            nw = self.inclined_seconds,
            itop = self.inclined_displacement * 1e3,
            iwhole = self.inclined_whole_displacement * 1e3,
            islide = self.inclined_slide * 1e3,
            dir = self.folder.display(),
        )
    }
}

/// Runs the whole block, the cut one, the 30° cut and its block whole at spacing `dx` into
/// `folder`'s `whole`, `cut`, `inclined` and `inclined_whole`.
pub fn run_closing(dx: f64, folder: &Path, quiet: bool) -> Result<ClosingResult> {
    let (whole, s0, intact_seconds) =
        run_in(&block_scene(dx, 100_000, ""), &folder.join("whole"), quiet)?;
    let cut_text = block_scene(dx, 100_000, &(block_precrack(dx) + SELF_CONTACT));
    let (cut, s1, cut_seconds) = run_in(&cut_text, &folder.join("cut"), quiet)?;
    let (a, b) = (
        whole.bodies[0].as_pd().expect("deformable"),
        cut.bodies[0].as_pd().expect("deformable"),
    );
    let faces = &b.crack_faces[0];
    let mut pressures = Vec::new();
    // The face whose force is the further from the load's.
    let mut face_force: f64 = 1.0;
    for side in &faces.particles {
        let f: f64 = side.iter().map(|&i| b.contact_force[i as usize].z).sum();
        let r = f.abs() / (STRESS * 0.25);
        if (r - 1.0).abs() > (face_force - 1.0).abs() {
            face_force = r;
        }
        for &i in side {
            let (i, x) = (i as usize, b.reference[i as usize]);
            if (0.01..0.4).contains(&x.x) && (0.01..0.4).contains(&x.y) {
                pressures.push(b.pressure_force(i) / b.case.segments.pressure_area[i] / STRESS);
            }
        }
    }
    let mean = pressures.iter().sum::<f64>() / pressures.len().max(1) as f64;
    let least = pressures.iter().copied().fold(f64::INFINITY, f64::min);
    let most = pressures.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let fragments = b
        .fracture
        .as_ref()
        .map_or(1, |f| f.fragments(&b.case.bonds).len());

    let (tilted, s2, inclined_seconds) =
        run_in(&inclined_scene(dx, true), &folder.join("inclined"), quiet)?;
    let (tilted_whole, _, _) = run_in(
        &inclined_scene(dx, false),
        &folder.join("inclined_whole"),
        quiet,
    )?;
    let t = tilted.bodies[0].as_pd().expect("deformable");
    let n = t.crack_faces[0].normal;
    let f: Vec3 = t.crack_faces[0].particles[0]
        .iter()
        .map(|&i| t.contact_force[i as usize])
        .sum();
    let expected = STRESS * 0.5 / 30f64.to_radians().cos();
    Ok(ClosingResult {
        spacing: dx,
        particles: b.len(),
        intact_iterations: s0.iterations,
        cut_iterations: s1.iterations,
        intact_seconds,
        cut_seconds,
        intact_displacement: top_displacement(a),
        cut_displacement: top_displacement(b),
        pressure: [mean, least, most],
        face_force,
        deepest: deepest(&cut),
        fragments,
        inclined_normal: -f.dot(&n) / expected,
        inclined_angle_deg: (f.dot(&n).abs() / f.norm()).min(1.0).acos().to_degrees(),
        inclined_iterations: s2.iterations,
        inclined_seconds,
        inclined_particles: t.len(),
        inclined_displacement: top_displacement(t),
        inclined_whole_displacement: top_displacement(
            tilted_whole.bodies[0].as_pd().expect("deformable"),
        ),
        inclined_slide: inclined_slide(t),
        folder: folder.to_path_buf(),
    })
}
