//! Options of the whole-step query.

use crate::kdop::DopKind;
use crate::narrow::NarrowOptions;

/// What a query reports.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Mode {
    /// Every colliding vertex-face and edge-edge pair with its time of impact.
    #[default]
    All,
    /// Only the earliest time of impact and one pair attaining it (what a simulator's line
    /// search needs). The query may skip work that cannot beat the best time found so far.
    Earliest,
}

/// How candidate feature pairs are found. Every method sends its candidates to the same
/// elementary tests, so all report the same contacts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum Method {
    /// The oracle: every vertex-face and edge-edge pair whose swept axis-aligned boxes come
    /// within `min_separation`, found by sort and sweep along x.
    Brute,
    /// A k-DOP bounding volume hierarchy over the triangles' swept volumes, built anew every
    /// step (the paper's baseline, as in Self-CCD).
    #[default]
    Bvh,
    /// The paper's method (section 4): the step's triangles are clustered into leaf and
    /// intermediate clusters proved free of self-contact ([`cluster`](crate::cluster)), a
    /// k-DOP hierarchy is built over the clusters, and a hierarchy over a leaf cluster's
    /// triangles only when that cluster's volume overlaps another's. Feature pairs inside one
    /// intermediate cluster are never tested. See [`QueryOptions::growth`].
    Cluster,
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Method::Brute => "brute",
            Method::Bvh => "bvh",
            Method::Cluster => "cluster",
        })
    }
}

/// How [`Method::Cluster`] grows its leaf clusters. Both are sound: what makes a cluster free
/// of self-contact is the disk certificate of [`cluster`](crate::cluster), which both apply.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ClusterGrowth {
    /// The paper's criterion on top of the certificate: a ring joins a leaf only if all its
    /// triangles face away from the observation point (`phi >= 0`, equation 2), and a merge
    /// also needs algorithm 1's `phi` test. On curved cloth it stops at most saddles and
    /// hollows, giving leaves of one or two triangles.
    Paper,
    /// The disk certificate alone ([`ClusterOptions::phi_filter`](crate::cluster::ClusterOptions::phi_filter)
    /// `false`): far bigger clusters, fewer candidate pairs; the default.
    #[default]
    Certificate,
}

impl std::fmt::Display for ClusterGrowth {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ClusterGrowth::Paper => "paper",
            ClusterGrowth::Certificate => "certificate",
        })
    }
}

/// Options of [`Ccd::query`](super::Ccd::query).
///
/// ```
/// use topoccd::kdop::DopKind;
/// use topoccd::step::{Mode, QueryOptions};
/// let mut options = QueryOptions::default();
/// assert_eq!(options.kdop, DopKind::K18);
/// options.mode = Mode::Earliest;
/// options.narrow.min_separation = 1e-4;
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct QueryOptions {
    /// Options of the elementary tests. `min_separation` also inflates every bounding volume;
    /// `t_max` bounds the times searched (contacts after it are not reported).
    pub narrow: NarrowOptions,
    /// Which k-DOP bounds the triangles in [`Method::Bvh`]. Default 18, as in the paper.
    pub kdop: DopKind,
    /// Report all contacts or only the earliest.
    pub mode: Mode,
    /// How [`Method::Cluster`] grows its leaf clusters (ignored by the other methods).
    pub growth: ClusterGrowth,
}
