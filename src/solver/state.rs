//! The state a load increment starts from: what ADR and the static solver save before an
//! increment and put back when it is cut back.

use super::dofs::Dofs;
use crate::body::Body;
use crate::math::Vec3;
use crate::model::Model;
use crate::scene::Motion;

/// The displacements and free translations: what a load step saves and restores.
#[derive(Clone)]
pub(super) struct State {
    u: Vec<Vec<Vec3>>,
    translation: Vec<Vec3>,
}

impl State {
    pub(super) fn of(model: &Model) -> State {
        State {
            u: model
                .bodies
                .iter()
                .map(|b| b.as_pd().map_or(Vec::new(), |pd| pd.u.clone()))
                .collect(),
            translation: model
                .bodies
                .iter()
                .map(|b| match b {
                    Body::Rigid(rb) => rb.translation,
                    Body::Deformable(_) => Vec3::zeros(),
                })
                .collect(),
        }
    }

    /// Puts the linear extrapolation `self + t (self − before)` into the model: the
    /// predictor of the next increment from the last two equilibria.
    pub(super) fn extrapolate(&self, before: &State, t: f64, model: &mut Model) {
        for (k, b) in model.bodies.iter_mut().enumerate() {
            match b {
                Body::Deformable(pd) => {
                    for ((u, now), was) in pd.u.iter_mut().zip(&self.u[k]).zip(&before.u[k]) {
                        *u = now + (now - was) * t;
                    }
                }
                Body::Rigid(rb) => {
                    if rb.motion == Motion::Free {
                        let (now, was) = (self.translation[k], before.translation[k]);
                        rb.translation = now + (now - was) * t;
                    }
                }
            }
        }
    }

    /// Puts `self + alpha · d` into the model.
    pub(super) fn apply(&self, model: &mut Model, d: Option<(f64, &Dofs)>) {
        for (k, b) in model.bodies.iter_mut().enumerate() {
            match b {
                Body::Deformable(pd) => {
                    pd.u.copy_from_slice(&self.u[k]);
                    if let Some((a, d)) = d {
                        for (u, d) in pd.u.iter_mut().zip(&d.pd[k]) {
                            *u += d * a;
                        }
                    }
                }
                Body::Rigid(rb) => {
                    rb.translation = self.translation[k];
                    if let Some((a, d)) = d {
                        if rb.motion == Motion::Free {
                            rb.translation += rb.axis * (a * d.rigid[k]);
                        }
                    }
                }
            }
        }
    }
}
