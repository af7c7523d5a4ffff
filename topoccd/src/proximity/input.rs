//! The input of a proximity query: one configuration (positions), its triangles, its free
//! edges, and the pair filter's groups and predicate. Validated once, borrowed.

use thiserror::Error;

use crate::math::DVec3;
use crate::mesh::{CanCollide, Positions, Step, StepError, Triangles};

/// Why a proximity query's input or options were refused. Each variant names the offending
/// element or option.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum ProximityError {
    /// The positions, the triangles or the groups (as [`Step::new`] checks them).
    #[error(transparent)]
    Input(#[from] StepError),
    /// An edge names a vertex that does not exist.
    #[error("edge {edge} names vertex {index}, but there are only {vertices} vertices")]
    EdgeIndex {
        /// Index of the edge.
        edge: usize,
        /// The offending vertex index.
        index: u32,
        /// Number of vertices.
        vertices: usize,
    },
    /// An edge uses one vertex twice.
    #[error("edge {edge} uses vertex {vertex} twice")]
    EdgeRepeatedVertex {
        /// Index of the edge.
        edge: usize,
        /// The repeated vertex.
        vertex: u32,
    },
    /// `dhat` not finite and `> 0`.
    #[error("dhat must be finite and > 0, got {0}")]
    Dhat(f64),
    /// `dmin` not finite and `>= 0`.
    #[error("dmin must be finite and >= 0, got {0}")]
    Dmin(f64),
    /// An allocation failed (the system refused the memory): the query gave up and freed
    /// what it held. Keep [`ProximityOptions::max_contacts`](crate::ProximityOptions) set
    /// (its default bounds the report).
    #[error("out of memory: could not allocate {bytes} bytes for the {what}: set max_contacts (a cap bounds the report)")]
    OutOfMemory {
        /// The buffer that could not grow.
        what: &'static str,
        /// The bytes asked for.
        bytes: usize,
    },
}

impl From<crate::alloc::AllocError> for ProximityError {
    fn from(e: crate::alloc::AllocError) -> Self {
        Self::OutOfMemory {
            what: e.what,
            bytes: e.bytes,
        }
    }
}

/// One configuration of a mesh for a proximity query: positions, triangles and free edges
/// (edges in no triangle: rods, hair, yarn), with the pair filter of a [`Step`] (groups and
/// `can_collide`). Vertices in no triangle and no edge are free points (particles).
///
/// An edge of `edges` that is also a side of a triangle is that triangle's edge: it is
/// counted once.
///
/// ```
/// use topoccd::Configuration;
/// let x = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [5.0, 5.0, 5.0]];
/// let config = Configuration::new(&x, &[[0u32, 1, 2]], &[[2, 3]])?;
/// assert_eq!(config.edges(), &[[2, 3]]);
/// let err = Configuration::new(&x, &[[0u32, 1, 2]], &[[3, 7]]).unwrap_err();
/// assert_eq!(err.to_string(), "edge 0 names vertex 7, but there are only 5 vertices");
/// # Ok::<(), topoccd::ProximityError>(())
/// ```
#[derive(Debug)]
pub struct Configuration<'a> {
    step: Step<'a>,
    edges: &'a [[u32; 2]],
}

impl<'a> Configuration<'a> {
    /// Checks and borrows the input: finite positions, triangles and edges naming existing,
    /// distinct vertices.
    pub fn new(
        x: impl Into<Positions<'a>>,
        triangles: impl Into<Triangles<'a>>,
        edges: &'a [[u32; 2]],
    ) -> Result<Self, ProximityError> {
        let x = x.into();
        let step = Step::new(x.clone(), x, triangles)?;
        let n = step.vertex_count();
        for (i, &[a, b]) in edges.iter().enumerate() {
            for v in [a, b] {
                if v as usize >= n {
                    return Err(ProximityError::EdgeIndex {
                        edge: i,
                        index: v,
                        vertices: n,
                    });
                }
            }
            if a == b {
                return Err(ProximityError::EdgeRepeatedVertex { edge: i, vertex: a });
            }
        }
        Ok(Self { step, edges })
    }

    /// One group id per vertex: features whose vertices all share one group are not paired
    /// (as [`Step::with_groups`]).
    pub fn with_groups(mut self, groups: &'a [u32]) -> Result<Self, ProximityError> {
        self.step = self.step.with_groups(groups)?;
        Ok(self)
    }

    /// A predicate on vertex pairs: features none of whose vertex pairs may collide are not
    /// paired (as [`Step::with_can_collide`]).
    pub fn with_can_collide(mut self, can_collide: CanCollide<'a>) -> Self {
        self.step = self.step.with_can_collide(can_collide);
        self
    }

    /// Whether vertices in no triangle and no edge are free points (`true`, the default: the
    /// IPC toolkit's rule) or ignored as leftovers (`false`), as [`Step::with_free_points`].
    ///
    /// ```
    /// use topoccd::{proximity, Configuration, ProximityOptions};
    /// // Two loose vertices 0.01 apart: two particles near each other, or two leftovers.
    /// let x = [[0.0, 0.0, 0.0], [0.01, 0.0, 0.0]];
    /// let none: [[u32; 3]; 0] = [];
    /// let options = ProximityOptions { dhat: 0.1, ..ProximityOptions::default() };
    /// let config = Configuration::new(&x, &none, &[])?;
    /// assert_eq!(proximity(&config, &options)?.vv.len(), 1);
    /// let config = Configuration::new(&x, &none, &[])?.with_free_points(false);
    /// assert!(proximity(&config, &options)?.vv.is_empty());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn with_free_points(mut self, free_points: bool) -> Self {
        self.step = self.step.with_free_points(free_points);
        self
    }

    /// Whether vertices in no triangle and no edge are free points (see
    /// [`Configuration::with_free_points`]).
    pub fn free_points(&self) -> bool {
        self.step.free_points()
    }

    /// The positions.
    pub fn x(&self) -> &[[f64; 3]] {
        self.step.x0()
    }

    /// The triangles.
    pub fn triangles(&self) -> &[[u32; 3]] {
        self.step.triangles()
    }

    /// The free edges as given.
    pub fn edges(&self) -> &[[u32; 2]] {
        self.edges
    }

    /// The number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.step.vertex_count()
    }

    /// The positions as vectors.
    pub(crate) fn pos(&self) -> &[DVec3] {
        self.step.pos0()
    }

    pub(crate) fn step(&self) -> &Step<'a> {
        &self.step
    }
}
