//! The per-step hierarchy (the paper's baseline, as in Self-CCD): a k-DOP tree over the
//! triangles' swept volumes, built anew every step, traversed against itself; every
//! overlapping triangle pair gives the feature pairs its two triangles own.
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
}

impl<const H: usize> PerStepBvh<H> {
    /// Computes the volumes swept by the step's triangles over `[0, t_max]` (the whole step
    /// for `t_max >= 1`), inflated by `sep`, and builds the hierarchy over them. It needs the
    /// positions and triangles only, not the step's topology.
    pub fn build(&mut self, step: &Step, t_max: f64, sep: f64, ws: &mut BvhWorkspace) {
        triangle_volumes_until(step, t_max, sep, &mut self.volumes);
        self.bvh.rebuild_from_volumes(&self.volumes, ws);
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
