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
//!
//! A whole CCD step: a vertex falls through a fixed triangle, checked by the per-step k-DOP
//! hierarchy and by the brute-force oracle.
//!
//! ```
//! use topoccd::math::DVec3;
//! use topoccd::step::{Ccd, Method, QueryOptions, Step};
//! let fixed = [DVec3::ZERO, DVec3::X, DVec3::Y];
//! let carrier = |z: f64| [0.0, 0.1, 0.1].map(|dz| DVec3::new(0.2 + dz, 0.2, z + 5.0 * dz));
//! let x0: Vec<DVec3> = fixed.iter().chain(&carrier(1.0)).copied().collect();
//! let x1: Vec<DVec3> = fixed.iter().chain(&carrier(-1.0)).copied().collect();
//! let step = Step::new(x0, x1, vec![[0, 1, 2], [3, 4, 5]])?;
//! let mut ccd = Ccd::new(); // keep it across steps: its buffers are reused
//! let report = ccd.query(&step, Method::Bvh, &QueryOptions::default());
//! assert_eq!((report.vf[0].vertex, report.vf[0].face), (3, 0));
//! assert!((report.earliest_toi().unwrap() - 0.5).abs() < 1e-6);
//! assert_eq!(report.vf, ccd.query(&step, Method::Brute, &QueryOptions::default()).vf);
//! # Ok::<(), topoccd::step::StepError>(())
//! ```
#![warn(missing_docs)]

pub mod bvh;
pub mod cluster;
pub mod io;
pub mod kdop;
pub mod math;
pub mod narrow;
pub mod scene;
pub mod step;
