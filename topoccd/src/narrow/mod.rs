//! The elementary tests of continuous collision detection under linear motion: a vertex against a
//! triangle ([`vertex_face()`]) and an edge against an edge ([`edge_edge()`]).
//!
//! Both are conservative: if the two features touch (in exact arithmetic) at some time in
//! `[0, tmax]`, the answer is [`Outcome::Contact`], with a time of impact no later than the true
//! first contact. See [`solver`] for the method and its guarantees.

pub mod bernstein;
pub mod closest;
mod edge_edge;
mod extremes;
mod lanes;
mod options;
pub mod prefilter;
pub mod solver;
mod vertex_edge;
mod vertex_face;
mod vertex_vertex;

pub use edge_edge::{edge_edge, EdgeEdge};
pub(crate) use edge_edge::edge_edge_from;
pub use options::NarrowOptions;
pub use vertex_edge::{vertex_edge, VertexEdge};
pub use vertex_face::{vertex_face, VertexFace};
pub use vertex_vertex::{vertex_vertex, VertexVertex};
pub(crate) use vertex_face::vertex_face_from;

/// How sure a reported contact is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Certainty {
    /// The search isolated the contact to within the tolerances: the features come within the
    /// documented distance of each other at a time in `[toi, toi + tolerance]`.
    Resolved,
    /// The iteration budget ran out first. `toi` is then only a lower bound of the first contact
    /// (the features may not touch at all): the answer stays on the safe side.
    IterationLimit,
    /// The input held a NaN or an infinite coordinate, or coordinates so far apart that their
    /// differences exceed 1e300 (outside the input range, [`range`](crate::range)); nothing
    /// could be decided, so the answer is a contact at time 0.
    InvalidInput,
}

/// The answer of an elementary test.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Outcome {
    /// The features stay farther apart than `min_distance` during `[0, tmax]`.
    Separated,
    /// The features (may) touch. `toi` is in `[0, tmax]` and never later than the first contact.
    Contact {
        /// Time of impact, in the step's time units (`0` = start, `1` = end of the step).
        toi: f64,
        /// Whether the contact was isolated or the search gave up conservatively.
        certainty: Certainty,
    },
}

impl Outcome {
    /// The time of impact, if the outcome is a contact.
    pub fn toi(&self) -> Option<f64> {
        match *self {
            Outcome::Separated => None,
            Outcome::Contact { toi, .. } => Some(toi),
        }
    }

    /// `true` for [`Outcome::Contact`].
    pub fn is_contact(&self) -> bool {
        matches!(self, Outcome::Contact { .. })
    }
}
