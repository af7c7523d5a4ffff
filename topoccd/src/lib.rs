//! # topoccd
//!
//! Continuous collision detection (CCD) for deforming triangle meshes whose topology may change
//! from one step to the next (cutting, tearing, fracture). Give it the vertex positions at t=0
//! and t=1 of one step and the triangles; it returns every vertex-face and edge-edge contact
//! with its time of impact, or only the earliest ones, and never misses a contact.
//!
//! The API is a handful of types: a [`Step`] (the input, borrowed, with an optional parent
//! list across a topology change and a pair filter), a reusable [`Ccd`] with [`QueryOptions`],
//! and a [`Report`] of [`VfContact`]s and [`EeContact`]s, each with a [`Certainty`] and, on
//! request, its geometry. [`io`] reads and writes meshes and frame sequences.
//!
//! For a contact solver's barrier, [`Ccd::proximity`] gives every primitive pair of one
//! [`Configuration`] closer than `dhat` (free edges and points included), with distances and
//! closest-feature types ([`distance`]), in a [`ProximityReport`]; the `Ccd` keeps its
//! hierarchy across a solver's iterations and refits it.
//!
//! A step across a cut: vertex 4 is split from vertex 1 and starts at its position, then a
//! vertex of the cut-off piece falls through the other piece.
//!
//! ```
//! use topoccd::{Ccd, Method, Mode, QueryOptions, Step};
//! let x0 = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 1.0], [0.2, 0.2, 1.0]];
//! let x1 = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 1.0], [0.2, 0.2, -1.0],
//!           [1.0, 0.0, 1.0]];
//! let triangles = [[0u32, 1, 2], [3, 4, 5]];
//! let step = Step::with_parents(&x0, &x1, &triangles, &[[5, 1]])?;
//! let mut ccd = Ccd::new(); // keep it across steps: its buffers are reused
//! let options = QueryOptions { mode: Mode::Earliest, geometry: true, ..QueryOptions::default() };
//! let report = ccd.query(&step, Method::Bvh, &options)?;
//! let hit = report.vf[0]; // the earliest pair(s)
//! assert_eq!((hit.vertex, hit.face), (4, 0));
//! assert!((hit.toi - 0.5).abs() < 1e-6); // not 0: vertex 5 and its parent 1 are one vertex
//! assert_eq!(hit.geometry.unwrap().normal, [0.0, 0.0, 1.0]);
//! assert_eq!(report.unresolved, 0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Inside, the folders follow the data: `mesh` (input model, topology, features, pair
//! filter) → `narrow` (elementary tests, prefilter, Bernstein bounds) → `contact` (the narrow
//! phase's driver: candidates to contacts, options, limits, report) → `kdop` and `bvh`
//! (bounding volumes) → `broad` (brute force, per-step hierarchy, clusters) → `query` →
//! [`io`]. Only the types re-exported here are public; the crate feature `internals` exposes the
//! rest, hidden and unstable, to the crate's own tests and the workspace's generators.
#![warn(missing_docs)]

/// Declares an internal module: private, or public and hidden with the feature `internals`
/// (for the crate's own tests and the workspace's generators and benchmarks).
macro_rules! internal {
    ($($name:ident),* $(,)?) => {$(
        #[cfg(feature = "internals")]
        #[doc(hidden)]
        pub mod $name;
        #[cfg(not(feature = "internals"))]
        #[allow(dead_code, unused_imports)]
        mod $name;
    )*};
}

internal!(broad, bvh, contact, kdop, math, mesh, narrow, query);

pub mod distance;
pub mod ipc;
mod proximity;

mod alloc;

pub mod check;
pub mod io;
pub mod line_search;
pub mod pair;
pub mod range;

pub use kdop::DopKind;
pub use mesh::{CanCollide, Frame, Positions, Step, StepError, Triangles};
pub use narrow::NarrowOptions;
/// The proximity query's parts timed one by one (for the benchmarks; internals only).
#[cfg(feature = "internals")]
#[doc(hidden)]
pub use proximity::floor as proximity_floor;
pub use proximity::{
    proximity, Configuration, EeProximity, ProximityError, ProximityMethod, ProximityOptions,
    ProximityReport, ProximityStats, VeProximity, VfProximity, VvProximity,
};
pub use query::DEFAULT_MAX_CONTACTS;
pub use query::{
    query, Ccd, Certainty, ClusterFigures, ClusterGrowth, Contact, EeContact, EeGeometry, Method,
    Mode, OptionsError, QueryOptions, Report, Seconds, Stats, VeContact, VfContact, VfGeometry,
    VvContact, AUTO_CLUSTER_TRIANGLES,
};
pub use query::{CancelToken, Phase, StopReason, Truncation};

/// The crate's README (its page on the registry), run as doctests. The repository's README and
/// the user guide are run by the workspace's test crate, `topoccd-tests`.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;
