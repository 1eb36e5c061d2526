//! A scene turned into bodies and contact passes, and the force evaluation the solvers call.
//!
//! `compute_forces` is one evaluation of Eq. 28: bond forces of every deformable body (Eq. 26
//! with the surface and volume corrections), applied loads, and contact forces.

pub mod domain;
mod found;
pub mod path;
mod serial;

use std::sync::Arc;

use rayon::prelude::*;

use self::domain::Domain;
use self::found::found_faces_pass;
pub use self::found::FOUND_FACES_EVERY;
use self::path::{LoadPath, Prescribed, RampedLoad};

use crate::body::lps::Stretch;
use crate::body::{build_body_on, Body, PdBody, FIX_X, FIX_Y, FIX_Z};
use crate::case::pairs::{pair_forces, PairKinematics};
use crate::contact::estimate::{resolve, ContactResolution, ContactSurface};
use crate::contact::fragments::FragmentPass;
use crate::contact::shortrange::ShortRangePass;
use crate::contact::{default_radius, hertz_stiffness, ContactLaw, ContactPass, WINDOW};
use crate::error::Result;
use crate::math::{Vec3, NOT_A_PARTICLE};
use crate::parallel::Comm;
use crate::scene::{excerpt, Axis, BodyKind, ContactMethod, Kinematics, Scene, SelfFaces};

/// Bodies and contact passes of a scene.
#[derive(Clone, Debug)]
pub struct Model {
    pub bodies: Vec<Body>,
    pub passes: Vec<ContactPass>,
    /// Pairs resolved by the short-range method.
    pub short_range: Vec<ShortRangePass>,
    /// The repulsion between the pieces of breaking bodies (a body its own short-range
    /// master, [`crate::contact::fragments`]).
    pub fragments: Vec<FragmentPass>,
    /// Force evaluations so far.
    pub evaluations: usize,
    /// Scratch: current positions of each deformable body.
    positions: Vec<Vec<Vec3>>,
    /// This rank's part, in a run decomposed over several processes.
    pub domain: Option<Domain>,
    /// Ramped loads and prescribed displacements along a quasi-static load path.
    pub path: LoadPath,
    /// Bonds do not fail in a force evaluation: the static solver breaks them between
    /// equilibria ([`Model::break_overstretched`]), not at the trial states of its line
    /// searches.
    pub hold_bonds: bool,
}

impl Model {
    /// Builds bodies, loads, constraints and contact passes from a scene.
    pub fn from_scene(scene: &Scene) -> Result<Model> {
        Model::from_scene_on(scene, None)
    }

    /// [`Model::from_scene`] for a run decomposed over the ranks of `comm`: each rank builds
    /// its part of the bodies that can be built so ([`crate::case::part`]); call
    /// [`Model::distribute`] with the same `comm` next. Collective.
    pub fn from_scene_on(scene: &Scene, comm: Option<&Arc<dyn Comm>>) -> Result<Model> {
        let mut bodies = Vec::with_capacity(scene.bodies.len());
        for spec in &scene.bodies {
            bodies.push(build_body_on(scene, spec, comm)?);
        }
        let index = |name: &str| scene.bodies.iter().position(|b| b.name == name);
        let mut path = LoadPath::default();

        for load in &scene.loads {
            let k = index(&load.body).ok_or_else(|| scene.error_at(&load.body, "no such body"))?;
            let force = Vec3::from(load.force);
            match &mut bodies[k] {
                Body::Rigid(rb) => {
                    if load.set.is_some() {
                        return Err(scene.error_at(
                            "set",
                            &format!("load on rigid body \"{}\": a rigid body takes its load as a whole (drop `set`)", load.body),
                        ));
                    }
                    rb.load += force;
                    if let Some(ramp) = load.ramp {
                        path.ramped.push(RampedLoad {
                            body: k,
                            ramp,
                            parts: Vec::new(),
                            whole: force,
                        });
                    }
                }
                Body::Deformable(pd) => {
                    let particles = match &load.set {
                        Some(set) => set_particles(scene, pd, set)?,
                        None => (0..pd.len() as u32).collect(),
                    };
                    let total: f64 = particles
                        .iter()
                        .map(|&p| pd.case.particles.volume[p as usize])
                        .sum();
                    let parts: Vec<(u32, Vec3)> = particles
                        .iter()
                        .map(|&p| (p, force * (pd.case.particles.volume[p as usize] / total)))
                        .collect();
                    for &(p, f) in &parts {
                        pd.load[p as usize] += f;
                    }
                    if let Some(ramp) = load.ramp {
                        path.ramped.push(RampedLoad {
                            body: k,
                            ramp,
                            parts,
                            whole: Vec3::zeros(),
                        });
                    }
                }
            }
        }
        for c in &scene.constraints {
            let k = index(&c.body).ok_or_else(|| scene.error_at(&c.body, "no such body"))?;
            let Some(pd) = bodies[k].as_pd_mut() else {
                continue;
            };
            let mut mask = 0;
            for f in &c.fix {
                mask |= match f {
                    Axis::X => FIX_X,
                    Axis::Y => FIX_Y,
                    Axis::Z => FIX_Z,
                };
            }
            let particles = match (&c.set, c.nearest) {
                (Some(set), _) => set_particles(scene, pd, set)?,
                (None, Some(point)) => nearest_particle(pd, Vec3::from(point))
                    .into_iter()
                    .collect(),
                (None, None) => Vec::new(),
            };
            for &p in &particles {
                pd.fixed[p as usize] |= mask;
            }
            if let Some(d) = c.displacement {
                path.prescribed.push(Prescribed {
                    body: k,
                    particles,
                    mask,
                    displacement: Vec3::from(d),
                    ramp: c.ramp,
                });
            }
        }

        let mut passes = Vec::new();
        let mut short_range = Vec::new();
        let mut fragments = Vec::new();
        for c in &scene.contacts {
            let (Some(s), Some(m)) = (index(&c.slave), index(&c.master)) else {
                continue;
            };
            if c.method == ContactMethod::ShortRange {
                if s == m {
                    fragments.push(FragmentPass::new(&bodies, s));
                } else {
                    short_range.push(ShortRangePass::new(&bodies, s, m));
                }
                continue;
            }
            let add = |s: usize, m: usize, weight: f64, bodies: &[Body]| {
                let sb = bodies[s].as_pd().expect("slave is deformable");
                let m_slave = sb.material.compliance();
                let m_master = match &bodies[m] {
                    Body::Deformable(b) => b.material.compliance(),
                    Body::Rigid(b) => b.material.map_or(0.0, |mat| mat.compliance()),
                };
                let radius = c.radius.unwrap_or(default_radius(sb.spacing()));
                let law = ContactLaw {
                    law: c.penalty,
                    stiffness: hertz_stiffness(m_slave, m_master, radius),
                    window: WINDOW * sb.spacing(),
                };
                ContactPass::new(bodies, s, m, law, weight).with_friction(c.friction)
            };
            if c.friction > 0.0 {
                for k in [s, m] {
                    if let Some(pd) = bodies[k].as_pd_mut() {
                        pd.friction = Some(crate::body::FrictionForces::new(pd.len()));
                    }
                }
            }
            // A mesh of several pieces keeps its pieces' pass unless the faces are asked for.
            let pieces = || {
                let pd = bodies[s].as_pd().expect("checked deformable");
                pd.case.bonds.components(|_| true).1.len() > 1
            };
            if s == m
                && scene.self_faces(c) == Some(SelfFaces::Found)
                && (c.faces.is_some() || !pieces())
            {
                // The surfaces its broken bonds open ([`ContactPass::found_faces`]), flat
                // where they meet as a crack's faces do.
                let pd = bodies[s].as_pd().expect("checked deformable");
                let window = WINDOW * pd.spacing();
                let law = match c.radius {
                    Some(radius) => {
                        let m_body = pd.material.compliance();
                        ContactLaw {
                            law: c.penalty,
                            stiffness: hertz_stiffness(m_body, m_body, radius),
                            window,
                        }
                    }
                    None => crack_face_law(pd, window),
                };
                let built = pd.segments().len();
                passes.push(found_faces_pass(&mut bodies, s, built, law, 0));
                continue;
            }
            if s == m {
                // The faces of the body's pre-cracks ([`ContactPass::crack`]).
                let pd = bodies[s].as_pd().expect("checked deformable");
                let m_body = pd.material.compliance();
                let window = WINDOW * pd.spacing();
                let law = match c.radius {
                    Some(radius) => ContactLaw {
                        law: c.penalty,
                        stiffness: hertz_stiffness(m_body, m_body, radius),
                        window,
                    },
                    None => crack_face_law(pd, window),
                };
                for f in 0..pd.crack_faces.len() {
                    passes.push(ContactPass::crack(&bodies, s, f, law));
                }
                if pd.crack_faces.is_empty() {
                    // A mesh of solids that share no node: its pieces against each other.
                    let (piece, sizes) = pd.case.bonds.components(|_| true);
                    if sizes.len() < 2 {
                        return Err(crate::error::Error::input(format!(
                            "contact pair names body \"{}\" as both slave and master: a body is its own master across the faces of its pre-cracks or between its pieces (solids of its mesh that no bond joins), and \"{}\" has no [[precrack]] and is one piece (contact between two bodies names two)",
                            scene.bodies[s].name, scene.bodies[s].name
                        )));
                    }
                    if sizes.len() >= u8::MAX as usize {
                        return Err(crate::error::Error::input(format!(
                            "body \"{}\" is {} pieces that no bond joins: contact between a body's pieces handles up to {}; mesh the pieces as bodies of their own",
                            scene.bodies[s].name,
                            sizes.len(),
                            u8::MAX - 1
                        )));
                    }
                    let law = ContactLaw {
                        law: c.penalty,
                        stiffness: hertz_stiffness(
                            m_body,
                            m_body,
                            c.radius.unwrap_or(default_radius(pd.spacing())),
                        ),
                        window,
                    };
                    passes.push(ContactPass::pieces(&bodies, s, &piece, law));
                }
                continue;
            }
            let two = c.two_pass && scene.bodies[m].kind == BodyKind::Deformable;
            let w = if two { 0.5 } else { 1.0 };
            passes.push(add(s, m, w, &bodies));
            if two {
                passes.push(add(m, s, w, &bodies));
            }
        }
        let positions = bodies
            .iter()
            .map(|b| {
                b.as_pd()
                    .map_or(Vec::new(), |pd| vec![Vec3::zeros(); pd.len()])
            })
            .collect();
        Ok(Model {
            bodies,
            passes,
            short_range,
            fragments,
            evaluations: 0,
            positions,
            domain: None,
            path,
            hold_bonds: false,
        })
    }

    /// The contact pairs, slave and master, each once (the second pass of a two-pass pair is
    /// its first reversed).
    pub fn contact_pairs(&self) -> Vec<(usize, usize)> {
        let mut pairs: Vec<(usize, usize)> = Vec::new();
        for p in &self.passes {
            if !pairs.contains(&(p.master, p.slave)) {
                pairs.push((p.slave, p.master));
            }
        }
        pairs.extend(self.short_range.iter().map(|p| (p.slave, p.master)));
        pairs
    }

    /// Whether pass `p` presses one deformable body on another checked one way only
    /// (`two_pass = false`): the master's nodes are then nobody's slaves, and nothing but
    /// the contacts on their segments weighs them in ADR's density.
    pub fn is_one_way_deformable(&self, p: &ContactPass) -> bool {
        p.weight == 1.0
            && p.slave != p.master
            && matches!(self.bodies[p.master], Body::Deformable(_))
            && !self
                .passes
                .iter()
                .any(|q| q.slave == p.master && q.master == p.slave)
    }

    /// The Hertz estimate of every contact pair under the applied loads, and how the slave's
    /// particles resolve it ([`crate::contact::estimate`]), at the reference configuration.
    pub fn contact_resolution(&self) -> Vec<ContactResolution> {
        self.contact_pairs()
            .into_iter()
            // A crack's faces meet flat: no Hertz contact to estimate.
            .filter(|&(s, m)| s != m)
            .map(|(s, m)| {
                let r = resolve(
                    &ContactSurface::of_body(&self.bodies[s]),
                    &ContactSurface::of_body(&self.bodies[m]),
                );
                let r = match self.bodies[s].as_pd() {
                    Some(pd) => r.with_mesh_hints(&pd.case),
                    None => r,
                };
                // A two-pass pair's passes share its stiffness; a short-range pair has none.
                match self.passes.iter().find(|p| p.slave == s && p.master == m) {
                    Some(p) => r.with_penalty(&p.law),
                    None => r,
                }
            })
            .collect()
    }

    /// Decomposes the model over the ranks of `comm` ([`domain`]): from here on this process
    /// evaluates and moves its own particles. Collective.
    pub fn distribute(&mut self, comm: Arc<dyn Comm>) -> Result<()> {
        // Every rank refuses alike, before any collective call.
        self.check_distributable()?;
        let domain = Domain::new(&self.bodies, &self.passes, &self.short_range, comm);
        let rank = domain.rank();
        for (k, body) in self.bodies.iter_mut().enumerate() {
            if let Some(pd) = body.as_pd_mut() {
                pd.owned = domain.ranges[k][rank].clone();
                // A case built as this rank's part has the rows of the pairs that act on its
                // particles, and only those: its list is already the restricted one.
                pd.pairs = if pd.case.part.is_some() {
                    std::mem::take(&mut pd.pairs).owning(pd.owned.clone())
                } else {
                    pd.pairs.restricted(pd.owned.clone())
                };
                pd.force_buffers = Default::default();
            }
        }
        for pass in &mut self.passes {
            pass.keep_slaves(domain.ranges[pass.slave][rank].clone());
        }
        for pass in &mut self.short_range {
            pass.keep_own(
                domain.ranges[pass.slave][rank].clone(),
                domain.ranges[pass.master][rank].clone(),
            );
        }
        self.domain = Some(domain);
        Ok(())
    }

    /// In a decomposed run, gives every rank every particle's state (collective); otherwise
    /// nothing. Call before reading the whole model: frames, checks, the summary.
    pub fn gather(&mut self) {
        if let Some(d) = &self.domain {
            d.gather(&mut self.bodies);
        }
    }

    /// `Σ_ranks mine[k]`, in rank order, in a decomposed run (collective); `mine` otherwise.
    pub fn sum_over_ranks(&self, mine: Vec<f64>) -> Vec<f64> {
        match &self.domain {
            Some(d) => d.comm().sum(&mine),
            None => mine,
        }
    }

    /// Per deformable body, `width` sums over its particles in the fixed order of
    /// [`block_sums`](crate::reduction::block_sums), then `extra` values summed over the ranks
    /// (collective in a decomposed run). `mine` holds, body after body, the sums of this
    /// process's blocks (`width` values a block, over its own particles), then the `extra`
    /// values. Every rank's blocks are added in order from zero: the ranges of a
    /// decomposition start on a block, so a decomposed run gets the bits of one process.
    pub fn sum_blocks(
        &self,
        mine: Vec<f64>,
        width: usize,
        extra: usize,
    ) -> (Vec<Vec<f64>>, Vec<f64>) {
        let parts = match &self.domain {
            Some(d) => d.comm().all_gather_varcount(&mine),
            None => vec![mine],
        };
        let deformable: Vec<(usize, &PdBody)> = self
            .bodies
            .iter()
            .enumerate()
            .filter_map(|(k, b)| b.as_pd().map(|pd| (k, pd)))
            .collect();
        let mut sums = vec![vec![0.0; width]; deformable.len()];
        let mut rest = vec![0.0; extra];
        for (q, part) in parts.iter().enumerate() {
            let mut at = 0;
            for (s, &(k, pd)) in sums.iter_mut().zip(&deformable) {
                let range = match &self.domain {
                    Some(d) => d.ranges[k][q].clone(),
                    None => pd.owned.clone(),
                };
                for _ in 0..range.len().div_ceil(crate::reduction::BLOCK) {
                    for (a, v) in s.iter_mut().zip(&part[at..at + width]) {
                        *a += v;
                    }
                    at += width;
                }
            }
            for (a, v) in rest.iter_mut().zip(&part[at..at + extra]) {
                *a += v;
            }
        }
        (sums, rest)
    }

    /// The largest of every rank's `mine` (collective in a decomposed run).
    pub fn max_over_ranks(&self, mine: f64) -> f64 {
        match &self.domain {
            Some(d) => d
                .comm()
                .all_gather(&[mine])
                .into_iter()
                .fold(mine, f64::max),
            None => mine,
        }
    }

    /// This process's rank (0 without decomposition).
    pub fn rank(&self) -> usize {
        self.domain.as_ref().map_or(0, Domain::rank)
    }

    /// Total particles.
    pub fn particles(&self) -> usize {
        self.bodies
            .iter()
            .filter_map(Body::as_pd)
            .map(PdBody::len)
            .sum()
    }

    /// Total directed bonds.
    pub fn bonds(&self) -> usize {
        self.bodies
            .iter()
            .filter_map(Body::as_pd)
            .map(|b| b.case.bond_count())
            .sum()
    }

    /// Breaks the bonds past their critical stretch at the current displacements (one
    /// process; [`Model::hold_bonds`]) and returns how many broke. The forces are not
    /// evaluated again.
    pub fn break_overstretched(&mut self) -> usize {
        let mut broken = 0;
        for (body, pos) in self.bodies.iter_mut().zip(&mut self.positions) {
            let Some(pd) = body.as_pd_mut() else { continue };
            let Some(fr) = pd
                .fracture
                .as_ref()
                .filter(|f| f.critical_stretch.is_some())
            else {
                continue;
            };
            pd.extended_positions(pos);
            let failed = fr.failing(&pd.case.bonds, pos, &pd.reference, pd.owned.clone());
            let failed = pd.spare_compressed(failed, pos);
            if !failed.is_empty() {
                let before = pd.fracture.as_ref().map_or(0, |f| f.broken);
                pd.break_failed(&failed, pos);
                broken += pd.fracture.as_ref().map_or(0, |f| f.broken) - before;
            }
        }
        broken
    }

    /// Evaluates all forces at the current displacements.
    pub fn compute_forces(&mut self) {
        self.evaluations += 1;
        if let Some(d) = &self.domain {
            d.share_displacements(&mut self.bodies);
        }
        let (domain, hold) = (&self.domain, self.hold_bonds);
        for (k, (body, pos)) in self.bodies.iter_mut().zip(&mut self.positions).enumerate() {
            match body {
                Body::Deformable(pd) => internal_forces_with(
                    pd,
                    pos,
                    hold,
                    |v| {
                        if let Some(d) = domain {
                            d.share(k, v);
                        }
                    },
                    |mine| match domain {
                        Some(d) => d.all_failed(&mine),
                        None => mine,
                    },
                ),
                Body::Rigid(rb) => {
                    rb.contact_force = Vec3::zeros();
                    rb.contact_stiffness = 0.0;
                }
            }
        }
        self.refresh_found_faces();
        match &self.domain {
            Some(d) => {
                let rebuild = d.rebuilds(&self.bodies, &self.passes);
                for (pass, r) in self.passes.iter_mut().zip(rebuild) {
                    pass.detect_with(&self.bodies, r);
                }
            }
            None => {
                for k in 0..self.passes.len() {
                    self.passes[k].detect(&self.bodies);
                }
            }
        }
        for pass in &mut self.short_range {
            pass.detect(&self.bodies);
        }
        for pass in &mut self.fragments {
            pass.detect(&self.bodies);
        }
        match &mut self.domain {
            Some(d) => d.apply_contact(&mut self.bodies, &mut self.passes),
            None => {
                for pass in &self.passes {
                    pass.apply(&mut self.bodies);
                }
            }
        }
        for pass in &self.short_range {
            pass.apply(&mut self.bodies);
        }
        for pass in &self.fragments {
            pass.apply(&mut self.bodies);
        }
        if let Some(d) = &self.domain {
            d.finish_short_range(&mut self.short_range);
        }
    }

    /// Keeps the stick points of every pass with friction as the history the next
    /// increment or step starts from ([`ContactPass::commit_friction`]).
    pub fn commit_friction(&mut self) {
        for pass in &mut self.passes {
            pass.commit_friction();
        }
    }

    /// Sum of the applied loads on all bodies.
    pub fn applied_load(&self) -> Vec3 {
        self.bodies
            .iter()
            .map(|b| match b {
                Body::Deformable(pd) => pd.load.iter().sum(),
                Body::Rigid(rb) => rb.load,
            })
            .sum()
    }

    /// Contacts found in the last evaluation.
    pub fn contact_count(&self) -> usize {
        let short: usize = self.short_range.iter().map(|p| p.touching).sum::<usize>()
            + self.fragments.iter().map(|p| p.touching).sum::<usize>();
        if let Some(d) = &self.domain {
            return d.contacts.iter().sum::<usize>() + short;
        }
        self.passes.iter().map(|p| p.contacts.len()).sum::<usize>() + short
    }

    /// The force on the slaves of pass `k` in the last evaluation (over all ranks).
    pub fn slave_force(&self, k: usize) -> Vec3 {
        match &self.domain {
            Some(d) => d.slave_forces[k],
            None => self.passes[k]
                .block_sums(None)
                .iter()
                .fold(Vec3::zeros(), |a, g| a + Vec3::new(g[0], g[1], g[2])),
        }
    }

    /// Missed contacts in the last evaluation.
    pub fn missed_contacts(&self) -> usize {
        self.passes.iter().map(|p| p.missed).sum::<usize>()
            + self.short_range.iter().map(|p| p.missed).sum::<usize>()
    }

    /// Verlet rebuilds so far.
    pub fn verlet_rebuilds(&self) -> usize {
        self.passes.iter().map(|p| p.verlet.rebuilds).sum()
    }
}

/// Bond forces plus applied loads into `pd.force`; resets contact accumulators. `pos` is
/// scratch space for the current positions (real particles, then mirror images).
pub fn internal_forces(pd: &mut PdBody, pos: &mut Vec<Vec3>) {
    internal_forces_with(pd, pos, false, |_| {}, |mine| mine);
}

/// [`internal_forces`] of the particles `pd.owned`, where `share` gives the ghosts the values
/// of their owners (a decomposed run: the LPS's force states, between its two sweeps) and
/// `all_failed` gives every rank the bonds that failed on any (collective).
///
/// Bonds that pass their critical stretch at these positions fail first ([`Fracture`]), unless
/// `hold`: the forces are those of the bonds that hold.
///
/// [`Fracture`]: crate::body::Fracture
fn internal_forces_with(
    pd: &mut PdBody,
    pos: &mut Vec<Vec3>,
    hold: bool,
    share: impl FnOnce(&mut [Vec3]),
    all_failed: impl FnOnce(Vec<(u32, u32)>) -> Vec<(u32, u32)>,
) {
    let x = &pd.case.particles.position;
    let n = pd.len();
    let ghosts = &pd.case.ghosts;
    pos.resize(n + ghosts.source.len(), Vec3::zeros());
    let (real, images) = pos.split_at_mut(n);
    real.par_iter_mut()
        .zip(x.par_iter().zip(pd.u.par_iter()))
        .for_each(|(p, (x, u))| *p = x + u);
    for (g, img) in images.iter_mut().enumerate() {
        *img = ghosts.reflect(real[ghosts.source[g] as usize], ghosts.mask[g]);
    }
    let pos: &[Vec3] = pos;
    if let Some(fr) = pd
        .fracture
        .as_ref()
        .filter(|f| f.critical_stretch.is_some() && !hold)
    {
        let failing = fr.failing(&pd.case.bonds, pos, &pd.reference, pd.owned.clone());
        let failed = all_failed(pd.spare_compressed(failing, pos));
        if !failed.is_empty() {
            pd.break_failed(&failed, pos);
        }
    }
    let kinematics = match pd.kinematics {
        Kinematics::Small => PairKinematics::Small(&pd.reference),
        Kinematics::Finite => PairKinematics::Finite,
    };
    let load = &pd.load;
    match &mut pd.lps {
        Some(lps) => {
            let stretch = match pd.kinematics {
                Kinematics::Small => Stretch::Small(&pd.reference),
                Kinematics::Finite => Stretch::Finite,
            };
            lps.forces_on(
                &pd.case,
                pos,
                stretch,
                pd.owned.clone(),
                share,
                &mut pd.force,
                |i, f, out| *out = f + load[i],
            );
        }
        None => pair_forces(
            &pd.pairs,
            pos,
            kinematics,
            &mut pd.force_buffers,
            &mut pd.force,
            |i, f, out| *out = f + load[i],
        ),
    }
    pd.contact_force.iter_mut().for_each(|f| *f = Vec3::zeros());
    pd.reaction_force
        .iter_mut()
        .for_each(|f| *f = Vec3::zeros());
    pd.contact_stiffness.iter_mut().for_each(|k| *k = 0.0);
    if let Some(f) = &mut pd.friction {
        f.reset();
    }
}

/// Particles of a named set of a body's mesh (its corner nodes that are particles).
/// The particle nearest `point` (reference positions; the first of equals).
fn nearest_particle(pd: &PdBody, point: Vec3) -> Option<u32> {
    (0..pd.len() as u32).min_by(|&a, &b| {
        let da = (pd.case.particles.position[a as usize] - point).norm_squared();
        let db = (pd.case.particles.position[b as usize] - point).norm_squared();
        da.total_cmp(&db)
    })
}

fn set_particles(scene: &Scene, pd: &PdBody, name: &str) -> Result<Vec<u32>> {
    let mesh = &pd.case.mesh;
    let Some(set) = mesh.set(name) else {
        let mut known: Vec<String> = mesh
            .sets
            .iter()
            .take(10)
            .map(|s| excerpt(&s.name))
            .collect();
        if mesh.sets.len() > 10 {
            known.push(format!("and {} more", mesh.sets.len() - 10));
        }
        return Err(scene.error_at(
            &format!("set = \"{name}\""),
            &format!(
                "body \"{}\" has no set \"{}\" (its sets: {})",
                pd.name,
                excerpt(name),
                if known.is_empty() {
                    "none".to_string()
                } else {
                    known.join(", ")
                }
            ),
        ));
    };
    let particles: Vec<u32> = mesh
        .set_nodes(set)
        .into_iter()
        .map(|n| pd.case.particles.particle_of_node[n as usize])
        .filter(|&p| p != NOT_A_PARTICLE)
        .collect();
    if particles.is_empty() {
        return Err(scene.error_at(
            &format!("set = \"{name}\""),
            &format!(
                "set \"{}\" of body \"{}\" holds no particle (no corner node of a 3D element)",
                excerpt(name),
                pd.name
            ),
        ));
    }
    Ok(particles)
}

/// The stiffness of the crack faces' linear penalty, in the body's `E Δ` (N/m per face
/// particle): measured on a hex block cut across its middle and compressed (docs/FRACTURE.md,
/// "Contact on new surfaces"), 30 leaves the faces 1.6 µm into each other under 1 MPa
/// (0.2 % of the block's compression; 10 and 100 move its stiffness by 0.1 %), and ADR
/// takes 452 iterations against the intact block's 197.
pub const CRACK_FACE_STIFFNESS: f64 = 30.0;

/// The penalty of a crack's faces where the scene gives no `radius`: linear, `k =`
/// [`CRACK_FACE_STIFFNESS`]` E Δ` per particle. The faces of a crack meet flat over their
/// whole area, as the body was whole there: Hertz's law for a particle pressing a surface
/// (`R = Δ/2`) let the same block's faces 0.74 mm into each other, 75 % of its compression.
fn crack_face_law(pd: &crate::body::PdBody, window: f64) -> ContactLaw {
    let k = CRACK_FACE_STIFFNESS * pd.material.youngs * pd.spacing();
    ContactLaw {
        law: crate::scene::PenaltyLaw::Linear,
        // The linear law's force is `stiffness √window δ`.
        stiffness: k / window.sqrt(),
        window,
    }
}
