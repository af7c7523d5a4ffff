//! The self-traversal's front of unrelated node pairs, kept while the tree's shape and its
//! leaves' relations do not change.
//!
//! A self-traversal descends every pair of subtrees whose volumes overlap. Where the leaves are
//! the triangles of a mesh, two subtrees that share a mesh vertex always overlap (both volumes
//! contain that vertex's path), so the traversal descends them every step, down to the pairs of
//! neighbouring triangles, only to drop those at the leaves: on a mesh, most of a traversal's
//! tests. Which node pairs are *related* (some leaf of one is related to some leaf of the
//! other) depends on the tree's shape and the leaves' relation only, not on the volumes.
//!
//! The *front* is the set of the highest unrelated pairs of the traversal: the unrelated child
//! pairs of related pairs, and the unrelated sibling pairs. Every unrelated pair of leaves lies
//! below exactly one of them, and no related pair of leaves below any. A traversal that starts
//! from the front ([`Bvh::par_front_pairs_until`]) therefore reports every unrelated pair of
//! leaves whose volumes overlap, each once, without a test on the related pairs above it; for
//! a valid tree (every node containing its children) these are exactly the unrelated pairs the
//! full traversal reports. The front stays valid while the tree is only refitted.

use super::traverse::{run, TestAll};
use super::{BoundingVolume, Bvh, LEAF};

impl<V: BoundingVolume> Bvh<V> {
    /// The front of the self-traversal (see the module documentation) into `out`, in a
    /// deterministic order, each pair `(a, b)` of node indices once. `related(a, b)` says
    /// whether the leaves of nodes `a` and `b` are related; it must hold only for leaves whose
    /// volumes overlap (the search takes two subtrees whose volumes are disjoint as unrelated).
    /// Costs about one full traversal.
    pub(crate) fn front(&self, related: &impl Fn(u32, u32) -> bool, out: &mut Vec<(u32, u32)>) {
        out.clear();
        if self.nodes.len() > 1 {
            self.front_of_self(0, related, out);
        }
    }

    /// The front below the self pair of internal node `n`.
    fn front_of_self(&self, n: u32, related: &impl Fn(u32, u32) -> bool, out: &mut Vec<(u32, u32)>) {
        let node = &self.nodes[n as usize];
        let (l, r) = (node.a, node.b);
        for c in [l, r] {
            if self.nodes[c as usize].b != LEAF {
                self.front_of_self(c, related, out);
            }
        }
        if !self.front_of_pair(l, r, related, out) {
            out.push((l, r));
        }
    }

    /// Whether nodes `a` and `b` (distinct, neither below the other) are related; if they are,
    /// the front below them is pushed to `out`. If not, nothing is pushed.
    fn front_of_pair(
        &self,
        a: u32,
        b: u32,
        related: &impl Fn(u32, u32) -> bool,
        out: &mut Vec<(u32, u32)>,
    ) -> bool {
        let (x, y) = (&self.nodes[a as usize], &self.nodes[b as usize]);
        let (x_leaf, y_leaf) = (x.b == LEAF, y.b == LEAF);
        if x_leaf && y_leaf {
            return related(a, b);
        }
        if !x.volume.overlaps(&y.volume) {
            return false;
        }
        // The child pairs the traversal would test, in its order.
        let mut pairs = [(0, 0); 4];
        let count = match (x_leaf, y_leaf) {
            (false, false) => {
                pairs = [(x.a, y.a), (x.a, y.b), (x.b, y.a), (x.b, y.b)];
                4
            }
            (false, true) => {
                pairs[..2].copy_from_slice(&[(x.a, b), (x.b, b)]);
                2
            }
            _ => {
                pairs[..2].copy_from_slice(&[(a, y.a), (a, y.b)]);
                2
            }
        };
        let mut rel = [false; 4];
        for k in 0..count {
            rel[k] = self.front_of_pair(pairs[k].0, pairs[k].1, related, out);
        }
        let any = rel[..count].iter().any(|&r| r);
        if any {
            for k in 0..count {
                if !rel[k] {
                    out.push(pairs[k]);
                }
            }
        }
        any
    }
}

impl<V: BoundingVolume> Bvh<V> {
    /// Calls `leaf_pair(a, b)` for every pair of leaves below the pairs of `front` (a slice of
    /// a [`Bvh::front`]) whose volumes overlap, each once, in a deterministic order: the
    /// traversal of the pairs of the front, one after the other. Returns the bounding-volume
    /// tests made.
    pub(crate) fn front_pairs(
        &self,
        front: &[(u32, u32)],
        stack: &mut Vec<(u32, u32)>,
        leaf_pair: &mut impl FnMut(u32, u32),
    ) -> u64 {
        let nodes = &self.nodes[..];
        let mut tests = front.len() as u64;
        for &(a, b) in front {
            let (x, y) = (&nodes[a as usize], &nodes[b as usize]);
            // Most pairs of the front stay apart: a test without a branch per slab.
            if !x.volume.overlaps(&y.volume) {
                continue;
            }
            if x.b == LEAF && y.b == LEAF {
                leaf_pair(x.a, y.a);
                continue;
            }
            stack.clear();
            stack.push((a, b));
            tests += run(nodes, nodes, stack, &TestAll, leaf_pair);
        }
        tests
    }
}
