//! The whole-step query: [`Ccd`] keeps scratch memory across steps; [`query`] is the one-shot
//! form. The pipeline: features and pair filter ([`mesh`](crate::mesh)), one broad phase
//! ([`broad`](crate::broad)), the narrow phase, the report.

use std::ops::ControlFlow;
use std::time::Instant;

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::Arc;

use super::limits::{CancelToken, Limits, Phase, StopReason, Truncation};
use super::narrow_phase::{
    self, first_pass_tau, lower, Context, FirstPass, Found, Keeper, Progress, Stream, WholeStep,
    EARLY,
};
use super::report::{Contact, Report, Seconds, Stats};
use super::{ClusterGrowth, Method, OptionsError, QueryOptions};
use crate::broad::cluster::phase::ClusterPhase;
use crate::broad::{
    brute, bvh::PerStepBvh, BroadInput, BroadStats, Candidates, PairRunner, Sink, Stopper,
    TaskPairs, CHUNK,
};
use crate::bvh::{BvhWorkspace, ParOptions};
use crate::kdop::DopKind;
use crate::mesh::features::{FeatureBoxes, Features};
use crate::mesh::filter::PairFilter;
use crate::mesh::star::Stars;
use crate::mesh::Step;
use crate::narrow::Certainty;

/// A reusable whole-step CCD query. Keep one per simulation and call [`Ccd::query`] every step:
/// its buffers (hierarchy, candidate pairs, per-feature data) are reused, and the topology may
/// change freely from one step to the next. What it carries over is checked, never trusted:
/// the topology and the per-step hierarchy's shape are kept only for the very same triangles
/// (compared exactly), the hierarchy refitted to the new volumes; the cluster method's leaves
/// are re-certified on the new positions.
#[derive(Clone, Debug, Default)]
pub struct Ccd {
    features: Features,
    /// The features' boxes over the whole step, for the second pass of an Earliest query
    /// whose first pass (which sweeps `features.boxes` over the start of the step only) did
    /// not find the answer (see [`bvh_query`]); swept only then.
    late_boxes: FeatureBoxes,
    canon: Vec<u32>,
    /// Rule 6 of the pair filter: the certified vertex stars.
    stars: Stars,
    /// With `true`, rule 6 is off (for the crate's tests, [`Ccd::distrust_stars`]).
    distrust_stars: bool,
    ws: BvhWorkspace,
    k6: PerStepBvh<3>,
    k14: PerStepBvh<7>,
    k18: PerStepBvh<9>,
    k26: PerStepBvh<13>,
    cluster: ClusterPhase,
    /// With `record`, every candidate of the last query (for the crate's tests).
    recorded: Candidates,
    record: bool,
    /// Whether the last Earliest query of the per-step BVH found its earliest contact late
    /// (after the step's first `1 / EARLY`): the next one then skips the first pass.
    late: bool,
    /// Buffer limits (candidate pairs) of a traversal task and of a sequential broad phase;
    /// `0` means the default ([`TASK_CHUNK`], [`CHUNK`]).
    limits: (usize, usize),
    /// The method and k-DOP type of the last hierarchy built, if the last query built one.
    last_tree: Option<(Method, DopKind)>,
    /// Stops the queries from another thread ([`Ccd::cancel_token`]).
    cancel: CancelToken,
}

/// Candidates a task of the parallel traversal buffers before solving them: a task drops its
/// buffer when it finishes, so what is buffered stays below a few MiB per thread whatever the
/// number of candidates.
const TASK_CHUNK: usize = 1 << 15;
/// In [`Mode::Earliest`](super::Mode::Earliest), the tasks of the parallel traversal run, and
/// are handed over, in batches of this many, then twice as many after each batch; each batch
/// is pruned with the best time of the batches before. (The first batches set the best time;
/// the later, bigger ones make the threads wait for each other less often.)
const TASK_BATCH: usize = 64;

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
    fn new(ctx: &Context<'_, '_>, (limit, budget): (f64, usize), index: usize, record: bool) -> Self {
        Self {
            buf: Candidates::default(),
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
            r.vf.extend_from_slice(&self.buf.vf);
            r.ee.extend_from_slice(&self.buf.ee);
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
struct Runner<'r, 'a, 's> {
    input: &'r BroadInput<'a, 's>,
    ctx: &'r Context<'a, 's>,
    record: bool,
    task_chunk: usize,
    found: &'r mut Found,
    totals: &'r mut Totals,
    recorded: &'r mut Candidates,
}

impl PairRunner for Runner<'_, '_, '_> {
    fn run(&mut self, source: &impl TaskPairs, ws: &mut BvhWorkspace) -> u64 {
        traverse_pass(
            source,
            (self.input, self.ctx, self.record, self.task_chunk, ws),
            &self.input.features.boxes,
            (f64::INFINITY, false),
            (self.found, self.totals, self.recorded),
        )
    }
}

/// What the candidates of a query amounted to.
#[derive(Default)]
struct Totals {
    vf_tests: u64,
    ee_tests: u64,
    peak: usize,
    /// Traversal tasks (or candidate buffers) whose contacts the report holds.
    tasks: u64,
}

impl Ccd {
    /// A query with empty buffers.
    ///
    /// ```
    /// let mut ccd = topoccd::Ccd::new(); // keep it across steps
    /// # let _ = &mut ccd;
    /// ```
    pub fn new() -> Self {
        Self::default()
    }

    /// Runs continuous collision detection over one step, after checking `options`
    /// ([`QueryOptions::validate`]).
    ///
    /// Every vertex-face pair and every pair of edges that share no vertex and pass the step's
    /// pair filter (see [`Step`]), and come within `options.narrow.min_separation` during
    /// `[0, options.narrow.t_max]`, is reported with the elementary tests' conservative time of
    /// impact and its [`Certainty`], in [`Mode::All`](super::Mode::All); only the earliest
    /// pair(s) in [`Mode::Earliest`](super::Mode::Earliest). Each feature pair is tested at
    /// most once. The result does not depend on the method, the thread count or earlier
    /// queries.
    ///
    /// ```
    /// use topoccd::{Ccd, Method, QueryOptions, Step};
    /// // A vertex (3) falls through a fixed triangle (0, 1, 2); a small triangle carries it.
    /// let x0 = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0],
    ///           [0.2, 0.2, 1.0], [0.3, 0.2, 1.5], [0.2, 0.3, 1.5]];
    /// let mut x1 = x0;
    /// for p in &mut x1[3..] { p[2] -= 2.0; }
    /// let step = Step::new(&x0, &x1, &[[0u32, 1, 2], [3, 4, 5]])?;
    /// let mut ccd = Ccd::new();
    /// let report = ccd.query(&step, Method::Bvh, &QueryOptions::default())?;
    /// assert_eq!((report.vf[0].vertex, report.vf[0].face), (3, 0));
    /// assert!((report.vf[0].toi - 0.5).abs() < 1e-6);
    /// assert_eq!(report.unresolved, 0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn query(
        &mut self,
        step: &Step<'_>,
        method: Method,
        options: &QueryOptions,
    ) -> Result<Report, OptionsError> {
        self.run(step, method, options, None)
    }

    /// [`Ccd::query`] in [`Mode::All`](super::Mode::All) that hands every contact to `each` as
    /// it is found, and keeps none: memory stays bounded however many contacts the step has.
    /// `each` is called from the query's threads, in no particular order (the contacts, each
    /// once, are those [`Ccd::query`] reports, with their times). The report returned has no
    /// contacts, but its `earliest` contact, its statistics and
    /// [`truncated`](Report::truncated). With
    /// [`max_contacts`](QueryOptions::max_contacts), at most that many are handed over (which
    /// ones depends on timing), then the query stops, truncated. Refuses
    /// [`Mode::Earliest`](super::Mode::Earliest) ([`OptionsError::Streaming`]), whose pairs are
    /// known only at the end.
    ///
    /// ```
    /// use std::sync::atomic::{AtomicUsize, Ordering};
    /// use topoccd::{Ccd, Method, QueryOptions, Step};
    /// let x0 = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0],
    ///           [0.2, 0.2, 1.0], [0.3, 0.2, 1.5], [0.2, 0.3, 1.5]];
    /// let mut x1 = x0;
    /// for p in &mut x1[3..] { p[2] -= 2.0; }
    /// let step = Step::new(&x0, &x1, &[[0u32, 1, 2], [3, 4, 5]])?;
    /// let count = AtomicUsize::new(0);
    /// let mut ccd = Ccd::new();
    /// let report = ccd.for_each_contact(&step, Method::Bvh, &QueryOptions::default(), |_c| {
    ///     count.fetch_add(1, Ordering::Relaxed); // e.g. write it to a file under a lock
    /// })?;
    /// let all = ccd.query(&step, Method::Bvh, &QueryOptions::default())?;
    /// assert_eq!(count.into_inner(), all.contact_count());
    /// assert_eq!(report.earliest, all.earliest);
    /// assert!(report.vf.is_empty() && report.truncated.is_none());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn for_each_contact(
        &mut self,
        step: &Step<'_>,
        method: Method,
        options: &QueryOptions,
        each: impl Fn(&Contact) + Sync,
    ) -> Result<Report, OptionsError> {
        if options.mode == super::Mode::Earliest {
            return Err(OptionsError::Streaming);
        }
        let stream = Stream::new(&each);
        self.run(step, method, options, Some(&stream))
    }

    /// A handle on this query object's [`CancelToken`]: cancelling it (from any thread) stops
    /// the query running, and every later one until the token is reset. Clones of a `Ccd`
    /// share its token.
    pub fn cancel_token(&self) -> CancelToken {
        self.cancel.clone()
    }

    /// Makes this query object obey `token` (e.g. one token for the `Ccd`s of several
    /// threads).
    pub fn set_cancel_token(&mut self, token: CancelToken) {
        self.cancel = token;
    }

    /// The query, its contacts kept in the report or handed to `stream`.
    fn run(
        &mut self,
        step: &Step<'_>,
        method: Method,
        options: &QueryOptions,
        stream: Option<&Stream<'_>>,
    ) -> Result<Report, OptionsError> {
        options.validate()?;
        let method = method.resolve(step.triangles().len());
        let start = Instant::now();
        let limits = Arc::new(Limits::new(
            options.max_contacts,
            options.deadline,
            Some(self.cancel.clone()),
        ));
        let sep = options.narrow.min_separation;
        // The end of the per-step hierarchy's first pass, if it makes one.
        let first_end = first_pass_end(options, !self.late);
        // The triangles of the last step again (a simulator's everyday step): the topology is
        // kept, and the per-step hierarchy refitted.
        let same = self.features.same_topology(step);
        // Rule 6 of the pair filter (certified vertex stars) holds for contact only.
        let stars_on = sep == 0.0 && !self.distrust_stars;
        if method == Method::Bvh {
            // The per-step hierarchy needs the positions only: it is built beside the topology
            // and the features (at the same time on two threads or more).
            // (A tree is refitted only if the last query built this very tree, so over the
            // same triangles.)
            let end = (first_end.unwrap_or(options.narrow.t_max), sep);
            let refit = same && self.last_tree == Some((Method::Bvh, options.kdop));
            let (features, stars, ws) = (&mut self.features, &mut self.stars, &mut self.ws);
            let build = || match options.kdop {
                DopKind::K6 => self.k6.build(step, end, refit, ws),
                DopKind::K14 => self.k14.build(step, end, refit, ws),
                DopKind::K18 => self.k18.build(step, end, refit, ws),
                DopKind::K26 => self.k26.build(step, end, refit, ws),
            };
            // The per-step hierarchy asks about every star: all are certified at once, beside
            // the tree. (With a first pass, the features' boxes are those of the first pass.)
            let prepare = || {
                features.update(step, same, first_end.unwrap_or(1.0));
                stars.reset(step.vertex_count(), same);
                if stars_on {
                    stars.certify_all(step, &features.topo);
                }
            };
            rayon::join(prepare, build);
            // Rule 6 before the volumes: the traversal drops neighbours in a certified star.
            let topo = &self.features.topo;
            let view = stars_on.then(|| self.stars.view(step, topo));
            let tris = step.triangles();
            match options.kdop {
                DopKind::K6 => self.k6.mark_stars(view, topo, tris),
                DopKind::K14 => self.k14.mark_stars(view, topo, tris),
                DopKind::K18 => self.k18.mark_stars(view, topo, tris),
                DopKind::K26 => self.k26.mark_stars(view, topo, tris),
            }
        } else {
            self.features.update(step, same, 1.0);
            self.stars.reset(step.vertex_count(), same);
            // The oracle asks about every star; the cluster method only about those of its
            // clusters' borders, one by one.
            if stars_on && method == Method::Brute {
                self.stars.certify_all(step, &self.features.topo);
            }
        }
        self.last_tree = None;
        let filter = PairFilter::new(
            step,
            sep,
            options.narrow.t_max,
            options.crack_filter,
            &mut self.canon,
            stars_on.then(|| self.stars.view(step, &self.features.topo)),
        );
        let input = BroadInput {
            step,
            features: &self.features,
            filter: &filter,
        };
        let prepared = start.elapsed().as_secs_f64();
        let edges = &self.features.topo.edges;
        let ctx = Context {
            limits: &limits,
            stream,
            step,
            edges,
            options,
            coord: filter.coord(),
            first: FirstPass::new(step, &self.features.topo, options),
            whole: None,
        };
        let mut found = Found::default();
        // Where a stop found the query: before the candidates (the build), or among them.
        let built = !limits.poll(true);
        let mut totals = Totals::default();
        let mut narrow = 0.0;
        let mut cluster = None;
        let record = self.record;
        let task_chunk = if self.limits.0 == 0 { TASK_CHUNK } else { self.limits.0 };
        let chunk = if self.limits.1 == 0 { CHUNK } else { self.limits.1 };
        let recorded = &mut self.recorded;
        recorded.clear();
        let broad = match method {
            _ if !built => BroadStats::default(),
            Method::Bvh => {
                self.last_tree = Some((Method::Bvh, options.kdop));
                let ws = &mut self.ws;
                let late_boxes = &mut self.late_boxes;
                let args = (&input, &ctx, record, task_chunk, ws);
                let out = (&mut found, &mut totals, recorded);
                let first = first_end;
                let (stats, late) = match options.kdop {
                    DopKind::K6 => bvh_query(&mut self.k6, args, late_boxes, first, out),
                    DopKind::K14 => bvh_query(&mut self.k14, args, late_boxes, first, out),
                    DopKind::K18 => bvh_query(&mut self.k18, args, late_boxes, first, out),
                    DopKind::K26 => bvh_query(&mut self.k26, args, late_boxes, first, out),
                };
                if options.mode == super::Mode::Earliest {
                    self.late = late;
                }
                stats
            }
            Method::Cluster => {
                // The parallel traversal's tasks solve their own candidates, as for the
                // per-step hierarchy.
                self.last_tree = Some((Method::Cluster, options.kdop));
                let paper = options.growth == ClusterGrowth::Paper;
                let stop = Arc::clone(&limits);
                self.cluster
                    .set_stop(Some(Stopper(Arc::new(move || stop.poll(false)))));
                let mut runner = Runner {
                    input: &input,
                    ctx: &ctx,
                    record,
                    task_chunk,
                    found: &mut found,
                    totals: &mut totals,
                    recorded,
                };
                let (stats, figures) = self.cluster.candidates(
                    &input,
                    options.kdop,
                    paper,
                    &mut self.ws,
                    &mut runner,
                );
                self.cluster.set_stop(None);
                cluster = Some(figures);
                stats
            }
            Method::Auto => unreachable!("Method::resolve never returns Auto"),
            Method::Brute => {
                // A sequential broad phase, its buffer solved in parallel whenever it is full.
                // Each buffer is one unit of the order a cap keeps (see `Keeper`).
                let mut best = None;
                let mut keeper = Keeper::default();
                let mut flush = |c: &Candidates| {
                    let t = Instant::now();
                    let budget = keeper.budget(&ctx, &found);
                    let mut part = Found::with_budget(&ctx, budget, ctx.limit(best));
                    ctx.solve_parallel(c, &mut best, &mut part);
                    part.deliver(&ctx);
                    let kept = keeper.take(&ctx, &mut found, &mut part);
                    if record {
                        recorded.vf.extend_from_slice(&c.vf);
                        recorded.ee.extend_from_slice(&c.ee);
                    }
                    narrow += t.elapsed().as_secs_f64();
                    kept
                };
                let stop = || limits.poll(true);
                let mut sink = Sink::new(chunk, &mut flush, &stop);
                let mut stats = {
                    let sink = &mut sink;
                    match options.kdop {
                        DopKind::K6 => brute::candidates::<3>(&input, &mut Vec::new(), sink),
                        DopKind::K14 => brute::candidates::<7>(&input, &mut Vec::new(), sink),
                        DopKind::K18 => brute::candidates::<9>(&input, &mut Vec::new(), sink),
                        DopKind::K26 => brute::candidates::<13>(&input, &mut Vec::new(), sink),
                    }
                };
                let t = Instant::now();
                sink.flush_now();
                stats.traverse += t.elapsed().as_secs_f64();
                totals = Totals {
                    vf_tests: sink.vf_total,
                    ee_tests: sink.ee_total,
                    peak: sink.peak,
                    tasks: 0,
                };
                drop(sink);
                totals.tasks = keeper.tasks;
                // The narrow phase ran inside the traversal: take it out of the traversal time.
                stats.traverse = (stats.traverse - narrow).max(0.0);
                stats
            }
        };
        let BroadStats {
            bv_tests,
            build,
            traverse,
        } = broad;
        let t = Instant::now();
        let by_time = matches!(
            limits.stopped(),
            Some(StopReason::Deadline | StopReason::Cancelled)
        );
        let earliest = if by_time {
            // What was found by then depends on timing: the report keeps the earliest.
            found.earliest_only()
        } else if stream.is_some() {
            found.streamed
        } else {
            narrow_phase::finish(&mut found, options)
        };
        narrow += t.elapsed().as_secs_f64();
        let truncated = limits.stopped().map(|reason| Truncation {
            reason,
            phase: if built {
                Phase::Candidates
            } else {
                Phase::Build
            },
            tasks: totals.tasks,
        });
        let unresolved = found.streamed_unresolved
            + found
                .vf
                .iter()
                .filter(|c| c.certainty != Certainty::Resolved)
                .count()
            + found
                .ee
                .iter()
                .filter(|c| c.certainty != Certainty::Resolved)
                .count();
        Ok(Report {
            vf: found.vf,
            ee: found.ee,
            earliest,
            unresolved,
            truncated,
            stats: Stats {
                method,
                bv_tests,
                vf_tests: totals.vf_tests,
                ee_tests: totals.ee_tests,
                peak_candidates: totals.peak as u64,
                seconds: Seconds {
                    build: prepared + build,
                    traverse,
                    narrow,
                    total: start.elapsed().as_secs_f64(),
                    clustering: cluster.map(|c| c.clustering_seconds),
                    merging: cluster.map(|c| c.merging_seconds),
                },
                cluster,
            },
        })
    }
}

/// Diagnostics for the crate's own tests (feature `internals`).
#[cfg(feature = "internals")]
impl Ccd {
    /// The candidate feature pairs of the last query, recorded with
    /// [`Ccd::record_candidates`]: exactly the pairs given to the narrow phase
    /// ([`Stats::vf_tests`], [`Stats::ee_tests`]), each once.
    pub fn candidates(&self) -> CandidatePairs<'_> {
        CandidatePairs {
            vf: &self.recorded.vf,
            ee: &self.recorded.ee,
            edges: &self.features.topo.edges,
        }
    }

    /// Sets the most candidate pairs a buffer holds before the narrow phase takes it: per task
    /// of the parallel traversal, and for the sequential broad phases (`0`: the default).
    pub fn set_buffer_limits(&mut self, task: usize, sequential: usize) {
        self.limits = (task, sequential);
    }

    /// With `true`, later queries keep every candidate pair for [`Ccd::candidates`] (memory
    /// then grows with the candidates).
    pub fn record_candidates(&mut self, record: bool) {
        self.record = record;
    }

    /// The topology of the last step queried.
    pub fn topology(&self) -> &crate::mesh::Topology {
        &self.features.topo
    }

    /// Runs [`Bvh::validate`](crate::bvh::Bvh::validate) on the hierarchy built by the last
    /// query, `step` (for [`Method::Cluster`]: on every level of its hierarchy), against the
    /// volumes of the step's triangles. `Ok` when the last query built none (as
    /// [`Method::Brute`] does).
    pub fn validate_tree(&self, step: &Step<'_>) -> Result<(), crate::bvh::BvhError> {
        match self.last_tree {
            None => Ok(()),
            Some((Method::Cluster, kind)) => self.cluster.validate(kind),
            Some((_, DopKind::K6)) => self.k6.validate(step),
            Some((_, DopKind::K14)) => self.k14.validate(step),
            Some((_, DopKind::K18)) => self.k18.validate(step),
            Some((_, DopKind::K26)) => self.k26.validate(step),
        }
    }

    /// Whether the last query's per-step hierarchy ([`Method::Bvh`]) was the one of the step
    /// before, refitted to this step's volumes (the same triangles again), rather than rebuilt.
    pub fn tree_refitted(&self) -> bool {
        match self.last_tree {
            Some((Method::Bvh, DopKind::K6)) => self.k6.refitted,
            Some((Method::Bvh, DopKind::K14)) => self.k14.refitted,
            Some((Method::Bvh, DopKind::K18)) => self.k18.refitted,
            Some((Method::Bvh, DopKind::K26)) => self.k26.refitted,
            _ => false,
        }
    }

    /// The clustering computed by the last [`Method::Cluster`] query (empty before the first).
    pub fn clustering(&self) -> &crate::broad::cluster::Clustering {
        &self.cluster.clustering
    }

    /// Whether the last [`Method::Cluster`] query, on `step`, put the features `a` and `b` (a
    /// vertex, an edge or a face, by their vertices) in one intermediate cluster, whose
    /// certificate proves that they never touch: the only pairs that method may leave out where
    /// the other methods report a contact, one the elementary test cannot tell from a touch
    /// (see [`Method`]). A scan of the step's triangles, for checks of a report.
    pub fn cluster_holds_both(&self, step: &Step<'_>, a: &[u32], b: &[u32]) -> bool {
        self.cluster.clustering.holds_both(step.triangles(), a, b)
    }

    /// With `true`, rule 6 of the pair filter is off: no vertex star counts as certified, and
    /// the neighbours in one give their candidates as with a minimum separation. A check of
    /// the certificate: the contacts must not change.
    pub fn distrust_stars(&mut self, distrust: bool) {
        self.distrust_stars = distrust;
    }

    /// With `true`, [`Method::Cluster`] treats every leaf cluster as uncertified: its
    /// candidates are then exactly those of [`Method::Bvh`]. A check of the traversal.
    pub fn distrust_certificates(&mut self, distrust: bool) {
        self.cluster.distrust = distrust;
    }

    /// On two threads or more, [`Method::Cluster`] builds the hierarchy over a leaf cluster's
    /// triangles while the other leaves grow when it has at least `triangles` triangles
    /// (`None`: the default, 1,024), whether or not the traversal will need it.
    pub fn set_ahead_triangles(&mut self, triangles: Option<usize>) {
        self.cluster.ahead = triangles;
    }

    /// How many of the lazy hierarchies of the last [`Method::Cluster`] query had been built
    /// ahead (see [`Ccd::set_ahead_triangles`]).
    pub fn lazy_built_ahead(&self) -> usize {
        self.cluster.last_ahead
    }
}

/// The candidate feature pairs of the last query (feature `internals`).
#[cfg(feature = "internals")]
#[derive(Clone, Copy, Debug)]
pub struct CandidatePairs<'a> {
    /// `[vertex, face]` pairs.
    pub vf: &'a [[u32; 2]],
    /// `[e, f]` pairs of indices into [`CandidatePairs::edges`], `e < f`.
    pub ee: &'a [[u32; 2]],
    /// The step's edges, `[i, j]` with `i < j`, sorted lexicographically.
    pub edges: &'a [[u32; 2]],
}

/// One-shot form of [`Ccd::query`] (allocates fresh buffers).
///
/// ```
/// use topoccd::{query, Method, QueryOptions, Step};
/// let x0 = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.2, 0.2, 1.0], [0.3, 0.2, 1.5], [0.2, 0.3, 1.5]];
/// let mut x1 = x0;
/// for p in &mut x1[3..] { p[2] -= 2.0; }
/// let step = Step::new(&x0, &x1, &[[0u32, 1, 2], [3, 4, 5]])?;
/// let options = QueryOptions::default();
/// let bvh = query(&step, Method::Bvh, &options)?;
/// let brute = query(&step, Method::Brute, &options)?;
/// assert!(bvh.contact_count() > 0);
/// assert_eq!((bvh.vf, bvh.ee), (brute.vf, brute.ee));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn query(
    step: &Step<'_>,
    method: Method,
    options: &QueryOptions,
) -> Result<Report, OptionsError> {
    Ccd::new().query(step, method, options)
}

/// The end `tau` of the first pass of [`bvh_query`] ([`first_pass_tau`]), `None` when there
/// is only one pass (not in Earliest mode, not `early`, or an interval too short to split).
/// Only if the first pass finds no contact early enough does the query look at the whole step.
fn first_pass_end(options: &QueryOptions, early: bool) -> Option<f64> {
    let two_pass = early && options.mode == super::Mode::Earliest;
    first_pass_tau(options).filter(|_| two_pass)
}

/// The per-step hierarchy's query: the parallel traversal of the hierarchy the caller built,
/// whose tasks solve their own candidates in bounded buffers. Returns the broad phase's
/// figures; the narrow phase's time is inside the traversal's (the two run interleaved on
/// every thread).
///
/// In [`Mode::Earliest`](super::Mode::Earliest), with `first_end` = `Some(tau)` from
/// [`first_pass_end`] (`tau = t_max / EARLY`), a first pass uses triangle volumes and feature
/// boxes (the features' own, swept by the caller over `[0, tau]`) and solves every
/// candidate over `[0, tau]` first. If it finds contacts whose earliest time `b` has
/// `b + 2 tolerance <= tau`, the answer is complete: a pair reported within the tolerance of
/// `b` is reported before `tau`, so its volumes over `[0, tau]` overlap (the narrow phase of
/// every method searches a pair they prove apart from `tau` only, [`FirstPass`], even where
/// rounding keeps it from separating the features) and the first pass tested it. The first
/// pass keeps only contacts of pairs that a query in [`Mode::All`](super::Mode::All) looks at
/// ([`WholeStep`]), so that Earliest reports only All's pairs. Otherwise the hierarchy is
/// refitted to the volumes swept over `[0, t_max]`, its leaves in `Mode::All`, the features'
/// boxes over the whole step are swept into `late_boxes`, and the hierarchy is traversed
/// again, pruned with whatever the first pass found; pairs found twice are reported once.
/// The first pass pays
/// when contacts are dense at the start of the step (resting contact) and is wasted
/// otherwise, so it stops after its first batch of tasks unless that batch found a contact
/// early enough, and [`Ccd`] tries it only while the last Earliest query's contact came early
/// (`early`); the answer is the same either way (the second pass alone is complete). Also
/// returns whether this step's earliest contact came late (after `t_max / EARLY`, or none),
/// with one pass or two. `tree` must have been built for this
/// step, over `[0, tau]` for two passes, else over `[0, t_max]`.
fn bvh_query<const H: usize>(
    tree: &mut PerStepBvh<H>,
    (input, ctx, record, task_chunk, ws): (
        &BroadInput<'_, '_>,
        &Context<'_, '_>,
        bool,
        usize,
        &mut BvhWorkspace,
    ),
    late_boxes: &mut FeatureBoxes,
    first_end: Option<f64>,
    (found, totals, recorded): (&mut Found, &mut Totals, &mut Candidates),
) -> (BroadStats, bool) {
    // Whether or not there is a first pass, a contact is late after the first `1 / EARLY`.
    let tau = ctx.options.narrow.t_max / EARLY;
    let two_pass = first_end.is_some();
    let end = first_end.unwrap_or(f64::INFINITY);
    let mut build = 0.0;
    let t = Instant::now();
    // A first pass keeps only contacts that the whole step's pass would look at too.
    let topo = &input.features.topo;
    let first_ctx = Context {
        whole: two_pass.then(|| WholeStep::new(input.step, topo, ctx.options)),
        ..*ctx
    };
    let mut bv_tests = traverse_pass(
        tree,
        (input, &first_ctx, record, task_chunk, ws),
        &input.features.boxes,
        (end, two_pass),
        (found, totals, recorded),
    );
    let mut traverse = t.elapsed().as_secs_f64();
    if two_pass {
        let mut best = None;
        lower(&mut best, found.vf.iter().map(|c| c.toi));
        lower(&mut best, found.ee.iter().map(|c| c.toi));
        let complete = best.is_some_and(|b| ctx.limit(Some(b)) <= end);
        if !complete && ctx.limits.stopped().is_none() {
            if ctx.limits.capped() {
                // The second pass finds again, with the same times, every contact of the
                // first that the report can hold, in its own order, which a cap follows.
                *found = Found::default();
            }
            let t = Instant::now();
            tree.refit_until_t_max(input);
            late_boxes.sweep(input.step, 1.0);
            build += t.elapsed().as_secs_f64();
            let t = Instant::now();
            let limit = ctx.limit(best);
            bv_tests += traverse_pass(
                tree,
                (input, ctx, record, task_chunk, ws),
                late_boxes,
                (limit, false),
                (found, totals, recorded),
            );
            // A contact of the first pass is found again, with the same time.
            found.vf.sort_unstable_by_key(|c| (c.vertex, c.face));
            found.vf.dedup_by_key(|c| (c.vertex, c.face));
            found.ee.sort_unstable_by_key(|c| (c.a, c.b));
            found.ee.dedup_by_key(|c| (c.a, c.b));
            traverse += t.elapsed().as_secs_f64();
        }
    }
    let mut best = None;
    lower(&mut best, found.vf.iter().map(|c| c.toi));
    lower(&mut best, found.ee.iter().map(|c| c.toi));
    let late = !best.is_some_and(|b| ctx.limit(Some(b)) <= tau);
    let stats = BroadStats {
        bv_tests,
        build,
        traverse,
    };
    (stats, late)
}

/// One parallel traversal of the hierarchy as built or refitted (or of the cluster method's
/// tasks), the triangle pairs' features checked against `boxes`, the tasks' candidates solved
/// with the limit `start` at first (lowered by what the batches find). With `first_pass`, the
/// traversal stops after its first batch of tasks unless that batch found a contact whose
/// limit is within `start` (a deterministic rule: the batches are fixed by the tree). Returns
/// the bounding-volume tests.
fn traverse_pass(
    tree: &impl TaskPairs,
    (input, ctx, record, task_chunk, ws): (
        &BroadInput<'_, '_>,
        &Context<'_, '_>,
        bool,
        usize,
        &mut BvhWorkspace,
    ),
    boxes: &FeatureBoxes,
    (start, first_pass): (f64, bool),
    (found, totals, recorded): (&mut Found, &mut Totals, &mut Candidates),
) -> u64 {
    let (features, filter) = (input.features, input.filter);
    // The limit of the batches handed over so far (f64 bits; only lowered between batches).
    let limit = AtomicU64::new(start.to_bits());
    // Earliest: growing batches, each pruned with what the batches before found. All: one
    // batch (a finished task keeps only what it found, so the buffers alive are the running
    // tasks').
    let batch = if ctx.options.mode == super::Mode::Earliest {
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
        Task::new(ctx, (limit, budget), index, record)
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
        task.buf = Candidates::default();
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
            recorded.vf.append(&mut r.vf);
            recorded.ee.append(&mut r.ee);
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
