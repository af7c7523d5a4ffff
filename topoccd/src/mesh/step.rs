//! The input of one step: positions at t=0 and t=1, the triangles, and what the step knows of
//! a topology change (parents) and of the pairs that may not collide (groups, a predicate).
//! Validated once; borrowed where the caller's layout allows it.

use std::borrow::Cow;

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

/// Why a step's input was refused. Each variant names the offending element.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum StepError {
    /// The two position arrays differ in length (and no parent list explains it).
    #[error("the step has {start} vertices at t=0 but {end} at t=1")]
    LengthMismatch {
        /// Vertex count at t=0.
        start: usize,
        /// Vertex count at t=1.
        end: usize,
    },
    /// With a topology change, the positions at t=0 outnumber those at t=1.
    #[error("the step has {start} vertices at t=0, more than the {end} at t=1 (vertex ids persist, so a topology change may only add vertices)")]
    Shrinks {
        /// Vertex count at t=0.
        start: usize,
        /// Vertex count at t=1.
        end: usize,
    },
    /// A flat coordinate array whose length is not a multiple of 3.
    #[error("the flat positions at {frame} hold {len} numbers, not a multiple of 3")]
    FlatLength {
        /// Which end of the step.
        frame: Frame,
        /// Number of values given.
        len: usize,
    },
    /// A flat index array whose length is not a multiple of 3.
    #[error("the flat triangle indices hold {len} numbers, not a multiple of 3")]
    FlatTriangles {
        /// Number of indices given.
        len: usize,
    },
    /// A triangle names a vertex that does not exist.
    #[error("triangle {triangle} names vertex {index}, but there are only {vertices} vertices")]
    IndexOutOfRange {
        /// Index of the triangle.
        triangle: usize,
        /// The offending vertex index.
        index: u64,
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
    /// A row `[child, parent]` of the parent list is invalid.
    #[error("parent row {row} [{child}, {parent}]: {reason}")]
    Parent {
        /// Index of the row.
        row: usize,
        /// The child vertex of the row.
        child: u32,
        /// The parent vertex of the row.
        parent: u32,
        /// What is wrong with it.
        reason: &'static str,
    },
    /// An edge of [`Step::with_edges`] names a vertex that does not exist.
    #[error("edge {edge} names vertex {index}, but there are only {vertices} vertices")]
    EdgeIndexOutOfRange {
        /// Index of the edge.
        edge: usize,
        /// The offending vertex index.
        index: u64,
        /// Number of vertices.
        vertices: usize,
    },
    /// An edge of [`Step::with_edges`] joins a vertex to itself.
    #[error("edge {edge} joins vertex {vertex} to itself")]
    DegenerateEdge {
        /// Index of the edge.
        edge: usize,
        /// The repeated vertex.
        vertex: u32,
    },
    /// The group ids do not give one id per vertex.
    #[error("{groups} group ids for {vertices} vertices (one per vertex expected)")]
    GroupsLength {
        /// Number of group ids given.
        groups: usize,
        /// Number of vertices.
        vertices: usize,
    },
    /// An allocation failed (the system refused the memory).
    #[error("out of memory: could not allocate {bytes} bytes for the {what}")]
    OutOfMemory {
        /// The buffer that could not grow.
        what: &'static str,
        /// The bytes asked for.
        bytes: usize,
    },
}

/// Vertex positions, borrowed when the caller's layout is `[f64; 3]` triples or a flat `x y z`
/// array, owned otherwise. Built by `From` (see [`Step::new`] for the accepted types).
#[derive(Clone, Debug)]
pub struct Positions<'a>(PositionsInner<'a>);

#[derive(Clone, Debug)]
enum PositionsInner<'a> {
    Points(Cow<'a, [DVec3]>),
    /// A flat array, checked for its length by the step.
    Flat(&'a [f64]),
}

impl<'a> Positions<'a> {
    fn resolve(self, frame: Frame) -> Result<Cow<'a, [DVec3]>, StepError> {
        match self.0 {
            PositionsInner::Points(p) => Ok(p),
            PositionsInner::Flat(xs) => {
                if xs.len() % 3 != 0 {
                    return Err(StepError::FlatLength {
                        frame,
                        len: xs.len(),
                    });
                }
                Ok(Cow::Borrowed(bytemuck::cast_slice(xs)))
            }
        }
    }
}

impl<'a> From<&'a [[f64; 3]]> for Positions<'a> {
    fn from(p: &'a [[f64; 3]]) -> Self {
        Self(PositionsInner::Points(Cow::Borrowed(bytemuck::cast_slice(p))))
    }
}

impl<'a, const N: usize> From<&'a [[f64; 3]; N]> for Positions<'a> {
    fn from(p: &'a [[f64; 3]; N]) -> Self {
        Self::from(p.as_slice())
    }
}

impl<'a> From<&'a Vec<[f64; 3]>> for Positions<'a> {
    fn from(p: &'a Vec<[f64; 3]>) -> Self {
        Self::from(p.as_slice())
    }
}

impl From<Vec<[f64; 3]>> for Positions<'_> {
    fn from(p: Vec<[f64; 3]>) -> Self {
        Self(PositionsInner::Points(Cow::Owned(
            p.into_iter().map(DVec3::from_array).collect(),
        )))
    }
}

impl<'a> From<&'a [f64]> for Positions<'a> {
    /// A flat array `x0 y0 z0 x1 y1 z1 ...`; its length must be a multiple of 3.
    fn from(xs: &'a [f64]) -> Self {
        Self(PositionsInner::Flat(xs))
    }
}

impl<'a> From<&'a [mint::Vector3<f64>]> for Positions<'a> {
    fn from(p: &'a [mint::Vector3<f64>]) -> Self {
        Self(PositionsInner::Points(Cow::Borrowed(bytemuck::cast_slice(
            mint_flat(p),
        ))))
    }
}

impl<'a> From<&'a [mint::Point3<f64>]> for Positions<'a> {
    fn from(p: &'a [mint::Point3<f64>]) -> Self {
        Self(PositionsInner::Points(Cow::Owned(
            p.iter().map(|q| DVec3::new(q.x, q.y, q.z)).collect(),
        )))
    }
}

#[cfg(feature = "glam")]
impl<'a> From<&'a [DVec3]> for Positions<'a> {
    /// glam 0.30 vectors, borrowed (feature `glam`).
    fn from(p: &'a [DVec3]) -> Self {
        Self(PositionsInner::Points(Cow::Borrowed(p)))
    }
}

#[cfg(feature = "glam")]
impl<'a> From<&'a Vec<DVec3>> for Positions<'a> {
    /// glam 0.30 vectors, borrowed (feature `glam`).
    fn from(p: &'a Vec<DVec3>) -> Self {
        Self(PositionsInner::Points(Cow::Borrowed(p)))
    }
}

#[cfg(feature = "glam")]
impl From<Vec<DVec3>> for Positions<'_> {
    /// glam 0.30 vectors, owned (feature `glam`).
    fn from(p: Vec<DVec3>) -> Self {
        Self(PositionsInner::Points(Cow::Owned(p)))
    }
}

/// `mint::Vector3<f64>` is `#[repr(C)] { x, y, z }`: three `f64` without padding.
fn mint_flat(p: &[mint::Vector3<f64>]) -> &[f64] {
    const _: () = assert!(std::mem::size_of::<mint::Vector3<f64>>() == 24);
    const _: () = assert!(std::mem::align_of::<mint::Vector3<f64>>() == 8);
    // SAFETY: `mint::Vector3<f64>` is `#[repr(C)]` with three `f64` fields (size and alignment
    // checked above), so `p` is `3 * p.len()` initialised, aligned `f64` values.
    unsafe { std::slice::from_raw_parts(p.as_ptr().cast::<f64>(), p.len() * 3) }
}

/// Triangle vertex indices, borrowed when given as `[u32; 3]` or a flat `u32` array, converted
/// (and range-checked) otherwise.
#[derive(Clone, Debug)]
pub struct Triangles<'a>(TrianglesInner<'a>);

#[derive(Clone, Debug)]
enum TrianglesInner<'a> {
    U32(Cow<'a, [[u32; 3]]>),
    FlatU32(&'a [u32]),
    Usize(&'a [[usize; 3]]),
}

impl<'a> Triangles<'a> {
    fn resolve(self) -> Result<Cow<'a, [[u32; 3]]>, StepError> {
        match self.0 {
            TrianglesInner::U32(t) => Ok(t),
            TrianglesInner::FlatU32(xs) => {
                if xs.len() % 3 != 0 {
                    return Err(StepError::FlatTriangles { len: xs.len() });
                }
                Ok(Cow::Borrowed(bytemuck::cast_slice(xs)))
            }
            TrianglesInner::Usize(ts) => ts
                .iter()
                .enumerate()
                .map(|(triangle, t)| {
                    let mut out = [0u32; 3];
                    for (o, &i) in out.iter_mut().zip(t) {
                        *o = u32::try_from(i).map_err(|_| StepError::IndexOutOfRange {
                            triangle,
                            index: i as u64,
                            vertices: u32::MAX as usize,
                        })?;
                    }
                    Ok(out)
                })
                .collect::<Result<Vec<_>, _>>()
                .map(Cow::Owned),
        }
    }
}

impl<'a> From<&'a [[u32; 3]]> for Triangles<'a> {
    fn from(t: &'a [[u32; 3]]) -> Self {
        Self(TrianglesInner::U32(Cow::Borrowed(t)))
    }
}

impl<'a, const N: usize> From<&'a [[u32; 3]; N]> for Triangles<'a> {
    fn from(t: &'a [[u32; 3]; N]) -> Self {
        Self::from(t.as_slice())
    }
}

impl<'a> From<&'a Vec<[u32; 3]>> for Triangles<'a> {
    fn from(t: &'a Vec<[u32; 3]>) -> Self {
        Self::from(t.as_slice())
    }
}

impl From<Vec<[u32; 3]>> for Triangles<'_> {
    fn from(t: Vec<[u32; 3]>) -> Self {
        Self(TrianglesInner::U32(Cow::Owned(t)))
    }
}

impl<'a> From<&'a [u32]> for Triangles<'a> {
    /// A flat array `a0 b0 c0 a1 b1 c1 ...`; its length must be a multiple of 3.
    fn from(t: &'a [u32]) -> Self {
        Self(TrianglesInner::FlatU32(t))
    }
}

impl<'a> From<&'a [[usize; 3]]> for Triangles<'a> {
    fn from(t: &'a [[usize; 3]]) -> Self {
        Self(TrianglesInner::Usize(t))
    }
}

impl<'a> From<&'a Vec<[usize; 3]>> for Triangles<'a> {
    fn from(t: &'a Vec<[usize; 3]>) -> Self {
        Self(TrianglesInner::Usize(t))
    }
}

/// A user predicate on vertex pairs: `false` means the two vertices' features never collide.
pub type CanCollide<'a> = &'a (dyn Fn(u32, u32) -> bool + Sync);

/// The validated input of one step. Vertices move linearly from their position at t=0 to
/// their position at t=1. Vertices no triangle references are allowed and ignored, unless the
/// step has edges ([`Step::with_edges`]: free edges and free points, codimensional geometry).
///
/// Pairs of features that share a vertex are never tested. Beyond that, a step may say which
/// pairs cannot collide:
/// - after a topology change ([`Step::with_parents`]) a new vertex and its parent, and the new
///   vertices of one parent, count as one vertex for this step, so the two sides of a fresh
///   crack, which start at the same place, are not reported (see
///   [`QueryOptions::crack_filter`](crate::QueryOptions::crack_filter));
/// - [`Step::with_groups`] and [`Step::with_can_collide`] filter pairs as the IPC toolkit's
///   `CollisionMesh::can_collide` does: a vertex-face or edge-edge pair is tested when at least
///   one vertex of one feature may collide with one vertex of the other.
///
/// The filters run behind every broad phase, so every [`Method`](crate::Method) reports the
/// same pairs.
#[derive(Clone)]
pub struct Step<'a> {
    x0: Cow<'a, [DVec3]>,
    x1: Cow<'a, [DVec3]>,
    triangles: Cow<'a, [[u32; 3]]>,
    /// The `[child, parent]` rows of a topology change.
    parents: Vec<[u32; 2]>,
    groups: Option<&'a [u32]>,
    can_collide: Option<CanCollide<'a>>,
    /// The edges of [`Step::with_edges`], if set: codimensional geometry is on.
    edges: Option<Cow<'a, [[u32; 2]]>>,
    /// Whether vertices in no triangle and no edge are free points (with edges set).
    free_points: bool,
}

impl std::fmt::Debug for Step<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Step")
            .field("vertices", &self.x0.len())
            .field("triangles", &self.triangles.len())
            .field("parents", &self.parents.len())
            .field("groups", &self.groups.is_some())
            .field("can_collide", &self.can_collide.is_some())
            .field("edges", &self.edges.as_ref().map(|e| e.len()))
            .finish()
    }
}

impl Default for Step<'_> {
    fn default() -> Self {
        Self {
            x0: Cow::Owned(Vec::new()),
            x1: Cow::Owned(Vec::new()),
            triangles: Cow::Owned(Vec::new()),
            parents: Vec::new(),
            groups: None,
            can_collide: None,
            edges: None,
            free_points: true,
        }
    }
}

impl<'a> Step<'a> {
    /// Validates the input of a step without topology change: as many positions at t=0 as at
    /// t=1. Positions are `&[[f64; 3]]`, a flat `&[f64]`, `&[mint::Vector3<f64>]` (borrowed,
    /// no copy) or `&[mint::Point3<f64>]`, `Vec<[f64; 3]>`; triangles are `&[[u32; 3]]`, a flat
    /// `&[u32]` (borrowed) or `&[[usize; 3]]`, `Vec<[u32; 3]>`. glam, nalgebra and cgmath
    /// convert to `mint`.
    ///
    /// ```
    /// use topoccd::{Step, StepError};
    /// let x = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    /// assert!(Step::new(&x, &x, &[[0u32, 1, 2]]).is_ok());
    /// let flat = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    /// assert!(Step::new(&flat[..], &flat[..], &[0u32, 1, 2][..]).is_ok());
    /// let err = Step::new(&x, &x, &[[0u32, 1, 3]]).unwrap_err();
    /// assert!(matches!(err, StepError::IndexOutOfRange { triangle: 0, index: 3, .. }));
    /// assert_eq!(err.to_string(), "triangle 0 names vertex 3, but there are only 3 vertices");
    /// ```
    pub fn new(
        x0: impl Into<Positions<'a>>,
        x1: impl Into<Positions<'a>>,
        triangles: impl Into<Triangles<'a>>,
    ) -> Result<Self, StepError> {
        let x0 = x0.into().resolve(Frame::Start)?;
        let x1 = x1.into().resolve(Frame::End)?;
        if x0.len() != x1.len() {
            return Err(StepError::LengthMismatch {
                start: x0.len(),
                end: x1.len(),
            });
        }
        Self::checked(x0, x1, triangles.into().resolve()?, Vec::new())
    }

    /// Validates the input of a step across a topology change (a cut, a tear, a fracture).
    /// Vertex ids persist, and new vertices are appended: `x0` may be shorter than `x1`. Each
    /// row `[child, parent]` of `parents` says that vertex `child` was split from `parent`. A
    /// new vertex (`child >= x0.len()`) starts at its parent's position at t=0; a new vertex
    /// without a parent starts where it ends (it does not move). A child must be a new vertex
    /// (`x0.len() <= child < x1.len()`), a parent an old one (`< x0.len()`), and a child
    /// appears in one row at most; anything else is a [`StepError::Parent`] naming the row.
    /// (Without a topology change, [`Step::new`] refuses `x0` and `x1` of different lengths.)
    ///
    /// For the step, a child and its parent, and two children of one parent, count as one
    /// vertex: pairs of features joined that way are not tested while
    /// [`QueryOptions::crack_filter`](crate::QueryOptions::crack_filter) is on (the default).
    ///
    /// ```
    /// use topoccd::{query, Method, QueryOptions, Step};
    /// // A triangle is cut off along the edge 1-2: vertices 3 and 4 are the copies of 1 and 2.
    /// let x0 = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]];
    /// let x1 = [[0.0, 0.0, -0.5], [1.0, 0.0, -0.5], [0.0, 1.0, -0.5], [1.0, 1.0, 0.5],
    ///           [1.0, 0.0, 0.5], [0.0, 1.0, 0.5]];
    /// let triangles = [[0u32, 1, 2], [4, 3, 5]];
    /// let step = Step::with_parents(&x0, &x1, &triangles, &[[4, 1], [5, 2]])?;
    /// assert_eq!(step.x0()[4], [1.0, 0.0, 0.0]); // starts at its parent
    /// let report = query(&step, Method::Bvh, &QueryOptions::default())?;
    /// assert_eq!(report.contact_count(), 0); // the two sides of the cut are not a contact
    /// // A child must be new, a parent old:
    /// let err = Step::with_parents(&x0, &x1, &triangles, &[[2, 1]]).unwrap_err();
    /// assert!(err.to_string().starts_with("parent row 0 [2, 1]: the child is not a new vertex"));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn with_parents(
        x0: impl Into<Positions<'a>>,
        x1: impl Into<Positions<'a>>,
        triangles: impl Into<Triangles<'a>>,
        parents: &[[u32; 2]],
    ) -> Result<Self, StepError> {
        let mut x0 = x0.into().resolve(Frame::Start)?;
        let x1 = x1.into().resolve(Frame::End)?;
        let (old, n) = (x0.len(), x1.len());
        if old > n {
            return Err(StepError::Shrinks { start: old, end: n });
        }
        let mut seen = vec![false; n];
        for (row, &[child, parent]) in parents.iter().enumerate() {
            let bad = |reason| StepError::Parent {
                row,
                child,
                parent,
                reason,
            };
            if child as usize >= n {
                return Err(bad("the child is not a vertex at t=1"));
            }
            if (child as usize) < old {
                return Err(bad(
                    "the child is not a new vertex (new vertices are appended: their ids are at \
                     least the vertex count at t=0)",
                ));
            }
            if parent as usize >= old {
                return Err(bad("the parent is not a vertex at t=0"));
            }
            if child == parent {
                return Err(bad("a vertex cannot be its own parent"));
            }
            if std::mem::replace(&mut seen[child as usize], true) {
                return Err(bad("the child already has a parent"));
            }
        }
        if old < n {
            let x0 = x0.to_mut();
            x0.extend_from_slice(&x1[old..]);
            for &[child, parent] in parents {
                if child as usize >= old {
                    x0[child as usize] = x0[parent as usize];
                }
            }
        }
        Self::checked(x0, x1, triangles.into().resolve()?, parents.to_vec())
    }

    fn checked(
        x0: Cow<'a, [DVec3]>,
        x1: Cow<'a, [DVec3]>,
        triangles: Cow<'a, [[u32; 3]]>,
        parents: Vec<[u32; 2]>,
    ) -> Result<Self, StepError> {
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
                    index: index.into(),
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
        Ok(Self {
            x0,
            x1,
            triangles,
            parents,
            groups: None,
            can_collide: None,
            edges: None,
            free_points: true,
        })
    }

    /// Sets one group id per vertex: two features are tested only if some vertex of one is in
    /// another group than some vertex of the other (so a group's features never collide with
    /// each other; give each object its own id to skip self-collision).
    ///
    /// ```
    /// use topoccd::{Step, StepError};
    /// let x = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    /// let step = Step::new(&x, &x, &[[0u32, 1, 2]])?;
    /// assert!(step.clone().with_groups(&[0, 0, 0]).is_ok());
    /// assert!(matches!(step.with_groups(&[0, 0]), Err(StepError::GroupsLength { .. })));
    /// # Ok::<(), StepError>(())
    /// ```
    pub fn with_groups(mut self, groups: &'a [u32]) -> Result<Self, StepError> {
        if groups.len() != self.x1.len() {
            return Err(StepError::GroupsLength {
                groups: groups.len(),
                vertices: self.x1.len(),
            });
        }
        self.groups = Some(groups);
        Ok(self)
    }

    /// Sets a predicate on vertex pairs (the IPC toolkit's `can_collide`): two features are
    /// tested only if it holds for some vertex of one and some vertex of the other. It is
    /// called from several threads.
    ///
    /// ```
    /// use topoccd::Step;
    /// let x = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    /// let pinned = |a: u32, b: u32| a != 0 && b != 0; // vertex 0 collides with nothing
    /// let step = Step::new(&x, &x, &[[0u32, 1, 2]])?.with_can_collide(&pinned);
    /// assert_eq!(step.vertex_count(), 3);
    /// # Ok::<(), topoccd::StepError>(())
    /// ```
    pub fn with_can_collide(mut self, can_collide: CanCollide<'a>) -> Self {
        self.can_collide = Some(can_collide);
        self
    }

    /// Sets the step's edges for codimensional geometry (rods, hair, yarn, particles): edges
    /// `[i, j]` that belong to no triangle (free edges) are then tested too, and every vertex
    /// in no triangle and no edge is a free point. Edges that are also edges of a triangle
    /// (as the IPC toolkit's edge lists hold them) are allowed and count once, as the
    /// triangle's; repeated edges count once. Without this call (the default), vertices that no
    /// triangle references are ignored. Pass an empty list to make such vertices points without
    /// free edges.
    ///
    /// A query then covers, besides vertex-face and edge-edge pairs of the triangles, the
    /// vertex-face pairs of free vertices, the edge-edge pairs of free edges, and the
    /// vertex-edge ([`Report::ve`](crate::Report::ve)) and vertex-vertex
    /// ([`Report::vv`](crate::Report::vv)) pairs of free points: every pair of primitives that
    /// can touch (see [`Report::ve`](crate::Report::ve) for why no other is needed). An edge
    /// naming a vertex out of range, or joining a vertex to itself, is an error naming it.
    ///
    /// ```
    /// use topoccd::{query, Method, QueryOptions, Step};
    /// // A rod (the free edge 0-1) lies along x; a particle (vertex 2) falls across it.
    /// let x0 = [[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.3, 0.0, 1.0]];
    /// let x1 = [[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.3, 0.0, -1.0]];
    /// let no_triangles: [[u32; 3]; 0] = [];
    /// let step = Step::new(&x0, &x1, &no_triangles)?.with_edges(&[[0, 1]])?;
    /// let report = query(&step, Method::Bvh, &QueryOptions::default())?;
    /// assert_eq!((report.ve[0].vertex, report.ve[0].edge), (2, [0, 1]));
    /// assert!(report.ve[0].toi <= 0.5 && report.ve[0].toi > 0.5 - 1e-6);
    /// let err = Step::new(&x0, &x1, &no_triangles)?.with_edges(&[[0, 3]]).unwrap_err();
    /// assert_eq!(err.to_string(), "edge 0 names vertex 3, but there are only 3 vertices");
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn with_edges(self, edges: &'a [[u32; 2]]) -> Result<Self, StepError> {
        self.edges_checked(Cow::Borrowed(edges))
    }

    /// As [`Step::with_edges`], the step owning the edges (a step that owns its positions,
    /// read from files, is a `Step<'static>`).
    ///
    /// ```
    /// use topoccd::Step;
    /// let x = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 0.0, 1.0]];
    /// let step: Step<'static> =
    ///     Step::new(x.clone(), x, Vec::<[u32; 3]>::new())?.with_edges_owned(vec![[0, 1]])?;
    /// assert_eq!(step.edges(), Some(&[[0u32, 1]][..]));
    /// # Ok::<(), topoccd::StepError>(())
    /// ```
    pub fn with_edges_owned(self, edges: Vec<[u32; 2]>) -> Result<Self, StepError> {
        self.edges_checked(Cow::Owned(edges))
    }

    fn edges_checked(mut self, edges: Cow<'a, [[u32; 2]]>) -> Result<Self, StepError> {
        let vertices = self.x1.len();
        for (edge, &[a, b]) in edges.iter().enumerate() {
            if let Some(&index) = [a, b].iter().find(|&&i| i as usize >= vertices) {
                return Err(StepError::EdgeIndexOutOfRange {
                    edge,
                    index: index.into(),
                    vertices,
                });
            }
            if a == b {
                return Err(StepError::DegenerateEdge { edge, vertex: a });
            }
        }
        self.edges = Some(edges);
        Ok(self)
    }

    /// Whether the vertices in no triangle and no edge are free points once the step has
    /// edges ([`Step::with_edges`]). `true` (the default) is the IPC toolkit's rule: such
    /// vertices are particles. `false` ignores them, as leftovers of a mesh (vertices a
    /// modelling tool kept after deleting their faces), while the free edges stay.
    ///
    /// ```
    /// use topoccd::{query, Method, QueryOptions, Step};
    /// // A rod (0-1) and a vertex (2) falling across it: a particle, or a leftover.
    /// let x0 = [[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.3, 0.0, 1.0]];
    /// let x1 = [[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.3, 0.0, -1.0]];
    /// let no_triangles: [[u32; 3]; 0] = [];
    /// let step = Step::new(&x0, &x1, &no_triangles)?.with_edges(&[[0, 1]])?;
    /// assert_eq!(query(&step, Method::Bvh, &QueryOptions::default())?.ve.len(), 1);
    /// let step = step.with_free_points(false);
    /// assert!(query(&step, Method::Bvh, &QueryOptions::default())?.ve.is_empty());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn with_free_points(mut self, free_points: bool) -> Self {
        self.free_points = free_points;
        self
    }

    /// Whether vertices in no triangle and no edge are free points (see
    /// [`Step::with_free_points`]; they are only with edges set).
    pub fn free_points(&self) -> bool {
        self.free_points
    }

    /// The edges of [`Step::with_edges`], if set.
    pub fn edges(&self) -> Option<&[[u32; 2]]> {
        self.edges.as_deref()
    }

    /// Positions at t=0 (for new vertices of a topology change, their parent's).
    pub fn x0(&self) -> &[[f64; 3]] {
        bytemuck::cast_slice(&self.x0)
    }

    /// Positions at t=1.
    pub fn x1(&self) -> &[[f64; 3]] {
        bytemuck::cast_slice(&self.x1)
    }

    /// The triangles, as vertex indices. Their order defines the face numbering.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.x0.len()
    }

    /// The `[child, parent]` rows of the step's topology change (empty without one).
    pub fn parents(&self) -> &[[u32; 2]] {
        &self.parents
    }

    /// Whether positions at t=0 are borrowed from the caller (no copy was made).
    ///
    /// ```
    /// use topoccd::Step;
    /// let x = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    /// assert!(Step::new(&x, &x, &[[0u32, 1, 2]])?.is_borrowed());
    /// assert!(!Step::new(x.clone(), x, &[[0u32, 1, 2]])?.is_borrowed());
    /// # Ok::<(), topoccd::StepError>(())
    /// ```
    pub fn is_borrowed(&self) -> bool {
        matches!(
            (&self.x0, &self.x1, &self.triangles),
            (Cow::Borrowed(_), Cow::Borrowed(_), Cow::Borrowed(_))
        )
    }

    /// Positions at t=0 as vectors (public with the feature `internals`).
    #[cfg(feature = "internals")]
    #[doc(hidden)]
    #[inline]
    pub fn pos0(&self) -> &[DVec3] {
        &self.x0
    }

    /// Positions at t=1 as vectors (public with the feature `internals`).
    #[cfg(feature = "internals")]
    #[doc(hidden)]
    #[inline]
    pub fn pos1(&self) -> &[DVec3] {
        &self.x1
    }

    /// Positions at t=0 as vectors.
    #[cfg(not(feature = "internals"))]
    #[inline]
    pub(crate) fn pos0(&self) -> &[DVec3] {
        &self.x0
    }

    /// Positions at t=1 as vectors.
    #[cfg(not(feature = "internals"))]
    #[inline]
    pub(crate) fn pos1(&self) -> &[DVec3] {
        &self.x1
    }

    /// The per-vertex group ids, if set.
    pub(crate) fn groups(&self) -> Option<&'a [u32]> {
        self.groups
    }

    /// The vertex-pair predicate, if set.
    pub(crate) fn can_collide(&self) -> Option<CanCollide<'a>> {
        self.can_collide
    }
}
