//! pdcontact: peridynamic point-to-surface contact from finite-element meshes.
//!
//! The modules follow the data's path (METHOD.md §1):
//!
//! | stage | module |
//! |---|---|
//! | mesh files → [`Mesh`](importers::Mesh) | [`importers`] (crate `pdcontact-importers`) |
//! | built-in hex8 shapes | [`generators`] |
//! | particles, volumes, spacing | [`discretize`] |
//! | cell lists, bond families | [`neighbours`] |
//! | volume and surface correction | [`correction`] |
//! | eigenvalue surface detection | [`surface`] |
//! | master segments, tributary areas | [`segments`] |
//! | the assembled PD case | [`case`] |
//! | VTK output | [`vtk`] |
//! | `convert` | [`convert`] |

pub use pdcontact_importers as importers;

pub mod case;
pub mod convert;
pub mod correction;
pub mod discretize;
pub mod error;
pub mod generators;
pub mod neighbours;
pub mod segments;
pub mod surface;
pub mod vtk;

pub use error::{Error, Result};
