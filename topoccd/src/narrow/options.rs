//! Options of the elementary tests.

/// Options of the elementary tests (vertex-face and edge-edge).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct NarrowOptions {
    /// Resolution of the search, absolute, in time units and in the features' own parameters
    /// (barycentric / edge coordinates), in `(0, 1)`. The reported time of impact is never
    /// later than the true first contact, and at most this much earlier unless the features
    /// come close before they touch: closer than `min_distance` plus `sqrt(3) / 2` times
    /// this much times their relative displacement over the step (the sum, over the three
    /// difference vectors of the elementary test, of their largest coordinate change), plus
    /// the rounding of their coordinates, which, with coordinates of 1e300 beside coordinates
    /// of 1, can exceed the gaps between the small ones. Nearly parallel edges keep this bound
    /// too (see the solver's documentation). Default `1e-6`.
    pub tolerance: f64,
    /// Most boxes of the parameter domain the search may examine, at least 1. When it runs out,
    /// the answer is a contact at the earliest time not yet ruled out
    /// ([`Certainty::IterationLimit`](super::Certainty::IterationLimit)). Default `1_000_000`.
    pub max_iterations: u32,
    /// Distance, in the coordinates' units, at or below which the features count as touching.
    /// `>= 0`. Default `0`.
    pub min_distance: f64,
    /// End of the time interval searched, in time units, in `(0, 1]`. Default `1`.
    pub tmax: f64,
}

impl Default for NarrowOptions {
    fn default() -> Self {
        Self {
            tolerance: 1e-6,
            max_iterations: 1_000_000,
            min_distance: 0.0,
            tmax: 1.0,
        }
    }
}
