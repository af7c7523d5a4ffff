//! The result of a whole-step query: contacts with their certainty and (on request) their
//! geometry, the earliest contact, and statistics.

use std::cmp::Ordering;

pub use crate::broad::cluster::phase::ClusterFigures;
pub use crate::narrow::Certainty;

use super::vertex_edge::{self, VeContact};
use crate::alloc::{try_push, AllocError};
use super::vertex_vertex::{self, VvContact};

/// A vertex that (may) touch a triangle during the step.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct VfContact {
    /// The vertex index.
    pub vertex: u32,
    /// The triangle's index in [`Step::triangles`](crate::Step::triangles).
    pub face: u32,
    /// Time of impact in `[0, tmax]`, no later than the first contact.
    pub toi: f64,
    /// Whether the contact was isolated or the search gave up conservatively.
    pub certainty: Certainty,
    /// Where the contact is, with [`QueryOptions::geometry`](crate::QueryOptions::geometry).
    pub geometry: Option<VfGeometry>,
}

/// The geometry of a vertex-face contact at its time of impact.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct VfGeometry {
    /// Barycentric coordinates, on the face's three vertices, of the face's point closest to
    /// the vertex (they sum to 1).
    pub barycentric: [f64; 3],
    /// That point.
    pub point: [f64; 3],
    /// Unit contact normal, from the face towards the side the vertex comes from: the
    /// direction from the point to the vertex when they are apart, else the face normal
    /// turned to the vertex's side at t=0.
    pub normal: [f64; 3],
    /// Distance between the vertex and the face at the time of impact.
    pub distance: f64,
}

/// The geometry of an edge-edge contact at its time of impact.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct EeGeometry {
    /// Parameter in `[0, 1]` of the closest point on edge `a`, from `a[0]` to `a[1]`.
    pub a_param: f64,
    /// Parameter in `[0, 1]` of the closest point on edge `b`, from `b[0]` to `b[1]`.
    pub b_param: f64,
    /// The midpoint of the two closest points.
    pub point: [f64; 3],
    /// Unit contact normal, from edge `b` towards edge `a`: the direction between the closest
    /// points when they are apart, else the cross product of the edges turned to `a`'s side
    /// at t=0.
    pub normal: [f64; 3],
    /// Distance between the edges at the time of impact.
    pub distance: f64,
}

/// Two edges that (may) touch during the step. Each edge is `[i, j]` with `i < j`, and
/// `a < b` lexicographically.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct EeContact {
    /// The first edge, by vertex indices.
    pub a: [u32; 2],
    /// The second edge.
    pub b: [u32; 2],
    /// Time of impact in `[0, tmax]`, no later than the first contact.
    pub toi: f64,
    /// Whether the contact was isolated or the search gave up conservatively.
    pub certainty: Certainty,
    /// Where the contact is, with [`QueryOptions::geometry`](crate::QueryOptions::geometry).
    pub geometry: Option<EeGeometry>,
}

/// One contact of either kind.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum Contact {
    /// A vertex-face contact.
    Vf(VfContact),
    /// An edge-edge contact.
    Ee(EeContact),
    /// A vertex-edge contact (a free point and a free edge).
    Ve(VeContact),
    /// A vertex-vertex contact (two free points).
    Vv(VvContact),
}

impl From<EeContact> for Contact {
    /// The contact of the driver's edge-edge pair `c`, of its kind: an edge of length zero
    /// `[p, p]` is the free point `p`.
    fn from(c: EeContact) -> Self {
        if let Some(v) = vertex_vertex::from_edge_edge(&c) {
            Contact::Vv(v)
        } else if let Some(v) = vertex_edge::from_edge_edge(&c) {
            Contact::Ve(v)
        } else {
            Contact::Ee(c)
        }
    }
}

impl Contact {
    /// The time of impact.
    pub fn toi(&self) -> f64 {
        match self {
            Contact::Vf(c) => c.toi,
            Contact::Ee(c) => c.toi,
            Contact::Ve(c) => c.toi,
            Contact::Vv(c) => c.toi,
        }
    }

    /// How sure the contact is.
    pub fn certainty(&self) -> Certainty {
        match self {
            Contact::Vf(c) => c.certainty,
            Contact::Ee(c) => c.certainty,
            Contact::Ve(c) => c.certainty,
            Contact::Vv(c) => c.certainty,
        }
    }

    /// The order that picks the earliest contact: by time of impact, then vertex-face before
    /// edge-edge before vertex-edge before vertex-vertex, then by `(vertex, face)`, `(a, b)`,
    /// `(vertex, edge)` or `(a, b)`.
    pub fn earliest_order(&self, other: &Self) -> Ordering {
        self.toi()
            .total_cmp(&other.toi())
            .then_with(|| match (self, other) {
                (Contact::Vf(x), Contact::Vf(y)) => (x.vertex, x.face).cmp(&(y.vertex, y.face)),
                (Contact::Ee(x), Contact::Ee(y)) => (x.a, x.b).cmp(&(y.a, y.b)),
                (Contact::Ve(x), Contact::Ve(y)) => (x.vertex, x.edge).cmp(&(y.vertex, y.edge)),
                (Contact::Vv(x), Contact::Vv(y)) => (x.a, x.b).cmp(&(y.a, y.b)),
                _ => self.kind().cmp(&other.kind()),
            })
    }

    /// The kind's rank in [`Contact::earliest_order`].
    fn kind(&self) -> u8 {
        match self {
            Contact::Vf(_) => 0,
            Contact::Ee(_) => 1,
            Contact::Ve(_) => 2,
            Contact::Vv(_) => 3,
        }
    }
}

/// Wall-clock time of each phase of a query, in seconds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Seconds {
    /// Topology, feature ownership, swept volumes and the hierarchy (or the oracle's sort).
    /// For [`Method::Cluster`](crate::Method::Cluster): the swept volumes, the hierarchy over
    /// the clusters and the lazy hierarchies over leaf clusters' triangles, but not the
    /// clustering itself.
    pub build: f64,
    /// Traversal (or sweep) down to the candidate feature pairs. For
    /// [`Method::Bvh`](crate::Method::Bvh) and [`Method::Cluster`](crate::Method::Cluster)
    /// this includes the elementary tests, which their traversal tasks run on their own
    /// candidates as they go.
    pub traverse: f64,
    /// The elementary tests (for [`Method::Bvh`](crate::Method::Bvh) and
    /// [`Method::Cluster`](crate::Method::Cluster), only the final sort and selection: their
    /// tests run inside the traversal).
    pub narrow: f64,
    /// The whole query.
    pub total: f64,
    /// [`Method::Cluster`](crate::Method::Cluster) only: growing the leaf clusters.
    pub clustering: Option<f64>,
    /// [`Method::Cluster`](crate::Method::Cluster) only: merging them into intermediate
    /// clusters.
    pub merging: Option<f64>,
}

/// Work counters of a query.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Stats {
    /// The method that ran (what [`Method::Auto`](crate::Method::Auto) chose).
    pub method: crate::Method,
    /// Bounding-volume overlap tests: k-DOP node pairs in [`Method::Bvh`](crate::Method::Bvh)
    /// (in [`Method::Cluster`](crate::Method::Cluster): of the cluster hierarchy and of the
    /// lazy hierarchies), box pairs of the sweep in [`Method::Brute`](crate::Method::Brute).
    pub bv_tests: u64,
    /// Vertex-face pairs given to the narrow phase (its conservative prefilter, then the
    /// elementary test for the pairs it cannot reject); each pair at most once per query.
    pub vf_tests: u64,
    /// Edge-edge pairs given to the narrow phase, as for `vf_tests`; each pair at most once.
    /// (In [`Mode::Earliest`](crate::Mode::Earliest) the per-step hierarchy may look at the
    /// step in two passes, the first over its start only, and count a pair once per pass.)
    pub ee_tests: u64,
    /// The most candidate pairs held in one buffer at once: candidates stream from the broad
    /// phase to the narrow phase in bounded buffers, so this stays bounded however many
    /// candidates a step has.
    pub peak_candidates: u64,
    /// Time of each phase.
    pub seconds: Seconds,
    /// [`Method::Cluster`](crate::Method::Cluster) only: the clusters and lazy hierarchies.
    pub cluster: Option<ClusterFigures>,
}

/// The result of a whole-step query.
#[derive(Clone, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Report {
    /// Colliding vertex-face pairs, sorted by `(vertex, face)`. In
    /// [`Mode::Earliest`](crate::Mode::Earliest), only those whose time of impact is within the
    /// tolerance of the earliest.
    pub vf: Vec<VfContact>,
    /// Colliding edge-edge pairs, sorted by `(a, b)`. In
    /// [`Mode::Earliest`](crate::Mode::Earliest), only those whose time of impact is within the
    /// tolerance of the earliest.
    pub ee: Vec<EeContact>,
    /// Colliding vertex-edge pairs, sorted by `(vertex, edge)`: a free point (a vertex in no
    /// triangle and no edge) and a free edge (of [`Step::with_edges`](crate::Step::with_edges),
    /// in no triangle). In [`Mode::Earliest`](crate::Mode::Earliest), as [`Report::vf`].
    ///
    /// With free edges and points, these and [`Report::vv`] complete the vertex-face and
    /// edge-edge pairs (a free vertex against every face, a free edge against every edge):
    /// the distance of two primitives (triangles, segments, points; closed convex polytopes)
    /// is reached at a vertex of one against the other or at an edge of each, so a point and a
    /// triangle meet as a vertex-face pair, a segment and a triangle as vertex-face pairs of
    /// the segment's ends or edge-edge pairs with the triangle's edges, two segments as an
    /// edge-edge pair; only a point against a segment, and two points, need pairs of their
    /// own.
    pub ve: Vec<VeContact>,
    /// Colliding vertex-vertex pairs, sorted by `(a, b)`: two free points. In
    /// [`Mode::Earliest`](crate::Mode::Earliest), as [`Report::vf`].
    pub vv: Vec<VvContact>,
    /// The earliest contact (the first in [`Contact::earliest_order`]), or `None` when nothing
    /// collides.
    pub earliest: Option<Contact>,
    /// Reported contacts whose [`Certainty`] is not [`Certainty::Resolved`]: the search gave
    /// up on them (iteration limit, unrepresentable coordinates) and reported a conservative
    /// time. Check it before trusting a time of impact of 0.
    pub unresolved: usize,
    /// `None` when the query ran to its end; else why it stopped early and how far it got
    /// ([`QueryOptions::max_contacts`](crate::QueryOptions::max_contacts),
    /// [`QueryOptions::deadline`](crate::QueryOptions::deadline), a
    /// [`CancelToken`](crate::CancelToken)): the report then holds only part of the step's
    /// contacts (see [`Truncation`](crate::Truncation) for which).
    pub truncated: Option<super::limits::Truncation>,
    /// Whether the report lists every pair within the tolerance of the earliest time (every
    /// contact, in [`Mode::All`](crate::Mode::All)). `false` when the query was truncated,
    /// or when [`Mode::Earliest`](crate::Mode::Earliest) found more such pairs than
    /// [`QueryOptions::max_contacts`](crate::QueryOptions::max_contacts) and kept the
    /// earliest of them. The earliest time itself is exact either way, unless the query
    /// stopped on a deadline or a cancellation.
    pub earliest_complete: bool,
    /// Work counters and timings.
    pub stats: Stats,
}

impl Report {
    /// The earliest time of impact, or `None` when nothing collides.
    pub fn earliest_toi(&self) -> Option<f64> {
        self.earliest.map(|c| c.toi())
    }

    /// Number of colliding pairs of all kinds.
    pub fn contact_count(&self) -> usize {
        self.vf.len() + self.ee.len() + self.ve.len() + self.vv.len()
    }
}

/// Splits the driver's edge-edge contacts (sorted by `(a, b)`) into the report's edge-edge,
/// vertex-edge and vertex-vertex contacts, each sorted ([`Contact::from`]).
/// The lists grow fallibly: an allocation the system refuses is an error, and `ee` is left as
/// it was.
pub(crate) fn split_points(
    ee: &mut Vec<EeContact>,
) -> Result<(Vec<VeContact>, Vec<VvContact>), AllocError> {
    let (mut ve, mut vv) = (Vec::new(), Vec::new());
    for c in ee.iter() {
        match Contact::from(*c) {
            Contact::Ve(v) => try_push(&mut ve, v, "vertex-edge contacts")?,
            Contact::Vv(v) => try_push(&mut vv, v, "vertex-vertex contacts")?,
            _ => {}
        }
    }
    if ve.len() + vv.len() > 0 {
        ee.retain(|c| matches!(Contact::from(*c), Contact::Ee(_)));
    }
    ve.sort_unstable_by_key(|c| (c.vertex, c.edge));
    Ok((ve, vv))
}
