//! `pdcontact friction`: Coulomb friction against its references (METHOD.md §10,
//! docs/VALIDATION.md "Friction"): a block on a tilted plane that stays or slides
//! ([`sliding`]), and a sphere pressed and then pushed sideways, whose contact sticks in a
//! disc and slips around it as Cattaneo and Mindlin found ([`mindlin`]).

pub mod mindlin;
pub mod sliding;

pub use mindlin::{run_mindlin, MindlinResult, MindlinScene};
pub use sliding::{run_sliding, SlidingBlock, SlidingResult};

use super::run_in;
