//! The options of a proximity query.

use std::time::Instant;

use super::ProximityError;

/// How the proximity query finds its candidate pairs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ProximityMethod {
    /// Hierarchies over the features' boxes (faces, edges, free points; four-wide nodes),
    /// kept in the [`Ccd`](crate::Ccd) and refitted while the primitives stay the same: each
    /// vertex against the faces, each edge against the edges.
    #[default]
    Bvh,
    /// One binary hierarchy over the triangles', free edges' and free points' boxes, whose
    /// leaf pairs list their feature pairs: the same report as [`ProximityMethod::Bvh`], kept
    /// to compare the two layouts.
    TriangleTree,
    /// Every feature pair, no hierarchy: the oracle the tests compare against. `O(n^2)`.
    Brute,
}

/// The options of [`Ccd::proximity`](crate::Ccd::proximity) and [`proximity`](crate::proximity()).
///
/// A pair is reported when its distance is below `dhat + dmin` (the IPC toolkit's active
/// set: `d - dmin < dhat`), up to the rounding bound of [`crate::distance::rounding_bound`].
///
/// ```
/// use topoccd::ProximityOptions;
/// let options = ProximityOptions { dhat: 1e-3, ..ProximityOptions::default() };
/// assert!(options.validate().is_ok());
/// assert!(ProximityOptions { dhat: 0.0, ..options }.validate().is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProximityOptions {
    /// The distance threshold, in the coordinates' units, finite and `> 0`. Default 1e-3.
    pub dhat: f64,
    /// The minimum distance offset (a thickness), finite and `>= 0`: pairs closer than
    /// `dmin + dhat` are reported. Default 0.
    pub dmin: f64,
    /// Stop once this many pairs (all kinds together) are found; the report says it is
    /// truncated and holds exactly this many. The pairs kept are those of the first tasks of
    /// the query's fixed order of work, the same for any thread count, and no task holds more
    /// than this many: the query's memory and time are bounded by the cap, not by the
    /// configuration. Default [`DEFAULT_MAX_CONTACTS`](crate::DEFAULT_MAX_CONTACTS)
    /// (one million), as every other entry point: a collapsed configuration (every vertex
    /// within `dhat` of every face) would otherwise list `n²` pairs. `None` lifts the cap.
    /// A query that stays under the cap keeps its pairs for the next query's reuse, as
    /// without one.
    pub max_contacts: Option<usize>,
    /// Stop at this instant (checked as each traversal task starts); the report says it is
    /// truncated, and which pairs it holds then depends on timing. Default `None`.
    pub deadline: Option<Instant>,
    /// The broad phase. Default [`ProximityMethod::Bvh`].
    pub method: ProximityMethod,
}

impl Default for ProximityOptions {
    fn default() -> Self {
        Self {
            dhat: 1e-3,
            dmin: 0.0,
            max_contacts: Some(crate::DEFAULT_MAX_CONTACTS),
            deadline: None,
            method: ProximityMethod::Bvh,
        }
    }
}

impl ProximityOptions {
    /// Checks every option against its documented range.
    pub fn validate(&self) -> Result<(), ProximityError> {
        if !(self.dhat.is_finite() && self.dhat > 0.0) {
            return Err(ProximityError::Dhat(self.dhat));
        }
        if !(self.dmin.is_finite() && self.dmin >= 0.0) {
            return Err(ProximityError::Dmin(self.dmin));
        }
        Ok(())
    }

    /// The distance below which a pair is reported: `dhat + dmin`.
    pub fn threshold(&self) -> f64 {
        self.dhat + self.dmin
    }
}
