//! A breaking body pressed on the surfaces its broken bonds open ([`ContactPass::found_faces`],
//! docs/FRACTURE.md, "Master segments on the faces found again"): the faces made at the
//! start and again as bonds break.

use super::Model;
use crate::body::new_faces::new_faces;
use crate::body::Body;
use crate::contact::{ContactLaw, ContactPass};

impl Model {
    /// Makes the faces of each body pressed on the surfaces its broken bonds open again,
    /// where bonds broke since they were made and [`FOUND_FACES_EVERY`] evaluations have
    /// passed ([`ContactPass::found_faces`]).
    pub(super) fn refresh_found_faces(&mut self) {
        for k in 0..self.passes.len() {
            let Some((built, broken, at)) = self.passes[k].found_faces_made() else {
                continue;
            };
            let s = self.passes[k].slave;
            let now = self.bodies[s]
                .as_pd()
                .and_then(|pd| pd.fracture.as_ref())
                .map_or(0, |f| f.broken);
            if now != broken && self.evaluations >= at + FOUND_FACES_EVERY {
                let law = self.passes[k].law;
                self.passes[k] =
                    found_faces_pass(&mut self.bodies, s, built, law, self.evaluations);
            }
        }
    }
}

/// Evaluations (time steps, ADR iterations) at least between two makings of the faces that
/// broken bonds opened (`Model::refresh_found_faces`): a face opens over many steps, and
/// the surface found again costs a test of each particle that lost a bond.
pub const FOUND_FACES_EVERY: usize = 10;

/// The faces body `s`'s broken bonds have opened (found again up to now) made its segments
/// after the `built` ones, and its pass against them ([`ContactPass::found_faces`]), at
/// evaluation `at`.
pub(super) fn found_faces_pass(
    bodies: &mut [Body],
    s: usize,
    built: usize,
    law: ContactLaw,
    at: usize,
) -> ContactPass {
    let pd = bodies[s].as_pd().expect("checked deformable");
    let faces = match pd.new_surface() {
        Some(found) => new_faces(pd, Some(&found)),
        None => new_faces(pd, None),
    };
    let pd = bodies[s].as_pd_mut().expect("checked deformable");
    pd.set_opened_faces(&faces);
    let segments = &mut pd.case.segments.segments;
    segments.truncate(built);
    segments.extend_from_slice(&faces.segments);
    ContactPass::found_faces(bodies, s, &faces, built, law, at)
}
