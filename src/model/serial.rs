//! What runs in one process for now: the contacts and failure criteria that a decomposed run
//! (`mpirun`, [`super::domain`]) refuses, each with its reason.

use super::Model;
use crate::body::Body;
use crate::error::{Error, Result};

impl Model {
    /// Refuses, naming the body and the reason, what [`Model::distribute`] cannot decompose:
    /// contact between a body's pieces, on the surfaces its broken bonds open or between its
    /// pre-cracks' faces, and `failure = "tension"` (its stress is fitted over both particles'
    /// neighbourhoods, and a rank lacks a ghost's).
    pub(super) fn check_distributable(&self) -> Result<()> {
        if let Some(p) = self.passes.iter().find(|p| p.is_pieces()) {
            return Err(Error::input(format!(
                "contact between the pieces of \"{}\" (solids of its mesh that no bond joins) runs in one process for now: run the scene without mpirun",
                self.bodies[p.slave].name()
            )));
        }
        if let Some(p) = self.passes.iter().find(|p| p.is_found_faces()) {
            return Err(Error::input(format!(
                "contact of \"{}\" with the surfaces its broken bonds open runs in one process for now: run the scene without mpirun",
                self.bodies[p.slave].name()
            )));
        }
        if let Some(p) = self.passes.iter().find(|p| p.is_crack()) {
            return Err(Error::input(format!(
                "contact between the faces of \"{}\"'s pre-cracks runs in one process for now: run the scene without mpirun",
                self.bodies[p.slave].name()
            )));
        }
        if let Some(pd) = self.bodies.iter().filter_map(Body::as_pd).find(|pd| {
            pd.fracture
                .as_ref()
                .is_some_and(|f| f.criterion == crate::body::fracture::FailureCriterion::Tension)
        }) {
            return Err(Error::input(format!(
                "failure = \"tension\" on \"{}\" runs in one process for now (a bond's stress is fitted over both its particles' neighbourhoods): run the scene without mpirun",
                pd.name
            )));
        }
        if let Some(p) = self.fragments.first() {
            return Err(Error::input(format!(
                "contact between the pieces of \"{}\" (its own short-range master) runs in one process for now: run the scene without mpirun",
                self.bodies[p.body].name()
            )));
        }
        Ok(())
    }
}
