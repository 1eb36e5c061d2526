//! Output: what a run leaves behind, and the figures read from it.
//!
//! | what | module |
//! |---|---|
//! | VTK XML files (`.vtu`, `.vtm`, `.pvd`), written atomically | [`vtk`] |
//! | the frames of a run, `run.pvd`, `view.py`, progress on stderr | [`frames`] |
//! | contact patch, Hertz and Sadowsky references | [`analysis`] |
//! | contact pressure recovered on the slave surface | [`recovery`] |
//! | the largest shear below a contact against Hertz's | [`subsurface`] |
//! | SVG charts (plotters), the load-displacement curve of a displacement-driven run | [`chart`] |

pub mod analysis;
pub mod chart;
pub mod frames;
pub mod recovery;
pub mod subsurface;
pub mod vtk;

pub use frames::{FrameWriter, RunMonitor, PVD_NAME};
