//! Refitting: new leaf volumes in the same tree, without rebuilding it.

use rayon::prelude::*;

use super::{BoundingVolume, Bvh, LEAF};

/// Trees with at least this many nodes compute their leaves' new volumes in parallel.
const PARALLEL_NODES: usize = 8192;

impl<V: BoundingVolume> Bvh<V> {
    /// Gives leaf `id` the volume `volume(id)` and every internal node the merge of its
    /// children's, keeping the tree's shape: `O(n)`, much cheaper than [`Bvh::rebuild`]. For a
    /// caller whose leaves' volumes changed but not their ids, e.g. swept volumes shrunk to
    /// `[0, t*]` once a contact at `t*` is known. The tree stays valid for the new volumes,
    /// though it may fit them worse than a rebuild would. `volume` is called once per leaf, on
    /// the current rayon pool for big trees.
    ///
    /// ```
    /// use topoccd::bvh::{Bvh, Leaf};
    /// use topoccd::kdop::Kdop;
    /// use topoccd::math::DVec3;
    /// let at = |x: f64| Kdop::<9>::from_points(&[DVec3::splat(x), DVec3::splat(x + 1.0)]);
    /// let leaves: Vec<_> = (0..50u32).map(|i| Leaf { id: i, volume: at(2.0 * i as f64) }).collect();
    /// let mut bvh = Bvh::from_leaves(&leaves);
    /// // Every leaf moves by 3.
    /// let moved: Vec<_> = leaves.iter().map(|l| Leaf { id: l.id, volume: at(2.0 * l.id as f64 + 3.0) }).collect();
    /// bvh.refit(|id| moved[id as usize].volume);
    /// assert!(bvh.validate(&moved).is_ok());
    /// ```
    pub fn refit(&mut self, volume: impl Fn(u32) -> V + Sync + Send) {
        if self.nodes.len() >= PARALLEL_NODES {
            self.nodes.par_iter_mut().for_each(|n| {
                if n.b == LEAF {
                    n.volume = volume(n.a);
                }
            });
        } else {
            for n in self.nodes.iter_mut().filter(|n| n.b == LEAF) {
                n.volume = volume(n.a);
            }
        }
        // Children come after their parents.
        for i in (0..self.nodes.len()).rev() {
            let n = self.nodes[i];
            if n.b != LEAF {
                debug_assert!(n.a as usize > i && n.b as usize > i);
                self.nodes[i].volume = self.nodes[n.a as usize]
                    .volume
                    .merge(&self.nodes[n.b as usize].volume);
            }
        }
    }
}
