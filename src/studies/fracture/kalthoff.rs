//! The Kalthoff-Winkler experiment (Kalthoff 2000; METHOD.md §9): a maraging steel plate,
//! 200 × 100 × 9 mm, with two edge notches 50 mm long and 50 mm apart, hit on its edge between
//! them by a steel projectile at 32 m/s. The cracks leave the notch tips at about 70° to the
//! notch direction (PD papers: 65-70°).
//!
//! The model: half the plate (a symmetry plane between the notches) and half its thickness
//! (a symmetry plane at mid-thickness), the notch a `[[precrack]]`; the projectile a
//! deformable steel bar 125 mm long and as thick as the plate, as wide as the notches' near
//! faces are apart (48.5 mm: the notches are 1.5 mm wide, the projectile's 50 mm reach their
//! middles; a precrack has no width, and a corner pressed into it would meet no face), given
//! 32 m/s and pressed on the plate through the point-to-surface contact (both ways), so that
//! the load is the contact's, not a velocity imposed on the plate's particles. Explicit
//! dynamics for 90 µs.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::run_in;
use crate::error::Result;
use crate::math::Vec3;

/// The notch tip, where the crack starts (x along the notch from the hit edge, y across).
const TIP: [f64; 2] = [0.05, 0.025];
/// Simulated time, s.
pub const END_TIME: f64 = 9e-5;
/// How far from the tip the angle at which the crack leaves it is measured, m: a quarter of the
/// plate's depth, where a crack on the coarser plates has not yet bent.
const LEAVING: f64 = 0.025;

/// One plate: its particle spacing.
#[derive(Clone, Debug)]
pub struct KalthoffPlate {
    /// Grid spacing Δ, m (the horizon is 3Δ), of the plate and of the projectile.
    pub spacing: f64,
    /// Simulated time, s.
    pub end_time: f64,
}

impl KalthoffPlate {
    /// The scene.
    pub fn scene(&self, folder: &str) -> String {
        let dx = self.spacing;
        format!(
            "# Kalthoff-Winkler: a notched steel plate hit between its notches at 32 m/s.\n\
             [solver]\nkind = \"explicit\"\nend_time = {end}\n\n\
             [output]\nfolder = \"{folder}\"\nevery = 50\n\n\
             [[body]]\nname = \"plate\"\n\
             generator = {{ shape = \"box\", min = [0, 0, 0], max = [0.1, 0.1, 0.0045], spacing = {dx} }}\n\
             material = {{ youngs_modulus = 190e9, poisson_ratio = 0.25, density = 8000, fracture_energy = 22170 }}\n\n\
             [[symmetry]]\nbody = \"plate\"\naxis = \"y\"\n\
             [[symmetry]]\nbody = \"plate\"\naxis = \"z\"\n\n\
             # The notch: 50 mm from the hit edge, 25 mm from the plate's middle.\n\
             [[precrack]]\nbody = \"plate\"\npoint = [0.025, 0.025, 0]\nnormal = [0, 1, 0]\nalong = [1, 0, 0]\nsize = [0.05, 1.0]\n\n\
             [[body]]\nname = \"projectile\"\n\
             generator = {{ shape = \"box\", min = [-0.1251, 0, 0], max = [-0.0001, 0.02425, 0.0045], spacing = {dx} }}\n\
             material = {{ youngs_modulus = 190e9, poisson_ratio = 0.25, density = 8000 }}\n\
             velocity = [32, 0, 0]\n\n\
             [[symmetry]]\nbody = \"projectile\"\naxis = \"y\"\n\
             [[symmetry]]\nbody = \"projectile\"\naxis = \"z\"\n\n\
             # A flat face on a flat edge at 32 m/s: R = Δ, twice a point contact's default, so\n\
             # that the projectile's corner does not sink through the plate's damaged edge.\n\
             [[contact]]\nslave = \"plate\"\nmaster = \"projectile\"\ntwo_pass = true\nradius = {r}\n",
            end = self.end_time,
            r = dx,
        )
    }
}

/// What a plate gave.
#[derive(Clone, Debug, Serialize)]
pub struct KalthoffResult {
    pub spacing: f64,
    pub horizon: f64,
    pub particles: usize,
    /// The crack from the notch tip: the direction of the damaged particles (damage ≥ 0.35)
    /// past the tip on the side away from the hit zone, as the angle to the notch direction
    /// (degrees; the experiment about 70°), from the principal axis of their positions about
    /// the tip; how many particles that is, and how far along the notch direction it reached
    /// (m from the hit edge; the plate is 0.1 m deep).
    pub crack_angle_deg: f64,
    /// The same over the damaged particles within [`LEAVING`] of the tip: the angle at which
    /// the crack leaves it (degrees).
    pub leaving_angle_deg: f64,
    pub crack_particles: usize,
    pub crack_reach: f64,
    /// Damaged particles (≥ 0.35) elsewhere: between the plate's middle and the notch's line
    /// past the tip (cracks the experiment does not show).
    pub other_damaged: usize,
    pub broken_bonds: usize,
    pub fragments: usize,
    pub steps: usize,
    pub wall_seconds: f64,
    pub folder: PathBuf,
}

impl KalthoffResult {
    /// The table a person reads.
    pub fn to_text(&self) -> String {
        format!(
            concat!(
                "Kalthoff-Winkler plate, Δ = {dx} mm, δ = {d:.1} mm, {n} particles (plate and projectile)\n",
                "crack from the notch tip at {a:.1}° to the notch, leaving it at {l:.1}° (its first 25 mm; experiment about 70°, PD papers 65-70°), {c} damaged particles, reaching {r:.1} mm of the 100 mm plate\n",
                "{o} damaged particles off that crack; {b} bonds broken, {f} fragments; {s} steps, {w:.1} s; frames in {dir}\n",
            ),
            dx = self.spacing * 1e3,
            d = self.horizon * 1e3,
            n = self.particles,
            a = self.crack_angle_deg,
            l = self.leaving_angle_deg,
            c = self.crack_particles,
            r = self.crack_reach * 1e3,
            o = self.other_damaged,
            b = self.broken_bonds,
            f = self.fragments,
            s = self.steps,
            w = self.wall_seconds,
            dir = self.folder.display(),
        )
    }
}

/// Runs `plate` into `folder` and measures its crack.
pub fn run_kalthoff(plate: &KalthoffPlate, folder: &Path, quiet: bool) -> Result<KalthoffResult> {
    let (model, summary, wall_seconds) = run_in(&plate.scene("."), folder, quiet)?;
    let pd = model
        .bodies
        .iter()
        .find_map(|b| b.as_pd())
        .expect("the plate is deformable");
    let tip = Vec3::new(TIP[0], TIP[1], 0.0);
    let (mut whole, mut leaving) = ([[0.0f64; 2]; 2], [[0.0f64; 2]; 2]);
    let (mut count, mut reach, mut other) = (0, 0.0f64, 0);
    for i in 0..pd.len() {
        let x = pd.case.particles.position[i];
        if pd.damage(i) < 0.35 || x.x <= TIP[0] + pd.spacing() {
            continue;
        }
        if x.y > TIP[1] {
            let p = [x.x - tip.x, x.y - tip.y];
            add_moment(&mut whole, p);
            if p[0].hypot(p[1]) <= LEAVING {
                add_moment(&mut leaving, p);
            }
            count += 1;
            reach = reach.max(x.x);
        } else {
            other += 1;
        }
    }
    let f = summary.fracture.first();
    Ok(KalthoffResult {
        spacing: plate.spacing,
        horizon: pd.case.horizon,
        particles: summary.particles,
        crack_angle_deg: principal_angle(&whole),
        leaving_angle_deg: principal_angle(&leaving),
        crack_particles: count,
        crack_reach: reach,
        other_damaged: other,
        broken_bonds: f.map_or(0, |f| f.broken_bonds),
        fragments: f.map_or(0, |f| f.fragments),
        steps: summary.iterations,
        wall_seconds,
        folder: folder.to_path_buf(),
    })
}

/// Adds a point's second moment about the tip.
fn add_moment(m: &mut [[f64; 2]; 2], p: [f64; 2]) {
    for a in 0..2 {
        for b in 0..2 {
            m[a][b] += p[a] * p[b];
        }
    }
}

/// The principal axis of a 2×2 second moment as an angle to the notch direction (x), in
/// [0°, 180°): the crack points away from the hit edge.
fn principal_angle(m: &[[f64; 2]; 2]) -> f64 {
    let angle = 0.5 * (2.0 * m[0][1]).atan2(m[0][0] - m[1][1]);
    angle.to_degrees().rem_euclid(180.0)
}
