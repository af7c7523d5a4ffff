//! The narrow phase's driver, below the broad phases: the broad phase hands buffers of
//! candidate pairs down (`Candidates`), the driver solves them with the elementary tests of
//! [`narrow`](crate::narrow) into contacts, under the query's options and limits; `query`
//! orchestrates from above.
//!
//! - `candidates`: the buffers of candidate pairs and the owner triangles' swept volumes;
//! - `driver`: batches, modes, limits, the first pass's rules, the report's order;
//! - `vertex_face`, `edge_edge`: each primitive kind's part (its query, prefilter, elementary
//!   test and contact), one file per kind; `vertex_edge`, `vertex_vertex`: the contacts of free
//!   points, which the driver solves as edge-edge pairs with edges of length zero;
//! - `options`, `limits`, `report`, `geometry`: what a query reads and fills (re-exported by
//!   `query`, which is where the public API names them).

mod candidates;
pub(crate) mod driver;
mod edge_edge;
pub(crate) mod geometry;
pub(crate) mod limits;
pub(crate) mod options;
pub(crate) mod report;
pub(crate) mod vertex_edge;
mod vertex_face;
pub(crate) mod vertex_vertex;

pub(crate) use candidates::{triangle_volume, Candidates};
pub use limits::{CancelToken, Phase, StopReason, Truncation};
pub use options::DEFAULT_MAX_CONTACTS;
pub use options::{ClusterGrowth, Method, Mode, OptionsError, QueryOptions, AUTO_CLUSTER_TRIANGLES};
pub use report::{
    Certainty, ClusterFigures, Contact, EeContact, EeGeometry, Report, Seconds, Stats, VfContact,
    VfGeometry,
};
pub use vertex_edge::VeContact;
pub use vertex_vertex::VvContact;
