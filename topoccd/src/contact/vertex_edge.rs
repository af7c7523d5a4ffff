//! Vertex-edge contacts: a free point against a free edge (codimensional geometry). The
//! driver solves such a pair as an edge-edge pair in which the point is an edge of length
//! zero `[p, p]` (see `broad::codim`, and [`narrow::vertex_edge`](crate::narrow::vertex_edge)
//! for the elementary test's guarantees); this file turns its contacts into the report's kind.

use super::report::{Certainty, EeContact, EeGeometry};

/// A point (a vertex in no triangle and no edge) and an edge that (may) touch during the step.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct VeContact {
    /// The point's vertex index.
    pub vertex: u32,
    /// The edge, `[i, j]` with `i < j`.
    pub edge: [u32; 2],
    /// Time of impact in `[0, tmax]`, no later than the first contact.
    pub toi: f64,
    /// Whether the contact was isolated or the search gave up conservatively.
    pub certainty: Certainty,
    /// Where the contact is, with [`QueryOptions::geometry`](crate::QueryOptions::geometry):
    /// as for two edges, the point being edge `a` of length zero (`a_param` is then 0) and the
    /// edge edge `b`.
    pub geometry: Option<EeGeometry>,
}

/// Which kind of contact the driver's edge-edge contact `c` is: `Some` with the vertex-edge
/// contact when exactly one of its edges has length zero (a point).
pub(crate) fn from_edge_edge(c: &EeContact) -> Option<VeContact> {
    let point = |e: [u32; 2]| e[0] == e[1];
    let (vertex, edge, flip) = match (point(c.a), point(c.b)) {
        (true, false) => (c.a[0], c.b, false),
        (false, true) => (c.b[0], c.a, true),
        _ => return None,
    };
    let geometry = c.geometry.map(|g| {
        if flip {
            EeGeometry {
                a_param: g.b_param,
                b_param: g.a_param,
                normal: g.normal.map(|x| -x),
                ..g
            }
        } else {
            g
        }
    });
    Some(VeContact {
        vertex,
        edge,
        toi: c.toi,
        certainty: c.certainty,
        geometry,
    })
}
