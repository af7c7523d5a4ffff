//! The whole-step query on top of the pipeline: [`Ccd`] and [`query`] run one broad phase and
//! the narrow phase over a [`Step`](crate::Step), with [`QueryOptions`], into a [`Report`].
//!
//! A query goes through three phases, timed separately in [`Seconds`]:
//! 1. *build*: the step's edges and feature ownership, the swept volumes, and the hierarchy of
//!    the method ([`Method::Bvh`], [`Method::Cluster`]);
//! 2. *traverse*: the candidate feature pairs, into a buffer;
//! 3. *narrow*: the elementary tests over the buffer.
//!
//! Each vertex-face and edge-edge pair is tested at most once per step, with nothing computed
//! across steps: every vertex and edge is owned by its incident triangle of lowest index, and
//! an overlapping triangle pair tests only the features its two triangles own.

mod ccd;
mod geometry;
mod limits;
mod narrow_phase;
mod options;
mod report;

#[cfg(feature = "internals")]
pub use ccd::CandidatePairs;
pub use ccd::{query, Ccd};
pub use limits::{CancelToken, Phase, StopReason, Truncation};
pub use options::{ClusterGrowth, Method, Mode, OptionsError, QueryOptions, AUTO_CLUSTER_TRIANGLES};
pub use report::{
    Certainty, ClusterFigures, Contact, EeContact, EeGeometry, Report, Seconds, Stats, VfContact,
    VfGeometry,
};
