//! Exact intersection tests of closed triangles and segments, from the orientation predicates
//! of the `robust` crate (Shewchuk's adaptive exact arithmetic): every sign below is the sign
//! of the exact determinant of the `f64` inputs, so touching, coplanar and degenerate
//! configurations are decided without tolerance.
//!
//! Two closed triangles meet exactly when an edge of one meets the other: the points of their
//! intersection that lie farthest along any direction are on the boundary of one of them (the
//! intersection is a segment on the line of the two planes, or a convex polygon in their
//! common plane). So a triangle pair is six segment-triangle tests at most.

use robust::{orient2d, orient3d, Coord, Coord3D};

use crate::range::normalizing_scale;

/// A point.
pub type P = [f64; 3];

fn o3(a: P, b: P, c: P, d: P) -> f64 {
    let c3 = |p: P| Coord3D {
        x: p[0],
        y: p[1],
        z: p[2],
    };
    orient3d(c3(a), c3(b), c3(c), c3(d))
}

/// The 2-d orientation of `a, b, c` projected along `axis` (that coordinate dropped).
fn o2(axis: usize, a: P, b: P, c: P) -> f64 {
    let (i, j) = match axis {
        0 => (1, 2),
        1 => (2, 0),
        _ => (0, 1),
    };
    let c2 = |p: P| Coord { x: p[i], y: p[j] };
    orient2d(c2(a), c2(b), c2(c))
}

/// An axis along which `a, b, c` project to a proper triangle (the normal of their plane has
/// a component along it), or `None` when the three points are collinear.
fn projection_axis(a: P, b: P, c: P) -> Option<usize> {
    (0..3).find(|&axis| o2(axis, a, b, c) != 0.0)
}

/// Whether `p` lies in the closed box of `a` and `b` along every coordinate (for points known
/// to be collinear with `a` and `b`: then it is on the closed segment).
fn within(a: P, b: P, p: P) -> bool {
    (0..3).all(|k| a[k].min(b[k]) <= p[k] && p[k] <= a[k].max(b[k]))
}

fn sign(x: f64) -> i8 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

/// Closed segments `pq` and `ab`, all four points in one plane that projects injectively along
/// `axis`.
fn segments_2d(axis: usize, p: P, q: P, a: P, b: P) -> bool {
    let d1 = sign(o2(axis, p, q, a));
    let d2 = sign(o2(axis, p, q, b));
    let d3 = sign(o2(axis, a, b, p));
    let d4 = sign(o2(axis, a, b, q));
    if d1 * d2 < 0 && d3 * d4 < 0 {
        return true;
    }
    (d1 == 0 && within(p, q, a))
        || (d2 == 0 && within(p, q, b))
        || (d3 == 0 && within(a, b, p))
        || (d4 == 0 && within(a, b, q))
}

/// Closed segments `pq` and `ab` in space.
pub fn segments(p: P, q: P, a: P, b: P) -> bool {
    if o3(p, q, a, b) != 0.0 {
        return false; // not coplanar (both segments are proper, and skew)
    }
    // Coplanar: project along an axis that is injective on a plane holding all four points.
    let plane = [(p, q, a), (p, q, b), (a, b, p), (a, b, q)]
        .into_iter()
        .find_map(|(x, y, z)| projection_axis(x, y, z));
    match plane {
        Some(axis) => segments_2d(axis, p, q, a, b),
        None => {
            // All four on one line (or one point): compare along a coordinate that varies,
            // which orders the line's points as the line does.
            match (0..3).find(|&k| [q, a, b].iter().any(|x| x[k] != p[k])) {
                None => true, // four copies of one point
                Some(k) => {
                    let (s0, s1) = (p[k].min(q[k]), p[k].max(q[k]));
                    let (t0, t1) = (a[k].min(b[k]), a[k].max(b[k]));
                    s0 <= t1 && t0 <= s1
                }
            }
        }
    }
}

/// The closed segment `pq` and the closed triangle `abc` (which may be degenerate).
pub fn segment_triangle(p: P, q: P, [a, b, c]: [P; 3]) -> bool {
    let Some(axis) = projection_axis(a, b, c) else {
        // A degenerate triangle is the union of its edges.
        return segments(p, q, a, b) || segments(p, q, b, c) || segments(p, q, c, a);
    };
    let sp = sign(o3(a, b, c, p));
    let sq = sign(o3(a, b, c, q));
    if sp * sq > 0 {
        return false; // both ends strictly on one side of the plane
    }
    if sp == 0 && sq == 0 {
        // In the triangle's plane: an end inside the triangle, or a crossing of an edge.
        let inside = |x: P| {
            let s = [
                sign(o2(axis, a, b, x)),
                sign(o2(axis, b, c, x)),
                sign(o2(axis, c, a, x)),
            ];
            s.iter().all(|&v| v >= 0) || s.iter().all(|&v| v <= 0)
        };
        return inside(p)
            || inside(q)
            || segments_2d(axis, p, q, a, b)
            || segments_2d(axis, p, q, b, c)
            || segments_2d(axis, p, q, c, a);
    }
    // The segment meets the plane in one point; it is in the closed triangle when the line
    // pq passes the three edges' lines on one side (or on them).
    let s = [
        sign(o3(p, q, a, b)),
        sign(o3(p, q, b, c)),
        sign(o3(p, q, c, a)),
    ];
    s.iter().all(|&v| v >= 0) || s.iter().all(|&v| v <= 0)
}

/// The closed triangles `t` and `u` (either may be degenerate). Coordinates far from 1 are
/// first multiplied by a power of two ([`normalizing_scale`] of the largest, as the CCD's
/// solver does): exact, and the signs do not change, but the predicates' products then
/// neither overflow nor underflow at any uniform scale.
pub fn triangles(t: [P; 3], u: [P; 3]) -> bool {
    let largest = t
        .iter()
        .chain(&u)
        .flatten()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let s = normalizing_scale(largest);
    if s == 1.0 {
        triangles_near_one(t, u)
    } else {
        let scaled = |t: [P; 3]| t.map(|p| p.map(|x| x * s));
        triangles_near_one(scaled(t), scaled(u))
    }
}

/// [`triangles`], its coordinates already scaled.
fn triangles_near_one(t: [P; 3], u: [P; 3]) -> bool {
    // Quick rejection: all of one triangle strictly on one side of the other's plane.
    let side = |t: [P; 3], u: [P; 3]| {
        let s = u.map(|x| sign(o3(t[0], t[1], t[2], x)));
        (s[0] > 0 && s[1] > 0 && s[2] > 0) || (s[0] < 0 && s[1] < 0 && s[2] < 0)
    };
    if side(t, u) || side(u, t) {
        return false;
    }
    let edges = |t: [P; 3]| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])];
    edges(t).into_iter().any(|(p, q)| segment_triangle(p, q, u))
        || edges(u).into_iter().any(|(p, q)| segment_triangle(p, q, t))
}
