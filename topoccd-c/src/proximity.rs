//! `topoccd_proximity`: the primitive pairs of one configuration closer than `dhat`, on a
//! `topoccd_ccd` (which keeps the proximity hierarchy and refits it across a solver's
//! iterations), with the report's arrays owned by the `topoccd_ccd`.

use std::time::{Duration, Instant};

use topoccd::{Configuration, ProximityError, ProximityOptions, ProximityReport, StopReason};

use crate::ccd::{run_on, topoccd_ccd, with_state};
use crate::status::{topoccd_status, Failure};
use crate::step::rows;

/// One configuration: positions, triangles, free edges (rods, hair) and optional groups,
/// borrowed for the call. Vertices in no triangle and no edge are free points.
///
/// ```c
/// topoccd_configuration config = {0};
/// config.x = x; config.vertex_count = 4;
/// config.triangles = triangles; config.triangle_count = 1;
/// ```
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct topoccd_configuration {
    /// Positions: `vertex_count` rows of 3 doubles.
    pub x: *const f64,
    /// Number of vertices.
    pub vertex_count: usize,
    /// Triangles: `triangle_count` rows of 3 vertex indices.
    pub triangles: *const u32,
    /// Number of triangles.
    pub triangle_count: usize,
    /// NULL, or `edge_count` rows of 2 vertex indices: free edges (an edge of a triangle
    /// given here counts once).
    pub edges: *const u32,
    /// Number of free edges.
    pub edge_count: usize,
    /// NULL, or one group id per vertex: features whose vertices all share one group are not
    /// paired.
    pub groups: *const u32,
    /// Number of group ids (`vertex_count` when `groups` is not NULL).
    pub group_count: usize,
}

/// The options of `topoccd_proximity`. `topoccd_proximity_options_default()` gives the
/// defaults.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct topoccd_proximity_options {
    /// The distance threshold, finite, > 0. Default 1e-3.
    pub dhat: f64,
    /// The minimum distance offset, finite, >= 0: pairs closer than `dhat + dmin` are
    /// reported. Default 0.
    pub dmin: f64,
    /// Most pairs the report keeps; 0 for no cap (`truncated` says when it cut). Default
    /// 1,000,000 (the Rust and Python default, as for `topoccd_query_options`), so that a
    /// collapsed configuration's n² pairs stay bounded. While a query stays under the cap, the
    /// pairs kept across a solver's iterations are reused.
    pub max_contacts: u64,
    /// Seconds the query may run; 0 for no limit. Default 0.
    pub timeout: f64,
    /// Threads: 0 for one per core, else a count in [1, 4096]. Default 0.
    pub threads: u32,
}

/// The proximity options' defaults.
#[no_mangle]
pub extern "C" fn topoccd_proximity_options_default() -> topoccd_proximity_options {
    let d = ProximityOptions::default();
    topoccd_proximity_options {
        dhat: d.dhat,
        dmin: d.dmin,
        max_contacts: d.max_contacts.map_or(0, |n| n as u64),
        timeout: 0.0,
        threads: 0,
    }
}

/// A vertex closer than the threshold to a triangle. `type` is ipctk's
/// `PointTriangleDistanceType`: 0-2 a corner, 3-5 an edge (edge k from corner k to k+1),
/// 6 the interior.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct topoccd_vf_proximity {
    /// The vertex.
    pub vertex: u32,
    /// The triangle.
    pub face: u32,
    /// The distance (not squared).
    pub distance: f64,
    /// The triangle's closest feature.
    pub r#type: u32,
}

/// Two edges closer than the threshold, each `[i, j]` with `i < j`, `a < b`. `type` is
/// ipctk's `EdgeEdgeDistanceType`, 0 (`EA0_EB0`) to 8 (`EA_EB`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct topoccd_ee_proximity {
    /// The first edge.
    pub a: [u32; 2],
    /// The second edge.
    pub b: [u32; 2],
    /// The distance (not squared).
    pub distance: f64,
    /// The closest features.
    pub r#type: u32,
}

/// A free point closer than the threshold to an edge. `type`: 0 `P_E0`, 1 `P_E1`, 2 `P_E`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct topoccd_ve_proximity {
    /// The free point.
    pub vertex: u32,
    /// The edge, `[i, j]` with `i < j`.
    pub edge: [u32; 2],
    /// The distance (not squared).
    pub distance: f64,
    /// The edge's closest feature.
    pub r#type: u32,
}

/// Two free points closer than the threshold, `a < b`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct topoccd_vv_proximity {
    /// The first point.
    pub a: u32,
    /// The second point.
    pub b: u32,
    /// The distance (not squared).
    pub distance: f64,
}

/// The pairs of the last `topoccd_proximity` call, each kind sorted by its indices, owned by
/// the `topoccd_ccd` until its next proximity call.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct topoccd_proximity_report {
    /// Vertex-face pairs.
    pub vf: *const topoccd_vf_proximity,
    /// Their number.
    pub vf_count: usize,
    /// Edge-edge pairs.
    pub ee: *const topoccd_ee_proximity,
    /// Their number.
    pub ee_count: usize,
    /// Free point-free edge pairs.
    pub ve: *const topoccd_ve_proximity,
    /// Their number.
    pub ve_count: usize,
    /// Free point-free point pairs.
    pub vv: *const topoccd_vv_proximity,
    /// Their number.
    pub vv_count: usize,
    /// Whether `max_contacts` cut the report.
    pub truncated: bool,
    /// Whether the hierarchy was refitted (the same primitives as the last call) rather than
    /// built.
    pub refitted: bool,
}

/// The arrays behind a `topoccd_proximity_report`, reused from call to call.
#[derive(Debug, Default)]
pub(crate) struct ProximityBuffers {
    vf: Vec<topoccd_vf_proximity>,
    ee: Vec<topoccd_ee_proximity>,
    ve: Vec<topoccd_ve_proximity>,
    vv: Vec<topoccd_vv_proximity>,
    view: Option<topoccd_proximity_report>,
}

// The view points into the buffers, which only the owning `topoccd_ccd` (behind its lock)
// touches.
unsafe impl Send for ProximityBuffers {}

impl ProximityBuffers {
    fn fill(&mut self, r: &ProximityReport) -> &topoccd_proximity_report {
        self.vf.clear();
        self.vf.extend(r.vf.iter().map(|p| topoccd_vf_proximity {
            vertex: p.vertex,
            face: p.face,
            distance: p.distance,
            r#type: p.kind as u32,
        }));
        self.ee.clear();
        self.ee.extend(r.ee.iter().map(|p| topoccd_ee_proximity {
            a: p.a,
            b: p.b,
            distance: p.distance,
            r#type: p.kind as u32,
        }));
        self.ve.clear();
        self.ve.extend(r.ve.iter().map(|p| topoccd_ve_proximity {
            vertex: p.vertex,
            edge: p.edge,
            distance: p.distance,
            r#type: p.kind as u32,
        }));
        self.vv.clear();
        self.vv.extend(r.vv.iter().map(|p| topoccd_vv_proximity {
            a: p.a,
            b: p.b,
            distance: p.distance,
        }));
        self.view.insert(topoccd_proximity_report {
            vf: self.vf.as_ptr(),
            vf_count: self.vf.len(),
            ee: self.ee.as_ptr(),
            ee_count: self.ee.len(),
            ve: self.ve.as_ptr(),
            ve_count: self.ve.len(),
            vv: self.vv.as_ptr(),
            vv_count: self.vv.len(),
            truncated: r.truncated == Some(StopReason::MaxContacts),
            refitted: r.stats.refitted,
        })
    }
}

/// The `topoccd::Configuration` of a `topoccd_configuration`, borrowing its arrays.
///
/// # Safety
/// The arrays of `c` are NULL or valid for reads of their counts' rows during `'a`.
pub(crate) unsafe fn configuration<'a>(
    c: &topoccd_configuration,
) -> Result<Configuration<'a>, Failure> {
    let x = rows::<f64, 3>(c.x, c.vertex_count, "x")?;
    let tris = rows::<u32, 3>(c.triangles, c.triangle_count, "triangles")?;
    let edges = rows::<u32, 2>(c.edges, c.edge_count, "edges")?;
    let groups = if c.groups.is_null() {
        None
    } else {
        Some(rows::<u32, 1>(c.groups, c.group_count, "groups")?)
    };
    let configuration = Configuration::new(x, tris, edges).map_err(failure)?;
    match groups.map(|g| g.as_flattened()) {
        Some(g) => configuration.with_groups(g).map_err(failure),
        None => Ok(configuration),
    }
}

pub(crate) fn failure(e: ProximityError) -> Failure {
    let status = match e {
        ProximityError::Dhat(_) | ProximityError::Dmin(_) => topoccd_status::InvalidOptions,
        ProximityError::OutOfMemory { .. } => topoccd_status::OutOfMemory,
        _ => topoccd_status::InvalidStep,
    };
    Failure::new(status, e.to_string())
}

/// Every primitive pair of `config` closer than `dhat + dmin`: vertex-face, edge-edge
/// (triangles' edges and free edges), free point-free edge and free point-free point, with their
/// distances and closest-feature types; `*report` receives a pointer to them, valid until the
/// next `topoccd_proximity` on `ccd` or `topoccd_ccd_free`. `options` may be NULL for the
/// defaults. Features sharing a vertex are not paired; groups apply. No pair closer than the
/// threshold is missed; a pair beyond it is reported only within a rounding bound (about 1e-14
/// times the pair's size). The `ccd` keeps the hierarchy: called again with the same
/// triangles and edges, it refits it.
///
/// Returns `TOPOCCD_STATUS_OK`, or `TOPOCCD_STATUS_NULL_POINTER`,
/// `TOPOCCD_STATUS_INVALID_HANDLE`, `TOPOCCD_STATUS_BUSY`, `TOPOCCD_STATUS_INVALID_OPTIONS`
/// (the message names the option), `TOPOCCD_STATUS_INVALID_STEP` (the message names the
/// element: `edge 2 names vertex 9, but there are only 4 vertices`), or
/// `TOPOCCD_STATUS_INVALID_ARGUMENT` after `timeout` (a deadline, not an error of the input:
/// the message says how many pairs were found by then).
///
/// ```c
/// /* A vertex (3) 0.5e-3 above a triangle. */
/// const double x[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.2, 0.5e-3};
/// const uint32_t triangles[] = {0, 1, 2};
/// topoccd_configuration config = {0};
/// config.x = x; config.vertex_count = 4;
/// config.triangles = triangles; config.triangle_count = 1;
/// topoccd_proximity_options options = topoccd_proximity_options_default();
/// const topoccd_proximity_report *r = NULL;
/// topoccd_proximity(ccd, &config, &options, &r);
/// /* r->vf_count == 1, r->vf[0].vertex == 3, r->vf[0].type == 6 (the interior) */
/// ```
///
/// # Safety
/// `ccd` is NULL or a `topoccd_ccd` this library returned; `config` is NULL or points to a
/// `topoccd_configuration` whose arrays are NULL or valid for reads of their counts' rows;
/// `options` is NULL or points to options; `report` is NULL or valid for a write of a pointer.
#[no_mangle]
pub unsafe extern "C" fn topoccd_proximity(
    ccd: *mut topoccd_ccd,
    config: *const topoccd_configuration,
    options: *const topoccd_proximity_options,
    report: *mut *const topoccd_proximity_report,
) -> topoccd_status {
    let started = Instant::now();
    with_state(ccd, |state| {
        if config.is_null() {
            return Err(Failure::null("config"));
        }
        if report.is_null() {
            return Err(Failure::null("report"));
        }
        let c = &*config;
        let o = if options.is_null() {
            topoccd_proximity_options_default()
        } else {
            *options
        };
        if !(o.timeout.is_finite() && o.timeout >= 0.0) {
            return Err(Failure::new(
                topoccd_status::InvalidOptions,
                format!("timeout must be finite and >= 0 seconds, got {}", o.timeout),
            ));
        }
        if o.threads > 4096 {
            return Err(Failure::new(
                topoccd_status::InvalidOptions,
                format!("threads must be 0 or in [1, 4096], got {}", o.threads),
            ));
        }
        let options = ProximityOptions {
            dhat: o.dhat,
            dmin: o.dmin,
            max_contacts: (o.max_contacts > 0).then_some(o.max_contacts as usize),
            deadline: (o.timeout > 0.0).then(|| started + Duration::from_secs_f64(o.timeout)),
            ..ProximityOptions::default()
        };
        options.validate().map_err(failure)?;
        let configuration = configuration(c)?;
        let found = run_on(state, o.threads as usize, |ccd| {
            ccd.proximity(&configuration, &options)
        })?
        .map_err(failure)?;
        if matches!(
            found.truncated,
            Some(StopReason::Deadline | StopReason::Cancelled)
        ) {
            return Err(Failure::new(
                topoccd_status::InvalidArgument,
                format!(
                    "the proximity query did not finish within timeout={} s (found {} pairs by then)",
                    o.timeout,
                    found.len()
                ),
            ));
        }
        *report = state.proximity.fill(&found);
        Ok(())
    })
}
