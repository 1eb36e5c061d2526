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
//! | the bond-force pass, each pair once | [`pairs`] |
//! | volume and surface correction | [`correction`] |
//! | eigenvalue surface detection | [`surface`] |
//! | master segments, tributary areas | [`segments`] |
//! | the assembled PD case | [`case`] |
//! | VTK output | [`vtk`] |
//! | `convert` | [`convert`] |
//! | `bench`: the bond-force kernel on LAMMPS's comparison problem | [`bench`] |

// `!(x > 0.0)` is the NaN-rejecting test the numerics want (a NaN must fail the check), and
// index loops over several parallel arrays read better than zipped iterators here.
#![allow(clippy::neg_cmp_op_on_partial_ord, clippy::needless_range_loop)]

pub use pdcontact_importers as importers;

pub mod body;
pub mod case;
pub mod contact;
pub mod convert;
pub mod error;
pub mod math;
pub mod model;
pub mod output;
pub mod reduction;
pub mod run;
pub mod scene;
pub mod solver;
pub mod studies;

pub use error::{Error, Result};
