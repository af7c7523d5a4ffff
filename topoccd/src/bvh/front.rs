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
//! from the front ([`Bvh::front_pairs`]) therefore reports every unrelated pair of
//! leaves whose volumes overlap, each once, without a test on the related pairs above it; for
//! a valid tree (every node containing its children) these are exactly the unrelated pairs the
//! full traversal reports. The front stays valid while the tree is only refitted.

use super::traverse::{run, TestAll};
use super::{BoundingVolume, Bvh, LEAF};

/// A front kept with its tree, in blocks: the block of an internal node is the front below
/// the pair of its two children. A change of relation below some leaves changes only the
/// blocks of their ancestors ([`Bvh::update_front_within`]).
#[derive(Clone, Debug, Default)]
pub(crate) struct Front {
    /// The pairs of the front, block after block, the internal nodes in post-order.
    pub pairs: Vec<(u32, u32)>,
    /// Per node: the start and the length of its block in `pairs` (empty for a leaf).
    blocks: Vec<(u32, u32)>,
    /// Scratch memory for the next `pairs` and `blocks`.
    next_pairs: Vec<(u32, u32)>,
    next_blocks: Vec<(u32, u32)>,
}

/// The next front's pairs and blocks, as they are written.
type BlocksOut<'a> = (&'a mut Vec<(u32, u32)>, &'a mut [(u32, u32)]);

/// The blocks of a front, read while the next are written.
#[derive(Clone, Copy)]
struct Blocks<'a> {
    pairs: &'a [(u32, u32)],
    blocks: &'a [(u32, u32)],
}

impl<V: BoundingVolume> Bvh<V> {
    /// Computes the front of the self-traversal (see the module documentation) into `front`,
    /// in a deterministic order, each pair `(a, b)` of node indices once, looking at `budget`
    /// node pairs at most: returns whether that was enough. If not, `front` holds no front (on
    /// a mesh collapsed to a few points every pair of subtrees overlaps, and the search would
    /// look at every pair of leaves). `related(a, b)` says whether the leaves of nodes `a` and
    /// `b` are related; it must hold only for leaves whose volumes overlap (the search takes
    /// two subtrees whose volumes are disjoint as unrelated). Costs about one full traversal.
    pub(crate) fn front_within(
        &self,
        related: &impl Fn(u32, u32) -> bool,
        front: &mut Front,
        budget: u64,
    ) -> bool {
        front.blocks.clear();
        self.update_front_within(related, &|_| true, front, budget)
    }

    /// [`Bvh::front_within`] without a budget, for the tests.
    #[cfg(test)]
    pub(crate) fn front(&self, related: &impl Fn(u32, u32) -> bool, front: &mut Front) {
        assert!(self.front_within(related, front, u64::MAX));
    }

    /// [`Bvh::update_front_within`] without a budget, for the tests.
    #[cfg(test)]
    pub(crate) fn update_front(
        &self,
        related: &impl Fn(u32, u32) -> bool,
        dirty: &impl Fn(u32) -> bool,
        front: &mut Front,
    ) {
        assert!(self.update_front_within(related, dirty, front, u64::MAX));
    }

    /// Recomputes the blocks of the nodes that `dirty` names (by node index) and keeps the
    /// others: the front of [`Bvh::front_within`] for a relation that changed only between
    /// leaves below dirty nodes, when the tree's shape is the one `front` was computed for (a
    /// refit keeps it). Every ancestor of a dirty node must be dirty. Costs the dirty blocks,
    /// plus a copy of the others; looks at `budget` node pairs at most, and returns whether
    /// that was enough (if not, `front` holds no front).
    pub(crate) fn update_front_within(
        &self,
        related: &impl Fn(u32, u32) -> bool,
        dirty: &impl Fn(u32) -> bool,
        front: &mut Front,
        budget: u64,
    ) -> bool {
        let mut left = budget;
        let mut pairs = std::mem::take(&mut front.next_pairs);
        let mut blocks = std::mem::take(&mut front.next_blocks);
        pairs.clear();
        blocks.clear();
        blocks.resize(self.nodes.len(), (0, 0));
        if self.nodes.len() > 1 {
            let old = Blocks {
                pairs: &front.pairs,
                blocks: &front.blocks,
            };
            self.front_blocks(0, related, dirty, old, (&mut pairs, &mut blocks), &mut left);
        }
        if left == 0 {
            front.pairs.clear();
            front.blocks.clear();
            (front.next_pairs, front.next_blocks) = (pairs, blocks);
            return false;
        }
        front.next_pairs = std::mem::replace(&mut front.pairs, pairs);
        front.next_blocks = std::mem::replace(&mut front.blocks, blocks);
        true
    }

    /// The blocks of internal node `n`'s subtree, in post-order, into `out` and `blocks`: the
    /// old ones where `dirty` does not name the node, else computed anew. Stops early once
    /// `left`, the node pairs it may still look at, is 0.
    fn front_blocks(
        &self,
        n: u32,
        related: &impl Fn(u32, u32) -> bool,
        dirty: &impl Fn(u32) -> bool,
        old: Blocks<'_>,
        (out, blocks): BlocksOut<'_>,
        left: &mut u64,
    ) {
        let node = &self.nodes[n as usize];
        let (l, r) = (node.a, node.b);
        for c in [l, r] {
            if self.nodes[c as usize].b != LEAF && *left > 0 {
                self.front_blocks(c, related, dirty, old, (out, blocks), left);
            }
        }
        if *left == 0 {
            return;
        }
        let start = out.len();
        if dirty(n) {
            if !self.front_of_pair(l, r, related, out, left) {
                out.push((l, r));
            }
        } else {
            let (from, len) = old.blocks[n as usize];
            out.extend_from_slice(&old.pairs[from as usize..(from + len) as usize]);
        }
        blocks[n as usize] = (start as u32, (out.len() - start) as u32);
    }

    /// Whether nodes `a` and `b` (distinct, neither below the other) are related; if they are,
    /// the front below them is pushed to `out`. If not, nothing is pushed. Each pair looked at
    /// takes one from `left`; once it is 0 the answer is meaningless (the caller drops it).
    fn front_of_pair(
        &self,
        a: u32,
        b: u32,
        related: &impl Fn(u32, u32) -> bool,
        out: &mut Vec<(u32, u32)>,
        left: &mut u64,
    ) -> bool {
        if *left == 0 {
            return false;
        }
        *left -= 1;
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
            rel[k] = self.front_of_pair(pairs[k].0, pairs[k].1, related, out, left);
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
    /// a [`Bvh::front_within`]) whose volumes overlap, each once, in a deterministic order: the
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
        for (i, &(a, b)) in front.iter().enumerate() {
            // The pairs of the front are known ahead: fetch the nodes of a later one.
            if let Some(&(p, q)) = front.get(i + PREFETCH_AHEAD) {
                prefetch(&nodes[p as usize]);
                prefetch(&nodes[q as usize]);
            }
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

/// How many pairs ahead [`Bvh::front_pairs`] fetches nodes.
const PREFETCH_AHEAD: usize = 8;

/// Asks the processor to bring `node` into the cache (a hint; nothing on other targets).
#[inline(always)]
fn prefetch<T>(node: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let p = node as *const T as *const i8;
        // SAFETY: prefetching is a hint that never faults; the lines lie within `node`.
        unsafe {
            for line in (0..std::mem::size_of::<T>()).step_by(64) {
                _mm_prefetch::<_MM_HINT_T0>(p.add(line));
            }
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = node;
}
