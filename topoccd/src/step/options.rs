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
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Method::Brute => "brute",
            Method::Bvh => "bvh",
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
}
