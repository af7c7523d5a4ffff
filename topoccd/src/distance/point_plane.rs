//! The squared distance from a point to the plane of a triangle, with its gradient and
//! Hessian: `f = ((p - t0) . n)^2 / |n|^2` with `n = (t1 - t0) x (t2 - t0)`, the kernel of
//! [`super::triple`] with `r = p - t0`, `u = t1 - t0`, `v = t2 - t0`.
//!
//! A degenerate triangle (`n == 0` exactly: collinear or coincident corners) has no plane.
//! Its corners then span a line or a point, and the functions return the distance to that
//! span: the point-line distance to the line of the triangle's longest edge, or the
//! point-point distance to `t0` when the corners coincide, with those derivatives (zeros for
//! the corners not involved). Never a NaN for finite input.

use super::linear_map::{pull_back_gradient, pull_back_hessian, scatter_gradient, scatter_hessian};
use super::point_line::{
    point_line_distance, point_line_distance_gradient, point_line_distance_hessian,
};
use super::point_point::{point_point_distance_gradient, point_point_distance_hessian};
use super::triple;
use crate::math::DVec3;

/// Rows: `r = p - t0`, `u = t1 - t0`, `v = t2 - t0`; columns: `p`, `t0`, `t1`, `t2`.
const MAP: [[f64; 4]; 3] = [
    [1.0, -1.0, 0.0, 0.0],
    [0.0, -1.0, 1.0, 0.0],
    [0.0, -1.0, 0.0, 1.0],
];

/// What a triangle with zero normal reduces to.
enum Span {
    /// The line through the two corners (indices among `p, t0, t1, t2`).
    Line([usize; 3]),
    /// The point `t0`.
    Point,
}

/// The span of a degenerate triangle's corners: the line of its longest edge, or `t0`.
#[inline(never)]
fn span(t0: DVec3, t1: DVec3, t2: DVec3) -> Span {
    let l = [
        (t1 - t0).length_squared(),
        (t2 - t1).length_squared(),
        (t0 - t2).length_squared(),
    ];
    let k = if l[0] >= l[1] && l[0] >= l[2] {
        0
    } else if l[1] >= l[2] {
        1
    } else {
        2
    };
    if l[k] == 0.0 {
        return Span::Point;
    }
    Span::Line([0, 1 + k, 1 + (k + 1) % 3])
}

/// The squared distance from `p` to the plane through `t0`, `t1`, `t2` (ipctk's
/// `point_plane_distance`); for a degenerate triangle, to the span of its corners (see the
/// module's documentation).
///
/// ```
/// use topoccd::distance::point_plane_distance;
/// use topoccd::math::DVec3;
/// let d = point_plane_distance(DVec3::new(7.0, -3.0, 2.0), DVec3::ZERO, DVec3::X, DVec3::Y);
/// assert_eq!(d, 4.0);
/// ```
#[inline]
pub fn point_plane_distance(p: DVec3, t0: DVec3, t1: DVec3, t2: DVec3) -> f64 {
    let (u, v) = (t1 - t0, t2 - t0);
    if u.cross(v).length_squared() == 0.0 {
        let x = [p, t0, t1, t2];
        return match span(t0, t1, t2) {
            Span::Line([_, a, b]) => point_line_distance(p, x[a], x[b]),
            Span::Point => (p - t0).length_squared(),
        };
    }
    triple::value(p - t0, u, v)
}

/// The gradient of [`point_plane_distance`] with respect to `p`, `t0`, `t1`, `t2`.
///
/// ```
/// use topoccd::distance::point_plane_distance_gradient;
/// use topoccd::math::DVec3;
/// // 2 above the plane z = 0: 2 d n for the point, shared by the corners with the opposite
/// // sign in proportion to the point's barycentric coordinates (here 1/2, 1/4, 1/4).
/// let g = point_plane_distance_gradient(
///     DVec3::new(0.25, 0.25, 2.0), DVec3::ZERO, DVec3::X, DVec3::Y);
/// assert_eq!(&g[..3], &[0.0, 0.0, 4.0]);
/// assert_eq!([g[5], g[8], g[11]], [-2.0, -1.0, -1.0]);
/// ```
#[inline]
pub fn point_plane_distance_gradient(p: DVec3, t0: DVec3, t1: DVec3, t2: DVec3) -> [f64; 12] {
    let (u, v) = (t1 - t0, t2 - t0);
    if u.cross(v).length_squared() == 0.0 {
        let x = [p, t0, t1, t2];
        return match span(t0, t1, t2) {
            Span::Line(idx) => {
                scatter_gradient(&point_line_distance_gradient(p, x[idx[1]], x[idx[2]]), &idx)
            }
            Span::Point => scatter_gradient(&point_point_distance_gradient(p, t0), &[0, 1]),
        };
    }
    pull_back_gradient(&MAP, &triple::gradient(p - t0, u, v))
}

/// The Hessian of [`point_plane_distance`] with respect to `p`, `t0`, `t1`, `t2`.
///
/// ```
/// use topoccd::distance::point_plane_distance_hessian;
/// use topoccd::math::DVec3;
/// let h = point_plane_distance_hessian(
///     DVec3::new(0.25, 0.25, 2.0), DVec3::ZERO, DVec3::X, DVec3::Y);
/// // In the point's coordinates: 2 n n^T / |n|^2.
/// assert_eq!([h[0][0], h[1][1], h[2][2], h[0][2]], [0.0, 0.0, 2.0, 0.0]);
/// ```
#[inline]
pub fn point_plane_distance_hessian(p: DVec3, t0: DVec3, t1: DVec3, t2: DVec3) -> [[f64; 12]; 12] {
    let (u, v) = (t1 - t0, t2 - t0);
    if u.cross(v).length_squared() == 0.0 {
        let x = [p, t0, t1, t2];
        return match span(t0, t1, t2) {
            Span::Line(idx) => {
                scatter_hessian(&point_line_distance_hessian(p, x[idx[1]], x[idx[2]]), &idx)
            }
            Span::Point => scatter_hessian(&point_point_distance_hessian(p, t0), &[0, 1]),
        };
    }
    pull_back_hessian(&MAP, &triple::hessian(p - t0, u, v))
}
