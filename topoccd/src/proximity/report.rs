//! The result of a proximity query: the pairs of each kind with their distance and
//! closest-feature type, in a fixed order.

use crate::distance::{EdgeEdgeType, PointEdgeType, PointTriangleType};
use crate::query::StopReason;

/// A vertex closer than the threshold to a triangle it is not a corner of.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct VfProximity {
    /// The vertex.
    pub vertex: u32,
    /// The triangle's index.
    pub face: u32,
    /// The distance (not squared).
    pub distance: f64,
    /// The triangle's feature closest to the vertex.
    pub kind: PointTriangleType,
}

/// Two edges, sharing no vertex, closer than the threshold. As in the CCD report, each edge is
/// `[i, j]` with `i < j` and `a < b` lexicographically; the type's `a` and `b` are these.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct EeProximity {
    /// The first edge.
    pub a: [u32; 2],
    /// The second edge.
    pub b: [u32; 2],
    /// The distance (not squared).
    pub distance: f64,
    /// The closest features of the two edges.
    pub kind: EdgeEdgeType,
}

/// A free point (in no triangle and no edge) closer than the threshold to a free edge (in no
/// triangle). A free point near a triangle's edge is near the triangle: a vertex-face pair.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct VeProximity {
    /// The free point.
    pub vertex: u32,
    /// The edge, `[i, j]` with `i < j`.
    pub edge: [u32; 2],
    /// The distance (not squared).
    pub distance: f64,
    /// The edge's feature closest to the point.
    pub kind: PointEdgeType,
}

/// Two free points closer than the threshold, `a < b`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct VvProximity {
    /// The first point.
    pub a: u32,
    /// The second point.
    pub b: u32,
    /// The distance (not squared).
    pub distance: f64,
}

/// Figures of one proximity query.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ProximityStats {
    /// Whether the hierarchy was refitted (the primitives of the last query again) rather
    /// than built.
    pub refitted: bool,
    /// Whether the query evaluated the candidates a former query of the same `Ccd` kept
    /// (the positions had moved less than its margin) rather than traversing the hierarchy.
    pub reused: bool,
    /// Bounding-volume overlap tests.
    pub bv_tests: u64,
    /// Feature pairs whose distance was computed.
    pub distance_tests: u64,
    /// Seconds spent on the primitives and the hierarchy.
    pub build_seconds: f64,
    /// Seconds spent on the traversal and the distances.
    pub traverse_seconds: f64,
    /// Seconds in all.
    pub total_seconds: f64,
}

/// The pairs closer than `dhat + dmin`, each kind sorted by its indices (`vf` by vertex then
/// face, `ee` by `a` then `b`, `ve` by vertex then edge, `vv` by `a` then `b`): the same for
/// any thread count and either method.
#[derive(Clone, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ProximityReport {
    /// Vertex-face pairs: every vertex against every triangle it is not a corner of.
    pub vf: Vec<VfProximity>,
    /// Edge-edge pairs: every edge (of a triangle, or free) against every edge sharing no
    /// vertex with it.
    pub ee: Vec<EeProximity>,
    /// Free point against free edge pairs.
    pub ve: Vec<VeProximity>,
    /// Free point against free point pairs.
    pub vv: Vec<VvProximity>,
    /// Why the query stopped early, if it did.
    pub truncated: Option<StopReason>,
    /// Figures.
    pub stats: ProximityStats,
}

impl ProximityReport {
    /// The number of pairs of all kinds.
    pub fn len(&self) -> usize {
        self.vf.len() + self.ee.len() + self.ve.len() + self.vv.len()
    }

    /// Whether no pair is reported.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Sorts each kind into the report's order.
    /// (Each key is the indices packed into one integer, most significant first: the same
    /// order as the tuple of indices, compared in one instruction or two.)
    pub(crate) fn sort(&mut self) {
        let pack = |v: &[u32]| v.iter().fold(0u128, |k, &i| (k << 32) | u128::from(i));
        self.vf
            .sort_unstable_by_key(|p| (u64::from(p.vertex) << 32) | u64::from(p.face));
        self.ee
            .sort_unstable_by_key(|p| pack(&[p.a[0], p.a[1], p.b[0], p.b[1]]));
        self.ve
            .sort_unstable_by_key(|p| pack(&[p.vertex, p.edge[0], p.edge[1]]));
        self.vv
            .sort_unstable_by_key(|p| (u64::from(p.a) << 32) | u64::from(p.b));
    }

    /// Keeps the first `n` pairs: `vf` first, then `ee`, `ve`, `vv`.
    pub(crate) fn truncate(&mut self, mut n: usize) {
        let mut cut = |len: usize| {
            let keep = len.min(n);
            n -= keep;
            keep
        };
        let k = cut(self.vf.len());
        self.vf.truncate(k);
        let k = cut(self.ee.len());
        self.ee.truncate(k);
        let k = cut(self.ve.len());
        self.ve.truncate(k);
        let k = cut(self.vv.len());
        self.vv.truncate(k);
    }
}
