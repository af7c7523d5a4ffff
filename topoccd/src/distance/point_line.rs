//! The squared distance from a point to an infinite line, with its gradient and Hessian.
//!
//! With `r = p - e0` and `u = e1 - e0`, `f = |r x u|^2 / |u|^2 = |w|^2`, where
//! `w = r - t u` is the part of `r` normal to the line and `t = r.u / |u|^2`. Then
//!
//! - `df/dr = 2 w`, `df/du = -2 t w`;
//! - `d2f/dr2 = 2 (I - u u^T / |u|^2)`, `d2f/dr du = -2 t I - (2 / |u|^2) u q^T` and
//!   `d2f/du2 = 2 t^2 I - (2 / |u|^2) q q^T`, with `q = r - 2 t u`;
//!
//! and the derivatives in `(p, e0, e1)` follow from `r` and `u` being differences of them.
//!
//! A degenerate line (`e0 == e1` exactly) is the point `e0`: the functions return the
//! point-point distance `|p - e0|^2` and its derivatives (with zeros for `e1`), never a NaN.

use super::linear_map::{add_block, diag_outer, pull_back_gradient, pull_back_hessian};
use crate::math::DVec3;

/// Rows: `r = p - e0`, `u = e1 - e0`; columns: `p`, `e0`, `e1`.
const MAP: [[f64; 3]; 2] = [[1.0, -1.0, 0.0], [0.0, -1.0, 1.0]];

/// The squared distance from `p` to the infinite line through `e0` and `e1`, as
/// `|(e0 - p) x (e1 - p)|^2 / |e1 - e0|^2` (ipctk's formula); `|p - e0|^2` when `e0 == e1`.
///
/// ```
/// use topoccd::distance::point_line_distance;
/// use topoccd::math::DVec3;
/// let d = point_line_distance(DVec3::new(5.0, 3.0, 4.0), DVec3::ZERO, DVec3::X);
/// assert_eq!(d, 25.0);
/// ```
#[inline]
pub fn point_line_distance(p: DVec3, e0: DVec3, e1: DVec3) -> f64 {
    let a = (e1 - e0).length_squared();
    if a == 0.0 {
        return (p - e0).length_squared();
    }
    (e0 - p).cross(e1 - p).length_squared() / a
}

/// The gradient of [`point_line_distance`] with respect to `p`, `e0`, `e1`.
///
/// ```
/// use topoccd::distance::point_line_distance_gradient;
/// use topoccd::math::DVec3;
/// // The point 2 above the middle of the line: pushing it up, or the line down, adds 2 d.
/// let g = point_line_distance_gradient(DVec3::new(0.5, 2.0, 0.0), DVec3::ZERO, DVec3::X);
/// assert_eq!(g, [0.0, 4.0, 0.0, 0.0, -2.0, 0.0, 0.0, -2.0, 0.0]);
/// ```
#[inline]
pub fn point_line_distance_gradient(p: DVec3, e0: DVec3, e1: DVec3) -> [f64; 9] {
    pull_back_gradient(&MAP, &gradient_ru(p - e0, e1 - e0))
}

/// The Hessian of [`point_line_distance`] with respect to `p`, `e0`, `e1`.
///
/// ```
/// use topoccd::distance::point_line_distance_hessian;
/// use topoccd::math::DVec3;
/// let h = point_line_distance_hessian(DVec3::new(0.5, 2.0, 0.0), DVec3::ZERO, DVec3::X);
/// // Along the line the distance does not change; across it, it is 2 |dp|^2.
/// assert_eq!((h[0][0], h[1][1], h[2][2]), (0.0, 2.0, 2.0));
/// ```
#[inline]
pub fn point_line_distance_hessian(p: DVec3, e0: DVec3, e1: DVec3) -> [[f64; 9]; 9] {
    pull_back_hessian(&MAP, &hessian_ru(p - e0, e1 - e0))
}

/// The gradient of `|r x u|^2 / |u|^2` with respect to `r` then `u`.
#[inline]
pub(crate) fn gradient_ru(r: DVec3, u: DVec3) -> [f64; 6] {
    let a = u.length_squared();
    if a == 0.0 {
        let g = r * 2.0;
        return [g.x, g.y, g.z, 0.0, 0.0, 0.0];
    }
    let t = r.dot(u) / a;
    let w = r - u * t;
    let (gr, gu) = (w * 2.0, w * (-2.0 * t));
    [gr.x, gr.y, gr.z, gu.x, gu.y, gu.z]
}

/// The Hessian of `|r x u|^2 / |u|^2` with respect to `r` then `u`.
#[inline]
pub(crate) fn hessian_ru(r: DVec3, u: DVec3) -> [[f64; 6]; 6] {
    let mut h = [[0.0; 6]; 6];
    let a = u.length_squared();
    if a == 0.0 {
        for (i, row) in h.iter_mut().take(3).enumerate() {
            row[i] = 2.0;
        }
        return h;
    }
    let t = r.dot(u) / a;
    let q = r - u * (2.0 * t);
    add_block(&mut h, 0, 0, diag_outer(2.0, -2.0 / a, u, u));
    add_block(&mut h, 0, 1, diag_outer(-2.0 * t, -2.0 / a, u, q));
    add_block(&mut h, 1, 1, diag_outer(2.0 * t * t, -2.0 / a, q, q));
    h
}
