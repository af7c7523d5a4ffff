//! # topoccd
//!
//! Continuous collision detection (CCD) for deforming triangle meshes whose topology may change
//! from one step to the next (cutting, tearing, fracture). Give it the vertex positions at t=0
//! and t=1 of one step and the triangles; it returns every vertex-face and edge-edge contact with
//! its time of impact, or only the earliest one.
//!
//! The crate is organised by pipeline stage:
//! - [`narrow`]: the elementary tests (vertex-face, edge-edge) under linear motion; conservative.
//! - [`kdop`], [`bvh`]: discrete oriented polytopes and a bounding volume hierarchy that knows
//!   only volumes and leaf ids.
//! - [`step`]: one simulation step (mesh, topology, the whole-step query, the brute-force oracle).
//! - [`cluster`]: the dynamic clustering of the paper (leaf and intermediate clusters).
//! - [`scene`]: seeded scene generators used by tests, benchmarks and the command line.
//! - [`io`]: file formats (PLY, OBJ, the query CSV files, ground truth).
#![warn(missing_docs)]

pub mod bvh;
pub mod cluster;
pub mod io;
pub mod kdop;
pub mod math;
pub mod narrow;
pub mod scene;
pub mod step;
