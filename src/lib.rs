//! pdcontact: peridynamic point-to-surface contact from finite-element meshes.
//!
//! The modules follow the data's path (METHOD.md §1), one folder per stage; a stage uses only
//! the stages above it in this table (the studies use the library's public API):
//!
//! | stage | module | what it holds |
//! |---|---|---|
//! | mesh files → [`Mesh`](importers::Mesh) | [`importers`] (crate `pdcontact-importers`) | CDB, MSH, INP readers, boundary faces |
//! | shared vocabulary | [`math`], [`reduction`], [`error`], [`parallel`] | `Vec3`, `NOT_A_PARTICLE`; ordered parallel sums; the error type and exit codes; the message-passing layer of a run over several processes |
//! | mesh → PD case | [`case`] | [`generators`](case::generators) (built-in hex8 shapes), [`discretize`](case::discretize) (particles, volumes, spacing), [`neighbours`](case::neighbours) (cell lists, bond families), [`pairs`](case::pairs) (the bond-force pass, each pair once), [`correction`](case::correction) (volume and surface correction), [`surface`](case::surface) (eigenvalue surface detection), [`segments`](case::segments) (master segments, tributary areas), the assembled [`PdCase`](case::PdCase) and its symmetry ghosts |
//! | scene file | [`scene`] | the TOML schema; `check.rs`: every check of its values |
//! | bodies | [`body`] | deformable and rigid body types; `build.rs`: a body built from its `[[body]]` (mesh I/O, transform, symmetry clipping, rigid faces); [`lps`](body::lps) (the linear peridynamic solid); [`fracture`](body::fracture) (bonds that fail, pre-cracks, damage), [`new_surface`](body::new_surface) and [`new_faces`](body::new_faces) (the surface broken bonds open, and its faces as master segments) |
//! | contact | [`contact`] | `broad.rs` (Verlet lists), `narrow.rs` (projection, segment rules), `law.rs` (Hertz penalty), the pass that ties them, [`shortrange`](contact::shortrange) (node-to-node repulsion), [`estimate`](contact::estimate) (the Hertz contact a pair will make, and the warnings when its particles resolve it poorly), [`overlap`](contact::overlap) (bodies that start inside each other) |
//! | model | [`model`] | a scene assembled: bodies, loads, supports, contact passes, and the force evaluation (Eq. 28); [`domain`](model::domain): the model decomposed over the ranks of an MPI run |
//! | solver | [`solver`] | `adr.rs` (adaptive dynamic relaxation), `explicit.rs` (velocity Verlet, stable step), `unheld.rs` (ADR: a loaded body gone past what it touches), the monitor and the checks they share |
//! | output | [`output`] | [`vtk`](output::vtk) (VTK XML files), [`frames`](output::frames) (frames, `run.pvd`, progress), [`analysis`](output::analysis) (contact pressure and patch, Hertz and Sadowsky references), [`chart`](output::chart) (SVG charts) |
//! | commands | [`run`], [`convert`] | a scene run to its frames and `summary.json` (`run/checks.rs`, `run/held.rs`: the checks before solving); a mesh turned into a case folder |
//! | studies | [`studies`] | [`demo`](studies::demo), [`scenarios`](studies::scenarios) and [`comparison`](studies::comparison) (the validation scenes against theory), [`validate`](studies::validate), [`sweep`](studies::sweep), [`stability`](studies::stability), [`bench`](studies::bench), [`fracture`](studies::fracture) (the notched beam against LEFM, Kalthoff-Winkler) |
//! | command line | [`cli`] | the arguments (clap), each command checked and run, its errors and exit codes |
//!
//! The body types come before the contact stage and the model after it: a model holds the
//! contact passes, and a contact pass works on bodies. The binaries are shells over
//! [`cli::main`]: `src/bin/pdcontact/` runs in one process; the `pdcontact-mpi` package (`mpi/`) starts MPI and hands it a
//! [`parallel::Comm`] on the system's MPI library, so that this library never needs one.
//!
//! The later stages read the scene's plain enums ([`Kinematics`](scene::Kinematics),
//! [`Motion`](scene::Motion), [`PenaltyLaw`](scene::PenaltyLaw),
//! [`ContactMethod`](scene::ContactMethod)) and the solver its
//! [`SolverSpec`](scene::SolverSpec) as the schema defines them: they are names and numbers
//! with no file logic, and a model copy of each would be a second definition of the same
//! values. The body builder, the model and the run are where a scene is read.
//!
//! "Case" names three things: a PD case ([`case::PdCase`]: one mesh as particles, bonds and
//! segments, what `pdcontact convert` writes as `case.toml`), a validation case
//! ([`ValidationCase`](studies::scenarios::ValidationCase): one validation scene and its
//! theory), and `--case` of `validate` and `sweep` (which problems: sphere, roller, punch).
//! The names stay, as the docs and scripts use them; each is said where it is defined.

// `!(x > 0.0)` is the NaN-rejecting test the numerics want (a NaN must fail the check), and
// index loops over several parallel arrays read better than zipped iterators here.
#![allow(clippy::neg_cmp_op_on_partial_ord, clippy::needless_range_loop)]

pub use pdcontact_importers as importers;

pub mod body;
pub mod case;
pub mod cli;
pub mod contact;
pub mod convert;
pub mod error;
pub mod math;
pub mod model;
pub mod output;
pub mod parallel;
pub mod reduction;
pub mod run;
pub mod scene;
pub mod solver;
pub mod studies;

pub use error::{Error, Result};
