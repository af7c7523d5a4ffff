//! The contact potential of incremental potential contact (IPC), above
//! [`proximity`](crate::proximity()): the normal collision set, barrier functions, the
//! barrier potential with its gradient and sparse Hessian, and the adaptive stiffness
//! helpers, in the conventions of the IPC toolkit (ipctk) 1.6.1.
//!
//! - [`NormalCollisions`]: built from a [`ProximityReport`](crate::ProximityReport) with
//!   [`NormalCollisions::from_proximity`], or in one call with [`NormalCollisions::build`];
//!   [`CollisionOptions`] holds ipctk's `dhat`, `dmin`, `use_area_weighting` and
//!   `collision_set_type`;
//! - [`Barrier`]: ipctk's barrier functions; [`BarrierPotential`]: energy, gradient and
//!   [`SparseMatrix`] Hessian, with a per-collision [`PsdProjection`];
//! - [`initial_barrier_stiffness`], [`update_barrier_stiffness`] and
//!   [`NormalCollisions::compute_minimum_distance`].
//!
//! Positions are `[[f64; 3]]`, one row per vertex; gradients and Hessians are over the
//! `3 n` coordinates `x0 y0 z0 x1 ...` (ipctk's row-major layout).
//!
//! A point over a triangle, and its barrier:
//!
//! ```
//! use topoccd::ipc::{BarrierPotential, CollisionOptions, NormalCollisions, PsdProjection};
//! use topoccd::{Ccd, Configuration};
//! let x = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.2, 0.2, 5e-4]];
//! let config = Configuration::new(&x, &[[0u32, 1, 2]], &[])?;
//! let options = CollisionOptions { dhat: 1e-3, ..Default::default() };
//! let collisions = NormalCollisions::build(&mut Ccd::new(), &config, &x, &options)?;
//! assert_eq!(collisions.fv.len(), 1);
//! let b = BarrierPotential::new(1e-3, 10.0);
//! let (d2, dhat2) = (25e-8f64, 1e-6);
//! let expected = 10.0 * -(d2 - dhat2).powi(2) * (d2 / dhat2).ln();
//! assert!((b.energy(&collisions, &x) - expected).abs() < 1e-12 * expected);
//! let g = b.gradient(&collisions, &x);
//! assert!(g[11] < 0.0); // pushes the point up: the energy falls as z grows
//! let h = b.hessian(&collisions, &x, PsdProjection::Clamp);
//! assert_eq!(h.size(), 12);
//! # Ok::<(), topoccd::ipc::IpcError>(())
//! ```

mod barrier;
mod collisions;
mod collisions_build;
pub mod friction;
mod mesh;
mod potential;
mod psd;
mod sparse;
mod stiffness;
mod types;

pub use barrier::Barrier;
pub use collisions::{
    CollisionOptions, CollisionSetType, EeCollision, EvCollision, FvCollision, NormalCollisions,
    VvCollision,
};
pub use potential::BarrierPotential;
pub use psd::{project_to_psd, PsdProjection};
pub use sparse::SparseMatrix;
pub use stiffness::{initial_barrier_stiffness, update_barrier_stiffness, InitialStiffness};

use thiserror::Error;

use crate::ProximityError;

/// Why a collision set or potential was refused.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum IpcError {
    /// The configuration or the proximity options.
    #[error(transparent)]
    Proximity(#[from] ProximityError),
    /// The rest positions do not have one row per vertex.
    #[error("rest positions have {got} rows, but the configuration has {vertices} vertices")]
    RestPositions {
        /// Rows given.
        got: usize,
        /// Vertices of the configuration.
        vertices: usize,
    },
    /// A rest position is not finite.
    #[error("rest position {0} is not finite")]
    RestNotFinite(usize),
    /// `dhat` not finite and `> 0`.
    #[error("dhat must be finite and > 0, got {0}")]
    Dhat(f64),
    /// `dmin` not finite and `>= 0`.
    #[error("dmin must be finite and >= 0, got {0}")]
    Dmin(f64),
    /// ipctk's `enable_shape_derivatives` is not supported.
    #[error("enable_shape_derivatives is not supported (the weights' derivatives with respect to the rest positions); build with it false")]
    ShapeDerivatives,
    /// Never returned: the improved max approximation is built (kept so that matches on
    /// this enum keep compiling).
    #[error("collision_set_type ImprovedMaxApprox is not supported (never returned)")]
    ImprovedMaxApprox,
    /// The proximity report was truncated (a cap or a deadline): the set would miss pairs.
    #[error("the proximity report is truncated ({0:?}); build from a complete report")]
    Truncated(crate::StopReason),
    /// A report names a vertex or face outside the configuration.
    #[error("the proximity report names {what} {index}, outside the configuration")]
    ReportIndex {
        /// `"vertex"` or `"face"`.
        what: &'static str,
        /// The index.
        index: u32,
    },
}

#[cfg(test)]
mod tests;
