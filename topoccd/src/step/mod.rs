//! One simulation step: the validated input ([`Step`]), its topology ([`Topology`]), and the
//! whole-step CCD query.

mod mesh;
mod topology;

pub use mesh::{Frame, Step, StepError};
pub use topology::Topology;
