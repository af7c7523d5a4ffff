//! The tasks of a parallel traversal that solve their own candidates: the per-step hierarchy
//! and the cluster method hand their triangle pairs to tasks in a fixed order ([`TaskPairs`]);
//! each task buffers the pairs' candidate features, solves them with the narrow phase on its
//! own thread in bounded buffers, and hands what it found over in task order, so the result
//! does not depend on the thread count.

use std::ops::ControlFlow;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, PoisonError};

use super::{BroadInput, Candidates, PairRunner, TaskPairs};
use crate::bvh::{BvhWorkspace, ParOptions};
use crate::mesh::features::FeatureBoxes;
use crate::contact::limits::Limits;
use crate::contact::driver::{lower, Context, Found, Keeper, Progress};
use crate::contact::Mode;

/// What a broad phase's passes read: the step, the narrow phase's context, the query's limits
/// and how the tasks buffer their candidates.
pub(crate) struct Passes<'r, 'a, 's> {
    pub input: &'r BroadInput<'a, 's>,
    pub ctx: &'r Context<'a, 's>,
    /// The query's limits, shared with the threads of a phase that polls them itself.
    pub limits: &'r Arc<Limits>,
    /// Whether every candidate is recorded ([`Out::recorded`]).
    pub record: bool,
    /// Candidates a traversal task buffers before solving them.
    pub task_chunk: usize,
    /// Candidates a sequential broad phase buffers before solving them in parallel.
    pub chunk: usize,
    /// The tasks' candidate buffers, kept across steps.
    pub buffers: &'r TaskBuffers,
}

/// The candidate buffers of the traversal's tasks, kept across steps (in the [`Ccd`](crate::Ccd)):
/// a task takes one as it starts and gives it back, emptied, as it finishes, so the steady
/// state allocates none. It holds as many as tasks ran at once (one per thread), each of at
/// most about [`TASK_CHUNK`] candidates.
#[derive(Debug, Default)]
pub(crate) struct TaskBuffers(Mutex<Vec<Candidates>>);

impl Clone for TaskBuffers {
    /// None (scratch memory).
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl TaskBuffers {
    fn take(&self) -> Candidates {
        let mut pool = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        pool.pop().unwrap_or_default()
    }

    fn give(&self, mut buf: Candidates) {
        buf.clear();
        let mut pool = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        pool.push(buf);
    }
}

/// Where a broad phase's passes put what they find.
pub(crate) struct Out<'o> {
    pub found: &'o mut Found,
    pub totals: &'o mut Totals,
    /// With [`Passes::record`], every candidate given to the narrow phase.
    pub recorded: &'o mut Candidates,
}

impl Out<'_> {
    /// The same outputs, borrowed again (for a second pass).
    pub fn reborrow(&mut self) -> Out<'_> {
        Out {
            found: self.found,
            totals: self.totals,
            recorded: self.recorded,
        }
    }
}

/// Candidates a task of the parallel traversal buffers before solving them: a task drops its
/// buffer when it finishes, so what is buffered stays below a few MiB per thread whatever the
/// number of candidates.
pub(crate) const TASK_CHUNK: usize = 1 << 15;
/// In [`Mode::Earliest`](crate::Mode::Earliest), the tasks of the parallel traversal run, and
/// are handed over, in batches of this many, then twice as many after each batch; each batch
/// is pruned with the best time of the batches before. (The first batches set the best time;
/// the later, bigger ones make the threads wait for each other less often.)
pub(crate) const TASK_BATCH: usize = 64;

/// The state of one task of the parallel traversal: its buffer and what it found.
struct Task {
    buf: Candidates,
    found: Found,
    limit: f64,
    vf_tests: u64,
    ee_tests: u64,
    peak: usize,
    recorded: Option<Candidates>,
    /// Triangle pairs given so far.
    pairs: u64,
    /// Whether the task is full or the query stopped: it takes no more pairs.
    done: bool,
    /// Its index in the traversal's fixed order, and the room at its batch's start, for
    /// [`Progress`].
    index: usize,
    budget: usize,
}

impl Task {
    /// A task that keeps at most `budget` contacts ([`Found::with_budget`]); it does nothing
    /// if the query has stopped.
    fn new(
        ctx: &Context<'_, '_>,
        (limit, budget): (f64, usize),
        index: usize,
        record: bool,
        buf: Candidates,
    ) -> Self {
        Self {
            buf,
            found: Found::with_budget(ctx, budget, limit),
            limit,
            vf_tests: 0,
            ee_tests: 0,
            peak: 0,
            recorded: record.then(Candidates::default),
            pairs: 0,
            done: ctx.limits.poll(true),
            index,
            budget,
        }
    }

    /// Whether the task holds all it may: its room, less what the tasks before it hold
    /// (`progress`, under a cap). Before its contacts count (an Earliest query whose earliest
    /// time it does not know to be 0), only when the tasks before it leave no room at all.
    fn full(&self, ctx: &Context<'_, '_>, progress: Option<&Progress>) -> bool {
        progress.is_some_and(|p| {
            let room = p.room(self.index, self.budget);
            room == 0 || (self.found.counting(ctx) && self.found.len() >= room)
        })
    }

    /// Solves what is buffered, on this thread.
    fn flush(&mut self, ctx: &Context<'_, '_>, progress: Option<&Progress>) {
        if self.done || self.full(ctx, progress) {
            self.done = true;
            self.buf.clear();
            return;
        }
        self.peak = self.peak.max(self.buf.len());
        self.vf_tests += self.buf.vf.len() as u64;
        self.ee_tests += self.buf.ee.len() as u64;
        ctx.solve(&self.buf, &mut self.limit, &mut self.found);
        self.found.settle(ctx, self.limit);
        self.found.deliver(ctx);
        if let Some(r) = &mut self.recorded {
            if ctx.limits.check(r.grow_for(&self.buf)) {
                r.vf.extend_from_slice(&self.buf.vf);
                r.ee.extend_from_slice(&self.buf.ee);
            }
        }
        self.buf.clear();
        if let Some(p) = progress.filter(|_| self.found.counting(ctx)) {
            p.set(self.index, self.found.len());
        }
        self.done = self.found.room == 0 || self.full(ctx, progress) || ctx.limits.poll(false);
    }

    /// Whether the task should take the triangle pair it is given: not once it is full or
    /// the query stopped (checked every [`TASK_POLL`] pairs).
    #[inline]
    fn takes(&mut self, ctx: &Context<'_, '_>, progress: Option<&Progress>) -> bool {
        self.pairs += 1;
        if self.pairs.is_multiple_of(TASK_POLL) && !self.done {
            self.done = ctx.limits.poll(false) || self.full(ctx, progress);
        }
        !self.done
    }
}

/// Triangle pairs a traversal task takes between two polls of the query's limits.
const TASK_POLL: u64 = 4096;
/// Traversal tasks whose contacts [`Progress`] follows (the per-step hierarchy splits a step
/// into about 512; later tasks keep their whole room).
const PROGRESS_TASKS: usize = 1 << 13;

/// Runs the tasks of the cluster method's traversal ([`traverse_pass`], over the whole step).
pub(crate) struct Runner<'r, 'a, 's, 'o> {
    pub passes: &'r Passes<'r, 'a, 's>,
    pub out: Out<'o>,
}

impl PairRunner for Runner<'_, '_, '_, '_> {
    fn run(&mut self, source: &impl TaskPairs, ws: &mut BvhWorkspace) -> u64 {
        let boxes = &self.passes.input.features.boxes;
        let start = (f64::INFINITY, false);
        traverse_pass(source, self.passes, ws, boxes, start, self.out.reborrow())
    }
}

/// What the candidates of a query amounted to.
#[derive(Default)]
pub(crate) struct Totals {
    pub vf_tests: u64,
    pub ee_tests: u64,
    pub peak: usize,
    /// Traversal tasks (or candidate buffers) whose contacts the report holds.
    pub tasks: u64,
}

/// One parallel traversal of the hierarchy as built or refitted (or of the cluster method's
/// tasks), the triangle pairs' features checked against `boxes`, the tasks' candidates solved
/// with the limit `start` at first (lowered by what the batches find). With `first_pass`, the
/// traversal stops after its first batch of tasks unless that batch found a contact whose
/// limit is within `start` (a deterministic rule: the batches are fixed by the tree). Returns
/// the bounding-volume tests.
pub(crate) fn traverse_pass(
    tree: &impl TaskPairs,
    passes: &Passes<'_, '_, '_>,
    ws: &mut BvhWorkspace,
    boxes: &FeatureBoxes,
    (start, first_pass): (f64, bool),
    out: Out<'_>,
) -> u64 {
    let Passes {
        input,
        ctx,
        record,
        task_chunk,
        ..
    } = *passes;
    let Out {
        found,
        totals,
        recorded,
    } = out;
    let (features, filter) = (input.features, input.filter);
    // The limit of the batches handed over so far (f64 bits; only lowered between batches).
    let limit = AtomicU64::new(start.to_bits());
    // Earliest: growing batches, each pruned with what the batches before found. All: one
    // batch (a finished task keeps only what it found, so the buffers alive are the running
    // tasks').
    let batch = if ctx.options.mode == Mode::Earliest {
        TASK_BATCH
    } else {
        usize::MAX
    };
    // Under a cap, a task keeps only what the tasks before it leave room for (`Progress`):
    // memory stays bounded with the usual batches (the result does not depend on them: see
    // `Keeper`).
    let capped = ctx.limits.capped() && ctx.stream.is_none();
    let progress = capped.then(|| Progress::new(PROGRESS_TASKS));
    let progress = progress.as_ref();
    let par = ParOptions {
        batch,
        grow: true,
        ..ParOptions::default()
    };
    // The contacts a task may keep: the room under the cap when its batch starts.
    let mut keeper = Keeper::default();
    let budget = AtomicUsize::new(keeper.budget(ctx, found));
    let make = |index| {
        let limit = f64::from_bits(limit.load(Ordering::Acquire));
        let budget = budget.load(Ordering::Acquire);
        Task::new(ctx, (limit, budget), index, record, passes.buffers.take())
    };
    let pair = |task: &mut Task, a: u32, b: u32| {
        if !task.takes(ctx, progress) {
            return;
        }
        features.triangle_pair(boxes, [a, b], filter, &mut task.buf.vf, &mut task.buf.ee);
        if task.buf.len() >= task_chunk {
            task.flush(ctx, progress);
        }
    };
    let finish = |task: &mut Task| {
        task.flush(ctx, progress);
        passes.buffers.give(std::mem::take(&mut task.buf));
    };
    let (mut consumed, mut early) = (0, false);
    let consume = |mut task: Task| {
        if keeper.full {
            // After the cap: not the report's.
            return ControlFlow::Break(());
        }
        let mut best = None;
        lower(&mut best, task.found.vf.iter().map(|c| c.toi));
        lower(&mut best, task.found.ee.iter().map(|c| c.toi));
        let current = f64::from_bits(limit.load(Ordering::Acquire));
        limit.store(current.min(ctx.limit(best)).to_bits(), Ordering::Release);
        early |= ctx.limit(best) <= start;
        let kept = keeper.take(ctx, found, &mut task.found);
        budget.store(keeper.budget(ctx, found), Ordering::Release);
        if let Some(p) = progress {
            p.handed_until(task.index + 1);
        }
        totals.tasks += 1;
        totals.vf_tests += task.vf_tests;
        totals.ee_tests += task.ee_tests;
        totals.peak = totals.peak.max(task.peak);
        if let Some(r) = &mut task.recorded {
            let appended = crate::alloc::try_append(&mut recorded.vf, &mut r.vf, "recorded candidates")
                .and_then(|()| crate::alloc::try_append(&mut recorded.ee, &mut r.ee, "recorded candidates"));
            ctx.limits.check(appended);
        }
        // The first task holds the pairs found while splitting; the first batch follows.
        consumed += 1;
        if kept.is_break() || (first_pass && consumed > TASK_BATCH && !early) {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    };
    // One check as each task starts: once the query stops, the tasks left are not traversed.
    // (and a task the tasks before it leave no room is not needed).
    let skip = |task: &Task| ctx.limits.poll(true) || task.full(ctx, progress);
    tree.pairs(ws, &par, make, pair, finish, consume, &skip)
}
