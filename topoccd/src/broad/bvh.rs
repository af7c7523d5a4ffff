//! The per-step hierarchy (the paper's baseline, as in Self-CCD): a k-DOP tree over the
//! triangles' swept volumes, built anew every step, traversed against itself; every
//! overlapping triangle pair gives the feature pairs its two triangles own.

use std::time::Instant;

use super::{triangle_volumes, BroadInput, BroadStats, Candidates};
use crate::bvh::{Bvh, BvhError, BvhWorkspace, Leaf};
use crate::kdop::Kdop;

/// The leaves and hierarchy of one k-DOP type, kept for reuse across steps.
#[derive(Clone, Debug, Default)]
pub(crate) struct PerStepBvh<const H: usize> {
    volumes: Vec<Kdop<H>>,
    leaves: Vec<Leaf<Kdop<H>>>,
    bvh: Bvh<Kdop<H>>,
}

impl<const H: usize> PerStepBvh<H> {
    /// Builds the hierarchy of the step and appends its candidates to `out`.
    pub fn candidates(
        &mut self,
        input: &BroadInput<'_, '_>,
        ws: &mut BvhWorkspace,
        out: &mut Candidates,
    ) -> BroadStats {
        let start = Instant::now();
        triangle_volumes(input.step, input.filter.sep, &mut self.volumes);
        self.leaves.clear();
        self.leaves
            .extend(self.volumes.iter().enumerate().map(|(t, &volume)| Leaf {
                id: t as u32,
                volume,
            }));
        self.bvh.rebuild(&self.leaves, ws);
        let build = start.elapsed().as_secs_f64();
        let t = Instant::now();
        let tris = input.step.triangles();
        let (features, filter) = (input.features, input.filter);
        let Candidates { vf, ee } = out;
        let bv_tests = self.bvh.self_pairs(ws, |a, b| {
            features.triangle_pair(tris, a, b, filter, vf, ee);
        });
        BroadStats {
            bv_tests,
            build,
            traverse: t.elapsed().as_secs_f64(),
        }
    }

    /// Checks the hierarchy of the last step against its leaves.
    pub fn validate(&self) -> Result<(), BvhError> {
        self.bvh.validate(&self.leaves)
    }
}
