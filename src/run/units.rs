//! Units and scale: warnings, before solving, for a scene whose numbers cannot all be meant
//! as written (SI: metres, newtons, pascals, kilograms per cubic metre). A modulus written in
//! MPa, a mesh in millimetres or a load in kilonewtons each move the Hertz estimate of a
//! contact (METHOD.md §7) by orders of magnitude; the estimate is where the slip shows.

use crate::body::{Body, Material};
use crate::contact::estimate::{ContactResolution, HertzEstimate};
use crate::model::Model;
use crate::scene::{Scene, SolverKind};

use super::checks::short;

/// A strain `p0 (1 − ν²)/E` beyond this is no small-strain contact: a slip of units, or a load far
/// beyond what the body's stiffness carries.
pub use crate::contact::estimate::STRAIN_LIMIT;

/// A strain `p0 (1 − ν²)/E` beyond this is no material's: the units slipped.
const UNIT_SLIP_STRAIN: f64 = 1.0;

/// Below this Young's modulus (Pa) a solid is softer than any rubber: the likely slip is a
/// modulus written in MPa or GPa.
const SOFTEST_SOLID: f64 = 1e5;

/// Beyond this size (m) a body is likelier a mesh in millimetres than a part in metres.
const LARGEST_PART: f64 = 100.0;

/// Densities of solids in kg/m³, from foams to osmium: 7.85 (steel in g/cm³) falls below.
const DENSITY_RANGE: (f64, f64) = (20.0, 3e4);

/// The slave's strain at the contact, `p0 (1 − ν²)/E`: Hertz's peak pressure over the slave's
/// own modulus (`p0/E*` against a rigid master; half that where the master is as stiff).
fn strain(e: &HertzEstimate, slave: &Material) -> f64 {
    e.peak_pressure() * slave.compliance()
}

/// Warnings for contacts whose estimate puts the contact beyond the body's size or its strain
/// beyond [`STRAIN_LIMIT`], naming the likely slip; and, in explicit dynamics (where mass is
/// real), densities outside [`DENSITY_RANGE`].
pub(super) fn scale_warnings(
    scene: &Scene,
    model: &Model,
    estimates: &[ContactResolution],
) -> Vec<String> {
    let mut warnings = Vec::new();
    for r in estimates {
        let Some(e) = &r.estimate else { continue };
        let Some(pd) = model
            .bodies
            .iter()
            .find(|b| b.name() == r.slave)
            .and_then(Body::as_pd)
        else {
            continue;
        };
        let Some((lo, hi)) = pd.case.mesh.bbox() else {
            continue;
        };
        let size = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
        let eps = strain(e, &pd.material);
        let too_wide = e.radius > 0.5 * size;
        if !(too_wide || eps > STRAIN_LIMIT) {
            continue;
        }
        let what = if too_wide {
            format!(
                "the Hertz estimate puts the contact {} at {} m on a body {} m across",
                e.what(),
                short(e.radius),
                short(size)
            )
        } else {
            format!(
                "the Hertz estimate puts the contact's strain p0 (1 − ν²)/E at {:.0} % (contact {} {} m, relative radius of curvature R* {} m)",
                100.0 * eps,
                e.what(),
                short(e.radius),
                // R* of the pair, not the slave's own: a flat slave under a ball has none.
                short(e.curvature_radius())
            )
        };
        let youngs = pd.material.youngs;
        let slip = if youngs < SOFTEST_SOLID {
            format!(
                "youngs_modulus = {} Pa is softer than any rubber: was it written in MPa or GPa? (pascals: 200 GPa = 2e11, 1000 MPa = 1e9)",
                short(youngs)
            )
        } else if size > LARGEST_PART {
            format!(
                "the body is {} m across: is its mesh in millimetres? (scale = 1e-3 in its [[body]] makes it metres)",
                short(size)
            )
        } else {
            format!(
                "the load on the contact ({} N) is far more than this body carries at small strain: was it written in kN or MN? (newtons), or the modulus too low?",
                short(e.load)
            )
        };
        // Orders of magnitude are a slip of units; a strain of tens of per cent may be meant
        // (a validation beyond Hertz's range), so it is said as such.
        if too_wide || eps > UNIT_SLIP_STRAIN {
            warnings.push(format!(
                "{}: {what}. Units are SI (m, N, Pa, kg/m³); likely a slip: {slip}",
                r.pair()
            ));
        } else {
            warnings.push(format!(
                "{}: {what}, where Hertz's theory and small kinematics hold to about {:.0} %: fine where a contact that large is meant (as `validate` presses its spheres to a = 0.3 R by default), else check the units (SI: m, N, Pa, kg/m³): {slip}",
                r.pair(),
                100.0 * STRAIN_LIMIT
            ));
        }
    }
    // A mesh in millimetres with a modulus in MPa and loads in N (a consistent set, and
    // Abaqus's and ANSYS's habit) keeps the contact's strain plausible: only the size shows.
    for b in model.bodies.iter().filter_map(Body::as_pd) {
        let Some((lo, hi)) = b.case.mesh.bbox() else {
            continue;
        };
        let size = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
        if size > LARGEST_PART {
            warnings.push(format!(
                "body \"{}\": {} m across: is its mesh in millimetres? Units are SI (m, N, Pa, kg/m³): scale = 1e-3 in its [[body]] makes it metres, and a modulus in MPa is written in Pa (210 GPa = 2.1e11)",
                b.name,
                short(size)
            ));
        }
    }
    if scene.solver.kind == SolverKind::Explicit {
        for b in model.bodies.iter().filter_map(Body::as_pd) {
            let rho = b.material.density;
            if !(DENSITY_RANGE.0..=DENSITY_RANGE.1).contains(&rho) {
                let hint = if rho < 1e-3 {
                    " (tonnes per mm³, the mm-t-s system? steel is 7.85e-9 t/mm³ = 7850 kg/m³)"
                } else if rho < DENSITY_RANGE.0 {
                    " (g/cm³? steel is 7.85 g/cm³ = 7850 kg/m³)"
                } else {
                    ""
                };
                warnings.push(format!(
                    "body \"{}\": density = {} kg/m³ lies outside what solids have ({}-{} kg/m³){hint}; explicit dynamics moves the body with this mass",
                    b.name,
                    short(rho),
                    short(DENSITY_RANGE.0),
                    short(DENSITY_RANGE.1)
                ));
            }
        }
    }
    warnings
}
