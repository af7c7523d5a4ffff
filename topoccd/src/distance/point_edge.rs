//! The distance between a point and a segment, with the closest feature of the segment.

use crate::math::DVec3;

/// Which feature of the segment `e0 e1` is closest to the point (the IPC toolkit's
/// `PointEdgeDistanceType`, same order).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[repr(u8)]
pub enum PointEdgeType {
    /// The endpoint `e0` (ipctk's `P_E0`).
    E0 = 0,
    /// The endpoint `e1` (`P_E1`).
    E1 = 1,
    /// The interior of the segment (`P_E`).
    Interior = 2,
}

/// The squared distance from `p` to the segment `e0 e1` and its closest feature, computed
/// relative to `e0`. A degenerate segment (`e0 == e1`) is its endpoint `e0`.
///
/// ```
/// use topoccd::distance::{point_edge_distance, PointEdgeType};
/// use topoccd::math::DVec3;
/// let (e0, e1) = (DVec3::ZERO, DVec3::X);
/// assert_eq!(point_edge_distance(DVec3::new(0.5, 2.0, 0.0), e0, e1), (4.0, PointEdgeType::Interior));
/// assert_eq!(point_edge_distance(DVec3::new(-3.0, 0.0, 4.0), e0, e1), (25.0, PointEdgeType::E0));
/// assert_eq!(point_edge_distance(DVec3::new(2.0, 0.0, 0.0), e0, e1), (1.0, PointEdgeType::E1));
/// ```
#[inline]
pub fn point_edge_distance(p: DVec3, e0: DVec3, e1: DVec3) -> (f64, PointEdgeType) {
    segment(p - e0, e1 - e0)
}

/// The squared distance from `w` (the point minus `e0`) to the segment from the origin to
/// `e` (= `e1 - e0`), and its type.
#[inline]
pub(crate) fn segment(w: DVec3, e: DVec3) -> (f64, PointEdgeType) {
    let ee = e.length_squared();
    let we = w.dot(e);
    if we <= 0.0 || ee == 0.0 {
        return (w.length_squared(), PointEdgeType::E0);
    }
    if we >= ee {
        return ((w - e).length_squared(), PointEdgeType::E1);
    }
    let t = we / ee;
    // The interior point is on the segment (t in (0, 1)); the endpoints may still be closer
    // after rounding, so the minimum of the three is kept.
    let interior = (w - e * t).length_squared();
    let (d0, d1) = (w.length_squared(), (w - e).length_squared());
    if interior <= d0 && interior <= d1 {
        (interior, PointEdgeType::Interior)
    } else if d0 <= d1 {
        (d0, PointEdgeType::E0)
    } else {
        (d1, PointEdgeType::E1)
    }
}
