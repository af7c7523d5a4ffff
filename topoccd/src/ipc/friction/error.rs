//! Errors of the friction module.

use super::tangential_collisions::StencilKind;

/// Bad input to the tangential collision set or the friction potential.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FrictionError {
    /// A collision names a vertex beyond the positions or velocities given.
    #[error("vertex {vertex} out of range ({vertices} vertices given)")]
    VertexOutOfRange {
        /// The vertex id.
        vertex: usize,
        /// Number of vertices given.
        vertices: usize,
    },
    /// Per-vertex friction coefficients of the wrong length.
    #[error("{len} friction coefficients for {vertices} vertices (one per vertex expected)")]
    CoefficientsLength {
        /// Number of coefficients given.
        len: usize,
        /// Number of vertices.
        vertices: usize,
    },
    /// A friction coefficient negative or not finite.
    #[error("friction coefficient {value} (expected finite and >= 0)")]
    BadCoefficient {
        /// The coefficient.
        value: f64,
    },
    /// The smooth mollifier's threshold is not positive and finite.
    #[error("eps_v = {eps_v} (expected finite and > 0)")]
    BadEpsV {
        /// The threshold given.
        eps_v: f64,
    },
    /// A stencil without a tangent plane at the lagged positions: coincident points, a
    /// zero-length edge, parallel edges or a zero-area triangle.
    #[error("{kind:?} collision {index} is degenerate: no tangent plane at the lagged positions")]
    DegenerateStencil {
        /// The stencil's kind.
        kind: StencilKind,
        /// Its index in the normal collisions given.
        index: usize,
    },
}
