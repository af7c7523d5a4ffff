//! The edge-edge mollifier of the IPC toolkit (`edge_edge_mollifier.cpp`), which smooths the
//! edge-edge barrier as two edges become parallel.
//!
//! With `x = |(ea1 - ea0) x (eb1 - eb0)|^2` and a threshold `eps_x` from the rest positions
//! ([`edge_edge_mollifier_threshold`]), the mollifier is `m(x) = (2 - x / eps_x) x / eps_x`
//! below `eps_x` and 1 above: `m(0) = 0`, `m(eps_x) = 1` with zero slope there. Its
//! derivatives: `m' = (2 / eps_x) (1 - x / eps_x)`, `m'' = -2 / eps_x^2` (0 above `eps_x`).
//!
//! The cross product's squared norm `x = |n|^2`, `n = u x v` with `u = ea1 - ea0` and
//! `v = eb1 - eb0`, has `dx/du = 2 v x n`, `dx/dv = 2 n x u`, `d2x/du2 = 2 (|v|^2 I - v v^T)`,
//! `d2x/dv2 = 2 (|u|^2 I - u u^T)` and `d2x/du dv = 2 (2 u v^T - v u^T - (u.v) I)`; the
//! composed mollifier has gradient `m' grad x` and Hessian `m' hess x + m'' grad x grad x^T`.

use super::linear_map::{add_block, diag_outer, pull_back_gradient, pull_back_hessian};
use crate::math::DVec3;

/// Rows: `u = ea1 - ea0`, `v = eb1 - eb0`; columns: `ea0`, `ea1`, `eb0`, `eb1`.
const MAP: [[f64; 4]; 2] = [[-1.0, 1.0, 0.0, 0.0], [0.0, 0.0, -1.0, 1.0]];

/// ipctk's scale of the threshold: `eps_x = 1e-3 |ea|^2 |eb|^2` at rest.
const THRESHOLD_SCALE: f64 = 1e-3;

/// The squared norm of the cross product of the edges, `|(ea1 - ea0) x (eb1 - eb0)|^2`
/// (`|ea|^2 |eb|^2` times the squared sine of their angle).
///
/// ```
/// use topoccd::distance::edge_edge_cross_squarednorm;
/// use topoccd::math::DVec3;
/// let x = edge_edge_cross_squarednorm(DVec3::ZERO, DVec3::X * 2.0, DVec3::Z, DVec3::Z + DVec3::Y * 3.0);
/// assert_eq!(x, 36.0);
/// ```
#[inline]
pub fn edge_edge_cross_squarednorm(ea0: DVec3, ea1: DVec3, eb0: DVec3, eb1: DVec3) -> f64 {
    (ea1 - ea0).cross(eb1 - eb0).length_squared()
}

/// The gradient of [`edge_edge_cross_squarednorm`] with respect to `ea0`, `ea1`, `eb0`,
/// `eb1`.
///
/// ```
/// use topoccd::distance::edge_edge_cross_squarednorm_gradient;
/// use topoccd::math::DVec3;
/// // Perpendicular edges: lengthening edge a by dx scales x = |ea|^2 |eb|^2 by (1 + dx)^2.
/// let g = edge_edge_cross_squarednorm_gradient(DVec3::ZERO, DVec3::X, DVec3::Z, DVec3::Z + DVec3::Y);
/// assert_eq!((g[3], g[0], g[10]), (2.0, -2.0, 2.0));
/// ```
#[inline]
pub fn edge_edge_cross_squarednorm_gradient(
    ea0: DVec3,
    ea1: DVec3,
    eb0: DVec3,
    eb1: DVec3,
) -> [f64; 12] {
    pull_back_gradient(&MAP, &cross_gradient_uv(ea1 - ea0, eb1 - eb0))
}

/// The Hessian of [`edge_edge_cross_squarednorm`] with respect to `ea0`, `ea1`, `eb0`,
/// `eb1`.
///
/// ```
/// use topoccd::distance::edge_edge_cross_squarednorm_hessian;
/// use topoccd::math::DVec3;
/// let h = edge_edge_cross_squarednorm_hessian(DVec3::ZERO, DVec3::X, DVec3::Z, DVec3::Z + DVec3::Y);
/// assert_eq!((h[3][3], h[4][4], h[3][0]), (2.0, 0.0, -2.0));
/// ```
#[inline]
pub fn edge_edge_cross_squarednorm_hessian(
    ea0: DVec3,
    ea1: DVec3,
    eb0: DVec3,
    eb1: DVec3,
) -> [[f64; 12]; 12] {
    pull_back_hessian(&MAP, &cross_hessian_uv(ea1 - ea0, eb1 - eb0, 1.0))
}

/// The gradient of `|u x v|^2` with respect to `u` then `v`.
#[inline]
fn cross_gradient_uv(u: DVec3, v: DVec3) -> [f64; 6] {
    let n = u.cross(v);
    let (gu, gv) = (v.cross(n) * 2.0, n.cross(u) * 2.0);
    [gu.x, gu.y, gu.z, gv.x, gv.y, gv.z]
}

/// `scale` times the Hessian of `|u x v|^2` with respect to `u` then `v`.
#[inline]
fn cross_hessian_uv(u: DVec3, v: DVec3, scale: f64) -> [[f64; 6]; 6] {
    let mut h = [[0.0; 6]; 6];
    let (uu, uv, vv) = (u.dot(u), u.dot(v), v.dot(v));
    let s2 = 2.0 * scale;
    add_block(&mut h, 0, 0, diag_outer(s2 * vv, -s2, v, v));
    add_block(&mut h, 1, 1, diag_outer(s2 * uu, -s2, u, u));
    let mut b = diag_outer(-s2 * uv, 2.0 * s2, u, v);
    let vu = diag_outer(0.0, -s2, v, u);
    for i in 0..3 {
        for j in 0..3 {
            b[i][j] += vu[i][j];
        }
    }
    add_block(&mut h, 0, 1, b);
    h
}

/// The mollifier's threshold from the rest positions of the edges:
/// `eps_x = 1e-3 |ea1_rest - ea0_rest|^2 |eb1_rest - eb0_rest|^2` (ipctk's constant).
///
/// ```
/// use topoccd::distance::edge_edge_mollifier_threshold;
/// use topoccd::math::DVec3;
/// let eps_x = edge_edge_mollifier_threshold(DVec3::ZERO, DVec3::X * 2.0, DVec3::Z, DVec3::Z + DVec3::Y);
/// assert_eq!(eps_x, 4e-3);
/// ```
#[inline]
pub fn edge_edge_mollifier_threshold(
    ea0_rest: DVec3,
    ea1_rest: DVec3,
    eb0_rest: DVec3,
    eb1_rest: DVec3,
) -> f64 {
    THRESHOLD_SCALE
        * (ea0_rest - ea1_rest).length_squared()
        * (eb0_rest - eb1_rest).length_squared()
}

/// The mollifier `m(x) = (2 - x / eps_x) x / eps_x` for `x < eps_x`, else 1; `x` is
/// [`edge_edge_cross_squarednorm`] (>= 0) and `eps_x` the threshold (> 0).
///
/// ```
/// use topoccd::distance::edge_edge_mollifier_scalar;
/// assert_eq!(edge_edge_mollifier_scalar(0.5, 1.0), 0.75);
/// assert_eq!(edge_edge_mollifier_scalar(2.0, 1.0), 1.0);
/// ```
#[inline]
pub fn edge_edge_mollifier_scalar(x: f64, eps_x: f64) -> f64 {
    if x < eps_x {
        let r = x / eps_x;
        (2.0 - r) * r
    } else {
        1.0
    }
}

/// The derivative `dm/dx = (2 / eps_x) (1 - x / eps_x)` of [`edge_edge_mollifier_scalar`]
/// for `x < eps_x`, else 0.
///
/// ```
/// use topoccd::distance::edge_edge_mollifier_derivative;
/// assert_eq!(edge_edge_mollifier_derivative(0.5, 1.0), 1.0);
/// assert_eq!(edge_edge_mollifier_derivative(1.0, 1.0), 0.0);
/// ```
#[inline]
pub fn edge_edge_mollifier_derivative(x: f64, eps_x: f64) -> f64 {
    if x < eps_x {
        let inv = 1.0 / eps_x;
        2.0 * inv * (-inv).mul_add(x, 1.0)
    } else {
        0.0
    }
}

/// The second derivative `d2m/dx2 = -2 / eps_x^2` of [`edge_edge_mollifier_scalar`] for
/// `x < eps_x`, else 0.
///
/// ```
/// use topoccd::distance::edge_edge_mollifier_second_derivative;
/// assert_eq!(edge_edge_mollifier_second_derivative(0.5, 2.0), -0.5);
/// assert_eq!(edge_edge_mollifier_second_derivative(3.0, 2.0), 0.0);
/// ```
#[inline]
pub fn edge_edge_mollifier_second_derivative(x: f64, eps_x: f64) -> f64 {
    if x < eps_x {
        -2.0 / (eps_x * eps_x)
    } else {
        0.0
    }
}

/// The mollifier of the edges `ea0 ea1` and `eb0 eb1`:
/// [`edge_edge_mollifier_scalar`] of their [`edge_edge_cross_squarednorm`].
///
/// ```
/// use topoccd::distance::{edge_edge_mollifier, edge_edge_mollifier_threshold};
/// use topoccd::math::DVec3;
/// let (ea0, ea1) = (DVec3::ZERO, DVec3::X);
/// let eps_x = edge_edge_mollifier_threshold(ea0, ea1, DVec3::Z, DVec3::Z + DVec3::Y);
/// // Perpendicular: 1. Parallel: 0.
/// assert_eq!(edge_edge_mollifier(ea0, ea1, DVec3::Z, DVec3::Z + DVec3::Y, eps_x), 1.0);
/// assert_eq!(edge_edge_mollifier(ea0, ea1, DVec3::Z, DVec3::Z + DVec3::X, eps_x), 0.0);
/// ```
#[inline]
pub fn edge_edge_mollifier(ea0: DVec3, ea1: DVec3, eb0: DVec3, eb1: DVec3, eps_x: f64) -> f64 {
    edge_edge_mollifier_scalar(edge_edge_cross_squarednorm(ea0, ea1, eb0, eb1), eps_x)
}

/// The gradient of [`edge_edge_mollifier`] with respect to `ea0`, `ea1`, `eb0`, `eb1`
/// (zero where `x >= eps_x`).
///
/// ```
/// use topoccd::distance::edge_edge_mollifier_gradient;
/// use topoccd::math::DVec3;
/// let g = edge_edge_mollifier_gradient(DVec3::ZERO, DVec3::X, DVec3::Z, DVec3::Z + DVec3::Y, 1e-3);
/// assert_eq!(g, [0.0; 12]); // not nearly parallel
/// ```
#[inline]
pub fn edge_edge_mollifier_gradient(
    ea0: DVec3,
    ea1: DVec3,
    eb0: DVec3,
    eb1: DVec3,
    eps_x: f64,
) -> [f64; 12] {
    let x = edge_edge_cross_squarednorm(ea0, ea1, eb0, eb1);
    if x >= eps_x {
        return [0.0; 12];
    }
    let d = edge_edge_mollifier_derivative(x, eps_x);
    edge_edge_cross_squarednorm_gradient(ea0, ea1, eb0, eb1).map(|g| d * g)
}

/// The Hessian of [`edge_edge_mollifier`] with respect to `ea0`, `ea1`, `eb0`, `eb1`
/// (zero where `x >= eps_x`).
///
/// ```
/// use topoccd::distance::edge_edge_mollifier_hessian;
/// use topoccd::math::DVec3;
/// // Parallel edges: x = 0 is a minimum of x, so only m' times the Hessian of x is left.
/// let h = edge_edge_mollifier_hessian(DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Y + DVec3::X, 1.0);
/// assert_eq!((h[4][4], h[3][3]), (4.0, 0.0)); // ea1 moving across edge b's direction
/// ```
#[inline]
pub fn edge_edge_mollifier_hessian(
    ea0: DVec3,
    ea1: DVec3,
    eb0: DVec3,
    eb1: DVec3,
    eps_x: f64,
) -> [[f64; 12]; 12] {
    let (u, v) = (ea1 - ea0, eb1 - eb0);
    let x = u.cross(v).length_squared();
    if x >= eps_x {
        return [[0.0; 12]; 12];
    }
    let d1 = edge_edge_mollifier_derivative(x, eps_x);
    let d2 = edge_edge_mollifier_second_derivative(x, eps_x);
    let g = cross_gradient_uv(u, v);
    let mut h = cross_hessian_uv(u, v, d1);
    for (row, gi) in h.iter_mut().zip(g) {
        for (x, gj) in row.iter_mut().zip(g) {
            *x += d2 * gi * gj;
        }
    }
    pull_back_hessian(&MAP, &h)
}
