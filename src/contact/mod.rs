//! Point-to-surface contact with a Hertz penalty (paper Secs. 2.2.2-2.2.4, METHOD.md §5).
//!
//! Split like a rigid-body engine's contact pipeline:
//!
//! * **broad phase** (`broad.rs`, [`VerletList`]): for each slave surface particle, the master segments it
//!   may touch. A segment is a candidate when one of its corner nodes lies within the cutoff plus
//!   a skin of 0.3Δ (Eq. 17: a segment's contact neighbours are the union of its corners'
//!   lists; here the union is inverted, slave → segments). Segments much larger than the slave
//!   spacing (a rigid plane of a few big quads) are found by their bounding box inflated by the
//!   cutoff instead, because their corners are far from their slaves. The list is rebuilt only
//!   when the two largest displacements since the last rebuild sum to more than the skin (the
//!   paper's five steps).
//! * **narrow phase** (`narrow.rs`, [`project`]): the segment and the slave are projected on the plane of
//!   Eq. 18, the bilinear map of Eqs. 19-20 is inverted for `(r, t)` by Newton's method, and the
//!   slave is inside when `|r|, |t| ≤ 1` (a small tolerance keeps particles on shared edges; each
//!   slave takes the one inside segment nearest to it among the segments that face it: their
//!   normals oppose the slave's outward normal; [`select_segment`] gives the rules at a convex
//!   master's corner, and a slave keeps the segment it touches while it stays in it). The gap is
//!   `g = (x_s − x_c(r,t)) · n_m` (Eq. 21); a slave is in contact when `g < 0` and `−g` is within
//!   the window 0.5Δ. A slave behind a segment by more than the window is a missed contact.
//!   A slave that projects outside every segment because it lies behind a concave edge or
//!   vertex of a deformed master (a dent) is held there ([`select_across_edge`]).
//! * **force** (`law.rs`, [`ContactLaw`]): `F = K δ^{3/2}` along `n_m` on the slave with
//!   `K = 4/(3(m_s + m_m)) √R`, `m = (1 − ν²)/E`, `m = 0` for a rigid body, `R = Δ/2` by
//!   default (Eqs. 22-24); the reaction goes to the master's corner nodes with the weights
//!   `N_i(r,t)`, or to the rigid body.
//! * **estimate** ([`estimate`]): before a run, the Hertz contact radius each pair will make
//!   under its loads, against the slave's particle spacing there (the warnings of `run` and
//!   `convert`).
//! * **overlap** ([`overlap`]): before a run, the slave particles that start inside their
//!   master deeper than the window, which the penalty cannot push back (`run` refuses them).

mod broad;
mod crack;
pub mod estimate;
pub mod fragments;
pub mod friction;
mod law;
mod narrow;
mod normal;
mod open;
pub mod overlap;
pub mod shortrange;
mod sums;

use rayon::prelude::*;

pub use broad::{TopTwo, VerletList};
pub use crack::CRACK_EDGE_MARGIN;
use crack::{CrackSides, FoundFaces};
pub use law::{default_radius, hertz_stiffness, ContactLaw};
pub use narrow::{
    project, project_any, project_on_plane_edge, select_across_edge, select_segment, slave_normal,
    Projection, Touch, EDGE_FACING, FACING, INSIDE_TOLERANCE,
};
pub use normal::{NodalTurn, Slide};

use crate::body::{Body, PdBody, RigidBody};
use crate::case::segments::MasterSegment;
use crate::math::Vec3;
use broad::distinct;
use friction::Anchor;
use narrow::within_window;

/// Segments around a master node whose normals turn from a segment's by more than this angle
/// (30°, the feature angle of ParaView's and VTK's normals filter) are across a feature edge
/// and do not smooth its normal ([`ContactPass::smooth_normal`]).
pub const FEATURE_ANGLE: f64 = std::f64::consts::PI / 6.0;
const FEATURE_COS: f64 = 0.866_025_403_784_438_6;
/// Skin of the Verlet list, in slave spacings.
pub const SKIN: f64 = 0.3;
/// The contact window, in slave spacings (the paper's 0.5Δ).
pub const WINDOW: f64 = 0.5;
/// The symmetry planes that a slave body and a deformable master share (the same axis and
/// place): `(slave plane bit, master plane bit, axis)`, the bits those of
/// [`Ghosts::on_plane`](crate::case::Ghosts::on_plane).
fn shared_planes(slave: &PdBody, master: MasterView) -> Vec<(u8, u8, usize)> {
    let Some(mb) = master.pd() else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for (ks, sp) in slave.case.ghosts.planes.iter().enumerate() {
        for (km, mp) in mb.case.ghosts.planes.iter().enumerate() {
            let tol = 1e-9 * (1.0 + sp.at.abs()) + 1e-6 * slave.spacing();
            if sp.axis == mp.axis && (sp.at - mp.at).abs() <= tol {
                out.push((1 << ks, 1 << km, sp.axis));
            }
        }
    }
    out
}

/// The edge of `segment` whose two corners lie on a plane (`on(node)`), as corner indices in
/// winding order; `None` unless exactly two of its distinct corners do and they are
/// neighbours.
fn plane_edge(segment: &MasterSegment, on: impl Fn(u32) -> bool) -> Option<(usize, usize)> {
    let corners = if segment.is_triangle() { 3 } else { 4 };
    let (mut hits, mut count) = ([0usize; 4], 0);
    for k in (0..corners).filter(|&k| on(segment.nodes[k])) {
        hits[count] = k;
        count += 1;
    }
    match (count, hits[0], hits[1]) {
        (2, a, b) if b == a + 1 => Some((a, b)),
        (2, 0, b) if b == corners - 1 => Some((b, 0)),
        _ => None,
    }
}

/// Slave `s`'s (at `p`) projection on segment `seg` of `view` ([`project_any`]), but on the
/// segment's edge in a symmetry plane where the slave lies on one the master shares
/// ([`project_on_plane_edge`]; `planes`: [`shared_planes`]).
fn project_plain(
    sb: &PdBody,
    view: MasterView,
    planes: &[(u8, u8, usize)],
    s: u32,
    p: Vec3,
    seg: u32,
) -> Option<(Projection, f64)> {
    let x = view.corners(seg as usize);
    let segment = &view.segments()[seg as usize];
    if let Some(mb) = view.pd() {
        let on = sb
            .case
            .ghosts
            .on_plane
            .get(s as usize)
            .copied()
            .unwrap_or(0);
        for &(slave_bit, master_bit, axis) in planes {
            if on & slave_bit == 0 {
                continue;
            }
            if let Some(edge) = plane_edge(segment, |n| {
                mb.case.ghosts.on_plane[n as usize] & master_bit != 0
            }) {
                return project_on_plane_edge(p, x, edge, axis);
            }
        }
    }
    project_any(p, x, segment.is_triangle())
}

/// A read-only view of a master surface: node positions and segments.
#[derive(Clone, Copy)]
pub enum MasterView<'a> {
    Pd(&'a PdBody),
    Rigid(&'a RigidBody),
    /// A deformable body whose nodes stand shifted by a fixed offset each (the faces of a
    /// pre-crack, each moved onto the crack plane: [`ContactPass::crack`]).
    Shifted(&'a PdBody, &'a [Vec3]),
}

impl<'a> MasterView<'a> {
    /// A view of a body.
    pub fn of(body: &'a Body) -> MasterView<'a> {
        match body {
            Body::Deformable(b) => MasterView::Pd(b),
            Body::Rigid(b) => MasterView::Rigid(b),
        }
    }

    /// Current position of master node `i`.
    #[inline]
    pub fn node(&self, i: u32) -> Vec3 {
        match self {
            MasterView::Pd(b) => b.position(i as usize),
            MasterView::Rigid(b) => b.position(i as usize),
            MasterView::Shifted(b, shift) => b.position(i as usize) + shift[i as usize],
        }
    }

    /// The deformable body, if the master is one.
    pub fn pd(&self) -> Option<&'a PdBody> {
        match *self {
            MasterView::Pd(b) | MasterView::Shifted(b, _) => Some(b),
            MasterView::Rigid(_) => None,
        }
    }

    /// The master segments.
    pub fn segments(&self) -> &'a [MasterSegment] {
        match self {
            MasterView::Pd(b) | MasterView::Shifted(b, _) => b.segments(),
            MasterView::Rigid(b) => &b.faces,
        }
    }

    /// Current corners of segment `s`.
    #[inline]
    pub fn corners(&self, s: usize) -> [Vec3; 4] {
        self.segments()[s].nodes.map(|n| self.node(n))
    }
}

/// One slave in contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactPoint {
    /// Slave particle.
    pub slave: u32,
    /// Master segment.
    pub segment: u32,
    pub projection: Projection,
    /// The segment's own normal, along which the gap is measured (`projection.normal` is
    /// smoothed): the penetration's gradient in the slave's motion.
    pub gap_normal: Vec3,
    /// Penetration `δ_p = −g ≥ 0`.
    pub penetration: f64,
    /// Force on the slave (N): the normal force along the master's normal, plus friction's.
    pub force: Vec3,
    /// The normal part of `force`, N (≥ 0).
    pub normal_force: f64,
    /// With friction: whether the slave sticks (`Some(true)`) or slips; `None` without.
    pub stick: Option<bool>,
    /// With friction: the energy the tangential penalty holds, `|F_t|² / (2 k_t)`, J.
    pub tangential_energy: f64,
    /// With friction: the tangential force's stiffness across the slip in the master's
    /// tangent plane, N/m ([`friction::Tangential::stiffness`]; the static solver's
    /// tangent); 0 without.
    pub shear_stiffness: f64,
    /// With friction: the work slip has dissipated since the committed stick point,
    /// `μ F_n` times the distance the stick point moved, J.
    pub slip_work: f64,
}

impl ContactPoint {
    /// Friction's part of the force on the slave (zero without friction), N.
    pub fn tangential_force(&self) -> Vec3 {
        self.force - self.projection.normal * self.normal_force
    }
}

/// Slave particles of one body checked against the master segments of another.
#[derive(Clone, Debug)]
pub struct ContactPass {
    pub slave: usize,
    pub master: usize,
    pub law: ContactLaw,
    /// 1, or ½ for each pass of a two-pass pair (the two passes share the pair's stiffness).
    pub weight: f64,
    /// Slave spacing Δ.
    pub spacing: f64,
    /// Radius around a slave in which a segment's corner makes it a candidate (without skin).
    pub cutoff: f64,
    /// Skin (0.3 Δ).
    pub skin: f64,
    /// The slave body's surface particles (in a decomposed run, those of this rank).
    pub slaves: Vec<u32>,
    /// The slave body's surface particles over all ranks.
    pub slave_count: usize,
    /// Master nodes used by segments (the nodes whose motion the rebuild rule tracks).
    master_nodes: Vec<u32>,
    /// Master node → segments (CSR over node index).
    node_seg_offsets: Vec<u32>,
    node_segs: Vec<u32>,
    /// Per master segment, its unit normal in the reference configuration: which segments
    /// around a node are smooth neighbours ([`FEATURE_ANGLE`]) is decided on these, once.
    reference_normals: Vec<Vec3>,
    /// Segments found by bounding box (much larger than the slave spacing).
    big_segments: Vec<u32>,
    pub verlet: VerletList,
    /// Contacts found in the last evaluation.
    pub contacts: Vec<ContactPoint>,
    /// Slaves found behind a segment by more than the window in the last evaluation.
    pub missed: usize,
    /// The deepest of them (this process's): the slave, the segment, the gap (negative).
    pub deepest_miss: Option<Miss>,
    /// Per slave, the segment it touched in the last evaluation ([`NO_SEGMENT`] if none).
    held: Vec<u32>,
    /// Coulomb's μ (0: frictionless, and nothing below is kept).
    pub friction: f64,
    /// Per slave, its stick point as committed at the end of the last increment or step
    /// ([`commit_friction`](Self::commit_friction)); `None` out of contact.
    sticks: Vec<Option<Anchor>>,
    /// Per slave, the stick point the last evaluation found (what a commit keeps), and the
    /// work its slip dissipated.
    trial: Vec<Trial>,
    /// Per slave, the work friction has dissipated over the committed increments or steps,
    /// J (the explicit solver's energy balance).
    pub friction_work: Vec<f64>,
    /// For the faces of a pre-crack ([`ContactPass::crack`]): the sides.
    crack: Option<CrackSides>,
    /// Per particle of the body, for the faces of a pre-crack: the offset that moves a face
    /// particle onto the crack plane (empty otherwise).
    shift: std::sync::Arc<Vec<Vec3>>,
    /// Per particle of the body, for the faces of a pre-crack: the share of its cell a slave
    /// presses with (empty otherwise: all of it; [`ContactPass::slave_scale`]).
    area_share: std::sync::Arc<Vec<f64>>,
    /// For a body against the surfaces its broken bonds opened ([`ContactPass::found_faces`]).
    found: Option<FoundFaces>,
}

/// A slave behind a segment by more than the window: the slave, the segment, the gap
/// (negative).
pub type Miss = (u32, u32, f64);

/// A contact's stick point as the evaluation found it, and the work its slip dissipated
/// (`None` without friction).
type Trial = Option<(Anchor, f64)>;

/// What the narrow phase finds for one slave: its contact and stick point, or a miss.
type Found = (Option<(ContactPoint, Trial)>, Option<Miss>);

/// No segment held.
const NO_SEGMENT: u32 = u32::MAX;

impl ContactPass {
    /// Sets up a pass; `bodies[slave]` must be deformable.
    pub fn new(
        bodies: &[Body],
        slave: usize,
        master: usize,
        law: ContactLaw,
        weight: f64,
    ) -> ContactPass {
        let sb = bodies[slave]
            .as_pd()
            .expect("slave bodies are deformable (checked by the scene)");
        let slaves: Vec<u32> = (0..sb.len() as u32)
            .filter(|&i| sb.case.surface.is_surface[i as usize])
            .collect();
        ContactPass::new_with(bodies, slave, master, law, weight, slaves, |_| true)
    }

    /// A pass of the slaves `slaves` against the master's segments that `segment` keeps.
    fn new_with(
        bodies: &[Body],
        slave: usize,
        master: usize,
        law: ContactLaw,
        weight: f64,
        slaves: Vec<u32>,
        segment: impl Fn(usize) -> bool,
    ) -> ContactPass {
        let sb = bodies[slave]
            .as_pd()
            .expect("slave bodies are deformable (checked by the scene)");
        let spacing = sb.spacing();
        let slave_count = slaves.len();
        let view = MasterView::of(&bodies[master]);
        let segs = view.segments();
        let node_count = match view {
            MasterView::Pd(b) | MasterView::Shifted(b, _) => b.len(),
            MasterView::Rigid(b) => b.vertices.len(),
        };
        // Segments whose half-diagonal exceeds 1.5 Δ go to the bounding-box phase.
        let half_diag = |s: &MasterSegment| {
            let c = s.nodes.map(|n| view.node(n));
            0.5 * (c[2] - c[0]).norm().max((c[3] - c[1]).norm())
        };
        let mut big_segments = Vec::new();
        let mut max_small = 0.0f64;
        let mut count = vec![0u32; node_count + 1];
        for (k, s) in segs.iter().enumerate().filter(|(k, _)| segment(*k)) {
            let h = half_diag(s);
            if h > 1.5 * spacing {
                big_segments.push(k as u32);
            } else {
                max_small = max_small.max(h);
                for n in distinct(&s.nodes) {
                    count[n as usize + 1] += 1;
                }
            }
        }
        for i in 0..node_count {
            count[i + 1] += count[i];
        }
        let mut fill = count.clone();
        let mut node_segs = vec![0u32; count[node_count] as usize];
        for (k, s) in segs.iter().enumerate().filter(|(k, _)| segment(*k)) {
            if big_segments.binary_search(&(k as u32)).is_ok() {
                continue;
            }
            for n in distinct(&s.nodes) {
                node_segs[fill[n as usize] as usize] = k as u32;
                fill[n as usize] += 1;
            }
        }
        let mut master_nodes: Vec<u32> = segs
            .iter()
            .enumerate()
            .filter(|(k, _)| segment(*k))
            .flat_map(|(_, s)| s.nodes)
            .collect();
        master_nodes.sort_unstable();
        master_nodes.dedup();
        let reference_normals = normal::reference_normals(view);
        let window = law.window;
        // A slave inside a segment's projection within the window is at most this far from the
        // segment's nearest corner.
        let cutoff = (max_small * max_small + window * window)
            .sqrt()
            .max(spacing);
        ContactPass {
            slave,
            master,
            law,
            weight,
            spacing,
            cutoff,
            skin: SKIN * spacing,
            slaves,
            slave_count,
            master_nodes,
            node_seg_offsets: count,
            node_segs,
            reference_normals,
            big_segments,
            verlet: VerletList::default(),
            contacts: Vec::new(),
            missed: 0,
            deepest_miss: None,
            held: vec![NO_SEGMENT; slave_count],
            friction: 0.0,
            sticks: Vec::new(),
            trial: Vec::new(),
            friction_work: Vec::new(),
            crack: None,
            shift: Default::default(),
            area_share: Default::default(),
            found: None,
        }
    }

    /// The master as this pass sees it (a crack's faces shifted onto its plane).
    fn view<'a>(&self, bodies: &'a [Body], shift: &'a [Vec3]) -> MasterView<'a> {
        match &bodies[self.master] {
            Body::Deformable(b) if !shift.is_empty() => MasterView::Shifted(b, shift),
            b => MasterView::of(b),
        }
    }

    /// Where slave particle `s` meets the master: its position (a crack's face particle
    /// shifted onto the crack plane).
    #[inline]
    fn slave_point(&self, sb: &PdBody, s: u32) -> Vec3 {
        if let Some(f) = &self.found {
            return sb.position(s as usize) + f.onto[s as usize];
        }
        sb.position(s as usize) + self.shift.get(s as usize).copied().unwrap_or_default()
    }

    /// The normal slave `s` faces its master by: on the faces broken bonds opened, the one
    /// found there, turned as its intact bonds say.
    fn facing_normal(&self, sb: &PdBody, s: u32) -> Vec3 {
        match &self.found {
            Some(f) => narrow::turned_normal(
                sb,
                s as usize,
                f.normal[s as usize],
                sb.fracture.as_ref().map(|f| f.intact.as_slice()),
            ),
            None => slave_normal(sb, s as usize),
        }
    }

    /// [`project_plain`] of slave `s` at `p` on segment `seg`; on the faces broken bonds
    /// opened, a slave that stood behind the segment before the load (where the faces'
    /// particles were rough) starts there.
    fn project_from_rest(
        &self,
        sb: &PdBody,
        view: MasterView,
        planes: &[(u8, u8, usize)],
        (s, p, seg): (u32, Vec3, u32),
    ) -> Option<(Projection, f64)> {
        let (mut pr, outside) = project_plain(sb, view, planes, s, p, seg)?;
        if let Some(f) = &self.found {
            let segment = &view.segments()[seg as usize];
            pr.gap -= f.reference_gap(sb, s, segment, &self.shift, &pr).min(0.0);
        }
        Some((pr, outside))
    }

    /// Finds the contacts of this pass at the current positions (broad phase as needed, then
    /// narrow phase). Forces are computed, not applied.
    pub fn detect(&mut self, bodies: &[Body]) {
        let sb = bodies[self.slave].as_pd().expect("slave is deformable");
        let shift = self.shift.clone();
        let rebuild = self.needs_rebuild(sb, self.view(bodies, &shift));
        self.detect_with(bodies, rebuild);
    }

    /// The two largest moves of this pass's slaves and of the master nodes `counts` accepts
    /// since the Verlet list was built (`None` before it is): what decides a rebuild, to be
    /// merged over the ranks of a decomposed run ([`crate::model::domain`]), each rank
    /// counting the master nodes it owns.
    pub fn largest_moves(&self, bodies: &[Body], counts: impl Fn(u32) -> bool) -> Option<TopTwo> {
        let sb = bodies[self.slave].as_pd().expect("slave is deformable");
        let shift = self.shift.clone();
        self.moves(sb, self.view(bodies, &shift), counts)
    }

    /// Keeps the slaves of `owned` only: a rank of a decomposed run detects contact for its
    /// own particles.
    pub fn keep_slaves(&mut self, owned: std::ops::Range<usize>) {
        if let Some(c) = &mut self.crack {
            let keep: Vec<bool> = self
                .slaves
                .iter()
                .map(|&s| owned.contains(&(s as usize)))
                .collect();
            let mut k = 0;
            c.slave_side.retain(|_| (keep[k], k += 1).0);
        }
        self.slaves.retain(|&s| owned.contains(&(s as usize)));
        self.held = vec![NO_SEGMENT; self.slaves.len()];
        if self.friction > 0.0 {
            self.reset_friction();
        }
        self.verlet = VerletList::default();
    }

    /// [`detect`](Self::detect) with the rebuild decided by the caller.
    pub fn detect_with(&mut self, bodies: &[Body], rebuild: bool) {
        let sb = bodies[self.slave].as_pd().expect("slave is deformable");
        let shift = self.shift.clone();
        let view = self.view(bodies, &shift);
        if rebuild {
            self.rebuild(sb, view);
        }
        let segs = view.segments();
        let window = self.law.window;
        let planes = shared_planes(sb, view);
        let project_on =
            |s: u32, p: Vec3, seg: u32| self.project_from_rest(sb, view, &planes, (s, p, seg));
        let contact = |k: usize, s: u32, segment: u32, mut pr: Projection| {
            let gap_normal = pr.normal;
            pr.normal = self.smooth_normal(view, segment, &pr);
            let d = -pr.gap;
            // A slave on a symmetry plane, or at a crack's front, is only part of its particle.
            let scale = self.slave_scale(sb, s as usize);
            let f = scale * self.law.force(d);
            let mut point = ContactPoint {
                slave: s,
                segment,
                projection: pr,
                gap_normal,
                penetration: d,
                force: pr.normal * f,
                normal_force: f,
                stick: None,
                tangential_energy: 0.0,
                shear_stiffness: 0.0,
                slip_work: 0.0,
            };
            let anchor = (self.friction > 0.0).then(|| {
                self.add_friction(
                    view,
                    k,
                    &mut point,
                    scale * self.law.relaxation_stiffness(d),
                )
            });
            let trial = anchor.map(|a| (a, point.slip_work));
            (Some((point, trial)), None)
        };
        let edge_margin = self.edge_margin();
        let results: Vec<Found> = (0..self.slaves.len())
            .into_par_iter()
            .map_init(Vec::new, |projections, k| {
                let s = self.slaves[k];
                let p = self.slave_point(sb, s);
                let (a, b) = (
                    self.verlet.offsets[k] as usize,
                    self.verlet.offsets[k + 1] as usize,
                );
                // A slave keeps the segment it touched while it stays inside it and within the
                // window: at a convex master's corner, where the slave's own normal turns with
                // the distortion around it, the normals cannot tell which face it is pressed on.
                let held = self.held[k];
                let kept = (held != NO_SEGMENT)
                    .then(|| project_on(s, p, held))
                    .flatten()
                    .filter(|(pr, outside)| *outside == 0.0 && within_window(pr, window))
                    .map(|(pr, _)| pr);
                if let Some(pr) = kept {
                    return contact(k, s, held, pr);
                }
                // Each candidate is projected once: the inside projections choose the segment,
                // and all of them serve the rule for concave edges when none does.
                projections.clear();
                projections.extend(self.verlet.candidates[a..b].iter().filter_map(|&seg| {
                    project_on(s, p, seg).map(|(pr, outside)| (seg, pr, outside))
                }));
                let normal = std::cell::LazyCell::new(|| self.facing_normal(sb, s));
                // A crack's face particle at the face's edge lies on the other face's edge;
                // the faces' lateral strains differ by a hair, and it would drop off that edge
                // and back in by turns: within a margin it stays on the segment it is nearest.
                // On the faces found again, a segment the slave does not face (the outer face
                // of the other side, seen edge-on from the crack's edge) does not hold it off
                // the face across.
                let any_inside = projections.iter().any(|c| {
                    c.2 == 0.0 && (self.found.is_none() || normal.dot(&c.1.normal) < -FACING)
                });
                // Beyond every segment of a pre-crack's face, the slave presses on the one
                // it is nearest: the nearest's plane continues the one it just left, where
                // another segment's plane, tilted by a hair under load and extended a quarter
                // spacing, would read its gap microns off and switch the force by as much each
                // time the slave crossed the edge (a gmsh tet10 block cut across did not
                // settle so). The faces found again keep the choice by the gap: they place
                // their slaves by a rule of their own (`crack::onto_faces`), and the nearest
                // segment there left two blocks cut across unsettled.
                let nearest = if any_inside || self.found.is_some() {
                    f64::INFINITY
                } else {
                    projections
                        .iter()
                        .map(|c| c.2)
                        .filter(|&o| o > 0.0)
                        .fold(f64::INFINITY, f64::min)
                };
                let inside = projections
                    .iter()
                    .filter(|c| {
                        c.2 == 0.0
                            || (!any_inside && c.2 <= edge_margin && c.2 <= nearest * (1.0 + 1e-9))
                    })
                    .map(|&(seg, pr, _)| (seg, pr));
                match select_segment(inside, || *normal, window) {
                    Touch::Contact(seg, pr) => contact(k, s, seg, pr),
                    // Among the pieces of a breaking body a particle behind a face it lost
                    // its bonds to is as often on a sliver's far side, or in crushed
                    // material, as through the face: not taken for a missed contact.
                    Touch::Missed(..) if self.found.is_some() => (None, None),
                    Touch::Missed(seg, gap) => (None, Some((s, seg, gap))),
                    Touch::Clear => match select_across_edge(
                        p,
                        projections.iter().copied(),
                        |seg| segs[seg as usize].nodes,
                        |seg| view.corners(seg as usize),
                        || *normal,
                        window,
                    ) {
                        Some((seg, pr)) => contact(k, s, seg, pr),
                        None => (None, None),
                    },
                }
            })
            .collect();
        self.missed = results.iter().filter(|r| r.1.is_some()).count();
        // The deepest, the first of equals: the same over any number of threads.
        self.deepest_miss = results.iter().filter_map(|r| r.1).fold(
            None,
            |d: Option<(u32, u32, f64)>, m| match d {
                Some(d) if d.2 <= m.2 => Some(d),
                _ => Some(m),
            },
        );
        for (held, r) in self.held.iter_mut().zip(&results) {
            *held = r.0.as_ref().map_or(NO_SEGMENT, |c| c.0.segment);
        }
        if self.friction > 0.0 {
            for (t, r) in self.trial.iter_mut().zip(&results) {
                *t = r.0.and_then(|c| c.1);
            }
        }
        self.contacts = results
            .into_iter()
            .filter_map(|r| r.0.map(|c| c.0))
            .collect();
    }

    /// Adds this pass's forces and contact stiffness to the bodies.
    pub fn apply(&self, bodies: &mut [Body]) {
        self.apply_to_slaves(bodies);
        match &mut bodies[self.master] {
            Body::Deformable(mb) => {
                for (n, f, k) in self.reactions(&mb.case.segments.segments) {
                    let n = n as usize;
                    mb.force[n] += f;
                    mb.contact_force[n] += f;
                    mb.reaction_force[n] += f;
                    mb.contact_stiffness[n] += k;
                }
                if let Some(fr) = &mut mb.friction {
                    for (n, t) in self.friction_reactions(&mb.case.segments.segments) {
                        fr.force[n as usize] += t;
                        fr.reaction[n as usize] += t;
                    }
                }
            }
            Body::Rigid(rb) => {
                for g in self.block_sums(Some(rb.axis)) {
                    rb.contact_force -= Vec3::new(g[0], g[1], g[2]);
                    rb.contact_stiffness += g[3];
                }
            }
        }
    }

    /// The candidate segments of slave `k` of this pass (an index into `slaves`) at the last
    /// Verlet rebuild.
    pub fn candidates(&self, k: usize) -> &[u32] {
        match (self.verlet.offsets.get(k), self.verlet.offsets.get(k + 1)) {
            (Some(&a), Some(&b)) if b > a => &self.verlet.candidates[a as usize..b as usize],
            _ => &[],
        }
    }

    /// Whether slave `k` of this pass (an index into `slaves`) had a candidate segment at the
    /// last Verlet rebuild: it may touch within a step (the slaves that ADR's density and the
    /// static solver's stabilisation weigh).
    pub fn may_touch(&self, k: usize) -> bool {
        !self.candidates(k).is_empty()
    }

    /// The slave side of [`apply`](Self::apply): the contacts' forces on the slaves and the
    /// contact stiffness of every slave that may touch.
    pub fn apply_to_slaves(&self, bodies: &mut [Body]) {
        let sb = bodies[self.slave].as_pd_mut().expect("slave is deformable");
        // Every slave with a candidate segment may touch within a step: it gets the tangent
        // of a light contact, and a slave in contact its own (ADR's density only: the
        // explicit step takes the largest tangent, `explicit::stable_time_step`).
        let may_touch = self.weight * self.law.relaxation_stiffness(0.0);
        for (k, &s) in self.slaves.iter().enumerate() {
            if self.verlet.offsets[k + 1] > self.verlet.offsets[k] {
                sb.contact_stiffness[s as usize] += may_touch;
            }
        }
        let factor = self.stiffness_factor();
        for c in &self.contacts {
            sb.force[c.slave as usize] += c.force;
            sb.contact_force[c.slave as usize] += c.force;
            // A contact is found among its slave's candidates, so the slave holds `may_touch`.
            sb.contact_stiffness[c.slave as usize] +=
                self.weight * self.law.relaxation_stiffness(c.penetration) * factor - may_touch;
            if let (Some(fr), Some(stick)) = (&mut sb.friction, c.stick) {
                let s = c.slave as usize;
                fr.force[s] += c.tangential_force();
                // Slipping in any pair reads as slipping.
                let state = i8::from(stick);
                fr.stick[s] = if fr.stick[s] < 0 {
                    state
                } else {
                    fr.stick[s].min(state)
                };
            }
        }
    }

    /// The reactions on a deformable master of segments `segments`, in the order [`apply`](Self::apply) adds
    /// them (contact by contact, corner by corner): `(node, force, stiffness)`, the force
    /// `−F N_i(r, t)` of Eq. 20's weights. A decomposed run sends each to the node's owner,
    /// who adds them in this order, rank after rank ([`crate::model::domain`]).
    pub fn reactions<'a>(
        &'a self,
        segments: &'a [MasterSegment],
    ) -> impl Iterator<Item = (u32, Vec3, f64)> + 'a {
        self.contacts.iter().flat_map(move |c| {
            let nodes = segments[c.segment as usize].nodes;
            let tangent = self.weight
                * self.law.relaxation_stiffness(c.penetration)
                * self.stiffness_factor();
            (0..4).filter_map(move |k| {
                let w = c.projection.weights[k];
                (w != 0.0).then(|| (nodes[k], -(c.force * w), tangent * w.abs()))
            })
        })
    }

    /// Energy stored by contact `c`: `∫ F dδ` for `F = K δ^{3/2}`, `F δ (2/5)` (Hertz), or
    /// `F δ / 2` (linear). The force applied, so that a slave on a symmetry plane counts only
    /// its share, as its force does.
    pub fn energy(&self, c: &ContactPoint) -> f64 {
        // Without friction the force is the normal one (its norm, as always measured).
        if self.friction > 0.0 {
            let f = c.normal_force;
            return c.tangential_energy
                + match self.law.law {
                    crate::scene::PenaltyLaw::Hertz => 0.4 * f * c.penetration,
                    crate::scene::PenaltyLaw::Linear => 0.5 * f * c.penetration,
                };
        }
        let f = c.force.norm();
        match self.law.law {
            crate::scene::PenaltyLaw::Hertz => 0.4 * f * c.penetration,
            crate::scene::PenaltyLaw::Linear => 0.5 * f * c.penetration,
        }
    }
}

#[cfg(test)]
mod tests;
