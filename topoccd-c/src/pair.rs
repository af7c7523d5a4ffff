//! The per-pair tests: a vertex against a triangle and an edge against an edge, for callers
//! that keep their own candidate lists (as the IPC toolkit's `point_triangle_ccd` does).

use topoccd::pair::{self, EdgeEdge, Outcome, VertexFace};

use crate::error::{deliver, topoccd_error};
use crate::options::{self, topoccd_query_options};
use crate::report::topoccd_certainty;
use crate::status::{guard, topoccd_status, Failure};

/// A vertex and a triangle, each point moving linearly from its `_t0` to its `_t1` position
/// (`x y z`). The order of the fields is that of the IPC toolkit's arguments: `v, f0, f1, f2`
/// at t=0, then at t=1.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct topoccd_vertex_face {
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

/// Two edges `ea` and `eb`, each end point moving linearly from its `_t0` to its `_t1` position:
/// `ea0, ea1, eb0, eb1` at t=0, then at t=1.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct topoccd_edge_edge {
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

/// The answer of a per-pair test.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct topoccd_outcome {
    /// Whether the features (may) touch during `[0, tmax]`; false: they stay farther apart
    /// than `min_distance`.
    pub contact: bool,
    /// A `topoccd_certainty` (`TOPOCCD_CERTAINTY_RESOLVED` when there is no contact).
    pub certainty: topoccd_certainty,
    /// With a contact, the time of impact in [0, tmax], never later than the first contact;
    /// NaN without.
    pub toi: f64,
}

impl From<Outcome> for topoccd_outcome {
    fn from(o: Outcome) -> Self {
        match o {
            Outcome::Separated => Self {
                contact: false,
                certainty: topoccd_certainty::Resolved,
                toi: f64::NAN,
            },
            Outcome::Contact { toi, certainty } => Self {
                contact: true,
                certainty: certainty.into(),
                toi,
            },
        }
    }
}

/// Runs one per-pair test and delivers its outcome.
///
/// # Safety
/// As the public functions below.
unsafe fn run<Q: Copy>(
    query: *const Q,
    options: *const topoccd_query_options,
    outcome: *mut topoccd_outcome,
    error: *mut *mut topoccd_error,
    test: impl FnOnce(&Q, &topoccd::NarrowOptions) -> Result<Outcome, topoccd::OptionsError>,
) -> topoccd_status {
    let result = guard(|| {
        if query.is_null() {
            return Err(Failure::null("query"));
        }
        if outcome.is_null() {
            return Err(Failure::null("outcome"));
        }
        let options = options::read(options)?;
        let found = test(&*query, &options.query.narrow)
            .map_err(|e| Failure::new(topoccd_status::InvalidOptions, e.to_string()))?;
        *outcome = found.into();
        Ok(())
    });
    deliver(result, error)
}

/// Continuous collision test of a vertex against a triangle (its interior, edges and corners)
/// over `[0, tmax]`, conservative: when they touch in exact arithmetic, the outcome is a
/// contact whose time of impact is never later than the first contact, and within `tolerance`
/// of it unless the features come close before they touch. `options` may be NULL (the
/// defaults); only `tolerance`, `max_iterations`, `min_distance` and `tmax` are read.
///
/// NaN or infinite coordinates are not an error: the outcome is a contact at time 0 marked
/// `TOPOCCD_CERTAINTY_INVALID_INPUT`. Returns `TOPOCCD_STATUS_NULL_POINTER` (`query` or
/// `outcome` NULL) or `TOPOCCD_STATUS_INVALID_OPTIONS`, with details in `*error` (see
/// `topoccd_error`; `error` may be NULL).
///
/// ```c
/// topoccd_vertex_face q = {
///     .v_t0 = {0.2, 0.2, 1}, .f1_t0 = {1, 0, 0}, .f2_t0 = {0, 1, 0},
///     .v_t1 = {0.2, 0.2, -1}, .f1_t1 = {1, 0, 0}, .f2_t1 = {0, 1, 0},
/// };
/// topoccd_outcome o;
/// topoccd_pair_vertex_face(&q, NULL, &o, NULL); /* o.contact, o.toi just below 0.5 */
/// ```
///
/// # Safety
/// `query` and `outcome` are NULL or valid for a read and a write of their type; `options` is
/// NULL or initialised by `topoccd_query_options_default`; `error` is NULL or valid for a write
/// of a pointer.
#[no_mangle]
pub unsafe extern "C" fn topoccd_pair_vertex_face(
    query: *const topoccd_vertex_face,
    options: *const topoccd_query_options,
    outcome: *mut topoccd_outcome,
    error: *mut *mut topoccd_error,
) -> topoccd_status {
    run(query, options, outcome, error, |q, o| {
        let q = VertexFace {
            v_t0: q.v_t0,
            f0_t0: q.f0_t0,
            f1_t0: q.f1_t0,
            f2_t0: q.f2_t0,
            v_t1: q.v_t1,
            f0_t1: q.f0_t1,
            f1_t1: q.f1_t1,
            f2_t1: q.f2_t1,
        };
        pair::vertex_face(&q, o)
    })
}

/// Continuous collision test of two edges (their interiors and end points) over
/// `[0, tmax]`; otherwise as `topoccd_pair_vertex_face`.
///
/// # Safety
/// As `topoccd_pair_vertex_face`.
#[no_mangle]
pub unsafe extern "C" fn topoccd_pair_edge_edge(
    query: *const topoccd_edge_edge,
    options: *const topoccd_query_options,
    outcome: *mut topoccd_outcome,
    error: *mut *mut topoccd_error,
) -> topoccd_status {
    run(query, options, outcome, error, |q, o| {
        let q = EdgeEdge {
            ea0_t0: q.ea0_t0,
            ea1_t0: q.ea1_t0,
            eb0_t0: q.eb0_t0,
            eb1_t0: q.eb1_t0,
            ea0_t1: q.ea0_t1,
            ea1_t1: q.ea1_t1,
            eb0_t1: q.eb0_t1,
            eb1_t1: q.eb1_t1,
        };
        pair::edge_edge(&q, o)
    })
}
