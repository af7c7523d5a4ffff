//! One pair of features tested on its own: a vertex against a triangle ([`vertex_face`]), an
//! edge against an edge ([`edge_edge`]), and, for codimensional geometry (free points and
//! edges), a vertex against an edge ([`vertex_edge`]) or a vertex ([`vertex_vertex`]), each
//! point moving linearly over the step.
//!
//! These are the elementary tests every [`Ccd`](crate::Ccd) query runs on its candidate pairs,
//! for callers that keep their own candidate lists (as the IPC toolkit's `point_triangle_ccd`
//! and `edge_edge_ccd`, `point_edge_ccd`, `point_point_ccd` do). They are conservative: when the features touch in exact arithmetic
//! at some time in `[0, tmax]`, the outcome is a contact whose time of impact is never later
//! than the first contact, and within [`NarrowOptions::tolerance`] of it unless the features
//! come close before they touch. The guarantees hold over the whole input range
//! ([`range`](crate::range)), at any uniform scale; a pair outside it is a contact at 0,
//! [`Certainty::InvalidInput`].
//!
//! ```
//! use topoccd::pair::{vertex_face, Outcome, VertexFace};
//! use topoccd::{Certainty, NarrowOptions};
//! // A vertex falls from z=1 to z=-1 through the triangle in the plane z=0: contact at t=0.5.
//! let q = VertexFace {
//!     v_t0: [0.2, 0.2, 1.0],
//!     f0_t0: [0.0, 0.0, 0.0], f1_t0: [1.0, 0.0, 0.0], f2_t0: [0.0, 1.0, 0.0],
//!     v_t1: [0.2, 0.2, -1.0],
//!     f0_t1: [0.0, 0.0, 0.0], f1_t1: [1.0, 0.0, 0.0], f2_t1: [0.0, 1.0, 0.0],
//! };
//! match vertex_face(&q, &NarrowOptions::default())? {
//!     Outcome::Contact { toi, certainty } => {
//!         assert!(toi <= 0.5 && toi > 0.5 - 1e-6);
//!         assert_eq!(certainty, Certainty::Resolved);
//!     }
//!     Outcome::Separated => unreachable!("the vertex crosses the triangle"),
//! }
//! # Ok::<(), topoccd::OptionsError>(())
//! ```

use crate::math::DVec3;
use crate::narrow;
use crate::query::OptionsError;

pub use crate::narrow::{Certainty, NarrowOptions, Outcome};

/// A vertex and a triangle, each point moving linearly from its `_t0` to its `_t1` position.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VertexFace {
    /// The vertex at t=0.
    pub v_t0: [f64; 3],
    /// Triangle corner 0 at t=0.
    pub f0_t0: [f64; 3],
    /// Triangle corner 1 at t=0.
    pub f1_t0: [f64; 3],
    /// Triangle corner 2 at t=0.
    pub f2_t0: [f64; 3],
    /// The vertex at t=1.
    pub v_t1: [f64; 3],
    /// Triangle corner 0 at t=1.
    pub f0_t1: [f64; 3],
    /// Triangle corner 1 at t=1.
    pub f1_t1: [f64; 3],
    /// Triangle corner 2 at t=1.
    pub f2_t1: [f64; 3],
}

/// Two edges `ea` and `eb`, each end point moving linearly from its `_t0` to its `_t1` position.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EdgeEdge {
    /// Edge a, end 0, at t=0.
    pub ea0_t0: [f64; 3],
    /// Edge a, end 1, at t=0.
    pub ea1_t0: [f64; 3],
    /// Edge b, end 0, at t=0.
    pub eb0_t0: [f64; 3],
    /// Edge b, end 1, at t=0.
    pub eb1_t0: [f64; 3],
    /// Edge a, end 0, at t=1.
    pub ea0_t1: [f64; 3],
    /// Edge a, end 1, at t=1.
    pub ea1_t1: [f64; 3],
    /// Edge b, end 0, at t=1.
    pub eb0_t1: [f64; 3],
    /// Edge b, end 1, at t=1.
    pub eb1_t1: [f64; 3],
}

impl VertexFace {
    /// The eight points in the order of the Sample-Queries files and of the IPC toolkit's
    /// arguments: `v, f0, f1, f2` at t=0, then at t=1.
    ///
    /// ```
    /// use topoccd::pair::VertexFace;
    /// let q = VertexFace::from_points([[0.0; 3]; 8]);
    /// assert_eq!(q.points(), [[0.0; 3]; 8]);
    /// ```
    pub fn from_points(p: [[f64; 3]; 8]) -> Self {
        let [v_t0, f0_t0, f1_t0, f2_t0, v_t1, f0_t1, f1_t1, f2_t1] = p;
        Self {
            v_t0,
            f0_t0,
            f1_t0,
            f2_t0,
            v_t1,
            f0_t1,
            f1_t1,
            f2_t1,
        }
    }

    /// The eight points, in the order of [`VertexFace::from_points`].
    pub fn points(&self) -> [[f64; 3]; 8] {
        [
            self.v_t0, self.f0_t0, self.f1_t0, self.f2_t0, self.v_t1, self.f0_t1, self.f1_t1,
            self.f2_t1,
        ]
    }

    fn internal(&self) -> narrow::VertexFace {
        narrow::VertexFace::from_points(self.points().map(DVec3::from_array))
    }
}

impl EdgeEdge {
    /// The eight points in the order of the Sample-Queries files and of the IPC toolkit's
    /// arguments: `ea0, ea1, eb0, eb1` at t=0, then at t=1.
    ///
    /// ```
    /// use topoccd::pair::EdgeEdge;
    /// let q = EdgeEdge::from_points([[1.0; 3]; 8]);
    /// assert_eq!(q.points(), [[1.0; 3]; 8]);
    /// ```
    pub fn from_points(p: [[f64; 3]; 8]) -> Self {
        let [ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1, eb1_t1] = p;
        Self {
            ea0_t0,
            ea1_t0,
            eb0_t0,
            eb1_t0,
            ea0_t1,
            ea1_t1,
            eb0_t1,
            eb1_t1,
        }
    }

    /// The eight points, in the order of [`EdgeEdge::from_points`].
    pub fn points(&self) -> [[f64; 3]; 8] {
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

    fn internal(&self) -> narrow::EdgeEdge {
        narrow::EdgeEdge::from_points(self.points().map(DVec3::from_array))
    }
}

/// Continuous collision test of a vertex against a triangle (its interior, edges and corners)
/// over `[0, options.tmax]`. Options out of their documented range are an
/// [`OptionsError`] ([`NarrowOptions::validate`]).
///
/// Non-finite coordinates, or coordinates whose differences exceed `1e300`, give a contact at
/// time 0 marked [`Certainty::InvalidInput`]; running out of `max_iterations` gives the earliest
/// time not yet ruled out, marked [`Certainty::IterationLimit`].
///
/// ```
/// use topoccd::pair::{vertex_face, VertexFace};
/// use topoccd::NarrowOptions;
/// // The vertex stays 1 above the triangle's plane: no contact, unless `min_distance`
/// // counts that distance as touching.
/// let q = VertexFace {
///     v_t0: [0.2, 0.2, 1.0], v_t1: [0.3, 0.2, 1.0],
///     f1_t0: [1.0, 0.0, 0.0], f2_t0: [0.0, 1.0, 0.0],
///     f1_t1: [1.0, 0.0, 0.0], f2_t1: [0.0, 1.0, 0.0],
///     ..Default::default()
/// };
/// assert!(!vertex_face(&q, &NarrowOptions::default())?.is_contact());
/// let near = NarrowOptions { min_distance: 1.0, ..NarrowOptions::default() };
/// assert_eq!(vertex_face(&q, &near)?.toi(), Some(0.0));
/// # Ok::<(), topoccd::OptionsError>(())
/// ```
pub fn vertex_face(query: &VertexFace, options: &NarrowOptions) -> Result<Outcome, OptionsError> {
    options.validate()?;
    Ok(narrow::vertex_face(&query.internal(), options))
}

/// Continuous collision test of two edges (their interiors and end points) over
/// `[0, options.tmax]`; otherwise as [`vertex_face`].
///
/// ```
/// use topoccd::pair::{edge_edge, EdgeEdge};
/// use topoccd::NarrowOptions;
/// // Edge a lies along x; edge b, along y, falls from z=1 to z=-1 across it: contact at 0.5.
/// let q = EdgeEdge {
///     ea0_t0: [-1.0, 0.0, 0.0], ea1_t0: [1.0, 0.0, 0.0],
///     eb0_t0: [0.0, -1.0, 1.0], eb1_t0: [0.0, 1.0, 1.0],
///     ea0_t1: [-1.0, 0.0, 0.0], ea1_t1: [1.0, 0.0, 0.0],
///     eb0_t1: [0.0, -1.0, -1.0], eb1_t1: [0.0, 1.0, -1.0],
/// };
/// let toi = edge_edge(&q, &NarrowOptions::default())?.toi().unwrap();
/// assert!(toi <= 0.5 && toi > 0.5 - 1e-6);
/// # Ok::<(), topoccd::OptionsError>(())
/// ```
pub fn edge_edge(query: &EdgeEdge, options: &NarrowOptions) -> Result<Outcome, OptionsError> {
    options.validate()?;
    Ok(narrow::edge_edge(&query.internal(), options))
}

/// A vertex and an edge, each point moving linearly from its `_t0` to its `_t1` position.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VertexEdge {
    /// The vertex at t=0.
    pub v_t0: [f64; 3],
    /// Edge end 0 at t=0.
    pub e0_t0: [f64; 3],
    /// Edge end 1 at t=0.
    pub e1_t0: [f64; 3],
    /// The vertex at t=1.
    pub v_t1: [f64; 3],
    /// Edge end 0 at t=1.
    pub e0_t1: [f64; 3],
    /// Edge end 1 at t=1.
    pub e1_t1: [f64; 3],
}

impl VertexEdge {
    /// The six points in the IPC toolkit's order (`point_edge_ccd`): `v, e0, e1` at t=0, then
    /// at t=1.
    ///
    /// ```
    /// use topoccd::pair::VertexEdge;
    /// let q = VertexEdge::from_points([[2.0; 3]; 6]);
    /// assert_eq!(q.points(), [[2.0; 3]; 6]);
    /// ```
    pub fn from_points(p: [[f64; 3]; 6]) -> Self {
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

    /// The six points, in the order of [`VertexEdge::from_points`].
    pub fn points(&self) -> [[f64; 3]; 6] {
        [
            self.v_t0, self.e0_t0, self.e1_t0, self.v_t1, self.e0_t1, self.e1_t1,
        ]
    }

    fn internal(&self) -> narrow::VertexEdge {
        narrow::VertexEdge::from_points(self.points().map(DVec3::from_array))
    }
}

/// Two vertices `a` and `b`, each moving linearly from its `_t0` to its `_t1` position.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VertexVertex {
    /// Vertex a at t=0.
    pub a_t0: [f64; 3],
    /// Vertex b at t=0.
    pub b_t0: [f64; 3],
    /// Vertex a at t=1.
    pub a_t1: [f64; 3],
    /// Vertex b at t=1.
    pub b_t1: [f64; 3],
}

impl VertexVertex {
    /// The four points in the IPC toolkit's order (`point_point_ccd`): `a, b` at t=0, then at
    /// t=1.
    ///
    /// ```
    /// use topoccd::pair::VertexVertex;
    /// let q = VertexVertex::from_points([[3.0; 3]; 4]);
    /// assert_eq!(q.points(), [[3.0; 3]; 4]);
    /// ```
    pub fn from_points(p: [[f64; 3]; 4]) -> Self {
        let [a_t0, b_t0, a_t1, b_t1] = p;
        Self {
            a_t0,
            b_t0,
            a_t1,
            b_t1,
        }
    }

    /// The four points, in the order of [`VertexVertex::from_points`].
    pub fn points(&self) -> [[f64; 3]; 4] {
        [self.a_t0, self.b_t0, self.a_t1, self.b_t1]
    }

    fn internal(&self) -> narrow::VertexVertex {
        narrow::VertexVertex::from_points(self.points().map(DVec3::from_array))
    }
}

/// Continuous collision test of a vertex against an edge (its interior and end points) over
/// `[0, options.tmax]`, for free points and edges (rods, hair, particles); otherwise as
/// [`vertex_face`]. It is the edge-edge test with the vertex as an edge of length zero, with
/// the same guarantees: no contact missed, and the features come within `min_distance` plus
/// `sqrt(3) / 2` times the tolerance times their relative displacement (plus rounding) of
/// each other at a time in `[toi, toi + tolerance]`.
///
/// ```
/// use topoccd::pair::{vertex_edge, VertexEdge};
/// use topoccd::NarrowOptions;
/// // The vertex falls from z=1 to z=-1 across the edge along x at z=0: contact at t=0.5.
/// let q = VertexEdge {
///     v_t0: [0.3, 0.0, 1.0], v_t1: [0.3, 0.0, -1.0],
///     e0_t0: [-1.0, 0.0, 0.0], e1_t0: [1.0, 0.0, 0.0],
///     e0_t1: [-1.0, 0.0, 0.0], e1_t1: [1.0, 0.0, 0.0],
/// };
/// let toi = vertex_edge(&q, &NarrowOptions::default())?.toi().unwrap();
/// assert!(toi <= 0.5 && toi > 0.5 - 1e-6);
/// # Ok::<(), topoccd::OptionsError>(())
/// ```
pub fn vertex_edge(query: &VertexEdge, options: &NarrowOptions) -> Result<Outcome, OptionsError> {
    options.validate()?;
    Ok(narrow::vertex_edge(&query.internal(), options))
}

/// Continuous collision test of two vertices over `[0, options.tmax]`, for free points
/// (particles); otherwise as [`vertex_edge`].
///
/// ```
/// use topoccd::pair::{vertex_vertex, VertexVertex};
/// use topoccd::NarrowOptions;
/// // Two particles 0.1 across pass each other: they touch only with `min_distance >= 0.1`.
/// let q = VertexVertex {
///     a_t0: [-1.0, 0.0, 0.0], a_t1: [1.0, 0.0, 0.0],
///     b_t0: [1.0, 0.1, 0.0], b_t1: [-1.0, 0.1, 0.0],
/// };
/// assert!(!vertex_vertex(&q, &NarrowOptions::default())?.is_contact());
/// let near = NarrowOptions { min_distance: 0.1, ..NarrowOptions::default() };
/// let toi = vertex_vertex(&q, &near)?.toi().unwrap();
/// assert!(toi <= 0.5 && toi > 0.5 - 1e-6);
/// # Ok::<(), topoccd::OptionsError>(())
/// ```
pub fn vertex_vertex(
    query: &VertexVertex,
    options: &NarrowOptions,
) -> Result<Outcome, OptionsError> {
    options.validate()?;
    Ok(narrow::vertex_vertex(&query.internal(), options))
}
