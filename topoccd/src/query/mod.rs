//! The whole-step query on top of the pipeline: [`Ccd`] and [`query`] run one broad phase and
//! the narrow phase over a [`Step`](crate::Step), with [`QueryOptions`], into a [`Report`].
//!
//! A query goes through three phases, timed separately in [`Seconds`]:
//! 1. *build*: the step's edges and feature ownership, the certified stars, the swept volumes,
//!    and the hierarchy of the method ([`Method::Bvh`], [`Method::Cluster`]);
//! 2. *traverse*: the candidate feature pairs, which the broad phase's tasks solve in bounded
//!    buffers as they come (the broad phases and their passes live in [`broad`](crate::broad)
//!    behind one interface, and hand the candidates down to the narrow phase's driver in
//!    [`contact`](crate::contact); this module orchestrates);
//! 3. *narrow*: the elementary tests over the candidates (inside the traversal's tasks, and the
//!    report's sorting and selection).
//!
//! Each vertex-face and edge-edge pair is tested at most once per step: every vertex and edge
//! is owned by its incident triangle of lowest index, and an overlapping triangle pair tests
//! only the features its two triangles own. What a [`Ccd`] carries from one step to the next
//! (the topology, the per-step hierarchy and its front, the cluster method's leaves) is checked
//! again on every step, never trusted.

mod ccd;

#[cfg(feature = "internals")]
pub use ccd::CandidatePairs;
pub use ccd::{query, Ccd};
pub use crate::contact::{CancelToken, Phase, StopReason, Truncation};
pub use crate::contact::DEFAULT_MAX_CONTACTS;
pub use crate::contact::{
    ClusterGrowth, Method, Mode, OptionsError, QueryOptions, AUTO_CLUSTER_TRIANGLES,
};
pub use crate::contact::{
    Certainty, ClusterFigures, Contact, EeContact, EeGeometry, Report, Seconds, Stats, VeContact,
    VfContact, VfGeometry, VvContact,
};
