//! The distance between a point and a triangle, with the closest feature of the triangle.

use super::point_edge::{segment, PointEdgeType};
use crate::math::DVec3;

/// Which feature of the triangle `t0 t1 t2` is closest to the point (the IPC toolkit's
/// `PointTriangleDistanceType`, same order). Edge `Ek` runs from `tk` to `t(k+1 mod 3)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[repr(u8)]
pub enum PointTriangleType {
    /// The vertex `t0` (ipctk's `P_T0`).
    T0 = 0,
    /// The vertex `t1` (`P_T1`).
    T1 = 1,
    /// The vertex `t2` (`P_T2`).
    T2 = 2,
    /// The interior of the edge `t0 t1` (`P_E0`).
    E0 = 3,
    /// The interior of the edge `t1 t2` (`P_E1`).
    E1 = 4,
    /// The interior of the edge `t2 t0` (`P_E2`).
    E2 = 5,
    /// The interior of the triangle (`P_T`).
    Interior = 6,
}

/// The squared distance from `p` to the triangle `t0 t1 t2` and its closest feature,
/// computed relative to `p`: the minimum over the three edges (each with its endpoints) and,
/// when the point's projection falls strictly inside a non-degenerate triangle, the interior.
/// On a tie the lower-dimensional feature wins (a vertex before an edge before the interior).
///
/// ```
/// use topoccd::distance::{point_triangle_distance, PointTriangleType};
/// use topoccd::math::DVec3;
/// let t = [DVec3::ZERO, DVec3::X, DVec3::Y];
/// let d = |p: [f64; 3]| point_triangle_distance(DVec3::from(p), t[0], t[1], t[2]);
/// assert_eq!(d([0.25, 0.25, 2.0]), (4.0, PointTriangleType::Interior));
/// assert_eq!(d([0.5, -1.0, 0.0]), (1.0, PointTriangleType::E0));
/// assert_eq!(d([-1.0, -1.0, 0.0]), (2.0, PointTriangleType::T0));
/// ```
pub fn point_triangle_distance(
    p: DVec3,
    t0: DVec3,
    t1: DVec3,
    t2: DVec3,
) -> (f64, PointTriangleType) {
    // Relative to p: the corners.
    let c = [t0 - p, t1 - p, t2 - p];
    // The common case first: the projection strictly inside a well-shaped triangle is the
    // closest point (the minimum below would pick it too).
    if let Some(d) = interior(c, WELL_SHAPED) {
        return (d, PointTriangleType::Interior);
    }
    let mut best = (f64::INFINITY, PointTriangleType::T0);
    // Vertices first, so that ties go to them.
    for (k, ty) in [
        PointTriangleType::T0,
        PointTriangleType::T1,
        PointTriangleType::T2,
    ]
    .into_iter()
    .enumerate()
    {
        let d = c[k].length_squared();
        if d < best.0 {
            best = (d, ty);
        }
    }
    for (k, ty) in [
        PointTriangleType::E0,
        PointTriangleType::E1,
        PointTriangleType::E2,
    ]
    .into_iter()
    .enumerate()
    {
        let (a, b) = (c[k], c[(k + 1) % 3]);
        // The point (origin) against the segment a b.
        let (d, kind) = segment(-a, b - a);
        if kind == PointEdgeType::Interior && d < best.0 {
            best = (d, ty);
        }
    }
    if let Some(d) = interior(c, 0.0) {
        if d < best.0 {
            best = (d, PointTriangleType::Interior);
        }
    }
    best
}

/// Triangles whose squared sine of the angle at `t0` is at least this take their interior
/// sub-case first.
const WELL_SHAPED: f64 = 1e-2;

/// The squared distance from the origin to its projection on the plane of the triangle with
/// corners `c`, when that projection falls strictly inside; `None` otherwise or for a
/// triangle whose squared sine at its first corner is not above `shape` (0: degenerate). The projection's barycentric coordinates solve the 2x2 normal
/// equations, and the distance is that of the point they give, which lies on the triangle up
/// to rounding.
#[inline]
fn interior(c: [DVec3; 3], shape: f64) -> Option<f64> {
    let (e1, e2) = (c[1] - c[0], c[2] - c[0]);
    let w = -c[0];
    let (a, b, d) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let det = a * d - b * b;
    // (A NaN fails the test too.)
    if det.partial_cmp(&(shape * a * d)) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let (we1, we2) = (w.dot(e1), w.dot(e2));
    let s = (d * we1 - b * we2) / det;
    let t = (a * we2 - b * we1) / det;
    if !(s > 0.0 && t > 0.0 && s + t < 1.0) {
        return None;
    }
    Some((w - e1 * s - e2 * t).length_squared())
}
