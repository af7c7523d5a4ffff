//! The squared distance between two infinite lines, with its gradient and Hessian:
//! `f = ((eb0 - ea0) . n)^2 / |n|^2` with `n = (ea1 - ea0) x (eb1 - eb0)`, the kernel of
//! [`super::triple`] with `r = eb0 - ea0`, `u = ea1 - ea0`, `v = eb1 - eb0`.
//!
//! Parallel lines (`n == 0` exactly) have no common normal; the functions then return the
//! distance between the lines all the same: from `ea0` to line b, or, when edge b is a
//! point, from `eb0` to line a, or, when both are points, between `ea0` and `eb0`, with those
//! derivatives (zeros for the points not involved). The value has no limit as two lines
//! become parallel (it depends on the direction of approach), so this is a convention, not a
//! continuous extension. Never a NaN for finite input.

use super::linear_map::{pull_back_gradient, pull_back_hessian, scatter_gradient, scatter_hessian};
use super::point_line::{
    point_line_distance, point_line_distance_gradient, point_line_distance_hessian,
};
use super::point_point::{point_point_distance_gradient, point_point_distance_hessian};
use super::triple;
use crate::math::DVec3;

/// Rows: `r = eb0 - ea0`, `u = ea1 - ea0`, `v = eb1 - eb0`; columns: `ea0`, `ea1`, `eb0`,
/// `eb1`.
const MAP: [[f64; 4]; 3] = [
    [-1.0, 0.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, -1.0, 1.0],
];

/// The sub-distance of parallel lines: indices of (point, line start, line end) among
/// `ea0, ea1, eb0, eb1`, or `None` for point-point `ea0 eb0`.
#[inline(never)]
fn parallel(u: DVec3, v: DVec3) -> Option<[usize; 3]> {
    if v.length_squared() > 0.0 {
        Some([0, 2, 3])
    } else if u.length_squared() > 0.0 {
        Some([2, 0, 1])
    } else {
        None
    }
}

/// The squared distance between the line through `ea0`, `ea1` and the line through `eb0`,
/// `eb1` (ipctk's `line_line_distance`); for parallel lines see the module's documentation.
///
/// ```
/// use topoccd::distance::line_line_distance;
/// use topoccd::math::DVec3;
/// let d = line_line_distance(DVec3::ZERO, DVec3::X, DVec3::new(5.0, 0.0, 3.0), DVec3::new(5.0, 1.0, 3.0));
/// assert_eq!(d, 9.0);
/// ```
#[inline]
pub fn line_line_distance(ea0: DVec3, ea1: DVec3, eb0: DVec3, eb1: DVec3) -> f64 {
    let (u, v) = (ea1 - ea0, eb1 - eb0);
    if u.cross(v).length_squared() == 0.0 {
        let x = [ea0, ea1, eb0, eb1];
        return match parallel(u, v) {
            Some([a, b, c]) => point_line_distance(x[a], x[b], x[c]),
            None => (eb0 - ea0).length_squared(),
        };
    }
    triple::value(eb0 - ea0, u, v)
}

/// The gradient of [`line_line_distance`] with respect to `ea0`, `ea1`, `eb0`, `eb1`.
///
/// ```
/// use topoccd::distance::line_line_distance_gradient;
/// use topoccd::math::DVec3;
/// // Crossing lines 3 apart along z: moving line b up by dz adds 2 * 3 dz, split between its
/// // points by where the closest point lies (here at eb0).
/// let g = line_line_distance_gradient(
///     DVec3::ZERO, DVec3::X, DVec3::new(0.0, 0.0, 3.0), DVec3::new(0.0, 1.0, 3.0));
/// assert_eq!([g[2], g[5], g[8], g[11]], [-6.0, 0.0, 6.0, 0.0]);
/// ```
#[inline]
pub fn line_line_distance_gradient(ea0: DVec3, ea1: DVec3, eb0: DVec3, eb1: DVec3) -> [f64; 12] {
    let (u, v) = (ea1 - ea0, eb1 - eb0);
    if u.cross(v).length_squared() == 0.0 {
        let x = [ea0, ea1, eb0, eb1];
        return match parallel(u, v) {
            Some(idx) => scatter_gradient(
                &point_line_distance_gradient(x[idx[0]], x[idx[1]], x[idx[2]]),
                &idx,
            ),
            None => scatter_gradient(&point_point_distance_gradient(ea0, eb0), &[0, 2]),
        };
    }
    pull_back_gradient(&MAP, &triple::gradient(eb0 - ea0, u, v))
}

/// The Hessian of [`line_line_distance`] with respect to `ea0`, `ea1`, `eb0`, `eb1`.
///
/// ```
/// use topoccd::distance::line_line_distance_hessian;
/// use topoccd::math::DVec3;
/// let h = line_line_distance_hessian(
///     DVec3::ZERO, DVec3::X, DVec3::new(0.0, 0.0, 3.0), DVec3::new(0.0, 1.0, 3.0));
/// // ea0 raised by t (ea1 fixed) tilts line a: d(t) = (3 - t)^2 / (1 + t^2) = 9 - 6t - 8t^2 + ...
/// assert_eq!(h[2][2], -16.0);
/// ```
#[inline]
pub fn line_line_distance_hessian(
    ea0: DVec3,
    ea1: DVec3,
    eb0: DVec3,
    eb1: DVec3,
) -> [[f64; 12]; 12] {
    let (u, v) = (ea1 - ea0, eb1 - eb0);
    if u.cross(v).length_squared() == 0.0 {
        let x = [ea0, ea1, eb0, eb1];
        return match parallel(u, v) {
            Some(idx) => scatter_hessian(
                &point_line_distance_hessian(x[idx[0]], x[idx[1]], x[idx[2]]),
                &idx,
            ),
            None => scatter_hessian(&point_point_distance_hessian(ea0, eb0), &[0, 2]),
        };
    }
    pull_back_hessian(&MAP, &triple::hessian(eb0 - ea0, u, v))
}
