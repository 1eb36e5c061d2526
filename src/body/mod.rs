//! Bodies of a scene: deformable PD bodies (particles and bonds) and rigid surfaces
//! (METHOD.md §4-6).
//!
//! A deformable body stores, per directed bond, the partner, the reference length `L` and the
//! weight `w = c G v_c V_i V_j / L` (N/m), so that the bond's force on particle `i` is
//! `w (|y| − L) y/|y|` with `y` the deformed bond: Eq. 26 (`c s n`) times the volumes, with the
//! surface factor `G` and the volume correction `v_c` folded in once. Because `G` and `v_c` are
//! symmetric, `w_ij = w_ji`: internal forces are equal and opposite and sum to zero.
//!
//! This module holds the body types; `build.rs` builds them from a scene ([`build_body`]).

mod build;
pub mod facing;
pub mod fracture;
pub mod lps;
pub mod new_faces;
pub mod new_surface;
pub mod stress;

pub use crate::case::crack_faces::CrackFaces;
pub use build::{body_mesh, build_body, build_body_on, clip_mesh};
pub use fracture::Fracture;
pub use lps::Lps;

use crate::case::correction::micromodulus;
use crate::case::pairs::{ForceBuffers, PairList};
use crate::case::segments::MasterSegment;
use crate::case::PdCase;
use crate::math::Vec3;
use crate::scene::{InfluenceFunction, Kinematics, MaterialModel, Motion};

/// Linear elastic material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    pub youngs: f64,
    pub poisson: f64,
    pub density: f64,
    /// Bond-based or the linear peridynamic solid.
    pub model: MaterialModel,
    /// The linear peridynamic solid's influence function.
    pub influence: InfluenceFunction,
}

impl Material {
    /// `m = (1 − ν²)/E` of Eq. 24.
    pub fn compliance(&self) -> f64 {
        (1.0 - self.poisson * self.poisson) / self.youngs
    }

    /// Lamé's constants `(λ, μ)` of E and ν.
    pub fn lame(&self) -> (f64, f64) {
        let (e, nu) = (self.youngs, self.poisson);
        (
            e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
            e / (2.0 * (1.0 + nu)),
        )
    }
}

/// Bit mask of fixed displacement components.
pub type FixMask = u8;
/// x fixed.
pub const FIX_X: FixMask = 1;
/// y fixed.
pub const FIX_Y: FixMask = 2;
/// z fixed.
pub const FIX_Z: FixMask = 4;

/// A deformable PD body and its state.
#[derive(Clone, Debug)]
pub struct PdBody {
    pub name: String,
    pub case: PdCase,
    pub material: Material,
    /// Bond kinematics.
    pub kinematics: Kinematics,
    /// Reference positions of the particles followed by their mirror images.
    pub reference: Vec<Vec3>,
    /// Micromodulus `c`.
    pub micromodulus: f64,
    /// Per directed bond: `c G v_c V_i V_j / L`, N/m; for an LPS body the stiffness that
    /// bounds its tangent's row ([`Lps::bond_stiffness`]), which sizes the solvers' steps.
    pub bond_weight: Vec<f32>,
    /// The linear peridynamic solid's data where the material is `model = "lps"`: its
    /// forces replace the bond-based pass over `pairs`.
    pub lps: Option<Lps>,
    /// Per particle: `Σ_j w_ij`, the sum of its bond stiffnesses (N/m).
    pub stiffness: Vec<f64>,
    /// The bonds each pair once, with their weights: what the force pass walks.
    pub pairs: PairList,
    /// Per-thread scratch of the force pass.
    pub force_buffers: ForceBuffers,
    /// `ρ V_i`.
    pub mass: Vec<f64>,
    /// Fixed components per particle (supports and symmetry planes).
    pub fixed: Vec<FixMask>,
    /// The components of `fixed` that symmetry planes hold (not supports).
    pub symmetric: Vec<FixMask>,
    /// Applied force per particle, N.
    pub load: Vec<Vec3>,
    /// Displacement.
    pub u: Vec<Vec3>,
    /// Velocity.
    pub v: Vec<Vec3>,
    /// Total force (internal + applied + contact), N.
    pub force: Vec<Vec3>,
    /// Contact force alone, N.
    pub contact_force: Vec<Vec3>,
    /// The part of `contact_force` this body takes as a deformable master: the reactions of
    /// other bodies' slaves spread on its nodes by the segments' shape functions (Eq. 20's
    /// weights), which lump a traction by tributary area, where a slave's own force goes by
    /// volume ([`PdBody::pressure_force`]).
    pub reaction_force: Vec<Vec3>,
    /// Extra stiffness from contact, for ADR's fictitious density (N/m): the tangent of each
    /// contact at its penetration ([`crate::contact::ContactLaw::relaxation_stiffness`]).
    pub contact_stiffness: Vec<f64>,
    /// The particles this process moves: all of them, or one rank's range in a decomposed
    /// run ([`crate::model::domain`]).
    pub owned: std::ops::Range<usize>,
    /// The bonds' failure state, where bonds may fail or a pre-crack cut some
    /// ([`fracture`]); `None`: every bond holds for good.
    pub fracture: Option<Fracture>,
    /// Friction's part of the contact forces, where the body is in a pair with friction
    /// (METHOD.md §10); `None` otherwise.
    pub friction: Option<FrictionForces>,
    /// The faces of its pre-cracks, where the body is its own contact master
    /// ([`crate::case::crack_faces`]); empty otherwise.
    pub crack_faces: Vec<CrackFaces>,
    /// The particle pairs each `[[precrack]]` parted ([`PdBody::crossed_crack`]).
    pub precrack_pairs: Vec<crate::case::crack_faces::PartedPairs>,
    /// Where the body is pressed on the faces its broken bonds opened: the pressure areas
    /// as built (`case.segments.pressure_area` then holds the new faces' areas where they
    /// have some, [`PdBody::set_opened_faces`]) and the surface's normals, found again ones
    /// included.
    pub opened: Option<(Vec<f64>, Vec<Vec3>)>,
    /// Where it is pressed on the faces found again of its pre-cracks: per particle, the share
    /// of its bonds across a crack's plane that the pre-cracks cut (1 through the body, less
    /// at a front inside it; [`crate::case::crack_faces::CrackFaces::share`]), by which its
    /// penalty is scaled as on a pre-crack's own faces; empty otherwise.
    pub crack_share: std::sync::Arc<Vec<f64>>,
}

/// A body's friction forces in the last evaluation, per particle.
#[derive(Clone, Debug, Default)]
pub struct FrictionForces {
    /// The tangential part of `contact_force`, N.
    pub force: Vec<Vec3>,
    /// The part of `force` that reactions as a master brought.
    pub reaction: Vec<Vec3>,
    /// As a slave: 1 sticking, 0 slipping, −1 not in contact.
    pub stick: Vec<i8>,
}

impl FrictionForces {
    /// Zeroed for `n` particles.
    pub fn new(n: usize) -> FrictionForces {
        FrictionForces {
            force: vec![Vec3::zeros(); n],
            reaction: vec![Vec3::zeros(); n],
            stick: vec![-1; n],
        }
    }

    /// Zeroes the forces and the states before an evaluation.
    pub fn reset(&mut self) {
        self.force.iter_mut().for_each(|f| *f = Vec3::zeros());
        self.reaction.iter_mut().for_each(|f| *f = Vec3::zeros());
        self.stick.iter_mut().for_each(|s| *s = -1);
    }
}

impl PdBody {
    /// The normal contact force of particle `i` as its pressure area `A*_i` carries it
    /// ([`pressure_areas`](crate::case::segments::pressure_areas)): a slave's own force, taken
    /// by volume, as it is; a master's reactions, which Eq. 20's shape functions lump by the
    /// tributary area `A_i` (`F_a = ∫ N_a p dA ≈ p A_a`), scaled by `A*_i / A_i`, so that
    /// `pressure_force / A*_i` is the traction on either side of a pair.
    /// With friction, its tangential part is left out: the normal force alone.
    pub fn pressure_force(&self, i: usize) -> f64 {
        let (t, tr) = self
            .friction
            .as_ref()
            .map_or((Vec3::zeros(), Vec3::zeros()), |f| {
                (f.force[i], f.reaction[i])
            });
        let reaction = self.reaction_force[i] - tr;
        if reaction == Vec3::zeros() {
            return (self.contact_force[i] - t).norm();
        }
        let scale = self.reaction_scale(i);
        (self.contact_force[i] - t - reaction + reaction * scale).norm()
    }

    /// `A*_i / A_i`: what turns a master's reactions, lumped by tributary area, into the
    /// force of its pressure area ([`Self::pressure_force`]).
    fn reaction_scale(&self, i: usize) -> f64 {
        let tributary = self.case.segments.tributary_area[i];
        // The areas as built: the tributary areas are of the segments as built.
        let area = match &self.opened {
            Some((built, _)) => built[i],
            None => self.case.segments.pressure_area[i],
        };
        if tributary > 0.0 {
            area / tributary
        } else {
            1.0
        }
    }

    /// Friction's force on particle `i` as its pressure area carries it (the reactions
    /// scaled as in [`Self::pressure_force`]): over `A*_i`, the shear traction (zero without
    /// friction).
    pub fn friction_force(&self, i: usize) -> Vec3 {
        let Some(f) = &self.friction else {
            return Vec3::zeros();
        };
        f.force[i] - f.reaction[i] + f.reaction[i] * self.reaction_scale(i)
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.u.len()
    }

    /// True without particles.
    pub fn is_empty(&self) -> bool {
        self.u.is_empty()
    }

    /// Current position of particle `i`.
    #[inline]
    pub fn position(&self, i: usize) -> Vec3 {
        self.case.particles.position[i] + self.u[i]
    }

    /// Whether bonds of this body fail during a run (a critical stretch; pre-cracks alone cut
    /// bonds but break none).
    pub fn may_break(&self) -> bool {
        self.fracture
            .as_ref()
            .is_some_and(|f| f.critical_stretch.is_some())
    }

    /// Grid spacing Δ.
    pub fn spacing(&self) -> f64 {
        self.case.particles.spacing
    }

    /// Master segments.
    pub fn segments(&self) -> &[MasterSegment] {
        &self.case.segments.segments
    }

    /// Builds the body from a PD case and a material.
    pub fn new(name: &str, case: PdCase, material: Material) -> PdBody {
        PdBody::without(name, case, material, &[], None)
    }

    /// [`PdBody::new`] for a body whose directed bonds `b` with `cut[b]` a pre-crack cuts
    /// before the run (they are broken after, by [`PdBody::break_bonds`]): an LPS body's
    /// weighted volumes and corrections are those of a body without them ([`Lps::without`]).
    /// An LPS body's skin correction goes on the surface particles `skin_on` marks where it is
    /// given (those that face a contact partner, [`facing`]), on every one where `None`.
    pub fn without(
        name: &str,
        mut case: PdCase,
        material: Material,
        cut: &[bool],
        skin_on: Option<&[bool]>,
    ) -> PdBody {
        let c = micromodulus(material.youngs, case.horizon);
        let n = case.particles.len();
        let vol = &case.particles.volume;
        let partner_vol = case.ghosts.partner_volumes(vol);
        let bonds = &case.bonds;
        let mut bond_weight = Vec::with_capacity(bonds.len());
        let mut stiffness = vec![0.0; n];
        let lps = (material.model == MaterialModel::Lps).then(|| {
            let position_aware = material.influence == InfluenceFunction::PositionAware;
            let mut lps = Lps::without(
                &case,
                material.youngs,
                material.poisson,
                position_aware,
                cut,
            );
            // `skin_correction` (on by default) asks for the LPS's own ([`lps::skin_factors`]).
            // A body no partner faces takes none: the same bits as without it.
            if case.skin.is_some() {
                let (factor, normal) = lps::skin_factors(&lps, &case, skin_on);
                if factor.iter().any(|&k| k != 1.0) {
                    lps.set_skin(&case, &factor, &normal);
                }
            }
            lps
        });
        let lps_stiffness = lps.as_ref().map(|l| l.bond_stiffness(&case));
        for i in 0..n {
            for b in bonds.range(i) {
                let j = bonds.partner[b] as usize;
                let w = match &lps_stiffness {
                    Some(k) => k[b],
                    None => {
                        c * case.correction.bond_factor[b] * vol[i] * partner_vol[j]
                            / bonds.length(b)
                    }
                };
                bond_weight.push(w as f32);
                stiffness[i] += w;
            }
        }
        // A rank's part holds its halo's rows in part: their stiffness is their owners'.
        if let Some(p) = &case.part {
            p.gather_scalar(&mut stiffness);
        }
        // The weights hold what the correction's factors gave (the pairs are made of them).
        drop(lps_stiffness);
        case.correction.release_factors();
        // Particles on a symmetry plane cannot move across it.
        let fixed: Vec<FixMask> = (0..n)
            .map(|i| {
                case.ghosts
                    .planes
                    .iter()
                    .enumerate()
                    .filter(|(k, _)| case.ghosts.on_plane[i] & (1 << k) != 0)
                    .fold(0, |m, (_, pl)| m | (1 << pl.axis))
            })
            .collect();
        let mut reference = Vec::new();
        case.ghosts
            .extend_positions(&case.particles.position, &mut reference);
        let symmetric: Vec<FixMask> = fixed.clone();
        PdBody {
            name: name.to_string(),
            symmetric,
            kinematics: Kinematics::Finite,
            reference,
            micromodulus: c,
            mass: vol[..n].iter().map(|v| v * material.density).collect(),
            fixed,
            load: vec![Vec3::zeros(); n],
            u: vec![Vec3::zeros(); n],
            v: vec![Vec3::zeros(); n],
            force: vec![Vec3::zeros(); n],
            contact_force: vec![Vec3::zeros(); n],
            reaction_force: vec![Vec3::zeros(); n],
            contact_stiffness: vec![0.0; n],
            owned: 0..n,
            fracture: None,
            friction: None,
            crack_faces: Vec::new(),
            precrack_pairs: Vec::new(),
            opened: None,
            crack_share: Default::default(),
            pairs: PairList::from_bonds(
                bonds,
                &bond_weight,
                &(0..n).map(|i| case.ghosts.share(i)).collect::<Vec<_>>(),
                n,
            ),
            force_buffers: ForceBuffers::default(),
            bond_weight,
            lps,
            stiffness,
            case,
            material,
        }
    }

    /// How the LPS pass stretches this body's bonds.
    pub fn stretch(&self) -> lps::Stretch<'_> {
        match self.kinematics {
            Kinematics::Small => lps::Stretch::Small(&self.reference),
            Kinematics::Finite => lps::Stretch::Finite,
        }
    }

    /// Bonds may fail past `critical_stretch` (`None`: only pre-cracks cut them): sets up the
    /// failure state, once, for the body's kinematics as they are now.
    pub fn enable_fracture(&mut self, critical_stretch: Option<f64>) {
        if self.fracture.is_none() {
            self.fracture = Some(Fracture::new(&self.case, critical_stretch, self.kinematics));
        }
    }

    /// Breaks the bonds `(i, b)` ([`Fracture::break_bonds`]).
    pub fn break_bonds(&mut self, broken: &[(u32, u32)]) {
        if let Some(f) = &mut self.fracture {
            f.break_bonds(
                &self.case.bonds,
                broken,
                &mut self.bond_weight,
                &mut self.pairs,
                self.lps.as_mut(),
            );
        }
    }

    /// Breaks the bonds `(i, b)` that failed at the positions `pos` (real particles, then
    /// images), first booking the strain energy each held on its particles' `work` of
    /// fracture (only this process's own particles: every rank breaks every failed bond, and
    /// each books its own), so that the energy balance holds across a break (METHOD.md §9).
    pub fn break_failed(&mut self, broken: &[(u32, u32)], pos: &[Vec3]) {
        let Some(fr) = &self.fracture else { return };
        let n = self.len();
        let bonds = &self.case.bonds;
        let mut booked = Vec::with_capacity(2 * broken.len());
        for &(i, b) in broken {
            let (i, b) = (i as usize, b as usize);
            if !fr.intact[b] {
                continue;
            }
            if self.owned.contains(&i) {
                booked.push((i, self.bond_energy(i, b, pos)));
            }
            let j = bonds.partner[b] as usize;
            if j < n && self.owned.contains(&j) {
                if let Some(c) = bonds.reverse(i, b) {
                    if fr.intact[c] {
                        booked.push((j, self.bond_energy(j, c, pos)));
                    }
                }
            }
        }
        let fr = self.fracture.as_mut().expect("checked above");
        for (k, e) in booked {
            fr.work[k] += e;
        }
        self.break_bonds(broken);
    }

    /// Where the body's pre-crack faces have passed through each other: the pair of
    /// particles that crossed deepest, `(precrack, behind, in front, depth)`, the depth how
    /// far the particle in front now lies behind its partner along the normal, m. `None`
    /// where none crossed. A particle that has lost every bond is debris, on no face (an
    /// impact that crushes a notch's mouth throws such particles across it).
    pub fn crossed_crack(&self) -> Option<(usize, u32, u32, f64)> {
        let detached = |i: u32| self.damage(i as usize) > 1.0 - 1e-9;
        let mut deepest: Option<(usize, u32, u32, f64)> = None;
        for (k, normal, pairs) in &self.precrack_pairs {
            for &(a, b) in pairs {
                if detached(a) || detached(b) {
                    continue;
                }
                let d = -normal.dot(&(self.position(b as usize) - self.position(a as usize)));
                if d > 0.0 && deepest.is_none_or(|x| d > x.3) {
                    deepest = Some((*k, a, b, d));
                }
            }
        }
        deepest
    }

    /// The surface that broken bonds opened, up to date ([`new_surface`]); `None` where
    /// bonds do not fail.
    pub fn new_surface(&self) -> Option<std::sync::MutexGuard<'_, new_surface::Found>> {
        let f = self.fracture.as_ref()?;
        Some(f.surface.current(&self.case, &self.reference, &f.intact))
    }

    /// Damage of particle `i` (0 where bonds do not fail).
    pub fn damage(&self, i: usize) -> f64 {
        self.fracture.as_ref().map_or(0.0, |f| f.damage(i))
    }

    /// Sets the velocity of every particle.
    pub fn set_velocity(&mut self, v: Vec3) {
        self.v.iter_mut().for_each(|x| *x = v);
    }

    /// Current positions of the particles followed by their mirror images.
    pub fn extended_positions(&self, out: &mut Vec<Vec3>) {
        let real: Vec<Vec3> = (0..self.len()).map(|i| self.position(i)).collect();
        self.case.ghosts.extend_positions(&real, out);
    }

    /// Strain energy of particle `i`'s bonds, `¼ Σ_j w (|y| − L)²` over its directed bonds
    /// (each pair is counted from both ends; a bond to a mirror image carries the half of its
    /// mirrored pair that belongs to this model), at the positions `pos`
    /// ([`extended_positions`](Self::extended_positions)).
    pub fn strain_energy_of(&self, i: usize, pos: &[Vec3]) -> f64 {
        if let Some(lps) = &self.lps {
            return lps.strain_energy_of(&self.case, i, pos, self.stretch());
        }
        self.case
            .bonds
            .range(i)
            .map(|b| self.bond_energy(i, b, pos))
            .sum::<f64>()
    }

    /// The share `¼ w (|y| − L)²` of particle `i`'s directed bond `b` in its strain energy
    /// (bond-based), at the positions `pos`.
    fn bond_energy(&self, i: usize, b: usize, pos: &[Vec3]) -> f64 {
        let bonds = &self.case.bonds;
        let j = bonds.partner[b] as usize;
        let stretch = match self.kinematics {
            Kinematics::Finite => (pos[j] - pos[i]).norm() - bonds.length(b),
            Kinematics::Small => {
                let xi = self.reference[j] - self.reference[i];
                (pos[j] - pos[i] - xi).dot(&xi) / bonds.length(b)
            }
        };
        0.25 * f64::from(self.bond_weight[b]) * stretch * stretch
    }

    /// Kinetic energy `½ m v²` of particle `i`.
    pub fn kinetic_energy_of(&self, i: usize) -> f64 {
        0.5 * self.mass[i] * self.v[i].norm_squared()
    }
}

/// A rigid surface: faces only, moved as a whole.
#[derive(Clone, Debug)]
pub struct RigidBody {
    pub name: String,
    /// Reference vertex positions.
    pub vertices: Vec<Vec3>,
    /// Outward faces (`[a, b, c, c]` for triangles).
    pub faces: Vec<MasterSegment>,
    /// Material for the contact stiffness; `None` is infinitely stiff (`m = 0` in Eq. 24).
    pub material: Option<Material>,
    pub motion: Motion,
    /// Prescribed velocity (`Motion::Velocity`).
    pub velocity: Vec3,
    /// Unit axis (`Motion::Free`).
    pub axis: Vec3,
    /// The whole prescribed displacement (`Motion::Displacement`), reached at the last load
    /// increment.
    pub displacement: Vec3,
    /// The share of the load path over which it moves (`None`: all of it;
    /// [`crate::scene::ramp_factor`]).
    pub ramp: Option<[f64; 2]>,
    /// Mass (`Motion::Free`, explicit runs).
    pub mass: f64,
    /// Current translation from the reference position.
    pub translation: Vec3,
    /// Speed along `axis` (`Motion::Free`).
    pub axial_speed: f64,
    /// Total applied force, N.
    pub load: Vec3,
    /// Total contact force on the body, N.
    pub contact_force: Vec3,
    /// Contact stiffness along the axis (for ADR's fictitious density).
    pub contact_stiffness: f64,
}

impl RigidBody {
    /// Current position of vertex `i`.
    #[inline]
    pub fn position(&self, i: usize) -> Vec3 {
        self.vertices[i] + self.translation
    }
}

/// A body of a scene.
#[derive(Clone, Debug)]
pub enum Body {
    Deformable(Box<PdBody>),
    Rigid(Box<RigidBody>),
}

impl Body {
    /// The body's name.
    pub fn name(&self) -> &str {
        match self {
            Body::Deformable(b) => &b.name,
            Body::Rigid(b) => &b.name,
        }
    }

    /// The deformable body, if it is one.
    pub fn as_pd(&self) -> Option<&PdBody> {
        match self {
            Body::Deformable(b) => Some(b),
            Body::Rigid(_) => None,
        }
    }

    /// The deformable body, mutably.
    pub fn as_pd_mut(&mut self) -> Option<&mut PdBody> {
        match self {
            Body::Deformable(b) => Some(b),
            Body::Rigid(_) => None,
        }
    }

    /// The rigid body, if it is one.
    pub fn as_rigid(&self) -> Option<&RigidBody> {
        match self {
            Body::Rigid(b) => Some(b),
            Body::Deformable(_) => None,
        }
    }
}
