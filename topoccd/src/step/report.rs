//! The result of a whole-step query: contacts, the earliest one, and statistics.

use std::cmp::Ordering;

/// A vertex that (may) touch a triangle during the step.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct VfContact {
    /// The vertex index.
    pub vertex: u32,
    /// The triangle's index in [`Step::triangles`](super::Step::triangles).
    pub face: u32,
    /// Time of impact in `[0, t_max]`, no later than the first contact (see
    /// [`narrow`](crate::narrow)).
    pub toi: f64,
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
    /// Time of impact in `[0, t_max]`, no later than the first contact.
    pub toi: f64,
}

/// One contact of either kind.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum Contact {
    /// A vertex-face contact.
    Vf(VfContact),
    /// An edge-edge contact.
    Ee(EeContact),
}

impl Contact {
    /// The time of impact.
    pub fn toi(&self) -> f64 {
        match self {
            Contact::Vf(c) => c.toi,
            Contact::Ee(c) => c.toi,
        }
    }

    /// The order that picks the earliest contact: by time of impact, then vertex-face before
    /// edge-edge, then by `(vertex, face)` or `(a, b)`.
    pub fn earliest_order(&self, other: &Self) -> Ordering {
        self.toi()
            .total_cmp(&other.toi())
            .then_with(|| match (self, other) {
                (Contact::Vf(x), Contact::Vf(y)) => (x.vertex, x.face).cmp(&(y.vertex, y.face)),
                (Contact::Ee(x), Contact::Ee(y)) => (x.a, x.b).cmp(&(y.a, y.b)),
                (Contact::Vf(_), Contact::Ee(_)) => Ordering::Less,
                (Contact::Ee(_), Contact::Vf(_)) => Ordering::Greater,
            })
    }
}

/// Wall-clock time of each phase of a query, in seconds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Seconds {
    /// Topology, feature ownership, swept volumes and the hierarchy (or the oracle's sort).
    /// For [`Method::Cluster`](super::Method::Cluster): the swept volumes, the hierarchy over
    /// the clusters and the lazy hierarchies over leaf clusters' triangles, but not the
    /// clustering itself.
    pub build: f64,
    /// Traversal (or sweep) down to the candidate feature pairs.
    pub traverse: f64,
    /// The elementary tests.
    pub narrow: f64,
    /// The whole query.
    pub total: f64,
    /// [`Method::Cluster`](super::Method::Cluster) only: growing the leaf clusters.
    pub clustering: Option<f64>,
    /// [`Method::Cluster`](super::Method::Cluster) only: merging them into intermediate
    /// clusters.
    pub merging: Option<f64>,
}

/// The figures of the paper's table 2 and the lazy hierarchies of
/// [`Method::Cluster`](super::Method::Cluster).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ClusterFigures {
    /// Number of leaf clusters.
    pub leaf: usize,
    /// Number of intermediate clusters.
    pub intermediate: usize,
    /// Average triangles per leaf cluster (table 2's ratio).
    pub triangles_per_leaf: f64,
    /// Average triangles per intermediate cluster.
    pub triangles_per_intermediate: f64,
    /// Hierarchies built over a leaf cluster's triangles, each at most once per step, only for
    /// leaf clusters whose volume overlaps another's.
    pub lazy_bvhs: usize,
    /// Overlapping pairs of leaf clusters in different intermediate clusters (and leaf pairs
    /// inside an intermediate cluster without certificate, if any).
    pub leaf_pairs: u64,
    /// Leaf clusters tested for self-contact because they carry no certificate (always `0`
    /// with the clustering of this crate, whose leaves are all certified).
    pub uncertified_leaves: usize,
}

/// Work counters of a query.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Stats {
    /// Bounding-volume overlap tests: k-DOP node pairs in [`Method::Bvh`](super::Method::Bvh)
    /// (in [`Method::Cluster`](super::Method::Cluster): of the cluster hierarchy and of the
    /// lazy hierarchies), box pairs of the sweep in [`Method::Brute`](super::Method::Brute).
    pub bv_tests: u64,
    /// Vertex-face pairs given to the narrow phase (its conservative prefilter, then the
    /// elementary test for the pairs it cannot reject); each pair at most once per query.
    pub vf_tests: u64,
    /// Edge-edge pairs given to the narrow phase, as for `vf_tests`; each pair at most once.
    pub ee_tests: u64,
    /// Time of each phase.
    pub seconds: Seconds,
    /// [`Method::Cluster`](super::Method::Cluster) only: the clusters and lazy hierarchies.
    pub cluster: Option<ClusterFigures>,
}

/// The result of a whole-step query.
#[derive(Clone, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Report {
    /// Colliding vertex-face pairs, sorted by `(vertex, face)`. Empty in
    /// [`Mode::Earliest`](super::Mode::Earliest).
    pub vf: Vec<VfContact>,
    /// Colliding edge-edge pairs, sorted by `(a, b)`. Empty in
    /// [`Mode::Earliest`](super::Mode::Earliest).
    pub ee: Vec<EeContact>,
    /// The earliest contact (the first in [`Contact::earliest_order`]), or `None` when nothing
    /// collides.
    pub earliest: Option<Contact>,
    /// Work counters and timings.
    pub stats: Stats,
}

impl Report {
    /// The earliest time of impact, or `None` when nothing collides.
    pub fn earliest_toi(&self) -> Option<f64> {
        self.earliest.map(|c| c.toi())
    }

    /// Number of colliding pairs of both kinds.
    pub fn contact_count(&self) -> usize {
        self.vf.len() + self.ee.len()
    }
}
