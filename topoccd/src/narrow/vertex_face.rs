//! Vertex against triangle.

use super::{solver, NarrowOptions, Outcome};
use crate::math::DVec3;

/// A vertex and a triangle, each point moving linearly from its `_t0` to its `_t1` position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VertexFace {
    /// The vertex at t=0.
    pub v_t0: DVec3,
    /// Triangle corner 0 at t=0.
    pub f0_t0: DVec3,
    /// Triangle corner 1 at t=0.
    pub f1_t0: DVec3,
    /// Triangle corner 2 at t=0.
    pub f2_t0: DVec3,
    /// The vertex at t=1.
    pub v_t1: DVec3,
    /// Triangle corner 0 at t=1.
    pub f0_t1: DVec3,
    /// Triangle corner 1 at t=1.
    pub f1_t1: DVec3,
    /// Triangle corner 2 at t=1.
    pub f2_t1: DVec3,
}

impl VertexFace {
    /// The eight points in the order of the query files: `v, f0, f1, f2` at t=0, then at t=1.
    pub fn from_points(p: [DVec3; 8]) -> Self {
        Self {
            v_t0: p[0],
            f0_t0: p[1],
            f1_t0: p[2],
            f2_t0: p[3],
            v_t1: p[4],
            f0_t1: p[5],
            f1_t1: p[6],
            f2_t1: p[7],
        }
    }

    /// The eight points, in the order of [`VertexFace::from_points`].
    pub fn points(&self) -> [DVec3; 8] {
        [
            self.v_t0, self.f0_t0, self.f1_t0, self.f2_t0, self.v_t1, self.f0_t1, self.f1_t1,
            self.f2_t1,
        ]
    }
}

/// Continuous collision test of a vertex against a triangle (the triangle's interior, edges and
/// corners included) over `[0, options.tmax]`.
///
/// ```
/// use topoccd::math::DVec3;
/// use topoccd::narrow::{vertex_face, NarrowOptions, VertexFace};
/// // A vertex falls from z=1 to z=-1 through the triangle in the plane z=0: contact at t=0.5.
/// let q = VertexFace {
///     v_t0: DVec3::new(0.2, 0.2, 1.0),
///     f0_t0: DVec3::ZERO, f1_t0: DVec3::X, f2_t0: DVec3::Y,
///     v_t1: DVec3::new(0.2, 0.2, -1.0),
///     f0_t1: DVec3::ZERO, f1_t1: DVec3::X, f2_t1: DVec3::Y,
/// };
/// let toi = vertex_face(&q, &NarrowOptions::default()).toi().unwrap();
/// assert!(toi <= 0.5 && toi > 0.5 - 1e-6);
/// ```
pub fn vertex_face(query: &VertexFace, options: &NarrowOptions) -> Outcome {
    solver::solve(&solver::Problem::vertex_face(query), options)
}

/// [`vertex_face`] for a pair proved apart by more than `min_distance` during
/// `[0, t_start]`: searched over `[t_start, tmax]` only ([`solver::solve_counted_from`]).
pub(crate) fn vertex_face_from(query: &VertexFace, options: &NarrowOptions, t_start: f64) -> Outcome {
    solver::solve_counted_from(&solver::Problem::vertex_face(query), options, t_start).0
}
