//! # topoccd-c
//!
//! The C API of [topoccd](../topoccd/index.html): continuous collision detection for deforming
//! triangle meshes whose topology changes (cutting, tearing, fracture), for programs written in
//! C and C++. It builds a static and a shared library (`libtopoccd_c.a`, `libtopoccd_c.so`)
//! and is declared in `include/topoccd.h`, generated from this crate by cbindgen and kept in the
//! repository (a test fails when it is out of date). `include/topoccd.hpp` is a header-only
//! C++17 wrapper: RAII objects, exceptions, views of the results, Eigen overloads. The guide's
//! page *C and C++* says how to build and link it (CMake, pkg-config, plain `cc`).
//!
//! The API mirrors the Rust one:
//! - `topoccd_ccd` (`topoccd_ccd_new`, `topoccd_ccd_free`) is the reusable query, kept across
//!   steps; `topoccd_ccd_query` runs one step given as a `topoccd_step` of borrowed arrays
//!   (positions at t=0 and t=1 as rows of 3 doubles, triangles as rows of 3 `uint32_t`,
//!   optional parents and groups) with a `topoccd_query_options` that
//!   `topoccd_query_options_default` fills;
//! - `topoccd_ccd_report` gives the report in place: arrays of `topoccd_vf_contact` and
//!   `topoccd_ee_contact` (ids, time of impact, certainty, optional geometry), the earliest
//!   contact and the statistics, owned by the `topoccd_ccd` until its next query;
//! - `topoccd_collision_free_stepsize` and `topoccd_is_step_collision_free` are a line
//!   search's questions, with `topoccd_line_search_options`;
//! - `topoccd_proximity` gives, on a `topoccd_ccd`, every primitive pair of one
//!   `topoccd_configuration` closer than `dhat` (free edges and points included), with
//!   distances and closest-feature types, in a `topoccd_proximity_report` it owns;
//! - `topoccd_pair_vertex_face` and `topoccd_pair_edge_edge` are the per-pair tests;
//! - `topoccd_collisions_build` makes, on a `topoccd_ccd`, the normal collision set of IPC
//!   (`topoccd_collisions`); `topoccd_barrier_energy`, `topoccd_barrier_gradient` and
//!   `topoccd_barrier_hessian` (a `topoccd_sparse` read as CSR) evaluate the barrier
//!   potential over it, with the stiffness helpers and the minimum distance beside them;
//!   `topoccd_tangential_collisions_build` and `topoccd_friction_energy`, `_gradient`,
//!   `_hessian` are friction over lagged tangential collisions;
//! - `topoccd_mesh_read`, `topoccd_frames_read` and `topoccd_sequence_open` read meshes, steps
//!   and frame sequences into objects that own their arrays.
//!
//! Errors: every function returns a `topoccd_status`. The message of a failed call on a
//! `topoccd_ccd` is `topoccd_ccd_last_error(ccd)`, kept per object (no global state); functions
//! without a `topoccd_ccd` hand back a `topoccd_error` object. Null pointers, out-of-range
//! indices and invalid input are refused with a code, and no panic crosses the boundary (each
//! entry point catches them: `TOPOCCD_STATUS_INTERNAL`).
//!
//! ```c
//! #include <topoccd.h>
//! #include <stdio.h>
//!
//! int main(void) {
//!     /* A triangle (3 4 5) falls through a fixed one (0 1 2); its vertex 3 hits at t=0.5. */
//!     const double x0[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.2, 1, 0.3, 0.2, 1.5, 0.2, 0.3, 1.5};
//!     const double x1[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.2, -1, 0.3, 0.2, -0.5, 0.2, 0.3, -0.5};
//!     const uint32_t triangles[] = {0, 1, 2, 3, 4, 5};
//!     topoccd_step step = {0};
//!     step.x0 = x0; step.x0_count = 6;
//!     step.x1 = x1; step.x1_count = 6;
//!     step.triangles = triangles; step.triangle_count = 2;
//!     topoccd_ccd *ccd = topoccd_ccd_new();
//!     const topoccd_report *r = NULL;
//!     if (topoccd_ccd_query(ccd, &step, NULL) != TOPOCCD_STATUS_OK
//!         || topoccd_ccd_report(ccd, &r) != TOPOCCD_STATUS_OK) {
//!         fprintf(stderr, "%s\n", topoccd_ccd_last_error(ccd));
//!         return 1;
//!     }
//!     printf("%zu contact(s), earliest at t=%g\n", r->vf_count + r->ee_count, r->earliest_toi);
//!     topoccd_ccd_free(&ccd);
//!     return 0;
//! }
//! ```
#![warn(missing_docs)]
// The C names of the API's types (`topoccd_ccd`, `topoccd_status`, ...) are its Rust names.
#![allow(non_camel_case_types)]

mod ccd;
mod error;
mod friction;
mod handle;
mod io;
mod ipc;
mod line_search;
mod options;
mod outputs;
mod pair;
mod proximity;
mod report;
mod sparse;
mod status;
mod step;

pub use ccd::{
    topoccd_ccd, topoccd_ccd_free, topoccd_ccd_last_error, topoccd_ccd_new, topoccd_ccd_query,
    topoccd_ccd_report,
};
pub use error::{topoccd_error, topoccd_error_free, topoccd_error_message, topoccd_error_status};
pub use friction::{
    topoccd_friction_energy, topoccd_friction_gradient, topoccd_friction_hessian,
    topoccd_tangential_collision, topoccd_tangential_collisions,
    topoccd_tangential_collisions_arrays, topoccd_tangential_collisions_build,
    topoccd_tangential_collisions_free,
};
pub use io::{
    topoccd_frames, topoccd_frames_face_origin, topoccd_frames_free, topoccd_frames_note,
    topoccd_frames_note_count, topoccd_frames_read, topoccd_frames_step, topoccd_mesh,
    topoccd_mesh_data, topoccd_mesh_free, topoccd_mesh_note, topoccd_mesh_note_count,
    topoccd_mesh_read, topoccd_mesh_view, topoccd_sequence, topoccd_sequence_free,
    topoccd_sequence_load, topoccd_sequence_open, topoccd_sequence_step_count,
};
pub use ipc::{
    topoccd_barrier, topoccd_barrier_energy, topoccd_barrier_gradient, topoccd_barrier_hessian,
    topoccd_barrier_potential, topoccd_barrier_potential_new, topoccd_collision_arrays,
    topoccd_collision_options, topoccd_collision_options_default, topoccd_collision_set_type,
    topoccd_collisions, topoccd_collisions_arrays, topoccd_collisions_build,
    topoccd_collisions_free, topoccd_collisions_minimum_distance, topoccd_ee_collision,
    topoccd_ev_collision, topoccd_fv_collision, topoccd_initial_barrier_stiffness,
    topoccd_psd_projection, topoccd_update_barrier_stiffness, topoccd_vv_collision,
};
pub use line_search::{
    topoccd_collision_free_stepsize, topoccd_is_step_collision_free, topoccd_line_search_options,
    topoccd_line_search_options_init,
};
pub use options::{
    topoccd_growth, topoccd_method, topoccd_mode, topoccd_query_options, topoccd_query_options_init,
};
pub use pair::{
    topoccd_edge_edge, topoccd_outcome, topoccd_pair_edge_edge, topoccd_pair_vertex_face,
    topoccd_vertex_face,
};
pub use proximity::{
    topoccd_configuration, topoccd_ee_proximity, topoccd_proximity, topoccd_proximity_options,
    topoccd_proximity_options_default, topoccd_proximity_report, topoccd_ve_proximity,
    topoccd_vf_proximity, topoccd_vv_proximity,
};
pub use report::{
    topoccd_certainty, topoccd_cluster_figures, topoccd_contact_kind, topoccd_ee_contact,
    topoccd_ee_geometry, topoccd_report, topoccd_seconds, topoccd_stats, topoccd_ve_contact,
    topoccd_vf_contact, topoccd_vf_geometry, topoccd_vv_contact,
};
pub use sparse::{topoccd_csr, topoccd_sparse, topoccd_sparse_csr, topoccd_sparse_free};
pub use status::{topoccd_status, topoccd_status_name, topoccd_version};
pub use step::topoccd_step;
