//! Vertex against edge: a point and a segment, for free points and free edges (codimensional
//! geometry), solved as an edge-edge test whose first edge has length zero.
//!
//! The solver's function is then `F(t, u, v) = P(t) + v B(t)` (the edge-edge form with
//! `A = 0`): still multilinear, so every argument of the [solver](super::solver) holds as
//! it stands. A box is excluded only along a direction that separates the convex hull of its
//! corner images from the ball of radius `min_distance`, whatever that direction is: a zero
//! direction (the normal `A x B`, the coplanarity cubic, which vanish here) never excludes
//! anything, and the closest points of a point and a segment are always computable (the
//! degenerate-feature search is not needed), so no contact is missed and the bound on how
//! early a time of impact can be is the edge-edge one: the features come within
//! `min_distance + sqrt(3) / 2 tolerance S_t + rounding` of each other at a time in
//! `[toi, toi + tolerance]`, `S_t` the sum of the largest coordinate changes of `P` and `B`
//! over the step (see [`NarrowOptions::tolerance`]).

use super::{edge_edge, EdgeEdge, NarrowOptions, Outcome};
use crate::math::DVec3;

/// A vertex `v` and an edge `e`, each point moving linearly from its `_t0` to its `_t1`
/// position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VertexEdge {
    /// The vertex at t=0.
    pub v_t0: DVec3,
    /// Edge end 0 at t=0.
    pub e0_t0: DVec3,
    /// Edge end 1 at t=0.
    pub e1_t0: DVec3,
    /// The vertex at t=1.
    pub v_t1: DVec3,
    /// Edge end 0 at t=1.
    pub e0_t1: DVec3,
    /// Edge end 1 at t=1.
    pub e1_t1: DVec3,
}

impl VertexEdge {
    /// The six points in the IPC toolkit's order: `v, e0, e1` at t=0, then at t=1.
    pub fn from_points(p: [DVec3; 6]) -> Self {
        let [v_t0, e0_t0, e1_t0, v_t1, e0_t1, e1_t1] = p;
        Self {
            v_t0,
            e0_t0,
            e1_t0,
            v_t1,
            e0_t1,
            e1_t1,
        }
    }

    /// The edge-edge query of the vertex, as an edge of length zero, against the edge.
    pub fn as_edge_edge(&self) -> EdgeEdge {
        EdgeEdge {
            ea0_t0: self.v_t0,
            ea1_t0: self.v_t0,
            eb0_t0: self.e0_t0,
            eb1_t0: self.e1_t0,
            ea0_t1: self.v_t1,
            ea1_t1: self.v_t1,
            eb0_t1: self.e0_t1,
            eb1_t1: self.e1_t1,
        }
    }
}

/// Continuous collision test of a vertex against an edge (its interior and end points) over
/// `[0, options.tmax]`, with the guarantees of the edge-edge test (see the
/// module's documentation).
///
/// ```
/// use topoccd::math::DVec3;
/// use topoccd::narrow::{vertex_edge, NarrowOptions, VertexEdge};
/// // The vertex falls from z=1 to z=-1 across the edge along x at z=0: contact at t=0.5.
/// let q = VertexEdge {
///     v_t0: DVec3::new(0.3, 0.0, 1.0), v_t1: DVec3::new(0.3, 0.0, -1.0),
///     e0_t0: DVec3::new(-1.0, 0.0, 0.0), e1_t0: DVec3::new(1.0, 0.0, 0.0),
///     e0_t1: DVec3::new(-1.0, 0.0, 0.0), e1_t1: DVec3::new(1.0, 0.0, 0.0),
/// };
/// let toi = vertex_edge(&q, &NarrowOptions::default()).toi().unwrap();
/// assert!(toi <= 0.5 && toi > 0.5 - 1e-6);
/// ```
pub fn vertex_edge(query: &VertexEdge, options: &NarrowOptions) -> Outcome {
    edge_edge(&query.as_edge_edge(), options)
}
