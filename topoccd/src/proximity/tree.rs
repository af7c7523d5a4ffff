//! The proximity hierarchy: a tree over the leaves' boxes (triangles, free edges, free
//! points), the `f32` boxes of `boxes` (inflated by half the reach of any pair), so that two
//! leaves whose features may be kept have overlapping boxes. Kept across queries and
//! refitted while the primitives stay the same; rebuilt when they change or when refitting
//! has loosened the tree too much.

use crate::bvh::{Bvh, BvhWorkspace};
use crate::math::DVec3;

use super::boxes::{leaf_box, Box3};
use super::primitives::Primitives;

/// Rebuild once the refitted tree's internal volumes have grown this much (the sum of their
/// extents, net of a change of the leaves' inflation) over the tree's as built.
const LOOSENESS: f64 = 1.5;

/// The proximity hierarchy and its leaves' volumes.
#[derive(Clone, Debug, Default)]
pub(crate) struct ProximityTree {
    pub bvh: Bvh<Box3>,
    /// The sum of the internal nodes' extents when built.
    built_size: f64,
    /// The leaves' inflation when built.
    built_h: f64,
    /// Whether the hierarchy holds a tree for the current primitives.
    valid: bool,
}

/// The sum of the internal nodes' extents.
fn size(bvh: &Bvh<Box3>) -> f64 {
    (bvh.nodes().iter())
        .filter(|n| n.children().is_some())
        .map(|n| n.volume.extent())
        .sum()
}

impl ProximityTree {
    /// Forgets the tree (the primitives changed).
    pub fn invalidate(&mut self) {
        self.valid = false;
    }

    /// Fits the tree to positions `x`, the leaves' boxes inflated by `h` (see
    /// `boxes::inflation`): refits the tree kept (same primitives), unless it has loosened
    /// too much; else builds it. Returns whether it was refitted.
    pub fn fit(&mut self, prims: &Primitives, x: &[DVec3], h: f64, ws: &mut BvhWorkspace) -> bool {
        let volume = |i: u32| leaf_box(prims, x, h, i);
        if self.valid && self.bvh.leaf_count() == prims.leaves.len() {
            self.bvh.refit(volume);
            // The growth of the geometry, net of a change of inflation (which widens every
            // internal node by twice the change on each of the three axes).
            let internal = self.bvh.leaf_count().saturating_sub(1) as f64;
            let s = size(&self.bvh) - 6.0 * internal * (h - self.built_h);
            if s.is_finite() && s <= LOOSENESS * self.built_size {
                return true;
            }
        }
        let center = |i: usize| {
            let l = &prims.leaves[i];
            let (lo, hi) = (l.vertices().iter())
                .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &v| {
                    (lo.min(x[v as usize]), hi.max(x[v as usize]))
                });
            (lo + hi) * 0.5
        };
        self.bvh
            .rebuild_from_fn(prims.leaves.len(), center, volume, ws);
        self.built_size = size(&self.bvh);
        self.built_h = h;
        self.valid = true;
        false
    }
}
