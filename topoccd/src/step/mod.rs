//! One simulation step: the validated input ([`Step`]), its topology ([`Topology`]), and the
//! whole-step CCD query ([`Ccd`], [`query`]) with its options and [`Report`].
//!
//! A query goes through three phases, timed separately in [`Seconds`]:
//! 1. *build*: the step's edges and feature ownership (see below), the swept boxes of the
//!    features, and for [`Method::Bvh`] a k-DOP hierarchy over the triangles' swept volumes;
//! 2. *traverse*: the candidate feature pairs, into a buffer — from the overlapping triangle
//!    pairs of the hierarchy, or for [`Method::Brute`] from a sort and sweep over all features;
//! 3. *narrow*: the elementary tests of [`narrow`](crate::narrow) over the buffer.
//!
//! Each vertex-face and edge-edge pair is tested at most once per step, with nothing computed
//! across steps: every vertex and edge is owned by its incident triangle of lowest index, and
//! an overlapping triangle pair tests only the features its two triangles own.

mod brute;
mod cluster_query;
mod cluster_tree;
mod features;
mod mesh;
mod narrow_phase;
mod options;
mod prefilter;
mod query;
mod report;
mod topology;

pub use mesh::{Frame, Step, StepError};
pub use options::{ClusterGrowth, Method, Mode, QueryOptions};
pub use query::{query, Candidates, Ccd};
pub use report::{ClusterFigures, Contact, EeContact, Report, Seconds, Stats, VfContact};
pub use topology::Topology;
