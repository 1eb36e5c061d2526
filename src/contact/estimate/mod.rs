//! The contact a scene will make, estimated before it runs: where the slave first touches the
//! master, the local radii of curvature there, the Hertz contact radius under the load, and how
//! many particle spacings span it (METHOD.md §5, §7; Hertz 1882; Johnson, *Contact Mechanics*,
//! 1985, §4.2-4.3).
//!
//! * **First contact.** The approach direction is the slave's applied load (or the master's,
//!   reversed). The slave's surface nodes that lead along it are cast as rays onto the master's
//!   faces that face them, and the master's leading nodes back onto the slave's faces; the
//!   nearest hit is the first contact `q`, and the face hit gives the contact normal `d` (from
//!   slave to master): the master's normal reversed, or the slave's own. The normal load `P` is
//!   the applied force along `d` (the larger of the slave's load along `d` and the master's
//!   against it); without one there is no estimate.
//! * **Curvature.** Each body's surface nodes that face the other (and their mirror images
//!   across its symmetry planes) are taken in a window around `q`, the smallest holding
//!   [`FIT_POINTS`] of them, as heights `h(u, v)` above the tangent plane at `q`. A least-squares
//!   paraboloid `h = c₀ + c₁u + c₂v + ½ uᵀHu` gives the curvature tensor `H`; the sagitta term is
//!   moved to the data (`h − ½ κ h²`, iterated), which makes the fit exact on spheres and
//!   cylinders whatever the window. A body with too few nodes near `q` (a rigid plane of a few
//!   large faces) is flat at the contact's scale. The relative curvature is `H_slave + H_master`;
//!   its principal curvatures `κ₁ ≥ κ₂`. Flat (`κ₁ D ≤ 10⁻³` over the slave's size `D`),
//!   concave or saddle-shaped contacts have no estimate: nothing is said about them.
//! * **Hertz.** `E* = 1/(m_s + m_m)`, `m = (1 − ν²)/E`, `m = 0` for a rigid body (Eq. 38, the
//!   contact law's Eq. 24). A point contact (`κ₂/κ₁ ≥ 0.1`): `c = √(ab) = (3PR_e/(4E*))^⅓` with
//!   `R_e = 1/√(κ₁κ₂)`, and the semi-minor axis `b = c (κ₂/κ₁)^⅓` (Johnson §4.3,
//!   `b/a ≈ (κ₂/κ₁)^⅔`); a sphere gives `a = (3PR/(4E*))^⅓` (Eq. 36). A line contact (a
//!   cylinder): `b = (4P′R/(πE*))^½` with `R = 1/κ₁` and `P′ = P/L`, `L` the length of the
//!   slave's surface along the line (Eq. 40). A symmetry plane through the contact carries the
//!   mirrored half of it: `P` doubles (for a line contact only across the line).
//! * **Resolution.** `Δ` is the spacing of the slave's surface particles near the contact:
//!   `√` of the median tributary area (a quad lattice's `Δ²`; `0.87 h²` per node on a
//!   triangulated surface of size `h`). On the Hertz sphere `a/Δ = 5` gives 1 % MRE and the
//!   structured demo at `a/Δ = 3.6` 8.6 %; at 2.5 the MRE is 5 % on radial layers and it grows
//!   fast below (docs/VALIDATION.md, "Spacing"): below [`WARN_SPACINGS`] the run warns.
//! * **Even areas.** The ratio of the 95th to the 5th percentile of the slave's surface
//!   particles' tributary areas within `max(2a, window)` of the contact (the whole slave
//!   without an estimate); above [`UNEVEN_AREA_RATIO`] the run warns. Measured (`convert` on
//!   each mesh, areas within `max(2a, window)` of the lowest point): structured cubed spheres
//!   1.05-1.13, gmsh-default tet4 and tet10 spheres 1.65-1.72, tets split into hexes 2.8-2.9
//!   (these give the 5-6 % MRE of docs/VALIDATION.md, "Unstructured meshes": no warning);
//!   (over the whole surface: 1.5-1.7 and 2.4-2.7); spheres graded from 0.01-0.02 to 0.2-0.3 m
//!   within 0.15-0.3 m of the pole 12-15, with MRE 44-55 % under Hertz at `a = 0.15 m` (uniform
//!   tet4 at the same `a/Δ`: 16-20 %); a box graded 14:1 along x 9.9, 45:1 37. A particle on a
//!   symmetry plane counts with its whole area (twice the half its model holds).
//! * **Graded meshes.** A body has one spacing `Δ_body` (the lattice spacing of its median
//!   particle volume), which sets its horizon. Where the surface near the contact is much finer
//!   than that (`Δ < ½ Δ_body`, [`GRADED_SPACING_RATIO`]) the mesh was graded toward the
//!   contact, and the pressure there is far from Hertz even where the areas change slowly: a
//!   gmsh sphere graded 0.03 → 0.15 m over 1 m (areas 3.4:1 near the pole, `Δ/Δ_body = 0.36`)
//!   gave MRE 64 % at `a = 0.15 m`. Uniform meshes measure `Δ/Δ_body` = 0.80-0.89 (tet4,
//!   tet10), 1.0-1.07 (tets split into hexes), 1.24-1.26 (cubed spheres); graded ones 0.34-0.43.
//!   Those figures were taken with one horizon per body. Where the mesh's local spacing spreads
//!   2:1 or more, the horizon now follows it ([`crate::case::HorizonKind::Local`]) and the same
//!   kind of sphere gives MRE 2.6-5.0 % (docs/VALIDATION.md, "Meshes refined towards the
//!   contact"): the warning is only for a body with one horizon (`horizon = "uniform"`, or a
//!   `spacing` given).
//! * **Penalty.** Where the model holds the pair's contact law
//!   ([`ContactResolution::with_penalty`]): how far a particle of the median tributary area
//!   sinks under Eq. 23 at Hertz's peak pressure, against the contact's depth (the approach
//!   `a²/R`, `b²/R` across a line). Hertz has no such compliance; it widens the contact. On
//!   the whole Hertz sphere at a/Δ = 4.6 (gmsh tet4) a sink of 1.4 % left the fitted radius
//!   +5.70 %, 0.3 % +4.18 %, 0.06 % +4.17 %: above [`PENALTY_WARN`] the run warns and names
//!   the radius for [`PENALTY_TARGET`].

mod geometry;

use serde::Serialize;

use crate::body::{Body, RigidBody};
use crate::case::segments::MasterSegment;
use crate::case::{PdCase, SymmetryPlane};
use crate::contact::ContactLaw;
use crate::math::{tangent_frame, Vec3};
use crate::scene::PenaltyLaw;
use geometry::{extent, first_contact, fit_curvature, line_length, principal};

/// `a/Δ` from which the pressure is at Hertz level (MRE 1 % on the Hertz sphere,
/// docs/VALIDATION.md, "Spacing").
pub const RESOLVED_SPACINGS: f64 = 5.0;
/// `a/Δ` below which a contact is said to be poorly resolved.
pub const WARN_SPACINGS: f64 = 3.0;
/// 95th-to-5th percentile ratio of tributary areas above which they are said to be uneven.
pub const UNEVEN_AREA_RATIO: f64 = 10.0;
/// Surface spacing near the contact over the body's spacing below which the mesh is graded.
pub const GRADED_SPACING_RATIO: f64 = 0.5;
/// The largest `a/R` of small-strain Hertz contact (METHOD.md §7, the "hertz" set).
pub const SMALL_STRAIN_RATIO: f64 = 0.15;
/// A strain `p0 (1 − ν²)/E` beyond this is no small-strain contact (on a sphere, `a/R` of
/// about 0.16): `run` warns of it ([`crate::run`]'s units check), and `convert`'s load stays
/// under it.
pub const STRAIN_LIMIT: f64 = 0.1;
/// Penetration at the Hertz peak over the contact's depth above which the penalty is said to
/// be soft. Measured on the whole Hertz sphere (a = 0.3 m, docs/VALIDATION.md, "The penalty"):
/// at 1.4 % (penalty radius 100 m, tets of a/Δ = 4.6) the contact is 1.5 points wider than with
/// a penalty 100 times stiffer, at 0.3 % the figures are within 0.1 point of a rigid contact.
pub const PENALTY_WARN: f64 = 0.01;
/// The ratio the suggested penalty radius gives.
pub const PENALTY_TARGET: f64 = 0.003;
/// Surface nodes (mirror images included) a curvature fit takes around the contact.
pub const FIT_POINTS: usize = 20;
/// Leading surface nodes of each body cast as rays to find the first contact.
const CANDIDATES: usize = 256;
/// `κ₂/κ₁` below which a contact is a line contact.
const LINE_RATIO: f64 = 0.1;

/// One body of a contact pair as the estimate sees it (reference configuration).
#[derive(Clone, Copy, Debug)]
pub struct ContactSurface<'a> {
    pub name: &'a str,
    /// Node positions (particles, or a rigid body's vertices).
    pub points: &'a [Vec3],
    /// Outward faces: master segments, or a rigid body's faces.
    pub faces: &'a [MasterSegment],
    /// Symmetry planes: the body is mirrored across them.
    pub planes: &'a [SymmetryPlane],
    /// Tributary area per particle (a deformable slave).
    pub tributary: Option<&'a [f64]>,
    /// Total applied force on the body, N.
    pub load: Vec3,
    /// `m = (1 − ν²)/E` (0 for a rigid body).
    pub compliance: f64,
    /// The body's grid spacing Δ (0 for a rigid body), m.
    pub grid_spacing: f64,
    /// Levels of `refine` the body's mesh was cut by: its new nodes lie on the straight edges,
    /// inside a curved surface, so the curvature fit takes `4^refine` times the nodes, the
    /// same patch of surface as on the mesh before it was cut, where the file's nodes weigh
    /// as they did (on a gmsh tet sphere cut once, 20 nodes fitted R = 0.875 m for 1 m).
    pub refine: u32,
}

impl<'a> ContactSurface<'a> {
    /// A PD case with its load and material.
    pub fn of_case(name: &'a str, case: &'a PdCase, load: Vec3, compliance: f64) -> Self {
        ContactSurface {
            name,
            points: &case.particles.position,
            faces: &case.segments.segments,
            planes: &case.ghosts.planes,
            tributary: Some(&case.segments.tributary_area),
            load,
            compliance,
            // A body whose horizon follows its local spacing has no one spacing to be finer
            // than: warning (c) is for bodies with one horizon.
            grid_spacing: if case.local_spacing.is_some() {
                0.0
            } else {
                case.particles.spacing
            },
            refine: case.refine,
        }
    }

    /// A rigid surface with its load and (optional) material.
    pub fn of_rigid(rb: &'a RigidBody) -> Self {
        ContactSurface {
            name: &rb.name,
            points: &rb.vertices,
            faces: &rb.faces,
            planes: &[],
            tributary: None,
            load: rb.load,
            compliance: rb.material.map_or(0.0, |m| m.compliance()),
            grid_spacing: 0.0,
            refine: 0,
        }
    }

    /// A body of a scene, at its reference configuration, with the loads applied to it.
    pub fn of_body(body: &'a Body) -> Self {
        match body {
            Body::Deformable(pd) => ContactSurface::of_case(
                &pd.name,
                &pd.case,
                pd.load.iter().sum(),
                pd.material.compliance(),
            ),
            Body::Rigid(rb) => ContactSurface::of_rigid(rb),
        }
    }

    /// Distinct corner nodes of the faces whose outward normal has a positive component
    /// along `toward` (all faces when `toward` is zero).
    pub(crate) fn facing_nodes(&self, toward: Vec3) -> Vec<u32> {
        let mut nodes: Vec<u32> = self
            .faces
            .iter()
            .filter(|f| toward == Vec3::zeros() || f.normal.dot(&toward) > 0.0)
            .flat_map(|f| f.nodes)
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        nodes
    }
}

/// Whether the contact is a point (sphere-like, elliptical) or a line (cylinder-like).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ContactShape {
    Point,
    Line,
}

/// The Hertz estimate of one contact.
#[derive(Clone, Debug, Serialize)]
pub struct HertzEstimate {
    /// First contact point, m.
    pub centre: [f64; 3],
    /// Contact normal, from the slave toward the master.
    pub normal: [f64; 3],
    /// Normal load of the whole contact (mirror images included), N.
    pub load: f64,
    /// `E*`, Pa.
    pub e_star: f64,
    /// Principal relative curvatures `κ₁ ≥ κ₂`, 1/m.
    pub curvatures: [f64; 2],
    /// The slave's own largest principal curvature there, 1/m (`κ₁` less the master's): the
    /// body's `a/R` is `radius` times it, what `validate --mesh --contact-ratio` takes.
    pub slave_curvature: f64,
    pub shape: ContactShape,
    /// Line contacts: the length `L` that carries the load (`P′ = P/L`), m.
    pub line_length: Option<f64>,
    /// Contact radius (point contact; the semi-minor axis of an elliptical one) or half-width
    /// (line contact), m.
    pub radius: f64,
    /// Radius of the slave's curvature fit window, m.
    pub window: f64,
}

/// What the estimate says about one contact pair.
#[derive(Clone, Debug, Serialize)]
pub struct ContactResolution {
    pub slave: String,
    pub master: String,
    pub estimate: Option<HertzEstimate>,
    /// Spacing of the slave's surface particles where the areas were measured, m.
    pub spacing: f64,
    /// The slave body's grid spacing Δ (its horizon is `m Δ`), m.
    pub grid_spacing: f64,
    /// `radius / spacing`.
    pub spacings: Option<f64>,
    /// 95th to 5th percentile of the tributary areas of the slave's surface particles near
    /// the contact (the whole slave without an estimate).
    pub area_ratio: f64,
    /// Particles those percentiles are taken over.
    pub area_particles: usize,
    /// Radius around the contact centre they were taken within (`None`: the whole slave), m.
    pub area_radius: Option<f64>,
    /// How far the pair's penalty lets a particle sink at the Hertz peak, where the estimate
    /// and the pair's contact law give it ([`ContactResolution::with_penalty`]).
    pub penalty: Option<PenaltyCompliance>,
    /// The slave is meshed in tet10 or hex20 and only their corners are particles
    /// (`second_order = "corners"`): the warning on few spacings names the mid-edge nodes.
    pub second_order_corners: bool,
    /// The slave is a first-order mesh of tets and hexes, not refined (`refine = 0`): the
    /// warning on few spacings names `refine`.
    pub refinable: bool,
}

/// The penetration a Hertz penalty (Eq. 23) allows under the estimated contact, against the
/// depth of the contact itself: a compliance that Hertz's theory does not have, which widens
/// the contact and lowers its peak.
#[derive(Clone, Debug, Serialize)]
pub struct PenaltyCompliance {
    /// The penalty radius R of `K = 4E*√R/3`, m.
    pub radius: f64,
    /// Penetration of a particle of the median tributary area at the peak pressure, m.
    pub penetration: f64,
    /// The contact's depth: Hertz's approach `a²/R` (sphere; `c²√(κ₁κ₂)` for an ellipse) or
    /// `b²/R` across a line contact, m.
    pub depth: f64,
    /// `penetration / depth`.
    pub ratio: f64,
    /// The penalty radius that brings the ratio to [`PENALTY_TARGET`], m.
    pub suggested_radius: f64,
}

impl ContactResolution {
    /// The pair as warnings name it.
    pub fn pair(&self) -> String {
        format!("contact \"{}\"/\"{}\"", self.slave, self.master)
    }

    /// Warning (a): the expected contact spans fewer than [`WARN_SPACINGS`] spacings.
    pub fn resolution_warning(&self) -> Option<String> {
        let (e, n) = (self.estimate.as_ref()?, self.spacings?);
        (n < WARN_SPACINGS).then(|| {
            format!(
                "{}: expected contact {} ≈ {} m spans {:.1} surface spacings (h = {} m{}); Hertz-level pressure needs ≥ {RESOLVED_SPACINGS} spacings across it — refine the mesh near the contact to h ≤ {} m, or raise the load",
                self.pair(),
                e.what(),
                sig(e.radius),
                n,
                sig(self.spacing),
                self.spacing_note(),
                sig(e.radius / RESOLVED_SPACINGS),
            ) + self.mesh_hint()
        })
    }

    /// What the surface spacing `h` of the resolution warnings is, beside the body's grid
    /// spacing Δ (the `spacing` of its scene, which sets the horizon): two measures of one
    /// mesh, so the messages name them apart (on gmsh tet meshes `h` is 0.80-0.89 Δ).
    pub fn spacing_note(&self) -> String {
        if self.grid_spacing > 0.0 {
            format!(
                ", √ of the median tributary area of the surface particles there; the body's spacing Δ = {} m sets its horizon",
                sig(self.grid_spacing)
            )
        } else {
            ", √ of the median tributary area of the surface particles there".into()
        }
    }

    /// What the slave's own mesh offers for more spacings across the contact, as the tail of
    /// a warning (empty where it offers nothing).
    pub fn mesh_hint(&self) -> &'static str {
        if self.second_order_corners {
            "; the mesh is second order (tet10 or hex20) and its corners alone are particles: second_order = \"all-nodes\" in the body makes every node one, about twice the spacings across the contact"
        } else if self.refinable {
            "; refine = 1 in the body cuts every tet and hex into eight at its edges' midpoints, about twice the spacings across the contact at about seven times the particles"
        } else {
            ""
        }
    }

    /// The resolution with the slave's mesh hints ([`Self::mesh_hint`]) taken from its case.
    pub fn with_mesh_hints(self, case: &PdCase) -> Self {
        ContactResolution {
            second_order_corners: case.corners_of_second_order(),
            refinable: case.refinable(),
            ..self
        }
    }

    /// Where the areas were measured, as warnings say it.
    fn region(&self) -> String {
        match (&self.estimate, self.area_radius) {
            (Some(e), Some(r)) => {
                // Round-off off the axes reads as noise: 6.12e-17 is 0.
                let c = Vec3::from(e.centre);
                let at = c.map(|x| if x.abs() > 1e-9 * c.norm() { x } else { 0.0 });
                format!(
                    "within {} m of the expected contact at [{}, {}, {}]",
                    sig(r),
                    sig(at.x),
                    sig(at.y),
                    sig(at.z)
                )
            }
            _ => "over the whole surface".to_string(),
        }
    }

    /// Warning (b): uneven tributary areas where the contact will be.
    pub fn area_warning(&self) -> Option<String> {
        (self.area_ratio > UNEVEN_AREA_RATIO).then(|| {
            format!(
                "{}: the tributary areas of \"{}\"'s surface particles vary {:.0}:1 {} (95th to 5th percentile of {} particles; above {UNEVEN_AREA_RATIO}:1 the contact pressure scatters with the mesh) — mesh the contact surface with elements of even size",
                self.pair(),
                self.slave,
                self.area_ratio,
                self.region(),
                self.area_particles,
            )
        })
    }

    /// Warning (c): the surface where the contact will be is much finer than the body's
    /// spacing (a mesh graded toward the contact).
    pub fn graded_warning(&self) -> Option<String> {
        (self.spacing > 0.0 && self.spacing < GRADED_SPACING_RATIO * self.grid_spacing).then(|| {
            format!(
                "{}: the surface particles of \"{}\" {} are {:.1} times closer (Δ = {} m) than the body's spacing Δ = {} m (the lattice spacing of its median particle volume, which sets the horizon: one spacing per body); pressures on a mesh graded toward the contact are far from Hertz — mesh the body with an even element size",
                self.pair(),
                self.slave,
                self.region(),
                self.grid_spacing / self.spacing,
                sig(self.spacing),
                sig(self.grid_spacing),
            )
        })
    }

    /// Warning (d): the penalty lets the particles sink by a sizeable part of the contact's
    /// own depth.
    pub fn penalty_warning(&self) -> Option<String> {
        let p = self.penalty.as_ref()?;
        (p.ratio > PENALTY_WARN).then(|| {
            format!(
                "{}: the penalty (radius = {} m) lets a particle at the expected peak pressure sink {} m, {:.1} % of the contact's depth ({} m); that compliance widens the contact and lowers its peak — set radius = {} (or more) in this [[contact]] for {:.1} %",
                self.pair(),
                sig(p.radius),
                sig(p.penetration),
                100.0 * p.ratio,
                sig(p.depth),
                sig(p.suggested_radius),
                100.0 * PENALTY_TARGET,
            )
        })
    }

    /// The warnings that apply.
    pub fn warnings(&self) -> Vec<String> {
        self.tagged_warnings().into_iter().map(|(w, _)| w).collect()
    }

    /// [`Self::warnings`], each with whether it is about the slave's mesh alone (its areas
    /// and grading where the contact will be) rather than about the scene's values (the load
    /// the spacings are measured against, the penalty).
    pub fn tagged_warnings(&self) -> Vec<(String, bool)> {
        [
            (self.resolution_warning(), false),
            (self.area_warning(), true),
            (self.graded_warning(), true),
            (self.penalty_warning(), false),
        ]
        .into_iter()
        .filter_map(|(w, on_mesh)| w.map(|w| (w, on_mesh)))
        .collect()
    }

    /// Adds what the pair's penalty does under the estimated contact (METHOD.md §5): the
    /// penetration `δ = (F/K)^⅔` (linear law: `F/(K√w)`) of a particle of the median tributary
    /// area `Δ²` at the peak pressure `p0` (`3P/(2πc²)`; a line contact `2P′/(πb)`). `K` is
    /// the law's `K = 4E*√R/3`, so `R = (3K/(4E*))²`; the suggested radius scales the ratio
    /// by `R^(-1/3)` (linear: `R^(-1/2)`). Nothing where there is no estimate.
    pub fn with_penalty(mut self, law: &ContactLaw) -> Self {
        let Some(e) = &self.estimate else {
            return self;
        };
        if !(self.spacing > 0.0 && law.stiffness.is_finite() && law.stiffness > 0.0) {
            return self;
        }
        let depth = e.depth();
        let peak = match e.shape {
            ContactShape::Point => {
                let c = e.radius * (e.curvatures[0] / e.curvatures[1]).cbrt();
                3.0 * e.load / (2.0 * std::f64::consts::PI * c * c)
            }
            ContactShape::Line => {
                let per_length = e.load / e.line_length.unwrap_or(f64::INFINITY);
                2.0 * per_length / (std::f64::consts::PI * e.radius)
            }
        };
        let force = peak * self.spacing * self.spacing;
        let (penetration, power) = match law.law {
            PenaltyLaw::Hertz => ((force / law.stiffness).powf(2.0 / 3.0), 3),
            PenaltyLaw::Linear => (force / (law.stiffness * law.window.sqrt()), 2),
        };
        let radius = (0.75 * law.stiffness / e.e_star).powi(2);
        let ratio = penetration / depth;
        if !(ratio.is_finite() && radius.is_finite()) {
            return self;
        }
        self.penalty = Some(PenaltyCompliance {
            radius,
            penetration,
            depth,
            ratio,
            suggested_radius: radius * (ratio / PENALTY_TARGET).max(1.0).powi(power),
        });
        self
    }
}

impl HertzEstimate {
    /// The contact's depth, m: Hertz's approach `a²/R` of a sphere (`c²√(κ₁κ₂)` for an
    /// ellipse of semi-major axis `c`), `b²κ₁` across a line contact (METHOD.md §7).
    pub fn depth(&self) -> f64 {
        let [k1, k2] = self.curvatures;
        match self.shape {
            ContactShape::Point => {
                let c = self.radius * (k1 / k2).cbrt();
                c * c * (k1 * k2).sqrt()
            }
            ContactShape::Line => self.radius * self.radius * k1,
        }
    }

    /// The contact's normal stiffness under its load, `dP/dδ = 3P/(2δ)` (`P ∝ δ^{3/2}`,
    /// METHOD.md §7), N/m; `None` across a line contact, whose approach is not a power of the
    /// load.
    pub fn stiffness(&self) -> Option<f64> {
        (self.shape == ContactShape::Point).then(|| 1.5 * self.load / self.depth())
    }

    /// "radius" or "half-width".
    pub fn what(&self) -> &'static str {
        match self.shape {
            ContactShape::Point => "radius",
            ContactShape::Line => "half-width",
        }
    }

    /// Hertz's peak pressure (METHOD.md §7) with the contact taken as circular of radius `a`
    /// (`3P/(2πa²)`) or, across a line, `2P′/(πb)`, Pa.
    pub fn peak_pressure(&self) -> f64 {
        match self.shape {
            ContactShape::Point => {
                3.0 * self.load / (2.0 * std::f64::consts::PI * self.radius * self.radius)
            }
            ContactShape::Line => {
                2.0 * self.load
                    / (self.line_length.unwrap_or(f64::INFINITY)
                        * std::f64::consts::PI
                        * self.radius)
            }
        }
    }

    /// The smallest principal radius of relative curvature `1/κ₁`, m.
    pub fn curvature_radius(&self) -> f64 {
        1.0 / self.curvatures[0]
    }

    /// The factor on the load that gives a contact radius (half-width) `radius` instead:
    /// `P ∝ a³` for a point contact, `P ∝ b²` for a line contact.
    pub fn load_factor(&self, radius: f64) -> f64 {
        let k = match self.shape {
            ContactShape::Point => 3,
            ContactShape::Line => 2,
        };
        (radius / self.radius).powi(k)
    }
}

/// A number with three significant digits, without trailing noise.
pub fn sig(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let digits = (2 - x.abs().log10().floor() as i32).max(0) as usize;
    if (1e-3..1e5).contains(&x.abs()) {
        format!("{x:.digits$}")
    } else {
        format!("{x:.2e}")
    }
}

/// Estimates the contact of `slave` pressed on `master` and measures the slave's surface
/// particles there.
pub fn resolve(slave: &ContactSurface, master: &ContactSurface) -> ContactResolution {
    let estimate = estimate(slave, master);
    let tributary = slave.tributary.unwrap_or(&[]);
    let mut nodes = slave.facing_nodes(Vec3::zeros());
    nodes.retain(|&n| tributary.get(n as usize).is_some_and(|&a| a > 0.0));
    let mut area_radius = None;
    if let Some((e, w)) = &estimate {
        let r = (2.0 * e.radius).max(*w);
        let c = Vec3::from(e.centre);
        let near: Vec<u32> = nodes
            .iter()
            .copied()
            .filter(|&n| (slave.points[n as usize] - c).norm() <= r)
            .collect();
        if near.len() >= 2 {
            nodes = near;
            area_radius = Some(r);
        }
    }
    // A particle on a symmetry plane holds the half of its area on the model's side.
    let whole = |n: u32| {
        let x = slave.points[n as usize];
        let cut = slave
            .planes
            .iter()
            .filter(|pl| (x[pl.axis] - pl.at).abs() <= 1e-9 * (1.0 + pl.at.abs()))
            .count();
        tributary[n as usize] * 2f64.powi(cut as i32)
    };
    let mut areas: Vec<f64> = nodes.iter().map(|&n| whole(n)).collect();
    areas.sort_by(f64::total_cmp);
    let pick = |p: f64| areas[((areas.len() - 1) as f64 * p).round() as usize];
    let (spacing, area_ratio) = if areas.is_empty() {
        (0.0, 1.0)
    } else {
        (pick(0.5).sqrt(), pick(0.95) / pick(0.05))
    };
    let spacings = estimate
        .as_ref()
        .filter(|_| spacing > 0.0)
        .map(|(e, _)| e.radius / spacing);
    ContactResolution {
        slave: slave.name.to_string(),
        master: master.name.to_string(),
        estimate: estimate.map(|(e, _)| e),
        spacing,
        grid_spacing: slave.grid_spacing,
        spacings,
        area_ratio,
        area_particles: areas.len(),
        area_radius,
        penalty: None,
        second_order_corners: false,
        refinable: false,
    }
}

/// The Hertz estimate and the slave's fit window, where geometry and loads give one.
fn estimate(slave: &ContactSurface, master: &ContactSurface) -> Option<(HertzEstimate, f64)> {
    let approach = if slave.load.norm() > 0.0 {
        slave.load.normalize()
    } else if master.load.norm() > 0.0 {
        -master.load.normalize()
    } else {
        return None;
    };
    let (q, d) = first_contact(slave, master, approach)?;
    let load = slave.load.dot(&d).max(-master.load.dot(&d));
    if !(load > 0.0) {
        return None;
    }
    let (e1, e2) = tangent_frame(d);
    let slave_nodes = slave.facing_nodes(d);
    let (hs, window) = fit_curvature(slave, &slave_nodes, q, d, e1, e2, -1.0)?;
    let hm = fit_curvature(master, &master.facing_nodes(-d), q, d, e1, e2, 1.0)
        .map_or([0.0; 3], |f| f.0);
    let h = [hs[0] + hm[0], hs[1] + hm[1], hs[2] + hm[2]];
    let (k1, k2, across) = principal(h, e1, e2);
    let slave_curvature = principal(hs, e1, e2).0;
    let size = extent(slave.points, &slave_nodes);
    if !(k1 * size > 1e-3) || k2 < -LINE_RATIO * k1 {
        return None;
    }
    let e_star = 1.0 / (slave.compliance + master.compliance);
    let on_plane =
        |pl: &&SymmetryPlane| d[pl.axis].abs() < 0.1 && (q[pl.axis] - pl.at).abs() <= 0.1 * window;
    let (shape, line_length, radius, load) = if k2 >= LINE_RATIO * k1 {
        let p = load * 2f64.powi(slave.planes.iter().filter(on_plane).count() as i32);
        let c = (3.0 * p / (k1 * k2).sqrt() / (4.0 * e_star)).cbrt();
        (ContactShape::Point, None, c * (k2 / k1).cbrt(), p)
    } else {
        let doubled = slave
            .planes
            .iter()
            .filter(on_plane)
            .filter(|pl| across[pl.axis].abs() > 0.9)
            .count();
        let p = load * 2f64.powi(doubled as i32);
        let length = line_length(slave, &slave_nodes, q, d, across, window)?;
        let b = (4.0 * (p / length) / (k1 * std::f64::consts::PI * e_star)).sqrt();
        (ContactShape::Line, Some(length), b, p)
    };
    let estimate = HertzEstimate {
        centre: q.into(),
        normal: d.into(),
        load,
        e_star,
        curvatures: [k1, k2],
        slave_curvature,
        shape,
        line_length,
        radius,
        window,
    };
    Some((estimate, window))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_read_with_three_digits() {
        assert_eq!(sig(0.065518), "0.0655");
        assert_eq!(sig(0.15), "0.150");
        assert_eq!(sig(4.8e6), "4.80e6");
        assert_eq!(sig(1.0), "1.00");
        assert_eq!(sig(0.0), "0");
    }

    #[test]
    fn the_load_scales_with_the_cube_or_square_of_the_radius() {
        let mut e = HertzEstimate {
            centre: [0.0; 3],
            normal: [0.0, 0.0, -1.0],
            load: 1.0,
            e_star: 1.0,
            curvatures: [1.0, 1.0],
            slave_curvature: 1.0,
            shape: ContactShape::Point,
            line_length: None,
            radius: 0.1,
            window: 0.3,
        };
        assert!((e.load_factor(0.2) - 8.0).abs() < 1e-12);
        e.shape = ContactShape::Line;
        assert!((e.load_factor(0.2) - 4.0).abs() < 1e-12);
    }
}
