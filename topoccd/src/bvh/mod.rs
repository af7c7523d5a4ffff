//! A bounding volume hierarchy over leaf volumes. It knows bounding volumes and leaf ids only;
//! the work at the leaves is a closure passed to the traversals.
//!
//! - [`Bvh::rebuild`] builds a binary tree top-down, splitting at the median of the leaves'
//!   centres along the longest axis of their bounds (deterministic; `O(n log n)`; the halves of
//!   big ranges built in parallel on the current rayon pool, into the same tree for any thread
//!   count).
//! - [`Bvh::self_pairs`] reports every unordered pair of distinct leaves whose volumes overlap,
//!   once; [`Bvh::tree_pairs`] every overlapping pair of a leaf of one tree and a leaf of
//!   another; [`Bvh::volume_leaves`] every leaf overlapping one given volume. All count the
//!   bounding-volume tests they make.
//! - [`Bvh::par_self_pairs`] and [`Bvh::par_tree_pairs`] do the same on the current rayon
//!   pool: the traversal is split into tasks in a fixed order, each with an accumulator of the
//!   caller's, returned in task order, so the output is the same for any thread count.
//! - [`Bvh::refit`] gives the leaves new volumes in the same tree, in linear time.
//! - [`Bvh::validate`] checks the tree against its leaves; the tests run it after every build.
//!
//! Scratch memory lives in a [`BvhWorkspace`] that a caller keeps across steps, and
//! [`Bvh::rebuild`] reuses the tree's node array, so a step allocates nothing once warm.
//!
//! ```
//! use topoccd::bvh::{Bvh, BvhWorkspace, Leaf};
//! use topoccd::kdop::Kdop;
//! use topoccd::math::DVec3;
//! // Three unit boxes along x; the first two touch.
//! let leaves: Vec<Leaf<Kdop<3>>> = [0.0, 1.0, 5.0]
//!     .iter()
//!     .enumerate()
//!     .map(|(i, &x)| Leaf {
//!         id: i as u32,
//!         volume: Kdop::from_points(&[DVec3::new(x, 0.0, 0.0), DVec3::new(x + 1.0, 1.0, 1.0)]),
//!     })
//!     .collect();
//! let mut ws = BvhWorkspace::default();
//! let mut bvh = Bvh::new();
//! bvh.rebuild(&leaves, &mut ws);
//! assert!(bvh.validate(&leaves).is_ok());
//! let mut pairs = Vec::new();
//! let bv_tests = bvh.self_pairs(&mut ws, |a, b| pairs.push((a.min(b), a.max(b))));
//! assert_eq!(pairs, vec![(0, 1)]);
//! assert!(bv_tests > 0);
//! ```

mod build;
mod front;
mod parallel;
mod refit;
mod traverse;
mod validation;
pub(crate) mod wide;

pub use parallel::{ParOptions, ParPairs};
pub(crate) use parallel::run_batches;
pub(crate) use front::Front;
pub(crate) use traverse::{LeafCheck, TestAll};
pub use validation::BvhError;

use crate::math::DVec3;

/// What the hierarchy needs of a bounding volume. `Send + Sync`, so that the hierarchy can be
/// built and traversed on several threads.
pub trait BoundingVolume: Copy + Send + Sync {
    /// The smallest volume (of this type) containing both.
    fn merge(&self, other: &Self) -> Self;
    /// Whether the two volumes may share a point; `false` proves them disjoint.
    fn overlaps(&self, other: &Self) -> bool;
    /// Whether `other` lies inside `self` (used by the validator).
    fn contains(&self, other: &Self) -> bool;
    /// A representative centre, used to split the leaves when building.
    fn center(&self) -> DVec3;
}

/// A leaf to build a hierarchy over: an id chosen by the caller and its volume.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Leaf<V> {
    /// The caller's id of the leaf (a triangle, a cluster...), reported by the traversals.
    pub id: u32,
    /// The leaf's bounding volume.
    pub volume: V,
}

/// Marks a leaf node in [`Node::b`].
const LEAF: u32 = u32::MAX;

/// One node of a [`Bvh`]: a volume and either two children or a leaf id.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node<V> {
    /// The node's volume, containing its children's (for a leaf, the leaf's volume).
    pub volume: V,
    /// Leaf: the leaf id. Internal node: the index of the first child.
    a: u32,
    /// Leaf: [`LEAF`]. Internal node: the index of the second child.
    b: u32,
}

impl<V> Node<V> {
    /// The leaf id, if this is a leaf.
    #[inline]
    pub fn leaf(&self) -> Option<u32> {
        (self.b == LEAF).then_some(self.a)
    }

    /// The indices of the two children in [`Bvh::nodes`], if this is an internal node.
    #[inline]
    pub fn children(&self) -> Option<[u32; 2]> {
        (self.b != LEAF).then_some([self.a, self.b])
    }
}

/// A binary bounding volume hierarchy; the root is node 0. Build it with [`Bvh::rebuild`].
#[derive(Clone, Debug)]
pub struct Bvh<V> {
    nodes: Vec<Node<V>>,
}

impl<V> Default for Bvh<V> {
    fn default() -> Self {
        Self { nodes: Vec::new() }
    }
}

/// Scratch memory of the build and the traversals, kept by the caller across steps.
#[derive(Clone, Debug, Default)]
pub struct BvhWorkspace {
    /// Build: the leaves' centres and their indices in the input.
    items: Vec<build::Item>,
    /// Traversal: pending node pairs.
    pairs: Vec<(u32, u32)>,
    /// Parallel traversals: the tasks.
    tasks: parallel::Tasks,
}

impl<V: BoundingVolume> Bvh<V> {
    /// An empty hierarchy.
    pub fn new() -> Self {
        Self::default()
    }

    /// Builds a hierarchy over `leaves` with a fresh workspace (see [`Bvh::rebuild`]).
    pub fn from_leaves(leaves: &[Leaf<V>]) -> Self {
        let mut bvh = Self::new();
        bvh.rebuild(leaves, &mut BvhWorkspace::default());
        bvh
    }

    /// The nodes; node 0 is the root. Empty when built over no leaves.
    pub fn nodes(&self) -> &[Node<V>] {
        &self.nodes
    }

    /// `true` when the hierarchy holds no leaf.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Number of leaves (a binary tree over `n >= 1` leaves has `2n - 1` nodes).
    pub fn leaf_count(&self) -> usize {
        self.nodes.len().div_ceil(2)
    }

    /// The volume of the root, containing every leaf's; `None` when empty.
    pub fn root_volume(&self) -> Option<&V> {
        self.nodes.first().map(|n| &n.volume)
    }
}

#[cfg(test)]
mod tests;
