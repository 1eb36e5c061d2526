//! The studies: programs built on the library's public API, apart from the pipeline stages.
//!
//! | command | module |
//! |---|---|
//! | `pdcontact demo`: the sphere on a plane against Hertz | [`demo`] |
//! | the validation scenes, shared by the studies | [`scenarios`] |
//! | `pdcontact fracture`: a notched beam broken against LEFM | [`fracture`] |
//! | a scene run and compared with its theory | [`comparison`] |
//! | `pdcontact validate`: the scenes against theory, the convergence studies | [`validate`] |
//! | `pdcontact sweep`: speed against accuracy | [`sweep`] |
//! | `pdcontact sweep --stability`: where the solvers and contact methods stop working | [`stability`] |
//! | `pdcontact bench`: the kernels and stages timed | [`bench`](mod@bench) |
//! | `pdcontact validate --mesh`: the Hertz sphere or roller on a user's mesh | [`user_mesh`] |

pub mod bench;
pub mod comparison;
pub mod demo;
pub mod fracture;
pub mod friction;
pub mod scenarios;
pub mod stability;
pub mod sweep;
pub mod user_mesh;
pub mod validate;
