//! `[body.material]`: the elastic constants, the PD material model and its influence function,
//! and what fails a bond (METHOD.md §2, §8, §9).

use serde::{Deserialize, Serialize};

/// Linear elastic material.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// E, Pa.
    pub youngs_modulus: f64,
    /// ν; bond-based PD fixes 1/4, the linear peridynamic solid takes any in its range.
    pub poisson_ratio: f64,
    /// ρ, kg/m³.
    pub density: f64,
    /// The PD material model (bond-based by default).
    #[serde(default)]
    pub model: MaterialModel,
    /// The linear peridynamic solid's influence function (constant by default), which is how
    /// it corrects its surface effect; `model = "lps"` only.
    pub influence_function: Option<InfluenceFunction>,
    /// Fracture energy G0, J/m²: bonds fail for good past the critical stretch
    /// `s0 = sqrt(5 G0 / (9 κ δ))` (Silling & Askari 2005; METHOD.md §9). Bond-based only.
    pub fracture_energy: Option<f64>,
    /// Instead of `fracture_energy`: the critical stretch s0 itself.
    pub critical_stretch: Option<f64>,
    /// What fails a bond past s0: its stretch alone (the default) or only a tension along it.
    pub failure: Option<FailureCriterion>,
}

/// `failure` of `[body.material]`: what fails a bond stretched past its critical stretch
/// (METHOD.md §9, [`crate::body::fracture`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum FailureCriterion {
    /// Silling & Askari 2005: the stretch alone.
    #[default]
    Stretch,
    /// The stretch, where a tension along the bond stretched it: the normal stress along the
    /// bond (`λ θ + 2 μ s` from its own stretch and its particles' recovered stresses) tensile
    /// and at least half the largest principal stress, so that a bond stretched only by
    /// Poisson's effect of a compression across it (below a contact) holds, as a brittle
    /// solid does; at a crack tip in tension the stretch alone decides, as Silling & Askari's.
    Tension,
}

/// `influence_function` of `[body.material]` (the linear peridynamic solid's).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum InfluenceFunction {
    /// ω = 1, each particle's force state scaled by one factor from its energy under three
    /// uniaxial stresses (a bar along its free faces 2-3 % stiff; docs/VALIDATION.md).
    #[default]
    Constant,
    /// Position-aware (Mitchell, Silling & Littlewood 2015): per particle, the weights that
    /// make its dilatation and strain energy the continuum's under every uniform strain (the
    /// bar within 1.3 %); not the default: two deformable spheres, an LPS one on a bond-based
    /// one, did not converge with it (docs/VALIDATION.md, "Any Poisson's ratio").
    PositionAware,
}

/// The largest Poisson's ratio the linear peridynamic solid takes (docs/VALIDATION.md, "Any
/// Poisson's ratio": where the uniaxial bar still gives E and ν within 2 %).
pub const LPS_MAX_POISSON: f64 = 0.49;

/// `model` of `[body.material]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum MaterialModel {
    /// Bond-based PD (the paper's, METHOD.md §2): pairwise bonds, ν = 1/4.
    #[default]
    BondBased,
    /// The linear peridynamic solid (ordinary state-based, METHOD.md §8): any ν.
    Lps,
}
