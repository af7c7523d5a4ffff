//! The proximity hierarchy: a tree over the leaves' boxes (triangles, free edges, free
//! points), each inflated by half the threshold (and a margin for the rounding bound), so
//! that two leaves whose features may be kept have overlapping boxes. Kept across queries and
//! refitted while the primitives stay the same; rebuilt when they change or when refitting
//! has loosened the tree too much.

use crate::bvh::{Bvh, BvhWorkspace};
use crate::kdop::Kdop;
use crate::math::{DVec3, UNIT_ROUNDOFF};

use super::primitives::Primitives;

/// Rebuild once the refitted tree's internal volumes have grown this much (the sum of their
/// extents) over the tree's as built.
const LOOSENESS: f64 = 1.5;

/// The proximity hierarchy and its leaves' volumes.
#[derive(Clone, Debug, Default)]
pub(crate) struct ProximityTree {
    pub bvh: Bvh<Kdop<3>>,
    /// The sum of the internal nodes' extents when built.
    built_size: f64,
    /// Whether the hierarchy holds a tree for the current primitives.
    valid: bool,
}

/// The box of `leaf` at positions `x`, inflated for threshold `r`.
#[inline]
pub(crate) fn leaf_box(prims: &Primitives, x: &[DVec3], r: f64, leaf: u32) -> Kdop<3> {
    let l = &prims.leaves[leaf as usize];
    let mut lo = x[l.verts[0] as usize];
    let mut hi = lo;
    for &v in &l.vertices()[1..] {
        lo = lo.min(x[v as usize]);
        hi = hi.max(x[v as usize]);
    }
    let diam = (hi - lo).max_element();
    let coord = lo.abs().max(hi.abs()).max_element();
    // Half the threshold, the rounding bound's share (see `pairs::Test::reach`), and the
    // rounding of the inflation itself.
    let h = 0.5 * r * (1.0 + 1e-6) + 1e-7 * diam + 4.0 * UNIT_ROUNDOFF * coord;
    Kdop {
        lo: (lo - h).to_array(),
        hi: (hi + h).to_array(),
    }
}

/// The sum of the internal nodes' extents.
fn size(bvh: &Bvh<Kdop<3>>) -> f64 {
    (bvh.nodes().iter())
        .filter(|n| n.children().is_some())
        .map(|n| (0..3).map(|i| n.volume.hi[i] - n.volume.lo[i]).sum::<f64>())
        .sum()
}

impl ProximityTree {
    /// Forgets the tree (the primitives changed).
    pub fn invalidate(&mut self) {
        self.valid = false;
    }

    /// Fits the tree to positions `x`: refits the tree kept (same primitives), unless it has
    /// loosened too much; else builds it. Returns whether it was refitted.
    pub fn fit(&mut self, prims: &Primitives, x: &[DVec3], r: f64, ws: &mut BvhWorkspace) -> bool {
        let volume = |i: u32| leaf_box(prims, x, r, i);
        if self.valid && self.bvh.leaf_count() == prims.leaves.len() {
            self.bvh.refit(volume);
            let s = size(&self.bvh);
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
        self.valid = true;
        false
    }
}
