//! Distances between the primitives at one configuration: point-point, point-edge,
//! point-triangle and edge-edge, each with the type of its closest features (the IPC
//! toolkit's `PointEdgeDistanceType`, `PointTriangleDistanceType` and `EdgeEdgeDistanceType`,
//! in the same order).
//!
//! Every function returns the *squared* distance, in `f64`, computed as the minimum over the
//! sub-cases of the pair (vertex-vertex, vertex-segment, interior), each sub-case being the
//! distance between two points that lie on the two features up to rounding. A sub-case that
//! does not apply (an interior case whose parameters fall outside, a degenerate triangle's
//! interior, parallel edges' interior) is skipped, never extrapolated: so the result is never
//! much smaller than the exact distance, and the endpoint sub-cases keep it from being much
//! larger. [`rounding_bound`] gives the bound used by the proximity query.
//!
//! The computations run on coordinates relative to the pair's first point, so the error
//! scales with the pair's own size, not with the coordinates' magnitude.
//!
//! # Derivatives
//!
//! For a contact potential, each closest-feature type has its squared distance, gradient and
//! Hessian in closed form, with respect to all the pair's points (x, y, z of each point in
//! argument order; row-major, symmetric Hessians), as the IPC toolkit defines them:
//! [`point_edge_distance_of_type`], [`point_triangle_distance_of_type`] and
//! [`edge_edge_distance_of_type`] with their `_gradient` and `_hessian`. A type maps to one of
//! the sub-distances [`point_point_distance`], [`point_line_distance`] (to the infinite
//! line), [`point_plane_distance`] and [`line_line_distance`], each with its own derivatives.
//! [`edge_edge_mollifier`] and its derivatives smooth the edge-edge barrier for nearly
//! parallel edges, and [`point_triangle_distance_batch`] and its siblings run a whole batch
//! of pairs into the caller's buffers.
//!
//! Point-plane and line-line share one kernel, `(r . n)^2 / |n|^2` with `n = u x v`, derived
//! once in the three difference vectors `(r, u, v)` and mapped to the points' coordinates by
//! the constant linear map (`g = A^T g_d`, `H = A^T H_d A`), applied block by block. Each
//! file documents its derivation. Where an interior formula is undefined (a zero-length edge,
//! a zero-area triangle, parallel lines) the functions return the distance to what the
//! feature degenerates to, documented per function, never a NaN for finite input.

mod batch;
mod by_type;
mod edge_edge;
mod line_line;
mod linear_map;
mod mollifier;
mod point_edge;
mod point_line;
mod point_plane;
mod point_point;
mod point_triangle;
mod triple;

pub use batch::{
    edge_edge_distance_batch, point_edge_distance_batch, point_point_distance_batch,
    point_triangle_distance_batch, BatchLengthError, BatchOutput,
};
pub use by_type::{
    edge_edge_distance_gradient, edge_edge_distance_hessian, edge_edge_distance_of_type,
    point_edge_distance_gradient, point_edge_distance_hessian, point_edge_distance_of_type,
    point_triangle_distance_gradient, point_triangle_distance_hessian,
    point_triangle_distance_of_type,
};
pub use edge_edge::{edge_edge_distance, EdgeEdgeType};
pub use line_line::{line_line_distance, line_line_distance_gradient, line_line_distance_hessian};
pub use mollifier::{
    edge_edge_cross_squarednorm, edge_edge_cross_squarednorm_gradient,
    edge_edge_cross_squarednorm_hessian, edge_edge_mollifier, edge_edge_mollifier_derivative,
    edge_edge_mollifier_gradient, edge_edge_mollifier_hessian, edge_edge_mollifier_scalar,
    edge_edge_mollifier_second_derivative, edge_edge_mollifier_threshold,
};
pub use point_edge::{point_edge_distance, PointEdgeType};
pub use point_line::{
    point_line_distance, point_line_distance_gradient, point_line_distance_hessian,
};
pub use point_plane::{
    point_plane_distance, point_plane_distance_gradient, point_plane_distance_hessian,
};
pub use point_point::{
    point_point_distance, point_point_distance_gradient, point_point_distance_hessian,
};
pub use point_triangle::{point_triangle_distance, PointTriangleType};

use crate::math::{DVec3, UNIT_ROUNDOFF};

/// Segments whose direction vectors have a squared sine of their angle below this are treated
/// as parallel by the edge-edge distance: only its endpoint sub-cases are used.
pub(crate) const PARALLEL_SIN2: f64 = 1e-20;

/// A bound `eps` on the error of the distances of this module (not squared): for a pair whose
/// points lie within `extent` of the pair's first point (largest absolute coordinate
/// difference), the computed distance `d~` and the exact distance `d` satisfy
/// `|d~ - d| <= eps` with `eps = 64 u extent sqrt(3)` (`u` = 2^-53) for point-point,
/// point-edge and point-triangle pairs, and for edge-edge pairs whose edges are not nearly
/// parallel. For nearly parallel edges (squared sine of the angle `s2` below 1e-2) the bound
/// adds `extent min(sqrt(s2), 16 u / sqrt(s2))` (the distance varies by at most the sine
/// times the length along such edges, and the interior sub-case's error grows as one over
/// the sine), passed as `sin2`; give `sin2 = 1` for the other kinds.
///
/// The derivation: every coordinate difference is one correctly rounded subtraction (relative
/// error `u`); the dot products, the clamped parameters and the final squared norm add a few
/// `u` each, relative to `extent` squared; the interior parameters of a nearly degenerate
/// triangle may be far off, but then the point they give still lies on the triangle (up to
/// rounding) or the sub-case is skipped and an edge sub-case, whose error is bounded as above,
/// takes over. 64 covers these terms with a wide margin.
///
/// ```
/// use topoccd::distance::rounding_bound;
/// let eps = rounding_bound(1.0, 1.0);
/// assert!(eps > 0.0 && eps < 1e-13);
/// assert!(rounding_bound(1.0, 1e-30) > eps); // nearly parallel edges
/// ```
#[inline]
pub fn rounding_bound(extent: f64, sin2: f64) -> f64 {
    let base = 64.0 * UNIT_ROUNDOFF * extent * 3f64.sqrt();
    if sin2 >= 1e-2 {
        return base;
    }
    let s = sin2.max(0.0).sqrt();
    base + extent * s.min(16.0 * UNIT_ROUNDOFF / s.max(f64::MIN_POSITIVE))
}

/// The largest absolute coordinate difference between `points` and `origin`.
#[inline]
pub(crate) fn extent(origin: DVec3, points: &[DVec3]) -> f64 {
    points
        .iter()
        .fold(0.0f64, |m, p| m.max((*p - origin).abs().max_element()))
}

/// The squared sine of the angle between two vectors (0 when either is zero).
#[inline]
pub(crate) fn sin2(u: DVec3, v: DVec3) -> f64 {
    let (a, c) = (u.length_squared(), v.length_squared());
    if a == 0.0 || c == 0.0 {
        return 0.0;
    }
    (u.cross(v).length_squared() / (a * c)).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests;

#[cfg(test)]
mod derivative_tests;
