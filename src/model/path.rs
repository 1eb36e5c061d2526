//! A quasi-static run's load path beyond proportional loading: loads, prescribed displacements
//! and driven bodies that rise over part of it ([`ramp_factor`]), so that a sphere can be
//! pressed by P first and pushed sideways by Q after (Cattaneo-Mindlin, METHOD.md §10).

use crate::body::{Body, FIX_X, FIX_Y, FIX_Z};
use crate::math::Vec3;
use crate::scene::ramp_factor;

/// A load with a ramp: its force on each particle (a rigid body: its whole force).
#[derive(Clone, Debug)]
pub struct RampedLoad {
    pub body: usize,
    pub ramp: [f64; 2],
    /// `(particle, force)`; empty for a rigid body.
    pub parts: Vec<(u32, Vec3)>,
    /// A rigid body's whole force.
    pub whole: Vec3,
}

/// Held components of particles brought to a displacement along the path.
#[derive(Clone, Debug)]
pub struct Prescribed {
    pub body: usize,
    pub particles: Vec<u32>,
    /// Fixed-component mask ([`FIX_X`] …).
    pub mask: u8,
    pub displacement: Vec3,
    pub ramp: Option<[f64; 2]>,
}

/// What moves along the load path other than in proportion to the load factor.
#[derive(Clone, Debug, Default)]
pub struct LoadPath {
    pub ramped: Vec<RampedLoad>,
    pub prescribed: Vec<Prescribed>,
}

impl LoadPath {
    /// Sets the ramped loads, the prescribed displacements and the driven rigid bodies at
    /// load factor `lambda`, after the solver has set every load to `lambda` times its whole
    /// (or left it whole when the path is walked in one step, `lambda` = 1): each ramped
    /// load gets `(ramp(λ) − λ)` of its force added. A scene without ramps is left as the
    /// proportional path makes it, to the bit.
    pub fn apply(&self, bodies: &mut [Body], lambda: f64) {
        for l in &self.ramped {
            let extra = ramp_factor(Some(l.ramp), lambda) - lambda;
            match &mut bodies[l.body] {
                Body::Deformable(pd) => {
                    for &(p, f) in &l.parts {
                        pd.load[p as usize] += f * extra;
                    }
                }
                Body::Rigid(rb) => rb.load += l.whole * extra,
            }
        }
        for p in &self.prescribed {
            let Some(pd) = bodies[p.body].as_pd_mut() else {
                continue;
            };
            let d = p.displacement * ramp_factor(p.ramp, lambda);
            for &i in &p.particles {
                let u = &mut pd.u[i as usize];
                for (a, bit) in [FIX_X, FIX_Y, FIX_Z].into_iter().enumerate() {
                    if p.mask & bit != 0 {
                        u[a] = d[a];
                    }
                }
            }
        }
        for b in bodies.iter_mut() {
            if let Body::Rigid(rb) = b {
                if rb.motion == crate::scene::Motion::Displacement {
                    rb.translation = rb.displacement * ramp_factor(rb.ramp, lambda);
                }
            }
        }
    }
}
