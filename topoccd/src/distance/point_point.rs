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

/// The gradient of [`point_point_distance`] with respect to `p` then `q`:
/// `(2 (p - q), 2 (q - p))`.
///
/// ```
/// use topoccd::distance::point_point_distance_gradient;
/// use topoccd::math::DVec3;
/// let g = point_point_distance_gradient(DVec3::ZERO, DVec3::new(3.0, 4.0, 0.0));
/// assert_eq!(g, [-6.0, -8.0, 0.0, 6.0, 8.0, 0.0]);
/// ```
#[inline]
pub fn point_point_distance_gradient(p: DVec3, q: DVec3) -> [f64; 6] {
    let d = (p - q) * 2.0;
    [d.x, d.y, d.z, -d.x, -d.y, -d.z]
}

/// The Hessian of [`point_point_distance`] with respect to `p` then `q`: the constant
/// `[[2 I, -2 I], [-2 I, 2 I]]`.
///
/// ```
/// use topoccd::distance::point_point_distance_hessian;
/// use topoccd::math::DVec3;
/// let h = point_point_distance_hessian(DVec3::ZERO, DVec3::X);
/// assert_eq!((h[0][0], h[0][3], h[1][0]), (2.0, -2.0, 0.0));
/// ```
#[inline]
pub fn point_point_distance_hessian(_p: DVec3, _q: DVec3) -> [[f64; 6]; 6] {
    let mut h = [[0.0; 6]; 6];
    for i in 0..3 {
        h[i][i] = 2.0;
        h[i + 3][i + 3] = 2.0;
        h[i][i + 3] = -2.0;
        h[i + 3][i] = -2.0;
    }
    h
}
