//! The distance between two points.

use crate::math::DVec3;

/// The squared distance between points `p` and `q` (exact but for the rounding of the
/// difference and of the squared norm).
///
/// ```
/// use topoccd::distance::point_point_distance;
/// use topoccd::math::DVec3;
/// assert_eq!(point_point_distance(DVec3::ZERO, DVec3::new(3.0, 4.0, 0.0)), 25.0);
/// ```
#[inline]
pub fn point_point_distance(p: DVec3, q: DVec3) -> f64 {
    (q - p).length_squared()
}
