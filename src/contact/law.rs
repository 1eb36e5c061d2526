//! The contact law (paper Sec. 2.2.4, Eqs. 22-24, METHOD.md §5): `F = K δ^{3/2}` along the
//! master segment's normal with `K = 4/(3(m_s + m_m)) √R`, `m = (1 − ν²)/E` (`m = 0` for a
//! rigid body), or the linear law kept for comparison.

use crate::scene::PenaltyLaw;

/// The penalty law of a pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactLaw {
    pub law: PenaltyLaw,
    /// `K` of Eq. 23 (N/m^1.5 for Hertz).
    pub stiffness: f64,
    /// Penetration window (m).
    pub window: f64,
}

impl ContactLaw {
    /// Force magnitude at penetration `d ≥ 0`.
    #[inline]
    pub fn force(&self, d: f64) -> f64 {
        match self.law {
            PenaltyLaw::Hertz => self.stiffness * d * d.sqrt(),
            PenaltyLaw::Linear => self.stiffness * self.window.sqrt() * d,
        }
    }

    /// Tangent stiffness `dF/dδ` at the edge of the window: the largest the contact can
    /// present, used for ADR's fictitious density and the explicit stable step.
    pub fn max_tangent(&self) -> f64 {
        match self.law {
            PenaltyLaw::Hertz => 1.5 * self.stiffness * self.window.sqrt(),
            PenaltyLaw::Linear => self.stiffness * self.window.sqrt(),
        }
    }
}

/// The penalty radius R of a pair that does not give one: Δ/2 of the slave (METHOD.md §5, the
/// paper's particle radius).
pub fn default_radius(slave_spacing: f64) -> f64 {
    0.5 * slave_spacing
}

/// `K = 4/(3(m_i + m_j)) √R` (Eq. 23), `m` from Eq. 24; `f64::INFINITY` when both are rigid.
pub fn hertz_stiffness(m_slave: f64, m_master: f64, radius: f64) -> f64 {
    4.0 / (3.0 * (m_slave + m_master)) * radius.sqrt()
}
