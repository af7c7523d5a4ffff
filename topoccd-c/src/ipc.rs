//! The contact potential of incremental potential contact (IPC), in C: `topoccd_collisions`
//! (the normal collision set, built on a `topoccd_ccd`), the barrier potential's energy,
//! gradient and Hessian (a `topoccd_sparse` in CSR), the stiffness helpers and the minimum
//! distance, in the conventions of the IPC toolkit (ipctk) 1.6.1.
//!
//! Positions are rows of 3 doubles; gradients have `3 n` entries `x0 y0 z0 x1 ...` and
//! Hessians are `3 n x 3 n` (ipctk's layout).

use topoccd::ipc::{
    self, Barrier, BarrierPotential, CollisionOptions, CollisionSetType, IpcError,
    NormalCollisions, PsdProjection,
};

use crate::ccd::{topoccd_ccd, with_state};
use crate::error::{deliver, topoccd_error};
use crate::handle::{self, Kind};
use crate::outputs;
use crate::proximity::{configuration, failure, topoccd_configuration};
use crate::sparse::topoccd_sparse;
use crate::status::{chain, guard, topoccd_status, Failure};
use crate::step::rows;

/// How the collision set is built (ipctk's `CollisionSetType`).
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum topoccd_collision_set_type {
    /// The original IPC set (ipctk's `IPC`, the default).
    Ipc = 0,
    /// ipctk's `IMPROVED_MAX_APPROX`: the plain set with the corrections of the improved max
    /// approximation, so a contact seen by several pairs counts once.
    ImprovedMaxApprox = 1,
}

/// How a collision's Hessian is made positive semi-definite before it is added (ipctk's
/// `PSDProjectionMethod`).
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum topoccd_psd_projection {
    /// No projection.
    None = 0,
    /// Negative eigenvalues set to 0.
    Clamp = 1,
    /// Negative eigenvalues replaced by their absolute values.
    Abs = 2,
}

/// A barrier function (ipctk's barrier classes).
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum topoccd_barrier {
    /// `-(d - dhat)^2 ln(d / dhat)` (ipctk's default `ClampedLogBarrier`).
    ClampedLog = 0,
    /// The clamped log barrier of `d / dhat`, dimensionless.
    NormalizedClampedLog = 1,
    /// `(d - dhat)^2 ln(d / dhat)^2`.
    ClampedLogSq = 2,
    /// `-2/(3 dhat) (d - dhat)^3`.
    Cubic = 3,
}

/// The options of `topoccd_collisions_build`; `topoccd_collision_options_default()` gives
/// ipctk's defaults.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct topoccd_collision_options {
    /// The activation distance, finite, > 0. Default 1e-3.
    pub dhat: f64,
    /// The minimum distance (a thickness), finite, >= 0. Default 0.
    pub dmin: f64,
    /// Weight each collision by the rest areas of its primitives. Default false.
    pub use_area_weighting: bool,
    /// A `topoccd_collision_set_type`. Default `TOPOCCD_COLLISION_SET_TYPE_IPC`.
    pub collision_set_type: u32,
}

/// The collision options' defaults (ipctk's).
#[no_mangle]
pub extern "C" fn topoccd_collision_options_default() -> topoccd_collision_options {
    let d = CollisionOptions::default();
    topoccd_collision_options {
        dhat: d.dhat,
        dmin: d.dmin,
        use_area_weighting: d.use_area_weighting,
        collision_set_type: topoccd_collision_set_type::Ipc as u32,
    }
}

/// A vertex-vertex collision.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct topoccd_vv_collision {
    /// The two vertices.
    pub vertices: [u32; 2],
    /// Its weight (multiplicity, or area with area weighting).
    pub weight: f64,
}

/// An edge-vertex collision.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct topoccd_ev_collision {
    /// The edge's index in the set's edge list (`topoccd_collision_arrays.edges`).
    pub edge_id: u32,
    /// The edge's vertices.
    pub edge: [u32; 2],
    /// The vertex.
    pub vertex: u32,
    /// Its weight.
    pub weight: f64,
}

/// An edge-edge collision (closest points inside both edges, or mollified).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct topoccd_ee_collision {
    /// The two edges' indices in the set's edge list.
    pub edge_ids: [u32; 2],
    /// The first edge's vertices.
    pub a: [u32; 2],
    /// The second edge's vertices.
    pub b: [u32; 2],
    /// The mollifier's threshold, from the rest positions.
    pub eps_x: f64,
    /// ipctk's `EdgeEdgeDistanceType`, 0 (`EA0_EB0`) to 8 (`EA_EB`).
    pub r#type: u32,
    /// Its weight.
    pub weight: f64,
}

/// A face-vertex collision (the closest point inside the triangle).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct topoccd_fv_collision {
    /// The face (a row of the configuration's triangles).
    pub face: u32,
    /// The face's vertices.
    pub triangle: [u32; 3],
    /// The vertex.
    pub vertex: u32,
    /// Its weight.
    pub weight: f64,
}

/// The arrays of a `topoccd_collisions`, borrowed: valid until `topoccd_collisions_free`.
/// Each kind in ipctk's order.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct topoccd_collision_arrays {
    /// Vertex-vertex collisions.
    pub vv: *const topoccd_vv_collision,
    /// Their number.
    pub vv_count: usize,
    /// Edge-vertex collisions.
    pub ev: *const topoccd_ev_collision,
    /// Their number.
    pub ev_count: usize,
    /// Edge-edge collisions.
    pub ee: *const topoccd_ee_collision,
    /// Their number.
    pub ee_count: usize,
    /// Face-vertex collisions.
    pub fv: *const topoccd_fv_collision,
    /// Their number.
    pub fv_count: usize,
    /// The edge list the `edge_id`s index: `edge_count` rows of 2 vertex indices.
    pub edges: *const u32,
    /// Its number of rows.
    pub edge_count: usize,
    /// The number of vertices of the configuration the set was built on: positions given to
    /// the potentials have this many rows.
    pub vertex_count: usize,
    /// The set's `dmin`.
    pub dmin: f64,
}

/// The normal collision set of one configuration (ipctk's `NormalCollisions`), built by
/// `topoccd_collisions_build`, freed by `topoccd_collisions_free`. Read-only once built: it
/// may be used from several threads at once.
pub struct topoccd_collisions {
    _private: [u8; 0],
}

pub(crate) struct CollisionsObject {
    pub(crate) set: NormalCollisions,
    pub(crate) vertex_count: usize,
    vv: Vec<topoccd_vv_collision>,
    ev: Vec<topoccd_ev_collision>,
    ee: Vec<topoccd_ee_collision>,
    fv: Vec<topoccd_fv_collision>,
}

impl Kind for CollisionsObject {
    const MAGIC: u64 = u64::from_be_bytes(*b"topoCOL1");
    const NAME: &'static str = "topoccd_collisions";
}

impl CollisionsObject {
    fn new(set: NormalCollisions, vertex_count: usize) -> Self {
        Self {
            vv: set
                .vv
                .iter()
                .map(|c| topoccd_vv_collision {
                    vertices: c.vertices,
                    weight: c.weight,
                })
                .collect(),
            ev: set
                .ev
                .iter()
                .map(|c| topoccd_ev_collision {
                    edge_id: c.edge_id,
                    edge: c.edge,
                    vertex: c.vertex,
                    weight: c.weight,
                })
                .collect(),
            ee: set
                .ee
                .iter()
                .map(|c| topoccd_ee_collision {
                    edge_ids: c.edge_ids,
                    a: c.a,
                    b: c.b,
                    eps_x: c.eps_x,
                    r#type: c.kind as u32,
                    weight: c.weight,
                })
                .collect(),
            fv: set
                .fv
                .iter()
                .map(|c| topoccd_fv_collision {
                    face: c.face,
                    triangle: c.triangle,
                    vertex: c.vertex,
                    weight: c.weight,
                })
                .collect(),
            set,
            vertex_count,
        }
    }
}

fn ipc_failure(e: IpcError) -> Failure {
    let status = match &e {
        IpcError::Proximity(p) => return failure(p.clone()),
        IpcError::RestPositions { .. } => topoccd_status::InvalidArgument,
        IpcError::RestNotFinite(_) => topoccd_status::InvalidStep,
        IpcError::Dhat(_)
        | IpcError::Dmin(_)
        | IpcError::ShapeDerivatives
        | IpcError::ImprovedMaxApprox => topoccd_status::InvalidOptions,
        _ => topoccd_status::Internal,
    };
    Failure::new(status, chain(&e))
}

fn collision_options(o: &topoccd_collision_options) -> Result<CollisionOptions, Failure> {
    let collision_set_type = match o.collision_set_type {
        0 => CollisionSetType::Ipc,
        1 => CollisionSetType::ImprovedMaxApprox,
        t => {
            return Err(Failure::new(
                topoccd_status::InvalidOptions,
                format!("collision_set_type must be 0 (IPC) or 1 (IMPROVED_MAX_APPROX), got {t}"),
            ))
        }
    };
    let options = CollisionOptions {
        dhat: o.dhat,
        dmin: o.dmin,
        use_area_weighting: o.use_area_weighting,
        collision_set_type,
        ..CollisionOptions::default()
    };
    options.validate().map_err(ipc_failure)?;
    Ok(options)
}

/// Builds the normal collision set of `config` (ipctk's `NormalCollisions::build(mesh, x,
/// dhat, dmin)`): the pairs closer than `dhat + dmin` found with `ccd`'s proximity (its
/// hierarchy is kept and refitted across a solver's iterations), each reduced to its closest
/// features and merged with its multiplicity. `rest_positions` (`rest_count` rows of 3
/// doubles, one per vertex) give the edge-edge mollifier thresholds and, with
/// `use_area_weighting`, the weights; pass `config->x` when there is no rest shape.
/// `options` may be NULL for the defaults. `*collisions` receives a new set (free it with
/// `topoccd_collisions_free`), NULL on failure.
///
/// Returns `TOPOCCD_STATUS_OK`, or `TOPOCCD_STATUS_NULL_POINTER`,
/// `TOPOCCD_STATUS_INVALID_HANDLE`, `TOPOCCD_STATUS_BUSY`, `TOPOCCD_STATUS_INVALID_OPTIONS`
/// (`dhat`, `dmin`, the set type), `TOPOCCD_STATUS_INVALID_STEP` (a triangle or edge naming a
/// vertex out of range, a NaN position or rest position), `TOPOCCD_STATUS_INVALID_ARGUMENT`
/// (`rest_count` not the vertex count); the message is `topoccd_ccd_last_error(ccd)`.
///
/// ```c
/// /* A vertex (3) 0.5e-3 above a triangle. */
/// const double x[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.2, 0.5e-3};
/// const uint32_t triangles[] = {0, 1, 2};
/// topoccd_configuration config = {0};
/// config.x = x; config.vertex_count = 4;
/// config.triangles = triangles; config.triangle_count = 1;
/// topoccd_collisions *c = NULL;
/// topoccd_collisions_build(ccd, &config, x, 4, NULL, &c); /* one face-vertex collision */
/// ```
///
/// # Safety
/// `ccd` is NULL or a `topoccd_ccd` this library returned; `config` is NULL or points to a
/// `topoccd_configuration` whose arrays are valid for their counts; `rest_positions` is NULL
/// or valid for `3 rest_count` doubles; `options` is NULL or points to options; `collisions`
/// is NULL or valid for a write of a pointer.
#[no_mangle]
pub unsafe extern "C" fn topoccd_collisions_build(
    ccd: *mut topoccd_ccd,
    config: *const topoccd_configuration,
    rest_positions: *const f64,
    rest_count: usize,
    options: *const topoccd_collision_options,
    collisions: *mut *mut topoccd_collisions,
) -> topoccd_status {
    outputs::clear(collisions);
    with_state(ccd, |state| {
        if config.is_null() {
            return Err(Failure::null("config"));
        }
        if collisions.is_null() {
            return Err(Failure::null("collisions"));
        }
        let o = if options.is_null() {
            topoccd_collision_options_default()
        } else {
            *options
        };
        let options = collision_options(&o)?;
        let configuration = configuration(&*config)?;
        let rest = rows::<f64, 3>(rest_positions, rest_count, "rest_positions")?;
        let set = NormalCollisions::build(&mut state.ccd, &configuration, rest, &options)
            .map_err(ipc_failure)?;
        let n = configuration.vertex_count();
        *collisions = handle::into_raw(CollisionsObject::new(set, n));
        Ok(())
    })
}

/// Frees `*collisions` and sets it to NULL. NULL, or a pointer to NULL, is allowed.
///
/// # Safety
/// `collisions` is NULL or points to NULL or to a `topoccd_collisions` this library returned,
/// not in use by another thread.
#[no_mangle]
pub unsafe extern "C" fn topoccd_collisions_free(collisions: *mut *mut topoccd_collisions) {
    let _ = guard(|| {
        handle::free::<CollisionsObject, _>(collisions);
        Ok(())
    });
}

/// The collisions as arrays: `*arrays` is filled with pointers into `collisions`, valid until
/// `topoccd_collisions_free`.
///
/// ```c
/// topoccd_collision_arrays a;
/// topoccd_collisions_arrays(c, &a, NULL);
/// for (size_t i = 0; i < a.fv_count; i++)
///     printf("vertex %u over face %u, weight %g\n", a.fv[i].vertex, a.fv[i].face, a.fv[i].weight);
/// ```
///
/// # Safety
/// `collisions` is NULL or a `topoccd_collisions` this library returned; `arrays` and `error`
/// are NULL or valid for a write.
#[no_mangle]
pub unsafe extern "C" fn topoccd_collisions_arrays(
    collisions: *const topoccd_collisions,
    arrays: *mut topoccd_collision_arrays,
    error: *mut *mut topoccd_error,
) -> topoccd_status {
    let result = guard(|| {
        let c = handle::get::<CollisionsObject, _>(collisions, "collisions")?;
        if arrays.is_null() {
            return Err(Failure::null("arrays"));
        }
        *arrays = topoccd_collision_arrays {
            vv: c.vv.as_ptr(),
            vv_count: c.vv.len(),
            ev: c.ev.as_ptr(),
            ev_count: c.ev.len(),
            ee: c.ee.as_ptr(),
            ee_count: c.ee.len(),
            fv: c.fv.as_ptr(),
            fv_count: c.fv.len(),
            edges: c.set.edges.as_ptr().cast(),
            edge_count: c.set.edges.len(),
            vertex_count: c.vertex_count,
            dmin: c.set.dmin,
        };
        Ok(())
    });
    deliver(result, error)
}

/// `x` as rows of the set's vertex count, finite.
///
/// # Safety
/// `x` is NULL or valid for `3 count` doubles.
pub(crate) unsafe fn positions<'a>(
    x: *const f64,
    count: usize,
    expected: usize,
    what: &str,
) -> Result<&'a [[f64; 3]], Failure> {
    if count != expected {
        return Err(Failure::new(
            topoccd_status::InvalidArgument,
            format!("{what} has {count} rows, but the collision set has {expected} vertices"),
        ));
    }
    if x.is_null() && count == 0 {
        return Ok(&[]);
    }
    if x.is_null() {
        return Err(Failure::null(what));
    }
    let x = rows::<f64, 3>(x, count, what)?;
    if let Some(i) = x.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
        return Err(Failure::new(
            topoccd_status::InvalidStep,
            format!("{what}: vertex {i} is not finite ({:?})", x[i]),
        ));
    }
    Ok(x)
}

/// The barrier potential's parameters (ipctk's `BarrierPotential(dhat, stiffness)`), passed
/// by pointer to the potential's functions; `topoccd_barrier_potential_new` fills them.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct topoccd_barrier_potential {
    /// The activation distance (not squared), finite, > 0.
    pub dhat: f64,
    /// The stiffness kappa, finite, > 0.
    pub stiffness: f64,
    /// A `topoccd_barrier`. Default `TOPOCCD_BARRIER_CLAMPED_LOG`.
    pub barrier: u32,
    /// ipctk's `use_physical_barrier`. Default false.
    pub use_physical_barrier: bool,
}

/// The clamped log barrier potential with `dhat` and `stiffness`.
#[no_mangle]
pub extern "C" fn topoccd_barrier_potential_new(
    dhat: f64,
    stiffness: f64,
) -> topoccd_barrier_potential {
    topoccd_barrier_potential {
        dhat,
        stiffness,
        barrier: topoccd_barrier::ClampedLog as u32,
        use_physical_barrier: false,
    }
}

fn barrier(b: u32) -> Result<Barrier, Failure> {
    Ok(match b {
        0 => Barrier::ClampedLog,
        1 => Barrier::NormalizedClampedLog,
        2 => Barrier::ClampedLogSq,
        3 => Barrier::Cubic,
        b => {
            return Err(Failure::new(
                topoccd_status::InvalidOptions,
                format!("barrier must be a topoccd_barrier in [0, 3], got {b}"),
            ))
        }
    })
}

pub(crate) fn projection(p: u32) -> Result<PsdProjection, Failure> {
    Ok(match p {
        0 => PsdProjection::None,
        1 => PsdProjection::Clamp,
        2 => PsdProjection::Abs,
        p => {
            return Err(Failure::new(
                topoccd_status::InvalidOptions,
                format!("projection must be a topoccd_psd_projection in [0, 2], got {p}"),
            ))
        }
    })
}

/// # Safety
/// `p` is NULL or points to a `topoccd_barrier_potential`.
pub(crate) unsafe fn potential(
    p: *const topoccd_barrier_potential,
) -> Result<BarrierPotential, Failure> {
    if p.is_null() {
        return Err(Failure::null("potential"));
    }
    let p = *p;
    if !(p.dhat.is_finite() && p.dhat > 0.0) {
        return Err(Failure::new(
            topoccd_status::InvalidOptions,
            format!("dhat must be finite and > 0, got {}", p.dhat),
        ));
    }
    if !(p.stiffness.is_finite() && p.stiffness > 0.0) {
        return Err(Failure::new(
            topoccd_status::InvalidOptions,
            format!("stiffness must be finite and > 0, got {}", p.stiffness),
        ));
    }
    Ok(BarrierPotential {
        barrier: barrier(p.barrier)?,
        dhat: p.dhat,
        stiffness: p.stiffness,
        use_physical_barrier: p.use_physical_barrier,
    })
}

/// The checked inputs of a potential's call.
///
/// # Safety
/// As the public functions.
unsafe fn inputs<'a>(
    p: *const topoccd_barrier_potential,
    collisions: *const topoccd_collisions,
    x: *const f64,
    vertex_count: usize,
) -> Result<(BarrierPotential, &'a CollisionsObject, &'a [[f64; 3]]), Failure> {
    let p = potential(p)?;
    let c = handle::get::<CollisionsObject, _>(collisions, "collisions")?;
    let x = positions(x, vertex_count, c.vertex_count, "x")?;
    Ok((p, c, x))
}

/// The barrier energy over `collisions` at positions `x` (`vertex_count` rows, the set's
/// vertex count; ipctk's `B(collisions, mesh, x)`) into `*energy`: `+inf` when a pair
/// touches.
///
/// Returns `TOPOCCD_STATUS_OK`, or `TOPOCCD_STATUS_NULL_POINTER`,
/// `TOPOCCD_STATUS_INVALID_HANDLE`, `TOPOCCD_STATUS_INVALID_OPTIONS` (`dhat`, `stiffness`,
/// `barrier`), `TOPOCCD_STATUS_INVALID_ARGUMENT` (`vertex_count` not the set's),
/// `TOPOCCD_STATUS_INVALID_STEP` (a NaN or infinite position), with the message in `*error`.
///
/// # Safety
/// `potential` is NULL or points to a `topoccd_barrier_potential`; `collisions` is NULL or a
/// `topoccd_collisions` this library returned; `x` is NULL or valid for `3 vertex_count`
/// doubles; `energy` and `error` are NULL or valid for a write.
#[no_mangle]
pub unsafe extern "C" fn topoccd_barrier_energy(
    potential: *const topoccd_barrier_potential,
    collisions: *const topoccd_collisions,
    x: *const f64,
    vertex_count: usize,
    energy: *mut f64,
    error: *mut *mut topoccd_error,
) -> topoccd_status {
    let result = guard(|| {
        let (p, c, x) = inputs(potential, collisions, x, vertex_count)?;
        outputs::energy(energy, || Ok(p.energy(&c.set, x)))
    });
    deliver(result, error)
}

/// The gradient of the barrier energy into `gradient`, `gradient_len` = `3 vertex_count`
/// doubles (`x0 y0 z0 x1 ...`), overwritten. Returns as `topoccd_barrier_energy`, and
/// `TOPOCCD_STATUS_INVALID_ARGUMENT` when `gradient_len` is not `3 vertex_count`.
///
/// # Safety
/// As `topoccd_barrier_energy`; `gradient` is NULL or valid for `gradient_len` writes.
#[no_mangle]
pub unsafe extern "C" fn topoccd_barrier_gradient(
    potential: *const topoccd_barrier_potential,
    collisions: *const topoccd_collisions,
    x: *const f64,
    vertex_count: usize,
    gradient: *mut f64,
    gradient_len: usize,
    error: *mut *mut topoccd_error,
) -> topoccd_status {
    let result = guard(|| {
        let (p, c, x) = inputs(potential, collisions, x, vertex_count)?;
        outputs::gradient(gradient, gradient_len, vertex_count, || {
            Ok(p.gradient(&c.set, x))
        })
    });
    deliver(result, error)
}

/// The Hessian of the barrier energy, `3 vertex_count` square, each collision's Hessian
/// projected by `projection` (a `topoccd_psd_projection`) before it is added (ipctk's
/// `hessian(collisions, mesh, x, project_hessian_to_psd)`): `*hessian` receives a new
/// `topoccd_sparse` (read it with `topoccd_sparse_csr`, free it with `topoccd_sparse_free`).
/// Returns as `topoccd_barrier_energy`, and `TOPOCCD_STATUS_INVALID_OPTIONS` for an unknown
/// projection.
///
/// # Safety
/// As `topoccd_barrier_energy`; `hessian` is NULL or valid for a write of a pointer.
#[no_mangle]
pub unsafe extern "C" fn topoccd_barrier_hessian(
    potential: *const topoccd_barrier_potential,
    collisions: *const topoccd_collisions,
    x: *const f64,
    vertex_count: usize,
    projection: u32,
    hessian: *mut *mut topoccd_sparse,
    error: *mut *mut topoccd_error,
) -> topoccd_status {
    outputs::clear(hessian);
    let result = guard(|| {
        let (p, c, x) = inputs(potential, collisions, x, vertex_count)?;
        outputs::hessian(hessian, projection, |m| Ok(p.hessian(&c.set, x, m)))
    });
    deliver(result, error)
}

/// ipctk's `compute_minimum_distance`: the smallest **squared** distance over the
/// collisions' pairs at positions `x` (`+inf` for an empty set), never larger than the exact
/// one beyond a rounding bound. Returns as `topoccd_barrier_energy`.
///
/// # Safety
/// `collisions` is NULL or a `topoccd_collisions` this library returned; `x` is NULL or valid
/// for `3 vertex_count` doubles; `distance_squared` and `error` are NULL or valid for a write.
#[no_mangle]
pub unsafe extern "C" fn topoccd_collisions_minimum_distance(
    collisions: *const topoccd_collisions,
    x: *const f64,
    vertex_count: usize,
    distance_squared: *mut f64,
    error: *mut *mut topoccd_error,
) -> topoccd_status {
    let result = guard(|| {
        let c = handle::get::<CollisionsObject, _>(collisions, "collisions")?;
        let x = positions(x, vertex_count, c.vertex_count, "x")?;
        if distance_squared.is_null() {
            return Err(Failure::null("distance_squared"));
        }
        *distance_squared = c.set.compute_minimum_distance(x);
        Ok(())
    });
    deliver(result, error)
}

fn finite(value: f64, what: &str, positive: bool) -> Result<(), Failure> {
    if value.is_finite() && (value > 0.0 || (!positive && value >= 0.0)) {
        return Ok(());
    }
    let range = if positive { "> 0" } else { ">= 0" };
    Err(Failure::new(
        topoccd_status::InvalidOptions,
        format!("{what} must be finite and {range}, got {value}"),
    ))
}

/// ipctk's `initial_barrier_stiffness`: the stiffness that balances the barrier's gradient
/// `grad_barrier` (at stiffness 1) against the energy's `grad_energy` (both `len` doubles),
/// clamped to `[kappa_min, 100 kappa_min]`; `*stiffness` receives it and `*max_stiffness`
/// (may be NULL) the cap for `topoccd_update_barrier_stiffness`. ipctk's defaults:
/// `min_barrier_stiffness_scale` = 1e11, `dmin` = 0.
///
/// Returns `TOPOCCD_STATUS_OK`, `TOPOCCD_STATUS_NULL_POINTER`, or
/// `TOPOCCD_STATUS_INVALID_OPTIONS` (a value out of range or NaN; the message names it).
///
/// # Safety
/// `grad_energy`, `grad_barrier` are NULL or valid for `len` doubles; `stiffness`,
/// `max_stiffness` and `error` are NULL or valid for a write.
#[no_mangle]
pub unsafe extern "C" fn topoccd_initial_barrier_stiffness(
    bbox_diagonal: f64,
    barrier: u32,
    dhat: f64,
    average_mass: f64,
    grad_energy: *const f64,
    grad_barrier: *const f64,
    len: usize,
    min_barrier_stiffness_scale: f64,
    dmin: f64,
    stiffness: *mut f64,
    max_stiffness: *mut f64,
    error: *mut *mut topoccd_error,
) -> topoccd_status {
    let result = guard(|| {
        finite(bbox_diagonal, "bbox_diagonal", true)?;
        finite(dhat, "dhat", true)?;
        finite(average_mass, "average_mass", true)?;
        finite(
            min_barrier_stiffness_scale,
            "min_barrier_stiffness_scale",
            true,
        )?;
        finite(dmin, "dmin", false)?;
        let b = self::barrier(barrier)?;
        let ge = rows::<f64, 1>(grad_energy, len, "grad_energy")?.as_flattened();
        let gb = rows::<f64, 1>(grad_barrier, len, "grad_barrier")?.as_flattened();
        if stiffness.is_null() {
            return Err(Failure::null("stiffness"));
        }
        let k = ipc::initial_barrier_stiffness(
            bbox_diagonal,
            b,
            dhat,
            average_mass,
            ge,
            gb,
            min_barrier_stiffness_scale,
            dmin,
        );
        *stiffness = k.stiffness;
        if !max_stiffness.is_null() {
            *max_stiffness = k.max_stiffness;
        }
        Ok(())
    });
    deliver(result, error)
}

/// ipctk's `update_barrier_stiffness`: `*stiffness` doubled (up to `max_barrier_stiffness`)
/// when the squared minimum distance keeps falling below `(dhat_epsilon_scale (bbox_diagonal
/// + dmin))^2`, else unchanged. The distances are squared ones
/// (`topoccd_collisions_minimum_distance`). ipctk's defaults: `dhat_epsilon_scale` = 1e-9,
/// `dmin` = 0.
///
/// Returns `TOPOCCD_STATUS_OK`, `TOPOCCD_STATUS_NULL_POINTER`, or
/// `TOPOCCD_STATUS_INVALID_OPTIONS` (a NaN, or a negative value).
///
/// # Safety
/// `stiffness` is NULL or valid for a read and a write; `error` is NULL or valid for a write.
#[no_mangle]
pub unsafe extern "C" fn topoccd_update_barrier_stiffness(
    prev_min_distance: f64,
    min_distance: f64,
    max_barrier_stiffness: f64,
    bbox_diagonal: f64,
    dhat_epsilon_scale: f64,
    dmin: f64,
    stiffness: *mut f64,
    error: *mut *mut topoccd_error,
) -> topoccd_status {
    let result = guard(|| {
        for (v, what) in [
            (prev_min_distance, "prev_min_distance"),
            (min_distance, "min_distance"),
        ] {
            if v.is_nan() || v < 0.0 {
                return Err(Failure::new(
                    topoccd_status::InvalidOptions,
                    format!("{what} must be >= 0 (a squared distance, +inf allowed), got {v}"),
                ));
            }
        }
        finite(max_barrier_stiffness, "max_barrier_stiffness", true)?;
        finite(bbox_diagonal, "bbox_diagonal", true)?;
        finite(dhat_epsilon_scale, "dhat_epsilon_scale", true)?;
        finite(dmin, "dmin", false)?;
        if stiffness.is_null() {
            return Err(Failure::null("stiffness"));
        }
        finite(*stiffness, "*stiffness", true)?;
        *stiffness = ipc::update_barrier_stiffness(
            prev_min_distance,
            min_distance,
            max_barrier_stiffness,
            *stiffness,
            bbox_diagonal,
            dhat_epsilon_scale,
            dmin,
        );
        Ok(())
    });
    deliver(result, error)
}
