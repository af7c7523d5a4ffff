//! The distance between two segments, with the closest features of each.

use super::point_edge::{segment, PointEdgeType};
use super::PARALLEL_SIN2;
use crate::math::DVec3;

/// Which features of the segments `ea0 ea1` and `eb0 eb1` are closest (the IPC toolkit's
/// `EdgeEdgeDistanceType`, same order): an endpoint or the interior of each.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[repr(u8)]
pub enum EdgeEdgeType {
    /// `ea0` and `eb0` (ipctk's `EA0_EB0`).
    Ea0Eb0 = 0,
    /// `ea0` and `eb1` (`EA0_EB1`).
    Ea0Eb1 = 1,
    /// `ea1` and `eb0` (`EA1_EB0`).
    Ea1Eb0 = 2,
    /// `ea1` and `eb1` (`EA1_EB1`).
    Ea1Eb1 = 3,
    /// The interior of edge a and `eb0` (`EA_EB0`).
    EaEb0 = 4,
    /// The interior of edge a and `eb1` (`EA_EB1`).
    EaEb1 = 5,
    /// `ea0` and the interior of edge b (`EA0_EB`).
    Ea0Eb = 6,
    /// `ea1` and the interior of edge b (`EA1_EB`).
    Ea1Eb = 7,
    /// The interiors of both edges (`EA_EB`).
    EaEb = 8,
}

impl EdgeEdgeType {
    /// The type of the same pair with the edges swapped (a becomes b).
    ///
    /// ```
    /// use topoccd::distance::EdgeEdgeType;
    /// assert_eq!(EdgeEdgeType::Ea0Eb1.swapped(), EdgeEdgeType::Ea1Eb0);
    /// assert_eq!(EdgeEdgeType::EaEb0.swapped(), EdgeEdgeType::Ea0Eb);
    /// ```
    pub fn swapped(self) -> Self {
        use EdgeEdgeType::*;
        match self {
            Ea0Eb0 => Ea0Eb0,
            Ea0Eb1 => Ea1Eb0,
            Ea1Eb0 => Ea0Eb1,
            Ea1Eb1 => Ea1Eb1,
            EaEb0 => Ea0Eb,
            EaEb1 => Ea1Eb,
            Ea0Eb => EaEb0,
            Ea1Eb => EaEb1,
            EaEb => EaEb,
        }
    }
}

/// The squared distance between the segments `ea0 ea1` and `eb0 eb1` and their closest
/// features, computed relative to `ea0`. Segments not nearly parallel (squared sine of their
/// angle at least 1e-2) solve the normal equations, clamped; the others take the minimum over
/// the four endpoint-segment sub-cases and, for segments not parallel (squared sine of their angle at least
/// 1e-20), the interior-interior sub-case, taken as the distance from the point of
/// edge a at the lines' closest parameter (when strictly inside) to segment b. On a tie the
/// endpoint sub-cases win, in the order of the type.
///
/// ```
/// use topoccd::distance::{edge_edge_distance, EdgeEdgeType};
/// use topoccd::math::DVec3;
/// let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
/// // Crossing at right angles, 1 apart.
/// let (d, ty) = edge_edge_distance(p(-1.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, -1.0, 1.0), p(0.0, 1.0, 1.0));
/// assert_eq!((d, ty), (1.0, EdgeEdgeType::EaEb));
/// // Parallel, overlapping: an endpoint against the other's interior.
/// let (d, ty) = edge_edge_distance(p(0.0, 0.0, 0.0), p(2.0, 0.0, 0.0), p(1.0, 3.0, 0.0), p(4.0, 3.0, 0.0));
/// assert_eq!((d, ty), (9.0, EdgeEdgeType::Ea1Eb));
/// ```
pub fn edge_edge_distance(ea0: DVec3, ea1: DVec3, eb0: DVec3, eb1: DVec3) -> (f64, EdgeEdgeType) {
    let u = ea1 - ea0;
    let (b0, b1) = (eb0 - ea0, eb1 - ea0);
    let v = b1 - b0;
    let (a, b, c) = (u.dot(u), u.dot(v), v.dot(v));
    let det = a * c - b * b;
    // Well-conditioned (not nearly parallel) segments: the distance is strictly convex in the
    // two parameters, and the clamped solution of the normal equations is its minimiser
    // (Ericson, Real-Time Collision Detection, 5.1.9); its points lie on the segments.
    if a > 0.0 && c > 0.0 && det >= WELL_CONDITIONED * a * c {
        let (d, e) = (-u.dot(b0), -v.dot(b0)); // u.w, v.w with w = ea0 - eb0
        let mut s = ((b * e - c * d) / det).clamp(0.0, 1.0);
        let mut t = (b * s + e) / c;
        if t <= 0.0 {
            t = 0.0;
            s = (-d / a).clamp(0.0, 1.0);
        } else if t >= 1.0 {
            t = 1.0;
            s = ((b - d) / a).clamp(0.0, 1.0);
        }
        let gap = u * s - b0 - v * t;
        return (gap.length_squared(), type_of(s, t));
    }
    robust(u, b0, b1, v, (a, b, c, det))
}

/// The squared sine of the angle between the edges from which [`edge_edge_distance`] solves
/// the normal equations directly; below, the minimum over the sub-cases.
pub(crate) const WELL_CONDITIONED: f64 = 1e-2;

/// The type of the closest points at parameters `s` (edge a) and `t` (edge b), each exactly
/// 0 or 1 at an endpoint.
#[inline]
fn type_of(s: f64, t: f64) -> EdgeEdgeType {
    use EdgeEdgeType::*;
    let end = |p: f64| {
        if p == 0.0 {
            0
        } else if p == 1.0 {
            1
        } else {
            2
        }
    };
    match (end(s), end(t)) {
        (0, 0) => Ea0Eb0,
        (0, 1) => Ea0Eb1,
        (1, 0) => Ea1Eb0,
        (1, 1) => Ea1Eb1,
        (2, 0) => EaEb0,
        (2, 1) => EaEb1,
        (0, _) => Ea0Eb,
        (1, _) => Ea1Eb,
        _ => EaEb,
    }
}

/// The minimum over the sub-cases, for nearly parallel or degenerate edges (see
/// [`edge_edge_distance`]); `u` is edge a, `b0`, `b1` edge b's ends relative to `ea0`, `v`
/// edge b, and `(a, b, c, det)` the normal equations' terms.
#[inline(never)]
fn robust(
    u: DVec3,
    b0: DVec3,
    b1: DVec3,
    v: DVec3,
    (a, b, c, det): (f64, f64, f64, f64),
) -> (f64, EdgeEdgeType) {
    use EdgeEdgeType::*;
    let mut best = (f64::INFINITY, Ea0Eb0);
    let mut take = |d: f64, ty: EdgeEdgeType| {
        if d < best.0 {
            best = (d, ty);
        }
    };
    // Endpoints of a against segment b, then endpoints of b against segment a.
    let pick = |k: PointEdgeType, e0: EdgeEdgeType, e1: EdgeEdgeType, inner: EdgeEdgeType| match k {
        PointEdgeType::E0 => e0,
        PointEdgeType::E1 => e1,
        PointEdgeType::Interior => inner,
    };
    let (d, k) = segment(-b0, v);
    take(d, pick(k, Ea0Eb0, Ea0Eb1, Ea0Eb));
    let (d, k) = segment(u - b0, v);
    take(d, pick(k, Ea1Eb0, Ea1Eb1, Ea1Eb));
    let (d, k) = segment(b0, u);
    take(d, pick(k, Ea0Eb0, Ea1Eb0, EaEb0));
    let (d, k) = segment(b1, u);
    take(d, pick(k, Ea0Eb1, Ea1Eb1, EaEb1));
    // The interiors: the closest parameter on a of the two lines, then that point against b.
    if det > PARALLEL_SIN2 * a * c {
        let w = -b0; // ea0 - eb0
        let (d_, e) = (u.dot(w), v.dot(w));
        let s = (b * e - c * d_) / det;
        if s > 0.0 && s < 1.0 {
            let (d, k) = segment(u * s - b0, v);
            if k == PointEdgeType::Interior {
                take(d, EaEb);
            } else {
                take(d, if k == PointEdgeType::E0 { EaEb0 } else { EaEb1 });
            }
        }
    }
    best
}
