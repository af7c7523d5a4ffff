//! The broad phases, side by side: each finds the candidate feature pairs of one step and
//! hands them, through the same ownership scheme (`Features`) and the same pair filter
//! (`PairFilter`), to the narrow phase.
//!
//! - `brute`: the oracle, a sort and sweep over every feature's swept box;
//! - `bvh`: a k-DOP hierarchy over the triangles' swept volumes, built anew every step;
//! - [`cluster`]: the paper's dynamic clustering, a hierarchy over certified clusters and lazy
//!   hierarchies over their triangles.
//!
//! # One answer, whatever the method
//! A vertex-face pair `(v, f)` is a candidate of every method exactly when the two features
//! share no vertex, pass the pair filter (whose last two rules drop the pairs whose owner
//! triangles stay apart along the direction between their mean points, or share a vertex whose
//! star is certified free of self-contact), their boxes swept over the whole step come
//! within the minimum separation, and the k-DOPs of `v`'s owner triangle and of `f` swept
//! over the times searched, `[0, tmax]`, overlap (each inflated by the separation); an
//! edge-edge pair likewise with its two owner triangles. The per-step
//! hierarchy finds exactly these (its traversal reports every overlapping triangle pair); the
//! oracle tests the k-DOPs of the owners explicitly; the cluster method finds them all except
//! pairs inside one certified intermediate cluster, which are proved never to touch (see
//! `cluster::traverse`). Since every method then runs the same elementary tests on the same
//! pairs, all report the same contacts with the same times, but for a pair inside a certified
//! cluster that the elementary test cannot tell from a touch (within the tolerance without
//! touching, or given up on): only the cluster method leaves it out. (The per-step
//! hierarchy's first look at the start of the step in `Mode::Earliest` uses volumes over that
//! start, and keeps only contacts of pairs that are candidates as above.)

pub(crate) mod brute;
pub(crate) mod bvh;
pub(crate) mod codim;
pub mod cluster;
pub(crate) mod tasks;

use std::ops::ControlFlow;

use rayon::prelude::*;

pub(crate) use crate::contact::{triangle_volume, Candidates};

use crate::bvh::{BvhWorkspace, ParOptions};
use crate::kdop::Kdop;
use crate::math::DVec3;
use crate::mesh::features::Features;
use crate::mesh::filter::PairFilter;
use crate::mesh::Step;

/// What a broad phase reads.
pub(crate) struct BroadInput<'a, 's> {
    pub step: &'a Step<'s>,
    pub features: &'a Features,
    pub filter: &'a PairFilter<'a>,
}

/// Most candidate pairs a buffer holds before it is handed to the narrow phase: memory stays
/// bounded by this, not by the number of candidates of the step (8 bytes a pair: 4 MiB).
pub(crate) const CHUNK: usize = 1 << 19;

/// A bounded buffer of candidates: a sequential broad phase pushes into `buf` and calls
/// [`Sink::check`] after each triangle pair; a full buffer goes to `flush` (the narrow phase)
/// and is emptied. `flush` returns `Break` when the query stops; the broad phase then asks
/// [`Sink::stopped`] (which also calls `stop`, the query's own check, every few thousand
/// calls) and ends early.
pub(crate) struct Sink<'f> {
    /// Whether the query stopped.
    stopped: bool,
    /// Calls of [`Sink::stopped`] so far.
    polls: u64,
    stop: &'f dyn Fn() -> bool,
    pub buf: Candidates,
    /// Candidates handed over so far.
    pub vf_total: u64,
    pub ee_total: u64,
    /// The largest number of candidates held at once.
    pub peak: usize,
    limit: usize,
    flush: &'f mut dyn FnMut(&Candidates) -> ControlFlow<()>,
}

impl<'f> Sink<'f> {
    pub fn new(
        limit: usize,
        flush: &'f mut dyn FnMut(&Candidates) -> ControlFlow<()>,
        stop: &'f dyn Fn() -> bool,
    ) -> Self {
        Self {
            stopped: false,
            polls: 0,
            stop,
            buf: Candidates::default(),
            vf_total: 0,
            ee_total: 0,
            peak: 0,
            limit: limit.max(1),
            flush,
        }
    }

    /// Flushes the buffer if it is full.
    #[inline]
    pub fn check(&mut self) {
        if self.buf.len() >= self.limit {
            self.flush_now();
        }
    }

    /// Hands whatever is buffered to the narrow phase.
    pub fn flush_now(&mut self) {
        self.peak = self.peak.max(self.buf.len());
        self.vf_total += self.buf.vf.len() as u64;
        self.ee_total += self.buf.ee.len() as u64;
        if self.buf.len() > 0 && !self.stopped {
            self.stopped = (self.flush)(&self.buf).is_break();
        }
        self.buf.clear();
    }

    /// Whether the query stopped: the broad phase should end. Cheap; call it in inner loops.
    #[inline]
    pub fn stopped(&mut self) -> bool {
        self.polls += 1;
        if !self.stopped && self.polls.is_multiple_of(4096) {
            self.stopped = (self.stop)();
        }
        self.stopped
    }
}

/// A broad phase whose overlapping triangle pairs come from parallel tasks: `pair(acc, a, b)`
/// for every triangle pair to test, each once, with one accumulator per task (made by
/// `make(i)`, `i` the task's index in the fixed order, finished by `finish` on the task's
/// thread), handed to `consume` in a fixed task
/// order, batch by batch ([`ParOptions::batch`]); once `consume` returns
/// [`ControlFlow::Break`], no batch after the one under way runs; `skip(acc)`, asked once as
/// each task starts, leaves that task untraversed (a query that stopped, a task not needed). The tasks, and what each
/// receives, depend on the input alone, never on the thread count. Returns the
/// bounding-volume tests.
pub(crate) trait TaskPairs {
    #[allow(clippy::too_many_arguments)]
    fn pairs<T: Send>(
        &self,
        ws: &mut BvhWorkspace,
        par: &ParOptions,
        make: impl Fn(usize) -> T + Sync + Send,
        pair: impl Fn(&mut T, u32, u32) + Sync + Send,
        finish: impl Fn(&mut T) + Sync + Send,
        consume: impl FnMut(T) -> ControlFlow<()>,
        skip: &(dyn Fn(&T) -> bool + Sync),
    ) -> u64;
}

/// What consumes the triangle pairs of a [`TaskPairs`] broad phase (the query's narrow
/// phase, run inside the tasks). Returns the bounding-volume tests.
pub(crate) trait PairRunner {
    fn run(&mut self, source: &impl TaskPairs, ws: &mut BvhWorkspace) -> u64;
}

/// Whether the query stopped, for the broad phase's long sequential loops (the cluster
/// method's leaf growth): a check cheap enough to run every iteration.
#[derive(Clone)]
pub(crate) struct Stopper(
    pub std::sync::Arc<dyn Fn() -> bool + Send + Sync>,
    /// The query's limits, where an allocation failure is recorded ([`Stopper::fail`]).
    pub Option<std::sync::Arc<crate::contact::limits::Limits>>,
);

impl Stopper {
    /// Whether the query stopped.
    #[inline]
    pub fn stopped(&self) -> bool {
        (self.0)()
    }

    /// Records an allocation failure: the query winds down and returns it. Without limits to
    /// record it in, the failure aborts, as an infallible allocation does.
    #[cold]
    pub fn fail(&self, e: crate::alloc::AllocError) {
        match &self.1 {
            Some(limits) => limits.fail(e),
            None => std::alloc::handle_alloc_error(
                std::alloc::Layout::from_size_align(e.bytes.max(1), 1)
                    .unwrap_or(std::alloc::Layout::new::<u8>()),
            ),
        }
    }
}

impl std::fmt::Debug for Stopper {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Stopper")
    }
}

/// What a broad phase did.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct BroadStats {
    /// Bounding-volume overlap tests.
    pub bv_tests: u64,
    /// Seconds spent building volumes and hierarchies.
    pub build: f64,
    /// Seconds spent traversing down to the candidates.
    pub traverse: f64,
    /// Seconds of the narrow phase run apart from the traversal (by a sequential broad phase).
    pub narrow: f64,
    /// The cluster method's figures.
    pub cluster: Option<cluster::phase::ClusterFigures>,
}

/// The interface the three broad phases share: once the query has the step's features, its
/// pair filter and the narrow phase's context (`passes`), a broad phase finds the step's
/// candidate pairs and runs the narrow phase on them, in its own tasks or in bounded buffers,
/// putting what it finds in `out`. What it keeps from one step to the next is its own, and is
/// checked again on every step ([`bvh::BvhPhase`], [`cluster::phase::ClusterPhase`]; the
/// oracle, [`brute::Brute`], keeps nothing).
pub(crate) trait BroadPhase {
    fn run(
        &mut self,
        passes: &tasks::Passes<'_, '_, '_>,
        ws: &mut BvhWorkspace,
        out: tasks::Out<'_>,
    ) -> BroadStats;
}

/// The k-DOP of every triangle swept over `[0, tmax]` (the whole step for `tmax >= 1`),
/// inflated by `inflation`, into `out`. Every method tests its owner triangles with these
/// volumes (the per-step hierarchy's leaves are the same, [`triangle_volume`]), so the
/// methods look at the same feature pairs.
pub(crate) fn triangle_volumes<const H: usize>(
    step: &Step<'_>,
    (tmax, inflation): (f64, f64),
    out: &mut Vec<Kdop<H>>,
) {
    let volume = triangle_volume(step, tmax, inflation);
    out.clear();
    // On the current rayon pool, in order.
    out.par_extend(
        (0..step.triangles().len() as u32)
            .into_par_iter()
            .with_min_len(1 << 12)
            .map(volume),
    );
}

/// Each vertex's part of the triangles' swept volumes over `[0, tmax]`
/// ([`Kdop::swept_point_until`]), into `out`: projected once per vertex rather than once per
/// incident triangle.
pub(crate) fn corner_volumes<const H: usize>(
    step: &Step<'_>,
    tmax: f64,
    out: &mut Vec<(Kdop<H>, DVec3)>,
) {
    let ends = step.pos0().par_iter().zip(step.pos1());
    out.clear();
    out.par_extend(
        ends.with_min_len(1 << 12)
            .map(|(&a, &b)| Kdop::swept_point_until(a, b, tmax)),
    );
}

/// [`triangle_volume`] from the vertices' [`corner_volumes`] over the same `tmax`: the same
/// volumes.
pub(crate) fn triangle_volume_from<'a, const H: usize>(
    step: &'a Step<'_>,
    corners: &'a [(Kdop<H>, DVec3)],
    tmax: f64,
    inflation: f64,
) -> impl Fn(u32) -> Kdop<H> + Sync + Send + Copy + 'a {
    let tris = step.triangles();
    move |t| {
        let c = tris[t as usize].map(|v| corners[v as usize]);
        Kdop::swept_triangle_from(&c, tmax, inflation)
    }
}
