//! Top-down construction: median split along the longest axis of the leaves' centres, the two
//! halves built in parallel (rayon) above a size threshold, into a node layout fixed by the
//! subtree sizes alone, so the tree is the same for any thread count.

use rayon::prelude::*;

use super::{BoundingVolume, Bvh, BvhWorkspace, Leaf, Node, LEAF};
use crate::math::DVec3;

/// Ranges of at least this many leaves have their two halves built as two rayon tasks. Below
/// it, a task costs more than it saves. (The output does not depend on it.)
const PARALLEL_LEAVES: usize = 4096;

/// One leaf to place: its volume's centre, each coordinate as an integer ordered as
/// `f64::total_cmp` orders the coordinate (see [`key`]), and its index in the input.
pub(super) type Item = ([u64; 3], u32);

/// The integer whose unsigned order is `f64::total_cmp`'s order of `x`. Comparing these is
/// cheaper than comparing the floats, and [`unkey`] gives `x` back.
#[inline]
fn key(x: f64) -> u64 {
    let bits = x.to_bits();
    if bits >> 63 == 1 {
        !bits
    } else {
        bits | (1 << 63)
    }
}

/// The inverse of [`key`].
#[inline]
fn unkey(k: u64) -> f64 {
    f64::from_bits(if k >> 63 == 1 { k & !(1 << 63) } else { !k })
}

impl<V: BoundingVolume> Bvh<V> {
    /// Rebuilds the hierarchy over `leaves`, reusing this tree's node array and the workspace.
    ///
    /// Top-down: a range of leaves is split at its median along the axis where the leaves'
    /// centres ([`BoundingVolume::center`]) spread most, ties broken by the leaves' positions in
    /// `leaves` (a range of two keeps the order the split above it left), so the tree depends
    /// only on the input. The depth is `ceil(log2 n)`, and the
    /// two children of a node are adjacent in [`Bvh::nodes`] and come after it: an internal
    /// node over `m` leaves with children at `c, c + 1` has the descendants of its first child
    /// (`2 m_1 - 2` nodes) at `c + 2..`, then those of its second child.
    ///
    /// The two halves of a big range are built as two tasks on the current rayon thread pool
    /// (on one thread when called from a pool of one); the node array is the same, bit for bit,
    /// for any number of threads.
    ///
    /// ```
    /// use topoccd::bvh::{Bvh, BvhWorkspace, Leaf};
    /// use topoccd::kdop::Kdop;
    /// use topoccd::math::DVec3;
    /// let leaves: Vec<_> = (0..10u32)
    ///     .map(|i| Leaf { id: 100 + i, volume: Kdop::<9>::from_point(DVec3::splat(i as f64)) })
    ///     .collect();
    /// let mut bvh = Bvh::new();
    /// bvh.rebuild(&leaves, &mut BvhWorkspace::default());
    /// assert_eq!(bvh.nodes().len(), 19);
    /// assert_eq!(bvh.leaf_count(), 10);
    /// assert!(bvh.validate(&leaves).is_ok());
    /// ```
    pub fn rebuild(&mut self, leaves: &[Leaf<V>], ws: &mut BvhWorkspace) {
        self.rebuild_with(
            leaves.len(),
            |i| leaves[i].volume.center(),
            |i| (leaves[i].volume, leaves[i].id),
            ws,
        );
    }

    /// [`Bvh::rebuild`] over `n` leaves whose volumes a function computes: leaf `i` has id `i`
    /// and volume `volume(i)`, computed once, where the build places the leaf (no array of the
    /// volumes is made); `center(i)` stands for the leaf when splitting (any point that
    /// represents its volume, e.g. its box's centre). The tree is the one [`Bvh::rebuild`]
    /// builds over leaves with those volumes whose [`BoundingVolume::center`] is `center(i)`.
    ///
    /// ```
    /// use topoccd::bvh::{Bvh, BvhWorkspace, Leaf};
    /// use topoccd::kdop::Kdop;
    /// use topoccd::math::DVec3;
    /// let volume = |i: u32| Kdop::<9>::from_point(DVec3::splat(i as f64));
    /// let mut bvh = Bvh::new();
    /// bvh.rebuild_from_fn(10, |i| DVec3::splat(i as f64), volume, &mut BvhWorkspace::default());
    /// let leaves: Vec<_> = (0..10).map(|i| Leaf { id: i, volume: volume(i) }).collect();
    /// assert!(bvh.validate(&leaves).is_ok());
    /// ```
    pub fn rebuild_from_fn(
        &mut self,
        n: usize,
        center: impl Fn(usize) -> DVec3 + Sync,
        volume: impl Fn(u32) -> V + Sync,
        ws: &mut BvhWorkspace,
    ) {
        self.rebuild_with(n, center, |i| (volume(i as u32), i as u32), ws);
    }

    /// The build over `n` leaves, leaf `i` being `leaf(i) = (volume, id)` and splitting by
    /// `center(i)`.
    fn rebuild_with(
        &mut self,
        n: usize,
        center: impl Fn(usize) -> DVec3 + Sync,
        leaf: impl Fn(usize) -> (V, u32) + Sync,
        ws: &mut BvhWorkspace,
    ) {
        if n == 0 {
            self.nodes.clear();
            return;
        }
        // Node indices are u32 with the top bit free (the traversals tag pairs with it).
        assert!(n <= 1 << 30, "too many leaves for a hierarchy: at most 2^30");
        let items = &mut ws.items;
        let item = |i: usize| (center(i).to_array().map(key), i as u32);
        if n >= PARALLEL_LEAVES {
            (0..n).into_par_iter().map(item).collect_into_vec(items);
        } else {
            items.clear();
            items.extend((0..n).map(item));
        }
        let placeholder = Node {
            volume: leaf(0).0,
            a: 0,
            b: LEAF,
        };
        // Every node is written by the build: only grow (or shrink) the array, so that a tree
        // rebuilt over as many leaves as last time is written once, not twice. A big array is
        // grown on the pool: its first writes are what maps its pages.
        let len = 2 * n - 1;
        self.nodes.truncate(len);
        let more = len - self.nodes.len();
        if more >= PARALLEL_LEAVES {
            self.nodes
                .par_extend(rayon::iter::repeat_n(placeholder, more));
        } else {
            self.nodes.resize(len, placeholder);
        }
        let (root, rest) = self.nodes.split_at_mut(1);
        build(&leaf, items, &mut root[0], rest, 1);
    }
}

/// Builds the subtree over `items` (not empty): writes its root node into `out` and its
/// other `2 m - 2` nodes into `block`, whose first node has index `base` in the whole array.
/// (Nodes are written where they go, never returned: they are big.)
fn build<V: BoundingVolume>(
    leaf: &(impl Fn(usize) -> (V, u32) + Sync),
    items: &mut [Item],
    out: &mut Node<V>,
    block: &mut [Node<V>],
    base: u32,
) {
    debug_assert_eq!(block.len() + 2, 2 * items.len());
    let len = items.len();
    if len == 1 {
        let (volume, id) = leaf(items[0].1 as usize);
        *out = Node {
            volume,
            a: id,
            b: LEAF,
        };
        return;
    }
    let mid = len / 2;
    // Two leaves need no split (their order in the array is as deterministic as any).
    if len > 2 {
        let axis = longest_axis(items);
        items.select_nth_unstable_by(mid, |x, y| (x.0[axis], x.1).cmp(&(y.0[axis], y.1)));
    }
    let (first, second) = items.split_at_mut(mid);
    let (pair, rest) = block.split_at_mut(2);
    let (out1, out2) = pair.split_at_mut(1);
    let (out1, out2) = (&mut out1[0], &mut out2[0]);
    let (block1, block2) = rest.split_at_mut(2 * first.len() - 2);
    let base1 = base + 2;
    let base2 = base1 + block1.len() as u32;
    if len >= PARALLEL_LEAVES {
        rayon::join(
            || build(leaf, first, out1, block1, base1),
            || build(leaf, second, out2, block2, base2),
        );
    } else {
        build(leaf, first, out1, block1, base1);
        build(leaf, second, out2, block2, base2);
    }
    out.volume = out1.volume.merge(&out2.volume);
    out.a = base;
    out.b = base + 1;
}

/// The axis along which the centres spread most.
fn longest_axis(range: &[Item]) -> usize {
    let mut lo = [u64::MAX; 3];
    let mut hi = [0u64; 3];
    for (c, _) in range {
        for k in 0..3 {
            lo[k] = lo[k].min(c[k]);
            hi[k] = hi[k].max(c[k]);
        }
    }
    let ext: [f64; 3] = std::array::from_fn(|k| unkey(hi[k]) - unkey(lo[k]));
    if ext[0] >= ext[1] && ext[0] >= ext[2] {
        0
    } else if ext[1] >= ext[2] {
        1
    } else {
        2
    }
}

#[cfg(test)]
mod tests {
    use super::{key, unkey};

    #[test]
    fn keys_order_as_total_cmp_and_invert() {
        let xs = [
            f64::NEG_INFINITY,
            -1e300,
            -1.5,
            -f64::MIN_POSITIVE,
            -0.0,
            0.0,
            5e-324,
            1.0,
            2.5,
            1e300,
            f64::INFINITY,
        ];
        for (i, &x) in xs.iter().enumerate() {
            assert_eq!(unkey(key(x)).to_bits(), x.to_bits());
            for &y in &xs[i + 1..] {
                assert!(key(x) < key(y), "{x} {y}");
            }
        }
        let nan = f64::NAN;
        assert_eq!(unkey(key(nan)).to_bits(), nan.to_bits());
        assert_eq!(key(nan).cmp(&key(1.0)), nan.total_cmp(&1.0));
        assert_eq!(key(-nan).cmp(&key(-1.0)), (-nan).total_cmp(&-1.0));
    }
}
