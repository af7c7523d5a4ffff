//! The input of one step: positions at t=0 and t=1 and the triangles, validated.

use crate::math::DVec3;
use thiserror::Error;

/// Which end of the step a position belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Frame {
    /// Positions at t=0.
    Start,
    /// Positions at t=1.
    End,
}

impl std::fmt::Display for Frame {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Frame::Start => "t=0",
            Frame::End => "t=1",
        })
    }
}

/// Why a step's input was refused.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum StepError {
    /// The two position arrays differ in length.
    #[error("the step has {start} vertices at t=0 but {end} at t=1")]
    LengthMismatch {
        /// Vertex count at t=0.
        start: usize,
        /// Vertex count at t=1.
        end: usize,
    },
    /// A triangle names a vertex that does not exist.
    #[error("triangle {triangle} names vertex {index}, but there are only {vertices} vertices")]
    IndexOutOfRange {
        /// Index of the triangle.
        triangle: usize,
        /// The offending vertex index.
        index: u32,
        /// Number of vertices.
        vertices: usize,
    },
    /// A triangle uses one vertex twice.
    #[error("triangle {triangle} uses vertex {vertex} more than once")]
    RepeatedVertex {
        /// Index of the triangle.
        triangle: usize,
        /// The repeated vertex.
        vertex: u32,
    },
    /// A coordinate is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate at {frame}: {position:?}")]
    NonFinite {
        /// Index of the vertex.
        vertex: usize,
        /// Which end of the step.
        frame: Frame,
        /// The offending position.
        position: [f64; 3],
    },
    /// More vertices than 32-bit indices can address.
    #[error("{vertices} vertices exceed the limit of {limit}")]
    TooManyVertices {
        /// Number of vertices given.
        vertices: usize,
        /// Largest supported number.
        limit: usize,
    },
}

/// The validated input of one step. Vertices move linearly from `x0[i]` to `x1[i]`.
/// Vertices no triangle references are allowed and ignored.
#[derive(Clone, Debug, Default)]
pub struct Step {
    x0: Vec<DVec3>,
    x1: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
}

impl Step {
    /// Validates and takes the input.
    ///
    /// ```
    /// use topoccd::math::DVec3;
    /// use topoccd::step::{Step, StepError};
    /// let x = vec![DVec3::ZERO, DVec3::X, DVec3::Y];
    /// assert!(Step::new(x.clone(), x.clone(), vec![[0, 1, 2]]).is_ok());
    /// let err = Step::new(x.clone(), x, vec![[0, 1, 3]]).unwrap_err();
    /// assert!(matches!(err, StepError::IndexOutOfRange { triangle: 0, index: 3, .. }));
    /// ```
    pub fn new(
        x0: Vec<DVec3>,
        x1: Vec<DVec3>,
        triangles: Vec<[u32; 3]>,
    ) -> Result<Self, StepError> {
        if x0.len() != x1.len() {
            return Err(StepError::LengthMismatch {
                start: x0.len(),
                end: x1.len(),
            });
        }
        let limit = u32::MAX as usize;
        if x0.len() > limit {
            return Err(StepError::TooManyVertices {
                vertices: x0.len(),
                limit,
            });
        }
        for (frame, xs) in [(Frame::Start, &x0), (Frame::End, &x1)] {
            if let Some(vertex) = xs.iter().position(|p| !p.is_finite()) {
                return Err(StepError::NonFinite {
                    vertex,
                    frame,
                    position: xs[vertex].to_array(),
                });
            }
        }
        for (triangle, tri) in triangles.iter().enumerate() {
            if let Some(&index) = tri.iter().find(|&&i| i as usize >= x0.len()) {
                return Err(StepError::IndexOutOfRange {
                    triangle,
                    index,
                    vertices: x0.len(),
                });
            }
            let [a, b, c] = *tri;
            if a == b || a == c {
                return Err(StepError::RepeatedVertex {
                    triangle,
                    vertex: a,
                });
            }
            if b == c {
                return Err(StepError::RepeatedVertex {
                    triangle,
                    vertex: b,
                });
            }
        }
        Ok(Self { x0, x1, triangles })
    }

    /// Positions at t=0.
    pub fn x0(&self) -> &[DVec3] {
        &self.x0
    }

    /// Positions at t=1.
    pub fn x1(&self) -> &[DVec3] {
        &self.x1
    }

    /// The triangles, as vertex indices. Their order defines the face numbering.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.x0.len()
    }
}
