//! Parallel traversals: the traversal is split into independent tasks, enumerated in a fixed
//! order that depends on the trees alone, run on the current rayon thread pool, and their
//! results returned in task order; so the output is the same for any number of threads.

use std::ops::ControlFlow;

use rayon::prelude::*;

use super::traverse::{run, step, LeafCheck, Sink, TestAll, OTHER};
use super::{BoundingVolume, Bvh, BvhWorkspace, Node};

/// How a parallel traversal splits and hands over its work. The tasks depend on these and on
/// the trees only, never on the thread count, so neither does the output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ParOptions {
    /// Split the traversal into at least this many tasks, when the trees have that many node
    /// pairs to split. Default 512: enough for rayon to balance a few threads over tasks of
    /// very unequal sizes.
    pub min_tasks: usize,
    /// Trees with fewer nodes than this (both of them, for two trees) are traversed as one
    /// task. Default 2048.
    pub min_nodes: usize,
    /// Run the tasks this many at a time, and hand over a batch's results before starting the
    /// next, so that at most one batch of results is alive at once. Default `usize::MAX` (one
    /// batch). `0` counts as 1.
    pub batch: usize,
    /// Double the batch after each batch (`batch`, `2 batch`, `4 batch`, ...): a caller that
    /// learns most from the first batches (an earliest-contact query's best time) waits for
    /// them, then the threads wait for each other less often. Default `false`.
    pub grow: bool,
}

impl Default for ParOptions {
    fn default() -> Self {
        Self {
            min_tasks: 512,
            min_nodes: 2048,
            batch: usize::MAX,
            grow: false,
        }
    }
}

/// The output of a parallel traversal.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ParPairs<T> {
    /// One value per task, made by the caller's `make` and fed the task's leaf pairs, in task
    /// order. Concatenating them gives the same sequence for any number of threads.
    pub results: Vec<T>,
    /// The number of bounding-volume overlap tests (also independent of the thread count).
    pub bv_tests: u64,
}

/// The tasks of the splitting phase: the node pairs left to descend (stack entries, see
/// `traverse::step`) and the leaf pairs found on the way.
#[derive(Clone, Debug, Default)]
pub(super) struct Tasks {
    /// Stack entries, each a task of the parallel phase.
    pub(super) entries: Vec<(u32, u32)>,
    /// The next round's entries.
    next: Vec<(u32, u32)>,
    /// Overlapping leaf pairs found while splitting, handed to the first accumulator.
    found: Vec<(u32, u32)>,
}

/// The sink of one splitting round.
struct Round<'a> {
    next: &'a mut Vec<(u32, u32)>,
    found: &'a mut Vec<(u32, u32)>,
}

impl Sink for Round<'_> {
    #[inline]
    fn push(&mut self, a: u32, b: u32) {
        self.next.push((a, b));
    }

    #[inline]
    fn leaf(&mut self, x: u32, y: u32) {
        self.found.push((x, y));
    }
}

impl<V: BoundingVolume> Bvh<V> {
    /// [`Bvh::self_pairs`] on the current rayon thread pool: the same leaf pairs, each once,
    /// handed to `leaf_pair` with a per-task accumulator made by `make`. The accumulators are
    /// returned in a fixed task order, and the pairs each receives, in order, depend only on
    /// the tree: the concatenated output is the same for any number of threads (and the same
    /// set as [`Bvh::self_pairs`]'s).
    ///
    /// ```
    /// use topoccd::bvh::{Bvh, Leaf};
    /// use topoccd::kdop::Kdop;
    /// use topoccd::math::DVec3;
    /// let leaves: Vec<_> = (0..1000)
    ///     .map(|i| {
    ///         let mut volume = Kdop::<9>::from_point(DVec3::new(i as f64, 0.0, 0.0));
    ///         volume.inflate(0.6);
    ///         Leaf { id: i, volume }
    ///     })
    ///     .collect();
    /// let bvh = Bvh::from_leaves(&leaves);
    /// let out = bvh.par_self_pairs(&mut Default::default(), Vec::new, |v, a, b| {
    ///     v.push((a.min(b), a.max(b)))
    /// });
    /// let mut pairs: Vec<(u32, u32)> = out.results.concat();
    /// pairs.sort();
    /// assert_eq!(pairs, (0..999).map(|i| (i, i + 1)).collect::<Vec<_>>());
    /// assert!(out.bv_tests > 0);
    /// ```
    pub fn par_self_pairs<T: Send>(
        &self,
        ws: &mut BvhWorkspace,
        make: impl Fn() -> T + Sync + Send,
        leaf_pair: impl Fn(&mut T, u32, u32) + Sync + Send,
    ) -> ParPairs<T> {
        let mut results = Vec::new();
        let options = ParOptions::default();
        let bv_tests = self.par_self_pairs_with(ws, &options, make, leaf_pair, |r| results.push(r));
        ParPairs { results, bv_tests }
    }

    /// [`Bvh::par_self_pairs`] with options, handing each task's accumulator to `consume`, in
    /// task order, batch by batch ([`ParOptions::batch`]): the caller can use (and drop) a
    /// batch's results before the next batch runs, e.g. to bound the memory of candidate pairs.
    /// Returns the number of bounding-volume overlap tests.
    ///
    /// ```
    /// use topoccd::bvh::{Bvh, Leaf, ParOptions};
    /// use topoccd::kdop::Kdop;
    /// use topoccd::math::DVec3;
    /// let leaves: Vec<_> = (0..5000)
    ///     .map(|i| {
    ///         let mut volume = Kdop::<9>::from_point(DVec3::new(i as f64, 0.0, 0.0));
    ///         volume.inflate(0.6);
    ///         Leaf { id: i, volume }
    ///     })
    ///     .collect();
    /// let bvh = Bvh::from_leaves(&leaves);
    /// let options = ParOptions { batch: 16, ..ParOptions::default() };
    /// let (mut pairs, mut largest) = (0, 0);
    /// bvh.par_self_pairs_with(&mut Default::default(), &options, Vec::new, |v, a, b| v.push((a, b)), |v| {
    ///     pairs += v.len();
    ///     largest = largest.max(v.len());
    /// });
    /// assert_eq!(pairs, 4999);
    /// assert!(largest < 100);
    /// ```
    pub fn par_self_pairs_with<T: Send>(
        &self,
        ws: &mut BvhWorkspace,
        options: &ParOptions,
        make: impl Fn() -> T + Sync + Send,
        leaf_pair: impl Fn(&mut T, u32, u32) + Sync + Send,
        consume: impl FnMut(T),
    ) -> u64 {
        self.par_self_pairs_finished(ws, options, make, leaf_pair, |_| {}, consume)
    }

    /// [`Bvh::par_self_pairs_with`] with `finish(acc)` called on each task's accumulator on the
    /// thread that ran the task, as soon as the task is done (e.g. to process what it buffered
    /// in parallel), before `consume` receives it in task order.
    pub fn par_self_pairs_finished<T: Send>(
        &self,
        ws: &mut BvhWorkspace,
        options: &ParOptions,
        make: impl Fn() -> T + Sync + Send,
        leaf_pair: impl Fn(&mut T, u32, u32) + Sync + Send,
        finish: impl Fn(&mut T) + Sync + Send,
        mut consume: impl FnMut(T),
    ) -> u64 {
        let consume = |r| {
            consume(r);
            ControlFlow::Continue(())
        };
        let make = |_| make();
        let (check, never) = (&TestAll, &|_: &T| false);
        self.par_self_pairs_until(ws, options, check, make, leaf_pair, finish, consume, never)
    }

    /// [`Bvh::par_self_pairs_finished`] whose `consume` may stop the traversal: once it returns
    /// [`ControlFlow::Break`], the results of the batch under way are still handed over, and
    /// no further batch runs. `make(i)` makes the accumulator of the `i`-th task in the fixed
    /// order (0: the pairs found while splitting), and `skip(acc)` is asked once as each task
    /// starts: a task it says to skip is not traversed (its accumulator, made and finished,
    /// receives no pair). Leaf pairs that `check` skips are neither tested nor reported.
    /// Returns the bounding-volume tests made.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn par_self_pairs_until<T: Send>(
        &self,
        ws: &mut BvhWorkspace,
        options: &ParOptions,
        check: &impl LeafCheck,
        make: impl Fn(usize) -> T + Sync + Send,
        leaf_pair: impl Fn(&mut T, u32, u32) + Sync + Send,
        finish: impl Fn(&mut T) + Sync + Send,
        consume: impl FnMut(T) -> ControlFlow<()>,
        skip: &(dyn Fn(&T) -> bool + Sync),
    ) -> u64 {
        let t = &mut ws.tasks;
        t.entries.clear();
        t.found.clear();
        if self.nodes.len() > 1 {
            t.entries.push((0, 0));
        }
        let small = self.nodes.len() < options.min_nodes;
        let nodes = &self.nodes[..];
        let f = (make, leaf_pair, finish, consume, skip);
        par_run((nodes, nodes, check), t, 0, small, options, f)
    }

    /// [`Bvh::tree_pairs`] on the current rayon thread pool, with per-task accumulators
    /// returned in a fixed task order, as [`Bvh::par_self_pairs`]: `leaf_pair(acc, a, b)` for
    /// every leaf `a` of `self` and `b` of `other` whose volumes overlap.
    ///
    /// ```
    /// use topoccd::bvh::{Bvh, Leaf};
    /// use topoccd::kdop::Kdop;
    /// use topoccd::math::DVec3;
    /// let boxes = |x0: f64| -> Vec<Leaf<Kdop<3>>> {
    ///     (0..500).map(|i| Leaf {
    ///         id: i,
    ///         volume: Kdop::from_points(&[DVec3::splat(x0 + i as f64), DVec3::splat(x0 + i as f64 + 0.9)]),
    ///     }).collect()
    /// };
    /// let (a, b) = (Bvh::from_leaves(&boxes(0.0)), Bvh::from_leaves(&boxes(0.5)));
    /// let out = a.par_tree_pairs(&b, &mut Default::default(), || 0usize, |n, _, _| *n += 1);
    /// assert_eq!(out.results.iter().sum::<usize>(), 999);
    /// ```
    pub fn par_tree_pairs<T: Send>(
        &self,
        other: &Bvh<V>,
        ws: &mut BvhWorkspace,
        make: impl Fn() -> T + Sync + Send,
        leaf_pair: impl Fn(&mut T, u32, u32) + Sync + Send,
    ) -> ParPairs<T> {
        let mut results = Vec::new();
        let options = ParOptions::default();
        let bv_tests =
            self.par_tree_pairs_with(other, ws, &options, make, leaf_pair, |r| results.push(r));
        ParPairs { results, bv_tests }
    }

    /// [`Bvh::par_tree_pairs`] with options, handing each task's accumulator to `consume` in
    /// task order, batch by batch, as [`Bvh::par_self_pairs_with`]. Returns the number of
    /// bounding-volume overlap tests.
    pub fn par_tree_pairs_with<T: Send>(
        &self,
        other: &Bvh<V>,
        ws: &mut BvhWorkspace,
        options: &ParOptions,
        make: impl Fn() -> T + Sync + Send,
        leaf_pair: impl Fn(&mut T, u32, u32) + Sync + Send,
        mut consume: impl FnMut(T),
    ) -> u64 {
        let (na, nb) = (&self.nodes[..], &other.nodes[..]);
        let t = &mut ws.tasks;
        t.entries.clear();
        t.found.clear();
        if na.is_empty() || nb.is_empty() {
            consume(make());
            return 0;
        }
        if na[0].volume.overlaps(&nb[0].volume) {
            match (na[0].leaf(), nb[0].leaf()) {
                (Some(x), Some(y)) => t.found.push((x, y)),
                _ => t.entries.push((0, OTHER)),
            }
        }
        let small = na.len() < options.min_nodes && nb.len() < options.min_nodes;
        let consume = |r| {
            consume(r);
            ControlFlow::Continue(())
        };
        let never: &(dyn Fn(&T) -> bool + Sync) = &|_| false;
        let f = (|_| make(), leaf_pair, |_: &mut T| {}, consume, never);
        par_run((na, nb, &TestAll), t, 1, small, options, f)
    }
}

/// Splits the entries of `t` level by level (every entry processed once per round, in order)
/// until there are at least `options.min_tasks` or none left (unless `small`), then runs them
/// on the rayon pool, batch by batch, handing the results to `consume` in task order. The
/// first result holds the leaf pairs found while splitting. Returns the overlap tests.
#[allow(clippy::type_complexity)]
fn par_run<V: BoundingVolume, T: Send>(
    (na, nb, check): (&[Node<V>], &[Node<V>], &impl LeafCheck),
    t: &mut Tasks,
    mut bv_tests: u64,
    small: bool,
    options: &ParOptions,
    (make, leaf_pair, finish, mut consume, skip): (
        impl Fn(usize) -> T + Sync + Send,
        impl Fn(&mut T, u32, u32) + Sync + Send,
        impl Fn(&mut T) + Sync + Send,
        impl FnMut(T) -> ControlFlow<()>,
        &(dyn Fn(&T) -> bool + Sync),
    ),
) -> u64 {
    while !small && !t.entries.is_empty() && t.entries.len() < options.min_tasks {
        t.next.clear();
        let mut round = Round {
            next: &mut t.next,
            found: &mut t.found,
        };
        for &(a, b) in &t.entries {
            bv_tests += step(na, nb, a, b, check, &mut round);
        }
        std::mem::swap(&mut t.entries, &mut t.next);
    }
    let mut first = make(0);
    for &(x, y) in &t.found {
        leaf_pair(&mut first, x, y);
    }
    finish(&mut first);
    if consume(first).is_break() {
        return bv_tests;
    }
    let body = |stack: &mut Vec<(u32, u32)>, &(a, b): &(u32, u32), acc: &mut T| {
        stack.clear();
        stack.push((a, b));
        run(na, nb, stack, check, &mut |x, y| leaf_pair(acc, x, y))
    };
    let f = (|i| make(i + 1), finish, skip);
    bv_tests + run_batches(&t.entries, options, Vec::new, body, f, &mut consume)
}

/// Runs `tasks` on the rayon pool, a batch at a time ([`ParOptions::batch`], doubled after
/// each batch with [`ParOptions::grow`]): each task's accumulator (made by `make(i)`, `i` the
/// task's index in `tasks`)
/// is filled by `body(scratch, task, acc)`, which returns its bounding-volume tests, and
/// finished by `finish` on the task's thread; the accumulators go to `consume` in task order,
/// so what `consume` sees does not depend on the thread count. Once `consume` returns
/// [`ControlFlow::Break`], the batch under way is handed over in full and no other batch runs.
/// `skip(acc)` is asked once as each task starts: when it says so, `body` does not run (a query
/// that stopped leaves the rest of the traversal at once). `scratch` makes per-thread scratch
/// memory. Returns the bounding-volume tests made.
#[allow(clippy::type_complexity)]
pub(crate) fn run_batches<W: Sync, S: Send, T: Send>(
    tasks: &[W],
    options: &ParOptions,
    scratch: impl Fn() -> S + Sync + Send,
    body: impl Fn(&mut S, &W, &mut T) -> u64 + Sync + Send,
    (make, finish, skip): (
        impl Fn(usize) -> T + Sync + Send,
        impl Fn(&mut T) + Sync + Send,
        &(dyn Fn(&T) -> bool + Sync),
    ),
    consume: &mut impl FnMut(T) -> ControlFlow<()>,
) -> u64 {
    let mut bv_tests = 0;
    let (mut size, mut rest) = (options.batch.max(1), tasks);
    while !rest.is_empty() {
        let offset = tasks.len() - rest.len();
        let (batch, later) = rest.split_at(size.min(rest.len()));
        rest = later;
        if options.grow {
            size = size.saturating_mul(2);
        }
        let mut stop = false;
        // One task per rayon job: the tasks' costs differ by orders of magnitude, and with
        // rayon's default splitting of the slice a thread could be left idle for long at the
        // end while the other worked through a run of heavy tasks.
        let done: Vec<(T, u64)> = batch
            .par_iter()
            .enumerate()
            .with_max_len(1)
            .map_init(&scratch, |s, (i, task)| {
                let mut acc = make(offset + i);
                let tests = if skip(&acc) { 0 } else { body(s, task, &mut acc) };
                finish(&mut acc);
                (acc, tests)
            })
            .collect();
        for (acc, tests) in done {
            stop |= consume(acc).is_break();
            bv_tests += tests;
        }
        if stop {
            break;
        }
    }
    bv_tests
}
