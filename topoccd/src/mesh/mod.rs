//! The input model of one step, at the bottom of the pipeline: the validated input
//! ([`Step`]), its connectivity ([`Topology`]), its features with their swept boxes and owners
//! (`features`), and the pair filter every broad phase applies (`filter`).

pub(crate) mod codim;
pub(crate) mod features;
pub(crate) mod filter;
pub(crate) mod star;
mod step;
mod topology;

pub use step::{CanCollide, Frame, Positions, Step, StepError, Triangles};
pub use topology::Topology;
