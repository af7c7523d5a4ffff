//! The normal collision set: the proximity pairs reduced to their closest features, merged
//! with their multiplicity (the IPC toolkit's `NormalCollisions`).

use crate::distance::EdgeEdgeType;

/// How the collision set is built (ipctk's `NormalCollisions::CollisionSetType`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum CollisionSetType {
    /// The original IPC set [Li et al. 2020] (ipctk's `IPC`, its default).
    #[default]
    Ipc,
    /// The improved max approximation [Li et al. 2023] (ipctk's `IMPROVED_MAX_APPROX`):
    /// adds negative-weight corrections so that a contact shared by several primitives is
    /// counted once. Meant with area weighting on.
    ImprovedMaxApprox,
}

/// The options of the collision set's build (ipctk's `NormalCollisions` settings and the
/// `dhat`, `dmin` of its `build`).
///
/// ```
/// use topoccd::ipc::CollisionOptions;
/// let options = CollisionOptions { dhat: 1e-3, use_area_weighting: true, ..Default::default() };
/// assert!(options.validate().is_ok());
/// assert!(CollisionOptions { dhat: -1.0, ..options }.validate().is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CollisionOptions {
    /// The barrier's activation distance, in the coordinates' units, finite and `> 0`.
    /// Default 1e-3.
    pub dhat: f64,
    /// The minimum distance (a thickness), finite and `>= 0`: a pair is active when its
    /// squared distance is below `(dhat + dmin)^2`. Default 0.
    pub dmin: f64,
    /// Weight each collision by the rest areas of its primitives (ipctk's
    /// `use_area_weighting`). Default `false`.
    pub use_area_weighting: bool,
    /// The set's formulation (ipctk's `collision_set_type`). Default
    /// [`CollisionSetType::Ipc`].
    pub collision_set_type: CollisionSetType,
    /// ipctk's `enable_shape_derivatives` (derivatives of the weights with respect to the
    /// rest positions). Not supported: `true` is refused with
    /// [`IpcError::ShapeDerivatives`](super::IpcError::ShapeDerivatives). Default `false`.
    pub enable_shape_derivatives: bool,
}

impl Default for CollisionOptions {
    fn default() -> Self {
        Self {
            dhat: 1e-3,
            dmin: 0.0,
            use_area_weighting: false,
            collision_set_type: CollisionSetType::Ipc,
            enable_shape_derivatives: false,
        }
    }
}

/// A vertex-vertex collision (ipctk's `VertexVertexNormalCollision`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VvCollision {
    /// The two vertices, `vertices[0] < vertices[1]`.
    pub vertices: [u32; 2],
    /// The multiplicity (or area) weight; negative for the improved max approximator's
    /// corrections.
    pub weight: f64,
}

/// An edge-vertex collision: the vertex against the interior of the edge (ipctk's
/// `EdgeVertexNormalCollision`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EvCollision {
    /// The edge's index in [`NormalCollisions::edges`].
    pub edge_id: u32,
    /// The edge's vertices, as in [`NormalCollisions::edges`].
    pub edge: [u32; 2],
    /// The vertex.
    pub vertex: u32,
    /// The weight.
    pub weight: f64,
}

/// An edge-edge collision, mollified for nearly parallel edges (ipctk's
/// `EdgeEdgeNormalCollision`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EeCollision {
    /// The first edge's index in [`NormalCollisions::edges`] (the lower one).
    pub edge_ids: [u32; 2],
    /// The first edge's vertices (`ea0`, `ea1`).
    pub a: [u32; 2],
    /// The second edge's vertices (`eb0`, `eb1`).
    pub b: [u32; 2],
    /// The mollifier threshold from the rest positions, `1e-3 |ea|^2 |eb|^2` (ipctk's
    /// `edge_edge_mollifier_threshold`).
    pub eps_x: f64,
    /// The closest features whose distance the barrier uses (the interiors, or another type
    /// when the edges are nearly parallel and the collision is mollified).
    pub kind: EdgeEdgeType,
    /// The weight.
    pub weight: f64,
}

/// A face-vertex collision: the vertex against the interior of the triangle (ipctk's
/// `FaceVertexNormalCollision`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FvCollision {
    /// The triangle's index in the configuration's triangles.
    pub face: u32,
    /// The triangle's vertices.
    pub triangle: [u32; 3],
    /// The vertex.
    pub vertex: u32,
    /// The weight.
    pub weight: f64,
}

/// The normal collision set of one configuration, as ipctk 1.6.1's `NormalCollisions::build`
/// makes it: every proximity pair reduced to its closest features (a vertex near a
/// triangle's edge is an edge-vertex collision, two edges closest at endpoints a
/// vertex-vertex one), repeated collisions merged by adding their weights, and kept when
/// the squared distance of its type is below `(dhat + dmin)^2`.
///
/// Each kind is sorted by its vertex indices: the same set and order on any thread count.
/// Built from the triangles and edges of the call, so a topology change needs no rebuild of
/// anything held.
///
/// ```
/// use topoccd::ipc::{CollisionOptions, NormalCollisions};
/// use topoccd::{Ccd, Configuration};
/// // A point 1e-4 above the middle of a triangle's edge 0-1: one edge-vertex collision.
/// let x = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.5, -1e-4, 0.0]];
/// let config = Configuration::new(&x, &[[0u32, 1, 2]], &[])?;
/// let options = CollisionOptions { dhat: 1e-3, ..Default::default() };
/// let c = NormalCollisions::build(&mut Ccd::new(), &config, &x, &options)?;
/// assert_eq!((c.vv.len(), c.ev.len(), c.ee.len(), c.fv.len()), (0, 1, 0, 0));
/// assert_eq!((c.ev[0].edge, c.ev[0].vertex, c.ev[0].weight), ([0, 1], 3, 1.0));
/// # Ok::<(), topoccd::ipc::IpcError>(())
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NormalCollisions {
    /// Vertex-vertex collisions, sorted by `vertices`.
    pub vv: Vec<VvCollision>,
    /// Edge-vertex collisions, sorted by `(edge, vertex)`.
    pub ev: Vec<EvCollision>,
    /// Edge-edge collisions, sorted by `(a, b, kind)`.
    pub ee: Vec<EeCollision>,
    /// Face-vertex collisions, sorted by `(triangle, vertex)`.
    pub fv: Vec<FvCollision>,
    /// The edges of the configuration the set was built on: each triangle's sides in the
    /// order of the triangles (side `k` from corner `k` to corner `k+1 mod 3`, first
    /// appearance), then the free edges not already there; each `[i, j]` as first met.
    pub edges: Vec<[u32; 2]>,
    /// The `dmin` of the build (ipctk stores it in each collision).
    pub dmin: f64,
    /// The options of the build.
    pub options: CollisionOptions,
}

impl NormalCollisions {
    /// The number of collisions of all kinds.
    pub fn len(&self) -> usize {
        self.vv.len() + self.ev.len() + self.ee.len() + self.fv.len()
    }

    /// Whether the set is empty.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}
