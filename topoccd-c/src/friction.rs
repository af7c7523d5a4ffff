//! Friction in C: `topoccd_tangential_collisions` (built from a normal collision set at the
//! lagged positions, with the barrier's normal forces) and the smooth friction potential's
//! energy, gradient and Hessian over velocities (ipctk's `TangentialCollisions` and
//! `FrictionPotential`).

use topoccd::ipc::friction::{
    FrictionCoefficients, FrictionError, FrictionPotential, StencilKind, TangentialCollisions,
};

use crate::error::{deliver, topoccd_error};
use crate::handle::{self, Kind};
use crate::ipc::{
    self, positions, topoccd_barrier_potential, topoccd_collisions, CollisionsObject,
};
use crate::outputs;
use crate::sparse::topoccd_sparse;
use crate::status::{guard, topoccd_status, Failure};

/// One tangential collision (ipctk's `TangentialCollision`), from the lagged positions.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct topoccd_tangential_collision {
    /// Its kind: 0 vertex-vertex, 1 edge-vertex, 2 edge-edge, 3 face-vertex.
    pub kind: u32,
    /// Its stencil's vertices (`vertex_count` of them: 2, 3, 4, 4): vertex-vertex `a b`,
    /// edge-vertex `v e0 e1`, edge-edge `a0 a1 b0 b1`, face-vertex `v t0 t1 t2`.
    pub vertices: [u32; 4],
    /// How many of `vertices` are used.
    pub vertex_count: u32,
    /// The closest point's coordinates (edge-vertex: 1, edge-edge and face-vertex: 2).
    pub closest_point: [f64; 2],
    /// The tangent basis, two orthonormal 3-vectors (`t0 t1`, 6 doubles).
    pub tangent_basis: [f64; 6],
    /// The lagged normal force magnitude.
    pub normal_force_magnitude: f64,
    /// The normal collision's weight.
    pub weight: f64,
    /// The static friction coefficient.
    pub mu_s: f64,
    /// The kinetic friction coefficient.
    pub mu_k: f64,
}

/// The tangential collisions of a normal collision set at its lagged positions, built by
/// `topoccd_tangential_collisions_build`, freed by `topoccd_tangential_collisions_free`.
pub struct topoccd_tangential_collisions {
    _private: [u8; 0],
}

struct TangentialObject {
    set: TangentialCollisions,
    vertex_count: usize,
    rows: Vec<topoccd_tangential_collision>,
}

impl Kind for TangentialObject {
    const MAGIC: u64 = u64::from_be_bytes(*b"topoTAN1");
    const NAME: &'static str = "topoccd_tangential_collisions";
}

fn friction_failure(e: FrictionError) -> Failure {
    let status = match &e {
        FrictionError::VertexOutOfRange { .. } | FrictionError::CoefficientsLength { .. } => {
            topoccd_status::InvalidArgument
        }
        FrictionError::BadCoefficient { .. } | FrictionError::BadEpsV { .. } => {
            topoccd_status::InvalidOptions
        }
        _ => topoccd_status::InvalidStep,
    };
    Failure::new(status, e.to_string())
}

/// Builds the tangential collisions of `collisions` at the lagged positions `x`
/// (`vertex_count` rows, the set's vertex count), with the normal force magnitudes of
/// `barrier` and the friction coefficients `mu_s` (static) and `mu_k` (kinetic), both finite
/// and >= 0 (ipctk's `TangentialCollisions::build(mesh, x, collisions, B, mu)` with
/// `mu_s = mu_k = mu`). Nearly parallel edge-edge collisions get no friction, as in ipctk.
///
/// Returns `TOPOCCD_STATUS_OK`, `TOPOCCD_STATUS_NULL_POINTER`, `TOPOCCD_STATUS_INVALID_HANDLE`,
/// `TOPOCCD_STATUS_INVALID_OPTIONS` (a coefficient, the barrier's parameters),
/// `TOPOCCD_STATUS_INVALID_ARGUMENT` (`vertex_count` not the set's), or
/// `TOPOCCD_STATUS_INVALID_STEP` (a NaN position, a degenerate stencil), with the message in
/// `*error`.
///
/// # Safety
/// `collisions` is NULL or a `topoccd_collisions` this library returned; `barrier` is NULL or
/// points to a `topoccd_barrier_potential`; `x` is NULL or valid for `3 vertex_count` doubles;
/// `tangential` and `error` are NULL or valid for a write of a pointer.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn topoccd_tangential_collisions_build(
    collisions: *const topoccd_collisions,
    barrier: *const topoccd_barrier_potential,
    x: *const f64,
    vertex_count: usize,
    mu_s: f64,
    mu_k: f64,
    tangential: *mut *mut topoccd_tangential_collisions,
    error: *mut *mut topoccd_error,
) -> topoccd_status {
    outputs::clear(tangential);
    let result = guard(|| {
        let b = ipc::potential(barrier)?;
        let c = handle::get::<CollisionsObject, _>(collisions, "collisions")?;
        let x = positions(x, vertex_count, c.vertex_count, "x")?;
        if tangential.is_null() {
            return Err(Failure::null("tangential"));
        }
        let mu = FrictionCoefficients::Global { mu_s, mu_k };
        let set = TangentialCollisions::build(x, &c.set, &b, mu).map_err(friction_failure)?;
        let rows = set
            .iter()
            .map(|t| {
                let n = t.kind.num_vertices();
                let mut vertices = [0u32; 4];
                for (o, &v) in vertices.iter_mut().zip(&t.vertices[..n]) {
                    *o = v as u32;
                }
                let [t0, t1] = t.tangent_basis;
                topoccd_tangential_collision {
                    kind: match t.kind {
                        StencilKind::VertexVertex => 0,
                        StencilKind::EdgeVertex => 1,
                        StencilKind::EdgeEdge => 2,
                        StencilKind::FaceVertex => 3,
                    },
                    vertices,
                    vertex_count: n as u32,
                    closest_point: t.closest_point,
                    tangent_basis: [t0.x, t0.y, t0.z, t1.x, t1.y, t1.z],
                    normal_force_magnitude: t.normal_force_magnitude,
                    weight: t.weight,
                    mu_s: t.mu_s,
                    mu_k: t.mu_k,
                }
            })
            .collect();
        *tangential = handle::into_raw(TangentialObject {
            set,
            vertex_count: c.vertex_count,
            rows,
        });
        Ok(())
    });
    deliver(result, error)
}

/// Frees `*tangential` and sets it to NULL. NULL, or a pointer to NULL, is allowed.
///
/// # Safety
/// `tangential` is NULL or points to NULL or to a `topoccd_tangential_collisions` this library
/// returned, not in use by another thread.
#[no_mangle]
pub unsafe extern "C" fn topoccd_tangential_collisions_free(
    tangential: *mut *mut topoccd_tangential_collisions,
) {
    let _ = guard(|| {
        handle::free::<TangentialObject, _>(tangential);
        Ok(())
    });
}

/// The tangential collisions as an array, in ipctk's order (vertex-vertex, edge-vertex,
/// edge-edge, face-vertex): `*rows` receives a pointer valid until
/// `topoccd_tangential_collisions_free`, `*count` their number.
///
/// # Safety
/// `tangential` is NULL or a `topoccd_tangential_collisions` this library returned; `rows`,
/// `count` and `error` are NULL or valid for a write.
#[no_mangle]
pub unsafe extern "C" fn topoccd_tangential_collisions_arrays(
    tangential: *const topoccd_tangential_collisions,
    rows: *mut *const topoccd_tangential_collision,
    count: *mut usize,
    error: *mut *mut topoccd_error,
) -> topoccd_status {
    let result = guard(|| {
        let t = handle::get::<TangentialObject, _>(tangential, "tangential")?;
        if rows.is_null() {
            return Err(Failure::null("rows"));
        }
        if count.is_null() {
            return Err(Failure::null("count"));
        }
        *rows = t.rows.as_ptr();
        *count = t.rows.len();
        Ok(())
    });
    deliver(result, error)
}

/// The checked inputs of a friction call.
///
/// # Safety
/// As the public functions.
unsafe fn inputs<'a>(
    eps_v: f64,
    tangential: *const topoccd_tangential_collisions,
    v: *const f64,
    vertex_count: usize,
) -> Result<(FrictionPotential, &'a TangentialObject, &'a [[f64; 3]]), Failure> {
    let p = FrictionPotential::new(eps_v).map_err(friction_failure)?;
    let t = handle::get::<TangentialObject, _>(tangential, "tangential")?;
    let v = positions(v, vertex_count, t.vertex_count, "velocities")?;
    Ok((p, t, v))
}

/// The friction potential `D(v)` with the smooth mollifier's threshold `eps_v` (finite, > 0, a
/// speed in the velocities' unit) over `tangential`, at velocities `v` (`vertex_count` rows)
/// into `*energy` (ipctk's `FrictionPotential(eps_v)(collisions, mesh, v)`).
///
/// Returns as `topoccd_barrier_energy` (`TOPOCCD_STATUS_INVALID_OPTIONS` for `eps_v`).
///
/// # Safety
/// `tangential` is NULL or a `topoccd_tangential_collisions` this library returned; `v` is
/// NULL or valid for `3 vertex_count` doubles; `energy` and `error` are NULL or valid for a
/// write.
#[no_mangle]
pub unsafe extern "C" fn topoccd_friction_energy(
    eps_v: f64,
    tangential: *const topoccd_tangential_collisions,
    v: *const f64,
    vertex_count: usize,
    energy: *mut f64,
    error: *mut *mut topoccd_error,
) -> topoccd_status {
    let result = guard(|| {
        let (p, t, v) = inputs(eps_v, tangential, v, vertex_count)?;
        outputs::energy(energy, || p.energy(&t.set, v).map_err(friction_failure))
    });
    deliver(result, error)
}

/// The gradient of the friction potential with respect to the velocities into `gradient`,
/// `gradient_len` = `3 vertex_count` doubles. Returns as `topoccd_friction_energy`.
///
/// # Safety
/// As `topoccd_friction_energy`; `gradient` is NULL or valid for `gradient_len` writes.
#[no_mangle]
pub unsafe extern "C" fn topoccd_friction_gradient(
    eps_v: f64,
    tangential: *const topoccd_tangential_collisions,
    v: *const f64,
    vertex_count: usize,
    gradient: *mut f64,
    gradient_len: usize,
    error: *mut *mut topoccd_error,
) -> topoccd_status {
    let result = guard(|| {
        let (p, t, v) = inputs(eps_v, tangential, v, vertex_count)?;
        outputs::gradient(gradient, gradient_len, vertex_count, || {
            p.gradient(&t.set, v).map_err(friction_failure)
        })
    });
    deliver(result, error)
}

/// The Hessian of the friction potential with respect to the velocities, `3 vertex_count`
/// square, each collision's 2x2 tangential matrix projected by `projection` (a
/// `topoccd_psd_projection`): `*hessian` receives a new `topoccd_sparse`. Returns as
/// `topoccd_friction_energy`.
///
/// # Safety
/// As `topoccd_friction_energy`; `hessian` is NULL or valid for a write of a pointer.
#[no_mangle]
pub unsafe extern "C" fn topoccd_friction_hessian(
    eps_v: f64,
    tangential: *const topoccd_tangential_collisions,
    v: *const f64,
    vertex_count: usize,
    projection: u32,
    hessian: *mut *mut topoccd_sparse,
    error: *mut *mut topoccd_error,
) -> topoccd_status {
    outputs::clear(hessian);
    let result = guard(|| {
        let (p, t, v) = inputs(eps_v, tangential, v, vertex_count)?;
        outputs::hessian(hessian, projection, |m| {
            p.hessian(&t.set, v, m).map_err(friction_failure)
        })
    });
    deliver(result, error)
}
