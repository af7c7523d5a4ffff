//! The squared distance of a given closest-feature type and its derivatives with respect to
//! all the points of the pair, as the IPC toolkit maps each type to a sub-distance:
//!
//! | pair | type | sub-distance |
//! |---|---|---|
//! | point-edge | `E0`, `E1` | point-point `p e0`, `p e1` |
//! | | `Interior` | point-line `p (e0 e1)` |
//! | point-triangle | `T0`, `T1`, `T2` | point-point `p tk` |
//! | | `E0`, `E1`, `E2` | point-line `p (t0 t1)`, `p (t1 t2)`, `p (t2 t0)` |
//! | | `Interior` | point-plane `p (t0 t1 t2)` |
//! | edge-edge | `EaiEbj` | point-point `eai ebj` |
//! | | `EaEb0`, `EaEb1` | point-line `eb0 (ea0 ea1)`, `eb1 (ea0 ea1)` |
//! | | `Ea0Eb`, `Ea1Eb` | point-line `ea0 (eb0 eb1)`, `ea1 (eb0 eb1)` |
//! | | `EaEb` | line-line `(ea0 ea1) (eb0 eb1)` |
//!
//! The entries of the points a type does not involve are 0. The type is taken as given (from
//! [`point_edge_distance`](super::point_edge_distance) and the others, or from a collision
//! set): at a type boundary the sub-distances of both sides agree in value, and their
//! derivatives agree to first order.

use super::line_line::{
    line_line_distance, line_line_distance_gradient, line_line_distance_hessian,
};
use super::linear_map::{scatter_gradient, scatter_hessian};
use super::point_line::{
    point_line_distance, point_line_distance_gradient, point_line_distance_hessian,
};
use super::point_plane::{
    point_plane_distance, point_plane_distance_gradient, point_plane_distance_hessian,
};
use super::point_point::{
    point_point_distance, point_point_distance_gradient, point_point_distance_hessian,
};
use super::{EdgeEdgeType, PointEdgeType, PointTriangleType};
use crate::math::DVec3;

/// A type's sub-distance: its kind and the indices of its points among the pair's.
#[derive(Clone, Copy)]
enum Sub {
    /// Point-point.
    Pp([usize; 2]),
    /// Point-line: the point, then the line's two points.
    Pl([usize; 3]),
    /// The pair's interior formula (point-line, point-plane or line-line), over all its
    /// points.
    Interior,
}

#[inline]
fn point_edge_sub(ty: PointEdgeType) -> Sub {
    match ty {
        PointEdgeType::E0 => Sub::Pp([0, 1]),
        PointEdgeType::E1 => Sub::Pp([0, 2]),
        PointEdgeType::Interior => Sub::Pl([0, 1, 2]),
    }
}

#[inline]
fn point_triangle_sub(ty: PointTriangleType) -> Sub {
    use PointTriangleType::*;
    match ty {
        T0 => Sub::Pp([0, 1]),
        T1 => Sub::Pp([0, 2]),
        T2 => Sub::Pp([0, 3]),
        E0 => Sub::Pl([0, 1, 2]),
        E1 => Sub::Pl([0, 2, 3]),
        E2 => Sub::Pl([0, 3, 1]),
        Interior => Sub::Interior,
    }
}

#[inline]
fn edge_edge_sub(ty: EdgeEdgeType) -> Sub {
    use EdgeEdgeType::*;
    match ty {
        Ea0Eb0 => Sub::Pp([0, 2]),
        Ea0Eb1 => Sub::Pp([0, 3]),
        Ea1Eb0 => Sub::Pp([1, 2]),
        Ea1Eb1 => Sub::Pp([1, 3]),
        EaEb0 => Sub::Pl([2, 0, 1]),
        EaEb1 => Sub::Pl([3, 0, 1]),
        Ea0Eb => Sub::Pl([0, 2, 3]),
        Ea1Eb => Sub::Pl([1, 2, 3]),
        EaEb => Sub::Interior,
    }
}

/// The value of a sub-distance of the points `x`; `four` is the interior formula.
#[inline(always)]
fn value<const P: usize>(x: &[DVec3; P], sub: Sub, four: impl Fn(&[DVec3; P]) -> f64) -> f64 {
    match sub {
        Sub::Pp([a, b]) => point_point_distance(x[a], x[b]),
        Sub::Pl([a, b, c]) => point_line_distance(x[a], x[b], x[c]),
        Sub::Interior => four(x),
    }
}

#[inline(always)]
fn gradient<const P: usize, const N: usize>(
    x: &[DVec3; P],
    sub: Sub,
    four: impl Fn(&[DVec3; P]) -> [f64; N],
) -> [f64; N] {
    match sub {
        Sub::Pp(i) => scatter_gradient(&point_point_distance_gradient(x[i[0]], x[i[1]]), &i),
        Sub::Pl(i) => {
            scatter_gradient(&point_line_distance_gradient(x[i[0]], x[i[1]], x[i[2]]), &i)
        }
        Sub::Interior => four(x),
    }
}

#[inline(always)]
fn hessian<const P: usize, const N: usize>(
    x: &[DVec3; P],
    sub: Sub,
    four: impl Fn(&[DVec3; P]) -> [[f64; N]; N],
) -> [[f64; N]; N] {
    match sub {
        Sub::Pp(i) => scatter_hessian(&point_point_distance_hessian(x[i[0]], x[i[1]]), &i),
        Sub::Pl(i) => scatter_hessian(&point_line_distance_hessian(x[i[0]], x[i[1]], x[i[2]]), &i),
        Sub::Interior => four(x),
    }
}

/// The squared distance from `p` to the feature `ty` of the segment `e0 e1`: to `e0`, to
/// `e1`, or to the segment's line (ipctk's `point_edge_distance` with a type).
///
/// ```
/// use topoccd::distance::{point_edge_distance_of_type, PointEdgeType};
/// use topoccd::math::DVec3;
/// let (p, e0, e1) = (DVec3::new(2.0, 1.0, 0.0), DVec3::ZERO, DVec3::X);
/// assert_eq!(point_edge_distance_of_type(p, e0, e1, PointEdgeType::E1), 2.0);
/// assert_eq!(point_edge_distance_of_type(p, e0, e1, PointEdgeType::Interior), 1.0);
/// ```
#[inline]
pub fn point_edge_distance_of_type(p: DVec3, e0: DVec3, e1: DVec3, ty: PointEdgeType) -> f64 {
    value(&[p, e0, e1], point_edge_sub(ty), |x| {
        point_line_distance(x[0], x[1], x[2])
    })
}

/// The gradient of [`point_edge_distance_of_type`] with respect to `p`, `e0`, `e1`.
///
/// ```
/// use topoccd::distance::{point_edge_distance_gradient, PointEdgeType};
/// use topoccd::math::DVec3;
/// let g = point_edge_distance_gradient(DVec3::new(2.0, 1.0, 0.0), DVec3::ZERO, DVec3::X, PointEdgeType::E1);
/// assert_eq!(g, [2.0, 2.0, 0.0, 0.0, 0.0, 0.0, -2.0, -2.0, 0.0]);
/// ```
#[inline]
pub fn point_edge_distance_gradient(p: DVec3, e0: DVec3, e1: DVec3, ty: PointEdgeType) -> [f64; 9] {
    gradient(&[p, e0, e1], point_edge_sub(ty), |x| {
        point_line_distance_gradient(x[0], x[1], x[2])
    })
}

/// The Hessian of [`point_edge_distance_of_type`] with respect to `p`, `e0`, `e1`.
///
/// ```
/// use topoccd::distance::{point_edge_distance_hessian, PointEdgeType};
/// use topoccd::math::DVec3;
/// let h = point_edge_distance_hessian(DVec3::new(2.0, 1.0, 0.0), DVec3::ZERO, DVec3::X, PointEdgeType::E0);
/// assert_eq!((h[0][0], h[0][3], h[6][6]), (2.0, -2.0, 0.0));
/// ```
#[inline]
pub fn point_edge_distance_hessian(
    p: DVec3,
    e0: DVec3,
    e1: DVec3,
    ty: PointEdgeType,
) -> [[f64; 9]; 9] {
    hessian(&[p, e0, e1], point_edge_sub(ty), |x| {
        point_line_distance_hessian(x[0], x[1], x[2])
    })
}

/// The squared distance from `p` to the feature `ty` of the triangle `t0 t1 t2`: a corner,
/// an edge's line or the plane (ipctk's `point_triangle_distance` with a type).
///
/// ```
/// use topoccd::distance::{point_triangle_distance_of_type, PointTriangleType};
/// use topoccd::math::DVec3;
/// let t = [DVec3::ZERO, DVec3::X, DVec3::Y];
/// let d = |ty| point_triangle_distance_of_type(DVec3::new(0.5, -1.0, 2.0), t[0], t[1], t[2], ty);
/// assert_eq!(d(PointTriangleType::E0), 5.0);
/// assert_eq!(d(PointTriangleType::Interior), 4.0);
/// ```
#[inline]
pub fn point_triangle_distance_of_type(
    p: DVec3,
    t0: DVec3,
    t1: DVec3,
    t2: DVec3,
    ty: PointTriangleType,
) -> f64 {
    value(&[p, t0, t1, t2], point_triangle_sub(ty), |x| {
        point_plane_distance(x[0], x[1], x[2], x[3])
    })
}

/// The gradient of [`point_triangle_distance_of_type`] with respect to `p`, `t0`, `t1`,
/// `t2`.
///
/// ```
/// use topoccd::distance::{point_triangle_distance_gradient, PointTriangleType};
/// use topoccd::math::DVec3;
/// let g = point_triangle_distance_gradient(
///     DVec3::new(0.25, 0.25, 2.0), DVec3::ZERO, DVec3::X, DVec3::Y, PointTriangleType::Interior);
/// assert_eq!(&g[..3], &[0.0, 0.0, 4.0]); // 2 d n
/// ```
#[inline]
pub fn point_triangle_distance_gradient(
    p: DVec3,
    t0: DVec3,
    t1: DVec3,
    t2: DVec3,
    ty: PointTriangleType,
) -> [f64; 12] {
    gradient(&[p, t0, t1, t2], point_triangle_sub(ty), |x| {
        point_plane_distance_gradient(x[0], x[1], x[2], x[3])
    })
}

/// The Hessian of [`point_triangle_distance_of_type`] with respect to `p`, `t0`, `t1`,
/// `t2`.
///
/// ```
/// use topoccd::distance::{point_triangle_distance_hessian, PointTriangleType};
/// use topoccd::math::DVec3;
/// let h = point_triangle_distance_hessian(
///     DVec3::new(0.25, 0.25, 2.0), DVec3::ZERO, DVec3::X, DVec3::Y, PointTriangleType::T2);
/// assert_eq!((h[0][0], h[0][9], h[3][3]), (2.0, -2.0, 0.0));
/// ```
#[inline]
pub fn point_triangle_distance_hessian(
    p: DVec3,
    t0: DVec3,
    t1: DVec3,
    t2: DVec3,
    ty: PointTriangleType,
) -> [[f64; 12]; 12] {
    hessian(&[p, t0, t1, t2], point_triangle_sub(ty), |x| {
        point_plane_distance_hessian(x[0], x[1], x[2], x[3])
    })
}

/// The squared distance between the features `ty` of the segments `ea0 ea1` and `eb0 eb1`:
/// two endpoints, an endpoint and the other edge's line, or the two lines (ipctk's
/// `edge_edge_distance` with a type).
///
/// ```
/// use topoccd::distance::{edge_edge_distance_of_type, EdgeEdgeType};
/// use topoccd::math::DVec3;
/// let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
/// let e = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(3.0, -1.0, 1.0), p(3.0, 1.0, 1.0)];
/// assert_eq!(edge_edge_distance_of_type(e[0], e[1], e[2], e[3], EdgeEdgeType::Ea1Eb), 5.0);
/// assert_eq!(edge_edge_distance_of_type(e[0], e[1], e[2], e[3], EdgeEdgeType::EaEb), 1.0);
/// ```
#[inline]
pub fn edge_edge_distance_of_type(
    ea0: DVec3,
    ea1: DVec3,
    eb0: DVec3,
    eb1: DVec3,
    ty: EdgeEdgeType,
) -> f64 {
    value(&[ea0, ea1, eb0, eb1], edge_edge_sub(ty), |x| {
        line_line_distance(x[0], x[1], x[2], x[3])
    })
}

/// The gradient of [`edge_edge_distance_of_type`] with respect to `ea0`, `ea1`, `eb0`,
/// `eb1`.
///
/// ```
/// use topoccd::distance::{edge_edge_distance_gradient, EdgeEdgeType};
/// use topoccd::math::DVec3;
/// let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
/// let g = edge_edge_distance_gradient(
///     p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(3.0, 0.0, 1.0), p(3.0, 1.0, 1.0), EdgeEdgeType::Ea1Eb0);
/// assert_eq!(g, [0.0, 0.0, 0.0, -4.0, 0.0, -2.0, 4.0, 0.0, 2.0, 0.0, 0.0, 0.0]);
/// ```
#[inline]
pub fn edge_edge_distance_gradient(
    ea0: DVec3,
    ea1: DVec3,
    eb0: DVec3,
    eb1: DVec3,
    ty: EdgeEdgeType,
) -> [f64; 12] {
    gradient(&[ea0, ea1, eb0, eb1], edge_edge_sub(ty), |x| {
        line_line_distance_gradient(x[0], x[1], x[2], x[3])
    })
}

/// The Hessian of [`edge_edge_distance_of_type`] with respect to `ea0`, `ea1`, `eb0`,
/// `eb1`.
///
/// ```
/// use topoccd::distance::{edge_edge_distance_hessian, EdgeEdgeType};
/// use topoccd::math::DVec3;
/// let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
/// let h = edge_edge_distance_hessian(
///     p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(3.0, 0.0, 1.0), p(3.0, 1.0, 1.0), EdgeEdgeType::Ea1Eb0);
/// assert_eq!((h[3][3], h[3][6], h[0][0]), (2.0, -2.0, 0.0));
/// ```
#[inline]
pub fn edge_edge_distance_hessian(
    ea0: DVec3,
    ea1: DVec3,
    eb0: DVec3,
    eb1: DVec3,
    ty: EdgeEdgeType,
) -> [[f64; 12]; 12] {
    hessian(&[ea0, ea1, eb0, eb1], edge_edge_sub(ty), |x| {
        line_line_distance_hessian(x[0], x[1], x[2], x[3])
    })
}
