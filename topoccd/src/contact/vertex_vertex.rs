//! Vertex-vertex contacts: two free points (codimensional geometry). The driver solves such a
//! pair as an edge-edge pair of two edges of length zero (see `broad::codim`, and
//! [`narrow::vertex_vertex`](crate::narrow::vertex_vertex) for the elementary test's
//! guarantees); this file turns its contacts into the report's kind.

use super::report::{Certainty, EeContact, EeGeometry};

/// Two points (vertices in no triangle and no edge) that (may) touch during the step.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct VvContact {
    /// The smaller vertex index.
    pub a: u32,
    /// The larger one.
    pub b: u32,
    /// Time of impact in `[0, tmax]`, no later than the first contact.
    pub toi: f64,
    /// Whether the contact was isolated or the search gave up conservatively.
    pub certainty: Certainty,
    /// Where the contact is, with [`QueryOptions::geometry`](crate::QueryOptions::geometry):
    /// as for two edges of length zero (both parameters 0; the normal from `b` to `a`).
    pub geometry: Option<EeGeometry>,
}

/// `Some` with the vertex-vertex contact when both edges of the driver's edge-edge contact
/// `c` have length zero (points).
pub(crate) fn from_edge_edge(c: &EeContact) -> Option<VvContact> {
    (c.a[0] == c.a[1] && c.b[0] == c.b[1]).then_some(VvContact {
        a: c.a[0],
        b: c.b[0],
        toi: c.toi,
        certainty: c.certainty,
        geometry: c.geometry,
    })
}
