//! The per-step hierarchy (the paper's baseline, as in Self-CCD): a k-DOP tree over the
//! triangles' swept volumes, built anew for every new topology (refitted while the triangles
//! stay the same and the tree fits them), traversed against itself; every overlapping
//! triangle pair gives the feature pairs its two triangles own.
//!
//! The traversal runs on the rayon pool as a fixed list of tasks (see
//! [`Bvh::par_self_pairs_with`]); each task gets its own accumulator, so the caller can run the
//! narrow phase inside the tasks on bounded buffers.

use std::ops::ControlFlow;

use super::{triangle_volume, BroadInput, TaskPairs};
use crate::bvh::{Bvh, BvhError, BvhWorkspace, Leaf, ParOptions};
use crate::kdop::Kdop;
use crate::math::{lerp, DVec3};
use crate::mesh::Step;

/// The hierarchy of one k-DOP type over the triangles' swept volumes (leaf `t` is triangle
/// `t`), kept for reuse across steps. The leaves' volumes live in the tree's nodes only: they
/// are computed from the positions where the build or the refit places them.
#[derive(Clone, Debug, Default)]
pub(crate) struct PerStepBvh<const H: usize> {
    bvh: Bvh<Kdop<H>>,
    /// The end of the times the leaves' volumes are swept over, and their inflation.
    swept: (f64, f64),
    /// What the tree's shape was built for, while it may still be refitted.
    shape: Option<Shape>,
    /// Whether the last [`PerStepBvh::build`] refitted the tree rather than rebuilt it.
    pub refitted: bool,
}

/// The volumes a hierarchy's shape was built for, and how well it fitted them.
#[derive(Clone, Copy, Debug)]
struct Shape {
    /// The end of the times swept and the inflation.
    t_max: f64,
    sep: f64,
    /// [`spread`] right after the build; `None` until a refit first needs it (until then the
    /// tree is as built, so it is measured then).
    spread: Option<f64>,
}

/// A refitted tree is kept while its [`spread`] stays within this factor of its spread when
/// built; past it, the tree is rebuilt.
const REFIT_SPREAD: f64 = 1.25;

/// How loosely a tree fits its leaves: the sum of its internal nodes' extents (the widths of
/// their first three slabs, the axes) over the root's extent. A tree refitted to leaves that
/// moved apart from their neighbours of the build has bigger internal nodes, which overlap
/// more and cost the traversal more tests.
fn spread<const H: usize>(bvh: &Bvh<Kdop<H>>) -> f64 {
    let extent = |v: &Kdop<H>| (0..3).map(|i| v.hi[i] - v.lo[i]).sum::<f64>();
    let Some(root) = bvh.root_volume() else {
        return 0.0;
    };
    let inner: f64 = (bvh.nodes().iter())
        .filter(|n| n.children().is_some())
        .map(|n| extent(&n.volume))
        .sum();
    inner / extent(root)
}

impl<const H: usize> PerStepBvh<H> {
    /// Fits the hierarchy to the volumes swept by the step's triangles over `[0, t_max]` (the
    /// whole step for `t_max >= 1`), inflated by `sep`. It needs the positions and triangles
    /// only, not the step's topology.
    ///
    /// With `same_triangles` (the step has the very triangles of the last step this was
    /// built for), and volumes swept over the same times with the same inflation, the last
    /// tree is refitted (`O(n)`, as Self-CCD does every step) rather than rebuilt, unless the
    /// refitted tree fits its leaves much worse than when it was built ([`REFIT_SPREAD`]).
    /// Either way every node contains its leaves, so what the traversal reports is the same.
    pub fn build(
        &mut self,
        step: &Step,
        (t_max, sep): (f64, f64),
        same_triangles: bool,
        ws: &mut BvhWorkspace,
    ) {
        let volume = triangle_volume::<H>(step, t_max, sep);
        self.swept = (t_max, sep);
        let kept = self.shape.filter(|s| same_triangles && s.t_max == t_max && s.sep == sep);
        if let Some(shape) = kept {
            let built = shape.spread.unwrap_or_else(|| spread(&self.bvh));
            self.bvh.refit(volume);
            self.refitted = spread(&self.bvh) <= REFIT_SPREAD * built;
            if self.refitted {
                self.shape = Some(Shape {
                    spread: Some(built),
                    ..shape
                });
                return;
            }
        }
        self.refitted = false;
        let (x0, x1, tris) = (step.pos0(), step.pos1(), step.triangles());
        // A leaf stands for its triangle's box at 0 and at `t_max` when splitting.
        let t_end = t_max.clamp(0.0, 1.0);
        let center = |t: usize| {
            let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
            for &v in &tris[t] {
                let (a, b) = (x0[v as usize], x1[v as usize]);
                let c = lerp(a, b, t_end);
                lo = lo.min(a).min(c);
                hi = hi.max(a).max(c);
            }
            (lo + hi) * 0.5
        };
        self.bvh.rebuild_from_fn(tris.len(), center, volume, ws);
        self.shape = Some(Shape {
            t_max,
            sep,
            spread: None,
        });
    }

    /// Refits the hierarchy to the volumes swept over the times searched, `[0, t_max]` (same
    /// tree, linear time): the leaves a build for those times has.
    pub fn refit_until_t_max(&mut self, input: &BroadInput<'_, '_>) {
        // The tree is about to stop being as built: measure its fit first.
        if let Some(shape) = &mut self.shape {
            if shape.spread.is_none() {
                shape.spread = Some(spread(&self.bvh));
            }
        }
        let (sep, t_max) = (input.filter.sep, input.filter.t_max());
        self.swept = (t_max, sep);
        self.bvh.refit(triangle_volume::<H>(input.step, t_max, sep));
    }

    /// Checks the hierarchy of the last step, `step`, against its leaves: the triangles'
    /// volumes swept over the times it was last fitted to.
    pub fn validate(&self, step: &Step) -> Result<(), BvhError> {
        let (t_max, sep) = self.swept;
        let volume = triangle_volume::<H>(step, t_max, sep);
        let leaves: Vec<Leaf<Kdop<H>>> = (0..step.triangles().len() as u32)
            .map(|t| Leaf {
                id: t,
                volume: volume(t),
            })
            .collect();
        self.bvh.validate(&leaves)
    }
}

/// Every overlapping pair of triangles of the hierarchy, each once (see [`TaskPairs`]).
impl<const H: usize> TaskPairs for PerStepBvh<H> {
    fn pairs<T: Send>(
        &self,
        ws: &mut BvhWorkspace,
        par: &ParOptions,
        make: impl Fn(usize) -> T + Sync + Send,
        pair: impl Fn(&mut T, u32, u32) + Sync + Send,
        finish: impl Fn(&mut T) + Sync + Send,
        consume: impl FnMut(T) -> ControlFlow<()>,
        skip: &(dyn Fn(&T) -> bool + Sync),
    ) -> u64 {
        self.bvh
            .par_self_pairs_until(ws, par, make, pair, finish, consume, skip)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A strip of `n` triangles along x, each vertex at `place(i)`, not moving in the step.
    fn strip(n: u32, place: impl Fn(u32) -> DVec3) -> Step<'static> {
        let x: Vec<[f64; 3]> = (0..n + 2).map(|i| place(i).to_array()).collect();
        let tris: Vec<[u32; 3]> = (0..n).map(|i| [i, i + 1, i + 2]).collect();
        Step::new(x.clone(), x, tris).expect("a valid step")
    }

    /// The same triangles again are refitted while the tree fits them, and rebuilt once the
    /// refitted tree would fit them much worse; over other times swept, or after a step of
    /// other triangles, the tree is rebuilt. Every tree holds its leaves.
    #[test]
    fn refits_only_while_the_tree_fits() {
        let along = |i: u32| DVec3::new(i as f64 * 0.5, (i % 2) as f64, 0.0);
        let mut tree = PerStepBvh::<9>::default();
        let mut ws = BvhWorkspace::default();
        let whole = (1.0, 0.0);
        tree.build(&strip(400, along), whole, true, &mut ws);
        assert!(!tree.refitted, "nothing to refit at first");
        // Shifted and slightly stretched: the same neighbours, refitted.
        let moved = |i: u32| along(i) * 1.01 + DVec3::new(3.0, 1.0, 0.0);
        let step = strip(400, moved);
        tree.build(&step, whole, true, &mut ws);
        assert!(tree.refitted);
        assert_eq!(tree.validate(&step), Ok(()));
        // The strip folded in two onto itself: leaves far apart in the tree overlap now, and
        // the refitted tree fits them loosely.
        let folded = |i: u32| {
            let x = (i as f64 * 0.5) % 100.0;
            DVec3::new(if i < 201 { x } else { 100.0 - x }, (i % 2) as f64, 0.0)
        };
        let step = strip(400, folded);
        tree.build(&step, whole, true, &mut ws);
        assert!(!tree.refitted, "a tree this loose is rebuilt");
        assert_eq!(tree.validate(&step), Ok(()));
        tree.build(&step, (0.5, 0.0), true, &mut ws);
        assert!(!tree.refitted, "other times swept");
        tree.build(&step, (0.5, 0.0), false, &mut ws);
        assert!(!tree.refitted, "other triangles");
        tree.build(&step, (0.5, 0.0), true, &mut ws);
        assert!(tree.refitted);
        assert_eq!(tree.validate(&step), Ok(()));
    }
}
