//! The contact law (paper Sec. 2.2.4, Eqs. 22-24, METHOD.md §5): `F = K δ^{3/2}` along the
//! master segment's normal with `K = 4/(3(m_s + m_m)) √R`, `m = (1 − ν²)/E` (`m = 0` for a
//! rigid body), or the linear law kept for comparison.

use crate::scene::PenaltyLaw;

/// The penetration, as a share of the window, at which ADR takes a candidate slave's contact
/// stiffness ([`ContactLaw::relaxation_stiffness`]): a tenth of the edge's tangent for the
/// Hertz law. Measured on the Hertz sphere of `pdcontact validate --mesh` (tet4, h = 0.06,
/// penalty 10⁴ R): 2,405 iterations at the window's edge (1), 1,693 at 0.1, 1,295 at 0.01,
/// 1,163 at 0.003, 1,245 at 3e-4, the figures the same to 0.005 points; at 0 a slave crosses
/// the window before it touches and the run stops.
pub const LIGHT_CONTACT: f64 = 0.01;

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

    /// Tangent stiffness `dF/dδ` at penetration `d ≥ 0`.
    #[inline]
    pub fn tangent(&self, d: f64) -> f64 {
        match self.law {
            PenaltyLaw::Hertz => 1.5 * self.stiffness * d.max(0.0).sqrt(),
            PenaltyLaw::Linear => self.stiffness * self.window.sqrt(),
        }
    }

    /// The contact stiffness ADR gives a slave at penetration `d` (0: a slave that may touch
    /// within a step): the tangent at `d`, and at least at [`LIGHT_CONTACT`] of the window.
    ///
    /// The tangent at the edge of the window, which every candidate slave got before, is
    /// far stiffer than a stiff penalty's working penetration (a few tenths of a percent of
    /// the contact's depth, `contact::estimate`): it weighed the particles at the contact's
    /// edge down, and they converged last. Without a floor a slave that has not touched yet
    /// moves at its bonds' density and can cross the window in one step.
    #[inline]
    pub fn relaxation_stiffness(&self, d: f64) -> f64 {
        self.tangent(d.clamp(LIGHT_CONTACT * self.window, self.window))
    }

    /// Tangent stiffness `dF/dδ` at the edge of the window: the largest the contact can
    /// present, used for the explicit stable step and for a free rigid body's density before
    /// it touches (a slave's ADR density is [`Self::relaxation_stiffness`]).
    pub fn max_tangent(&self) -> f64 {
        self.tangent(self.window)
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
