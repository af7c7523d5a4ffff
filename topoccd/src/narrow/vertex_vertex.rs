//! Vertex against vertex: two points, for free points (codimensional geometry), solved as an
//! edge-edge test of two edges of length zero.
//!
//! The solver's function is then `F(t, u, v) = P(t)`, the difference of the two points (the
//! edge-edge form with `A = B = 0`): multilinear, so the [solver](super::solver)'s arguments
//! hold as they stand (see `vertex_edge` for why the vanishing normal
//! and coplanarity cubic exclude nothing wrongly). The closest points' direction is `P` at
//! the box's mid time, the exact one, so the bound on how early a time of impact can be is the
//! edge-edge one: the points come within `min_distance + sqrt(3) / 2 tolerance S_t +
//! rounding` of each other at a time in `[toi, toi + tolerance]`, `S_t` the largest coordinate
//! change of `P` over the step.

use super::{edge_edge, EdgeEdge, NarrowOptions, Outcome};
use crate::math::DVec3;

/// Two vertices `a` and `b`, each moving linearly from its `_t0` to its `_t1` position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VertexVertex {
    /// Vertex a at t=0.
    pub a_t0: DVec3,
    /// Vertex b at t=0.
    pub b_t0: DVec3,
    /// Vertex a at t=1.
    pub a_t1: DVec3,
    /// Vertex b at t=1.
    pub b_t1: DVec3,
}

impl VertexVertex {
    /// The four points in the IPC toolkit's order: `a, b` at t=0, then at t=1.
    pub fn from_points(p: [DVec3; 4]) -> Self {
        let [a_t0, b_t0, a_t1, b_t1] = p;
        Self {
            a_t0,
            b_t0,
            a_t1,
            b_t1,
        }
    }

    /// The edge-edge query of the two vertices as edges of length zero.
    pub fn as_edge_edge(&self) -> EdgeEdge {
        EdgeEdge {
            ea0_t0: self.a_t0,
            ea1_t0: self.a_t0,
            eb0_t0: self.b_t0,
            eb1_t0: self.b_t0,
            ea0_t1: self.a_t1,
            ea1_t1: self.a_t1,
            eb0_t1: self.b_t1,
            eb1_t1: self.b_t1,
        }
    }
}

/// Continuous collision test of two vertices over `[0, options.tmax]`, with the guarantees
/// of the edge-edge test.
///
/// ```
/// use topoccd::math::DVec3;
/// use topoccd::narrow::{vertex_vertex, NarrowOptions, VertexVertex};
/// // Two points meet head on at the origin at t=0.25.
/// let q = VertexVertex {
///     a_t0: DVec3::new(-1.0, 0.0, 0.0), a_t1: DVec3::new(3.0, 0.0, 0.0),
///     b_t0: DVec3::new(1.0, 0.0, 0.0), b_t1: DVec3::new(-3.0, 0.0, 0.0),
/// };
/// let toi = vertex_vertex(&q, &NarrowOptions::default()).toi().unwrap();
/// assert!(toi <= 0.25 && toi > 0.25 - 1e-6);
/// ```
pub fn vertex_vertex(query: &VertexVertex, options: &NarrowOptions) -> Outcome {
    edge_edge(&query.as_edge_edge(), options)
}
