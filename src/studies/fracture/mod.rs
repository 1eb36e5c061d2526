//! `pdcontact fracture`: bond failure against its references (METHOD.md §9,
//! docs/FRACTURE.md): a notched three-point bend beam broken under displacement control
//! against linear elastic fracture mechanics ([`beam`]), and the Kalthoff-Winkler plate hit
//! between its notches by a projectile, whose cracks leave the notch tips at about 70°
//! ([`kalthoff`]); a block cut through and compressed, its crack's faces pressed together
//! ([`closing`]); and a ball fired through a brittle plate, whose pieces are kept apart by
//! their contact with each other ([`perforation`]).

pub mod beam;
pub mod closing;
pub mod kalthoff;
pub mod perforation;

pub use beam::{lefm_peak_load, run_beam, shape_factor, BeamResult, NotchedBeam};
pub use closing::{run_closing, ClosingResult};
pub use kalthoff::{run_kalthoff, KalthoffPlate, KalthoffResult};
pub use perforation::{run_perforation, PerforationResult};

/// The studies' run helper, without an observer.
fn run_in(
    text: &str,
    folder: &std::path::Path,
    quiet: bool,
) -> crate::error::Result<(crate::model::Model, crate::run::RunSummary, f64)> {
    super::run_in(text, folder, quiet, &mut crate::solver::Silent)
}
