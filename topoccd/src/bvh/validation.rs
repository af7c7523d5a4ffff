//! The validator: the tree's shape and volumes against its leaves.

use super::{BoundingVolume, Bvh, Leaf};
use thiserror::Error;

/// A broken invariant of a [`Bvh`], found by [`Bvh::validate`].
#[derive(Debug, Error, Clone, PartialEq, Eq)]
pub enum BvhError {
    /// The tree has the wrong number of nodes for its leaves.
    #[error("{nodes} nodes for {leaves} leaves (a binary tree needs 2n - 1)")]
    NodeCount {
        /// Number of nodes.
        nodes: usize,
        /// Number of leaves given.
        leaves: usize,
    },
    /// A child index points outside the node array or to a node already reached.
    #[error("node {node} has a child {child} that is out of range or reached twice")]
    BadChild {
        /// The parent node.
        node: usize,
        /// The offending child index.
        child: u32,
    },
    /// A node's volume does not contain one of its children's.
    #[error("node {node} does not contain its child {child}")]
    NotContained {
        /// The parent node.
        node: usize,
        /// The child node.
        child: u32,
    },
    /// A leaf id is unknown, appears twice, or its volume differs from the given one.
    #[error("leaf id {id} is unknown, repeated, or has the wrong volume")]
    BadLeaf {
        /// The leaf id.
        id: u32,
    },
    /// A given leaf is missing from the tree.
    #[error("leaf id {id} is missing from the tree")]
    MissingLeaf {
        /// The leaf id.
        id: u32,
    },
}

impl<V: BoundingVolume + PartialEq> Bvh<V> {
    /// Checks that the tree is a binary tree over exactly `leaves` (each leaf id once, with its
    /// volume), every node reached once from the root, and every node's volume containing its
    /// children's. The ids in `leaves` must be distinct.
    ///
    /// ```
    /// use topoccd::bvh::{Bvh, BvhError, Leaf};
    /// use topoccd::kdop::Kdop;
    /// use topoccd::math::DVec3;
    /// let leaves: Vec<_> = (0..5u32)
    ///     .map(|i| Leaf { id: i, volume: Kdop::<7>::from_point(DVec3::splat(i as f64)) })
    ///     .collect();
    /// let bvh = Bvh::from_leaves(&leaves);
    /// assert_eq!(bvh.validate(&leaves), Ok(()));
    /// assert!(matches!(bvh.validate(&leaves[..4]), Err(BvhError::NodeCount { .. })));
    /// ```
    pub fn validate(&self, leaves: &[Leaf<V>]) -> Result<(), BvhError> {
        let nodes = self.nodes();
        let expected = if leaves.is_empty() {
            0
        } else {
            2 * leaves.len() - 1
        };
        if nodes.len() != expected {
            return Err(BvhError::NodeCount {
                nodes: nodes.len(),
                leaves: leaves.len(),
            });
        }
        if nodes.is_empty() {
            return Ok(());
        }
        let mut by_id: Vec<(u32, usize)> =
            leaves.iter().enumerate().map(|(i, l)| (l.id, i)).collect();
        by_id.sort_unstable();
        let mut seen_leaf = vec![false; leaves.len()];
        let mut seen_node = vec![false; nodes.len()];
        seen_node[0] = true;
        let mut stack = vec![0usize];
        while let Some(n) = stack.pop() {
            let node = &nodes[n];
            match node.children() {
                Some(children) => {
                    for c in children {
                        let ok = (c as usize) < nodes.len() && !seen_node[c as usize];
                        if !ok {
                            return Err(BvhError::BadChild { node: n, child: c });
                        }
                        seen_node[c as usize] = true;
                        if !node.volume.contains(&nodes[c as usize].volume) {
                            return Err(BvhError::NotContained { node: n, child: c });
                        }
                        stack.push(c as usize);
                    }
                }
                None => {
                    let id = node.a;
                    let Ok(k) = by_id.binary_search_by_key(&id, |&(i, _)| i) else {
                        return Err(BvhError::BadLeaf { id });
                    };
                    let index = by_id[k].1;
                    if seen_leaf[index] || leaves[index].volume != node.volume {
                        return Err(BvhError::BadLeaf { id });
                    }
                    seen_leaf[index] = true;
                }
            }
        }
        match seen_leaf.iter().position(|&s| !s) {
            Some(i) => Err(BvhError::MissingLeaf { id: leaves[i].id }),
            None => Ok(()),
        }
    }
}
