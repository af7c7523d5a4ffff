//! The per-step hierarchy (the paper's baseline, as in Self-CCD): a k-DOP tree over the
//! triangles' swept volumes, built anew for every new topology (refitted while the triangles
//! stay the same and the tree fits them), traversed against itself; every overlapping
//! triangle pair gives the feature pairs its two triangles own.
//!
//! The traversal runs on the rayon pool as a fixed list of tasks (see
//! [`Bvh::par_self_pairs_with`]); each task gets its own accumulator, so the caller can run the
//! narrow phase inside the tasks on bounded buffers.

use std::ops::ControlFlow;
use std::time::Instant;

use super::{triangle_volumes_until, BroadInput, TaskPairs};
use crate::bvh::{Bvh, BvhError, BvhWorkspace, Leaf, ParOptions};
use crate::kdop::Kdop;
use crate::mesh::Step;

/// The triangles' volumes (leaf `t` is triangle `t`) and hierarchy of one k-DOP type, kept
/// for reuse across steps.
#[derive(Clone, Debug, Default)]
pub(crate) struct PerStepBvh<const H: usize> {
    volumes: Vec<Kdop<H>>,
    bvh: Bvh<Kdop<H>>,
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
    /// [`spread`] right after the build.
    spread: f64,
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
    /// Computes the volumes swept by the step's triangles over `[0, t_max]` (the whole step
    /// for `t_max >= 1`), inflated by `sep`, and fits the hierarchy to them. It needs the
    /// positions and triangles only, not the step's topology.
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
        triangle_volumes_until(step, t_max, sep, &mut self.volumes);
        let kept = self.shape.filter(|s| same_triangles && s.t_max == t_max && s.sep == sep);
        if let Some(shape) = kept {
            let volumes = &self.volumes;
            self.bvh.refit(|id| volumes[id as usize]);
            self.refitted = spread(&self.bvh) <= REFIT_SPREAD * shape.spread;
            if self.refitted {
                return;
            }
        }
        self.refitted = false;
        self.bvh.rebuild_from_volumes(&self.volumes, ws);
        let spread = spread(&self.bvh);
        self.shape = Some(Shape { t_max, sep, spread });
    }

    /// Recomputes the volumes over the whole step and refits the hierarchy to them (same
    /// tree, linear time). Returns the seconds spent.
    pub fn refit_whole_step(&mut self, input: &BroadInput<'_, '_>) -> f64 {
        let start = Instant::now();
        triangle_volumes_until(input.step, 1.0, input.filter.sep, &mut self.volumes);
        let volumes = &self.volumes;
        self.bvh.refit(|id| volumes[id as usize]);
        start.elapsed().as_secs_f64()
    }

    /// Checks the hierarchy of the last step against its leaves.
    pub fn validate(&self) -> Result<(), BvhError> {
        let leaves: Vec<Leaf<Kdop<H>>> = (self.volumes.iter().enumerate())
            .map(|(t, &volume)| Leaf {
                id: t as u32,
                volume,
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
        make: impl Fn() -> T + Sync + Send,
        pair: impl Fn(&mut T, u32, u32) + Sync + Send,
        finish: impl Fn(&mut T) + Sync + Send,
        consume: impl FnMut(T) -> ControlFlow<()>,
    ) -> u64 {
        self.bvh
            .par_self_pairs_until(ws, par, make, pair, finish, consume)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::DVec3;

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
        tree.build(&strip(400, moved), whole, true, &mut ws);
        assert!(tree.refitted);
        assert_eq!(tree.validate(), Ok(()));
        // The strip folded in two onto itself: leaves far apart in the tree overlap now, and
        // the refitted tree fits them loosely.
        let folded = |i: u32| {
            let x = (i as f64 * 0.5) % 100.0;
            DVec3::new(if i < 201 { x } else { 100.0 - x }, (i % 2) as f64, 0.0)
        };
        tree.build(&strip(400, folded), whole, true, &mut ws);
        assert!(!tree.refitted, "a tree this loose is rebuilt");
        assert_eq!(tree.validate(), Ok(()));
        tree.build(&strip(400, folded), (0.5, 0.0), true, &mut ws);
        assert!(!tree.refitted, "other times swept");
        tree.build(&strip(400, folded), (0.5, 0.0), false, &mut ws);
        assert!(!tree.refitted, "other triangles");
        tree.build(&strip(400, folded), (0.5, 0.0), true, &mut ws);
        assert!(tree.refitted);
        assert_eq!(tree.validate(), Ok(()));
    }
}
