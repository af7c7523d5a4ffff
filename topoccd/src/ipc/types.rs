//! The closest-feature classification the collision set uses, with the IPC toolkit 1.6.1's
//! rules (projections and their tie-breaking), so that the set is ipctk's pair for pair; and
//! the squared distance of a given type (point-point, point-line, point-plane, line-line).
//!
//! The proximity query's own types ([`crate::distance`]) agree with these except on the
//! boundaries between regions, where either choice gives the same distance up to rounding.

// Index loops over small fixed-size arrays read as the formulas do.
#![allow(clippy::needless_range_loop)]

use crate::distance::{EdgeEdgeType, PointEdgeType, PointTriangleType};
use crate::math::DVec3;

/// The closest feature of segment `e0 e1` to `p`: the interior when the projection's
/// parameter is in `[0, 1]`; a degenerate segment is its endpoint `e0`.
#[inline]
pub(crate) fn point_edge_type(p: DVec3, e0: DVec3, e1: DVec3) -> PointEdgeType {
    let e = e1 - e0;
    let ee = e.length_squared();
    if ee == 0.0 {
        return PointEdgeType::E0;
    }
    let ratio = e.dot(p - e0) / ee;
    if ratio < 0.0 {
        PointEdgeType::E0
    } else if ratio > 1.0 {
        PointEdgeType::E1
    } else {
        PointEdgeType::Interior
    }
}

/// The 2x2 solve of `(B B^T) x = B (p - o)` with `B`'s rows `r0`, `r1` (a symmetric
/// positive system, solved by its LDL^T factors).
#[inline]
fn param(r0: DVec3, r1: DVec3, w: DVec3) -> (f64, f64) {
    let (a, b, c) = (r0.dot(r0), r0.dot(r1), r1.dot(r1));
    let (y0, y1) = (r0.dot(w), r1.dot(w));
    // LDL^T with pivoting as a 2x2 symmetric solve: a robust closed form.
    if a >= c {
        let l = if a != 0.0 { b / a } else { 0.0 };
        let d1 = c - l * b;
        let z1 = y1 - l * y0;
        let x1 = if d1 != 0.0 { z1 / d1 } else { 0.0 };
        let x0 = if a != 0.0 { (y0 - b * x1) / a } else { 0.0 };
        (x0, x1)
    } else {
        let l = b / c;
        let d0 = a - l * b;
        let z0 = y0 - l * y1;
        let x0 = if d0 != 0.0 { z0 / d0 } else { 0.0 };
        let x1 = (y1 - b * x0) / c;
        (x0, x1)
    }
}

/// The closest feature of triangle `t0 t1 t2` to `p`: for each edge `k` the parameter of
/// the projection along it and the side of the edge's outward direction; an edge when the
/// point projects inside its span on its outer side, else a vertex when both adjacent edges
/// put it beyond that vertex, else the interior.
#[inline]
pub(crate) fn point_triangle_type(p: DVec3, t0: DVec3, t1: DVec3, t2: DVec3) -> PointTriangleType {
    let n = (t1 - t0).cross(t2 - t0);
    let t = [t0, t1, t2];
    let mut s = [0.0; 3];
    for k in 0..3 {
        let r0 = t[(k + 1) % 3] - t[k];
        let r1 = r0.cross(n);
        let (u, v) = param(r0, r1, p - t[k]);
        if u > 0.0 && u < 1.0 && v >= 0.0 {
            return [
                PointTriangleType::E0,
                PointTriangleType::E1,
                PointTriangleType::E2,
            ][k];
        }
        s[k] = u;
    }
    if s[0] <= 0.0 && s[2] >= 1.0 {
        PointTriangleType::T0
    } else if s[1] <= 0.0 && s[0] >= 1.0 {
        PointTriangleType::T1
    } else if s[2] <= 0.0 && s[1] >= 1.0 {
        PointTriangleType::T2
    } else {
        PointTriangleType::Interior
    }
}

/// Edges whose squared sine of their angle is below this are parallel for
/// [`edge_edge_type`] (ipctk 1.6.1's relative threshold).
const PARALLEL_THRESHOLD: f64 = 2.5e-16;

/// The closest features of segments `ea0 ea1` and `eb0 eb1`: the clamped parameters of
/// the lines' closest points, with the parallel case apart.
pub(crate) fn edge_edge_type(ea0: DVec3, ea1: DVec3, eb0: DVec3, eb1: DVec3) -> EdgeEdgeType {
    use EdgeEdgeType::*;
    let (u, v, w) = (ea1 - ea0, eb1 - eb0, ea0 - eb0);
    let (a, b, c, d, e) = (u.dot(u), u.dot(v), v.dot(v), u.dot(w), v.dot(w));
    let det = a * c - b * b;
    if a == 0.0 && c == 0.0 {
        return Ea0Eb0;
    } else if a == 0.0 {
        return Ea0Eb;
    } else if c == 0.0 {
        return EaEb0;
    }
    let tol = PARALLEL_THRESHOLD * a * c;
    let cross2 = u.cross(v).length_squared();
    if cross2 < tol {
        return parallel_type(ea0, ea1, eb0, eb1);
    }
    let mut default = EaEb;
    let sn = b * e - c * d;
    let (mut tn, mut td);
    if sn <= 0.0 {
        (tn, td) = (e, c);
        default = Ea0Eb;
    } else if sn >= det {
        (tn, td) = (e + b, c);
        default = Ea1Eb;
    } else {
        (tn, td) = (a * e - b * d, det);
        if tn > 0.0 && tn < td && cross2 < tol {
            if sn < det / 2.0 {
                (tn, td) = (e, c);
                default = Ea0Eb;
            } else {
                (tn, td) = (e + b, c);
                default = Ea1Eb;
            }
        }
    }
    if tn <= 0.0 {
        if -d <= 0.0 {
            Ea0Eb0
        } else if -d >= a {
            Ea1Eb0
        } else {
            EaEb0
        }
    } else if tn >= td {
        if -d + b <= 0.0 {
            Ea0Eb1
        } else if -d + b >= a {
            Ea1Eb1
        } else {
            EaEb1
        }
    } else {
        default
    }
}

/// The closest features of parallel segments: by the parameters of `eb0` and `eb1` along
/// edge a.
fn parallel_type(ea0: DVec3, ea1: DVec3, eb0: DVec3, eb1: DVec3) -> EdgeEdgeType {
    use EdgeEdgeType::*;
    let ea = ea1 - ea0;
    let aa = ea.length_squared();
    let alpha = (eb0 - ea0).dot(ea) / aa;
    let beta = (eb1 - ea0).dot(ea) / aa;
    // 0, 1: an endpoint; 2: the interior.
    let (ac, bc) = if alpha < 0.0 {
        (
            if (0.0..=1.0).contains(&beta) { 2 } else { 0 },
            if beta <= alpha {
                0
            } else if beta <= 1.0 {
                1
            } else {
                2
            },
        )
    } else if alpha > 1.0 {
        (
            if (0.0..=1.0).contains(&beta) { 2 } else { 1 },
            if beta >= alpha {
                0
            } else if 0.0 <= beta {
                1
            } else {
                2
            },
        )
    } else {
        (2, 0)
    };
    match (ac, bc) {
        (0, 0) => Ea0Eb0,
        (0, 1) => Ea0Eb1,
        (1, 0) => Ea1Eb0,
        (1, 1) => Ea1Eb1,
        (2, 0) => EaEb0,
        (2, 1) => EaEb1,
        (0, 2) => Ea0Eb,
        (1, 2) => Ea1Eb,
        _ => EaEb,
    }
}

/// The squared distance from `p` to the line through `e0 e1`.
#[inline]
pub(crate) fn point_line_sq(p: DVec3, e0: DVec3, e1: DVec3) -> f64 {
    let e = e1 - e0;
    (e0 - p).cross(e1 - p).length_squared() / e.length_squared()
}

/// The squared distance from `p` to the plane of `t0 t1 t2`.
#[inline]
pub(crate) fn point_plane_sq(p: DVec3, t0: DVec3, t1: DVec3, t2: DVec3) -> f64 {
    let n = (t1 - t0).cross(t2 - t0);
    let s = (p - t0).dot(n);
    s * s / n.length_squared()
}

/// The squared distance between the lines through `ea0 ea1` and `eb0 eb1`.
#[inline]
pub(crate) fn line_line_sq(ea0: DVec3, ea1: DVec3, eb0: DVec3, eb1: DVec3) -> f64 {
    let n = (ea1 - ea0).cross(eb1 - eb0);
    let s = (eb0 - ea0).dot(n);
    s * s / n.length_squared()
}

/// The squared distance of the point-edge pair for the type.
#[inline]
pub(crate) fn point_edge_sq(p: DVec3, e0: DVec3, e1: DVec3, ty: PointEdgeType) -> f64 {
    match ty {
        PointEdgeType::E0 => (p - e0).length_squared(),
        PointEdgeType::E1 => (p - e1).length_squared(),
        PointEdgeType::Interior => point_line_sq(p, e0, e1),
    }
}

/// The squared distance of the point-triangle pair for the type.
#[inline]
pub(crate) fn point_triangle_sq(
    p: DVec3,
    t0: DVec3,
    t1: DVec3,
    t2: DVec3,
    ty: PointTriangleType,
) -> f64 {
    use PointTriangleType::*;
    match ty {
        T0 => (p - t0).length_squared(),
        T1 => (p - t1).length_squared(),
        T2 => (p - t2).length_squared(),
        E0 => point_line_sq(p, t0, t1),
        E1 => point_line_sq(p, t1, t2),
        E2 => point_line_sq(p, t2, t0),
        Interior => point_plane_sq(p, t0, t1, t2),
    }
}

/// The squared distance of the edge-edge pair for the type.
#[inline]
pub(crate) fn edge_edge_sq(
    ea0: DVec3,
    ea1: DVec3,
    eb0: DVec3,
    eb1: DVec3,
    ty: EdgeEdgeType,
) -> f64 {
    use EdgeEdgeType::*;
    match ty {
        Ea0Eb0 => (ea0 - eb0).length_squared(),
        Ea0Eb1 => (ea0 - eb1).length_squared(),
        Ea1Eb0 => (ea1 - eb0).length_squared(),
        Ea1Eb1 => (ea1 - eb1).length_squared(),
        EaEb0 => point_line_sq(eb0, ea0, ea1),
        EaEb1 => point_line_sq(eb1, ea0, ea1),
        Ea0Eb => point_line_sq(ea0, eb0, eb1),
        Ea1Eb => point_line_sq(ea1, eb0, eb1),
        EaEb => line_line_sq(ea0, ea1, eb0, eb1),
    }
}

/// The mollifier threshold of two edges at rest: `1e-3 |ea|^2 |eb|^2`.
#[inline]
pub(crate) fn mollifier_threshold(ea0: DVec3, ea1: DVec3, eb0: DVec3, eb1: DVec3) -> f64 {
    1e-3 * (ea0 - ea1).length_squared() * (eb0 - eb1).length_squared()
}
