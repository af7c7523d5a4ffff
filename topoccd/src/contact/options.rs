//! Options of the whole-step query, validated once ([`QueryOptions::validate`]).

use crate::kdop::DopKind;
use crate::narrow::NarrowOptions;
use thiserror::Error;

/// What a query reports.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Mode {
    /// Every colliding vertex-face and edge-edge pair with its time of impact.
    #[default]
    All,
    /// Only the earliest time of impact and the pairs attaining it: every pair whose time of
    /// impact is within the tolerance of the earliest (at least one). What a simulator's line
    /// search needs; the query skips work that cannot beat the best time found so far.
    ///
    /// What it reports are contacts of [`Mode::All`], unchanged: All's contacts within the
    /// tolerance of the earliest, but for a pair the elementary test cannot tell from a touch
    /// over the whole step at the time it reports, which Earliest, searching a shorter
    /// interval first, may rule out and leave out: one the search gave up on, or one that
    /// comes within the tolerance without touching then (the solver's bound, which includes
    /// the rounding of the pair's coordinates: with coordinates of 1e300 beside coordinates of
    /// 1, a pair 0.78 apart that touches only later). No pair that touches within the
    /// tolerance of the earliest time is left out.
    Earliest,
}

/// How candidate feature pairs are found. Every method sends its candidates to the same
/// elementary tests, so all report the same contacts, with the same times. The one exception
/// is a pair the elementary test cannot tell from a touch (one that comes within the tolerance
/// without touching, or that the search gave up on) whose features lie in one of
/// [`Method::Cluster`]'s intermediate clusters: the cluster's certificate proves that they never
/// touch, and the cluster method leaves the pair out.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
#[non_exhaustive]
pub enum Method {
    /// The oracle: every vertex-face and edge-edge pair whose swept axis-aligned boxes come
    /// within `min_distance`, found by sort and sweep along x.
    Brute,
    /// A k-DOP bounding volume hierarchy over the triangles' swept volumes, built anew every
    /// step (the paper's baseline, as in Self-CCD).
    Bvh,
    /// The paper's method (section 4): the step's triangles are clustered into leaf and
    /// intermediate clusters proved free of self-contact, a
    /// k-DOP hierarchy is built over the clusters, and a hierarchy over a leaf cluster's
    /// triangles only when that cluster's volume overlaps another's. Feature pairs inside one
    /// intermediate cluster are never tested. See [`QueryOptions::growth`].
    Cluster,
    /// [`Method::Bvh`] or [`Method::Cluster`], chosen for each step by [`Method::resolve`]
    /// from its size; [`Stats::method`](crate::Stats::method) tells which ran. The default.
    #[default]
    Auto,
}

/// [`Method::Auto`] runs [`Method::Cluster`] on steps with at least this many triangles, and
/// [`Method::Bvh`] on smaller ones. Below it the clustering costs about what it saves; above,
/// the certified clusters skip whole patches of pairs and the cluster method is 1.2 to 2.2
/// times faster (the README's table 1).
pub const AUTO_CLUSTER_TRIANGLES: usize = 100_000;

impl Method {
    /// The method that runs on a step of `triangles` triangles: itself, except for
    /// [`Method::Auto`] (see [`AUTO_CLUSTER_TRIANGLES`]).
    ///
    /// ```
    /// use topoccd::Method;
    /// assert_eq!(Method::Auto.resolve(10_000), Method::Bvh);
    /// assert_eq!(Method::Auto.resolve(1_000_000), Method::Cluster);
    /// assert_eq!(Method::Brute.resolve(1_000_000), Method::Brute);
    /// ```
    pub fn resolve(self, triangles: usize) -> Method {
        match self {
            Method::Auto if triangles >= AUTO_CLUSTER_TRIANGLES => Method::Cluster,
            Method::Auto => Method::Bvh,
            m => m,
        }
    }
}

impl std::str::FromStr for Method {
    type Err = String;

    /// `"brute"`, `"bvh"`, `"cluster"` or `"auto"`.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "brute" => Ok(Method::Brute),
            "bvh" => Ok(Method::Bvh),
            "cluster" => Ok(Method::Cluster),
            "auto" => Ok(Method::Auto),
            _ => Err(format!(
                "unknown method {s:?} (expected brute, bvh, cluster or auto)"
            )),
        }
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Method::Brute => "brute",
            Method::Bvh => "bvh",
            Method::Cluster => "cluster",
            Method::Auto => "auto",
        })
    }
}

/// How [`Method::Cluster`] grows its leaf clusters. Both are sound: what makes a cluster free
/// of self-contact is the disk certificate of the cluster method, which both apply.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ClusterGrowth {
    /// The paper's criterion on top of the certificate: a ring joins a leaf only if all its
    /// triangles face away from the observation point (`phi >= 0`, equation 2), and a merge
    /// also needs algorithm 1's `phi` test. On curved cloth it stops at most saddles and
    /// hollows, giving leaves of one or two triangles.
    Paper,
    /// The disk certificate alone (`ClusterOptions::phi_filter`
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

/// Options of [`Ccd::query`](crate::Ccd::query), checked by [`QueryOptions::validate`].
///
/// ```
/// use topoccd::{DopKind, Mode, QueryOptions};
/// let mut options = QueryOptions::default();
/// assert_eq!(options.kdop, DopKind::K18);
/// options.mode = Mode::Earliest;
/// options.narrow.min_distance = 1e-4;
/// assert!(options.validate().is_ok());
/// options.narrow.tolerance = 0.0;
/// assert_eq!(
///     options.validate().unwrap_err().to_string(),
///     "tolerance must be in (0, 1), got 0"
/// );
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct QueryOptions {
    /// Options of the elementary tests. `min_distance` also inflates every bounding volume;
    /// `tmax` bounds the times searched (contacts after it are not reported).
    pub narrow: NarrowOptions,
    /// Which k-DOP bounds the triangles in [`Method::Bvh`]. Default 18, as in the paper.
    pub kdop: DopKind,
    /// Report all contacts or only the earliest.
    pub mode: Mode,
    /// How [`Method::Cluster`] grows its leaf clusters (ignored by the other methods).
    pub growth: ClusterGrowth,
    /// Whether contacts carry their geometry (barycentric coordinates, point and normal at
    /// the time of impact). Default `false`.
    pub geometry: bool,
    /// Whether the two sides of a fresh crack are kept apart: with a topology change
    /// ([`Step::with_parents`](crate::Step::with_parents)), a new vertex and its parent count
    /// as one vertex, so pairs joined that way are not tested. Default `true`.
    pub crack_filter: bool,
    /// The most contacts the report keeps: [`DEFAULT_MAX_CONTACTS`] (one million) by default,
    /// `None` for no limit (asked explicitly: memory then grows with the contacts). Once the
    /// query knows more, it stops and the report says so
    /// ([`Report::truncated`](crate::Report::truncated)): it then holds the first
    /// `max_contacts` contacts of the query's fixed order of work, the same for any thread
    /// count (see [`Truncation`](crate::Truncation)). In [`Mode::Earliest`] the earliest time
    /// stays exact: the query truncates only once it knows that time is 0 (nothing is
    /// earlier), keeping the first `max_contacts` pairs within the tolerance of it; before
    /// that it keeps at most about `max_contacts` of the earliest pairs found, and
    /// [`Report::earliest_complete`](crate::Report::earliest_complete) says whether the pairs
    /// within the tolerance of the earliest time are all listed. Memory then stays bounded by
    /// a few times `max_contacts` contacts (about 112 bytes each).
    ///
    /// A step whose vertices collapsed (positions cast to integers, a mesh scaled to zero)
    /// can have hundreds of millions of contacts at t=0; the cap turns that into a quick,
    /// truncated answer.
    pub max_contacts: Option<usize>,
    /// When the query gives up: past this instant it stops within about a millisecond of
    /// work per thread (the checks run in the traversal tasks, between a few dozen elementary
    /// tests, in the brute-force sweep and in the cluster growth), and the report, holding
    /// only the earliest contact found by then, says so
    /// ([`Report::truncated`](crate::Report::truncated),
    /// [`StopReason::Deadline`](crate::StopReason::Deadline)). `None` (the default): no
    /// deadline. Not serialised. To stop a query from another thread, see
    /// [`Ccd::cancel_token`](crate::Ccd::cancel_token).
    #[cfg_attr(feature = "serde", serde(skip))]
    pub deadline: Option<std::time::Instant>,
}

impl Default for QueryOptions {
    fn default() -> Self {
        Self {
            narrow: NarrowOptions::default(),
            kdop: DopKind::default(),
            mode: Mode::default(),
            growth: ClusterGrowth::default(),
            geometry: false,
            crack_filter: true,
            max_contacts: Some(DEFAULT_MAX_CONTACTS),
            deadline: None,
        }
    }
}

/// The default of [`QueryOptions::max_contacts`]: one million contacts, about 112 MB of
/// report (a few times that while the query runs: 260 MB on one thread, 360 MB on two, on a
/// step whose vertices collapsed), far more than a simulation step has. The Python package,
/// the static check and `batch` use the same default; the line-search helpers keep one pair.
pub const DEFAULT_MAX_CONTACTS: usize = 1_000_000;

/// An option out of its range. The message names the option, its range and the value.
#[derive(Debug, Error, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum OptionsError {
    /// `tolerance` not in `(0, 1)`.
    #[error("tolerance must be in (0, 1), got {0}")]
    Tolerance(f64),
    /// `max_iterations` is 0.
    #[error("max_iterations must be at least 1, got 0")]
    MaxIterations,
    /// `min_distance` negative or not finite.
    #[error("min_distance must be finite and >= 0, got {0}")]
    MinDistance(f64),
    /// `tmax` not in `(0, 1]`.
    #[error("tmax must be in (0, 1], got {0}")]
    Tmax(f64),
    /// [`Ccd::for_each_contact`](crate::Ccd::for_each_contact) asked for
    /// [`Mode::Earliest`], whose pairs are known only at the end.
    #[error("mode Earliest cannot stream its contacts (its pairs are known only at the end); use Ccd::query")]
    Streaming,
    /// An allocation failed (the system refused the memory): the query gave up and freed
    /// what it held. Lower [`QueryOptions::max_contacts`] (its default bounds the report),
    /// or stream the contacts ([`Ccd::for_each_contact`](crate::Ccd::for_each_contact)).
    #[error("out of memory: could not allocate {bytes} bytes for the {what}: set max_contacts (a cap bounds the report) or stream the contacts")]
    OutOfMemory {
        /// The buffer that could not grow.
        what: &'static str,
        /// The bytes asked for.
        bytes: usize,
    },
}

impl From<crate::alloc::AllocError> for OptionsError {
    fn from(e: crate::alloc::AllocError) -> Self {
        Self::OutOfMemory {
            what: e.what,
            bytes: e.bytes,
        }
    }
}

impl QueryOptions {
    /// Checks every option against its documented range. [`Ccd::query`](crate::Ccd::query)
    /// calls it first and refuses invalid options.
    pub fn validate(&self) -> Result<(), OptionsError> {
        self.narrow.validate()
    }
}

impl NarrowOptions {
    /// Checks every option against its documented range, as [`QueryOptions::validate`] and the
    /// [`pair`](crate::pair) tests do.
    ///
    /// ```
    /// use topoccd::{NarrowOptions, OptionsError};
    /// assert!(NarrowOptions::default().validate().is_ok());
    /// let bad = NarrowOptions { tolerance: 0.0, ..NarrowOptions::default() };
    /// assert!(matches!(bad.validate(), Err(OptionsError::Tolerance(_))));
    /// ```
    pub fn validate(&self) -> Result<(), OptionsError> {
        let n = self;
        if !(n.tolerance > 0.0 && n.tolerance < 1.0) {
            return Err(OptionsError::Tolerance(n.tolerance));
        }
        if n.max_iterations == 0 {
            return Err(OptionsError::MaxIterations);
        }
        if !(n.min_distance >= 0.0 && n.min_distance.is_finite()) {
            return Err(OptionsError::MinDistance(n.min_distance));
        }
        if !(n.tmax > 0.0 && n.tmax <= 1.0) {
            return Err(OptionsError::Tmax(n.tmax));
        }
        Ok(())
    }
}
