//! The report of a query as C reads it: contacts in arrays of C structs that the `topoccd_ccd`
//! owns and reuses from query to query, read in place.

use topoccd::{
    Certainty, ClusterFigures, Contact, EeContact, EeGeometry, Report, Seconds, Stats, StopReason,
    VeContact, VfContact, VvContact,
};

use crate::options::method_code;

/// How sure a contact is.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum topoccd_certainty {
    /// The search isolated the contact: the features come within the documented distance of
    /// each other at a time in `[toi, toi + tolerance]`.
    Resolved = 0,
    /// The iteration budget ran out first: `toi` is only a lower bound of the first contact
    /// (the features may not touch at all), on the safe side.
    IterationLimit = 1,
    /// A coordinate was NaN or infinite, or coordinates so far apart that their differences
    /// exceed 1e300: nothing could be decided, and the answer is a contact at time 0.
    InvalidInput = 2,
}

impl From<Certainty> for topoccd_certainty {
    fn from(c: Certainty) -> Self {
        match c {
            Certainty::Resolved => Self::Resolved,
            Certainty::IterationLimit => Self::IterationLimit,
            Certainty::InvalidInput => Self::InvalidInput,
        }
    }
}

/// Which kind of contact is the earliest.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum topoccd_contact_kind {
    /// Nothing collides.
    None = 0,
    /// A vertex-face contact.
    Vf = 1,
    /// An edge-edge contact.
    Ee = 2,
    /// A contact of a free point with a free edge (`ve`).
    Ve = 3,
    /// A contact of two free points (`vv`).
    Vv = 4,
}

/// Where a vertex-face contact is, at its time of impact.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct topoccd_vf_geometry {
    /// Barycentric coordinates, on the face's three vertices, of the face's point closest to
    /// the vertex (they sum to 1).
    pub barycentric: [f64; 3],
    /// That point.
    pub point: [f64; 3],
    /// Unit contact normal, from the face towards the side the vertex comes from.
    pub normal: [f64; 3],
    /// Distance between the vertex and the face.
    pub distance: f64,
}

/// Where an edge-edge contact is, at its time of impact.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct topoccd_ee_geometry {
    /// Parameter in [0, 1] of the closest point on edge `a`, from `a[0]` to `a[1]`.
    pub a_param: f64,
    /// Parameter in [0, 1] of the closest point on edge `b`, from `b[0]` to `b[1]`.
    pub b_param: f64,
    /// The midpoint of the two closest points.
    pub point: [f64; 3],
    /// Unit contact normal, from edge `b` towards edge `a`.
    pub normal: [f64; 3],
    /// Distance between the edges.
    pub distance: f64,
}

/// A vertex that (may) touch a triangle during the step.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct topoccd_vf_contact {
    /// The vertex.
    pub vertex: u32,
    /// The triangle's index in the step's triangles.
    pub face: u32,
    /// Time of impact in [0, tmax], never later than the first contact.
    pub toi: f64,
    /// A `topoccd_certainty`.
    pub certainty: topoccd_certainty,
    /// Whether `geometry` holds the contact's geometry (with the option `geometry`); else it
    /// is zero.
    pub has_geometry: bool,
    /// The contact's geometry.
    pub geometry: topoccd_vf_geometry,
}

/// Two edges that (may) touch during the step. Each edge is `[i, j]` with `i < j`, and
/// `a < b` lexicographically.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct topoccd_ee_contact {
    /// The first edge, by vertex indices.
    pub a: [u32; 2],
    /// The second edge.
    pub b: [u32; 2],
    /// Time of impact in [0, tmax], never later than the first contact.
    pub toi: f64,
    /// A `topoccd_certainty`.
    pub certainty: topoccd_certainty,
    /// Whether `geometry` holds the contact's geometry (with the option `geometry`); else it
    /// is zero.
    pub has_geometry: bool,
    /// The contact's geometry.
    pub geometry: topoccd_ee_geometry,
}

/// A free point (a vertex in no triangle and no edge) and a free edge that (may) touch during
/// the step (codimensional geometry: the step's `edges`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct topoccd_ve_contact {
    /// The point's vertex.
    pub vertex: u32,
    /// The edge, `[i, j]` with `i < j`.
    pub edge: [u32; 2],
    /// Time of impact in [0, tmax], never later than the first contact.
    pub toi: f64,
    /// A `topoccd_certainty`.
    pub certainty: topoccd_certainty,
    /// Whether `geometry` holds the contact's geometry (with the option `geometry`); else it
    /// is zero.
    pub has_geometry: bool,
    /// The contact's geometry, as for two edges: the point is edge `a` of length zero
    /// (`a_param` 0), the edge is edge `b`.
    pub geometry: topoccd_ee_geometry,
}

/// Two free points that (may) touch during the step (codimensional geometry).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct topoccd_vv_contact {
    /// The smaller vertex index.
    pub a: u32,
    /// The larger one.
    pub b: u32,
    /// Time of impact in [0, tmax], never later than the first contact.
    pub toi: f64,
    /// A `topoccd_certainty`.
    pub certainty: topoccd_certainty,
    /// Whether `geometry` holds the contact's geometry (with the option `geometry`); else it
    /// is zero.
    pub has_geometry: bool,
    /// The contact's geometry, as for two edges of length zero (both parameters 0, the normal
    /// from `b` to `a`).
    pub geometry: topoccd_ee_geometry,
}

/// Wall-clock seconds of each phase of a query.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct topoccd_seconds {
    /// Topology, features, swept volumes and the hierarchy (or the oracle's sort).
    pub build: f64,
    /// Traversal down to the candidate pairs (with the elementary tests, for the hierarchies).
    pub traverse: f64,
    /// The elementary tests (for the hierarchies, only the final sort and selection).
    pub narrow: f64,
    /// The whole query.
    pub total: f64,
    /// `TOPOCCD_METHOD_CLUSTER` only, else NaN: growing the leaf clusters.
    pub clustering: f64,
    /// `TOPOCCD_METHOD_CLUSTER` only, else NaN: merging them into intermediate clusters.
    pub merging: f64,
}

/// The clusters of `TOPOCCD_METHOD_CLUSTER` (see the Rust `ClusterFigures`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct topoccd_cluster_figures {
    /// Leaf clusters.
    pub leaf: u64,
    /// Intermediate clusters.
    pub intermediate: u64,
    /// Average triangles per leaf cluster.
    pub triangles_per_leaf: f64,
    /// Average triangles per intermediate cluster.
    pub triangles_per_intermediate: f64,
    /// Hierarchies built over a leaf cluster's triangles.
    pub lazy_bvhs: u64,
    /// Overlapping pairs of leaf clusters in different intermediate clusters.
    pub leaf_pairs: u64,
    /// Leaf clusters without certificate (always 0 with this library's clustering).
    pub uncertified_leaves: u64,
    /// Leaf clusters carried over from the last step (same triangles) and certified anew.
    pub reused_leaves: u64,
    /// Seconds spent growing the leaf clusters.
    pub clustering_seconds: f64,
    /// Seconds spent merging them.
    pub merging_seconds: f64,
}

/// Work counters of a query.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct topoccd_stats {
    /// The `topoccd_method` that ran (what `TOPOCCD_METHOD_AUTO` chose).
    pub method: u32,
    /// Bounding-volume overlap tests.
    pub bv_tests: u64,
    /// Vertex-face pairs given to the narrow phase.
    pub vf_tests: u64,
    /// Edge-edge pairs given to the narrow phase.
    pub ee_tests: u64,
    /// The most candidate pairs held in one buffer at once.
    pub peak_candidates: u64,
    /// Time of each phase.
    pub seconds: topoccd_seconds,
    /// Whether `cluster` holds the cluster method's figures; else it is zero.
    pub has_cluster: bool,
    /// The cluster method's figures.
    pub cluster: topoccd_cluster_figures,
}

/// The result of the last query of a `topoccd_ccd`, read in place: its arrays belong to the
/// `topoccd_ccd` and stay valid, unchanged, until its next query or `topoccd_ccd_free`. Before
/// the first query, and after a query that failed, it is empty.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct topoccd_report {
    /// Colliding vertex-face pairs, sorted by `(vertex, face)`; with `TOPOCCD_MODE_EARLIEST`,
    /// those within the tolerance of the earliest time. Valid for `vf_count` elements.
    pub vf: *const topoccd_vf_contact,
    /// Number of vertex-face contacts.
    pub vf_count: usize,
    /// Colliding edge-edge pairs, sorted by `(a, b)`; with `TOPOCCD_MODE_EARLIEST`, those within
    /// the tolerance of the earliest time. Valid for `ee_count` elements.
    pub ee: *const topoccd_ee_contact,
    /// Number of edge-edge contacts.
    pub ee_count: usize,
    /// A `topoccd_contact_kind`: which array holds the earliest contact, or
    /// `TOPOCCD_CONTACT_KIND_NONE` when nothing collides.
    pub earliest_kind: topoccd_contact_kind,
    /// The earliest contact's index in `vf`, `ee`, `ve` or `vv` (by `earliest_kind`); 0 when
    /// none.
    pub earliest_index: usize,
    /// The earliest time of impact; NaN when nothing collides.
    pub earliest_toi: f64,
    /// Reported contacts whose certainty is not `TOPOCCD_CERTAINTY_RESOLVED`: check it before
    /// trusting a time of impact of 0.
    pub unresolved: usize,
    /// Work counters and timings.
    pub stats: topoccd_stats,
    /// A `topoccd_stop_reason`: `TOPOCCD_STOP_REASON_NONE` for a complete report, else why the
    /// query stopped early (`max_contacts`, `timeout`), and the report holds only part
    /// of the step's contacts.
    pub truncated: topoccd_stop_reason,
    /// Whether the report lists every pair within the tolerance of the earliest time (every
    /// contact in `TOPOCCD_MODE_ALL`): false when truncated, or when `TOPOCCD_MODE_EARLIEST`
    /// found more such pairs than `max_contacts` and kept the earliest of them (the earliest
    /// time is exact either way).
    pub earliest_complete: bool,
    /// Colliding pairs of a free point and a free edge (a step with `edges`), sorted by
    /// `(vertex, edge)`. Valid for `ve_count` elements.
    pub ve: *const topoccd_ve_contact,
    /// Number of vertex-edge contacts.
    pub ve_count: usize,
    /// Colliding pairs of two free points, sorted by `(a, b)`. Valid for `vv_count` elements.
    pub vv: *const topoccd_vv_contact,
    /// Number of vertex-vertex contacts.
    pub vv_count: usize,
}

/// Why a query stopped before the end ([`topoccd_report::truncated`]).
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum topoccd_stop_reason {
    /// The report is complete.
    None = 0,
    /// The report holds `max_contacts` contacts and the step has more.
    MaxContacts = 1,
    /// `timeout` passed.
    Deadline = 2,
    /// The query was cancelled.
    Cancelled = 3,
}

/// The report's arrays, kept by a `topoccd_ccd` and refilled by each query, and the C view of
/// them.
#[derive(Debug)]
pub(crate) struct ReportBuffers {
    vf: Vec<topoccd_vf_contact>,
    ee: Vec<topoccd_ee_contact>,
    ve: Vec<topoccd_ve_contact>,
    vv: Vec<topoccd_vv_contact>,
    /// Points into `vf`, `ee`, `ve` and `vv`: rebuilt whenever they change.
    view: topoccd_report,
}

// SAFETY: the only pointers of `ReportBuffers` are those of `view`, into its own vectors; the
// buffers move between threads with them.
unsafe impl Send for ReportBuffers {}

impl Default for ReportBuffers {
    fn default() -> Self {
        let mut buffers = Self {
            vf: Vec::new(),
            ee: Vec::new(),
            ve: Vec::new(),
            vv: Vec::new(),
            view: empty_view(),
        };
        buffers.clear();
        buffers
    }
}

fn empty_view() -> topoccd_report {
    topoccd_report {
        vf: std::ptr::null(),
        vf_count: 0,
        ee: std::ptr::null(),
        ee_count: 0,
        earliest_kind: topoccd_contact_kind::None,
        earliest_index: 0,
        earliest_toi: f64::NAN,
        unresolved: 0,
        stats: topoccd_stats::default(),
        truncated: topoccd_stop_reason::None,
        earliest_complete: false,
        ve: std::ptr::null(),
        ve_count: 0,
        vv: std::ptr::null(),
        vv_count: 0,
    }
}

fn vf_contact(c: &VfContact) -> topoccd_vf_contact {
    let g = c.geometry.map(|g| topoccd_vf_geometry {
        barycentric: g.barycentric,
        point: g.point,
        normal: g.normal,
        distance: g.distance,
    });
    topoccd_vf_contact {
        vertex: c.vertex,
        face: c.face,
        toi: c.toi,
        certainty: c.certainty.into(),
        has_geometry: g.is_some(),
        geometry: g.unwrap_or_default(),
    }
}

fn ee_geometry(g: EeGeometry) -> topoccd_ee_geometry {
    topoccd_ee_geometry {
        a_param: g.a_param,
        b_param: g.b_param,
        point: g.point,
        normal: g.normal,
        distance: g.distance,
    }
}

fn ee_contact(c: &EeContact) -> topoccd_ee_contact {
    let g = c.geometry.map(ee_geometry);
    topoccd_ee_contact {
        a: c.a,
        b: c.b,
        toi: c.toi,
        certainty: c.certainty.into(),
        has_geometry: g.is_some(),
        geometry: g.unwrap_or_default(),
    }
}

fn ve_contact(c: &VeContact) -> topoccd_ve_contact {
    let g = c.geometry.map(ee_geometry);
    topoccd_ve_contact {
        vertex: c.vertex,
        edge: c.edge,
        toi: c.toi,
        certainty: c.certainty.into(),
        has_geometry: g.is_some(),
        geometry: g.unwrap_or_default(),
    }
}

fn vv_contact(c: &VvContact) -> topoccd_vv_contact {
    let g = c.geometry.map(ee_geometry);
    topoccd_vv_contact {
        a: c.a,
        b: c.b,
        toi: c.toi,
        certainty: c.certainty.into(),
        has_geometry: g.is_some(),
        geometry: g.unwrap_or_default(),
    }
}

fn seconds(s: &Seconds) -> topoccd_seconds {
    topoccd_seconds {
        build: s.build,
        traverse: s.traverse,
        narrow: s.narrow,
        total: s.total,
        clustering: s.clustering.unwrap_or(f64::NAN),
        merging: s.merging.unwrap_or(f64::NAN),
    }
}

fn cluster(c: &ClusterFigures) -> topoccd_cluster_figures {
    topoccd_cluster_figures {
        leaf: c.leaf as u64,
        intermediate: c.intermediate as u64,
        triangles_per_leaf: c.triangles_per_leaf,
        triangles_per_intermediate: c.triangles_per_intermediate,
        lazy_bvhs: c.lazy_bvhs as u64,
        leaf_pairs: c.leaf_pairs,
        uncertified_leaves: c.uncertified_leaves as u64,
        reused_leaves: c.reused_leaves as u64,
        clustering_seconds: c.clustering_seconds,
        merging_seconds: c.merging_seconds,
    }
}

fn stats(s: &Stats) -> topoccd_stats {
    topoccd_stats {
        method: method_code(s.method),
        bv_tests: s.bv_tests,
        vf_tests: s.vf_tests,
        ee_tests: s.ee_tests,
        peak_candidates: s.peak_candidates,
        seconds: seconds(&s.seconds),
        has_cluster: s.cluster.is_some(),
        cluster: s.cluster.as_ref().map(cluster).unwrap_or_default(),
    }
}

impl ReportBuffers {
    /// Empties the report (before a query, so that a failed query leaves nothing stale).
    pub fn clear(&mut self) {
        self.vf.clear();
        self.ee.clear();
        self.ve.clear();
        self.vv.clear();
        self.view = topoccd_report {
            vf: self.vf.as_ptr(),
            ee: self.ee.as_ptr(),
            ve: self.ve.as_ptr(),
            vv: self.vv.as_ptr(),
            ..empty_view()
        };
    }

    /// Fills the buffers from a report, reusing their memory.
    pub fn fill(&mut self, report: &Report) {
        self.clear();
        self.vf.extend(report.vf.iter().map(vf_contact));
        self.ee.extend(report.ee.iter().map(ee_contact));
        self.ve.extend(report.ve.iter().map(ve_contact));
        self.vv.extend(report.vv.iter().map(vv_contact));
        // The earliest contact is one of the reported ones (the library picks it among them,
        // and Earliest keeps those within the tolerance of it): its index in its array, which
        // is sorted by pair, each pair once.
        let (kind, found) = match &report.earliest {
            None => (topoccd_contact_kind::None, Ok(0)),
            Some(Contact::Vf(c)) => (
                topoccd_contact_kind::Vf,
                report
                    .vf
                    .binary_search_by(|x| (x.vertex, x.face).cmp(&(c.vertex, c.face))),
            ),
            Some(Contact::Ee(c)) => (
                topoccd_contact_kind::Ee,
                report.ee.binary_search_by(|x| (x.a, x.b).cmp(&(c.a, c.b))),
            ),
            Some(Contact::Ve(c)) => (
                topoccd_contact_kind::Ve,
                report
                    .ve
                    .binary_search_by(|x| (x.vertex, x.edge).cmp(&(c.vertex, c.edge))),
            ),
            Some(Contact::Vv(c)) => (
                topoccd_contact_kind::Vv,
                report.vv.binary_search_by(|x| (x.a, x.b).cmp(&(c.a, c.b))),
            ),
        };
        debug_assert!(found.is_ok(), "the earliest contact is not in the report");
        self.view = topoccd_report {
            vf: self.vf.as_ptr(),
            vf_count: self.vf.len(),
            ee: self.ee.as_ptr(),
            ee_count: self.ee.len(),
            earliest_kind: kind,
            earliest_index: found.unwrap_or_else(|i| i),
            earliest_toi: report.earliest_toi().unwrap_or(f64::NAN),
            unresolved: report.unresolved,
            stats: stats(&report.stats),
            truncated: match report.truncated.map(|t| t.reason) {
                None => topoccd_stop_reason::None,
                Some(StopReason::MaxContacts) => topoccd_stop_reason::MaxContacts,
                Some(StopReason::Deadline) => topoccd_stop_reason::Deadline,
                Some(StopReason::Cancelled) => topoccd_stop_reason::Cancelled,
            },
            earliest_complete: report.earliest_complete,
            ve: self.ve.as_ptr(),
            ve_count: self.ve.len(),
            vv: self.vv.as_ptr(),
            vv_count: self.vv.len(),
        };
    }

    /// The C view of the buffers, valid while they are not changed.
    pub fn view(&self) -> &topoccd_report {
        &self.view
    }
}
