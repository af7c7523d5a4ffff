//! Edge against edge.

use super::{solver, NarrowOptions, Outcome};
use crate::math::DVec3;

/// Two edges `ea` and `eb`, each end point moving linearly from its `_t0` to its `_t1` position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeEdge {
    /// Edge a, end 0, at t=0.
    pub ea0_t0: DVec3,
    /// Edge a, end 1, at t=0.
    pub ea1_t0: DVec3,
    /// Edge b, end 0, at t=0.
    pub eb0_t0: DVec3,
    /// Edge b, end 1, at t=0.
    pub eb1_t0: DVec3,
    /// Edge a, end 0, at t=1.
    pub ea0_t1: DVec3,
    /// Edge a, end 1, at t=1.
    pub ea1_t1: DVec3,
    /// Edge b, end 0, at t=1.
    pub eb0_t1: DVec3,
    /// Edge b, end 1, at t=1.
    pub eb1_t1: DVec3,
}

impl EdgeEdge {
    /// The eight points in the order of the query files: `ea0, ea1, eb0, eb1` at t=0, then t=1.
    pub fn from_points(p: [DVec3; 8]) -> Self {
        Self {
            ea0_t0: p[0],
            ea1_t0: p[1],
            eb0_t0: p[2],
            eb1_t0: p[3],
            ea0_t1: p[4],
            ea1_t1: p[5],
            eb0_t1: p[6],
            eb1_t1: p[7],
        }
    }

    /// The eight points, in the order of [`EdgeEdge::from_points`].
    pub fn points(&self) -> [DVec3; 8] {
        [
            self.ea0_t0,
            self.ea1_t0,
            self.eb0_t0,
            self.eb1_t0,
            self.ea0_t1,
            self.ea1_t1,
            self.eb0_t1,
            self.eb1_t1,
        ]
    }

    /// The same query with the two edges swapped.
    pub fn swapped(&self) -> Self {
        Self {
            ea0_t0: self.eb0_t0,
            ea1_t0: self.eb1_t0,
            eb0_t0: self.ea0_t0,
            eb1_t0: self.ea1_t0,
            ea0_t1: self.eb0_t1,
            ea1_t1: self.eb1_t1,
            eb0_t1: self.ea0_t1,
            eb1_t1: self.ea1_t1,
        }
    }
}

/// Continuous collision test of two edges (end points included) over `[0, options.tmax]`.
///
/// ```
/// use topoccd::math::DVec3;
/// use topoccd::narrow::{edge_edge, EdgeEdge, NarrowOptions};
/// // Edge a along x at z=1 falls to z=-1 across edge b along y at z=0: contact at t=0.5.
/// let q = EdgeEdge {
///     ea0_t0: DVec3::new(-1.0, 0.0, 1.0), ea1_t0: DVec3::new(1.0, 0.0, 1.0),
///     eb0_t0: DVec3::new(0.0, -1.0, 0.0), eb1_t0: DVec3::new(0.0, 1.0, 0.0),
///     ea0_t1: DVec3::new(-1.0, 0.0, -1.0), ea1_t1: DVec3::new(1.0, 0.0, -1.0),
///     eb0_t1: DVec3::new(0.0, -1.0, 0.0), eb1_t1: DVec3::new(0.0, 1.0, 0.0),
/// };
/// let toi = edge_edge(&q, &NarrowOptions::default()).toi().unwrap();
/// assert!(toi <= 0.5 && toi > 0.5 - 1e-6);
/// ```
pub fn edge_edge(query: &EdgeEdge, options: &NarrowOptions) -> Outcome {
    solver::solve(&solver::Problem::edge_edge(query), options)
}

/// [`edge_edge`] for a pair proved apart by more than `min_distance` during
/// `[0, t_start]` (see [`vertex_face_from`](super::vertex_face::vertex_face_from)).
pub(crate) fn edge_edge_from(query: &EdgeEdge, options: &NarrowOptions, t_start: f64) -> Outcome {
    solver::solve_counted_from(&solver::Problem::edge_edge(query), options, t_start).0
}
